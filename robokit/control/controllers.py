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
    """A gain as an (n,) array: a scalar is broadcast; a vector must have length n.

    The one gain check of robokit's controllers and of the seed's computed torque.

    Parameters
    ----------
    value : float or (n,) array_like
        The gain(s), finite and non-negative.
    n : int
        Number of joints.
    name : str
        Argument name for the error message.

    Returns
    -------
    (n,) ndarray
        One gain per joint.

    Raises
    ------
    InputError
        On a wrong length, or a negative or non-finite gain.

    Examples
    --------
    >>> gains(2.0, 3, "Kp")
    array([2., 2., 2.])
    """
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


class _IntegralController(_Controller):
    """A controller with an integral term ``self.integral`` = ∫ε dt of an error ε of the law
    (``_integrand``): the position error for computed torque, the velocity-loop error for
    independent joint control."""

    def _integrand(self, q: np.ndarray, dq: np.ndarray, q_des: np.ndarray, dq_des: np.ndarray) -> np.ndarray:
        raise NotImplementedError  # pragma: no cover - every subclass defines it

    def reset(self) -> None:
        """Clear the integral term (``self.integral`` = 0)."""
        self.integral = np.zeros(self.n)

    def update(self, dt: float, q: np.ndarray, dq: np.ndarray, q_des: np.ndarray, dq_des: np.ndarray) -> None:
        """Advance the integral of the law's error ε by one step (rectangle rule): ``∫ε += ε dt``.

        ε is the velocity-loop error ``q̇_ref − q̇`` for :class:`IndependentJoint` and the position
        error ``q_d − q`` for :class:`ComputedTorque` (which does not use ``dq``, ``dq_des`` here).

        Parameters
        ----------
        dt : float
            The time step, s.
        q, dq : ndarray, shape (n,)
            Measured joint positions (rad / m) and velocities.
        q_des, dq_des : ndarray, shape (n,)
            Desired positions and velocities.

        Returns
        -------
        None
            ``self.integral`` is updated.
        """
        self.integral = self.integral + dt * self._integrand(q, dq, q_des, dq_des)


class _PDController(_Controller):
    """A PD law on a model ``robot`` with gains ``Kp``, ``Kv`` (n,) and no internal state."""

    def __init__(self, robot: Robot, Kp: ArrayLike, Kv: ArrayLike) -> None:
        self.robot, self.n = robot, robot.n
        self.Kp, self.Kv = gains(Kp, self.n, "Kp"), gains(Kv, self.n, "Kv")


class IndependentJoint(_IntegralController):
    """Independent joint control (Lecture 8): position P around a velocity P/PI loop.

    ``τ = J_nom ⊙ (K_v (q̇_ref − q̇) + K_i ∫(q̇_ref − q̇) dt) [+ g(q)]`` with
    ``q̇_ref = K_p e [+ q̇_d]``. Call as ``tau = ctrl(t, q, dq, q_des, dq_des, ddq_des)``.

    Parameters
    ----------
    n : int
        Number of joints.
    Kp : float or (n,) array_like
        Position-loop gain (1/s).
    Kv : float or (n,) array_like
        Velocity-loop gain (1/s).
    J_nom : float or (n,) array_like
        Fixed nominal inertia per joint (kg·m²).
    Ki : float or (n,) array_like, optional
        Velocity-loop integral gain (1/s²); 0 (default) for a P velocity loop.
    velocity_ff : bool, optional
        Add q̇_d to the velocity reference; default True.
    gravity : Robot, optional
        A robot whose gravity torques g(q) are fed forward; None (default) for none.

    Examples
    --------
    0.1 rad behind on joint 1 with Kp = 10 asks for 1 rad/s; Kv = 50 on J_nom = 6.86 kg·m² makes
    343 N·m:

    >>> ctrl = IndependentJoint(2, Kp=10, Kv=50, J_nom=[6.86, 0.96])
    >>> z = np.zeros(2)
    >>> ctrl(0.0, z, z, [0.1, 0], z, z)
    array([343.,   0.])
    """

    def __init__(self, n: int, Kp: ArrayLike, Kv: ArrayLike, J_nom: ArrayLike, Ki: ArrayLike = 0.0,
                 velocity_ff: bool = True, gravity: Robot | None = None) -> None:
        self.n = int(n)
        self.Kp, self.Kv, self.Ki = gains(Kp, self.n, "Kp"), gains(Kv, self.n, "Kv"), gains(Ki, self.n, "Ki")
        self.J_nom = gains(J_nom, self.n, "J_nom")
        self.velocity_ff = bool(velocity_ff)
        self.gravity = gravity
        self.reset()

    def _integrand(self, q: np.ndarray, dq: np.ndarray, q_des: np.ndarray, dq_des: np.ndarray) -> np.ndarray:
        # the velocity-loop error q̇_ref − q̇, q̇_ref = K_p e [+ q̇_d]
        dq_ref = self.Kp * (q_des - q) + (dq_des if self.velocity_ff else 0.0)
        return dq_ref - dq

    def __call__(self, t: float, q: np.ndarray, dq: np.ndarray, q_des: np.ndarray, dq_des: np.ndarray,
                 ddq_des: np.ndarray) -> np.ndarray:
        ev = self._integrand(q, dq, q_des, dq_des)
        tau = self.J_nom * (self.Kv * ev + self.Ki * self.integral)
        if self.gravity is not None:
            tau = tau + self.gravity.gravity_torques(q)
        return tau


