r"""The kinematic bicycle model and its controllers (Lecture 9).

State ``x = (x, y, θ)`` (m, m, rad) of the rear-axle centre in the world frame {O}; inputs
``u = (v, γ)``: speed along the vehicle's x axis (m/s) and steering angle (rad); wheelbase L:

    ẋ = v cos θ,   ẏ = v sin θ,   θ̇ = (v / L) tan γ,

with the non-holonomic constraint ``ẏ cos θ − ẋ sin θ = 0`` (no sideways velocity). The model is
undefined at γ = ±π/2, which is rejected. For constant (v, γ) over a step the motion is an arc of
radius L / tan γ about the instantaneous centre of rotation; :meth:`BicycleModel.step` integrates
that arc exactly.

Controllers (each called as ``ctrl(t, x, dt) -> (v, γ)``; ``dt`` advances integral terms):

* :class:`MoveToPoint`: ``v* = K_v ‖p* − p‖``, ``θ* = atan2(y* − y, x* − x)``, ``γ = K_h (θ* ⊖ θ)``;
* :class:`FollowLine` (ax + by + c = 0): ``d = (a, b, c)·(x, y, 1)/√(a² + b²)``,
  ``θ* = atan2(−a, b)``, ``γ = −K_d d + K_h (θ* ⊖ θ)`` at a constant speed;
* :class:`PurePursuit` (a moving target on a path, kept at distance d*):
  ``e = ‖p*(t) − p‖ − d*``, ``v* = K_v e + K_i ∫e dt``, ``γ = K_h (θ* ⊖ θ)``.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Callable, overload

import numpy as np
from numpy.typing import ArrayLike

from robokit._arrays import FloatVector, as_scalar, as_vector
from robokit.errors import InputError
from robokit.spatial.basics import wrap_angle

#: Most control periods :func:`run_vehicle` runs (T / dt).
MAX_STEPS = 1_000_000

__all__ = ["BicycleModel", "MoveToPoint", "FollowLine", "PurePursuit", "VehicleRun", "run_vehicle", "angdiff"]


@overload
def angdiff(a: float, b: float = 0.0) -> float: ...
@overload
def angdiff(a: float | np.ndarray, b: float | np.ndarray = 0.0) -> float | np.ndarray: ...
def angdiff(a: float | np.ndarray, b: float | np.ndarray = 0.0) -> float | np.ndarray:
    """The angle ``a ⊖ b`` wrapped to (−π, π] (scalar or array), Corke's name for it.

    Parameters
    ----------
    a : float or ndarray
        Angle(s) (rad).
    b : float or ndarray, default 0
        Angle(s) subtracted (rad), broadcast against ``a``.

    Returns
    -------
    float or ndarray
        ``wrap(a − b)`` in (−π, π] (rad): a float for scalar input, else an array of the broadcast shape.

    Examples
    --------
    >>> round(angdiff(np.radians(170), np.radians(-170)), 4)   # 340° is −20°
    -0.3491
    """
    return wrap_angle(np.asarray(a, dtype=float) - b) if np.ndim(a) else wrap_angle(float(a) - float(b))


class _HeadingModel:
    """What the bicycle and the unicycle share: ``ẋ = v cos θ, ẏ = v sin θ, θ̇ = ω`` (Lecture 9).

    A subclass gives ``limit(u) -> (v, u₂)`` and ``_turn_rate(v, u₂) -> ω``; for the unicycle
    u₂ is ω itself, for the bicycle the steering angle γ with ``ω = (v / L) tan γ``.
    """

    def limit(self, u: ArrayLike) -> np.ndarray:  # pragma: no cover - every model defines it
        raise NotImplementedError

    def _turn_rate(self, v: float, u2: float) -> float:  # pragma: no cover - every model defines it
        raise NotImplementedError

    def deriv(self, x: ArrayLike, u: ArrayLike) -> np.ndarray:
        """``(ẋ, ẏ, θ̇) = (v cos θ, v sin θ, ω)`` at state x and inputs u (limits applied).

        ω is the model's turn rate: ``v tan γ / L`` for the bicycle's u = (v, γ), ω itself for
        the unicycle's u = (v, ω).

        Parameters
        ----------
        x : array_like, shape (3,)
            State (x, y, θ).
        u : array_like, shape (2,)
            Speed v (m/s) and the second input: steering angle γ (rad) or turn rate ω (rad/s).

        Returns
        -------
        ndarray, shape (3,)
        """
        x = as_vector(x, "x", 3)
        v, u2 = self.limit(u)
        return np.array([v * math.cos(x[2]), v * math.sin(x[2]), self._turn_rate(v, u2)])

    def step(self, x: ArrayLike, u: ArrayLike, dt: float) -> np.ndarray:
        """The state after ``dt`` s at constant inputs: the exact arc of radius v/ω (a straight line
        when ω = 0: γ = 0 for the bicycle).

        Parameters
        ----------
        x : array_like, shape (3,)
            State (x, y, θ).
        u : array_like, shape (2,)
            Inputs (v, γ) or (v, ω), limits applied.
        dt : float
            Duration, s (> 0).

        Returns
        -------
        ndarray, shape (3,)
            The new state, θ wrapped.
        """
        x = as_vector(x, "x", 3)
        v, u2 = self.limit(u)
        dt = as_scalar(dt, "dt", positive=True)
        w = self._turn_rate(v, u2)
        th = x[2]
        if abs(w) < 1e-12:
            return np.array([x[0] + v * dt * math.cos(th), x[1] + v * dt * math.sin(th), th])
        th1 = th + w * dt
        Rr = v / w  # signed radius (L / tan γ for the bicycle)
        return np.array([x[0] + Rr * (math.sin(th1) - math.sin(th)), x[1] - Rr * (math.cos(th1) - math.cos(th)),
                         angdiff(th1)])


class BicycleModel(_HeadingModel):
    """Kinematic bicycle: ``ẋ = v cos θ, ẏ = v sin θ, θ̇ = (v / L) tan γ`` (Lecture 9).

    Parameters
    ----------
    L : float
        Wheelbase (m, > 0).
    steer_max : float
        Steering-angle limit (rad, 0 < steer_max < π/2); inputs beyond it are clipped.
    speed_max : float
        Speed limit (m/s, > 0); inputs beyond it are clipped.

    Examples
    --------
    Full steering lock of 45° on a 1 m wheelbase: a circle of radius L / tan γ = 1 m, so a quarter
    turn at 1 m/s (π/2 s) ends at (1, 1) heading +y.

    >>> car = BicycleModel(L=1.0)
    >>> car.step([0, 0, 0], [1.0, np.pi / 4], np.pi / 2).round(4)
    array([1.    , 1.    , 1.5708])
    """

    def __init__(self, L: float = 1.0, steer_max: float = np.deg2rad(60.0), speed_max: float = 5.0) -> None:
        self.L = as_scalar(L, "L", positive=True)
        self.steer_max = as_scalar(steer_max, "steer_max", positive=True)
        if self.steer_max >= np.pi / 2:
            raise InputError(f"steer_max: must be below π/2 (the model is undefined at ±π/2), got {steer_max!r}")
        self.speed_max = as_scalar(speed_max, "speed_max", positive=True)

    def limit(self, u: ArrayLike) -> np.ndarray:
        """Inputs clipped to the speed and steering limits (``steer_max`` < π/2, so a demanded
        γ = ±π/2, where the model is undefined, is clipped like any other angle beyond the limit).

        Parameters
        ----------
        u : array_like, shape (2,)
            Demanded u = (v, γ) (see the module docstring).

        Returns
        -------
        ndarray, shape (2,)
            u with v clipped to ±``speed_max`` and γ to ±``steer_max``.
        """
        v, gamma = as_vector(u, "u", 2)
        return np.array([np.clip(v, -self.speed_max, self.speed_max),
                         np.clip(gamma, -self.steer_max, self.steer_max)])

    def _turn_rate(self, v: float, gamma: float) -> float:
        # θ̇ = ω = (v / L) tan γ
        return v / self.L * math.tan(gamma)

    @staticmethod
    def sideways_velocity(x: FloatVector, xdot: FloatVector) -> float:
        """``ẏ cos θ − ẋ sin θ``: zero for every motion the model allows (the non-holonomic constraint).

        Parameters
        ----------
        x : array_like, shape (3,)
            State (x, y, θ).
        xdot : array_like, shape (3,)
            Its time derivative.

        Returns
        -------
        float
            The velocity across the vehicle's heading, m/s.
        """
        return float(xdot[1] * math.cos(x[2]) - xdot[0] * math.sin(x[2]))


@dataclass
class MoveToPoint:
    """Drive to ``goal``: speed proportional to the distance, heading P control (Lecture 9).

    ``v = K_v ‖p* − p‖``, ``γ = K_h (atan2(y* − y, x* − x) ⊖ θ)``; called as ``ctrl(t, x, dt) -> (v, γ)``.

    Attributes
    ----------
    goal : tuple
        (x*, y*) of the goal in the world frame (m).
    Kv : float
        Speed gain (1/s).
    Kh : float
        Heading gain (dimensionless: rad of steering per rad of heading error).
    """

    goal: tuple
    Kv: float = 0.5
    Kh: float = 2.0

    def __call__(self, t: float, x: FloatVector, dt: float = 0.0) -> tuple[float, float]:
        dx, dy = self.goal[0] - x[0], self.goal[1] - x[1]
        return self.Kv * math.hypot(dx, dy), self.Kh * angdiff(math.atan2(dy, dx), x[2])


@dataclass
class FollowLine:
    """Follow the line ``a x + b y + c = 0`` at constant speed (Lecture 9).

    ``γ = −K_d d + K_h (θ* ⊖ θ)`` with d the signed distance to the line and ``θ* = atan2(−a, b)``
    its direction; called as ``ctrl(t, x, dt) -> (v, γ)``.

    Attributes
    ----------
    line : tuple
        (a, b, c), not both a and b zero.
    v : float
        Speed (m/s).
    Kd : float
        Distance gain (rad/m, ≥ 0).
    Kh : float
        Heading gain (≥ 0).
    """

    line: tuple
    v: float = 1.0
    Kd: float = 0.5
    Kh: float = 1.0

    def __post_init__(self) -> None:
        if isinstance(self.line, (int, float, np.number)):
            raise InputError(f"line: expected the coefficients (a, b, c) of a x + b y + c = 0 as one tuple, got "
                             f"{self.line!r} (write FollowLine((a, b, c), v=...))")
        a, b, c = as_vector(self.line, "line", 3)
        if math.hypot(a, b) == 0.0:
            raise InputError(f"line: a and b cannot both be zero, got {tuple(self.line)!r}")
        self.line = (float(a), float(b), float(c))
        self.v = as_scalar(self.v, "v")
        self.Kd = as_scalar(self.Kd, "Kd", nonnegative=True)
        self.Kh = as_scalar(self.Kh, "Kh", nonnegative=True)

    def distance(self, x: FloatVector) -> float:
        """Signed normal distance of the vehicle from the line ax + by + c = 0.

        Parameters
        ----------
        x : array_like, shape (3,)
            Vehicle pose (x, y, θ).

        Returns
        -------
        float
            The distance, m (positive on the side the line's normal (a, b) points to).
        """
        a, b, c = self.line
        return (a * x[0] + b * x[1] + c) / math.hypot(a, b)

    def __call__(self, t: float, x: FloatVector, dt: float = 0.0) -> tuple[float, float]:
        a, b, _ = self.line
        theta_star = math.atan2(-a, b)
        return self.v, -self.Kd * self.distance(x) + self.Kh * angdiff(theta_star, x[2])


class PurePursuit:
    """Chase a target moving along ``path(t) -> (x*, y*)`` at distance ``d_star`` (Lecture 9).

    Speed: PI on ``e = ‖p* − p‖ − d*``; steering: P on the heading to the target. Called as
    ``ctrl(t, x, dt) -> (v, γ)``; ``dt`` advances the integral.

    Parameters
    ----------
    path : callable
        ``path(t) -> (x*, y*)``: the target's position at time t (s), world frame (m).
    d_star : float
        Distance to keep behind the target (m).
    Kv : float
        Proportional speed gain (1/s).
    Ki : float
        Integral speed gain (1/s²).
    Kh : float
        Heading gain.
    """

    def __init__(self, path: Callable[[float], FloatVector], d_star: float = 1.0, Kv: float = 1.0, Ki: float = 0.3, Kh: float = 2.0) -> None:
        self.path, self.d_star, self.Kv, self.Ki, self.Kh = path, float(d_star), Kv, Ki, Kh
        self.integral = 0.0

    def error(self, t: float, x: FloatVector) -> float:
        """How far the vehicle is from where it should be: its distance to the path's point at time t,
        minus the following distance d*.

        Parameters
        ----------
        t : float
            Time, s.
        x : array_like, shape (3,)
            Vehicle pose (x, y, θ).

        Returns
        -------
        float
            The distance error, m (positive: lagging behind).
        """
        px, py = self.path(t)
        return math.hypot(px - x[0], py - x[1]) - self.d_star

    def __call__(self, t: float, x: FloatVector, dt: float = 0.0) -> tuple[float, float]:
        px, py = self.path(t)
        e = math.hypot(px - x[0], py - x[1]) - self.d_star
        self.integral += e * dt
        return self.Kv * e + self.Ki * self.integral, self.Kh * angdiff(math.atan2(py - x[1], px - x[0]), x[2])


@dataclass
class VehicleRun:
    """A simulated run of :func:`run_vehicle`.

    Attributes
    ----------
    t : (K,) ndarray
        Times (s), from 0 in steps of ``dt``.
    x : (K, 3) ndarray
        States (x, y, θ) (m, m, rad) at the times t.
    u : (K, 2) ndarray
        Inputs (v, γ) (m/s, rad) applied from t[k] to t[k+1] (the last row repeats the one before).
    """

    t: np.ndarray
    x: np.ndarray
    u: np.ndarray


def run_vehicle(model: BicycleModel, controller: Callable[[float, np.ndarray, float], FloatVector], x0: ArrayLike, T: float, dt: float = 0.05, stop: Callable[[float, np.ndarray], bool] | None = None) -> VehicleRun:
    """Run ``controller`` on ``model`` from ``x0`` for ``T`` s with control period ``dt``.

    Each period the controller's inputs are clipped to the model's limits and held, and the state
    advances along the exact arc (:meth:`BicycleModel.step`).

    Parameters
    ----------
    model : BicycleModel
        The vehicle.
    controller : callable
        ``controller(t, x, dt) -> (v, γ)``, e.g. :class:`MoveToPoint`.
    x0 : (3,) array_like
        Initial state (x, y, θ) (m, m, rad).
    T : float
        Duration (s, > 0).
    dt : float
        Control period (s, > 0).
    stop : callable, optional
        ``stop(t, x) -> bool`` ends the run early (e.g. goal reached).

    Returns
    -------
    VehicleRun
        ``.t`` (K,), ``.x`` (K, 3), ``.u`` (K, 2).

    Examples
    --------
    >>> run = run_vehicle(BicycleModel(), MoveToPoint((5.0, 5.0)), [0, 0, 0], T=30.0)
    >>> bool(np.hypot(*(run.x[-1, :2] - 5.0)) < 0.05)     # reached the goal
    True
    """
    x = as_vector(x0, "x0", 3).copy()
    T = as_scalar(T, "T", positive=True)
    dt = as_scalar(dt, "dt", positive=True)
    if T / dt > MAX_STEPS:  # a Python loop of that many steps would not end in any reasonable time
        raise InputError(f"T/dt: {T:g} s in steps of {dt:g} s is more than {MAX_STEPS} steps; robokit takes at most "
                         f"{MAX_STEPS}: raise dt or shorten T")
    n = int(math.ceil(T / dt))
    ts, xs, us = [0.0], [x.copy()], []
    for k in range(n):
        t = k * dt
        u = model.limit(controller(t, x, dt))
        us.append(u)
        x = model.step(x, u, dt)
        ts.append(t + dt)
        xs.append(x.copy())
        if stop is not None and stop(t + dt, x):
            break
    us.append(us[-1] if us else np.zeros(2))
    return VehicleRun(np.array(ts), np.array(xs), np.array(us))
