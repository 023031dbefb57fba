r"""MJCF out: :func:`mjcf_from_robot` (``robokit convert ROBOT -o OUT.xml``).

Writing (:func:`mjcf_from_robot`, used by ``robokit convert ROBOT -o OUT.xml``)
    One MJCF body per joint of the robot's chain, placed in its parent body as Pinocchio's
    joint placement; the joint at the body's origin (``hinge``/``slide`` with the axis in the
    body frame, ``range`` from the limits, ``armature`` and ``damping``); the inertial
    (``mass``, ``pos`` of the centre of mass, the principal frame ``quat`` and moments
    ``diaginertia`` — not ``fullinertia``, which MuJoCo's compiler diagonalises only to about
    1e-6 rad); the
    visual geometry as MuJoCo geoms (primitives, or STL/OBJ meshes referenced by absolute
    path), or a capsule from the joint to the next joint where there is none; the tip frame
    as a ``<site>``; ``<option gravity>``. Lengths in m, angles in rad
    (``<compiler angle="radian">``), masses in kg. A joint's dry friction (a URDF's ``<dynamics
    friction>``) becomes its ``frictionloss`` and a finite, positive effort limit its
    ``actuatorfrcrange`` (± the limit), as MuJoCo's own URDF reader takes them; MJCF has no
    velocity limit, and a note lists the ones not written.

    MuJoCo's compiler rejects inertials that the course models use on purpose: a moving body
    with no mass (PUMA 560's link 1), point masses with no rotational inertia (the two-link
    arm) and inertia tensors that break the triangle inequality ``A + B ≥ C`` (PUMA 560's
    link 3, as published). For such a body the ``<inertial>`` holds the nearest values MuJoCo
    accepts (masses and principal moments raised to a floor, the two smaller moments raised
    until ``A + B = C``) and the exact values go in ``<custom><numeric
    name="robokit_inertial:BODY" data="m cx cy cz Ixx Iyy Izz Ixy Ixz Iyz"/>``; robokit reads
    the exact values back (so DH → MJCF → robokit is exact), and the exporter says on stderr
    which bodies MuJoCo alone will see differently.
"""
from __future__ import annotations

import os
from pathlib import Path
from typing import TYPE_CHECKING, Any, cast
from xml.sax.saxutils import quoteattr

import numpy as np
from numpy.typing import ArrayLike

from robokit.description.inertia import principal_moments, triangle_margin
from robokit.description.mjcf import CUSTOM_INERTIAL_PREFIX
from robokit._deprecation import deprecated_alias

if TYPE_CHECKING:
    from robokit.description.robot import Robot

__all__ = ["mjcf_from_robot", "joint_armature_damping"]

#: mesh files MuJoCo reads
_MUJOCO_MESH_EXT = {".stl", ".obj", ".msh"}
#: MuJoCo's mjMINVAL is 1e-15; the floor used for inertials MuJoCo would reject
_MASS_FLOOR = 1e-6
_INERTIA_FLOOR = 1e-9


def _f(x: float) -> str:
    x = float(x)
    return "0" if x == 0.0 else repr(x)


def _v(v: ArrayLike) -> str:
    return " ".join(_f(x) for x in np.ravel(v))


def _quat(R: np.ndarray) -> np.ndarray:
    """Unit quaternion (w, x, y, z) of a rotation, w ≥ 0."""
    import pinocchio as pin

    q = pin.Quaternion(np.asarray(R, dtype=float)).coeffs()  # (x, y, z, w)
    wxyz = np.array([q[3], q[0], q[1], q[2]])
    return -wxyz if wxyz[0] < 0 else wxyz


def _pose_attrs(T: np.ndarray) -> str:
    T = np.asarray(T, dtype=float)
    out = []
    if np.any(T[:3, 3] != 0):
        out.append(f'pos="{_v(T[:3, 3])}"')
    if not np.array_equal(T[:3, :3], np.eye(3)):
        out.append(f'quat="{_v(_quat(T[:3, :3]))}"')
    return " ".join(out)


def _mujoco_accepts(mass: float, I: np.ndarray) -> bool:
    """Would MuJoCo's compiler take this moving body's inertial as written? (Its floors on mass
    and moments, and the triangle inequality with a margin that survives MuJoCo's own rounding.)"""
    ev = principal_moments(I)
    if mass <= _MASS_FLOOR * 1e-3 or ev[0] <= _INERTIA_FLOOR * 1e-3:
        return False
    return triangle_margin(ev) >= 1e-9 * ev[2]


