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

import math
import os
from typing import Any

from robokit._arrays import MAX_MAGNITUDE
from robokit.errors import InputError

__all__ = ["MAX_JOINTS", "check_joint_count", "unbounded_limits"]

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


def unbounded_limits(model: Any, source: str) -> list[str]:
    """Apply robokit's one rule for joint limits to a Pinocchio model, in place: a limit beyond
    :data:`~robokit._arrays.MAX_MAGNITUDE` (1e12) in magnitude means "no limit on that side".

    Robot files write "unlimited" as huge finite numbers (``±1e16`` in many URDFs, ``±1e308``,
    ``±3.4e38``); left finite they overflow every computation that uses the range (a random
    configuration, a slider, a sampling box). A lower limit below −1e12 becomes −∞ and an upper
    limit above 1e12 becomes +∞, as Pinocchio writes a joint without limits; the joint is then
    treated like a continuous joint wherever a range is needed (±π around zero). A lower limit
    above 1e12, or an upper limit below −1e12, leaves no range at all and is refused.

    Parameters
    ----------
    model : pinocchio.Model
        The model whose ``lowerPositionLimit``/``upperPositionLimit`` are changed.
    source : str
        The file (or robot) named in the notes and the message.

    Returns
    -------
    list of str
        One note per joint whose limits were read as unlimited.

    Raises
    ------
    InputError
        ``SOURCE: joint 'j': lower limit 1e+308 is out of range …``.

    Examples
    --------
    >>> import numpy as np, pinocchio as pin
    >>> model = pin.buildSampleModelManipulator()
    >>> model.upperPositionLimit[0] = 1e308
    >>> unbounded_limits(model, "arm.urdf")[0].split(" read as")[0]
    "arm.urdf: joint 'shoulder1_joint': upper limit 1e+308"
    >>> bool(np.isinf(model.upperPositionLimit[0]))
    True
    """
    notes = []
    lower, upper = model.lowerPositionLimit.copy(), model.upperPositionLimit.copy()
    for j in range(1, model.njoints):
        jm = model.joints[j]
        if jm.nq != 1 or jm.idx_q < 0:
            continue
        k, name = jm.idx_q, model.names[j]
        lo, hi = float(lower[k]), float(upper[k])
        for side, v in (("lower", lo), ("upper", hi)):
            if v != v:
                raise InputError(f"{source}: joint {name!r}: {side} limit is NaN")
        if lo > MAX_MAGNITUDE or hi < -MAX_MAGNITUDE:
            side, v = ("lower", lo) if lo > MAX_MAGNITUDE else ("upper", hi)
            raise InputError(f"{source}: joint {name!r}: {side} limit {v:g} is out of range (at most "
                             f"{MAX_MAGNITUDE:g} in magnitude; beyond it a limit means no limit on its own side)")
        changed = [f"{side} limit {v:g}" for side, v in (("lower", lo), ("upper", hi))
                   if math.isfinite(v) and abs(v) > MAX_MAGNITUDE]
        if changed:
            if lo < -MAX_MAGNITUDE:
                lower[k] = -math.inf
            if hi > MAX_MAGNITUDE:
                upper[k] = math.inf
            notes.append(f"{source}: joint {name!r}: {' and '.join(changed)} read as no limit (limits beyond "
                         f"{MAX_MAGNITUDE:g} in magnitude mean unlimited)")
    if notes:
        model.lowerPositionLimit, model.upperPositionLimit = lower, upper
    return notes
