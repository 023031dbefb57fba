r"""Compiled per-pose parts of the general 6R closed-form IK (Raghavan–Roth elimination,
Manocha–Canny eigenproblem); the derivation is in :mod:`robokit.ik.general_6r`.

Every array is C-contiguous float64; lengths are in units of the arm's scale (the caller
divides them by it). Vectors of the 14 loop-closure quantities carry a 15th entry, 1, so
that a translation acts on them linearly:
``f(l, p) = (l, p, p·p, l·p, l×p, (p·p)l − 2(l·p)p, 1)`` for a unit vector l and a point p.

Kernels
-------
``pencil(P, K1, Tz2, d6, T06, gc, gs, out)``
    the 12×12 quadratic matrix polynomial ``A x² + B x + C`` of one pose (x = tan(φ/2),
    θ₃ = φ + γ) and, for the back-substitution, the pseudo-inverse pieces of the 14×8
    matrix of joints 1–2; returns the smallest / largest singular value ratio of that matrix.
``companion(work, M)``
    the 24 × 24 linearisation of ``A x² + B x + C`` (when A is well conditioned).
``recover(…)``, ``distinct(…)``
    back-substitution and polish of the real eigenvalues; solutions without repeats.
``f_pose(T, inverse, out)``
    the 15 × 15 map of the 14 quantities under a rigid motion (the target's W = T₀₆⁻¹).
``fill_joint(alpha, a, d, T06, theta, j)``
    the eliminated joint from the five others.
``fk_pose(alpha, a, d, theta, out)``
    the pose of ``Z₁X₁ ⋯ X₅Z₆`` (canonical DH chain) at the rotation angles θ.
``jacobian(alpha, a, d, theta, T, J)``
    the geometric Jacobian of that chain.
``polish(alpha, a, d, T06, theta, iters)``
    Newton–Raphson on the pose error ``(p* − p, log(R* Rᵀ))`` with the geometric Jacobian;
    updates θ in place and returns the final error norm.
"""
from __future__ import annotations

import math

import numpy as np

from robokit.kernels._jit import njit

__all__ = ["side_tensor", "pencil", "companion", "recover", "distinct", "f_pose", "fill_joint", "fk_pose", "jacobian",
           "polish", "fvec"]


@njit
def fvec(l0: float, l1: float, l2: float, p0: float, p1: float, p2: float, out: np.ndarray) -> None:
    """The 15 quantities ``f(l, p)`` (see the module docstring) into ``out``."""
    pp = p0 * p0 + p1 * p1 + p2 * p2
    lp = l0 * p0 + l1 * p1 + l2 * p2
    out[0] = l0
    out[1] = l1
    out[2] = l2
    out[3] = p0
    out[4] = p1
    out[5] = p2
    out[6] = pp
    out[7] = lp
    out[8] = l1 * p2 - l2 * p1
    out[9] = l2 * p0 - l0 * p2
    out[10] = l0 * p1 - l1 * p0
    out[11] = pp * l0 - 2.0 * lp * p0
    out[12] = pp * l1 - 2.0 * lp * p1
    out[13] = pp * l2 - 2.0 * lp * p2
    out[14] = 1.0


@njit
def _rz_parts(v: np.ndarray, sign: float, out: np.ndarray) -> None:
    """Split Rz(θ)·v (v a 15-vector) into its cos θ, sin θ and constant parts.

    out[0] · cos θ + out[1] · sin θ + out[2] = F_{Rz(sign·θ)} v.
    """
    for k in range(15):
        out[0, k] = 0.0
        out[1, k] = 0.0
        out[2, k] = v[k]
    for b in (0, 3, 8, 11):  # the four vector blocks
        x, y = v[b], v[b + 1]
        out[0, b] = x
        out[0, b + 1] = y
        out[1, b] = -sign * y
        out[1, b + 1] = sign * x
        out[2, b] = 0.0
        out[2, b + 1] = 0.0


