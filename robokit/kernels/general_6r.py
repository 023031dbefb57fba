r"""Compiled per-pose parts of the general 6R closed-form IK (Raghavan–Roth elimination,
Manocha–Canny eigenproblem); the derivation is in :mod:`robokit.ik.general_6r`.

Every array is C-contiguous float64; lengths are in units of the arm's scale (the caller
divides them by it). Vectors of the 14 loop-closure quantities carry a 15th entry, 1, so
that a translation acts on them linearly:
``f(l, p) = (l, p, p·p, l·p, l×p, (p·p)l − 2(l·p)p, 1)`` for a unit vector l and a point p.

Kernels
-------
``solve_pose(chain, tol, ri, mats, const, vec, T06s, out)``
    the whole solve of one pose in one call: for the best reading of the loop equation (and the
    next ones on a badly conditioned pose) ``reading_candidates``, then the solutions merged and
    ordered; the per-arm tables come from :class:`robokit.ik.general_6r.GeneralSixR`.
``reading_matrices``, ``score_reading``, ``reading_candidates``
    one reading: its two sides for a pose; its conditioning figure (to rank the readings once
    per arm); its polished candidates.
``pencil(P, r, gc, gs, out, Np, Pinv)``
    the 12×12 quadratic matrix polynomial ``A x² + B x + C`` of one pose (x = tan(φ/2),
    θ₃ = φ + γ) and, for the back-substitution, the pseudo-inverse pieces of the 14×8
    matrix of joints 1–2; returns the smallest / largest singular value ratio of that matrix.
``companion(work, M)``, ``deflate(work, M)``, ``turn(work, t)``, ``eigenvalues(h, wr, wi)``,
``null_vector(work, y, v)``
    the 24 × 24 linearisation of ``A x² + B x + C`` (when A is well conditioned), the same
    without its eigenvalues ±i (when ``A x² + B x + C`` is singular there), the turned
    variable (when A is not), the eigenvalues of a real matrix (balancing, Hessenberg
    reduction, Francis double-shift QR), the null vector at a real root (inverse iteration).
``sv_ratio(a)``
    σ_min/σ_max of a small matrix (Golub–Kahan bidiagonalisation, Sturm-count bisection).
``distinct(…)``
    solutions without repeats.
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

The small dense linear algebra (Householder vectors, one-sided Jacobi SVD, LU with partial
pivoting, the eigenvalue iteration) is written here from Golub & Van Loan, *Matrix
Computations*, so that the whole pipeline compiles into one call without LAPACK round trips
(numba's ``np.linalg.svd`` of a 12 × 12 matrix costs about as much as this module's whole
eigenvalue solve). The generated C (:mod:`robokit.codegen`) takes the same steps.
"""
from __future__ import annotations

import math

import numpy as np

from robokit.kernels._jit import njit
from robokit.kernels.lie import inv_t, mul_tt, mul_tt_inplace

__all__ = ["side_tensor", "pencil", "companion", "deflate", "nullity_at_i", "turn", "eigenvalues", "null_vector",
           "sv_ratio", "regularity",
           "reading_matrices", "score_reading", "reading_candidates", "solve_pose", "distinct", "f_pose", "fill_joint",
           "fk_pose", "jacobian", "polish", "fvec"]


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
    cur[0] = np.ascontiguousarray(Ms[0]) @ np.ascontiguousarray(f)
    n = 1
    parts = np.empty((3, 15))
    split = np.empty((27, 15))
    for j in range(k):
        for t in range(n):  # every row split into its cos, sin and constant parts …
            _rz_parts(cur[t], signs[j], parts)
            for b in range(3):
                split[t + n * b] = parts[b]
        n *= 3
        cur[:n] = split[:n] @ np.ascontiguousarray(Ms[j + 1]).T  # … then the next constant map
    out[:n] = cur[:n]


@njit
def fill_joint(alpha: np.ndarray, a: np.ndarray, d: np.ndarray, T06: np.ndarray, theta: np.ndarray, j: int) -> None:
    """Set θ_j from the others: ``Rz(θ_j) = (Z₁X₁⋯X_{j−1})⁻¹ T₀₆ (X_j Z_{j+1} ⋯ Z₆)⁻¹ Tz(−d_j)``."""
    A = np.eye(4)
    B = np.eye(4)
    for i in range(6):
        if i != j:
            z_step(B if i > j else A, theta[i], d[i])
        if i < 5:
            x_step(B if i >= j else A, alpha[i], a[i])
    # R = A_Rᵀ R₀₆ B_Rᵀ (rotation part of A⁻¹ T B⁻¹)
    R1 = np.empty((4, 4))
    inv_t(A, R1)
    mul_tt_inplace(R1, T06, R1)
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
    for i in range(6):  # out ← out · Zᵢ Xᵢ (no X after the last joint)
        z_step(out, theta[i], d[i])
        if i < 5:
            x_step(out, alpha[i], a[i])


@njit
def z_step(G: np.ndarray, theta_i: float, d_i: float) -> None:
    """G ← G · Rz(θᵢ)Tz(dᵢ): the joint factor Zᵢ of ``Z₁X₁ ⋯ X₅Z₆``."""
    c, s = math.cos(theta_i), math.sin(theta_i)
    for r in range(3):
        x, y = G[r, 0], G[r, 1]
        G[r, 0] = c * x + s * y
        G[r, 1] = -s * x + c * y
        G[r, 3] += d_i * G[r, 2]


@njit
def x_step(G: np.ndarray, alpha_i: float, a_i: float) -> None:
    """G ← G · Tx(aᵢ)Rx(αᵢ): the link factor Xᵢ of ``Z₁X₁ ⋯ X₅Z₆``."""
    ca, sa = math.cos(alpha_i), math.sin(alpha_i)
    for r in range(3):
        G[r, 3] += a_i * G[r, 0]
        y, z = G[r, 1], G[r, 2]
        G[r, 1] = ca * y + sa * z
        G[r, 2] = -sa * y + ca * z


@njit
def _pose_error(Tt: np.ndarray, T: np.ndarray, e: np.ndarray) -> float:
    """e = (p* − p, ω) with exp([ω]) = R* Rᵀ (space frame); returns ‖e‖."""
    for r in range(3):
        e[r] = Tt[r, 3] - T[r, 3]
    # R_err = R* Rᵀ (rotation part of T* T⁻¹)
    Tinv = np.empty((4, 4))
    inv_t(T, Tinv)
    Re = np.empty((4, 4))
    mul_tt(Tt, Tinv, Re)
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
        z_step(G, theta[i], d[i])  # G ← G · Zᵢ Xᵢ, as in fk_pose
        if i < 5:
            x_step(G, alpha[i], a[i])


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


