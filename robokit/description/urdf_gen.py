r"""DH table → URDF (frame conventions: the "Generated and loaded URDFs" page of the documentation).

Layout of the generated URDF, for joint i = 1..N:

``dh_{i−1}`` —joint_i (revolute/prismatic about z — about −z for a flipped joint —, origin Oᵢ)→ ``link_i`` —fixed (origin Fᵢ)→ ``dh_i``

* standard convention: joint i moves about z_{i−1}, so Oᵢ = I and
  Fᵢ = Rz(θᵢ) Tz(dᵢ) Tx(aᵢ) Rx(αᵢ) (θᵢ, dᵢ the offsets);
* modified convention: joint i moves about z_i, so Oᵢ = Rx(α_{i−1}) Tx(a_{i−1}) Rz(θᵢ) Tz(dᵢ)
  and Fᵢ = I.

Because Rz(q) commutes with Rz(θ) and Tz(d) (and Tz(q) with both), the pose of ``dh_i`` is
exactly ⁰Tᵢ for every q. The moving body of link i is ``link_i``; its mass, centre of mass
and inertia, given in DH frame {i}, are written in ``link_i``'s frame with the fixed
transform Fᵢ (centre of mass ``Fᵢ · com``, inertia axes rotated by the rotation of Fᵢ through
the ``<inertial><origin rpy>``), so the URDF describes the same rigid body in both
conventions. The root link is ``base_link`` with ``dh_0`` fixed at the table's ``base``; the
``tool`` link is fixed to ``dh_N`` at the table's ``tool``. Missing joint limits become
±π (revolute) or ±1 m (prismatic) in the URDF text (which needs numbers; the robot robokit
builds from the table itself leaves those joints unlimited, ±inf); effort 1000 and velocity
10 are placeholders.

Visual geometry: a cylinder on every joint axis and a thinner cylinder from each joint to the
next one (and to the tool), sized from the arm's dimensions, so meshcat shows the arm.
"""
from __future__ import annotations

from dataclasses import dataclass, field
from xml.sax.saxutils import quoteattr

import numpy as np
from numpy.typing import ArrayLike

from robokit.description.dh import DHTable, dh_transform, rpy_from_matrix
from robokit.description.model_builder import Description, Geometry, Inertial, Joint, Link, Pose
from robokit.errors import InputTypeError
from robokit._deprecation import deprecated_alias

__all__ = ["urdf_from_dh", "description_from_dh"]


def _f(x: float) -> str:
    """A float with full round-trip precision, without noise like '-0'."""
    x = float(x)
    if x == 0.0:
        return "0"
    return repr(x)


def _vec(v: np.ndarray) -> str:
    return " ".join(_f(x) for x in v)


def _origin(T: np.ndarray) -> str:
    T = np.asarray(T, dtype=float)
    return f'<origin xyz="{_vec(T[:3, 3])}" rpy="{_vec(rpy_from_matrix(T[:3, :3]))}"/>'


#: The colours of the generated robot's visuals (URDF materials).
MATERIALS = {"robokit_joint": (0.95, 0.55, 0.1, 1.0), "robokit_link": (0.55, 0.6, 0.7, 1.0),
             "robokit_base": (0.3, 0.3, 0.35, 1.0)}


def _cylinder_pose(p0: ArrayLike, p1: ArrayLike) -> tuple[np.ndarray, float] | None:
    """(pose of a cylinder whose axis runs from p0 to p1, its length); None when they coincide."""
    p0, p1 = np.asarray(p0, float), np.asarray(p1, float)
    d = p1 - p0
    length = float(np.linalg.norm(d))
    if length < 1e-9:
        return None
    z = d / length
    ref = np.array([1.0, 0.0, 0.0]) if abs(z[0]) < 0.9 else np.array([0.0, 1.0, 0.0])
    x = np.cross(ref, z)
    x /= np.linalg.norm(x)
    y = np.cross(z, x)
    T = np.eye(4)
    T[:3, :3] = np.column_stack([x, y, z])
    T[:3, 3] = 0.5 * (p0 + p1)
    return T, length


def _visual_text(T: np.ndarray, radius: float, length: float, material: str) -> str:
    return (f"<visual>{_origin(T)}<geometry><cylinder radius=\"{_f(radius)}\" length=\"{_f(length)}\"/>"
            f"</geometry><material name=\"{material}\"/></visual>")


def _cylinder_between(p0: ArrayLike, p1: ArrayLike, radius: float, material: str) -> str | None:
    c = _cylinder_pose(p0, p1)
    return None if c is None else _visual_text(c[0], radius, c[1], material)


@dataclass(frozen=True)
class _Cylinder:
    T: np.ndarray
    radius: float
    length: float
    material: str


