r"""Euler angles in all 12 sequences, intrinsic (moving axes) and extrinsic (fixed axes) (Lecture 2).

A sequence is a string of three axis letters, e.g. ``"ZYX"`` (Tait–Bryan: three different
axes) or ``"ZYZ"`` (proper Euler: first and last equal). With angles ``(a, b, c)``:

* intrinsic (moving axes, the course's "绕新的轴"): rotate by a about the first axis, then by b
  about the *new* second axis, then by c about the *newest* third axis:
  ``R = R₁(a) R₂(b) R₃(c)``;
* extrinsic (fixed axes, e.g. roll–pitch–yaw about x, y, z of the fixed frame): rotate by a
  about the fixed first axis, then b about the fixed second, then c about the fixed third:
  ``R = R₃(c) R₂(b) R₁(a)``.

So extrinsic ``"XYZ"`` with (roll, pitch, yaw) equals intrinsic ``"ZYX"`` with (yaw, pitch, roll).

Ranges returned by :func:`euler_from_matrix`: a, c ∈ (−π, π]; the middle angle b ∈ [−π/2, π/2]
for Tait–Bryan sequences and b ∈ [0, π] for proper Euler sequences.

Gimbal lock (b = ±π/2 for Tait–Bryan, b ∈ {0, π} for proper Euler): the first and third
axes line up and only their sum (or difference) is determined. The documented choice: the
*third* rotation angle of the composition order is set to 0 — c = 0 for intrinsic, a = 0 for
extrinsic — and the other carries the whole angle. ``return_gimbal=True`` also returns a flag
telling the caller that this happened.
"""
from __future__ import annotations

import math

import numpy as np
from numpy.typing import ArrayLike

from robokit._arrays import as_scalar, as_vector
from robokit.errors import InputError
from robokit.spatial.so3 import check_rotation
from robokit.spatial.basics import wrap_angle

__all__ = ["matrix_from_euler", "euler_from_matrix", "EULER_SEQUENCES", "elementary_rotation", "check_sequence"]

_AX = {"X": 0, "Y": 1, "Z": 2}
EULER_SEQUENCES = tuple(
    a + b + c for a in "XYZ" for b in "XYZ" for c in "XYZ" if a != b and b != c
)  # 12 sequences: 6 Tait–Bryan (all different), 6 proper Euler (first = last)


def check_sequence(seq: str) -> str:
    """The Euler sequence ``seq`` upper-cased, or :class:`~robokit.errors.InputError` if it is not one
    of the 12 of :data:`EULER_SEQUENCES`.

    Parameters
    ----------
    seq : str
        Three axis letters, e.g. ``"zyx"`` or ``"ZYZ"``.

    Returns
    -------
    str
        ``seq.upper()``.

    Examples
    --------
    >>> check_sequence("zyz")
    'ZYZ'
    """
    if not isinstance(seq, str) or seq.upper() not in EULER_SEQUENCES:
        raise InputError(f"seq: expected one of {', '.join(EULER_SEQUENCES)}, got {seq!r}")
    return seq.upper()


_AXIS_INDEX = {0: 0, 1: 1, 2: 2, "x": 0, "y": 1, "z": 2}


def elementary_rotation(axis: int | str, angle: float) -> np.ndarray:
    """The rotation by ``angle`` (rad) about the x, y or z axis: Rx, Ry, Rz (Lecture 2).

    Parameters
    ----------
    axis : {"x", "y", "z"} or {0, 1, 2}
        The axis; anything else raises ``InputError`` (a ``ValueError``).
    angle : float
        The angle, rad, right-handed about the axis.

    Returns
    -------
    (3, 3) ndarray
        ``Rz = [[c, −s, 0], [s, c, 0], [0, 0, 1]]`` and its x and y analogues.

    Examples
    --------
    Rz(90°) maps x to y; Rx(90°) maps y to z:

    >>> elementary_rotation("z", np.pi / 2).round(12) @ [1.0, 0.0, 0.0]
    array([0., 1., 0.])
    >>> elementary_rotation(0, np.pi / 2).round(12) @ [0.0, 1.0, 0.0]
    array([0., 0., 1.])
    """
    k = None if isinstance(axis, bool) else _AXIS_INDEX.get(axis) if isinstance(axis, (int, str, np.integer)) else None
    if k is None:
        raise InputError(f"axis: expected 'x', 'y', 'z' or 0, 1, 2, got {axis!r}")
    return _elementary(k, as_scalar(angle, "angle"))


def _elementary(axis: int, angle: float) -> np.ndarray:
    c, s = math.cos(angle), math.sin(angle)
    if axis == 0:
        return np.array([[1.0, 0.0, 0.0], [0.0, c, -s], [0.0, s, c]])
    if axis == 1:
        return np.array([[c, 0.0, s], [0.0, 1.0, 0.0], [-s, 0.0, c]])
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


