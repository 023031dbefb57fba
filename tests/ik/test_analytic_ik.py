"""AnalyticIK as an object: the solver Protocol (a hand-written toy solver plugs in), the cache that
follows its robot (in-place edits of base/tool/limits, replaced tables), and the contract."""
import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import robokit as rk
from shared_robots import robot as shared_robot
from robokit.description.dh import DHLink, DHTable, matrix_from_rpy
from robokit.errors import InputError
from robokit.ik import AnalyticIK, ClosedFormSolver, PositionBranch, ik_analytic, ik_analytic_kind
from robokit.ik import closed_form


def _reaches(robot, sols, T, q_true):
    """Every solution reaches T (Pinocchio FK, 1e-9) and the generating configuration is among them."""
    assert sols
    for s in sols:
        assert np.abs(robot.frame_pose(s.q) - T).max() < 1e-9, s.label
    d = [np.abs(np.angle(np.exp(1j * (s.q - q_true)))).max() for s in sols]
    assert min(d) < 1e-7


# ---------------------------------------------------------------------------- a toy solver
def _gantry_table(base=None):
    """A Cartesian gantry (three prismatic joints along x, y, z of frame 0) and a ZYZ wrist."""
    h = math.pi / 2
    links = (DHLink("P", a=0.0, alpha=-h, d=0.3, theta=-h), DHLink("P", a=0.0, alpha=-h, d=0.2, theta=-h),
             DHLink("P", a=0.0, alpha=0.0, d=0.1, theta=0.0), DHLink("R", alpha=-h), DHLink("R", alpha=h),
             DHLink("R", d=0.15))
    return DHTable("gantry", "standard", links, base=np.eye(4) if base is None else base)


class ToyGantrySolver:
    """Hand-written closed form of the gantry: the wrist centre is affine in (q1, q2, q3); the
    wrist is R_preᵀR06 = Rz(θ4)Ry(θ5)Rz(θ6) (ZYZ, both branches)."""

    method = "spherical wrist"

    def __init__(self, chain):
        self.chain = chain
        self.calls = []

        self.w6 = np.array([0.0, 0.0, -chain.d0[5]])  # Z6 = Rz(θ6)Tz(d6): the centre is d6 back along z6

        def centre(q123):
            return (chain.fk6(list(q123) + [0.0, 0.0, 0.0]) @ np.r_[self.w6, 1.0])[:3]

        self.W0 = centre([0.0, 0.0, 0.0])
        self.A = np.column_stack([centre(e) - self.W0 for e in np.eye(3)])
        self.R_pre = chain.fk6(np.zeros(6))[:3, :3]  # Rz(θ4..6 = 0) are identities

    def refusal(self):
        return None

    def position(self, T06):
        self.calls.append("position")
        W = T06[:3, :3] @ self.w6 + T06[:3, 3]
        q123 = np.linalg.solve(self.A, W - self.W0)
        return [PositionBranch(tuple(q123), "gantry, ", False, None)]

    def wrist(self, T06, branch, wrist_ref):
        self.calls.append("wrist")
        M = self.R_pre.T @ T06[:3, :3]
        s5 = math.hypot(M[0, 2], M[1, 2])
        rows = []
        for sign, label in ((1.0, "no flip"), (-1.0, "flip")):
            t5 = math.atan2(sign * s5, M[2, 2])
            t4 = math.atan2(sign * M[1, 2], sign * M[0, 2])
            t6 = math.atan2(sign * M[2, 1], -sign * M[2, 0])
            th0 = self.chain.th0
            rows.append((tuple(branch.q) + (t4 - th0[3], t5 - th0[4], t6 - th0[5]), branch.label + label, False))
        return rows

    def joint_angles(self, T06, wrist_ref):
        return [row for b in self.position(T06) for row in self.wrist(T06, b, wrist_ref)]


def test_a_hand_written_solver_implements_the_protocol_and_plugs_in(monkeypatch):
    table = _gantry_table()
    robot = rk.load(table)
    monkeypatch.setitem(closed_form.SOLVERS, "spherical wrist", ToyGantrySolver)
    ik = AnalyticIK(robot)
    assert isinstance(ik.solver, ToyGantrySolver) and isinstance(ik.solver, ClosedFormSolver)
    assert ik.method == "spherical wrist" and not ik.reversed
    rng = np.random.default_rng(5)
    for _ in range(5):
        q = np.r_[rng.uniform(-0.4, 0.4, 3), rng.uniform(-2.5, 2.5, 3)]
        q[4] = rng.uniform(0.3, 2.5) * rng.choice([-1, 1])  # away from the wrist singularity
        T = robot.frame_pose(q)
        sols = ik.solve(T)
        _reaches(robot, sols, T, q)
        assert sorted(s.label for s in sols) == ["gantry, flip", "gantry, no flip"]
    assert ik.solver.calls[:2] == ["position", "wrist"]  # AnalyticIK went through the interface


