"""Where a warning about the user's input should point: the user's own line, not robokit's."""
from __future__ import annotations

import os
import sys

_PACKAGE = os.path.dirname(os.path.abspath(__file__)) + os.sep


def outside_level() -> int:
    """The ``stacklevel`` that makes a ``warnings.warn`` call, made by the function that calls this one,
    name the first frame outside the robokit package: the line of the user's own code that loaded the
    robot, say, however deep robokit's readers are below it. When every frame is robokit's (the
    ``robokit`` command), the outermost of them.

    Examples
    --------
    >>> import warnings
    >>> def f():
    ...     warnings.warn("x", UserWarning, stacklevel=outside_level())
    >>> outside_level() >= 1
    True
    """
    frame = sys._getframe(1)  # the function about to call warnings.warn: stacklevel 1
    level = 1
    while frame.f_back is not None and os.path.abspath(frame.f_code.co_filename).startswith(_PACKAGE):
        frame, level = frame.f_back, level + 1
    return level
