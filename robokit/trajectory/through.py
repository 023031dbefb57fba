r"""Through points and multi-segment Cartesian paths with blends (Lecture 3).

**Through points.** With blends the multi-segment trajectory approaches a via point but does not
pass it (Lecture 3). To make the path go *exactly through* a point P, the lecture adds two pseudo via
points, one on each side of P:

    P⁻ = P − d·û,   P⁺ = P + d·û,

with û the unit bisector of the incoming and outgoing directions (the incoming direction when the
path turns back on itself) and d a distance (axis units). The straight segment P⁻ → P⁺ passes P at
its middle, so P lies on a linear part of the trajectory as long as the blends at P⁻ and P⁺ do not
reach the middle of that segment (``tacc`` shorter than the segment). :func:`through_viapoints`
builds the augmented via-point list; :func:`ms_through_trajectory` runs :func:`ms_trajectory` on
it (with ``tsegment``, each original segment's time is split in proportion to the distances).

**Cartesian paths.** :func:`ms_cartesian_trajectory` moves the tool through a list of poses
``T₀, T₁, …`` on straight lines in position and on geodesics in orientation, with blends at the
via poses, timed like :func:`ms_trajectory` (linear segments with blends, i.e. LSPB-timed). Each
segment i has the relative rotation ``R_iᵀ R_{i+1} = exp([k̂ᵢ] θᵢ)``; a progress variable sᵢ goes
from 0 to 1 over segment i, and the axes ``(p, s₀, s₁, …)`` are sent through :func:`ms_trajectory`
together (so all arrive at each via pose together and are blended over the same interval). The
orientation is

    R(t) = R₀ exp([k̂₀] θ₀ s₀(t)) exp([k̂₁] θ₁ s₁(t)) ⋯

On the linear part of segment i this is ``R_i exp([k̂ᵢ] θᵢ sᵢ)`` — a rotation about a fixed axis
(slerp); inside a blend two consecutive rotations progress at once, so the angular velocity
changes smoothly from one axis to the next. The speed limits are ``speed`` (m/s per position axis,
as ``qdmax``) and ``angular_speed`` (rad/s about the segment's axis: ``ṡᵢ ≤ angular_speed / θᵢ``).
"""
from __future__ import annotations

from typing import Any, Sequence

import numpy as np
from numpy.typing import ArrayLike

from robokit._arrays import as_array, as_scalar
from robokit.spatial.se3 import check_transform
from robokit.trajectory.core import Trajectory
from robokit.trajectory.multisegment import _empty, ms_trajectory
from robokit.spatial import lie
from robokit.errors import InputError

__all__ = ["through_viapoints", "ms_through_trajectory", "ms_cartesian_trajectory"]


