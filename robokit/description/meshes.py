r"""One rule for the files a robot description may make robokit read: meshes (URDF, xacro,
MJCF ``<mesh file>``, MJCF ``meshdir``/``assetdir``), MJCF ``<include file>`` and xacro
``<xacro:include>`` / ``xacro.load_yaml``.

A file named by a robot description is read only if, after resolving symbolic links, it lies
inside one of the **allowed roots**:

* the folder of the top-level description file;
* the ROS package holding it (the nearest folder above it with a ``package.xml``);
* every folder given by the user as a package folder (``package_dirs=``, ``--package-path``)
  and every package found in them (``$(find pkg)``, ``package://pkg``).

Anything else — an absolute path such as ``/etc/passwd``, ``../`` out of the package, a
``file://`` URI elsewhere, a symlink inside the folder that points out of it — is refused with
one line naming the file that asked for it, unless the user allows it explicitly
(``allow_outside_meshes=True``, which applies to meshes only: an include is data that is
parsed and is always confined).
"""
from __future__ import annotations

import os
from pathlib import Path
from typing import Iterable, Sequence

from robokit.errors import InputError

__all__ = ["MAX_MESH_BYTES", "MAX_PACKAGE_SEARCH", "MAX_TOTAL_MESH_BYTES", "allowed_roots", "confine", "is_inside",
           "mesh_file_problem", "package_below", "package_name", "without_meshes"]

#: Folders that :func:`package_below` looks at under one ``package_dirs`` folder, at most (a
#: workspace's ``src/`` holds tens to hundreds; a home folder given by mistake is not crawled whole).
MAX_PACKAGE_SEARCH = 10_000
#: Marker files that hide a folder from colcon and catkin, and so from :func:`package_below`.
_IGNORE_MARKERS = ("COLCON_IGNORE", "CATKIN_IGNORE", "AMENT_IGNORE")


def without_meshes(collision: bool, count: int) -> str:
    """What a note on meshes not read says robokit does without them: a visual mesh is only drawn;
    a collision mesh is a shape the collision checks (:class:`robokit.collision.World`) no longer
    see on its link.

    Parameters
    ----------
    collision : bool
        Whether the meshes are collision geometry (else visual).
    count : int
        How many meshes the note is about (1: "it", more: "them").

    Returns
    -------
    str
        The end of the note, after what was not read.

    Examples
    --------
    >>> without_meshes(False, 1), without_meshes(True, 2)
    ('drawn without it', 'collision checks go without them (their links are checked without those shapes)')
    """
    it = "it" if count == 1 else "them"
    if not collision:
        return f"drawn without {it}"
    whose = "its link is" if count == 1 else "their links are"
    return f"collision checks go without {it} ({whose} checked without {'that shape' if count == 1 else 'those shapes'})"


def allowed_roots(top: str | os.PathLike[str], package_dirs: Sequence[str | os.PathLike[str]] | None = (),
                  extra: Iterable[str | os.PathLike[str]] = ()) -> list[Path]:
    """The folders files named by ``top`` may be read from (see the module docstring).

    Parameters
    ----------
    top : str or Path
        The top-level description file the user gave.
    package_dirs : sequence of str or Path
        Package folders the user gave.
    extra : iterable of str or Path
        Folders of packages found for the file (``$(find pkg)``).

    Returns
    -------
    list of Path
        Resolved folders.

    Examples
    --------
    A file outside any ROS package may read meshes from its own folder only:

    >>> import pathlib, tempfile
    >>> with tempfile.TemporaryDirectory() as tmp:
    ...     urdf = pathlib.Path(tmp, "arm.urdf")
    ...     print(allowed_roots(urdf) == [urdf.parent.resolve()])
    True
    """
    folder = Path(top).resolve().parent
    roots = [folder] + [Path(p).expanduser().resolve() for p in (package_dirs or ())]
    roots += [Path(p).resolve() for p in extra]
    for parent in (folder, *folder.parents):
        if (parent / "package.xml").is_file():
            roots.append(parent)
            break
    return roots


