"""What a first user of the installed wheel ran into (an audit of the README, getting started and
docs/cli.md, run from outside the checkout): each test checks the command line's contract of
docs/cli.md (one ``robokit:`` line naming the argument, exit status 2, nothing written) or what the
documentation promises, never a value copied from the code under test."""
import os
import shutil

import numpy as np
import pytest
import yaml
from hardening_support import assert_one_line_error, tmp_leftovers

import robokit
from robokit.description.models import model_path


# ----------------------------------------------------------------------------- convert without -o
def test_convert_dh_file_without_output_prints_its_table(tmp_path, main_cli):
    """docs/cli.md: without ``-o`` "the DH table printed on stdout", for a DH model as for any robot.
    A DH *file* was refused ("-o/--output: required") while the same table by its shipped name printed."""
    src = tmp_path / "my_arm.yaml"
    shutil.copy(model_path("puma560"), src)
    run = main_cli("convert", src)
    assert run.rc == 0, run.err
    table = yaml.safe_load(src.read_text(encoding="utf-8"))
    rows = [ln.split() for ln in run.out.splitlines() if ln[:1].isdigit()]
    assert len(rows) == len(table["links"])
    for i, (row, link) in enumerate(zip(rows, table["links"]), 1):  # i  joint  a  alpha(deg)  d  theta ...
        assert int(row[0]) == i and row[1] == link["joint"]
        assert float(row[2]) == pytest.approx(link["a"], abs=1e-5)
        assert float(row[3]) == pytest.approx(link["alpha"], abs=1e-3)  # this file's angles are in degrees
        assert float(row[4]) == pytest.approx(link["d"], abs=1e-5)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["my_arm.yaml"]  # nothing written
    # the same text as the shipped model's, and a missing file is named as missing (not "-o required")
    assert main_cli("convert", "puma560").out.replace("my_arm", "puma560") == run.out.replace("my_arm", "puma560")
    assert_one_line_error(main_cli("convert", tmp_path / "nofile.yaml"), "nofile.yaml", "not found")


def test_convert_dh_file_without_output_still_refuses_a_tip(tmp_path, main_cli):
    src = tmp_path / "my_arm.yaml"
    shutil.copy(model_path("puma560"), src)
    assert_one_line_error(main_cli("convert", src, "--tip", "flange"), "tip")


# ----------------------------------------------------------------------------- plan: NaN and seeds
@pytest.mark.parametrize("flag, values", [
    ("--start", ["nan", "0.3", "-0.3", "0", "0", "0"]),
    ("--start", ["0", "inf", "-0.3", "0", "0", "0"]),
    ("--goal", ["1.4", "0.3", "-0.3", "0", "0", "nan"]),
    ("--goal", ["1.4", "0.3", "-0.3", "0", "0", "1e999"]),  # float("1e999") is inf
])
def test_plan_names_a_non_finite_start_or_goal(flag, values, tmp_path, main_cli):
    """A NaN in --start/--goal was reported as "--dt/--vmax/--amax: the trajectory would last at
    least nan s": the wrong options named."""
    args = {"--start": ["0", "0.3", "-0.3", "0", "0", "0"], "--goal": ["1.4", "0.3", "-0.3", "0", "0", "0"]}
    args[flag] = values
    out = tmp_path / "traj.csv"
    run = main_cli("plan", "puma560", "--start", *args["--start"], "--goal", *args["--goal"], "-o", out)
    line = assert_one_line_error(run, flag, "NaN or infinite")
    assert "--dt" not in line
    assert not out.exists() and tmp_leftovers(tmp_path) == []


@pytest.mark.parametrize("seed", ["-1", str(2**64 - 1), str(2**70)])
def test_plan_refuses_a_seed_out_of_range(seed, tmp_path, main_cli):
    """``--seed -1`` ended in numpy's ValueError, reported as an internal error (exit 3). OMPL is
    seeded with seed + 1, an unsigned 64-bit integer: 0 … 2⁶⁴ − 2."""
    out = tmp_path / "traj.csv"
    run = main_cli("plan", "puma560", "--start", 0, 0.3, -0.3, 0, 0, 0, "--goal", 1.4, 0.3, -0.3, 0, 0, 0,
                   "--seed", seed, "-o", out)
    assert_one_line_error(run, "--seed", seed)
    assert not out.exists() and tmp_leftovers(tmp_path) == []


