r"""DH-side kinematics (Lectures 4 and 7): Jacobians by outward velocity propagation, static forces
by inward propagation.

Velocity propagation (Lecture 7, Craig ch. 5), link by link in each link's own frame, for unit
rate of one joint at a time — the columns of the Jacobian. With ``ᶦR_{i−1}`` the rotation from
frame {i−1} to {i} and ``ⁱ⁻¹p_i`` the origin of {i} in {i−1}:

* modified (Craig) convention, joint i turns about ẑ_i:
  ``ᶦω_i = ᶦR_{i−1} ⁱ⁻¹ω_{i−1} + θ̇_i ẑ``,
  ``ᶦv_i = ᶦR_{i−1}(ⁱ⁻¹v_{i−1} + ⁱ⁻¹ω_{i−1} × ⁱ⁻¹p_i) + ḋ_i ẑ``;
* standard convention, joint i turns about ẑ_{i−1} (through the origin of {i−1}):
  ``ᶦω_i = ᶦR_{i−1}(ⁱ⁻¹ω_{i−1} + θ̇_i ẑ)``,
  ``ᶦv_i = ᶦR_{i−1}(ⁱ⁻¹v_{i−1} + (ⁱ⁻¹ω_{i−1} + θ̇_i ẑ) × ⁱ⁻¹p_i + ḋ_i ẑ)``.

The tool frame, rigidly attached to {N}, gets ``ω_t = ᵗR_N ω_N``, ``v_t = ᵗR_N(v_N + ω_N × ᴺp_t)``.
The result is the geometric Jacobian ``(ω; v)`` of the tool origin, in the tool frame; rotated by
``blockdiag(R, R)`` (R = the tool's orientation in base_link) it is the base-frame Jacobian.

Static forces propagate inward (Craig ch. 5): with ``(f, n)`` the force and moment the tool
exerts on the environment, ``f_i = f_{i+1}``, ``n_i = n_{i+1} + (o_{i+1} − o_i) × f_{i+1}`` about
the origin of each joint's axis frame, ``τ_i = ẑ_iᵀ n_i`` (revolute) or ``ẑ_iᵀ f_i`` (prismatic) —
the same as ``τ = Jᵀ F``.
"""
from __future__ import annotations

import numpy as np

from robokit._arrays import as_vector

__all__ = ["dh_jacobian", "dh_static_torques"]


def _skew(w):
    return np.array([[0.0, -w[2], w[1]], [w[2], 0.0, -w[0]], [-w[1], w[0], 0.0]])


def dh_jacobian(table, q, frame: str = "base") -> np.ndarray:
    """Geometric Jacobian (6×n, rows (ω; v) of the tool origin) of a :class:`DHTable` by outward
    velocity propagation.

    table : DHTable (standard or modified, revolute and prismatic joints); q : (n,) joint values;
    frame : "base" — expressed in base_link axes (= Pinocchio's LOCAL_WORLD_ALIGNED), or
    "tool" — in the tool frame's axes (= Pinocchio's LOCAL).

    Example: for the planar 2-link arm the v rows are Lecture 6's ``[[−l₁s₁ − l₂s₁₂, −l₂s₁₂], …]``.
    """
    if frame not in ("base", "tool"):
        raise ValueError(f"frame: expected 'base' or 'tool', got {frame!r}")
    q = as_vector(q, "q", table.n)
    n = table.n
    Ts = [table.link_transform(i, q[i]) for i in range(n)]  # ⁱ⁻¹T_i
    tool = np.asarray(table.tool, dtype=float)
    zhat = np.array([0.0, 0.0, 1.0])
    standard = table.convention == "standard"
    J = np.empty((6, n))
    for j in range(n):  # unit rate of joint j
        w = np.zeros(3)
        v = np.zeros(3)
        for i in range(n):
            R = Ts[i][:3, :3]  # ⁱ⁻¹R_i
            p = Ts[i][:3, 3]  # ⁱ⁻¹p_i
            rate = 1.0 if i == j else 0.0
            revolute = table.links[i].joint == "R"
            if standard:
                w_prev = w + (rate * zhat if revolute else 0.0)
                v = R.T @ (v + np.cross(w_prev, p) + (0.0 if revolute else rate * zhat))
                w = R.T @ w_prev
            else:
                v = R.T @ (v + np.cross(w, p)) + (0.0 if revolute else rate * zhat)
                w = R.T @ w + (rate * zhat if revolute else 0.0)
        # the tool, rigidly attached to {N}
        Rt, pt = tool[:3, :3], tool[:3, 3]
        v = Rt.T @ (v + np.cross(w, pt))
        w = Rt.T @ w
        J[:3, j], J[3:, j] = w, v
    if frame == "tool":
        return J
    R_base_tool = table.fk(q)[:3, :3]
    return np.vstack([R_base_tool @ J[:3], R_base_tool @ J[3:]])


def dh_static_torques(table, q, F_tip) -> np.ndarray:
    """Joint torques (n,) that balance a static tip wrench, by inward force propagation.

    F_tip : (6,) ``(n, f)`` — moment and force the tool exerts on the environment, expressed in
    the tool frame (angular first, as Modern Robotics' F_tip). Returns τ with ``τ = J_toolᵀ F_tip``.
    """
    q = as_vector(q, "q", table.n)
    F = as_vector(F_tip, "F_tip", 6)
    frames = table.frames(q)
    T_tool = frames[-1] @ np.asarray(table.tool, dtype=float)
    R = T_tool[:3, :3]
    f = R @ F[3:]  # in base axes
    n_moment = R @ F[:3]  # moment about the tool origin
    point = T_tool[:3, 3]
    standard = table.convention == "standard"
    tau = np.empty(table.n)
    for i in range(table.n - 1, -1, -1):
        axis_frame = frames[i] if standard else frames[i + 1]  # joint i+1 (1-based) axis frame
        o, z = axis_frame[:3, 3], axis_frame[:3, 2]
        n_moment = n_moment + np.cross(point - o, f)  # moment carried inward to this joint's origin
        point = o
        tau[i] = z @ n_moment if table.links[i].joint == "R" else z @ f
    return tau
