"""The package type-checks: ``python -m mypy robokit`` (configured in pyproject.toml) exits 0.

robokit ships ``py.typed``, so its annotations are a promise to users' type checkers; this test
keeps them true. Modules under ``disallow_untyped_defs`` must annotate every function.
"""
import importlib.util
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]


@pytest.mark.skipif(importlib.util.find_spec("mypy") is None, reason="mypy is not installed (the 'test' extra)")
def test_mypy_clean():
    proc = subprocess.run([sys.executable, "-m", "mypy", "robokit"], cwd=ROOT, capture_output=True, text=True)
    assert proc.returncode == 0, f"mypy failed (exit {proc.returncode}):\n{proc.stdout}\n{proc.stderr}"
