r"""How big a mesh file is, in triangles and vertices, read from its bytes before any mesh
library parses it — one rule for every mesh robokit reads (a robot's meshes loaded by
Pinocchio, a scene's obstacle meshes loaded by trimesh, the meshes drawn on a teach page).

A byte cap does not bound triangles: an OBJ face line ``f 1 2 1 2 1 2 …`` is a polygon fan of
one triangle per two bytes, so a 36 MB file makes 18 million triangles (2.5 GB in trimesh, and
more in coal's BVH). So the size a file declares is counted first, by format:

==========================  ==========================================================
STL (binary, ASCII)         50 bytes (binary) or more (ASCII) per triangle: the byte cap bounds it
OBJ                         ``v`` lines; per ``f`` line, its corners − 2
PLY (ASCII, binary)         the header's vertex count; per face, its corners − 2
OFF                         the header's counts; per face line, its corners − 2
COLLADA (``.dae``)          per ``<triangles>``/``<polylist>``/``<polygons>``/fans/strips, its
                            triangles, times the instances of its geometry in the scene
glTF (``.gltf``, ``.glb``)  per primitive, its index (or vertex) count, times the nodes using its mesh
==========================  ==========================================================

Other formats are counted as one triangle per byte (no uncompressed format packs more) and read
only when that bound is within the limits; compressed containers (``.3mf``, ``.zae``, ``.fbx``,
``.blend``, ``.ifczip``) are refused. A file of more than :data:`MAX_MESH_TRIANGLES` triangles or
:data:`MAX_MESH_VERTICES` vertices is refused with its count, before it is parsed, and so is a
text file (or binary STL) holding a number beyond 1e12 in magnitude; once parsed,
:func:`check_mesh_arrays` checks the arrays themselves (counts, finite coordinates of at most
1e12) before anything is built from them.
"""
from __future__ import annotations

import json
import os
import re
import struct
from typing import Any, Iterable

import numpy as np

from robokit._arrays import MAX_MAGNITUDE
from robokit.errors import InputError

__all__ = ["MAX_MESH_TRIANGLES", "MAX_MESH_VERTICES", "COUNTED_FORMATS", "mesh_counts", "check_mesh_bytes",
           "check_mesh_arrays"]

#: Most triangles one mesh file may make (the largest mesh of example-robot-data has about
#: 700,000; Pinocchio's loader takes over a gigabyte for two million).
MAX_MESH_TRIANGLES = 2_000_000
#: Most vertices one mesh file may make.
MAX_MESH_VERTICES = 2_000_000
#: The formats counted from their structure (see the module docstring).
COUNTED_FORMATS = ("stl", "obj", "ply", "off", "dae", "gltf", "glb")
_COMPRESSED = ("3mf", "zae", "fbx", "blend", "ifczip", "zip", "gz", "7z")


def mesh_counts(raw: bytes, ext: str) -> tuple[int, int]:
    """Upper bounds of the vertices and triangles the mesh file ``raw`` makes, from its bytes.

    Parameters
    ----------
    raw : bytes
        The file's content.
    ext : str
        Its format: the file extension, with or without the dot, any case.

    Returns
    -------
    (int, int)
        Vertices and triangles (each at least what a parser makes of the file).

    Raises
    ------
    InputError
        A compressed container format (``fbx``, ``3mf``, …), or a COLLADA file that is not
        XML robokit reads (a ``<!DOCTYPE>``, nodes instancing each other in a cycle).

    Examples
    --------
    >>> mesh_counts(b"v 0 0 0\\nv 1 0 0\\nv 0 1 0\\nv 1 1 0\\nf 1 2 4 3\\n", ".obj")
    (4, 2)
    """
    e = ext.lower().lstrip(".")
    if e in _COMPRESSED:
        raise InputError(f"a .{e} file is compressed: robokit cannot bound what it expands to; export the mesh as "
                         "STL, OBJ, PLY or COLLADA")
    counter = {"stl": _stl, "obj": _obj, "ply": _ply, "off": _off, "dae": _dae, "gltf": _gltf, "glb": _glb}.get(e)
    if counter is None:
        return len(raw), len(raw)
    return counter(raw)