@njit
def side_tensor(Ms: np.ndarray, signs: np.ndarray, f: np.ndarray, out: np.ndarray) -> None:
    """One side of the loop equation as a tensor over its joints' (cos θ, sin θ, 1).

    Ms : (k + 1, 15, 15) constant maps, signs : (k,) ±1 — the side is
    ``Ms[k] · Rz(±θ_{k−1}) · ⋯ · Ms[1] · Rz(±θ₀) · Ms[0] · f`` (Ms[0] applied first);
    out : (3**k, 15), row ``i₀ + 3 i₁ + 9 i₂`` … the coefficient of ``b(θ₀)ᵢ₀ b(θ₁)ᵢ₁ ⋯``
    with ``b(θ) = (cos θ, sin θ, 1)``.
    """
    k = signs.shape[0]
    cur = np.empty((27, 15))
    nxt = np.empty((27, 15))
    for r in range(15):
        acc = 0.0
        for m in range(15):
            acc += Ms[0, r, m] * f[m]
        cur[0, r] = acc
    n = 1
    parts = np.empty((3, 15))
    for j in range(k):
        for t in range(n):
            _rz_parts(cur[t], signs[j], parts)
            for b in range(3):
                row = t + n * b
                for r in range(15):
                    acc = 0.0
                    for m in range(15):
                        acc += Ms[j + 1, r, m] * parts[b, m]
                    nxt[row, r] = acc
        n *= 3
        for t in range(n):
            for r in range(15):
                cur[t, r] = nxt[t, r]
    for t in range(n):
        for r in range(15):
            out[t, r] = cur[t, r]


@njit
def pencil(P: np.ndarray, r: np.ndarray, gc: float, gs: float, out: np.ndarray, Np: np.ndarray,
           Pinv: np.ndarray) -> float:
    """The quadratic matrix polynomial of one pose.

    P : (3, 15, 9) the three-joint side (pivot basis (cos, sin, 1); rows f; columns the
    monomials ``b(θ_b) ⊗ b(θ_c)`` of the other two joints); r : (15, 9) the two-joint side
    (columns ``b(θ_d) ⊗ b(θ_e)``, the last one the constant); (gc, gs): cos γ, sin γ of the
    pivot's shift. Writes out : (3, 12, 12) = (A, B, C); Np : (3, 14, 9) ``P`` with the
    constant of the two-joint side moved over (for the back-substitution); Pinv : (8, 14)
    the pseudo-inverse of the 14 × 8 matrix Q of the two-joint side. Returns σ_min/σ_max of Q.
    """
    Q = np.ascontiguousarray(r[:14, :8])
    U, sv, Vt = np.linalg.svd(Q)
    ratio = sv[7] / sv[0] if sv[0] > 0.0 else 0.0
    for i in range(8):
        for k in range(14):
            acc = 0.0
            for j in range(8):
                if sv[j] > 1e-14 * sv[0]:
                    acc += Vt[j, i] * U[k, j] / sv[j]
            Pinv[i, k] = acc
    for i3 in range(3):
        for k in range(14):
            for m in range(9):
                Np[i3, k, m] = P[i3, k, m]
    for k in range(14):
        Np[2, k, 8] -= r[k, 8]
    # Σ_i3 = N P′_i3, N the left null space of Q (6 × 14)
    sig = np.zeros((3, 6, 9))
    for i3 in range(3):
        for e in range(6):
            for m in range(9):
                s = 0.0
                for k in range(14):
                    s += U[k, 8 + e] * Np[i3, k, m]
                sig[i3, e, m] = s
    # θ₃ = φ + γ: (cos, sin) of θ₃ in terms of φ; then x = tan(φ/2): A x² + B x + C
    G = np.array([[1.0, 0.0, -1.0], [0.0, 2.0, 0.0], [1.0, 0.0, 1.0]])
    for c in range(3):
        for i in range(12):
            for j in range(12):
                out[c, i, j] = 0.0
    for e in range(6):
        for m in range(9):
            sc = sig[0, e, m] * gc + sig[1, e, m] * gs
            ss = -sig[0, e, m] * gs + sig[1, e, m] * gc
            s1 = sig[2, e, m]
            coef2 = s1 - sc  # x²
            coef1 = 2.0 * ss  # x
            coef0 = s1 + sc  # 1
            if coef0 == 0.0 and coef1 == 0.0 and coef2 == 0.0:
                continue
            i4, i5 = m // 3, m % 3
            for j4 in range(3):
                g4 = G[i4, j4]
                if g4 == 0.0:
                    continue
                for j5 in range(3):
                    g = g4 * G[i5, j5]
                    if g == 0.0:
                        continue
                    col = j4 * 3 + j5
                    out[0, e, col] += g * coef2
                    out[1, e, col] += g * coef1
                    out[2, e, col] += g * coef0
                    out[0, 6 + e, col + 3] += g * coef2
                    out[1, 6 + e, col + 3] += g * coef1
                    out[2, 6 + e, col + 3] += g * coef0
    return ratio


