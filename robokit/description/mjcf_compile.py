r"""MJCF read with MuJoCo's compiler rules: :func:`compile_mjcf` gives one record per body.

robokit does not call MuJoCo to read a model: it applies the rules of MuJoCo's compiler, as the
MJCF reference documents them, to the file itself, and tests the result against MuJoCo.
What decides a number, and is therefore computed here as MuJoCo computes it:

* ``<compiler>``: ``angle`` (degrees unless ``radian``; euler, axisangle, hinge ranges,
  ``ref``/``springref``), ``eulerseq``, ``autolimits``, ``inertiafromgeom`` (``true``: every
  body's inertia from its geoms, ``auto``: bodies without ``<inertial>``, ``false``: never),
  ``inertiagrouprange``, ``boundmass``, ``boundinertia``, ``balanceinertia``, ``settotalmass``,
  ``fusestatic``, ``fitaabb``, ``meshdir``/``assetdir``, ``strippath``;
* default classes: ``<default class>`` nesting, ``class`` and ``childclass`` (on bodies and
  frames) for joints, geoms, sites and meshes;
* poses everywhere: ``pos`` with ``quat``, ``axisangle``, ``euler``, ``xyaxes`` or ``zaxis``;
  ``<frame>`` (nested, with ``childclass``); geom and site ``fromto``;
* geoms: ``sphere``, ``capsule``, ``cylinder``, ``ellipsoid``, ``box`` and ``mesh`` (meshes by
  MuJoCo's union-of-pyramids rule, ``legacy``/``exact``/``convex``/``shell``), ``density``,
  ``mass``, ``shellinertia``, a primitive fitted to a mesh (``type`` with ``mesh``,
  ``fitscale``); the body inertia as MuJoCo sums it (centre of mass, parallel axes, principal
  axes by MuJoCo's own Jacobi iteration), including MuJoCo's rule that a body with no mass
  source keeps its inertial frame at the body's ``pos``/``quat``;
* joints: ``hinge``, ``slide``, ``ball``, ``free`` (several per body, composed in order about
  their ``pos``), ``axis``, ``range``/``limited``, ``ref`` (the zero of the joint), ``armature``,
  ``damping``; ``<option gravity>`` and ``<flag gravity="disable">``.

What MuJoCo's compiler refuses is refused (:class:`robokit.errors.InputError`, one line naming the file and
the element): what its schema does not know (:mod:`robokit.description._mjcf_schema`), repeated names and
references to undefined objects, more than 6 degrees of freedom or a rotation after a ball joint in one
body, a moving body without mass or inertia, sizes that are not positive, planes on moving bodies, mocap
bodies that are not jointless children of the world, keyframes of the wrong sizes, and bad keywords.

The result, :class:`CompiledMjcf`, holds every body of the file (the world first), each with
its placement in its parent, joints, inertial (as MuJoCo's ``body_mass``, ``body_ipos``,
``body_iquat``, ``body_inertia``), geoms and sites. Bodies without a name are named from their
parent and their place among its child bodies (``wrist/body1``); joints, geoms and sites
likewise (``wrist/joint0``). :func:`robokit.description.mjcf.load_mjcf` builds the robot from it.
"""
from __future__ import annotations

import math
import os
import xml.etree.ElementTree as ET
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Iterator, Sequence

import numpy as np

from robokit.description import _mjcf_math as mm
from robokit.description._mjcf_schema import check_names, check_references, check_schema
from robokit.errors import InputError

__all__ = ["MjcfJoint", "MjcfGeom", "MjcfSite", "MjcfBody", "CompiledMjcf", "compile_mjcf"]

_NAN = float("nan")
_ORIENT = ("axisangle", "xyaxes", "zaxis", "euler")
_ORIENT_N = {"axisangle": 4, "xyaxes": 6, "zaxis": 3, "euler": 3}
_GEOM_TYPES = ("plane", "hfield", "sphere", "capsule", "ellipsoid", "cylinder", "box", "mesh", "sdf")
_JOINT_TYPES = ("free", "ball", "slide", "hinge")
_DEFAULTED = ("joint", "geom", "site", "mesh")
#: body-name attributes of elements that keep a body from being fused (``fusestatic``)
_BODY_REFS = ("body", "body1", "body2", "objname", "target", "refname")


@dataclass(frozen=True)
class MjcfJoint:
    """One MJCF joint, compiled.

    Attributes
    ----------
    name : str
        Its name (``<body>/joint<k>`` when the file gives none).
    type : str
        ``"hinge"``, ``"slide"``, ``"ball"`` or ``"free"``.
    pos, axis : numpy.ndarray, shape (3,)
        Anchor and unit axis in the body frame (m).
    limited : bool
        Whether ``range`` limits it.
    range : numpy.ndarray, shape (2,)
        Limits, rad (hinge) or m (slide).
    ref, springref : float
        The joint value at which the body sits as written, and the spring's rest value.
    armature, damping, stiffness, frictionloss : float
        As written (kg·m² or kg, N·m·s/rad or N·s/m, ...).
    named : bool
        Whether the file names it.
    effort : float
        ``e`` of a limited, symmetric ``actuatorfrcrange="-e e"`` (N·m or N): what MuJoCo clamps the
        total actuator force on the joint to, a URDF's effort limit as MuJoCo's URDF reader writes
        it; inf when the force is not limited (an asymmetric range is noted, not read).
    """

    name: str
    type: str
    pos: np.ndarray
    axis: np.ndarray
    limited: bool
    range: np.ndarray
    ref: float = 0.0
    springref: float = 0.0
    armature: float = 0.0
    damping: float = 0.0
    stiffness: float = 0.0
    frictionloss: float = 0.0
    named: bool = True
    effort: float = math.inf


@dataclass(frozen=True)
class MjcfGeom:
    """One MJCF geom, compiled (MuJoCo's ``geom_*`` fields).

    Attributes
    ----------
    name : str
        Its name (``<body>/geom<k>`` when unnamed).
    type : str
        One of ``plane hfield sphere capsule ellipsoid cylinder box mesh sdf``.
    size : numpy.ndarray, shape (3,)
        MuJoCo's sizes (radii, half lengths), m.
    pos : numpy.ndarray, shape (3,)
        Position in the body frame (for a mesh, its centre of mass), m.
    quat : numpy.ndarray, shape (4,)
        Orientation (w, x, y, z) in the body frame (for a mesh, its principal axes).
    contype, conaffinity, group : int
        Collision bit masks and group.
    mass : float
        Its mass as the compiler computed it (0 when the body's inertia does not come from geoms), kg.
    rgba : numpy.ndarray, shape (4,)
        Colour.
    mesh : str or None
        The mesh asset's name for a mesh geom.
    vertices, faces : numpy.ndarray or None
        A mesh geom's vertices (in this geom frame, m) and triangles.
    mesh_file : str or None
        The mesh file, for viewers.
    mesh_file_pose : numpy.ndarray, shape (4, 4), or None
        Where the file's coordinates, times ``mesh_scale``, sit in this geom frame (None when no
        rigid motion and scale express it).
    mesh_scale : numpy.ndarray, shape (3,)
        The mesh asset's scale.
    """

    name: str
    type: str
    size: np.ndarray
    pos: np.ndarray
    quat: np.ndarray
    contype: int = 1
    conaffinity: int = 1
    group: int = 0
    mass: float = 0.0
    rgba: np.ndarray = field(default_factory=lambda: np.array([0.5, 0.5, 0.5, 1.0]))
    mesh: str | None = None
    vertices: np.ndarray | None = None
    faces: np.ndarray | None = None
    mesh_file: str | None = None
    mesh_file_pose: np.ndarray | None = None
    mesh_scale: np.ndarray = field(default_factory=lambda: np.ones(3))


@dataclass(frozen=True)
class MjcfSite:
    """One MJCF site: a named frame on a body.

    Attributes
    ----------
    name : str
        Its name (``<body>/site<k>`` when unnamed).
    pos : numpy.ndarray, shape (3,)
        Position in the body frame, m.
    quat : numpy.ndarray, shape (4,)
        Orientation (w, x, y, z) in the body frame.
    """

    name: str
    pos: np.ndarray
    quat: np.ndarray


@dataclass(frozen=True)
class MjcfBody:
    """One body of an MJCF model, compiled as MuJoCo's compiler does.

    Attributes
    ----------
    name : str
        Its name; ``<parent>/body<k>`` (k its place among the parent's child bodies) when unnamed.
    parent : int
        Index of the parent body in :attr:`CompiledMjcf.bodies` (-1 for the world).
    pos : numpy.ndarray, shape (3,)
        Body frame origin in the parent's body frame, m (frames applied).
    quat : numpy.ndarray, shape (4,)
        Body frame orientation (w, x, y, z) in the parent's.
    joints : tuple of MjcfJoint
        Its joints, in the order MuJoCo composes them.
    mass : float
        kg (MuJoCo's ``body_mass``).
    ipos, iquat, inertia : numpy.ndarray
        Centre of mass (3,) and principal frame (4,) in the body frame, principal moments (3,)
        about the centre of mass, kg·m² (``body_ipos``, ``body_iquat``, ``body_inertia``).
    geoms : tuple of MjcfGeom
    sites : tuple of MjcfSite
    named : bool
        Whether the file names it.
    mocap : bool
        A mocap body.
    """

    name: str
    parent: int
    pos: np.ndarray
    quat: np.ndarray
    joints: tuple[MjcfJoint, ...]
    mass: float
    ipos: np.ndarray
    iquat: np.ndarray
    inertia: np.ndarray
    geoms: tuple[MjcfGeom, ...] = ()
    sites: tuple[MjcfSite, ...] = ()
    named: bool = True
    mocap: bool = False

    @property
    def inertia_matrix(self) -> np.ndarray:
        """The 3×3 inertia about the centre of mass, body axes (kg·m²)."""
        return np.array(mm.six_to_matrix(mm.rotated_inertia(tuple(self.inertia), tuple(self.iquat)))).reshape(3, 3)


