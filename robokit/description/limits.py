"""The sizes robokit accepts in a robot description, checked before Pinocchio builds anything.

:data:`MAX_JOINTS` = 256. A serial manipulator has 1 to about 10 joints; hyper-redundant
snake arms and continuum-robot discretisations reach a few dozen to about a hundred; a whole
humanoid or a multi-arm tree in one file has up to a few hundred. 256 is above all of these,
while a chain this long still builds in well under a second and a few MB (Pinocchio's model,
the product-of-exponentials parameters and an n×n mass matrix). Beyond it the cost is not
worth it and, measured on this project's machines, Pinocchio fails badly: a 1,000-joint URDF
took 20 GB and was killed, 5,000 joints crashed ``createData`` (exit 139). Joints are
counted in the checked text (every ``<joint>`` of a URDF or an MJCF file, fixed ones included,
the rows of a DH table), so nothing large is ever built.
"""
from __future__ import annotations

import os

from robokit.errors import InputError

__all__ = ["MAX_JOINTS", "check_joint_count"]

#: Most joints a robot description may have (see the module docstring for why 256).
MAX_JOINTS = 256


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
        ``SOURCE: N joints; robokit reads at most 256 ...``.

    Examples
    --------
    >>> check_joint_count(6, "arm.urdf")
    >>> check_joint_count(1000, "snake.urdf")
    Traceback (most recent call last):
    ...
    robokit.errors.InputError: snake.urdf: 1000 joints; robokit reads robots of at most 256 joints
    """
    if count > MAX_JOINTS:
        raise InputError(f"{source}: {count} {what}; robokit reads robots of at most {MAX_JOINTS} joints")
