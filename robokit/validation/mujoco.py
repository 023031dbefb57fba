"""Validation rows: MuJoCo as a second reference (rows appear only when ``mujoco`` is importable).

Every shipped model and example-robot-data arm is written as MJCF and compiled by MuJoCo;
its body/site poses, mass matrix (with armature), bias forces and inverse dynamics (with
armature and damping) are compared with Pinocchio and with the course code on random
states. See :mod:`robokit.validation.mujoco_check`.
"""
from __future__ import annotations

import numpy as np

from robokit.validation.core import ARMS, CheckRow, robot as load

SAMPLES = 20
TOL = 1e-9


def checks(rng: np.random.Generator) -> list[CheckRow]:
    from robokit.description.models import shipped_models
    from robokit.validation.mujoco_check import compare_with_mujoco, import_mujoco

    if import_mujoco() is None:  # optional dependency: no rows without it
        return []
    rows = []
    for name in list(shipped_models()) + list(ARMS):
        c = compare_with_mujoco(load(name), samples=SAMPLES, rng=rng)
        extra = f"; exact inertial put into MjModel for {', '.join(c.restored)}" if c.restored else ""
        rows += [
            CheckRow("MuJoCo body/site poses vs Pinocchio FK", name, SAMPLES, c.fk, TOL, "abs, max entry",
                     f"{c.frames} frames"),
            CheckRow("MuJoCo mj_fullM vs crba / course mass_matrix (+armature)", name, SAMPLES,
                     max(c.M_pinocchio, c.M_course), TOL, "abs, max entry",
                     f"pinocchio {c.M_pinocchio:.1e}, course {c.M_course:.1e}{extra}"),
            CheckRow("MuJoCo qfrc_bias vs nonLinearEffects / course c+g", name, SAMPLES,
                     max(c.bias_pinocchio, c.bias_course), TOL, "abs, max entry",
                     f"pinocchio {c.bias_pinocchio:.1e}, course {c.bias_course:.1e}"),
            CheckRow("MuJoCo mj_inverse vs rnea / course inverse_dynamics (+armature, damping)", name, SAMPLES,
                     max(c.inverse_pinocchio, c.inverse_course), TOL, "abs, max entry",
                     f"pinocchio {c.inverse_pinocchio:.1e}, course {c.inverse_course:.1e}"),
        ]
    return rows
