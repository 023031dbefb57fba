r"""The IK back ends: objects that say whether they support a problem (and why not) and solve it.

:func:`robokit.solve_ik` and the capability maps (:mod:`robokit.workspace.reach`) use the
same ordered list, :data:`BACKENDS`:

``"analytic"`` — :class:`ClosedFormBackend`
    :func:`robokit.ik_analytic` (spherical wrist, three parallel axes): the in-limit solution
    nearest ``q0``. Supports a full pose of the robot's tip on a :class:`robokit.Robot` with
    a closed form; ``weights`` with every entry > 0 (an exact solution has zero weighted
    error) and a time budget (it takes microseconds) do not change its answer.
``"planar"`` — :class:`PlanarBackend`
    2 or 3 revolute joints about parallel axes (:mod:`robokit.ik.planar`): the in-limit
    solution nearest ``q0``. Same problems as the closed form.
``"compiled"`` — :class:`CompiledLMBackend`
    The compiled Levenberg–Marquardt solver (:func:`robokit.kernels.ik.solve_poe_ik`) on the
    course PoE parameters: a full pose of the tip, no weights, no time budget.
``"lm"`` — :class:`PinocchioLMBackend`
    Levenberg–Marquardt with limits and restarts (:func:`robokit.ik.lm.lm_loop`), Pinocchio
    FK/Jacobians: everything — any frame, position only, weights, a time budget, any
    RobotLike.

With ``method="auto"`` the back ends are tried in this order; the first that supports the
problem and whose answer meets the tolerance answers, and ``IKResult.method`` names it
(``IKResult.tried`` says why each earlier one did not). ``method=NAME`` uses that one only and
raises :class:`robokit.errors.InputError` with its reason when it does not support the
problem — a back end is never swapped silently.

Randomness: every back end draws from the problem's generator, seeded by default with
:data:`DEFAULT_SEED`, so the same call gives the same answer on every run.
"""
from __future__ import annotations

import math

import time
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Callable, cast

import numpy as np

from robokit.ik.closed_form import analytic_ik
from robokit.ik.lm import IKResult, _result, lm_loop
from robokit.ik.planar import PlanarChain, planar_chain, planar_reason

if TYPE_CHECKING:
    from robokit.description.protocol import RobotLike
    from robokit.description.robot import Robot

__all__ = ["BACKENDS", "DEFAULT_SEED", "IKProblem", "IKBackend", "ClosedFormBackend", "PlanarBackend",
           "CompiledLMBackend", "PinocchioLMBackend", "backend", "reach_backend", "solve_problem"]

#: The seed of ``solve_ik``'s random restarts when ``rng`` is not given.
DEFAULT_SEED = 0


