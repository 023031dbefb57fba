r"""Numbers in the text tables robokit reads (the calibration CSV, a ``--trajectory`` CSV): one
syntax of a number, one reader of rows, every error an :class:`~robokit.errors.InputError` naming
the file, the line and the column.

**A number** is written in ASCII as an optional sign, digits with an optional decimal point, and
an optional exponent — ``-0.5``, ``12``, ``.25``, ``1.5e-3``, ``2E+04`` — with spaces or tabs
around it allowed. Nothing else is a number, though Python's ``float`` accepts it: no ``1_0``,
no digits of other scripts (``١٢``), no ``inf``/``nan``, no hexadecimal; and its magnitude is at
most :data:`~robokit._arrays.MAX_MAGNITUDE` (1e12), the bound every number of a robot file has.

**A table** is lines separated by ``\n``, ``\r\n`` or ``\r``; cells separated by commas, each
stripped of spaces and tabs and of one pair of enclosing double quotes (a spreadsheet's
``"q1"``). Blank lines and lines starting with ``#`` are skipped. A line is at most
:data:`MAX_LINE` characters. The reader never uses Python's ``csv`` module, whose errors (a cell
over 131,072 characters, a NUL byte) are neither named nor bounded.
"""
from __future__ import annotations

import math
import re
from typing import Iterator, Sequence

from robokit._arrays import MAX_MAGNITUDE
from robokit.errors import InputError

__all__ = ["MAX_LINE", "NUMBER", "parse_number", "table_lines", "number_row"]

#: The syntax of a number (used with ``fullmatch``; ``[0-9]`` is ASCII only, unlike ``\d``).
NUMBER = re.compile(r"[+-]?(?:[0-9]+(?:\.[0-9]*)?|\.[0-9]+)(?:[eE][+-]?[0-9]+)?")
#: Longest line of a table (characters): a row of 128 joint values at 25 digits is 3.3 kB.
MAX_LINE = 16_384
_LINE_BREAK = re.compile(r"\r\n|\r|\n")


def parse_number(text: str, where: str) -> float:
    """The number ``text`` holds (see the module docstring), or :class:`InputError` naming ``where``.

    Parameters
    ----------
    text : str
        The cell, spaces and tabs around it allowed.
    where : str
        The file, line and column, for the message.

    Returns
    -------
    float

    Raises
    ------
    InputError
        ``WHERE: not a number ('1_0'); …``, ``not a finite number``, ``out of range``.

    Examples
    --------
    >>> parse_number(" 1.5e-3 ", "d.csv: line 2, column 1")
    0.0015
    >>> parse_number("1_0", "d.csv: line 2, column 1")
    Traceback (most recent call last):
    ...
    robokit.errors.InputError: d.csv: line 2, column 1: not a number ('1_0'); a number is written like -0.5, 12 or 1.5e-3
    """
    t = text.strip(" \t")
    if not NUMBER.fullmatch(t):
        return _fail(where, f"not a number ({t[:40]!r}); a number is written like -0.5, 12 or 1.5e-3")
    v = float(t)
    if not math.isfinite(v):
        return _fail(where, f"not a finite number ({t[:40]!r})")
    if abs(v) > MAX_MAGNITUDE:
        return _fail(where, f"{v:g} is out of range (at most {MAX_MAGNITUDE:g} in magnitude; SI units)")
    return v


def _fail(where: str, what: str) -> float:
    raise InputError(f"{where}: {what}")


def table_lines(text: str, source: str) -> Iterator[tuple[int, list[str]]]:
    """The rows of a table: ``(line number, cells)`` for every line that is not blank or a comment.

    Parameters
    ----------
    text : str
        The file's text.
    source : str
        The file, for the messages.

    Yields
    ------
    (int, list of str)
        The 1-based line number and the line's cells (stripped, unquoted).

    Raises
    ------
    InputError
        ``SOURCE: line L, column C: the line is longer than 16384 characters`` (C the cell where it
        crosses the bound); ``SOURCE: line L, column C: a double quote inside a cell``.

    Examples
    --------
    >>> list(table_lines('# made by hand\\n"q1", q2\\n\\n0.5,1\\n', "d.csv"))
    [(2, ['q1', 'q2']), (4, ['0.5', '1'])]
    """
    for k, line in enumerate(_LINE_BREAK.split(text), 1):
        if len(line) > MAX_LINE:
            c = line.count(",", 0, MAX_LINE) + 1
            raise InputError(f"{source}: line {k}, column {c}: the line is longer than {MAX_LINE} characters")
        stripped = line.strip(" \t")
        if not stripped or stripped.startswith("#"):
            continue
        cells = []
        for c, cell in enumerate(line.split(","), 1):
            cell = cell.strip(" \t")
            if len(cell) >= 2 and cell[0] == cell[-1] == '"':
                cell = cell[1:-1]
            if '"' in cell:
                raise InputError(f"{source}: line {k}, column {c}: a double quote inside a cell ({cell[:40]!r})")
            cells.append(cell)
        yield k, cells


def number_row(cells: Sequence[str], source: str, line: int, names: Sequence[str] | None = None) -> list[float]:
    """The numbers of one row, each cell read by :func:`parse_number`.

    Parameters
    ----------
    cells : sequence of str
        The row's cells (from :func:`table_lines`).
    source : str
        The file.
    line : int
        The row's line number.
    names : sequence of str, optional
        Column names (the header), shown with the column number.

    Returns
    -------
    list of float

    Raises
    ------
    InputError
        ``SOURCE: line L, column C ('q2'): not a number …``.

    Examples
    --------
    >>> number_row(["0.5", "1"], "d.csv", 4, ["q1", "q2"])
    [0.5, 1.0]
    """
    out = []
    for c, cell in enumerate(cells):
        label = f" ({names[c]!r})" if names is not None and c < len(names) else ""
        out.append(parse_number(cell, f"{source}: line {line}, column {c + 1}{label}"))
    return out
