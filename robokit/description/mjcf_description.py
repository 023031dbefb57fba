r"""A compiled MJCF file as a :class:`~robokit.description.model_builder.Description`.

:func:`description_from_mjcf` turns body ``first``'s subtree of a
:class:`~robokit.description.mjcf_compile.CompiledMjcf` into the format-independent description
that :func:`~robokit.description.model_builder.build_model` makes the Pinocchio model of, laid out
as MuJoCo lays the model out:

* each body is a ``BODY`` frame; a body welded to its parent (no joint) is a frame-less fixed
  joint (:attr:`~robokit.description.model_builder.Joint.frame` False: MuJoCo has no such joint,
  so the model has no ``FIXED_JOINT`` frame for it), the top body, if jointless, a root link at
  its pose in the world;
* each joint is a Pinocchio joint (``hinge`` revolute, ``slide`` prismatic, ``ball`` spherical,
  ``free`` floating, whose value is the body's pose in the world, as in MuJoCo: the body's
  ``pos``/``quat`` are only MuJoCo's initial ``qpos``) with a ``JOINT`` frame, composed as MuJoCo
  composes a body's joints
  j₁ … jₖ placed at ``pos``/``quat`` in its parent,

      body(q) = parent · X_body · ∏ₖ T(pₖ) · Mₖ(qₖ − refₖ) · T(−pₖ)

  (Mₖ the rotation about, or translation along, the joint's axis; pₖ its anchor): joint 1 sits at
  X_body · T(p₁); joint k + 1 hangs on joint k through a frame-less link
  (:attr:`~robokit.description.model_builder.Link.frame` False) at Mₖ(−refₖ) · T(pₖ₊₁ − pₖ); the
  body at Mₖ(−refₖ) · T(−pₖ) in the last joint. So robokit's joint value is MuJoCo's ``qpos`` and
  the body sits as written when every joint is at its ``ref``;
* a joint the loader will lock off the chain (``held``) is measured from MuJoCo's ``qpos0``
  instead, so that the chain, cut at the joints' neutral value, is cut where MuJoCo's model
  holds them: a hinge or slide from its ``ref`` (no Mₖ(−refₖ) factor), a free joint from the
  body's ``pos``/``quat``; a ball joint's neutral value, the identity, is already its ``qpos0``;
* inertials are the compiler's (``body_mass``, ``body_ipos``, the full inertia tensor) as MuJoCo's
  dynamics uses them (:func:`_inertial`): a principal frame within ``FRAME_EPS`` of the body's
  (each quaternion component, either sign) is the body's, and then a centre of mass within
  ``FRAME_EPS`` of the body's origin (each coordinate) is at the origin (the compiler's
  ``body_sameframe``: its kinematics then takes the body frame for the inertial one); sites are
  ``OP_FRAME`` frames right after their body's frame (MuJoCo numbers them body by body), sites and
  geoms placed by the same tolerance as MuJoCo places them (:func:`_placed`);
* geoms are shapes named as the file names them: the collision model holds the geoms MuJoCo can
  collide (``contype`` or ``conaffinity`` non-zero), the visual model those of groups 0–2 (what
  MuJoCo's viewer shows); a mesh is its compiled triangles, drawn from its file when the
  compiler kept where the file sits (``mesh_file_pose``). Planes, height fields and SDF geoms have
  no shape robokit builds: they are listed, for a note.
"""
from __future__ import annotations

from typing import AbstractSet, Any

import numpy as np

from robokit.description import _mjcf_math as mm
from robokit.description.mjcf_compile import CompiledMjcf, MjcfBody, MjcfGeom, MjcfJoint
from robokit.description.model_builder import Description, FrameSpec, Geometry, Inertial, Joint, Link, Pose

__all__ = ["description_from_mjcf", "GeomMasks"]

#: the collision bit masks of every geometry robokit puts in the collision model, by geometry name:
#: ``(contype, conaffinity, body name)``
GeomMasks = dict[str, tuple[int, int, str]]

_KINDS = {"hinge": "revolute", "slide": "prismatic", "ball": "ball", "free": "floating"}


def _se3(pos: Any, quat: Any) -> Any:
    import pinocchio as pin

    R = np.array(mm.quat_to_matrix(tuple(float(x) for x in quat))).reshape(3, 3)
    return pin.SE3(R, np.asarray(pos, dtype=float).copy())


