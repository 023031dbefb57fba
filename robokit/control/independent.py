r"""Independent joint control through the motor model, with the disturbance from the other joints
(Lecture 8).

Each joint j is a DC motor (``i = K_a u``, ``τ_m = K_m i``) behind a gearbox G_j, driving the arm:
the plant is the full arm with its drives (:func:`robokit.forward_dynamics_with_drives`),

    (M(q) + diag(G² J_m)) q̈ + c(q, q̇) + g(q) + G² B_m q̇ + |G| T_c = G K_m K_a u.

Each joint's controller sees only its own motor (Lecture 8's cascade), motor side
(``ω = G q̇``):

    position loop   q̇*_j = K_p,j (q_d,j − q_j) + q̇_d,j          (velocity feedforward)
    velocity loop   u_j  = K_v,j (G_j q̇*_j − ω_j) + K_i,j ∫(G_j q̇*_j − ω_j) dt  [+ g_j(q) / (G_j K_m K_a)]

(the bracket: optional gravity feedforward, Lecture 8's "torque feedforward"). The single-joint
model the loop is designed for is ``(J_m + M_jj/G²) ω̇ + B_m ω = K_m K_a u − τ_d`` (transfer function
``K_m K_a / (J s + B)``); everything else is the **disturbance** seen by motor j,

    τ_d,j = (1/G_j) (Σ_{k≠j} M_jk q̈_k + c_j(q, q̇) + g_j(q) + |G_j| T_c,j),

gravity, velocity coupling and acceleration coupling from the other joints (and Coulomb friction).
:func:`simulate_independent_joints` records it.

With P loops (K_i = 0) a constant disturbance leaves the steady-state position error
``e_j = τ_d,j G_j / (G_j² K_m K_a K_v,j K_p,j)``; with K_i > 0 (a type-1 loop) it goes to zero.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import ArrayLike

from robokit.errors import DivergenceError
from robokit._arrays import as_scalar, as_vector
from robokit.control.controllers import gains
from robokit.control.simulate import _desired
from robokit.dynamics.drives import drive_parameters, forward_dynamics_with_drives
from robokit.errors import InputError

if TYPE_CHECKING:
    from robokit.description.robot import Robot

__all__ = ["IndependentJointRun", "simulate_independent_joints"]


@dataclass
class IndependentJointRun:
    """Result of :func:`simulate_independent_joints`, arrays over the K control instants.

    ``error`` (K, n) is ``q_des − q`` (rad).

    Attributes
    ----------
    t : (K,) ndarray
        Control instants (s).
    q, dq : (K, n) ndarray
        Joint angles (rad) and rates (rad/s).
    u : (K, n) ndarray
        Motor voltages (V), held over each period.
    q_des, dq_des : (K, n) ndarray
        The desired trajectory.
    disturbance : (K, n) ndarray
        The disturbance torque each motor sees (N·m, motor side; see the module docstring).
    effective_inertia : (K, n) ndarray
        ``J_m + M_jj(q)/G²`` along the run (kg·m², motor side).
    """

    t: np.ndarray
    q: np.ndarray
    dq: np.ndarray
    u: np.ndarray
    q_des: np.ndarray
    dq_des: np.ndarray
    disturbance: np.ndarray
    effective_inertia: np.ndarray

    @property
    def error(self) -> np.ndarray:
        """(K, n) ``q_des − q`` (rad)."""
        return self.q_des - self.q


def simulate_independent_joints(robot: Robot, trajectory: Any, Kp: ArrayLike, Kv: ArrayLike, Ki: ArrayLike = 0.0, *,
                                Ka: float = 1.0, Km: float = 0.228, gravity_ff: bool = False,
                                q0: ArrayLike | None = None, dq0: ArrayLike | None = None, substeps: int = 2,
                                coulomb: bool = True) -> IndependentJointRun:
    """Simulate independent joint control of a DH robot with drive data along a trajectory (Lecture 8).

    See the module docstring for the loops and the disturbance each motor sees.

    Parameters
    ----------
    robot : Robot
        A :class:`robokit.Robot` with a DH table carrying drive data (Jm, G, B, Tc per link).
    trajectory : Trajectory or tuple
        An object with ``t``, ``q``, ``qd``, ``qdd`` on a uniform grid (the control period), or a
        tuple ``(t, q, qd, qdd)``.
    Kp : float or (n,) array_like
        Position-loop gain (1/s).
    Kv : float or (n,) array_like
        Velocity-loop gain (V·s/rad, motor side).
    Ki : float or (n,) array_like, optional
        Velocity-loop integral gain (V/rad); default 0.
    Ka : float, optional
        Amplifier gain (A/V); default 1.
    Km : float, optional
        Torque constant (N·m/A); default 0.228 (the value Corke quotes for the PUMA's joint motors;
        illustrative, the same for every joint).
    gravity_ff : bool, optional
        Add ``g_j(q)/(G_j K_m K_a)`` to u; default False.
    q0, dq0 : (n,) array_like, optional
        Start (default the desired start).
    substeps : int, optional
        RK4 plant steps per control period; default 2.
    coulomb : bool, optional
        Include Coulomb friction in the plant; default True.

    Returns
    -------
    IndependentJointRun
        State, voltages, the disturbances and effective inertias over the run.

    Raises
    ------
    DivergenceError
        When the loop blows up — velocity-loop gains too high for the control period (the run so far
        in ``.partial``; at a 5 ms period Kv = 0.2 diverges on the PUMA 560).
    InputError
        On bad arguments.

    Examples
    --------
    A 0.2 s quintic move of the PUMA 560 at a 5 ms control period; a P velocity loop lags the path:

    >>> puma = rk.load("puma560")
    >>> t = np.arange(0, 0.2 + 1e-9, 0.005)
    >>> from robokit.trajectory import quintic_trajectory
    >>> traj = quintic_trajectory(np.zeros(6), [0.1, 0.1, -0.1, 0, 0, 0], 0.2, t=t)
    >>> run = simulate_independent_joints(puma, traj, Kp=10, Kv=0.05)
    >>> run.q.shape, run.disturbance.shape, bool(abs(run.error).max() > 0)
    ((41, 6), (41, 6), True)
    """
    t, qd, dqd, ddqd = _desired(trajectory)
    n = robot.n
    if qd.shape[1] != n:
        raise InputError(f"trajectory.q: expected {n} joint columns for {robot.name}, got {qd.shape[1]}")
    Kp, Kv, Ki = gains(Kp, n, "Kp"), gains(Kv, n, "Kv"), gains(Ki, n, "Ki")
    Ka = as_scalar(Ka, "Ka", positive=True)
    Km = as_scalar(Km, "Km", positive=True)
    substeps = int(substeps)
    if substeps < 1:
        raise InputError(f"substeps: expected a positive integer, got {substeps}")
    Jm, G, B, Tc = drive_parameters(robot)
    q = qd[0].copy() if q0 is None else as_vector(q0, "q0", n).copy()
    dq = dqd[0].copy() if dq0 is None else as_vector(dq0, "dq0", n).copy()
    K = len(t)
    Q, DQ, U, D, JE = (np.empty((K, n)) for _ in range(5))
    integral = np.zeros(n)

    def accel(q: np.ndarray, dq: np.ndarray, u: np.ndarray) -> np.ndarray:
        return forward_dynamics_with_drives(robot, q, dq, G * Km * Ka * u, coulomb=coulomb)

    for k in range(K):
        dq_ref = Kp * (qd[k] - q) + dqd[k]
        ev = G * (dq_ref - dq)  # motor-side velocity error
        u = Kv * ev + Ki * integral
        if gravity_ff:
            u = u + robot.gravity_torques(q) / (G * Km * Ka)
        # record the state, the voltage and the disturbance each motor sees
        M = robot.crba(q)
        ddq = accel(q, dq, u)
        tau_joint = robot.rnea(q, dq, ddq) - np.diag(M) * ddq  # coupling + c + g
        if coulomb:
            tau_joint = tau_joint + np.abs(G) * np.where(dq > 0, Tc[:, 0], np.where(dq < 0, Tc[:, 1], 0.0))
        Q[k], DQ[k], U[k], D[k], JE[k] = q, dq, u, tau_joint / G, Jm + np.diag(M) / (G * G)
        if k == K - 1:
            break
        h = (t[k + 1] - t[k]) / substeps
        for _ in range(substeps):
            a1 = accel(q, dq, u)
            a2 = accel(q + 0.5 * h * dq, dq + 0.5 * h * a1, u)
            a3 = accel(q + 0.5 * h * (dq + 0.5 * h * a1), dq + 0.5 * h * a2, u)
            a4 = accel(q + h * (dq + 0.5 * h * a2), dq + h * a3, u)
            q = q + h * dq + h * h / 6 * (a1 + a2 + a3)
            dq = dq + h / 6 * (a1 + 2 * a2 + 2 * a3 + a4)
            if not (np.all(np.isfinite(q)) and np.all(np.isfinite(dq))) or np.abs(dq).max() > 1e6:
                partial = IndependentJointRun(t[: k + 1].copy(), Q[: k + 1], DQ[: k + 1], U[: k + 1],
                                              qd[: k + 1].copy(), dqd[: k + 1].copy(), D[: k + 1], JE[: k + 1])
                raise DivergenceError(
                    f"simulate_independent_joints: the loop diverged at t = {t[k + 1]:g} s (gains too high for "
                    f"the control period {t[k + 1] - t[k]:g} s, or too few substeps); lower Kv/Kp or raise "
                    f"substeps (the run so far is in .partial)", partial)
        integral = integral + (t[k + 1] - t[k]) * ev
    return IndependentJointRun(t, Q, DQ, U, qd, dqd, D, JE)