@dataclass(frozen=True)
class CompiledMjcf:
    """An MJCF file compiled by MuJoCo's rules (see the module docstring).

    Attributes
    ----------
    name : str
        ``<mujoco model>`` (or the file's stem).
    path : str
        The file.
    bodies : tuple of MjcfBody
        Every body, the world first, parents before children (MuJoCo's order).
    gravity : numpy.ndarray, shape (3,)
        m/s² (zero when ``<flag gravity="disable">``).
    compiler : dict
        The compiler settings in force.
    excluded : tuple of (str, str)
        ``<contact><exclude body1 body2>`` pairs.
    notes : tuple of str
        What was read but is not modelled.
    """

    name: str
    path: str
    bodies: tuple[MjcfBody, ...]
    gravity: np.ndarray
    compiler: dict
    excluded: tuple[tuple[str, str], ...] = ()
    notes: tuple[str, ...] = ()

    def subtree(self, index: int) -> list[int]:
        """Indices of body ``index`` and all its descendants, in order.

        Parameters
        ----------
        index : int
            A body index.

        Returns
        -------
        list of int
        """
        out, keep = [], {index}
        for i, b in enumerate(self.bodies):
            if i == index or b.parent in keep:
                keep.add(i)
                out.append(i)
        return out


# --------------------------------------------------------------------------- attribute reading
#: Why a joint attribute robokit reads is not in its model (one note per attribute, :class:`_Ctx`).
_JOINT_EXTRAS_WHY = {
    "frictionloss": "robokit's rigid-body dynamics has no joint friction (MuJoCo applies it through its "
                    "constraint solver); the values stay in robot.model.friction, as a URDF's <dynamics friction>",
    "stiffness": "robokit's rigid-body dynamics has no joint springs (a passive force in MuJoCo, not part of its "
                 "bias force or mass matrix)",
    "springdamper": "its spring and damper follow from the compiled inertia, and robokit's rigid-body dynamics "
                    "has no passive forces",
    "actuatorfrcrange": "an asymmetric range: robokit's effort limit is one bound ±e (a range -e e is read as it)",
}


class _Ctx:
    def __init__(self, path: Path, root: ET.Element) -> None:
        self.path = path
        self.root = root
        self.compiler: dict[str, Any] = {
            "angle": "degree", "eulerseq": "xyz", "autolimits": True, "inertiafromgeom": "auto",
            "inertiagrouprange": (0, 5), "boundmass": 0.0, "boundinertia": 0.0, "balanceinertia": False,
            "settotalmass": -1.0, "fusestatic": False, "fitaabb": False, "meshdir": "", "texturedir": "",
            "strippath": False, "discardvisual": False, "alignfree": False,
        }
        self.notes: list[str] = []
        #: joint attributes read but not modelled: attribute → [(joint, value as written)], one note each
        self.joint_extras: dict[str, list[tuple[str, str]]] = {}
        self.defaults: dict[str, dict[str, dict[str, str]]] = {}
        self.meshes: dict[str, dict[str, str]] = {}
        self.mesh_cache: dict[str, Any] = {}
        self.names: dict[str, set[str]] = {}  # every object's name, by kind (check_names)

    def check_refs(self, elem: ET.Element, name: str, attrs: dict[str, str], refs: dict[str, str]) -> None:
        """Refuse an attribute (own or from a default class) naming an asset the file lacks, as MuJoCo does."""
        for key, kind in refs.items():
            value = attrs.get(key)
            if value and value not in self.names.get(kind, set()):
                raise InputError(f"{self.where(elem, name)} {key}={value!r}: no {kind} named {value!r} (MuJoCo refuses "
                                 "the file)")

    @property
    def degree(self) -> bool:
        return self.compiler["angle"] != "radian"

    def where(self, elem: ET.Element | None = None, name: str | None = None) -> str:
        tag = "" if elem is None else f" <{elem.tag}{f' name={name!r}' if name else ''}>"
        return f"{self.path}:{tag}"


def _numbers(ctx: _Ctx, attrs: dict[str, str], key: str, n: int | None, elem: ET.Element,
             exact: bool = True) -> list[float] | None:
    text = attrs.get(key)
    if text is None:
        return None
    try:
        vals = [float(t) for t in text.split()]
    except ValueError:
        raise InputError(f"{ctx.where(elem, attrs.get('name'))} attribute {key}={text!r}: expected numbers") from None
    if n is not None and ((exact and len(vals) != n) or len(vals) > n or not vals):
        raise InputError(f"{ctx.where(elem, attrs.get('name'))} attribute {key}={text!r}: expected "
                         f"{n if exact else f'1 to {n}'} numbers, got {len(vals)}")
    if not all(math.isfinite(v) for v in vals):
        raise InputError(f"{ctx.where(elem, attrs.get('name'))} attribute {key}={text!r}: not finite")
    return vals


def _flag(ctx: _Ctx, attrs: dict[str, str], key: str, default: bool, elem: ET.Element) -> bool:
    v = attrs.get(key)
    if v is None:
        return default
    if v not in ("true", "false"):
        raise InputError(f"{ctx.where(elem, attrs.get('name'))} attribute {key}={v!r}: expected true or false")
    return v == "true"


def _int(ctx: _Ctx, attrs: dict[str, str], key: str, default: int, elem: ET.Element) -> int:
    v = attrs.get(key)
    if v is None:
        return default
    try:
        return int(v)
    except ValueError:
        raise InputError(f"{ctx.where(elem, attrs.get('name'))} attribute {key}={v!r}: expected an integer") from None


def _read_compiler(ctx: _Ctx) -> None:
    c = ctx.compiler
    for comp in ctx.root.iter("compiler"):
        a = comp.attrib
        if a.get("coordinate") == "global":
            raise InputError(f"{ctx.path}: <compiler coordinate='global'>: global coordinates are no longer read by "
                             "MuJoCo (since 2.3.3); convert the model first")
        if "angle" in a:
            if a["angle"] not in ("degree", "radian"):
                raise InputError(f"{ctx.path}: <compiler angle={a['angle']!r}>: expected degree or radian")
            c["angle"] = a["angle"]
        if "eulerseq" in a:
            seq = a["eulerseq"]
            if len(seq) != 3:  # the letters are checked where an euler angle is read, as MuJoCo does
                raise InputError(f"{ctx.path}: <compiler eulerseq={seq!r}>: must have exactly 3 characters")
            c["eulerseq"] = seq
        if "inertiafromgeom" in a:
            if a["inertiafromgeom"] not in ("true", "false", "auto"):
                raise InputError(f"{ctx.path}: <compiler inertiafromgeom={a['inertiafromgeom']!r}>: expected true, "
                                 "false or auto")
            c["inertiafromgeom"] = a["inertiafromgeom"]
        for key in ("autolimits", "balanceinertia", "fusestatic", "fitaabb", "strippath", "discardvisual",
                    "alignfree"):
            c[key] = _flag(ctx, dict(a), key, c[key], comp)
        for key in ("boundmass", "boundinertia", "settotalmass"):
            v = _numbers(ctx, dict(a), key, 1, comp)
            if v is not None:
                c[key] = v[0]
        g = _numbers(ctx, dict(a), "inertiagrouprange", 2, comp)
        if g is not None:
            c["inertiagrouprange"] = (int(g[0]), int(g[1]))
        if "assetdir" in a:
            c["meshdir"] = c["texturedir"] = a["assetdir"]
        for key in ("meshdir", "texturedir"):
            if key in a:
                c[key] = a[key]


def _read_defaults(ctx: _Ctx) -> None:
    out = ctx.defaults

    def merge(parent: dict[str, str], own: dict[str, str]) -> dict[str, str]:
        attrs = dict(parent)
        for k, v in own.items():
            if k == "size" and "size" in parent:  # a partial size overrides the first entries only
                old, new = parent["size"].split(), v.split()
                v = " ".join(new + old[len(new):])
            attrs[k] = v
        return attrs

    def walk(elem: ET.Element, inherited: dict[str, dict[str, str]], top: bool) -> None:
        name = elem.get("class", "main")
        if top and name != "main":
            raise InputError(f"{ctx.path}: the top <default> is class 'main', not {name!r}")
        if not top and "class" not in elem.attrib:
            raise InputError(f"{ctx.path}: a nested <default> needs a class name")
        if name in out and not top:
            raise InputError(f"{ctx.path}: <default class={name!r}> defined twice")
        mine = {tag: dict(inherited.get(tag, {})) for tag in _DEFAULTED}
        for child in elem:
            if child.tag in _DEFAULTED:
                mine[child.tag] = merge(mine[child.tag], dict(child.attrib))
        if top and name in out:
            for tag in _DEFAULTED:
                out[name][tag].update(mine[tag])
        else:
            out[name] = mine
        for child in elem.findall("default"):
            walk(child, mine, False)

    for top in ctx.root.findall("default"):
        walk(top, {}, True)
    out.setdefault("main", {tag: {} for tag in _DEFAULTED})