@pytest.mark.parametrize("seed", [-1, 2**64 - 1, 1.5, True, "0"])
def test_library_plan_refuses_a_bad_seed_naming_it(seed):
    puma = robokit.load("puma560")
    with pytest.raises(robokit.InputError, match=r"^seed: "):
        robokit.plan(puma, [0, 0.3, -0.3, 0, 0, 0], [1.4, 0.3, -0.3, 0, 0, 0], seed=seed)


# ----------------------------------------------------------------------------- validate --seed
def test_validate_refuses_a_negative_seed(main_cli):
    """``robokit validate --seed -1`` printed a FAIL row (numpy's ValueError) and exited 1, "a check
    failed": bad input is status 2."""
    run = main_cli("validate", "--seed", "-1", "--area", "spatial")
    assert_one_line_error(run, "--seed", "-1")
    assert "FAIL" not in run.out
    with pytest.raises(robokit.InputError, match="--seed"):
        from robokit.validation import main
        main(seed=-1, areas=["spatial"])


# ----------------------------------------------------------------------------- unwritable output folder
def _refuse_writes_in(monkeypatch, folder):
    """``os.open`` as in a folder the user may not write in: creating any file there (named or
    O_TMPFILE) fails with EACCES, as it does for a user without write permission."""
    real = os.open
    creating = os.O_CREAT | getattr(os, "O_TMPFILE", 0)

    def guarded(path, flags, *args, **kwargs):
        p = os.path.abspath(os.fspath(path))
        if flags & creating and (p == str(folder) or os.path.dirname(p) == str(folder)):
            raise PermissionError(13, "Permission denied", os.fspath(path))
        return real(path, flags, *args, **kwargs)

    monkeypatch.setattr(os, "open", guarded)


@pytest.mark.parametrize("args, name", [
    (["convert", "puma560", "-o", "{d}/puma560.json"], "puma560.json"),
    (["convert", "puma560", "-o", "{d}/puma560.urdf"], "puma560.urdf"),
    (["plan", "puma560", "--start", "0", "0.3", "-0.3", "0", "0", "0", "--goal", "0.2", "0.3", "-0.3", "0", "0", "0",
      "-o", "{d}/traj.csv"], "traj.csv"),
])
def test_unwritable_output_folder_names_the_output_not_a_temporary(args, name, tmp_path, monkeypatch, main_cli):
    """A folder that cannot be written gave ``[Errno 13] Permission denied: 'ro/.puma560.json.1a2b3c4d.tmp'``:
    a temporary file the user never named. The message names the output file and the reason."""
    folder = tmp_path / "ro"
    folder.mkdir()
    _refuse_writes_in(monkeypatch, folder)
    run = main_cli(*[a.format(d=folder) for a in args])
    line = assert_one_line_error(run, name, "Permission denied")
    assert ".tmp" not in line
    assert list(folder.iterdir()) == []


@pytest.mark.skipif(not hasattr(os, "geteuid") or os.geteuid() == 0, reason="root writes in any folder")
def test_read_only_folder_really_refused(tmp_path, main_cli):
    folder = tmp_path / "ro"
    folder.mkdir()
    folder.chmod(0o555)
    try:
        run = main_cli("convert", "puma560", "-o", folder / "puma560.json")
        line = assert_one_line_error(run, "puma560.json")
        assert ".tmp" not in line
        assert list(folder.iterdir()) == []
    finally:
        folder.chmod(0o755)


def test_library_writer_raises_input_error_naming_the_file(tmp_path, monkeypatch):
    from robokit._io import atomic_write

    folder = tmp_path / "ro"
    folder.mkdir()
    _refuse_writes_in(monkeypatch, folder)
    with pytest.raises(robokit.InputError, match=r"output: cannot write .*a\.txt.*Permission denied") as info:
        atomic_write(folder / "a.txt", "x")
    assert ".tmp" not in str(info.value)
    assert np.all([not p.name.endswith(".tmp") for p in folder.iterdir()])


