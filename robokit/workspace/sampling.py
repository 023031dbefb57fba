r"""Reachable workspace by sampling (Lecture 5): extent, volume estimate, picture.

The reachable workspace is the set of positions the tool (or any frame) reaches with the
joints inside their limits. It is estimated by forward kinematics (Pinocchio) at many
configurations drawn uniformly inside the limits; the volume (or, for a planar arm, the
area) is estimated by counting occupied voxels (pixels) of a given size, which — unlike a
convex hull — keeps holes such as the inner disc of a two-link arm's annulus
``|l₁ − l₂| ≤ r ≤ l₁ + l₂``.

(This is the *reachable* workspace of positions; :func:`robokit.workspace.capability_map`
adds orientations — the dexterous workspace — by inverse kinematics.)
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np
from robokit.errors import InputError

from robokit._optional import require

if TYPE_CHECKING:
    from robokit.description.robot import Robot

__all__ = ["Workspace", "sample_workspace", "plot_workspace"]


@dataclass
class Workspace:
    """Sampled workspace of one frame (returned by :func:`sample_workspace`).

    Attributes
    ----------
    points : ndarray, shape (K, 3)
        Frame positions in the base frame (m).
    q : ndarray, shape (K, n)
        The configurations sampled.
    lower, upper : ndarray, shape (3,)
        Extent of the points (m).
    reach : ndarray, shape (K,)
        Distance of each point from the base origin (m).
    planar : bool
        True if all points lie in one horizontal plane (z extent below 1e-9 m).
    measure : float
        Occupied volume (m³), or area (m²) when planar, counted in cells of edge ``cell``.
    cell : float
        The cell edge (m).

    Examples
    --------
    >>> import robokit
    >>> ws = sample_workspace(robokit.load("rrr"), 500, rng=0)
    >>> ws.points.shape, ws.planar
    ((500, 3), True)
    """

    points: np.ndarray
    q: np.ndarray
    lower: np.ndarray
    upper: np.ndarray
    reach: np.ndarray
    planar: bool
    measure: float
    cell: float


def sample_workspace(robot: Robot, n_samples: int = 20000, frame: str | None = None, cell: float | None = None,
                     rng: int | np.random.Generator | None = None) -> Workspace:
    """Sample the reachable workspace of ``frame`` (default the tip) of ``robot`` (Lecture 5).

    Forward kinematics at ``n_samples`` configurations drawn uniformly inside the joint
    limits; the volume (area for a planar arm) is the number of occupied cells times the
    cell's volume (area).

    Parameters
    ----------
    robot : robokit.Robot
        The arm.
    n_samples : int
        Configurations drawn uniformly inside the joint limits (unlimited joints: [−π, π]).
    frame : str, optional
        The frame whose positions are sampled (default the tip).
    cell : float, optional
        Cell edge (m) of the volume estimate (default 1/40 of the largest extent).
    rng : int or numpy.random.Generator, optional
        Seed or generator.

    Returns
    -------
    Workspace
        ``.points`` (K, 3) m in the base frame, ``.reach``, ``.measure`` (m³ or m²), ...

    Examples
    --------
    >>> import robokit
    >>> ws = sample_workspace(robokit.load("rrr"), 2000, rng=0)
    >>> bool(1.09 < ws.reach.max() <= 0.5 + 0.4 + 0.2)  # nearly l1 + l2 + l3, never more
    True
    """
    if int(n_samples) < 1:
        raise InputError(f"n_samples: expected a positive count, got {n_samples!r}")
    rng = np.random.default_rng(rng)
    qlim = np.array(robot.qlim, dtype=float)
    lo = np.where(np.isfinite(qlim[:, 0]), qlim[:, 0], -np.pi)
    hi = np.where(np.isfinite(qlim[:, 1]), qlim[:, 1], np.pi)
    Q = rng.uniform(lo, hi, size=(int(n_samples), robot.n))
    P = np.empty((len(Q), 3))
    for k, q in enumerate(Q):
        P[k] = robot.frame_pose(q, frame)[:3, 3]
    lower, upper = P.min(axis=0), P.max(axis=0)
    span = upper - lower
    planar = bool(span[2] < 1e-9)
    if cell is None:
        cell = float(max(span.max(), 1e-9) / 40.0)
    elif not cell > 0:
        raise InputError(f"cell: expected a positive size, got {cell!r}")
    dims = 2 if planar else 3
    idx = np.floor((P[:, :dims] - lower[:dims]) / cell).astype(np.int64)
    occupied = len(np.unique(idx, axis=0))
    measure = occupied * cell**dims
    return Workspace(P, Q, lower, upper, np.linalg.norm(P, axis=1), planar, float(measure), float(cell))


def plot_workspace(ws: Workspace, ax: Any = None, s: float = 1.0, color: str = "tab:blue") -> Any:
    """Scatter plot of a sampled workspace (2-D for planar arms, 3-D otherwise).

    Parameters
    ----------
    ws : Workspace
        From :func:`sample_workspace`.
    ax : matplotlib Axes, optional
        Axes to draw in (a 3-D one for a spatial arm); default a new figure.
    s : float
        Marker size (points²).
    color : str
        Marker colour.

    Returns
    -------
    matplotlib.figure.Figure
        The figure drawn in.

    Examples
    --------
    >>> import robokit, matplotlib
    >>> matplotlib.use("Agg")
    >>> fig = plot_workspace(sample_workspace(robokit.load("rrr"), 500, rng=0))
    >>> fig.axes[0].get_xlabel()
    'x [m]'
    """
    plt = require("matplotlib.pyplot", "plotting")

    if ax is None:
        fig = plt.figure(figsize=(6, 5))
        ax = fig.add_subplot(111) if ws.planar else fig.add_subplot(111, projection="3d")
    else:
        fig = ax.figure
    P = ws.points
    if ws.planar:
        ax.scatter(P[:, 0], P[:, 1], s=s, color=color, alpha=0.4, linewidths=0)
        ax.set_aspect("equal")
        ax.set_xlabel("x [m]")
        ax.set_ylabel("y [m]")
        ax.set_title(f"reachable workspace (area ≈ {ws.measure:.3g} m²)")
    else:
        ax.scatter(P[:, 0], P[:, 1], P[:, 2], s=s, color=color, alpha=0.3, linewidths=0)
        ax.set_xlabel("x [m]")
        ax.set_ylabel("y [m]")
        ax.set_zlabel("z [m]")
        ax.set_title(f"reachable workspace (volume ≈ {ws.measure:.3g} m³)")
    return fig
