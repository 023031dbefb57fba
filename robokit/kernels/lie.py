r"""Small rigid-body helpers for the compiled kernels, written out entry by entry.

Everything here works on plain float64 arrays and writes its result into an ``out``
argument, so the recursions in :mod:`robokit.kernels.poe`, :mod:`robokit.kernels.dynamics`
and :mod:`robokit.kernels.dh` allocate nothing inside their loops over joints.

Conventions (Modern Robotics, Lectures 3–4): a pose is a 4×4 homogeneous transform
``T = [[R, p], [0, 1]]``; a twist ``V = (ω, v)`` and a wrench ``F = (m, f)`` are 6-vectors,
angular first. The formulas used:

* screw exponential, unit axis ``ω̂`` (‖ω‖ ≠ 0, θ scaled by ‖ω‖):
  ``R = I + sin θ [ω̂] + (1 − cos θ)[ω̂]²``, ``p = (Iθ + (1 − cos θ)[ω̂] + (θ − sin θ)[ω̂]²) v``;
  prismatic (ω = 0): ``R = I``, ``p = v θ``;
* adjoint map ``Ad_T V = (R ω, p × (R ω) + R v)``, its transpose on wrenches
  ``Ad_Tᵀ F = (Rᵀ(m − p × f), Rᵀ f)``;
* Lie bracket ``ad_V X = (ω × x_ω, v × x_ω + ω × x_v)`` and ``ad_Vᵀ F = −(ω × m + v × f, ω × f)``.

These are helpers, not public API: the public, checked functions are the seed functions
(:func:`robokit.fkin_space` and friends).
"""
from __future__ import annotations

import math

from robokit.kernels._jit import njit
import numpy as np

#: ‖ω‖ below this makes a screw prismatic (a pure translation), as in the seed library.
PRISMATIC_TOL = 1e-12


@njit
def set_identity(T: np.ndarray) -> None:
    """T ← I₄."""
    for r in range(4):
        for c in range(4):
            T[r, c] = 1.0 if r == c else 0.0


@njit
def copy44(A: np.ndarray, out: np.ndarray) -> None:
    """out ← A (4×4)."""
    for r in range(4):
        for c in range(4):
            out[r, c] = A[r, c]


@njit
def set_bottom_row(T: np.ndarray) -> None:
    """T's last row ← (0, 0, 0, 1): the row every homogeneous transform ends with."""
    T[3, 0] = 0.0
    T[3, 1] = 0.0
    T[3, 2] = 0.0
    T[3, 3] = 1.0


@njit
def exp_screw(S: np.ndarray, j: int, theta: float, T: np.ndarray) -> None:
    """T ← exp([S_j] θ): the pose reached by moving ``theta`` along column ``j`` of the screw
    list ``S`` (6, n). Closed form (Rodrigues and the G(θ) matrix), exact for any ‖ω‖."""
    wx, wy, wz = S[0, j], S[1, j], S[2, j]
    vx, vy, vz = S[3, j], S[4, j], S[5, j]
    nw = math.sqrt(wx * wx + wy * wy + wz * wz)
    set_bottom_row(T)
    if nw < PRISMATIC_TOL:  # prismatic: a pure translation along v
        for r in range(3):
            for c in range(3):
                T[r, c] = 1.0 if r == c else 0.0
        T[0, 3] = vx * theta
        T[1, 3] = vy * theta
        T[2, 3] = vz * theta
        return
    # unit axis and scaled angle
    wx, wy, wz = wx / nw, wy / nw, wz / nw
    vx, vy, vz = vx / nw, vy / nw, vz / nw
    th = theta * nw
    s, c = math.sin(th), math.cos(th)  # type: ignore[assignment]  # c was a loop index above
    omc = 1.0 - c
    # R = I + s [ω] + (1 − c) [ω]²   ([ω]² = ω ωᵀ − I for a unit ω)
    T[0, 0] = c + omc * wx * wx
    T[0, 1] = omc * wx * wy - s * wz
    T[0, 2] = omc * wx * wz + s * wy
    T[1, 0] = omc * wx * wy + s * wz
    T[1, 1] = c + omc * wy * wy
    T[1, 2] = omc * wy * wz - s * wx
    T[2, 0] = omc * wx * wz - s * wy
    T[2, 1] = omc * wy * wz + s * wx
    T[2, 2] = c + omc * wz * wz
    # p = θ v + (1 − c) ω × v + (θ − s) ω × (ω × v),  ω × (ω × v) = ω (ω·v) − v
    cx, cy, cz = wy * vz - wz * vy, wz * vx - wx * vz, wx * vy - wy * vx
    wv = wx * vx + wy * vy + wz * vz
    tms = th - s
    T[0, 3] = th * vx + omc * cx + tms * (wx * wv - vx)
    T[1, 3] = th * vy + omc * cy + tms * (wy * wv - vy)
    T[2, 3] = th * vz + omc * cz + tms * (wz * wv - vz)