# ---------------------------------------------------------------- small dense linear algebra
# Written from Golub & Van Loan, *Matrix Computations* (4th ed.): Householder vectors §5.1.3,
# one-sided Jacobi SVD §8.6.3, Golub–Kahan bidiagonalisation §5.4.8 with Sturm-count bisection
# (Demmel & Kahan 1990), LU with partial pivoting §3.4, balancing §7.5.7, Hessenberg reduction
# §7.4.3, Francis double-shift QR §7.5.5. The same steps as the generated C (robokit.codegen).


@njit
def _house(x: np.ndarray, n: int, v: np.ndarray) -> float:
    """Householder vector of x[:n]: ``(I − β v vᵀ) x = (±‖x‖, 0, …, 0)`` with v[0] = 1 written
    into v[:n]; returns β (0 when x is already a multiple of e₁)."""
    sigma = 0.0
    for i in range(1, n):
        sigma += x[i] * x[i]
    v[0] = 1.0
    for i in range(1, n):
        v[i] = x[i]
    if sigma == 0.0:
        return 0.0
    x0 = x[0]
    mu = math.sqrt(x0 * x0 + sigma)
    v0 = x0 - mu if x0 <= 0.0 else -sigma / (x0 + mu)
    for i in range(1, n):
        v[i] /= v0
    return 2.0 * v0 * v0 / (sigma + v0 * v0)


@njit
def _reflect_column(a: np.ndarray, k: int, x: np.ndarray, vv: np.ndarray) -> float:
    """The Householder reflection that zeroes column k of the m × n matrix a below row k, applied
    to a from the left (columns k …); its vector in vv[:m − k] (x is scratch); returns β."""
    m, n = a.shape
    for i in range(k, m):
        x[i - k] = a[i, k]
    beta = _house(x, m - k, vv)
    for j in range(k, n):
        s = 0.0
        for i in range(k, m):
            s += vv[i - k] * a[i, j]
        s *= beta
        for i in range(k, m):
            a[i, j] -= s * vv[i - k]
    return beta


@njit
def _svd_jacobi(a: np.ndarray, sv: np.ndarray, u: np.ndarray, v: np.ndarray) -> None:
    """One-sided Jacobi SVD (Hestenes) of the m × n matrix a (overwritten), m ≥ n: plane rotations
    make the columns orthogonal; sv (n,) the singular values, decreasing; u (m, n) the left
    singular vectors (columns), v (n, n) the right ones: ``a = u diag(sv) vᵀ``."""
    m, n = a.shape
    for i in range(n):
        for j in range(n):
            v[i, j] = 1.0 if i == j else 0.0
    rotated = True
    sweep = 0
    while rotated and sweep < 60:
        rotated = False
        sweep += 1
        for p in range(n - 1):
            for q in range(p + 1, n):
                al = 0.0
                be = 0.0
                ga = 0.0
                for i in range(m):
                    x, y = a[i, p], a[i, q]
                    al += x * x
                    be += y * y
                    ga += x * y
                if ga == 0.0 or abs(ga) <= 1e-15 * math.sqrt(al * be):
                    continue
                rotated = True
                # the rotation that zeroes the (p, q) entry of the 2 × 2 Gram matrix
                zeta = (be - al) / (2.0 * ga)
                t = (1.0 if zeta >= 0.0 else -1.0) / (abs(zeta) + math.sqrt(1.0 + zeta * zeta))
                c = 1.0 / math.sqrt(1.0 + t * t)
                s = c * t
                for i in range(m):
                    x, y = a[i, p], a[i, q]
                    a[i, p] = c * x - s * y
                    a[i, q] = s * x + c * y
                for i in range(n):
                    x, y = v[i, p], v[i, q]
                    v[i, p] = c * x - s * y
                    v[i, q] = s * x + c * y
    norms = np.empty(n)
    order = np.empty(n, dtype=np.int64)
    for p in range(n):
        s2 = 0.0
        for i in range(m):
            s2 += a[i, p] * a[i, p]
        norms[p] = math.sqrt(s2)
        order[p] = p
    for p in range(1, n):  # insertion sort, decreasing
        o = order[p]
        q = p - 1
        while q >= 0 and norms[order[q]] < norms[o]:
            order[q + 1] = order[q]
            q -= 1
        order[q + 1] = o
    tmp = v.copy()
    for p in range(n):
        o = order[p]
        sv[p] = norms[o]
        inv = 1.0 / norms[o] if norms[o] > 0.0 else 0.0
        for i in range(m):
            u[i, p] = a[i, o] * inv
        for i in range(n):
            v[i, p] = tmp[i, o]


@njit
def _gk_count(c: np.ndarray, length: int, mu: float) -> int:
    """How many eigenvalues of the length × length tridiagonal with zero diagonal and
    off-diagonal c are below mu: the negative pivots of its LDLᵀ − μI (Sylvester's inertia)."""
    q = -mu
    count = 1 if q < 0.0 else 0
    for i in range(1, length):
        if q == 0.0:
            q = -1e-300
        q = -mu - c[i - 1] * c[i - 1] / q
        if q < 0.0:
            count += 1
    return count


@njit
def _bidiagonal(a: np.ndarray, c: np.ndarray) -> float:
    """Householder bidiagonalisation of the m × n matrix a (overwritten), m ≥ n: c (2n − 1) the
    off-diagonal ``(d₁, e₁, d₂, …, dₙ)`` of the Golub–Kahan tridiagonal ``[[0, Bᵀ], [B, 0]]``,
    whose eigenvalues are ±σᵢ; returns a Gershgorin bound on σ_max."""
    m, n = a.shape
    x = np.empty(m)
    vv = np.empty(m)
    for k in range(n):
        _reflect_column(a, k, x, vv)  # left reflection: column k below the diagonal
        c[2 * k] = a[k, k]
        if k < n - 2:  # right reflection: row k right of the superdiagonal
            for j in range(k + 1, n):
                x[j - k - 1] = a[k, j]
            beta = _house(x, n - k - 1, vv)
            for i in range(k, m):
                s = 0.0
                for j in range(k + 1, n):
                    s += a[i, j] * vv[j - k - 1]
                s *= beta
                for j in range(k + 1, n):
                    a[i, j] -= s * vv[j - k - 1]
        if k < n - 1:
            c[2 * k + 1] = a[k, k + 1]
    bound = 0.0
    for k in range(2 * n - 1):
        mu = abs(c[k]) + (abs(c[k + 1]) if k + 1 < 2 * n - 1 else 0.0)
        bound = max(bound, mu)
    return bound


