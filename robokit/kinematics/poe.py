r"""Product-of-exponentials forward kinematics and Jacobians (Lecture 4/6, seed 004 §3).

Screw axes are the columns of a 6×n array, angular first ``(ω, v)``.

* space form:  ``T(θ) = e^{[S₁]θ₁} ⋯ e^{[Sₙ]θₙ} M``;
  space Jacobian ``J_s = [S₁, Ad_{e^{[S₁]θ₁}} S₂, …, Ad_{e^{[S₁]θ₁}⋯e^{[Sₙ₋₁]θₙ₋₁}} Sₙ]``;
* body form:   ``T(θ) = M e^{[B₁]θ₁} ⋯ e^{[Bₙ]θₙ}``;
  body Jacobian ``J_b = [Ad_{e^{−[Bₙ]θₙ}⋯e^{−[B₂]θ₂}} B₁, …, Bₙ]``.

Each exponential of a unit screw uses the closed form (Rodrigues for the rotation, and
``G(θ)v`` for the translation), so these are exact to rounding. The batched variants
accept a leading dimension of configurations (N, n); every function runs the compiled kernel of
:mod:`robokit.kernels.poe` (one configuration, or the parallel batched kernel for (N, n)).

``thetalist``, the argument every function takes: joint values (rad for revolute, m for
prismatic joints), (n,) for one configuration or (N, n) for N at once (the result then gains a
leading N axis). Every function raises :class:`~robokit.errors.InputError` when a shape does not
match, a value is NaN or infinite, or (``fkin_*``) ``M`` is not a rigid transform.
"""
from __future__ import annotations

from math import hypot
from types import ModuleType
from typing import Any, Callable

import numpy as np
from numpy.typing import ArrayLike

from robokit._arrays import as_array, as_matrix, kernel_arrays
from robokit._units import TURN, check_radians, radian_ranges, revolute_columns, surely_radians
from robokit.spatial.se3 import check_transform
from robokit.errors import InputError

__all__ = ["fkin_body", "fkin_space", "jacobian_body", "jacobian_space"]


#: One of robokit's two module-level caches (docs/caches.md): the seed library's constant arguments
#: (screw lists, home poses) given as bare arrays — no Robot to keep them — validated once and
#: remembered by *value* (``(kind, shape, bytes)``; an array changed in place is validated again),
#: at most 256 entries.
_VALIDATED: dict = {}
_kp = None  # robokit.kernels.poe, imported on first use (so `import robokit` does not load numba)


def _kernels() -> ModuleType:
    global _kp
    from robokit.kernels import poe

    _kp = poe
    return poe


_F64 = np.dtype(np.float64)
_FK_NDIMS = (2, 2, 1)  # (M, Slist, thetalist) as the one-configuration FK kernels take them
_J_NDIMS = (2, 1)  # (Slist, thetalist) for the Jacobian kernels


def _screws(S: ArrayLike, name: str) -> np.ndarray:
    """A C-contiguous 6×n float array of screw axes; constants are validated once and remembered
    (by their bytes, so an array changed in place is validated again)."""
    if type(S) is np.ndarray and S.dtype is _F64:
        hit = _VALIDATED.get(("S", S.shape, S.tobytes()))
        if hit is not None:
            return hit
    S = np.array(as_matrix(S, name, 6, None), order="C")  # a writeable copy, as the kernels take it
    if len(_VALIDATED) > 256:
        _VALIDATED.clear()
    _VALIDATED["S", S.shape, S.tobytes()] = S
    return S


def _home(M: ArrayLike) -> np.ndarray:
    """A validated 4×4 home pose (remembered once validated, by its bytes)."""
    if type(M) is np.ndarray and M.dtype is _F64:
        hit = _VALIDATED.get(("M", M.shape, M.tobytes()))
        if hit is not None:
            return hit
    M = np.array(check_transform(M, "M"), order="C")  # a writeable copy, as the kernels take it
    if len(_VALIDATED) > 256:
        _VALIDATED.clear()
    _VALIDATED["M", M.shape, M.tobytes()] = M
    return M


