r"""A URDF document as a :class:`~robokit.description.model_builder.Description` (the builder's input).

:func:`description_from_urdf` reads the text :func:`robokit.description.urdf_check.read_urdf`
has checked (meshes resolved to absolute paths, missing ones already dropped) with urdfdom's
rules, which Pinocchio's URDF parser follows:

* a link's ``<inertial>``: ``<origin xyz rpy>`` (default zero) places the centre of mass and the
  inertia axes, ``<mass value>``, ``<inertia ixx … izz>`` (missing entries 0);
* a joint's ``<origin>`` is its frame in the parent link's frame, and the child link's frame is
  the joint frame; ``<axis xyz>`` defaults to x; ``<limit lower upper effort velocity>``
  (a continuous joint without ``<limit>``: unlimited effort and velocity); ``<dynamics damping
  friction>``;
* joints are taken in the order urdfdom builds its tree — the children of each link sorted by
  joint name — so that the model's joints come out in the order Pinocchio's parser gives them;
* ``<visual>``/``<collision>``: ``<origin>``, box/cylinder/sphere/mesh (``scale``), and for a
  visual the ``<material>``'s colour (a named material is global: its first definition, at the
  robot's top level or in an earlier link, wins). A colour is read as urdfdom reads it
  (:func:`material_color`): ``rgba`` split at spaces, each part a number from 0 to 1; a part that
  is not leaves the material without a colour (a visual's material is then no material: the
  default colour; a top-level one is black), and a count other than four leaves it black. The
  URDF reader notes each such colour (:func:`color_problem`); nothing else depends on it.

``<mimic>``, ``<transmission>``, ``<gazebo>`` and ``<safety_controller>`` are not read here (the
URDF loader reports the first and refuses a mimic joint on the chain); the reflected rotor inertia
Drake's transmissions give (:func:`robokit.description.urdf_check.read_urdf` reads them) comes in as
``armature``.

:func:`robokit.description.urdf_files.load_urdf` (and so xacro, whose expansion is URDF) builds
every URDF robot this way; the tests hold the result equal to Pinocchio's own URDF parser
(``pinocchio.buildModelFromXML``/``buildGeomFromUrdfString``) on the shipped, example-robot-data
and maker-published arms: the same frames, joints, inertias, limits and geometry.
"""
from __future__ import annotations

import math
import re
import xml.etree.ElementTree as ET
from typing import Mapping, Sequence

from robokit.description.model_builder import JOINT_KINDS, Description, Geometry, Inertial, Joint, Link, Pose
from robokit.errors import InputError

__all__ = ["color_problem", "description_from_urdf", "material_color"]


def _floats(text: str | None, n: int, default: tuple[float, ...], where: str) -> tuple[float, ...]:
    if text is None:
        return default
    what = "a finite number" if n == 1 else f"{n} finite numbers"
    try:
        vals = tuple(float(t) for t in text.split())
    except ValueError:
        raise InputError(f"{where}: expected {what}, got {text!r}") from None
    if len(vals) != n or not all(math.isfinite(v) for v in vals):
        raise InputError(f"{where}: expected {what}, got {text!r}")
    return vals