def test_builtin_solvers_implement_the_protocol():
    for name in ("puma560", "ur5"):
        ik = AnalyticIK(rk.load(name))
        assert isinstance(ik.solver, ClosedFormSolver)
        robot = rk.load(name)
        q = np.array([0.3, -0.7, 0.9, 0.4, 0.8, -0.3])
        T = robot.frame_pose(q)
        T06 = ik.chain.target_06(T)
        rows = [r for b in ik.solver.position(T06) for r in ik.solver.wrist(T06, b, 0.0)]
        assert sorted(r[1] for r in rows) == sorted(r[1] for r in ik.solver.joint_angles(T06, 0.0))
        _reaches(robot, ik.solve(T), T, q)


# ---------------------------------------------------------------------------- the object
def test_analytic_ik_object_matches_ik_analytic_and_gives_a_reason():
    robot = rk.load("puma560")
    ik = AnalyticIK(robot)
    q = np.array([0.1, -0.5, 0.3, 0.4, 0.6, -0.2])
    T = robot.frame_pose(q)
    a, b = ik.solve(T), ik_analytic(robot, T)
    assert [s.label for s in a] == [s.label for s in b]
    assert all(np.array_equal(x.q, y.q) for x, y in zip(a, b))
    assert ik.kind == ik_analytic_kind(robot) and bool(ik)
    panda = AnalyticIK(shared_robot("panda"))
    assert not panda and panda.method is None and "7 joints" in panda.reason
    with pytest.raises(InputError, match="robot: no closed-form inverse kinematics: the arm has 7 joints"):
        panda.solve(np.eye(4))
    with pytest.raises(InputError, match="T"):
        ik.solve(np.ones((4, 4)))
    with pytest.raises(TypeError, match="robot"):
        AnalyticIK(object())


# ---------------------------------------------------------------------------- cache ownership
def _puma_table():
    """The PUMA's DH table as a table of one's own (a robot's table has read-only base and tool)."""
    import dataclasses

    dh = rk.load("puma560").dh
    return dataclasses.replace(dh, base=np.array(dh.base), tool=np.array(dh.tool))


def test_editing_base_in_place_invalidates_the_cached_solver():
    table = _puma_table()
    held = AnalyticIK(table)
    q = np.array([0.2, -0.6, 0.4, 0.3, 0.7, 0.1])
    before = ik_analytic(table, table.fk(q))
    assert before
    table.base[:3, 3] += [0.05, -0.02, 0.3]  # the frozen table's array, edited in place
    table.base[:3, :3] = matrix_from_rpy([0.1, -0.2, 0.3])
    table.tool[2, 3] += 0.07
    T = table.fk(q)  # the table's own FK with the new base and tool
    for sols in (ik_analytic(table, T), held.solve(T)):
        assert sols
        for s in sols:
            assert np.abs(table.fk(s.q) - T).max() < 1e-9
        assert min(np.abs(np.angle(np.exp(1j * (s.q - q)))).max() for s in sols) < 1e-7


def test_a_robot_with_other_limits_flags_its_solutions_by_them():
    """A Robot never changes (its limits are read-only); with_limits gives the copy whose closed
    form flags solutions by the new limits, and the original keeps its own."""
    robot = rk.load("puma560")
    q = np.array([0.2, -0.6, 0.4, 0.3, 0.7, 0.1])
    T = robot.frame_pose(q)
    assert sum(s.within_limits for s in ik_analytic(robot, T)) >= 2
    with pytest.raises(ValueError, match="read-only"):
        robot.qlim[0] = [q[0] - 1e-3, q[0] + 1e-3]
    with pytest.raises(AttributeError, match="with_limits"):
        robot.qlim = np.tile([-0.01, 0.01], (6, 1))
    qlim = robot.qlim.copy()
    qlim[0] = [q[0] - 1e-3, q[0] + 1e-3]  # joint 1 pinned near q₁
    pinned = robot.with_limits(qlim)
    for sols in (AnalyticIK(pinned).solve(T), ik_analytic(pinned, T)):
        inside = [s for s in sols if s.within_limits]
        assert inside and all(abs(s.q[0] - q[0]) <= 1e-3 for s in inside)
        assert any(abs(s.q[0] - q[0]) > 0.1 for s in sols)  # the other shoulder: flagged outside
    assert not any(s.within_limits for s in ik_analytic(robot.with_limits(np.tile([-0.01, 0.01], (6, 1))), T))
    assert sum(s.within_limits for s in ik_analytic(robot, T)) >= 2  # the original is unchanged


