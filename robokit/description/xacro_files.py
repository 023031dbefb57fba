r"""xacro files (``.urdf.xacro``, ``.xacro``) without ROS.

A xacro file is expanded to URDF with the ``xacro`` Python package, then loaded like any
URDF. ROS finds packages through its index (``$(find pkg)`` needs ``ament_index_python``);
robokit finds them itself, in this order:

1. each folder ``D`` of ``package_dirs``: ``D/<pkg>/package.xml``, ``D`` itself when its
   ``package.xml`` is named ``<pkg>``, or a sub-folder of ``D`` whose ``package.xml`` is; then,
   in each ``D``, the package at any depth below it, as colcon finds a workspace's packages
   (``src/<repository>/<package>``: :func:`robokit.description.meshes.package_below`);
2. the xacro file's own folder and every folder above it, by the three rules of step 1 (not at
   any depth) — so a package found beside the file (a ROS workspace's ``src/``) needs no option.

The package of a ``package.xml`` is its ``<name>`` element (the folder name if it has none).
``$(find pkg)`` (also inside ``$(eval ...)``) becomes the package folder, and mesh URIs
``package://pkg/path`` and ``file://path`` become absolute file paths; relative mesh paths are
taken from the top-level file's folder. ``$(arg name)`` values come from ``xacro_args``
(every key must be an argument the file declares with ``<xacro:arg>`` or uses), else from
the ``default`` of its ``<xacro:arg>``.

Errors (a missing file or include, an undefined argument or property, a package not found,
malformed XML) raise :class:`robokit.errors.InputError` with one line naming the file, and
where it can be found the line and element. A mesh file that is not there (a package shipped
without its meshes) is dropped with one note for all of them: kinematics and dynamics do not
need it. URDF elements with no meaning for the rigid-body model (``<gazebo>``,
``<transmission>``, ``<ros2_control>``, …) are ignored and named in a note on stderr, as the URDF
reader names them in a ``.urdf`` file (one note per kind of element, the same words).
"""
from __future__ import annotations

import os
import re
import threading
import xml.etree.ElementTree as ET
from pathlib import Path
from typing import TYPE_CHECKING, Any, Mapping, Sequence

from robokit._optional import require
from robokit.description.spec import RobotSpec, xacro_args_tuple
from robokit.description.urdf_files import _from_urdf_file, absolute_dirs
from robokit._io import read_input_bytes
from robokit._xml import check_xml, parse_xml
from robokit.description.limits import check_joint_count
from robokit.description.meshes import MAX_PACKAGE_SEARCH, allowed_roots, confine, package_below, package_name
from robokit.description.urdf_check import MAX_URDF_BYTES
from robokit.description.xacro_safety import guarded
from robokit._deprecation import warn
from robokit.errors import InputError, MissingExtraError

if TYPE_CHECKING:
    from robokit.description.robot import Robot

__all__ = ["expand_xacro", "find_package", "load_xacro"]

_UNSET: Any = object()
_LOCK = threading.Lock()  # the xacro package keeps its state in module globals


def _package_dirs(package_dirs: Any, package_path: Any, where: str) -> Any:
    """``package_dirs``, or the value of its old name ``package_path`` (with a deprecation warning)."""
    if package_path is _UNSET:
        return package_dirs
    if package_dirs is not None and package_dirs != ():
        raise InputError(f"{where}: give package_dirs only (package_path is its old name)")
    warn("package_path=", category=FutureWarning)  # the name robokit.load uses is package_dirs=
    return package_path


def _package_name(package_xml: Path) -> str:
    return package_name(package_xml) or ""


def _package_in(folder: Path, pkg: str) -> Path | None:
    if not folder.is_dir():
        return None
    cand = folder / pkg / "package.xml"
    if cand.is_file() and _package_name(cand) == pkg:
        return cand.parent
    own = folder / "package.xml"
    if own.is_file() and _package_name(own) == pkg:
        return folder
    try:
        subs = sorted(folder.iterdir())
    except OSError:
        return None
    for sub in subs:
        px = sub / "package.xml"
        if px.is_file() and _package_name(px) == pkg:
            return sub
    return None


