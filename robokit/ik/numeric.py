r"""Numerical inverse kinematics (Lecture 5; seed 004 ``ikin_body``/``ikin_space``).

Two solvers:

* :func:`ikin_body` / :func:`ikin_space` — the seed library's Newton–Raphson on the twist
  error, with Modern Robotics semantics: ``(thetalist, success)``, no exception for an
  unreachable target. Body form: ``V_b = log(T_sb(θ)⁻¹ T_sd)``, ``θ ← θ + J_b⁺(θ) V_b``
  until ``‖ω_b‖ ≤ eomg`` and ``‖v_b‖ ≤ ev``. Space form: ``V_s = Ad_{T_sb} V_b`` with
  ``J_s``. Up to ``max_iterations`` (default 100; Modern Robotics stops at 20).

* :func:`solve_ik` — a robust solver for any :class:`robokit.Robot` and any frame:
  Levenberg–Marquardt (damped least squares with the damping ``λ = λ₀ ‖e‖² + λ_min``
  growing with the error, after Sugihara 2011), joint limits enforced by projection
  after every step, full-pose or position-only mode, a weighted error, and random
  restarts inside the limits until an iteration, restart or time budget runs out.
  It uses Pinocchio (through the Robot's methods) for FK and Jacobians.

Errors are measured in the target frame: the pose error is the body twist
``log(T(θ)⁻¹ T_target)`` (angular first, rad and m); the position error is
``p_target − p(θ)`` in the base frame (m).
"""
from __future__ import annotations

import math
import time
from dataclasses import dataclass
from typing import TYPE_CHECKING, Callable, cast

import numpy as np
from numpy.typing import ArrayLike

from robokit._arrays import as_matrix, as_scalar, as_vector
from robokit.spatial.se3 import check_transform
from robokit.spatial import lie
from robokit.errors import InputError, InputTypeError

if TYPE_CHECKING:
    from robokit.description.protocol import RobotLike
    from robokit.description.robot import Robot

_Closures = tuple[Callable[[np.ndarray], tuple[np.ndarray, float]], Callable[[np.ndarray], np.ndarray], np.ndarray]

__all__ = ["ikin_body", "ikin_space", "IKResult", "solve_ik"]

# an attempt that is still this far off after this many iterations is abandoned for a fresh seed
_EARLY_IT, _EARLY_ERR = 15, 1e-2


def _check_screws(S: ArrayLike, name: str) -> np.ndarray:
    S = as_matrix(S, name, 6, None)
    return S


def _fk_body(M: np.ndarray, Blist: np.ndarray, theta: np.ndarray) -> np.ndarray:
    from robokit.kinematics.poe import screw_exponentials

    T = M
    for E in screw_exponentials(Blist, theta):
        T = T @ E
    return T


def _jac_body(Blist: np.ndarray, theta: np.ndarray) -> np.ndarray:
    from robokit.kinematics.poe import jacobian_body

    return jacobian_body(Blist, theta)


def _newton_args(screws: ArrayLike, name: str, M: ArrayLike, T: ArrayLike, thetalist0: ArrayLike, eomg: float,
                 ev: float) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, float, float]:
    """The checked arguments of ikin_body/ikin_space: (screws, M, T, θ₀ copy, eomg, ev)."""
    screws = _check_screws(screws, name)
    theta = as_vector(thetalist0, "thetalist0", screws.shape[1]).copy()
    return (screws, check_transform(M, "M"), check_transform(T, "T"), theta,
            as_scalar(eomg, "eomg", nonnegative=True), as_scalar(ev, "ev", nonnegative=True))


