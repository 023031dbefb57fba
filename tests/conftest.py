"""Test-suite settings: a non-interactive matplotlib backend (no display is needed anywhere), and
kernels compiled in the calling process on a cache miss (``ROBOKIT_COMPILE=wait``) so that every
test runs the machine code, deterministically; tests/kernels/test_coldstart.py runs the background
mode in subprocesses of its own.

Shared helpers live in tests/support/ (``hardening_support``: the CLI run in-process or in a
subprocess and the one-line error contract; ``limited_cli``: the CLI under resource limits;
``shared_robots``: a robot (and the factory-calibrated UR5e) loaded once per process for the tests
that only compute with it;
``doc_pages``: a documentation page's Python run as a reader runs it, its shown values compared;
``pybullet_sdf`` and ``mujoco_site``: a loaded robot against PyBullet's ``loadSDF`` and MuJoCo), put
on sys.path here since the suite runs with --import-mode=importlib; the fixtures ``write`` and
``main_cli`` below serve every folder."""
import os
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))  # browser_support: the page tests' Chromium

os.environ.setdefault("MPLBACKEND", "Agg")
os.environ.setdefault("ROBOKIT_COMPILE", "wait")

import matplotlib  # noqa: E402

matplotlib.use("Agg")

import pytest  # noqa: E402
from hypothesis import settings as _hypothesis_settings  # noqa: E402

# Property tests (hypothesis) draw new random examples on every run of the suite: a developer's
# `make test` explores. CI (.ci/run exports ROBOKIT_HYPOTHESIS=ci) draws each test's examples from a
# seed of the test itself, the same on every machine and run, and keeps no example database: its
# verdict is the commit's, reproducible with `ROBOKIT_HYPOTHESIS=ci make test`, never a new random
# draw's. An example a developer's run finds is pinned in its test with @example.
_hypothesis_settings.register_profile("ci", derandomize=True, database=None)
if os.environ.get("ROBOKIT_HYPOTHESIS") == "ci":
    _hypothesis_settings.load_profile("ci")

sys.path.insert(0, str(Path(__file__).resolve().parent / "support"))

import hardening_support as hs  # noqa: E402


@pytest.fixture
def write(tmp_path):
    """``write(name, text_or_bytes) -> Path`` in the test's tmp folder."""
    def _write(name, content):
        p = tmp_path / name
        p.parent.mkdir(parents=True, exist_ok=True)
        if isinstance(content, bytes):
            p.write_bytes(content)
        else:
            p.write_text(content, encoding="utf-8")
        return p

    return _write


@pytest.fixture
def main_cli(capfd):
    """``main_cli(*args) -> Run``: robokit.cli.main in-process; stdout/stderr captured at the file
    descriptors, so that what native code (urdfdom) writes to fd 2 is seen too."""
    return lambda *args: hs.run_main(args, capfd)
