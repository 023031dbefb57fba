"""The collision world: a robot's geometry and the obstacles around it, queried with coal.

Geometry of the robot
    * A robot with collision geometry (``robot.collision_model``: URDF/MJCF collision meshes,
      example-robot-data) uses it as loaded — meshes as triangle BVHs.
    * ``World(..., convex=True)`` replaces each of these meshes by its **convex hull** (coal's
      ``BVHModel.buildConvexHull``, Qhull underneath; built once per robot and cached). A hull
      contains its mesh, so the hull world is *conservative*: whenever the meshes touch, the
      hulls do, and every distance is at most the mesh distance. It is faster (GJK on a
      convex set instead of a tree of triangles) but sees concave links (a U-shaped bracket, a
      base with a recess) as filled. Primitive shapes and obstacle meshes are used as given, and
      so is a flat mesh (all its vertices in one plane), which Qhull cannot wrap.
    * A robot without it (the DH models, whose generated URDF has only visuals) gets one
      **capsule per link**: the segment from the link's joint origin to the next joint's origin
      (to the tip frame for the last link), radius the thinnest visual cylinder attached to that
      joint (the generated URDF's link cylinders), or :data:`DEFAULT_CAPSULE_RADIUS`. A
      zero-length segment becomes a sphere of that radius.

Pairs checked
    Every robot geometry against every obstacle, and the robot's **self-collision pairs**:
    all pairs of geometries on different links except (a) adjacent links (parent and child
    joint, or two links fixed to one joint) and (b) pairs in contact in *every* one of
    :data:`SELF_SAMPLES` random configurations (uniform in the joint limits,
    ``numpy.random.default_rng(SELF_SEED)``) — MoveIt setup assistant's "adjacent" and "always
    in collision" rules. Pairs that never collided in the samples are listed too but are
    *kept* (a folded arm must still be seen). For a robot read from MJCF, (c) every pair MuJoCo
    would never test is skipped too (``robot.contact_rules``,
    :class:`robokit.description.mjcf.ContactRules`): ``(contype₁ & conaffinity₂) |
    (contype₂ & conaffinity₁)`` zero, geoms of bodies welded together, a body and its parent
    (MuJoCo's parent filter) and the ``<contact><exclude>`` body pairs; an MJCF geom whose masks
    share no bit with MuJoCo's default (contype = conaffinity = 1) is not checked against
    obstacles either. ``describe()`` lists each such pair with its reason.

    The filter works on pairs of geometries (shapes); the table reports **link pairs**, each
    once, in one of three places: *adjacent*; *always in contact* — only when every shape pair
    of the two links was in contact in every sample (the link pair is then not checked); or
    *checked* — at least one of its shape pairs is checked, and when some of its shape pairs
    were in contact in every sample (two shapes of one link, one of them overlapping the other
    link at every configuration) those alone are skipped and the table says how many
    (``partly``). A link is named by its body frame in the file (a geometry on a frame the
    file does not name, e.g. an unnamed MJCF body, counts for the nearest named frame above).
    The result is computed once per robot and cached (:func:`self_collision_pairs`), always on
    the robot's own geometry (meshes, not hulls): a convex world checks the same pairs, which
    keeps it conservative. ``print(world.describe())`` shows the table.

Padding
    ``padding`` (m) inflates every robot geometry: a robot–obstacle pair counts as colliding
    when its distance is below ``padding``, a self pair below ``2·padding``, and
    :meth:`World.distance` reports the distance of the inflated geometry.

Accuracy
    Distances are computed by coal with GJK tolerance :data:`GJK_TOLERANCE` (coal's default,
    1e-6, left hull and mesh distances up to 1e-8 m apart where both are exact).

Shipping a world
    A ``World`` holds coal objects, which are not sent between processes. ``world.state()``
    is its plain data (:class:`WorldState`: the robot's ``RobotSpec``, the obstacles, the
    padding, ``convex`` and the self-collision pairs); ``World.from_state(state)`` rebuilds it
    in another process without recomputing the pairs, and ``pickle`` does exactly this (a
    world pickles as its state), so Dask ships a world to its workers.
"""
from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any, Callable, Iterable, cast

