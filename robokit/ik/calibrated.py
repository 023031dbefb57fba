r"""Exact IK of a calibrated or nearly special arm: the nominal structure's closed form gives one start
per branch, Newton's method on the arm's own kinematics finishes each.

Calibration (:func:`robokit.calibrate`) moves every joint axis a little, so a spherical wrist's
axes no longer meet in one point and a UR arm's three parallel axes are no longer exactly parallel:
the closed forms of :mod:`robokit.ik.pieper` and :mod:`robokit.ik.parallel_axes` do not apply to the
arm on the bench. They apply to its **projection**: the same arm with the structure restored —

* *spherical wrist* (axes 4–6, or 1–3 counted from the tool): the three axis lines moved, each
  parallel to itself, through the point nearest to all three (least squares);
* *three parallel axes* (axes 2–4, or 3–5): their directions replaced by the mean direction, each
  line turned about its joint's origin; then the two axes that must meet (5 and 6, or 1 and 2)
  moved, parallel to themselves, through the midpoint of their common normal;

and with it the nominal arm's other relations: the angle between consecutive axes set to the
nominal's (detected arms: right angles and parallels within :data:`NEAR_ANGLE` made exact; each
correction turns the later axes together, about the common normal), runs of parallel axes averaged,
consecutive axes that meet moved onto each other. The tool pose at q = 0 and the joint zeros are
kept. The projected arm's closed form (compiled, :mod:`robokit.kernels.closed_form`) gives up to 8
solutions, one per branch, each within the size of the errors of a solution of the real arm;
Newton's method with a second-order correction on the real arm's product of exponentials
(:mod:`robokit.kernels.calibrated_ik`) converges each to 1e-12 in 2–3 steps. Away from singular poses each branch of the nominal structure
has exactly one solution of the real arm near it (the implicit function theorem), so the count is
the nominal's and so are the labels. Near a singular pose (within about the size of the errors):

* a branch the projected arm just misses (near the workspace's boundary) gets its start from the
  pose moved about the shoulder (the kernel's ``RELAX``);
* two branches can reach the same root (**merged**: one solution, ``degenerate`` set, its label
  naming both branches) or have no exact root any more (**vanished**: the roots of a fold became
  complex; :meth:`CalibratedArm.branches` lists every branch's outcome and a
  :class:`robokit.errors.RobokitWarning` says so once per arm);
* the roots the real arm has there beyond the nominal's are searched along the Jacobian's
  near-null direction from the points involved (flagged ``degenerate``). This search is not
  exhaustive: within a few milliradians of a singular configuration a root can be missed (every
  returned one is exact) — for example a calibrated UR5 at θ₅ = −0.34 mrad, where the arm's roots
  lie close to a curve (θ₄, θ₆ nearly free) and a 500-seed sweep finds one more. Never silently:
  whenever the search runs (a point whose scaled Jacobian has a singular value below
  :data:`robokit.kernels.calibrated_ik.SIGMA_EXPLORE`, 0.02), a :class:`robokit.errors.RobokitWarning`
  names that singular value; ``nominal=False`` gives the general 6R method there.

Which structure. In this order:

1. the one the caller names: ``nominal=`` a robot (its closed form's structure) or a method name
   (``"spherical wrist"``, ``"three parallel axes"``);
2. the nominal arm recorded on the robot (``robot.nominal``: :func:`robokit.calibrate` records the
   arm it started from, and the calibrated robot's spec carries it to other processes), when the
   arm is within :data:`RECORDED` (10) times the tolerances below of its structure;
3. detected: a structure whose axes are off by at most :data:`NEAR_ANGLE` (rad, between axes that
   must be parallel) and :data:`NEAR_DISTANCE` times the arm's reach (m, of axes that must meet),
   the reach being the largest distance from joint 1's origin to another joint's or the tool.

Only arms for which no structure holds exactly come here (an exactly special arm keeps its closed
form; a robot with none of these structures, even nearly, keeps the general 6R method).
"""
from __future__ import annotations

import math
import warnings
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any, Callable, Sequence

import numpy as np

from robokit._arrays import kernel_array
from robokit.errors import InputError, RobokitWarning
from robokit.ik.solution import IKSolution, _from_rows, check_pose
from robokit.kernels import calibrated_ik as _kci
from robokit.kernels import closed_form as _kcf

if TYPE_CHECKING:
    from robokit.description.dh import DHTable
    from robokit.ik._dh_chain import DHChain

__all__ = ["CalibratedArm", "Branch", "NEAR_ANGLE", "NEAR_DISTANCE", "STRUCTURES", "calibrated_arm", "ERROR_MEASURED",
           "search_constants", "start_error"]

#: Detected (not named) structures: the largest angle (rad) between axes that must be parallel.
NEAR_ANGLE = 1e-2
#: Detected structures: the largest distance of an axis from the point where its group must meet,
#: as a fraction of the arm's reach.
NEAR_DISTANCE = 1e-2
#: A nominal recorded on the robot (not named by the caller) is used when the arm is within this many
#: times the detection tolerances of its structure (a calibration's errors are far smaller).
RECORDED = 10.0
#: The near-singular search's constants (:mod:`robokit.kernels.calibrated_ik`) were measured complete on
#: arms whose tip pose differs from their projected arm's by up to about 0.008 (:func:`start_error`: the
#: calibrated PUMA 560, UR5 and random Pieper arm of ``benchmarks/calibrated_ik``, every joint placement off
#: by up to 2 mrad / 2 mm). An arm farther from its structure gets the constants of :func:`search_constants`.
ERROR_MEASURED = 1e-2