def _rotation_from_rpy(roll: float, pitch: float, yaw: float) -> tuple[float, ...]:
    """The rotation ``Rz(yaw) Ry(pitch) Rx(roll)`` computed the way urdfdom and Pinocchio compute it, to the
    last bit: urdfdom's ``Rotation::setFromRPY`` (the half-angle quaternion, normalised), then Eigen's
    quaternion-to-matrix. A model built from these numbers equals Pinocchio's URDF parser's exactly, so
    what is an exact zero there (an axis offset, a product of inertia) is one here too; the generated
    C's constants depend on it."""
    phi, the, psi = roll / 2.0, pitch / 2.0, yaw / 2.0
    sp, cp, st, ct, ss, cs = (math.sin(phi), math.cos(phi), math.sin(the), math.cos(the), math.sin(psi),
                              math.cos(psi))
    x = sp * ct * cs - cp * st * ss
    y = cp * st * cs + sp * ct * ss
    z = cp * ct * ss - sp * st * cs
    w = cp * ct * cs + sp * st * ss
    n = math.sqrt(x * x + y * y + z * z + w * w)
    x, y, z, w = (0.0, 0.0, 0.0, 1.0) if n == 0.0 else (x / n, y / n, z / n, w / n)
    tx, ty, tz = 2.0 * x, 2.0 * y, 2.0 * z
    twx, twy, twz = tx * w, ty * w, tz * w
    txx, txy, txz = tx * x, ty * x, tz * x
    tyy, tyz, tzz = ty * y, tz * y, tz * z
    return (1.0 - (tyy + tzz), txy - twz, txz + twy,
            txy + twz, 1.0 - (txx + tzz), tyz - twx,
            txz - twy, tyz + twx, 1.0 - (txx + tyy))


def _origin(el: ET.Element | None, where: str) -> Pose:
    if el is None:
        return Pose()
    o = el.find("origin")
    if o is None:
        return Pose()
    xyz = _floats(o.get("xyz"), 3, (0.0, 0.0, 0.0), f"{where} <origin xyz>")
    roll, pitch, yaw = _floats(o.get("rpy"), 3, (0.0, 0.0, 0.0), f"{where} <origin rpy>")
    return Pose(_rotation_from_rpy(roll, pitch, yaw), (xyz[0], xyz[1], xyz[2]))


def _product(A: Sequence[float], B: Sequence[float]) -> list[float]:
    """A·B of two row-major 3×3 matrices, each entry summed left to right (as Eigen's 3×3 product does)."""
    return [A[3 * i] * B[j] + A[3 * i + 1] * B[3 + j] + A[3 * i + 2] * B[6 + j] for i in range(3) for j in range(3)]


def _attr(el: ET.Element | None, key: str, default: float, where: str) -> float:
    if el is None or el.get(key) is None:
        return default
    return _floats(el.get(key), 1, (default,), f"{where} {key}")[0]


def _inertial(link: ET.Element, where: str) -> Inertial | None:
    el = link.find("inertial")
    if el is None:
        return None
    mass = _attr(el.find("mass"), "value", 0.0, f"{where} <mass>")
    ine = el.find("inertia")
    ixx, ixy, ixz, iyy, iyz, izz = (_attr(ine, k, 0.0, f"{where} <inertia>")
                                    for k in ("ixx", "ixy", "ixz", "iyy", "iyz", "izz"))
    frame = _origin(el, f"{where} <inertial>")
    # R I Rᵀ in Pinocchio's URDF parser's order, its lower triangle kept (Pinocchio's Symmetric3 reads that)
    R = frame.rotation
    Rt = (R[0], R[3], R[6], R[1], R[4], R[7], R[2], R[5], R[8])
    J = _product(_product(R, (ixx, ixy, ixz, ixy, iyy, iyz, ixz, iyz, izz)), Rt)
    return Inertial(mass, frame.translation, (J[0], J[3], J[6], J[4], J[7], J[8]))


#: A number as urdfdom's ``strToDouble`` reads one (a C++ stream of the classic locale, read to the end):
#: no NaN, infinity, hexadecimal or digit separators.
_CXX_DOUBLE = re.compile(r"[+-]?(?:\d+\.?\d*|\.\d+)(?:[eE][+-]?\d+)?\Z")
#: The colour urdfdom gives a material whose ``rgba`` it could not take (``Color::clear``).
_CLEARED = (0.0, 0.0, 0.0, 1.0)


def _rgba(text: str) -> tuple[float, ...] | None:
    """urdfdom's reading of an ``rgba``: the parts between spaces (tabs do not separate), each a
    number from 0 to 1; None if a part is not."""
    values = []
    for part in text.split(" "):
        if not part:
            continue
        if not _CXX_DOUBLE.match(part):
            return None
        v = float(part)
        if not 0.0 <= v <= 1.0:
            return None
        values.append(v)
    return tuple(values)


