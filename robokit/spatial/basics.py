"""Scalar and vector basics of the seed function library (seed 004 §1)."""
from __future__ import annotations

import numpy as np

from robokit._arrays import as_array, as_vector

__all__ = ["near_zero", "normalize"]


def near_zero(z) -> bool:
    """True if ``|z| < 1e-6`` (the seed library's zero test).

    Example: ``near_zero(-1e-7)`` → ``True``.
    """
    return bool(abs(float(as_array(z, "z", ()))) < 1e-6)


def normalize(V) -> np.ndarray:
    """``V / ‖V‖`` for a vector ``V`` of any length.

    Raises ``ValueError`` for the zero vector (it has no direction).
    Example: ``normalize([1, 2, 3])`` → ``[0.267, 0.535, 0.802]``.
    """
    V = as_vector(V, "V")
    n = float(np.linalg.norm(V))
    if n == 0.0:
        raise ValueError("V: cannot normalize the zero vector")
    return V / n
