r"""Rotations: SO(3), its Lie algebra so(3), the exponential and logarithm (Lecture 2, seed 004 §2).

A rotation matrix ``R`` (3×3, det +1) maps coordinates in a rotated frame to the
reference frame. ``[ω]`` is the 3×3 skew matrix of ω with ``[ω] x = ω × x``. Exponential
coordinates ``ω̂θ`` (a 3-vector) describe a rotation by θ about the unit axis ω̂.

Formulas (Rodrigues):
    exp([ω̂]θ) = I + sin θ [ω̂] + (1 − cos θ) [ω̂]²
    log R: θ = atan2(‖vee((R − Rᵀ)/2)‖, (tr R − 1)/2), [ω̂]θ = θ/(2 sin θ) (R − Rᵀ),
with a Taylor series near θ = 0 and the symmetric part ``(R + Rᵀ)/2 − cos θ I = (1 − cos θ) ω̂ω̂ᵀ``
for θ > π/2, which stays accurate up to and at θ = π.
"""
from __future__ import annotations

import numpy as np

from robokit.errors import InputError
from robokit._arrays import as_matrix, as_vector
from robokit.spatial.lie import exp3, hat, log3
from robokit.spatial.basics import wrap_angle
from numpy.typing import ArrayLike
from typing import Callable

__all__ = [
    "rot_inv",
    "vec_to_so3",
    "so3_to_vec",
    "axis_ang_3",
    "matrix_exp_3",
    "matrix_log_3",
    "project_to_SO3",
    "distance_to_SO3",
    "test_if_SO3",
    "euler_to_matrix",
    "matrix_to_euler",
    "check_rotation",
]

#: A matrix farther than this (Frobenius ‖RᵀR − I‖, or det ≤ 0) from SO(3) is refused
#: where a rotation is required.
SO3_TOLERANCE = 1e-6


def check_rotation(R: ArrayLike, name: str = "R", tol: float = SO3_TOLERANCE) -> np.ndarray:
    """``R`` as a 3×3 float array, or :class:`~robokit.errors.InputError` if it is not a rotation.

    The test is ``distance_to_SO3(R) <= tol`` (orthonormal columns and det +1).

    Parameters
    ----------
    R : (3, 3) array_like
        The candidate rotation.
    name : str
        The argument's name in the error message.
    tol : float
        Largest accepted ``‖RᵀR − I‖_F`` (default :data:`SO3_TOLERANCE`, 1e-6).

    Returns
    -------
    (3, 3) ndarray
        ``R`` as float64.

    Examples
    --------
    >>> check_rotation(np.eye(3)).tolist()[0]
    [1.0, 0.0, 0.0]
    >>> check_rotation(2 * np.eye(3))
    Traceback (most recent call last):
    ...
    robokit.errors.InputError: R: not a rotation matrix (distance to SO(3) 5.2 > 1e-06)
    """
    return _check_group(R, name, 3, _distance_so3, "a rotation matrix", "SO(3)", tol)


def _check_group(M: ArrayLike, name: str, size: int, distance: Callable[[np.ndarray], float], what: str, group: str,
                 tol: float) -> np.ndarray:
    # M as a (size, size) float array if ``distance(M)`` to the group is at most tol, else InputError
    M = as_matrix(M, name, size, size)
    d = distance(M)
    if d > tol:
        raise InputError(f"{name}: not {what} (distance to {group} {d:.3g} > {tol:g})")
    return M


