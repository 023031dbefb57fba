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
    """Geometric Jacobian (6×n, rows (ω; v) of the tool origin) of a :class:`DHTable` by outward
    velocity propagation.

    table : DHTable (standard or modified, revolute and prismatic joints); q : (n,) joint values;
    reference : "base" — expressed in base_link axes (= Pinocchio's LOCAL_WORLD_ALIGNED), or
    "tool" — in the tool frame's axes (= Pinocchio's LOCAL).

    Example: for the planar 2-link arm the v rows are Lecture 6's ``[[−l₁s₁ − l₂s₁₂, −l₂s₁₂], …]``.
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
    """Joint torques (n,) that balance a static tip wrench, by inward force propagation.

    Parameters
    ----------
    table : DHTable
    q : (n,) joint values (rad, m).
    F_tip : (6,) ``(n, f)`` — moment (N·m, about the tool origin) and force (N) the tool exerts on
        the environment, angular first as Modern Robotics' F_tip.
    reference : "tool" (default) — F_tip in the tool frame's axes; "base" — in base_link's axes
        (the wrench a force sensor mounted in the world would report, moved to the tool origin).

    Returns
    -------
    (n,) ndarray
        τ with ``τ = J_toolᵀ F_tip`` ("tool") or ``τ = J_baseᵀ F_tip`` ("base", J with rows (ω; v)
        of the tool origin in base axes, as :func:`dh_jacobian`).

    Example: ``dh_static_torques(table, q, [0, 0, 0, 0, 0, -10], reference="base")`` holds 10 N
    pushing down on the environment.
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
