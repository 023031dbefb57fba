r"""Exciting trajectories for dynamic identification: optimised finite Fourier series (Swevers et al. 1997).

Each joint follows a finite Fourier series of base frequency ``ω_f = 2π / T`` (T the period):

.. math::

    q_j(t) = q_{j,0} + \sum_{l=1}^{L} \frac{a_{jl}}{ω_f l} \sin(ω_f l t) - \frac{b_{jl}}{ω_f l} \cos(ω_f l t),
    \qquad
    \dot q_j(t) = \sum_{l=1}^{L} a_{jl} \cos(ω_f l t) + b_{jl} \sin(ω_f l t)

(and ``q̈`` by differentiating once more), so the motion is periodic: position, velocity and
acceleration at t = T equal those at t = 0, and measurements over several periods can be
averaged. Two coefficients per joint are fixed so that the arm starts and ends at rest:
``Σ_l a_jl = 0`` (q̇(0) = 0) and ``Σ_l l b_jl = 0`` (q̈(0) = 0).

Limits are met by construction: for any coefficients, each joint's series is scaled by the largest
factor that keeps its position range inside the joint limits (less a margin), its speed below
``qd_max`` and its acceleration below ``qdd_max`` (checked on a fine grid), and its offset
``q_{j,0}`` centres it between the limits. The optimiser (``scipy.optimize.minimize``, L-BFGS-B
with finite-difference gradients, a bounded number of evaluations, from a seeded random start) then
minimises the logarithm of the condition number of the base regressor (rigid body + friction,
:mod:`robokit.calibration.regressor`) stacked over the trajectory's samples.
"""
from __future__ import annotations

import math
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import ArrayLike

from robokit._arrays import as_array, as_count, as_scalar
from robokit.calibration.chain import chain_from_robot
from robokit.calibration.identification import MAX_EVALUATIONS
from robokit.calibration.regressor import base_parameters, full_regressor
from robokit.errors import InputError
from robokit.trajectory.core import MAX_SAMPLES, Trajectory

if TYPE_CHECKING:
    from robokit.description.robot import Robot

__all__ = ["excitation_trajectory", "fourier_series"]


def fourier_series(a: ArrayLike, b: ArrayLike, q0: ArrayLike, period: float,
                   t: ArrayLike) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Positions, velocities, accelerations (len(t), n) of the finite Fourier series (module docstring).

    Parameters
    ----------
    a, b : array_like, shape (n, L)
        Coefficients (rad/s or m/s): ``q̇ⱼ = Σ_l aⱼₗ cos(ω_f l t) + bⱼₗ sin(ω_f l t)``.
    q0 : array_like, shape (n,)
        Offsets (rad, m).
    period : float
        T (s); ``ω_f = 2π/T``.
    t : array_like, shape (K,)
        Times (s).

    Returns
    -------
    q, qd, qdd : ndarray, shape (K, n)

    Examples
    --------
    >>> import numpy as np
    >>> from robokit.calibration import fourier_series
    >>> q, qd, qdd = fourier_series([[1.0]], [[0.0]], [0.0], 2 * np.pi, [0.0, np.pi / 2])
    >>> np.round(q[:, 0], 12).tolist(), np.round(qd[:, 0], 12).tolist()
    ([0.0, 1.0], [1.0, 0.0])
    """
    A, B = np.atleast_2d(np.asarray(a, dtype=float)), np.atleast_2d(np.asarray(b, dtype=float))
    t = np.asarray(t, dtype=float)
    L = A.shape[1]
    wf = 2.0 * math.pi / float(period)
    wl = wf * np.arange(1, L + 1)  # (L,)
    s, c = np.sin(np.outer(t, wl)), np.cos(np.outer(t, wl))  # (K, L)
    q = np.asarray(q0, dtype=float)[None, :] + s @ (A / wl).T - c @ (B / wl).T
    qd = c @ A.T + s @ B.T
    qdd = -s @ (A * wl).T + c @ (B * wl).T
    return q, qd, qdd


def _coefficients(x: np.ndarray, n: int, L: int) -> tuple[np.ndarray, np.ndarray]:
    """Free coefficients (n·2(L−1),) → a, b (n, L) with Σ a = 0 and Σ l b = 0 per joint."""
    X = x.reshape(n, 2, L - 1)
    a = np.empty((n, L))
    b = np.empty((n, L))
    a[:, :-1] = X[:, 0]
    b[:, :-1] = X[:, 1]
    a[:, -1] = -X[:, 0].sum(axis=1)
    b[:, -1] = -(X[:, 1] * np.arange(1, L)).sum(axis=1) / L
    return a, b


def _fit_limits(a: np.ndarray, b: np.ndarray, period: float, lo: np.ndarray, hi: np.ndarray, qd_max: np.ndarray,
                qdd_max: np.ndarray, grid: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Scale each joint's coefficients to the tightest limit and centre it: (a, b, q0)."""
    n = a.shape[0]
    d, dd, ddd = fourier_series(a, b, np.zeros(n), period, grid)
    span = d.max(axis=0) - d.min(axis=0)
    with np.errstate(divide="ignore", invalid="ignore"):
        s = np.minimum.reduce([np.where(span > 0, (hi - lo) / span, np.inf),
                               np.where(np.abs(dd).max(axis=0) > 0, qd_max / np.abs(dd).max(axis=0), np.inf),
                               np.where(np.abs(ddd).max(axis=0) > 0, qdd_max / np.abs(ddd).max(axis=0), np.inf)])
    s = np.where(np.isfinite(s), s, 0.0)
    q0 = 0.5 * (lo + hi) - 0.5 * s * (d.max(axis=0) + d.min(axis=0))
    return a * s[:, None], b * s[:, None], q0


