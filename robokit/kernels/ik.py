r"""Numerical inverse kinematics of a PoE chain, compiled end to end (Lecture 5, Modern Robotics §6.2).

Given the home pose M, the space screw axes Slist (6, n) and a target pose T_sd, find θ with
``T_sb(θ) = e^{[S₁]θ₁}⋯e^{[Sₙ]θₙ} M = T_sd`` inside the joint limits.

Iteration (damped least squares / Levenberg–Marquardt on the body-frame pose error):

* error twist in the end-effector frame: ``V_b = log(T_sb(θ)⁻¹ T_sd)`` (6,), ``E = ½ ‖V_b‖²``;
* body Jacobian ``J_b = Ad_{T_sb⁻¹} J_s`` (computed in the same pass as the FK);
* step ``Δθ = (J_bᵀ J_b + λ I)⁻¹ J_bᵀ V_b`` (a Cholesky solve of the damped normal equations);
* the damping is robokit's one law (:mod:`robokit.kernels.lm_damping`, Sugihara 2011):
  ``λ = λ₀‖V_b‖² + λ_min`` (λ₀ = 1e-2, λ_min = 1e-9), the same as :func:`robokit.ik.lm.lm_loop`'s;
* the step is projected onto the joint limits (``θ ← clamp(θ + Δθ, θ_min, θ_max)``) and kept
  only if it lowers E; otherwise it is retried once with ``10(λ + 10⁻⁶)`` (a shorter, more
  gradient-like step). A run that is rejected 3 times, is still farther than 1e-2 after 15
  iterations, or uses up ``max_iterations`` is restarted from a uniformly random configuration
  inside the limits (``[−π, π]`` for an unlimited joint), at most ``max_restarts`` times, from
  numba's generator seeded with ``seed``.

Success: orientation error ``‖log(R_sbᵀ R_sd)‖ < tol`` (rad) and position error
``‖p_sb − p_sd‖ < tol`` (m), with θ inside the limits (guaranteed by the projection).

Example::

    >>> import numpy as np, robokit
    >>> from robokit.kernels.ik import solve_poe_ik
    >>> r = robokit.load("ur5"); p = r.poe
    >>> T = r.frame_pose(np.array([0.3, -1.0, 1.2, -0.5, 0.4, 0.2]))
    >>> q, ok, iterations, restarts = solve_poe_ik(p.M, p.Slist, T, np.zeros(6), r.qlim)
"""
from __future__ import annotations

import math

import numpy as np
from numpy.typing import ArrayLike

from robokit._arrays import as_array, as_int, as_scalar, kernel_array
from robokit.errors import InputError
from robokit.kernels._jit import njit
from robokit.kernels.dynamics import cholesky_solve
from robokit.kernels.poe import fkin_space_into
from robokit.kernels.lie import adjoint_screw, exp_screw, inv_t, log_se3, log_so3, mul_tt, mul_tt_inplace, set_identity
from robokit.kernels.lm_damping import (DAMPING, EARLY_ERROR, EARLY_ITERATION, MIN_DAMPING, STALL_LIMIT, lm_damping,
                                        lm_retry_damping)

__all__ = ["solve_poe_ik", "solve_poe_ik_kernel"]

# the one damping law (robokit.kernels.lm_damping), compiled into the loop below
_damping = njit(lm_damping)
_retry_damping = njit(lm_retry_damping)


@njit
def normal_equations(J: np.ndarray, F: np.ndarray, H: np.ndarray, g: np.ndarray) -> None:
    """H ← JᵀJ (n × n) and g ← JᵀF (n,) for a 6 × n Jacobian J and a 6-vector F: the normal
    equations of the least-squares step ``J Δq ≈ F`` (damped by the caller)."""
    n = J.shape[1]
    for i in range(n):
        acc = 0.0
        for r in range(6):
            acc += J[r, i] * F[r]
        g[i] = acc
        for j in range(i, n):
            acc = 0.0
            for r in range(6):
                acc += J[r, i] * J[r, j]
            H[i, j] = acc
            H[j, i] = acc


