r"""Product-of-exponentials kinematics as compiled loops over the joints (Lecture 4/6,
Modern Robotics ch. 4–5).

Screw axes are the columns of a (6, n) array, angular first ``(ω, v)``.

* space form: ``T(θ) = e^{[S₁]θ₁} ⋯ e^{[Sₙ]θₙ} M``;
  space Jacobian, column i: ``J_s,i = Ad_{e^{[S₁]θ₁}⋯e^{[S_{i−1}]θ_{i−1}}} Sᵢ``;
* body form: ``T(θ) = M e^{[B₁]θ₁} ⋯ e^{[Bₙ]θₙ}``;
  body Jacobian, column i: ``J_b,i = Ad_{e^{−[Bₙ]θₙ}⋯e^{−[B_{i+1}]θ_{i+1}}} Bᵢ``.

Each function here exists twice: ``name`` for one configuration θ (n,) and ``name_batch``
for N configurations (N, n), spread over the CPU cores (``numba.prange`` over blocks of
configurations; each block reuses one small scratch space, so memory beyond the result
stays bounded). Both call the same ``*_into`` routine, so they agree to the last bit.

Arguments must be C-contiguous float64 arrays (the signatures are fixed, so numba builds
one specialisation of each kernel). The single-configuration kernels raise ``ValueError``
when θ has the wrong length or holds NaN/inf; the checked, documented entry points are the
seed functions :func:`robokit.fkin_space`, :func:`robokit.fkin_body`,
:func:`robokit.jacobian_space` and :func:`robokit.jacobian_body`.

Example::

    >>> import numpy as np
    >>> from robokit.kernels.poe import fkin_space
    >>> S = np.array([[0.0], [0.0], [1.0], [0.0], [0.0], [0.0]])  # one joint about z
    >>> M = np.eye(4); M[0, 3] = 1.0
    >>> np.round(fkin_space(M, S, np.array([np.pi / 2]))[:3, 3], 12)
    array([0., 1., 0.])
"""
from __future__ import annotations

import math

import numpy as np

from robokit.kernels._jit import FK_BATCH, njit, prange
from robokit.kernels.lie import adjoint_screw, check_joint_values, copy44, exp_screw, mul_tt_inplace, set_identity

__all__ = [
    "fkin_space", "fkin_body", "jacobian_space", "jacobian_body",
    "fkin_space_batch", "fkin_body_batch", "jacobian_space_batch", "jacobian_body_batch",
    "block_range", "n_blocks", "MAX_BLOCKS", "SERIAL_BELOW", "screw_exponentials",
]

_SIG_FK = "float64[:, ::1](float64[:, ::1], float64[:, ::1], float64[::1])"
_SIG_FK_BATCH = "float64[:, :, ::1](float64[:, ::1], float64[:, ::1], float64[:, ::1])"
_SIG_J = "float64[:, ::1](float64[:, ::1], float64[::1])"
_SIG_J_BATCH = "float64[:, :, ::1](float64[:, ::1], float64[:, ::1])"
_SIG_EXP = "float64[:, :, :, ::1](float64[:, ::1], float64[:, ::1])"


# ------------------------------------------------------------------ blocks for the batched kernels
#: Below this many rows a batched kernel runs serially on the calling thread (calling its
#: ``*_rows`` function from row ``np.int64(0)``: a literal 0 would make numba compile that function
#: a second time, for the constant).
SERIAL_BELOW = 256

#: The batched kernels cut N configurations into at most this many blocks, handed out to
#: the threads by ``prange``; each block allocates its small scratch space once.
MAX_BLOCKS = 64


@njit
def n_blocks(N: int) -> int:
    """How many blocks to cut N configurations into: ``min(N, MAX_BLOCKS)``, at least 1."""
    return max(1, min(N, MAX_BLOCKS))


@njit
def block_range(b: int, nb: int, N: int) -> tuple[int, int]:
    """Configurations [lo, hi) of block b out of nb (contiguous, sizes differ by at most one)."""
    return (b * N) // nb, ((b + 1) * N) // nb


@njit
def check_theta(Slist: np.ndarray, thetalist: np.ndarray) -> None:
    """Raise ``ValueError`` unless θ has one finite value per screw axis."""
    check_joint_values(thetalist, Slist.shape[1], "thetalist", "screw axis (column of the screw list)")