def start_error(M: np.ndarray, Slist: np.ndarray, projected: DHTable, revolute: Sequence[bool], reach: float,
                limits: Sequence[tuple[float, float]] | None = None, samples: int = 64) -> float:
    """How far the projected arm's tip pose is from the arm's: the largest orientation difference (rad)
    and position difference divided by the reach, over ``samples`` joint vectors drawn with a fixed seed
    (revolute joints in [−π, π], prismatic ones within their limits or ±reach/2) — the size of the
    errors of the closed form's starts, which decides how far from a singular configuration the arm can
    have roots beyond the nominal structure's (:func:`search_constants`).

    Parameters
    ----------
    M, Slist : numpy.ndarray
        The arm's product of exponentials (tip pose at q = 0, space screw axes as columns).
    projected : DHTable
        The projected arm (the robot's joint zeros and tool pose).
    revolute : sequence of bool
        Per joint.
    reach : float
        The arm's reach (m).
    limits : sequence of (lo, hi), optional
        Joint limits (prismatic joints are drawn within them).
    samples : int
        Joint vectors.

    Returns
    -------
    float
    """
    from robokit.kinematics.poe import fkin_space

    rng = np.random.default_rng(0)
    lo = np.array([-math.pi if r else -0.5 * reach for r in revolute])
    hi = -lo
    if limits is not None:
        for j, (a, b) in enumerate(limits):
            if not revolute[j] and math.isfinite(a) and math.isfinite(b):
                lo[j], hi[j] = a, b
    error = 0.0
    for _ in range(samples):
        q = rng.uniform(lo, hi)
        A, B = fkin_space(M, Slist, q), projected.fk(q)
        c = min(1.0, max(-1.0, 0.5 * (float(np.trace(A[:3, :3].T @ B[:3, :3])) - 1.0)))
        error = max(error, math.acos(c), float(np.linalg.norm(A[:3, 3] - B[:3, 3])) / reach)
    return error


def search_constants(error: float) -> tuple[float, bool, float]:
    """The near-singular search's threshold and rule for an arm whose starts are off by ``error``
    (:func:`start_error`).

    Up to :data:`ERROR_MEASURED`: :data:`robokit.kernels.calibrated_ik.SIGMA_EXPLORE` (0.02), and the
    first solution's singular values stand for the pose's, and the fold starts' windows are
    :data:`robokit.kernels.closed_form.FOLD_STARTS` and ``FOLD_IMAG``. Beyond it the roots that the
    nominal structure lacks appear farther from singular configurations: at a fold two roots meet where
    ``f(s) = a s² + e`` changes sign, the Jacobian there about ``2 √(a e)``, so the threshold grows as
    ``√error``, and each solution is checked (a wrist singularity is one branch pair's, not the pose's);
    the projected arm misses a reach by up to about the error (``FOLD_STARTS`` grows as ``error``), and
    a complex pair of its quartic moves off the real line as the square root of a perturbation of a
    double root — but ``FOLD_IMAG`` grows as ``error`` too: with the square root, one pair of the
    study below was 0.55 rad off the real line where the window was 0.40 (two roots missed silently;
    the linear window finds them, at 3–5 % more poses searched on the Pieper arm, none on the others).
    Measured (``docs/course/calibration.md``) on the benchmark's PUMA 560, UR5 and random Pieper arm
    with every joint placement off by up to 10 mrad / 10 mm (error 0.03–0.04; three draws of each
    arm, 600 random poses each): of the roots a 500-start sweep finds, 54 were missing with the fixed
    constants, 35 of them without a warning; 3 with these, none without a warning (and none without
    a warning on two more draws).

    Parameters
    ----------
    error : float
        rad, and m per m of reach.

    Returns
    -------
    (float, bool, float)
        ``(sigma_explore, every, fold_scale)`` for :func:`robokit.kernels.calibrated_ik.pack_arm`.
    """
    if not error > ERROR_MEASURED:
        return _kci.SIGMA_EXPLORE, False, 1.0
    return _kci.SIGMA_EXPLORE * math.sqrt(error / ERROR_MEASURED), True, error / ERROR_MEASURED


#: Newton stops below this orientation (rad) and position (m) error; a start whose polish ends
#: above ``TOL_ACCEPT`` has no solution near it.
TOL_STOP, TOL_ACCEPT, MAX_STEPS = 1e-12, 1e-10, 30

#: (method, counted from the tool) → (joints that must be parallel, joints that must meet), 0-based.
STRUCTURES: dict[tuple[str, bool], tuple[tuple[int, ...], tuple[int, ...]]] = {
    ("spherical wrist", False): ((), (3, 4, 5)),
    ("spherical wrist", True): ((), (0, 1, 2)),
    ("three parallel axes", False): ((1, 2, 3), (4, 5)),
    ("three parallel axes", True): ((2, 3, 4), (0, 1)),
}

Line = tuple[np.ndarray, np.ndarray, str]


@dataclass(frozen=True)
class Branch:
    """What became of one branch of the nominal structure at one pose (:meth:`CalibratedArm.branches`).

    Attributes
    ----------
    label : str
        The nominal branch (``"left, elbow up, flip"``).
    outcome : str
        ``"solution"`` (a distinct solution of the arm), ``"merged"`` (it reached the root of an
        earlier branch) or ``"vanished"`` (no exact solution of the arm near it).
    index : int or None
        Index of its solution in :meth:`CalibratedArm.solve`'s list (None when vanished).
    orientation_error, position_error : float
        At the end of Newton's method (rad, m): below 1e-10 for a solution.

    Examples
    --------
    >>> Branch("right, elbow up, no flip", "solution", 0, 0.0, 0.0).outcome
    'solution'
    """

    label: str
    outcome: str
    index: int | None
    orientation_error: float
    position_error: float


@dataclass(frozen=True)
class _Geometry:
    """A 6-joint chain as lines at q = 0 and its PoE (base frame, m)."""

    lines: list[Line]
    M: np.ndarray
    Slist: np.ndarray
    qlim: np.ndarray | None
    reach: float


