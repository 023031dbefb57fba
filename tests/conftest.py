"""Test-suite settings: a non-interactive matplotlib backend (no display is needed anywhere), and
kernels compiled in the calling process on a cache miss (``ROBOKIT_COMPILE=wait``) so that every
test runs the machine code, deterministically; tests/kernels/test_coldstart.py runs the background
mode in subprocesses of its own."""
import os
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))  # browser_support: the page tests' Chromium

os.environ.setdefault("MPLBACKEND", "Agg")
os.environ.setdefault("ROBOKIT_COMPILE", "wait")

import matplotlib  # noqa: E402

matplotlib.use("Agg")