def find_package(pkg: str, package_dirs: Sequence[str | os.PathLike[str]] | None = (),
                 start: str | os.PathLike[str] | None = None, *, package_path: Any = _UNSET) -> Path:
    """Folder of the package named ``pkg``.

    Parameters
    ----------
    pkg : str
        Package name (the ``<name>`` of its ``package.xml``).
    package_dirs : sequence of str or Path
        Folders searched first (see the module docstring for the rules). ``package_path`` is
        its old name, deprecated.
    start : str or Path, optional
        A file or folder; its folder and every folder above it are searched next.

    Returns
    -------
    Path
        The package's folder (the one holding its ``package.xml``).

    Raises
    ------
    InputError
        If no folder holds the package; the message lists where it looked.

    Examples
    --------
    >>> import pathlib, tempfile
    >>> with tempfile.TemporaryDirectory() as tmp:
    ...     pkg = pathlib.Path(tmp, "src", "my_arm_description")
    ...     pkg.mkdir(parents=True)
    ...     _ = (pkg / "package.xml").write_text("<package><name>my_arm_description</name></package>")
    ...     print(find_package("my_arm_description", [pathlib.Path(tmp, "src")]) == pkg.resolve())
    True
    """
    package_path = _package_dirs(package_dirs, package_path, "find_package")
    folders = [Path(p).expanduser() for p in (package_path or ())]
    for d in folders:
        found = _package_in(d, pkg)
        if found is not None:
            return found.resolve()
    stopped: list[str] = []
    for d in folders:  # then at any depth, as colcon finds a workspace's packages (src/<repository>/<package>)
        found, stopped_here = package_below(d, pkg)
        if found is not None:
            return found
        if stopped_here:
            stopped.append(str(d))
    if start is not None:
        s = Path(start).resolve()
        for d in ([s] if s.is_dir() else []) + list(s.parents):
            found = _package_in(d, pkg)
            if found is not None:
                return found.resolve()
    where = [str(d) for d in folders] + ([f"{Path(start).resolve().parent} and the folders above it"]
                                         if start is not None else [])
    bound = (f"; the search below {', '.join(stopped)} stopped after {MAX_PACKAGE_SEARCH} folders: give the "
             "folder that holds the package" if stopped else "")
    raise InputError(f"package {pkg!r} not found (no package.xml named {pkg!r} in {'; '.join(where) or 'no folder'}"
                     f"{bound}); add its parent folder with --package-path / package_dirs=")


class _ArgRecorder(dict):
    """The xacro argument mapping; records the names the file declares or uses."""

    def __init__(self, values: Mapping[str, str]) -> None:
        super().__init__(values)
        self.seen: set = set()

    def __contains__(self, key: object) -> bool:
        self.seen.add(key)
        return dict.__contains__(self, key)

    def __getitem__(self, key: Any) -> Any:
        self.seen.add(key)
        return dict.__getitem__(self, key)


def _locate(file: Path, token: str | re.Pattern[str]) -> str:
    """``line N, <tag>`` of the first place in ``file`` holding ``token`` (a string or a compiled
    regular expression), or ""."""
    try:
        text = file.read_text(encoding="utf-8")
    except (OSError, UnicodeDecodeError):
        return ""
    if isinstance(token, re.Pattern):
        m = token.search(text)
        pos = m.start() if m else -1
    else:
        pos = text.find(token) if token else -1
    if pos < 0:
        return ""
    line = text.count("\n", 0, pos) + 1
    start = text.rfind("<", 0, pos + 1)
    m = re.match(r"<\s*([\w:.-]+)", text[start:]) if start >= 0 else None
    return f"line {line}, <{m.group(1)}>" if m else f"line {line}"


