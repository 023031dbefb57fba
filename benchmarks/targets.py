"""The speed targets, each beside the peer measured in the same run (issue 29's table).

Tables (Markdown, printed; nothing is asserted):

1. cold start — a new process with a fresh, empty numba cache (``NUMBA_CACHE_DIR`` a new temporary
   folder) against the same process started again on the now warm cache: ``robokit validate``
   (whole command), the first ``fkin_space``, ``inverse_dynamics`` and ``solve_ik`` (Panda) call;
2. closed-form IK — ``ik_analytic`` (all solutions of one pose) on the PUMA 560 and the UR5 against
   EAIK (C++) and ``ur-analytic-ik`` (C++), and ``solve_ik`` on the UR5 against roboticstoolbox's
   C++ ``ik_LM`` on the same targets;
3. per call against Pinocchio for n = 3 … 100 joints (random chains): FK, Jacobian, RNEA, CRBA and
   forward dynamics (ABA, and the lecture's CRBA + Cholesky) — the seed function, its kernel alone
   and the packed model's method (``robokit.kernels.packed.pack_model``, built once);
4. batched over N configurations, per configuration: the five (seed functions, then the packed
   model's ``*_many``) against a Python loop over Pinocchio, and RNEA / forward dynamics against
   ``rneaInParallel`` / ``abaInParallel`` on the same threads;
5. ``Robot`` methods against the raw Pinocchio call each wraps (UR5);
6. simulation — ``robokit.simulate`` (PUMA 560, computed torque, RK4, 1 kHz) against the same loop
   written by hand over Pinocchio, and the seed's ``simulate_control`` compiled against its Python loop.

Run: ``python -m benchmarks.targets [--quick] [--only cold|ik|call|batch|robot|sim]``.
"""
from __future__ import annotations

import argparse
import os
import statistics
import subprocess
import sys
import tempfile
import time

import numpy as np

from benchmarks._chains import random_chain
from benchmarks._harness import fmt_time, machine, table, time_best


def _ratio(a: float, b: float) -> str:
    return f"{a / b:.2f}×" if np.isfinite(a) and np.isfinite(b) and b > 0 else "n/a"


# ------------------------------------------------------------------ 1. cold start
_TAIL = ("\nfrom robokit.kernels import _jit\n"
         "w = _jit._BG.worker\n"
         "print('KERNELS', len(_jit._BG.by_number), sum(map(len, _jit._COMPILED.values())), w.pid if w else 0)\n")
_COLD = {
    "fkin_space (UR5)": ("import robokit as rk, numpy as np; r = rk.load('ur5'); p = r.poe; import time; "
                         "t = time.perf_counter(); rk.fkin_space(p.M, p.Slist, np.zeros(r.n)); "
                         "print(time.perf_counter() - t)"),
    "inverse_dynamics (UR5)": ("import robokit as rk, numpy as np; r = rk.load('ur5'); p = r.poe; z = np.zeros(r.n); "
                               "import time; t = time.perf_counter(); "
                               "rk.inverse_dynamics(z, z, z, r.gravity, np.zeros(6), p.Mlist, p.Glist, p.Slist); "
                               "print(time.perf_counter() - t)"),
    "solve_ik (Panda)": ("import robokit as rk, numpy as np; r = rk.load('panda'); "
                         "T = r.frame_pose(r.random_configuration(1)); import time; t = time.perf_counter(); "
                         "rk.solve_ik(r, T); print(time.perf_counter() - t)"),
    "ik_analytic (PUMA 560)": ("import robokit as rk, numpy as np; r = rk.load('puma560'); "
                               "T = r.frame_pose(np.full(6, 0.3)); import time; t = time.perf_counter(); "
                               "rk.ik_analytic(r, T); print(time.perf_counter() - t)"),
    "robokit validate": ("import time, contextlib, io; t = time.perf_counter(); from robokit.cli import main\n"
                         "with contextlib.redirect_stdout(io.StringIO()):\n"
                         "    try: main(['validate'])\n"
                         "    except SystemExit: pass\n"
                         "print(time.perf_counter() - t)"),
}


