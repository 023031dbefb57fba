r"""Deterministic, uniform sets of tool orientations for capability maps.

Spatial arms: the *super-Fibonacci spiral* of Alexa (M. Alexa, "Super-Fibonacci Spirals:
Fast, Low-Discrepancy Sampling of SO(3)", CVPR 2022). The i-th of K unit quaternions, with
``s = i + ½``, is

.. math::

    q_i = \bigl(\sqrt{s/K}\,\sin\alpha_i,\ \sqrt{s/K}\,\cos\alpha_i,\
          \sqrt{1-s/K}\,\sin\beta_i,\ \sqrt{1-s/K}\,\cos\beta_i\bigr),\qquad
    \alpha_i = 2\pi s/\varphi,\ \beta_i = 2\pi s/\psi,

with :math:`\varphi = \sqrt 2` and :math:`\psi \approx 1.5337511687552` the real root of
:math:`\psi^4 = \psi + 4`. The radii :math:`\sqrt{s/K}`, :math:`\sqrt{1-s/K}` make the points
equidistributed for the uniform (Haar) measure on the 3-sphere; the two irrational angle
increments spread them like a Fibonacci lattice. Since ``q`` and ``−q`` are the same
rotation, the set covers SO(3) with low discrepancy; it is the same for the same K on
every machine (no random numbers). Quaternions are scalar first, ``(w, x, y, z)``.

Planar arms (all joint axes parallel to one normal ``n``): the only tool orientations are
``Rot(n, φ) R₀``; the set is ``φ_k = 2πk/K``, k = 0 … K−1.
"""
from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike
from robokit.errors import InputError, InputTypeError

__all__ = ["super_fibonacci_rotations", "planar_rotations"]

#: The real root of ψ⁴ = ψ + 4 (Alexa 2022).
_PSI = 1.533751168755204288118041
_PHI = np.sqrt(2.0)


def _count(K: object, name: str = "orientations") -> int:
    if isinstance(K, bool) or not isinstance(K, (int, np.integer)):
        raise InputTypeError(f"{name}: expected a positive integer count, got {type(K).__name__} {K!r}")
    if K < 1:
        raise InputError(f"{name}: expected a positive count, got {K}")
    return int(K)


def _matrices_from_quaternions(Q: np.ndarray) -> np.ndarray:
    """(K, 3, 3) rotation matrices of (K, 4) unit quaternions (w, x, y, z)."""
    w, x, y, z = Q.T
    R = np.empty((len(Q), 3, 3))
    R[:, 0, 0] = 1 - 2 * (y * y + z * z)
    R[:, 0, 1] = 2 * (x * y - w * z)
    R[:, 0, 2] = 2 * (x * z + w * y)
    R[:, 1, 0] = 2 * (x * y + w * z)
    R[:, 1, 1] = 1 - 2 * (x * x + z * z)
    R[:, 1, 2] = 2 * (y * z - w * x)
    R[:, 2, 0] = 2 * (x * z - w * y)
    R[:, 2, 1] = 2 * (y * z + w * x)
    R[:, 2, 2] = 1 - 2 * (x * x + y * y)
    return R


def super_fibonacci_rotations(K: int) -> np.ndarray:
    """K rotations spread uniformly over SO(3) (Alexa's super-Fibonacci spiral).

    Parameters
    ----------
    K : int
        Number of rotations, ≥ 1.

    Returns
    -------
    (K, 3, 3) ndarray
        Rotation matrices (orthonormal, det +1). The same K always gives the same set.

    Examples
    --------
    >>> R = super_fibonacci_rotations(100)
    >>> R.shape
    (100, 3, 3)
    """
    K = _count(K)
    s = np.arange(K, dtype=float) + 0.5
    r = np.sqrt(s / K)
    big_r = np.sqrt(1.0 - s / K)
    alpha = 2.0 * np.pi * s / _PHI
    beta = 2.0 * np.pi * s / _PSI
    Q = np.stack([r * np.sin(alpha), r * np.cos(alpha), big_r * np.sin(beta), big_r * np.cos(beta)], axis=1)
    Q /= np.linalg.norm(Q, axis=1, keepdims=True)
    return _matrices_from_quaternions(Q)


def planar_rotations(K: int, normal: ArrayLike, R0: ArrayLike | None = None) -> np.ndarray:
    """K rotations ``Rot(normal, 2πk/K) · R0``, k = 0 … K−1: the orientation set of a planar arm.

    Parameters
    ----------
    K : int
        Number of rotations, ≥ 1.
    normal : (3,) array
        The plane normal (the arm's common joint axis) in the base frame; normalised here.
    R0 : (3, 3) array, optional
        The tool orientation at zero joint angles (default identity).

    Returns
    -------
    (K, 3, 3) ndarray

    Examples
    --------
    >>> planar_rotations(4, [0, 0, 1])[1].round(6)[:2, :2]
    array([[ 0., -1.],
           [ 1.,  0.]])
    """
    K = _count(K)
    n = np.asarray(normal, dtype=float)
    if n.shape != (3,) or not np.isfinite(n).all() or np.linalg.norm(n) < 1e-12:
        raise InputError(f"normal: expected a non-zero finite (3,) vector, got {np.asarray(normal).tolist()!r}")
    n = n / np.linalg.norm(n)
    R0 = np.eye(3) if R0 is None else np.asarray(R0, dtype=float)
    phi = 2.0 * np.pi * np.arange(K) / K
    c, s = np.cos(phi), np.sin(phi)
    nx = np.array([[0, -n[2], n[1]], [n[2], 0, -n[0]], [-n[1], n[0], 0]])
    R = np.eye(3) + s[:, None, None] * nx + (1 - c)[:, None, None] * (nx @ nx)
    return R @ R0
