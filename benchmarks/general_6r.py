"""General 6R closed-form IK benchmark: every solution of one pose, beside roboticstoolbox's
``analytic_ik`` (Raghavan–Roth, derived symbolically) and a numerical IK from 200 seeds.

Arms: the Kinova JACO² 6-DOF non-spherical (Kinova's classic DH table), a random general 6R
arm, and the PUMA 560 with axes 4 and 5 moved 1 mm apart (no longer a spherical wrist). For
each arm ``--poses`` targets (FK of random configurations, seed 0); per target the median time
of one ``ik_analytic`` call (``_harness.time_call``), then the median over the targets.
Peers in the same run:

* roboticstoolbox-python 1.5 ``DHRobot.analytic_ik().solve(T, joint_limits=False)`` on the
  same standard-DH arm (all solutions of one pose; the one-off symbolic derivation is timed
  separately). Only for the arms given by ``--rtb`` (default: the Jaco), the derivation
  taking minutes per arm.
* the generated C (``robokit codegen``'s ``NAME_ik``, gcc ``-O2``, ``benchmarks.codegen``'s driver:
  256 poses from FK of random configurations, fastest of 7 batches) and its instructions per pose
  (valgrind's callgrind, when installed: a count the machine's load does not change).
* robokit's compiled Levenberg–Marquardt ``solve_ik(method="compiled", max_restarts=0)`` from
  200 random seeds, de-duplicated (1e-6 rad): the time for the 200 runs and how many distinct
  solutions they find.

* the generated C of the same arm (``robokit.codegen``, gcc ``-O2``, ``NAME_ik`` called through
  ctypes: every solution of one pose, the C's own Hessenberg/Francis QR), per pose.

Also printed: robokit's compiled kernel alone (``kernels.general_6r.solve_pose``, the one call
``ik_analytic`` makes, without building the solution objects), solution counts, how many numerical solutions the closed form misses (should
be 0), and the largest Pinocchio FK error of a returned solution. The machine is shared (2
cores, other jobs running): the load average is printed with the table. Asserts nothing.

Run: ``.venv/bin/python -m benchmarks.general_6r [--quick] [--poses N] [--rtb all|none|jaco]``
"""
from __future__ import annotations

import argparse
import math
import os
import statistics
import time

import numpy as np

from benchmarks._harness import fmt_time, machine, table, time_call

WIDE = np.array([-2 * np.pi, 2 * np.pi])


def jaco2_table():
    """Kinova JACO² 6-DOF non-spherical (j2n6s300), classic DH (Kinova's JACO² 6 DOF
    specification guide): D1 = 0.2755, D2 = 0.41, D3 = 0.2073, D4 = D5 = 0.0741, D6 = 0.16,
    e2 = 0.0098 m, aa = 30°."""
    from robokit.description.dh import DHLink, DHTable

    D1, D2, D3, D4, D5, D6, e2 = 0.2755, 0.4100, 0.2073, 0.0741, 0.0741, 0.1600, 0.0098
    aa = math.radians(30.0)
    k = math.sin(aa) / math.sin(2 * aa)
    d = [D1, 0.0, -e2, -(D3 + k * D4), -(k * D4 + k * D5), -(k * D5 + D6)]
    alpha = [math.pi / 2, math.pi, math.pi / 2, 2 * aa, 2 * aa, math.pi]
    a = [0.0, D2, 0.0, 0.0, 0.0, 0.0]
    return DHTable("jaco2_6n", "standard", tuple(DHLink("R", a=a[i], alpha=alpha[i], d=d[i], qlim=WIDE)
                                                  for i in range(6)))


def random_general_table(seed=3):
    from robokit.description.dh import DHLink, DHTable

    rng = np.random.default_rng(seed)
    return DHTable("random_6r", "standard", tuple(
        DHLink("R", a=rng.uniform(-0.5, 0.5), alpha=rng.uniform(-np.pi, np.pi), d=rng.uniform(-0.5, 0.5),
               theta=rng.uniform(-np.pi, np.pi), qlim=WIDE) for _ in range(6)))


def puma_offset_table(eps=1e-3):
    import robokit
    from robokit.description.dh import DHLink, DHTable

    t = robokit.load("puma560").dh
    rows = [DHLink("R", r.a + (eps if i == 3 else 0.0), r.alpha, r.d, r.theta, qlim=WIDE)
            for i, r in enumerate(t.links)]
    return DHTable("puma560_offset_1mm", t.convention, tuple(rows), base=t.base, tool=t.tool)


