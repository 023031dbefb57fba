"""Scalar and vector basics of the seed function library (seed 004 §1)."""
from __future__ import annotations

import math

import numpy as np
from numpy.typing import ArrayLike

from robokit._arrays import as_array, as_vector
from robokit.errors import InputError

__all__ = ["near_zero", "normalize", "unit_vector", "wrap_angle"]


def near_zero(z: ArrayLike) -> bool:
    """True if ``|z| < 1e-6`` (the seed library's zero test).

    Example: ``near_zero(-1e-7)`` → ``True``.
    """
    return bool(abs(float(as_array(z, "z", ()))) < 1e-6)


def normalize(V: ArrayLike) -> np.ndarray:
    """``V / ‖V‖`` for a vector ``V`` of any length.

    Raises ``ValueError`` for the zero vector (it has no direction).
    Example: ``normalize([1, 2, 3])`` → ``[0.267, 0.535, 0.802]``.
    """
    V = as_vector(V, "V")
    n = float(np.linalg.norm(V))
    if n == 0.0:
        raise InputError("V: cannot normalize the zero vector")
    return V / n


def unit_vector(v: ArrayLike, name: str) -> np.ndarray:
    """The direction ``v / ‖v‖`` of a 3-vector (an axis, a line's direction): ``InputError``
    naming ``name`` for a (near-)zero vector (‖v‖ < 1e-12).

    Example: ``unit_vector([0, 0, 2], "axis")`` → ``[0, 0, 1]``.
    """
    w = as_vector(v, name, 3)
    n = float(np.linalg.norm(w))
    if n < 1e-12:
        raise InputError(f"{name}: expected a nonzero direction, got {w.tolist()}")
    return w / n


def wrap_angle(a: ArrayLike) -> float | np.ndarray:
    """Angles wrapped to (−π, π]: a float for a scalar, an array for an array (no checks).

    The one angle-wrapping function of robokit (rotations, IK solutions, vehicle headings).
    Example: ``wrap_angle(3 * np.pi / 2)`` → ``-π/2``; ``wrap_angle(-np.pi)`` → ``π``.
    """
    if isinstance(a, (float, int)):
        w = math.fmod(a + math.pi, 2.0 * math.pi)
        if w <= 0.0:
            w += 2.0 * math.pi
        return w - math.pi
    a = np.asarray(a, dtype=float)
    w = np.mod(a + np.pi, 2.0 * np.pi) - np.pi
    w = np.where(w <= -np.pi, w + 2.0 * np.pi, w)
    return float(w) if w.ndim == 0 else w
