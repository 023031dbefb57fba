r"""The identification's Newton–Euler regressor ``τ = Y(q, q̇, q̈) π`` as a compiled kernel (issue 42, item 5).

The same recursion as :func:`robokit.calibration.inertial_regressor` (see
:mod:`robokit.calibration.regressor` for the derivation), in the joint frames of a
:class:`robokit.calibration.JointChain` — placements ``X₁ … X_{n+1}`` (4×4) and unit joint
screws ``Aᵢ`` (6,) in their own frames — with the standard parameters of each link in joint i's
frame about its origin, Pinocchio's order ``(m, m c, I_xx, I_xy, I_yy, I_xz, I_yz, I_zz)``:

* forward, ``V₀ = 0``, ``V̇₀ = (0, −g)``, ``T_{i,i−1} = (Xᵢ e^{[Aᵢ]qᵢ})⁻¹``:
  ``Vᵢ = Ad_{T_{i,i−1}} V_{i−1} + Aᵢ q̇ᵢ``, ``V̇ᵢ = Ad_{T_{i,i−1}} V̇_{i−1} + ad_{Vᵢ} Aᵢ q̇ᵢ + Aᵢ q̈ᵢ``;
* link i's own wrench ``Kᵢ πᵢ`` with ``Kᵢ = Φ(V̇ᵢ) − ad_{Vᵢ}ᵀ Φ(Vᵢ)`` (6×10; ``G V = Φ(V) π``);
* backward: ``Y_{ji} = Aⱼᵀ Ad_{T_{j+1,j}}ᵀ ⋯ Ad_{T_{i,i−1}}ᵀ Kᵢ`` for i ≥ j, zero for i < j — each
  of the ten columns of ``Kᵢ`` a wrench carried inward joint by joint.

The ten columns are kept as the rows of a (10, 6) array so that every wrench is contiguous;
nothing is allocated inside the loops.
"""
from __future__ import annotations

import numpy as np

from robokit.kernels._jit import njit
from robokit.kernels.lie import ad_transpose_wrench, ad_twist, adjoint_transpose_wrench, adjoint_twist, dot6, exp_screw, inv_t, mul_tt

__all__ = ["inertial_regressor"]

_SIG = ("float64[:, :, ::1](float64[:, :, ::1], float64[:, ::1], float64[:, ::1], float64[:, ::1], float64[:, ::1], "
        "float64[::1])")


@njit
def phi_rows(V: np.ndarray, P: np.ndarray) -> None:
    """P (10, 6) ← Φ(V)ᵀ: row k is the wrench ``G V`` gets from parameter k (``G V = Φ(V) π``)."""
    wx, wy, wz, vx, vy, vz = V[0], V[1], V[2], V[3], V[4], V[5]
    for k in range(10):
        for r in range(6):
            P[k, r] = 0.0
    # m: (0, v)
    P[0, 3], P[0, 4], P[0, 5] = vx, vy, vz
    # m c: angular −[v] (m c) ... as columns: (−[v] e_c ; [ω] e_c)
    # column c of −[v]: −v × e_c;  column c of [ω]: ω × e_c
    P[1, 0], P[1, 1], P[1, 2] = 0.0, -vz, vy  # −(v × e_x) = (0, −v_z, v_y)
    P[2, 0], P[2, 1], P[2, 2] = vz, 0.0, -vx  # −(v × e_y)
    P[3, 0], P[3, 1], P[3, 2] = -vy, vx, 0.0  # −(v × e_z)
    P[1, 3], P[1, 4], P[1, 5] = 0.0, wz, -wy  # ω × e_x
    P[2, 3], P[2, 4], P[2, 5] = -wz, 0.0, wx  # ω × e_y
    P[3, 3], P[3, 4], P[3, 5] = wy, -wx, 0.0  # ω × e_z
    # I ω = L(ω) (I_xx, I_xy, I_yy, I_xz, I_yz, I_zz)
    P[4, 0] = wx              # I_xx
    P[5, 0], P[5, 1] = wy, wx  # I_xy
    P[6, 1] = wy              # I_yy
    P[7, 0], P[7, 2] = wz, wx  # I_xz
    P[8, 1], P[8, 2] = wz, wy  # I_yz
    P[9, 2] = wz              # I_zz