@dataclass
class _DHLayout:
    """The generated robot, structured: what :func:`urdf_from_dh` writes and :func:`description_from_dh` builds."""

    links: list[tuple[str, tuple[np.ndarray, float, tuple[float, ...]] | None, list[_Cylinder]]] = field(
        default_factory=list)  # (name, (T_link_com, mass, (xx, yy, zz, xy, yz, xz)) or None, visuals)
    joints: list[tuple[str, str, str, str, np.ndarray, float, float, float]] = field(
        default_factory=list)  # (name, kind, parent, child, origin, axis z sign, lower, upper)


def _layout(table: DHTable) -> _DHLayout:
    if not isinstance(table, DHTable):
        raise InputTypeError(f"table: expected a DHTable, got {type(table).__name__}")
    n = table.n
    scale = max([abs(l.a) for l in table.links] + [abs(l.d) for l in table.links] + [0.1])
    r_joint = max(0.01, 0.08 * scale)
    r_link = 0.45 * r_joint
    I4 = np.eye(4)
    O, F = [], []
    for l in table.links:
        if table.convention == "standard":
            O.append(I4)
            F.append(dh_transform(l.a, l.alpha, l.d, l.theta, "standard"))
        else:
            O.append(dh_transform(l.a, l.alpha, l.d, l.theta, "modified"))
            F.append(I4)

    def cyl(p0: ArrayLike, p1: ArrayLike, radius: float, material: str) -> list[_Cylinder]:
        c = _cylinder_pose(p0, p1)
        return [] if c is None else [_Cylinder(c[0], radius, c[1], material)]

    qlim = table.qlim
    out = _DHLayout()
    out.links.append(("base_link", None, []))
    # dh_0 carries the base plinth visual: a cylinder on joint 1's axis where it starts
    base_vis = cyl([0, 0, -0.6 * r_joint], [0, 0, 0.6 * r_joint], 1.6 * r_joint, "robokit_base") \
        if table.convention == "standard" else []
    out.links.append(("dh_0", None, base_vis))
    out.joints.append(("base_to_dh_0", "fixed", "base_link", "dh_0", np.asarray(table.base, float), 1.0, 0.0, 0.0))
    for i, l in enumerate(table.links, start=1):
        Fi = F[i - 1]
        inertial = None
        if l.mass > 0 or np.any(np.asarray(l.inertia) != 0):
            Tc = Fi.copy()
            Tc[:3, 3] = Fi[:3, :3] @ np.asarray(l.com, float) + Fi[:3, 3]
            inertial = (Tc, float(l.mass), tuple(float(v) for v in l.inertia))
        # joint i's axis passes through link_i's origin along z
        visuals = cyl([0, 0, -1.2 * r_joint], [0, 0, 1.2 * r_joint], r_joint, "robokit_joint")
        # segment(s) to the next joint's origin (or the tool): through the DH frame origin
        nxt = (F[i - 1] @ O[i])[:3, 3] if i < n else (Fi @ table.tool)[:3, 3]
        mid = Fi[:3, 3]
        for a, b in (([0, 0, 0], [0, 0, mid[2]]), ([0, 0, mid[2]], mid), (mid, nxt)):
            visuals += cyl(a, b, r_link, "robokit_link")
        out.links.append((f"link_{i}", inertial, visuals))
        out.joints.append((f"joint_{i}", "revolute" if l.joint == "R" else "prismatic", f"dh_{i - 1}", f"link_{i}",
                           O[i - 1], -1.0 if l.flip else 1.0, float(qlim[i - 1, 0]), float(qlim[i - 1, 1])))
        out.links.append((f"dh_{i}", None, []))
        out.joints.append((f"link_{i}_to_dh_{i}", "fixed", f"link_{i}", f"dh_{i}", Fi, 1.0, 0.0, 0.0))
    out.links.append(("tool", None, cyl([0, 0, 0], [0, 0, 0.5 * r_joint], 0.7 * r_joint, "robokit_joint")))
    out.joints.append((f"dh_{n}_to_tool", "fixed", f"dh_{n}", "tool", np.asarray(table.tool, float), 1.0, 0.0, 0.0))
    return out


