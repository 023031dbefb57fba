"""Seed ikin_body / ikin_space: the textbook example, random arms, unreachable targets."""
import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from robokit import matrix_exp_6, vec_to_se3
from robokit.ik.numeric import ikin_body, ikin_space

# Modern Robotics (Lynch & Park), example 6.1 / IKinBody docstring: a 3R open chain.
BLIST = np.array([[0, 0, -1, 2, 0, 0], [0, 0, 0, 0, 1, 0], [0, 0, 1, 0, 0, 0.1]], float).T
SLIST = np.array([[0, 0, 1, 4, 0, 0], [0, 0, 0, 0, 1, 0], [0, 0, -1, -6, 0, -0.1]], float).T
M = np.array([[-1, 0, 0, 0], [0, 1, 0, 6], [0, 0, -1, 2], [0, 0, 0, 1]], float)
T_BOOK = np.array([[0, 1, 0, -5], [1, 0, 0, 4], [0, 0, -1, 1.6858], [0, 0, 0, 1]], float)


def fk_space(Slist, M, q):
    T = np.eye(4)
    for i, qi in enumerate(q):
        T = T @ matrix_exp_6(vec_to_se3(Slist[:, i] * qi))
    return T @ M


def test_textbook_example_values():
    # the book's published answers for these tolerances
    q, ok = ikin_body(BLIST, M, T_BOOK, [1.5, 2.5, 3], 0.01, 0.001)
    assert ok and np.allclose(q, [1.57073819, 2.999667, 3.14153913], atol=1e-8)
    q, ok = ikin_space(SLIST, M, T_BOOK, [1.5, 2.5, 3], 0.01, 0.001)
    assert ok and np.allclose(q, [1.57073783, 2.99966384, 3.1415342], atol=1e-8)


def random_arm(rng, n):
    """Random revolute screw axes S = (ω, −ω × p) and a random home pose."""
    S = np.zeros((6, n))
    for i in range(n):
        w = rng.normal(size=3)
        w /= np.linalg.norm(w)
        p = rng.normal(size=3) * 0.3
        S[:3, i] = w
        S[3:, i] = -np.cross(w, p)
    M = matrix_exp_6(vec_to_se3(np.r_[rng.normal(size=3), rng.normal(size=3)]))
    return S, M


@settings(max_examples=40, deadline=None)
@given(st.integers(0, 10_000), st.integers(6, 7))
def test_converges_from_nearby_seed(seed, n):
    rng = np.random.default_rng(seed)
    S, Mh = random_arm(rng, n)
    q_true = rng.uniform(-np.pi, np.pi, n)
    T = fk_space(S, Mh, q_true)
    q0 = q_true + rng.uniform(-0.1, 0.1, n)
    B = np.linalg.inv(_adj(Mh)) @ S
    for solver, screws in ((ikin_space, S), (ikin_body, B)):
        q, ok = solver(screws, Mh, T, q0, 1e-10, 1e-10)
        if ok:
            assert np.abs(fk_space(S, Mh, q) - T).max() < 1e-9


def _adj(T):
    R, p = T[:3, :3], T[:3, 3]
    P = np.array([[0, -p[2], p[1]], [p[2], 0, -p[0]], [-p[1], p[0], 0]])
    A = np.zeros((6, 6))
    A[:3, :3] = R
    A[3:, 3:] = R
    A[3:, :3] = P @ R
    return A


def test_nearby_seed_success_rate_on_ur5_like_arm():
    """A UR5-like arm (published UR5 dimensions) from seeds within 0.1 rad: NR must converge."""
    W1, W2, L1, L2, H1, H2 = 0.109, 0.082, 0.425, 0.392, 0.089, 0.095
    S = np.array([[0, 0, 1, 0, 0, 0], [0, 1, 0, -H1, 0, 0], [0, 1, 0, -H1, 0, L1],
                  [0, 1, 0, -H1, 0, L1 + L2], [0, 0, -1, -W1, L1 + L2, 0], [0, 1, 0, H2 - H1, 0, L1 + L2]], float).T
    Mh = np.array([[-1, 0, 0, L1 + L2], [0, 0, 1, W1 + W2], [0, 1, 0, H1 - H2], [0, 0, 0, 1]], float)
    rng = np.random.default_rng(7)
    ok_count = 0
    for _ in range(50):
        q_true = rng.uniform(-np.pi, np.pi, 6)
        T = fk_space(S, Mh, q_true)
        q, ok = ikin_space(S, Mh, T, q_true + rng.uniform(-0.1, 0.1, 6), 1e-10, 1e-10)
        ok_count += ok
        if ok:
            assert np.abs(fk_space(S, Mh, q) - T).max() < 1e-9
    assert ok_count >= 48


def test_unreachable_reports_failure_without_exception():
    T = T_BOOK.copy()
    T[:3, 3] = [100.0, 0.0, 0.0]
    q, ok = ikin_body(BLIST, M, T, [1.5, 2.5, 3], 1e-6, 1e-6)
    assert ok is False and np.all(np.isfinite(q))
    q, ok = ikin_space(SLIST, M, T, [1.5, 2.5, 3], 1e-6, 1e-6)
    assert ok is False and np.all(np.isfinite(q))


def test_bad_input():
    with pytest.raises(ValueError, match="thetalist0"):
        ikin_body(BLIST, M, T_BOOK, [1.5, 2.5], 0.01, 0.001)
    with pytest.raises(ValueError, match="T"):
        ikin_space(SLIST, M, np.ones((4, 4)), [1.5, 2.5, 3], 0.01, 0.001)
    with pytest.raises(ValueError, match="Slist"):
        ikin_space(SLIST[:5], M, T_BOOK, [1.5, 2.5, 3], 0.01, 0.001)
