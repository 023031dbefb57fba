"""Compiled course kernels against Pinocchio, modern_robotics and roboticstoolbox-python.

Tables (Markdown, printed; nothing is asserted):

1. per call on the UR5 — the seed functions (argument checks + compiled kernel) against
   Pinocchio (forwardKinematics + frame, computeJointJacobians, rnea, crba, aba),
   modern_robotics and roboticstoolbox-python (an ``rtb.ETS`` built from the Pinocchio chain);
2. DH forms on the PUMA 560 — robokit's DH functions against Pinocchio on the generated URDF and
   roboticstoolbox's ``Puma560`` DH model (its C ``rne``);
3. batched, per configuration — the parallel kernels at N = 10², 10³, 10⁴, 10⁵ (10⁶ with
   ``--big``) against a Python loop over Pinocchio and ``pinocchio.rneaInParallel``, for DOF 2
   (twolink), 6 (UR5), 7 (Panda) and a generated 30-joint DH chain, with the growth of the
   process's peak resident memory;
4. IK — the compiled solver against roboticstoolbox's C++ ``ik_LM`` on the same reachable targets
   and initial guesses (UR5, Panda, PUMA 560).

Run: ``python -m benchmarks.kernels [--quick] [--big]``. Every ratio compares numbers measured in
the same run on the same machine (printed at the top).
"""
from __future__ import annotations

import argparse
import resource
import time

import numpy as np

from benchmarks._harness import fmt_time, machine, table, time_call


def _ets_from_robot(robot):
    """An ``rtb.ETS`` of the robot's Pinocchio chain: each joint placement as a static SE3, the joint
    as an elementary rotation/translation about its axis, the tip frame's placement last."""
    import roboticstoolbox as rtb

    model = robot.model
    ets = rtb.ETS()
    for j in range(1, model.njoints):
        ets = ets * rtb.ET.SE3(model.jointPlacements[j].homogeneous)
        jm = model.joints[j]
        name = jm.shortname()
        lim = robot.qlim[j - 1]
        qlim = [max(lim[0], -2 * np.pi), min(lim[1], 2 * np.pi)]
        kind = {"JointModelRX": rtb.ET.Rx, "JointModelRY": rtb.ET.Ry, "JointModelRZ": rtb.ET.Rz,
                "JointModelPX": rtb.ET.tx, "JointModelPY": rtb.ET.ty, "JointModelPZ": rtb.ET.tz}.get(name)
        if kind is None:
            raise NotImplementedError(f"joint type {name} not mapped to an rtb ET")
        ets = ets * kind(qlim=qlim)
    frame = model.frames[robot.tip_id]
    ets = ets * rtb.ET.SE3(frame.placement.homogeneous)
    return ets


def _ratio(a, b):
    return f"{a / b:.2f}×" if np.isfinite(a) and np.isfinite(b) else "n/a"


