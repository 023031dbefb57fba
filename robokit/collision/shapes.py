"""Obstacles: primitive shapes and meshes placed in the robot's base frame.

Every obstacle has a ``pose`` (4×4 homogeneous transform of the shape's own frame in the
base frame, metres) and a ``name`` (used by :meth:`World.colliding_pairs`). Shapes are
centred on their frame's origin; a cylinder's axis is its frame's z axis.

Every number of an obstacle — sizes, radii, lengths, the pose, a mesh's vertices — is bounded
like every number of a robot file (at most :data:`robokit._arrays.MAX_MAGNITUDE` = 1e12 in
magnitude, SI units), checked before anything reaches coal (whose eigen solver loops and
prints on 1e300 coordinates).
"""
from __future__ import annotations

import os
from pathlib import Path
from typing import Any

import numpy as np

from robokit._arrays import as_array, as_scalar
from robokit._optional import require
from robokit.errors import InputError

__all__ = ["Obstacle", "Box", "Sphere", "Cylinder", "Mesh", "MAX_MESH_BYTES"]

MAX_MESH_BYTES = 64 * 2**20  # a user's obstacle mesh file may be at most 64 MiB


def _pose(pose: Any) -> np.ndarray:
    if pose is None:
        return np.eye(4)
    T = as_array(pose, "pose", (4, 4), bounded=True)
    R = T[:3, :3]
    if not np.allclose(R @ R.T, np.eye(3), atol=1e-6) or np.linalg.det(R) < 0 or not np.allclose(T[3], [0, 0, 0, 1]):
        raise InputError("pose: not a homogeneous transform (rotation part must be orthonormal, last row 0 0 0 1)")
    return T


class Obstacle:
    """Base of the obstacle shapes (not used directly); instances are read-only.

    Attributes
    ----------
    pose : ndarray, shape (4, 4)
        Pose of the shape's own frame in the robot's base frame (m).
    name : str
        The name :meth:`World.colliding_pairs <robokit.collision.World.colliding_pairs>`
        reports ("" lets the World call it ``<type>_<k>``).

    Examples
    --------
    >>> from robokit.collision import Box, Obstacle
    >>> isinstance(Box([1, 1, 1]), Obstacle)
    True
    """

    pose: np.ndarray
    name: str

    def __setattr__(self, key: str, value: Any) -> None:
        raise AttributeError(f"{type(self).__name__} is read-only")

    def _set(self, pose: Any, name: str, **fields: Any) -> None:
        """Set the shape's own (already checked) fields, then the checked ``pose`` and ``name``
        (the only writes a read-only obstacle gets, in this order: ``repr`` lists them so)."""
        for key, value in fields.items():
            object.__setattr__(self, key, value)
        object.__setattr__(self, "pose", _pose(pose))
        object.__setattr__(self, "name", name)

    def __repr__(self) -> str:
        fields = {k: v for k, v in vars(self).items() if k not in ("pose", "vertices", "faces")}
        body = ", ".join(f"{k}={v.tolist() if isinstance(v, np.ndarray) else v!r}" for k, v in fields.items())
        return f"{type(self).__name__}({body}, xyz={self.pose[:3, 3].tolist()})"

    def geometry(self) -> Any:  # pragma: no cover - overridden
        """The coal collision geometry of the shape (in its own frame).

        Returns
        -------
        coal.CollisionGeometry
        """
        raise NotImplementedError


class Box(Obstacle):
    """A box of full edge lengths ``size`` = (x, y, z) in m, centred on ``pose``'s origin.

    Parameters
    ----------
    size : array_like, shape (3,)
        Full edge lengths along the box frame's x, y, z axes (m), each > 0.
    pose, name : optional
        As for :class:`Obstacle`; the pose is the box centre's (identity by default).

    Attributes
    ----------
    size : ndarray, shape (3,)
        The edge lengths (m); ``pose`` and ``name`` as given.

    Examples
    --------
    >>> from robokit.collision import Box
    >>> Box([0.1, 0.2, 0.3]).size.tolist()
    [0.1, 0.2, 0.3]
    """

    size: np.ndarray

    def __init__(self, size: Any, pose: Any = None, name: str = "") -> None:
        s = as_array(size, "size", (3,), bounded=True)
        if (s <= 0).any():
            raise InputError(f"size: every edge length must be > 0, got {s.tolist()}")
        self._set(pose, str(name), size=s)

    def geometry(self) -> Any:
        """The coal geometry: ``coal.Box`` with the full edge lengths.

        Returns
        -------
        coal.Box
        """
        import coal
        return coal.Box(*self.size)


