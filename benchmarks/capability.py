"""Capability-map benchmark: IK problems per second per core, Dask scaling, a UR5 map's cost.

1. Per-core rate: the voxels of the UR5 and Panda 5 cm grids (after the pre-pass) are
   shuffled with a fixed seed and the first ``--voxels`` of them get the full sweep of
   ``--orientations`` tool orientations in this process (``client="serial"``): the problems are
   drawn from the same mix of reachable and unreachable poses as the whole map.
2. Scaling: the same chunks on a ``LocalCluster`` of one worker process, then of two
   (``threads_per_worker=1``); the speed-up is the ratio of the wall times (the cluster's
   start-up is excluded; each worker's first chunk pays its imports and robot build).
3. The UR5 map at 5 cm with 100 orientations: run in full with ``--full``; otherwise its time
   on 2 cores is extrapolated from the measured rate and the map's size (said in the table).
4. Projection for a 10⁸-problem map on N workers from the measured per-core rate.

Peak memory: tracemalloc's peak while one chunk is computed (measured apart from the
timing, which tracemalloc would slow down), and the process's maximum resident set size. Prints Markdown tables naming the machine; asserts nothing.

Run: ``.venv/bin/python -m benchmarks.capability [--quick] [--full]``
"""
from __future__ import annotations

import argparse
import os
import resource
import time
import tracemalloc

import numpy as np

from benchmarks._harness import machine, table


def _grid(robot, res, seed=0):
    from robokit.workspace.grid import reachable_voxels

    keys, _ = reachable_voxels(robot, res, seed=seed)
    return keys.astype(float) * res


def _rate(robot_name, res, K, n_voxels, chunk):
    """Serial sweep of n_voxels random voxels of the grid: (problems/s, seconds, M of the grid, backend, peak bytes)."""
    import robokit
    from robokit.workspace.capability import _chunk_counts, _describe
    from robokit.workspace.orientations import super_fibonacci_rotations
    from robokit.workspace.reach import ik_backend

    robot = robokit.load(robot_name)
    centres = _grid(robot, res)
    rng = np.random.default_rng(0)
    pick = centres[rng.permutation(len(centres))[:n_voxels]]
    R = super_fibonacci_rotations(K)
    desc = _describe(robot_name, robot)
    _chunk_counts(desc, pick[:1], R[:2], 20, 0, 0)  # build the robot and back end outside the timing
    t0 = time.perf_counter()
    hits = 0
    for c in range(0, len(pick), chunk):
        hits += int(_chunk_counts(desc, pick[c:c + chunk], R, 20, 0, c // chunk).sum())
    dt = time.perf_counter() - t0
    # peak memory of one chunk, measured apart: tracemalloc slows Python code several-fold
    tracemalloc.start()
    _chunk_counts(desc, pick[:chunk], R, 20, 0, 0)
    peak = tracemalloc.get_traced_memory()[1]
    tracemalloc.stop()
    problems = len(pick) * K
    return dict(robot=robot_name, backend=ik_backend(robot), M=len(centres), problems=problems, seconds=dt,
                rate=problems / dt, reached=hits / problems, peak=peak, pick=pick, R=R, desc=desc)


def _cluster_time(run, workers, chunk):
    import logging

    from distributed import Client, LocalCluster

    from robokit.workspace.capability import _chunk_counts

    with LocalCluster(n_workers=workers, threads_per_worker=1, processes=True, dashboard_address=None,
                      silence_logs=logging.ERROR) as lc, Client(lc) as client:
        # warm every worker up (imports, robot and IK back end built) before timing
        client.run(_chunk_counts, run["desc"], run["pick"][:1], run["R"][:1], 20, 0, 0)
        t0 = time.perf_counter()
        futs = [client.submit(_chunk_counts, run["desc"], run["pick"][c:c + chunk], run["R"], 20, 0, c // chunk,
                              pure=False) for c in range(0, len(run["pick"]), chunk)]
        client.gather(futs)
        return time.perf_counter() - t0


def main(argv=None):
    ap = argparse.ArgumentParser(prog="benchmarks.capability")
    ap.add_argument("--quick", action="store_true", help="fewer voxels (a rough figure in a few seconds)")
    ap.add_argument("--full", action="store_true", help="also compute the whole UR5 5 cm / 100-orientation map on 2 workers")
    ap.add_argument("--voxels", type=int, default=None, help="voxels swept per robot (default 12, --quick 3)")
    ap.add_argument("--orientations", type=int, default=100)
    args = ap.parse_args(argv)
    nvox = args.voxels or (3 if args.quick else 12)
    K, res = args.orientations, 0.05
    print(f"## Capability maps — {machine()}\n")
    print(f"Per-core rate: {nvox} random voxels of the {res * 100:.0f} cm grid × {K} orientations, in one process; "
          "numeric IK: 20 restarts per target.\n")
    runs = [_rate(name, res, K, nvox, chunk=2) for name in ("ur5", "panda")]
    print(table(["robot", "IK back end", "voxels in the 5 cm grid", "problems timed", "reached", "seconds",
                 "problems / s / core", "peak per chunk (tracemalloc)"],
                [[r["robot"], r["backend"], r["M"], r["problems"], f"{100 * r['reached']:.1f} %", f"{r['seconds']:.1f}",
                  f"{r['rate']:.0f}", f"{r['peak'] / 1e6:.1f} MB"] for r in runs]))
    ur5 = runs[0]

    print("\nScaling on a LocalCluster (the UR5 chunks above, 2 voxels per task):\n")
    t1 = _cluster_time(ur5, 1, 2)
    t2 = _cluster_time(ur5, 2, 2)
    print(table(["workers", "seconds", "speed-up"], [[1, f"{t1:.2f}", "1.00×"], [2, f"{t2:.2f}", f"{t1 / t2:.2f}×"]]))
    print(f"\n(The machine's {os.cpu_count()} cores are shared with other jobs: the speed-up is measured, not ideal.)")

    problems = ur5["M"] * K
    rows = []
    if args.full:
        import robokit

        tracemalloc.start()
        t0 = time.perf_counter()
        cmap = robokit.capability_map("ur5", res, orientations=K, client=None, progress=False)
        dt = time.perf_counter() - t0
        peak = tracemalloc.get_traced_memory()[1]
        tracemalloc.stop()
        rows.append(["ur5, measured (LocalCluster, 2 workers)", len(cmap.centres), problems, f"{dt:.0f} s",
                     f"{peak / 1e6:.0f} MB", f"{len(cmap.dexterous)}"])
    est = problems / (ur5["rate"] * min(2, os.cpu_count() or 1) * min(1.0, (t1 / t2) / 2))
    rows.append(["ur5, extrapolated from the measured rate and 2-worker speed-up", ur5["M"], problems,
                 f"{est:.0f} s ({est / 3600:.2f} h)", "as above (chunk-bounded)", "n/a"])
    print(f"\nUR5 map at {res * 100:.0f} cm with {K} orientations:\n")
    print(table(["run", "voxels", "IK problems", "time on 2 cores", "driver peak", "dexterous voxels"], rows))

    print(f"\nProjection for a 10⁸-problem map at {ur5['rate']:.0f} problems/s/core (UR5, {ur5['backend']} IK), "
          "assuming linear scaling:\n")
    print(table(["workers N", "hours"], [[n, f"{1e8 / (ur5['rate'] * n) / 3600:.2f}"] for n in (2, 16, 64, 256, 1024)]))
    print(f"\nProcess max RSS: {resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024:.0f} MB")


if __name__ == "__main__":
    main()
