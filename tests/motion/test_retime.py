"""retime against independent checks: limits at every sample (torques by Pinocchio's rnea),
duration no longer than a uniformly scaled rest-to-rest time scaling of the same path, and
the closed-form trapezoid (bang-coast-bang) on a straight line."""
import numpy as np
import pinocchio as pin
import pytest

import robokit
from robokit.errors import InputError
from robokit.motion import path_spline, retime

pytest.importorskip("toppra")
REL = 1e-6  # TOPP-RA's LP tolerance at the grid points (module docstring of robokit.motion.retime)
P = np.array([[0, 0, 0, 0, 0, 0], [1, 0.5, -0.5, 0, 0.3, 0], [1.5, -0.2, 0.3, 1, 0, 0.5]], float)


@pytest.fixture(scope="module")
def puma():
    return robokit.load("puma560")


def _uniform_cubic_duration(spline, vmax, amax):
    """Shortest T for q(s(t)), s = 3τ² − 2τ³, τ = t/T, within the limits (closed form in T)."""
    tau = np.linspace(0, 1, 4001)
    s, s1, s2 = 3 * tau**2 - 2 * tau**3, 6 * tau - 6 * tau**2, 6 - 12 * tau
    q1, q2 = spline(s, 1), spline(s, 2)
    Tv = np.max(np.abs(q1 * s1[:, None]) / vmax)
    Ta = np.sqrt(np.max(np.abs(q2 * (s1**2)[:, None] + q1 * s2[:, None]) / amax))
    return max(Tv, Ta)


def test_velocity_acceleration_limits_and_duration(puma):
    vmax = np.array([1.0, 0.8, 1.2, 2.0, 2.0, 2.0])
    amax = np.array([2.0, 1.5, 3.0, 5.0, 5.0, 5.0])
    tr = retime(puma, P, vmax, amax)
    assert np.all(np.diff(tr.t) > 0)
    np.testing.assert_allclose(tr.q[[0, -1]], P[[0, -1]], atol=1e-12)
    np.testing.assert_allclose(tr.qd[[0, -1]], 0, atol=1e-12)
    assert np.all(np.abs(tr.qd) <= vmax * (1 + REL))
    assert np.all(np.abs(tr.qdd) <= amax * (1 + REL))
    # some limit is active (time-optimal: it cannot be uniformly slower than the limits)
    assert np.max(np.abs(tr.qd) / vmax) > 0.999 or np.max(np.abs(tr.qdd) / amax) > 0.999
    # q̇ is the time derivative of q (finite differences of the samples)
    fd = np.gradient(tr.q, tr.t, axis=0)
    assert np.max(np.abs(fd[5:-5] - tr.qd[5:-5])) < 0.05 * vmax.max()
    spline, _ = path_spline(P, 6)
    assert tr.t[-1] <= _uniform_cubic_duration(spline, vmax, amax)


def test_straight_line_is_the_trapezoid(puma):
    q0, q1 = np.zeros(6), np.array([1.2, 0, 0, 0, 0, 0])
    v, a = 1.0, 2.0
    tr = retime(puma, [q0, q1], v, a, grid=400)
    T_exact = 1.2 / v + v / a  # D ≥ v²/a: accelerate, coast, decelerate
    assert tr.t[-1] == pytest.approx(T_exact, rel=2 / 400)
    assert np.max(np.abs(tr.qd[:, 0])) == pytest.approx(v, rel=REL)  # it coasts at the limit


def test_torque_limits_checked_with_pinocchio(puma):
    vmax, amax = 2.0, 20.0
    free = retime(puma, P, vmax, amax)
    tau_free = np.array([pin.rnea(puma.model, puma.data, q, qd, qdd) for q, qd, qdd in zip(free.q, free.qd, free.qdd)])
    tau_max = np.maximum(0.8 * np.abs(tau_free).max(0), 1e-3)
    g_max = np.abs([pin.computeGeneralizedGravity(puma.model, puma.data, q) for q in free.q]).max(0)
    tau_max = np.maximum(tau_max, 1.05 * g_max)  # feasible: above the gravity torque on the path
    tr = retime(puma, P, vmax, amax, tau_max=tau_max)
    tau = np.array([pin.rnea(puma.model, puma.data, q, qd, qdd) for q, qd, qdd in zip(tr.q, tr.qd, tr.qdd)])
    assert np.all(np.abs(tau) <= tau_max * (1 + REL) + 1e-9)
    assert tr.t[-1] > free.t[-1]  # the torque limit binds
    assert np.max(np.abs(tau) / tau_max) > 0.99


def test_bad_input(puma):
    with pytest.raises(InputError, match="vmax"):
        retime(puma, P, -1.0, 1.0)
    with pytest.raises(InputError, match="amax"):
        retime(puma, P, 1.0, [1.0, 2.0])
    with pytest.raises(InputError, match="path"):
        retime(puma, np.zeros((1, 6)), 1.0, 1.0)
    with pytest.raises(InputError, match="path"):
        retime(puma, np.zeros((3, 6)), 1.0, 1.0)
    with pytest.raises(InputError, match="path"):
        retime(puma, P, 1.0, 1.0, tau_max=[1e-3] * 6)  # below gravity: infeasible


def test_a_trajectory_as_the_path(puma):
    from robokit.trajectory import cubic_trajectory
    tr0 = cubic_trajectory(P[0], P[1], tf=2.0, t=20)
    a = retime(puma, tr0, 1.0, 2.0)
    b = retime(puma, tr0.q, 1.0, 2.0)
    np.testing.assert_array_equal(a.t, b.t)
    assert np.all(np.abs(a.qd) <= 1.0 * (1 + REL))
