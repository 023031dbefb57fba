r"""Closed-loop simulation of a Robot under a joint controller (Lecture 8).

The plant is the Robot's rigid-body model integrated with the articulated-body algorithm
(ABA): ``q̈ = FD(q, q̇, τ − τ_f(q̇) − Jᵀ F_tip)`` with optional joint friction
``τ_f = G²B q̇ + |G| T_c(sign q̇)`` (viscous and Coulomb, from the DH file's motor-side ``B``
and ``Tc`` referred through the gear ratio ``G``) and optional motor inertia reflected
through the gears, ``G² J_m``, added to the diagonal of M (Pinocchio's ``armature``). The
controller is sampled once per control period (the spacing of the desired trajectory's time
grid); the torque is held over the period while the plant is integrated with ``substeps``
fixed steps of RK4 (default) or explicit Euler.

With a built-in controller the loop runs compiled (:mod:`robokit.kernels.simulation`: the
course's ABA on the Robot's PoE model); with any other controller, or ``compiled=False``, in
Python over Pinocchio's ``aba``. Both give the same result to 1e-9.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING, Any, Callable, Iterable

import numpy as np
from numpy.typing import ArrayLike

from robokit._arrays import as_array, as_vector, kernel_array
from robokit.description.robot import check_robot_radians
from robokit.dynamics.drives import friction_torque, joint_drive_parameters
from robokit.dynamics.integration import second_order_step
from robokit.errors import InputError

if TYPE_CHECKING:
    from robokit.description.robot import Robot

__all__ = ["SimResult", "simulate"]


@dataclass
class SimResult:
    """Result of :func:`simulate`: arrays over the K control instants.

    ``error`` (K, n) is ``q_des − q``; ``rms_error()`` the (n,) RMS error per joint; ``plot()``
    draws :func:`robokit.control.plot_tracking`.

    Attributes
    ----------
    t : (K,) ndarray
        Control instants (s).
    q, dq : (K, n) ndarray
        Measured joint angles (rad) and rates (rad/s).
    tau : (K, n) ndarray
        Commanded torques (N·m), held over ``[t_k, t_k+1)``.
    q_des, dq_des : (K, n) ndarray
        The desired trajectory.

    Examples
    --------
    A hand-made result (two joints, three instants) whose second joint lags 0.1 rad:

    >>> t = np.array([0.0, 0.1, 0.2])
    >>> q_des = np.zeros((3, 2))
    >>> res = SimResult(t, q_des - [0.0, 0.1], np.zeros((3, 2)), np.zeros((3, 2)), q_des, np.zeros((3, 2)))
    >>> res
    SimResult(3 samples × 2 joints, t = 0 … 0.2 s, max |error| 0.1 rad)
    """

    t: np.ndarray
    q: np.ndarray
    dq: np.ndarray
    tau: np.ndarray
    q_des: np.ndarray
    dq_des: np.ndarray

    @property
    def error(self) -> np.ndarray:
        return self.q_des - self.q

    def rms_error(self) -> np.ndarray:
        """RMS tracking error per joint, ``sqrt(mean_k (q_des − q)²)``.

        Returns
        -------
        numpy.ndarray, shape (n,)
            rad (m for prismatic joints).

        Examples
        --------
        >>> res.rms_error().round(4)
        array([0. , 0.1])
        """
        return np.sqrt(np.mean(self.error**2, axis=0))

    def plot(self, joints: Iterable[int] | None = None, title: str | None = None) -> Any:
        """Desired and actual joint angles, the tracking error and the torques, stacked.

        See :func:`robokit.control.plot_tracking` (needs the ``plot`` extra, matplotlib).

        Parameters
        ----------
        joints : iterable of int, optional
            The joints drawn (default all).
        title : str, optional
            The figure's title.

        Returns
        -------
        matplotlib.figure.Figure
            The figure (three rows of axes).

        Examples
        --------
        >>> import matplotlib
        >>> matplotlib.use("Agg")
        >>> fig = res.plot(title="two joints")
        >>> type(fig).__name__
        'Figure'
        """
        from robokit.control.plot import plot_tracking

        return plot_tracking(self, joints=joints, title=title)

    def __repr__(self) -> str:
        K, n = self.q.shape
        if K == 0:
            return "SimResult(empty)"
        worst = float(np.abs(self.error).max())
        return f"SimResult({K} samples × {n} joints, t = {self.t[0]:g} … {self.t[-1]:g} s, max |error| {worst:.3g} rad)"


def _drive_parameters(robot: Robot) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(B, Tc, armature) of the Robot's drives referred to the joints, zeros without a DH table."""
    dh = getattr(robot, "dh", None)
    if dh is None:
        n = robot.n
        return np.zeros(n), np.zeros((n, 2)), np.zeros(n)
    return joint_drive_parameters(dh)