class Sphere(Obstacle):
    """A sphere of ``radius`` (m) centred on ``pose``'s origin.

    Parameters
    ----------
    radius : float
        Radius (m), > 0.
    pose, name : optional
        As for :class:`Obstacle`; the pose is the centre's (identity by default).

    Examples
    --------
    >>> from robokit.collision import Sphere
    >>> Sphere(0.1).radius
    0.1
    """

    radius: float

    def __init__(self, radius: Any, pose: Any = None, name: str = "") -> None:
        self._set(pose, str(name), radius=as_scalar(radius, "radius", positive=True, bounded=True))

    def geometry(self) -> Any:
        """The coal geometry.

        Returns
        -------
        coal.Sphere
        """
        import coal
        return coal.Sphere(self.radius)


class Cylinder(Obstacle):
    """A cylinder of ``radius`` and full ``length`` (m) along ``pose``'s z axis, centred on its origin.

    Parameters
    ----------
    radius, length : float
        Radius and full length along the frame's z axis (m), > 0.
    pose, name : optional
        As for :class:`Obstacle`; the pose is the centre's (identity by default), the axis its z.

    Examples
    --------
    >>> from robokit.collision import Cylinder
    >>> Cylinder(0.05, 1.0).length
    1.0
    """

    radius: float
    length: float

    def __init__(self, radius: Any, length: Any, pose: Any = None, name: str = "") -> None:
        self._set(pose, str(name), radius=as_scalar(radius, "radius", positive=True, bounded=True),
                  length=as_scalar(length, "length", positive=True, bounded=True))

    def geometry(self) -> Any:
        """The coal geometry (coal's length is the full length too).

        Returns
        -------
        coal.Cylinder
        """
        import coal
        return coal.Cylinder(self.radius, self.length)


class Mesh(Obstacle):
    """A triangle mesh read from ``path`` (STL, OBJ, PLY, … — what trimesh reads), in m.

    The file must be a regular file of at most :data:`MAX_MESH_BYTES` bytes; its triangles and
    vertices are counted from its bytes before it is parsed, and the parsed arrays checked
    before anything is built from them (at most 2,000,000 of each, coordinates of at most 1e12:
    :mod:`robokit.description.mesh_size`). It is read with trimesh (the ``viz`` extra). The mesh
    is used as given (a triangle soup for coal's BVH, no convex hull): collisions are with its
    surface.

    Parameters
    ----------
    path : str or path-like
        The mesh file (coordinates in m).
    pose, name : optional
        As for :class:`Obstacle`; the pose is the mesh frame's (identity by default), the
        default name the file's stem.

    Attributes
    ----------
    vertices : ndarray, shape (V, 3)
        Vertices (m) in the mesh frame (read once: a pickled Mesh carries them).
    faces : ndarray of int, shape (F, 3)
        Triangles as vertex indices.
    path : pathlib.Path
        The file read.

    Examples
    --------
    >>> import os, tempfile, trimesh
    >>> from robokit.collision import Mesh
    >>> path = os.path.join(tempfile.mkdtemp(), "block.stl")
    >>> _ = trimesh.creation.box([0.2, 0.2, 0.2]).export(path)
    >>> Mesh(path).faces.shape
    (12, 3)
    """

    path: Path
    vertices: np.ndarray
    faces: np.ndarray

    def __init__(self, path: str | os.PathLike[str], pose: Any = None, name: str = "") -> None:
        import io
        import warnings

        from robokit._io import read_input_bytes
        from robokit.description.mesh_size import check_mesh_arrays, check_mesh_bytes

        p = Path(path)
        try:
            raw = read_input_bytes(p, MAX_MESH_BYTES, "a mesh file")  # a regular file, bounded
        except InputError as exc:
            raise InputError(f"path: {exc}") from None
        ext = p.suffix.lower().lstrip(".")
        check_mesh_bytes(raw, ext, f"path: {p}")  # triangles counted before any parser runs
        trimesh = require("trimesh", "a Mesh obstacle")
        try:
            # numbers are judged once parsed (check_mesh_arrays): the parser's own overflow warnings
            # on absurd coordinates are not printed
            with warnings.catch_warnings(), np.errstate(all="ignore"):
                warnings.simplefilter("ignore")
                tm = trimesh.load(io.BytesIO(raw), file_type=ext, force="mesh",
                                  resolver=trimesh.resolvers.FilePathResolver(str(p)))
        except Exception as exc:  # trimesh raises many types for bad files
            raise InputError(f"path: cannot read mesh {p} ({str(exc)[:200]})") from None
        V, F = check_mesh_arrays(getattr(tm, "vertices", np.zeros((0, 3))), getattr(tm, "faces", np.zeros((0, 3))),
                                 f"path: {p}")
        self._set(pose, str(name) or p.stem, path=p, vertices=V, faces=F)

    def geometry(self) -> Any:
        """The coal geometry: a bounding-volume hierarchy of the triangles.

        Returns
        -------
        coal.BVHModelOBBRSS
        """
        import coal
        bvh = coal.BVHModelOBBRSS()
        bvh.beginModel(len(self.faces), len(self.vertices))
        bvh.addVertices(self.vertices)
        bvh.addTriangles(self.faces)
        bvh.endModel()
        return bvh
