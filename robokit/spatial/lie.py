r"""The vector Lie kernel of SO(3) and SE(3): fast, batched, **unchecked**.

Every function takes arrays whose last axes are the object (a 3-vector, a 6-vector twist
``(ω, v)``, a 3×3 rotation, a 4×4 pose) and any number of leading batch axes, and returns the
same batch shape. Nothing is validated: these are the building blocks the course layers use
on arrays they have already checked. The seed library's functions (``matrix_exp_6``,
``adjoint``, …) are the checked, one-at-a-time versions on top of this kernel.

=============  ==================  ===================  ==========================================
function       input (…, shape)    output (…, shape)    formula
=============  ==================  ===================  ==========================================
``hat``        ω (3,)              [ω] (3, 3)           ``[ω] x = ω × x``
``vee``        [ω] (3, 3)          ω (3,)               inverse of ``hat``
``exp3``       ωθ (3,)             R (3, 3)             Rodrigues: ``I + sin θ [ω̂] + (1 − cos θ)[ω̂]²``
``log3``       R (3, 3)            ωθ (3,), θ ∈ [0, π]  inverse of ``exp3`` (stable near 0 and π)
``exp6``       Sθ (6,)             T (4, 4)             Modern Robotics eq. 3.88
``log6``       T (4, 4)            Sθ (6,)              Modern Robotics §3.3.3.2
``inv``        T (4, 4)            T⁻¹ (4, 4)           ``[[Rᵀ, −Rᵀp], [0, 1]]``
``adjoint``    T (4, 4)            Ad_T (6, 6)          ``[[R, 0], [[p]R, R]]``
``ad``         V (6,)              ad_V (6, 6)          ``[[[ω], 0], [[v], [ω]]]``
=============  ==================  ===================  ==========================================

Twists are angular first, ``(ω, v)``. Example::

    >>> import numpy as np
    >>> from robokit.spatial import lie
    >>> T = lie.exp6(np.array([[0, 0, np.pi / 2, 1, 0, 0], [0, 0, 0, 0, 0, 2]]))   # two poses
    >>> T.shape, np.allclose(lie.log6(T)[1], [0, 0, 0, 0, 0, 2])
    ((2, 4, 4), True)
"""
from __future__ import annotations

from typing import Any, Callable

import numpy as np
from numpy.typing import ArrayLike

__all__ = ["hat", "vee", "exp3", "log3", "exp6", "log6", "inv", "adjoint", "ad", "exp3_coefficients"]


def hat(w: np.ndarray) -> np.ndarray:
    """``[ω]``: the skew-symmetric matrix with ``[ω] x = ω × x``, batched and unchecked.

    Parameters
    ----------
    w : (..., 3) ndarray
        Vectors ω.

    Returns
    -------
    (..., 3, 3) ndarray
        ``[ω]`` for each vector.

    Examples
    --------
    >>> hat(np.array([[1.0, 0, 0], [0, 0, 2.0]]))[1]
    array([[ 0., -2.,  0.],
           [ 2.,  0., -0.],
           [-0.,  0.,  0.]])
    """
    w = np.asarray(w, dtype=float)
    if w.ndim == 1:
        return np.array([[0.0, -w[2], w[1]], [w[2], 0.0, -w[0]], [-w[1], w[0], 0.0]])
    W = np.zeros(w.shape + (3,))
    W[..., 0, 1], W[..., 0, 2], W[..., 1, 2] = -w[..., 2], w[..., 1], -w[..., 0]
    W[..., 1, 0], W[..., 2, 0], W[..., 2, 1] = w[..., 2], -w[..., 1], w[..., 0]
    return W


def vee(W: np.ndarray) -> np.ndarray:
    """ω of ``[ω]`` (the inverse of :func:`hat`), from the lower-left entries; batched, unchecked.

    Parameters
    ----------
    W : (..., 3, 3) ndarray
        Skew-symmetric matrices.

    Returns
    -------
    (..., 3) ndarray
        ω for each matrix.

    Examples
    --------
    >>> vee(hat(np.array([1.0, 2.0, 3.0])))
    array([1., 2., 3.])
    """
    W = np.asarray(W, dtype=float)
    return np.stack([W[..., 2, 1], W[..., 0, 2], W[..., 1, 0]], axis=-1)


