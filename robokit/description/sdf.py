r"""SDFormat (``.sdf``, ``.world``) in: :func:`load_sdf` (``robokit.load("model.sdf")``).

No pip parser of SDFormat is kept up to date (``python-sdformat`` last released in 2022, the
``sdformat14`` bindings once, Pinocchio's wheel is built without libsdformat), so robokit reads
the subset a robot arm needs itself, with the specification's frame rules, into a
:class:`~robokit.description.model_builder.Description` that
:func:`~robokit.description.model_builder.build_model` turns into the Pinocchio model.

What is read
    * one ``<model>`` — the file's own, or the one model of a ``<world>`` (a ``<model>`` or an
      ``<include>``); its ``<pose>`` places it in the world; ``<static>true</static>`` makes it
      immovable (refused at the top: nothing would move; a static nested model's links are
      fixed to the world and its joints locked);
    * ``<link>``: ``<pose>``, ``<inertial>`` (``<pose>``, ``<mass>``, ``<inertia>`` about the
      centre of mass in the inertial frame's axes; a link without ``<inertial>`` gets
      SDFormat's default, 1 kg and 1 kg·m² about each axis, as libsdformat gives it — noted),
      ``<visual>``/``<collision>`` with ``<pose>`` and a box, cylinder, sphere, capsule or mesh
      (``<uri>``, ``<scale>``) geometry, and the visual's ``<material><diffuse>`` colour;
    * ``<joint>`` of type revolute, continuous, prismatic or fixed: ``<parent>``/``<child>``
      (a link, ``world``, or — SDFormat 1.8 — a frame, meaning the link it is attached to),
      ``<pose>``, ``<axis><xyz expressed_in=…>`` (SDFormat 1.4: in the model frame; 1.5–1.6:
      in the joint frame unless ``<use_parent_model_frame>``), ``<limit>`` (``lower``/``upper``
      of ±1e16 or beyond — SDFormat's "no limit"; Gazebo's files write ±1.79769e+308 or ``inf`` —
      read as ±inf; a negative ``effort``/``velocity`` as unlimited), ``<dynamics><damping>``/``<friction>`` (stored in the model, as for URDF);
      Drake's ``<drake:rotor_inertia>`` and ``<drake:gear_ratio>`` become the joint's reflected
      inertia ``rotor_inertia · gear_ratio²``, which Drake adds to the mass matrix's diagonal and to
      inverse dynamics, as ``model.armature`` does (only on a joint Drake actuates: ``<effort>``
      not 0) — one note says so, and ``reflected_inertia=False`` leaves it out; ``<axis><initial_position>``
      (the joint's initial position, which Gazebo does not apply) becomes the robot's named configuration
      ``"initial"`` over the chain's joints (a value on a joint off the chain, locked at 0, is noted);
    * ``<frame name attached_to>`` — an operational frame of the model;
    * nested ``<model>``\ s (names scoped ``outer::inner::link``), ``<include>`` of
      ``model://NAME`` (a folder NAME with a ``model.config`` or a ``model.sdf``) and
      ``package://PKG/…`` URIs, looked up in ``package_dirs`` (at any depth below them, as colcon finds packages) and beside the including file,
      with ``<name>``, ``<pose>``, ``<static>``, ``<placement_frame>`` and ``merge``.

Frames and poses (SDFormat 1.7–1.11, and the 1.4–1.6 rules before them)
    Every ``<pose>`` is relative to the frame its ``relative_to`` names (1.5–1.6: the legacy
    ``frame`` attribute) or else to its element's default: a link and a nested model to the
    model frame, a joint to its child link, a ``<frame>`` to the frame it is attached to (by
    default the model frame), an inertial, visual or collision to its link; the model frame
    (``__model__``) is where the model's ``<pose>`` puts it (``placement_frame``: where that
    frame lands) and is attached to its canonical link. Poses are ``x y z roll pitch yaw``
    (``degrees="true"`` allowed) or ``rotation_format="quat_xyzw"``. A loop of ``relative_to``
    or an unknown frame is refused.

What is not modelled
    Everything else is read and listed once in a note (``<plugin>``, ``<sensor>``,
    ``<self_collide>``, ``<surface>``, joint springs, ``<enable_wind>true</enable_wind>``, ``<drake:…>`` elements other than the two
    above such as collision filter groups and acceleration limits, ...); purely cosmetic
    elements (materials other than the diffuse colour, shadows, transparency) are skipped
    silently. A robokit robot is fixed-base: the root link is fixed to the world where the model
    places it (noted when no joint to ``world`` says so).

Custom elements and attributes
    Names are read as written, as libsdformat (TinyXML2) reads them: a prefix needs no ``xmlns``
    and means what it spells (``drake:rotor_inertia`` is Drake's, declared or not). A custom
    element — a name holding ``:`` — is named in the not-modelled note where it stands (no shape
    inside ``<geometry>``); a custom attribute (``gz:expressed_in`` on a contact's ``<fdir1>``) is
    ignored without a note, as libsdformat keeps it without one.

Bounds and confinement (as for URDF, see docs/hardening.md)
    Each file is read by the bounded reader (at most :data:`MAX_SDF_BYTES`, regular files), its
    XML checked (no DTD or entities, depth and element caps); includes are followed at most
    :data:`MAX_INCLUDE_DEPTH` deep and :data:`MAX_INCLUDES` files, a cycle is refused, nested
    models at most :data:`MAX_MODEL_DEPTH` deep, joints counted across all files and capped at
    :data:`robokit.description.limits.MAX_JOINTS`. Every file an include or a mesh names must lie
    inside the top file's folder, its ROS package or ``package_dirs`` (meshes elsewhere only with
    ``allow_outside_meshes=True``); anything else is refused with one line.
"""
from __future__ import annotations

import math
import os
import re
import xml.etree.ElementTree as ET
from dataclasses import dataclass, field
from pathlib import Path
from typing import Sequence

import numpy as np

from robokit._io import decode_utf8, read_input_bytes
from robokit._xml import parse_xml
from robokit.description.builder import build_robot
from robokit.description.limits import check_joint_count
from robokit.description.meshes import allowed_roots, confine, package_below, package_name
from robokit.description.model_builder import (Description, FrameSpec, Geometry, Inertial, Joint, Link, Pose,
                                               build_model)
from robokit.description.robot import Robot
from robokit.description.reflected import DrakeRotor, drake_reflected_inertia
from robokit.description.spec import RobotSpec
from robokit.errors import InputError

__all__ = ["load_sdf", "description_from_sdf", "MAX_SDF_BYTES", "MAX_INCLUDES", "MAX_INCLUDE_DEPTH",
           "MAX_MODEL_DEPTH"]

#: Largest SDFormat file (and each include) read; all files together at most 4× this.
MAX_SDF_BYTES = 20 << 20
#: Deepest ``<include>`` nesting and most files included.
MAX_INCLUDE_DEPTH, MAX_INCLUDES = 20, 200
#: Deepest nesting of ``<model>`` elements (included ones counted).
MAX_MODEL_DEPTH = 64

