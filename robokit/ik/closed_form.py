r"""Every closed-form IK solution of a robot whose geometry has one (Lecture 5).

``ik_analytic_kind(robot)`` looks at the joint axes (at q = 0, in the base frame) and says
which method applies, or why none does:

* **spherical wrist** — 6 joints, the last three revolute with axes meeting in one point
  (and no two consecutive wrist axes parallel): Pieper's method (:mod:`robokit.ik.pieper`),
  any twists and lengths, revolute or prismatic joints 1–3;
* **three parallel axes** — 6 revolute joints, axes 2, 3, 4 parallel, axes 5 and 6 meeting,
  axis 1 and axis 5 not parallel to the others (UR3/UR5/UR10/UR16):
  :mod:`robokit.ik.parallel_axes`.

Both structures are also recognised counted from the tool (axes 1–3 meeting in one point;
axes 3–5 parallel with axes 1 and 2 meeting): the chain is then read backwards (its FK is
the inverse pose, joint k ↔ joint 7 − k, q′ = −q), solved for T⁻¹, and the labels say
"(chain reversed)"; at a singularity the free joint is then joint 3 (or 1) with the value
``wrist_ref``.

Other arms — 7 joints (panda), wrists whose axes do not meet, … — have no closed form here
and ``ik_analytic`` raises ``ValueError`` with the reason in the arm's terms.

The robot's DH table (``robot.dh``, or for a URDF the table :func:`robokit.urdf_to_dh`
extracts, whose FK equals the URDF's) is turned once into the canonical chain and the
solver's constants; these are cached on the robot (attribute ``_closed_form``).

Solutions: joint values q (rad, m), revolute ones wrapped to (−π, π] — or shifted by 2π
where that lands inside limits wider than ±π —, flagged ``within_limits``, labelled with
their branch: "right"/"left" (the wrist centre on the + or − side of the common normal
from axis 1 to axis 2, i.e. of frame 1's x axis), "elbow up"/"elbow down" (the sign of
``((O₃ − O₂) × (W − O₃))·z₃``, O₂, O₃ the feet of the normal between axes 2 and 3, z₃
axis 3: positive is "elbow down", as for the PUMA 560 of Corke's toolbox), "no flip"/"flip"
(the sign of ``sin θ₅ · sin α₄ · sin α₅``; positive is "no flip"), and "wrist singular" when
axes 4 and 6 (spherical wrist) or axis 6 and the parallel axes (UR) line up — then the free
angle is the documented choice ``q₄ = wrist_ref`` (spherical) or ``q₆ = wrist_ref`` (UR).
For a prismatic joint 3 the elbow part reads "d3 +"/"d3 −" (the sign of the joint's
total offset). Labels that would repeat (a general arm's quartic may give two roots on
one side) get " #2".
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING, Sequence, cast

import numpy as np
from numpy.typing import ArrayLike

from robokit.ik._dh_chain import DHChain
from robokit.ik.analytic import IKSolution
from robokit.ik.parallel_axes import ParallelAxesSolver
from robokit.ik.pieper import PieperSolver
from robokit.spatial.se3 import check_transform
from robokit.errors import InputError, InputTypeError

if TYPE_CHECKING:
    from robokit.description.dh import DHTable
    from robokit.description.robot import Robot

_Row = tuple[Sequence[float], str, bool]  # (q, label, degenerate) of one solution

__all__ = ["ClosedFormKind", "ik_analytic", "ik_analytic_kind"]

_TWO_PI = 2.0 * math.pi
_ANGLE_TOL = 1e-9  # rad: axes this close to parallel are parallel
_DIST_TOL = 1e-9  # m (scaled by the arm's size when larger than 1 m)


@dataclass(frozen=True)
class ClosedFormKind:
    """Which closed form applies to a robot.

    method : ``"spherical wrist"``, ``"three parallel axes"`` or None (no closed form);
    reason : one sentence in the arm's terms — why the method applies, or why none does.
    ``bool(kind)`` is True when a method applies.
    """

    method: str | None
    reason: str

    def __bool__(self) -> bool:
        return self.method is not None


class ClosedFormModel:
    """One robot's closed-form IK: canonical chain, method, solver constants (built once)."""

    def __init__(self, table: DHTable, qlim: ArrayLike | None = None) -> None:
        self.chain = DHChain(table, qlim)
        self.reversed = False
        self.kind, self.solver, self.solver_chain = self._method(self.chain)
        if self.kind.method is None and self.chain.n == 6:
            # the same structures counted from the tool: axes 1–3 meeting (a spherical wrist at the
            # base), or axes 3–5 parallel with axes 1 and 2 meeting — solve the inverse pose
            rc = self.chain.reversed()
            kind, solver, _ = self._method(rc)
            if kind.method is not None:
                where = {"spherical wrist": "axes 1–3 meet in one point (a spherical joint group at the base)",
                         "three parallel axes": "axes 3–5 are parallel and axes 1 and 2 meet"}[kind.method]
                self.kind = ClosedFormKind(kind.method, f"{where}: the {kind.method} method on the chain read "
                                                        f"from the tool back to the base")
                self.solver, self.solver_chain, self.reversed = solver, rc, True
        ch = self.chain
        self.rev_list = [k == "R" for k in ch.kinds]
        self.all_rev = all(self.rev_list)
        # limits with the 1e-12 tolerance of the within_limits flag folded in
        self.lim_list = None if ch.qlim is None else [(float(lo) - 1e-12, float(hi) + 1e-12) for lo, hi in ch.qlim]

    @staticmethod
    def _method(chain: DHChain) -> tuple[ClosedFormKind, PieperSolver | ParallelAxesSolver | None, DHChain]:
        """(kind, solver, chain) for one reading of the chain."""
        kind = _detect(chain)
        solver: PieperSolver | ParallelAxesSolver | None = None
        if kind.method == "spherical wrist":
            solver = PieperSolver(chain)
            if not _positions_in_3d(solver):
                kind = ClosedFormKind(None, "axes 4–6 meet in one point, but joints 1–3 cannot move the wrist "
                                            "centre in three independent directions (their axes confine it "
                                            "to a surface)")
                solver = None
        elif kind.method == "three parallel axes":
            solver = ParallelAxesSolver(chain)
        if solver is not None:
            solver.w6_list = [float(v) for v in solver.w6]
            solver.th0_all = [float(t) for t in chain.th0]
        return kind, solver, chain

    # ------------------------------------------------------------------ solving
    def solve(self, T: np.ndarray, wrist_ref: float = 0.0) -> list[IKSolution]:
        if self.solver is None:
            raise InputError(f"robot: no closed-form inverse kinematics: {self.kind.reason}")
        if self.reversed:  # solve T⁻¹ with the reversed chain; q = −q′ in reverse order
            R, p = T[:3, :3], T[:3, 3]
            Tinv = np.eye(4)
            Tinv[:3, :3] = R.T
            Tinv[:3, 3] = -R.T @ p
            T06 = self.solver_chain.target_06(Tinv)
            rows = self._rows(T06, -wrist_ref)
            rows = [(tuple(-v for v in q[::-1]), label + " (chain reversed)", degen) for q, label, degen in rows]
        else:
            rows = self._rows(self.chain.target_06(T), wrist_ref)
        return self._finish(rows)

    def _rows(self, T06: np.ndarray, wrist_ref: float) -> list[_Row]:
        if isinstance(self.solver, ParallelAxesSolver):
            return self.solver.solve(T06, wrist_ref)
        return self._pieper(T06, wrist_ref)

    def _pieper(self, T06: np.ndarray, wrist_ref: float) -> list[_Row]:
        sv = self.solver
        assert isinstance(sv, PieperSolver)  # _rows sends the parallel-axes solver elsewhere
        th0 = sv.th0_all
        (r00, r01, r02, p0), (r10, r11, r12, p1), (r20, r21, r22, p2) = T06[:3].tolist()
        w6x, w6y, w6z = sv.w6_list
        W = (r00 * w6x + r01 * w6y + r02 * w6z + p0, r10 * w6x + r11 * w6y + r12 * w6z + p1,
             r20 * w6x + r21 * w6y + r22 * w6z + p2)
        R06 = ((r00, r01, r02), (r10, r11, r12), (r20, r21, r22))
        rows: list[_Row] = []
        for q123, singular1, degen_pos in sv.position(W):
            th, _ = sv._angles(q123)
            head = self._shoulder(q123, th, W, singular1) + self._elbow(q123, th)
            for t4, t5, t6, flip, degen in sv.wrist(th, R06, wrist_ref):
                q = (q123[0], q123[1], q123[2], t4 - th0[3], t5 - th0[4], t6 - th0[5])
                rows.append((q, head + flip, degen or degen_pos or singular1))
        return rows

    def _shoulder(self, q: Sequence[float], th: Sequence[float], W: Sequence[float], singular: bool) -> str:
        if self.solver_chain.kinds[0] != "R":
            return ""
        if singular:
            return "shoulder singular, "
        x1 = math.cos(th[0]) * W[0] + math.sin(th[0]) * W[1]
        return "right, " if x1 >= 0.0 else "left, "

    def _elbow(self, q: Sequence[float], th: Sequence[float]) -> str:
        sv = self.solver
        assert isinstance(sv, PieperSolver)  # called from _pieper only
        if self.solver_chain.kinds[2] == "P":
            d = self.solver_chain.d0[2] + q[2]
            return "d3 +, " if d >= 0.0 else "d3 −, "
        c3, s3 = math.cos(th[2]), math.sin(th[2])
        e = (s3 * sv.v[0] + c3 * sv.v[1]) * (sv.a2 if sv.a2 != 0.0 else 1.0)
        return "elbow down, " if e > 0.0 else "elbow up, "

    def _finish(self, rows: list[_Row]) -> list[IKSolution]:
        """Wrap, shift into limits, flag, drop duplicates, label: rows → IKSolutions.

        Plain Python on at most a few dozen numbers (numpy's per-call overhead would dominate).
        """
        if not rows:
            return []
        rev = self.rev_list
        all_rev = self.all_rev
        lims = self.lim_list
        rem = math.remainder
        two_pi, pi = _TWO_PI, math.pi
        kept: list[list[float]] = []
        meta: list[tuple[bool, str, bool]] = []
        labels: dict[str, int] = {}
        for q, label, degen in rows:
            if all_rev:
                qq = [rem(v, two_pi) for v in q]
            else:
                qq = [(rem(v, two_pi) if r else float(v)) for v, r in zip(q, rev)]
            if -pi in qq:  # (−π, π]
                qq = [(pi if (v == -pi and r) else v) for v, r in zip(qq, rev)]
            inside = True
            if lims is not None:
                for j, (lo, hi) in enumerate(lims):
                    v = qq[j]
                    if v < lo or v > hi:
                        if rev[j] and lo <= v + two_pi <= hi:
                            qq[j] = v + two_pi  # limits wider than ±π: the shifted angle is inside
                        elif rev[j] and lo <= v - two_pi <= hi:
                            qq[j] = v - two_pi
                        else:
                            inside = False
            dup = False
            for other in kept:  # distinct solutions only (angles compared modulo 2π)
                for v, o, r in zip(qq, other, rev):
                    d = rem(v - o, two_pi) if r else v - o
                    if d >= 1e-9 or d <= -1e-9:
                        break
                else:
                    dup = True
                    break
            if dup:
                continue
            kept.append(qq)
            n = labels.get(label, 0) + 1
            labels[label] = n
            meta.append((inside, label if n == 1 else f"{label} #{n}", bool(degen)))
        Q = np.array(kept)
        return [_solution(Q[k], *meta[k]) for k in range(len(kept))]


