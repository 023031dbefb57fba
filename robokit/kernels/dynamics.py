r"""Newton–Euler dynamics of a PoE chain as compiled loops (Lecture 7, Modern Robotics ch. 8).

Model in the Modern Robotics form: ``Mlist`` (n+1, 4, 4), ``Mlist[i]`` the pose of link frame
{i+1} (at the centre of mass) in frame {i}, ``Mlist[n]`` the end-effector frame in {n};
``Glist`` (n, 6, 6) the spatial inertia of each link in its frame, ``[[I, 0], [0, m 1]]``;
``Slist`` (6, n) the space screw axes. Twists ``(ω, v)`` and wrenches ``(m, f)`` angular first.
``Ftip`` is the wrench the end-effector applies to the environment, in the end-effector frame.

Constants of the model (computed at the start of every call, O(n)):
    ``M₀ᵢ = Mlist[0] ⋯ Mlist[i−1]``,  ``Aᵢ = Ad_{M₀ᵢ⁻¹} Sᵢ`` (joint i's screw in frame {i}).
Link transforms: ``T_{i,i−1} = e^{−[Aᵢ]θᵢ} Mlist[i−1]⁻¹``, ``T_{n+1,n} = Mlist[n]⁻¹``.

Inverse dynamics (recursive Newton–Euler), with ``V₀ = 0`` and ``V̇₀ = (0, −g)``:
    forward, i = 1..n:  ``Vᵢ = Ad_{T_{i,i−1}} V_{i−1} + Aᵢ θ̇ᵢ``
                        ``V̇ᵢ = Ad_{T_{i,i−1}} V̇_{i−1} + ad_{Vᵢ} Aᵢ θ̇ᵢ + Aᵢ θ̈ᵢ``
    backward, i = n..1, ``F_{n+1} = Ftip``:
                        ``Fᵢ = Ad_{T_{i+1,i}}ᵀ F_{i+1} + Gᵢ V̇ᵢ − ad_{Vᵢ}ᵀ Gᵢ Vᵢ``,   ``τᵢ = Fᵢᵀ Aᵢ``.

Mass matrix (composite rigid bodies): ``Kₙ = Gₙ``, ``K_{i−1} = G_{i−1} + Ad_{T_{i,i−1}}ᵀ Kᵢ Ad_{T_{i,i−1}}``;
    ``M_{ii} = Aᵢᵀ Kᵢ Aᵢ``; the composite force ``Kᵢ Aᵢ`` carried inward gives
    ``M_{ji} = A_jᵀ (Ad_{T_{j+1,j}}ᵀ ⋯ Ad_{T_{i,i−1}}ᵀ) Kᵢ Aᵢ`` for j < i. Computed in the base frame
    (the same matrix): with ``Pᵢ = T_{i,0}``, ``Kᵢ⁰ = Σ_{j≥i} Ad_{P_j}ᵀ G_j Ad_{P_j}`` and the screws
    ``Sᵢ⁰ = Ad_{Pᵢ⁻¹} Aᵢ``, ``M_{ji} = S_j⁰ᵀ Kᵢ⁰ Sᵢ⁰`` — one transform per link, six products per entry.

Forward dynamics: ``M(θ) θ̈ = τ − h(θ, θ̇)`` with ``h`` the inverse dynamics at θ̈ = 0, solved by
a Cholesky factorisation ``M = L Lᵀ`` (M is symmetric positive definite).

Per-configuration kernels check the lengths and finiteness of their vectors (``ValueError``);
the ``*_batch`` kernels run over a leading dimension N in parallel and check nothing (their
caller, e.g. :func:`robokit.inverse_dynamics`, does). Arguments are C-contiguous float64 arrays.

Example::

    >>> import robokit
    >>> from robokit.kernels.dynamics import mass_matrix
    >>> p = robokit.load("twolink").poe
    >>> M = mass_matrix(np.zeros(2), p.Mlist, p.Glist, p.Slist)   # 2×2, symmetric positive definite
"""
from __future__ import annotations

import math

import numpy as np

from robokit.kernels._jit import njit, prange
from robokit.kernels.lie import (
    ad_transpose_wrench, ad_twist, adjoint_matrix, adjoint_screw, adjoint_transpose_wrench, adjoint_twist,
    all_finite, copy44, exp_screw, inv_t, mat6_vec, mul_tt, mul_tt_inplace, set_identity,
)
from robokit.kernels.poe import SERIAL_BELOW, block_range, n_blocks

__all__ = [
    "inverse_dynamics", "mass_matrix", "forward_dynamics", "forward_dynamics_crba",
    "inverse_dynamics_batch", "mass_matrix_batch", "forward_dynamics_batch", "forward_dynamics_crba_batch",
    "forward_dynamics_trajectory",
]

_A1 = "float64[::1]"
_A2 = "float64[:, ::1]"
_A3 = "float64[:, :, ::1]"
_MODEL = f"{_A3}, {_A3}, {_A2}"  # Mlist, Glist, Slist


