"""The pieces every validation area uses: a row of the table, the robots, the error measure."""
from __future__ import annotations

import functools
import math
from contextlib import contextmanager
from contextvars import ContextVar
from dataclasses import asdict, dataclass, field
from typing import TYPE_CHECKING, Iterable, Iterator

import numpy as np
from numpy.typing import ArrayLike

if TYPE_CHECKING:
    from robokit.description.robot import Robot

__all__ = ["CheckRow", "robot", "max_error", "SHIPPED", "ARMS", "MODELS", "models", "only_robot"]

#: The shipped DH models (models/*.yaml) compared in every robot row.
SHIPPED = ("twolink", "rrr", "puma560")
#: The example-robot-data arms compared in every robot row.
ARMS = ("ur5", "panda", "z1", "xarm7", "kinova")
#: Both, in table order.
MODELS = SHIPPED + ARMS


@dataclass
class CheckRow:
    """One row of the validation table.

    Attributes
    ----------
    quantity : str
        What is compared, e.g. ``"matrix_exp_6 vs pinocchio.exp6"``.
    model : str
        Robot model name, or ``"-"`` for robot-free checks.
    cases : int
        Number of samples compared.
    max_error : float
        The largest error over the samples (norm or relative error as ``metric`` says; SI units).
    tolerance : float
        The row passes when ``max_error <= tolerance``.
    metric : str
        How the error is measured (e.g. ``"abs, Frobenius"``, ``"rel, inf-norm"``).
    note : str
        Free text (e.g. the Pinocchio reference frame used).
    error : str
        The exception text when the check raised (the row then fails).
    passed : bool
        Property: no error, ``cases > 0`` and a finite ``max_error <= tolerance``.

    Examples
    --------
    >>> CheckRow("matrix_exp_6 vs pinocchio.exp6", "-", 100, 3e-16, 1e-9).passed
    True
    >>> CheckRow("fk", "ur5", 100, 2e-6, 1e-9).passed
    False
    """

    quantity: str
    model: str
    cases: int
    max_error: float
    tolerance: float
    metric: str = "abs"
    note: str = ""
    error: str = field(default="")

    @property
    def passed(self) -> bool:
        """True when there is no error, ``cases > 0`` and ``max_error`` is finite and ≤ ``tolerance``."""
        return not self.error and math.isfinite(self.max_error) and self.max_error <= self.tolerance and self.cases > 0

    def as_dict(self) -> dict:
        """The row as a JSON-ready dict (what ``robokit validate --json`` prints per row).

        Returns
        -------
        dict
            The fields and ``passed``.

        Examples
        --------
        >>> CheckRow("fk", "ur5", 10, 1e-15, 1e-9).as_dict()["passed"]
        True
        """
        d = asdict(self)
        d["passed"] = self.passed
        return d


#: (label, robot) of ``robokit validate MODEL``: the one robot the robot rows compare (None: MODELS).
_ONLY: ContextVar[tuple[str, Robot] | None] = ContextVar("robokit_validation_only", default=None)


def models() -> tuple[str, ...]:
    """The robots the robot rows (kinematics, dynamics, ik) compare: :data:`MODELS`, or within
    :func:`only_robot` that one robot's label.

    Returns
    -------
    tuple of str
        Names :func:`robot` loads.

    Examples
    --------
    >>> models() == MODELS
    True
    """
    only = _ONLY.get()
    return MODELS if only is None else (only[0],)


@contextmanager
def only_robot(label: str, loaded: Robot) -> Iterator[None]:
    """Within this block the robot rows compare ``loaded`` alone, under the name ``label``
    (``robokit validate MODEL``).

    Parameters
    ----------
    label : str
        The model column of its rows.
    loaded : Robot
        The robot.

    Yields
    ------
    None
    """
    token = _ONLY.set((label, loaded))
    try:
        yield
    finally:
        _ONLY.reset(token)


def robot(name: str) -> Robot:
    """``robokit.load(name)``, loaded once per validation run and shared by the check modules (within
    :func:`only_robot`, its robot for its label).

    Parameters
    ----------
    name : str
        A name of :func:`models`.

    Returns
    -------
    Robot
        The robot.
    """
    only = _ONLY.get()
    if only is not None and name == only[0]:
        return only[1]
    return _loaded(name)


@functools.lru_cache(maxsize=None)
def _loaded(name: str) -> Robot:
    from robokit.description.loading import load

    return load(name)


def max_error(pairs: Iterable[tuple[ArrayLike, ArrayLike]]) -> float:
    """Largest ``‖a − b‖`` (Frobenius / 2-norm) over an iterable of ``(a, b)`` array pairs.

    Parameters
    ----------
    pairs : iterable of (array_like, array_like)
        Pairs of arrays of equal shape (a computed value and its reference).

    Returns
    -------
    float
        The largest norm of the difference (0.0 for no pairs; ``inf`` as soon as one is not finite).

    Examples
    --------
    >>> max_error([([1.0, 2.0], [1.0, 2.0]), ([3.0, 0.0], [0.0, 4.0])])
    5.0
    """
    worst = 0.0
    for a, b in pairs:
        e = float(np.linalg.norm(np.asarray(a, dtype=float) - np.asarray(b, dtype=float)))
        if not math.isfinite(e):
            return math.inf
        worst = max(worst, e)
    return worst


