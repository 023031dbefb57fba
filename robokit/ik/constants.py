r"""The typed contract between the closed-form IK and the code generators.

A robot's closed-form IK (:class:`robokit.ik.AnalyticIK`) holds a solver built once from the
canonical chain ``Z₁X₁ ⋯ Z₆`` (:mod:`robokit.ik._dh_chain`). :func:`closed_form_constants`
exports everything another implementation of the same algorithm needs — the C written by
:mod:`robokit.codegen`, the compiled kernels — as one immutable record,
:class:`ClosedFormConstants`: the chain (joint kinds, offsets, base′⁻¹ and tool′⁻¹, scale),
how the robot's joints map onto it (read backwards, flipped joints) and the solver's own
numbers, one frozen dataclass per method:

================================  ===========================================================
``"spherical wrist"``             :class:`robokit.ik.pieper.PieperConstants`
``"three parallel axes"``         :class:`robokit.ik.parallel_axes.ParallelAxesConstants`
``"general 6R"``                  ``general_6r``: the read-only mapping of
                                  :meth:`robokit.ik.general_6r.GeneralSixR.export_constants`
================================  ===========================================================

A calibrated or nearly special arm (:mod:`robokit.ik.calibrated`) exports the constants of its
projected arm's closed form (the starts) with ``calibrated``, the read-only mapping of the
polish's numbers (``CalibratedArm.export_constants``).
"""
from __future__ import annotations

from dataclasses import dataclass, replace
from types import MappingProxyType
from typing import TYPE_CHECKING, Any, Mapping

import numpy as np

from robokit.ik.closed_form import AnalyticIK, analytic_ik
from robokit.ik.parallel_axes import ParallelAxesConstants, ParallelAxesSolver
from robokit.ik.pieper import PieperConstants, PieperSolver

if TYPE_CHECKING:
    from robokit.description.dh import DHTable
    from robokit.description.robot import Robot

__all__ = ["ClosedFormConstants", "closed_form_constants"]

Matrix4 = tuple[tuple[float, float, float, float], ...]


def _matrix(T: Any) -> Matrix4 | None:
    if T is None:
        return None
    A = np.asarray(T, dtype=float)
    return tuple((float(r[0]), float(r[1]), float(r[2]), float(r[3])) for r in A)


@dataclass(frozen=True)
class ClosedFormConstants:
    r"""A robot's closed-form IK as numbers (what :func:`closed_form_constants` returns).

    Attributes
    ----------
    method : str or None
        ``"spherical wrist"``, ``"three parallel axes"``, ``"general 6R"`` (for a calibrated arm:
        its projected arm's method) or None when no closed form applies.
    reason : str
        Why the method applies, or why none does (:func:`robokit.ik_analytic_kind`'s sentence).
    reversed : bool
        The structure is found counted from the tool: the solver's chain is the robot's read
        backwards (joint k ↔ joint 7 − k, q′ = −q) and reaches T⁻¹.
    kinds : tuple of str
        ``"R"``/``"P"`` of the solver's chain's joints (reversed when ``reversed``).
    th0, d0 : tuple of float
        The solver's chain's joint offsets θ₀ (rad) and d₀ (m).
    base_inv, tool_inv : 4×4 tuple of tuple of float, or None
        ``T₀₆ = base_inv · T · tool_inv`` (T⁻¹ when reversed); None for the identity.
    scale : float
        The chain's size (m): tolerances are relative to it.
    flip : tuple of bool or None
        The robot's joints (its own order) written ``θ = θ₀ − q`` in the DH table: solved as
        q′ = −q. None when there are none.
    free_flipped : bool
        The joint a singular pose leaves free (``wrist_ref``'s) is flipped: the solver gets −wrist_ref.
    solver : PieperConstants, ParallelAxesConstants or None
        The method's own numbers (None for ``"general 6R"`` and without a closed form).
    general_6r : mapping or None
        For ``"general 6R"``: ``GeneralSixR.export_constants()``, read-only.
    calibrated : mapping or None
        For a calibrated or nearly special arm: the polish's numbers
        (``CalibratedArm.export_constants()``: method, reason, shoulder, reach, tolerances), read-only.

    Examples
    --------
    >>> import robokit
    >>> c = closed_form_constants(robokit.load("ur5"))
    >>> c.method, type(c.solver).__name__, c.reversed
    ('three parallel axes', 'ParallelAxesConstants', False)
    """

    method: str | None
    reason: str
    reversed: bool = False
    kinds: tuple[str, ...] = ()
    th0: tuple[float, ...] = ()
    d0: tuple[float, ...] = ()
    base_inv: Matrix4 | None = None
    tool_inv: Matrix4 | None = None
    scale: float = 1.0
    flip: tuple[bool, ...] | None = None
    free_flipped: bool = False
    solver: PieperConstants | ParallelAxesConstants | None = None
    general_6r: Mapping[str, Any] | None = None
    calibrated: Mapping[str, Any] | None = None


def _export(ik: AnalyticIK) -> ClosedFormConstants:
    """The record of one AnalyticIK without the calibrated part."""
    sv = ik.solver
    if not ik.kind or sv is None:
        return ClosedFormConstants(ik.kind.method, ik.kind.reason)
    sc = sv.chain  # the chain the solver solves (the robot's read backwards when reversed)
    solver: PieperConstants | ParallelAxesConstants | None = None
    general: Mapping[str, Any] | None = None
    if isinstance(sv, (PieperSolver, ParallelAxesSolver)):
        solver = sv.constants()
    else:
        export = getattr(sv, "export_constants", None)  # a registered solver's own export (general 6R)
        if export is not None:
            general = MappingProxyType(dict(export()))
    flip = ik._flip
    return ClosedFormConstants(
        ik.kind.method, ik.kind.reason, bool(ik.reversed), tuple(str(k) for k in sc.kinds),
        tuple(float(x) for x in sc.th0), tuple(float(x) for x in sc.d0), _matrix(sc.base_inv), _matrix(sc.tool_inv),
        float(sc.scale), None if flip is None else tuple(bool(f) for f in flip), bool(ik._free_flipped), solver,
        general)


def closed_form_constants(robot: Robot | DHTable, nominal: Any = None) -> ClosedFormConstants:
    """Every number of ``robot``'s closed-form IK, as one immutable record (see the module docstring).

    Parameters
    ----------
    robot : :class:`robokit.Robot` or :class:`robokit.DHTable`
        Any robot; one without a closed form gives ``method`` None and the reason.
    nominal : Robot, DHTable, RobotSpec, str or False, optional
        The nominal structure of a calibrated or nearly special arm (as :func:`robokit.ik_analytic`'s).

    Returns
    -------
    ClosedFormConstants
        The constants of the solver :func:`robokit.ik_analytic` uses; for a calibrated arm those
        of its projected arm's closed form, with ``calibrated`` set.

    Raises
    ------
    ValueError
        If the robot's DH table cannot be extracted (as :func:`robokit.ik.analytic_ik`).

    Examples
    --------
    >>> import robokit
    >>> c = closed_form_constants(robokit.load("puma560"))
    >>> c.method, c.solver.case, c.solver.deg
    ('spherical wrist', 'RR-a1', 2)
    >>> closed_form_constants(robokit.load("panda")).method is None
    True
    """
    ik = analytic_ik(robot, nominal) if nominal is not None else analytic_ik(robot)
    cal = ik.calibrated
    if ik.kind and cal is not None:
        out = _export(cal.nominal)
        return replace(out, calibrated=MappingProxyType(dict(cal.export_constants())))
    return _export(ik)
