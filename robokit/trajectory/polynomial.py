r"""Joint-space polynomial trajectories (Lecture 3; seed 004 §5 "三次多项式标度").

Cubic between two points (4 conditions: end positions and velocities)::

    θ(t) = a0 + a1 t + a2 t² + a3 t³,   0 ≤ t ≤ T
    a0 = θ0,  a1 = θ̇0,
    a2 = (3(θf − θ0) − (2θ̇0 + θ̇f) T) / T²,
    a3 = (−2(θf − θ0) + (θ̇0 + θ̇f) T) / T³

Quintic (6 conditions: positions, velocities and accelerations at both ends), the
closed-form solution of the lecture's 6×6 system ``[s0 sT ṡ0 ṡT s̈0 s̈T] = M [A … F]``::

    a0 = θ0, a1 = θ̇0, a2 = θ̈0/2,
    a3 = (20Δ − (8θ̇f + 12θ̇0)T − (3θ̈0 − θ̈f)T²) / (2T³)
    a4 = (−30Δ + (14θ̇f + 16θ̇0)T + (3θ̈0 − 2θ̈f)T²) / (2T⁴)
    a5 = (12Δ − 6(θ̇f + θ̇0)T − (θ̈0 − θ̈f)T²) / (2T⁵),      Δ = θf − θ0

Cubics through via points (one cubic per interval, C1 at the via points), with the
three ways of Lecture 3 to choose the via-point velocities:

1. given — e.g. from the desired Cartesian velocity through the inverse Jacobian;
2. ``"heuristic"`` — zero where the slopes of the adjacent straight lines change sign
   (or either is zero), otherwise their mean;
3. ``"continuous"`` — the velocities that make the acceleration continuous too (C2):
   at each via point k, with intervals h_{k−1}, h_k and Δ_j = θ_{j+1} − θ_j,

       (2/h_{k−1}) θ̇_{k−1} + 4(1/h_{k−1} + 1/h_k) θ̇_k + (2/h_k) θ̇_{k+1}
           = 6 Δ_{k−1}/h_{k−1}² + 6 Δ_k/h_k²,

   a tridiagonal linear system (the lecture's 8-equation example for one via point is
   the case m = 3).

All coefficients are returned ascending (``a0, a1, …``), per axis in the last dimension.
"""
from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike

from robokit.trajectory.core import (
    Trajectory,
    as_axes,
    eval_piecewise,
    increasing_times,
    optional_axes,
    positive_duration,
    sample_times,
    viapoint_matrix,
)
from robokit.errors import InputError

__all__ = [
    "cubic_coefficients",
    "quintic_coefficients",
    "cubic_trajectory",
    "quintic_trajectory",
    "via_point_velocities",
    "cubic_via_trajectory",
]


def _ends(q0: ArrayLike, qf: ArrayLike) -> tuple[np.ndarray, np.ndarray]:
    a = as_axes(q0, "q0")
    b = as_axes(qf, "qf", a.shape[0])
    return a, b


def cubic_coefficients(q0: ArrayLike, qf: ArrayLike, tf: float, qd0: ArrayLike | None = None, qdf: ArrayLike | None = None) -> np.ndarray:
    """Coefficients of the cubic with given end positions and velocities (seed 004 §5).

    Parameters
    ----------
    q0, qf, tf, qd0, qdf
        End positions, duration T and end velocities (see :mod:`robokit.trajectory.core`).

    Returns
    -------
    ndarray, shape (4, n)
        ``[a0, a1, a2, a3]`` per axis: ``θ(t) = a0 + a1 t + a2 t² + a3 t³``.

    Examples
    --------
    >>> cubic_coefficients(0.0, 1.0, 1.0)[:, 0]   # 3t² − 2t³
    array([ 0.,  0.,  3., -2.])
    """
    a, b = _ends(q0, qf)
    n = a.shape[0]
    T = positive_duration(tf, "tf")
    v0 = optional_axes(qd0, "qd0", n)
    v1 = optional_axes(qdf, "qdf", n)
    d = b - a
    return np.array([a, v0, (3.0 * d - (2.0 * v0 + v1) * T) / T**2, (-2.0 * d + (v0 + v1) * T) / T**3])