# ----------------------------------------------------------------------------- degrees on the command line
def test_view_notes_degrees_typed_after_q(tmp_path, main_cli):
    """docs/conventions.md: degrees typed by mistake are named. ``robokit view puma560 -q 0 45 -90 0 30 0``
    drew a contorted arm without a word: the library's check took the values for robokit's own."""
    out = tmp_path / "p.html"
    run = main_cli("view", "puma560", "-q", 0, 45, -90, 0, 30, 0, "-o", out)
    assert run.rc == 0, run.err
    notes = [ln for ln in run.err_lines if ln.startswith("robokit: note:")]
    assert len(notes) == 1 and "-q" in notes[0] and "degrees" in notes[0], run.err
    run = main_cli("view", "puma560", "-q", *np.radians([0, 45, -90, 0, 30, 0]), "-o", out)
    assert run.rc == 0 and not [ln for ln in run.err_lines if ln.startswith("robokit: note:")], run.err


def test_view_notes_a_trajectory_file_in_degrees(tmp_path, main_cli):
    """The rows of ``--trajectory FILE`` are the user's values too: a file written in degrees gets the
    note (once), the same file in radians none."""
    out = tmp_path / "p.html"
    rows = np.array([[0, 10, -20, 0, 30, 0], [0, 45, -90, 0, 30, 0], [0, 60, -120, 0, 40, 0]], float)
    for values, noted in ((rows, True), (np.radians(rows), False)):
        csv = tmp_path / "traj.csv"
        csv.write_text("q1,q2,q3,q4,q5,q6\n" + "\n".join(",".join(f"{x:.6f}" for x in r) for r in values) + "\n")
        run = main_cli("view", "puma560", "--trajectory", csv, "-o", out)
        assert run.rc == 0, run.err
        notes = [ln for ln in run.err_lines if ln.startswith("robokit: note:")]
        assert len(notes) == (1 if noted else 0), run.err
        assert not noted or ("--trajectory" in notes[0] and "degrees" in notes[0]), run.err


def test_plan_in_degrees_names_the_options(tmp_path, main_cli):
    """The same start and goal in degrees: a note per option, and the error names --start (the
    library's q_start is not what the user typed)."""
    out = tmp_path / "traj.csv"
    run = main_cli("plan", "puma560", "--start", 0, 17, -17, 0, 0, 0, "--goal", 80, 17, -17, 0, 0, 0, "-o", out)
    line = assert_one_line_error(run, "--start", "limits")
    assert "q_start" not in line
    notes = [ln for ln in run.err_lines if ln.startswith("robokit: note:")]
    assert [n.split()[2] for n in notes] == ["--start:", "--goal:"] and all("degrees" in n for n in notes), run.err
    assert not out.exists()
    run = main_cli("plan", "puma560", "--start", 0, 0.3, -0.3, 0, 0, 0, "--goal", 5, 5, 5, 0, 0, 0, "-o", out)
    assert "q_start" not in assert_one_line_error(run, "--goal", "limits")


# ----------------------------------------------------------------------------- plan: a pose goal for a 6-joint arm
def test_plan_goal_pose_reaches_the_pose_on_a_six_joint_arm(tmp_path, main_cli):
    """docs/cli.md offered '6 numbers x y z roll pitch yaw' after --goal, but for a 6-joint arm (the
    PUMA, every UR) six numbers are joint values: the pose goal could not be given at all. With
    --goal-pose, the last row of the CSV puts the tool at the pose, by Pinocchio's own FK of the
    shipped URDF (its roll-pitch-yaw by pinocchio.rpy)."""
    pin = pytest.importorskip("pinocchio")
    from robokit.description.models import models_dir

    model = pin.buildModelFromUrdf(str(models_dir() / "puma560.urdf"))
    data = model.createData()
    tool = model.getFrameId("tool")
    pin.framesForwardKinematics(model, data, np.array([1.0, 0.3, -0.3, 0.2, 0.4, 0.1]))
    goal = data.oMf[tool].copy()
    pose = [repr(float(v)) for v in (*goal.translation, *pin.rpy.matrixToRpy(goal.rotation))]
    out = tmp_path / "traj.csv"
    run = main_cli("plan", "puma560", "--start", 0, 0.3, -0.3, 0, 0, 0, "--goal-pose", *pose, "-o", out)
    assert run.rc == 0, run.err
    last = np.array(out.read_text().strip().splitlines()[-1].split(","), dtype=float)
    pin.framesForwardKinematics(model, data, last)
    assert np.abs(data.oMf[tool].homogeneous - goal.homogeneous).max() < 1e-6
    # --goal with the same six numbers stays joint values (documented), and both goals at once are refused
    bad = tmp_path / "bad.csv"
    run = main_cli("plan", "puma560", "--start", 0, 0.3, -0.3, 0, 0, 0, "--goal", *pose, "--goal-pose", *pose, "-o", bad)
    assert_one_line_error(run, "--goal")
    run = main_cli("plan", "puma560", "--start", 0, 0.3, -0.3, 0, 0, 0, "--goal-pose", 0.5, 0, "nan", 0, 0, 0, "-o", bad)
    assert_one_line_error(run, "--goal-pose", "NaN")
    run = main_cli("plan", "puma560", "--start", 0, 0.3, -0.3, 0, 0, 0, "--goal-pose", 9, 9, 9, 0, 0, 0, "-o", bad)
    assert_one_line_error(run, "--goal-pose", "IK")
    assert not bad.exists() and tmp_leftovers(tmp_path) == []