# ------------------------------------------------------------------ model constants and link transforms
@njit
def check_model(Mlist: np.ndarray, Glist: np.ndarray, Slist: np.ndarray) -> None:
    """Raise ``ValueError`` unless Mlist is (n+1, 4, 4) and Glist (n, 6, 6) for Slist (6, n)."""
    n = Slist.shape[1]
    if Slist.shape[0] != 6:
        raise ValueError("Slist: expected shape (6, n)")
    if Mlist.shape[0] != n + 1 or Mlist.shape[1] != 4 or Mlist.shape[2] != 4:
        raise ValueError("Mlist: expected shape (n+1, 4, 4) for the n columns of Slist")
    if Glist.shape[0] != n or Glist.shape[1] != 6 or Glist.shape[2] != 6:
        raise ValueError("Glist: expected shape (n, 6, 6) for the n columns of Slist")
    # the checks robokit.dynamics makes of a model (finite, homogeneous link frames to 1e-9,
    # symmetric inertias to 1e-9 of their size), so that a seed function can pass the user's
    # arrays straight here; a refusal sends it to those checks, which name the problem
    for i in range(6):
        for j in range(n):
            if not math.isfinite(Slist[i, j]):
                raise ValueError("Slist: contains NaN or infinite values")
    for k in range(n + 1):
        for i in range(4):
            for j in range(4):
                if not math.isfinite(Mlist[k, i, j]):
                    raise ValueError("Mlist: contains NaN or infinite values")
        if (abs(Mlist[k, 3, 0]) > 1e-9 or abs(Mlist[k, 3, 1]) > 1e-9 or abs(Mlist[k, 3, 2]) > 1e-9
                or abs(Mlist[k, 3, 3] - 1.0) > 1e-9):
            raise ValueError("Mlist: expected homogeneous transforms (last row [0, 0, 0, 1])")
    big, asym = 0.0, 0.0
    for k in range(n):
        for i in range(6):
            for j in range(6):
                v = Glist[k, i, j]
                if not math.isfinite(v):
                    raise ValueError("Glist: contains NaN or infinite values")
                big = max(big, abs(v))
                asym = max(asym, abs(v - Glist[k, j, i]))
    if asym > 1e-9 * max(1.0, big):
        raise ValueError("Glist: expected symmetric 6×6 spatial inertias")


@njit
def check_vector(x: np.ndarray, n: int, which: int) -> None:
    """Raise ``ValueError`` unless x has n finite entries (``which`` numbers the argument). Callers pass
    constants as ``np.int64(k)``: a literal ``k`` would make numba compile one copy per value."""
    if x.shape[0] != n or not all_finite(x):
        if which == 0:
            raise ValueError("thetalist: expected one finite value per joint")
        elif which == 1:
            raise ValueError("dthetalist: expected one finite value per joint")
        elif which == 2:
            raise ValueError("ddthetalist: expected one finite value per joint")
        elif which == 3:
            raise ValueError("g: expected 3 finite values")
        elif which == 4:
            raise ValueError("Ftip: expected 6 finite values")
        else:
            raise ValueError("taulist: expected one finite value per joint")


@njit
def link_screws(Mlist: np.ndarray, Slist: np.ndarray, A: np.ndarray, Minv: np.ndarray) -> None:
    """A (6, n) ← the joint screws in the link frames, ``Aᵢ = Ad_{M₀ᵢ⁻¹} Sᵢ``;
    Minv (n+1, 4, 4) ← ``Mlist[i]⁻¹``."""
    n = Slist.shape[1]
    M0i = np.empty((4, 4))
    M0i_inv = np.empty((4, 4))
    tmp = np.empty((4, 4))
    set_identity(M0i)
    for i in range(n):
        mul_tt_inplace(M0i, Mlist[i], tmp)  # M₀ᵢ = M₀,ᵢ₋₁ Mlist[i−1]  (0-based: through Mlist[i])
        inv_t(M0i, M0i_inv)
        adjoint_screw(M0i_inv, Slist, i, A, i)
    for i in range(n + 1):
        inv_t(Mlist[i], Minv[i])


@njit
def link_transforms(A: np.ndarray, Minv: np.ndarray, thetalist: np.ndarray, Tl: np.ndarray, E: np.ndarray) -> None:
    """Tl (n+1, 4, 4) ← the link-to-link poses at θ: ``Tl[i] = T_{i+1,i} = e^{−[A_{i+1}]θ_{i+1}} Mlist[i]⁻¹``
    (0-based i; it maps frame-{i} coordinates into frame {i+1}), and ``Tl[n] = Mlist[n]⁻¹``."""
    n = A.shape[1]
    for i in range(n):
        exp_screw(A, i, -thetalist[i], E)
        mul_tt(E, Minv[i], Tl[i])
    copy44(Minv[n], Tl[n])