@njit
def sv_ratio(a: np.ndarray) -> float:
    """σ_min/σ_max of the m × n matrix a (m ≥ n; a is overwritten), each to 1e-7 relative, by
    bisection on the Sturm counts of the Golub–Kahan tridiagonal; ratios below 1e-20 give 0."""
    n = a.shape[1]
    c = np.empty(2 * n)
    bound = _bidiagonal(a, c)
    if bound == 0.0 or not bound < np.inf:
        return 0.0
    lo = 0.0
    for k in range(2 * n - 1):  # σ_max is at least every entry of the bidiagonal
        lo = max(lo, abs(c[k]))
    hi = bound
    it = 0
    while it < 100 and hi - lo > 1e-7 * hi:  # σ_max: #{σ < μ} = count(μ) − n reaches n
        mid = 0.5 * (lo + hi)
        if _gk_count(c, 2 * n, mid) - n >= n:
            hi = mid
        else:
            lo = mid
        it += 1
    smax = hi
    if _gk_count(c, 2 * n, 1e-20 * smax) - n >= 1:
        return 0.0
    lo, hi = 1e-20 * smax, smax
    it = 0
    while it < 100 and hi - lo > 1e-7 * hi:  # σ_min, bisecting its logarithm
        mid = math.sqrt(lo * hi)
        if _gk_count(c, 2 * n, mid) - n >= 1:
            hi = mid
        else:
            lo = mid
        it += 1
    return 0.5 * (lo + hi) / smax


@njit
def _well_conditioned(a: np.ndarray, tol: float) -> bool:
    """Whether σ_min > tol · σ_max holds for sure (one Sturm count on a's bidiagonal; False
    may be a false alarm). a is overwritten."""
    n = a.shape[1]
    c = np.empty(2 * n)
    bound = _bidiagonal(a, c)
    return bound > 0.0 and _gk_count(c, 2 * n, tol * bound) - n == 0


@njit
def _lu(a: np.ndarray, piv: np.ndarray) -> None:
    """LU factorisation with partial pivoting of the n × n matrix a, in place; piv[k] the row
    swapped with k. A zero pivot is replaced by a tiny one (the callers want a null vector by
    inverse iteration, or have checked the conditioning)."""
    n = a.shape[0]
    big = 0.0
    for i in range(n):
        for j in range(n):
            big = max(big, abs(a[i, j]))
    for k in range(n):
        p = k
        best = abs(a[k, k])
        for i in range(k + 1, n):
            if abs(a[i, k]) > best:
                best = abs(a[i, k])
                p = i
        piv[k] = p
        if p != k:
            for j in range(n):
                t = a[k, j]
                a[k, j] = a[p, j]
                a[p, j] = t
        if a[k, k] == 0.0:
            a[k, k] = 1e-300 + 1e-18 * big
        for i in range(k + 1, n):
            l = a[i, k] / a[k, k]
            a[i, k] = l
            for j in range(k + 1, n):
                a[i, j] -= l * a[k, j]


@njit
def _lu_solve(lu: np.ndarray, piv: np.ndarray, b: np.ndarray) -> None:
    """Solve ``(LU) x = b`` in place (lu, piv from :func:`_lu`)."""
    n = lu.shape[0]
    for i in range(n):
        t = b[piv[i]]
        b[piv[i]] = b[i]
        b[i] = t
    for i in range(n):
        for j in range(i):
            b[i] -= lu[i, j] * b[j]
    for i in range(n - 1, -1, -1):
        for j in range(i + 1, n):
            b[i] -= lu[i, j] * b[j]
        b[i] /= lu[i, i]


@njit
def _balance(h: np.ndarray) -> None:
    """Parlett–Reinsch balancing of the n × n matrix h in place: ``D⁻¹ h D`` with D a diagonal
    of powers of 2 that makes each row's and column's off-diagonal norms alike (same eigenvalues)."""
    n = h.shape[0]
    done = False
    while not done:
        done = True
        for i in range(n):
            c = 0.0
            r = 0.0
            for j in range(n):
                if j != i:
                    c += abs(h[j, i])
                    r += abs(h[i, j])
            if c == 0.0 or r == 0.0 or not c + r < np.inf:
                continue  # nothing to balance (or not finite: the QR iteration fails and says so)
            f = 1.0
            s = c + r
            g = r / 2.0
            while c < g:
                f *= 2.0
                c *= 4.0
            g = r * 2.0
            while c >= g:
                f /= 2.0
                c /= 4.0
            if (c + r) / f < 0.95 * s:
                done = False
                for j in range(n):
                    h[i, j] /= f
                    h[j, i] *= f


@njit
def _hessenberg(h: np.ndarray) -> None:
    """Reduce the n × n matrix h in place to upper Hessenberg form by Householder reflections
    from both sides (a similarity: the eigenvalues are kept)."""
    n = h.shape[0]
    x = np.empty(n)
    vv = np.empty(n)
    for k in range(n - 2):
        ln = n - k - 1
        for i in range(ln):
            x[i] = h[k + 1 + i, k]
        beta = _house(x, ln, vv)
        if beta == 0.0:
            continue
        for j in range(k, n):
            s = 0.0
            for i in range(ln):
                s += vv[i] * h[k + 1 + i, j]
            s *= beta
            for i in range(ln):
                h[k + 1 + i, j] -= s * vv[i]
        for i in range(n):
            s = 0.0
            for j in range(ln):
                s += h[i, k + 1 + j] * vv[j]
            s *= beta
            for j in range(ln):
                h[i, k + 1 + j] -= s * vv[j]
        for i in range(k + 2, n):
            h[i, k] = 0.0


@njit
def _reflect3(x: float, y: float, z: float, three: bool) -> tuple[float, float, float]:
    """The Householder reflection ``I − β v vᵀ``, v = (1, v₁, v₂), taking (x, y, z) — or (x, y)
    when not ``three`` — to (∗, 0, 0): (β, v₁, v₂)."""
    sigma = y * y + (z * z if three else 0.0)
    if sigma == 0.0:
        return 0.0, 0.0, 0.0
    mu = math.sqrt(x * x + sigma)
    v0 = x - mu if x <= 0.0 else -sigma / (x + mu)
    return 2.0 * v0 * v0 / (sigma + v0 * v0), y / v0, (z / v0 if three else 0.0)


_EPS = 2.220446049250313e-16


