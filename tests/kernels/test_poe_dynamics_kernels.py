"""The compiled PoE and Newton–Euler kernels against Pinocchio (1e-9), and batched against per-call (1e-12)."""
import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import robokit as rk
from shared_robots import robot as shared_robot
from robokit.kernels import dynamics as kd
from robokit.kernels import poe as kp

MODELS = ["ur5", "panda", "puma560", "twolink"]


@pytest.fixture(scope="module")
def robots():
    return {name: shared_robot(name) for name in MODELS}


def _c(*arrays):
    # the kernels take writeable C-contiguous float64 arrays (their contract); robot.poe's are read-only
    return [np.array(a, dtype=float, order="C") for a in arrays]


def rel(a, b):
    return np.abs(np.asarray(a) - np.asarray(b)).max() / max(1.0, np.abs(b).max())


@pytest.mark.parametrize("name", MODELS)
def test_poe_kernels_vs_pinocchio(name, robots):
    r = robots[name]
    M, S, B = _c(r.poe.M, r.poe.Slist, r.poe.Blist)
    rng = np.random.default_rng(0)
    for _ in range(50):
        q = r.random_configuration(rng)
        T = r.frame_pose(q)
        assert np.abs(kp.fkin_space(M, S, q) - T).max() < 1e-9
        assert np.abs(kp.fkin_body(M, B, q) - T).max() < 1e-9
        assert np.abs(kp.jacobian_space(S, q) - r.jacobian(q, reference="world")).max() < 1e-9
        assert np.abs(kp.jacobian_body(B, q) - r.jacobian(q, reference="local")).max() < 1e-9


@pytest.mark.parametrize("name", MODELS)
def test_dynamics_kernels_vs_pinocchio(name, robots):
    r = robots[name]
    Ml, Gl, Sl = _c(r.poe.Mlist, r.poe.Glist, r.poe.Slist)
    g = r.gravity.copy()  # writeable, as the kernels take it
    rng = np.random.default_rng(1)
    for _ in range(50):
        q, dq, ddq = r.random_configuration(rng), rng.normal(size=r.n), rng.normal(size=r.n)
        F = rng.normal(size=6)
        Jb = r.jacobian(q, reference="local")
        tau = kd.inverse_dynamics(q, dq, ddq, g, F, Ml, Gl, Sl)
        assert rel(tau, r.rnea(q, dq, ddq) + Jb.T @ F) < 1e-9
        assert rel(kd.mass_matrix(q, Ml, Gl, Sl), r.crba(q)) < 1e-9
        tau_in = rng.normal(size=r.n) * 5
        dd = kd.forward_dynamics(q, dq, tau_in, g, F, Ml, Gl, Sl)
        dd_aba = r.aba(q, dq, tau_in - Jb.T @ F)
        assert np.abs(dd - dd_aba).max() <= 1e-9 * max(1.0, np.abs(dd_aba).max())


@pytest.mark.parametrize("name", MODELS)
def test_batched_kernels_equal_per_call(name, robots):
    r = robots[name]
    M, S, B, Ml, Gl, Sl = _c(r.poe.M, r.poe.Slist, r.poe.Blist, r.poe.Mlist, r.poe.Glist, r.poe.Slist)
    g = r.gravity.copy()  # writeable, as the kernels take it
    rng = np.random.default_rng(2)
    N = 300  # more rows than blocks, so blocks hold several rows
    Q = np.ascontiguousarray([r.random_configuration(rng) for _ in range(N)])
    D, A, Tau, F = (rng.normal(size=(N, k)) for k in (r.n, r.n, r.n, 6))
    out = {
        "fs": kp.fkin_space_batch(M, S, Q), "fb": kp.fkin_body_batch(M, B, Q),
        "js": kp.jacobian_space_batch(S, Q), "jb": kp.jacobian_body_batch(B, Q),
        "id": kd.inverse_dynamics_batch(Q, D, A, g, F, Ml, Gl, Sl),
        "id1": kd.inverse_dynamics_batch(Q, D, A, g, F[:1].copy(), Ml, Gl, Sl),
        "mm": kd.mass_matrix_batch(Q, Ml, Gl, Sl),
        "fd": kd.forward_dynamics_batch(Q, D, Tau, g, F, Ml, Gl, Sl),
    }
    for k in range(N):
        one = {
            "fs": kp.fkin_space(M, S, Q[k]), "fb": kp.fkin_body(M, B, Q[k]),
            "js": kp.jacobian_space(S, Q[k]), "jb": kp.jacobian_body(B, Q[k]),
            "id": kd.inverse_dynamics(Q[k], D[k], A[k], g, F[k], Ml, Gl, Sl),
            "id1": kd.inverse_dynamics(Q[k], D[k], A[k], g, F[0], Ml, Gl, Sl),
            "mm": kd.mass_matrix(Q[k], Ml, Gl, Sl),
            "fd": kd.forward_dynamics(Q[k], D[k], Tau[k], g, F[k], Ml, Gl, Sl),
        }
        for key, val in one.items():
            assert np.abs(out[key][k] - val).max() <= 1e-12 * max(1.0, np.abs(val).max()), key