@njit
def workspace(n: int) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Scratch arrays for one configuration of an n-joint chain: A (6, n) link-frame screws,
    Minv (n+1, 4, 4), Tl (n+1, 4, 4) link transforms, E (4, 4), V and Vd (n, 6) link twists and
    accelerations, v6 (six 6-vector temporaries), K (n, 6, 6) composite inertias, X (two 6×6)."""
    A = np.empty((6, n))
    Minv = np.empty((n + 1, 4, 4))
    Tl = np.empty((n + 1, 4, 4))
    E = np.empty((4, 4))
    V = np.empty((n, 6))
    Vd = np.empty((n, 6))
    v6 = np.empty((6, 6))  # rows: six 6-vector temporaries
    K = np.empty((n, 6, 6))
    X = np.empty((2, 6, 6))
    return A, Minv, Tl, E, V, Vd, v6, K, X


@njit
def at_configuration(Mlist: np.ndarray, Slist: np.ndarray, thetalist: np.ndarray, A: np.ndarray, Minv: np.ndarray, Tl: np.ndarray, E: np.ndarray) -> None:
    """The model constants (``Aᵢ``, ``Mlist[i]⁻¹``) and the link transforms at θ into a
    :func:`workspace`: the start of every one-configuration kernel."""
    link_screws(Mlist, Slist, A, Minv)
    link_transforms(A, Minv, thetalist, Tl, E)


@njit
def check_state(thetalist: np.ndarray, dthetalist: np.ndarray, x: np.ndarray, x_which: int, g: np.ndarray, Ftip: np.ndarray, Mlist: np.ndarray, Glist: np.ndarray, Slist: np.ndarray) -> None:
    """Check the model and the state (θ, θ̇, x, g, Ftip) of a dynamics kernel, in that order — x is
    θ̈ (``x_which`` 2) or τ (5), as :func:`check_vector` numbers them."""
    check_model(Mlist, Glist, Slist)
    n = Slist.shape[1]
    check_vector(thetalist, n, np.int64(0))
    check_vector(dthetalist, n, np.int64(1))
    check_vector(x, n, x_which)
    check_vector(g, np.int64(3), np.int64(3))
    check_vector(Ftip, np.int64(6), np.int64(4))


# ------------------------------------------------------------------ recursive Newton–Euler
@njit
def rnea_into(A: np.ndarray, Tl: np.ndarray, Glist: np.ndarray, dthetalist: np.ndarray, ddthetalist: np.ndarray, g: np.ndarray, Ftip: np.ndarray, V: np.ndarray, Vd: np.ndarray, v6: np.ndarray, tau: np.ndarray) -> None:
    """τ ← inverse dynamics with the link transforms Tl already at θ (see the module docstring)."""
    n = A.shape[1]
    Ai, Vprev, Vdprev, F, t1, t2 = v6[0], v6[1], v6[2], v6[3], v6[4], v6[5]
    for r in range(6):
        Vprev[r] = 0.0
        Vdprev[r] = 0.0
    Vdprev[3], Vdprev[4], Vdprev[5] = -g[0], -g[1], -g[2]  # gravity as an upward base acceleration
    # forward iterations: twists and accelerations of the links, each in its own frame
    for i in range(n):
        for r in range(6):
            Ai[r] = A[r, i]
        adjoint_twist(Tl[i], Vprev, t1)  # Ad_{T_{i,i−1}} V_{i−1}
        for r in range(6):
            V[i, r] = t1[r] + Ai[r] * dthetalist[i]
        adjoint_twist(Tl[i], Vdprev, t1)  # Ad_{T_{i,i−1}} V̇_{i−1}
        ad_twist(V[i], Ai, t2)  # ad_{Vᵢ} Aᵢ
        for r in range(6):
            Vd[i, r] = t1[r] + t2[r] * dthetalist[i] + Ai[r] * ddthetalist[i]
        Vprev, Vdprev = V[i], Vd[i]
    # backward iterations: wrenches transmitted through the joints
    for r in range(6):
        F[r] = Ftip[r]
    for i in range(n - 1, -1, -1):
        adjoint_transpose_wrench(Tl[i + 1], F, t1)  # Ad_{T_{i+1,i}}ᵀ F_{i+1}
        mat6_vec(Glist[i], Vd[i], t2)  # Gᵢ V̇ᵢ
        for r in range(6):
            F[r] = t1[r] + t2[r]
        mat6_vec(Glist[i], V[i], t1)  # Gᵢ Vᵢ
        ad_transpose_wrench(V[i], t1, t2)  # ad_{Vᵢ}ᵀ Gᵢ Vᵢ
        acc = 0.0
        for r in range(6):
            F[r] -= t2[r]
            acc += F[r] * A[r, i]
        tau[i] = acc  # τᵢ = Fᵢᵀ Aᵢ


# ------------------------------------------------------------------ composite-rigid-body mass matrix
@njit
def crba_into(A: np.ndarray, Tl: np.ndarray, Glist: np.ndarray, K: np.ndarray, X: np.ndarray, v6: np.ndarray, Mout: np.ndarray) -> None:
    """Mout (n, n) ← M(θ) with the link transforms Tl already at θ, composite rigid bodies in the
    base frame (see the module docstring): ``Pᵢ = T_{i,0}``, ``Gᵢ⁰ = Ad_{Pᵢ}ᵀ Gᵢ Ad_{Pᵢ}``,
    ``Sᵢ⁰ = Ad_{Pᵢ⁻¹} Aᵢ``, ``Kᵢ⁰ = Σ_{j ≥ i} G_j⁰`` (sums: no transform per step), and
    ``M_{ji} = S_j⁰ · (Kᵢ⁰ Sᵢ⁰)`` for j ≤ i, six products per entry — the same matrix as carrying
    the composite forces inward link by link, with O(n) transforms instead of O(n²)."""
    n = A.shape[1]
    Ad, KAd = X[0], X[1]
    F = v6[0]
    T4 = np.empty((3, 4, 4))
    P, Pinv, tmp = T4[0], T4[1], T4[2]
    Sw = np.empty((6, n))
    set_identity(P)
    for i in range(n):
        mul_tt(Tl[i], P, tmp)  # T_{i+1,0} = T_{i+1,i} T_{i,0}
        copy44(tmp, P)
        inv_t(P, Pinv)
        adjoint_screw(Pinv, A, i, Sw, i)  # joint i's screw in base coordinates
        adjoint_matrix(P, Ad)
        # KAd = Gᵢ Ad (Ad's upper-right block is zero), then Adᵀ KAd (symmetric: one triangle)
        for r in range(6):
            for c in range(6):
                acc = 0.0
                for k in range(3 if c >= 3 else 0, 6):
                    acc += Glist[i, r, k] * Ad[k, c]
                KAd[r, c] = acc
        for r in range(6):
            for c in range(r, 6):
                acc = 0.0
                for k in range(3 if r >= 3 else 0, 6):
                    acc += Ad[k, r] * KAd[k, c]
                K[i, r, c] = acc
                K[i, c, r] = acc
    # composite inertias: suffix sums, inward
    for i in range(n - 2, -1, -1):
        for r in range(6):
            for c in range(6):
                K[i, r, c] += K[i + 1, r, c]
    for i in range(n):
        for r in range(6):
            acc = 0.0
            for c in range(6):
                acc += K[i, r, c] * Sw[c, i]
            F[r] = acc
        for j in range(i + 1):
            acc = 0.0
            for r in range(6):
                acc += Sw[r, j] * F[r]
            Mout[j, i] = acc
            Mout[i, j] = acc


# ------------------------------------------------------------------ Cholesky solve
@njit
def cholesky_solve(Mm: np.ndarray, b: np.ndarray, L: np.ndarray, x: np.ndarray) -> bool:
    """x ← M⁻¹ b by ``M = L Lᵀ`` (L overwritten; M untouched). Returns False when M is not
    positive definite (then x is left NaN)."""
    n = Mm.shape[0]
    for j in range(n):
        s = Mm[j, j]
        for k in range(j):
            s -= L[j, k] * L[j, k]
        if not s > 0.0:
            for r in range(n):
                x[r] = np.nan
            return False
        d = math.sqrt(s)
        L[j, j] = d
        for i in range(j + 1, n):
            s = Mm[i, j]
            for k in range(j):
                s -= L[i, k] * L[j, k]
            L[i, j] = s / d
    for i in range(n):  # L y = b
        s = b[i]
        for k in range(i):
            s -= L[i, k] * x[k]
        x[i] = s / L[i, i]
    for i in range(n - 1, -1, -1):  # Lᵀ x = y
        s = x[i]
        for k in range(i + 1, n):
            s -= L[k, i] * x[k]
        x[i] = s / L[i, i]
    return True


@njit
def forward_dynamics_into(A: np.ndarray, Tl: np.ndarray, Glist: np.ndarray, dthetalist: np.ndarray, taulist: np.ndarray, g: np.ndarray, Ftip: np.ndarray, zeros: np.ndarray, V: np.ndarray, Vd: np.ndarray, v6: np.ndarray, K: np.ndarray, X: np.ndarray, Mm: np.ndarray, L: np.ndarray, h: np.ndarray, ddq: np.ndarray) -> bool:
    """θ̈ ← M(θ)⁻¹ (τ − h(θ, θ̇)) with the link transforms Tl at θ; returns False if M is not SPD."""
    n = A.shape[1]
    rnea_into(A, Tl, Glist, dthetalist, zeros, g, Ftip, V, Vd, v6, h)  # h = c + g + Jᵀ Ftip
    crba_into(A, Tl, Glist, K, X, v6, Mm)
    for i in range(n):
        h[i] = taulist[i] - h[i]
    return cholesky_solve(Mm, h, L, ddq)


# ------------------------------------------------------------------ articulated-body forward dynamics
@njit
def congruence_add(Ad: np.ndarray, Ia: np.ndarray, tmp: np.ndarray, out: np.ndarray) -> None:
    """out ← out + Adᵀ Ia Ad for 6×6 matrices (an inertia carried into the parent frame). Ad is an
    adjoint map ``[[R, 0], [[p] R, R]]``: the products skip its zero upper-right block (terms that
    add an exact zero: the same sums, a quarter fewer operations)."""
    for r in range(6):
        for c in range(6):
            acc = 0.0
            for k in range(3 if c >= 3 else 0, 6):
                acc += Ia[r, k] * Ad[k, c]
            tmp[r, c] = acc
    for r in range(6):
        for c in range(6):
            acc = 0.0
            for k in range(3 if r >= 3 else 0, 6):
                acc += Ad[k, r] * tmp[k, c]
            out[r, c] += acc


@njit
def aba_workspace(n: int) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Scratch for the articulated-body recursion: Ia (n, 6, 6) articulated inertias, P (n, 6) bias
    forces, C (n, 6) velocity-product accelerations, U (n, 6) ``Iᵃᵢ Aᵢ``, du (n, 2) ``(Dᵢ, uᵢ)``,
    X (3, 6, 6) scratch."""
    return (np.empty((n, 6, 6)), np.empty((n, 6)), np.empty((n, 6)), np.empty((n, 6)), np.empty((n, 2)),
            np.empty((3, 6, 6)))


