"""Exceptions raised by robokit.

Every deliberate check in robokit raises :class:`InputError` (a ``ValueError``): bad input (a
wrong shape, a non-finite value, a complex or non-numeric array, a malformed or hostile file),
with a message that names the argument (or the file, link and key) and what was received.
A wrong *type* (a string where a number is needed, a robot where a table is needed) raises
:class:`InputTypeError`, which is an ``InputError`` and also a ``TypeError``, so that both
``except ValueError`` and ``except TypeError`` code keep working. The CLI maps ``InputError``
(and an ``OSError`` on a file the user named) to one line on stderr and exit status 2, and
any other exception to exit status 3 (a bug): no heuristics. Plain ``ValueError``/``TypeError``
raises are banned outside the compiled kernels (``tests/hardening/test_errors_by_type.py``).
"""


class RobokitError(Exception):
    """Base class of robokit's own exceptions.

    Attributes
    ----------
    args : tuple
        As for any exception: robokit raises it with one message string, ``args == (message,)``.
    """


class InputError(RobokitError, ValueError):
    """Bad input: the message names the argument (or file, link and key) and what was wrong.

    A ``ValueError``, so ``except ValueError`` code keeps working; the CLI prints it as one
    ``robokit: error: ...`` line and exits with status 2.

    Attributes
    ----------
    args : tuple
        ``(message,)``: what was wrong, starting with the argument's name
        (``"q: expected shape (6,), got (5,)"``).

    Examples
    --------
    >>> try:
    ...     rk.normalize([0.0, 0.0, 0.0])
    ... except rk.InputError as e:
    ...     print(isinstance(e, ValueError))
    True
    """


class MissingExtraError(InputError, ImportError):
    """An optional dependency is not installed: the message names the extra that brings it
    (``pip install 'robokit[viz]'``). It is an ``ImportError`` for Python callers and, like any
    ``InputError``, one line and exit status 2 from the CLI."""

    def __init__(self, message: str, extra: str = "") -> None:
        super().__init__(message)
        self.extra = extra


class InputTypeError(InputError, TypeError):
    """Bad input of the wrong type (e.g. a string where a number is needed); an :class:`InputError`."""


class RobokitWarning(UserWarning):
    """Something robokit did on the user's behalf that they should know (a mesh not found and
    drawn without, a floating base fixed, a tree's tip chosen); the CLI prints it as one line.

    Attributes
    ----------
    args : tuple
        ``(message,)``, as ``warnings.warn(message, RobokitWarning)`` makes it.
    """


class PhysicalityWarning(RobokitWarning):
    """A link's inertia is physically impossible: it is not positive definite (a negative
    principal moment, or a zero mass with a nonzero rotational inertia) or its principal moments
    break the triangle inequality ``I1 + I2 ≥ I3``. The robot loads with one such warning per
    link, naming the link and the inequality with its numbers; ``robokit.load(..., strict=True)``
    refuses it with an :class:`InputError` instead.

    Attributes
    ----------
    args : tuple
        ``(message,)``: ``"<file>: link 'link2': principal moments ... break the triangle inequality ..."``.

    Examples
    --------
    >>> issubclass(PhysicalityWarning, RobokitWarning) and issubclass(PhysicalityWarning, UserWarning)
    True
    """


class DegreesWarning(RobokitWarning):
    """A joint value looks like degrees: a revolute value beyond a full turn (±2π rad) and past
    its joint's limits. robokit takes radians; ``rk.deg2rad`` converts. Given once per call, by
    every entry point that takes joint values (see the docs' Conventions page for which joints
    and arguments are checked).

    Attributes
    ----------
    args : tuple
        ``(message,)``, naming the argument and the joints.

    Examples
    --------
    >>> import warnings
    >>> with warnings.catch_warnings(record=True) as w:
    ...     warnings.simplefilter("always")
    ...     _ = rk.load("puma560").frame_pose([0, 45, -90, 0, 30, 0])
    >>> w[0].category.__name__
    'DegreesWarning'
    """


class DivergenceError(RobokitError, ArithmeticError):
    """A simulation or iteration blew up (non-finite or runaway values): the model, the gains or
    the step make it unstable — not bad input.

    Parameters
    ----------
    message : str
        What diverged and where (the step, the time).
    partial : object, optional
        The result up to the last finite step, of the type the function returns on success;
        kept as the attribute ``partial``.
    """

    def __init__(self, message: str, partial: object = None) -> None:
        super().__init__(message)
        self.partial = partial
