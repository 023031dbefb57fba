"""Pictures of capability maps: matplotlib slices for notebooks and a meshcat page of the voxels.

Colours follow the index from 0 (dark) to 1 (bright, the dexterous workspace) with
matplotlib's ``viridis`` colour map in both.
"""
from __future__ import annotations

import os
from typing import TYPE_CHECKING, cast

import numpy as np
from numpy.typing import ArrayLike
from robokit.errors import InputError, InputTypeError

from robokit._optional import require

if TYPE_CHECKING:
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure, SubFigure
    from robokit.description.robot import Robot
    from robokit.workspace.capability import CapabilityMap

__all__ = ["plot_capability_slice", "capability_html", "legend_html", "map_view_direction"]

_AXES = {"x": 0, "y": 1, "z": 2}


def _as_map(cmap: CapabilityMap | str | os.PathLike[str]) -> CapabilityMap:
    from robokit.workspace.capability import CapabilityMap

    if isinstance(cmap, CapabilityMap):
        return cmap
    if isinstance(cmap, (str, bytes)) or hasattr(cmap, "__fspath__"):
        return CapabilityMap.load(cast("str | os.PathLike[str]", cmap))
    raise InputTypeError(f"map: expected a CapabilityMap or an .npz path, got {type(cmap).__name__}")


def plot_capability_slice(cmap: CapabilityMap | str | os.PathLike[str], axis: str = "z", value: float | None = None, ax: Axes | None = None, cmap_name: str = "viridis") -> Figure | SubFigure:
    """Draw the voxels of one slice of a capability map, coloured by their index.

    Parameters
    ----------
    cmap : :class:`CapabilityMap` or path of an ``.npz`` map
    axis : {"x", "y", "z"}
        The base-frame axis the slice is perpendicular to.
    value : float, optional
        Coordinate of the slice along ``axis`` (m); the voxels whose centre is within half a
        voxel of it are drawn. Default: the coordinate with the most voxels. A planar arm's
        map is one slice: use the axis along its normal (``z`` for the shipped models).
    ax : matplotlib Axes, optional
    cmap_name : str
        matplotlib colour map.

    Returns
    -------
    matplotlib.figure.Figure

    Examples
    --------
    >>> import robokit
    >>> m = robokit.capability_map("rrr", 0.1, orientations=8, client="serial")
    >>> fig = plot_capability_slice(m, "z")
    """
    plt = require("matplotlib.pyplot", "plotting a capability map")

    m = _as_map(cmap)
    if axis not in _AXES:
        raise InputError(f"axis: expected 'x', 'y' or 'z', got {axis!r}")
    k = _AXES[axis]
    others = [i for i in range(3) if i != k]
    coord = m.centres[:, k]
    if len(coord) == 0:
        raise InputError("map: has no voxels")
    if value is None:
        levels, counts = np.unique(np.round(coord / m.resolution), return_counts=True)
        value = float(levels[np.argmax(counts)] * m.resolution)
    value = float(value)
    if not np.isfinite(value):
        raise InputError(f"value: expected a finite coordinate in m, got {value!r}")
    sel = np.abs(coord - value) <= 0.5 * m.resolution + 1e-12
    if not sel.any():
        raise InputError(f"value: no voxel centre within {0.5 * m.resolution:g} m of {axis} = {value:g} m "
                         f"(the map spans {coord.min():.3g} … {coord.max():.3g} m)")
    fig: Figure | SubFigure
    if ax is None:
        fig, ax = plt.subplots(figsize=(5.5, 5))
    else:
        fig = ax.figure
    P, D = m.centres[sel], m.index[sel]
    names = "xyz"
    sc = ax.scatter(P[:, others[0]], P[:, others[1]], c=D, cmap=cmap_name, vmin=0.0, vmax=1.0, marker="s",
                    s=max(4.0, 2000.0 / max(1.0, np.sqrt(len(P)))), linewidths=0)
    fig.colorbar(sc, ax=ax, label="capability index")
    ax.set_aspect("equal")
    ax.set_xlabel(f"{names[others[0]]} [m]")
    ax.set_ylabel(f"{names[others[1]]} [m]")
    title = f"{m.robot} " if m.robot else ""
    ax.set_title(f"{title}capability map, {axis} = {value:.3g} m (K = {len(m.orientations)})")
    return fig