@njit
def aba_into(A: np.ndarray, Tl: np.ndarray, Glist: np.ndarray, dthetalist: np.ndarray, taulist: np.ndarray,
             g: np.ndarray, Ftip: np.ndarray, armature: np.ndarray, V: np.ndarray, v6: np.ndarray, Ia: np.ndarray,
             P: np.ndarray, C: np.ndarray, U: np.ndarray, du: np.ndarray, X: np.ndarray, ddq: np.ndarray) -> bool:
    """θ̈ ← forward dynamics by Featherstone's articulated-body algorithm, with the link transforms Tl
    already at θ (three passes, see the module docstring); ``armature`` (n,) is added to each joint's
    ``Dᵢ`` (reflected motor inertia, 0 for none). Returns False when some ``Dᵢ ≤ 0`` (then θ̈ is NaN)."""
    n = A.shape[1]
    Ai, Vprev, t1, t2, pa = v6[0], v6[1], v6[2], v6[3], v6[4]
    Ad, tmp, Iaa = X[0], X[1], X[2]
    for r in range(6):
        Vprev[r] = 0.0
    # pass 1, outward: link twists Vᵢ, velocity-product accelerations cᵢ = ad_{Vᵢ} Aᵢ θ̇ᵢ,
    # bias forces pᵢ = −ad_{Vᵢ}ᵀ Gᵢ Vᵢ, and Iᵃᵢ = Gᵢ to start with
    for i in range(n):
        for r in range(6):
            Ai[r] = A[r, i]
        adjoint_twist(Tl[i], Vprev, t1)
        for r in range(6):
            V[i, r] = t1[r] + Ai[r] * dthetalist[i]
        ad_twist(V[i], Ai, t2)
        for r in range(6):
            C[i, r] = t2[r] * dthetalist[i]
        mat6_vec(Glist[i], V[i], t1)
        ad_transpose_wrench(V[i], t1, t2)
        for r in range(6):
            P[i, r] = -t2[r]
            for c in range(6):
                Ia[i, r, c] = Glist[i, r, c]
        Vprev = V[i]
    # the tip wrench the end-effector exerts on the environment loads the last link
    adjoint_transpose_wrench(Tl[n], Ftip, t1)
    for r in range(6):
        P[n - 1, r] += t1[r]
    # pass 2, inward: Uᵢ = Iᵃᵢ Aᵢ, Dᵢ = Aᵢᵀ Uᵢ, uᵢ = τᵢ − Aᵢᵀ pᵢ; the parent receives
    # Ad_{T_{i,i−1}}ᵀ (Iᵃᵢ − Uᵢ Uᵢᵀ / Dᵢ) Ad_{T_{i,i−1}} and Ad_{T_{i,i−1}}ᵀ (pᵢ + Iᵃ cᵢ + Uᵢ uᵢ / Dᵢ)
    for i in range(n - 1, -1, -1):
        D = armature[i]
        u = taulist[i]
        for r in range(6):
            acc = 0.0
            for c in range(6):
                acc += Ia[i, r, c] * A[c, i]
            U[i, r] = acc
            D += A[r, i] * acc
            u -= A[r, i] * P[i, r]
        if not D > 0.0:
            for r in range(n):
                ddq[r] = np.nan
            return False
        du[i, 0] = D
        du[i, 1] = u
        if i == 0:
            break
        for r in range(6):
            for c in range(6):
                Iaa[r, c] = Ia[i, r, c] - U[i, r] * U[i, c] / D
        for r in range(6):
            acc = P[i, r] + U[i, r] * u / D
            for c in range(6):
                acc += Iaa[r, c] * C[i, c]
            pa[r] = acc
        adjoint_matrix(Tl[i], Ad)
        congruence_add(Ad, Iaa, tmp, Ia[i - 1])
        adjoint_transpose_wrench(Tl[i], pa, t1)
        for r in range(6):
            P[i - 1, r] += t1[r]
    # pass 3, outward: a'ᵢ = Ad_{T_{i,i−1}} a_{i−1} + cᵢ, θ̈ᵢ = (uᵢ − Uᵢᵀ a'ᵢ) / Dᵢ, aᵢ = a'ᵢ + Aᵢ θ̈ᵢ,
    # from the base's a₀ = (0, −g) (gravity as an upward acceleration of the base)
    acc6 = v6[5]
    for r in range(6):
        acc6[r] = 0.0
    acc6[3], acc6[4], acc6[5] = -g[0], -g[1], -g[2]
    for i in range(n):
        adjoint_twist(Tl[i], acc6, t1)
        s = du[i, 1]
        for r in range(6):
            t1[r] += C[i, r]
            s -= U[i, r] * t1[r]
        qdd = s / du[i, 0]
        ddq[i] = qdd
        for r in range(6):
            acc6[r] = t1[r] + A[r, i] * qdd
    return True


