r"""Building blocks of closed-form inverse kinematics (Lecture 5): the equation
``a cos θ + b sin θ = c`` and the Paden–Kahan subproblems.

``solve_trig``
    Lecture 5's polynomial substitution ``u = tan(θ/2)``, ``cos θ = (1 − u²)/(1 + u²)``,
    ``sin θ = 2u/(1 + u²)`` turns ``a cos θ + b sin θ = c`` into
    ``(a + c) u² − 2b u + (c − a) = 0``, so ``θ = 2 atan((b ± √(a² + b² − c²))/(a + c))``.
    The roots are taken in a cancellation-free form (Vieta's product of roots) and as
    ``2 atan2(·, ·)``, which also covers ``a + c = 0`` (the root ``u = ∞``, θ = π).

Paden–Kahan subproblems (Murray, Li and Sastry, *A Mathematical Introduction to Robotic
Manipulation*, 1994, §3.2.2), for unit axes ``ω`` through a point ``r`` (all vectors in one
frame, lengths in m, angles in rad; a rotation by θ about the axis is ``exp([ω]θ)``):

``pk_subproblem1``  rotate a point p about one axis onto a point q: θ;
``pk_subproblem2``  rotate p about ω₂ then about ω₁ (axes meeting at r) onto q: (θ₁, θ₂) pairs;
``pk_subproblem3``  rotate p about one axis to the distance δ from q: θ.

Each returns every solution as a list (empty when there is none). A configuration in which
every angle works (p on the axis) returns the single choice 0 and says so in the docstring.
Angles are wrapped to (−π, π].
"""
from __future__ import annotations

import math
from typing import cast

import numpy as np
from numpy.typing import ArrayLike

from robokit._arrays import as_scalar, as_vector
from robokit.spatial.basics import unit_vector, wrap_angle
from robokit.errors import InputError

__all__ = ["pk_subproblem1", "pk_subproblem2", "pk_subproblem3", "solve_trig"]

_PI = math.pi
_TWO_PI = 2.0 * math.pi




def _trig_roots(a: float, b: float, c: float, tol: float = 1e-12) -> list[float] | None:
    """Roots of a cos θ + b sin θ = c as a list of angles in (−π, π] (no checks).

    Returns None when every θ solves it (a = b = c = 0). A discriminant a² + b² − c² within
    ``tol``·(a² + b²) below zero is taken as a double root (tangency).
    """
    r2 = a * a + b * b
    if r2 < 1e-300:
        return None if c == 0.0 else []
    disc = r2 - c * c
    if disc < -tol * r2:
        return []
    sq = math.sqrt(disc) if disc > 0.0 else 0.0
    # (a + c) u² − 2b u + (c − a) = 0: A u² + B u + C with B = −2b
    A, C = a + c, c - a
    # q = −(B + sign(B)·√(B² − 4AC))/2 = b + sign(b)·√disc (never a difference of close numbers)
    q = b + (sq if b >= 0.0 else -sq)
    if q == 0.0:  # b = 0 and disc = 0: a double root u = 0 (θ = 0) or u = ∞ (θ = π)
        return [0.0] if A != 0.0 else [_PI]
    t1 = cast(float, wrap_angle(2.0 * math.atan2(q, A)))  # u₁ = q/A  (A = 0: u₁ = ∞, θ = π)
    t2 = cast(float, wrap_angle(2.0 * math.atan2(C, q)))  # u₂ = C/q  (Vieta: u₁u₂ = C/A)
    if sq == 0.0:
        return [t1]
    return [t1, t2]


def solve_trig(a: float, b: float, c: float) -> list[float]:
    r"""All real θ ∈ (−π, π] with ``a cos θ + b sin θ = c`` (Lecture 5, tan(θ/2) substitution).

    Parameters
    ----------
    a, b, c : float
        Coefficients (any units, the same for all three).

    Returns
    -------
    list of float
        Two roots when ``a² + b² > c²``, one (a double root) when ``a² + b² = c²`` (to a
        relative 1e-12), none when ``a² + b² < c²``; sorted ascending. ``a = b = 0`` gives
        ``[]`` when ``c ≠ 0``.

    Raises
    ------
    ValueError
        For non-finite input, and for ``a = b = c = 0``, where every θ is a solution.

    Notes
    -----
    With ``u = tan(θ/2)``: ``(a + c)u² − 2bu + (c − a) = 0``. The roots are computed as
    ``u₁ = q/(a + c)``, ``u₂ = (c − a)/q``, ``q = b + sign(b)√(a² + b² − c²)``, and returned as
    ``2 atan2(q, a + c)`` and ``2 atan2(c − a, q)``: exact when ``a + c = 0`` (θ = π).

    Examples
    --------
    >>> [round(t, 12) for t in solve_trig(1.0, 0.0, 0.0)]   # cos θ = 0
    [-1.570796326795, 1.570796326795]
    >>> solve_trig(1.0, 1.0, 3.0)                           # |c| > √(a² + b²)
    []
    """
    a, b, c = as_scalar(a, "a"), as_scalar(b, "b"), as_scalar(c, "c")
    roots = _trig_roots(a, b, c)
    if roots is None:
        raise InputError("a, b, c: all zero, so every angle solves 0·cos θ + 0·sin θ = 0")
    return sorted(roots)