def _attrs(ctx: _Ctx, elem: ET.Element, childclass: str) -> tuple[dict[str, str], dict[str, str]]:
    """(merged attributes, the class defaults alone) of a joint/geom/site/mesh element."""
    cls = elem.get("class", childclass)
    if cls not in ctx.defaults:
        raise InputError(f"{ctx.where(elem, elem.get('name'))} class={cls!r}: no <default class={cls!r}>")
    dflt = ctx.defaults[cls].get(elem.tag, {})
    out = dict(dflt)
    for k, v in elem.attrib.items():
        if k == "size" and "size" in dflt:
            old, new = dflt["size"].split(), v.split()
            v = " ".join(new + old[len(new):])
        out[k] = v
    return out, dflt


def _orientation(ctx: _Ctx, elem: ET.Element, attrs: dict[str, str], dflt: dict[str, str]) -> mm.Quat:
    """The element's orientation: its own ``quat`` or alternative (axisangle, xyaxes, zaxis,
    euler) if it has one, else its class's, else the identity (MuJoCo 4's rule)."""
    own = [k for k in _ORIENT + ("quat",) if k in elem.attrib]
    if len(own) > 1:
        raise InputError(f"{ctx.where(elem, attrs.get('name'))}: multiple orientation specifiers are not allowed")
    source = own or [k for k in _ORIENT + ("quat",) if k in dflt][-1:]
    if not source:
        return mm.IDENTITY
    kind = source[0]
    if kind == "quat":
        q = _numbers(ctx, attrs, "quat", 4, elem)
        assert q is not None
        quat = mm.unit_quat(q)
    else:
        vals = _numbers(ctx, attrs, kind, _ORIENT_N[kind], elem)
        assert vals is not None
        res = mm.orientation(kind, vals, ctx.degree, ctx.compiler["eulerseq"])
        if isinstance(res, str):
            raise InputError(f"{ctx.where(elem, attrs.get('name'))}: {kind}: {res}")
        quat = res
    if quat == (0.0, 0.0, 0.0, 0.0):
        raise InputError(f"{ctx.where(elem, attrs.get('name'))}: quat is zero")
    return quat


def _vec3(v: Sequence[float] | None, default: Sequence[float] = (0.0, 0.0, 0.0)) -> mm.Vec:
    x = v if v is not None else default
    return (float(x[0]), float(x[1]), float(x[2]))


# --------------------------------------------------------------------------- meshes
def _mesh_file(ctx: _Ctx, file: str) -> Path:
    from robokit.description.meshes import allowed_roots, confine

    if ctx.compiler["strippath"]:
        file = os.path.basename(file)
    top = ctx.path.resolve().parent
    base = top / ctx.compiler["meshdir"] if ctx.compiler["meshdir"] else top
    return confine(base / file, allowed_roots(ctx.path, ctx.compiler.get("package_dirs")), ctx.path, f"<mesh file={file!r}>",
                   allow_outside=ctx.compiler.get("allow_outside_meshes", False))


def _read_assets(ctx: _Ctx) -> None:
    for asset in ctx.root.findall("asset"):
        for m in asset.findall("mesh"):
            attrs, _ = _attrs(ctx, m, "main")
            name = attrs.get("name")
            if name is None:
                f = attrs.get("file")
                if f is None:
                    raise InputError(f"{ctx.where(m)}: a mesh needs a name or a file")
                name = os.path.splitext(os.path.basename(f))[0]
            if name in ctx.meshes:
                raise InputError(f"{ctx.where(m, name)}: repeated mesh name")
            attrs["__elem__"] = ""  # marker
            ctx.meshes[name] = attrs


#: The attributes of an asset that name a file MuJoCo opens, and the compiler folder it is in.
_ASSET_FILES = {"mesh": (("file",), "meshdir"), "skin": (("file",), "meshdir"),
                "hfield": (("file",), "meshdir"),
                "texture": (("file", "fileright", "fileleft", "fileup", "filedown", "filefront", "fileback"),
                            "texturedir")}


def _check_asset_files(ctx: _Ctx) -> None:
    """Refuse an asset whose file does not exist, used or not: MuJoCo's compiler opens every asset's file
    (an unused ``<mesh>`` or ``<texture>`` whose file is missing fails its compile). Folders as MuJoCo
    4.0.1 takes them, measured: ``meshdir`` for meshes, skins and height fields, ``texturedir`` for
    textures."""
    top = ctx.path.resolve().parent
    for asset in ctx.root.findall("asset") + ctx.root.findall("deformable"):  # a <skin> is in <deformable>
        for el in asset:
            if el.tag not in _ASSET_FILES:
                continue
            keys, folder = _ASSET_FILES[el.tag]
            for key in keys:
                file = el.get(key)
                if not file:
                    continue
                shown = os.path.basename(file) if ctx.compiler["strippath"] else file
                base = top / ctx.compiler[folder] if ctx.compiler[folder] else top
                if not (base / shown).exists():
                    raise InputError(f"{ctx.where(el, el.get('name'))} {key}={file!r}: {base / shown}: file not found "
                                     "(MuJoCo opens every asset's file, used or not)")


def _mesh(ctx: _Ctx, name: str, elem: ET.Element, needed: bool) -> tuple[Any, dict[str, str]]:
    """(mesh inertia, file, scale, refpos, refquat, vertices, faces) of a mesh asset; the
    inertia is None when MuJoCo could not compute it and no number needs it (an ASCII STL
    drawn by a viewer)."""
    from robokit.description._mjcf_mesh import mesh_inertia, read_ascii_stl, read_mesh_file

    if name not in ctx.meshes:
        raise InputError(f"{ctx.where(elem, elem.get('name'))} mesh={name!r}: no such mesh asset")
    a = ctx.meshes[name]
    if name in ctx.mesh_cache and (ctx.mesh_cache[name][0] is not None or not needed):
        return ctx.mesh_cache[name], a
    fake = ET.Element("mesh", {k: v for k, v in a.items() if not k.startswith("__")})
    mode = a.get("inertia", "legacy")
    if mode not in ("legacy", "exact", "convex", "shell"):
        raise InputError(f"{ctx.where(fake, name)} inertia={mode!r}: expected convex, exact, legacy or shell")
    scale = _numbers(ctx, a, "scale", 3, fake) or [1.0, 1.0, 1.0]
    refpos = _numbers(ctx, a, "refpos", 3, fake) or [0.0, 0.0, 0.0]
    refquat = _numbers(ctx, a, "refquat", 4, fake) or [1.0, 0.0, 0.0, 0.0]
    file = a.get("file")
    msh = False
    path = None
    if file is not None:
        path = _mesh_file(ctx, file)
        where = f"{ctx.path}: mesh {name!r} ({path})"
        try:
            verts, faces = read_mesh_file(path)
        except InputError:
            if needed or path.suffix.lower() != ".stl":
                raise
            verts, faces = read_ascii_stl(path)
            ctx.notes.append(f"{where}: an ASCII STL, which MuJoCo does not read; drawn and collided only")
            out = (None, path, scale, refpos, refquat, verts * np.asarray(scale), faces)
            ctx.mesh_cache[name] = out
            return out, a
        msh = path.suffix.lower() == ".msh"
    else:
        vals = _numbers(ctx, a, "vertex", None, fake)
        if not vals or len(vals) % 3:
            raise InputError(f"{ctx.where(fake, name)}: vertex needs 3 numbers per vertex")
        verts = np.array(vals).reshape(-1, 3)
        fv = _numbers(ctx, a, "face", None, fake)
        faces = np.zeros((0, 3), dtype=np.int64) if not fv else np.array(fv, dtype=np.int64).reshape(-1, 3)
        where = f"{ctx.path}: mesh {name!r}"
    if int(a.get("maxhullvert", "-1")) > -1 and (mode == "convex" or len(faces) == 0):
        raise InputError(f"{where}: maxhullvert (a partial convex hull) is not computed by robokit; remove it")
    info = mesh_inertia(verts, faces, scale=scale, refpos=refpos, refquat=refquat, inertia=mode, where=where, msh=msh)
    ctx.mesh_cache[name] = (info, path, scale, refpos, refquat, info.vertices, info.faces)
    return ctx.mesh_cache[name], a


# --------------------------------------------------------------------------- geoms
def _geom_volume(gtype: str, size: Sequence[float], shell: bool) -> float:
    r, h = size[0], 2 * size[1]
    if gtype == "sphere":
        return 4 * math.pi * r * r if shell else 4 * math.pi * r ** 3 / 3
    if gtype == "capsule":
        return 4 * math.pi * r * r + 2 * math.pi * r * h if shell else math.pi * (r * r * h + 4 * r ** 3 / 3)
    if gtype == "cylinder":
        return 2 * math.pi * r * r + 2 * math.pi * r * h if shell else math.pi * r * r * h
    if gtype == "ellipsoid":
        if shell:  # Thomsen's approximation, as MuJoCo
            p = 1.6075
            t = (size[0] * size[1]) ** p + (size[1] * size[2]) ** p + (size[2] * size[0]) ** p
            return 4 * math.pi * (t / 3) ** (1 / p)
        return 4 * math.pi * size[0] * size[1] * size[2] / 3
    if gtype in ("box", "hfield"):
        if shell:
            return 8 * (size[0] * size[1] + size[1] * size[2] + size[2] * size[0])
        return size[0] * size[1] * size[2] * 8
    return 0.0


