"""Plots for mobile robots: paths, landmarks, and covariance ellipses (matplotlib; returns the Figure)."""
from __future__ import annotations

from collections.abc import Sequence
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import ArrayLike

from robokit._optional import require
from robokit.mobile.estimation import error_ellipse

if TYPE_CHECKING:
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure, SubFigure

__all__ = ["plot_estimation"]


def plot_estimation(true_path: ArrayLike, est_path: ArrayLike | None = None, covariances: Sequence[ArrayLike] | np.ndarray | None = None, landmarks: ArrayLike | None = None, landmark_estimates: ArrayLike | None = None,
                    every: int = 10, n_sigma: float = 1.0, ax: Axes | None = None) -> Figure | SubFigure:
    """Plot a true path, an estimated path with its error ellipses, and landmarks (matplotlib).

    Parameters
    ----------
    true_path : (K, ≥2) array_like
        True poses; columns x, y (m) are drawn.
    est_path : (K, ≥2) array_like, optional
        Estimated poses.
    covariances : sequence of (≥2, ≥2) arrays, optional
        The estimate's covariances; the (x, y) block's ``n_sigma`` ellipse is drawn every ``every`` steps.
    landmarks : (N, 2) array_like, optional
        True landmark positions (m).
    landmark_estimates : (M, 2) array_like, optional
        Estimated landmark positions (m).
    every : int
        Draw one ellipse every this many steps.
    n_sigma : float
        Ellipse size in standard deviations.
    ax : matplotlib Axes, optional
        Where to draw (default: a new 6×6 in figure).

    Returns
    -------
    matplotlib.figure.Figure
        The figure drawn into.
    """
    plt = require("matplotlib.pyplot", "plotting")

    fig = ax.figure if ax is not None else plt.figure(figsize=(6, 6))
    ax = ax or fig.add_subplot(111)
    T = np.asarray(true_path)
    ax.plot(T[:, 0], T[:, 1], "k-", lw=1.5, label="true")
    if est_path is not None:
        E = np.asarray(est_path)
        ax.plot(E[:, 0], E[:, 1], "b--", lw=1.2, label="estimate")
        if covariances is not None:
            for k in range(0, len(E), max(1, int(every))):
                pts, _, _ = error_ellipse(np.asarray(covariances[k])[:2, :2], E[k, :2], n_sigma)
                ax.plot(pts[:, 0], pts[:, 1], "b-", lw=0.6, alpha=0.6)
    if landmarks is not None:
        L = np.asarray(landmarks)
        ax.plot(L[:, 0], L[:, 1], "k*", ms=10, label="landmarks")
    if landmark_estimates is not None:
        L = np.asarray(landmark_estimates)
        ax.plot(L[:, 0], L[:, 1], "r+", ms=10, label="estimated landmarks")
    ax.set_aspect("equal")
    ax.set_xlabel("x [m]")
    ax.set_ylabel("y [m]")
    ax.legend(loc="best", fontsize="small")
    return fig
