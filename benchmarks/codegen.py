"""Generated C (``robokit codegen``) speed: FK, Jacobian, IK (all solutions), gravity, RNEA per call.

For each robot the C files are generated, compiled with ``-O2`` together with a small C driver
(``clock_gettime(CLOCK_MONOTONIC)`` around loops over 256 configurations / poses, the fastest
of 7 runs — the machine is shared, and the minimum is the least disturbed figure), and run as a subprocess; in the same run the Python peers are timed on the same robot:
Pinocchio's ``forwardKinematics`` (and ``rnea``) called from Python, ``Robot.frame_pose``, and
robokit's Python ``ik_analytic``. Prints a Markdown table with ratios; asserts nothing.

Run: ``.venv/bin/python -m benchmarks.codegen [--quick]``
"""
from __future__ import annotations

import argparse
import subprocess
import tempfile
import warnings
from pathlib import Path

import numpy as np

import time

from benchmarks._harness import fmt_time, machine, table


def time_call(fn, repeats: int = 7, target: float = 0.05) -> float:
    """Fastest of ``repeats`` batches, seconds per call (as the C driver reports)."""
    fn()
    t0 = time.perf_counter()
    fn()
    number = max(1, int(target / max(time.perf_counter() - t0, 1e-7)))
    best = float("inf")
    for _ in range(repeats):
        t0 = time.perf_counter_ns()
        for _ in range(number):
            fn()
        best = min(best, (time.perf_counter_ns() - t0) / number * 1e-9)
    return best

DRIVER = r"""
#define _POSIX_C_SOURCE 199309L
#include <stdio.h>
#include <stdlib.h>
#include <time.h>
#include "@NAME@.h"

#define K 256
static double now(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}
static int cmp(const void *a, const void *b)
{
    const double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}
static double Q[K][@NAME@_N], QD[K][@NAME@_N], T[K][16];
#if @NAME@_HAS_IK
static double SOL[@NAME@_MAX_SOLUTIONS * @NAME@_N];
#endif
volatile double sink;

int main(int argc, char **argv)
{
    const long reps = argc > 1 ? atol(argv[1]) : 200;
    const long reps_ik = argc > 2 ? atol(argv[2]) : reps;
    double J[6 * @NAME@_N], Tb[16], tau[@NAME@_N], t[7], acc = 0.0;
    unsigned long s = 12345;
    int k, j, r, run;
    long total = 0;
    for (k = 0; k < K; ++k) {
        for (j = 0; j < @NAME@_N; ++j) {
            s = s * 6364136223846793005UL + 1442695040888963407UL;
            Q[k][j] = ((double)(s >> 11) / 9007199254740992.0 - 0.5) * 5.0;
            QD[k][j] = ((double)(s >> 13) / 2251799813685248.0 - 0.5);
        }
        @NAME@_fk(Q[k], T[k]);
    }
#define TIME(label, body, nreps)                                                \
    for (run = 0; run < 7; ++run) {                                             \
        const double t0 = now();                                                \
        for (r = 0; r < nreps; ++r) {                                           \
            for (k = 0; k < K; ++k) {                                           \
                body;                                                           \
            }                                                                   \
        }                                                                       \
        t[run] = (now() - t0) / ((double)nreps * K);                            \
    }                                                                           \
    qsort(t, 7, sizeof t[0], cmp);                                              \
    printf("%s %.6e\n", label, t[0]);
    TIME("fk", (@NAME@_fk(Q[k], Tb), acc += Tb[3]), reps)
    TIME("jacobian", (@NAME@_jacobian(Q[k], J), acc += J[0]), reps)
    TIME("gravity", (@NAME@_gravity(Q[k], tau), acc += tau[0]), reps)
    TIME("rnea", (@NAME@_rnea(Q[k], QD[k], QD[k], tau), acc += tau[0]), reps)
#if @NAME@_HAS_IK
    TIME("ik", (total += @NAME@_ik(T[k], SOL), acc += SOL[0]), reps_ik)
    printf("solutions %.6e\n", (double)total / (7.0 * (double)reps_ik * K));
#endif
    sink = acc;
    return 0;
}
"""


def _c_times(robot, folder: Path, reps: int, reps_ik: int) -> dict[str, float]:
    from robokit.codegen import generate_c, write_c
    from robokit.codegen.build import STRICT_FLAGS, find_compiler

    cc = find_compiler()
    if cc is None:
        raise SystemExit("no C compiler found (install gcc)")
    src = generate_c(robot)
    write_c(src, folder)
    (folder / "driver.c").write_text(DRIVER.replace("@NAME@", src.name))
    exe = folder / "bench"
    subprocess.run([cc, *STRICT_FLAGS, "-O2", "-c", str(folder / f"{src.name}.c"), "-o", str(folder / "g.o")],
                   check=True)
    subprocess.run([cc, "-std=c99", "-O2", "-I", str(folder), str(folder / "driver.c"), str(folder / "g.o"),
                    "-o", str(exe), "-lm"], check=True)
    out = subprocess.run([str(exe), str(reps), str(reps_ik)], capture_output=True, text=True, check=True).stdout
    times = {line.split()[0]: float(line.split()[1]) for line in out.splitlines()}
    times.update(_instructions(exe, src.name, folder))
    return times