_JOINT_KINDS = ("revolute", "continuous", "prismatic", "fixed")
#: The examples' file: a 2 kg bob 1 m below a hinge about x.
_PENDULUM_SDF = ('<sdf version="1.9"><model name="pendulum"><link name="base"/>'
                 '<link name="bob"><pose>0 0 -1 0 0 0</pose><inertial><mass>2</mass></inertial></link>'
                 '<joint name="hinge" type="revolute"><parent>base</parent><child>bob</child>'
                 '<pose relative_to="base"/><axis><xyz>1 0 0</xyz></axis></joint></model></sdf>')
_NO_LIMIT = 1e16
#: The world frame's node name (no SDFormat name holds a NUL: a link may be named "world" before 1.7).
_WORLD = "\x00world"
#: Cosmetic elements skipped without a note.
_COSMETIC = {"material", "cast_shadows", "laser_retro", "transparency", "visibility_flags", "meta",
             "must_be_base_link", "allow_auto_disable"}
#: Flags that change no number when false (skipped then) and name a force robokit does not model when true.
_FORCE_FLAGS = {"enable_wind": "wind forces"}
_KNOWN = {
    "model": {"pose", "static", "link", "joint", "frame", "model", "include"},
    "link": {"pose", "inertial", "visual", "collision"},
    "inertial": {"pose", "mass", "inertia"},
    "visual": {"pose", "geometry"},
    "collision": {"pose", "geometry"},
    "joint": {"parent", "child", "pose", "axis", "drake:rotor_inertia", "drake:gear_ratio"},
    "axis": {"xyz", "use_parent_model_frame", "limit", "dynamics", "mimic", "initial_position"},
    "limit": {"lower", "upper", "effort", "velocity"},
    "dynamics": {"damping", "friction", "spring_reference", "spring_stiffness"},
    "include": {"uri", "name", "pose", "static", "placement_frame"},
    "frame": {"pose"},
    "mesh": {"uri", "scale", "submesh"},
}
#: Why an element robokit does not model matters, where the reason is not its name.
_WHY = {"<drake:declare_convex> in <mesh>": "Drake collides with the mesh's convex hull; robokit's World does "
                                            "with convex=True"}


def _tag(el: ET.Element) -> str:
    """The element's tag as written, prefix and all (``drake:rotor_inertia``): the file is read with
    names as TinyXML2 reads them (:func:`robokit._xml.parse_xml` with ``namespaces=False``), so a
    prefix means what it spells, declared or not, as in libsdformat and Drake (which look
    ``drake:rotor_inertia`` up by that name)."""
    return str(el.tag)


def _child(el: ET.Element, tag: str) -> ET.Element | None:
    for c in el:
        if _tag(c) == tag:
            return c
    return None


def _join(scope: str, name: str) -> str:
    return f"{scope}::{name}" if scope else name


@dataclass
class _Node:
    """A frame of the pose graph: its pose ``X`` relative to ``rel`` (an absolute frame name, or the world).

    ``rel_raw`` (as written, resolved in ``scope``) overrides ``default_rel``; ``attached_raw`` (resolved in
    ``inner`` for a model, else ``scope``) overrides ``attached``. A model's ``inner`` is its own scope.
    """

    kind: str
    X: np.ndarray
    rel_raw: str | None
    scope: _Scope
    where: str
    default_rel: str = _WORLD
    attached_raw: str | None = None
    attached: str = _WORLD
    inner: _Scope | None = None
    placement_frame: str | None = None
    rel: str = _WORLD


@dataclass
class _Scope:
    prefix: str
    model_node: str
    version: tuple[int, int]
    file: Path
    static: bool = False
    world_link: bool = False  # SDFormat < 1.7: a link of this model named "world" is what "world" means

    @property
    def legacy(self) -> bool:
        return self.version < (1, 7)

    def resolve(self, raw: str, where: str) -> str:
        raw = raw.strip()
        if raw == "world":
            return _join(self.prefix, "world") if self.world_link else _WORLD
        if raw == "__model__":
            return self.model_node
        if raw.endswith("::__model__"):
            return _join(self.prefix, raw[: -len("::__model__")])
        return _join(self.prefix, raw)


@dataclass
class _JointRaw:
    name: str
    kind: str
    parent_raw: str
    child_raw: str
    scope: _Scope
    axis: tuple[float, float, float]
    axis_in: str | None  # raw frame name the axis is expressed in; None: the joint frame
    lower: float
    upper: float
    effort: float
    velocity: float
    damping: float
    friction: float
    rotor: float | None
    gear: float | None
    mimic: str | None
    initial: float = 0.0  # <axis><initial_position>
    mimic_terms: tuple[float, float] = (1.0, 0.0)  # <mimic>: value = multiplier · leader + offset (reference folded in)


@dataclass
class _Reader:
    top: Path
    package_dirs: tuple[Path, ...]
    allow_outside_meshes: bool
    roots: list[Path]
    nodes: dict[str, _Node] = field(default_factory=dict)
    links: dict[str, tuple[ET.Element, _Scope]] = field(default_factory=dict)
    joints: list[_JointRaw] = field(default_factory=list)
    frames: list[str] = field(default_factory=list)
    unmodelled: dict[str, int] = field(default_factory=dict)
    leading: list[str] = field(default_factory=list)  # numbers read from a text with more after them
    files: int = 1
    total_bytes: int = 0
    joint_count: int = 0
    gravity: tuple[float, float, float] = (0.0, 0.0, -9.81)
    world_fixed: set[str] = field(default_factory=set)
    memo: dict[str, np.ndarray] = field(default_factory=dict)
    model_name: str = ""
    missing_meshes: list[str] = field(default_factory=list)
    missing_collision: list[str] = field(default_factory=list)  # the links of the collision meshes among them

    def note_unmodelled(self, el: ET.Element, context: str) -> None:
        known = _KNOWN.get(context, set())
        for c in el:
            t = _tag(c)
            if t in known or t in _COSMETIC or not isinstance(c.tag, str):
                continue
            if t in _FORCE_FLAGS:
                if (c.text or "").strip().lower() not in ("true", "1"):
                    continue
                t = f"{t}>true</{t}"  # shown as <enable_wind>true</enable_wind>
            key = f"<{t}> in <{context}>"
            key += f" ({_FORCE_FLAGS[_tag(c)]})" if _tag(c) in _FORCE_FLAGS else ""
            key += f" ({_WHY[key]})" if key in _WHY else ""
            self.unmodelled[key] = self.unmodelled.get(key, 0) + 1

    def read_root(self, path: Path, what: str) -> ET.Element:
        raw = read_input_bytes(path, MAX_SDF_BYTES, what)
        self.total_bytes += len(raw)
        if self.total_bytes > 4 * MAX_SDF_BYTES:
            raise InputError(f"{self.top}: the files included add up to more than {4 * MAX_SDF_BYTES >> 20} MiB")
        return parse_xml(decode_utf8(raw, path), path, namespaces=False)