def quintic_coefficients(q0: ArrayLike, qf: ArrayLike, tf: float, qd0: ArrayLike | None = None, qdf: ArrayLike | None = None, qdd0: ArrayLike | None = None, qddf: ArrayLike | None = None) -> np.ndarray:
    """Coefficients of the quintic with given end positions, velocities and accelerations.

    Parameters
    ----------
    q0, qf, tf, qd0, qdf, qdd0, qddf
        End positions, duration T, end velocities and accelerations (see
        :mod:`robokit.trajectory.core`).

    Returns
    -------
    ndarray, shape (6, n)
        ``[a0 … a5]`` per axis, ``θ(t) = Σ a_k t^k`` (the lecture writes the same
        polynomial as ``A t⁵ + B t⁴ + … + F``, i.e. ``A = a5 … F = a0``).

    Examples
    --------
    >>> quintic_coefficients(0.0, 1.0, 1.0)[:, 0]   # 10t³ − 15t⁴ + 6t⁵
    array([  0.,   0.,   0.,  10., -15.,   6.])
    """
    a, b = _ends(q0, qf)
    n = a.shape[0]
    T = positive_duration(tf, "tf")
    v0 = optional_axes(qd0, "qd0", n)
    v1 = optional_axes(qdf, "qdf", n)
    c0 = optional_axes(qdd0, "qdd0", n)
    c1 = optional_axes(qddf, "qddf", n)
    d = b - a
    return np.array(
        [
            a,
            v0,
            0.5 * c0,
            (20.0 * d - (8.0 * v1 + 12.0 * v0) * T - (3.0 * c0 - c1) * T**2) / (2.0 * T**3),
            (-30.0 * d + (14.0 * v1 + 16.0 * v0) * T + (3.0 * c0 - 2.0 * c1) * T**2) / (2.0 * T**4),
            (12.0 * d - 6.0 * (v1 + v0) * T - (c0 - c1) * T**2) / (2.0 * T**5),
        ]
    )


def _single(name: str, coeffs: np.ndarray, T: float, t: ArrayLike | None) -> Trajectory:
    ts = sample_times(t, 0.0, T)
    q, qd, qdd = eval_piecewise(np.array([0.0, T]), coeffs[None], ts)
    return Trajectory(ts, q, qd, qdd, name=name, info={"coefficients": coeffs, "tf": T})


def cubic_trajectory(q0: ArrayLike, qf: ArrayLike, tf: float, t: ArrayLike | None = None, qd0: ArrayLike | None = None, qdf: ArrayLike | None = None) -> Trajectory:
    """A cubic from ``q0`` to ``qf`` in ``tf`` seconds, sampled with velocity and acceleration.

    Parameters
    ----------
    q0, qf, tf, t, qd0, qdf
        The cubic's ends, duration, sample grid and end velocities (see
        :mod:`robokit.trajectory.core`).

    Returns
    -------
    Trajectory
        ``t`` (K,), ``q``/``qd``/``qdd`` (K, n); ``info["coefficients"]`` is (4, n).
        ``qdd`` jumps at the ends (a cubic cannot also fix accelerations).

    Examples
    --------
    >>> tr = cubic_trajectory(0.0, 1.0, 2.0, t=3)
    >>> tr.q[:, 0].tolist(), tr.qd[:, 0].tolist()
    ([0.0, 0.5, 1.0], [0.0, 0.75, 0.0])
    """
    T = positive_duration(tf, "tf")
    return _single("cubic", cubic_coefficients(q0, qf, T, qd0, qdf), T, t)


