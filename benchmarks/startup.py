"""Start-up time: how long a new process takes to be ready, beside the peers measured in the same run.

Each row starts a fresh interpreter ``--repeats`` times (after one warm-up start, so the files are
in the page cache) and reports the minimum and the median wall time of the whole process, and the
median's ratio to ``python -c "import pinocchio"`` (robokit's own dependency: the floor a
Pinocchio-based tool starts from). Rows: ``python -c pass`` (the interpreter alone),
``import pinocchio``, ``import numba``, ``import robokit``, ``robokit --version``, ``robokit --help``,
and ``import robokit`` plus ``robokit.load("ur5")`` (the first thing a notebook does). The processes
run in a temporary folder, so the robokit measured is the one installed in this interpreter's
environment (``--python`` chooses another interpreter: compare two checkouts' venvs in one run).

Nothing is asserted (issue 40's targets — ``--version``/``--help`` ≤ 0.3 s, ``import robokit`` ≤ 0.5 s
on an idle machine — are read off the table). ``python -X importtime -c "import robokit"`` shows
where the time of a slow import goes.

Run: ``python -m benchmarks.startup [--repeats N] [--python PATH ...]``.
"""
from __future__ import annotations

import argparse
import os
import shutil
import statistics
import subprocess
import sys
import tempfile
import time

from benchmarks._harness import machine, table


def _rows(python: str) -> list[tuple[str, list[str]]]:
    script = os.path.join(os.path.dirname(python), "robokit")
    cli = [script] if os.path.exists(script) else [python, "-m", "robokit"]
    return [
        ("python -c pass", [python, "-c", "pass"]),
        ("import pinocchio", [python, "-c", "import pinocchio"]),
        ("import numba", [python, "-c", "import numba"]),
        ("import robokit", [python, "-c", "import robokit"]),
        ("robokit --version", cli + ["--version"]),
        ("robokit --help", cli + ["--help"]),
        ("import robokit; robokit.load('ur5')", [python, "-c", "import robokit; robokit.load('ur5')"]),
    ]


def _time(cmd: list[str], repeats: int, cwd: str) -> tuple[float, float]:
    env = {k: v for k, v in os.environ.items() if k != "PYTHONPATH"}
    subprocess.run(cmd, cwd=cwd, env=env, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, check=True)
    samples = []
    for _ in range(repeats):
        t0 = time.perf_counter()
        subprocess.run(cmd, cwd=cwd, env=env, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, check=True)
        samples.append(time.perf_counter() - t0)
    return min(samples), statistics.median(samples)


def main(argv: list[str] | None = None) -> None:
    ap = argparse.ArgumentParser(prog="python -m benchmarks.startup", description=__doc__.split("\n")[0])
    ap.add_argument("--repeats", type=int, default=7, help="starts per row (default 7)")
    ap.add_argument("--quick", action="store_true", help="3 starts per row")
    ap.add_argument("--python", action="append", default=[], help="interpreter(s) to measure (default: this one)")
    args, _ = ap.parse_known_args(argv)
    repeats = 3 if args.quick else args.repeats
    pythons = args.python or [sys.executable]
    print(f"## Start-up time (wall, whole process; {repeats} starts per row after one warm-up)\n")
    print(machine())
    print(f"load average {os.getloadavg()[0]:.2f} on {os.cpu_count()} cores at the start\n")
    cwd = tempfile.mkdtemp(prefix="rk-startup-")
    try:
        for python in pythons:
            if len(pythons) > 1:
                print(f"### {python}\n")
            rows = []
            measured = [(name, *_time(cmd, repeats, cwd)) for name, cmd in _rows(python)]
            ref = dict((n, med) for n, _, med in measured)["import pinocchio"]
            for name, best, med in measured:
                rows.append([name, f"{best:.3f} s", f"{med:.3f} s", f"{med / ref:.2f}×"])
            print(table(["command", "min", "median", "median / import pinocchio"], rows))
            print()
    finally:
        shutil.rmtree(cwd, ignore_errors=True)
    print(f"load average {os.getloadavg()[0]:.2f} at the end")


if __name__ == "__main__":
    main()
