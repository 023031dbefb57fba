r"""Newton–Euler dynamics in product-of-exponentials form (Lecture 7, seed 004 §4, Modern Robotics ch. 8).

Model (Modern Robotics): ``Mlist[i]`` is the pose of link frame {i+1} (at the centre of
mass) in frame {i}, ``Mlist[n]`` the end-effector frame in {n}; ``Glist[i]`` the 6×6
spatial inertia of link i+1 in its frame, angular first ``[[I, 0], [0, m 1]]``; ``Slist``
the space screw axes (6×n). Wrenches ``(m, f)`` are angular first; ``Ftip`` is the wrench
the end-effector applies *to the environment*, expressed in the end-effector frame.

With ``Aᵢ = Ad_{M₀ᵢ⁻¹} Sᵢ`` (joint i's screw in frame {i}, ``M₀ᵢ = Mlist[0]⋯Mlist[i−1]``) and
``T_{i,i−1} = e^{−[Aᵢ]θᵢ} Mlist[i−1]⁻¹``:

forward iterations (i = 1..n), with ``V₀ = 0``, ``V̇₀ = (0, −g)`` (gravity as a base acceleration):
    ``Vᵢ = Ad_{T_{i,i−1}} V_{i−1} + Aᵢ θ̇ᵢ``
    ``V̇ᵢ = Ad_{T_{i,i−1}} V̇_{i−1} + ad_{Vᵢ} Aᵢ θ̇ᵢ + Aᵢ θ̈ᵢ``
backward iterations (i = n..1), with ``F_{n+1} = Ftip``, ``T_{n+1,n} = Mlist[n]⁻¹``:
    ``Fᵢ = Ad_{T_{i+1,i}}ᵀ F_{i+1} + Gᵢ V̇ᵢ − ad_{Vᵢ}ᵀ Gᵢ Vᵢ``,  ``τᵢ = Fᵢᵀ Aᵢ``.

The mass matrix uses the composite-rigid-body algorithm in the same frames
(``Kᵢ = Gᵢ + Ad_{T_{i+1,i}}ᵀ K_{i+1} Ad_{T_{i+1,i}}``, ``M_{ji} = A_jᵀ (Ad …)ᵀ Kᵢ Aᵢ``), which
equals n calls of inverse dynamics with unit accelerations, at a fraction of the cost.
The model constants (Aᵢ, Mlist⁻¹, the screw exponential data) are computed once per model
and cached, so repeated calls on the same model only do the recursions.
"""
from __future__ import annotations

import numpy as np

from robokit._arrays import as_array, as_scalar, as_vector
from robokit.kinematics.poe import _adjoint_many, _exps
from robokit.spatial.se3 import _inv

__all__ = [
    "inverse_dynamics",
    "mass_matrix",
    "vel_quadratic_forces",
    "gravity_forces",
    "end_effector_forces",
    "forward_dynamics",
    "euler_step",
    "inverse_dynamics_trajectory",
    "forward_dynamics_trajectory",
]

_MODELS: dict = {}




class _Model:
    """Constants of one (Mlist, Glist, Slist) model."""

    def __init__(self, Mlist, Glist, Slist):
        n = Slist.shape[1]
        self.n = n
        self.Minv = np.array([_inv(M) for M in Mlist])  # (n+1, 4, 4)
        self.G = np.array(Glist)  # (n, 6, 6)
        M0i = np.eye(4)
        A = np.empty((6, n))
        for i in range(n):
            M0i = M0i @ Mlist[i]
            A[:, i] = _adjoint_many(_inv(M0i)[None])[0] @ Slist[:, i]
        self.A = A
        self.AT = np.ascontiguousarray(A.T)  # rows Aᵢ
        self.Ad_tip = _adjoint_many(self.Minv[n][None])[0]  # Ad_{T_{n+1,n}}

    def transforms(self, theta):
        """Ad_{T_{i,i−1}} for i = 1..n: (n, 6, 6)."""
        T = _exps(self.A, -theta) @ self.Minv[: self.n]
        return _adjoint_many(T)


