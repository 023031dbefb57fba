"""The robot interface every robot-taking function of robokit accepts, written down.

:class:`RobotLike` is a :class:`typing.Protocol`: anything with these attributes and methods
works — a :class:`robokit.Robot` (Pinocchio underneath, the fast path), or your own object (a
symbolic arm lambdified, a wrapper around another library, a test double). Functions that need
more (Pinocchio's model for the dynamics, the DH table for the closed forms) say so and take a
:class:`robokit.Robot`.

Conventions: q (n,) joint values (rad for revolute, m for prismatic); poses 4×4 in the base
frame; Jacobians 6×n, **angular rows first** (ω; v); ``frame=None`` means the robot's tip;
``reference`` is where the Jacobian is expressed: "world" (space Jacobian), "local" (body
Jacobian, the frame's own axes) or "local_world_aligned" (the course's geometric Jacobian: ω and
the velocity of the frame origin, base axes).
"""
from __future__ import annotations

from typing import Any, Protocol, runtime_checkable

import numpy as np
from numpy.typing import ArrayLike

__all__ = ["RobotLike"]


@runtime_checkable
class RobotLike(Protocol):
    """What robokit needs of a robot: ``n``, ``qlim``, ``frame_pose`` and ``jacobian``.

    A structural type: any object with these members satisfies it (``isinstance`` checks the
    members' presence only). Conventions are those of the module docstring.

    Attributes
    ----------
    n : int
        Number of joints.
    qlim : numpy.ndarray, shape (n, 2)
        Lower and upper joint limits, rad or m (±inf where unlimited).
    frame_pose : callable
        ``frame_pose(q, frame=None) -> (4, 4)``: pose of ``frame`` (default the tip) in the base
        frame at q (n,), m.
    jacobian : callable
        ``jacobian(q, frame=None, reference=None) -> (6, n)``: rows ``(ω; v)``, expressed as
        ``reference`` (a :class:`robokit.Frame` or its lower-case name) says.

    Examples
    --------
    >>> isinstance(rk.load("twolink"), RobotLike), isinstance(object(), RobotLike)
    (True, False)
    """

    #: number of joints
    n: int
    #: (n, 2) lower and upper joint limits (±inf where unlimited)
    qlim: np.ndarray

    def frame_pose(self, q: ArrayLike, frame: str | None = None) -> np.ndarray:
        """Pose of ``frame`` in the base frame at q.

        Parameters
        ----------
        q : array_like, shape (n,)
            Joint values, rad or m.
        frame : str or None, optional
            The frame (None: the tip).

        Returns
        -------
        numpy.ndarray, shape (4, 4)
            ``T_base_frame``, m.
        """
        ...

    def jacobian(self, q: ArrayLike, frame: str | None = None, reference: Any = None) -> np.ndarray:
        """Jacobian of ``frame`` at q, angular rows first.

        Parameters
        ----------
        q, frame
            As in :meth:`frame_pose`.
        reference : robokit.Frame or str, optional
            Where it is expressed (``Frame.WORLD``, ``Frame.LOCAL`` or ``Frame.LOCAL_WORLD_ALIGNED``;
            the *Conventions* page); omitted: ``Frame.LOCAL_WORLD_ALIGNED``, robokit's one default.

        Returns
        -------
        numpy.ndarray, shape (6, n)
            Rows ``(ω; v)``: the frame's twist per unit joint rate.
        """
        ...
