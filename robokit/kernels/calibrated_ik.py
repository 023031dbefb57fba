r"""Exact IK of a calibrated (or nearly special) arm in compiled code: the closed form of the
nearest arm of the nominal structure gives one start per branch, Newton's method on the arm's own
product of exponentials finishes each one.

The arm's kinematics is its PoE, ``T(q) = e^{[S₁]q₁} ⋯ e^{[S₆]q₆} M``. Its nominal structure (a
spherical wrist, or three parallel axes) is broken by small errors, so the closed forms of
:mod:`robokit.kernels.closed_form` do not apply to it; they do apply to the *projected* arm, the
same arm with the structure restored (:mod:`robokit.ik.calibrated` builds it and packs its
constants ``Kn``). Per pose:

1. every closed-form solution of the projected arm (:func:`robokit.kernels.closed_form.pieper_solve_into`
   or ``parallel_axes_solve_into``): one start per branch, its branch code and degenerate flag; when
   it gives fewer than ``GENERIC_ROWS``, also those of the pose moved toward and away from the
   shoulder by the ``RELAX`` fractions of the reach, for the branches it lacks (the projected arm's
   workspace boundary is not quite the arm's);
2. each start is polished by :func:`polish`: Newton's method on the first-order spatial pose error
   (:func:`_error`) with the space Jacobian, both from
   :func:`robokit.kernels.ik.fk_and_space_jacobian` (the FK and Jacobian of the compiled numerical
   IK), Levenberg–Marquardt steps where a Newton step fails, until the orientation error (rad) and
   the position error (m) are below ``tol_stop``; a start whose polish ends above ``tol_accept``
   has no solution near it;
3. a start that reached a solution already found (two branches converging to one root), or none,
   is tried once more from its start mirrored through the point the polish reached
   (``2 q₀ − q``): near a fold, where two roots of the arm approach each other, the second root
   lies on the other side of the start;
4. around a solution the polish moved farther than ``EXPLORE``, a merged or vanished branch and a
   singular choice of the nominal, where the arm's Jacobian has a singular value below
   ``SIGMA_EXPLORE`` (:func:`_null_direction`), the roots along the near-null direction are searched
   from the ``EXPLORE_STEPS`` (the real arm can have more roots there than the nominal structure);
5. the outcome of every branch is written to ``branches``: a distinct solution, merged into an
   earlier solution (that solution is flagged degenerate), or vanished (no exact solution of the
   arm near that branch: the two roots of a fold became complex);
6. the solutions are wrapped, shifted into wide limits, flagged and written as the closed-form
   kernels write theirs (:func:`robokit.kernels.closed_form._finish_into`).

Solutions are distinct to ``SAME`` (rad or m, angles modulo 2π): two polished roots closer than
that are one root (near a fold Newton's method converges to a double root only to about the
square root of the precision).

Example (``AnalyticIK`` builds the arguments; ``ik_analytic`` calls these kernels)::

    >>> import numpy as np, robokit
    >>> from robokit.ik.closed_form import AnalyticIK
    >>> arm = AnalyticIK(calibrated_robot).calibrated   # doctest: +SKIP
    >>> n = calibrated_solve_into(arm._Kn, arm._kind, arm.M, arm.Slist, arm._post_q, T, 0.0,
    ...                           arm.shoulder, arm.reach, 1e-12, 1e-10, 30, out, branches)  # doctest: +SKIP
"""
from __future__ import annotations

import math

import numpy as np

from robokit.kernels._jit import njit, prange
from robokit.kernels import closed_form as _cf
from robokit.kernels.dynamics import cholesky_solve
from robokit.kernels.ik import fk_and_space_jacobian, normal_equations

__all__ = ["polish", "calibrated_solve_into", "calibrated_batch", "SAME", "BRANCH_COLS", "SOLUTION", "MERGED",
           "VANISHED"]

