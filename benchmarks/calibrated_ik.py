"""Exact IK of calibrated arms (issue 43): the polished closed form against the nominal closed form and
the general 6R method, in Python and in the generated C, measured in the same run.

Arms: the PUMA 560, the UR5 and a random Pieper arm, each with every joint placement, the base and the
tool off by up to 2 mrad / 2 mm (built as ``robokit.calibrate`` builds its result), and — run from a
checkout, whose tests/data holds them — a real UR5e's factory calibration read through Universal Robots'
xacro package (off its nominal by up to 3.5 mrad / 0.68 mm; the nominal: the package's default UR5e). Per arm, on the same
random poses (reachable by construction), time per pose of

* ``ik_analytic`` of the nominal arm (its closed form) on the nominal's poses — the reference;
* ``ik_analytic`` of the calibrated arm (``"calibrated …"``: the projected arm's closed form, then Newton
  on the arm's own product of exponentials);
* ``ik_analytic(..., nominal=False)`` of the calibrated arm (the general 6R method) on fewer poses;
* the generated C (``-O2``) of the nominal and of the calibrated arm (``NAME_ik``), through ctypes.

Per pose: the least CPU time of a few batches (the nominal's and the calibrated arm's batches
alternate, pose by pose: the machine's drifting speed weighs on both alike); the table gives the median over the poses (the common
pose: one start per branch, each finished in 2–3 second-order Newton steps) and the mean (near-singular poses, where
the polish searches for the roots that merge or appear, weigh in), then the percentiles over the poses
(50, 75, 90) of each pose's calibrated / nominal ratio (the two measured back to back) and the share of poses
within 2×. The ratio columns are time / nominal
closed form (Python rows against the Python reference, C rows against the nominal's C). The load average is printed: numbers taken on a shared machine are only
comparable within one run. Prints Markdown; asserts nothing.

Run: ``.venv/bin/python -m benchmarks.calibrated_ik [--quick] [--steady]``; ``--quick --steady`` (40
poses, 5 batches of 100 calls each) measures as docs/performance.md's fifth-session table was measured
(the default's batches of 5 calls are noisier; the machine's own speed can drift between runs, so
compare the ratios of one run).
"""
from __future__ import annotations

import argparse
import os
import tempfile
import time
import warnings

import numpy as np

from benchmarks._harness import fmt_time, machine, table


def _arms(size: float = 2e-3, seed: int = 0):
    """(label, nominal, calibrated) of the PUMA 560, the UR5 and a random Pieper arm, every joint placement,
    the base and the tool off by up to ``size`` (rad, m), drawn from ``default_rng(seed)`` in that order."""
    import robokit as rk
    from robokit.calibration import chain_from_robot, robot_from_chain
    from robokit.description.dh import DHLink, DHTable

    rng = np.random.default_rng(seed)
    rows = [DHLink("R", a=0.2, alpha=1.1, d=0.4), DHLink("R", a=0.5, alpha=-0.6, d=0.1),
            DHLink("R", a=0.1, alpha=1.9, d=-0.05), DHLink("R", a=0.0, alpha=-1.3, d=0.35),
            DHLink("R", a=0.0, alpha=0.9, d=0.0), DHLink("R", a=0.02, alpha=0.0, d=0.12)]
    out = []
    for label, model in (("PUMA 560", "puma560"), ("UR5", "ur5"), ("random Pieper arm", DHTable("pieper", "standard",
                                                                                               tuple(rows)))):
        nominal = rk.load(model)
        delta = rng.uniform(-size, size, (nominal.n + 1, 6))
        out.append((label, nominal, robot_from_chain(nominal, chain_from_robot(nominal).perturbed(delta))))
    return out


def _factory_ur5e():
    """(label, nominal, calibrated): a real UR5e's factory calibration read through Universal Robots'
    xacro package (the test data of tests/calibration/test_factory_calibration.py), and the same package's
    default UR5e; None outside a checkout (no tests/data)."""
    import robokit as rk

    data = os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "tests", "data")
    xacro = os.path.join(data, "ur_description", "urdf", "ur.urdf.xacro")
    calibration = os.path.join(data, "ur_calibration", "ur5e_factory_calibration.yaml")
    if not (os.path.exists(xacro) and os.path.exists(calibration)):
        return None
    args = {"ur_type": "ur5e", "name": "ur"}
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", rk.RobokitWarning)  # (its meshes are not in the test data)
        nominal = rk.load(xacro, xacro_args=args, package_dirs=[data])
        cal = rk.load(xacro, xacro_args={**args, "kinematics_params": calibration}, package_dirs=[data])
    return "UR5e (its factory calibration)", nominal, cal


def _per_pose(fn, poses, rounds, calls=5):
    """(median, mean) over the poses of each pose's time per call (the least of ``rounds`` batches of
    ``calls`` calls, CPU time: less sensitive to other processes on a shared machine than wall time). The median
    is the common pose; the mean includes the poses near a singular one, where the polish searches."""
    for T in poses[:3]:
        fn(T)
    each = []
    for T in poses:
        best = np.inf
        for _ in range(rounds):
            t0 = time.process_time()
            for _ in range(calls):
                fn(T)
            best = min(best, (time.process_time() - t0) / calls)
        each.append(best)
    return float(np.median(each)), float(np.mean(each))


