"""No compile wait on first use (``ROBOKIT_COMPILE``): on a cache miss the first calls run the
kernel's interpreted twin while a background worker compiles it into numba's cache, then switch to
the machine code; ``wait`` compiles in the calling process, ``off`` never compiles.

The modes are exercised in subprocesses with an empty temporary ``NUMBA_CACHE_DIR`` (the test
suite itself runs with ``ROBOKIT_COMPILE=wait``, see conftest.py). Nothing here is timed: waits
are bounded only so that a broken worker fails the test instead of hanging it.
"""
import os
import pathlib
import subprocess
import sys
import time

import numpy as np
import pytest

from robokit.kernels import _jit

ROOT = pathlib.Path(__file__).resolve().parents[2]

PRELUDE = r"""
import os, sys, time, threading
import numpy as np
from numba.core import event
from robokit.kernels import poe, _jit

class Count(event.Listener):
    n = 0
    def on_start(self, ev): Count.n += 1
    def on_end(self, ev): pass
event.register("numba:compile", Count())
M = np.eye(4); M[:3, 3] = [0.1, 0.2, 0.3]
S = np.array([[0, 0, 1, 0, 0, 0], [0, 1, 0, -0.4, 0, 0.1], [1, 0, 0, 0, 0.3, -0.2]], float).T.copy()
q = np.array([0.3, -0.7, 1.1])
Q = np.random.default_rng(0).uniform(-3, 3, (21000, 3))  # 63,000 joint-configurations > FK_BATCH

def until(pred, what, bound=900):
    t0 = time.monotonic()
    while not pred():
        assert time.monotonic() - t0 < bound, what
        time.sleep(0.2)
"""

BACKGROUND = PRELUDE + r"""
first = poe.fkin_space(M, S, q)
job = _jit._BG.jobs[(id(poe.fkin_space), poe.fkin_space._robokit_signature)]
assert poe.fkin_space.signatures == [] and job.state == "queued"  # the first call ran as Python
assert Count.n == 0  # nothing was compiled in this process
try:
    poe.fkin_space(M, S, q.astype(np.float32))
except TypeError:
    pass
else:
    raise AssertionError("float32 accepted while interpreted")
small = poe.fkin_space_batch(M, S, Q[:5])  # a small batch runs as Python too
assert poe.fkin_space_batch.signatures == []
results = []
threads = [threading.Thread(target=lambda: results.append(poe.fkin_space(M, S, q))) for _ in range(4)]
[t.start() for t in threads]; [t.join() for t in threads]
until(lambda: poe.fkin_space(M, S, q) is not None and poe.fkin_space.signatures, "fkin_space never switched")
assert not poe.fkin_space._can_compile  # machine code for good: the hook is not reached again
compiled = poe.fkin_space(M, S, q)
assert np.abs(first - compiled).max() <= 1e-12 and all(np.abs(r - compiled).max() <= 1e-12 for r in results)
big = poe.fkin_space_batch(M, S, Q)  # a large batch waits for its machine code
assert len(poe.fkin_space_batch.signatures) == 1
assert np.abs(big[:5] - small).max() <= 1e-12 and np.abs(big[7] - poe.fkin_space(M, S, Q[7])).max() <= 1e-12
assert Count.n == 0  # still: the worker compiled, not this process
poe.jacobian_space(S, q)  # queued, left for the worker to finish after this process exits
import multiprocessing
def child(conn):  # a forked child gets a worker of its own, not its parent's pipes
    J = poe.jacobian_body(S, q)
    conn.send((J, _jit._BG.worker.pid, poe.jacobian_body.signatures == []))
a, b = multiprocessing.get_context("fork").Pipe()
proc = multiprocessing.get_context("fork").Process(target=child, args=(b,)); proc.start()
J, child_worker, interpreted = a.recv(); proc.join()
assert proc.exitcode == 0 and interpreted and child_worker != _jit._BG.worker.pid
print("PID", _jit._BG.worker.pid)
print("ok")
"""

WARM = PRELUDE + r"""
poe.fkin_space(M, S, q); poe.fkin_space_batch(M, S, Q); poe.jacobian_space(S, q)
assert [len(k.signatures) for k in (poe.fkin_space, poe.fkin_space_batch, poe.jacobian_space)] == [1, 1, 1]
assert Count.n == 0 and _jit._BG.worker is None  # loaded from the cache: no compile, no worker
assert poe.jacobian_space.stats.cache_hits
print("ok")
"""