def through_viapoints(viapoint: ArrayLike, through: Sequence[int] | None = None, distance: float = 0.25) -> tuple[np.ndarray, list[tuple[float, ...]]]:
    """Via points with every through point replaced by the two pseudo via points around it.

    The pseudo points are ``P ∓ d û``, û the unit bisector of the incoming and outgoing
    directions (module docstring, Lecture 3).

    Parameters
    ----------
    viapoint : array_like, shape (M, n)
        Points (first row the start, last the goal), axis units (rad or m).
    through : sequence of int, optional
        Indices of the interior rows the path must pass exactly (default all interior rows
        1 … M−2).
    distance : float, optional
        d > 0: below 1 a fraction of the shorter of the two segments next to the point (default
        0.25); from 1 up an absolute distance in axis units.

    Returns
    -------
    points : numpy.ndarray, shape (M + len(through), n)
        The augmented via points.
    fractions : list of tuple of float
        Per original segment, ``(f_start, f_end)``: the fractions of its length cut off at its
        start and at its end by pseudo points (used to split segment times).

    Examples
    --------
    The corner (1, 0) is replaced by ``(1, 0) ∓ 0.2 (1, 1)/√2``:

    >>> points, fractions = through_viapoints([[0, 0], [1, 0], [1, 1]], [1], 0.2)
    >>> points.round(4).tolist()
    [[0.0, 0.0], [0.8586, -0.1414], [1.1414, 0.1414], [1.0, 1.0]]
    """
    W = as_array(viapoint, "viapoint")
    if W.ndim != 2 or W.shape[0] < 3:
        raise InputError(f"viapoint: expected an (M, n) array with M ≥ 3 (a start, interior points, a goal), "
                         f"got shape {W.shape}")
    M = W.shape[0]
    idx = list(range(1, M - 1)) if through is None else sorted({int(i) for i in np.atleast_1d(through)})
    for i in idx:
        if not 0 < i < M - 1:
            raise InputError(f"through: index {i} is not an interior via point (1 … {M - 2})")
    d = as_scalar(distance, "distance", positive=True)
    frac = [[0.0, 0.0] for _ in range(M - 1)]
    out = [W[0]]
    for i in range(1, M):
        if i in idx:
            a, p, b = W[i - 1], W[i], W[i + 1]
            lin, lout = np.linalg.norm(p - a), np.linalg.norm(b - p)
            if lin == 0 or lout == 0:
                raise InputError(f"viapoint: row {i} repeats a neighbour; a through point needs distinct neighbours")
            u = (p - a) / lin + (b - p) / lout
            if np.linalg.norm(u) < 1e-9:  # the path turns straight back: use the incoming direction
                u = (p - a) / lin
            u = u / np.linalg.norm(u)
            dist = d * min(lin, lout) if d < 1 else d
            if dist >= min(lin, lout):
                raise InputError(f"distance: {dist:g} does not fit between via point {i} and its neighbours "
                                 f"(segments of length {lin:g} and {lout:g})")
            out.extend([p - dist * u, p + dist * u])
            frac[i - 1][1] = dist / lin
            frac[i][0] = dist / lout
        else:
            out.append(W[i])
    return np.array(out), [tuple(f) for f in frac]


def ms_through_trajectory(viapoint: ArrayLike, dt: float, tacc: ArrayLike, qdmax: ArrayLike | None = None, tsegment: ArrayLike | None = None, through: Sequence[int] | None = None, distance: float = 0.25, **kwargs: Any) -> Trajectory:
    """:func:`ms_trajectory` whose path passes exactly through the chosen via points (Lecture 3).

    Parameters
    ----------
    viapoint : array_like, shape (M, n)
        Points (first row the start, last the goal), axis units (rad or m).
    dt : float
        Sample time step, s (> 0).
    tacc : float or array_like
        Blend time(s), s, as :func:`ms_trajectory` (per segment of the augmented list).
    qdmax : float or array_like, shape (n,), optional
        Maximum speed per axis; exactly one of ``qdmax``/``tsegment``.
    tsegment : array_like, shape (M − 1,), optional
        One duration (s) per *original* segment; each is split between the pieces in proportion
        to their lengths, and the piece between two pseudo points gets the two adjacent shares.
    through, distance : optional
        As :func:`through_viapoints`.
    **kwargs
        Passed on to :func:`ms_trajectory` (``q0``, ``qd0``, ``qdf``, ``verbose``).

    Returns
    -------
    Trajectory
        As :func:`ms_trajectory`; ``info["through_times"]`` holds the time (on ``t``'s axis) at
        which the path is at each through point, ``info["through"]`` their indices.

    Examples
    --------
    The path is exactly at the corner (1, 0) at its through time (a plain ``ms_trajectory``
    cuts the corner):

    >>> tr = ms_through_trajectory([[0, 0], [1, 0], [1, 1]], 0.01, 0.2, qdmax=0.5)
    >>> t1 = tr.info["through_times"][0]
    >>> [round(float(np.interp(t1, tr.t, tr.q[:, j])), 6) for j in range(2)]
    [1.0, 0.0]
    """
    W = as_array(viapoint, "viapoint")
    pts, frac = through_viapoints(W, through, distance)
    M = W.shape[0]
    idx = list(range(1, M - 1)) if through is None else sorted({int(i) for i in np.atleast_1d(through)})
    if tsegment is not None and not _empty(tsegment):
        T = as_array(tsegment, "tsegment")
        if T.shape != (M - 1,):
            raise InputError(f"tsegment: expected {M - 1} segment times (one per original segment), got shape {T.shape}")
        new = []
        carry = 0.0
        for k in range(M - 1):
            f0, f1 = frac[k]
            body = T[k] * (1.0 - f0 - f1)
            if f0 > 0:
                new.append(carry + T[k] * f0)  # the piece between the pseudo points around via k
            new.append(body)
            carry = T[k] * f1
        tsegment = np.array(new)
        qdmax = None
    tr = ms_trajectory(pts, dt, tacc, qdmax=qdmax, tsegment=tsegment, **kwargs)
    vt = np.asarray(tr.info["via_times"])
    # via_times lists start and targets; pseudo points of through point j sit at consecutive rows
    times = []
    r = 0
    for i in range(M):
        if i in idx:
            times.append(0.5 * (vt[r] + vt[r + 1]))
            r += 2
        else:
            r += 1
    info = dict(tr.info)
    info["through_times"] = np.array(times)
    info["through"] = np.array(idx)
    return Trajectory(tr.t, tr.q, tr.qd, tr.qdd, name="ms_through_trajectory", labels=tr.labels, info=info)


