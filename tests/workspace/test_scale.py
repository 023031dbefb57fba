"""Capability maps at scale: Dask equals in-process bit for bit, bounded memory, resume after a kill, the CLI."""
import os
import signal
import subprocess
import sys
import textwrap
import time
import tracemalloc
from pathlib import Path

import numpy as np
import pytest

from robokit.cli import main as cli_main
from robokit.description.dh import DHLink, DHTable
from robokit.workspace import CapabilityMap, capability_map

ROOT = Path(__file__).resolve().parents[2]


@pytest.fixture(scope="module")
def cluster():
    distributed = pytest.importorskip("distributed")
    env = dict(os.environ)
    os.environ["PYTHONPATH"] = os.pathsep.join([str(ROOT)] + [p for p in env.get("PYTHONPATH", "").split(os.pathsep)
                                                             if p])
    try:
        with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None,
                                      silence_logs=40) as lc, distributed.Client(lc) as client:
            yield client
    finally:
        os.environ.clear()
        os.environ.update(env)


def test_cluster_map_equals_serial_map_bit_for_bit(cluster):
    # numeric IK (random restarts seeded per chunk) on a spatial arm, several chunks per worker
    kw = dict(orientations=3, chunk_size=6, samples=20000, restarts=3)
    serial = capability_map("puma560", 0.35, client="serial", **kw)
    assert serial.parameters["ik"] in ("compiled", "analytic")
    dask = capability_map("puma560", 0.35, client=cluster, **kw)
    assert serial.timings["chunks"] >= 4 and dask.timings["workers"] == 2
    assert np.array_equal(serial.centres, dask.centres)
    assert np.array_equal(serial.index, dask.index)
    assert 0 < serial.index.max() and serial.index.min() == 0.0
    # and through a scheduler address
    address = cluster.scheduler.address
    planar = capability_map("rrr", 0.1, orientations=8, client="serial")
    assert np.array_equal(capability_map("rrr", 0.1, orientations=8, client=address).index, planar.index)


def test_driver_memory_is_bounded_by_the_chunk():
    """The same 3R grid (~6500 voxels) with K = 8 and K = 64 orientations: the (M, K, 4, 4)
    target array of an unchunked sweep grows 8× (to ~53 MB); the driver's peak allocation
    must not grow with K and stays a small fraction of that array."""
    table = DHTable("planar3r", "standard", tuple(DHLink(joint="R", a=a) for a in (0.5, 0.4, 0.2)))
    capability_map(table, 0.1, orientations=4, client="serial")  # imports and caches outside the measurement
    peaks, sizes = [], []
    for K in (8, 64):
        tracemalloc.start()
        try:
            cmap = capability_map(table, 0.025, orientations=K, client="serial", chunk_size=32)
            peaks.append(tracemalloc.get_traced_memory()[1])
        finally:
            tracemalloc.stop()
        sizes.append(len(cmap.centres) * K * 16 * 8)
        assert cmap.timings["problems"] == len(cmap.centres) * K
    assert len(cmap.centres) > 6000
    chunk_bytes = 32 * 128 * 16 * 8
    assert peaks[1] < peaks[0] + 4 * chunk_bytes, peaks
    assert peaks[1] < sizes[1] / 10, (peaks, sizes)


RUN = textwrap.dedent("""
    import sys
    from robokit.workspace import capability_map
    capability_map("puma560", 0.35, orientations=2, client="serial", store=sys.argv[1], chunk_size=2,
                   samples=20000, restarts=2)
""")


def test_resume_after_kill(tmp_path):
    store = tmp_path / "map.chunks"
    env = dict(os.environ, PYTHONPATH=os.pathsep.join([str(ROOT), os.environ.get("PYTHONPATH", "")]))
    proc = subprocess.Popen([sys.executable, "-c", RUN, str(store)], env=env, stdout=subprocess.DEVNULL,
                            stderr=subprocess.PIPE)
    try:
        deadline = time.monotonic() + 120
        while len(list(store.glob("chunk_*.npz"))) < 3:
            assert proc.poll() is None, proc.stderr.read().decode()
            assert time.monotonic() < deadline
            time.sleep(0.005)
        proc.send_signal(signal.SIGKILL)
        proc.wait()
    finally:
        if proc.poll() is None:
            proc.kill()
            proc.wait()
        proc.stderr.close()
    written = sorted(p.name for p in store.glob("chunk_*.npz"))
    kw = dict(orientations=2, client="serial", chunk_size=2, samples=20000, restarts=2)
    resumed = capability_map("puma560", 0.35, store=store, **kw)
    n_chunks = resumed.parameters["chunks"]
    assert 3 <= len(written) < n_chunks  # killed part way
    assert resumed.timings["chunks_resumed"] == len(written)
    assert resumed.timings["chunks"] == n_chunks - len(written)
    fresh = capability_map("puma560", 0.35, **kw)
    assert np.array_equal(resumed.index, fresh.index) and np.array_equal(resumed.centres, fresh.centres)
    # other parameters: the old chunks are not reused
    other = capability_map("puma560", 0.35, store=store, **dict(kw, restarts=1))
    assert other.timings["chunks_resumed"] == 0


