r"""``ms_trajectory``: multi-segment, multi-axis linear motion with polynomial blends.

The seed library's function (seed 004 §5 "多段抛物线混合轨迹"), with the argument set and
meaning of Corke's ``mstraj`` (Robotics Toolbox for Python), and the same number of
samples for the same inputs.

The axes move together along straight lines between consecutive points; all axes arrive
at each via point at the same time. Around each via point the two lines are joined by a
blend of duration ``tacc`` centred on the via-point time, so the via point itself is
*approached, not passed* (Lecture 3). As in ``mstraj`` the blend is the quintic with the
velocities of the two lines at its ends and zero end accelerations, so position,
velocity and acceleration are continuous.

Timing (all times are rounded up to whole steps ``dt``, as ``mstraj`` does):

* ``tacc`` → ``ceil(tacc/dt)·dt``; the half blend ``tacc2 = ceil(tacc/2/dt)·dt``;
  the first segment starts with a half blend, later ones with a full blend.
* segment duration: ``tsegment[i]``, or, from ``qdmax``, the slowest axis
  ``max_j(blend + ceil(|Δq_j|/qdmax_j/dt)·dt)``, at least ``2·tacc``.

The output's first sample is one step ``dt`` after the start point (the start is where
the robot already is and is not repeated), the last sample is the final point, and
``t = dt·[0, 1, …, K−1]``, as in ``mstraj``.
"""
from __future__ import annotations

import math
from typing import Any

import numpy as np
from numpy.typing import ArrayLike

from robokit._arrays import as_array, as_scalar
from robokit.trajectory.core import MAX_SAMPLES, Trajectory, as_axes, viapoint_matrix
from robokit.errors import InputError, InputTypeError

__all__ = ["ms_trajectory", "ms_lspb_trajectory"]


