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
   shoulder point, from joint 1's axis, or both (``RELAX_MOVES``, fractions of the reach), for the
   branches it lacks (the projected arm's workspace boundary is not quite the arm's) — except the relaxed poses :func:`_relax_mask` shows
   cannot add one (Pieper's general case: the labels of the positions at a relaxed pose, from the
   position quartic's real roots, are all sure and present already, or their wrist cannot reach the
   orientation; three parallel axes: the labels of a relaxed pose's branches, from
   :func:`_parallel_codes`, are all sure and present already); a relaxed pose's rows are computed
   only where that is not shown, and finished (wrapped, de-duplicated) only when they hold a
   branch the starts lack; and, Pieper's method only, the **fold starts** of the pose itself
   (``closed_form.FOLD_STARTS``, ``FOLD_IMAG``): where the projected arm just has no root — a
   position whose oblique wrist misses the orientation by |cos θ₅| − 1 ≤ 0.1, two starts at θ₅ =
   ±√(2 (|cos θ₅| − 1)) from the wrist's fold; a complex pair of the joint-3 quartic within 0.2 rad
   of the real line, a position at its real part — the arm itself may have two roots there
   (measured on 3,600 random poses of the benchmark's random Pieper arm: a 500-start sweep found 49
   roots this path missed without these starts, none with them). They
   are polished after every other start (as the relaxed poses' starts: more steps, a solution
   flagged degenerate and searched around), their labels do not stand for a branch the relaxed
   poses need not supply, and one that finds no new root is no branch (not merged, not vanished);
