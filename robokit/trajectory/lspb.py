r"""Linear segments with parabolic blends (LSPB, trapezoidal velocity), Lecture 3.

Single segment from θ0 to θf in time t_f, blends of equal duration t_b and equal
acceleration magnitude θ̈ at both ends, symmetric about (t_f/2, (θ0+θf)/2)::

    θ̈ t_b = (θ_h − θ_b)/(t_h − t_b),   θ_b = θ0 + ½ θ̈ t_b²,   t_f = 2 t_h
    ⇒ θ̈ t_b² − θ̈ t_f t_b + (θf − θ0) = 0,
      t_b = t_f/2 − √(θ̈² t_f² − 4 θ̈ (θf − θ0)) / (2θ̈),
    feasible only if |θ̈| ≥ 4|θf − θ0| / t_f²  (equality: no linear segment).

The linear segment's velocity is V = (θf − θ0)/(t_f − t_b) and V = θ̈ t_b. Given the
blend time instead, 0 < t_b ≤ t_f/2; given the peak velocity, |θf − θ0|/t_f < |V| ≤
2|θf − θ0|/t_f.

Several segments through via points (the lecture's scheme, Craig §7.3): given the
points θ_k, the durations t_{d,jk} between them and the blend acceleration magnitude,
interior blends are centred on the via-point times (so interior via points are approached
but not passed), the first and last blends lie wholly inside their segments::

    θ̇_jk = (θ_k − θ_j)/t_djk,   θ̈_k = SGN(θ̇_kl − θ̇_jk)|θ̈_k|,   t_k = (θ̇_kl − θ̇_jk)/θ̈_k,
    t_jk = t_djk − ½t_j − ½t_k
    first:  θ̈_1 = SGN(θ_2 − θ_1)|θ̈_1|,  t_1 = t_d12 − √(t_d12² − 2(θ_2 − θ_1)/θ̈_1),
            θ̇_12 = (θ_2 − θ_1)/(t_d12 − ½t_1),  t_12 = t_d12 − t_1 − ½t_2
    last:   θ̈_n = SGN(θ_{n−1} − θ_n)|θ̈_n|,  t_n = t_d(n−1)n − √(t_d(n−1)n² + 2(θ_n − θ_{n−1})/θ̈_n),
            θ̇_(n−1)n = (θ_n − θ_{n−1})/(t_d(n−1)n − ½t_n),  t_(n−1)n = t_d(n−1)n − t_n − ½t_{n−1}
"""
from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike

from robokit._arrays import as_scalar
from robokit.trajectory.core import (
    Trajectory,
    as_axes,
    eval_piecewise,
    positive_duration,
    sample_times,
    viapoint_matrix,
)
from robokit.errors import InputError

__all__ = ["lspb_trajectory", "lspb_via_trajectory"]

_REL = 1e-12  # relative slack for the feasibility equalities (triangular profile allowed)


def _axis_pieces(breaks: list[float], coeffs: list[list[float]]) -> tuple[np.ndarray, np.ndarray]:
    """Drop zero-length pieces; return arrays for eval_piecewise (one axis)."""
    b = [breaks[0]]
    c = []
    for k, ck in enumerate(coeffs):
        if breaks[k + 1] > breaks[k]:
            b.append(breaks[k + 1])
            c.append(ck)
    if not c:  # everything degenerate: a constant
        b.append(breaks[-1] if breaks[-1] > breaks[0] else breaks[0] + 1.0)
        c.append(coeffs[0])
    return np.array(b), np.array(c)[:, :, None]


