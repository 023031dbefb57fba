"""A frame by name, when several frames of a Pinocchio model share it.

A URDF may give a joint and its child link one name (example-robot-data's Z1: the fixed joint
``gripperStator`` and the link ``gripperStator``); Pinocchio then has a joint frame and a body
frame of that name, and ``model.getFrameId(name)`` refuses to choose. robokit's rule: a name
means the link — the body frame — when there is one, else an operational frame (an MJCF
``<site>``, an SDFormat ``<frame>``, a tool), else the one frame of that name. (In a URDF the
body and joint frames coincide: a child link's frame is its joint's frame. In MJCF they need not:
MuJoCo keeps one namespace per kind, and dm_control's humanoid has a site and a joint both called
``left_knee`` — the name of a tip or frame there is a body's or a site's, never a joint's.)
"""
from __future__ import annotations

from typing import Any

__all__ = ["frame_index"]


def frame_index(model: Any, name: str) -> int:
    """The index of the frame called ``name``: its body frame when another frame shares the name,
    else its operational frame (a site) rather than a joint frame.

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
    ops = [k for k in matches if model.frames[k].type == pin.FrameType.OP_FRAME]
    return (ops or matches or [int(model.nframes)])[0]
