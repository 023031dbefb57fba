"""The compile notice and lazy compilation: with a cold on-disk cache (a fresh NUMBA_CACHE_DIR)
the first call of a kernel compiles that kernel only — its batch twin and the module's other
kernels stay uncompiled — and prints one line naming it and counting; a warm cache prints nothing."""
import os
import pathlib
import subprocess
import sys

ROOT = pathlib.Path(__file__).resolve().parents[2]
SCRIPT = ("import numpy as np; from robokit.kernels import poe, _jit; "
          "print(_jit.cache_dir(poe.fkin_space)); "
          "print(poe.fkin_space(np.eye(4), np.eye(6)[:, :2].copy(), np.zeros(2))[0, 0]); "
          "print(len(poe.fkin_space.signatures), len(poe.fkin_space_batch.signatures), "
          "len(poe.jacobian_body.signatures))")


def _run(cache):
    env = dict(os.environ, NUMBA_CACHE_DIR=str(cache),
               PYTHONPATH=str(ROOT) + os.pathsep + os.environ.get("PYTHONPATH", ""))
    env.pop("NUMBA_DISABLE_JIT", None)
    return subprocess.run([sys.executable, "-c", SCRIPT], env=env, capture_output=True, text=True, timeout=600)


def test_lazy_compile_and_notice(tmp_path):
    cold = _run(tmp_path)
    assert cold.returncode == 0, cold.stderr[-2000:]
    lines = [line for line in cold.stderr.splitlines() if line.startswith("robokit: compiling")]
    import robokit.kernels.poe  # noqa: F401  (registers the poe kernels)
    from robokit.kernels import _jit

    count = len(_jit._KERNELS["poe"])  # the kernels with a signature in robokit/kernels/poe.py
    assert lines == [lines[0]] and f"poe kernels (1/{count}: fkin_space)" in lines[0]
    assert "first run only" not in cold.stderr
    out = cold.stdout.splitlines()
    assert out[0].startswith(str(tmp_path))  # the cache lives where numba was told
    assert out[2] == "1 0 0"  # only the kernel that was called is compiled
    assert any(tmp_path.rglob("*.nbi"))  # and numba wrote its index there
    warm = _run(tmp_path)
    assert warm.returncode == 0, warm.stderr[-2000:]
    assert "robokit: compiling" not in warm.stderr
    assert warm.stdout.splitlines()[2] == "1 0 0"


def test_wrong_types_still_raise_type_error():
    import numpy as np
    import pytest

    from robokit.kernels import poe

    with pytest.raises(TypeError):
        poe.fkin_space(np.eye(4), np.eye(6)[:, :2].copy(), np.zeros(2, dtype=np.float32))
    assert len(poe.fkin_space.signatures) == 1  # no second specialisation was built