@njit
def eigenvalues(h: np.ndarray, wr: np.ndarray, wi: np.ndarray) -> int:
    """Eigenvalues ``wr + i wi`` of the n × n real matrix h (destroyed): balancing, Hessenberg
    reduction, then Francis double-shift QR steps with deflation at negligible subdiagonal
    entries (the criterion of Ahues & Tisseur 1997) on the active window only — no vectors.
    Returns 0, or −1 when the iteration did not converge (40 n steps without a deflation)."""
    n = h.shape[0]
    _balance(h)
    _hessenberg(h)
    hi = n - 1
    its = 0
    while hi >= 0:
        # the lowest lo with h[lo, lo−1] negligible beside its neighbours (with zero diagonals, as
        # in a companion matrix, beside the next subdiagonal entries)
        lo = hi
        while lo > 0:
            sub = abs(h[lo, lo - 1])
            if sub <= 1e-300:
                h[lo, lo - 1] = 0.0
                break
            tst = abs(h[lo - 1, lo - 1]) + abs(h[lo, lo])
            if tst == 0.0:
                tst = (abs(h[lo - 1, lo - 2]) if lo >= 2 else 0.0) + (abs(h[lo + 1, lo]) if lo + 1 < n else 0.0)
            if sub <= _EPS * tst:
                sup = abs(h[lo - 1, lo])
                dd = abs(h[lo - 1, lo - 1] - h[lo, lo])
                hh = abs(h[lo, lo])
                ab, ba = max(sub, sup), min(sub, sup)
                aa, bb = max(hh, dd), min(hh, dd)
                ss = aa + ab
                if ba * (ab / ss) <= max(_EPS * (bb * (aa / ss)), 1e-300):
                    h[lo, lo - 1] = 0.0
                    break
            lo -= 1
        if lo == hi:  # a 1 × 1 block: a real eigenvalue
            wr[hi] = h[hi, hi]
            wi[hi] = 0.0
            hi -= 1
            its = 0
        elif lo == hi - 1:  # a 2 × 2 block: two real eigenvalues or a complex pair
            a, b, c, d = h[hi - 1, hi - 1], h[hi - 1, hi], h[hi, hi - 1], h[hi, hi]
            p = 0.5 * (a - d)
            disc = p * p + b * c
            if disc >= 0.0:
                z = p + (math.sqrt(disc) if p >= 0.0 else -math.sqrt(disc))
                wr[hi - 1] = d + z
                wr[hi] = d - b * c / z if z != 0.0 else d
                wi[hi - 1] = 0.0
                wi[hi] = 0.0
            else:
                wr[hi - 1] = d + p
                wr[hi] = d + p
                wi[hi - 1] = math.sqrt(-disc)
                wi[hi] = -math.sqrt(-disc)
            hi -= 2
            its = 0
        else:
            its += 1
            if its > 40 * n:
                return -1
            if its % 10 == 0:  # exceptional shifts (ad hoc, as in LAPACK's dlahqr) break cycles
                top = its % 20 == 10
                if top:
                    e = abs(h[lo + 1, lo]) + abs(h[lo + 2, lo + 1])
                    h11 = 0.75 * e + h[lo, lo]
                else:
                    e = abs(h[hi, hi - 1]) + abs(h[hi - 1, hi - 2])
                    h11 = 0.75 * e + h[hi, hi]
                s = 2.0 * h11
                t = h11 * h11 + 0.4375 * e * e
            else:  # the eigenvalues of the trailing 2 × 2 block as the shifts
                s = h[hi - 1, hi - 1] + h[hi, hi]
                t = h[hi - 1, hi - 1] * h[hi, hi] - h[hi - 1, hi] * h[hi, hi - 1]
            # first column of (H − s₁)(H − s₂): the bulge, chased down the subdiagonal
            x = h[lo, lo] * h[lo, lo] + h[lo, lo + 1] * h[lo + 1, lo] - s * h[lo, lo] + t
            y = h[lo + 1, lo] * (h[lo, lo] + h[lo + 1, lo + 1] - s)
            z = h[lo + 1, lo] * h[lo + 2, lo + 1]
            for m in range(lo, hi):
                three = m < hi - 1
                c0 = m - 1 if m > lo else lo
                r1 = min(m + 3, hi)
                beta, v1, v2 = _reflect3(x, y, z, three)
                if beta != 0.0:
                    bv1, bv2 = beta * v1, beta * v2
                    if three:
                        for j in range(c0, hi + 1):  # from the left: rows m … m+2
                            sm = h[m, j] + v1 * h[m + 1, j] + v2 * h[m + 2, j]
                            h[m, j] -= beta * sm
                            h[m + 1, j] -= bv1 * sm
                            h[m + 2, j] -= bv2 * sm
                        for i in range(lo, r1 + 1):  # from the right: columns m … m+2
                            sm = h[i, m] + v1 * h[i, m + 1] + v2 * h[i, m + 2]
                            h[i, m] -= beta * sm
                            h[i, m + 1] -= bv1 * sm
                            h[i, m + 2] -= bv2 * sm
                    else:  # the last step: a 2-vector reflection
                        for j in range(c0, hi + 1):
                            sm = h[m, j] + v1 * h[m + 1, j]
                            h[m, j] -= beta * sm
                            h[m + 1, j] -= bv1 * sm
                        for i in range(lo, r1 + 1):
                            sm = h[i, m] + v1 * h[i, m + 1]
                            h[i, m] -= beta * sm
                            h[i, m + 1] -= bv1 * sm
                if three:
                    x = h[m + 1, m]
                    y = h[m + 2, m]
                    z = h[m + 3, m] if m < hi - 2 else 0.0
    return 0


@njit
def _left_null_space(q: np.ndarray, out: np.ndarray) -> None:
    """The left null space of the 14 × 8 matrix q: the last 6 columns of the orthogonal factor of
    its Householder QR, into out (14, 6) (orthonormal columns, ``outᵀ q = 0`` when q has rank 8)."""
    m, n = q.shape
    r = q.copy()
    vs = np.zeros((n, m))
    betas = np.empty(n)
    x = np.empty(m)
    vv = np.empty(m)
    for j in range(n):
        betas[j] = _reflect_column(r, j, x, vv)
        for i in range(m - j):
            vs[j, i] = vv[i]
    for e in range(m - n):  # columns n … m−1 of H₀H₁⋯H_{n−1}: the reflections applied to eₙ₊ₑ, last first
        for i in range(m):
            x[i] = 0.0
        x[n + e] = 1.0
        for j in range(n - 1, -1, -1):
            s = 0.0
            for i in range(j, m):
                s += vs[j, i - j] * x[i]
            s *= betas[j]
            for i in range(j, m):
                x[i] -= s * vs[j, i - j]
        for i in range(m):
            out[i, e] = x[i]


