r"""The one damping law of robokit's Levenberg–Marquardt IK (Lecture 5; Sugihara 2011).

Both Levenberg–Marquardt loops — :func:`robokit.ik.lm.lm_loop` (Pinocchio or any RobotLike,
any frame, weights, position-only) and the compiled PoE kernel
:func:`robokit.kernels.ik.solve_poe_ik` — take their step ``(JᵀWJ + λI) Δq = JᵀWe`` with the
damping of this module, and nothing else:

* **λ = λ₀‖e‖² + λ_min** (:func:`lm_damping`; λ₀ = ``damping`` = 1e-2, λ_min =
  ``min_damping`` = 1e-9 by default): heavy damping (a short, gradient-like step) far from the
  target, Gauss–Newton near it — T. Sugihara, "Solvability-unconcerned inverse kinematics by
  the Levenberg–Marquardt method", IEEE Trans. Robotics 27(5), 2011;
* a step that does not lower the error is retried once with ``10(λ + 10⁻⁶)``
  (:func:`lm_retry_damping`); after :data:`STALL_LIMIT` such steps the attempt stops;
* an attempt still farther than :data:`EARLY_ERROR` after :data:`EARLY_ITERATION` iterations is
  abandoned for a fresh random start (a restart is cheaper than crawling).

Why this law and not Marquardt's adaptive ``λ ← λ/3`` (accepted) / ``λ ← 10λ`` (rejected),
which the compiled kernel used before: measured with ``benchmarks/lm_damping.py`` (same loop,
same starts and targets, one attempt of 30 iterations), Sugihara's law solves slightly fewer
targets per attempt but needs about 8 instead of 13 iterations when it does, and gives up on
hopeless starts early, so a solution costs 2.5–3× fewer iterations once failed attempts are
restarted (docs/ik.md has the table). Plain Python (no numba): the kernel compiles the same
functions.
"""
from __future__ import annotations

__all__ = ["lm_damping", "lm_retry_damping", "DAMPING", "MIN_DAMPING", "STALL_LIMIT", "EARLY_ITERATION",
           "EARLY_ERROR"]

#: λ₀, the default weight of the squared error in λ.
DAMPING = 1e-2
#: λ_min, the default floor of λ (keeps the normal equations positive definite).
MIN_DAMPING = 1e-9
#: Rejected steps (after their retry) that end an attempt.
STALL_LIMIT = 3
#: An attempt whose error is still above EARLY_ERROR (rad and m) after EARLY_ITERATION iterations restarts.
EARLY_ITERATION, EARLY_ERROR = 15, 1e-2


def lm_damping(err: float, damping: float, min_damping: float) -> float:
    """Sugihara's damping ``λ = damping·err² + min_damping`` for the error norm ``err``.

    Parameters
    ----------
    err : float
        ‖e‖ of the current error (rad and m).
    damping, min_damping : float
        λ₀ and λ_min (non-negative).

    Returns
    -------
    float
        λ.

    Examples
    --------
    >>> round(lm_damping(0.1, DAMPING, MIN_DAMPING), 12)
    0.000100001
    """
    return damping * err * err + min_damping


def lm_retry_damping(lam: float) -> float:
    """The heavier damping ``10(λ + 10⁻⁶)`` of the one retry after a step that did not lower the error.

    Parameters
    ----------
    lam : float
        The λ of the rejected step.

    Returns
    -------
    float

    Examples
    --------
    >>> round(lm_retry_damping(1e-3), 9)
    0.01001
    """
    return 10.0 * (lam + 1e-6)