def _pose(X: Any) -> Pose:
    return Pose.from_matrix(X.homogeneous)


def _shift(p: Any) -> Any:
    import pinocchio as pin

    return pin.SE3(np.eye(3), np.asarray(p, dtype=float))


def _ref_offset(j: MjcfJoint, held: AbstractSet[str] = frozenset()) -> Any:
    """The constant part of M(q − ref): a rotation by −ref about the axis or a shift by −ref along it
    (none for a joint in ``held``, whose value is measured from its ``ref``)."""
    import pinocchio as pin

    if j.ref == 0.0 or j.type in ("ball", "free") or j.name in held:
        return pin.SE3.Identity()
    if j.type == "hinge":
        return pin.SE3(pin.AngleAxis(-j.ref, np.asarray(j.axis, dtype=float)).matrix(), np.zeros(3))
    return pin.SE3(np.eye(3), -j.ref * np.asarray(j.axis, dtype=float))


#: MuJoCo's compiler takes a body's inertial frame for its body frame when they differ by less than this
#: in every quaternion component (and, for the centre of mass too, every coordinate, m): ``body_sameframe``
#: (mjSAMEFRAME_BODY or _BODYROT), after which its kinematics places the inertia in the body frame
#: and ignores the difference — measured with MuJoCo 4.0.1: a centre of mass 9.99e-7 m off the origin
#: is at the origin in ``mj_fullM``, 1e-6 m is not.
FRAME_EPS = 1e-6


_IDENTITY = (1.0, 0.0, 0.0, 0.0)


def _same_quat(a: Any, b: Any) -> bool:
    """MuJoCo's compiler test: every component within ``FRAME_EPS``, of b or of −b (one rotation)."""
    qa, qb = np.asarray(a, dtype=float), np.asarray(b, dtype=float)
    return bool(np.all(np.abs(qa - qb) < FRAME_EPS) or np.all(np.abs(qa + qb) < FRAME_EPS))


def _same_vec(a: Any, b: Any) -> bool:
    return bool(np.all(np.abs(np.asarray(a, dtype=float) - np.asarray(b, dtype=float)) < FRAME_EPS))


def _same_frame(b: MjcfBody) -> tuple[bool, bool]:
    """(principal frame is the body's, centre of mass too) by MuJoCo's compiler test (``FRAME_EPS``)."""
    rot = _same_quat(b.iquat, _IDENTITY)
    return rot, rot and _same_vec(b.ipos, (0.0, 0.0, 0.0))


def _inertial_frame(b: MjcfBody) -> tuple[Any, Any]:
    """(centre of mass, principal frame's quaternion) in the body frame as MuJoCo's kinematics places
    them (``xipos``, ``ximat``): the body's own where the compiler's ``body_sameframe`` says so."""
    rot, pos = _same_frame(b)
    return ((0.0, 0.0, 0.0) if pos else b.ipos), (_IDENTITY if rot else b.iquat)


def _placed(pos: Any, quat: Any, b: MjcfBody) -> Any:
    """A site's or geom's placement in its body as MuJoCo's kinematics computes it (``site_sameframe``,
    ``geom_sameframe``: the compiler's tests in this order, each within ``FRAME_EPS``): at the body's
    frame; its orientation the body's; at the body's inertial frame (as placed by
    :func:`_inertial_frame`); its orientation the inertial frame's; else as written."""
    import pinocchio as pin

    ipos, iquat = _inertial_frame(b)
    if _same_vec(pos, (0.0, 0.0, 0.0)) and _same_quat(quat, _IDENTITY):
        return pin.SE3.Identity()
    if _same_quat(quat, _IDENTITY):
        return _se3(pos, _IDENTITY)
    if _same_vec(pos, b.ipos) and _same_quat(quat, b.iquat):
        return _se3(ipos, iquat)
    if _same_quat(quat, b.iquat):
        return _se3(pos, iquat)
    return _se3(pos, quat)


