"""Closed-form IK benchmark: every solution of one pose, per robot, beside roboticstoolbox.

For each robot, ``--poses`` targets (FK of random configurations, seed 0); for each target
the median time of one call returning *all* closed-form solutions (``_harness.time_call``),
then the median over the targets. Robots: PUMA 560 (the shipped DH model), UR5 and UR10
(example-robot-data URDFs), and a random spherical-wrist arm with general twists (Pieper's
quartic case). Peers measured in the same run: roboticstoolbox-python's ``ikine_a`` on its
``rtb.models.DH.Puma560`` (one call returns one configuration; all 8 take eight calls with
the configuration strings "lun" … "rdf"), robokit's ``ik_puma560`` on the DH table, and
robokit's numerical ``solve_ik`` (one solution, from a random seed) for scale. Also printed:
the solution counts and the largest FK error of any returned solution (Pinocchio FK).
Prints Markdown tables; asserts nothing.

Run: ``.venv/bin/python -m benchmarks.ik_analytic [--quick]``
"""
from __future__ import annotations

import argparse
import statistics

import numpy as np

from benchmarks._harness import fmt_time, machine, table, time_call


def _spherical_arm():
    from robokit.description.dh import DHLink, DHTable

    rng = np.random.default_rng(4)
    rows = []
    for i in range(6):
        rows.append(DHLink("R", rng.uniform(-0.5, 0.5) if i < 3 else 0.0, rng.uniform(0.4, 2.7),
                           rng.uniform(-0.5, 0.5) if i != 4 else 0.0, rng.uniform(-3, 3)))
    return DHTable("random_spherical", "standard", tuple(rows))


def main(argv=None):
    import robokit
    from robokit.ik import ik_analytic, ik_puma560, solve_ik

    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="5 poses per robot instead of 25")
    ap.add_argument("--poses", type=int, default=None)
    args, _ = ap.parse_known_args(argv)
    n_poses = args.poses or (5 if args.quick else 25)
    rng = np.random.default_rng(0)
    robots = [("PUMA 560", robokit.load("puma560")), ("UR5", robokit.load("ur5")), ("UR10", robokit.load("ur10")),
              ("random spherical wrist (quartic)", robokit.load(_spherical_arm()))]
    import os

    load = ", ".join(f"{x:.2f}" for x in os.getloadavg())
    print(f"## Closed-form IK, all solutions of one pose ({machine()}; load average {load})\n")
    rows, medians = [], {}
    for name, robot in robots:
        kind = robokit.ik_analytic_kind(robot)
        times, counts, worst = [], [], 0.0
        for _ in range(n_poses):
            q = robot.random_configuration(rng)
            T = robot.frame_pose(q)
            sols = ik_analytic(robot, T)
            counts.append(len(sols))
            for s in sols:
                worst = max(worst, float(np.abs(robot.frame_pose(s.q) - T).max()))
            times.append(time_call(ik_analytic, robot, T, repeats=5, target=0.02))
        medians[name] = statistics.median(times)
        hist = ", ".join(f"{c}×{counts.count(c)}" for c in sorted(set(counts), reverse=True))
        rows.append([name, kind.method, fmt_time(medians[name]), hist, f"{worst:.1e}"])
    print(table(["robot", "method", "median per call (all solutions)", "solutions (count×poses)",
                 "max FK error (m)"], rows))

    # peers on the PUMA 560
    puma = robots[0][1]
    peer_rows = [["robokit ik_analytic", "all (8)", fmt_time(medians["PUMA 560"]), "1.0"]]
    Ts = [puma.frame_pose(puma.random_configuration(rng)) for _ in range(n_poses)]
    t = statistics.median(time_call(ik_puma560, puma.dh, T, repeats=5, target=0.02) for T in Ts)
    peer_rows.append(["robokit ik_puma560 (DH table)", "all (8)", fmt_time(t), f"{t / medians['PUMA 560']:.2f}"])
    try:
        import roboticstoolbox as rtb
        from spatialmath import SE3

        p560 = rtb.models.DH.Puma560()
        configs = [a + b + c for a in "lr" for b in "ud" for c in "nf"]
        Ts_rtb = [SE3(p560.fkine(puma.random_configuration(rng)).A) for _ in range(n_poses)]
        t1 = statistics.median(time_call(p560.ikine_a, T, "lun", repeats=5, target=0.02) for T in Ts_rtb)

        def all8(T):
            return [p560.ikine_a(T, c) for c in configs]

        t8 = statistics.median(time_call(all8, T, repeats=3, target=0.02) for T in Ts_rtb)
        peer_rows.append(["roboticstoolbox ikine_a (DH.Puma560)", "one", fmt_time(t1), f"{t1 / medians['PUMA 560']:.2f}"])
        peer_rows.append(["roboticstoolbox ikine_a × 8 configs", "all (8)", fmt_time(t8),
                          f"{t8 / medians['PUMA 560']:.2f}"])
    except ImportError:  # pragma: no cover - the bench extra is not installed
        peer_rows.append(["roboticstoolbox", "not installed", "n/a", "n/a"])
    q0s = [puma.random_configuration(rng) for _ in range(n_poses)]
    tn = statistics.median(time_call(solve_ik, puma, T, q0=q0, repeats=3, target=0.02) for T, q0 in zip(Ts, q0s))
    peer_rows.append(["robokit solve_ik (numerical, random seed)", "one", fmt_time(tn), f"{tn / medians['PUMA 560']:.2f}"])
    print()
    print("### PUMA 560: closed form beside peers (ratio = time / robokit ik_analytic)\n")
    print(table(["solver", "solutions per call", "median per call", "ratio"], peer_rows))


if __name__ == "__main__":
    main()
