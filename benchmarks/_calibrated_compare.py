"""Before/after check of the calibrated arms' exact IK (issue 43): the same answers from two versions.

``dump OUT`` writes, for calibrated PUMA 560, UR5 and random Pieper arms (the arms of
:mod:`benchmarks.calibrated_ik`, with two calibration draws each) and many poses — random
configurations, and some near a wrist singularity (θ₅ within 2 mrad of 0) — every solution of
``ik_analytic`` (q, within_limits, label, degenerate), ``AnalyticIK(arm).calibrated.branches(T)``
and the warnings raised. ``compare A B`` reads two dumps (say main's and a branch's) and counts the
poses whose solution sets, labels, flags or branch outcomes differ, or whose q differ by more than
1e-9; it also checks every solution of B against Pinocchio's FK (``robot.frame_pose``) to 1e-9.

Run: ``.venv/bin/python -m benchmarks._calibrated_compare dump /tmp/a.pkl [--poses N]`` in each
version, then ``... compare /tmp/a.pkl /tmp/b.pkl``. Not part of ``python -m benchmarks``.
"""
from __future__ import annotations

import argparse
import pickle
import warnings

import numpy as np


def _arms(draws: int = 2):
    import robokit as rk
    from robokit.calibration import chain_from_robot, robot_from_chain
    from robokit.description.dh import DHLink, DHTable

    rows = [DHLink("R", a=0.2, alpha=1.1, d=0.4), DHLink("R", a=0.5, alpha=-0.6, d=0.1),
            DHLink("R", a=0.1, alpha=1.9, d=-0.05), DHLink("R", a=0.0, alpha=-1.3, d=0.35),
            DHLink("R", a=0.0, alpha=0.9, d=0.0), DHLink("R", a=0.02, alpha=0.0, d=0.12)]
    rng = np.random.default_rng(0)
    out = []
    for draw in range(draws):
        for label, model in (("PUMA 560", "puma560"), ("UR5", "ur5"),
                             ("random Pieper arm", DHTable("pieper", "standard", tuple(rows)))):
            nominal = rk.load(model)
            delta = rng.uniform(-2e-3, 2e-3, (nominal.n + 1, 6))
            out.append((f"{label} #{draw}", nominal, robot_from_chain(nominal, chain_from_robot(nominal).perturbed(delta))))
    return out


def dump(path: str, poses: int) -> None:
    import robokit as rk
    from robokit.ik.closed_form import AnalyticIK

    result = {}
    for label, _nominal, cal in _arms():
        arm = AnalyticIK(cal).calibrated
        rng = np.random.default_rng(7)
        rows = []
        for i in range(poses):
            q = cal.random_configuration(rng)
            if i % 10 == 9:  # near the wrist singularity
                q[4] = rng.uniform(-2e-3, 2e-3)
            T = cal.frame_pose(q)
            with warnings.catch_warnings(record=True) as caught:
                warnings.simplefilter("always", rk.RobokitWarning)
                sols = rk.ik_analytic(cal, T)
                branches = arm.branches(T)
            rows.append({"T": T, "sols": [(np.array(s.q), bool(s.within_limits), s.label, bool(s.degenerate))
                                          for s in sols],
                         "branches": [(b.label, b.outcome, b.index, b.orientation_error, b.position_error)
                                      for b in branches],
                         "warnings": [str(w.message)[:60] for w in caught]})
        result[label] = rows
    with open(path, "wb") as f:
        pickle.dump(result, f)
    print(f"{path}: {sum(len(v) for v in result.values())} poses")


def compare(a_path: str, b_path: str) -> int:
    with open(a_path, "rb") as f:
        A = pickle.load(f)
    with open(b_path, "rb") as f:
        B = pickle.load(f)
    arms = {label: cal for label, _n, cal in _arms()}
    bad_total = 0
    for label in A:
        cal = arms[label]
        counts = dict(poses=0, solutions=0, set=0, labels=0, flags=0, q=0, branches=0, warnings=0, fk=0)
        qdiff = 0.0
        for ra, rb in zip(A[label], B[label]):
            counts["poses"] += 1
            sa, sb = ra["sols"], rb["sols"]
            counts["solutions"] += len(sb)
            for q, _w, _l, _d in sb:
                if np.abs(cal.frame_pose(q) - rb["T"]).max() > 1e-9:
                    counts["fk"] += 1
            if len(sa) != len(sb):
                counts["set"] += 1
                continue
            if [s[2] for s in sa] != [s[2] for s in sb]:
                counts["labels"] += 1
            if [(s[1], s[3]) for s in sa] != [(s[1], s[3]) for s in sb]:
                counts["flags"] += 1
            d = max([float(np.abs(x[0] - y[0]).max()) for x, y in zip(sa, sb)] + [0.0])
            qdiff = max(qdiff, d)
            if d > 1e-9:
                counts["q"] += 1
            if [b[:3] for b in ra["branches"]] != [b[:3] for b in rb["branches"]] or any(
                    (x[1] == "vanished") != (max(y[3], y[4]) >= 1e-10) for x, y in zip(ra["branches"], rb["branches"])):
                counts["branches"] += 1
            if ra["warnings"] != rb["warnings"]:
                counts["warnings"] += 1
        bad = sum(v for k, v in counts.items() if k not in ("poses", "solutions"))
        bad_total += bad
        print(f"{label}: {counts}; largest |Δq| {qdiff:.1e}")
    print("identical" if bad_total == 0 else f"{bad_total} differences")
    return bad_total


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    sub = ap.add_subparsers(dest="cmd", required=True)
    d = sub.add_parser("dump")
    d.add_argument("path")
    d.add_argument("--poses", type=int, default=300)
    c = sub.add_parser("compare")
    c.add_argument("a")
    c.add_argument("b")
    args = ap.parse_args(argv)
    if args.cmd == "dump":
        dump(args.path, args.poses)
    else:
        raise SystemExit(1 if compare(args.a, args.b) else 0)


if __name__ == "__main__":
    main()
