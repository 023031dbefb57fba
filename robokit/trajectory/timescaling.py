r"""Time scalings and the seed library's point-to-point trajectories (seed 004 §5; Modern Robotics ch. 9).

A path θ(s), s ∈ [0, 1], is turned into a trajectory by a time scaling s(t) on [0, T_f]
with s(0) = 0, s(T_f) = 1 and, here, zero velocity at both ends:

* cubic    s = 3(t/T)² − 2(t/T)³                 (zero end velocities)
* quintic  s = 10(t/T)³ − 15(t/T)⁴ + 6(t/T)⁵     (zero end velocities and accelerations)
* lspb     trapezoidal velocity, peak ṡ = 1.5/T (blend time T/3), Lecture 3

Point-to-point trajectories of the seed library (N samples, equally spaced in time,
both ends included):

* joint space:     θ(s) = θ_start + s (θ_end − θ_start)
* screw motion:    X(s) = X_start exp(log(X_start⁻¹ X_end) s)      (a constant screw)
* Cartesian:       p(s) = p_start + s (p_end − p_start),
                   R(s) = R_start exp(log(R_startᵀ R_end) s)       (straight line + fixed-axis rotation)
"""
from __future__ import annotations

from numbers import Integral
from typing import Callable

import numpy as np
from numpy.typing import ArrayLike

from robokit._arrays import as_array, as_vector
from robokit._units import TURN, check_radians
from robokit.spatial.se3 import check_transform
from robokit.trajectory.core import positive_duration
from robokit.spatial import lie
from robokit.errors import InputError

__all__ = [
    "cubic_time_scaling",
    "quintic_time_scaling",
    "time_scaling",
    "joint_trajectory",
    "screw_trajectory",
    "cartesian_trajectory",
]


def _cubic(r: np.ndarray) -> np.ndarray:
    # s(r) = 3r² − 2r³, r = t/T
    return 3.0 * r**2 - 2.0 * r**3


def _quintic(r: np.ndarray) -> np.ndarray:
    # s(r) = 10r³ − 15r⁴ + 6r⁵, r = t/T
    return r**3 * (10.0 - 15.0 * r + 6.0 * r**2)


def _scaling(s_of_r: Callable[[np.ndarray], np.ndarray], Tf: float, t: ArrayLike) -> float | np.ndarray:
    # s(t/Tf) at the time(s) t: a float for a scalar t, else an array shaped like t
    T = positive_duration(Tf, "Tf")
    x = as_array(t, "t")
    s = s_of_r(x / T)
    return float(s) if x.ndim == 0 else s


def cubic_time_scaling(Tf: float, t: ArrayLike) -> float | np.ndarray:
    """Cubic time scaling s(t) = 3(t/Tf)² − 2(t/Tf)³ (zero velocity at t = 0 and Tf).

    Parameters
    ----------
    Tf : float
        Total time, s (> 0).
    t : float or array
        Current time(s), s (usually in [0, Tf]; the polynomial is evaluated as is outside).

    Returns
    -------
    float or ndarray (same shape as ``t``): the path parameter s ∈ [0, 1] for t ∈ [0, Tf].

    Examples
    --------
    >>> round(cubic_time_scaling(2, 0.6), 12)
    0.216
    """
    return _scaling(_cubic, Tf, t)


def quintic_time_scaling(Tf: float, t: ArrayLike) -> float | np.ndarray:
    """Quintic time scaling s(t) = 10(t/Tf)³ − 15(t/Tf)⁴ + 6(t/Tf)⁵ (zero end velocity and acceleration).

    Parameters
    ----------
    Tf, t : float, float or array_like
        Total time and current time(s), as for :func:`cubic_time_scaling`.

    Returns
    -------
    float or numpy.ndarray
        The quintic's s, shaped like ``t`` (as for :func:`cubic_time_scaling`).

    Examples
    --------
    ``s(0.6) = 10·0.3³ − 15·0.3⁴ + 6·0.3⁵`` for Tf = 2; halfway, s = 1/2:

    >>> round(quintic_time_scaling(2, 0.6), 12), quintic_time_scaling(2, 1.0)
    (0.16308, 0.5)
    """
    return _scaling(_quintic, Tf, t)


