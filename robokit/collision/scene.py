"""Scene YAML files: the obstacles of a :class:`~robokit.collision.World` (read strictly).

Format (documented for users in the scene YAML page of the documentation)::

    padding: 0.01            # optional, m (robot inflation)
    obstacles:
      - type: box            # box | sphere | cylinder | mesh
        name: wall           # optional, unique
        size: [0.4, 0.05, 0.8]        # box: full edge lengths (m)
        pose: {xyz: [0.45, 0.35, 0.4], rpy: [0, 0, 0]}   # base frame; m, rad (fixed-axis roll-pitch-yaw)
      - type: sphere
        radius: 0.1
      - type: cylinder
        radius: 0.05
        length: 0.6          # full length along the pose's z axis
      - type: mesh
        path: table.stl      # relative to the scene file's folder, and inside it (or a package folder)

Unknown keys are refused (naming the key and the obstacle).
"""
from __future__ import annotations

import os
from pathlib import Path
from typing import Any, Sequence

import numpy as np

from robokit._arrays import MAX_MAGNITUDE, as_array
from robokit._yaml import load_yaml_file
from robokit.collision.shapes import Box, Cylinder, Mesh, Obstacle, Sphere
from robokit.description.meshes import allowed_roots, is_inside
from robokit.errors import InputError

__all__ = ["load_scene", "pose_from_xyz_rpy"]

_KEYS = {"box": {"size"}, "sphere": {"radius"}, "cylinder": {"radius", "length"}, "mesh": {"path"}}


def pose_from_xyz_rpy(xyz: Any, rpy: Any) -> np.ndarray:
    """4×4 pose from a position (m) and URDF-style roll-pitch-yaw (rad): R = Rz(y) Ry(p) Rx(r).

    Parameters
    ----------
    xyz : array_like, shape (3,)
        Position of the frame's origin (m).
    rpy : array_like, shape (3,)
        Roll, pitch, yaw (rad), fixed axes x, y, z applied in that order (as URDF's ``rpy``).

    Returns
    -------
    ndarray, shape (4, 4)
        The homogeneous transform.

    Examples
    --------
    >>> pose_from_xyz_rpy([1, 2, 3], [0, 0, 0])[:3, 3].tolist()
    [1.0, 2.0, 3.0]
    """
    p = as_array(xyz, "xyz", (3,), bounded=True)
    r, pi, y = as_array(rpy, "rpy", (3,), bounded=True)
    cr, sr, cp, sp, cy, sy = np.cos(r), np.sin(r), np.cos(pi), np.sin(pi), np.cos(y), np.sin(y)
    T = np.eye(4)
    T[:3, :3] = [[cy * cp, cy * sp * sr - sy * cr, cy * sp * cr + sy * sr],
                 [sy * cp, sy * sp * sr + cy * cr, sy * sp * cr - cy * sr],
                 [-sp, cp * sr, cp * cr]]
    T[:3, 3] = p
    return T