def per_call(reps):
    import pinocchio as pin

    import robokit as rk

    try:
        import modern_robotics as mr
    except ImportError:  # pragma: no cover
        mr = None
    try:
        ets = _ets_from_robot(rk.load("ur5"))
    except Exception:  # pragma: no cover
        ets = None
    ur5 = rk.load("ur5")
    p = ur5.poe
    model, data = ur5.model, ur5.data
    rng = np.random.default_rng(0)
    q, dq, ddq, tau = (rng.normal(size=6) for _ in range(4))
    g, z6 = ur5.gravity, np.zeros(6)
    Ml, Gl = list(p.Mlist), list(p.Glist)
    rk.fkin_space(p.M, p.Slist, q)  # load the kernels (and compile them on a cold cache)
    rk.inverse_dynamics(q, dq, ddq, g, z6, p.Mlist, p.Glist, p.Slist)

    def pin_fk():
        pin.forwardKinematics(model, data, q)
        pin.updateFramePlacement(model, data, ur5.tip_id)

    cases = [
        ("fkin_space", lambda: rk.fkin_space(p.M, p.Slist, q), pin_fk,
         (lambda: mr.FKinSpace(p.M, p.Slist, q)) if mr else None, (lambda: ets.fkine(q)) if ets else None),
        ("jacobian_space", lambda: rk.jacobian_space(p.Slist, q), lambda: pin.computeJointJacobians(model, data, q),
         (lambda: mr.JacobianSpace(p.Slist, q)) if mr else None, (lambda: ets.jacob0(q)) if ets else None),
        ("inverse_dynamics", lambda: rk.inverse_dynamics(q, dq, ddq, g, z6, p.Mlist, p.Glist, p.Slist),
         lambda: pin.rnea(model, data, q, dq, ddq),
         (lambda: mr.InverseDynamics(q, dq, ddq, g, z6, Ml, Gl, p.Slist)) if mr else None, None),
        ("mass_matrix", lambda: rk.mass_matrix(q, p.Mlist, p.Glist, p.Slist), lambda: pin.crba(model, data, q),
         (lambda: mr.MassMatrix(q, Ml, Gl, p.Slist)) if mr else None, None),
        ("forward_dynamics", lambda: rk.forward_dynamics(q, dq, tau, g, z6, p.Mlist, p.Glist, p.Slist),
         lambda: pin.aba(model, data, q, dq, tau),
         (lambda: mr.ForwardDynamics(q, dq, tau, g, z6, Ml, Gl, p.Slist)) if mr else None, None),
    ]
    rows = []
    for name, ours, pino, mrf, rtbf in cases:
        t_pin = time_call(pino, repeats=reps)
        t_ours = time_call(ours, repeats=reps)
        t_mr = time_call(mrf, repeats=reps, target=0.1) if mrf else float("nan")
        t_rtb = time_call(rtbf, repeats=reps) if rtbf else float("nan")
        rows.append([name, fmt_time(t_ours), fmt_time(t_pin), _ratio(t_ours, t_pin), fmt_time(t_mr),
                     _ratio(t_mr, t_ours), fmt_time(t_rtb), _ratio(t_rtb, t_ours)])
    print("\n## 1. Per call, UR5 (seed functions: checks + compiled kernel)\n")
    print(table(["function", "robokit", "Pinocchio", "robokit / Pinocchio", "modern_robotics",
                 "MR / robokit", "rtb (ETS)", "rtb / robokit"], rows))


def dh_forms(reps):
    import pinocchio as pin

    import robokit as rk
    from robokit.dynamics import dh_inverse_dynamics
    from robokit.kinematics import dh_jacobian, dh_static_torques

    r = rk.load("puma560")
    model, data = r.model, r.data
    rng = np.random.default_rng(1)
    q, dq, ddq, F = r.random_configuration(rng), rng.normal(size=6), rng.normal(size=6), rng.normal(size=6)
    g = r.gravity
    try:
        import roboticstoolbox as rtb

        puma = rtb.models.DH.Puma560()
    except Exception:  # pragma: no cover
        puma = None
    dh_jacobian(r.dh, q)
    dh_inverse_dynamics(r.dh, q, dq, ddq, g, trace=False)
    cases = [
        ("dh_jacobian (base axes)", lambda: dh_jacobian(r.dh, q),
         lambda: pin.computeFrameJacobian(model, data, q, r.tip_id, pin.LOCAL_WORLD_ALIGNED),
         (lambda: puma.jacob0(q)) if puma else None),
        ("dh_static_torques", lambda: dh_static_torques(r.dh, q, F),
         lambda: pin.computeFrameJacobian(model, data, q, r.tip_id, pin.LOCAL).T @ F, None),
        ("dh_inverse_dynamics", lambda: dh_inverse_dynamics(r.dh, q, dq, ddq, g, trace=False),
         lambda: pin.rnea(model, data, q, dq, ddq), (lambda: puma.rne(q, dq, ddq)) if puma else None),
    ]
    rows = []
    for name, ours, pino, rtbf in cases:
        t_pin = time_call(pino, repeats=reps)
        t_ours = time_call(ours, repeats=reps)
        t_rtb = time_call(rtbf, repeats=reps) if rtbf else float("nan")
        rows.append([name, fmt_time(t_ours), fmt_time(t_pin), _ratio(t_ours, t_pin), fmt_time(t_rtb),
                     _ratio(t_rtb, t_ours)])
    print("\n## 2. DH forms, PUMA 560 (per call)\n")
    print(table(["function", "robokit", "Pinocchio", "robokit / Pinocchio", "rtb Puma560 (DH)",
                 "rtb / robokit"], rows))
    print("\n(rtb's Puma560 uses Corke's parameters, robokit's the shipped puma560.yaml: same kind of model, "
          "not the same numbers. The static-torque Pinocchio column is computeFrameJacobian + Jᵀ F.)")


