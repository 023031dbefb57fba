"""Validation rows for ``robokit validate``: trajectories against Pinocchio and closed forms."""
from __future__ import annotations

import numpy as np

from robokit.validation.core import CheckRow
from robokit.spatial import lie


def _random_pose(rng: np.random.Generator, angle_max: float = 3.0) -> np.ndarray:
    
    w = rng.normal(size=3)
    w *= rng.uniform(0.05, angle_max) / np.linalg.norm(w)
    return lie.exp6(np.concatenate([w, rng.normal(size=3)]))


def checks(rng: np.random.Generator) -> list[CheckRow]:
    import pinocchio as pin

    from robokit.trajectory import (
        cartesian_line_trajectory,
        cartesian_trajectory,
        cubic_via_trajectory,
        ms_trajectory,
        quintic_coefficients,
        quintic_time_scaling,
        screw_trajectory,
    )

    rows = []
    pairs = [(_random_pose(rng), _random_pose(rng)) for _ in range(20)]
    N = 9
    s_grid = np.array([quintic_time_scaling(1.0, k / (N - 1)) for k in range(N)])

    # screw_trajectory vs Pinocchio's exp6/log6 (Pinocchio orders twists linear first; its own convention end to end)
    err = 0.0
    for X0, X1 in pairs:
        V = pin.log6(pin.SE3(X0).inverse() * pin.SE3(X1))
        for X, s in zip(screw_trajectory(X0, X1, 1.0, N, 5), s_grid):
            err = max(err, float(np.abs(X - (pin.SE3(X0) * pin.exp6(V * s)).homogeneous).max()))
    rows.append(CheckRow("screw_trajectory vs pinocchio X0·exp6(s·log6(X0⁻¹X1))", "-", len(pairs) * N, err, 1e-9, "abs, max entry"))

    # cartesian_trajectory and cartesian_line_trajectory orientation vs Pinocchio quaternion slerp, position vs lerp
    err_c = 0.0
    err_l = 0.0
    for X0, X1 in pairs:
        q0, q1 = pin.Quaternion(X0[:3, :3]), pin.Quaternion(X1[:3, :3])
        line = cartesian_line_trajectory(X0, X1, 1.0, t=N, method="quintic")
        assert line.poses is not None  # a Cartesian trajectory has its poses
        for k, (X, s) in enumerate(zip(cartesian_trajectory(X0, X1, 1.0, N, 5), s_grid)):
            R_ref = q0.slerp(s, q1).matrix()
            p_ref = (1 - s) * X0[:3, 3] + s * X1[:3, 3]
            err_c = max(err_c, float(np.abs(X[:3, :3] - R_ref).max()), float(np.abs(X[:3, 3] - p_ref).max()))
            Y = line.poses[k]
            err_l = max(err_l, float(np.abs(Y[:3, :3] - R_ref).max()), float(np.abs(Y[:3, 3] - p_ref).max()))
    rows.append(CheckRow("cartesian_trajectory vs pinocchio Quaternion.slerp + lerp", "-", len(pairs) * N, err_c, 1e-9, "abs, max entry"))
    rows.append(CheckRow("cartesian_line_trajectory vs pinocchio Quaternion.slerp + lerp", "-", len(pairs) * N, err_l, 1e-9, "abs, max entry"))

    # quintic coefficients vs solving the lecture's 6×6 boundary-condition system
    err = 0.0
    for _ in range(50):
        b = rng.normal(size=6)
        T = float(rng.uniform(0.3, 3.0))
        M = np.array(
            [
                [0, 0, 0, 0, 0, 1],
                [T**5, T**4, T**3, T**2, T, 1],
                [0, 0, 0, 0, 1, 0],
                [5 * T**4, 4 * T**3, 3 * T**2, 2 * T, 1, 0],
                [0, 0, 0, 2, 0, 0],
                [20 * T**3, 12 * T**2, 6 * T, 2, 0, 0],
            ]
        )
        ref = np.linalg.solve(M, b)[::-1]
        got = quintic_coefficients(b[0], b[1], T, b[2], b[3], b[4], b[5])[:, 0]
        err = max(err, float(np.abs(got - ref).max() / (1 + np.abs(ref).max())))
    rows.append(CheckRow("quintic_coefficients vs lecture 6×6 system (numpy solve)", "-", 50, err, 1e-9, "rel, max entry"))

    # via cubics, continuous-acceleration rule: position/velocity/acceleration jumps at the via points
    err = 0.0
    cases = 30
    for _ in range(cases):
        m = int(rng.integers(3, 7))
        P = rng.normal(size=(m, 2))
        times = np.concatenate([[0.0], np.cumsum(rng.uniform(0.3, 2.0, size=m - 1))])
        C = cubic_via_trajectory(P, times, t=2, velocities="continuous").info["coefficients"]
        h = np.diff(times)
        for k in range(m - 2):
            x = h[k]
            left = [C[k, 0] + C[k, 1] * x + C[k, 2] * x**2 + C[k, 3] * x**3, C[k, 1] + 2 * C[k, 2] * x + 3 * C[k, 3] * x**2, 2 * C[k, 2] + 6 * C[k, 3] * x]
            right = [C[k + 1, 0], C[k + 1, 1], 2 * C[k + 1, 2]]
            scale = 1 + max(np.abs(r).max() for r in right)
            err = max(err, max(float(np.abs(a - b).max()) for a, b in zip(left, right)) / scale)
    rows.append(CheckRow("cubic_via (continuous) C2 jumps at via points", "-", cases, err, 1e-9, "rel, max |left − right|"))

    # ms_trajectory vs the hand-derived example (also in the Robotics Toolbox's mstraj tests)
    via = np.array([[4.0, 1.0], [4.0, 4.0], [5.0, 2.0], [2.0, 5.0]])
    q = ms_trajectory(via, dt=1, tacc=1, qdmax=[2, 1], q0=[4, 1]).q
    ref = np.array(
        [[4, 1], [4, 1.75], [4, 2.5], [4, 3.25], [4 + 1 / 3, 4 - 2 / 3], [4 + 2 / 3, 4 - 4 / 3], [4.25, 2.75], [3.5, 3.5], [2.75, 4.25], [2, 5]]
    )
    err = float(np.abs(q - ref).max()) if q.shape == ref.shape else float("inf")
    rows.append(CheckRow("ms_trajectory vs hand-derived mstraj example", "-", 1, err, 1e-12, "abs, max entry", note="10 samples, 2 axes"))
    return rows
