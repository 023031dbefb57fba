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
   ``(1 + x²)⁴`` (the half-angle substitution's ±i), leaving the 16 of a general 6R arm.
4. **Eigenproblem** (Manocha & Canny 1994). Instead of expanding the determinant, the
   quadratic matrix polynomial is linearised: ``[[0, I], [−C, −B]] z = x [[I, 0], [0, A]] z``
   with ``z = (v, x v)`` (24 × 24); the real eigenvalues are the x₃ of the solutions and each
   eigenvector holds v, the monomials of x₄ and x₅. When A is close to singular (a solution
   near the half-angle's point at infinity) the generalised eigenproblem (QZ) is used; the
   variable is turned by a fixed angle γ first (``θ₃ = 2 atan x + γ``) so that θ₃ = π is an
   ordinary point.
5. **Back-substitution.** θ₄, θ₅ from ratios of v's entries (as ``2 atan2(vᵢ₊₁, vᵢ)``, so
   that x = ∞ is θ = π), θ₁, θ₂ from ``m₁₂ = Q⁺ P(θ₃) m₄₅`` (least squares, 14 equations),
   θ₆ from ``Rz(θ₆) = (Z₁X₁⋯X₅ Tz(d₆))⁻¹ T₀₆``.
6. **Polish.** A few Newton–Raphson steps on the pose error with the geometric Jacobian
   bring every candidate to the pose to rounding; candidates that do not converge (complex
   roots with a small imaginary part, kept on purpose so that near-double real roots are not
   lost) are dropped, and solutions closer than 1e-7 rad in every joint are merged.

Numerics: lengths are divided by the arm's size; the elimination is run on the chain and on
the chain read backwards (joint 4 becomes the eigenvalue variable) when the 14 × 8 matrix Q
or the leading coefficient A is badly conditioned for the forward reading, and the
solutions of both are merged.

Use through :func:`robokit.ik_analytic` (it picks this solver for a 6R arm that has neither
a spherical wrist nor three parallel axes); :class:`GeneralSixR` is the solver object.
"""
from __future__ import annotations

import math
from typing import TYPE_CHECKING, Sequence

import numpy as np

from robokit.kernels.general_6r import fk_pose, fvec, jacobian, pencil, polish

if TYPE_CHECKING:
    from robokit.ik._dh_chain import DHChain

__all__ = ["GeneralSixR"]

_GAMMA = 0.6180339887498949  # rad: the θ₃ shift of the half-angle variable (any non-special value)
_IMAG_TOL = 1e-3  # an eigenvalue is a candidate when its imaginary part, as an angle, is below this
_CONVERGED = 1e-11  # pose error (scaled units) below which a polished candidate is a solution
_SAME = 1e-7  # rad: solutions this close in every joint are one


def _f_translate(t: Sequence[float]) -> np.ndarray:
    """15 × 15 map of f(l, p) (with its trailing 1) under p → p + t."""
    t = np.asarray(t, dtype=float)
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


def _rz_parts(v: np.ndarray, sign: float) -> np.ndarray:
    """(3, 15): the cos θ, sin θ and constant parts of f under Rz(sign·θ)."""
    out = np.zeros((3, 15))
    out[2] = v
    for b in (0, 3, 8, 11):
        x, y = v[b], v[b + 1]
        out[0, b], out[0, b + 1] = x, y
        out[1, b], out[1, b + 1] = -sign * y, sign * x
        out[2, b] = out[2, b + 1] = 0.0
    return out


class _Elimination:
    """The per-arm constants of one reading of the chain (lengths divided by ``scale``)."""

    def __init__(self, chain: DHChain, scale: float) -> None:
        self.alpha = np.ascontiguousarray(chain.alpha, dtype=float)
        self.a = np.ascontiguousarray(chain.a, dtype=float) / scale
        self.d = np.ascontiguousarray(chain.d0, dtype=float) / scale
        self.th0 = np.asarray(chain.th0, dtype=float)
        al, a, d = self.alpha, self.a, self.d
        ez = np.array([0.0, 0.0, 1.0])
        ex = np.array([1.0, 0.0, 0.0])

        def FX(i: int) -> np.ndarray:  # X_{i+1} = Tx(a)Rx(α) on f
            return _f_translate(a[i] * ex) @ _f_rotate_x(al[i])

        def FTz(i: int) -> np.ndarray:
            return _f_translate(d[i] * ez)

        f0 = np.zeros(15)
        fvec(0.0, 0.0, 1.0, 0.0, 0.0, 0.0, f0)
        g5 = _rz_parts(FTz(4) @ FX(4) @ f0, 1.0)  # Z₅X₅(e_z, 0): (c₅, s₅, 1) parts
        P = np.empty((3, 15, 9))
        M4 = FTz(3) @ FX(3)
        M3 = FTz(2) @ FX(2)
        X2 = FX(1)
        for i5 in range(3):
            g4 = _rz_parts(M4 @ g5[i5], 1.0)
            for i4 in range(3):
                g3 = _rz_parts(M3 @ g4[i4], 1.0)
                for i3 in range(3):
                    P[i3, :, i4 * 3 + i5] = X2 @ g3[i3]
        self.P = np.ascontiguousarray(P)
        self.K1 = np.ascontiguousarray(_f_rotate_x(-al[0]) @ _f_translate(-a[0] * ex) @ _f_translate(-d[0] * ez))
        self.Tz2 = np.ascontiguousarray(_f_translate(-d[1] * ez))
        self.d6 = float(d[5])
        self.gc, self.gs = math.cos(_GAMMA), math.sin(_GAMMA)
        self.work = np.empty((3, 12, 12))
        self.Np = np.empty((3, 14, 9))
        self.Pinv = np.empty((8, 14))

    def candidates(self, T06s: np.ndarray) -> tuple[list[np.ndarray], float]:
        """Polished rotation angles θ (6,) of the solutions for the scaled target, and a
        conditioning figure (the smaller of Q's and A's singular value ratios)."""
        ratio = pencil(self.P, self.K1, self.Tz2, self.d6, T06s, self.gc, self.gs, self.work, self.Np, self.Pinv)
        A, B, C = self.work
        sA = np.linalg.svd(A, compute_uv=False)
        condA = sA[-1] / sA[0] if sA[0] > 0.0 else 0.0
        n = 12
        if condA > 1e-10:
            Ainv = np.linalg.inv(A)
            M = np.zeros((2 * n, 2 * n))
            M[:n, n:] = np.eye(n)
            M[n:, :n] = -Ainv @ C
            M[n:, n:] = -Ainv @ B
            lam, Z = np.linalg.eig(M)
            xs = [(complex(v), 1.0 + 0j) for v in lam]
        else:
            import scipy.linalg

            L0 = np.zeros((2 * n, 2 * n))
            L0[:n, n:] = np.eye(n)
            L0[n:, :n] = -C
            L0[n:, n:] = -B
            L1 = np.eye(2 * n)
            L1[n:, n:] = A
            w, Z = scipy.linalg.eig(L0, L1, homogeneous_eigvals=True)
            xs = [(complex(w[0, k]), complex(w[1, k])) for k in range(2 * n)]
        out: list[np.ndarray] = []
        for k, (num, den) in enumerate(xs):
            # angle φ = 2 atan(num/den); a real root has num/den real
            if abs(den) > 1e-300:
                lam_k = num / den
                imag = 2.0 * abs(lam_k.imag) / (1.0 + abs(lam_k) ** 2)
                if imag > _IMAG_TOL:
                    continue
                phi = 2.0 * math.atan(lam_k.real)
            else:
                phi = math.pi
            z = Z[:, k]
            v = z[:n] if abs(math.tan(phi / 2.0)) <= 1.0 else z[n:]
            j = int(np.argmax(np.abs(v)))
            v = (v * (abs(v[j]) / v[j])).real
            th = self._back(phi + _GAMMA, v, T06s)
            err = polish(self.alpha, self.a, self.d, T06s, th, 12)
            if err < _CONVERGED:
                out.append(th)
        return out, min(ratio, condA)

    def _back(self, th3: float, v: np.ndarray, T06s: np.ndarray) -> np.ndarray:
        V = v.reshape(4, 3)  # V[i, j] ~ x₄ⁱ x₅ʲ
        best, th4 = -1.0, 0.0
        for i in range(3):
            for j in range(3):
                w = V[i, j] ** 2 + V[i + 1, j] ** 2
                if w > best:
                    best, th4 = w, 2.0 * math.atan2(V[i + 1, j], V[i, j])
        best, th5 = -1.0, 0.0
        for i in range(4):
            for j in range(2):
                w = V[i, j] ** 2 + V[i, j + 1] ** 2
                if w > best:
                    best, th5 = w, 2.0 * math.atan2(V[i, j + 1], V[i, j])
        t4 = np.array([math.cos(th4), math.sin(th4), 1.0])
        t5 = np.array([math.cos(th5), math.sin(th5), 1.0])
        m45 = np.outer(t4, t5).ravel()
        rhs = (self.Np[0] * math.cos(th3) + self.Np[1] * math.sin(th3) + self.Np[2]) @ m45
        m12 = self.Pinv @ rhs
        th1 = math.atan2(m12[5], m12[2])
        th2 = math.atan2(m12[7], m12[6])
        th = np.array([th1, th2, th3, th4, th5, 0.0])
        T = np.empty((4, 4))
        fk_pose(self.alpha, self.a, self.d, th, T)
        R = T[:3, :3].T @ T06s[:3, :3]
        th[5] = math.atan2(R[1, 0], R[0, 0])
        return th


class GeneralSixR:
    """Every closed-form IK solution of a 6R arm in general position (see the module docstring).

    Build once per arm with :meth:`from_chain`; :meth:`solve` returns, for a target ``T₀₆``
    of the canonical chain, the solutions as ``(q, label, degenerate)`` rows (q: joint values
    in rad, offsets removed), as the other closed-form solvers do.
    """

    #: what ``ik_analytic_kind`` adds to the reason when this solver takes an arm
    REASON = "; the general 6R method applies (Raghavan–Roth elimination, up to 16 solutions)"

    def __init__(self, chain: DHChain) -> None:
        why = self.refusal(chain)
        if why is not None:
            raise ValueError(f"robot: {why}")
        self.chain = chain
        self.scale = float(chain.scale)
        self.forward = _Elimination(chain, self.scale)
        self.backward = _Elimination(chain.reversed(), self.scale)

    @staticmethod
    def refusal(chain: DHChain) -> str | None:
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
        """
        if chain.n != 6:
            return f"the general 6R method needs 6 joints, the arm has {chain.n}"
        if any(k != "R" for k in chain.kinds):
            j = 1 + list(chain.kinds).index("P")
            return f"the general 6R method needs revolute joints, joint {j} is prismatic"
        scale = float(chain.scale)
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
        """
        return cls(chain)

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
            (ordered by q₃), degenerate False.
        """
        T06s = np.array(T06, dtype=float)
        T06s[:3, 3] /= self.scale
        sols, ratio = self.forward.candidates(T06s)
        if ratio < 1e-6:
            Ti = np.eye(4)
            Ti[:3, :3] = T06s[:3, :3].T
            Ti[:3, 3] = -T06s[:3, :3].T @ T06s[:3, 3]
            back, _ = self.backward.candidates(Ti)
            sols = sols + [-th[::-1] for th in back]
        q_list: list[np.ndarray] = []
        th0 = self.forward.th0
        for th in sols:
            q = np.remainder(th - th0 + math.pi, 2.0 * math.pi) - math.pi
            if not any(np.all(np.abs(np.remainder(q - o + math.pi, 2.0 * math.pi) - math.pi) < _SAME) for o in q_list):
                q_list.append(q)
        q_list.sort(key=lambda q: tuple(q[[2, 0, 1, 3, 4, 5]]))
        m = len(q_list)
        return [(q, f"solution {k + 1} of {m}", False) for k, q in enumerate(q_list)]