def ms_cartesian_trajectory(poses: ArrayLike, dt: float, tacc: ArrayLike, speed: ArrayLike | None = None, angular_speed: float | None = None, tsegment: ArrayLike | None = None, verbose: bool = False) -> Trajectory:
    """Multi-segment Cartesian tool path through ``poses`` with blends in position and orientation.

    See the module docstring for the construction (straight lines in position, fixed-axis
    rotations in orientation, blended over ``tacc``, timed like :func:`ms_trajectory`).

    Parameters
    ----------
    poses : array_like, shape (M, 4, 4)
        Via poses ``T_world_tool`` (first the start, last the goal), m.
    dt : float
        Sample time, s (> 0).
    tacc : float or array_like
        Blend time(s), s.
    speed : float or array_like, shape (3,), optional
        Linear speed limit per axis, m/s; give it with ``angular_speed``.
    angular_speed : float, optional
        Angular speed limit about each segment's axis, rad/s.
    tsegment : array_like, shape (M − 1,), optional
        Segment durations, s (instead of the two speeds).
    verbose : bool, optional
        Print the timing of each segment.

    Returns
    -------
    Trajectory
        ``poses`` (K, 4, 4); ``q`` (K, 6) = ``(φ, p)`` with φ the rotation vector of ``R(t) R₀ᵀ``
        (world frame, rad) and p the position (m); ``qd`` = ``(ω, ṗ)`` (world-frame angular
        velocity and the tool origin's velocity); ``qdd`` = ``(ω̇, p̈)`` (ω̇ by central
        differences); ``info``: ``"s"`` (K, M−1) the progress variables, ``"via_times"``,
        ``"segment_times"``, ``"angles"`` θᵢ (rad), ``"axes"`` k̂ᵢ (in frame i).

    Examples
    --------
    0.5 m along x, then 0.5 m along y while turning 90° about z:

    >>> T0, T1 = np.eye(4), np.eye(4)
    >>> T1[:3, 3] = [0.5, 0.0, 0.0]
    >>> T2 = rk.Rp_to_trans(rk.euler_to_matrix([np.pi / 2, 0, 0]), [0.5, 0.5, 0.0])
    >>> tr = ms_cartesian_trajectory([T0, T1, T2], 0.01, 0.2, speed=0.5, angular_speed=1.0)
    >>> np.allclose(tr.poses[-1], T2), tr.info["angles"].round(4).tolist()
    (True, [0.0, 1.5708])
    """
    P = as_array(poses, "poses")
    if P.ndim != 3 or P.shape[1:] != (4, 4) or P.shape[0] < 2:
        raise InputError(f"poses: expected an (M, 4, 4) array of at least two poses, got shape {P.shape}")
    Ts = [check_transform(T, f"poses[{i}]") for i, T in enumerate(P)]
    M = len(Ts)
    ns = M - 1
    ws = [lie.log3(Ts[i][:3, :3].T @ Ts[i + 1][:3, :3]) for i in range(ns)]
    thetas = np.array([np.linalg.norm(w) for w in ws])
    axes = [w / t if t > 0 else np.zeros(3) for w, t in zip(ws, thetas)]
    via = np.zeros((M, 3 + ns))
    for i in range(M):
        via[i, :3] = Ts[i][:3, 3]
        via[i, 3:3 + i] = 1.0  # segments before via i are complete
    if tsegment is not None and not _empty(tsegment):
        if speed is not None or angular_speed is not None:
            raise InputError("speed/angular_speed, tsegment: give the speed limits or the segment times, not both")
        tr = ms_trajectory(via, dt, tacc, tsegment=tsegment, verbose=verbose)
    else:
        if speed is None or angular_speed is None:
            raise InputError("speed, angular_speed: give both speed limits (or tsegment)")
        v = as_scalar(speed, "speed", positive=True)
        w = as_scalar(angular_speed, "angular_speed", positive=True)
        # a segment without rotation is never limited by its progress variable
        sdot = np.where(thetas > 0, w / np.where(thetas > 0, thetas, 1.0), 1e9)
        try:
            tr = ms_trajectory(via, dt, tacc, qdmax=np.r_[np.full(3, v), sdot], verbose=verbose)
        except InputError as exc:  # ms_trajectory's qdmax is built here from speed and angular_speed
            if str(exc).startswith("dt/qdmax: "):
                raise InputError("dt/speed/angular_speed: " + str(exc)[len("dt/qdmax: "):]) from None
            raise
    assert tr.qd is not None and tr.qdd is not None  # ms_trajectory always gives its derivatives
    S = tr.q[:, 3:]
    Sd = tr.qd[:, 3:]
    K = len(tr.t)
    R0 = Ts[0][:3, :3]
    poses_out = np.empty((K, 4, 4))
    poses_out[:] = np.eye(4)
    omega = np.zeros((K, 3))
    for k in range(K):
        R = R0.copy()
        w_world = np.zeros(3)
        for i in range(ns):
            # ω = Σ R_before_i k̂ᵢ θᵢ ṡᵢ: each factor's rate, seen in the world through the factors before it
            w_world += (R @ axes[i]) * thetas[i] * Sd[k, i]
            R = R @ lie.exp3(ws[i] * S[k, i])
        poses_out[k, :3, :3] = R
        omega[k] = w_world
    poses_out[:, :3, 3] = tr.q[:, :3]
    phi = np.array([lie.log3(poses_out[k, :3, :3] @ R0.T) for k in range(K)])
    q = np.hstack([phi, tr.q[:, :3]])
    qd = np.hstack([omega, tr.qd[:, :3]])
    wdot = np.gradient(omega, tr.t, axis=0) if K > 1 else np.zeros_like(omega)
    qdd = np.hstack([wdot, tr.qdd[:, :3]])
    info = {"s": S, "via_times": tr.info.get("via_times"), "segment_times": tr.info.get("segment_times"),
            "angles": thetas, "axes": np.array(axes), "in_blend": tr.info.get("in_blend")}
    return Trajectory(tr.t, q, qd, qdd, poses=poses_out, name="ms_cartesian_trajectory",
                      labels=("φx", "φy", "φz", "x", "y", "z"), info=info)
