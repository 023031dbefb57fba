r"""MJCF (MuJoCo's XML format) in: :func:`load_mjcf`.

Reading (:func:`load_mjcf`, used by ``robokit.load("arm.xml")``)
    The file (and every ``<include>``) is read bounded and confined
    (:func:`robokit.description.mjcf_safety.check_mjcf`), compiled by MuJoCo's compiler rules
    (:func:`robokit.description.mjcf_compile.compile_mjcf`: default classes, frames, every
    orientation form, inertia from geoms and meshes, ``boundmass``/``boundinertia``,
    ``balanceinertia``, ``settotalmass``, ``fusestatic``, joint ``ref``, several joints per body)
    and built into a Pinocchio model directly, so that mass, centre of mass and inertia of every
    body, the mass matrix and inverse dynamics are MuJoCo's (``body_mass``, ``body_ipos``,
    ``body_inertia``, ``mj_fullM``, ``mj_inverse``).

    Joint ``armature`` (reflected rotor inertia) is added to the diagonal of M and to inverse
    dynamics, as MuJoCo adds it, and a note says so; ``reflected_inertia=False`` leaves it out. Joint
    ``damping`` is kept in ``robot.model.damping`` (rigid-body dynamics does not add it; MuJoCo
    adds the passive force −b·q̇, which ``mj_inverse`` counts).

    Joints off the chain to the tip (a gripper's fingers) are locked at MuJoCo's ``qpos0``, where
    the file draws them — a hinge or slide at its ``ref``, a ball or free joint with its body as
    written — so that M, gravity torques and inverse dynamics are MuJoCo's with them there; one
    note names them, each with the value it is held at.

    Elements with no meaning for a serial-chain model (actuators, tendons, equality
    constraints, sensors, contact pairs, keyframes, top-level bodies other than the robot's,
    joint friction loss and springs, gravity compensation, fluid forces) are named in a note
    (a ``RobokitWarning``). The collision rules of the file (``contype``/``conaffinity``,
    ``<contact><exclude>``, MuJoCo's parent–child filter) travel with the robot
    (``robot.contact_rules``) for :class:`robokit.collision.World`.

    Exact inertials written by :func:`robokit.description.mjcf_write.mjcf_from_robot` in
    ``<custom><numeric name="robokit_inertial:BODY">`` replace the approximate ones MuJoCo
    needed (see :mod:`robokit.description.mjcf_write`).

Writing is :mod:`robokit.description.mjcf_write` (``mjcf_from_robot``, ``joint_armature_damping``).
"""
from __future__ import annotations

import dataclasses
import math
import os
import xml.etree.ElementTree as ET
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any, Sequence

import numpy as np

from robokit.description.builder import build_robot, default_tip
from robokit.description.frames import frame_index
from robokit.description.mjcf_compile import CompiledMjcf, MjcfJoint, compile_mjcf
from robokit.description.spec import RobotSpec
from robokit.errors import InputError

if TYPE_CHECKING:
    from robokit.description.robot import Robot

__all__ = ["load_mjcf", "first_body_placement", "ContactRules", "CUSTOM_INERTIAL_PREFIX"]

#: prefix of the ``<custom><numeric>`` names that carry exact inertials
CUSTOM_INERTIAL_PREFIX = "robokit_inertial:"
#: top-level MJCF sections that carry nothing for a serial-chain model
_IGNORED_SECTIONS = ("actuator", "tendon", "equality", "sensor", "contact", "keyframe")


