r"""MJCF mesh assets as MuJoCo's compiler sees them: vertices, faces, volume, inertia (private).

Reading (bounded: the file was confined and size-checked by
:func:`robokit.description.mjcf_safety.check_mjcf`)
    * binary STL (MuJoCo reads no ASCII STL; at most 200,000 triangles, as MuJoCo);
    * OBJ: ``v`` and ``f`` lines of the file's first object or group, negative indices counted
      from the end; polygons split into triangles as MuJoCo 4.0.1 splits them (measured on its
      ``mesh_face``): a quad along its shorter diagonal (0–2 if shorter than 1–3, else 1–3), a
      polygon of five or more vertices (:data:`MAX_POLYGON` at most) by MuJoCo's ear clipping
      (:func:`_polygon`);
    * MSH, MuJoCo's own binary format;
    * inline ``vertex``/``face`` attributes (vertices only: their convex hull).
    Coordinates are single precision in MuJoCo, so they are rounded to float32 here too.

Processing (MuJoCo's order): ``refpos`` subtracted, ``refquat`` undone, ``scale`` applied
(a mirror flips the triangles' winding); the area-weighted centroid of the faces is the apex
of the union-of-pyramids construction; volume (or area, ``inertia="shell"``), centre of mass
and inertia are summed over the triangles (``legacy``: each pyramid counted positive;
``exact``: signed, a closed well-oriented mesh required; ``convex``: the convex hull's
triangles; ``shell``: the surface); the inertia is reduced to principal axes by Jacobi rotations
stopped where MuJoCo stops them (:func:`robokit.description._mjcf_math.jacobi_principal_axes`, relative
tolerance 1e-7: up to about 1e-7 rad short of the exact axes, as MuJoCo's frame is). MuJoCo moves the
mesh so that its centre of mass is at the origin and its principal axes are the coordinate
axes; the geom's frame absorbs that offset (``MeshInertia.pos``/``quat``).
"""
from __future__ import annotations

import math
import struct
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Sequence

import numpy as np

from robokit.description._mjcf_math import (MESH_EIG_RELTOL, MINVAL, Quat, Vec, conj, jacobi_principal_axes,
                                              quat_to_matrix, unit_quat)
from robokit.errors import InputError

#: Most triangles MuJoCo reads from one STL file.
MAX_STL_TRIANGLES = 200_000
#: Most vertices of one OBJ polygon robokit splits into triangles.
MAX_POLYGON = 1000
#: The work MuJoCo's ear clipping may take in one OBJ file: each triangle tried costs ``_TRY_COST``
#: plus the polygon's remaining vertices; a file may spend ``MAX_EAR_WORK`` plus ``_WORK_PER_VERTEX`` per
#: polygon vertex (a polygon of n vertices normally takes about n tries; a hostile one up to n²).
MAX_EAR_WORK, _TRY_COST, _WORK_PER_VERTEX = 10_000_000, 30, 40


@dataclass(frozen=True)
class MeshInertia:
    """What MuJoCo's compiler keeps of a mesh for mass and inertia.

    ``volume`` is the volume (the area for ``inertia="shell"``); ``pos``/``quat`` the centre of
    mass and principal frame in the mesh's (scaled) coordinates; ``box`` the half sizes of the
    box with the same principal moments per unit volume; ``aamm`` the axis-aligned bounds in the
    principal frame (min xyz, max xyz)."""

    volume: float
    pos: Vec
    quat: Quat
    box: Vec
    aamm: tuple[float, ...]
    vertices: np.ndarray  # (nv, 3) in the mesh's scaled coordinates (before centring)
    faces: np.ndarray  # (nf, 3)


def _float32(values: Any) -> np.ndarray:
    return np.asarray(values, dtype=np.float64).astype(np.float32).astype(np.float64)


def _read_stl(raw: bytes, where: str) -> tuple[np.ndarray, np.ndarray]:
    if len(raw) < 84:
        raise InputError(f"{where}: not a binary STL file (MuJoCo reads binary STL only)")
    (n,) = struct.unpack_from("<i", raw, 80)
    if n < 1 or n > MAX_STL_TRIANGLES or n * 50 != len(raw) - 84:
        raise InputError(f"{where}: not a binary STL file of 1 to {MAX_STL_TRIANGLES} triangles (an ASCII STL, "
                         "which MuJoCo does not read, or a truncated file)")
    rec = np.frombuffer(raw, dtype=np.dtype([("n", "<f4", 3), ("v", "<f4", (3, 3)), ("a", "<u2")]), count=n, offset=84)
    tri = rec["v"].astype(np.float64).reshape(-1, 3)
    if not np.isfinite(tri).all() or np.abs(tri).max() > 2.0 ** 30:
        raise InputError(f"{where}: vertex coordinates not finite or beyond 2^30")
    verts, inverse = np.unique(tri, axis=0, return_inverse=True)
    return verts, inverse.reshape(-1, 3)


