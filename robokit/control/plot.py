"""One-call plots of a closed-loop run: desired vs actual joints, tracking error, torques."""
from __future__ import annotations

from typing import Any, Iterable

import numpy as np

from robokit._optional import require

__all__ = ["plot_tracking"]


def plot_tracking(result: Any, joints: Iterable[int] | None = None, title: str | None = None) -> Any:
    """Three stacked panels of a closed-loop run: joint angles, tracking error, torques.

    Desired (dashed) and actual joint angles, the error ``q_des − q`` and the commanded torques
    against time. Needs the ``plot`` extra (matplotlib).

    Parameters
    ----------
    result : SimResult or object
        A :class:`~robokit.control.simulate.SimResult`, or any object with ``t`` (K,), ``q``,
        ``q_des`` and ``tau`` (K, n).
    joints : iterable of int, optional
        Columns (0-based joints) to draw; default all.
    title : str, optional
        Figure title.

    Returns
    -------
    matplotlib.figure.Figure
        The figure with its three axes.
    """
    plt = require("matplotlib.pyplot", "plotting")

    t = np.asarray(result.t)
    q, qd, tau = np.asarray(result.q), np.asarray(result.q_des), np.asarray(result.tau)
    cols = range(q.shape[1]) if joints is None else list(joints)
    fig, axes = plt.subplots(3, 1, figsize=(8, 8), sharex=True)
    for j in cols:
        # actual: a wide pale line; desired: a thin dark dashed line on top, so both stay visible
        # where they coincide (good tracking)
        (line,) = axes[0].plot(t, q[:, j], lw=3.0, alpha=0.45, label=f"q{j + 1}", zorder=2)
        axes[0].plot(t, qd[:, j], "--", color=line.get_color(), lw=1.2, dashes=(4, 2), zorder=3)
        axes[1].plot(t, qd[:, j] - q[:, j], color=line.get_color(), label=f"e{j + 1}")
        axes[2].plot(t, tau[:, j], color=line.get_color(), label=f"τ{j + 1}")
    axes[0].set_ylabel("joint [rad]\n(wide: actual, dashed: desired)")
    axes[1].set_ylabel("error [rad]")
    axes[2].set_ylabel("torque [N·m]")
    axes[2].set_xlabel("t [s]")
    for ax in axes:
        ax.grid(True, alpha=0.3)
    # the legend beside the panels, never over a curve
    axes[0].legend(loc="upper left", bbox_to_anchor=(1.01, 1.0), fontsize="small", borderaxespad=0.0)
    if title:
        fig.suptitle(title)
    fig.tight_layout()
    return fig
