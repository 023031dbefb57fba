r"""Compile every course kernel ahead of first use, in parallel: ``python -m robokit.kernels``.

Each kernel is otherwise compiled when it is first needed — by default in a background worker
while its first calls run as plain Python (:mod:`robokit.kernels._jit`), about a second each on a
laptop, then loaded from numba's on-disk cache in later processes. For a machine image, a container or
a CI cache, compiling all of them once up front removes every later wait; this runs them in
``jobs`` worker processes (default: one per CPU core) that write numba's cache, and prints
``compiling course kernels (k/N: module.kernel, t s)`` as each finishes.

Example::

    python -m robokit.kernels            # all kernels, one worker per core
    python -m robokit.kernels --jobs 1 poe dynamics
"""
from __future__ import annotations

import argparse
import importlib
import multiprocessing
import os
import sys
import time
from concurrent.futures import ProcessPoolExecutor, as_completed
from typing import Sequence, TextIO

__all__ = ["MODULES", "kernels", "warm", "main"]

#: The kernel modules, in the order their kernels are listed.
MODULES = ("poe", "dynamics", "packed", "dh", "ik", "simulation", "regressor")


def kernels(modules: Sequence[str] = MODULES) -> list[tuple[str, str]]:
    """``(module, kernel)`` for every kernel with a declared signature in ``modules``.

    Parameters
    ----------
    modules : names of kernel modules (``"poe"``, ``"dynamics"``, …).

    Returns
    -------
    list of (module, kernel name), in definition order.

    Example: ``("poe", "fkin_space") in kernels(["poe"])``.
    """
    from robokit.kernels import _jit

    for m in modules:
        importlib.import_module(f"robokit.kernels.{m}")
    return [(m, name) for m in modules for name in _jit._KERNELS.get(m, [])]


def _compile_one(item: tuple[str, str]) -> tuple[str, str, float]:
    from robokit.kernels import _jit

    _jit.quiet = True
    module, name = item
    t0 = time.perf_counter()
    _jit.compile_now(getattr(importlib.import_module(f"robokit.kernels.{module}"), name))
    return module, name, time.perf_counter() - t0


def warm(modules: Sequence[str] = MODULES, jobs: int | None = None, stream: TextIO | None = None) -> int:
    """Compile (or load from the cache) every kernel of ``modules`` in ``jobs`` processes.

    Parameters
    ----------
    modules : kernel modules to compile; jobs : worker processes (default ``os.cpu_count()``);
    stream : where progress lines go (default stderr).

    Returns
    -------
    int : how many kernels were compiled or found in the cache.

    Example: ``warm(["poe"], jobs=1)``.
    """
    out = sys.stderr if stream is None else stream
    items = kernels(modules)
    jobs = max(1, min(len(items), jobs or os.cpu_count() or 1))
    ctx = multiprocessing.get_context("spawn")  # fresh interpreters: no numba state inherited
    with ProcessPoolExecutor(jobs, mp_context=ctx) as pool:
        futures = [pool.submit(_compile_one, item) for item in items]
        for k, fut in enumerate(as_completed(futures), 1):
            module, name, seconds = fut.result()
            print(f"compiling course kernels ({k}/{len(items)}: {module}.{name}, {seconds:.1f} s)", file=out,
                  flush=True)
    return len(items)


def main(argv: Sequence[str] | None = None) -> int:
    """Command line of ``python -m robokit.kernels [--jobs J] [MODULE ...]``; returns the exit status."""
    ap = argparse.ArgumentParser(prog="python -m robokit.kernels", description=__doc__.splitlines()[0])
    ap.add_argument("modules", nargs="*", default=[], metavar="MODULE",
                    help=f"kernel modules ({', '.join(MODULES)}); default all")
    ap.add_argument("--jobs", type=int, default=None, help="worker processes (default: one per core)")
    args = ap.parse_args(argv)
    unknown = sorted(set(args.modules) - set(MODULES))
    if unknown:
        ap.error(f"MODULE: unknown kernel module(s) {', '.join(unknown)}; expected some of {', '.join(MODULES)}")
    t0 = time.perf_counter()
    n = warm(args.modules or MODULES, args.jobs)
    print(f"{n} kernels ready in {time.perf_counter() - t0:.1f} s", file=sys.stderr)
    return 0
