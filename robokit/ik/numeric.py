r"""Numerical inverse kinematics (Lecture 5; seed 004 ``ikin_body``/``ikin_space``).

Two solvers:

* :func:`ikin_body` / :func:`ikin_space` — the seed library's Newton–Raphson on the twist
  error, with Modern Robotics semantics: ``(thetalist, success)``, no exception for an
  unreachable target. Body form: ``V_b = log(T_sb(θ)⁻¹ T_sd)``, ``θ ← θ + J_b⁺(θ) V_b``
  until ``‖ω_b‖ ≤ eomg`` and ``‖v_b‖ ≤ ev``. Space form: ``V_s = Ad_{T_sb} V_b`` with
  ``J_s``. Up to ``max_iterations`` (default 100; Modern Robotics stops at 20).

* :func:`solve_ik` — inverse kinematics for any :class:`robokit.Robot` and any frame, by
  the IK back ends of :mod:`robokit.ik.backends` tried in a documented order (closed form,
  planar, compiled Levenberg–Marquardt, Pinocchio Levenberg–Marquardt — :mod:`robokit.ik.lm`);
  ``IKResult.method`` names the one that answered. Deterministic by default (fixed seed).

"""
from __future__ import annotations

import time
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import ArrayLike

from robokit._arrays import as_matrix, as_scalar, as_vector
from robokit._deprecation import renamed_argument, warn_once
from robokit._units import check_radians, radian_ranges, revolute_columns
from robokit.ik.backends import DEFAULT_SEED, IKProblem, backend, solve_problem
from robokit.ik.lm import IKResult
from robokit.ik.solution import CollisionChecker, check_pose
from robokit.spatial.se3 import check_transform
from robokit.spatial import lie
from robokit.errors import InputError, InputTypeError

if TYPE_CHECKING:
    from robokit.description.protocol import RobotLike
    from robokit.description.robot import Robot

__all__ = ["ikin_body", "ikin_space", "IKResult", "solve_ik"]



def _check_screws(S: ArrayLike, name: str) -> np.ndarray:
    S = as_matrix(S, name, 6, None)
    return S


def _fk_body(M: np.ndarray, Blist: np.ndarray, theta: np.ndarray) -> np.ndarray:
    from robokit.kinematics.poe import fkin_body  # the compiled PoE kernel, robokit's one PoE FK

    return fkin_body(M, Blist, theta)


def _jac_body(Blist: np.ndarray, theta: np.ndarray) -> np.ndarray:
    from robokit.kinematics.poe import jacobian_body

    return jacobian_body(Blist, theta)


def _newton_args(screws: ArrayLike, name: str, M: ArrayLike, T: ArrayLike, thetalist0: ArrayLike, eomg: float,
                 ev: float) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, float, float]:
    """The checked arguments of ikin_body/ikin_space: (screws, M, T, θ₀ copy, eomg, ev)."""
    screws = _check_screws(screws, name)
    theta = as_vector(thetalist0, "thetalist0", screws.shape[1]).copy()
    check_radians(theta, *radian_ranges(revolute_columns(screws)), "thetalist0")
    return (screws, check_transform(M, "M"), check_transform(T, "T"), theta,
            as_scalar(eomg, "eomg", nonnegative=True), as_scalar(ev, "ev", nonnegative=True))


def _pinv_solve(J: np.ndarray, V: np.ndarray) -> np.ndarray:
    """``J⁺ V``: for a square non-singular J this is ``J⁻¹ V`` (solved directly, much cheaper than
    an SVD); otherwise the Moore–Penrose pseudo-inverse."""
    if J.shape[0] == J.shape[1]:
        try:
            return np.linalg.solve(J, V)
        except np.linalg.LinAlgError:
            pass
    return np.linalg.pinv(J) @ V


