r"""Cartesian straight-line trajectories with slerp orientation (Lecture 3, "笛卡尔空间中的直线规划").

Position: all three components vary linearly, ``p(s) = p0 + s (p1 − p0)``.

Orientation: the relative rotation ``ΔR = R0ᵀ R1`` has an angle–axis form ``(k̂, θ)``
and the orientation turns about that one fixed axis, ``R(s) = R0 exp([k̂] s θ)``
(Lecture 3's "补充插值方法" ``ᵂR_i = ᵂR_0 ⁰R_i(k̂_Δ, s θ_Δ)``). With θ ∈ [0, π] this is
exactly quaternion slerp between the unit quaternions of R0 and R1 taken in the same
hemisphere: ``q(s) = q0 (q0⁻¹ q1)^s``. It keeps R(s) on SO(3) (unlike the lecture's
counter-examples, interpolating matrices ``(1 − s)R0 + sR1`` or Euler angles/angle–axis
vectors component-wise), and the axis, seen in the world frame, is the constant
``R0 k̂``.

The angle–axis form is not unique: the same ΔR is also the rotation by ``θ − 2π`` about
k̂ (i.e. 2π − θ about −k̂; for quaternions, q and −q). Interpolating that form also ends
at R1 about the same fixed axis, but goes "the long way" round;
:func:`slerp_rotation` with ``shortest=False`` gives it, to show the difference.

Time: s = s(t) is any time scaling of :mod:`robokit.trajectory.timescaling`
(cubic, quintic or LSPB), so velocity and acceleration are ``ṗ = ṡ(p1 − p0)``,
``ω = ṡ θ R0 k̂`` (world frame) and likewise for the second derivatives.

Converting to joint space (design note, not implemented here): a future
``cartesian_to_joint(robot, traj, ik=...)`` will solve IK at every pose of
``traj.poses`` warm-started from the previous solution, and report the two problems
Lecture 3 lists — a pose outside the workspace (IK fails: the index and the pose are
reported) and joint-rate blow-up near a singularity (|Δθ|/Δt above the joint limits or a
growing condition number of the Jacobian). It belongs with the IK issue; until then
use ``traj.poses`` with an IK solver directly.
"""
from __future__ import annotations

import numpy as np

from robokit._arrays import as_array
from robokit.spatial.se3 import check_transform
from robokit.spatial.so3 import _exp3, _log3_vec, check_rotation
from robokit.trajectory.core import Trajectory, positive_duration, sample_times
from robokit.trajectory.timescaling import time_scaling

__all__ = ["slerp_rotation", "cartesian_line_trajectory"]


def _relative_rotation_vector(R0: np.ndarray, R1: np.ndarray, shortest: bool) -> np.ndarray:
    """k̂θ of R0ᵀR1 in R0's frame; θ ∈ [0, π] (shortest) or θ − 2π (the other form)."""
    w = _log3_vec(R0.T @ R1)
    if shortest:
        return w
    theta = float(np.linalg.norm(w))
    if theta < 1e-12:
        raise ValueError("shortest=False: R0 and R1 are equal, so the 'long way' (a full turn) has no defined axis")
    return w * (theta - 2.0 * np.pi) / theta


def slerp_rotation(R0, R1, s, shortest: bool = True) -> np.ndarray:
    """Rotations on the fixed-axis path from ``R0`` (s = 0) to ``R1`` (s = 1): quaternion slerp.

    ``R(s) = R0 exp([k̂] s θ)`` with ``k̂θ = log(R0ᵀ R1)``, θ ∈ [0, π] (the quaternion
    slerp, shortest path). With ``shortest=False`` the other angle–axis form of the same
    relative rotation, θ − 2π about k̂, is used (the long way round, same axis).

    Parameters
    ----------
    R0, R1 : array (3, 3)
        Start and end rotations (``R_world_tool``).
    s : float or array (K,)
        Path parameter(s), normally in [0, 1].
    shortest : bool
        Take the shorter (True, the slerp) or the longer way about the same axis.

    Returns
    -------
    ndarray (3, 3) for a scalar ``s``, else (K, 3, 3).

    Example
    -------
    >>> import numpy as np
    >>> Rz = lambda a: np.array([[np.cos(a), -np.sin(a), 0], [np.sin(a), np.cos(a), 0], [0, 0, 1]])
    >>> np.allclose(slerp_rotation(np.eye(3), Rz(1.0), 0.25), Rz(0.25))
    True
    """
    A = check_rotation(R0, "R0")
    B = check_rotation(R1, "R1")
    sv = as_array(s, "s")
    w = _relative_rotation_vector(A, B, shortest)
    if sv.ndim == 0:
        return A @ _exp3(w * float(sv))
    if sv.ndim != 1:
        raise ValueError(f"s: expected a number or a 1-D array, got shape {sv.shape}")
    return np.array([A @ _exp3(w * x) for x in sv])