@njit
def pencil(P: np.ndarray, r: np.ndarray, gc: float, gs: float, out: np.ndarray, Np: np.ndarray,
           Pinv: np.ndarray) -> float:
    """The quadratic matrix polynomial of one pose.

    P : (3, 15, 9) the three-joint side (pivot basis (cos, sin, 1); rows f; columns the
    monomials ``b(θ_b) ⊗ b(θ_c)`` of the other two joints); r : (15, 9) the two-joint side
    (columns ``b(θ_d) ⊗ b(θ_e)``, the last one the constant); (gc, gs): cos γ, sin γ of the
    pivot's shift. Writes out : (3, 12, 12) = (A, B, C); Np : (3, 14, 9) ``P`` with the
    constant of the two-joint side moved over (for the back-substitution); Pinv : (8, 14)
    the pseudo-inverse of the 14 × 8 matrix Q of the two-joint side (singular values below
    1e-14 σ_max dropped). Returns σ_min/σ_max of Q.
    """
    Q = np.empty((14, 8))
    for k in range(14):
        for j in range(8):
            Q[k, j] = r[k, j]
    work = Q.copy()
    U = np.empty((14, 8))
    sv = np.empty(8)
    V = np.empty((8, 8))  # columns: the right singular vectors
    _svd_jacobi(work, sv, U, V)
    ratio = sv[7] / sv[0] if sv[0] > 0.0 else 0.0
    for i in range(8):
        for k in range(14):
            acc = 0.0
            for j in range(8):
                if sv[j] > 1e-14 * sv[0]:
                    acc += V[i, j] * U[k, j] / sv[j]
            Pinv[i, k] = acc
    for i3 in range(3):
        for k in range(14):
            for m in range(9):
                Np[i3, k, m] = P[i3, k, m]
    for k in range(14):
        Np[2, k, 8] -= r[k, 8]
    # Σ_i3 = Nᵀ P′_i3, N the left null space of Q (14 × 6): θ of the two-joint side eliminated
    N = np.empty((14, 6))
    _left_null_space(Q, N)
    sig = np.empty((3, 6, 9))
    Nt = np.ascontiguousarray(N.T)
    for i3 in range(3):
        sig[i3] = Nt @ Np[i3]
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
def regularity(work: np.ndarray, x: float) -> float:
    """σ_min/σ_max of the 12 × 12 matrix ``A x² + B x + C`` ((A, B, C) = work (3, 12, 12)):
    about 0 at every x when the pencil is singular (a near-continuum of solutions)."""
    L = np.empty((12, 12))
    for i in range(12):
        for j in range(12):
            L[i, j] = work[0, i, j] * x * x + work[1, i, j] * x + work[2, i, j]
    return sv_ratio(L)


@njit
def companion(work: np.ndarray, M: np.ndarray) -> float:
    """From (A, B, C) = work (3, 12, 12): the 24 × 24 companion matrix
    ``[[0, I], [−A⁻¹C, −A⁻¹B]]`` into M when A is well conditioned (LU with partial pivoting);
    returns σ_min/σ_max of A (the caller turns the variable instead when it is at most 1e-10,
    and M is then left unset)."""
    A = work[0].copy()
    cond = sv_ratio(A)
    if not cond > 1e-10:
        return cond
    lu = work[0].copy()
    piv = np.empty(12, dtype=np.int64)
    _lu(lu, piv)
    col = np.empty(12)
    for i in range(24):
        for j in range(24):
            M[i, j] = 0.0
    for i in range(12):
        M[i, 12 + i] = 1.0
    for j in range(24):  # column j of [C, B], solved
        for i in range(12):
            col[i] = work[2, i, j] if j < 12 else work[1, i, j - 12]
        _lu_solve(lu, piv, col)
        for i in range(12):
            M[12 + i, j] = -col[i]
    return cond


#: Largest number of eigenvalue pairs ±i that :func:`deflate` removes (the C's workspace holds 4).
DEFLATE_MAX = 4


@njit
def _eliminate_i(work: np.ndarray, Kr: np.ndarray, Ki: np.ndarray, perm: np.ndarray) -> int:
    """Gaussian elimination with complete pivoting of ``L(i) = C − A + iB`` ((A, B, C) = work)
    into (Kr, Ki) (12 × 12: real and imaginary parts) with the column order perm; pivots below
    1e-11 of the largest entry end it. Returns the rank (the null space's dimension is 12 − rank)."""
    n = 12
    big = 0.0
    for i in range(n):
        for j in range(n):
            Kr[i, j] = work[2, i, j] - work[0, i, j]
            Ki[i, j] = work[1, i, j]
            big = max(big, Kr[i, j] * Kr[i, j] + Ki[i, j] * Ki[i, j])
        perm[i] = i
    for k in range(n):
        best, p, q = -1.0, k, k
        for i in range(k, n):
            for j in range(k, n):
                m2 = Kr[i, j] * Kr[i, j] + Ki[i, j] * Ki[i, j]
                if m2 > best:
                    best, p, q = m2, i, j
        if not best > 1e-22 * big:
            return k
        for j in range(n):  # rows k, p
            Kr[k, j], Kr[p, j] = Kr[p, j], Kr[k, j]
            Ki[k, j], Ki[p, j] = Ki[p, j], Ki[k, j]
        for i in range(n):  # columns k, q
            Kr[i, k], Kr[i, q] = Kr[i, q], Kr[i, k]
            Ki[i, k], Ki[i, q] = Ki[i, q], Ki[i, k]
        perm[k], perm[q] = perm[q], perm[k]
        pr, pi = Kr[k, k] / best, -Ki[k, k] / best  # 1 / pivot
        for i in range(k + 1, n):
            lr = Kr[i, k] * pr - Ki[i, k] * pi
            li = Kr[i, k] * pi + Ki[i, k] * pr
            for j in range(k + 1, n):
                Kr[i, j] -= lr * Kr[k, j] - li * Ki[k, j]
                Ki[i, j] -= lr * Ki[k, j] + li * Kr[k, j]
    return n


@njit
def nullity_at_i(work: np.ndarray) -> int:
    """How many independent null vectors ``A x² + B x + C`` ((A, B, C) = work) has at x = i
    (:func:`deflate`; the solver records it per reading once per arm, and only the readings
    where it is positive try the deflation)."""
    Kr = np.empty((12, 12))
    Ki = np.empty((12, 12))
    perm = np.empty(12, dtype=np.int64)
    return 12 - _eliminate_i(work, Kr, Ki, perm)


