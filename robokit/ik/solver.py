r"""The interface every closed-form 6-joint solver implements (used by :class:`robokit.ik.AnalyticIK`).

A closed-form solver is built once per robot from the canonical chain
``Z₁X₁Z₂X₂ ⋯ X₅Z₆`` of :mod:`robokit.ik._dh_chain` (both DH conventions), computes its own
constants in ``__init__`` (nothing is written into it from outside), and answers for a target
``T06`` — the pose to reach with ``Z₁X₁ ⋯ Z₆``, i.e. the tip pose with the chain's base′ and
tool′ removed — in three steps, the Lecture 5 decoupling:

``position(T06) -> list[PositionBranch]``
    **The position sub-problem**: the joints fixed by a point of the arm that the last joints
    do not move (Pieper: θ₁–θ₃ from the wrist centre W; the UR family: θ₁ from W's coordinate
    along the parallel axes). Each :class:`PositionBranch` carries those joint values, the
    branch label so far (``"right, elbow up, "``), a degenerate flag and whatever the wrist
    step needs (``data``; opaque to the caller).
``wrist(T06, branch, wrist_ref) -> list[Row]``
    **The wrist sub-problem**: completes one branch to every full solution, each a row
    ``(q (6,), label, degenerate)`` of joint *variables* (rad, m; the DH offsets already
    removed; any angle range). At a singularity the free joint takes ``wrist_ref``.
``joint_angles(T06, wrist_ref) -> list[Row]``
    **The joint angles**: every row of every branch (``wrist`` over ``position``) — the one
    call :class:`robokit.ik.AnalyticIK` makes; a solver may compute it in one pass.
``refusal() -> str | None``
    None if the solver applies to its chain, else the reason in the arm's terms (e.g. a
    wrist centre that joints 1–3 cannot move in three directions).
``method : str``
    The structure's name as :func:`robokit.ik_analytic_kind` reports it
    (``"spherical wrist"``, ``"three parallel axes"``, …).

:class:`robokit.ik.AnalyticIK` does the rest for every solver: removes base′/tool′, reads a
chain backwards when the structure is found counted from the tool, wraps, shifts into the
limits, drops duplicates and flags limits (:func:`robokit.ik.solution.solutions_from_rows`).
A solver whose method has no natural split (a general 6R elimination) implements
``position`` as the whole solve, returning complete branches, and ``wrist`` as the identity
on them; ``joint_angles`` is what must be right. The test suite checks the interface with a
hand-written toy solver.

Register a new solver either under a structure the detection in ``robokit.ik.closed_form``
reports (``closed_form.SOLVERS[method] = cls``), or — for a solver that decides for itself,
such as a general 6R elimination — by appending its class to ``closed_form.FALLBACK``: it is
then tried for every 6-joint arm none of the special structures fits (so its constructor must
accept any 6-joint chain without raising), and takes the arm when its ``refusal()`` returns
None.
"""
from __future__ import annotations

from typing import TYPE_CHECKING, Any, NamedTuple, Protocol, Sequence, runtime_checkable

import numpy as np

from robokit.ik.solution import Row

if TYPE_CHECKING:
    from robokit.ik._dh_chain import DHChain

__all__ = ["ClosedFormSolver", "PositionBranch"]


class PositionBranch(NamedTuple):
    """One branch of the position sub-problem.

    Attributes
    ----------
    q : sequence of float
        Joint values fixed by the position step (joints 1..k; rad or m, offsets removed).
    label : str
        The branch label so far (ends with ``", "`` when the wrist step appends to it).
    degenerate : bool
        True if a singular choice was made.
    data : object, optional
        What the wrist step needs (solver-specific; e.g. Pieper's rotation angles θ₁–θ₃).

    Examples
    --------
    >>> b = PositionBranch(q=(0.1, 0.2, 0.3), label="right, elbow up, ", degenerate=False)
    >>> b.label + "no flip", b.data is None
    ('right, elbow up, no flip', True)
    """

    q: Sequence[float]
    label: str
    degenerate: bool
    data: Any = None