#: Two polished solutions closer than this (rad or m, angles modulo 2π) are one solution.
SAME = 1e-7
#: Per-branch outcome codes written to ``branches[:, 1]``.
SOLUTION, MERGED, VANISHED = 0, 1, 2
#: Branches of the nominal structure in general position (both structures: 4 positions × 2 wrists).
GENERIC_ROWS = 8
#: When the projected arm's closed form gives fewer branches, it is also solved for the pose moved
#: toward (f < 0) or away from (f > 0) the shoulder by these fractions of the reach: the starts of
#: branches that the projected arm just cannot reach but the arm itself can (near the workspace's
#: outer or inner boundary).
RELAX = (-2e-3, 2e-3, -6e-3, 6e-3, -2e-2, 2e-2)
#: No Newton step moves a joint more than this (rad, m): far from a root the linear model is not trusted.
MAX_STEP = 0.5
#: A polish that moved a joint farther than this (rad or m) from its start was near a singular pose:
#: the roots along the arm's near-singular direction there are searched too.
EXPLORE = 0.1
#: ... when the arm's Jacobian there (velocity rows divided by the reach) has a singular value below this.
SIGMA_EXPLORE = 0.02
#: Newton steps at most from each start of that search.
EXPLORE_MAX_STEPS = 25
#: The starts of that search: the point plus these multiples of π/4 (in the largest joint) along
#: the near-singular direction.
EXPLORE_STEPS = (0.1, -0.1, 0.3, -0.3, 1.0, -1.0, 2.0, -2.0, 3.0, -3.0, 4.0)
#: Columns of ``branches``: branch code, outcome, index of the solution (−1 if vanished),
#: orientation error (rad), position error (m) at the end of the polish.
BRANCH_COLS = 5


@njit
def _error(T: np.ndarray, Td: np.ndarray, F: np.ndarray) -> tuple[float, float, float]:
    """F ← (ω, v), the spatial twist that moves T to Td, to first order: ``ω = vee(A − Aᵀ)/2`` with
    ``A = R_d Rᵀ`` (sin θ times the axis), ``v = Δp − ω × p`` with ``Δp = p_d − p`` (p moves with
    ``v + ω × p``). F is zero exactly when T = Td (for an orientation error below π/2) and its
    derivative there is the space Jacobian's, so Newton's method with J_s converges quadratically.
    Returns (½(‖ω‖² + ‖Δp‖²), ‖ω‖ (rad, or 2 − ‖ω‖ beyond π/2), ‖Δp‖ (m))."""
    a01 = Td[0, 0] * T[1, 0] + Td[0, 1] * T[1, 1] + Td[0, 2] * T[1, 2]
    a10 = Td[1, 0] * T[0, 0] + Td[1, 1] * T[0, 1] + Td[1, 2] * T[0, 2]
    a02 = Td[0, 0] * T[2, 0] + Td[0, 1] * T[2, 1] + Td[0, 2] * T[2, 2]
    a20 = Td[2, 0] * T[0, 0] + Td[2, 1] * T[0, 1] + Td[2, 2] * T[0, 2]
    a12 = Td[1, 0] * T[2, 0] + Td[1, 1] * T[2, 1] + Td[1, 2] * T[2, 2]
    a21 = Td[2, 0] * T[1, 0] + Td[2, 1] * T[1, 1] + Td[2, 2] * T[1, 2]
    wx, wy, wz = 0.5 * (a21 - a12), 0.5 * (a02 - a20), 0.5 * (a10 - a01)
    px, py, pz = T[0, 3], T[1, 3], T[2, 3]
    dx, dy, dz = Td[0, 3] - px, Td[1, 3] - py, Td[2, 3] - pz
    F[0], F[1], F[2] = wx, wy, wz
    F[3] = dx - (wy * pz - wz * py)
    F[4] = dy - (wz * px - wx * pz)
    F[5] = dz - (wx * py - wy * px)
    tr = 0.0  # trace of A = Σ R_d ∘ R: below 1 beyond π/2, where ‖ω‖ = sin θ falls again
    for r in range(3):
        for c in range(3):
            tr += Td[r, c] * T[r, c]
    rot = math.sqrt(wx * wx + wy * wy + wz * wz)
    if tr < 1.0:
        rot = 2.0 - rot
    pos = math.sqrt(dx * dx + dy * dy + dz * dz)
    return 0.5 * (rot * rot + pos * pos), rot, pos