def _quintic_blend(p0: np.ndarray, p1: np.ndarray, v0: np.ndarray, v1: np.ndarray, T: float, tau: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Quintic from (p0, v0) to (p1, v1) over [0, T] with zero end accelerations, at times tau.

    Returns q, qd, qdd, each (len(tau), n).
    """
    d = p1 - p0
    a3 = (20.0 * d - (8.0 * v1 + 12.0 * v0) * T) / (2.0 * T**3)
    a4 = (-30.0 * d + (14.0 * v1 + 16.0 * v0) * T) / (2.0 * T**4)
    a5 = (12.0 * d - 6.0 * (v1 + v0) * T) / (2.0 * T**5)
    x = tau[:, None]
    q = p0 + x * (v0 + x * x * (a3 + x * (a4 + x * a5)))
    qd = v0 + x * x * (3.0 * a3 + x * (4.0 * a4 + x * 5.0 * a5))
    qdd = x * (6.0 * a3 + x * (12.0 * a4 + x * 20.0 * a5))
    end = np.isclose(tau, T, rtol=0.0, atol=1e-12 * T)
    q[end], qd[end], qdd[end] = p1, v1, 0.0  # the blend ends exactly where the line begins
    return q, qd, qdd


def _blend(blend_from: np.ndarray, last: np.ndarray, p1: np.ndarray, v0: np.ndarray, v1: np.ndarray, nb: int,
           dt: float, segment: str, k: int, tseg: float, tacc: float, before: str) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The nb samples (at dt, 2dt, …, nb·dt) of the quintic blend from ``blend_from`` (velocity v0)
    to (p1, v1).

    The blend must start at the newest sample ``last``: when it does not, the segment before it
    (``segment``, tsegment[k] = tseg, blend time tacc) had no linear part and InputError says so.
    """
    if nb > 1 and not np.array_equal(blend_from, last):
        raise InputError(
            f"tsegment: {segment} (tsegment[{k}] = {tseg:g} s) is too short for its blends "
            f"(tacc = {tacc:g} s at dt = {dt:g} s): it has no linear part before the {before} blend"
        )
    tau: np.ndarray = np.arange(1, nb + 1) * dt
    return _quintic_blend(blend_from, p1, v0, v1, nb * dt, tau)


def _emit(chunks: tuple[list, list, list, list], q: np.ndarray, qd: np.ndarray, qdd: np.ndarray, in_blend: bool) -> int:
    """Append one run of samples to ``chunks`` = (q, q̇, q̈, in-blend flag) lists; return its length."""
    for chunk, x in zip(chunks, (q, qd, qdd, np.full(q.shape[0], in_blend))):
        chunk.append(x)
    return q.shape[0]


def _per_axis(x: ArrayLike, name: str, n: int, *, allow_scalar: bool = True) -> np.ndarray:
    arr = as_array(x, name)
    if arr.ndim == 0 and allow_scalar:
        return np.full(n, float(arr))
    if arr.ndim != 1 or arr.shape[0] != n:
        raise InputError(f"{name}: expected a number or {n} values (one per axis), got shape {arr.shape}")
    return arr.copy()


def _empty(x: Any) -> bool:
    """The seed's idiom ``qdmax=[]``: an empty list/array means "not given"."""
    return x is not None and not isinstance(x, str) and np.size(x) == 0


def ms_trajectory(viapoint: ArrayLike | None = None, dt: float | None = None, tacc: ArrayLike | None = None, qdmax: ArrayLike | None = None, tsegment: ArrayLike | None = None, q0: ArrayLike | None = None, qd0: ArrayLike | None = None, qdf: ArrayLike | None = None,
                  verbose: bool = False, *, viapoints: ArrayLike | None = None) -> Trajectory:
    """Multi-segment multi-axis trajectory with blends (seed 004 §5; Corke's ``mstraj``).

    Parameters
    ----------
    viapoint : array (M, n)
        Points, one row per point, one column per axis (rad or m). The last row is the goal.
        Without ``q0`` the first row is the start and the motion has M−1 segments;
        with ``q0`` every row is a target and there are M segments.
    dt : float
        Sample time step, s (> 0).
    tacc : float or array (segments,)
        Blend (acceleration) time, s (≥ 0); an array gives one per segment (``tacc[i]``
        is the blend at the start of segment i). 0 gives straight lines with corners.
    qdmax : float or array (n,), optional
        Maximum speed per axis (> 0); each segment's duration is set by its slowest axis.
        An empty list ``[]`` means "not given" (the seed's idiom, ``mstraj(p, [], tseg, …)``).
    tsegment : array (segments,), optional
        Duration of each segment, s (> 0). Exactly one of ``qdmax`` / ``tsegment`` (``[]`` = not given).
    q0 : array (n,), optional
        Start position; default the first row of ``viapoint``.
    qd0, qdf : array (n,), optional
        Start and final velocities (default 0).
    verbose : bool
        Print the timing of each segment.
    viapoints : array (M, n), keyword only
        Alias of ``viapoint`` (the seed's spelling); give one of the two.

    Returns
    -------
    Trajectory
        ``t`` (K,) = ``dt·arange(K)``, ``q``, ``qd``, ``qdd`` (K, n) (velocity and
        acceleration are the analytic derivatives of the lines and blends). ``info``:
        ``"segment_times"`` (segments,), ``"slowest"`` (axis that set each duration, or −1),
        ``"arrive"`` (planned arrival times as ``mstraj`` reports them), ``"via"`` (the
        target rows), ``"via_points"`` (start and targets) and ``"via_times"`` (when the
        straight lines pass through them, on the ``t`` axis), ``"tacc"`` (blend times after
        rounding), ``"in_blend"`` (K,) bool: the sample lies in a blend, not on a line.

        As in ``mstraj``, ``qdmax`` limits the straight parts; a blend can be faster (the
        first half blend starts at ``qd0`` and must still meet the line on time).

    Raises
    ------
    ValueError
        Both or neither of ``qdmax``/``tsegment``; wrong lengths; ``dt ≤ 0``; ``tacc < 0``;
        a non-positive segment time or speed; or a ``tsegment`` so short that a segment has
        no linear part before a blend longer than one step (``mstraj`` would then start
        the blend from a stale point and jump).

    Examples
    --------
    >>> tr = ms_trajectory([[0.0], [1.0], [3.0]], dt=0.1, tacc=0.2, tsegment=[1.0, 1.0])
    >>> len(tr), round(float(tr.q[-1, 0]), 12)
    (20, 3.0)
    """
    if viapoints is not None:
        if viapoint is not None:
            raise InputTypeError("viapoint, viapoints: give one of them (viapoints is an alias of viapoint)")
        viapoint = viapoints
    for name, value in (("viapoint", viapoint), ("dt", dt), ("tacc", tacc)):
        if value is None:
            raise InputTypeError(f"ms_trajectory: missing the argument {name!r}")
    qdmax = None if _empty(qdmax) else qdmax
    tsegment = None if _empty(tsegment) else tsegment
    if (qdmax is None) == (tsegment is None):
        raise InputError(
            "qdmax/tsegment: give exactly one of them (qdmax = speed limit per axis, or tsegment = "
            f"duration of each segment); got {'both' if qdmax is not None else 'neither'}"
        )
    W = as_array(viapoint, "viapoint")
    if W.ndim != 2 or W.shape[1] < 1:
        raise InputError(
            f"viapoint: expected a 2-D array, one row per point and one column per axis, got shape {W.shape}"
            + (" (for a single axis use np.reshape(viapoint, (-1, 1)))" if W.ndim == 1 else "")
        )
    n = W.shape[1]
    if q0 is None:
        if W.shape[0] < 2:
            raise InputError(f"viapoint: without q0 the first row is the start, so at least 2 rows are needed, got {W.shape[0]}")
        start = W[0].copy()
        targets = W[1:].copy()
    else:
        start = as_axes(q0, "q0")
        if start.shape[0] != n:
            raise InputError(f"q0: expected {n} values (the number of columns of viapoint), got {start.shape[0]}")
        if W.shape[0] < 1:
            raise InputError("viapoint: needs at least one row (the goal)")
        targets = W.copy()
    ns = targets.shape[0]
    dt = as_scalar(dt, "dt")
    if not dt > 0:
        raise InputError(f"dt: the time step must be positive, got {dt!r}")
    tacc_arr = as_array(tacc, "tacc")
    if tacc_arr.ndim == 0:
        tacc_arr = np.full(ns, float(tacc_arr))
    elif tacc_arr.shape != (ns,):
        raise InputError(f"tacc: expected a number or {ns} values (one per segment), got shape {tacc_arr.shape}")
    if np.any(tacc_arr < 0):
        raise InputError(f"tacc: blend times must be non-negative, got {tacc_arr.tolist()}")
    if qdmax is not None:
        speed = _per_axis(qdmax, "qdmax", n)
        if np.any(speed <= 0):
            raise InputError(f"qdmax: speeds must be positive, got {speed.tolist()}")
        seg_given = None
    else:
        seg_given = as_array(tsegment, "tsegment")
        if seg_given.ndim != 1 or seg_given.shape[0] != ns:
            raise InputError(f"tsegment: expected {ns} segment times (one per segment), got shape {seg_given.shape}")
        if np.any(seg_given <= 0):
            k = int(np.argmin(seg_given))
            raise InputError(f"tsegment: segment times must be positive, got tsegment[{k}] = {seg_given[k]!r}")
    v_start = np.zeros(n) if qd0 is None else _per_axis(qd0, "qd0", n, allow_scalar=False)
    v_end = np.zeros(n) if qdf is None else _per_axis(qdf, "qdf", n, allow_scalar=False)

    chunks: tuple[list, list, list, list] = ([], [], [], [])  # q, q̇, q̈, in-blend flags, one run of samples each
    count = 0  # samples emitted so far; sample i is at construction time (i+1)·dt
    seg_times, slowest_axes, arrive, via_idx = [], [], [], []
    q_prev = start
    qd_prev = v_start
    blend_from = start  # where the next blend starts: the last linear sample (mstraj's rule)
    last = start  # the newest sample (the start before any is emitted)
    clock = 0.0
    tacc2 = 0.0
    for seg in range(ns):
        q_next = targets[seg]
        ta = math.ceil(tacc_arr[seg] / dt) * dt
        tacc2 = math.ceil(ta / 2 / dt) * dt
        taccx = tacc2 if seg == 0 else ta
        dq = q_next - q_prev
        if seg_given is None:
            tl = np.ceil(np.abs(dq) / speed / dt) * dt
            tt = taccx + tl
            slowest = int(np.argmax(tt))
            tseg = float(tt[slowest])
            if tseg <= 2 * ta:
                tseg = 2 * ta
        else:
            tseg = float(seg_given[seg])
            slowest = -1
        if tseg <= 0:  # only with qdmax, tacc = 0 and a repeated point: nothing to do
            tseg = 0.0
        if count + (taccx + tseg + tacc2) / dt > MAX_SAMPLES:  # before any of this segment's samples is made
            given = "qdmax" if seg_given is None else "tsegment"
            raise InputError(f"dt/{given}: the trajectory would have more than {MAX_SAMPLES} samples (segment {seg} "
                             f"lasts {tseg:g} s, sampled every {dt:g} s); robokit makes at most {MAX_SAMPLES}: "
                             f"raise dt or shorten the motion")
        seg_times.append(tseg)
        slowest_axes.append(slowest)
        arrive.append(clock + tseg + (tacc2 if seg > 0 else 0.0))
        qd = dq / tseg if tseg > 0 else np.zeros(n)
        if verbose:
            print(f"ms_trajectory segment {seg}: {q_prev} -> {q_next}, tseg {tseg:g} s, tacc {ta:g} s, slowest axis {slowest}")

        nb = round(taccx / dt) if taccx > 0 else 0
        if nb > 0:
            # (seg ≥ 1 here whenever the check can fail: at seg 0 the blend starts at the start)
            blend = _blend(blend_from, last, q_prev + tacc2 * qd, qd_prev, qd, nb, dt,
                           f"segment {seg - 1}", seg - 1, seg_times[seg - 1], tacc_arr[seg - 1], "next")
            count += _emit(chunks, *blend, True)
            last = blend[0][-1]
        clock += taccx
        # segment-local time 0 (the line through q_prev) is round(tacc2/dt) samples before
        # the end of this blend
        via_idx.append(count - round(tacc2 / dt))

        i0 = round((tacc2 + dt) / dt)
        i1 = round((tseg - tacc2) / dt)
        if i1 >= i0:
            tl_s = np.arange(i0, i1 + 1) * dt
            s = tl_s / tseg
            ql = (1.0 - s)[:, None] * q_prev + s[:, None] * q_next
            count += _emit(chunks, ql, np.tile(qd, (ql.shape[0], 1)), np.zeros_like(ql), False)
            clock += ql.shape[0] * dt
            blend_from = ql[-1]
            last = ql[-1]
        q_prev = q_next
        qd_prev = qd

    nb = round(tacc2 / dt) if tacc2 > 0 else 0
    if nb > 0:
        count += _emit(chunks, *_blend(blend_from, last, q_prev, qd_prev, v_end, nb, dt,
                                       "the last segment", ns - 1, seg_times[-1], tacc_arr[-1], "final"), True)
    if count == 0:
        raise InputError("viapoint: the motion has no samples (every segment has zero length and tacc = 0)")
    q, qdv, qddv = (np.vstack(c) for c in chunks[:3])
    t = dt * np.arange(q.shape[0])
    # via-point times on the t axis: sample i is at construction time (i+1)·dt, i.e. t = i·dt
    origin = [(k - 1) * dt for k in via_idx]  # t of the line's q_prev (segment-local time 0)
    via_times = np.array([origin[0]] + [origin[k] + seg_times[k] for k in range(ns)])
    info = {
        "segment_times": np.array(seg_times),
        "slowest": np.array(slowest_axes),
        "arrive": np.array(arrive),
        "via": targets,
        "via_points": np.vstack([start, targets]),
        "via_times": via_times,
        "tacc": np.array([math.ceil(x / dt) * dt for x in tacc_arr]),
        "dt": dt,
        "in_blend": np.concatenate(chunks[3]),
    }
    return Trajectory(t, q, qdv, qddv, name="ms_trajectory", info=info)


def ms_lspb_trajectory(viapoint: ArrayLike, dt: float, tacc: float, qdmax: ArrayLike | None = None,
                       tsegment: ArrayLike | None = None) -> Trajectory:
    r"""The plain multi-segment trajectory a student expects from :func:`ms_trajectory`'s arguments.

    Straight lines at constant speed between consecutive via points (all axes arrive together),
    joined around each via point by a **parabolic** blend of duration ``tacc`` (constant
    acceleration), starting and ending at rest — the lecture's linear segments with parabolic
    blends (LSPB) through via points, with the blend time given instead of the acceleration. It
    differs from Corke's ``mstraj`` (:func:`ms_trajectory`, kept as it is) in the three places
    that surprise a reader of ``mstraj``'s output:

    * the first sample is the start point at ``t = 0`` (``mstraj`` begins one step later, and its
      time axis then puts the start at ``t = −dt``);
    * no axis is ever faster than ``qdmax``: with a parabolic blend the velocity goes linearly
      from one line's to the next, so it stays between them (``mstraj``'s quintic blends, and its
      first half blend that must meet the line on time from rest, go above ``qdmax``);
    * each segment lasts ``max(tacc, max_j |Δq_j| / qdmax_j)``: its slowest axis at exactly
      ``qdmax`` (``mstraj`` counts the blend into the segment time, so its lines run slower).

    With via points :math:`P_0, …, P_{M-1}`, segment times :math:`T_k` and line velocities
    :math:`V_k = (P_{k+1} - P_k)/T_k`, the line of segment k passes :math:`P_k` at
    :math:`\tau_k = t_{acc}/2 + \sum_{i<k} T_i`; the blend around :math:`P_k` lasts
    :math:`[\tau_k - t_{acc}/2, \tau_k + t_{acc}/2]` with acceleration
    :math:`(V_k - V_{k-1})/t_{acc}` (:math:`V_{-1} = V_{M-1} = 0`): it starts exactly at
    :math:`P_0` at :math:`t = 0` and ends exactly at :math:`P_{M-1}` at rest at
    :math:`\tau_{M-1} + t_{acc}/2`. Interior via points are approached, not passed (the blend
    cuts the corner by :math:`|V_k - V_{k-1}|\, t_{acc}/8`).

    Parameters
    ----------
    viapoint : array (M, n), M ≥ 2
        Start, via points and goal, one row per point (rad or m); a 1-D list is one axis.
    dt : float
        Sample step, s (> 0); the samples are ``0, dt, 2dt, …`` and the end time.
    tacc : float
        Blend time, s (≥ 0; 0 gives straight lines with corners).
    qdmax : float or array (n,), optional
        Speed limit per axis (> 0): each segment as fast as its slowest axis allows.
    tsegment : array (M−1,), optional
        Segment durations :math:`T_k`, s (each ≥ ``tacc``). Exactly one of ``qdmax``/``tsegment``.

    Returns
    -------
    Trajectory
        ``t`` from 0 to the end time, ``q``, ``qd``, ``qdd`` (exact). ``info``:
        ``"segment_times"`` :math:`T_k`, ``"line_times"`` :math:`\tau_k`, ``"velocities"``
        :math:`V_k` (M−1, n), ``"via_points"``, ``"via_times"`` (0, the interior
        :math:`\tau_k`, the end time), ``"tacc"``, ``"in_blend"`` (K,) bool.

    Raises
    ------
    InputError
        Both or neither of ``qdmax``/``tsegment``; a non-positive speed, ``dt`` or segment time;
        ``tacc < 0``; a segment shorter than ``tacc`` (its two blends would overlap).

    Examples
    --------
    The README's ``mstraj`` sample, plainly: the start at t = 0, never faster than 0.5:

    >>> tr = ms_lspb_trajectory([[0, 0], [1, 0], [1, 1]], dt=0.05, tacc=0.5, qdmax=0.5)
    >>> float(tr.t[0]), tr.q[0].tolist(), tr.q[-1].tolist(), float(abs(tr.qd).max())
    (0.0, [0.0, 0.0], [1.0, 1.0], 0.5)
    >>> tr.info["segment_times"].tolist(), tr.info["via_times"].tolist()
    ([2.0, 2.0], [0.0, 2.25, 4.5])
    """
    P = viapoint_matrix(viapoint, "viapoint")
    M, n = P.shape
    dt = as_scalar(dt, "dt", positive=True)
    tacc = as_scalar(tacc, "tacc", nonnegative=True)
    qdmax = None if _empty(qdmax) else qdmax
    tsegment = None if _empty(tsegment) else tsegment
    if (qdmax is None) == (tsegment is None):
        raise InputError("qdmax/tsegment: give exactly one of them (qdmax = speed limit per axis, or tsegment = "
                         f"duration of each segment); got {'both' if qdmax is not None else 'neither'}")
    D = np.diff(P, axis=0)
    if qdmax is not None:
        speed = _per_axis(qdmax, "qdmax", n)
        if np.any(speed <= 0):
            raise InputError(f"qdmax: speeds must be positive, got {speed.tolist()}")
        T = np.maximum(tacc, (np.abs(D) / speed).max(axis=1))
    else:
        T = as_array(tsegment, "tsegment", (M - 1,))
        if np.any(T <= 0):
            k = int(np.argmin(T))
            raise InputError(f"tsegment: segment times must be positive, got tsegment[{k}] = {T[k]!r}")
        if np.any(T < tacc * (1 - 1e-12)):
            k = int(np.argmin(T - tacc))
            raise InputError(f"tsegment: segment {k} lasts {T[k]:g} s, less than the blend time tacc = {tacc:g} s "
                             "(its blends would overlap)")
    V = np.divide(D, T[:, None], out=np.zeros_like(D), where=T[:, None] > 0)
    tau = 0.5 * tacc + np.concatenate([[0.0], np.cumsum(T)])  # when the lines pass the via points
    end = float(tau[-1] + 0.5 * tacc)
    if not end > 0:
        raise InputError("viapoint: the motion has no duration (every segment has zero length and tacc = 0)")
    if end / dt > MAX_SAMPLES:
        given = "qdmax" if qdmax is not None else "tsegment"
        raise InputError(f"dt/{given}: the trajectory would have more than {MAX_SAMPLES} samples ({end:g} s sampled "
                         f"every {dt:g} s); robokit makes at most {MAX_SAMPLES}: raise dt or shorten the motion")
    K = int(math.floor(end / dt * (1 + 1e-12))) + 1
    t = dt * np.arange(K)
    if end - t[-1] > 1e-9 * end:
        t = np.append(t, end)
    t[-1] = end
    Vin = np.vstack([np.zeros(n), V])  # velocity before via point k
    Vout = np.vstack([V, np.zeros(n)])  # and after it
    # the segment a sample lies in: its last via point k with τ_k − tacc/2 ≤ t, on the line or in that blend
    seg = np.clip(np.searchsorted(tau - 0.5 * tacc, t, side="right") - 1, 0, M - 1)
    s = t - tau[seg]  # time since the line of segment k (or, before it, of segment k−1) passed P_k
    in_blend = s < 0.5 * tacc
    q = P[seg] + np.where(in_blend[:, None], Vin[seg], Vout[seg]) * s[:, None]
    qd = np.where(in_blend[:, None], Vin[seg], Vout[seg])
    qdd = np.zeros_like(q)
    if tacc > 0:
        u = (s + 0.5 * tacc)[in_blend][:, None]  # time into the blend
        dv = (Vout[seg] - Vin[seg])[in_blend]
        frac = u / tacc  # in [0, 1]: no overflow for a tiny tacc
        q[in_blend] += 0.5 * dv * frac * u
        qd[in_blend] += dv * frac
        with np.errstate(over="ignore"):
            qdd[in_blend] = dv / tacc
    q[0], q[-1] = P[0], P[-1]  # exactly
    if tacc > 0:
        qd[[0, -1]] = 0.0  # from rest, to rest (exactly, whatever the rounding of the end time)
    info = {
        "segment_times": T,
        "line_times": tau,
        "velocities": V,
        "via_points": P,
        "via_times": np.concatenate([[0.0], tau[1:-1], [end]]),
        "tacc": tacc,
        "in_blend": in_blend,
    }
    return Trajectory(t, q, qd, qdd, name="ms_lspb", info=info)
