"""Validation rows for inverse kinematics: the closed forms reproduce Pinocchio's forward
kinematics, and the configuration that made a pose is always among the solutions found."""
from __future__ import annotations

import warnings

import numpy as np
from numpy.typing import ArrayLike

from robokit.errors import RobokitWarning
from robokit.ik import ik_analytic, ik_analytic_kind
from robokit.validation.core import CheckRow, models, robot as load

SAMPLES = 100


def _wrapped_distance(a: ArrayLike, b: ArrayLike, revolute: np.ndarray) -> float:
    d = np.asarray(a, float) - np.asarray(b, float)
    d[revolute] = np.mod(d[revolute] + np.pi, 2 * np.pi) - np.pi
    return float(np.abs(d).max())


def checks(rng: np.random.Generator) -> list[CheckRow]:
    rows = []
    for name in models():
        robot = load(name)
        if not ik_analytic_kind(robot).method:
            continue
        revolute = np.linalg.norm(robot.poe.Slist[:3], axis=0) > 1e-12
        worst_pose, worst_missing, count, noted = 0.0, 0.0, 0, 0
        for _ in range(SAMPLES):
            q = robot.random_configuration(rng)
            T = robot.frame_pose(q)
            with warnings.catch_warnings(record=True) as said:  # counted in the row, not one line per pose
                warnings.simplefilter("always", RobokitWarning)
                sols = ik_analytic(robot, T)
            noted += any(issubclass(w.category, RobokitWarning) for w in said)
            for w in said:
                if not issubclass(w.category, RobokitWarning):
                    warnings.warn_explicit(w.message, w.category, w.filename, w.lineno)
            count += len(sols)
            for s in sols:
                worst_pose = max(worst_pose, float(np.abs(robot.frame_pose(s.q) - T).max()))
            nearest = min((_wrapped_distance(s.q, q, revolute) for s in sols), default=np.inf)
            worst_missing = max(worst_missing, nearest)
        kind = ik_analytic_kind(robot).method
        rows.append(CheckRow(f"ik_analytic ({kind}): every solution vs Pinocchio FK", name, count, worst_pose, 1e-9,
                             "abs, max entry",
                             f"ik_analytic noted {noted} of {SAMPLES} poses (near a singularity)" if noted else ""))
        rows.append(CheckRow("ik_analytic: the generating q is among the solutions", name, SAMPLES, worst_missing,
                             1e-6, "abs, max joint (wrapped)"))
    return rows
