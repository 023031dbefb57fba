r"""Pieper's method for 6-joint arms whose last three axes meet in one point (Lecture 5).

The chain is taken in the canonical form of :mod:`robokit.ik._dh_chain`,
``Z₁X₁Z₂X₂Z₃X₃Z₄X₄Z₅X₅Z₆`` with ``Zᵢ = Rz(θᵢ)Tz(dᵢ)`` and ``Xᵢ = Rx(αᵢ)Tx(aᵢ)`` (Craig's
link transforms regrouped; a standard-convention table gives the same form).

**Wrist centre.** Axes 4, 5, 6 meet at W, the origin of the frame after ``Z₄``. W does not
move with θ₄, θ₅, θ₆, so its position depends on joints 1–3 only:
``⁰W = Z₁X₁Z₂ · f``, ``f = X₂Z₃ · ³W`` with ``³W = Rx(α₃)(a₃, 0, d₄)ᵀ = (a₃, −d₄sα₃, d₄cα₃)ᵀ``
(Lecture 5's ``³P₄ORG``). From the target, ``⁰W = T₀₆ · ⁶W`` with ``⁶W`` constant.

**Position (joint 1 revolute).** Rotating about axis 1 keeps ``h = W_z − d₁`` and
``r = W_x² + W_y² + h²``; with ``F = f + d₂e₃`` (Lecture 5's f₁, f₂, f₃ with d₂ folded in)
``r = 2a₁(F₁c₂ − F₂s₂) + a₁² + ‖F‖²`` and ``h = sα₁(F₂c₂ + F₁s₂) + cα₁F₃`` — the lecture's
``r = (k₁c₂ + k₂s₂)2a₁ + k₃``, ``z = (k₁s₂ − k₂c₂)sα₁ + k₄`` with ``k₁ = F₁``, ``k₂ = −F₂``.
* ``a₁ = 0``: ``r = k₃(θ₃)``, one equation in θ₃; θ₂ then from the h equation;
* ``sα₁ = 0``: ``h = k₄(θ₃)``; θ₂ then from the r equation;
* otherwise eliminating (c₂, s₂): ``(r − k₃)²/(4a₁²) + (h − k₄)²/sα₁² = k₁² + k₂²``.
With ``u = tan(θ₃/2)`` each is a polynomial in u — of degree 2 in the first two cases and
4 (the quartic) in general; its real roots give θ₃, then (c₂, s₂) solve the linear pair,
and θ₁ = atan2(W_y, W_x) − atan2(g₂, g₁) with ``g = X₁Z₂F``.
A prismatic joint 3 makes F linear in d₃ (the same equations are then polynomials in d₃ of
degree ≤ 4); a prismatic joint 2 leaves θ₂ fixed and the unknown d₂ enters h linearly and r
quadratically; a prismatic joint 1 keeps W_x, W_y (in frame 0′ turned by θ₁'s offset) and
gives d₁ last. The polynomial's coefficients are linear in a few monomials of the target
(r², r, h², h, 1); their matrix is computed once per robot.

This module builds those constants once per chain (:class:`PieperConstants`); the algorithm
itself — the one implementation, in Python and compiled alike — is
:mod:`robokit.kernels.closed_form` (``pieper_position``, ``pieper_wrist``, ``pieper_rows``; run
``NUMBA_DISABLE_JIT=1`` to step through it as plain Python). Roots come from the eigenvalues
of the companion matrix, are polished by Newton steps on the polynomial, taken in ascending
order (so the solutions come in an order that does not depend on the eigen-solver), and each
(θ₁, θ₂, θ₃) is checked — and, if needed, polished by Newton steps on the wrist-centre
equation ``⁰W(q₁, q₂, q₃) = ⁰W`` itself.

**Orientation.** With ``R₃ = Rz(θ₁)Rx(α₁)Rz(θ₂)Rx(α₂)Rz(θ₃)Rx(α₃)`` the wrist must give
``M = R₃ᵀ·R₀₆ = Rz(θ₄)Rx(α₄)Rz(θ₅)Rx(α₅)Rz(θ₆)`` — the ZYZ Euler problem of seed 003 when
α₄ = ∓α₅ = ±90°, and in general: ``M₂₂ = cα₄cα₅ − sα₄sα₅c₅`` gives ±θ₅, then θ₄ from the
third column and θ₆ from the third row (two atan2's). When axes 4 and 6 line up (θ₅ = 0 or
π for a right-angled wrist) only θ₄ ± θ₆ is determined: the documented choice is
``q₄ = wrist_ref`` (default 0), θ₆ takes the rest, and the solution is flagged.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING, Sequence

import numpy as np

from robokit.ik.solution import Row
from robokit.ik.solver import PositionBranch

if TYPE_CHECKING:
    from robokit.ik._dh_chain import DHChain

_PI = math.pi
#: Branch labels by the kernels' codes (:mod:`robokit.kernels.closed_form`): shoulder, elbow, wrist.
SHOULDER_LABELS = ("right, ", "left, ", "shoulder singular, ", "")
ELBOW_LABELS = ("elbow down, ", "elbow up, ", "d3 +, ", "d3 \u2212, ")
WRIST_LABELS = ("no flip", "flip", "wrist singular")
#: The position cases, in the order of their codes in the kernel (``ci[1]``).
_CASES = ("RR-quartic", "RR-a1", "RR-s1", "PR-quartic", "PR-c1", "RP-quartic", "RP-c1", "PP")
_U_R = np.array([1.0, 0.0, 1.0])  # 1 + u² (revolute: u = tan(θ/2))
_U_P = np.array([1.0, 0.0, 0.0])  # 1 (prismatic: the variable itself)


def _mul(p: np.ndarray, q: np.ndarray) -> np.ndarray:
    """Product of two length-3 coefficient arrays (low → high) as a length-5 array."""
    return np.convolve(p, q)


def _num(coef: Sequence[float] | np.ndarray, kind: str) -> np.ndarray:
    """Numerator polynomial (length 3) of a quantity k₀ + k_c cos θ + k_s sin θ (over 1 + u²),
    or, for a prismatic variable, of the polynomial k₀ + k₁q + k₂q² (over 1)."""
    k0, k1, k2 = coef
    if kind == "R":
        return np.array([k0 + k1, 2.0 * k2, k0 - k1])
    return np.array([k0, k1, k2])


def _rz_v(c: float, s: float, v: Sequence[float]) -> tuple[float, float, float]:
    return (c * v[0] - s * v[1], s * v[0] + c * v[1], v[2])




def pack_offsets_and_twists(th0: Sequence[float], d0: Sequence[float], ca: Sequence[float],
                            sa: Sequence[float]) -> np.ndarray:
    """The kernel's float constants (64,) with the layout both closed-form kernels share filled in:
    θ₀ (6), d₀ (6), cos α (5), sin α (5) (:mod:`robokit.kernels.closed_form`)."""
    cf = np.zeros(64)
    cf[0:6], cf[6:12], cf[12:17], cf[17:22] = th0, d0, ca, sa
    return cf


Triple = tuple[float, float, float]


def _triple(x: Sequence[float] | np.ndarray) -> Triple:
    return (float(x[0]), float(x[1]), float(x[2]))


@dataclass(frozen=True)
class ChainNumbers:
    """The joint offsets and twists of a canonical chain ``Z₁X₁ ⋯ Z₆`` that every closed-form
    method's constants start with.

    Attributes
    ----------
    th0, d0 : tuple of float
        The chain's six joint offsets θ₀ (rad) and d₀ (m).
    ca, sa : tuple of float
        cos αᵢ, sin αᵢ of the five twists (exact zeros for right angles).
    """

    th0: tuple[float, ...]
    d0: tuple[float, ...]
    ca: tuple[float, ...]
    sa: tuple[float, ...]


@dataclass(frozen=True)
class PieperConstants(ChainNumbers):
    r"""The numbers Pieper's method needs for one canonical chain, computed once (module docstring).

    What :class:`PieperSolver` exports (:meth:`PieperSolver.constants`) for the compiled kernel
    (:mod:`robokit.kernels.closed_form`) and the C emitter (:mod:`robokit.codegen.ik`). Lengths
    in m, angles in rad; a "triple" is a quantity ``k₀ + k₁ cos θ₃ + k₂ sin θ₃`` of a revolute
    joint 3 (or ``k₀ + k₁ d₃ + k₂ d₃²`` of a prismatic one).

    Attributes
    ----------
    case : str
        Which position equations apply: ``"RR-quartic"``, ``"RR-a1"`` (a₁ = 0), ``"RR-s1"``
        (sin α₁ = 0), ``"PR-quartic"``, ``"PR-c1"``, ``"RP-quartic"``, ``"RP-c1"`` or ``"PP"``
        (the kinds of joints 1 and 2, then the special case).
    deg : int
        Nominal degree of the joint-3 polynomial (4 for the quartic cases, else 2).
    kinds : tuple of str
        ``"R"``/``"P"`` of joints 1–3.
    C : tuple of tuple of float
        The polynomial's coefficients (low → high) are ``Σₖ mₖ C[k]`` for the monomials m of
        the wrist centre of ``case`` (e.g. ``(r², r, h², h, 1)`` for ``"RR-quartic"``).
    th0, d0, ca, sa : tuple of float
        Joint offsets and twists (:class:`ChainNumbers`).
    a1, a2, d1, d2 : float
        Lengths of links 1, 2 and offsets d₁, d₂ (m).
    w3, w6 : tuple of float
        The wrist centre in the frame after Z₃ (``³W``) and after Z₆ (``⁶W``), m.
    f : tuple of three triples
        ``f = X₂Z₃ · ³W`` rotated by α₂ (Lecture 5's f₁, f₂, f₃).
    v : tuple of float
        ``³W + d₃e₃`` (revolute joint 3) or its rotation by θ₃'s offset (prismatic): the elbow label's vector.
    Ka, Kb : triple or None
        ``‖F‖² + a₁²`` and ``cα₁F₃`` (revolute joints 1 and 2), else None.
    phi : pair of triples or None
        ``(φ₁, φ₂)`` = f turned by θ₂'s offset (prismatic joint 2), else None.
    nf2 : triple
        ``‖f‖²``.
    scale : float
        The chain's size (m): tolerances are relative to it.

    Examples
    --------
    >>> import robokit
    >>> from robokit.ik._dh_chain import DHChain
    >>> c = PieperSolver(DHChain(robokit.load("puma560").dh)).constants()
    >>> c.case, c.deg, c.kinds
    ('RR-a1', 2, ('R', 'R', 'R'))
    """

    case: str
    deg: int
    kinds: tuple[str, str, str]
    C: tuple[tuple[float, ...], ...]
    a1: float
    a2: float
    d1: float
    d2: float
    w3: Triple
    w6: Triple
    f: tuple[Triple, Triple, Triple]
    v: Triple
    Ka: Triple | None
    Kb: Triple | None
    phi: tuple[Triple, Triple] | None
    nf2: Triple
    scale: float


class PieperSolver:
    """Pieper's method for one chain: its constants, computed once (see the module docstring).

    Implements :class:`robokit.ik.solver.ClosedFormSolver`: ``position`` places the wrist
    centre (θ₁–θ₃, labels "right/left, elbow up/down"), ``wrist`` the last three joints
    ("no flip/flip"), ``joint_angles`` both.

    Parameters
    ----------
    chain : DHChain
        The canonical chain (6 joints, axes 4–6 revolute and meeting in one point).

    Examples
    --------
    >>> import robokit
    >>> from robokit.ik._dh_chain import DHChain
    >>> PieperSolver(DHChain(robokit.load("puma560").dh)).method
    'spherical wrist'
    """

    method = "spherical wrist"

    def __init__(self, chain: DHChain) -> None:
        self.chain = chain
        self.th0_list = [float(t) for t in chain.th0]
        self.d0_list = [float(t) for t in chain.d0]
        k = chain.kinds
        self.j1, self.j2, self.j3 = k[0], k[1], k[2]
        th0, d0, al, a = chain.th0, chain.d0, chain.alpha, chain.a
        tol = 1e-12 * chain.scale
        self.a1, self.a2 = float(a[0]), float(a[1])
        self.ca = [math.cos(x) for x in al]
        self.sa = [math.sin(x) for x in al]
        for i in range(5):  # exact zeros for the right angles of a DH file in degrees
            if abs(self.ca[i]) < 1e-15:
                self.ca[i] = 0.0
            if abs(self.sa[i]) < 1e-15:
                self.sa[i] = 0.0
        ca1, sa1, ca2, sa2, ca3, sa3 = self.ca[0], self.sa[0], self.ca[1], self.sa[1], self.ca[2], self.sa[2]
        a1, a2, a3 = self.a1, self.a2, float(a[2])
        d2 = float(d0[1])
        self.d1 = float(d0[0])
        self.d2 = d2
        # wrist centre in the frame after Z₃ and in the frame after Z₆
        w3 = np.array([a3, -sa3 * d0[3], ca3 * d0[3]])
        self.w3_list = [float(v) for v in w3]
        G = chain.x(3) @ chain.z(4, 0.0) @ chain.x(4) @ chain.z(5, 0.0)  # frame 4 → frame 6 at q₅ = q₆ = 0
        Ginv = np.linalg.inv(G)
        self.w6 = Ginv[:3, 3].copy()
        self.w6_list = [float(v) for v in self.w6]
        # f(x₃) = X₂Z₃ · ³W as coefficient triples in (1, cos θ₃, sin θ₃) or (1, d, d²)
        if self.j3 == "R":
            v = w3 + np.array([0.0, 0.0, d0[2]])
            self.v = v
            fx = np.array([a2, v[0], -v[1]])
            fy = np.array([0.0, v[1], v[0]])
            fz = np.array([v[2], 0.0, 0.0])
            nf2 = np.array([a2 * a2 + v @ v, 2.0 * a2 * v[0], -2.0 * a2 * v[1]])
            self.U = _U_R
        else:
            c0, s0 = math.cos(th0[2]), math.sin(th0[2])
            p0 = np.array(_rz_v(c0, s0, w3 + np.array([0.0, 0.0, d0[2]])))
            b = p0 + np.array([a2, 0.0, 0.0])
            self.v = p0
            fx = np.array([b[0], 0.0, 0.0])
            fy = np.array([b[1], 0.0, 0.0])
            fz = np.array([b[2], 1.0, 0.0])
            nf2 = np.array([b @ b, 2.0 * b[2], 1.0])
            self.U = _U_P
        f1, f2, f3 = fx, ca2 * fy - sa2 * fz, sa2 * fy + ca2 * fz
        self.f = (f1, f2, f3)
        kind, U = self.j3, self.U
        UU = _mul(U, U)

        def N(c: Sequence[float] | np.ndarray) -> np.ndarray:
            return _num(c, kind)

        self.case: str | None = None
        if self.j2 == "R":
            F3 = f3 + np.array([d2, 0.0, 0.0])
            self.F3 = F3
            Fn2 = _mul(N(f1), N(f1)) + _mul(N(f2), N(f2))
            if self.j1 == "R":
                Ka = nf2 + 2.0 * d2 * f3 + np.array([a1 * a1 + d2 * d2, 0.0, 0.0])
                Kb = ca1 * F3
                self.Ka, self.Kb = Ka, Kb
                if abs(a1) > tol and sa1 != 0.0:
                    self.case = "RR-quartic"  # m = (r², r, h², h, 1)
                    rows = [sa1 * sa1 * UU, -2.0 * sa1 * sa1 * _mul(U, N(Ka)), 4.0 * a1 * a1 * UU,
                            -8.0 * a1 * a1 * _mul(U, N(Kb)),
                            sa1 * sa1 * _mul(N(Ka), N(Ka)) + 4.0 * a1 * a1 * _mul(N(Kb), N(Kb))
                            - 4.0 * a1 * a1 * sa1 * sa1 * Fn2]
                elif abs(a1) <= tol:
                    self.case = "RR-a1"  # r = k₃(θ₃): m = (r, 1)
                    rows = [U, -N(Ka)]
                else:
                    self.case = "RR-s1"  # h = k₄(θ₃): m = (h, 1)
                    rows = [U, -N(Kb)]
            else:
                if ca1 != 0.0:
                    self.case = "PR-quartic"  # m = (X², y², y, 1), X = x′ − a₁
                    rows = [ca1 * ca1 * UU, UU, 2.0 * sa1 * _mul(U, N(F3)),
                            sa1 * sa1 * _mul(N(F3), N(F3)) - ca1 * ca1 * Fn2]
                else:
                    self.case = "PR-c1"  # y′ + sα₁F₃ = 0: m = (y, 1)
                    rows = [U, sa1 * N(F3)]
        else:
            c2, s2 = math.cos(th0[1]), math.sin(th0[1])
            phi1, phi2 = c2 * f1 - s2 * f2, s2 * f1 + c2 * f2
            self.phi = (phi1, phi2)
            if self.j1 == "R":
                if ca1 != 0.0:
                    self.case = "RP-quartic"  # m = (r, h², h, 1)
                    rows = [ca1 * ca1 * UU, -UU, 2.0 * sa1 * _mul(U, N(phi2)),
                            -ca1 * ca1 * (a1 * a1 * UU + _mul(U, N(nf2)) - _mul(N(f3), N(f3))
                                          + 2.0 * a1 * _mul(U, N(phi1))) - sa1 * sa1 * _mul(N(phi2), N(phi2))]
                else:
                    self.case = "RP-c1"  # sα₁φ₂ = h: m = (h, 1)
                    rows = [U, -sa1 * N(phi2)]
            else:
                self.case = "PP"  # φ₁ = x′ − a₁: m = (X, 1)
                rows = [U, -N(phi1)]
        self.nf2 = nf2
        self.deg = 4 if self.case.endswith("quartic") else 2  # nominal degree in u (or d₃)
        R = np.zeros((len(rows), self.deg + 1))
        for i, row in enumerate(rows):
            row = np.asarray(row, dtype=float)[: self.deg + 1]
            R[i, : len(row)] = row
        self.C = R  # polynomial coefficients (low → high) = Σ m_k C[k]
        self.C_list = R.tolist()
        # wrist
        self.ca4, self.sa4, self.ca5, self.sa5 = self.ca[3], self.sa[3], self.ca[4], self.sa[4]
        self._kernel_args: tuple[np.ndarray, np.ndarray, np.ndarray] | None = None

    def constants(self) -> PieperConstants:
        """This solver's :class:`PieperConstants` (what the kernel and the C emitter read)."""
        assert self.case is not None  # set in __init__
        rr = self.j1 == "R" and self.j2 == "R"
        return PieperConstants(
            case=self.case, deg=self.deg, kinds=(self.j1, self.j2, self.j3),
            C=tuple(tuple(float(x) for x in row) for row in self.C_list),
            th0=tuple(self.th0_list), d0=tuple(self.d0_list), ca=tuple(self.ca), sa=tuple(self.sa),
            a1=self.a1, a2=self.a2, d1=self.d1, d2=self.d2, w3=_triple(self.w3_list), w6=_triple(self.w6_list),
            f=(_triple(self.f[0]), _triple(self.f[1]), _triple(self.f[2])), v=_triple(self.v),
            Ka=_triple(self.Ka) if rr else None, Kb=_triple(self.Kb) if rr else None,
            phi=(_triple(self.phi[0]), _triple(self.phi[1])) if self.j2 == "P" else None,
            nf2=_triple(self.nf2), scale=float(self.chain.scale))

    def kernel_constants(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """``(ci, cf, C)`` for :func:`robokit.kernels.closed_form.closed_form_solve`: :meth:`constants`
        packed into flat arrays (the layout of :mod:`robokit.kernels.closed_form`)."""
        k = self.constants()
        ci = np.array([0, _CASES.index(k.case), int(k.kinds[2] == "R"), k.deg, len(k.C), 0], dtype=np.int64)
        cf = pack_offsets_and_twists(k.th0, k.d0, k.ca, k.sa)
        cf[22:26] = k.a1, k.a2, k.d1, k.d2
        cf[26:29], cf[29:32] = k.w3, k.w6
        cf[32:41] = k.f[0] + k.f[1] + k.f[2]
        if k.Ka is not None and k.Kb is not None:
            cf[41:44], cf[44:47] = k.Ka, k.Kb
        cf[47:50] = k.v
        cf[50] = k.scale
        if k.phi is not None:
            cf[51:57] = k.phi[0] + k.phi[1]
        cf[57:60] = k.nf2
        cf[60:63] = [1.0 if kind == "R" else 0.0 for kind in k.kinds]
        C = np.zeros((5, 5))
        C[: len(k.C), : k.deg + 1] = k.C
        return ci, cf, C

    # ------------------------------------------------------------------ the solver interface
    def _packed(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """:meth:`kernel_constants`, computed on first use."""
        if self._kernel_args is None:
            self._kernel_args = self.kernel_constants()
        return self._kernel_args

    def refusal(self) -> str | None:
        """None if joints 1–3 move the wrist centre in 3 independent directions, else the reason.

        The 3×3 Jacobian of the wrist centre ``⁰W = Z₁X₁Z₂X₂Z₃ · ³W`` (central differences of the
        chain's own transforms) is checked at a few fixed pseudo-random configurations; a
        positioning structure that is rank-deficient at all of them (e.g. a prismatic joint
        perpendicular to a revolute one in a plane) has a continuum of solutions, not a finite set.

        Returns
        -------
        str or None
        """
        chain = self.chain
        w3 = np.array([*self.w3_list, 1.0])
        X1, X2 = chain.x(0), chain.x(1)

        def wrist_centre(q: np.ndarray) -> np.ndarray:
            return (chain.z(0, q[0]) @ X1 @ chain.z(1, q[1]) @ X2 @ chain.z(2, q[2]) @ w3)[:3]

        rng = np.random.default_rng(12345)
        scale = chain.scale
        for _ in range(4):
            q = rng.uniform(-2.0, 2.0, 3)
            J = np.empty((3, 3))
            h = 1e-6
            for j in range(3):
                dq = np.zeros(3)
                dq[j] = h
                J[:, j] = (wrist_centre(q + dq) - wrist_centre(q - dq)) / (2.0 * h)
            J[:, [chain.kinds[j] == "R" for j in range(3)]] /= scale  # revolute columns in m/rad → unitless
            if np.linalg.svd(J, compute_uv=False)[-1] > 1e-6:
                return None
        return ("axes 4–6 meet in one point, but joints 1–3 cannot move the wrist centre in three "
                "independent directions (their axes confine it to a surface)")

    def position(self, T06: np.ndarray) -> list[PositionBranch]:
        """θ₁–θ₃ placing the wrist centre ``⁰W = T06·⁶W``: one branch per (right/left, elbow up/down).

        Runs :func:`robokit.kernels.closed_form.pieper_position` (the one implementation).

        Parameters
        ----------
        T06 : (4, 4) ndarray
            Target of ``Z₁X₁ ⋯ Z₆`` in frame 0′ (m).

        Returns
        -------
        branches : list of PositionBranch
            ``q`` (3,) joint variables 1–3, ``label`` e.g. ``"right, elbow up, "``,
            ``data`` the rotation angles θ₁–θ₃ (offsets included).
        """
        from robokit.kernels.closed_form import pieper_position

        ci, cf, C = self._packed()
        Q3, codes, degen, TH = pieper_position(ci, cf, C, np.ascontiguousarray(T06, dtype=float))
        return [PositionBranch(tuple(q), SHOULDER_LABELS[s] + ELBOW_LABELS[e], bool(d), th)
                for q, (s, e), d, th in zip(Q3.tolist(), codes.tolist(), degen.tolist(), TH)]

    def wrist(self, T06: np.ndarray, branch: PositionBranch, wrist_ref: float) -> list[Row]:
        """The wrist's (q₄, q₅, q₆) for one position branch: ``M = R₃ᵀR₀₆`` (flip/no flip).

        Runs :func:`robokit.kernels.closed_form.pieper_wrist`. Parameters
        and result as :meth:`robokit.ik.solver.ClosedFormSolver.wrist`.
        """
        from robokit.kernels.closed_form import pieper_wrist

        _, cf, _ = self._packed()
        th0 = self.th0_list
        q1, q2, q3 = branch.q
        angles, flips = pieper_wrist(cf, np.asarray(branch.data, dtype=float),
                                     np.ascontiguousarray(T06, dtype=float), float(wrist_ref))
        return [((q1, q2, q3, t4 - th0[3], t5 - th0[4], t6 - th0[5]), branch.label + WRIST_LABELS[f],
                 bool(f == 2 or branch.degenerate)) for (t4, t5, t6), f in zip(angles.tolist(), flips.tolist())]

    def joint_angles(self, T06: np.ndarray, wrist_ref: float) -> list[Row]:
        """Every row ``(q (6,), label, degenerate)`` reaching ``T06`` (up to 4 positions × 2 wrists).

        Runs :func:`robokit.kernels.closed_form.pieper_rows`.

        Parameters
        ----------
        T06 : (4, 4) ndarray
            Target of ``Z₁X₁ ⋯ Z₆`` in frame 0′ (m).
        wrist_ref : float
            q₄ at a wrist singularity (rad).

        Returns
        -------
        list of Row
        """
        from robokit.kernels.closed_form import pieper_rows

        ci, cf, C = self._packed()
        Q, codes, degen = pieper_rows(ci, cf, C, np.ascontiguousarray(T06, dtype=float), float(wrist_ref))
        return [(tuple(q), SHOULDER_LABELS[s] + ELBOW_LABELS[e] + WRIST_LABELS[w], bool(d))
                for q, (s, e, w), d in zip(Q.tolist(), codes.tolist(), degen.tolist())]
