r"""A Pinocchio model from a compiled MJCF file (private to :mod:`robokit.description.mjcf`).

Each body of :class:`~robokit.description.mjcf_compile.CompiledMjcf` becomes a BODY frame;
each of its joints a Pinocchio joint, composed as MuJoCo composes them: for a body with
joints j₁ … jₖ placed at ``pos``/``quat`` in its parent,

    body(q) = parent · X_body · ∏ₖ T(pₖ) · Mₖ(qₖ − refₖ) · T(−pₖ)

(Mₖ the rotation about, or translation along, the joint's axis; pₖ its anchor). Joint k's
frame is placed at T(pₖ) with the body's axes, the constant part of Mₖ(qₖ − refₖ) moves into the
next placement, so robokit's joint value is MuJoCo's ``qpos`` and the body sits as written when
every joint is at its ``ref``. A body with no joint is welded to its parent's joint. Inertials
are appended to the joint that carries the body; sites become operational frames; geoms become
coal shapes: the collision model holds the geoms MuJoCo can collide (``contype`` or
``conaffinity`` non-zero), the visual model those of groups 0–2 (what MuJoCo's viewer shows).
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from robokit.description import _mjcf_math as mm
from robokit.description.mjcf_compile import CompiledMjcf, MjcfGeom, MjcfJoint

#: the collision bit masks of every geom robokit puts in the collision model, by geometry name
GeomMasks = dict[str, tuple[int, int, str]]


@dataclass
class BuiltModel:
    model: Any
    visual: Any
    collision: Any
    masks: GeomMasks  # collision geometry name → (contype, conaffinity, body name)
    skipped: list[str]  # geoms with no coal shape (planes, height fields)


def _se3(pos: Any, quat: Any) -> Any:
    import pinocchio as pin

    R = np.array(mm.quat_to_matrix(tuple(float(x) for x in quat))).reshape(3, 3)
    return pin.SE3(R, np.asarray(pos, dtype=float).copy())


def _joint_model(j: MjcfJoint) -> Any:
    import pinocchio as pin

    a = j.axis
    if j.type == "free":
        return pin.JointModelFreeFlyer()
    if j.type == "ball":
        return pin.JointModelSpherical()
    unit = [tuple(np.eye(3)[k]) for k in range(3)]
    aligned = [k for k in range(3) if tuple(float(x) for x in a) == unit[k]]
    if j.type == "hinge":
        return (pin.JointModelRX, pin.JointModelRY, pin.JointModelRZ)[aligned[0]]() if aligned else \
            pin.JointModelRevoluteUnaligned(np.asarray(a, dtype=float))
    return (pin.JointModelPX, pin.JointModelPY, pin.JointModelPZ)[aligned[0]]() if aligned else \
        pin.JointModelPrismaticUnaligned(np.asarray(a, dtype=float))


def _ref_offset(j: MjcfJoint) -> Any:
    """The constant part of M(q − ref): a rotation by −ref about the axis or a shift by −ref along it."""
    import pinocchio as pin

    if j.ref == 0.0 or j.type in ("ball", "free"):
        return pin.SE3.Identity()
    if j.type == "hinge":
        return pin.SE3(pin.AngleAxis(-j.ref, np.asarray(j.axis, dtype=float)).matrix(), np.zeros(3))
    return pin.SE3(np.eye(3), -j.ref * np.asarray(j.axis, dtype=float))


def _inertia(mass: float, com: np.ndarray, Ic: np.ndarray) -> Any:
    """A Pinocchio inertia from mass, centre of mass and the inertia about it, also when the
    latter is not positive (the exact inertials robokit's writer keeps; Pinocchio's checked
    constructor refuses those) and when the mass is zero (a massless link with a rotational
    inertia, PUMA 560's link 1: going through dynamic parameters would divide by the mass and give
    NaN). Set field by field, as the shared model builder does."""
    import pinocchio as pin

    Y = pin.Inertia.Zero()
    Y.mass = float(mass)
    Y.lever = np.asarray(com, dtype=float)
    Y.inertia = 0.5 * (np.asarray(Ic, dtype=float) + np.asarray(Ic, dtype=float).T)
    return Y


def _shape(g: MjcfGeom) -> Any:
    import coal

    s = g.size
    if g.type == "sphere":
        return coal.Sphere(float(s[0]))
    if g.type == "capsule":
        return coal.Capsule(float(s[0]), float(2 * s[1]))
    if g.type == "cylinder":
        return coal.Cylinder(float(s[0]), float(2 * s[1]))
    if g.type == "box":
        return coal.Box(float(2 * s[0]), float(2 * s[1]), float(2 * s[2]))
    if g.type == "ellipsoid":
        return coal.Ellipsoid(float(s[0]), float(s[1]), float(s[2]))
    if g.type == "mesh" and g.vertices is not None and g.faces is not None:
        return _bvh(g.vertices, g.faces)
    return None


def _bvh(vertices: np.ndarray, faces: np.ndarray) -> Any:
    import coal

    m = coal.BVHModelOBBRSS()
    m.beginModel(len(faces), len(vertices))
    m.addVertices(np.ascontiguousarray(vertices, dtype=float))
    m.addTriangles(np.ascontiguousarray(faces, dtype=np.int64))
    m.endModel()
    return m


def build_model(c: CompiledMjcf, first: int, armature: bool = True) -> BuiltModel:
    """The Pinocchio model, visual and collision models of body ``first``'s subtree."""
    import pinocchio as pin

    model = pin.Model()
    model.name = c.name
    model.gravity.linear = np.asarray(c.gravity, dtype=float)
    visual, collision = pin.GeometryModel(), pin.GeometryModel()
    masks: GeomMasks = {}
    skipped: list[str] = []
    joint_of = {0: 0}
    frame_of = {0: 0}
    in_joint = {0: pin.SE3.Identity()}
    inf = np.array([np.inf])
    for i in c.subtree(first):
        b = c.bodies[i]
        p = b.parent
        X = in_joint[p] * _se3(b.pos, b.quat)
        jid, fid = joint_of[p], frame_of[p]
        if b.joints:
            place = X * pin.SE3(np.eye(3), np.asarray(b.joints[0].pos, dtype=float))
            for k, j in enumerate(b.joints):
                jm = _joint_model(j)
                if j.type in ("hinge", "slide"):
                    new = model.addJoint(jid, jm, place, j.name, inf, inf, np.array([j.range[0]]),
                                         np.array([j.range[1]]))
                else:
                    new = model.addJoint(jid, jm, place, j.name)
                jmod = model.joints[new]
                if j.type in ("hinge", "slide"):
                    model.armature[jmod.idx_v] = j.armature if armature else 0.0
                    model.damping[jmod.idx_v] = j.damping
                fid = model.addJointFrame(new, fid)
                jid = new
                here = np.asarray(j.pos, dtype=float)
                nxt = np.asarray(b.joints[k + 1].pos, dtype=float) if k + 1 < len(b.joints) else np.zeros(3)
                place = _ref_offset(j) * pin.SE3(np.eye(3), nxt - here)
            X = place
        joint_of[i] = jid
        in_joint[i] = X
        frame_of[i] = model.addBodyFrame(b.name, jid, X, fid)
        Ib = _inertia(float(b.mass), np.asarray(b.ipos, dtype=float), b.inertia_matrix)
        model.appendBodyToJoint(jid, Ib, X)
        for s in b.sites:
            model.addFrame(pin.Frame(s.name, jid, frame_of[i], X * _se3(s.pos, s.quat), pin.FrameType.OP_FRAME))
        for g in b.geoms:
            shape = _shape(g)
            if shape is None:
                skipped.append(f"{g.name} ({g.type})")
                continue
            place_g = X * _se3(g.pos, g.quat)
            color = np.asarray(g.rgba, dtype=float)
            if (g.contype or g.conaffinity):
                collision.addGeometryObject(pin.GeometryObject(g.name, jid, frame_of[i], place_g, shape))
                masks[g.name] = (int(g.contype), int(g.conaffinity), b.name)
            if 0 <= g.group <= 2:
                if g.mesh_file is not None and g.mesh_file_pose is not None and g.vertices is not None:
                    T = g.mesh_file_pose
                    scaled = (np.asarray(g.vertices) - T[:3, 3]) @ T[:3, :3]  # S·v in the file's axes
                    vis = _bvh(scaled, np.asarray(g.faces))
                    go = pin.GeometryObject(g.name, jid, frame_of[i], place_g * pin.SE3(T[:3, :3].copy(), T[:3, 3].copy()),
                                            vis, g.mesh_file, np.asarray(g.mesh_scale, dtype=float), True, color)
                else:
                    go = pin.GeometryObject(g.name, jid, frame_of[i], place_g, shape)
                    go.meshColor = color
                visual.addGeometryObject(go)
    return BuiltModel(model, visual, collision, masks, skipped)
