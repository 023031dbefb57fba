"""Files, signals and the network: permissions follow the umask, a killed command leaves no
temporary file and no viewer server, servers listen on loopback only, meshes stay in their folder."""
import os
import signal
import subprocess
import sys
import textwrap
import time

import numpy as np
import psutil
import pytest
from hardening_support import (
    HANG_GUARD,
    PEND_L,
    PENDULUM_YAML,
    assert_one_line_error,
    pendulum_urdf,
    subprocess_env,
    tmp_leftovers,
)

import robokit
from robokit._io import atomic_write

SERVER_MODULE = "robokit.viz._server"


def _with_umask(mask, fn):
    old = os.umask(mask)
    try:
        return fn()
    finally:
        os.umask(old)


# ----------------------------------------------------------------------------- permissions
@pytest.mark.parametrize("mask,mode", [(0o022, 0o644), (0o077, 0o600), (0o002, 0o664)])
def test_written_file_follows_the_umask(mask, mode, tmp_path):
    out = tmp_path / "a.txt"
    _with_umask(mask, lambda: atomic_write(out, "x"))
    assert out.stat().st_mode & 0o777 == mode
    assert tmp_leftovers(tmp_path) == []


def test_replacing_a_0644_file_under_umask_022_leaves_0644(tmp_path):
    out = tmp_path / "a.txt"
    out.write_text("old")
    out.chmod(0o644)
    _with_umask(0o022, lambda: atomic_write(out, "new"))
    assert out.read_text() == "new"
    assert out.stat().st_mode & 0o777 == 0o644


def test_cli_output_follows_the_umask(write, tmp_path):
    src = write("pendulum.yaml", PENDULUM_YAML)
    for mask, mode in ((0o077, 0o600), (0o022, 0o644)):
        out = tmp_path / f"out{mask:o}.urdf"
        p = subprocess.run([sys.executable, "-m", "robokit.cli", "convert", str(src), "-o", str(out)],
                           capture_output=True, check=False, text=True, env=subprocess_env(), timeout=HANG_GUARD,
                           preexec_fn=lambda m=mask: os.umask(m))
        assert p.returncode == 0, p.stderr
        assert out.stat().st_mode & 0o777 == mode


@pytest.mark.parametrize("old_mode", [0o600, 0o640, 0o750, 0o444])
@pytest.mark.parametrize("mask", [0o022, 0o002])
def test_replacing_a_file_keeps_its_mode(old_mode, mask, tmp_path):
    """Issue 39, class 13: replacing an existing file keeps its permission bits whatever the umask
    (was: ``0666 & ~umask``, so a private 0600 output became world-readable 0644)."""
    out = tmp_path / "a.txt"
    out.write_text("old")
    out.chmod(old_mode)
    _with_umask(mask, lambda: atomic_write(out, "new"))
    assert out.read_text() == "new"
    assert out.stat().st_mode & 0o7777 == old_mode
    assert tmp_leftovers(tmp_path) == []


def test_replacing_keeps_the_owner_and_group_where_permitted(tmp_path):
    out = tmp_path / "a.txt"
    out.write_text("old")
    groups = [g for g in os.getgroups() if g != out.stat().st_gid]
    if groups:  # a group of ours other than the file's: an unprivileged user may keep it
        os.chown(out, -1, groups[0])
    before = out.stat()
    atomic_write(out, "new")
    after = out.stat()
    assert (after.st_uid, after.st_gid) == (before.st_uid, before.st_gid)
    assert after.st_ino != before.st_ino  # a new file (atomic replace), not the old one rewritten


def test_a_symlink_at_the_output_is_replaced_not_followed(tmp_path):
    """A new file follows the umask, also where a symbolic link stood; the link's target is untouched."""
    target = tmp_path / "target.txt"
    target.write_text("precious")
    target.chmod(0o600)
    out = tmp_path / "a.txt"
    out.symlink_to(target)
    _with_umask(0o022, lambda: atomic_write(out, "new"))
    assert not out.is_symlink() and out.read_text() == "new" and out.stat().st_mode & 0o777 == 0o644
    assert target.read_text() == "precious" and target.stat().st_mode & 0o777 == 0o600


