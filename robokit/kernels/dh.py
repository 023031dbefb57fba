r"""Denavit–Hartenberg kinematics and dynamics as compiled loops (Lectures 4 and 7; Craig,
*Introduction to Robotics*, ch. 3, 5 and 6).

A DH table is packed into plain arrays by :func:`pack_dh` (done once per table and remembered):
``P`` (n, 5) rows ``(a, α, d, θ, prismatic)`` (prismatic = 1.0 for a P joint, else 0.0),
``modified`` (1 for Craig's modified convention, 0 for the standard one), ``base`` and ``tool``
(4, 4), and the inertial parameters ``mass`` (n,), ``com`` (n, 3) in frame {i}, ``inertia``
(n, 3, 3) about the centre of mass in frame-{i} axes.

Link transforms ``ⁱ⁻¹Tᵢ`` (a revolute qᵢ adds to θᵢ, a prismatic one to dᵢ):
    standard ``Rz(θ) Tz(d) Tx(a) Rx(α)`` — joint i moves about z_{i−1};
    modified ``Rx(α_{i−1}) Tx(a_{i−1}) Rz(θ) Tz(d)`` — joint i moves about z_i.

* FK: ``T_base_tool = base · ⁰T₁ ⋯ ᴺ⁻¹T_N · tool``.
* Jacobian, one outward O(n) pass: velocity propagation is linear in q̇, so the tool twist is
  the sum of each joint's own contribution; walking outward once, joint j's axis (unit ẑ_j
  through the origin o_j, both in base_link) gives the column's angular part ``ẑ_j`` (revolute)
  and the velocity of the base origin ``o_j × ẑ_j`` (revolute) or ``ẑ_j`` (prismatic). At the end
  the reference point moves to the tool origin p, ``v ← v + ω × p`` (the rigid-body velocity
  transfer of the propagation formula ``v_{i+1} = v_i + ω_i × p``), giving
  ``J_j = (ẑ_j, ẑ_j × (p − o_j))``; optionally rotated into the tool frame by ``R_toolᵀ``.
* Static forces, inward (Craig §5.9): ``f_i = f_{i+1}``, ``n_i = n_{i+1} + (o_{i+1} − o_i) × f``,
  ``τ_i = ẑ_iᵀ n_i`` (revolute) or ``ẑ_iᵀ f_i`` (prismatic), all in base_link axes.
* Craig's recursive Newton–Euler (§6.5), outward then inward, each link in its own frame (see
  :func:`dh_inverse_dynamics` below and :mod:`robokit.dynamics.dh_newton_euler`).

Example::

    >>> import robokit
    >>> from robokit.kernels.dh import dh_jacobian, pack_dh
    >>> P, modified, base, tool, mass, com, inertia = pack_dh(robokit.load("puma560").dh)
    >>> J = dh_jacobian(P, modified, base, tool, np.zeros(6), 0)   # (6, 6), base_link axes
"""
from __future__ import annotations

import math
from typing import Any

import numpy as np

from robokit.kernels._jit import FK_BATCH, njit, prange
from robokit.kernels.lie import all_finite, check_joint_values, copy44, mul_tt, mul_tt_inplace
from robokit.kernels.poe import SERIAL_BELOW, block_range, n_blocks

__all__ = [
    "pack_dh", "dh_fk", "dh_frames", "dh_jacobian", "dh_static_torques", "dh_inverse_dynamics",
    "dh_fk_batch", "dh_jacobian_batch", "dh_static_torques_batch", "dh_inverse_dynamics_batch",
]

_A1 = "float64[::1]"
_A2 = "float64[:, ::1]"
_A3 = "float64[:, :, ::1]"
_TABLE = f"{_A2}, int64, {_A2}, {_A2}"  # P, modified, base, tool
_INERTIA = f"{_A1}, {_A2}, {_A3}"  # mass, com, inertia

# ``table`` is typed Any: kernels sit below robokit.description (tests/test_layers.py).
def _kernel_matrix(a: Any) -> np.ndarray:
    a = np.ascontiguousarray(a, dtype=float)
    return a if a.flags.writeable else np.array(a)