@njit
def _newton_step(J: np.ndarray, F: np.ndarray, A: np.ndarray, x: np.ndarray) -> bool:
    """x ← J⁻¹ F (6 × 6) by Gaussian elimination with partial pivoting on the copy A; False when a
    pivot is below 1e-12 of the largest entry (J singular for this purpose)."""
    big = 0.0
    for r in range(6):
        for c in range(6):
            A[r, c] = J[r, c]
            big = max(big, abs(J[r, c]))
        x[r] = F[r]
    if not big > 0.0:
        return False
    for c in range(6):
        p = c
        for r in range(c + 1, 6):
            if abs(A[r, c]) > abs(A[p, c]):
                p = r
        if abs(A[p, c]) <= 1e-12 * big:
            return False
        if p != c:
            for k in range(6):
                A[c, k], A[p, k] = A[p, k], A[c, k]
            x[c], x[p] = x[p], x[c]
        for r in range(c + 1, 6):
            f = A[r, c] / A[c, c]
            for k in range(c, 6):
                A[r, k] -= f * A[c, k]
            x[r] -= f * x[c]
    for r in range(5, -1, -1):
        acc = x[r]
        for k in range(r + 1, 6):
            acc -= A[r, k] * x[k]
        x[r] = acc / A[r, r]
    return True


@njit
def polish(M: np.ndarray, Slist: np.ndarray, Td: np.ndarray, q: np.ndarray, tol_stop: float, max_steps: int,
           W: np.ndarray, J: np.ndarray, V: np.ndarray) -> tuple[float, float, int]:
    """Newton's method on the pose error :func:`_error` of the PoE ``(M, Slist)`` with its space
    Jacobian (:func:`robokit.kernels.ik.fk_and_space_jacobian`), q (6,) updated in place; a step
    that does not lower the error, or a singular Jacobian, switches to Levenberg–Marquardt
    (damping λ times the largest diagonal entry of JᵀJ, λ from 1e-9, ×10 on failure, ÷10 on
    success, back to Newton below 1e-9); no step moves a joint more than ``MAX_STEP``. Stops when the
    orientation error (rad) and the position error (m) are below ``tol_stop``. Returns (orientation
    error, position error, FK evaluations). Scratch: W (5, 4, 4), J (5, 6, 6), V (4, 6)."""
    n = Slist.shape[1]
    P, E, tmp = W[2], W[3], W[4]
    H, L = J[2], J[3]
    g, step = V[2], V[3]
    trial = np.empty(6)
    cur = 0  # W[cur], J[cur], V[cur]: the current iterate's pose, Jacobian and error; 1 − cur: the trial's
    fk_and_space_jacobian(M, Slist, q, W[0], J[0], P, E, tmp)
    err, rot, pos = _error(W[0], Td, V[0])
    lam = 0.0  # 0: Newton; else the damping, relative to the largest diagonal entry of Jᵀ J
    evals = 1
    for _ in range(max_steps):
        if rot < tol_stop and pos < tol_stop:
            break
        Jc, F = J[cur], V[cur]
        solved = lam == 0.0 and _newton_step(Jc, F, J[4], step)
        if not solved:
            if lam == 0.0:
                lam = 1e-9
            normal_equations(Jc, F, H, g)  # (Jᵀ J + λ d I) Δq = Jᵀ F,  d = max diag(Jᵀ J)
            big = 0.0
            for i in range(n):
                big = max(big, H[i, i])
            for i in range(n):
                H[i, i] += lam * big
            if not cholesky_solve(H, g, L, step):
                lam *= 10.0
                if lam > 1e3:
                    break
                continue
        longest = 0.0  # a step longer than MAX_STEP (rad, m) is shortened: Newton's model is local
        for i in range(n):
            longest = max(longest, abs(step[i]))
        shrink = MAX_STEP / longest if longest > MAX_STEP else 1.0
        for i in range(n):
            trial[i] = q[i] + shrink * step[i]
        nxt = 1 - cur
        fk_and_space_jacobian(M, Slist, trial, W[nxt], J[nxt], P, E, tmp)
        evals += 1
        e2, r2, p2 = _error(W[nxt], Td, V[nxt])
        if e2 < err:
            for i in range(n):
                q[i] = trial[i]
            cur = nxt
            err, rot, pos = e2, r2, p2
            if lam > 0.0:
                lam = lam * 0.1 if lam > 1e-9 else 0.0
        else:
            lam = 1e-9 if lam == 0.0 else lam * 10.0
            if lam > 1e3:
                break
    return rot, pos, evals


