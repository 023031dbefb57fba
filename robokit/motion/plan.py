"""Collision-free joint-space planning: RRT-Connect (OMPL), shortcutting, then retiming.

1. **Goal.** A joint vector is used as given; a 4×4 tip pose is turned into joint goals by
   the closed-form IK (``ik_analytic``) when the arm has one, else by ``solve_ik`` from
   ``q_start`` and random seeds; of the solutions inside the limits and collision-free in
   ``world``, the one nearest to ``q_start`` (Euclidean in joint space) is the goal.
2. **Search.** OMPL's ``RRTConnect`` (Kuffner & LaValle 2000) in the box of joint limits
   (±π around the start for unlimited joints); a state is valid when ``world.in_collision``
   is False. Motions are checked by OMPL at ``resolution`` (rad, Euclidean joint distance
   between consecutive checked states).
3. **Shortcutting.** ``shortcuts`` random shortcut attempts (numpy ``default_rng(seed)``):
   two points on the path are joined by a straight joint-space segment when every state on
   it, at ``resolution``, is valid.
4. **Retiming.** The polyline is densified (waypoints at most ``spacing`` apart) and
   retimed by :func:`robokit.motion.retime.retime` (cubic spline through the waypoints, TOPP-RA).
   The spline is then checked at ``resolution`` along its whole length; where it cuts a
   corner into an obstacle, the waypoints are densified further (spacing halved, up to
   6 times) and the path retimed again.

Every state of the returned trajectory's path — its samples and the spline between them,
at ``resolution`` — is collision-free in ``world`` and inside the joint limits.
"""
from __future__ import annotations

import dataclasses
from typing import Any

import numpy as np

from robokit._arrays import as_array, as_scalar
from robokit.description.robot import check_robot_radians
from robokit._optional import require
from robokit.errors import InputError
from robokit.motion.retime import path_spline, retime
from robokit.trajectory.core import Trajectory

__all__ = ["plan", "goal_configurations", "DEFAULT_RESOLUTION"]

DEFAULT_RESOLUTION = 0.01  # rad
#: The largest ``seed`` :func:`plan` takes: OMPL is seeded with ``seed + 1``, an unsigned 64-bit integer.
MAX_SEED = 2**64 - 2


class _Checker:
    def __init__(self, robot: Any, world: Any, lo: np.ndarray, hi: np.ndarray, resolution: float) -> None:
        self.robot, self.world, self.lo, self.hi, self.res = robot, world, lo, hi, resolution

    def valid(self, q: np.ndarray) -> bool:
        if np.any(q < self.lo - 1e-12) or np.any(q > self.hi + 1e-12):
            return False
        return self.world is None or not self.world.in_collision(q)

    def segment(self, a: np.ndarray, b: np.ndarray) -> bool:
        k = max(int(np.ceil(np.linalg.norm(b - a) / self.res)), 1)
        return all(self.valid(a + (b - a) * (i / k)) for i in range(1, k + 1))

    def curve(self, spline: Any) -> bool:
        s = np.linspace(0.0, 1.0, 201)
        q = spline(s)
        L = float(np.sum(np.linalg.norm(np.diff(q, axis=0), axis=1)))
        k = max(int(np.ceil(L / self.res)) * 2, 2)
        return all(self.valid(x) for x in spline(np.linspace(0.0, 1.0, k + 1)))


