"""Motor model vs its first-order analytic response, gear reflection vs the lecture's relations,
gain design vs characteristic polynomials, step measures vs closed forms of 1st/2nd-order systems."""
import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from robokit.control.design import critical_gains, pid_gains_bandwidth, plot_step_response, step_info
from robokit.control.motor import DCMotor, effective_inertia, joint_from_motor


def test_motor_simulation_matches_first_order_analytic_response():
    m = DCMotor(Ka=0.9, Km=0.228, J=3.3e-4, B=8.2e-4)
    t = np.linspace(0, 5 * m.time_constant, 200)
    np.testing.assert_allclose(m.simulate(t, 2.0), m.step_response(t, 2.0), rtol=1e-7, atol=1e-9)
    assert m.step_response([1e6], 2.0)[0] == pytest.approx(2.0 * m.dc_gain)
    num, den = m.transfer_function()
    # H(s) = num/den: the DC gain and the pole −B/J
    assert num[0] / den[1] == pytest.approx(m.dc_gain)
    assert np.roots(den)[0] == pytest.approx(-m.B / m.J)
    assert m.torque(2.0) == pytest.approx(0.228 * 0.9 * 2.0)
    assert m.current(2.0) == pytest.approx(1.8)


def test_motor_with_disturbance_and_coulomb_settles_where_torques_balance():
    m = DCMotor(Ka=1.0, Km=0.2, J=1e-3, B=1e-3, Tc=(0.02, -0.02))
    t = np.linspace(0, 20.0, 800)  # 20 time constants: e^{-20} below the tolerance
    w = m.simulate(t, 1.0, tau_d=0.05)
    # K u = B ω + Tc + τ_d  ⇒  ω = (0.2 − 0.02 − 0.05) / 1e-3
    assert w[-1] == pytest.approx(130.0, rel=1e-6)


def test_gear_reflection_lecture_relations():
    J, B, tau = joint_from_motor(-62.6, 2e-4, 1.48e-3, 0.4)
    assert J == pytest.approx(62.6**2 * 2e-4)
    assert B == pytest.approx(62.6**2 * 1.48e-3)
    assert tau == pytest.approx(-62.6 * 0.4)
    assert effective_inertia(2e-4, 2.0, 100.0) == pytest.approx(2e-4 + 2.0 / 1e4)
    with pytest.raises(ValueError, match="G"):
        effective_inertia(1.0, 1.0, 0.0)


@settings(max_examples=30, deadline=None)
@given(st.floats(0.01, 10), st.floats(0.5, 200))
def test_critical_gains_double_pole(J, wn):
    Kp, Kv = critical_gains(J, omega_n=wn)
    # J s² + Kv s + Kp has the discriminant 0 (critical damping) and the double root −ω_n
    assert Kv**2 - 4 * J * Kp == pytest.approx(0.0, abs=1e-9 * Kv**2)
    assert -Kv / (2 * J) == pytest.approx(-wn)
    Kp2, Kv2 = critical_gains(J, Kp=Kp)
    assert Kv2 == pytest.approx(Kv)


def test_lecture_unit_inertia_rule_and_pid_poles():
    assert critical_gains(1.0, Kp=100.0) == (100.0, 20.0)
    J, wb = 0.7, 12.0
    Kp, Ki, Kd = pid_gains_bandwidth(J, wb)
    np.testing.assert_allclose([J, Kd, Kp, Ki], J * np.poly([-wb, -wb, -wb]))
    with pytest.raises(ValueError, match="omega_n, Kp"):
        critical_gains(1.0)


@settings(max_examples=20, deadline=None)
@given(st.floats(0.1, 0.8), st.floats(1.0, 20.0))
def test_step_info_second_order_closed_forms(zeta, wn):
    t = np.linspace(0, 12 / (zeta * wn), 40001)
    wd = wn * np.sqrt(1 - zeta**2)
    y = 1 - np.exp(-zeta * wn * t) * (np.cos(wd * t) + zeta / np.sqrt(1 - zeta**2) * np.sin(wd * t))
    info = step_info(t, y, target=1.0)
    assert info.overshoot == pytest.approx(100 * np.exp(-np.pi * zeta / np.sqrt(1 - zeta**2)), rel=1e-3)
    assert info.peak_time == pytest.approx(np.pi / wd, rel=1e-3)
    assert abs(info.steady_state_error) < 1e-4


def test_step_info_first_order_closed_forms_and_plot():
    tau = 0.3
    t = np.linspace(0, 20 * tau, 60001)  # long enough that y[-1] is the final value to 1e-8
    y = 2.0 * (1 - np.exp(-t / tau))
    info = step_info(t, y, target=2.5)
    assert info.rise_time == pytest.approx(tau * np.log(9), rel=1e-4)
    assert info.settling_time == pytest.approx(tau * np.log(50), rel=1e-4)
    assert info.overshoot == 0.0
    assert info.steady_state_error == pytest.approx(0.5, abs=1e-4)
    ax = plot_step_response(t, y, target=2.5)
    xs, ys = ax.lines[0].get_data()
    np.testing.assert_array_equal(ys, y)
    assert ax.lines[1].get_ydata()[0] == pytest.approx(2.5)  # the target line
    with pytest.raises(ValueError, match="y"):
        step_info(t, np.zeros_like(t))
