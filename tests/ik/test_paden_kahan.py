"""Lecture 5 building blocks: a cos θ + b sin θ = c, Paden–Kahan subproblems 1–3, the
homework RRR arm with a full pose. Checked by substitution into the defining equations
(rotations built here with Rodrigues' formula) and against the generating angles."""
import math

import numpy as np
import pytest
from hypothesis import assume, given, settings
from hypothesis import strategies as st

from robokit.ik import ik_rrr_pose, pk_subproblem1, pk_subproblem2, pk_subproblem3, solve_trig

angles = st.floats(-math.pi, math.pi, allow_nan=False)
coef = st.floats(-10.0, 10.0, allow_nan=False)
vec = st.lists(st.floats(-2.0, 2.0, allow_nan=False), min_size=3, max_size=3).map(np.array)


def rot(w, t):
    """Rodrigues: rotation by t about the unit axis w."""
    w = np.asarray(w, float) / np.linalg.norm(w)
    K = np.array([[0, -w[2], w[1]], [w[2], 0, -w[0]], [-w[1], w[0], 0]])
    return np.eye(3) + math.sin(t) * K + (1 - math.cos(t)) * K @ K


def adist(a, b):
    return abs(math.remainder(a - b, 2 * math.pi))


@settings(max_examples=300, deadline=None)
@given(coef, coef, angles)
def test_solve_trig_contains_generator_and_roots_solve(a, b, t):
    assume(math.hypot(a, b) > 1e-6)
    c = a * math.cos(t) + b * math.sin(t)
    roots = solve_trig(a, b, c)
    assert 1 <= len(roots) <= 2
    for r in roots:
        assert -math.pi < r <= math.pi
        assert abs(a * math.cos(r) + b * math.sin(r) - c) <= 1e-12 * max(1.0, math.hypot(a, b))
    # a double root (tangency) can only be located to √ε in angle
    tol = 1e-9 if abs(math.hypot(a, b) - abs(c)) > 1e-6 * math.hypot(a, b) else 1e-6
    assert min(adist(r, t) for r in roots) < tol


def test_solve_trig_degenerate_cases():
    assert solve_trig(1.0, 1.0, 3.0) == []  # |c| > √(a² + b²)
    assert solve_trig(0.0, 0.0, 1.0) == []  # 0 = 1
    with pytest.raises(ValueError, match="every angle"):
        solve_trig(0.0, 0.0, 0.0)
    (r,) = solve_trig(1.0, 0.0, -1.0)  # a + c = 0: the root u = ∞, θ = π
    assert r == pytest.approx(math.pi, abs=1e-15)
    roots = solve_trig(-2.0, 1.0, 2.0)  # a + c = 0 with b ≠ 0: π and one finite root
    assert any(abs(r - math.pi) < 1e-15 for r in roots) and len(roots) == 2
    (r,) = solve_trig(0.0, 2.0, 2.0)  # tangency: sin θ = 1
    assert r == pytest.approx(math.pi / 2, abs=1e-12)
    with pytest.raises(ValueError, match="a"):
        solve_trig(float("nan"), 1.0, 0.0)


@settings(max_examples=200, deadline=None)
@given(vec, vec, vec, angles)
def test_subproblem1(w, r, p, t):
    assume(np.linalg.norm(w) > 0.1)
    w = w / np.linalg.norm(w)
    assume(np.linalg.norm(np.cross(w, p - r)) > 1e-3)
    q = r + rot(w, t) @ (p - r)
    (theta,) = pk_subproblem1(w, r, p, q)
    assert adist(theta, t) < 1e-9
    assert pk_subproblem1(w, r, p, q + 0.1 * w) == []  # not on the same circle


@settings(max_examples=200, deadline=None)
@given(vec, vec, vec, vec, angles, angles)
def test_subproblem2(w1, w2, r, p, t1, t2):
    assume(np.linalg.norm(w1) > 0.1 and np.linalg.norm(w2) > 0.1)
    w1, w2 = w1 / np.linalg.norm(w1), w2 / np.linalg.norm(w2)
    assume(np.linalg.norm(np.cross(w1, w2)) > 0.1)
    u = p - r
    # away from the configurations where p or the intermediate point lies on an axis
    assume(np.linalg.norm(np.cross(w2, u)) > 0.05 and np.linalg.norm(np.cross(w1, rot(w2, t2) @ u)) > 0.05)
    q = r + rot(w1, t1) @ rot(w2, t2) @ u
    sols = pk_subproblem2(w1, w2, r, p, q)
    assert 1 <= len(sols) <= 2
    for a, b in sols:
        assert np.abs(r + rot(w1, a) @ rot(w2, b) @ u - q).max() < 1e-8
    assert min(max(adist(a, t1), adist(b, t2)) for a, b in sols) < 1e-6