import numpy as np

from robokit._arrays import as_array, as_scalar
from robokit.collision.shapes import Obstacle
from robokit.errors import InputError

__all__ = ["World", "WorldState", "SelfCollisionPairs", "self_collision_pairs", "DEFAULT_CAPSULE_RADIUS",
           "SELF_SAMPLES", "SELF_SEED", "GJK_TOLERANCE"]

DEFAULT_CAPSULE_RADIUS = 0.04  # m, for a DH link with no visual cylinder
SELF_SAMPLES = 1000
SELF_SEED = 0
#: coal's GJK tolerance for the distance queries (m).
GJK_TOLERANCE = 1e-9



def _se3(T: np.ndarray) -> Any:
    import pinocchio as pin
    return pin.SE3(np.asarray(T[:3, :3], dtype=float).copy(), np.asarray(T[:3, 3], dtype=float).copy())


def _reported(robot: Any) -> set[str]:
    """The frame names the robot reports (``robot.frame_names``; every frame for other objects)."""
    names = getattr(robot, "frame_names", None)
    return set(names) if names is not None else {f.name for f in robot.model.frames}


def _link_name(model: Any, joint: int, reported: set[str] | None = None) -> str:
    for f in model.frames:
        if f.parentJoint == joint and str(f.type) == "BODY" and (reported is None or f.name in reported):
            return str(f.name)
    return str(model.names[joint])


def _frame_link_name(model: Any, frame: int, reported: set[str]) -> str:
    """The name of a geometry's frame, or of its nearest ancestor frame the file names."""
    k, seen = frame, 0
    while k < len(model.frames) and model.frames[k].name not in reported and seen < len(model.frames):
        if model.frames[k].parentFrame == k:
            break
        k, seen = model.frames[k].parentFrame, seen + 1
    if k < len(model.frames) and model.frames[k].name in reported:
        return str(model.frames[k].name)
    return _link_name(model, model.frames[frame].parentJoint, reported) if frame < len(model.frames) else "?"


def _capsule_model(robot: Any) -> Any:
    """One capsule (or sphere) per moving link, from consecutive joint origins."""
    import coal
    import pinocchio as pin
    model = robot.model
    gm = pin.GeometryModel()
    radius: dict[int, float] = {}
    if robot.visual_model is not None:
        for g in robot.visual_model.geometryObjects:
            if isinstance(g.geometry, coal.Cylinder):
                r = float(g.geometry.radius)
                radius[g.parentJoint] = min(radius.get(g.parentJoint, np.inf), r)
    tip_frame = model.frames[robot.tip_id]
    for j in range(1, model.njoints):
        ends = [np.asarray(model.jointPlacements[k].translation) for k in range(1, model.njoints)
                if model.parents[k] == j]
        if not ends:
            ends = [np.asarray(tip_frame.placement.translation) if tip_frame.parentJoint == j else np.zeros(3)]
        r = radius.get(j, DEFAULT_CAPSULE_RADIUS)
        name = _link_name(model, j, _reported(robot))
        for e_i, end in enumerate(ends):
            L = float(np.linalg.norm(end))
            if L < 1e-9:
                geom, R = coal.Sphere(r), np.eye(3)
            else:
                z = end / L
                a = np.array([1.0, 0, 0]) if abs(z[0]) < 0.9 else np.array([0, 1.0, 0])
                x = np.cross(a, z)
                x /= np.linalg.norm(x)
                R = np.column_stack([x, np.cross(z, x), z])
                geom = coal.Capsule(r, L)
            T = np.eye(4)
            T[:3, :3], T[:3, 3] = R, end / 2
            go = pin.GeometryObject(f"{name}_capsule{e_i}", j, _se3(T), geom)
            gm.addGeometryObject(go)
    return gm


def _solid(points: np.ndarray) -> bool:
    """Whether the points span 3-D space (Qhull needs that; coal's wrapper crashes on a flat set)."""
    if len(points) < 4 or not np.isfinite(points).all():
        return False
    c = points - points.mean(axis=0)
    sv = np.linalg.svd(c, compute_uv=False)
    return bool(sv[2] > 1e-9 * max(sv[0], 1e-300))


