"""Controllers and simulation (Lecture 8): closed-loop claims checked against analytic solutions
and an independent integration (modern_robotics)."""
import numpy as np

from robokit.errors import DivergenceError
import pytest

import robokit as rk
from robokit.control import ComputedTorque, GravityPD, IndependentJoint, ModelFeedforward, simulate


@pytest.fixture(scope="module")
def twolink():
    return rk.load("twolink")


@pytest.fixture(scope="module")
def puma():
    return rk.load("puma560")


def hold(q_goal, T, dt):
    t = np.arange(0.0, T + 0.5 * dt, dt)
    q = np.tile(q_goal, (len(t), 1))
    return (t, q, np.zeros_like(q), np.zeros_like(q))


def test_computed_torque_error_follows_second_order_response(twolink):
    """Perfect model: ë + Kv ė + Kp e = 0; critical damping e(t) = e₀(1 + ωt)e^{−ωt}."""
    w = 8.0
    goal = np.array([0.4, -0.3])
    e0 = np.array([0.05, -0.02])
    dt = 1e-4
    traj = hold(goal, 1.0, dt)
    res = simulate(twolink, ComputedTorque(twolink, Kp=w * w, Kv=2 * w), traj, q0=goal - e0, dq0=np.zeros(2))
    t = res.t
    analytic = e0[None, :] * ((1 + w * t) * np.exp(-w * t))[:, None]
    # the torque is held over each 0.1 ms period: the deviation is O(dt) of the response
    assert np.abs(res.error - analytic).max() < 2e-3 * np.abs(e0).max()


def test_computed_torque_six_joints_converges(puma):
    start = np.array([0.0, -0.5, 0.5, 0.0, 0.3, 0.0])
    goal = np.array([0.6, -0.2, 0.9, 0.4, -0.3, 0.5])
    tr = rk.trajectory.quintic_trajectory(start, goal, 1.0, t=np.arange(0, 1.0 + 1e-9, 1e-3))
    t_end = np.arange(tr.t[-1] + 1e-3, 2.5, 1e-3)
    t = np.r_[tr.t, t_end]
    q = np.vstack([tr.q, np.tile(goal, (len(t_end), 1))])
    dq = np.vstack([tr.qd, np.zeros((len(t_end), 6))])
    ddq = np.vstack([tr.qdd, np.zeros((len(t_end), 6))])
    res = simulate(puma, ComputedTorque(puma, Kp=400.0), (t, q, dq, ddq), q0=start + 0.02, dq0=np.zeros(6))
    assert np.abs(res.error[-1]).max() < 1e-6
    assert np.abs(res.error).max() < 0.05


def test_pi_removes_gravity_steady_state_error_that_p_leaves(twolink):
    """Lecture 8: independent joint control without gravity feedforward. A P velocity loop leaves a
    steady-state position error under gravity; PI drives it to zero."""
    goal = np.array([0.3, 0.5])
    traj = hold(goal, 6.0, 1e-3)
    J_nom = np.array([5.0, 1.0])
    p_only = IndependentJoint(2, Kp=5.0, Kv=30.0, J_nom=J_nom, Ki=0.0)
    pi = IndependentJoint(2, Kp=5.0, Kv=30.0, J_nom=J_nom, Ki=60.0)
    e_p = simulate(twolink, p_only, traj).error[-1]
    e_pi = simulate(twolink, pi, traj).error[-1]
    # P: the steady-state error balances gravity: J_nom Kv Kp e = g(q)
    g = twolink.gravity_torques(goal - e_p)
    assert np.allclose(J_nom * 30.0 * 5.0 * e_p, g, rtol=1e-3, atol=1e-6)
    assert np.abs(e_p).max() > 1e-2
    assert np.abs(e_pi).max() < 1e-4
    # with gravity feedforward the P loop is fine too
    ff = IndependentJoint(2, Kp=5.0, Kv=30.0, J_nom=J_nom, gravity=twolink)
    assert np.abs(simulate(twolink, ff, traj).error[-1]).max() < 1e-4


def test_gravity_pd_and_feedforward_track(puma):
    goal = np.array([0.2, -0.4, 0.6, 0.1, 0.2, 0.0])
    traj = hold(goal, 4.0, 1e-3)
    # gains scaled to each joint's inertia (the wrist's is ~1e-4 kg·m²): stable at a 1 ms period
    res = simulate(puma, GravityPD(puma, Kp=[200, 300, 150, 1, 1, 0.2], Kv=[40, 60, 30, 0.1, 0.1, 0.01]), traj,
                   q0=goal + 0.05, dq0=np.zeros(6), substeps=2)
    assert np.abs(res.error[-1]).max() < 1e-4  # PD + exact gravity: zero steady-state error
    mf = ModelFeedforward(puma, Kp=100.0, Kv=20.0)
    tau = mf(0.0, goal, np.zeros(6), goal, np.zeros(6), np.zeros(6))
    assert np.allclose(tau, puma.gravity_torques(goal))


