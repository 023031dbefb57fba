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

Roots come from ``numpy.roots`` (the eigenvalues of the companion matrix), are polished by
Newton steps on the polynomial, taken in ascending order (so the solutions come in an order
that does not depend on the eigen-solver), and each (θ₁, θ₂, θ₃) is checked — and, if needed,
polished by Newton steps on the wrist-centre equation ``⁰W(q₁, q₂, q₃) = ⁰W`` itself.

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

from robokit.ik.paden_kahan import _trig_roots
from robokit.ik.solution import Row
from robokit.ik.solver import PositionBranch

if TYPE_CHECKING:
    from robokit.ik._dh_chain import DHChain

_PI = math.pi
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


def _val(coef: Sequence[float] | np.ndarray, x: float, kind: str, cs: tuple[float, float] | None = None) -> float:
    """Value of a coefficient triple at θ (revolute; ``cs`` = (cos θ, sin θ)) or q (prismatic)."""
    if kind == "R":
        assert cs is not None  # a revolute joint's value needs (cos θ, sin θ)
        c, s = cs
        return coef[0] + coef[1] * c + coef[2] * s
    return coef[0] + (coef[1] + coef[2] * x) * x


def _rz_v(c: float, s: float, v: Sequence[float]) -> tuple[float, float, float]:
    return (c * v[0] - s * v[1], s * v[0] + c * v[1], v[2])


def _rx_v(c: float, s: float, v: Sequence[float]) -> tuple[float, float, float]:
    return (v[0], c * v[1] - s * v[2], s * v[1] + c * v[2])


Triple = tuple[float, float, float]


def _triple(x: Sequence[float] | np.ndarray) -> Triple:
    return (float(x[0]), float(x[1]), float(x[2]))