def _geometry(robot: Any, chain: DHChain | None, flip: Sequence[bool] | None) -> _Geometry:
    """Lines and PoE of a Robot (its own ``poe`` and joint origins) or of a DH table (its canonical
    chain, flipped joints turning about −z)."""
    if chain is None:
        from robokit.description.urdf_to_dh import joint_axes

        lines = [(p, d, k) for p, d, k in joint_axes(robot)]
        M = kernel_array(robot.poe.M, float)  # writeable, as the kernels take them (no copy of a Robot's)
        S = kernel_array(robot.poe.Slist, float)
        qlim = np.asarray(robot.qlim, dtype=float)
    else:
        R, t = chain.base[:3, :3], chain.base[:3, 3]
        lines = []
        for i, (p, d) in enumerate(chain.axes()):
            d = R @ d * (-1.0 if flip is not None and flip[i] else 1.0)
            lines.append((R @ p + t, d, chain.kinds[i]))
        M = np.ascontiguousarray(chain.fk(np.zeros(chain.n)), dtype=float)
        S = np.zeros((6, chain.n))
        for i, (p, d, k) in enumerate(lines):
            if k == "R":
                S[:3, i], S[3:, i] = d, -np.cross(d, p)
            else:
                S[3:, i] = d
        qlim = None
        if chain.qlim is not None:
            qlim = np.array([(-hi, -lo) if flip is not None and flip[i] else (lo, hi)
                             for i, (lo, hi) in enumerate(chain.qlim)], dtype=float)
    o1 = lines[0][0]
    reach = max([float(np.linalg.norm(p - o1)) for p, _, _ in lines] + [float(np.linalg.norm(M[:3, 3] - o1)), 1e-3])
    return _Geometry(lines, M, S, qlim, reach)


def _angle(d1: np.ndarray, d2: np.ndarray) -> float:
    return math.atan2(float(np.linalg.norm(np.cross(d1, d2))), abs(float(d1 @ d2)))


def _meet(lines: Sequence[Line]) -> tuple[np.ndarray, float]:
    """Least-squares meeting point of the lines, and the largest distance of a line from it."""
    A, b = np.zeros((3, 3)), np.zeros(3)
    for p, d, _ in lines:
        P = np.eye(3) - np.outer(d, d)
        A += P
        b += P @ p
    x = np.linalg.lstsq(A, b, rcond=None)[0]
    return x, max(float(np.linalg.norm((np.eye(3) - np.outer(d, d)) @ (x - p))) for p, d, _ in lines)


def deviation(geo: _Geometry, structure: tuple[str, bool]) -> tuple[float, float]:
    """(largest angle between axes that must be parallel (rad), largest distance of an axis from the
    point its group must meet at (m)) of ``geo`` for ``structure`` (a key of :data:`STRUCTURES`);
    (inf, inf) when a joint that must be revolute is prismatic."""
    par, meet = STRUCTURES[structure]
    if any(geo.lines[i][2] != "R" for i in par + meet):
        return math.inf, math.inf
    ang = max([_angle(geo.lines[par[0]][1], geo.lines[i][1]) for i in par[1:]] + [0.0])
    # the meeting group measured with the parallel group made parallel, before it is placed on its
    # meeting point (as _project does next): after that the distance would be zero whatever the arm
    parallel = [(p.copy(), d.copy(), k) for p, d, k in geo.lines]
    _make_parallel(parallel, [par] if par else [])
    _, dist = _meet([parallel[i] for i in meet])
    return ang, dist


def _signed_angle(d1: np.ndarray, d2: np.ndarray) -> float:
    """Angle in [0, π] between two directions (signs kept: the DH twist up to its sign)."""
    return math.atan2(float(np.linalg.norm(np.cross(d1, d2))), float(d1 @ d2))


def _rotate(v: np.ndarray, axis: np.ndarray, angle: float) -> np.ndarray:
    """v turned by ``angle`` about the unit ``axis`` (Rodrigues)."""
    c, s = math.cos(angle), math.sin(angle)
    return v * c + np.cross(axis, v) * s + axis * float(axis @ v) * (1.0 - c)


def _set_twists(lines: list[Line], twists: Sequence[float | None]) -> list[Line]:
    """The lines with the angle between consecutive directions i, i+1 set to ``twists[i]`` (None:
    kept): each correction turns direction i+1 and every later one together (their own angles
    kept), about the common normal of directions i and i+1; the points stay."""
    out = [(p.copy(), d.copy(), k) for p, d, k in lines]
    for i, target in enumerate(twists):
        if target is None:
            continue
        di, dj = out[i][1], out[i + 1][1]
        delta = target - _signed_angle(di, dj)
        if delta == 0.0:
            continue
        axis = np.cross(di, dj)
        if float(np.linalg.norm(axis)) < 1e-12:  # parallel or opposite: any normal of di
            axis = np.cross(di, [1.0, 0.0, 0.0] if abs(di[0]) < 0.9 else [0.0, 1.0, 0.0])
        axis = axis / np.linalg.norm(axis)
        for k in range(i + 1, len(out)):
            p, d, kind = out[k]
            d = _rotate(d, axis, delta)
            out[k] = (p, d / np.linalg.norm(d), kind)
    return out


def _make_parallel(lines: list[Line], groups: Sequence[Sequence[int]]) -> None:
    """Give each group of ``lines`` (indices) one direction, the average of theirs (signs kept); the
    points stay. In place."""
    for group in groups:
        ref = lines[group[0]][1]
        u = sum((lines[i][1] if lines[i][1] @ ref >= 0 else -lines[i][1]) for i in group)
        u = u / np.linalg.norm(u)
        for i in group:
            p, d, k = lines[i]
            lines[i] = (p, u if d @ u >= 0 else -u, k)