def check_mesh_bytes(raw: bytes, ext: str, source: str | os.PathLike[str]) -> tuple[int, int]:
    """Refuse a mesh file that makes more than :data:`MAX_MESH_TRIANGLES` triangles or
    :data:`MAX_MESH_VERTICES` vertices, before it is parsed (:func:`mesh_counts`).

    Parameters
    ----------
    raw : bytes
        The file's content.
    ext : str
        Its extension.
    source : str or Path
        The file, for the message.

    Returns
    -------
    (int, int)
        The counted vertices and triangles.

    Raises
    ------
    InputError
        ``SOURCE: mesh of 18000000 triangles; robokit reads meshes of at most 2000000 …``.

    Examples
    --------
    >>> check_mesh_bytes(b"v 0 0 0\\nv 1 0 0\\nv 0 1 0\\nf 1 2 3\\n", "obj", "tri.obj")
    (3, 1)
    """
    try:
        v, t = mesh_counts(raw, ext)
    except InputError as exc:
        raise InputError(f"{source}: {exc}") from None
    counted = ext.lower().lstrip(".") in COUNTED_FORMATS
    big = _largest_number(raw, ext.lower().lstrip("."))
    if big > MAX_MAGNITUDE:
        raise InputError(f"{source}: a vertex coordinate of {big:g} is out of range (at most {MAX_MAGNITUDE:g} in "
                         "magnitude, like every number of a robot file)")
    for what, count, limit in (("triangles", t, MAX_MESH_TRIANGLES), ("vertices", v, MAX_MESH_VERTICES)):
        if count > limit:
            size = (f"{count} {what}" if counted else
                    f"{len(raw)} bytes of a format robokit does not count (up to one triangle per byte)")
            raise InputError(f"{source}: mesh of {size}; robokit reads meshes of at most {limit} {what} "
                             "(decimate it first)")
    return v, t


def check_mesh_arrays(vertices: Any, faces: Any, source: str | os.PathLike[str]) -> tuple[np.ndarray, np.ndarray]:
    """A parsed mesh's arrays, checked before anything is built from them: at most
    :data:`MAX_MESH_VERTICES` vertices and :data:`MAX_MESH_TRIANGLES` triangles, finite coordinates
    of at most 1e12 in magnitude, indices inside the vertex array.

    Parameters
    ----------
    vertices : array_like, shape (V, 3)
        Coordinates.
    faces : array_like of int, shape (F, 3)
        Triangles.
    source : str or Path
        The file, for the message.

    Returns
    -------
    (ndarray, ndarray)
        ``vertices`` as float64 (V, 3) and ``faces`` as int64 (F, 3).

    Raises
    ------
    InputError
        Naming the file and what is wrong.

    Examples
    --------
    >>> V, F = check_mesh_arrays([[0, 0, 0], [1, 0, 0], [0, 1, 0]], [[0, 1, 2]], "tri.obj")
    >>> V.shape, F.shape
    ((3, 3), (1, 3))
    """
    V = np.asarray(vertices, dtype=float)
    F = np.asarray(faces, dtype=np.int64)
    if V.ndim != 2 or V.shape[1:] != (3,) or F.ndim != 2 or F.shape[1:] != (3,) or len(F) == 0:
        raise InputError(f"{source}: holds no triangles")
    if len(F) > MAX_MESH_TRIANGLES or len(V) > MAX_MESH_VERTICES:
        raise InputError(f"{source}: mesh of {len(F)} triangles and {len(V)} vertices; robokit reads meshes of at "
                         f"most {MAX_MESH_TRIANGLES} triangles and {MAX_MESH_VERTICES} vertices (decimate it first)")
    if not np.isfinite(V).all():
        raise InputError(f"{source}: a vertex coordinate is NaN or infinite")
    big = float(np.abs(V).max()) if V.size else 0.0
    if big > MAX_MAGNITUDE:
        raise InputError(f"{source}: a vertex coordinate of {big:g} is out of range (at most {MAX_MAGNITUDE:g} in "
                         "magnitude, like every number of a robot file)")
    if F.min() < 0 or F.max() >= len(V):
        raise InputError(f"{source}: a triangle names a vertex the mesh does not have")
    return V, F