@dataclass
class IKProblem:
    """One inverse-kinematics problem, checked (what :func:`robokit.solve_ik` was asked).

    Parameters
    ----------
    robot : :class:`robokit.Robot` or RobotLike
        The robot.
    frame : str or None
        The frame to place (None: the robot's tip).
    q0 : (n,) ndarray
        Initial guess inside the limits (rad, m).
    position_only : bool
        Place the frame's origin at ``p_target`` only, else the whole pose ``T_target``.
    T_target : (4, 4) ndarray or None
        Target pose of the frame in the base frame (m); None in position mode.
    p_target : (3,) ndarray or None
        Target position of the frame's origin in the base frame (m); None in pose mode.
    weights : (6,) or (3,) ndarray or None
        Error weights (ω, v) or position weights; None when not given.
    q0_given : bool
        True when the caller chose ``q0`` (False: the default, zeros clipped to the limits).
    tol, max_iterations, max_restarts, time_budget, damping, min_damping
        As in :func:`robokit.solve_ik` (``max_iterations`` None: the back end's default).
    seed : int
        Seeds the restarts (:data:`DEFAULT_SEED` unless ``rng`` was given).
    rng : numpy Generator or None
        The generator the Pinocchio loop draws from (None: one seeded with ``seed``, made by
        :meth:`generator` on first use).
    t_start : float
        ``time.perf_counter()`` when the problem was made (default now): the results'
        ``seconds`` and the time budget count from it.

    Examples
    --------
    >>> import numpy as np, robokit
    >>> robot = robokit.load("ur5")
    >>> p = IKProblem.tip_pose(robot, robot.frame_pose(np.zeros(6)))
    >>> ClosedFormBackend().unsupported(p) is None
    True
    """

    robot: Robot | RobotLike
    frame: str | None
    q0: np.ndarray
    position_only: bool = False
    T_target: np.ndarray | None = None
    p_target: np.ndarray | None = None
    weights: np.ndarray | None = None
    q0_given: bool = False
    tol: float = 1e-10
    max_iterations: int | None = None
    max_restarts: int = 100
    time_budget: float | None = None
    damping: float = 1e-2
    min_damping: float = 1e-9
    seed: int = DEFAULT_SEED
    rng: np.random.Generator | None = None
    t_start: float = field(default_factory=time.perf_counter)

    def generator(self) -> np.random.Generator:
        """The generator the restarts draw from: ``rng``, or one seeded with ``seed`` (made on first
        use — a closed-form answer never pays for it).

        Returns
        -------
        numpy.random.Generator
            The same generator on every call.
        """
        if self.rng is None:
            self.rng = np.random.default_rng(self.seed)
        return self.rng

    @classmethod
    def tip_pose(cls, robot: Robot, T: np.ndarray) -> IKProblem:
        """The problem "place the tip at the pose T" from q0 = 0 clipped to the limits, with the
        defaults of :func:`robokit.solve_ik`.

        Parameters
        ----------
        robot : Robot
            The robot.
        T : array_like, shape (4, 4)
            Target tip pose in the base frame, m.

        Returns
        -------
        IKProblem
            ``frame=None``, ``position_only=False``, ``T_target=T``.

        Examples
        --------
        >>> p = IKProblem.tip_pose(rk.load("twolink"), np.eye(4))
        >>> p.q0.tolist(), p.position_only, p.T_target.shape
        ([0.0, 0.0], False, (4, 4))
        """
        qlim = np.array(robot.qlim, dtype=float)
        q0 = np.clip(np.zeros(robot.n), qlim[:, 0], qlim[:, 1])
        return cls(robot, None, q0, T_target=np.asarray(T, dtype=float))


def _is_robot(robot: object) -> bool:
    from robokit.description.robot import Robot

    return isinstance(robot, Robot)


def _tip_pose_reason(p: IKProblem, what: str) -> str | None:
    """Why a back end that solves a full pose of a Robot's tip cannot take ``p`` (None: it can)."""
    if not _is_robot(p.robot):
        return f"{what} needs a robokit.Robot, got {type(p.robot).__name__}"
    if p.position_only:
        return f"{what} solves a full pose, not a position (position_only=True)"
    tip = getattr(p.robot, "tip", None)
    if p.frame is not None and p.frame != tip:
        return f"{what} solves the tip frame {tip!r}, not {p.frame!r}"
    return None


def _exact_reason(p: IKProblem, what: str) -> str | None:
    """Why an exact (closed-form) back end cannot take ``p``: as :func:`_tip_pose_reason`, and
    weights with a zero entry (part of the pose left free: another problem)."""
    why = _tip_pose_reason(p, what)
    if why is None and p.weights is not None and not np.all(p.weights > 0):
        why = f"{what} solves the whole pose; weights with a zero entry leave part of it free"
    return why


def _nearest(Q: np.ndarray, q0: np.ndarray, revolute: np.ndarray) -> np.ndarray:
    """The row of Q (k, n) nearest q0 (n,), revolute differences taken modulo 2π."""
    D = Q - q0
    D[:, revolute] = np.mod(D[:, revolute] + np.pi, 2 * np.pi) - np.pi
    return cast(np.ndarray, Q[int(np.argmin(np.einsum("ij,ij->i", D, D)))].copy())


