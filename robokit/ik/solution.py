r"""One inverse-kinematics solution, and the checks every closed-form solver shares.

:class:`IKSolution` is what every closed-form solver returns (``ik_analytic``, the lecture's
``ik_planar_2link``, ``ik_puma560``, …): a configuration ``q`` that reaches the target, its
branch ``label``, whether it lies inside the joint limits and whether a singular choice was
made. The helpers below turn a solver's raw rows ``(q, label, degenerate)`` into distinct,
wrapped, limit-flagged solutions (:func:`solutions_from_rows`) and check a target pose once
(:func:`check_pose`); they hold no state.

Conventions: revolute joint values in rad, wrapped to (−π, π] — or shifted by 2π where that
lands inside limits wider than ±π —; prismatic joint values in m, untouched.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any, Protocol, Sequence, runtime_checkable

import numpy as np
from numpy.typing import ArrayLike

from robokit.errors import InputError
from robokit.spatial.se3 import check_transform

__all__ = ["IKSolution", "check_pose", "solutions_from_rows"]

#: One raw solution of a closed-form solver: (q (n,), branch label, degenerate).
Row = tuple[Sequence[float], str, bool]

_TWO_PI = 2.0 * math.pi


@dataclass(frozen=True)
class IKSolution:
    """One inverse-kinematics solution.

    Parameters
    ----------
    q : (n,) ndarray
        Joint values (rad for revolute joints, m for prismatic).
    within_limits : bool
        True if every joint is inside its limits (True when no limits are given).
    label : str
        The branch, e.g. ``"elbow up"`` or ``"left, elbow up, no flip"``.
    degenerate : bool
        True if the target is at a singularity where the solver made a documented choice
        for a free angle (e.g. θ₅ = 0 of a spherical wrist).
    extra : dict
        Solver-specific extras (empty for robokit's closed forms); not compared by ``==``.
    collision_free : bool or None
        With a ``world`` (:class:`robokit.collision.World`) given to the solver: whether the
        arm at ``q`` is free of self- and world collisions; None without a world.

    Examples
    --------
    >>> import numpy as np
    >>> IKSolution(np.array([0.0, 1.5708]), True, "elbow down").label
    'elbow down'
    """

    q: np.ndarray
    within_limits: bool = True
    label: str = ""
    degenerate: bool = False
    extra: dict = field(default_factory=dict, compare=False, repr=False)
    collision_free: bool | None = None


def _row_label(rows: list, k: int) -> str:
    """The label of row k of ``rows`` = ``[out, n, codes, names]`` (a :class:`_Rows` or the plain
    list :func:`_solutions_from_kernel` builds): every row's label is decoded on first use, with
    " #2", … for a label that repeats, and kept in ``rows[3]``."""
    names = rows[3]
    if names is None:
        codes = rows[2]
        names = [codes[c] for c in rows[0][:rows[1], 7].tolist()]
        if len(set(names)) < len(names):
            seen: dict[str, int] = {}
            for j, label in enumerate(names):
                seen[label] = seen.get(label, 0) + 1
                if seen[label] > 1:
                    names[j] = f"{label} #{seen[label]}"
        rows[3] = names
    return names[k]


class _Rows(list):
    """The rows of one compiled closed-form solve, ``[out, n, codes, names]`` (``out`` (16, 9): q,
    within, branch code, degenerate per row; ``n`` rows valid; ``codes`` branch code → label;
    ``names`` the decoded labels, None until first used), shared by the :class:`_RowSolution`
    objects made from it. A list, so that the compiled path builds it with one list display."""

    __slots__ = ()

    def __init__(self, out: np.ndarray, n: int, codes: dict) -> None:
        super().__init__((out, n, codes, None))

    @property
    def out(self) -> np.ndarray:
        return self[0]

    @property
    def n(self) -> int:
        return self[1]

    def label(self, k: int) -> str:
        return _row_label(self, k)


class _RowSolution(IKSolution):
    """An :class:`IKSolution` read from row ``_k`` of a compiled solve's output (:class:`_Rows`):
    made with two attribute stores (no ``__init__``, no per-solution arrays or strings), its
    fields decoded when first read — ``q`` a view of the row (the same object on every read),
    ``label`` from the branch code. In every other respect an IKSolution: frozen, the same
    fields, ``repr`` and ``==``; ``dataclasses.replace``, ``copy`` and ``pickle`` give a plain
    IKSolution."""

    __slots__ = ("_rows", "_k", "_q", "_extra")
    _rows: _Rows
    _k: int
    _q: np.ndarray
    _extra: dict

    def __new__(cls, *args: Any, **kwargs: Any) -> IKSolution:  # type: ignore[misc]
        return IKSolution(*args, **kwargs)  # dataclasses.replace(sol, ...) calls type(sol)(...)

    @classmethod
    def from_rows(cls, rows: list) -> list[IKSolution]:
        """One solution per valid row of ``rows`` (a :class:`_Rows`, or ``[out, n, codes, None]``)."""
        return _from_rows(rows, cls)

    @property
    def q(self) -> np.ndarray:  # noqa: D102 - the field of IKSolution
        try:
            return self._q
        except AttributeError:
            q = self._rows[0][self._k, :6]
            _SET_Q(self, q)
            return q

    @property
    def within_limits(self) -> bool:  # noqa: D102
        return bool(self._rows[0][self._k, 6] == 1.0)

    @property
    def label(self) -> str:  # noqa: D102
        return _row_label(self._rows, self._k)

    @property
    def degenerate(self) -> bool:  # noqa: D102
        return bool(self._rows[0][self._k, 8] == 1.0)

    @property
    def extra(self) -> dict:  # noqa: D102
        try:
            return self._extra
        except AttributeError:
            extra: dict = {}
            _SET_EXTRA(self, extra)
            return extra

    def _plain(self) -> IKSolution:
        return IKSolution(self.q, self.within_limits, self.label, self.degenerate, self.extra, self.collision_free)

    def __reduce__(self) -> tuple:
        return (IKSolution, (self.q, self.within_limits, self.label, self.degenerate, self.extra,
                             self.collision_free))

    def __repr__(self) -> str:
        return repr(self._plain())

    def __eq__(self, other: object) -> bool:
        if isinstance(other, _RowSolution):
            other = other._plain()
        return self._plain() == other if isinstance(other, IKSolution) else NotImplemented

    __hash__ = IKSolution.__hash__


_SET_ROWS, _SET_K = _RowSolution._rows.__set__, _RowSolution._k.__set__  # type: ignore[attr-defined]
_SET_Q, _SET_EXTRA = _RowSolution._q.__set__, _RowSolution._extra.__set__  # type: ignore[attr-defined]


def _from_rows(rows: list, cls: type = _RowSolution, new: Any = object.__new__, set_rows: Any = _SET_ROWS,
               set_k: Any = _SET_K) -> list[IKSolution]:
    """One :class:`_RowSolution` per valid row of ``rows`` (``[out, n, codes, names]``): two slot
    stores each, past the frozen ``__setattr__`` (the defaults bind the names once)."""
    result: list[IKSolution] = []
    append = result.append
    for k in range(rows[1]):
        sol = new(cls)
        set_rows(sol, rows)
        set_k(sol, k)
        append(sol)
    return result


def _solutions_from_kernel(out: np.ndarray, n: int, codes: dict) -> list[IKSolution]:
    """The solutions of a compiled closed-form solve's first ``n`` rows of ``out`` (q, within,
    branch code, degenerate; ``codes`` maps a branch code to its label), read lazily from ``out``."""
    return _from_rows([out, n, codes, None]) if n else []


@runtime_checkable
class CollisionChecker(Protocol):
    """What IK needs of a collision world (:class:`robokit.collision.World` is one)."""

    def in_collision(self, q: Any) -> Any:
        """True if the arm at joint values ``q`` (n,) touches itself or an obstacle."""
        ...


def with_collision_flags(solutions: Sequence[IKSolution], world: CollisionChecker | None) -> list[IKSolution]:
    """The solutions with ``.collision_free`` set from ``world`` (unchanged when world is None)."""
    if world is None:
        return list(solutions)
    return [IKSolution(s.q, s.within_limits, s.label, s.degenerate, s.extra, not bool(world.in_collision(s.q)))
            for s in solutions]


def _within(q: np.ndarray, qlim: ArrayLike | None) -> bool:
    """True if q lies inside the (n, 2) limits (1e-12 tolerance); True without limits."""
    if qlim is None:
        return True
    qlim = np.asarray(qlim, dtype=float)
    tol = 1e-12
    return bool(np.all(q >= qlim[:, 0] - tol) and np.all(q <= qlim[:, 1] + tol))


def _qlim_or_none(qlim: ArrayLike | None, n: int, name: str = "qlim") -> np.ndarray | None:
    """The (n, 2) float limits, or None; InputError naming ``name`` for another shape."""
    if qlim is None:
        return None
    arr = np.asarray(qlim, dtype=float)
    if arr.shape != (n, 2):
        raise InputError(f"{name}: expected shape ({n}, 2), got {arr.shape}")
    return arr


def check_pose(T: ArrayLike, name: str = "T") -> np.ndarray:
    """``T`` as a float 4×4 rigid transform, or InputError naming ``name``.

    A clean float64 (4, 4) array with RᵀR = I to 1e-9, det R > 0 and last row (0, 0, 0, 1)
    is accepted by a quick scalar test (a closed-form solve costs a few µs, numpy's checks
    would double it); anything else goes through :func:`robokit.spatial.check_transform`,
    which converts it or raises.

    Parameters
    ----------
    T : (4, 4) array_like
        A pose (m).
    name : str
        The argument's name in the error message.

    Returns
    -------
    (4, 4) ndarray
        ``T`` itself when it is already a clean float array.

    Examples
    --------
    >>> import numpy as np
    >>> check_pose(np.eye(4)).shape
    (4, 4)
    """
    if type(T) is np.ndarray and T.dtype == np.float64 and T.shape == (4, 4):
        (a, b, c, _), (d, e, f, _), (g, h, i, _), last = T.tolist()
        dev = max(abs(a * a + d * d + g * g - 1.0), abs(b * b + e * e + h * h - 1.0), abs(c * c + f * f + i * i - 1.0),
                  abs(a * b + d * e + g * h), abs(a * c + d * f + g * i), abs(b * c + e * f + h * i))
        det = a * (e * i - f * h) - b * (d * i - f * g) + c * (d * h - e * g)
        finite = math.isfinite(a + b + c + d + e + f + g + h + i + T[0, 3] + T[1, 3] + T[2, 3])
        if finite and dev < 1e-9 and det > 0.0 and last == [0.0, 0.0, 0.0, 1.0]:
            return T
    try:
        return check_transform(T, name)
    except InputError:
        raise
    except ValueError as exc:  # the spatial checks raise plain ValueErrors
        raise InputError(str(exc)) from None


_new = object.__new__


def _solution(q: np.ndarray, within_limits: bool, label: str, degenerate: bool) -> IKSolution:
    """An IKSolution built without the frozen dataclass's field-by-field ``__init__`` (a
    quarter of the cost of a call for 8 solutions); the same object in every respect."""
    sol = _new(IKSolution)
    sol.__dict__.update(q=q, within_limits=within_limits, label=label, degenerate=degenerate, extra={})
    return sol


def solutions_from_rows(rows: Sequence[Row], revolute: Sequence[bool],
                        limits: Sequence[tuple[float, float]] | None) -> list[IKSolution]:
    """Wrap, shift into limits, flag, drop duplicates, label: raw rows → :class:`IKSolution`.

    Parameters
    ----------
    rows : sequence of (q (n,), label, degenerate)
        A solver's raw solutions (joint values in rad/m, any angle range).
    revolute : (n,) sequence of bool
        Which joints are revolute (their values are wrapped to (−π, π]).
    limits : (n,) sequence of (lo, hi) or None
        Joint limits with the 1e-12 tolerance of ``within_limits`` already folded in.

    Returns
    -------
    list of IKSolution
        Distinct solutions (angles compared modulo 2π to 1e-9), revolute values wrapped to
        (−π, π] or shifted by ±2π into limits wider than ±π; a label that repeats gets
        " #2", " #3", ….

    Notes
    -----
    Plain Python on at most a few dozen numbers (numpy's per-call overhead would dominate).

    Examples
    --------
    >>> sols = solutions_from_rows([((4.0, 0.5), "a", False), ((4.0 - 6.283185307179586, 0.5), "a", False)],
    ...                            [True, True], None)
    >>> len(sols), round(float(sols[0].q[0]), 4)
    (1, -2.2832)
    """
    if not rows:
        return []
    rev = list(revolute)
    all_rev = all(rev)
    lims = limits
    rem = math.remainder
    two_pi, pi = _TWO_PI, math.pi
    kept: list[list[float]] = []
    meta: list[tuple[bool, str, bool]] = []
    labels: dict[str, int] = {}
    for q, label, degen in rows:
        if all_rev:
            qq = [rem(v, two_pi) for v in q]
        else:
            qq = [(rem(v, two_pi) if r else float(v)) for v, r in zip(q, rev)]
        if -pi in qq:  # (−π, π]
            qq = [(pi if (v == -pi and r) else v) for v, r in zip(qq, rev)]
        inside = True
        if lims is not None:
            for j, (lo, hi) in enumerate(lims):
                v = qq[j]
                if v < lo or v > hi:
                    if rev[j] and lo <= v + two_pi <= hi:
                        qq[j] = v + two_pi  # limits wider than ±π: the shifted angle is inside
                    elif rev[j] and lo <= v - two_pi <= hi:
                        qq[j] = v - two_pi
                    else:
                        inside = False
        dup = False
        for other in kept:  # distinct solutions only (angles compared modulo 2π)
            for v, o, r in zip(qq, other, rev):
                d = rem(v - o, two_pi) if r else v - o
                if d >= 1e-9 or d <= -1e-9:
                    break
            else:
                dup = True
                break
        if dup:
            continue
        kept.append(qq)
        n = labels.get(label, 0) + 1
        labels[label] = n
        meta.append((inside, label if n == 1 else f"{label} #{n}", bool(degen)))
    Q = np.array(kept)
    return [_solution(Q[k], *meta[k]) for k in range(len(kept))]
