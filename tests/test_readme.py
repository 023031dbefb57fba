"""The README's code blocks run as written: every ```python block in a fresh interpreter, and
every `robokit ...` line of the ```sh blocks through the command line, in a temporary folder."""
import os
import re
import shlex
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
README = (ROOT / "README.md").read_text(encoding="utf-8")
PY_BLOCKS = re.findall(r"```python\n(.*?)```", README, flags=re.S)
SH_LINES = [ln.split("#")[0].strip() for block in re.findall(r"```sh\n(.*?)```", README, flags=re.S)
            for ln in block.splitlines() if ln.strip().startswith("robokit ")]


def _env():
    env = dict(os.environ, MPLBACKEND="Agg")
    env["PYTHONPATH"] = os.pathsep.join([str(ROOT), env.get("PYTHONPATH", "")]).rstrip(os.pathsep)
    return env


def test_readme_has_code():
    assert len(PY_BLOCKS) >= 6 and len(SH_LINES) >= 5


@pytest.mark.parametrize("code", PY_BLOCKS, ids=[f"python-{i}" for i in range(len(PY_BLOCKS))])
def test_readme_python_block_runs(code, tmp_path):
    proc = subprocess.run([sys.executable, "-c", code], cwd=tmp_path, env=_env(), capture_output=True,
                          text=True, timeout=600)
    assert proc.returncode == 0, proc.stderr[-2000:]


@pytest.mark.parametrize("line", SH_LINES, ids=[f"sh-{i}" for i in range(len(SH_LINES))])
def test_readme_command_runs(line, tmp_path):
    argv = shlex.split(line)[1:]
    proc = subprocess.run([sys.executable, "-m", "robokit.cli", *argv], cwd=tmp_path, env=_env(),
                          capture_output=True, text=True, timeout=600)
    assert proc.returncode == 0, (line, proc.stderr[-2000:])
    for i, a in enumerate(argv):  # every file the line says it writes exists and is not empty
        if a in ("-o", "--output"):
            assert (tmp_path / argv[i + 1]).stat().st_size > 0