def color_problem(material: ET.Element) -> str | None:
    """What urdfdom cannot take in a ``<material>``'s ``<color rgba>``, or None.

    Parameters
    ----------
    material : xml.etree.ElementTree.Element
        A ``<material>`` element.

    Returns
    -------
    str or None
        ``"<color rgba='…'> is not 4 numbers from 0 to 1"`` for an ``rgba`` urdfdom does not read
        as a colour (:func:`material_color` says what it does instead), else None.
    """
    c = material.find("color")
    text = c.get("rgba") if c is not None else None
    if text is None:
        return None
    values = _rgba(text)
    if values is not None and len(values) == 4:
        return None
    return f"<color rgba={text!r}> is not 4 numbers from 0 to 1"


def material_color(material: ET.Element) -> tuple[float, float, float, float] | None:
    """A ``<material>``'s colour as urdfdom's ``parseMaterial`` reads it.

    Parameters
    ----------
    material : xml.etree.ElementTree.Element
        A ``<material>`` element (at the robot's top level or in a ``<visual>``).

    Returns
    -------
    tuple of 4 float or None
        The ``rgba`` of four numbers from 0 to 1; black (0, 0, 0, 1) for an ``rgba`` of parts
        from 0 to 1 but not four of them, or for a material with only a ``<texture filename>``
        or a part that is not such a number beside a texture; None for a material urdfdom finds
        undefined (no ``rgba``, or a part that is not a number from 0 to 1, and no texture).
    """
    c = material.find("color")
    text = c.get("rgba") if c is not None else None
    values = _rgba(text) if text is not None else None
    texture = material.find("texture")
    if values is None:
        return _CLEARED if texture is not None and texture.get("filename") is not None else None
    if len(values) != 4:
        return _CLEARED
    return (values[0], values[1], values[2], values[3])


def _color(visual: ET.Element, materials: dict[str, tuple[float, float, float, float]],
           where: str) -> tuple[float, float, float, float] | None:
    """A visual's colour by urdfdom's rule: a named material is global, its first definition wins;
    a material defined in place that urdfdom finds undefined is no material (None)."""
    mat = visual.find("material")
    if mat is None:
        return None
    name = mat.get("name", "")
    if name and name in materials:
        return materials[name]
    color = material_color(mat)
    if color is not None and name:
        materials[name] = color
    return color


def _geometries(link: ET.Element, name: str, materials: dict[str, tuple[float, float, float, float]],
                source: str) -> list[Geometry]:
    out = []
    for role in ("visual", "collision"):
        for el in link.findall(role):
            where = f"{source}: link {name!r} <{role}>"
            g = el.find("geometry")
            shape = next(iter(g), None) if g is not None else None
            if shape is None:
                continue
            placement = _origin(el, where)
            color = _color(el, materials, where) if role == "visual" else None
            common = dict(placement=placement, collision=role == "collision", color=color)
            if shape.tag == "box":
                size = _floats(shape.get("size"), 3, (0.0, 0.0, 0.0), f"{where} <box size>")
                out.append(Geometry(name, "box", size=size, **common))  # type: ignore[arg-type]
            elif shape.tag == "cylinder":
                size = (_attr(shape, "radius", 0.0, where), _attr(shape, "length", 0.0, where))
                out.append(Geometry(name, "cylinder", size=size, **common))  # type: ignore[arg-type]
            elif shape.tag == "sphere":
                out.append(Geometry(name, "sphere", size=(_attr(shape, "radius", 0.0, where),),
                                    **common))  # type: ignore[arg-type]
            elif shape.tag == "mesh":
                sx, sy, sz = _floats(shape.get("scale"), 3, (1.0, 1.0, 1.0), f"{where} <mesh scale>")
                out.append(Geometry(name, "mesh", mesh=shape.get("filename"), scale=(sx, sy, sz),
                                    **common))  # type: ignore[arg-type]
    return out