def _instructions(exe: Path, name: str, folder: Path) -> dict[str, float]:
    """Instructions per call of each function (valgrind's callgrind, inclusive counts): a figure the
    load of a shared machine does not change. {} when valgrind is not installed."""
    import re
    import shutil

    if shutil.which("valgrind") is None or shutil.which("callgrind_annotate") is None:
        return {}
    out = folder / "callgrind.out"
    subprocess.run(["valgrind", "--tool=callgrind", f"--callgrind-out-file={out}", str(exe), "1", "1"],
                   capture_output=True, check=True)
    text = subprocess.run(["callgrind_annotate", "--inclusive=yes", str(out)], capture_output=True, text=True,
                          check=True).stdout
    calls = {"fk": 8 * 256, "jacobian": 7 * 256, "gravity": 7 * 256, "rnea": 7 * 256, "ik_ex": 7 * 256}
    res = {}
    for fn, n in calls.items():
        m = re.search(rf"^\s*([\d,]+) .*:{name}_{fn} ", text, flags=re.M)
        if m:
            res[f"ir_{fn}"] = int(m.group(1).replace(",", "")) / n
    return res


def _quartic_arm():
    """A random spherical-wrist arm whose positioning equation is the general quartic."""
    from robokit.description.dh import DHLink, DHTable

    rng = np.random.default_rng(11)
    rows = []
    for i in range(6):
        rows.append(DHLink("R", 0.0 if i in (3, 4) else rng.uniform(0.1, 0.5), rng.uniform(0.5, 2.5),
                           0.0 if i == 4 else rng.uniform(-0.4, 0.4), rng.uniform(-np.pi, np.pi),
                           mass=1.0, com=np.array([0.05, 0.0, 0.0]), inertia=np.array([0.01, 0.01, 0.01, 0, 0, 0])))
    return DHTable("quartic_arm", "standard", tuple(rows))


def _jaco_table():
    """The Kinova JACO² 6-DOF non-spherical (offset wrist), classic DH from Kinova's JACO² 6 DOF
    Advanced Specification Guide (as in tests/ik/test_general_6r.py)."""
    import math

    from robokit.description.dh import DHLink, DHTable

    D1, D2, D3, D4, D5, D6, e2 = 0.2755, 0.4100, 0.2073, 0.0741, 0.0741, 0.1600, 0.0098
    aa = math.radians(30.0)
    k = math.sin(aa) / math.sin(2 * aa)
    alpha = [math.pi / 2, math.pi, math.pi / 2, 2 * aa, 2 * aa, math.pi]
    a = [0.0, D2, 0.0, 0.0, 0.0, 0.0]
    d = [D1, 0.0, -e2, -(D3 + k * D4), -(k * D4 + k * D5), -(k * D5 + D6)]
    return DHTable("jaco2_6n", "standard", tuple(DHLink("R", a=a[i], alpha=alpha[i], d=d[i], mass=1.0,
                                                        com=np.array([0.0, 0.0, 0.05]),
                                                        inertia=np.array([0.01, 0.01, 0.01, 0, 0, 0]))
                                                  for i in range(6)))


def _general_arm():
    """A random general 6R arm (standard DH, seed 3): no two axes meet or are parallel."""
    from robokit.description.dh import DHLink, DHTable

    rng = np.random.default_rng(3)
    return DHTable("general_6r", "standard", tuple(
        DHLink("R", a=rng.uniform(-0.5, 0.5), alpha=rng.uniform(-3, 3), d=rng.uniform(-0.5, 0.5),
               theta=rng.uniform(-np.pi, np.pi), mass=1.0, com=np.array([0.05, 0.0, 0.0]),
               inertia=np.array([0.01, 0.01, 0.01, 0, 0, 0])) for _ in range(6)))


def _eaik_ik(robot):
    """EAIK's IK of the arm's standard DH table as a callable T -> solutions, or a reason string."""
    try:
        from eaik.IK_DH import DhRobot
    except ImportError:
        return "EAIK not installed"
    dh = robot.dh
    if dh is None or dh.convention != "standard" or any(l.theta != 0.0 for l in dh.links):
        return "—"
    L = dh.links
    arm = DhRobot(np.array([l.alpha for l in L]), np.array([l.a for l in L]), np.array([l.d for l in L]))
    if not arm.hasKnownDecomposition():
        return "no decomposition (EAIK has no general 6R solver)"
    return arm


