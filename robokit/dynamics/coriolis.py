r"""The Coriolis matrix C(q, q̇) of the dynamic equation ``τ = M q̈ + C q̇ + g`` (Lecture 7).

:func:`coriolis_matrix` — a factorisation with ``C q̇ = c(q, q̇)``: by default the one with
``Ṁ − 2C`` skew-symmetric, from the PoE model: with each link's body Jacobian Jᵢ, spatial
inertia Gᵢ and twist Vᵢ = Jᵢ q̇, ``C = Σᵢ Jᵢᵀ (Gᵢ J̇ᵢ + Bᵢ Jᵢ)`` where
``Bᵢ = ½ (−ad_{Vᵢ}ᵀ Gᵢ + Gᵢ ad_{Vᵢ} + X(Gᵢ Vᵢ))`` is skew and satisfies ``Bᵢ Vᵢ = −ad_{Vᵢ}ᵀ Gᵢ Vᵢ``
(X(h) the matrix with ``X(h) V = −ad_Vᵀ h``); ``J̇ᵢ`` column j is ``ad_{Jᵢ,j} Σ_{k>j} Jᵢ,k q̇_k``.
"""
from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike

from robokit._arrays import as_vector
from robokit.dynamics.newton_euler import _Model, _model, _radians, inverse_dynamics
from robokit.spatial import lie
from robokit.errors import InputError

__all__ = ["coriolis_matrix"]


def _X(h: np.ndarray) -> np.ndarray:
    """X(h) with X(h) V = −ad_Vᵀ h for every twist V (h a wrench (m, f))."""
    X = np.zeros((6, 6))
    X[:3, :3] = -lie.hat(h[:3])
    X[:3, 3:] = -lie.hat(h[3:])
    X[3:, :3] = -lie.hat(h[3:])
    return X


def _link_jacobians(m: _Model, theta: np.ndarray) -> np.ndarray:
    """Body Jacobians Jᵢ (n, 6, n) of the link frames {1..n} (Modern Robotics frames)."""
    n = m.n
    Ad = m.transforms(theta)  # Ad_{T_{i,i−1}}
    J = np.zeros((n, 6, n))
    for i in range(n):
        if i > 0:
            J[i, :, :i] = Ad[i] @ J[i - 1, :, :i]
        J[i, :, i] = m.AT[i]
    return J


def coriolis_matrix(thetalist: ArrayLike, dthetalist: ArrayLike, Mlist: ArrayLike, Glist: ArrayLike,
                    Slist: ArrayLike, method: str = "christoffel") -> np.ndarray:
    """The n×n Coriolis matrix C(θ, θ̇) with ``C θ̇ = c(θ, θ̇)``, in one of two factorisations (Lecture 7).

    The velocity-product torque ``c(θ, θ̇) = Σⱼₖ cᵢⱼₖ θ̇ⱼ θ̇ₖ`` is a quadratic form in θ̇; C is not
    unique, only ``C θ̇`` is. For the PUMA 560 at the lecture's nominal pose
    ``qn = (0, π/4, π, 0, π/4, 0)`` with all rates 0.5 rad/s, ``C₁₂`` is −0.9115 (lecture) and
    −0.6453 (Christoffel); ``C θ̇`` agrees.

    Parameters
    ----------
    thetalist, dthetalist : (n,) array_like
        Joint values and rates (rad, rad/s).
    Mlist, Glist, Slist : (n+1, 4, 4), (n, 6, 6), (6, n) array_like
        The model: link frames (m), spatial inertias (kg·m², kg), screw axes (:mod:`robokit.dynamics.newton_euler`).
    method : {"christoffel", "lecture"}, optional
        ``"christoffel"`` (default) — the Christoffel-symbol matrix ``Cₖⱼ = Σᵢ Γᵢⱼₖ θ̇ᵢ`` of the mass
        matrix, the one with ``Ṁ − 2C`` skew-symmetric (computed from the link body Jacobians, see
        the module docstring); ``"lecture"`` — the factorisation the lecture prints (Corke's
        toolbox, from Newton–Euler runs with ``θ̈ = 0`` and no gravity): column k collects the
        centripetal term of θ̇ₖ and every Coriolis product θ̇ⱼθ̇ₖ with j < k,
        ``C[:, k] = c(eₖ) θ̇ₖ + Σ_{j<k} (c(eⱼ + eₖ) − c(eⱼ) − c(eₖ)) θ̇ⱼ``, with ``c(u)`` the
        velocity-product torque at joint rates u.

    Returns
    -------
    (n, n) ndarray
        C(θ, θ̇) in N·m·s (revolute joints).

    Raises
    ------
    InputError
        On a ``method`` other than ``"christoffel"`` and ``"lecture"``, or joint values or a
        model of the wrong shape, NaN or infinite.

    Examples
    --------
    The planar two-link arm at θ₂ = π/2, θ̇ = (1, 1): both factorisations give the same
    ``C θ̇ = c(θ, θ̇) = (−3.6, 1.2)`` (:func:`robokit.vel_quadratic_forces`), but different C:

    >>> p = rk.load("twolink").poe
    >>> q, dq = [0.3, np.pi / 2], [1.0, 1.0]
    >>> C = coriolis_matrix(q, dq, p.Mlist, p.Glist, p.Slist)
    >>> C.round(4), (C @ dq).round(4)
    (array([[-1.2, -2.4],
           [ 1.2,  0. ]]), array([-3.6,  1.2]))
    >>> (coriolis_matrix(q, dq, p.Mlist, p.Glist, p.Slist, "lecture") @ dq).round(4)
    array([-3.6,  1.2])
    """
    if method not in ("christoffel", "lecture"):
        raise InputError(f"method: expected 'christoffel' or 'lecture', got {method!r}")
    m = _model(Mlist, Glist, Slist)
    th = _radians(m, as_vector(thetalist, "thetalist", m.n))
    dth = as_vector(dthetalist, "dthetalist", m.n)
    n = m.n
    if method == "lecture":
        return _coriolis_lecture(th, dth, Mlist, Glist, Slist, n)
    J = _link_jacobians(m, th)
    C = np.zeros((n, n))
    for i in range(n):
        Ji = J[i]
        V = Ji @ dth
        Jd = np.zeros((6, n))
        for j in range(i + 1):
            rel = Ji[:, j + 1:i + 1] @ dth[j + 1:i + 1]
            Jd[:, j] = lie.ad(Ji[:, j]) @ rel
        G = m.G[i]
        adV = lie.ad(V)
        B = 0.5 * (-adV.T @ G + G @ adV + _X(G @ V))
        C += Ji.T @ (G @ Jd + B @ Ji)
    return C


def _coriolis_lecture(th: np.ndarray, dth: np.ndarray, Mlist: ArrayLike, Glist: ArrayLike, Slist: ArrayLike,
                      n: int) -> np.ndarray:
    """The lecture's (Corke's) factorisation, from velocity-product torques c(u) (θ̈ = 0, g = 0)."""
    z3, z6, zn = np.zeros(3), np.zeros(6), np.zeros(n)

    def c(u: np.ndarray) -> np.ndarray:
        return inverse_dynamics(th, u, zn, z3, z6, Mlist, Glist, Slist)

    eye = np.eye(n)
    Csq = np.column_stack([c(eye[j]) for j in range(n)])  # c(eⱼ): the θ̇ⱼ² coefficients
    C = Csq * dth  # centripetal: column j times θ̇ⱼ
    for j in range(n):
        for k in range(j + 1, n):
            C[:, k] += (c(eye[j] + eye[k]) - Csq[:, j] - Csq[:, k]) * dth[j]
    return C
