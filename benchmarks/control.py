"""Control benchmark (issue 8): one PUMA 560 trajectory tracked by each controller, with a perfect
and with a 20 % wrong model, plus simulation speed against modern_robotics.

Table 1: RMS and max tracking error and peak torque, 2 s at 1 kHz control, RK4 plant.
Table 2: wall time of 2 s of PUMA 560 at 1 kHz under computed torque (robokit.simulate), and of
``simulate_control`` (MR semantics) against ``modern_robotics.SimulateControl`` on the same inputs,
with the largest difference of their results. Prints Markdown; asserts nothing.

Run: ``.venv/bin/python -m benchmarks.control [--quick]``
"""
from __future__ import annotations

import argparse
import time

import numpy as np

from benchmarks._harness import fmt_time, machine, table


def _wrong_model(robot, factor=1.2):
    """The same robot with every link's mass and inertia scaled by ``factor`` (a 20 % wrong model)."""
    import dataclasses

    import robokit as rk

    links = tuple(dataclasses.replace(l, mass=l.mass * factor, inertia=np.asarray(l.inertia) * factor)
                  for l in robot.dh.links)
    return rk.load(dataclasses.replace(robot.dh, links=links))


def main(argv=None):
    import robokit as rk
    from robokit.control import ComputedTorque, GravityPD, IndependentJoint, ModelFeedforward, simulate

    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="shorter MR comparison")
    args = ap.parse_args(argv)
    puma = rk.load("puma560")
    wrong = _wrong_model(puma)
    start = np.zeros(6)
    goal = np.array([0.8, -0.5, 0.9, 0.5, 0.6, -0.4])
    dt = 1e-3
    traj = rk.trajectory.quintic_trajectory(start, goal, 2.0, t=np.arange(0.0, 2.0 + dt / 2, dt))
    J_nom = np.diag(puma.crba(start))  # nominal (fixed) inertia per joint: the diagonal of M at the start
    print(f"# Control benchmark\n\nmachine: {machine()}\nPUMA 560, quintic move over 2 s, control at 1 kHz, "
          "RK4 plant (2 substeps), rigid-body model only (no motor inertia or friction); PD gains scaled by the "
          "nominal joint inertia diag M(q₀)\n")
    rows = []
    for label, model in (("perfect model", puma), ("20 % wrong model", wrong)):
        controllers = {
            "independent joint PI + gravity ff": IndependentJoint(6, Kp=20.0, Kv=60.0, Ki=300.0, J_nom=J_nom,
                                                                   gravity=model),
            "PD + gravity compensation": GravityPD(model, Kp=J_nom * 400.0, Kv=J_nom * 40.0),
            "model feedforward + PD": ModelFeedforward(model, Kp=J_nom * 400.0, Kv=J_nom * 40.0),
            "computed torque (Kv = 2√Kp)": ComputedTorque(model, Kp=400.0),
            "computed torque PID": ComputedTorque(model, Kp=400.0, Kv=40.0, Ki=1000.0),
        }
        for name, ctrl in controllers.items():
            res = simulate(puma, ctrl, traj, substeps=2, motor_inertia=False)
            e = np.abs(res.error)
            rows.append([label, name, f"{np.sqrt(np.mean(res.error ** 2)):.2e}", f"{e.max():.2e}",
                         f"{np.abs(res.tau).max():.1f}"])
    print(table(["model", "controller", "RMS error [rad]", "max error [rad]", "peak torque [N·m]"], rows))

    # speed: 2 s of PUMA at 1 kHz under computed torque, RK4
    ctrl = ComputedTorque(puma, Kp=400.0)
    t0 = time.perf_counter()
    simulate(puma, ctrl, traj)
    t_sim = time.perf_counter() - t0
    speed = [["robokit.simulate, computed torque, RK4, 2 s @ 1 kHz", fmt_time(t_sim), "", ""]]
    try:
        import matplotlib

        matplotlib.use("Agg")
        import modern_robotics as mr
    except ImportError:  # pragma: no cover
        mr = None
    p = puma.poe
    N = 50 if args.quick else 200
    h = 0.01
    tt = np.arange(N) * h
    qd = np.outer(np.sin(tt), goal)
    dqd = np.outer(np.cos(tt), goal)
    ddqd = -qd
    inputs = (np.zeros(6), goal.copy(), puma.gravity, np.zeros((N, 6)), p.Mlist, p.Glist, p.Slist, qd, dqd, ddqd,
              puma.gravity, p.Mlist, np.array(p.Glist) * 1.2, 20.0, 10.0, 18.0, h, 2)
    t0 = time.perf_counter()
    tau_rk, th_rk = rk.simulate_control(*inputs)
    t_rk = time.perf_counter() - t0
    if mr is not None:
        import matplotlib.pyplot as plt

        mr_inputs = list(inputs)
        mr_inputs[4], mr_inputs[5], mr_inputs[11], mr_inputs[12] = (list(p.Mlist), list(p.Glist), list(p.Mlist),
                                                                    list(np.array(p.Glist) * 1.2))
        t0 = time.perf_counter()
        tau_mr, th_mr = mr.SimulateControl(*mr_inputs)
        t_mr = time.perf_counter() - t0
        plt.close("all")
        diff = max(np.abs(th_rk - th_mr).max(), np.abs(tau_rk - tau_mr).max())
        speed.append([f"simulate_control, {N} steps × 2 (6 joints)", fmt_time(t_rk), fmt_time(t_mr),
                      f"{t_mr / t_rk:.1f}× faster, max |Δ| = {diff:.1e}"])
    else:
        speed.append([f"simulate_control, {N} steps × 2 (6 joints)", fmt_time(t_rk), "not installed", ""])
    print()
    print(table(["simulation", "robokit", "modern_robotics", "ratio"], speed))


if __name__ == "__main__":
    main()
