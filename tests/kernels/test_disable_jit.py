"""With NUMBA_DISABLE_JIT=1 the same kernel source runs as plain Python and still agrees with
Pinocchio: a small subset of the kernel tests, in a subprocess with that variable set."""
import os
import pathlib
import subprocess
import sys

ROOT = pathlib.Path(__file__).resolve().parents[2]

SCRIPT = r"""
import numba, numpy as np, robokit as rk
assert numba.config.DISABLE_JIT
from robokit.kernels import dynamics as kd, poe as kp, _jit
assert _jit.jit_disabled() and not hasattr(kp.fkin_space, "signatures")  # plain Python functions
r = rk.load("twolink")
p = r.poe
c = lambda a: np.ascontiguousarray(a, dtype=float)
M, S, B, Ml, Gl, Sl = map(c, (p.M, p.Slist, p.Blist, p.Mlist, p.Glist, p.Slist))
rng = np.random.default_rng(0)
Q = np.array([r.random_configuration(rng) for _ in range(5)])
for q in Q:
    assert np.abs(kp.fkin_space(M, S, q) - r.frame_pose(q)).max() < 1e-9
    assert np.abs(kp.jacobian_body(B, q) - r.jacobian(q, reference="local")).max() < 1e-9
    dq, ddq = rng.normal(size=2), rng.normal(size=2)
    assert np.abs(kd.inverse_dynamics(q, dq, ddq, c(r.gravity), np.zeros(6), Ml, Gl, Sl) - r.rnea(q, dq, ddq)).max() < 1e-9
    assert np.abs(kd.mass_matrix(q, Ml, Gl, Sl) - r.crba(q)).max() < 1e-9
    tau = rng.normal(size=2)
    for fd in (kd.forward_dynamics, kd.forward_dynamics_crba):  # articulated bodies and CRBA + Cholesky
        assert np.abs(fd(q, dq, tau, c(r.gravity), np.zeros(6), Ml, Gl, Sl) - r.aba(q, dq, tau)).max() < 1e-9
T = kp.fkin_space_batch(M, S, Q)
assert np.abs(T[2] - kp.fkin_space(M, S, Q[2])).max() < 1e-12
assert np.abs(rk.inverse_dynamics(Q[0], Q[1], Q[2], r.gravity, np.zeros(6), p.Mlist, p.Glist, p.Slist)
              - r.rnea(Q[0], Q[1], Q[2])).max() < 1e-9
from robokit.control.seed import simulate_control
qd = np.outer(np.linspace(0, 1, 6), [0.3, -0.2]).copy()
args = (qd[0], np.zeros(2), r.gravity, np.zeros((6, 6)), p.Mlist, p.Glist, p.Slist, qd, np.zeros_like(qd),
        np.zeros_like(qd), r.gravity, p.Mlist, p.Glist, 20.0, 1.0, 10.0, 0.01, 2)
a, b = simulate_control(*args), simulate_control(*args, compiled=False)  # the simulation kernel as Python
assert np.abs(a[1] - b[1]).max() < 1e-12
try:
    kp.fkin_space(M, S, np.array([np.nan, 0.0]))
except ValueError as e:
    assert "NaN" in str(e)
else:
    raise AssertionError("NaN accepted")
assert _jit._BG.worker is None and not _jit._BG.jobs  # no background compile worker either
print("ok")
"""


def test_kernels_run_as_plain_python():
    env = dict(os.environ, NUMBA_DISABLE_JIT="1", PYTHONPATH=str(ROOT) + os.pathsep + os.environ.get("PYTHONPATH", ""))
    proc = subprocess.run([sys.executable, "-c", SCRIPT], env=env, capture_output=True, text=True, timeout=600)
    assert proc.returncode == 0, proc.stderr[-3000:]
    assert proc.stdout.strip().endswith("ok")
    assert "robokit: compiling" not in proc.stderr  # nothing is compiled