# ----------------------------------------------------------------------------- argparse's own errors
@pytest.mark.parametrize("args, names", [
    (["validate", "--seed", "abc"], ["--seed", "abc"]),
    (["validate", "--area"], ["--area"]),
    (["convert", "puma560", "--convention", "weird"], ["--convention", "weird"]),
    (["convert", "puma560", "--bogus"], ["--bogus"]),
    (["view", "puma560"], ["-o/--output"]),
    (["teach", "ur5", "--xacro-arg", "foo"], ["--xacro-arg", "foo"]),
    (["frobnicate"], ["frobnicate"]),
    (["plan", "puma560", "--start", "0", "0", "0", "0", "0", "0", "--goal-pose", "1", "2", "3", "-o", "t.csv"],
     ["--goal-pose"]),
])
def test_usage_errors_are_one_robokit_line(args, names, tmp_path, monkeypatch, main_cli):
    """docs/cli.md: bad input gives "one line starting with `robokit:`". argparse's errors started
    with the subcommand's name instead ("robokit validate: argument --seed: invalid int value")."""
    monkeypatch.chdir(tmp_path)
    line = assert_one_line_error(main_cli(*args), *names)
    assert line.startswith("robokit: error: ")
    assert list(tmp_path.iterdir()) == []


# ----------------------------------------------------------------------------- a capability map in a script
def test_capability_map_in_an_unguarded_script_says_what_to_do(tmp_path):
    """The samples of course/capability-maps.md and course/motion.md, copied into a script and run
    with ``python script.py``, ended in ~500 lines of Dask tracebacks and "RuntimeError: Nanny failed
    to start": Dask's spawned workers import the script again. The last line now says to guard the
    call (or compute serially), and it is the only error: the workers, running the script again, leave
    without a word (no Dask log, no traceback of theirs) and the parent's error has no Dask chain. The
    guarded script makes the map."""
    pytest.importorskip("distributed")
    pytest.importorskip("cryptography")
    import subprocess
    import sys

    from hardening_support import subprocess_env

    body = 'cmap = robokit.capability_map("rrr", 0.3, orientations=2)\nprint("voxels", len(cmap.index))\n'
    script = tmp_path / "unguarded.py"
    script.write_text("import robokit\n" + body)
    p = subprocess.run([sys.executable, str(script)], cwd=tmp_path, capture_output=True, text=True, timeout=300,
                       env=subprocess_env())
    last = p.stderr.strip().splitlines()[-1]
    assert p.returncode != 0 and last.startswith("robokit.errors.RobokitError:"), p.stderr[-2000:]
    assert 'if __name__ == "__main__":' in last and str(script) in last and "client='serial'" in last
    assert p.stderr.count("Traceback") == 1 and "distributed" not in p.stderr, p.stderr[-3000:]
    assert len(p.stderr.splitlines()) < 30, p.stderr
    guarded = tmp_path / "guarded.py"
    guarded.write_text("import robokit\nif __name__ == '__main__':\n" + "".join("    " + ln + "\n" for ln in body.splitlines()))
    p = subprocess.run([sys.executable, str(guarded)], cwd=tmp_path, capture_output=True, text=True, timeout=300,
                       env=subprocess_env())
    assert p.returncode == 0 and "voxels" in p.stdout, p.stderr[-2000:]