@dataclass(frozen=True)
class ContactRules:
    """Which geometry pairs of an MJCF robot MuJoCo would never test for contact.

    MuJoCo tests two geoms only when ``(contype₁ & conaffinity₂) | (contype₂ & conaffinity₁)``
    is non-zero, never two geoms of bodies welded together (no joint between them), never a
    body and its parent's (the parent filter, unless ``<flag filterparent="disable">``; the
    world excepted) and never the body pairs of ``<contact><exclude>``.

    Attributes
    ----------
    masks : dict of str to (int, int, str)
        Collision geometry name → (contype, conaffinity, body name).
    weld : dict of str to str
        Body name → its weld body: itself if it has a joint, else its parent's weld body
        (``"world"`` for bodies fixed to the world).
    weld_parent : dict of str to str
        Body name → the weld body of its weld body's parent.
    excluded : frozenset of frozenset of str
        The ``<contact><exclude>`` body pairs.
    filterparent : bool
        Whether the parent filter is on.

    Examples
    --------
    >>> rules = ContactRules({"a": (1, 0, "l1"), "b": (1, 0, "l3")}, {"l1": "l1", "l3": "l3"},
    ...                      {"l1": "world", "l3": "l2"}, frozenset(), True)
    >>> rules.why("a", "b")
    'contype/conaffinity: (1 & 0) | (1 & 0) = 0'
    """

    masks: dict[str, tuple[int, int, str]]
    weld: dict[str, str]
    weld_parent: dict[str, str]
    excluded: frozenset[frozenset[str]]
    filterparent: bool

    def why(self, geom_a: str, geom_b: str) -> str | None:
        """Why MuJoCo never tests this pair of collision geometries (None if it does).

        Parameters
        ----------
        geom_a, geom_b : str
            Collision geometry names (``robot.collision_model`` object names).

        Returns
        -------
        str or None
            The rule that excludes the pair.
        """
        if geom_a not in self.masks or geom_b not in self.masks:
            return None
        ct1, ca1, b1 = self.masks[geom_a]
        ct2, ca2, b2 = self.masks[geom_b]
        w1, w2 = self.weld.get(b1, b1), self.weld.get(b2, b2)
        if w1 == w2:
            return f"same rigid body ({w1})"
        if self.filterparent and w1 != "world" and w2 != "world" and (
                w1 == self.weld_parent.get(b2) or w2 == self.weld_parent.get(b1)):
            return f"parent and child bodies ({w1}, {w2}; MuJoCo's filterparent)"
        if frozenset((b1, b2)) in self.excluded:
            return f"<contact><exclude body1={b1!r} body2={b2!r}>"
        if not (ct1 & ca2) and not (ct2 & ca1):
            return f"contype/conaffinity: ({ct1} & {ca2}) | ({ct2} & {ca1}) = 0"
        return None

    def why_not_obstacle(self, geom: str) -> str | None:
        """Why MuJoCo would never test this robot geometry against an obstacle, taken as a geom
        with MuJoCo's default masks (contype = conaffinity = 1); None if it would.

        Parameters
        ----------
        geom : str
            A collision geometry name.

        Returns
        -------
        str or None
        """
        if geom not in self.masks:
            return None
        ct, ca, _ = self.masks[geom]
        if not (ct & 1) and not (ca & 1):
            return f"contype/conaffinity ({ct}, {ca}) share no bit with an obstacle's (1, 1)"
        return None


def first_body_placement(path: str | os.PathLike[str]) -> tuple[str | None, np.ndarray | None]:
    """The worldbody's first ``<body>`` and its pose, if that body has no joint.

    Parameters
    ----------
    path : str or os.PathLike
        The MJCF file.

    Returns
    -------
    name : str or None
        The body's name; None when the first body has a joint or there is no body.
    pose : numpy.ndarray, shape (4, 4), or None
        Its pose in the world frame by MuJoCo's rules (``pos``; ``quat``, ``axisangle``,
        ``euler``, ``xyaxes`` or ``zaxis`` in the compiler's angle unit; enclosing frames).

    Examples
    --------
    >>> import pathlib, tempfile
    >>> xml = ('<mujoco><worldbody><body name="base" pos="0 0 0.5">'
    ...        '<body name="l1"><joint name="j1"/><geom size="0.1"/></body></body></worldbody></mujoco>')
    >>> with tempfile.TemporaryDirectory() as tmp:
    ...     path = pathlib.Path(tmp, "arm.xml")
    ...     _ = path.write_text(xml)
    ...     name, T = first_body_placement(path)
    >>> name, T[:3, 3].tolist()
    ('base', [0.0, 0.0, 0.5])
    """
    from robokit.description import _mjcf_math as mm

    c = compile_mjcf(path)
    tops = [b for b in c.bodies[1:] if b.parent == 0]
    if not tops or tops[0].joints:
        return None, None
    T = np.eye(4)
    T[:3, :3] = np.array(mm.quat_to_matrix(tuple(tops[0].quat))).reshape(3, 3)
    T[:3, 3] = tops[0].pos
    return tops[0].name, T