def _geom_inertia(gtype: str, size: Sequence[float], m: float, shell: bool) -> mm.Vec:
    """Principal moments of a primitive of mass m about its centre, geom axes (MuJoCo's formulas)."""
    if gtype == "sphere":
        i = 2 * m * size[0] ** 2 / (3 if shell else 5)
        return (i, i, i)
    r, hh = size[0], size[1]
    h = 2 * hh
    if gtype == "capsule":
        if not shell:
            ms = m * 4 * r / (4 * r + 3 * h)
            mc = m - ms
            ixx = mc * (3 * r * r + h * h) / 12
            izz = mc * r * r / 2
            si = 2 * ms * r * r / 5
            ixx += si + ms * h * (3 * r + 2 * h) / 8
            return (ixx, ixx, izz + si)
        a_s, a_c = 4 * math.pi * r * r, 2 * math.pi * r * h
        ms = m * a_s / (a_s + a_c)
        mc = m - ms
        ixx = mc * (6 * r * r + h * h) / 12
        izz = mc * r * r
        si = 2 * ms * r * r / 3
        hs_com = r / 2
        hs_pos = hh + hs_com
        ixx += si + ms * (hs_pos * hs_pos - hs_com * hs_com)
        return (ixx, ixx, izz + si)
    if gtype == "cylinder":
        if not shell:
            ixx = m * (3 * r * r + h * h) / 12
            return (ixx, ixx, m * r * r / 2)
        a_d, a_c = math.pi * r * r, 2 * math.pi * r * h
        md = m * a_d / (2 * a_d + a_c)
        mc = m - 2 * md
        ixx = mc * (6 * r * r + h * h) / 12 + 2 * (md * r * r / 4 + md * hh * hh)
        return (ixx, ixx, mc * r * r + 2 * (md * r * r / 2))
    s0, s1, s2 = size[0] ** 2, size[1] ** 2, size[2] ** 2
    if gtype == "ellipsoid":
        if not shell:
            return (m * (s1 + s2) / 5, m * (s0 + s2) / 5, m * (s0 + s1) / 5)
        eps = 1e-6
        va = 4 * math.pi * size[0] * size[1] * size[2] / 3
        ae, be, ce = size[0] + eps, size[1] + eps, size[2] + eps
        vb = 4 * math.pi * ae * be * ce / 3
        dens = m / (vb - va)
        ma, mb = va * dens, vb * dens
        return (mb * (be * be + ce * ce) / 5 - ma * (s1 + s2) / 5, mb * (ae * ae + ce * ce) / 5 - ma * (s0 + s2) / 5,
                mb * (ae * ae + be * be) / 5 - ma * (s0 + s1) / 5)
    if gtype in ("box", "hfield"):
        if not shell:
            return (m * (s1 + s2) / 3, m * (s0 + s2) / 3, m * (s0 + s1) / 3)
        lx, ly, lz = 2 * size[0], 2 * size[1], 2 * size[2]
        a0, a1, a2 = lx * ly, ly * lz, lz * lx
        at = 2 * (a0 + a1 + a2)
        m0, m1, m2 = m * a0 / at, m * a1 / at, m * a2 / at
        ix = (m0 * ly * ly / 12, m1 * (ly * ly + lz * lz) / 12, m2 * lz * lz / 12)
        iy = (m0 * lx * lx / 12, m1 * lz * lz / 12, m2 * (lx * lx + lz * lz) / 12)
        iz = (m0 * (lx * lx + ly * ly) / 12, m1 * ly * ly / 12, m2 * lx * lx / 12)
        return (2 * (m0 * s2 + m2 * s1 + sum(ix)), 2 * (m0 * s2 + m1 * s0 + sum(iy)), 2 * (m1 * s0 + m2 * s1 + sum(iz)))
    return (0.0, 0.0, 0.0)


@dataclass
class _Geom:
    out: MjcfGeom
    mass: float
    inertia: mm.Vec
    pos: mm.Vec
    quat: mm.Quat
    group: int


def _geom(ctx: _Ctx, elem: ET.Element, cls: str, name: str, frame: tuple[mm.Vec, mm.Quat] | None,
          infer: bool) -> _Geom:
    a, dflt = _attrs(ctx, elem, cls)
    ctx.check_refs(elem, name, a, {"material": "material", "hfield": "hfield"})
    gtype = a.get("type", "sphere")
    if gtype not in _GEOM_TYPES:
        raise InputError(f"{ctx.where(elem, name)} type={gtype!r}: expected one of {', '.join(_GEOM_TYPES)}")
    size = list(_numbers(ctx, a, "size", 3, elem, exact=False) or [])
    size = [float(x) for x in size] + [0.0] * (3 - len(size))
    group = _int(ctx, a, "group", 0, elem)
    ig = ctx.compiler["inertiagrouprange"]
    infer = infer and ig[0] <= group <= ig[1]
    shell = _flag(ctx, a, "shellinertia", False, elem)
    fromto = _numbers(ctx, a, "fromto", 6, elem)
    pos = _vec3(_numbers(ctx, a, "pos", 3, elem))
    if fromto is not None:
        if gtype not in ("capsule", "cylinder", "ellipsoid", "box"):
            raise InputError(f"{ctx.where(elem, name)}: fromto requires capsule, cylinder, box or ellipsoid")
        if any(pos):
            raise InputError(f"{ctx.where(elem, name)}: both pos and fromto defined")
        vec, n = mm.normalized((fromto[0] - fromto[3], fromto[1] - fromto[4], fromto[2] - fromto[5]))
        size[1] = n / 2
        if size[1] < mm.EPS:
            raise InputError(f"{ctx.where(elem, name)}: fromto points too close")
        if gtype in ("ellipsoid", "box"):
            size[2], size[1] = size[1], size[0]
        pos = ((fromto[0] + fromto[3]) / 2, (fromto[1] + fromto[4]) / 2, (fromto[2] + fromto[5]) / 2)
        quat = mm.z_to_quat(vec)
    else:
        quat = _orientation(ctx, elem, a, dflt)
    mesh_name = a.get("mesh")
    vertices = faces = None
    mesh_file, file_pose, mesh_scale = None, None, np.ones(3)
    mvol = None
    info = None
    if mesh_name is not None and gtype in ("mesh", "sdf", "sphere", "capsule", "cylinder", "ellipsoid", "box"):
        if fromto is not None:
            raise InputError(f"{ctx.where(elem, name)}: fromto cannot be used with a mesh geom")
        needed = infer or gtype not in ("mesh", "sdf")
        (info, path, scale, refpos, refquat, mverts, mfaces), _ = _mesh(ctx, mesh_name, elem, needed)
        if info is None:  # drawn and collided only, in the geom's own frame (MuJoCo would refuse the file)
            vertices, faces, mvol = mverts, mfaces, 0.0
            mesh_file, mesh_scale = str(path), np.asarray(scale, dtype=float)
            if np.allclose(refpos, 0) and np.allclose(refquat, [1, 0, 0, 0]):
                file_pose = np.eye(4)
        else:
            center = (0.0, 0.0, 0.0)
            if gtype not in ("mesh", "sdf"):  # a primitive fitted to the mesh
                fit = float((_numbers(ctx, a, "fitscale", 1, elem) or [1.0])[0])
                if not ctx.compiler["fitaabb"]:
                    b = info.box
                    if gtype == "sphere":
                        size[0] = (b[0] + b[1] + b[2]) / 3
                    elif gtype == "capsule":
                        size[0] = (b[0] + b[1]) / 2
                        size[1] = max(0.0, b[2] - size[0] / 2)
                    elif gtype == "cylinder":
                        size[0], size[1] = (b[0] + b[1]) / 2, b[2]
                    else:
                        size[:3] = list(b)
                else:
                    lo, hi = info.aamm[:3], info.aamm[3:]
                    center = ((lo[0] + hi[0]) / 2, (lo[1] + hi[1]) / 2, (lo[2] + hi[2]) / 2)
                    half = [hi[k] - center[k] for k in range(3)]
                    if gtype == "sphere":
                        size[0] = max(half)
                    elif gtype in ("capsule", "cylinder"):
                        size[0], size[1] = max(half[0], half[1]), half[2]
                        if gtype == "capsule":
                            size[1] -= size[0]
                    else:
                        size[:3] = half
                size = [s * fit for s in size]
            else:
                if shell:
                    raise InputError(f"{ctx.where(elem, name)}: for mesh geoms, inertia is set on the mesh asset "
                                     "(<mesh inertia='shell'>), not with shellinertia")
                mvol = info.volume
                lo, hi = info.aamm[:3], info.aamm[3:]
                size = [max(abs(lo[k]), abs(hi[k])) for k in range(3)]
            meshpos = mm.rotate(info.quat, center)
            meshpos = (meshpos[0] + info.pos[0], meshpos[1] + info.pos[1], meshpos[2] + info.pos[2])
            pos, quat = mm.compose(pos, quat, meshpos, info.quat)
            if gtype in ("mesh", "sdf"):
                # vertices in the compiled geom frame: Rᵀ (v - meshpos)
                R = np.array(mm.quat_to_matrix(info.quat)).reshape(3, 3)
                vertices = (info.vertices - np.array(meshpos)) @ R
                faces = info.faces
                mesh_scale = np.asarray(scale, dtype=float)
                if path is not None:
                    mesh_file = str(path)
                    file_pose = _file_pose(scale, refpos, refquat, meshpos, info.quat)
    elif gtype in ("mesh", "sdf"):
        raise InputError(f"{ctx.where(elem, name)}: a {gtype} geom needs a mesh attribute")
    _check_size(ctx, elem, name, gtype, size, mesh_name is not None)
    condim = _int(ctx, a, "condim", 3, elem)
    if condim not in (1, 3, 4, 6):
        raise InputError(f"{ctx.where(elem, name)} condim={condim}: expected 1, 3, 4 or 6 (MuJoCo refuses the file: "
                         "invalid condim)")
    if infer and gtype in ("hfield", "sdf"):
        raise InputError(f"{ctx.where(elem, name)}: the mass of a {gtype} geom is not computed by robokit; give the "
                         "body an <inertial>")
    mass = 0.0
    inertia: mm.Vec = (0.0, 0.0, 0.0)
    if infer:
        vol = mvol if mvol is not None else _geom_volume(gtype, size, shell)
        given = _numbers(ctx, a, "mass", 1, elem)
        density = float((_numbers(ctx, a, "density", 1, elem) or [1000.0])[0])
        if given is not None:
            if given[0] == 0:
                mass = 0.0
            elif vol > mm.EPS:
                mass = given[0]
        else:
            mass = density * vol if density != 0 else 0.0
        if mass != 0:
            if gtype in ("mesh", "sdf"):
                assert info is not None
                b = info.box
                inertia = (mass * (b[1] * b[1] + b[2] * b[2]) / 3, mass * (b[0] * b[0] + b[2] * b[2]) / 3,
                           mass * (b[0] * b[0] + b[1] * b[1]) / 3)
            else:
                inertia = _geom_inertia(gtype, size, mass, shell)
        if mass < 0 or min(inertia) < 0 or density < 0:
            raise InputError(f"{ctx.where(elem, name)}: mass, inertia or density are negative")
    if frame is not None:
        pos, quat = mm.compose(frame[0], frame[1], pos, quat)
    rgba = _numbers(ctx, a, "rgba", 4, elem) or [0.5, 0.5, 0.5, 1.0]
    out = MjcfGeom(name=name, type=gtype, size=np.array(size), pos=np.array(pos), quat=np.array(quat),
                   contype=_int(ctx, a, "contype", 1, elem), conaffinity=_int(ctx, a, "conaffinity", 1, elem),
                   group=group, mass=mass, rgba=np.array(rgba), mesh=mesh_name if gtype in ("mesh", "sdf") else None,
                   vertices=vertices, faces=faces, mesh_file=mesh_file, mesh_file_pose=file_pose, mesh_scale=mesh_scale)
    return _Geom(out, mass, inertia, pos, quat, group)