@njit
def check_screws(Slist: np.ndarray) -> None:
    """Raise ``ValueError`` unless the screw list is 6×n and finite (the caller's full checks then
    name the problem: a kernel called straight on the user's arrays checks its constants itself)."""
    if Slist.shape[0] != 6:
        raise ValueError("Slist: expected 6 rows")
    for i in range(6):
        for j in range(Slist.shape[1]):
            if not math.isfinite(Slist[i, j]):
                raise ValueError("Slist: contains NaN or infinite values")


@njit
def check_home(M: np.ndarray) -> None:
    """Raise ``ValueError`` unless M is a 4×4 rigid transform by a quick test (RᵀR = I to 1e-9
    entrywise, det R > 0, last row exactly (0, 0, 0, 1), finite) — stricter than
    :func:`robokit.spatial.check_transform`, which then decides (and names the problem)."""
    if M.shape[0] != 4 or M.shape[1] != 4:
        raise ValueError("M: expected a 4×4 matrix")
    a, b, c, d, e, f, g, h, i = M[0, 0], M[0, 1], M[0, 2], M[1, 0], M[1, 1], M[1, 2], M[2, 0], M[2, 1], M[2, 2]
    dev = max(abs(a * a + d * d + g * g - 1.0), abs(b * b + e * e + h * h - 1.0), abs(c * c + f * f + i * i - 1.0),
              abs(a * b + d * e + g * h), abs(a * c + d * f + g * i), abs(b * c + e * f + h * i))
    det = a * (e * i - f * h) - b * (d * i - f * g) + c * (d * h - e * g)
    if not (math.isfinite(a + b + c + d + e + f + g + h + i + M[0, 3] + M[1, 3] + M[2, 3]) and dev < 1e-9
            and det > 0.0 and M[3, 0] == 0.0 and M[3, 1] == 0.0 and M[3, 2] == 0.0 and M[3, 3] == 1.0):
        raise ValueError("M: not a rigid transform by the quick test")


# ------------------------------------------------------------------ forward kinematics
@njit
def fkin_space_into(M: np.ndarray, Slist: np.ndarray, thetalist: np.ndarray, T: np.ndarray, E: np.ndarray, tmp: np.ndarray) -> None:
    """T ← e^{[S₁]θ₁} ⋯ e^{[Sₙ]θₙ} M (E, tmp: 4×4 scratch)."""
    set_identity(T)
    for i in range(Slist.shape[1]):
        exp_screw(Slist, i, thetalist[i], E)  # E = e^{[Sᵢ]θᵢ}
        mul_tt_inplace(T, E, tmp)  # T ← T E
    mul_tt_inplace(T, M, tmp)  # … M


@njit
def fkin_body_into(M: np.ndarray, Blist: np.ndarray, thetalist: np.ndarray, T: np.ndarray, E: np.ndarray, tmp: np.ndarray) -> None:
    """T ← M e^{[B₁]θ₁} ⋯ e^{[Bₙ]θₙ} (E, tmp: 4×4 scratch)."""
    copy44(M, T)
    for i in range(Blist.shape[1]):
        exp_screw(Blist, i, thetalist[i], E)
        mul_tt_inplace(T, E, tmp)


@njit(_SIG_EXP)
def screw_exponentials(Slist: np.ndarray, thetas: np.ndarray) -> np.ndarray:
    """Every joint's exponential ``e^{[Sⱼ]θₖⱼ}`` (N, n, 4, 4) for screws ``Slist`` (6, n) at the N
    configurations ``thetas`` (N, n): :func:`robokit.kernels.lie.exp_screw` for each, the one
    screw exponential of robokit (the factors of the PoE product, for callers that need them
    one by one: the Newton–Euler link transforms, the numeric IK, the calibration chain). The
    caller checks that ``thetas`` has n columns."""
    N, n = thetas.shape
    out = np.empty((N, n, 4, 4))
    for k in range(N):
        for j in range(n):
            exp_screw(Slist, j, thetas[k, j], out[k, j])
    return out