def _project(lines: list[Line], structure: tuple[str, bool],
             extra: tuple[list[tuple[int, ...]], list[tuple[int, int]]] = ([], []),
             twists: Sequence[float | None] | None = None) -> list[Line]:
    """The lines with ``structure`` restored (module docstring), and with it the nominal arm's
    ``twists`` (the angles between consecutive axes, :func:`_set_twists`) and ``extra`` relations:
    runs of consecutive parallel axes (their directions averaged) and pairs of consecutive axes
    that meet (the line not placed yet moved, parallel to itself, onto the other)."""
    par, meet = STRUCTURES[structure]
    out = _set_twists(lines, twists) if twists is not None else [(p.copy(), d.copy(), k) for p, d, k in lines]
    _make_parallel(out, [g for g in extra[0] if not set(g) & set(par)] + ([par] if par else []))
    W, _ = _meet([out[i] for i in meet])
    for i in meet:
        p, d, k = out[i]
        out[i] = (W.copy(), d, k)
    placed = set(meet)
    for a, b in extra[1]:
        if {a, b} <= placed:
            continue
        move, keep = (b, a) if a in placed else (a, b)
        (pm, dm, km), (pk, dk, _) = out[move], out[keep]
        c = np.cross(dm, dk)
        if float(np.linalg.norm(c)) < 1e-12:  # parallel lines meet only if they coincide
            continue
        # the feet of the common normal: pm + s dm and pk + t dk
        A = np.array([[dm @ dm, -(dm @ dk)], [dm @ dk, -(dk @ dk)]])
        s_, t_ = np.linalg.solve(A, np.array([(pk - pm) @ dm, (pk - pm) @ dk]))
        out[move] = (pm + (pk + t_ * dk - (pm + s_ * dm)), dm, km)
        placed |= {a, b}
    return out


def _relations(geo: _Geometry, angle: float, distance: float) -> tuple[list[tuple[int, ...]], list[tuple[int, int]]]:
    """(runs of consecutive revolute axes parallel within ``angle``, consecutive revolute pairs
    meeting within ``distance``) of ``geo``."""
    runs: list[tuple[int, ...]] = []
    pairs: list[tuple[int, int]] = []
    n = len(geo.lines)
    run = [0]
    for i in range(n - 1):
        (pa, da, ka), (pb, db, kb) = geo.lines[i], geo.lines[i + 1]
        if ka == "R" and kb == "R" and _angle(da, db) <= angle:
            run.append(i + 1)
            continue
        if len(run) > 1:
            runs.append(tuple(run))
        run = [i + 1]
        if ka == "R" and kb == "R" and 2.0 * _meet([geo.lines[i], geo.lines[i + 1]])[1] <= distance:
            pairs.append((i, i + 1))
    if len(run) > 1:
        runs.append(tuple(run))
    return runs, pairs


def _label_of(structure: tuple[str, bool]) -> str:
    par, meet = STRUCTURES[structure]
    what = {("spherical wrist", False): "axes 4–6 meet in one point (spherical wrist)",
            ("spherical wrist", True): "axes 1–3 meet in one point (a spherical joint group at the base)",
            ("three parallel axes", False): "axes 2–4 are parallel and axes 5 and 6 meet",
            ("three parallel axes", True): "axes 3–5 are parallel and axes 1 and 2 meet"}[structure]
    return what