2. each start is polished by :func:`polish` (the sines and cosines of the starts' joint values, which
   branches share, computed once: :func:`_start_trig`): Newton's method with a second-order correction
   (:func:`_newton_step`: the pose error after a step is O(d³) rather than O(d²), so the closed
   form's starts, about 5e-3 off, reach 1e-15 in two steps rather than three) on the spatial pose
   error (:func:`_error`, the logarithm of the error transform to second order near the target)
   with the space Jacobian, both from :func:`fk_jacobian` (one pass through the packed chain of
   :func:`pack_arm`), the Jacobian factored by 3 × 3 blocks (:func:`_block_factor`, else 6 × 6
   with pivoting), Levenberg–Marquardt steps where a step fails (the normal equations of
   :mod:`robokit.kernels.ik`), until the orientation error (rad) and the position error (m) are
   below ``tol_stop``; a start whose polish ends above ``tol_accept`` has no solution near it;
3. a start that reached a solution already found (two branches converging to one root), or none,
   is tried once more from its start mirrored through the point the polish reached
   (``2 q₀ − q``): near a fold, where two roots of the arm approach each other, the second root
   lies on the other side of the start; where the first polish failed and the mirrored start reached a
   new root, the point where the first one stalled (in the error's valley near a singular
   configuration, along which the arm's other roots there lie) is a search point, that root not
   (while rows are free past the starts: one per such point in the generated C);
4. the near-singular search (the real arm can have more roots there than the nominal structure):
   its points are the solutions the polish moved farther than ``EXPLORE``, merged or vanished
   branches, singular choices of the nominal, and — where the pose is near singular — every
   branch's solution (the first one not searched already is checked, first by a cheap lower bound
   of its smallest singular value, :func:`_sigma_bound`; the others where it, or a search point,
   was near singular: near a singular position of a wrist-partitioned arm every branch is). At
   each point where the arm's Jacobian has a singular value below ``SIGMA_EXPLORE``
   (:func:`_null_direction`): polishes from the ``EXPLORE_STEPS`` along the near-null direction,
   then the curve along which the arm almost reaches the pose is followed both ways from every
   such point (:func:`_trace`) and polished where the error is least along it (measured on 3,000
   random poses of the benchmark's calibrated PUMA 560: the roots a 500-start sweep found and this
   path missed went from 20 to 0 with the curves, the stall points of step 3 and every point's own
   curve; on the UR5 from 7 to 0, with the elbow fold starts);
5. the outcome of every branch is written to ``branches``: a distinct solution, merged into an
   earlier solution (that solution is flagged degenerate), or vanished (no exact solution of the
   arm near that branch: the two roots of a fold became complex);
6. where the joints are all revolute and the number of solutions is odd (the arm, a general 6R arm,
   has an even number), the closest two within ``DOUBLE`` are one double root reached twice: the later
   is dropped (:func:`_double_root`; where none are, one is missing:
   :meth:`robokit.ik.closed_form.AnalyticIK.solve` adds the general 6R method's);
7. the solutions are wrapped, shifted into wide limits, flagged and written as the closed-form
   kernels write theirs (:func:`robokit.kernels.closed_form._finish`).

Solutions are distinct to ``SAME`` (rad or m, angles modulo 2π): two polished roots closer than
that are one root (near a fold Newton's method converges to a double root only to about the
square root of the precision).

Example (``AnalyticIK`` builds the arguments; ``ik_analytic`` calls these kernels)::

    >>> import numpy as np, robokit
    >>> from robokit.ik.closed_form import AnalyticIK
    >>> arm = AnalyticIK(calibrated_robot).calibrated   # doctest: +SKIP
    >>> n = calibrated_solve_into(arm._KC, arm._kind, T, 0.0, out, work)  # doctest: +SKIP
"""
from __future__ import annotations

import math
from typing import Any

import numpy as np

from robokit.kernels._jit import machine_code, njit, prange
from robokit.kernels import closed_form as _cf
from robokit.kernels.ik import normal_equations

__all__ = ["pack_arm", "first_axis", "local_transforms", "fk_jacobian", "polish", "scratch", "calibrated_solve_into", "solve_into_entry", "calibrated_batch", "SAME",
           "FLAGGED", "STATUS", "BRANCH_COLS", "BRANCH_ROWS", "SOLUTION", "MERGED", "VANISHED", "FRAMES", "KINDS", "PITCHES"]

#: Two polished solutions closer than this (rad or m, angles modulo 2π) are one solution.
SAME = 1e-7
#: An arm of revolute joints off its nominal structure is a general 6R arm: its solutions are the real
#: roots of a polynomial of degree 16, so there is an even number of them (complex roots come in
#: conjugate pairs). Where the solve ends with an odd number and two of them are closer than this
#: (√``TOL_ACCEPT`` of :mod:`robokit.ik.calibrated`: how near Newton's method comes to a double root
#: whose pose it reaches to ``TOL_ACCEPT``), they are one double root, reached twice: the later is
#: dropped (measured: 2 of 89,000 random poses of the benchmark's arms, pairs 1.0e-7 and 2.4e-7 apart).
DOUBLE = 1e-5
#: Per-branch outcome codes written to ``branches[:, 1]``.
SOLUTION, MERGED, VANISHED = 0, 1, 2
#: Branches of the nominal structure in general position (both structures: 4 positions × 2 wrists).
GENERIC_ROWS = 8
#: When the projected arm's closed form gives fewer branches, it is also solved for the pose moved
#: toward (f < 0) or away from (f > 0) the shoulder by these fractions of the reach: the starts of
#: branches that the projected arm just cannot reach but the arm itself can (near the workspace's
#: outer or inner boundary).
RELAX = (-2e-3, 2e-3, -6e-3, 6e-3, -2e-2, 2e-2)
#: The relaxed poses, in the order they are solved: the tool moved by ``reach · (f_r u_r + f_l u_l)``
#: with u_r the unit vector from the shoulder point to the tool (toward or away from the shoulder:
#: ``RELAX``), u_l its part perpendicular to joint 1's axis, normalised (toward or away from that
#: axis), and both at once at the corners (f_r, f_l of opposite or equal signs). The projected
#: arm's workspace is bounded in two directions there: by the spheres about the shoulder and, with a
#: shoulder offset (the PUMA 560's d₃), by the cylinder about axis 1 — measured on the benchmark's
#: calibrated PUMA 560: 15 of 3,000 random poses had a wrist centre just inside that cylinder and no
#: start from the moves toward or away from the shoulder; the sideways moves gave 14 of them their
#: starts, a corner move the last (its wrist centre also at the outer sphere). The sideways and corner
#: moves are tried only while the pose has no start at all (as at those poses): tried wherever a branch
#: is missing they doubled the calibrated random Pieper arm's median time (most of its poses lack two of
#: the four positions, far from any boundary) and found nothing more.
RELAX_MOVES = tuple((f, 0.0) for f in RELAX) + tuple((0.0, f) for f in RELAX) + tuple(
    (r * f, l * f) for f in (6e-3, 2e-2) for r, l in ((-1.0, 1.0), (1.0, 1.0), (1.0, -1.0), (-1.0, -1.0)))
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
#: The near-singular search also follows the curve along which the arm almost reaches the pose
#: (:func:`_trace`), both ways from each point searched: ``TRACE_STEPS`` predictor steps of
#: ``TRACE_STEP`` (rad-like: a unit joint direction) along the near-null direction, each corrected by
#: ``TRACE_PULL`` Gauss–Newton steps across it; a local minimum of the pose error along the curve is
#: polished. The generated C keeps the curve's point, previous point, two directions and the last
#: three error norms in ``TRACE_ROWS`` free rows of its output, so a trace runs only where more rows
#: than that are free, and finds a root only while one more is (both sides alike).
TRACE_STEP, TRACE_STEPS, TRACE_PULL, TRACE_ROWS = 0.15, 43, 2, 5
#: Columns of ``branches``: branch code, outcome, index of the solution (−1 if vanished),
#: orientation error (rad), position error (m) at the end of the polish.
BRANCH_COLS = 5


@njit(inline=True)
def _error(T: np.ndarray, Td: np.ndarray, F: np.ndarray) -> tuple[float, float, float]:
    """F ← the spatial twist that moves T to Td: near Td (an orientation error below ``LOG_NEAR``
    rad) the logarithm of ``X = Td T⁻¹`` to second order (ω = θ u, v = V(ω)⁻¹ u_X, below), else to
    first order (ω = sin θ u, v = Δp − ω × p); both are zero exactly when T = Td and have the space
    Jacobian's derivative there, so Newton's method with J_s converges quadratically, and the
    second-order one is what :func:`_newton_step`'s second-order step needs.

    ``X = [A, p_X]`` with ``A = R_d Rᵀ`` and ``p_X = p_d − A p``; ``vee(A − Aᵀ)/2 = sin θ u``;
    ``θ/sin θ = 1 + s²/6 + 3s⁴/40 + …`` (s = sin θ); the exponential's ``V(ω) = I + (1 − cos θ)/θ² [ω]
    + (θ − sin θ)/θ³ [ω]²`` has the inverse ``I − [ω]/2 + k [ω]²`` with ``k = (1 − θ sin θ / (2(1 − cos
    θ)))/θ² = 1/12 + θ²/720 + …``. Below LOG_NEAR the series' first omitted terms are below 1e-11 of
    the error itself (they change the convergence constant, not the root).

    Returns (½(rot² + pos²), rot, pos) with rot = ‖sin θ u‖ (rad, or 2 − it beyond π/2) and pos = ‖Δp‖ (m)."""
    return _error_of((T[0, 0], T[0, 1], T[0, 2], T[0, 3], T[1, 0], T[1, 1], T[1, 2], T[1, 3], T[2, 0], T[2, 1],
                      T[2, 2], T[2, 3]), Td, F)


@njit(inline=True)
def _error_of(t: tuple[float, ...], Td: np.ndarray, F: np.ndarray) -> tuple[float, float, float]:
    """:func:`_error` of the pose whose first three rows are t (12 floats, row by row, as
    :func:`_chain_pose` returns them: the polish keeps its poses in registers, never stored)."""
    t00, t01, t02, t03, t10, t11, t12, t13, t20, t21, t22, t23 = t
    a00 = Td[0, 0] * t00 + Td[0, 1] * t01 + Td[0, 2] * t02
    a01 = Td[0, 0] * t10 + Td[0, 1] * t11 + Td[0, 2] * t12
    a02 = Td[0, 0] * t20 + Td[0, 1] * t21 + Td[0, 2] * t22
    a10 = Td[1, 0] * t00 + Td[1, 1] * t01 + Td[1, 2] * t02
    a11 = Td[1, 0] * t10 + Td[1, 1] * t11 + Td[1, 2] * t12
    a12 = Td[1, 0] * t20 + Td[1, 1] * t21 + Td[1, 2] * t22
    a20 = Td[2, 0] * t00 + Td[2, 1] * t01 + Td[2, 2] * t02
    a21 = Td[2, 0] * t10 + Td[2, 1] * t11 + Td[2, 2] * t12
    a22 = Td[2, 0] * t20 + Td[2, 1] * t21 + Td[2, 2] * t22
    sx, sy, sz = 0.5 * (a21 - a12), 0.5 * (a02 - a20), 0.5 * (a10 - a01)
    px, py, pz = t03, t13, t23
    dx, dy, dz = Td[0, 3] - px, Td[1, 3] - py, Td[2, 3] - pz
    s2 = sx * sx + sy * sy + sz * sz
    tr = a00 + a11 + a22  # 1 + 2 cos θ: below 1 beyond π/2, where ‖sin θ u‖ falls again
    if s2 < LOG_NEAR * LOG_NEAR and tr > 1.0:
        f = 1.0 + s2 * (_I6 + s2 * 0.075)  # θ / sin θ
        wx, wy, wz = f * sx, f * sy, f * sz
        k = _I12 + (wx * wx + wy * wy + wz * wz) * _I720
        ux = Td[0, 3] - (a00 * px + a01 * py + a02 * pz)  # p_X = p_d − A p
        uy = Td[1, 3] - (a10 * px + a11 * py + a12 * pz)
        uz = Td[2, 3] - (a20 * px + a21 * py + a22 * pz)
        cx, cy, cz = wy * uz - wz * uy, wz * ux - wx * uz, wx * uy - wy * ux  # ω × p_X
        F[0], F[1], F[2] = wx, wy, wz
        F[3] = ux - 0.5 * cx + k * (wy * cz - wz * cy)
        F[4] = uy - 0.5 * cy + k * (wz * cx - wx * cz)
        F[5] = uz - 0.5 * cz + k * (wx * cy - wy * cx)
    else:
        F[0], F[1], F[2] = sx, sy, sz
        F[3] = dx - (sy * pz - sz * py)
        F[4] = dy - (sz * px - sx * pz)
        F[5] = dz - (sx * py - sy * px)
    rot = math.sqrt(s2)
    if tr < 1.0:
        rot = 2.0 - rot
    pos = math.sqrt(dx * dx + dy * dy + dz * dz)
    return 0.5 * (rot * rot + pos * pos), rot, pos


#: :func:`_error` gives the logarithm (second order) below this orientation error (rad), the
#: first-order twist above it.
LOG_NEAR = 0.02


@njit(inline=True)
def _second_order(J: np.ndarray, d: np.ndarray, out: np.ndarray) -> None:
    """out ← ½ Σ_{i<j} dᵢ dⱼ [Jᵢ, Jⱼ], the second-order term of the pose error's change along d.

    With the space Jacobian's columns Jᵢ at q, ``T(q + d) = e^{[J₁]d₁} ⋯ e^{[J₆]d₆} T(q)`` exactly
    (each factor moved to the left through the earlier joints' motions is conjugated into Jᵢ), and the
    Baker–Campbell–Hausdorff formula gives ``log(e^{X₁} ⋯ e^{X₆}) = Σ Xᵢ + ½ Σ_{i<j} [Xᵢ, Xⱼ] + O(d³)``;
    the twists' bracket is ``[(ω, v), (ω′, v′)] = (ω × ω′, ω × v′ − ω′ × v)``. Summed as
    ``Σⱼ [Pⱼ₋₁, dⱼ Jⱼ]`` with the running sum ``Pⱼ = Σ_{i≤j} dᵢ Jᵢ``: five brackets (P₀ = d₁ J₁
    before the loop: its bracket with an empty sum is zero)."""
    d0 = d[0]
    pw0, pw1, pw2 = d0 * J[0, 0], d0 * J[1, 0], d0 * J[2, 0]
    pv0, pv1, pv2 = d0 * J[3, 0], d0 * J[4, 0], d0 * J[5, 0]
    o0 = o1 = o2 = o3 = o4 = o5 = 0.0
    for j in range(1, 6):
        dj = d[j]
        bw0, bw1, bw2 = dj * J[0, j], dj * J[1, j], dj * J[2, j]
        bv0, bv1, bv2 = dj * J[3, j], dj * J[4, j], dj * J[5, j]
        o0 += pw1 * bw2 - pw2 * bw1
        o1 += pw2 * bw0 - pw0 * bw2
        o2 += pw0 * bw1 - pw1 * bw0
        o3 += (pw1 * bv2 - pw2 * bv1) - (bw1 * pv2 - bw2 * pv1)
        o4 += (pw2 * bv0 - pw0 * bv2) - (bw2 * pv0 - bw0 * pv2)
        o5 += (pw0 * bv1 - pw1 * bv0) - (bw0 * pv1 - bw1 * pv0)
        pw0, pw1, pw2 = pw0 + bw0, pw1 + bw1, pw2 + bw2
        pv0, pv1, pv2 = pv0 + bv0, pv1 + bv1, pv2 + bv2
    out[0], out[1], out[2] = 0.5 * o0, 0.5 * o1, 0.5 * o2
    out[3], out[4], out[5] = 0.5 * o3, 0.5 * o4, 0.5 * o5


@njit(inline=True)
def _det3(a00: float, a01: float, a02: float, a10: float, a11: float, a12: float, a20: float, a21: float,
          a22: float) -> float:
    return a00 * (a11 * a22 - a12 * a21) - a01 * (a10 * a22 - a12 * a20) + a02 * (a10 * a21 - a11 * a20)


#: :func:`_block_factor` eliminates by 3 × 3 blocks only when the pivot block's determinant (three
#: unit axes: the volume they span) is at least this, and the Schur complement's at least
#: ``BLOCK_SCHUR`` times its Frobenius norm cubed; else the 6 × 6 elimination with pivoting.
BLOCK_AXES, BLOCK_SCHUR = 1e-3, 1e-6


@njit(inline=True)
def _block_elimination(J: np.ndarray) -> tuple:
    """The space Jacobian J (ω rows 0–2, v rows 3–5) eliminated by 3 × 3 blocks, as values (in
    registers where inlined): pivot block ``D`` = the ω rows of joints p…p+2, the three joints whose
    axes span the larger volume (p = 3, the wrist, or p = 0), the other three o…o+2; returns (ok, p,
    ``D⁻¹``, ``K = D⁻¹ Jω,o``, ``S⁻¹``) with the Schur complement ``S = Jv,o − Jv,p K``, each 3 × 3 as 9
    floats row by row. Exact for any J with D and S invertible (Gaussian elimination by blocks);
    straight-line arithmetic with two divisions, where the 6 × 6 elimination searches a pivot per
    column. ok False (the factors meaningless) when either block is near singular (``BLOCK_AXES``,
    ``BLOCK_SCHUR``)."""
    dw = _det3(J[0, 3], J[0, 4], J[0, 5], J[1, 3], J[1, 4], J[1, 5], J[2, 3], J[2, 4], J[2, 5])
    da = _det3(J[0, 0], J[0, 1], J[0, 2], J[1, 0], J[1, 1], J[1, 2], J[2, 0], J[2, 1], J[2, 2])
    p = 3 if abs(dw) >= abs(da) else 0
    ok = max(abs(dw), abs(da)) >= BLOCK_AXES
    det2 = 0.0
    if ok:
        o = 3 - p
        # D⁻¹ (the pivot block: the ω rows of joints p…p+2) by its adjugate
        a00, a01, a02 = J[0, p], J[0, p + 1], J[0, p + 2]
        a10, a11, a12 = J[1, p], J[1, p + 1], J[1, p + 2]
        a20, a21, a22 = J[2, p], J[2, p + 1], J[2, p + 2]
        b00, b01, b02 = a11 * a22 - a12 * a21, a02 * a21 - a01 * a22, a01 * a12 - a02 * a11
        b10, b11, b12 = a12 * a20 - a10 * a22, a00 * a22 - a02 * a20, a02 * a10 - a00 * a12
        b20, b21, b22 = a10 * a21 - a11 * a20, a01 * a20 - a00 * a21, a00 * a11 - a01 * a10
        inv = 1.0 / (a00 * b00 + a01 * b10 + a02 * b20)
        d00, d01, d02 = b00 * inv, b01 * inv, b02 * inv
        d10, d11, d12 = b10 * inv, b11 * inv, b12 * inv
        d20, d21, d22 = b20 * inv, b21 * inv, b22 * inv
        o00, o01, o02 = J[0, o], J[0, o + 1], J[0, o + 2]  # K = D⁻¹ Jω,o
        o10, o11, o12 = J[1, o], J[1, o + 1], J[1, o + 2]
        o20, o21, o22 = J[2, o], J[2, o + 1], J[2, o + 2]
        k00 = d00 * o00 + d01 * o10 + d02 * o20
        k01 = d00 * o01 + d01 * o11 + d02 * o21
        k02 = d00 * o02 + d01 * o12 + d02 * o22
        k10 = d10 * o00 + d11 * o10 + d12 * o20
        k11 = d10 * o01 + d11 * o11 + d12 * o21
        k12 = d10 * o02 + d11 * o12 + d12 * o22
        k20 = d20 * o00 + d21 * o10 + d22 * o20
        k21 = d20 * o01 + d21 * o11 + d22 * o21
        k22 = d20 * o02 + d21 * o12 + d22 * o22
        v00, v01, v02 = J[3, p], J[3, p + 1], J[3, p + 2]  # the Schur complement S = Jv,o − Jv,p K
        v10, v11, v12 = J[4, p], J[4, p + 1], J[4, p + 2]
        v20, v21, v22 = J[5, p], J[5, p + 1], J[5, p + 2]
        s00 = J[3, o] - (v00 * k00 + v01 * k10 + v02 * k20)
        s01 = J[3, o + 1] - (v00 * k01 + v01 * k11 + v02 * k21)
        s02 = J[3, o + 2] - (v00 * k02 + v01 * k12 + v02 * k22)
        s10 = J[4, o] - (v10 * k00 + v11 * k10 + v12 * k20)
        s11 = J[4, o + 1] - (v10 * k01 + v11 * k11 + v12 * k21)
        s12 = J[4, o + 2] - (v10 * k02 + v11 * k12 + v12 * k22)
        s20 = J[5, o] - (v20 * k00 + v21 * k10 + v22 * k20)
        s21 = J[5, o + 1] - (v20 * k01 + v21 * k11 + v22 * k21)
        s22 = J[5, o + 2] - (v20 * k02 + v21 * k12 + v22 * k22)
        s = s00 * s00 + s01 * s01 + s02 * s02 + s10 * s10 + s11 * s11 + s12 * s12 + s20 * s20 + s21 * s21 + s22 * s22
        c00, c01, c02 = s11 * s22 - s12 * s21, s02 * s21 - s01 * s22, s01 * s12 - s02 * s11
        c10, c11, c12 = s12 * s20 - s10 * s22, s00 * s22 - s02 * s20, s02 * s10 - s00 * s12
        c20, c21, c22 = s10 * s21 - s11 * s20, s01 * s20 - s00 * s21, s00 * s11 - s01 * s10
        det2 = s00 * c00 + s01 * c10 + s02 * c20
        ok = det2 != 0.0 and abs(det2) >= BLOCK_SCHUR * s * math.sqrt(s)
    if not ok:
        z = 0.0
        return (False, p, z, z, z, z, z, z, z, z, z, z, z, z, z, z, z, z, z, z, z, z, z, z, z, z, z, z, z)
    inv2 = 1.0 / det2
    return (True, p, d00, d01, d02, d10, d11, d12, d20, d21, d22, k00, k01, k02, k10, k11, k12, k20, k21, k22,
            c00 * inv2, c01 * inv2, c02 * inv2, c10 * inv2, c11 * inv2, c12 * inv2, c20 * inv2, c21 * inv2,
            c22 * inv2)


@njit(inline=True)
def _block_factor(J: np.ndarray, B: np.ndarray) -> bool:
    """:func:`_block_elimination` of J stored into B (6, 6): ``B[0:3, 0:3] = D⁻¹``, ``B[0:3, 3:6] =
    K``, ``B[3:6, 0:3] = S⁻¹``, ``B[3, 3] = p``; False (nothing to rely on in B) where it is not ok."""
    (ok, p, d00, d01, d02, d10, d11, d12, d20, d21, d22, k00, k01, k02, k10, k11, k12, k20, k21, k22, e00, e01, e02,
     e10, e11, e12, e20, e21, e22) = _block_elimination(J)
    if not ok:
        return False
    B[0, 0], B[0, 1], B[0, 2], B[0, 3], B[0, 4], B[0, 5] = d00, d01, d02, k00, k01, k02
    B[1, 0], B[1, 1], B[1, 2], B[1, 3], B[1, 4], B[1, 5] = d10, d11, d12, k10, k11, k12
    B[2, 0], B[2, 1], B[2, 2], B[2, 3], B[2, 4], B[2, 5] = d20, d21, d22, k20, k21, k22
    B[3, 0], B[3, 1], B[3, 2], B[3, 3] = e00, e01, e02, p
    B[4, 0], B[4, 1], B[4, 2] = e10, e11, e12
    B[5, 0], B[5, 1], B[5, 2] = e20, e21, e22
    return True


@njit(inline=True)
def _lu_factor(J: np.ndarray, A: np.ndarray, piv: np.ndarray) -> bool:
    """A ← the LU factors of J (6 × 6) with partial pivoting, the diagonal stored as its reciprocals,
    piv ← the row swapped into each column (rows of earlier columns not swapped: :func:`_lu_solve`
    replays the swaps in order); False when a pivot is below 1e-12 of the largest entry (J singular
    for this purpose)."""
    big = 0.0
    for r in range(6):
        for c in range(6):
            a = J[r, c]
            A[r, c] = a
            if abs(a) > big:
                big = abs(a)
    if not big > 0.0:
        return False
    small = 1e-12 * big
    for c in range(6):
        p = c
        best = abs(A[c, c])
        for r in range(c + 1, 6):
            if abs(A[r, c]) > best:
                p, best = r, abs(A[r, c])
        if best <= small:
            return False
        piv[c] = p
        if p != c:
            for k in range(c, 6):
                A[c, k], A[p, k] = A[p, k], A[c, k]
        inv = 1.0 / A[c, c]
        A[c, c] = inv
        for r in range(c + 1, 6):
            f = A[r, c] * inv
            A[r, c] = f
            for k in range(c + 1, 6):
                A[r, k] -= f * A[c, k]
    return True


@njit(inline=True)
def _lu_solve(A: np.ndarray, piv: np.ndarray, e: np.ndarray, x: np.ndarray) -> None:
    """x ← J⁻¹ e from :func:`_lu_factor`."""
    for r in range(6):
        x[r] = e[r]
    for c in range(6):
        p = int(piv[c])
        if p != c:
            x[c], x[p] = x[p], x[c]
        for r in range(c + 1, 6):
            x[r] -= A[r, c] * x[c]
    for r in range(5, -1, -1):
        acc = x[r]
        for k in range(r + 1, 6):
            acc -= A[r, k] * x[k]
        x[r] = acc * A[r, r]


@njit(inline=True)
def _newton_step(J: np.ndarray, F: np.ndarray, work: np.ndarray, x: np.ndarray) -> bool:
    """x ← the step that zeroes the pose error F (:func:`_error`) to second order: ``d = J⁻¹ F``,
    then, for ``SECOND_ORDER[0] < max|d| ≤ SECOND_ORDER[1]``, ``x = J⁻¹ (F − ½ B(d, d))`` with
    :func:`_second_order`'s B (the pose error after the step is then O(d³), where Newton's is O(d²):
    from the closed form's starts, about 5e-3 off, two steps reach 1e-15 where Newton's method needs
    three); the correction is dropped when it is not small against d (far from a root). J is
    factored once for both solves, by 3 × 3 blocks (:func:`_block_elimination`: every factor a local
    variable, nothing stored but x; measured on the UR5 and the PUMA 560, compiled as the polish is:
    93 → 77 ns a step from factors kept in ``work``) — or,
    where the blocks are near singular, with pivoting (:func:`_lu_newton_step`). False when J is
    singular for this purpose. Scratch: ``work`` rows 20–26, 32 and 47."""
    (ok, p, d00, d01, d02, d10, d11, d12, d20, d21, d22, k00, k01, k02, k10, k11, k12, k20, k21, k22, e00, e01, e02,
     e10, e11, e12, e20, e21, e22) = _block_elimination(J)
    if not ok:
        return _lu_newton_step(J, F, work, x)  # the 6 × 6 elimination with pivoting
    o = 3 - p
    v00, v01, v02 = J[3, p], J[3, p + 1], J[3, p + 2]  # Jv,p
    v10, v11, v12 = J[4, p], J[4, p + 1], J[4, p + 2]
    v20, v21, v22 = J[5, p], J[5, p + 1], J[5, p + 2]
    f0, f1, f2, f3, f4, f5 = F[0], F[1], F[2], F[3], F[4], F[5]
    for it in range(2):  # d = J⁻¹ F; then, with the correction, J⁻¹ (F − ½ B(d, d))
        # y = D⁻¹ fω, x_o = S⁻¹ (f_v − Jv,p y), x_p = y − K x_o
        y0 = d00 * f0 + d01 * f1 + d02 * f2
        y1 = d10 * f0 + d11 * f1 + d12 * f2
        y2 = d20 * f0 + d21 * f1 + d22 * f2
        r0 = f3 - (v00 * y0 + v01 * y1 + v02 * y2)
        r1 = f4 - (v10 * y0 + v11 * y1 + v12 * y2)
        r2 = f5 - (v20 * y0 + v21 * y1 + v22 * y2)
        xo0 = e00 * r0 + e01 * r1 + e02 * r2
        xo1 = e10 * r0 + e11 * r1 + e12 * r2
        xo2 = e20 * r0 + e21 * r1 + e22 * r2
        xp0 = y0 - (k00 * xo0 + k01 * xo1 + k02 * xo2)
        xp1 = y1 - (k10 * xo0 + k11 * xo1 + k12 * xo2)
        xp2 = y2 - (k20 * xo0 + k21 * xo1 + k22 * xo2)
        if it == 1:
            break
        # d, kept in x
        x[o], x[o + 1], x[o + 2] = xo0, xo1, xo2
        x[p], x[p + 1], x[p + 2] = xp0, xp1, xp2
        big = max(abs(xo0), abs(xo1), abs(xo2), abs(xp0), abs(xp1), abs(xp2))
        if not SECOND_ORDER[0] < big <= SECOND_ORDER[1]:
            return True
        d = work[32]
        _second_order(J, x, d)
        f0, f1, f2, f3, f4, f5 = F[0] - d[0], F[1] - d[1], F[2] - d[2], F[3] - d[3], F[4] - d[4], F[5] - d[5]
    change = max(abs(xo0 - x[o]), abs(xo1 - x[o + 1]), abs(xo2 - x[o + 2]), abs(xp0 - x[p]), abs(xp1 - x[p + 1]),
                 abs(xp2 - x[p + 2]))
    if change <= 0.5 * big:
        x[o], x[o + 1], x[o + 2] = xo0, xo1, xo2
        x[p], x[p + 1], x[p + 2] = xp0, xp1, xp2
    return True


@njit(inline=True)
def _lu_newton_step(J: np.ndarray, F: np.ndarray, work: np.ndarray, x: np.ndarray) -> bool:
    """:func:`_newton_step` with J factored by the 6 × 6 elimination with pivoting (:func:`_lu_factor`):
    where its 3 × 3 blocks are near singular."""
    A, piv, d = work[20:26], work[47], work[32]
    if not _lu_factor(J, A, piv):
        return False
    _lu_solve(A, piv, F, d)
    big = 0.0
    for i in range(6):
        big = max(big, abs(d[i]))
    if SECOND_ORDER[0] < big <= SECOND_ORDER[1]:
        _second_order(J, d, x)
        for i in range(6):
            x[i] = F[i] - x[i]
        _lu_solve(A, piv, x, x)  # in place: the solve copies e into x first
        change = 0.0
        for i in range(6):
            change = max(change, abs(x[i] - d[i]))
        if change <= 0.5 * big:
            return True
    for i in range(6):
        x[i] = d[i]
    return True


#: :func:`_newton_step` adds the second-order correction to steps between these lengths (rad, m): below
#: it is under the rounding of what it corrects, above the quadratic model is not trusted.
SECOND_ORDER = (1e-6, 0.05)


#: Layout of the packed constants ``C`` (:func:`pack_arm`): the base's and the tip's 3 × 4 transforms
#: (``L₀``, ``L₆``), per joint the seven numbers of its factors (θ, b, cos α, sin α, a, cos θ, sin θ), the
#: joint kinds (0 revolute, 1 prismatic), the screw pitches, ``post_q`` (5, 6), the shoulder point (3,),
#: the reach (m), tol_stop, tol_accept, max_steps, the arm's near-singular threshold (``SIGMA_EXPLORE``
#: or more: :func:`robokit.ik.calibrated.search_constants`) and 1 where every solution's singular values
#: are checked (``every``), else 0, and the fold starts' windows' factor (``fold_scale``, at least 1).
_L, _DH, _KIND, _PITCH, _POST, _SHOULDER, _REACH, _TOL_STOP, _TOL_ACCEPT, _MAX_STEPS, _SIGMA, _EVERY, _FOLDS, _LEN = (
    0, 24, 66, 72, 78, 108, 111, 112, 113, 114, 115, 116, 117, 118)
#: Where ``C`` keeps the chain: ``L₀`` and ``L₆`` (3 × 4 each, row-major) and the per-joint
#: numbers; the joint kinds; the pitches.
FRAMES, KINDS, PITCHES = slice(_L, _KIND), slice(_KIND, _PITCH), slice(_PITCH, _POST)
#: Rows of the scratch array ``work`` (:func:`scratch`): (rows, 6); the last MAX_ROWS (16) are the
#: branches' outcomes (:func:`calibrated_solve_into`).
_WORK_ROWS = 185
BRANCH_ROWS = slice(96, 112)
#: The row of ``work`` where :func:`calibrated_solve_into` leaves (merged branches, vanished branches, σ,
#: the wrists' least shortfall |cos θ₅| − 1; then the fold starts' switch and a scratch entry).
STATUS = 144
#: :func:`calibrated_solve_into` adds this to the number of solutions when a branch merged or
#: vanished or the near-singular search ran (the status row then says which).
FLAGGED = 1000


def pack_arm(M: np.ndarray, Slist: np.ndarray, post_q: np.ndarray, shoulder: np.ndarray, reach: float,
             tol_stop: float, tol_accept: float, max_steps: int, sigma_explore: float = SIGMA_EXPLORE,
             every: bool = False, fold_scale: float = 1.0) -> np.ndarray:
    """The arm's constants in one float64 array ``C`` (the kernels' layout above).

    The product of exponentials ``T(q) = e^{[S₁]q₁} ⋯ e^{[S₆]q₆} M`` is rewritten with one frame
    ``Fᵢ`` per joint axis: its z axis the joint's axis, its x axis perpendicular to this axis and the
    next one (any direction perpendicular to it where they are parallel, and for the last axis),
    its origin the point of the axis nearest the previous frame's origin (the first: nearest the
    base origin; a prismatic joint's axis runs through the previous origin). Then
    ``e^{[Sᵢ]qᵢ} = Fᵢ Zᵢ(qᵢ) Fᵢ⁻¹`` with ``Zᵢ`` a rotation about z (and ``hᵢ qᵢ`` along it, h the pitch)
    or a translation along z, and consecutive frames are ``Fᵢ⁻¹ Fᵢ₊₁ = Rx(αᵢ) Tr(aᵢ, bᵢ, 0) Rz(θᵢ₊₁)``
    (the next origin seen from this one is perpendicular to the next axis, so it has no component
    along it), hence ``T(q) = L₀ Z₁′ X₁ Z₂′ X₂ ⋯ X₅ Z₆′ L₆`` with ``L₀ = F₁``, ``L₆ = F₆⁻¹ M``,
    ``Xᵢ = Rx(αᵢ) Tr(aᵢ, bᵢ, 0)`` and ``Zᵢ′ = Rz(θᵢ + qᵢ) Tz(hᵢqᵢ)`` (a prismatic joint:
    ``Rz(θᵢ) Tz(qᵢ)``; θ₁ = 0). Per joint the running product mixes two columns twice and moves along
    two of them (no exponential, no 3 × 3 product): about two thirds of the arithmetic of a general
    3 × 4 factor per joint, and no parameter grows where axes are nearly parallel (as Denavit and
    Hartenberg's d does). Plain numpy (called once per arm); each ``Fᵢ⁻¹ Fᵢ₊₁`` is checked against
    its factors (to 1e-12).

    Parameters
    ----------
    M : (4, 4) ndarray
        Tip pose at q = 0 in the base frame (m).
    Slist : (6, 6) ndarray
        Space screw axes (ω; v) as columns.
    post_q : (5, 6) ndarray
        As :func:`robokit.kernels.closed_form.pack_constants` (revolute flags, limits).
    shoulder : (3,) ndarray
        The point the relaxed poses are moved about (m).
    reach, tol_stop, tol_accept : float
        m; rad or m.
    max_steps : int
        Newton steps at most per start.
    sigma_explore : float, optional
        The near-singular search runs around a point whose scaled Jacobian has a singular value below
        this (default ``SIGMA_EXPLORE``).
    every : bool, optional
        Check each solution's smallest singular value (else the first one's only, unless a search
        point was near singular): for arms farther from their structure (:func:`robokit.ik.calibrated.search_constants`).
    fold_scale : float, optional
        The fold starts' windows (``closed_form.FOLD_STARTS`` and ``FOLD_IMAG`` times this; default 1).

    Returns
    -------
    (118,) ndarray

    Examples
    --------
    >>> S = np.zeros((6, 6)); S[2] = 1.0; S[4] = -0.1 * np.arange(6)  # six parallel z axes, 0.1 m apart
    >>> C = pack_arm(np.eye(4), S, np.zeros((5, 6)), np.zeros(3), 1.0, 1e-12, 1e-10, 30)
    >>> C.shape
    (118,)
    """
    n = Slist.shape[1]
    kind = np.zeros(6)
    pitch = np.zeros(6)
    z: list[np.ndarray] = []
    point: list[np.ndarray | None] = []
    for i in range(n):  # each axis as a line: unit direction z and (revolute) a point of it
        w, v = Slist[:3, i], Slist[3:, i]
        if np.linalg.norm(w) > 0.5:  # revolute (unit ω): the point nearest the base origin, the pitch
            zi = w / np.linalg.norm(w)
            point.append(np.cross(zi, v))
            pitch[i] = float(zi @ v)
        else:  # prismatic: the direction alone matters
            zi = v / np.linalg.norm(v)
            point.append(None)
            kind[i] = 1.0
        z.append(zi)
    origins: list[np.ndarray] = []
    for i in range(n):  # each origin: the point of its axis nearest the previous origin
        prev = origins[-1] if origins else np.zeros(3)
        on_axis = point[i]
        if on_axis is None:
            origins.append(prev.copy())
        else:
            origins.append(on_axis + float((prev - on_axis) @ z[i]) * z[i])
    frames = []
    for i in range(n):
        zi = z[i]
        # zᵢ × (zᵢ₊₁ − zᵢ) = zᵢ × zᵢ₊₁, without the cancellation of nearly parallel axes (⟂ zᵢ₊₁ to rounding)
        x = np.cross(zi, z[i + 1] - zi) if i + 1 < n else np.zeros(3)
        if not np.linalg.norm(x) > 1e-200:  # parallel to the next axis, or the last one: any direction ⟂ z
            x = np.cross(zi, [1.0, 0.0, 0.0] if abs(zi[0]) < 0.9 else [0.0, 1.0, 0.0])
        x = x / np.linalg.norm(x)
        F = np.eye(4)
        F[:3, 0], F[:3, 1], F[:3, 2], F[:3, 3] = x, np.cross(zi, x), zi, origins[i]
        frames.append(F)
    dh = np.zeros((6, 7))
    dh[:, 2], dh[:, 5] = 1.0, 1.0  # cos α = 1 after the last joint, cos θ = 1 at the first
    between = [np.linalg.inv(frames[i]) @ frames[i + 1] for i in range(n - 1)]
    for i, L in enumerate(between):
        alpha, theta = math.atan2(-L[1, 2], L[2, 2]), math.atan2(-L[0, 1], L[0, 0])
        ct, st, ca, sa = math.cos(theta), math.sin(theta), math.cos(alpha), math.sin(alpha)
        dh[i, 1:5] = ca * L[1, 3] + sa * L[2, 3], ca, sa, L[0, 3]  # Rx(α) Tr(a, b, 0) after joint i: b, cos α, sin α, a
        dh[i + 1, 0] = theta  # Rz(θ) at joint i + 1
        dh[i + 1, 5:7] = ct, st
    C = np.zeros(_LEN)
    C[_L:_L + 12] = frames[0][:3, :].ravel()
    C[_L + 12:_DH] = (np.linalg.inv(frames[n - 1]) @ M)[:3, :].ravel()
    C[_DH:_KIND] = dh.ravel()
    C[_KIND:_PITCH], C[_PITCH:_POST] = kind, pitch
    C[_POST:_SHOULDER] = np.asarray(post_q, dtype=float).ravel()
    C[_SHOULDER:_REACH] = shoulder
    C[_REACH], C[_TOL_STOP], C[_TOL_ACCEPT], C[_MAX_STEPS] = reach, tol_stop, tol_accept, max_steps
    C[_SIGMA], C[_EVERY], C[_FOLDS] = sigma_explore, 1.0 if every else 0.0, fold_scale
    # the factors read back (local_transforms) must be the frames' relations, to rounding
    factors = local_transforms(C)[1:n]
    for i, L in enumerate(between):
        miss = float(np.abs(factors[i] - L[:3]).max())
        if not miss < 1e-12 * max(1.0, float(np.abs(L[:3, 3]).max())):
            raise AssertionError(f"pack_arm: joint frames {i} and {i + 1} are not related by Rx Tr Rz (off by {miss:.3g})")
    return C


def first_axis(C: np.ndarray) -> tuple[float, float, float]:
    """Joint 1's axis direction (unit, base frame) of the packed arm ``C``: the z axis of its first
    frame, the axis the relaxed moves (``RELAX_MOVES``) go across.

    Parameters
    ----------
    C : (118,) ndarray
        From :func:`pack_arm`.

    Returns
    -------
    tuple of 3 float

    Examples
    --------
    >>> S = np.zeros((6, 6)); S[2] = 1.0; S[4] = -0.1 * np.arange(6)  # six parallel z axes, 0.1 m apart
    >>> C = pack_arm(np.eye(4), S, np.zeros((5, 6)), np.zeros(3), 1.0, 1e-12, 1e-10, 30)
    >>> first_axis(C)
    (0.0, 0.0, 1.0)
    """
    return float(C[_L + 2]), float(C[_L + 6]), float(C[_L + 10])


def local_transforms(C: np.ndarray) -> np.ndarray:
    """The packed arm ``C`` as seven 3 × 4 local transforms ``T(q) = L₀ Z₁(q₁) L₁ ⋯ Z₆(q₆) L₆`` with
    ``Zᵢ`` the bare joint motion (a rotation about z with ``hᵢ qᵢ`` along it, or a translation along
    z): ``L₀`` and ``L₆`` as packed, ``Lᵢ = Xᵢ Rz(θᵢ₊₁)`` between joints (:func:`pack_arm`). The form
    the generated C composes (:mod:`robokit.codegen.ik_calibrated`). Plain numpy.

    Parameters
    ----------
    C : (118,) ndarray
        From :func:`pack_arm`.

    Returns
    -------
    (7, 3, 4) ndarray

    Examples
    --------
    >>> S = np.zeros((6, 6)); S[2] = 1.0; S[4] = -0.1 * np.arange(6)  # six parallel z axes, 0.1 m apart
    >>> C = pack_arm(np.eye(4), S, np.zeros((5, 6)), np.zeros(3), 1.0, 1e-12, 1e-10, 30)
    >>> local_transforms(C).shape
    (7, 3, 4)
    """
    dh = C[_DH:_KIND].reshape(6, 7)
    out = np.empty((7, 3, 4))
    out[0], out[6] = C[_L:_L + 12].reshape(3, 4), C[_L + 12:_DH].reshape(3, 4)
    for i in range(5):
        b, ca, sa, a = dh[i, 1:5]
        ct, st = dh[i + 1, 5], dh[i + 1, 6]
        out[i + 1] = [[ct, -st, 0.0, a], [st * ca, ct * ca, -sa, b * ca], [st * sa, ct * sa, ca, b * sa]]
    return out


@njit(inline=True)
def _trig(C: np.ndarray, q: np.ndarray, sc: np.ndarray) -> None:
    """sc[0] ← sin, sc[1] ← cos of ``θᵢ + qᵢ`` of the revolute joints (their angle in the DH form of
    :func:`pack_arm`)."""
    for i in range(6):
        if C[_KIND + i] == 0.0:
            angle = C[_DH + 7 * i] + q[i]
            sc[0, i] = math.sin(angle)
            sc[1, i] = math.cos(angle)


@njit(inline=True)
def _start_trig(C: np.ndarray, nom: np.ndarray, m: int, sct: np.ndarray) -> None:
    """sct[2r], sct[2r + 1] ← the sines and cosines of start r's DH angles (:func:`_trig` of row r
    of ``nom``, r < m), a joint value that an earlier start has too (the same float) taken from it:
    a closed form's branches share joint values (measured on calibrated arms with eight branches, the
    median number of distinct values per joint: a UR5's 2, 8, 8, 8, 4, 4; a PUMA 560's 3, 4, 2, 8,
    8, 8), so about 30 % of the sines and cosines are copies — the same numbers :func:`_trig`
    would compute."""
    for r in range(m):
        for i in range(6):
            if C[_KIND + i] != 0.0:
                continue
            v = nom[r, i]
            k = 0
            while k < r and nom[k, i] != v:
                k += 1
            if k < r:
                sct[2 * r, i] = sct[2 * k, i]
                sct[2 * r + 1, i] = sct[2 * k + 1, i]
            else:
                angle = C[_DH + 7 * i] + v
                sct[2 * r, i] = math.sin(angle)
                sct[2 * r + 1, i] = math.cos(angle)


@njit(inline=True)
def _advance(C: np.ndarray, sc: np.ndarray, step: np.ndarray, out: np.ndarray) -> None:
    """out ← sin, cos of (q + step) from sc = sin, cos of q by the angle-addition formulas; sin and
    cos of a step below 0.02 rad by their Taylor series (sin to δ⁷, cos to δ⁸: the next terms are
    below 1e-20 of the step) — multiplications only (a Newton step is ~1e-3 … 1e-10 rad)."""
    for i in range(6):
        if C[_KIND + i] != 0.0:
            continue
        d = step[i]
        if -0.02 < d < 0.02:
            d2 = d * d
            sd = d * (1.0 - d2 * (_I6 - d2 * (_I120 - d2 * _I5040)))
            cd = 1.0 - d2 * (0.5 - d2 * (_I24 - d2 * (_I720 - d2 * _I40320)))
        else:
            sd, cd = math.sin(d), math.cos(d)
        s, c = sc[0, i], sc[1, i]
        out[0, i] = s * cd + c * sd
        out[1, i] = c * cd - s * sd


_I6, _I12, _I24, _I120, _I720, _I5040, _I40320 = (1.0 / 6.0, 1.0 / 12.0, 1.0 / 24.0, 1.0 / 120.0, 1.0 / 720.0, 1.0 / 5040.0,
                                                  1.0 / 40320.0)


@njit(inline=True)
def fk_jacobian(C: np.ndarray, q: np.ndarray, sc: np.ndarray, T: np.ndarray, J: np.ndarray) -> None:
    """T ← the tip pose (4, 4) and J ← the space Jacobian (6, 6; ω rows first, v of the point at the
    base origin) of the packed arm ``C`` (:func:`pack_arm`) at q, the sin and cos of the revolute
    joints' DH angles θᵢ + qᵢ given in sc (2, 6, :func:`_trig`): one pass through the DH factors,
    the Jacobian's columns read off the running product (joint i's axis z and point p: ω = z,
    v = p × z + h z; prismatic: v = z)."""
    _chain(C, q, sc, T, J, True)


@njit(inline=True)
def _chain_pose(C: np.ndarray, q: np.ndarray, sc: np.ndarray, J: np.ndarray, jac: bool) -> tuple[float, ...]:
    """The tip pose's first three rows (12 floats, row by row) and J ← the space Jacobian (:func:`fk_jacobian`),
    J written only when ``jac`` (the pose alone: the same arithmetic, so the same pose to the last bit). The running product starts at ``L₀``; at joint i its z column is
    the joint's axis and its origin a point of it (the Jacobian's column), then ``Zᵢ′`` and ``Xᵢ``
    (:func:`pack_arm`) mix two columns each and move the origin along them; ``L₆`` ends it."""
    r00, r01, r02, px = C[0], C[1], C[2], C[3]
    r10, r11, r12, py = C[4], C[5], C[6], C[7]
    r20, r21, r22, pz = C[8], C[9], C[10], C[11]
    for i in range(6):
        o = _DH + 7 * i
        if C[_KIND + i] == 0.0:
            h = C[_PITCH + i]
            if jac:
                J[0, i], J[1, i], J[2, i] = r02, r12, r22
                J[3, i] = py * r22 - pz * r12 + h * r02
                J[4, i] = pz * r02 - px * r22 + h * r12
                J[5, i] = px * r12 - py * r02 + h * r22
            s, c = sc[0, i], sc[1, i]
            t = h * q[i]
        else:
            if jac:
                J[0, i], J[1, i], J[2, i] = 0.0, 0.0, 0.0
                J[3, i], J[4, i], J[5, i] = r02, r12, r22
            s, c = C[o + 6], C[o + 5]
            t = q[i]
        # Zᵢ′: Rz(θᵢ + qᵢ) mixes columns 0 and 1; Tz moves the origin along column 2 (a screw's pitch,
        # a prismatic joint)
        r00, r01 = c * r00 + s * r01, c * r01 - s * r00
        r10, r11 = c * r10 + s * r11, c * r11 - s * r10
        r20, r21 = c * r20 + s * r21, c * r21 - s * r20
        if t != 0.0:
            px, py, pz = px + t * r02, py + t * r12, pz + t * r22
        if i < 5:  # Xᵢ: Rx(αᵢ) mixes columns 1 and 2, then Tr(aᵢ, bᵢ, 0) moves along columns 0 and 1
            b, ca, sa, a = C[o + 1], C[o + 2], C[o + 3], C[o + 4]
            r01, r02 = ca * r01 + sa * r02, ca * r02 - sa * r01
            r11, r12 = ca * r11 + sa * r12, ca * r12 - sa * r11
            r21, r22 = ca * r21 + sa * r22, ca * r22 - sa * r21
            px, py, pz = px + a * r00 + b * r01, py + a * r10 + b * r11, pz + a * r20 + b * r21
    o = _L + 12
    a00, a01, a02, a03 = C[o], C[o + 1], C[o + 2], C[o + 3]
    a10, a11, a12, a13 = C[o + 4], C[o + 5], C[o + 6], C[o + 7]
    a20, a21, a22, a23 = C[o + 8], C[o + 9], C[o + 10], C[o + 11]
    return (r00 * a00 + r01 * a10 + r02 * a20, r00 * a01 + r01 * a11 + r02 * a21, r00 * a02 + r01 * a12 + r02 * a22,
            r00 * a03 + r01 * a13 + r02 * a23 + px,
            r10 * a00 + r11 * a10 + r12 * a20, r10 * a01 + r11 * a11 + r12 * a21, r10 * a02 + r11 * a12 + r12 * a22,
            r10 * a03 + r11 * a13 + r12 * a23 + py,
            r20 * a00 + r21 * a10 + r22 * a20, r20 * a01 + r21 * a11 + r22 * a21, r20 * a02 + r21 * a12 + r22 * a22,
            r20 * a03 + r21 * a13 + r22 * a23 + pz)


@njit(inline=True)
def _chain(C: np.ndarray, q: np.ndarray, sc: np.ndarray, T: np.ndarray, J: np.ndarray, jac: bool) -> None:
    """:func:`_chain_pose` with the pose written into T (4, 4)."""
    t = _chain_pose(C, q, sc, J, jac)
    T[0, 0], T[0, 1], T[0, 2], T[0, 3] = t[0], t[1], t[2], t[3]
    T[1, 0], T[1, 1], T[1, 2], T[1, 3] = t[4], t[5], t[6], t[7]
    T[2, 0], T[2, 1], T[2, 2], T[2, 3] = t[8], t[9], t[10], t[11]
    T[3, 0], T[3, 1], T[3, 2], T[3, 3] = 0.0, 0.0, 0.0, 1.0


@njit(refcount=False, contract=True)
def polish(C: np.ndarray, Td: np.ndarray, q: np.ndarray, max_steps: int, work: np.ndarray) -> tuple[float, float, int]:
    """:func:`_polish` from q's own sines and cosines."""
    return _polish(C, Td, q, max_steps, work, True)