# --------------------------------------------------------------------------- reading
def _robot_root(c: CompiledMjcf) -> int:
    """The top-level body whose subtree is the robot: the first with a hinge or slide joint
    (else the first top-level body)."""
    tops = [i for i, b in enumerate(c.bodies) if b.parent == 0]
    for i in tops:
        if any(j.type in ("hinge", "slide") for k in c.subtree(i) for j in c.bodies[k].joints):
            return i
    return tops[0]


def _ignored_notes(root: ET.Element, c: CompiledMjcf, first: int, path: Path) -> list[str]:
    notes = []
    for section in _IGNORED_SECTIONS:
        for elem in root.findall(section):
            kids = sorted({ch.tag for ch in elem})
            if section == "contact":  # <exclude> pairs are read: robot.contact_rules skips them
                kids = [k for k in kids if k != "exclude"]
            if kids:
                notes.append(f"{path}: <{section}> ignored ({', '.join(kids)}): robokit models the rigid-body chain "
                             "only")
    for i, b in enumerate(c.bodies):
        if b.parent == 0 and i != first:
            notes.append(f"{path}: <body name={b.name!r}> ignored: robokit reads one top-level body tree, the "
                         f"robot's ({c.bodies[first].name!r})")
    return notes


def _custom_inertials(root: ET.Element, path: Path) -> dict[str, np.ndarray]:
    out = {}
    for num in root.iter("numeric"):
        name = num.get("name", "")
        if name.startswith(CUSTOM_INERTIAL_PREFIX):
            try:
                data = np.array([float(t) for t in num.get("data", "").split()])
            except ValueError:
                raise InputError(f"{path}: <numeric name={name!r}> data: expected numbers") from None
            if data.size != 10 or not np.isfinite(data).all():
                raise InputError(f"{path}: <numeric name={name!r}> data: expected 10 finite numbers")
            out[name[len(CUSTOM_INERTIAL_PREFIX):]] = data
    return out


def _with_exact_inertials(c: CompiledMjcf, exact: dict[str, np.ndarray], path: Path) -> CompiledMjcf:
    """Replace the inertials MuJoCo needed adjusted by the exact ones robokit wrote."""
    from robokit.description import _mjcf_math as mm
    from robokit.description._notes import note

    names = {b.name: i for i, b in enumerate(c.bodies)}
    bodies = list(c.bodies)
    for body, d in exact.items():
        if body not in names:
            note(f"{path}: <numeric name='{CUSTOM_INERTIAL_PREFIX}{body}'> ignored: no body {body!r}")
            continue
        xx, yy, zz, xy, xz, yz = d[4:]
        w, V = np.linalg.eigh(np.array([[xx, xy, xz], [xy, yy, yz], [xz, yz, zz]]))
        if np.linalg.det(V) < 0:
            V[:, 2] = -V[:, 2]
        q = mm.frame_to_quat(tuple(V[:, 0]), tuple(V[:, 1]), tuple(V[:, 2]))
        bodies[names[body]] = dataclasses.replace(bodies[names[body]], mass=float(d[0]), ipos=np.array(d[1:4]),
                                                  iquat=np.array(q), inertia=w.copy())
    return dataclasses.replace(c, bodies=tuple(bodies))