def _regularized(mass: float, I: np.ndarray) -> tuple[float, np.ndarray, np.ndarray]:
    """Nearest inertial MuJoCo accepts: (mass, principal moments (3,), rotation to principal axes)."""
    ev, V = np.linalg.eigh(I)
    if np.linalg.det(V) < 0:
        V[:, 0] = -V[:, 0]
    ev = np.maximum(ev, _INERTIA_FLOOR)
    order = np.argsort(ev)
    if triangle_margin(ev) < 0:
        gap = -0.5 * triangle_margin(ev) * (1 + 1e-9)
        ev[order[0]] += gap
        ev[order[1]] += gap
    return max(mass, _MASS_FLOOR), ev, V


def _joint_axis(model: Any, j: int) -> tuple[str, np.ndarray]:
    """(kind, axis in the joint frame) of a one-dof joint: kind "hinge" or "slide"."""
    import pinocchio as pin

    jm = model.joints[j]
    jd = jm.createData()
    jm.calc(jd, pin.neutral(model))
    S = np.asarray(jd.S).reshape(6, -1)[:, 0]  # (v; ω)
    if np.linalg.norm(S[3:]) > 1e-12:
        return "hinge", S[3:] / np.linalg.norm(S[3:])
    return "slide", S[:3] / np.linalg.norm(S[:3])


def _geom_xml(go: Any, mesh_assets: dict, color_default: str = "0.7 0.7 0.75 1") -> str | None:
    """A ``<geom>`` of one Pinocchio geometry object (placement relative to its joint), or
    None when MuJoCo cannot draw it."""
    import pinocchio as pin  # noqa: F401

    g = go.geometry
    kind = type(g).__name__
    color = np.asarray(go.meshColor, dtype=float)
    rgba = " ".join(f"{x:.4g}" for x in color) if np.any(color != 0) else color_default
    pose = _pose_attrs(go.placement.homogeneous)
    common = f'{pose} rgba="{rgba}" contype="0" conaffinity="0" group="1"'
    if kind == "Cylinder":
        return f'<geom type="cylinder" size="{_f(g.radius)} {_f(g.halfLength)}" {common}/>'
    if kind == "Capsule":
        return f'<geom type="capsule" size="{_f(g.radius)} {_f(g.halfLength)}" {common}/>'
    if kind == "Sphere":
        return f'<geom type="sphere" size="{_f(g.radius)}" {common}/>'
    if kind == "Box":
        return f'<geom type="box" size="{_v(np.asarray(g.halfSide))}" {common}/>'
    path = getattr(go, "meshPath", "") or ""
    if path and Path(path).suffix.lower() in _MUJOCO_MESH_EXT and Path(path).is_file():
        scale = tuple(float(s) for s in np.asarray(go.meshScale))
        key = (os.path.abspath(path), scale)
        if key not in mesh_assets:
            mesh_assets[key] = f"mesh_{len(mesh_assets)}"
        return f'<geom type="mesh" mesh="{mesh_assets[key]}" {common}/>'
    return None


def joint_armature_damping(robot: Robot) -> tuple[np.ndarray, np.ndarray]:
    """Armature (reflected rotor inertia) and viscous damping of each joint.

    For a robot from a DH file: ``G² Jm`` (kg·m²) and ``G² B`` (N·m·s/rad), the motor-side
    values referred to the joint; otherwise the model's ``armature`` and ``damping`` (from an
    MJCF file, or a URDF's ``<dynamics damping>``).

    Parameters
    ----------
    robot : Robot
        The robot.

    Returns
    -------
    armature : numpy.ndarray, shape (n,)
        Per joint, kg·m² (kg for prismatic joints).
    damping : numpy.ndarray, shape (n,)
        Per joint, N·m·s/rad (N·s/m for prismatic joints).

    Examples
    --------
    The Puma 560's joint 1: ``Jm = 2e-4`` kg·m², gear ratio −62.6111:

    >>> armature, damping = joint_armature_damping(rk.load("puma560"))
    >>> round(float(armature[0]), 4), round(2e-4 * 62.6111 ** 2, 4)
    (0.784, 0.784)
    """
    if robot.dh is not None:
        arm = np.array([l.joint_inertia for l in robot.dh.links])
        damp = np.array([l.G * l.G * l.B for l in robot.dh.links])
        return arm, damp
    model = robot.model
    idx = [model.joints[j].idx_v for j in range(1, model.njoints)]
    return np.array(model.armature)[idx], np.array(model.damping)[idx]


