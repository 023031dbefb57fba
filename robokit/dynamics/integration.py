r"""Energy and time integration of the course forward dynamics (Lecture 7).

* :func:`second_order_step` — one step of ``q̈ = a(t, q, q̇)`` by Euler, the lecture's Taylor step
  (``q + q̇Δt + ½q̈Δt²``) or fourth-order Runge–Kutta: the one integrator robokit uses (here and in
  :func:`robokit.control.simulate`);
* :func:`integrate` — the course forward dynamics over time (e.g. the PUMA 560 collapsing under
  gravity); :func:`total_energy` — kinetic plus potential energy, to watch the drift.
"""
from __future__ import annotations

from typing import TYPE_CHECKING, Callable

import numpy as np
from numpy.typing import ArrayLike

from robokit._arrays import as_scalar, as_vector
from robokit.dynamics.newton_euler import forward_dynamics
from robokit.errors import InputError

if TYPE_CHECKING:
    from robokit.description.robot import Robot

__all__ = ["second_order_step", "integrate", "total_energy"]

METHODS = ("rk4", "euler", "taylor")


def second_order_step(accel: Callable[[float, np.ndarray, np.ndarray], np.ndarray], t: float, q: np.ndarray,
                      dq: np.ndarray, h: float, method: str = "rk4") -> tuple[np.ndarray, np.ndarray]:
    """``(q, q̇)`` after one step ``h`` of ``q̈ = accel(t, q, q̇)``: the integrator robokit uses.

    No argument checks (the callers have made them).

    Parameters
    ----------
    accel : callable
        ``accel(t, q, dq) -> (n,)`` acceleration.
    t : float
        Time at the start of the step (s).
    q, dq : (n,) ndarray
        State at t.
    h : float
        Step (s).
    method : {"rk4", "euler", "taylor"}, optional
        ``"rk4"`` (default) — classical fourth-order Runge–Kutta on the state (q, q̇);
        ``"euler"`` — ``q ← q + q̇h``, ``q̇ ← q̇ + q̈h``; ``"taylor"`` — the lecture's
        ``q ← q + q̇h + ½q̈h²``, ``q̇ ← q̇ + q̈h``.

    Returns
    -------
    q, dq : (n,) ndarray
        State at t + h.

    Examples
    --------
    The harmonic oscillator ``q̈ = −q`` from (1, 0): RK4 gives (cos 0.1, −sin 0.1) to 4 digits; the
    lecture's step under a constant 2 m/s² is exact, ``q = q̇h + h²``:

    >>> second_order_step(lambda t, q, dq: -q, 0.0, np.array([1.0]), np.array([0.0]), 0.1)
    (array([0.995]), array([-0.0998]))
    >>> second_order_step(lambda t, q, dq: np.array([2.0]), 0.0, np.array([0.0]), np.array([1.0]), 0.1,
    ...                   "taylor")
    (array([0.11]), array([1.2]))
    """
    if method == "euler":
        a = accel(t, q, dq)
        return q + h * dq, dq + h * a
    if method == "taylor":
        a = accel(t, q, dq)
        return q + h * dq + 0.5 * h * h * a, dq + h * a
    k1q, k1v = dq, accel(t, q, dq)
    k2q, k2v = dq + 0.5 * h * k1v, accel(t + 0.5 * h, q + 0.5 * h * k1q, dq + 0.5 * h * k1v)
    k3q, k3v = dq + 0.5 * h * k2v, accel(t + 0.5 * h, q + 0.5 * h * k2q, dq + 0.5 * h * k2v)
    k4q, k4v = dq + h * k3v, accel(t + h, q + h * k3q, dq + h * k3v)
    return (q + h / 6.0 * (k1q + 2.0 * k2q + 2.0 * k3q + k4q),
            dq + h / 6.0 * (k1v + 2.0 * k2v + 2.0 * k3v + k4v))