class _Best:
    """The iterate with the smallest error twist seen, returned when Newton–Raphson fails (a
    diverging iteration must not hand back θ ≈ 1e28); revolute angles wrapped to (−π, π]."""

    def __init__(self, screws: np.ndarray) -> None:
        self.revolute = np.linalg.norm(screws[:3], axis=0) > 1e-12
        self.err = np.inf
        self.theta: np.ndarray | None = None

    def keep(self, theta: np.ndarray, V: np.ndarray) -> bool:
        e = float(np.linalg.norm(V))
        if not (np.isfinite(e) and np.isfinite(theta).all()):
            return False
        if e < self.err:
            self.err, self.theta = e, theta.copy()
        return bool(np.abs(theta).max() < 1e6)  # diverged: stop

    def result(self) -> np.ndarray:
        assert self.theta is not None  # keep() is called before the first result()
        t = self.theta.copy()
        t[self.revolute] = np.pi - np.mod(np.pi - t[self.revolute], 2 * np.pi)  # (−π, π]: π stays π
        return t


def ikin_body(Blist: ArrayLike, M: ArrayLike, T: ArrayLike, thetalist0: ArrayLike, eomg: float, ev: float,
              max_iterations: int = 100) -> tuple[np.ndarray, bool]:
    """Newton–Raphson inverse kinematics in the body frame (seed 004 §3, Modern Robotics 6.2).

    Iterates ``θ ← θ + J_b(θ)⁺ V_b`` with the body error twist ``[V_b] = log(T_sb(θ)⁻¹ T)`` until
    ``‖ω_b‖ ≤ eomg`` and ``‖v_b‖ ≤ ev``.

    Parameters
    ----------
    Blist : (6, n) array_like
        Body screw axes (columns, angular first ``(ω; v)``) in the end-effector frame at θ = 0.
    M : (4, 4) array_like
        End-effector pose at θ = 0 in the space frame (metres).
    T : (4, 4) array_like
        Target end-effector pose in the space frame (metres).
    thetalist0 : (n,) array_like
        Initial guess (rad / m).
    eomg : float
        Tolerance on the angular part of the error twist (rad).
    ev : float
        Tolerance on the linear part of the error twist (m).
    max_iterations : int, optional
        Newton steps before giving up; default 100.

    Returns
    -------
    thetalist : (n,) ndarray
        The joint values (rad / m; revolute angles wrapped to (−π, π]).
    success : bool
        False (no exception) when the iteration does not converge, e.g. for an unreachable target —
        ``thetalist`` is then the iterate with the smallest error seen, never a diverged value.

    Examples
    --------
    The planar 2R arm of :func:`robokit.fkin_body` (unit links): the tip at (1, 1) pointing along x
    is reached with the shoulder up and the elbow back, θ = (π/2, −π/2):

    >>> M = np.array([[1., 0, 0, 2], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]])
    >>> Blist = np.array([[0, 0, 1, 0, 2, 0], [0, 0, 1, 0, 1, 0]]).T
    >>> T = np.array([[1., 0, 0, 1], [0, 1, 0, 1], [0, 0, 1, 0], [0, 0, 0, 1]])
    >>> theta, success = rk.ikin_body(Blist, M, T, [1.2, -1.2], 1e-9, 1e-9)
    >>> theta.round(4), success
    (array([ 1.5708, -1.5708]), True)
    """
    Blist, M, T, theta, eomg, ev = _newton_args(Blist, "Blist", M, T, thetalist0, eomg, ev)
    best = _Best(Blist)
    for _ in range(max_iterations + 1):
        Vb = lie.log6(lie.inv(_fk_body(M, Blist, theta)) @ T)
        if np.linalg.norm(Vb[:3]) <= eomg and np.linalg.norm(Vb[3:]) <= ev:
            return theta, True
        if not best.keep(theta, Vb):
            break
        theta = theta + _pinv_solve(_jac_body(Blist, theta), Vb)
    return best.result(), False