def pk_subproblem1(omega: ArrayLike, r: ArrayLike, p: ArrayLike, q: ArrayLike, tol: float = 1e-9) -> list[float]:
    """Paden–Kahan subproblem 1: θ with ``exp([ω]θ)(p − r) = q − r``.

    Parameters
    ----------
    omega : array_like, shape (3,)
        Axis direction (normalised here).
    r : array_like, shape (3,)
        A point on the axis, m.
    p, q : array_like, shape (3,)
        The point before and after the rotation, m (all vectors in one frame).
    tol : float, optional
        Consistency tolerance, m (default 1e-9).

    Returns
    -------
    list of float
        ``[θ]`` (rad, in (−π, π]) when q is p rotated about the axis (same height along ω and
        same distance from the axis, to ``tol``); ``[]`` otherwise. If p lies on the axis every θ
        works and the documented choice is ``[0.0]``.

    Notes
    -----
    ``u = p − r``, ``v = q − r``, their projections ``u′ = u − ωωᵀu``, ``v′ = v − ωωᵀv``;
    ``θ = atan2(ωᵀ(u′ × v′), u′ᵀv′)``.

    Examples
    --------
    >>> round(pk_subproblem1([0, 0, 1], [0, 0, 0], [1, 0, 0], [0, 1, 0])[0], 12)
    1.570796326795
    """
    w = unit_vector(omega, "omega")
    r, p, q = as_vector(r, "r", 3), as_vector(p, "p", 3), as_vector(q, "q", 3)
    return _sp1(w, p - r, q - r, tol)


def _sp1(w: np.ndarray, u: np.ndarray, v: np.ndarray, tol: float) -> list[float]:
    hu, hv = float(w @ u), float(w @ v)
    up, vp = u - hu * w, v - hv * w
    nu, nv = float(np.linalg.norm(up)), float(np.linalg.norm(vp))
    if abs(hu - hv) > tol or abs(nu - nv) > tol:
        return []
    if nu <= tol:
        return [0.0]
    return [cast(float, wrap_angle(math.atan2(float(w @ np.cross(up, vp)), float(up @ vp))))]


def pk_subproblem2(omega1: ArrayLike, omega2: ArrayLike, r: ArrayLike, p: ArrayLike, q: ArrayLike,
                   tol: float = 1e-9) -> list[tuple[float, float]]:
    """Paden–Kahan subproblem 2: (θ₁, θ₂) with ``exp([ω₁]θ₁) exp([ω₂]θ₂)(p − r) = q − r``.

    Parameters
    ----------
    omega1, omega2 : array_like, shape (3,)
        Directions of two non-parallel axes (normalised here); parallel axes raise
        :class:`~robokit.errors.InputError`.
    r : array_like, shape (3,)
        The point where the two axes meet, m.
    p, q : array_like, shape (3,)
        The point before and after the two rotations, m (all vectors in one frame).
    tol : float, optional
        Consistency tolerance, m (default 1e-9).

    Returns
    -------
    list of (float, float)
        ``(θ₁, θ₂)`` pairs in rad: two in general, one when the intermediate point is unique,
        none when q cannot be reached (``‖p − r‖ ≠ ‖q − r‖`` or the circles do not meet).

    Notes
    -----
    The intermediate point ``c − r = z = αω₁ + βω₂ ± γ(ω₁ × ω₂)`` (with u = p − r,
    v = q − r):
    ``α = ((ω₁ᵀω₂)ω₂ᵀu − ω₁ᵀv)/((ω₁ᵀω₂)² − 1)``, ``β = ((ω₁ᵀω₂)ω₁ᵀv − ω₂ᵀu)/((ω₁ᵀω₂)² − 1)``,
    ``γ² = (‖u‖² − α² − β² − 2αβω₁ᵀω₂)/‖ω₁ × ω₂‖²``; then θ₂ rotates p to c about ω₂ and θ₁
    rotates c to q about ω₁ (subproblem 1 twice).

    Examples
    --------
    Both pairs carry y onto x (rotations about z, then x, through the origin):

    >>> sols = pk_subproblem2([0, 0, 1], [1, 0, 0], [0, 0, 0], [0, 1, 0], [1, 0, 0])
    >>> from robokit.spatial import elementary_rotation as rot
    >>> len(sols), all(np.allclose(rot("z", t1) @ rot("x", t2) @ [0, 1, 0], [1, 0, 0]) for t1, t2 in sols)
    (2, True)
    """
    w1, w2 = unit_vector(omega1, "omega1"), unit_vector(omega2, "omega2")
    r, p, q = as_vector(r, "r", 3), as_vector(p, "p", 3), as_vector(q, "q", 3)
    cr = np.cross(w1, w2)
    ncr2 = float(cr @ cr)
    if ncr2 < 1e-18:
        raise InputError("omega1, omega2: the axes are parallel; subproblem 2 needs intersecting axes")
    u, v = p - r, q - r
    if abs(np.linalg.norm(u) - np.linalg.norm(v)) > tol:
        return []
    k = float(w1 @ w2)
    den = k * k - 1.0
    alpha = (k * float(w2 @ u) - float(w1 @ v)) / den
    beta = (k * float(w1 @ v) - float(w2 @ u)) / den
    g2 = (float(u @ u) - alpha * alpha - beta * beta - 2.0 * alpha * beta * k) / ncr2
    scale = max(1.0, float(u @ u))
    if g2 < -tol * scale:
        return []
    g = math.sqrt(max(g2, 0.0))
    out = []
    for sign in ((1.0, -1.0) if g > tol else (1.0,)):
        z = alpha * w1 + beta * w2 + sign * g * cr
        t2 = _sp1(w2, u, z, 10 * tol)
        t1 = _sp1(w1, z, v, 10 * tol)
        if t1 and t2:
            out.append((t1[0], t2[0]))
    return out