def _xacro_error(exc: BaseException, files: Sequence[str | None], path: Path, missing_pkg: Sequence[tuple[str, str]],
                 macros: Sequence[str] = ()) -> InputError:
    """One-line InputError for an exception raised while expanding ``path``."""
    import xml.parsers.expat

    current = Path(files[-1]) if files and files[-1] else path
    if missing_pkg:
        pkg, err = missing_pkg[0]
        where = _locate(current, f"$(find {pkg})")
        return InputError(f"{current}: {where + ': ' if where else ''}$(find {pkg}): {err}")
    if isinstance(exc, xml.parsers.expat.ExpatError):
        msg = xml.parsers.expat.ErrorString(exc.code)
        return InputError(f"{current}:{exc.lineno}:{exc.offset + 1}: not well-formed XML ({msg})")
    text = " ".join(str(exc).split())
    sub = getattr(exc, "exc", None)
    token: str | re.Pattern[str] = ""
    if sub is not None and type(sub).__name__ == "ArgException":
        token = f"$(arg {sub.args[0]})"
        text = f"$(arg {sub.args[0]}): undefined argument (declare it with <xacro:arg name=\"{sub.args[0]}\" "\
               "default=\"...\"/> or pass xacro_args / --xacro-arg)"
    elif isinstance(sub, OSError) and getattr(sub, "filename", None):
        missing = Path(sub.filename)
        token = missing.name
        text = f"<xacro:include> file not found: {missing}"
    else:
        m = re.search(r'[Ii]nvalid parameter "([\w.:-]+)"', text)
        if macros and re.search(r"[Uu]ndefined parameters|[Ii]nvalid parameter", text):
            token = re.compile(rf"<(xacro:)?{re.escape(macros[-1])}[\s/>]")  # the macro call
        elif m:
            token = f'{m.group(1)}="'
        else:
            m = (re.search(r"name '([^']+)' is not defined", text) or re.search(r"macro name: ([\w.:-]+)", text)
                 or re.search(r"[Uu]ndefined parameters? \[?'?([\w.:-]+)", text)
                 or re.search(r"['\"]([^'\"]{2,})['\"]", text))
            token = m.group(1) if m else ""
            # the expression itself, where the file has it as written: a name (an undefined property)
            # may appear earlier in the file, as the name of an argument (Interbotix's
            # <xacro:arg name="robot_model"/> above <xacro:arg name="robot_name" default="${robot_model}"/>)
            expr = re.search(r"when evaluating expression '(.+)'", text)
            if expr and _locate(current, "${" + expr.group(1) + "}"):
                token = "${" + expr.group(1) + "}"
    where = _locate(current, token) if token else ""
    if not where and token:  # the offending text may sit in the file that included this one
        for f in reversed(files[:-1]):
            if f and _locate(Path(f), token):
                current, where = Path(f), _locate(Path(f), token)
                break
    return InputError(f"{current}: {where + ': ' if where else ''}{text}")


def _resolve_mesh_uri(uri: str, top: Path, package_path: Sequence[str | os.PathLike[str]] | None) -> Path:
    if uri.startswith("package://"):
        rest = uri[len("package://"):]
        pkg, _, rel = rest.partition("/")
        return find_package(pkg, package_path, top) / rel
    if uri.startswith("file://"):
        return Path(uri[len("file://"):])
    p = Path(uri)
    return p if p.is_absolute() else (top.parent / p)


