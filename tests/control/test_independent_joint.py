"""Independent joint control of the PUMA 560 through the motor model: the lecture's steady-state
error of P loops under the gravity disturbance, zero error with PI, and the recorded disturbance."""
import numpy as np
import pytest

import robokit
from robokit.control.independent import simulate_independent_joints
from robokit.dynamics.drives import drive_parameters


@pytest.fixture(scope="module")
def puma():
    return robokit.load("puma560")


def _hold(q, T=1.5, dt=1e-3):
    t = np.arange(0, T + dt / 2, dt)
    Q = np.tile(q, (len(t), 1))
    return (t, Q, np.zeros_like(Q), np.zeros_like(Q))


Q_HOLD = np.array([0.0, 0.6, -0.4, 0.0, 0.3, 0.0])
KM, KA = 0.228, 1.0


def _gains(puma, bw=100.0):
    """Velocity-loop gain for a motor-side bandwidth bw: Kv = bw J / (Km Ka)."""
    Jm, G, B, Tc = drive_parameters(puma)
    J = Jm + np.diag(puma.crba(Q_HOLD)) / G**2
    return bw * J / (KM * KA)


def test_p_loops_leave_the_lecture_steady_state_error(puma):
    Kv, Kp = _gains(puma), 10.0
    run = simulate_independent_joints(puma, _hold(Q_HOLD), Kp=Kp, Kv=Kv, Km=KM, Ka=KA, coulomb=False)
    _, G, B, _ = drive_parameters(puma)
    q_end = run.q[-1]
    g = puma.gravity_torques(q_end)
    # at rest: G Km Ka Kv G Kp e = g(q)  ⇒  e = g / (G² Km Ka Kv Kp)
    e_expected = g / (G**2 * KM * KA * Kv * Kp)
    np.testing.assert_allclose(run.error[-1], e_expected, atol=2e-6)
    assert abs(run.error[-1, 1]) > 1e-3  # the shoulder visibly sags under gravity
    # the disturbance each motor sees at rest is the gravity torque referred through its gearbox
    np.testing.assert_allclose(run.disturbance[-1], g / G, atol=1e-5)


def test_pi_loops_remove_the_steady_state_error(puma):
    Kv = _gains(puma)
    run = simulate_independent_joints(puma, _hold(Q_HOLD, T=3.0), Kp=10.0, Kv=Kv, Ki=5.0 * Kv, Km=KM, Ka=KA,
                                      coulomb=False)
    assert np.abs(run.error[-1]).max() < 1e-4
    p = simulate_independent_joints(puma, _hold(Q_HOLD, T=3.0), Kp=10.0, Kv=Kv, Km=KM, Ka=KA, coulomb=False)
    assert np.abs(p.error[-1]).max() > 20 * np.abs(run.error[-1]).max()


def test_gravity_feedforward_and_moving_joint_disturbs_the_others(puma):
    Kv = _gains(puma)
    run = simulate_independent_joints(puma, _hold(Q_HOLD, T=1.0), Kp=10.0, Kv=Kv, Km=KM, Ka=KA, gravity_ff=True,
                                      coulomb=False)
    assert np.abs(run.error[-1]).max() < 1e-6  # gravity fed forward exactly: nothing left to reject
    # a fast move of joint 1 alone: the other motors see coupling torques (nonzero disturbance)
    t = np.arange(0, 0.6, 1e-3)
    s = np.clip(t / 0.5, 0, 1)
    q = np.tile(Q_HOLD, (len(t), 1))
    q[:, 0] += 1.0 * (10 * s**3 - 15 * s**4 + 6 * s**5)
    qd = np.gradient(q, t, axis=0)
    qdd = np.gradient(qd, t, axis=0)
    run = simulate_independent_joints(puma, (t, q, qd, qdd), Kp=10.0, Kv=Kv, Km=KM, Ka=KA, gravity_ff=True)
    grav = np.array([puma.gravity_torques(qq) for qq in run.q]) / drive_parameters(puma)[1]
    coupling = run.disturbance - grav
    assert np.abs(coupling[:, 1]).max() > 1e-4  # shoulder motor feels the waist's motion
    # and the effective inertia of the waist motor changes with the pose along the way
    assert run.effective_inertia[:, 0].max() > run.effective_inertia[:, 0].min()


def test_bad_arguments(puma):
    with pytest.raises(ValueError, match="Kp"):
        simulate_independent_joints(puma, _hold(Q_HOLD, T=0.01), Kp=-1.0, Kv=0.1)
    with pytest.raises(ValueError, match="DH table"):
        ur5 = robokit.load("ur5")
        simulate_independent_joints(ur5, _hold(np.zeros(6), T=0.01), Kp=1.0, Kv=0.1)


def test_too_high_gains_for_the_period_raise_divergence_with_the_partial_run(puma):
    from robokit.errors import DivergenceError

    t = np.arange(0, 0.3 + 1e-9, 0.005)  # a 5 ms control period: Kv = 0.2 is far beyond its stability bound
    hold = (t, np.tile(Q_HOLD, (len(t), 1)), np.zeros((len(t), 6)), np.zeros((len(t), 6)))
    with pytest.raises(DivergenceError, match="diverged") as info:
        simulate_independent_joints(puma, hold, Kp=10, Kv=0.2)
    part = info.value.partial
    assert 0 < len(part.t) < len(t) and np.all(np.isfinite(part.q))
    # the docstring's example gains at the same period stay bounded
    run = simulate_independent_joints(puma, hold, Kp=10, Kv=0.05)
    assert np.all(np.isfinite(run.q)) and np.abs(run.q - Q_HOLD).max() < 0.2