# ------------------------------------------------------------------ one configuration
@njit(f"{_A1}({_A1}, {_A1}, {_A1}, {_A1}, {_A1}, {_MODEL})")
def inverse_dynamics(thetalist: np.ndarray, dthetalist: np.ndarray, ddthetalist: np.ndarray, g: np.ndarray, Ftip: np.ndarray, Mlist: np.ndarray, Glist: np.ndarray, Slist: np.ndarray) -> np.ndarray:
    """Joint torques τ (n,) = M θ̈ + c + g(θ) + Jᵀ Ftip by recursive Newton–Euler."""
    check_state(thetalist, dthetalist, ddthetalist, np.int64(2), g, Ftip, Mlist, Glist, Slist)
    n = Slist.shape[1]
    A, Minv, Tl, E, V, Vd, v6, K, X = workspace(n)
    at_configuration(Mlist, Slist, thetalist, A, Minv, Tl, E)
    tau = np.empty(n)
    rnea_into(A, Tl, Glist, dthetalist, ddthetalist, g, Ftip, V, Vd, v6, tau)
    return tau


@njit(f"{_A2}({_A1}, {_MODEL})")
def mass_matrix(thetalist: np.ndarray, Mlist: np.ndarray, Glist: np.ndarray, Slist: np.ndarray) -> np.ndarray:
    """Mass matrix M(θ) (n, n), symmetric positive definite, by the composite-rigid-body algorithm."""
    check_model(Mlist, Glist, Slist)
    n = Slist.shape[1]
    check_vector(thetalist, n, np.int64(0))
    A, Minv, Tl, E, V, Vd, v6, K, X = workspace(n)
    at_configuration(Mlist, Slist, thetalist, A, Minv, Tl, E)
    Mm = np.empty((n, n))
    crba_into(A, Tl, Glist, K, X, v6, Mm)
    return Mm


