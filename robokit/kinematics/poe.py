r"""Product-of-exponentials forward kinematics and Jacobians (Lecture 4/6, seed 004 §3).

Screw axes are the columns of a 6×n array, angular first ``(ω, v)``.

* space form:  ``T(θ) = e^{[S₁]θ₁} ⋯ e^{[Sₙ]θₙ} M``;
  space Jacobian ``J_s = [S₁, Ad_{e^{[S₁]θ₁}} S₂, …, Ad_{e^{[S₁]θ₁}⋯e^{[Sₙ₋₁]θₙ₋₁}} Sₙ]``;
* body form:   ``T(θ) = M e^{[B₁]θ₁} ⋯ e^{[Bₙ]θₙ}``;
  body Jacobian ``J_b = [Ad_{e^{−[Bₙ]θₙ}⋯e^{−[B₂]θ₂}} B₁, …, Bₙ]``.

Each exponential of a unit screw uses the closed form (Rodrigues for the rotation, and
``G(θ)v`` for the translation), so these are exact to rounding. The batched variants
accept a leading dimension of configurations (N, n) and are vectorised over it.
"""
from __future__ import annotations

import numpy as np

from robokit._arrays import as_array, as_matrix
from robokit.spatial.se3 import check_transform

__all__ = ["fkin_body", "fkin_space", "jacobian_body", "jacobian_space"]


_VALID: set = set()  # bytes of model constants (screw lists, home poses) already validated


def _screws(S, name):
    """A 6×n float array of screw axes; constants are validated once and remembered."""
    if type(S) is np.ndarray and S.dtype == np.float64 and S.ndim == 2 and S.shape[0] == 6:
        key = (name, S.shape, S.tobytes())
        if key in _VALID:
            return S
        S = as_matrix(S, name, 6, None)
        if len(_VALID) > 256:
            _VALID.clear()
        _VALID.add(key)
        return S
    return as_matrix(S, name, 6, None)


def _home(M):
    """A validated 4×4 home pose (remembered once validated)."""
    if type(M) is np.ndarray and M.dtype == np.float64 and M.shape == (4, 4):
        key = ("M", M.tobytes())
        if key in _VALID:
            return M
        M = check_transform(M, "M")
        _VALID.add(key)
        return M
    return check_transform(M, "M")


def _theta(thetalist, n, name="thetalist"):
    if type(thetalist) is np.ndarray and thetalist.dtype == np.float64 and thetalist.shape == (n,):
        th = thetalist
    else:
        th = as_array(thetalist, name, finite=False)
        if th.ndim not in (1, 2) or th.shape[-1] != n:
            raise ValueError(f"{name}: expected shape ({n},) or (N, {n}) for {n} screw axes, got shape {th.shape}")
    if not np.isfinite(th).all():
        raise ValueError(f"{name}: contains NaN or infinite values")
    return th


_CACHE: dict = {}


def _screw_data(S: np.ndarray):
    """Per-screw constants, cached by the screws' bytes: for each column, the unit-axis
    skew matrix W and W², the scaled v, Wv, W²v and the scale ‖ω‖ (1 for prismatic)."""
    key = (S.shape, S.tobytes())
    hit = _CACHE.get(key)
    if hit is not None:
        return hit
    n = S.shape[1]
    W = np.zeros((n, 3, 3))
    v = np.zeros((n, 3))
    scale = np.ones(n)
    rev = np.zeros(n, dtype=bool)
    for i in range(n):
        w, vi = S[:3, i], S[3:, i]
        wn = float(np.linalg.norm(w))
        if wn > 1e-12:
            rev[i] = True
            scale[i] = wn
            w = w / wn
            vi = vi / wn
            W[i] = [[0.0, -w[2], w[1]], [w[2], 0.0, -w[0]], [-w[1], w[0], 0.0]]
        v[i] = vi
    W2 = W @ W
    Wv = np.einsum("nij,nj->ni", W, v)
    W2v = np.einsum("nij,nj->ni", W2, v)
    data = (W, W2, v, Wv, W2v, scale, rev)
    if len(_CACHE) > 64:
        _CACHE.clear()
    _CACHE[key] = data
    return data


def _exps(S: np.ndarray, theta: np.ndarray) -> np.ndarray:
    """exp([Sᵢ]θᵢ) for every screw column i: theta (..., n) → (..., n, 4, 4).

    Closed form for a screw with ‖ω‖ ≠ 0 (scaled to a unit axis, θ' = ‖ω‖θ):
    R = I + sin θ' W + (1 − cos θ') W², p = θ' v + (1 − cos θ') W v + (θ' − sin θ') W² v;
    for ω = 0 (prismatic): R = I, p = θ v.
    """
    W, W2, v, Wv, W2v, scale, rev = _screw_data(S)
    th = theta * scale
    st, ct = np.sin(th), np.cos(th)
    st = np.where(rev, st, 0.0)
    omc = np.where(rev, 1.0 - ct, 0.0)
    tms = np.where(rev, th - st, 0.0)
    out = np.zeros(theta.shape + (4, 4))
    out[..., :3, :3] = np.eye(3) + st[..., None, None] * W + omc[..., None, None] * W2
    out[..., :3, 3] = th[..., None] * v + omc[..., None] * Wv + tms[..., None] * W2v
    out[..., 3, 3] = 1.0
    return out