#: the sizes MuJoCo requires positive, by geom or site type (``plane``: its grid spacing, the third)
_POSITIVE_SIZES = {"sphere": (0,), "capsule": (0, 1), "cylinder": (0, 1), "ellipsoid": (0, 1, 2), "box": (0, 1, 2),
                   "plane": (2,)}


def _check_size(ctx: _Ctx, elem: ET.Element, name: str, gtype: str, size: Sequence[float], fitted: bool) -> None:
    """MuJoCo's rule: a primitive's sizes positive (a primitive fitted to a mesh takes its sizes from it)."""
    if fitted and gtype != "plane":
        return
    for k in _POSITIVE_SIZES.get(gtype, ()):
        if not size[k] > 0:
            raise InputError(f"{ctx.where(elem, name)}: a {gtype} needs size[{k}] > 0, got {size[k]:g} (MuJoCo "
                             "refuses the file)")


def _file_pose(scale: Sequence[float], refpos: Sequence[float], refquat: Sequence[float], meshpos: mm.Vec,
               mquat: mm.Quat) -> np.ndarray | None:
    """Where scale·(file coordinates) sit in the compiled geom frame, when a rigid motion says it."""
    s = np.asarray(scale, dtype=float)
    rq = mm.unit_quat(refquat)
    Rr = np.array(mm.quat_to_matrix(rq)).reshape(3, 3)
    if not np.allclose(Rr, np.eye(3)) and not (s[0] == s[1] == s[2]):
        return None
    # processed vertex v1 = S Rrᵀ (v - p) = Rrᵀ (S v) - S Rrᵀ p  (S uniform or Rr = I)
    A = Rr.T
    b = -(s * (Rr.T @ np.asarray(refpos, dtype=float))) if np.allclose(Rr, np.eye(3)) else -s[0] * (Rr.T @ np.asarray(refpos, dtype=float))
    Rm = np.array(mm.quat_to_matrix(mquat)).reshape(3, 3)
    T = np.eye(4)
    T[:3, :3] = Rm.T @ A
    T[:3, 3] = Rm.T @ (b - np.asarray(meshpos))
    return T


# --------------------------------------------------------------------------- bodies
@dataclass
class _Body:
    name: str
    parent: int
    pos: mm.Vec
    quat: mm.Quat
    joints: list[MjcfJoint]
    mass: float
    ipos: mm.Vec
    iquat: mm.Quat
    inertia: mm.Vec
    geoms: list[MjcfGeom]
    sites: list[MjcfSite]
    named: bool
    mocap: bool
    elem: ET.Element | None = None


def _joint(ctx: _Ctx, elem: ET.Element, cls: str, name: str, named: bool,
           frame: tuple[mm.Vec, mm.Quat] | None) -> MjcfJoint:
    a, _ = _attrs(ctx, elem, cls)
    jtype = "free" if elem.tag == "freejoint" else a.get("type", "hinge")
    if jtype not in _JOINT_TYPES:
        raise InputError(f"{ctx.where(elem, name)} type={jtype!r}: expected hinge, slide, ball or free")
    rng = _numbers(ctx, a, "range", 2, elem) or [0.0, 0.0]
    limited_attr = a.get("limited", "auto")
    if limited_attr not in ("true", "false", "auto"):
        raise InputError(f"{ctx.where(elem, name)} limited={limited_attr!r}: expected true, false or auto")
    if jtype == "free":
        limited = False
    elif limited_attr == "auto":
        has = not (rng[0] == 0 and rng[1] == 0)
        if not ctx.compiler["autolimits"] and has:
            raise InputError(f"{ctx.where(elem, name)}: joint has range but not limited; set <compiler "
                             "autolimits='true'>, give limited explicitly or remove the range (MuJoCo refuses it)")
        limited = rng[0] < rng[1]
    else:
        limited = limited_attr == "true"
    if limited:
        if rng[0] >= rng[1] and jtype != "ball":
            raise InputError(f"{ctx.where(elem, name)}: range[0] should be smaller than range[1]")
        if ctx.degree and jtype in ("hinge", "ball"):
            rng = [r * math.pi / 180.0 for r in rng]
    axis = _vec3(_numbers(ctx, a, "axis", 3, elem), (0.0, 0.0, 1.0))
    pos = _vec3(_numbers(ctx, a, "pos", 3, elem))
    if jtype in ("free", "ball"):
        axis = (0.0, 0.0, 1.0)
    elif frame is not None:
        axis = mm.rotate(frame[1], axis)
    axis_n, n = mm.normalized(axis)
    if n < mm.EPS:
        raise InputError(f"{ctx.where(elem, name)}: axis too small")
    if jtype == "free":
        pos = (0.0, 0.0, 0.0)
    elif frame is not None:
        pos = mm.compose(frame[0], frame[1], pos, mm.IDENTITY)[0]
    ref = float((_numbers(ctx, a, "ref", 1, elem) or [0.0])[0])
    springref = float((_numbers(ctx, a, "springref", 1, elem) or [0.0])[0])
    if jtype == "hinge" and ctx.degree:
        ref *= math.pi / 180.0
        springref *= math.pi / 180.0

    def num(key: str) -> float:
        return float((_numbers(ctx, a, key, 1, elem) or [0.0])[0])

    sd = _numbers(ctx, a, "springdamper", 2, elem)
    if sd is not None and (sd[0] or sd[1]):
        ctx.joint_extras.setdefault("springdamper", []).append((name, " ".join(a["springdamper"].split())))
    for key in ("frictionloss", "stiffness"):
        if num(key) != 0.0:
            ctx.joint_extras.setdefault(key, []).append((name, a[key].strip()))
    return MjcfJoint(name=name, type=jtype, pos=np.array(pos), axis=np.array(axis_n), limited=limited,
                     range=np.array(rng if limited else [-math.inf, math.inf], dtype=float), ref=ref,
                     springref=springref, armature=num("armature"), damping=num("damping"),
                     stiffness=num("stiffness"), frictionloss=num("frictionloss"), named=named,
                     effort=_actuator_force_limit(ctx, elem, a, name))


def _actuator_force_limit(ctx: _Ctx, elem: ET.Element, a: dict[str, str], name: str) -> float:
    """The joint's effort limit from ``actuatorfrclimited``/``actuatorfrcrange``, with MuJoCo's rules (``auto``:
    limited when the compiler's autolimits is on and the range is not empty; a range given with ``auto`` and
    autolimits off, or a limited empty range, refused as MuJoCo refuses them); inf when not limited."""
    frc = _numbers(ctx, a, "actuatorfrcrange", 2, elem) or [0.0, 0.0]
    flag = a.get("actuatorfrclimited", "auto")
    if flag not in ("true", "false", "auto"):
        raise InputError(f"{ctx.where(elem, name)} actuatorfrclimited={flag!r}: expected true, false or auto")
    if flag == "auto":
        if not ctx.compiler["autolimits"] and not (frc[0] == 0 and frc[1] == 0):
            raise InputError(f"{ctx.where(elem, name)}: joint has actuatorfrcrange but not actuatorfrclimited; set "
                             "<compiler autolimits='true'>, give actuatorfrclimited or remove the range (MuJoCo "
                             "refuses it)")
        limited = frc[0] < frc[1]
    else:
        limited = flag == "true"
    if not limited:
        return math.inf
    if frc[0] >= frc[1]:
        raise InputError(f"{ctx.where(elem, name)}: actuatorfrcrange[0] should be smaller than actuatorfrcrange[1]")
    if frc[0] == -frc[1]:
        return float(frc[1])
    ctx.joint_extras.setdefault("actuatorfrcrange", []).append((name, " ".join(a["actuatorfrcrange"].split())))
    return math.inf