@njit
def _same(a: np.ndarray, b: np.ndarray, rev: np.ndarray) -> bool:
    for j in range(6):
        d = a[j] - b[j]
        if rev[j] != 0.0:
            d = _cf._rem(d)
        if d >= SAME or d <= -SAME:
            return False
    return True


@njit
def _find(q: np.ndarray, Q: np.ndarray, n: int, rev: np.ndarray) -> int:
    for k in range(n):
        if _same(q, Q[k], rev):
            return k
    return -1


@njit
def _null_direction(M: np.ndarray, Slist: np.ndarray, q: np.ndarray, reach: float, W: np.ndarray, J: np.ndarray,
                    V: np.ndarray, v: np.ndarray) -> float:
    """v ← the unit joint direction along which the arm's Jacobian at q is closest to singular:
    inverse iteration (4 steps from (1, …, 1)) on ``H = J̃ᵀJ̃ + 1e-12 I``, J̃ the space Jacobian with its
    velocity rows divided by the reach (m), so both halves are rad-like. Returns the estimate
    ``√(vᵀHv)`` of J̃'s smallest singular value (0 when H is not positive definite)."""
    n = Slist.shape[1]
    Jc, H, L = J[0], J[2], J[3]
    fk_and_space_jacobian(M, Slist, q, W[0], Jc, W[2], W[3], W[4])
    for r in range(3, 6):
        for c in range(n):
            Jc[r, c] /= reach
    x = V[2]
    for i in range(n):
        v[i] = 1.0
    normal_equations(Jc, v, H, x)  # H = J̃ᵀJ̃ (x is overwritten below)
    for i in range(n):
        H[i, i] += 1e-12
    for _ in range(4):
        if not cholesky_solve(H, v, L, x):
            return 0.0
        norm = 0.0
        for i in range(n):
            norm += x[i] * x[i]
        norm = math.sqrt(norm)
        for i in range(n):
            v[i] = x[i] / norm
    rq = 0.0
    for i in range(n):
        for j in range(n):
            rq += v[i] * H[i, j] * v[j]
    return math.sqrt(max(rq, 0.0))


@njit
def _nominal_rows(Kn: np.ndarray, method: int, T: np.ndarray, wrist_ref: float, out: np.ndarray) -> int:
    if method == _cf.PIEPER:
        return _cf.pieper_solve_into(Kn, T, wrist_ref, out)
    return _cf.parallel_axes_solve_into(Kn, T, wrist_ref, out)