# --------------------------------------------------------------------------- numbers
def _floats(text: str | None, where: str, counts: tuple[int, ...]) -> list[float]:
    try:
        vals = [float(t) for t in (text or "").split()]
    except ValueError:
        raise InputError(f"{where}: expected numbers, got {(text or '').strip()[:60]!r}") from None
    if len(vals) not in counts:
        raise InputError(f"{where}: expected {' or '.join(map(str, counts))} numbers, got {len(vals)}")
    if not all(math.isfinite(v) and abs(v) <= 1e17 for v in vals):
        raise InputError(f"{where}: numbers must be finite and at most 1e17 in size")
    return vals


#: A number at the start of a text, as a C++ stream reads one (libsdformat's scalar values).
_LEADING_NUMBER = re.compile(r"[+-]?(?:\d+\.?\d*|\.\d+)(?:[eE][+-]?\d+)?")


def _scalar(text: str, where: str, rd: _Reader | None) -> float:
    """A scalar value as libsdformat reads it: the whole text when it is a number, else the number it
    starts with, the rest ignored (measured with Drake 1.58's libsdformat: ``2.5"`` is 2.5, ``1 2`` is 1,
    ``1e-1x`` 0.1; Drake's own iiwa14_polytope_collision.sdf writes ``<velocity>2.356194490192345"``),
    noted once per file; a text that does not start with a number is refused, as libsdformat refuses it."""
    text = text.strip()
    try:
        return float(text)
    except ValueError:
        pass
    m = _LEADING_NUMBER.match(text)
    if m is None:
        raise InputError(f"{where}: expected a number, got {text[:60]!r}")
    value = float(m.group())
    if rd is not None:
        rd.leading.append(f"{where.rsplit(': ', 1)[-1]} {text[:30]!r} as {value:g}")
    return value


def _limit(el: ET.Element | None, tag: str, default: float, where: str, rd: _Reader | None = None) -> float:
    """A joint limit: any magnitude, ``inf`` included — Gazebo's files write "no limit" as
    ±1.79769e+308 (its wheel joints) or ``inf`` (libsdformat reads both); NaN is refused."""
    c = _child(el, tag) if el is not None else None
    if c is None or not (c.text or "").strip():
        return default
    text = (c.text or "").strip()
    value = _scalar(text, f"{where} <{tag}>", rd)
    if math.isnan(value):
        raise InputError(f"{where} <{tag}>: expected a number, got {text[:60]!r}")
    return value


def _number(el: ET.Element | None, tag: str, default: float, where: str, rd: _Reader | None = None) -> float:
    c = _child(el, tag) if el is not None else None
    if c is None or not (c.text or "").strip():
        return default
    value = _scalar(c.text or "", f"{where} <{tag}>", rd)
    if not (math.isfinite(value) and abs(value) <= 1e17):
        raise InputError(f"{where} <{tag}>: numbers must be finite and at most 1e17 in size")
    return value


def _flag(el: ET.Element | None, tag: str) -> bool | None:
    c = _child(el, tag) if el is not None else None
    if c is None:
        return None
    return (c.text or "").strip().lower() in ("1", "true")


def _pose(el: ET.Element, where: str, scope: _Scope) -> tuple[np.ndarray, str | None]:
    """(T, relative_to) of the ``<pose>`` child of ``el`` (identity, None when absent)."""
    from robokit.spatial.quaternion import matrix_from_quaternion

    p = _child(el, "pose")
    if p is None:
        return np.eye(4), None
    rel = p.get("relative_to") or (p.get("frame") if scope.legacy else None) or None
    fmt = p.get("rotation_format", "euler_rpy")
    T = np.eye(4)
    if fmt == "quat_xyzw":
        v = _floats(p.text, f"{where} <pose>", (0, 7))
        if v:
            q = np.array([v[6], v[3], v[4], v[5]])
            if np.linalg.norm(q) < 1e-12:
                raise InputError(f"{where} <pose>: the quaternion is zero")
            T[:3, :3] = matrix_from_quaternion(q / np.linalg.norm(q))
            T[:3, 3] = v[:3]
    elif fmt == "euler_rpy":
        v = _floats(p.text, f"{where} <pose>", (0, 6))
        if v:
            rpy = np.radians(v[3:]) if (p.get("degrees") or "").lower() in ("1", "true") else np.asarray(v[3:])
            T = Pose.from_xyz_rpy(v[:3], rpy).matrix
    else:
        raise InputError(f"{where} <pose>: rotation_format {fmt!r} (expected euler_rpy or quat_xyzw)")
    return T, rel


def _pose_value(T: np.ndarray) -> Pose:
    return Pose.from_matrix(T)


def _check_name(name: str | None, where: str, legacy: bool = False) -> str:
    if not name or not name.isprintable() or len(name) > 200:
        raise InputError(f"{where}: expected a printable name (at most 200 characters), got {name!r}")
    if (name == "world" and not legacy) or (name.startswith("__") and name.endswith("__")):
        raise InputError(f"{where}: the name {name!r} is reserved in SDFormat")
    return name


def _version(root: ET.Element, path: Path) -> tuple[int, int]:
    text = root.get("version", "1.11")
    try:
        major, minor = (int(x) for x in text.strip().split(".")[:2])
    except ValueError:
        raise InputError(f"{path}: <sdf version={text!r}>: expected a version such as 1.9") from None
    return major, minor


# --------------------------------------------------------------------------- URIs
def _find_package(pkg: str, rel: str, roots: Sequence[Path]) -> Path | None:
    for root in roots:
        for cand in (root / pkg / rel, root / rel if (root.name == pkg or (
                (root / "package.xml").is_file() and package_name(root / "package.xml") == pkg)) else None):
            if cand is not None and os.path.lexists(cand):
                return cand
    return None


def _resolve_uri(rd: _Reader, uri: str, source: Path) -> Path | None:
    """The path a ``model://``, ``package://``, ``file://``, absolute or relative URI names (None: not found)."""
    uri = uri.strip()
    if uri.startswith("model://") or uri.startswith("package://"):
        scheme, rest = uri.split("://", 1)
        name, _, rel = rest.partition("/")
        if scheme == "model":
            for root in [*rd.package_dirs, source.parent, source.parent.parent]:
                if os.path.lexists(root / name):
                    return root / name / rel
            return None
        found = _find_package(name, rel, [*rd.package_dirs, source.parent, *source.parent.parents])
        for d in [] if found is not None else rd.package_dirs:  # at any depth, as colcon finds packages
            pkg, _ = package_below(d, name)
            if pkg is not None and os.path.lexists(pkg / rel):
                return pkg / rel
        return found
    if "://" in uri and not uri.startswith("file://"):
        raise InputError(f"{source}: URI {uri!r}: only model://, package://, file:// and paths are read")
    p = Path(uri[len("file://"):] if uri.startswith("file://") else uri)
    return p if p.is_absolute() else source.parent / p


