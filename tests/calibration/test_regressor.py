"""The Newton–Euler regressor against Pinocchio's computeJointTorqueRegressor and rnea; base parameters
as a property (Y π = Y_b C π for any π)."""
import numpy as np
import pinocchio as pin
import pytest
from calibration_support import motions
from hypothesis import given, settings
from hypothesis import strategies as st

from robokit.calibration import (
    base_parameters,
    chain_from_robot,
    friction_regressor,
    full_regressor,
    inertial_regressor,
    standard_parameter_names,
    standard_parameters,
)
from robokit.description.robot import Robot

NAMES = ["puma560", "ur5", "rrr", "rpr", "panda"]


@pytest.mark.parametrize("name", NAMES)
def test_regressor_equals_pinocchio(robots, name):
    robot = robots(name)
    rng = np.random.default_rng(1)
    q, dq, ddq = motions(robot, 6, rng)
    Y = inertial_regressor(chain_from_robot(robot), q, dq, ddq, robot.gravity)
    for k in range(len(q)):
        Yp = pin.computeJointTorqueRegressor(robot.model, robot.data, robot.q_pin(q[k]), dq[k], ddq[k])
        np.testing.assert_allclose(Y[k], Yp, atol=1e-10)
    np.testing.assert_allclose(Y @ standard_parameters(robot), robot.rnea(q, dq, ddq), atol=1e-9)


@settings(max_examples=15, deadline=None, derandomize=True)
@given(seed=st.integers(0, 2**31 - 1))
def test_regressor_times_random_parameters_is_rnea(robots, seed):
    """For random standard parameters π (not necessarily physical), Y π equals Pinocchio's rnea of the
    model carrying those inertias."""
    robot = robots("puma560")
    rng = np.random.default_rng(seed)
    pi = rng.normal(0, 1, 10 * robot.n)
    model = pin.Model(robot.model)
    for j in range(robot.n):
        model.inertias[j + 1] = pin.Inertia.FromDynamicParameters(pi[10 * j:10 * j + 10])
    other = Robot("random", model, robot.tip)
    q, dq, ddq = motions(robot, 3, rng)
    Y = inertial_regressor(chain_from_robot(robot), q, dq, ddq, robot.gravity)
    np.testing.assert_allclose(Y @ pi, other.rnea(q, dq, ddq), atol=1e-8 * (1 + np.abs(Y @ pi).max()))


def test_friction_columns():
    dq = np.array([[0.5, -2.0, 0.0]])
    F = friction_regressor(dq)
    fv, fc = np.array([1.0, 2.0, 3.0]), np.array([0.1, 0.2, 0.3])
    theta = np.ravel(np.column_stack([fv, fc]))
    np.testing.assert_allclose(F[0] @ theta, fv * dq[0] + fc * np.sign(dq[0]))


@pytest.mark.parametrize("name", ["puma560", "rrr", "rpr"])
def test_base_parameters_reproduce_every_parameter_set(robots, name):
    robot = robots(name)
    bp = base_parameters(robot)
    rng = np.random.default_rng(4)
    q, dq, ddq = motions(robot, 40, rng)
    W = full_regressor(chain_from_robot(robot), q, dq, ddq, robot.gravity)
    Wb = W[:, :, bp.independent]
    p = W.shape[2]
    for _ in range(3):
        pi = rng.normal(0, 1, p)
        np.testing.assert_allclose(Wb @ bp.of(pi), W @ pi, atol=1e-8 * (1 + np.abs(W @ pi).max()))
    # the base regressor has full column rank and spans the full one (independent SVD rank)
    s = np.linalg.svd(W.reshape(-1, p), compute_uv=False)
    assert bp.count == int(np.sum(s > 1e-9 * s[0]))
    assert np.linalg.matrix_rank(Wb.reshape(-1, bp.count)) == bp.count
    assert len(bp.meaning()) == bp.count
    assert bp.names == standard_parameter_names(robot.n)


def test_base_parameter_meaning_planar_arm(robots):
    """The planar 3R arm (joints parallel, gravity in the plane) has 3 base inertial parameters per link
    (Khalil & Dombre: a planar link contributes m·cx, m·cy, Izz after regrouping) — 9 — plus 6 friction."""
    robot = robots("rrr")
    bp = base_parameters(robot)
    assert bp.count == 9 + 6
    text = " ".join(bp.meaning())
    assert "I3zz" in text and "fv1" in text


def test_base_parameters_do_not_depend_on_samples(robots):
    robot = robots("puma560")
    a, b = base_parameters(robot, rng=1), base_parameters(robot, rng=2, samples=200)
    np.testing.assert_array_equal(a.independent, b.independent)
    np.testing.assert_allclose(a.beta, b.beta, atol=1e-8)