def _chain30():
    import robokit as rk
    from robokit.description.dh import DHLink, DHTable

    rng = np.random.default_rng(30)
    links = []
    for _ in range(30):
        A = rng.normal(size=(3, 3))
        I = A @ A.T * 0.01 + np.eye(3) * 0.005
        links.append(DHLink("R", float(rng.uniform(0.05, 0.2)), float(rng.choice([-np.pi / 2, np.pi / 2])),
                            float(rng.uniform(-0.1, 0.1)), 0.0, np.array([-np.pi, np.pi]), 1.0,
                            rng.normal(size=3) * 0.02, np.array([I[0, 0], I[1, 1], I[2, 2], I[0, 1], I[1, 2], I[0, 2]])))
    return rk.load(DHTable("chain30", "standard", tuple(links)))


def batched(sizes, reps):
    import pinocchio as pin

    import robokit as rk

    robots = [("twolink", rk.load("twolink")), ("ur5", rk.load("ur5")), ("panda", rk.load("panda")),
              ("chain30 (DH)", _chain30())]
    rows = []
    for name, r in robots:
        p = r.poe
        model = r.model
        n = r.n
        pool = pin.ModelPool(model, 2)
        for N in sizes:
            rng = np.random.default_rng(N)
            Q = np.array([r.random_configuration(rng) for _ in range(min(N, 1000))])
            Q = np.ascontiguousarray(np.resize(Q, (N, n)))
            D, A = rng.normal(size=(N, n)), rng.normal(size=(N, n))
            g, z6 = r.gravity, np.zeros(6)
            data = model.createData()
            QT, DT, AT = (np.asfortranarray(X.T) for X in (Q, D, A))
            loop_reps = 3 if N >= 100_000 else reps

            def loop_rnea():
                for k in range(N):
                    pin.rnea(model, data, Q[k], D[k], A[k])

            def loop_fk():
                for k in range(N):
                    pin.forwardKinematics(model, data, Q[k])
                    pin.updateFramePlacement(model, data, r.tip_id)

            def par_rnea():
                pin.rneaInParallel(2, pool, QT, DT, AT)

            for fname, ours, loop, par in [
                ("inverse_dynamics", lambda: rk.inverse_dynamics(Q, D, A, g, z6, p.Mlist, p.Glist, p.Slist),
                 loop_rnea, par_rnea),
                ("fkin_space", lambda: rk.fkin_space(p.M, p.Slist, Q), loop_fk, None),
                ("mass_matrix", lambda: rk.mass_matrix(Q, p.Mlist, p.Glist, p.Slist),
                 None, None),
            ]:
                if fname == "mass_matrix" and N > 10_000:
                    continue  # N n² output; the other two tables already show the scaling
                rss0 = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
                t_ours = time_call(ours, repeats=loop_reps, target=0.05) / N
                rss1 = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
                t_loop = time_call(loop, repeats=loop_reps, target=0.05) / N if loop else float("nan")
                t_par = time_call(par, repeats=loop_reps, target=0.05) / N if par else float("nan")
                rows.append([name, n, fname, f"{N:,}", fmt_time(t_ours), fmt_time(t_loop), _ratio(t_ours, t_loop),
                             fmt_time(t_par), _ratio(t_ours, t_par), f"{max(0, rss1 - rss0) / 1024:.1f} MB"])
    print("\n## 3. Batched, per configuration (parallel kernels, 2 threads)\n")
    print(table(["robot", "DOF", "function", "N", "robokit batched", "loop over Pinocchio", "ratio",
                 "rneaInParallel (2 thr)", "ratio", "peak RSS growth"], rows))
    print("\n(ratio < 1: robokit faster. Peak RSS growth: rise of the process's maximum resident set "
          "during robokit's call; 0 when an earlier, larger call already set the maximum.)")


