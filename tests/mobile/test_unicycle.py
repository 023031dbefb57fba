"""Unicycle / differential drive: exact arc vs integrated ODE, equivalence with the bicycle, wheel
kinematics, and running with run_vehicle."""
import math

import numpy as np
import pytest

from robokit.mobile import BicycleModel, DifferentialDrive, UnicycleModel, run_vehicle


def test_step_is_the_exact_solution_of_the_ode():
    m = UnicycleModel()
    x0, u, dt = np.array([0.5, -1.0, 0.7]), np.array([1.3, -0.8]), 0.9
    x = x0.copy()
    h = dt / 2000
    for _ in range(2000):  # RK4 on the ODE
        k1 = m.deriv(x, u)
        k2 = m.deriv(x + h / 2 * k1, u)
        k3 = m.deriv(x + h / 2 * k2, u)
        k4 = m.deriv(x + h * k3, u)
        x = x + h / 6 * (k1 + 2 * k2 + 2 * k3 + k4)
    np.testing.assert_allclose(m.step(x0, u, dt), x, atol=1e-10)
    # turning on the spot
    np.testing.assert_allclose(m.step(x0, [0.0, 1.0], 0.5), x0 + [0, 0, 0.5])


def test_bicycle_is_a_unicycle_with_omega_v_tan_gamma_over_L():
    b, m = BicycleModel(L=2.0), UnicycleModel()
    x0 = np.array([1.0, 2.0, -0.4])
    v, g = 1.5, 0.3
    np.testing.assert_allclose(m.step(x0, [v, v / 2.0 * math.tan(g)], 0.7), b.step(x0, [v, g], 0.7), atol=1e-12)


def test_differential_drive_wheel_kinematics():
    dd = DifferentialDrive(r=0.1, W=0.5)
    np.testing.assert_allclose(dd.body_velocity([10, 10]), [1.0, 0.0])
    np.testing.assert_allclose(dd.body_velocity([-5, 5]), [0.0, 2 * 0.1 * 5 / 0.5])  # spin in place
    u = np.array([0.6, -1.1])
    np.testing.assert_allclose(dd.body_velocity(dd.wheel_speeds(u)), u)
    # wheel limit: scaled together, curvature kept
    lim = dd.limit([10.0, 10.0])
    assert np.abs(dd.wheel_speeds(lim)).max() == pytest.approx(dd.wheel_max)
    assert lim[1] / lim[0] == pytest.approx(1.0)
    with pytest.raises(ValueError, match="W"):
        DifferentialDrive(0.1, 0.0)


def test_runs_with_run_vehicle_and_reaches_a_point():
    goal = np.array([3.0, 2.0])

    def ctrl(t, x, dt):  # move to a point, (v, ω) form
        th_goal = math.atan2(goal[1] - x[1], goal[0] - x[0])
        err = math.remainder(th_goal - x[2], 2 * math.pi)
        return [0.5 * np.linalg.norm(goal - x[:2]), 3.0 * err]

    run = run_vehicle(DifferentialDrive(0.1, 0.4), ctrl, [0, 0, 0], T=30.0, dt=0.05)
    assert np.linalg.norm(run.x[-1, :2] - goal) < 0.05
    # no sideways motion (non-holonomic): finite differences of the path stay along the heading
    d = np.diff(run.x[:, :2], axis=0)
    side = d[:, 1] * np.cos(run.x[:-1, 2] + np.diff(run.x[:, 2]) / 2) - d[:, 0] * np.sin(run.x[:-1, 2] + np.diff(run.x[:, 2]) / 2)
    assert np.abs(side).max() < 1e-3