def test_cli_outputs_replacing_private_files_stay_private(write, tmp_path):
    """Two writers of the command line (convert's file, codegen's pair) replacing 0600 files under
    umask 022: still 0600."""
    src = write("pendulum.yaml", PENDULUM_YAML)
    urdf = tmp_path / "out.urdf"
    folder = tmp_path / "c"
    folder.mkdir()
    for p in (urdf, folder / "pendulum.h", folder / "pendulum.c"):
        p.write_text("old")
        p.chmod(0o600)
    for args in (["convert", src, "-o", urdf], ["codegen", src, "-o", folder]):
        p = subprocess.run([sys.executable, "-m", "robokit.cli", *map(str, args)], capture_output=True, check=False,
                           text=True, env=subprocess_env(), timeout=HANG_GUARD, preexec_fn=lambda: os.umask(0o022))
        assert p.returncode == 0, p.stderr
    for p in (urdf, folder / "pendulum.h", folder / "pendulum.c"):
        assert p.read_text() != "old" and p.stat().st_mode & 0o777 == 0o600, p


def test_interrupted_write_leaves_the_old_file_and_no_temporary(tmp_path, monkeypatch):
    out = tmp_path / "a.txt"
    out.write_text("old")

    def interrupted(*a, **k):
        raise KeyboardInterrupt

    monkeypatch.setattr(os, "replace", interrupted)
    with pytest.raises(KeyboardInterrupt):
        atomic_write(out, "new")
    monkeypatch.undo()
    assert out.read_text() == "old"
    assert tmp_leftovers(tmp_path) == []


# ----------------------------------------------------------------------------- output paths
def _writers(tmp_path, main_cli):
    """Each writer that checks its output path before any work: (argument named in the message,
    suffix of its output, write(path) -> the error message without the CLI's ``robokit: error:``)."""
    from robokit.description.convert import convert

    def library(fn):
        def write(path):
            with pytest.raises(robokit.InputError) as info:
                fn(path)
            return str(info.value)
        return write

    pend = tmp_path / "pend.yaml"
    pend.write_text(PENDULUM_YAML)

    def cli(path):
        return assert_one_line_error(main_cli("view", pend, "-o", path), "-o").removeprefix("robokit: error: ")

    return [("output", ".txt", library(lambda p: atomic_write(p, "x"))),
            ("output", ".urdf", library(lambda p: convert(pend, p))),
            ("-o", ".html", cli)]


@pytest.mark.parametrize("k", range(3))
def test_output_in_a_missing_folder_or_onto_a_folder_is_refused_before_writing(k, tmp_path, main_cli):
    what, suffix, write = _writers(tmp_path, main_cli)[k]
    before = sorted(p.name for p in tmp_path.iterdir())
    missing = tmp_path / "no_such_folder" / f"out{suffix}"
    message = write(missing)
    assert message == f"{what}: folder {str(missing.parent)!r} does not exist", message
    folder = tmp_path / f"taken{suffix}"
    folder.mkdir()
    message = write(folder)
    assert message == f"{what}: {str(folder)!r} is a folder", message
    assert sorted(p.name for p in tmp_path.iterdir()) == sorted(before + [folder.name])
    assert list(folder.iterdir()) == [] and tmp_leftovers(tmp_path) == []


# ----------------------------------------------------------------------------- signals
def _servers_of(proc: psutil.Process) -> list[psutil.Process]:
    out = []
    for c in proc.children(recursive=True):
        try:
            if SERVER_MODULE in " ".join(c.cmdline()):
                out.append(c)
        except psutil.Error:
            pass
    return out