def _chain(E):
    """Running products along the joint axis: E (..., n, 4, 4) → P (..., n, 4, 4), Pᵢ = E₀⋯Eᵢ."""
    P = np.empty_like(E)
    P[..., 0, :, :] = E[..., 0, :, :]
    for i in range(1, E.shape[-3]):
        P[..., i, :, :] = P[..., i - 1, :, :] @ E[..., i, :, :]
    return P


def fkin_space(M, Slist, thetalist) -> np.ndarray:
    """End-effector pose ``e^{[S₁]θ₁} ⋯ e^{[Sₙ]θₙ} M`` (space form of the PoE formula).

    M : 4×4 home pose of the end-effector; Slist : 6×n space screw axes (columns, (ω, v));
    thetalist : (n,) joint values, or (N, n) for N configurations at once.
    Returns 4×4 (or (N, 4, 4)).

    Example: ``fkin_space(M, Slist, np.zeros(n))`` is ``M``.
    """
    Slist = _screws(Slist, "Slist")
    M = _home(M)
    th = _theta(thetalist, Slist.shape[1])
    E = _exps(Slist, th)
    T = E[..., 0, :, :]
    for i in range(1, Slist.shape[1]):
        T = T @ E[..., i, :, :]
    return T @ M


def fkin_body(M, Blist, thetalist) -> np.ndarray:
    """End-effector pose ``M e^{[B₁]θ₁} ⋯ e^{[Bₙ]θₙ}`` (body form of the PoE formula).

    M : 4×4 home pose; Blist : 6×n body screw axes (in the end-effector frame at home);
    thetalist : (n,) or (N, n). Returns 4×4 (or (N, 4, 4)).
    """
    Blist = _screws(Blist, "Blist")
    M = _home(M)
    th = _theta(thetalist, Blist.shape[1])
    E = _exps(Blist, th)
    T = M @ E[..., 0, :, :]
    for i in range(1, Blist.shape[1]):
        T = T @ E[..., i, :, :]
    return T


def jacobian_space(Slist, thetalist) -> np.ndarray:
    """Space Jacobian ``J_s(θ)`` (6×n, rows (ω; v)): twist of the end-effector in the space frame.

    Column i is ``Ad_{e^{[S₁]θ₁}⋯e^{[S_{i−1}]θ_{i−1}}} Sᵢ``. Slist : 6×n; thetalist : (n,) or (N, n).
    Returns 6×n (or (N, 6, n)).
    """
    Slist = _screws(Slist, "Slist")
    n = Slist.shape[1]
    th = _theta(thetalist, n)
    J = np.empty(th.shape[:-1] + (6, n))
    J[..., :, 0] = Slist[:, 0]
    if n > 1:
        P = _chain(_exps(Slist[:, :-1], th[..., :-1]))  # prefix products T_1..T_{n-1}
        A = _adjoint_many(P)  # (..., n-1, 6, 6)
        J[..., :, 1:] = np.swapaxes(np.einsum("...kij,jk->...ki", A, Slist[:, 1:]), -1, -2)
    return J


def jacobian_body(Blist, thetalist) -> np.ndarray:
    """Body Jacobian ``J_b(θ)`` (6×n, rows (ω; v)): twist of the end-effector in its own frame.

    Column i is ``Ad_{e^{−[Bₙ]θₙ}⋯e^{−[B_{i+1}]θ_{i+1}}} Bᵢ``. Blist : 6×n; thetalist : (n,) or (N, n).
    Returns 6×n (or (N, 6, n)).
    """
    Blist = _screws(Blist, "Blist")
    n = Blist.shape[1]
    th = _theta(thetalist, n)
    J = np.empty(th.shape[:-1] + (6, n))
    J[..., :, n - 1] = Blist[:, n - 1]
    if n > 1:
        # suffix products e^{-[B_n]θ_n} ⋯ e^{-[B_{i+1}]θ_{i+1}} for i = n-1 .. 1 (reversed order)
        E = _exps(Blist[:, :0:-1], -th[..., :0:-1])  # joints n, n-1, …, 2
        P = _chain(E)  # P_k = e^{-B_n θ_n} ⋯ e^{-B_{n-k} θ_{n-k}}
        A = _adjoint_many(P)
        cols = np.einsum("...kij,jk->...ki", A, Blist[:, n - 2::-1])  # for columns n-1, …, 1 (0-based n-2 … 0)
        J[..., :, n - 2::-1] = np.swapaxes(cols, -1, -2)
    return J


def _adjoint_many(T: np.ndarray) -> np.ndarray:
    """Adjoints (..., 6, 6) of poses (..., 4, 4)."""
    R, p = T[..., :3, :3], T[..., :3, 3]
    P = np.zeros(T.shape[:-2] + (3, 3))
    P[..., 0, 1], P[..., 0, 2], P[..., 1, 2] = -p[..., 2], p[..., 1], -p[..., 0]
    P[..., 1, 0], P[..., 2, 0], P[..., 2, 1] = p[..., 2], -p[..., 1], p[..., 0]
    A = np.zeros(T.shape[:-2] + (6, 6))
    A[..., :3, :3] = R
    A[..., 3:, 3:] = R
    A[..., 3:, :3] = P @ R
    return A