def _theta(thetalist: ArrayLike, n: int, name: str = "thetalist") -> np.ndarray:
    """(n,) or (N, n) finite joint values as a C-contiguous float64 array."""
    th = as_array(thetalist, name, finite=False)
    if th.ndim not in (1, 2) or th.shape[-1] != n:
        raise InputError(f"{name}: expected shape ({n},) or (N, {n}) for {n} screw axes, got shape {th.shape}")
    if not np.isfinite(th).all():
        raise InputError(f"{name}: contains NaN or infinite values")
    th = np.ascontiguousarray(th)
    return th if th.flags.writeable else th.copy()  # the kernels' signatures take writeable arrays


def _radians(th: np.ndarray, S: np.ndarray) -> None:
    """The degrees check of the seed library (robokit._units): every revolute column at ±2π."""
    lo, hi = radian_ranges(revolute_columns(S))
    check_radians(th, lo, hi, "thetalist")


def _run(kernel: Callable[..., np.ndarray], batch: Callable[..., np.ndarray], thetalist: ArrayLike, n: int,
         *args: Any) -> np.ndarray:
    """Checked θ (n,) or (N, n) → the one-configuration or the batched kernel (the slow path);
    ``args[0]`` is the screw list."""
    th = _theta(thetalist, n)
    _radians(th, args[0])
    return kernel(*args, th) if th.ndim == 1 else batch(*args, th)


def _run_fk(kernel: Callable[..., np.ndarray], batch: Callable[..., np.ndarray], thetalist: ArrayLike,
            M: np.ndarray, S: np.ndarray) -> np.ndarray:
    """:func:`_run` for FK with a checked M: the one-configuration kernel refuses an M that is
    rigid only to check_transform's tolerance (its quick test is stricter), which the batched
    kernel (no such test) then answers."""
    th = _theta(thetalist, S.shape[1])
    _radians(th, S)
    if th.ndim == 2:
        return batch(M, S, th)
    try:
        return kernel(M, S, th)
    except ValueError:  # M within check_transform's tolerance of SE(3) but not the kernel's 1e-9
        return batch(M, S, th[None])[0]


def _poe(kernel: Callable[..., np.ndarray], batch: Callable[..., np.ndarray], args: tuple, name: str) -> np.ndarray:
    """The one body of the four PoE functions: ``args`` is ``(M, S, θ)`` for an FK form or
    ``(S, θ)`` for a Jacobian, ``name`` the screw list's name in messages.

    The fast path first: lists, read-only or strided arrays converted once at most; the kernel checks
    θ, the screws' shape and finiteness (and M's rigidity) itself. On a bad value, the full checks
    (the slow path, :func:`_run` / :func:`_run_fk`) name it."""
    fast = kernel_arrays(args, _FK_NDIMS if len(args) == 3 else _J_NDIMS)
    if fast is not None and surely_radians(fast[-1]):
        try:
            return kernel(*fast)
        except ValueError:  # a bad value: the full checks below name it
            pass
    S, thetalist = _screws(args[-2], name), args[-1]
    if len(args) == 2:
        return _run(kernel, batch, thetalist, S.shape[1], S)
    return _run_fk(kernel, batch, thetalist, _home(args[0]), S)


# The screw exponentials of many joints/configurations at once, for the modules that need the factors
# one by one (the Newton–Euler model's link transforms, the numeric IK, the calibration chain). Like the
# FK and the Jacobians, they are the compiled kernels of robokit.kernels (the one screw exponential).


def screw_exponentials(S: np.ndarray, theta: np.ndarray) -> np.ndarray:
    """exp([Sᵢ]θᵢ) for every screw column i: theta (..., n) → (..., n, 4, 4).

    Closed form for a screw with ‖ω‖ ≠ 0 (scaled to a unit axis, θ' = ‖ω‖θ):
    R = I + sin θ' W + (1 − cos θ') W², p = θ' v + (1 − cos θ') W v + (θ' − sin θ') W² v;
    for ω = 0 (prismatic): R = I, p = θ v — computed by :func:`robokit.kernels.lie.exp_screw`
    (through :func:`robokit.kernels.poe.screw_exponentials`).

    Parameters
    ----------
    S : numpy.ndarray, shape (6, n)
        Screw axes, one column per joint, ``(ω; v)``.
    theta : numpy.ndarray, shape (..., n)
        Joint values (rad, m), any leading dimensions.

    Returns
    -------
    numpy.ndarray, shape (..., n, 4, 4)
        The exponentials.

    Examples
    --------
    >>> S = np.array([[0.0], [0.0], [1.0], [0.0], [0.0], [0.0]])  # about z through the origin
    >>> screw_exponentials(S, np.array([np.pi / 2]))[0][:2, :2].round(4).tolist()
    [[0.0, -1.0], [1.0, 0.0]]
    """
    from robokit.kernels.poe import screw_exponentials as kernel

    S = np.ascontiguousarray(S, dtype=float)
    theta = np.asarray(theta, dtype=float)
    n = S.shape[1] if S.ndim == 2 and S.shape[0] == 6 else -1
    if n < 0 or theta.ndim < 1 or theta.shape[-1] != n:
        raise InputError(f"screw_exponentials: expected S (6, n) and theta (..., n), got {S.shape} and {theta.shape}")
    flat = np.ascontiguousarray(theta.reshape(-1, n))
    return kernel(S, flat).reshape(theta.shape + (4, 4))


