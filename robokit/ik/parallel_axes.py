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

import numpy as np

from robokit.ik.paden_kahan import _trig_roots


class ParallelAxesSolver:
    """Precomputed constants of the three-parallel-axes method for one chain."""

    def __init__(self, chain):
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

    def solve(self, T06, q6_ref):
        """Rows (q (6,), label parts, degenerate) of every solution for the pose T06 (frame 0′)."""
        R, p = T06[:3, :3], T06[:3, 3]
        W = R @ self.w6 + p
        Wx, Wy, Wz = float(W[0]), float(W[1]), float(W[2])
        ca, sa = self.ca, self.sa
        ca1, sa1, ca4, sa4, ca5, sa5 = ca[0], sa[0], ca[3], sa[3], ca[4], sa[4]
        th0 = self.th0
        t1s = _trig_roots(-sa1 * Wy, sa1 * Wx, self.KW - ca1 * (Wz - self.d1), 1e-10)
        if not t1s:
            return []
        out = []
        a1, a2, a3 = self.a1, self.a2, self.a3
        for t1 in t1s:
            c1, s1 = math.cos(t1), math.sin(t1)
            x1 = c1 * Wx + s1 * Wy
            shoulder = "right" if x1 * sa1 >= 0.0 else "left"
            u = np.array([sa1 * s1, -sa1 * c1, ca1])
            ut = self.sig * (R.T @ u)
            rho = math.hypot(float(ut[0]), float(ut[1]))  # |sin| of the angle between axis 6 and u
            if ca4 == 0.0 and ca5 == 0.0:  # right-angled wrist (UR): |s₅| = ρ, c₅ = −ũ_z/(sα₄sα₅)
                c5r = -float(ut[2]) / (sa4 * sa5)
                t5s = [math.atan2(rho, c5r), math.atan2(-rho, c5r)] if rho > 1e-10 else [math.atan2(0.0, c5r)]
            else:
                t5s = _trig_roots(-sa4 * sa5, 0.0, float(ut[2]) - ca4 * ca5, 1e-10)
            if not t5s:
                continue
            # (Z₁X₁)⁻¹ as a 4×4
            R1 = np.array([[c1, -s1 * ca1, s1 * sa1], [s1, c1 * ca1, -c1 * sa1], [0.0, sa1, ca1]])
            o1 = np.array([a1 * c1, a1 * s1, self.d1])
            for t5 in t5s:
                c5, s5 = math.cos(t5), math.sin(t5)
                vx, vy = s5 * sa4, ca5 * c5 * sa4 + sa5 * ca4
                if rho <= 1e-10:
                    t6, degenerate = th0[5] + q6_ref, True
                else:
                    t6, degenerate = math.atan2(vy, vx) - math.atan2(float(ut[1]), float(ut[0])), False
                G = self.X4 @ _z4(t5, self.d5) @ self.X5 @ _z4(t6, self.d6)
                # T₁₄ = (Z₁X₁)⁻¹ T₀₆ G⁻¹
                Rg, pg = G[:3, :3], G[:3, 3]
                R14 = R1.T @ (R @ Rg.T)
                p14 = R1.T @ (p - R @ (Rg.T @ pg) - o1)
                phi = math.atan2(R14[1, 0], R14[0, 0])
                x, y = float(p14[0]), float(p14[1])
                c3 = (x * x + y * y - a2 * a2 - a3 * a3) / (2.0 * a2 * a3)
                if abs(c3) > 1.0 + 1e-10:
                    continue
                c3 = max(-1.0, min(1.0, c3))
                s3a = math.sqrt(max(0.0, 1.0 - c3 * c3))
                wrist = "wrist singular" if degenerate else ("no flip" if s5 * sa4 * sa5 > 0.0 else "flip")
                for sgn in (1.0, -1.0):
                    s3 = sgn * s3a
                    psi = math.atan2(s3, c3)
                    t2 = math.atan2(y, x) - math.atan2(a3 * s3, a2 + a3 * c3)
                    t4p = phi - t2 - psi
                    t3, t4 = self.s2 * psi, self.sig * t4p
                    elbow = "elbow down" if a2 * a3 * s3 > 0.0 else "elbow up"
                    q = [t1 - th0[0], t2 - th0[1], t3 - th0[2], t4 - th0[3], t5 - th0[4], t6 - th0[5]]
                    out.append((q, f"{shoulder}, {elbow}, {wrist}", degenerate))
                    if s3a == 0.0:
                        break
        return out


def _z4(theta, d):
    c, s = math.cos(theta), math.sin(theta)
    return np.array([[c, -s, 0.0, 0.0], [s, c, 0.0, 0.0], [0.0, 0.0, 1.0, d], [0.0, 0.0, 0.0, 1.0]])
