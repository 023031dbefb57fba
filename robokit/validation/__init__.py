"""The main job: the course implementations against Pinocchio, as a table of largest errors.

This package sits on top of robokit: it imports the course areas and Pinocchio and nothing
below imports it. ``AREAS`` is the one explicit list of what is compared, in dependency
order: each entry names a module of this package whose ``checks(rng)`` returns
:class:`~robokit.validation.core.CheckRow` rows over the robots of
:data:`~robokit.validation.core.MODELS`. A check that raises becomes a failed row carrying
the exception text, so one broken area never hides the others.
"""
from __future__ import annotations

import importlib
import json
import math
import time
import traceback
from typing import Any, Iterator, Sequence

import numpy as np

from robokit.validation.core import ARMS, MODELS, SHIPPED, CheckRow, max_error, only_robot, robot

__all__ = ["AREAS", "ROBOT_AREAS", "CheckRow", "robot", "max_error", "MODELS", "ARMS", "SHIPPED", "iter_rows", "run_all",
           "format_table", "main"]

#: The areas whose rows compare robots: what ``robokit validate MODEL`` runs on that robot.
ROBOT_AREAS = ("kinematics", "dynamics", "ik")

#: (area, module) in dependency order; the module is ``robokit.validation.<module>``.
AREAS = (
    ("spatial", "spatial"),
    ("description", "description"),
    ("description", "urdf_to_dh"),
    ("description", "mujoco"),
    ("kinematics", "kinematics"),
    ("dynamics", "dynamics"),
    ("ik", "ik"),
    ("trajectory", "trajectory"),
)


def iter_rows(seed: int = 0, areas: Sequence[tuple[str, str]] = AREAS) -> Iterator[tuple[str, list[CheckRow]]]:
    """Run the checks area by area, yielding each area's rows as soon as it finishes.

    A check module that raises gives one failed row carrying the exception text.

    Parameters
    ----------
    seed : int, optional
        Seed of each area's random generator (default 0: reproducible).
    areas : sequence of (str, str), optional
        ``(area, module)`` pairs, the module being ``robokit.validation.<module>`` (default
        :data:`AREAS`, all of them, in dependency order).

    Yields
    ------
    area : str
        The area's name.
    rows : list of CheckRow
        Its rows.

    Examples
    --------
    >>> [(area, len(rows) > 0) for area, rows in iter_rows(areas=[("trajectory", "trajectory")])]
    [('trajectory', True)]
    """
    for area, module in areas:
        modname = f"robokit.validation.{module}"
        try:
            mod = importlib.import_module(modname)
            rng = np.random.default_rng(seed)
            rows = list(mod.checks(rng))
        except Exception as exc:  # a broken check is a failed row, not a crash
            tb = traceback.format_exception_only(type(exc), exc)[-1].strip()
            rows = [CheckRow(f"{modname}: raised", "-", 0, math.inf, 0.0, error=tb)]
        yield area, rows


def run_all(seed: int = 0, areas: Sequence[tuple[str, str]] = AREAS) -> list[CheckRow]:
    """Run every area's checks with a seeded generator and return all rows.

    Parameters
    ----------
    seed : int, optional
        Seed of each area's random generator (default 0).
    areas : sequence of (str, str), optional
        ``(area, module)`` pairs (default :data:`AREAS`).

    Returns
    -------
    list of CheckRow
        The rows of every area, in order.

    Examples
    --------
    The trajectory checks (course time scalings and screw paths against Pinocchio's exp/log):

    >>> rows = run_all(areas=[("trajectory", "trajectory")])
    >>> all(r.passed for r in rows)
    True
    """
    return [row for _, rows in iter_rows(seed, areas) for row in rows]


def format_table(rows: list[CheckRow]) -> str:
    """The rows as an aligned text table (with the errors of failed checks below it).

    Parameters
    ----------
    rows : list of CheckRow
        The rows to print.

    Returns
    -------
    str
        A header line, a rule, one line per row (max error to 3 significant digits, ``ok`` or
        ``FAIL``).

    Examples
    --------
    >>> print(format_table([CheckRow("matrix_exp_6 vs pinocchio.exp6", "-", 100, 3.1e-16, 1e-9,
    ...                              "abs, Frobenius")]))
    quantity                        model  cases  max error  tol    metric          pass
    ------------------------------  -----  -----  ---------  -----  --------------  ----
    matrix_exp_6 vs pinocchio.exp6  -      100    3.10e-16   1e-09  abs, Frobenius  ok
    """
    head = ("quantity", "model", "cases", "max error", "tol", "metric", "pass")
    body = [_row_cells(r) for r in rows]
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


def _row_cells(r: CheckRow) -> tuple[str, ...]:
    return (
        r.quantity,
        r.model,
        str(r.cases),
        f"{r.max_error:.2e}" if math.isfinite(r.max_error) else "inf",
        f"{r.tolerance:.0e}",
        r.metric,
        "ok" if r.passed else "FAIL",
    )


def _line(cells: Sequence[str]) -> str:
    """One row of the streamed table; a quantity longer than its column wraps at a space onto a
    first line of its own, so the other columns stay aligned."""
    first, rest = cells[0], list(cells[1:])
    lead: list[str] = []
    width = _WIDTHS[0]
    while len(first) > width:
        cut = first.rfind(" ", 3, width + 1)  # after the continuation indent: always progress
        cut = width if cut < 3 else cut
        lead.append(first[:cut].rstrip())
        first = "  " + first[cut:].lstrip()
    row = "  ".join(c.ljust(w) for c, w in zip([first, *rest], _WIDTHS)).rstrip()
    return "\n".join([*lead, row])


