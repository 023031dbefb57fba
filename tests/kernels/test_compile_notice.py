"""The one-line compile notice: printed once on stderr when the kernels' on-disk cache is cold,
not printed when it is warm (a fresh NUMBA_CACHE_DIR makes the cache cold)."""
import os
import pathlib
import subprocess
import sys

ROOT = pathlib.Path(__file__).resolve().parents[2]
NOTICE = "compiling course kernels (first run only) ..."
SCRIPT = ("import numpy as np; from robokit.kernels import poe, _jit; "
          "print(_jit.cache_dir(poe.fkin_space)); "
          "print(poe.fkin_space(np.eye(4), np.eye(6)[:, :2].copy(), np.zeros(2))[0, 0])")


def _run(cache):
    env = dict(os.environ, NUMBA_CACHE_DIR=str(cache),
               PYTHONPATH=str(ROOT) + os.pathsep + os.environ.get("PYTHONPATH", ""))
    env.pop("NUMBA_DISABLE_JIT", None)
    return subprocess.run([sys.executable, "-c", SCRIPT], env=env, capture_output=True, text=True, timeout=600)


def test_notice_once_when_cold_and_never_when_warm(tmp_path):
    cold = _run(tmp_path)
    assert cold.returncode == 0, cold.stderr[-2000:]
    assert cold.stderr.count(NOTICE) == 1
    assert cold.stdout.splitlines()[0].startswith(str(tmp_path))  # the cache lives where numba was told
    assert any(tmp_path.rglob("*.nbi"))  # and numba wrote its index there
    warm = _run(tmp_path)
    assert warm.returncode == 0, warm.stderr[-2000:]
    assert NOTICE not in warm.stderr