@njit
def mul_tt(A: np.ndarray, B: np.ndarray, out: np.ndarray) -> None:
    """out ← A B for homogeneous transforms (the last rows are [0, 0, 0, 1]); out may not alias A or B."""
    for r in range(3):
        a0, a1, a2 = A[r, 0], A[r, 1], A[r, 2]
        for c in range(3):
            out[r, c] = a0 * B[0, c] + a1 * B[1, c] + a2 * B[2, c]
        out[r, 3] = a0 * B[0, 3] + a1 * B[1, 3] + a2 * B[2, 3] + A[r, 3]
    set_bottom_row(out)


@njit
def mul_tt_inplace(A: np.ndarray, B: np.ndarray, tmp: np.ndarray) -> None:
    """A ← A B (row by row through locals: the same sums, in the same order, as :func:`mul_tt`;
    ``tmp`` is not needed and kept for the callers' signature). B may not alias A."""
    b00, b01, b02, b03 = B[0, 0], B[0, 1], B[0, 2], B[0, 3]
    b10, b11, b12, b13 = B[1, 0], B[1, 1], B[1, 2], B[1, 3]
    b20, b21, b22, b23 = B[2, 0], B[2, 1], B[2, 2], B[2, 3]
    for r in range(3):
        a0, a1, a2, a3 = A[r, 0], A[r, 1], A[r, 2], A[r, 3]
        A[r, 0] = a0 * b00 + a1 * b10 + a2 * b20
        A[r, 1] = a0 * b01 + a1 * b11 + a2 * b21
        A[r, 2] = a0 * b02 + a1 * b12 + a2 * b22
        A[r, 3] = a0 * b03 + a1 * b13 + a2 * b23 + a3


@njit
def inv_t(T: np.ndarray, out: np.ndarray) -> None:
    """out ← T⁻¹ = [[Rᵀ, −Rᵀ p], [0, 1]]."""
    for r in range(3):
        for c in range(3):
            out[r, c] = T[c, r]
    for r in range(3):
        out[r, 3] = -(T[0, r] * T[0, 3] + T[1, r] * T[1, 3] + T[2, r] * T[2, 3])
    set_bottom_row(out)


@njit
def adjoint_twist(T: np.ndarray, V: np.ndarray, out: np.ndarray) -> None:
    """out ← Ad_T V = (R ω, p × (R ω) + R v) for a twist V = (ω, v) (6,)."""
    w0 = T[0, 0] * V[0] + T[0, 1] * V[1] + T[0, 2] * V[2]
    w1 = T[1, 0] * V[0] + T[1, 1] * V[1] + T[1, 2] * V[2]
    w2 = T[2, 0] * V[0] + T[2, 1] * V[1] + T[2, 2] * V[2]
    px, py, pz = T[0, 3], T[1, 3], T[2, 3]
    out[3] = py * w2 - pz * w1 + T[0, 0] * V[3] + T[0, 1] * V[4] + T[0, 2] * V[5]
    out[4] = pz * w0 - px * w2 + T[1, 0] * V[3] + T[1, 1] * V[4] + T[1, 2] * V[5]
    out[5] = px * w1 - py * w0 + T[2, 0] * V[3] + T[2, 1] * V[4] + T[2, 2] * V[5]
    out[0] = w0
    out[1] = w1
    out[2] = w2


