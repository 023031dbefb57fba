r"""Unit quaternions, scalar first ``q = (w, x, y, z)`` (Lecture 2).

A unit quaternion ``q = (cos(θ/2), sin(θ/2) ω̂)`` represents the rotation by θ about ω̂; q and
−q represent the same rotation. Conversions are numerically robust: ``quaternion_from_matrix``
picks the largest of w², x², y², z² (Shepperd's method) before dividing, and returns w ≥ 0.
"""
from __future__ import annotations

import math

import numpy as np

from robokit._arrays import as_scalar, as_vector
from robokit.spatial.basics import _axis_and_norm
from robokit.spatial.so3 import check_rotation
from numpy.typing import ArrayLike
from robokit.errors import InputError

__all__ = [
    "check_quaternion",
    "quaternion_from_matrix",
    "matrix_from_quaternion",
    "quaternion_from_axis_angle",
    "axis_angle_from_quaternion",
    "quaternion_multiply",
    "quaternion_conjugate",
    "quaternion_rotate",
    "quaternion_slerp",
]


def check_quaternion(q: ArrayLike, name: str = "q", tol: float = 1e-6) -> np.ndarray:
    """``q`` as a (4,) float array of unit norm, renormalised; :class:`~robokit.errors.InputError` otherwise.

    Parameters
    ----------
    q : (4,) array_like
        Quaternion (w, x, y, z), scalar first.
    name : str
        The argument's name in the error message.
    tol : float
        Largest accepted ``|‖q‖ − 1|``.

    Returns
    -------
    (4,) ndarray
        ``q / ‖q‖``.

    Examples
    --------
    >>> float(np.linalg.norm(check_quaternion([1.0, 0, 0, 1e-7])))
    1.0
    >>> check_quaternion([2.0, 0, 0, 0])
    Traceback (most recent call last):
    ...
    robokit.errors.InputError: q: expected a unit quaternion (w, x, y, z), got norm 2
    """
    q = as_vector(q, name, 4)
    n = float(np.linalg.norm(q))
    if abs(n - 1.0) > tol:
        raise InputError(f"{name}: expected a unit quaternion (w, x, y, z), got norm {n:.6g}")
    return q / n


def quaternion_from_matrix(R: ArrayLike) -> np.ndarray:
    """Unit quaternion (w, x, y, z), w ≥ 0, of a rotation matrix (Shepperd's method, Lecture 2).

    Parameters
    ----------
    R : (3, 3) array_like
        The rotation to convert (checked: see :mod:`robokit.spatial`).

    Returns
    -------
    (4,) ndarray
        ``(cos(θ/2), sin(θ/2) ω̂)`` with w ≥ 0.

    Examples
    --------
    Rz(90°): ``(cos 45°, 0, 0, sin 45°)``.

    >>> quaternion_from_matrix([[0, -1, 0], [1, 0, 0], [0, 0, 1]]).round(4)
    array([0.7071, 0.    , 0.    , 0.7071])
    """
    R = check_rotation(R, "R")
    tr = R[0, 0] + R[1, 1] + R[2, 2]
    cands = (tr, R[0, 0], R[1, 1], R[2, 2])
    k = int(np.argmax(cands))
    if k == 0:
        s = 2.0 * math.sqrt(max(0.0, 1.0 + tr))
        q = np.array([0.25 * s, (R[2, 1] - R[1, 2]) / s, (R[0, 2] - R[2, 0]) / s, (R[1, 0] - R[0, 1]) / s])
    elif k == 1:
        s = 2.0 * math.sqrt(max(0.0, 1.0 + R[0, 0] - R[1, 1] - R[2, 2]))
        q = np.array([(R[2, 1] - R[1, 2]) / s, 0.25 * s, (R[0, 1] + R[1, 0]) / s, (R[0, 2] + R[2, 0]) / s])
    elif k == 2:
        s = 2.0 * math.sqrt(max(0.0, 1.0 + R[1, 1] - R[0, 0] - R[2, 2]))
        q = np.array([(R[0, 2] - R[2, 0]) / s, (R[0, 1] + R[1, 0]) / s, 0.25 * s, (R[1, 2] + R[2, 1]) / s])
    else:
        s = 2.0 * math.sqrt(max(0.0, 1.0 + R[2, 2] - R[0, 0] - R[1, 1]))
        q = np.array([(R[1, 0] - R[0, 1]) / s, (R[0, 2] + R[2, 0]) / s, (R[1, 2] + R[2, 1]) / s, 0.25 * s])
    q /= np.linalg.norm(q)
    return -q if q[0] < 0 else q