# ----------------------------------------------------------------------------- magnitudes
#: A number of a text mesh that may exceed 1e12: an exponent of 12 or more, or 13 digits in a row —
#: a whole token: not part of a word, nor of a name joined by hyphens (a COLLADA exporter's UUID ids,
#: ``mesh-a0ec2a07-c575-44a5-9e27-ecb9…``, hold ``9e27`` and ``303287e80685`` between hyphens; the
#: number's own sign is matched at the hyphen, where the byte before it is a separator).
_HUGE = re.compile(rb"(?<![\w.-])[+-]?(?:[0-9]{13,}\.?[0-9]*|[0-9]*\.?[0-9]+[eE]\+?0*(?:[0-9]{3,}|1[2-9]|[2-9][0-9]))"
                   rb"(?![\w.+-])")
#: What every match of ``_HUGE`` contains (13 digits in a row, or an exponent of 12 or more), found
#: without the look-behind: most meshes have none, and then the scan with ``_HUGE`` is skipped
#: (:func:`_maybe_huge`).
_MAYBE_EXPONENT = re.compile(rb"[eE]\+?0*(?:[0-9]{3}|1[2-9]|[2-9][0-9])")


def _maybe_huge(raw: bytes) -> bool:
    """Whether ``raw`` holds 13 digits in a row or an exponent of 12 or more (``_MAYBE_EXPONENT``):
    the digits counted with numpy (a window of 13 bytes all digits), the exponent with the regular
    expression, which starts only at an ``e``. One regular expression for both scanned every digit:
    measured on example-robot-data's Baxter COLLADA meshes (24 files, 26 MB), 1.04 s; this, 0.32 s."""
    if _MAYBE_EXPONENT.search(raw) is not None:
        return True
    a = np.frombuffer(raw, dtype=np.uint8)
    # in blocks overlapping by 12 bytes (a run of 13 lies whole in one), so that the counts of a 32 MB
    # mesh take a few MB, not eight bytes per byte of the file
    for start in range(0, max(len(a) - 12, 1), _BLOCK):
        block = a[start:start + _BLOCK + 12]
        if len(block) < 13:
            break
        run = np.zeros(len(block) + 1, dtype=np.int32)
        np.cumsum((block >= 0x30) & (block <= 0x39), out=run[1:])
        if np.any(run[13:] - run[:-13] == 13):
            return True
    return False


#: Bytes of a text mesh :func:`_maybe_huge` counts digits in at a time.
_BLOCK = 1 << 20


def _largest_number(raw: bytes, ext: str) -> float:
    """The largest magnitude among a mesh file's numbers that could exceed 1e12, found without
    parsing (0 when there is none): every number of a text format (OBJ, OFF, COLLADA, ASCII PLY and
    STL), the coordinates of a binary STL. Other binary formats are checked once parsed
    (:func:`check_mesh_arrays`)."""
    if ext == "stl" and len(raw) >= 84 and 84 + 50 * struct.unpack_from("<I", raw, 80)[0] == len(raw):
        n = (len(raw) - 84) // 50
        rec = np.frombuffer(raw, dtype=np.dtype([("f", "<f4", (12,)), ("a", "<u2")]), count=n, offset=84)
        with np.errstate(all="ignore"):
            xyz = np.abs(rec["f"][:, 3:].astype(float))
        return float(np.nan_to_num(xyz, nan=np.inf).max()) if n else 0.0
    if ext == "ply" and b"binary" in raw[:200]:
        return 0.0
    if ext not in ("obj", "off", "dae", "ply", "stl"):
        return 0.0
    big = 0.0
    if not _maybe_huge(raw):
        return big
    for m in _HUGE.finditer(raw):
        try:
            big = max(big, abs(float(m.group(0))))
        except ValueError:  # "e13" alone, "1.2.3e20": not a number a parser reads
            continue
    return big