def _model(Mlist, Glist, Slist) -> _Model:
    if all(type(a) is np.ndarray and a.dtype == np.float64 for a in (Mlist, Glist, Slist)):
        hit = _MODELS.get((Mlist.tobytes(), Glist.tobytes(), Slist.tobytes()))
        if hit is not None and hit.n == Slist.shape[1] and Mlist.shape == (hit.n + 1, 4, 4):
            return hit  # already validated constants
    Slist = as_array(Slist, "Slist", (6, None))
    n = Slist.shape[1]
    Mlist = as_array(Mlist, "Mlist", (n + 1, 4, 4))
    Glist = as_array(Glist, "Glist", (n, 6, 6))
    key = (Mlist.tobytes(), Glist.tobytes(), Slist.tobytes())
    m = _MODELS.get(key)
    if m is None:
        if np.abs(Mlist[:, 3, :] - np.array([0.0, 0.0, 0.0, 1.0])).max() > 1e-9:
            raise ValueError("Mlist: expected homogeneous transforms (last row [0, 0, 0, 1])")
        if np.abs(Glist - np.swapaxes(Glist, 1, 2)).max() > 1e-9 * max(1.0, np.abs(Glist).max()):
            raise ValueError("Glist: expected symmetric 6×6 spatial inertias")
        if len(_MODELS) > 32:
            _MODELS.clear()
        m = _MODELS[key] = _Model(Mlist, Glist, Slist)
    return m


def _ad_times(V, X):
    """``ad_V X = (ω × x_ω, v × x_ω + ω × x_v)`` for single twists, in plain floats (fast for 6-vectors)."""
    w0, w1, w2, v0, v1, v2 = V.tolist()
    a0, a1, a2, b0, b1, b2 = X.tolist()
    return np.array([w1 * a2 - w2 * a1, w2 * a0 - w0 * a2, w0 * a1 - w1 * a0,
                     v1 * a2 - v2 * a1 + w1 * b2 - w2 * b1,
                     v2 * a0 - v0 * a2 + w2 * b0 - w0 * b2,
                     v0 * a1 - v1 * a0 + w0 * b1 - w1 * b0])


def _adT_times(V, F):
    """``ad_Vᵀ F = −(ω × m + v × f, ω × f)`` for a twist V and a wrench F = (m, f)."""
    w0, w1, w2, v0, v1, v2 = V.tolist()
    m0, m1, m2, f0, f1, f2 = F.tolist()
    return np.array([-(w1 * m2 - w2 * m1 + v1 * f2 - v2 * f1),
                     -(w2 * m0 - w0 * m2 + v2 * f0 - v0 * f2),
                     -(w0 * m1 - w1 * m0 + v0 * f1 - v1 * f0),
                     -(w1 * f2 - w2 * f1), -(w2 * f0 - w0 * f2), -(w0 * f1 - w1 * f0)])


def _rnea(m: _Model, theta, dtheta, ddtheta, g, Ftip):
    n = m.n
    Ad = m.transforms(theta)
    A, G = m.AT, m.G
    V = np.zeros(6)
    Vd = np.zeros(6)
    Vd[3:] = -g
    Vs = np.empty((n, 6))
    Vds = np.empty((n, 6))
    for i in range(n):
        Ai = A[i]
        V = Ad[i] @ V + Ai * dtheta[i]
        Vd = Ad[i] @ Vd + _ad_times(V, Ai) * dtheta[i] + Ai * ddtheta[i]
        Vs[i] = V
        Vds[i] = Vd
    F = Ftip
    Ad_next = m.Ad_tip
    tau = np.empty(n)
    for i in range(n - 1, -1, -1):
        F = Ad_next.T @ F + G[i] @ Vds[i] - _adT_times(Vs[i], G[i] @ Vs[i])
        tau[i] = F @ A[i]
        Ad_next = Ad[i]
    return tau


def _cross_b(a, b):
    """Row-wise cross products of (N, 3) arrays (faster than np.cross for small N·3)."""
    out = np.empty_like(b if b.ndim == 2 else a)
    a0, a1, a2 = (a[..., 0], a[..., 1], a[..., 2])
    b0, b1, b2 = (b[..., 0], b[..., 1], b[..., 2])
    out[..., 0] = a1 * b2 - a2 * b1
    out[..., 1] = a2 * b0 - a0 * b2
    out[..., 2] = a0 * b1 - a1 * b0
    return out