def test_simulate_control_matches_modern_robotics(twolink):
    mr = pytest.importorskip("modern_robotics")
    import matplotlib

    matplotlib.use("Agg")
    p = twolink.poe
    N, dt = 60, 0.01
    t = np.arange(N) * dt
    qd = np.c_[0.3 * np.sin(2 * t), 0.2 * np.cos(3 * t)]
    dqd = np.c_[0.6 * np.cos(2 * t), -0.6 * np.sin(3 * t)]
    ddqd = np.c_[-1.2 * np.sin(2 * t), -1.8 * np.cos(3 * t)]
    Ftip = np.zeros((N, 6))
    Mt = np.array(p.Mlist)
    Gt = np.array(p.Glist) * 1.2  # the controller's model is 20 % off
    args = ([0.1, 0.1], [0.0, 0.0], twolink.gravity, Ftip, p.Mlist, p.Glist, p.Slist, qd, dqd, ddqd,
            twolink.gravity * 0.9, Mt, Gt, 20.0, 10.0, 18.0, dt, 4)
    tau, th = rk.simulate_control(*args)
    import matplotlib.pyplot as plt

    tau_mr, th_mr = mr.SimulateControl(args[0], args[1], args[2], Ftip, list(p.Mlist), list(p.Glist), p.Slist,
                                       qd, dqd, ddqd, args[10], list(Mt), list(Gt), 20.0, 10.0, 18.0, dt, 4)
    plt.close("all")
    assert np.abs(th - th_mr).max() < 1e-6 and np.abs(tau - tau_mr).max() < 1e-6
    # computed_torque is the law inside: check one step by hand
    tau0 = rk.computed_torque([0.1, 0.1], [0, 0], [0, 0], twolink.gravity * 0.9, Mt, Gt, p.Slist, qd[0], dqd[0], ddqd[0],
                              20.0, 10.0, 18.0)
    assert np.allclose(tau0, tau[0])


def test_friction_and_motor_inertia_change_the_plant(puma):
    goal = np.zeros(6)
    traj = hold(goal, 0.2, 1e-3)
    zero = lambda *a: np.zeros(6)  # noqa: E731
    heavy = simulate(puma, zero, traj, q0=goal, dq0=np.full(6, 0.5), motor_inertia=True)
    fric = simulate(puma, zero, traj, q0=goal, dq0=np.full(6, 0.5), motor_inertia=True, friction=True)
    # the reflected motor inertia G²Jm dominates the wrist: it barely slows down without friction …
    assert np.all(np.abs(heavy.dq[-1, 3:] - 0.5) < 0.05)
    # … and with friction (G²B q̇ + |G|Tc) it decelerates; over 0.2 s the drop is about (friction/inertia)·t
    for j in (3, 4, 5):
        link = puma.dh.links[j]
        decel = rk.dynamics.friction_torques(puma.dh, np.full(6, 0.5))[j] / (link.joint_inertia + puma.crba(goal)[j, j])
        if decel * 0.2 > 0.6:  # enough friction to stop it within 0.2 s: at rest (up to Coulomb chatter)
            assert abs(fric.dq[-1, j]) < 0.02
        else:
            assert 0.5 * decel * 0.2 < 0.5 - fric.dq[-1, j] < 1.5 * decel * 0.2
    # without the motors' inertia the wrist's viscous friction (G²B ≈ 0.2 N·m·s/rad on ~1e-4 kg·m²)
    # is too stiff for RK4 at 1 ms: the simulator says so instead of returning NaN
    with pytest.raises(DivergenceError, match="diverged") as info:
        simulate(puma, zero, traj, q0=goal, dq0=np.full(6, 0.5), friction=True)
    part = info.value.partial  # the simulation up to the last finite step is kept
    assert 0 < len(part.t) < len(traj[0]) and np.isfinite(part.q).all() and np.isfinite(part.dq).all()
    assert np.allclose(part.q[0], goal)


def test_bad_input(twolink):
    with pytest.raises(ValueError, match="Kp"):
        ComputedTorque(twolink, Kp=[1, 2, 3])
    with pytest.raises(ValueError, match="trajectory.t"):
        simulate(twolink, GravityPD(twolink, 1, 1), (np.array([0, 0.1, 0.15]), np.zeros((3, 2)), None, None))
    with pytest.raises(ValueError, match="method"):
        simulate(twolink, GravityPD(twolink, 1, 1), hold(np.zeros(2), 0.1, 0.01), method="rk45")


def test_plot_tracking(twolink):
    from robokit.control import plot_tracking

    traj = hold(np.array([0.2, 0.1]), 0.2, 0.01)
    res = simulate(twolink, GravityPD(twolink, 50.0, 10.0), traj, q0=np.zeros(2))
    fig = plot_tracking(res, title="PD")
    assert len(fig.axes) == 3
    assert len(fig.axes[0].lines) == 4 and len(fig.axes[2].lines) == 2  # desired + actual per joint; torques
    assert np.allclose(fig.axes[1].lines[0].get_ydata(), res.error[:, 0])


def test_sim_result_plots_and_legend_sits_beside_the_curves(twolink):
    from robokit.trajectory import plot_trajectory

    traj = hold(np.array([0.2, 0.1]), 0.2, 0.01)
    res = simulate(twolink, GravityPD(twolink, 50.0, 10.0), traj, q0=np.zeros(2))
    fig = res.plot(title="PD")
    ax = fig.axes[0]
    actual, desired = ax.lines[0], ax.lines[1]
    assert np.allclose(actual.get_ydata(), res.q[:, 0]) and np.allclose(desired.get_ydata(), res.q_des[:, 0])
    assert desired.get_zorder() > actual.get_zorder()  # the desired line is drawn on top
    fig.canvas.draw()
    legend_box = ax.get_legend().get_window_extent()
    assert legend_box.x0 >= ax.get_window_extent().x1 - 1  # outside the panel: covers no curve
    f2 = plot_trajectory(res)
    assert np.allclose(f2.axes[0].lines[0].get_ydata(), res.q[:, 0])
    assert np.allclose(f2.axes[1].lines[1].get_ydata(), res.dq[:, 1])
    with pytest.raises(ValueError, match="traj"):
        plot_trajectory(object())
