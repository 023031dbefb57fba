"""Validation rows for URDF → DH: the extracted tables' FK against Pinocchio, both conventions."""
from __future__ import annotations

import numpy as np

from robokit.validation.core import ARMS, CheckRow, robot as load

SAMPLES = 100


def checks(rng: np.random.Generator) -> list[CheckRow]:
    from robokit.description.urdf_to_dh import dh_from_urdf

    rows = []
    for name in ARMS:
        r = load(name)
        for convention in ("standard", "modified"):
            table = dh_from_urdf(r, convention, samples=1).table
            worst = 0.0
            for _ in range(SAMPLES):
                q = r.random_configuration(rng)
                worst = max(worst, float(np.abs(table.fk(q) - r.frame_pose(q)).max()))
            rows.append(CheckRow(f"URDF → DH ({convention}) FK vs Pinocchio FK of {r.tip}", name, SAMPLES, worst, 1e-9,
                                 "abs, max entry"))
    return rows