class CalibratedArm:
    """The exact IK of one calibrated or nearly special 6-joint arm (module docstring).

    Built by :class:`robokit.ik.closed_form.AnalyticIK` (``AnalyticIK(robot).calibrated``); use
    :func:`robokit.ik_analytic` for the solutions.

    Attributes
    ----------
    method : str
        ``"calibrated spherical wrist"`` or ``"calibrated three parallel axes"``.
    reason : str
        Which structure, from where (named, recorded nominal, detected) and how far the arm is from it.
    structure : tuple of (str, bool)
        The nominal structure and whether it is counted from the tool (a key of :data:`STRUCTURES`).
    deviation : tuple of float
        (rad, m): how far the arm's axes are from the structure.
    start_error : float
        How far the projected arm's tip pose is from the arm's (:func:`start_error`: rad, and m per m
        of reach): the size of the errors of the closed form's starts.
    sigma_explore : float
        The near-singular search runs where the scaled Jacobian has a singular value below this
        (:func:`search_constants`: 0.02, more for an arm farther from its structure).
    nominal : AnalyticIK
        The closed form of the projected arm (the starts).
    projected : DHTable
        The projected arm (standard DH, the robot's joint zeros and tool pose).

    Examples
    --------
    >>> import numpy as np, robokit
    >>> from robokit.calibration import chain_from_robot, robot_from_chain
    >>> robot = robokit.load("puma560")
    >>> delta = np.random.default_rng(1).uniform(-1e-3, 1e-3, (7, 6))
    >>> arm = robot_from_chain(robot, chain_from_robot(robot).perturbed(delta))
    >>> ik = robokit.ik.analytic_ik(arm)
    >>> ik.method, ik.calibrated.structure
    ('calibrated spherical wrist', ('spherical wrist', False))
    >>> sols = ik.solve(arm.frame_pose(np.array([0.3, -0.5, 0.4, 0.2, 0.6, -0.1])))
    >>> len(sols), all(np.abs(arm.frame_pose(s.q) - arm.frame_pose(np.array([0.3, -0.5, 0.4, 0.2, 0.6, -0.1]))).max()
    ...                   < 1e-9 for s in sols)
    (8, True)
    """

    def __init__(self, geo: _Geometry, structure: tuple[str, bool], nominal: Any, projected: DHTable,
                 deviation: tuple[float, float], source: str, revolute: Sequence[bool],
                 limits: Sequence[tuple[float, float]] | None) -> None:
        self.structure = structure
        self.method = f"calibrated {structure[0]}"
        self.deviation = deviation
        self.nominal = nominal
        self.projected = projected
        self.M, self.Slist, self.reach = geo.M, geo.Slist, geo.reach
        # the point poses are scaled about when a branch is missing (the kernel's RELAX): axes 1 and 2
        self.shoulder = np.ascontiguousarray(_meet(geo.lines[:2])[0])
        kn = nominal._kernel
        self._Kn, self._labels = kn[0], kn[1]
        self._kind = _kcf.PIEPER if structure[0] == "spherical wrist" else _kcf.PARALLEL_AXES
        post_q = np.zeros((5, 6))
        post_q[0] = 1.0
        post_q[1] = [1.0 if r else 0.0 for r in revolute]
        if limits is not None:
            post_q[2] = [lo for lo, _ in limits]
            post_q[3] = [hi for _, hi in limits]
            post_q[4, 0] = 1.0
        else:
            post_q[2], post_q[3] = -np.inf, np.inf
        self._post_q = post_q
        #: How far the closed form's starts are off (:func:`start_error`), and the search's constants for that.
        self.start_error = start_error(self.M, self.Slist, projected, revolute, self.reach, limits)
        self.sigma_explore, self._every, self._fold_scale = search_constants(self.start_error)
        # everything the kernel reads of this arm, in one array (one argument to dispatch)
        self._C = _kci.pack_arm(self.M, self.Slist, post_q, self.shoulder, self.reach, TOL_STOP, TOL_ACCEPT,
                                MAX_STEPS, self.sigma_explore, self._every, self._fold_scale)
        self._KC = np.concatenate([self._C, self._Kn])  # both, as the kernel takes them
        self._work = _kci.scratch()  # reused: the kernel holds the GIL, so one call runs at a time
        self._branches = self._work[_kci.BRANCH_ROWS]  # where the kernel writes each branch's outcome
        self._status = self._work[_kci.STATUS]  # (merged, vanished, σ) of a flagged solve
        self._ref_sign = nominal._kernel_ref(1.0)  # wrist_ref in the sign of the projected arm's solver
        self._into: Any = None  # the kernel's machine code without numba's type dispatch (_kci.solve_into_entry)
        self._warned = False
        self._general_warned = False  # AnalyticIK._general's warning, said once per arm
        self._odd_warned = False  # AnalyticIK._even's warning, said once per arm
        self._merged_warned = False  # _warn_merged's, said once per arm
        #: Every joint revolute: off its nominal structure the arm is a general 6R arm, whose solutions
        #: are the real roots of a polynomial of degree 16, an even number of them (complex roots come in
        #: conjugate pairs); an odd count means one is missing (:data:`robokit.kernels.calibrated_ik.DOUBLE`).
        self.parity = all(bool(r) for r in revolute)
        ang, dist = deviation
        off = []
        if STRUCTURES[structure][0]:
            off.append(f"the parallel axes differ by up to {ang:.2g} rad")
        off.append(f"the axes that should meet pass up to {dist:.2g} m from a common point")
        self.reason = (f"{source}: {_label_of(structure)} on the nominal arm, but {' and '.join(off)}; "
                       f"the nominal structure's closed form gives one start per branch and Newton's method on "
                       f"this arm's own kinematics finishes each")

    def __repr__(self) -> str:
        return f"CalibratedArm({self.method!r}, deviation=({self.deviation[0]:.2g} rad, {self.deviation[1]:.2g} m))"

    def export_constants(self) -> dict[str, Any]:
        """The numbers the generated C's polish needs (:mod:`robokit.codegen.ik`): method, reason,
        shoulder (3,), reach, the kernel's tolerances and search constants, and the arm's local
        transforms (``frames`` (7, 3, 4): :func:`robokit.kernels.calibrated_ik.local_transforms`,
        ``kinds`` 0/1 revolute/prismatic, ``pitches``: :func:`robokit.kernels.calibrated_ik.pack_arm`).

        Returns
        -------
        dict
        """
        return {"method": self.method, "reason": self.reason, "shoulder": self.shoulder.copy(), "reach": self.reach,
                "tol_stop": TOL_STOP, "tol_accept": TOL_ACCEPT, "max_steps": MAX_STEPS, "same": _kci.SAME,
                "double": _kci.DOUBLE, "parity": self.parity,
                "explore": _kci.EXPLORE, "explore_steps": tuple(_kci.EXPLORE_STEPS), "max_step": _kci.MAX_STEP,
                "sigma_explore": self.sigma_explore, "every": self._every, "explore_max_steps": _kci.EXPLORE_MAX_STEPS,
                "trace_step": _kci.TRACE_STEP, "trace_steps": _kci.TRACE_STEPS, "trace_pull": _kci.TRACE_PULL,
                "trace_rows": _kci.TRACE_ROWS,
                "generic_rows": _kci.GENERIC_ROWS, "relax": tuple(_kci.RELAX_MOVES), "radial": tuple(_kci.RELAX),
                "axis1": _kci.first_axis(self._C), "max_rows": _kcf.MAX_ROWS,
                "fold_starts": _kcf.FOLD_STARTS * self._fold_scale, "free_wrist": _kcf.FREE_WRIST * self._fold_scale,
                "fold_position_wrist": _kcf.FOLD_POSITION_WRIST * self._fold_scale,
                "free_samples": _kcf.FREE_SAMPLES, "free_iterations": _kcf.FREE_ITERATIONS,
                "fold_imag": _kcf.FOLD_IMAG * self._fold_scale, "fold_code": _kcf.FOLD_CODE,
                "log_near": _kci.LOG_NEAR, "second_order": tuple(_kci.SECOND_ORDER), "block_axes": _kci.BLOCK_AXES,
                "block_schur": _kci.BLOCK_SCHUR, "frames": _kci.local_transforms(self._C),
                "kinds": self._C[_kci.KINDS].astype(int).tolist(), "pitches": self._C[_kci.PITCHES].tolist(),
                "labels": [self._labels[c] for c in sorted(self._labels)]}

    def refusal(self) -> str | None:
        """Why this method does not apply to the arm, or None (it always applies: it was built for this arm).

        Returns
        -------
        None
        """
        return None

    def may_reach(self, T: np.ndarray) -> bool:
        """Whether the tip position of T is within 1.5 × the reach of the shoulder point (the point the
        relaxed poses are moved about): a pose beyond it is taken as out of reach (the reach is the
        largest distance from joint 1's origin to another joint's or the tool, and the shoulder point
        lies on joint 1's axis); one inside that gets no solution from the nominal structure's closed
        form is solved by the general 6R method (:meth:`robokit.ik.closed_form.AnalyticIK._solve`).

        Parameters
        ----------
        T : (4, 4) ndarray
            Target pose of the tip in the base frame, m.

        Returns
        -------
        bool
        """
        d = T[:3, 3] - self.shoulder
        return bool(float(d @ d) <= (1.5 * self.reach) ** 2)

    def _solve(self, T: np.ndarray, wrist_ref: float) -> tuple[np.ndarray, int, np.ndarray]:
        """(out, the kernel's result, branches) for T, the full rigid-transform check (which raises or
        gives the nearest rigid transform) where the kernel's quick one fails."""
        out = np.empty((_kcf.MAX_ROWS, _kcf.OUT_COLS))
        ref = wrist_ref * self._ref_sign
        for attempt in range(2):
            n = _kci.calibrated_solve_into(self._KC, self._kind, T, ref, out, self._work)
            if n != -1 or attempt:
                break
            T = _nearest_rigid(T)
        return out, n, self._branches

    def solve(self, T: np.ndarray, wrist_ref: float = 0.0) -> list[IKSolution]:
        """Every solution for the tip pose T (a checked, C-contiguous float64 (4, 4) rigid transform).

        Parameters
        ----------
        T : numpy.ndarray, shape (4, 4)
            Target pose of the tip in the base frame, m.
        wrist_ref : float
            The free joint's value at a singularity of the nominal structure, rad.

        Returns
        -------
        list of IKSolution
            As :func:`robokit.ik_analytic`; a solution reached by several branches is labelled
            ``"A (merged with B)"`` and flagged ``degenerate``.
        """
        if type(T) is not np.ndarray or T.dtype is not _F64 or T.shape != (4, 4) or not T.flags.c_contiguous:
            T = np.ascontiguousarray(check_pose(T), dtype=float)
        return self._solve_checked(T, wrist_ref, 5)

    def _solve_checked(self, T: np.ndarray, wrist_ref: float, level: int = 4, out: np.ndarray | None = None,
                       n: int = 0) -> list[IKSolution]:
        """:meth:`solve` of a T known to be a C-contiguous float64 (4, 4) array (the kernel's machine
        code is called without numba's type dispatch); its warnings name the caller ``level`` frames up.
        ``out``, ``n``: the kernel's output and result for this T and wrist_ref where the caller ran it
        already (:meth:`robokit.ik.closed_form.AnalyticIK._solve` runs the common case itself)."""
        if out is None:
            out = np.empty(_OUT_SHAPE)
            into = self._into
            if into is None:
                into = _kci.solve_into_entry()
                if into is None:  # not compiled for these types yet (or plain Python): numba's dispatch
                    into = _kci.calibrated_solve_into
                else:
                    self._into = into
            n = into(self._KC, self._kind, T, wrist_ref * self._ref_sign, out, self._work)
        if 0 < n < _FLAGGED:  # the common case: solutions, no branch merged or vanished, no search
            return _from_rows([out, n, self._labels, None])
        if n == -1:  # T failed the kernel's quick rigid-transform test: the full check (raises), or its nearest
            out, n, _ = self._solve(_nearest_rigid(T), wrist_ref)
        merged = vanished = 0
        sigma = math.inf
        if n >= _FLAGGED:
            n -= _FLAGGED
            merged, vanished, sigma = int(self._status[0]), int(self._status[1]), float(self._status[2])
        if vanished:
            self._warn_vanished(self._branches, level)
        elif merged and not sigma <= self.sigma_explore:
            self._warn_merged(self._branches, level)
        if sigma <= self.sigma_explore:
            warnings.warn(f"ik_analytic: this pose is near a singular configuration of the arm (smallest singular "
                          f"value of its Jacobian, velocity rows divided by the reach: {sigma:.2g}, searched below "
                          f"{self.sigma_explore:.2g}); there the arm can have roots beyond the nominal structure's "
                          f"branches, and the search for them (along the near-singular direction and the curve of near-"
                          f"solutions) is not exhaustive: "
                          f"a solution may be missing (each returned one is exact; nominal=False gives the general "
                          f"6R method)", RobokitWarning, stacklevel=level)
        if n <= 0:
            return []
        sols = _from_rows([out, n, self._labels, None])
        if not merged:
            return sols
        branches = self._branches
        m = int(np.count_nonzero(branches[:, 0] >= 0.0))
        merged_rows = [(int(branches[r, 2]), self._labels[float(branches[r, 0])]) for r in range(m)
                       if branches[r, 1] == _kci.MERGED]
        # a solution reached by several branches names them all (after its own label and repeat number)
        plain = [IKSolution(s.q, s.within_limits, s.label, s.degenerate) for s in sols]
        for k in sorted({k for k, _ in merged_rows}):
            names = ", ".join(name for kk, name in merged_rows if kk == k)
            s = plain[k]
            plain[k] = IKSolution(s.q, s.within_limits, f"{s.label} (merged with {names})", s.degenerate)
        return plain

    def missing(self, sols: Sequence[IKSolution], others: Sequence[IKSolution], T: np.ndarray) -> list[IKSolution]:
        """Those of ``others`` (another method's solutions) that reach T (1e-9 in every entry of the
        pose) and are not within :data:`robokit.kernels.calibrated_ik.DOUBLE` (rad or m, angles modulo
        2π) of one of ``sols`` or of one taken before.

        Parameters
        ----------
        sols, others : sequence of IKSolution
            The solutions found, and the candidates.
        T : numpy.ndarray, shape (4, 4)
            The tip pose.

        Returns
        -------
        list of IKSolution
            The new ones, in the order of ``others``.
        """
        from robokit.kinematics.poe import fkin_space

        rev = self._post_q[1] != 0.0
        have = [np.asarray(s.q, dtype=float) for s in sols]
        new: list[IKSolution] = []
        for s in others:
            q = np.asarray(s.q, dtype=float)
            if not np.abs(fkin_space(self.M, self.Slist, q) - T).max() <= 1e-9:
                continue
            if have:
                d = np.abs(q - np.stack(have))
                d[:, rev] = np.abs(np.remainder(d[:, rev] + math.pi, 2.0 * math.pi) - math.pi)
                if d.max(axis=1).min() < _kci.DOUBLE:
                    continue
            have.append(q)
            new.append(s)
        return new

    def branches(self, T: np.ndarray, wrist_ref: float = 0.0) -> list[Branch]:
        """What became of each branch of the nominal structure at the pose T: a solution of its own,
        merged into an earlier branch's, or vanished (its errors at the end of Newton's method).

        Parameters
        ----------
        T, wrist_ref
            The tip pose and the free joint's value at a singularity, exactly as :meth:`solve` takes them.

        Returns
        -------
        list of Branch
            One per branch of the projected arm's closed form, in its order.
        """
        branches = self._solve(T, wrist_ref)[2].copy()
        return [Branch(self._labels[float(branches[r, 0])], ("solution", "merged", "vanished")[int(branches[r, 1])],
                       None if branches[r, 2] < 0 else int(branches[r, 2]), float(branches[r, 3]),
                       float(branches[r, 4])) for r in range(int(np.count_nonzero(branches[:, 0] >= 0.0)))]

    def solve_batch(self, Ts: np.ndarray, wrist_ref: float = 0.0) -> tuple[np.ndarray, np.ndarray]:
        """Every solution of N poses at once, in the compiled kernel.

        Parameters
        ----------
        Ts : numpy.ndarray, shape (N, 4, 4)
            Tool poses in the base frame (m).
        wrist_ref : float, optional
            The wrist reference angle (rad) of the nominal closed form.

        Returns
        -------
        tuple of numpy.ndarray
            ``(out, counts)``: out (N, 16, 9) rows as :func:`robokit.kernels.calibrated_ik.calibrated_batch`
            writes them, counts (N,) the number of solutions of each pose.
        """
        return _kci.calibrated_batch(self._KC, self._kind, Ts, self.nominal._kernel_ref(wrist_ref))

    def _warn_vanished(self, branches: np.ndarray, level: int = 4) -> None:
        if self._warned:
            return
        m = int(np.count_nonzero(branches[:, 0] >= 0.0))
        gone = [self._labels[float(branches[r, 0])] for r in range(m) if branches[r, 1] == _kci.VANISHED]
        if gone:
            self._warned = True
            warnings.warn(f"ik_analytic: near a singular pose, the branch(es) {', '.join(gone)} of the nominal "
                          f"structure have no exact solution on this arm (two roots met and left); "
                          f"AnalyticIK(robot).calibrated.branches(T) lists every branch (said once per arm)",
                          RobokitWarning, stacklevel=level)


    def _warn_merged(self, branches: np.ndarray, level: int = 4) -> None:
        """Said once per arm, at a pose where a branch merged and nothing else warned: two branches of
        the nominal structure reached one root, so the arm's pair of roots for the one that merged
        (near a fold) may lie elsewhere. Measured (20,000 random poses of each of the benchmark's
        calibrated arms and a real UR5e, ``default_rng(4242)``): poses merged without another warning
        only on the random Pieper arm, 609 of them, and at one of those (``shared_robots.MERGED_MISS``)
        two roots — the generating configuration one of them — which the general 6R method returns."""
        if self._merged_warned:
            return
        m = int(np.count_nonzero(branches[:, 0] >= 0.0))
        into = [(self._labels[float(branches[r, 0])], int(branches[r, 2])) for r in range(m)
                if branches[r, 1] == _kci.MERGED]
        if into:
            self._merged_warned = True
            names = ", ".join(f"{name} (into solution {k + 1})" for name, k in into)
            warnings.warn(f"ik_analytic: at this pose the branch(es) {names} of the nominal structure reached "
                          f"another branch's solution (merged): near a fold of the arm the pair of solutions of "
                          f"such a branch can lie elsewhere, so a solution may be missing (nominal=False gives the "
                          f"general 6R method; AnalyticIK(robot).calibrated.branches(T) lists every branch; said "
                          f"once per arm)", RobokitWarning, stacklevel=level)