@njit(f"{_A1}({_A1}, {_A1}, {_A1}, {_A1}, {_A1}, {_MODEL})")
def forward_dynamics(thetalist: np.ndarray, dthetalist: np.ndarray, taulist: np.ndarray, g: np.ndarray, Ftip: np.ndarray, Mlist: np.ndarray, Glist: np.ndarray, Slist: np.ndarray) -> np.ndarray:
    """Joint accelerations θ̈ (n,) = M(θ)⁻¹ (τ − c − g(θ) − Jᵀ Ftip) by the articulated-body algorithm, O(n)."""
    check_state(thetalist, dthetalist, taulist, np.int64(5), g, Ftip, Mlist, Glist, Slist)
    n = Slist.shape[1]
    A, Minv, Tl, E, V, Vd, v6, K, X = workspace(n)
    at_configuration(Mlist, Slist, thetalist, A, Minv, Tl, E)
    Ia, P, C, U, du, X3 = aba_workspace(n)
    ddq = np.empty(n)
    if not aba_into(A, Tl, Glist, dthetalist, taulist, g, Ftip, np.zeros(n), V, v6, Ia, P, C, U, du, X3, ddq):
        raise ValueError("Glist: the mass matrix is not positive definite at this configuration "
                         "(a joint drives no inertia)")
    return ddq


@njit(f"{_A1}({_A1}, {_A1}, {_A1}, {_A1}, {_A1}, {_MODEL})")
def forward_dynamics_crba(thetalist: np.ndarray, dthetalist: np.ndarray, taulist: np.ndarray, g: np.ndarray, Ftip: np.ndarray, Mlist: np.ndarray, Glist: np.ndarray, Slist: np.ndarray) -> np.ndarray:
    """Joint accelerations θ̈ (n,) = M(θ)⁻¹ (τ − c − g(θ) − Jᵀ Ftip): the lecture's form, CRBA + Cholesky, O(n²)."""
    check_state(thetalist, dthetalist, taulist, np.int64(5), g, Ftip, Mlist, Glist, Slist)
    n = Slist.shape[1]
    A, Minv, Tl, E, V, Vd, v6, K, X = workspace(n)
    at_configuration(Mlist, Slist, thetalist, A, Minv, Tl, E)
    Mm = np.empty((n, n))
    L = np.zeros((n, n))
    h = np.empty(n)
    ddq = np.empty(n)
    if not forward_dynamics_into(A, Tl, Glist, dthetalist, taulist, g, Ftip, np.zeros(n), V, Vd, v6, K, X, Mm, L,
                                 h, ddq):
        raise ValueError("Glist: the mass matrix is not positive definite at this configuration "
                         "(a joint drives no inertia)")
    return ddq