def pack_dh(table: Any) -> tuple[np.ndarray, int, np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """The arrays of a :class:`robokit.DHTable` in the kernels' layout (see the module docstring):
    ``(P, modified, base, tool, mass, com, inertia)``. Packed once per table and kept on it (a
    DHTable is frozen: no module-level cache keyed by its identity)."""
    hit = table.__dict__.get("_packed")
    if hit is not None:
        return hit
    n = table.n
    P = np.empty((n, 5))
    mass = np.empty(n)
    com = np.empty((n, 3))
    inertia = np.empty((n, 3, 3))
    for i, link in enumerate(table.links):
        P[i] = (link.a, link.alpha, link.d, link.theta, 1.0 if link.joint == "P" else 0.0)
        mass[i] = link.mass
        com[i] = np.asarray(link.com, dtype=float)
        inertia[i] = link.inertia_matrix
    # the table's own arrays when the kernels' signatures take them (writeable C-contiguous float64:
    # an in-place edit of a table of one's own is then seen, and followed by the closed-form IK),
    # else a private copy (a robot's table holds read-only base and tool: they cannot change)
    packed = (P, 1 if table.convention == "modified" else 0, _kernel_matrix(table.base),
              _kernel_matrix(table.tool), mass, com, inertia)
    table.__dict__["_packed"] = packed  # beside the frozen dataclass's fields, as kinematics/dh.py's flip signs
    return packed


# ------------------------------------------------------------------ small 3-vector helpers
@njit
def cross3(a: np.ndarray, b: np.ndarray, out: np.ndarray) -> None:
    """out ← a × b."""
    x = a[1] * b[2] - a[2] * b[1]
    y = a[2] * b[0] - a[0] * b[2]
    z = a[0] * b[1] - a[1] * b[0]
    out[0], out[1], out[2] = x, y, z


@njit
def rot(T: np.ndarray, x: np.ndarray, out: np.ndarray) -> None:
    """out ← R x with R the rotation block of T (out may alias x). For Rᵀ x pass ``T.T``: a view
    with swapped strides (no copy), the same products summed in the same order."""
    a = T[0, 0] * x[0] + T[0, 1] * x[1] + T[0, 2] * x[2]
    b = T[1, 0] * x[0] + T[1, 1] * x[1] + T[1, 2] * x[2]
    c = T[2, 0] * x[0] + T[2, 1] * x[1] + T[2, 2] * x[2]
    out[0], out[1], out[2] = a, b, c


# ------------------------------------------------------------------ link transforms and frames
@njit
def link_transform(P: np.ndarray, i: int, modified: int, q_i: float, T: np.ndarray) -> None:
    """T ← ⁱ⁻¹Tᵢ of row i at joint value q_i (0-based i)."""
    a, alpha, d, theta = P[i, 0], P[i, 1], P[i, 2], P[i, 3]
    if P[i, 4] > 0.5:
        d += q_i  # prismatic: the variable adds to d
    else:
        theta += q_i  # revolute: the variable adds to θ
    ct, st = math.cos(theta), math.sin(theta)
    ca, sa = math.cos(alpha), math.sin(alpha)
    if modified == 0:  # Rz(θ) Tz(d) Tx(a) Rx(α)
        T[0, 0], T[0, 1], T[0, 2], T[0, 3] = ct, -st * ca, st * sa, a * ct
        T[1, 0], T[1, 1], T[1, 2], T[1, 3] = st, ct * ca, -ct * sa, a * st
        T[2, 0], T[2, 1], T[2, 2], T[2, 3] = 0.0, sa, ca, d
    else:  # Rx(α) Tx(a) Rz(θ) Tz(d)
        T[0, 0], T[0, 1], T[0, 2], T[0, 3] = ct, -st, 0.0, a
        T[1, 0], T[1, 1], T[1, 2], T[1, 3] = st * ca, ct * ca, -sa, -sa * d
        T[2, 0], T[2, 1], T[2, 2], T[2, 3] = st * sa, ct * sa, ca, ca * d
    T[3, 0], T[3, 1], T[3, 2], T[3, 3] = 0.0, 0.0, 0.0, 1.0


@njit
def check_q(P: np.ndarray, q: np.ndarray) -> None:
    """Raise ``ValueError`` unless q has one finite value per row of the DH table."""
    check_joint_values(q, P.shape[0], "q", "row of the DH table")


@njit
def fk_into(P: np.ndarray, modified: int, base: np.ndarray, tool: np.ndarray, q: np.ndarray, T: np.ndarray, L: np.ndarray, tmp: np.ndarray) -> None:
    """T ← base · ⁰T₁ ⋯ ᴺ⁻¹T_N · tool (L, tmp: 4×4 scratch)."""
    copy44(base, T)
    for i in range(P.shape[0]):
        link_transform(P, i, modified, q[i], L)
        mul_tt_inplace(T, L, tmp)
    mul_tt_inplace(T, tool, tmp)


@njit
def jacobian_into(P: np.ndarray, modified: int, base: np.ndarray, tool: np.ndarray, q: np.ndarray, in_tool: int, J: np.ndarray, T: np.ndarray, L: np.ndarray, tmp: np.ndarray) -> None:
    """J (6, n) ← the geometric Jacobian of the tool origin (one outward pass, module docstring);
    base_link axes, or the tool frame's axes when ``in_tool`` is 1."""
    n = P.shape[0]
    copy44(base, T)
    for i in range(n):
        link_transform(P, i, modified, q[i], L)
        if modified == 1:  # joint i moves about z of frame {i}: step to frame {i} first
            mul_tt_inplace(T, L, tmp)
        zx, zy, zz = T[0, 2], T[1, 2], T[2, 2]  # the joint axis ẑ and a point o on it, base_link
        ox, oy, oz = T[0, 3], T[1, 3], T[2, 3]
        if P[i, 4] > 0.5:  # prismatic: no rotation, the base origin moves along ẑ
            J[0, i], J[1, i], J[2, i] = 0.0, 0.0, 0.0
            J[3, i], J[4, i], J[5, i] = zx, zy, zz
        else:  # revolute: ω = ẑ, the base origin moves with o × ẑ
            J[0, i], J[1, i], J[2, i] = zx, zy, zz
            J[3, i] = oy * zz - oz * zy
            J[4, i] = oz * zx - ox * zz
            J[5, i] = ox * zy - oy * zx
        if modified == 0:  # joint i moved about z of frame {i−1}: now step to frame {i}
            mul_tt_inplace(T, L, tmp)
    mul_tt_inplace(T, tool, tmp)  # the tool pose
    px, py, pz = T[0, 3], T[1, 3], T[2, 3]
    for j in range(n):  # move the reference point to the tool origin: v ← v + ω × p
        wx, wy, wz = J[0, j], J[1, j], J[2, j]
        J[3, j] += wy * pz - wz * py
        J[4, j] += wz * px - wx * pz
        J[5, j] += wx * py - wy * px
        if in_tool == 1:  # express in the tool frame's axes: Rᵀ ω, Rᵀ v
            for r in (0, 3):
                a = T[0, 0] * J[r, j] + T[1, 0] * J[r + 1, j] + T[2, 0] * J[r + 2, j]
                b = T[0, 1] * J[r, j] + T[1, 1] * J[r + 1, j] + T[2, 1] * J[r + 2, j]
                c = T[0, 2] * J[r, j] + T[1, 2] * J[r + 1, j] + T[2, 2] * J[r + 2, j]
                J[r, j], J[r + 1, j], J[r + 2, j] = a, b, c


@njit
def static_torques_into(P: np.ndarray, modified: int, base: np.ndarray, tool: np.ndarray, q: np.ndarray, F: np.ndarray, frames: np.ndarray, T: np.ndarray, L: np.ndarray, tmp: np.ndarray, tau: np.ndarray) -> None:
    """τ (n,) ← the joint torques that balance the tool wrench F = (n, f) (tool frame), by inward
    force propagation in base_link axes; ``frames`` (n+1, 4, 4) scratch for the DH frames."""
    n = P.shape[0]
    copy44(base, frames[0])
    for i in range(n):
        link_transform(P, i, modified, q[i], L)
        mul_tt(frames[i], L, frames[i + 1])
    mul_tt(frames[n], tool, T)
    # the wrench in base_link axes, moment about the tool origin
    fx = T[0, 0] * F[3] + T[0, 1] * F[4] + T[0, 2] * F[5]
    fy = T[1, 0] * F[3] + T[1, 1] * F[4] + T[1, 2] * F[5]
    fz = T[2, 0] * F[3] + T[2, 1] * F[4] + T[2, 2] * F[5]
    mx = T[0, 0] * F[0] + T[0, 1] * F[1] + T[0, 2] * F[2]
    my = T[1, 0] * F[0] + T[1, 1] * F[1] + T[1, 2] * F[2]
    mz = T[2, 0] * F[0] + T[2, 1] * F[1] + T[2, 2] * F[2]
    px, py, pz = T[0, 3], T[1, 3], T[2, 3]
    for i in range(n - 1, -1, -1):
        A = frames[i] if modified == 0 else frames[i + 1]  # the frame whose z is joint i's axis
        ox, oy, oz = A[0, 3], A[1, 3], A[2, 3]
        dx, dy, dz = px - ox, py - oy, pz - oz  # carry the moment to this joint's origin
        mx += dy * fz - dz * fy
        my += dz * fx - dx * fz
        mz += dx * fy - dy * fx
        px, py, pz = ox, oy, oz
        if P[i, 4] > 0.5:
            tau[i] = A[0, 2] * fx + A[1, 2] * fy + A[2, 2] * fz
        else:
            tau[i] = A[0, 2] * mx + A[1, 2] * my + A[2, 2] * mz


@njit
def rnea_into(P: np.ndarray, modified: int, base: np.ndarray, tool: np.ndarray, mass: np.ndarray, com: np.ndarray, inertia: np.ndarray, q: np.ndarray, dq: np.ndarray, ddq: np.ndarray, g: np.ndarray, F: np.ndarray, Ts: np.ndarray, w3: np.ndarray, Fs: np.ndarray, Ns: np.ndarray, tau: np.ndarray) -> None:
    """τ ← Craig's recursive Newton–Euler (both conventions). Scratch: Ts (n, 4, 4) link
    transforms, w3 (12, 3) 3-vectors, Fs and Ns (n, 3) link forces and moments."""
    n = P.shape[0]
    w, wd, vd, w1, wd1, a, t, u, pc, f, nm, fo = (w3[0], w3[1], w3[2], w3[3], w3[4], w3[5], w3[6], w3[7],
                                                  w3[8], w3[9], w3[10], w3[11])
    for r in range(3):
        w[r] = 0.0
        wd[r] = 0.0
        vd[r] = -g[r]
    rot(base.T, vd, vd)  # v̇₀ = −g (the base accelerates upward), in frame {0}
    for i in range(n):
        link_transform(P, i, modified, q[i], Ts[i])
        T = Ts[i]  # ⁱT_{i+1} (0-based): R = its rotation, p = its translation; ⁱ⁺¹R_i = Rᵀ
        p = T[:3, 3]
        rev = P[i, 4] < 0.5
        qd, qdd = dq[i], ddq[i]
        if modified == 0:  # the joint acts about z of frame {i}: add it there, then rotate into {i+1}
            for r in range(3):
                w1[r] = w[r]
                wd1[r] = wd[r]
            if rev:
                w1[2] += qd
                wd1[0] += w[1] * qd  # ω × θ̇ ẑ
                wd1[1] -= w[0] * qd
                wd1[2] += qdd
            cross3(wd1, p, a)  # a = v̇ + ω̇' × p + ω' × (ω' × p)
            cross3(w1, p, t)
            cross3(w1, t, u)
            for r in range(3):
                a[r] += vd[r] + u[r]
            if not rev:  # + 2 ω' × ḋ ẑ + d̈ ẑ
                a[0] += 2.0 * w1[1] * qd
                a[1] -= 2.0 * w1[0] * qd
                a[2] += qdd
            rot(T.T, w1, w)
            rot(T.T, wd1, wd)
            rot(T.T, a, vd)
        else:  # the joint acts about z of frame {i+1}
            cross3(wd, p, a)  # a = Rᵀ(ω̇ × p + ω × (ω × p) + v̇)
            cross3(w, p, t)
            cross3(w, t, u)
            for r in range(3):
                a[r] += u[r] + vd[r]
            rot(T.T, a, a)
            rot(T.T, w, t)  # t = Rᵀ ω
            rot(T.T, wd, wd)
            for r in range(3):
                w[r] = t[r]
            if rev:
                w[2] += qd
                wd[0] += t[1] * qd  # (Rᵀω) × θ̇ ẑ
                wd[1] -= t[0] * qd
                wd[2] += qdd
            else:
                a[0] += 2.0 * w[1] * qd
                a[1] -= 2.0 * w[0] * qd
                a[2] += qdd
            for r in range(3):
                vd[r] = a[r]
        # the link's centre of mass: v̇_C = ω̇ × p_C + ω × (ω × p_C) + v̇;  F = m v̇_C,  N = I ω̇ + ω × I ω
        for r in range(3):
            pc[r] = com[i, r]
        cross3(wd, pc, a)
        cross3(w, pc, t)
        cross3(w, t, u)
        for r in range(3):
            Fs[i, r] = mass[i] * (a[r] + u[r] + vd[r])
        I = inertia[i]
        for r in range(3):
            t[r] = I[r, 0] * w[0] + I[r, 1] * w[1] + I[r, 2] * w[2]
        cross3(w, t, u)
        for r in range(3):
            Ns[i, r] = I[r, 0] * wd[0] + I[r, 1] * wd[1] + I[r, 2] * wd[2] + u[r]
    # inward: start from the tool's wrench on the environment, carried into frame {N}
    rot(tool, F[3:], f)
    rot(tool, F[:3], nm)
    cross3(tool[:3, 3], f, t)
    for r in range(3):
        nm[r] += t[r]
    for i in range(n - 1, -1, -1):
        # f, nm: the force/moment link i exerts on link i+1 (or the tool on the environment),
        # already in frame {i+1} (0-based: link i's own frame)
        for r in range(3):
            pc[r] = com[i, r]
        cross3(pc, Fs[i], t)
        for r in range(3):
            fo[r] = f[r]  # force on the next link, in frame {i+1}
            f[r] = fo[r] + Fs[i, r]  # f_i = f_out + F_i
            nm[r] = Ns[i, r] + nm[r] + t[r]  # n_i = N_i + n_out + p_C × F_i (+ p_next × f_out below)
        if i < n - 1:
            cross3(Ts[i + 1][:3, 3], fo, t)
            for r in range(3):
                nm[r] += t[r]
        T = Ts[i]
        rev = P[i, 4] < 0.5
        if modified == 0:  # the axis is z of frame {i}: τ = ẑᵀ(R n + p × R f) or ẑᵀ R f
            rot(T, f, a)
            if rev:
                rot(T, nm, u)
                cross3(T[:3, 3], a, t)
                tau[i] = u[2] + t[2]
            else:
                tau[i] = a[2]
        else:
            tau[i] = nm[2] if rev else f[2]
        rot(T, f, f)  # into frame {i}: what the inner link i−1 transmits to link i
        rot(T, nm, nm)


# ------------------------------------------------------------------ one configuration
@njit(f"{_A2}({_TABLE}, {_A1})")
def dh_fk(P: np.ndarray, modified: int, base: np.ndarray, tool: np.ndarray, q: np.ndarray) -> np.ndarray:
    """Tool pose (4, 4) in base_link."""
    check_q(P, q)
    W = np.empty((3, 4, 4))
    fk_into(P, modified, base, tool, q, W[0], W[1], W[2])
    return W[0].copy()


@njit(f"{_A3}({_A2}, int64, {_A2}, {_A1})")
def dh_frames(P: np.ndarray, modified: int, base: np.ndarray, q: np.ndarray) -> np.ndarray:
    """Poses (n + 1, 4, 4) of DH frames {0..n} in base_link: ``base · ⁰T₁ ⋯ ⁱ⁻¹Tᵢ`` (row 0 is base)."""
    check_q(P, q)
    n = P.shape[0]
    out = np.empty((n + 1, 4, 4))
    L = np.empty((4, 4))
    copy44(base, out[0])
    for i in range(n):
        link_transform(P, i, modified, q[i], L)
        mul_tt(out[i], L, out[i + 1])
    return out


@njit(f"{_A2}({_TABLE}, {_A1}, int64)")
def dh_jacobian(P: np.ndarray, modified: int, base: np.ndarray, tool: np.ndarray, q: np.ndarray, in_tool: int) -> np.ndarray:
    """Geometric Jacobian (6, n) of the tool origin, rows (ω; v): base_link axes (in_tool = 0,
    Pinocchio's LOCAL_WORLD_ALIGNED) or tool axes (in_tool = 1, LOCAL)."""
    check_q(P, q)
    J = np.empty((6, P.shape[0]))
    W = np.empty((3, 4, 4))
    jacobian_into(P, modified, base, tool, q, in_tool, J, W[0], W[1], W[2])
    return J


@njit(f"{_A1}({_TABLE}, {_A1}, {_A1})")
def dh_static_torques(P: np.ndarray, modified: int, base: np.ndarray, tool: np.ndarray, q: np.ndarray, F: np.ndarray) -> np.ndarray:
    """Joint torques (n,) balancing the tool wrench F = (n, f) (what the tool exerts, tool frame): τ = Jᵀ F."""
    check_q(P, q)
    if F.shape[0] != 6 or not all_finite(F):
        raise ValueError("F_tip: expected 6 finite values")
    n = P.shape[0]
    frames = np.empty((n + 1, 4, 4))
    W = np.empty((3, 4, 4))
    tau = np.empty(n)
    static_torques_into(P, modified, base, tool, q, F, frames, W[0], W[1], W[2], tau)
    return tau


@njit(f"{_A1}({_TABLE}, {_INERTIA}, {_A1}, {_A1}, {_A1}, {_A1}, {_A1})")
def dh_inverse_dynamics(P: np.ndarray, modified: int, base: np.ndarray, tool: np.ndarray, mass: np.ndarray, com: np.ndarray, inertia: np.ndarray, q: np.ndarray, dq: np.ndarray, ddq: np.ndarray, g: np.ndarray, F: np.ndarray) -> np.ndarray:
    """Joint torques/forces (n,) by Craig's recursive Newton–Euler; g (3,) in base_link; F (6,) the
    wrench (n, f) the tool exerts on the environment, tool frame."""
    check_q(P, q)
    n = P.shape[0]
    if dq.shape[0] != n or ddq.shape[0] != n or not (all_finite(dq) and all_finite(ddq)):
        raise ValueError("dq, ddq: expected one finite value per joint")
    if g.shape[0] != 3 or F.shape[0] != 6 or not (all_finite(g) and all_finite(F)):
        raise ValueError("gravity, F_tip: expected 3 and 6 finite values")
    Ts = np.empty((n, 4, 4))
    w3 = np.empty((12, 3))
    Fs = np.empty((n, 3))
    Ns = np.empty((n, 3))
    tau = np.empty(n)
    rnea_into(P, modified, base, tool, mass, com, inertia, q, dq, ddq, g, F, Ts, w3, Fs, Ns, tau)
    return tau


# ------------------------------------------------------------------ N configurations, in parallel
@njit
def fk_rows(lo: int, hi: int, P: np.ndarray, modified: int, base: np.ndarray, tool: np.ndarray, Q: np.ndarray, out: np.ndarray) -> None:
    W = np.empty((2, 4, 4))
    for k in range(lo, hi):
        fk_into(P, modified, base, tool, Q[k], out[k], W[0], W[1])


@njit
def jacobian_rows(lo: int, hi: int, P: np.ndarray, modified: int, base: np.ndarray, tool: np.ndarray, Q: np.ndarray, in_tool: int, out: np.ndarray) -> None:
    W = np.empty((3, 4, 4))
    for k in range(lo, hi):
        jacobian_into(P, modified, base, tool, Q[k], in_tool, out[k], W[0], W[1], W[2])


@njit
def static_torques_rows(lo: int, hi: int, P: np.ndarray, modified: int, base: np.ndarray, tool: np.ndarray, Q: np.ndarray, Fs: np.ndarray, out: np.ndarray) -> None:
    n = P.shape[0]
    frames = np.empty((n + 1, 4, 4))
    W = np.empty((3, 4, 4))
    for k in range(lo, hi):
        static_torques_into(P, modified, base, tool, Q[k], Fs[k if Fs.shape[0] > 1 else 0], frames, W[0], W[1],
                            W[2], out[k])


@njit
def rnea_rows(lo: int, hi: int, P: np.ndarray, modified: int, base: np.ndarray, tool: np.ndarray, mass: np.ndarray, com: np.ndarray, inertia: np.ndarray, Q: np.ndarray, dQ: np.ndarray, ddQ: np.ndarray, g: np.ndarray, Fs: np.ndarray, out: np.ndarray) -> None:
    n = P.shape[0]
    Ts = np.empty((n, 4, 4))
    w3 = np.empty((12, 3))
    Fl = np.empty((n, 3))
    Nl = np.empty((n, 3))
    for k in range(lo, hi):
        rnea_into(P, modified, base, tool, mass, com, inertia, Q[k], dQ[k], ddQ[k], g, Fs[k if Fs.shape[0] > 1 else 0],
                  Ts, w3, Fl, Nl, out[k])


@njit(f"{_A3}({_TABLE}, {_A2})", parallel=True, interpret_while_compiling=FK_BATCH)
def dh_fk_batch(P: np.ndarray, modified: int, base: np.ndarray, tool: np.ndarray, Q: np.ndarray) -> np.ndarray:
    """Tool poses (N, 4, 4) for the rows of Q (N, n)."""
    N = Q.shape[0]
    out = np.empty((N, 4, 4))
    if N < SERIAL_BELOW:  # too few rows to pay for waking the threads
        fk_rows(np.int64(0), N, P, modified, base, tool, Q, out)
        return out
    nb = n_blocks(N)
    for b in prange(nb):
        lo, hi = block_range(b, nb, N)
        fk_rows(lo, hi, P, modified, base, tool, Q, out)
    return out


@njit(f"{_A3}({_TABLE}, {_A2}, int64)", parallel=True, interpret_while_compiling=FK_BATCH)
def dh_jacobian_batch(P: np.ndarray, modified: int, base: np.ndarray, tool: np.ndarray, Q: np.ndarray, in_tool: int) -> np.ndarray:
    """Jacobians (N, 6, n) for the rows of Q (N, n)."""
    N = Q.shape[0]
    out = np.empty((N, 6, P.shape[0]))
    if N < SERIAL_BELOW:  # too few rows to pay for waking the threads
        jacobian_rows(np.int64(0), N, P, modified, base, tool, Q, in_tool, out)
        return out
    nb = n_blocks(N)
    for b in prange(nb):
        lo, hi = block_range(b, nb, N)
        jacobian_rows(lo, hi, P, modified, base, tool, Q, in_tool, out)
    return out


@njit(f"{_A2}({_TABLE}, {_A2}, {_A2})", parallel=True)
def dh_static_torques_batch(P: np.ndarray, modified: int, base: np.ndarray, tool: np.ndarray, Q: np.ndarray, Fs: np.ndarray) -> np.ndarray:
    """Static torques (N, n) for the rows of Q (N, n) and tool wrenches Fs (N, 6) or (1, 6)."""
    N = Q.shape[0]
    out = np.empty((N, P.shape[0]))
    if N < SERIAL_BELOW:  # too few rows to pay for waking the threads
        static_torques_rows(np.int64(0), N, P, modified, base, tool, Q, Fs, out)
        return out
    nb = n_blocks(N)
    for b in prange(nb):
        lo, hi = block_range(b, nb, N)
        static_torques_rows(lo, hi, P, modified, base, tool, Q, Fs, out)
    return out


@njit(f"{_A2}({_TABLE}, {_INERTIA}, {_A2}, {_A2}, {_A2}, {_A1}, {_A2})", parallel=True)
def dh_inverse_dynamics_batch(P: np.ndarray, modified: int, base: np.ndarray, tool: np.ndarray, mass: np.ndarray, com: np.ndarray, inertia: np.ndarray, Q: np.ndarray, dQ: np.ndarray, ddQ: np.ndarray, g: np.ndarray, Fs: np.ndarray) -> np.ndarray:
    """Craig Newton–Euler torques (N, n) for the rows of Q, dQ, ddQ (N, n); Fs (N, 6) or (1, 6)."""
    N = Q.shape[0]
    out = np.empty((N, P.shape[0]))
    if N < SERIAL_BELOW:  # too few rows to pay for waking the threads
        rnea_rows(np.int64(0), N, P, modified, base, tool, mass, com, inertia, Q, dQ, ddQ, g, Fs, out)
        return out
    nb = n_blocks(N)
    for b in prange(nb):
        lo, hi = block_range(b, nb, N)
        rnea_rows(lo, hi, P, modified, base, tool, mass, com, inertia, Q, dQ, ddQ, g, Fs, out)
    return out
