r"""Gain design and step-response measures for joint loops (Lecture 8).

* :func:`critical_gains` — PD gains of a critically damped loop on an inertia J:
  ``J ë + K_v ė + K_p e = 0`` has the characteristic polynomial ``J s² + K_v s + K_p``; critical
  damping ``ζ = 1`` at natural frequency ω_n gives ``K_p = J ω_n²``, ``K_v = 2 J ω_n = 2√(K_p J)``
  (for unit inertia, the lecture's ``K_v = 2√K_p``).
* :func:`pid_gains_bandwidth` — PID gains of ``τ = K_p e + K_i ∫e + K_d ė`` on J with all three
  closed-loop poles at ``s = −ω_b`` (ω_b the loop bandwidth): ``J s³ + K_d s² + K_p s + K_i =
  J (s + ω_b)³`` ⇒ ``K_d = 3 J ω_b``, ``K_p = 3 J ω_b²``, ``K_i = J ω_b³``.
* :func:`step_info` — overshoot, rise time, settling time, steady-state error of a step response;
  :func:`plot_step_response` draws one with those marks.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import ArrayLike

from robokit._optional import require
from robokit._arrays import as_scalar, as_vector
from robokit.errors import InputError

__all__ = ["critical_gains", "pid_gains_bandwidth", "StepInfo", "step_info", "plot_step_response"]


def critical_gains(inertia: ArrayLike, omega_n: ArrayLike | None = None,
                   Kp: ArrayLike | None = None) -> tuple[np.ndarray, np.ndarray]:
    """``(K_p, K_v)`` of a critically damped PD loop on an inertia J (Lecture 8).

    ``J s² + K_v s + K_p`` with ζ = 1 at natural frequency ω_n: ``K_p = J ω_n²``,
    ``K_v = 2 J ω_n = 2√(K_p J)``.

    Parameters
    ----------
    inertia : float or (n,) array_like
        J (kg·m²), positive.
    omega_n : float or (n,) array_like, optional
        Natural frequency (rad/s).
    Kp : float or (n,) array_like, optional
        Position gain (N·m/rad). Give exactly one of ``omega_n`` and ``Kp``.

    Returns
    -------
    Kp, Kv : ndarray
        Position (N·m/rad) and velocity (N·m·s/rad) gains.

    Raises
    ------
    InputError
        On a non-positive inertia, frequency or gain, or not exactly one of ``omega_n``/``Kp``.

    Examples
    --------
    For unit inertia the lecture's ``K_v = 2√K_p``:

    >>> [float(k) for k in critical_gains(1.0, Kp=100.0)]
    [100.0, 20.0]
    >>> [float(k) for k in critical_gains(2.0, omega_n=10.0)]
    [200.0, 40.0]
    """
    J = np.asarray(inertia, dtype=float)
    if np.any(J <= 0) or not np.all(np.isfinite(J)):
        raise InputError(f"inertia: expected positive inertias, got {J}")
    if (omega_n is None) == (Kp is None):
        raise InputError("omega_n, Kp: give exactly one of them")
    if omega_n is not None:
        w = np.asarray(omega_n, dtype=float)
        if np.any(w <= 0):
            raise InputError(f"omega_n: expected a positive frequency, got {w}")
        return J * w * w, 2.0 * J * w
    Kp = np.asarray(Kp, dtype=float)
    if np.any(Kp <= 0):
        raise InputError(f"Kp: expected a positive gain, got {Kp}")
    return Kp, 2.0 * np.sqrt(Kp * J)


def pid_gains_bandwidth(inertia: ArrayLike, bandwidth: ArrayLike) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """``(K_p, K_i, K_d)`` placing the three poles of a PID loop on inertia J at ``s = −ω_b``.

    ``J s³ + K_d s² + K_p s + K_i = J (s + ω_b)³`` ⇒ ``K_p = 3Jω_b²``, ``K_i = Jω_b³``,
    ``K_d = 3Jω_b``. The integral term removes the steady-state error of a constant disturbance (a
    type-1 loop, Lecture 8) at the price of some overshoot of steps.

    Parameters
    ----------
    inertia : float or (n,) array_like
        J (kg·m²), positive.
    bandwidth : float or (n,) array_like
        ω_b (rad/s), positive.

    Returns
    -------
    Kp, Ki, Kd : ndarray
        Gains (N·m/rad, N·m/(rad·s), N·m·s/rad).

    Raises
    ------
    InputError
        On a non-positive inertia or bandwidth.

    Examples
    --------
    >>> [float(k) for k in pid_gains_bandwidth(1.0, 10.0)]
    [300.0, 1000.0, 30.0]
    """
    J = np.asarray(inertia, dtype=float)
    w = np.asarray(bandwidth, dtype=float)
    if np.any(J <= 0):
        raise InputError(f"inertia: expected positive inertias, got {J}")
    if np.any(w <= 0):
        raise InputError(f"bandwidth: expected a positive frequency, got {w}")
    return 3.0 * J * w**2, J * w**3, 3.0 * J * w


@dataclass
class StepInfo:
    """Step-response measures, from :func:`step_info`.

    Attributes
    ----------
    overshoot : float
        Peak beyond the final value, % of the step (0 if none).
    peak, peak_time : float
        Value and time (s) of the extreme.
    rise_time : float
        Time from 10 % to 90 % of the step (s).
    settling_time : float
        First time after which the response stays within ±``settle`` of the step around the final
        value (s); NaN if it never settles within the record.
    steady_state_error : float
        Target − final value.
    final : float
        The final value (last sample).
    """

    overshoot: float
    peak: float
    peak_time: float
    rise_time: float
    settling_time: float
    steady_state_error: float
    final: float


def _crossing(t: np.ndarray, y: np.ndarray, level: float) -> float:
    """First time y crosses ``level`` going up (linear interpolation); NaN if never."""
    idx = np.nonzero(y >= level)[0]
    if len(idx) == 0:
        return float("nan")
    k = idx[0]
    if k == 0:
        return float(t[0])
    return float(t[k - 1] + (level - y[k - 1]) * (t[k] - t[k - 1]) / (y[k] - y[k - 1]))


def step_info(t: ArrayLike, y: ArrayLike, target: float | None = None, y0: float | None = None, settle: float = 0.02,
              rise: tuple[float, float] = (0.1, 0.9)) -> StepInfo:
    """Measures of a step response y(t) (see :class:`StepInfo`; Lecture 8).

    The response is assumed to have settled by the end of the record (the final value is y[-1]).

    Parameters
    ----------
    t : (K,) array_like
        Increasing times (s).
    y : (K,) array_like
        The response.
    target : float, optional
        The commanded final value (default the last sample, then the steady-state error is 0).
    y0 : float, optional
        The initial value (default y[0]).
    settle : float, optional
        Settling band, fraction of the step; default 0.02 (2 %).
    rise : (float, float), optional
        The rise-time band; default (0.1, 0.9).

    Returns
    -------
    StepInfo
        Overshoot, peak, rise and settling times, steady-state error, final value.

    Raises
    ------
    InputError
        When the times do not increase or the response does not move.

    Examples
    --------
    A first-order lag ``1 − e^{−t/τ}`` (τ = 0.5 s) has rise time ``τ ln 9`` and 2 % settling time
    ``τ ln 50``, and no overshoot:

    >>> t = np.linspace(0, 5, 5001)
    >>> info = step_info(t, 1 - np.exp(-t / 0.5), target=1.0)
    >>> info.overshoot, round(info.rise_time, 2), round(info.settling_time, 2)
    (0.0, 1.1, 1.95)
    >>> round(float(0.5 * np.log(9)), 2), round(float(0.5 * np.log(50)), 2)
    (1.1, 1.96)
    """
    t = as_vector(t, "t")
    y = as_vector(y, "y", len(t))
    if np.any(np.diff(t) <= 0):
        raise InputError("t: times must increase strictly")
    y0 = float(y[0]) if y0 is None else as_scalar(y0, "y0")
    final = float(y[-1])
    target = final if target is None else as_scalar(target, "target")
    step = final - y0
    if step == 0:
        raise InputError("y: the response does not move (final value equals the initial value)")
    s = (y - y0) / step  # normalised: 0 → 1, increasing
    k_peak = int(np.argmax(s))
    overshoot = max(0.0, (s[k_peak] - 1.0) * 100.0)
    rise_time = _crossing(t, s, rise[1]) - _crossing(t, s, rise[0])
    outside = np.nonzero(np.abs(s - 1.0) > settle)[0]
    if len(outside) == 0:
        settling = float(t[0])
    elif outside[-1] == len(t) - 1:
        settling = float("nan")
    else:
        k = outside[-1]
        # interpolate the last exit from the band
        a, b = abs(s[k] - 1.0), abs(s[k + 1] - 1.0)
        settling = float(t[k] + (a - settle) / (a - b) * (t[k + 1] - t[k])) if a != b else float(t[k + 1])
    return StepInfo(overshoot, float(y[k_peak]), float(t[k_peak]), float(rise_time), settling, target - final, final)


def plot_step_response(t: ArrayLike, y: ArrayLike, target: float | None = None, info: StepInfo | None = None,
                       ax: Any = None, label: str | None = None) -> Any:
    """Plot a step response with its measures marked (Lecture 8).

    The target, the settling band, the peak, the 10–90 % rise and the settling time. Needs the
    ``plot`` extra (matplotlib).

    Parameters
    ----------
    t, y : (K,) array_like
        Times (s) and response.
    target : float, optional
        Commanded value (default the final value).
    info : StepInfo, optional
        Precomputed :func:`step_info` (computed when None).
    ax : matplotlib.axes.Axes, optional
        Axes to draw on (a new figure otherwise).
    label : str, optional
        Legend label of the response.

    Returns
    -------
    matplotlib.axes.Axes
        The axes drawn on.
    """
    plt = require("matplotlib.pyplot", "plotting")

    t = as_vector(t, "t")
    y = as_vector(y, "y", len(t))
    info = info or step_info(t, y, target)
    target = info.final + info.steady_state_error
    if ax is None:
        _, ax = plt.subplots(figsize=(7, 4))
    ax.plot(t, y, label=label or "response")
    ax.axhline(target, color="k", lw=0.8, ls="--", label="target")
    band = 0.02 * abs(info.final - y[0])
    ax.axhspan(info.final - band, info.final + band, color="tab:green", alpha=0.15, label="±2 % band")
    ax.plot([info.peak_time], [info.peak], "v", color="tab:red", label=f"overshoot {info.overshoot:.1f} %")
    if np.isfinite(info.settling_time):
        ax.axvline(info.settling_time, color="tab:green", lw=0.8, label=f"settling {info.settling_time:.3g} s")
    ax.set_xlabel("t (s)")
    ax.set_ylabel("response")
    ax.set_title(f"rise {info.rise_time:.3g} s, steady-state error {info.steady_state_error:.3g}")
    ax.legend(loc="best", fontsize=8)
    return ax
