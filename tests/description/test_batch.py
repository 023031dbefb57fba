"""A Robot's batched methods (``*_batch``, Q of shape (N, n)) equal its per-configuration methods
(Pinocchio); an (N, n) q given to a one-configuration method still works, with one DeprecationWarning."""
import numpy as np
import pytest

import robokit as rk
from shared_robots import robot as shared_robot


@pytest.mark.parametrize("name", ["ur5", "panda", "puma560", "kinova", "twolink"])
def test_batched_methods_equal_the_per_call_ones(name):
    r = shared_robot(name)
    rng = np.random.default_rng(1)
    N = 300  # above the kernels' serial threshold, so the parallel path runs too
    Q = np.array([r.random_configuration(rng) for _ in range(N)])
    dQ, ddQ = rng.normal(size=(N, r.n)), rng.normal(size=(N, r.n))
    T = r.frame_pose_batch(Q)
    J = {ref: r.jacobian_batch(Q, reference=ref) for ref in ("world", "local", "local_world_aligned")}
    M = r.crba_batch(Q)
    tau = r.rnea_batch(Q, dQ, ddQ, threads=2)
    ddq = r.aba_batch(Q, dQ, tau)
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
        r.frame_pose_batch(np.zeros((3, 5)))
    with pytest.raises(ValueError, match="frame"):
        r.jacobian_batch(np.zeros((3, 6)), frame="base_link")
    with pytest.raises(ValueError, match="threads"):
        r.rnea_batch(np.zeros((2, 6)), np.zeros((2, 6)), np.zeros((2, 6)), threads=0)
    with pytest.raises(ValueError, match="NaN"):
        r.crba_batch(np.full((2, 6), np.nan))
    two, three = np.zeros((2, 6)), np.zeros((3, 6))
    with pytest.raises(ValueError, match=r"q, dq, ddq: expected equal shapes, got \(2, 6\), \(3, 6\), \(2, 6\)"):
        r.rnea_batch(two, three, two)
    with pytest.raises(ValueError, match=r"q, dq, tau: expected equal shapes, got \(2, 6\), \(2, 6\), \(3, 6\)"):
        r.aba_batch(two, two, three)


def test_a_batch_given_to_a_one_configuration_method_warns_once_and_still_works():
    """frame_pose no longer switches engine on the input's shape: an (N, n) q is deprecated (until
    0.4.0), warned once per method per process, and gives what the explicit batch method gives."""
    import warnings

    from robokit import _deprecation

    r = rk.load("puma560")
    rng = np.random.default_rng(3)
    Q = np.array([r.random_configuration(rng) for _ in range(4)])
    Z = np.zeros_like(Q)
    calls = {"frame_pose": (lambda: r.frame_pose(Q), lambda: r.frame_pose_batch(Q)),
             "jacobian": (lambda: r.jacobian(Q), lambda: r.jacobian_batch(Q)),
             "rnea": (lambda: r.rnea(Q, Z, Z), lambda: r.rnea_batch(Q, Z, Z)),
             "crba": (lambda: r.crba(Q), lambda: r.crba_batch(Q)),
             "aba": (lambda: r.aba(Q, Z, Z), lambda: r.aba_batch(Q, Z, Z))}
    for method, (old, new) in calls.items():
        key = f"Robot.{method}((N, n) q)"
        _deprecation._WARNED.discard(key)
        with warnings.catch_warnings(record=True) as rec:
            warnings.simplefilter("always")
            a, b = old(), old()
        dep = [w for w in rec if issubclass(w.category, DeprecationWarning)]
        assert len(dep) == 1 and f"{method}_batch" in str(dep[0].message) and "0.4.0" in str(dep[0].message)
        assert dep[0].filename == __file__
        expected = new()
        assert a.shape == expected.shape and np.array_equal(a, expected) and np.array_equal(b, expected), method


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