@njit
def adjoint_screw(T: np.ndarray, S: np.ndarray, j: int, J: np.ndarray, col: int) -> None:
    """J[:, col] ← Ad_T S[:, j]: a screw axis (column j of S) carried by the pose T."""
    w0 = T[0, 0] * S[0, j] + T[0, 1] * S[1, j] + T[0, 2] * S[2, j]
    w1 = T[1, 0] * S[0, j] + T[1, 1] * S[1, j] + T[1, 2] * S[2, j]
    w2 = T[2, 0] * S[0, j] + T[2, 1] * S[1, j] + T[2, 2] * S[2, j]
    px, py, pz = T[0, 3], T[1, 3], T[2, 3]
    J[0, col] = w0
    J[1, col] = w1
    J[2, col] = w2
    J[3, col] = py * w2 - pz * w1 + T[0, 0] * S[3, j] + T[0, 1] * S[4, j] + T[0, 2] * S[5, j]
    J[4, col] = pz * w0 - px * w2 + T[1, 0] * S[3, j] + T[1, 1] * S[4, j] + T[1, 2] * S[5, j]
    J[5, col] = px * w1 - py * w0 + T[2, 0] * S[3, j] + T[2, 1] * S[4, j] + T[2, 2] * S[5, j]


@njit
def adjoint_transpose_wrench(T: np.ndarray, F: np.ndarray, out: np.ndarray) -> None:
    """out ← Ad_Tᵀ F = (Rᵀ(m − p × f), Rᵀ f) for a wrench F = (m, f).

    With ``T = T_ab`` (frame {b} in {a}) this carries a wrench expressed in {a} into {b}:
    ``F_b = Ad_{T_ab}ᵀ F_a`` (power is frame-independent: ``F_bᵀ V_b = F_aᵀ V_a``)."""
    px, py, pz = T[0, 3], T[1, 3], T[2, 3]
    f0, f1, f2 = F[3], F[4], F[5]
    m0 = F[0] - (py * f2 - pz * f1)
    m1 = F[1] - (pz * f0 - px * f2)
    m2 = F[2] - (px * f1 - py * f0)
    out[0] = T[0, 0] * m0 + T[1, 0] * m1 + T[2, 0] * m2
    out[1] = T[0, 1] * m0 + T[1, 1] * m1 + T[2, 1] * m2
    out[2] = T[0, 2] * m0 + T[1, 2] * m1 + T[2, 2] * m2
    out[3] = T[0, 0] * f0 + T[1, 0] * f1 + T[2, 0] * f2
    out[4] = T[0, 1] * f0 + T[1, 1] * f1 + T[2, 1] * f2
    out[5] = T[0, 2] * f0 + T[1, 2] * f1 + T[2, 2] * f2


@njit
def adjoint_matrix(T: np.ndarray, out: np.ndarray) -> None:
    """out (6×6) ← Ad_T = [[R, 0], [[p] R, R]]."""
    px, py, pz = T[0, 3], T[1, 3], T[2, 3]
    for r in range(3):
        for c in range(3):
            out[r, c] = T[r, c]
            out[r + 3, c + 3] = T[r, c]
            out[r, c + 3] = 0.0
    for c in range(3):
        out[3, c] = py * T[2, c] - pz * T[1, c]
        out[4, c] = pz * T[0, c] - px * T[2, c]
        out[5, c] = px * T[1, c] - py * T[0, c]