@njit
def fill_joint(alpha: np.ndarray, a: np.ndarray, d: np.ndarray, T06: np.ndarray, theta: np.ndarray, j: int) -> None:
    """Set θ_j from the others: ``Rz(θ_j) = (Z₁X₁⋯X_{j−1})⁻¹ T₀₆ (X_j Z_{j+1} ⋯ Z₆)⁻¹ Tz(−d_j)``."""
    A = np.eye(4)
    B = np.eye(4)
    for i in range(6):
        c, s = math.cos(theta[i]), math.sin(theta[i])
        M = B if i > j else A
        if i != j:
            for r in range(3):
                x, y = M[r, 0], M[r, 1]
                M[r, 0] = c * x + s * y
                M[r, 1] = -s * x + c * y
                M[r, 3] += d[i] * M[r, 2]
        if i < 5:
            M = B if i >= j else A
            ca, sa = math.cos(alpha[i]), math.sin(alpha[i])
            for r in range(3):
                M[r, 3] += a[i] * M[r, 0]
                y, z = M[r, 1], M[r, 2]
                M[r, 1] = ca * y + sa * z
                M[r, 2] = -sa * y + ca * z
    # R = A_Rᵀ R₀₆ B_Rᵀ (rotation part of A⁻¹ T B⁻¹)
    R1 = np.empty((3, 3))
    for i in range(3):
        for k in range(3):
            acc = 0.0
            for m in range(3):
                acc += A[m, i] * T06[m, k]
            R1[i, k] = acc
    r00 = 0.0
    r10 = 0.0
    for m in range(3):
        r00 += R1[0, m] * B[0, m]
        r10 += R1[1, m] * B[0, m]
    theta[j] = math.atan2(r10, r00)


@njit
def fk_pose(alpha: np.ndarray, a: np.ndarray, d: np.ndarray, theta: np.ndarray, out: np.ndarray) -> None:
    """Pose of ``Z₁X₁ ⋯ X₅Z₆`` at the rotation angles θ (6,) into out (4, 4)."""
    for i in range(4):
        for j in range(4):
            out[i, j] = 1.0 if i == j else 0.0
    for i in range(6):
        c, s = math.cos(theta[i]), math.sin(theta[i])
        # out ← out · Rz(θ)Tz(d)
        for r in range(3):
            x, y = out[r, 0], out[r, 1]
            out[r, 0] = c * x + s * y
            out[r, 1] = -s * x + c * y
            out[r, 3] += d[i] * out[r, 2]
        if i < 5:
            ca, sa = math.cos(alpha[i]), math.sin(alpha[i])
            # out ← out · Tx(a)Rx(α)
            for r in range(3):
                out[r, 3] += a[i] * out[r, 0]
                y, z = out[r, 1], out[r, 2]
                out[r, 1] = ca * y + sa * z
                out[r, 2] = -sa * y + ca * z