_new = object.__new__


def _solution(q: np.ndarray, within_limits: bool, label: str, degenerate: bool) -> IKSolution:
    """An IKSolution built without the frozen dataclass's field-by-field ``__init__`` (a
    quarter of the cost of a call for 8 solutions); the same object in every respect."""
    sol = _new(IKSolution)
    sol.__dict__.update(q=q, within_limits=within_limits, label=label, degenerate=degenerate, extra={})
    return sol


# ---------------------------------------------------------------------- detection
def _positions_in_3d(sv: PieperSolver) -> bool:
    """True if joints 1–3 move the wrist centre in 3 independent directions somewhere.

    The 3×3 Jacobian of the wrist centre (central differences) is checked at a few fixed
    pseudo-random configurations; a positioning structure that is rank-deficient at all
    of them (e.g. a prismatic joint perpendicular to a revolute one in a plane) has a
    continuum of solutions, not a finite set.
    """
    rng = np.random.default_rng(12345)
    scale = sv.chain.scale
    for _ in range(4):
        q = list(rng.uniform(-2.0, 2.0, 3))
        J = np.empty((3, 3))
        h = 1e-6
        for j in range(3):
            qp, qm = list(q), list(q)
            qp[j] += h
            qm[j] -= h
            pp = sv._wrist_point(*sv._angles(qp))
            pm = sv._wrist_point(*sv._angles(qm))
            J[:, j] = [(pp[k] - pm[k]) / (2.0 * h) for k in range(3)]
        J[:, [sv.chain.kinds[j] == "R" for j in range(3)]] /= scale  # revolute columns in m/rad → unitless
        if np.linalg.svd(J, compute_uv=False)[-1] > 1e-6:
            return True
    return False


