"""Numerics through the Python API: non-finite input refused by name, divergence reported with the
finite part, singular and unreachable cases answered sensibly."""
import math

import numpy as np
import pytest
from hardening_support import PEND_G, PEND_LC, PEND_M, PENDULUM_YAML

import robokit
from robokit.errors import DivergenceError


@pytest.fixture(scope="module")
def pendulum(tmp_path_factory):
    p = tmp_path_factory.mktemp("pend") / "pendulum.yaml"
    p.write_text(PENDULUM_YAML)
    return robokit.load(p)


@pytest.fixture(scope="module")
def puma():
    return robokit.load("puma560")


BAD = [np.nan, np.inf, -np.inf]


@pytest.mark.parametrize("bad", BAD)
@pytest.mark.parametrize("call,arg", [
    ("frame_pose", "q"), ("jacobian", "q"), ("crba", "q"),
    ("rnea", "q"), ("rnea", "dq"), ("rnea", "ddq"),
    ("aba", "q"), ("aba", "dq"), ("aba", "tau"),
])
def test_robot_methods_refuse_non_finite_input_by_argument_name(call, arg, bad, puma):
    n = puma.n
    args = {"q": np.zeros(n), "dq": np.zeros(n), "ddq": np.zeros(n), "tau": np.zeros(n)}
    args[arg] = args[arg].copy()
    args[arg][2] = bad
    order = {"frame_pose": ["q"], "jacobian": ["q"], "crba": ["q"],
             "rnea": ["q", "dq", "ddq"], "aba": ["q", "dq", "tau"]}[call]
    with pytest.raises(ValueError, match=rf"^{arg}: .*(NaN|infinite)"):
        getattr(puma, call)(*[args[k] for k in order])


def _pendulum_mr(pendulum):
    poe = pendulum.poe
    return poe.Mlist, poe.Glist, poe.Slist


def _desired(N, dt):
    t = np.arange(N) * dt
    return np.c_[0.3 * np.sin(t)], np.c_[0.3 * np.cos(t)], np.c_[-0.3 * np.sin(t)]


@pytest.mark.parametrize("gain", ["Kp", "Ki", "Kd"])
def test_simulate_control_refuses_negative_gains_by_name(gain, pendulum):
    Mlist, Glist, Slist = _pendulum_mr(pendulum)
    N, dt = 20, 0.01
    qd, dqd, ddqd = _desired(N, dt)
    g = np.array([0, 0, -PEND_G])
    K = {"Kp": 20.0, "Ki": 1.0, "Kd": 5.0}
    K[gain] = -1.0
    with pytest.raises(ValueError, match=rf"^{gain}: .*non-negative"):
        robokit.simulate_control([0.0], [0.0], g, np.zeros((N, 6)), Mlist, Glist, Slist, qd, dqd, ddqd,
                                 g, Mlist, Glist, K["Kp"], K["Ki"], K["Kd"], dt, 1)


def test_simulate_control_unstable_gains_raise_divergence_with_finite_partial(pendulum):
    Mlist, Glist, Slist = _pendulum_mr(pendulum)
    N, dt = 200, 0.01
    qd, dqd, ddqd = _desired(N, dt)
    g = np.array([0, 0, -PEND_G])
    args = lambda k: ([0.5], [0.0], g, np.zeros((k, 6)), Mlist, Glist, Slist, qd[:k], dqd[:k], ddqd[:k],
                      g, Mlist, Glist, 1e6, 0.0, 10.0, dt, 1)
    # Kp = 1e6 1/s² with one Euler step of 10 ms per period: hω ≈ 10, far past the stability limit
    with pytest.raises(DivergenceError) as ei:
        robokit.simulate_control(*args(N))
    taumat, thetamat = ei.value.partial
    k = len(thetamat)
    assert 0 < k < N and taumat.shape == (k, 1)
    assert np.isfinite(taumat).all() and np.isfinite(thetamat).all()
    # the partial result is exactly the run of the first k periods (which does not diverge)
    tau_k, theta_k = robokit.simulate_control(*args(k))
    np.testing.assert_array_equal(thetamat, theta_k)
    np.testing.assert_array_equal(taumat, tau_k)


def test_control_simulate_divergence_raises_with_finite_partial(pendulum):
    from robokit.control import ComputedTorque, simulate

    dt, N = 0.01, 300
    t = np.arange(N) * dt
    qd, dqd, ddqd = _desired(N, dt)
    ctrl = ComputedTorque(pendulum, Kp=1e7, Kv=1e4)  # RK4 at h = 10 ms: hω ≈ 30, unstable
    with pytest.raises(DivergenceError) as ei:
        simulate(pendulum, ctrl, (t, qd, dqd, ddqd), q0=[0.4])
    part = ei.value.partial
    k = len(part.t)
    assert 0 < k < N
    assert np.isfinite(part.q).all() and np.isfinite(part.dq).all() and np.isfinite(part.tau).all()
    again = simulate(pendulum, ComputedTorque(pendulum, Kp=1e7, Kv=1e4), (t[:k], qd[:k], dqd[:k], ddqd[:k]), q0=[0.4])
    np.testing.assert_array_equal(part.q, again.q)
    np.testing.assert_array_equal(part.tau, again.tau)


