r"""``Robot.save(path)``: a robot written back as a description file robokit (and other tools) can read.

* ``.urdf`` — the robot's URDF: a calibrated robot's own (the URDF its spec carries: joint
  placements and axes as calibrated, the nominal inertias, the reflected rotor inertias as Drake
  ``<transmission>``\ s, which load back as the same armature), a URDF file's text, or for a DH robot
  the URDF of its table (:func:`robokit.description.urdf_gen.urdf_from_dh`). A URDF robot loaded with
  ``reflected_inertia=False`` from a file whose transmissions give Drake's rotor inertia is written
  as its file all the same, with a warning: that file loads back with the inertia unless loaded with
  ``reflected_inertia=False`` again. The tools and limits :meth:`~robokit.Robot.with_tool` and
  :meth:`~robokit.Robot.with_limits` gave a URDF or calibrated robot are written into its URDF (each tool
  a massless link fixed to the tip before it, the last one the file's default tip; each chain joint's
  ``<limit>``; an unlimited revolute joint ``continuous``), so the file loads back as the robot saved; a
  limit a URDF joint cannot hold (one side infinite) raises :class:`robokit.errors.InputError`;
* ``.yaml`` / ``.yml`` — a DH table, only when one reproduces the robot exactly: the robot's own
  table, or the one :func:`robokit.dh_from_urdf` extracts when its forward kinematics equals the
  robot's to 1e-9 (checked after writing it to text and reading it back) with offsets of the arm's
  size (at most ten times the farthest joint origin or tool from the base, and 1 m — nearly
  parallel axes need offsets far beyond the arm, the DH discontinuity).

Anything else raises :class:`robokit.errors.InputError` saying what robokit can write for that robot.
The file is written atomically (:func:`robokit._io.atomic_write`): never half-written.
"""
from __future__ import annotations

import os
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from robokit._io import atomic_write
from robokit.description import robot as _robot_module
from robokit.errors import InputError

if TYPE_CHECKING:
    from robokit.description.robot import Robot

__all__ = ["robot_text", "save_robot", "dh_yaml_text"]


def dh_yaml_text(robot: Robot, arg: str = "path") -> str:
    """The DH YAML of ``robot`` when a DH table reproduces it exactly (module docstring).

    Parameters
    ----------
    robot : Robot
    arg : str
        The argument named in an error message (``-o`` for the command line).

    Returns
    -------
    str
        YAML text (angles in degrees), with a comment line saying how well it reproduces the robot.

    Raises
    ------
    InputError
        When no DH table reproduces the robot to 1e-9 with offsets of the arm's size.

    Examples
    --------
    >>> dh_yaml_text(rk.load("rrr")).count("joint:")
    3
    """
    import yaml

    from robokit.description.dh import DHTable
    from robokit.description.urdf_to_dh import dh_from_urdf

    if robot.dh is not None:
        return robot.dh.to_yaml_str("deg")
    res = dh_from_urdf(robot, "standard")
    frames = robot.frame_poses(np.zeros(robot.n))
    size = 10.0 * max([1.0] + [float(np.linalg.norm(T[:3, 3])) for T in frames.values()])
    big = max((abs(v), f"{k}{i + 1}") for i, l in enumerate(res.table.links) for k, v in (("a", l.a), ("d", l.d)))
    if big[0] > size:
        raise InputError(f"{arg}: {robot.name} has nearly parallel joint axes that a DH table describes only with "
                         f"{big[1]} = {big[0]:.3g} m (the DH discontinuity); write a URDF instead (.urdf)")
    text = res.table.to_yaml_str("deg")
    back = DHTable.from_dict(yaml.safe_load(text), source="<saved>")
    rng = np.random.default_rng(0)
    worst = 0.0
    for _ in range(100):
        qs = robot.random_configuration(rng)
        worst = max(worst, float(np.abs(back.fk(qs) - robot.frame_pose(qs)).max()))
    if not (res.exact and worst <= 1e-9):
        raise InputError(f"{arg}: {robot.name} is not exactly a DH arm (a DH table reproduces it only to "
                         f"{max(worst, res.residual):.2e}); write a URDF instead (.urdf)")
    return f"# {robot.name}: this DH table reproduces the robot to {worst:.1e}\n" + text


