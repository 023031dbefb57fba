"""The closed-form IK constants the C emitter reads, gathered in one place (no public names).

Everything comes through robokit's typed contract, :func:`robokit.ik.closed_form_constants`
(a frozen :class:`robokit.ik.ClosedFormConstants` with the method's own frozen dataclass:
:class:`robokit.ik.pieper.PieperConstants`, :class:`robokit.ik.parallel_axes.ParallelAxesConstants`,
:class:`robokit.ik.GeneralSixRConstants`),
re-shaped into the plain :class:`IKConstants` the emitters use (the joint limits are the
robot's own, ``robot.qlim``). If a robot has no closed form, or its DH table cannot be
extracted, the generated files say ``NAME_HAS_IK 0`` and why (kinematics and dynamics are
generated regardless).
"""
from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any, Mapping

import numpy as np

from robokit.ik import ClosedFormConstants, GeneralSixRConstants, closed_form_constants
from robokit.ik.parallel_axes import ParallelAxesConstants
from robokit.ik.pieper import PieperConstants
from robokit.ik.planar_solver import PlanarConstants


@dataclass
class IKConstants:
    """Everything the C IK needs, as plain numbers (see the module docstring)."""

    method: str | None
    reason: str
    reversed: bool = False
    rev: list[bool] = field(default_factory=list)
    lims: list[tuple[float, float]] | None = None
    kinds: list[str] = field(default_factory=list)  # of the solver's chain (reversed when reversed)
    th0: list[float] = field(default_factory=list)
    d0: list[float] = field(default_factory=list)
    base_inv: np.ndarray | None = None
    tool_inv: np.ndarray | None = None
    scale: float = 1.0
    #: Pieper's constants (method "spherical wrist"), else None.
    pieper: PieperConstants | None = None
    #: The three-parallel-axes constants (method "three parallel axes"), else None.
    parallel: ParallelAxesConstants | None = None
    #: The planar method's constants (method "planar"), else None.
    planar: PlanarConstants | None = None
    #: The general 6R method's constants (method "general 6R"), else None.
    general: GeneralSixRConstants | None = None
    flip: list[bool] | None = None  # joints solved as q' = -q (in the robot's order)
    free_flipped: bool = False  # wrist_ref's joint is flipped: the solver gets -wrist_ref
    #: A calibrated or nearly special arm (robokit.ik.calibrated): the fields above are then the
    #: closed form of its projected arm (the starts), and this mapping holds the polish's numbers
    #: (method, reason, shoulder, reach and the kernel's tolerances); None otherwise.
    calibrated: Mapping[str, Any] | None = None
    #: A general 6R arm whose DH table's offsets are kilometres (robokit.ik.closed_form.ILL_DH): every
    #: solution finished by Newton's method on the arm's own kinematics (robokit.ik.general_6r.ArmPolish);
    #: that polish's numbers, else None.
    arm_polish: Mapping[str, Any] | None = None


def ik_constants(robot: Any, nominal: Any = None) -> IKConstants:
    """The closed-form IK constants of ``robot`` (method None with the reason when it has none).

    Parameters
    ----------
    robot : :class:`robokit.Robot`
    nominal : optional
        The nominal structure of a calibrated or nearly special arm (``robokit.ik_analytic``'s).

    Returns
    -------
    IKConstants
        For a calibrated arm: the constants of its projected arm's closed form, with
        ``calibrated`` holding the polish's numbers.
    """
    try:
        c = closed_form_constants(robot, nominal)
    except ValueError as exc:  # e.g. a robot whose DH table cannot be extracted
        return IKConstants(None, str(exc))
    if c.method is None or c.solver is None:
        return IKConstants(None, c.reason)
    return _read(robot, c)


def _read(robot: Any, c: ClosedFormConstants) -> IKConstants:
    kinds = list(c.kinds[::-1] if c.reversed else c.kinds)  # the robot's own order
    qlim = np.asarray(robot.qlim, dtype=float)
    lims = [(float(lo) - 1e-12, float(hi) + 1e-12) for lo, hi in qlim]  # the within_limits tolerance
    return IKConstants(
        c.method, c.reason, c.reversed, [k == "R" for k in kinds], lims, list(c.kinds), list(c.th0), list(c.d0),
        None if c.base_inv is None else np.array(c.base_inv, dtype=float),
        None if c.tool_inv is None else np.array(c.tool_inv, dtype=float), c.scale,
        pieper=c.solver if isinstance(c.solver, PieperConstants) else None,
        parallel=c.solver if isinstance(c.solver, ParallelAxesConstants) else None,
        general=c.solver if isinstance(c.solver, GeneralSixRConstants) else None,
        planar=c.solver if isinstance(c.solver, PlanarConstants) else None,
        flip=None if c.flip is None else list(c.flip), free_flipped=c.free_flipped, calibrated=c.calibrated,
        arm_polish=c.arm_polish)
