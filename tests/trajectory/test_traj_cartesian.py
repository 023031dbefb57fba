"""Cartesian straight line with slerp orientation (Lecture 3): SO(3), fixed axis, Pinocchio slerp, derivatives."""
import numpy as np
import pinocchio as pin
import pytest
from hypothesis import given, settings, strategies as st

from robokit import matrix_exp_6, vec_to_se3
from robokit.trajectory import cartesian_line_trajectory, slerp_rotation


def random_pose(rng, angle_max=3.0):
    w = rng.normal(size=3)
    w *= rng.uniform(0.05, angle_max) / np.linalg.norm(w)
    return matrix_exp_6(vec_to_se3(np.concatenate([w, rng.normal(size=3)])))


def unit(v):
    return v / np.linalg.norm(v)


@settings(max_examples=60, deadline=None)
@given(st.integers(0, 2**32 - 1), st.sampled_from(["cubic", "quintic", "lspb", 3, 5]))
def test_line_stays_on_SO3_rotates_about_one_axis_and_moves_straight(seed, method):
    rng = np.random.default_rng(seed)
    X0, X1 = random_pose(rng), random_pose(rng)
    tr = cartesian_line_trajectory(X0, X1, 2.0, t=41, method=method)
    P = tr.poses
    assert P.shape == (41, 4, 4)
    np.testing.assert_allclose(P[0], X0, atol=1e-14)
    np.testing.assert_allclose(P[-1], X1, atol=1e-12)
    R = P[:, :3, :3]
    np.testing.assert_allclose(np.einsum("kji,kjl->kil", R, R), np.broadcast_to(np.eye(3), R.shape), atol=1e-12)
    np.testing.assert_allclose(np.linalg.det(R), 1.0, atol=1e-12)
    np.testing.assert_array_equal(P[:, 3, :], np.broadcast_to([0, 0, 0, 1], (41, 4)))
    # one fixed axis: the world-frame rotation vector of R(t) R0ᵀ is parallel to the same axis
    axis = tr.info["axis_world"]
    s = tr.info["s"]
    theta = tr.info["angle"]
    for k in range(41):
        w = pin.log3(R[k] @ X0[:3, :3].T)
        np.testing.assert_allclose(w, s[k] * theta * axis, atol=1e-9)
    # straight line, at the fraction s of the way
    d = X1[:3, 3] - X0[:3, 3]
    np.testing.assert_allclose(P[:, :3, 3], X0[:3, 3] + s[:, None] * d, atol=1e-12)


def test_orientation_matches_pinocchio_quaternion_slerp():
    rng = np.random.default_rng(11)
    for _ in range(20):
        X0, X1 = random_pose(rng), random_pose(rng)
        q0, q1 = pin.Quaternion(X0[:3, :3]), pin.Quaternion(X1[:3, :3])
        for s in np.linspace(0, 1, 7):
            np.testing.assert_allclose(slerp_rotation(X0[:3, :3], X1[:3, :3], s), q0.slerp(s, q1).matrix(), atol=1e-9)


def test_velocity_and_acceleration_are_the_derivatives():
    rng = np.random.default_rng(5)
    X0, X1 = random_pose(rng), random_pose(rng)
    tr = cartesian_line_trajectory(X0, X1, 1.5, t=3001, method="quintic")
    h = tr.t[1] - tr.t[0]
    np.testing.assert_allclose((tr.q[2:] - tr.q[:-2]) / (2 * h), tr.qd[1:-1], atol=1e-5)
    np.testing.assert_allclose((tr.qd[2:] - tr.qd[:-2]) / (2 * h), tr.qdd[1:-1], atol=1e-4)
    # ω from the rotation matrices themselves: log(R(t+h) R(t−h)ᵀ)/(2h) (world frame)
    R = tr.poses[:, :3, :3]
    for k in range(100, 3000, 250):
        w = pin.log3(R[k + 1] @ R[k - 1].T) / (2 * h)
        np.testing.assert_allclose(w, tr.qd[k, :3], atol=1e-5)
    assert tr.labels == ("φx", "φy", "φz", "x", "y", "z")


def test_angle_axis_non_uniqueness_long_way():
    Rz = lambda a: np.array([[np.cos(a), -np.sin(a), 0], [np.sin(a), np.cos(a), 0], [0, 0, 1.0]])
    R0, R1 = np.eye(3), Rz(np.pi / 2)
    short = slerp_rotation(R0, R1, np.linspace(0, 1, 5))
    long = slerp_rotation(R0, R1, np.linspace(0, 1, 5), shortest=False)
    np.testing.assert_allclose(short[2], Rz(np.pi / 4), atol=1e-14)
    # the other angle–axis form of the same rotation: −3π/2 about z, passing −3π/4 halfway
    np.testing.assert_allclose(long[2], Rz(-3 * np.pi / 4), atol=1e-14)
    np.testing.assert_allclose(long[-1], R1, atol=1e-14)
    for R in long:
        w = pin.log3(R)
        assert np.linalg.norm(w[:2]) < 1e-12  # still about the z axis
    with pytest.raises(ValueError, match="shortest"):
        slerp_rotation(R0, R0, 0.5, shortest=False)


def test_bad_input():
    with pytest.raises(ValueError, match="T_end"):
        cartesian_line_trajectory(np.eye(4), np.ones((4, 4)), 1.0)
    with pytest.raises(ValueError, match="tf"):
        cartesian_line_trajectory(np.eye(4), np.eye(4), 0.0)
    with pytest.raises(ValueError, match="method"):
        cartesian_line_trajectory(np.eye(4), np.eye(4), 1.0, method=7)
    with pytest.raises(ValueError, match="R1"):
        slerp_rotation(np.eye(3), np.eye(3) * 2, 0.5)
