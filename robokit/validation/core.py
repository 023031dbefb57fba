"""The pieces every validation area uses: a row of the table, the robots, the error measure."""
from __future__ import annotations

import functools
import math
from dataclasses import asdict, dataclass, field
from typing import TYPE_CHECKING, Iterable

import numpy as np
from numpy.typing import ArrayLike

if TYPE_CHECKING:
    from robokit.description.robot import Robot

__all__ = ["CheckRow", "robot", "max_error", "SHIPPED", "ARMS", "MODELS"]

#: The shipped DH models (models/*.yaml) compared in every robot row.
SHIPPED = ("twolink", "rrr", "puma560")
#: The example-robot-data arms compared in every robot row.
ARMS = ("ur5", "panda", "z1", "xarm7", "kinova")
#: Both, in table order.
MODELS = SHIPPED + ARMS


@dataclass
class CheckRow:
    """One row of the validation table.

    quantity  : what is compared, e.g. ``"matrix_exp_6 vs pinocchio.exp6"``.
    model     : robot model name, or ``"-"`` for robot-free checks.
    cases     : number of samples compared.
    max_error : the largest error over the samples (norm or relative error as ``metric`` says).
    tolerance : the row passes when ``max_error <= tolerance``.
    metric    : how the error is measured (e.g. ``"abs, Frobenius"``, ``"rel, inf-norm"``).
    note      : free text (e.g. the Pinocchio reference frame used).
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
        return not self.error and math.isfinite(self.max_error) and self.max_error <= self.tolerance and self.cases > 0

    def as_dict(self) -> dict:
        d = asdict(self)
        d["passed"] = self.passed
        return d


@functools.lru_cache(maxsize=None)
def robot(name: str) -> Robot:
    """``robokit.load(name)``, loaded once per validation run and shared by the check modules."""
    from robokit.description.loading import load

    return load(name)


def max_error(pairs: Iterable[tuple[ArrayLike, ArrayLike]]) -> float:
    """Largest ``‖a − b‖`` (Frobenius / 2-norm) over an iterable of ``(a, b)`` array pairs."""
    worst = 0.0
    for a, b in pairs:
        e = float(np.linalg.norm(np.asarray(a, dtype=float) - np.asarray(b, dtype=float)))
        if not math.isfinite(e):
            return math.inf
        worst = max(worst, e)
    return worst