@njit(refcount=False, inline=True)
def _polish(C: np.ndarray, Td: np.ndarray, q: np.ndarray, max_steps: int, work: np.ndarray,
            trig: bool) -> tuple[float, float, int]:
    """Newton's method with a second-order correction (:func:`_newton_step`) on the pose error
    :func:`_error` of the packed arm ``C`` with its space Jacobian (:func:`fk_jacobian`), q (6,)
    updated in place; a step that does not lower the error,
    or a singular Jacobian, switches to Levenberg–Marquardt (damping λ times the largest diagonal
    entry of JᵀJ, λ from 1e-9, ×10 on failure, ÷10 on success, back to Newton below 1e-9); no step
    moves a joint more than ``MAX_STEP``. The sines and cosines are computed once at the start and
    carried through the steps by the angle-addition formulas (:func:`_advance`). Stops when the
    orientation error (rad) and the position error (m) are below ``C``'s tol_stop. A step from an
    iterate whose errors are below ``FINAL`` is expected to stop there: its trial point's pose is
    evaluated without the Jacobian (the same arithmetic, the same pose; the Jacobian is computed
    after all if the iteration goes on), so the check that ends a typical polish costs a pose only.
    Returns (orientation error, position error, FK evaluations); the sines and cosines of the final q
    (carried by angle addition) are then in ``work``'s rows 43–44. Scratch: work (:func:`scratch`);
    ``trig`` False: the caller has written the sines and cosines of q (:func:`_trig`) into its rows
    43–44 (the starts share theirs: :func:`_start_trig`)."""
    n = 6
    tol_stop = C[_TOL_STOP]
    J0, J1, H, L = work[8:14], work[14:20], work[26:32], work[32:38]
    F0, F1, g, step, trial = work[38], work[39], work[40], work[41], work[42]
    sc0, sc1 = work[43:45], work[45:47]
    if trig:
        _trig(C, q, sc0)
    # (J0, F0, sc0): the current iterate; (J1, F1, sc1): a trial; their poses only in registers (_chain_pose)
    err, rot, pos = _error_of(_chain_pose(C, q, sc0, J0, True), Td, F0)
    lam = 0.0  # 0: Newton; else the damping, relative to the largest diagonal entry of Jᵀ J
    evals = 1
    swapped = False  # sc0 is rows 45–46, not 43–44
    for _ in range(max_steps):
        if rot < tol_stop and pos < tol_stop:
            break
        solved = lam == 0.0 and _newton_step(J0, F0, work, step)
        if not solved:
            if lam == 0.0:
                lam = 1e-9
            normal_equations(J0, F0, H, g)  # (Jᵀ J + λ d I) Δq = Jᵀ F,  d = max diag(Jᵀ J)
            big = 0.0
            for i in range(n):
                big = max(big, H[i, i])
            for i in range(n):
                H[i, i] += lam * big
            if not _cholesky_factor(H, L):
                lam *= 10.0
                if lam > 1e3:
                    break
                continue
            _cholesky_solve(L, g, step)
        longest = 0.0  # a step longer than MAX_STEP (rad, m) is shortened: Newton's model is local
        for i in range(n):
            longest = max(longest, abs(step[i]))
        if longest > MAX_STEP:
            shrink = MAX_STEP / longest
            for i in range(n):
                step[i] *= shrink
        for i in range(n):
            trial[i] = q[i] + step[i]
        _advance(C, sc0, step, sc1)
        jac = not (rot < FINAL and pos < FINAL)  # else the trial is expected to end the polish
        e2, r2, p2 = _error_of(_chain_pose(C, trial, sc1, J1, jac), Td, F1)
        evals += 1
        if e2 < err:
            for i in range(n):
                q[i] = trial[i]
            F0, F1 = F1, F0  # the trial becomes the iterate: its buffers are swapped in, not copied
            sc0, sc1 = sc1, sc0
            swapped = not swapped
            if jac:
                J0, J1 = J1, J0
            elif not (r2 < tol_stop and p2 < tol_stop):
                _chain_pose(C, q, sc0, J0, True)  # not the end after all: its Jacobian (its pose again)
                evals += 1
            err, rot, pos = e2, r2, p2
            if lam > 0.0:
                lam = lam * 0.1 if lam > 1e-9 else 0.0
        else:
            lam = 1e-9 if lam == 0.0 else lam * 10.0
            if lam > 1e3:
                break
    if swapped:  # the final iterate's sines and cosines in rows 43–44, where the caller reads them
        for i in range(n):
            work[43, i], work[44, i] = sc0[0, i], sc0[1, i]
    return rot, pos, evals