def _ad_apply(V, X):
    """ad_V X for batches of twists V, X (N, 6): (ω × x_ω, v × x_ω + ω × x_v)."""
    w, v = V[:, :3], V[:, 3:]
    xw, xv = X[..., :3], X[..., 3:]
    out = np.empty((V.shape[0], 6))
    out[:, :3] = _cross_b(w, np.broadcast_to(xw, w.shape))
    out[:, 3:] = _cross_b(v, np.broadcast_to(xw, w.shape)) + _cross_b(w, np.broadcast_to(xv, w.shape))
    return out


def _adT_apply(V, F):
    """ad_Vᵀ F for batches (N, 6): (−(ω × m + v × f), −ω × f) with F = (m, f)."""
    w, v = V[:, :3], V[:, 3:]
    mm, ff = F[:, :3], F[:, 3:]
    out = np.empty_like(F)
    out[:, :3] = -(_cross_b(w, mm) + _cross_b(v, ff))
    out[:, 3:] = -_cross_b(w, ff)
    return out


def _rnea_batch(m: _Model, theta, dtheta, ddtheta, g, Ftip):
    """Newton–Euler for N configurations at once: theta, dtheta, ddtheta (N, n); Ftip (N, 6) or (6,)."""
    N, n = theta.shape
    Ad = _adjoint_many(_exps(m.A, -theta) @ m.Minv[:n])  # (N, n, 6, 6)
    A, G = m.AT, m.G
    V = np.zeros((N, 6))
    Vd = np.zeros((N, 6))
    Vd[:, 3:] = -g
    Vs = np.empty((n, N, 6))
    Vds = np.empty((n, N, 6))
    for i in range(n):
        Ai = A[i]
        V = np.einsum("nij,nj->ni", Ad[:, i], V) + Ai * dtheta[:, i:i + 1]
        Vd = np.einsum("nij,nj->ni", Ad[:, i], Vd) + _ad_apply(V, Ai) * dtheta[:, i:i + 1] + Ai * ddtheta[:, i:i + 1]
        Vs[i], Vds[i] = V, Vd
    F = np.broadcast_to(Ftip, (N, 6)).copy()
    tau = np.empty((N, n))
    for i in range(n - 1, -1, -1):
        F = F @ m.Ad_tip if i == n - 1 else np.einsum("nji,nj->ni", Ad[:, i + 1], F)
        F = F + Vds[i] @ G[i].T - _adT_apply(Vs[i], Vs[i] @ G[i].T)
        tau[:, i] = F @ A[i]
    return tau


def _crba_batch(m: _Model, theta):
    """Mass matrices (N, n, n) by the composite-rigid-body algorithm, vectorised over N."""
    N, n = theta.shape
    Ad = _adjoint_many(_exps(m.A, -theta) @ m.Minv[:n])
    A = m.AT
    K = np.broadcast_to(m.G, (N, n, 6, 6)).copy()
    for i in range(n - 1, 0, -1):
        AdT = np.swapaxes(Ad[:, i], 1, 2)
        K[:, i - 1] += AdT @ K[:, i] @ Ad[:, i]
    M = np.empty((N, n, n))
    for i in range(n):
        F = K[:, i] @ A[i]
        M[:, i, i] = F @ A[i]
        for j in range(i, 0, -1):
            F = np.einsum("nji,nj->ni", Ad[:, j], F)
            M[:, j - 1, i] = M[:, i, j - 1] = F @ A[j - 1]
    return M


def _crba(m: _Model, theta):
    n = m.n
    Ad = m.transforms(theta)
    A, G = m.AT, m.G
    K = G.copy()
    for i in range(n - 1, 0, -1):
        K[i - 1] = K[i - 1] + Ad[i].T @ K[i] @ Ad[i]
    M = np.empty((n, n))
    for i in range(n):
        F = K[i] @ A[i]
        M[i, i] = F @ A[i]
        for j in range(i, 0, -1):
            F = Ad[j].T @ F  # the composite force, expressed in frame {j}
            M[j - 1, i] = M[i, j - 1] = F @ A[j - 1]
    return M


def _vec(x, name, n):
    return as_vector(x, name, n)


def _args(thetalist, Mlist, Glist, Slist):
    m = _model(Mlist, Glist, Slist)
    return m, _vec(thetalist, "thetalist", m.n)