def test_cli_workspace_writes_the_four_arrays(tmp_path, capsys, cluster):
    out = tmp_path / "map.npz"
    status = cli_main(["workspace", "rrr", "--resolution", "0.1", "--orientations", "8",
                       "--scheduler", cluster.scheduler.address, "-o", str(out)])
    assert status == 0
    with np.load(out) as z:
        assert sorted(z.files) == ["centres", "index", "orientations", "resolution"]
        index = z["index"]
    assert np.array_equal(index, capability_map("rrr", 0.1, orientations=8, client="serial").index)
    assert not (tmp_path / "map.npz.chunks").exists()
    page = tmp_path / "map.html"
    assert cli_main(["view", str(out), "-o", str(page)]) == 0
    assert page.stat().st_size > 1000 and "<html" in page.read_text(encoding="utf-8")[:2000].lower()


@pytest.mark.parametrize("args, word", [
    (["--resolution", "-1"], "--resolution"),
    (["--resolution", "0.1", "--orientations", "0"], "--orientations"),
    (["--resolution", "0.1", "-o", "x.txt"], "-o"),
    (["--resolution", "0.1", "-o", "missing/x.npz"], "-o"),
    (["--resolution", "0.1", "--robot-typo"], "unrecognized"),
])
def test_cli_bad_input(tmp_path, capsys, args, word, monkeypatch):
    monkeypatch.chdir(tmp_path)
    if "-o" not in args:
        args = args + ["-o", "x.npz"]
    assert cli_main(["workspace", "rrr"] + args) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith("robokit:") and word in err[0]
    assert list(tmp_path.iterdir()) == []


def test_cli_unknown_robot(tmp_path, capsys):
    assert cli_main(["workspace", "no_such_arm", "--resolution", "0.1", "-o", str(tmp_path / "m.npz")]) == 2
    assert capsys.readouterr().err.startswith("robokit: error: model:")
    assert list(tmp_path.iterdir()) == []


def test_plot_slice(tmp_path):
    from robokit.workspace import plot_capability_slice

    cmap = capability_map("rrr", 0.1, orientations=8, client="serial")
    fig = plot_capability_slice(cmap, "z")
    ax = fig.axes[0]
    assert len(ax.collections[0].get_offsets()) == len(cmap.centres)  # a planar map is one slice
    with pytest.raises(ValueError, match="value"):
        plot_capability_slice(cmap, "z", value=5.0)
    with pytest.raises(ValueError, match="axis"):
        plot_capability_slice(cmap, "w")
    assert isinstance(CapabilityMap.load(cmap.save(tmp_path / "m.npz")), CapabilityMap)


def test_an_unlimited_prismatic_joint_is_refused_naming_it():
    """A DH joint without qlim is unlimited (±inf); for a prismatic one the arm reaches without bound, and the map
    was silently cut where the grid's sampling put unlimited joints (±π m). With limits it maps as usual."""
    import robokit as rk
    from robokit.errors import InputError

    links = (DHLink("R", a=0.3, alpha=0.0, d=0.0), DHLink("P", a=0.0, alpha=1.5707963267948966, d=0.2),
             DHLink("R", a=0.2, alpha=0.0, d=0.0))
    with pytest.raises(InputError, match="joint_2.*prismatic with no limits"):
        rk.capability_map(rk.load(DHTable("slider", "standard", links)), 0.2, orientations=2, client="serial")
    limited = links[:1] + (DHLink("P", a=0.0, alpha=1.5707963267948966, d=0.2, qlim=(0.0, 0.3)),) + links[2:]
    cmap = rk.capability_map(rk.load(DHTable("slider", "standard", limited)), 0.2, orientations=2, client="serial")
    assert len(cmap.centres) > 0