def _quad(idx: Sequence[int], v: np.ndarray) -> list[tuple[int, int, int]]:
    """A quad's two triangles, split along the shorter diagonal (single precision, as MuJoCo's
    OBJ reader compares them; a tie splits along 1–3)."""
    a, b, c, d = (v[k].astype(np.float32) for k in idx)
    if float(((a - c) ** 2).sum()) < float(((b - d) ** 2).sum()):
        return [(idx[0], idx[1], idx[2]), (idx[0], idx[2], idx[3])]
    return [(idx[0], idx[1], idx[3]), (idx[1], idx[2], idx[3])]


def _inside3(x: Sequence[np.float32], y: Sequence[np.float32], tx: np.ndarray, ty: np.ndarray) -> np.ndarray:
    """Which of the points (tx, ty) are inside the triangle (x, y) by the crossing-number rule, in single
    precision (an edge whose ends are on one side of a point is not divided by: masked)."""
    inside = np.zeros(len(tx), dtype=bool)
    j = 2
    for i in range(3):  # (the caller silences the division by zero that the mask drops)
        straddles = (y[i] > ty) != (y[j] > ty)
        inside ^= straddles & (tx < (x[j] - x[i]) * (ty - y[i]) / (y[j] - y[i]) + x[i])
        j = i
    return inside


def _polygon(idx: Sequence[int], v: np.ndarray, budget: list[int], where: str) -> list[tuple[int, int, int]]:
    """Triangles of a polygon of five or more vertices as MuJoCo 4.0.1's OBJ reader clips them
    (single precision; its output measured on ``mesh_face``, a non-planar 11-gon of MuJoCo
    Menagerie's ARX L5 camera vertex for vertex). MuJoCo reads OBJ files with the tinyobjloader
    library, whose triangulation this reproduces as measured (written here from that output and
    this description, not from its code). The polygon is projected onto the coordinate
    plane its first corner faces most; then, from a guessed vertex, the triangle of it and its
    next two is cut off unless its turn and that of its first edge about the origin have opposite
    signs (MuJoCo's rule, not the polygon's orientation) or it holds one of the other vertices
    (the middle vertex leaves the ring and the guess stays), else the guess moves on; a ring
    that no cut shortens in a full turn is given up (its triangles are missing, as in MuJoCo).
    ``budget[0]``: the work the file may still spend (:data:`MAX_EAR_WORK`), so that a hostile file
    is refused in bounded time."""
    f = v.astype(np.float32)
    n = len(idx)
    axes = (1, 2)
    eps = np.finfo(np.float32).eps
    for k in range(n):  # the first corner with a cross product: the plane it faces most
        p0, p1, p2 = f[idx[k]], f[idx[(k + 1) % n]], f[idx[(k + 2) % n]]
        e0, e1 = p1 - p0, p2 - p1
        cx = abs(e0[1] * e1[2] - e0[2] * e1[1])
        cy = abs(e0[2] * e1[0] - e0[0] * e1[2])
        cz = abs(e0[0] * e1[1] - e0[1] * e1[0])
        if cx > eps or cy > eps or cz > eps:
            if not (cx > cy and cx > cz):
                axes = (0, 1) if cz > cx and cz > cy else (0, 2)
            break
    X = f[list(idx), axes[0]]
    Y = f[list(idx), axes[1]]
    out: list[tuple[int, int, int]] = []
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        _clip(np.arange(n), X, Y, out, idx, budget, where)
    return out


