r"""One builder from a format-independent robot description to a Pinocchio model: no URDF text in between.

A file reader (SDFormat, URDF, …) turns its file into a :class:`Description` — small frozen
values, in SI units, with every pose already resolved into the frames below — and
:func:`build_model` makes the ``pinocchio.Model`` and the visual and collision
``pinocchio.GeometryModel`` from it with Pinocchio's own calls (``addJoint``,
``appendBodyToJoint``, ``addJointFrame``, ``addBodyFrame``, ``addFrame``), exactly as
Pinocchio's URDF parser lays a model out:

* the **root link** (a link that is no joint's child) is a ``BODY`` frame on the universe joint at
  its pose in the world (:attr:`Description.root_poses`, identity by default), its inertia added
  to the universe's;
* a **moving joint** (revolute, continuous, prismatic) is a Pinocchio joint placed at the parent
  link's frame × :attr:`Joint.placement`, with a ``JOINT`` frame of its name; its child link is
  appended to it at :attr:`Joint.child_placement` (a ``BODY`` frame of the link's name; the
  link's inertia added to the joint's when it is not zero);
* a **fixed joint** is a ``FIXED_JOINT`` frame of its name (carrying the child's inertia, which
  Pinocchio adds to the parent joint's) and a ``BODY`` frame of the child link;
* **extra frames** (:class:`FrameSpec`: an SDFormat ``<frame>``, an MJCF ``<site>``) are ``OP_FRAME``
  frames, after the whole tree or (:attr:`Description.frames_with_links`) each after its link's
  ``BODY`` frame;
* children are added depth first, in the order the joints are given.

MJCF's layout, where MuJoCo gives a body several joints or none, is two options of the same calls:
a **frame-less link** (:attr:`Link.frame` False) between two joints of one body has no ``BODY``
frame (the next joint's ``JOINT`` frame hangs on the previous one's), and a **frame-less fixed
joint** (:attr:`Joint.frame` False, a welded body) has no ``FIXED_JOINT`` frame (the child's
``BODY`` frame hangs on the parent's, its inertia appended to the parent joint). A **ball** joint
is ``JointModelSpherical`` (its quaternion bounded by ±1.01, otherwise unlimited).

Joint models, as the URDF parser picks them: an axis along +x, +y or +z (after normalising) is
``JointModelRX``/``RY``/``RZ`` (``PX``/``PY``/``PZ``), any other axis ``RevoluteUnaligned``
(``PrismaticUnaligned``); a **floating** joint is ``JointModelFreeFlyer`` and a **planar** one
``JointModelPlanar`` (motion in the joint frame's xy plane, whatever the axis, as urdfdom's parser
makes them), unlimited but for the unit quaternion / (cos, sin) part, bounded by ±1.01. A **continuous** joint is Pinocchio's unbounded revolute joint
(``JointModelRUBX``/``RUBY``/``RUBZ``/``RevoluteUnboundedUnaligned``), with nq = 2 — its
configuration is (cos θ, sin θ), bounded by ±1.01 as the URDF parser bounds it — and nv = 1.

Per joint the model holds the position limits (``lowerPositionLimit``/``upperPositionLimit``),
the effort and velocity limits, the viscous ``damping`` and the dry ``friction`` (as the URDF
parser stores ``<dynamics>``; robokit's dynamics does not add them), and the reflected rotor
inertia :attr:`Joint.armature` in ``model.armature``, which Pinocchio's ``crba``, ``rnea`` and
``aba`` add on the joint's diagonal of the mass matrix (τ += armature · q̈).

Geometry (:class:`Geometry`) becomes ``GeometryObject``\ s named ``<link>_<k>`` (k counting the
link's visual or collision shapes from 0, the URDF parser's names), link by link in the model's
order (depth first, as the URDF parser walks the tree) on the link's joint and body
frame (or named :attr:`Geometry.name`); box, cylinder, sphere, capsule and ellipsoid are coal
primitives, a mesh is loaded by coal's mesh loader (a file that cannot be read is left out, with a
note), a trimesh (triangles in memory, e.g. MJCF's compiled meshes) is coal's BVH of them.

The result is checked by the tests against ``pinocchio.buildModelFromXML`` on the same robot
written as URDF: the same frames (names, types, parents, placements), joints, inertias and limits,
and the same forward kinematics, Jacobians, RNEA and mass matrix to 1e-12.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any, Iterable, Sequence

import numpy as np
from numpy.typing import ArrayLike

from robokit.description.dh import matrix_from_rpy
from robokit.description.limits import MAX_JOINTS, check_joint_count
from robokit.errors import InputError

__all__ = ["Pose", "Inertial", "Link", "Joint", "FrameSpec", "Geometry", "Description", "JOINT_KINDS",
           "GEOMETRY_KINDS", "build_model"]

#: The joint kinds a :class:`Joint` may have.
JOINT_KINDS = ("revolute", "continuous", "prismatic", "fixed", "floating", "planar", "ball")
#: The shapes a :class:`Geometry` may have, and the sizes each takes.
GEOMETRY_KINDS = {"box": 3, "cylinder": 2, "sphere": 1, "capsule": 2, "ellipsoid": 3, "mesh": 0, "trimesh": 0}

Vec3 = tuple[float, float, float]


def _vec3(value: ArrayLike, what: str) -> Vec3:
    v = np.asarray(value, dtype=float).reshape(-1)
    if v.shape != (3,) or not np.all(np.isfinite(v)):
        raise InputError(f"{what}: expected 3 finite numbers, got {np.asarray(value).tolist()!r}")
    return (float(v[0]), float(v[1]), float(v[2]))


@dataclass(frozen=True)
class Pose:
    """A rigid transform: the pose of a frame B in a frame A, ``T_A_B`` (rotation and translation).

    Attributes
    ----------
    rotation : tuple of 9 float
        ``R_A_B`` row-major (columns: B's axes in A).
    translation : tuple of 3 float
        ``p_A_B``, B's origin in A, m.

    Examples
    --------
    >>> Pose.from_xyz_rpy([0.1, 0.0, 0.2], [0.0, 0.0, np.pi / 2]).matrix.round(3)[:3].tolist()
    [[0.0, -1.0, 0.0, 0.1], [1.0, 0.0, 0.0, 0.0], [0.0, 0.0, 1.0, 0.2]]
    """

    rotation: tuple[float, ...] = (1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0)
    translation: Vec3 = (0.0, 0.0, 0.0)

    @staticmethod
    def from_matrix(T: ArrayLike) -> Pose:
        """The pose of a 4×4 homogeneous transform.

        Parameters
        ----------
        T : array_like, shape (4, 4)

        Returns
        -------
        Pose

        Examples
        --------
        >>> Pose.from_matrix(np.eye(4)) == Pose()
        True
        """
        M = np.asarray(T, dtype=float)
        if M.shape != (4, 4) or not np.all(np.isfinite(M)):
            raise InputError(f"pose: expected a finite 4x4 transform, got shape {M.shape}")
        return Pose(tuple(float(x) for x in M[:3, :3].reshape(-1)), _vec3(M[:3, 3], "pose translation"))

    @staticmethod
    def from_xyz_rpy(xyz: ArrayLike, rpy: ArrayLike) -> Pose:
        """The pose of a translation and URDF/SDFormat roll-pitch-yaw angles ``Rz(yaw) Ry(pitch) Rx(roll)``.

        Parameters
        ----------
        xyz : array_like, shape (3,)
            Translation, m.
        rpy : array_like, shape (3,)
            Roll, pitch, yaw, rad (rotations about the fixed x, y, z axes, in that order).

        Returns
        -------
        Pose

        Examples
        --------
        >>> Pose.from_xyz_rpy([1, 2, 3], [0, 0, 0]).translation
        (1.0, 2.0, 3.0)
        """
        T = np.eye(4)
        T[:3, :3] = matrix_from_rpy(_vec3(rpy, "rpy"))
        T[:3, 3] = _vec3(xyz, "xyz")
        return Pose.from_matrix(T)

    @property
    def matrix(self) -> np.ndarray:
        """The 4×4 homogeneous transform ``T_A_B`` (a new array)."""
        T = np.eye(4)
        T[:3, :3] = np.asarray(self.rotation, dtype=float).reshape(3, 3)
        T[:3, 3] = self.translation
        return T


@dataclass(frozen=True)
class Inertial:
    """A link's mass properties, in the link frame.

    Attributes
    ----------
    mass : float
        kg (≥ 0).
    com : tuple of 3 float
        The centre of mass in the link frame, m.
    inertia : tuple of 6 float
        The rotational inertia about the centre of mass, in the link frame's axes:
        ``(ixx, ixy, ixz, iyy, iyz, izz)``, kg·m².

    Examples
    --------
    >>> float(Inertial(2.0, (0.0, 0.0, 0.1), (0.01, 0.0, 0.0, 0.01, 0.0, 0.02)).matrix()[2, 2])
    0.02
    """

    mass: float
    com: Vec3 = (0.0, 0.0, 0.0)
    inertia: tuple[float, float, float, float, float, float] = (0.0, 0.0, 0.0, 0.0, 0.0, 0.0)

    @staticmethod
    def from_frame(mass: float, pose: Pose, inertia_in_frame: Sequence[float]) -> Inertial:
        """The inertial of a mass whose centre and inertia axes are given as a frame ``pose`` in the link.

        Parameters
        ----------
        mass : float
            kg.
        pose : Pose
            The inertial frame in the link frame: its origin is the centre of mass.
        inertia_in_frame : sequence of 6 float
            ``(ixx, ixy, ixz, iyy, iyz, izz)`` about the centre of mass in the inertial frame's axes.

        Returns
        -------
        Inertial
            With the inertia re-expressed in the link's axes, ``R I Rᵀ``.

        Examples
        --------
        A rod along the inertial frame's x, turned a quarter about z, lies along the link's y:

        >>> pose = Pose.from_xyz_rpy([0, 0, 0], [0, 0, np.pi / 2])
        >>> (np.round(Inertial.from_frame(1.0, pose, (0.0, 0, 0, 1.0, 0, 1.0)).inertia, 12) + 0.0).tolist()
        [1.0, 0.0, 0.0, 0.0, 0.0, 1.0]
        """
        ixx, ixy, ixz, iyy, iyz, izz = (float(v) for v in inertia_in_frame)
        I = np.array([[ixx, ixy, ixz], [ixy, iyy, iyz], [ixz, iyz, izz]])
        R = np.asarray(pose.rotation, dtype=float).reshape(3, 3)
        J = R @ I @ R.T
        ixx, ixy, ixz, iyy, iyz, izz = (float(J[i, j]) for i, j in ((0, 0), (0, 1), (0, 2), (1, 1), (1, 2), (2, 2)))
        return Inertial(float(mass), pose.translation, (ixx, ixy, ixz, iyy, iyz, izz))

    def matrix(self) -> np.ndarray:
        """The 3×3 rotational inertia about the centre of mass, link axes, kg·m².

        Returns
        -------
        numpy.ndarray, shape (3, 3)

        Examples
        --------
        >>> Inertial(1.0, inertia=(1.0, 0.0, 0.0, 2.0, 0.0, 3.0)).matrix().diagonal().tolist()
        [1.0, 2.0, 3.0]
        """
        ixx, ixy, ixz, iyy, iyz, izz = self.inertia
        return np.array([[ixx, ixy, ixz], [ixy, iyy, iyz], [ixz, iyz, izz]])


@dataclass(frozen=True)
class Link:
    """One rigid body.

    Attributes
    ----------
    name : str
        Its name (a ``BODY`` frame of the model).
    inertial : Inertial or None
        Its mass properties; None: massless.
    frame : bool
        Whether it is a ``BODY`` frame of the model (default). False: an intermediate link between
        two joints of one body (MJCF's several joints per body), with no frame, no geometry and no
        :class:`FrameSpec` of its own (an inertial, if given, is appended to its joint); the next
        joint hangs on the previous one's ``JOINT`` frame.

    Examples
    --------
    >>> Link("base").inertial is None
    True
    """

    name: str
    inertial: Inertial | None = None
    frame: bool = True


@dataclass(frozen=True)
class Joint:
    """One joint between two links.

    Attributes
    ----------
    name : str
        Its name.
    kind : str
        One of :data:`JOINT_KINDS`.
    parent : str or None
        The parent link; None: the world (the joint hangs on Pinocchio's universe).
    child : str
        The child link.
    placement : Pose
        The joint frame in the parent link's frame (in the world for ``parent=None``), at q = 0.
    child_placement : Pose
        The child link's frame in the joint frame (identity in URDF, where they coincide; MJCF
        puts here the constant part of a joint's ``ref`` offset and the way back from its anchor).
    axis : tuple of 3 float
        The motion axis in the joint frame (normalised by the builder); unused for ``"fixed"``.
    lower, upper : float
        Position limits, rad or m (±inf when unlimited; unused for continuous and fixed joints).
    velocity, effort : float
        Velocity (rad/s or m/s) and effort (N·m or N) limits, inf when unlimited.
    damping, friction : float
        Viscous damping (N·m·s/rad or N·s/m) and dry friction (N·m or N), stored in the model.
    armature : float
        Reflected rotor inertia (kg·m² or kg), added on the joint's diagonal of M and in RNEA.
    frame : bool
        Whether the joint is a frame of the model (default): a ``JOINT`` frame, or for a fixed
        joint a ``FIXED_JOINT`` frame carrying the child's inertia. False (fixed joints only: an
        MJCF body welded to its parent, which MuJoCo gives no joint): the child's ``BODY`` frame
        hangs directly on the parent link's frame and its inertia is appended to the parent joint.

    Examples
    --------
    >>> Joint("j1", "continuous", "base", "link1").axis
    (0.0, 0.0, 1.0)
    """

    name: str
    kind: str
    parent: str | None
    child: str
    placement: Pose = field(default_factory=Pose)
    child_placement: Pose = field(default_factory=Pose)
    axis: Vec3 = (0.0, 0.0, 1.0)
    lower: float = -math.inf
    upper: float = math.inf
    velocity: float = math.inf
    effort: float = math.inf
    damping: float = 0.0
    friction: float = 0.0
    armature: float = 0.0
    frame: bool = True


@dataclass(frozen=True)
class FrameSpec:
    """A named frame fixed to a link (an SDFormat ``<frame>``): an ``OP_FRAME`` of the model.

    Attributes
    ----------
    name : str
    parent : str or None
        The link it is attached to; None: the world.
    placement : Pose
        The frame in that link's frame.

    Examples
    --------
    >>> FrameSpec("tcp", "link6", Pose(translation=(0.0, 0.0, 0.1))).parent
    'link6'
    """

    name: str
    parent: str | None
    placement: Pose = field(default_factory=Pose)


@dataclass(frozen=True)
class Geometry:
    """A shape fixed to a link, for drawing (visual) or collision checking (collision).

    Attributes
    ----------
    link : str
        The link it belongs to.
    kind : str
        ``"box"``, ``"cylinder"``, ``"sphere"``, ``"capsule"``, ``"ellipsoid"``, ``"mesh"`` (a
        file coal loads) or ``"trimesh"`` (triangles given as :attr:`vertices` and :attr:`faces`).
    placement : Pose
        The shape's frame in the link frame (a cylinder's and capsule's axis is its z).
    size : tuple of float
        box: the three full edge lengths; cylinder and capsule: (radius, length); sphere:
        (radius,); ellipsoid: its three semi-axes; mesh and trimesh: ().
    collision : bool
        True: a collision shape; False: a visual one.
    mesh : str or None
        The mesh file (an absolute path the reader has already confined). For a trimesh: the file
        the triangles came from, kept as the geometry's ``meshPath`` for viewers that redraw it
        (None: none).
    scale : tuple of 3 float
        The mesh's scale per axis (for a trimesh only recorded, as ``meshScale``: its vertices
        are already scaled).
    color : tuple of 4 float or None
        RGBA in [0, 1]; None: the viewer's default.
    name : str or None
        The geometry object's name; None: ``<link>_<k>`` (the URDF parser's names).
    vertices : numpy.ndarray or None, shape (n, 3)
        A trimesh's vertices in the shape's frame, m.
    faces : numpy.ndarray or None, shape (m, 3)
        A trimesh's triangles, as indices into :attr:`vertices`.

    Examples
    --------
    >>> Geometry("link1", "cylinder", Pose(), (0.05, 0.3)).size
    (0.05, 0.3)
    """

    link: str
    kind: str
    placement: Pose = field(default_factory=Pose)
    size: tuple[float, ...] = ()
    collision: bool = False
    mesh: str | None = None
    scale: Vec3 = (1.0, 1.0, 1.0)
    color: tuple[float, float, float, float] | None = None
    name: str | None = None
    vertices: np.ndarray | None = field(default=None, compare=False, repr=False)
    faces: np.ndarray | None = field(default=None, compare=False, repr=False)


@dataclass(frozen=True)
class Description:
    """A whole robot, format-independent: what :func:`build_model` takes.

    Attributes
    ----------
    name : str
        The robot's (model's) name.
    links : tuple of Link
    joints : tuple of Joint
        A tree: every link is the child of at most one joint.
    frames : tuple of FrameSpec
    geometries : tuple of Geometry
    root_poses : tuple of (str, Pose)
        The world pose of links that are no joint's child (default: identity).
    gravity : tuple of 3 float
        m/s², in the world frame.
    frames_with_links : bool
        False (default): the :attr:`frames` are added after the whole tree, in the order given
        (SDFormat's ``<frame>`` elements); True: each right after its link's ``BODY`` frame (MJCF's
        sites, which MuJoCo numbers body by body).

    Examples
    --------
    >>> d = Description("one", (Link("base"), Link("arm", Inertial(1.0, (0.5, 0, 0)))),
    ...                 (Joint("j1", "revolute", "base", "arm", lower=-1.0, upper=1.0),))
    >>> build_model(d)[0].nq
    1
    """

    name: str
    links: tuple[Link, ...]
    joints: tuple[Joint, ...] = ()
    frames: tuple[FrameSpec, ...] = ()
    geometries: tuple[Geometry, ...] = ()
    root_poses: tuple[tuple[str, Pose], ...] = ()
    gravity: Vec3 = (0.0, 0.0, -9.81)
    frames_with_links: bool = False


# --------------------------------------------------------------------------- checks
def _check(desc: Description) -> tuple[dict[str, Link], dict[str | None, list[Joint]], list[str]]:
    """Links by name, joints by parent link (file order), and the root links; InputError if not a tree."""
    # moving joints are what Pinocchio's Data grows with; fixed joints are frames (the readers bound their count)
    check_joint_count(sum(j.kind != "fixed" for j in desc.joints), desc.name, "moving joints")
    if len(desc.joints) > 4 * MAX_JOINTS:
        raise InputError(f"{desc.name}: {len(desc.joints)} joints; robokit builds at most {4 * MAX_JOINTS} "
                         f"(of which {MAX_JOINTS} moving)")
    links: dict[str, Link] = {}
    for link in desc.links:
        if link.name in links:
            raise InputError(f"{desc.name}: link {link.name!r} is defined twice")
        links[link.name] = link
    names: set[str] = set()
    children: dict[str | None, list[Joint]] = {}
    parent_of: dict[str, str | None] = {}
    for j in desc.joints:
        if j.name in names:
            raise InputError(f"{desc.name}: joint {j.name!r} is defined twice")
        names.add(j.name)
        if j.kind not in JOINT_KINDS:
            raise InputError(f"{desc.name}: joint {j.name!r} is a {j.kind!r} joint; robokit builds "
                             f"{', '.join(JOINT_KINDS)} joints")
        for end in (j.parent, j.child):
            if end is not None and end not in links:
                raise InputError(f"{desc.name}: joint {j.name!r} names link {end!r}, which is not defined")
        if j.child in parent_of:
            raise InputError(f"{desc.name}: link {j.child!r} is the child of two joints")
        parent_of[j.child] = j.parent
        if j.kind in _AXIS_MODELS and np.linalg.norm(j.axis) < 1e-12:
            raise InputError(f"{desc.name}: joint {j.name!r}: the axis is zero")
        if j.kind in ("revolute", "prismatic") and j.lower > j.upper:
            raise InputError(f"{desc.name}: joint {j.name!r}: lower limit {j.lower:g} is above the upper limit "
                             f"{j.upper:g}")
        if j.armature < 0 or not math.isfinite(j.armature):
            raise InputError(f"{desc.name}: joint {j.name!r}: the reflected inertia must be finite and >= 0")
        if not j.frame and j.kind != "fixed":
            raise InputError(f"{desc.name}: joint {j.name!r}: a {j.kind} joint is always a frame of the model")
        children.setdefault(j.parent, []).append(j)
    roots = [name for name in links if name not in parent_of]
    for name in roots:
        if not links[name].frame:
            raise InputError(f"{desc.name}: link {name!r} has no frame but is no joint's child")
    # every link must reach the world: walk up from each (a cycle never does)
    for name in links:
        seen, k = set(), name
        while k in parent_of:
            if k in seen:
                raise InputError(f"{desc.name}: the joints form a loop through link {k!r}")
            seen.add(k)
            up = parent_of[k]
            if up is None:
                break
            k = up
    pose_names = [n for n, _ in desc.root_poses]
    for n in pose_names:
        if n not in roots:
            raise InputError(f"{desc.name}: root pose given for {n!r}, which is not a root link")
    return links, children, roots


# --------------------------------------------------------------------------- Pinocchio
def _se3(pose: Pose) -> Any:
    import pinocchio as pin

    return pin.SE3(np.asarray(pose.rotation, dtype=float).reshape(3, 3), np.asarray(pose.translation, dtype=float))


def _inertia(inertial: Inertial | None) -> Any:
    import pinocchio as pin

    Y = pin.Inertia.Zero()
    if inertial is None:
        return Y
    # set field by field: the checked constructor refuses a rotated rod whose zero moment came out -1e-22, which
    # Pinocchio's URDF parser (and so every URDF robokit reads) accepts; the readers check physical validity
    Y.mass = float(inertial.mass)
    Y.lever = np.asarray(inertial.com, dtype=float)
    Y.inertia = inertial.matrix()
    return Y


_AXIS_MODELS = {
    "revolute": ("JointModelRX", "JointModelRY", "JointModelRZ", "JointModelRevoluteUnaligned"),
    "continuous": ("JointModelRUBX", "JointModelRUBY", "JointModelRUBZ", "JointModelRevoluteUnboundedUnaligned"),
    "prismatic": ("JointModelPX", "JointModelPY", "JointModelPZ", "JointModelPrismaticUnaligned"),
}


def _joint_model(joint: Joint) -> Any:
    """The Pinocchio joint model of a moving joint (the URDF parser's choice, see the module docstring)."""
    import pinocchio as pin

    axis = np.asarray(joint.axis, dtype=float)
    axis = axis / np.linalg.norm(axis)
    names = _AXIS_MODELS[joint.kind]
    for k in range(3):
        if np.allclose(axis, np.eye(3)[k], rtol=0.0, atol=1e-12):
            return getattr(pin, names[k])()
    if joint.kind == "continuous":
        return _unbounded_unaligned(axis)
    return getattr(pin, names[3])(axis)


def _unbounded_unaligned(axis: np.ndarray) -> Any:
    """Pinocchio's unbounded revolute joint about ``axis`` (unit, not along x, y or z).

    Pinocchio's Python bindings construct ``JointModelRevoluteUnboundedUnaligned`` without an axis
    only (the constructor taking one is not bound), so the joint model is taken from a one-joint
    model made by Pinocchio's model graph (``pinocchio.graph``: no URDF text involved), whose
    ``JointRevoluteUnbounded`` takes the axis; the result is the same joint the URDF parser makes.
    """
    import pinocchio as pin

    try:
        return pin.JointModelRevoluteUnboundedUnaligned(axis)
    except TypeError:  # Boost.Python.ArgumentError (a TypeError): no constructor taking the axis
        pass
    graph = pin.graph
    g = graph.ModelGraph()
    g.addBody("parent", pin.Inertia.Zero())
    g.addBody("child", pin.Inertia.Zero())
    g.addJoint("joint", graph.JointRevoluteUnbounded(axis), "parent", pin.SE3.Identity(), "child",
               pin.SE3.Identity())
    return graph.buildModel(g, "parent", pin.SE3.Identity()).joints[1]


@dataclass(frozen=True)
class _Where:
    """Where a link sits in the model being built: its joint, its placement in that joint, and the
    frame its children's frames hang on (its BODY frame; a frame-less link's JOINT frame)."""

    joint: int
    placement: Any
    frame: int


def _add_moving(model: Any, joint: Joint, parent: _Where, inertia: Any, body: bool) -> _Where:
    """addJoint + addJointFrame + the child body, as the URDF parser's addJointAndBody does
    (``body=False``: no BODY frame for the child, a frame-less intermediate link)."""
    import pinocchio as pin

    if joint.kind in _AXIS_MODELS:
        jm = _joint_model(joint)
        effort, velocity = np.array([joint.effort]), np.array([joint.velocity])
        if joint.kind == "continuous":
            lo, hi = np.array([-1.01, -1.01]), np.array([1.01, 1.01])
        else:
            lo, hi = np.array([joint.lower]), np.array([joint.upper])
    else:
        # a floating, planar or ball joint, as the URDF parser makes the first two: unlimited but for the
        # unit (co)sine/quaternion part of the configuration (±1.01); no damping, friction, armature
        jm, nv, nq, unit = {"floating": (pin.JointModelFreeFlyer(), 6, 7, 4),
                            "planar": (pin.JointModelPlanar(), 3, 4, 2),
                            "ball": (pin.JointModelSpherical(), 3, 4, 4)}[joint.kind]
        effort, velocity = np.full(nv, np.inf), np.full(nv, np.inf)
        lo, hi = np.full(nq, -np.inf), np.full(nq, np.inf)
        lo[nq - unit:], hi[nq - unit:] = -1.01, 1.01
    jid = model.addJoint(parent.joint, jm, parent.placement * _se3(joint.placement), joint.name,
                         effort, velocity, lo, hi)
    if joint.kind in _AXIS_MODELS:
        iv = model.joints[jid].idx_v
        for attr, value in (("damping", joint.damping), ("upperDryFrictionLimit", joint.friction),
                            ("lowerDryFrictionLimit", -joint.friction), ("armature", joint.armature)):
            arr = np.array(getattr(model, attr), dtype=float)
            arr[iv] = value
            setattr(model, attr, arr)
    jfid = model.addJointFrame(jid, parent.frame)
    placement = model.frames[jfid].placement * _se3(joint.child_placement)
    if not inertia.isZero(0.0):
        model.appendBodyToJoint(jid, inertia, placement)
    if not body:
        return _Where(jid, placement, jfid)
    return _Where(jid, placement, model.addBodyFrame(joint.child, jid, placement, jfid))


def _add_fixed(model: Any, joint: Joint, parent: _Where, inertia: Any, body: bool) -> _Where:
    """A fixed joint: a FIXED_JOINT frame carrying the child's inertia and the child's BODY frame, or
    (``joint.frame`` False) the BODY frame alone, hung on the parent's frame, the inertia appended."""
    import pinocchio as pin

    placement = parent.placement * _se3(joint.placement)
    fid = parent.frame
    if joint.frame:
        fid = model.addFrame(pin.Frame(joint.name, parent.joint, parent.frame, placement, pin.FrameType.FIXED_JOINT,
                                       inertia))
    placement = placement * _se3(joint.child_placement)
    if not joint.frame and not inertia.isZero(0.0):
        model.appendBodyToJoint(parent.joint, inertia, placement)
    if body:
        fid = model.addBodyFrame(joint.child, parent.joint, placement, fid)
    return _Where(parent.joint, placement, fid)


def build_model(desc: Description) -> tuple[Any, Any, Any, list[str]]:
    """The Pinocchio model and geometry of a :class:`Description` (see the module docstring).

    Parameters
    ----------
    desc : Description
        The robot.

    Returns
    -------
    model : pinocchio.Model
        The whole kinematic tree, gravity ``desc.gravity``.
    visual : pinocchio.GeometryModel
        The visual shapes.
    collision : pinocchio.GeometryModel
        The collision shapes.
    notes : list of str
        What was left out (a mesh coal could not read), one line each.

    Raises
    ------
    InputError
        Not a tree (a link child of two joints, a loop, a joint naming an unknown link), two
        links or joints with one name, an unknown joint kind, a zero axis, lower > upper, more
        moving joints than :data:`robokit.description.limits.MAX_JOINTS` (or four times as many
        joints in all), a frame-less link that is a root or carries a frame or a geometry.

    Examples
    --------
    A planar arm of two 1 m links, each a 1 kg point mass at its end:

    >>> def link(name): return Link(name, Inertial(1.0, (1.0, 0.0, 0.0)))
    >>> shift = Pose(translation=(1.0, 0.0, 0.0))
    >>> desc = Description("planar", (Link("base"), link("l1"), link("l2")),
    ...                    (Joint("j1", "revolute", "base", "l1", lower=-3, upper=3),
    ...                     Joint("j2", "revolute", "l1", "l2", shift, lower=-3, upper=3)))
    >>> model, visual, collision, notes = build_model(desc)
    >>> model.nq, [f.name for f in model.frames][1:]
    (2, ['base', 'j1', 'l1', 'j2', 'l2'])
    """
    import pinocchio as pin

    links, children, roots = _check(desc)
    model = pin.Model()
    model.name = desc.name
    model.gravity = pin.Motion(np.asarray(_vec3(desc.gravity, "gravity")), np.zeros(3))
    root_pose = dict(desc.root_poses)
    where: dict[str, _Where] = {}
    body_fid: dict[str, int] = {}
    attached: dict[str | None, list[FrameSpec]] = {}
    for fs in desc.frames:
        if fs.parent is not None and (fs.parent not in links or not links[fs.parent].frame):
            raise InputError(f"{desc.name}: frame {fs.name!r} is attached to {fs.parent!r}, which is not a link"
                             + (" with a frame" if fs.parent in links else ""))
        attached.setdefault(fs.parent if desc.frames_with_links else None, []).append(fs)

    def add_frames(link_name: str | None) -> None:
        for fs in attached.get(link_name, []):
            if fs.parent is None:
                parent = _Where(0, model.frames[0].placement, 0)
            else:
                parent = where[fs.parent]
            model.addFrame(pin.Frame(fs.name, parent.joint, parent.frame, parent.placement * _se3(fs.placement),
                                     pin.FrameType.OP_FRAME), False)

    def add_subtree(link_name: str) -> None:
        if links[link_name].frame:
            body_fid[link_name] = where[link_name].frame
            add_frames(link_name)
        for joint in children.get(link_name, []):
            add_joint(joint, where[link_name])

    def add_joint(joint: Joint, parent: _Where) -> None:
        child = links[joint.child]
        add = _add_fixed if joint.kind == "fixed" else _add_moving
        where[joint.child] = add(model, joint, parent, _inertia(child.inertial), child.frame)
        add_subtree(joint.child)

    for name in roots:
        placement = _se3(root_pose.get(name, Pose()))
        where[name] = _Where(0, placement, model.addFrame(pin.Frame(name, 0, 0, placement, pin.FrameType.BODY,
                                                                    _inertia(links[name].inertial))))
        add_subtree(name)
    for joint in children.get(None, []):
        add_joint(joint, _Where(0, model.frames[0].placement, 0))
    add_frames(None)
    visual, collision, notes = _geometry_models(model, desc.geometries, body_fid, desc.name)
    return model, visual, collision, notes


# --------------------------------------------------------------------------- geometry
_DEFAULT_COLOR = np.array([0.9, 0.9, 0.9, 1.0])


def _shape(geom: Geometry, where: str) -> tuple[Any, str]:
    """(coal collision geometry, Pinocchio's meshPath for it)."""
    import coal

    want = GEOMETRY_KINDS.get(geom.kind)
    if want is None:
        raise InputError(f"{where}: unknown shape {geom.kind!r} (expected one of {', '.join(GEOMETRY_KINDS)})")
    if len(geom.size) != want or not all(math.isfinite(s) and s >= 0 for s in geom.size):
        raise InputError(f"{where}: a {geom.kind} takes {want} non-negative sizes, got {list(geom.size)}")
    if geom.kind == "box":
        return coal.Box(*geom.size), "BOX"
    if geom.kind == "cylinder":
        return coal.Cylinder(*geom.size), "CYLINDER"
    if geom.kind == "capsule":
        return coal.Capsule(*geom.size), "CAPSULE"
    if geom.kind == "sphere":
        return coal.Sphere(geom.size[0]), "SPHERE"
    if geom.kind == "ellipsoid":
        return coal.Ellipsoid(*geom.size), "ELLIPSOID"
    if geom.kind == "trimesh":
        return _bvh(geom, where), geom.mesh or ""
    from robokit.description.meshes import mesh_file_problem, without_meshes

    if not geom.mesh:
        raise InputError(f"{where}: a mesh needs a file")
    problem = mesh_file_problem(geom.mesh)
    if problem is not None:
        raise _MeshSkipped(f"{where}: mesh {geom.mesh!r} not read ({problem}); "
                           f"{without_meshes(geom.collision, 1)}")
    try:
        return coal.MeshLoader().load(geom.mesh, np.asarray(geom.scale, dtype=float)), geom.mesh
    except Exception as exc:  # coal raises RuntimeError/ValueError with the loader's message
        from robokit.description.builder import one_line

        raise _MeshSkipped(f"{where}: mesh {geom.mesh!r} not read ({one_line(exc)}); "
                           f"{without_meshes(geom.collision, 1)}") from None


def _bvh(geom: Geometry, where: str) -> Any:
    """coal's bounding-volume hierarchy of a trimesh's triangles."""
    import coal

    v = np.asarray(geom.vertices if geom.vertices is not None else np.zeros((0, 3)), dtype=float)
    f = np.asarray(geom.faces if geom.faces is not None else np.zeros((0, 3)))
    if v.ndim != 2 or v.shape[1] != 3 or not np.all(np.isfinite(v)) or len(v) == 0:
        raise InputError(f"{where}: a trimesh takes an (n, 3) array of finite vertices, got shape {v.shape}")
    if f.ndim != 2 or f.shape[1] != 3 or len(f) == 0 or f.dtype.kind not in "iu" or f.min() < 0 or f.max() >= len(v):
        raise InputError(f"{where}: a trimesh takes an (m, 3) array of vertex indices in [0, {len(v)}), "
                         f"got shape {f.shape}")
    m = coal.BVHModelOBBRSS()
    m.beginModel(len(f), len(v))
    m.addVertices(np.ascontiguousarray(v))
    m.addTriangles(np.ascontiguousarray(f, dtype=np.int64))
    m.endModel()
    return m


class _MeshSkipped(Exception):
    """A mesh the loader could not read: left out with a note."""


def _geometry_models(model: Any, geometries: Iterable[Geometry], body_fid: dict[str, int],
                     name: str) -> tuple[Any, Any, list[str]]:
    import pinocchio as pin

    out = {False: pin.GeometryModel(), True: pin.GeometryModel()}
    counts: dict[tuple[str, bool], int] = {}
    notes: list[str] = []
    # in the model's link order (depth first, as the URDF parser walks the tree), each link's shapes as given
    geometries = sorted(geometries, key=lambda g: body_fid.get(g.link, -1))
    for geom in geometries:
        role = "collision" if geom.collision else "visual"
        where = f"{name}: link {geom.link!r}, {role} {geom.kind}"
        if geom.link not in body_fid:
            raise InputError(f"{where}: no such link with a frame")
        key = (geom.link, geom.collision)
        k = counts.get(key, 0)
        counts[key] = k + 1
        try:
            shape, mesh_path = _shape(geom, where)
        except _MeshSkipped as skipped:
            notes.append(str(skipped))
            continue
        fid = body_fid[geom.link]
        frame = model.frames[fid]
        color = _DEFAULT_COLOR if geom.color is None else np.asarray(geom.color, dtype=float)
        scale = np.asarray(geom.scale if geom.kind in ("mesh", "trimesh") else (1.0, 1.0, 1.0), dtype=float)
        go = pin.GeometryObject(geom.name or f"{geom.link}_{k}", frame.parentJoint, fid,
                                frame.placement * _se3(geom.placement), shape, mesh_path, scale, geom.color is not None,
                                color)
        out[geom.collision].addGeometryObject(go)
    return out[False], out[True], notes