def ik(n_targets):
    import robokit as rk
    from robokit.kernels.ik import solve_poe_ik

    rows = []
    for name in ("ur5", "panda", "puma560"):
        r = rk.load(name)
        p = r.poe
        try:
            ets = _ets_from_robot(r)
        except Exception:  # pragma: no cover
            ets = None
        rng = np.random.default_rng(5)
        targets = [r.frame_pose(r.random_configuration(rng)) for _ in range(n_targets)]
        guesses = [r.random_configuration(rng) for _ in range(n_targets)]
        solve_poe_ik(p.M, p.Slist, targets[0], guesses[0], r.qlim)  # load/compile
        rk.solve_ik(r, targets[0], q0=guesses[0])  # closed-form set-up, if any
        ours_t, ours_ok, rtb_t, rtb_ok = [], 0, [], 0
        auto_t, auto_ok = [], 0
        for k, (T, q0) in enumerate(zip(targets, guesses)):
            t0 = time.perf_counter()
            res = rk.solve_ik(r, T, q0=q0, rng=k)
            auto_t.append(time.perf_counter() - t0)
            auto_ok += bool(res.success) and np.abs(r.frame_pose(res.q) - T).max() < 1e-9 and bool(
                np.all(res.q >= r.qlim[:, 0] - 1e-12) and np.all(res.q <= r.qlim[:, 1] + 1e-12))
        for k, (T, q0) in enumerate(zip(targets, guesses)):
            t0 = time.perf_counter()
            q, ok, _, _ = solve_poe_ik(p.M, p.Slist, T, q0, r.qlim, 1e-10, 30, 200, k)
            ours_t.append(time.perf_counter() - t0)
            ours_ok += bool(ok) and np.abs(r.frame_pose(q) - T).max() < 1e-9
            if ets is not None:
                np.random.seed(k)
                t0 = time.perf_counter()
                sol = ets.ik_LM(T, q0=q0, ilimit=30, slimit=200, tol=5e-21, joint_limits=True)
                rtb_t.append(time.perf_counter() - t0)
                q_rtb, ok_rtb = (sol.q, sol.success) if hasattr(sol, "success") else (sol[0], sol[1])
                rtb_ok += bool(ok_rtb) and np.abs(r.frame_pose(np.asarray(q_rtb, dtype=float)) - T).max() < 1e-9
        med_o = float(np.median(ours_t))
        med_a = float(np.median(auto_t))
        med_r = float(np.median(rtb_t)) if rtb_t else float("nan")
        method = "closed form" if rk.ik_analytic_kind(r).method else "compiled LM"
        rows.append([name, n_targets, f"{100 * ours_ok / n_targets:.1f} %", fmt_time(med_o),
                     f"{100 * auto_ok / n_targets:.1f} %", f"{fmt_time(med_a)} ({method})",
                     f"{100 * rtb_ok / n_targets:.1f} %" if rtb_t else "n/a", fmt_time(med_r), _ratio(med_o, med_r),
                     _ratio(med_a, med_r)])
    print("\n## 4. IK from random initial guesses, reachable targets (success verified with Pinocchio FK to 1e-9)\n")
    print(table(["robot", "targets", "kernel success", "kernel median", "solve_ik success", "solve_ik median",
                 "rtb ik_LM success", "rtb median", "kernel / rtb", "solve_ik / rtb"], rows))


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="fewer repeats, N up to 10⁴, 50 IK targets")
    ap.add_argument("--big", action="store_true", help="also N = 10⁶ in the batched table")
    ap.add_argument("--only", choices=["call", "dh", "batch", "ik"], help="run one table")
    args = ap.parse_args(argv)
    reps = 3 if args.quick else 5
    sizes = [100, 1_000, 10_000] if args.quick else [100, 1_000, 10_000, 100_000]
    if args.big:
        sizes.append(1_000_000)
    print(f"# Compiled course kernels\n\nmachine: {machine()}")
    if args.only in (None, "call"):
        per_call(reps)
    if args.only in (None, "dh"):
        dh_forms(reps)
    if args.only in (None, "batch"):
        batched(sizes, reps)
    if args.only in (None, "ik"):
        ik(50 if args.quick else 1000)


if __name__ == "__main__":
    main()
