"""Calibration benchmark (issue 32): the Newton–Euler regressor against Pinocchio's, and the wall time of
the three calibration entry points on a PUMA 560.

Table 1: time per sample of the regressor Y(q, q̇, q̈) (10n columns): robokit's course recursion
(``inertial_regressor``: the compiled kernel of :mod:`robokit.kernels.regressor`, over a batch of N
samples and called once per sample; and the numpy-over-the-batch recursion it replaced) against a
Python loop over ``pinocchio.computeJointTorqueRegressor``, measured in the same run, with their
largest difference.
Table 2: wall time of ``calibrate`` (noiseless poses), ``identify_dynamics`` (random motions) and
``excitation_trajectory`` (a bounded number of evaluations). Prints Markdown; asserts nothing.

Run: ``.venv/bin/python -m benchmarks.calibration [--quick]``
"""
from __future__ import annotations

import argparse
import time

import numpy as np

from benchmarks._harness import fmt_time, machine, table


def main(argv=None):
    import pinocchio as pin

    import robokit as rk
    from robokit.calibration import chain_from_robot, inertial_regressor
    from robokit.calibration.regressor import _inertial_regressor_numpy

    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="fewer samples")
    args = ap.parse_args(argv)
    print(f"# Calibration benchmark\n\nmachine: {machine()}\n")
    rows = []
    rng = np.random.default_rng(0)
    for name in ("puma560", "ur5", "panda"):
        robot = rk.load(name)
        chain = chain_from_robot(robot)
        N = 200 if args.quick else 2000
        q = np.array([robot.random_configuration(rng) for _ in range(N)])
        dq, ddq = rng.standard_normal((2, N, robot.n))
        qp = [robot.q_pin(x) for x in q]
        inertial_regressor(chain, q[:1], dq[:1], ddq[:1], robot.gravity)  # load the kernel
        t0 = time.perf_counter()
        Y = inertial_regressor(chain, q, dq, ddq, robot.gravity)
        t_rk = (time.perf_counter() - t0) / N
        t0 = time.perf_counter()
        for k in range(N):
            inertial_regressor(chain, q[k:k + 1], dq[k:k + 1], ddq[k:k + 1], robot.gravity)
        t_one = (time.perf_counter() - t0) / N
        t0 = time.perf_counter()
        _inertial_regressor_numpy(chain, q, dq, ddq, robot.gravity)
        t_np = (time.perf_counter() - t0) / N
        t0 = time.perf_counter()
        Yp = np.array([pin.computeJointTorqueRegressor(robot.model, robot.data, qp[k], dq[k], ddq[k]).copy()
                       for k in range(N)])
        t_pin = (time.perf_counter() - t0) / N
        rows.append([name, robot.n, N, fmt_time(t_rk), fmt_time(t_one), fmt_time(t_np), fmt_time(t_pin),
                     f"{t_rk / t_pin:.3g}", f"{t_one / t_pin:.3g}", f"{np.abs(Y - Yp).max():.1e}"])
    print("## Regressor per sample\n")
    print(table(["robot", "n", "samples", "robokit (kernel, batch)", "robokit (kernel, one call per sample)",
                 "robokit (numpy over the batch, before)", "Pinocchio (Python loop)", "batch / Pinocchio",
                 "per-sample call / Pinocchio", "max |Δ|"], rows))
    puma = rk.load("puma560")
    rows = []
    for K in ((50,) if args.quick else (50, 200)):
        true = chain_from_robot(puma).perturbed(rng.normal(0, 2e-3, (7, 6)))
        Q = np.array([puma.random_configuration(rng) for _ in range(K)])
        T = true.fk(Q)
        t0 = time.perf_counter()
        res = rk.calibrate(puma, Q, T)
        rows.append([f"calibrate, {K} poses", fmt_time(time.perf_counter() - t0),
                     f"{res.iterations} LM iterations, RMS after {res.rms_after:.1e} m"])
    for N in ((500,) if args.quick else (500, 5000)):
        q = np.array([puma.random_configuration(rng) for _ in range(N)])
        dq, ddq = rng.standard_normal((2, N, 6))
        tau = puma.rnea(q, dq, ddq) + 0.5 * dq
        t0 = time.perf_counter()
        ident = rk.identify_dynamics(puma, q, dq, ddq, tau)
        rows.append([f"identify_dynamics, {N} samples", fmt_time(time.perf_counter() - t0),
                     f"{ident.base.count} base parameters, condition number {ident.condition_number:.3g}"])
        t0 = time.perf_counter()
        rk.identify_dynamics(puma, q, dq, ddq, tau + rng.normal(0, 0.2, tau.shape), physically_consistent=True)
        rows.append([f"identify_dynamics, {N} samples, physically_consistent", fmt_time(time.perf_counter() - t0),
                     ""])
    ev = 100 if args.quick else 300
    t0 = time.perf_counter()
    tr = rk.excitation_trajectory(puma, 10.0, harmonics=5, qd_max=1.5, qdd_max=4.0, max_evaluations=ev)
    rows.append([f"excitation_trajectory, 5 harmonics, {ev} evaluations", fmt_time(time.perf_counter() - t0),
                 f"condition number {tr.info['initial_condition_number']:.3g} → {tr.info['condition_number']:.3g}"])
    print("\n## PUMA 560 wall times\n")
    print(table(["call", "wall time", "result"], rows))


if __name__ == "__main__":
    main()
