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
library), and starts the inward iteration. The recursion runs as a compiled loop
(:func:`robokit.kernels.dh.dh_inverse_dynamics`, both conventions, R and P joints).
"""
from __future__ import annotations

from types import ModuleType
from typing import TYPE_CHECKING, Literal, overload

import numpy as np
from numpy.typing import ArrayLike

from robokit._arrays import as_vector, kernel_array
from robokit.dynamics.dh_trace import DHDynamicsTrace, dh_newton_euler_trace
from robokit.kinematics.dh import flip_signs

if TYPE_CHECKING:
    from robokit.description.dh import DHTable

__all__ = ["dh_inverse_dynamics"]

_NO_WRENCH = np.zeros(6)  # the default tip wrench (never written)
_kdh = None  # robokit.kernels.dh, imported on first use (the recursion itself lives there)


def _kernels() -> ModuleType:
    global _kdh
    from robokit.kernels import dh

    _kdh = dh
    return dh


@overload
def dh_inverse_dynamics(table: DHTable, q: ArrayLike, dq: ArrayLike, ddq: ArrayLike, gravity: ArrayLike | None = ...,
                        F_tip: ArrayLike | None = ...,
                        trace: Literal[True] = ...) -> tuple[np.ndarray, DHDynamicsTrace]: ...


@overload
def dh_inverse_dynamics(table: DHTable, q: ArrayLike, dq: ArrayLike, ddq: ArrayLike, gravity: ArrayLike | None = ...,
                        F_tip: ArrayLike | None = ..., *, trace: Literal[False]) -> np.ndarray: ...


def dh_inverse_dynamics(table: DHTable, q: ArrayLike, dq: ArrayLike, ddq: ArrayLike, gravity: ArrayLike | None = None,
                        F_tip: ArrayLike | None = None,
                        trace: bool = True) -> np.ndarray | tuple[np.ndarray, DHDynamicsTrace]:
    """Joint torques/forces (n,) by Craig's recursive Newton–Euler on a :class:`DHTable`, with the
    recursion's every step (the lecture's table) unless ``trace=False``.

    Parameters
    ----------
    table : DHTable
        Uses the table's link masses, centres of mass and inertias (frame-{i} axes, about the COM).
    q, dq, ddq : (n,) array_like
        Joint positions, rates, accelerations (rad or m).
    gravity : (3,) array_like, optional
        In base_link (default the table's), m/s².
    F_tip : (6,) array_like, optional
        The wrench (n, f) the tool exerts on the environment, in the tool frame.
    trace : bool
        Also return every step of the iterations (Lecture 7's ⁱωᵢ, ⁱω̇ᵢ, ⁱv̇ᵢ, v̇_Cᵢ, Fᵢ, Nᵢ, ⁱfᵢ, ⁱnᵢ,
        see :class:`robokit.dynamics.DHDynamicsTrace`; ``print(trace)`` is the per-link table).
        Default True; ``trace=False`` returns the torques alone, from the compiled recursion
        (about a microsecond for six joints: the form for loops and controllers).

    Returns
    -------
    (tau, trace) : ((n,) ndarray, DHDynamicsTrace)
        Joint torques (N·m) / forces (N) and the recursion's steps; with ``trace=False`` the
        torques alone.

    Examples
    --------
    The course's planar two-link arm (point masses m₁ = 2 kg, m₂ = 1.5 kg at the link ends,
    l₁ = 1 m, l₂ = 0.8 m, gravity −y) held horizontal carries ``τ₁ = (m₁ + m₂) g l₁ + m₂ g l₂``,
    ``τ₂ = m₂ g l₂``; at any state Craig's recursion equals the PoE form
    :func:`robokit.inverse_dynamics`:

    >>> robot = rk.load("twolink")
    >>> tau, steps = dh_inverse_dynamics(robot.dh, [0, 0], [0, 0], [0, 0])
    >>> tau.round(4)
    array([46.107, 11.772])
    >>> dh_inverse_dynamics(robot.dh, [0, 0], [0, 0], [0, 0], trace=False).round(4)
    array([46.107, 11.772])
    >>> p = robot.poe
    >>> tau = rk.inverse_dynamics([0.3, -0.4], [0.5, 1], [1, -2], robot.gravity, np.zeros(6),
    ...                           p.Mlist, p.Glist, p.Slist)
    >>> bool(np.allclose(dh_inverse_dynamics(robot.dh, [0.3, -0.4], [0.5, 1], [1, -2], trace=False), tau))
    True
    """
    if trace:
        return dh_newton_euler_trace(table, q, dq, ddq, gravity, F_tip)
    n = table.n
    k = _kdh or _kernels()
    packed = k.pack_dh(table)
    g = table.gravity if gravity is None else gravity
    F = _NO_WRENCH if F_tip is None else F_tip
    signs = flip_signs(table)
    if all(type(x) is np.ndarray and x.ndim == 1 for x in (q, dq, ddq, g, F)) and signs is None:
        try:  # the kernel checks lengths and finiteness itself
            return k.dh_inverse_dynamics(*packed, q, dq, ddq, g, F)
        except (TypeError, ValueError):  # another dtype/layout or a bad value: the full checks below
            pass
    c = kernel_array  # writeable too: a robot's gravity is read-only
    q = c(as_vector(q, "q", n))
    dq = c(as_vector(dq, "dq", n))
    ddq = c(as_vector(ddq, "ddq", n))
    g = c(as_vector(g, "gravity", 3))
    F = c(as_vector(F, "F_tip", 6))
    if signs is not None:  # a flipped joint moves by −qᵢ: the recursion sees s∘q, its torque is sᵢτᵢ
        return k.dh_inverse_dynamics(*packed, q * signs, dq * signs, ddq * signs, g, F) * signs
    return k.dh_inverse_dynamics(*packed, q, dq, ddq, g, F)
