"""The numerical reference of the closed-form IK tests: the distinct exact solutions robokit's compiled
Levenberg–Marquardt finds from many uniform starts (imported as ``ik_sweep``; tests/conftest.py puts
tests/support on sys.path)."""
import numpy as np


def angle_dist(a, b):
    """The largest joint difference, angles modulo 2π (rad)."""
    d = np.asarray(a, float) - np.asarray(b, float)
    return float(np.abs(np.angle(np.exp(1j * d))).max())


def sweep(robot, T, seeds=500, rng=0):
    """Distinct solutions of ``solve_poe_ik`` on the robot's PoE (joint limits ignored, ±4π, so that every
    solution can be reached) from ``seeds`` uniform starts in [−π, π]⁶ (``default_rng(rng)``): each
    reaches T to 1e-9 through ``robot.frame_pose``, revolute joints wrapped into (−π, π]."""
    from robokit.kernels.ik import solve_poe_ik

    rng = np.random.default_rng(rng)
    revolute = np.abs(robot.poe.Slist[:3]).sum(axis=0) > 0.5
    wide = np.tile([-4 * np.pi, 4 * np.pi], (robot.n, 1))
    found = []
    for k in range(seeds):
        q, ok, _, _ = solve_poe_ik(robot.poe.M, robot.poe.Slist, T, rng.uniform(-np.pi, np.pi, robot.n), wide,
                                   tol=1e-11, max_iterations=60, max_restarts=0, seed=k)
        q = np.where(revolute, np.angle(np.exp(1j * q)), q)
        if ok and np.abs(robot.frame_pose(q) - T).max() < 1e-9 and not any(angle_dist(q, f) < 1e-6 for f in found):
            found.append(q)
    return found
