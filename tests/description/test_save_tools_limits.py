"""Robot.save of a URDF robot that with_tool / with_limits changed: the saved file holds the tools and
limits, so loading it gives the robot that was saved (before, the file was written as it was read and the
tool and limits were silently lost: a tool 0.14 m off and limits 1.5 rad off on Drake's iiwa).

The reference is the robot itself (Pinocchio's model robokit built and then changed with with_tool /
with_limits), against the saved file loaded again by robokit's URDF path (Pinocchio's URDF parser)."""
import warnings
import xml.etree.ElementTree as ET

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import robokit
from robokit.description.dh import matrix_from_rpy
from robokit.errors import InputError, RobokitWarning

from robokit.description.models import model_path

IIWA = "tests/data/sdf/drake_iiwa14/iiwa14_no_collision.urdf"


def _load(path, **kw):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RobokitWarning)  # (meshes not vendored, the file's notes)
        return robokit.load(str(path), **kw)


def _pose(xyz, rpy):
    T = np.eye(4)
    T[:3, :3] = matrix_from_rpy(rpy)
    T[:3, 3] = xyz
    return T


def _same_robot(a, b, samples=5):
    """The largest difference of tip pose, Jacobian and M over random configurations (inf: other limits)."""
    rng = np.random.default_rng(3)
    worst = 0.0 if np.array_equal(a.qlim, b.qlim) else np.inf
    for _ in range(samples):
        q = a.random_configuration(rng)
        worst = max(worst, float(np.abs(a.frame_pose(q) - b.frame_pose(q)).max()),
                    float(np.abs(a.jacobian(q) - b.jacobian(q)).max()), float(np.abs(a.crba(q) - b.crba(q)).max()))
    return worst


def test_a_urdf_robots_tools_and_limits_are_in_the_saved_file(tmp_path):
    robot = _load(IIWA)
    lim = np.column_stack([robot.qlim[:, 0] * 0.5, robot.qlim[:, 1] * 0.25])
    changed = (robot.with_tool(_pose([0.01, -0.02, 0.15], [0.3, -0.2, 1.0]))
               .with_tool(_pose([0.0, 0.05, 0.0], [0.0, 0.4, 0.0]), "flange2").with_limits(lim))
    back = _load(changed.save(tmp_path / "iiwa_tool.urdf"))
    assert back.tip == "flange2"
    assert _same_robot(changed, back) < 1e-12
    assert _same_robot(robot.with_limits(lim), back) > 0.1  # the file alone (the old save): the tool lost
    assert np.allclose(back.qlim, lim, rtol=0, atol=0)
    # the rest of the file as it was: Drake's transmissions (reflected inertia) still read
    assert np.allclose(np.asarray(back.model.armature), np.asarray(robot.model.armature), rtol=0, atol=0)


def test_a_calibrated_robots_tool_is_in_the_saved_file(tmp_path):
    from robokit.calibration import chain_from_robot, robot_from_chain

    nominal = robokit.load("puma560")
    cal = robot_from_chain(nominal, chain_from_robot(nominal).perturbed(
        np.random.default_rng(0).uniform(-2e-3, 2e-3, (7, 6))))
    changed = cal.with_tool(_pose([0.0, 0.0, 0.12], [0.1, 0.2, 0.3]))
    back = _load(changed.save(tmp_path / "cal_tool.urdf"))
    assert back.tip == "tcp"
    assert _same_robot(changed, back) < 1e-12


def test_unlimited_revolute_joints_are_written_continuous(tmp_path):
    robot = _load(model_path("rrr", ".urdf"))
    lim = robot.qlim.copy()
    lim[1] = (-np.inf, np.inf)
    changed = robot.with_limits(lim)
    path = changed.save(tmp_path / "rrr_free.urdf")
    kinds = {j.get("name"): j.get("type") for j in ET.parse(path).getroot().findall("joint")}
    assert kinds[robot.joint_names[1]] == "continuous"
    back = _load(path)
    assert _same_robot(changed, back) < 1e-12


def test_a_half_open_limit_cannot_be_written_and_nothing_is(tmp_path):
    robot = _load(model_path("rrr", ".urdf"))
    lim = robot.qlim.copy()
    lim[0, 1] = np.inf
    with pytest.raises(InputError, match=r"joint .* cannot hold; give finite limits"):
        robot.with_limits(lim).save(tmp_path / "x.urdf")
    assert not (tmp_path / "x.urdf").exists()


@settings(max_examples=15, deadline=None)
@given(xyz=st.lists(st.floats(-0.5, 0.5), min_size=3, max_size=3),
       rpy=st.lists(st.floats(-3.1, 3.1), min_size=3, max_size=3))
def test_any_tool_pose_survives_the_file(tmp_path_factory, xyz, rpy):
    robot = _load(model_path("rrr", ".urdf"))
    changed = robot.with_tool(_pose(xyz, rpy))
    back = _load(changed.save(tmp_path_factory.mktemp("t") / "rrr_tool.urdf"))
    assert back.tip == "tcp"
    assert _same_robot(changed, back, samples=2) < 1e-12


def test_a_tip_off_the_longest_chain_is_named_when_saved(tmp_path):
    """A URDF cannot record a tip chosen with tip=: the save warns with the tip= that loads it back."""
    robot = _load(IIWA, tip="iiwa_link_5")
    with pytest.warns(RobokitWarning, match=r"default tip is iiwa_link_ee, not 'iiwa_link_5': load it with "
                                            r"tip='iiwa_link_5'"):
        path = robot.save(tmp_path / "iiwa5.urdf")
    assert _load(path).tip == "iiwa_link_ee"
    assert _same_robot(robot, _load(path, tip="iiwa_link_5")) < 1e-12
    with warnings.catch_warnings():
        warnings.simplefilter("error", RobokitWarning)  # the default tip: nothing to say
        _load(IIWA).save(tmp_path / "iiwa.urdf")