@njit
def regressor_into(X: np.ndarray, A: np.ndarray, q: np.ndarray, dq: np.ndarray, ddq: np.ndarray, gravity: np.ndarray,
                   Y: np.ndarray, S: np.ndarray, Ti: np.ndarray, K: np.ndarray, E: np.ndarray, T: np.ndarray,
                   V: np.ndarray, dV: np.ndarray, t6: np.ndarray, u6: np.ndarray, P: np.ndarray,
                   U: np.ndarray) -> None:
    """Y (n, 10n) ← the regressor of one sample (q, q̇, q̈ (n,)); the rest are scratch:
    S (6, n) the screws as columns, Ti (n, 4, 4), K (n, 10, 6), E/T (4, 4), V/dV/t6/u6 (6,), P/U (10, 6)."""
    n = A.shape[0]
    for r in range(6):
        V[r] = 0.0
        dV[r] = 0.0
    dV[3], dV[4], dV[5] = -gravity[0], -gravity[1], -gravity[2]
    for i in range(n):
        exp_screw(S, i, q[i], E)
        mul_tt(X[i], E, T)  # T_{i−1,i}
        inv_t(T, Ti[i])  # T_{i,i−1}
        adjoint_twist(Ti[i], V, t6)
        for r in range(6):
            V[r] = t6[r] + A[i, r] * dq[i]
        adjoint_twist(Ti[i], dV, t6)
        ad_twist(V, A[i], u6)
        for r in range(6):
            dV[r] = t6[r] + u6[r] * dq[i] + A[i, r] * ddq[i]
        phi_rows(dV, K[i])
        phi_rows(V, P)
        for k in range(10):
            ad_transpose_wrench(V, P[k], t6)
            for r in range(6):
                K[i, k, r] -= t6[r]
    for j in range(n):
        for c in range(10 * n):
            Y[j, c] = 0.0
    for i in range(n):
        for k in range(10):
            for r in range(6):
                U[k, r] = K[i, k, r]
        for j in range(i, -1, -1):
            for k in range(10):
                Y[j, 10 * i + k] = dot6(A[j], U[k])
            if j > 0:
                for k in range(10):
                    adjoint_transpose_wrench(Ti[j], U[k], t6)  # Ad_{T_{j,j−1}}ᵀ: the wrench in frame j−1
                    for r in range(6):
                        U[k, r] = t6[r]


@njit(_SIG)
def inertial_regressor(X: np.ndarray, A: np.ndarray, q: np.ndarray, dq: np.ndarray, ddq: np.ndarray,
                       gravity: np.ndarray) -> np.ndarray:
    """The regressor Y (N, n, 10n) of N samples (rows of q, q̇, q̈ (N, n)) for the chain with
    placements X (n+1, 4, 4) and joint screws A (n, 6) (rows, in their own frames); gravity (3,)."""
    N, n = q.shape
    Y = np.empty((N, n, 10 * n))
    S = np.ascontiguousarray(A.T)
    Ti = np.empty((n, 4, 4))
    K = np.empty((n, 10, 6))
    E = np.empty((4, 4))
    T = np.empty((4, 4))
    V = np.empty(6)
    dV = np.empty(6)
    t6 = np.empty(6)
    u6 = np.empty(6)
    P = np.empty((10, 6))
    U = np.empty((10, 6))
    for s in range(N):
        regressor_into(X, A, q[s], dq[s], ddq[s], gravity, Y[s], S, Ti, K, E, T, V, dV, t6, u6, P, U)
    return Y
