r"""Every closed-form IK solution of a robot whose geometry has one (Lecture 5).

``ik_analytic_kind(robot)`` looks at the joint axes (at q = 0, in the base frame) and says
which method applies, or why none does:

* **spherical wrist** — 6 joints, the last three revolute with axes meeting in one point
  (and no two consecutive wrist axes parallel): Pieper's method (:mod:`robokit.ik.pieper`),
  any twists and lengths, revolute or prismatic joints 1–3;
* **three parallel axes** — 6 revolute joints, axes 2, 3, 4 parallel, axes 5 and 6 meeting,
  axis 1 and axis 5 not parallel to the others (UR3/UR5/UR10/UR16):
  :mod:`robokit.ik.parallel_axes`;
* **general 6R** — any other arm of 6 revolute joints (an offset wrist such as the Kinova
  Jaco's, axes that miss by a millimetre): :mod:`robokit.ik.general_6r`, up to 16
  solutions labelled ``"solution k of m"``. The special methods stay first (they are faster);
* **planar** — 1 to 3 revolute joints whose axes are parallel (consecutive axes apart), or one
  prismatic joint: :mod:`robokit.ik.planar_solver` (Lecture 5's planar arms in any plane; a
  pose off the arm's plane is out of reach).

Both structures are also recognised counted from the tool (axes 1–3 meeting in one point;
axes 3–5 parallel with axes 1 and 2 meeting): the chain is then read backwards (its FK is
the inverse pose, joint k ↔ joint 7 − k, q′ = −q), solved for T⁻¹, and the labels say
"(chain reversed)"; at a singularity the free joint is then joint 3 (or 1) with the value
``wrist_ref``.

Other arms — 7 joints (panda), 4 or 5, non-planar arms of 2 or 3, a prismatic joint without
the special structures, axes dependent everywhere — have no closed form here and ``ik_analytic`` raises
``ValueError`` with the reason in the arm's terms.

The robot's DH table (``robot.dh``, or for a URDF the table :func:`robokit.dh_from_urdf`
extracts, whose FK equals the URDF's) is turned once into the canonical chain and the
solver's constants, owned by an :class:`AnalyticIK` object (hold one, or let
:func:`ik_analytic` keep one per robot while the robot lives). The object checks on every
solve whether what it was built from changed (``robot.dh``/``robot.qlim`` replaced, a table's
``base``/``tool``/limits edited in place) and rebuilds itself if so. The solvers implement
one interface, :class:`robokit.ik.solver.ClosedFormSolver` (position sub-problem, wrist
sub-problem, joint angles); ``SOLVERS`` maps each detected structure's method name to its
solver class, and ``FALLBACK`` lists solvers tried, in order, for a 6-joint arm with none of
these structures (the first whose ``refusal()`` is None takes it).

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
import warnings
import weakref
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any, Callable, Sequence, cast

import numpy as np
from numpy.typing import ArrayLike

from robokit._arrays import as_scalar
from robokit._units import TURN, check_radians
from robokit.errors import InputError, InputTypeError, RobokitWarning
from robokit.ik._dh_chain import DHChain
from robokit.ik.parallel_axes import ParallelAxesSolver
from robokit.ik.pieper import ELBOW_LABELS, SHOULDER_LABELS, WRIST_LABELS, PieperSolver
from robokit.ik.planar_solver import PlanarSolver
from robokit.ik.solution import (CollisionChecker, IKSolution, _solutions_from_kernel, check_pose,
                                 solutions_from_rows, with_collision_flags)
from robokit.description.spec import RobotSpec
from robokit.ik.solver import ClosedFormSolver

_new_object = object.__new__

if TYPE_CHECKING:
    from robokit.description.dh import DHTable
    from robokit.description.robot import Robot
    from robokit.ik.calibrated import CalibratedArm

__all__ = ["AnalyticIK", "ClosedFormKind", "analytic_ik", "ik_analytic", "ik_analytic_batch", "ik_analytic_kind"]

_ANGLE_TOL = 1e-9  # rad: axes this close to parallel are parallel
#: ``AnalyticIK(table, _EXACT_ONLY)``: the exact closed forms only (the projected arm of a calibrated one).
_EXACT_ONLY: Any = object()
_DIST_TOL = 1e-9  # m (scaled by the arm's size when larger than 1 m)
#: An exactly special arm whose DH table's offsets sum to more than this many times the arm's size
#: (two consecutive axes nearly but not exactly parallel: their common normal is far away, and the
#: offsets are kilometres of opposite signs) is solved as a nearly special arm instead (the
#: projected arm's closed form, those axes made parallel, then Newton on the arm: robokit.ik.calibrated):
#: the special closed form's arithmetic cancels those offsets. MuJoCo Menagerie's UFACTORY Lite 6 (right
#: angles written to 6 digits: axes 2 and 3 7.3e-6 rad apart, offsets 27 km, 6.6e4 × its size) lost
#: roots at 4 of 15 poses within 1e-3 rad of its elbow singularity, the generating configuration at 6
#: (its roots of degree 2 cancel d₂² ≈ 7e8 m²); solved so, none. At 100 × the cancellation costs about
#: 1e-12 of the arm's size.
ILL_DH = 100.0


@dataclass(frozen=True)
class ClosedFormKind:
    """Which closed form applies to a robot (what :func:`ik_analytic_kind` returns).

    ``bool(kind)`` is True when a method applies.

    Attributes
    ----------
    method : str or None
        ``"spherical wrist"``, ``"three parallel axes"``, ``"planar"``, ``"general 6R"`` or None (no closed form).
    reason : str
        One sentence in the arm's terms: why the method applies, or why none does.

    Examples
    --------
    >>> kind = ik_analytic_kind(rk.load("puma560"))
    >>> kind.method, bool(kind)
    ('spherical wrist', True)
    >>> bool(ik_analytic_kind(rk.load("panda")))
    False
    """

    method: str | None
    reason: str

    def __bool__(self) -> bool:
        return self.method is not None


#: The solver class of each method :func:`_detect` can report (see :mod:`robokit.ik.solver`
#: for the interface a new one implements).
SOLVERS: dict[str, Callable[[DHChain], ClosedFormSolver]] = {
    "spherical wrist": PieperSolver,
    "three parallel axes": ParallelAxesSolver,
    "planar": PlanarSolver,
}
#: ik_analytic_kind's reason for a planar arm, by its number of joints (0: one prismatic joint).
_PLANAR_REASONS = {0: "one prismatic joint: its value from the tool's position along the axis (planar method)",
                   1: "one revolute joint: its angle from the tool's turn about the axis (planar method)",
                   2: "axes 1 and 2 are parallel: a planar 2R arm (Lecture 5), one solution per tool pose",
                   3: "axes 1–3 are parallel: a planar 3R arm (Lecture 5), elbow up and down"}


#: Solvers tried, in order, for a 6-joint chain with none of the structures above (read either
#: way): the first whose ``refusal()`` is None solves it. A general 6R solver registers here.
def _general_six_r(chain: DHChain) -> ClosedFormSolver:
    """:class:`robokit.ik.general_6r.GeneralSixR` of the chain; imported here, on the first arm that
    needs it, because it loads its compiled kernels (numba) when imported."""
    from robokit.ik.general_6r import GeneralSixR

    return GeneralSixR(chain)


FALLBACK: list[Callable[[DHChain], ClosedFormSolver]] = [_general_six_r]


def _is_table(robot: object) -> bool:
    return hasattr(robot, "links") and hasattr(robot, "convention")


def _is_robot(robot: object) -> bool:
    return hasattr(robot, "model") and hasattr(robot, "qlim")


def _table_key(table: DHTable, link_limits: bool) -> tuple:
    """What the closed form of ``table`` depends on, as ids and bytes (cheap to compare)."""
    key: tuple = (id(table.links), table.convention, np.asarray(table.base, dtype=float).tobytes(),
                  np.asarray(table.tool, dtype=float).tobytes())
    if link_limits:
        key += tuple(None if l.qlim is None else np.asarray(l.qlim, dtype=float).tobytes() for l in table.links)
    return key


_F64 = np.dtype(np.float64)
_SHAPE44 = (4, 4)
_OUT_SHAPE = (16, 9)  # (MAX_ROWS, OUT_COLS) of robokit.kernels.closed_form (checked when the kernel is first packed)
_CAL_FLAGGED = 1000  # robokit.kernels.calibrated_ik.FLAGGED, without importing it here (a test checks they agree)


def _fast_key(table: DHTable, link_limits: bool = True) -> tuple:
    """The bytes of a table's arrays that can be edited in place (base, tool, and with
    ``link_limits`` the links' limits)."""
    base, tool = table.base, table.tool
    key: tuple = (base.tobytes() if type(base) is np.ndarray else np.asarray(base, dtype=float).tobytes(),
                  tool.tobytes() if type(tool) is np.ndarray else np.asarray(tool, dtype=float).tobytes())
    if not link_limits:
        return key
    return key + tuple(None if l.qlim is None else np.asarray(l.qlim, dtype=float).tobytes() for l in table.links)