@njit
def fk_and_space_jacobian(M: np.ndarray, Slist: np.ndarray, theta: np.ndarray, T: np.ndarray, Js: np.ndarray, P: np.ndarray, E: np.ndarray, tmp: np.ndarray) -> None:
    """T ← T_sb(θ) and Js ← J_s(θ) in one pass: the prefix products of the space Jacobian
    ``P = e^{[S₁]θ₁}⋯e^{[S_{i−1}]θ_{i−1}}`` (column i is ``Ad_P Sᵢ``) also build the FK."""
    n = Slist.shape[1]
    set_identity(P)
    for i in range(n):
        adjoint_screw(P, Slist, i, Js, i)
        exp_screw(Slist, i, theta[i], E)
        mul_tt_inplace(P, E, tmp)
    mul_tt(P, M, T)


@njit
def fk_and_body_jacobian(M: np.ndarray, Slist: np.ndarray, theta: np.ndarray, T: np.ndarray, Jb: np.ndarray, Js: np.ndarray, P: np.ndarray, E: np.ndarray, tmp: np.ndarray, Tinv: np.ndarray) -> None:
    """T ← T_sb(θ) and Jb ← J_b(θ): :func:`fk_and_space_jacobian`, then ``J_b = Ad_{T⁻¹} J_s``."""
    n = Slist.shape[1]
    fk_and_space_jacobian(M, Slist, theta, T, Js, P, E, tmp)
    inv_t(T, Tinv)
    for i in range(n):
        adjoint_screw(Tinv, Js, i, Jb, i)


@njit
def pose_error(T: np.ndarray, Td: np.ndarray, Tinv: np.ndarray, Terr: np.ndarray, V: np.ndarray, w3: np.ndarray) -> tuple[float, float, float]:
    """V ← log(T⁻¹ T_d) (body-frame error twist); returns (E = ½‖V‖², orientation error, position error)."""
    inv_t(T, Tinv)
    mul_tt(Tinv, Td, Terr)
    log_se3(Terr, V)
    E = 0.0
    for r in range(6):
        E += V[r] * V[r]
    log_so3(Terr, w3)
    rot_err = math.sqrt(w3[0] * w3[0] + w3[1] * w3[1] + w3[2] * w3[2])
    dx, dy, dz = T[0, 3] - Td[0, 3], T[1, 3] - Td[1, 3], T[2, 3] - Td[2, 3]
    return 0.5 * E, rot_err, math.sqrt(dx * dx + dy * dy + dz * dz)


@njit
def clamp(theta: np.ndarray, qlim: np.ndarray) -> None:
    for i in range(theta.shape[0]):
        if theta[i] < qlim[i, 0]:
            theta[i] = qlim[i, 0]
        elif theta[i] > qlim[i, 1]:
            theta[i] = qlim[i, 1]


@njit
def random_configuration(qlim: np.ndarray, theta: np.ndarray) -> None:
    for i in range(theta.shape[0]):
        lo, hi = qlim[i, 0], qlim[i, 1]
        if not math.isfinite(lo):
            lo = -math.pi
        if not math.isfinite(hi):
            hi = math.pi
        theta[i] = np.random.uniform(lo, hi)


@njit("Tuple((float64[::1], boolean, int64, int64))(float64[:, ::1], float64[:, ::1], float64[:, ::1], "
      "float64[::1], float64[:, ::1], float64, int64, int64, int64)")