def _paired(fn_a, fn_b, poses_a, poses_b, rounds, calls=5):
    """:func:`_per_pose` of two callables on paired poses, their batches alternating (a, b, a, b, …
    per pose), so that the machine's speed, which drifts on a shared machine, weighs on both alike:
    ((median, mean) of a, (median, mean) of b, each pose's b / a (its two times are taken back to back,
    milliseconds apart, so a drift of the machine's speed during the run cancels in it))."""
    for Ta, Tb in zip(poses_a[:3], poses_b[:3]):
        fn_a(Ta)
        fn_b(Tb)
    each_a, each_b = [], []
    for Ta, Tb in zip(poses_a, poses_b):
        best_a = best_b = np.inf
        for _ in range(rounds):
            for fn, T, which in ((fn_a, Ta, 0), (fn_b, Tb, 1)):
                t0 = time.process_time()
                for _ in range(calls):
                    fn(T)
                t = (time.process_time() - t0) / calls
                if which == 0:
                    best_a = min(best_a, t)
                else:
                    best_b = min(best_b, t)
        each_a.append(best_a)
        each_b.append(best_b)
    return ((float(np.median(each_a)), float(np.mean(each_a))), (float(np.median(each_b)), float(np.mean(each_b))),
            np.array(each_b) / np.array(each_a))


def _c_loop(lib, poses, rounds, float32=False):
    """:func:`_per_pose` of NAME_ik through ctypes."""
    import ctypes

    t = np.float32 if float32 else np.float64
    ct = ctypes.POINTER(ctypes.c_float if float32 else ctypes.c_double)
    f = getattr(lib.lib, f"{lib.name}_ik")
    q = np.zeros(lib.max_solutions * lib.n, t)
    qp = q.ctypes.data_as(ct)
    keep = [np.ascontiguousarray(T.reshape(-1), dtype=t) for T in poses]
    ptrs = [T.ctypes.data_as(ct) for T in keep]
    return _per_pose(lambda p: f(p, qp), ptrs, rounds)


def main(argv=None):
    import robokit as rk
    from robokit.codegen import generate_c
    from robokit.codegen.build import compile_library, find_compiler

    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="fewer poses and rounds")
    ap.add_argument("--steady", action="store_true",
                    help="5 batches of 100 calls per pose (steadier medians on a noisy machine; slower)")
    args = ap.parse_args(argv)
    n_poses, rounds, n_g6r = (40, 2, 3) if args.quick else (200, 5, 10)
    calls = 5
    if args.steady:
        rounds, calls = 5, 100
    print(f"# Calibrated arms: exact IK (issue 43)\n\nmachine: {machine()}; load average "
          f"{os.getloadavg()[0]:.2f} (2 cores shared: compare ratios within this run)\n")
    cc = find_compiler()
    rows = []
    paired: list[list[str]] = []
    warnings.simplefilter("ignore", rk.RobokitWarning)
    factory = _factory_ur5e()
    for label, nominal, cal in _arms() + ([factory] if factory else []):
        rng = np.random.default_rng(1)
        Q = [cal.random_configuration(rng) for _ in range(n_poses)]
        Tn = [nominal.frame_pose(q) for q in Q]
        Tc = [cal.frame_pose(q) for q in Q]
        t_nom, t_cal, per_pose = _paired(lambda T: rk.ik_analytic(nominal, T), lambda T: rk.ik_analytic(cal, T), Tn, Tc,
                               rounds, calls)
        t_g6r = _per_pose(lambda T: rk.ik_analytic(cal, T, nominal=False), Tc[:n_g6r], 1)
        counts = np.mean([len(rk.ik_analytic(cal, T)) for T in Tc])
        kind = rk.ik_analytic_kind(cal).method

        def row(method, note, t, ref):
            rows.append([label, method, note, fmt_time(t[0]), f"{t[0] / ref[0]:.2f}×", fmt_time(t[1]),
                         f"{t[1] / ref[1]:.2f}×"])

        row("Python: nominal closed form", "spherical wrist" if "spherical" in kind else "three parallel axes",
            t_nom, t_nom)
        row(f"Python: {kind}", f"{counts:.2f} solutions/pose", t_cal, t_nom)
        p50, p75, p90 = np.percentile(per_pose, [50, 75, 90])
        paired.append([label, f"{p50:.2f}×", f"{p75:.2f}×", f"{p90:.1f}×", f"{np.mean(per_pose <= 2.0):.0%}"])
        row("Python: general 6R (nominal=False)", f"{n_g6r} poses", t_g6r, t_nom)
        if cc is not None:
            with tempfile.TemporaryDirectory() as tmp:
                ln = compile_library(generate_c(nominal, name="nom"), os.path.join(tmp), nominal.n, compiler=cc)
                os.mkdir(os.path.join(tmp, "cal"))
                lc = compile_library(generate_c(cal, name="cal"), os.path.join(tmp, "cal"), cal.n, compiler=cc)
                c_nom = _c_loop(ln, Tn, rounds)
                c_cal = _c_loop(lc, Tc, rounds)
            row("C -O2: nominal NAME_ik", "", c_nom, c_nom)
            row("C -O2: calibrated NAME_ik", "", c_cal, c_nom)
    print(table(["arm", "method", "", "median per pose", "ratio", "mean per pose", "ratio"], rows))
    print("\nPer pose, calibrated / nominal `ik_analytic` on the same configuration, measured back to back "
          "(a drift of the machine's speed during the run cancels in each pose's ratio); percentiles over the "
          "poses (the tail: poses near a singular configuration, where the search runs) and the share within 2×:\n")
    print(table(["arm", "p50", "p75", "p90", "within 2×"], paired))


if __name__ == "__main__":
    main()
