"""Notes about what a file reader ignored or adjusted, shown on stderr.

Readers of robot files (xacro, MJCF) call :func:`note` for every element they skip or
value they change. A note is a ``RobokitWarning`` (a ``UserWarning``): the ``robokit``
command prints it as one line ``robokit: note: ...``; in Python it shows like any warning
and is silenced with ``warnings.simplefilter("ignore", robokit.errors.RobokitWarning)``.
"""
from __future__ import annotations

import warnings

try:
    from robokit.errors import RobokitWarning
except ImportError:  # pragma: no cover - older robokit.errors without the warning class
    RobokitWarning = UserWarning  # type: ignore[misc, assignment]


def note(message: str) -> None:
    """Emit one note (whitespace collapsed to one line) as a ``RobokitWarning``."""
    from robokit._stack import outside_level

    warnings.warn(" ".join(str(message).split()), RobokitWarning, stacklevel=outside_level())
