r"""A DH table in one canonical form, for the closed-form solvers (no public names).

Both DH conventions factor into the same alternating product of screw motions along the
joint axes and constant motions along the common normals between consecutive axes:

* standard: ``ⁱ⁻¹Tᵢ = Rz(θᵢ)Tz(dᵢ) · Tx(aᵢ)Rx(αᵢ)``, so
  ``T = base · Z₁X₁ Z₂X₂ ⋯ Z₆X₆ · tool``;
* modified (Craig): ``ⁱ⁻¹Tᵢ = Rx(α_{i−1})Tx(a_{i−1}) · Rz(θᵢ)Tz(dᵢ)``, so
  ``T = base · X₀ · Z₁X₁ ⋯ X₅Z₆ · tool``,

with ``Zᵢ = Rz(θᵢ)Tz(dᵢ)`` (joint i moves θᵢ or dᵢ) and ``Xᵢ = Rx(αᵢ)Tx(aᵢ)`` (αᵢ, aᵢ: the
angle and distance between axes i and i+1 — ``Tx`` and ``Rx`` commute). The canonical chain
is ``base′ · Z₁X₁Z₂X₂ ⋯ X₅Z₆ · tool′`` with ``base′ = base·X₀`` (modified) and
``tool′ = X₆·tool`` (standard). Frame {0′} = base′ has joint 1's axis as its z axis.
"""
from __future__ import annotations

import math

from typing import TYPE_CHECKING, Sequence

import numpy as np
from numpy.typing import ArrayLike
from robokit.spatial import lie
from robokit.errors import InputError

if TYPE_CHECKING:
    from robokit.description.dh import DHTable



def _rx4(alpha: float, a: float) -> np.ndarray:
    c, s = math.cos(alpha), math.sin(alpha)
    return np.array([[1.0, 0.0, 0.0, a], [0.0, c, -s, 0.0], [0.0, s, c, 0.0], [0.0, 0.0, 0.0, 1.0]])


def _rz4(theta: float, d: float) -> np.ndarray:
    c, s = math.cos(theta), math.sin(theta)
    return np.array([[c, -s, 0.0, 0.0], [s, c, 0.0, 0.0], [0.0, 0.0, 1.0, d], [0.0, 0.0, 0.0, 1.0]])


