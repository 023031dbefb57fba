r"""Angle–axis (Rodrigues) and the two-vector representation (Lecture 2).

``matrix_from_axis_angle(ω̂, θ) = I + sin θ [ω̂] + (1 − cos θ)[ω̂]²`` and its inverse with
θ ∈ [0, π] (θ = 0: the axis is free and (1, 0, 0) is returned; θ = π: the axis sign is free
and :func:`robokit.matrix_log_3`'s choice is used). The two-vector representation builds R
from the approach vector a (the tool's z) and the orientation vector o (its y): n = o × a,
R = [n o a].
"""
from __future__ import annotations

import numpy as np

from robokit._arrays import as_scalar, as_vector
from robokit.spatial.basics import _axis_and_norm
from robokit.spatial.so3 import check_rotation
from robokit.spatial import lie
from numpy.typing import ArrayLike
from robokit.errors import InputError

__all__ = ["matrix_from_axis_angle", "axis_angle_from_matrix", "matrix_from_two_vectors"]


def matrix_from_axis_angle(axis: ArrayLike, angle: float) -> np.ndarray:
    """Rotation by ``angle`` about ``axis``: ``I + sin θ [ω̂] + (1 − cos θ)[ω̂]²`` (Rodrigues, Lecture 2).

    Parameters
    ----------
    axis : (3,) array_like
        Rotation axis (normalised here; not zero).
    angle : float
        Rotation angle θ (rad), right-handed about the axis.

    Returns
    -------
    (3, 3) ndarray
        ``R = exp([ω̂]θ)``, ω̂ the normalised axis.

    Examples
    --------
    120° about (1, 1, 1) permutes the axes: x → y.

    >>> (matrix_from_axis_angle([1, 1, 1], 2 * np.pi / 3) @ [1, 0, 0]).round(4)
    array([-0.,  1.,  0.])
    """
    axis, n = _axis_and_norm(axis)
    return lie.exp3(axis / n * as_scalar(angle, "angle"))


def axis_angle_from_matrix(R: ArrayLike) -> tuple[np.ndarray, float]:
    """``(axis, angle)`` of a rotation, angle ∈ [0, π] (the inverse of :func:`matrix_from_axis_angle`).

    At angle 0 the axis is free and (1, 0, 0) is returned; at angle π the axis sign follows
    :func:`robokit.matrix_log_3`'s choice.

    Parameters
    ----------
    R : (3, 3) array_like
        The rotation whose axis and angle are returned (checked: see :mod:`robokit.spatial`).

    Returns
    -------
    axis : (3,) ndarray
        Unit rotation axis.
    angle : float
        Rotation angle (rad), in [0, π].

    Examples
    --------
    >>> axis, angle = axis_angle_from_matrix([[0, -1, 0], [1, 0, 0], [0, 0, 1]])
    >>> axis, round(float(np.degrees(angle)), 4)
    (array([0., 0., 1.]), 90.0)
    """
    w = lie.log3(check_rotation(R, "R"))
    th = float(np.linalg.norm(w))
    if th == 0.0:
        return np.array([1.0, 0.0, 0.0]), 0.0
    return w / th, th


def matrix_from_two_vectors(o: ArrayLike, a: ArrayLike, tol: float = 1e-6) -> np.ndarray:
    """``R = [n o a]`` with ``n = o × a`` from the orientation vector o and approach vector a (Lecture 2).

    The two-vector representation of a tool orientation: a is the tool's z (approach), o its y
    (the direction the gripper opens along).

    Parameters
    ----------
    o : (3,) array_like
        Orientation vector (normalised here).
    a : (3,) array_like
        Approach vector (normalised here); must be orthogonal to o within ``tol``.
    tol : float
        Largest accepted ``|o·a|`` after normalising (else :class:`~robokit.errors.InputError`).

    Returns
    -------
    (3, 3) ndarray
        The rotation with columns n, o, a.

    Examples
    --------
    A tool pointing down (a = −z) with its y along the base y:

    >>> matrix_from_two_vectors([0, 1, 0], [0, 0, -1])
    array([[-1.,  0.,  0.],
           [ 0.,  1.,  0.],
           [ 0.,  0., -1.]])
    """
    o = as_vector(o, "o", 3)
    a = as_vector(a, "a", 3)
    no, na = float(np.linalg.norm(o)), float(np.linalg.norm(a))
    if no == 0.0 or na == 0.0:
        raise InputError("o, a: expected non-zero vectors")
    o, a = o / no, a / na
    if abs(float(o @ a)) > tol:
        raise InputError(f"o, a: expected orthogonal vectors, got o·a = {float(o @ a):.3g}")
    return np.column_stack([np.cross(o, a), o, a])
