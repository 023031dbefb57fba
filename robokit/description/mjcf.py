r"""MJCF (MuJoCo's XML format) in: :func:`load_mjcf`.

Reading (:func:`load_mjcf`, used by ``robokit.load("arm.xml")``)
    The kinematic tree, joint axes and ranges, inertials and armature are read by
    Pinocchio's MJCF parser (``pinocchio.buildModelFromMJCF``) and the visual and collision
    geometry by ``pinocchio.buildGeomFromMJCF``. robokit corrects what Pinocchio 4.1 gets
    wrong or leaves out, so that the model is the one MuJoCo builds from the same file:

    * the placement (``pos`` and orientation) of the worldbody's first body when that body
      has no joint — Pinocchio drops it, so every body came out where MuJoCo would put it
      only if that body sat at the origin;
    * gravity, from ``<option gravity>`` (MuJoCo's default ``0 0 -9.81``);
    * the range of slide joints, which Pinocchio converts from degrees as if they were
      angles (MuJoCo takes them in metres whatever ``<compiler angle>`` says);
    * exact inertials written by :func:`mjcf_from_robot` for bodies MuJoCo's compiler cannot
      take as they are (see below).

    Elements with no meaning for a serial-chain model (actuators, tendons, equality
    constraints, sensors, contact pairs, keyframes, bodies after the first one in the
    worldbody, joint friction loss and springs) are ignored, and each is named in a note on
    stderr (a ``RobokitWarning``). Joint ``damping`` is kept in
    ``robot.model.damping`` (robokit's rigid-body dynamics does not add it).

    Exact inertials written by :func:`robokit.description.mjcf_write.mjcf_from_robot` in
    ``<custom><numeric name="robokit_inertial:BODY">`` replace the approximate ones MuJoCo
    needed (see :mod:`robokit.description.mjcf_write`).

Writing is :mod:`robokit.description.mjcf_write` (``mjcf_from_robot``, ``joint_armature_damping``).
"""
from __future__ import annotations

import math
import os
import xml.etree.ElementTree as ET
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import ArrayLike

from robokit.description._notes import note
from robokit.description.builder import build_robot, default_tip
from robokit.description.spec import RobotSpec
from robokit.errors import InputError

if TYPE_CHECKING:
    from robokit.description.robot import Robot

__all__ = ["load_mjcf", "first_body_placement", "CUSTOM_INERTIAL_PREFIX"]

#: prefix of the ``<custom><numeric>`` names that carry exact inertials
CUSTOM_INERTIAL_PREFIX = "robokit_inertial:"
#: top-level MJCF sections that carry nothing for a serial-chain model
_IGNORED_SECTIONS = ("actuator", "tendon", "equality", "sensor", "contact", "keyframe")


# --------------------------------------------------------------------------- XML helpers
def _parse_xml(path: Path) -> ET.Element:
    from robokit.description.mjcf_safety import read_mjcf_root

    return read_mjcf_root(path)  # bounded: regular file, byte cap, no DTD, depth and size capped


def _floats(elem: ET.Element | _Attr, attr: str, n: int | None, path: str | os.PathLike[str]) -> np.ndarray | None:
    text = elem.get(attr)
    if text is None:
        return None
    try:
        vals = np.array([float(t) for t in text.split()])
    except ValueError:
        raise InputError(f"{path}: <{elem.tag} name={elem.get('name', '')!r}> attribute {attr}={text!r}: "
                         "expected numbers") from None
    if n is not None and vals.size != n:
        raise InputError(f"{path}: <{elem.tag} name={elem.get('name', '')!r}> attribute {attr}={text!r}: "
                         f"expected {n} numbers, got {vals.size}")
    if not np.all(np.isfinite(vals)):
        raise InputError(f"{path}: <{elem.tag} name={elem.get('name', '')!r}> attribute {attr}: not finite")
    return vals


def _axis_rotation(axis: ArrayLike, angle: float) -> np.ndarray:
    a = np.asarray(axis, dtype=float)
    a = a / np.linalg.norm(a)
    K = np.array([[0, -a[2], a[1]], [a[2], 0, -a[0]], [-a[1], a[0], 0]])
    return np.eye(3) + math.sin(angle) * K + (1 - math.cos(angle)) * K @ K