def expand_xacro(path: str | os.PathLike[str], xacro_args: Mapping[str, str] | None = None,
                 package_dirs: Sequence[str | os.PathLike[str]] | None = None, *, package_path: Any = _UNSET,
                 package_dirs_out: list[Path] | None = None, allow_outside_meshes: bool = False) -> str:
    """The URDF text of a xacro file, with packages and mesh paths resolved.

    Parameters
    ----------
    path : str or Path
        A ``.xacro`` / ``.urdf.xacro`` file (a plain ``.urdf`` also works: its ``package://``
        mesh URIs are resolved).
    xacro_args : dict, optional
        Argument values, ``{"name": "value"}`` (values are converted with ``str``).
    package_dirs : sequence of str or Path, optional
        Folders searched for packages (see the module docstring). ``package_path`` is its old
        name, deprecated.
    package_dirs_out : list, optional
        Filled with the folders of the packages ``$(find …)`` found (meshes may be read there).
    allow_outside_meshes : bool
        Accept meshes outside the allowed roots of :mod:`robokit.description.meshes`.

    Returns
    -------
    str
        URDF text; mesh ``filename`` attributes of files that exist are absolute paths (the
        others keep their reference, for the URDF reader to drop with a note).

    Raises
    ------
    InputError
        One line naming the file (and line/element where known): file or include not
        found, undefined argument, unknown ``xacro_args`` key, package not found,
        malformed XML, a mesh outside the allowed folders; an expression, include,
        environment variable or amount of work :mod:`robokit.description.xacro_safety` refuses.

    Notes
    -----
    Expressions are evaluated by robokit's interpreter (:mod:`robokit.description.xacro_expr`),
    never by Python's ``eval``; files are read bounded and confined; YAML files are read as
    PyYAML reads them; see :mod:`robokit.description.xacro_safety`.

    Examples
    --------
    >>> import pathlib, tempfile
    >>> XACRO = ('<robot xmlns:xacro="http://www.ros.org/wiki/xacro" name="arm">'
    ...          '<xacro:arg name="l1" default="0.4"/>'
    ...          '<link name="base_link"/><link name="link1"/><link name="tool"/>'
    ...          '<joint name="j1" type="continuous"><parent link="base_link"/><child link="link1"/>'
    ...          '<axis xyz="0 0 1"/></joint>'
    ...          '<joint name="j2" type="continuous"><parent link="link1"/><child link="tool"/>'
    ...          '<origin xyz="$(arg l1) 0 0"/><axis xyz="0 0 1"/></joint></robot>')
    >>> with tempfile.TemporaryDirectory() as tmp:
    ...     path = pathlib.Path(tmp, "arm.urdf.xacro")
    ...     _ = path.write_text(XACRO)
    ...     urdf = expand_xacro(path, {"l1": "0.5"})
    ...     robot = load_xacro(path, xacro_args={"l1": "0.5"})   # the same file as a Robot
    >>> 'xyz="0.5 0 0"' in urdf
    True
    >>> robot.n, robot.frame_pose([0.0, 0.0])[:3, 3].tolist()
    (2, [0.5, 0.0, 0.0])
    """
    try:
        xacro = require("xacro", "reading a .xacro file")
        sargs = require("xacro.substitution_args", "reading a .xacro file")
    except MissingExtraError as exc:  # the same one line, naming the file
        raise MissingExtraError(f"{path}: {exc}", extra=exc.extra) from None

    package_path = _package_dirs(package_dirs, package_path, "expand_xacro")
    path = Path(path)
    if not path.exists():  # a FIFO or device is refused by the bounded reader
        raise InputError(f"{path}: file not found")
    args = {}
    for k, v in (xacro_args or {}).items():
        if not isinstance(k, str) or not k.isidentifier():
            raise InputError(f"xacro_args: argument names must be identifiers, got {k!r}")
        args[k] = str(v)
    package_path = [Path(p) for p in (package_path or [])]
    for d in package_path:
        assert isinstance(d, Path)
        if not d.expanduser().is_dir():
            raise InputError(f"package_dirs: {str(d)!r} is not a folder")
    check_xml(read_input_bytes(path, MAX_URDF_BYTES, "a xacro file"), path)  # named as the user gave it
    top = path.resolve()
    missing_pkg: list = []
    found: list[Path] = []

    def find(pkg: str) -> str:
        try:
            folder = find_package(pkg, package_path, top)
        except InputError as exc:
            missing_pkg.append((pkg, str(exc)))
            raise
        found.append(folder)
        return str(folder)

    recorder = _ArgRecorder(args)
    env_seen: set = set()
    with _LOCK:
        saved = sargs._eval_find, sargs._eval_dict.get("find")
        sargs._eval_find = find
        sargs._eval_dict["find"] = find
        try:
            with guarded(top, lambda: allowed_roots(top, package_path, found), args, env_seen, MAX_URDF_BYTES):
                doc = xacro.process_file(str(top), mappings=recorder)
                text = doc.toxml()
        except Exception as exc:  # xacro raises XacroException, ExpatError, NameError, ...
            refused = None if missing_pkg else _robokit_error(exc)
            if refused is not None:
                raise refused from None
            files = [str(f) if f else None for f in (getattr(xacro, "filestack", None) or [])]
            macros = [m.body.getAttribute("name") for m in (getattr(xacro, "macrostack", None) or [])
                      if getattr(m, "body", None) is not None]
            raise _xacro_error(exc, files, top, missing_pkg, macros) from None
        finally:
            sargs._eval_find = saved[0]
            if saved[1] is not None:
                sargs._eval_dict["find"] = saved[1]
    recorder.seen |= env_seen
    unknown = sorted(set(args) - recorder.seen)
    if unknown:
        declared = sorted(recorder.seen)
        raise InputError(f"{path}: unknown xacro argument(s) {', '.join(unknown)}; the file declares "
                         f"{', '.join(declared) if declared else 'no arguments'}")
    if package_dirs_out is not None:
        package_dirs_out.extend(found)
    return _resolve_meshes(text, top, package_path, allowed_roots(top, package_path, found), allow_outside_meshes)


