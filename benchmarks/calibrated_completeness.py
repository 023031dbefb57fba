"""How complete the calibrated arms' closed-form IK is (issue 43): on random poses, the roots a numerical
sweep finds that ``ik_analytic`` does not return.

Arms: those of :mod:`benchmarks.calibrated_ik` (the PUMA 560, the UR5 and a random Pieper arm, every
joint placement, the base and the tool off by up to 2 mrad / 2 mm). Per arm, random configurations;
per pose, the sweep is robokit's compiled Levenberg–Marquardt (``solve_poe_ik`` on the arm's product of
exponentials, joint limits ignored) from ``--seeds`` uniform starts in [−π, π]⁶, a root kept when its
pose is within 1e-9 of the target and it is 1e-6 rad from every root kept before. A root is missed when
it is 1e-6 rad (angles modulo 2π) from every returned solution. Also per arm: how many of the poses
with a missed root the solve flagged as one where a root may be missing (the near-singular search ran,
or a branch vanished: ``ik_analytic`` then warns, once per arm for a vanished branch) and how many of the
missed roots the general 6R method (``nominal=False``) returns. The poses come from random configurations,
so each is reachable: a pose where nothing is returned is one the method wrongly calls out of reach.

Prints Markdown; asserts nothing (tests/calibration/test_calibrated_ik.py pins what is known).

``--errors 1e-2 --draws 3``: arms farther from their structure (errors up to 10 mrad / 10 mm, three
random draws of each arm: ``default_rng(0)``, ``(1)``, ``(2)``); flagged then means below the arm's own
threshold (``CalibratedArm.sigma_explore``, :func:`robokit.ik.calibrated.search_constants`).

Run: ``.venv/bin/python -m benchmarks.calibrated_completeness [--poses 300] [--seeds 500] [--errors 2e-3] [--draws 1]``.
"""
from __future__ import annotations

import argparse
import time
import warnings

import numpy as np

from benchmarks._harness import machine, table


def _angle_dist(a: np.ndarray, b: np.ndarray) -> float:
    d = np.asarray(a, float) - np.asarray(b, float)
    return float(np.abs(np.angle(np.exp(1j * d))).max())


def _sweep(robot, T: np.ndarray, seeds: int, rng: np.random.Generator) -> list[np.ndarray]:
    from robokit.errors import DegreesWarning
    from robokit.kernels.ik import solve_poe_ik

    wide = np.tile([-4 * np.pi, 4 * np.pi], (robot.n, 1))
    found: list[np.ndarray] = []
    for k in range(seeds):
        q, ok, _, _ = solve_poe_ik(robot.poe.M, robot.poe.Slist, T, rng.uniform(-np.pi, np.pi, robot.n), wide,
                                   tol=1e-11, max_iterations=60, max_restarts=0, seed=k)
        with warnings.catch_warnings():  # the sweep's joints roam ±4π on purpose (DegreesWarning beyond a turn)
            warnings.simplefilter("ignore", DegreesWarning)
            reached = ok and np.abs(robot.frame_pose(q) - T).max() < 1e-9
        if reached and not any(_angle_dist(q, f) < 1e-6 for f in found):
            found.append(q)
    return found


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--poses", type=int, default=300, help="random configurations per arm")
    ap.add_argument("--seeds", type=int, default=500, help="sweep starts per pose")
    ap.add_argument("--errors", type=float, default=2e-3, help="the arms' errors: up to this (rad, m) per joint placement")
    ap.add_argument("--draws", type=int, default=1, help="random draws of the arms (seeds 0, 1, ...)")
    args = ap.parse_args()

    import robokit
    from robokit.errors import RobokitWarning
    from robokit.ik.closed_form import analytic_ik
    from benchmarks.calibrated_ik import _arms

    print(machine())
    rows = []
    arms = [(f"{label} (draw {d})" if args.draws > 1 else label, cal)
            for d in range(args.draws) for label, _nominal, cal in _arms(args.errors, d)]
    print(f"\nErrors up to {args.errors:g} rad / {args.errors:g} m per joint placement.")
    for label, cal in arms:
        rng = np.random.default_rng(21)
        t0 = time.perf_counter()
        returned = found_total = missed = poses_missed = searched = general_has = empty = 0
        for _ in range(args.poses):
            T = cal.frame_pose(cal.random_configuration(rng))
            with warnings.catch_warnings():
                warnings.simplefilter("ignore", RobokitWarning)
                sols = robokit.ik_analytic(cal, T)
            status = analytic_ik(cal).calibrated._status  # this solve's (the warnings are said once per arm)
            flagged = status[2] <= analytic_ik(cal).calibrated.sigma_explore or status[1] > 0  # ik_analytic warned (or said it once)
            found = _sweep(cal, T, args.seeds, rng)
            returned += len(sols)
            found_total += len(found)
            lost = [f for f in found if not sols or min(_angle_dist(f, s.q) for s in sols) >= 1e-6]
            if lost:
                missed += len(lost)
                poses_missed += 1
                empty += not sols
                searched += bool(flagged)
                general = robokit.ik_analytic(cal, T, nominal=False)
                general_has += sum(1 for f in lost if general and min(_angle_dist(f, s.q) for s in general) < 1e-6)
        rows.append([label, str(args.poses), str(returned), str(found_total), str(missed),
                     f"{poses_missed} ({100.0 * poses_missed / args.poses:.1f} %)", str(empty), str(searched), str(general_has),
                     f"{time.perf_counter() - t0:.0f} s"])
    print(f"\nRandom poses, a {args.seeds}-start sweep each:\n")
    print(table(["arm", "poses", "solutions returned", "roots the sweep found", "roots missed",
                 "poses with a root missed", "of those, none returned", "of those, flagged (a warning)",
                 "missed roots nominal=False returns",
                 "time"], rows))


if __name__ == "__main__":
    main()