#: :func:`polish` evaluates a trial point's pose without the Jacobian when the iterate it steps from
#: has orientation (rad) and position (m) errors below this: the second-order step then ends below
#: 1e-12 unless the error's third-order constant exceeds 1000 (the error after a step from e is
#: about c e³; measured on calibrated arms from the closed form's starts: c ≈ 2–50).
FINAL = 1e-5


def scratch() -> np.ndarray:
    """The scratch array of :func:`polish` and :func:`calibrated_solve_into` ((185, 6) float64; rows
    ``BRANCH_ROWS`` the branches' outcomes, row ``STATUS`` the status).

    Returns
    -------
    (185, 6) ndarray

    Examples
    --------
    >>> scratch().shape
    (185, 6)
    """
    return np.empty((_WORK_ROWS, 6))


@njit(inline=True)
def _same(a: np.ndarray, b: np.ndarray, rev: np.ndarray) -> bool:
    """Whether a and b are one solution (within ``SAME``, angles modulo 2π). A difference between
    SAME and 6 in magnitude is decided without the remainder (the same answer: up to π the
    remainder is the difference itself, beyond it is at least 2π − 6 in magnitude)."""
    for j in range(6):
        d = a[j] - b[j]
        if SAME <= abs(d) <= 6.0:
            return False
        if rev[j] != 0.0:
            d = _cf._rem(d)
        if d >= SAME or d <= -SAME:
            return False
    return True


@njit(inline=True)
def _has_code(codes: np.ndarray, m: int, code: float) -> bool:
    """Whether the branch code is among the first m of ``codes``."""
    for r in range(m):
        if codes[r] == code:
            return True
    return False


@njit(inline=True)
def _find(q: np.ndarray, Q: np.ndarray, n: int, rev: np.ndarray) -> int:
    for k in range(n):
        if _same(q, Q[k], rev):
            return k
    return -1