def _clip(ring: np.ndarray, X: np.ndarray, Y: np.ndarray, out: list[tuple[int, int, int]], idx: Sequence[int],
          budget: list[int], where: str) -> None:
    """The ear clipping of :func:`_polygon`, its triangles appended to ``out``."""
    half = np.float32(0.5)
    n = len(ring)
    guess, tries, before = 0, n, n
    while len(ring) > 3 and tries > 0:
        m = len(ring)
        if guess >= m:
            guess -= m
        if before != m:
            before, tries = m, m
        else:
            tries -= 1
        budget[0] -= _TRY_COST + m
        if budget[0] < 0:
            raise InputError(f"{where}: its polygons take too long to split into triangles (robokit's bound: "
                             f"{_TRY_COST} + n per triangle tried, {MAX_EAR_WORK} + {_WORK_PER_VERTEX} per polygon "
                             "vertex in all)")
        order = np.concatenate((ring[guess:], ring[:guess]))
        x, y = X[order[:3]], Y[order[:3]]
        cross = (x[1] - x[0]) * (y[2] - y[1]) - (y[1] - y[0]) * (x[2] - x[1])
        area = (x[0] * y[1] - y[0] * x[1]) * half  # MuJoCo's turn test: against the origin, not the polygon
        if cross * area < 0:
            guess += 1
            continue
        if _inside3(x, y, X[order[3:]], Y[order[3:]]).any():
            guess += 1
            continue
        out.append((idx[order[0]], idx[order[1]], idx[order[2]]))
        ring = np.delete(ring, (guess + 1) % m)
    if len(ring) == 3:
        out.append((idx[ring[0]], idx[ring[1]], idx[ring[2]]))


def _read_obj(text: str, where: str) -> tuple[np.ndarray, np.ndarray]:
    verts: list[list[float]] = []
    polygons: list[tuple[int, list[int]]] = []
    started = False
    for lineno, line in enumerate(text.splitlines(), 1):
        parts = line.split()
        if not parts:
            continue
        if parts[0] == "v":
            try:
                verts.append([float(x) for x in parts[1:4]])
            except ValueError:
                raise InputError(f"{where}:{lineno}: bad vertex line") from None
            if len(verts[-1]) != 3:
                raise InputError(f"{where}:{lineno}: a vertex needs three coordinates")
        elif parts[0] in ("o", "g") and polygons:
            started = True  # MuJoCo reads the first shape only
        elif parts[0] == "f" and not started:
            idx = []
            for p in parts[1:]:
                try:
                    k = int(p.split("/")[0])
                except ValueError:
                    raise InputError(f"{where}:{lineno}: bad face index {p!r}") from None
                idx.append(k - 1 if k > 0 else len(verts) + k)
            if len(idx) < 3:
                raise InputError(f"{where}:{lineno}: a face needs at least three vertices")
            if len(idx) > MAX_POLYGON:
                raise InputError(f"{where}:{lineno}: a face of {len(idx)} vertices (robokit splits polygons of at "
                                 f"most {MAX_POLYGON} into triangles)")
            polygons.append((lineno, idx))
    v = _float32(verts).reshape(-1, 3)
    faces: list[tuple[int, int, int]] = []
    budget = [MAX_EAR_WORK + _WORK_PER_VERTEX * sum(len(idx) for _, idx in polygons if len(idx) > 4)]
    for lineno, idx in polygons:
        if len(idx) == 3:
            faces.append((idx[0], idx[1], idx[2]))
            continue
        if min(idx) < 0 or max(idx) >= len(v):
            raise InputError(f"{where}:{lineno}: a face names a vertex that does not exist")
        faces.extend(_quad(idx, v) if len(idx) == 4 else _polygon(idx, v, budget, f"{where}:{lineno}"))
    return v, np.asarray(faces, dtype=np.int64).reshape(-1, 3)


def _read_msh(raw: bytes, where: str) -> tuple[np.ndarray, np.ndarray]:
    if len(raw) < 16:
        raise InputError(f"{where}: missing header in MSH file")
    nv, nn, nt, nf = struct.unpack_from("<4i", raw, 0)
    if nv < 4 or nf < 0 or nn < 0 or nt < 0 or (nn and nn != nv) or (nt and nt != nv):
        raise InputError(f"{where}: invalid sizes in MSH file")
    if len(raw) != 16 + 12 * nv + 12 * nn + 8 * nt + 12 * nf:
        raise InputError(f"{where}: unexpected file size in MSH file")
    verts = np.frombuffer(raw, "<f4", 3 * nv, 16).astype(np.float64).reshape(-1, 3)
    faces = np.frombuffer(raw, "<i4", 3 * nf, 16 + 12 * nv + 12 * nn + 8 * nt).astype(np.int64).reshape(-1, 3)
    return verts, faces


