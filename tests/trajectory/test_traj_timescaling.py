"""Seed/MR time scalings and point-to-point trajectories: closed forms, modern_robotics, Pinocchio."""
import numpy as np
import pinocchio as pin
import pytest
from hypothesis import given, settings, strategies as st

from robokit import cartesian_trajectory, cubic_time_scaling, joint_trajectory, matrix_exp_6, quintic_time_scaling, screw_trajectory, vec_to_se3
from robokit.trajectory import time_scaling


def random_pose(rng, angle_max=3.0):
    w = rng.normal(size=3)
    w *= rng.uniform(0, angle_max) / np.linalg.norm(w)
    return matrix_exp_6(vec_to_se3(np.concatenate([w, rng.normal(size=3)])))


def test_closed_form_values():
    # s = 3(0.3)² − 2(0.3)³ = 0.27 − 0.054 = 0.216
    assert cubic_time_scaling(2, 0.6) == pytest.approx(0.216, abs=1e-15)
    # s = 10(0.3)³ − 15(0.3)⁴ + 6(0.3)⁵ = 0.27 − 0.1215 + 0.01458 = 0.16308
    assert quintic_time_scaling(2, 0.6) == pytest.approx(0.16308, abs=1e-15)
    assert cubic_time_scaling(5, 0.0) == 0.0 and cubic_time_scaling(5, 5.0) == 1.0
    assert quintic_time_scaling(5, 2.5) == pytest.approx(0.5, abs=1e-15)
    np.testing.assert_allclose(cubic_time_scaling(2.0, np.array([0.0, 1.0, 2.0])), [0.0, 0.5, 1.0], atol=1e-15)


@pytest.mark.parametrize("method", ["cubic", "quintic", "lspb"])
def test_time_scaling_derivatives_and_ends(method):
    T = 1.7
    t = np.linspace(0, T, 20001)
    s, sd, sdd = time_scaling(method, T, t)
    assert s[0] == 0.0 and abs(s[-1] - 1.0) < 1e-14 and sd[0] == 0.0 and abs(sd[-1]) < 1e-14
    h = t[1] - t[0]
    # central differences: O(h²) error, O(h·|s̈ jump|) next to the LSPB blend ends
    np.testing.assert_allclose((s[2:] - s[:-2]) / (2 * h), sd[1:-1], atol=max(1e-6, h * np.abs(sdd).max()))
    inner = slice(2, -2)
    fdd = (sd[2:] - sd[:-2]) / (2 * h)
    ok = np.abs(fdd - sdd[1:-1])[inner]
    if method == "lspb":  # sdd jumps at the two blend ends: skip the samples next to them
        assert np.sum(ok > 1e-6) <= 4
        assert sd.max() == pytest.approx(1.5 / T)
    else:
        assert ok.max() < 1e-6
    if method == "quintic":
        assert sdd[0] == 0.0 and abs(sdd[-1]) < 1e-12


def test_joint_trajectory_example_and_shape():
    traj = joint_trajectory([1, 0, 0, 1, 1, 0.2, 0, 1], [1.2, 0.5, 0.6, 1.1, 2, 2, 0.9, 1], 4, 6, 3)
    assert traj.shape == (6, 8)
    np.testing.assert_allclose(traj[0], [1, 0, 0, 1, 1, 0.2, 0, 1])
    np.testing.assert_allclose(traj[-1], [1.2, 0.5, 0.6, 1.1, 2, 2, 0.9, 1], atol=1e-15)
    # the Modern Robotics book's printed example (JointTrajectory docstring), 4 decimals
    np.testing.assert_allclose(traj[1], [1.0208, 0.052, 0.0624, 1.0104, 1.104, 0.3872, 0.0936, 1], atol=1e-4)


