"""``NAME_joint_poses`` (every joint frame's pose, the teach page's placements come from it) against
Pinocchio's ``data.oMi[1..n]``, compiled with the strict flags through ctypes, on arms the repository
does not ship: random standard and modified DH tables (prismatic joints, base and tool offsets), a
calibrated arm (every joint placement perturbed, as ``robokit.calibrate`` builds its result) and a
general 6R arm; plus its declaration in the header."""
import numpy as np
import pytest

import robokit
from tests.codegen.test_codegen import calibrated_arm, jaco2_table, joint_frames, random_table


def _arms():
    return {
        "random standard DH": lambda: robokit.load(random_table(101, "standard", "RRPRRR")),
        "random modified DH": lambda: robokit.load(random_table(202, "modified", "RPRRRRR")),
        "calibrated PUMA": lambda: calibrated_arm("puma560", 5),
        "general 6R (JACO2)": lambda: robokit.load(jaco2_table()),
        "ur5 (URDF)": lambda: robokit.load("ur5"),
    }


@pytest.mark.parametrize("which", list(_arms()))
def test_joint_poses_equal_pinocchio_oMi(build, which):
    robot = _arms()[which]()
    lib = build(robot)
    rng = np.random.default_rng(3)
    for _ in range(10):
        q = robot.random_configuration(rng)
        ref = joint_frames(robot, q)
        got = lib.joint_poses(q)
        assert got.shape == (robot.n, 4, 4)
        # 1e-12 of the arm's size (rotation entries are ≤ 1, positions ≤ the reach)
        assert np.abs(got - ref).max() <= 1e-12 * max(1.0, float(np.abs(ref).max())), which
        # the last joint's frame carried by its constant placement is the tool (Pinocchio's frame_pose)
        tip = robot.model.frames[robot.tip_id]
        if tip.parentJoint == robot.n:
            np.testing.assert_allclose(got[-1] @ tip.placement.homogeneous, lib.fk(q), rtol=0, atol=1e-12)


def test_header_declares_joint_poses():
    from robokit.codegen import generate_c

    src = generate_c(robokit.load("puma560"))
    assert "void puma560_joint_poses(const double q[puma560_N], double T[16 * puma560_N]);" in src.header
    assert "data.oMi[k]" in src.header
