"""Compiled closed-form IK: all solutions of one pose against EAIK and ``ur-analytic-ik``,
``solve_ik`` against roboticstoolbox's C++ ``ik_LM``, and the batched form at N = 10⁴.

Tables (Markdown; nothing is asserted):

1. **All solutions of one pose.** For each robot, ``--poses`` targets (FK of random
   configurations); per target the median time of one call (``_harness.time_call``), robokit
   and the peers alternated target by target, then the median over the targets. robokit:
   ``ik_analytic`` (a list of ``IKSolution``) and the bare compiled kernel
   (``closed_form_solve``: one array). Peers in the same run: EAIK (``eaik.IK_DH.DhRobot``
   built from the arm's standard DH α, a, d — the same geometry; its targets are its own FK of
   the same configurations, so each solver gets reachable poses of its own frames) and
   ``ur-analytic-ik`` (its ``ur5``/``ur10`` modules; UR arms only).
2. **solve_ik (closed form inside) vs rtb ``ik_LM``** on the same reachable targets and
   initial guesses (``benchmarks.kernels``' ETS construction): median per call, success
   verified with Pinocchio FK to 1e-9.
3. **Batched**: ``ik_analytic_batch`` over N = 10⁴ poses (numba threads as configured) against
   a Python loop over ``ik_analytic`` and EAIK's ``IK_batched``; per-pose time.

Run: ``.venv/bin/python -m benchmarks.ik_closed_form [--quick]``
"""
from __future__ import annotations

import argparse
import os
import statistics
import time

import numpy as np

from benchmarks._harness import fmt_time, machine, table, time_call


def _ratio(a, b):
    return f"{a / b:.2f}×" if np.isfinite(a) and np.isfinite(b) and b > 0 else "n/a"


def _spherical_arm():
    from robokit.description.dh import DHLink, DHTable

    rng = np.random.default_rng(4)
    rows = []
    for i in range(6):
        rows.append(DHLink("R", rng.uniform(-0.5, 0.5) if i < 3 else 0.0, rng.uniform(0.4, 2.7),
                           rng.uniform(-0.5, 0.5) if i != 4 else 0.0, 0.0))
    return DHTable("random_spherical", "standard", tuple(rows))


def _standard_dh(robot):
    """The arm's standard DH table (its own, or the one extracted from its URDF), or None."""
    from robokit.description.urdf_to_dh import dh_from_urdf

    if robot.dh is not None:
        return robot.dh if robot.dh.convention == "standard" else None
    res = dh_from_urdf(robot, "standard")
    return res.table if res.exact else None


def _eaik(robot):
    try:
        from eaik.IK_DH import DhRobot
    except ImportError:
        return None
    dh = _standard_dh(robot)
    if dh is None:
        return None
    L = dh.links
    return DhRobot(np.array([l.alpha for l in L]), np.array([l.a for l in L]), np.array([l.d for l in L]))


def _ur_module(name):
    try:
        import ur_analytic_ik
    except ImportError:
        return None
    return getattr(ur_analytic_ik, name, None)


def per_pose(n_poses):
    import robokit
    from robokit.ik import AnalyticIK, ik_analytic
    from robokit.kernels.closed_form import closed_form_solve

    robots = [("PUMA 560", "puma560", robokit.load("puma560")), ("UR5", "ur5", robokit.load("ur5")),
              ("UR10", "ur10", robokit.load("ur10")),
              ("random spherical wrist (quartic)", None, robokit.load(_spherical_arm()))]
    rows = []
    for label, name, robot in robots:
        ik = AnalyticIK(robot)
        K = ik._kernel[0]
        eaik = _eaik(robot)
        ur = _ur_module(name) if name and name.startswith("ur") else None
        rng = np.random.default_rng(0)
        t_rk, t_k, t_e, t_u, counts, worst = [], [], [], [], [], 0.0
        for _ in range(n_poses):
            q = robot.random_configuration(rng)
            T = robot.frame_pose(q)
            sols = ik_analytic(robot, T)
            counts.append(len(sols))
            worst = max([worst] + [float(np.abs(robot.frame_pose(s.q) - T).max()) for s in sols])
            t_rk.append(time_call(ik_analytic, robot, T, repeats=5, target=0.01))
            t_k.append(time_call(closed_form_solve, K, T, 0.0, repeats=5, target=0.01))
            if eaik is not None:
                Te = np.ascontiguousarray(eaik.fwdKin(q))
                t_e.append(time_call(eaik.IK, Te, repeats=5, target=0.01))
            if ur is not None:
                Tu = np.ascontiguousarray(ur.forward_kinematics(*q))
                t_u.append(time_call(ur.inverse_kinematics, Tu, repeats=5, target=0.01))
        med = statistics.median
        m_rk, m_k = med(t_rk), med(t_k)
        m_e = med(t_e) if t_e else float("nan")
        m_u = med(t_u) if t_u else float("nan")
        rows.append([label, ik.method, fmt_time(m_rk), fmt_time(m_k), fmt_time(m_e) if t_e else "n/a",
                     _ratio(m_rk, m_e), fmt_time(m_u) if t_u else "n/a", _ratio(m_rk, m_u),
                     f"{min(counts)}–{max(counts)}", f"{worst:.1e}"])
    print(table(["robot", "method", "robokit ik_analytic", "compiled kernel alone", "EAIK (C++)",
                 "ik_analytic / EAIK", "ur-analytic-ik", "ik_analytic / ur-analytic-ik", "solutions",
                 "max FK error (m, Pinocchio)"], rows))


