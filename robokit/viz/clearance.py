r"""Collision display for the teach pendant: which links touch, and how far the nearest pair is.

Two consumers share the definitions of :class:`robokit.collision.World` (its geometry, its
checked pairs, its ``padding``):

* the notebook teach widget (:func:`robokit.viz.teach.teach_widget` with ``world=``) calls
  :func:`clearance` on every slider change: coal, through Pinocchio, on the World's own
  geometry model;
* the offline teach page (no Python behind it) gets :func:`clearance_page_data`: for a robot
  modelled by **capsules** (the DH models: one capsule per link, see
  :mod:`robokit.collision.world`) and primitive obstacles (box, sphere, cylinder), the
  capsules' home poses, radii and half-lengths, the obstacles and the checked pairs, from
  which ``teach_math.js`` (``RKMath.clearance``) computes the same distances in the page.
  A robot with collision meshes, or a mesh obstacle, gets ``supported: false`` and the page
  says that the collision display needs the notebook (Python).

Distances (m) are those of the padded geometry, as :meth:`World.distance` reports them: a
robot–obstacle pair's distance minus ``padding``, a self pair's minus ``2·padding``.

The page's distances, for a capsule of segment ``[a, b]`` and radius ``r`` (``p(t) = a + t(b − a)``):

* capsule–capsule: ``min_{s,t} |p₁(s) − p₂(t)| − r₁ − r₂`` (the inner minimum over t is the
  point–segment distance in closed form; the outer one, a convex function of s, by ternary search);
* capsule–sphere, –box, –cylinder: ``min_t sdf(p(t)) − r`` with the shape's exact signed
  distance function (convex, so ternary search finds its minimum on the segment).

Both are exact (to ~1e-12) when the shapes are apart; in contact the page's negative value is
the deepest point of the capsule's core inside the other shape minus its radius, an estimate
of coal's penetration depth (the page shows "in contact" and which pairs).
"""
from __future__ import annotations

import re
from typing import Any

import numpy as np
from numpy.typing import ArrayLike

from robokit.errors import InputError

__all__ = ["clearance", "clearance_page_data"]

_CAPSULE_SUFFIX = re.compile(r"_capsule\d+\Z")


def _geometry(world: Any) -> tuple[Any, int, list[str]]:
    """The World's geometry model, how many of its objects are the robot's, and each object's name
    (link name for the robot's, obstacle name for the rest)."""
    gm = world.geometry_model
    n_obs = len(world.obstacles)
    n_robot = gm.ngeoms - n_obs
    model = world.robot.model
    names = []
    for i, go in enumerate(gm.geometryObjects):
        if i >= n_robot:
            names.append(world.obstacle_names[i - n_robot])
        elif _CAPSULE_SUFFIX.search(go.name):
            names.append(_CAPSULE_SUFFIX.sub("", go.name))
        elif go.parentFrame < len(model.frames):
            names.append(str(model.frames[go.parentFrame].name))
        else:
            names.append(str(model.names[go.parentJoint]))
    return gm, n_robot, names


def _pairs(world: Any) -> tuple[list[tuple[int, int]], np.ndarray]:
    gm, n_robot, _ = _geometry(world)
    pairs = [(int(cp.first), int(cp.second)) for cp in gm.collisionPairs]
    margins = np.array([2 * world.padding if max(i, j) < n_robot else world.padding for i, j in pairs])
    return pairs, margins


def clearance(world: Any, q: ArrayLike) -> dict:
    """The collision state of ``world``'s robot at ``q``: what the teach pendant shows.

    Parameters
    ----------
    world : robokit.collision.World
        The robot with its obstacles (and padding).
    q : array_like, shape (n,)
        Joint values (rad / m).

    Returns
    -------
    dict
        ``distance`` (float, m: :meth:`World.distance` at q, ≤ 0 in contact; ``inf`` when no
        pair is checked), ``closest`` ((name, name) of the pair at that distance, or None),
        ``in_collision`` (bool), ``pairs`` (list of (name, name) in contact:
        :meth:`World.colliding_pairs`), ``links`` (sorted names of the robot's links in
        contact) and ``joints`` (sorted Pinocchio joint indices of those links' geometries).

    Examples
    --------
    >>> import numpy as np, robokit
    >>> from robokit.collision import World, Sphere
    >>> T = np.eye(4); T[:3, 3] = [2.0, 0, 0]
    >>> w = World(robokit.load("puma560"), [Sphere(0.1, T, name="ball")])
    >>> c = clearance(w, np.zeros(6))
    >>> c["in_collision"], c["distance"] > 0, c["pairs"]
    (False, True, [])
    """
    import pinocchio as pin

    qv = np.asarray(q, dtype=float)
    robot = world.robot
    if qv.shape != (robot.n,):
        raise InputError(f"q: expected {robot.n} joint values for {robot.name}, got shape {qv.shape}")
    if not np.isfinite(qv).all():
        raise InputError("q: contains NaN or infinite values")
    gm, n_robot, names = _geometry(world)
    pairs, margins = _pairs(world)
    distance = float(world.distance(qv))
    colliding = world.colliding_pairs(qv)
    closest = None
    if pairs:
        gd = pin.GeometryData(gm)
        data = robot.model.createData()
        pin.computeDistances(robot.model, data, gm, gd, robot.q_pin(qv))
        d = np.array([r.min_distance for r in gd.distanceResults]) - margins
        k = int(np.argmin(d))
        closest = (names[pairs[k][0]], names[pairs[k][1]])
        if colliding and closest not in colliding:
            closest = colliding[0]
    robot_names = {names[i] for i in range(n_robot)}
    links = sorted({nm for p in colliding for nm in p if nm in robot_names})
    joints = sorted({int(gm.geometryObjects[i].parentJoint) for i in range(n_robot) if names[i] in links})
    return {"distance": distance, "closest": closest, "in_collision": bool(colliding), "pairs": colliding,
            "links": links, "joints": joints}