def _contact_rules(c: CompiledMjcf, root: ET.Element, masks: dict[str, tuple[int, int, str]]) -> ContactRules:
    weld: dict[str, str] = {"world": "world"}
    for b in c.bodies[1:]:
        weld[b.name] = b.name if (b.joints or b.mocap) else weld[c.bodies[b.parent].name]
    parent = {b.name: c.bodies[b.parent].name for b in c.bodies[1:]}
    weld_parent = {b.name: weld[parent[weld[b.name]]] if weld[b.name] != "world" else "world" for b in c.bodies[1:]}
    filterparent = all(f.get("filterparent") != "disable" for opt in root.iter("option") for f in opt.findall("flag"))
    return ContactRules(masks, weld, weld_parent, frozenset(frozenset(p) for p in c.excluded), filterparent)


def _locked_joints(c: CompiledMjcf, first: int, model: Any, tip: str) -> list[MjcfJoint]:
    """The joints of body ``first``'s tree off the chain to ``tip``, which build_robot locks (none when
    the model has no frame ``tip``: build_robot refuses it)."""
    from robokit.description.builder import _chain_joints

    if not model.existFrame(tip):
        return []
    chain = {str(model.names[j]) for j in _chain_joints(model, tip)}
    return [j for k in c.subtree(first) for j in c.bodies[k].joints if j.name not in chain]


def _locked_note(name: str, tip: str, locked: list[MjcfJoint], degree: bool) -> str:
    """The note naming the joints locked off the chain and the value each is held at, MuJoCo's qpos0
    (a hinge's in the file's angle unit)."""
    def held(j: MjcfJoint) -> str:
        if j.type == "hinge":
            return f"{j.name} {math.degrees(j.ref):g}°" if degree else f"{j.name} {j.ref:g} rad"
        if j.type == "slide":
            return f"{j.name} {j.ref:g} m"
        return f"{j.name} ({j.type})"

    return (f"{name}: joints off the chain to {tip!r} locked at MuJoCo's qpos0, where the file draws them (a hinge "
            f"or slide at its ref, a ball or free joint with its body as written), and their bodies merged: "
            f"{', '.join(held(j) for j in locked)}")


def _default_tip(model: Any) -> str:
    """The last site on the chain's last joint (not one named like a body); else the first (in the
    file) of the deepest bodies fixed to that joint."""
    import pinocchio as pin

    body = default_tip(model)
    j = model.frames[frame_index(model, body)].parentJoint  # a joint may share the body's name
    body_names = {f.name for f in model.frames if f.type == pin.FrameType.BODY}
    # a site that shares a body's name cannot be the tip: the name means the body (frame_index)
    sites = [f.name for f in model.frames
             if f.type == pin.FrameType.OP_FRAME and f.parentJoint == j and f.name not in body_names]
    if sites:
        return str(sites[-1])

    def depth(fid: int) -> int:
        d = 0
        while fid != 0 and model.frames[fid].type != pin.FrameType.JOINT:
            fid, d = model.frames[fid].parentFrame, d + 1
        return d

    bodies = [(depth(i), -i, f.name) for i, f in enumerate(model.frames)
              if f.type == pin.FrameType.BODY and f.parentJoint == j]
    return str(max(bodies)[2]) if bodies else body