def ikin_space(Slist: ArrayLike, M: ArrayLike, T: ArrayLike, thetalist0: ArrayLike, eomg: float, ev: float,
               max_iterations: int = 100) -> tuple[np.ndarray, bool]:
    """Newton–Raphson inverse kinematics in the space frame (seed 004 §3, Modern Robotics 6.2).

    The error twist is ``V_s = Ad_{T_sb} log(T_sb⁻¹ T)`` and the step ``θ ← θ + J_s(θ)⁺ V_s``, until
    ``‖ω_s‖ ≤ eomg`` and ``‖v_s‖ ≤ ev``.

    Parameters
    ----------
    Slist : (6, n) array_like
        Space screw axes (columns, ``(ω; v)``).
    M, T : (4, 4) array_like
        End-effector pose at θ = 0 and the target pose, both in the space frame (metres).
    thetalist0 : (n,) array_like
        Initial guess (rad / m).
    eomg, ev : float
        Tolerances on the angular (rad) and linear (m) parts of the error twist.
    max_iterations : int, optional
        Newton steps before giving up; default 100.

    Returns
    -------
    thetalist : (n,) ndarray
        As :func:`ikin_body`'s (rad / m; revolute angles wrapped to (−π, π]).
    success : bool
        False (no exception) when the iteration does not converge (e.g. an unreachable target);
        ``thetalist`` is then the best iterate seen.

    Examples
    --------
    The planar 2R arm of :func:`robokit.fkin_space` (unit links): the pose of :func:`ikin_body`'s
    example, and a target 3 m away, out of reach:

    >>> M = np.array([[1., 0, 0, 2], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]])
    >>> Slist = np.array([[0, 0, 1, 0, 0, 0], [0, 0, 1, 0, -1, 0]]).T
    >>> T = np.array([[1., 0, 0, 1], [0, 1, 0, 1], [0, 0, 1, 0], [0, 0, 0, 1]])
    >>> theta, success = rk.ikin_space(Slist, M, T, [1.2, -1.2], 1e-9, 1e-9)
    >>> theta.round(4), success
    (array([ 1.5708, -1.5708]), True)
    >>> far = M.copy()
    >>> far[0, 3] = 3.0
    >>> rk.ikin_space(Slist, M, far, [0.2, 1.2], 1e-9, 1e-9)[1]
    False
    """
    Slist, M, T, theta, eomg, ev = _newton_args(Slist, "Slist", M, T, thetalist0, eomg, ev)
    from robokit.kinematics.poe import fkin_space, jacobian_space  # the compiled PoE kernels

    Slist = np.ascontiguousarray(Slist)
    best = _Best(Slist)
    for _ in range(max_iterations + 1):
        Tsb = fkin_space(M, Slist, theta)
        Js = jacobian_space(Slist, theta)
        Vs = lie.adjoint(Tsb) @ lie.log6(lie.inv(Tsb) @ T)
        if np.linalg.norm(Vs[:3]) <= eomg and np.linalg.norm(Vs[3:]) <= ev:
            return theta, True
        if not best.keep(theta, Vs):
            break
        theta = theta + _pinv_solve(Js, Vs)
    return best.result(), False


def _collision_free(robot: Robot | RobotLike, target: ArrayLike, frame: str | None, q0: ArrayLike | None,
                    world: CollisionChecker, max_restarts: int, rng: int | np.random.Generator | None,
                    kw: dict) -> IKResult:
    """solve_ik's answer when it is collision-free in ``world``, else retried from new seeds."""
    g = np.random.default_rng(DEFAULT_SEED if rng is None else rng)
    qlim = np.array(robot.qlim, dtype=float)
    lo = np.where(np.isfinite(qlim[:, 0]), qlim[:, 0], -np.pi)
    hi = np.where(np.isfinite(qlim[:, 1]), qlim[:, 1], np.pi)
    res = None
    for k in range(int(max_restarts) + 1):
        seed = q0 if k == 0 else g.uniform(lo, hi)
        res = solve_ik(robot, target, seed, frame, **kw)
        if res.success and not bool(world.in_collision(res.q)):
            return res
    assert res is not None
    res.success = False
    res.tried["world"] = f"no collision-free solution in {int(max_restarts) + 1} attempts"
    return res