def _nearest_small(rows: list[np.ndarray], q0: np.ndarray, revolute: list[bool]) -> np.ndarray:
    """:func:`_nearest` for a few rows (the closed form's ≤ 16 solutions of 6 joints), in plain
    Python: numpy's per-call overhead would be most of the time. A copy of the nearest row."""
    ref = q0.tolist()
    two_pi, pi = 2.0 * math.pi, math.pi
    best, best_d = 0, math.inf
    for k, row in enumerate(rows):
        d2 = 0.0
        for v, r, rev in zip(row.tolist(), ref, revolute):
            d = v - r
            if rev:
                d = (d + pi) % two_pi - pi  # np.mod's sign convention (that of the divisor)
            d2 += d * d
        if d2 < best_d:
            best, best_d = k, d2
    return np.array(rows[best], dtype=float)


def _from_random_starts(robot: Robot, targets: np.ndarray, rng: np.random.Generator,
                        reach: Callable[[np.ndarray, np.ndarray, int], bool]) -> np.ndarray:
    """``reach(T, q0, seed)`` for each target T, from a random initial guess q0 uniform inside the
    limits (±π where a limit is infinite) and a seed, both drawn from ``rng`` in that order:
    the iterative back ends' :meth:`IKBackend.reaches`. A (B,) bool array."""
    qlim = np.array(robot.qlim, dtype=float)
    lo = np.where(np.isfinite(qlim[:, 0]), qlim[:, 0], -np.pi)
    hi = np.where(np.isfinite(qlim[:, 1]), qlim[:, 1], np.pi)
    out = np.zeros(len(targets), dtype=bool)
    for b, T in enumerate(targets):
        q0 = rng.uniform(lo, hi)
        out[b] = reach(T, q0, int(rng.integers(2**31 - 1)))
    return out


class IKBackend:
    """An IK back end: ``name``, :meth:`unsupported` (why not, or None) and :meth:`solve`.

    :meth:`reaches` answers "which of these tip poses are reachable inside the limits?" for
    capability maps; the default solves each target with :meth:`solve`. Subclasses take no
    constructor arguments.

    Attributes
    ----------
    name : str
        What :attr:`IKResult.method` records for an answer of this back end.

    Examples
    --------
    >>> [b.name for b in BACKENDS]
    ['analytic', 'planar', 'compiled', 'lm']
    """

    name = ""

    def __init__(self) -> None:
        """No arguments: a back end keeps no settings (a problem's own fields steer it)."""

    def unsupported(self, problem: IKProblem) -> str | None:
        """Whether this back end can solve ``problem``.

        Parameters
        ----------
        problem : IKProblem
            The problem.

        Returns
        -------
        str or None
            None if it can, else the reason (one sentence; ``solve_ik`` records it in
            ``IKResult.tried``).
        """
        raise NotImplementedError

    def solve(self, problem: IKProblem) -> IKResult:
        """Solve a supported ``problem``.

        Parameters
        ----------
        problem : IKProblem
            A problem :meth:`unsupported` accepted.

        Returns
        -------
        IKResult
            ``method`` is :attr:`name`; ``success`` False (no exception) when no answer meets the
            tolerance.
        """
        raise NotImplementedError

    def reaches(self, robot: Robot, targets: np.ndarray, rng: np.random.Generator, restarts: int) -> np.ndarray:
        """Which of these tip poses the back end reaches inside the limits (for capability maps).

        Each target is solved from a random initial guess (drawn from ``rng``, as the restarts'
        seed), so a chunk's answers depend only on the generator's state.

        Parameters
        ----------
        robot : Robot
            The robot.
        targets : numpy.ndarray, shape (B, 4, 4)
            Tip poses in the base frame, m.
        rng : numpy.random.Generator
            Draws the initial guesses and seeds.
        restarts : int
            Random restarts per target (iterative back ends).

        Returns
        -------
        numpy.ndarray of bool, shape (B,)
            True where a solution inside the limits was found.

        Examples
        --------
        Half a turn at the shoulder is reachable, 3 m away is not (links 1 m and 0.8 m):

        >>> robot = rk.load("twolink")
        >>> far = np.eye(4); far[0, 3] = 3.0
        >>> targets = np.stack([robot.frame_pose([np.pi / 2, 0.3]), far])
        >>> backend("planar").reaches(robot, targets, np.random.default_rng(0), 0).tolist()
        [True, False]
        """
        def reach(T: np.ndarray, q0: np.ndarray, seed: int) -> bool:
            p = IKProblem(robot, None, q0, T_target=T, q0_given=True, max_restarts=restarts, seed=seed,
                          max_iterations=60)
            return self.solve(p).success

        return _from_random_starts(robot, targets, rng, reach)

    def __repr__(self) -> str:
        return f"{type(self).__name__}()"