_F64 = np.dtype(np.float64)
_OUT_SHAPE = (_kcf.MAX_ROWS, _kcf.OUT_COLS)  # the kernel's output rows
_FLAGGED = _kci.FLAGGED


def _nearest_rigid(T: np.ndarray) -> np.ndarray:
    """T after the full rigid-transform check (raises), as the nearest rigid transform: R's polar
    factor (for a T that failed the kernel's quick test)."""
    T = check_pose(T)
    U, _, Vt = np.linalg.svd(T[:3, :3])
    Tc = np.eye(4)
    Tc[:3, :3], Tc[:3, 3] = U @ Vt, T[:3, 3]
    return Tc


def _geometry_of(robot: Any) -> _Geometry:
    """:func:`_geometry` of a Robot or a DH table."""
    if hasattr(robot, "links") and hasattr(robot, "convention"):
        from robokit.ik._dh_chain import DHChain

        return _geometry(robot, DHChain(robot), [bool(getattr(l, "flip", False)) for l in robot.links])
    return _geometry(robot, None, None)


def _structure_of(nominal: Any, closed_form: Callable[[Any], Any]) -> list[tuple[str, bool]] | str:
    """The structures to try for ``nominal`` (a robot, a DH table, a spec or a method name), or why none
    (``closed_form`` builds the exact closed form of a robot: ``AnalyticIK``)."""
    if isinstance(nominal, str):
        if nominal not in ("spherical wrist", "three parallel axes"):
            raise InputError(f"nominal: expected a robot or 'spherical wrist' / 'three parallel axes', got {nominal!r}")
        return [(nominal, False), (nominal, True)]
    try:
        ik = closed_form(nominal)
    except InputError:
        raise
    except Exception as exc:  # pragma: no cover - a nominal robokit cannot read
        return f"the nominal arm has no closed form ({exc})"
    if ik.method not in ("spherical wrist", "three parallel axes"):
        return f"the nominal arm has no special structure ({ik.reason})"
    return [(str(ik.method), bool(ik.reversed))]