def solve_ik(robot: Robot | RobotLike, T: ArrayLike | None = None, q0: ArrayLike | None = None,
             frame: str | None = None, *, position_only: bool = False, weights: ArrayLike | None = None,
             tol: float = 1e-10, max_iterations: int | None = None, max_restarts: int = 100,
             time_budget: float | None = None, damping: float = 1e-2, min_damping: float = 1e-9,
             rng: int | np.random.Generator | None = None, method: str = "auto",
             world: CollisionChecker | None = None, target: ArrayLike | None = None) -> IKResult:
    """Inverse kinematics for any Robot and frame, by the first IK back end that supports the problem.

    Parameters
    ----------
    robot : :class:`robokit.Robot` or RobotLike
        The arm (any object with ``n``, ``qlim``, ``frame_pose`` and ``jacobian`` works with
        the ``"lm"`` back end).
    T : (4, 4) or (3,) array_like
        Pose of ``frame`` in the base frame (m), or with ``position_only`` its position (3,).
    q0 : (n,) array_like, optional
        Initial guess (rad, m); default the zero configuration; clipped to the limits. The
        closed forms return the in-limit solution nearest it.
    frame : str, optional
        The frame to place (default the robot's tip). The former order
        ``solve_ik(robot, T, frame, q0)`` still works, with a ``DeprecationWarning``.
    position_only : bool
        Match the position only.
    weights : (6,) or (3,) array_like, optional
        Non-negative weights of the body-twist error (ω, v), or of the position error.
    tol : float
        Success when the position error (m) and the orientation error (rad) are below it.
    max_iterations : int, optional
        Per attempt (default 30 for the compiled solver, 60 for the Pinocchio loop).
    max_restarts : int
        Random restarts (uniform inside the limits) after the first attempt.
    time_budget : float, optional
        Seconds after which no new restart begins (the ``"lm"`` back end; the closed forms
        accept it and take microseconds).
    damping, min_damping : float
        ``λ = damping·‖e‖² + min_damping`` of the LM steps.
    rng : int or numpy Generator, optional
        Seeds the restarts. Default: the fixed seed :data:`robokit.ik.backends.DEFAULT_SEED`
        (0), so the same call gives the same answer on every run — on a redundant arm too;
        pass another seed (or a Generator) for another answer.
    method : str
        ``"auto"`` (default): the back ends of :mod:`robokit.ik.backends` in their documented
        order — ``"analytic"`` (closed form), ``"planar"``, ``"compiled"`` (compiled LM),
        ``"lm"`` (Pinocchio LM) —, the first that supports the problem and meets ``tol``.
        A name picks that back end only.
    world : :class:`robokit.collision.World`, optional
        Collision-free answers only: a solution where ``world.in_collision`` is True is
        rejected and the solve repeated from a new seed (``q0`` first, then up to
        ``max_restarts`` seeds uniform in the limits from ``rng``); ``.success`` is False if
        no collision-free solution was found (``.tried["world"]`` says so).
    target : (4, 4) or (3,) array_like, optional
        The former name of ``T`` (deprecated; give one of the two).

    Returns
    -------
    IKResult
        ``.q`` (n,) inside the limits, ``.success``, the errors, and ``.method``: the back end
        that answered (``.tried``: why the earlier ones did not).

    Raises
    ------
    InputError
        For bad arguments, an unknown ``method``, or a named ``method`` that does not support
        the problem (e.g. ``method="compiled"`` with ``weights``): the reason is in the
        message. A back end is never swapped silently.

    Notes
    -----
    Lecture 5. The LM back ends solve ``(JᵀWJ + λI) Δq = JᵀWe`` per step and project
    ``q + Δq`` onto the joint limits; the returned configuration is always inside them.

    Examples
    --------
    >>> import numpy as np, robokit
    >>> robot = robokit.load("ur5")
    >>> res = solve_ik(robot, robot.frame_pose(np.full(6, 0.4)))
    >>> bool(res.success), res.method
    (True, 'analytic')
    >>> solve_ik(robot, robot.frame_pose(np.full(6, 0.4)), weights=[1, 1, 1, 1, 1, 0]).method
    'lm'
    """
    t_start = time.perf_counter()
    target = renamed_argument("solve_ik(target=)", T, target, None, "solve_ik")
    if target is None:
        raise InputError("T: expected the target pose (4, 4), or with position_only its position (3,), got None")
    if isinstance(q0, str) and not isinstance(frame, str):  # the former order solve_ik(robot, T, frame, q0)
        warn_once("solve_ik(robot, T, frame, q0)")
        frame, q0 = q0, frame
    if frame is not None and not isinstance(frame, str):
        raise InputTypeError(f"frame: expected a frame name (str) or None, got {type(frame).__name__} "
                             "(the initial guess is q0, the third argument: solve_ik(robot, T, q0))")
    if world is not None:
        if q0 is not None:  # checked here: the attempts' solve_ik calls are robokit's own (silent)
            from robokit.description.robot import check_robot_radians

            check_robot_radians(robot, as_vector(q0, "q0", int(robot.n)), "q0")
        return _collision_free(robot, target, frame, q0, world, max_restarts, rng,
                               dict(position_only=position_only, weights=weights, tol=tol,
                                    max_iterations=max_iterations, max_restarts=max_restarts,
                                    time_budget=time_budget, damping=damping, min_damping=min_damping,
                                    rng=rng, method=method))
    from robokit.description.protocol import RobotLike
    from robokit.description.robot import Robot, check_robot_radians

    if not isinstance(robot, Robot) and not isinstance(robot, RobotLike):
        raise InputTypeError(f"robot: expected a robokit.Robot or an object with n, qlim, frame_pose and jacobian "
                        f"(robokit.description.RobotLike), got {type(robot).__name__}")
    if not isinstance(method, str):
        raise InputError(f"method: expected a string, got {type(method).__name__}")
    if method != "auto":
        backend(method)  # an unknown name fails before any work
    n = robot.n
    qlim = np.array(robot.qlim, dtype=float)
    p_target = T_target = None
    if position_only:
        p_target = as_vector(target if np.ndim(target) == 1 else np.asarray(target)[:3, 3], "T", 3)
        w = None if weights is None else as_vector(weights, "weights", 3)
    else:
        T_target = check_pose(target, "T")  # a clean float (4, 4) rigid transform in ~1 µs
        w = None if weights is None else as_vector(weights, "weights", 6)
    if w is not None and np.any(w < 0):
        raise InputError(f"weights: expected non-negative entries, got {w}")
    if q0 is None:
        q = np.zeros(n)
    else:
        q = as_vector(q0, "q0", n)
        check_robot_radians(robot, q, "q0")  # a seed in degrees would be clipped to the limits unnoticed
    q = np.clip(q, qlim[:, 0], qlim[:, 1])
    tol = as_scalar(tol, "tol", positive=True)
    _count(max_restarts, "max_restarts", 0)
    if max_iterations is not None:
        _count(max_iterations, "max_iterations", 1)
    damping = as_scalar(damping, "damping", nonnegative=True)
    min_damping = as_scalar(min_damping, "min_damping", nonnegative=True)
    if time_budget is not None:
        time_budget = as_scalar(time_budget, "time_budget", positive=True)
    seed, gen = _seeded(rng)
    problem = IKProblem(robot, frame, q, position_only=position_only, T_target=T_target, p_target=p_target,
                        weights=w, q0_given=q0 is not None, tol=tol, max_iterations=max_iterations,
                        max_restarts=int(max_restarts), time_budget=time_budget, damping=float(damping),
                        min_damping=float(min_damping), seed=seed, rng=gen, t_start=t_start)
    return solve_problem(problem, method)


def _count(value: object, name: str, least: int) -> None:
    """InputError unless ``value`` is an integer ≥ ``least`` (bools refused)."""
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)) or value < least:
        raise InputError(f"{name}: expected an integer ≥ {least}, got {value!r}")


def _seeded(rng: int | np.random.Generator | None) -> tuple[int, np.random.Generator | None]:
    """(integer seed, Generator or None) of ``rng``: None → :data:`DEFAULT_SEED`; an int →
    itself (the back ends seed a Generator with it when they need one); a Generator → an
    integer drawn from it (for the compiled solver) and the Generator itself."""
    if rng is None:
        return DEFAULT_SEED, None
    if isinstance(rng, (int, np.integer)) and not isinstance(rng, bool):
        if rng < 0:
            raise InputError(f"rng: expected a non-negative seed, got {rng}")
        return int(rng), None
    if isinstance(rng, np.random.Generator):
        return int(rng.integers(2**31 - 1)), rng
    raise InputError(f"rng: expected None, a non-negative integer seed or a numpy Generator, got {type(rng).__name__}")