def rot_inv(R: ArrayLike) -> np.ndarray:
    """Inverse of a rotation matrix, ``R⁻¹ = Rᵀ`` (seed 004 §2).

    A 4×4 homogeneous transform is refused with a pointer to :func:`trans_inv` (its inverse is not
    its transpose).

    Parameters
    ----------
    R : (3, 3) array_like
        The rotation to invert (checked: see :mod:`robokit.spatial`).

    Returns
    -------
    (3, 3) ndarray
        ``Rᵀ`` (a new array).

    Examples
    --------
    The inverse of Rz(90°) is Rz(−90°): it maps y back to x.

    >>> Rz90 = np.array([[0, -1, 0], [1, 0, 0], [0, 0, 1]])
    >>> rot_inv(Rz90) @ [0, 1, 0]
    array([1., 0., 0.])
    """
    if np.shape(R) == (4, 4):
        raise InputError("R: got a 4×4 matrix; rot_inv inverts a 3×3 rotation — for a homogeneous "
                         "transform use trans_inv(T)")
    return check_rotation(R, "R").T.copy()


def vec_to_so3(omg: ArrayLike) -> np.ndarray:
    """The 3×3 skew-symmetric matrix ``[ω]`` of a 3-vector ω, so that ``[ω] x = ω × x`` (seed 004 §2).

    Parameters
    ----------
    omg : (3,) array_like
        The vector ω (e.g. an angular velocity, rad/s).

    Returns
    -------
    (3, 3) ndarray
        ``[[0, −ω₃, ω₂], [ω₃, 0, −ω₁], [−ω₂, ω₁, 0]]``.

    Examples
    --------
    >>> vec_to_so3([1, 2, 3])
    array([[ 0., -3.,  2.],
           [ 3.,  0., -1.],
           [-2.,  1.,  0.]])
    >>> bool(np.allclose(vec_to_so3([1, 2, 3]) @ [4, 5, 6], np.cross([1, 2, 3], [4, 5, 6])))
    True
    """
    w = as_vector(omg, "omg", 3)
    return hat(w)


def so3_to_vec(so3mat: ArrayLike) -> np.ndarray:
    """The 3-vector ω of a 3×3 skew-symmetric matrix ``[ω]`` (the inverse of :func:`vec_to_so3`).

    Only the lower-left entries are read: ``(m[2,1], m[0,2], m[1,0])``, as in the seed library.

    Parameters
    ----------
    so3mat : (3, 3) array_like
        The skew matrix ``[ω]``.

    Returns
    -------
    (3,) ndarray
        ω.

    Examples
    --------
    >>> so3_to_vec([[0, -3, 2], [3, 0, -1], [-2, 1, 0]])
    array([1., 2., 3.])
    """
    m = as_matrix(so3mat, "so3mat", 3, 3)
    return np.array([m[2, 1], m[0, 2], m[1, 0]])


def axis_ang_3(expc3: ArrayLike) -> tuple[np.ndarray, float]:
    """Split exponential coordinates ``ω̂θ`` (3-vector) into the unit axis ω̂ and the angle θ ≥ 0.

    Parameters
    ----------
    expc3 : (3,) array_like
        Exponential coordinates ω̂θ of a rotation (rad); not the zero vector (no rotation has no
        axis: :class:`~robokit.errors.InputError`).

    Returns
    -------
    omghat : (3,) ndarray
        Unit rotation axis ω̂.
    theta : float
        Rotation angle θ = ‖expc3‖ (rad).

    Examples
    --------
    >>> omghat, theta = axis_ang_3([0, 0, 2.0])
    >>> omghat, theta
    (array([0., 0., 1.]), 2.0)
    """
    v = as_vector(expc3, "expc3", 3)
    theta = float(np.linalg.norm(v))
    if theta == 0.0:
        raise InputError("expc3: the zero vector has no rotation axis")
    return v / theta, theta


def matrix_exp_3(so3mat: ArrayLike) -> np.ndarray:
    """Rotation matrix ``exp([ω̂]θ) = I + sin θ [ω̂] + (1 − cos θ) [ω̂]²`` of a 3×3 skew matrix
    (Rodrigues' formula, seed 004 §2).

    Parameters
    ----------
    so3mat : (3, 3) array_like
        ``[ω̂]θ``, the skew matrix of the exponential coordinates (rad); only its lower-left
        entries are read.

    Returns
    -------
    (3, 3) ndarray
        The rotation matrix R ∈ SO(3).

    Examples
    --------
    90° about z maps x to y:

    >>> R = matrix_exp_3(vec_to_so3([0, 0, np.pi / 2]))
    >>> R @ [1, 0, 0]
    array([0., 1., 0.])
    """
    return exp3(so3_to_vec(so3mat))