@njit(inline=True)
def _cholesky_factor(H: np.ndarray, L: np.ndarray) -> bool:
    """L ← the Cholesky factor of H (6 × 6, lower triangle), its diagonal stored as reciprocals (the
    solves multiply); False when H is not positive definite."""
    for j in range(6):
        s = H[j, j]
        for k in range(j):
            s -= L[j, k] * L[j, k]
        if not s > 0.0:
            return False
        inv = 1.0 / math.sqrt(s)
        L[j, j] = inv
        for i in range(j + 1, 6):
            s = H[i, j]
            for k in range(j):
                s -= L[i, k] * L[j, k]
            L[i, j] = s * inv
    return True


@njit(inline=True)
def _cholesky_solve(L: np.ndarray, b: np.ndarray, x: np.ndarray) -> None:
    """x ← (L Lᵀ)⁻¹ b from :func:`_cholesky_factor`'s L; x may be b."""
    for i in range(6):
        s = b[i]
        for k in range(i):
            s -= L[i, k] * x[k]
        x[i] = s * L[i, i]
    for i in range(5, -1, -1):
        s = x[i]
        for k in range(i + 1, 6):
            s -= L[k, i] * x[k]
        x[i] = s * L[i, i]


@njit(refcount=False, contract=True)
def _null_direction(C: np.ndarray, q: np.ndarray, work: np.ndarray, v: np.ndarray) -> float:
    """v ← the unit joint direction along which the arm's Jacobian at q is closest to singular:
    inverse iteration (4 steps from (1, …, 1), with ``H⁻¹ = L⁻ᵀL⁻¹`` from one factorization) on ``H =
    J̃ᵀJ̃ + 1e-12 I``, J̃ the
    space Jacobian with its velocity rows divided by the reach (m), so both halves are rad-like.
    Returns the estimate ``√(vᵀHv)`` of J̃'s smallest singular value (0 when H is not positive
    definite). Scratch: ``work`` rows 0–3, 8–13, 26–37, 40–41, 43–44."""
    n = 6
    reach = C[_REACH]
    T, Jc, H, L = work[0:4, 0:4], work[8:14], work[26:32], work[32:38]
    x, tmp, sc = work[40], work[41], work[43:45]
    _trig(C, q, sc)
    fk_jacobian(C, q, sc, T, Jc)
    for r in range(3, 6):
        for c in range(n):
            Jc[r, c] /= reach
    for i in range(n):
        v[i] = 1.0
    normal_equations(Jc, v, H, x)  # H = J̃ᵀJ̃ (x is overwritten below)
    for i in range(n):
        H[i, i] += 1e-12
    if not _cholesky_factor(H, L):
        return 0.0
    # M = L⁻¹ (lower triangular, over L: its diagonal holds the reciprocals already, each column of
    # the rest by forward substitution); then each step v ← Mᵀ M v = H⁻¹ v, normalised: products,
    # not substitutions (independent rows: a short dependency chain)
    for c in range(n - 1):
        for i in range(c + 1, n):
            acc = 0.0
            for k in range(c, i):
                acc += L[i, k] * (tmp[k] if k > c else L[c, c])
            tmp[i] = -acc * L[i, i]
        for i in range(c + 1, n):
            L[i, c] = tmp[i]
    for _ in range(4):
        for i in range(n):
            acc = 0.0
            for k in range(i + 1):
                acc += L[i, k] * v[k]
            tmp[i] = acc
        norm = 0.0
        for i in range(n):
            acc = 0.0
            for k in range(i, n):
                acc += L[k, i] * tmp[k]
            x[i] = acc
            norm += acc * acc
        norm = 1.0 / math.sqrt(norm)
        for i in range(n):
            v[i] = x[i] * norm
    rq = 0.0
    for i in range(n):
        for j in range(n):
            rq += v[i] * H[i, j] * v[j]
    return math.sqrt(max(rq, 0.0))


@njit(refcount=False, contract=True)
def _sigma_bound(C: np.ndarray, q: np.ndarray, work: np.ndarray, trig: bool = True) -> float:
    """A lower bound of the smallest singular value of the scaled Jacobian J̃ at q (as
    :func:`_null_direction` estimates it), cheaper than that estimate: ``1 / ‖J̃⁻¹‖_F`` (at most √6
    below the value), J⁻¹ written out from :func:`_block_factor`'s blocks (straight-line products),
    its velocity columns times the reach; 0 where J does not factor by blocks. With ``D⁻¹``, ``K``,
    ``S⁻¹`` of that factorization and ``M = S⁻¹ Jv,p D⁻¹``: ``J⁻¹ = [[D⁻¹ + K M, −K S⁻¹], [−M, S⁻¹]]``
    (rows: the pivot block's joints, then the others; columns: ω, then v). ``trig`` False: q's sines
    and cosines are in ``work``'s rows 43–44 already. Scratch: ``work`` rows 0–3, 8–13, 20–22, 26–31,
    43–44."""
    T, J, B, sc = work[0:4, 0:4], work[8:14], work[26:32], work[43:45]
    G = work[20:23]  # G = Jv,p D⁻¹ in columns 0–2, M in 3–5
    reach = C[_REACH]
    if trig:
        _trig(C, q, sc)
    fk_jacobian(C, q, sc, T, J)
    if not _block_factor(J, B):
        return 0.0
    p = int(B[3, 3])
    for r in range(3):
        for c in range(3):
            G[r, c] = J[3 + r, p] * B[0, c] + J[3 + r, p + 1] * B[1, c] + J[3 + r, p + 2] * B[2, c]
    for r in range(3):
        for c in range(3):
            G[r, 3 + c] = B[3 + r, 0] * G[0, c] + B[3 + r, 1] * G[1, c] + B[3 + r, 2] * G[2, c]
    omega = 0.0  # ‖D⁻¹ + K M‖² + ‖M‖²: the ω columns
    vel = 0.0  # ‖K S⁻¹‖² + ‖S⁻¹‖²: the velocity columns
    for r in range(3):
        for c in range(3):
            a = B[r, c] + B[r, 3] * G[0, 3 + c] + B[r, 4] * G[1, 3 + c] + B[r, 5] * G[2, 3 + c]
            b = B[r, 3] * B[3, c] + B[r, 4] * B[4, c] + B[r, 5] * B[5, c]
            omega += a * a + G[r, 3 + c] * G[r, 3 + c]
            vel += b * b + B[3 + r, c] * B[3 + r, c]
    return 1.0 / math.sqrt(omega + vel * reach * reach)


#: The relaxed poses are solved only where they can add a branch (:func:`_relax_mask`). Where a
#: decision is within these margins (relative) it is unsure and the relaxed poses are solved: a
#: critical value of the position quartic near zero (a double root: the closed form takes a complex
#: pair as real when its imaginary part is below 1e-6, where that value is about 1e-12 of the
#: quartic's size), and a branch label's defining quantity near zero.
RELAX_UNSURE, LABEL_UNSURE = 1e-8, 1e-6


@njit
def _quartic_roots(c: np.ndarray, roots: np.ndarray, guesses: int, pts: np.ndarray, vals: np.ndarray) -> int:
    """Real roots of Σ c_k t^k (k ≤ 4) into ``roots``, ascending; their count, or −1 when unsure:
    a leading coefficient near zero (a root near t = ∞), two critical points (nearly) coinciding,
    or a critical value within ``RELAX_UNSURE`` of zero (a double root). The quartic is monotone
    between its critical points (the roots of its derivative, a cubic: trigonometric or Cardano
    formula, then Newton), so each sign change of the values there brackets one root, found by
    Newton's method kept inside the bracket (the bracket's secant or middle when it leaves), from the
    bracket's middle or, for the first ``guesses`` roots, from the value in ``roots`` when it is inside
    (the roots of a nearby quartic). Scratch: pts, vals (5,)."""
    c0, c1, c2, c3, c4 = c[0], c[1], c[2], c[3], c[4]
    scale = max(abs(c0), abs(c1), abs(c2), abs(c3), abs(c4))
    if scale == 0.0 or abs(c4) <= 1e-6 * scale:
        return -1
    A, B, C = 0.75 * c3 / c4, 0.5 * c2 / c4, 0.25 * c1 / c4  # P'/(4 c4) = t³ + A t² + B t + C
    Q = (A * A - 3.0 * B) / 9.0
    R = (2.0 * A * A * A - 9.0 * A * B + 27.0 * C) / 54.0
    Q3 = Q * Q * Q
    if abs(R * R - Q3) <= 1e-9 * (R * R + abs(Q3)):
        return -1
    # pts: −bound, the critical points ascending, +bound
    nc = 0
    if R * R < Q3:
        th = math.acos(max(-1.0, min(1.0, R / math.sqrt(Q3))))
        sq = -2.0 * math.sqrt(Q)
        pts[1] = sq * math.cos(th / 3.0) - A / 3.0
        pts[2] = sq * math.cos((th + 2.0 * math.pi) / 3.0) - A / 3.0
        pts[3] = sq * math.cos((th - 2.0 * math.pi) / 3.0) - A / 3.0
        nc = 3
    else:
        S = -math.copysign(1.0, R) * (abs(R) + math.sqrt(R * R - Q3)) ** (1.0 / 3.0)
        pts[1] = S + (Q / S if S != 0.0 else 0.0) - A / 3.0
        nc = 1
    for i in range(2, nc + 1):  # ascending
        x = pts[i]
        k = i
        while k > 1 and pts[k - 1] > x:
            pts[k] = pts[k - 1]
            k -= 1
        pts[k] = x
    # Fujiwara's bound: every root within 2 max |c_{4-k}/c₄|^{1/k}
    bound = 2.0 * max(abs(c3 / c4), math.sqrt(abs(c2 / c4)), abs(c1 / c4) ** (1.0 / 3.0), (0.5 * abs(c0 / c4)) ** 0.25)
    for i in range(1, nc + 1):
        t = pts[i]
        for _ in range(2):  # Newton on the cubic: the formula's rounding
            d1 = ((4.0 * c4 * t + 3.0 * c3) * t + 2.0 * c2) * t + c1
            d2 = (12.0 * c4 * t + 6.0 * c3) * t + 2.0 * c2
            if d2 == 0.0:
                break
            t -= d1 / d2
        pts[i] = t
        a = abs(t)
        p = (((c4 * t + c3) * t + c2) * t + c1) * t + c0
        if abs(p) <= RELAX_UNSURE * ((((abs(c4) * a + abs(c3)) * a + abs(c2)) * a + abs(c1)) * a + abs(c0)):
            return -1
        vals[i] = p
    pts[0], pts[nc + 1] = -bound - 1.0, bound + 1.0
    for i in (0, nc + 1):
        t = pts[i]
        vals[i] = (((c4 * t + c3) * t + c2) * t + c1) * t + c0
    n = 0
    for i in range(nc + 1):
        lo, hi, flo = pts[i], pts[i + 1], vals[i]
        if (flo > 0.0) == (vals[i + 1] > 0.0):
            continue
        fhi = vals[i + 1]
        t = roots[n] if n < guesses and lo < roots[n] < hi else 0.5 * (lo + hi)
        for _ in range(100):
            p = (((c4 * t + c3) * t + c2) * t + c1) * t + c0
            a = abs(t)
            if abs(p) <= 1e-15 * ((((abs(c4) * a + abs(c3)) * a + abs(c2)) * a + abs(c1)) * a + abs(c0)):
                break  # at the rounding of the quartic: far below the labels' margins
            if (p > 0.0) == (flo > 0.0):
                lo, flo = t, p
            else:
                hi, fhi = t, p
            dp = ((4.0 * c4 * t + 3.0 * c3) * t + 2.0 * c2) * t + c1
            tn = t - p / dp if dp != 0.0 else lo
            if not lo < tn < hi:  # Newton left the bracket: the secant of the bracket, else its middle
                tn = lo - flo * (hi - lo) / (fhi - flo)
                if not lo < tn < hi:
                    tn = 0.5 * (lo + hi)
            if hi - lo <= 1e-13 * (1.0 + a):
                break
            t = tn
        roots[n] = t
        n += 1
    return n