class _ExactBackend(IKBackend):
    """What the two closed-form back ends share: a full tip pose (:func:`_exact_reason`), then
    the arm's own test (:meth:`_why_not`); a solve is the in-limit exact solution nearest ``q0``
    (:meth:`_nearest_solution`), no iterations, or an unsuccessful result at ``q0``."""

    _what = ""  #: the method as the reasons name it ("the closed form")
    _none = ""  #: the reason of a pose with no solution inside the limits

    def _why_not(self, robot: Robot) -> str | None:  # pragma: no cover - overridden
        """None when the arm has this closed form, else why not."""
        raise NotImplementedError

    def _nearest_solution(self, robot: Robot, T: np.ndarray, q0: np.ndarray) -> np.ndarray | None:  # pragma: no cover
        """The in-limit solution for the tip pose T nearest q0, or None when there is none."""
        raise NotImplementedError

    def unsupported(self, problem: IKProblem) -> str | None:
        why = _exact_reason(problem, self._what)
        return why if why is not None else self._why_not(cast("Robot", problem.robot))

    def solve(self, problem: IKProblem) -> IKResult:
        robot = cast("Robot", problem.robot)
        assert problem.T_target is not None  # a full pose (unsupported() says so)
        best = self._nearest_solution(robot, problem.T_target, problem.q0)
        if best is None:
            return _failed(robot, problem, self.name, self._none)
        return _result(robot, best, problem.T_target, problem.tol, 0, 0, problem.t_start, self.name)


