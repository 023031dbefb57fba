r"""Radians, not degrees: the one check of every entry point that takes joint values.

robokit takes revolute joint values in radians. A value written in degrees is a number
robokit would happily use (45 rad is a valid angle), so a student who types
``frame_pose([0, 45, -90, 0, 30, 0])`` would get a pose, silently wrong. Every entry point that
takes a configuration calls :func:`check_radians`, which warns **once per call**
(:class:`robokit.errors.DegreesWarning`, a ``RobokitWarning``) when a revolute value lies
outside its *plausible range* (:func:`radian_ranges`):

* beyond a full turn, ``|θ| > 2π``, **and** beyond the joint's own limits (an arm whose joint
  turns ±400° is not flagged at 7 rad), or
* beyond the joint's limits by more than a turn (``θ < lo − 2π`` or ``θ > hi + 2π``: a seed
  ``q0`` that far out is not a wrapped angle).

The message names the argument and the joints, says that this looks like degrees and how to
convert (``rk.deg2rad``); it holds no values, so a loop over many such calls warns once per
call site (Python's default warning filter). Prismatic joints (metres) are never checked.

Continuous joints (no limits, Pinocchio's ``nq = 2`` joints) are checked at ``±2π`` in one-off
configurations (``frame_pose``, ``jacobian``, the dynamics at one ``q``), where 45 for an
endless joint is degrees far more often than a wound-up angle, and **exempt** wherever a
multi-turn value is a legitimate state: batches of configurations (rows of a trajectory or a
log), trajectories' end and via points, simulations' states, IK seeds (the current state of an
endless wrist that has turned three times). The robot-less seed library (``fkin_space(M, Slist,
θ)``, ``inverse_dynamics(θ, …)``) knows no joint kinds beyond the screw axes: it checks every
revolute column (``ω ≠ 0``) at ``±2π``; robot-less joint values (``joint_trajectory``'s ends,
``select_solution``'s ``q_ref``, ``ik_analytic``'s ``wrist_ref``) are checked at ``±2π`` (they are
angles by name). The docs' Conventions page lists every entry point.

Cost: the hot paths (``Robot.frame_pose`` and friends, the seed FK and Jacobians) filter first
with a test that *implies* the check passes — ``hypot(*q) ≤ r`` (one C call, which also
rejects NaN/inf), else ``lo₁ ≤ min(q)`` and ``max(q) ≤ hi₁`` with the tightest bounds over the
joints — and call :func:`check_radians` only when the filter fails.
"""
from __future__ import annotations

import math
import os
import sys
import warnings
from types import FrameType

import numpy as np
from numpy.typing import ArrayLike

from robokit.errors import DegreesWarning

__all__ = ["TURN", "radian_ranges", "fast_bounds", "revolute_columns", "check_radians", "warn_user", "CHECK_HELPERS"]

#: A full turn, rad.
TURN = 2.0 * math.pi

_PACKAGE = os.path.dirname(os.path.abspath(__file__)) + os.sep


def radian_ranges(revolute: ArrayLike, qlim: ArrayLike | None = None,
                  exempt: ArrayLike | None = None) -> tuple[np.ndarray, np.ndarray]:
    """Per joint, the range outside which a value looks like degrees (see the module docstring).

    Parameters
    ----------
    revolute : array_like of bool, shape (n,)
        Which joints are revolute (only those are checked).
    qlim : array_like, shape (n, 2), optional
        Joint limits (rad for revolute joints; ±inf where a joint has none). Default: none.
    exempt : array_like of bool, shape (n,), optional
        Joints never checked (continuous joints where multi-turn values are legitimate).

    Returns
    -------
    lo, hi : numpy.ndarray, shape (n,)
        ``[min(−2π, lo), max(2π, hi)]`` intersected with ``[lo − 2π, hi + 2π]`` for a limited
        revolute joint, ``[−2π, 2π]`` for an unlimited one, ``[−inf, inf]`` for prismatic and
        exempt joints.

    Examples
    --------
    >>> lo, hi = radian_ranges([True, True, False], [[-3, 3], [-20, 20], [0, 1]])
    >>> np.round(hi, 3).tolist()
    [6.283, 20.0, inf]
    """
    rev = np.asarray(revolute, dtype=bool).ravel()
    n = rev.size
    lim = np.full((n, 2), [-np.inf, np.inf]) if qlim is None else np.asarray(qlim, dtype=float).reshape(n, 2)
    lo = np.full(n, -np.inf)
    hi = np.full(n, np.inf)
    for i in range(n):
        if not rev[i] or (exempt is not None and bool(np.asarray(exempt, dtype=bool).ravel()[i])):
            continue
        low, high = float(lim[i, 0]), float(lim[i, 1])
        hi[i] = min(max(TURN, high), high + TURN) if math.isfinite(high) else TURN
        lo[i] = max(min(-TURN, low), low - TURN) if math.isfinite(low) else -TURN
    return lo, hi


