"""Speed benchmark (issue 11): the course implementations against modern_robotics and Pinocchio.

Table 1 — per call on the UR5: robokit's seed functions, the same call in modern_robotics, and
the closest Pinocchio call, with the ratios. Table 2 — batched evaluation (a leading dimension
of N configurations) per configuration, against a Python loop over Pinocchio, at N = 1, 100,
10,000, with peak memory of the batched call. Table 3 — robokit.Robot methods against the raw
Pinocchio call they wrap. Median of repeated runs after a warm-up; prints Markdown, asserts nothing.

Run: ``.venv/bin/python -m benchmarks.speed [--quick]``
"""
from __future__ import annotations

import argparse
import tracemalloc

import numpy as np

from benchmarks._harness import fmt_time, machine, table, time_call


def main(argv=None):
    import pinocchio as pin

    import robokit as rk

    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="fewer repeats, N up to 1,000")
    args = ap.parse_args(argv)
    reps = 3 if args.quick else 7
    try:
        import modern_robotics as mr
    except ImportError:  # pragma: no cover
        mr = None
    ur5 = rk.load("ur5")
    p = ur5.poe
    model, data = ur5.model, ur5.data
    rng = np.random.default_rng(0)
    q, dq, ddq = rng.normal(size=6), rng.normal(size=6), rng.normal(size=6)
    tau = rng.normal(size=6)
    g, z6 = ur5.gravity, np.zeros(6)
    T_target = rk.fkin_space(p.M, p.Slist, q)
    q0 = q + 0.05
    Ml, Gl = list(p.Mlist), list(p.Glist)
    cases = [
        ("fkin_space", lambda: rk.fkin_space(p.M, p.Slist, q),
         (lambda: mr.FKinSpace(p.M, p.Slist, q)) if mr else None,
         lambda: (pin.forwardKinematics(model, data, q), pin.updateFramePlacement(model, data, ur5.tip_id))),
        ("jacobian_space", lambda: rk.jacobian_space(p.Slist, q),
         (lambda: mr.JacobianSpace(p.Slist, q)) if mr else None,
         lambda: pin.computeFrameJacobian(model, data, q, ur5.tip_id, pin.WORLD)),
        ("inverse_dynamics", lambda: rk.inverse_dynamics(q, dq, ddq, g, z6, p.Mlist, p.Glist, p.Slist),
         (lambda: mr.InverseDynamics(q, dq, ddq, g, z6, Ml, Gl, p.Slist)) if mr else None,
         lambda: pin.rnea(model, data, q, dq, ddq)),
        ("mass_matrix", lambda: rk.mass_matrix(q, p.Mlist, p.Glist, p.Slist),
         (lambda: mr.MassMatrix(q, Ml, Gl, p.Slist)) if mr else None,
         lambda: pin.crba(model, data, q)),
        ("forward_dynamics", lambda: rk.forward_dynamics(q, dq, tau, g, z6, p.Mlist, p.Glist, p.Slist),
         (lambda: mr.ForwardDynamics(q, dq, tau, g, z6, Ml, Gl, p.Slist)) if mr else None,
         lambda: pin.aba(model, data, q, dq, tau)),
        ("ikin_space (from 0.05 rad away)", lambda: rk.ikin_space(p.Slist, p.M, T_target, q0, 1e-9, 1e-9),
         (lambda: mr.IKinSpace(p.Slist, p.M, T_target, q0, 1e-9, 1e-9)) if mr else None, None),
    ]
    rows = []
    for name, ours, theirs, pino in cases:
        t_ours = time_call(ours, repeats=reps)
        t_mr = time_call(theirs, repeats=reps, target=0.2) if theirs else float("nan")
        t_pin = time_call(pino, repeats=reps) if pino else float("nan")
        rows.append([name, fmt_time(t_ours), fmt_time(t_mr), f"{t_mr / t_ours:.1f}×" if theirs else "n/a",
                     fmt_time(t_pin), f"{t_ours / t_pin:.0f}×" if pino else "n/a"])
    print(f"# Speed benchmark\n\nmachine: {machine()}\n\n## Per call, UR5\n")
    print(table(["function", "robokit", "modern_robotics", "robokit faster by", "Pinocchio", "robokit / Pinocchio"],
                rows))

    sizes = [1, 100, 1000] if args.quick else [1, 100, 10_000]
    rows = []
    for N in sizes:
        Q, D, A = rng.normal(size=(N, 6)), rng.normal(size=(N, 6)), rng.normal(size=(N, 6))

        def loop_fk():
            for k in range(N):
                pin.forwardKinematics(model, data, Q[k])
                pin.updateFramePlacement(model, data, ur5.tip_id)

        def loop_j():
            for k in range(N):
                pin.computeFrameJacobian(model, data, Q[k], ur5.tip_id, pin.WORLD)

        def loop_id():
            for k in range(N):
                pin.rnea(model, data, Q[k], D[k], A[k])

        def loop_m():
            for k in range(N):
                pin.crba(model, data, Q[k])

        batch = [
            ("fkin_space", lambda: rk.fkin_space(p.M, p.Slist, Q), loop_fk),
            ("jacobian_space", lambda: rk.jacobian_space(p.Slist, Q), loop_j),
            ("inverse_dynamics", lambda: rk.inverse_dynamics(Q, D, A, g, z6, p.Mlist, p.Glist, p.Slist), loop_id),
            ("mass_matrix", lambda: rk.mass_matrix(Q, p.Mlist, p.Glist, p.Slist), loop_m),
        ]
        for name, fb, fl in batch:
            tb = time_call(fb, repeats=reps) / N
            tl = time_call(fl, repeats=reps) / N
            tracemalloc.start()
            fb()
            peak = tracemalloc.get_traced_memory()[1]
            tracemalloc.stop()
            rows.append([name, f"{N:,}", fmt_time(tb), fmt_time(tl), f"{tb / tl:.2f}", f"{peak / 1e6:.1f} MB"])
    print("\n## Batched, per configuration (UR5)\n")
    print(table(["function", "N", "robokit batched", "Python loop over Pinocchio", "ratio (≤ 1: faster)",
                 "peak memory"], rows))

    rows = []
    for name, ours, raw in [
        ("Robot.rnea", lambda: ur5.rnea(q, dq, ddq), lambda: pin.rnea(model, data, q, dq, ddq)),
        ("Robot.crba", lambda: ur5.crba(q), lambda: pin.crba(model, data, q)),
        ("Robot.aba", lambda: ur5.aba(q, dq, tau), lambda: pin.aba(model, data, q, dq, tau)),
        ("Robot.frame_pose", lambda: ur5.frame_pose(q),
         lambda: (pin.forwardKinematics(model, data, q), pin.updateFramePlacement(model, data, ur5.tip_id))),
        ("Robot.jacobian", lambda: ur5.jacobian(q), lambda: pin.computeFrameJacobian(model, data, q, ur5.tip_id, pin.WORLD)),
    ]:
        to, tr = time_call(ours, repeats=reps), time_call(raw, repeats=reps)
        rows.append([name, fmt_time(to), fmt_time(tr), f"{to / tr:.1f}×"])
    print("\n## Robot methods on top of Pinocchio (UR5)\n")
    print(table(["method", "robokit.Robot", "raw Pinocchio", "overhead"], rows))


if __name__ == "__main__":
    main()