class ClosedFormBackend(_ExactBackend):
    """``"analytic"``: every closed-form solution (:func:`robokit.ik_analytic`), the in-limit one
    nearest ``q0``; no iterations (see the module docstring).

    Supports a full tip pose of a :class:`robokit.Robot` that has a closed form.

    Examples
    --------
    >>> robot = rk.load("puma560")
    >>> p = IKProblem.tip_pose(robot, robot.frame_pose(np.full(6, 0.2)))
    >>> res = ClosedFormBackend().solve(p)
    >>> res.method, res.success, np.allclose(robot.frame_pose(res.q), p.T_target)
    ('analytic', True, True)
    >>> ClosedFormBackend().unsupported(IKProblem.tip_pose(rk.load("panda"), np.eye(4)))
    'no closed form: the arm has 7 joints; the closed forms here need exactly 6, or a planar arm of 1–3 joints (use solve_ik)'
    """

    name = "analytic"
    _what = "the closed form"
    _none = "no closed-form solution inside the joint limits"

    def _why_not(self, robot: Robot) -> str | None:
        ik = analytic_ik(robot)
        if ik.method == "planar":  # ik_analytic's planar closed form is PlanarBackend's, vectorised there
            return "a planar arm: the planar back end solves it"
        return None if ik.method else f"no closed form: {ik.reason}"

    def _nearest_solution(self, robot: Robot, T: np.ndarray, q0: np.ndarray) -> np.ndarray | None:
        ik = analytic_ik(robot)
        sols = [s for s in ik.solve(T) if s.within_limits]
        return _nearest_small([s.q for s in sols], q0, ik._revolute) if sols else None

    def reaches(self, robot: Robot, targets: np.ndarray, rng: np.random.Generator, restarts: int) -> np.ndarray:
        """All targets at once: the batched closed form (compiled, parallel over targets), then one
        batched FK of the in-limit solutions as a check.

        Parameters
        ----------
        robot : Robot
            The robot (it has a closed form).
        targets : numpy.ndarray, shape (B, 4, 4)
            Tip poses in the base frame, m.
        rng : numpy.random.Generator
            Unused (the closed form needs no initial guess).
        restarts : int
            Unused.

        Returns
        -------
        numpy.ndarray of bool, shape (B,)
            True where an in-limit solution reproduces the target: every pose entry within
            ``1e-6 · max(1, ‖p_home‖₁)`` (``p_home`` the tip's position at q = 0, m).
        """
        ik = analytic_ik(robot)
        tol_fk = 1e-6 * max(1.0, float(np.abs(robot.poe.M[:3, 3]).sum()))
        targets = np.asarray(targets, dtype=float)
        out = np.zeros(len(targets), dtype=bool)
        if len(targets) == 0:
            return out
        Q, within, _ = ik.solve_batch(targets)
        b, k = np.nonzero(within)
        if len(b):
            err = np.abs(robot.frame_pose_batch(Q[b, k]) - targets[b]).max(axis=(1, 2))
            out[b[err < tol_fk]] = True
        return out


class PlanarBackend(_ExactBackend):
    """``"planar"``: the closed form of planar 2R/3R arms (:mod:`robokit.ik.planar`), the in-limit
    solution nearest ``q0``.

    Supports a full tip pose of a :class:`robokit.Robot` whose joints are parallel revolute axes
    in one plane. The arm's planar geometry is cached per robot and rebuilt when its screws,
    home pose or limits change.

    Examples
    --------
    >>> robot = rk.load("twolink")
    >>> res = PlanarBackend().solve(IKProblem.tip_pose(robot, robot.frame_pose([0.3, 0.4])))
    >>> res.method, res.success, res.q.round(6).tolist()
    ('planar', True, [0.3, 0.4])
    """

    name = "planar"
    _what = "the planar closed form"
    _none = "no planar solution inside the joint limits"

    def _why_not(self, robot: Robot) -> str | None:
        reason = self._planar(robot)[1]
        return None if reason is None else f"not a planar arm: {reason}"

    def _planar(self, robot: Robot) -> tuple[PlanarChain | None, str | None]:
        """(chain, reason) of ``robot``, computed once per robot and kept with it (a Robot never
        changes: :meth:`robokit.Robot.derived`)."""
        def build() -> tuple[PlanarChain | None, str | None]:
            reason = planar_reason(robot)
            return (planar_chain(robot) if reason is None else None), reason

        derived = getattr(robot, "derived", None)
        return cast("tuple[PlanarChain | None, str | None]", build() if derived is None else derived("planar_chain", build))

    def _nearest_solution(self, robot: Robot, T: np.ndarray, q0: np.ndarray) -> np.ndarray | None:
        chain = self._planar(robot)[0]
        assert chain is not None  # unsupported() checked it
        sols = chain.solutions(T)
        return _nearest(np.array(sols), q0, np.ones(robot.n, dtype=bool)) if sols else None

    def reaches(self, robot: Robot, targets: np.ndarray, rng: np.random.Generator, restarts: int) -> np.ndarray:
        chain = self._planar(robot)[0]
        assert chain is not None  # chosen only for planar arms
        return chain.success(targets)


def _kernel_available() -> str | None:
    try:
        from robokit.kernels.ik import solve_poe_ik  # noqa: F401
    except ImportError as exc:  # pragma: no cover - numba is a core dependency
        return f"the compiled solver is unavailable ({exc})"
    return None