def is_inside(path: str | os.PathLike[str], roots: Iterable[str | os.PathLike[str]]) -> bool:
    """Whether ``path`` (symlinks resolved) is one of ``roots`` or inside one.

    Parameters
    ----------
    path : str or os.PathLike
        The file or folder to test.
    roots : iterable of str or os.PathLike
        The allowed folders.

    Returns
    -------
    bool
        True if the resolved path equals a resolved root or lies below one.

    Examples
    --------
    >>> is_inside("/a/b/c.stl", ["/a"]), is_inside("/a/../etc/passwd", ["/a"])
    (True, False)
    """
    p = Path(path).resolve()
    for r in roots:
        r = Path(r).resolve()
        if p == r or r in p.parents:
            return True
    return False


def confine(path: str | os.PathLike[str], roots: Iterable[str | os.PathLike[str]], source: str | os.PathLike[str],
            what: str, *, allow_outside: bool = False, hint: str = "") -> Path:
    """``path`` resolved, or :class:`InputError` if it lies outside ``roots`` (see the module docstring).

    Parameters
    ----------
    path : str or Path
        The file the description names (already made absolute by the caller).
    roots : iterable of str or Path
        :func:`allowed_roots`.
    source : str or Path
        The description file that names it (in the message).
    what : str
        What it is, e.g. ``"<mesh file='../x.stl'>"`` (in the message).
    allow_outside : bool
        Accept it anyway (the user's explicit choice, for meshes).
    hint : str
        Appended to the message (how to allow it, where that differs by format).

    Returns
    -------
    Path
        The resolved path.

    Raises
    ------
    InputError
        ``SOURCE: WHAT is outside the file's folder, its package and the package folders given``.

    Examples
    --------
    >>> confine("/etc/passwd", ["/ws/arm"], "arm.xml", "<include file='/etc/passwd'>")
    Traceback (most recent call last):
    ...
    robokit.errors.InputError: arm.xml: <include file='/etc/passwd'> is outside the file's folder, its package and the package folders given
    """
    p = Path(path).resolve()
    roots = list(roots)
    if allow_outside or is_inside(p, roots):
        return p
    raise InputError(f"{source}: {what} is outside the file's folder, its package and the package folders given{hint}")


#: Largest ``package.xml`` read to learn a package's name.
MAX_PACKAGE_XML_BYTES = 1 << 20


def package_below(folder: str | os.PathLike[str], pkg: str) -> tuple[Path | None, bool]:
    """The package named ``pkg`` at any depth below ``folder``, found as colcon and catkin find a
    workspace's packages: a folder holding a ``package.xml`` is a package and is not searched
    further; hidden folders and folders holding ``COLCON_IGNORE``, ``CATKIN_IGNORE`` or
    ``AMENT_IGNORE`` are skipped; shallower folders first, each level in name order, a folder reached
    twice through symbolic links visited once; at most :data:`MAX_PACKAGE_SEARCH` folders.

    Parameters
    ----------
    folder : str or os.PathLike
        Where to search (a ``package_dirs`` folder: a workspace's ``src/``, which may hold the makers'
        repositories, each holding its packages).
    pkg : str
        The package name (the ``<name>`` of its ``package.xml``).

    Returns
    -------
    (Path or None, bool)
        The package's folder (None when not found), and whether the search stopped at
        :data:`MAX_PACKAGE_SEARCH` folders before it was done.

    Examples
    --------
    >>> import pathlib, tempfile
    >>> with tempfile.TemporaryDirectory() as tmp:
    ...     pkg = pathlib.Path(tmp, "kuka_experimental", "kuka_kr6_support")
    ...     pkg.mkdir(parents=True)
    ...     _ = (pkg / "package.xml").write_text("<package><name>kuka_kr6_support</name></package>")
    ...     found, stopped = package_below(tmp, "kuka_kr6_support")
    ...     print(found == pkg.resolve(), stopped)
    True False
    """
    level = [Path(folder)]
    seen: set[Path] = set()
    visited = 0
    while level:
        deeper: list[Path] = []
        for d in level:
            try:
                real = d.resolve()
                if real in seen or not real.is_dir():
                    continue
            except (OSError, RuntimeError):
                continue
            seen.add(real)
            visited += 1
            if visited > MAX_PACKAGE_SEARCH:
                return None, True
            if any((d / marker).exists() for marker in _IGNORE_MARKERS):
                continue
            manifest = d / "package.xml"
            if manifest.is_file():
                if package_name(manifest) == pkg:
                    return real, False
                continue  # a package: colcon does not look for packages inside one
            try:
                deeper.extend(sorted(c for c in d.iterdir() if not c.name.startswith(".")))
            except OSError:
                continue
        level = deeper
    return None, False