def exp3_coefficients(theta: ArrayLike) -> tuple[Any, Any]:
    """``A = sin θ / θ`` and ``B = (1 − cos θ) / θ²`` of Rodrigues' formula (Taylor series below θ = 1e-4;
    above, ``B = 2 sin²(θ/2) / θ²``, which keeps its relative accuracy where ``1 − cos θ`` cancels).

    Parameters
    ----------
    theta : float or array_like
        Rotation angle(s) θ ≥ 0 (rad).

    Returns
    -------
    A : float or ndarray
        ``sin θ / θ`` (1 at θ = 0).
    B : float or ndarray
        ``(1 − cos θ) / θ²`` (½ at θ = 0).

    Examples
    --------
    >>> A, B = exp3_coefficients(0.0)
    >>> float(A), float(B)
    (1.0, 0.5)
    """
    theta = np.asarray(theta, dtype=float)
    if theta.ndim == 0:
        t = float(theta)
        if t < 1e-4:
            t2 = t * t
            return 1.0 - t2 / 6.0 + t2 * t2 / 120.0, 0.5 - t2 / 24.0 + t2 * t2 / 720.0
        h = np.sin(0.5 * t) / t  # 1 − cos θ = 2 sin²(θ/2): no cancellation for small θ
        return np.sin(t) / t, 2.0 * h * h
    small = theta < 1e-4
    safe = np.where(small, 1.0, theta)
    t2 = theta * theta
    A = np.where(small, 1.0 - t2 / 6.0 + t2 * t2 / 120.0, np.sin(safe) / safe)
    h = np.sin(0.5 * safe) / safe  # 1 − cos θ = 2 sin²(θ/2): no cancellation for small θ
    B = np.where(small, 0.5 - t2 / 24.0 + t2 * t2 / 720.0, 2.0 * h * h)
    return A, B


def exp3(w: np.ndarray) -> np.ndarray:
    """``exp([ωθ])``: exponential coordinates → rotations, ``I + A[ωθ] + B[ωθ]²`` (Rodrigues).

    Batched and unchecked.

    Parameters
    ----------
    w : (..., 3) ndarray
        Exponential coordinates ωθ (rad).

    Returns
    -------
    (..., 3, 3) ndarray
        Rotation matrices.

    Examples
    --------
    >>> (exp3(np.array([0, 0, np.pi / 2])) @ [1, 0, 0]).round(4)
    array([0., 1., 0.])
    """
    w = np.asarray(w, dtype=float)
    W = hat(w)
    A, B = exp3_coefficients(np.linalg.norm(w, axis=-1))
    A, B = np.asarray(A)[..., None, None], np.asarray(B)[..., None, None]
    return np.eye(3) + A * W + B * (W @ W)


def _each_matrix(one: Callable[[np.ndarray], np.ndarray], M: np.ndarray, size: int) -> np.ndarray:
    # ``one`` (a matrix -> a (size,) vector) applied to every matrix of a (..., k, k) batch
    M = np.asarray(M, dtype=float)
    if M.ndim == 2:
        return one(M)
    flat = M.reshape((-1,) + M.shape[-2:])
    return np.array([one(m) for m in flat]).reshape(M.shape[:-2] + (size,))


def _log3_one(R: np.ndarray) -> np.ndarray:
    s_vec = 0.5 * np.array([R[2, 1] - R[1, 2], R[0, 2] - R[2, 0], R[1, 0] - R[0, 1]])  # sin θ · ω̂
    s = float(np.linalg.norm(s_vec))
    c = min(1.0, max(-1.0, 0.5 * (R[0, 0] + R[1, 1] + R[2, 2] - 1.0)))
    theta = float(np.arctan2(s, c))
    if c >= 0.0:  # θ ≤ π/2: the skew part is well conditioned
        if theta < 1e-4:
            t2 = theta * theta
            factor = 1.0 + t2 / 6.0 + 7.0 * t2 * t2 / 360.0  # θ / sin θ
        else:
            factor = theta / s
        return factor * s_vec
    # θ > π/2: the symmetric part gives the axis; the skew part only its sign.
    B = 0.5 * (R + R.T) - c * np.eye(3)  # (1 − cos θ) ω̂ ω̂ᵀ
    k = int(np.argmax(np.diag(B)))
    axis = B[:, k] / np.sqrt(B[k, k] * (1.0 - c))
    axis /= np.linalg.norm(axis)
    d = float(axis @ s_vec)
    if d < 0.0 or (d == 0.0 and axis[np.argmax(np.abs(axis))] < 0.0):
        axis = -axis
    return theta * axis


