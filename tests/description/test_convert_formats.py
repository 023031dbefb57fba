"""A shipped model converts to every format robokit writes, and each output describes the same arm
(its forward kinematics, from the written file, equals the model's to 1e-9); other outputs are
refused with the list of formats."""
import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import pinocchio as pin
import pytest

import robokit as rk
from robokit.kinematics import fkin_space

ROOT = Path(__file__).resolve().parents[2]


def _convert(*args, cwd):
    return subprocess.run([sys.executable, "-m", "robokit.cli", "convert", *map(str, args)], cwd=cwd,
                          capture_output=True, text=True, env={"PYTHONPATH": str(ROOT), "PATH": "/usr/bin:/bin"})


@pytest.mark.parametrize("name", ["twolink", "rrr", "puma560"])
def test_shipped_model_to_every_format(name, tmp_path):
    robot = rk.load(name)
    rng = np.random.default_rng(0)
    qs = [robot.random_configuration(rng) for _ in range(5)]
    for suffix in (".urdf", ".json", ".yaml", ".xml"):
        out = tmp_path / f"{name}{suffix}"
        p = _convert(name, "-o", out, cwd=tmp_path)
        assert p.returncode == 0, p.stderr
        assert out.stat().st_size > 0
    urdf = pin.buildModelFromUrdf(str(tmp_path / f"{name}.urdf"))
    data = urdf.createData()
    poe = json.loads((tmp_path / f"{name}.json").read_text())
    again = rk.load(tmp_path / f"{name}.yaml")
    tool = urdf.getFrameId("tool")
    for q in qs:
        T = robot.frame_pose(q)
        pin.framesForwardKinematics(urdf, data, q)
        assert np.abs(data.oMf[tool].homogeneous - T).max() < 1e-9
        assert np.abs(fkin_space(np.array(poe["M"]), np.array(poe["Slist"]), q) - T).max() < 1e-9
        assert np.abs(again.frame_pose(q) - T).max() < 1e-9


def test_unknown_output_lists_the_formats(tmp_path):
    p = _convert("puma560", "-o", tmp_path / "p.txt", cwd=tmp_path)
    assert p.returncode == 2
    line = p.stderr.strip().splitlines()
    assert len(line) == 1 and all(s in line[0] for s in (".urdf", ".json", ".yaml", ".xml"))
    assert not (tmp_path / "p.txt").exists()


def test_urdf_output_of_a_non_dh_robot_says_why(tmp_path):
    p = _convert("ur5", "-o", tmp_path / "u.urdf", cwd=tmp_path)
    assert p.returncode == 2 and "not a DH model" in p.stderr and not (tmp_path / "u.urdf").exists()


@pytest.mark.parametrize("name", ["ur5", "panda"])
def test_a_urdf_robot_says_where_its_dh_table_is_and_that_table_reproduces_it(name):
    robot = rk.load(name)
    assert robot.dh is None and "robokit.dh_from_urdf(robot).table" in repr(robot)
    res = rk.dh_from_urdf(robot)
    assert res.exact
    again = rk.load(res.table)
    rng = np.random.default_rng(1)
    for _ in range(10):
        q = robot.random_configuration(rng)
        assert np.abs(again.frame_pose(q) - robot.frame_pose(q)).max() < 1e-9  # Pinocchio on both
