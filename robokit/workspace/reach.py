r"""Is a tool pose reachable? The IK back end of capability maps, chosen per robot.

The back end is the first of :data:`robokit.ik.backends.BACKENDS` — the list
:func:`robokit.solve_ik` tries, in the same order — that supports "the tip at a pose"
for the robot (:func:`ik_backend` says which):

``"analytic"``
    Arms that ``robokit.ik_analytic`` solves (spherical wrists, three parallel axes): a
    pose is reachable when one of its solutions is within the limits and its forward
    kinematics (Pinocchio) reproduces the target to 1e-6.
``"planar"``
    Arms whose joints are all revolute about parallel axes with 2 or 3 joints: the
    vectorised closed form of :mod:`robokit.ik.planar` (a solution counts when every
    angle, shifted by a multiple of 2π, lies inside the joint limits and its forward
    kinematics reproduces the target to 1e-9 relative to the arm's size).
``"compiled"`` (or ``"lm"`` where the compiled solver is unavailable)
    Everything else: Levenberg–Marquardt with random restarts from a random initial guess,
    both drawn from the chunk's generator. A failure after the restarts is counted as
    unreachable, so a numeric capability index is a lower bound of the true one.
"""
from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import ArrayLike
from robokit._arrays import as_int
from robokit.errors import InputError

from robokit.ik.backends import reach_backend
from robokit.ik.planar import PlanarChain, planar_chain  # noqa: F401  (their former home; capability.py uses them)

if TYPE_CHECKING:
    from robokit.description.robot import Robot

__all__ = ["ik_success", "ik_backend"]

#: Restarts of the numerical IK per target (after the first attempt).
DEFAULT_RESTARTS = 20


def ik_backend(robot: Robot) -> str:
    """The name of the IK back end :func:`ik_success` uses for ``robot``.

    The first of :data:`robokit.ik.backends.BACKENDS` that supports "the tip at a pose" for
    this robot — the same list and order :func:`robokit.solve_ik` uses.

    Parameters
    ----------
    robot : robokit.Robot
        The arm (its tip frame is the tool).

    Returns
    -------
    str
        ``"analytic"``, ``"planar"``, ``"compiled"`` or ``"lm"`` (see the module docstring).

    Examples
    --------
    >>> import robokit
    >>> ik_backend(robokit.load("rrr"))
    'planar'
    """
    return reach_backend(robot).name


class _Backend:
    """One robot's IK back end, chosen once and reused for every chunk."""

    def __init__(self, robot: Robot, restarts: int = DEFAULT_RESTARTS) -> None:
        self.robot = robot
        self.backend = reach_backend(robot)
        self.kind = self.backend.name
        self.restarts = int(restarts)

    def success(self, targets: np.ndarray, rng: np.random.Generator) -> np.ndarray:
        return self.backend.reaches(self.robot, targets, rng, self.restarts)


def ik_success(robot: Robot, targets: ArrayLike, *, rng: int | np.random.Generator | None = None, restarts: int = DEFAULT_RESTARTS) -> np.ndarray:
    """Which target poses of the tip does ``robot`` reach (inside its joint limits)?

    Parameters
    ----------
    robot : :class:`robokit.Robot` or anything ``robokit.load`` accepts
    targets : (B, 4, 4) array
        Target poses of the tip frame in the base frame (m).
    rng : numpy Generator or int, optional
        Seeds the numerical back end's initial guesses and restarts (unused by the closed forms).
    restarts : int
        Random restarts of the numerical back end per target.

    Returns
    -------
    (B,) bool ndarray

    Notes
    -----
    The back end is chosen per robot (:func:`ik_backend`): ``robokit.ik_analytic``, a
    vectorised planar closed form, or numerical IK (whose failures count as unreachable).

    Examples
    --------
    >>> import numpy as np, robokit
    >>> robot = robokit.load("rrr")
    >>> T = robot.frame_pose(np.array([0.3, -0.2, 0.5]))
    >>> ik_success(robot, T[None]).tolist()
    [True]
    """
    from robokit.description.loading import load

    robot = load(robot)
    T = np.asarray(targets, dtype=float)
    if T.ndim != 3 or T.shape[1:] != (4, 4):
        raise InputError(f"targets: expected shape (B, 4, 4), got {T.shape}")
    if not np.isfinite(T).all():
        raise InputError("targets: contains NaN or infinite values")
    restarts = as_int(restarts, "restarts", minimum=0)
    return _Backend(robot, restarts).success(T, np.random.default_rng(rng))
