r"""Joint-space controllers of Lecture 8, all with one call shape.

Every controller is a small object called as ``tau = ctrl(t, q, dq, q_des, dq_des, ddq_des)``:
time t (s), measured joint angles q and rates dq (n,), desired q_d, q̇_d, q̈_d (n,); it
returns the joint torques τ (n,) (N·m, or N for prismatic joints). Controllers with
memory (an integral term) have ``reset()``; the simulator calls it at the start and
advances their state once per control period through ``update(dt, q, dq, q_des, dq_des)``.

With e = q_d − q and ė = q̇_d − q̇:

* :class:`IndependentJoint` — per-joint cascade of Lecture 8: a position loop P whose
  output, plus the velocity feedforward q̇_d, is the velocity reference of an inner P or PI
  velocity loop acting on a fixed nominal inertia J_nom per joint:
  ``τ = J_nom ⊙ (K_v (q̇_ref − q̇) + K_i ∫(q̇_ref − q̇) dt) [+ g(q)]``, ``q̇_ref = q̇_d + K_p e``.
  The nominal inertia does not change with the arm's pose — which is exactly why its
  performance varies over the workspace (Lecture 8).
* :class:`GravityPD` — what industrial controllers do: ``τ = K_p e + K_v ė + g(q)``.
* :class:`ModelFeedforward` — ``τ = τ_ff(q_d, q̇_d, q̈_d) + K_p e + K_v ė`` with τ_ff from
  inverse dynamics of the (estimated) model along the desired trajectory.
* :class:`ComputedTorque` — ``τ = M(q)(q̈_d + K_v ė + K_p e + K_i ∫e) + c(q, q̇) + g(q)``;
  with a perfect model the error obeys ``ë + K_v ė + K_p e (+ K_i ∫e) = 0``;
  ``K_v = 2√K_p`` is critical damping (the default when ``Kv`` is omitted).

The model-based controllers take a :class:`robokit.Robot` ``robot`` (their model) — pass a Robot with
wrong inertial parameters to study model error (the plant in the simulator is separate).
"""
from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import ArrayLike

from robokit._arrays import as_vector
from robokit.errors import InputError

if TYPE_CHECKING:
    from robokit.description.robot import Robot

__all__ = ["IndependentJoint", "GravityPD", "ModelFeedforward", "ComputedTorque", "gains"]


def gains(value: ArrayLike, n: int, name: str) -> np.ndarray:
    """A gain as an (n,) array: a scalar is broadcast; a vector must have length n; finite and ≥ 0
    (the one gain check of robokit's controllers and of the seed's computed torque)."""
    arr = np.asarray(value, dtype=float)
    if arr.ndim == 0:
        arr = np.full(n, float(arr))
    arr = as_vector(arr, name, n)
    if not np.isfinite(arr).all() or np.any(arr < 0):
        raise InputError(f"{name}: gains must be finite and non-negative, got {arr.tolist()}")
    return arr


class _Controller:
    n: int

    def reset(self) -> None:
        """Clear any internal state (integral terms)."""

    def update(self, dt: float, q: np.ndarray, dq: np.ndarray, q_des: np.ndarray, dq_des: np.ndarray) -> None:
        """Advance internal state by one control period ``dt`` (s)."""


