"""Run a documentation page's Python as a reader would, and compare what it prints with what the page shows.

A page's ```python blocks run in order as one script — one namespace, top to bottom, like a notebook —
in a fresh interpreter (``python -c``, so that, as in a notebook, no worker process re-runs the page),
in a folder of the caller's choosing. What the page shows is found from the code itself:

* ``print(...)`` (or a ``for``/``with`` statement that prints) followed right away by comment lines
  ``# ...``: those lines, without their ``# ``, are its output line by line (a comment at the end of
  the statement's line then only describes it);
* otherwise ``print(...)  # shown`` — a top-level print whose line ends in a comment: that comment is
  its output;
* a statement followed right away by ``# SomeWarning: message`` lines: the warnings it raises
  (``category: message``, whitespace not significant);
* a ```text block right after a ```python block: the output of that block's last statement;
* a ``>>>`` block (doctest style): each ``>>> expression`` followed by the lines its value's repr shows,
  as the Python prompt shows them.

A single shown line matches the printed one when

* it says ``about X`` (X a number or several, ``about [0.8, 0.667]``): the numbers printed are as many,
  and each rounded to X's significant digits is X (an X below 1e-9 stands for round-off: the value is at
  most 10·X; an X of 0 for a value below 1e-9 in size);
* otherwise it is the printed text (or that text's repr: ``# 'analytic'``), or starts with it and a space
  or a colon and a space (``# 6 joints``, ``# (1000, 8, 6): ...``).

Several shown lines match line by line, whitespace not significant. Every other print runs unchecked;
every checked value is compared, never rounded into agreement: the numbers on the page are what the
code prints.
"""
from __future__ import annotations

import ast
import doctest
import io
import json
import os
import re
import subprocess
import sys
import tokenize
from dataclasses import dataclass
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]

_WARNING_LINE = re.compile(r"#\s*[A-Za-z_][\w.]*Warning: ")


@dataclass(frozen=True)
class Shown:
    """What the page shows for one statement: its output (``kind == "out"``) or its warnings."""

    kind: str
    text: str
    line: int  # the statement's first line in the page's script (1-based)
    source: str


def python_blocks(text: str) -> list[str]:
    return re.findall(r"^```python\n(.*?)^```", text, flags=re.S | re.M)


def _blocks_with_output(text: str) -> list[tuple[str, str | None]]:
    """Each ```python block, with the ```text block that follows it directly (its output), if any."""
    fences = list(re.finditer(r"^```(\w*)\n(.*?)^```[ \t]*\n", text, flags=re.S | re.M))
    out = []
    for i, f in enumerate(fences):
        if f.group(1) != "python":
            continue
        nxt = fences[i + 1] if i + 1 < len(fences) else None
        direct = nxt is not None and nxt.group(1) == "text" and not text[f.end():nxt.start()].strip()
        out.append((f.group(2), nxt.group(2) if direct else None))
    return out


def _doctest_block(block: str) -> str:
    """A ``>>>`` block as plain code: each example with output becomes ``_rk_display(expression)``
    followed by its output as comment lines."""
    out = []
    for ex in doctest.DocTestParser().get_examples(block):
        if ex.want:
            out += ["_rk_display((", ex.source.rstrip("\n"), "))"]
            out += [("# " + w).rstrip() for w in ex.want.rstrip("\n").splitlines()]
        else:
            out += ex.source.rstrip("\n").splitlines()
    return "\n".join(out) + "\n"


def page_code(text: str) -> str:
    """The page's Python blocks, in order, as one script (``>>>`` blocks made plain code; a ```text
    block right after a block, its output, as comment lines after it)."""
    parts = []
    for block, output in _blocks_with_output(text):
        parts.append(_doctest_block(block) if block.lstrip().startswith(">>>") else block)
        if output is not None:
            parts.append("".join(("# " + ln).rstrip() + "\n" for ln in output.splitlines()))
    return "".join(parts)


def _inline_comment(line: str) -> str | None:
    try:
        tokens = list(tokenize.generate_tokens(io.StringIO(line + "\n").readline))
    except (tokenize.TokenError, SyntaxError):
        return None
    comment = next((t for t in tokens if t.type == tokenize.COMMENT), None)
    return comment.string[1:].strip() if comment else None


def _calls_print(node: ast.AST) -> bool:
    return any(isinstance(n, ast.Call) and isinstance(n.func, ast.Name) and n.func.id in ("print", "_rk_display")
               for n in ast.walk(node))


def shown_values(code: str) -> dict[int, tuple[int, int, Shown]]:
    """Statement number -> (first line, last line, what the page shows), for the statements that show
    something."""
    lines = code.splitlines()
    found = {}
    for stmt in ast.parse(code).body:
        first, last = stmt.lineno, stmt.end_lineno or stmt.lineno
        following = []
        for nxt in lines[last:]:
            if not (nxt == "#" or nxt.startswith("# ")):
                break
            following.append(nxt)
        source = "\n".join(lines[first - 1:last])
        is_print = (isinstance(stmt, ast.Expr) and isinstance(stmt.value, ast.Call)
                    and isinstance(stmt.value.func, ast.Name) and stmt.value.func.id in ("print", "_rk_display"))
        inline = _inline_comment(lines[last - 1]) if is_print else None
        if following and _WARNING_LINE.match(following[0]):
            shown = Shown("warn", "\n".join(f[2:] for f in following), first, source)
        elif following and _calls_print(stmt):
            shown = Shown("out", "\n".join(f[2:] for f in following), first, source)
        elif inline:
            shown = Shown("out", inline, first, source)
        else:
            continue
        found[len(found)] = (first, last, shown)
    return found