@njit
def ad_twist(V: np.ndarray, X: np.ndarray, out: np.ndarray) -> None:
    """out ← ad_V X = (ω × x_ω, v × x_ω + ω × x_v) (the Lie bracket [V, X])."""
    w0, w1, w2, v0, v1, v2 = V[0], V[1], V[2], V[3], V[4], V[5]
    a0, a1, a2, b0, b1, b2 = X[0], X[1], X[2], X[3], X[4], X[5]
    out[0] = w1 * a2 - w2 * a1
    out[1] = w2 * a0 - w0 * a2
    out[2] = w0 * a1 - w1 * a0
    out[3] = v1 * a2 - v2 * a1 + w1 * b2 - w2 * b1
    out[4] = v2 * a0 - v0 * a2 + w2 * b0 - w0 * b2
    out[5] = v0 * a1 - v1 * a0 + w0 * b1 - w1 * b0


@njit
def ad_transpose_wrench(V: np.ndarray, F: np.ndarray, out: np.ndarray) -> None:
    """out ← ad_Vᵀ F = −(ω × m + v × f, ω × f) for a twist V and a wrench F = (m, f)."""
    w0, w1, w2, v0, v1, v2 = V[0], V[1], V[2], V[3], V[4], V[5]
    m0, m1, m2, f0, f1, f2 = F[0], F[1], F[2], F[3], F[4], F[5]
    out[0] = -(w1 * m2 - w2 * m1 + v1 * f2 - v2 * f1)
    out[1] = -(w2 * m0 - w0 * m2 + v2 * f0 - v0 * f2)
    out[2] = -(w0 * m1 - w1 * m0 + v0 * f1 - v1 * f0)
    out[3] = -(w1 * f2 - w2 * f1)
    out[4] = -(w2 * f0 - w0 * f2)
    out[5] = -(w0 * f1 - w1 * f0)


@njit
def mat6_vec(G: np.ndarray, x: np.ndarray, out: np.ndarray) -> None:
    """out ← G x for a 6×6 G."""
    for r in range(6):
        acc = 0.0
        for c in range(6):
            acc += G[r, c] * x[c]
        out[r] = acc


@njit
def dot6(a: np.ndarray, b: np.ndarray) -> float:
    """aᵀ b for 6-vectors."""
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2] + a[3] * b[3] + a[4] * b[4] + a[5] * b[5]


@njit
def log_so3(R: np.ndarray, out: np.ndarray) -> None:
    """out (3,) ← ω θ with exp([ω]θ) = R, θ ∈ [0, π] (matrix logarithm of a rotation, Lecture 3).

    Three regimes: θ ≈ 0 (first-order series), θ ≈ π (axis from the largest diagonal entry
    of ``(R + I)/2 = ω ωᵀ``, sign fixed by the antisymmetric part), and the generic formula
    ``[ω] = (R − Rᵀ) / (2 sin θ)``.
    """
    tr = R[0, 0] + R[1, 1] + R[2, 2]
    cos_t = 0.5 * (tr - 1.0)
    if cos_t > 1.0:
        cos_t = 1.0
    elif cos_t < -1.0:
        cos_t = -1.0
    ax = R[2, 1] - R[1, 2]
    ay = R[0, 2] - R[2, 0]
    az = R[1, 0] - R[0, 1]
    sin2 = math.sqrt(ax * ax + ay * ay + az * az)  # = 2 sin θ
    theta = math.atan2(sin2, 2.0 * cos_t)
    if theta < 1e-6:
        # R ≈ I + [ω θ]: ω θ ≈ vee(R − Rᵀ)/2 (error O(θ³))
        out[0] = 0.5 * ax
        out[1] = 0.5 * ay
        out[2] = 0.5 * az
        return
    if theta > math.pi - 1e-4:
        # near π the antisymmetric part vanishes; use the symmetric part instead:
        # (R + Rᵀ)/2 = cos θ I + (1 − cos θ) ω ωᵀ, so ωᵢ² = (Rᵢᵢ − cos θ)/(1 − cos θ) and
        # ωᵢωⱼ = (Rᵢⱼ + Rⱼᵢ) / (2(1 − cos θ)); start from the largest ωᵢ² for accuracy.
        omc = 1.0 - cos_t
        d0, d1, d2 = R[0, 0], R[1, 1], R[2, 2]
        if d0 >= d1 and d0 >= d2:
            x = math.sqrt(max(0.0, (d0 - cos_t) / omc))
            y = (R[0, 1] + R[1, 0]) / (2.0 * omc * x)
            z = (R[0, 2] + R[2, 0]) / (2.0 * omc * x)
        elif d1 >= d2:
            y = math.sqrt(max(0.0, (d1 - cos_t) / omc))
            x = (R[0, 1] + R[1, 0]) / (2.0 * omc * y)
            z = (R[1, 2] + R[2, 1]) / (2.0 * omc * y)
        else:
            z = math.sqrt(max(0.0, (d2 - cos_t) / omc))
            x = (R[0, 2] + R[2, 0]) / (2.0 * omc * z)
            y = (R[1, 2] + R[2, 1]) / (2.0 * omc * z)
        nrm = math.sqrt(x * x + y * y + z * z)
        x, y, z = x / nrm, y / nrm, z / nrm
        if x * ax + y * ay + z * az < 0.0:  # R − Rᵀ = 2 sin θ [ω] fixes the sign of the axis
            x, y, z = -x, -y, -z
        out[0] = x * theta
        out[1] = y * theta
        out[2] = z * theta
        return
    k = theta / sin2
    out[0] = k * ax
    out[1] = k * ay
    out[2] = k * az