def matrix_log_3(R: ArrayLike) -> np.ndarray:
    """The 3×3 skew matrix ``[ω̂]θ`` with ``exp([ω̂]θ) = R`` and θ ∈ [0, π] (seed 004 §2).

    ``R = I`` gives the zero matrix. θ near π is computed from the symmetric part of R,
    so it stays accurate; at θ = π exactly (two valid axes ±ω̂) the axis whose largest
    component is positive is returned.

    Parameters
    ----------
    R : (3, 3) array_like
        The rotation whose logarithm is returned (checked: see :mod:`robokit.spatial`).

    Returns
    -------
    (3, 3) ndarray
        ``[ω̂]θ`` (rad).

    Examples
    --------
    >>> Rz90 = np.array([[0, -1, 0], [1, 0, 0], [0, 0, 1]])
    >>> so3_to_vec(matrix_log_3(Rz90)).round(4)            # 90° about z
    array([0.    , 0.    , 1.5708])
    >>> so3_to_vec(matrix_log_3(np.diag([1.0, -1, -1]))).round(4)   # θ = π about x
    array([3.1416, 0.    , 0.    ])
    """
    R = check_rotation(R, "R")
    return hat(log3(R))


def project_to_SO3(mat: ArrayLike) -> np.ndarray:
    """The rotation matrix nearest to ``mat`` in the Frobenius norm (via SVD).

    With ``mat = U Σ Vᵀ`` the answer is ``U diag(1, 1, det(UVᵀ)) Vᵀ``: for an input with
    det < 0 (a reflection), the smallest singular direction is flipped, which is still
    the nearest rotation.

    Parameters
    ----------
    mat : (3, 3) array_like
        Any real 3×3 matrix (e.g. a rotation corrupted by rounding or noise).

    Returns
    -------
    (3, 3) ndarray
        The nearest R ∈ SO(3).

    Examples
    --------
    >>> R = project_to_SO3([[0.675, 0.150, 0.720], [0.370, 0.771, -0.511], [-0.630, 0.619, 0.472]])
    >>> R.round(4)
    array([[ 0.679 ,  0.1489,  0.7189],
           [ 0.3732,  0.7732, -0.5127],
           [-0.6322,  0.6164,  0.4694]])
    >>> test_if_SO3(R)
    True
    """
    M = as_matrix(mat, "mat", 3, 3)
    U, _, Vt = np.linalg.svd(M)
    d = np.sign(np.linalg.det(U @ Vt)) or 1.0
    return U @ np.diag([1.0, 1.0, d]) @ Vt


_I3 = np.eye(3)


def _det3(M: np.ndarray) -> float:
    (a, b, c), (d, e, f), (g, h, i) = M.tolist()
    return a * (e * i - f * h) - b * (d * i - f * g) + c * (d * h - e * g)


def _distance_so3(M: np.ndarray) -> float:
    if _det3(M) <= 0.0:
        return 1e9
    E = (M.T @ M - _I3).ravel()
    return float(np.sqrt(E @ E))


def distance_to_SO3(mat: ArrayLike) -> float:
    """Distance of a 3×3 matrix from SO(3), as Modern Robotics defines it.

    Parameters
    ----------
    mat : (3, 3) array_like
        Any real 3×3 matrix.

    Returns
    -------
    float
        ``‖matᵀ mat − I‖_F`` if det(mat) > 0, else the large value 1e9.

    Examples
    --------
    >>> distance_to_SO3(np.eye(3))
    0.0
    >>> distance_to_SO3(np.diag([1.0, 1.0, -1.0]))      # a reflection
    1000000000.0
    """
    return _distance_so3(as_matrix(mat, "mat", 3, 3))