def _desired(trajectory: Any) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """(t, q_des, dq_des, ddq_des) from a Trajectory-like object or a tuple."""
    if isinstance(trajectory, tuple):
        t, q_des, dq_des, ddq_des = trajectory
    else:
        t, q_des = trajectory.t, trajectory.q
        dq_des = getattr(trajectory, "qd", None)  # a Trajectory's qd is its velocity
        ddq_des = getattr(trajectory, "qdd", None)
    t = as_vector(t, "trajectory.t")
    q_des = as_array(q_des, "trajectory.q", (len(t), None))
    dq_des = np.zeros_like(q_des) if dq_des is None else as_array(dq_des, "trajectory.qd", q_des.shape)
    ddq_des = np.zeros_like(q_des) if ddq_des is None else as_array(ddq_des, "trajectory.qdd", q_des.shape)
    if len(t) < 2:
        raise InputError("trajectory: needs at least two samples")
    steps = np.diff(t)
    if np.any(steps <= 0):
        raise InputError("trajectory.t: times must increase strictly")
    if np.ptp(steps) > 1e-9 * max(1.0, steps.mean()):
        raise InputError("trajectory.t: the control grid must be uniform (one control period)")
    return t, q_des, dq_des, ddq_des


def simulate(robot: Robot, controller: Callable[..., ArrayLike], trajectory: Any, q0: ArrayLike | None = None,
             dq0: ArrayLike | None = None, *, substeps: int = 1, method: str = "rk4", friction: bool = False,
             motor_inertia: bool = False, Ftip: ArrayLike | None = None, compiled: bool = True) -> SimResult:
    """Simulate ``robot`` under ``controller`` tracking ``trajectory`` (Lecture 8).

    The plant is the robot's rigid-body model integrated with the articulated-body algorithm (see
    the module docstring); the controller is sampled once per control period and its torque held
    while the plant takes ``substeps`` RK4 (or Euler) steps.

    Parameters
    ----------
    robot : Robot
        The plant (:class:`robokit.Robot`).
    controller : callable
        Called as ``controller(t, q, dq, q_des, dq_des, ddq_des) -> tau`` (see
        :mod:`robokit.control.controllers`); ``reset()``/``update(...)`` are called when present.
    trajectory : Trajectory or tuple
        An object with ``t`` (K,), ``q``, ``qd``, ``qdd`` (K, n) on a uniform grid (a
        :class:`~robokit.trajectory.Trajectory`), or a tuple ``(t, q_des, dq_des, ddq_des)``; the grid
        spacing is the control period (s).
    q0, dq0 : (n,) array_like, optional
        Initial state (default: the desired state at t₀).
    substeps : int, optional
        Plant integration steps per control period; default 1.
    method : {"rk4", "euler"}, optional
        Plant integrator; default "rk4".
    friction, motor_inertia : bool, optional
        Include the DH file's joint friction and reflected motor inertia ``G² J_m``; default False.
    Ftip : (K, 6) array_like, optional
        Wrench history ``(m, f)`` applied *by* the tip on the environment, in the tip frame (Modern
        Robotics' Ftip), resisted through ``J_bᵀ F``.
    compiled : bool, optional
        With one of the built-in controllers (:class:`~robokit.control.GravityPD`,
        :class:`~robokit.control.ModelFeedforward`, :class:`~robokit.control.ComputedTorque`,
        :class:`~robokit.control.IndependentJoint`) the whole loop steps inside one compiled kernel
        (:mod:`robokit.kernels.simulation`), agreeing with the Python loop over Pinocchio to 1e-9; any
        other controller, or ``compiled=False``, runs the Python loop. The compiled loop does not
        write the controller's integral state back.

    Returns
    -------
    SimResult
        ``t``, ``q``, ``dq``, ``tau``, ``q_des``, ``dq_des`` over the K control instants.

    Raises
    ------
    DivergenceError
        When the state blows up (the result so far in ``.partial``).
    InputError
        On a bad trajectory, option or controller output.

    Examples
    --------
    Computed torque with Kp = 100 (critically damped, ω = 10 rad/s) pulls the planar arm back from a
    0.1 rad error within 1 s (the Python loop here; the default compiled loop gives the same):

    >>> robot = rk.load("twolink")
    >>> t = np.arange(0, 1.0 + 1e-9, 0.01)
    >>> hold = np.zeros((len(t), 2))
    >>> from robokit.control import ComputedTorque
    >>> res = simulate(robot, ComputedTorque(robot, Kp=100.0), (t, hold, hold, hold), q0=[0.1, 0.0],
    ...                compiled=False)
    >>> res.q.shape, bool(abs(res.error[-1]).max() < 1e-3)
    ((101, 2), True)
    """
    import pinocchio as pin

    t, q_des, dq_des, ddq_des = _desired(trajectory)
    n = robot.n
    if q_des.shape[1] != n:
        raise InputError(f"trajectory.q: expected {n} joint columns for {robot.name}, got {q_des.shape[1]}")
    if method not in ("rk4", "euler"):
        raise InputError(f"method: expected 'rk4' or 'euler', got {method!r}")
    substeps = int(substeps)
    if substeps < 1:
        raise InputError(f"substeps: expected a positive integer, got {substeps}")
    q = q_des[0].copy() if q0 is None else as_vector(q0, "q0", n).copy()
    if not check_robot_radians(robot, q_des, "trajectory.q") and q0 is not None:  # states: may wind
        check_robot_radians(robot, q, "q0")
    dq = dq_des[0].copy() if dq0 is None else as_vector(dq0, "dq0", n).copy()
    K = len(t)
    F = None if Ftip is None else as_array(Ftip, "Ftip", (K, 6))
    B, Tc, arm = _drive_parameters(robot)
    use_fric = friction and (np.any(B) or np.any(Tc))
    model, data = robot.model, robot.model.createData()
    arm_v = np.zeros(model.nv)
    if motor_inertia and np.any(arm):
        model = model.copy()
        arm_v[: n] = arm  # the chain's velocity coordinates are the joint rates, in order
        model.armature = arm_v
        data = model.createData()
    same_coords = model.nq == model.nv == n
    kind = _compiled_kind(controller, n) if compiled and getattr(robot, "poe", None) is not None else None
    if kind is not None:
        plant_arm = arm_v[:n] if (motor_inertia and np.any(arm)) else np.asarray(robot.model.armature, float)[:n]
        return _simulate_compiled(robot, controller, kind, t, q, dq, q_des, dq_des, ddq_des, F, B, Tc,
                                  bool(use_fric), plant_arm, substeps, method)

    def accel(qa: np.ndarray, dqa: np.ndarray, tau: np.ndarray) -> np.ndarray:
        if use_fric:
            tau = tau - friction_torque(dqa, B, Tc)
        qp = qa if same_coords else robot.q_pin(qa)
        return pin.aba(model, data, qp, dqa, tau)

    h = (t[1] - t[0]) / substeps
    Q, DQ, TAU = np.empty((K, n)), np.empty((K, n)), np.empty((K, n))
    if hasattr(controller, "reset"):
        controller.reset()
    for k in range(K):
        Q[k], DQ[k] = q, dq
        tau = np.asarray(controller(t[k], q, dq, q_des[k], dq_des[k], ddq_des[k]), dtype=float)
        if tau.shape != (n,) or not np.all(np.isfinite(tau)):
            raise InputError(f"controller: returned {tau!r} at t = {t[k]:g} s; expected {n} finite torques")
        TAU[k] = tau
        if k == K - 1:
            break
        tau_plant = tau
        if F is not None and np.any(F[k]):
            Jb = robot.jacobian(q, None, reference="local")
            tau_plant = tau - Jb.T @ F[k]
        if hasattr(controller, "update"):
            controller.update(t[k + 1] - t[k], q, dq, q_des[k], dq_des[k])
        def plant(_t: float, qa: np.ndarray, dqa: np.ndarray, tau_plant: np.ndarray = tau_plant) -> np.ndarray:
            return accel(qa, dqa, tau_plant)

        for _ in range(substeps):
            q, dq = second_order_step(plant, t[k], q, dq, h, method)
        if not (np.all(np.isfinite(q)) and np.all(np.isfinite(dq))) or np.abs(dq).max() > 1e6:
            from robokit.errors import DivergenceError

            partial = SimResult(t[: k + 1].copy(), Q[: k + 1], DQ[: k + 1], TAU[: k + 1], q_des[: k + 1].copy(),
                                dq_des[: k + 1].copy())
            raise DivergenceError(
                f"simulate: the integration diverged at t = {t[k + 1]:g} s (a stiff plant or controller for a "
                f"step of {h:g} s); use more substeps or smaller gains (the result so far is in .partial)",
                partial)
    return SimResult(t.copy(), Q, DQ, TAU, q_des.copy(), dq_des.copy())