class CompiledLMBackend(IKBackend):
    """``"compiled"``: the compiled Levenberg–Marquardt solver on the PoE parameters
    (:func:`robokit.kernels.ik.solve_poe_ik`; 30 iterations per attempt by default).

    Supports a full tip pose of a :class:`robokit.Robot`, without error weights or a time budget.

    Examples
    --------
    >>> import dataclasses
    >>> p = IKProblem.tip_pose(rk.load("twolink"), np.eye(4))
    >>> CompiledLMBackend().unsupported(p) is None
    True
    >>> CompiledLMBackend().unsupported(dataclasses.replace(p, weights=np.ones(6)))
    "the compiled solver has no error weights (method='lm' has)"
    """

    name = "compiled"

    def unsupported(self, problem: IKProblem) -> str | None:
        why = _tip_pose_reason(problem, "the compiled solver")
        if why is None and problem.weights is not None:
            why = "the compiled solver has no error weights (method='lm' has)"
        if why is None and problem.time_budget is not None:
            why = "the compiled solver has no time budget (method='lm' has)"
        return why or _kernel_available()

    def solve(self, problem: IKProblem) -> IKResult:
        from robokit.kernels.ik import solve_poe_ik

        robot = cast("Robot", problem.robot)
        assert problem.T_target is not None  # a full pose (unsupported() says so)
        p = robot.poe
        its = 30 if problem.max_iterations is None else problem.max_iterations
        q, ok, iterations, restarts = solve_poe_ik(p.M, p.Slist, problem.T_target, problem.q0,
                                                   np.array(robot.qlim, dtype=float), tol=problem.tol,
                                                   max_iterations=int(its), max_restarts=int(problem.max_restarts),
                                                   seed=int(problem.seed))
        return _result(robot, np.asarray(q, float), problem.T_target, problem.tol, int(iterations), int(restarts),
                       problem.t_start, self.name)

    def reaches(self, robot: Robot, targets: np.ndarray, rng: np.random.Generator, restarts: int) -> np.ndarray:
        from robokit.kernels.ik import solve_poe_ik

        poe = robot.poe
        qlim = np.array(robot.qlim, dtype=float)

        def reach(T: np.ndarray, q0: np.ndarray, seed: int) -> bool:
            return bool(solve_poe_ik(poe.M, poe.Slist, T, q0, qlim, 1e-10, 60, restarts, seed)[1])

        return _from_random_starts(robot, targets, rng, reach)


class PinocchioLMBackend(IKBackend):
    """``"lm"``: Levenberg–Marquardt with limits, restarts, weights and a time budget, for any
    Robot (Pinocchio) or RobotLike and any frame (:func:`robokit.ik.lm.lm_loop`; 60 iterations
    per attempt by default). It supports every problem: the last back end tried.

    Examples
    --------
    The planar arm (1 m and 0.8 m) reaching (0, 1.8, 0), position only:

    >>> robot = rk.load("twolink")
    >>> p = IKProblem(robot, None, np.zeros(2), position_only=True, p_target=np.array([0.0, 1.8, 0.0]))
    >>> res = PinocchioLMBackend().solve(p)
    >>> res.method, res.success, robot.frame_pose(res.q)[:3, 3].round(6).tolist()
    ('lm', True, [0.0, 1.8, 0.0])
    """

    name = "lm"

    def unsupported(self, problem: IKProblem) -> str | None:
        return None

    def solve(self, problem: IKProblem) -> IKResult:
        robot = problem.robot
        if problem.position_only:
            w = np.ones(3) if problem.weights is None else problem.weights
        else:
            w = np.ones(6) if problem.weights is None else problem.weights
        return lm_loop(robot, problem.frame, problem.q0.copy(), position_only=problem.position_only,
                       p_target=problem.p_target, T_target=problem.T_target, w=w, tol=problem.tol,
                       max_iterations=60 if problem.max_iterations is None else problem.max_iterations,
                       max_restarts=problem.max_restarts, time_budget=problem.time_budget, damping=problem.damping,
                       min_damping=problem.min_damping, rng=problem.generator(), t_start=problem.t_start)