@njit
def _pose_error(Tt: np.ndarray, T: np.ndarray, e: np.ndarray) -> float:
    """e = (p* − p, ω) with exp([ω]) = R* Rᵀ (space frame); returns ‖e‖."""
    for r in range(3):
        e[r] = Tt[r, 3] - T[r, 3]
    # R_err = R* Rᵀ
    Re = np.empty((3, 3))
    for i in range(3):
        for j in range(3):
            s = 0.0
            for k in range(3):
                s += Tt[i, k] * T[j, k]
            Re[i, j] = s
    tr = Re[0, 0] + Re[1, 1] + Re[2, 2]
    cth = 0.5 * (tr - 1.0)
    cth = 1.0 if cth > 1.0 else (-1.0 if cth < -1.0 else cth)
    wx, wy, wz = Re[2, 1] - Re[1, 2], Re[0, 2] - Re[2, 0], Re[1, 0] - Re[0, 1]
    sth = 0.5 * math.sqrt(wx * wx + wy * wy + wz * wz)
    th = math.atan2(sth, cth)
    fac = 0.5
    if sth >= 1e-12:
        fac = 0.5 * th / sth
    e[3] = fac * wx
    e[4] = fac * wy
    e[5] = fac * wz
    return math.sqrt(e[0] * e[0] + e[1] * e[1] + e[2] * e[2] + e[3] * e[3] + e[4] * e[4] + e[5] * e[5])


@njit
def jacobian(alpha: np.ndarray, a: np.ndarray, d: np.ndarray, theta: np.ndarray, T: np.ndarray,
             J: np.ndarray) -> None:
    """Geometric Jacobian (6 × 6, rows (v, ω), space frame, at the end point T[:3, 3]) of
    ``Z₁X₁ ⋯ Z₆`` at θ into J; column i is ``(zᵢ × (p − oᵢ), zᵢ)`` for joint i's axis
    (zᵢ, oᵢ) and the pose T = fk_pose(θ)."""
    G = np.eye(4)
    for i in range(6):
        z0, z1, z2 = G[0, 2], G[1, 2], G[2, 2]
        rx, ry, rz = T[0, 3] - G[0, 3], T[1, 3] - G[1, 3], T[2, 3] - G[2, 3]
        J[0, i] = z1 * rz - z2 * ry
        J[1, i] = z2 * rx - z0 * rz
        J[2, i] = z0 * ry - z1 * rx
        J[3, i] = z0
        J[4, i] = z1
        J[5, i] = z2
        c, s = math.cos(theta[i]), math.sin(theta[i])
        for r in range(3):
            x, y = G[r, 0], G[r, 1]
            G[r, 0] = c * x + s * y
            G[r, 1] = -s * x + c * y
            G[r, 3] += d[i] * G[r, 2]
        if i < 5:
            ca, sa = math.cos(alpha[i]), math.sin(alpha[i])
            for r in range(3):
                G[r, 3] += a[i] * G[r, 0]
                y, z = G[r, 1], G[r, 2]
                G[r, 1] = ca * y + sa * z
                G[r, 2] = -sa * y + ca * z


@njit
def polish(alpha: np.ndarray, a: np.ndarray, d: np.ndarray, T06: np.ndarray, theta: np.ndarray,
           iters: int) -> float:
    """Newton–Raphson on the pose error (geometric Jacobian of ``Z₁X₁ ⋯ Z₆``, space frame).

    Updates theta (6,) in place; returns the final ‖(Δp, Δω)‖ (a step that does not lower
    the error is not taken).
    """
    T = np.empty((4, 4))
    e = np.empty(6)
    J = np.empty((6, 6))
    fk_pose(alpha, a, d, theta, T)
    err = _pose_error(T06, T, e)
    trial = np.empty(6)
    for _ in range(iters):
        if err < 1e-15:
            break
        jacobian(alpha, a, d, theta, T, J)
        dq = np.linalg.lstsq(J, e, rcond=1e-12)[0]
        for i in range(6):
            trial[i] = theta[i] + dq[i]
        fk_pose(alpha, a, d, trial, T)
        new = _pose_error(T06, T, e)
        if not new < err:
            fk_pose(alpha, a, d, theta, T)
            _pose_error(T06, T, e)
            break
        err = new
        for i in range(6):
            theta[i] = trial[i]
    return err


