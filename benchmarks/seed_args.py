"""The seed functions called the way the course and the Modern Robotics book call them (issue 42, item 6).

One table, per call on the UR5: each seed function with

* ``arrays`` — packed arguments: C-contiguous, writeable float64 arrays (``robot.poe``'s own);
* ``book`` — the book's types: ``Mlist``/``Glist`` Python lists of arrays, ``Slist`` written as
  rows and transposed (``np.array([...]).T``, a non-contiguous view), ``M`` a nested list;
* ``tuples`` — ``Mlist``/``Glist`` tuples of arrays, joint values a tuple of floats;
* ``nested lists`` — every argument plain nested Python lists of floats (``.tolist()``);
* ``read-only`` — the packed arrays with ``writeable=False`` (e.g. from ``np.load(mmap_mode='r')``);

beside ``modern_robotics`` given the same arguments (the ``book`` ones), with the ratios
modern_robotics / robokit and robokit / the same call on packed arrays. Timings are the best of
short batches (:func:`benchmarks._harness.time_best`); nothing is asserted.

Run: ``python -m benchmarks.seed_args [--quick]``.
"""
from __future__ import annotations

import argparse

import numpy as np

from benchmarks._harness import fmt_time, machine, table, time_best


def _variants(p, q, dq, ddq, tau, g):
    """The argument sets, each a dict of the seed functions' argument names."""
    F = np.zeros(6)
    arrays = dict(M=p.M, Slist=p.Slist, Blist=p.Blist, Mlist=p.Mlist, Glist=p.Glist, q=q, dq=dq, ddq=ddq,
                  tau=tau, g=g, F=F)
    slist_rows = np.array(p.Slist.T.tolist())  # the book writes the screws as rows, then .T
    blist_rows = np.array(p.Blist.T.tolist())
    book = dict(M=p.M.tolist(), Slist=slist_rows.T, Blist=blist_rows.T, Mlist=[m.copy() for m in p.Mlist],
                Glist=[G.copy() for G in p.Glist], q=q.copy(), dq=dq.copy(), ddq=ddq.copy(), tau=tau.copy(),
                g=g.copy(), F=F.copy())
    tuples = dict(arrays, Mlist=tuple(m.copy() for m in p.Mlist), Glist=tuple(G.copy() for G in p.Glist),
                  q=tuple(q.tolist()), dq=tuple(dq.tolist()), ddq=tuple(ddq.tolist()), tau=tuple(tau.tolist()),
                  g=tuple(g.tolist()), F=tuple(F.tolist()))
    nested = {k: np.asarray(v).tolist() for k, v in arrays.items()}
    readonly = {}
    for k, v in arrays.items():
        v = np.array(v)
        v.flags.writeable = False
        readonly[k] = v
    return [("arrays", arrays), ("book", book), ("tuples", tuples), ("nested lists", nested),
            ("read-only", readonly)]


def cases(rk, mr):
    """(name, robokit call, modern_robotics call) on one argument dict ``a``."""
    return [
        ("fkin_space", lambda a: rk.fkin_space(a["M"], a["Slist"], a["q"]),
         lambda a: mr.FKinSpace(np.array(a["M"]), a["Slist"], a["q"])),
        ("fkin_body", lambda a: rk.fkin_body(a["M"], a["Blist"], a["q"]),
         lambda a: mr.FKinBody(np.array(a["M"]), a["Blist"], a["q"])),
        ("jacobian_space", lambda a: rk.jacobian_space(a["Slist"], a["q"]),
         lambda a: mr.JacobianSpace(a["Slist"], a["q"])),
        ("jacobian_body", lambda a: rk.jacobian_body(a["Blist"], a["q"]),
         lambda a: mr.JacobianBody(a["Blist"], a["q"])),
        ("inverse_dynamics", lambda a: rk.inverse_dynamics(a["q"], a["dq"], a["ddq"], a["g"], a["F"], a["Mlist"],
                                                           a["Glist"], a["Slist"]),
         lambda a: mr.InverseDynamics(a["q"], a["dq"], a["ddq"], a["g"], a["F"], a["Mlist"], a["Glist"], a["Slist"])),
        ("mass_matrix", lambda a: rk.mass_matrix(a["q"], a["Mlist"], a["Glist"], a["Slist"]),
         lambda a: mr.MassMatrix(a["q"], a["Mlist"], a["Glist"], a["Slist"])),
        ("vel_quadratic_forces", lambda a: rk.vel_quadratic_forces(a["q"], a["dq"], a["Mlist"], a["Glist"], a["Slist"]),
         lambda a: mr.VelQuadraticForces(a["q"], a["dq"], a["Mlist"], a["Glist"], a["Slist"])),
        ("gravity_forces", lambda a: rk.gravity_forces(a["q"], a["g"], a["Mlist"], a["Glist"], a["Slist"]),
         lambda a: mr.GravityForces(a["q"], a["g"], a["Mlist"], a["Glist"], a["Slist"])),
        ("end_effector_forces", lambda a: rk.end_effector_forces(a["q"], a["F"], a["Mlist"], a["Glist"], a["Slist"]),
         lambda a: mr.EndEffectorForces(a["q"], a["F"], a["Mlist"], a["Glist"], a["Slist"])),
        ("forward_dynamics", lambda a: rk.forward_dynamics(a["q"], a["dq"], a["tau"], a["g"], a["F"], a["Mlist"],
                                                           a["Glist"], a["Slist"]),
         lambda a: mr.ForwardDynamics(a["q"], a["dq"], a["tau"], a["g"], a["F"], a["Mlist"], a["Glist"], a["Slist"])),
    ]


def main(argv=None):
    import robokit as rk

    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="fewer batches")
    ap.add_argument("--only", default="", help="comma-separated function names")
    args = ap.parse_args(argv)
    batches = 30 if args.quick else 150
    try:
        import modern_robotics as mr
    except ImportError:  # pragma: no cover
        mr = None
    ur5 = rk.load("ur5")
    p = ur5.poe
    rng = np.random.default_rng(0)
    q, dq, ddq, tau = (rng.normal(size=6) for _ in range(4))
    variants = _variants(p, q, dq, ddq, tau, np.asarray(ur5.gravity, dtype=float))
    book = dict(variants)["book"]
    only = {s for s in args.only.split(",") if s}
    rows = []
    for name, ours, theirs in cases(rk, mr):
        if only and name not in only:
            continue
        t_mr = time_best(theirs, book, batches=max(5, batches // 10), target=0.01) if mr else float("nan")
        t_packed = float("nan")
        for label, a in variants:
            try:
                t = time_best(ours, a, batches=batches)
            except Exception as exc:  # a call that fails is reported as such (issue 42 found read-only θ failing)
                rows.append([name, label, f"fails: {type(exc).__name__}", "", "", ""])
                continue
            if label == "arrays":
                t_packed = t
            rows.append([name, label, fmt_time(t), fmt_time(t_mr) if label == "book" else "",
                         f"{t_mr / t:.0f}×" if mr else "n/a", f"{t / t_packed:.2f}×"])
    print(f"# Seed functions with the book's argument types (UR5)\n\nmachine: {machine()}\n")
    print(table(["function", "arguments", "robokit", "modern_robotics (book args)", "modern_robotics / robokit",
                 "robokit / robokit on arrays"], rows))


if __name__ == "__main__":
    main()
