"""Validation rows for robot descriptions: DH forward kinematics and PoE forward kinematics vs Pinocchio."""
from __future__ import annotations

import numpy as np

from robokit.validate import CheckRow, robot as load

#: example-robot-data arms compared in `robokit validate`
ARMS = ("ur5", "panda", "z1", "xarm7", "kinova")
SAMPLES = 200


def _poe_fk(poe, theta):
    from robokit.spatial.se3 import _exp6

    T = np.eye(4)
    for i, th in enumerate(theta):
        T = T @ _exp6(poe.Slist[:, i] * th)
    return T @ poe.M


def checks(rng) -> list[CheckRow]:
    import pinocchio as pin

    from robokit.description.models import shipped_models

    rows = []
    for name in shipped_models():
        robot = load(name)
        table = robot.dh
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
            worst = max(worst, np.abs(_poe_fk(robot.poe, q) - robot.frame_pose(q)).max())
        rows.append(CheckRow(f"PoE FK (URDF → M, Slist) vs Pinocchio FK of {robot.tip}", name, SAMPLES, worst, 1e-9,
                             "abs, max entry"))
    return rows