def legend_html(cmap: CapabilityMap, cmap_name: str = "viridis") -> str:
    """The colour legend of a map page: a bar from index 0 to 1 in the points' colour map, with
    what the index means and the map's size.

    Parameters
    ----------
    cmap : CapabilityMap
        The map (its K and voxel count are written in the legend).
    cmap_name : str
        A matplotlib colour map name (the one the points use; default ``"viridis"``).

    Returns
    -------
    str
        An HTML ``<div id="robokit-legend">`` fixed in the page's lower-left corner.

    Examples
    --------
    >>> import robokit
    >>> cmap = robokit.capability_map("rrr", 0.2, orientations=4, client="serial")
    >>> "fraction of the 4 tool orientations" in legend_html(cmap)
    True
    """
    stops = ", ".join(f"rgb({r * 255:.0f},{g * 255:.0f},{b * 255:.0f}) {100 * t:.0f}%"
                      for t, (r, g, b) in zip(np.linspace(0, 1, 11), _colours(np.linspace(0, 1, 11), cmap_name)))
    K = len(cmap.orientations)
    return (
        '<div id="robokit-legend" style="position:fixed;left:12px;bottom:12px;z-index:10;padding:8px 10px;'
        'background:rgba(255,255,255,0.88);border-radius:6px;font:13px sans-serif;color:#222">'
        f'<div>capability index: fraction of the {K} tool orientations reachable</div>'
        f'<div style="height:14px;width:260px;margin:6px 0 2px;background:linear-gradient(to right, {stops})"></div>'
        '<div style="display:flex;justify-content:space-between;width:260px"><span>0</span><span>0.5</span>'
        f'<span>1</span></div><div>{len(cmap.centres)} voxels of {cmap.resolution:g} m</div></div>')


def _with_legend(page: str, cmap: CapabilityMap) -> str:
    i = page.rfind("</body>")
    legend = legend_html(cmap)
    return page[:i] + legend + page[i:] if i >= 0 else page + legend


def _colours(index: ArrayLike, cmap_name: str = "viridis") -> np.ndarray:
    colormaps = require("matplotlib", "colouring a capability map").colormaps

    return colormaps[cmap_name](np.clip(index, 0.0, 1.0))[:, :3]


def _outline(centres: np.ndarray) -> np.ndarray:
    """The points that frame a map: the vertices of its centres' convex hull (a perspective view of
    the hull is the hull of the projected vertices), or all of them when the hull is flat."""
    from scipy.spatial import ConvexHull, QhullError

    P = np.asarray(centres, dtype=float).reshape(-1, 3)
    try:
        return P[ConvexHull(P).vertices]
    except (QhullError, ValueError):  # flat (a planar arm's map) or too few points
        return P