def _once(robot: Any, key: str, build: Callable[[], Any]) -> Any:
    """``robot.derived(key, build)`` (computed once, kept with the robot); ``build()`` for a
    robot-like object without that store."""
    derived = getattr(robot, "derived", None)
    return build() if derived is None else derived(key, build)


def _hull(robot: Any, k: int, geometry: Any) -> Any:
    """The convex hull of the robot's k-th collision mesh (a coal ConvexBase), built once per
    robot; None for a flat or degenerate mesh (kept as a mesh: it is its own conservative bound)."""
    hulls: dict[int, Any] = _once(robot, "convex_hulls", dict)  # one per geometry index, built once per robot
    if k not in hulls:
        if not _solid(np.asarray(geometry.vertices(), dtype=float)):
            hulls[k] = None
        else:
            mesh = geometry.clone()  # the robot's own geometry is left untouched
            mesh.buildConvexHull(False, "Qt")
            hulls[k] = mesh.convex
    return hulls[k]


def _robot_geometry(robot: Any, convex: bool = False) -> tuple[Any, list[str], str]:
    import coal
    import pinocchio as pin
    cm = robot.collision_model
    if cm is not None and cm.ngeoms > 0:
        gm = pin.GeometryModel()
        hulls = 0
        for k, g in enumerate(cm.geometryObjects):
            go = pin.GeometryObject(g)
            if convex and isinstance(g.geometry, coal.BVHModelBase):
                hull = _hull(robot, k, g.geometry)
                if hull is not None:
                    go.geometry = hull
                    hulls += 1
            gm.addGeometryObject(go)
        reported = _reported(robot)
        names = [_frame_link_name(robot.model, g.parentFrame, reported) if g.parentFrame < len(robot.model.frames)
                 else _link_name(robot.model, g.parentJoint, reported) for g in gm.geometryObjects]
        return gm, names, "convex hulls of the collision meshes" if hulls else "collision meshes"
    gm = _capsule_model(robot)
    reported = _reported(robot)
    return gm, [_link_name(robot.model, g.parentJoint, reported) for g in gm.geometryObjects], "capsules"


def _adjacent(model: Any, a: int, b: int) -> bool:
    return a == b or model.parents[a] == b or model.parents[b] == a


@dataclass(frozen=True)
class SelfCollisionPairs:
    """The self-collision pairs of one robot, computed once (see the module docstring).

    Every link pair appears once, in ``checked``, ``adjacent`` or ``always`` (module docstring).

    Attributes
    ----------
    checked : list of (str, str)
        The (link, link) name pairs that are checked (at least one of their shape pairs).
    adjacent : list of (str, str)
        Link pairs skipped as adjacent (parent and child joint, or fixed to one joint).
    always : list of (str, str)
        Link pairs skipped because every one of their shape pairs was in contact in every sample.
    never : list of (str, str)
        Checked link pairs that never collided in the samples (kept, listed for information).
    partly : list of (str, str, int, int)
        Checked link pairs some of whose shape pairs were in contact in every sample and are
        skipped: ``(link, link, skipped, shape pairs)``.
    index_pairs : list of (int, int)
        The checked shape pairs, as indices of the robot's geometries.
    samples, seed : int
        The sampling used (:data:`SELF_SAMPLES`, :data:`SELF_SEED`).
    geometry : str
        ``"collision meshes"`` or ``"capsules"`` (the geometry the filter was computed on).
    excluded : list of (str, str, str)
        Pairs skipped because the robot's file says they never collide (MJCF contact rules):
        (link, link, reason), one per geometry pair.

    Examples
    --------
    >>> import robokit
    >>> pairs = self_collision_pairs(robokit.load("ur5"))
    >>> ("upper_arm_link", "forearm_link") in pairs.adjacent
    True
    """

    checked: list[tuple[str, str]]
    adjacent: list[tuple[str, str]]
    always: list[tuple[str, str]]
    never: list[tuple[str, str]]
    index_pairs: list[tuple[int, int]]
    samples: int
    seed: int
    geometry: str
    excluded: list[tuple[str, str, str]] = field(default_factory=list)
    partly: list[tuple[str, str, int, int]] = field(default_factory=list)

    def __str__(self) -> str:
        part = {(a, b): (k, n) for a, b, k, n in self.partly}
        lines = [f"self-collision pairs ({self.geometry}; {self.samples} samples, seed {self.seed}), per link pair:",
                 f"  checked ({len(self.checked)} link pairs, {len(self.index_pairs)} shape pairs):"]
        for a, b in self.checked:
            k_n = part.get((a, b))
            extra = (f"  ({k_n[0]} of its {k_n[1]} shape pairs in contact in every sample: those skipped)"
                     if k_n else "")
            lines.append(f"    {a} – {b}{extra}")
        lines.append(f"  skipped, adjacent ({len(self.adjacent)}): " + ", ".join(f"{a}–{b}" for a, b in self.adjacent))
        lines.append(f"  skipped, always in contact ({len(self.always)}; every shape pair in every sample): "
                     + ", ".join(f"{a}–{b}" for a, b in self.always))
        lines.append(f"  checked but never colliding in the samples ({len(self.never)}): "
                     + ", ".join(f"{a}–{b}" for a, b in self.never))
        if self.excluded:
            lines.append(f"  skipped, never tested by the file's contact rules ({len(self.excluded)}):")
            lines += [f"    {a} – {b}: {why}" for a, b, why in self.excluded]
        return "\n".join(lines)