MODES = PRELUDE + r"""
from robokit.errors import InputError
from robokit.kernels import _background
os.environ["ROBOKIT_COMPILE"] = "off"
for _ in range(3):
    J = poe.jacobian_body(S, q)
assert poe.jacobian_body.signatures == [] and Count.n == 0 and _jit._BG.worker is None
assert not any(f.endswith((".nbi", ".nbc")) for _, _, fs in os.walk(os.environ["NUMBA_CACHE_DIR"]) for f in fs)
os.environ["ROBOKIT_COMPILE"] = "eventually"
try:
    poe.jacobian_body(S, q)
except InputError as e:
    assert "ROBOKIT_COMPILE" in str(e) and "background" in str(e)
else:
    raise AssertionError("bad ROBOKIT_COMPILE accepted")
os.environ["ROBOKIT_COMPILE"] = "wait"
J2 = poe.jacobian_body(S, q)  # compiled here and now
assert len(poe.jacobian_body.signatures) == 1 and Count.n >= 1 and _jit._BG.worker is None
assert np.abs(J - J2).max() <= 1e-12
os.environ["ROBOKIT_COMPILE"] = "background"
_background._PACKAGE = "/nowhere/robokit"  # the worker's robokit is not ours: it refuses every job
first = poe.fkin_body(M, S, q)  # queued; runs as Python
until(lambda: poe.fkin_body(M, S, q) is not None and poe.fkin_body.signatures, "no fallback after a failure")
assert np.abs(poe.fkin_body(M, S, q) - first).max() <= 1e-12
def no_worker():
    raise OSError("no processes here")
_background.Worker = no_worker  # a worker that cannot start: compile here with a note
_jit._BG.worker = None  # as if the first worker had exited
n = Count.n
poe.jacobian_space(S, q)
assert len(poe.jacobian_space.signatures) == 1 and Count.n > n
print("ok")
"""


def _run(script, cache, mode="background"):
    env = dict(os.environ, NUMBA_CACHE_DIR=str(cache), ROBOKIT_COMPILE=mode,
               PYTHONPATH=str(ROOT) + os.pathsep + os.environ.get("PYTHONPATH", ""))
    env.pop("NUMBA_DISABLE_JIT", None)
    proc = subprocess.run([sys.executable, "-c", script], env=env, capture_output=True, text=True, timeout=1200)
    assert proc.returncode == 0, proc.stderr[-3000:]
    assert proc.stdout.strip().endswith("ok"), proc.stdout
    return proc


def _alive(pid):
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    return True


def test_background_compile_then_warm_cache(tmp_path):
    cold = _run(BACKGROUND, tmp_path)
    notices = [line for line in cold.stderr.splitlines() if line.startswith("robokit:")]
    assert "compiling course kernels in the background" in notices[0] and "first poe.fkin_space" in notices[0]
    assert any("waiting for poe.fkin_space_batch" in line for line in notices)
    assert "robokit: compiling poe kernels" not in cold.stderr  # nothing compiled in the process itself
    assert "still compiling in the background" in notices[-1]  # jacobian_space was left to the worker
    pid = int(cold.stdout.split("PID")[1].split()[0])
    t0 = time.monotonic()
    while _alive(pid):  # the worker finishes its queue after its parent has gone, then exits
        assert time.monotonic() - t0 < 900, "the worker did not exit"
        time.sleep(0.2)
    assert not list(tmp_path.rglob("*.tmp.*"))  # no half-written cache file
    warm = _run(WARM, tmp_path)
    assert "robokit:" not in warm.stderr


def test_off_wait_and_no_worker(tmp_path):
    proc = _run(MODES, tmp_path, mode="off")
    assert "robokit: compiling poe kernels" in proc.stderr  # the wait mode's notice
    assert "background compile of poe.fkin_body failed (RuntimeError: the worker imported robokit from" in proc.stderr
    assert "cannot start the background compile worker (OSError: no processes here)" in proc.stderr


# ---------------------------------------------------------------- the twins run the same source

