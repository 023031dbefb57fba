"""meshcat geometry of collision obstacles, shared by :mod:`robokit.viz.scene` and
:mod:`robokit.viz.teach` (it imports neither)."""
from __future__ import annotations

from typing import Any

import numpy as np

from robokit._optional import require
from robokit.errors import InputError

__all__ = ["obstacle_geometry"]

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
