r"""Closed-form dynamics of the planar two-link arm with point masses at the link ends (Lecture 7).

With c₂ = cos θ₂, s₂ = sin θ₂, c₁ = cos θ₁, c₁₂ = cos(θ₁ + θ₂) and gravity g along −y:

    M = [[l₂²m₂ + 2l₁l₂m₂c₂ + l₁²(m₁ + m₂), l₂²m₂ + l₁l₂m₂c₂], [l₂²m₂ + l₁l₂m₂c₂, l₂²m₂]]
    V = [−m₂l₁l₂s₂θ̇₂² − 2m₂l₁l₂s₂θ̇₁θ̇₂, m₂l₁l₂s₂θ̇₁²]
    G = [m₂l₂g c₁₂ + (m₁ + m₂)l₁g c₁, m₂l₂g c₁₂]

and the configuration-space form ``τ = M θ̈ + B [θ̇₁θ̇₂] + C [θ̇₁², θ̇₂²] + G`` with
``B = [−2m₂l₁l₂s₂, 0]ᵀ``, ``C = [[0, −m₂l₁l₂s₂], [m₂l₁l₂s₂, 0]]``.
"""
from __future__ import annotations

import math

import numpy as np
from numpy.typing import ArrayLike

from robokit._arrays import as_vector

__all__ = ["twolink_dynamics"]


def twolink_dynamics(q: ArrayLike, dq: ArrayLike, l1: float, l2: float, m1: float, m2: float,
                     g: float = 9.81) -> dict[str, np.ndarray]:
    """The Lecture 7 closed forms of the planar two-link arm with point masses at the link ends.

    See the module docstring for M, V, G, B and C.

    Parameters
    ----------
    q, dq : (2,) array_like
        Joint angles (rad) and rates (rad/s).
    l1, l2 : float
        Link lengths (m).
    m1, m2 : float
        Point masses at the ends of links 1 and 2 (kg).
    g : float, optional
        Gravity magnitude (m/s²), acting along −y; default 9.81.

    Returns
    -------
    dict of str to ndarray
        ``"M"`` (2, 2) kg·m²; ``"V"`` (2,) and ``"G"`` (2,) N·m; ``"B"`` (2, 1) and ``"C"`` (2, 2)
        N·m·s², so that ``τ = M θ̈ + V + G = M θ̈ + B θ̇₁θ̇₂ + C (θ̇₁², θ̇₂²) + G``.

    Examples
    --------
    They agree with the course Newton–Euler on the shipped model of the same arm:

    >>> d = twolink_dynamics([0, np.pi / 2], [1, 1], 1.0, 0.8, 2.0, 1.5)
    >>> d["M"].round(4), d["V"].round(4)
    (array([[4.46, 0.96],
           [0.96, 0.96]]), array([-3.6,  1.2]))
    >>> p = rk.load("twolink").poe
    >>> bool(np.allclose(d["M"], rk.mass_matrix([0, np.pi / 2], p.Mlist, p.Glist, p.Slist)))
    True
    """
    q1, q2 = as_vector(q, "q", 2)
    d1, d2 = as_vector(dq, "dq", 2)
    c1, c2, s2, c12 = math.cos(q1), math.cos(q2), math.sin(q2), math.cos(q1 + q2)
    M = np.array([[l2**2 * m2 + 2 * l1 * l2 * m2 * c2 + l1**2 * (m1 + m2), l2**2 * m2 + l1 * l2 * m2 * c2],
                  [l2**2 * m2 + l1 * l2 * m2 * c2, l2**2 * m2]])
    V = np.array([-m2 * l1 * l2 * s2 * d2**2 - 2 * m2 * l1 * l2 * s2 * d1 * d2, m2 * l1 * l2 * s2 * d1**2])
    G = np.array([m2 * l2 * g * c12 + (m1 + m2) * l1 * g * c1, m2 * l2 * g * c12])
    B = np.array([[-2 * m2 * l1 * l2 * s2], [0.0]])
    C = np.array([[0.0, -m2 * l1 * l2 * s2], [m2 * l1 * l2 * s2, 0.0]])
    return {"M": M, "V": V, "G": G, "B": B, "C": C}
