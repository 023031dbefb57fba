r"""Levenberg–Marquardt inverse kinematics with limits and restarts, and :class:`IKResult`.

The ``"lm"`` back end of :func:`robokit.solve_ik` (:mod:`robokit.ik.backends`): damped least
squares with the damping ``λ = λ₀ ‖e‖² + λ_min`` growing with the error (Sugihara 2011; the
one law of :mod:`robokit.kernels.lm_damping`, which the compiled kernel uses too), joint
limits enforced by projection after every step, full-pose or position-only
mode, a weighted error, and random restarts inside the limits until an iteration, restart or
time budget runs out. For a :class:`robokit.Robot` it evaluates FK and Jacobians with
Pinocchio directly; any other RobotLike through its ``frame_pose``/``jacobian``.

Errors are measured in the target frame: the pose error is the body twist
``log(T(θ)⁻¹ T_target)`` (angular first, rad and m); the position error is
``p_target − p(θ)`` in the base frame (m).
"""
from __future__ import annotations

import math
import time
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Callable

import numpy as np

from robokit.kernels.lm_damping import EARLY_ERROR, EARLY_ITERATION, STALL_LIMIT, lm_damping, lm_retry_damping
from robokit.spatial import lie

if TYPE_CHECKING:
    from robokit.description.protocol import RobotLike
    from robokit.description.robot import Robot

_Closures = tuple[Callable[[np.ndarray], tuple[np.ndarray, float]], Callable[[np.ndarray], np.ndarray], np.ndarray]

__all__ = ["IKResult", "lm_loop"]