def main(as_json: bool = False, seed: int = 0, areas: Sequence[str] | None = None, model: Any = None,
         tip: str | None = None, **load_options: Any) -> int:
    """What ``robokit validate`` runs: every check, printed as a table or as JSON.

    With ``model`` (``robokit validate MODEL``: a robot file, a shipped model or an example-robot-data
    name, loaded as :func:`robokit.load` loads it) only the robot rows run (:data:`ROBOT_AREAS`:
    kinematics, dynamics, ik), on that robot alone.

    Without ``as_json`` the rows are streamed as each area finishes; on a terminal a progress
    line on stderr says which area is running (piped, the output is plain lines only). robokit's
    compile notices (the kernels compiling in the background on a new machine) are held while the
    table prints and come after it, never between its lines; on a terminal the progress line
    shows them as they happen.

    Parameters
    ----------
    as_json : bool, optional
        Print one JSON document at the end instead of the table (default False).
    seed : int, optional
        Seed of the random samples (default 0).
    areas : sequence of str, optional
        Only these areas (names of :data:`AREAS`: ``spatial``, ``description``, ``kinematics``,
        ``dynamics``, ``ik``, ``trajectory``); default all (with ``model``: :data:`ROBOT_AREAS`).
    model : str, path or Robot, optional
        The one robot to compare (default: the shipped models and example-robot-data arms).
    tip : str, optional
        Its tip frame (``robokit.load``'s ``tip``).
    **load_options
        ``robokit.load``'s options for its file (``xacro_args``, ``package_dirs``, ...).

    Returns
    -------
    int
        The exit status: 0 if every row passes, else 1.

    Raises
    ------
    InputError
        An unknown area name (with ``model``, one that compares no robot), a negative ``seed``, or a
        model that does not load.
    """
    import sys

    from robokit.kernels._jit import held_notices

    if isinstance(seed, bool) or not isinstance(seed, (int, np.integer)) or seed < 0:
        from robokit.errors import InputError

        raise InputError(f"--seed: expected a non-negative integer, got {seed!r}")
    chosen: tuple[tuple[str, str], ...] = AREAS
    known = list(dict.fromkeys(a for a, _ in AREAS)) if model is None else list(ROBOT_AREAS)
    if areas:
        unknown = [a for a in areas if a not in known]
        if unknown:
            from robokit.errors import InputError

            which = "the areas are" if model is None else "the areas that compare a robot (MODEL) are"
            raise InputError(f"--area: unknown area {unknown[0]!r}; {which} {', '.join(known)}")
    chosen = tuple(x for x in AREAS if x[0] in (areas or known))
    only = None
    if model is not None:
        from robokit.description.loading import load
        from robokit.description.robot import Robot

        loaded = model if isinstance(model, Robot) else load(model, tip=tip, **load_options)
        if any(a == "ik" for a, _ in chosen):
            from robokit.ik import ik_analytic_kind

            kind = ik_analytic_kind(loaded)
            if not kind.method:
                print(f"robokit: note: {loaded.name}: no ik rows (no closed-form inverse kinematics: {kind.reason})",
                      file=sys.stderr)
        only = only_robot(loaded.name, loaded)
        only.__enter__()
    t0 = time.perf_counter()
    rows: list[CheckRow] = []
    progress = None
    if not as_json and sys.stderr.isatty():
        from rich.console import Console

        progress = Console(stderr=True).status("validating ...")
        progress.start()
    state = {"area": "", "notice": ""}

    def show_notice(line: str) -> None:  # a compile notice, held until the table is done
        if progress is not None:
            state["notice"] = line.removeprefix("robokit: ")[:90]
            progress.update(f"validating ... {state['area']} ({state['notice']})")

    held = held_notices(show_notice)
    held.__enter__()
    try:
        if not as_json:
            head = ("quantity", "model", "cases", "max error", "tol", "metric", "pass")
            print(_line(head))
            print(_line(tuple("-" * w for w in _WIDTHS)), flush=True)
        for modname, new in iter_rows(seed=seed, areas=chosen):
            rows.extend(new)
            state["area"] = f"{modname} done ({len(rows)} rows)"
            if progress is not None:
                progress.update(f"validating ... {state['area']}")
            if not as_json:
                for r in new:
                    print(_line(_row_cells(r)))
                    if r.error:
                        print(f"  error in {r.quantity} [{r.model}]: {r.error}")
                sys.stdout.flush()
        elapsed = time.perf_counter() - t0
        ok = bool(rows) and all(r.passed for r in rows)
        if as_json:
            print(json.dumps({"passed": ok, "seconds": round(elapsed, 3), "rows": [r.as_dict() for r in rows]},
                             indent=1))
        else:
            n_fail = sum(not r.passed for r in rows)
            print(f"\n{len(rows) - n_fail} passed, {n_fail} failed  ({elapsed:.1f} s)")
        sys.stdout.flush()
    finally:
        if progress is not None:
            progress.stop()
        held.__exit__(None, None, None)  # the compile notices, after the table
        if only is not None:
            only.__exit__(None, None, None)
    return 0 if ok else 1
