r"""The common normal of two lines (Lecture 4: where DH frames sit between two joint axes).

A line is a point p and a direction z. The common normal of lines 1 and 2 is the segment that is
perpendicular to both; its feet are

    f₁ = p₁ + s z₁,   f₂ = p₂ + t z₂,

where, with unit directions, ``b = z₁·z₂``, ``w = p₁ − p₂``, ``d = z₁·w``, ``e = z₂·w``:

    s = (b e − d) / (1 − b²),   t = (e − b d) / (1 − b²)

(the minimum of ‖f₁ − f₂‖², whose gradient vanishes when ``f₂ − f₁`` is perpendicular to z₁ and z₂).
Its length is the DH link length a, its direction the DH x axis. Special cases:

* skew lines: the unique normal, length > 0, direction ``(f₂ − f₁)/‖f₂ − f₁‖``;
* intersecting lines: length 0, both feet at the intersection, direction ``z₁ × z₂ / ‖z₁ × z₂‖``
  (the sign is a free choice of the DH convention; this one is returned);
* parallel lines (``‖z₁ × z₂‖ ≤ tol``): every point of line 1 has a normal; the one through the
  projection of ``ref`` on line 1 is returned (default ``ref = p₁``), direction from line 1 to line 2;
* coincident lines: length 0, ``f₁ = f₂`` = the projection of ref, direction undefined: any unit
  vector perpendicular to z₁ is a valid x; the one returned is ``z₁ × x̂`` (or ``z₁ × ŷ`` if z₁ ∥ x̂),
  normalised.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from robokit._arrays import as_scalar, as_vector
from robokit.spatial.basics import unit_vector

__all__ = ["CommonNormal", "common_normal"]


@dataclass(frozen=True)
class CommonNormal:
    """The common normal of two lines (Lecture 4), as :func:`common_normal` returns it.

    Attributes
    ----------
    foot1, foot2 : (3,) ndarray
        Its feet on line 1 and line 2 (the lines' length unit).
    direction : (3,) ndarray
        Unit vector from foot1 to foot2 (see the module docstring for intersecting and coincident
        lines): the DH x axis.
    length : float
        ``‖foot2 − foot1‖``: the DH link length a.
    kind : str
        "skew", "intersecting", "parallel" or "coincident".
    alpha : float
        The twist (rad, in (−π, π]) that turns ẑ₁ into ẑ₂ about the normal's direction x̂ — the DH α,
        ``α = atan2((ẑ₁ × ẑ₂)·x̂, ẑ₁·ẑ₂)`` (= sgn((ẑ₁ × ẑ₂)·x̂)·cos⁻¹(ẑ₁·ẑ₂)).
    """

    foot1: np.ndarray
    foot2: np.ndarray
    direction: np.ndarray
    length: float
    kind: str
    alpha: float = 0.0




def common_normal(p1: ArrayLike, z1: ArrayLike, p2: ArrayLike, z2: ArrayLike, ref: ArrayLike | None = None, tol: float = 1e-9) -> CommonNormal:
    """The common normal of line 1 (point p1, direction z1) and line 2 (p2, z2) (Lecture 4).

    The feet minimise ``‖f₁ − f₂‖``; the special cases (intersecting, parallel, coincident lines) are
    decided as the module docstring says. Any length unit.

    Parameters
    ----------
    p1, p2 : (3,) array_like
        A point on each line.
    z1, z2 : (3,) array_like
        The lines' directions (need not be unit; not zero).
    ref : (3,) array_like, optional
        For parallel or coincident lines, the normal is taken through the projection of ref on
        line 1 (default p1).
    tol : float
        Parallel when ``‖ẑ₁ × ẑ₂‖ ≤ tol``, meeting when the length ≤ tol.

    Returns
    -------
    CommonNormal
        ``.foot1``, ``.foot2``, ``.direction``, ``.length``, ``.kind``, ``.alpha``.

    Examples
    --------
    The x axis and the y axis lifted to z = 2: the normal runs up the z axis, a = 2, and x turns into
    y about +z (α = +90°).

    >>> cn = common_normal([0, 0, 0], [1, 0, 0], [0, 0, 2], [0, 1, 0])
    >>> cn.foot1, cn.foot2, cn.direction, cn.length, cn.kind, round(float(np.degrees(cn.alpha)), 4)
    (array([0., 0., 0.]), array([0., 0., 2.]), array([0., 0., 1.]), 2.0, 'skew', 90.0)
    """
    p1 = as_vector(p1, "p1", 3)
    p2 = as_vector(p2, "p2", 3)
    z1 = unit_vector(z1, "z1")
    z2 = unit_vector(z2, "z2")
    tol = as_scalar(tol, "tol", positive=True)
    cross = np.cross(z1, z2)
    if np.linalg.norm(cross) > tol:
        w = p1 - p2
        b = float(z1 @ z2)
        d, e = float(z1 @ w), float(z2 @ w)
        den = float(cross @ cross)  # = 1 − (ẑ₁·ẑ₂)², without the cancellation of 1 − b² for nearly parallel lines
        f1 = p1 + (b * e - d) / den * z1
        f2 = p2 + (e - b * d) / den * z2
        L = float(np.linalg.norm(f2 - f1))
        if L > tol:
            # the normal's direction is ±ẑ₁×ẑ₂ exactly; (f2 − f1) only gives its sign (dividing the
            # difference of the feet by a short length would lose digits)
            c = cross / np.linalg.norm(cross)
            return _with_twist(f1, f2, c if c @ (f2 - f1) >= 0 else -c, L, "skew", z1, z2)
        m = 0.5 * (f1 + f2)
        return _with_twist(m, m.copy(), cross / np.linalg.norm(cross), 0.0, "intersecting", z1, z2)
    r = p1 if ref is None else as_vector(ref, "ref", 3)
    f1 = p1 + float((r - p1) @ z1) * z1
    f2 = p2 + float((f1 - p2) @ z2) * z2
    L = float(np.linalg.norm(f2 - f1))
    if L > tol:
        return _with_twist(f1, f2, (f2 - f1) / L, L, "parallel", z1, z2)
    x = np.cross(z1, [1.0, 0.0, 0.0]) if abs(z1[0]) < 0.9 else np.cross(z1, [0.0, 1.0, 0.0])
    return _with_twist(f1, f1.copy(), x / np.linalg.norm(x), 0.0, "coincident", z1, z2)


def _with_twist(f1: np.ndarray, f2: np.ndarray, x: np.ndarray, length: float, kind: str, z1: np.ndarray,
                z2: np.ndarray) -> CommonNormal:
    """The normal with its twist α = atan2((ẑ₁ × ẑ₂)·x̂, ẑ₁·ẑ₂), in (−π, π]."""
    alpha = math.atan2(float(np.cross(z1, z2) @ x), float(z1 @ z2))
    if alpha <= -math.pi:
        alpha = math.pi
    return CommonNormal(f1, f2, x, length, kind, alpha)
