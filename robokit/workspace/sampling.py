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
    """Sampled workspace of one frame.

    points : (K, 3) frame positions in the base frame (m); q : (K, n) the configurations;
    lower, upper : (3,) extent (m); reach : (K,) distance of each point from the base origin;
    planar : True if all points lie in one horizontal plane (z extent below 1e-9 m);
    measure : occupied volume (m³), or area (m²) when planar, estimated with
    cells of edge ``cell`` (m).
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
    """Sample the reachable workspace of ``frame`` (default the tip) of ``robot``.

    robot : a :class:`robokit.Robot`; n_samples : configurations drawn uniformly inside the
    joint limits (unlimited joints: [−π, π]); cell : voxel edge (m) for the volume estimate
    (default: 1/40 of the largest extent); rng : Generator or seed.

    Example: ``ws = robokit.workspace.sample_workspace(robokit.load("twolink"), 5000); ws.reach.max()`` ≈ l₁ + l₂.
    """
    if int(n_samples) < 1:
        raise InputError(f"n_samples: expected a positive count, got {n_samples!r}")
    rng = np.random.default_rng(rng)
    qlim = np.asarray(robot.qlim, dtype=float)
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
    """Scatter plot of a sampled workspace (2-D for planar arms, 3-D otherwise); returns the Figure."""
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