def description_from_urdf(text: str | bytes, source: str = "<URDF>",
                          armature: Mapping[str, float] | None = None) -> Description:
    """The :class:`~robokit.description.model_builder.Description` of a URDF document.

    Parameters
    ----------
    text : str or bytes
        The URDF, as :func:`robokit.description.urdf_check.read_urdf` returns it (checked,
        meshes resolved).
    source : str
        Names the document in messages.
    armature : mapping of str to float, optional
        Joint name → reflected rotor inertia (kg·m², kg for a prismatic joint), the joint's
        :attr:`~robokit.description.model_builder.Joint.armature` (default none).

    Returns
    -------
    Description
        Links, joints (in urdfdom's order), geometry; gravity (0, 0, −9.81).

    Raises
    ------
    InputError
        A number that does not parse, a joint of an unknown kind, no single root link.

    Examples
    --------
    >>> from robokit.description.models import model_path
    >>> desc = description_from_urdf(model_path("rrr", ".urdf").read_text())
    >>> [j.name for j in desc.joints if j.kind == "revolute"]
    ['joint_1', 'joint_2', 'joint_3']
    """
    from robokit._xml import parse_xml

    root = parse_xml(text, source, namespaces=False)  # names as written, as urdfdom reads them
    materials: dict[str, tuple[float, float, float, float]] = {}
    for mat in root.findall("material"):  # urdfdom keeps a top-level material whatever its colour
        materials.setdefault(mat.get("name", ""), material_color(mat) or _CLEARED)
    links, geoms = [], []
    for el in root.findall("link"):
        name = el.get("name", "")
        links.append(Link(name, _inertial(el, f"{source}: link {name!r}")))
        geoms.extend(_geometries(el, name, materials, source))
    by_parent: dict[str, list[Joint]] = {}
    child_of: set[str] = set()
    for el in root.findall("joint"):
        name, kind = el.get("name", ""), el.get("type", "")
        where = f"{source}: joint {name!r}"
        if kind not in JOINT_KINDS:
            raise InputError(f"{where}: a {kind!r} joint; a URDF joint is one of {', '.join(JOINT_KINDS)}")
        parent_el, child_el = el.find("parent"), el.find("child")
        parent = parent_el.get("link", "") if parent_el is not None else ""
        child = child_el.get("link", "") if child_el is not None else ""
        child_of.add(child)
        axis_el = el.find("axis")
        axis = _floats(axis_el.get("xyz") if axis_el is not None else None, 3, (1.0, 0.0, 0.0), f"{where} <axis xyz>")
        lim, dyn = el.find("limit"), el.find("dynamics")
        unlimited = kind == "continuous" and lim is None
        joint = Joint(name, kind, parent, child, _origin(el, where), axis=(axis[0], axis[1], axis[2]),
                      lower=_attr(lim, "lower", 0.0, f"{where} <limit>"),
                      upper=_attr(lim, "upper", 0.0, f"{where} <limit>"),
                      effort=math.inf if unlimited else _attr(lim, "effort", 0.0, f"{where} <limit>"),
                      velocity=math.inf if unlimited else _attr(lim, "velocity", 0.0, f"{where} <limit>"),
                      damping=_attr(dyn, "damping", 0.0, f"{where} <dynamics>"),
                      friction=_attr(dyn, "friction", 0.0, f"{where} <dynamics>"),
                      armature=(armature or {}).get(name, 0.0))
        by_parent.setdefault(parent, []).append(joint)
    roots = [link.name for link in links if link.name not in child_of]
    if len(roots) != 1:
        raise InputError(f"{source}: expected one root link, found {len(roots)}: {', '.join(roots[:8])}")
    # the builder adds each link's children in the order given: by joint name, as urdfdom's std::map
    joints = sorted((j for js in by_parent.values() for j in js), key=lambda j: j.name)
    return Description(root.get("name", "robot"), tuple(links), tuple(joints), geometries=tuple(geoms))