@njit
def deflate(work: np.ndarray, M: np.ndarray) -> int:
    """Remove the eigenvalues x = ±i from the companion matrix M (24 × 24) of
    ``A x² + B x + C`` ((A, B, C) = work): returns n, with M[:n, :n] holding the other eigenvalues.

    When the pivot is the joint of its group farthest from the eliminated one, its rotation is
    the outermost map of its side: the ``e^{iθ}`` part of the side has rank 4, and
    ``L(i) = C − A + iB`` is singular with four null vectors (the half-angle substitution's
    points at infinity, ``(1 + x²)⁴`` in the determinant); other readings have none, or fewer on
    special arms. Each null vector v = a + ib gives the eigenvectors ``(v, ±i v)`` of M, whose
    real span Z = ``[a, b; −b, a]`` is invariant (checked: ``M Z = Z Λ`` to 1e-12 of M's
    largest entry, with v of unit length). With p the rows of Z picked by Gauss–Jordan
    elimination with row pivoting, q the others and ``G = Z_q Z_p⁻¹`` (entries at most 1e4), the
    similarity ``S = [[I, 0], [G, I]]`` (in the order p, q) makes M block triangular:
    ``S⁻¹ M S = [[∗, ∗], [0, M_qq − G M_pq]]``, and that trailing block keeps the other
    eigenvalues (cost ∝ n³: 16 × 16 instead of 24 × 24 for four pairs; the similarity itself
    costs a few thousand operations). The null vectors come from :func:`_eliminate_i` (at most
    :data:`DEFLATE_MAX` used). Returns 24 with M untouched when L(i) is regular or a check
    fails."""
    n = 12
    Kr = np.empty((n, n))
    Ki = np.empty((n, n))
    perm = np.empty(n, dtype=np.int64)
    rank = _eliminate_i(work, Kr, Ki, perm)
    r = min(n - rank, DEFLATE_MAX)
    if r == 0:
        return 24
    # the null vectors (free unknown rank + t = 1, the others 0) by back-substitution, scaled to
    # |v| = 1, into Z (24 × 2r): the columns (a; −b) and (b; a) of each
    r2 = 2 * r
    Z = np.empty((24, r2))
    yr = np.empty(n)
    yi = np.empty(n)
    for t in range(r):
        f = rank + t
        for i in range(rank - 1, -1, -1):
            sr, si = -Kr[i, f], -Ki[i, f]
            for j in range(i + 1, rank):
                sr -= Kr[i, j] * yr[j] - Ki[i, j] * yi[j]
                si -= Kr[i, j] * yi[j] + Ki[i, j] * yr[j]
            dd = Kr[i, i] * Kr[i, i] + Ki[i, i] * Ki[i, i]
            yr[i] = (sr * Kr[i, i] + si * Ki[i, i]) / dd
            yi[i] = (si * Kr[i, i] - sr * Ki[i, i]) / dd
        for j in range(rank, n):
            yr[j] = 1.0 if j == f else 0.0
            yi[j] = 0.0
        nrm = 0.0
        for j in range(n):
            nrm += yr[j] * yr[j] + yi[j] * yi[j]
        nrm = 1.0 / math.sqrt(nrm)
        for j in range(n):  # v[perm[j]] = y[j]
            Z[perm[j], 2 * t] = Z[12 + perm[j], 2 * t + 1] = yr[j] * nrm
            Z[perm[j], 2 * t + 1] = yi[j] * nrm
            Z[12 + perm[j], 2 * t] = -yi[j] * nrm
    top = 1.0  # M's largest entry (its first rows: 0 and 1)
    for i in range(12, 24):
        for j in range(24):
            top = max(top, abs(M[i, j]))
    # the invariance check: M z = −z′ and M z′ = z for each pair (z, z′) (rows 0…11 hold exactly)
    worst = 0.0
    for i in range(12, 24):
        for c in range(r2):
            acc = -Z[i, c - 1] if c & 1 else Z[i, c + 1]
            for j in range(24):
                acc += M[i, j] * Z[j, c]
            worst = max(worst, abs(acc))
    if not worst <= 1e-12 * top:
        return 24
    # Gauss–Jordan on Z's columns with row pivoting: Z ← Z Z_p⁻¹, the identity on the pivot rows p
    # (used[i] = 1 + the column), G = Z_q Z_p⁻¹ on the others q
    used = np.zeros(24, dtype=np.int64)
    for c in range(r2):
        best, p = 0.0, -1
        for i in range(24):
            if used[i] == 0 and abs(Z[i, c]) > best:
                best, p = abs(Z[i, c]), i
        if p < 0:
            return 24
        used[p] = 1 + c
        inv = 1.0 / Z[p, c]
        for i in range(24):
            Z[i, c] *= inv
        for j in range(r2):
            fj = Z[p, j]
            if j == c or fj == 0.0:
                continue
            for i in range(24):
                Z[i, j] -= fj * Z[i, c]
    g = 0.0  # the similarity's size: G's largest entry
    for i in range(24):
        if used[i] == 0:
            for c in range(r2):
                g = max(g, abs(Z[i, c]))
    if not g <= 1e4:
        return 24
    # with S = [[I, 0], [G, I]] in the order (p, q): S⁻¹ M S = [[∗, ∗], [0, M_qq − G M_pq]]
    m = 24 - r2
    Mpq = np.empty((r2, m))
    for i in range(24):
        if used[i] != 0:
            b = 0
            for j in range(24):
                if used[j] == 0:
                    Mpq[used[i] - 1, b] = M[i, j]
                    b += 1
    H = np.empty((m, m))
    k = 0
    for i in range(24):
        if used[i] != 0:
            continue
        b = 0
        for j in range(24):
            if used[j] != 0:
                continue
            x = M[i, j]
            for c in range(r2):
                x -= Z[i, c] * Mpq[c, b]
            H[k, b] = x
            b += 1
        k += 1
    for i in range(m):
        for j in range(m):
            M[i, j] = H[i, j]
    return m


@njit
def turn(work: np.ndarray, t: float) -> None:
    """Turn the half-angle variable in place: ``x = (y + t)/(1 − t y)`` and the polynomial times
    ``(1 − t y)²`` give ``A′ y² + B′ y + C′`` with ``A′ = A − t B + t² C``,
    ``B′ = 2t A + (1 − t²) B − 2t C``, ``C′ = t² A + t B + C`` — the same roots, as angles, with
    the root at x = ∞ moved to y = −1/t."""
    for i in range(12):
        for j in range(12):
            a, b, c = work[0, i, j], work[1, i, j], work[2, i, j]
            work[0, i, j] = a - t * b + t * t * c
            work[1, i, j] = 2.0 * t * a + (1.0 - t * t) * b - 2.0 * t * c
            work[2, i, j] = t * t * a + t * b + c


@njit
def _perturb(A: np.ndarray) -> None:
    """Add a fixed, deterministic, well-conditioned matrix of norm ~1e-6 max|A| to A (12 × 12)."""
    big = 0.0
    for i in range(12):
        for j in range(12):
            big = max(big, abs(A[i, j]))
    if big == 0.0:
        big = 1.0
    for i in range(12):
        for j in range(12):
            A[i, j] += 1e-6 * big * ((1.0 if i == j else 0.0) + 0.3 * math.sin(1.0 + 12 * i + 7.0 * j))


