"""Validation rows for robot descriptions: DH forward kinematics and PoE forward kinematics vs Pinocchio."""
from __future__ import annotations

import numpy as np

from robokit.kinematics import fkin_space

from robokit.validation.core import ARMS, CheckRow, robot as load

SAMPLES = 200


def checks(rng: np.random.Generator) -> list[CheckRow]:
    import pinocchio as pin

    from robokit.description.models import shipped_models

    rows = []
    for name in shipped_models():
        robot = load(name)
        table = robot.dh
        assert table is not None  # a shipped DH model
        ids = [robot.model.getFrameId(f"dh_{i}") for i in range(table.n + 1)] + [robot.tip_id]
        worst = 0.0
        for _ in range(SAMPLES):
            q = robot.random_configuration(rng)
            pin.framesForwardKinematics(robot.model, robot.data, q)
            F = list(table.frames(q)) + [table.fk(q)]
            worst = max(worst, max(np.abs(robot.data.oMf[f].homogeneous - T).max() for f, T in zip(ids, F)))
        rows.append(CheckRow("DH FK (dh_0..dh_N, tool) vs Pinocchio FK of generated URDF", name, SAMPLES, worst, 1e-9,
                             "abs, max entry"))
    for name in list(shipped_models()) + list(ARMS):
        robot = load(name)
        worst = 0.0
        for _ in range(SAMPLES):
            q = robot.random_configuration(rng)
            worst = max(worst, np.abs(fkin_space(robot.poe.M, robot.poe.Slist, q) - robot.frame_pose(q)).max())
        rows.append(CheckRow(f"PoE FK (URDF → M, Slist) vs Pinocchio FK of {robot.tip}", name, SAMPLES, worst, 1e-9,
                             "abs, max entry"))
    return rows