def fkin_space(M: ArrayLike, Slist: ArrayLike, thetalist: ArrayLike) -> np.ndarray:
    """End-effector pose by the space form of the product of exponentials (Lecture 4, seed 004 §3).

    ``T(θ) = e^{[S₁]θ₁} e^{[S₂]θ₂} ⋯ e^{[Sₙ]θₙ} M`` with each exponential in closed form (Rodrigues
    for the rotation, ``G(θ) v`` for the translation).

    Parameters
    ----------
    M : (4, 4) array_like
        Home pose of the end-effector frame in the space (base) frame, at θ = 0; metres.
    Slist : (6, n) array_like
        Screw axes of the joints in the space frame, one column each, angular first ``(ω; v)``:
        a revolute joint ``(ω̂, −ω̂ × q)`` (q a point on its axis, m), a prismatic one ``(0, v̂)``.
    thetalist : (n,) or (N, n) array_like
        Joint values (rad for revolute, m for prismatic joints), or N configurations at once.

    Returns
    -------
    (4, 4) ndarray, or (N, 4, 4) for N configurations
        Pose of the end-effector in the space frame (rotation and position in metres).

    Raises
    ------
    InputError
        When a shape does not match (``Slist`` not 6×n, ``thetalist`` not (n,) or (N, n)), ``M`` is
        not a rigid transform, or a value is NaN/infinite.

    See Also
    --------
    fkin_body : the same pose from the body-frame screw axes.

    Examples
    --------
    A planar 2R arm with unit links: joint 1 about z at the origin, joint 2 about z at (1, 0, 0),
    the tip at (2, 0, 0) at home. At θ = (0, π/2) the tip is at (1, 1, 0):

    >>> M = np.array([[1., 0, 0, 2], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]])
    >>> Slist = np.array([[0, 0, 1, 0, 0, 0], [0, 0, 1, 0, -1, 0]]).T
    >>> T = rk.fkin_space(M, Slist, [0, np.pi / 2])
    >>> T[:3, 3].round(4)
    array([1., 1., 0.])
    >>> rk.fkin_space(M, Slist, np.zeros((5, 2))).shape  # five configurations at once
    (5, 4, 4)
    """
    k = _kp or _kernels()
    return _poe(k.fkin_space, k.fkin_space_batch, (M, Slist, thetalist), "Slist")


def fkin_body(M: ArrayLike, Blist: ArrayLike, thetalist: ArrayLike) -> np.ndarray:
    """End-effector pose by the body form of the product of exponentials (Lecture 4, seed 004 §3).

    ``T(θ) = M e^{[B₁]θ₁} e^{[B₂]θ₂} ⋯ e^{[Bₙ]θₙ}``; the body screws are ``Bᵢ = Ad_{M⁻¹} Sᵢ``.

    Parameters
    ----------
    M : (4, 4) array_like
        Home pose of the end-effector frame in the space (base) frame, at θ = 0; metres.
    Blist : (6, n) array_like
        Screw axes of the joints in the end-effector frame at home, one column each, ``(ω; v)``.
    thetalist : (n,) or (N, n) array_like
        Joint values (the module docstring).

    Returns
    -------
    (4, 4) ndarray, or (N, 4, 4) for N configurations
        Pose of the end-effector in the space frame (metres), the same as :func:`fkin_space`.

    Examples
    --------
    The planar 2R arm of :func:`fkin_space` (unit links), seen from its tip: joint 1's axis is 2 m
    behind the tip, joint 2's 1 m, so ``B₁ = (0, 0, 1, 0, 2, 0)``, ``B₂ = (0, 0, 1, 0, 1, 0)``.
    Turning joint 1 by π/2 swings the tip from (2, 0) to (0, 2):

    >>> M = np.array([[1., 0, 0, 2], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]])
    >>> Blist = np.array([[0, 0, 1, 0, 2, 0], [0, 0, 1, 0, 1, 0]]).T
    >>> rk.fkin_body(M, Blist, [np.pi / 2, 0]).round(4)
    array([[ 0., -1.,  0.,  0.],
           [ 1.,  0.,  0.,  2.],
           [ 0.,  0.,  1.,  0.],
           [ 0.,  0.,  0.,  1.]])
    """
    k = _kp or _kernels()
    return _poe(k.fkin_body, k.fkin_body_batch, (M, Blist, thetalist), "Blist")


