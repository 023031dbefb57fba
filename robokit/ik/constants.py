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
``"planar"``                      :class:`robokit.ik.planar_solver.PlanarConstants`
``"general 6R"``                  :class:`GeneralSixRConstants` (its readings
                                  :class:`GeneralSixRReading`), built from
                                  :meth:`robokit.ik.general_6r.GeneralSixR.export_constants`
                                  (also kept as that read-only mapping, ``general_6r``)
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
from robokit.ik.planar_solver import PlanarConstants, PlanarSolver

if TYPE_CHECKING:
    from robokit.description.dh import DHTable
    from robokit.description.robot import Robot

__all__ = ["ClosedFormConstants", "GeneralSixRConstants", "GeneralSixRReading", "closed_form_constants"]

Matrix4 = tuple[tuple[float, float, float, float], ...]
Table = tuple[tuple[float, ...], ...]


def _floats(x: Any) -> tuple[float, ...]:
    return tuple(float(v) for v in np.asarray(x, dtype=float).reshape(-1))


def _rows(x: Any) -> Table:
    return tuple(_floats(r) for r in np.asarray(x, dtype=float))


def _ints(x: Any) -> tuple[int, ...]:
    return tuple(int(v) for v in np.asarray(x).reshape(-1))


@dataclass(frozen=True)
class GeneralSixRReading:
    r"""One reading of the loop equation of the general 6R method, as numbers (one item of
    :attr:`GeneralSixRConstants.readings`; ``export_constants()["arrangements"]``).

    Attributes
    ----------
    roles : tuple of int
        Joint indices (0-based): the pivot (the eigenvalue), the other two of its group, the
        two of the 14 × 8 system, the eliminated joint.
    three_has_w : bool
        The target's map is on the three-joint side.
    w_index : int
        The slot of ``Ms`` replaced per pose by ``pre · F(W) · post``.
    w_inverse : bool
        W is T₀₆ (not T₀₆⁻¹).
    deflate : int
        How many eigenvalue pairs x = ±i the solve removes before its eigenvalue iteration
        (0: none tried).
    const : tuple of tuple of float
        The side without the target as its tensor, 3ᵏ rows of 15.
    Ms : tuple of tables
        The target side's k + 1 maps, 15 × 15 each.
    pre, post : tuple of tuple of float
        15 × 15 each.
    signs : tuple of float
        The signs of the target side's k joint rotations.
    f : tuple of float
        The target side's start vector (15).
    perm3, perm2 : tuple of int
        The rows of the two sides' tensors behind P (27) and r (9).

    Examples
    --------
    >>> import robokit
    >>> from robokit.ik.general_6r import GeneralSixR
    >>> from robokit.ik._dh_chain import DHChain
    >>> c = GeneralSixRConstants.from_export(GeneralSixR(DHChain(robokit.load("puma560").dh)).export_constants())
    >>> r = c.readings[0]
    >>> len(r.perm3), len(r.perm2), len(r.Ms) == len(r.signs) + 1, len(r.pre), len(r.pre[0])
    (27, 9, True, 15, 15)
    """

    roles: tuple[int, ...]
    three_has_w: bool
    w_index: int
    w_inverse: bool
    deflate: int
    const: Table
    Ms: tuple[Table, ...]
    pre: Table
    post: Table
    signs: tuple[float, ...]
    f: tuple[float, ...]
    perm3: tuple[int, ...]
    perm2: tuple[int, ...]


