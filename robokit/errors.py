"""Exceptions raised by robokit.

``InputError`` is a ``ValueError``: bad input (a wrong shape, a non-finite value, a
malformed file) raises it, or a plain ``ValueError``/``TypeError``, with a message that
names the argument and what was received. The CLI turns these into one line on stderr
and exit status 2.
"""


class RobokitError(Exception):
    """Base class of robokit's own exceptions."""


class InputError(RobokitError, ValueError):
    """Bad input: the message names the argument (or file, link and key) and what was wrong."""