@njit
def log_se3(T: np.ndarray, out: np.ndarray) -> None:
    """out (6,) ← (ω θ, v θ) with exp([S]θ) = T (matrix logarithm of a pose, Lecture 4):
    ``ωθ = log R``, ``vθ = G(θ)⁻¹ p`` with
    ``G⁻¹ = I/θ − [ω]/2 + (1/θ − cot(θ/2)/2)[ω]²`` (times θ for the scaled v)."""
    log_so3(T, out)
    wx, wy, wz = out[0], out[1], out[2]
    th = math.sqrt(wx * wx + wy * wy + wz * wz)
    px, py, pz = T[0, 3], T[1, 3], T[2, 3]
    # (vθ) = (I − [ωθ]/2 + k [ωθ]²) p, with k = (1 − (θ/2) cot(θ/2)) / θ²
    if th < 1e-6:
        k = 1.0 / 12.0
    else:
        half = 0.5 * th
        k = (1.0 - half * math.cos(half) / math.sin(half)) / (th * th)
    cx, cy, cz = wy * pz - wz * py, wz * px - wx * pz, wx * py - wy * px  # [ωθ] p
    ccx, ccy, ccz = wy * cz - wz * cy, wz * cx - wx * cz, wx * cy - wy * cx  # [ωθ]² p
    out[3] = px - 0.5 * cx + k * ccx
    out[4] = py - 0.5 * cy + k * ccy
    out[5] = pz - 0.5 * cz + k * ccz


@njit
def all_finite(x: np.ndarray) -> bool:
    """True when every entry of the 1-D array x is finite (no NaN, no ±inf)."""
    for i in range(x.shape[0]):
        if not math.isfinite(x[i]):
            return False
    return True


@njit
def check_joint_values(q: np.ndarray, n: int, name: str, per: str) -> None:
    """Raise ``ValueError`` unless the 1-D array q holds n joint values, all finite: the one check
    of a joint vector for the kinematics kernels, whose messages name the argument (``name``) and
    what each value belongs to (``per``, e.g. ``"row of the DH table"``)."""
    if q.shape[0] != n:
        raise ValueError(name + ": expected one joint value per " + per)
    if not all_finite(q):
        raise ValueError(name + ": contains NaN or infinite values")


__all__ = [
    "PRISMATIC_TOL", "set_identity", "copy44", "exp_screw", "mul_tt", "mul_tt_inplace", "inv_t",
    "adjoint_twist", "adjoint_screw", "adjoint_transpose_wrench", "adjoint_matrix", "ad_twist",
    "ad_transpose_wrench", "mat6_vec", "dot6", "log_so3", "log_se3", "all_finite",
    "check_joint_values",
]
