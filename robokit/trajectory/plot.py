"""Plots of trajectories in one call (matplotlib; works with the non-interactive Agg backend).

Both functions build a ``matplotlib.figure.Figure`` directly (no pyplot global state,
so nothing pops up and nothing is drawn twice in a notebook) and return it; call
``fig.savefig(path)`` to write it, or let a notebook display it.
"""
from __future__ import annotations

from typing import TYPE_CHECKING
from typing import Sequence

import numpy as np

from robokit._optional import require
from robokit.errors import InputError
from robokit.trajectory.core import Trajectory

if TYPE_CHECKING:
    from matplotlib.figure import Figure

__all__ = ["plot_trajectory", "plot_path_3d"]


def _figure(figsize: tuple[float, float]) -> Figure:
    figure = require("matplotlib.figure", "plotting").Figure
    return figure(figsize=figsize, layout="constrained")


def plot_trajectory(traj: Trajectory, *, title: str | None = None, labels: Sequence[str] | None = None, show_via: bool = True, figsize: tuple[float, float] = (8.0, 7.0)) -> Figure:
    """Position, velocity and acceleration against time, one panel each, all axes overlaid.

    Parameters
    ----------
    traj : Trajectory or SimResult
        Any trajectory of :mod:`robokit.trajectory` (``qd``/``qdd`` panels are drawn when present), or
        a simulation's result (:class:`robokit.control.SimResult`: its ``q`` and ``dq``; for desired vs
        actual use :func:`robokit.control.plot_tracking` or ``result.plot()``).
    title : str, optional
        Figure title (default: the trajectory's name).
    labels : sequence of str, optional
        Legend names of the axes (default ``traj.labels`` or ``q1 … qn``).
    show_via : bool
        Mark the via points (``traj.info["via_times"]``, ``["via_points"]``) on the
        position panel, when the generator records them.
    figsize : (float, float)
        Size in inches.

    Returns
    -------
    matplotlib.figure.Figure
        One panel per quantity (position, velocity, acceleration), time in s on the shared x axis.

    Examples
    --------
    >>> import matplotlib
    >>> matplotlib.use("Agg")
    >>> from robokit.trajectory import cubic_trajectory
    >>> fig = plot_trajectory(cubic_trajectory([0, 1], [1, 0], 2.0))
    >>> len(fig.axes), [ax.get_ylabel() for ax in fig.axes]
    (3, ['position', 'velocity', 'acceleration'])
    """
    if not isinstance(traj, Trajectory):
        if hasattr(traj, "t") and hasattr(traj, "q") and hasattr(traj, "dq"):  # a simulation (SimResult)
            traj = Trajectory(np.asarray(traj.t, float), np.asarray(traj.q, float), np.asarray(traj.dq, float),
                              name="simulation")
        else:
            raise InputError(f"traj: expected a robokit Trajectory or a simulation result (t, q, dq), got "
                             f"{type(traj).__name__}")
    names = tuple(labels) if labels is not None else traj.column_labels()
    if len(names) != traj.n:
        raise InputError(f"labels: expected {traj.n} names (one per axis), got {len(names)}")
    panels = [("position", traj.q)]
    if traj.qd is not None:
        panels.append(("velocity", traj.qd))
    if traj.qdd is not None:
        panels.append(("acceleration", traj.qdd))
    fig = _figure(figsize)
    axes = fig.subplots(len(panels), 1, sharex=True, squeeze=False)[:, 0]
    marker = "." if len(traj) <= 60 else None
    for ax, (what, data) in zip(axes, panels):
        for j in range(traj.n):
            ax.plot(traj.t, data[:, j], marker=marker, label=names[j])
        ax.set_ylabel(what)
        ax.grid(True, alpha=0.4)
    if show_via and "via_times" in traj.info and "via_points" in traj.info:
        vt = np.asarray(traj.info["via_times"])
        vp = np.asarray(traj.info["via_points"])
        for j in range(traj.n):
            axes[0].plot(vt, vp[:, j], "ko", mfc="none", ms=7, label="via points" if j == 0 else None)
    axes[0].legend(loc="best", fontsize="small", ncol=min(traj.n + 1, 4))
    axes[-1].set_xlabel("t (s)")
    fig.suptitle(title if title is not None else traj.name)
    return fig


