"""Collision-free capability maps on a 2-worker Dask cluster: the workers rebuild the world from
its plain data (``World.state``) and count exactly what the in-process map counts; the floor
takes poses away; ``robokit workspace --obstacles`` does the same from a scene file."""
import os
from pathlib import Path

import numpy as np
import pytest

import robokit
from robokit.cli import main as cli_main
from robokit.collision import Box, World
from robokit.workspace import CapabilityMap, capability_map

ROOT = Path(__file__).resolve().parents[2]
KW = dict(orientations=8, chunk_size=12)  # the CLI's pre-pass; more chunks than workers
SCENE = """\
padding: 0.0
obstacles:
  - type: box
    name: floor
    size: [3.0, 3.0, 0.1]
    pose: {xyz: [0, 0, -0.1], rpy: [0, 0, 0]}
"""


def _floor():
    T = np.eye(4)
    T[:3, 3] = [0, 0, -0.1]  # top 5 cm below the base
    return Box([3.0, 3.0, 0.1], T, name="floor")


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


@pytest.fixture(scope="module")
def maps():
    puma = robokit.load("puma560")
    world = World(puma, [_floor()])
    free = capability_map(puma, 0.3, client="serial", **KW)
    serial = capability_map(puma, 0.3, client="serial", world=world, **KW)
    return puma, world, free, serial


def test_world_map_on_dask_equals_serial(cluster, maps):
    puma, world, free, serial = maps
    dask = capability_map(puma, 0.3, client=cluster, world=world, **KW)
    assert dask.timings["workers"] == 2 and dask.timings["chunks"] >= 4
    np.testing.assert_array_equal(dask.centres, serial.centres)
    np.testing.assert_array_equal(dask.index, serial.index)  # same counts, voxel by voxel
    np.testing.assert_array_equal(dask.centres, free.centres)
    assert np.all(dask.index <= free.index)
    assert np.any(dask.index < free.index)  # the floor takes some poses away
    assert dask.parameters["fingerprint"] != free.parameters["fingerprint"]


def test_convex_world_map_on_dask_equals_serial(cluster):
    """UR5 collision meshes replaced by hulls in the workers too: same counts as in-process, and
    no more than the mesh world's (the hulls are conservative)."""
    ur5 = robokit.load("ur5")
    kw = dict(orientations=2, chunk_size=40, samples=20000)
    hull = World(ur5, [_floor()], convex=True)
    serial = capability_map(ur5, 0.5, client="serial", world=hull, **kw)
    dask = capability_map(ur5, 0.5, client=cluster, world=hull, **kw)
    assert dask.timings["workers"] == 2 and dask.timings["chunks"] >= 4
    np.testing.assert_array_equal(dask.index, serial.index)
    mesh = capability_map(ur5, 0.5, client="serial", world=World(ur5, [_floor()]), **kw)
    assert np.all(serial.index <= mesh.index) and serial.index.sum() > 0


def test_cli_workspace_with_obstacles(cluster, maps, tmp_path, capsys):
    puma, world, free, serial = maps
    scene = tmp_path / "scene.yaml"
    scene.write_text(SCENE)
    out = tmp_path / "map.npz"
    rc = cli_main(["workspace", "puma560", "--resolution", "0.3", "--orientations", "8", "--obstacles", str(scene),
                   "--describe-world", "--scheduler", cluster.scheduler.address, "-o", str(out)])
    assert rc == 0
    printed = capsys.readouterr().out
    assert "World for 'puma560'" in printed and "obstacle floor" in printed and "self-collision pairs" in printed
    got = CapabilityMap.load(out)  # other chunks than KW's; the same counts (closed-form IK, no random numbers)
    np.testing.assert_array_equal(got.centres, serial.centres)
    np.testing.assert_array_equal(got.index, serial.index)
    assert got.index.sum() < free.index.sum()
    assert not out.with_name(out.name + ".chunks").exists()


def test_cli_workspace_bad_scene_writes_nothing(tmp_path, capsys):
    scene = tmp_path / "scene.yaml"
    scene.write_text("obstacles:\n  - type: box\n    size: [1, 1]\n")
    out = tmp_path / "map.npz"
    rc = cli_main(["workspace", "puma560", "--resolution", "0.3", "--orientations", "8", "--obstacles", str(scene),
                   "--scheduler", "serial", "-o", str(out)])
    err = capsys.readouterr().err.strip().splitlines()
    assert rc == 2 and len(err) == 1 and err[0].startswith("robokit: error:") and "size" in err[0]
    assert not out.exists() and not out.with_name(out.name + ".chunks").exists()