def _run_cold(code: str, cache: str, mode: str) -> dict[str, float]:
    """One new process on numba cache ``cache`` with ``ROBOKIT_COMPILE=mode``: the seconds the
    script printed (the call), the whole process's wall and CPU seconds, the kernels sent to the
    background worker and compiled in the process; waits for the worker to exit (so that the next
    run meets the cache the worker left)."""
    import resource

    env = dict(os.environ, NUMBA_CACHE_DIR=cache, ROBOKIT_COMPILE=mode)
    env.pop("NUMBA_DISABLE_JIT", None)
    cpu0 = resource.getrusage(resource.RUSAGE_CHILDREN)
    t0 = time.perf_counter()
    proc = subprocess.run([sys.executable, "-c", code + _TAIL], env=env, capture_output=True, text=True,
                          timeout=3600)
    wall = time.perf_counter() - t0
    cpu1 = resource.getrusage(resource.RUSAGE_CHILDREN)
    out = {"call": float("nan"), "wall": wall, "cpu": cpu1.ru_utime - cpu0.ru_utime + cpu1.ru_stime - cpu0.ru_stime,
           "background": 0, "here": 0, "worker": 0.0}
    lines = proc.stdout.strip().splitlines()
    try:
        _, bg, here, pid = lines[-1].split()
        out.update(call=float(lines[-2]), background=int(bg), here=int(here))
    except (ValueError, IndexError):
        return out
    t1 = time.perf_counter()
    while int(pid):
        try:
            os.kill(int(pid), 0)
        except ProcessLookupError:
            break
        time.sleep(0.2)
    out["worker"] = time.perf_counter() - t1
    return out


def cold_start(quick: bool) -> None:
    rows = []
    modes = (("wait", "before (compile, then run)"), ("background", "after (background compile)"))
    for name, code in _COLD.items():
        if quick and name == "robokit validate":
            continue
        for mode, label in modes:
            with tempfile.TemporaryDirectory() as cache:
                first = _run_cold(code, cache, mode)
                second = _run_cold(code, cache, mode)
            key = "wall" if name == "robokit validate" else "call"
            rows.append([name, label, f"{first[key]:.2f} s", f"{first['cpu']:.1f} s",
                         f"{first['background']} / {first['here']}", f"{first['worker']:.1f} s",
                         f"{second[key]:.2f} s", _ratio(first[key], second[key]),
                         f"{first[key] - 1.5 * second[key]:+.2f} s"])
    print("\n## 1. Cold start: fresh numba cache and a new process, then the same again on the warm cache\n")
    print(table(["what", "mode", "first (cold cache)", "its CPU", "kernels: background / here",
                 "worker busy after exit", "second (warm)", "first / second",
                 "first − 1.5 × second (target ≤ 3 s)"], rows))
    print("\n(validate: the whole command, interpreter start included; the others: the first call only, "
          "after `import robokit` and loading the robot. 'its CPU': user + system seconds of the process "
          "(not its worker) — on a loaded machine the wall time mostly measures the scheduler. "
          "'before' is ROBOKIT_COMPILE=wait, robokit's behaviour before the background worker.)")


_STEADY = r"""
import time, numpy as np, robokit as rk
from robokit.kernels import poe
r = rk.load('ur5'); p = r.poe
M, S, q = np.array(p.M), np.array(p.Slist), np.zeros(r.n)  # writeable copies, as the kernel takes them
t0 = time.monotonic()
while not poe.fkin_space.signatures:  # background: runs as Python until the worker is done
    poe.fkin_space(M, S, q); time.sleep(0.05)
    assert time.monotonic() - t0 < 1800
best = []
for _ in range(7):
    t = time.perf_counter()
    for _ in range(20000):
        poe.fkin_space(M, S, q)
    best.append((time.perf_counter() - t) / 20000)
print(min(best) * 1e6)
"""