@njit
def null_vector(work: np.ndarray, y: float, v: np.ndarray) -> None:
    """The null vector v (12,) of the (nearly) singular ``A y² + B y + C`` at a real eigenvalue
    y: inverse iteration (two LU solves); for |y| > 1 the matrix divided by y²."""
    L = np.empty((12, 12))
    big = abs(y) > 1.0
    y1 = 1.0 / y if big else y
    for i in range(12):
        for j in range(12):
            if big:
                L[i, j] = work[0, i, j] + work[1, i, j] * y1 + work[2, i, j] * y1 * y1
            else:
                L[i, j] = work[0, i, j] * y * y + work[1, i, j] * y + work[2, i, j]
    piv = np.empty(12, dtype=np.int64)
    _lu(L, piv)
    for i in range(12):
        v[i] = 1.0 / (1.0 + 0.1 * i)
    for _ in range(2):
        _lu_solve(L, piv, v)
        nrm = 0.0
        for i in range(12):
            nrm += v[i] * v[i]
        nrm = 1.0 / math.sqrt(nrm) if nrm > 0.0 and nrm < np.inf else 0.0
        for i in range(12):
            v[i] *= nrm


@njit
def polish(alpha: np.ndarray, a: np.ndarray, d: np.ndarray, T06: np.ndarray, theta: np.ndarray,
           iters: int) -> float:
    """Newton–Raphson on the pose error (geometric Jacobian of ``Z₁X₁ ⋯ Z₆``, space frame).

    The step is the least-squares solution of ``J Δθ = e``: by LU when J is well conditioned
    (σ_min > 1e-10 σ_max for sure), else by the SVD with singular values below 1e-12 σ_max
    dropped (numpy's ``lstsq`` with ``rcond=1e-12``). Updates theta (6,) in place; returns the
    final ‖(Δp, Δω)‖ (a step that does not lower the error is not taken).
    """
    T = np.empty((4, 4))
    e = np.empty(6)
    J = np.empty((6, 6))
    W = np.empty((6, 6))
    U = np.empty((6, 6))
    V = np.empty((6, 6))
    sv = np.empty(6)
    dq = np.empty(6)
    piv = np.empty(6, dtype=np.int64)
    fk_pose(alpha, a, d, theta, T)
    err = _pose_error(T06, T, e)
    trial = np.empty(6)
    for _ in range(iters):
        if err < 1e-15:
            break
        jacobian(alpha, a, d, theta, T, J)
        W[:, :] = J
        if _well_conditioned(W, 1e-10):
            for i in range(6):
                dq[i] = e[i]
            _lu(J, piv)
            _lu_solve(J, piv, dq)
        else:
            _svd_jacobi(J, sv, U, V)
            for i in range(6):
                dq[i] = 0.0
            for j in range(6):
                if not sv[j] > 1e-12 * sv[0]:
                    continue
                ue = 0.0
                for i in range(6):
                    ue += U[i, j] * e[i]
                ue /= sv[j]
                for i in range(6):
                    dq[i] += V[i, j] * ue
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


# ---------------------------------------------------------------- one reading, one pose, one call
# The per-arm tables of one reading of the loop equation (robokit.ik.general_6r._Arrangement):
# ri (47,) int: roles (6: pivot, b, c, d, e, eliminated joint), three_has_w, nw (joints on the
#   target's side), w_index, w_inverse, perm3 (27), perm2 (9), deflate (the null space of
#   A x² + B x + C at x = i, its dimension at ordinary poses: 0 means no deflation is tried);
# mats (6, 15, 15): the target side's maps Ms[0 … nw] (slot w_index replaced per pose), pre, post;
# const (27, 15): the side without the target as its tensor (3**(5 − nw) rows used);
# vec (18,): signs (3; nw used), f (15) the target side's start vector.
# The solver's numbers, tol (8,): gamma, t (the turn of the variable, tan(δ/2)), imag_tol,
# converged, same, x0, poor, and the number of readings; chain (4, 6): α (5), a (5), d, θ₀.
RI_SIZE = 47
T_GAMMA, T_TURN, T_IMAG, T_CONVERGED, T_SAME, T_X0, T_POOR, T_READINGS = 0, 1, 2, 3, 4, 5, 6, 7


@njit
def reading_matrices(T06s: np.ndarray, ri: np.ndarray, mats: np.ndarray, const: np.ndarray, vec: np.ndarray,
                     P: np.ndarray, r: np.ndarray) -> None:
    """P (3, 15, 9), the three-joint side with the pivot first, and r (15, 9), the two-joint side,
    of one reading for the scaled target T06s (see :func:`pencil` and the tables above)."""
    nw = ri[7]
    FW = np.empty((15, 15))
    f_pose(T06s, ri[9] == 0, FW)  # W = T₀₆⁻¹: its map, or T₀₆'s for W⁻¹
    Ms = mats[:nw + 1].copy()
    Ms[ri[8]] = (mats[4] @ FW) @ mats[5]  # pre F(W) post
    Gw = np.empty((3 ** nw, 15))
    side_tensor(Ms, vec[:nw].copy(), vec[3:18].copy(), Gw)
    three_has_w = ri[6] != 0
    for i in range(3):
        for k in range(15):
            for m in range(9):
                row = ri[10 + i * 9 + m]
                P[i, k, m] = Gw[row, k] if three_has_w else const[row, k]
    for k in range(15):
        for m in range(9):
            row = ri[37 + m]
            r[k, m] = const[row, k] if three_has_w else Gw[row, k]


@njit
def _reading_pencil(T06s: np.ndarray, ri: np.ndarray, mats: np.ndarray, const: np.ndarray, vec: np.ndarray,
                    gamma: float, work: np.ndarray, Np: np.ndarray, Pinv: np.ndarray) -> float:
    """:func:`pencil` of one reading for the pose T06s (both sides built by :func:`reading_matrices`)."""
    P = np.empty((3, 15, 9))
    r = np.empty((15, 9))
    reading_matrices(T06s, ri, mats, const, vec, P, r)
    return pencil(P, r, math.cos(gamma), math.sin(gamma), work, Np, Pinv)