def main(argv=None) -> None:
    import pinocchio as pin

    import robokit
    from robokit.ik import ik_analytic, ik_analytic_kind

    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="fewer repetitions")
    ap.add_argument("--only", default=None, help="comma-separated robot names (default: all)")
    args = ap.parse_args(argv)
    reps = 20 if args.quick else 200
    warnings.simplefilter("ignore")
    robots = [robokit.load("puma560"), robokit.load("ur5"), robokit.load(_quartic_arm()), robokit.load("panda"),
              robokit.load(_jaco_table()), robokit.load(_general_arm())]
    if args.only:
        keep = set(args.only.split(","))
        robots = [r for r in robots if r.name in keep]
    rows, irows, grows = [], [], []
    rng = np.random.default_rng(0)
    with tempfile.TemporaryDirectory() as tmp:
        for robot in robots:
            folder = Path(tmp) / robot.name
            folder.mkdir()
            kind = ik_analytic_kind(robot).method
            general = kind == "general 6R"
            c = _c_times(robot, folder, reps, max(1, reps // 50) if general else reps)
            qs = [robot.random_configuration(rng) for _ in range(64)]
            it = iter(qs * 10**6)
            q_pin = [robot.q_pin(q) for q in qs]
            itp = iter(q_pin * 10**6)
            t_pin_fk = time_call(lambda: pin.forwardKinematics(robot.model, robot.data, next(itp)))
            t_frame = time_call(lambda: robot.frame_pose(next(it)))
            v = np.zeros(robot.n)
            t_pin_rnea = time_call(lambda: pin.rnea(robot.model, robot.data, next(itp), v, v))
            if kind is not None:
                Ts = iter([robot.frame_pose(q) for q in qs] * 10**6)
                t_py_ik = time_call(lambda: ik_analytic(robot, next(Ts)), repeats=3 if general else 7,
                                    target=0.5 if general else 0.2)
            else:
                t_py_ik = float("nan")
            name = f"{robot.name} ({kind or 'no closed form'})"
            rows.append([name, fmt_time(c["fk"]), fmt_time(t_pin_fk), f"{t_pin_fk / c['fk']:.0f}×",
                         fmt_time(t_frame), fmt_time(c["jacobian"]), fmt_time(c["gravity"]), fmt_time(c["rnea"]),
                         fmt_time(t_pin_rnea), f"{t_pin_rnea / c['rnea']:.0f}×",
                         fmt_time(c["ik"]) if "ik" in c else "—",
                         f"{c['solutions']:.2f}" if "solutions" in c else "—",
                         fmt_time(t_py_ik) if kind else "—",
                         f"{t_py_ik / c['ik']:.0f}×" if "ik" in c else "—"])
            if general:
                eaik = _eaik_ik(robot)
                if isinstance(eaik, str):
                    t_eaik = eaik
                else:
                    Te = iter([np.ascontiguousarray(robot.frame_pose(q)) for q in qs] * 10**6)
                    t_eaik = fmt_time(time_call(lambda: eaik.IK(next(Te))))
                grows.append([robot.name, fmt_time(c["ik"]), f"{c['solutions']:.2f}", fmt_time(t_py_ik),
                              f"{t_py_ik / c['ik']:.0f}×", t_eaik,
                              f"{c['ir_ik_ex']:,.0f}" if "ir_ik_ex" in c else "—"])
            if any(k.startswith("ir_") for k in c):
                irows.append([robot.name] + [f"{c[k]:,.0f}" if k in c else "—"
                                             for k in ("ir_fk", "ir_jacobian", "ir_gravity", "ir_rnea", "ir_ik_ex")])
    print("## Generated C (robokit codegen), per call — machine shared with other jobs (under load)")
    print()
    print(machine() + "; C: gcc -O2, driver timing 256 inputs × reps; C and Python: fastest of 7 batches")
    print()
    print(table(["robot", "C fk", "pin.forwardKinematics (Python)", "ratio", "Robot.frame_pose", "C jacobian",
                 "C gravity", "C rnea", "pin.rnea (Python)", "ratio", "C ik (all)", "solutions/pose",
                 "ik_analytic (Python)", "ratio"], rows))
    if grows:
        print()
        print("General 6R (Raghavan–Roth / Manocha–Canny): every solution of one pose")
        print()
        print(table(["robot", "C ik (all)", "solutions/pose", "ik_analytic (Python)", "ratio", "EAIK (C++)",
                     "C instructions/call"], grows))
    if irows:
        print()
        print("Instructions per call of the generated C (valgrind callgrind, inclusive of libm; independent of "
              "the machine's load):")
        print()
        print(table(["robot", "fk", "jacobian", "gravity", "rnea", "ik (all solutions)"], irows))


if __name__ == "__main__":
    main()