def _line_distance(p1: np.ndarray, d1: np.ndarray, p2: np.ndarray, d2: np.ndarray) -> float:
    """Distance between two lines (points p, unit directions d)."""
    c = np.cross(d1, d2)
    nc = float(np.linalg.norm(c))
    w = p2 - p1
    if nc < 1e-12:
        return float(np.linalg.norm(w - (w @ d1) * d1))
    return abs(float(w @ c)) / nc


def _angle(d1: np.ndarray, d2: np.ndarray) -> float:
    """Angle between two axis lines, in [0, π/2] (direction signs ignored)."""
    return math.atan2(float(np.linalg.norm(np.cross(d1, d2))), abs(float(d1 @ d2)))


def _meeting_point(lines: Sequence[tuple[np.ndarray, np.ndarray]]) -> tuple[np.ndarray, float]:
    """Least-squares point of several lines and its largest distance to them."""
    A = np.zeros((3, 3))
    b = np.zeros(3)
    for p, d in lines:
        P = np.eye(3) - np.outer(d, d)
        A += P
        b += P @ p
    x = np.linalg.lstsq(A, b, rcond=None)[0]
    dist = max(float(np.linalg.norm((np.eye(3) - np.outer(d, d)) @ (x - p))) for p, d in lines)
    return x, dist


