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

from robokit.errors import InputError
from robokit._arrays import as_vector

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


def dh_jacobian(table: DHTable, q: ArrayLike, reference: str = "base") -> np.ndarray:
    """Geometric Jacobian of a DH table by outward velocity propagation (Lecture 7, Craig ch. 5).

    The recursion of this module's docstring, run for all columns in one O(n) pass: column j is
    ``(ẑ_j, ẑ_j × (p − o_j))`` for a revolute joint and ``(0, ẑ_j)`` for a prismatic one, with
    ``ẑ_j``, ``o_j`` the joint's axis and origin and p the tool origin. Flipped joints
    (``flip: true``) get their column negated.

    Parameters
    ----------
    table : DHTable
        Standard or modified convention, revolute and prismatic joints (base and tool included).
    q : (n,) array_like
        Joint values (rad for revolute, m for prismatic joints).
    reference : {"base", "tool"}, optional
        Axes of the result: ``"base"`` (default) — base_link axes (Pinocchio's
        LOCAL_WORLD_ALIGNED); ``"tool"`` — the tool frame's axes (Pinocchio's LOCAL).

    Returns
    -------
    (6, n) ndarray
        Rows ``(ω; v)``: angular velocity (rad/s) and velocity of the tool origin (m/s) per unit
        joint rate, in the chosen axes.

    Raises
    ------
    InputError
        When ``q`` has the wrong length or non-finite values, or ``reference`` is unknown.

    Examples
    --------
    The course's planar two-link arm (l₁ = 1 m, l₂ = 0.8 m) at q = (0, π/2): the v rows x, y are
    Lecture 6's ``[[−l₁s₁ − l₂s₁₂, −l₂s₁₂], [l₁c₁ + l₂c₁₂, l₂c₁₂]] = [[−0.8, −0.8], [1, 0]]``:

    >>> table = rk.load("twolink").dh
    >>> dh_jacobian(table, [0, np.pi / 2])[3:5].round(4)
    array([[-0.8, -0.8],
           [ 1. ,  0. ]])
    """
    if reference not in ("base", "tool"):
        raise InputError(f"reference: expected 'base' or 'tool', got {reference!r}")
    k = _kdh or _kernels()
    P, modified, base, tool = k.pack_dh(table)[:4]
    in_tool = 1 if reference == "tool" else 0
    signs = flip_signs(table)
    if signs is not None:
        return k.dh_jacobian(P, modified, base, tool, _q(q, table.n) * signs, in_tool) * signs
    if type(q) is np.ndarray and q.ndim == 1:
        try:
            return k.dh_jacobian(P, modified, base, tool, q, in_tool)
        except (TypeError, ValueError):  # another dtype/layout or a bad value: the full checks below
            pass
    return k.dh_jacobian(P, modified, base, tool, _q(q, table.n), in_tool)


def dh_static_torques(table: DHTable, q: ArrayLike, F_tip: ArrayLike, reference: str = "tool") -> np.ndarray:
    """Joint torques that balance a static tip wrench, by inward force propagation (Lecture 7).

    ``f_i = f_{i+1}``, ``n_i = n_{i+1} + (o_{i+1} − o_i) × f_{i+1}``, ``τ_i = ẑ_iᵀ n_i`` (revolute) or
    ``ẑ_iᵀ f_i`` (prismatic), the same as ``τ = Jᵀ F_tip``.

    Parameters
    ----------
    table : DHTable
        Standard or modified convention, revolute and prismatic joints.
    q : (n,) array_like
        Joint values (rad, m).
    F_tip : (6,) array_like
        ``(n, f)`` — moment (N·m, about the tool origin) and force (N) the tool exerts on the
        environment, angular first as Modern Robotics' ``Ftip``.
    reference : {"tool", "base"}, optional
        ``"tool"`` (default) — ``F_tip`` in the tool frame's axes; ``"base"`` — in base_link's axes
        (the wrench a force sensor mounted in the world would report, moved to the tool origin).

    Returns
    -------
    (n,) ndarray
        τ (N·m for revolute, N for prismatic joints) with ``τ = J_toolᵀ F_tip`` ("tool") or
        ``τ = J_baseᵀ F_tip`` ("base", J with rows (ω; v) of the tool origin in base axes, as
        :func:`dh_jacobian`).

    Raises
    ------
    InputError
        On a wrong length, non-finite values or an unknown ``reference``.

    Examples
    --------
    The planar two-link arm stretched along x (tip at 1.8 m) pushing 10 N down (−y of the base)
    on the environment needs τ = (−10 N × 1.8 m, −10 N × 0.8 m):

    >>> table = rk.load("twolink").dh
    >>> dh_static_torques(table, [0, 0], [0, 0, 0, 0, -10, 0], reference="base").round(4)
    array([-18.,  -8.])
    """
    if reference not in ("tool", "base"):
        raise InputError(f"reference: expected 'tool' or 'base', got {reference!r}")
    k = _kdh or _kernels()
    P, modified, base, tool = k.pack_dh(table)[:4]
    signs = flip_signs(table)
    if reference == "base":
        qv = _q(q, table.n)
        Fb = _q(F_tip, 6, "F_tip")
        R = k.dh_fk(P, modified, base, tool, qv * signs if signs is not None else qv)[:3, :3]
        F_tip = np.ascontiguousarray(np.concatenate([R.T @ Fb[:3], R.T @ Fb[3:]]))
    if signs is not None:
        return k.dh_static_torques(P, modified, base, tool, _q(q, table.n) * signs, _q(F_tip, 6, "F_tip")) * signs
    if type(q) is np.ndarray and q.ndim == 1 and type(F_tip) is np.ndarray and F_tip.ndim == 1:
        try:
            return k.dh_static_torques(P, modified, base, tool, q, F_tip)
        except (TypeError, ValueError):
            pass
    return k.dh_static_torques(P, modified, base, tool, _q(q, table.n), _q(F_tip, 6, "F_tip"))
