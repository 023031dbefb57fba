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
from typing import TYPE_CHECKING

import numpy as np

from robokit.ik.pieper import ChainNumbers, ELBOW_LABELS, SHOULDER_LABELS, WRIST_LABELS, pack_offsets_and_twists
from robokit.ik.solution import Row
from robokit.ik.solver import PositionBranch

if TYPE_CHECKING:
    from robokit.ik._dh_chain import DHChain


@dataclass(frozen=True)
class ParallelAxesConstants(ChainNumbers):
    r"""The numbers of the three-parallel-axes method for one canonical chain (module docstring).

    What :class:`ParallelAxesSolver` exports (:meth:`ParallelAxesSolver.constants`) for the
    compiled kernel (:mod:`robokit.kernels.closed_form`) and the C emitter
    (:mod:`robokit.codegen.ik`). Lengths in m, angles in rad.

    Attributes
    ----------
    th0, d0, ca, sa : tuple of float
        Joint offsets and twists (:class:`robokit.ik.pieper.ChainNumbers`).
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

    Notes
    -----
    This class builds the constants (:class:`ParallelAxesConstants`); the algorithm — the one
    implementation — is :mod:`robokit.kernels.closed_form` (``parallel_axes_position``,
    ``parallel_axes_wrist``, ``parallel_axes_rows``; plain Python under ``NUMBA_DISABLE_JIT=1``).
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
        self._cf: np.ndarray | None = None

    def constants(self) -> ParallelAxesConstants:
        """This solver's :class:`ParallelAxesConstants` (what the kernel and the C emitter read)."""
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
        cf = pack_offsets_and_twists(k.th0, k.d0, k.ca, k.sa)
        cf[22:31] = k.a1, k.a2, k.a3, k.a4, k.a5, k.d1, k.d5, k.d6, k.KW
        cf[31:34] = k.w6
        cf[34], cf[35] = k.s2, k.sig
        return ci, cf, np.zeros((5, 5))

    def _packed(self) -> np.ndarray:
        """The kernel's float constants (:meth:`kernel_constants`), computed on first use."""
        if self._cf is None:
            self._cf = self.kernel_constants()[1]
        return self._cf

    def position(self, T06: np.ndarray) -> list[PositionBranch]:
        """θ₁ from W's coordinate along the parallel axes (step 1): the shoulder branches.

        Runs :func:`robokit.kernels.closed_form.parallel_axes_position`.

        Parameters
        ----------
        T06 : (4, 4) ndarray
            Target of the canonical chain (m, frame 0′).

        Returns
        -------
        list of PositionBranch
            ``q`` (1,) joint variable 1, ``label`` ``"right, "`` or ``"left, "``,
            ``data`` (θ₁ (rad, the DH offset included), shoulder code).
        """
        from robokit.kernels.closed_form import parallel_axes_position

        t1s, shoulders = parallel_axes_position(self._packed(), np.ascontiguousarray(T06, dtype=float))
        th0 = self.th0_list[0]
        return [PositionBranch((t1 - th0,), SHOULDER_LABELS[s], False, (t1, s))
                for t1, s in zip(t1s.tolist(), shoulders.tolist())]

    def wrist(self, T06: np.ndarray, branch: PositionBranch, wrist_ref: float) -> list[Row]:
        """θ₅, θ₆ and the planar θ₂–θ₄ (steps 2–4) for one θ₁: rows ``(q (6,), label, degenerate)``.

        At the singularity (axis 6 parallel to the parallel axes) ``q₆ = wrist_ref``. Runs
        :func:`robokit.kernels.closed_form.parallel_axes_wrist`. Parameters
        and result as :meth:`robokit.ik.solver.ClosedFormSolver.wrist`.
        """
        from robokit.kernels.closed_form import parallel_axes_wrist

        t1, shoulder = branch.data
        Q, codes, degen = parallel_axes_wrist(self._packed(), np.ascontiguousarray(T06, dtype=float), float(t1),
                                              int(shoulder), float(wrist_ref))
        return _rows(Q, codes, degen)

    def joint_angles(self, T06: np.ndarray, wrist_ref: float) -> list[Row]:
        """Every row ``(q (6,), label, degenerate)`` reaching ``T06`` (2 × 2 × 2 in general).

        Runs :func:`robokit.kernels.closed_form.parallel_axes_rows` (the one implementation).

        Parameters
        ----------
        T06 : (4, 4) ndarray
            Target of ``Z₁X₁ ⋯ Z₆`` in frame 0′ (m).
        wrist_ref : float
            q₆ at the singularity (rad).

        Returns
        -------
        list of Row
        """
        from robokit.kernels.closed_form import parallel_axes_rows

        Q, codes, degen = parallel_axes_rows(self._packed(), np.ascontiguousarray(T06, dtype=float), float(wrist_ref))
        return _rows(Q, codes, degen)

    #: The same as :meth:`joint_angles`.
    solve = joint_angles

    def refusal(self) -> str | None:
        """None: the detection of three parallel axes is all this method needs.

        Returns
        -------
        None
        """
        return None


def _rows(Q: np.ndarray, codes: np.ndarray, degen: np.ndarray) -> list[Row]:
    """Rows ``(q, label, degenerate)`` from a kernel's raw rows and branch codes."""
    return [(tuple(q), SHOULDER_LABELS[s] + ELBOW_LABELS[e] + WRIST_LABELS[w], bool(d))
            for q, (s, e, w), d in zip(Q.tolist(), codes.tolist(), degen.tolist())]