@runtime_checkable
class ClosedFormSolver(Protocol):
    """A closed-form solver for one canonical chain (see the module docstring).

    A :class:`typing.Protocol`: any class with these members is a solver.

    Attributes
    ----------
    method : str
        The structure's name, as :func:`robokit.ik_analytic_kind` reports it.
    chain : DHChain
        The canonical chain ``Z₁X₁ ⋯ Z₆`` the solver was built for (:mod:`robokit.ik._dh_chain`).

    Examples
    --------
    >>> import robokit
    >>> from robokit.ik.closed_form import AnalyticIK
    >>> solver = AnalyticIK(robokit.load("puma560")).solver
    >>> isinstance(solver, ClosedFormSolver), solver.method, solver.refusal() is None
    (True, 'spherical wrist', True)
    """

    method: str
    chain: DHChain

    def refusal(self) -> str | None:
        """Whether the method applies to ``chain``.

        Returns
        -------
        str or None
            None if it applies, else why not (one sentence in the arm's terms).
        """
        ...

    def position(self, T06: np.ndarray) -> list[PositionBranch]:
        """The position sub-problem: every branch of the joints a point of the arm fixes.

        Parameters
        ----------
        T06 : numpy.ndarray, shape (4, 4)
            Target of the canonical chain ``Z₁X₁ ⋯ Z₆`` (the tip pose with base′ and tool′ removed),
            in frame 0′, m.

        Returns
        -------
        list of PositionBranch
            One per branch (e.g. Pieper's four: left/right × elbow up/down); [] if out of reach.

        Examples
        --------
        >>> import robokit
        >>> from robokit.ik.closed_form import AnalyticIK
        >>> solver = AnalyticIK(robokit.load("puma560")).solver
        >>> T06 = solver.chain.fk6(np.array([0.1, 0.2, 0.3, 0.4, 0.5, 0.6]))
        >>> [b.label for b in solver.position(T06)]
        ['left, elbow up, ', 'right, elbow up, ', 'left, elbow down, ', 'right, elbow down, ']
        """
        ...

    def wrist(self, T06: np.ndarray, branch: PositionBranch, wrist_ref: float) -> list[Row]:
        """The wrist sub-problem: every full solution completing one position branch.

        Parameters
        ----------
        T06 : numpy.ndarray, shape (4, 4)
            The target of :meth:`position`.
        branch : PositionBranch
            One of its branches.
        wrist_ref : float
            The free joint's value at a wrist singularity, rad.

        Returns
        -------
        list of Row
            Rows ``(q (6,), label, degenerate)``: joint variables in rad or m (DH offsets removed,
            any angle range), the full label, whether a singular choice was made.
        """
        ...

    def joint_angles(self, T06: np.ndarray, wrist_ref: float) -> list[Row]:
        """Every row of every branch (:meth:`wrist` over :meth:`position`): the call
        :class:`robokit.ik.AnalyticIK` makes.

        Parameters
        ----------
        T06 : numpy.ndarray, shape (4, 4)
            Target of the canonical chain, frame 0′, m.
        wrist_ref : float
            The free joint's value at a wrist singularity, rad.

        Returns
        -------
        list of Row
            Rows ``(q (6,), label, degenerate)`` (joint variables, any angle range); [] if out of reach.

        Examples
        --------
        >>> from robokit import load
        >>> from robokit.ik.closed_form import analytic_ik
        >>> solver = analytic_ik(load("ur5")).solver
        >>> T06 = solver.chain.fk6(np.array([0.1, 0.2, 0.3, 0.4, 0.5, 0.6]))
        >>> rows = solver.joint_angles(T06, 0.0)
        >>> len(rows), all(np.allclose(solver.chain.fk6(np.asarray(q)), T06) for q, _, _ in rows)
        (8, True)
        """
        ...
