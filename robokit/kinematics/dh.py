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

Because the propagation is linear in q̇, the compiled kernel (:mod:`robokit.kernels.dh`) does it
for all columns in one outward O(n) pass: each joint's unit twist is recorded where the pass
meets its axis (``ẑ_j`` and the base-origin velocity ``o_j × ẑ_j``), and the reference point is
moved to the tool origin at the end (``v ← v + ω × p``), giving ``J_j = (ẑ_j, ẑ_j × (p − o_j))``.

Static forces propagate inward (Craig ch. 5): with ``(f, n)`` the force and moment the tool
exerts on the environment, ``f_i = f_{i+1}``, ``n_i = n_{i+1} + (o_{i+1} − o_i) × f_{i+1}`` about
the origin of each joint's axis frame, ``τ_i = ẑ_iᵀ n_i`` (revolute) or ``ẑ_iᵀ f_i`` (prismatic) —
the same as ``τ = Jᵀ F``.
"""
from __future__ import annotations

from types import ModuleType
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import ArrayLike

from robokit._arrays import as_vector, check_reference
from robokit.frames import DEFAULT_FRAME, Frame, reference_or_default

if TYPE_CHECKING:
    from robokit.description.dh import DHTable

__all__ = ["dh_jacobian", "dh_static_torques"]


_kdh = None  # robokit.kernels.dh, imported on first use


def _kernels() -> ModuleType:
    global _kdh
    from robokit.kernels import dh

    _kdh = dh
    return dh


def _q(q: ArrayLike, n: int, name: str = "q") -> np.ndarray:
    return np.ascontiguousarray(as_vector(q, name, n))


def flip_signs(table: DHTable) -> np.ndarray | None:
    """(n,) with −1 for every flipped joint (``flip: true``) and +1 otherwise, or None when no joint
    is flipped (remembered on the table). A flipped joint's variable enters the DH row as −qᵢ, so
    the compiled recursions — written for unflipped joints — take ``s ∘ q`` and their Jacobian
    columns and joint torques are multiplied by s (the chain rule)."""
    cached = table.__dict__.get("_flip_signs", False)
    if cached is not False:
        return cached
    s = np.array([-1.0 if getattr(link, "flip", False) else 1.0 for link in table.links])
    signs = s if (s < 0).any() else None
    object.__setattr__(table, "_flip_signs", signs)
    return signs


def _tool_pose(k: ModuleType, table: DHTable, q: ArrayLike) -> np.ndarray:
    """4×4 tool pose in base_link (the compiled DH product, flipped joints included)."""
    P, modified, base, tool = k.pack_dh(table)[:4]
    qv = _q(q, table.n)
    signs = flip_signs(table)
    return np.asarray(k.dh_fk(P, modified, base, tool, qv * signs if signs is not None else qv))


def dh_jacobian(table: DHTable, q: ArrayLike, reference: Frame | str = DEFAULT_FRAME) -> np.ndarray:
    """Jacobian (6×n, rows (ω; v)) of the tool of a :class:`DHTable`, by outward velocity propagation.

    Parameters
    ----------
    table : DHTable
        Standard or modified convention, revolute and prismatic joints, with its base and tool.
    q : (n,) array_like
        Joint values (rad for revolute, m for prismatic joints).
    reference : Frame or str, default Frame.LOCAL_WORLD_ALIGNED
        Where the twist is expressed, a :class:`robokit.Frame` (the *Conventions* page):
        ``LOCAL_WORLD_ALIGNED`` (formerly "base") — ω and the velocity of the tool origin in
        base_link axes (the lecture's geometric Jacobian ⁰J); ``LOCAL`` (formerly "tool"/"body") —
        the same twist in the tool frame's axes (body Jacobian); ``WORLD`` (formerly "space") — the
        twist taken at the base origin, ``v₀ = v_tool + p × ω`` (space Jacobian).

    Returns
    -------
    (6, n) ndarray
        Column j is the tool twist for unit rate of joint j: rows 0–2 ω (rad/s), rows 3–5 v (m/s).

    Examples
    --------
    The planar 2-link arm (l₁ = l₂ = 1) at q = (0, 90°): Lecture 6's v rows
    ``[[−l₁s₁ − l₂s₁₂, −l₂s₁₂], [l₁c₁ + l₂c₁₂, l₂c₁₂]]``, and ω = ż for both joints.

    >>> from robokit.description import DHTable, DHLink
    >>> arm = DHTable("planar2", "standard", (DHLink("R", a=1.0), DHLink("R", a=1.0)))
    >>> J = dh_jacobian(arm, [0.0, np.pi / 2])
    >>> J[[2, 3, 4]].round(4)
    array([[ 1.,  1.],
           [-1., -1.],
           [ 1.,  0.]])
    """
    ref = check_reference(reference)
    k = _kdh or _kernels()
    P, modified, base, tool = k.pack_dh(table)[:4]
    if ref == "world":  # the space Jacobian: the same twist with v taken at the base origin, v₀ = v_p + p × ω
        J = dh_jacobian(table, q, Frame.LOCAL_WORLD_ALIGNED)
        p = _tool_pose(k, table, q)[:3, 3]
        J[3:] += np.cross(p, J[:3], axis=0)
        return J
    in_tool = 1 if ref == "local" else 0
    signs = flip_signs(table)
    if signs is not None:
        return k.dh_jacobian(P, modified, base, tool, _q(q, table.n) * signs, in_tool) * signs
    if type(q) is np.ndarray and q.ndim == 1:
        try:
            return k.dh_jacobian(P, modified, base, tool, q, in_tool)
        except (TypeError, ValueError):  # another dtype/layout or a bad value: the full checks below
            pass
    return k.dh_jacobian(P, modified, base, tool, _q(q, table.n), in_tool)


def dh_static_torques(table: DHTable, q: ArrayLike, F_tip: ArrayLike, reference: Frame | str | None = None) -> np.ndarray:
    """Joint torques that balance a static tip wrench, by inward force propagation (Lecture 7).

    ``f_i = f_{i+1}``, ``n_i = n_{i+1} + (o_{i+1} − o_i) × f_{i+1}``, ``τ_i = ẑ_iᵀ n_i`` (revolute) or
    ``ẑ_iᵀ f_i`` (prismatic), the same as ``τ = Jᵀ F_tip``.

    Parameters
    ----------
    table : DHTable
        The arm (standard or modified convention, with its base and tool).
    q : (n,) array_like
        Joint values (rad, m).
    F_tip : (6,) array_like
        ``(n, f)``: moment (N·m) and force (N) the tool exerts on the environment, angular first
        as Modern Robotics' F_tip, in the frame ``reference`` names.
    reference : Frame or str, optional
        The frame F_tip is given in, a :class:`robokit.Frame` as for :func:`dh_jacobian`:
        ``LOCAL_WORLD_ALIGNED`` (robokit's one default) — base_link axes, moment about the tool
        origin (a force sensor's reading moved to the tool); ``LOCAL`` — tool axes, moment about
        the tool origin; ``WORLD`` — base_link axes, moment about the base origin. Omitted:
        LOCAL_WORLD_ALIGNED (before 0.3 this function read F_tip in LOCAL, tool axes).

    Returns
    -------
    (n,) ndarray
        τ (N·m for revolute, N for prismatic joints) with ``τ = J_refᵀ F_tip``, J_ref the
        :func:`dh_jacobian` with the same ``reference``.

    Examples
    --------
    The planar 2-link arm (l₁ = l₂ = 1) stretched along x pushing 10 N down (−y, base axes) on the
    environment: ``τ = Jᵀ F`` gives 10 N × 2 m at the shoulder and 10 N × 1 m at the elbow.

    >>> from robokit.description import DHTable, DHLink
    >>> arm = DHTable("planar2", "standard", (DHLink("R", a=1.0), DHLink("R", a=1.0)))
    >>> from robokit.frames import Frame
    >>> dh_static_torques(arm, [0.0, 0.0], [0, 0, 0, 0, -10, 0], reference=Frame.LOCAL_WORLD_ALIGNED).round(4)
    array([-20., -10.])
    """
    ref = reference_or_default(reference, "dh_static_torques")
    k = _kdh or _kernels()
    P, modified, base, tool = k.pack_dh(table)[:4]
    signs = flip_signs(table)
    if ref != "local":
        Fb = _q(F_tip, 6, "F_tip")
        T = _tool_pose(k, table, q)
        if ref == "world":  # moment about the base origin → about the tool origin: n_p = n₀ − p × f
            Fb = np.concatenate([Fb[:3] - np.cross(T[:3, 3], Fb[3:]), Fb[3:]])
        R = T[:3, :3]
        F_tip = np.ascontiguousarray(np.concatenate([R.T @ Fb[:3], R.T @ Fb[3:]]))
    if signs is not None:
        return k.dh_static_torques(P, modified, base, tool, _q(q, table.n) * signs, _q(F_tip, 6, "F_tip")) * signs
    if type(q) is np.ndarray and q.ndim == 1 and type(F_tip) is np.ndarray and F_tip.ndim == 1:
        try:
            return k.dh_static_torques(P, modified, base, tool, q, F_tip)
        except (TypeError, ValueError):
            pass
    return k.dh_static_torques(P, modified, base, tool, _q(q, table.n), _q(F_tip, 6, "F_tip"))