def _sources(robot: Robot | DHTable) -> tuple[tuple, tuple]:
    """(key, objects): the key changes when anything the closed form was built from changes —
    a replaced ``robot.dh``/``robot.qlim``/``table.links``, or ``base``/``tool``/limits
    edited in place; ``objects`` are held so that the ids in the key stay unique (never the
    robot itself: the per-robot cache must not keep it alive)."""
    if _is_table(robot):
        table = cast("DHTable", robot)
        return _table_key(table, True), (table.links,)
    rob = cast("Robot", robot)
    dh, qlim = rob.dh, rob.qlim
    key: tuple = (id(dh), id(rob.model), np.asarray(qlim, dtype=float).tobytes())
    if dh is not None:
        key += _table_key(dh, False)
    return key, (dh, rob.model, qlim, None if dh is None else dh.links)


def _wrist_ref(wrist_ref: object) -> float:
    """The checked ``wrist_ref`` (rad): a real number, warned of when it looks like degrees."""
    ref = as_scalar(wrist_ref, "wrist_ref")
    check_radians(ref, -TURN, TURN, "wrist_ref")
    return ref


#: What ``ik_analytic`` says when a calibrated arm's pose within reach has no solution from either method.
_EMPTY_WITHIN_REACH = ("ik_analytic: no solution at this pose, which lies within the arm's reach: neither the "
                       "nominal structure's closed form nor the general 6R method gives one. At a singular "
                       "configuration of the nominal structure (a wrist singularity: its solutions form a "
                       "continuum) both can miss a pose this arm reaches; robokit.solve_ik from several starts "
                       "can find it")