def load_mjcf(path: str | os.PathLike[str], tip: str | None = None, *,
              package_dirs: Sequence[str | os.PathLike[str]] | None = None, allow_outside_meshes: bool = False,
              reflected_inertia: bool = True) -> Robot:
    """Load an MJCF file as a :class:`robokit.Robot` (see the module docstring).

    Parameters
    ----------
    path : str or Path
        An MJCF ``.xml`` file (root element ``<mujoco>``).
    tip : str, optional
        The chain's tip frame (a body or site name). Default: the last site of the chain's
        last body, else that body's first deepest fixed child body, else that body.
    package_dirs : sequence of str or Path, optional
        More folders the file's includes and assets may be read from, beside the file's folder and
        its package (a project whose task files include ``../scene/...`` passes the folder above).
    allow_outside_meshes : bool
        Read mesh files outside the file's folder, its package and ``package_dirs`` (refused by
        default; see :mod:`robokit.description.meshes`). Includes are always confined.
    reflected_inertia : bool
        Add each joint's ``armature`` (reflected rotor inertia) to M and inverse dynamics, as MuJoCo does (default);
        False leaves it out (``robot.model.armature`` is then zero).

    Returns
    -------
    Robot
        With gravity from ``<option gravity>``, armature in ``robot.model.armature``, damping in
        ``robot.model.damping``, the file's contact rules in ``robot.contact_rules``;
        ``robot.spec == RobotSpec("mjcf", path=<absolute path>, tip=tip, ...)``.

    Raises
    ------
    InputError
        Missing file, malformed XML (file:line:column), a root element other than
        ``<mujoco>``, what MuJoCo's compiler refuses, or no serial chain to the tip.

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
    from robokit.description.mjcf_description import _mjcf_parts
    from robokit.description.mjcf_safety import check_mjcf
    from robokit.description.model_builder import build_model
    from robokit.description.urdf_files import absolute_dirs

    path = Path(path)
    if not path.exists():  # a FIFO or device is refused by the bounded reader
        raise InputError(f"{path}: file not found")
    if not isinstance(reflected_inertia, (bool, np.bool_)):
        raise InputError(f"reflected_inertia: expected True or False, got {reflected_inertia!r}")
    armature = bool(reflected_inertia)
    root = check_mjcf(path, package_dirs=package_dirs, allow_outside_meshes=allow_outside_meshes, expand_includes=True)
    if root.tag != "mujoco":
        raise InputError(f"{path}: root element <{root.tag}> is not <mujoco>; an MJCF file starts with <mujoco>")
    if all(world.find(".//body") is None for world in root.findall("worldbody")):  # MuJoCo merges them all
        raise InputError(f"{path}: <worldbody> has no <body>; nothing to load")
    c = compile_mjcf(path, root, allow_outside_meshes=allow_outside_meshes, package_dirs=package_dirs)
    if len(c.bodies) < 2:
        raise InputError(f"{path}: <worldbody> has no <body>; nothing to load")
    first = _robot_root(c)
    notes = _ignored_notes(root, c, first, path) + list(c.notes)
    exact = _custom_inertials(root, path)
    if exact:
        c = _with_exact_inertials(c, exact, path)
    desc, masks, skipped = _mjcf_parts(c, first, armature=armature)
    model, visual, collision, _ = build_model(desc)  # no mesh files read: the compiler read them
    name = c.name
    spec = RobotSpec("mjcf", path=os.path.abspath(path), tip=tip, allow_outside_meshes=allow_outside_meshes,
                     package_dirs=absolute_dirs(package_dirs),
                     reflected_inertia=armature)
    tip = tip or _default_tip(model)
    locked = _locked_joints(c, first, model, tip)
    if any(j.type == "free" or j.type in ("hinge", "slide") and j.ref != 0.0 for j in locked):
        # built again with these joints' neutral value at MuJoCo's qpos0, where build_robot cuts the chain
        desc, masks, skipped = _mjcf_parts(c, first, armature=armature, held={j.name for j in locked})
        model, visual, collision, _ = build_model(desc)
    if skipped:
        notes.append(f"{path}: geoms without a shape robokit draws or collides ignored: {', '.join(skipped)}")
    off = {j.name for j in locked}  # (a locked joint's armature is on its own diagonal entry in MuJoCo, none here)
    chain_arm = [(j.name, j.armature) for k in c.subtree(first) for j in c.bodies[k].joints
                 if j.armature and j.name not in off]
    if chain_arm and armature:
        shown = ", ".join(f"{n} {a:g}" for n, a in chain_arm[:8]) + (", ..." if len(chain_arm) > 8 else "")
        notes.append(f"{name}: joint armature (reflected rotor inertia) added to the mass matrix's diagonal and to "
                     f"inverse dynamics, as MuJoCo adds it ({shown}); load(..., reflected_inertia=False) or --no-reflected-inertia leaves it out")
    if locked:
        notes.append(_locked_note(name, tip, locked, c.compiler["angle"] != "radian"))
    geoms = [visual if visual.ngeoms else None, collision if collision.ngeoms else None]
    robot = build_robot(name, model, tip, geoms, {}, spec, notes)
    robot._amend(contact_rules=_contact_rules(c, root, masks))
    return robot
