"""What the degrees check (:mod:`robokit._units`) costs on the hot paths, beside the calls it guards.

The hot paths (``Robot.frame_pose``/``jacobian``/``rnea``/..., the seed ``fkin_space``/
``jacobian_space``) used to test a float64 (n,) ``q`` for finiteness with ``isfinite(sum(q.tolist()))``.
They now test ``hypot(*q) ≤ r`` (finite and inside every joint's range: tier 1) or, when that fails,
a finite hypot and ``lo₁ ≤ min(q)``, ``max(q) ≤ hi₁`` (tier 2). The table times both filter
expressions on their own, on a 6-vector of small angles (‖q‖ ≤ 2π: tier 1) and one of large angles
inside the UR5's ±2π limits (tier 2), and the whole call beside Pinocchio's own
``forwardKinematics`` + ``updateFramePlacement`` (the peer). The check's cost is the difference
of the filters.

``.venv/bin/python -m benchmarks.degrees [--quick]``; nothing is asserted.
"""
from __future__ import annotations

import sys
from math import hypot, isfinite

import numpy as np

from benchmarks._harness import fmt_time, machine, table, time_best


def main(argv=None) -> None:
    argv = list(sys.argv[1:] if argv is None else argv)
    batches = 30 if "--quick" in argv else 200
    import pinocchio as pin

    import robokit as rk

    rows = []
    for name, q in (("puma560", np.array([0.1, -0.5, 0.3, 0.4, 0.6, -0.2])),
                    ("ur5", np.array([0.1, -0.5, 0.3, 0.4, 0.6, -0.2])),
                    ("ur5", np.array([4.0, -3.5, 2.0, -5.0, 3.0, 5.5]))):
        robot = rk.load(name)
        r1, lo1, hi1 = robot._r1, robot._lo1, robot._hi1
        tier = 1 if hypot(*q.tolist()) <= r1 else 2
        old = time_best(lambda: isfinite(sum(q.tolist())), batches=batches)

        def new() -> bool:
            return (h := hypot(*(t := q.tolist()))) <= r1 or (isfinite(h) and lo1 <= min(t) and max(t) <= hi1)

        assert new()
        t_new = time_best(new, batches=batches)
        call = time_best(robot.frame_pose, q, batches=batches)
        model, data, fid = robot.model, robot.data, robot.tip_id

        def peer() -> np.ndarray:
            pin.forwardKinematics(model, data, q)
            return pin.updateFramePlacement(model, data, fid).homogeneous

        t_peer = time_best(peer, batches=batches)
        p = robot.poe
        fk = time_best(rk.fkin_space, p.M, p.Slist, q, batches=batches)
        rows.append([f"{name}, tier {tier}", fmt_time(old), fmt_time(t_new), fmt_time(t_new - old), fmt_time(call),
                     f"{(t_new - old) / call:.1%}", fmt_time(t_peer), f"{call / t_peer:.2f}", fmt_time(fk)])
    print(f"# The degrees check on the hot paths\n\nmachine: {machine()}\n")
    print(table(["q", "old filter", "new filter", "check costs", "frame_pose", "of the call", "pinocchio FK",
                 "frame_pose / pinocchio", "fkin_space"], rows))


if __name__ == "__main__":
    main()