def _fmt_len(x: float) -> str:
    return f"{x:.3g} m"


def _detect(chain: DHChain) -> ClosedFormKind:
    n = chain.n
    if n != 6:
        return ClosedFormKind(None, f"the arm has {n} joints; the closed forms here need exactly 6 "
                                    f"(use solve_ik)")
    axes = chain.axes()
    tol = _DIST_TOL * max(1.0, chain.scale)
    kinds = chain.kinds
    # 1. spherical wrist: axes 4, 5, 6 revolute and meeting in one point
    wrist_reason = None
    if any(k != "R" for k in kinds[3:]):
        j = 4 + [k for k in kinds[3:]].index("P")
        wrist_reason = f"joint {j} is prismatic, so there is no spherical wrist"
    else:
        a45, a56 = _angle(axes[3][1], axes[4][1]), _angle(axes[4][1], axes[5][1])
        _, dist = _meeting_point(axes[3:6])
        if dist > tol:
            wrist_reason = f"axes 4–6 do not intersect: closest distance {_fmt_len(dist)}"
        elif a45 < _ANGLE_TOL or a56 < _ANGLE_TOL:
            pair = "4 and 5" if a45 < _ANGLE_TOL else "5 and 6"
            wrist_reason = f"axes {pair} coincide, so the wrist has fewer than three independent axes"
    if wrist_reason is None:
        a12 = _angle(axes[0][1], axes[1][1])
        d12 = _line_distance(axes[0][0], axes[0][1], axes[1][0], axes[1][1])
        if kinds[0] == "R" and kinds[1] == "R" and a12 < _ANGLE_TOL and d12 <= tol:
            return ClosedFormKind(None, "axes 1 and 2 coincide: the wrist centre's position is not determined")
        if kinds[0] == "P" and kinds[1] == "P" and a12 < _ANGLE_TOL:
            return ClosedFormKind(None, "joints 1 and 2 are parallel prismatic joints: the wrist centre's "
                                        "position is not determined")
        types = "".join(kinds[:3])
        return ClosedFormKind("spherical wrist", f"axes 4–6 meet in one point (spherical wrist); "
                                                 f"Pieper's method with {types} positioning joints")
    # 2. three consecutive parallel axes 2–4, axes 5 and 6 meeting
    if any(k != "R" for k in kinds):
        return ClosedFormKind(None, wrist_reason + "; and not all joints are revolute (needed for the "
                                                   "parallel-axes method)")
    a23, a34 = _angle(axes[1][1], axes[2][1]), _angle(axes[2][1], axes[3][1])
    if a23 > _ANGLE_TOL or a34 > _ANGLE_TOL:
        worst = max(a23, a34)
        return ClosedFormKind(None, wrist_reason + f"; and axes 2–4 are not parallel (they differ by "
                                                   f"{math.degrees(worst):.3g}°)")
    d56 = _line_distance(axes[4][0], axes[4][1], axes[5][0], axes[5][1])
    if d56 > tol:
        return ClosedFormKind(None, wrist_reason + f"; axes 2–4 are parallel but axes 5 and 6 do not intersect "
                                                   f"(distance {_fmt_len(d56)})")
    if _angle(axes[4][1], axes[5][1]) < _ANGLE_TOL:
        return ClosedFormKind(None, wrist_reason + "; axes 2–4 are parallel but axes 5 and 6 coincide")
    if _angle(axes[0][1], axes[1][1]) < _ANGLE_TOL:
        return ClosedFormKind(None, wrist_reason + "; axis 1 is parallel to axes 2–4")
    if _angle(axes[4][1], axes[1][1]) < _ANGLE_TOL:
        return ClosedFormKind(None, wrist_reason + "; axis 5 is parallel to axes 2–4")
    for i in (1, 2):
        if _line_distance(axes[i][0], axes[i][1], axes[i + 1][0], axes[i + 1][1]) <= tol:
            return ClosedFormKind(None, wrist_reason + f"; axes {i + 1} and {i + 2} coincide")
    return ClosedFormKind("three parallel axes", "axes 2–4 are parallel and axes 5 and 6 meet "
                                                  "(UR-type arm): θ₁, θ₅, θ₆ then a planar 3R arm")