def calibrated_arm(robot: Any, chain: DHChain | None, flip: Sequence[bool] | None, revolute: Sequence[bool],
                   limits: Sequence[tuple[float, float]] | None, nominal: Any,
                   closed_form: Callable[[Any], Any]) -> tuple[CalibratedArm | None, str]:
    """The :class:`CalibratedArm` of a 6-joint ``robot`` (a Robot; or a DH table with ``chain`` its
    canonical chain and ``flip`` its flipped joints), or (None, why not).

    Parameters
    ----------
    robot : Robot or DHTable
        The arm.
    chain : DHChain or None
        For a DH table: its canonical chain (None for a Robot: its own PoE is used).
    flip : sequence of bool or None
        For a DH table: the flipped joints.
    revolute : sequence of bool
        Which joints are revolute.
    limits : sequence of (lo, hi) or None
        Joint limits with the 1e-12 tolerance folded in.
    nominal : Robot, DHTable, RobotSpec, str or None
        The nominal structure named by the caller (module docstring); None: the robot's recorded
        ``nominal``, else detection.
    closed_form : callable
        ``closed_form(robot_or_table)``: the exact closed form of an arm (an
        :class:`~robokit.ik.closed_form.AnalyticIK` without this calibrated step), for the nominal arm
        and the projected one.

    Returns
    -------
    (CalibratedArm or None, str)
        The arm's exact IK, or None and the reason no nominal structure applies.
    """
    from robokit.description.urdf_to_dh import dh_from_lines

    source = "named by the caller"
    recorded = nominal is None
    if recorded:
        nominal = getattr(robot, "nominal", None)
        source = "the nominal arm it was calibrated from"
    if nominal is not None and not isinstance(nominal, str):
        from robokit.description.loading import load
        from robokit.description.spec import RobotSpec

        if isinstance(nominal, RobotSpec):
            nominal = load(nominal)
    geo = _geometry(robot, chain, flip)
    if nominal is not None:
        tried = _structure_of(nominal, closed_form)
        if isinstance(tried, str):
            return None, tried
        if isinstance(nominal, str):
            source = f"the {nominal} named by the caller"
        else:
            source = f"{source} ({getattr(nominal, 'name', 'a DH table')})"
        candidates = sorted(tried, key=lambda s: max(deviation(geo, s)[0], deviation(geo, s)[1] / geo.reach))
        if recorded:  # a recorded nominal far from this arm (not a calibration of it) is not used
            candidates = [s for s in candidates if deviation(geo, s)[0] <= RECORDED * NEAR_ANGLE
                          and deviation(geo, s)[1] <= RECORDED * NEAR_DISTANCE * geo.reach]
            if not candidates:
                nominal = None
    if nominal is None:
        source = "detected"
        scored = []
        for s in STRUCTURES:
            ang, dist = deviation(geo, s)
            if ang <= NEAR_ANGLE and dist <= NEAR_DISTANCE * geo.reach:
                scored.append((max(ang / NEAR_ANGLE, dist / (NEAR_DISTANCE * geo.reach)), s))
        if not scored:
            return None, (f"no nominal structure within {NEAR_ANGLE:g} rad and {NEAR_DISTANCE:g} × the reach "
                          f"({NEAR_DISTANCE * geo.reach:.3g} m)")
        candidates = [s for _, s in sorted(scored)]
        source = (f"detected (axes within {NEAR_ANGLE:g} rad and {NEAR_DISTANCE:g} × the reach of the "
                  f"structure)")
    twists: list[float | None]
    if nominal is not None and not isinstance(nominal, str):
        ngeo = _geometry_of(nominal)
        if [k for _, _, k in ngeo.lines] != [k for _, _, k in geo.lines]:
            return None, (f"the nominal arm's joints ({''.join(k for _, _, k in ngeo.lines)}) are not this arm's "
                          f"({''.join(k for _, _, k in geo.lines)})")
        extra = _relations(ngeo, 1e-9, 1e-9 * max(1.0, ngeo.reach))  # the nominal's exact relations
        twists = [_signed_angle(ngeo.lines[i][1], ngeo.lines[i + 1][1]) for i in range(len(geo.lines) - 1)]
    else:
        extra = _relations(geo, NEAR_ANGLE, NEAR_DISTANCE * geo.reach)
        twists = []  # right angles and parallels within NEAR_ANGLE made exact
        for i in range(len(geo.lines) - 1):
            a = _signed_angle(geo.lines[i][1], geo.lines[i + 1][1])
            near = min((0.0, 0.5 * math.pi, math.pi), key=lambda t: abs(a - t))
            twists.append(near if abs(a - near) <= NEAR_ANGLE else None)
    why = "the projected arm has no closed form"
    for s in candidates:
        lines = _project(geo.lines, s, extra, twists)
        table = dh_from_lines(lines, geo.M, f"{getattr(robot, 'name', 'arm')}_nominal", geo.qlim)
        ik = closed_form(table)
        if ik.method != s[0] or ik._kernel is None:
            why = f"the arm with its {s[0]} restored is not solved by that closed form ({ik.reason})"
            continue
        return CalibratedArm(geo, s, ik, table, deviation(geo, s), source, revolute, limits), ""
    return None, why