def log3(R: np.ndarray) -> np.ndarray:
    """Exponential coordinates ωθ, θ ∈ [0, π], of rotations (the inverse of :func:`exp3`); batched, unchecked.

    Near θ = 0 a series; beyond θ = π/2 the axis comes from the symmetric part of R (well
    conditioned up to θ = π); at exactly θ = π the axis sign is free and the one whose largest
    component is positive is returned.

    Parameters
    ----------
    R : (..., 3, 3) ndarray
        Rotation matrices (not checked).

    Returns
    -------
    (..., 3) ndarray
        ωθ (rad).

    Examples
    --------
    >>> log3(np.diag([-1.0, -1.0, 1.0])).round(4)     # a half turn about z
    array([0.    , 0.    , 3.1416])
    """
    return _each_matrix(_log3_one, R, 3)


def _exp6_one(V: np.ndarray) -> np.ndarray:
    w, v = V[:3], V[3:]
    theta = float(np.linalg.norm(w))
    W = hat(w)
    W2 = W @ W
    A, B = exp3_coefficients(theta)
    if theta < 1e-4:
        t2 = theta * theta
        C = 1.0 / 6.0 - t2 / 120.0 + t2 * t2 / 5040.0
    else:
        C = (theta - np.sin(theta)) / theta**3
    T = np.eye(4)
    T[:3, :3] = np.eye(3) + A * W + B * W2
    T[:3, 3] = v + B * (W @ v) + C * (W2 @ v)
    return T


def exp6(V: np.ndarray) -> np.ndarray:
    """``exp([V])``: twists with the angle folded in → poses; batched, unchecked (Modern Robotics eq. 3.88).

    ``R = I + A[ω] + B[ω]²``, ``p = (I + B[ω] + C[ω]²) v`` with A, B as in :func:`exp3` and
    ``C = (θ − sin θ)/θ³`` (series near 0); a pure translation (ω = 0) gives ``p = v``.

    Parameters
    ----------
    V : (..., 6) ndarray
        Exponential coordinates ``Sθ = (ωθ, vθ)``.

    Returns
    -------
    (..., 4, 4) ndarray
        Poses.

    Examples
    --------
    >>> exp6(np.array([0, 0, 0, 1.0, 2.0, 3.0]))[:3, 3]     # pure translation
    array([1., 2., 3.])
    """
    V = np.asarray(V, dtype=float)
    if V.ndim == 1:
        return _exp6_one(V)
    w, v = V[..., :3], V[..., 3:]
    theta = np.linalg.norm(w, axis=-1)
    W = hat(w)
    W2 = W @ W
    A, B = exp3_coefficients(theta)
    small = theta < 1e-4
    safe = np.where(small, 1.0, theta)
    t2 = theta * theta
    C = np.where(small, 1.0 / 6.0 - t2 / 120.0 + t2 * t2 / 5040.0, (safe - np.sin(safe)) / safe**3)
    T = np.zeros(V.shape[:-1] + (4, 4))
    T[..., :3, :3] = np.eye(3) + A[..., None, None] * W + B[..., None, None] * W2
    T[..., :3, 3] = v + B[..., None] * np.einsum("...ij,...j->...i", W, v) + C[..., None] * np.einsum(
        "...ij,...j->...i", W2, v)
    T[..., 3, 3] = 1.0
    return T


def _log6_one(T: np.ndarray) -> np.ndarray:
    w = _log3_one(T[:3, :3])
    theta = float(np.linalg.norm(w))
    W = hat(w)
    if theta < 1e-4:
        t2 = theta * theta
        D = 1.0 / 12.0 + t2 / 720.0 + t2 * t2 / 30240.0
    else:
        half = 0.5 * theta
        D = (1.0 - half * np.cos(half) / np.sin(half)) / (theta * theta)
    p = T[:3, 3]
    v = p - 0.5 * (W @ p) + D * (W @ (W @ p))
    return np.concatenate([w, v])