def _compiled_kind(controller: Any, n: int) -> int | None:
    """The compiled kernel's code for a built-in controller over a Robot with PoE parameters, else None."""
    from robokit.control.controllers import ComputedTorque, GravityPD, IndependentJoint, ModelFeedforward

    kinds = {GravityPD: 0, ModelFeedforward: 1, ComputedTorque: 2, IndependentJoint: 3}
    kind = kinds.get(type(controller))
    if kind is None:
        return None
    model_robot = controller.gravity if kind == 3 else controller.robot
    if model_robot is not None and (getattr(model_robot, "poe", None) is None or getattr(model_robot, "n", -1) != n):
        return None
    return kind


def _simulate_compiled(robot: Robot, controller: Any, kind: int, t: np.ndarray, q: np.ndarray, dq: np.ndarray,
                       q_des: np.ndarray, dq_des: np.ndarray, ddq_des: np.ndarray, F: np.ndarray | None,
                       B: np.ndarray, Tc: np.ndarray, use_fric: bool, arm: np.ndarray, substeps: int,
                       method: str) -> SimResult:
    """:func:`simulate` for a built-in controller, stepped by :func:`robokit.kernels.simulation.simulate_robot`."""
    from robokit.kernels.simulation import simulate_robot

    c = kernel_array  # C-contiguous and writeable, as the kernel's signature takes it
    n, K = robot.n, len(t)
    p = robot.poe
    model_robot = controller.gravity if kind == 3 else controller.robot
    use_gravity = int(model_robot is not None)
    mr = model_robot if model_robot is not None else robot
    pc = mr.poe
    zeros = np.zeros(n)
    Ki = getattr(controller, "Ki", zeros)
    J_nom = getattr(controller, "J_nom", zeros)
    Fk = np.zeros((K, 6)) if F is None else F
    Q, DQ, TAU, status = simulate_robot(
        c(q, float), c(dq, float), c(t, float), c(q_des, float), c(dq_des, float), c(ddq_des, float),
        c(p.Mlist, float), c(p.Glist, float), c(p.Slist, float), c(robot.gravity, float), c(arm, float),
        c(B, float), c(np.asarray(Tc, float).reshape(n, 2)), int(use_fric), c(Fk, float), kind,
        c(pc.Mlist, float), c(pc.Glist, float), c(pc.Slist, float), c(mr.gravity, float),
        c(np.asarray(mr.model.armature, float)[:n]), c(controller.Kp, float), c(controller.Kv, float), c(Ki, float),
        c(J_nom, float), int(getattr(controller, "velocity_ff", False)), use_gravity, int(substeps),
        0 if method == "rk4" else 1)
    if status < -1:
        k = -int(status) - 2
        raise InputError(f"controller: returned {TAU[k]!r} at t = {t[k]:g} s; expected {n} finite torques")
    if status >= 0:
        from robokit.errors import DivergenceError

        k = int(status)
        h = (t[1] - t[0]) / substeps
        partial = SimResult(t[: k + 1].copy(), Q[: k + 1], DQ[: k + 1], TAU[: k + 1], q_des[: k + 1].copy(),
                            dq_des[: k + 1].copy())
        raise DivergenceError(
            f"simulate: the integration diverged at t = {t[k + 1]:g} s (a stiff plant or controller for a "
            f"step of {h:g} s); use more substeps or smaller gains (the result so far is in .partial)", partial)
    return SimResult(t.copy(), Q, DQ, TAU, q_des.copy(), dq_des.copy())