# ---------------------------------------------------------------------- public API
def _model(robot: Robot | DHTable) -> ClosedFormModel:
    """The cached ClosedFormModel of a Robot or a DH table (built on first use)."""
    cached = getattr(robot, "_closed_form", None)
    if isinstance(cached, ClosedFormModel):
        return cached
    if hasattr(robot, "links") and hasattr(robot, "convention"):  # a DH table
        model = ClosedFormModel(cast("DHTable", robot))
    elif hasattr(robot, "model") and hasattr(robot, "qlim"):
        table = getattr(robot, "dh", None)
        if table is None:
            from robokit.description.urdf_to_dh import urdf_to_dh

            res = urdf_to_dh(robot, "standard")
            table = res.table
        qlim = np.asarray(robot.qlim, dtype=float)
        model = ClosedFormModel(table, qlim)
        if robot.dh is None and not res.exact:
            model.kind = ClosedFormKind(None, f"the DH table extracted from {robot.name} reproduces its forward "
                                              f"kinematics only to {res.residual:.2e} (> 1e-9)")
            model.solver = None
    else:
        raise InputTypeError(f"robot: expected a robokit Robot (robokit.load) or a DHTable, got {type(robot).__name__}")
    try:
        object.__setattr__(robot, "_closed_form", model)
    except (AttributeError, TypeError):  # pragma: no cover - objects without a __dict__
        pass
    return model