def many_solutions_table():
    """A random general 6R arm (seed 1128 of a search over 30 000 random arm/pose pairs) and a pose of
    it with 14 real solutions — the most that search found (16, the bound, is rare for random arms)."""
    from robokit.description.dh import DHLink, DHTable

    rows = [(0.923235, -0.491836, -0.705859), (0.218669, 1.384281, -0.725224), (0.736298, -1.35968, -0.59417),
            (0.21131, -1.454559, -0.11714), (0.602698, -0.394998, -0.867023), (0.94085, -1.74476, 0.303884)]
    q = np.array([-2.6497734133136186, 2.3612831206549263, -1.0045810158041708, -0.22591212383724724,
                  3.0838287806256934, 2.3318126860362476])
    return DHTable("many_6r", "standard", tuple(DHLink("R", a=a, alpha=al, d=d, qlim=WIDE) for a, al, d in rows)), q


def kernel_call(robot, nominal=None):
    """The one compiled call ``ik_analytic`` makes per pose on a general 6R arm, as ``f(T)``: the
    target made canonical and scaled, then ``kernels.general_6r.solve_pose`` (no solution objects)."""
    from robokit.ik.closed_form import analytic_ik
    from robokit.kernels.general_6r import solve_pose

    model = analytic_ik(robot, nominal)
    solver, el = model.solver, model.solver.elim
    out = np.empty((96, 7))

    def f(T):
        T06s = np.array(model.chain.target_06(T), dtype=float)  # (a copy: target_06 may return T itself)
        T06s[:3, 3] /= solver.scale
        return solve_pose(el.kchain, el.ktol, *el.kreadings, T06s, out)
    return f


def c_ik(robot, folder):
    """The generated C's ``NAME_ik`` (gcc -O2) of ``robot`` as ``f(T)`` through ctypes, or a string
    saying why not (no compiler, no IK in the C)."""
    import ctypes

    from robokit.codegen import generate_c
    from robokit.codegen.build import compile_library, find_compiler

    cc = find_compiler()
    if cc is None:
        return "no C compiler"
    lib = compile_library(generate_c(robot, name="g6r"), folder, robot.n, compiler=cc)
    fn = getattr(lib.lib, f"{lib.name}_ik", None)
    if fn is None:
        return "no IK in the C"
    ct = ctypes.POINTER(ctypes.c_double)
    sol = np.zeros(lib.max_solutions * lib.n)
    sp = sol.ctypes.data_as(ct)

    def f(T):
        Tc = np.ascontiguousarray(T, dtype=float).reshape(-1)
        return fn(Tc.ctypes.data_as(ct), sp)
    return f


def _rtb_robot(tab):
    import roboticstoolbox as rtb
    from spatialmath import SE3

    r = rtb.DHRobot([rtb.RevoluteDH(a=l.a, alpha=l.alpha, d=l.d, offset=l.theta) for l in tab.links], name=tab.name)
    if not np.allclose(tab.base, np.eye(4)):
        r.base = SE3(tab.base, check=False)
    if not np.allclose(tab.tool, np.eye(4)):
        r.tool = SE3(tab.tool, check=False)
    return r


def _dist(a, b):
    return float(np.abs(np.angle(np.exp(1j * (np.asarray(a) - np.asarray(b))))).max())


def _c_ik(robot) -> dict:
    """The generated C's NAME_ik per pose (s) and, with valgrind, its instructions per pose (``ir_ik_ex``)."""
    import tempfile
    from pathlib import Path

    from benchmarks.codegen import _c_times

    with tempfile.TemporaryDirectory() as tmp:
        return _c_times(robot, Path(tmp), 1, 1)