def _inertial(b: MjcfBody) -> Inertial:
    """A body's inertial as MuJoCo's dynamics uses it: the compiler's mass, centre of mass and principal
    inertia, the frame snapped to the body's where the compiler's ``body_sameframe`` test holds
    (``FRAME_EPS``)."""
    rot, pos = _same_frame(b)
    Ic = np.diag(np.asarray(b.inertia, dtype=float)) if rot else np.asarray(b.inertia_matrix, dtype=float)
    Ic = 0.5 * (Ic + Ic.T)
    c = (0.0, 0.0, 0.0) if pos else (float(b.ipos[0]), float(b.ipos[1]), float(b.ipos[2]))
    return Inertial(float(b.mass), c,
                    (float(Ic[0, 0]), float(Ic[0, 1]), float(Ic[0, 2]), float(Ic[1, 1]), float(Ic[1, 2]),
                     float(Ic[2, 2])))


def _joints(b: MjcfBody, parent: str | None, armature: bool,
            held: AbstractSet[str] = frozenset()) -> tuple[list[Link], list[Joint]]:
    """The joints of one body with at least one joint, and the frame-less links between them; a
    joint in ``held`` has its neutral value at MuJoCo's ``qpos0`` (module docstring)."""
    import pinocchio as pin

    links: list[Link] = []
    joints: list[Joint] = []
    if b.joints[0].type == "free":  # MuJoCo sets a free body's pose to its qpos: pos, quat and anchor unused
        at = _pose(_se3(b.pos, b.quat)) if b.joints[0].name in held else Pose()  # held: qpos0 is pos, quat
        return [], [Joint(b.joints[0].name, "floating", parent, b.name, at)]
    place = _se3(b.pos, b.quat) * _shift(b.joints[0].pos)
    for k, j in enumerate(b.joints):
        last = k + 1 == len(b.joints)
        child = b.name if last else f"\x00{b.name}/{k}"  # a NUL never appears in an XML name
        if not last:
            links.append(Link(child, frame=False))
        after = _ref_offset(j, held) * (_shift(-np.asarray(j.pos, dtype=float)) if last else pin.SE3.Identity())
        axis = (float(j.axis[0]), float(j.axis[1]), float(j.axis[2]))
        moving = j.type in ("hinge", "slide")
        joints.append(Joint(j.name, _KINDS[j.type], parent, child, _pose(place), _pose(after), axis,
                            lower=float(j.range[0]) if moving else -np.inf,
                            upper=float(j.range[1]) if moving else np.inf,
                            damping=float(j.damping) if moving else 0.0,
                            friction=float(j.frictionloss) if moving else 0.0,
                            armature=float(j.armature) if moving and armature else 0.0,
                            effort=float(j.effort) if moving else np.inf))
        if not last:
            place = _shift(np.asarray(b.joints[k + 1].pos, dtype=float) - np.asarray(j.pos, dtype=float))
        parent = child
    return links, joints


def _shape(g: MjcfGeom) -> tuple[str, tuple[float, ...]] | None:
    """(kind, sizes) of a geom as :class:`~robokit.description.model_builder.Geometry` takes them."""
    s = [float(x) for x in g.size]
    if g.type == "sphere":
        return "sphere", (s[0],)
    if g.type in ("capsule", "cylinder"):
        return g.type, (s[0], 2 * s[1])
    if g.type == "box":
        return "box", (2 * s[0], 2 * s[1], 2 * s[2])
    if g.type == "ellipsoid":
        return "ellipsoid", (s[0], s[1], s[2])
    if g.type == "mesh" and g.vertices is not None and g.faces is not None:
        return "trimesh", ()
    return None


def _geometries(g: MjcfGeom, b: MjcfBody) -> list[Geometry]:
    """The collision and visual shapes of one geom (none, one or both)."""
    kind, size = _shape(g) or ("", ())
    body = b.name
    place = _placed(g.pos, g.quat, b)
    rgba = (float(g.rgba[0]), float(g.rgba[1]), float(g.rgba[2]), float(g.rgba[3]))
    out = []
    if g.contype or g.conaffinity:
        out.append(Geometry(body, kind, _pose(place), size, True, color=rgba, name=g.name, vertices=g.vertices,
                            faces=g.faces))
    if 0 <= g.group <= 2:
        if g.mesh_file is not None and g.mesh_file_pose is not None and g.vertices is not None:
            T = np.asarray(g.mesh_file_pose, dtype=float)
            scaled = (np.asarray(g.vertices) - T[:3, 3]) @ T[:3, :3]  # S·v in the file's axes
            import pinocchio as pin

            at = place * pin.SE3(T[:3, :3].copy(), T[:3, 3].copy())
            scale = (float(g.mesh_scale[0]), float(g.mesh_scale[1]), float(g.mesh_scale[2]))
            out.append(Geometry(body, "trimesh", _pose(at), (), False, g.mesh_file, scale, rgba, g.name, scaled,
                                np.asarray(g.faces)))
        else:
            out.append(Geometry(body, kind, _pose(place), size, False, color=rgba, name=g.name, vertices=g.vertices,
                                faces=g.faces))
    return out


