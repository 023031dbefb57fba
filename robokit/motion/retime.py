"""Time-optimal retiming of a joint path (TOPP-RA, Pham & Pham 2018) under joint velocity,
acceleration and torque limits.

The path ``q(s)``, ``s ∈ [0, 1]``, is a cubic spline (scipy's not-a-knot) through the
waypoints at their normalised cumulative chord length. Along it, ``q̇ = q'(s) ṡ`` and
``q̈ = q''(s) ṡ² + q'(s) s̈``, and the torque of Newton–Euler (Lecture 7) is
``τ = M(q)(q'' ṡ² + q' s̈) + c(q, q') ṡ² + g(q)``: every limit is linear in
``(x, u) = (ṡ², s̈)``. TOPP-RA (the ``toppra`` package, the ``motion`` extra) finds the
fastest profile ``ṡ(s)`` on a grid of ``grid`` + 1 points with ``ṡ = 0`` at both ends;
the torques come from robokit's Newton–Euler on ``robot.poe``
(:func:`robokit.dynamics.newton_euler.inverse_dynamics`).

The returned samples are the grid points: at each, ``q̇`` and ``q̈`` are computed from the
grid's ``ṡᵢ`` and the stage's constant ``s̈ᵢ = (ṡᵢ₊₁² − ṡᵢ²)/(2Δs)`` — the values TOPP-RA's
constraints hold (up to its LP solver's tolerance, ~1e-8 relative). ``q̈`` is
right-continuous: sample i carries stage i's acceleration, valid on ``[tᵢ, tᵢ₊₁)``, and the
last sample (at rest, after arrival) has ``q̈ = 0``. Time advances by
``Δt = 2Δs/(ṡᵢ + ṡᵢ₊₁)`` (constant ``s̈`` per stage). Between grid points the limits hold
only approximately (the discretisation error of TOPP-RA shrinks with the grid spacing).
"""
from __future__ import annotations

from typing import Any

import numpy as np

from robokit._arrays import as_array, kernel_array
from robokit.description.robot import check_robot_radians
from robokit._optional import require
from robokit.errors import InputError
from robokit.trajectory.core import Trajectory

__all__ = ["retime", "path_spline"]


def _limit(x: Any, name: str, n: int) -> np.ndarray:
    a = as_array(x, name)
    if a.ndim == 0:
        a = np.full(n, float(a))
    if a.shape != (n,):
        raise InputError(f"{name}: expected a number or shape ({n},), got {a.shape}")
    if (a <= 0).any():
        raise InputError(f"{name}: every limit must be > 0, got {a.tolist()}")
    return a


def path_spline(waypoints: Any, n: int) -> tuple[Any, np.ndarray]:
    """The cubic spline ``q(s)``, ``s ∈ [0, 1]``, through waypoints at normalised chord length.

    Parameters
    ----------
    waypoints : (K, n) array_like or Trajectory
        K ≥ 2 joint-space waypoints (rad / m), or a :class:`~robokit.trajectory.Trajectory`
        (its ``q``).
    n : int
        Number of joints.

    Returns
    -------
    spline : scipy.interpolate.CubicSpline
        ``q(s)`` for ``s ∈ [0, 1]``, (n,) values.
    ss : (K',) ndarray
        The waypoints' parameters (cumulative chord length, normalised to end at 1); repeated
        waypoints are dropped, so K' ≤ K.

    Examples
    --------
    >>> sp, ss = path_spline([[0.0, 0.0], [1.0, 2.0]], 2)
    >>> sp(0.5).tolist()
    [0.5, 1.0]
    """
    from scipy.interpolate import CubicSpline
    q = waypoints.q if isinstance(waypoints, Trajectory) else waypoints
    W = as_array(q, "path")
    if W.ndim != 2 or W.shape[1] != n or W.shape[0] < 2:
        raise InputError(f"path: expected (K, {n}) waypoints with K >= 2, got shape {W.shape}")
    step = np.linalg.norm(np.diff(W, axis=0), axis=1)
    keep = np.r_[True, step > 1e-12]
    W, step = W[keep], step[step > 1e-12]
    if len(W) < 2:
        raise InputError("path: all waypoints are the same configuration; nothing to retime")
    ss = np.r_[0.0, np.cumsum(step)] / step.sum()
    ss[-1] = 1.0
    return CubicSpline(ss, W, bc_type="not-a-knot"), ss