@njit
def score_reading(T06s: np.ndarray, ri: np.ndarray, mats: np.ndarray, const: np.ndarray, vec: np.ndarray,
                  gamma: float, x0: float) -> float:
    """How well one reading solves the pose T06s: the smaller of σ_min/σ_max of its 14 × 8
    matrix Q and of its pencil at x0 (used once per arm to rank the 36 readings)."""
    work = np.empty((3, 12, 12))
    ratio = _reading_pencil(T06s, ri, mats, const, vec, gamma, work, np.empty((3, 14, 9)), np.empty((8, 14)))
    return min(ratio, regularity(work, x0))


@njit
def reading_candidates(chain: np.ndarray, tol: np.ndarray, T06s: np.ndarray, ri: np.ndarray, mats: np.ndarray,
                       const: np.ndarray, vec: np.ndarray, out: np.ndarray, start: int) -> tuple[int, float]:
    """The polished rotation angles θ (6,) of the solutions for the scaled target T06s with one
    reading, into the rows start, start + 1, … of out: (how many, the conditioning figure — the
    smallest σ_min/σ_max of Q, of A and of the pencil at x0; 0 when the eigenvalue iteration did
    not converge, so that the pose is also solved with the next readings)."""
    alpha, a, d = chain[0, :5], chain[1, :5], chain[2]
    gamma, t = tol[T_GAMMA], tol[T_TURN]
    work = np.empty((3, 12, 12))
    Np = np.empty((3, 14, 9))
    Pinv = np.empty((8, 14))
    rq = _reading_pencil(T06s, ri, mats, const, vec, gamma, work, Np, Pinv)
    M = np.empty((24, 24))
    condA = companion(work, M)
    reg = regularity(work, tol[T_X0])
    turned = False
    if not condA > 1e-10:
        # A near singular (a root near the half-angle's point at infinity): the variable is turned
        # by a fixed angle, which gives the same roots with a regular leading matrix
        turn(work, t)
        turned = True
        if not companion(work, M) > 1e-10:
            # singular in both variables: det(A x² + B x + C) vanishes identically (the pose has a
            # continuum of solutions for this reading). The eigenvalues of a slightly perturbed
            # pencil are then used as candidates: its regular part's roots (moved by the
            # perturbation, polished back) and points where the continuum meets the perturbation
            _perturb(work[0])
            if not companion(work, M) > 1e-10:
                return 0, 0.0
    ratio = min(rq, condA, reg)
    # the roots x = ±i of the half-angle substitution (pivot outermost: four pairs) removed first
    n = deflate(work, M) if ri[46] > 0 else 24
    H = np.ascontiguousarray(M[:n, :n]) if n < 24 else M
    wr = np.empty(n)
    wi = np.empty(n)
    if eigenvalues(H, wr, wi) != 0:
        # the QR iteration did not converge (a cluster of equal roots that every pose of the arm
        # has for this reading, e.g. the xArm 6's with θ₃ as the eigenvalue): no candidates, and
        # the figure 0 so that the pose is solved with the next readings too
        return 0, 0.0
    roles = ri[:6]
    v = np.empty(12)
    th = np.empty(6)
    count = 0
    for k in range(n):
        lam = wr[k]
        imag = 2.0 * abs(wi[k]) / (1.0 + lam * lam + wi[k] * wi[k])
        if imag > tol[T_IMAG]:  # not real to the tolerance (as an angle): no candidate
            continue
        phi = 2.0 * math.atan2(lam + t, 1.0 - t * lam) if turned else 2.0 * math.atan(lam)
        null_vector(work, lam, v)
        err = _candidate(alpha, a, d, T06s, v.reshape((4, 3)), phi, Np, Pinv, roles, gamma, th)
        if err < tol[T_CONVERGED]:
            for i in range(6):
                out[start + count, i] = th[i]
            count += 1
    return count, ratio


@njit
def solve_pose(chain: np.ndarray, tol: np.ndarray, ri: np.ndarray, mats: np.ndarray, const: np.ndarray,
               vec: np.ndarray, T06s: np.ndarray, out: np.ndarray) -> int:
    """Every solution of the general 6R arm for the scaled target T06s (4, 4) in one call: the best
    reading, and when the pose is badly conditioned for it (figure below ``poor``) the next ones
    too; duplicates merged; ordered by q₃, then q₁, q₂, q₄, q₅, q₆. Writes rows
    ``(q (6) = θ − θ₀ wrapped to [−π, π), singular)`` into out (24 × readings, 7) and returns
    how many (0 for a target that is not finite). ``singular``: near a badly conditioned pose,
    1.0 where the 6 × 6 Jacobian is singular (σ_min < 1e-8 σ_max).

    ri, mats, const, vec: the readings' tables, best first (leading axis; see above)."""
    for i in range(3):
        for j in range(4):
            if not abs(T06s[i, j]) < np.inf:
                return 0
    nread = int(tol[T_READINGS])
    TH = np.empty((24 * nread, 6))
    n = 0
    ratio = 1.0
    for k in range(nread):  # the best reading; on a badly conditioned pose (near a singular one) the next ones too
        if k > 0 and not ratio < tol[T_POOR]:
            break
        more, figure = reading_candidates(chain, tol, T06s, ri[k], mats[k], const[k], vec[k], TH, n)
        if k == 0:
            ratio = figure
        n += more
    poor = ratio < tol[T_POOR]
    th0 = chain[3]
    Q = np.empty((max(n, 1), 6))
    m = distinct(TH, n, th0, tol[T_SAME], Q)
    tmp = np.empty(6)
    for i in range(1, m):  # ordered by q₃, then q₁, q₂, q₄, q₅, q₆ (a stable insertion sort)
        for c in range(6):
            tmp[c] = Q[i, c]
        j = i - 1
        while j >= 0 and _before(tmp, Q[j]):
            for c in range(6):
                Q[j + 1, c] = Q[j, c]
            j -= 1
        for c in range(6):
            Q[j + 1, c] = tmp[c]
    T = np.empty((4, 4))
    J = np.empty((6, 6))
    t6 = np.empty(6)
    for i in range(m):
        singular = False
        if poor:  # near a singular pose: flag the solutions where the Jacobian is singular
            for c in range(6):
                t6[c] = Q[i, c] + th0[c]
            fk_pose(chain[0, :5], chain[1, :5], chain[2], t6, T)
            jacobian(chain[0, :5], chain[1, :5], chain[2], t6, T, J)
            singular = sv_ratio(J) < 1e-8
        for c in range(6):
            out[i, c] = Q[i, c]
        out[i, 6] = 1.0 if singular else 0.0
    return m


@njit
def _before(x: np.ndarray, y: np.ndarray) -> bool:
    """Whether row x comes before row y: by q₃, then q₁, q₂, q₄, q₅, q₆."""
    for c in (2, 0, 1, 3, 4, 5):
        if x[c] < y[c]:
            return True
        if x[c] > y[c]:
            return False
    return False
