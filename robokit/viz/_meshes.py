r"""Compact meshes for self-contained pages: a robot's mesh files as coloured triangle lists,
decimated by vertex clustering.

A mesh file (``.dae``, ``.stl``, ``.obj``) is read with trimesh, which applies the file's node
transforms exactly as Pinocchio's loader (assimp, through coal) does — the vertices are in
the geometry object's own frame. Its parts are grouped by colour, and each group is
simplified by **vertex clustering**: space is cut into cubes of side ``cell``; the vertices in
one cube are replaced by their mean, triangles whose corners fall into fewer than three
cubes vanish, and repeated triangles are dropped. Every kept vertex is then within
``cell·√3`` of an original vertex and every original vertex within ``cell·√3`` of a kept one,
so at ``cell`` = 1–3 mm the picture is unchanged while the page shrinks several times.
"""
from __future__ import annotations

import os
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import ArrayLike
from robokit.errors import InputError

from robokit._optional import require
from robokit.description.mesh_size import MAX_MESH_TRIANGLES, check_mesh_arrays, check_mesh_bytes

__all__ = ["mesh_parts", "cluster_decimate", "decimated_visuals", "draw_parts", "PAGE_MESH_CELL"]

#: Cube side (m) of the vertex clustering of meshes written into pages (teach, view, Scene.html).
PAGE_MESH_CELL = 0.002


def cluster_decimate(vertices: ArrayLike, faces: ArrayLike, cell: float) -> tuple[np.ndarray, np.ndarray]:
    """Vertex-clustering simplification of one triangle mesh.

    vertices : (V, 3) float; faces : (F, 3) int; cell : cube side (same unit as vertices, > 0).
    Returns ``(vertices (V', 3) float64, faces (F', 3) int64)``: one vertex per occupied cube
    (the mean of its vertices), the triangles that still span three cubes, without repeats.
    """
    V = np.asarray(vertices, dtype=float)
    F = np.asarray(faces, dtype=np.int64)
    if not cell > 0:
        raise InputError(f"cell: expected a positive cube side, got {cell!r}")
    if len(V) == 0 or len(F) == 0:
        return np.zeros((0, 3)), np.zeros((0, 3), dtype=np.int64)
    keys = np.floor(V / cell).astype(np.int64)
    _, cluster, counts = np.unique(keys, axis=0, return_inverse=True, return_counts=True)
    cluster = cluster.ravel()
    sums = np.zeros((len(counts), 3))
    np.add.at(sums, cluster, V)
    newV = sums / counts[:, None]
    newF = cluster[F]
    keep = (newF[:, 0] != newF[:, 1]) & (newF[:, 1] != newF[:, 2]) & (newF[:, 0] != newF[:, 2])
    newF = newF[keep]
    if len(newF):
        # a triangle and its rotations are the same face: compare them in a canonical order
        # (rotated so that the smallest index comes first, keeping the orientation)
        r = np.argmin(newF, axis=1)
        idx = (np.arange(3)[None, :] + r[:, None]) % 3
        canon = np.take_along_axis(newF, idx, axis=1)
        _, first = np.unique(canon, axis=0, return_index=True)
        newF = newF[np.sort(first)]
    used = np.unique(newF)
    remap = np.full(len(newV), -1, dtype=np.int64)
    remap[used] = np.arange(len(used))
    return newV[used], remap[newF]


def _color_of(geom: Any) -> tuple:
    """(r, g, b, a) in [0, 1] of a trimesh geometry (its material's main colour, else grey)."""
    visual: Any = getattr(geom, "visual", None)
    try:
        c = np.asarray(visual.material.main_color, dtype=float)
    except Exception:
        try:
            c = np.asarray(visual.main_color, dtype=float)
        except Exception:
            c = np.array([170, 170, 170, 255], dtype=float)
    c = c.ravel()
    if c.size == 3:
        c = np.r_[c, 255.0]
    return tuple(np.round(c[:4] / 255.0, 3))


#: Most triangles a mesh file may hold to be drawn (the file is refused beyond, with its count):
#: robokit's one bound for every mesh file (:mod:`robokit.description.mesh_size`).
MAX_MESH_FACES = MAX_MESH_TRIANGLES
#: Most triangles one mesh file may put on a page after decimation; beyond, the cube side is
#: doubled until it fits (a note gives the sizes).
MAX_PAGE_FACES = 200_000