def robot_text(robot: Robot, suffix: str, arg: str = "path", dest: str | os.PathLike[str] | None = None) -> str:
    """The text :func:`save_robot` writes for a file ending in ``suffix`` (``.urdf``, ``.yaml``, ``.yml``).

    Parameters
    ----------
    robot : Robot
    suffix : str
        The file suffix, with its dot.
    arg : str
        The argument named in an error message.
    dest : str or path-like, optional
        Where the text will be written: a URDF file's relative mesh paths are rewritten relative
        to it (:func:`_relocated_meshes`). None keeps them as the file gives them.

    Returns
    -------
    str
        The file's text: :func:`dh_yaml_text` for ``.yaml``/``.yml``; for ``.urdf``, a calibrated
        robot's URDF, the URDF generated from a DH table, or a URDF file's own text.

    Raises
    ------
    InputError
        Another suffix, or a robot robokit cannot write in that format (module docstring).

    Examples
    --------
    >>> robot_text(rk.load("twolink"), ".urdf").count('<joint name="joint_')
    2
    """
    suffix = suffix.lower()
    if suffix in (".yaml", ".yml"):
        return dh_yaml_text(robot, arg)
    if suffix != ".urdf":
        raise InputError(f"{arg}: robokit writes a robot as .urdf or .yaml (DH), got {suffix or 'no suffix'!r}")
    spec = robot.spec
    if spec is not None and spec.kind == "calibrated" and spec.text is not None:
        return _with_tools_and_limits(spec.text, robot, arg)
    if robot.dh is not None:
        from robokit.description.urdf_gen import urdf_from_dh

        return urdf_from_dh(robot.dh)
    if spec is not None and spec.kind == "urdf" and spec.path is not None:
        from robokit._io import read_input_text
        from robokit.description.urdf_check import MAX_URDF_BYTES

        text = read_input_text(Path(spec.path), MAX_URDF_BYTES, "a URDF file")
        if not spec.reflected_inertia and _has_drake_rotor(text, spec.path):
            import warnings

            from robokit._stack import outside_level
            from robokit.errors import RobokitWarning

            warnings.warn(f"{arg}: {robot.name} was loaded with reflected_inertia=False, but its URDF file, written as "
                          "it is, gives joints Drake's rotor inertia (drake:rotor_inertia in a <transmission>): load "
                          "the saved file with reflected_inertia=False (--no-reflected-inertia) for this robot's M",
                          RobokitWarning, stacklevel=outside_level())
        if dest is not None:
            text = _relocated_meshes(text, robot, Path(spec.path), Path(dest), arg)
        return _with_tools_and_limits(text, robot, arg)
    raise InputError(f"{arg}: robokit has no URDF text for {robot.name} (loaded from {robot.source or 'a model'}); "
                     "it writes URDF for calibrated robots, DH robots and URDF files")


def _relocated_meshes(text: str, robot: Robot, source: Path, dest: Path, arg: str) -> str:
    """A URDF file's text (read from ``source``) to be written at ``dest``: each relative mesh path
    (or ``file://`` one) that the source finds is rewritten relative to ``dest``'s folder, so the saved
    file draws and collides with the same meshes. Unchanged when both are in one folder or nothing is
    relative. A warning, once, names what loading the saved file then needs: the meshes outside its
    folder (``allow_outside_meshes=True``), a ``package://`` mesh found from the source's folder but
    not from ``dest``'s (the ``package_dirs`` to give).

    Examples
    --------
    >>> import tempfile, os
    >>> with tempfile.TemporaryDirectory() as tmp:
    ...     os.makedirs(os.path.join(tmp, "a", "meshes")); os.makedirs(os.path.join(tmp, "b"))
    ...     open(os.path.join(tmp, "a", "meshes", "m.stl"), "w").close()
    ...     urdf = '<robot name="r"><link name="l"><visual><geometry><mesh filename="meshes/m.stl"/></geometry></visual></link></robot>'
    ...     out = _relocated_meshes(urdf, None, Path(tmp, "a", "r.urdf"), Path(tmp, "a", "meshes", "r.urdf"), "path")
    >>> 'filename="m.stl"' in out
    True
    """
    import warnings
    import xml.etree.ElementTree as ET

    from robokit._stack import outside_level
    from robokit._xml import parse_xml
    from robokit.description.meshes import allowed_roots, is_inside
    from robokit.description.urdf_check import _package_roots, _resolve_mesh
    from robokit.errors import RobokitWarning

    src_dir, dest_dir = source.parent.resolve(), dest.parent.resolve()
    if src_dir == dest_dir:
        return text
    root = parse_xml(text, str(source), namespaces=False)
    spec = getattr(robot, "spec", None)
    package_dirs = list(spec.package_dirs) if spec is not None else []
    src_roots, dest_roots = _package_roots(source, package_dirs), _package_roots(dest, package_dirs)
    allowed = allowed_roots(dest, package_dirs)
    changed = 0
    outside: set[Path] = set()
    packages: dict[str, str] = {}
    for mesh in root.iter("mesh"):
        uri = mesh.get("filename") or ""
        if uri.startswith("package://"):
            found, _ = _resolve_mesh(uri, source, src_roots, [])
            if found is not None and _resolve_mesh(uri, dest, dest_roots, [])[0] is None:
                pkg = uri[len("package://"):].partition("/")[0]
                rel = uri[len("package://") + len(pkg) + 1:]
                top = Path(str(found)[:-len(rel)].rstrip("/\\")) if rel and str(found).endswith(rel) else found.parent
                packages.setdefault(pkg, str(top.parent if top.name == pkg else top))
            continue
        if "://" in uri[:12] and not uri.startswith("file://"):
            continue
        found, _ = _resolve_mesh(uri, source, [], [])
        if found is None or not found.exists():
            continue
        try:
            new = os.path.relpath(found, dest_dir)
        except ValueError:  # another drive (Windows): no relative path
            new = str(found)
        new = new.replace(os.sep, "/")
        if new != uri:
            mesh.set("filename", new)
            changed += 1
        if not is_inside(found, allowed):
            outside.add(found)
    said = []
    if outside:
        said.append(f"{len(outside)} mesh file(s) outside its folder (load it with allow_outside_meshes=True, "
                    "or save it in a folder that holds them)")
    if packages:
        said.append("package(s) found from the source's folder only: load it with package_dirs=["
                    + ", ".join(repr(v) for v in sorted(set(packages.values()))) + "] (--package-path) for "
                    + ", ".join(sorted(packages)))
    if said:
        warnings.warn(f"{arg}: the saved URDF of {getattr(robot, 'name', 'the robot')} has " + "; and ".join(said),
                      RobokitWarning, stacklevel=outside_level())
    if not changed:
        return text
    return '<?xml version="1.0"?>\n' + ET.tostring(root, encoding="unicode") + "\n"


