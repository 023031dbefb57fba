r"""Closed-form IK of 6R arms with three consecutive parallel axes (2, 3, 4) whose axes 5 and 6
meet — the UR3/UR5/UR10/UR16 family (Lecture 5's tools: ``a cos θ + b sin θ = c``, the
planar 2-link arm).

Canonical chain ``Z₁X₁Z₂X₂Z₃X₃Z₄X₄Z₅X₅Z₆`` (:mod:`robokit.ik._dh_chain`); axes 2–4 share the
direction u (α₂, α₃ ∈ {0, π}); W is the point where axes 5 and 6 meet.

1. **θ₁.** W lies on axis 5, so it does not move with θ₅ (nor with θ₆: it is on axis 6) and is
   fixed in link 4; joints 2–4 turn about u, so W's coordinate along u, measured in the
   frame after ``X₁``, is a constant K_W of the arm. With ``⁰W = T₀₆·⁶W`` and
   ``u = Rz(θ₁)Rx(α₁)e₃`` this is ``(−sα₁W_y) cos θ₁ + (sα₁W_x) sin θ₁ = K_W − cα₁(W_z − d₁)``:
   two θ₁ (shoulder left/right) by :func:`robokit.ik.paden_kahan.solve_trig`.
2. **θ₅.** u is fixed in link 4, so in the tool frame ``ũ = R₄₆ᵀe₃`` (up to the sign σ of
   α₂, α₃ flips) and ``ũ_z = cα₄cα₅ − sα₄sα₅ cos θ₅``: two θ₅ (wrist flip/no flip).
3. **θ₆.** ``(ũ_x, ũ_y) = Rz(−θ₆)(v_x, v_y)`` with v known from θ₅: θ₆ = atan2(v_y, v_x) −
   atan2(ũ_y, ũ_x). When axis 6 is parallel to u (sin θ₅ = 0 for UR), θ₆ is free: the
   documented choice is ``q₆ = wrist_ref`` and the solution is flagged.
4. **θ₂, θ₃, θ₄.** ``T₁₄ = (Z₁X₁)⁻¹ T₀₆ (X₄Z₅X₅Z₆)⁻¹`` is a planar 3R motion: its angle
   φ = θ₂ + θ₃ + θ₄ and the position of frame 4's origin, reached by the 2-link arm
   (a₂, a₃) — two elbows (up/down) by the law of cosines.

In general position 2 × 2 × 2 = 8 solutions.
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


@dataclass(frozen=True)
class ParallelAxesConstants:
    r"""The numbers of the three-parallel-axes method for one canonical chain (module docstring).

    What :class:`ParallelAxesSolver` exports (:meth:`ParallelAxesSolver.constants`) for the
    compiled kernel (:mod:`robokit.kernels.closed_form`) and the C emitter
    (:mod:`robokit.codegen.ik`). Lengths in m, angles in rad.

    Attributes
    ----------
    th0, d0 : tuple of float
        The chain's six joint offsets θ₀ (rad) and d₀ (m).
    ca, sa : tuple of float
        cos αᵢ, sin αᵢ of the five twists (exact zeros for right angles).
    s2, sig : float
        ±1: the sign of cos α₂ (α₂ = 0 or π) and of cos α₂ · cos α₃.
    a1, a2, a3, a4, a5 : float
        Link lengths (m).
    d1, d5, d6 : float
        Joint offsets d₁, d₅, d₆ (m).
    KW : float
        W's coordinate along the parallel axes in the frame after X₁ (m; step 1).
    w6 : tuple of float
        W (where axes 5 and 6 meet) in the frame after Z₆ (m).

    Examples
    --------
    >>> import robokit
    >>> from robokit.ik._dh_chain import DHChain
    >>> from robokit.description.urdf_to_dh import dh_from_urdf
    >>> c = ParallelAxesSolver(DHChain(dh_from_urdf(robokit.load("ur5"), "standard").table)).constants()
    >>> c.s2, c.sig
    (1.0, 1.0)
    """

    th0: tuple[float, ...]
    d0: tuple[float, ...]
    ca: tuple[float, ...]
    sa: tuple[float, ...]
    s2: float
    sig: float
    a1: float
    a2: float
    a3: float
    a4: float
    a5: float
    d1: float
    d5: float
    d6: float
    KW: float
    w6: tuple[float, float, float]


class ParallelAxesSolver:
    """The three-parallel-axes method for one chain: its constants, computed once.

    Implements :class:`robokit.ik.solver.ClosedFormSolver`: ``position`` is step 1 (θ₁,
    "right/left"), ``wrist`` steps 2–4 (θ₅ "no flip/flip", θ₆, the planar θ₂–θ₄ "elbow
    up/down"), ``joint_angles`` all of them.

    Parameters
    ----------
    chain : DHChain
        The canonical chain (6 revolute joints, axes 2–4 parallel, axes 5 and 6 meeting).

    Examples
    --------
    >>> import robokit
    >>> from robokit.ik._dh_chain import DHChain
    >>> from robokit.description.urdf_to_dh import dh_from_urdf
    >>> ParallelAxesSolver(DHChain(dh_from_urdf(robokit.load("ur5"), "standard").table)).method
    'three parallel axes'
    """

    method = "three parallel axes"

    def __init__(self, chain: DHChain) -> None:
        self.chain = chain
        al, a, d0, th0 = chain.alpha, chain.a, chain.d0, chain.th0
        self.ca = [math.cos(x) for x in al]
        self.sa = [math.sin(x) for x in al]
        for i in range(5):
            if abs(self.ca[i]) < 1e-15:
                self.ca[i] = 0.0
            if abs(self.sa[i]) < 1e-15:
                self.sa[i] = 0.0
        self.s2 = 1.0 if self.ca[1] > 0 else -1.0  # α₂ = 0 or π
        self.s3 = 1.0 if self.ca[2] > 0 else -1.0
        self.sig = self.s2 * self.s3
        self.a1, self.a2, self.a3 = float(a[0]), float(a[1]), float(a[2])
        self.d1 = float(d0[0])
        # W in frame 4 (after Z₄) and in frame 6 (after Z₆): a₅ = 0 puts it at frame 5's origin
        X4 = chain.x(3)
        self.w4 = X4[:3, :3] @ np.array([0.0, 0.0, d0[4]]) + X4[:3, 3]
        G56 = chain.x(4) @ chain.z(5, 0.0)
        self.w6 = np.linalg.inv(G56)[:3, 3].copy()
        # K_W: W's coordinate along u in the frame after X₁ (θ₂..θ₄-invariant)
        P = chain.z(1, 0.0) @ chain.x(1) @ chain.z(2, 0.0) @ chain.x(2) @ chain.z(3, 0.0)
        self.KW = float((P[:3, :3] @ self.w4 + P[:3, 3])[2])
        self.X4, self.X5 = X4, chain.x(4)
        self.d5, self.d6 = float(d0[4]), float(d0[5])
        self.th0 = th0
        self.th0_list = [float(t) for t in th0]
        self.w6_list = [float(v) for v in self.w6]
        self.a4, self.a5 = float(a[3]), float(a[4])

    def constants(self) -> ParallelAxesConstants:
        """The solver's constants as an immutable record (what the kernel and the C emitter read).

        Returns
        -------
        ParallelAxesConstants

        Examples
        --------
        >>> import robokit
        >>> from robokit.ik._dh_chain import DHChain
        >>> from robokit.description.urdf_to_dh import dh_from_urdf
        >>> round(ParallelAxesSolver(DHChain(dh_from_urdf(robokit.load("ur5"), "standard").table)).constants().a2, 3)
        0.425
        """
        w6 = self.w6_list
        return ParallelAxesConstants(
            th0=tuple(self.th0_list), d0=tuple(float(v) for v in self.chain.d0), ca=tuple(self.ca),
            sa=tuple(self.sa), s2=self.s2, sig=self.sig, a1=self.a1, a2=self.a2, a3=self.a3, a4=self.a4, a5=self.a5,
            d1=self.d1, d5=self.d5, d6=self.d6, KW=self.KW, w6=(w6[0], w6[1], w6[2]))

    def kernel_constants(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """``(ci, cf, C)`` for :func:`robokit.kernels.closed_form.closed_form_solve`: :meth:`constants`
        packed into flat arrays."""
        k = self.constants()
        ci = np.array([1, 0, 1, 0, 0, 0], dtype=np.int64)
        cf = np.zeros(64)
        cf[0:6], cf[6:12] = k.th0, k.d0
        cf[12:17], cf[17:22] = k.ca, k.sa
        cf[22:31] = k.a1, k.a2, k.a3, k.a4, k.a5, k.d1, k.d5, k.d6, k.KW
        cf[31:34] = k.w6
        cf[34], cf[35] = k.s2, k.sig
        return ci, cf, np.zeros((5, 5))

    def solve(self, T06: np.ndarray, wrist_ref: float) -> list[tuple[Sequence[float], str, bool]]:
        """Rows (q (6,), label, degenerate) of every solution for the pose T06 (frame 0′).

        Plain float arithmetic (no per-solution numpy): the poses of step 4 are composed
        from the elementary rotations written out.
        """
        T = T06.tolist()
        rows: list[Row] = []
        for branch in self._branches(T):
            rows.extend(self._complete(T, branch, wrist_ref))
        return rows

    def position(self, T06: np.ndarray) -> list[PositionBranch]:
        """θ₁ from W's coordinate along the parallel axes (step 1): the shoulder branches.

        Parameters
        ----------
        T06 : (4, 4) ndarray
            Target of ``Z₁X₁ ⋯ Z₆`` in frame 0′ (m).

        Returns
        -------
        list of PositionBranch
            ``q`` (1,) joint variable 1, ``label`` ``"right, "`` or ``"left, "``,
            ``data`` θ₁ (rad, the DH offset included).
        """
        return self._branches(T06.tolist())

    def wrist(self, T06: np.ndarray, branch: PositionBranch, wrist_ref: float) -> list[Row]:
        """θ₅, θ₆ and the planar θ₂–θ₄ (steps 2–4) for one θ₁: rows ``(q (6,), label, degenerate)``.

        At the singularity (axis 6 parallel to the parallel axes) ``q₆ = wrist_ref``.
        """
        return self._complete(T06.tolist(), branch, wrist_ref)

    def joint_angles(self, T06: np.ndarray, wrist_ref: float) -> list[Row]:
        """Every row ``(q (6,), label, degenerate)`` reaching ``T06`` (2 × 2 × 2 in general)."""
        return self.solve(T06, wrist_ref)

    def refusal(self) -> str | None:
        """None: the detection of three parallel axes is all this method needs."""
        return None

    def _branches(self, T: list[list[float]]) -> list[PositionBranch]:
        (r00, r01, r02, px), (r10, r11, r12, py), (r20, r21, r22, pz) = T[:3]
        w6x, w6y, w6z = self.w6_list
        Wx = r00 * w6x + r01 * w6y + r02 * w6z + px
        Wy = r10 * w6x + r11 * w6y + r12 * w6z + py
        Wz = r20 * w6x + r21 * w6y + r22 * w6z + pz
        ca1, sa1 = self.ca[0], self.sa[0]
        th0 = self.th0_list
        t1s = _trig_roots(-sa1 * Wy, sa1 * Wx, self.KW - ca1 * (Wz - self.d1), 1e-10)
        if not t1s:
            return []
        out = []
        for t1 in t1s:
            c1, s1 = math.cos(t1), math.sin(t1)
            shoulder = "right, " if (c1 * Wx + s1 * Wy) * sa1 >= 0.0 else "left, "
            out.append(PositionBranch((t1 - th0[0],), shoulder, False, t1))
        return out

    def _complete(self, T: list[list[float]], branch: PositionBranch, wrist_ref: float) -> list[Row]:
        (r00, r01, r02, px), (r10, r11, r12, py), (r20, r21, r22, pz) = T[:3]
        ca, sa = self.ca, self.sa
        ca1, sa1, ca4, sa4, ca5, sa5 = ca[0], sa[0], ca[3], sa[3], ca[4], sa[4]
        th0 = self.th0_list
        a1, a2, a3, a4, a5 = self.a1, self.a2, self.a3, self.a4, self.a5
        d5, d6, sig = self.d5, self.d6, self.sig
        right_angles = ca4 == 0.0 and ca5 == 0.0
        out: list[Row] = []
        shoulder, t1 = branch.label, branch.data
        c1, s1 = math.cos(t1), math.sin(t1)
        ux, uy, uz = sa1 * s1, -sa1 * c1, ca1  # u = Rz(θ₁)Rx(α₁)e₃
        # ũ = σ R₀₆ᵀ u: u seen from the tool
        utx = sig * (r00 * ux + r10 * uy + r20 * uz)
        uty = sig * (r01 * ux + r11 * uy + r21 * uz)
        utz = sig * (r02 * ux + r12 * uy + r22 * uz)
        rho = math.hypot(utx, uty)  # |sin| of the angle between axis 6 and u
        if right_angles:  # (UR) |s₅| = ρ, c₅ = −ũ_z/(sα₄sα₅)
            c5r = -utz / (sa4 * sa5)
            t5s: list[float] | None = ([math.atan2(rho, c5r), math.atan2(-rho, c5r)] if rho > 1e-10
                                       else [math.atan2(0.0, c5r)])
        else:
            t5s = _trig_roots(-sa4 * sa5, 0.0, utz - ca4 * ca5, 1e-10)
        if not t5s:
            return out
        for t5 in t5s:
            c5, s5 = math.cos(t5), math.sin(t5)
            vx, vy = s5 * sa4, ca5 * c5 * sa4 + sa5 * ca4
            if rho <= 1e-10:
                t6, degenerate = th0[5] + wrist_ref, True
            else:
                t6, degenerate = math.atan2(vy, vx) - math.atan2(uty, utx), False
            c6, s6 = math.cos(t6), math.sin(t6)
            # G = X₄Z₅X₅Z₆ (frame 4 → frame 6). gx = Gᵀe₁ (x₄ in frame 6): Rz(−θ₆)Rx(−α₅)Rz(−θ₅)e₁
            gx0, gy0, gz0 = c5, -ca5 * s5, sa5 * s5
            gx = (c6 * gx0 + s6 * gy0, -s6 * gx0 + c6 * gy0, gz0)
            # frame 4's origin in frame 6: child coordinates through X₄, Z₅, X₅, Z₆
            ox, oy, oz = -a4, 0.0, 0.0
            ox, oy, oz = c5 * ox + s5 * oy, -s5 * ox + c5 * oy, oz - d5
            ox, oy, oz = ox - a5, ca5 * oy + sa5 * oz, -sa5 * oy + ca5 * oz
            ox, oy, oz = c6 * ox + s6 * oy, -s6 * ox + c6 * oy, oz - d6
            # in frame 0′: x₄ = R₀₆ gx, o₄ = p + R₀₆ o
            X0 = r00 * gx[0] + r01 * gx[1] + r02 * gx[2]
            X1 = r10 * gx[0] + r11 * gx[1] + r12 * gx[2]
            X2 = r20 * gx[0] + r21 * gx[1] + r22 * gx[2]
            O0 = px + r00 * ox + r01 * oy + r02 * oz - a1 * c1
            O1 = py + r10 * ox + r11 * oy + r12 * oz - a1 * s1
            O2 = pz + r20 * ox + r21 * oy + r22 * oz - self.d1
            # into the frame after X₁: R₁ᵀ with R₁ = Rz(θ₁)Rx(α₁) (columns (c₁, s₁, 0), (−s₁cα₁, c₁cα₁, sα₁))
            phi = math.atan2(-s1 * ca1 * X0 + c1 * ca1 * X1 + sa1 * X2, c1 * X0 + s1 * X1)
            x = c1 * O0 + s1 * O1
            y = -s1 * ca1 * O0 + c1 * ca1 * O1 + sa1 * O2
            c3 = (x * x + y * y - a2 * a2 - a3 * a3) / (2.0 * a2 * a3)
            if abs(c3) > 1.0 + 1e-10:
                continue
            c3 = max(-1.0, min(1.0, c3))
            s3a = math.sqrt(max(0.0, 1.0 - c3 * c3))
            wrist = "wrist singular" if degenerate else ("no flip" if s5 * sa4 * sa5 > 0.0 else "flip")
            base = math.atan2(y, x)
            for s3 in ((s3a, -s3a) if s3a > 0.0 else (0.0,)):
                psi = math.atan2(s3, c3)
                t2 = base - math.atan2(a3 * s3, a2 + a3 * c3)
                t3, t4 = self.s2 * psi, sig * (phi - t2 - psi)
                elbow = "elbow down, " if a2 * a3 * s3 > 0.0 else "elbow up, "
                q = (t1 - th0[0], t2 - th0[1], t3 - th0[2], t4 - th0[3], t5 - th0[4], t6 - th0[5])
                out.append((q, shoulder + elbow + wrist, degenerate))
        return out
