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
±π (revolute) or ±1 m (prismatic); effort 1000 and velocity 10 are placeholders.

Visual geometry: a cylinder on every joint axis and a thinner cylinder from each joint to the
next one (and to the tool), sized from the arm's dimensions, so meshcat shows the arm.
"""
from __future__ import annotations

from xml.sax.saxutils import quoteattr

import numpy as np
from numpy.typing import ArrayLike

from robokit.description.dh import DHTable, dh_transform, rpy_from_matrix
from robokit.errors import InputTypeError
from robokit._deprecation import deprecated_alias

__all__ = ["urdf_from_dh"]


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


def _cylinder_between(p0: ArrayLike, p1: ArrayLike, radius: float, material: str) -> str | None:
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
    return (f"<visual>{_origin(T)}<geometry><cylinder radius=\"{_f(radius)}\" length=\"{_f(length)}\"/>"
            f"</geometry><material name=\"{material}\"/></visual>")


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
    qlim = table.qlim
    lines = ['<?xml version="1.0"?>', f"<robot name={quoteattr(table.name)}>",
             '  <material name="robokit_joint"><color rgba="0.95 0.55 0.1 1"/></material>',
             '  <material name="robokit_link"><color rgba="0.55 0.6 0.7 1"/></material>',
             '  <material name="robokit_base"><color rgba="0.3 0.3 0.35 1"/></material>',
             '  <link name="base_link"/>']
    # dh_0 carries the base plinth visual: a cylinder on joint 1's axis where it starts
    base_vis = ""
    if table.convention == "standard":
        base_vis = _cylinder_between([0, 0, -0.6 * r_joint], [0, 0, 0.6 * r_joint], 1.6 * r_joint, "robokit_base") or ""
    lines.append(f'  <link name="dh_0">{base_vis}</link>')
    lines.append(f'  <joint name="base_to_dh_0" type="fixed"><parent link="base_link"/><child link="dh_0"/>'
                 f"{_origin(table.base)}</joint>")
    for i, l in enumerate(table.links, start=1):
        Fi = F[i - 1]
        parts = []
        if l.mass > 0 or np.any(np.asarray(l.inertia) != 0):
            Tc = Fi.copy()
            Tc[:3, 3] = Fi[:3, :3] @ np.asarray(l.com, float) + Fi[:3, 3]
            xx, yy, zz, xy, yz, xz = (float(v) for v in l.inertia)
            parts.append(f"<inertial>{_origin(Tc)}<mass value=\"{_f(l.mass)}\"/>"
                         f"<inertia ixx=\"{_f(xx)}\" ixy=\"{_f(xy)}\" ixz=\"{_f(xz)}\" iyy=\"{_f(yy)}\" "
                         f"iyz=\"{_f(yz)}\" izz=\"{_f(zz)}\"/></inertial>")
        # joint i's axis passes through link_i's origin along z
        v = _cylinder_between([0, 0, -1.2 * r_joint], [0, 0, 1.2 * r_joint], r_joint, "robokit_joint")
        if v:
            parts.append(v)
        # segment(s) to the next joint's origin (or the tool): through the DH frame origin
        nxt = (F[i - 1] @ O[i])[:3, 3] if i < n else (Fi @ table.tool)[:3, 3]
        mid = Fi[:3, 3]
        for a, b in (([0, 0, 0], [0, 0, mid[2]]), ([0, 0, mid[2]], mid), (mid, nxt)):
            v = _cylinder_between(a, b, r_link, "robokit_link")
            if v:
                parts.append(v)
        lines.append(f'  <link name="link_{i}">{"".join(parts)}</link>')
        jtype = "revolute" if l.joint == "R" else "prismatic"
        lines.append(
            f'  <joint name="joint_{i}" type="{jtype}"><parent link="dh_{i - 1}"/><child link="link_{i}"/>'
            f'{_origin(O[i - 1])}<axis xyz="0 0 {-1 if l.flip else 1}"/>'
            f'<limit lower="{_f(qlim[i - 1, 0])}" upper="{_f(qlim[i - 1, 1])}" effort="1000" velocity="10"/></joint>'
        )
        lines.append(f'  <link name="dh_{i}"/>')
        lines.append(f'  <joint name="link_{i}_to_dh_{i}" type="fixed"><parent link="link_{i}"/>'
                     f'<child link="dh_{i}"/>{_origin(Fi)}</joint>')
    tip_vis = _cylinder_between([0, 0, 0], [0, 0, 0.5 * r_joint], 0.7 * r_joint, "robokit_joint") or ""
    lines.append(f'  <link name="tool">{tip_vis}</link>')
    lines.append(f'  <joint name="dh_{n}_to_tool" type="fixed"><parent link="dh_{n}"/><child link="tool"/>'
                 f"{_origin(table.tool)}</joint>")
    lines.append("</robot>")
    return "\n".join(lines) + "\n"

# Former names (before the X_from_Y rule): they warn and call the new function.
dh_to_urdf = deprecated_alias(urdf_from_dh, "dh_to_urdf")