def fast_bounds(lo: np.ndarray, hi: np.ndarray) -> tuple[float, float, float]:
    """The scalars of the hot paths' filter: ``(r, lo₁, hi₁)`` with ``r = min(−lo₁, hi₁)`` and
    ``lo₁ = max lo``, ``hi₁ = min hi`` — a vector with ``hypot(*q) ≤ r``, or with every entry in
    ``[lo₁, hi₁]``, passes :func:`check_radians` (all finite, never inf: an inf entry fails them).

    Parameters
    ----------
    lo, hi : numpy.ndarray, shape (n,)
        From :func:`radian_ranges`.

    Returns
    -------
    tuple of float

    Examples
    --------
    >>> fast_bounds(np.array([-6.0, -np.inf]), np.array([7.0, np.inf]))
    (6.0, -6.0, 7.0)
    """
    big = sys.float_info.max
    lo1 = min(float(np.max(lo, initial=-np.inf)), big) if lo.size else -big
    hi1 = max(float(np.min(hi, initial=np.inf)), -big) if hi.size else big
    lo1, hi1 = max(lo1, -big), min(hi1, big)
    return min(-lo1, hi1), lo1, hi1


def revolute_columns(S: np.ndarray) -> np.ndarray:
    """Which screw axes (columns of a 6×n ``Slist``/``Blist``, rows ``(ω; v)``) are revolute: ``ω ≠ 0``.

    Parameters
    ----------
    S : numpy.ndarray, shape (6, n)

    Returns
    -------
    numpy.ndarray of bool, shape (n,)

    Examples
    --------
    >>> revolute_columns(np.array([[0, 0, 1, 0, 0, 0], [0, 0, 0, 0, 0, 1]], float).T).tolist()
    [True, False]
    """
    return np.abs(np.asarray(S, dtype=float)[:3]).max(axis=0) > 0.0


def _joint_list(idx: list[int]) -> str:
    shown = [str(i + 1) for i in idx[:8]] + (["…"] if len(idx) > 8 else [])
    return ("joint " if len(idx) == 1 else "joints ") + ", ".join(shown)


