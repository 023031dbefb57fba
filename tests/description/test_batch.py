"""A Robot's batched methods (q of shape (N, n)) equal its per-configuration methods (Pinocchio)."""
import numpy as np
import pytest

import robokit as rk


@pytest.mark.parametrize("name", ["ur5", "panda", "puma560", "kinova", "twolink"])
def test_batched_methods_equal_the_per_call_ones(name):
    r = rk.load(name)
    rng = np.random.default_rng(1)
    N = 300  # above the kernels' serial threshold, so the parallel path runs too
    Q = np.array([r.random_configuration(rng) for _ in range(N)])
    dQ, ddQ = rng.normal(size=(N, r.n)), rng.normal(size=(N, r.n))
    T = r.frame_pose(Q)
    J = {ref: r.jacobian(Q, reference=ref) for ref in ("world", "local", "local_world_aligned")}
    M = r.crba(Q)
    tau = r.rnea(Q, dQ, ddQ, threads=2)
    ddq = r.aba(Q, dQ, tau)
    for k in range(0, N, 7):
        assert np.abs(T[k] - r.frame_pose(Q[k])).max() < 1e-12
        for ref, Jb in J.items():
            assert np.abs(Jb[k] - r.jacobian(Q[k], reference=ref)).max() < 1e-12, ref
        assert np.abs(M[k] - r.crba(Q[k])).max() <= 1e-12 * max(1.0, np.abs(M[k]).max())
        assert np.abs(tau[k] - r.rnea(Q[k], dQ[k], ddQ[k])).max() <= 1e-10 * max(1.0, np.abs(tau[k]).max())
    assert np.abs(ddq - ddQ).max() < 1e-8  # aba inverts rnea


def test_batched_methods_refuse_bad_input():
    r = rk.load("ur5")
    with pytest.raises(ValueError, match="q"):
        r.frame_pose(np.zeros((3, 5)))
    with pytest.raises(ValueError, match="frame"):
        r.jacobian(np.zeros((3, 6)), frame="base_link")
    with pytest.raises(ValueError, match="threads"):
        r.rnea(np.zeros((2, 6)), np.zeros((2, 6)), np.zeros((2, 6)), threads=0)
    with pytest.raises(ValueError, match="NaN"):
        r.crba(np.full((2, 6), np.nan))


def test_one_row_batch_keeps_its_batch_axis():
    """Q of shape (1, n) gives (1, ...) results, equal to the per-configuration call (Pinocchio
    returns a (n,) vector for a single column; the batch axis must survive)."""
    r = rk.load("puma560")
    rng = np.random.default_rng(2)
    q, dq, ddq = r.random_configuration(rng), rng.normal(size=r.n), rng.normal(size=r.n)
    tau = r.rnea(q[None], dq[None], ddq[None])
    assert tau.shape == (1, r.n)
    assert np.abs(tau[0] - r.rnea(q, dq, ddq)).max() < 1e-10
    ddq_back = r.aba(q[None], dq[None], tau)
    assert ddq_back.shape == (1, r.n)
    assert np.abs(ddq_back[0] - ddq).max() < 1e-8
    assert r.frame_pose(q[None]).shape == (1, 4, 4)
    assert r.crba(q[None]).shape == (1, r.n, r.n)
