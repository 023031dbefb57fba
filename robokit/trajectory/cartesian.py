r"""Cartesian straight-line trajectories with slerp orientation (Lecture 3, "笛卡尔空间中的直线规划").

Position: all three components vary linearly, ``p(s) = p0 + s (p1 − p0)``.

Orientation: the relative rotation ``ΔR = R0ᵀ R1`` has an angle–axis form ``(k̂, θ)``
and the orientation turns about that one fixed axis, ``R(s) = R0 exp([k̂] s θ)``
(Lecture 3's "补充插值方法" ``ᵂR_i = ᵂR_0 ⁰R_i(k̂_Δ, s θ_Δ)``). With θ ∈ [0, π] this is
exactly quaternion slerp between the unit quaternions of R0 and R1 taken in the same
hemisphere: ``q(s) = q0 (q0⁻¹ q1)^s``. It keeps R(s) on SO(3) (unlike the lecture's
counter-examples, interpolating matrices ``(1 − s)R0 + sR1`` or Euler angles/angle–axis
vectors component-wise), and the axis, seen in the world frame, is the constant
``R0 k̂``. At θ = π exactly both ±k̂ are shortest; the axis is ``matrix_log_3``'s
documented choice.

The angle–axis form is not unique: the same ΔR is also the rotation by ``θ − 2π`` about
k̂ (i.e. 2π − θ about −k̂; for quaternions, q and −q). Interpolating that form also ends
at R1 about the same fixed axis, but goes "the long way" round;
:func:`slerp_rotation` with ``shortest=False`` gives it, to show the difference.

Time: s = s(t) is any time scaling of :mod:`robokit.trajectory.timescaling`
(cubic, quintic or LSPB), so velocity and acceleration are ``ṗ = ṡ(p1 − p0)``,
``ω = ṡ θ R0 k̂`` (world frame) and likewise for the second derivatives.

Converting to joint space (:func:`joint_trajectory_from_cartesian`): inverse kinematics at every pose,
warm-started from the previous solution, with the two problems Lecture 3 lists detected
and reported — a pose outside the workspace (IK fails: ``ValueError`` naming the samples)
and joint-rate blow-up near a singularity (joint rates above ``qd_limit``: a
``RuntimeWarning`` and per-sample flags, with the Jacobian's condition number).
"""
from __future__ import annotations

import warnings
from typing import Any, Callable, cast

import numpy as np
from numpy.typing import ArrayLike

from robokit._arrays import as_array, as_vector
from robokit.description.robot import check_robot_radians
from robokit.spatial.se3 import check_transform
from robokit.spatial.so3 import check_rotation
from robokit.trajectory.core import Trajectory, positive_duration, sample_times
from robokit.trajectory.timescaling import time_scaling
from robokit.spatial import lie
from robokit.errors import InputError, InputTypeError
from robokit._deprecation import deprecated_alias

__all__ = ["slerp_rotation", "cartesian_line_trajectory", "joint_trajectory_from_cartesian"]


def _relative_rotation_vector(R0: np.ndarray, R1: np.ndarray, shortest: bool) -> np.ndarray:
    """k̂θ of R0ᵀR1 in R0's frame; θ ∈ [0, π] (shortest) or θ − 2π (the other form)."""
    w = lie.log3(R0.T @ R1)
    if shortest:
        return w
    theta = float(np.linalg.norm(w))
    if theta < 1e-12:
        raise InputError("shortest=False: R0 and R1 are equal, so the 'long way' (a full turn) has no defined axis")
    return w * (theta - 2.0 * np.pi) / theta


def slerp_rotation(R0: ArrayLike, R1: ArrayLike, s: ArrayLike, shortest: bool = True) -> np.ndarray:
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

    Examples
    --------
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
        return A @ lie.exp3(w * float(sv))
    if sv.ndim != 1:
        raise InputError(f"s: expected a number or a 1-D array, got shape {sv.shape}")
    return np.array([A @ lie.exp3(w * x) for x in sv])


def cartesian_line_trajectory(T_start: ArrayLike, T_end: ArrayLike, tf: float, t: ArrayLike | None = None, method: int | str = "quintic", shortest: bool = True) -> Trajectory:
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

    Examples
    --------
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
        poses[i, :3, :3] = R0 @ lie.exp3(w * s[i])
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