def _quat_to_matrix(q: ArrayLike) -> np.ndarray:
    w, x, y, z = np.asarray(q, dtype=float) / np.linalg.norm(q)
    return np.array([
        [1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
        [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
        [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)],
    ])


def _compiler_settings(root: ET.Element) -> dict:
    out = {"angle": "degree", "eulerseq": "xyz"}
    for comp in root.iter("compiler"):
        for key in out:
            if comp.get(key) is not None:
                out[key] = comp.get(key, "")
    return out


def _body_rotation(body: ET.Element, compiler: dict, path: str | os.PathLike[str]) -> np.ndarray:
    """Orientation of an MJCF ``<body>`` in its parent, by MuJoCo's rules (one of quat,
    axisangle, euler, xyaxes, zaxis; the compiler's angle unit and Euler sequence)."""
    k = math.pi / 180.0 if compiler["angle"] == "degree" else 1.0
    q = _floats(body, "quat", 4, path)
    if q is not None:
        if np.linalg.norm(q) == 0:
            raise InputError(f"{path}: <body name={body.get('name', '')!r}> quat is zero")
        return _quat_to_matrix(q)
    aa = _floats(body, "axisangle", 4, path)
    if aa is not None:
        return _axis_rotation(aa[:3], aa[3] * k)
    eu = _floats(body, "euler", 3, path)
    if eu is not None:
        seq = compiler["eulerseq"]
        R = np.eye(3)
        for c, a in zip(seq, eu):
            Ri = _axis_rotation(np.eye(3)["xyz".index(c.lower())], a * k)
            R = R @ Ri if c.islower() else Ri @ R  # lower case: rotating axes; upper case: fixed axes
        return R
    xy = _floats(body, "xyaxes", 6, path)
    if xy is not None:
        x = xy[:3] / np.linalg.norm(xy[:3])
        y = xy[3:] - (xy[3:] @ x) * x
        y /= np.linalg.norm(y)
        return np.column_stack([x, y, np.cross(x, y)])
    za = _floats(body, "zaxis", 3, path)
    if za is not None:
        z = za / np.linalg.norm(za)
        c = float(z[2])
        axis = np.cross([0.0, 0.0, 1.0], z)
        s = float(np.linalg.norm(axis))
        if s < 1e-12:
            return np.eye(3) if c > 0 else _axis_rotation([1.0, 0.0, 0.0], math.pi)
        return _axis_rotation(axis / s, math.atan2(s, c))
    return np.eye(3)


def first_body_placement(path: str | os.PathLike[str]) -> tuple[str | None, np.ndarray | None]:
    """The worldbody's first ``<body>`` and its pose, if that body has no joint.

    This is the placement Pinocchio 4.1's MJCF parser drops; robokit puts it back.

    Parameters
    ----------
    path : str or os.PathLike
        The MJCF file.

    Returns
    -------
    name : str or None
        The body's name; None when the first body has a joint (Pinocchio places it correctly)
        or there is no body.
    pose : numpy.ndarray, shape (4, 4), or None
        Its pose in the world frame: ``pos`` in m, the rotation by MuJoCo's rules (``quat``,
        ``axisangle``, ``euler``, ``xyaxes`` or ``zaxis``, the compiler's angle unit).

    Examples
    --------
    >>> import pathlib, tempfile
    >>> xml = ('<mujoco><worldbody><body name="base" pos="0 0 0.5">'
    ...        '<body name="l1"><joint name="j1"/></body></body></worldbody></mujoco>')
    >>> with tempfile.TemporaryDirectory() as tmp:
    ...     path = pathlib.Path(tmp, "arm.xml")
    ...     _ = path.write_text(xml)
    ...     name, T = first_body_placement(path)
    >>> name, T[:3, 3].tolist()
    ('base', [0.0, 0.0, 0.5])
    """
    path = Path(path)
    root = _parse_xml(path)
    world = root.find("worldbody")
    body = world.find("body") if world is not None else None
    if body is None:
        return None, None
    if body.find("joint") is not None or body.find("freejoint") is not None:
        return None, None
    T = np.eye(4)
    pos = _floats(body, "pos", 3, path)
    if pos is not None:
        T[:3, 3] = pos
    T[:3, :3] = _body_rotation(body, _compiler_settings(root), path)
    return body.get("name"), T


# --------------------------------------------------------------------------- reading
def _ignored_notes(root: ET.Element, path: Path) -> list[str]:
    notes = []
    for section in _IGNORED_SECTIONS:
        for elem in root.findall(section):
            kids = sorted({c.tag for c in elem})
            if kids:
                notes.append(f"{path}: <{section}> ignored ({', '.join(kids)}): robokit models the rigid-body chain only")
    world = root.find("worldbody")
    if world is not None:
        bodies = world.findall("body")
        for b in bodies[1:]:
            notes.append(f"{path}: <body name={b.get('name', '')!r}> ignored: only the worldbody's first body tree "
                         "is read (Pinocchio's MJCF parser)")
        for j in world.iter("joint"):
            for attr in ("frictionloss", "stiffness"):
                v = j.get(attr)
                if v is not None and float(v.split()[0]) != 0.0:
                    notes.append(f"{path}: <joint name={j.get('name', '')!r}> {attr}={v} ignored")
    if root.find("include") is not None or root.find(".//include") is not None:
        notes.append(f"{path}: <include> found: the first body's placement is read from this file only")
    return notes


def _apply_first_body_fix(model: Any, geoms: list[Any], name: str | None, X: np.ndarray) -> bool:
    """Left-multiply the placements of everything hung on the universe joint from the first
    body down by X (the first body's world pose) if Pinocchio left it out; True if applied."""
    import pinocchio as pin

    fid = None
    for i, f in enumerate(model.frames):
        if i > 0 and f.parentJoint == 0 and f.type == pin.FrameType.BODY and (name is None or f.name == name):
            fid = i
            break
    if fid is None:
        return False
    Xs = pin.SE3(X[:3, :3].copy(), X[:3, 3].copy())
    if np.allclose(model.frames[fid].placement.homogeneous, X, atol=1e-12):
        return False  # this Pinocchio places the first body correctly
    if not np.allclose(model.frames[fid].placement.homogeneous, np.eye(4), atol=1e-12):
        raise InputError(f"first body {name!r}: Pinocchio placed it neither at the identity nor at its MJCF pose; "
                         "cannot correct this parser's output")
    # frames in the first body's subtree: those whose parent-frame chain reaches fid
    in_tree = {fid}
    for i, f in enumerate(model.frames):
        if f.parentJoint == 0 and i not in in_tree:
            k, seen = f.parentFrame, set()
            while k not in in_tree and k != 0 and k not in seen:
                seen.add(k)
                k = model.frames[k].parentFrame
            if k in in_tree:
                in_tree.add(i)
    for i in sorted(in_tree):
        model.frames[i].placement = Xs * model.frames[i].placement
    for j in range(1, model.njoints):
        if model.parents[j] == 0:
            model.jointPlacements[j] = Xs * model.jointPlacements[j]
    for gm in geoms:
        if gm is None:
            continue
        for go in gm.geometryObjects:
            if go.parentJoint == 0 and go.parentFrame in in_tree:
                go.placement = Xs * go.placement
    return True


def _joint_defaults(root: ET.Element) -> dict:
    """``{class name: {attribute: value}}`` of the ``<joint>`` defaults, nested classes
    inheriting from their parents (the top ``<default>`` is class "main")."""
    out = {}

    def walk(elem: ET.Element, inherited: dict) -> None:
        name = elem.get("class", "main")
        attrs = dict(inherited)
        j = elem.find("joint")
        if j is not None:
            attrs.update(j.attrib)
        out[name] = attrs
        for child in elem.findall("default"):
            walk(child, attrs)

    for top in root.findall("default"):
        walk(top, {})
    return out


def _slide_ranges(root: ET.Element, path: str | os.PathLike[str]) -> dict:
    """``{joint name: (lower, upper)}`` of the slide joints with a range, in m (MuJoCo never
    converts a slide joint's range, whatever the compiler's angle unit)."""
    defaults = _joint_defaults(root)
    out = {}

    def walk(elem: ET.Element, childclass: str) -> None:
        for child in elem:
            if child.tag == "joint":
                attrs = dict(defaults.get(child.get("class", childclass), {}))
                attrs.update(child.attrib)
                if attrs.get("type", "hinge") == "slide" and "range" in attrs and attrs.get("limited") != "false":
                    rng = _floats(_Attr(attrs, child), "range", 2, path)
                    assert rng is not None  # "range" in attrs
                    out[child.get("name", "")] = (float(rng[0]), float(rng[1]))
            elif child.tag == "body":
                walk(child, child.get("childclass", childclass))

    world = root.find("worldbody")
    if world is not None:
        walk(world, "main")
    return out


class _Attr:
    """An element-like view of merged attributes (for :func:`_floats` messages)."""

    def __init__(self, attrs: dict, elem: ET.Element) -> None:
        self.attrs, self.tag = attrs, elem.tag

    def get(self, key: str, default: str | None = None) -> str | None:
        return self.attrs.get(key, default)


def _fix_slide_ranges(model: Any, root: ET.Element, path: str | os.PathLike[str]) -> None:
    """Pinocchio 4.1 converts slide ranges from degrees like hinge ranges; MuJoCo does not."""
    for name, (lo, hi) in _slide_ranges(root, path).items():
        if not name or not model.existJointName(name):
            continue
        jm = model.joints[model.getJointId(name)]
        if jm.nq == 1 and jm.shortname().startswith(("JointModelP", "JointModelPrismatic")):
            model.lowerPositionLimit[jm.idx_q] = lo
            model.upperPositionLimit[jm.idx_q] = hi


def _gravity(root: ET.Element, path: str | os.PathLike[str]) -> np.ndarray:
    g = np.array([0.0, 0.0, -9.81])
    for opt in root.iter("option"):
        v = _floats(opt, "gravity", 3, path)
        if v is not None:
            g = v
    return g


def _custom_inertials(root: ET.Element, path: str | os.PathLike[str]) -> dict:
    out = {}
    for num in root.iter("numeric"):
        name = num.get("name", "")
        if name.startswith(CUSTOM_INERTIAL_PREFIX):
            data = _floats(num, "data", 10, path)
            out[name[len(CUSTOM_INERTIAL_PREFIX):]] = data
    return out


def _apply_custom_inertials(model: Any, exact: dict, path: str | os.PathLike[str]) -> list[str]:
    import pinocchio as pin

    applied = []
    for body, d in exact.items():
        if not model.existFrame(body, pin.FrameType.BODY):
            note(f"{path}: <numeric name='{CUSTOM_INERTIAL_PREFIX}{body}'> ignored: no body {body!r}")
            continue
        f = model.frames[model.getFrameId(body, pin.FrameType.BODY)]
        j = f.parentJoint
        others = [g for g in model.frames if g.type == pin.FrameType.BODY and g.parentJoint == j and g.name != body]
        if j == 0 or others or not np.allclose(f.placement.homogeneous, np.eye(4)):
            note(f"{path}: exact inertial of {body!r} ignored: the body is not alone at its joint's origin")
            continue
        m, c, (xx, yy, zz, xy, xz, yz) = d[0], d[1:4], d[4:]
        I = np.array([[xx, xy, xz], [xy, yy, yz], [xz, yz, zz]])
        model.inertias[j] = pin.Inertia(float(m), np.array(c, dtype=float), I)
        applied.append(body)
    return applied


def _default_tip(model: Any) -> str:
    """The last site (operational frame) on the chain's last joint, else the last body."""
    import pinocchio as pin

    body = default_tip(model)
    j = model.frames[model.getFrameId(body)].parentJoint
    sites = [f.name for f in model.frames if f.type == pin.FrameType.OP_FRAME and f.parentJoint == j]
    return sites[-1] if sites else body


def load_mjcf(path: str | os.PathLike[str], tip: str | None = None, *, allow_outside_meshes: bool = False) -> Robot:
    """Load an MJCF file as a :class:`robokit.Robot` (see the module docstring).

    Parameters
    ----------
    path : str or Path
        An MJCF ``.xml`` file (root element ``<mujoco>``).
    tip : str, optional
        The chain's tip frame (a body or site name). Default: the last site of the chain's
        last body, else that body.
    allow_outside_meshes : bool
        Read mesh files outside the file's folder and its package (refused by default; see
        :mod:`robokit.description.meshes`). Includes are always confined.

    Returns
    -------
    Robot
        With gravity from ``<option gravity>``, armature in ``robot.model.armature``;
        ``robot.spec == RobotSpec("mjcf", path=<absolute path>, tip=tip)``.

    Raises
    ------
    InputError
        Missing file, malformed XML (file:line:column), a root element other than
        ``<mujoco>``, a model Pinocchio cannot parse, or no serial chain to the tip.

    Examples
    --------
    The shipped planar arm written as MJCF and read back:

    >>> import pathlib, tempfile
    >>> from robokit.description.mjcf_write import mjcf_from_robot
    >>> with tempfile.TemporaryDirectory() as tmp:
    ...     path = pathlib.Path(tmp, "twolink.xml")
    ...     _ = path.write_text(mjcf_from_robot(rk.load("twolink"))[0])
    ...     robot = load_mjcf(path)
    >>> robot.n, robot.frame_pose([0.0, np.pi / 2])[:3, 3].round(4).tolist()
    (2, [1.0, 0.8, 0.0])
    """
    import pinocchio as pin

    path = Path(path)
    if not path.exists():  # a FIFO or device is refused by the bounded reader
        raise InputError(f"{path}: file not found")
    from robokit.description.mjcf_safety import check_mjcf

    import tempfile

    # Pinocchio reads robokit's checked copy (includes, files, joints checked), never the user's files again
    checked_dir = tempfile.TemporaryDirectory(prefix="robokit-mjcf-")
    checked = str(Path(checked_dir.name) / "model.xml")
    try:
        root = check_mjcf(path, allow_outside_meshes=allow_outside_meshes, copy_to=checked_dir.name)
        if root.tag != "mujoco":
            raise InputError(f"{path}: root element <{root.tag}> is not <mujoco>; an MJCF file starts with <mujoco>")
        world = root.find("worldbody")
        if world is None or world.find("body") is None:
            raise InputError(f"{path}: <worldbody> has no <body>; nothing to load")
        for n in _ignored_notes(root, path):
            note(n)
        gravity = _gravity(root, path)
        exact = _custom_inertials(root, path)
        first_name, X = first_body_placement(path)
        try:
            model = pin.buildModelFromMJCF(checked)
        except Exception as exc:  # Pinocchio raises ValueError/RuntimeError with multi-line text
            msg = " ".join(str(exc).replace(checked, str(path)).split()) or type(exc).__name__
            raise InputError(f"{path}: Pinocchio's MJCF parser rejected the file ({msg[:300]})") from None
        geoms = []
        for gtype, label in ((pin.GeometryType.VISUAL, "visual"), (pin.GeometryType.COLLISION, "collision")):
            try:
                geoms.append(pin.buildGeomFromMJCF(model, checked, gtype))
            except Exception as exc:
                note(f"{path}: {label} geometry not loaded ({' '.join(str(exc).replace(checked, str(path)).split())[:200]})")
                geoms.append(None)
    finally:
        checked_dir.cleanup()
    if X is not None:
        _apply_first_body_fix(model, geoms, first_name, X)
    model.gravity.linear = gravity
    _fix_slide_ranges(model, root, path)
    if exact:
        _apply_custom_inertials(model, exact, path)
    spec = RobotSpec("mjcf", path=os.path.abspath(path), tip=tip, allow_outside_meshes=allow_outside_meshes)
    tip = tip or _default_tip(model)
    name = root.get("model") or path.stem
    return build_robot(name, model, tip, geoms, {}, spec)