@dataclass(frozen=True)
class GeneralSixRConstants:
    r"""The numbers of the general 6R method (Raghavan–Roth elimination) for one arm, as the C
    emitter reads them (:mod:`robokit.codegen.ik_general`).

    Attributes
    ----------
    alpha : tuple of float
        Twists α₁ … α₅ of the canonical chain (rad).
    a : tuple of float
        Lengths a₁ … a₅, divided by ``scale``.
    d : tuple of float
        Offsets d₁ … d₆, divided by ``scale``.
    th0 : tuple of float
        Joint offsets θ₀ (rad).
    scale : float
        The chain's size (m).
    gamma : float
        The pivot's turn γ (rad): ``θ = 2 atan x + γ``.
    imag_tol, converged, same, x0, poor, turn : float
        The solver's tolerances: an eigenvalue's imaginary part as an angle, the converged pose
        error, the same solution (rad), where the pencil's regularity is measured, the badly
        conditioned reading, the fixed turn of the variable when A is near singular (rad).
    readings : tuple of GeneralSixRReading
        The readings solved, the best first (the next ones on a badly conditioned pose).

    Examples
    --------
    >>> import numpy as np, robokit
    >>> from robokit.description.dh import DHLink, DHTable
    >>> rng = np.random.default_rng(3)
    >>> table = DHTable("g", "standard", tuple(DHLink("R", a=rng.uniform(-.5, .5), alpha=rng.uniform(-3, 3),
    ...                                               d=rng.uniform(-.5, .5)) for _ in range(6)))
    >>> c = closed_form_constants(robokit.load(table))
    >>> c.method, type(c.solver).__name__, len(c.solver.readings)
    ('general 6R', 'GeneralSixRConstants', 4)
    """

    alpha: tuple[float, ...]
    a: tuple[float, ...]
    d: tuple[float, ...]
    th0: tuple[float, ...]
    scale: float
    gamma: float
    imag_tol: float
    converged: float
    same: float
    x0: float
    poor: float
    turn: float
    readings: tuple[GeneralSixRReading, ...]

    @classmethod
    def from_export(cls, e: Mapping[str, Any]) -> "GeneralSixRConstants":
        """The record of ``GeneralSixR.export_constants()``.

        Parameters
        ----------
        e : mapping
            The export (keys as documented there).

        Returns
        -------
        GeneralSixRConstants
            The same numbers as a typed record, one :class:`GeneralSixRReading` per reading.

        Examples
        --------
        >>> import robokit
        >>> from robokit.ik.general_6r import GeneralSixR
        >>> from robokit.ik._dh_chain import DHChain
        >>> chain = DHChain(robokit.load("puma560").dh)
        >>> GeneralSixRConstants.from_export(GeneralSixR(chain).export_constants()).readings[0].roles[5] >= 0
        True
        """
        readings = tuple(GeneralSixRReading(
            _ints(r["roles"]), bool(r["three_has_w"]), int(r["w_index"]), bool(r["w_inverse"]), int(r["deflate"]),
            _rows(r["const"]), tuple(_rows(M) for M in np.asarray(r["Ms"], dtype=float)), _rows(r["pre"]),
            _rows(r["post"]), _floats(r["signs"]), _floats(r["f"]), _ints(r["perm3"]), _ints(r["perm2"]))
            for r in e["arrangements"])
        return cls(_floats(e["alpha"]), _floats(e["a"]), _floats(e["d"]), _floats(e["th0"]), float(e["scale"]),
                   float(e["gamma"]), float(e["imag_tol"]), float(e["converged"]), float(e["same"]), float(e["x0"]),
                   float(e["poor"]), float(e["turn"]), readings)


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
        ``"spherical wrist"``, ``"three parallel axes"``, ``"planar"``, ``"general 6R"`` (for a calibrated arm:
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
    solver : PieperConstants, ParallelAxesConstants, PlanarConstants, GeneralSixRConstants or None
        The method's own numbers (None without a closed form, or for a registered solver that
        exports none).
    general_6r : mapping or None
        For ``"general 6R"``: ``GeneralSixR.export_constants()``, read-only.
    calibrated : mapping or None
        For a calibrated or nearly special arm: the polish's numbers
        (``CalibratedArm.export_constants()``: method, reason, shoulder, reach, tolerances), read-only.
    arm_polish : mapping or None
        For a general 6R arm whose DH table's offsets exceed ``ILL_DH`` × its size (every solution
        finished on the arm's own kinematics: :class:`robokit.ik.general_6r.ArmPolish`): that polish's
        numbers (``ArmPolish.export_constants()``), read-only; None otherwise.

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
    solver: PieperConstants | ParallelAxesConstants | PlanarConstants | GeneralSixRConstants | None = None
    general_6r: Mapping[str, Any] | None = None
    calibrated: Mapping[str, Any] | None = None
    arm_polish: Mapping[str, Any] | None = None


def _export(ik: AnalyticIK) -> ClosedFormConstants:
    """The record of one AnalyticIK without the calibrated part."""
    sv = ik.solver
    if not ik.kind or sv is None:
        return ClosedFormConstants(ik.kind.method, ik.kind.reason)
    sc = sv.chain  # the chain the solver solves (the robot's read backwards when reversed)
    solver: PieperConstants | ParallelAxesConstants | PlanarConstants | GeneralSixRConstants | None = None
    general: Mapping[str, Any] | None = None
    if isinstance(sv, (PieperSolver, ParallelAxesSolver, PlanarSolver)):
        solver = sv.constants()
    else:
        export = getattr(sv, "export_constants", None)  # a registered solver's own export (general 6R)
        if export is not None:
            general = MappingProxyType(dict(export()))
            if ik.kind.method == "general 6R":
                solver = GeneralSixRConstants.from_export(general)
    flip = ik._flip
    return ClosedFormConstants(
        ik.kind.method, ik.kind.reason, bool(ik.reversed), tuple(str(k) for k in sc.kinds),
        tuple(float(x) for x in sc.th0), tuple(float(x) for x in sc.d0), _matrix(sc.base_inv), _matrix(sc.tool_inv),
        float(sc.scale), None if flip is None else tuple(bool(f) for f in flip), bool(ik._free_flipped), solver,
        general, None, None if ik._arm_polish is None else MappingProxyType(dict(ik._arm_polish.export_constants())))


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
