"""The main job: the course implementations against Pinocchio, as a table of largest errors.

Each area of robokit contributes rows through modules ``robokit/<area>/checks.py`` or
``robokit/<area>/checks_<topic>.py`` that define ``checks(rng) -> iterable of CheckRow``.
``run_all`` imports the ones that exist, areas in dependency order, modules by name, and
collects their rows; a check that raises becomes a failed row carrying the exception
text, so one broken area never hides the others.
"""
from __future__ import annotations

import functools
import importlib
import json
import math
import pkgutil
import time
import traceback
from dataclasses import asdict, dataclass, field

import numpy as np

AREAS = ("spatial", "description", "kinematics", "dynamics", "ik", "trajectory", "control", "mobile")


@dataclass
class CheckRow:
    """One row of the validation table.

    quantity  : what is compared, e.g. ``"matrix_exp_6 vs pinocchio.exp6"``.
    model     : robot model name, or ``"-"`` for robot-free checks.
    cases     : number of samples compared.
    max_error : the largest error over the samples (norm or relative error as ``metric`` says).
    tolerance : the row passes when ``max_error <= tolerance``.
    metric    : how the error is measured (e.g. ``"abs, Frobenius"``, ``"rel, inf-norm"``).
    note      : free text (e.g. the Pinocchio reference frame used).
    """

    quantity: str
    model: str
    cases: int
    max_error: float
    tolerance: float
    metric: str = "abs"
    note: str = ""
    error: str = field(default="")

    @property
    def passed(self) -> bool:
        return not self.error and math.isfinite(self.max_error) and self.max_error <= self.tolerance and self.cases > 0

    def as_dict(self) -> dict:
        d = asdict(self)
        d["passed"] = self.passed
        return d


@functools.lru_cache(maxsize=None)
def robot(name: str):
    """``robokit.load(name)``, loaded once per validation run and shared by the check modules."""
    from robokit.description.robot import load

    return load(name)


def max_error(pairs) -> float:
    """Largest ``‖a − b‖`` (Frobenius / 2-norm) over an iterable of ``(a, b)`` array pairs."""
    worst = 0.0
    for a, b in pairs:
        e = float(np.linalg.norm(np.asarray(a, dtype=float) - np.asarray(b, dtype=float)))
        if not math.isfinite(e):
            return math.inf
        worst = max(worst, e)
    return worst


def _check_modules(area: str) -> list[str]:
    try:
        pkg = importlib.import_module(f"robokit.{area}")
    except ModuleNotFoundError as exc:
        if exc.name == f"robokit.{area}":
            return []
        raise
    names = [m.name for m in pkgutil.iter_modules(pkg.__path__) if m.name == "checks" or m.name.startswith("checks_")]
    return [f"robokit.{area}.{n}" for n in sorted(names)]


def iter_rows(seed: int = 0, areas=AREAS):
    """Yield ``(module name, rows)`` as each check module finishes (areas in dependency order)."""
    for area in areas:
        try:
            modnames = _check_modules(area)
        except Exception as exc:
            yield f"robokit.{area}", [CheckRow(f"{area}: import", "-", 0, math.inf, 0.0, error=repr(exc))]
            continue
        for modname in modnames:
            try:
                mod = importlib.import_module(modname)
                rng = np.random.default_rng(seed)
                rows = list(mod.checks(rng))
            except Exception as exc:  # a broken check is a failed row, not a crash
                tb = traceback.format_exception_only(type(exc), exc)[-1].strip()
                rows = [CheckRow(f"{modname}: raised", "-", 0, math.inf, 0.0, error=tb)]
            yield modname, rows


def run_all(seed: int = 0, areas=AREAS) -> list[CheckRow]:
    """Run every available area's checks with a seeded generator; return all rows."""
    return [row for _, rows in iter_rows(seed, areas) for row in rows]


def format_table(rows: list[CheckRow]) -> str:
    """The rows as an aligned text table."""
    head = ("quantity", "model", "cases", "max error", "tol", "metric", "pass")
    body = [
        (
            r.quantity,
            r.model,
            str(r.cases),
            f"{r.max_error:.2e}" if math.isfinite(r.max_error) else "inf",
            f"{r.tolerance:.0e}",
            r.metric,
            "ok" if r.passed else "FAIL",
        )
        for r in rows
    ]
    widths = [max(len(x) for x in col) for col in zip(head, *body)]
    line = lambda cells: "  ".join(c.ljust(w) for c, w in zip(cells, widths)).rstrip()
    out = [line(head), line(tuple("-" * w for w in widths))]
    out += [line(b) for b in body]
    for r in rows:
        if r.error:
            out.append(f"  error in {r.quantity} [{r.model}]: {r.error}")
    return "\n".join(out)


#: Column widths of the streamed table (rows are printed as they are computed).
_WIDTHS = (58, 10, 5, 9, 5, 18, 4)


def _row_cells(r: CheckRow):
    return (
        r.quantity,
        r.model,
        str(r.cases),
        f"{r.max_error:.2e}" if math.isfinite(r.max_error) else "inf",
        f"{r.tolerance:.0e}",
        r.metric,
        "ok" if r.passed else "FAIL",
    )


def _line(cells) -> str:
    return "  ".join(c.ljust(w) for c, w in zip(cells, _WIDTHS)).rstrip()


def main(as_json: bool = False, seed: int = 0) -> int:
    """Run and print the table (rows streamed as each area finishes) or, with ``as_json``, one
    JSON document at the end. Returns the exit status: 0 if every row passes, else 1.

    On a terminal a progress line on stderr says which area is running; piped, the output is
    plain lines only.
    """
    import sys

    t0 = time.perf_counter()
    rows: list[CheckRow] = []
    progress = None
    if not as_json and sys.stderr.isatty():
        from rich.console import Console

        progress = Console(stderr=True).status("validating ...")
        progress.start()
    try:
        if not as_json:
            head = ("quantity", "model", "cases", "max error", "tol", "metric", "pass")
            print(_line(head))
            print(_line(tuple("-" * w for w in _WIDTHS)), flush=True)
        for modname, new in iter_rows(seed=seed):
            rows.extend(new)
            if progress is not None:
                progress.update(f"validating ... {modname.split('.')[1]} done ({len(rows)} rows)")
            if not as_json:
                for r in new:
                    print(_line(_row_cells(r)))
                    if r.error:
                        print(f"  error in {r.quantity} [{r.model}]: {r.error}")
                sys.stdout.flush()
    finally:
        if progress is not None:
            progress.stop()
    elapsed = time.perf_counter() - t0
    ok = bool(rows) and all(r.passed for r in rows)
    if as_json:
        print(json.dumps({"passed": ok, "seconds": round(elapsed, 3), "rows": [r.as_dict() for r in rows]}, indent=1))
    else:
        n_fail = sum(not r.passed for r in rows)
        print(f"\n{len(rows) - n_fail} passed, {n_fail} failed  ({elapsed:.1f} s)")
    return 0 if ok else 1