def check_radians(q: ArrayLike, lo: ArrayLike, hi: ArrayLike, name: str, owner: str = "") -> bool:
    """Warn once (:class:`~robokit.errors.DegreesWarning`) when a joint value looks like degrees.

    Parameters
    ----------
    q : array_like, shape (n,), (N, n) or ()
        Joint values (rad / m), already checked finite.
    lo, hi : array_like, shape (n,) or ()
        The plausible range per joint (:func:`radian_ranges`).
    name : str
        The argument's name (``q``, ``q0``, ``thetalist``…), named in the message.
    owner : str
        The robot's name (or what the values belong to), for the message.

    Returns
    -------
    bool
        True when a value looks like degrees (then it warned, unless robokit itself made the call
        with values it computed: see :func:`warn_user`).

    Examples
    --------
    >>> import warnings
    >>> lo, hi = radian_ranges([True, True])
    >>> with warnings.catch_warnings(record=True) as w:
    ...     warnings.simplefilter("always")
    ...     check_radians(np.array([0.0, 45.0]), lo, hi, "q", "twolink")
    True
    >>> print(w[0].message)
    q: joint 2 of twolink holds a value beyond a full turn (|q| > 2π rad, past the limits): this looks like degrees; robokit takes radians (rk.deg2rad(q) converts)
    """
    a = np.asarray(q, dtype=float)
    bad = (a < lo) | (a > hi)
    if not bad.any():
        return False
    if bad.ndim >= 1:
        idx = np.flatnonzero(bad.reshape(-1, bad.shape[-1]).any(axis=0)).tolist()
        where = _joint_list(idx) + (f" of {owner}" if owner else "")
        what = f"{where} {'holds' if len(idx) == 1 else 'hold'} {'values' if bad.ndim > 1 else 'a value' if len(idx) == 1 else 'values'}"
    else:
        what = "the value" + (f" for {owner}" if owner else "") + " is"
    warn_user(f"{name}: {what} beyond a full turn (|{name}| > 2π rad, past the limits): this looks like degrees; "
              f"robokit takes radians (rk.deg2rad({name}) converts)", DegreesWarning)
    return True


#: Public helpers of the check itself: like private (``_x``) functions, they are not the entry point
#: that owns a check (see :func:`warn_user`).
CHECK_HELPERS = frozenset({"check_radians", "check_robot_radians", "batch_frame_pose", "batch_jacobian",
                           "batch_crba", "batch_rnea", "batch_aba"})


def _in_robokit(frame: FrameType) -> bool:
    return frame.f_code.co_filename.startswith(_PACKAGE)


def warn_user(message: str, category: type[Warning]) -> bool:
    """``warnings.warn`` pointed at the user's call — when the values came from the user.

    The check's *owner* is the first function above the check that is not one of its helpers
    (a private ``_x`` function of robokit or one of :data:`CHECK_HELPERS`): the entry point whose
    argument is checked. It warns only when the owner was called from outside robokit (directly,
    or through robokit's private wrappers); robokit's own calls from a public function with values
    it computed (an IK iteration, a simulation's state after many turns) stay silent — an entry
    point that passes a user's values on to another checks them itself first.

    Parameters
    ----------
    message : str
    category : type of Warning

    Returns
    -------
    bool
        True when it warned.

    Examples
    --------
    >>> warn_user("x", UserWarning)   # doctest: +SKIP
    """
    frame: FrameType | None = sys._getframe(1)
    level = 2  # stacklevel 2 is the caller of warn_user, sys._getframe(1)
    while frame is not None and _in_robokit(frame) and (
            frame.f_code.co_filename == __file__ or frame.f_code.co_name.startswith("_")
            or frame.f_code.co_name in CHECK_HELPERS):
        frame, level = frame.f_back, level + 1
    if frame is None or not _in_robokit(frame):  # a helper called straight from outside: warn there
        warnings.warn(message, category, stacklevel=level)
        return True
    caller = frame.f_back  # the owner's caller, through robokit's private wrappers
    level += 1
    while caller is not None and _in_robokit(caller) and caller.f_code.co_name.startswith("_"):
        caller, level = caller.f_back, level + 1
    if caller is None or _in_robokit(caller):
        return False  # robokit's own call (a public function's computed values): its values are its own
    warnings.warn(message, category, stacklevel=level)
    return True


def surely_radians(th: np.ndarray) -> bool:
    """True when joint values need no degrees check because every ``|θᵢ| ≤ 2π`` is implied (the
    seed functions' fast paths, on the 1-D float64 array the kernel will get): ``hypot(*θ) ≤ 2π``
    or every entry in ``[-2π, 2π]``. False sends the call to the checked path, which warns.

    Parameters
    ----------
    th : numpy.ndarray, shape (n,)
        Joint values (rad).

    Returns
    -------
    bool

    Examples
    --------
    >>> surely_radians(np.array([0.1, -2.0, 3.0])), surely_radians(np.array([0.0, 45.0]))
    (True, False)
    """
    t = th.tolist()
    return math.hypot(*t) <= TURN or (-TURN <= min(t) and max(t) <= TURN)