def map_view_direction(centres: ArrayLike) -> tuple[float, float]:
    """The direction (azimuth, elevation in degrees) a map page looks from.

    A map that fills a volume is seen from the usual 3/4 view (45°, 25°). A flat map — a planar
    arm's, whose voxel centres span a plane: the smallest of their principal extents is below
    0.15 of the largest — is seen 25° off its normal (towards the 3/4 view), nearly face-on: from
    the 3/4 view a horizontal map would be foreshortened to sin 25° = 0.42 of its depth,
    almost edge-on.

    Parameters
    ----------
    centres : array_like, shape (M, 3)
        The voxel centres (m).

    Returns
    -------
    azimuth, elevation : float
        Degrees.

    Examples
    --------
    >>> disk = [[np.cos(a), np.sin(a), 0.0] for a in np.linspace(0, 6, 40)]
    >>> [round(v, 1) for v in map_view_direction(disk)]
    [45.0, 65.0]
    """
    P = np.asarray(centres, dtype=float).reshape(-1, 3)
    az0, el0 = np.deg2rad(45.0), np.deg2rad(25.0)
    d0 = np.array([np.cos(el0) * np.cos(az0), np.cos(el0) * np.sin(az0), np.sin(el0)])
    if len(P) < 3:
        return 45.0, 25.0
    _, s, Vt = np.linalg.svd(P - P.mean(axis=0), full_matrices=False)
    if not (s[0] > 0 and s[-1] < 0.15 * s[0]):
        return 45.0, 25.0
    n = Vt[-1]
    if abs(n[2]) > 1e-9:
        n = n if n[2] > 0 else -n  # from above
    elif n @ d0 < 0:
        n = -n
    t = d0 - (d0 @ n) * n
    if np.linalg.norm(t) < 1e-9:  # the normal is the 3/4 direction itself
        t = np.cross(n, [0.0, 0.0, 1.0]) if abs(n[2]) < 0.9 else np.cross(n, [1.0, 0.0, 0.0])
    t = t / np.linalg.norm(t)
    d = np.cos(np.deg2rad(25.0)) * n + np.sin(np.deg2rad(25.0)) * t
    return float(np.degrees(np.arctan2(d[1], d[0]))), float(np.degrees(np.arcsin(np.clip(d[2], -1.0, 1.0))))


def capability_html(cmap: CapabilityMap | str | os.PathLike[str], robot: Robot | str | None = None, point_size: float | None = None) -> str:
    """A self-contained meshcat page of a capability map: one coloured point per voxel.

    Parameters
    ----------
    cmap : :class:`CapabilityMap` or path of an ``.npz`` map
    robot : robot or anything ``robokit.load`` accepts, optional
        Drawn at its zero configuration when given. Default: the robot the map describes
        (its ``description``: a shipped or example-robot-data name, a DH table or the chain's
        geometry, see :mod:`robokit.workspace.map_robot`), else none. A path stored in a map
        is never opened: only one passed here.
    point_size : float, optional
        Point size (m); default 0.6 × the resolution.

    Returns
    -------
    str
        The HTML page (no server needed to view it).

    Examples
    --------
    >>> import robokit
    >>> page = capability_html(robokit.capability_map("rrr", 0.1, orientations=8, client="serial"))
    """
    g = require("meshcat.geometry", "viewing a capability map")

    from robokit.viz.scene import Scene, camera_offset, new_visualizer, stop_server

    m = _as_map(cmap)
    if robot is None and m.description is not None:
        robot = m.description.robot()
    P = m.centres.T.astype(np.float32)
    C = _colours(m.index).T.astype(np.float32)
    size = float(point_size) if point_size is not None else 0.6 * m.resolution
    cloud = g.PointCloud(position=P, color=C, size=size)
    azimuth, elevation = map_view_direction(m.centres)
    if robot is not None:
        with Scene(robot) as scene:
            scene.show(None)
            scene.vis["points/capability"].set_object(cloud)
            scene.include(_outline(m.centres))  # the map is what the view frames
            scene.frame_camera(0.7, azimuth, elevation)
            return _with_legend(scene.html(), m)
    vis = new_visualizer()
    try:
        vis["points/capability"].set_object(cloud)
        outline = _outline(m.centres) if len(m.centres) else np.zeros((1, 3))
        centre, off = camera_offset(outline, 0.7, azimuth, elevation)
        T = np.eye(4)
        T[:3, 3] = -centre
        for name in ("points", "/Grid", "/Axes"):
            vis[name].set_transform(T)
        vis["/Cameras/default/rotated/<object>"].set_property("position", [off[0], off[2], -off[1]])
        return _with_legend(vis.static_html(), m)
    finally:
        stop_server(getattr(vis.window, "server_proc", None))
