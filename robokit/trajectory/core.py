r"""The ``Trajectory`` result type and the small helpers every trajectory generator shares.

A trajectory (Lecture 3) is the time history of position, velocity and acceleration of
each degree of freedom. Here it is sampled on a time grid:

* ``t``   (K,)   sample times, s, increasing;
* ``q``   (K, n) positions, one row per sample, one column per axis (rad or m);
* ``qd``  (K, n) velocities (rad/s or m/s), analytic (not finite differences);
* ``qdd`` (K, n) accelerations (rad/s² or m/s²), analytic;
* ``poses`` (K, 4, 4) for Cartesian trajectories: the pose of the tool in the world frame.

Piecewise polynomials are stored per segment in *local* time ``τ = t − t_i`` with
ascending coefficients ``c0 + c1 τ + c2 τ² + …``; :func:`eval_piecewise` evaluates
position, velocity and acceleration of such a spline on any time grid.

The single-segment generators (:mod:`robokit.trajectory.polynomial` and
:func:`robokit.trajectory.lspb.lspb_trajectory`) share these parameters, defined here once:

* ``q0, qf`` — float or array_like (n,): start and end positions, one entry per axis (rad or m);
* ``tf`` — float: the duration, s (> 0); the move runs on ``[0, tf]``;
* ``t`` — None, int or array_like (K,): the sample grid on ``[0, tf]``: None (101 samples), a
  number of samples (ends included), or increasing times (:func:`sample_times`);
* ``qd0, qdf`` and ``qdd0, qddf`` — float or array_like (n,), optional: end velocities
  (rad/s or m/s) and end accelerations (rad/s² or m/s²), default 0.
"""
from __future__ import annotations

from dataclasses import dataclass, field
from numbers import Integral

import numpy as np
from numpy.typing import ArrayLike

from robokit.errors import InputError
from robokit._arrays import as_array, as_scalar
from robokit.errors import InputTypeError

__all__ = ["Trajectory"]

#: Number of samples used when a generator is called with ``t=None``.
DEFAULT_SAMPLES = 101
#: Most samples a trajectory generator makes from an integer count (``t=N``, ``samples=N``): a
#: million is 1000 s at 1 kHz, and q, q̇, q̈ of a 6-joint arm take 144 MB. Checked before anything
#: is allocated (``t=10**10`` would ask for 80 GB per array).
MAX_SAMPLES = 1_000_000


@dataclass(frozen=True, eq=False)
class Trajectory:
    """A sampled trajectory: times, positions, velocities, accelerations (and poses).

    Attributes
    ----------
    t : ndarray, shape (K,)
        Sample times in seconds, increasing.
    q : ndarray, shape (K, n)
        Positions, one row per sample and one column per axis (joint angle in rad or
        joint displacement in m; for Cartesian trajectories see ``labels``).
    qd, qdd : ndarray, shape (K, n), or None
        Velocities and accelerations at the same samples (analytic derivatives of the
        generating curve), ``None`` when the generator does not define them.
    poses : ndarray, shape (K, 4, 4), or None
        For Cartesian trajectories, the pose ``T_world_tool`` at each sample.
    name : str
        The function that made it (``"cubic"``, ``"lspb"``, ``"ms_trajectory"``, …).
    labels : tuple of str, or None
        Names of the columns of ``q`` (used by the plots); default ``q1 … qn``.
    info : dict
        Generator-specific extras (coefficients, blend times, via-point times, …),
        documented by each generator.

    Examples
    --------
    A cubic rest-to-rest move over 2 s, sampled 5 times (every 0.5 s):

    >>> from robokit.trajectory import cubic_trajectory
    >>> tr = cubic_trajectory([0.0], [1.0], tf=2.0, t=5)
    >>> tr.t.shape, tr.q.shape, len(tr)
    ((5,), (5, 1), 5)
    >>> tr.t.tolist(), float(tr.q[2, 0]), tr.name
    ([0.0, 0.5, 1.0, 1.5, 2.0], 0.5, 'cubic')
    """

    t: np.ndarray
    q: np.ndarray
    qd: np.ndarray | None = None
    qdd: np.ndarray | None = None
    poses: np.ndarray | None = None
    name: str = "trajectory"
    labels: tuple | None = None
    info: dict = field(default_factory=dict)

    @property
    def n(self) -> int:
        """Number of axes (columns of ``q``)."""
        return int(self.q.shape[1])

    @property
    def duration(self) -> float:
        """``t[-1] − t[0]`` in seconds."""
        return float(self.t[-1] - self.t[0]) if len(self.t) else 0.0

    def column_labels(self) -> tuple:
        """Names of the columns of ``q``: ``labels`` or the default ``("q1", …, "qn")``.

        Returns
        -------
        tuple of str
            n names.

        Examples
        --------
        >>> from robokit.trajectory import cubic_trajectory
        >>> cubic_trajectory([0.0, 0.0], [1.0, 2.0], 1.0, t=3).column_labels()
        ('q1', 'q2')
        """
        return tuple(self.labels) if self.labels is not None else tuple(f"q{i + 1}" for i in range(self.n))

    def __len__(self) -> int:
        return int(self.t.shape[0])

    def __repr__(self) -> str:
        extra = ", with poses" if self.poses is not None else ""
        return f"Trajectory({self.name!r}: {len(self)} samples × {self.n} axes over {self.duration:g} s{extra})"


# ----------------------------------------------------------------------------- helpers