@njit
def _position_codes(Kn: np.ndarray, Wx: float, Wy: float, Wz: float, mz: np.ndarray, codes: np.ndarray,
                    sc: np.ndarray, guesses: int) -> int:
    """The (shoulder, elbow) codes ``10 s + e`` of the positions of the projected arm's Pieper
    solution (its general case: joints 1, 2 revolute, a quartic in joint 3) for the wrist centre W
    in the canonical chain's frame, as ``closed_form._pieper_position`` labels them, into ``codes``;
    their count, or −1 when unsure (:func:`_quartic_roots`; a label's quantity within
    ``LABEL_UNSURE`` of zero; a degenerate position). A position whose wrist cannot reach the
    orientation gets the code −1: the closed form gives it no row (``closed_form._wrist_angles``:
    with twists α₄, α₅ not right angles, cos θ₅ = (cos α₄ cos α₅ − m_z)/(sin α₄ sin α₅), m the
    target's z axis ``mz`` (3,) in the canonical chain's frame turned back through joints 1–3,
    must be within ±1 (the relaxed poses' solves give no fold starts); beyond by less than
    ``LABEL_UNSURE`` it is unsure: −1 returned). Scratch: sc
    rows 0–3 (≥ 5 columns; row 1 the roots, its first ``guesses`` those of a nearby pose on entry)."""
    cf = Kn[_cf._K_CF:_cf._K_C]
    Cm = Kn[_cf._K_C:_cf._K_PRE]
    nrows = int(Kn[_cf._K_CI + 4])
    rev3 = int(Kn[_cf._K_CI + 2]) == 1
    scale = cf[_cf._SCALE]
    h = Wz - cf[_cf._D1]
    r = Wx * Wx + Wy * Wy + h * h
    coeffs, ts = sc[0], sc[1]
    for j in range(5):
        acc = 0.0
        for k in range(nrows):
            mk = r * r if k == 0 else r if k == 1 else h * h if k == 2 else h if k == 3 else 1.0
            acc += mk * Cm[5 * k + j]
        coeffs[j] = acc
    nr = _quartic_roots(coeffs, ts, guesses, sc[2], sc[3])
    if nr < 0:
        return -1
    ca1, sa1, a1 = cf[_cf._CA], cf[_cf._SA], cf[_cf._A1]
    sa_, sb_ = 2.0 * a1, sa1
    if sa_ == 0.0 or sb_ == 0.0:
        return -1
    rxy = math.hypot(Wx, Wy)
    vsize = abs(cf[_cf._V]) + abs(cf[_cf._V + 1])
    ca4, sa4, ca5, sa5 = cf[_cf._CA + 3], cf[_cf._SA + 3], cf[_cf._CA + 4], cf[_cf._SA + 4]
    right_angles = ca4 == 0.0 and ca5 == 0.0  # then cos θ₅ = −m_z/(sin α₄ sin α₅): always within ±1
    k45 = sa4 * sa5
    if not right_angles and abs(k45) <= LABEL_UNSURE:
        return -1
    for i in range(nr):
        # the closed form's angles by their sines and cosines (no transcendental function): joint 3 from
        # t = tan(x₃/2); θ₂ = atan2(y, x) gives (cos, sin) = (x, y)/‖(x, y)‖; θ₁ = atan2(W_y, W_x) − atan2(g₂, g₁)
        # gives cos θ₁ W_x + sin θ₁ W_y = ‖W_xy‖ g₁/‖g‖: the shoulder label is the sign of g₁
        t = ts[i]
        if rev3:
            den = 1.0 / (1.0 + t * t)
            c3, s3 = (1.0 - t * t) * den, 2.0 * t * den
            x3 = 0.0
        else:
            c3, s3, x3 = 0.0, 0.0, t
        f1 = _cf._val(cf, _cf._F, x3, rev3, c3, s3)
        f2 = _cf._val(cf, _cf._F + 3, x3, rev3, c3, s3)
        f3 = _cf._val(cf, _cf._F + 6, x3, rev3, c3, s3)
        F3 = f3 + cf[_cf._D2]
        ra = r - _cf._val(cf, _cf._KA, x3, rev3, c3, s3)
        rb = h - ca1 * F3
        if f1 * f1 + f2 * f2 <= 1e-12 * scale * scale:
            return -1
        A, B = ra / sa_, rb / sb_
        y2, x2 = f1 * B - f2 * A, f1 * A + f2 * B
        n2 = math.sqrt(x2 * x2 + y2 * y2)
        if n2 <= LABEL_UNSURE * scale * scale:
            return -1
        c2, s2 = x2 / n2, y2 / n2
        u = s2 * f1 + c2 * f2
        g1, g2 = a1 + c2 * f1 - s2 * f2, ca1 * u - sa1 * F3
        g = math.sqrt(g1 * g1 + g2 * g2)
        if g <= LABEL_UNSURE * scale or rxy <= LABEL_UNSURE * scale or abs(g1) <= LABEL_UNSURE * g:
            return -1
        if rev3:
            e = s3 * cf[_cf._V] + c3 * cf[_cf._V + 1]
            if abs(e) <= LABEL_UNSURE * vsize:
                return -1
            e *= cf[_cf._A2] if cf[_cf._A2] != 0.0 else 1.0
            elbow = 0 if e > 0.0 else 1
        else:
            d = cf[_cf._D0 + 2] + x3
            if abs(d) <= LABEL_UNSURE * scale:
                return -1
            elbow = 2 if d >= 0.0 else 3
        sh = g1
        codes[i] = 10 * (0 if sh >= 0.0 else 1) + elbow
        if not right_angles:  # can the wrist reach the orientation from this position?
            # θ₁ = atan2(W_y, W_x) − atan2(g₂, g₁), θ₂ = atan2(y₂, x₂), θ₃: their cosines and sines
            c1, s1 = (Wx * g1 + Wy * g2) / (rxy * g), (Wy * g1 - Wx * g2) / (rxy * g)
            if not rev3:
                c3, s3 = math.cos(cf[_cf._TH0 + 2]), math.sin(cf[_cf._TH0 + 2])
            mx, my, m3 = mz[0], mz[1], mz[2]
            for j in range(3):  # m turned back through joint j's rotation θⱼ, then its twist αⱼ
                c = c1 if j == 0 else c2 if j == 1 else c3
                s = s1 if j == 0 else s2 if j == 1 else s3
                mx, my = c * mx + s * my, c * my - s * mx
                ca, sa = cf[_cf._CA + j], cf[_cf._SA + j]
                my, m3 = ca * my + sa * m3, ca * m3 - sa * my
            c5 = abs((ca4 * ca5 - m3) / k45)
            if c5 > 1.0 + LABEL_UNSURE:
                codes[i] = -1.0  # no wrist solution: no row
            elif c5 > 1.0 - LABEL_UNSURE:
                return -1
    return nr


@njit
def _trig_pair(a: float, b: float, c: float, sc: np.ndarray) -> int:
    """The cosines and sines of the roots of a cos θ + b sin θ = c (as ``closed_form._trig_roots``
    finds them, tolerance 1e-10) into sc[0:2] (cos) and sc[2:4] (sin), without an angle: their
    count, or −1 when unsure (the discriminant within ``LABEL_UNSURE`` of zero, relative: the count
    is 1 or 0 or 2 there)."""
    r2 = a * a + b * b
    if r2 < 1e-200:
        return -1
    disc = r2 - c * c
    if abs(disc) <= LABEL_UNSURE * r2:
        return -1
    if disc < 0.0:
        return 0
    sq = math.sqrt(disc)
    for k in range(2):  # θ = atan2(b, a) ± acos(c/√r2)
        w = sq if k == 0 else -sq
        sc[k], sc[2 + k] = (a * c - b * w) / r2, (b * c + a * w) / r2
    return 2


@njit
def _parallel_codes(cf: np.ndarray, T: np.ndarray, codes: np.ndarray, sc: np.ndarray) -> int:
    """The branch codes (shoulder·100 + elbow·10 + wrist) of the projected arm's three-parallel-axes
    solution (``closed_form._parallel_shoulders`` and ``_parallel_complete``) for the canonical
    chain's target T (4, 4), into ``codes``: their count, or −1 when unsure (a root count, a label's
    sign or the elbow's reach within ``LABEL_UNSURE`` of its boundary, relative; a singular wrist).
    The same conditions as the closed form, on the cosines and sines of its angles (no angle, no
    row): what a relaxed pose's solve would label, at a fraction of its cost. Scratch: sc (≥ 8)."""
    r00, r01, r02, px = T[0, 0], T[0, 1], T[0, 2], T[0, 3]
    r10, r11, r12, py = T[1, 0], T[1, 1], T[1, 2], T[1, 3]
    r20, r21, r22, pz = T[2, 0], T[2, 1], T[2, 2], T[2, 3]
    w6x, w6y, w6z = cf[_cf._PA_W6], cf[_cf._PA_W6 + 1], cf[_cf._PA_W6 + 2]
    Wx = r00 * w6x + r01 * w6y + r02 * w6z + px
    Wy = r10 * w6x + r11 * w6y + r12 * w6z + py
    Wz = r20 * w6x + r21 * w6y + r22 * w6z + pz
    ca1, sa1 = cf[_cf._CA], cf[_cf._SA]
    ca4, sa4, ca5, sa5 = cf[_cf._CA + 3], cf[_cf._SA + 3], cf[_cf._CA + 4], cf[_cf._SA + 4]
    a1, a2, a3, a4, a5 = cf[_cf._PA_A1], cf[_cf._PA_A2], cf[_cf._PA_A3], cf[_cf._PA_A4], cf[_cf._PA_A5]
    d1, d5, d6, sig = cf[_cf._PA_D1], cf[_cf._PA_D5], cf[_cf._PA_D6], cf[_cf._PA_SIG]
    right_angles = ca4 == 0.0 and ca5 == 0.0
    k45 = sa4 * sa5
    if a2 * a3 == 0.0 or k45 == 0.0:
        return -1
    n1 = _trig_pair(-sa1 * Wy, sa1 * Wx, cf[_cf._PA_KW] - ca1 * (Wz - d1), sc[0:4])
    if n1 < 0:
        return -1
    n = 0
    for i1 in range(n1):
        c1, s1 = sc[i1], sc[2 + i1]
        side = (c1 * Wx + s1 * Wy) * sa1
        if abs(side) <= LABEL_UNSURE * (abs(Wx) + abs(Wy)) * abs(sa1):
            return -1
        shoulder = 0 if side >= 0.0 else 1
        ux, uy, uz = sa1 * s1, -sa1 * c1, ca1
        utx = sig * (r00 * ux + r10 * uy + r20 * uz)
        uty = sig * (r01 * ux + r11 * uy + r21 * uz)
        utz = sig * (r02 * ux + r12 * uy + r22 * uz)
        rho = math.hypot(utx, uty)
        if rho <= LABEL_UNSURE:
            return -1  # a wrist singularity: θ₆ is the documented choice there, degenerate
        if right_angles:  # θ₅ = atan2(±ρ, −m_z/k): cos θ₅ ∝ −m_z/k, sin θ₅ ∝ ±ρ (‖·‖ > 0)
            c5r = -utz / k45
            h5 = math.sqrt(rho * rho + c5r * c5r)
            n5 = 2
            sc[4], sc[5], sc[6], sc[7] = c5r / h5, c5r / h5, rho / h5, -rho / h5
        else:
            n5 = _trig_pair(-k45, 0.0, utz - ca4 * ca5, sc[4:8])
            if n5 < 0:
                return -1
        for i5 in range(n5):
            c5, s5 = sc[4 + i5], sc[6 + i5]
            if abs(s5) <= LABEL_UNSURE:
                return -1
            wrist = 0 if s5 * k45 > 0.0 else 1
            vx, vy = s5 * sa4, ca5 * c5 * sa4 + sa5 * ca4
            nv = math.hypot(vx, vy)
            if nv <= LABEL_UNSURE:
                return -1
            # θ₆ = atan2(v_y, v_x) − atan2(ut_y, ut_x)
            c6, s6 = (vx * utx + vy * uty) / (nv * rho), (vy * utx - vx * uty) / (nv * rho)
            ox, oy, oz = -a4 * c5, a4 * s5, -d5
            ox, oy, oz = ox - a5, ca5 * oy + sa5 * oz, -sa5 * oy + ca5 * oz
            ox, oy, oz = c6 * ox + s6 * oy, -s6 * ox + c6 * oy, oz - d6
            O0 = px + r00 * ox + r01 * oy + r02 * oz - a1 * c1
            O1 = py + r10 * ox + r11 * oy + r12 * oz - a1 * s1
            O2 = pz + r20 * ox + r21 * oy + r22 * oz - d1
            x = c1 * O0 + s1 * O1
            y = -s1 * ca1 * O0 + c1 * ca1 * O1 + sa1 * O2
            c3 = (x * x + y * y - a2 * a2 - a3 * a3) / (2.0 * a2 * a3)
            if abs(abs(c3) - 1.0) <= LABEL_UNSURE:
                return -1
            if abs(c3) > 1.0:
                continue  # out of the planar arm's reach: no row
            for elbow in range(2):  # s₃ = ±√(1 − c₃²): a₂a₃s₃ > 0 is elbow 0, the other elbow 1
                if n == codes.shape[0]:
                    return -1
                codes[n] = shoulder * 100 + elbow * 10 + wrist
                n += 1
    return n


@njit(inline=True)
def _fold_code(code: float) -> tuple[float, bool]:
    """A row's branch code without the fold starts' ``closed_form.FOLD_CODE`` in its wrist digit,
    and whether it had it."""
    if int(code) % 10 >= _cf.FOLD_CODE:
        return code - _cf.FOLD_CODE, True
    return code, False


@njit(inline=True)
def _relax_frame(T: np.ndarray, shoulder: np.ndarray, C: np.ndarray) -> tuple[float, float, float, float, float,
                                                                                float]:
    """What the relaxed moves (``RELAX_MOVES``) at the tool pose T are made of: (v, h, dist, ρ) with v the
    vector from the shoulder point to the tool (dist its length), h its coordinate along joint 1's axis a
    (the z axis of the packed arm's first frame) and ρ the length of its part across it, ``v − h a``."""
    vx, vy, vz = T[0, 3] - shoulder[0], T[1, 3] - shoulder[1], T[2, 3] - shoulder[2]
    h = vx * C[_L + 2] + vy * C[_L + 6] + vz * C[_L + 10]
    dist2 = vx * vx + vy * vy + vz * vz
    return vx, vy, vz, h, math.sqrt(dist2), math.sqrt(dist2 - h * h if dist2 - h * h > 0.0 else 0.0)


@njit(inline=True)
def _relax_move(i: int, reach: float, h: float, dist: float, rho: float) -> tuple[bool, float, float]:
    """The i-th relaxed move ``reach (f_r u_r + f_l u_l)`` (u_r = v / dist, u_l = (v − h a) / ρ) written
    ``(c₁ + c₂) v − c₂ h a``: (defined, c₁, c₂); not defined where a direction it needs has no length
    (the generated C computes the same numbers in the same order)."""
    cr, cl = RELAX_MOVES[i][0] * reach, RELAX_MOVES[i][1] * reach
    if (cr != 0.0 and not dist > 0.0) or (cl != 0.0 and not rho > 0.0):
        return False, 0.0, 0.0
    return True, cr / dist if cr != 0.0 else 0.0, cl / rho if cl != 0.0 else 0.0


