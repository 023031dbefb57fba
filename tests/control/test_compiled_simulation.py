"""The compiled closed loops (robokit.kernels.simulation) against the Python loops they replace:
``simulate`` with every built-in controller (plant over Pinocchio in Python, PoE articulated-body
recursion compiled: 1e-9) and the seed's ``simulate_control`` (same operations: 1e-12); divergence
raises the same DivergenceError with the same partial result."""
import numpy as np
import pytest

import robokit as rk
from robokit.control import ComputedTorque, GravityPD, IndependentJoint, ModelFeedforward, simulate
from robokit.control.seed import simulate_control
from robokit.errors import DivergenceError


@pytest.fixture(scope="module")
def puma():
    return rk.load("puma560")


def _trajectory(n, K=120, dt=0.005):
    t = np.arange(K) * dt
    w = np.linspace(0.5, 1.5, n)
    q = 0.3 * np.sin(np.outer(t, w))
    dq = 0.3 * np.cos(np.outer(t, w)) * w
    ddq = -0.3 * np.sin(np.outer(t, w)) * w**2
    return t, q, dq, ddq


def _controllers(r):
    return {
        "gravity_pd": GravityPD(r, Kp=200.0, Kv=20.0),
        "feedforward": ModelFeedforward(r, Kp=200.0, Kv=20.0),
        "computed_torque": ComputedTorque(r, Kp=400.0, Ki=50.0),
        "independent": IndependentJoint(r.n, Kp=20.0, Kv=40.0, Ki=5.0, J_nom=np.full(r.n, 0.5), gravity=r),
    }


@pytest.mark.parametrize("which", ["gravity_pd", "feedforward", "computed_torque", "independent"])
@pytest.mark.parametrize("method", ["rk4", "euler"])
def test_compiled_simulate_equals_python_loop(puma, which, method):
    traj = _trajectory(puma.n)
    ctrl = _controllers(puma)[which]
    rng = np.random.default_rng(0)
    F = rng.normal(size=(len(traj[0]), 6))
    q0 = traj[1][0] + 0.02
    kw = dict(q0=q0, substeps=2, method=method, friction=True, motor_inertia=True, Ftip=F)
    a = simulate(puma, ctrl, traj, compiled=True, **kw)
    b = simulate(puma, ctrl, traj, compiled=False, **kw)
    for x, y in ((a.q, b.q), (a.dq, b.dq), (a.tau, b.tau)):
        assert np.abs(x - y).max() <= 1e-9 * max(1.0, np.abs(y).max())


def test_compiled_simulate_diverges_like_python(puma):
    traj = _trajectory(puma.n, K=400, dt=0.02)
    ctrl = GravityPD(puma, Kp=1e6, Kv=1e5)  # far too stiff for 20 ms Euler steps
    errors = []
    for compiled in (True, False):
        with pytest.raises(DivergenceError) as info:
            simulate(puma, ctrl, traj, method="euler", compiled=compiled)
        errors.append(info.value)
    a, b = errors[0].partial, errors[1].partial
    assert a.q.shape == b.q.shape and np.abs(a.q - b.q).max() <= 1e-9 * max(1.0, np.abs(b.q).max())
    assert str(errors[0]) == str(errors[1])


def test_python_controller_still_runs_in_the_python_loop(puma):
    traj = _trajectory(puma.n, K=30)
    pd = GravityPD(puma, Kp=200.0, Kv=20.0)
    calls = []

    def law(t, q, dq, q_des, dq_des, ddq_des):
        calls.append(t)
        return pd(t, q, dq, q_des, dq_des, ddq_des)

    a = simulate(puma, law, traj, motor_inertia=True)
    b = simulate(puma, pd, traj, motor_inertia=True)  # the compiled loop
    assert len(calls) == 30
    assert np.abs(a.q - b.q).max() <= 1e-9


def test_compiled_simulate_control_equals_python_loop(puma):
    p = puma.poe
    t, qd, dqd, ddqd = _trajectory(puma.n, K=80, dt=0.01)
    F = np.random.default_rng(1).normal(size=(len(t), 6))
    args = (qd[0] + 0.05, dqd[0], puma.gravity, F, p.Mlist, p.Glist, p.Slist, qd, dqd, ddqd, puma.gravity * 0.95,
            p.Mlist, p.Glist * 1.1, 20.0, 10.0, 18.0, 0.01, 4)
    a = simulate_control(*args)
    b = simulate_control(*args, compiled=False)
    assert np.abs(a[0] - b[0]).max() <= 1e-12 * max(1.0, np.abs(b[0]).max())
    assert np.abs(a[1] - b[1]).max() <= 1e-12


def test_compiled_simulate_control_diverges_like_python(puma):
    p = puma.poe
    t, qd, dqd, ddqd = _trajectory(puma.n, K=200, dt=0.05)
    args = (qd[0] + 0.5, dqd[0], puma.gravity, np.zeros((len(t), 6)), p.Mlist, p.Glist, p.Slist, qd, dqd, ddqd,
            puma.gravity, p.Mlist, p.Glist, 1e7, 0.0, 1e5, 0.05, 1)
    parts = []
    for compiled in (True, False):
        with pytest.raises(DivergenceError) as info:
            simulate_control(*args, compiled=compiled)
        parts.append(info.value.partial)
    assert parts[0][0].shape == parts[1][0].shape
    assert np.abs(parts[0][1] - parts[1][1]).max() <= 1e-12