def test_seed_functions_batched_and_trajectory(robots):
    r = robots["ur5"]
    p = r.poe
    rng = np.random.default_rng(3)
    Q, D, Tau = (rng.normal(size=(40, 6)) for _ in range(3))
    dd = rk.forward_dynamics(Q, D, Tau, r.gravity, np.zeros(6), p.Mlist, p.Glist, p.Slist)
    for k in range(0, 40, 7):
        assert np.abs(dd[k] - rk.forward_dynamics(Q[k], D[k], Tau[k], r.gravity, np.zeros(6),
                                                  p.Mlist, p.Glist, p.Slist)).max() < 1e-12 * max(1, np.abs(dd[k]).max())
    # the trajectory integrator against explicit Euler steps written here
    th, dth = Q[0].copy(), D[0].copy()
    thm, dthm = rk.forward_dynamics_trajectory(th, dth, Tau[:5], r.gravity, np.zeros((5, 6)),
                                               p.Mlist, p.Glist, p.Slist, 0.01, 3)
    for k in range(4):
        for _ in range(3):
            a = r.aba(th, dth, Tau[k])
            th, dth = th + 0.01 / 3 * dth, dth + 0.01 / 3 * a
        assert np.abs(thm[k + 1] - th).max() < 1e-9 and np.abs(dthm[k + 1] - dth).max() < 1e-8


def test_kernel_argument_errors(robots):
    p = robots["twolink"].poe
    M, S = _c(p.M, p.Slist)
    with pytest.raises(ValueError, match="thetalist"):
        kp.fkin_space(M, S, np.zeros(3))
    with pytest.raises(ValueError, match="NaN"):
        kp.jacobian_body(S, np.array([np.nan, 0.0]))
    import numba

    if not numba.config.DISABLE_JIT:  # one compiled signature: float64 only (plain Python accepts ints)
        with pytest.raises(TypeError):
            kp.fkin_space(M, S, np.zeros(2, dtype=np.int64))
    Ml, Gl, Sl = _c(p.Mlist, p.Glist, p.Slist)
    with pytest.raises(ValueError, match="dthetalist"):
        kd.inverse_dynamics(np.zeros(2), np.zeros(3), np.zeros(2), np.zeros(3), np.zeros(6), Ml, Gl, Sl)
    with pytest.raises(ValueError, match="Glist"):
        kd.mass_matrix(np.zeros(2), Ml, Gl[:1].copy(), Sl)
    with pytest.raises(ValueError, match="positive definite"):
        kd.forward_dynamics(np.zeros(2), np.zeros(2), np.zeros(2), np.zeros(3), np.zeros(6), Ml,
                            np.zeros_like(Gl), Sl)


@settings(max_examples=60, deadline=None)
@given(st.lists(st.floats(-5, 5), min_size=6, max_size=6), st.floats(-4, 4))
def test_exp_and_log_round_trip(v, th):
    """exp of a general screw (any ‖ω‖, prismatic) against the seed's matrix exponential, and log∘exp = id."""
    from robokit.kernels.lie import exp_screw, log_se3

    S = np.array(v, dtype=float).reshape(6, 1)
    T = np.empty((4, 4))
    exp_screw(S, 0, th, T)
    assert np.allclose(T, rk.matrix_exp_6(rk.vec_to_se3(S[:, 0] * th)), atol=1e-9)
    V = np.empty(6)
    log_se3(T, V)
    T2 = rk.matrix_exp_6(rk.vec_to_se3(V))
    assert np.allclose(T2, T, atol=1e-9)
    assert np.linalg.norm(V[:3]) <= np.pi + 1e-12


def test_log_near_pi():
    from robokit.kernels.lie import log_so3

    rng = np.random.default_rng(4)
    for eps in (0.0, 1e-9, 1e-6, 1e-3):
        for _ in range(20):
            w = rng.normal(size=3)
            w /= np.linalg.norm(w)
            R = rk.matrix_exp_3(rk.vec_to_so3(w * (np.pi - eps)))
            out = np.empty(3)
            log_so3(R, out)
            assert np.allclose(rk.matrix_exp_3(rk.vec_to_so3(out)), R, atol=1e-9)