_DOFS = {"free": 6, "ball": 3, "hinge": 1, "slide": 1}


def _check_joint_order(ctx: _Ctx, elem: ET.Element, name: str, joints: Sequence[MjcfJoint]) -> None:
    """MuJoCo's rules for the joints of one body: at most 6 degrees of freedom (a free joint has 6,
    a ball 3), and no rotation (a hinge or ball) after a ball joint."""
    dofs = sum(_DOFS[j.type] for j in joints)
    if dofs > 6:
        kinds = ", ".join(f"{j.name} ({j.type})" for j in joints)
        raise InputError(f"{ctx.where(elem, name)}: more than 6 degrees of freedom in one body ({dofs}: {kinds}); "
                         "MuJoCo refuses the file")
    ball = None
    for j in joints:
        if ball is not None and j.type in ("hinge", "ball"):
            raise InputError(f"{ctx.where(elem, name)}: {j.type} joint {j.name!r} follows ball joint {ball!r}; "
                             "MuJoCo refuses a rotation after a ball joint in one body")
        if j.type == "ball":
            ball = j.name


def _placed(ctx: _Ctx, elem: ET.Element, a: dict[str, str], name: str | None, cls: str
            ) -> tuple[str, mm.Vec, mm.Quat]:
    """A ``<frame>``'s or ``<body>``'s childclass (``cls`` when it names none; checked), position and
    orientation in its parent, from its attributes ``a``."""
    cls = a.get("childclass", cls)
    if cls not in ctx.defaults:
        raise InputError(f"{ctx.where(elem, name)} childclass={cls!r}: no such default class")
    return cls, _vec3(_numbers(ctx, a, "pos", 3, elem)), _orientation(ctx, elem, a, {})


def _children(elem: ET.Element, frame: tuple[mm.Vec, mm.Quat] | None, cls: str, ctx: _Ctx
              ) -> Iterator[tuple[ET.Element, tuple[mm.Vec, mm.Quat] | None, str]]:
    """The element's children with the frame (accumulated ``<frame>`` pose) and childclass they sit in."""
    for child in elem:
        if child.tag == "frame":
            fa = dict(child.attrib)
            fcls, fpos, fquat = _placed(ctx, child, fa, fa.get("name"), cls)
            if frame is not None:
                fpos, fquat = mm.compose(frame[0], frame[1], fpos, fquat)
            yield from _children(child, (fpos, mm.unit_quat(fquat)), fcls, ctx)
        else:
            yield child, frame, cls


def _body(ctx: _Ctx, elem: ET.Element, parent: int, name: str, named: bool, frame: tuple[mm.Vec, mm.Quat] | None,
          cls: str, out: list[_Body]) -> None:
    a = dict(elem.attrib)
    cls, bpos, bquat = _placed(ctx, elem, a, name, cls)
    me = len(out)
    body = _Body(name, parent, bpos, bquat, [], 0.0, (_NAN, 0.0, 0.0), mm.IDENTITY, (0.0, 0.0, 0.0), [], [], named,
                 _flag(ctx, a, "mocap", False, elem), elem)
    out.append(body)
    # explicit inertial
    inertial = elem.find("inertial")
    explicit = inertial is not None
    if inertial is not None:
        ia = dict(inertial.attrib)
        ipos = _numbers(ctx, ia, "pos", 3, inertial)
        mass = _numbers(ctx, ia, "mass", 1, inertial)
        if ipos is None or mass is None:
            raise InputError(f"{ctx.where(inertial)} of body {name!r}: pos and mass are required")
        body.mass, body.ipos = mass[0], _vec3(ipos)
        body.iquat = _orientation(ctx, inertial, ia, {})
        full = _numbers(ctx, ia, "fullinertia", 6, inertial)
        diag = _numbers(ctx, ia, "diaginertia", 3, inertial)
        if full is not None:
            if any(k in ia for k in _ORIENT):
                raise InputError(f"{ctx.where(inertial)} of body {name!r}: fullinertia and an inertial orientation "
                                 "cannot both be given")
            if diag is not None and any(diag):
                raise InputError(f"{ctx.where(inertial)} of body {name!r}: fullinertia and diaginertia cannot both "
                                 "be given")
            res = mm.full_inertia(full)
            if isinstance(res, str):
                raise InputError(f"{ctx.where(inertial)} of body {name!r}: fullinertia: {res}")
            body.iquat, body.inertia = res
        elif diag is not None:
            body.inertia = _vec3(diag)
    # children in document order (frames flattened)
    ifg = ctx.compiler["inertiafromgeom"]
    infer = (not explicit) or ifg == "true"
    geoms: list[_Geom] = []
    child_bodies: list[tuple[ET.Element, tuple[mm.Vec, mm.Quat] | None, str]] = []
    k_geom = k_site = k_joint = 0
    for child, frame_c, ccls in _children(elem, None, cls, ctx):
        if child.tag in ("joint", "freejoint"):
            jname = child.get("name")
            body.joints.append(_joint(ctx, child, ccls, jname or f"{name}/joint{k_joint}", jname is not None, frame_c))
            k_joint += 1
        elif child.tag == "geom":
            gname = child.get("name") or f"{name}/geom{k_geom}"
            geoms.append(_geom(ctx, child, ccls, gname, frame_c, infer))
            k_geom += 1
        elif child.tag == "site":
            sname = child.get("name") or f"{name}/site{k_site}"
            body.sites.append(_site(ctx, child, ccls, sname, frame_c))
            k_site += 1
        elif child.tag == "body":
            child_bodies.append((child, frame_c, ccls))
        elif child.tag in ("attach", "replicate", "composite", "flexcomp"):
            raise InputError(f"{ctx.where(child)} in body {name!r}: <{child.tag}> is not read by robokit; "
                             "expand it into plain bodies first")
    _check_joint_order(ctx, elem, name, body.joints)
    body.geoms = [g.out for g in geoms]
    if ifg == "true" or (not explicit and ifg == "auto"):
        _inertia_from_geoms(ctx, body, geoms)
    if math.isnan(body.ipos[0]):  # no mass source: MuJoCo puts the inertial frame at the body's own pos/quat
        body.ipos, body.iquat = bpos, bquat
    c = ctx.compiler
    body.mass = max(body.mass, c["boundmass"])
    body.inertia = (max(body.inertia[0], c["boundinertia"]), max(body.inertia[1], c["boundinertia"]),
                    max(body.inertia[2], c["boundinertia"]))
    A, B, C = body.inertia
    if body.mass < 0 or min(body.inertia) < 0:
        raise InputError(f"{ctx.where(elem, name)}: mass and inertia cannot be negative")
    if A + B < C or A + C < B or B + C < A:
        if c["balanceinertia"]:
            m = (A + B + C) / 3.0
            body.inertia = (m, m, m)
        else:
            raise InputError(f"{ctx.where(elem, name)}: principal moments {list(body.inertia)} break A + B >= C; "
                             "MuJoCo refuses this body (<compiler balanceinertia='true'> averages them)")
    if frame is not None:
        body.pos, body.quat = mm.compose(frame[0], frame[1], bpos, bquat)
    for k, (child, frame_c, ccls) in enumerate(child_bodies):
        cname = child.get("name")
        _body(ctx, child, me, cname or f"{name}/body{k}", cname is not None, frame_c, ccls, out)


def _site(ctx: _Ctx, elem: ET.Element, cls: str, name: str, frame: tuple[mm.Vec, mm.Quat] | None) -> MjcfSite:
    a, dflt = _attrs(ctx, elem, cls)
    ctx.check_refs(elem, name, a, {"material": "material"})
    stype = a.get("type", "sphere")
    if stype not in _GEOM_TYPES:
        raise InputError(f"{ctx.where(elem, name)} type={stype!r}: expected one of sphere, capsule, ellipsoid, "
                         "cylinder, box, mesh")
    if stype in ("plane", "hfield"):
        raise InputError(f"{ctx.where(elem, name)} type={stype!r}: MuJoCo allows no plane or height field as a site")
    if stype == "mesh" and a.get("mesh") not in ctx.meshes:
        raise InputError(f"{ctx.where(elem, name)}: a mesh site needs the name of a mesh asset "
                         f"(mesh={a.get('mesh')!r})")
    ssize = list(_numbers(ctx, a, "size", 3, elem, exact=False) or [])
    _check_size(ctx, elem, name, stype, ssize + [0.005] * (3 - len(ssize)), False)  # MuJoCo's default site size
    fromto = _numbers(ctx, a, "fromto", 6, elem)
    if fromto is not None:
        if stype not in ("capsule", "cylinder", "ellipsoid", "box"):
            raise InputError(f"{ctx.where(elem, name)}: fromto requires capsule, cylinder, box or ellipsoid")
        if any(_numbers(ctx, a, "pos", 3, elem) or ()):
            raise InputError(f"{ctx.where(elem, name)}: both pos and fromto defined")
        if mm.normalized((fromto[0] - fromto[3], fromto[1] - fromto[4], fromto[2] - fromto[5]))[1] / 2 < mm.EPS:
            raise InputError(f"{ctx.where(elem, name)}: fromto points too close")
        vec, _ = mm.normalized((fromto[0] - fromto[3], fromto[1] - fromto[4], fromto[2] - fromto[5]))
        pos = ((fromto[0] + fromto[3]) / 2, (fromto[1] + fromto[4]) / 2, (fromto[2] + fromto[5]) / 2)
        quat = mm.z_to_quat(vec)
    else:
        pos = _vec3(_numbers(ctx, a, "pos", 3, elem))
        quat = _orientation(ctx, elem, a, dflt)
    if frame is not None:
        pos, quat = mm.compose(frame[0], frame[1], pos, quat)
    return MjcfSite(name, np.array(pos), np.array(quat))