def steady_state() -> None:
    """The kernel's per-call cost once it runs machine code: switched from Python after a
    background compile, against compiled in the process from the start (``wait``) — same cache."""
    rows = []
    with tempfile.TemporaryDirectory() as cache:
        for mode in ("background", "wait", "background", "wait"):
            env = dict(os.environ, NUMBA_CACHE_DIR=cache, ROBOKIT_COMPILE=mode)
            env.pop("NUMBA_DISABLE_JIT", None)
            proc = subprocess.run([sys.executable, "-c", _STEADY], env=env, capture_output=True, text=True,
                                  timeout=3600)
            rows.append([mode, "cold" if len(rows) == 0 else "warm",
                         f"{float(proc.stdout.strip().splitlines()[-1]):.2f} µs" if proc.stdout.strip() else "n/a"])
    print("\n### Per call after the switch (kernel `poe.fkin_space`, UR5, best of 7 × 20,000 calls)\n")
    print(table(["mode", "cache at start", "per call"], rows))


# ------------------------------------------------------------------ 2. closed-form IK
def _eaik_from_poe(poe):
    """An EAIK HPRobot of a PoE chain: joint axes H (n, 3) and the offsets P (n+1, 3) between points
    on consecutive axes (a point on axis i: ωᵢ × vᵢ for a unit ωᵢ), the last to the tool origin."""
    from eaik.IK_HP import HPRobot

    S = np.asarray(poe.Slist)
    H = S[:3].T.copy()
    pts = np.array([np.cross(S[:3, i], S[3:, i]) for i in range(S.shape[1])])
    tip = np.asarray(poe.M)[:3, 3]
    P = np.vstack([pts[0], np.diff(pts, axis=0), tip - pts[-1]])
    return HPRobot(H, P)


