r"""Closed-form inverse kinematics of a general 6R arm (Raghavan–Roth elimination, Manocha–Canny
eigenproblem): every solution — at most 16 — of an arm with no special structure, such as the
Kinova Jaco's offset wrist.

Notation: the canonical DH chain of :mod:`robokit.ik._dh_chain`,
``T₀₆ = Z₁X₁Z₂X₂Z₃X₃Z₄X₄Z₅X₅Z₆`` with ``Zᵢ = Rz(θᵢ)Tz(dᵢ)`` and ``Xᵢ = Rx(αᵢ)Tx(aᵢ)`` (θᵢ the
joint's total angle, offset included), T₀₆ the target with base and tool removed.

1. **Loop equation.** Z₆ turns about and slides along its own z axis, so the z axis ``l`` of
   T₀₆ and the point ``p = o − d₆ l`` (o the origin of T₀₆) do not depend on θ₆. Splitting
   the chain after joint 2,

   ``X₂Z₃X₃Z₄X₄Z₅X₅ · (e_z, 0) = Z₂⁻¹X₁⁻¹Z₁⁻¹ · (l, p)``:

   a unit vector and a point whose left side depends on θ₃, θ₄, θ₅ and right side on θ₁, θ₂.
2. **The 14 equations.** Both sides are the same pair (l, p), so they have the same
   ``f(l, p) = (l, p, p·p, l·p, l×p, (p·p)l − 2(l·p)p)`` — 3 + 3 + 1 + 1 + 3 + 3 = 14
   scalars (Raghavan & Roth 1993). A rotation R maps f(l, p) linearly (vectors by R, scalars
   unchanged), and so does a translation t: ``p·p → p·p + 2t·p + t·t``, ``l·p → l·p + t·l``,
   ``l×p → l×p + l×t``, ``(p·p)l − 2(l·p)p → … + 2t×(l×p) + t²l − 2(l·p)t − 2(t·l)t`` (the
   products that would raise the degree combine into ``t×(l×p)``). Hence each side of the 14
   equations is linear in the products of (cos θᵢ, sin θᵢ, 1) of its joints:
   ``P(θ₃) · m₄₅ = Q · m₁₂`` with ``m₄₅ = (c₄,s₄,1)⊗(c₅,s₅,1)`` (9 monomials),
   ``m₁₂ = (c₁,s₁,1)⊗(c₂,s₂,1)`` without its constant (8), P (14 × 9) linear in c₃, s₃ — the
   arm's constants and the constant of the right side —, Q (14 × 8) fixed by the pose.
   The coefficients are built by chaining these linear maps along the chain (no symbolic
   algebra): P once per arm, Q per pose.
3. **Elimination of θ₁, θ₂.** With N the 6 × 14 left null space of Q (from its SVD),
   ``Σ(θ₃) m₄₅ = 0`` with ``Σ = N P`` (6 × 9). The half-angle substitution
   ``xᵢ = tan(θᵢ/2)`` (``cos θ = (1 − x²)/(1 + x²)``, ``sin θ = 2x/(1 + x²)``) and
   multiplication by ``(1 + x₄²)(1 + x₅²)`` give 6 equations in the monomials ``x₄ⁱx₅ʲ``
   (i, j ≤ 2); with the same 6 multiplied by x₄ these are 12 equations in the 12 monomials
   ``x₄ⁱx₅ʲ`` (i ≤ 3, j ≤ 2): ``(A x₃² + B x₃ + C) v = 0`` (12 × 12, entries quadratic in x₃).
   A solution needs ``det(A x² + B x + C) = 0``: a polynomial of degree 24 with the factor
   ``(1 + x²)⁴`` (the half-angle substitution's ±i), leaving the 16 of a general 6R arm. (The
   factor comes from θ₃'s rotation being the outermost map of its side — in the other readings
   below it is there when the eigenvalue joint is the farthest of its group from the eliminated
   joint, and absent otherwise; where present it is removed before the eigenvalue iteration,
   :func:`robokit.kernels.general_6r.deflate`.)
4. **Eigenproblem** (Manocha & Canny 1994). Instead of expanding the determinant, the
   quadratic matrix polynomial is linearised: ``[[0, I], [−C, −B]] z = x [[I, 0], [0, A]] z``
   with ``z = (v, x v)`` (24 × 24); the real eigenvalues are the x₃ of the solutions. The
   variable is turned by a fixed angle γ first (``θ₃ = 2 atan x + γ``) so that θ₃ = π is an
   ordinary point. With A regular this is the eigenproblem of the companion matrix
   ``[[0, I], [−A⁻¹C, −A⁻¹B]]``, solved by balancing, Hessenberg reduction and Francis
   double-shift QR steps (Golub & Van Loan §7.4–7.5; eigenvalues only); v at each real
   eigenvalue is the null vector of ``A x² + B x + C`` (inverse iteration). When A is close to
   singular (a solution near the half-angle's point at infinity) the variable is turned once
   more, ``x = (y + t)/(1 − t y)``: the same roots as angles, a regular leading matrix. When the
   pencil is singular for every x (a pose with a continuum of solutions for this reading), a
   tiny fixed perturbation of A makes it regular and its eigenvalues serve as candidates.
5. **Back-substitution.** θ₄, θ₅ from ratios of v's entries (as ``2 atan2(vᵢ₊₁, vᵢ)``, so
   that x = ∞ is θ = π), θ₁, θ₂ from ``m₁₂ = Q⁺ P(θ₃) m₄₅`` (least squares, 14 equations),
   θ₆ from ``Rz(θ₆) = (Z₁X₁⋯X₅ Tz(d₆))⁻¹ T₀₆``.
6. **Polish.** A few Newton–Raphson steps on the pose error with the geometric Jacobian
   bring every candidate to the pose to rounding; candidates that do not converge (complex
   roots with a small imaginary part, kept on purpose so that near-double real roots are not
   lost) are dropped, and solutions closer than 1e-7 rad in every joint are merged.

Numerics: lengths are divided by the DH table's size (Σ|aᵢ| + Σ|dᵢ|). The reading above (θ₆ eliminated, θ₁θ₂ on
one side, θ₃ the eigenvalue) is one of 36: the loop ``Z₁X₁ ⋯ Z₆ T₀₆⁻¹ = I`` can be read
cyclically from any joint j (θ_j eliminated), with the three-joint group before or after it
and any of its joints as the eigenvalue (:class:`_Arrangement`). Special neighbours make some
readings degenerate — on the Kinova Jaco every consecutive pair of axes meets or is parallel,
and with θ₃ as the eigenvalue ``det(A x² + B x + C)`` vanishes identically —, so all 36 are
scored once per arm (the conditioning of Q and of the pencil at random poses) and the best
solves; a pose badly conditioned for it (σ_min/σ_max of Q, of A or of the pencil at a fixed x
below 1e-4), or where its eigenvalue iteration does not converge (a multiple root the reading has
at every pose, as the xArm 6's best one), is also solved with the next three and the solutions
merged. The ranking is done
once, in the solver's constructor, and the best readings' tables are kept on it, packed for the
compiled solve: each pose is one call of :func:`robokit.kernels.general_6r.solve_pose` (matrix
build, elimination, eigenvalues, back-substitution, polish, merging and ordering).

Use through :func:`robokit.ik_analytic` (it picks this solver for a 6R arm that has neither
a spherical wrist nor three parallel axes); :class:`GeneralSixR` is the solver object.
"""
from __future__ import annotations