def _spd_solve(A: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Solve A x = b for a symmetric positive definite A (LAPACK dposv: Cholesky, small overhead)."""
    from scipy.linalg.lapack import dposv

    _, x, info = dposv(A, b)
    if info != 0:  # not positive definite after all: fall back to a general solve
        return np.linalg.solve(A, b)
    return x


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

    Blist : 6×n body screw axes (columns, angular first) in the end-effector frame at zero;
    M : 4×4 end-effector pose at θ = 0; T : 4×4 target pose; thetalist0 : (n,) initial guess;
    eomg, ev : tolerances on the angular (rad) and linear (m) parts of the body twist error.

    Returns ``(thetalist, success)``; ``success`` is False (no exception) when the iteration
    does not converge, e.g. for an unreachable target — ``thetalist`` is then the iterate with
    the smallest error seen (revolute angles wrapped to (−π, π]), never a diverged value.

    Example: for a planar 2R arm, ``ikin_body(Blist, M, fkin_body(M, Blist, [0.3, 0.4]),
    [0.2, 0.5], 1e-9, 1e-9)`` → ``(array([0.3, 0.4]), True)``.
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

    Slist : 6×n space screw axes; M, T, thetalist0, eomg, ev as in :func:`ikin_body`.
    The error twist is ``V_s = Ad_{T_sb} log(T_sb⁻¹ T)`` and the step ``J_s⁺ V_s``.
    Returns ``(thetalist, success)``.
    """
    Slist, M, T, theta, eomg, ev = _newton_args(Slist, "Slist", M, T, thetalist0, eomg, ev)
    n = Slist.shape[1]
    from robokit.kinematics.poe import prefix_products, screw_exponentials

    Slist = np.ascontiguousarray(Slist)
    best = _Best(Slist)
    for _ in range(max_iterations + 1):
        # forward kinematics and space Jacobian from one set of exponentials
        P = prefix_products(screw_exponentials(Slist, theta))  # prefix products e^{[S1]θ1}⋯e^{[Si]θi}
        Tsb = P[-1] @ M
        Js = Slist.copy()
        if n > 1:
            Js[:, 1:] = np.einsum("kij,jk->ik", lie.adjoint(P[:-1]), Slist[:, 1:])
        Vs = lie.adjoint(Tsb) @ lie.log6(lie.inv(Tsb) @ T)
        if np.linalg.norm(Vs[:3]) <= eomg and np.linalg.norm(Vs[3:]) <= ev:
            return theta, True
        if not best.keep(theta, Vs):
            break
        theta = theta + _pinv_solve(Js, Vs)
    return best.result(), False


@dataclass
class IKResult:
    """Result of :func:`solve_ik`.

    q : (n,) the best configuration found (joint angles, inside the limits);
    success : True if the error is below the tolerance;
    residual : ``hypot(orientation_error, position_error)`` at ``q`` (rad/m mixed for poses);
    position_error, orientation_error : m and rad at ``q`` (orientation NaN-free 0 in position mode);
    iterations : total iterations over all attempts; restarts : random restarts used;
    seconds : wall time.
    """

    q: np.ndarray
    success: bool
    residual: float
    position_error: float
    orientation_error: float
    iterations: int
    restarts: int
    seconds: float


def solve_ik(robot: Robot | RobotLike, target: ArrayLike, frame: str | None = None, q0: ArrayLike | None = None, *,
             position_only: bool = False, weights: ArrayLike | None = None, tol: float = 1e-10,
             max_iterations: int | None = None, max_restarts: int = 100, time_budget: float | None = None,
             damping: float = 1e-2, min_damping: float = 1e-9, rng: int | np.random.Generator | None = None,
             method: str = "auto") -> IKResult:
    """Inverse kinematics for any Robot and frame: closed form, compiled LM, or Pinocchio LM.

    method : "auto" (default) — for a full pose of the robot's tip with no weights and no
    time budget: the closed form when the arm has one (:func:`robokit.ik_analytic`; the
    solution inside the limits nearest ``q0`` is returned), else the compiled
    Levenberg–Marquardt solver (:func:`robokit.kernels.ik.solve_poe_ik`); anything else
    (another frame, position only, weights, a time budget) uses the Pinocchio-based loop
    below. "analytic", "compiled" and "lm" force one of them ("analytic" raises
    ``ValueError`` for an arm without a closed form).

    The Pinocchio-based loop ("lm") is Levenberg–Marquardt with joint limits and random
    restarts, for any Robot and frame:

    robot : a :class:`robokit.Robot`; target : 4×4 pose (or a (3,) position with
    ``position_only``) of ``frame`` (default the robot's tip) in the base frame;
    q0 : (n,) initial guess (default: the robot's zero configuration clipped to the limits);
    weights : (6,) weights of the body-twist error (ω, v), or (3,) in position mode;
    tol : success when the position error (m) and the orientation error (rad) are below it (the
    residual is ``hypot(orientation_error, position_error)``); max_iterations : per attempt (default
    30 for the compiled solver, 60 for the Pinocchio loop);
    max_restarts : random restarts (uniform inside the limits) after the first attempt;
    time_budget : seconds, optional; damping : λ₀ in ``λ = λ₀‖e‖² + min_damping``;
    rng : numpy Generator or seed for the restarts.

    Each step solves ``(JᵀWJ + λI) Δq = JᵀWe`` and projects ``q + Δq`` onto the joint
    limits; an attempt stops when ``‖e‖ < tol``, or when it stalls. The returned
    configuration is always inside the limits.

    Example::

        robot = robokit.load("ur5")
        res = solve_ik(robot, robot.frame_pose(q_true))
        res.success, res.q
    """
    t_start = time.perf_counter()
    from robokit.description.protocol import RobotLike
    from robokit.description.robot import Robot

    is_robot = isinstance(robot, Robot)
    if not is_robot and not isinstance(robot, RobotLike):
        raise InputTypeError(f"robot: expected a robokit.Robot or an object with n, qlim, frame_pose and jacobian "
                        f"(robokit.description.RobotLike), got {type(robot).__name__}")
    n = robot.n
    lo = np.asarray(robot.qlim, dtype=float)[:, 0]
    hi = np.asarray(robot.qlim, dtype=float)[:, 1]
    sample_lo = np.where(np.isfinite(lo), lo, -np.pi)
    sample_hi = np.where(np.isfinite(hi), hi, np.pi)
    p_target = T_target = None
    if position_only:
        p_target = as_vector(target if np.ndim(target) == 1 else np.asarray(target)[:3, 3], "target", 3)
        w = np.ones(3) if weights is None else as_vector(weights, "weights", 3)
    else:
        T_target = check_transform(target, "target")
        w = np.ones(6) if weights is None else as_vector(weights, "weights", 6)
    if np.any(w < 0):
        raise InputError(f"weights: expected non-negative entries, got {w}")
    q = np.clip(np.zeros(n) if q0 is None else as_vector(q0, "q0", n), lo, hi)
    tol = as_scalar(tol, "tol", positive=True)

    if method not in ("auto", "analytic", "compiled", "lm"):
        raise InputError(f"method: expected 'auto', 'analytic', 'compiled' or 'lm', got {method!r}")
    plain = (is_robot and not position_only and weights is None and time_budget is None
             and (frame is None or frame == getattr(robot, "tip", None)))
    if method in ("analytic", "compiled") and not plain:
        raise InputError(f"method: {method!r} solves a full pose of the robot's tip without weights or time budget")
    if plain and method in ("auto", "analytic"):
        assert T_target is not None  # plain: not position_only
        res = _solve_closed_form(cast("Robot", robot), T_target, q, tol, t_start, required=method == "analytic")
        if res is not None:
            return res
    if plain and method in ("auto", "compiled"):
        assert T_target is not None  # plain: not position_only
        return _solve_compiled(cast("Robot", robot), T_target, q, tol, 30 if max_iterations is None else max_iterations,
                               max_restarts, rng, t_start)
    if max_iterations is None:
        max_iterations = 60

    rng = np.random.default_rng(rng)
    if is_robot:
        error, jac, w_int = _pinocchio_closures(cast("Robot", robot), frame, position_only, p_target, T_target, w)
    else:  # any RobotLike: frame_pose(q, frame) and jacobian(q, frame, reference) (angular first)
        error, jac, w_int = _generic_closures(robot, frame, position_only, p_target, T_target, w)
    w_pin = w_int

    best_q, best_err = q.copy(), np.inf
    iterations = 0
    restarts = 0
    eye = np.eye(n)
    while True:
        e, err = error(q)
        stall = 0
        for it in range(max_iterations):
            if err < tol:
                break
            J = jac(q)
            JW = J.T * w_pin
            A = JW @ J
            g = JW @ e
            lam = damping * err * err + min_damping
            q_new = np.clip(q + _spd_solve(A + lam * eye, g), lo, hi)
            e_new, err_new = error(q_new)
            iterations += 1
            if err_new < err:
                q, e, err = q_new, e_new, err_new
                stall = 0
            else:
                # a worse step: retry once with heavier damping (shorter, more gradient-like step)
                q_try = np.clip(q + _spd_solve(A + 10.0 * (lam + 1e-6) * eye, g), lo, hi)
                e_try, err_try = error(q_try)
                if err_try < err:
                    q, e, err = q_try, e_try, err_try
                stall += 1
                if stall >= 3:
                    break
            if it == _EARLY_IT and err > _EARLY_ERR:
                break  # far from converging from this seed: a fresh restart is cheaper
        if err < best_err:
            best_q, best_err = q.copy(), err
        out_of_time = time_budget is not None and time.perf_counter() - t_start > time_budget
        if best_err < tol or restarts >= max_restarts or out_of_time:
            break
        restarts += 1
        q = rng.uniform(sample_lo, sample_hi)
    T = robot.frame_pose(best_q, frame)
    if position_only:
        assert p_target is not None
        pos_err, rot_err = float(np.linalg.norm(p_target - T[:3, 3])), 0.0
    else:
        assert T_target is not None  # not position_only
        rot_err = _rotation_error(T[:3, :3], T_target[:3, :3])
        pos_err = float(np.linalg.norm(T_target[:3, 3] - T[:3, 3]))
    return IKResult(best_q, bool(best_err < tol), math.hypot(rot_err, pos_err), pos_err, rot_err,
                    iterations, restarts, time.perf_counter() - t_start)


def _result(robot: Robot, q: np.ndarray, T_target: np.ndarray, tol: float, iterations: int, restarts: int,
            t_start: float) -> IKResult:
    T = robot.frame_pose(q)
    rot_err = _rotation_error(T[:3, :3], T_target[:3, :3])
    d = T_target[:3, 3] - T[:3, 3]
    pos_err = math.sqrt(float(d @ d))
    return IKResult(q, bool(rot_err < tol and pos_err < tol), math.hypot(rot_err, pos_err), pos_err, rot_err,
                    iterations, restarts, time.perf_counter() - t_start)


def _rotation_error(R: np.ndarray, R_target: np.ndarray) -> float:
    """The angle (rad) of ``Rᵀ R_target``: atan2 of its skew part's norm and (trace − 1)/2 (accurate
    near 0, unlike an arccos of the trace)."""
    E = R.T @ R_target
    s = 0.5 * math.sqrt((E[2, 1] - E[1, 2]) ** 2 + (E[0, 2] - E[2, 0]) ** 2 + (E[1, 0] - E[0, 1]) ** 2)
    return math.atan2(s, 0.5 * (E[0, 0] + E[1, 1] + E[2, 2] - 1.0))


def _solve_closed_form(robot: Robot, T_target: np.ndarray, q0: np.ndarray, tol: float, t_start: float,
                       required: bool) -> IKResult | None:
    """The closed form's in-limit solution nearest ``q0`` (None: no closed form, or none of its
    solutions inside the limits — the numerical solver then takes over)."""
    from robokit.ik.closed_form import ik_analytic, ik_analytic_kind

    kind = ik_analytic_kind(robot)
    if not kind.method:
        if required:
            raise InputError(f"method: 'analytic' needs a closed form; {kind.reason}")
        return None
    sols = [s for s in ik_analytic(robot, T_target) if s.within_limits]
    if not sols:
        return None
    revolute = np.linalg.norm(robot.poe.Slist[:3], axis=0) > 1e-12
    Q = np.array([s.q for s in sols], dtype=float)
    D = Q - q0
    D[:, revolute] = np.mod(D[:, revolute] + np.pi, 2 * np.pi) - np.pi  # angles compared modulo 2π
    best = Q[int(np.argmin(np.einsum("ij,ij->i", D, D)))].copy()
    res = _result(robot, best, T_target, tol, 0, 0, t_start)
    return res if res.success else None  # a closed form off by more than tol: let LM polish from scratch


def _solve_compiled(robot: Robot, T_target: np.ndarray, q0: np.ndarray, tol: float, max_iterations: int,
                    max_restarts: int, rng: int | np.random.Generator | None, t_start: float) -> IKResult:
    from robokit.kernels.ik import solve_poe_ik

    if isinstance(rng, (int, np.integer)) and not isinstance(rng, bool):
        seed = int(rng)
    else:
        seed = int(np.random.default_rng(rng).integers(2**31 - 1))
    p = robot.poe
    q, ok, iterations, restarts = solve_poe_ik(p.M, p.Slist, T_target, q0, np.asarray(robot.qlim, float), tol=tol,
                                               max_iterations=int(max_iterations),
                                               max_restarts=int(max_restarts), seed=seed)
    return _result(robot, np.asarray(q, float), T_target, tol, int(iterations), int(restarts), t_start)


def _pinocchio_closures(robot: Robot, frame: str | None, position_only: bool, p_target: np.ndarray | None,
                        T_target: np.ndarray | None, w: np.ndarray) -> _Closures:
    """Error and Jacobian evaluated with Pinocchio directly (one Data, no conversions).

    The error is in Pinocchio's twist order (v, ω) — the weights are reordered to match."""
    import pinocchio as pin

    model, data = robot.model, robot.data  # the Robot's reused workspace
    fid = robot.frame_id(frame)
    to_q = (lambda qc: qc) if model.nq == model.nv else robot.q_pin
    if position_only:
        rf = pin.ReferenceFrame.LOCAL_WORLD_ALIGNED
        w_int = w
    else:
        rf = pin.ReferenceFrame.LOCAL
        assert T_target is not None  # not position_only
        M_target = pin.SE3(T_target[:3, :3].copy(), T_target[:3, 3].copy())
        w_int = np.r_[w[3:], w[:3]]

    def error(qc: np.ndarray) -> tuple[np.ndarray, float]:
        pin.forwardKinematics(model, data, to_q(qc))
        oMf = pin.updateFramePlacement(model, data, fid)
        e = p_target - oMf.translation if position_only else pin.log6(oMf.actInv(M_target)).vector
        return e, float(np.sqrt(e @ e))

    def jac(qc: np.ndarray) -> np.ndarray:
        pin.computeJointJacobians(model, data, to_q(qc))
        J = pin.getFrameJacobian(model, data, fid, rf)
        return J[:3] if position_only else J

    return error, jac, w_int


def _generic_closures(robot: RobotLike, frame: str | None, position_only: bool, p_target: np.ndarray | None,
                      T_target: np.ndarray | None, w: np.ndarray) -> _Closures:
    """Error and Jacobian through ``robot.frame_pose`` / ``robot.jacobian`` (angular first)."""

    def error(qc: np.ndarray) -> tuple[np.ndarray, float]:
        T = robot.frame_pose(qc, frame)
        e = p_target - T[:3, 3] if position_only else lie.log6(lie.inv(T) @ T_target)
        return e, float(np.sqrt(e @ e))

    def jac(qc: np.ndarray) -> np.ndarray:
        if position_only:
            return robot.jacobian(qc, frame, reference="local_world_aligned")[3:, :]
        return robot.jacobian(qc, frame, reference="local")

    return error, jac, w