class DHChain:
    """Canonical form of a DH table (see the module docstring).

    kinds : (n,) "R"/"P"; th0, d0 : (n,) the rows' θ and d (offsets; rad, m);
    alpha, a : (n−1,) twist and length between axes i and i+1 (rad, m);
    base, tool : 4×4 (base′ and tool′); base_inv, tool_inv : their inverses or None when
    identity; qlim : (n, 2) or None; scale : a length of the arm (m) for tolerances (see
    :meth:`_arm_length`); dh_length : ``Σ|aᵢ| + Σ|dᵢ|`` (m), the size of the numbers the DH
    products round.
    """

    def __init__(self, table: DHTable, qlim: ArrayLike | None = None) -> None:
        links = list(table.links)
        n = len(links)
        conv = getattr(table, "convention", "standard")
        if conv not in ("standard", "modified"):
            raise InputError(f"robot: DH convention must be 'standard' or 'modified', got {conv!r}")
        self.n = n
        self.kinds = [str(l.joint) for l in links]
        for i, k in enumerate(self.kinds):
            if k not in ("R", "P"):
                raise InputError(f"robot: joint {i + 1} has type {k!r}; expected 'R' or 'P'")
        self.th0 = np.array([float(l.theta) for l in links])
        self.d0 = np.array([float(l.d) for l in links])
        base = np.asarray(getattr(table, "base", np.eye(4)), dtype=float)
        tool = np.asarray(getattr(table, "tool", np.eye(4)), dtype=float)
        if conv == "standard":
            self.alpha = np.array([float(l.alpha) for l in links[:-1]])
            self.a = np.array([float(l.a) for l in links[:-1]])
            last = links[-1]
            if last.alpha != 0.0 or last.a != 0.0:
                tool = _rx4(float(last.alpha), float(last.a)) @ tool
        else:
            self.alpha = np.array([float(l.alpha) for l in links[1:]])
            self.a = np.array([float(l.a) for l in links[1:]])
            first = links[0]
            if first.alpha != 0.0 or first.a != 0.0:
                base = base @ _rx4(float(first.alpha), float(first.a))
        self.base, self.tool = base, tool
        self.base_inv = None if np.array_equal(base, np.eye(4)) else lie.inv(base)
        self.tool_inv = None if np.array_equal(tool, np.eye(4)) else lie.inv(tool)
        if qlim is None and all(getattr(l, "qlim", None) is not None for l in links):
            qlim = np.array([l.qlim for l in links], dtype=float)
        self.qlim = None if qlim is None else np.asarray(qlim, dtype=float)
        self.dh_length = float(np.abs(self.a).sum() + np.abs(self.d0).sum())
        self.scale = max(1e-3, self._arm_length())

    def _arm_length(self) -> float:
        """The arm's size (m) at q = 0: the shorter of ``Σ|aᵢ| + Σ|dᵢ|`` and the path from frame
        {0′}'s origin through the nearest point of each joint axis in turn to the tool's origin.

        The DH sum alone is not a size when two consecutive axes are nearly parallel: their common
        normal is then far away, and the table's d offsets are huge with opposite signs (an
        xArm Lite 6 URDF, whose right angles are written 1.5708, gives d₂ = d₃ = 27 km). Tolerances
        scaled by it would take axes that miss by micrometres for axes that meet.
        """
        here, path = np.zeros(3), 0.0
        for point, u in self.axes():
            foot = point + float(np.dot(here - point, u)) * u
            path += float(np.linalg.norm(foot - here))
            here = foot
        path += float(np.linalg.norm((self.fk6(np.zeros(self.n)) @ self.tool)[:3, 3] - here))
        return min(self.dh_length, path)

    # ------------------------------------------------------------------ kinematics
    def z(self, i: int, q_i: float) -> np.ndarray:
        """4×4 ``Zᵢ`` of joint i (0-based) at joint value q_i."""
        if self.kinds[i] == "R":
            return _rz4(self.th0[i] + q_i, self.d0[i])
        return _rz4(self.th0[i], self.d0[i] + q_i)

    def x(self, i: int) -> np.ndarray:
        """4×4 ``Xᵢ`` between axes i and i+1 (0-based i)."""
        return _rx4(self.alpha[i], self.a[i])

    def fk6(self, q: Sequence[float] | np.ndarray) -> np.ndarray:
        """Pose of the frame after ``Z_n`` in frame {0′} (tool′ and base′ excluded)."""
        T = self.z(0, q[0])
        for i in range(1, self.n):
            T = T @ self.x(i - 1) @ self.z(i, q[i])
        return T

    def fk(self, q: Sequence[float] | np.ndarray) -> np.ndarray:
        """4×4 tool pose in base_link: ``base′ · fk6(q) · tool′`` (equals the table's FK)."""
        return self.base @ self.fk6(q) @ self.tool

    def target_06(self, T: np.ndarray) -> np.ndarray:
        """``base′⁻¹ · T · tool′⁻¹``: the pose to reach with ``Z₁X₁ ⋯ Z₆``."""
        if self.base_inv is not None:
            T = self.base_inv @ T
        if self.tool_inv is not None:
            T = T @ self.tool_inv
        return T

    def axes(self) -> list[tuple[np.ndarray, np.ndarray]]:
        """Joint axes at q = 0 in frame {0′}: list of (point (3,), unit direction (3,))."""
        out = []
        G = np.eye(4)
        for i in range(self.n):
            out.append((G[:3, 3].copy(), G[:3, 2].copy()))
            if i < self.n - 1:
                G = G @ self.z(i, 0.0) @ self.x(i)
        return out

    def reversed(self) -> "DHChain":
        """The chain read from the tool back to the base: its FK is the inverse pose.

        ``T⁻¹ = tool′⁻¹ · Z₆⁻¹X₅⁻¹ ⋯ X₁⁻¹Z₁⁻¹ · base′⁻¹`` with ``Zᵢ⁻¹ = Rz(−θᵢ)Tz(−dᵢ)`` and
        ``Xᵢ⁻¹ = Rx(−αᵢ)Tx(−aᵢ)``: again the canonical form, with joint k of the reversed
        chain = joint n+1−k of this one and q′ = −q.
        """
        rc = DHChain.__new__(DHChain)
        rc.n = self.n
        rc.kinds = self.kinds[::-1]
        rc.th0, rc.d0 = -self.th0[::-1], -self.d0[::-1]
        rc.alpha, rc.a = -self.alpha[::-1], -self.a[::-1]
        rc.base, rc.tool = lie.inv(self.tool), lie.inv(self.base)
        rc.base_inv = None if self.tool_inv is None else self.tool.copy()
        rc.tool_inv = None if self.base_inv is None else self.base.copy()
        rc.qlim = None if self.qlim is None else -self.qlim[::-1, ::-1]
        rc.scale, rc.dh_length = self.scale, self.dh_length
        return rc