def matrix_from_euler(angles: ArrayLike, seq: str = "ZYX", extrinsic: bool = False) -> np.ndarray:
    """Rotation matrix of Euler angles ``angles = (a, b, c)`` (rad) about the axes of ``seq`` (Lecture 2).

    Intrinsic: ``R₁(a) R₂(b) R₃(c)``; extrinsic: ``R₃(c) R₂(b) R₁(a)`` (see the module docstring).

    Parameters
    ----------
    angles : (3,) array_like
        (a, b, c) (rad), in the order of ``seq``.
    seq : str
        One of the 12 sequences of :data:`EULER_SEQUENCES` (case-insensitive), default "ZYX".
    extrinsic : bool
        False: moving (intrinsic) axes; True: fixed (extrinsic) axes.

    Returns
    -------
    (3, 3) ndarray
        ``R₁(a) R₂(b) R₃(c)`` (intrinsic) or ``R₃(c) R₂(b) R₁(a)`` (extrinsic).

    Examples
    --------
    Intrinsic ZYX equals the seed's ``euler_to_matrix``; extrinsic XYZ with the angles reversed is
    the same rotation (roll–pitch–yaw):

    >>> ang = [0.3, -0.2, 0.1]
    >>> bool(np.allclose(matrix_from_euler(ang, "ZYX"), rk.euler_to_matrix(ang)))
    True
    >>> bool(np.allclose(matrix_from_euler(ang[::-1], "XYZ", extrinsic=True), rk.euler_to_matrix(ang)))
    True
    """
    a, b, c = as_vector(angles, "angles", 3)
    s = check_sequence(seq)
    i, j, k = (_AX[ch] for ch in s)
    if extrinsic:
        return _elementary(k, c) @ _elementary(j, b) @ _elementary(i, a)
    return _elementary(i, a) @ _elementary(j, b) @ _elementary(k, c)




def _intrinsic_angles(R: np.ndarray, i: int, j: int, k: int) -> tuple[float, float, float, bool]:
    """(a, b, c, gimbal) with R = R_i(a) R_j(b) R_k(c), intrinsic; at gimbal lock c = 0."""
    if i != k:  # Tait–Bryan
        eps = 1.0 if (j - i) % 3 == 1 else -1.0  # sign of the permutation (i, j, k)
        sb = eps * R[i, k]
        sb = max(-1.0, min(1.0, sb))
        cb = math.hypot(R[i, j], R[i, i])
        b = math.atan2(sb, cb)
        if cb > 1e-10:
            a = math.atan2(-eps * R[j, k], R[k, k])
            c = math.atan2(-eps * R[i, j], R[i, i])
            return a, b, c, False
        # b = ±π/2: R depends on a ± c only; take c = 0, then R = R_i(a) R_j(b) and
        # column j of R is R_i(a) e_j: its (k, j) entry is eps·sin a and (j, j) entry cos a
        a = math.atan2(eps * R[k, j], R[j, j])
        return a, (math.pi / 2 if sb > 0 else -math.pi / 2), 0.0, True
    # proper Euler: i == k; m is the remaining axis
    m = 3 - i - j
    eps = 1.0 if (j - i) % 3 == 1 else -1.0  # sign of the permutation (i, j, m)
    cb = max(-1.0, min(1.0, R[i, i]))
    sb = math.hypot(R[i, j], R[i, m])
    b = math.atan2(sb, cb)
    if sb > 1e-10:
        a = math.atan2(R[j, i], -eps * R[m, i])
        c = math.atan2(R[i, j], eps * R[i, m])
        return a, b, c, False
    # b = 0 or π: take c = 0, R = R_i(a) R_j(b); column j: (j, j) entry cos a, (m, j) entry eps·sin a
    a = math.atan2(eps * R[m, j], R[j, j])
    return a, (0.0 if cb > 0 else math.pi), 0.0, True


def euler_from_matrix(R: ArrayLike, seq: str = "ZYX", extrinsic: bool = False, return_gimbal: bool = False) -> np.ndarray | tuple[np.ndarray, bool]:
    """Euler angles ``(a, b, c)`` of a rotation matrix for the axis sequence ``seq`` (Lecture 2).

    The inverse of :func:`matrix_from_euler` with the ranges and the gimbal-lock choice of the
    module docstring: a, c ∈ (−π, π]; b ∈ [−π/2, π/2] (Tait–Bryan) or [0, π] (proper Euler); at
    gimbal lock the third angle of the composition order is 0.

    Parameters
    ----------
    R : (3, 3) array_like
        The rotation to write as angles about the axes of ``seq`` (checked: see :mod:`robokit.spatial`).
    seq : str
        One of the 12 sequences (default "ZYX").
    extrinsic : bool
        Fixed axes instead of moving ones.
    return_gimbal : bool
        Also return whether R is at this sequence's singular configuration.

    Returns
    -------
    angles : (3,) ndarray
        (a, b, c) (rad).
    gimbal : bool
        Only with ``return_gimbal=True``: True at gimbal lock.

    Examples
    --------
    >>> R = matrix_from_euler([0.5, 1.0, -0.4], "ZYZ")
    >>> euler_from_matrix(R, "ZYZ").round(4)
    array([ 0.5,  1. , -0.4])
    >>> angles, gimbal = euler_from_matrix(elementary_rotation("z", 0.7), "ZYZ", return_gimbal=True)
    >>> angles.round(4), gimbal                  # b = 0: the whole angle in a, c = 0
    (array([0.7, 0. , 0. ]), True)
    """
    R = check_rotation(R, "R")
    s = check_sequence(seq)
    i, j, k = (_AX[ch] for ch in s)
    if extrinsic:
        # R = R_k(c) R_j(b) R_i(a) is the intrinsic sequence (k, j, i) with angles (c, b, a)
        c, b, a, gimbal = _intrinsic_angles(R, k, j, i)
    else:
        a, b, c, gimbal = _intrinsic_angles(R, i, j, k)
    out = np.array([wrap_angle(a), b, wrap_angle(c)])
    return (out, gimbal) if return_gimbal else out