_PRELUDE = '''\
import io as _rk_io, json as _rk_json, sys as _rk_sys, warnings as _rk_warnings
_RK_SHOWN = []
class _RkTee(_rk_io.TextIOBase):
    def __init__(self, out):
        self.out, self.parts = out, []
    def write(self, s):
        self.parts.append(s)
        return self.out.write(s)
    def flush(self):
        self.out.flush()
def _rk_display(value):
    if value is not None:
        print(repr(value))
def _rk_begin():
    global _rk_tee, _rk_catch, _rk_caught
    _rk_tee = _RkTee(_rk_sys.stdout)
    _rk_sys.stdout = _rk_tee
    _rk_catch = _rk_warnings.catch_warnings(record=True)
    _rk_caught = _rk_catch.__enter__()
    _rk_warnings.simplefilter("always")
def _rk_end(k):
    _rk_sys.stdout = _rk_tee.out
    _rk_catch.__exit__(None, None, None)
    for w in _rk_caught:
        _rk_warnings.showwarning(w.message, w.category, w.filename, w.lineno)
    _RK_SHOWN.append([k, "".join(_rk_tee.parts), [f"{w.category.__name__}: {w.message}" for w in _rk_caught]])
'''

_EPILOGUE = '''
with open({path!r}, "w", encoding="utf-8") as _rk_f:
    _rk_json.dump(_RK_SHOWN, _rk_f)
'''


def instrumented(code: str, record: str) -> tuple[str, dict[int, Shown]]:
    """The script with each statement that shows something between ``_rk_begin()`` and ``_rk_end(k)``
    (its output and warnings recorded, and still printed), writing the records to ``record`` at the end."""
    found = shown_values(code)
    starts = {first: k for k, (first, _, _) in found.items()}
    ends = {last: k for k, (_, last, _) in found.items()}
    out = [_PRELUDE]
    for i, line in enumerate(code.splitlines(), 1):
        if i in starts:
            out.append("_rk_begin()")
        out.append(line)
        if i in ends:
            out.append(f"_rk_end({ends[i]})")
    out.append(_EPILOGUE.format(path=str(record)))
    return "\n".join(out) + "\n", {k: shown for k, (_, _, shown) in found.items()}


_NUMBER = re.compile(r"[-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?")


def _about(x: float, v: float) -> bool:
    if x == 0:
        return abs(v) < 1e-9
    if abs(x) < 1e-9:
        return abs(v) <= 10 * abs(x)
    digits = len(re.sub(r"[^0-9]", "", f"{x:e}".split("e")[0]).rstrip("0")) or 1
    return float(f"{v:.{digits - 1}e}") == x


def matches(printed: str, shown: str) -> bool:
    """Whether ``printed`` (a statement's output, its final newline removed) is what the page shows."""
    if "\n" in shown or "\n" in printed:
        return [ln.split() for ln in printed.splitlines()] == [ln.split() for ln in shown.splitlines()]
    about = re.search(r"\babout ([-+0-9.eE\[\](),\s]+)", shown)
    if about:
        want = [float(x) for x in _NUMBER.findall(about.group(1))]
        got = [float(x) for x in _NUMBER.findall(printed)]
        return bool(want) and len(want) == len(got) and all(_about(x, v) for x, v in zip(want, got))
    return any(shown == c or shown.startswith((c + " ", c + ": ")) for c in (printed, repr(printed)))


def warnings_match(caught: list[str], shown: str) -> bool:
    return " ".join("\n".join(caught).split()) == " ".join(shown.split())


@dataclass
class PageRun:
    returncode: int
    stdout: str
    stderr: str
    shown: dict[int, Shown]
    recorded: list  # [k, output, warnings] per statement run

    def mismatches(self) -> list[str]:
        """Every shown value that is not what the code printed, and every statement that never ran."""
        wrong = []
        ran = {k for k, _, _ in self.recorded}
        for k, shown in self.shown.items():
            if k not in ran:
                wrong.append(f"line {shown.line}: never ran:\n{shown.source}")
        for k, out, caught in self.recorded:
            shown = self.shown[k]
            printed = out[:-1] if out.endswith("\n") else out
            if shown.kind == "warn":
                if not warnings_match(caught, shown.text):
                    wrong.append(f"line {shown.line}: the page shows the warning(s)\n{shown.text}\nthe code raised\n"
                                 + ("\n".join(caught) or "(none)") + f"\nin\n{shown.source}")
            elif not matches(printed, shown.text):
                wrong.append(f"line {shown.line}: the page shows\n{shown.text}\nthe code printed\n{printed}\n"
                             f"in\n{shown.source}")
        return wrong


def environment(env: dict[str, str] | None = None) -> dict[str, str]:
    """This process's environment, with ``env``, a non-interactive matplotlib, and this checkout's robokit."""
    run_env = dict(os.environ, MPLBACKEND="Agg", **(env or {}))
    run_env["PYTHONPATH"] = os.pathsep.join([str(ROOT), run_env.get("PYTHONPATH", "")]).rstrip(os.pathsep)
    return run_env


def run_page(page: Path, cwd: Path, env: dict[str, str] | None = None, timeout: float = 600) -> PageRun:
    """Run ``page``'s Python in ``cwd`` (a fresh interpreter importing robokit from this checkout)."""
    record = cwd / "_rk_shown.json"
    script, shown = instrumented(page_code(page.read_text(encoding="utf-8")), str(record))
    p = subprocess.run([sys.executable, "-c", script], cwd=cwd, env=environment(env), capture_output=True,
                       text=True, timeout=timeout)
    recorded = json.loads(record.read_text(encoding="utf-8")) if record.is_file() else []
    return PageRun(p.returncode, p.stdout, p.stderr, shown, recorded)