def _model_file(rd: _Reader, folder: Path, source: Path, what: str) -> Path:
    """The SDFormat file of a model folder: ``model.config``'s ``<sdf>`` (highest version), else model.sdf."""
    config = folder / "model.config"
    if config.is_file():
        confine(config, rd.roots, source, what)
        root = rd.read_root(config, "a model.config")
        best: tuple[tuple[int, int], str] | None = None
        for s in root.iter("sdf"):
            try:
                ver = tuple(int(x) for x in s.get("version", "0.0").split(".")[:2])
            except ValueError:
                ver = (0, 0)
            if (s.text or "").strip() and (best is None or ver > best[0]):
                best = ((ver[0], ver[1]) if len(ver) == 2 else (0, 0), (s.text or "").strip())
        if best is not None:
            return folder / best[1]
    return folder / "model.sdf"


# --------------------------------------------------------------------------- reading
def _add_node(rd: _Reader, name: str, node: _Node) -> None:
    if name in rd.nodes:
        raise InputError(f"{node.where}: the name {name!r} is used twice (links, joints, frames and models share "
                         "one namespace)")
    rd.nodes[name] = node


def _read_model(rd: _Reader, el: ET.Element, scope: _Scope, depth: int, stack: tuple[Path, ...]) -> None:
    """Read the links, joints, frames and nested models of the model ``el`` (its node already added)."""
    if depth > MAX_MODEL_DEPTH:
        raise InputError(f"{scope.file}: models nested deeper than {MAX_MODEL_DEPTH} levels")
    where_model = f"{scope.file}: model {scope.model_node!r}"
    rd.note_unmodelled(el, "model")
    first: str | None = None  # the canonical link by default: the first link, else the first nested model's
    scope.world_link = scope.legacy and any(_tag(c) == "link" and c.get("name") == "world" for c in el)
    for c in el:
        t = _tag(c)
        if t == "link":
            name = _join(scope.prefix, _check_name(c.get("name"), f"{where_model}: a <link>", scope.legacy))
            where = f"{scope.file}: link {name!r}"
            X, rel = _pose(c, where, scope)
            _add_node(rd, name, _Node("link", X, rel, scope, where, default_rel=scope.model_node, attached=name))
            rd.links[name] = (c, scope)
            if scope.static:
                rd.world_fixed.add(name)
            first = first or name
            for sub in ("inertial", "visual", "collision"):
                for s in (x for x in c if _tag(x) == sub):
                    rd.note_unmodelled(s, sub)
            rd.note_unmodelled(c, "link")
        elif t == "joint":
            _read_joint(rd, c, scope)
        elif t == "frame":
            name = _join(scope.prefix, _check_name(c.get("name"), f"{where_model}: a <frame>"))
            where = f"{scope.file}: frame {name!r}"
            X, rel = _pose(c, where, scope)
            attached = c.get("attached_to") or None
            to = scope.resolve(attached, where) if attached else scope.model_node
            _add_node(rd, name, _Node("frame", X, rel, scope, where, default_rel=to, attached_raw=attached,
                                      attached=scope.model_node))
            rd.frames.append(name)
            rd.note_unmodelled(c, "frame")
        elif t == "model":
            name = _check_name(c.get("name"), f"{where_model}: a nested <model>")
            nested = _nested_model(rd, c, scope, name, None, None, scope.version, False, scope.static, depth, stack,
                                   scope.file)
            first = first or nested
        elif t == "include":
            nested = _include(rd, c, scope, depth, stack)
            first = first or nested
    node = rd.nodes[scope.model_node]
    canonical = el.get("canonical_link")
    if scope.static:
        node.attached = _WORLD
    elif canonical:
        node.attached_raw = canonical
    elif first is not None:
        node.attached = first


def _nested_model(rd: _Reader, el: ET.Element, parent: _Scope, name: str, pose: tuple[np.ndarray, str | None] | None,
                  placement: str | None, version: tuple[int, int], merge: bool, static: bool, depth: int,
                  stack: tuple[Path, ...], file: Path, top: bool = False) -> str:
    """Add the node of a model (the top one, a nested or an included one) and read it; return the node's name.

    The top model's node is ``__model__`` and its elements are not prefixed; a nested model's elements are
    ``name::element`` (not when ``merge``: an SDFormat 1.9 ``<include merge="true">``).
    """
    node_name = "__model__" if top else _join(parent.prefix, name)
    if top:
        rd.model_name = name
    static = static or bool(_flag(el, "static"))
    inner = _Scope("" if top else parent.prefix if merge else node_name, node_name, version, file, static)
    where = f"{file}: model {name!r}"
    X, rel = pose if pose is not None else _pose(el, where, parent)
    node = _Node("model", X, rel, parent, where, default_rel=parent.model_node, inner=inner,
                 placement_frame=placement or el.get("placement_frame") or None)
    _add_node(rd, node_name, node)
    _read_model(rd, el, inner, depth + 1, stack)
    return node_name


def _include(rd: _Reader, inc: ET.Element, scope: _Scope, depth: int, stack: tuple[Path, ...],
             top: bool = False) -> str:
    rd.note_unmodelled(inc, "include")
    uri_el = _child(inc, "uri")
    uri = (uri_el.text or "").strip() if uri_el is not None else ""
    what = f"<include> of {uri!r}"
    if not uri:
        raise InputError(f"{scope.file}: an <include> without a <uri>")
    if len(stack) > MAX_INCLUDE_DEPTH:
        raise InputError(f"{scope.file}: {what}: includes nested deeper than {MAX_INCLUDE_DEPTH} levels")
    rd.files += 1
    if rd.files > MAX_INCLUDES:
        raise InputError(f"{rd.top}: more than {MAX_INCLUDES} files included")
    target = _resolve_uri(rd, uri, scope.file)
    if target is None or not os.path.lexists(target):
        raise InputError(f"{scope.file}: {what}: not found beside the file or in the package folders given "
                         "(package_dirs, --package-path)")
    target = confine(target, rd.roots, scope.file, what)
    if target.is_dir():
        target = confine(_model_file(rd, target, scope.file, what), rd.roots, scope.file, what)
    if target in stack:
        chain = " -> ".join(p.name for p in (*stack[stack.index(target):], target))
        raise InputError(f"{scope.file}: {what}: include cycle ({chain})")
    root = rd.read_root(target, "an SDFormat file")
    model = root if _tag(root) == "model" else _child(root, "model")
    if model is None:
        raise InputError(f"{target}: included by {scope.file}: no <model> in it")
    version = _version(root, target) if _tag(root) == "sdf" else scope.version
    name_el = _child(inc, "name")
    name = _check_name((name_el.text or "").strip() if name_el is not None else model.get("name"),
                       f"{scope.file}: {what}")
    pose = _pose(inc, f"{scope.file}: {what}", scope) if _child(inc, "pose") is not None else None
    pf_el = _child(inc, "placement_frame")
    merge = (inc.get("merge") or "").lower() in ("1", "true")
    static = bool(_flag(inc, "static")) or scope.static
    return _nested_model(rd, model, scope, name, pose, (pf_el.text or "").strip() if pf_el is not None else None,
                         version, merge, static, depth, (*stack, target), target, top)