@njit
def _relax_mask(Kn: np.ndarray, method: int, T: np.ndarray, shoulder: np.ndarray, reach: float, m: int,
                codes: np.ndarray, degenerate: bool, sc: np.ndarray, C: np.ndarray) -> int:
    """Which relaxed poses (``RELAX_MOVES``; bit i for the i-th) can give a branch the pose's own m rows
    (branch ``codes``; ``degenerate``: one of them is) lack: all of them, except in Pieper's general
    case (joints 1, 2 revolute, a quartic in joint 3) when no row is degenerate; there, a relaxed
    pose is left out when every position of it (:func:`_position_codes`, each label sure) has a
    shoulder and elbow label that the rows have already, or a wrist that cannot reach the
    orientation (then the closed form gives it no row: a random Pieper arm's wrist, its twists not
    right angles, leaves one or three of the four positions at about a third of its poses). The
    relaxed solves would add nothing there (their wrist rows are the two regular flips). A random
    Pieper arm has two of its four positions at about half of its poses, far from any boundary:
    there the relaxed solves were most of the time. Scratch: sc (7, 6); C: the packed arm (joint 1's
    axis)."""
    every = (1 << len(RELAX_MOVES)) - 1
    if method != _cf.PIEPER or int(Kn[_cf._K_CI + 1]) != 0 or int(Kn[_cf._K_CI + 3]) != 4:
        return every
    if degenerate:
        return every
    px, py, pz, h, dist, rho = _relax_frame(T, shoulder, C)
    if dist == 0.0:
        return every
    ax, ay, az = C[_L + 2], C[_L + 6], C[_L + 10]
    # the wrist centre in the canonical chain's frame: W = pre · T · post · w6 (T⁻¹ when the chain is
    # reversed, as closed_form._target); a relaxed pose moves T's position by c₁ v + c₂ (v − h a)
    # (_relax_move), so W by c₁ dv + c₂ dl with dv = pre R v (reversed: −pre Rᵀ v), dl likewise; the
    # target's z axis there (the wrist's reach) is pre R post_z (reversed: pre Rᵀ post_z) at every relaxed pose
    pre = Kn[_cf._K_PRE:_cf._K_POST]
    post = Kn[_cf._K_POST:_cf._K_PQ]
    cf = Kn[_cf._K_CF:_cf._K_C]
    rev = int(Kn[_cf._K_CI + 5]) == 1
    x, v, z = sc[4, 0:3], sc[5, 0:3], sc[4, 3:6]
    vl = sc[3, 0:3]
    v0 = post[0] * cf[_cf._W6] + post[1] * cf[_cf._W6 + 1] + post[2] * cf[_cf._W6 + 2] + post[3]
    v1 = post[4] * cf[_cf._W6] + post[5] * cf[_cf._W6 + 1] + post[6] * cf[_cf._W6 + 2] + post[7]
    v2 = post[8] * cf[_cf._W6] + post[9] * cf[_cf._W6 + 1] + post[10] * cf[_cf._W6 + 2] + post[11]
    lx, ly, lz = px - h * ax, py - h * ay, pz - h * az
    for r in range(3):
        if rev:  # T⁻¹ v = Rᵀ (v − p); the move: −Rᵀ u
            x[r] = T[0, r] * (v0 - T[0, 3]) + T[1, r] * (v1 - T[1, 3]) + T[2, r] * (v2 - T[2, 3])
            v[r] = -(T[0, r] * px + T[1, r] * py + T[2, r] * pz)
            vl[r] = -(T[0, r] * lx + T[1, r] * ly + T[2, r] * lz)
            z[r] = T[0, r] * post[2] + T[1, r] * post[6] + T[2, r] * post[10]
        else:
            x[r] = T[r, 0] * v0 + T[r, 1] * v1 + T[r, 2] * v2 + T[r, 3]
            v[r] = px if r == 0 else py if r == 1 else pz
            vl[r] = lx if r == 0 else ly if r == 1 else lz
            z[r] = T[r, 0] * post[2] + T[r, 1] * post[6] + T[r, 2] * post[10]
    W0x = pre[0] * x[0] + pre[1] * x[1] + pre[2] * x[2] + pre[3]
    W0y = pre[4] * x[0] + pre[5] * x[1] + pre[6] * x[2] + pre[7]
    W0z = pre[8] * x[0] + pre[9] * x[1] + pre[10] * x[2] + pre[11]
    dx = pre[0] * v[0] + pre[1] * v[1] + pre[2] * v[2]
    dy = pre[4] * v[0] + pre[5] * v[1] + pre[6] * v[2]
    dz = pre[8] * v[0] + pre[9] * v[1] + pre[10] * v[2]
    ex = pre[0] * vl[0] + pre[1] * vl[1] + pre[2] * vl[2]
    ey = pre[4] * vl[0] + pre[5] * vl[1] + pre[6] * vl[2]
    ez = pre[8] * vl[0] + pre[9] * vl[1] + pre[10] * vl[2]
    mz = sc[5, 3:6]
    for r in range(3):
        mz[r] = pre[4 * r] * z[0] + pre[4 * r + 1] * z[1] + pre[4 * r + 2] * z[2]
    pc = sc[6]
    n = 0
    mask = 0
    for i in range(len(RELAX_MOVES)):
        defined, s, t = _relax_move(i, reach, h, dist, rho)
        if not defined or (i >= len(RELAX) and m > 0):
            continue  # (the sideways and corner moves: only for a pose without a start)
        n = _position_codes(Kn, W0x + s * dx + t * ex, W0y + s * dy + t * ey, W0z + s * dz + t * ez, mz, pc, sc,
                            max(n, 0))  # from the last roots
        if n < 0:
            mask |= 1 << i
            continue
        for j in range(n):
            if pc[j] < 0.0:
                continue  # no row: its wrist cannot reach the orientation
            have = False
            for r in range(m):
                if int(codes[r]) // 10 == int(pc[j]):
                    have = True
                    break
            if not have:
                mask |= 1 << i
                break
    return mask