def _sample_axes(pieces: list[tuple[np.ndarray, np.ndarray]], ts: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    n = len(pieces)
    q = np.empty((ts.size, n))
    qd = np.empty_like(q)
    qdd = np.empty_like(q)
    for j, (b, c) in enumerate(pieces):
        q[:, j : j + 1], qd[:, j : j + 1], qdd[:, j : j + 1] = eval_piecewise(b, c, ts)
    return q, qd, qdd


def lspb_trajectory(q0: ArrayLike, qf: ArrayLike, tf: float, t: ArrayLike | None = None, *, blend_time: ArrayLike | None = None, acceleration: ArrayLike | None = None, max_velocity: ArrayLike | None = None) -> Trajectory:
    """A trapezoidal-velocity (LSPB) move from ``q0`` to ``qf`` in ``tf`` seconds (Lecture 3).

    Give at most one of ``blend_time``, ``acceleration`` or ``max_velocity``; with none,
    the peak velocity is 1.5 × the mean velocity (``t_b = t_f/3``). Each axis is planned
    independently with the same duration.

    Parameters
    ----------
    q0, qf, tf, t
        End positions θ0, θf, duration t_f and sample grid (see :mod:`robokit.trajectory.core`).
    blend_time : float, optional
        Blend duration t_b, the same for all axes, with 0 < t_b ≤ t_f/2.
    acceleration : float or array (n,), optional
        Blend acceleration magnitude |θ̈| > 0 per axis; must satisfy
        |θ̈| ≥ 4|θf − θ0|/t_f², else ``ValueError`` with the smallest feasible value.
    max_velocity : float or array (n,), optional
        Peak (linear-segment) speed |V| per axis, |θf − θ0|/t_f < |V| ≤ 2|θf − θ0|/t_f.

    Returns
    -------
    Trajectory
        ``info``: ``"blend_time"`` (n,), ``"velocity"`` (n,) signed peak velocity,
        ``"acceleration"`` (n,) signed acceleration of the first blend.

    Examples
    --------
    >>> tr = lspb_trajectory(0.0, 1.0, 2.0, t=5, max_velocity=0.75)   # t_b = 2 − 1/0.75
    >>> round(float(tr.info["blend_time"][0]), 12), float(tr.qd[:, 0].max())
    (0.666666666667, 0.75)
    """
    a0 = as_axes(q0, "q0")
    n = a0.shape[0]
    af = as_axes(qf, "qf", n)
    T = positive_duration(tf, "tf")
    given = [k for k, v in (("blend_time", blend_time), ("acceleration", acceleration), ("max_velocity", max_velocity)) if v is not None]
    if len(given) > 1:
        raise InputError(f"lspb_trajectory: give at most one of blend_time, acceleration, max_velocity; got {', '.join(given)}")
    d = af - a0
    ad = np.abs(d)
    sgn = np.sign(d)
    if blend_time is not None:
        tb_all = as_scalar(blend_time, "blend_time")
        if not 0.0 < tb_all <= 0.5 * T * (1.0 + _REL):
            raise InputError(f"blend_time: must satisfy 0 < t_b <= tf/2 = {0.5 * T:g} s, got {tb_all!r}")
        tb = np.full(n, min(tb_all, 0.5 * T))
        speed = ad / (T - tb)
    elif acceleration is not None:
        acc = as_axes(acceleration, "acceleration", n)
        if np.any(acc <= 0):
            raise InputError(f"acceleration: magnitudes must be positive, got {acc.tolist()}")
        need = 4.0 * ad / T**2
        bad = acc < need * (1.0 - _REL)
        if np.any(bad):
            j = int(np.argmax(bad))
            raise InputError(
                f"acceleration: too small for axis {j}: |θ̈| = {acc[j]:g} but moving {ad[j]:g} in {T:g} s "
                f"needs |θ̈| >= 4|θf − θ0|/tf² = {need[j]:g}"
            )
        disc = np.maximum(T * T - 4.0 * ad / acc, 0.0)
        tb = 2.0 * ad / (acc * (T + np.sqrt(disc)))  # = T/2 − √(θ̈²T² − 4θ̈|Δ|)/(2θ̈), stable form
        speed = acc * tb
    else:
        if max_velocity is not None:
            speed = as_axes(max_velocity, "max_velocity", n)
            speed = np.abs(speed)
            lo, hi = ad / T, 2.0 * ad / T
            bad = (ad > 0) & ((speed <= lo) | (speed > hi * (1.0 + _REL)))
            if np.any(bad):
                j = int(np.argmax(bad))
                raise InputError(
                    f"max_velocity: for axis {j} (moving {ad[j]:g} in {T:g} s) the peak speed must satisfy "
                    f"{lo[j]:g} < |V| <= {hi[j]:g}, got {speed[j]:g}"
                )
            speed = np.minimum(speed, hi)
        else:
            speed = 1.5 * ad / T
        with np.errstate(divide="ignore", invalid="ignore"):
            tb = np.where(ad > 0, T - ad / np.where(speed > 0, speed, 1.0), 0.0)
    V = sgn * speed
    with np.errstate(divide="ignore", invalid="ignore"):
        acc_signed = np.where(tb > 0, V / np.where(tb > 0, tb, 1.0), 0.0)
    tb = np.where(ad > 0, tb, 0.0)
    pieces = []
    for j in range(n):
        a, v, b = acc_signed[j], V[j], tb[j]
        if ad[j] == 0.0:
            pieces.append(_axis_pieces([0.0, T], [[a0[j], 0.0, 0.0]]))
            continue
        q_b = a0[j] + 0.5 * a * b * b
        breaks = [0.0, b, T - b, T]
        coeffs = [[a0[j], 0.0, 0.5 * a], [q_b, v, 0.0], [af[j] - 0.5 * a * b * b, v, -0.5 * a]]
        pieces.append(_axis_pieces(breaks, coeffs))
    ts = sample_times(t, 0.0, T)
    q, qd, qdd = _sample_axes(pieces, ts)
    info = {"blend_time": tb, "velocity": V, "acceleration": acc_signed, "tf": T}
    return Trajectory(ts, q, qd, qdd, name="lspb", info=info)


def _sgn(x: float) -> float:
    return 1.0 if x > 0 else (-1.0 if x < 0 else 0.0)


def lspb_via_trajectory(viapoints: ArrayLike, durations: ArrayLike, acceleration: ArrayLike, t: ArrayLike | None = None) -> Trajectory:
    """Multi-segment LSPB through via points, the lecture's scheme (Craig §7.3), sampled.

    Interior via points are *approached, not passed*: the blend around each one is
    centred on its time, and the path cuts the corner. The start and the goal are
    reached exactly, at rest.

    Parameters
    ----------
    viapoints : array (m, n), m ≥ 2
        Start, via points and goal, one row per point.
    durations : array (m−1,)
        Durations t_d between consecutive points, s (> 0).
    acceleration : float or array (n,) or array (m, n)
        Blend acceleration magnitudes |θ̈| > 0 (per axis, or per point and axis).
    t : None, int or array (K,)
        Sample grid on ``[0, Σ durations]``.

    Returns
    -------
    Trajectory
        ``info``: ``"times"`` (m,) via-point times, ``"blend_times"`` (m, n),
        ``"accelerations"`` (m, n) signed, ``"velocities"`` (m−1, n) of the linear
        segments, ``"linear_durations"`` (m−1, n); ``"via_times"``/``"via_points"`` for plots.

    Raises ``ValueError`` when the acceleration is too small for a segment (the square
    root of the first/last-segment formula would be imaginary, or the blends overlap).

    Examples
    --------
    The lecture's worked example, in degrees:

    >>> tr = lspb_via_trajectory([[5.0], [15.0], [40.0]], [1.0, 1.0], 80.0)
    >>> tr.info["blend_times"][:, 0].round(3).tolist()
    [0.134, 0.254, 0.388]
    """
    P = viapoint_matrix(viapoints, "viapoints")
    m, n = P.shape
    from robokit._arrays import as_array

    td = as_array(durations, "durations", (m - 1,))
    if np.any(td <= 0):
        k = int(np.argmin(td))
        raise InputError(f"durations: every duration must be positive, got durations[{k}] = {td[k]!r}")
    acc_in = as_array(acceleration, "acceleration")
    if acc_in.ndim == 2:
        if acc_in.shape != (m, n):
            raise InputError(f"acceleration: expected a number, shape ({n},) or ({m}, {n}), got shape {acc_in.shape}")
        A = acc_in.copy()
    else:
        A = np.tile(as_axes(acc_in, "acceleration", n), (m, 1))
    if np.any(A <= 0):
        raise InputError("acceleration: magnitudes must be positive")
    times = np.concatenate([[0.0], np.cumsum(td)])
    tb = np.zeros((m, n))
    acc = np.zeros((m, n))
    vel = np.zeros((m - 1, n))
    lin = np.zeros((m - 1, n))
    pieces = []
    for j in range(n):
        th = P[:, j]
        if m == 2:  # one segment: the symmetric LSPB of the lecture
            d = th[1] - th[0]
            a = A[0, j]
            T = td[0]
            if abs(d) > 0 and a < 4 * abs(d) / T**2 * (1 - _REL):
                raise InputError(
                    f"acceleration: too small for axis {j}: |θ̈| = {a:g} but moving {abs(d):g} in {T:g} s "
                    f"needs |θ̈| >= 4|θf − θ0|/tf² = {4 * abs(d) / T**2:g}"
                )
            b = 2 * abs(d) / (a * (T + np.sqrt(max(T * T - 4 * abs(d) / a, 0.0)))) if d else 0.0
            tb[:, j] = b
            acc[0, j], acc[1, j] = _sgn(d) * a, -_sgn(d) * a
            vel[0, j] = acc[0, j] * b
            lin[0, j] = T - 2 * b
        else:
            # first segment
            d = th[1] - th[0]
            a1 = _sgn(d) * A[0, j]
            if a1 != 0.0:
                disc = td[0] ** 2 - 2.0 * d / a1
                if disc < -_REL * td[0] ** 2:
                    raise InputError(
                        f"acceleration: too small for the first segment of axis {j}: need |θ̈| >= "
                        f"2|θ2 − θ1|/t_d12² = {2 * abs(d) / td[0] ** 2:g}, got {A[0, j]:g}"
                    )
                tb[0, j] = td[0] - np.sqrt(max(disc, 0.0))
            acc[0, j] = a1
            vel[0, j] = d / (td[0] - 0.5 * tb[0, j])
            # last segment
            d = th[-1] - th[-2]
            an = _sgn(th[-2] - th[-1]) * A[-1, j]
            if an != 0.0:
                disc = td[-1] ** 2 + 2.0 * d / an
                if disc < -_REL * td[-1] ** 2:
                    raise InputError(
                        f"acceleration: too small for the last segment of axis {j}: need |θ̈| >= "
                        f"2|θn − θ(n−1)|/t_d² = {2 * abs(d) / td[-1] ** 2:g}, got {A[-1, j]:g}"
                    )
                tb[-1, j] = td[-1] - np.sqrt(max(disc, 0.0))
            acc[-1, j] = an
            vel[-1, j] = d / (td[-1] - 0.5 * tb[-1, j])
            # interior segments
            for k in range(1, m - 2):
                vel[k, j] = (th[k + 1] - th[k]) / td[k]
            # interior blends
            for k in range(1, m - 1):
                dv = vel[k, j] - vel[k - 1, j]
                acc[k, j] = _sgn(dv) * A[k, j]
                tb[k, j] = dv / acc[k, j] if acc[k, j] != 0.0 else 0.0
            # linear durations
            for k in range(m - 1):
                first = tb[k, j] if k == 0 else 0.5 * tb[k, j]
                last = tb[k + 1, j] if k == m - 2 else 0.5 * tb[k + 1, j]
                lin[k, j] = td[k] - first - last
            if np.any(lin[:, j] < -_REL * td.max()):
                k = int(np.argmin(lin[:, j]))
                raise InputError(
                    f"acceleration: too small for axis {j}: the blends around segment {k} overlap "
                    f"(linear part {lin[k, j]:g} s < 0); increase the acceleration or the durations"
                )
        pieces.append(_via_pieces(th, times, tb[:, j], acc[:, j], vel[:, j]))
    ts = sample_times(t, 0.0, float(times[-1]))
    q, qd, qdd = _sample_axes(pieces, ts)
    info = {
        "times": times,
        "blend_times": tb,
        "accelerations": acc,
        "velocities": vel,
        "linear_durations": np.maximum(lin, 0.0),
        "via_times": times,
        "via_points": P,
    }
    return Trajectory(ts, q, qd, qdd, name="lspb_via", info=info)


def _via_pieces(th: np.ndarray, times: np.ndarray, tb: np.ndarray, acc: np.ndarray, vel: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Pieces (breaks, coefficients) of one axis of the multi-segment LSPB."""
    m = th.shape[0]

    def line(k: int, tt: float) -> float:  # position of the linear segment k (k → k+1) at time tt
        if k == 0 and m > 2:
            return th[1] + vel[0] * (tt - times[1])  # the first line passes θ2 at T2
        if k == 0:
            return th[0] + 0.5 * acc[0] * tb[0] ** 2 + vel[0] * (tt - tb[0])
        return th[k] + vel[k] * (tt - times[k])

    breaks = [0.0]
    coeffs = []
    # first blend: from rest at θ1
    breaks.append(tb[0])
    coeffs.append([th[0], 0.0, 0.5 * acc[0]])
    for k in range(m - 1):
        start = tb[0] if k == 0 else times[k] + 0.5 * tb[k]
        end = times[-1] - tb[-1] if k == m - 2 else times[k + 1] - 0.5 * tb[k + 1]
        breaks.append(end)
        coeffs.append([line(k, start), vel[k], 0.0])
        if k < m - 2:  # interior blend around via point k+1
            b0 = times[k + 1] - 0.5 * tb[k + 1]
            breaks.append(times[k + 1] + 0.5 * tb[k + 1])
            coeffs.append([line(k, b0), vel[k], 0.5 * acc[k + 1]])
    # last blend: to rest at θn
    b0 = times[-1] - tb[-1]
    breaks.append(times[-1])
    coeffs.append([line(m - 2, b0), vel[-1], 0.5 * acc[-1]])
    return _axis_pieces(breaks, coeffs)