def _failed(robot: Robot, problem: IKProblem, name: str, why: str) -> IKResult:
    """An unsuccessful result at ``q0`` (inside the limits) with the reason in ``tried``."""
    assert problem.T_target is not None
    res = _result(robot, problem.q0.copy(), problem.T_target, problem.tol, 0, 0, problem.t_start, name)
    res.success = False
    res.tried = {name: why}
    return res


#: The back ends in the order ``solve_ik(method="auto")`` and capability maps try them.
BACKENDS: tuple[IKBackend, ...] = (ClosedFormBackend(), PlanarBackend(), CompiledLMBackend(), PinocchioLMBackend())


def backend(name: str) -> IKBackend:
    """The back end called ``name`` (``"analytic"``, ``"planar"``, ``"compiled"``, ``"lm"``).

    Parameters
    ----------
    name : str
        The back end's :attr:`IKBackend.name`.

    Returns
    -------
    IKBackend
        The instance :data:`BACKENDS` holds (one per name, shared).

    Raises
    ------
    InputError
        For another name (the message lists the names).

    Examples
    --------
    >>> backend("lm").name
    'lm'
    """
    from robokit.errors import InputError

    for b in BACKENDS:
        if b.name == name:
            return b
    names = ", ".join(repr(b.name) for b in BACKENDS)
    raise InputError(f"method: expected 'auto' or one of {names}, got {name!r}")


def solve_problem(problem: IKProblem, method: str = "auto") -> IKResult:
    """Solve ``problem`` with the back end ``method``, or the first suitable one (``"auto"``).

    Parameters
    ----------
    problem : IKProblem
    method : str
        ``"auto"`` or a back end's name.

    Returns
    -------
    IKResult
        ``.method`` the back end that answered; ``.tried`` why each earlier one did not.
        With ``"auto"``, when no back end meets the tolerance, the result with the smallest
        residual.

    Raises
    ------
    InputError
        If the named back end does not support the problem (its reason is in the message).

    Examples
    --------
    >>> import numpy as np, robokit
    >>> robot = robokit.load("panda")
    >>> solve_problem(IKProblem.tip_pose(robot, robot.frame_pose(np.full(7, 0.2)))).method
    'compiled'
    """
    from robokit.errors import InputError

    if method != "auto":
        b = backend(method)
        why = b.unsupported(problem)
        if why is not None:
            raise InputError(f"method: {method!r} does not support this problem: {why}")
        return b.solve(problem)
    tried: dict[str, str] = {}
    best: IKResult | None = None
    for b in BACKENDS:
        why = b.unsupported(problem)
        if why is not None:
            tried[b.name] = why
            continue
        res = b.solve(problem)
        if res.success:
            res.tried = tried
            return res
        tried[b.name] = res.tried.get(b.name, f"no solution within tol = {problem.tol:g} "
                                              f"(residual {res.residual:.2e})")
        if best is None or not (res.residual >= best.residual):
            best = res
    assert best is not None  # "lm" supports every problem
    best.tried = {k: v for k, v in tried.items() if k != best.method}
    return best


def reach_backend(robot: Robot) -> IKBackend:
    """The first back end of :data:`BACKENDS` that supports "the tip at a pose" for ``robot``.

    Parameters
    ----------
    robot : :class:`robokit.Robot`

    Returns
    -------
    IKBackend

    Examples
    --------
    >>> import robokit
    >>> reach_backend(robokit.load("rrr")).name
    'planar'
    """
    p = IKProblem.tip_pose(robot, np.eye(4))
    for b in BACKENDS:
        if b.unsupported(p) is None:
            return b
    raise AssertionError("unreachable: the 'lm' back end supports every problem")  # pragma: no cover

