"""The closed-form IK constants the C emitter reads, gathered in one place (no public names).

This is the only module of :mod:`robokit.codegen` that knows how :mod:`robokit.ik` stores a
robot's closed-form solver: it calls the public ``ik_analytic_kind`` (which builds and caches
the solver on the robot) and copies the solver's numbers into a plain :class:`IKConstants`.
If the solvers' internals change, this is the one place to follow them.

Read from the cached closed-form model: ``kind`` (method, reason), ``reversed``,
``rev_list``, ``lim_list``, ``solver_chain`` (``kinds``, ``th0``, ``d0``, ``base_inv``,
``tool_inv``, ``scale``) and the solver's constants (Pieper: ``case``, ``deg``, ``C_list``,
``w6_list``, ``w3_list``, ``th0_list``, ``d0_list``, ``ca``, ``sa``, ``a1``, ``a2``, ``d1``,
``d2``, ``f``, ``Ka``, ``phi``, ``nf2``, ``v``, ``j1``, ``j2``; three parallel axes: ``ca``, ``sa``, ``s2``, ``sig``,
``a1``…``a5``, ``d1``, ``d5``, ``d6``, ``KW``, ``w6_list``, ``th0_list``).
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


_PIEPER = ("case", "deg", "C_list", "w6_list", "w3_list", "th0_list", "d0_list", "ca", "sa", "a1", "a2", "d1",
           "d2", "f", "v", "ca4", "sa4", "ca5", "sa5")
_PARALLEL = ("ca", "sa", "s2", "sig", "a1", "a2", "a3", "a4", "a5", "d1", "d5", "d6", "KW", "w6_list", "th0_list")


def ik_constants(robot: Any) -> IKConstants:
    """The closed-form IK constants of ``robot`` (method None with the reason when it has none)."""
    from robokit.ik import ik_analytic_kind

    try:
        kind = ik_analytic_kind(robot)
    except ValueError as exc:  # e.g. a robot whose DH table cannot be extracted
        return IKConstants(None, str(exc))
    model = getattr(robot, "_closed_form", None)
    if not kind or model is None or getattr(model, "solver", None) is None:
        return IKConstants(None, kind.reason)
    try:
        return _read(kind, model)
    except (AttributeError, KeyError, TypeError) as exc:  # the solver's internals moved: say so, keep FK etc.
        return IKConstants(None, f"robokit's closed-form solver ({kind.method}) does not expose the constants "
                                 f"the C emitter reads ({type(exc).__name__}: {exc}); please report")


def _read(kind: Any, model: Any) -> IKConstants:
    sv, sc = model.solver, model.solver_chain
    out = IKConstants(kind.method, kind.reason, bool(model.reversed), list(model.rev_list),
                      None if model.lim_list is None else [(float(a), float(b)) for a, b in model.lim_list],
                      [str(k) for k in sc.kinds], [float(x) for x in sc.th0], [float(x) for x in sc.d0],
                      None if sc.base_inv is None else np.array(sc.base_inv, dtype=float),
                      None if sc.tool_inv is None else np.array(sc.tool_inv, dtype=float), float(sc.scale))
    names = _PIEPER if kind.method == "spherical wrist" else _PARALLEL
    for name in names:
        if hasattr(sv, name):
            out.solver[name] = getattr(sv, name)
    if kind.method == "spherical wrist":
        if sv.j2 == "R" and sv.j1 == "R":
            out.solver["Ka"] = np.asarray(sv.Ka, dtype=float)
        if sv.j2 == "P":
            out.solver["phi"] = tuple(np.asarray(x, dtype=float) for x in sv.phi)
            out.solver["nf2"] = np.asarray(sv.nf2, dtype=float)
    return out
