"""The sizes robokit accepts in a robot description, checked before Pinocchio builds anything.

:data:`MAX_JOINTS` = 128. A serial manipulator has 1 to about 10 joints; hyper-redundant
snake arms and discretised continuum robots have a few dozen to about a hundred. What a
longer chain costs is Pinocchio's: its ``Data`` grows faster than n². Measured on this
project's machines (2 shared cores, under load), loading a planar DH chain of n joints took

====  ========  ==================  ====================================
n     time      extra memory        of which ``model.createData()``
====  ========  ==================  ====================================
64    0.8 s     36 MB
128   2.1 s     220 MB
256   10 s      1.6 GB              1.1 GB
====  ========  ==================  ====================================

and a 1,000-joint URDF took 20 GB and was killed, 5,000 joints crashed ``createData``
(exit 139). 128 joints is above every serial arm and stays within a laptop's means.
Joints are counted in the checked text — every ``<joint>`` of a URDF or an MJCF file (fixed
ones included), the rows of a DH table — so nothing large is ever built.
"""
from __future__ import annotations

import os

from robokit.errors import InputError

__all__ = ["MAX_JOINTS", "check_joint_count"]

#: Most joints a robot description may have (see the module docstring for why 128).
MAX_JOINTS = 128


def check_joint_count(count: int, source: str | os.PathLike[str], what: str = "joints") -> None:
    """Refuse a description with more than :data:`MAX_JOINTS` joints.

    Parameters
    ----------
    count : int
        Joints counted in the description (``<joint>`` elements, DH rows).
    source : str or Path
        The file (or object) named in the message.
    what : str
        What was counted ("joints", "<joint> elements", "links").

    Raises
    ------
    InputError
        ``SOURCE: N joints; robokit reads robots of at most 128 joints``.

    Examples
    --------
    >>> check_joint_count(6, "arm.urdf")
    >>> check_joint_count(1000, "snake.urdf")
    Traceback (most recent call last):
    ...
    robokit.errors.InputError: snake.urdf: 1000 joints; robokit reads robots of at most 128 joints
    """
    if count > MAX_JOINTS:
        raise InputError(f"{source}: {count} {what}; robokit reads robots of at most {MAX_JOINTS} joints")