# ----------------------------------------------------------------------------- a folder or an unknown file as MODEL
@pytest.mark.parametrize("command", [["convert"], ["view", "-o", "p.html"], ["codegen", "-o", "gen"]])
def test_model_that_is_a_folder_or_an_unread_file_is_named_as_such(command, tmp_path, monkeypatch, main_cli):
    """``robokit convert my_robot_folder`` said "unknown robot 'my_robot_folder'; rk.models() lists the
    names ..." although the folder exists: the message now says it is a folder (or a file whose
    suffix robokit does not read)."""
    monkeypatch.chdir(tmp_path)
    (tmp_path / "arm_description").mkdir()
    (tmp_path / "arm.txt").write_text("<robot name='x'/>")
    sub, *rest = command
    line = assert_one_line_error(main_cli(sub, "arm_description", *rest), "'arm_description'", "is a folder")
    assert "unknown robot" not in line
    line = assert_one_line_error(main_cli(sub, "arm.txt", *rest), "'arm.txt'", ".urdf")
    assert "unknown robot" not in line
    assert sorted(p.name for p in tmp_path.iterdir()) == ["arm.txt", "arm_description"]
    with pytest.raises(robokit.InputError, match="is a folder"):
        robokit.load(tmp_path / "arm_description")


# ----------------------------------------------------------------------------- output = input
@pytest.mark.parametrize("out_name", ["arm.yaml", "./arm.yaml", "link.yaml"])
def test_convert_refuses_to_write_over_its_input(out_name, tmp_path, monkeypatch, main_cli):
    """``robokit convert arm.yaml -o arm.yaml`` replaced the user's DH file (its comments, its degrees)
    with robokit's normalised table, without a word. Now one line naming the clash; the file is
    unchanged, byte for byte."""
    monkeypatch.chdir(tmp_path)
    src = tmp_path / "arm.yaml"
    shutil.copy(model_path("puma560"), src)
    (tmp_path / "link.yaml").symlink_to(src)
    before = src.read_bytes()
    run = main_cli("convert", "link.yaml" if out_name == "arm.yaml" else "arm.yaml", "-o", out_name)
    assert_one_line_error(run, "is the input file")
    assert src.read_bytes() == before and tmp_leftovers(tmp_path) == []
    assert main_cli("convert", "arm.yaml", "-o", "copy.yaml").rc == 0  # another name is fine


def test_calibrate_refuses_to_write_over_its_model(tmp_path, monkeypatch, main_cli):
    monkeypatch.chdir(tmp_path)
    assert main_cli("convert", "puma560", "-o", "arm.urdf").rc == 0
    before = (tmp_path / "arm.urdf").read_bytes()
    (tmp_path / "data.csv").write_text("q1,q2,q3,q4,q5,q6,x,y,z\n")
    assert_one_line_error(main_cli("calibrate", "arm.urdf", "data.csv", "-o", "arm.urdf"), "-o", "arm.urdf",
                          "is the input file")
    assert (tmp_path / "arm.urdf").read_bytes() == before


# ----------------------------------------------------------------------------- unbounded sample counts
UNBOUNDED = {
    # call, the arguments the message must name
    "ms_trajectory": ("rk.ms_trajectory([[0.0], [1000.0]], dt=1e-4, tacc=0.5, qdmax=0.01)", ["dt/qdmax", "1000000"]),
    "ms_trajectory_tsegment": ("rk.ms_trajectory([[0.0], [1.0]], dt=1e-4, tacc=0.5, tsegment=[1e6])",
                               ["dt/tsegment", "1000000"]),
    "ms_trajectory_overflow": ("rk.ms_trajectory([[0, 0], [1e12, 1]], dt=1e-6, tacc=0.5, qdmax=1e-6)", ["dt/qdmax"]),
    "ms_lspb_trajectory": ("rk.trajectory.ms_lspb_trajectory([[0.0], [1000.0]], dt=1e-4, tacc=0.5, qdmax=0.01)",
                           ["dt/qdmax", "1000000"]),
    "ms_cartesian_trajectory": (
        "rk.trajectory.through.ms_cartesian_trajectory(np.stack([np.eye(4), T1]), dt=1e-4, tacc=0.5, speed=0.01, "
        "angular_speed=0.1)", ["dt/speed/angular_speed"]),
    "track_line": ("rk.control.track_line(rk.load('twolink'), [0.3, 0.5], [1.0, 0.5, 0.0], duration=1e5, dt=1e-4)",
                   ["duration/dt", "1000000"]),
    "run_vehicle": ("rk.mobile.vehicle.run_vehicle(rk.mobile.vehicle.BicycleModel(), lambda t, x, dt: (0.1, 0.0), "
                    "[0, 0, 0], T=1e6, dt=1e-4)", ["T/dt", "1000000"]),
}