def self_collision_pairs(robot: Any) -> SelfCollisionPairs:
    """The robot's self-collision pairs: adjacent and always-in-contact pairs removed.

    Computed once per robot object (cached), with :data:`SELF_SAMPLES` configurations drawn
    by ``robot.random_configuration`` from ``numpy.random.default_rng(SELF_SEED)``.

    Parameters
    ----------
    robot : robokit.Robot

    Returns
    -------
    SelfCollisionPairs
        ``print()`` it for the table of checked and skipped pairs.

    Examples
    --------
    >>> import robokit
    >>> from robokit.collision import self_collision_pairs
    >>> print(self_collision_pairs(robokit.load("puma560")).geometry)
    capsules
    """
    # computed once per robot and kept with it (Robot.derived: a robot never changes)
    return cast("SelfCollisionPairs", _once(robot, "self_collision_pairs", lambda: _self_collision_pairs(robot)))


def _self_collision_pairs(robot: Any) -> SelfCollisionPairs:
    import pinocchio as pin
    gm, names, kind = _robot_geometry(robot)
    model = robot.model
    objs = list(gm.geometryObjects)
    first: dict[str, int] = {}  # link name → index of its first geometry: the order a link pair is written in
    for k, nm in enumerate(names):
        first.setdefault(nm, k)

    def key(i: int, j: int) -> tuple[str, str]:
        a, b = names[i], names[j]
        return (a, b) if first[a] <= first[b] else (b, a)

    rules = getattr(robot, "contact_rules", None)
    adjacent: dict[tuple[str, str], None] = {}
    cand, excluded = [], []
    for i in range(len(objs)):
        for j in range(i + 1, len(objs)):
            why = rules.why(objs[i].name, objs[j].name) if rules is not None else None
            if why is not None:
                excluded.append((names[i], names[j], f"{objs[i].name} and {objs[j].name}: {why}"))
                continue
            if names[i] == names[j]:
                continue  # two shapes of one link
            if _adjacent(model, objs[i].parentJoint, objs[j].parentJoint):
                adjacent[key(i, j)] = None
            else:
                cand.append((i, j))
    for i, j in cand:
        gm.addCollisionPair(pin.CollisionPair(i, j))
    gd = pin.GeometryData(gm)
    data = model.createData()
    rng = np.random.default_rng(SELF_SEED)
    counts = np.zeros(len(cand), dtype=int)
    for _ in range(SELF_SAMPLES if cand else 0):  # no candidate pair (a two-link arm): nothing to sample
        q = robot.q_pin(robot.random_configuration(rng))
        pin.computeCollisions(model, data, gm, gd, q, False)
        counts += np.array([gd.collisionResults[k].isCollision() for k in range(len(cand))], dtype=int)
    # per link pair: its shape pairs and their contact counts, in the order the pairs first appear
    by_link: dict[tuple[str, str], list[tuple[tuple[int, int], int]]] = {}
    for c, n in zip(cand, counts):
        by_link.setdefault(key(*c), []).append((c, int(n)))
    keep = [c for c, n in zip(cand, counts) if n < SELF_SAMPLES]
    checked, always, never, partly = [], [], [], []
    for lp, shapes in by_link.items():
        skipped = sum(1 for _, n in shapes if n == SELF_SAMPLES)
        if skipped == len(shapes):
            always.append(lp)
            continue
        checked.append(lp)
        if skipped:
            partly.append((lp[0], lp[1], skipped, len(shapes)))
        if all(n == 0 for _, n in shapes):
            never.append(lp)
    res = SelfCollisionPairs(checked=checked, adjacent=list(adjacent), always=always, never=never, index_pairs=keep,
                             samples=SELF_SAMPLES, seed=SELF_SEED, geometry=kind, partly=partly,
                             excluded=excluded)
    return res


