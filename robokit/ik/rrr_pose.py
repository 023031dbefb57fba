r"""The Lecture 5 homework arm (spatial RRR) with a full target pose.

The arm (Craig's convention, Lecture 4/5 homework): ``⁰T₁ = Rz(θ₁)``;
``¹T₂ = Rx(90°) Tx(L₁) Rz(θ₂)``; ``²T₃ = Tx(L₂) Rz(θ₃)``; the tool frame is frame {3} moved by
L₃ along x₃. Written out,

    ⁰T₃ = [[C₁C₂₃, −C₁S₂₃,  S₁, C₁(L₁ + L₂C₂)],
           [S₁C₂₃, −S₁S₂₃, −C₁, S₁(L₁ + L₂C₂)],
           [S₂₃,    C₂₃,    0,   L₂S₂        ]].

Given the whole pose (not only the position, for which see
:func:`robokit.ik.analytic.ik_rrr_position`) the lecture reads the angles off:
``θ₁ = atan2(R₁₃, −R₂₃)``; ``C₂ = (C₁P_x + S₁P_y − L₁)/L₂`` (the lecture's ``P_x/C₁ − L₁``
or ``P_y/S₁ − L₁``, without the division), ``S₂ = P_z/L₂``, ``θ₂ = atan2(S₂, C₂)``;
``θ₃ = atan2(R₃₁, R₃₂) − θ₂``. A pose this arm cannot take (z₃ not horizontal, or a
position off the circle of radius L₂) gives no solution.
"""
from __future__ import annotations

import math

from typing import cast

import numpy as np
from numpy.typing import ArrayLike

from robokit._arrays import as_scalar
from robokit.ik.solution import IKSolution, _qlim_or_none, _within
from robokit.spatial.se3 import check_transform
from robokit.spatial.basics import wrap_angle

__all__ = ["ik_rrr_pose"]


def _fk(q: np.ndarray, L1: float, L2: float, L3: float) -> np.ndarray:
    c1, s1 = math.cos(q[0]), math.sin(q[0])
    c2, s2 = math.cos(q[1]), math.sin(q[1])
    c23, s23 = math.cos(q[1] + q[2]), math.sin(q[1] + q[2])
    r = L1 + L2 * c2
    T = np.array([[c1 * c23, -c1 * s23, s1, c1 * r],
                  [s1 * c23, -s1 * s23, -c1, s1 * r],
                  [s23, c23, 0.0, L2 * s2],
                  [0.0, 0.0, 0.0, 1.0]])
    T[:3, 3] += L3 * T[:3, 0]
    return T


def ik_rrr_pose(T: ArrayLike, L1: float, L2: float, L3: float = 0.0, qlim: ArrayLike | None = None,
                tol: float = 1e-9) -> list[IKSolution]:
    r"""The joint angles (θ₁, θ₂, θ₃) of the Lecture 5 homework RRR arm for a full tool pose.

    Parameters
    ----------
    T : (4, 4) array
        Pose of the tool frame (frame {3} moved L₃ along x₃) in the base frame {0} (m).
    L1, L2, L3 : float
        Link lengths (m); L₂ > 0, L₁, L₃ ≥ 0.
    qlim : (3, 2) array, optional
        Joint limits (rad) for the ``within_limits`` flag.
    tol : float
        How closely the solution must reproduce T (entry-wise) to be returned.

    Returns
    -------
    list of :class:`IKSolution`
        One solution (the pose fixes every angle), angles wrapped to (−π, π]; ``[]`` when
        the arm cannot take the pose.

    Examples
    --------
    >>> T = _fk([0.3, -0.4, 0.9], 0.3, 0.5, 0.2)
    >>> [round(float(v), 9) for v in ik_rrr_pose(T, 0.3, 0.5, 0.2)[0].q]
    [0.3, -0.4, 0.9]
    """
    T = check_transform(T, "T")
    L1 = as_scalar(L1, "L1", nonnegative=True)
    L2 = as_scalar(L2, "L2", positive=True)
    L3 = as_scalar(L3, "L3", nonnegative=True)
    qlim = _qlim_or_none(qlim, 3)
    R = T[:3, :3]
    p = T[:3, 3] - L3 * R[:, 0]  # origin of frame {3}
    if math.hypot(R[0, 2], R[1, 2]) < 0.5:
        return []  # z₃ = (S₁, −C₁, 0) must be horizontal
    t1 = math.atan2(R[0, 2], -R[1, 2])
    c1, s1 = math.cos(t1), math.sin(t1)
    c2 = (c1 * p[0] + s1 * p[1] - L1) / L2
    s2 = p[2] / L2
    t2 = math.atan2(s2, c2)
    t3 = math.atan2(R[2, 0], R[2, 1]) - t2
    q = cast(np.ndarray, wrap_angle(np.array([t1, t2, t3])))
    if np.abs(_fk(q, L1, L2, L3) - T).max() > tol * max(1.0, L1 + L2 + L3):
        return []
    return [IKSolution(q, _within(q, qlim), "unique")]