@pytest.mark.parametrize("case", sorted(UNBOUNDED))
def test_a_huge_sample_count_is_refused_before_any_allocation(case, tmp_path):
    """A duration or distance far beyond the step (a slow qdmax, a tiny dt) asked for 10⁹ samples:
    ms_lspb_trajectory was killed by the kernel's OOM killer, track_line raised MemoryError,
    run_vehicle looped for hours and ms_trajectory raised numpy's 'Maximum allowed size exceeded'.
    Each now raises InputError naming its arguments, as quintic_trajectory does for its t
    (robokit.trajectory.core.MAX_SAMPLES). Run in a subprocess limited to 3 GB of address space
    and 120 s, so that a regression fails the test instead of the machine."""
    import resource
    import subprocess
    import sys

    from hardening_support import subprocess_env

    call, names = UNBOUNDED[case]
    code = ("import numpy as np, robokit as rk, robokit.mobile.vehicle, robokit.trajectory.through\n"
            "T1 = np.eye(4); T1[0, 3] = 1000.0\n"
            f"try:\n    {call}\n    print('NO ERROR')\n"
            "except Exception as e:\n    print(type(e).__name__ + ': ' + str(e))\n")

    def limit():
        resource.setrlimit(resource.RLIMIT_AS, (3 << 30, 3 << 30))

    p = subprocess.run([sys.executable, "-c", code], cwd=tmp_path, capture_output=True, text=True, timeout=120,
                       env=subprocess_env(ROBOKIT_COMPILE="off"), preexec_fn=limit)
    out = p.stdout.strip().splitlines()[-1] if p.stdout.strip() else p.stderr[-1000:]
    assert out.startswith("InputError: "), out
    for name in names:
        assert name in out, out


def test_cubic_via_names_its_velocities_argument():
    """``cubic_via_trajectory(..., velocities="bogus")`` said "method: expected 'heuristic' or
    'continuous'": there is no ``method`` argument (it is via_point_velocities')."""
    with pytest.raises(robokit.InputError, match=r"^velocities: .*'continuous', 'heuristic' or an array") as info:
        robokit.trajectory.cubic_via_trajectory([[0.0], [1.0], [2.0]], times=[0, 1, 2], velocities="bogus")
    assert "method" not in str(info.value)


# ----------------------------------------------------------------------------- negative values after an option
@pytest.mark.parametrize("value", ["-inf", "-nan", "-Infinity"])
def test_a_negative_infinity_after_an_option_is_refused_by_the_option(value, tmp_path, main_cli):
    """argparse reads only ``-2`` and ``-.5`` as negative numbers: ``--goal ... -inf`` ended in "unrecognized
    arguments: -inf", as if -inf were an option. The value now reaches robokit's check, whose one line
    names the option (docs/cli.md)."""
    out = tmp_path / "traj.csv"
    run = main_cli("plan", "puma560", "--start", 0, 0.3, -0.3, 0, 0, 0, "--goal", 1.4, 0.3, -0.3, 0, 0, value,
                   "-o", out)
    line = assert_one_line_error(run, "--goal", "NaN or infinite")
    assert "unrecognized" not in line and not out.exists()
    run = main_cli("view", "puma560", "-q", 0, 0, 0, 0, 0, value, "-o", tmp_path / "p.html")
    assert "unrecognized" not in assert_one_line_error(run, "-q", "NaN or infinite")
    run = main_cli("workspace", "rrr", "--resolution", value, "-o", tmp_path / "m.npz")
    assert "unrecognized" not in assert_one_line_error(run, "--resolution")


def test_a_negative_value_with_an_exponent_after_an_option_is_a_value(tmp_path, main_cli):
    """``-1e-3`` is a number too (argparse took it for an option): the plan runs with it."""
    out = tmp_path / "traj.csv"
    run = main_cli("plan", "puma560", "--start", 0, 0.3, -0.3, 0, 0, "-1e-3", "--goal", 1.4, 0.3, -0.3, 0, 0,
                   "-1E-3", "-o", out)
    assert run.rc == 0, run.err
    rows = [ln for ln in out.read_text().splitlines() if ln and not ln.startswith(("#", "q"))]
    assert float(rows[0].split(",")[-1]) == pytest.approx(-1e-3) and float(rows[-1].split(",")[-1]) == pytest.approx(-1e-3)