def cartesian_line_trajectory(T_start, T_end, tf, t=None, method="quintic", shortest: bool = True) -> Trajectory:
    """Straight-line tool motion with slerp orientation, timed by a time scaling (Lecture 3).

    Parameters
    ----------
    T_start, T_end : array (4, 4)
        Start and end poses ``T_world_tool`` in SE(3).
    tf : float
        Duration, s (> 0).
    t : None, int or array (K,)
        Sample grid on ``[0, tf]`` (None: 101 samples; int: number of samples).
    method : 3, 5, ``"cubic"``, ``"quintic"`` or ``"lspb"``
        The time scaling s(t) (see :func:`robokit.trajectory.time_scaling`).
    shortest : bool
        Rotate the short way (slerp, default) or the long way about the same axis.

    Returns
    -------
    Trajectory
        ``poses`` (K, 4, 4); ``q`` (K, 6) = ``(φ, p)``: φ the rotation vector of
        ``R(t) R0ᵀ`` in the world frame (it stays on the fixed axis ``R0 k̂``) and p the
        position, m; ``qd`` = ``(ω, ṗ)`` (world-frame angular velocity and the origin's
        velocity); ``qdd`` = ``(ω̇, p̈)``; angular first, as robokit's twists.
        ``info``: ``"axis_world"`` (3,), ``"angle"`` θ (rad), ``"s"``, ``"sd"``, ``"sdd"``.

    Example
    -------
    >>> import numpy as np
    >>> T1 = np.eye(4); T1[:3, 3] = [1.0, 0.0, 0.0]
    >>> tr = cartesian_line_trajectory(np.eye(4), T1, 2.0, t=3)
    >>> tr.poses[1][:3, 3].tolist()
    [0.5, 0.0, 0.0]
    """
    X0 = check_transform(T_start, "T_start")
    X1 = check_transform(T_end, "T_end")
    T = positive_duration(tf, "tf")
    ts = sample_times(t, 0.0, T)
    s, sd, sdd = time_scaling(method, T, ts)
    R0, p0 = X0[:3, :3], X0[:3, 3]
    p1 = X1[:3, 3]
    w = _relative_rotation_vector(R0, X1[:3, :3], shortest)  # in R0's frame
    theta = float(np.linalg.norm(w))
    phi_dir = R0 @ w  # world-frame rotation vector of the whole move: θ R0 k̂
    K = ts.size
    poses = np.empty((K, 4, 4))
    poses[:] = np.eye(4)
    for i in range(K):
        poses[i, :3, :3] = R0 @ _exp3(w * s[i])
    dp = p1 - p0
    poses[:, :3, 3] = p0 + s[:, None] * dp
    if s[-1] == 1.0:
        poses[-1, :3, 3] = p1
    q = np.hstack([s[:, None] * phi_dir, poses[:, :3, 3]])
    qd = np.hstack([sd[:, None] * phi_dir, sd[:, None] * dp])
    qdd = np.hstack([sdd[:, None] * phi_dir, sdd[:, None] * dp])
    axis = phi_dir / theta if theta > 0 else np.zeros(3)
    info = {"axis_world": axis, "angle": theta, "s": s, "sd": sd, "sdd": sdd}
    labels = ("φx", "φy", "φz", "x", "y", "z")
    return Trajectory(ts, q, qd, qdd, poses=poses, name="cartesian_line", labels=labels, info=info)