@njit
def calibrated_solve_into(Kn: np.ndarray, method: int, M: np.ndarray, Slist: np.ndarray, post_q: np.ndarray,
                          T: np.ndarray, wrist_ref: float, shoulder: np.ndarray, reach: float, tol_stop: float,
                          tol_accept: float, max_steps: int, out: np.ndarray, branches: np.ndarray) -> int:
    """Every solution of the arm ``(M, Slist)`` for the tip pose T (module docstring).

    Kn: the projected arm's packed closed-form constants; method: ``closed_form.PIEPER`` or
    ``PARALLEL_AXES``; post_q (5, 6): the arm's revolute flags and limits as in
    :func:`robokit.kernels.closed_form.pack_constants` (row 0, the signs, is not used);
    wrist_ref: the free joint's value at a singularity, in the sign of the projected arm's
    solver. Writes the solutions into ``out`` (MAX_ROWS, OUT_COLS) as the closed-form kernels do
    and each branch's outcome into ``branches`` (MAX_ROWS, BRANCH_COLS); returns the number of
    solutions, −1 when T fails the quick rigid-transform test."""
    nom = np.empty((_cf.MAX_ROWS, _cf.OUT_COLS))
    m = _nominal_rows(Kn, method, T, wrist_ref, nom)
    if m < 0:
        return m
    if m < GENERIC_ROWS:  # a branch missing: near the projected arm's workspace boundary, say; relaxed poses
        Tr = np.empty((4, 4))
        extra = np.empty((_cf.MAX_ROWS, _cf.OUT_COLS))
        for f in RELAX:
            for r in range(4):
                for c in range(4):
                    Tr[r, c] = T[r, c]
            dist = math.sqrt((T[0, 3] - shoulder[0]) ** 2 + (T[1, 3] - shoulder[1]) ** 2 + (T[2, 3] - shoulder[2]) ** 2)
            if dist == 0.0:
                continue
            for r in range(3):
                Tr[r, 3] = T[r, 3] + f * reach * (T[r, 3] - shoulder[r]) / dist
            me = _nominal_rows(Kn, method, Tr, wrist_ref, extra)
            for k in range(me):
                have = False
                for r in range(m):
                    if nom[r, 7] == extra[k, 7]:
                        have = True
                        break
                if not have and m < _cf.MAX_ROWS:
                    for c in range(_cf.OUT_COLS):
                        nom[m, c] = extra[k, c]
                    nom[m, 8] = 2.0  # a start from a relaxed pose: its solution is flagged degenerate
                    m += 1
    rev = post_q[1]
    W = np.empty((5, 4, 4))
    J = np.empty((5, 6, 6))
    V = np.empty((4, 6))
    Td = np.ascontiguousarray(T)
    rows = np.empty((_cf.MAX_ROWS, 6))
    rcodes = np.empty((_cf.MAX_ROWS, 3), dtype=np.int64)
    rdegen = np.zeros(_cf.MAX_ROWS, dtype=np.bool_)
    q = np.empty(6)
    q2 = np.empty(6)
    ns = 0
    # the points to explore around (near a singular pose): a solution the polish moved far from its
    # start, a branch that vanished (the point its polish reached), a singular choice of the nominal
    seeds = np.empty((_cf.MAX_ROWS, 6))
    seed_code = np.empty(_cf.MAX_ROWS, dtype=np.int64)
    nseed = 0
    for r in range(m):
        relaxed = nom[r, 8] == 2.0
        for j in range(6):
            q[j] = nom[r, j]
        rot, pos, _ = polish(M, Slist, Td, q, tol_stop, EXPLORE_MAX_STEPS if relaxed else max_steps, W, J, V)
        moved = 0.0
        for j in range(6):
            moved = max(moved, abs(q[j] - nom[r, j]))
        ok = rot < tol_accept and pos < tol_accept
        k = _find(q, rows, ns, rev) if ok else -1
        degen = nom[r, 8] != 0.0
        if not ok or k >= 0:  # a root found already, or none: once more from the mirrored start
            for j in range(6):
                q2[j] = 2.0 * nom[r, j] - q[j]
            rot2, pos2, _ = polish(M, Slist, Td, q2, tol_stop, EXPLORE_MAX_STEPS if relaxed else max_steps, W, J, V)
            if rot2 < tol_accept and pos2 < tol_accept and _find(q2, rows, ns, rev) < 0:
                for j in range(6):
                    q[j] = q2[j]
                rot, pos, ok, k, degen = rot2, pos2, True, -1, True
            elif not ok and rot2 < tol_accept and pos2 < tol_accept:
                k = _find(q2, rows, ns, rev)
                rot, pos, ok = rot2, pos2, True
        code = int(nom[r, 7])
        # searched around: a solution the polish moved far, merging branches, a singular choice of the
        # nominal, a branch that vanished (not one from a relaxed pose: that pose may be out of reach)
        if moved > EXPLORE or k >= 0 or (degen and not relaxed) or (not ok and not relaxed):
            for j in range(6):
                seeds[nseed, j] = q[j]
            seed_code[nseed] = code
            nseed += 1
        branches[r, 0] = code
        branches[r, 3] = rot
        branches[r, 4] = pos
        if ok and k < 0:
            for j in range(6):
                rows[ns, j] = q[j]
            rcodes[ns, 0] = code // 100
            rcodes[ns, 1] = (code // 10) % 10
            rcodes[ns, 2] = code % 10
            rdegen[ns] = degen
            branches[r, 1] = SOLUTION
            branches[r, 2] = ns
            ns += 1
        elif ok:  # two branches reach one root: the branches merge here
            rdegen[k] = True
            branches[r, 1] = MERGED
            branches[r, 2] = k
        else:
            branches[r, 1] = VANISHED
            branches[r, 2] = -1
    v = np.empty(6)
    for k in range(nseed):  # every root along the arm's near-singular direction there
        if _null_direction(M, Slist, seeds[k], reach, W, J, V, v) > SIGMA_EXPLORE:
            continue  # not near a singular configuration: no other root nearby to look for
        big = 0.0
        for j in range(6):
            big = max(big, abs(v[j]))
        for step in EXPLORE_STEPS:
            if ns == _cf.MAX_ROWS:
                break
            for j in range(6):
                q[j] = seeds[k, j] + step * (0.25 * math.pi / big) * v[j]
            rot, pos, _ = polish(M, Slist, Td, q, tol_stop, EXPLORE_MAX_STEPS, W, J, V)
            if rot < tol_accept and pos < tol_accept and _find(q, rows, ns, rev) < 0:
                for j in range(6):
                    rows[ns, j] = q[j]
                code = seed_code[k]
                rcodes[ns, 0] = code // 100
                rcodes[ns, 1] = (code // 10) % 10
                rcodes[ns, 2] = code % 10
                rdegen[ns] = True
                ns += 1
    ci = np.zeros(6, dtype=np.int64)  # not reversed: the starts are in the robot's own joints already
    return _cf._finish_into(ci, post_q, rows, rcodes, rdegen, ns, out)


@njit(parallel=True)
def calibrated_batch(Kn: np.ndarray, method: int, M: np.ndarray, Slist: np.ndarray, post_q: np.ndarray,
                     Ts: np.ndarray, wrist_ref: float, shoulder: np.ndarray, reach: float, tol_stop: float,
                     tol_accept: float,
                     max_steps: int) -> tuple[np.ndarray, np.ndarray]:
    """:func:`calibrated_solve_into` over (N, 4, 4) poses, in parallel over the poses: (out (N,
    MAX_ROWS, OUT_COLS) with NaN rows past each count, counts (N,))."""
    N = Ts.shape[0]
    out = np.full((N, _cf.MAX_ROWS, _cf.OUT_COLS), np.nan)
    counts = np.zeros(N, dtype=np.int64)
    for i in prange(N):
        branches = np.empty((_cf.MAX_ROWS, BRANCH_COLS))
        counts[i] = calibrated_solve_into(Kn, method, M, Slist, post_q, Ts[i], wrist_ref, shoulder, reach,
                                          tol_stop, tol_accept, max_steps, out[i], branches)
    return out, counts