def _read_joint(rd: _Reader, el: ET.Element, scope: _Scope) -> None:
    name = _join(scope.prefix, _check_name(el.get("name"), f"{scope.file}: a <joint>"))
    where = f"{scope.file}: joint {name!r}"
    kind = el.get("type", "")
    if kind not in _JOINT_KINDS:
        raise InputError(f"{where}: a {kind!r} joint; robokit reads revolute, continuous, prismatic and fixed joints")
    rd.joint_count += 1
    check_joint_count(rd.joint_count, rd.top, "<joint> elements")
    parent_el, child_el = _child(el, "parent"), _child(el, "child")
    if parent_el is None or child_el is None or not (parent_el.text or "").strip() or not (child_el.text or "").strip():
        raise InputError(f"{where}: needs a <parent> and a <child>")
    child_raw = (child_el.text or "").strip()
    X, rel = _pose(el, where, scope)
    _add_node(rd, name, _Node("joint", X, rel, scope, where, default_rel=scope.resolve(child_raw, where),
                              attached_raw=child_raw))
    rd.note_unmodelled(el, "joint")
    axis_el = _child(el, "axis")
    xyz: list[float] = [0.0, 0.0, 1.0]
    axis_in: str | None = None
    lim = dyn = None
    mimic = None
    mimic_terms = (1.0, 0.0)
    initial = 0.0
    if axis_el is not None:
        rd.note_unmodelled(axis_el, "axis")
        xyz_el = _child(axis_el, "xyz")
        if xyz_el is not None and (xyz_el.text or "").strip():
            xyz = _floats(xyz_el.text, f"{where} <axis><xyz>", (3,))
        if xyz_el is not None and xyz_el.get("expressed_in"):
            axis_in = xyz_el.get("expressed_in")
        if scope.version < (1, 5) or _flag(axis_el, "use_parent_model_frame"):
            axis_in = "__model__"
        lim, dyn = _child(axis_el, "limit"), _child(axis_el, "dynamics")
        for sub, ctx in ((lim, "limit"), (dyn, "dynamics")):
            if sub is not None:
                rd.note_unmodelled(sub, ctx)
        mim = _child(axis_el, "mimic")
        mimic = mim.get("joint") if mim is not None else None
        if mim is not None:  # SDFormat 1.11: follower = multiplier · (leader − reference) + offset
            multiplier = _number(mim, "multiplier", 1.0, f"{where} <mimic>", rd)
            offset = _number(mim, "offset", 0.0, f"{where} <mimic>", rd)
            reference = _number(mim, "reference", 0.0, f"{where} <mimic>", rd)
            mimic_terms = (multiplier, offset - multiplier * reference)
        init_el = _child(axis_el, "initial_position")
        if init_el is not None and (init_el.text or "").strip():
            initial = _floats(init_el.text, f"{where} <axis><initial_position>", (1,))[0]
    elif kind != "fixed":
        raise InputError(f"{where}: a {kind} joint needs an <axis>")
    lower = _limit(lim, "lower", -_NO_LIMIT, where, rd)
    upper = _limit(lim, "upper", _NO_LIMIT, where, rd)
    lower = -math.inf if lower <= -_NO_LIMIT else lower
    upper = math.inf if upper >= _NO_LIMIT else upper
    if kind in ("revolute", "prismatic") and lower > upper:
        raise InputError(f"{where}: lower limit {lower:g} is above the upper limit {upper:g}")
    effort = _limit(lim, "effort", -1.0, where, rd)
    velocity = _limit(lim, "velocity", -1.0, where, rd)
    stiffness = _number(dyn, "spring_stiffness", 0.0, where, rd)
    if stiffness != 0.0:
        key = "<spring_stiffness> (joint springs)"
        rd.unmodelled[key] = rd.unmodelled.get(key, 0) + 1
    rotor = gear = None
    for c in el:
        if _tag(c) == "drake:rotor_inertia":
            rotor = _floats(c.text, f"{where} <drake:rotor_inertia>", (1,))[0]
        elif _tag(c) == "drake:gear_ratio":
            gear = _floats(c.text, f"{where} <drake:gear_ratio>", (1,))[0]
    if (rotor is not None and rotor < 0) or (gear is not None and gear < 0):
        raise InputError(f"{where}: drake:rotor_inertia and drake:gear_ratio must be >= 0")
    damping, friction = _number(dyn, "damping", 0.0, where, rd), _number(dyn, "friction", 0.0, where, rd)
    if damping < 0 or friction < 0:
        raise InputError(f"{where}: damping and friction must be >= 0")
    kind = "fixed" if scope.static else kind
    rd.joints.append(_JointRaw(name, kind, (parent_el.text or "").strip(), child_raw, scope,
                               (xyz[0], xyz[1], xyz[2]), axis_in, lower, upper,
                               math.inf if effort < 0 else effort, math.inf if velocity < 0 else velocity,
                               damping, friction, rotor, gear, mimic, 0.0 if scope.static else initial,
                               mimic_terms))


# --------------------------------------------------------------------------- the pose graph
def _resolve_names(rd: _Reader) -> None:
    for node in rd.nodes.values():
        node.rel = node.scope.resolve(node.rel_raw, node.where) if node.rel_raw else node.default_rel
        if node.attached_raw:
            node.attached = (node.inner or node.scope).resolve(node.attached_raw, node.where)
        for ref in (node.rel, node.attached):
            if ref != _WORLD and ref not in rd.nodes:
                raise InputError(f"{node.where}: refers to {ref.split('::')[-1]!r}, which is no link, joint, frame or "
                                 "model here")


def _world_pose(rd: _Reader, name: str) -> np.ndarray:
    """X_W_name at q = 0, following ``rel`` up to the world (iteratively; a loop is refused)."""
    if name == _WORLD:
        return np.eye(4)
    path: list[str] = []
    seen: set[str] = set()
    cur = name
    while cur != _WORLD and cur not in rd.memo:
        if cur in seen:
            loop = " -> ".join([*path[path.index(cur):], cur])
            raise InputError(f"{rd.nodes[name].where}: the poses' relative_to frames form a loop ({loop})")
        seen.add(cur)
        node = rd.nodes[cur]
        if node.kind == "model" and node.placement_frame:
            rd.memo[cur] = _placed_model(rd, cur)
            break
        path.append(cur)
        cur = node.rel
    T = np.eye(4) if cur == _WORLD else rd.memo[cur]
    for n in reversed(path):
        T = T @ rd.nodes[n].X
        rd.memo[n] = T
    return rd.memo[name]