def ik_analytic_kind(robot: Robot | DHTable) -> ClosedFormKind:
    """Which closed-form IK applies to ``robot``, decided from its joint axes.

    Parameters
    ----------
    robot : :class:`robokit.Robot` (from a DH file or a URDF) or a :class:`robokit.DHTable`.

    Returns
    -------
    ClosedFormKind
        ``.method`` is ``"spherical wrist"`` (Pieper), ``"three parallel axes"`` (UR family)
        or None; ``.reason`` says why, in the arm's terms (e.g. ``"axes 4–6 do not
        intersect: closest distance 0.0946 m; …"``).

    Notes
    -----
    The axes are the joint axes at q = 0 (lines in the base frame, from the DH table).
    Distances below 1e-9 m (times the arm's size in m when larger than 1) count as zero,
    angles below 1e-9 rad as parallel.

    Examples
    --------
    >>> import robokit
    >>> ik_analytic_kind(robokit.load("puma560")).method
    'spherical wrist'
    """
    return _model(robot).kind


def ik_analytic(robot: Robot | DHTable, T: ArrayLike, wrist_ref: float = 0.0) -> list[IKSolution]:
    r"""Every closed-form IK solution of ``robot`` for the tip pose ``T``.

    Parameters
    ----------
    robot : :class:`robokit.Robot` or :class:`robokit.DHTable`
        A 6-joint arm with a spherical wrist (Pieper) or three consecutive parallel axes
        whose last two axes meet (UR family); see :func:`ik_analytic_kind`.
    T : (4, 4) array
        Target pose of the tip (``robot.frame_pose``'s frame; for a DH table the tool) in
        the base frame (m).
    wrist_ref : float
        At a wrist singularity, the value given to the free joint (q₄ for a spherical wrist,
        q₆ for the parallel-axes arms; rad). Default 0.

    Returns
    -------
    list of :class:`IKSolution`
        Distinct solutions (8 for a PUMA 560 or a UR in general position, up to 8 — 4
        positions × 2 wrists — for any spherical-wrist arm); each ``.q`` (6,) in rad/m,
        revolute joints wrapped to (−π, π] (or shifted by 2π into wider limits),
        ``.within_limits``, ``.label`` (branch, see the module docstring), ``.degenerate``
        (a singular choice was made). ``[]`` when T is out of reach.

    Raises
    ------
    ValueError
        If the robot has no closed form (the reason is in the message) or T is not a rigid
        transform.

    Notes
    -----
    Lecture 5: Pieper's wrist-centre decoupling (θ₁–θ₃ from a polynomial in tan(θ₃/2) of
    degree 2 or 4, the wrist from Euler-type angles), or for the UR family θ₁, θ₅, θ₆ from
    ``a cos θ + b sin θ = c`` and θ₂–θ₄ from a planar arm.

    Examples
    --------
    >>> import numpy as np, robokit
    >>> robot = robokit.load("puma560")
    >>> T = robot.frame_pose(np.array([0.1, -0.5, 0.3, 0.4, 0.6, -0.2]))
    >>> len(ik_analytic(robot, T))
    8
    """
    model = _model(robot)
    return model.solve(_check_pose(T), float(wrist_ref))


def _check_pose(T: ArrayLike) -> np.ndarray:
    """T as a float 4×4 rigid transform: a quick test for a clean float array (RᵀR = I to 1e-9,
    det R > 0, last row exact), else the full :func:`check_transform` (which raises)."""
    if type(T) is np.ndarray and T.dtype == np.float64 and T.shape == (4, 4):
        (a, b, c, _), (d, e, f, _), (g, h, i, _), last = T.tolist()
        dev = max(abs(a * a + d * d + g * g - 1.0), abs(b * b + e * e + h * h - 1.0), abs(c * c + f * f + i * i - 1.0),
                  abs(a * b + d * e + g * h), abs(a * c + d * f + g * i), abs(b * c + e * f + h * i))
        det = a * (e * i - f * h) - b * (d * i - f * g) + c * (d * h - e * g)
        finite = math.isfinite(a + b + c + d + e + f + g + h + i + T[0, 3] + T[1, 3] + T[2, 3])
        if finite and dev < 1e-9 and det > 0.0 and last == [0.0, 0.0, 0.0, 1.0]:
            return T
    return check_transform(T, "T")