class GravityPD(_PDController):
    """PD with gravity compensation (Lecture 8): ``τ = K_p e + K_v ė + g(q)``.

    Call as ``tau = ctrl(t, q, dq, q_des, dq_des, ddq_des)``.

    Parameters
    ----------
    robot : Robot
        The model whose gravity torques are compensated.
    Kp : float or (n,) array_like
        Position gain (N·m/rad).
    Kv : float or (n,) array_like
        Velocity gain (N·m·s/rad).

    Examples
    --------
    The planar two-link arm horizontal, 0.1 rad short on joint 1: ``50 × 0.1`` plus its gravity
    torques (46.107, 11.772):

    >>> robot = rk.load("twolink")
    >>> z = np.zeros(2)
    >>> GravityPD(robot, Kp=50, Kv=10)(0.0, z, z, [0.1, 0], z, z).round(4)
    array([51.107, 11.772])
    """

    def __call__(self, t: float, q: np.ndarray, dq: np.ndarray, q_des: np.ndarray, dq_des: np.ndarray,
                 ddq_des: np.ndarray) -> np.ndarray:
        return self.Kp * (q_des - q) + self.Kv * (dq_des - dq) + self.robot.gravity_torques(q)


class ModelFeedforward(_PDController):
    """Model-based feedforward plus PD (Lecture 8): ``τ = ID(q_d, q̇_d, q̈_d) + K_p e + K_v ė``.

    Call as ``tau = ctrl(t, q, dq, q_des, dq_des, ddq_des)``.

    Parameters
    ----------
    robot : Robot
        The (estimated) model whose inverse dynamics ``robot.rnea`` gives the feedforward.
    Kp, Kv : float or (n,) array_like
        As for :class:`GravityPD`.

    Examples
    --------
    On the desired path (e = 0) it is inverse dynamics alone: for the planar arm horizontal with
    q̈_d = (1, 0), ``M(0)[:, 0] + g(0) = (6.86 + 46.107, 2.16 + 11.772)``:

    >>> robot = rk.load("twolink")
    >>> z = np.zeros(2)
    >>> ModelFeedforward(robot, Kp=50, Kv=10)(0.0, z, z, z, z, [1.0, 0]).round(4)
    array([52.967, 13.932])
    """

    def __call__(self, t: float, q: np.ndarray, dq: np.ndarray, q_des: np.ndarray, dq_des: np.ndarray,
                 ddq_des: np.ndarray) -> np.ndarray:
        return self.robot.rnea(q_des, dq_des, ddq_des) + self.Kp * (q_des - q) + self.Kv * (dq_des - dq)


class ComputedTorque(_IntegralController):
    """Computed torque (inverse dynamics control, Lecture 8), optionally with an integral term.

    ``τ = M(q)(q̈_d + K_v ė + K_p e + K_i ∫e dt) + c(q, q̇) + g(q)`` with M, c, g of ``robot``
    (computed as one ``rnea(q, q̇, a)`` call); with a perfect model the error obeys
    ``ë + K_v ė + K_p e (+ K_i ∫e) = 0``. Call as ``tau = ctrl(t, q, dq, q_des, dq_des, ddq_des)``.

    Parameters
    ----------
    robot : Robot
        The controller's (estimated) model.
    Kp : float or (n,) array_like
        Position gain (1/s²).
    Kv : float or (n,) array_like, optional
        Velocity gain (1/s); default ``2√Kp`` (critical damping).
    Ki : float or (n,) array_like, optional
        Integral gain (1/s³); default 0.

    Examples
    --------
    Kp = 100 gives Kv = 20; 0.1 rad short on joint 1 of the horizontal planar arm:
    ``τ = M(0) (10, 0) + g(0)``:

    >>> robot = rk.load("twolink")
    >>> ctrl = ComputedTorque(robot, Kp=100.0)
    >>> ctrl.Kv
    array([20., 20.])
    >>> z = np.zeros(2)
    >>> ctrl(0.0, z, z, [0.1, 0], z, z).round(4)
    array([114.707,  33.372])
    """

    def __init__(self, robot: Robot, Kp: ArrayLike, Kv: ArrayLike | None = None, Ki: ArrayLike = 0.0) -> None:
        self.robot, self.n = robot, robot.n
        self.Kp = gains(Kp, self.n, "Kp")
        self.Kv = 2.0 * np.sqrt(self.Kp) if Kv is None else gains(Kv, self.n, "Kv")
        self.Ki = gains(Ki, self.n, "Ki")
        self.reset()

    def _integrand(self, q: np.ndarray, dq: np.ndarray, q_des: np.ndarray, dq_des: np.ndarray) -> np.ndarray:
        return q_des - q  # the position error e, integrated to ∫e dt

    def __call__(self, t: float, q: np.ndarray, dq: np.ndarray, q_des: np.ndarray, dq_des: np.ndarray,
                 ddq_des: np.ndarray) -> np.ndarray:
        a = ddq_des + self.Kv * (dq_des - dq) + self.Kp * (q_des - q) + self.Ki * self.integral
        return self.robot.rnea(q, dq, a)
