"""IK benchmark (issue 6): success rate and solve time on ur5, panda (arm) and puma560.

For each robot, 1,000 reachable targets (FK of random configurations inside the limits;
fewer with ``--quick``), solved from two kinds of seed: "near" (the generating
configuration plus uniform noise of ±0.3 rad, clipped to the limits) and "random"
(uniform inside the limits). Solvers: robokit's ``solve_ik`` (LM + limits + restarts,
Pinocchio FK/Jacobians), the seed ``ikin_space`` (Newton–Raphson on the course PoE
parameters, no limits, no restarts), ``modern_robotics.IKinSpace`` where installed, and
the analytic PUMA 560 solver. Tolerances: 1e-9 on the rotation (rad) and position (m)
error for every solver. Prints Markdown tables; asserts nothing.

Run: ``.venv/bin/python -m benchmarks.ik [--quick]``
"""
from __future__ import annotations

import argparse
import time

import numpy as np

from benchmarks._harness import fmt_time, machine, table


def _pose_error(T, T_target):
    from robokit.spatial.lie import inv, log6

    e = log6(inv(T) @ T_target)
    return float(np.linalg.norm(e[:3])), float(np.linalg.norm(T[:3, 3] - T_target[:3, 3]))


def _targets(robot, count, rng):
    lo, hi = robot.qlim[:, 0], robot.qlim[:, 1]
    lo = np.where(np.isfinite(lo), lo, -np.pi)
    hi = np.where(np.isfinite(hi), hi, np.pi)
    Q = rng.uniform(lo, hi, size=(count, robot.n))
    return Q, [robot.frame_pose(q) for q in Q], lo, hi


def _run(solver, Q, Ts, seeds, robot, tol=1e-9):
    times, ok = [], 0
    for q0, T in zip(seeds, Ts):
        t0 = time.perf_counter()
        q = solver(T, q0)
        times.append(time.perf_counter() - t0)
        if q is None:
            continue
        inside = np.all(q >= robot.qlim[:, 0] - 1e-9) and np.all(q <= robot.qlim[:, 1] + 1e-9)
        rot, pos = _pose_error(robot.frame_pose(q), T)
        ok += bool(rot < tol and pos < tol and inside)
    times = np.array(times)
    return ok / len(Ts), float(np.median(times)), float(np.percentile(times, 95))


def main(argv=None):
    import robokit
    from robokit.ik import ik_puma560, ikin_space, solve_ik

    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="100 targets per robot instead of 1000")
    args = ap.parse_args(argv)
    count = 100 if args.quick else 1000
    try:
        import modern_robotics as mr
    except ImportError:  # pragma: no cover
        mr = None
    print(f"# IK benchmark\n\nmachine: {machine()}\ntargets per robot: {count}; success = rotation and position "
          f"error < 1e-9 and inside the joint limits\n")
    rows = []
    for name in ("ur5", "panda", "puma560"):
        robot = robokit.load(name)
        rng = np.random.default_rng(0)
        Q, Ts, lo, hi = _targets(robot, count, rng)
        seed_sets = {
            "near (±0.3 rad)": [np.clip(q + rng.uniform(-0.3, 0.3, robot.n), lo, hi) for q in Q],
            "random": [rng.uniform(lo, hi) for _ in Q],
        }
        poe = robot.poe
        solvers = {
            "robokit solve_ik": lambda T, q0: solve_ik(robot, T, q0=q0, rng=1).q,
            "robokit ikin_space": lambda T, q0: (lambda r: r[0] if r[1] else None)(
                ikin_space(poe.Slist, poe.M, T, q0, 1e-9, 1e-9)),
        }
        if mr is not None:
            solvers["modern_robotics IKinSpace"] = lambda T, q0: (lambda r: r[0] if r[1] else None)(
                mr.IKinSpace(poe.Slist, poe.M, T, q0, 1e-9, 1e-9))
        for seed_name, seeds in seed_sets.items():
            for sname, solver in solvers.items():
                if sname.startswith("modern") and seed_name == "random" and count > 100:
                    sub = slice(0, 200)  # MR is slow; 200 targets are enough for its rate
                else:
                    sub = slice(None)
                rate, med, p95 = _run(solver, Q[sub], Ts[sub], seeds[sub], robot)
                rows.append([name, seed_name, sname, f"{100 * rate:.1f} %", fmt_time(med), fmt_time(p95)])
        if name == "puma560":
            def analytic(T, q0):
                sols = ik_puma560(robot.dh, T)
                inside = [s for s in sols if s.within_limits]
                if not inside:
                    return None
                return min(inside, key=lambda s: np.abs(s.q - q0).sum()).q
            rate, med, p95 = _run(analytic, Q, Ts, seed_sets["random"], robot)
            rows.append([name, "(any)", "robokit ik_puma560 (all 8)", f"{100 * rate:.1f} %", fmt_time(med),
                         fmt_time(p95)])
    print(table(["robot", "seed", "solver", "success", "median", "95th pct"], rows))


if __name__ == "__main__":
    main()