class AnalyticIK:
    r"""The closed-form inverse kinematics of one robot, as an object to hold and reuse.

    Built once from the robot's DH table (``robot.dh``, or for a URDF the table
    :func:`robokit.dh_from_urdf` extracts): the canonical chain, the method (see
    :func:`ik_analytic_kind` and the module docstring) and the solver's constants. The object
    owns them: when what they were built from changes — ``robot.dh`` or ``robot.qlim``
    replaced, a table's ``base``/``tool`` or limits edited in place — the next :meth:`solve`
    rebuilds them first, so an answer never comes from stale constants.

    Parameters
    ----------
    robot : :class:`robokit.Robot` or :class:`robokit.DHTable`
        Any robot; one without a closed form gives an object whose ``kind.method`` is None
        and whose ``reason`` says why (its :meth:`solve` raises).

    Attributes
    ----------
    kind : ClosedFormKind
        ``.method`` (``"spherical wrist"``, ``"three parallel axes"`` or None) and ``.reason``.
    solver : ClosedFormSolver or None
        The solver object (:mod:`robokit.ik.solver`) for the chain it solves.
    reversed : bool
        True when the structure is found counted from the tool (the chain is read backwards).

    Examples
    --------
    >>> import numpy as np, robokit
    >>> ik = AnalyticIK(robokit.load("puma560"))
    >>> ik.kind.method
    'spherical wrist'
    >>> T = robokit.load("puma560").frame_pose(np.array([0.1, -0.5, 0.3, 0.4, 0.6, -0.2]))
    >>> len(ik.solve(T))
    8
    >>> AnalyticIK(robokit.load("panda")).reason
    'the arm has 7 joints; the closed forms here need exactly 6, or a planar arm of 1–3 joints (use solve_ik)'
    """

    kind: ClosedFormKind
    solver: ClosedFormSolver | None
    reversed: bool
    #: The exact IK of a calibrated or nearly special arm (:mod:`robokit.ik.calibrated`), else None.
    calibrated: CalibratedArm | None = None
    #: Use the packed kernel (:mod:`robokit.kernels.closed_form`: solve and post-process in one
    #: call) when it covers the chain; False runs the solver's ``joint_angles`` (the same kernel's
    #: rows for Pieper and UR) and the Python post-processing (``solutions_from_rows``).
    use_kernel: bool = True

    def __init__(self, robot: Robot | DHTable, nominal: Any = None) -> None:
        if not (_is_table(robot) or _is_robot(robot)):
            raise InputTypeError(f"robot: expected a robokit Robot (robokit.load) or a DHTable, got {type(robot).__name__}")
        self._strong: Robot | DHTable | None = robot
        self._weak: weakref.ref | None = None
        self._nominal = nominal
        self._nominal_arg = nominal  # as given (the per-robot cache compares it)
        # False for the projected arm of a calibrated one (its own closed form only, no recursion)
        # and for nominal=False (the arm as it is: no nominal structure named, recorded or detected)
        self._try_calibrated = nominal is not _EXACT_ONLY and nominal is not False
        if not self._try_calibrated:
            self._nominal = None
        self._build()

    @classmethod
    def _shared(cls, robot: Robot | DHTable, nominal: Any = None) -> AnalyticIK:
        """An AnalyticIK that refers to ``robot`` only weakly (for the per-robot cache: it must
        not keep its robot alive). Raises TypeError if ``robot`` has no weak references."""
        ik = cls(robot, nominal)
        ik._weak, ik._strong = weakref.ref(robot), None
        return ik

    @property
    def _robot(self) -> Robot | DHTable:
        robot = self._strong if self._weak is None else self._weak()
        if robot is None:  # pragma: no cover - the cache drops an entry with its robot
            raise ReferenceError("the robot of this AnalyticIK no longer exists")
        return robot

    @property
    def method(self) -> str | None:
        """The closed form's name (``kind.method``), None without one."""
        return self.kind.method

    @property
    def reason(self) -> str:
        """Why the method applies, or why no closed form does (``kind.reason``)."""
        return self.kind.reason

    def __bool__(self) -> bool:
        return self.kind.method is not None

    def __repr__(self) -> str:
        name = getattr(self._robot, "name", type(self._robot).__name__)
        return f"AnalyticIK({name!r}, method={self.kind.method!r})"

    _watch: tuple | None = None

    def _build(self) -> None:
        robot = self._robot
        self._key, self._held = _sources(robot)
        src: Any = robot
        if _is_table(src):
            self._watch = (True, src.links, _fast_key(src))
        else:
            dh = src.dh
            self._watch = (False, dh, None if dh is None else _fast_key(dh, False), src.model, src.qlim,
                           np.asarray(src.qlim, dtype=float).tobytes(), None if dh is None else dh.links)
        override: ClosedFormKind | None = None
        qlim: np.ndarray | None = None
        if _is_table(robot):
            table = cast("DHTable", robot)
        else:
            rob = cast("Robot", robot)
            if rob.dh is not None:
                table = rob.dh
            else:
                from robokit.description.urdf_to_dh import dh_from_urdf

                res = dh_from_urdf(rob, "standard")
                table = res.table
                if not res.exact:
                    override = ClosedFormKind(None, f"the DH table extracted from {rob.name} reproduces its forward "
                                                    f"kinematics only to {res.residual:.2e} (> 1e-9)")
            qlim = np.asarray(rob.qlim, dtype=float)
        links = list(table.links)
        if qlim is None and all(getattr(l, "qlim", None) is not None for l in links):
            qlim = np.array([l.qlim for l in links], dtype=float)
        # a flipped joint (θ = θ₀ − q, DHLink.flip) is solved as the unflipped joint of q′ = −q
        flip = [bool(getattr(l, "flip", False)) for l in links]
        self._flip = flip if any(flip) else None
        qlim_chain = qlim
        if qlim is not None and self._flip is not None:
            qlim_chain = np.array([(-hi, -lo) if f else (lo, hi) for (lo, hi), f in zip(qlim, flip)])
        self.chain = DHChain(table, qlim_chain)
        self.reversed = False
        self.kind, self.solver = _method(self.chain)
        if self.kind.method is None and self.chain.n == 6:
            # the same structures counted from the tool: axes 1–3 meeting (a spherical wrist at the
            # base), or axes 3–5 parallel with axes 1 and 2 meeting — solve the inverse pose
            kind, solver = _method(self.chain.reversed())
            if kind.method is not None:
                where = {"spherical wrist": "axes 1–3 meet in one point (a spherical joint group at the base)",
                         "three parallel axes": "axes 3–5 are parallel and axes 1 and 2 meet"}.get(
                             kind.method, "the structure is found counted from the tool")
                self.kind = ClosedFormKind(kind.method, f"{where}: the {kind.method} method on the chain read "
                                                        f"from the tool back to the base")
                self.solver, self.reversed = solver, True
        self._revolute = [k == "R" for k in self.chain.kinds]
        # limits (of q, not q′) with the 1e-12 tolerance of the within_limits flag folded in
        self._limits = None if qlim is None else [(float(lo) - 1e-12, float(hi) + 1e-12) for lo, hi in qlim]
        self.calibrated = None
        exact: tuple[tuple[ClosedFormKind, Any], bool] | None = None
        if (self.kind.method in ("spherical wrist", "three parallel axes") and self.chain.n == 6
                and self._try_calibrated and self.chain.dh_length > ILL_DH * self.chain.scale):
            # an exactly special arm with a DH table too ill-conditioned for its closed form (ILL_DH):
            # the calibrated path below, which solves the projected arm (nearly parallel axes made
            # parallel) and polishes on the arm; the exact method stays if that path does not apply
            exact = (self.kind, self.solver), self.reversed
            self.kind = ClosedFormKind(None, (
                f"{self.kind.reason}, but the DH table's offsets sum to {self.chain.dh_length:.3g} m, "
                f"{self.chain.dh_length / self.chain.scale:.2g} × the arm's size (two axes nearly but not "
                f"exactly parallel), too large for its closed form's arithmetic"))
            self.solver, self.reversed = None, False
        if self.kind.method is None and self.chain.n == 6 and self._try_calibrated:
            # a calibrated or nearly special arm: the nominal structure's closed form, then Newton on
            # the arm's own kinematics (robokit.ik.calibrated); its PoE, not the DH table, is solved
            from robokit.ik.calibrated import calibrated_arm

            is_table = _is_table(robot)
            cal, why = calibrated_arm(robot, self.chain if is_table else None, self._flip if is_table else None,
                                      self._revolute, self._limits, self._nominal,
                                      lambda arm: AnalyticIK(arm, _EXACT_ONLY))
            if cal is not None:
                reason = cal.reason if exact is None else f"{self.kind.reason}: {cal.reason}"
                self.kind, self.calibrated, override = ClosedFormKind(cal.method, reason), cal, None
            elif self._nominal is not None:
                raise InputError(f"nominal: {why}")
            elif exact is not None:
                (self.kind, self.solver), self.reversed = exact
        if self.kind.method is None and self.chain.n == 6:
            # solvers for arms with no special structure (e.g. a general 6R elimination): each
            # says by refusal() whether it takes the chain; the first that does solves it
            reasons: list[str] = []
            for make in FALLBACK:
                solver = make(self.chain)
                why_not = solver.refusal()
                if why_not is None:
                    said = f"{self.kind.reason}; the {solver.method} method solves it"
                    run = getattr(solver, "parallel_run", None)
                    if run is not None:
                        # exactly special geometry makes the eigenproblem degenerate: the solver eliminates
                        # on the arm with the run turned and polishes on the arm (general_6r.PARALLEL_TURN)
                        said += (f"; axes {run + 1}–{run + 3} are exactly parallel, which makes its eigenproblem "
                                 f"degenerate, so it eliminates on the arm with them turned by "
                                 f"{_general_turn():g} rad and polishes every root on the arm itself")
                    self.kind = ClosedFormKind(solver.method, said)
                    self.solver = solver
                    break
                reasons.append(why_not)
            else:
                if reasons:
                    self.kind = ClosedFormKind(None, f"{self.kind.reason}; {'; '.join(reasons)}")
        if override is not None:
            self.kind, self.solver = override, None
        # a general 6R arm whose DH table's offsets are kilometres (ILL_DH): the table reproduces the arm
        # only to ~1e-11 m, so each solution is finished on the robot's own kinematics (general_6r.ArmPolish)
        self._arm_polish: Any = None
        if (self.kind.method == "general 6R" and self.solver is not None and not _is_table(robot)
                and self.chain.dh_length > ILL_DH * self.chain.scale):
            from robokit.ik.general_6r import ArmPolish

            poe = cast("Robot", robot).poe
            self._arm_polish = ArmPolish(poe.M, poe.Slist, self._revolute)
            self.kind = ClosedFormKind(self.kind.method, (
                f"{self.kind.reason}; its DH table's offsets sum to {self.chain.dh_length:.3g} m, "
                f"{self.chain.dh_length / self.chain.scale:.2g} × the arm's size, so every solution is finished "
                f"by Newton's method on the arm's own kinematics"))
        # the joint a singular pose leaves free (wrist_ref's joint), in the order of self.chain
        free = {"spherical wrist": 3, "three parallel axes": 5, "planar": 0}.get(self.kind.method or "")
        self._free_flipped = (free is not None and self._flip is not None
                              and self._flip[5 - free if self.reversed else free])
        self._ref_sign = (-1.0 if self._free_flipped else 1.0) * (-1.0 if self.reversed else 1.0)
        self._kernel = self._kernel_args()
        self._into: Any = None  # kernel[4]'s entry point (solve_into_entry), found on a solve

    def _kernel_args(self) -> tuple | None:
        """The compiled path's arguments (:mod:`robokit.kernels.closed_form`), or None when the
        solver has no kernel for this chain (then the Python solver answers)."""
        solver = self.solver
        consts = getattr(solver, "kernel_constants", None)
        if solver is None or consts is None or self.chain.n != 6:
            return None
        packed = consts()
        if packed is None:
            return None
        from robokit.kernels import closed_form as _kcf  # numba: imported with the first compiled solve

        ci, cf, C = packed
        ci = ci.copy()
        ci[5] = int(self.reversed)
        chain = solver.chain  # the reversed chain when self.reversed
        pre = np.eye(4) if chain.base_inv is None else np.ascontiguousarray(chain.base_inv, dtype=float)
        post = np.eye(4) if chain.tool_inv is None else np.ascontiguousarray(chain.tool_inv, dtype=float)
        post_q = np.zeros((5, 6))
        sign = -1.0 if self.reversed else 1.0
        post_q[0] = [(-sign if (self._flip is not None and self._flip[j]) else sign) for j in range(6)]
        post_q[1] = [1.0 if r else 0.0 for r in self._revolute]
        if self._limits is not None:
            post_q[2] = [lo for lo, _ in self._limits]
            post_q[3] = [hi for _, hi in self._limits]
            post_q[4, 0] = 1.0
        else:
            post_q[2], post_q[3] = -np.inf, np.inf
        suffix = " (chain reversed)" if self.reversed else ""
        labels = {}
        for s, shoulder in enumerate(_SHOULDER):
            for e, elbow in enumerate(_ELBOW):
                for w, wrist in enumerate(_WRIST):
                    labels[float(100 * s + 10 * e + w)] = shoulder + elbow + wrist + suffix
        pieper = int(ci[0]) == _kcf.PIEPER
        assert (_kcf.MAX_ROWS, _kcf.OUT_COLS) == _OUT_SHAPE  # the output array solve() allocates
        return (_kcf.pack_constants(ci, cf, C, pre, post, post_q), labels,
                _kcf.pieper_solve if pieper else _kcf.parallel_axes_solve,
                _kcf.pieper_batch if pieper else _kcf.parallel_axes_batch,
                _kcf.pieper_solve_into if pieper else _kcf.parallel_axes_solve_into,
                (_kcf.MAX_ROWS, _kcf.OUT_COLS), _kcf.solve_into_entry)

    def _kernel_ref(self, wrist_ref: float) -> float:
        """wrist_ref in the sign of the solver's chain (flipped free joint, reversed chain)."""
        if self._free_flipped:
            wrist_ref = -wrist_ref
        return -wrist_ref if self.reversed else wrist_ref

    def _refresh(self) -> None:
        """Rebuild the constants if what they were built from has changed."""
        if _sources(self._robot)[0] != self._key:
            self._build()

    def _unchanged(self) -> bool:
        """True when nothing the constants were built from has changed: the same objects (ids)
        and the same bytes of the arrays that can be edited in place — the cheap test of
        :meth:`_refresh` on every solve (a few hundred ns: one ``tobytes`` per array)."""
        robot: Any = self._strong if self._weak is None else self._weak()
        watch = self._watch
        if watch is None or robot is None:
            return False
        if watch[0]:  # a DH table: its links, and base/tool/limits edited in place
            return robot.links is watch[1] and watch[2] == _fast_key(robot)
        dh = robot.dh
        if dh is not watch[1] or robot.model is not watch[3] or robot.qlim is not watch[4]:
            return False
        qlim = watch[4]
        if (qlim.tobytes() if type(qlim) is np.ndarray else np.asarray(qlim, dtype=float).tobytes()) != watch[5]:
            return False
        if dh is None:
            return True
        if dh.links is not watch[6]:
            return False
        base, tool, key = dh.base, dh.tool, watch[2]
        if type(base) is np.ndarray and type(tool) is np.ndarray:  # _fast_key(dh, False), inline
            return base.tobytes() == key[0] and tool.tobytes() == key[1]
        return key == _fast_key(dh, False)

    def solve(self, T: ArrayLike, wrist_ref: float = 0.0) -> list[IKSolution]:
        """Every closed-form solution for the tip pose ``T`` — the list :func:`ik_analytic` returns.

        Parameters
        ----------
        T : (4, 4) array_like
            Target pose of the tip in the base frame (m).
        wrist_ref : float
            The free joint's value at a wrist singularity (rad); default 0.

        Returns
        -------
        list of IKSolution
            See :func:`ik_analytic`; ``[]`` when T is out of reach.

        Raises
        ------
        InputError
            If the robot has no closed form (``reason`` is in the message) or T is not a rigid
            transform.

        Examples
        --------
        >>> robot = rk.load("puma560")
        >>> q = np.array([0.1, 0.2, 0.3, 0.4, 0.5, 0.6])
        >>> sols = analytic_ik(robot).solve(robot.frame_pose(q))
        >>> len(sols), any(np.allclose(s.q, q) for s in sols)
        (8, True)
        """
        if not self._unchanged():
            self._build()
        if not (type(wrist_ref) is float and -TURN <= wrist_ref <= TURN):
            wrist_ref = _wrist_ref(wrist_ref)
        if self.calibrated is not None:  # called from this frame, as ik_analytic's _solve does: the
            # calibrated solver's warnings count their stacklevel from here
            if type(T) is not np.ndarray or T.dtype is not _F64 or T.shape != (4, 4) or not T.flags.c_contiguous:
                T = np.ascontiguousarray(_check_pose(T), dtype=float)
            sols = self.calibrated._solve_checked(T, wrist_ref)
            if sols:
                return self._even(T, wrist_ref, sols) if len(sols) & 1 and self.calibrated.parity else sols
            if not self.calibrated.may_reach(T):
                return sols
            return self._general(T, wrist_ref)
        return self._solve(T, wrist_ref)

    def _solve(self, T: ArrayLike, wrist_ref: float) -> list[IKSolution]:
        """:meth:`solve` once the constants are current and ``wrist_ref`` is a checked float."""
        cal = self.calibrated
        if cal is not None:  # robokit.ik.calibrated (it checks T the quick way, then fully)
            if type(T) is not np.ndarray or T.dtype is not _F64 or T.shape != (4, 4) or not T.flags.c_contiguous:
                T = np.ascontiguousarray(_check_pose(T), dtype=float)
            into = cal._into
            if into is not None:  # the common case of CalibratedArm._solve_checked, here: one Python call less
                out = np.empty(_OUT_SHAPE)
                n = into(cal._KC, cal._kind, T, wrist_ref * cal._ref_sign, out, cal._work)
                if 0 < n < _CAL_FLAGGED and not (n & 1 and cal.parity):
                    return _solutions_from_kernel(out, n, cal._labels)
                sols = cal._solve_checked(T, wrist_ref, 4, out, n)
            else:
                sols = cal._solve_checked(T, wrist_ref)
            if sols:
                return self._even(T, wrist_ref, sols) if len(sols) & 1 and cal.parity else sols
            if not cal.may_reach(T):
                return sols
            return self._general(T, wrist_ref)
        kernel = self._kernel
        if kernel is not None and self.use_kernel:
            # the kernel's one signature (float64, C order, 4×4); its rigid-transform test is compiled
            if type(T) is not np.ndarray or T.dtype is not _F64 or T.shape != _SHAPE44 or not T.flags.c_contiguous:
                T = np.ascontiguousarray(_check_pose(T), dtype=float)
            out = np.empty(_OUT_SHAPE)  # the solutions' q are views of this one array
            into = self._into
            if into is None:  # the kernel's machine code without numba's type dispatch, once it has some
                into = self._into = kernel[6](kernel[4])
                if into is None:
                    into = kernel[4]
            n = into(kernel[0], T, wrist_ref * self._ref_sign, out)  # = self._kernel_ref(wrist_ref)
            if n < 0:  # not a clean rigid transform: the full check (raises, or converts)
                T = np.ascontiguousarray(_check_pose(T), dtype=float)
                n = kernel[4](kernel[0], T, self._kernel_ref(wrist_ref), out)
                if n < 0:
                    return self._solve_python(T, wrist_ref)
            return _solutions_from_kernel(out, n, kernel[1]) if n else []
        return self._solve_python(_check_pose(T), wrist_ref)

    def solve_batch(self, Ts: ArrayLike, wrist_ref: float = 0.0) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Every closed-form solution of each of N tip poses, as arrays (compiled, parallel over poses).

        Parameters
        ----------
        Ts : (N, 4, 4) array_like
            Target poses of the tip in the base frame (m); each must be a rigid transform.
        wrist_ref : float
            The free joint's value at a wrist singularity (rad); default 0.

        Returns
        -------
        Q : (N, m_max, n) ndarray
            ``Q[i, :counts[i]]`` are the solutions of ``Ts[i]`` — the same values, in the same
            order, as ``solve(Ts[i])`` gives — and the rows after them are NaN; ``m_max`` is
            the largest count in the batch (0 when no pose is reachable).
        within : (N, m_max) bool
            ``within_limits`` of each solution (False on the NaN rows).
        counts : (N,) int
            Number of solutions of each pose (0: out of reach).

        Raises
        ------
        InputError
            If the robot has no closed form, ``Ts`` is not (N, 4, 4), or a pose is not a rigid
            transform (the first such index is named).

        Examples
        --------
        >>> import numpy as np, robokit
        >>> robot = robokit.load("puma560")
        >>> Ts = np.stack([robot.frame_pose(np.full(6, 0.1 * k)) for k in range(1, 4)])
        >>> Q, within, counts = AnalyticIK(robot).solve_batch(Ts)
        >>> Q.shape, counts.tolist()
        ((3, 8, 6), [8, 8, 8])
        """
        self._refresh()
        wrist_ref = wrist_ref if type(wrist_ref) is float and -TURN <= wrist_ref <= TURN else _wrist_ref(wrist_ref)
        if self.solver is None and self.calibrated is None:
            raise InputError(f"robot: no closed-form inverse kinematics: {self.kind.reason}")
        Ts = _check_poses(Ts)
        N = Ts.shape[0]
        if self.calibrated is not None:
            out, counts = self.calibrated.solve_batch(Ts, wrist_ref)
            extra: dict[int, list[IKSolution]] = {}
            for idx in np.flatnonzero(counts == 0):  # as solve: the general method where no start was found
                pose = int(idx)
                if self.calibrated.may_reach(Ts[pose]):
                    found = self._general(np.ascontiguousarray(Ts[pose]), wrist_ref)
                    if found:
                        extra[pose] = found
                        counts[pose] = len(found)
            if self.calibrated.parity:  # as solve: an odd number of solutions is completed
                for idx in np.flatnonzero(counts & 1):
                    pose = int(idx)
                    n = int(counts[pose])
                    if pose in extra:
                        continue  # the general method's own solutions already
                    have = [IKSolution(out[pose, k, :6].copy(), bool(out[pose, k, 6] == 1.0), "", False)
                            for k in range(n)]
                    found = self._even(np.ascontiguousarray(Ts[pose]), wrist_ref, have)
                    if len(found) > n:
                        extra[pose] = found
                        counts[pose] = len(found)
            m = int(counts.max()) if N else 0
            Q, within = out[:, :m, :6].copy(), out[:, :m, 6] == 1.0
            for pose, found in extra.items():
                for k, sol in enumerate(found):
                    Q[pose, k], within[pose, k] = sol.q, sol.within_limits
            return Q, within, counts
        kernel = self._kernel
        if kernel is None or not self.use_kernel:  # the Python solver, pose by pose
            sols = [self._solve_python(T, wrist_ref) for T in Ts]
            counts = np.array([len(s) for s in sols], dtype=np.int64)
            m = int(counts.max()) if N else 0
            Q = np.full((N, m, self.chain.n), np.nan)
            within = np.zeros((N, m), dtype=bool)
            for i, row in enumerate(sols):
                for k, sol in enumerate(row):
                    Q[i, k], within[i, k] = sol.q, sol.within_limits
            return Q, within, counts
        out, counts = kernel[3](kernel[0], Ts, self._kernel_ref(wrist_ref))
        m = int(counts.max()) if N else 0
        return out[:, :m, :6].copy(), out[:, :m, 6] == 1.0, counts

    def _general(self, T: np.ndarray, wrist_ref: float) -> list[IKSolution]:
        """A calibrated arm's pose where the nominal structure's closed form gave no start although the
        arm may reach it (:meth:`robokit.ik.calibrated.CalibratedArm.may_reach`): the general 6R
        method's solutions (``nominal=False``; labels ``"solution k of m"``), said once per arm when
        there are any — the nominal structure's closed form called the pose out of reach wrongly
        there (measured: 15 of 3,000 random poses of the benchmark's calibrated PUMA 560 before the relaxed
        poses moved the tool away from joint 1's axis too, none since, nor of its UR5 and Pieper arm). []
        when the general method does not apply, or has no root: then a RobokitWarning says so at every such
        pose (the Dobot ME6's file, whose axes 5 and 6 miss by 8.6e-8 m, reaches poses at θ₅ = 0 that both
        methods miss; the pose may also be out of reach)."""
        cal = self.calibrated
        assert cal is not None  # called for a calibrated arm only
        sols = self._general_solutions(T, wrist_ref) or []
        if not sols:  # within reach, and neither method has a root: out of reach, or a singular pose both miss
            warnings.warn(_EMPTY_WITHIN_REACH, RobokitWarning, stacklevel=4)
        elif not cal._general_warned:
            cal._general_warned = True
            said = (f"ik_analytic: the nominal structure's closed form gives no start at this pose, which the arm "
                    f"reaches: the general 6R method's {len(sols)} solutions are returned (labelled 'solution k of "
                    f"m'; said once per arm; the generated C returns none there)")
            warnings.warn(said, RobokitWarning, stacklevel=4)
        return sols

    def _general_solutions(self, T: np.ndarray, wrist_ref: float) -> list[IKSolution] | None:
        """The general 6R method's solutions of this robot at T (``nominal=False``), None when the
        method does not apply to it."""
        try:
            general = _CACHE.get(self._robot, False)
            general._refresh()
            return general._solve(T, wrist_ref)
        except InputError:
            return None

    def _even(self, T: np.ndarray, wrist_ref: float, sols: list[IKSolution]) -> list[IKSolution]:
        """A calibrated arm's pose where the solve found an odd number of solutions although an arm of
        revolute joints off its nominal structure has an even number
        (:attr:`robokit.ik.calibrated.CalibratedArm.parity`): at least one is missing, so the general 6R
        method's solutions that reach T (1e-9) and are not within
        :data:`robokit.kernels.calibrated_ik.DOUBLE` of one found are appended (labels ``"solution k of
        m"``), said once per arm. Measured on 80,000 random poses of the benchmark's four calibrated arms:
        14 odd counts; at 13 the general method gave exactly the missing root (at 4 the configuration
        that made the pose), at one two found roots 2.4e-7 apart were one double root (the kernel now drops
        the second: :data:`robokit.kernels.calibrated_ik.DOUBLE`)."""
        cal = self.calibrated
        assert cal is not None  # called for a calibrated arm only
        others = self._general_solutions(T, wrist_ref)
        if others is None:
            return sols
        added = sols + cal.missing(sols, others, T)
        if len(added) > len(sols) and not cal._odd_warned:
            cal._odd_warned = True
            warnings.warn(f"ik_analytic: an odd number of solutions ({len(sols)}) at this pose, where an arm of "
                          f"revolute joints off its nominal structure has an even number: the general 6R method's "
                          f"{len(added) - len(sols)} missing one(s) added (labelled 'solution k of m'; said once "
                          f"per arm; the generated C returns the set without them)", RobokitWarning, stacklevel=4)
        return added

    def _solve_python(self, T: np.ndarray, wrist_ref: float) -> list[IKSolution]:
        """The Python solver (the reference of the compiled path)."""
        if self.calibrated is not None:  # one implementation (plain Python under NUMBA_DISABLE_JIT)
            return self.calibrated.solve(np.ascontiguousarray(T, dtype=float), wrist_ref)
        solver = self.solver
        if solver is None:
            raise InputError(f"robot: no closed-form inverse kinematics: {self.kind.reason}")
        if self._free_flipped:
            wrist_ref = -wrist_ref  # the free joint is flipped: q′ = −wrist_ref gives q = wrist_ref
        if self.reversed:  # solve T⁻¹ with the reversed chain; q = −q′ in reverse order
            R, p = T[:3, :3], T[:3, 3]
            Tinv = np.eye(4)
            Tinv[:3, :3] = R.T
            Tinv[:3, 3] = -R.T @ p
            rows = solver.joint_angles(solver.chain.target_06(Tinv), -wrist_ref)
            rows = [(tuple(-v for v in q[::-1]), label + " (chain reversed)", degen) for q, label, degen in rows]
        else:
            rows = solver.joint_angles(self.chain.target_06(T), wrist_ref)
        if self._flip is not None:  # q = −q′ for the flipped joints
            flip = self._flip
            rows = [(tuple(-v if f else v for v, f in zip(q, flip)), label, degen) for q, label, degen in rows]
        if self._arm_polish is not None:  # the DH table too coarse for the arm (ILL_DH): finished on the arm
            rows = self._arm_polish.finish(T, rows)
        return solutions_from_rows(rows, self._revolute, self._limits)


_SHOULDER, _ELBOW, _WRIST = SHOULDER_LABELS, ELBOW_LABELS, WRIST_LABELS


def _method(chain: DHChain) -> tuple[ClosedFormKind, ClosedFormSolver | None]:
    """(kind, solver) for one reading of the chain."""
    kind = _detect(chain)
    if kind.method is None:
        return kind, None
    make = SOLVERS.get(kind.method)
    if make is None:  # a structure whose solver is not registered
        return ClosedFormKind(None, f"{kind.reason}, but no solver for the {kind.method} method is registered"), None
    solver = make(chain)
    why_not = solver.refusal()
    if why_not is not None:
        return ClosedFormKind(None, why_not), None
    return kind, solver


class _NotBuilt(Exception):
    """Raised by :func:`_not_built`: the robot has no AnalyticIK yet (``Robot.derived`` stores nothing)."""


def _not_built() -> Any:
    raise _NotBuilt


_KEY_NONE = ("analytic_ik", None)  # the per-robot key of _Cache.get without a nominal arm


class _Cache:
    """One :class:`AnalyticIK` per robot or table, for the one-call :func:`ik_analytic`: built on
    first use and kept *with* the object (a Robot's :meth:`~robokit.Robot.derived` store, a
    DHTable's instance dictionary), so it lives exactly as long as its robot — no module-level
    table keyed by identity. The AnalyticIK refers to its robot weakly (no cycle keeps it alive).
    Objects with neither store, or without weak references, get a fresh AnalyticIK per call.
    """

    def get(self, robot: Robot | DHTable, nominal: Any = None) -> AnalyticIK:
        if nominal is None or isinstance(nominal, (str, bool, RobotSpec)):
            key: Any = ("analytic_ik", nominal)  # by value
        else:  # a nominal Robot/DHTable object: held in the entry, so its id stays its own
            key = ("analytic_ik", id(nominal))
        derived = getattr(robot, "derived", None)
        if derived is not None:
            store = None
        else:
            store = getattr(robot, "__dict__", None)
            if store is None:
                return AnalyticIK(robot, nominal)
            store = store.setdefault("_analytic_ik", {})
            hit = store.get(key)
            if hit is not None:
                return cast(AnalyticIK, hit[1])

        def build() -> tuple[Any, AnalyticIK]:
            try:
                return nominal, AnalyticIK._shared(robot, nominal)
            except TypeError:  # pragma: no cover - objects without weak references
                return nominal, AnalyticIK(robot, nominal)

        if store is None:
            return cast(AnalyticIK, derived(key, build)[1])  # type: ignore[misc]
        store[key] = entry = build()
        return entry[1]


_CACHE = _Cache()
_check_pose = check_pose


def _check_poses(Ts: ArrayLike) -> np.ndarray:
    """(N, 4, 4) float64 C-contiguous rigid transforms, or InputError naming ``Ts`` (and the index)."""
    arr = np.asarray(Ts)
    if arr.ndim != 3 or arr.shape[1:] != (4, 4):
        raise InputError(f"Ts: expected shape (N, 4, 4), got {arr.shape}")
    if not np.issubdtype(arr.dtype, np.number) or np.iscomplexobj(arr):
        raise InputError(f"Ts: expected real numbers, got dtype {arr.dtype}")
    arr = np.ascontiguousarray(arr, dtype=np.float64)
    R = arr[:, :3, :3]
    dev = np.abs(np.einsum("nji,njk->nik", R, R) - np.eye(3)).max(axis=(1, 2)) if len(arr) else np.zeros(0)
    bad = ~np.isfinite(arr).all(axis=(1, 2)) | (dev >= 1e-9) | (np.linalg.det(R) <= 0.0) if len(arr) else dev > 0
    bad |= (arr[:, 3] != np.array([0.0, 0.0, 0.0, 1.0])).any(axis=1) if len(arr) else bad
    if bad.any():
        i = int(np.flatnonzero(bad)[0])
        _check_pose(arr[i], f"Ts[{i}]")  # raises with the reason
        arr[i] = _check_pose(arr[i], f"Ts[{i}]")  # pragma: no cover - a looser full check accepted it
    return arr

# ---------------------------------------------------------------------- detection
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


def _general_turn() -> float:
    """robokit.ik.general_6r.PARALLEL_TURN (imported when a general 6R arm needs it: numba kernels)."""
    from robokit.ik.general_6r import PARALLEL_TURN

    return PARALLEL_TURN


def _detect(chain: DHChain) -> ClosedFormKind:
    n = chain.n
    if n in (1, 2, 3):
        why = PlanarSolver(chain).refusal()
        if why is None:
            return ClosedFormKind("planar", _PLANAR_REASONS[n if chain.kinds[0] == "R" else 0])
        return ClosedFormKind(None, f"the arm has {n} joint{'s' if n > 1 else ''} and is not a planar arm: {why}; "
                                    f"the closed forms here need a planar arm of 1–3 joints or exactly 6 joints "
                                    f"(use solve_ik)")
    if n != 6:
        return ClosedFormKind(None, f"the arm has {n} joints; the closed forms here need exactly 6, or a planar "
                                    f"arm of 1–3 joints (use solve_ik)")
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
def analytic_ik(robot: Robot | DHTable, nominal: Any = None) -> AnalyticIK:
    """The shared :class:`AnalyticIK` of ``robot`` (built on first use, kept while ``robot`` lives).

    Parameters
    ----------
    robot : :class:`robokit.Robot` or :class:`robokit.DHTable`
    nominal : Robot, DHTable, RobotSpec, str or False, optional
        The nominal structure of a calibrated or nearly special arm (see :func:`ik_analytic`).

    Returns
    -------
    AnalyticIK
        The same object on every call for the same robot; it rebuilds itself when the robot's
        table or limits change.

    Examples
    --------
    >>> import robokit
    >>> analytic_ik(robokit.load("puma560")).method
    'spherical wrist'
    """
    return _CACHE.get(robot, nominal)


def ik_analytic_kind(robot: Robot | DHTable, nominal: Any = None) -> ClosedFormKind:
    """Which closed-form IK applies to ``robot``, decided from its joint axes.

    Parameters
    ----------
    robot : :class:`robokit.Robot` (from a DH file or a URDF) or a :class:`robokit.DHTable`.
    nominal : Robot, DHTable, RobotSpec, str or False, optional
        The nominal structure of a calibrated or nearly special arm, or False for none (see
        :func:`ik_analytic`).

    Returns
    -------
    ClosedFormKind
        ``.method`` is ``"spherical wrist"`` (Pieper), ``"three parallel axes"`` (UR family),
        ``"planar"`` (1–3 parallel revolute joints, or one prismatic joint),
        ``"calibrated spherical wrist"`` / ``"calibrated three parallel axes"`` (a calibrated or
        nearly special arm: the nominal structure's closed form polished by Newton's method on the
        arm's own kinematics, :mod:`robokit.ik.calibrated`), ``"general 6R"`` (any other 6R arm)
        or None; ``.reason`` says why, in the arm's terms (e.g. ``"axes 4–6 do not intersect:
        closest distance 0.0946 m; …"``).

    Notes
    -----
    The axes are the joint axes at q = 0 (lines in the base frame, from the DH table).
    Distances below 1e-9 m (times the arm's size in m when larger than 1) count as zero,
    angles below 1e-9 rad as parallel. An arm that misses a structure by at most
    :data:`robokit.ik.calibrated.NEAR_ANGLE` (0.01 rad) and ``NEAR_DISTANCE`` (0.01 × its reach), or
    whose nominal structure is named or recorded (``robot.nominal``), is a calibrated one.

    Examples
    --------
    >>> import robokit
    >>> ik_analytic_kind(robokit.load("puma560")).method
    'spherical wrist'
    """
    ik = _CACHE.get(robot, nominal)
    ik._refresh()
    return ik.kind


def ik_analytic(robot: Robot | DHTable, T: ArrayLike, wrist_ref: float = 0.0,
                world: CollisionChecker | None = None, nominal: Any = None) -> list[IKSolution]:
    r"""Every closed-form IK solution of ``robot`` for the tip pose ``T``.

    The one-call form of :class:`AnalyticIK`: ``ik_analytic(robot, T)`` is
    ``AnalyticIK(robot).solve(T)`` with the object built once per robot and reused.

    Parameters
    ----------
    robot : :class:`robokit.Robot` or :class:`robokit.DHTable`
        A 6-joint arm (a spherical wrist, three consecutive parallel axes whose last two axes meet,
        or any other 6R arm), or a planar arm of 1–3 joints (:mod:`robokit.ik.planar_solver`); see
        :func:`ik_analytic_kind`.
    T : (4, 4) array
        Target pose of the tip (``robot.frame_pose``'s frame; for a DH table the tool) in
        the base frame (m).
    wrist_ref : float
        At a wrist singularity, the value given to the free joint (q₄ for a spherical wrist,
        q₆ for the parallel-axes arms, q₁ of a planar 3R arm folded onto its first axis; rad). Default 0. A collision world given here, as in
        ``ik_analytic(robot, T, world)``, is taken as ``world`` (wrist_ref then 0); None is the default.
    world : :class:`robokit.collision.World`, optional
        When given, each solution's ``.collision_free`` says whether the arm is free of self-
        and obstacle collisions there (None without a world). All solutions are returned.
    nominal : Robot, DHTable, RobotSpec, str or False, optional
        For an arm whose URDF or DH table is nearly but not exactly special: the nominal arm, or
        its structure's name (``"spherical wrist"``, ``"three parallel axes"``). Its closed form
        gives one start per branch and Newton's method on ``robot``'s own kinematics finishes each
        (:mod:`robokit.ik.calibrated`). Not needed for a robot from :func:`robokit.calibrate`
        (it records its nominal) nor for axes within 0.01 rad and 0.01 × the reach of the
        structure (detected). ``False``: none — an arm that is not exactly special is solved by the
        general 6R method. A pose for which the nominal structure gives no start but that the arm
        may reach (within 1.5 × its reach of the shoulder) is solved by the general 6R method too
        (labels ``"solution k of m"``; a ``RobokitWarning`` once per arm).

    Returns
    -------
    list of :class:`IKSolution`
        Distinct solutions (8 for a PUMA 560 or a UR in general position, up to 8 — 4
        positions × 2 wrists — for any spherical-wrist arm, up to 16 for a general 6R arm,
        labelled ``"solution k of m"``, 2 for a planar 3R arm, 1 for a planar arm of one or two
        joints); each ``.q`` (n,) in rad/m,
        revolute joints wrapped to (−π, π] (or shifted by 2π into wider limits),
        ``.within_limits``, ``.label`` (branch, see the module docstring), ``.degenerate``
        (a singular choice was made). ``[]`` when T is out of reach.

    Raises
    ------
    InputError
        (a ValueError) If the robot has no closed form (the reason is in the message) or T is
        not a rigid transform.

    Notes
    -----
    Lecture 5: Pieper's wrist-centre decoupling (θ₁–θ₃ from a polynomial in tan(θ₃/2) of
    degree 2 or 4, the wrist from Euler-type angles), or for the UR family θ₁, θ₅, θ₆ from
    ``a cos θ + b sin θ = c`` and θ₂–θ₄ from a planar arm. Both are one implementation each,
    :mod:`robokit.kernels.closed_form`, run as compiled code (or as plain Python under
    ``NUMBA_DISABLE_JIT=1``); ``AnalyticIK.use_kernel = False`` runs the solver's rows through
    the Python post-processing (:func:`robokit.ik.solution.solutions_from_rows`) instead of the
    kernel's. Many poses at once: :func:`ik_analytic_batch`.

    Examples
    --------
    >>> import numpy as np, robokit
    >>> robot = robokit.load("puma560")
    >>> T = robot.frame_pose(np.array([0.1, -0.5, 0.3, 0.4, 0.6, -0.2]))
    >>> len(ik_analytic(robot, T))
    8
    """
    if not (type(wrist_ref) is float and -TURN <= wrist_ref <= TURN):
        if world is None and hasattr(wrist_ref, "in_collision"):  # ik_analytic(robot, T, world): the documented form
            world, wrist_ref = wrist_ref, 0.0
        elif wrist_ref is None:  # ik_analytic(robot, T, None): the documented form's "no world"
            wrist_ref = 0.0
        else:
            wrist_ref = _wrist_ref(wrist_ref)  # checked here: the solver's own check is silent when robokit calls it
    ik = None
    if nominal is None:  # a Robot's object, kept by Robot.derived: one dictionary lookup
        derived = getattr(robot, "derived", None)
        if derived is not None:
            try:
                ik = derived(_KEY_NONE, _not_built)[1]
            except _NotBuilt:
                pass
    if ik is None:
        ik = _CACHE.get(robot, nominal)
    if not ik._unchanged():
        ik._build()
    solutions = ik._solve(T, wrist_ref)
    return solutions if world is None else with_collision_flags(solutions, world)


def ik_analytic_batch(robot: Robot | DHTable, Ts: ArrayLike, wrist_ref: float = 0.0) -> tuple[np.ndarray, np.ndarray]:
    r"""Every closed-form IK solution of ``robot`` for each of N tip poses, as arrays.

    The batched :func:`ik_analytic`: compiled and parallel over the poses (numba ``prange``)
    for capability maps and data sets.

    Parameters
    ----------
    robot : :class:`robokit.Robot` or :class:`robokit.DHTable`
        An arm with a closed form (see :func:`ik_analytic_kind`).
    Ts : (N, 4, 4) array_like
        Target poses of the tip in the base frame (m).
    wrist_ref : float
        The free joint's value at a wrist singularity (rad); default 0.

    Returns
    -------
    Q : (N, m_max, n) ndarray
        ``Q[i, :counts[i]]`` are the joint values (rad, m) of the solutions of ``Ts[i]``, equal
        and in the same order to ``[s.q for s in ik_analytic(robot, Ts[i])]``; the remaining
        rows are NaN. ``m_max`` is the largest count in the batch.
    counts : (N,) int
        Number of solutions per pose (0: out of reach).

    Raises
    ------
    InputError
        (a ValueError) If the robot has no closed form, ``Ts`` is not (N, 4, 4) or a pose is
        not a rigid transform.

    Notes
    -----
    Lecture 5 (the same methods as :func:`ik_analytic`). For the within-limits flags use
    :meth:`AnalyticIK.solve_batch`.

    Examples
    --------
    >>> import numpy as np, robokit
    >>> robot = robokit.load("ur5")
    >>> Ts = np.stack([robot.frame_pose(np.full(6, 0.2)), robot.frame_pose(np.full(6, -0.4))])
    >>> Q, counts = ik_analytic_batch(robot, Ts)
    >>> Q.shape, counts.tolist()
    ((2, 8, 6), [8, 4])
    """
    if not (type(wrist_ref) is float and -TURN <= wrist_ref <= TURN):
        wrist_ref = _wrist_ref(wrist_ref)
    Q, _, counts = _CACHE.get(robot).solve_batch(Ts, wrist_ref)
    return Q, counts
