"""Seed dynamics (PoE Newton–Euler, CRBA, forward dynamics) against Pinocchio and modern_robotics."""
import numpy as np
import pytest

import robokit as rk
from shared_robots import robot as shared_robot

MODELS = ["twolink", "rrr", "puma560", "ur5", "panda", "z1", "xarm7", "kinova"]


@pytest.fixture(scope="module")
def loaded():
    return {name: shared_robot(name) for name in MODELS}


def rel(a, b):
    return np.abs(np.asarray(a) - np.asarray(b)).max() / max(1.0, np.abs(b).max())


@pytest.mark.parametrize("name", MODELS)
def test_against_pinocchio(name, loaded):
    r = loaded[name]
    p = r.poe
    args = (p.Mlist, p.Glist, p.Slist)
    rng = np.random.default_rng(0)
    for _ in range(100):
        th, dth, ddth = r.random_configuration(rng), rng.normal(size=r.n), rng.normal(size=r.n)
        tau = rng.normal(size=r.n) * 5
        F = rng.normal(size=6)
        assert rel(rk.inverse_dynamics(th, dth, ddth, r.gravity, np.zeros(6), *args), r.rnea(th, dth, ddth)) < 1e-9
        M = rk.mass_matrix(th, *args)
        assert rel(M, r.crba(th)) < 1e-9
        assert np.allclose(M, M.T, atol=0) and np.linalg.eigvalsh(M).min() > 0
        assert rel(rk.gravity_forces(th, r.gravity, *args), r.gravity_torques(th)) < 1e-9
        c_ref = r.nonlinear_effects(th, dth) - r.gravity_torques(th)
        assert rel(rk.vel_quadratic_forces(th, dth, *args), c_ref) < 1e-9
        Jb = r.jacobian(th, reference="local")
        assert rel(rk.end_effector_forces(th, F, *args), Jb.T @ F) < 1e-9
        # forward dynamics: compare τ reproduced by inverse dynamics (relative to τ), and with ABA
        dd = rk.forward_dynamics(th, dth, tau, r.gravity, F, *args)
        tau_back = r.rnea(th, dth, dd) + Jb.T @ F
        assert rel(tau_back, tau) < 1e-9
        dd_aba = r.aba(th, dth, tau - Jb.T @ F)
        assert np.abs(dd - dd_aba).max() <= 1e-9 * max(1.0, np.abs(dd_aba).max())


def test_against_modern_robotics(loaded):
    mr = pytest.importorskip("modern_robotics")
    r = loaded["ur5"]
    p = r.poe
    rng = np.random.default_rng(1)
    for _ in range(10):
        th, dth, ddth = rng.normal(size=6), rng.normal(size=6), rng.normal(size=6)
        F = rng.normal(size=6)
        ref = mr.InverseDynamics(th, dth, ddth, r.gravity, F, list(p.Mlist), list(p.Glist), p.Slist)
        assert rel(rk.inverse_dynamics(th, dth, ddth, r.gravity, F, p.Mlist, p.Glist, p.Slist), ref) < 1e-9
        assert rel(rk.mass_matrix(th, p.Mlist, p.Glist, p.Slist), mr.MassMatrix(th, list(p.Mlist), list(p.Glist), p.Slist)) < 1e-9


def test_trajectories_mr_semantics(loaded):
    mr = pytest.importorskip("modern_robotics")
    r = loaded["puma560"]
    p = r.poe
    rng = np.random.default_rng(2)
    N = 8
    Q, dQ, ddQ, Ft = (rng.normal(size=(N, 6)) for _ in range(4))
    taus = rk.inverse_dynamics_trajectory(Q, dQ, ddQ, r.gravity, Ft, p.Mlist, p.Glist, p.Slist)
    assert taus.shape == (N, 6)
    for k in range(N):
        assert rel(taus[k], rk.inverse_dynamics(Q[k], dQ[k], ddQ[k], r.gravity, Ft[k], p.Mlist, p.Glist, p.Slist)) < 1e-12
    th0, dth0 = rng.normal(size=6), rng.normal(size=6)
    taumat = rng.normal(size=(N, 6)) * 10
    Ftip = np.zeros((N, 6))
    thm, dthm = rk.forward_dynamics_trajectory(th0, dth0, taumat, r.gravity, Ftip, p.Mlist, p.Glist, p.Slist, 0.01, 4)
    thr, dthr = mr.ForwardDynamicsTrajectory(th0, dth0, taumat, r.gravity, Ftip, list(p.Mlist), list(p.Glist), p.Slist, 0.01, 4)
    assert np.abs(thm - thr).max() < 1e-9 and np.abs(dthm - dthr).max() < 1e-8
    a, b = rk.euler_step([1, 2], [3, 4], [5, 6], 0.1)
    assert np.allclose(a, [1.3, 2.4]) and np.allclose(b, [3.5, 4.6])


def test_bad_input(loaded):
    p = loaded["twolink"].poe
    with pytest.raises(ValueError, match="thetalist"):
        rk.mass_matrix([0, 0, 0], p.Mlist, p.Glist, p.Slist)
    with pytest.raises(ValueError, match="Glist"):
        rk.mass_matrix([0, 0], p.Mlist, p.Glist[:1], p.Slist)
    with pytest.raises(ValueError, match="g"):
        rk.gravity_forces([0, 0], [0, 0], p.Mlist, p.Glist, p.Slist)
    with pytest.raises(ValueError, match="intRes"):
        rk.forward_dynamics_trajectory([0, 0], [0, 0], np.zeros((3, 2)), [0, 0, -9.81], np.zeros((3, 6)),
                                       p.Mlist, p.Glist, p.Slist, 0.01, 0)