def _method_name(method: int | str) -> str:
    if isinstance(method, bool):
        raise InputError(f"method: expected 3 (cubic) or 5 (quintic), got {method!r}")
    if isinstance(method, Integral) or (isinstance(method, float) and float(method).is_integer()):
        if int(method) == 3:
            return "cubic"
        if int(method) == 5:
            return "quintic"
    if method in ("cubic", "quintic", "lspb"):
        return method
    raise InputError(f"method: expected 3 (cubic) or 5 (quintic) (or 'cubic', 'quintic', 'lspb'), got {method!r}")


def time_scaling(method: int | str, Tf: float, t: ArrayLike) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """A time scaling with its derivatives: ``(s, ṡ, s̈)`` at times ``t``.

    Parameters
    ----------
    method : 3, 5, ``"cubic"``, ``"quintic"`` or ``"lspb"``
        The scaling (see the module docstring); ``"lspb"`` has peak ṡ = 1.5/Tf.
    Tf : float
        Total time, s (> 0).
    t : float or array (K,)
        Times, s, in [0, Tf] (clipped to it).

    Returns
    -------
    (s, sd, sdd) : three arrays shaped like ``t`` (1/s and 1/s² for the derivatives).

    Examples
    --------
    >>> s, sd, sdd = time_scaling("lspb", 3.0, [0.0, 1.5, 3.0])
    >>> s.tolist(), sd.tolist()
    ([0.0, 0.5, 1.0], [0.0, 0.5, 0.0])
    """
    kind = _method_name(method)
    T = positive_duration(Tf, "Tf")
    x = np.clip(as_array(t, "t"), 0.0, T)
    r = x / T
    if kind == "cubic":
        return _cubic(r), (6 * r - 6 * r**2) / T, (6 - 12 * r) / T**2
    if kind == "quintic":
        return (
            _quintic(r),
            r**2 * (30 - 60 * r + 30 * r**2) / T,
            r * (60 - 180 * r + 120 * r**2) / T**2,
        )
    # lspb from 0 to 1: V = 1.5/T, t_b = T/3, a = V/t_b = 4.5/T²
    tb = T / 3.0
    V = 1.5 / T
    a = V / tb
    s = np.where(x <= tb, 0.5 * a * x**2, np.where(x <= T - tb, 0.5 * a * tb**2 + V * (x - tb), 1.0 - 0.5 * a * (T - x) ** 2))
    sd = np.where(x <= tb, a * x, np.where(x <= T - tb, V, a * (T - x)))
    sdd = np.where(x < tb, a, np.where(x <= T - tb, 0.0, -a))
    return s, sd, sdd


def _grid(Tf: float, N: int, method: int | str) -> np.ndarray:
    kind = _method_name(method)
    if kind == "lspb":
        raise InputError("method: expected 3 (cubic) or 5 (quintic), got 'lspb'")
    T = positive_duration(Tf, "Tf")
    if isinstance(N, bool) or not isinstance(N, Integral) or N < 2:
        raise InputError(f"N: the number of points must be an integer >= 2, got {N!r}")
    t = T / (int(N) - 1) * np.arange(int(N))
    t[-1] = T
    s = cubic_time_scaling(T, t) if kind == "cubic" else quintic_time_scaling(T, t)
    return s


def _pose_grid(Xstart: ArrayLike, Xend: ArrayLike, Tf: float, N: int, method: int | str) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    # the checked end poses and the N values of s, for the two pose trajectories
    return check_transform(Xstart, "Xstart"), check_transform(Xend, "Xend"), _grid(Tf, N, method)