import math
from typing import TYPE_CHECKING, Any, Sequence

import numpy as np

from robokit.ik.solver import PositionBranch
from robokit.kernels.general_6r import (DEFLATE_MAX, RI_SIZE, T_CONVERGED, T_GAMMA, T_IMAG, T_POOR, T_READINGS,
                                        T_SAME, T_TURN, T_X0, fk_pose, fvec, jacobian, nullity_at_i, pencil,
                                        reading_matrices, score_reading, side_tensor, solve_pose)
from robokit.errors import InputError
from robokit.kernels import calibrated_ik as _kci
from robokit.kernels.calibrated_ik import pack_arm, polish, scratch

if TYPE_CHECKING:
    from robokit.ik._dh_chain import DHChain

__all__ = ["ArmPolish", "GeneralSixR", "PARALLEL_SIN", "PARALLEL_TURN", "parallel_run"]

_GAMMA = 0.6180339887498949  # rad: the θ₃ shift of the half-angle variable (any non-special value)
_IMAG_TOL = 1e-3  # an eigenvalue is a candidate when its imaginary part, as an angle, is below this
_CONVERGED = 1e-11  # pose error (scaled units) below which a polished candidate is a solution
_SAME = 1e-7  # rad: solutions this close in every joint are one
_X0 = 0.37  # where the pencil's regularity is measured (σ_min/σ_max of A x² + B x + C)
_POOR = 1e-4  # below this conditioning figure a pose is also solved with the next readings …
_EXTRA = 3  # … this many of them
_TURN = 1.1  # rad: the fixed turn of the half-angle variable where A is near singular (x = (y + t)/(1 − t y))
#: Three consecutive axes exactly parallel (each twist between them within ``PARALLEL_SIN`` of 0 or π in
#: its sine) make the eigenproblem degenerate (double and infinite roots: measured on the SO-ARM100,
#: whose axes 2–4 are parallel and whose axes 5 and 6 do not meet, so that no special method takes it:
#: about half the roots a numerical sweep finds were lost). For such an arm the elimination's tables are
#: built for the arm with the run's two twists turned by ``PARALLEL_TURN`` and ``-0.7 PARALLEL_TURN``
#: rad (an arm in general position, whose roots are within about the turn divided by the Jacobian's
#: smallest singular value of the arm's); the back-substitution's last joint and the Newton polish use
#: the arm itself, so every candidate converges to a root of the arm, and roots that two candidates
#: reach are merged as usual. Measured on 68 random arms with a run at each place, both conventions
#: (1,968 poses, a third with the run stretched out, where pairs of roots come close): with 1e-7 no root
#: of a 200-start sweep was lost; 1e-5 and 1e-6 lost close pairs at 3 poses, 1e-9 and 1e-10 at 5.
PARALLEL_SIN, PARALLEL_TURN = 1e-7, 1e-7


def _f_translate(t: np.ndarray) -> np.ndarray:
    """15 × 15 map of f(l, p) (with its trailing 1) under p → p + t."""
    tt = float(t @ t)
    tx = np.array([[0.0, -t[2], t[1]], [t[2], 0.0, -t[0]], [-t[1], t[0], 0.0]])
    F = np.eye(15)
    F[3:6, 14] = t
    F[6, 3:6] = 2.0 * t
    F[6, 14] = tt
    F[7, 0:3] = t
    F[8:11, 0:3] = -tx
    F[11:14, 8:11] = 2.0 * tx
    F[11:14, 0:3] = tt * np.eye(3) - 2.0 * np.outer(t, t)
    F[11:14, 7] = -2.0 * t
    return F


def _f_rotate_x(alpha: float) -> np.ndarray:
    """15 × 15 map of f(l, p) under the rotation Rx(α)."""
    c, s = math.cos(alpha), math.sin(alpha)
    R = np.array([[1.0, 0.0, 0.0], [0.0, c, -s], [0.0, s, c]])
    F = np.eye(15)
    for b in (0, 3, 8, 11):
        F[b:b + 3, b:b + 3] = R
    return F


