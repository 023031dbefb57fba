"""``make test``'s warm-up: every compiled kernel the test suite runs, compiled into numba's on-disk
cache before pytest starts, in one process per core, each compiling different kernels.

Two kinds of kernels:

* the course kernels with a declared signature, exactly what ``python -m robokit.kernels`` compiles
  (:func:`robokit.kernels.warm.kernels`, one job each);
* the analytic-IK kernels (robokit/kernels/closed_form.py, general_6r.py, calibrated_ik.py), which
  have no declared signature: numba compiles them for the argument types of their first call. They
  are compiled here by what the suite itself calls, through robokit's public API (a solve and a batch
  solve of each method on a robot of that kind), so the types compiled are the ones the wrappers
  pass — ``solve_into_entry``/``machine_code`` then find the machine code the tests use. These need
  robots (and a calibrated robot from robokit.calibration), which the kernels layer may not import:
  hence this script, outside the package.

Without it, on a cold cache, both pytest workers compile the same analytic-IK kernels at the same
time in their first tests (75-160 s each). The IK jobs are submitted first (the longest), then the
course kernels fill the other core. Each job's result is only the cache it writes: the solves' own
answers are checked by the tests, not here. A job that fails fails the warm-up (and ``make test``):
a kernel that does not compile here would not compile in the tests either.

Run: ``python .ci/warm_kernels.py [--jobs J]`` (default: one process per core).
"""
from __future__ import annotations

import argparse
import multiprocessing
import os
import sys
import time
from concurrent.futures import ProcessPoolExecutor, as_completed

POSE_Q = (0.3, -0.5, 0.4, 0.2, 0.6, -0.1)


def _solve_each_way(robot, method: str):
    """One pose through ``ik_analytic`` (the single-pose kernel), two through ``solve_batch`` (the
    parallel batch kernel) and, for a closed form, one through its Python solver's compiled rows,
    after checking the robot got the method meant; returns the robot's ``AnalyticIK``."""
    import numpy as np

    from robokit.ik import ik_analytic
    from robokit.ik.closed_form import analytic_ik

    ik = analytic_ik(robot)
    if ik.method != method:
        raise RuntimeError(f"warm-up: {robot.name} is solved by {ik.method!r}, not {method!r}")
    T = robot.frame_pose(np.array(POSE_Q))
    ik_analytic(robot, T)
    ik.solve(T)
    ik.solve_batch(np.stack([T, robot.frame_pose(np.array(POSE_Q) * 0.5)]))
    if ik.calibrated is None and ik.solver is not None and hasattr(ik.solver, "joint_angles"):
        ik.solver.joint_angles(ik.chain.target_06(T), 0.0)  # the Python solver's path (pieper_rows, ...)
    return ik


def _closed_form() -> None:
    import robokit

    _solve_each_way(robokit.load("puma560"), "spherical wrist")
    _solve_each_way(robokit.load("ur5"), "three parallel axes")


def _general_6r() -> None:
    import math

    import numpy as np

    import robokit
    from robokit.description.dh import DHLink, DHTable

    # an offset wrist (axes 4-6 do not meet) and no two parallel axes: neither closed form applies
    alpha = [math.pi / 2, math.pi, math.pi / 2, 1.0472, 1.0472, math.pi]
    a = [0.0, 0.41, 0.0, 0.0, 0.0, 0.0]
    d = [0.2755, 0.0, -0.0098, -0.25, -0.086, -0.203]
    wide = np.array([-2 * np.pi, 2 * np.pi])
    table = DHTable("warm_6r", "standard", tuple(DHLink("R", a=a[i], alpha=alpha[i], d=d[i], qlim=wide)
                                                  for i in range(6)))
    _solve_each_way(robokit.load(table), "general 6R")


def _calibrated(name: str, method: str) -> None:
    import numpy as np

    import robokit
    from robokit.calibration import chain_from_robot, robot_from_chain

    from robokit.kernels import calibrated_ik as kci

    robot = robokit.load(name)
    delta = np.random.default_rng(1).uniform(-1e-3, 1e-3, (7, 6))
    arm = _solve_each_way(robot_from_chain(robot, chain_from_robot(robot).perturbed(delta)), method).calibrated
    # the packed chain's pose and Jacobian on their own (tests/calibration/test_calibrated_chain.py)
    C = kci.pack_arm(arm.M, arm.Slist, np.zeros((5, 6)), np.zeros(3), 1.0, 1e-12, 1e-10, 30)
    sc, T, J = np.empty((2, 6)), np.empty((4, 4)), np.empty((6, 6))
    kci._trig(C, np.array(POSE_Q), sc)
    kci.fk_jacobian(C, np.array(POSE_Q), sc, T, J)


def _calibrated_both() -> None:
    """Both calibrated structures in one process, one after the other: their kernels are the same
    machine code (the method is an argument), so the second finds the first's in the cache — measured
    on a cold cache, idle 2-core AMD EPYC VM: 230.7 s for the PUMA 560's, then 1.1 s for the UR5's.
    As two jobs on the two cores they compiled the same kernels twice at the same time (213 and 151 s
    in a CI rehearsal), the longest jobs of the warm-up."""
    _calibrated("puma560", "calibrated spherical wrist")
    _calibrated("ur5", "calibrated three parallel axes")


#: name -> function of the analytic-IK jobs (module-level functions: the pool pickles them by name),
#: the longest first.
IK_JOBS = {
    "calibrated IK (spherical wrist, three parallel axes)": (_calibrated_both, ()),
    "general 6R IK": (_general_6r, ()),
    "closed-form IK": (_closed_form, ()),
}


def _run_ik(name: str) -> tuple[str, float]:
    os.environ.setdefault("ROBOKIT_COMPILE", "wait")  # as the test suite (tests/conftest.py): compile here
    from robokit.kernels import _jit

    _jit.quiet = True
    t0 = time.perf_counter()
    func, args = IK_JOBS[name]
    func(*args)
    return name, time.perf_counter() - t0


def _run_kernel(item: tuple[str, str]) -> tuple[str, float]:
    from robokit.kernels.warm import _compile_one

    module, name, seconds = _compile_one(item)
    return f"{module}.{name}", seconds


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(prog="python .ci/warm_kernels.py", description=__doc__.splitlines()[0])
    ap.add_argument("--jobs", type=int, default=None, help="worker processes (default: one per core)")
    args = ap.parse_args(argv)
    from robokit.kernels.warm import kernels

    items = kernels()
    total = len(IK_JOBS) + len(items)
    jobs = max(1, args.jobs or os.cpu_count() or 1)
    t0 = time.perf_counter()
    ctx = multiprocessing.get_context("spawn")  # fresh interpreters: no numba state inherited
    with ProcessPoolExecutor(jobs, mp_context=ctx) as pool:
        futures = [pool.submit(_run_ik, name) for name in IK_JOBS]
        futures += [pool.submit(_run_kernel, item) for item in items]
        for k, fut in enumerate(as_completed(futures), 1):
            name, seconds = fut.result()
            print(f"compiling kernels ({k}/{total}: {name}, {seconds:.1f} s)", file=sys.stderr, flush=True)
    print(f"{total} kernel jobs ready in {time.perf_counter() - t0:.1f} s", file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main())
