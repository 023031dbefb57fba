"""Closed-form IK: every solution reproduces its target; the generating configuration is found.

Forward kinematics here is written out independently in the test (the DH product of
seed 003 eq. 13, and the lecture's closed forms), so the solvers are checked against the
definition of the arm, not against themselves.
"""
import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from types import SimpleNamespace

from robokit.ik.analytic import (
    ik_planar_2link,
    ik_planar_rrr,
    ik_puma560,
    ik_rrr_position,
    ik_spherical_wrist,
    select_solution,
)

angles = st.floats(-np.pi, np.pi, allow_nan=False)


def dh_std(a, alpha, d, theta):
    ct, st_, ca, sa = np.cos(theta), np.sin(theta), np.cos(alpha), np.sin(alpha)
    return np.array([[ct, -st_ * ca, st_ * sa, a * ct], [st_, ct * ca, -ct * sa, a * st_], [0, sa, ca, d], [0, 0, 0, 1]])


def rz(t):
    c, s = np.cos(t), np.sin(t)
    return np.array([[c, -s, 0], [s, c, 0], [0, 0, 1.0]])


def ry(t):
    c, s = np.cos(t), np.sin(t)
    return np.array([[c, 0, s], [0, 1.0, 0], [-s, 0, c]])


def angle_dist(a, b):
    return np.abs(np.angle(np.exp(1j * (np.asarray(a) - np.asarray(b))))).max()


# PUMA 560, standard DH as in Corke's toolbox (a2 = 0.4318, a3 = 0.0203, d3 = 0.15005, d4 = 0.4318),
# with a base offset, a tool and θ offsets added so the general case is exercised.
PUMA_ROWS = [(0, np.pi / 2, 0.6718, 0), (0.4318, 0, 0, 0.1), (0.0203, -np.pi / 2, 0.15005, -0.2),
             (0, np.pi / 2, 0.4318, 0), (0, -np.pi / 2, 0, 0.3), (0, 0, 0.056, 0)]


def make_puma(qlim=None):
    base = np.eye(4)
    base[:3, :3] = rz(0.4)
    base[:3, 3] = [0.1, -0.2, 0.05]
    tool = np.eye(4)
    tool[:3, 3] = [0.0, 0.01, 0.1]
    links = [SimpleNamespace(a=a, alpha=al, d=d, theta=th, joint="R", qlim=None if qlim is None else qlim[i])
             for i, (a, al, d, th) in enumerate(PUMA_ROWS)]
    table = SimpleNamespace(links=links, convention="standard", base=base, tool=tool)

    def fk(q):
        T = base.copy()
        for (a, al, d, th), qi in zip(PUMA_ROWS, q):
            T = T @ dh_std(a, al, d, th + qi)
        return T @ tool

    return table, fk


@settings(max_examples=150, deadline=None)
@given(st.lists(angles, min_size=6, max_size=6))
def test_puma_all_eight_reproduce_target_and_contain_generator(q):
    table, fk = make_puma()
    q = np.array(q)
    T = fk(q)
    sols = ik_puma560(table, T)
    sin5 = abs(np.sin(q[4] + PUMA_ROWS[4][3]))
    if sin5 > 1e-6:
        assert len(sols) == 8
        assert len({s.label for s in sols}) == 8
    for s in sols:
        assert np.abs(fk(s.q) - T).max() < 1e-9
    assert min(angle_dist(s.q, q) for s in sols) < 1e-6 or sin5 < 1e-6


def test_puma_unreachable_gives_empty_list():
    table, fk = make_puma()
    T = np.eye(4)
    T[:3, 3] = [3.0, 0.0, 0.5]
    assert ik_puma560(table, T) == []


def test_puma_wrist_singularity_documented_choice():
    table, fk = make_puma()
    q = np.array([0.3, -0.5, 0.4, 0.7, -0.3, 0.2])  # θ5 = q5 + 0.3 = 0: joints 4 and 6 aligned
    T = fk(q)
    sols = ik_puma560(table, T, theta4_ref=0.7)
    assert any(s.degenerate for s in sols)  # the arm branch of the generator has θ5 = 0
    for s in sols:
        assert np.abs(fk(s.q) - T).max() < 1e-9
    assert min(angle_dist(s.q, q) for s in sols) < 1e-9  # θ4_ref = the true θ4 gives the generator back


def test_puma_limits_flag_and_rejects_other_structures():
    qlim = [(-2.8, 2.8), (-3.9, 0.8), (-0.8, 3.9), (-1.9, 2.9), (-1.75, 1.75), (-4.6, 4.6)]
    table, fk = make_puma(qlim)
    T = fk(np.array([0.2, -0.4, 0.5, 0.1, 0.6, -0.3]))
    sols = ik_puma560(table, T)
    assert any(s.within_limits for s in sols)
    for s in sols:
        inside = all(lo - 1e-12 <= v <= hi + 1e-12 for v, (lo, hi) in zip(s.q, qlim))
        assert s.within_limits == inside
    bad = SimpleNamespace(links=table.links[:5], convention="standard", base=table.base, tool=table.tool)
    with pytest.raises(ValueError, match="six revolute"):
        ik_puma560(bad, T)
    mod = SimpleNamespace(links=table.links, convention="modified", base=table.base, tool=table.tool)
    with pytest.raises(ValueError, match="standard"):
        ik_puma560(mod, T)