def _placed_model(rd: _Reader, name: str) -> np.ndarray:
    """A model whose ``<pose>`` gives the pose of its placement frame: X_W_M = X_W_rel · X · X_M_P⁻¹."""
    node = rd.nodes[name]
    assert node.inner is not None
    pf = node.inner.resolve(node.placement_frame or "", node.where)
    if pf not in rd.nodes:
        raise InputError(f"{node.where}: placement_frame {node.placement_frame!r} is no frame of the model")
    X_M_P, cur, seen = np.eye(4), pf, set()
    chain = []
    while cur != name:
        if cur == _WORLD or cur in seen:
            raise InputError(f"{node.where}: placement_frame {node.placement_frame!r} is not placed inside the model")
        seen.add(cur)
        chain.append(cur)
        cur = rd.nodes[cur].rel
    for n in reversed(chain):
        X_M_P = X_M_P @ rd.nodes[n].X
    return _world_pose(rd, node.rel) @ node.X @ np.linalg.inv(X_M_P)


def _attached_link(rd: _Reader, name: str, where: str) -> str | None:
    """The link a frame moves with (None: the world)."""
    seen: set[str] = set()
    cur = name
    while cur != _WORLD:
        node = rd.nodes[cur]
        if node.kind == "link":
            return cur
        if cur in seen:
            raise InputError(f"{where}: attached_to frames form a loop through {cur!r}")
        seen.add(cur)
        cur = node.attached
    return None


# --------------------------------------------------------------------------- geometry and inertia
def _inertial(rd: _Reader, link: str, el: ET.Element, scope: _Scope, X_W_L: np.ndarray) -> Inertial | None:
    where = f"{scope.file}: link {link!r} <inertial>"
    ine_el = _child(el, "inertial")
    if ine_el is None:
        return None
    if (ine_el.get("auto") or "").lower() in ("1", "true"):
        key = "<inertial auto='true'> (inertia computed from collisions; the written values are used)"
        rd.unmodelled[key] = rd.unmodelled.get(key, 0) + 1
    mass = _number(ine_el, "mass", 1.0, where, rd)
    if mass < 0:
        raise InputError(f"{where}: the mass must be >= 0, got {mass:g}")
    I_el = _child(ine_el, "inertia")
    values = [_number(I_el, k, d, where, rd) for k, d in (("ixx", 1.0), ("ixy", 0.0), ("ixz", 0.0), ("iyy", 1.0),
                                                     ("iyz", 0.0), ("izz", 1.0))]
    X, rel = _pose(ine_el, where, scope)
    if rel is not None and scope.resolve(rel, where) != link:
        # SDFormat has no relative_to on an inertial's pose (libsdformat: "not defined in SDF"; Gazebo
        # ignores it and reads the pose in the link frame, Drake refuses the file): the two readings differ
        raise InputError(f"{where} <pose relative_to={rel!r}>: SDFormat reads an inertial's pose in its link's "
                         "frame only (libsdformat does not define relative_to there: Gazebo ignores it, Drake "
                         "refuses the file); write the pose in the link's frame")
    if rel is not None:
        key = "relative_to on <inertial><pose> (not SDFormat's; it names the inertial's own link: no change)"
        rd.unmodelled[key] = rd.unmodelled.get(key, 0) + 1
    X_L_I = X
    I = Inertial(mass, inertia=(values[0], values[1], values[2], values[3], values[4], values[5])).matrix()
    if np.linalg.eigvalsh(I).min() < -1e-9 * max(1.0, float(np.abs(I).max())):
        raise InputError(f"{where}: the inertia tensor is not positive semi-definite")
    return Inertial.from_frame(mass, _pose_value(X_L_I), values)


def _in_link(rd: _Reader, X: np.ndarray, rel: str | None, scope: _Scope, X_W_L: np.ndarray, where: str) -> np.ndarray:
    """A link child's pose in the link frame (its ``relative_to`` frame, default the link)."""
    if rel is None:
        return X
    target = scope.resolve(rel, where)
    if target != _WORLD and target not in rd.nodes:
        raise InputError(f"{where}: relative_to {rel!r} is no frame here")
    return np.linalg.inv(X_W_L) @ (_world_pose(rd, target) if target != _WORLD else np.eye(4)) @ X


def _geometries(rd: _Reader, link: str, el: ET.Element, scope: _Scope, X_W_L: np.ndarray) -> list[Geometry]:
    out = []
    for role in ("visual", "collision"):
        for g_el in (c for c in el if _tag(c) == role):
            where = f"{scope.file}: link {link!r} <{role} name={g_el.get('name', '')!r}>"
            geo = _child(g_el, "geometry")
            shapes = [c for c in geo if isinstance(c.tag, str)] if geo is not None else []
            # a custom element (a prefixed name) is no shape of SDFormat's: libsdformat keeps it beside the shape
            shape = next((c for c in shapes if ":" not in _tag(c)), shapes[0] if shapes else None)
            if shape is None:
                continue
            kind = _tag(shape)
            X, rel = _pose(g_el, where, scope)
            placement = _pose_value(_in_link(rd, X, rel, scope, X_W_L, where))
            color = None
            mat = _child(g_el, "material") if role == "visual" else None
            diffuse = _child(mat, "diffuse") if mat is not None else None
            if diffuse is not None:
                rgba = _floats(diffuse.text, f"{where} <diffuse>", (3, 4))
                color = (rgba[0], rgba[1], rgba[2], rgba[3] if len(rgba) == 4 else 1.0)
            mesh: tuple[str, tuple[float, float, float]] | None = None
            if kind == "box":
                size_el = _child(shape, "size")
                size = tuple(_floats(size_el.text if size_el is not None else "1 1 1", f"{where} <box><size>", (3,)))
            elif kind in ("cylinder", "capsule"):
                size = (_number(shape, "radius", 1.0 if kind == "cylinder" else 0.5, where, rd),
                        _number(shape, "length", 1.0, where, rd))
            elif kind == "sphere":
                size = (_number(shape, "radius", 1.0, where, rd),)
            elif kind == "mesh":
                size, mesh = (), _mesh(rd, shape, scope, where)
                if mesh is None:
                    continue
            else:
                key = f"<{kind}> geometry (not drawn)"
                rd.unmodelled[key] = rd.unmodelled.get(key, 0) + 1
                continue
            out.append(Geometry(link, kind, placement, size, role == "collision", mesh[0] if mesh else None,
                                mesh[1] if mesh else (1.0, 1.0, 1.0), color))
    return out


def _mesh(rd: _Reader, shape: ET.Element, scope: _Scope, where: str) -> tuple[str, tuple[float, float, float]] | None:
    """(confined absolute path, scale) of a ``<mesh>``; None (counted in a note) when the file is not found."""
    uri_el = _child(shape, "uri")
    uri = (uri_el.text or "").strip() if uri_el is not None else ""
    scale_el = _child(shape, "scale")
    scale = _floats(scale_el.text, f"{where} <scale>", (3,)) if scale_el is not None else [1.0, 1.0, 1.0]
    rd.note_unmodelled(shape, "mesh")
    if _child(shape, "submesh") is not None:
        key = "<submesh> (the whole mesh is drawn)"
        rd.unmodelled[key] = rd.unmodelled.get(key, 0) + 1
    path = _resolve_uri(rd, uri, scope.file) if uri else None
    if path is not None:
        path = confine(path, rd.roots, scope.file, f"mesh {uri!r}", allow_outside=rd.allow_outside_meshes)
    if path is None or not path.exists():
        rd.missing_meshes.append(uri)
        if "<collision" in where:
            rd.missing_collision.append(where.split(": ", 1)[-1].split(" <")[0].replace("link ", ""))
        return None
    return str(path), (scale[0], scale[1], scale[2])