@pytest.mark.parametrize("method", [3, 5])
def test_against_modern_robotics(method):
    mr = pytest.importorskip("modern_robotics")
    rng = np.random.default_rng(7)
    for _ in range(10):
        Tf = rng.uniform(0.5, 5.0)
        t = rng.uniform(0, Tf)
        ref = mr.CubicTimeScaling(Tf, t) if method == 3 else mr.QuinticTimeScaling(Tf, t)
        got = cubic_time_scaling(Tf, t) if method == 3 else quintic_time_scaling(Tf, t)
        assert abs(got - ref) < 1e-12
        a, b = rng.normal(size=4), rng.normal(size=4)
        N = int(rng.integers(2, 12))
        np.testing.assert_allclose(joint_trajectory(a, b, Tf, N, method), mr.JointTrajectory(a, b, Tf, N, method), atol=1e-12)
        X0, X1 = random_pose(rng), random_pose(rng)
        for ours, theirs in zip(screw_trajectory(X0, X1, Tf, N, method), mr.ScrewTrajectory(X0, X1, Tf, N, method)):
            np.testing.assert_allclose(ours, theirs, atol=1e-9)
        for ours, theirs in zip(cartesian_trajectory(X0, X1, Tf, N, method), mr.CartesianTrajectory(X0, X1, Tf, N, method)):
            np.testing.assert_allclose(ours, theirs, atol=1e-9)


@settings(max_examples=40, deadline=None)
@given(st.integers(0, 2**32 - 1), st.sampled_from([3, 5]), st.integers(2, 9))
def test_screw_trajectory_against_pinocchio(seed, method, N):
    rng = np.random.default_rng(seed)
    X0, X1 = random_pose(rng), random_pose(rng)
    path = screw_trajectory(X0, X1, 2.0, N, method)
    assert len(path) == N
    V = pin.log6(pin.SE3(X0).inverse() * pin.SE3(X1))  # pinocchio: linear first
    for k, X in enumerate(path):
        s = (cubic_time_scaling if method == 3 else quintic_time_scaling)(2.0, 2.0 * k / (N - 1))
        ref = (pin.SE3(X0) * pin.exp6(V * s)).homogeneous
        np.testing.assert_allclose(X, ref, atol=1e-9)
    np.testing.assert_allclose(path[-1], X1, atol=1e-9)


def test_cartesian_trajectory_is_a_straight_line_with_fixed_axis():
    rng = np.random.default_rng(3)
    X0, X1 = random_pose(rng), random_pose(rng)
    path = cartesian_trajectory(X0, X1, 3.0, 11, 5)
    d = X1[:3, 3] - X0[:3, 3]
    axis = None
    for X in path:
        r = X[:3, 3] - X0[:3, 3]
        assert np.linalg.norm(np.cross(r, d)) < 1e-12
        w = pin.log3(X0[:3, :3].T @ X[:3, :3])
        if np.linalg.norm(w) > 1e-6:
            u = w / np.linalg.norm(w)
            axis = u if axis is None else axis
            assert abs(abs(u @ axis) - 1) < 1e-12
    np.testing.assert_allclose(path[-1], X1, atol=1e-12)


@pytest.mark.parametrize(
    "call, word",
    [
        (lambda: joint_trajectory([0, 0], [1, 1], 1.0, 5, 4), "method"),
        (lambda: joint_trajectory([0, 0], [1, 1], 1.0, 5, "lspb"), "method"),
        (lambda: joint_trajectory([0, 0], [1, 1], 1.0, 1, 3), "N"),
        (lambda: joint_trajectory([0, 0], [1, 1], 1.0, 2.5, 3), "N"),
        (lambda: joint_trajectory([0, 0], [1, 1], 0.0, 5, 3), "Tf"),
        (lambda: joint_trajectory([0, 0], [1, 1, 1], 1.0, 5, 3), "thetaend"),
        (lambda: screw_trajectory(np.eye(4), np.eye(4), 1.0, 5, 7), "method"),
        (lambda: cartesian_trajectory(np.eye(4), 2 * np.eye(4), 1.0, 5, 3), "Xend"),
        (lambda: cubic_time_scaling(0, 0.5), "Tf"),
        (lambda: quintic_time_scaling(-1, 0.5), "Tf"),
    ],
)
def test_bad_input(call, word):
    with pytest.raises(ValueError, match=word):
        call()