# ----------------------------------------------------------------------------- counters
def _stl(raw: bytes) -> tuple[int, int]:
    # binary: 84-byte header + 50 bytes per triangle; ASCII: one "facet" per triangle (≥ 50 bytes)
    t = max((len(raw) - 84) // 50, raw.count(b"facet"), 0)
    return 3 * t, t


def _polygons(counts: Iterable[int]) -> int:
    return int(sum(max(k - 2, 0) for k in counts))


#: The bytes of a face index of a text mesh (``7``, ``7/2``, ``7//3``, ``-1``): any other byte
#: separates indices, so that no separator a parser might honour (``\r``, ``\v``, a non-breaking
#: space) hides a corner.
_INDEX_BYTES = np.zeros(256, dtype=bool)
_INDEX_BYTES[list(b"0123456789+-/")] = True


def _normalized(raw: bytes) -> bytes:
    """The text a text-mesh parser sees (``\r\n`` and ``\n`` end lines, a backslash at the end
    of a line continues it); text with NUL bytes (UTF-16, UTF-32) is refused."""
    if b"\x00" in raw:
        raise InputError("a text mesh with NUL bytes (UTF-16 or UTF-32?): robokit reads UTF-8 or single-byte text")
    return raw.replace(b"\r\n", b"\n").replace(b"\\\n", b"") + b"\n"


def _text_lines(raw: bytes) -> list[bytes]:
    return _normalized(raw).split(b"\n")


_BLANK = np.zeros(256, dtype=bool)
_BLANK[list(b" \t\r\f\v")] = True


def _keyed_lines(a: np.ndarray, key: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Start of the body and end of every line of ``a`` (bytes as uint8) whose first word is the
    one letter ``key`` (``f``, ``v``); also the newline positions."""
    newlines = np.flatnonzero(a == 10)
    starts = np.r_[0, newlines + 1]
    starts = starts[starts < a.size]
    pos = starts.copy()
    blank = _BLANK[a[pos]]
    while blank.any():  # leading blanks (rare): step over them, all lines at once
        pos[blank] += 1
        blank[blank] = pos[blank] < a.size
        blank[blank] = _BLANK[a[pos[blank]]]
    ok = pos + 1 < a.size
    pos = pos[ok]
    hit = (a[pos] == key) & _BLANK[a[pos + 1]]
    body = pos[hit] + 1
    k = np.searchsorted(newlines, body)
    ends = np.where(k < newlines.size, newlines[np.minimum(k, max(newlines.size - 1, 0))] if newlines.size
                    else a.size, a.size)
    return body, ends, newlines


def _indices_per_line(a: np.ndarray, key: int) -> np.ndarray:
    """For every line whose first word is ``key``, the number of indices after it (vectorised: a
    36 MB file of polygon fans is counted in well under a second)."""
    body, ends, _ = _keyed_lines(a, key)
    if body.size == 0:
        return np.zeros(0, dtype=np.int64)
    inside = _INDEX_BYTES[a]
    first = np.flatnonzero(inside[1:] & ~inside[:-1]) + 1  # where an index starts (a[0] is never one)
    return np.searchsorted(first, ends) - np.searchsorted(first, body)


def _obj(raw: bytes) -> tuple[int, int]:
    a = np.frombuffer(_normalized(raw), dtype=np.uint8)
    if a.size < 2:
        return 0, 0
    v = _keyed_lines(a, ord("v"))[0].size
    return v, int(np.maximum(_indices_per_line(a, ord("f")) - 2, 0).sum())


def _off(raw: bytes) -> tuple[int, int]:
    lines = [ln.split(b"#")[0].split() for ln in _text_lines(raw)]
    lines = [ln for ln in lines if ln]
    if not lines:
        return 0, 0
    head, k = lines[0], 1
    if head[0].endswith(b"OFF"):
        head, k = (head[1:], 1) if len(head) > 1 else ((lines[1] if len(lines) > 1 else []), 2)
    try:
        nv, nf = int(head[0]), int(head[1])
    except (IndexError, ValueError):
        return len(raw), len(raw)
    faces = lines[k + nv:]
    return nv, _polygons(max(len(f) - 1, int(f[0]) if f[0].isdigit() else 0) for f in faces)


_PLY_TYPES = {"char": "b", "int8": "b", "uchar": "B", "uint8": "B", "short": "h", "int16": "h", "ushort": "H",
              "uint16": "H", "int": "i", "int32": "i", "uint": "I", "uint32": "I", "float": "f", "float32": "f",
              "double": "d", "float64": "d"}


def _ply(raw: bytes) -> tuple[int, int]:
    end = raw.find(b"end_header")
    if not raw.startswith(b"ply") or end < 0:
        return len(raw), len(raw)
    body = raw[raw.index(b"\n", end) + 1:] if b"\n" in raw[end:] else b""
    elements: list[tuple[str, int, list[list[str]]]] = []
    fmt = "ascii"
    for line in raw[:end].decode("latin-1").splitlines():
        w = line.split()
        if w[:1] == ["format"] and len(w) > 1:
            fmt = w[1]
        elif w[:1] == ["element"] and len(w) > 2:
            elements.append((w[1], int(w[2]) if w[2].isdigit() else len(raw), []))
        elif w[:1] == ["property"] and elements:
            elements[-1][2].append(w[1:])
    nv = next((c for name, c, _ in elements if name == "vertex"), 0)
    tri = 0
    if fmt == "ascii":
        lines = [ln for ln in _text_lines(body) if ln.strip()]
        row = 0
        for name, count, props in elements:
            if name == "face":  # a face line: the corner count, the corners (and maybe more)
                tri += _polygons(max(len(ln.split()) - 1, int(ln.split()[0]) if ln.split()[0].isdigit() else 0)
                                 for ln in lines[row:])
                break
            row += count
        return nv, tri
    order = "<" if fmt == "binary_little_endian" else ">"
    pos = 0
    for name, count, props in elements:
        fixed = all(p[0] != "list" for p in props)
        if fixed:
            size = sum(struct.calcsize(_PLY_TYPES.get(p[0], "d")) for p in props)
            pos += size * count
            continue
        if name != "face":
            return nv, len(raw)  # lists elsewhere: count by bytes
        for _ in range(count):  # walk the face records; stop as soon as the bound is passed
            for p in props:
                if p[0] == "list" and len(p) >= 3:
                    cf, vf = order + _PLY_TYPES.get(p[1], "B"), _PLY_TYPES.get(p[2], "i")
                    if pos + struct.calcsize(cf) > len(body):
                        return nv, tri
                    k = struct.unpack_from(cf, body, pos)[0]
                    pos += struct.calcsize(cf) + k * struct.calcsize(vf)
                    if p[-1] in ("vertex_indices", "vertex_index"):
                        tri += max(k - 2, 0)
                else:
                    pos += struct.calcsize(_PLY_TYPES.get(p[0], "d"))
            if tri > MAX_MESH_TRIANGLES:
                return nv, tri
    return nv, tri


def _dae(raw: bytes) -> tuple[int, int]:
    from robokit._xml import parse_xml

    root = parse_xml(raw, "COLLADA")

    def local(el: Any) -> str:
        return el.tag.rsplit("}", 1)[-1]

    geometry: dict[str, tuple[int, int]] = {}
    for g in root.iter():
        if local(g) != "geometry":
            continue
        tri = verts = 0
        for el in g.iter():
            tag = local(el)
            if tag == "float_array":
                verts += int(el.get("count", "0") or 0) // 3
            if tag not in ("triangles", "polylist", "polygons", "trifans", "tristrips"):
                continue
            offsets = [int(i.get("offset", "0") or 0) for i in el if local(i) == "input"]
            stride = max(offsets) + 1 if offsets else 1
            if tag == "triangles":
                tri += int(el.get("count", "0") or 0)
            elif tag == "polylist":
                vc = next((c for c in el if local(c) == "vcount"), None)
                tri += _polygons(int(x) for x in (vc.text or "").split()) if vc is not None else 0
            else:
                tri += _polygons(len((p.text or "").split()) // stride for p in el if local(p) in ("p", "ph"))
        geometry[g.get("id", "")] = (verts, tri)
    # instances: how many times each node is placed (a node may instance other nodes: a DAG)
    nodes = {n.get("id"): n for n in root.iter() if local(n) == "node" and n.get("id")}
    memo: dict[int, tuple[int, int]] = {}

    def size(node: Any, stack: tuple[int, ...]) -> tuple[int, int]:
        key = id(node)
        if key in stack:
            raise InputError("COLLADA nodes instance each other in a cycle")
        if key in memo:
            return memo[key]
        v = t = 0
        for c in node:
            tag = local(c)
            if tag == "instance_geometry":
                gv, gt = geometry.get((c.get("url") or "").lstrip("#"), (0, 0))
                v, t = v + gv, t + gt
            elif tag == "instance_node":
                target = nodes.get((c.get("url") or "").lstrip("#"))
                if target is not None:
                    nv, nt = size(target, stack + (key,))
                    v, t = v + nv, t + nt
            elif tag == "node":
                nv, nt = size(c, stack + (key,))
                v, t = v + nv, t + nt
            if t > MAX_MESH_TRIANGLES or v > MAX_MESH_VERTICES:
                break
        memo[key] = (v, t)
        return v, t

    scenes = [s for s in root.iter() if local(s) == "visual_scene"]
    if not scenes:
        return sum(g[0] for g in geometry.values()), sum(g[1] for g in geometry.values())
    v = t = 0
    for s in scenes:
        sv, st = size(s, ())
        v, t = v + sv, t + st
    # a parser may also load geometries no node places: count them once
    return max(v, sum(g[0] for g in geometry.values())), max(t, sum(g[1] for g in geometry.values()))


def _gltf_counts(doc: Any, raw_len: int) -> tuple[int, int]:
    if not isinstance(doc, dict):
        return raw_len, raw_len
    accessors = doc.get("accessors") or []

    def count(i: Any) -> int:
        try:
            return int(accessors[int(i)].get("count", 0))
        except (IndexError, TypeError, ValueError, AttributeError):
            return raw_len

    meshes = []
    for mesh in doc.get("meshes") or []:
        v = t = 0
        for prim in (mesh or {}).get("primitives") or []:
            mode = prim.get("mode", 4)
            attrs = prim.get("attributes") or {}
            nv = count(attrs["POSITION"]) if "POSITION" in attrs else 0
            ni = count(prim["indices"]) if "indices" in prim else nv
            v += nv
            t += ni // 3 if mode == 4 else max(ni - 2, 0) if mode in (5, 6) else 0
        meshes.append((v, t))
    uses = [0] * len(meshes)
    for node in doc.get("nodes") or []:
        m = node.get("mesh") if isinstance(node, dict) else None
        if isinstance(m, int) and 0 <= m < len(meshes):
            uses[m] += 1
    v = sum(mv * max(u, 1) for (mv, _), u in zip(meshes, uses))
    t = sum(mt * max(u, 1) for (_, mt), u in zip(meshes, uses))
    return v, t


def _gltf(raw: bytes) -> tuple[int, int]:
    try:
        return _gltf_counts(json.loads(raw), len(raw))
    except (ValueError, RecursionError):
        return len(raw), len(raw)


def _glb(raw: bytes) -> tuple[int, int]:
    if len(raw) < 20 or raw[:4] != b"glTF":
        return len(raw), len(raw)
    n, kind = struct.unpack_from("<I4s", raw, 12)
    if kind != b"JSON" or 20 + n > len(raw):
        return len(raw), len(raw)
    try:
        return _gltf_counts(json.loads(raw[20: 20 + n]), len(raw))
    except (ValueError, RecursionError):
        return len(raw), len(raw)