@settings(max_examples=200, deadline=None)
@given(angles, angles, st.floats(0.2, 2.0), st.floats(0.2, 2.0))
def test_planar_2link(t1, t2, l1, l2):
    x = l1 * np.cos(t1) + l2 * np.cos(t1 + t2)
    y = l1 * np.sin(t1) + l2 * np.sin(t1 + t2)
    sols = ik_planar_2link(x, y, l1, l2)
    assert 1 <= len(sols) <= 2
    for s in sols:
        a, b = s.q
        assert abs(l1 * np.cos(a) + l2 * np.cos(a + b) - x) < 1e-9
        assert abs(l1 * np.sin(a) + l2 * np.sin(a + b) - y) < 1e-9
    if abs(np.sin(t2)) > 1e-6 and np.hypot(x, y) > 1e-6:
        assert min(angle_dist(s.q, [t1, t2]) for s in sols) < 1e-6


def test_planar_2link_annulus_and_lecture_values():
    assert ik_planar_2link(2.5, 0.0, 1.0, 1.0) == []  # beyond l1 + l2
    assert ik_planar_2link(0.2, 0.0, 1.0, 0.5) == []  # inside |l1 − l2|
    sols = ik_planar_2link(1.0, 1.0, 1.0, 1.0)
    qs = sorted(tuple(np.round(s.q, 12)) for s in sols)
    assert np.allclose(qs, [(0.0, np.pi / 2), (np.pi / 2, -np.pi / 2)], atol=1e-12)
    with pytest.raises(ValueError, match="l1"):
        ik_planar_2link(1, 1, -1, 1)


@settings(max_examples=150, deadline=None)
@given(angles, angles, angles)
def test_planar_rrr_pose(t1, t2, t3):
    l1, l2, l3 = 0.5, 0.4, 0.2
    phi = t1 + t2 + t3
    x = l1 * np.cos(t1) + l2 * np.cos(t1 + t2) + l3 * np.cos(phi)
    y = l1 * np.sin(t1) + l2 * np.sin(t1 + t2) + l3 * np.sin(phi)
    sols = ik_planar_rrr(x, y, phi, l1, l2, l3)
    assert sols
    for s in sols:
        a, b, c = s.q
        assert abs(l1 * np.cos(a) + l2 * np.cos(a + b) + l3 * np.cos(a + b + c) - x) < 1e-9
        assert abs(l1 * np.sin(a) + l2 * np.sin(a + b) + l3 * np.sin(a + b + c) - y) < 1e-9
        assert angle_dist(a + b + c, phi) < 1e-9


@settings(max_examples=150, deadline=None)
@given(angles, angles, angles)
def test_spherical_wrist_both_branches(a, b, c):
    R = rz(a) @ ry(b) @ rz(c)
    sols = ik_spherical_wrist(R)
    for s in sols:
        assert np.abs(rz(s.q[0]) @ ry(s.q[1]) @ rz(s.q[2]) - R).max() < 1e-9
    if abs(np.sin(b)) > 1e-6:
        assert len(sols) == 2
        assert sols[0].q[1] > 0 > sols[1].q[1]  # θ5 ∈ (0, π) and (−π, 0), seed 003 eqs. 16–17


def test_spherical_wrist_degenerate():
    R = rz(0.9)  # θ5 = 0: only θ4 + θ6 = 0.9 is determined
    (s,) = ik_spherical_wrist(R, theta4_ref=0.25)
    assert s.degenerate and np.allclose(s.q, [0.25, 0.0, 0.65])
    R = rz(0.4) @ ry(np.pi) @ rz(0.1)  # θ5 = π: θ4 − θ6 = 0.3 is determined
    (s,) = ik_spherical_wrist(R, theta4_ref=0.0)
    assert np.abs(rz(s.q[0]) @ ry(s.q[1]) @ rz(s.q[2]) - R).max() < 1e-12


@settings(max_examples=150, deadline=None)
@given(angles, angles, angles)
def test_rrr_position_lecture5(t1, t2, t3):
    L1, L2, L3 = 0.3, 0.5, 0.4

    def pos(q):  # Lecture 5 homework: ⁰P_tool
        a, b, c = q
        r = L1 + L2 * np.cos(b) + L3 * np.cos(b + c)
        return np.array([np.cos(a) * r, np.sin(a) * r, L2 * np.sin(b) + L3 * np.sin(b + c)])

    p = pos([t1, t2, t3])
    sols = ik_rrr_position(p, L1, L2, L3)
    assert sols
    for s in sols:
        assert np.abs(pos(s.q) - p).max() < 1e-9
    if abs(np.sin(t3)) > 1e-6 and np.hypot(p[0], p[1]) > 1e-6:
        assert min(angle_dist(s.q, [t1, t2, t3]) for s in sols) < 1e-6


def test_select_solution():
    sols = ik_planar_2link(1.0, 1.0, 1.0, 1.0, qlim=[(-np.pi, np.pi), (0.0, np.pi)])
    assert [s.within_limits for s in sols] == [True, False]
    best = select_solution(sols, [1.5, -1.5])
    assert np.allclose(best.q, [0.0, np.pi / 2])  # the other one is outside the limits
    best = select_solution(sols, [1.5, -1.5], within_limits=False)
    assert np.allclose(best.q, [np.pi / 2, -np.pi / 2])
    assert select_solution([], [0, 0]) is None