def _wait_for_server(popen, timeout=HANG_GUARD) -> list[psutil.Process]:
    parent = psutil.Process(popen.pid)
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        servers = _servers_of(parent)
        if servers:
            return servers
        if popen.poll() is not None:
            pytest.fail(f"robokit view exited ({popen.returncode}) before starting its server: "
                        f"{popen.stderr.read()}")
        time.sleep(0.02)
    pytest.fail("no meshcat server appeared (hang guard)")


def _gone(procs, timeout=10.0) -> bool:
    """True when every process has exited (a zombie counts as gone) within ``timeout`` s."""
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        alive = []
        for p in procs:
            try:
                if p.is_running() and p.status() != psutil.STATUS_ZOMBIE:
                    alive.append(p)
            except psutil.NoSuchProcess:
                pass
        if not alive:
            return True
        time.sleep(0.05)
    return False


def _reap(procs):
    for p in procs:
        try:
            p.kill()
        except psutil.Error:
            pass


def _foreground_signals() -> None:
    """In the child before exec: SIGINT and SIGTERM as a terminal gives them to a foreground
    command (default disposition, not blocked). A test runner's worker may have SIGINT ignored or
    blocked (both survive exec; an ignored SIGINT stays ignored in Python, as POSIX asks of a
    background job), which is not the situation this test is about."""
    for s in (signal.SIGINT, signal.SIGTERM):
        signal.signal(s, signal.SIG_DFL)
    signal.pthread_sigmask(signal.SIG_UNBLOCK, {signal.SIGINT, signal.SIGTERM})


@pytest.mark.parametrize("sig,rc,line", [(signal.SIGTERM, 143, "robokit: terminated"),
                                         (signal.SIGINT, 130, "robokit: interrupted"),
                                         (signal.SIGKILL, -9, None)])
def test_signal_during_view_leaves_no_temporary_and_no_server(sig, rc, line, write, tmp_path):
    """The signal is sent while the view's meshcat server runs. On a busy machine the small page
    can be finished before the signal lands (exit 0, the page written): that run tested nothing
    and is repeated, up to three times; a SIGINT/SIGTERM that robokit swallowed looks the same
    every time and fails."""
    src = write("pendulum.yaml", PENDULUM_YAML)
    for attempt in range(3):
        outdir = tmp_path / f"out{attempt}"
        outdir.mkdir()
        popen = subprocess.Popen([sys.executable, "-m", "robokit.cli", "view", str(src), "-o",
                                  str(outdir / "page.html")],
                                 stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, env=subprocess_env(),
                                 preexec_fn=_foreground_signals)
        servers = []
        try:
            servers = _wait_for_server(popen)
            popen.send_signal(sig)
            _, err = popen.communicate(timeout=HANG_GUARD)
            if popen.returncode == 0 and err.startswith("wrote ") and attempt < 2:
                continue  # finished before the signal landed: try again
            assert popen.returncode == rc, (err, "runner's SIGINT:", signal.getsignal(signal.SIGINT),
                                            "blocked:", signal.pthread_sigmask(signal.SIG_BLOCK, set()))
            if line is not None:
                lines = [ln for ln in err.splitlines() if ln.strip()]
                assert lines == [line], err
            assert _gone(servers), f"meshcat server still running after {sig.name}"
            assert tmp_leftovers(outdir) == []
            assert not (outdir / "page.html").exists()
            return
        finally:
            if popen.poll() is None:
                popen.kill()
                popen.wait()
            _reap(servers)


# ----------------------------------------------------------------------------- network
_CHILD = textwrap.dedent("""
    import sys, time
    import robokit
    from robokit.viz import LiveViewer
    from robokit.viz.scene import Scene
    viewer = LiveViewer()
    scene = Scene(robokit.load(sys.argv[1]))
    print(viewer.process.pid, scene.vis.window.server_proc.pid, flush=True)
    time.sleep(120)
""")


