"""Random serial chains of any length for the growth-with-n tables (Pinocchio model + PoE parameters)."""
from __future__ import annotations

import numpy as np


def random_chain(n: int, seed: int = 0):
    """(model, data, tip frame id, PoE parameters) of an n-joint chain: revolute joints about random
    unit axes, random placements (links 0.1–0.3 m), random physical inertias, a 'tip' frame."""
    import pinocchio as pin

    from robokit.description.poe import poe_from_model

    rng = np.random.default_rng(seed)
    model = pin.Model()
    parent = 0
    for i in range(n):
        quat = rng.normal(size=4)
        quat /= np.linalg.norm(quat)
        place = pin.SE3(pin.Quaternion(*quat).toRotationMatrix(), rng.uniform(-0.2, 0.2, 3))
        axis = rng.normal(size=3)
        axis /= np.linalg.norm(axis)
        parent = model.addJoint(parent, pin.JointModelRevoluteUnaligned(axis), place, f"j{i}")
        L = rng.normal(size=(3, 3))
        model.appendBodyToJoint(parent, pin.Inertia(rng.uniform(0.2, 3.0), rng.uniform(-0.1, 0.1, 3),
                                                    L @ L.T * 0.05 + 0.01 * np.eye(3)), pin.SE3.Identity())
    fid = model.addFrame(pin.Frame("tip", parent, 0, pin.SE3(np.eye(3), np.array([0.0, 0.0, 0.1])),
                                   pin.FrameType.OP_FRAME))
    return model, model.createData(), fid, poe_from_model(model, "tip")