def inverse_dynamics(thetalist, dthetalist, ddthetalist, g, Ftip, Mlist, Glist, Slist) -> np.ndarray:
    """Joint torques ``τ = M(θ)θ̈ + c(θ, θ̇) + g(θ) + Jᵀ(θ) F_tip`` by Newton–Euler (n,).

    thetalist, dthetalist, ddthetalist : (n,) rad, rad/s, rad/s² — or (N, n) for N states at
    once (then τ is (N, n), computed vectorised over N); g : (3,) gravity (m/s²), e.g.
    [0, 0, −9.81]; Ftip : (6,) (or (N, 6)) wrench (m, f) applied by the end-effector, in its
    frame; Mlist : n+1 4×4; Glist : n 6×6; Slist : 6×n (Modern Robotics form).
    """
    m = _model(Mlist, Glist, Slist)
    if np.ndim(thetalist) == 2:
        th = as_array(thetalist, "thetalist", (None, m.n))
        N = th.shape[0]
        dth = as_array(dthetalist, "dthetalist", (N, m.n))
        ddth = as_array(ddthetalist, "ddthetalist", (N, m.n))
        F = as_array(Ftip, "Ftip", (N, 6) if np.ndim(Ftip) == 2 else (6,))
        g = _vec(g, "g", 3)
        if N <= 4:  # too few to pay for the vectorised set-up
            Fk = np.broadcast_to(F, (N, 6))
            return np.array([_rnea(m, th[k], dth[k], ddth[k], g, Fk[k]) for k in range(N)]).reshape(N, m.n)
        return _rnea_batch(m, th, dth, ddth, g, F)
    th = _vec(thetalist, "thetalist", m.n)
    return _rnea(m, th, _vec(dthetalist, "dthetalist", m.n), _vec(ddthetalist, "ddthetalist", m.n),
                 _vec(g, "g", 3), _vec(Ftip, "Ftip", 6))


def mass_matrix(thetalist, Mlist, Glist, Slist) -> np.ndarray:
    """The n×n mass matrix M(θ) (composite-rigid-body algorithm), symmetric positive definite.

    thetalist : (n,), or (N, n) for N configurations at once (then (N, n, n), vectorised).
    """
    m = _model(Mlist, Glist, Slist)
    if np.ndim(thetalist) == 2:
        th = as_array(thetalist, "thetalist", (None, m.n))
        if th.shape[0] <= 4:
            return np.array([_crba(m, t) for t in th]).reshape(th.shape[0], m.n, m.n)
        return _crba_batch(m, th)
    return _crba(m, _vec(thetalist, "thetalist", m.n))


def vel_quadratic_forces(thetalist, dthetalist, Mlist, Glist, Slist) -> np.ndarray:
    """Coriolis and centripetal torques ``c(θ, θ̇)`` (n,): inverse dynamics with θ̈ = 0, g = 0, F_tip = 0."""
    m, th = _args(thetalist, Mlist, Glist, Slist)
    z = np.zeros(m.n)
    return _rnea(m, th, _vec(dthetalist, "dthetalist", m.n), z, np.zeros(3), np.zeros(6))


def gravity_forces(thetalist, g, Mlist, Glist, Slist) -> np.ndarray:
    """Gravity torques ``g(θ)`` (n,): inverse dynamics with θ̇ = θ̈ = 0, F_tip = 0."""
    m, th = _args(thetalist, Mlist, Glist, Slist)
    z = np.zeros(m.n)
    return _rnea(m, th, z, z, _vec(g, "g", 3), np.zeros(6))


def end_effector_forces(thetalist, Ftip, Mlist, Glist, Slist) -> np.ndarray:
    """Torques ``Jᵀ(θ) F_tip`` (n,) that balance the tip wrench: inverse dynamics with no motion, no gravity."""
    m, th = _args(thetalist, Mlist, Glist, Slist)
    z = np.zeros(m.n)
    return _rnea(m, th, z, z, np.zeros(3), _vec(Ftip, "Ftip", 6))