def _spd_solve(A: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Solve A x = b for a symmetric positive definite A (LAPACK dposv: Cholesky, small overhead)."""
    from scipy.linalg.lapack import dposv

    _, x, info = dposv(A, b)
    if info != 0:  # not positive definite after all: fall back to a general solve
        return np.linalg.solve(A, b)
    return x



@dataclass
class IKResult:
    """Result of :func:`solve_ik` (and of :func:`robokit.ik.ik_jacobian_transpose`).

    Attributes
    ----------
    q : numpy.ndarray, shape (n,)
        The best configuration found (rad, m; inside the joint limits).
    success : bool
        True if the error is below the tolerance.
    residual : float
        ``hypot(orientation_error, position_error)`` at ``q`` (rad and m mixed for poses).
    position_error : float
        Distance of the frame's origin from the target at ``q``, m.
    orientation_error : float
        Angle of the remaining rotation at ``q``, rad (0 in position mode).
    iterations : int
        Total iterations over all attempts.
    restarts : int
        Random restarts used.
    seconds : float
        Wall time, s.
    method : str
        The back end that answered: ``"analytic"``, ``"planar"``, ``"compiled"``, ``"lm"``;
        ``"transpose"`` for :func:`robokit.ik.ik_jacobian_transpose`.
    tried : dict of str to str
        For each back end ``solve_ik`` considered but did not take the answer from, why (it does
        not support the problem, or its answer missed the tolerance).

    Examples
    --------
    >>> import numpy as np, robokit
    >>> robot = robokit.load("puma560")
    >>> res = robokit.solve_ik(robot, robot.frame_pose(np.full(6, 0.3)))
    >>> res.method, res.success, res.position_error < 1e-9
    ('analytic', True, True)
    """

    q: np.ndarray
    success: bool
    residual: float
    position_error: float
    orientation_error: float
    iterations: int
    restarts: int
    seconds: float
    method: str = ""
    tried: dict[str, str] = field(default_factory=dict)


def lm_loop(robot: Robot | RobotLike, frame: str | None, q: np.ndarray, *, position_only: bool,
            p_target: np.ndarray | None, T_target: np.ndarray | None, w: np.ndarray, tol: float,
            max_iterations: int, max_restarts: int, time_budget: float | None, damping: float,
            min_damping: float, rng: np.random.Generator, t_start: float) -> IKResult:
    """Levenberg–Marquardt with joint limits and random restarts (the ``"lm"`` back end).

    Parameters
    ----------
    robot : :class:`robokit.Robot` (Pinocchio FK/Jacobians) or any RobotLike
        (``frame_pose``/``jacobian``).
    frame : str or None
        The frame to place (None: the tip).
    q : (n,) ndarray
        Initial guess, inside the limits (rad, m).
    position_only : bool
        Match ``p_target`` only, else the pose ``T_target``.
    p_target : (3,) ndarray or None
        Target position of the frame's origin, base frame (m); used in position mode.
    T_target : (4, 4) ndarray or None
        Target pose of the frame, base frame (m); used in pose mode.
    w : (6,) or (3,) ndarray
        Non-negative weights of the body-twist error (ω, v), or of the position error.
    tol : float
        Success when the error norm is below it (rad and m).
    max_iterations, max_restarts : int
        Per attempt; random restarts (uniform inside the limits) after the first attempt.
    time_budget : float or None
        Seconds since ``t_start`` after which no new restart begins.
    damping, min_damping : float
        ``λ = damping·‖e‖² + min_damping`` (Sugihara 2011).
    rng : numpy Generator
        Draws the restarts.
    t_start : float
        ``time.perf_counter()`` at the start of the call (for ``seconds`` and the budget).

    Returns
    -------
    IKResult
        With ``method="lm"``; ``q`` always inside the limits.

    Notes
    -----
    Each step solves ``(JᵀWJ + λI) Δq = JᵀWe`` and projects ``q + Δq`` onto the joint
    limits; an attempt stops when ``‖e‖ < tol``, when it stalls, or when it is still far
    off after 15 iterations.

    Examples
    --------
    >>> import numpy as np, robokit
    >>> robot = robokit.load("twolink")
    >>> T = robot.frame_pose(np.array([0.3, 0.4]))
    >>> res = lm_loop(robot, None, np.zeros(2), position_only=False, p_target=None, T_target=T, w=np.ones(6),
    ...               tol=1e-10, max_iterations=60, max_restarts=5, time_budget=None, damping=1e-2,
    ...               min_damping=1e-9, rng=np.random.default_rng(0), t_start=0.0)
    >>> bool(res.success)
    True
    """
    from robokit.description.robot import Robot

    n = robot.n
    qlim = np.array(robot.qlim, dtype=float)
    lo, hi = qlim[:, 0], qlim[:, 1]
    sample_lo = np.where(np.isfinite(lo), lo, -np.pi)
    sample_hi = np.where(np.isfinite(hi), hi, np.pi)
    if isinstance(robot, Robot):
        error, jac, w_pin = _pinocchio_closures(robot, frame, position_only, p_target, T_target, w)
    else:  # any RobotLike: frame_pose(q, frame) and jacobian(q, frame, reference) (angular first)
        error, jac, w_pin = _generic_closures(robot, frame, position_only, p_target, T_target, w)

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
            lam = lm_damping(err, damping, min_damping)
            q_new = np.clip(q + _spd_solve(A + lam * eye, g), lo, hi)
            e_new, err_new = error(q_new)
            iterations += 1
            if err_new < err:
                q, e, err = q_new, e_new, err_new
                stall = 0
            else:
                # a worse step: retry once with heavier damping (shorter, more gradient-like step)
                q_try = np.clip(q + _spd_solve(A + lm_retry_damping(lam) * eye, g), lo, hi)
                e_try, err_try = error(q_try)
                if err_try < err:
                    q, e, err = q_try, e_try, err_try
                stall += 1
                if stall >= STALL_LIMIT:
                    break
            if it == EARLY_ITERATION and err > EARLY_ERROR:
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
                    iterations, restarts, time.perf_counter() - t_start, "lm")


def _result(robot: Robot, q: np.ndarray, T_target: np.ndarray, tol: float, iterations: int, restarts: int,
            t_start: float, method: str) -> IKResult:
    """The IKResult of ``q`` for a tip pose target, errors measured with Pinocchio FK."""
    T = robot.frame_pose(q)
    rot_err = _rotation_error(T[:3, :3], T_target[:3, :3])
    (_, _, _, x), (_, _, _, y), (_, _, _, z) = T[:3].tolist()
    (_, _, _, xt), (_, _, _, yt), (_, _, _, zt) = T_target[:3].tolist()
    pos_err = math.sqrt((xt - x) ** 2 + (yt - y) ** 2 + (zt - z) ** 2)
    return IKResult(q, bool(rot_err < tol and pos_err < tol), math.hypot(rot_err, pos_err), pos_err, rot_err,
                    iterations, restarts, time.perf_counter() - t_start, method)


def _rotation_error(R: np.ndarray, R_target: np.ndarray) -> float:
    """The angle (rad) of ``Rᵀ R_target``: atan2 of its skew part's norm and (trace − 1)/2 (accurate
    near 0, unlike an arccos of the trace)."""
    (a, b, c), (d, e, f), (g, h, i) = R.tolist()  # Eᵢⱼ = Σₖ Rₖᵢ R_targetₖⱼ, in plain floats (9 numbers:
    (A, B, C), (D, E_, F), (G, H, I) = R_target.tolist()  # numpy's per-call overhead would dominate)
    e00, e11, e22 = a * A + d * D + g * G, b * B + e * E_ + h * H, c * C + f * F + i * I
    e01, e10 = a * B + d * E_ + g * H, b * A + e * D + h * G
    e02, e20 = a * C + d * F + g * I, c * A + f * D + i * G
    e12, e21 = b * C + e * F + h * I, c * B + f * E_ + i * H
    s = 0.5 * math.sqrt((e21 - e12) ** 2 + (e02 - e20) ** 2 + (e10 - e01) ** 2)
    return math.atan2(s, 0.5 * (e00 + e11 + e22 - 1.0))


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