@dataclass(frozen=True)
class WorldState:
    """A :class:`World` as plain data, to rebuild it in another process (:meth:`World.from_state`).

    Attributes
    ----------
    spec : robokit.RobotSpec or None
        What ``robokit.load`` rebuilds the robot from (None for a robot built by hand).
    robot : str
        The robot's name.
    obstacles : tuple of Box, Sphere, Cylinder, Mesh
        The obstacles (plain Python objects holding numpy arrays; a Mesh carries its vertices
        and faces, so its file is not read again).
    padding : float
        m.
    convex : bool
        Convex hulls instead of the collision meshes.
    self_pairs : SelfCollisionPairs
        The self-collision filter, computed once on the driver.

    Examples
    --------
    >>> import pickle, robokit
    >>> from robokit.collision import World
    >>> state = World(robokit.load("rrr")).state()
    >>> World.from_state(pickle.loads(pickle.dumps(state))).robot.name
    'rrr'
    """

    spec: Any
    robot: str
    obstacles: tuple
    padding: float
    convex: bool
    self_pairs: SelfCollisionPairs


def _pairs_match(pairs: Any, names: list[str], n_robot: int) -> bool:
    """Whether shipped self-collision pairs index this robot geometry (each checked shape pair on
    two links of a checked link pair, and every checked link pair with a shape pair)."""
    if not isinstance(pairs, SelfCollisionPairs):
        return False
    links = {frozenset(p) for p in pairs.checked}
    if not all(0 <= i < j < n_robot and frozenset((names[i], names[j])) in links for i, j in pairs.index_pairs):
        return False
    return links == {frozenset((names[i], names[j])) for i, j in pairs.index_pairs}


def _rebuild(state: WorldState) -> "World":
    return World.from_state(state)


