"""Checks an MJCF file and everything it names before Pinocchio or MuJoCo reads it.

:func:`check_mjcf` reads the file with robokit's bounded reader (regular files only), checks
its XML (:func:`robokit._xml.check_xml`: no DTD, bounded depth and size), then follows every
``<include file=…>`` the same way (at most :data:`MAX_INCLUDE_DEPTH` levels and
:data:`MAX_INCLUDES` files), and confines every file the model names — ``<include>``,
``<mesh>``/``<skin>``/``<hfield>`` (relative to ``meshdir``/``assetdir``), ``<texture>``
(relative to ``texturedir``/``assetdir``) and ``<model>`` — with the rule of
:mod:`robokit.description.meshes` (the file's folder, its package, the package folders given),
meshes excepted when ``allow_outside_meshes``; an asset that is not a regular file or is larger
than :data:`robokit.description.meshes.MAX_MESH_BYTES` is refused. Joints are counted across the includes
and limited to :data:`robokit.description.limits.MAX_JOINTS`.
"""
from __future__ import annotations

import os
import xml.etree.ElementTree as ET
from pathlib import Path
from typing import Sequence

from robokit._io import decode_utf8, read_input_bytes
from robokit._xml import parse_xml
from robokit.description.limits import check_joint_count
from robokit.description.meshes import allowed_roots, confine, mesh_file_problem
from robokit.errors import InputError

__all__ = ["MAX_INCLUDES", "MAX_INCLUDE_DEPTH", "MAX_MJCF_BYTES", "check_mjcf", "read_mjcf_root"]

#: How to read a file the model names in a sibling folder of the file's (``../scene/...``).
_HINT = "; pass a folder that holds it in package_dirs= (--package-path)"

#: Largest MJCF file (and include) read.
MAX_MJCF_BYTES = 20 << 20
#: Deepest ``<include>`` nesting and most files followed.
MAX_INCLUDE_DEPTH, MAX_INCLUDES = 20, 200

_ASSET_DIR = {"mesh": "meshdir", "skin": "meshdir", "texture": "texturedir", "hfield": "meshdir"}


def read_mjcf_root(path: str | os.PathLike[str]) -> ET.Element:
    """The root element of one MJCF file, read bounded and checked (see the module docstring).

    Parameters
    ----------
    path : str or Path
        The file.

    Returns
    -------
    xml.etree.ElementTree.Element

    Raises
    ------
    InputError
        Naming the file: missing, not a regular file, too large, not UTF-8, malformed or hostile XML.

    Examples
    --------
    >>> import pathlib, tempfile
    >>> with tempfile.TemporaryDirectory() as tmp:
    ...     path = pathlib.Path(tmp, "empty.xml")
    ...     _ = path.write_text('<mujoco model="empty"><worldbody/></mujoco>')
    ...     print(read_mjcf_root(path).tag)
    mujoco
    """
    raw = read_input_bytes(path, MAX_MJCF_BYTES, "an MJCF file")
    return parse_xml(decode_utf8(raw, path), path)