@njit(_SIG_FK)
def fkin_space(M: np.ndarray, Slist: np.ndarray, thetalist: np.ndarray) -> np.ndarray:
    """End-effector pose (4×4) ``e^{[S₁]θ₁} ⋯ e^{[Sₙ]θₙ} M``; M (4, 4), Slist (6, n), θ (n,) rad or m."""
    check_screws(Slist)
    check_home(M)
    check_theta(Slist, thetalist)
    W = np.empty((3, 4, 4))
    fkin_space_into(M, Slist, thetalist, W[0], W[1], W[2])
    return W[0].copy()


@njit(_SIG_FK)
def fkin_body(M: np.ndarray, Blist: np.ndarray, thetalist: np.ndarray) -> np.ndarray:
    """End-effector pose (4×4) ``M e^{[B₁]θ₁} ⋯ e^{[Bₙ]θₙ}``; M (4, 4), Blist (6, n), θ (n,)."""
    check_screws(Blist)
    check_home(M)
    check_theta(Blist, thetalist)
    W = np.empty((3, 4, 4))
    fkin_body_into(M, Blist, thetalist, W[0], W[1], W[2])
    return W[0].copy()


@njit
def fkin_space_rows(lo: int, hi: int, M: np.ndarray, Slist: np.ndarray, thetas: np.ndarray, out: np.ndarray) -> None:
    """out[k] ← space-form FK of row k, for lo ≤ k < hi (one block of a batched call)."""
    W = np.empty((2, 4, 4))
    for k in range(lo, hi):
        fkin_space_into(M, Slist, thetas[k], out[k], W[0], W[1])


@njit
def fkin_body_rows(lo: int, hi: int, M: np.ndarray, Blist: np.ndarray, thetas: np.ndarray, out: np.ndarray) -> None:
    """out[k] ← body-form FK of row k, for lo ≤ k < hi."""
    W = np.empty((2, 4, 4))
    for k in range(lo, hi):
        fkin_body_into(M, Blist, thetas[k], out[k], W[0], W[1])


@njit(_SIG_FK_BATCH, parallel=True, interpret_while_compiling=FK_BATCH)
def fkin_space_batch(M: np.ndarray, Slist: np.ndarray, thetas: np.ndarray) -> np.ndarray:
    """Poses (N, 4, 4) for the N configurations in the rows of ``thetas`` (N, n), space form."""
    N = thetas.shape[0]
    out = np.empty((N, 4, 4))
    if N < SERIAL_BELOW:  # too few rows to pay for waking the threads
        fkin_space_rows(np.int64(0), N, M, Slist, thetas, out)
        return out
    nb = n_blocks(N)
    for b in prange(nb):
        lo, hi = block_range(b, nb, N)
        fkin_space_rows(lo, hi, M, Slist, thetas, out)
    return out


@njit(_SIG_FK_BATCH, parallel=True, interpret_while_compiling=FK_BATCH)
def fkin_body_batch(M: np.ndarray, Blist: np.ndarray, thetas: np.ndarray) -> np.ndarray:
    """Poses (N, 4, 4) for the N configurations in the rows of ``thetas`` (N, n), body form."""
    N = thetas.shape[0]
    out = np.empty((N, 4, 4))
    if N < SERIAL_BELOW:  # too few rows to pay for waking the threads
        fkin_body_rows(np.int64(0), N, M, Blist, thetas, out)
        return out
    nb = n_blocks(N)
    for b in prange(nb):
        lo, hi = block_range(b, nb, N)
        fkin_body_rows(lo, hi, M, Blist, thetas, out)
    return out


# ------------------------------------------------------------------ Jacobians
@njit
def jacobian_space_into(Slist: np.ndarray, thetalist: np.ndarray, J: np.ndarray, T: np.ndarray, E: np.ndarray, tmp: np.ndarray) -> None:
    """J (6, n) ← space Jacobian: column i is Sᵢ carried by T = e^{[S₁]θ₁}⋯e^{[S_{i−1}]θ_{i−1}}."""
    set_identity(T)
    n = Slist.shape[1]
    for i in range(n):
        adjoint_screw(T, Slist, i, J, i)  # J_s,i = Ad_T Sᵢ
        if i + 1 < n:
            exp_screw(Slist, i, thetalist[i], E)
            mul_tt_inplace(T, E, tmp)  # T ← T e^{[Sᵢ]θᵢ}