def read_ascii_stl(path: Path) -> tuple[np.ndarray, np.ndarray]:
    """(vertices, triangles) of an ASCII STL file — for drawing and collision only: MuJoCo
    reads no ASCII STL, so no mass comes from one."""
    from robokit._io import read_input_bytes
    from robokit.description.meshes import MAX_MESH_BYTES

    text = read_input_bytes(path, MAX_MESH_BYTES, "a mesh file").decode("ascii", errors="replace")
    pts = []
    for line in text.splitlines():
        parts = line.split()
        if len(parts) == 4 and parts[0] == "vertex":
            try:
                pts.append([float(x) for x in parts[1:]])
            except ValueError:
                raise InputError(f"{path}: bad vertex line {line.strip()!r}") from None
    if not pts or len(pts) % 3:
        raise InputError(f"{path}: no triangles in this ASCII STL")
    v = np.array(pts)
    return v, np.arange(len(v)).reshape(-1, 3)


def read_mesh_file(path: Path) -> tuple[np.ndarray, np.ndarray]:
    """(vertices (n, 3), triangles (m, 3)) of an STL, OBJ or MSH file as MuJoCo reads it."""
    from robokit._io import read_input_bytes
    from robokit.description.meshes import MAX_MESH_BYTES

    raw = read_input_bytes(path, MAX_MESH_BYTES, "a mesh file")
    ext = path.suffix.lower()
    where = str(path)
    if ext == ".stl":
        return _read_stl(raw, where)
    if ext == ".obj":
        return _read_obj(raw.decode("utf-8", errors="replace"), where)
    if ext == ".msh":
        return _read_msh(raw, where)
    raise InputError(f"{where}: MuJoCo reads .stl, .obj and .msh meshes, not {ext or 'a file without extension'}")


def _hull_faces(v: np.ndarray, where: str) -> np.ndarray:
    from scipy.spatial import ConvexHull, QhullError

    try:
        hull = ConvexHull(v)
    except (QhullError, ValueError) as exc:
        raise InputError(f"{where}: no convex hull ({str(exc).splitlines()[0][:120]})") from None
    f = hull.simplices.astype(np.int64)
    inside = v[hull.vertices].mean(axis=0)
    n = np.cross(v[f[:, 1]] - v[f[:, 0]], v[f[:, 2]] - v[f[:, 0]])
    flip = np.einsum("ij,ij->i", n, v[f].mean(axis=1) - inside) < 0
    f[flip] = f[flip][:, [0, 2, 1]]
    return f