def check_mjcf(path: str | os.PathLike[str], package_dirs: Sequence[str | os.PathLike[str]] | None = None,
               allow_outside_meshes: bool = False, copy_to: str | os.PathLike[str] | None = None,
               expand_includes: bool = False) -> ET.Element:
    """Check an MJCF file, its includes and the files it names; return its root element.

    Parameters
    ----------
    path : str or Path
        The top-level MJCF file.
    package_dirs : sequence of str or Path, optional
        Further folders files may be read from.
    allow_outside_meshes : bool
        Accept mesh, skin, texture and height-field files outside the allowed roots.
    copy_to : str or Path, optional
        A folder to write the **checked** text to, for a parser that reads files (Pinocchio):
        ``model.xml`` and one ``include_<k>.xml`` per include, with every asset path made
        absolute (it was confined) and every ``<include>`` pointing to its checked copy — so
        that the parser never re-reads the user's files.

    Returns
    -------
    xml.etree.ElementTree.Element
        The top file's root element.

    Raises
    ------
    InputError
        One line naming the file: see the module docstring.

    Examples
    --------
    >>> import pathlib, tempfile
    >>> from robokit.description.mjcf_write import mjcf_from_robot
    >>> with tempfile.TemporaryDirectory() as tmp:
    ...     path = pathlib.Path(tmp, "twolink.xml")
    ...     _ = path.write_text(mjcf_from_robot(rk.load("twolink"))[0])
    ...     print(check_mjcf(path).get("model"))
    twolink
    """
    path = Path(path)
    roots = allowed_roots(path, package_dirs)
    top_dir = path.resolve().parent
    top = read_mjcf_root(path)
    compiler: dict[str, str] = {}
    for c in top.iter("compiler"):
        compiler.update({k: v for k, v in c.attrib.items() if k in ("meshdir", "texturedir", "assetdir")})
    count = {"joints": 0, "files": 1}
    copies: list[tuple[str, ET.Element]] = [("model.xml", top)]
    included: dict[int, ET.Element] = {}
    if copy_to is not None:  # the checked copy lives elsewhere: asset folders become absolute
        for c in top.iter("compiler"):
            for key in ("meshdir", "texturedir", "assetdir"):
                if c.get(key) is not None:
                    c.set(key, str(top_dir / c.get(key, "")))

    def walk(root: ET.Element, source: Path, depth: int) -> None:
        count["joints"] += sum(1 for _ in root.iter("joint")) + sum(1 for _ in root.iter("freejoint"))
        check_joint_count(count["joints"], path, "<joint> elements")
        for el in root.iter():
            f = el.get("file")
            if f is None:
                continue
            what = f"<{el.tag} file={f!r}>"
            if el.tag == "include":
                inc = confine(top_dir / f, roots, source, what, hint=_HINT)
                if depth >= MAX_INCLUDE_DEPTH:
                    raise InputError(f"{source}: {what}: includes nested deeper than {MAX_INCLUDE_DEPTH} levels")
                count["files"] += 1
                if count["files"] > MAX_INCLUDES:
                    raise InputError(f"{path}: more than {MAX_INCLUDES} files included")
                inc_root = read_mjcf_root(inc)
                walk(inc_root, inc, depth + 1)
                included[id(el)] = inc_root
                if copy_to is not None:
                    name = f"include_{len(copies)}.xml"
                    copies.append((name, inc_root))
                    el.set("file", name)
                continue
            sub = compiler.get(_ASSET_DIR.get(el.tag, ""), compiler.get("assetdir", ""))
            base = top_dir / sub if sub else top_dir
            asset = confine(base / f, roots, source, what, allow_outside=allow_outside_meshes and el.tag in _ASSET_DIR,
                            hint=_HINT + (" or allow_outside_meshes=True (--allow-outside-meshes)"
                                          if el.tag in _ASSET_DIR else ""))
            # only a <mesh> is a mesh: a texture, skin or height field is never read by robokit
            problem = mesh_file_problem(asset, el.tag == "mesh") if os.path.lexists(asset) else None
            if problem is not None:
                raise InputError(f"{source}: {what}: {problem}")
            if copy_to is not None:
                el.set("file", str(asset))

    walk(top, path, 0)
    if expand_includes and included:
        _expand(top, included)
    if copy_to is not None:
        for name, root in copies:
            (Path(copy_to) / name).write_text(ET.tostring(root, encoding="unicode"), encoding="utf-8")
    return top


def _expand(elem: ET.Element, included: dict[int, ET.Element]) -> None:
    """Replace each ``<include>`` child (recursively) by the children of the file it names."""
    kids: list[ET.Element] = []
    for child in list(elem):
        if child.tag == "include" and id(child) in included:
            inc = included[id(child)]
            _expand(inc, included)
            kids.extend(list(inc))
        else:
            _expand(child, included)
            kids.append(child)
    elem[:] = kids