def quintic_trajectory(q0: ArrayLike, qf: ArrayLike, tf: float, t: ArrayLike | None = None, qd0: ArrayLike | None = None, qdf: ArrayLike | None = None, qdd0: ArrayLike | None = None, qddf: ArrayLike | None = None) -> Trajectory:
    """A quintic from ``q0`` to ``qf`` in ``tf`` seconds with given end velocities and accelerations.

    ``q(t) = Σₖ cₖ tᵏ`` (k = 0..5), the six coefficients per axis fixed by the end positions,
    velocities and accelerations (Lecture 3).

    Parameters
    ----------
    q0, qf, tf, t, qd0, qdf, qdd0, qddf
        The quintic's ends, duration, sample grid, end velocities and accelerations (see
        :mod:`robokit.trajectory.core`).

    Returns
    -------
    Trajectory
        ``t`` (K,), ``q``/``qd``/``qdd`` (K, n); ``info["coefficients"]`` is (6, n), ascending.

    Examples
    --------
    Rest to rest in 1 s: halfway at t = 0.5 with the peak speed ``15/8 · Δq``:

    >>> tr = quintic_trajectory([0.0, 1.0], [1.0, 0.0], 1.0, t=3)
    >>> tr.q[1].tolist(), tr.qd[1].tolist()
    ([0.5, 0.5], [1.875, -1.875])
    """
    T = positive_duration(tf, "tf")
    return _single("quintic", quintic_coefficients(q0, qf, T, qd0, qdf, qdd0, qddf), T, t)


def via_point_velocities(viapoints: ArrayLike, times: ArrayLike, method: str = "heuristic", qd0: ArrayLike | None = None, qdf: ArrayLike | None = None) -> np.ndarray:
    """Velocities at the via points for piecewise cubics (Lecture 3, methods 2 and 3).

    Parameters
    ----------
    viapoints : array (m, n)
        Start point, via points and goal, one row per point, one column per axis.
    times : array (m,)
        Strictly increasing times at which the points are reached, s.
    method : ``"heuristic"`` or ``"continuous"``
        ``"heuristic"``: zero where the slopes of the adjacent line segments differ in
        sign or either is zero, else their mean. ``"continuous"``: the velocities that
        make the acceleration continuous at every via point (tridiagonal system).
    qd0, qdf : float or array (n,), optional
        Velocities at the start and the goal (default 0).

    Returns
    -------
    ndarray (m, n)
        Row k is the velocity at point k (rows 0 and m−1 are ``qd0`` and ``qdf``).

    Examples
    --------
    >>> via_point_velocities([[0.0], [1.0], [3.0], [2.0]], [0, 1, 2, 3])[:, 0].tolist()
    [0.0, 1.5, 0.0, 0.0]
    """
    if method not in ("heuristic", "continuous"):
        raise InputError(f"method: expected 'heuristic' or 'continuous', got {method!r}")
    P = viapoint_matrix(viapoints, "viapoints")
    m, n = P.shape
    T = increasing_times(times, "times", m)
    v = np.zeros((m, n))
    v[0] = optional_axes(qd0, "qd0", n)
    v[-1] = optional_axes(qdf, "qdf", n)
    if m == 2:
        return v
    h = np.diff(T)  # (m−1,)
    slope = np.diff(P, axis=0) / h[:, None]  # (m−1, n)
    if method == "heuristic":
        left, right = slope[:-1], slope[1:]
        same = np.sign(left) * np.sign(right) > 0
        v[1:-1] = np.where(same, 0.5 * (left + right), 0.0)
        return v
    # "continuous": the tridiagonal system of the module docstring
    k = m - 2  # unknowns: interior velocities
    A = np.zeros((k, k))
    rhs = np.zeros((k, n))
    for j in range(k):  # via point j+1, between intervals j and j+1
        hl, hr = h[j], h[j + 1]
        A[j, j] = 4.0 * (1.0 / hl + 1.0 / hr)
        if j > 0:
            A[j, j - 1] = 2.0 / hl
        if j < k - 1:
            A[j, j + 1] = 2.0 / hr
        rhs[j] = 6.0 * slope[j] / hl + 6.0 * slope[j + 1] / hr
    rhs[0] -= (2.0 / h[0]) * v[0]
    rhs[-1] -= (2.0 / h[-1]) * v[-1]
    v[1:-1] = np.linalg.solve(A, rhs)
    return v