class _Arrangement:
    """One way of writing the loop equation (eliminated joint j, the three-joint group on
    either side, its pivot joint), with the per-arm constant maps of both sides.

    The loop ``Z₁X₁ ⋯ X₅Z₆W = I`` with ``W = T₀₆⁻¹`` is read cyclically from just after
    ``Z_j``: ``R Z_j = I`` with ``R = L_j Z_{j+1} L_{j+1} ⋯ L_{j−1}`` (Lᵢ = Xᵢ, L₆ = W), so
    ``R (e_z, 0) = (e_z, −d_j e_z)``; R is cut into ``G₁G₂`` after the first n₁ joints:
    ``G₂ (e_z, 0) = G₁⁻¹ (e_z, −d_j e_z)``. j = 6, n₁ = 2 is the reading of the module
    docstring; the others are its cyclic re-indexings.
    """

    def __init__(self, el: "_Elimination", j: int, n1: int, piv: int) -> None:
        self.j, self.n1, self.piv = j, n1, piv
        J = [(j + t) % 6 for t in range(1, 6)]
        ez, ex = np.array([0.0, 0.0, 1.0]), np.array([1.0, 0.0, 0.0])
        al, a, d = el.alpha, el.a, el.d

        I15 = np.eye(15)
        Op = tuple[np.ndarray, int, np.ndarray]  # pre @ F(W)^w @ post (w = 0: pre alone)

        def const(M: np.ndarray) -> Op:
            return (M, 0, I15)

        def L(i: int, inverse: bool) -> Op:  # the link after joint i: Xᵢ, or W after joint 6
            if i == 5:
                return (I15, -1 if inverse else 1, I15)
            if inverse:
                return const(_f_rotate_x(-al[i]) @ _f_translate(-a[i] * ex))
            return const(_f_translate(a[i] * ex) @ _f_rotate_x(al[i]))

        def comp(X: Op, Y: Op) -> Op:  # X applied after Y
            if X[1] != 0:
                return (X[0], X[1], X[2] @ Y[0])
            if Y[1] != 0:
                return (X[0] @ Y[0], Y[1], Y[2])
            return const(X[0] @ Y[0])

        def Tz(dz: float) -> Op:
            return const(_f_translate(dz * ez))

        # side 1: G₁⁻¹ (e_z, −d_j e_z): L_j⁻¹, Rz(−θ_{J0}), Tz(−d_{J0}) then L_{J0}⁻¹, Rz(−θ_{J1}), …
        ops1 = [L(j, True)]
        for t in range(1, n1):
            ops1.append(comp(L(J[t - 1], True), Tz(-d[J[t - 1]])))
        ops1.append(Tz(-d[J[n1 - 1]]))
        joints1 = J[:n1]
        # side 2: G₂ (e_z, 0): L_{J4} then Tz(d_{J4}), Rz(θ_{J4}), L_{J3}, Tz, Rz, …, L_{J[n1−1]}
        rest = J[n1:][::-1]
        ops2 = [comp(Tz(d[i]), L(i, False)) for i in rest] + [L(J[n1 - 1], False)]
        joints2 = rest
        self.sides = [(ops1, np.array([-1.0] * n1), joints1), (ops2, np.array([1.0] * len(rest)), joints2)]
        f1 = np.zeros(15)
        fvec(0.0, 0.0, 1.0, 0.0, 0.0, -d[j], f1)
        f2 = np.zeros(15)
        fvec(0.0, 0.0, 1.0, 0.0, 0.0, 0.0, f2)
        self.fstart = [f1, f2]
        three = 0 if n1 == 3 else 1
        self.three, self.two = three, 1 - three
        o = self.sides[three][2]
        self.pivot = o[piv]
        self.others = [o[k] for k in range(3) if k != piv]
        self.pair = list(self.sides[self.two][2])
        self.roles = np.array([self.pivot, *self.others, *self.pair, j], dtype=np.int64)
        # per side: the stacked maps, and where the target's W sits (index, pre, inverse?, post)
        self.Ms: list[np.ndarray] = []
        self.w_at: list[tuple[int, np.ndarray, bool, np.ndarray] | None] = []
        for ops, _, _ in self.sides:
            self.Ms.append(np.ascontiguousarray(np.stack([pre for pre, _, _ in ops])))
            at = [(i, pre, w < 0, post) for i, (pre, w, post) in enumerate(ops) if w != 0]
            self.w_at.append(at[0] if at else None)
        #: how many eigenvalue pairs x = ±i the solve removes before its eigenvalue iteration (the
        #: null space of A x² + B x + C at x = i at ordinary poses; set by _Elimination for the
        #: readings it keeps, 0 until then: no deflation tried)
        self.deflate = 0
        self._packed = self.packed()

    def nullity_at_i(self, T06s: np.ndarray) -> int:
        """The dimension of the null space of ``A x² + B x + C`` at x = i for the scaled pose
        T06s: 4 when the pivot is the joint of its group farthest from the eliminated one (the
        ``(1 + x²)⁴`` of the determinant), else 0 — or more on special arms and poses."""
        P, r = self.matrices(T06s)
        work = np.empty((3, 12, 12))
        pencil(P, r, math.cos(_GAMMA), math.sin(_GAMMA), work, np.empty((3, 14, 9)), np.empty((8, 14)))
        return int(nullity_at_i(work))

    def tables(self) -> dict[str, Any]:
        """This reading's per-arm tables (the items of ``export_constants()["arrangements"]``)."""
        w_side = 0 if self.w_at[0] is not None else 1
        c_side = 1 - w_side
        const = np.empty((3 ** len(self.sides[c_side][1]), 15))
        side_tensor(self.Ms[c_side], self.sides[c_side][1], self.fstart[c_side], const)
        at = self.w_at[w_side]
        assert at is not None
        i, pre, inverse, post = at
        # the row of the three-joint side's tensor G3 (rows i₀ + 3 i₁ + 9 i₂ over the group's joints
        # in order) behind P[i, :, m] (pivot basis i, then the other two joints' monomial m), and of
        # the two-joint side's G2 behind r[:, m] (m = 3 i_d + i_e, rows of G2 i_e + 3 i_d)
        weight = (1, 3, 9)
        b, c = [k for k in range(3) if k != self.piv]
        perm3 = [ip * weight[self.piv] + ib * weight[b] + ic * weight[c]
                 for ip in range(3) for ib in range(3) for ic in range(3)]
        perm2 = [i_d + 3 * i_e for i_d in range(3) for i_e in range(3)]
        return {"roles": self.roles.copy(), "three_has_w": w_side == self.three, "const": const,
                "Ms": self.Ms[w_side].copy(), "w_index": int(i), "w_inverse": bool(inverse), "pre": pre.copy(),
                "post": post.copy(), "signs": self.sides[w_side][1].copy(), "f": self.fstart[w_side].copy(),
                "perm3": np.array(perm3, dtype=np.int64), "perm2": np.array(perm2, dtype=np.int64),
                "deflate": int(self.deflate)}

    def packed(self) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """The tables as the compiled kernels take them (:mod:`robokit.kernels.general_6r`):
        ri (46,) int, mats (6, 15, 15), const (27, 15), vec (18,)."""
        t = self.tables()
        nw = len(t["signs"])
        ri = np.zeros(RI_SIZE, dtype=np.int64)
        ri[:6] = t["roles"]
        ri[6:10] = [int(t["three_has_w"]), nw, t["w_index"], int(t["w_inverse"])]
        ri[10:37] = t["perm3"]
        ri[37:46] = t["perm2"]
        ri[46] = t["deflate"]
        mats = np.zeros((6, 15, 15))
        mats[:nw + 1] = t["Ms"]
        mats[4], mats[5] = t["pre"], t["post"]
        const = np.zeros((27, 15))
        const[:len(t["const"])] = t["const"]
        vec = np.zeros(18)
        vec[:nw] = t["signs"]
        vec[3:] = t["f"]
        return ri, mats, const, vec

    def matrices(self, T06s: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(P (3, 15, 9), r (15, 9)) of the pose: the three-joint side with the pivot first
        and the two-joint side (:func:`robokit.kernels.general_6r.reading_matrices`)."""
        P, r = np.empty((3, 15, 9)), np.empty((15, 9))
        reading_matrices(np.ascontiguousarray(T06s, dtype=float), *self._packed, P, r)
        return P, r


def parallel_run(alpha: np.ndarray) -> int | None:
    """The first joint (0-based) of three consecutive axes exactly parallel — twists ``alpha[i]`` and
    ``alpha[i + 1]`` of the canonical chain both within ``PARALLEL_SIN`` of 0 or π in their sines — or None.

    Parameters
    ----------
    alpha : (5,) array
        The canonical chain's twists (rad).

    Returns
    -------
    int or None

    Examples
    --------
    >>> import math, numpy as np
    >>> parallel_run(np.array([math.pi / 2, 0.0, 0.0, math.pi / 2, -math.pi / 2]))  # axes 2–4 (a UR arm)
    1
    >>> parallel_run(np.array([math.pi / 2, 0.0, 1e-3, math.pi / 2, -math.pi / 2])) is None
    True
    """
    for i in range(len(alpha) - 1):
        if abs(math.sin(alpha[i])) < PARALLEL_SIN and abs(math.sin(alpha[i + 1])) < PARALLEL_SIN:
            return i
    return None


class _Elimination:
    """The per-arm constants (lengths divided by ``scale``) and the chosen arrangements."""

    def __init__(self, chain: DHChain, scale: float) -> None:
        true_alpha = np.ascontiguousarray(chain.alpha, dtype=float)
        #: the first joint (0-based) of a run of three exactly parallel axes, or None (PARALLEL_TURN)
        self.parallel_run = parallel_run(true_alpha)
        # the readings' tables are built for the arm with that run turned (PARALLEL_TURN); the chain
        # the solve back-substitutes and polishes on is the arm itself (restored below)
        self.alpha = true_alpha.copy()
        if self.parallel_run is not None:
            self.alpha[self.parallel_run] += PARALLEL_TURN
            self.alpha[self.parallel_run + 1] -= 0.7 * PARALLEL_TURN
        self.a = np.ascontiguousarray(chain.a, dtype=float) / scale
        self.d = np.ascontiguousarray(chain.d0, dtype=float) / scale
        self.th0 = np.asarray(chain.th0, dtype=float)
        # score every arrangement on a few poses; keep them best first
        rng = np.random.default_rng(2024)
        poses = []
        for _ in range(3):
            T = np.empty((4, 4))
            fk_pose(self.alpha, self.a, self.d, rng.uniform(-math.pi, math.pi, 6), T)
            poses.append(T)
        scored = []
        for j in range(6):
            for n1 in (2, 3):
                for piv in range(3):
                    arr = _Arrangement(self, j, n1, piv)
                    score = min(score_reading(T, *arr._packed, _GAMMA, _X0) for T in poses)
                    scored.append((score, j, n1, piv, arr))
        scored.sort(key=lambda t: -t[0])
        self.arrangements = [t[4] for t in scored]
        self.scores = [t[0] for t in scored]
        # the readings used: the eigenvalue pairs x = ±i that each pose's solve may remove (the
        # null space at x = i has the same dimension at every ordinary pose: the smallest seen)
        for arr in self.arrangements[:_EXTRA + 1]:
            arr.deflate = min(DEFLATE_MAX, min(arr.nullity_at_i(T) for T in poses))
            arr._packed = arr.packed()
        # what the compiled solve takes (robokit.kernels.general_6r.solve_pose): the chain (the arm's
        # own, not the turned one), the tolerances and the tables of the readings it may use, best first
        self.alpha = true_alpha
        self.kchain = np.zeros((4, 6))
        self.kchain[0, :5], self.kchain[1, :5], self.kchain[2], self.kchain[3] = self.alpha, self.a, self.d, self.th0
        self.ktol = np.zeros(8)
        self.ktol[[T_GAMMA, T_TURN, T_IMAG, T_CONVERGED, T_SAME, T_X0, T_POOR, T_READINGS]] = [
            _GAMMA, math.tan(0.5 * _TURN), _IMAG_TOL, _CONVERGED, _SAME, _X0, _POOR, _EXTRA + 1]
        used = [arr._packed for arr in self.arrangements[:_EXTRA + 1]]
        ri, mats, const, vec = (np.ascontiguousarray(np.stack([u[k] for u in used])) for k in range(4))
        self.kreadings = (ri, mats, const, vec)


#: :class:`ArmPolish`: Newton on the arm's own kinematics stops below this orientation (rad) and position (m)
#: error, accepts a solution below ``ARM_ACCEPT``, takes at most ``ARM_STEPS`` steps per solution (the
#: calibrated path's numbers, :mod:`robokit.ik.calibrated`).
ARM_STOP, ARM_ACCEPT, ARM_STEPS = 1e-12, 1e-10, 30


class ArmPolish:
    """The general 6R method's solutions finished on the arm's own product of exponentials, for an arm
    whose DH table does not reproduce it to the precision its solutions need.

    Where two consecutive axes are nearly but not exactly parallel, the DH table's offsets are
    kilometres of opposite signs (the Kinova Gen3 lite as Kinova publishes it: axes 2 and 3 7.3e-6 rad
    apart, d₂ ≈ d₃ ≈ −38 km). The table's numbers, rounded at that size (its twist α₂ to 4e-16 rad,
    times 38 km), describe the arm only to about 1e-11 m — measured against Pinocchio, also when the
    table is evaluated in 40-digit arithmetic —, and the method's Newton polish on that chain reaches
    the arm's pose only as closely. Near a singular configuration (the Jacobian's smallest singular
    value σ) that is a joint error of about 1e-11 m / σ: within 2e-4 rad of the Gen3 lite's elbow
    singularity, solutions 1e-7 to 3e-6 rad from the configuration that generated the pose, and two
    polished copies of one root, not merged (an odd number of solutions). This polish, on the arm's
    PoE rewritten with one frame per joint axis (:func:`robokit.kernels.calibrated_ik.pack_arm`: no
    parameter grows where axes are nearly parallel), finishes each solution to ``ARM_STOP``; copies
    that reach one root (``_SAME``, angles modulo 2π) are merged, and a row whose polish does not
    reach ``ARM_ACCEPT`` is dropped: no root of the arm is there. (The method accepts a candidate
    whose pose error is below 1e-11 of the DH table's size — 7.6e-7 m for the Gen3 lite —; near the
    elbow singularity such a row can be the bottom of the error's valley between the two roots of a
    fold, 3.5e-10 m off the pose on the arm and 1e-7 from singular, measured.)

    Parameters
    ----------
    M : (4, 4) array
        The tip's pose at q = 0 in the base frame (m).
    Slist : (6, 6) array
        Space screw axes (ω; v) as columns.
    revolute : (6,) sequence of bool
        Which joints are revolute (their values compared modulo 2π).

    Examples
    --------
    >>> import numpy as np, robokit
    >>> robot = robokit.load("puma560")
    >>> arm = ArmPolish(robot.poe.M, robot.poe.Slist, [True] * 6)
    >>> q = np.array([0.1, 0.2, 0.3, 0.4, 0.5, 0.6])
    >>> rows = arm.finish(robot.frame_pose(q), [(q + 1e-6, "solution 1 of 2", False), (q, "solution 2 of 2", False)])
    >>> len(rows), rows[0][1], float(np.abs(np.asarray(rows[0][0]) - q).max()) < 1e-12
    (1, 'solution 1 of 1', True)
    """

    def __init__(self, M: np.ndarray, Slist: np.ndarray, revolute: Sequence[bool]) -> None:
        post_q = np.zeros((5, 6))
        post_q[0] = 1.0
        post_q[1] = [1.0 if r else 0.0 for r in revolute]
        post_q[2], post_q[3] = -np.inf, np.inf
        M = np.ascontiguousarray(M, dtype=float)
        reach = max(1e-3, float(np.linalg.norm(M[:3, 3])))  # (the relaxed poses' scale: unused by polish)
        self._C = pack_arm(M, np.ascontiguousarray(Slist, dtype=float), post_q, np.zeros(3), reach,
                           ARM_STOP, ARM_ACCEPT, ARM_STEPS)
        self._work = scratch()
        self._revolute = [bool(r) for r in revolute]

    def export_constants(self) -> dict[str, Any]:
        """The numbers the generated C's copy of this polish needs (:mod:`robokit.codegen.ik_general`):
        the polish's tolerances and steps (``tol_stop``, ``tol_accept``, ``max_steps``), the merge's
        ``same`` (rad), which joints are ``revolute``, the kernel's constants of
        :func:`robokit.kernels.calibrated_ik.polish` (``log_near``, ``second_order``, ``block_axes``,
        ``block_schur``, ``max_step``) and the arm's local transforms (``frames`` (7, 3, 4):
        :func:`robokit.kernels.calibrated_ik.local_transforms`, ``kinds`` 0/1 revolute/prismatic,
        ``pitches``), as :meth:`robokit.ik.calibrated.CalibratedArm.export_constants` names them.

        Returns
        -------
        dict
            The constants, keyed as above.

        Examples
        --------
        >>> import robokit
        >>> robot = robokit.load("puma560")
        >>> c = ArmPolish(robot.poe.M, robot.poe.Slist, [True] * 6).export_constants()
        >>> c["tol_accept"], c["max_steps"], c["frames"].shape
        (1e-10, 30, (7, 3, 4))
        """
        C = self._C
        return {"tol_stop": ARM_STOP, "tol_accept": ARM_ACCEPT, "max_steps": ARM_STEPS, "same": _SAME,
                "revolute": list(self._revolute), "log_near": _kci.LOG_NEAR,
                "second_order": tuple(_kci.SECOND_ORDER), "block_axes": _kci.BLOCK_AXES,
                "block_schur": _kci.BLOCK_SCHUR, "max_step": _kci.MAX_STEP, "frames": _kci.local_transforms(C),
                "kinds": C[_kci.KINDS].astype(int).tolist(), "pitches": C[_kci.PITCHES].tolist()}

    def _same(self, x: np.ndarray, y: np.ndarray) -> bool:
        d = x - y
        for i, rev in enumerate(self._revolute):
            if rev:
                d[i] = math.remainder(float(d[i]), 2.0 * math.pi)
        return bool(np.abs(d).max() < _SAME)

    def finish(self, T: np.ndarray, rows: Sequence[tuple[Sequence[float], str, bool]]
               ) -> list[tuple[Sequence[float], str, bool]]:
        """Each row's q polished on the arm for the tip pose T; rows whose polish does not reach
        ``ARM_ACCEPT`` dropped, rows that reach one root merged (the first kept, flagged degenerate
        when a merged one was) and labelled ``"solution k of m"`` anew.

        Parameters
        ----------
        T : (4, 4) array
            The tip's target pose in the base frame (m).
        rows : sequence of (q (6,), label, degenerate)
            The general 6R method's solutions in the arm's joint values (rad).

        Returns
        -------
        list of (q, label, degenerate)
            In the order of ``rows``; a label's ``"solution k of m"`` renumbered, the rest of it kept.
        """
        Td = np.ascontiguousarray(T, dtype=float)
        kept: list[list[Any]] = []
        for q_in, label, degen in rows:
            q = np.array(q_in, dtype=float)
            rot, pos, _ = polish(self._C, Td, q, ARM_STEPS, self._work)
            if not (rot < ARM_ACCEPT and pos < ARM_ACCEPT):
                continue  # no root of the arm here: a near miss of the table's chain (see the class docstring)
            for k in kept:
                if self._same(k[0], q):
                    k[2] = k[2] or bool(degen)
                    break
            else:
                kept.append([q, label, bool(degen)])
        m = len(kept)
        out: list[tuple[Sequence[float], str, bool]] = []
        for number, (q, label, degen) in enumerate(kept, 1):
            head, sep, tail = label.partition(" of ")
            if head.startswith("solution ") and sep:
                digits = len(tail) - len(tail.lstrip("0123456789"))
                label = f"solution {number} of {m}{tail[digits:]}"
            out.append((q.tolist(), label, degen))
        return out


class GeneralSixR:
    """Every closed-form IK solution of a 6R arm in general position (see the module docstring).

    Build once per arm with :meth:`from_chain`; :meth:`solve` returns, for a target ``T₀₆``
    of the canonical chain, the solutions as ``(q, label, degenerate)`` rows (q: joint values
    in rad, offsets removed), as the other closed-form solvers do. Users normally call
    :func:`robokit.ik_analytic`, which builds this solver for a general 6R arm, caches it on
    the robot and turns the rows into :class:`robokit.ik.IKSolution` objects.

    Parameters
    ----------
    chain : DHChain
        The arm's canonical chain (:mod:`robokit.ik._dh_chain`); any 6-joint chain is accepted,
        and :meth:`refusal` says whether the method applies.

    Examples
    --------
    >>> import numpy as np
    >>> from robokit.description.dh import DHLink, DHTable
    >>> from robokit.ik._dh_chain import DHChain
    >>> rng = np.random.default_rng(3)
    >>> table = DHTable("g", "standard", tuple(DHLink("R", a=rng.uniform(-.5, .5), alpha=rng.uniform(-3, 3),
    ...                                               d=rng.uniform(-.5, .5)) for _ in range(6)))
    >>> chain = DHChain(table)
    >>> solver = GeneralSixR.from_chain(chain)
    >>> q = np.array([0.1, 0.2, 0.3, 0.4, 0.5, 0.6])
    >>> rows = solver.solve(chain.fk6(q))
    >>> min(float(np.abs(np.asarray(r[0]) - q).max()) for r in rows) < 1e-9
    True
    """

    #: what ``ik_analytic_kind`` adds to the reason when this solver takes an arm
    REASON = "; the general 6R method applies (Raghavan–Roth elimination, up to 16 solutions)"

    #: the structure's name, as :func:`robokit.ik_analytic_kind` reports it
    method = "general 6R"

    def __init__(self, chain: DHChain) -> None:
        """Any 6-joint chain is accepted; :meth:`refusal` says whether the method applies. When it
        does, the elimination's per-arm constants are built here, once: the 36 readings of the
        loop equation are scored and the best ones kept with the solver (:attr:`elim`)."""
        self.chain = chain
        # lengths are divided by the DH table's own size, not the arm's (chain.scale): where two
        # axes are nearly parallel the table's offsets are kilometres, and its products round at
        # that size (the Kinova Gen3 lite: 38 km; near its elbow singularity the polish then
        # reaches 1e-11 of the arm's size too rarely, and solutions were lost)
        self.scale = max(1e-3, float(chain.dh_length))
        self._why = self.refusal_of(chain)
        self._elim = None if self._why is not None else _Elimination(chain, self.scale)

    @property
    def parallel_run(self) -> int | None:
        """The first joint (0-based) of three consecutive exactly parallel axes, whose twists the
        elimination's tables are built turned (``PARALLEL_TURN``), or None (also when the method does
        not apply)."""
        return None if self._elim is None else self._elim.parallel_run

    @property
    def elim(self) -> "_Elimination":
        """The per-arm constants of the elimination (the readings ranked best first); raises
        :class:`~robokit.errors.InputError` when the method does not apply to the chain."""
        if self._elim is None:
            raise InputError(f"robot: {self._why}")
        return self._elim

    def refusal(self) -> str | None:
        """None when the general 6R method applies to this chain, else the reason (see
        :meth:`refusal_of`).

        Returns
        -------
        str or None
            The answer :meth:`refusal_of` gave for this chain when the solver was built.

        Examples
        --------
        >>> import robokit
        >>> from robokit.ik._dh_chain import DHChain
        >>> GeneralSixR(DHChain(robokit.load("puma560").dh)).refusal() is None
        True
        """
        return self._why

    @staticmethod
    def refusal_of(chain: DHChain) -> str | None:
        """Why the general 6R method does not apply to ``chain``, or None when it does.

        It needs six revolute joints whose axes are independent somewhere: an arm whose 6 × 6
        Jacobian is rank-deficient at every configuration (two axes coincide, …) has a
        continuum of solutions, not a finite set. The Jacobian is checked at four fixed
        pseudo-random configurations (smallest / largest singular value above 1e-9).

        Parameters
        ----------
        chain : DHChain
            The canonical chain of the arm.

        Returns
        -------
        str or None
            None when the chain has six joints, all revolute, with axes independent somewhere;
            else one sentence naming the first of these conditions that fails.

        Examples
        --------
        >>> import robokit
        >>> from robokit.ik._dh_chain import DHChain
        >>> GeneralSixR.refusal_of(DHChain(robokit.load("puma560").dh)) is None  # six independent axes
        True
        """
        if chain.n != 6:
            return f"the general 6R method needs 6 joints, the arm has {chain.n}"
        if any(k != "R" for k in chain.kinds):
            j = 1 + list(chain.kinds).index("P")
            return f"the general 6R method needs revolute joints, joint {j} is prismatic"
        scale = max(1e-3, float(chain.dh_length))
        al = np.ascontiguousarray(chain.alpha, dtype=float)
        a = np.ascontiguousarray(chain.a, dtype=float) / scale
        d = np.ascontiguousarray(chain.d0, dtype=float) / scale
        rng = np.random.default_rng(12345)
        T, J = np.empty((4, 4)), np.empty((6, 6))
        for _ in range(4):
            th = rng.uniform(-math.pi, math.pi, 6)
            fk_pose(al, a, d, th, T)
            jacobian(al, a, d, th, T, J)
            sv = np.linalg.svd(J, compute_uv=False)
            if sv[-1] > 1e-9 * sv[0]:
                return None
        return ("the joint axes are dependent at every configuration (the 6 × 6 Jacobian is singular "
                "everywhere), so a pose has a continuum of solutions")

    @classmethod
    def from_chain(cls, chain: DHChain) -> "GeneralSixR":
        """The solver of a canonical DH chain of six revolute joints.

        Parameters
        ----------
        chain : DHChain
            The arm (:mod:`robokit.ik._dh_chain`), six revolute joints.

        Returns
        -------
        GeneralSixR
            ``cls(chain)``: the elimination's constants are computed here, once per arm (none when
            :meth:`refusal_of` refuses the chain).

        Examples
        --------
        >>> import robokit
        >>> from robokit.ik._dh_chain import DHChain
        >>> len(GeneralSixR.from_chain(DHChain(robokit.load("puma560").dh)).elim.arrangements)
        36
        """
        return cls(chain)

    def export_constants(self) -> dict[str, Any]:
        """The per-arm numbers of this solver, as plain arrays, for code generators
        (:mod:`robokit.codegen` writes ``NAME_ik`` from them, step for step as :meth:`solve`).

        Returns
        -------
        dict
            ``alpha`` (5,), ``a`` (5,), ``d`` (6,) of the scaled chain (lengths divided by
            ``scale``, m), ``th0`` (6,) offsets (rad), ``scale`` (m), the tolerances ``gamma``,
            ``imag_tol``, ``converged``, ``same``, ``x0``, ``poor``, and ``arrangements``: the
            ``1 + extra`` best readings, each a dict with ``roles`` (6,) joint indices (pivot, b,
            c, d, e, eliminated), ``three_has_w`` (the target's map is on the three-joint side),
            ``const`` ((3**k, 15) the tensor of the side without the target, from
            :func:`~robokit.kernels.general_6r.side_tensor`), for the side with it ``Ms``
            ((k + 1, 15, 15), slot ``w_index`` replaced per pose by ``pre @ F(W) @ post`` with
            ``W = T₀₆⁻¹``, or ``T₀₆`` when ``w_inverse``), ``signs`` (k,), ``f`` (15,), and the row
            permutations ``perm3`` (27,) and ``perm2`` (9,) that :meth:`_Arrangement.matrices`
            applies: ``P[i, k, m] = G3[perm3[9 i + m], k]``, ``r[k, m] = G2[perm2[m], k]``;
            ``deflate``, how many eigenvalue pairs x = ±i the solve removes before its eigenvalue
            iteration (0: none tried; see :func:`robokit.kernels.general_6r.deflate`).

        Examples
        --------
        >>> import robokit
        >>> from robokit.ik._dh_chain import DHChain
        >>> c = GeneralSixR(DHChain(robokit.load("puma560").dh)).export_constants()
        >>> len(c["arrangements"]), c["arrangements"][0]["const"].shape[1]
        (4, 15)
        """
        el = self.elim
        return {"alpha": el.alpha.copy(), "a": el.a.copy(), "d": el.d.copy(), "th0": el.th0.copy(),
                "scale": self.scale, "gamma": _GAMMA, "imag_tol": _IMAG_TOL, "converged": _CONVERGED, "same": _SAME,
                "x0": _X0, "poor": _POOR, "turn": _TURN,
                "arrangements": [arr.tables() for arr in el.arrangements[:_EXTRA + 1]]}

    def solve(self, T06: np.ndarray, wrist_ref: float = 0.0) -> list[tuple[Sequence[float], str, bool]]:
        """Every solution for the pose ``T06`` (4 × 4, m) of ``Z₁X₁ ⋯ Z₆``.

        Parameters
        ----------
        T06 : (4, 4) array
            Target of the canonical chain (base′ and tool′ removed), m.
        wrist_ref : float
            Unused (the general case has no free joint); accepted for the common solver shape.

        Returns
        -------
        list of (q, label, degenerate)
            q (6,) joint values (rad) — ``θ − θ_offset`` —, label ``"solution k of m"``
            (ordered by q₃), degenerate False; ``[]`` when the pose is out of reach. Near a
            singular pose (the conditioning figure of the elimination below 1e-4) the next three
            readings are solved too, and a solution whose 6 × 6 Jacobian is singular
            (σ_min < 1e-8 σ_max) is labelled ``"solution k of m, singular"`` and flagged
            degenerate: there the solutions may form a continuum (e.g. four parallel axes), of
            which the ones returned are points, not necessarily the configuration that
            generated the pose.

        Examples
        --------
        >>> import numpy as np, robokit
        >>> from robokit.ik._dh_chain import DHChain
        >>> chain = DHChain(robokit.load("puma560").dh)
        >>> chain.a[3] = 0.001  # axes 4 and 5 of the PUMA 1 mm apart: no spherical wrist
        >>> len(GeneralSixR.from_chain(chain).solve(chain.fk6(np.array([0.1, -0.5, 0.3, 0.4, 0.6, -0.2]))))
        8

        Notes
        -----
        An arm that is *exactly* special (a spherical wrist, three parallel axes) makes the
        eigenproblem degenerate (double and infinite roots) and may lose solutions here;
        :func:`robokit.ik_analytic` sends such arms to their special solvers. Arms special
        only approximately (1e-8 m, 1e-8 rad and more off) are solved here in full.
        """
        T06s = np.array(T06, dtype=float)
        T06s[:3, 3] /= self.scale
        el = self.elim
        out = np.empty((24 * (_EXTRA + 1), 7))
        m = solve_pose(el.kchain, el.ktol, *el.kreadings, T06s, out)
        rows: list[tuple[Sequence[float], str, bool]] = []
        for k in range(m):
            singular = bool(out[k, 6])
            label = f"solution {k + 1} of {m}" + (", singular" if singular else "")
            rows.append((out[k, :6].tolist(), label, singular))
        return rows

    def joint_angles(self, T06: np.ndarray, wrist_ref: float = 0.0) -> list[tuple[Sequence[float], str, bool]]:
        """Every solution for ``T06``: the same as :meth:`solve` (the name of the closed-form
        solver interface).

        Parameters
        ----------
        T06 : (4, 4) array
            Target of the canonical chain, m.
        wrist_ref : float
            Unused (no free joint in the general case).

        Returns
        -------
        list of (q, label, degenerate)

        Examples
        --------
        The chain of :meth:`solve`'s example (the PUMA without a spherical wrist):

        >>> len(GeneralSixR(chain).joint_angles(chain.fk6(np.array([0.1, -0.5, 0.3, 0.4, 0.6, -0.2]))))
        8
        """
        return self.solve(T06, wrist_ref)

    def position(self, T06: np.ndarray) -> list[PositionBranch]:
        """The elimination has no position/wrist split: the whole solve, each solution a
        complete branch ``(q, label, degenerate, None)``.

        Parameters
        ----------
        T06 : (4, 4) array
            Target of the canonical chain, m.

        Returns
        -------
        list of (q (6,), label, degenerate, None)

        Examples
        --------
        The chain of :meth:`solve`'s example:

        >>> len(GeneralSixR(chain).position(chain.fk6(np.zeros(6)))) > 0
        True
        """
        return [PositionBranch(q, label, degen, None) for q, label, degen in self.solve(T06)]

    def wrist(self, T06: np.ndarray, branch: PositionBranch, wrist_ref: float = 0.0
              ) -> list[tuple[Sequence[float], str, bool]]:
        """The identity on a branch of :meth:`position` (already a full solution).

        Parameters
        ----------
        T06 : (4, 4) array
            Target (unused).
        branch : (q, label, degenerate, data)
            One item of :meth:`position`.
        wrist_ref : float
            Unused.

        Returns
        -------
        list of (q, label, degenerate)
            The one row of the branch.

        Examples
        --------
        >>> GeneralSixR.wrist(None, None, ([0.0] * 6, "solution 1 of 1", False, None))
        [([0.0, 0.0, 0.0, 0.0, 0.0, 0.0], 'solution 1 of 1', False)]
        """
        return [(branch[0], branch[1], bool(branch[2]))]