def forward_dynamics(thetalist, dthetalist, taulist, g, Ftip, Mlist, Glist, Slist) -> np.ndarray:
    """Joint accelerations ``θ̈ = M(θ)⁻¹ (τ − c(θ, θ̇) − g(θ) − Jᵀ F_tip)`` (n,).

    One Newton–Euler pass gives the bias ``c + g + JᵀF`` and the CRBA gives M; the linear
    system is solved by Cholesky (M is symmetric positive definite).
    """
    m, th = _args(thetalist, Mlist, Glist, Slist)
    dth = _vec(dthetalist, "dthetalist", m.n)
    bias = _rnea(m, th, dth, np.zeros(m.n), _vec(g, "g", 3), _vec(Ftip, "Ftip", 6))
    M = _crba(m, th)
    rhs = _vec(taulist, "taulist", m.n) - bias
    try:
        L = np.linalg.cholesky(M)
        return np.linalg.solve(L.T, np.linalg.solve(L, rhs))
    except np.linalg.LinAlgError:
        raise ValueError("Glist: the mass matrix is not positive definite at this configuration "
                         "(a joint drives no inertia)") from None


def euler_step(thetalist, dthetalist, ddthetalist, dt):
    """One explicit Euler step: ``(θ + dt θ̇, θ̇ + dt θ̈)``; dt in s."""
    th = as_vector(thetalist, "thetalist")
    n = len(th)
    dth = as_vector(dthetalist, "dthetalist", n)
    ddth = as_vector(ddthetalist, "ddthetalist", n)
    dt = as_scalar(dt, "dt")
    return th + dt * dth, dth + dt * ddth


def inverse_dynamics_trajectory(thetamat, dthetamat, ddthetamat, g, Ftipmat, Mlist, Glist, Slist) -> np.ndarray:
    """Torques along a trajectory: row k of the (N, n) result is ``inverse_dynamics`` of row k.

    thetamat, dthetamat, ddthetamat : (N, n); Ftipmat : (N, 6); g : (3,).
    """
    m = _model(Mlist, Glist, Slist)
    Q = as_array(thetamat, "thetamat", (None, m.n))
    N = Q.shape[0]
    dQ = as_array(dthetamat, "dthetamat", (N, m.n))
    ddQ = as_array(ddthetamat, "ddthetamat", (N, m.n))
    F = as_array(Ftipmat, "Ftipmat", (N, 6))
    g = _vec(g, "g", 3)
    return np.array([_rnea(m, Q[k], dQ[k], ddQ[k], g, F[k]) for k in range(N)]).reshape(N, m.n)


def forward_dynamics_trajectory(thetalist, dthetalist, taumat, g, Ftipmat, Mlist, Glist, Slist, dt, intRes):
    """Simulate the arm under a torque history with Euler integration (Modern Robotics semantics).

    thetalist, dthetalist : (n,) initial state; taumat : (N, n) torques, row k held over
    [k dt, (k+1) dt); Ftipmat : (N, 6); dt : s; intRes : Euler steps per dt.
    Returns ``(thetamat, dthetamat)``, both (N, n): row 0 is the initial state, row k+1 the
    state after applying row k (the last torque row is not applied, as in Modern Robotics).
    """
    m = _model(Mlist, Glist, Slist)
    th = _vec(thetalist, "thetalist", m.n).copy()
    dth = _vec(dthetalist, "dthetalist", m.n).copy()
    tau = as_array(taumat, "taumat", (None, m.n))
    N = tau.shape[0]
    F = as_array(Ftipmat, "Ftipmat", (N, 6))
    g = _vec(g, "g", 3)
    dt = as_scalar(dt, "dt", positive=True)
    intRes = int(intRes)
    if intRes < 1:
        raise ValueError(f"intRes: expected a positive integer, got {intRes}")
    h = dt / intRes
    thetamat = np.empty((N, m.n))
    dthetamat = np.empty((N, m.n))
    thetamat[0], dthetamat[0] = th, dth
    z = np.zeros(m.n)
    for k in range(N - 1):
        for _ in range(intRes):
            M = _crba(m, th)
            bias = _rnea(m, th, dth, z, g, F[k])
            ddth = np.linalg.solve(M, tau[k] - bias)
            th, dth = th + h * dth, dth + h * ddth
        thetamat[k + 1], dthetamat[k + 1] = th, dth
    return thetamat, dthetamat