def test_control_simulate_stable_gains_hold_the_pendulum(pendulum):
    # the stable counterpart (so the divergence above is the gains, not the set-up): holding
    # θ = 0.3 needs the gravity torque m g l_c cos θ
    from robokit.control import ComputedTorque, simulate

    dt, N = 0.01, 300
    t = np.arange(N) * dt
    qd = np.full((N, 1), 0.3)
    res = simulate(pendulum, ComputedTorque(pendulum, Kp=100.0), (t, qd, np.zeros((N, 1)), np.zeros((N, 1))), q0=[0.0])
    assert abs(res.q[-1, 0] - 0.3) < 1e-3
    np.testing.assert_allclose(res.tau[-1, 0], PEND_M * PEND_G * PEND_LC * math.cos(res.q[-1, 0]), rtol=1e-2)


@pytest.mark.parametrize("J,V,expected", [
    # rank-one rows: J⁺ = Jᵀ / ‖J‖²
    ([[1.0, 1.0], [0.0, 0.0]], [2.0, 3.0], [1.0, 1.0]),
    # planar 2R (l₁ = l₂ = 1) stretched along x: J = [[0, 0], [2, 1]]
    ([[0.0, 0.0], [2.0, 1.0]], [1.0, 1.0], [0.4, 0.2]),
    # a zero Jacobian: the pseudo-inverse is zero
    ([[0.0, 0.0], [0.0, 0.0]], [1.0, -1.0], [0.0, 0.0]),
])
def test_resolved_rate_dls_with_zero_damping_at_a_singularity_is_the_pseudo_inverse(J, V, expected):
    dq = robokit.kinematics.resolved_rate(np.array(J), np.array(V), method="dls", damping=0.0)
    np.testing.assert_allclose(dq, expected, atol=1e-12)


def _planar_2r():
    S = np.array([[0, 0, 1, 0, 0, 0], [0, 0, 1, 0, -1, 0]], float).T  # z axes at x = 0 and x = 1
    M = np.eye(4)
    M[0, 3] = 2.0
    B = robokit.adjoint(robokit.trans_inv(M)) @ S
    return S, B, M


@pytest.mark.parametrize("target,theta0", [
    ((5.0, 0.0, 0.0), [0.0, 0.0]),          # beyond reach, straight ahead
    ((-5.0, 0.0, 0.0), [math.pi, 0.0]),     # beyond reach behind, starting at θ₁ = π
    ((0.0, 5.0, 0.0), [0.1, 0.2]),
    ((1.0, 1.0, 1.0), [0.3, -0.4]),         # out of the arm's plane
    ((-5.0, 0.0, 0.0), [40.0, -25.0]),      # a wound-up initial guess
])
@pytest.mark.parametrize("solver", ["ikin_body", "ikin_space"])
def test_ik_on_unreachable_target_fails_with_finite_wrapped_angles(solver, target, theta0):
    S, B, M = _planar_2r()
    T = np.eye(4)
    T[:3, 3] = target
    screws = B if solver == "ikin_body" else S
    theta, ok = getattr(robokit, solver)(screws, M, T, theta0, 1e-6, 1e-6)
    assert not ok
    theta = np.asarray(theta)
    assert theta.shape == (2,) and np.isfinite(theta).all()
    assert np.all(theta > -math.pi) and np.all(theta <= math.pi), theta
    # what it returns is a real configuration: its reach is within the arm's 2 m
    p = robokit.fkin_space(M, S, theta)[:3, 3]
    assert np.linalg.norm(p) <= 2.0 + 1e-12


@pytest.mark.parametrize("cut, named", [("Slist", "Slist: expected 6 columns"), ("Mlist", "Mlist: expected shape (7, 4, 4)"),
                                        ("Glist", "Glist: expected shape (6, 6, 6)")])
def test_a_model_list_one_joint_short_is_named_itself(cut, named, puma):
    """Mlist, Glist and Slist must agree on n: the one that disagrees with the other two is named (a
    Slist missing a column was reported as a wrong Mlist)."""
    from robokit.dynamics.coriolis import coriolis_matrix

    model = {"Mlist": puma.poe.Mlist, "Glist": puma.poe.Glist, "Slist": puma.poe.Slist}
    model[cut] = model[cut][:, :5] if cut == "Slist" else model[cut][:-1]
    with pytest.raises(robokit.InputError, match=named.replace("(", r"\(").replace(")", r"\)")):
        coriolis_matrix(np.zeros(6), np.full(6, 0.5), model["Mlist"], model["Glist"], model["Slist"])
