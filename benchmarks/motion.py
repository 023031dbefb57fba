"""Collision and motion benchmark (issue 34): World queries against python-fcl on the same geometry,
and the wall time of retime and plan.

Table 1: time per configuration of ``World.in_collision`` and ``World.distance`` (coal through
Pinocchio, all checked pairs) against python-fcl doing the same pairs (objects placed with Pinocchio's
FK, a Python loop over pairs, early exit on the first collision like ``in_collision``), measured in the
same run on the same random configurations. Table 2: the robot's collision meshes against their
convex hulls (``World(..., convex=True)``) on the same configurations: time per call, the speed-up,
and how much more often the (conservative) hulls report a collision; and a small collision-free
capability map (serial) with each. Table 3: wall time of ``retime`` (3 waypoints, 200 stages; with
and without torque limits) and ``plan`` (PUMA around a wall). Prints Markdown; asserts nothing.

Run: ``.venv/bin/python -m benchmarks.motion [--quick]``
"""
from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import numpy as np

from benchmarks._harness import fmt_time, machine, table


def main(argv=None):
    import robokit as rk
    from robokit.collision import Box, World

    sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests" / "collision"))
    from _fcl_ref import FclWorld

    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="fewer configurations")
    args = ap.parse_args(argv)
    print(f"# Collision and motion benchmark\n\nmachine: {machine()}\n")
    N = 50 if args.quick else 300
    T = np.eye(4)
    T[:3, 3] = [0.45, 0.35, 0.4]
    rows = []
    for name in ("puma560", "ur5", "panda"):
        r = rk.load(name)
        w = World(r, [Box([0.4, 0.05, 0.8], T, name="wall")])
        ref = FclWorld(w)
        rng = np.random.default_rng(0)
        qs = [r.random_configuration(rng) for _ in range(N)]
        t0 = time.perf_counter()
        for q in qs:
            w.in_collision(q)
        t_col = (time.perf_counter() - t0) / N
        t0 = time.perf_counter()
        for q in qs:
            w.distance(q)
        t_dist = (time.perf_counter() - t0) / N
        t0 = time.perf_counter()
        for q in qs:
            ref.pair_distances(q)
        t_fcl = (time.perf_counter() - t0) / N  # collide + distance per pair
        rows.append([name, len(w._pairs), w.self_pairs.geometry, fmt_time(t_col), fmt_time(t_dist),
                     fmt_time(t_fcl), f"{t_fcl / t_dist:.1f}×"])
    print(table(["robot", "pairs", "robot geometry", "in_collision", "distance", "python-fcl collide+distance",
                 "fcl / distance"], rows))
    print()
    rows = []
    for name in ("ur5", "panda"):
        r = rk.load(name)
        obstacles = [Box([0.4, 0.05, 0.8], T, name="wall")]
        worlds = {"meshes": World(r, obstacles), "convex hulls": World(r, obstacles, convex=True)}
        rng = np.random.default_rng(1)
        qs = np.array([r.random_configuration(rng) for _ in range(N)])
        got = {}
        for label, w in worlds.items():
            t0 = time.perf_counter()
            hits = w.in_collision(qs)
            t_col = (time.perf_counter() - t0) / N
            t0 = time.perf_counter()
            d = w.distance(qs)
            t_dist = (time.perf_counter() - t0) / N
            got[label] = (t_col, t_dist, hits, d)
        (mc, md, mh, mdist), (hc, hd, hh, hdist) = got["meshes"], got["convex hulls"]
        assert not np.any(mh & ~hh) and np.all(hdist <= mdist + 1e-9)  # conservative, as documented
        rows.append([name, fmt_time(mc), fmt_time(hc), f"{mc / hc:.1f}×", fmt_time(md), fmt_time(hd),
                     f"{md / hd:.1f}×", f"{mh.mean():.0%}", f"{hh.mean():.0%}"])
    print(table(["robot", "in_collision meshes", "hulls", "speed-up", "distance meshes", "hulls", "speed-up",
                 "in collision (meshes)", "in collision (hulls)"], rows))
    print()
    r = rk.load("ur5")
    floor = Box([3.0, 3.0, 0.1], np.diag([1.0, 1.0, 1.0, 1.0]) @ _translation([0, 0, -0.1]), name="floor")
    kw = dict(orientations=4 if args.quick else 8, client="serial", samples=20000)
    rk.capability_map(r, 0.5, **kw)  # warm-up: compiled IK kernels
    rows = []
    base = None
    for label, world in (("no world", None), ("meshes", World(r, [floor])), ("convex hulls", World(r, [floor], convex=True))):
        t0 = time.perf_counter()
        cmap = rk.capability_map(r, 0.3 if not args.quick else 0.5, world=world, **kw)
        dt = time.perf_counter() - t0
        base = dt if base is None else base
        rows.append([label, len(cmap.centres), f"{cmap.index.sum() * len(cmap.orientations):.0f}", f"{dt:.2f} s",
                     f"{dt / base:.1f}×"])
    print(table(["UR5 capability map (floor)", "voxels", "poses reached", "wall time", "vs no world"], rows))
    print()
    r = rk.load("puma560")
    P = np.array([[0, 0, 0, 0, 0, 0], [1, 0.5, -0.5, 0, 0.3, 0], [1.5, -0.2, 0.3, 1, 0, 0.5]], float)
    rk.retime(r, P, 1.0, 2.0, tau_max=[100, 150, 60, 10, 10, 10])  # warm-up (imports, compiled kernels)
    rows = []
    for label, kw in (("retime, v/a limits", {}), ("retime, v/a/torque limits", {"tau_max": [100, 150, 60, 10, 10, 10]})):
        t0 = time.perf_counter()
        tr = rk.retime(r, P, 1.0, 2.0, **kw)
        rows.append([label, fmt_time(time.perf_counter() - t0), f"{tr.t[-1]:.3f} s"])
    w = World(r, [Box([0.4, 0.05, 0.8], T, name="wall")])
    t0 = time.perf_counter()
    tr = rk.plan(r, [0, 0.3, -0.3, 0, 0, 0], [1.4, 0.3, -0.3, 0, 0, 0], w)
    rows.append(["plan PUMA around a wall", fmt_time(time.perf_counter() - t0), f"{tr.t[-1]:.3f} s"])
    print(table(["call", "wall time", "trajectory duration"], rows))


def _translation(xyz):
    T = np.eye(4)
    T[:3, 3] = xyz
    return T


if __name__ == "__main__":
    main()