def retime(robot: Any, path: Any, vmax: Any, amax: Any, tau_max: Any = None, *, grid: int = 200) -> Trajectory:
    """Time-optimal parameterisation of a joint path under velocity, acceleration and torque limits.

    Parameters
    ----------
    robot : robokit.Robot
        The robot (``robot.poe`` gives Newton–Euler's parameters; gravity ``robot.gravity``).
    path : (K, n) array_like or Trajectory
        Waypoints (joint values, rad / m), or a Trajectory (its ``q`` rows are the waypoints);
        interpolated by a cubic spline (module docstring).
    vmax, amax : float or (n,) array_like
        Symmetric joint velocity (rad/s) and acceleration (rad/s²) limits, > 0.
    tau_max : float or (n,) array_like, optional
        Symmetric joint torque limits (N·m / N), > 0 (default None: none).
    grid : int, optional
        Number of TOPP-RA stages (grid points − 1), default 200.

    Returns
    -------
    Trajectory
        ``t`` (grid + 1,), ``q``, ``qd``, ``qdd`` (grid + 1, n), starting and ending at rest;
        ``name == "retime"``; ``info``: ``s`` (grid,) path parameters, ``sd`` (ṡ), ``sdd`` (s̈),
        ``duration`` (s), ``spline`` (the path's CubicSpline).

    Raises
    ------
    InputError
        For bad limits or paths, or when no parameterisation satisfies the limits (e.g. the
        torque limit is below the gravity torque somewhere on the path).

    Examples
    --------
    Joint 1 moves 1 rad at most 1 rad/s and 2 rad/s²: 0.5 s to speed up, 0.5 s at full speed,
    0.5 s to stop — 1.5 s in all:

    >>> import robokit
    >>> r = robokit.load("twolink")
    >>> tr = robokit.retime(r, [[0.0, 0.0], [1.0, 0.5]], vmax=1.0, amax=2.0)
    >>> round(float(tr.t[-1]), 4), bool(np.abs(tr.qd).max() <= 1.0 + 1e-6), tr.q[-1].tolist()
    (1.5, True, [1.0, 0.5])
    """
    ta = require("toppra", "retime")
    algo = require("toppra.algorithm", "retime")
    constraint = require("toppra.constraint", "retime")

    n = robot.n
    vm, am = _limit(vmax, "vmax", n), _limit(amax, "amax", n)
    if not isinstance(grid, (int, np.integer)) or grid < 2:
        raise InputError(f"grid: expected an integer >= 2, got {grid!r}")
    spline, ss = path_spline(path, n)
    check_robot_radians(robot, spline(ss), "path")  # the waypoints (a path's rows may wind: states)
    tpath = ta.SplineInterpolator(ss, spline(ss), bc_type="not-a-knot")
    cons: list[Any] = [constraint.JointVelocityConstraint(np.column_stack([-vm, vm])),
                       constraint.JointAccelerationConstraint(np.column_stack([-am, am]))]
    if tau_max is not None:
        tm = _limit(tau_max, "tau_max", n)
        from robokit.dynamics.newton_euler import inverse_dynamics
        p = robot.poe
        g, F0 = np.array(robot.gravity, dtype=float), np.zeros(6)
        # the arrays behind robot.poe's read-only views, as the kernel takes them (once, not per call)
        Ml, Gl, Sl = kernel_array(p.Mlist), kernel_array(p.Glist), kernel_array(p.Slist)

        def inv_dyn(q: np.ndarray, qd: np.ndarray, qdd: np.ndarray) -> np.ndarray:
            return np.asarray(inverse_dynamics(q, qd, qdd, g, F0, Ml, Gl, Sl))

        cons.append(constraint.JointTorqueConstraint(inv_dyn, np.column_stack([-tm, tm]), np.zeros(n)))
    s = np.linspace(0.0, 1.0, int(grid) + 1)
    inst = algo.TOPPRA(cons, tpath, gridpoints=s, parametrizer="ParametrizeConstAccel")
    inst.compute_parameterization(0.0, 0.0)
    sd = inst.problem_data.sd_vec
    if sd is None or inst.problem_data.return_code.name != "Ok" or not np.isfinite(sd).all():
        raise InputError("path: no time parameterisation satisfies the limits on this path "
                         "(a torque limit below the gravity torque, or a path through a singular pose)")
    sd = np.maximum(np.asarray(sd, dtype=float), 0.0)
    ds = np.diff(s)
    u = (sd[1:] ** 2 - sd[:-1] ** 2) / (2 * ds)
    sdd = np.r_[u, 0.0]  # right-continuous: stage i's s̈ on [tᵢ, tᵢ₊₁); at rest after the end
    dt = 2 * ds / (sd[:-1] + sd[1:])
    t = np.r_[0.0, np.cumsum(dt)]
    q, qs, qss = spline(s), spline(s, 1), spline(s, 2)
    qd = qs * sd[:, None]
    qdd = qss * (sd ** 2)[:, None] + qs * sdd[:, None]
    return Trajectory(t=t, q=q, qd=qd, qdd=qdd, name="retime",
                      info={"s": s, "sd": sd, "sdd": sdd, "duration": float(t[-1]), "spline": spline})