def _urdf_link_of(robot: Robot, frame_id: int) -> str:
    """The URDF link whose frame is the Pinocchio frame ``frame_id``: the link itself, or the child
    link of a joint (a URDF joint's frame is its child link's)."""
    pin = robot._pin
    frame = robot.model.frames[frame_id]
    if frame.type == pin.FrameType.BODY:
        return str(frame.name)
    for f in robot.model.frames:  # a joint's frame: the body frame after it, at the same place
        if f.type == pin.FrameType.BODY and f.parentFrame == frame_id and f.placement.isApprox(frame.placement):
            return str(f.name)
    raise InputError(f"path: the tip {frame.name!r} of {robot.name} is no link of its URDF; a tool added to it "
                     "cannot be written there")


def _with_tools_and_limits(text: str, robot: Robot, arg: str) -> str:
    """A URDF robot's text with what :meth:`~robokit.Robot.with_tool` and
    :meth:`~robokit.Robot.with_limits` gave it (``robot.spec.tools`` and ``.limits``), which the file
    itself does not hold: each tool a massless link fixed to the tip before it, each chain joint's
    ``<limit lower upper>`` set (its effort and velocity kept; a revolute joint limited to (−inf, inf)
    becomes ``continuous``, URDF's unlimited revolute joint). Unchanged when there are none.

    Examples
    --------
    >>> from robokit.description.models import model_path
    >>> T = np.eye(4); T[2, 3] = 0.1
    >>> robot = rk.load(str(model_path("rrr", ".urdf"))).with_tool(T)
    >>> text = _with_tools_and_limits(robot_text(rk.load(str(model_path("rrr", ".urdf"))), ".urdf"), robot, "path")
    >>> '<link name="tcp" />' in text, rk.load(str(model_path("rrr", ".urdf"))).tip
    (True, 'tool')
    """
    import xml.etree.ElementTree as ET

    from robokit._xml import parse_xml
    from robokit.description.dh import rpy_from_matrix

    spec = robot.spec
    if spec is None or (not spec.tools and not spec.limits):
        _check_tip(text, robot, arg)
        return text
    root = parse_xml(text, robot.source or "the robot's URDF", namespaces=False)
    joints = {j.get("name"): j for j in root.findall("joint")}
    links = {link.get("name") for link in root.findall("link")}
    if spec.tools:
        parent = _urdf_link_of(robot, int(robot.model.frames[robot.model.getFrameId(spec.tools[0][0])].parentFrame))
        for name, values in spec.tools:
            T = np.array(values, dtype=float).reshape(4, 4)
            joint = f"{parent}_to_{name}"
            while joint in joints or joint in links:
                joint += "_"
            if name in links:
                raise InputError(f"{arg}: the tool {name!r} has the name of a link of the URDF; give it another")
            el = ET.SubElement(root, "joint", {"name": joint, "type": "fixed"})
            ET.SubElement(el, "origin", {"xyz": " ".join(repr(float(v)) for v in T[:3, 3]),
                                         "rpy": " ".join(repr(float(v)) for v in rpy_from_matrix(T[:3, :3]))})
            ET.SubElement(el, "parent", {"link": parent})
            ET.SubElement(el, "child", {"link": name})
            ET.SubElement(root, "link", {"name": name})
            joints[joint] = el
            links.add(name)
            parent = name
    for name, (lo, hi) in zip(robot.joint_names, spec.limits):
        found = joints.get(name)
        if found is None:
            raise InputError(f"{arg}: joint {name!r} of {robot.name} is not in its URDF; its limits cannot be written")
        el = found
        kind = el.get("type")
        if kind == "continuous" or (kind == "revolute" and lo == -np.inf and hi == np.inf):
            if np.isfinite(lo) or np.isfinite(hi):  # (with_limits refuses it; a hand-made spec might not)
                raise InputError(f"{arg}: joint {name!r} is continuous; its limits can only be (-inf, inf)")
            el.set("type", "continuous")
            for limit in el.findall("limit"):
                for key in ("lower", "upper"):
                    limit.attrib.pop(key, None)
            continue
        if not (np.isfinite(lo) and np.isfinite(hi)):
            raise InputError(f"{arg}: joint {name!r} ({kind}) has the limits ({lo:g}, {hi:g}), which a URDF "
                             f"{kind} joint cannot hold; give finite limits (with_limits)")
        existing = el.find("limit")
        limit = ET.SubElement(el, "limit", {"effort": "0", "velocity": "0"}) if existing is None else existing
        limit.set("lower", repr(float(lo)))
        limit.set("upper", repr(float(hi)))
    out = '<?xml version="1.0"?>\n' + ET.tostring(root, encoding="unicode") + "\n"
    _check_tip(out, robot, arg)
    return out


