"""Exciting trajectories: limits, periodicity, analytic derivatives, determinism, and a better-conditioned
identification than the starting coefficients."""
import numpy as np
import pytest
from calibration_support import perturbed_inertias

import robokit
from robokit.calibration import fourier_series
from robokit.errors import InputError


@pytest.fixture(scope="module")
def puma_trajectory(robots):
    robot = robots("puma560")
    return robot, robokit.excitation_trajectory(robot, 8.0, harmonics=4, qd_max=1.5, qdd_max=4.0, max_evaluations=60,
                                                samples=801)


def test_limits_rest_and_periodicity(puma_trajectory):
    robot, tr = puma_trajectory
    assert tr.q.shape == tr.qd.shape == tr.qdd.shape == (801, robot.n)
    assert tr.t[0] == 0.0 and tr.t[-1] == 8.0
    lo, hi = robot.qlim[:, 0], robot.qlim[:, 1]
    assert np.all(tr.q >= lo) and np.all(tr.q <= hi)
    assert np.abs(tr.qd).max() <= 1.5 * (1 + 1e-3)
    assert np.abs(tr.qdd).max() <= 4.0 * (1 + 1e-3)
    for x in (tr.q, tr.qd, tr.qdd):
        np.testing.assert_allclose(x[0], x[-1], atol=1e-12)  # periodic: nothing jumps between periods
    np.testing.assert_allclose(tr.qd[0], 0.0, atol=1e-12)  # from rest
    np.testing.assert_allclose(tr.qdd[0], 0.0, atol=1e-12)


def test_derivatives_are_those_of_the_positions(puma_trajectory):
    _, tr = puma_trajectory
    h = 1e-5
    t = tr.t[100:110]
    info = tr.info
    qp, _, _ = fourier_series(info["a"], info["b"], info["q0"], info["period"], t + h)
    qm, _, _ = fourier_series(info["a"], info["b"], info["q0"], info["period"], t - h)
    _, dp, _ = fourier_series(info["a"], info["b"], info["q0"], info["period"], t + h)
    _, dm, _ = fourier_series(info["a"], info["b"], info["q0"], info["period"], t - h)
    np.testing.assert_allclose((qp - qm) / (2 * h), tr.qd[100:110], atol=1e-7)
    np.testing.assert_allclose((dp - dm) / (2 * h), tr.qdd[100:110], atol=1e-6)


def test_optimisation_improves_conditioning_and_is_deterministic(robots, puma_trajectory):
    robot, tr = puma_trajectory
    assert tr.info["condition_number"] < tr.info["initial_condition_number"]
    assert tr.info["evaluations"] <= 60
    again = robokit.excitation_trajectory(robot, 8.0, harmonics=4, qd_max=1.5, qdd_max=4.0, max_evaluations=60,
                                          samples=801)
    np.testing.assert_array_equal(again.q, tr.q)


def test_identification_along_the_trajectory(robots, puma_trajectory):
    robot, tr = puma_trajectory
    rng = np.random.default_rng(3)
    true = perturbed_inertias(robot, rng)
    fv, fc = rng.uniform(0.5, 2.0, robot.n), rng.uniform(0.1, 1.0, robot.n)
    tau = true.rnea(tr.q, tr.qd, tr.qdd) + fv * tr.qd + fc * np.sign(tr.qd)
    res = robokit.identify_dynamics(robot, tr.q, tr.qd, tr.qdd, tau)
    np.testing.assert_allclose(res.condition_number, tr.info["condition_number"], rtol=1e-6)
    np.testing.assert_allclose(res.predict(tr.q, tr.qd, tr.qdd), tau, atol=1e-7)


def test_bad_input(robots):
    robot = robots("rrr")
    with pytest.raises(InputError, match="duration"):
        robokit.excitation_trajectory(robot, -1.0)
    with pytest.raises(InputError, match="harmonics"):
        robokit.excitation_trajectory(robot, 1.0, harmonics=1)
    with pytest.raises(InputError, match="qd_max"):
        robokit.excitation_trajectory(robot, 1.0, qd_max=0.0)
    with pytest.raises(InputError, match="qlim"):
        robokit.excitation_trajectory(robot, 1.0, qlim=[[0, 1]] * 2)