def _mjcf_parts(c: CompiledMjcf, first: int, armature: bool = True, held: AbstractSet[str] = frozenset()
                ) -> tuple[Description, GeomMasks, list[str]]:
    """:func:`description_from_mjcf`, the collision masks and the geoms left out (``"name (type)"``);
    the joints named in ``held`` (to be locked off the chain) with their neutral value at MuJoCo's
    ``qpos0`` (module docstring)."""
    links: list[Link] = []
    joints: list[Joint] = []
    frames: list[FrameSpec] = []
    geoms: list[Geometry] = []
    masks: GeomMasks = {}
    skipped: list[str] = []
    roots: list[tuple[str, Pose]] = []
    subtree = c.subtree(first)
    for i in subtree:
        b = c.bodies[i]
        parent = c.bodies[b.parent].name if i != first else None
        if b.joints:
            more, js = _joints(b, parent, armature, held)
            links += more
            joints += js
        elif parent is None:
            roots.append((b.name, _pose(_se3(b.pos, b.quat))))
        else:  # welded to its parent: no joint in MuJoCo, no joint frame here
            joints.append(Joint(f"\x00weld/{b.name}", "fixed", parent, b.name, _pose(_se3(b.pos, b.quat)),
                                frame=False))
        links.append(Link(b.name, _inertial(b)))
        frames += [FrameSpec(s.name, b.name, _pose(_placed(s.pos, s.quat, b))) for s in b.sites]
        for g in b.geoms:
            if _shape(g) is None:
                skipped.append(f"{g.name} ({g.type})")
                continue
            geoms += _geometries(g, b)
            if g.contype or g.conaffinity:
                masks[g.name] = (int(g.contype), int(g.conaffinity), b.name)
    desc = Description(c.name, tuple(links), tuple(joints), tuple(frames), tuple(geoms), tuple(roots),
                       (float(c.gravity[0]), float(c.gravity[1]), float(c.gravity[2])), frames_with_links=True)
    return desc, masks, skipped


def description_from_mjcf(c: CompiledMjcf, first: int, armature: bool = True) -> Description:
    """The description of body ``first``'s subtree of a compiled MJCF file (see the module docstring).

    Parameters
    ----------
    c : CompiledMjcf
        The file as MuJoCo's compiler rules read it (:func:`~robokit.description.mjcf_compile.compile_mjcf`).
    first : int
        The index in ``c.bodies`` of the top body of the robot (a child of the world).
    armature : bool
        Keep each hinge's and slide's ``armature`` (reflected rotor inertia), as MuJoCo adds it
        (default); False: zero.

    Returns
    -------
    Description
        For :func:`~robokit.description.model_builder.build_model`; gravity from ``<option>``.

    Examples
    --------
    A body with two hinges: one frame-less link between them, no extra ``BODY`` frame:

    >>> import pathlib, tempfile
    >>> from robokit.description.mjcf_compile import compile_mjcf
    >>> from robokit.description.model_builder import build_model
    >>> xml = ('<mujoco><worldbody><body name="a"><joint name="j1" axis="0 0 1"/><joint name="j2" axis="0 1 0"/>'
    ...        '<geom size="0.1"/><site name="tip" pos="0.2 0 0"/></body></worldbody></mujoco>')
    >>> with tempfile.TemporaryDirectory() as tmp:
    ...     path = pathlib.Path(tmp, "two.xml")
    ...     _ = path.write_text(xml)
    ...     desc = description_from_mjcf(compile_mjcf(path), 1)
    >>> [f.name for f in build_model(desc)[0].frames]
    ['universe', 'j1', 'j2', 'a', 'tip']
    """
    return _mjcf_parts(c, first, armature)[0]