def _check_tip(text: str, robot: Robot, arg: str) -> None:
    """Warn when loading ``text`` would give another tip than ``robot``'s (one chosen with ``tip=`` off
    the file's longest chain, which a URDF cannot record): the warning names the ``tip=`` to load it with."""
    import warnings

    from robokit._stack import outside_level
    from robokit._xml import parse_xml
    from robokit.description.builder import choose_tip
    from robokit.errors import RobokitWarning

    root = parse_xml(text, robot.source or "the robot's URDF", namespaces=False)
    names = {str(el.get("name")) for tag in ("link", "joint") for el in root.findall(tag) if el.get("name") is not None}
    try:
        default = choose_tip(robot._pin.buildModelFromXML(text), names)[0]
    except InputError:
        default = None
    if default != robot.tip:
        warnings.warn(f"{arg}: the saved URDF's default tip is {default or 'none (a tree)'}, not {robot.tip!r}: load "
                      f"it with tip={robot.tip!r} (--tip {robot.tip}) for this robot", RobokitWarning,
                      stacklevel=outside_level())


def _has_drake_rotor(text: str, source: str) -> bool:
    """Whether a URDF's transmissions hold Drake's rotor inertia or gear ratio (names as written)."""
    from robokit._xml import parse_xml

    root = parse_xml(text, source, namespaces=False)
    return any(el.tag in ("drake:rotor_inertia", "drake:gear_ratio")
               for tr in root.findall("transmission") for el in tr.iter())


def save_robot(robot: Robot, path: str | os.PathLike[str]) -> Path:
    """Write ``robot`` to ``path`` (``.urdf``, or ``.yaml``/``.yml`` when a DH table reproduces it), atomically.

    Parameters
    ----------
    robot : Robot
    path : str or path-like
        The file to write; its folder must exist.

    Returns
    -------
    Path
        The file written.

    Raises
    ------
    InputError
        See :func:`robot_text`; a folder that does not exist.

    Examples
    --------
    >>> import tempfile, os
    >>> with tempfile.TemporaryDirectory() as tmp:
    ...     p = save_robot(rk.load("rrr"), os.path.join(tmp, "rrr.urdf"))
    ...     rk.load(p).n
    3
    """
    out = Path(path)
    if out.is_dir():
        raise InputError(f"path: {str(out)!r} is a folder")
    return atomic_write(out, robot_text(robot, out.suffix, dest=out))


_robot_module._WRITER[:] = [save_robot]  # Robot.save
