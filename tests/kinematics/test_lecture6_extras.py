"""geometric_jacobian (lecture's closed form, Pinocchio), the damped inverse (J + pI)⁻¹ and the
Jacobian-transpose IK with viscous dampers."""
import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import robokit
from robokit.ik.transpose import ik_jacobian_transpose
from robokit.kinematics.velocity import geometric_jacobian, resolved_rate


@pytest.fixture(scope="module")
def twolink():
    return robokit.load("twolink")


@settings(max_examples=25, deadline=None)
@given(st.floats(-3, 3), st.floats(-3, 3))
def test_geometric_jacobian_twolink_lecture_closed_form(twolink, t1, t2):
    a1, a2 = 1.0, 0.8  # models/twolink.yaml
    J = geometric_jacobian(twolink, [t1, t2])
    s1, c1, s12, c12 = np.sin(t1), np.cos(t1), np.sin(t1 + t2), np.cos(t1 + t2)
    Jv = np.array([[-a1 * s1 - a2 * s12, -a2 * s12], [a1 * c1 + a2 * c12, a2 * c12]])  # Lecture 6
    np.testing.assert_allclose(J[3:5], Jv, atol=1e-12)
    np.testing.assert_allclose(J[5], 0.0, atol=1e-12)
    np.testing.assert_allclose(J[:3], [[0, 0], [0, 0], [1, 1]], atol=1e-12)


@pytest.mark.parametrize("name", ["puma560", "rrr", "ur5"])
def test_geometric_jacobian_matches_pinocchio(name):
    import pinocchio as pin

    robot = robokit.load(name)
    q = robot.random_configuration(1)
    J = geometric_jacobian(robot, q)
    Jp = pin.computeFrameJacobian(robot.model, robot.model.createData(), robot.q_pin(q), robot.tip_id,
                                  pin.ReferenceFrame.LOCAL_WORLD_ALIGNED)
    np.testing.assert_allclose(J, np.r_[Jp[3:], Jp[:3]], atol=1e-10)  # Pinocchio is (v; ω)


@settings(max_examples=30, deadline=None)
@given(st.integers(0, 10_000), st.floats(1e-3, 0.5))
def test_damped_inverse_residual_is_minus_p_qdot(seed, p):
    rng = np.random.default_rng(seed)
    J, V = rng.normal(size=(6, 6)), rng.normal(size=6)
    dq = resolved_rate(J, V, method="damped_inverse", damping=p)
    np.testing.assert_allclose(J @ dq - V, -p * dq, atol=1e-8 * (1 + np.abs(dq).max()))


def test_damped_inverse_finite_at_singularity_and_exact_without_damping():
    J = np.diag([1.0, 1.0, 0.0])  # singular
    dq = resolved_rate(J, [1.0, 2.0, 3.0], method="damped_inverse", damping=0.01)
    assert np.all(np.isfinite(dq))
    A = np.array([[2.0, 1.0], [0.5, 3.0]])
    np.testing.assert_allclose(resolved_rate(A, [1.0, 1.0], method="damped_inverse", damping=0.0),
                               np.linalg.solve(A, [1.0, 1.0]))
    with pytest.raises(ValueError, match="square"):
        resolved_rate(np.ones((2, 3)), [1.0, 1.0], method="damped_inverse")


def test_jacobian_transpose_ik_reaches_the_goal():
    robot = robokit.load("puma560")
    q_goal = np.array([0.4, -0.6, 0.3, 0.5, 0.8, -0.3])
    T = robot.frame_pose(q_goal)
    res = ik_jacobian_transpose(robot, T, q_goal + np.array([0.2, -0.15, 0.2, -0.2, 0.15, 0.2]), tol=1e-8)
    assert res.success
    T_got = robot.frame_pose(res.q)
    assert np.linalg.norm(T_got[:3, 3] - T[:3, 3]) < 1e-7
    assert np.linalg.norm(T_got[:3, :3] - T[:3, :3]) < 1e-7


def test_jacobian_transpose_ik_reports_unreachable():
    robot = robokit.load("twolink")
    T = np.eye(4)
    T[:3, 3] = [3.0, 0.0, 0.0]  # beyond l1 + l2 = 1.8 m
    res = ik_jacobian_transpose(robot, T, [0.3, 0.3], max_iterations=300)
    assert not res.success
    assert res.position_error > 1.0
    with pytest.raises(ValueError, match="damper"):
        ik_jacobian_transpose(robot, T, damper=0.0)
