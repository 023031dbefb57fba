r"""Craig's recursive Newton–Euler on a DH table (Lecture 7; Craig, *Introduction to Robotics*, §6.5).

Outward iterations (i = 0 … N−1), in each link's own frame, with ``ⁱ⁺¹R_i`` the rotation from
frame {i} to {i+1}, ``ⁱp_{i+1}`` the origin of {i+1} in {i}, ``p_C`` the centre of mass of link i+1
in its frame, ẑ = (0, 0, 1):

modified (Craig) convention — joint i+1 moves about ẑ of frame {i+1}:
    ω_{i+1} = R ω_i + θ̇ ẑ
    ω̇_{i+1} = R ω̇_i + R ω_i × θ̇ ẑ + θ̈ ẑ
    v̇_{i+1} = R (ω̇_i × p + ω_i × (ω_i × p) + v̇_i)   [+ 2 ω_{i+1} × ḋ ẑ + d̈ ẑ for a prismatic joint]
standard convention — joint i+1 moves about ẑ of frame {i}: the same equations written in frame {i}
with ω' = ω_i + θ̇ ẑ, ω̇' = ω̇_i + ω_i × θ̇ ẑ + θ̈ ẑ, then rotated into {i+1}.

Then ``v̇_C = ω̇ × p_C + ω × (ω × p_C) + v̇``, ``F = m v̇_C``, ``N = I_C ω̇ + ω × I_C ω``.
Inward iterations (i = N … 1): ``f_i = R f_{i+1} + F_i``, ``n_i = N_i + R n_{i+1} + p_C × F_i + p × R f_{i+1}``,
and the joint torque is the component along the joint axis of the moment about a point on it:
``τ_i = n_iᵀ ẑ`` (modified; ``f_iᵀ ẑ`` for a prismatic joint), or, in the standard convention,
``τ_i = ẑᵀ (R n_i + p × R f_i)`` in frame {i−1} (``ẑᵀ R f_i`` prismatic).

Gravity enters as an upward acceleration of the base, ``v̇₀ = −g`` (Lecture 7). The tip wrench
``F_tip = (n, f)`` is what the tool exerts on the environment, in the tool frame (as in the seed
library), and starts the inward iteration.
"""
from __future__ import annotations

import numpy as np

from robokit._arrays import as_vector

__all__ = ["dh_inverse_dynamics"]

_Z = np.array([0.0, 0.0, 1.0])


def dh_inverse_dynamics(table, q, dq, ddq, gravity=None, F_tip=None) -> np.ndarray:
    """Joint torques/forces (n,) by Craig's recursive Newton–Euler on a :class:`DHTable`.

    q, dq, ddq : (n,) joint positions, rates, accelerations (rad or m); gravity : (3,) in base_link
    (default the table's); F_tip : (6,) wrench (n, f) the tool exerts on the environment, tool frame.
    Uses the table's link masses, centres of mass and inertias (frame-{i} axes, about the COM).
    """
    n = table.n
    q = as_vector(q, "q", n)
    dq = as_vector(dq, "dq", n)
    ddq = as_vector(ddq, "ddq", n)
    g = as_vector(table.gravity if gravity is None else gravity, "gravity", 3)
    F = np.zeros(6) if F_tip is None else as_vector(F_tip, "F_tip", 6)
    standard = table.convention == "standard"
    base = np.asarray(table.base, dtype=float)
    Ts = [table.link_transform(i, q[i]) for i in range(n)]
    w = np.zeros(3)
    wd = np.zeros(3)
    vd = base[:3, :3].T @ (-g)  # the base accelerates upward: v̇₀ = −g, in frame {0}
    Fs, Ns = [], []
    for i in range(n):
        R = Ts[i][:3, :3].T  # ⁱ⁺¹R_i
        p = Ts[i][:3, 3]  # ⁱp_{i+1}
        link = table.links[i]
        rev = link.joint == "R"
        if standard:
            w1 = w + (dq[i] * _Z if rev else 0.0)
            wd1 = wd + (np.cross(w, dq[i] * _Z) + ddq[i] * _Z if rev else 0.0)
            a = vd + np.cross(wd1, p) + np.cross(w1, np.cross(w1, p))
            if not rev:
                a = a + 2.0 * np.cross(w1, dq[i] * _Z) + ddq[i] * _Z
            w, wd, vd = R @ w1, R @ wd1, R @ a
        else:
            a = R @ (np.cross(wd, p) + np.cross(w, np.cross(w, p)) + vd)
            w_new = R @ w + (dq[i] * _Z if rev else 0.0)
            wd_new = R @ wd + (np.cross(R @ w, dq[i] * _Z) + ddq[i] * _Z if rev else 0.0)
            if not rev:
                a = a + 2.0 * np.cross(w_new, dq[i] * _Z) + ddq[i] * _Z
            w, wd, vd = w_new, wd_new, a
        pc = np.asarray(link.com, dtype=float)
        Ic = link.inertia_matrix
        vdc = np.cross(wd, pc) + np.cross(w, np.cross(w, pc)) + vd
        Fs.append(link.mass * vdc)
        Ns.append(Ic @ wd + np.cross(w, Ic @ w))
    # inward: start from the tool's wrench on the environment, carried to frame {N}
    tool = np.asarray(table.tool, dtype=float)
    f = tool[:3, :3] @ F[3:]
    nm = tool[:3, :3] @ F[:3] + np.cross(tool[:3, 3], f)
    R_next = np.eye(3)
    p_next = np.zeros(3)
    tau = np.empty(n)
    for i in range(n - 1, -1, -1):
        link = table.links[i]
        pc = np.asarray(link.com, dtype=float)
        f_out = R_next @ f  # force of link i+1 (or the environment) on … expressed in frame {i+1}
        n_out = R_next @ nm
        f_i = f_out + Fs[i]
        n_i = Ns[i] + n_out + np.cross(pc, Fs[i]) + np.cross(p_next, f_out)
        R_i = Ts[i][:3, :3]  # ⁱ⁻¹R_i
        if standard:
            f_prev = R_i @ f_i
            if link.joint == "R":
                tau[i] = _Z @ (R_i @ n_i + np.cross(Ts[i][:3, 3], f_prev))
            else:
                tau[i] = _Z @ f_prev
        else:
            tau[i] = _Z @ n_i if link.joint == "R" else _Z @ f_i
        f, nm = f_i, n_i
        R_next, p_next = R_i, Ts[i][:3, 3]
    return tau