def as_axes(x: ArrayLike, name: str, n: int | None = None) -> np.ndarray:
    """A scalar or 1-D array as a float vector of ``n`` axes (a scalar gives one axis, or
    is broadcast to ``n`` axes when ``n`` is given)."""
    arr = as_array(x, name)
    if arr.ndim == 0:
        return np.full(1 if n is None else n, float(arr))
    if arr.ndim != 1:
        raise InputError(f"{name}: expected a number or a 1-D array of axes, got shape {arr.shape}")
    if n is not None and arr.shape[0] != n:
        raise InputError(f"{name}: expected {n} axes (one per axis), got {arr.shape[0]}")
    return arr.copy()


def optional_axes(x: ArrayLike | None, name: str, n: int) -> np.ndarray:
    """``x`` as an ``n``-vector (scalars broadcast), or zeros when ``x`` is None."""
    return np.zeros(n) if x is None else as_axes(x, name, n)


def positive_duration(tf: ArrayLike, name: str = "tf") -> float:
    """A finite duration > 0, else ``ValueError`` naming the argument."""
    v = as_scalar(tf, name)
    if not v > 0.0:
        raise InputError(f"{name}: the duration must be positive, got {v!r}")
    return v


def sample_times(t: ArrayLike | None, t_start: float, t_end: float, name: str = "t") -> np.ndarray:
    """The sample grid of a generator on ``[t_start, t_end]``.

    ``t`` is None (``DEFAULT_SAMPLES`` equally spaced samples, both ends included), an
    integer ``N ≥ 2`` (N equally spaced samples, both ends included), or a 1-D array of
    strictly increasing times inside ``[t_start, t_end]``.
    """
    if t is None:
        return np.linspace(t_start, t_end, DEFAULT_SAMPLES)
    if isinstance(t, bool):
        raise InputTypeError(f"{name}: expected a number of samples or an array of times, got {t!r}")
    if isinstance(t, Integral):
        if t < 2:
            raise InputError(f"{name}: a number of samples must be at least 2, got {t}")
        if int(t) > MAX_SAMPLES:
            raise InputError(f"{name}: {int(t)} samples; robokit makes at most {MAX_SAMPLES} (give fewer, or an array "
                             "of times)")
        return np.linspace(t_start, t_end, int(t))
    arr = as_array(t, name)
    if arr.ndim != 1 or arr.size == 0:
        raise InputError(f"{name}: expected an integer number of samples or a non-empty 1-D array of times, got shape {arr.shape}")
    if arr.size > 1 and not np.all(np.diff(arr) > 0):
        k = int(np.argmin(np.diff(arr)))
        raise InputError(f"{name}: sample times must be strictly increasing, but {name}[{k + 1}] = {arr[k + 1]!r} <= {name}[{k}] = {arr[k]!r}")
    slack = 1e-9 * max(1.0, abs(t_start), abs(t_end))
    if arr[0] < t_start - slack or arr[-1] > t_end + slack:
        raise InputError(f"{name}: sample times must lie in [{t_start:g}, {t_end:g}] s, got [{arr[0]:g}, {arr[-1]:g}]")
    return np.clip(arr, t_start, t_end)


def increasing_times(times: ArrayLike, name: str, m: int | None = None) -> np.ndarray:
    """A 1-D array of strictly increasing times (length ``m`` if given)."""
    arr = as_array(times, name, (None,))
    if m is not None and arr.shape[0] != m:
        raise InputError(f"{name}: expected {m} times (one per via point), got {arr.shape[0]}")
    d = np.diff(arr)
    if np.any(d <= 0):
        k = int(np.argmin(d))
        raise InputError(
            f"{name}: times must be strictly increasing, but {name}[{k + 1}] = {arr[k + 1]!r} <= {name}[{k}] = {arr[k]!r}"
        )
    return arr


def viapoint_matrix(viapoints: ArrayLike, name: str, min_rows: int = 2) -> np.ndarray:
    """Via points as an (m, n) float matrix, one row per point (m ≥ ``min_rows``); a 1-D list is
    one axis, ``[p0, p1, ...]`` → shape (m, 1)."""
    arr = as_array(viapoints, name)
    if arr.ndim == 1:
        arr = arr.reshape(-1, 1)
    if arr.ndim != 2:
        raise InputError(
            f"{name}: expected a 2-D array with one row per point and one column per axis (or a 1-D list "
            f"for one axis), got shape {arr.shape}")
    if arr.shape[0] < min_rows or arr.shape[1] < 1:
        raise InputError(f"{name}: expected at least {min_rows} rows (points) and 1 column (axis), got shape {arr.shape}")
    return arr.copy()


def eval_piecewise(breaks: np.ndarray, coeffs: np.ndarray, t: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Evaluate a piecewise polynomial and its first two derivatives.

    breaks : (m+1,) increasing segment boundaries.
    coeffs : (m, d+1, n) ascending coefficients of each segment in local time ``τ = t − breaks[i]``.
    t      : (K,) sample times (outside the range the end segments are extended).
    Returns ``(q, qd, qdd)``, each (K, n). At a boundary the segment that starts there is used,
    so ``q(breaks[i]) = coeffs[i, 0]`` exactly.
    """
    m, dp1, _ = coeffs.shape
    i = np.clip(np.searchsorted(breaks, t, side="right") - 1, 0, m - 1)
    tau = (t - breaks[i])[:, None]
    c = coeffs[i]  # (K, d+1, n)
    q = c[:, dp1 - 1].copy()
    for k in range(dp1 - 2, -1, -1):
        q = q * tau + c[:, k]
    qd = np.zeros_like(q)
    for k in range(dp1 - 1, 0, -1):
        qd = qd * tau + k * c[:, k]
    qdd = np.zeros_like(q)
    for k in range(dp1 - 1, 1, -1):
        qdd = qdd * tau + k * (k - 1) * c[:, k]
    return q, qd, qdd
