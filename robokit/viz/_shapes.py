"""meshcat geometry of collision obstacles, shared by :mod:`robokit.viz.scene` and
:mod:`robokit.viz.teach` (it imports neither)."""
from __future__ import annotations

from typing import Any

import numpy as np

from robokit._optional import require
from robokit.errors import InputError

__all__ = ["obstacle_geometry", "ground_grid_segments"]

#: meshcat's cylinders stand along their y axis; robokit's (and coal's) along z.
_Y_TO_Z = np.array([[1.0, 0, 0, 0], [0, 0, -1, 0], [0, 1, 0, 0], [0, 0, 0, 1]])


def obstacle_geometry(obstacle: Any, index: int = 0) -> tuple[Any, np.ndarray]:
    """The meshcat geometry of one obstacle and the pose to draw it at.

    Parameters
    ----------
    obstacle : robokit.collision.Box, Sphere, Cylinder or Mesh
        The shape, with its ``pose`` (4×4, base frame, m).
    index : int
        Its position in the obstacle list (named in the error for anything else).

    Returns
    -------
    (geometry, T)
        A ``meshcat.geometry`` object and the 4×4 pose of its node (a cylinder's turned so
        that meshcat's y axis is the shape's z axis).

    Examples
    --------
    >>> from robokit.collision import Sphere
    >>> obstacle_geometry(Sphere(0.1))[1].shape
    (4, 4)
    """
    g = require("meshcat.geometry", "the viewer")
    kind = type(obstacle).__name__
    T = np.asarray(getattr(obstacle, "pose", np.eye(4)), dtype=float)
    if kind == "Box":
        return g.Box([float(x) for x in obstacle.size]), T
    if kind == "Sphere":
        return g.Sphere(float(obstacle.radius)), T
    if kind == "Cylinder":
        return g.Cylinder(float(obstacle.length), float(obstacle.radius)), T @ _Y_TO_Z
    if kind == "Mesh":
        return g.TriangularMeshGeometry(np.asarray(obstacle.vertices, dtype=float),
                                        np.asarray(obstacle.faces, dtype=np.int64)), T
    raise InputError(f"obstacles: item {index} is a {kind}, not a Box, Sphere, Cylinder or Mesh")


def ground_grid_segments(reach: float, spacing: float | None = None) -> tuple[np.ndarray, float, float]:
    """Line segments of a square ground grid in the z = 0 plane, centred on the origin, sized to ``reach``.

    Parameters
    ----------
    reach : float
        The robot's horizontal reach (m); the grid's half-width is ``1.1·reach`` rounded up to
        a whole number of cells.
    spacing : float, optional
        Cell size (m); default a round step (…, 0.05, 0.1, 0.2, 0.25, 0.5, 1, … m) giving about
        eight cells from the centre to the edge.

    Returns
    -------
    (points, half, spacing)
        ``points`` (3, 2L) float32, consecutive pairs being the ends of L segments (meshcat's
        ``LineSegments`` layout); the half-width and the cell size (m).

    Examples
    --------
    >>> _, half, spacing = ground_grid_segments(0.9)
    >>> round(half, 3), round(spacing, 3)
    (1.0, 0.125)
    """
    reach = max(float(reach), 0.1)
    if spacing is None:
        raw = 1.1 * reach / 8
        mag = 10.0 ** np.floor(np.log10(raw))
        spacing = float(min((m * mag for m in (1, 1.25, 2, 2.5, 5, 10) if m * mag >= raw - 1e-12), default=10 * mag))
    elif not (spacing > 0 and np.isfinite(spacing)):
        raise InputError(f"spacing: expected a positive cell size (m), got {spacing!r}")
    half = float(np.ceil(1.1 * reach / spacing - 1e-9) * spacing)
    ticks = np.arange(-half, half + 0.5 * spacing, spacing)
    seg = []
    for t in ticks:
        seg += [[t, -half, 0.0], [t, half, 0.0], [-half, t, 0.0], [half, t, 0.0]]
    return np.array(seg, dtype=np.float32).T, half, float(spacing)