def _inertia_from_geoms(ctx: _Ctx, body: _Body, geoms: list[_Geom]) -> None:
    sel = [g for g in geoms if g.mass > mm.EPS]
    if len(sel) == 1:
        g = sel[0]
        body.ipos, body.iquat, body.mass, body.inertia = g.pos, g.quat, g.mass, g.inertia
    elif len(sel) > 1:
        mass = 0.0
        com = [0.0, 0.0, 0.0]
        for g in sel:
            mass += g.mass
            for k in range(3):
                com[k] += g.mass * g.pos[k]
        if mass < mm.EPS:
            raise InputError(f"{ctx.path}: body {body.name!r}: mass too small to compute a centre of mass")
        ipos = (com[0] / mass, com[1] / mass, com[2] / mass)
        tot = [0.0] * 6
        for g in sel:
            d = (g.pos[0] - ipos[0], g.pos[1] - ipos[1], g.pos[2] - ipos[2])
            i0 = mm.rotated_inertia(g.inertia, g.quat)
            i1 = mm.point_mass_inertia(g.mass, d)
            for j in range(6):
                tot[j] = tot[j] + i0[j] + i1[j]
        res = mm.full_inertia(tot)
        if isinstance(res, str):
            raise InputError(f"{ctx.path}: body {body.name!r}: {res}")
        body.mass, body.ipos = mass, ipos
        body.iquat, body.inertia = res


def _accumulate(ctx: _Ctx, parent: _Body, child: _Body) -> None:
    """Fuse a static body's inertial into its parent's (MuJoCo's ``fusestatic``)."""
    cpos, cquat = mm.compose(child.pos, child.quat, child.ipos, child.iquat)
    masses = (parent.mass, child.mass)
    ip = (parent.ipos, cpos)
    iq = (parent.iquat, cquat)
    inert = (parent.inertia, child.inertia)
    total = masses[0] + masses[1]
    if total < mm.MINVAL:
        parent.mass, parent.inertia, parent.ipos, parent.iquat = 0.0, (0.0, 0.0, 0.0), (0.0, 0.0, 0.0), mm.IDENTITY
        return
    com = tuple((masses[0] * ip[0][k] + masses[1] * ip[1][k]) / total for k in range(3))
    tot = [0.0] * 6
    for j in range(2):
        d = (ip[j][0] - com[0], ip[j][1] - com[1], ip[j][2] - com[2])
        a = mm.rotated_inertia(inert[j], iq[j])
        b = mm.point_mass_inertia(masses[j], d)
        for k in range(6):
            tot[k] += a[k] + b[k]
    res = mm.full_inertia(tot)
    if isinstance(res, str):
        raise InputError(f"{ctx.path}: fusing static body {child.name!r}: {res}")
    parent.mass, parent.ipos = total, (com[0], com[1], com[2])
    parent.iquat, parent.inertia = res


def _referenced_bodies(root: ET.Element) -> set[str]:
    out = set()
    for section in ("contact", "equality", "tendon", "actuator", "sensor", "custom", "skin"):
        for sec in root.findall(section):
            for el in sec.iter():
                for key in _BODY_REFS:
                    if key in el.attrib:
                        out.add(el.attrib[key])
    for el in root.iter():
        if el.tag in ("camera", "light") and "target" in el.attrib:
            out.add(el.attrib["target"])
    return out


def _fused_into_world(ctx: _Ctx, bodies: list[_Body]) -> tuple[set[int], set[int]]:
    """Apply ``fusestatic``: fuse every static body's inertial into its parent, as MuJoCo does;
    the indices of the bodies whose mass MuJoCo drops into the world (it does not count them
    in ``settotalmass``), and of every body fused."""
    keep = _referenced_bodies(ctx.root)
    parent_of = {i: b.parent for i, b in enumerate(bodies)}
    pose = {i: (b.pos, b.quat) for i, b in enumerate(bodies)}
    gone: set[int] = set()
    dropped: set[int] = set()
    for i in range(1, len(bodies)):
        b = bodies[i]
        if b.joints or b.mocap or (b.named and b.name in keep):
            continue
        par = parent_of[i]
        if par != 0 and b.mass >= mm.MINVAL:
            # the child's inertial, placed by its (possibly re-parented) pose
            saved = (b.pos, b.quat)
            b.pos, b.quat = pose[i]
            _accumulate(ctx, bodies[par], b)
            b.pos, b.quat = saved
        if par == 0:
            dropped.add(i)
        b.mass, b.inertia = 0.0, (0.0, 0.0, 0.0)
        gone.add(i)
        for j, p in parent_of.items():  # its children now hang on its parent
            if p == i:
                parent_of[j] = par
                pose[j] = mm.compose(pose[i][0], pose[i][1], pose[j][0], pose[j][1])
    return dropped, gone


def _check_free_joints(ctx: _Ctx, bodies: list[_Body], fused: set[int]) -> None:
    """MuJoCo's rule: a free joint only on a top-level body, a child of the world (once ``fusestatic``
    has fused the static bodies above it into the world)."""
    for b in bodies[1:]:
        if any(j.type == "free" for j in b.joints):
            up = b.parent
            while up in fused:
                up = bodies[up].parent
            if up != 0:
                raise InputError(f"{ctx.where(b.elem, b.name)}: its free joint hangs below body {bodies[up].name!r}; "
                                 "MuJoCo allows a free joint only on a top-level body (a child of <worldbody>)")


#: the keywords of ``<option>``'s keyword attributes (MuJoCo's XML reference)
_OPTION_WORDS = {"integrator": ("Euler", "RK4", "implicit", "implicitfast"), "cone": ("pyramidal", "elliptic"),
                 "jacobian": ("dense", "sparse", "auto"), "solver": ("PGS", "CG", "Newton")}


def _check_moving_masses(ctx: _Ctx, bodies: list[_Body]) -> None:
    """MuJoCo's rule: a body with a joint has mass and principal moments of at least mjMINVAL
    (1e-15), its own or those of a body welded to it below (a child without a joint, and so on)."""
    def solid(b: _Body) -> bool:
        return b.mass >= mm.MINVAL and min(b.inertia) >= mm.MINVAL

    kids: dict[int, list[int]] = {}
    for i, b in enumerate(bodies[1:], 1):
        kids.setdefault(b.parent, []).append(i)
    for i, b in enumerate(bodies[1:], 1):
        if not b.joints or solid(b):
            continue
        stack, found = list(kids.get(i, [])), False
        while stack and not found:
            k = stack.pop()
            if not bodies[k].joints:
                found = solid(bodies[k])
                stack.extend(kids.get(k, []))
        if not found:
            raise InputError(f"{ctx.where(b.elem, b.name)}: a body with a joint needs mass and inertia (mass "
                             f"{b.mass:g} kg, principal moments {', '.join(f'{x:g}' for x in b.inertia)} kg·m², and "
                             "no body welded below it has both); MuJoCo refuses the file")


def _check_planes(ctx: _Ctx, bodies: list[_Body]) -> None:
    """MuJoCo's rules: a plane geom only on a body that does not move (no joint on it or above it); a
    mocap body a child of the world without joints."""
    moving = [False] * len(bodies)
    for i, b in enumerate(bodies[1:], 1):
        moving[i] = bool(b.joints) or moving[b.parent]
        if b.mocap and (b.joints or b.parent != 0):
            raise InputError(f"{ctx.where(b.elem, b.name)}: a mocap body must be a child of <worldbody> without "
                             "joints (MuJoCo refuses the file)")
        for g in b.geoms:
            if moving[i] and g.type == "plane":
                raise InputError(f"{ctx.path}: <geom name={g.name!r}> in <body name={b.name!r}>: a plane only on a "
                                 "body that does not move (MuJoCo refuses the file)")


_NQ = {"free": 7, "ball": 4, "hinge": 1, "slide": 1}


def _check_keyframes(ctx: _Ctx, bodies: list[_Body]) -> None:
    """MuJoCo's rule: a ``<key>``'s ``qpos``, ``qvel``, ``ctrl``, ``mpos`` and ``mquat`` have at most the model's
    sizes (MuJoCo 4.0.1 fills a shorter one up; Menagerie's xArm 6 with its gripper keys 6 of its 12 positions)."""
    joints = [j for b in bodies for j in b.joints]
    nmocap = sum(1 for b in bodies if b.mocap)
    nu = sum(1 for sec in ctx.root.findall("actuator") for a in sec if isinstance(a.tag, str))
    sizes = {"qpos": sum(_NQ[j.type] for j in joints), "qvel": sum(_DOFS[j.type] for j in joints), "ctrl": nu,
             "mpos": 3 * nmocap, "mquat": 4 * nmocap}
    for sec in ctx.root.findall("keyframe"):
        for key in sec.findall("key"):
            for attr, n in sizes.items():
                vals = _numbers(ctx, dict(key.attrib), attr, None, key)
                if vals is not None and len(vals) > n:
                    raise InputError(f"{ctx.where(key, key.get('name'))} {attr}: {len(vals)} numbers, the model has "
                                     f"{n} (MuJoCo refuses the file)")