class World:
    """A robot and its obstacles, with collision and distance queries (coal through Pinocchio).

    Parameters
    ----------
    robot : robokit.Robot
        Its collision meshes are used, or capsules for a model without them (module docstring).
    obstacles : iterable of Box, Sphere, Cylinder, Mesh
        Placed in the robot's base frame (m). Unnamed ones are called ``<type>_<k>``.
    padding : float, >= 0, m
        Security margin inflating the robot's geometry.
    convex : bool
        Replace each of the robot's collision meshes by its convex hull: faster and
        conservative (never "free" where the meshes touch), but concave links look filled.
        No effect on capsule models (module docstring).

    Attributes
    ----------
    robot : robokit.Robot
        The robot.
    obstacles : tuple of Obstacle
        The obstacles, in the order given.
    obstacle_names : list of str
        Their names (given or ``<type>_<k>``).
    padding : float
        m.
    convex : bool
        Whether convex hulls replace the meshes.
    geometry : str
        The robot geometry in use: ``"collision meshes"``, ``"convex hulls of the collision
        meshes"`` or ``"capsules"``.
    self_pairs : SelfCollisionPairs
        The self-collision filter (``print(world.describe())`` shows it).
    obstacle_excluded : list of (str, str)
        Robot geometries not checked against obstacles (MJCF masks that share no bit with
        MuJoCo's default geom): (link, reason).
    geometry_model : pinocchio.GeometryModel
        Robot geometries first, then obstacles (``obstacle:<name>``).

    Examples
    --------
    >>> import numpy as np, robokit
    >>> from robokit.collision import World, Box
    >>> T = np.eye(4); T[:3, 3] = [0.6, 0, 0.3]
    >>> w = World(robokit.load("puma560"), [Box([0.1, 1.0, 1.0], T, name="wall")])
    >>> w.in_collision(np.zeros(6)), w.in_collision([0, 0, -1.5, 0, 0, 0])
    (False, True)
    >>> w.geometry
    'capsules'
    """

    def __init__(self, robot: Any, obstacles: Iterable[Obstacle] = (), padding: float = 0.0,
                 convex: bool = False) -> None:
        self._build(robot, obstacles, padding, convex, None)

    @classmethod
    def from_state(cls, state: WorldState, robot: Any = None) -> "World":
        """Rebuild a world from :meth:`state` (in another process, say), without recomputing
        the self-collision pairs.

        Parameters
        ----------
        state : WorldState
            From :meth:`World.state`.
        robot : robokit.Robot, optional
            The robot to use (default ``robokit.load(state.spec)``); it must be the same robot
            (name and collision geometry).

        Returns
        -------
        World
            Answers as the world ``state`` was taken from.

        Examples
        --------
        >>> import robokit
        >>> w = World(robokit.load("puma560"), padding=0.01)
        >>> World.from_state(w.state()).padding
        0.01
        """
        if not isinstance(state, WorldState):
            raise InputError(f"state: expected a WorldState (World.state()), got {type(state).__name__}")
        if robot is None:
            if state.spec is None:
                raise InputError(f"state: the robot {state.robot!r} has no RobotSpec to rebuild it from; pass robot=")
            from robokit.description.loading import load
            robot = load(state.spec)
        if robot.name != state.robot:
            raise InputError(f"robot: the world was built for {state.robot!r}, not for {robot.name!r}")
        w = cls.__new__(cls)
        w._build(robot, state.obstacles, state.padding, state.convex, state.self_pairs)
        return w

    def state(self) -> WorldState:
        """The world as plain, picklable data (no coal objects): see :class:`WorldState`.

        Returns
        -------
        WorldState

        Examples
        --------
        >>> import robokit
        >>> World(robokit.load("rrr")).state().padding
        0.0
        """
        return WorldState(spec=getattr(self.robot, "spec", None), robot=str(self.robot.name),
                          obstacles=self.obstacles, padding=self.padding, convex=self.convex,
                          self_pairs=self.self_pairs)

    def __reduce__(self) -> tuple[Any, tuple[WorldState]]:
        return (_rebuild, (self.state(),))

    def _build(self, robot: Any, obstacles: Iterable[Obstacle], padding: float, convex: bool,
               self_pairs: SelfCollisionPairs | None) -> None:
        import pinocchio as pin
        if not isinstance(convex, (bool, np.bool_)):
            raise InputError(f"convex: expected True or False, got {convex!r}")
        self.robot = robot
        self.padding = as_scalar(padding, "padding", nonnegative=True, bounded=True)
        self.convex = bool(convex)
        obs = list(obstacles)
        for k, o in enumerate(obs):
            if not isinstance(o, Obstacle):
                raise InputError(f"obstacles: item {k} is a {type(o).__name__}, not a Box, Sphere, Cylinder or Mesh")
        gm, names, self.geometry = _robot_geometry(robot, self.convex)
        self._n_robot = gm.ngeoms
        if self_pairs is None:
            self_pairs = self_collision_pairs(robot)
        elif not _pairs_match(self_pairs, names, self._n_robot):
            raise InputError(f"state: its self-collision pairs do not match {robot.name!r}'s collision geometry "
                             f"({self._n_robot} geometries here)")
        self.self_pairs = self_pairs
        counters: dict[str, int] = {}
        self.obstacle_names: list[str] = []
        for o in obs:
            kind = type(o).__name__.lower()
            nm = o.name or f"{kind}_{counters.get(kind, 0)}"
            counters[kind] = counters.get(kind, 0) + 1
            if nm in self.obstacle_names:
                raise InputError(f"obstacles: two obstacles are named {nm!r}")
            self.obstacle_names.append(nm)
            gm.addGeometryObject(pin.GeometryObject(f"obstacle:{nm}", 0, _se3(o.pose), o.geometry()))
            names.append(nm)
        self.obstacles = tuple(obs)
        self._names = names
        pairs = list(self.self_pairs.index_pairs)
        margins = [2 * self.padding] * len(pairs)
        rules = getattr(robot, "contact_rules", None)
        objs = list(gm.geometryObjects)
        self.obstacle_excluded: list[tuple[str, str]] = []
        for i in range(self._n_robot):
            why = rules.why_not_obstacle(objs[i].name) if rules is not None else None
            if why is not None:
                self.obstacle_excluded.append((names[i], f"{objs[i].name}: {why}"))
                continue
            for j in range(self._n_robot, gm.ngeoms):
                pairs.append((i, j))
                margins.append(self.padding)
        for i, j in pairs:
            gm.addCollisionPair(pin.CollisionPair(i, j))
        self._pairs = pairs
        self._margins = np.array(margins)
        self.geometry_model = gm
        self._gd = pin.GeometryData(gm)
        for k, m in enumerate(margins):
            req = self._gd.collisionRequests[k]
            req.security_margin = m
            # Pinocchio's default requests (enable_contact=False) missed a capsule resting 2 cm
            # deep in a box at some joint angles; with contacts enabled coal finds it.
            req.enable_contact = True
            req.num_max_contacts = 1
        for dreq in self._gd.distanceRequests:
            dreq.gjk_tolerance = GJK_TOLERANCE
        self._data = robot.model.createData()
        self._pin = pin

    # ------------------------------------------------------------------ helpers
    def _qs(self, q: Any) -> tuple[np.ndarray, bool]:
        a = as_array(q, "q")
        n = self.robot.n
        if a.ndim == 1 and a.shape == (n,):
            return a[None], False
        if a.ndim == 2 and a.shape[1] == n:
            return a, True
        raise InputError(f"q: expected shape ({n},) or (N, {n}) for {self.robot.name}, got {a.shape}")

    def _collide(self, q: np.ndarray, stop: bool) -> bool:
        pin = self._pin
        return bool(pin.computeCollisions(self.robot.model, self._data, self.geometry_model, self._gd,
                                          self.robot.q_pin(q), stop))

    def _pairs_state(self, q: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Per checked pair: in contact (bool) and signed distance of the padded geometry (m).

        A pair is in contact when coal's collision test says so (its distance is then ≤ 0).
        """
        pin = self._pin
        if not self._pairs:
            return np.zeros(0, dtype=bool), np.zeros(0)
        qp = self.robot.q_pin(q)
        pin.computeDistances(self.robot.model, self._data, self.geometry_model, self._gd, qp)
        d = np.array([r.min_distance for r in self._gd.distanceResults]) - self._margins
        pin.computeCollisions(self.robot.model, self._data, self.geometry_model, self._gd, qp, False)
        flags = np.array([r.isCollision() for r in self._gd.collisionResults])
        d = np.where(flags, np.minimum(d, 0.0), d)
        return flags, d

    def _hit(self, q: np.ndarray) -> bool:
        return self._collide(q, True)

    # ------------------------------------------------------------------ queries
    def in_collision(self, q: Any) -> Any:
        """Whether the (padded) robot touches itself or an obstacle at ``q``.

        Parameters
        ----------
        q : array_like, shape (n,) or (N, n), joint values (rad / m).

        Returns
        -------
        bool, or ndarray of bool (N,) for a batch.

        Examples
        --------
        >>> import robokit
        >>> from robokit.collision import Box, pose_from_xyz_rpy
        >>> wall = Box([0.1, 1.0, 1.0], pose_from_xyz_rpy([0.6, 0, 0.3], [0, 0, 0]), name="wall")
        >>> w = World(robokit.load("puma560"), [wall])
        >>> w.in_collision([[0, 0, 0, 0, 0, 0], [0, 0, -1.5, 0, 0, 0]])
        array([False,  True])
        """
        qs, batch = self._qs(q)
        out = np.array([self._hit(x) for x in qs], dtype=bool)
        return out if batch else bool(out[0])

    def distance(self, q: Any) -> Any:
        """Minimum distance (m) over the checked pairs of the padded geometry; ≤ 0 in contact.

        A pair in contact reports coal's signed (penetration) distance, at most 0.

        Parameters
        ----------
        q : array_like, shape (n,) or (N, n).

        Returns
        -------
        float, or ndarray (N,); ``inf`` when no pair is checked.

        Examples
        --------
        The world ``w`` of :meth:`in_collision` (the PUMA 560 and a wall 0.6 m ahead of it):

        >>> round(w.distance(np.zeros(6)), 4)
        0.0737
        """
        qs, batch = self._qs(q)
        out = np.array([float(self._pairs_state(x)[1].min()) if self._pairs else np.inf for x in qs])
        return out if batch else float(out[0])

    def colliding_pairs(self, q: Any) -> Any:
        """The (link or obstacle name, link or obstacle name) pairs in contact at ``q``.

        Parameters
        ----------
        q : array_like, shape (n,) or (N, n).

        Returns
        -------
        list of (str, str), or a list of such lists for a batch (one per row).

        Examples
        --------
        The world ``w`` of :meth:`in_collision`:

        >>> w.colliding_pairs([0, 0, -1.5, 0, 0, 0])
        [('link_4', 'wall')]
        """
        qs, batch = self._qs(q)
        out = []
        for x in qs:
            flags, _ = self._pairs_state(x)
            got: list[tuple[str, str]] = []
            seen: set[frozenset[str]] = set()
            for k, (i, j) in enumerate(self._pairs):
                if flags[k]:
                    p = (self._names[i], self._names[j])
                    if frozenset(p) not in seen:  # a link pair once, whichever of its shapes touch
                        seen.add(frozenset(p))
                        got.append(p)
            out.append(got)
        return out if batch else out[0]

    def describe(self) -> str:
        """A printable account of the world: robot geometry, padding, obstacles, the pairs checked
        and the self-collision filter (checked and skipped pairs, with the reason).

        Returns
        -------
        str
            Several lines; ``print()`` it.

        Examples
        --------
        >>> import robokit
        >>> print(World(robokit.load("puma560")).describe().splitlines()[0])
        World for 'puma560': robot geometry capsules, padding 0 m, convex=False
        """
        lines = [f"World for {self.robot.name!r}: robot geometry {self.geometry}, padding {self.padding:g} m, "
                 f"convex={self.convex}"]
        if self.convex and self.geometry == "capsules":
            lines.append("  (convex=True has no effect: the model has no collision meshes, only capsules)")
        if self.convex:
            import coal
            flat = [g.name for g in list(self.geometry_model.geometryObjects)[:self._n_robot]
                    if isinstance(g.geometry, coal.BVHModelBase)]
            if flat:
                lines.append(f"  kept as meshes (flat, no convex hull): {', '.join(flat)}")
        lines.append(f"  robot geometries: {self._n_robot}; obstacles: {len(self.obstacles)}; shape pairs checked: "
                     f"{len(self._pairs)} ({len(self.self_pairs.index_pairs)} self, over "
                     f"{len(self.self_pairs.checked)} link pairs; "
                     f"{len(self._pairs) - len(self.self_pairs.index_pairs)} robot–obstacle)")
        for nm, o in zip(self.obstacle_names, self.obstacles):
            lines.append(f"  obstacle {nm}: {o!r}")
        for link, why in self.obstacle_excluded:
            lines.append(f"  not checked against obstacles: {link} ({why})")
        lines.append(str(self.self_pairs))
        return "\n".join(lines)

    def __repr__(self) -> str:
        return (f"World({self.robot.name!r}, {len(self.obstacles)} obstacles, padding={self.padding}, "
                f"{len(self._pairs)} pairs, robot geometry: {self.geometry})")