def solve_poe_ik_kernel(M: np.ndarray, Slist: np.ndarray, Td: np.ndarray, q0: np.ndarray, qlim: np.ndarray, tol: float, max_iterations: int, max_restarts: int, seed: int) -> tuple[np.ndarray, bool, int, int]:
    """The compiled solver (arguments already checked): returns (θ, success, iterations, restarts)."""
    np.random.seed(seed)
    n = Slist.shape[1]
    T = np.empty((4, 4))
    W = np.empty((6, 4, 4))  # scratch poses
    Jb = np.empty((6, n))
    Js = np.empty((6, n))
    V = np.empty(6)
    V_trial = np.empty(6)
    w3 = np.empty(3)
    H = np.empty((n, n))
    L = np.zeros((n, n))
    g = np.empty(n)
    step = np.empty(n)
    theta = q0.copy()
    trial = np.empty(n)
    clamp(theta, qlim)
    iterations = 0
    for attempt in range(max_restarts + 1):
        if attempt > 0:
            random_configuration(qlim, theta)
        fk_and_body_jacobian(M, Slist, theta, T, Jb, Js, W[0], W[1], W[2], W[3])
        E, rot_err, pos_err = pose_error(T, Td, W[3], W[4], V, w3)
        stall = 0
        for it in range(max_iterations):
            if rot_err < tol and pos_err < tol:
                return theta, True, iterations, attempt
            iterations += 1
            # damped normal equations (J_bᵀ J_b + λ I) Δθ = J_bᵀ V_b, λ by the one law; a step
            # that does not lower E is retried once with heavier damping
            normal_equations(Jb, V, H, g)
            err = math.sqrt(2.0 * E)
            lam = _damping(err, DAMPING, MIN_DAMPING)
            accepted = False
            for retry in range(2):
                if retry == 1:
                    lam = _retry_damping(lam)
                for i in range(n):
                    H[i, i] += lam
                solved = cholesky_solve(H, g, L, step)
                for i in range(n):
                    H[i, i] -= lam
                if not solved:
                    continue
                for i in range(n):
                    trial[i] = theta[i] + step[i]
                clamp(trial, qlim)
                fkin_space_into(M, Slist, trial, W[5], W[1], W[2])
                E_new, rot_new, pos_new = pose_error(W[5], Td, W[3], W[4], V_trial, w3)
                if E_new < E:  # accept
                    for i in range(n):
                        theta[i] = trial[i]
                    fk_and_body_jacobian(M, Slist, theta, T, Jb, Js, W[0], W[1], W[2], W[3])
                    for r in range(6):
                        V[r] = V_trial[r]
                    E, rot_err, pos_err = E_new, rot_new, pos_new
                    accepted = True
                    break
            if accepted and retry == 0:
                stall = 0
            else:
                stall += 1
                if stall >= STALL_LIMIT:
                    break
            if it == EARLY_ITERATION and math.sqrt(2.0 * E) > EARLY_ERROR:
                break  # far from converging from this start: a fresh restart is cheaper
        if rot_err < tol and pos_err < tol:
            return theta, True, iterations, attempt
    return theta, False, iterations, max_restarts


def solve_poe_ik(M: ArrayLike, Slist: ArrayLike, T: ArrayLike, q0: ArrayLike, qlim: ArrayLike, tol: float = 1e-10, max_iterations: int = 30, max_restarts: int = 200, seed: int = 0) -> tuple[np.ndarray, bool, int, int]:
    """Numerical IK of a PoE chain (see the module docstring): θ with ``fkin_space(M, Slist, θ) = T``.

    M : (4, 4) home pose of the end-effector; Slist : (6, n) space screw axes (ω, v);
    T : (4, 4) target pose in the space frame; q0 : (n,) initial guess (rad or m);
    qlim : (n, 2) lower/upper limits (±inf allowed); tol : position (m) and orientation (rad)
    tolerance; max_iterations : per run; max_restarts : random restarts after the first run;
    seed : seed of the restarts' random generator.

    Returns ``(q, success, iterations, restarts)``: q (n,) the solution or the last iterate,
    success a bool, iterations the total number of damped steps, restarts how many random
    restarts were used.
    """
    # C-contiguous and writeable, as the kernel's signature takes them (a Robot's read-only poe arrays:
    # their writeable base, robokit._arrays.writeable_base; other read-only arrays: a copy)
    Slist = kernel_array(as_array(Slist, "Slist", (6, None)))
    n = Slist.shape[1]
    M = kernel_array(as_array(M, "M", (4, 4)))
    T = kernel_array(as_array(T, "T", (4, 4)))
    q0 = kernel_array(as_array(q0, "q0", (n,)))
    qlim = kernel_array(as_array(qlim, "qlim", (n, 2), finite=False))
    if np.isnan(qlim).any() or (qlim[:, 0] > qlim[:, 1]).any():
        raise InputError("qlim: expected rows [lower, upper] with lower <= upper and no NaN")
    tol = as_scalar(tol, "tol", positive=True)
    max_iterations = as_int(max_iterations, "max_iterations", minimum=0)
    max_restarts = as_int(max_restarts, "max_restarts", minimum=0)
    seed = as_int(seed, "seed")
    q, ok, it, rs = solve_poe_ik_kernel(M, Slist, T, q0, qlim, tol, int(max_iterations), int(max_restarts),
                                        int(seed) % (2**32))
    return q, bool(ok), int(it), int(rs)
