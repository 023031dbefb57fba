"""Which damping law for robokit's Levenberg–Marquardt IK (issue 41): success rate and iterations.

robokit had two: ``ik/lm.py`` used Sugihara's error-dependent damping ``λ = λ₀‖e‖² + λ_min``
(Sugihara 2011, with one heavier retry ``10(λ + 10⁻⁶)`` after a rejected step and a stop after
three rejections), ``kernels/ik.py`` Marquardt's adaptive one (``λ ← λ/3`` after an accepted step,
``λ ← 10λ`` after a rejected one, from ``λ = 10⁻³``). Both laws run here in the same loop (the
compiled kernel's: body-twist error, Cholesky solve of the damped normal equations, projection
on the joint limits), from the same random starts to the same random reachable targets, one
attempt each (no restarts), 30 iterations at most, tolerance 1e-10 (rad and m). "Hard" starts:
uniform in the limits (far from the target); "near-singular" targets: a wrist or elbow angle
within 1e-3 rad of a singularity (θ₅ = 0 for the UR5 and the PUMA, θ₄ = 0 for the Panda).
"Iterations per solved target" divides every iteration spent (failed attempts included) by the
number of targets solved: the cost of one solution when failed attempts are restarted.

Prints Markdown; asserts nothing. Run: ``.venv/bin/python -m benchmarks.lm_damping [--quick]``
"""
from __future__ import annotations

import argparse
import math

import numpy as np
from numba import njit

from benchmarks._harness import machine, table


def _loop(law: int):
    from robokit.kernels.dynamics import cholesky_solve
    from robokit.kernels.ik import clamp, fk_and_body_jacobian, normal_equations, pose_error
    from robokit.kernels.poe import fkin_space_into

    @njit
    def run(M, Slist, Td, q0, qlim, tol, max_iterations, lam0, lam_min):
        n = Slist.shape[1]
        T = np.empty((4, 4))
        W = np.empty((6, 4, 4))
        Jb, Js = np.empty((6, n)), np.empty((6, n))
        V, V_trial, w3 = np.empty(6), np.empty(6), np.empty(3)
        H, L = np.empty((n, n)), np.zeros((n, n))
        g, step = np.empty(n), np.empty(n)
        theta = q0.copy()
        trial = np.empty(n)
        fk_and_body_jacobian(M, Slist, theta, T, Jb, Js, W[0], W[1], W[2], W[3])
        E, rot_err, pos_err = pose_error(T, Td, W[3], W[4], V, w3)
        lam = 1e-3
        stall = 0
        it = 0
        while it < max_iterations:
            if rot_err < tol and pos_err < tol:
                return True, it
            it += 1
            normal_equations(Jb, V, H, g)
            tries = 2 if law == 1 else 1
            accepted = False
            for attempt in range(tries):
                if law == 1:
                    lam = lam0 * 2.0 * E + lam_min if attempt == 0 else 10.0 * (lam + 1e-6)
                for i in range(n):
                    H[i, i] += lam
                ok = cholesky_solve(H, g, L, step)
                for i in range(n):
                    H[i, i] -= lam
                if not ok:
                    continue
                for i in range(n):
                    trial[i] = theta[i] + step[i]
                clamp(trial, qlim)
                fkin_space_into(M, Slist, trial, W[5], W[1], W[2])
                E_new, rot_new, pos_new = pose_error(W[5], Td, W[3], W[4], V_trial, w3)
                if E_new < E:
                    theta[:] = trial
                    fk_and_body_jacobian(M, Slist, theta, T, Jb, Js, W[0], W[1], W[2], W[3])
                    V[:] = V_trial
                    E, rot_err, pos_err = E_new, rot_new, pos_new
                    accepted = True
                    break
            if law == 0:
                if accepted:
                    lam = max(lam / 3.0, 1e-12)
                else:
                    lam *= 10.0
                    if lam > 1e8:
                        break
            elif accepted and attempt == 0:
                stall = 0
            else:
                stall += 1
                if stall >= 3:
                    break
        return rot_err < tol and pos_err < tol, it

    return run


def _cases(name: str, count: int, near_singular: bool, rng: np.random.Generator):
    import robokit as rk

    robot = rk.load(name)
    qlim = np.ascontiguousarray(robot.qlim, dtype=float)
    lo = np.where(np.isfinite(qlim[:, 0]), qlim[:, 0], -np.pi)
    hi = np.where(np.isfinite(qlim[:, 1]), qlim[:, 1], np.pi)
    wrist = 3 if robot.n == 7 else 4
    out = []
    for _ in range(count):
        q = rng.uniform(lo, hi)
        if near_singular:
            q[wrist] = float(np.clip(rng.uniform(-1e-3, 1e-3), lo[wrist], hi[wrist]))
        out.append((robot.frame_pose(q), rng.uniform(lo, hi)))
    p = robot.poe
    return np.array(p.M), np.array(p.Slist), qlim, out  # writeable copies, as the kernels take them


def main(argv: list[str] | None = None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="fewer targets")
    args = ap.parse_args(argv)
    count = 100 if args.quick else 400
    laws = {"Marquardt λ/3, 10λ (kernels/ik.py before)": _loop(0), "Sugihara λ₀‖e‖² + λ_min (ik/lm.py)": _loop(1)}
    rows = []
    for name in ("ur5", "puma560", "panda"):
        for near in (False, True):
            M, S, qlim, cases = _cases(name, count, near, np.random.default_rng(7))
            for label, run in laws.items():
                wins, its, spent = 0, [], 0
                for Td, q0 in cases:
                    ok, it = run(M, S, np.ascontiguousarray(Td), q0, qlim, 1e-10, 30, 1e-2, 1e-9)
                    spent += it
                    if ok:
                        wins += 1
                        its.append(it)
                rows.append([name, "near-singular" if near else "random", label, f"{100.0 * wins / len(cases):.1f} %",
                             f"{np.mean(its):.1f}" if its else "-", f"{spent / max(wins, 1):.1f}"])
    print(f"# LM damping laws: one attempt from a random start, 30 iterations, tol 1e-10 ({machine()})\n")
    print(table(["robot", "targets", "law", "success", "mean iterations (successes)", "iterations per solved target (all attempts)"], rows))


if __name__ == "__main__":
    main()
