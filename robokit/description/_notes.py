"""Notes about what a file reader ignored or adjusted, shown on stderr.

Readers of robot files (xacro, MJCF) call :func:`note` for every element they skip or
value they change. The notes go to the ``robokit.formats`` logger at WARNING level: with no
logging configured, Python prints the bare message on stderr; applications silence them
with ``logging.getLogger("robokit.formats").setLevel(logging.ERROR)``.
"""
from __future__ import annotations

import logging

LOGGER = logging.getLogger("robokit.formats")


def note(message: str) -> None:
    """Emit one note (one line, prefixed ``robokit: note:``) on the ``robokit.formats`` logger."""
    LOGGER.warning("robokit: note: %s", " ".join(str(message).split()))