# --------------------------------------------------------------------------- the description
def description_from_sdf(path: str | os.PathLike[str], package_dirs: Sequence[str | os.PathLike[str]] | None = None,
                         allow_outside_meshes: bool = False,
                         reflected_inertia: bool = True) -> tuple[Description, list[str], dict[str, str]]:
    """Read an SDFormat file into a :class:`~robokit.description.model_builder.Description`.

    Parameters
    ----------
    path : str or Path
        A ``.sdf`` file with one ``<model>``, or a world file with one model.
    package_dirs : sequence of str or Path, optional
        Folders searched for ``model://`` and ``package://`` URIs (and allowed to be read from).
    allow_outside_meshes : bool
        Read meshes outside the file's folder, its package and ``package_dirs``.
    reflected_inertia : bool
        Add ``drake:rotor_inertia · drake:gear_ratio²`` to the joints' armature (default True).

    Returns
    -------
    description : Description
    notes : list of str
        What robokit did on the user's behalf or read without modelling, one line each.
    mimic : dict of str to str
        ``{joint: joint it mimics}`` (SDFormat 1.11 ``<mimic>``).

    Raises
    ------
    InputError
        One line naming the file and the element: a bound or confinement rule broken, an unknown
        frame, a ``relative_to`` loop, a joint kind robokit does not build (the module docstring).

    Examples
    --------
    >>> import pathlib, tempfile
    >>> with tempfile.TemporaryDirectory() as tmp:
    ...     p = pathlib.Path(tmp, "pendulum.sdf")
    ...     _ = p.write_text(_PENDULUM_SDF)
    ...     desc, notes, _ = description_from_sdf(p)
    >>> desc.joints[0].placement.translation, desc.joints[0].child_placement.translation
    ((0.0, 0.0, 0.0), (0.0, 0.0, -1.0))
    """
    desc, notes, mimic, _, _ = _read_sdf(path, package_dirs, allow_outside_meshes, reflected_inertia)
    return desc, notes, mimic


def _read_sdf(path: str | os.PathLike[str], package_dirs: Sequence[str | os.PathLike[str]] | None,
              allow_outside_meshes: bool, reflected_inertia: bool
              ) -> tuple[Description, list[str], dict[str, str], dict[str, float], dict[str, tuple[float, float]]]:
    """:func:`description_from_sdf`'s result, the joints' nonzero ``<axis><initial_position>`` and the mimic
    joints' (multiplier, offset − multiplier · reference)."""
    top = Path(path)
    rd = _Reader(top, tuple(Path(d).expanduser().resolve() for d in (package_dirs or ())), allow_outside_meshes,
                 allowed_roots(top, package_dirs))
    root = rd.read_root(top, "an SDFormat file")
    if _tag(root) != "sdf":
        raise InputError(f"{top}: root element <{_tag(root)}> is not <sdf>; an SDFormat file starts with <sdf>")
    version = _version(root, top)
    gravity_note = None
    model = _child(root, "model")
    inc = None
    if model is None:
        world = _child(root, "world")
        if world is None:
            raise InputError(f"{top}: no <model> or <world> in the file")
        models = [c for c in world if _tag(c) in ("model", "include")]
        if len(models) != 1:
            names = [c.get("name") or "".join(c.findtext("uri") or "") for c in models]
            raise InputError(f"{top}: world {world.get('name', '')!r} has {len(models)} models "
                             f"({', '.join(n.strip() for n in names[:8])}); robokit loads a world with one model")
        g = _child(world, "gravity")
        phys = _child(world, "physics")
        g = g if g is not None else (_child(phys, "gravity") if phys is not None else None)
        gv = _floats(g.text, f"{top}: <gravity>", (3,)) if g is not None else [0.0, 0.0, -9.8]
        rd.gravity = (gv[0], gv[1], gv[2])
        gravity_note = None if g is not None else f"{top}: world gravity is SDFormat's default, 0 0 -9.8 m/s²"
        for c in world:
            if _tag(c) not in ("model", "include", "gravity", "physics") and isinstance(c.tag, str):
                key = f"<{_tag(c)}> in <world>"
                rd.unmodelled[key] = rd.unmodelled.get(key, 0) + 1
        if _tag(models[0]) == "include":
            inc = models[0]
        else:
            model = models[0]
    world_scope = _Scope("", _WORLD, version, top)
    stack = (top.resolve(),)
    if inc is not None:
        _include(rd, inc, world_scope, 0, stack, top=True)
    else:
        assert model is not None
        name = _check_name(model.get("name"), f"{top}: <model>")
        _nested_model(rd, model, world_scope, name, None, None, version, False, False, 0, stack, top, top=True)
    top_node = rd.nodes["__model__"]
    assert top_node.inner is not None
    top_name = rd.model_name
    static_top = top_node.inner.static
    if static_top:
        raise InputError(f"{top}: <static>true</static>: a static model does not move; robokit loads robots with "
                         "moving joints")
    _resolve_names(rd)
    desc, notes, mimic = _describe(rd, top_name, reflected_inertia, gravity_note)
    return (desc, notes, mimic, {j.name: j.initial for j in rd.joints if j.initial != 0.0},
            {j.name: j.mimic_terms for j in rd.joints if j.name in mimic})