def plot_path_3d(traj: Trajectory, *, frames: int = 5, axis_length: float | None = None, title: str | None = None, figsize: tuple[float, float] = (6.0, 6.0)) -> Figure:
    """The 3-D path of a Cartesian trajectory, with a few orientation triads along it.

    Parameters
    ----------
    traj : Trajectory with ``poses``, or array (K, 4, 4), or a list of 4×4 poses
        E.g. :func:`cartesian_line_trajectory`, :func:`cartesian_trajectory`,
        :func:`screw_trajectory`.
    frames : int
        Number of orientation triads (x red, y green, z blue) drawn along the path.
    axis_length : float, optional
        Triad length, m (default: 15 % of the path's extent, or 0.1 m).
    title : str, optional
        Figure title (default: the trajectory's name).
    figsize : (float, float)
        Size in inches.

    Returns
    -------
    matplotlib.figure.Figure
        One 3-D axes: the path of the tool origin (m, base frame) and the triads.

    Examples
    --------
    >>> import matplotlib
    >>> matplotlib.use("Agg")
    >>> from robokit.trajectory import cartesian_line_trajectory
    >>> T1 = np.eye(4); T1[:3, 3] = [0.3, 0.2, 0.1]
    >>> fig = plot_path_3d(cartesian_line_trajectory(np.eye(4), T1, 1.0))
    >>> ax = fig.axes[0]
    >>> len(fig.axes), ax.name, np.array(ax.lines[0].get_data_3d())[:, -1].tolist()    # the path ends at T1
    (1, '3d', [0.3, 0.2, 0.1])
    """
    if isinstance(traj, Trajectory):
        if traj.poses is None:
            raise InputError("traj: this trajectory has no poses (only Cartesian trajectories can be drawn in 3-D)")
        P = np.asarray(traj.poses, dtype=float)
        name = traj.name
    else:
        P = np.asarray(traj, dtype=float)
        name = "path"
    if P.ndim != 3 or P.shape[1:] != (4, 4) or P.shape[0] < 1:
        raise InputError(f"traj: expected poses of shape (K, 4, 4), got shape {P.shape}")
    p = P[:, :3, 3]
    extent = float(np.max(np.ptp(p, axis=0))) if len(p) > 1 else 0.0
    L = axis_length if axis_length is not None else (0.15 * extent if extent > 0 else 0.1)
    fig = _figure(figsize)
    ax = fig.add_subplot(projection="3d")
    ax.plot(p[:, 0], p[:, 1], p[:, 2], "k-", lw=1.5, label="path")
    ax.plot(*p[0], "go", label="start")
    ax.plot(*p[-1], "rs", label="end")
    idx: np.ndarray | list[int] = np.unique(np.linspace(0, len(P) - 1, max(int(frames), 0)).round().astype(int)) if frames > 0 else []
    for i in idx:
        for k, c in enumerate("rgb"):
            a = P[i, :3, k] * L
            ax.plot([p[i, 0], p[i, 0] + a[0]], [p[i, 1], p[i, 1] + a[1]], [p[i, 2], p[i, 2] + a[2]], c, lw=1.2)
    lo = p.min(axis=0) - L
    hi = p.max(axis=0) + L
    c = 0.5 * (lo + hi)
    r = 0.5 * float(np.max(hi - lo))
    ax.set_xlim(c[0] - r, c[0] + r)
    ax.set_ylim(c[1] - r, c[1] + r)
    ax.set_zlim(c[2] - r, c[2] + r)
    ax.set_xlabel("x (m)")
    ax.set_ylabel("y (m)")
    ax.set_zlabel("z (m)")
    ax.legend(loc="upper left", fontsize="small")
    ax.set_title(title if title is not None else name)
    return fig
