"""The closed-form IK constants the C emitter reads, gathered in one place (no public names).

This is the only module of :mod:`robokit.codegen` that knows how :mod:`robokit.ik` holds a
robot's closed-form solver. It asks robokit's public interface for the solver — the
:class:`robokit.ik.AnalyticIK` object of ``robokit.ik.analytic_ik(robot)`` where robokit has it,
else the model ``robokit.ik_analytic_kind`` caches on the robot — and copies the solver's
numbers into a plain :class:`IKConstants`. If the solvers' internals change, this is the one
place to follow them; if a number is missing, the generated files say ``NAME_HAS_IK 0`` and
why (kinematics and dynamics are generated regardless).

Read from the closed-form object: ``kind`` (method, reason), ``reversed``, ``chain.kinds``,
the flipped joints (``_flip``, ``_free_flipped``: DH joints with ``flip: true``, solved as
q′ = −q), ``solver.chain`` (``kinds``, ``th0``, ``d0``, ``base_inv``, ``tool_inv``, ``scale``)
and the solver's constants (Pieper: ``case``, ``deg``, ``C_list``, ``w6_list``, ``w3_list``,
``th0_list``, ``d0_list``, ``ca``, ``sa``, ``a1``, ``a2``, ``d1``, ``d2``, ``f``, ``Ka``,
``phi``, ``nf2``, ``v``, ``j1``, ``j2``, ``ca4``…``sa5``; three parallel axes: ``ca``, ``sa``,
``s2``, ``sig``, ``a1``…``a5``, ``d1``, ``d5``, ``d6``, ``KW``, ``w6_list``, ``th0_list``; general
6R: the dict of ``GeneralSixR.export_constants()`` — the scaled chain, the tolerances and the
four best readings' tables).
The joint limits are the robot's own (``robot.qlim``).
"""
from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np


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
    solver: dict[str, Any] = field(default_factory=dict)
    flip: list[bool] | None = None  # joints solved as q' = -q (in the robot's order)
    free_flipped: bool = False  # wrist_ref's joint is flipped: the solver gets -wrist_ref
    #: A calibrated or nearly special arm (robokit.ik.calibrated): the fields above are then the
    #: closed form of its projected arm (the starts), and this dict holds the polish's numbers
    #: (method, reason, shoulder, reach and the kernel's tolerances); None otherwise.
    calibrated: dict[str, Any] | None = None


_PIEPER = ("case", "deg", "C_list", "w6_list", "w3_list", "th0_list", "d0_list", "ca", "sa", "a1", "a2", "d1",
           "d2", "f", "v", "ca4", "sa4", "ca5", "sa5", "j1", "j2")
_PARALLEL = ("ca", "sa", "s2", "sig", "a1", "a2", "a3", "a4", "a5", "d1", "d5", "d6", "KW", "w6_list", "th0_list")


def _closed_form(robot: Any, nominal: Any = None) -> tuple[Any, Any, Any, bool]:
    """(kind, solver, chain of the robot, reversed) from robokit's closed-form IK object."""
    import robokit.ik as rik

    maker = getattr(rik, "analytic_ik", None)
    if maker is not None:  # the AnalyticIK object
        ik = maker(robot, nominal) if nominal is not None else maker(robot)
        return ik.kind, ik.solver, ik, bool(ik.reversed)
    kind = rik.ik_analytic_kind(robot)  # builds and caches the closed-form model on the robot
    model = getattr(robot, "_closed_form", None)
    if model is None:
        return kind, None, None, False
    return kind, model.solver, model, bool(model.reversed)


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
        kind, solver, owner, rev = _closed_form(robot, nominal)
    except ValueError as exc:  # e.g. a robot whose DH table cannot be extracted
        return IKConstants(None, str(exc))
    cal = getattr(owner, "calibrated", None)
    if kind and cal is not None:
        try:
            nom = cal.nominal
            out = _read(robot, nom.kind, nom.solver, nom, bool(nom.reversed))
            out.calibrated = cal.export_constants()
            return out
        except (AttributeError, KeyError, TypeError) as exc:
            return IKConstants(None, f"robokit's calibrated IK ({kind.method}) does not expose the constants the "
                                     f"C emitter reads ({type(exc).__name__}: {exc}); please report")
    if not kind or solver is None:
        return IKConstants(None, kind.reason)
    try:
        return _read(robot, kind, solver, owner, rev)
    except (AttributeError, KeyError, TypeError) as exc:  # the solver's internals moved: say so, keep FK etc.
        return IKConstants(None, f"robokit's closed-form solver ({kind.method}) does not expose the constants "
                                 f"the C emitter reads ({type(exc).__name__}: {exc}); please report")


def _read(robot: Any, kind: Any, sv: Any, owner: Any, reversed_: bool) -> IKConstants:
    sc = sv.chain  # the chain the solver solves (read backwards when reversed)
    kinds = [str(k) for k in (sc.kinds[::-1] if reversed_ else sc.kinds)]  # the robot's own order
    qlim = np.asarray(robot.qlim, dtype=float)
    lims = [(float(lo) - 1e-12, float(hi) + 1e-12) for lo, hi in qlim]  # the within_limits tolerance
    flip = getattr(owner, "_flip", None)
    out = IKConstants(kind.method, kind.reason, reversed_, [k == "R" for k in kinds], lims,
                      [str(k) for k in sc.kinds], [float(x) for x in sc.th0], [float(x) for x in sc.d0],
                      None if sc.base_inv is None else np.array(sc.base_inv, dtype=float),
                      None if sc.tool_inv is None else np.array(sc.tool_inv, dtype=float), float(sc.scale),
                      flip=None if flip is None else [bool(f) for f in flip],
                      free_flipped=bool(getattr(owner, "_free_flipped", False)))
    if kind.method == "general 6R":  # the elimination's per-arm numbers, through its one export method
        out.solver.update(sv.export_constants())
        return out
    names = _PIEPER if kind.method == "spherical wrist" else _PARALLEL
    for name in names:
        out.solver[name] = getattr(sv, name)
    if kind.method == "spherical wrist":
        if sv.j2 == "R" and sv.j1 == "R":
            out.solver["Ka"] = np.asarray(sv.Ka, dtype=float)
        if sv.j2 == "P":
            out.solver["phi"] = tuple(np.asarray(x, dtype=float) for x in sv.phi)
            out.solver["nf2"] = np.asarray(sv.nf2, dtype=float)
    return out