def _describe(rd: _Reader, name: str, reflected_inertia: bool,
              gravity_note: str | None) -> tuple[Description, list[str], dict[str, str]]:
    from robokit.description.limits import MAX_JOINTS

    if len(rd.links) > MAX_JOINTS + 1 or len(rd.frames) > 8 * MAX_JOINTS:
        raise InputError(f"{rd.top}: {len(rd.links)} links and {len(rd.frames)} frames; robokit reads robots of at "
                         f"most {MAX_JOINTS} joints ({MAX_JOINTS + 1} links, {8 * MAX_JOINTS} frames)")
    notes: list[str] = []
    if gravity_note:
        notes.append(gravity_note)
    links, geoms = [], []
    no_inertial = []
    X_W = {ln: _world_pose(rd, ln) for ln in rd.links}
    for ln, (el, scope) in rd.links.items():
        inertial = _inertial(rd, ln, el, scope, X_W[ln])
        if inertial is None and ln not in rd.world_fixed:
            no_inertial.append(ln)
            inertial = Inertial(1.0, (0.0, 0.0, 0.0), (1.0, 0.0, 0.0, 1.0, 0.0, 1.0))
        links.append(Link(ln, inertial))
        geoms.extend(_geometries(rd, ln, el, scope, X_W[ln]))
    if no_inertial:
        notes.append(f"{rd.top}: links without <inertial> get SDFormat's default, 1 kg and 1 kg·m² about each axis "
                     f"(as libsdformat): {', '.join(no_inertial[:10])}")
    joints, mimic = [], {}
    armatures, reflected_notes = drake_reflected_inertia(
        [DrakeRotor(j.name, j.kind, j.effort, j.rotor, j.gear) for j in rd.joints
         if j.rotor is not None or j.gear is not None], reflected_inertia, rd.top)
    for j in rd.joints:
        where = f"{j.scope.file}: joint {j.name!r}"
        parent_name = j.scope.resolve(j.parent_raw, where)
        if parent_name != _WORLD and parent_name not in rd.nodes:
            raise InputError(f"{where}: parent {j.parent_raw!r} is no link or frame here")
        parent = _attached_link(rd, parent_name, where)
        child_name = j.scope.resolve(j.child_raw, where)
        if child_name == _WORLD:
            raise InputError(f"{where}: the child is the world; robokit reads joints whose child is a link")
        child = _attached_link(rd, child_name, where)
        if child is None:
            raise InputError(f"{where}: the child {j.child_raw!r} is fixed to the world")
        if parent == child:
            raise InputError(f"{where}: parent and child are the same link {child!r}")
        X_W_J = _world_pose(rd, j.name)
        X_W_P = X_W[parent] if parent is not None else np.eye(4)
        axis = np.asarray(j.axis, dtype=float)
        if j.axis_in is not None:
            frame = j.scope.resolve(j.axis_in, where)
            if frame != _WORLD and frame not in rd.nodes:
                raise InputError(f"{where}: <xyz expressed_in={j.axis_in!r}>: no such frame")
            R_W_E = (_world_pose(rd, frame) if frame != _WORLD else np.eye(4))[:3, :3]
            axis = X_W_J[:3, :3].T @ R_W_E @ axis
        if j.mimic:
            mimic[j.name] = j.scope.resolve(j.mimic, where)
        joints.append(Joint(j.name, j.kind, parent, child, _pose_value(np.linalg.inv(X_W_P) @ X_W_J),
                            _pose_value(np.linalg.inv(X_W_J) @ X_W[child]),
                            (float(axis[0]), float(axis[1]), float(axis[2])),
                            j.lower, j.upper, j.velocity, j.effort, j.damping, j.friction,
                            armatures.get(j.name, 0.0)))
    notes.extend(reflected_notes)
    children = {j.child for j in joints}
    roots = [ln for ln in rd.links if ln not in children]
    free = [r for r in roots if r not in rd.world_fixed]
    if free:
        notes.append(f"{rd.top}: {', '.join(free[:10])} fixed to the world where the file places "
                     f"{'it' if len(free) == 1 else 'them'} (robokit's robots are fixed-base; SDFormat leaves a "
                     "link without a joint to the world free)")
    frames = []
    for fname in rd.frames:
        where = rd.nodes[fname].where
        link = _attached_link(rd, fname, where)
        X_W_L = X_W[link] if link is not None else np.eye(4)
        frames.append(FrameSpec(fname, link, _pose_value(np.linalg.inv(X_W_L) @ _world_pose(rd, fname))))
    if rd.unmodelled:
        shown = ", ".join(f"{k}" + (f" ×{n}" if n > 1 else "") for k, n in sorted(rd.unmodelled.items()))
        notes.append(f"{rd.top}: read but not modelled: {shown}")
    if rd.leading:
        shown = ", ".join(rd.leading[:6]) + (f" and {len(rd.leading) - 6} more" if len(rd.leading) > 6 else "")
        notes.append(f"{rd.top}: numbers read as libsdformat reads them, the number a text starts with and "
                     f"nothing after it: {shown}")
    if rd.missing_meshes:
        shown = ", ".join(rd.missing_meshes[:4]) + (", ..." if len(rd.missing_meshes) > 4 else "")
        lost = ""
        if rd.missing_collision:
            lost = (f"; collision checks go without {len(rd.missing_collision)} of them (links "
                    f"{', '.join(dict.fromkeys(rd.missing_collision))} are checked without those shapes)")
        notes.append(f"{rd.top}: {len(rd.missing_meshes)} mesh file(s) not found, drawn without them "
                     f"(give their folder with package_dirs / --package-path){lost}: {shown}")
    desc = Description(name, tuple(links), tuple(joints), tuple(frames), tuple(geoms),
                       tuple((r, _pose_value(X_W[r])) for r in roots), rd.gravity)
    return desc, notes, mimic


def load_sdf(path: str | os.PathLike[str], tip: str | None = None, *,
             package_dirs: Sequence[str | os.PathLike[str]] | None = None, allow_outside_meshes: bool = False,
             reflected_inertia: bool = True) -> Robot:
    """Load an SDFormat file as a :class:`~robokit.description.robot.Robot` (see the module docstring).

    Parameters
    ----------
    path : str or Path
        A ``.sdf`` (or ``.world``) file.
    tip : str, optional
        The chain's tip frame (default: the end of the longest chain,
        :func:`~robokit.description.builder.choose_tip`).
    package_dirs : sequence of str or Path, optional
        Folders searched for ``model://`` and ``package://`` URIs.
    allow_outside_meshes : bool
        Read meshes outside the file's folder, its package and ``package_dirs``.
    reflected_inertia : bool
        Model Drake's ``rotor_inertia · gear_ratio²`` as the joints' armature (default True).

    Returns
    -------
    Robot
        With ``robot.spec == RobotSpec("sdf", path=<absolute path>, ...)``.

    Raises
    ------
    InputError
        A missing file, anything :func:`description_from_sdf` refuses, no moving joint on the chain
        to the tip.

    Examples
    --------
    >>> import pathlib, tempfile, warnings
    >>> with tempfile.TemporaryDirectory() as tmp:
    ...     p = pathlib.Path(tmp, "pendulum.sdf")
    ...     _ = p.write_text(_PENDULUM_SDF)
    ...     with warnings.catch_warnings():
    ...         warnings.simplefilter("ignore")
    ...         robot = load_sdf(p)
    >>> robot.n, (robot.frame_pose([np.pi / 2])[:3, 3].round(6) + 0.0).tolist()   # the bob swings up to +y
    (1, [0.0, 1.0, 0.0])
    """
    path = Path(path)
    if not path.exists():
        raise InputError(f"{path}: file not found")
    desc, notes, mimic, initial, mimic_terms = _read_sdf(path, package_dirs, allow_outside_meshes, reflected_inertia)
    model, visual, collision, geo_notes = build_model(desc)
    from robokit.description.urdf_files import absolute_dirs

    spec = RobotSpec("sdf", path=os.path.abspath(path), tip=tip, package_dirs=absolute_dirs(package_dirs),
                     allow_outside_meshes=bool(allow_outside_meshes), reflected_inertia=bool(reflected_inertia))
    return build_robot(desc.name, model, tip, [visual, collision], {}, spec, [*notes, *geo_notes], mimic=mimic,
                       joint_values={"initial": initial} if initial else None, mimic_terms=mimic_terms)