def _triangles(v: np.ndarray, f: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Per triangle: area, unit normal, centre (MuJoCo drops triangles below 1e-15)."""
    a, b, c = v[f[:, 0]], v[f[:, 1]], v[f[:, 2]]
    n = np.cross(b - a, c - a)
    length = np.linalg.norm(n, axis=1)
    ok = length >= MINVAL
    area = np.where(ok, 0.5 * length, 0.0)
    unit = np.where(ok[:, None], n / np.where(ok, length, 1.0)[:, None], 0.0)
    return area, unit, (a + b + c) / 3


def mesh_inertia(vertices: np.ndarray, faces: np.ndarray | None, *, scale: Sequence[float] = (1, 1, 1),
                 refpos: Sequence[float] = (0, 0, 0), refquat: Sequence[float] = (1, 0, 0, 0),
                 inertia: str = "legacy", where: str = "mesh", msh: bool = False) -> MeshInertia:
    """Volume, centre of mass, principal frame and inertia box of a mesh, by MuJoCo's rules
    (module docstring). ``vertices`` are rounded to float32 first; ``faces`` None or empty:
    the convex hull's."""
    v = _float32(vertices).reshape(-1, 3)
    if len(v) < 4:
        raise InputError(f"{where}: a mesh needs at least 4 vertices")
    f = None if faces is None or len(faces) == 0 else np.asarray(faces, dtype=np.int64).reshape(-1, 3)
    if f is not None and (f.min() < 0 or f.max() >= len(v)):
        raise InputError(f"{where}: a face names a vertex that does not exist")
    if f is not None and inertia == "exact":
        area, _, _ = _triangles(v, f)
        big = f[area > math.sqrt(MINVAL)]
        half = np.concatenate([big[:, [0, 1]], big[:, [1, 2]], big[:, [2, 0]]])
        if len(np.unique(half, axis=0)) < len(half):
            raise InputError(f"{where}: faces have inconsistent orientation (MuJoCo refuses inertia='exact' on it)")
    hull = None
    if f is None or inertia == "convex":
        hull = _hull_faces(v, where)
        if f is None:
            f = hull
    s = np.asarray(scale, dtype=float)
    if s[0] * s[1] * s[2] < 0 and not msh:  # a mirror: MuJoCo flips the winding (an MSH file twice)
        f = f[:, [0, 2, 1]]
        hull = None if hull is None else hull[:, [0, 2, 1]]
    v = v - np.asarray(refpos, dtype=float)
    q = unit_quat(refquat)
    if q != (1.0, 0.0, 0.0, 0.0):
        R = np.array(quat_to_matrix(q)).reshape(3, 3)
        v = v @ R  # Rᵀ v per row
    v = v * s
    area, _, centre = _triangles(v, f)
    total = area.sum()
    if total < MINVAL:
        raise InputError(f"{where}: mesh surface area is too small")
    facecen = (area[:, None] * centre).sum(axis=0) / total
    used = hull if inertia == "convex" else f
    assert used is not None
    area_u, normal_u, centre_u = _triangles(v, used)
    if inertia == "shell":
        w = area
        vol = w.sum()
        if vol < MINVAL:
            raise InputError(f"{where}: mesh surface area is too small")
        com = (w[:, None] * (centre * 0.75 + facecen * 0.25)).sum(axis=0) / vol
    else:
        w = np.einsum("ij,ij->i", centre_u - facecen, normal_u) * area_u / 3
        if inertia == "legacy":
            w = np.abs(w)
        vol = w.sum()
        if vol < MINVAL:
            raise InputError(f"{where}: mesh volume is {'negative (misoriented triangles)' if vol < 0 else 'too small'}"
                             + ("" if vol < 0 else "; inertia='shell' reads thin meshes"))
        com = (w[:, None] * (centre_u * 0.75 + facecen * 0.25)).sum(axis=0) / vol
    # products of inertia about the centre of mass, apex at the centre of mass
    vc = v - com
    tri = f if inertia == "shell" else used
    ar, nr, ce = _triangles(vc, tri)
    if inertia == "shell":
        wv, C = ar, 12.0
    else:
        wv, C = np.einsum("ij,ij->i", ce, nr) * ar / 3, 20.0
        if inertia == "legacy":
            wv = np.abs(wv)
    total_volume = float(wv.sum())
    D, E, F = vc[tri[:, 0]], vc[tri[:, 1]], vc[tri[:, 2]]
    P = np.zeros(6)
    for j, (a, b) in enumerate(((0, 0), (1, 1), (2, 2), (0, 1), (0, 2), (1, 2))):
        term = (2 * (D[:, a] * D[:, b] + E[:, a] * E[:, b] + F[:, a] * F[:, b]) + D[:, a] * E[:, b]
                + D[:, b] * E[:, a] + D[:, a] * F[:, b] + D[:, b] * F[:, a] + E[:, a] * F[:, b] + E[:, b] * F[:, a])
        P[j] = float((wv / C * term).sum())
    full = (P[1] + P[2], -P[3], -P[4], -P[3], P[0] + P[2], -P[5], -P[4], -P[5], P[0] + P[1])
    ev, quat = jacobi_principal_axes(full, MESH_EIG_RELTOL)
    if ev[2] <= 0:
        raise InputError(f"{where}: eigenvalue of mesh inertia must be positive")
    tol = (1.0 - 1e-6)
    if (ev[0] + ev[1] < ev[2] * tol - 1e-9 or ev[0] + ev[2] < ev[1] * tol - 1e-9
            or ev[1] + ev[2] < ev[0] * tol - 1e-9):
        raise InputError(f"{where}: eigenvalues of mesh inertia violate A + B >= C")
    box = tuple(0.5 * math.sqrt(6 * x / total_volume) if x > 0 else 0.0
                for x in (ev[1] + ev[2] - ev[0], ev[0] + ev[2] - ev[1], ev[0] + ev[1] - ev[2]))
    R = np.array(quat_to_matrix(conj(quat))).reshape(3, 3)
    local = vc @ R.T
    aamm = tuple(local.min(axis=0).tolist() + local.max(axis=0).tolist())
    return MeshInertia(total_volume, (float(com[0]), float(com[1]), float(com[2])), quat,
                       (box[0], box[1], box[2]), aamm, v, f)