def pk_subproblem3(omega: ArrayLike, r: ArrayLike, p: ArrayLike, q: ArrayLike, delta: float,
                   tol: float = 1e-9) -> list[float]:
    """Paden–Kahan subproblem 3: θ with ``‖exp([ω]θ)(p − r) − (q − r)‖ = δ``.

    Parameters
    ----------
    omega, r : array_like, shape (3,)
        The axis: its direction (normalised here) and a point on it, m.
    p, q : array_like, shape (3,)
        The rotated point and the fixed point, m (all vectors in one frame).
    delta : float
        The required distance, m (≥ 0).
    tol : float, optional
        Tolerance, m (default 1e-9).

    Returns
    -------
    list of float
        Angles θ in rad, sorted: two in general, one at tangency, none when δ is out of reach.
        If p or q lies on the axis the distance does not depend on θ: ``[0.0]`` (the documented
        choice) when it equals δ, else ``[]``.

    Notes
    -----
    With projections ``u′, v′`` onto the plane normal to ω and ``δ′² = δ² − (ωᵀ(p − q))²``:
    ``θ₀ = atan2(ωᵀ(u′ × v′), u′ᵀv′)``, ``θ = θ₀ ± acos((‖u′‖² + ‖v′‖² − δ′²)/(2‖u′‖‖v′‖))``
    (the law of cosines; solved here with :func:`solve_trig`).

    Examples
    --------
    Rotating (1, 0, 0) about z to be 2 m from itself takes half a turn:

    >>> sorted(round(t, 12) for t in pk_subproblem3([0, 0, 1], [0, 0, 0], [1, 0, 0], [1, 0, 0], 2.0))
    [3.14159265359]
    """
    w = unit_vector(omega, "omega")
    r, p, q = as_vector(r, "r", 3), as_vector(p, "p", 3), as_vector(q, "q", 3)
    delta = as_scalar(delta, "delta", nonnegative=True)
    u, v = p - r, q - r
    up, vp = u - (w @ u) * w, v - (w @ v) * w
    dz = float(w @ (u - v))
    d2 = delta * delta - dz * dz
    nu, nv = float(np.linalg.norm(up)), float(np.linalg.norm(vp))
    if nu <= tol or nv <= tol:
        return [0.0] if abs(math.sqrt(max(d2, 0.0)) - math.hypot(nu, nv)) <= tol and d2 >= -tol else []
    # ‖Rot(θ)u′ − v′‖² = ‖u′‖² + ‖v′‖² − 2(u′ᵀv′ cos θ + ωᵀ(u′ × v′) sin θ) = δ′²
    a = 2.0 * float(up @ vp)
    b = 2.0 * float(w @ np.cross(up, vp))
    c = nu * nu + nv * nv - d2
    roots = _trig_roots(a, b, c, tol=1e-10)
    return sorted(roots or [])
