"""Scalar and vector basics of the seed function library (seed 004 §1)."""
from __future__ import annotations

import math

import numpy as np
from numpy.typing import ArrayLike

from robokit._arrays import as_array, as_vector
from robokit.errors import InputError

__all__ = ["near_zero", "normalize", "unit_vector", "wrap_angle", "deg2rad", "rad2deg"]


def near_zero(z: ArrayLike) -> bool:
    """Whether ``|z| < 1e-6`` (the seed library's zero test, seed 004 §1).

    Parameters
    ----------
    z : float or 0-d array_like
        A scalar.

    Returns
    -------
    bool
        True if ``|z| < 1e-6``.

    Examples
    --------
    >>> near_zero(-1e-7), near_zero(1e-5)
    (True, False)
    """
    return bool(abs(float(as_array(z, "z", ()))) < 1e-6)


def normalize(V: ArrayLike) -> np.ndarray:
    """``V / ‖V‖`` for a vector ``V`` of any length (seed 004 §1).

    Parameters
    ----------
    V : (m,) array_like
        A non-zero vector (the zero vector has no direction: :class:`~robokit.errors.InputError`,
        a ``ValueError``).

    Returns
    -------
    (m,) ndarray
        The unit vector along V.

    Examples
    --------
    >>> normalize([3, 0, 4])
    array([0.6, 0. , 0.8])
    """
    V = as_vector(V, "V")
    n = float(np.linalg.norm(V))
    if n == 0.0:
        raise InputError("V: cannot normalize the zero vector")
    return V / n


def unit_vector(v: ArrayLike, name: str) -> np.ndarray:
    """The direction ``v / ‖v‖`` of a 3-vector (an axis, a line's direction).

    Parameters
    ----------
    v : (3,) array_like
        The vector; ‖v‖ < 1e-12 raises :class:`~robokit.errors.InputError` naming ``name``.
    name : str
        The argument's name in the error message.

    Returns
    -------
    (3,) ndarray
        The unit vector.

    Examples
    --------
    >>> unit_vector([0, 0, 2], "axis")
    array([0., 0., 1.])
    """
    w = as_vector(v, name, 3)
    n = float(np.linalg.norm(w))
    if n < 1e-12:
        raise InputError(f"{name}: expected a nonzero direction, got {w.tolist()}")
    return w / n


def _axis_and_norm(axis: ArrayLike) -> tuple[np.ndarray, float]:
    # a rotation axis as a float (3,) array and its norm ‖axis‖ > 0 (the zero vector has no direction)
    axis = as_vector(axis, "axis", 3)
    n = float(np.linalg.norm(axis))
    if n == 0.0:
        raise InputError("axis: the zero vector has no direction")
    return axis, n


def wrap_angle(a: ArrayLike) -> float | np.ndarray:
    """Angles wrapped to (−π, π] (no checks): the one angle-wrapping function of robokit.

    Used for rotations, IK solutions and vehicle headings.

    Parameters
    ----------
    a : float or array_like
        Angle(s) (rad).

    Returns
    -------
    float or ndarray
        ``a`` wrapped to (−π, π]: a float for a scalar, an array of the same shape for an array.

    Examples
    --------
    >>> round(wrap_angle(3 * np.pi / 2), 4), round(wrap_angle(-np.pi), 4)   # −π maps to +π
    (-1.5708, 3.1416)
    >>> wrap_angle(np.array([0.0, 2 * np.pi + 0.5]))
    array([0. , 0.5])
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


def deg2rad(x: ArrayLike) -> float | np.ndarray:
    """Degrees to radians, ``x·π/180`` (robokit takes every angle in radians).

    Parameters
    ----------
    x : float or array_like
        Angle(s) in degrees (a joint vector, a trajectory's rows, ...).

    Returns
    -------
    float or numpy.ndarray
        A float for a scalar, a float64 array of the same shape for an array.

    Raises
    ------
    InputError
        Non-numeric input (strings, booleans, complex values).

    Examples
    --------
    >>> rk.deg2rad([0, 45, -90, 0, 30, 0]).round(4)
    array([ 0.    ,  0.7854, -1.5708,  0.    ,  0.5236,  0.    ])
    >>> rk.deg2rad(180)
    3.141592653589793
    """
    a = as_array(x, "x", finite=False) * (math.pi / 180.0)
    return float(a) if a.ndim == 0 else a


def rad2deg(x: ArrayLike) -> float | np.ndarray:
    """Radians to degrees, ``x·180/π`` (for printing; robokit itself takes radians).

    Parameters
    ----------
    x : float or array_like
        Angle(s) in radians.

    Returns
    -------
    float or numpy.ndarray
        ``x`` in degrees, a float or an array as for :func:`deg2rad`.

    Raises
    ------
    InputError
        As for :func:`deg2rad`.

    Examples
    --------
    >>> rk.rad2deg(np.pi / 2)
    90.0
    """
    a = as_array(x, "x", finite=False) * (180.0 / math.pi)
    return float(a) if a.ndim == 0 else a
