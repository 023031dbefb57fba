"""Boundary checks: turn array-likes into float64 arrays of the expected shape, or raise.

Every public function validates its arguments once, here, so that the numerical code
below it can assume clean input. Errors name the argument and what was received.
"""
from __future__ import annotations

from collections.abc import Sequence
from typing import TypeAlias

import numpy as np

from robokit.errors import InputError

#: A vector argument whose entries the code reads directly (``x[0]``): a sequence of floats or an array.
FloatVector: TypeAlias = "Sequence[float] | np.ndarray"


def _describe(a: object) -> str:
    arr = np.asarray(a)
    return f"shape {arr.shape}" if arr.ndim else f"value {arr!r}"


def as_array(x: object, name: str, shape: tuple[int | None, ...] | None = None, *, finite: bool = True) -> np.ndarray:
    """Return ``x`` as a float64 array, checking its shape (``None`` in ``shape`` = any size).

    Raises ``ValueError`` naming ``name`` when the shape differs, the values are not
    numbers, or (with ``finite``) any entry is NaN or infinite.
    """
    try:
        arr = np.asarray(x, dtype=float)
    except (TypeError, ValueError):
        raise InputError(f"{name}: expected an array of numbers, got {type(x).__name__} {x!r:.80}") from None
    if shape is not None:
        ok = arr.ndim == len(shape) and all(s is None or s == d for s, d in zip(shape, arr.shape))
        if not ok:
            want = "(" + ", ".join("n" if s is None else str(s) for s in shape) + ("," if len(shape) == 1 else "") + ")"
            raise InputError(f"{name}: expected shape {want}, got {_describe(arr)}")
    if finite and not np.isfinite(arr).all():
        raise InputError(f"{name}: contains NaN or infinite values")
    return arr


def as_vector(x: object, name: str, n: int | None = None) -> np.ndarray:
    """A 1-D float64 array of length ``n`` (any length if ``None``)."""
    return as_array(x, name, (n,))


def as_matrix(x: object, name: str, rows: int | None = None, cols: int | None = None) -> np.ndarray:
    """A 2-D float64 array of the given size (``None`` = any)."""
    return as_array(x, name, (rows, cols))


def as_scalar(x: object, name: str, *, positive: bool = False, nonnegative: bool = False) -> float:
    """A finite float; optionally > 0 or >= 0."""
    arr = as_array(x, name, ())
    v = float(arr)
    if positive and not v > 0:
        raise InputError(f"{name}: expected a positive number, got {v!r}")
    if nonnegative and not v >= 0:
        raise InputError(f"{name}: expected a non-negative number, got {v!r}")
    return v