def _per_joint(x: ArrayLike, name: str, n: int) -> np.ndarray:
    """A scalar or (n,) limit, bounded like every number (1e12)."""
    arr = as_array(x, name, bounded=True)
    if arr.shape not in ((), (1,), (n,)):
        raise InputError(f"{name}: expected a number or {n} numbers, got shape {arr.shape}")
    return np.broadcast_to(arr, (n,)).astype(float)


def excitation_trajectory(robot: Robot | str, duration: float, harmonics: int = 5, *, qlim: ArrayLike | None = None,
                          qd_max: ArrayLike | None = None, qdd_max: ArrayLike | None = None, samples: int = 501,
                          margin: float = 0.05, friction: bool = True, max_evaluations: int = 400,
                          rng: int | np.random.Generator | None = 0) -> Trajectory:
    r"""A periodic exciting trajectory for dynamic identification (finite Fourier series, Swevers et al. 1997).

    The coefficients are optimised for the condition number of the base regressor (rigid body plus
    friction) within the joint position, velocity and acceleration limits (see the module docstring).

    Parameters
    ----------
    robot : Robot or str
        The arm (anything :func:`robokit.load` accepts).
    duration : float
        The period T (s); the trajectory covers exactly one period, from rest to rest.
    harmonics : int
        Number of harmonics L per joint (≥ 2).
    qlim : array_like, shape (n, 2), optional
        Position limits (rad, m); default the robot's (unlimited joints: ±π). A fraction ``margin``
        of each range is kept free at both ends.
    qd_max, qdd_max : float or array_like, shape (n,), optional
        Speed and acceleration limits (rad/s, rad/s²; m/s, m/s²); default the model's velocity
        limits (1 rad/s where it has none) and three times those per second.
    samples : int
        Number of samples of the returned trajectory over [0, T] (both ends included), 3 to
        :data:`robokit.trajectory.core.MAX_SAMPLES` (checked before anything is allocated).
    margin : float
        Fraction of each joint range left free at each end, in [0, 0.5).
    friction : bool
        Condition the regressor that includes the friction columns.
    max_evaluations : int
        Evaluations of the condition number at most (bounds the optimisation time; deterministic),
        1 to 100,000.
    rng : int or numpy.random.Generator or None
        Seed of the starting coefficients.

    Returns
    -------
    Trajectory
        ``.t`` (samples,), ``.q``, ``.qd``, ``.qdd`` (samples, n), name ``"excitation"``; ``.info`` holds
        ``a``, ``b`` (n, L), ``q0`` (n,), ``period``, ``harmonics``, ``condition_number`` (of the base
        regressor on the returned samples), ``initial_condition_number`` and ``evaluations``.

    Examples
    --------
    >>> import robokit
    >>> tr = robokit.excitation_trajectory("rrr", duration=5.0, harmonics=3, max_evaluations=50)
    >>> tr.q.shape, bool(abs(tr.qd[0]).max() < 1e-9 and abs(tr.qd[-1]).max() < 1e-9)
    ((501, 3), True)
    """
    from scipy.optimize import minimize

    from robokit.description import load

    robot = load(robot)
    n = robot.n
    T = as_scalar(duration, "duration", positive=True, bounded=True)
    harmonics = as_count(harmonics, "harmonics", 2, 50)
    samples = as_count(samples, "samples", 3, MAX_SAMPLES)
    max_evaluations = as_count(max_evaluations, "max_evaluations", 1, MAX_EVALUATIONS)
    margin = as_scalar(margin, "margin", nonnegative=True)
    if not margin < 0.5:
        raise InputError(f"margin: expected a fraction in [0, 0.5), got {margin!r}")
    lim = np.array(robot.qlim, dtype=float) if qlim is None else as_array(qlim, "qlim", (n, 2), finite=False,
                                                                           bounded=True)
    if np.isnan(lim).any():
        raise InputError("qlim: contains NaN values")
    lim = np.where(np.isfinite(lim), lim, np.array([-math.pi, math.pi]))
    if np.any(lim[:, 1] <= lim[:, 0]):
        raise InputError(f"qlim: expected lower < upper for every joint, got {lim.tolist()}")
    rng_ = lim[:, 1] - lim[:, 0]
    lo, hi = lim[:, 0] + margin * rng_, lim[:, 1] - margin * rng_
    vmodel = np.asarray(robot.model.velocityLimit, dtype=float)[:n]
    vdef = np.where(np.isfinite(vmodel) & (vmodel > 0), vmodel, 1.0)
    vmax = vdef if qd_max is None else _per_joint(qd_max, "qd_max", n)
    amax = 3.0 * vdef if qdd_max is None else _per_joint(qdd_max, "qdd_max", n)
    for name, v in (("qd_max", vmax), ("qdd_max", amax)):
        if np.any(v <= 0):
            raise InputError(f"{name}: expected positive limits, got {v.tolist()}")
    L = harmonics
    chain = chain_from_robot(robot)
    base = base_parameters(robot, friction=friction)
    grid = np.linspace(0.0, T, 40 * L + 1)  # limit checks: 40 points per period of the top harmonic
    m_eval = max(2 * L * 4, -(-3 * base.count // n), 40)
    t_eval = np.linspace(0.0, T, m_eval, endpoint=False) + 0.5 * T / m_eval
    evaluations = 0

    def build(x: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        a, b = _coefficients(x, n, L)
        return _fit_limits(a, b, T, lo, hi, vmax, amax, grid)

    def cond_of(a: np.ndarray, b: np.ndarray, q0: np.ndarray, t: np.ndarray) -> float:
        q, qd, qdd = fourier_series(a, b, q0, T, t)
        W = full_regressor(chain, q, qd, qdd, robot.gravity, friction)[:, :, base.independent]
        sv = np.linalg.svd(W.reshape(-1, base.count), compute_uv=False)
        return float(sv[0] / sv[-1]) if sv[-1] > 0 else math.inf

    def objective(x: np.ndarray) -> float:
        nonlocal evaluations
        evaluations += 1
        c = cond_of(*build(x), t_eval)
        return math.log(c) if math.isfinite(c) else 1e3

    gen = np.random.default_rng(rng)
    x0 = gen.standard_normal(n * 2 * (L - 1)) * np.tile(1.0 / np.arange(1, L), 2 * n)  # amplitudes ∝ 1/l
    f0 = objective(x0)
    best = {"x": x0, "f": f0}

    class _Budget(Exception):
        pass

    def tracked(x: np.ndarray) -> float:
        if evaluations >= max_evaluations:
            raise _Budget
        f = objective(x)
        if f < best["f"]:
            best["x"], best["f"] = x.copy(), f
        return f

    try:
        minimize(tracked, x0, method="L-BFGS-B",
                 options={"maxfun": max_evaluations, "maxiter": max_evaluations, "eps": 1e-6})
    except _Budget:
        pass
    a, b, q0 = build(best["x"])
    t = np.linspace(0.0, T, samples)
    q, qd, qdd = fourier_series(a, b, q0, T, t)
    info = {"a": a, "b": b, "q0": q0, "period": T, "harmonics": L,
            "condition_number": cond_of(a, b, q0, t), "initial_condition_number": math.exp(f0),
            "evaluations": evaluations}
    return Trajectory(t, q, qd, qdd, name="excitation", labels=tuple(f"q{i + 1}" for i in range(n)), info=info)