def total_energy(robot: Robot, q: ArrayLike, dq: ArrayLike) -> float:
    """Kinetic plus potential energy ``½ q̇ᵀ M q̇ + V(q)`` of the robot (J), V from its gravity.

    Parameters
    ----------
    robot : Robot
        A :class:`robokit.Robot` (Pinocchio's potential energy, zero at the base height).
    q, dq : (n,) array_like
        Joint values and rates (rad, rad/s).

    Returns
    -------
    float
        The energy in joules.

    Examples
    --------
    The planar two-link arm hanging straight down (θ₁ = −π/2) has ``V = −(m₁ l₁ + m₂ (l₁ + l₂)) g``;
    horizontal, turning at θ̇₁ = 1 rad/s, ``½ M₁₁ = ½ × 6.86``:

    >>> robot = rk.load("twolink")
    >>> round(total_energy(robot, [-np.pi / 2, 0], [0, 0]), 4), round(total_energy(robot, [0, 0], [1, 0]), 4)
    (-46.107, 3.43)
    """
    import pinocchio as pin

    q = as_vector(q, "q", robot.n)
    dq = as_vector(dq, "dq", robot.n)
    V = pin.computePotentialEnergy(robot.model, robot.data, robot.q_pin(q))
    return float(0.5 * dq @ robot.crba(q) @ dq + V)


def integrate(thetalist: ArrayLike, dthetalist: ArrayLike, taufun: Callable[[float, np.ndarray, np.ndarray], ArrayLike],
              g: ArrayLike, Mlist: ArrayLike, Glist: ArrayLike, Slist: ArrayLike, dt: float, steps: int,
              method: str = "rk4") -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Integrate the course forward dynamics ``θ̈ = M⁻¹(τ − c − g)`` over time (Lecture 7).

    Parameters
    ----------
    thetalist, dthetalist : (n,) array_like
        Initial joint values and rates (rad, rad/s).
    taufun : callable
        ``taufun(t, θ, θ̇) -> τ (n,)`` (N·m), e.g. ``lambda t, q, dq: np.zeros(n)`` for a free fall.
    g : (3,) array_like
        Gravity in the base frame (m/s²).
    Mlist, Glist, Slist : (n+1, 4, 4), (n, 6, 6), (6, n) array_like
        The model: link frames (m), spatial inertias (kg·m², kg), screw axes (:mod:`robokit.dynamics.newton_euler`).
    dt : float
        Step (s), positive.
    steps : int
        Number of steps.
    method : {"rk4", "euler", "taylor"}, optional
        ``"rk4"`` (default, fourth-order Runge–Kutta); ``"euler"`` (``θ ← θ + θ̇Δt``,
        ``θ̇ ← θ̇ + θ̈Δt``); ``"taylor"`` — the lecture's step ``θ̇(t+Δt) = θ̇ + θ̈Δt``,
        ``θ(t+Δt) = θ + θ̇Δt + ½θ̈Δt²``.

    Returns
    -------
    t : (steps+1,) ndarray
        Times (s), from 0.
    thetamat, dthetamat : (steps+1, n) ndarray
        Joint values and rates at those times; row 0 the initial state.

    Raises
    ------
    InputError
        On an unknown ``method``, a ``dt`` that is not positive, or joint values or a model of the
        wrong shape, NaN or infinite.

    Examples
    --------
    The planar two-link arm falls freely for 1 s; RK4 keeps its energy (0 J at the start):

    >>> robot = rk.load("twolink")
    >>> p = robot.poe
    >>> t, Q, dQ = integrate([0, 0], [0, 0], lambda t, q, dq: np.zeros(2), [0, -9.81, 0],
    ...                      p.Mlist, p.Glist, p.Slist, 0.01, 100)
    >>> Q.shape, abs(total_energy(robot, Q[-1], dQ[-1])) < 1e-5
    ((101, 2), True)
    """
    th = as_vector(thetalist, "thetalist").copy()
    dth = as_vector(dthetalist, "dthetalist", len(th)).copy()
    dt = as_scalar(dt, "dt", positive=True)
    if method not in METHODS:
        raise InputError(f"method: expected 'rk4', 'euler' or 'taylor', got {method!r}")
    z6 = np.zeros(6)

    def acc(t: float, a: np.ndarray, b: np.ndarray) -> np.ndarray:
        return forward_dynamics(a, b, taufun(t, a, b), g, z6, Mlist, Glist, Slist)

    T = np.arange(int(steps) + 1) * dt
    Q = np.empty((len(T), len(th)))
    D = np.empty_like(Q)
    Q[0], D[0] = th, dth
    for k in range(int(steps)):
        th, dth = second_order_step(acc, T[k], th, dth, dt, method)
        Q[k + 1], D[k + 1] = th, dth
    return T, Q, D