def test_meshcat_servers_listen_on_loopback_only_and_die_with_their_parent(write):
    src = write("pendulum.yaml", PENDULUM_YAML)
    child = subprocess.Popen([sys.executable, "-c", _CHILD, str(src)], stdout=subprocess.PIPE,
                             stderr=subprocess.PIPE, text=True, env=subprocess_env())
    servers = []
    try:
        first = child.stdout.readline()
        assert first.strip(), child.stderr.read()
        servers = [psutil.Process(int(pid)) for pid in first.split()]
        for server in servers:
            assert SERVER_MODULE in " ".join(server.cmdline())
            deadline = time.monotonic() + HANG_GUARD
            listening = []
            while not listening and time.monotonic() < deadline:
                listening = [c for c in server.net_connections(kind="inet") if c.status == psutil.CONN_LISTEN]
                time.sleep(0.05)
            assert listening, "the server listens on nothing"
            assert {c.laddr.ip for c in listening} == {"127.0.0.1"}, listening
        child.kill()  # SIGKILL: no clean-up code runs in the parent
        child.wait(timeout=HANG_GUARD)
        assert _gone(servers), "a meshcat server outlived its SIGKILLed parent"
    finally:
        if child.poll() is None:
            child.kill()
            child.wait()
        _reap(servers)


# ----------------------------------------------------------------------------- meshes
_STL = b"solid t\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 0.1 0 0\nvertex 0 0.1 0\nendloop\nendfacet\nendsolid t\n"


def _mesh_urdf(filename: str) -> str:
    return pendulum_urdf(extra=f'<visual><geometry><mesh filename="{filename}"/></geometry></visual>')


def _check_fk(robot):
    np.testing.assert_allclose(robot.frame_pose([0.5])[:3, 3], [PEND_L * np.cos(0.5), 0, PEND_L * np.sin(0.5)],
                               atol=1e-12)


def test_missing_mesh_warned_by_name_and_robot_still_loads(write, tmp_path, main_cli):
    src = write("pkg/robot.urdf", _mesh_urdf("meshes/arm_missing.stl"))
    with pytest.warns(robokit.errors.RobokitWarning, match="arm_missing.stl"):
        robot = robokit.load(src)
    _check_fk(robot)
    r = main_cli("convert", src, "-o", tmp_path / "out.json")
    assert r.rc == 0, r.err
    assert any(ln.startswith("robokit: note:") and "arm_missing.stl" in ln and "'arm'" in ln for ln in r.err.splitlines())


def test_mesh_inside_the_urdf_folder_is_loaded(write):
    write("pkg/meshes/arm.stl", _STL)
    robot = robokit.load(write("pkg/robot.urdf", _mesh_urdf("meshes/arm.stl")))
    files = [g.meshPath for g in robot.visual_model.geometryObjects]
    assert any(f.endswith("arm.stl") for f in files), files


@pytest.mark.parametrize("kind", ["etc_absolute", "dotdot", "absolute_outside", "file_uri"])
def test_mesh_outside_the_urdf_folder_refused_unless_allowed(kind, write, tmp_path, main_cli):
    outside = write("elsewhere/x.stl", _STL)
    ref = {"etc_absolute": "/etc/hostname", "dotdot": "../../../elsewhere/x.stl",
           "absolute_outside": str(outside), "file_uri": f"file://{outside}"}[kind]
    src = write("ws/pkg/urdf/robot.urdf", _mesh_urdf(ref))
    with pytest.raises(robokit.InputError) as ei:
        robokit.load(src)
    assert "'arm'" in str(ei.value) and ref in str(ei.value) and "allow_outside_meshes" in str(ei.value)
    out = tmp_path / "out.json"
    assert_one_line_error(main_cli("convert", src, "-o", out), "robot.urdf", "outside")
    assert not out.exists()
    if kind != "etc_absolute":  # allowed: the mesh outside is read
        robot = robokit.load(src, allow_outside_meshes=True)
        _check_fk(robot)
        files = [g.meshPath for g in robot.visual_model.geometryObjects]
        assert any(os.path.samefile(f, outside) for f in files if os.path.exists(f)), files