# ------------------------------------------------------------------ N configurations, in parallel
# Each parallel kernel hands out blocks of rows with ``prange``; one block is a plain serial loop
# (the ``*_rows`` functions) that allocates its scratch space once.
@njit
def inverse_dynamics_rows(lo: int, hi: int, thetas: np.ndarray, dthetas: np.ndarray, ddthetas: np.ndarray, g: np.ndarray, Ftips: np.ndarray, Mlist: np.ndarray, Glist: np.ndarray, Slist: np.ndarray, out: np.ndarray) -> None:
    """out[k] ← τ for rows lo ≤ k < hi."""
    A, Minv, Tl, E, V, Vd, v6, K, X = workspace(Slist.shape[1])
    link_screws(Mlist, Slist, A, Minv)
    for k in range(lo, hi):
        link_transforms(A, Minv, thetas[k], Tl, E)
        rnea_into(A, Tl, Glist, dthetas[k], ddthetas[k], g, Ftips[k if Ftips.shape[0] > 1 else 0], V, Vd, v6, out[k])


@njit
def mass_matrix_rows(lo: int, hi: int, thetas: np.ndarray, Mlist: np.ndarray, Glist: np.ndarray, Slist: np.ndarray, out: np.ndarray) -> None:
    """out[k] ← M(θ_k) for rows lo ≤ k < hi."""
    A, Minv, Tl, E, V, Vd, v6, K, X = workspace(Slist.shape[1])
    link_screws(Mlist, Slist, A, Minv)
    for k in range(lo, hi):
        link_transforms(A, Minv, thetas[k], Tl, E)
        crba_into(A, Tl, Glist, K, X, v6, out[k])


@njit
def forward_dynamics_rows(lo: int, hi: int, thetas: np.ndarray, dthetas: np.ndarray, taus: np.ndarray, g: np.ndarray, Ftips: np.ndarray, Mlist: np.ndarray, Glist: np.ndarray, Slist: np.ndarray, out: np.ndarray) -> None:
    """out[k] ← θ̈ by the articulated-body algorithm for rows lo ≤ k < hi (NaN where some Dᵢ ≤ 0)."""
    n = Slist.shape[1]
    A, Minv, Tl, E, V, Vd, v6, K, X = workspace(n)
    link_screws(Mlist, Slist, A, Minv)
    Ia, P, C, U, du, X3 = aba_workspace(n)
    zeros = np.zeros(n)
    for k in range(lo, hi):
        link_transforms(A, Minv, thetas[k], Tl, E)
        aba_into(A, Tl, Glist, dthetas[k], taus[k], g, Ftips[k if Ftips.shape[0] > 1 else 0], zeros, V, v6,
                 Ia, P, C, U, du, X3, out[k])


@njit
def forward_dynamics_crba_rows(lo: int, hi: int, thetas: np.ndarray, dthetas: np.ndarray, taus: np.ndarray, g: np.ndarray, Ftips: np.ndarray, Mlist: np.ndarray, Glist: np.ndarray, Slist: np.ndarray, out: np.ndarray) -> None:
    """out[k] ← θ̈ for rows lo ≤ k < hi (NaN where M is not positive definite)."""
    n = Slist.shape[1]
    A, Minv, Tl, E, V, Vd, v6, K, X = workspace(n)
    link_screws(Mlist, Slist, A, Minv)
    Mm = np.empty((n, n))
    L = np.zeros((n, n))
    h = np.empty(n)
    zeros = np.zeros(n)
    for k in range(lo, hi):
        link_transforms(A, Minv, thetas[k], Tl, E)
        forward_dynamics_into(A, Tl, Glist, dthetas[k], taus[k], g, Ftips[k if Ftips.shape[0] > 1 else 0], zeros,
                              V, Vd, v6, K, X, Mm, L, h, out[k])


@njit(f"{_A2}({_A2}, {_A2}, {_A2}, {_A1}, {_A2}, {_MODEL})", parallel=True)
def inverse_dynamics_batch(thetas: np.ndarray, dthetas: np.ndarray, ddthetas: np.ndarray, g: np.ndarray, Ftips: np.ndarray, Mlist: np.ndarray, Glist: np.ndarray, Slist: np.ndarray) -> np.ndarray:
    """Torques (N, n) for the rows of thetas, dthetas, ddthetas (N, n); Ftips (N, 6), or (1, 6)
    for one wrench shared by all rows."""
    N, n = thetas.shape
    out = np.empty((N, n))
    if N < SERIAL_BELOW:  # too few rows to pay for waking the threads
        inverse_dynamics_rows(np.int64(0), N, thetas, dthetas, ddthetas, g, Ftips, Mlist, Glist, Slist, out)
        return out
    nb = n_blocks(N)
    for b in prange(nb):
        lo, hi = block_range(b, nb, N)
        inverse_dynamics_rows(lo, hi, thetas, dthetas, ddthetas, g, Ftips, Mlist, Glist, Slist, out)
    return out


