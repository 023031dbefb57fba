"""The hardening suite's fixtures; its helpers are in hardening_support.py (put on sys.path here,
since the suite runs with --import-mode=importlib)."""
import sys
from pathlib import Path

import pytest

sys.path.insert(0, str(Path(__file__).resolve().parent))

import hardening_support as hs


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