class IndependentJoint(_Controller):
    """Independent joint control (Lecture 8): position P around a velocity P/PI loop.

    n : joint count; Kp : position-loop gain (1/s); Kv : velocity-loop gain (1/s);
    Ki : velocity-loop integral gain (1/s²), 0 for a P velocity loop;
    J_nom : (n,) fixed nominal inertia per joint (kg·m²);
    velocity_ff : add q̇_d to the velocity reference; gravity : a Robot whose gravity
    torques g(q) are fed forward (None: no gravity feedforward).
    """

    def __init__(self, n: int, Kp: ArrayLike, Kv: ArrayLike, J_nom: ArrayLike, Ki: ArrayLike = 0.0,
                 velocity_ff: bool = True, gravity: Robot | None = None) -> None:
        self.n = int(n)
        self.Kp, self.Kv, self.Ki = gains(Kp, self.n, "Kp"), gains(Kv, self.n, "Kv"), gains(Ki, self.n, "Ki")
        self.J_nom = gains(J_nom, self.n, "J_nom")
        self.velocity_ff = bool(velocity_ff)
        self.gravity = gravity
        self.reset()

    def reset(self) -> None:
        self.integral = np.zeros(self.n)

    def _vel_error(self, q: np.ndarray, dq: np.ndarray, q_des: np.ndarray, dq_des: np.ndarray) -> np.ndarray:
        dq_ref = self.Kp * (q_des - q) + (dq_des if self.velocity_ff else 0.0)
        return dq_ref - dq

    def update(self, dt: float, q: np.ndarray, dq: np.ndarray, q_des: np.ndarray, dq_des: np.ndarray) -> None:
        self.integral = self.integral + dt * self._vel_error(q, dq, q_des, dq_des)

    def __call__(self, t: float, q: np.ndarray, dq: np.ndarray, q_des: np.ndarray, dq_des: np.ndarray,
                 ddq_des: np.ndarray) -> np.ndarray:
        ev = self._vel_error(q, dq, q_des, dq_des)
        tau = self.J_nom * (self.Kv * ev + self.Ki * self.integral)
        if self.gravity is not None:
            tau = tau + self.gravity.gravity_torques(q)
        return tau


class GravityPD(_Controller):
    """PD with gravity compensation: ``τ = K_p e + K_v ė + g(q)`` (N·m/rad, N·m·s/rad)."""

    def __init__(self, robot: Robot, Kp: ArrayLike, Kv: ArrayLike) -> None:
        self.robot, self.n = robot, robot.n
        self.Kp, self.Kv = gains(Kp, self.n, "Kp"), gains(Kv, self.n, "Kv")

    def __call__(self, t: float, q: np.ndarray, dq: np.ndarray, q_des: np.ndarray, dq_des: np.ndarray,
                 ddq_des: np.ndarray) -> np.ndarray:
        return self.Kp * (q_des - q) + self.Kv * (dq_des - dq) + self.robot.gravity_torques(q)


class ModelFeedforward(_Controller):
    """Model-based feedforward plus PD: ``τ = ID(q_d, q̇_d, q̈_d) + K_p e + K_v ė``."""

    def __init__(self, robot: Robot, Kp: ArrayLike, Kv: ArrayLike) -> None:
        self.robot, self.n = robot, robot.n
        self.Kp, self.Kv = gains(Kp, self.n, "Kp"), gains(Kv, self.n, "Kv")

    def __call__(self, t: float, q: np.ndarray, dq: np.ndarray, q_des: np.ndarray, dq_des: np.ndarray,
                 ddq_des: np.ndarray) -> np.ndarray:
        return self.robot.rnea(q_des, dq_des, ddq_des) + self.Kp * (q_des - q) + self.Kv * (dq_des - dq)


class ComputedTorque(_Controller):
    """Computed torque (inverse dynamics control), optionally with an integral term.

    ``τ = M(q)(q̈_d + K_v ė + K_p e + K_i ∫e dt) + c(q, q̇) + g(q)`` with M, c, g of ``robot``
    (computed as one ``rnea(q, q̇, a)`` call). Kp in 1/s², Kv in 1/s (default 2√Kp,
    critical damping), Ki in 1/s³.
    """

    def __init__(self, robot: Robot, Kp: ArrayLike, Kv: ArrayLike | None = None, Ki: ArrayLike = 0.0) -> None:
        self.robot, self.n = robot, robot.n
        self.Kp = gains(Kp, self.n, "Kp")
        self.Kv = 2.0 * np.sqrt(self.Kp) if Kv is None else gains(Kv, self.n, "Kv")
        self.Ki = gains(Ki, self.n, "Ki")
        self.reset()

    def reset(self) -> None:
        self.integral = np.zeros(self.n)

    def update(self, dt: float, q: np.ndarray, dq: np.ndarray, q_des: np.ndarray, dq_des: np.ndarray) -> None:
        self.integral = self.integral + dt * (q_des - q)

    def __call__(self, t: float, q: np.ndarray, dq: np.ndarray, q_des: np.ndarray, dq_des: np.ndarray,
                 ddq_des: np.ndarray) -> np.ndarray:
        a = ddq_des + self.Kv * (dq_des - dq) + self.Kp * (q_des - q) + self.Ki * self.integral
        return self.robot.rnea(q, dq, a)