@njit(f"{_A3}({_A2}, {_MODEL})", parallel=True)
def mass_matrix_batch(thetas: np.ndarray, Mlist: np.ndarray, Glist: np.ndarray, Slist: np.ndarray) -> np.ndarray:
    """Mass matrices (N, n, n) for the rows of thetas (N, n)."""
    N, n = thetas.shape
    out = np.empty((N, n, n))
    if N < SERIAL_BELOW:  # too few rows to pay for waking the threads
        mass_matrix_rows(np.int64(0), N, thetas, Mlist, Glist, Slist, out)
        return out
    nb = n_blocks(N)
    for b in prange(nb):
        lo, hi = block_range(b, nb, N)
        mass_matrix_rows(lo, hi, thetas, Mlist, Glist, Slist, out)
    return out


@njit(f"{_A2}({_A2}, {_A2}, {_A2}, {_A1}, {_A2}, {_MODEL})", parallel=True)
def forward_dynamics_batch(thetas: np.ndarray, dthetas: np.ndarray, taus: np.ndarray, g: np.ndarray, Ftips: np.ndarray, Mlist: np.ndarray, Glist: np.ndarray, Slist: np.ndarray) -> np.ndarray:
    """Accelerations (N, n) for the rows of thetas, dthetas, taus (N, n); Ftips (N, 6) or (1, 6).
    Articulated-body algorithm per row; a row whose mass matrix is not positive definite comes back NaN."""
    N, n = thetas.shape
    out = np.empty((N, n))
    if N < SERIAL_BELOW:  # too few rows to pay for waking the threads
        forward_dynamics_rows(np.int64(0), N, thetas, dthetas, taus, g, Ftips, Mlist, Glist, Slist, out)
        return out
    nb = n_blocks(N)
    for b in prange(nb):
        lo, hi = block_range(b, nb, N)
        forward_dynamics_rows(lo, hi, thetas, dthetas, taus, g, Ftips, Mlist, Glist, Slist, out)
    return out


@njit(f"{_A2}({_A2}, {_A2}, {_A2}, {_A1}, {_A2}, {_MODEL})", parallel=True)
def forward_dynamics_crba_batch(thetas: np.ndarray, dthetas: np.ndarray, taus: np.ndarray, g: np.ndarray, Ftips: np.ndarray, Mlist: np.ndarray, Glist: np.ndarray, Slist: np.ndarray) -> np.ndarray:
    """Accelerations (N, n) for the rows of thetas, dthetas, taus (N, n); Ftips (N, 6) or (1, 6).
    CRBA + Cholesky per row. A row whose mass matrix is not positive definite comes back NaN."""
    N, n = thetas.shape
    out = np.empty((N, n))
    if N < SERIAL_BELOW:  # too few rows to pay for waking the threads
        forward_dynamics_crba_rows(np.int64(0), N, thetas, dthetas, taus, g, Ftips, Mlist, Glist, Slist, out)
        return out
    nb = n_blocks(N)
    for b in prange(nb):
        lo, hi = block_range(b, nb, N)
        forward_dynamics_crba_rows(lo, hi, thetas, dthetas, taus, g, Ftips, Mlist, Glist, Slist, out)
    return out


@njit(f"{_A3}({_A1}, {_A1}, {_A2}, {_A1}, {_A2}, {_MODEL}, float64, int64)", interpret_while_compiling=False)
def forward_dynamics_trajectory(thetalist: np.ndarray, dthetalist: np.ndarray, taumat: np.ndarray, g: np.ndarray, Ftipmat: np.ndarray, Mlist: np.ndarray, Glist: np.ndarray, Slist: np.ndarray, dt: float, intRes: int) -> np.ndarray:
    """Euler integration of the forward dynamics under a torque history (Modern Robotics semantics):
    row 0 is the initial state, row k+1 the state after holding ``taumat[k]`` and ``Ftipmat[k]``
    for dt seconds in ``intRes`` steps. Returns one (2, N, n) array: thetamat and dthetamat."""
    N, n = taumat.shape
    out = np.empty((2, N, n))
    A, Minv, Tl, E, V, Vd, v6, K, X = workspace(n)
    link_screws(Mlist, Slist, A, Minv)
    Ia, P, C, U, du, X3 = aba_workspace(n)
    ddq = np.empty(n)
    zeros = np.zeros(n)
    th = np.empty(n)
    dth = np.empty(n)
    for i in range(n):
        th[i] = thetalist[i]
        dth[i] = dthetalist[i]
        out[0, 0, i] = th[i]
        out[1, 0, i] = dth[i]
    step = dt / intRes
    for k in range(N - 1):
        for _ in range(intRes):
            link_transforms(A, Minv, th, Tl, E)
            if not aba_into(A, Tl, Glist, dth, taumat[k], g, Ftipmat[k], zeros, V, v6, Ia, P, C, U, du, X3, ddq):
                raise ValueError("Glist: the mass matrix is not positive definite along the trajectory")
            for i in range(n):
                th[i] += step * dth[i]  # θ ← θ + h θ̇ (with the old θ̇) …
                dth[i] += step * ddq[i]  # … then θ̇ ← θ̇ + h θ̈
        for i in range(n):
            out[0, k + 1, i] = th[i]
            out[1, k + 1, i] = dth[i]
    return out