@njit
def calibrated_solve_into(KC: np.ndarray, method: int, T: np.ndarray, wrist_ref: float, out: np.ndarray,
                          work: np.ndarray) -> int:
    """Every solution of the packed arm for the tip pose T (module docstring).

    KC: the packed arm ``C`` (:func:`pack_arm`) followed by the projected arm's packed closed-form
    constants ``Kn`` (:func:`robokit.kernels.closed_form.pack_constants`; one array: one argument to
    convert per call); method:
    ``closed_form.PIEPER`` or ``PARALLEL_AXES``; wrist_ref: the free joint's value at a singularity,
    in the sign of the projected arm's solver. Writes the solutions into ``out`` (MAX_ROWS,
    OUT_COLS) as the closed-form kernels do and each branch's outcome into ``work``'s rows
    ``BRANCH_ROWS`` (columns ``0:BRANCH_COLS``; code −1 past the last branch); work: :func:`scratch`.
    The rows of ``out`` past the number of solutions are scratch. Returns the number of solutions,
    plus ``FLAGGED`` when a branch merged or vanished or the near-singular search ran (σ ≤
    ``SIGMA_EXPLORE``); −1 when T fails the quick rigid-transform test. ``work[STATUS]`` then holds
    (merged branches, vanished branches, σ, the least |cos θ₅| − 1 of the positions whose wrist cannot
    reach the orientation): σ the smallest
    singular value of the scaled Jacobian (:func:`_null_direction`) at the points the near-singular
    search started from, ``inf`` when it did not run (no point needed it); the fourth ``inf`` where
    no wrist fell short (and for three parallel axes). One int, not a tuple: no tuple to box on every call (about
    40 ns; :meth:`robokit.ik.calibrated.CalibratedArm.solve` reads the status only when flagged)."""
    C, Kn = KC[:_LEN], KC[_LEN:]
    branches = work[BRANCH_ROWS]
    R = _cf.MAX_ROWS
    # work rows: 0–47 polish's scratch, 48–63 the starts (then the search points), 64–79 the
    # solutions, 80–82 q, q2, v, 83–88 the starts' branch codes (then the search points') and
    # degenerate flags (16 each), 89–95 the relaxed poses' scratch, 96–111 the branches, 112–143
    # the starts' sines and cosines, 144 the status
    nom = work[48:64]
    codes, degens = work[83:86].reshape(18), work[86:89].reshape(18)
    first = out  # the projected arm's rows, copied out below: out is written only at the end
    for r in range(R):
        branches[r, 0] = -1.0
    if not _cf._rigid(T):
        return -1
    # the projected arm's closed form (closed_form.pieper_solve_into's or parallel_axes_solve_into's
    # steps after its rigid-transform test), its scratch kept: the relaxed poses'
    # solves and the solutions' branch codes and flags reuse it (one set of allocations a call)
    ci_r, cf_r, C_r, post_r, T06, raw, rcodes, rdegen, qq, s_r = _cf._unpack(Kn, T)
    # Pieper's method: the least |cos θ₅| − 1 of the positions whose wrist cannot reach the
    # orientation (twists not right angles: closed_form._wrist_angles) into status[3], and the
    # fold starts (closed_form.FOLD_STARTS: status[4], their windows' factor, at least 1); at the relaxed
    # poses, none (row 95)
    status = work[STATUS]
    status[3], status[4] = math.inf, C[_FOLDS]
    fold = work[STATUS, 3:6]
    if method == _cf.PIEPER:
        m = _cf._pieper(ci_r, cf_r, C_r, T06, wrist_ref, raw, rcodes, rdegen, s_r, fold)
    else:
        m = _cf._parallel_axes(cf_r, T06, wrist_ref, raw, rcodes, rdegen, s_r, fold)
    m = _cf._finish(ci_r, post_r, raw, rcodes, rdegen, m, first, qq)
    degenerate = False
    # the branches' starts in order from row 0; the fold starts (closed_form.FOLD_STARTS) from row
    # R − 1 down, kept for the end: they are polished after every other start
    mb = 0
    nfold = 0
    for r in range(m):
        code, folded = _fold_code(first[r, 7])
        k = R - 1 - nfold if folded else mb
        for j in range(6):
            nom[k, j] = first[r, j]
        codes[k] = code
        if folded:
            degens[k] = 3.0
            nfold += 1
        else:
            degenerate = degenerate or first[r, 8] != 0.0
            degens[k] = first[r, 8]
            mb += 1
    m = mb
    shoulder = C[_SHOULDER:_REACH]
    reach = C[_REACH]
    # a branch missing: near the projected arm's workspace boundary, say; relaxed poses
    mask = _relax_mask(Kn, method, T, shoulder, reach, m, codes, degenerate, work[89:96], C) if m < GENERIC_ROWS else 0
    if mask != 0:
        Tr = np.empty((4, 4))
        # the closed form's own steps on its scratch: each relaxed pose's raw rows, finished (as a
        # solve of that pose finishes them) only when they hold a branch the starts lack
        pre_r, postT_r = Kn[_cf._K_PRE:_cf._K_POST].reshape((4, 4)), Kn[_cf._K_POST:_cf._K_PQ].reshape((4, 4))
        pc, pcs = work[89:91].reshape(12), work[91:93].reshape(12)
        fold_relaxed = work[95, 0:3]  # (the mask's scratch before)
        fold_relaxed[0], fold_relaxed[1] = math.inf, 0.0
        vx, vy, vz, h, dist, rho = _relax_frame(T, shoulder, C)
        ax, ay, az = C[_L + 2], C[_L + 6], C[_L + 10]
        for i in range(len(RELAX_MOVES)):
            defined, c1, c2 = _relax_move(i, reach, h, dist, rho)
            if not defined or (i >= len(RELAX) and m > 0):
                continue  # the sideways and corner moves only while the pose has no start (RELAX_MOVES)
            if (mask >> i) & 1 == 0:
                continue  # its rows are branches the starts have (_relax_mask)
            if m + nfold > R - 8:
                break  # as the generated C, whose rows (the fold starts' too) leave 8 free for a relaxed solve's
            for r in range(4):
                for c in range(4):
                    Tr[r, c] = T[r, c]
            Tr[0, 3] = T[0, 3] + ((c1 + c2) * vx - c2 * h * ax)
            Tr[1, 3] = T[1, 3] + ((c1 + c2) * vy - c2 * h * ay)
            Tr[2, 3] = T[2, 3] + ((c1 + c2) * vz - c2 * h * az)
            T06 = _cf._target(ci_r, pre_r, postT_r, Tr, s_r[1][0:4], s_r[1][4:8])
            if method == _cf.PIEPER:
                mr = _cf._pieper(ci_r, cf_r, C_r, T06, wrist_ref, raw, rcodes, rdegen, s_r, fold_relaxed)
            else:  # its labels first, without the rows (_parallel_codes); the rows only if one is new
                nc = _parallel_codes(cf_r, T06, pc, pcs)
                new = nc < 0
                for k in range(max(nc, 0)):
                    new = new or not _has_code(codes, m, pc[k])
                if not new:
                    continue
                mr = _cf._parallel_axes(cf_r, T06, wrist_ref, raw, rcodes, rdegen, s_r)
            new = False
            for k in range(mr):
                code, _ = _fold_code(float(rcodes[k, 0] * 100 + rcodes[k, 1] * 10 + rcodes[k, 2]))
                new = new or not _has_code(codes, m, code)
            if not new:
                continue  # every branch it gives, the starts have: its rows are not finished
            me = _cf._finish(ci_r, post_r, raw, rcodes, rdegen, mr, first, qq)
            for k in range(me):
                code, _ = _fold_code(first[k, 7])
                if m < R - nfold and not _has_code(codes, m, code):
                    for j in range(6):
                        nom[m, j] = first[k, j]
                    codes[m] = code
                    degens[m] = 2.0  # a start from a relaxed pose: its solution is flagged degenerate
                    m += 1
    # the fold starts last, in their order: their block (rows R − nfold … R − 1, the first at the end)
    # reversed in place, then moved down row by row (m ≤ R − nfold, so each row is read before a
    # later move writes over it: with more than (R − m) / 2 fold starts the two ranges overlap)
    for f in range(nfold // 2):
        a, b = R - nfold + f, R - 1 - f
        for j in range(6):
            nom[a, j], nom[b, j] = nom[b, j], nom[a, j]
        codes[a], codes[b] = codes[b], codes[a]
    for f in range(nfold):
        k = R - nfold + f
        for j in range(6):
            nom[m, j] = nom[k, j]
        codes[m], degens[m] = codes[k], 3.0
        m += 1
    return _polish_starts(C, T, m, out, work, ci_r, rcodes, rdegen, qq)


@njit(inline=True)
def _append(q: np.ndarray, code: int, rows: np.ndarray, rcodes: np.ndarray, rdegen: np.ndarray, ns: int) -> None:
    """Row ns ← a root the near-singular search found: q, its search point's branch code, degenerate."""
    for j in range(6):
        rows[ns, j] = q[j]
    rcodes[ns, 0] = code // 100
    rcodes[ns, 1] = (code // 10) % 10
    rcodes[ns, 2] = code % 10
    rdegen[ns] = True


@njit(inline=True)
def _dist2(a: np.ndarray, b: np.ndarray, rev: np.ndarray) -> float:
    """The squared distance of two joint vectors (revolute differences modulo 2π)."""
    dist = 0.0
    for j in range(6):
        d = a[j] - b[j]
        if rev[j] != 0.0:
            d = _cf._rem(d)
        dist += d * d
    return dist


@njit(inline=True)
def _double_root(rows: np.ndarray, ns: int, rev: np.ndarray) -> int:
    """Of an odd number ns of solutions (``rows``) of an arm whose joints are all revolute: ``keep · R
    + drop`` (R = ``MAX_ROWS``, keep < drop) for the closest two when they are closer than ``DOUBLE``
    in every joint (angles modulo 2π): one double root, reached twice; 0 otherwise (also where a
    joint is prismatic: no parity argument then)."""
    for j in range(6):
        if rev[j] == 0.0:
            return 0
    best, keep, drop = DOUBLE, 0, 0
    for b in range(1, ns):
        for a in range(b):
            d = 0.0
            for j in range(6):
                d = max(d, abs(_cf._rem(rows[a, j] - rows[b, j])))
            if d < best:
                best, keep, drop = d, a, b
    return keep * _cf.MAX_ROWS + drop


@njit(refcount=False, contract=True)
def _trace(C: np.ndarray, T: np.ndarray, start: np.ndarray, v0: np.ndarray, sign: float, work: np.ndarray,
           rows: np.ndarray, ns: int, limit: int, rev: np.ndarray, rcodes: np.ndarray, rdegen: np.ndarray,
           code: int) -> int:
    """Follow the curve of near-solutions from ``start`` (a point where the scaled Jacobian is near
    singular, v0 its near-null direction, ``sign`` the way): near a singular configuration the arm
    almost reaches T along a whole curve (at the singularity of the nominal structure, a self-motion),
    and the real arm's roots there are the points of that curve where the error vanishes, often
    0.5–3 rad from the closed form's. Each of ``TRACE_STEPS`` steps: a predictor step of
    ``TRACE_STEP`` along v, then ``TRACE_PULL`` Gauss–Newton corrections in the hyperplane across v
    (``(P J̃ᵀJ̃ P + v vᵀ) y = P J̃ᵀ F``, P = I − v vᵀ; J̃, F: velocity rows divided by the reach), v
    updated before the last one to the near-null direction of its J̃ (two steps of inverse iteration
    on ``J̃ᵀJ̃ + 1e-12 I`` from v, the sign kept along the curve; the Cholesky factor in place). Where the error's norm has a local minimum along the curve the
    point is polished (:func:`polish`, ``EXPLORE_MAX_STEPS``), a new root appended to ``rows`` (code
    ``code``, flagged degenerate) while ``ns < limit``. A point searched later that this curve passes
    is traced again all the same: near an exact singularity curves of near-solutions cross, and this
    one may have few steps left there (measured: 2 roots missed on 9,400 PUMA 560 and UR5 poses where
    such points were skipped, none otherwise; the mean per pose about 50 % higher).
    Returns the new ``ns``, plus ``FLAGGED`` when the curve closed (came back within ``TRACE_STEP`` of
    ``start``: the other way is the same curve). Scratch: ``work`` rows 0–47 (:func:`polish`'s) and
    148–152."""
    reach = C[_REACH]
    q, qp, v, vp, pt = work[148], work[149], work[150], work[151], work[152]
    Tq, J, H = work[0:4, 0:4], work[8:14], work[26:32]
    F, g, y, sc = work[38], work[40], work[41], work[43:45]
    tol_accept = C[_TOL_ACCEPT]
    explore_steps = EXPLORE_MAX_STEPS + 0 * ns
    for j in range(6):
        q[j] = start[j]
        v[j] = sign * v0[j]
    r1 = r2 = math.inf
    h2 = TRACE_STEP * TRACE_STEP
    for k in range(TRACE_STEPS):
        for j in range(6):
            qp[j] = q[j]
            q[j] += TRACE_STEP * v[j]
            vp[j] = v[j]
        r = 0.0
        for it in range(TRACE_PULL):
            _trig(C, q, sc)
            fk_jacobian(C, q, sc, Tq, J)
            _error(Tq, T, F)
            for i in range(3, 6):
                F[i] /= reach
                for c in range(6):
                    J[i, c] /= reach
            if it == TRACE_PULL - 1:
                # the curve's direction here: two steps of inverse iteration on J̃ᵀJ̃ + 1e-12 I from v,
                # its sign kept
                normal_equations(J, v, H, g)
                for i in range(6):
                    H[i, i] += 1e-12
                if not _cholesky_factor(H, H):
                    return ns
                for _ in range(2):
                    _cholesky_solve(H, v, y)
                    norm = 0.0
                    for i in range(6):
                        norm += y[i] * y[i]
                    norm = 1.0 / math.sqrt(norm)
                    for i in range(6):
                        v[i] = y[i] * norm
                d = 0.0
                for j in range(6):
                    d += v[j] * vp[j]
                if d < 0.0:
                    for j in range(6):
                        v[j] = -v[j]
            for i in range(6):  # J ← J P, P = I − v vᵀ
                acc = 0.0
                for c in range(6):
                    acc += J[i, c] * v[c]
                for c in range(6):
                    J[i, c] -= acc * v[c]
            normal_equations(J, F, H, g)
            for i in range(6):
                for c in range(6):
                    H[i, c] += v[i] * v[c]
                H[i, i] += 1e-12
            if not _cholesky_factor(H, H):
                return ns
            _cholesky_solve(H, g, y)
            r = 0.0
            for i in range(6):
                r += F[i] * F[i]
                q[i] += y[i]
        r = math.sqrt(r)
        if r1 < r2 and r1 <= r:  # the error's local minimum along the curve: at the previous point
            for j in range(6):
                pt[j] = qp[j]
            rot, pos, _ = polish(C, T, pt, explore_steps, work)
            if rot < tol_accept and pos < tol_accept and ns < limit and _find(pt, rows, ns, rev) < 0:
                _append(pt, code, rows, rcodes, rdegen, ns)
                ns += 1
        r2, r1 = r1, r
        if k >= 2 and _dist2(q, start, rev) < h2:
            return ns + FLAGGED
    return ns


@njit(refcount=False, contract=True)
def _polish_starts(C: np.ndarray, T: np.ndarray, m: int, out: np.ndarray, work: np.ndarray, ci_r: np.ndarray,
                   rcodes: np.ndarray, rdegen: np.ndarray, qq: np.ndarray) -> int:
    """Steps 2–7 of :func:`calibrated_solve_into` (module docstring) from its m starts (``work``'s
    rows 48–63; their branch codes and degenerate flags in rows 83–88): each polished, searched
    around where needed, the solutions written to ``out`` and each branch's outcome to ``work``'s
    branch rows; returns what that kernel returns. ``ci_r``, ``rcodes``, ``rdegen``, ``qq``: the
    projected arm's closed-form scratch (:func:`robokit.kernels.closed_form._unpack`), reused for
    the solutions' codes.

    A kernel of its own, without reference counting (``refcount=False``), :func:`_polish` copied
    into it (``inline``), its multiply-adds fused (``contract``, :func:`robokit.kernels._jit.njit`):
    the closed form before it allocates its scratch, so it needs numba's reference counting, which
    then counts every view and every array handed to a call up and down; here none is counted and the
    polish is no call. Measured on the UR5 in a compiled loop (the kernel alone, idle, median of 40
    poses): 6.3 µs a solve before, 6.0 µs as its own kernel (the same solutions to the bit on 900
    poses), 5.75 µs with the polish copied in and fused (5.95 µs fused but called: the copy costs
    about 18 s more of compiling, once per machine)."""
    branches = work[BRANCH_ROWS]
    nom = work[48:64]
    rows = work[64:80]
    q, q2, v = work[80], work[81], work[82]
    stall = work[152]  # (the trace's scratch, free until the search)
    codes, degens = work[83:86].reshape(18), work[86:89].reshape(18)
    seeded = work[145:148].reshape(18)  # per solution: a search point below already
    scs = work[153:185]  # per solution of a start: its sines and cosines (rows 2i, 2i + 1), for its σ bound
    R = _cf.MAX_ROWS
    post_q = C[_POST:_SHOULDER].reshape((5, 6))
    rev = post_q[1]
    tol_accept = C[_TOL_ACCEPT]
    max_steps = int(C[_MAX_STEPS])
    ns = 0
    sct, sc0 = work[112:144], work[43:45]
    _start_trig(C, nom, m, sct)
    # the points to explore around (near a singular pose): a solution the polish moved far from its
    # start, a branch that vanished (the point its polish reached), a singular choice of the nominal;
    # stored over the starts already polished (seed k ≤ start r), their branch codes over the codes
    # already read
    nseed = 0
    merged = 0
    vanished = 0
    nb = 0  # branch rows written
    nstall = 0  # search points where a polish stalled (the generated C keeps each in a row past the starts)
    for r in range(m):
        relaxed = degens[r] >= 2.0  # a relaxed pose's start, or a fold start (3)
        fold = degens[r] == 3.0
        for j in range(6):
            q[j] = nom[r, j]
            sc0[0, j] = sct[2 * r, j]
            sc0[1, j] = sct[2 * r + 1, j]
        steps = EXPLORE_MAX_STEPS if relaxed else max_steps
        rot, pos, _ = _polish(C, T, q, steps, work, False)
        moved = 0.0
        for j in range(6):
            moved = max(moved, abs(q[j] - nom[r, j]))
        ok = rot < tol_accept and pos < tol_accept
        k = _find(q, rows, ns, rev) if ok else -1
        degen = degens[r] != 0.0
        stalled = False  # the polish failed and the mirrored start reached a new root: where it stalled is searched
        if not ok or k >= 0:  # a root found already, or none: once more from the mirrored start
            for j in range(6):
                q2[j] = 2.0 * nom[r, j] - q[j]
            rot2, pos2, _ = polish(C, T, q2, steps, work)
            if rot2 < tol_accept and pos2 < tol_accept and _find(q2, rows, ns, rev) < 0:
                stalled = not ok and nstall < R - m
                if stalled:
                    nstall += 1
                for j in range(6):
                    stall[j] = q[j]
                    q[j] = q2[j]
                rot, pos, ok, k, degen = rot2, pos2, True, -1, True
            elif not ok and rot2 < tol_accept and pos2 < tol_accept:
                k = _find(q2, rows, ns, rev)
                rot, pos, ok = rot2, pos2, True
        code = int(codes[r])
        # searched around: a solution the polish moved far, merging branches, a singular choice of the
        # nominal, a branch that vanished (not one from a relaxed pose: that pose may be out of reach)
        point = (moved > EXPLORE or k >= 0 or (degen and not relaxed) or (not ok and not relaxed) or (fold and ok)
                 or stalled)
        if point:
            for j in range(6):
                nom[nseed, j] = stall[j] if stalled else q[j]
            codes[nseed] = code
            nseed += 1
            if k >= 0:
                seeded[k] = 1.0  # that solution is this search point
        if fold and not (ok and k < 0):
            continue  # a fold start that found no new root: not a branch of the nominal structure
        branches[nb, 0] = code
        branches[nb, 3] = rot
        branches[nb, 4] = pos
        if ok and k < 0:
            seeded[ns] = 1.0 if point and not stalled else 0.0
            for j in range(6):  # the last polish's (the one that reached q): rows 43–44
                scs[2 * ns, j], scs[2 * ns + 1, j] = work[43, j], work[44, j]
            _append(q, code, rows, rcodes, rdegen, ns)
            rdegen[ns] = degen
            branches[nb, 1] = SOLUTION
            branches[nb, 2] = ns
            ns += 1
        elif ok:  # two branches reach one root: the branches merge here
            rdegen[k] = True
            branches[nb, 1] = MERGED
            branches[nb, 2] = k
            merged += 1
        else:
            branches[nb, 1] = VANISHED
            branches[nb, 2] = -1
            vanished += 1
        nb += 1
    sigma = math.inf
    # an int64 like max_steps: the global constant itself would be typed Literal[int](25) and compile
    # a second polish for it
    explore_steps = EXPLORE_MAX_STEPS + 0 * max_steps
    # the branches' solutions are searched around too where the arm is near singular there: the first
    # one not searched already is checked; the others where it, or a search point, was near singular
    # (near a singular position of a wrist-partitioned arm every branch is)
    nsol = ns
    checked = False
    sigma_explore = C[_SIGMA]
    every = C[_EVERY] != 0.0  # each solution checked (an arm farther from its structure), not the first only
    for k in range(nseed + nsol):  # every root along the arm's near-singular direction and curve there
        if k < nseed:
            pending = nseed - k - 1  # the search points still to come (the C keeps them in its rows)
            for j in range(6):
                q2[j] = nom[k, j]
            code = int(codes[k])
        else:
            i = k - nseed
            if seeded[i] == 1.0:
                continue  # a search point above already
            pending = 0
            for j in range(6):
                q2[j] = rows[i, j]
            if sigma > sigma_explore:  # no point searched so far was near singular
                if checked and not every:
                    break  # the pose is not near a singular configuration: its other solutions are not either
                checked = True
                for j in range(6):  # its sines and cosines from its polish: no _trig
                    work[43, j], work[44, j] = scs[2 * i, j], scs[2 * i + 1, j]
                if _sigma_bound(C, q2, work, False) > sigma_explore:
                    if every:
                        continue  # this solution surely is not near a singular configuration
                    break  # surely not near a singular configuration (the common pose: a cheap bound says so)
            code = int(rcodes[i, 0] * 100 + rcodes[i, 1] * 10 + rcodes[i, 2])
        sk = _null_direction(C, q2, work, v)
        if sk > sigma_explore:
            continue  # not near a singular configuration: no other root nearby to look for
        sigma = min(sigma, sk)
        big = 0.0
        for j in range(6):
            big = max(big, abs(v[j]))
        for step in EXPLORE_STEPS:
            if ns == R:
                break
            for j in range(6):
                q[j] = q2[j] + step * (0.25 * math.pi / big) * v[j]
            rot, pos, _ = polish(C, T, q, explore_steps, work)
            if rot < tol_accept and pos < tol_accept and _find(q, rows, ns, rev) < 0:
                _append(q, code, rows, rcodes, rdegen, ns)
                ns += 1
        if R - ns - pending > TRACE_ROWS:  # the curve through it, both ways (one, if it closes)
            for sign in (1.0, -1.0):
                got = _trace(C, T, q2, v, sign, work, rows, ns, R - pending - TRACE_ROWS, rev, rcodes, rdegen, code)
                ns = got % FLAGGED
                if got >= FLAGGED:
                    break
    if ns % 2 == 1:  # an odd number: a root reached twice (a double root), or one missing (the caller's)
        drop = _double_root(rows, ns, rev)
        if drop > 0:
            keep = drop // R
            drop = drop % R
            rdegen[keep] = True
            for r in range(drop, ns - 1):
                for j in range(6):
                    rows[r, j] = rows[r + 1, j]
                rcodes[r, 0], rcodes[r, 1], rcodes[r, 2] = rcodes[r + 1, 0], rcodes[r + 1, 1], rcodes[r + 1, 2]
                rdegen[r] = rdegen[r + 1]
            ns -= 1
            for r in range(nb):
                if branches[r, 2] == drop:
                    branches[r, 1] = MERGED
                    branches[r, 2] = keep
                    merged += 1
                elif branches[r, 2] > drop:
                    branches[r, 2] -= 1
    ci_r[5] = 0  # not reversed: the solutions are in the robot's own joints already
    n = _cf._finish(ci_r, post_q, rows, rcodes, rdegen, ns, out, qq)
    status = work[STATUS]
    status[0], status[1], status[2] = merged, vanished, sigma
    return n + FLAGGED if merged or vanished or sigma <= sigma_explore else n


def solve_into_entry() -> Any:
    """The machine code of :func:`calibrated_solve_into` for the one set of argument types
    :class:`robokit.ik.calibrated.CalibratedArm` passes — KC (n,), T (4, 4), out and work 2-D, all
    float64 in C order, ``method`` a Python int, ``wrist_ref`` a Python float — as a
    callable without numba's type dispatch, or None while there is none (not compiled yet, or plain
    Python: then call the kernel itself). As :func:`robokit.kernels.closed_form.solve_into_entry`.

    Returns
    -------
    callable or None

    Examples
    --------
    >>> entry = solve_into_entry()
    >>> entry is None or callable(entry)
    True
    """
    return machine_code(calibrated_solve_into, "vimfmm")


@njit(parallel=True)
def calibrated_batch(KC: np.ndarray, method: int, Ts: np.ndarray, wrist_ref: float) -> tuple[np.ndarray, np.ndarray]:
    """:func:`calibrated_solve_into` over (N, 4, 4) poses, in parallel over the poses: (out (N,
    MAX_ROWS, OUT_COLS) with NaN rows past each count, counts (N,))."""
    N = Ts.shape[0]
    out = np.full((N, _cf.MAX_ROWS, _cf.OUT_COLS), np.nan)
    counts = np.zeros(N, dtype=np.int64)
    for i in prange(N):
        work = np.empty((_WORK_ROWS, 6))
        n = calibrated_solve_into(KC, method, Ts[i], wrist_ref, out[i], work)
        if n >= FLAGGED:
            n -= FLAGGED
        counts[i] = n
        for r in range(max(n, 0), _cf.MAX_ROWS):  # out[i] was the kernel's scratch before its rows
            for c in range(_cf.OUT_COLS):
                out[i, r, c] = np.nan
    return out, counts