def log6(T: np.ndarray) -> np.ndarray:
    """Exponential coordinates Sθ of poses, rotation angle θ ∈ [0, π] (the inverse of :func:`exp6`); batched.

    ``ω = log3(R)``, ``v = (I − ½[ω] + D[ω]²) p`` with ``D = (1 − (θ/2) cot(θ/2)) / θ²``. Unchecked.

    Parameters
    ----------
    T : (..., 4, 4) ndarray
        Poses.

    Returns
    -------
    (..., 6) ndarray
        ``(ωθ, vθ)``.

    Examples
    --------
    >>> V = np.array([0.2, -0.1, 0.4, 0.5, 0.0, -1.0])
    >>> bool(np.allclose(log6(exp6(V)), V))
    True
    """
    return _each_matrix(_log6_one, T, 6)


def inv(T: np.ndarray) -> np.ndarray:
    """``T⁻¹ = [[Rᵀ, −Rᵀp], [0, 1]]`` of poses; batched, unchecked.

    Parameters
    ----------
    T : (..., 4, 4) ndarray
        Poses ``T_a_b``.

    Returns
    -------
    (..., 4, 4) ndarray
        ``T_b_a``.

    Examples
    --------
    >>> T = exp6(np.array([[0, 0, 1.0, 1, 0, 0], [0, 0, 0, 0, 0, 2.0]]))
    >>> bool(np.allclose(inv(T) @ T, np.eye(4)))
    True
    """
    T = np.asarray(T, dtype=float)
    if T.ndim == 2:
        Ti = np.eye(4)
        Rt = T[:3, :3].T
        Ti[:3, :3] = Rt
        Ti[:3, 3] = -Rt @ T[:3, 3]
        return Ti
    Rt = np.swapaxes(T[..., :3, :3], -1, -2)
    Ti = np.zeros(T.shape)
    Ti[..., :3, :3] = Rt
    Ti[..., :3, 3] = -np.einsum("...ij,...j->...i", Rt, T[..., :3, 3])
    Ti[..., 3, 3] = 1.0
    return Ti


def adjoint(T: np.ndarray) -> np.ndarray:
    """``Ad_T = [[R, 0], [[p]R, R]]`` of poses, so that ``V_a = Ad_{T_ab} V_b``; batched, unchecked.

    Parameters
    ----------
    T : (..., 4, 4) ndarray
        Poses, as for :func:`inv`.

    Returns
    -------
    (..., 6, 6) ndarray
        Adjoint maps of twists ordered (ω, v).

    Examples
    --------
    >>> T = exp6(np.array([0.3, 0.1, -0.2, 1.0, 0.5, 0.0]))
    >>> V = np.array([1.0, 0, 0, 0, 1.0, 0])
    >>> bool(np.allclose(adjoint(inv(T)) @ adjoint(T) @ V, V))      # Ad_{T⁻¹} = Ad_T⁻¹
    True
    """
    T = np.asarray(T, dtype=float)
    R, p = T[..., :3, :3], T[..., :3, 3]
    A = np.zeros(T.shape[:-2] + (6, 6))
    A[..., :3, :3] = R
    A[..., 3:, 3:] = R
    A[..., 3:, :3] = hat(p) @ R
    return A


def ad(V: np.ndarray) -> np.ndarray:
    """``ad_V = [[[ω], 0], [[v], [ω]]]`` of twists, the Lie bracket ``ad_V W = [V, W]``; batched, unchecked.

    Parameters
    ----------
    V : (..., 6) ndarray
        Twists (ω, v).

    Returns
    -------
    (..., 6, 6) ndarray
        ``ad_V``.

    Examples
    --------
    >>> V, W = np.array([0, 0, 1.0, 0, 0, 0]), np.array([1.0, 0, 0, 0, 0, 0])
    >>> ad(V) @ W                         # [ω_V] ω_W = z × x = y
    array([0., 1., 0., 0., 0., 0.])
    """
    V = np.asarray(V, dtype=float)
    A = np.zeros(V.shape[:-1] + (6, 6))
    Wm = hat(V[..., :3])
    A[..., :3, :3] = Wm
    A[..., 3:, 3:] = Wm
    A[..., 3:, :3] = hat(V[..., 3:])
    return A