def test_if_SO3(mat: ArrayLike) -> bool:
    """Whether a 3×3 matrix is (close to) a rotation: ``distance_to_SO3(mat) < 1e-3``.

    Parameters
    ----------
    mat
        As for :func:`distance_to_SO3`.

    Returns
    -------
    bool
        True for a rotation matrix (to 1e-3).

    Examples
    --------
    >>> test_if_SO3(np.eye(3)), test_if_SO3(1.01 * np.eye(3))
    (True, False)
    """
    return bool(distance_to_SO3(mat) < 1e-3)


test_if_SO3.__test__ = False  # type: ignore[attr-defined]  # not a pytest test despite its name


def euler_to_matrix(euler: ArrayLike) -> np.ndarray:
    """``Rz(α) Ry(β) Rx(γ)`` for ZYX Euler angles ``euler = [α, β, γ]`` (rad; seed 004 §2).

    Moving-axis reading: rotate by α about z, then β about the new y, then γ about the new x.

    Parameters
    ----------
    euler : (3,) array_like
        [α, β, γ] (rad).

    Returns
    -------
    (3, 3) ndarray
        ``R = Rz(α)·Ry(β)·Rx(γ)``.

    Examples
    --------
    α = 90° alone is Rz(90°), which maps x to y:

    >>> euler_to_matrix([np.pi / 2, 0, 0]) @ [1, 0, 0]
    array([0., 1., 0.])
    """
    a, b, g = as_vector(euler, "euler", 3)
    ca, sa, cb, sb, cg, sg = np.cos(a), np.sin(a), np.cos(b), np.sin(b), np.cos(g), np.sin(g)
    return np.array(
        [
            [ca * cb, ca * sb * sg - sa * cg, ca * sb * cg + sa * sg],
            [sa * cb, sa * sb * sg + ca * cg, sa * sb * cg - ca * sg],
            [-sb, cb * sg, cb * cg],
        ]
    )


def matrix_to_euler(R: ArrayLike) -> np.ndarray:
    """ZYX Euler angles ``[α, β, γ]`` with ``euler_to_matrix([α, β, γ]) = R`` (seed 004 §2).

    Ranges: β ∈ [−π/2, π/2], α, γ ∈ (−π, π]. At gimbal lock (β = ±π/2, where only
    α ∓ γ is determined) the documented choice is γ = 0 and α carries the whole angle.

    Parameters
    ----------
    R : (3, 3) array_like
        The rotation to write as ZYX Euler angles (checked: see :mod:`robokit.spatial`).

    Returns
    -------
    (3,) ndarray
        [α, β, γ] (rad).

    Examples
    --------
    >>> matrix_to_euler(euler_to_matrix([0.3, -0.2, 0.1])).round(4)
    array([ 0.3, -0.2,  0.1])
    >>> matrix_to_euler(euler_to_matrix([0.3, np.pi / 2, 0.1])).round(4)   # gimbal lock: γ = 0
    array([0.2   , 1.5708, 0.    ])
    """
    R = check_rotation(R, "R")
    sb = -R[2, 0]
    cb = float(np.hypot(R[0, 0], R[1, 0]))
    beta = float(np.arctan2(sb, cb))
    if cb > 1e-10:
        alpha = float(np.arctan2(R[1, 0], R[0, 0]))
        gamma = float(np.arctan2(R[2, 1], R[2, 2]))
    else:
        # R = Rz(α) Ry(±π/2) Rx(γ): R[0,1] = ∓sin(α ∓ γ)…; with γ = 0: R[1,1] = cos α, R[0,1] = −sin α.
        gamma = 0.0
        alpha = float(np.arctan2(-R[0, 1], R[1, 1]))
        beta = np.pi / 2 if sb > 0 else -np.pi / 2
    return np.array([wrap_angle(alpha), beta, wrap_angle(gamma)])