def _ik_answer(ans: Any, q_prev: np.ndarray | None) -> tuple[np.ndarray | None, bool]:
    """(q, success) from an IK callable's answer: an object with ``.q``/``.success``, a
    ``(q, success)`` pair, or a list of candidate solutions (arrays or objects with ``.q``;
    those flagged ``within_limits=False`` are skipped; the nearest to ``q_prev`` is taken)."""
    if hasattr(ans, "q") and hasattr(ans, "success"):
        return np.asarray(ans.q, dtype=float), bool(ans.success)
    if isinstance(ans, tuple) and len(ans) == 2 and np.ndim(ans[1]) == 0:
        return np.asarray(ans[0], dtype=float), bool(ans[1])
    if isinstance(ans, (list, tuple)):
        cands = [np.asarray(getattr(c, "q", c), dtype=float) for c in ans if getattr(c, "within_limits", True)]
        if not cands:
            return None, False
        if q_prev is None:
            return cands[0], True
        return min(cands, key=lambda c: float(np.linalg.norm(c - q_prev))), True
    raise InputTypeError(
        "ik: expected the IK callable to return an object with .q and .success, a (q, success) pair, "
        f"or a list of solutions; got {type(ans).__name__}"
    )


def joint_trajectory_from_cartesian(robot: Any, traj: Trajectory, ik: Callable[[np.ndarray, np.ndarray | None], Any] | None = None, q0: ArrayLike | None = None, *, frame: str | None = None, position_only: bool = False, qd_limit: ArrayLike | None = None, tol: float = 1e-6) -> Trajectory:
    """Joint-space trajectory following a Cartesian one, by IK at every pose (Lecture 3).

    Each pose of ``traj.poses`` is solved with ``ik``, starting from the previous solution
    (so the arm stays on one branch). The two problems of Cartesian paths of Lecture 3 are
    detected: a pose the IK cannot reach (outside the workspace) raises ``ValueError``
    listing the samples; joint rates above ``qd_limit`` (near a singularity a small
    Cartesian speed needs a huge joint speed) give a ``RuntimeWarning`` and are flagged in
    ``info``.

    Parameters
    ----------
    robot : object
        A :class:`robokit.Robot` or anything with ``n`` and, for the default IK and the
        checks, ``qlim``, ``frame_pose(q, frame)`` and ``jacobian(q, frame, reference=...)``.
    traj : Trajectory
        A Cartesian trajectory with ``poses`` (K, 4, 4), e.g. from :func:`cartesian_line_trajectory`.
    ik : callable, optional
        ``ik(T_target, q_guess) -> answer`` where ``q_guess`` is the previous solution (``q0``
        or None for the first pose) and ``answer`` is an object with ``.q`` and ``.success``
        (e.g. :func:`robokit.ik.solve_ik`'s result), a ``(q, success)`` pair, or a list of
        solutions (the closed-form solvers' lists: the one nearest the previous solution is
        taken). Default: :func:`robokit.ik.solve_ik` (restarts only if a warm start fails).
    q0 : array (n,), optional
        Initial guess for the first pose (default: the IK's own).
    frame : str, optional
        The robot frame that follows the path (default the tip).
    position_only : bool
        Follow the positions only (for arms with fewer than 6 joints).
    qd_limit : float or array (n,), optional
        Joint speed limits (rad/s or m/s) used to flag joint-rate blow-up.
    tol : float
        Largest accepted pose error of a solution (m and rad), checked with ``frame_pose``.

    Returns
    -------
    Trajectory
        ``t`` as ``traj.t``; ``q`` (K, n) joint positions; ``qd``, ``qdd`` by finite
        differences (second order, ``numpy.gradient``); ``poses`` = ``traj.poses``.
        ``info``: ``"pose_error"`` (K,), ``"max_joint_rate"`` (n,), ``"rate_exceeded"`` (K,)
        bool (with ``qd_limit``), ``"jacobian_condition"`` (K,) (if the robot has ``jacobian``).

    Examples
    --------
    The planar arm's tip on a straight line between two reachable points (positions only: a
    2-joint arm cannot also hold an interpolated orientation):

    >>> robot = rk.load("twolink")
    >>> T_a, T_b = robot.frame_pose([0.2, 0.6]), robot.frame_pose([0.6, 0.4])
    >>> line = cartesian_line_trajectory(T_a, T_b, 1.0, t=11)
    >>> qtraj = joint_trajectory_from_cartesian(robot, line, q0=[0.2, 0.6], position_only=True)
    >>> qtraj.q.shape, qtraj.q[-1].round(6).tolist(), bool(qtraj.info["pose_error"].max() < 1e-6)
    ((11, 2), [0.6, 0.4], True)
    """
    if not isinstance(traj, Trajectory) or traj.poses is None:
        raise InputError("traj: expected a Cartesian Trajectory with poses (e.g. from cartesian_line_trajectory)")
    n = int(robot.n)
    poses = np.asarray(traj.poses, dtype=float)
    K = poses.shape[0]
    tol = float(tol)
    guess = None if q0 is None else as_vector(q0, "q0", n)
    if guess is not None:
        check_robot_radians(robot, guess, "q0")
    if ik is None:
        from robokit.ik.numeric import solve_ik

        def ik(T: np.ndarray, q_guess: np.ndarray | None) -> Any:
            res = solve_ik(robot, T, q_guess, frame, position_only=position_only, max_restarts=0 if q_guess is not None else 30)
            if not res.success and q_guess is not None:
                res = solve_ik(robot, T, q_guess, frame, position_only=position_only)
            return res

    has_fk = hasattr(robot, "frame_pose")
    q = np.zeros((K, n))
    ok = np.zeros(K, dtype=bool)
    pose_err = np.full(K, np.inf)
    prev = guess
    for k in range(K):
        qk, success = _ik_answer(ik(poses[k], prev), prev)
        if qk is not None:
            qk = as_vector(qk, "ik result", n)
            if has_fk:
                T = np.asarray(robot.frame_pose(qk, frame), dtype=float)
                e = float(np.linalg.norm(T[:3, 3] - poses[k, :3, 3]))
                if not position_only:
                    e = max(e, float(np.linalg.norm(lie.log3(T[:3, :3].T @ poses[k, :3, :3]))))
                pose_err[k] = e
                success = success and e <= tol
            else:
                pose_err[k] = 0.0 if success else np.inf
        if success:
            q[k] = qk
            ok[k] = True
            prev = qk
    if not ok.all():
        bad = np.flatnonzero(~ok)
        shown = ", ".join(f"{i} (t = {traj.t[i]:.3g} s, p = {np.round(poses[i, :3, 3], 4).tolist()})" for i in bad[:3])
        raise InputError(
            f"traj: {bad.size} of {K} poses cannot be reached (IK failed): samples {shown}"
            + (" …" if bad.size > 3 else "")
            + " — the path leaves the workspace (Lecture 3: intermediate points unreachable)"
        )
    t = np.asarray(traj.t, dtype=float)
    if K >= 3:
        qd = cast(np.ndarray, np.gradient(q, t, axis=0, edge_order=2))
        qdd = np.gradient(qd, t, axis=0, edge_order=2)
    elif K == 2:
        qd = cast(np.ndarray, np.gradient(q, t, axis=0))
        qdd = np.zeros_like(q)
    else:
        qd = np.zeros_like(q)
        qdd = np.zeros_like(q)
    info = {"pose_error": pose_err, "max_joint_rate": np.abs(qd).max(axis=0)}
    if hasattr(robot, "jacobian"):
        cond = np.empty(K)
        for k in range(K):
            J = np.asarray(robot.jacobian(q[k], frame, reference="local_world_aligned"), dtype=float)
            cond[k] = np.linalg.cond(J[3:] if position_only else J)
        info["jacobian_condition"] = cond
    if qd_limit is not None:
        lim = np.abs(as_array(qd_limit, "qd_limit"))
        lim = np.full(n, float(lim)) if lim.ndim == 0 else as_vector(lim, "qd_limit", n)
        exceeded = np.any(np.abs(qd) > lim, axis=1)
        info["rate_exceeded"] = exceeded
        if exceeded.any():
            k = int(np.argmax(np.max(np.abs(qd) / lim, axis=1)))
            cond_txt = f", Jacobian condition number {info['jacobian_condition'][k]:.3g}" if "jacobian_condition" in info else ""
            warnings.warn(
                f"joint_trajectory_from_cartesian: joint rates exceed qd_limit at {int(exceeded.sum())} of {K} samples, worst "
                f"{np.abs(qd[k]).max():.3g} at t = {t[k]:.3g} s{cond_txt} — the path passes near a singularity "
                "(Lecture 3: high joint rates); slow down or move the path",
                RuntimeWarning,
                stacklevel=2,
            )
    labels = tuple(robot.joint_names) if hasattr(robot, "joint_names") and len(getattr(robot, "joint_names")) == n else None
    return Trajectory(t, q, qd, qdd, poses=poses, name="joint_trajectory_from_cartesian", labels=labels, info=info)

# Former names (before the X_from_Y rule): they warn and call the new function.
cartesian_to_joint = deprecated_alias(joint_trajectory_from_cartesian, "cartesian_to_joint")
