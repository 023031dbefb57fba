"""The Jacobian-transpose IK is a gradient step of size alpha*gain/damper on 1/2 |Delta|^2: it
converges when the step is below 2 / lambda_max(J^T J) of the tool-frame Jacobian and not when it
is well above it (the condition the docstring and the inverse-kinematics page state)."""
import numpy as np

import robokit as rk
from robokit.ik import ik_jacobian_transpose


def _lambda_max(robot, q):
    J = robot.jacobian(np.asarray(q, dtype=float), reference="local")
    return float(np.linalg.eigvalsh(J.T @ J).max())


def test_step_below_the_bound_converges_and_above_it_does_not():
    robot = rk.load("twolink")
    q_goal, q0 = np.array([0.5, 0.5]), np.array([0.3, 0.8])
    T = robot.frame_pose(q_goal)
    bound = min(2.0 / _lambda_max(robot, q) for q in np.linspace(q0, q_goal, 5))
    assert 0.2 < bound < 0.5  # the default alpha = 0.5 is too large for this arm
    ok = ik_jacobian_transpose(robot, T, q0, alpha=0.2)
    assert ok.success and np.allclose(robot.frame_pose(ok.q), T, atol=1e-7)
    bad = ik_jacobian_transpose(robot, T, q0, max_iterations=2000)
    assert not bad.success


def test_puma_default_step_is_below_its_bound():
    robot = rk.load("puma560")
    q_goal = np.array([0.1, 0.2, 0.3, 0.4, 0.5, 0.6])
    assert 0.5 < 2.0 / _lambda_max(robot, q_goal)
    res = ik_jacobian_transpose(robot, robot.frame_pose(q_goal), q_goal + 0.1)
    assert res.success and np.allclose(res.q, q_goal, atol=1e-6)