def main(argv=None):
    import robokit
    from robokit.ik import ik_analytic, solve_ik

    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="3 poses per arm instead of 10")
    ap.add_argument("--poses", type=int, default=None)
    ap.add_argument("--rtb", default="jaco", choices=["jaco", "all", "none"])
    args, _ = ap.parse_known_args(argv)
    n_poses = args.poses or (3 if args.quick else 10)
    many, q_many = many_solutions_table()
    arms = [("Kinova JACO² 6-DOF (offset wrist)", jaco2_table()), ("random general 6R", random_general_table()),
            ("PUMA 560, axes 4–5 1 mm apart", puma_offset_table()), ("a 14-solution pose of a random arm", many)]
    load = ", ".join(f"{x:.2f}" for x in os.getloadavg())
    print(f"## General 6R closed-form IK, all solutions of one pose ({machine()}; load average {load}, "
          f"shared machine: times are under load)\n")
    import tempfile

    tmp = tempfile.TemporaryDirectory()
    M = np.random.default_rng(1).standard_normal((24, 24))
    t_eig = time_call(np.linalg.eig, M, repeats=5, target=0.02)
    rows = []
    for k, (name, tab) in enumerate(arms):
        robot = robokit.load(tab)
        c = _c_ik(robot)
        t0 = time.perf_counter()
        # the general 6R method on every arm (the nearly special PUMA defaults to its calibrated
        # spherical-wrist solver: nominal=False asks for the arm as it is, by elimination)
        nominal = None if robokit.ik_analytic_kind(robot).method == "general 6R" else False
        robokit.ik_analytic_kind(robot, nominal=nominal)  # builds the solver (scores the 36 readings)
        build = time.perf_counter() - t0
        use_rtb = args.rtb == "all" or (args.rtb == "jaco" and k == 0)
        ik_rtb, rtb_build = None, float("nan")
        if use_rtb:
            try:
                r = _rtb_robot(tab)
                t0 = time.perf_counter()
                ik_rtb = r.analytic_ik()  # roboticstoolbox ≥ 1.5 (and SymPy)
                rtb_build = time.perf_counter() - t0
            except (ImportError, AttributeError) as exc:  # an older toolbox: no analytic IK for a general arm
                print(f"roboticstoolbox analytic_ik not available: {exc}")
                use_rtb = False
        rng = np.random.default_rng(0)
        kern = kernel_call(robot, nominal)
        t_k = []
        t_rk, t_rtb, t_num, n_rk, n_rtb, n_num, missed, worst, agree = [], [], [], [], [], [], 0, 0.0, 0
        for _ in range(1 if tab is many else n_poses):
            q = q_many if tab is many else rng.uniform(-np.pi, np.pi, 6)
            T = robot.frame_pose(q)
            sols = ik_analytic(robot, T, nominal=nominal)
            t_rk.append(time_call(ik_analytic, robot, T, nominal=nominal, repeats=5, target=0.02))
            t_k.append(time_call(kern, T, repeats=5, target=0.02))
            n_rk.append(len(sols))
            worst = max([worst] + [float(np.abs(robot.frame_pose(s.q) - T).max()) for s in sols])
            if ik_rtb is not None:
                res = ik_rtb.solve(T, joint_limits=False)
                Qr = np.asarray(res.q).reshape(-1, 6) if res.success else np.zeros((0, 6))
                t_rtb.append(time_call(ik_rtb.solve, T, joint_limits=False, repeats=3, target=0.02))
                n_rtb.append(len(Qr))
                agree += int(len(Qr) == len(sols) and all(min(_dist(x, s.q) for s in sols) < 1e-6 for x in Qr))
            seeds = rng.uniform(-np.pi, np.pi, (200, 6))
            t0 = time.perf_counter()
            found = []
            for s0 in seeds:
                res = solve_ik(robot, T, q0=s0, method="compiled", max_restarts=0)
                if res.success and not any(_dist(res.q, f) < 1e-6 for f in found):
                    found.append(res.q)
            t_num.append(time.perf_counter() - t0)
            n_num.append(len(found))
            missed += sum(1 for f in found if not sols or min(_dist(f, s.q) for s in sols) > 1e-6)
        m_rk = statistics.median(t_rk)
        m_rtb = statistics.median(t_rtb) if t_rtb else float("nan")
        m_num = statistics.median(t_num)
        m_k = statistics.median(t_k)
        rows.append([name, fmt_time(build), fmt_time(m_rk), fmt_time(m_k), fmt_time(c["ik"]),
                     f"{c['ir_ik_ex']:,.0f}" if "ir_ik_ex" in c else "no valgrind", f"{m_rk / c['ik']:.1f}×",
                     f"{statistics.mean(n_rk):.1f} ({min(n_rk)}–{max(n_rk)})",
                     f"{worst:.1e}", fmt_time(rtb_build) if use_rtb else "not run",
                     fmt_time(m_rtb) if use_rtb else "not run",
                     f"{statistics.mean(n_rtb):.1f}, same set {agree}/{len(t_rk)}" if use_rtb else "",
                     f"{m_rtb / m_rk:.1f}×" if use_rtb else "",
                     fmt_time(m_num), f"{statistics.mean(n_num):.1f}, missed by closed form: {missed}",
                     f"{m_num / m_rk:.0f}×"])
    print(table(["arm", "robokit build", "robokit all solutions", "its compiled kernel alone", "C NAME_ik (-O2)",
                 "C instructions / pose", "Python / C", "# solutions (min–max)", "max FK error",
                 "rtb derivation", "rtb solve", "# rtb", "rtb / robokit", "numerical IK ×200 seeds",
                 "# distinct numerical", "numerical / robokit"], rows))
    print(f"\nFor scale, in the same run: numpy.linalg.eig of one 24 × 24 matrix (the size of the eigenproblem "
          f"each pose needs; robokit solves it with its own compiled routine) {fmt_time(t_eig)}.")
    tmp.cleanup()
    print(f"\n{n_poses} poses per arm (one for the 14-solution pose). robokit: `ik_analytic` (general 6R method); rtb: roboticstoolbox "
          "`DHRobot.analytic_ik().solve` (1.5.0, SymPy derivation once per arm); numerical: robokit's "
          "compiled LM from 200 random seeds, de-duplicated.")


if __name__ == "__main__":
    main()