@settings(max_examples=200, deadline=None)
@given(vec, vec, vec, vec, angles)
def test_subproblem3(w, r, p, q, t):
    assume(np.linalg.norm(w) > 0.1)
    w = w / np.linalg.norm(w)
    assume(np.linalg.norm(np.cross(w, p - r)) > 1e-2 and np.linalg.norm(np.cross(w, q - r)) > 1e-2)
    delta = float(np.linalg.norm(r + rot(w, t) @ (p - r) - q))
    up, vp = np.cross(w, p - r), np.cross(w, q - r)  # |u′|, |v′| (norms of the projections)
    dz = float(w @ (p - q))
    k = (up @ up + vp @ vp - (delta ** 2 - dz ** 2)) / (2 * np.linalg.norm(up) * np.linalg.norm(vp))
    assume(abs(k) < 1 - 1e-6)  # at tangency (one double root) the angle is only good to √ε
    sols = pk_subproblem3(w, r, p, q, delta)
    assert 1 <= len(sols) <= 2
    for s in sols:
        assert abs(np.linalg.norm(r + rot(w, s) @ (p - r) - q) - delta) < 1e-8
    assert min(adist(s, t) for s in sols) < 1e-5  # near tangency the angle is ill-conditioned


def test_subproblems_unreachable_and_bad_axes():
    z = [0, 0, 1]
    assert pk_subproblem3(z, [0, 0, 0], [1, 0, 0], [1, 0, 0], 3.0) == []  # farther than 2 m
    (t,) = pk_subproblem3(z, [0, 0, 0], [1, 0, 0], [1, 0, 0], 0.0)  # tangency: the double root θ = 0
    assert abs(t) < 1e-12
    assert pk_subproblem2(z, [1, 0, 0], [0, 0, 0], [1, 0, 0], [0, 2, 0]) == []  # |p| ≠ |q|
    with pytest.raises(ValueError, match="parallel"):
        pk_subproblem2(z, z, [0, 0, 0], [1, 0, 0], [1, 0, 0])
    with pytest.raises(ValueError, match="omega"):
        pk_subproblem1([0, 0, 0], [0, 0, 0], [1, 0, 0], [1, 0, 0])


def homework_tool_pose(q, L1, L2, L3):
    """Lecture 5 homework: ⁰T₃ written out (Craig's convention), tool L₃ along x₃."""
    c1, s1, c2, s2 = math.cos(q[0]), math.sin(q[0]), math.cos(q[1]), math.sin(q[1])
    c23, s23 = math.cos(q[1] + q[2]), math.sin(q[1] + q[2])
    T = np.array([[c1 * c23, -c1 * s23, s1, c1 * (c2 * L2 + L1)],
                  [s1 * c23, -s1 * s23, -c1, s1 * (c2 * L2 + L1)],
                  [s23, c23, 0, s2 * L2], [0, 0, 0, 1.0]])
    T[:3, 3] += L3 * T[:3, 0]
    return T


@settings(max_examples=200, deadline=None)
@given(angles, angles, angles)
def test_rrr_full_pose_lecture5(t1, t2, t3):
    L1, L2, L3 = 0.3, 0.5, 0.4
    T = homework_tool_pose([t1, t2, t3], L1, L2, L3)
    (s,) = ik_rrr_pose(T, L1, L2, L3)
    assert np.abs(homework_tool_pose(s.q, L1, L2, L3) - T).max() < 1e-12
    assert max(adist(a, b) for a, b in zip(s.q, [t1, t2, t3])) < 1e-9


def test_rrr_full_pose_unreachable():
    T = homework_tool_pose([0.2, 0.3, 0.4], 0.3, 0.5, 0.4)
    T[2, 3] += 0.05  # off the arm's surface
    assert ik_rrr_pose(T, 0.3, 0.5, 0.4) == []
    assert ik_rrr_pose(np.eye(4), 0.3, 0.5, 0.4) == []  # z₃ vertical: not a pose of this arm
    with pytest.raises(ValueError, match="L2"):
        ik_rrr_pose(np.eye(4), 0.3, 0.0, 0.4)