@njit
def f_pose(T: np.ndarray, inverse: bool, out: np.ndarray) -> None:
    """15 × 15 map of f(l, p) under the rigid motion T (or T⁻¹): ``F_tr(p) F_rot(R)``."""
    R = np.empty((3, 3))
    p = np.empty(3)
    for i in range(3):
        for k in range(3):
            R[i, k] = T[k, i] if inverse else T[i, k]
    for i in range(3):
        acc = 0.0
        for k in range(3):
            acc += R[i, k] * T[k, 3]
        p[i] = -acc if inverse else T[i, 3]
    tt = p[0] * p[0] + p[1] * p[1] + p[2] * p[2]
    Ft = np.eye(15)
    for i in range(3):
        Ft[3 + i, 14] = p[i]
        Ft[6, 3 + i] = 2.0 * p[i]
        Ft[7, i] = p[i]
        Ft[11 + i, 7] = -2.0 * p[i]
        for k in range(3):
            Ft[11 + i, k] = (tt if i == k else 0.0) - 2.0 * p[i] * p[k]
    Ft[6, 14] = tt
    # l×p → l×p + l×p_T ; v → v + 2 p_T×(l×p)
    Ft[8, 1], Ft[8, 2] = p[2], -p[1]
    Ft[9, 0], Ft[9, 2] = -p[2], p[0]
    Ft[10, 0], Ft[10, 1] = p[1], -p[0]
    Ft[11, 9], Ft[11, 10] = -2.0 * p[2], 2.0 * p[1]
    Ft[12, 8], Ft[12, 10] = 2.0 * p[2], -2.0 * p[0]
    Ft[13, 8], Ft[13, 9] = -2.0 * p[1], 2.0 * p[0]
    for i in range(15):
        for k in range(15):
            out[i, k] = 0.0
    # out = Ft · F_rot(R): F_rot is block-diagonal (R on the blocks 0, 3, 8, 11; 1 elsewhere)
    for i in range(15):
        for k in (6, 7, 14):
            out[i, k] = Ft[i, k]
        for b in (0, 3, 8, 11):
            for c in range(3):
                acc = 0.0
                for m in range(3):
                    acc += Ft[i, b + m] * R[m, c]
                out[i, b + c] = acc


@njit
def _candidate(alpha: np.ndarray, a: np.ndarray, d: np.ndarray, T06: np.ndarray, V: np.ndarray, phi: float,
               Np: np.ndarray, Pinv: np.ndarray, roles: np.ndarray, gamma: float, th: np.ndarray) -> float:
    """θ (6,) into th from the pivot's φ and the monomial vector V (4, 3) ~ x_bⁱx_cʲ, then
    polished; returns the final pose error."""
    mbc = np.empty(9)
    rhs = np.empty(14)
    best, thb = -1.0, 0.0
    for i in range(3):
        for j in range(3):
            w = V[i, j] ** 2 + V[i + 1, j] ** 2
            if w > best:
                best, thb = w, 2.0 * math.atan2(V[i + 1, j], V[i, j])
    best, thc = -1.0, 0.0
    for i in range(4):
        for j in range(2):
            w = V[i, j] ** 2 + V[i, j + 1] ** 2
            if w > best:
                best, thc = w, 2.0 * math.atan2(V[i, j + 1], V[i, j])
    thp = phi + gamma
    cb, sb, cc, sc = math.cos(thb), math.sin(thb), math.cos(thc), math.sin(thc)
    tb = (cb, sb, 1.0)
    tc = (cc, sc, 1.0)
    for i in range(3):
        for j in range(3):
            mbc[i * 3 + j] = tb[i] * tc[j]
    cp, sp = math.cos(thp), math.sin(thp)
    for r in range(14):
        acc = 0.0
        for m in range(9):
            acc += (Np[0, r, m] * cp + Np[1, r, m] * sp + Np[2, r, m]) * mbc[m]
        rhs[r] = acc
    m2 = 0.0
    m5 = 0.0
    m6 = 0.0
    m7 = 0.0
    for r in range(14):
        m2 += Pinv[2, r] * rhs[r]
        m5 += Pinv[5, r] * rhs[r]
        m6 += Pinv[6, r] * rhs[r]
        m7 += Pinv[7, r] * rhs[r]
    th[roles[0]] = thp
    th[roles[1]] = thb
    th[roles[2]] = thc
    th[roles[3]] = math.atan2(m5, m2)
    th[roles[4]] = math.atan2(m7, m6)
    th[roles[5]] = 0.0
    fill_joint(alpha, a, d, T06, th, roles[5])
    return polish(alpha, a, d, T06, th, 30)