@njit
def jacobian_body_into(Blist: np.ndarray, thetalist: np.ndarray, J: np.ndarray, T: np.ndarray, E: np.ndarray, tmp: np.ndarray) -> None:
    """J (6, n) ← body Jacobian: column i is Bᵢ carried by T = e^{−[Bₙ]θₙ}⋯e^{−[B_{i+1}]θ_{i+1}}."""
    set_identity(T)
    n = Blist.shape[1]
    for i in range(n - 1, -1, -1):
        adjoint_screw(T, Blist, i, J, i)  # J_b,i = Ad_T Bᵢ
        if i > 0:
            exp_screw(Blist, i, -thetalist[i], E)
            mul_tt_inplace(T, E, tmp)  # T ← T e^{−[Bᵢ]θᵢ}


@njit(_SIG_J)
def jacobian_space(Slist: np.ndarray, thetalist: np.ndarray) -> np.ndarray:
    """Space Jacobian (6, n), rows (ω; v): the end-effector twist in the space frame per unit θ̇."""
    check_screws(Slist)
    check_theta(Slist, thetalist)
    J = np.empty((6, Slist.shape[1]))
    W = np.empty((3, 4, 4))
    jacobian_space_into(Slist, thetalist, J, W[0], W[1], W[2])
    return J


@njit(_SIG_J)
def jacobian_body(Blist: np.ndarray, thetalist: np.ndarray) -> np.ndarray:
    """Body Jacobian (6, n), rows (ω; v): the end-effector twist in its own frame per unit θ̇."""
    check_screws(Blist)
    check_theta(Blist, thetalist)
    J = np.empty((6, Blist.shape[1]))
    W = np.empty((3, 4, 4))
    jacobian_body_into(Blist, thetalist, J, W[0], W[1], W[2])
    return J


@njit
def jacobian_space_rows(lo: int, hi: int, Slist: np.ndarray, thetas: np.ndarray, out: np.ndarray) -> None:
    """out[k] ← space Jacobian of row k, for lo ≤ k < hi."""
    W = np.empty((3, 4, 4))
    for k in range(lo, hi):
        jacobian_space_into(Slist, thetas[k], out[k], W[0], W[1], W[2])


@njit
def jacobian_body_rows(lo: int, hi: int, Blist: np.ndarray, thetas: np.ndarray, out: np.ndarray) -> None:
    """out[k] ← body Jacobian of row k, for lo ≤ k < hi."""
    W = np.empty((3, 4, 4))
    for k in range(lo, hi):
        jacobian_body_into(Blist, thetas[k], out[k], W[0], W[1], W[2])



@njit(_SIG_J_BATCH, parallel=True, interpret_while_compiling=FK_BATCH)
def jacobian_space_batch(Slist: np.ndarray, thetas: np.ndarray) -> np.ndarray:
    """Space Jacobians (N, 6, n) for the rows of ``thetas`` (N, n)."""
    N = thetas.shape[0]
    out = np.empty((N, 6, Slist.shape[1]))
    if N < SERIAL_BELOW:  # too few rows to pay for waking the threads
        jacobian_space_rows(np.int64(0), N, Slist, thetas, out)
        return out
    nb = n_blocks(N)
    for b in prange(nb):
        lo, hi = block_range(b, nb, N)
        jacobian_space_rows(lo, hi, Slist, thetas, out)
    return out


@njit(_SIG_J_BATCH, parallel=True, interpret_while_compiling=FK_BATCH)
def jacobian_body_batch(Blist: np.ndarray, thetas: np.ndarray) -> np.ndarray:
    """Body Jacobians (N, 6, n) for the rows of ``thetas`` (N, n)."""
    N = thetas.shape[0]
    out = np.empty((N, 6, Blist.shape[1]))
    if N < SERIAL_BELOW:  # too few rows to pay for waking the threads
        jacobian_body_rows(np.int64(0), N, Blist, thetas, out)
        return out
    nb = n_blocks(N)
    for b in prange(nb):
        lo, hi = block_range(b, nb, N)
        jacobian_body_rows(lo, hi, Blist, thetas, out)
    return out