def package_name(package_xml: str | os.PathLike[str]) -> str | None:
    """The ``<name>`` of a ROS ``package.xml`` (bounded, regular files only).

    Parameters
    ----------
    package_xml : str or os.PathLike
        Path of the manifest.

    Returns
    -------
    str or None
        The package name; the folder's name if the manifest has no ``<name>``; None if the file
        cannot be read as a manifest.

    Examples
    --------
    >>> import pathlib, tempfile
    >>> with tempfile.TemporaryDirectory() as tmp:
    ...     manifest = pathlib.Path(tmp, "package.xml")
    ...     _ = manifest.write_text("<package><name>arm_description</name></package>")
    ...     print(package_name(manifest))
    arm_description
    """
    from robokit._io import read_input_bytes
    from robokit._xml import parse_xml

    try:
        root = parse_xml(read_input_bytes(package_xml, MAX_PACKAGE_XML_BYTES, "a package.xml"), package_xml)
    except InputError:
        return None
    return (root.findtext("name") or Path(package_xml).parent.name).strip()


#: Largest mesh file read (bytes). The largest mesh of example-robot-data is 28.8 MB (a
#: quadruped's trunk, COLLADA); a page embedding a larger one would be unwieldy and loading a
#: 2-million-face mesh takes Pinocchio's loader over a gigabyte.
MAX_MESH_BYTES = 32 << 20
#: Most mesh bytes one robot description may make robokit read in total.
MAX_TOTAL_MESH_BYTES = 256 << 20


def mesh_file_problem(path: str | os.PathLike[str], count_triangles: bool = True) -> str | None:
    """Why the mesh file ``path`` is not read, or None if it may be.

    Parameters
    ----------
    path : str or os.PathLike
        The mesh file.
    count_triangles : bool
        Also count its triangles (False for a file that is not a mesh, such as an MJCF
        ``<texture>``, which robokit never reads: only its kind and size are checked).

    Returns
    -------
    str or None
        ``"not found"``, ``"not a regular file"`` (a FIFO, a device such as ``/dev/zero``), the
        size when it is larger than :data:`MAX_MESH_BYTES`, the triangle or vertex count when it
        makes more than :data:`robokit.description.mesh_size.MAX_MESH_TRIANGLES` (counted from
        the bytes, :func:`robokit.description.mesh_size.check_mesh_bytes`), or None when the file
        may be read.

    Examples
    --------
    >>> mesh_file_problem("/dev/zero")
    'not a regular file'
    """
    import stat

    from robokit._io import read_input_bytes
    from robokit.description.mesh_size import check_mesh_bytes

    try:
        st = os.stat(path)
    except OSError:
        return "not found"
    if not stat.S_ISREG(st.st_mode):
        return "not a regular file"
    if st.st_size > MAX_MESH_BYTES:
        return f"{st.st_size / 1e6:.1f} MB; robokit reads mesh files of at most {MAX_MESH_BYTES / 1e6:.1f} MB"
    if not count_triangles:
        return None
    try:  # triangles and vertices counted from the bytes, before Pinocchio's loader parses anything
        check_mesh_bytes(read_input_bytes(path, MAX_MESH_BYTES, "a mesh file"), Path(path).suffix, "")
    except InputError as exc:
        return str(exc).removeprefix(": ")
    return None
