"""Flipped joints (``flip: true``) in the DH Jacobian, static forces and Craig's Newton–Euler
agree with Pinocchio on the URDF generated from the same table (where the joint axis is −z)."""
import numpy as np

import robokit as rk
from robokit.description.dh import DHLink, DHTable
from robokit.dynamics import dh_inverse_dynamics
from robokit.kinematics import dh_jacobian, dh_static_torques


def _table(convention):
    rng = np.random.default_rng(3)
    links = []
    for i, flip in enumerate([False, True, False, True]):
        links.append(DHLink("R" if i != 2 else "P", a=0.3 * rng.random(), alpha=rng.uniform(-1.5, 1.5),
                            d=0.2 * rng.random(), theta=rng.uniform(-1, 1), mass=1.0 + rng.random(),
                            com=rng.normal(scale=0.05, size=3), inertia=np.array([0.02, 0.03, 0.04, 0.001, 0.0, 0.002]),
                            flip=flip))
    return DHTable("flipped", convention, tuple(links), np.array([0, 0, -9.81]), np.eye(4), np.eye(4))


def test_flipped_joints_match_pinocchio():
    for convention in ("standard", "modified"):
        table = _table(convention)
        robot = rk.load(table)
        rng = np.random.default_rng(0)
        for _ in range(20):
            q, dq, ddq = rng.uniform(-1, 1, 4), rng.normal(size=4), rng.normal(size=4)
            assert np.abs(table.fk(q) - robot.frame_pose(q)).max() < 1e-12
            J = dh_jacobian(table, q)
            assert np.abs(J - robot.jacobian(q, reference="local_world_aligned")).max() < 1e-9
            Jt = robot.jacobian(q, reference="local")
            F = rng.normal(size=6)
            assert np.abs(dh_static_torques(table, q, F, reference="local") - Jt.T @ F).max() < 1e-9
            assert np.abs(dh_inverse_dynamics(table, q, dq, ddq, trace=False) - robot.rnea(q, dq, ddq)).max() < 1e-9