def closed_form(quick: bool) -> None:
    import robokit as rk

    n_poses = 20 if quick else 100
    rows = []
    rng = np.random.default_rng(0)
    for name in ("puma560", "ur5"):
        r = rk.load(name)
        poses = [r.frame_pose(r.random_configuration(rng)) for _ in range(n_poses)]
        rk.ik_analytic(r, poses[0])
        t_rk = statistics.median(time_best(rk.ik_analytic, r, T, batches=20) for T in poses)
        n_rk = statistics.mean(len(rk.ik_analytic(r, T)) for T in poses)
        rows.append([name, "robokit ik_analytic", fmt_time(t_rk), f"{n_rk:.1f}", "1.00×"])
        from robokit.ik import analytic_ik

        ik = analytic_ik(r)
        K, solve_into = ik._kernel[0], ik._kernel[4]
        out = np.empty((16, 9))
        t_k = statistics.median(time_best(solve_into, K, T, 0.0, out, batches=20) for T in poses)
        rows.append([name, "its compiled kernel alone (no Python objects)", fmt_time(t_k), f"{n_rk:.1f}",
                     _ratio(t_rk, t_k)])
        try:
            if name == "puma560":
                from eaik.IK_DH import DhRobot

                links = r.dh.links
                bot = DhRobot(np.array([float(l.alpha) for l in links]), np.array([float(l.a) for l in links]),
                              np.array([float(l.d) for l in links]))
            else:
                bot = _eaik_from_poe(r.poe)
            qs = [r.random_configuration(rng) for _ in range(n_poses)]
            eposes = [bot.fwdKin(q) for q in qs]  # EAIK's own frames: the same problem, all solutions
            t_e = statistics.median(time_best(bot.IK, T, batches=20) for T in eposes)
            n_e = statistics.mean(len(bot.IK(T).Q) for T in eposes)
            rows.append([name, "EAIK (C++)", fmt_time(t_e), f"{n_e:.1f}", _ratio(t_rk, t_e)])
        except ImportError:
            rows.append([name, "EAIK (C++)", "not installed", "", ""])
        if name == "ur5":
            try:
                import ur_analytic_ik as uik

                qs = [r.random_configuration(rng) for _ in range(n_poses)]
                uposes = [np.ascontiguousarray(uik.ur5.forward_kinematics(*q)) for q in qs]
                t_u = statistics.median(time_best(uik.ur5.inverse_kinematics, T, batches=20)
                                        for T in uposes)
                n_u = statistics.mean(len(uik.ur5.inverse_kinematics(T)) for T in uposes)
                rows.append([name, "ur-analytic-ik (C++)", fmt_time(t_u), f"{n_u:.1f}", _ratio(t_rk, t_u)])
            except ImportError:
                rows.append([name, "ur-analytic-ik (C++)", "not installed", "", ""])
    # the general 6R method (an offset wrist: no special structure): target ≤ 300 µs per pose from
    # Python (issue 42), beside its compiled kernel alone and the generated C through ctypes
    import tempfile

    from benchmarks.general_6r import c_ik, jaco2_table, kernel_call

    r = rk.load(jaco2_table())
    poses = [r.frame_pose(r.random_configuration(rng)) for _ in range(max(5, n_poses // 5))]
    rk.ik_analytic(r, poses[0])
    t_g = statistics.median(time_best(rk.ik_analytic, r, T, batches=5) for T in poses)
    n_g = statistics.mean(len(rk.ik_analytic(r, T)) for T in poses)
    rows.append(["jaco2 (general 6R)", "robokit ik_analytic (target ≤ 300 µs)", fmt_time(t_g), f"{n_g:.1f}",
                 _ratio(t_g, 300e-6) + " of 300 µs"])
    kern = kernel_call(r)
    t_gk = statistics.median(time_best(kern, T, batches=5) for T in poses)
    rows.append(["jaco2 (general 6R)", "its compiled kernel alone (no Python objects)", fmt_time(t_gk), f"{n_g:.1f}",
                 _ratio(t_g, t_gk)])
    with tempfile.TemporaryDirectory() as tmp:
        c = c_ik(r, tmp)
        if isinstance(c, str):
            rows.append(["jaco2 (general 6R)", "generated C (-O2, ctypes)", c, "", ""])
        else:
            t_gc = statistics.median(time_best(c, T, batches=5) for T in poses)
            rows.append(["jaco2 (general 6R)", "generated C (-O2, ctypes)", fmt_time(t_gc), f"{n_g:.1f}",
                         _ratio(t_g, t_gc)])
    # solve_ik UR5 against rtb's C++ ik_LM on the same targets and guesses
    try:
        from benchmarks.kernels import _ets_from_robot

        r = rk.load("ur5")
        ets = _ets_from_robot(r)
        targets = [r.frame_pose(r.random_configuration(rng)) for _ in range(n_poses)]
        guesses = [r.random_configuration(rng) for _ in range(n_poses)]
        rk.solve_ik(r, targets[0], q0=guesses[0])
        t_s, t_l = [], []
        for T, q0 in zip(targets, guesses):
            t0 = time.perf_counter()
            rk.solve_ik(r, T, q0=q0)
            t_s.append(time.perf_counter() - t0)
            t0 = time.perf_counter()
            ets.ik_LM(T, q0=q0, ilimit=30, slimit=100, tol=5e-21, joint_limits=True)
            t_l.append(time.perf_counter() - t0)
        rows.append(["ur5", "robokit solve_ik (closed form inside)", fmt_time(statistics.median(t_s)), "1", "1.00×"])
        rows.append(["ur5", "roboticstoolbox ik_LM (C++)", fmt_time(statistics.median(t_l)), "1",
                     _ratio(statistics.median(t_s), statistics.median(t_l))])
    except ImportError:
        rows.append(["ur5", "roboticstoolbox ik_LM", "not installed", "", ""])
    print(f"\n## 2. Closed-form IK: all solutions of one pose (median over {n_poses} poses)\n")
    print(table(["robot", "solver", "median per pose", "solutions (mean)", "robokit / this"], rows))
    print("\n(EAIK and ur-analytic-ik solve poses from their own forward kinematics of the same geometry: the "
          "same problem in their frames. robokit's spherical-wrist and parallel-axes closed forms run as one "
          "compiled call writing one array; the list of IKSolution objects is read lazily from it. The general "
          "6R method is one compiled call per pose too, its own eigenvalue solver inside.)")


# ------------------------------------------------------------------ 3. per call, growth with n
def _cases(model, data, fid, p, q, dq, a):
    """(name, robokit seed function, Pinocchio peer, the seed's compiled kernel alone, the packed
    model's method) per row of table 3."""
    import pinocchio as pin

    import robokit as rk

    from robokit.kernels import dynamics as kd
    from robokit.kernels import poe as kp
    from robokit.kernels.packed import pack_model

    g, z6 = np.array(model.gravity.linear), np.zeros(6)
    M, S, Ml, Gl = p.M, p.Slist, p.Mlist, p.Glist
    pm = pack_model(Ml, Gl, S, g, M=M)
    return [
        ("FK (fkin_space)", lambda: rk.fkin_space(M, S, q),
         lambda: (pin.forwardKinematics(model, data, q), pin.updateFramePlacement(model, data, fid)),
         lambda: kp.fkin_space(M, S, q), lambda: pm.fk(q)),
        ("Jacobian (jacobian_space)", lambda: rk.jacobian_space(S, q),
         lambda: pin.computeFrameJacobian(model, data, q, fid, pin.WORLD), lambda: kp.jacobian_space(S, q),
         lambda: pm.jacobian(q)),
        ("RNEA (inverse_dynamics)", lambda: rk.inverse_dynamics(q, dq, a, g, z6, Ml, Gl, S),
         lambda: pin.rnea(model, data, q, dq, a), lambda: kd.inverse_dynamics(q, dq, a, g, z6, Ml, Gl, S),
         lambda: pm.rnea(q, dq, a)),
        ("CRBA (mass_matrix)", lambda: rk.mass_matrix(q, Ml, Gl, S),
         lambda: pin.crba(model, data, q), lambda: kd.mass_matrix(q, Ml, Gl, S), lambda: pm.crba(q)),
        ("FD (forward_dynamics, ABA)", lambda: rk.forward_dynamics(q, dq, a, g, z6, Ml, Gl, S),
         lambda: pin.aba(model, data, q, dq, a), lambda: kd.forward_dynamics(q, dq, a, g, z6, Ml, Gl, S),
         lambda: pm.aba(q, dq, a)),
        ("FD (method='crba')", lambda: rk.forward_dynamics(q, dq, a, g, z6, Ml, Gl, S, method="crba"),
         lambda: pin.aba(model, data, q, dq, a), lambda: kd.forward_dynamics_crba(q, dq, a, g, z6, Ml, Gl, S),
         lambda: pm.forward_dynamics_crba(q, dq, a)),
    ]


def per_call(ns: list[int], reps: int) -> None:
    rows = []
    for n in ns:
        model, data, fid, p = random_chain(n, seed=n)
        rng = np.random.default_rng(n)
        q, dq, a = rng.uniform(-2, 2, n), rng.normal(size=n), rng.normal(size=n)
        for name, ours, peer, kernel, packed in _cases(model, data, fid, p, q, dq, a):
            t_p = time_best(peer, batches=reps)
            t_o = time_best(ours, batches=reps)
            t_k = time_best(kernel, batches=reps)
            t_m = time_best(packed, batches=reps)
            rows.append([n, name, fmt_time(t_o), fmt_time(t_k), fmt_time(t_m), fmt_time(t_p), _ratio(t_o, t_p),
                         _ratio(t_k, t_p), _ratio(t_m, t_p)])
    print("\n## 3. Per call against Pinocchio, growth with n (random chains; target ≤ 3×)\n")
    print(table(["n", "function", "robokit (seed function)", "seed kernel alone", "packed model (PackedModel)",
                 "Pinocchio", "seed function / Pinocchio", "seed kernel / Pinocchio",
                 "packed / Pinocchio (target ≤ 3×)"], rows))
    print("\n(FD rows compare with Pinocchio's `aba`. The seed function's time includes the argument checks and "
          "the call into its kernel, which checks the model and derives its constants on every call; the packed "
          "model (`robokit.kernels.packed.pack_model`, built once like Pinocchio's Model) is what an object "
          "holding a fixed model calls: one read-only array, the joint vectors and the output per dispatch.)")


# ------------------------------------------------------------------ 4. batched
def batched(ns: list[int], N: int, reps: int) -> None:
    import numba
    import pinocchio as pin

    import robokit as rk

    threads = min(2, os.cpu_count() or 1)
    rows = []
    for n in ns:
        model, data, fid, p = random_chain(n, seed=n)
        rng = np.random.default_rng(n)
        Q, D, A = rng.uniform(-2, 2, (N, n)), rng.normal(size=(N, n)), rng.normal(size=(N, n))
        g, z6 = np.array(model.gravity.linear), np.zeros(6)
        QT, DT, AT = (np.asfortranarray(X.T) for X in (Q, D, A))
        pool = pin.ModelPool(model, threads)
        from robokit.kernels import packed as kpk

        pm = kpk.pack_model(p.Mlist, p.Glist, p.Slist, g, M=p.M)

        def loop(f):
            def run():
                for k in range(N):
                    f(k)
            return run

        cases = [
            ("FK", lambda: rk.fkin_space(p.M, p.Slist, Q),
             loop(lambda k: (pin.forwardKinematics(model, data, Q[k]), pin.updateFramePlacement(model, data, fid))),
             None),
            ("Jacobian", lambda: rk.jacobian_space(p.Slist, Q),
             loop(lambda k: pin.computeFrameJacobian(model, data, Q[k], fid, pin.WORLD)), None),
            ("RNEA", lambda: rk.inverse_dynamics(Q, D, A, g, z6, p.Mlist, p.Glist, p.Slist),
             loop(lambda k: pin.rnea(model, data, Q[k], D[k], A[k])),
             lambda: pin.rneaInParallel(threads, pool, QT, DT, AT)),
            ("CRBA", lambda: rk.mass_matrix(Q, p.Mlist, p.Glist, p.Slist),
             loop(lambda k: pin.crba(model, data, Q[k])), None),
            ("FD (ABA)", lambda: rk.forward_dynamics(Q, D, A, g, z6, p.Mlist, p.Glist, p.Slist),
             loop(lambda k: pin.aba(model, data, Q[k], D[k], A[k])),
             lambda: pin.abaInParallel(threads, pool, QT, DT, AT)),
        ]
        cases += [
            ("FK, packed model", lambda: pm.fk_many(Q), cases[0][2], None),
            ("Jacobian, packed model", lambda: pm.jacobian_many(Q), cases[1][2], None),
            ("RNEA, packed model", lambda: pm.rnea_many(Q, D, A), cases[2][2], cases[2][3]),
            ("CRBA, packed model", lambda: pm.crba_many(Q), cases[3][2], None),
            ("FD (ABA), packed model", lambda: pm.aba_many(Q, D, A), cases[4][2], cases[4][3]),
        ]
        for name, ours, pin_loop, par in cases:
            t_loop = time_best(pin_loop, batches=max(10, reps // 4)) / N
            numba.set_num_threads(1)
            t_one = time_best(ours, batches=max(10, reps // 4)) / N
            numba.set_num_threads(threads)
            t_ours = time_best(ours, batches=max(10, reps // 4)) / N
            t_par = time_best(par, batches=max(10, reps // 4)) / N if par else float("nan")
            rows.append([n, name, fmt_time(t_one), fmt_time(t_ours), fmt_time(t_loop), _ratio(t_ours, t_loop),
                         fmt_time(t_par) if par else "—", _ratio(t_ours, t_par) if par else "—"])
    print(f"\n## 4. Batched, N = {N:,} configurations, time per configuration ({threads} threads)\n")
    print(table(["n", "function", "robokit, 1 thread", f"robokit, {threads} threads", "Python loop over Pinocchio",
                 "robokit / loop (target ≤ 0.5×)", f"Pinocchio *InParallel ({threads} thr)",
                 "robokit / InParallel (target ≤ 1×)"], rows))


# ------------------------------------------------------------------ 5. Robot methods
def robot_methods(reps: int) -> None:
    import pinocchio as pin

    import robokit as rk

    rows = []
    for name in ("ur5", "panda"):
        r = rk.load(name)
        m, d, fid = r.model, r.data, r.tip_id
        rng = np.random.default_rng(2)
        q, dq, a = r.random_configuration(rng), rng.normal(size=r.n), rng.normal(size=r.n)
        cases = [
            ("frame_pose(q)", lambda: r.frame_pose(q),
             lambda: (pin.forwardKinematics(m, d, q), pin.updateFramePlacement(m, d, fid).homogeneous)),
            ("jacobian(q)", lambda: r.jacobian(q),  # its default frame: LOCAL_WORLD_ALIGNED
             lambda: pin.computeFrameJacobian(m, d, q, fid, pin.LOCAL_WORLD_ALIGNED)),
            ("rnea(q, dq, ddq)", lambda: r.rnea(q, dq, a), lambda: pin.rnea(m, d, q, dq, a)),
            ("crba(q)", lambda: r.crba(q), lambda: pin.crba(m, d, q)),
            ("aba(q, dq, tau)", lambda: r.aba(q, dq, a), lambda: pin.aba(m, d, q, dq, a)),
            ("gravity_torques(q)", lambda: r.gravity_torques(q), lambda: pin.computeGeneralizedGravity(m, d, q)),
        ]
        for meth, ours, raw in cases:
            t_raw = time_best(raw, batches=reps)
            t_o = time_best(ours, batches=reps)
            rows.append([name, meth, fmt_time(t_o), fmt_time(t_raw), _ratio(t_o, t_raw)])
    print("\n## 5. Robot methods against the raw Pinocchio call they wrap (target ≤ 1.5×)\n")
    print(table(["robot", "method", "Robot method", "raw Pinocchio", "ratio"], rows))
    print("\n(The methods test q once (Robot._fast: float64 (n,), finite, not degrees), convert angles to "
          "Pinocchio's configuration and swap the Jacobian's rows to (ω; v); crba returns Pinocchio's symmetric "
          "array as is. Timings taken under load are for ratios only.)")


# ------------------------------------------------------------------ 6. simulation
def _best_wall(fn, runs: int = 3) -> float:
    """The shortest of ``runs`` wall times of ``fn()`` (s)."""
    best = float("inf")
    for _ in range(runs):
        t0 = time.perf_counter()
        fn()
        best = min(best, time.perf_counter() - t0)
    return best


def simulation(seconds: float) -> None:
    import pinocchio as pin

    import robokit as rk
    from robokit.control import ComputedTorque, simulate
    from robokit.control.seed import simulate_control

    r = rk.load("puma560")
    dt = 1e-3
    K = int(round(seconds / dt)) + 1
    t = np.arange(K) * dt
    w = np.linspace(0.5, 1.5, r.n)
    qd, dqd, ddqd = 0.5 * np.sin(np.outer(t, w)), 0.5 * np.cos(np.outer(t, w)) * w, -0.5 * np.sin(np.outer(t, w)) * w**2
    ctrl = ComputedTorque(r, Kp=100.0)
    simulate(r, ctrl, (t[:3], qd[:3], dqd[:3], ddqd[:3]))  # load / compile
    res = simulate(r, ctrl, (t, qd, dqd, ddqd))
    res_py = simulate(r, ctrl, (t, qd, dqd, ddqd), compiled=False)
    t_rk = _best_wall(lambda: simulate(r, ctrl, (t, qd, dqd, ddqd)))
    t_rk_py = _best_wall(lambda: simulate(r, ctrl, (t, qd, dqd, ddqd), compiled=False))
    model, data = r.model, r.model.createData()
    Kp, Kv = ctrl.Kp, ctrl.Kv

    def by_hand():  # computed torque + RK4 written directly over Pinocchio
        q, dq = qd[0].copy(), dqd[0].copy()
        out = np.empty((K, r.n))
        for k in range(K):
            out[k] = q
            if k == K - 1:
                break
            tau = pin.rnea(model, data, q, dq, ddqd[k] + Kv * (dqd[k] - dq) + Kp * (qd[k] - q))
            k1v = pin.aba(model, data, q, dq, tau)
            k2v = pin.aba(model, data, q + 0.5 * dt * dq, dq + 0.5 * dt * k1v, tau)
            k3v = pin.aba(model, data, q + 0.5 * dt * (dq + 0.5 * dt * k1v), dq + 0.5 * dt * k2v, tau)
            k4v = pin.aba(model, data, q + dt * (dq + 0.5 * dt * k2v), dq + dt * k3v, tau)
            q = q + dt / 6.0 * (dq + 2 * (dq + 0.5 * dt * k1v) + 2 * (dq + 0.5 * dt * k2v) + dq + dt * k3v)
            dq = dq + dt / 6.0 * (k1v + 2 * k2v + 2 * k3v + k4v)
        return out

    q_hand = by_hand()
    t_hand = _best_wall(by_hand)
    rows = [["robokit.simulate (compiled loop)", f"{t_rk:.4f} s", _ratio(t_rk, t_hand),
             f"{np.abs(res.q - q_hand).max():.1e}"],
            ["robokit.simulate(compiled=False) (Python loop)", f"{t_rk_py:.4f} s", _ratio(t_rk_py, t_hand),
             f"{np.abs(res_py.q - q_hand).max():.1e}"],
            ["the same loop by hand over Pinocchio", f"{t_hand:.4f} s", "1.00×", "0"]]
    p = r.poe
    N = K - 1
    args = (qd[0] + 0.05, dqd[0], r.gravity, np.zeros((N, 6)), p.Mlist, p.Glist, p.Slist, qd[1:], dqd[1:], ddqd[1:],
            r.gravity, p.Mlist, p.Glist * 1.2, 20.0, 10.0, 18.0, dt, 1)
    simulate_control(*args[:3], np.zeros((3, 6)), *args[4:7], qd[1:4], dqd[1:4], ddqd[1:4], *args[10:])
    a = simulate_control(*args)
    b = simulate_control(*args, compiled=False)
    t_sc = _best_wall(lambda: simulate_control(*args))
    t_sc_py = _best_wall(lambda: simulate_control(*args, compiled=False))
    rows.append(["simulate_control (seed, compiled)", f"{t_sc:.4f} s", _ratio(t_sc, t_sc_py),
                 f"{np.abs(a[1] - b[1]).max():.1e}"])
    rows.append(["simulate_control(compiled=False)", f"{t_sc_py:.4f} s", "1.00×", "0"])
    print(f"\n## 6. Simulation: PUMA 560, computed torque, {seconds:g} s at 1 kHz, RK4 (seed: Euler, 20 % model "
          "error); the shortest of three runs\n")
    print(table(["loop", "wall time", "ratio to the reference row (target ≤ 0.5×)", "max |Δq| to the reference (rad)"],
                rows))


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="fewer sizes, shorter runs, no cold `validate`")
    ap.add_argument("--only", choices=["cold", "ik", "call", "batch", "robot", "sim"], help="run one table")
    args = ap.parse_args(argv)
    quick = args.quick
    reps = 60 if quick else 200  # short batches; the minimum is reported
    print(f"# Speed targets\n\nmachine: {machine()}")
    if args.only in (None, "cold"):
        cold_start(quick)
        steady_state()
    if args.only in (None, "ik"):
        closed_form(quick)
    if args.only in (None, "call"):
        per_call([3, 6, 30, 100] if quick else [3, 6, 12, 30, 60, 100], reps)
    if args.only in (None, "batch"):
        batched([6, 30] if quick else [6, 30, 100], 2_000 if quick else 10_000, reps)
    if args.only in (None, "robot"):
        robot_methods(reps)
    if args.only in (None, "sim"):
        simulation(1.0 if quick else 5.0)


if __name__ == "__main__":
    main()
