r"""Planar poses SE(2): ``(x, y, θ)`` ↔ 3×3 homogeneous matrices (Lectures 2 and 9).

``T = [[cos θ, −sin θ, x], [sin θ, cos θ, y], [0, 0, 1]]``: the pose of a frame in the plane.
Composition is the matrix product; angles are returned in (−π, π].
"""
from __future__ import annotations

import math

import numpy as np

from robokit._arrays import as_array, as_matrix, as_vector
from numpy.typing import ArrayLike
from robokit.errors import InputError

__all__ = ["se2_from_pose", "pose_from_se2", "se2_compose", "se2_inverse", "se2_transform_points"]


def se2_from_pose(pose: ArrayLike) -> np.ndarray:
    """3×3 homogeneous matrix ``[[cos θ, −sin θ, x], [sin θ, cos θ, y], [0, 0, 1]]`` of a planar pose.

    Parameters
    ----------
    pose : (3,) array_like
        (x, y, θ) (m, m, rad): the frame's origin and heading in the reference frame.

    Returns
    -------
    (3, 3) ndarray
        The SE(2) matrix.

    Examples
    --------
    >>> se2_from_pose([1.0, 2.0, np.pi / 2]).round(4)
    array([[ 0., -1.,  1.],
           [ 1.,  0.,  2.],
           [ 0.,  0.,  1.]])
    """
    x, y, th = as_vector(pose, "pose", 3)
    c, s = math.cos(th), math.sin(th)
    return np.array([[c, -s, x], [s, c, y], [0.0, 0.0, 1.0]])


def _check_se2(T: ArrayLike, name: str = "T") -> np.ndarray:
    T = as_matrix(T, name, 3, 3)
    R = T[:2, :2]
    err = float(np.abs(R.T @ R - np.eye(2)).max()) + abs(float(np.linalg.det(R)) - 1.0)
    if err > 1e-6 or np.abs(T[2] - (0.0, 0.0, 1.0)).max() > 1e-9:
        raise InputError(f"{name}: not an SE(2) matrix (rotation error {err:.3g} or last row {T[2]})")
    return T


def pose_from_se2(T: ArrayLike) -> np.ndarray:
    """``(x, y, θ)`` of a 3×3 SE(2) matrix, θ ∈ (−π, π] (the inverse of :func:`se2_from_pose`).

    Parameters
    ----------
    T : (3, 3) array_like
        An SE(2) matrix (checked: orthonormal rotation block, last row (0, 0, 1)).

    Returns
    -------
    (3,) ndarray
        (x, y, θ) (m, m, rad).

    Examples
    --------
    >>> pose_from_se2(se2_from_pose([1.0, 2.0, 3.0])).round(4)
    array([1., 2., 3.])
    """
    T = _check_se2(T)
    th = math.atan2(T[1, 0], T[0, 0])
    return np.array([T[0, 2], T[1, 2], math.pi if th == -math.pi else th])


def se2_compose(*poses: ArrayLike) -> np.ndarray:
    """The pose ``p₁ ⊕ p₂ ⊕ …`` of planar poses: the product of their matrices (Lecture 9).

    Parameters
    ----------
    *poses : (3,) array_like
        One or more poses (x, y, θ) (m, m, rad), each relative to the one before.

    Returns
    -------
    (3,) ndarray
        The last frame's pose in the first one's reference frame (θ wrapped as the module docstring says).

    Examples
    --------
    Drive 1 m, turn left 90°, drive 1 m: at (1, 1) facing +y.

    >>> se2_compose([1, 0, np.pi / 2], [1, 0, 0]).round(4)
    array([1.    , 1.    , 1.5708])
    """
    if not poses:
        raise InputError("poses: expected at least one pose")
    T = np.eye(3)
    for k, p in enumerate(poses):
        T = T @ se2_from_pose(as_vector(p, f"poses[{k}]", 3))
    return pose_from_se2(T)


def se2_inverse(pose: ArrayLike) -> np.ndarray:
    """The inverse pose ``⊖p = (−Rᵀt, −θ)``, so that ``p ⊕ ⊖p = (0, 0, 0)``.

    Parameters
    ----------
    pose : (3,) array_like
        A planar pose, as for :func:`se2_from_pose`.

    Returns
    -------
    (3,) ndarray
        ``⊖p``: the reference frame's pose seen from the frame ``pose`` places.

    Examples
    --------
    >>> bool(np.allclose(se2_compose([1.0, 2.0, 0.5], se2_inverse([1.0, 2.0, 0.5])), 0))
    True
    """
    x, y, th = as_vector(pose, "pose", 3)
    c, s = math.cos(th), math.sin(th)
    t = -np.array([c * x + s * y, -s * x + c * y])
    w = math.atan2(math.sin(-th), math.cos(-th))
    return np.array([t[0], t[1], math.pi if w == -math.pi else w])


def se2_transform_points(pose: ArrayLike, points: ArrayLike) -> np.ndarray:
    """Points given in the frame ``pose`` expressed in the reference frame: ``R p + t``.

    Parameters
    ----------
    pose : (3,) array_like
        (x, y, θ) of the frame in the reference frame (m, m, rad).
    points : (2,) or (K, 2) array_like
        Points in that frame (m).

    Returns
    -------
    (2,) or (K, 2) ndarray
        The points in the reference frame.

    Examples
    --------
    >>> se2_transform_points([1.0, 0.0, np.pi / 2], [[1.0, 0.0], [0.0, 1.0]]).round(4)
    array([[1., 1.],
           [0., 0.]])
    """
    x, y, th = as_vector(pose, "pose", 3)
    P = as_array(points, "points")
    if P.shape[-1] != 2 or P.ndim not in (1, 2):
        raise InputError(f"points: expected shape (2,) or (K, 2), got {P.shape}")
    c, s = math.cos(th), math.sin(th)
    R = np.array([[c, -s], [s, c]])
    return P @ R.T + np.array([x, y])