def solve_ik_vs_rtb(n_targets):
    import robokit as rk

    from benchmarks.kernels import _ets_from_robot

    rows = []
    for name in ("ur5", "puma560"):
        r = rk.load(name)
        try:
            ets = _ets_from_robot(r)
        except Exception:  # pragma: no cover - roboticstoolbox missing
            ets = None
        rng = np.random.default_rng(5)
        targets = [r.frame_pose(r.random_configuration(rng)) for _ in range(n_targets)]
        guesses = [r.random_configuration(rng) for _ in range(n_targets)]
        rk.solve_ik(r, targets[0], q0=guesses[0])
        t_o, ok_o, t_r, ok_r = [], 0, [], 0
        for k, (T, q0) in enumerate(zip(targets, guesses)):
            t_o.append(time_call(rk.solve_ik, r, T, q0=q0, repeats=3, target=0.005))
            res = rk.solve_ik(r, T, q0=q0)
            ok_o += bool(res.success) and np.abs(r.frame_pose(res.q) - T).max() < 1e-9
            if ets is not None:
                np.random.seed(k)
                t0 = time.perf_counter()
                sol = ets.ik_LM(T, q0=q0, ilimit=30, slimit=200, tol=5e-21, joint_limits=True)
                t_r.append(time.perf_counter() - t0)
                q_r, s_r = (sol.q, sol.success) if hasattr(sol, "success") else (sol[0], sol[1])
                ok_r += bool(s_r) and np.abs(r.frame_pose(np.asarray(q_r, dtype=float)) - T).max() < 1e-9
        m_o = statistics.median(t_o)
        m_r = statistics.median(t_r) if t_r else float("nan")
        rows.append([name, n_targets, f"{100 * ok_o / n_targets:.0f} %", fmt_time(m_o),
                     f"{100 * ok_r / n_targets:.0f} %" if t_r else "n/a", fmt_time(m_r) if t_r else "n/a",
                     _ratio(m_o, m_r)])
    print(table(["robot", "targets", "solve_ik success", "solve_ik median", "rtb ik_LM success", "rtb ik_LM median",
                 "solve_ik / rtb"], rows))


def batched(n):
    import numba

    import robokit
    from robokit.ik import ik_analytic, ik_analytic_batch

    rows = []
    for label, name in (("PUMA 560", "puma560"), ("UR5", "ur5")):
        robot = robokit.load(name)
        rng = np.random.default_rng(2)
        qs = np.stack([robot.random_configuration(rng) for _ in range(n)])
        Ts = robot.frame_pose(qs)
        ik_analytic_batch(robot, Ts[:4])  # compile / load
        t0 = time.perf_counter()
        _, counts = ik_analytic_batch(robot, Ts)
        t_b = (time.perf_counter() - t0) / n
        m = min(n, 2000)
        t0 = time.perf_counter()
        for T in Ts[:m]:
            ik_analytic(robot, T)
        t_l = (time.perf_counter() - t0) / m
        eaik = _eaik(robot)
        t_e = float("nan")
        if eaik is not None:
            Te = [np.ascontiguousarray(eaik.fwdKin(q)) for q in qs]
            eaik.IK_batched(Te[:4], num_worker_threads=numba.get_num_threads())
            t0 = time.perf_counter()
            eaik.IK_batched(Te, num_worker_threads=numba.get_num_threads())
            t_e = (time.perf_counter() - t0) / n
        rows.append([label, n, numba.get_num_threads(), fmt_time(t_b), fmt_time(t_l), _ratio(t_b, t_l),
                     fmt_time(t_e) if np.isfinite(t_e) else "n/a", _ratio(t_b, t_e), f"{counts.mean():.2f}"])
    print(table(["robot", "N", "threads", "ik_analytic_batch per pose", "loop of ik_analytic per pose",
                 "batch / loop", "EAIK IK_batched per pose", "batch / EAIK", "mean solutions"], rows))


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="8 poses per robot, N = 2000 in the batch")
    args, _ = ap.parse_known_args(argv)
    n_poses = 8 if args.quick else 25
    load = ", ".join(f"{x:.2f}" for x in os.getloadavg())
    print(f"## Compiled closed-form IK ({machine()}; load average {load})\n")
    print("### All solutions of one pose (median over poses of the per-call median)\n")
    per_pose(n_poses)
    print("\n### solve_ik on arms with a closed form vs roboticstoolbox ik_LM (same targets)\n")
    solve_ik_vs_rtb(20 if args.quick else 50)
    print("\n### Batched closed form\n")
    batched(2000 if args.quick else 10_000)


if __name__ == "__main__":
    main()