@dataclass(frozen=True)
class PieperConstants:
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
    th0, d0 : tuple of float
        The chain's six joint offsets θ₀ (rad) and d₀ (m).
    ca, sa : tuple of float
        cos αᵢ, sin αᵢ of the five twists (exact zeros for right angles).
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
    th0: tuple[float, ...]
    d0: tuple[float, ...]
    ca: tuple[float, ...]
    sa: tuple[float, ...]
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
            self.c2s2 = (c2, s2)
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
        self.rot_kinds = k[:3]

    def constants(self) -> PieperConstants:
        """The solver's constants as an immutable record (what the kernel and the C emitter read).

        Returns
        -------
        PieperConstants

        Examples
        --------
        >>> import robokit
        >>> from robokit.ik._dh_chain import DHChain
        >>> PieperSolver(DHChain(robokit.load("puma560").dh)).constants().w6
        (0.0, 0.0, 0.0)
        """
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

    def kernel_constants(self) -> tuple[np.ndarray, np.ndarray, np.ndarray] | None:
        """``(ci, cf, C)`` for :func:`robokit.kernels.closed_form.closed_form_solve` (revolute
        joints 1 and 2; joint 3 revolute or prismatic), or None when only this Python solver
        covers the chain (a prismatic joint 1 or 2): :meth:`constants` packed into flat arrays."""
        k = self.constants()
        if k.Ka is None or k.Kb is None:
            return None
        ci = np.array([0, {"RR-quartic": 0, "RR-a1": 1, "RR-s1": 2}[k.case], int(k.kinds[2] == "R"), k.deg,
                       len(k.C), 0], dtype=np.int64)
        cf = np.zeros(64)
        cf[0:6], cf[6:12] = k.th0, k.d0
        cf[12:17], cf[17:22] = k.ca, k.sa
        cf[22:26] = k.a1, k.a2, k.d1, k.d2
        cf[26:29], cf[29:32] = k.w3, k.w6
        cf[32:41] = k.f[0] + k.f[1] + k.f[2]
        cf[41:44], cf[44:47], cf[47:50] = k.Ka, k.Kb, k.v
        cf[50] = k.scale
        C = np.zeros((5, 5))
        C[: len(k.C), : k.deg + 1] = k.C
        return ci, cf, C

    # ------------------------------------------------------------------ position
    def _roots(self, coeffs: Sequence[float]) -> list[float] | None:
        """Real roots of Σ cₖ tᵏ as joint-3 values (θ₃ total angle or d₃ variable)."""
        scale = max(abs(x) for x in coeffs)
        if scale == 0.0:
            return None  # identically satisfied: θ₃ free
        c = coeffs
        deg = len(c) - 1
        extra = []
        while deg > 0 and abs(c[deg]) <= 1e-11 * scale:
            deg -= 1
        if self.j3 == "R" and deg < len(c) - 1:
            extra.append(_PI)  # the root u = ∞ (θ₃ = π) of the degree-deficient polynomial
        if deg == 0:
            ts = []
        elif deg == 1:
            ts = [-c[0] / c[1]]
        elif deg == 2:
            A, B, C0 = c[2], c[1], c[0]
            disc = B * B - 4.0 * A * C0
            if disc < -1e-12 * max(B * B, abs(4.0 * A * C0), 1e-300):
                ts = []
            else:
                sq = math.sqrt(max(disc, 0.0))
                q = -0.5 * (B + (sq if B >= 0.0 else -sq))
                ts = [q / A, C0 / q] if q != 0.0 else [0.0]
        else:
            # the companion matrix of the monic polynomial; its eigenvalues are the roots
            comp = np.zeros((deg, deg))
            comp[0, :] = [-c[deg - 1 - j] / c[deg] for j in range(deg)]
            comp[np.arange(1, deg), np.arange(deg - 1)] = 1.0
            rts = np.linalg.eigvals(comp).tolist()
            ts = [float(z.real) for z in rts if abs(z.imag) <= 1e-6 * (1.0 + abs(z.real))]
            ts = sorted(self._newton_poly(c[: deg + 1], t) for t in ts)  # ascending: an order that does not depend on LAPACK
        if self.j3 == "R":
            return [2.0 * math.atan(t) for t in ts] + extra
        return ts

    @staticmethod
    def _newton_poly(c: Sequence[float], t: float) -> float:
        for _ in range(3):
            p, dp = 0.0, 0.0
            for ck in c[::-1]:
                dp = dp * t + p
                p = p * t + ck
            if dp == 0.0:
                break
            step = p / dp
            t -= step
            if abs(step) <= 1e-15 * (1.0 + abs(t)):
                break
        return t

    def _wrist_point(self, th: Sequence[float], dd: Sequence[float]) -> tuple[float, float, float]:
        """⁰W of joint values given as rotation angles th (3,) and offsets dd (3,) — a check."""
        c3, s3 = math.cos(th[2]), math.sin(th[2])
        w3 = self.w3_list
        p = _rz_v(c3, s3, (w3[0], w3[1], w3[2] + dd[2]))
        p = _rx_v(self.ca[1], self.sa[1], (p[0] + self.a2, p[1], p[2]))
        c2, s2 = math.cos(th[1]), math.sin(th[1])
        p = _rz_v(c2, s2, (p[0], p[1], p[2] + dd[1]))
        p = _rx_v(self.ca[0], self.sa[0], (p[0] + self.a1, p[1], p[2]))
        c1, s1 = math.cos(th[0]), math.sin(th[0])
        return _rz_v(c1, s1, (p[0], p[1], p[2] + dd[0]))

    def _angles(self, q: Sequence[float]) -> tuple[list[float], list[float]]:
        """(rotation angles, offsets) of joints 1–3 at joint values q."""
        kinds, th0, d0 = self.chain.kinds, self.th0_list, self.d0_list
        th, dd = [], []
        for i in range(3):
            if kinds[i] == "R":
                th.append(th0[i] + q[i])
                dd.append(d0[i])
            else:
                th.append(th0[i])
                dd.append(d0[i] + q[i])
        return th, dd

    def _polish(self, q: Sequence[float], W: Sequence[float]) -> tuple[list[float], float]:
        """Newton steps on ⁰W(q₁, q₂, q₃) = W (the wrist-centre equation); returns (q, error)."""
        q = list(q)
        err = math.inf
        for it in range(4):
            th, dd = self._angles(q)
            p = self._wrist_point(th, dd)
            e = np.array([W[0] - p[0], W[1] - p[1], W[2] - p[2]])
            err = float(np.abs(e).max())
            if err <= 1e-13 * self.chain.scale or it == 3:
                break
            J = np.empty((3, 3))
            h = 1e-7
            for j in range(3):
                qq = list(q)
                qq[j] += h
                t2, d2 = self._angles(qq)
                p2 = self._wrist_point(t2, d2)
                qq[j] -= 2 * h
                t3, d3 = self._angles(qq)
                p3 = self._wrist_point(t3, d3)
                J[:, j] = [(p2[k] - p3[k]) / (2 * h) for k in range(3)]
            try:
                dq = np.linalg.lstsq(J, e, rcond=1e-12)[0]
            except np.linalg.LinAlgError:  # pragma: no cover
                break
            q = [q[k] + float(dq[k]) for k in range(3)]
        return q, err

    def wrist_centre_joints(self, W: Sequence[float]) -> list[tuple[list[float], bool, bool]]:
        """Every (q₁, q₂, q₃, label parts, degenerate) placing the wrist centre at W (frame 0′)."""
        th0, d0 = self.th0_list, self.d0_list
        ca1, sa1 = self.ca[0], self.sa[0]
        a1 = self.a1
        f1c, f2c, f3c = self.f
        kind = self.j3
        Wx, Wy, Wz = W
        if self.j1 == "R":
            h = Wz - self.d1
            r = Wx * Wx + Wy * Wy + h * h
            case = self.case
            assert case is not None  # set in __init__
            m = {"RR-quartic": (r * r, r, h * h, h, 1.0), "RR-a1": (r, 1.0), "RR-s1": (h, 1.0),
                 "RP-quartic": (r, h * h, h, 1.0), "RP-c1": (h, 1.0)}[case]
        else:
            c0, s0 = math.cos(th0[0]), math.sin(th0[0])
            xp, yp = c0 * Wx + s0 * Wy, -s0 * Wx + c0 * Wy
            zp = Wz
            X = xp - a1
            case = self.case
            assert case is not None  # set in __init__
            m = {"PR-quartic": (X * X, yp * yp, yp, 1.0), "PR-c1": (yp, 1.0), "PP": (X, 1.0)}[case]
        C = self.C_list
        coeffs = [sum(mk * row[j] for mk, row in zip(m, C)) for j in range(self.deg + 1)]
        roots3 = self._roots(coeffs)
        check = self.deg == 4  # roots from the companion matrix: verify (and polish) each triple
        degenerate = False
        if roots3 is None:  # the equation holds for every joint-3 value: documented choice q₃ = 0
            roots3 = [th0[2] if kind == "R" else 0.0]
            degenerate = True
        out = []
        for x3 in roots3:
            cs = (math.cos(x3), math.sin(x3)) if kind == "R" else None
            f1, f2, f3 = _val(f1c, x3, kind, cs), _val(f2c, x3, kind, cs), _val(f3c, x3, kind, cs)
            q3 = x3 - th0[2] if kind == "R" else x3
            cand = []  # (rotation angle θ₂ or offset d₂, g₁, g₂, g₃)
            if self.j2 == "R":
                F3 = f3 + self.d2
                if self.j1 == "R":
                    Ka = _val(self.Ka, x3, kind, cs)
                    sa_, ra = 2.0 * a1, r - Ka
                    sb_, rb = sa1, h - ca1 * F3
                else:
                    sa_, ra = 1.0, X
                    sb_, rb = ca1, yp + sa1 * F3
                th2s: list[float] | None = []
                if case in ("RR-quartic", "PR-quartic"):
                    n2 = f1 * f1 + f2 * f2
                    if n2 > 1e-24 * self.chain.scale ** 2:
                        A, B = ra / sa_, rb / sb_
                        th2s = [math.atan2(f1 * B - f2 * A, f1 * A + f2 * B)]
                    else:
                        th2s = [th0[1]]
                        degenerate = True
                elif case == "RR-a1":  # θ₂ from eq. b: sb(F₂c₂ + F₁s₂) = rb
                    th2s = _trig_roots(sb_ * f2, sb_ * f1, rb, 1e-10)
                else:  # RR-s1, PR-c1: θ₂ from eq. a: sa(F₁c₂ − F₂s₂) = ra
                    th2s = _trig_roots(sa_ * f1, -sa_ * f2, ra, 1e-10)
                if th2s is None:
                    th2s, degenerate = [th0[1]], True
                for t2 in th2s:
                    c2, s2 = math.cos(t2), math.sin(t2)
                    g1 = a1 + c2 * f1 - s2 * f2
                    u = s2 * f1 + c2 * f2
                    cand.append((t2 - th0[1], g1, ca1 * u - sa1 * F3, sa1 * u + ca1 * F3))
            else:
                pc1, pc2 = self.phi
                p1, p2 = _val(pc1, x3, kind, cs), _val(pc2, x3, kind, cs)
                if self.j1 == "R":
                    if case == "RP-quartic":
                        Ds = [(h - sa1 * p2) / ca1 - f3]
                    else:
                        nf2 = _val(self.nf2, x3, kind, cs)
                        Ds = self._quad_roots(1.0, 2.0 * f3, a1 * a1 + nf2 + 2.0 * a1 * p1 - r)
                else:
                    Ds = [(ca1 * p2 - yp) / sa1 - f3]
                for D in Ds:
                    cand.append((D - d0[1], a1 + p1, ca1 * p2 - sa1 * (f3 + D), sa1 * p2 + ca1 * (f3 + D)))
            for q2, g1, g2, g3 in cand:
                if self.j1 == "R":
                    if math.hypot(g1, g2) <= 1e-12 * self.chain.scale:
                        t1, singular1 = th0[0], True
                    else:
                        t1, singular1 = math.atan2(Wy, Wx) - math.atan2(g2, g1), False
                    q1 = t1 - th0[0]
                else:
                    q1, singular1 = zp - d0[0] - g3, False
                q = [q1, q2, q3]
                if not check:  # closed-form roots (degree ≤ 2): the back-substitution is exact
                    out.append((q, singular1, degenerate))
                    continue
                th, dd = self._angles(q)
                p = self._wrist_point(th, dd)
                err = max(abs(W[0] - p[0]), abs(W[1] - p[1]), abs(W[2] - p[2]))
                if err > 1e-12 * self.chain.scale:
                    if err > 1e-5 * self.chain.scale:
                        continue  # a spurious root (a complex pair taken as real)
                    q, err = self._polish(q, W)
                    if err > 1e-11 * self.chain.scale:
                        continue
                out.append((q, singular1, degenerate))
        return out

    @staticmethod
    def _quad_roots(A: float, B: float, C: float) -> list[float]:
        disc = B * B - 4.0 * A * C
        if disc < -1e-12 * max(B * B, abs(4.0 * A * C), 1e-300):
            return []
        sq = math.sqrt(max(disc, 0.0))
        qv = -0.5 * (B + (sq if B >= 0.0 else -sq))
        if qv == 0.0:
            return [0.0]
        return [qv / A, C / qv] if sq > 0.0 else [qv / A]

    # ------------------------------------------------------------------ orientation
    def wrist_angles(self, th: Sequence[float], R06: Sequence[Sequence[float]],
                     q4_ref: float) -> list[tuple[float, float, float, str, bool]]:
        """Every (θ₄, θ₅, θ₆ rotation angles, flip, degenerate) with
        Rz(θ₄)Rx(α₄)Rz(θ₅)Rx(α₅)Rz(θ₆) = R₃ᵀR₀₆, R₃ = Rz(θ₁)Rx(α₁)Rz(θ₂)Rx(α₂)Rz(θ₃)Rx(α₃).

        ``R06`` is a nested list (3×3, rows); plain float arithmetic, no numpy.
        """
        ca, sa = self.ca, self.sa
        cs = [(math.cos(t), math.sin(t)) for t in th]
        (r00, r01, r02), (r10, r11, r12), (r20, r21, r22) = R06
        # m = R₃ᵀ z₆ (M e₃) and, for the singular case, R₃ᵀ x₆ (M e₁): apply Rz(−θ₁), Rx(−α₁), …
        mx, my, mz = r02, r12, r22
        ex, ey, ez = r00, r10, r20
        for i in range(3):
            c, s_ = cs[i]
            mx, my = c * mx + s_ * my, c * my - s_ * mx
            ex, ey = c * ex + s_ * ey, c * ey - s_ * ex
            c, s_ = ca[i], sa[i]
            my, mz = c * my + s_ * mz, c * mz - s_ * my
            ey, ez = c * ey + s_ * ez, c * ez - s_ * ey
        # n₄ = R₃ e₃ (axis 4 in frame 0′): apply Rx(α₃), Rz(θ₃), …, Rz(θ₁) to e₃
        nx, ny, nz = 0.0, 0.0, 1.0
        for i in (2, 1, 0):
            c, s_ = ca[i], sa[i]
            ny, nz = c * ny - s_ * nz, s_ * ny + c * nz
            c, s_ = cs[i]
            nx, ny = c * nx - s_ * ny, s_ * nx + c * ny
        row0 = r00 * nx + r10 * ny + r20 * nz  # e₃ᵀM = (R₀₆ᵀ n₄)ᵀ
        row1 = r01 * nx + r11 * ny + r21 * nz
        ca4, sa4, ca5, sa5 = self.ca4, self.sa4, self.ca5, self.sa5
        k = sa4 * sa5
        rho = math.hypot(mx, my)  # |sin| of the angle between axes 4 and 6
        if ca4 == 0.0 and ca5 == 0.0:  # right-angled wrist (ZYZ type): |s₅| = ρ, c₅ = −M₂₂/(sα₄sα₅)
            c5, s5 = -mz / k, rho
        else:
            c5 = (ca4 * ca5 - mz) / k
            if abs(c5) > 1.0 + 1e-10:
                return []  # this orientation is out of reach of an oblique wrist
            c5 = max(-1.0, min(1.0, c5))
            s5 = math.sqrt(max(0.0, 1.0 - c5 * c5))
        if rho <= 1e-10:  # axes 4 and 6 aligned: only θ₄ + θ₆ or θ₄ − θ₆ is fixed
            th4_ref = q4_ref + self.th0_list[3]
            gamma = math.atan2(ca4 * s5, c5)
            sk = 1.0 if mz > 0.0 else -1.0
            t6 = sk * (math.atan2(ey, ex) - th4_ref - gamma)
            return [(th4_ref, math.atan2(s5, c5), t6, "wrist singular", True)]
        am = math.atan2(my, mx)
        ar = math.atan2(row1, row0)
        yp = -ca4 * sa5 * c5 - sa4 * ca5
        b_ = sa4 * c5 * ca5 + ca4 * sa5
        out = []
        for s in (s5, -s5):
            t4 = am - math.atan2(yp, sa5 * s)
            t6 = math.atan2(b_, sa4 * s) - ar
            out.append((t4, math.atan2(s, c5), t6, "no flip" if s * k > 0.0 else "flip", False))
            if s5 == 0.0:
                break
        return out

    # ------------------------------------------------------------------ the solver interface
    def refusal(self) -> str | None:
        """None if joints 1–3 move the wrist centre in 3 independent directions, else the reason.

        The 3×3 Jacobian of the wrist centre (central differences) is checked at a few fixed
        pseudo-random configurations; a positioning structure that is rank-deficient at all
        of them (e.g. a prismatic joint perpendicular to a revolute one in a plane) has a
        continuum of solutions, not a finite set.
        """
        rng = np.random.default_rng(12345)
        scale = self.chain.scale
        for _ in range(4):
            q = list(rng.uniform(-2.0, 2.0, 3))
            J = np.empty((3, 3))
            h = 1e-6
            for j in range(3):
                qp, qm = list(q), list(q)
                qp[j] += h
                qm[j] -= h
                pp = self._wrist_point(*self._angles(qp))
                pm = self._wrist_point(*self._angles(qm))
                J[:, j] = [(pp[k] - pm[k]) / (2.0 * h) for k in range(3)]
            J[:, [self.chain.kinds[j] == "R" for j in range(3)]] /= scale  # revolute columns in m/rad → unitless
            if np.linalg.svd(J, compute_uv=False)[-1] > 1e-6:
                return None
        return ("axes 4–6 meet in one point, but joints 1–3 cannot move the wrist centre in three "
                "independent directions (their axes confine it to a surface)")

    def _branches(self, T: list[list[float]]) -> list[PositionBranch]:
        (r00, r01, r02, p0), (r10, r11, r12, p1), (r20, r21, r22, p2) = T[:3]
        w6x, w6y, w6z = self.w6_list
        W = (r00 * w6x + r01 * w6y + r02 * w6z + p0, r10 * w6x + r11 * w6y + r12 * w6z + p1,
             r20 * w6x + r21 * w6y + r22 * w6z + p2)
        out = []
        for q123, singular1, degen_pos in self.wrist_centre_joints(W):
            th, _ = self._angles(q123)
            head = self._shoulder(th, W, singular1) + self._elbow(q123, th)
            out.append(PositionBranch(q123, head, bool(degen_pos or singular1), th))
        return out

    def _complete(self, T: list[list[float]], branch: PositionBranch, wrist_ref: float) -> list[Row]:
        th0 = self.th0_list
        q123, head, degen_pos, th = branch
        R06 = (T[0][:3], T[1][:3], T[2][:3])
        rows: list[Row] = []
        for t4, t5, t6, flip, degen in self.wrist_angles(th, R06, wrist_ref):
            q = (q123[0], q123[1], q123[2], t4 - th0[3], t5 - th0[4], t6 - th0[5])
            rows.append((q, head + flip, degen or degen_pos))
        return rows

    def position(self, T06: np.ndarray) -> list[PositionBranch]:
        """θ₁–θ₃ placing the wrist centre ``⁰W = T06·⁶W``: one branch per (right/left, elbow up/down).

        Parameters
        ----------
        T06 : (4, 4) ndarray
            Target of ``Z₁X₁ ⋯ Z₆`` in frame 0′ (m).

        Returns
        -------
        list of PositionBranch
            ``q`` (3,) joint variables 1–3, ``label`` e.g. ``"right, elbow up, "``,
            ``data`` the rotation angles θ₁–θ₃ (offsets included).
        """
        return self._branches(T06.tolist())

    def wrist(self, T06: np.ndarray, branch: PositionBranch, wrist_ref: float) -> list[Row]:
        """The wrist's (q₄, q₅, q₆) for one position branch: ``M = R₃ᵀR₀₆`` (flip/no flip).

        Returns rows ``(q (6,), label, degenerate)``; at a wrist singularity ``q₄ = wrist_ref``.
        """
        return self._complete(T06.tolist(), branch, wrist_ref)

    def joint_angles(self, T06: np.ndarray, wrist_ref: float) -> list[Row]:
        """Every row ``(q (6,), label, degenerate)`` reaching ``T06`` (up to 4 positions × 2 wrists)."""
        T = T06.tolist()
        rows: list[Row] = []
        for branch in self._branches(T):
            rows.extend(self._complete(T, branch, wrist_ref))
        return rows

    def _shoulder(self, th: Sequence[float], W: Sequence[float], singular: bool) -> str:
        if self.chain.kinds[0] != "R":
            return ""
        if singular:
            return "shoulder singular, "
        x1 = math.cos(th[0]) * W[0] + math.sin(th[0]) * W[1]
        return "right, " if x1 >= 0.0 else "left, "

    def _elbow(self, q: Sequence[float], th: Sequence[float]) -> str:
        if self.chain.kinds[2] == "P":
            d = self.chain.d0[2] + q[2]
            return "d3 +, " if d >= 0.0 else "d3 −, "
        c3, s3 = math.cos(th[2]), math.sin(th[2])
        e = (s3 * self.v[0] + c3 * self.v[1]) * (self.a2 if self.a2 != 0.0 else 1.0)
        return "elbow down, " if e > 0.0 else "elbow up, "