def _limits(robot: Any, q_start: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    lo = np.where(np.isfinite(robot.qlim[:, 0]), robot.qlim[:, 0], q_start - np.pi)
    hi = np.where(np.isfinite(robot.qlim[:, 1]), robot.qlim[:, 1], q_start + np.pi)
    return lo, hi


def goal_configurations(robot: Any, T: Any, world: Any = None, q_start: Any = None, *, seeds: int = 20,
                        rng: int = 0) -> list[np.ndarray]:
    """Collision-free joint configurations reaching the tip pose ``T``, nearest to ``q_start`` first.

    Parameters
    ----------
    robot : robokit.Robot
        The robot.
    T : (4, 4) array_like
        Tip pose in the base frame (m).
    world : robokit.collision.World or None, optional
        Obstacles and self-collision (None: joint limits only).
    q_start : (n,) array_like, optional
        The configuration the solutions are sorted by distance to (default zeros).
    seeds : int, optional
        Random initial guesses for ``solve_ik`` when there is no closed form (default 20).
    rng : int, optional
        Their seed (default 0).

    Returns
    -------
    list of (n,) ndarray
        Joint values (rad / m), possibly none, inside the joint limits and collision-free,
        nearest to ``q_start`` first.

    Examples
    --------
    >>> import robokit
    >>> r = robokit.load("puma560")
    >>> T = r.frame_pose([0.1] * 6)
    >>> qs = goal_configurations(r, T)
    >>> len(qs) > 0, all(np.allclose(r.frame_pose(q), T) for q in qs)
    (True, True)
    """
    from robokit.ik.closed_form import ik_analytic
    from robokit.ik.numeric import solve_ik
    T = as_array(T, "goal", (4, 4))
    q0 = np.zeros(robot.n) if q_start is None else as_array(q_start, "q_start", (robot.n,))
    if q_start is not None:
        check_robot_radians(robot, q0, "q_start")
    cands: list[np.ndarray] = []
    try:
        cands = [s.q for s in ik_analytic(robot, T) if s.within_limits]
        closed_form = True
    except (InputError, ValueError, NotImplementedError):
        closed_form = False  # no closed form for this arm: numerical IK from seeds
    if not closed_form:
        g = np.random.default_rng(rng)
        for k in range(seeds):
            seed = q0 if k == 0 else robot.random_configuration(g)
            res = solve_ik(robot, T, q0=seed, max_restarts=0)
            if res.success:
                cands.append(np.asarray(res.q, dtype=float))
    ok = [q for q in cands if world is None or not world.in_collision(q)]
    ok.sort(key=lambda q: float(np.linalg.norm(q - q0)))
    return ok


_SEEDED: list[int] = []


def _rrt_connect(robot: Any, chk: _Checker, qa: np.ndarray, qb: np.ndarray, timeout: float, seed: int) -> np.ndarray:
    ob = require("ompl.base", "plan")
    og = require("ompl.geometric", "plan")
    ou = require("ompl.util", "plan")
    ou.setLogLevel(ou.LogLevel.LOG_WARN)
    if not _SEEDED:  # OMPL takes one seed per process, before its first random number
        ou.setLogLevel(ou.LogLevel.LOG_ERROR)
        ou.RNG.setSeed(int(seed) + 1)
        ou.setLogLevel(ou.LogLevel.LOG_WARN)
        _SEEDED.append(int(seed))
    n = robot.n
    space = ob.RealVectorStateSpace(n)
    bounds = ob.RealVectorBounds(n)
    for i in range(n):
        bounds.setLow(i, float(chk.lo[i]))
        bounds.setHigh(i, float(chk.hi[i]))
    space.setBounds(bounds)
    ss = og.SimpleSetup(space)

    def valid(s: Any) -> bool:
        return chk.valid(np.array([s[i] for i in range(n)]))

    ss.setStateValidityChecker(valid)
    si = ss.getSpaceInformation()
    si.setStateValidityCheckingResolution(chk.res / space.getMaximumExtent())
    a, b = space.allocState(), space.allocState()
    for i in range(n):
        a[i], b[i] = float(qa[i]), float(qb[i])
    ss.setStartAndGoalStates(a, b)
    ss.setPlanner(og.RRTConnect(si))
    solved = ss.solve(float(timeout))
    if not solved or not ss.haveExactSolutionPath():
        raise InputError(f"goal: no collision-free path found in {timeout} s (RRT-Connect)")
    p = ss.getSolutionPath()
    return np.array([[p.getState(k)[i] for i in range(n)] for k in range(p.getStateCount())])


def _shortcut(path: np.ndarray, chk: _Checker, tries: int, rng: np.random.Generator) -> np.ndarray:
    pts = list(path)
    for _ in range(tries):
        if len(pts) < 3:
            break
        i, j = sorted(rng.choice(len(pts), 2, replace=False))
        if j - i < 2:
            continue
        if chk.segment(pts[i], pts[j]):
            pts = pts[: i + 1] + pts[j:]
    return np.array(pts)


def _densify(path: np.ndarray, spacing: float) -> np.ndarray:
    out = [path[0]]
    for a, b in zip(path[:-1], path[1:]):
        k = max(int(np.ceil(np.linalg.norm(b - a) / spacing)), 1)
        out += [a + (b - a) * (i / k) for i in range(1, k + 1)]
    return np.array(out)


def plan(robot: Any, q_start: Any, goal: Any, world: Any = None, *, vmax: Any = 1.0, amax: Any = 2.0,
         tau_max: Any = None, resolution: float = DEFAULT_RESOLUTION, timeout: float = 5.0,
         shortcuts: int = 100, spacing: float = 0.1, seed: int = 0, grid: int = 200) -> Trajectory:
    """A collision-free, time-optimal joint trajectory from ``q_start`` to ``goal``.

    Steps (module docstring): goal IK → OMPL RRT-Connect → shortcutting → TOPP-RA retiming,
    with every state checked at ``resolution``.

    Parameters
    ----------
    robot : robokit.Robot
        The robot.
    q_start : (n,) array_like
        Start joint values (rad / m), inside the limits and collision-free.
    goal : (n,) or (4, 4) array_like
        Goal joint values, or a tip pose in the base frame (m; solved by IK, the nearest
        collision-free solution taken).
    world : robokit.collision.World or None, optional
        Obstacles and self-collision (None: joint limits only).
    vmax, amax, tau_max : float or (n,) array_like, optional
        Velocity (rad/s), acceleration (rad/s²) and torque (N·m / N; None: no torque limit)
        limits for :func:`robokit.motion.retime.retime` (defaults 1.0, 2.0, None).
    resolution : float, optional
        The largest joint-space step between checked states, rad.
    timeout : float, optional
        RRT-Connect's time budget, s (default 5).
    shortcuts : int, optional
        Random shortcut attempts (default 100).
    spacing : float, optional
        Waypoint spacing for the spline, rad (default 0.1).
    seed : int, optional
        The shortcutting's and IK seeds' random seed, and OMPL's (OMPL accepts one seed per
        process: the first plan's; later calls continue its stream): 0 to :data:`MAX_SEED`.
    grid : int, optional
        TOPP-RA stages (at least 4 per waypoint interval of the densified path; default 200).

    Returns
    -------
    Trajectory
        ``t``, ``q``, ``qd``, ``qdd`` (retimed, at rest at both ends); ``name == "plan"``;
        ``info``: ``waypoints`` (the shortcut polyline), ``rrt_path``, ``goal`` (the joint goal),
        ``resolution``, plus ``retime``'s ``s``, ``sd``, ``sdd``, ``duration``, ``spline``.

    Raises
    ------
    InputError
        Start or goal in collision / outside the limits, no collision-free IK solution, no
        path found within ``timeout``, or a ``seed`` that is not an integer from 0 to
        :data:`MAX_SEED`.

    Examples
    --------
    >>> import numpy as np, robokit
    >>> from robokit.collision import World, Box
    >>> r = robokit.load("puma560")
    >>> T = np.eye(4); T[:3, 3] = [0.5, 0.0, 0.3]
    >>> world = World(r, [Box([0.1, 0.3, 0.3], T)])
    >>> goal = [1.0, 0.3, -0.5, 0, 0, 0]
    >>> tr = robokit.plan(r, np.zeros(6), goal, world)
    >>> np.allclose(tr.q[-1], goal), bool(world.in_collision(tr.q).any())
    (True, False)
    """
    if isinstance(seed, bool) or not isinstance(seed, (int, np.integer)) or not 0 <= seed <= MAX_SEED:
        raise InputError(f"seed: expected an integer from 0 to {MAX_SEED}, got {seed!r}")
    n = robot.n
    q0 = as_array(q_start, "q_start", (n,))
    warned = check_robot_radians(robot, q0, "q_start")
    res = as_scalar(resolution, "resolution", positive=True)
    timeout = as_scalar(timeout, "timeout", positive=True)
    spacing = as_scalar(spacing, "spacing", positive=True)
    lo, hi = _limits(robot, q0)
    chk = _Checker(robot, world, lo, hi, res)
    if not chk.valid(q0):
        raise InputError("q_start: in collision or outside the joint limits")
    g = as_array(goal, "goal")
    if g.shape == (4, 4):
        goals = goal_configurations(robot, g, world, q0, rng=seed)
        if not goals:
            raise InputError("goal: no collision-free IK solution inside the joint limits reaches this pose")
        qg = goals[0]
    elif g.shape == (n,):
        qg = g
        if not warned:
            check_robot_radians(robot, qg, "goal")
        if not chk.valid(qg):
            raise InputError("goal: in collision or outside the joint limits")
    else:
        raise InputError(f"goal: expected ({n},) joint values or a (4, 4) pose, got shape {g.shape}")
    if chk.segment(q0, qg):
        rrt = np.array([q0, qg])
    else:
        rrt = _rrt_connect(robot, chk, q0, qg, timeout, seed)
    way = _shortcut(rrt, chk, shortcuts, np.random.default_rng(seed))
    d = spacing
    for _ in range(7):
        dense = _densify(way, d)
        spline, _ = path_spline(dense, n)
        if chk.curve(spline):
            break
        d /= 2
    else:
        raise InputError("goal: the smoothed path could not be kept collision-free (try a finer spacing)")
    tr = retime(robot, dense, vmax, amax, tau_max, grid=max(int(grid), 4 * (len(dense) - 1)))
    info = dict(tr.info, waypoints=way, rrt_path=rrt, goal=qg, resolution=res, spacing=d)
    return dataclasses.replace(tr, name="plan", info=info)
