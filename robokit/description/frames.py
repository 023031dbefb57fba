"""A frame by name, when several frames of a Pinocchio model share it.

A URDF may give a joint and its child link one name (example-robot-data's Z1: the fixed joint
``gripperStator`` and the link ``gripperStator``); Pinocchio then has a joint frame and a body
frame of that name, and ``model.getFrameId(name)`` refuses to choose. robokit's rule: a name
means the link — the body frame — when there is one, else the one frame of that name. (In a
URDF the two coincide: a child link's frame is its joint's frame.)
"""
from __future__ import annotations

from typing import Any

__all__ = ["frame_index"]


def frame_index(model: Any, name: str) -> int:
    """The index of the frame called ``name``: its body frame when a joint frame shares the name.

    Parameters
    ----------
    model : pinocchio.Model
    name : str

    Returns
    -------
    int
        An index into ``model.frames`` (``model.nframes`` when no frame has that name, as
        Pinocchio's ``getFrameId``).

    Examples
    --------
    >>> robot = rk.load("z1")       # a fixed joint and a link are both called 'gripperStator'
    >>> robot.model.frames[frame_index(robot.model, "gripperStator")].type.name
    'BODY'
    """
    import pinocchio as pin

    if model.existFrame(name, pin.FrameType.BODY):
        return int(model.getFrameId(name, pin.FrameType.BODY))
    matches = [k for k, f in enumerate(model.frames) if f.name == name]
    return matches[0] if matches else int(model.nframes)
