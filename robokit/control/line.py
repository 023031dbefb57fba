r"""Resolved-rate control of the tool along a straight line (Lecture 6).

:func:`track_line` moves the tool from where it is to ``p_goal`` on a straight line, the desired
position timed by a quintic (:func:`robokit.trajectory.quintic_trajectory`), the orientation held;
each step commands the twist ``V = (K e_ω, ṗ_des + K e_p)`` and integrates
``q̇ = resolved_rate(J, V)`` (:func:`robokit.kinematics.resolved_rate`, Euler step dt), with an
optional null-space push away from the joint limits (``null_gain``,
:func:`robokit.kinematics.joint_limit_gradient`).
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import ArrayLike

from robokit._arrays import as_scalar, as_vector
from robokit.kinematics.velocity import joint_limit_gradient, resolved_rate
from robokit.errors import InputError
from robokit.trajectory.core import MAX_SAMPLES
from robokit.trajectory.polynomial import quintic_trajectory

if TYPE_CHECKING:
    from robokit.description.robot import Robot

__all__ = ["LineTrackingResult", "track_line"]


@dataclass
class LineTrackingResult:
    """Result of :func:`track_line`, over the K + 1 control steps.

    Attributes
    ----------
    t : (K+1,) ndarray
        Times (s).
    q : (K+1, n) ndarray
        Joint values (rad).
    p : (K+1, 3) ndarray
        Actual tool positions, base frame (m).
    p_des : (K+1, 3) ndarray
        Desired positions on the line (m).
    error : (K+1,) ndarray
        ``‖p_des − p‖`` (m).
    """

    t: np.ndarray
    q: np.ndarray
    p: np.ndarray
    p_des: np.ndarray
    error: np.ndarray


def track_line(robot: Robot, q0: ArrayLike, p_goal: ArrayLike, duration: float, dt: float = 0.005,
               method: str = "dls", gain: float = 5.0, damping: float = 0.02, null_gain: float = 0.0,
               frame: str | None = None) -> LineTrackingResult:
    """Resolved-rate control of the tool along a straight line to ``p_goal`` (Lecture 6).

    The desired position is timed by a quintic, the orientation held; each step commands
    ``V = (K e_ω, ṗ_des + K e_p)`` and integrates ``q̇ = resolved_rate(J, V)`` with an Euler step
    (see the module docstring).

    Parameters
    ----------
    robot : Robot
        A :class:`robokit.Robot`.
    q0 : (n,) array_like
        Start configuration (rad); the line starts at its tool position.
    p_goal : (3,) array_like
        End of the line, base frame (m).
    duration : float
        Duration of the move (s), positive.
    dt : float, optional
        Control step (s); default 0.005.
    method : str, optional
        :func:`robokit.kinematics.resolved_rate` method; default "dls" (adaptive damping).
    gain : float, optional
        Feedback gain K on the position and orientation errors (1/s); default 5.
    damping : float, optional
        Maximum damping λ of "dls"; default 0.02.
    null_gain : float, optional
        Weight of the null-space push away from the joint limits
        (:func:`robokit.kinematics.joint_limit_gradient`); default 0 (off).
    frame : str, optional
        Tool frame; default the robot's tip.

    Returns
    -------
    LineTrackingResult
        Joint path, actual and desired positions and the error along the line.

    Examples
    --------
    10 cm along x with the PUMA 560 in half a second stays within a millimetre of the line:

    >>> puma = rk.load("puma560")
    >>> q0 = np.array([0, 0.5, -0.3, 0, 0.7, 0])
    >>> p0 = puma.frame_pose(q0)[:3, 3]
    >>> res = track_line(puma, q0, p0 + [0.1, 0, 0], duration=0.5)
    >>> res.q.shape, bool(res.error.max() < 1e-3)
    ((101, 6), True)
    """
    q = as_vector(q0, "q0", robot.n).copy()
    robot.check_radians(q, "q0", state=True)
    p_goal = as_vector(p_goal, "p_goal", 3)
    duration = as_scalar(duration, "duration", positive=True)
    dt = as_scalar(dt, "dt", positive=True)
    T0 = robot.frame_pose(q, frame)
    p0, R_des = T0[:3, 3].copy(), T0[:3, :3].copy()
    if duration / dt > MAX_SAMPLES:  # before any step is allocated (1e5 s at 1e-4 s asked 1e9 steps)
        raise InputError(f"duration/dt: {duration:g} s in steps of {dt:g} s is more than {MAX_SAMPLES} steps; "
                         f"robokit takes at most {MAX_SAMPLES}: raise dt or shorten the duration")
    K = int(np.ceil(duration / dt))
    times = np.minimum(np.arange(K + 1) * dt, duration)
    scaling = quintic_trajectory(0.0, 1.0, duration, t=times)  # s(t) and ṡ(t), rest to rest
    assert scaling.qd is not None  # a quintic has its velocity
    ts, qs, ps, pds, errs = [], [], [], [], []
    for k in range(K + 1):
        p_des = p0 + scaling.q[k, 0] * (p_goal - p0)
        v_des = scaling.qd[k, 0] * (p_goal - p0)
        T = robot.frame_pose(q, frame)
        e_p = p_des - T[:3, 3]
        Re = R_des @ T[:3, :3].T
        e_w = 0.5 * np.array([Re[2, 1] - Re[1, 2], Re[0, 2] - Re[2, 0], Re[1, 0] - Re[0, 1]])
        ts.append(times[k])
        qs.append(q.copy())
        ps.append(T[:3, 3].copy())
        pds.append(p_des)
        errs.append(np.linalg.norm(e_p))
        if k == K:
            break
        J = robot.jacobian(q, frame, reference="local_world_aligned")
        V = np.r_[gain * e_w, v_des + gain * e_p]
        z = null_gain * joint_limit_gradient(q, robot.qlim) if null_gain else None
        q = q + dt * resolved_rate(J, V, method=method, damping=damping, adaptive=True, z=z)
    return LineTrackingResult(np.array(ts), np.array(qs), np.array(ps), np.array(pds), np.array(errs))
