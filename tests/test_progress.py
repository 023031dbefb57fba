"""A slow first use says what is happening while it happens (issue 40): one line, then the elapsed
time, then how long it took — and nothing when the step is quick. Checked on
:class:`robokit._progress.Slow` itself and where it is wired in: an optional import through
``robokit._optional.require`` (a first ``retime`` imports TOPP-RA) and the wait for a background
compile (a first ``simulate``). Slowness is simulated (a delayed import, a fake compile worker):
nothing here times robokit."""
import io
import os
import re
import subprocess
import sys
import time
from pathlib import Path

import pytest

from robokit._progress import Slow

ROOT = Path(__file__).resolve().parents[1]


class _Tty(io.StringIO):
    def isatty(self):
        return True


def test_a_slow_step_gets_a_line_then_progress_then_its_total():
    out = io.StringIO()
    with Slow("robokit: doing X ...", after=0.1, every=0.2, done="robokit: X", stream=out, still="still doing X"):
        time.sleep(1.5)
    lines = out.getvalue().splitlines()
    assert lines[0] == "robokit: doing X ..."
    ticks = lines[1:-1]
    assert len(ticks) >= 2 and all(re.fullmatch(r"robokit: \.\.\. still doing X, \d+ s", t) for t in ticks), lines
    assert re.fullmatch(r"robokit: X in \d+\.\d s", lines[-1]), lines


def test_a_quick_step_prints_nothing():
    out = io.StringIO()
    with Slow("robokit: doing X ...", after=0.5, done="robokit: X", stream=out):
        pass
    assert out.getvalue() == ""


def test_on_a_terminal_the_line_is_rewritten_in_place():
    out = _Tty()
    with Slow("robokit: doing X ...", after=0.0, done="robokit: X", stream=out):
        time.sleep(2.5)
    text = out.getvalue()
    assert text.startswith("robokit: doing X ...\r") and re.search(r"\rrobokit: doing X \.\.\. \d+ s", text)
    assert text.count("\n") == 2 and re.search(r"\nrobokit: X in \d+\.\d s\n$", text), repr(text)


def test_a_failing_step_propagates_without_a_done_line():
    out = io.StringIO()
    with pytest.raises(KeyError):
        with Slow("robokit: doing X ...", after=0.0, done="robokit: X", stream=out):
            time.sleep(0.1)
            raise KeyError("x")
    assert out.getvalue() == "robokit: doing X ...\n"


def test_a_slow_optional_import_says_so():
    """``require`` of a package whose import takes 3 s (a finder delays it, in a fresh interpreter):
    the announcement names the package and what needs it, then the total."""
    code = r"""
import sys, time, importlib.abc
class Slow(importlib.abc.MetaPathFinder):
    def find_spec(self, name, path, target=None):
        if name == "sympy":
            time.sleep(3.0)
        return None
sys.meta_path.insert(0, Slow())
from robokit._optional import require
require("sympy", "robokit.symbolic")
require("sympy", "robokit.symbolic")  # imported already: silent
"""
    p = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, cwd=ROOT, timeout=120)
    assert p.returncode == 0, p.stderr
    lines = p.stderr.strip().splitlines()
    assert lines[0].startswith("robokit: robokit.symbolic: importing sympy (its first use in this process")
    assert re.fullmatch(r"robokit: sympy imported in \d+\.\d s", lines[-1]) and len(lines) == 2, lines


def test_waiting_for_a_background_compile_shows_progress(monkeypatch, capsys):
    """``_jit._wait_for`` (a simulation kernel waits for the worker) with a fake worker that
    finishes the job after 1.2 s: the waiting line at once, then the total."""
    from robokit.kernels import _jit, poe

    r, w = os.pipe()
    t0 = time.monotonic()

    class FakeWorker:
        dead = False
        fileno = r

        def poll(self):
            return [("ok", 1, "1.2")] if time.monotonic() - t0 > 1.2 else []

    job = _jit._Job(1, poe.fkin_space, poe.fkin_space._robokit_signature)
    bg = _jit._Background()
    bg.worker, bg.by_number = FakeWorker(), {1: job}
    monkeypatch.setattr(_jit, "_BG", bg)
    monkeypatch.setattr(_jit, "quiet", False)
    try:
        _jit._wait_for(job)
    finally:
        os.close(r)
        os.close(w)
    assert job.state == "ready"
    lines = capsys.readouterr().err.strip().splitlines()
    assert lines[0].startswith("robokit: waiting for poe.fkin_space to compile")
    assert re.fullmatch(r"robokit: poe\.fkin_space compiled in \d+\.\d s", lines[-1]), lines