def mesh_parts(path: str | os.PathLike[str], cell: float, override_rgba: ArrayLike | None = None) -> list:
    """The mesh file ``path`` as decimated parts ``[(vertices (V, 3), faces (F, 3), rgba), …]``.

    Parts of one colour are merged; ``override_rgba`` (4,) paints everything one colour (the
    URDF's material when it overrides the file's). Vertices are in the file's frame (node
    transforms applied, mesh scale not), in the file's unit as trimesh reads it.

    The file is read bounded (a regular file of at most
    :data:`robokit.description.meshes.MAX_MESH_BYTES`); a mesh of more than
    :data:`MAX_MESH_FACES` triangles is refused with its count, counted from the file's bytes
    before it is parsed (:func:`robokit.description.mesh_size.check_mesh_bytes`) and again once
    parsed; the decimated result keeps at
    most :data:`MAX_PAGE_FACES` triangles (``cell`` is doubled until it does, with a note).
    """
    import io
    import warnings

    trimesh = require("trimesh", "drawing meshes")

    from robokit._io import read_input_bytes
    from robokit.description.meshes import MAX_MESH_BYTES
    from robokit.errors import InputError, RobokitWarning

    raw = read_input_bytes(path, MAX_MESH_BYTES, "a mesh file")
    ext = os.path.splitext(str(path))[1].lower().lstrip(".")
    check_mesh_bytes(raw, ext, path)  # triangles counted before trimesh parses anything
    resolver = trimesh.resolvers.FilePathResolver(str(path))  # an OBJ's .mtl, a COLLADA's textures
    with warnings.catch_warnings(), np.errstate(all="ignore"):  # numbers are judged once parsed
        warnings.simplefilter("ignore")
        scene: Any = trimesh.load(io.BytesIO(raw), file_type=ext, force="scene", resolver=resolver)
    groups: dict[tuple, list[tuple[np.ndarray, np.ndarray]]] = {}
    total = 0
    for node in scene.graph.nodes_geometry:
        T, name = scene.graph[node]
        geom = scene.geometry.get(name)
        if geom is None or not hasattr(geom, "faces") or len(geom.faces) == 0:
            continue
        total += len(geom.faces)
        if total > MAX_MESH_FACES:
            raise InputError(f"{path}: mesh of more than {MAX_MESH_FACES} triangles; robokit draws meshes of at most "
                             f"{MAX_MESH_FACES} (decimate it first)")
        V, F = check_mesh_arrays(np.asarray(geom.vertices, dtype=float) @ T[:3, :3].T + T[:3, 3], geom.faces, path)
        rgba = tuple(np.round(np.asarray(override_rgba, float), 3)) if override_rgba is not None else _color_of(geom)
        groups.setdefault(rgba, []).append((V, F))
    merged = []
    for rgba, items in groups.items():
        offs = np.cumsum([0] + [len(v) for v, _ in items[:-1]])
        V = np.vstack([v for v, _ in items])
        F = np.vstack([f + o for (_, f), o in zip(items, offs)])
        merged.append((V, F, rgba))
    c = cell
    for _ in range(40):
        parts = []
        for V, F, rgba in merged:
            Vd, Fd = cluster_decimate(V, F, c)
            if len(Fd):
                parts.append((Vd, Fd, rgba))
        kept = sum(len(p[1]) for p in parts)
        if kept <= MAX_PAGE_FACES:
            break
        c *= 2.0
    if c != cell:
        warnings.warn(f"{path}: {total} triangles decimated to {kept} for the page (cube side {c:g} instead of "
                      f"{cell:g}; at most {MAX_PAGE_FACES} per mesh)", RobokitWarning, stacklevel=2)
    return parts


def decimated_visuals(visual_model: Any, cell: float = PAGE_MESH_CELL) -> list[tuple[Any, list]]:
    """``(geometry object, parts)`` for every visual of a Pinocchio ``GeometryModel`` drawn from a
    mesh file (``.dae``, ``.stl``, ``.obj``), its parts from :func:`mesh_parts` (the URDF's colour
    when it overrides the file's, and always for STL files, which have none).

    Parameters
    ----------
    visual_model : pinocchio.GeometryModel
        The robot's visuals.
    cell : float
        Cube side of the decimation (m, in the meshes' own unit).

    Returns
    -------
    list of (pinocchio.GeometryObject, list)
        Only the mesh-file visuals (primitives are drawn as they are).
    """
    out = []
    for go in visual_model.geometryObjects:
        ext = Path(go.meshPath).suffix.lower() if go.meshPath else ""
        if ext in (".dae", ".stl", ".obj") and Path(go.meshPath).is_file():
            override = np.asarray(go.meshColor, float) if (go.overrideMaterial or ext == ".stl") else None
            out.append((go, mesh_parts(go.meshPath, cell, override)))
    return out


def draw_parts(node: Any, parts: list) -> None:
    """Draw decimated parts as the children ``part0``, ``part1``, … of a meshcat node (a Phong
    material of each part's colour and opacity); the node's own transform places them.

    Parameters
    ----------
    node : meshcat.Visualizer
        The node (``vis[path]``) the mesh file was drawn at.
    parts : list
        From :func:`mesh_parts`.
    """
    g = require("meshcat.geometry", "drawing meshes")
    for i, (V, F, rgba) in enumerate(parts):
        color = int(rgba[0] * 255) * 65536 + int(rgba[1] * 255) * 256 + int(rgba[2] * 255)
        node[f"part{i}"].set_object(g.TriangularMeshGeometry(V, F),
                                    g.MeshPhongMaterial(color=color, opacity=float(rgba[3]), shininess=30))
