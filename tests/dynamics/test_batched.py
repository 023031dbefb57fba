"""Batched (N, n) evaluation equals the per-call functions to 1e-12 and Pinocchio."""
import numpy as np
import pytest

import robokit as rk
from shared_robots import robot as shared_robot


@pytest.mark.parametrize("name", ["ur5", "panda", "puma560"])
def test_batched_dynamics_equal_per_call(name):
    r = shared_robot(name)
    p = r.poe
    rng = np.random.default_rng(0)
    N = 200
    Q = np.array([r.random_configuration(rng) for _ in range(N)])
    D, A = rng.normal(size=(N, r.n)), rng.normal(size=(N, r.n))
    F = rng.normal(size=(N, 6))
    tau = rk.inverse_dynamics(Q, D, A, r.gravity, F, p.Mlist, p.Glist, p.Slist)
    M = rk.mass_matrix(Q, p.Mlist, p.Glist, p.Slist)
    assert tau.shape == (N, r.n) and M.shape == (N, r.n, r.n)
    for k in range(0, N, 17):
        one = rk.inverse_dynamics(Q[k], D[k], A[k], r.gravity, F[k], p.Mlist, p.Glist, p.Slist)
        assert np.abs(tau[k] - one).max() <= 1e-12 * max(1.0, np.abs(one).max())
        assert np.abs(M[k] - rk.mass_matrix(Q[k], p.Mlist, p.Glist, p.Slist)).max() <= 1e-12 * np.abs(M[k]).max()
        ref = r.rnea(Q[k], D[k], A[k]) + r.jacobian(Q[k], reference="local").T @ F[k]
        assert np.abs(tau[k] - ref).max() <= 1e-9 * max(1.0, np.abs(ref).max())
        assert np.abs(M[k] - r.crba(Q[k])).max() <= 1e-9 * np.abs(M[k]).max()
    tau_g = rk.inverse_dynamics(Q, D, A, r.gravity, np.zeros(6), p.Mlist, p.Glist, p.Slist)  # one Ftip for all
    assert np.allclose(tau_g[3], rk.inverse_dynamics(Q[3], D[3], A[3], r.gravity, np.zeros(6), p.Mlist, p.Glist, p.Slist))
