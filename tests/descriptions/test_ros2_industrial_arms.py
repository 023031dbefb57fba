"""Industrial arms as their makers publish them for ROS 2 (Techman TM5-900, DENSO VS-060, Dobot ME6;
tests/data/<maker>/SOURCE), loaded with :func:`robokit.load` from the makers' own xacro files (with the
xacro arguments a user passes) and held against Pinocchio built directly from the ``xacro`` program's
expansion of the same files (tests/support/xacro_reference.py, not through robokit).

Compared at random joint values within the file's limits: the pose of every link frame, the space, body
and geometric Jacobians of the tip, M and the gravity torques (to 1e-12 of each quantity's largest
entry), the position, velocity and effort limits; and what robokit says once about what it does not
model (missing meshes, <gazebo>, <transmission>, <ros2_control>).
"""
from __future__ import annotations

import warnings
from pathlib import Path

import numpy as np
import pinocchio as pin
import pytest

import robokit
from xacro_reference import xacro_urdfs

DATA = Path(__file__).resolve().parents[1] / "data"
DENSO = "denso_robot_descriptions/urdf/denso_robot.urdf.xacro"

#: label -> (maker folder under tests/data, xacro file inside it, xacro arguments, tip,
#: the blocks robokit notes as read but not modelled)
ARMS = {
    "Techman TM5-900": ("techman", "tm_description/xacro/tm5-900.urdf.xacro", {}, "flange",
                        ("<gazebo>", "<transmission>")),
    "Techman TM5-900 prefix": ("techman", "tm_description/xacro/tm5-900.urdf.xacro", {"prefix": "left_"},
                               "left_flange", ("<gazebo>", "<transmission>")),
    "DENSO VS-060": ("denso", DENSO, {"model": "vs060"}, "J6", ("<gazebo>", "<transmission>", "<ros2_control>")),
    "Dobot ME6": ("dobot", "cra_description/urdf/me6_robot.xacro", {}, "Link6", ("<gazebo>", "<ros2_control>")),
}


@pytest.fixture(scope="module")
def reference() -> dict[str, str]:
    """The xacro program's URDF of every arm (one subprocess for all)."""
    return xacro_urdfs({k: (DATA / m, f, a) for k, (m, f, a, _, _) in ARMS.items()})


def load(label: str) -> tuple[robokit.Robot, list[str]]:
    """The arm as a user loads it (the file and its arguments: its packages are found beside it), and
    what robokit said."""
    maker, rel, args, _, _ = ARMS[label]
    with warnings.catch_warnings(record=True) as said:
        warnings.simplefilter("always")
        robot = robokit.load(DATA / maker / rel, xacro_args=args or None)
    return robot, [str(w.message) for w in said]


@pytest.mark.parametrize("label", list(ARMS))
def test_arm_matches_pinocchio_on_the_xacro_program_output(label, reference):
    robot, said = load(label)
    model = pin.buildModelFromXML(reference[label])
    data = model.createData()
    assert robot.tip == ARMS[label][3] and robot.n == 6
    joints = [model.joints[model.getJointId(j)] for j in robot.joint_names]
    iq, iv = [j.idx_q for j in joints], [j.idx_v for j in joints]
    assert len(set(robot.joint_names)) == 6 and all(model.existJointName(j) for j in robot.joint_names)
    lo, hi = model.lowerPositionLimit[iq], model.upperPositionLimit[iq]
    assert np.array_equal(np.asarray(robot.qlim, float), np.c_[lo, hi])
    rv = [robot.model.joints[robot.model.getJointId(j)].idx_v for j in robot.joint_names]
    assert np.array_equal(robot.model.velocityLimit[rv], model.velocityLimit[iv])
    assert np.array_equal(robot.model.effortLimit[rv], model.effortLimit[iv])

    body = pin.FrameType.BODY
    links = [f for f in robot.frame_names if model.existFrame(f, body)]
    assert robot.tip in links and len(links) >= 7  # the base, six links, the flange
    fid = model.getFrameId(robot.tip, body)
    frames = {
        pin.WORLD: robokit.Frame.WORLD, pin.LOCAL: robokit.Frame.LOCAL,
        pin.LOCAL_WORLD_ALIGNED: robokit.Frame.LOCAL_WORLD_ALIGNED,
    }
    rng = np.random.default_rng(11)
    worst = dict(pose=0.0, J=0.0, M=0.0, g=0.0)
    for _ in range(20):
        q = rng.uniform(lo, hi)
        qf = pin.neutral(model)
        qf[iq] = q
        pin.framesForwardKinematics(model, data, qf)
        for f in links:
            worst["pose"] = max(worst["pose"], np.abs(robot.frame_pose(q, f) - data.oMf[model.getFrameId(f, body)].homogeneous).max())
        for ref, rk_ref in frames.items():
            J = pin.computeFrameJacobian(model, data, qf, fid, ref)[:, iv]
            J = np.vstack([J[3:], J[:3]])  # robokit: angular rows first
            worst["J"] = max(worst["J"], np.abs(robot.jacobian(q, reference=rk_ref) - J).max() / np.abs(J).max())
        M = pin.crba(model, data, qf)
        M = (np.triu(M) + np.triu(M, 1).T)[np.ix_(iv, iv)]
        g = pin.computeGeneralizedGravity(model, data, qf)[iv]
        assert np.abs(M).max() > 1e-3 and np.abs(g).max() > 1e-2  # these files give inertias
        worst["M"] = max(worst["M"], np.abs(robot.crba(q) - M).max() / np.abs(M).max())
        worst["g"] = max(worst["g"], np.abs(robot.gravity_torques(q) - g).max() / np.abs(g).max())
    assert max(worst.values()) < 1e-12, worst

    assert not [s for s in said if "has mass (the file gives none)" in s], said
    assert len([s for s in said if "mesh files not found" in s]) == 1, said  # one note, not one per mesh
    for block in ARMS[label][4]:  # each block the file has and robokit does not model: one note
        assert len([s for s in said if block in s and "read but not modelled" in s]) == 1, (block, said)


def test_the_prefix_renames_and_moves_nothing():
    """tm5-900.urdf.xacro's prefix argument names every link and joint; the arm is the same arm."""
    plain, _ = load("Techman TM5-900")
    left, _ = load("Techman TM5-900 prefix")
    assert left.joint_names == tuple("left_" + j for j in plain.joint_names)
    q = np.random.default_rng(3).uniform(-2, 2, 6)
    assert np.abs(left.frame_pose(q) - plain.frame_pose(q)).max() == 0.0