def urdf_from_dh(table: DHTable) -> str:
    r"""The URDF text of a :class:`DHTable`; it loads in Pinocchio and yourdfpy.

    The layout is the one of the URDF format page of the documentation: root link ``base_link``,
    a massless link ``dh_<i>`` fixed at each DH frame {i} (base transform applied), joints
    ``joint_<i>`` with the table's limits, the links' inertia carried into the URDF link frames,
    a ``tool`` link at ``T_base_N · tool`` and simple visual geometry.

    Parameters
    ----------
    table : DHTable
        The arm (either convention; lengths in m, angles in rad).

    Returns
    -------
    str
        The URDF document (XML text).

    Examples
    --------
    >>> table = rk.load("twolink").dh
    >>> urdf = urdf_from_dh(table)
    >>> urdf.count("<joint name=\"joint_"), "<link name=\"tool\"" in urdf
    (2, True)
    """
    lay = _layout(table)
    lines = ['<?xml version="1.0"?>', f"<robot name={quoteattr(table.name)}>"]
    lines += [f'  <material name="{m}"><color rgba="{" ".join(_f(c) if c != 1.0 else "1" for c in rgba)}"/>'
              "</material>" for m, rgba in MATERIALS.items()]
    joints = {j[3]: j for j in lay.joints}  # by child link: each link is followed by the joint to it
    for name, inertial, visuals in lay.links:
        parts = []
        if inertial is not None:
            Tc, mass, (xx, yy, zz, xy, yz, xz) = inertial
            parts.append(f"<inertial>{_origin(Tc)}<mass value=\"{_f(mass)}\"/>"
                         f"<inertia ixx=\"{_f(xx)}\" ixy=\"{_f(xy)}\" ixz=\"{_f(xz)}\" iyy=\"{_f(yy)}\" "
                         f"iyz=\"{_f(yz)}\" izz=\"{_f(zz)}\"/></inertial>")
        parts += [_visual_text(v.T, v.radius, v.length, v.material) for v in visuals]
        bare = name == "base_link" or (name.startswith("dh_") and name != "dh_0")  # written as <link .../>
        lines.append(f'  <link name="{name}"/>' if bare else f'  <link name="{name}">{"".join(parts)}</link>')
        if name in joints:
            jn, kind, parent, child, origin, sign, lo, hi = joints[name]
            if kind == "fixed":
                lines.append(f'  <joint name="{jn}" type="fixed"><parent link="{parent}"/><child link="{child}"/>'
                             f"{_origin(origin)}</joint>")
            else:
                lines.append(
                    f'  <joint name="{jn}" type="{kind}"><parent link="{parent}"/><child link="{child}"/>'
                    f'{_origin(origin)}<axis xyz="0 0 {-1 if sign < 0 else 1}"/>'
                    f'<limit lower="{_f(lo)}" upper="{_f(hi)}" effort="1000" velocity="10"/></joint>')
    lines.append("</robot>")
    return "\n".join(lines) + "\n"


def description_from_dh(table: DHTable) -> Description:
    """The :class:`~robokit.description.model_builder.Description` of a :class:`DHTable`: the layout
    :func:`urdf_from_dh` writes (the same links, joints, frames, inertials and shapes), for the model
    builder — poses as matrices, with no rpy angles in between.

    Parameters
    ----------
    table : DHTable
        The arm.

    Returns
    -------
    Description
        Gravity from the table; a joint without ``qlim`` unlimited (±inf: the robot's ``qlim``), where
        the URDF text writes ±π or ±1 m.

    Examples
    --------
    >>> desc = description_from_dh(rk.load("rrr").dh)
    >>> [j.name for j in desc.joints if j.kind == "revolute"]
    ['joint_1', 'joint_2', 'joint_3']
    """
    lay = _layout(table)
    links, geoms = [], []
    for name, inertial, visuals in lay.links:
        ine = None
        if inertial is not None:
            Tc, mass, (xx, yy, zz, xy, yz, xz) = inertial
            ine = Inertial.from_frame(mass, Pose.from_matrix(Tc), (xx, xy, xz, yy, yz, zz))
        links.append(Link(name, ine))
        geoms += [Geometry(name, "cylinder", Pose.from_matrix(v.T), (v.radius, v.length), color=MATERIALS[v.material])
                  for v in visuals]
    # a joint the table gives no qlim is unlimited in the robot (±inf, as robokit reads a URDF joint without
    # limits); only the URDF text needs numbers there (±π, ±1 m)
    free = iter([l.qlim is None for l in table.links])
    joints = []
    for jn, kind, parent, child, origin, sign, lo, hi in lay.joints:
        if kind == "fixed":
            joints.append(Joint(jn, "fixed", parent, child, Pose.from_matrix(origin)))
            continue
        if next(free):
            lo, hi = -np.inf, np.inf
        joints.append(Joint(jn, kind, parent, child, Pose.from_matrix(origin), axis=(0.0, 0.0, sign), lower=lo,
                            upper=hi, velocity=10.0, effort=1000.0))
    g = np.asarray(table.gravity, dtype=float)
    return Description(table.name, tuple(links), tuple(joints), geometries=tuple(geoms),
                       gravity=(float(g[0]), float(g[1]), float(g[2])))


# Former names (before the X_from_Y rule): they warn and call the new function.
dh_to_urdf = deprecated_alias(urdf_from_dh, "dh_to_urdf")