def mjcf_from_robot(robot: Robot) -> tuple[str, list[str]]:
    """MJCF text of a robot's chain, and notes for stderr (see the module docstring).

    Parameters
    ----------
    robot : Robot or str
        A :class:`robokit.Robot`, or anything :func:`robokit.load` accepts (a shipped
        model name, a DH ``.yaml``, a ``.urdf``/``.xacro``/``.xml`` file, an
        example-robot-data name).

    Returns
    -------
    text : str
        The MJCF document; MuJoCo (``mujoco.MjModel.from_xml_string``) and robokit load it.
    notes : list of str
        What was approximated or left out (inertials MuJoCo cannot take exactly, meshes
        MuJoCo cannot read, Coulomb friction).

    Notes
    -----
    Armature is the DH file's ``G² Jm`` (or the model's ``armature``); damping the DH
    file's ``G² B`` (or the URDF's ``<dynamics damping>``).

    Examples
    --------
    >>> text, notes = mjcf_from_robot(rk.load("twolink"))
    >>> '<mujoco model="twolink">' in text, text.count('type="hinge"')
    (True, 2)
    """
    import pinocchio as pin

    from robokit.description.loading import load
    from robokit.description.robot import Robot

    if not isinstance(robot, Robot):
        robot = load(robot)
    model = robot.model
    n = model.njoints - 1
    notes: list[str] = []
    armature, damping = joint_armature_damping(robot)
    if robot.dh is not None and any(np.any(np.asarray(l.Tc) != 0) for l in robot.dh.links):
        notes.append(f"{robot.name}: Coulomb friction Tc not written (MuJoCo's frictionloss is symmetric and "
                     "acts through the constraint solver)")
    # the file's dry friction and effort limits (a DH table's robot has placeholders for the limits, not written)
    iv = [model.joints[j].idx_v for j in range(1, n + 1)]
    friction = np.asarray(model.friction, dtype=float)[iv]
    effort = np.asarray(model.effortLimit, dtype=float)[iv] if robot.dh is None else np.full(n, np.inf)
    velocity = np.asarray(model.velocityLimit, dtype=float)[iv]
    if robot.dh is None and (np.isfinite(velocity) & (velocity > 0)).any():
        notes.append(f"{robot.name}: joint velocity limits not written (MJCF has none; "
                     f"{', '.join(f'{model.names[j]} {v:g}' for j, v in enumerate(velocity, 1) if np.isfinite(v))})")

    used: set = set()

    def unique(name: str) -> str:
        base, k = name, 1
        while name in used:
            k += 1
            name = f"{base}_{k}"
        used.add(name)
        return name

    body_names = {}
    for j in range(1, n + 1):
        cands = [f.name for f in model.frames if f.type == pin.FrameType.BODY and f.parentJoint == j]
        body_names[j] = unique(cands[0] if cands else f"{model.names[j]}_body")
    joint_names = {j: model.names[j] for j in range(1, n + 1)}

    # geometry per joint: visuals MuJoCo can read, else collisions, else a capsule to the next joint
    mesh_assets: dict = {}
    geoms_by_joint: dict[int, list[str]] = {j: [] for j in range(0, n + 1)}
    skipped: set[str] = set()
    for j in range(0, n + 1):
        for gm in (robot.visual_model, robot.collision_model):
            if gm is None:
                continue
            objs = [go for go in gm.geometryObjects if go.parentJoint == j]
            xml = [_geom_xml(go, mesh_assets) for go in objs]
            if objs and all(x is not None for x in xml):
                geoms_by_joint[j] = cast("list[str]", xml)  # none is None
                break
            skipped.update(Path(go.meshPath).suffix for go, x in zip(objs, xml) if x is None and go.meshPath)
    if skipped:
        notes.append(f"{robot.name}: meshes of type {', '.join(sorted(skipped))} not written (MuJoCo reads STL, OBJ, "
                     "MSH); those bodies get their collision meshes or a capsule between joint origins")
    scale = max(0.05, float(max(np.linalg.norm(model.jointPlacements[j].translation) for j in range(1, n + 1))))
    for j in range(1, n + 1):
        if geoms_by_joint[j]:
            continue
        p_next = model.jointPlacements[j + 1].translation if j < n else \
            model.frames[robot.tip_id].placement.translation
        r = 0.04 * scale
        if np.linalg.norm(p_next) > 1e-9:
            geoms_by_joint[j].append(f'<geom type="capsule" fromto="0 0 0 {_v(p_next)}" size="{_f(r)}" '
                                     'rgba="0.55 0.6 0.7 1" contype="0" conaffinity="0" group="1"/>')
        else:
            geoms_by_joint[j].append(f'<geom type="sphere" size="{_f(1.5 * r)}" rgba="0.95 0.55 0.1 1" '
                                     'contype="0" conaffinity="0" group="1"/>')

    customs = []
    lines_by_joint = {}
    for j in range(1, n + 1):
        Y = model.inertias[j]
        mass, c, I = float(Y.mass), np.array(Y.lever), np.array(Y.inertia)
        body = body_names[j]
        if _mujoco_accepts(mass, I):
            # principal axes computed here, exactly: MuJoCo's compiler would reduce a fullinertia
            # with a Jacobi iteration that stops about 1e-6 rad short of the principal frame
            ev, V = np.linalg.eigh(I)
            if np.linalg.det(V) < 0:
                V[:, 0] = -V[:, 0]
            inertial = (f'<inertial pos="{_v(c)}" quat="{_v(_quat(V))}" mass="{_f(mass)}" '
                        f'diaginertia="{_v(ev)}"/>')
        else:
            m2, ev, V = _regularized(mass, I)
            inertial = (f'<inertial pos="{_v(c)}" quat="{_v(_quat(V))}" mass="{_f(m2)}" '
                        f'diaginertia="{_v(ev)}"/>')
            data = [mass, *c, I[0, 0], I[1, 1], I[2, 2], I[0, 1], I[0, 2], I[1, 2]]
            customs.append(f'    <numeric name={quoteattr(CUSTOM_INERTIAL_PREFIX + body)} data="{_v(data)}"/>')
            notes.append(f"{robot.name}: body {body!r}: MuJoCo rejects its inertial (mass {mass:g} kg, principal "
                         f"moments {np.round(np.linalg.eigvalsh(I), 6).tolist()}); written as the nearest accepted one "
                         f"(mass {m2:g}, moments {np.round(ev, 6).tolist()}), exact values in <custom> for robokit")
        kind, axis = _joint_axis(model, j)
        jm = model.joints[j]
        attrs = [f'name={quoteattr(joint_names[j])}', f'type="{kind}"', f'axis="{_v(axis)}"']
        if jm.nq == 1:
            lo, hi = model.lowerPositionLimit[jm.idx_q], model.upperPositionLimit[jm.idx_q]
            if np.isfinite(lo) and np.isfinite(hi) and lo < hi:
                attrs.append(f'limited="true" range="{_f(lo)} {_f(hi)}"')
            else:
                attrs.append('limited="false"')
        else:
            attrs.append('limited="false"')
        if armature[j - 1] != 0:
            attrs.append(f'armature="{_f(armature[j - 1])}"')
        if damping[j - 1] != 0:
            attrs.append(f'damping="{_f(damping[j - 1])}"')
        if friction[j - 1] != 0:  # a URDF's <dynamics friction>, as MuJoCo's own URDF reader takes it
            attrs.append(f'frictionloss="{_f(friction[j - 1])}"')
        if 0 < effort[j - 1] < np.inf:  # a file's effort limit, as MuJoCo's URDF reader takes it (0: none)
            attrs.append(f'actuatorfrclimited="true" actuatorfrcrange="{_f(-effort[j - 1])} {_f(effort[j - 1])}"')
        lines_by_joint[j] = (inertial, f"<joint {' '.join(attrs)}/>")

    tip_frame = model.frames[robot.tip_id]
    site_name = robot.tip if robot.tip not in body_names.values() else f"{robot.tip}_site"
    site = (tip_frame.parentJoint,
            " ".join(f"<site name={quoteattr(site_name)} {_pose_attrs(tip_frame.placement.homogeneous)} "
                     f'size="{_f(0.02 * scale)}" rgba="0.1 0.8 0.2 1"/>'.split()))

    g = robot.gravity
    out = ['<?xml version="1.0"?>',
           f"<!-- written by robokit from {robot.source or robot.name}: SI units (m, kg, s), angles in rad -->",
           f"<mujoco model={quoteattr(robot.name)}>",
           '  <compiler angle="radian" autolimits="true" inertiafromgeom="false"/>',
           f'  <option gravity="{_v(g)}"/>']
    if mesh_assets:
        out.append("  <asset>")
        for (p, sc), name in mesh_assets.items():
            out.append(f"    <mesh name={quoteattr(name)} file={quoteattr(p)} scale=\"{_v(sc)}\"/>")
        out.append("  </asset>")
    if customs:
        out.append("  <custom>")
        out.extend(customs)
        out.append("  </custom>")
    out.append("  <worldbody>")
    for gx in geoms_by_joint[0]:
        out.append(f"    {gx}")
    if site[0] == 0:
        out.append(f"    {site[1]}")
    indent = "    "
    for j in range(1, n + 1):
        inertial, joint = lines_by_joint[j]
        out.append(f"{indent}<body name={quoteattr(body_names[j])} {_pose_attrs(model.jointPlacements[j].homogeneous)}>"
                   .replace(" >", ">"))
        indent += "  "
        out.append(f"{indent}{joint}")
        out.append(f"{indent}{inertial}")
        for gx in geoms_by_joint[j]:
            out.append(f"{indent}{gx}")
        if site[0] == j:
            out.append(f"{indent}{site[1]}")
    for j in range(n, 0, -1):
        indent = indent[:-2]
        out.append(f"{indent}</body>")
    out.append("  </worldbody>")
    out.append("</mujoco>")
    return "\n".join(out) + "\n", notes

# Former names (before the X_from_Y rule): they warn and call the new function.
robot_to_mjcf = deprecated_alias(mjcf_from_robot, "robot_to_mjcf")
