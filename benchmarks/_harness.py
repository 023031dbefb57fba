"""A small timing harness for the benchmark scripts: warm-up, repeated runs, median, tables.

Times are per call, from ``time.perf_counter_ns`` over batches sized so that one batch
takes about ``target`` seconds; the reported figure is the median over ``repeats``
batches after one warm-up batch. Nothing here asserts on time: benchmarks print tables.
"""
from __future__ import annotations

import os
import platform
import statistics
import time


def machine() -> str:
    """One line describing the machine and the numeric stack the numbers were measured on."""
    import numpy as np

    try:
        import pinocchio as pin

        pin_v = pin.__version__
    except Exception:  # pragma: no cover
        pin_v = "n/a"
    cpu = platform.processor() or platform.machine()
    try:
        with open("/proc/cpuinfo") as fh:
            for line in fh:
                if line.startswith("model name"):
                    cpu = line.split(":", 1)[1].strip()
                    break
    except OSError:
        pass
    return (f"{cpu}, {os.cpu_count()} cores, Python {platform.python_version()}, numpy {np.__version__}, "
            f"pinocchio {pin_v}")


def time_call(fn, *args, repeats: int = 7, target: float = 0.05, **kwargs) -> float:
    """Median seconds per call of ``fn(*args, **kwargs)``."""
    fn(*args, **kwargs)  # warm-up
    t0 = time.perf_counter()
    fn(*args, **kwargs)
    one = max(time.perf_counter() - t0, 1e-7)
    number = max(1, int(target / one))
    samples = []
    for _ in range(repeats):
        t0 = time.perf_counter_ns()
        for _ in range(number):
            fn(*args, **kwargs)
        samples.append((time.perf_counter_ns() - t0) / number * 1e-9)
    return statistics.median(samples)


def fmt_time(seconds: float) -> str:
    """Seconds as a readable figure with a unit (ns, µs, ms, s)."""
    if seconds != seconds:  # NaN
        return "n/a"
    for unit, scale in (("s", 1.0), ("ms", 1e-3), ("µs", 1e-6), ("ns", 1e-9)):
        if seconds >= scale or unit == "ns":
            return f"{seconds / scale:.3g} {unit}"
    return f"{seconds:.3g} s"


def table(headers, rows) -> str:
    """A Markdown table (pastes into an issue note as it is)."""
    rows = [[str(c) for c in r] for r in rows]
    widths = [max(len(h), *(len(r[i]) for r in rows)) if rows else len(h) for i, h in enumerate(headers)]
    line = lambda cells: "| " + " | ".join(c.ljust(w) for c, w in zip(cells, widths)) + " |"
    out = [line(headers), "|" + "|".join("-" * (w + 2) for w in widths) + "|"]
    out += [line(r) for r in rows]
    return "\n".join(out)


def time_best(fn, *args, batches: int = 200, target: float = 0.002, **kwargs) -> float:
    """Seconds per call of ``fn(*args, **kwargs)``: the minimum over ``batches`` short batches of about
    ``target`` seconds each. On a shared, loaded machine the minimum is the least disturbed figure
    (a median of long batches mostly measures the other processes); peers timed the same way compare
    fairly."""
    fn(*args, **kwargs)  # warm-up
    t0 = time.perf_counter()
    fn(*args, **kwargs)
    one = max(time.perf_counter() - t0, 1e-7)
    number = max(1, int(target / one))
    best = float("inf")
    for _ in range(batches):
        t0 = time.perf_counter_ns()
        for _ in range(number):
            fn(*args, **kwargs)
        best = min(best, (time.perf_counter_ns() - t0) / number * 1e-9)
    return best
