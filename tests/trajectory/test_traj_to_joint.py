"""joint_trajectory_from_cartesian: IK along a Cartesian path; workspace exits and singular joint rates reported.

The robot is a local planar 2R arm (link lengths 1, 1, joints about z) with the Robot
interface the converter uses (n, qlim, frame_pose, jacobian), written here from its
textbook forward kinematics, so the test does not depend on other areas' robot loading.
"""
import numpy as np
import pytest

from robokit import Rp_to_trans, Trajectory
from robokit.trajectory import cartesian_line_trajectory, joint_trajectory_from_cartesian
from robokit.ik.analytic import ik_planar_2link

L1 = L2 = 1.0


class Planar2R:
    n = 2
    qlim = np.array([[-np.pi, np.pi], [-np.pi, np.pi]])
    joint_names = ("shoulder", "elbow")

    def frame_pose(self, q, frame=None):
        c1, s1 = np.cos(q[0]), np.sin(q[0])
        c12, s12 = np.cos(q[0] + q[1]), np.sin(q[0] + q[1])
        T = np.eye(4)
        T[:2, :2] = [[c12, -s12], [s12, c12]]
        T[:3, 3] = [L1 * c1 + L2 * c12, L1 * s1 + L2 * s12, 0.0]
        return T

    def jacobian(self, q, frame=None, reference="world"):
        T = self.frame_pose(q)
        p = T[:3, 3]
        p1 = np.array([L1 * np.cos(q[0]), L1 * np.sin(q[0]), 0.0])
        z = np.array([0.0, 0.0, 1.0])
        J = np.zeros((6, 2))
        for j, pj in enumerate([np.zeros(3), p1]):
            J[:3, j] = z
            J[3:, j] = np.cross(z, p - pj)  # origin velocity, world axes
        if reference == "local_world_aligned":
            return J
        if reference == "local":
            R = T[:3, :3]
            return np.vstack([R.T @ J[:3], R.T @ J[3:]])
        raise ValueError(reference)


def analytic_ik(T, q_guess):
    return ik_planar_2link(T[0, 3], T[1, 3], L1, L2)


def line(p0, p1, tf=2.0, K=201):
    return cartesian_line_trajectory(Rp_to_trans(np.eye(3), p0), Rp_to_trans(np.eye(3), p1), tf, t=K, method="quintic")


@pytest.mark.parametrize("ik", [analytic_ik, None], ids=["closed-form", "solve_ik"])
def test_follows_the_line_and_joint_velocity_maps_to_tool_velocity(ik):
    robot = Planar2R()
    path = line([1.2, 0.3, 0.0], [0.4, 1.1, 0.0])
    qt = joint_trajectory_from_cartesian(robot, path, ik=ik, q0=[0.0, 1.0], position_only=True)
    assert isinstance(qt, Trajectory) and qt.q.shape == (201, 2)
    assert qt.labels == ("shoulder", "elbow")
    for k in range(0, 201, 20):
        np.testing.assert_allclose(robot.frame_pose(qt.q[k])[:3, 3], path.poses[k, :3, 3], atol=1e-9)
    # one branch all the way (elbow sign kept) and the differential kinematics hold: J(q) q̇ = ṗ
    assert np.all(qt.q[:, 1] > 0)
    for k in range(20, 181, 20):
        v = robot.jacobian(qt.q[k], reference="local_world_aligned")[3:] @ qt.qd[k]
        np.testing.assert_allclose(v, path.qd[k, 3:], atol=2e-4)
    assert np.all(qt.info["pose_error"] < 1e-9)
    assert np.all(np.isfinite(qt.info["jacobian_condition"]))


def test_unreachable_pose_is_reported():
    robot = Planar2R()
    path = line([1.5, 0.0, 0.0], [2.5, 0.0, 0.0], K=21)  # beyond reach 2 after halfway
    with pytest.raises(ValueError, match=r"traj: 10 of 21 poses cannot be reached.*workspace"):
        joint_trajectory_from_cartesian(robot, path, ik=analytic_ik, position_only=True)


def test_joint_rate_blow_up_near_singularity_is_flagged():
    robot = Planar2R()
    # passing 1 cm from the base, where the folded arm (θ2 ≈ π, l1 = l2) is singular:
    # θ1 must swing by about π in a few hundredths of a second
    path = line([-0.5, 0.01, 0.0], [0.5, 0.01, 0.0], tf=2.0, K=401)
    with pytest.warns(RuntimeWarning, match="singularity"):
        qt = joint_trajectory_from_cartesian(robot, path, ik=analytic_ik, q0=[np.pi / 2, 2.5], position_only=True, qd_limit=3.0)
    assert qt.info["rate_exceeded"].any()
    assert qt.info["max_joint_rate"].max() > 20.0
    assert qt.info["jacobian_condition"].max() > 50.0
    # a path well inside the workspace stays within the same limit
    calm = joint_trajectory_from_cartesian(robot, line([1.2, 0.3, 0.0], [0.4, 1.1, 0.0]), ik=analytic_ik, q0=[0.0, 1.0], position_only=True, qd_limit=3.0)
    assert not calm.info["rate_exceeded"].any()


def test_bad_input():
    robot = Planar2R()
    with pytest.raises(ValueError, match="traj"):
        joint_trajectory_from_cartesian(robot, Trajectory(np.zeros(2), np.zeros((2, 2))))
    with pytest.raises(TypeError, match="ik"):
        joint_trajectory_from_cartesian(robot, line([1.0, 0.0, 0.0], [1.1, 0.0, 0.0], K=3), ik=lambda T, q: "nonsense", position_only=True)