def _robokit_error(exc: BaseException) -> InputError | None:
    """The InputError robokit's own hooks raised inside xacro (possibly wrapped by xacro), or None."""
    seen = 0
    e: BaseException | None = exc
    while e is not None and seen < 10:
        if isinstance(e, InputError):
            return InputError(str(e))
        e = getattr(e, "exc", None)
        seen += 1
    return None


def _resolve_meshes(text: str, top: Path, package_path: Sequence[str | os.PathLike[str]] | None,
                    roots: Sequence[Path], allow_outside: bool) -> str:
    root = parse_xml(text, f"{top} (expanded)", namespaces=False)  # a URDF: names as urdfdom reads them
    check_joint_count(len(root.findall("joint")), top, "<joint> elements in the expansion")
    if root.tag != "robot":
        raise InputError(f"{top}: root element <{root.tag}> is not <robot>; a xacro robot description "
                         "expands to a URDF <robot>")
    for mesh in root.iter("mesh"):
        uri = mesh.get("filename", "")
        try:
            p = _resolve_mesh_uri(uri, top, package_path)
        except InputError:
            continue  # its package is not there: the URDF reader drops the mesh with a note
        p = confine(p, roots, top, f"<mesh filename={uri!r}>", allow_outside=allow_outside)
        if p.is_file():  # a missing mesh keeps its reference: the URDF reader drops it with a note
            mesh.set("filename", str(p.resolve()))
    return ET.tostring(root, encoding="unicode")


def load_xacro(path: str | os.PathLike[str], tip: str | None = None, *, xacro_args: Mapping[str, str] | None = None,
               package_dirs: Sequence[str | os.PathLike[str]] | None = None, package_path: Any = _UNSET,
               allow_outside_meshes: bool = False, reflected_inertia: bool = True) -> Robot:
    """Load a xacro (or URDF) file as a :class:`robokit.Robot`.

    Parameters
    ----------
    path : str or Path
        ``.xacro`` / ``.urdf.xacro`` (or ``.urdf`` whose ``package://`` meshes need
        ``package_dirs``).
    tip : str, optional
        Tip frame of the chain (default: the last link of the chain).
    xacro_args, package_dirs
        See :func:`expand_xacro` (``package_path`` is the old name of ``package_dirs``,
        deprecated).
    allow_outside_meshes : bool
        Read meshes outside the file's folder, its package, the package folders given and the
        packages ``$(find …)`` found (refused by default; the rule of
        :mod:`robokit.description.meshes`, the same for every format).
    reflected_inertia : bool
        Add Drake's reflected rotor inertia of the expansion's transmissions to the joints'
        armature, as for a URDF file (:func:`robokit.description.urdf_files.load_urdf`; default True).

    Returns
    -------
    Robot
        ``robot.spec == RobotSpec("xacro", path=<absolute path>, tip=tip, package_dirs=...,
        xacro_args=...)``.

    Raises
    ------
    InputError
        See :func:`expand_xacro`; also a URDF Pinocchio cannot build.

    Examples
    --------
    :func:`expand_xacro`'s example loads its two-joint arm with ``load_xacro`` too.
    """
    package_path = _package_dirs(package_dirs, package_path, "load_xacro")
    path = Path(path)
    name = path.name.lower()
    if not (name.endswith(".xacro") or name.endswith(".urdf")):
        raise InputError(f"xacro_args/package_dirs: apply to .xacro and .urdf files, got {str(path)!r}")
    found: list[Path] = []
    text = expand_xacro(path, xacro_args, package_path, package_dirs_out=found,
                        allow_outside_meshes=allow_outside_meshes)
    spec = RobotSpec("xacro", path=os.path.abspath(path), tip=tip, package_dirs=absolute_dirs(package_path),
                     xacro_args=xacro_args_tuple(xacro_args), allow_outside_meshes=allow_outside_meshes,
                     reflected_inertia=bool(reflected_inertia))
    # One mesh rule for every format: the meshes must lie in the file's folder, its package, the
    # package folders given or the packages $(find) found, unless allow_outside_meshes.
    dirs = [*(package_path or []), *found]
    return _from_urdf_file(path, tip, package_dirs=dirs, allow_outside_meshes=allow_outside_meshes, text=text,
                           spec=spec, reflected_inertia=reflected_inertia)

