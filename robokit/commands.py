"""The commands of the ``robokit`` command line: each runs one job through the library, writes its
file and says on stderr what it wrote. Argument parsing is in :mod:`robokit.cli`; the work is
in the modules these functions call. Errors propagate as exceptions (the CLI turns them into
one line and an exit status).
"""
from __future__ import annotations

import sys
from pathlib import Path

__all__ = ["convert_command"]


def convert_command(input, output, tip=None, convention="standard", **load_options) -> int:
    """``robokit convert``: write ``output`` (or print a DH table); notes on stderr. Returns 0."""
    from robokit.description.convert import convert

    if output is None and Path(str(input)).suffix.lower() in (".yaml", ".yml"):
        raise ValueError("-o/--output: required (e.g. -o robot.urdf)")
    text, notes = convert(input, output, tip=tip, convention=convention, **load_options)
    for note in notes:
        print(f"robokit: note: {note}", file=sys.stderr)
    if output is None:
        sys.stdout.write(text)
    else:
        print(f"wrote {output}", file=sys.stderr)
    return 0
