"""--convex and --describe-world on the command line: the hull plan is free for the meshes too
(the hulls are conservative), and the description is printed on request without changing a map."""
import numpy as np
import pytest

import robokit
from robokit.cli import main
from robokit.collision import Box, World, pose_from_xyz_rpy
from robokit.workspace import CapabilityMap, capability_map

SCENE = """\
obstacles:
  - type: box
    name: pillar
    size: [0.1, 0.1, 1.0]
    pose: {xyz: [0.45, 0.3, 0.5], rpy: [0, 0, 0]}
"""


def test_plan_convex_path_is_free_for_the_meshes(tmp_path, capsys):
    pytest.importorskip("ompl")
    scene = tmp_path / "scene.yaml"
    scene.write_text(SCENE)
    out = tmp_path / "traj.csv"
    start, goal = [0, -1.57, 1.2, -1.57, 0, 0], [1.2, -1.57, 1.2, -1.57, 0, 0]
    rc = main(["plan", "ur5", "--start", *map(str, start), "--goal", *map(str, goal), "--obstacles", str(scene),
               "--convex", "--describe-world", "-o", str(out)])
    assert rc == 0
    printed = capsys.readouterr().out
    assert "robot geometry convex hulls of the collision meshes" in printed and "obstacle pillar" in printed
    Q = np.loadtxt(out, delimiter=",", comments="#", skiprows=2)
    np.testing.assert_allclose(Q[0], start, atol=1e-9)
    np.testing.assert_allclose(Q[-1], goal, atol=1e-9)
    ur5 = robokit.load("ur5")
    mesh = World(ur5, [Box([0.1, 0.1, 1.0], pose_from_xyz_rpy([0.45, 0.3, 0.5], [0, 0, 0]), name="pillar")])
    assert not mesh.in_collision(Q).any()


def test_workspace_describe_world_alone_does_not_change_the_map(tmp_path, capsys):
    out = tmp_path / "map.npz"
    rc = main(["workspace", "puma560", "--resolution", "0.4", "--orientations", "4", "--describe-world",
               "--scheduler", "serial", "-o", str(out)])
    assert rc == 0
    printed = capsys.readouterr().out
    assert "self-collision pairs (capsules" in printed and "not used for the map" in printed
    got = CapabilityMap.load(out)
    np.testing.assert_array_equal(got.index, capability_map("puma560", 0.4, 4, client="serial").index)