def test_interpreted_twins_match_the_compiled_kernels():
    """Each twin against its compiled kernel (the suite runs with ROBOKIT_COMPILE=wait), including
    the IK solver, whose random restarts come from numba's generator: the twin draws the very same
    numbers from a generator of its own and leaves numpy's global one alone."""
    import robokit as rk
    from robokit.kernels import dynamics as kd, ik, poe

    r = rk.load("puma560")
    p = r.poe
    c = np.ascontiguousarray
    M, S, B, Ml, Gl, g = (np.array(a) for a in (p.M, p.Slist, p.Blist, p.Mlist, p.Glist, r.gravity))  # writeable copies, as the kernels take them
    rng = np.random.default_rng(3)
    q, dq, ddq = (c(rng.uniform(-2, 2, 6)) for _ in range(3))
    F = np.zeros(6)
    cases = [(poe.fkin_space, (M, S, q)), (poe.jacobian_body, (B, q)),
             (kd.inverse_dynamics, (q, dq, ddq, g, F, Ml, Gl, S)), (kd.mass_matrix, (q, Ml, Gl, S)),
             (kd.forward_dynamics, (q, dq, ddq, g, F, Ml, Gl, S)),
             (poe.fkin_space_batch, (M, S, c(rng.uniform(-2, 2, (4, 6)))))]
    for kernel, args in cases:
        assert np.abs(_jit.interpreted(kernel)(*args) - kernel(*args)).max() <= 1e-12, kernel.__name__
    T = c(r.frame_pose(c(rng.uniform(-2, 2, 6))))
    qlim = r.qlim.copy()  # a writeable copy of the read-only limits, as the kernel takes it
    args = (M, S, T, c(np.zeros(6)), qlim, 1e-10, 30, 50, 7)
    np.random.seed(123)
    before = np.random.random()
    np.random.seed(123)
    a, b = _jit.interpreted(ik.solve_poe_ik_kernel)(*args), ik.solve_poe_ik_kernel(*args)
    assert np.random.random() == before  # the twin did not reseed numpy's global generator
    assert a[1:] == b[1:] and np.abs(a[0] - b[0]).max() <= 1e-12


def test_mode_is_read_from_the_environment(monkeypatch):
    from robokit.errors import InputError

    monkeypatch.setenv("ROBOKIT_COMPILE", "OFF")
    assert _jit.compile_mode() == "off"
    monkeypatch.delenv("ROBOKIT_COMPILE")
    assert _jit.compile_mode() == "background"
    monkeypatch.setenv("ROBOKIT_COMPILE", "later")
    with pytest.raises(InputError, match="ROBOKIT_COMPILE: expected one of background, wait, off"):
        _jit.compile_mode()


def test_batch_size_decides_interpret_or_wait():
    from robokit.kernels import poe

    assert _jit._batch_work(poe.fkin_space_batch, (np.eye(4), np.zeros((6, 3)), np.zeros((10, 3)))) == 30
    assert _jit._batch_work(poe.fkin_space, (np.eye(4), np.zeros((6, 3)), np.zeros(3))) == 0
    assert poe.fkin_space._robokit_interpret > 10**9  # single calls always run as Python meanwhile
    assert poe.fkin_space_batch._robokit_interpret == _jit.FK_BATCH
    from robokit.kernels import dynamics, simulation

    assert dynamics.mass_matrix_batch._robokit_interpret == _jit.SMALL_BATCH
    assert simulation.simulate_control._robokit_interpret < 0  # a long loop: always waits


def test_worker_protocol_urgent_first_and_failures():
    """The worker's loop on pipes: urgent jobs first, every job answered, a job outside
    robokit.kernels refused, end of input ends it once the queue is done."""
    from robokit.kernels import _background, poe

    jobs = [f"1 robokit.kernels.poe fkin_space {_background.encode(poe.fkin_space._robokit_signature)}",
            f"2 os path {_background.encode('float64()')}",
            f"3 robokit.kernels.poe jacobian_body {_background.encode(poe.jacobian_body._robokit_signature)} urgent"]
    r_in, w_in = os.pipe()
    r_out, w_out = os.pipe()
    os.write(w_in, ("\n".join(jobs) + "\n").encode())
    os.close(w_in)
    with os.fdopen(r_in, "rb") as fin, os.fdopen(w_out, "wb") as fout:
        assert _background.serve(fin, fout) == 0
    with os.fdopen(r_out, "rb") as f:
        replies = f.read().decode().splitlines()
    assert [line.split()[:2] for line in replies] == [["ok", "3"], ["ok", "1"], ["fail", "2"]]
    assert "not a robokit kernel module" in replies[2]
    assert poe.jacobian_body.signatures and poe.fkin_space.signatures  # compiled (or loaded) into the cache


def test_cli_refuses_a_bad_mode_in_one_line():
    env = dict(os.environ, ROBOKIT_COMPILE="soon", PYTHONPATH=str(ROOT) + os.pathsep + os.environ.get("PYTHONPATH", ""))
    proc = subprocess.run([sys.executable, "-c", "import sys; from robokit.cli import main; sys.exit(main(['validate']))"],
                          env=env, capture_output=True, text=True, timeout=300)
    assert proc.returncode == 2 and proc.stdout == ""
    assert proc.stderr.strip().splitlines() == [
        "robokit: error: ROBOKIT_COMPILE: expected one of background, wait, off; got 'soon'"]
