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
    """3×3 homogeneous matrix of a planar pose ``(x, y, θ)`` (m, m, rad)."""
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
    """``(x, y, θ)`` of a 3×3 SE(2) matrix, θ ∈ (−π, π]."""
    T = _check_se2(T)
    th = math.atan2(T[1, 0], T[0, 0])
    return np.array([T[0, 2], T[1, 2], math.pi if th == -math.pi else th])


def se2_compose(*poses: ArrayLike) -> np.ndarray:
    """The pose ``p₁ ⊕ p₂ ⊕ …`` of planar poses (x, y, θ): the product of their matrices."""
    if not poses:
        raise InputError("poses: expected at least one pose")
    T = np.eye(3)
    for k, p in enumerate(poses):
        T = T @ se2_from_pose(as_vector(p, f"poses[{k}]", 3))
    return pose_from_se2(T)


def se2_inverse(pose: ArrayLike) -> np.ndarray:
    """The inverse pose ``⊖p``: ``(−Rᵀt, −θ)``."""
    x, y, th = as_vector(pose, "pose", 3)
    c, s = math.cos(th), math.sin(th)
    t = -np.array([c * x + s * y, -s * x + c * y])
    w = math.atan2(math.sin(-th), math.cos(-th))
    return np.array([t[0], t[1], math.pi if w == -math.pi else w])


def se2_transform_points(pose: ArrayLike, points: ArrayLike) -> np.ndarray:
    """Points (2,) or (K, 2) given in the frame ``pose`` expressed in the reference frame: ``R p + t``."""
    x, y, th = as_vector(pose, "pose", 3)
    P = as_array(points, "points")
    if P.shape[-1] != 2 or P.ndim not in (1, 2):
        raise InputError(f"points: expected shape (2,) or (K, 2), got {P.shape}")
    c, s = math.cos(th), math.sin(th)
    R = np.array([[c, -s], [s, c]])
    return P @ R.T + np.array([x, y])