def clearance_page_data(world: Any) -> dict:
    """What the offline teach page needs to compute ``world``'s distances itself (``RKMath.clearance``).

    Parameters
    ----------
    world : robokit.collision.World
        The robot with its obstacles (and padding).

    Returns
    -------
    dict
        Plain JSON-able values. Always ``supported`` (bool), ``reason`` (why not, else ""),
        ``padding`` (m) and ``obstacles_drawn`` (the obstacles' names). When supported:
        ``geoms`` — the robot's capsules, each ``{"name": link, "k": parent joint count,
        "T": 4×4 home pose (base frame, q = 0; the capsule's axis is its z), "radius",
        "half": half-length (0 for a sphere)}``, then the obstacles, each ``{"name",
        "type": "box" | "sphere" | "cylinder", "T": 4×4 pose, "half": box half-sizes (3,)
        or cylinder half-length, "radius"}``; ``pairs`` (checked pairs as index pairs into
        ``geoms``) and ``margins`` (m, subtracted from each pair's distance).

    Examples
    --------
    >>> import robokit
    >>> from robokit.collision import World
    >>> clearance_page_data(World(robokit.load("puma560")))["supported"]
    True
    """
    import coal
    import pinocchio as pin

    robot = world.robot
    gm, n_robot, names = _geometry(world)
    out: dict = {"supported": False, "reason": "", "padding": float(world.padding),
                 "obstacles_drawn": list(world.obstacle_names)}
    model = robot.model
    if model.nq != robot.n or model.njoints != robot.n + 1:
        out["reason"] = "the collision display of this page needs the notebook (Python): the robot is not a plain chain"
        return out
    data = model.createData()
    pin.forwardKinematics(model, data, pin.neutral(model))
    geoms = []
    for i, go in enumerate(gm.geometryObjects[:n_robot]):
        g = go.geometry
        T = (data.oMi[go.parentJoint] * go.placement).homogeneous
        if isinstance(g, coal.Capsule):
            geoms.append({"name": names[i], "k": int(go.parentJoint), "T": T.tolist(), "radius": float(g.radius),
                          "half": float(g.halfLength)})
        elif isinstance(g, coal.Sphere):
            geoms.append({"name": names[i], "k": int(go.parentJoint), "T": T.tolist(), "radius": float(g.radius),
                          "half": 0.0})
        else:
            out["reason"] = ("the collision display of this page covers capsule models (DH robots); this robot has "
                             "collision meshes: use the notebook teach pendant (Python computes it)")
            return out
    for o, nm in zip(world.obstacles, world.obstacle_names):
        kind = type(o).__name__
        T = np.asarray(o.pose, dtype=float).tolist()
        if kind == "Box":
            geoms.append({"name": nm, "type": "box", "T": T, "half": (0.5 * np.asarray(o.size, float)).tolist(),
                          "radius": 0.0})
        elif kind == "Sphere":
            geoms.append({"name": nm, "type": "sphere", "T": T, "radius": float(o.radius), "half": 0.0})
        elif kind == "Cylinder":
            geoms.append({"name": nm, "type": "cylinder", "T": T, "radius": float(o.radius),
                          "half": 0.5 * float(o.length)})
        else:
            out["reason"] = (f"obstacle {nm!r} is a mesh: the collision display of this page covers boxes, spheres "
                             "and cylinders; use the notebook teach pendant (Python computes it)")
            return out
    pairs, margins = _pairs(world)
    out.update(supported=True, geoms=geoms, pairs=[list(p) for p in pairs], margins=margins.tolist())
    return out
