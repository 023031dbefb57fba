r"""Closed-form IK of short planar arms for :func:`robokit.ik_analytic` (Lecture 5): one to three
revolute joints about parallel axes, or a single prismatic joint.

Canonical chain ``Z₁X₁ ⋯ Z_n`` (:mod:`robokit.ik._dh_chain`), frame {0′} with joint 1's axis as
its z axis. Every axis is parallel to z (the twists are 0 or π), so the arm moves in the x–y plane
of {0′}: with ``rᵢ`` the point where axis i meets that plane, ``dᵢ = r_{i+1} − rᵢ`` (``r_{n+1}``
the origin of the frame after ``Z_n``, at q = 0) and ``ψᵢ = sᵢ θᵢ`` (sᵢ = ±1: axis i along +z or
−z), the pose reached is

``p = r₁ + Σᵢ Rot(ψ₁+⋯+ψᵢ) dᵢ``, ``R = Rz(φ) R₀`` with ``φ = ψ₁+⋯+ψ_n``, ``p_z = h``

(R₀ and h: that frame's orientation and height at q = 0). A pose T₀₆ is reachable only if
``R R₀ᵀ`` turns about z alone (|R R₀ᵀ e₃ − e₃| ≤ 1e-9) and its height is h (to 1e-9 m times the
arm's size when above 1 m); then φ = atan2 of ``R R₀ᵀ``'s first column, and

* **one joint**: ψ₁ = φ, if ``r₁ + Rot(φ) d₁`` is the target's position;
* **two joints**: the point ``w = p − r₁ − Rot(φ) d₂`` must lie at ``l₁ = |d₁|`` from r₁:
  ψ₁ = atan2(w) − atan2(d₁), ψ₂ = φ − ψ₁ — one solution (the other elbow reaches the same point
  with the tool turned differently); labelled by the side the elbow bends to;
* **three joints** (Lecture 5's planar RRR): the wrist point ``w = p − r₁ − Rot(φ) d₃`` is
  placed by the two-link arm, ``cos δ = (|w|² − l₁² − l₂²)/(2 l₁ l₂)``, δ = ±acos: "elbow
  down" (δ > 0: the second link turns counter-clockwise about z from the first), "elbow up";
  ``ψ₁ = atan2(w) − atan2(l₂ sin δ, l₁ + l₂ cos δ) − atan2(d₁)``, ``ψ₂ = δ + atan2(d₁) −
  atan2(d₂)``, ``ψ₃ = φ − ψ₁ − ψ₂``. Stretched or folded (|cos δ| ≥ 1 as computed) the two
  merge into one solution; folded onto axis 1 (w = 0, possible only when l₁ = l₂) joint 1 is free:
  it takes ``wrist_ref`` (default 0) and the solution is flagged degenerate;
* **one prismatic joint** (along z): q = p_z − h, if the orientation is R₀ and the position's
  x, y are those of q = 0.

The C of :mod:`robokit.codegen.ik_planar` computes the same numbers in the same order.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from robokit.ik.solution import Row
from robokit.ik.solver import PositionBranch

if TYPE_CHECKING:
    from robokit.ik._dh_chain import DHChain

__all__ = ["PlanarConstants", "PlanarSolver", "PLANAR_LABELS", "ANGLE_TOL", "LENGTH_TOL"]

#: rad: the largest tilt of the target's z axis (relative to the arm's) the arm is said to reach.
ANGLE_TOL = 1e-9
#: m (times the arm's size when above 1 m): the largest distance of the target from the arm's plane,
#: and of its position from the reachable one, the arm is said to reach.
LENGTH_TOL = 1e-9
#: The labels, in the order of the label codes the generated C reports.
PLANAR_LABELS = ("elbow down", "elbow up", "only solution")


@dataclass(frozen=True)
class PlanarConstants:
    r"""The numbers of the planar method for one canonical chain (see the module docstring).

    Lengths in m, angles in rad, all in frame {0′}.

    Attributes
    ----------
    n : int
        Joints (1–3).
    prismatic : bool
        One prismatic joint (n = 1) along z.
    signs : tuple of float
        sᵢ = ±1: axis i along +z or −z.
    r1 : tuple of float
        Where axis 1 meets the x–y plane (x, y).
    d : tuple of tuple of float
        The link vectors dᵢ (x, y), the last one to the frame after ``Z_n``.
    lengths, angles : tuple of float
        |dᵢ| and atan2(dᵢ).
    R0 : tuple of tuple of float
        The frame after ``Z_n`` at q = 0: its orientation (3 × 3).
    h : float
        ... and its height (z).
    tol_len : float
        The length tolerance (``LENGTH_TOL`` times the arm's size when above 1 m).

    Examples
    --------
    >>> import robokit
    >>> from robokit.ik.closed_form import AnalyticIK
    >>> c = AnalyticIK(robokit.load("rrr")).solver.constants()
    >>> c.n, c.lengths  # (the last link's 0.2 m is the DH row's X₃, in tool′: d₃ ends on axis 3)
    (3, (0.5, 0.4, 0.0))
    """

    n: int
    prismatic: bool
    signs: tuple[float, ...]
    r1: tuple[float, float]
    d: tuple[tuple[float, float], ...]
    lengths: tuple[float, ...]
    angles: tuple[float, ...]
    R0: tuple[tuple[float, float, float], ...]
    h: float
    tol_len: float


class PlanarSolver:
    """The planar method for one canonical chain of 1–3 joints (see the module docstring).

    Implements :class:`robokit.ik.solver.ClosedFormSolver`; it has no natural split, so
    ``position`` is the whole solve and ``wrist`` the identity.

    Parameters
    ----------
    chain : DHChain
        The canonical chain (any chain: :meth:`refusal` says whether the method applies).

    Examples
    --------
    >>> import numpy as np, robokit
    >>> from robokit.ik.closed_form import AnalyticIK
    >>> solver = AnalyticIK(robokit.load("rrr")).solver
    >>> rows = solver.joint_angles(solver.chain.fk6(np.array([0.3, 0.4, 0.5])), 0.0)
    >>> [(np.round(q, 4).tolist(), label) for q, label, _ in rows]
    [([0.3, 0.4, 0.5], 'elbow down'), ([0.655, -0.4, 0.945], 'elbow up')]
    """

    method = "planar"

    def __init__(self, chain: DHChain) -> None:
        self.chain = chain
        n = chain.n
        axes = chain.axes()
        self.n = n
        self.prismatic = n == 1 and chain.kinds[0] == "P"
        self._dirs = [a[1] for a in axes]
        M = chain.fk6(np.zeros(n))
        pts = [np.asarray(a[0][:2], dtype=float) for a in axes] + [M[:2, 3]]
        d = [pts[i + 1] - pts[i] for i in range(n)]
        self.signs = tuple(1.0 if float(a[1][2]) > 0 else -1.0 for a in axes)
        self.r1 = (float(pts[0][0]), float(pts[0][1]))
        self.d = tuple((float(v[0]), float(v[1])) for v in d)
        self.lengths = tuple(math.hypot(x, y) for x, y in self.d)
        self.angles = tuple(math.atan2(y, x) for x, y in self.d)
        self.R0 = tuple((float(r[0]), float(r[1]), float(r[2])) for r in M[:3, :3])
        self.h = float(M[2, 3])
        self.tol_len = LENGTH_TOL * max(1.0, float(chain.scale))

    def constants(self) -> PlanarConstants:
        """This solver's numbers (what the C emitter reads).

        Returns
        -------
        PlanarConstants
            Frozen; the same on every call.
        """
        return PlanarConstants(self.n, self.prismatic, self.signs, self.r1, self.d, self.lengths, self.angles,
                               self.R0, self.h, self.tol_len)

    def refusal(self) -> str | None:
        """None when the chain is a planar arm of 1–3 joints (see the module docstring), else why not.

        Returns
        -------
        str or None
            The first condition that fails, in the arm's terms.
        """
        n, kinds = self.n, self.chain.kinds
        if n < 1 or n > 3:
            return f"the arm has {n} joints; the planar closed form takes 1 to 3"
        if n > 1 and "P" in kinds:
            return f"joint {kinds.index('P') + 1} is prismatic (the planar closed form takes revolute joints)"
        for i in range(1, n):
            z = self._dirs[i]
            tilt = math.atan2(math.hypot(float(z[0]), float(z[1])), abs(float(z[2])))
            if tilt >= ANGLE_TOL:
                return f"axis {i + 1} is not parallel to axis 1 (they differ by {math.degrees(tilt):.3g}°)"
        for i in range(n - 1):
            if self.lengths[i] <= self.tol_len:
                return f"axes {i + 1} and {i + 2} coincide (a link of zero length)"
        return None

    def joint_angles(self, T06: np.ndarray, wrist_ref: float = 0.0) -> list[Row]:
        """Every solution for the pose T06 (the module docstring's steps).

        Parameters
        ----------
        T06 : numpy.ndarray, shape (4, 4)
            The pose to reach with ``Z₁X₁ ⋯ Z_n`` in frame {0′}, m.
        wrist_ref : float
            Three joints folded onto axis 1 (w = 0, l₁ = l₂): the value of the free joint 1 (rad);
            that solution is flagged degenerate.

        Returns
        -------
        list of (q (n,), label, degenerate)
            The chain's joint variables (rad, m); [] when T06 is out of reach.
        """
        R0, T = self.R0, T06
        # Rn = R R0ᵀ: its third column (tilt of the axes) and first column (φ)
        rn = [[T[i, 0] * R0[j][0] + T[i, 1] * R0[j][1] + T[i, 2] * R0[j][2] for j in range(3)] for i in range(3)]
        tilt = math.sqrt(rn[0][2] * rn[0][2] + rn[1][2] * rn[1][2] + (rn[2][2] - 1.0) * (rn[2][2] - 1.0))
        if not tilt <= ANGLE_TOL:
            return []
        phi = math.atan2(rn[1][0], rn[0][0])
        tol = self.tol_len
        px, py, pz = float(T[0, 3]), float(T[1, 3]), float(T[2, 3])
        if self.prismatic:
            d = self.d[0]
            if abs(phi) > ANGLE_TOL or math.hypot(px - self.r1[0] - d[0], py - self.r1[1] - d[1]) > tol:
                return []
            return [((pz - self.h,), PLANAR_LABELS[2], False)]
        if not abs(pz - self.h) <= tol:
            return []
        c, s = math.cos(phi), math.sin(phi)
        x, y = px - self.r1[0], py - self.r1[1]
        dx, dy = self.d[-1]
        wx, wy = x - (c * dx - s * dy), y - (s * dx + c * dy)  # p − r₁ − Rot(φ) d_n
        sg = self.signs
        if self.n == 1:
            if math.hypot(wx, wy) > tol:
                return []
            return [((sg[0] * phi,), PLANAR_LABELS[2], False)]
        l1, b1 = self.lengths[0], self.angles[0]
        if self.n == 2:
            if abs(math.hypot(wx, wy) - l1) > tol:
                return []
            psi1 = math.atan2(wy, wx) - b1
            psi2 = phi - psi1
            bend = math.sin(psi2 + self.angles[1] - b1)  # the second link's side of the first
            return [((sg[0] * psi1, sg[1] * psi2), PLANAR_LABELS[0 if bend >= 0.0 else 1], False)]
        l2, b2 = self.lengths[1], self.angles[1]
        rw = math.hypot(wx, wy)
        if rw > l1 + l2 + tol or rw < abs(l1 - l2) - tol:
            return []
        if rw <= tol:  # folded onto axis 1 (l₁ = l₂): joint 1 is free and takes wrist_ref
            psi1 = sg[0] * wrist_ref
            psi2 = math.pi + b1 - b2
            return [((wrist_ref, sg[1] * psi2, sg[2] * (phi - psi1 - psi2)), PLANAR_LABELS[0], True)]
        cd = (wx * wx + wy * wy - l1 * l1 - l2 * l2) / (2.0 * l1 * l2)
        merged = cd >= 1.0 or cd <= -1.0  # stretched or folded: one solution
        delta = math.acos(min(1.0, max(-1.0, cd)))
        aw = math.atan2(wy, wx)
        rows: list[Row] = []
        for k, sgn in enumerate((1.0, -1.0)):
            dl = sgn * delta
            psi1 = aw - math.atan2(l2 * math.sin(dl), l1 + l2 * math.cos(dl)) - b1
            psi2 = dl + b1 - b2
            psi3 = phi - psi1 - psi2
            rows.append(((sg[0] * psi1, sg[1] * psi2, sg[2] * psi3), PLANAR_LABELS[k], False))
            if merged:
                break
        return rows

    def position(self, T06: np.ndarray) -> list[PositionBranch]:
        """The whole solve (:meth:`joint_angles`), one branch per solution.

        Parameters
        ----------
        T06 : numpy.ndarray, shape (4, 4)
            The pose to reach with the canonical chain, m.

        Returns
        -------
        list of PositionBranch
            Complete solutions as branches.
        """
        return [PositionBranch(tuple(q), label, degen) for q, label, degen in self.joint_angles(T06)]

    def wrist(self, T06: np.ndarray, branch: PositionBranch, wrist_ref: float) -> list[Row]:
        """The identity on a complete branch.

        Parameters
        ----------
        T06 : numpy.ndarray, shape (4, 4)
            Unused.
        branch : PositionBranch
            A branch :meth:`position` returned.
        wrist_ref : float
            Unused.

        Returns
        -------
        list of (q, label, degenerate)
            The branch as the one row it is.
        """
        return [(tuple(branch.q), branch.label, branch.degenerate)]
