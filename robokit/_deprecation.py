"""Deprecated aliases: an old public name that keeps working and says which name replaced it.

robokit's naming rule (see the docs' *Conventions* page): the seed library keeps the names of the
course's function documentation (``euler_to_matrix``, ``Rp_to_trans``, …); every other public
conversion reads ``X_from_Y`` (``matrix_from_rpy``, ``urdf_from_dh``). A function renamed to the
rule keeps its old name as an alias made by :func:`deprecated_alias`: every call emits a
``DeprecationWarning`` naming the new function, attributed to the caller's line (Python shows it
in scripts' ``__main__``, notebooks and test runs, once per line by default), then calls the new
function with the same arguments.
Old names are not listed in any ``__all__`` (so star-imports and the API pages show only the new
ones) but stay importable from where they were.
"""
from __future__ import annotations

import functools
import warnings
from collections.abc import Callable
from typing import Any, TypeVar

__all__ = ["deprecated_alias"]

F = TypeVar("F", bound=Callable[..., Any])


def deprecated_alias(new: F, old: str) -> F:
    """``new`` under its former name ``old``, warning on every call.

    Parameters
    ----------
    new : callable
        The function (or class) under its current name.
    old : str
        The former name, e.g. ``"rpy_to_matrix"``.

    Returns
    -------
    callable
        A function with ``new``'s signature that emits ``DeprecationWarning("old is deprecated:
        use module.new")`` (attributed to the caller's line) and returns ``new(*args, **kwargs)``.

    Examples
    --------
    >>> import warnings
    >>> def matrix_from_thing(x): return 2 * x
    >>> thing_to_matrix = deprecated_alias(matrix_from_thing, "thing_to_matrix")
    >>> with warnings.catch_warnings(record=True) as w:
    ...     warnings.simplefilter("always")
    ...     thing_to_matrix(3), str(w[0].message).split(":")[0]
    (6, 'thing_to_matrix is deprecated')
    """
    target = f"{new.__module__}.{new.__qualname__}"
    message = f"{old} is deprecated: use {target} (same arguments, same result)"

    @functools.wraps(new)
    def alias(*args: Any, **kwargs: Any) -> Any:
        warnings.warn(message, DeprecationWarning, stacklevel=2)
        return new(*args, **kwargs)

    alias.__name__ = old
    alias.__qualname__ = old
    alias.__doc__ = f"Deprecated alias of :func:`{target}` (renamed to the ``X_from_Y`` rule)."
    alias.__deprecated_for__ = target  # type: ignore[attr-defined]
    return alias  # type: ignore[return-value]