def jacobian_space(Slist: ArrayLike, thetalist: ArrayLike) -> np.ndarray:
    """Space Jacobian ``J_s(θ)`` (Lecture 6, seed 004 §3): the end-effector twist in the space frame.

    Column i is ``Ad_{e^{[S₁]θ₁} ⋯ e^{[S_{i−1}]θ_{i−1}}} Sᵢ`` (column 1 is ``S₁``), so that
    ``V_s = J_s(θ) θ̇``. Its linear rows are the velocity of the point of the body at the space
    origin, not of the tool (see :func:`robokit.kinematics.geometric_jacobian` for that).

    Parameters
    ----------
    Slist : (6, n) array_like
        Space-frame screw axes, one column per joint, ``(ω; v)``.
    thetalist : (n,) or (N, n) array_like
        Joint values (the module docstring); the last one does not enter ``J_s``.

    Returns
    -------
    (6, n) ndarray, or (N, 6, n) for N configurations
        Rows ``(ω; v)`` (rad/s and m/s per unit joint rate), space-frame axes.

    Examples
    --------
    The planar 2R arm of :func:`fkin_space`: with θ₁ = 0, column 2 is the screw of joint 2,
    ``(ẑ, −ẑ × (1, 0, 0)) = (0, 0, 1, 0, −1, 0)``:

    >>> Slist = np.array([[0, 0, 1, 0, 0, 0], [0, 0, 1, 0, -1, 0]]).T
    >>> rk.jacobian_space(Slist, [0, np.pi / 2]).T.round(4)
    array([[ 0.,  0.,  1.,  0.,  0.,  0.],
           [ 0.,  0.,  1.,  0., -1.,  0.]])
    """
    k = _kp or _kernels()
    return _poe(k.jacobian_space, k.jacobian_space_batch, (Slist, thetalist), "Slist")


def jacobian_body(Blist: ArrayLike, thetalist: ArrayLike) -> np.ndarray:
    """Body Jacobian ``J_b(θ)`` (Lecture 6, seed 004 §3): the end-effector twist in its own frame.

    Column i is ``Ad_{e^{−[Bₙ]θₙ} ⋯ e^{−[B_{i+1}]θ_{i+1}}} Bᵢ`` (column n is ``Bₙ``), so that
    ``V_b = J_b(θ) θ̇``; ``J_b = Ad_{T⁻¹} J_s``.

    Parameters
    ----------
    Blist : (6, n) array_like
        Body-frame screw axes (end-effector frame at home), one column per joint, ``(ω; v)``.
    thetalist : (n,) or (N, n) array_like
        Joint values (the module docstring); ``J_b`` does not depend on the first.

    Returns
    -------
    (6, n) ndarray, or (N, 6, n) for N configurations
        Rows ``(ω; v)``: angular velocity and velocity of the end-effector origin, both in
        end-effector axes, per unit joint rate.

    Examples
    --------
    The planar 2R arm of :func:`fkin_body` at θ = (0, π/2): the tip is at (1, 1) turned by 90°;
    joint 2 moves it along its own y axis at 1 m/s per rad/s, joint 1 along (1, 1) in tip axes:

    >>> Blist = np.array([[0, 0, 1, 0, 2, 0], [0, 0, 1, 0, 1, 0]]).T
    >>> rk.jacobian_body(Blist, [0, np.pi / 2]).T.round(4)
    array([[0., 0., 1., 1., 1., 0.],
           [0., 0., 1., 0., 1., 0.]])
    """
    k = _kp or _kernels()
    return _poe(k.jacobian_body, k.jacobian_body_batch, (Blist, thetalist), "Blist")