def load_scene(path: str | os.PathLike[str], *, package_dirs: Sequence[str | os.PathLike[str]] | None = None,
               allow_outside_meshes: bool = False) -> tuple[list[Obstacle], float]:
    """Read a scene YAML file: its obstacles and padding.

    A mesh path is confined exactly like a robot file's meshes
    (:func:`robokit.description.meshes.is_inside`): after resolving symbolic links it must lie in
    the scene file's folder, the ROS package holding it or one of ``package_dirs``. Anything else
    (``/etc/passwd``, ``../secret.stl``, a symlink out) is refused before it is opened, with one
    message whether or not the file exists, unless ``allow_outside_meshes``.

    Parameters
    ----------
    path : str or path-like
        The .yaml file (format in the module docstring); mesh paths in it are relative to
        its folder.
    package_dirs : sequence of str or path-like, optional
        More folders mesh files may be read from.
    allow_outside_meshes : bool
        Read mesh files wherever the scene says (the user's explicit choice,
        ``--allow-outside-meshes``).

    Returns
    -------
    obstacles : list of Box, Sphere, Cylinder, Mesh
        In the file's order, poses in the robot's base frame.
    padding : float
        m (0 when the file has none).

    Raises
    ------
    InputError
        Naming the file, the obstacle (index) and the key that is wrong; a mesh path outside the
        allowed folders (``… is outside the file's folder, its package and the package folders
        given``).

    Examples
    --------
    >>> import os, tempfile
    >>> path = os.path.join(tempfile.mkdtemp(), "scene.yaml")
    >>> with open(path, "w") as f:
    ...     _ = f.write("padding: 0.01\\nobstacles:\\n  - {type: sphere, name: ball, radius: 0.1}\\n")
    >>> obstacles, padding = load_scene(path)
    >>> obstacles[0].name, padding
    ('ball', 0.01)
    """
    path = Path(path)
    doc = load_yaml_file(path)
    src = str(path)
    if not isinstance(doc, dict):
        raise InputError(f"{src}: expected a mapping with an 'obstacles' list")
    extra = set(doc) - {"obstacles", "padding"}
    if extra:
        raise InputError(f"{src}: unknown key {sorted(extra)[0]!r} (expected 'obstacles', 'padding')")
    padding = doc.get("padding", 0.0)
    if (isinstance(padding, bool) or not isinstance(padding, (int, float)) or not 0 <= padding <= MAX_MAGNITUDE):
        raise InputError(f"{src}: padding: expected a number in [0, {MAX_MAGNITUDE:g}] (m), got {padding!r}")
    roots = allowed_roots(path, package_dirs)
    items = doc.get("obstacles", [])
    if not isinstance(items, list):
        raise InputError(f"{src}: obstacles: expected a list")
    out: list[Obstacle] = []
    for k, it in enumerate(items):
        where = f"{src}: obstacle {k}"
        if not isinstance(it, dict):
            raise InputError(f"{where}: expected a mapping")
        kind = it.get("type")
        if kind not in _KEYS:
            raise InputError(f"{where}: type: expected one of box, sphere, cylinder, mesh, got {kind!r}")
        allowed = _KEYS[kind] | {"type", "name", "pose"}
        bad = set(it) - allowed
        if bad:
            raise InputError(f"{where}: unknown key {sorted(bad)[0]!r} for a {kind}")
        missing = _KEYS[kind] - set(it)
        if missing:
            raise InputError(f"{where}: missing {sorted(missing)[0]!r}")
        pose = it.get("pose", {}) or {}
        if not isinstance(pose, dict) or set(pose) - {"xyz", "rpy"}:
            raise InputError(f"{where}: pose: expected {{xyz: [x, y, z], rpy: [r, p, y]}}")
        name = it.get("name", "")
        if not isinstance(name, str):
            raise InputError(f"{where}: name: expected a string")
        try:
            T = pose_from_xyz_rpy(pose.get("xyz", [0, 0, 0]), pose.get("rpy", [0, 0, 0]))
            if kind == "box":
                out.append(Box(it["size"], T, name))
            elif kind == "sphere":
                out.append(Sphere(it["radius"], T, name))
            elif kind == "cylinder":
                out.append(Cylinder(it["radius"], it["length"], T, name))
            else:
                if not isinstance(it["path"], str) or not it["path"] or "\x00" in it["path"]:
                    raise InputError("path: expected a file name")
                mesh = path.parent / it["path"]
                if not (allow_outside_meshes or is_inside(mesh, roots)):  # checked before anything is opened
                    raise InputError(f"path: {it['path'][:100]!r} is outside the scene file's folder, its package "
                                     "and the package folders given (--allow-outside-meshes reads it)")
                out.append(Mesh(mesh, T, name))
        except InputError as exc:
            raise InputError(f"{where}: {exc}") from None
    return out, float(padding)