def cubic_via_trajectory(viapoints: ArrayLike, times: ArrayLike, t: ArrayLike | None = None, velocities: str | ArrayLike = "continuous", qd0: ArrayLike | None = None, qdf: ArrayLike | None = None) -> Trajectory:
    """Piecewise cubics through via points, sampled with velocity and acceleration (Lecture 3).

    Every point is passed exactly at its time; velocities are continuous (C1); with
    ``velocities="continuous"`` the acceleration is continuous as well (C2).

    Parameters
    ----------
    viapoints : array (m, n)
        Start, via points and goal, one row per point (rad or m).
    times : array (m,)
        Strictly increasing times of the points, s (``times[0]`` is the start time).
    t : None, int or array (K,)
        Sample grid on ``[times[0], times[-1]]`` (see :func:`cubic_trajectory`).
    velocities : ``"continuous"``, ``"heuristic"`` or array (m, n)
        How the via-point velocities are chosen (Lecture 3 methods 3, 2, or 1 = given,
        e.g. from Cartesian velocities through the inverse Jacobian).
    qd0, qdf : float or array (n,), optional
        Start and goal velocities (default 0); not allowed with a given velocity array,
        whose first and last rows are used instead.

    Returns
    -------
    Trajectory
        ``info``: ``"times"`` (m,), ``"velocities"`` (m, n), ``"coefficients"``
        (m−1, 4, n) ascending in local time ``t − times[k]``, ``"via_times"``,
        ``"via_points"`` (for plotting).

    Examples
    --------
    >>> tr = cubic_via_trajectory([[0.0], [1.0], [3.0]], [0.0, 1.0, 2.0], t=5)
    >>> tr.info["velocities"][:, 0].tolist()      # 8 v1 = 6·1 + 6·2
    [0.0, 2.25, 0.0]
    """
    P = viapoint_matrix(viapoints, "viapoints")
    m, n = P.shape
    T = increasing_times(times, "times", m)
    if isinstance(velocities, str):
        if velocities not in ("heuristic", "continuous"):  # via_point_velocities would name its own 'method'
            raise InputError(f"velocities: expected 'continuous', 'heuristic' or an array of shape ({m}, {n}), "
                             f"got {velocities!r}")
        V = via_point_velocities(P, T, velocities, qd0, qdf)
    else:
        if qd0 is not None or qdf is not None:
            raise InputError("qd0/qdf: not used when velocities is an array (its first and last rows are the end velocities)")
        from robokit._arrays import as_array

        V = as_array(velocities, "velocities", (m, n)).copy()
    h = np.diff(T)
    coeffs = np.empty((m - 1, 4, n))
    for k in range(m - 1):
        d = P[k + 1] - P[k]
        coeffs[k, 0] = P[k]
        coeffs[k, 1] = V[k]
        coeffs[k, 2] = (3.0 * d - (2.0 * V[k] + V[k + 1]) * h[k]) / h[k] ** 2
        coeffs[k, 3] = (-2.0 * d + (V[k] + V[k + 1]) * h[k]) / h[k] ** 3
    ts = sample_times(t, float(T[0]), float(T[-1]))
    q, qd, qdd = eval_piecewise(T, coeffs, ts)
    info = {"times": T, "velocities": V, "coefficients": coeffs, "via_times": T, "via_points": P}
    return Trajectory(ts, q, qd, qdd, name="cubic_via", info=info)