def test_the_solver_is_kept_with_its_robot_and_goes_with_it():
    import gc
    import weakref

    table = _puma_table()
    assert closed_form.analytic_ik(table) is closed_form.analytic_ik(table)
    robot = rk.load("ur5")
    ik = closed_form.analytic_ik(robot)
    assert ik is closed_form.analytic_ik(robot) and robot.derived(("analytic_ik", None), lambda: None)[1] is ik
    refs = [weakref.ref(table), weakref.ref(robot), weakref.ref(ik)]
    del table, robot, ik
    gc.collect()
    assert all(r() is None for r in refs)  # nothing module-level keeps a robot, a table or its solver alive


@settings(max_examples=10, deadline=None, derandomize=True)
@given(st.integers(0, 2**31 - 1))
def test_any_in_place_edit_of_base_and_tool_is_followed(seed):
    """Property: after random in-place edits of a table's base and tool, every solution of the one-call
    form and of a held object reaches the table's own FK, the generating configuration among them."""
    rng = np.random.default_rng(seed)
    table = _puma_table()
    held = AnalyticIK(table)
    for _ in range(2):
        table.base[:3, :3] = matrix_from_rpy(rng.uniform(-1, 1, 3))
        table.base[:3, 3] = rng.uniform(-0.5, 0.5, 3)
        table.tool[:3, :3] = matrix_from_rpy(rng.uniform(-1, 1, 3))
        table.tool[:3, 3] = rng.uniform(-0.2, 0.2, 3)
        q = rng.uniform(-2.5, 2.5, 6)
        T = table.fk(q)
        for sols in (ik_analytic(table, T), held.solve(T)):
            assert sols and all(np.abs(table.fk(s.q) - T).max() < 1e-9 for s in sols)
            assert min(np.abs(np.angle(np.exp(1j * (s.q - q)))).max() for s in sols) < 1e-7


@settings(max_examples=12, deadline=None, derandomize=True)
@given(st.lists(st.booleans(), min_size=6, max_size=6), st.integers(0, 2**31 - 1))
def test_flipped_joints_are_solved_in_their_own_sign(flips, seed):
    """DHLink.flip (θ = θ₀ − q): every solution reaches the pose by Pinocchio's FK, the generating
    configuration is among them, limits are flagged in q, and at a wrist singularity q₄ = wrist_ref."""
    import dataclasses

    table = _puma_table()
    lim = np.array([[-2.0, 2.5], [-2.2, 1.9], [-2.4, 2.6], [-2.8, 2.7], [-1.9, 2.1], [-2.9, 2.8]])
    links = tuple(dataclasses.replace(l, flip=f, qlim=lim[i]) for i, (l, f) in enumerate(zip(table.links, flips)))
    robot = rk.load(dataclasses.replace(table, links=links))
    rng = np.random.default_rng(seed)
    q = rng.uniform(lim[:, 0] + 0.05, lim[:, 1] - 0.05)
    T = robot.frame_pose(q)
    sols = ik_analytic(robot, T)
    _reaches(robot, sols, T, q)
    for s in sols:
        assert s.within_limits == bool(np.all(s.q >= lim[:, 0] - 1e-12) and np.all(s.q <= lim[:, 1] + 1e-12))
    q[4] = 0.0  # the wrist singularity: q₄ is the documented free choice
    T = robot.frame_pose(q)
    sols = ik_analytic(robot, T, wrist_ref=0.3)
    assert all(np.abs(robot.frame_pose(s.q) - T).max() < 1e-9 for s in sols)
    assert any(s.degenerate and abs(s.q[3] - 0.3) < 1e-12 for s in sols)


class _ToyGantryFallback(ToyGantrySolver):
    method = "toy gantry"


class _Refuses(ToyGantrySolver):
    method = "never"

    def refusal(self):
        return "the toy takes no arm"


def test_a_fallback_solver_takes_arms_without_a_registered_structure(monkeypatch):
    """The hook a general 6R solver uses: FALLBACK solvers decide by refusal() whether they take an arm."""
    robot = rk.load(_gantry_table())
    monkeypatch.delitem(closed_form.SOLVERS, "spherical wrist")  # the gantry's structure has no solver now
    monkeypatch.setattr(closed_form, "FALLBACK", [_Refuses, _ToyGantryFallback])
    ik = AnalyticIK(robot)
    assert ik.method == "toy gantry" and "no solver for the spherical wrist method" in ik.reason
    q = np.array([0.1, -0.2, 0.3, 0.4, 1.1, -0.6])
    T = robot.frame_pose(q)
    _reaches(robot, ik.solve(T), T, q)
    monkeypatch.setattr(closed_form, "FALLBACK", [_Refuses])
    ik = AnalyticIK(robot)
    assert ik.method is None
    with pytest.raises(InputError, match="no closed-form inverse kinematics"):
        ik.solve(T)
    monkeypatch.setattr(closed_form, "FALLBACK", [_ToyGantryFallback])
    assert AnalyticIK(shared_robot("panda")).method is None  # 7 joints: fallbacks are for 6-joint arms only