@njit
def recover(alpha: np.ndarray, a: np.ndarray, d: np.ndarray, T06: np.ndarray, num: np.ndarray, den: np.ndarray,
            Z: np.ndarray, Np: np.ndarray, Pinv: np.ndarray, roles: np.ndarray, gamma: float, imag_tol: float,
            conv_tol: float, out: np.ndarray) -> int:
    """Back-substitution and polish of every eigenvalue ``num/den`` that is real to ``imag_tol``
    (as an angle): roles = (pivot, b, c, d, e, j) joint indices (the eigenvalue's joint, the
    two of the eigenvector's monomials ``x_bⁱx_cʲ``, the two of the 14 × 8 system, the
    eliminated one); Z (24, 24) complex eigenvectors. Writes the converged θ (6,) into the
    rows of out (24, 6); returns how many."""
    count = 0
    V = np.empty((4, 3))
    th = np.empty(6)
    for k in range(num.shape[0]):
        nu, de = num[k], den[k]
        if abs(de) > 1e-300:
            lam = nu / de
            imag = 2.0 * abs(lam.imag) / (1.0 + abs(lam) ** 2)
            if imag > imag_tol:
                continue
            phi = 2.0 * math.atan(lam.real)
        else:
            phi = math.pi
        off = 0 if abs(math.tan(0.5 * phi)) <= 1.0 else 12
        jm, big = 0, -1.0
        for i in range(12):
            w = abs(Z[off + i, k])
            if w > big:
                big, jm = w, i
        if big <= 0.0:
            continue
        ph = Z[off + jm, k].conjugate() / big
        for i in range(12):
            V[i // 3, i % 3] = (Z[off + i, k] * ph).real
        err = _candidate(alpha, a, d, T06, V, phi, Np, Pinv, roles, gamma, th)
        if err < conv_tol:
            for i in range(6):
                out[count, i] = th[i]
            count += 1
    return count


@njit
def distinct(TH: np.ndarray, n: int, th0: np.ndarray, same: float, out: np.ndarray) -> int:
    """Rows 0..n−1 of TH as joint values ``q = θ − θ₀`` wrapped to [−π, π), without repeats
    (two rows closer than ``same`` rad in every joint, modulo 2π, are one) into out; returns
    how many."""
    m = 0
    two_pi = 2.0 * math.pi
    q = np.empty(6)
    for r in range(n):
        for i in range(6):
            v = TH[r, i] - th0[i]
            q[i] = v - two_pi * math.floor((v + math.pi) / two_pi)
        dup = False
        for o in range(m):
            close = True
            for i in range(6):
                dv = q[i] - out[o, i]
                dv = dv - two_pi * math.floor((dv + math.pi) / two_pi)
                if abs(dv) >= same:
                    close = False
                    break
            if close:
                dup = True
                break
        if not dup:
            for i in range(6):
                out[m, i] = q[i]
            m += 1
    return m


@njit
def companion(work: np.ndarray, M: np.ndarray) -> float:
    """From (A, B, C) = work (3, 12, 12): the 24 × 24 companion matrix
    ``[[0, I], [−A⁻¹C, −A⁻¹B]]`` into M when A is well conditioned; returns σ_min/σ_max of A
    (the caller uses the generalised eigenproblem instead when it is below 1e-10, and M is
    then left unset)."""
    A = np.ascontiguousarray(work[0])
    sv = np.linalg.svd(A)[1]
    cond = sv[11] / sv[0] if sv[0] > 0.0 else 0.0
    if cond <= 1e-10:
        return cond
    rhs = np.empty((12, 24))
    for i in range(12):
        for j in range(12):
            rhs[i, j] = work[2, i, j]
            rhs[i, 12 + j] = work[1, i, j]
    X = np.linalg.solve(A, rhs)
    for i in range(24):
        for j in range(24):
            M[i, j] = 0.0
    for i in range(12):
        M[i, 12 + i] = 1.0
        for j in range(24):
            M[12 + i, j] = -X[i, j]
    return cond