def joint_trajectory(thetastart: ArrayLike, thetaend: ArrayLike, Tf: float, N: int, method: int | str) -> np.ndarray:
    """Straight-line joint-space trajectory with cubic or quintic time scaling (seed 004 §5).

    Parameters
    ----------
    thetastart, thetaend : array (n,)
        Start and end joint positions (rad or m).
    Tf : float
        Total time, s (> 0).
    N : int
        Number of points (≥ 2), equally spaced in time, both ends included.
    method : 3 or 5
        Cubic or quintic time scaling; anything else raises ``ValueError``.

    Returns
    -------
    ndarray (N, n): row i is θ at time i·Tf/(N−1).

    Examples
    --------
    >>> joint_trajectory([0, 0], [1, 2], 2, 3, 3).tolist()
    [[0.0, 0.0], [0.5, 1.0], [1.0, 2.0]]
    """
    a = as_vector(thetastart, "thetastart")
    b = as_vector(thetaend, "thetaend", a.shape[0])
    # joint values by name, kinds unknown: every value at ±2π (robokit._units), one warning per call
    if not check_radians(a, -TURN, TURN, "thetastart"):
        check_radians(b, -TURN, TURN, "thetaend")
    s = _grid(Tf, N, method)
    return a + s[:, None] * (b - a)


def screw_trajectory(Xstart: ArrayLike, Xend: ArrayLike, Tf: float, N: int, method: int | str) -> list[np.ndarray]:
    """Trajectory along the constant screw motion from ``Xstart`` to ``Xend`` (seed 004 §5).

    X(s) = X_start exp(log(X_start⁻¹ X_end) s), s from the cubic (3) or quintic (5) time scaling.

    Parameters
    ----------
    Xstart, Xend : array (4, 4)
        Start and end poses in SE(3) (``T_world_tool``).
    Tf : float
        Total time, s (> 0).
    N : int
        Number of points (≥ 2), equally spaced in time, both ends included.
    method : 3 or 5
        Cubic or quintic time scaling (``"cubic"``, ``"quintic"`` also accepted).

    Returns
    -------
    list of N arrays (4, 4); the first is ``Xstart``, the last ``Xend``.

    Examples
    --------
    >>> import numpy as np
    >>> X1 = np.eye(4); X1[:3, 3] = [1, 0, 0]
    >>> [float(X[0, 3]) for X in screw_trajectory(np.eye(4), X1, 1, 3, 3)]
    [0.0, 0.5, 1.0]
    """
    X0, X1, s = _pose_grid(Xstart, Xend, Tf, N, method)
    V = lie.log6(lie.inv(X0) @ X1)
    out = [X0 @ lie.exp6(V * si) for si in s]
    out[0] = X0.copy()
    return out


def cartesian_trajectory(Xstart: ArrayLike, Xend: ArrayLike, Tf: float, N: int, method: int | str) -> list[np.ndarray]:
    """Straight-line position with fixed-axis rotation between two poses (seed 004 §5).

    p(s) = p_start + s (p_end − p_start),  R(s) = R_start exp(log(R_startᵀ R_end) s): the
    tool origin moves on a straight line while the orientation turns about one fixed axis
    (the same path as quaternion slerp); s from the cubic (3) or quintic (5) time scaling.

    Parameters
    ----------
    Xstart, Xend, Tf, N, method
        As for :func:`screw_trajectory` (poses in m).

    Returns
    -------
    list of numpy.ndarray, shape (4, 4) each
        The N poses; the first is ``Xstart``, the last ``Xend``.

    Examples
    --------
    A quarter turn about z on the way to x = 1 m: the midpoint stays on the straight line, where
    the constant screw of :func:`screw_trajectory` swings out to y = −0.2071 m:

    >>> X1 = rk.Rp_to_trans(rk.euler_to_matrix([np.pi / 2, 0, 0]), [1, 0, 0])
    >>> cartesian_trajectory(np.eye(4), X1, 1, 3, 5)[1][:3, 3], screw_trajectory(np.eye(4), X1, 1, 3, 5)[1][:3, 3]
    (array([0.5, 0. , 0. ]), array([ 0.5   , -0.2071,  0.    ]))
    """
    X0, X1, s = _pose_grid(Xstart, Xend, Tf, N, method)
    R0, p0 = X0[:3, :3], X0[:3, 3]
    R1, p1 = X1[:3, :3], X1[:3, 3]
    w = lie.log3(R0.T @ R1)
    out = []
    for si in s:
        X = np.eye(4)
        X[:3, :3] = R0 @ lie.exp3(w * si)
        X[:3, 3] = p0 + si * (p1 - p0)
        out.append(X)
    out[0] = X0.copy()
    return out