def compile_mjcf(path: str | os.PathLike[str], root: ET.Element | None = None, *,
                 allow_outside_meshes: bool = False,
                 package_dirs: Sequence[str | os.PathLike[str]] | None = None) -> CompiledMjcf:
    """Compile an MJCF file by MuJoCo's rules, without MuJoCo (see the module docstring).

    Parameters
    ----------
    path : str or os.PathLike
        The MJCF file (for messages and relative mesh paths).
    root : xml.etree.ElementTree.Element, optional
        Its root element with every ``<include>`` expanded (default: read and checked from
        ``path`` by :func:`robokit.description.mjcf_safety.check_mjcf`).
    allow_outside_meshes : bool
        Read mesh files outside the file's folder, its package and ``package_dirs``.
    package_dirs : sequence of str or Path, optional
        More folders the file's includes and meshes may be read from.

    Returns
    -------
    CompiledMjcf
        Every body with its pose, joints, inertial, geoms and sites.

    Raises
    ------
    InputError
        What MuJoCo's compiler refuses (bad numbers, a body breaking A + B >= C without
        ``balanceinertia``, a joint with a range but not limited and ``autolimits="false"``, ...),
        naming the file and element.

    Examples
    --------
    A capsule from 0 to 0.4 m along x, radius 0.05 m, density 1000 kg/m³, the body's
    inertia computed from it (``inertiafromgeom`` is "auto" and there is no ``<inertial>``):

    >>> import pathlib, tempfile
    >>> xml = ('<mujoco><worldbody><body name="arm"><joint axis="0 0 1"/>'
    ...        '<geom type="capsule" fromto="0 0 0 0.4 0 0" size="0.05"/></body></worldbody></mujoco>')
    >>> with tempfile.TemporaryDirectory() as tmp:
    ...     path = pathlib.Path(tmp, "arm.xml")
    ...     _ = path.write_text(xml)
    ...     arm = compile_mjcf(path).bodies[1]
    >>> round(arm.mass, 4), arm.ipos.round(4).tolist()       # π r² L ρ + 4/3 π r³ ρ
    (3.6652, [0.2, 0.0, 0.0])
    """
    path = Path(path)
    if root is None:
        from robokit.description.mjcf_safety import check_mjcf

        root = check_mjcf(path, package_dirs=package_dirs, allow_outside_meshes=allow_outside_meshes, expand_includes=True)
    if root.tag != "mujoco":
        raise InputError(f"{path}: root element <{root.tag}> is not <mujoco>; an MJCF file starts with <mujoco>")
    check_schema(root, path)
    known = check_names(root, path)
    check_references(root, path, known)
    ctx = _Ctx(path, root)
    ctx.names = known
    _read_compiler(ctx)
    ctx.compiler["allow_outside_meshes"] = allow_outside_meshes
    ctx.compiler["package_dirs"] = tuple(package_dirs or ())
    _read_defaults(ctx)
    _read_assets(ctx)
    _check_asset_files(ctx)
    # MuJoCo merges every <worldbody> section into the world, in the file's order (a scene that includes
    # the arm's file has two: the arm's and its own floor's, and either may come first)
    worlds = root.findall("worldbody")
    bodies: list[_Body] = [_Body("world", -1, (0.0, 0.0, 0.0), mm.IDENTITY, [], 0.0, (0.0, 0.0, 0.0), mm.IDENTITY,
                                 (0.0, 0.0, 0.0), [], [], True, False, worlds[0] if worlds else None)]
    if worlds:
        k_body = k_geom = k_site = 0
        world_geoms: list[_Geom] = []
        for child, frame_c, ccls in (c for world in worlds for c in _children(world, None, "main", ctx)):
            if child.tag == "body":
                name = child.get("name")
                _body(ctx, child, 0, name or f"world/body{k_body}", name is not None, frame_c, ccls, bodies)
                k_body += 1
            elif child.tag == "geom":
                world_geoms.append(_geom(ctx, child, ccls, child.get("name") or f"world/geom{k_geom}", frame_c, False))
                k_geom += 1
            elif child.tag in ("attach", "replicate", "flexcomp"):
                raise InputError(f"{ctx.where(child)} in <worldbody>: <{child.tag}> is not read by robokit; "
                                 "expand it into plain bodies first")
            elif child.tag == "site":
                bodies[0].sites.append(_site(ctx, child, ccls, child.get("name") or f"world/site{k_site}", frame_c))
                k_site += 1
        bodies[0].geoms = [g.out for g in world_geoms]
    # MuJoCo lists bodies depth first: _body appends parents before children, siblings in order
    dropped: set[int] = set()
    fused: set[int] = set()
    if ctx.compiler["fusestatic"]:
        dropped, fused = _fused_into_world(ctx, bodies)
    _check_free_joints(ctx, bodies, fused)
    _check_planes(ctx, bodies)
    stm = ctx.compiler["settotalmass"]
    if stm > 0:
        total = sum(b.mass for i, b in enumerate(bodies) if i > 0 and i not in dropped)
        scale = max(mm.MINVAL, stm / max(mm.MINVAL, total))
        for i, b in enumerate(bodies):
            if i > 0:
                b.mass *= scale
                b.inertia = (b.inertia[0] * scale, b.inertia[1] * scale, b.inertia[2] * scale)
    _check_moving_masses(ctx, bodies)
    _check_keyframes(ctx, bodies)
    gravity = np.array([0.0, 0.0, -9.81])
    for opt in root.iter("option"):
        g = _numbers(ctx, dict(opt.attrib), "gravity", 3, opt)
        if g is not None:
            gravity = np.array(g)
        for key in ("density", "viscosity"):
            v = _numbers(ctx, dict(opt.attrib), key, 1, opt)
            if v is not None and v[0] != 0:
                ctx.notes.append(f"{path}: <option {key}={v[0]:g}> ignored: robokit models no fluid forces")
        for key, words in _OPTION_WORDS.items():
            if key in opt.attrib and opt.get(key) not in words:
                raise InputError(f"{path}: <option {key}={opt.get(key)!r}>: expected {' or '.join(words)} (MuJoCo "
                                 "refuses the file: invalid keyword)")
        for flag in opt.findall("flag"):
            for key, word in flag.attrib.items():
                if word not in ("enable", "disable"):
                    raise InputError(f"{path}: <flag {key}={word!r}>: expected enable or disable (MuJoCo refuses the "
                                     "file: invalid keyword)")
            if flag.get("gravity") == "disable":
                gravity = np.zeros(3)
    comp = [(b.name, " ".join(b.elem.get("gravcomp", "").split())) for b in bodies[1:]
            if b.elem is not None and float(b.elem.get("gravcomp", "0") or 0) != 0]
    if comp:  # one note for every body that has it, as for the joint attributes below
        shown = ", ".join(repr(n) for n, _ in comp[:6]) + (f" and {len(comp) - 6} more" if len(comp) > 6 else "")
        values = list(dict.fromkeys(v for _, v in comp))
        listed = ", ".join(values[:6]) + (", …" if len(values) > 6 else "")
        ctx.notes.append(f"{path}: <body> gravcomp of bod{'ies' if len(comp) > 1 else 'y'} {shown} [{listed}] ignored: "
                         "robokit's dynamics has no gravity compensation force (its gravity torques and inverse "
                         "dynamics carry these bodies' full weight; MuJoCo counts the compensation as a passive "
                         "force, which mj_inverse leaves out unless the joint has actuatorgravcomp)")
    for key, owners in ctx.joint_extras.items():  # one note per attribute, every joint that has it
        joints = [n for n, _ in owners]
        shown = ", ".join(repr(n) for n in joints[:6]) + (f" and {len(joints) - 6} more" if len(joints) > 6 else "")
        values = list(dict.fromkeys(v for _, v in owners))
        listed = ", ".join(values[:6]) + (", …" if len(values) > 6 else "")
        ctx.notes.append(f"{path}: <joint> {key} of joint{'s' if len(joints) > 1 else ''} {shown} [{listed}] "
                         f"ignored: {_JOINT_EXTRAS_WHY[key]}")
    excluded = []
    for contact in root.findall("contact"):
        for ex in contact.findall("exclude"):
            b1, b2 = ex.get("body1"), ex.get("body2")
            if b1 is None or b2 is None:
                raise InputError(f"{path}: <exclude> needs body1 and body2")
            excluded.append((b1, b2))
    names = {b.name for b in bodies}
    for b1, b2 in excluded:
        for bn in (b1, b2):
            if bn not in names:
                raise InputError(f"{path}: <exclude body1={b1!r} body2={b2!r}>: no body {bn!r}")
    frozen = tuple(MjcfBody(name=b.name, parent=b.parent, pos=np.array(b.pos), quat=np.array(b.quat),
                            joints=tuple(b.joints), mass=float(b.mass), ipos=np.array(b.ipos), iquat=np.array(b.iquat),
                            inertia=np.array(b.inertia), geoms=tuple(b.geoms), sites=tuple(b.sites), named=b.named,
                            mocap=b.mocap) for b in bodies)
    compiler = {k: v for k, v in ctx.compiler.items() if k not in ("allow_outside_meshes", "package_dirs")}
    return CompiledMjcf(name=root.get("model") or path.stem, path=str(path), bodies=frozen, gravity=gravity,
                        compiler=compiler, excluded=tuple(excluded), notes=tuple(dict.fromkeys(ctx.notes)))