def matrix_from_quaternion(q: ArrayLike) -> np.ndarray:
    """Rotation matrix of a unit quaternion (w, x, y, z) (Lecture 2).

    Parameters
    ----------
    q : (4,) array_like
        Unit quaternion, scalar first (checked, renormalised).

    Returns
    -------
    (3, 3) ndarray
        ``R(q)``, the same for q and −q.

    Examples
    --------
    >>> (matrix_from_quaternion([np.cos(np.pi / 4), 0, 0, np.sin(np.pi / 4)]) @ [1, 0, 0]).round(4)
    array([0., 1., 0.])
    """
    w, x, y, z = check_quaternion(q)
    return np.array(
        [
            [1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
            [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
            [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)],
        ]
    )


def quaternion_from_axis_angle(axis: ArrayLike, angle: float) -> np.ndarray:
    """``(cos(θ/2), sin(θ/2) ω̂)`` for a rotation by ``angle`` about ``axis`` (Lecture 2).

    Parameters
    ----------
    axis, angle
        As for :func:`robokit.spatial.axis_angle.matrix_from_axis_angle`.

    Returns
    -------
    (4,) ndarray
        Unit quaternion (w, x, y, z).

    Examples
    --------
    >>> quaternion_from_axis_angle([0, 0, 2], np.pi).round(4)      # half turn about z
    array([0., 0., 0., 1.])
    """
    axis, n = _axis_and_norm(axis)
    th = as_scalar(angle, "angle")
    return np.r_[math.cos(0.5 * th), math.sin(0.5 * th) * axis / n]


def axis_angle_from_quaternion(q: ArrayLike) -> tuple[np.ndarray, float]:
    """``(axis, angle)`` of a unit quaternion, angle ∈ [0, π] (q and −q give the same).

    Parameters
    ----------
    q : (4,) array_like
        Unit quaternion (w, x, y, z).

    Returns
    -------
    axis : (3,) ndarray
        Unit axis; (1, 0, 0) for the identity.
    angle : float
        Rotation angle (rad), in [0, π].

    Examples
    --------
    >>> axis, angle = axis_angle_from_quaternion([0.0, 0.0, -1.0, 0.0])
    >>> axis, round(angle, 4)
    (array([ 0., -1.,  0.]), 3.1416)
    """
    q = check_quaternion(q)
    if q[0] < 0:
        q = -q
    s = float(np.linalg.norm(q[1:]))
    angle = 2.0 * math.atan2(s, q[0])
    if s < 1e-15:
        return np.array([1.0, 0.0, 0.0]), 0.0
    return q[1:] / s, angle


def quaternion_multiply(q1: ArrayLike, q2: ArrayLike) -> np.ndarray:
    """Hamilton product ``q1 ⊗ q2``: the rotation ``R(q1) R(q2)`` (q2 first, then q1 in the fixed frame).

    Parameters
    ----------
    q1, q2 : (4,) array_like
        Quaternions (w, x, y, z).

    Returns
    -------
    (4,) ndarray
        ``q1 ⊗ q2``.

    Examples
    --------
    Two quarter turns about z make a half turn:

    >>> qz90 = quaternion_from_axis_angle([0, 0, 1], np.pi / 2)
    >>> quaternion_multiply(qz90, qz90).round(4)
    array([0., 0., 0., 1.])
    """
    w1, x1, y1, z1 = as_vector(q1, "q1", 4)
    w2, x2, y2, z2 = as_vector(q2, "q2", 4)
    return np.array(
        [
            w1 * w2 - x1 * x2 - y1 * y2 - z1 * z2,
            w1 * x2 + x1 * w2 + y1 * z2 - z1 * y2,
            w1 * y2 - x1 * z2 + y1 * w2 + z1 * x2,
            w1 * z2 + x1 * y2 - y1 * x2 + z1 * w2,
        ]
    )


def quaternion_conjugate(q: ArrayLike) -> np.ndarray:
    """``q* = (w, −x, −y, −z)``: the inverse rotation of a unit quaternion.

    Parameters
    ----------
    q : (4,) array_like
        Quaternion (w, x, y, z).

    Returns
    -------
    (4,) ndarray
        The conjugate.

    Examples
    --------
    >>> q = quaternion_from_axis_angle([1, 2, 3], 0.7)
    >>> bool(np.allclose(quaternion_multiply(q, quaternion_conjugate(q)), [1, 0, 0, 0]))
    True
    """
    q = as_vector(q, "q", 4)
    return np.r_[q[0], -q[1:]]


def quaternion_rotate(q: ArrayLike, v: ArrayLike) -> np.ndarray:
    """The vector ``v`` rotated by the unit quaternion q: the vector part of ``q ⊗ (0, v) ⊗ q*``.

    Parameters
    ----------
    q : (4,) array_like
        Unit quaternion (w, x, y, z).
    v : (3,) array_like
        The vector, in the rotated frame's axes.

    Returns
    -------
    (3,) ndarray
        ``R(q) v``.

    Examples
    --------
    >>> quaternion_rotate(quaternion_from_axis_angle([0, 0, 1], np.pi / 2), [1, 0, 0]).round(4)
    array([0., 1., 0.])
    """
    q = check_quaternion(q)
    v = as_vector(v, "v", 3)
    u, w = q[1:], q[0]
    t = 2.0 * np.cross(u, v)
    return v + w * t + np.cross(u, t)


def quaternion_slerp(q0: ArrayLike, q1: ArrayLike, s: ArrayLike) -> np.ndarray:
    """Spherical linear interpolation from q0 (s = 0) to q1 (s = 1) along the shorter arc.

    ``slerp = sin((1−s)Ω)/sin Ω q0 + sin(sΩ)/sin Ω q1`` with cos Ω = q0·q1 (q1 negated when
    q0·q1 < 0 so the rotation takes the short way); normalised linear interpolation when the
    quaternions are nearly parallel.

    Parameters
    ----------
    q0, q1 : (4,) array_like
        Unit quaternions (w, x, y, z) at s = 0 and s = 1.
    s : float or (K,) array_like
        Interpolation parameter(s), finite (normally in [0, 1]).

    Returns
    -------
    (4,) or (K, 4) ndarray
        Unit quaternion(s) along the arc.

    Examples
    --------
    Half-way between the identity and 90° about z is 45° about z:

    >>> q = quaternion_slerp([1, 0, 0, 0], quaternion_from_axis_angle([0, 0, 1], np.pi / 2), 0.5)
    >>> bool(np.allclose(q, quaternion_from_axis_angle([0, 0, 1], np.pi / 4)))
    True
    """
    q0, q1 = check_quaternion(q0, "q0"), check_quaternion(q1, "q1")
    s_arr = np.asarray(s, dtype=float)
    if not np.all(np.isfinite(s_arr)):
        raise InputError("s: contains NaN or infinite values")
    d = float(q0 @ q1)
    if d < 0.0:
        q1, d = -q1, -d
    d = min(1.0, d)
    omega = math.acos(d)
    ss = np.atleast_1d(s_arr)[:, None]
    if omega < 1e-8:
        out = (1 - ss) * q0 + ss * q1
    else:
        so = math.sin(omega)
        out = np.sin((1 - ss) * omega) / so * q0 + np.sin(ss * omega) / so * q1
    out /= np.linalg.norm(out, axis=1, keepdims=True)
    return out[0] if s_arr.ndim == 0 else out
