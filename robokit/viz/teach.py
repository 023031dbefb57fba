r"""A teach pendant: move a robot's joints with sliders and watch the course's quantities live.

Two front ends share one set of definitions:

* :func:`teach_html` — one self-contained HTML page (no server, works offline from a file):
  a slider per joint, buttons for the robot's named poses, the robot in meshcat's 3-D view
  (its meshes, or the simple links of a DH model) with its DH/joint frames and the tool
  triad, and readouts computed **in the page** by the robot's own generated C
  (:func:`robokit.codegen.generate_c`, the controller's code) compiled to WebAssembly
  (:mod:`robokit.codegen.wasm`): tool pose, Jacobian, the bodies' placements and the IK come
  from the module, JavaScript (``teach.js``, ``teach_math.js``) turns them into the display.
  ``robokit teach MODEL`` writes it (:func:`robokit.commands.teach_command`).
* :func:`teach_widget` — the same in a Jupyter notebook: ipywidgets sliders driving a live
  meshcat scene, the readouts computed in Python by :func:`teach_readouts`
  (``Scene(robot).teach()``).

The quantities, at joint values q (rad for revolute joints, m for prismatic ones):

* the tool pose ``T(q) = e^{[S_1]q_1} ⋯ e^{[S_n]q_n} M`` (Lecture 4): position, roll–pitch–yaw
  ``(r, p, y)`` with ``R = Rz(y) Ry(p) Rx(r)`` (the URDF convention) and the unit quaternion
  ``(w, x, y, z)`` (scalar first, ``w ≥ 0``);
* the geometric Jacobian ``J`` (6×n, rows ``(ω; v)``, ``v`` the velocity of the tool origin,
  base axes — Pinocchio's LOCAL_WORLD_ALIGNED): column i is ``Ad_{T_{i-1}} S_i`` (the space
  Jacobian, with ``T_{i-1} = e^{[S_1]q_1} ⋯ e^{[S_{i-1}]q_{i-1}}``) with ``v ← v + ω × p_tool``;
* on the task rows ``J_t`` of ``J`` (all six rows when n ≥ 6; for fewer joints, the rows the
  arm can move along, or its translational ones — see :func:`task_rows`): Yoshikawa's
  manipulability ``w = √det(J_t J_tᵀ)``, the condition number ``σ_max / σ_min``, and, when
  ``σ_min / σ_max < SINGULAR_RATIO``, a singularity warning naming the lost direction — the
  left singular vector of the smallest singular value;
* the joint-limit margin ``min_i min(q_i − lo_i, hi_i − q_i)`` over the limited joints.

Each visual of the robot is placed like the frame of its parent joint k:
``T_g(q) = P_k(q) T_g(0)``, ``T_g(0)`` its pose at q = 0 (from Pinocchio) and
``P_k(q) = ᵒMᵢ[k](q) ᵒMᵢ[k](0)⁻¹ = e^{[S_1]q_1} ⋯ e^{[S_k]q_k}``, the joint frame poses
``ᵒMᵢ[k]`` coming from the module's ``NAME_joint_poses``.
"""
from __future__ import annotations

import base64
import html as _html
import json
import math
from importlib import resources
import os
import re
from pathlib import Path
from typing import TYPE_CHECKING, Any, Sequence

import numpy as np
from numpy.typing import ArrayLike
from robokit.errors import InputError

from robokit._optional import available, require

if TYPE_CHECKING:
    from robokit.description.dh import DHTable
    from robokit.description.robot import Robot


__all__ = [
    "NAMED_POSES",
    "SINGULAR_RATIO",
    "task_rows",
    "ready_pose",
    "teach_parameters",
    "teach_data",
    "teach_readouts",
    "teach_html",
    "teach_widget",
]

#: Named poses of the lecture (those of P. Corke's Robotics Toolbox), per robot name, in rad.
#: ``qn`` bends joint 3 to 180°, beyond the PUMA's ±135° limit: the page clamps it.
NAMED_POSES = {
    "puma560": {
        "qz": [0.0, 0.0, 0.0, 0.0, 0.0, 0.0],
        "qr": [0.0, math.pi / 2, -math.pi / 2, 0.0, 0.0, 0.0],
        "qs": [0.0, 0.0, -math.pi / 2, 0.0, 0.0, 0.0],
        "qn": [0.0, math.pi / 4, math.pi, 0.0, math.pi / 4, 0.0],
    },
}

#: The page warns of a singularity when σ_min / σ_max of the task Jacobian falls below this.
SINGULAR_RATIO = 0.02

#: Below this σ_min the configuration is called singular (not only near one).
SINGULAR_TOL = 1e-9

ROW_NAMES = ("rotation about x", "rotation about y", "rotation about z",
             "translation along x", "translation along y", "translation along z")
ROW_SYMBOLS = ("ωx", "ωy", "ωz", "vx", "vy", "vz")

#: A frame label's height, per unit of triad length (the page's triads are short: a tenth of the reach).
LABEL_HEIGHT = 0.6

#: Slider range of joints without limits: ±180° (revolute), ±1 m (prismatic).
_UNLIMITED = {"R": math.pi, "P": 1.0}


# --------------------------------------------------------------------------- robot data
def _joint_types(robot: Robot) -> list[str]:
    """'R' or 'P' per joint, from the screw axes (a prismatic joint has ω = 0)."""
    S = robot.poe.Slist
    return ["P" if np.linalg.norm(S[:3, i]) < 1e-12 else "R" for i in range(robot.n)]


def _slider_ranges(robot: Robot, types: Sequence[str]) -> np.ndarray:
    """(n, 2) slider ranges: the joint limits, or ±180° / ±1 m where a joint has none."""
    rng = np.array(robot.qlim, dtype=float).copy()
    for i, t in enumerate(types):
        if not np.isfinite(rng[i, 0]):
            rng[i, 0] = -_UNLIMITED[t]
        if not np.isfinite(rng[i, 1]):
            rng[i, 1] = _UNLIMITED[t]
    return rng


def task_rows(robot: Robot, samples: int = 24, seed: int = 0) -> list[int]:
    """The rows of the 6×n geometric Jacobian the manipulability measures use.

    n ≥ 6: all six rows. Fewer joints: the rows that are not zero at every one of ``samples``
    random configurations (a planar arm in the xy plane moves along ωz, vx, vy) if there are
    at most n of them; otherwise the translational ones among them (vx, vy, vz for a spatial
    three-joint arm; vx, vy for the planar two-link arm).

    Parameters
    ----------
    robot : robokit.Robot
        The arm (n joints).
    samples : int
        Random configurations (uniform in the slider ranges) the rows are probed at.
    seed : int
        Seed of ``numpy.random.default_rng`` for those configurations.

    Returns
    -------
    list of int
        Row indices into the Jacobian's rows (ω; v), i.e. 0..5.

    Examples
    --------
    >>> import robokit
    >>> task_rows(robokit.load("twolink"))
    [3, 4]
    """
    n = robot.n
    if n >= 6:
        return list(range(6))
    rng = np.random.default_rng(seed)
    lo, hi = _slider_ranges(robot, _joint_types(robot)).T
    J_abs = np.zeros((6, n))
    for _ in range(samples):
        J_abs = np.maximum(J_abs, np.abs(robot.jacobian(rng.uniform(lo, hi), reference="local_world_aligned")))
    active = [r for r in range(6) if J_abs[r].max() > 1e-9]
    if len(active) <= n:
        return active
    return [r for r in active if r >= 3]


def _named_poses(robot: Robot) -> dict:
    poses = {k: np.asarray(v, dtype=float) for k, v in NAMED_POSES.get(robot.name, {}).items()}
    for k, v in robot.configurations.items():
        if k == "zero" and any(np.all(p == 0) for p in poses.values()):
            continue
        poses.setdefault(k, np.asarray(v, dtype=float))
    return {k: v for k, v in poses.items() if v.shape == (robot.n,)}


#: The inverse condition number σ_min/σ_max (task rows) a searched opening pose reaches: three times
#: the page's near-singularity threshold, so the pendant opens clear of any warning.
READY_RATIO = 3 * SINGULAR_RATIO


def _conditioning(robot: Robot, q: np.ndarray, rows: list[int]) -> tuple[float, float]:
    """(σ_min/σ_max, Σ log(σᵢ/σ_max + 1e-6)) of the task Jacobian at q: the page's measure, and a
    smooth one that also rises when one of several lost directions comes back."""
    J = robot.jacobian(q, reference="local_world_aligned")[rows]
    s = np.linalg.svd(J, compute_uv=False)
    if s[0] <= 0:
        return 0.0, -np.inf
    r = np.zeros(J.shape[0])
    r[: len(s)] = s / s[0]
    return float(r[-1]), float(np.log(r + 1e-6).sum())


def ready_pose(robot: Robot) -> tuple[str, np.ndarray]:
    """The configuration the teach pages open at: a named pose of the model that is clear of any
    singularity, else a well-conditioned pose found near the model's ready pose, deterministically.

    The named poses (:data:`NAMED_POSES`, then the robot's ``configurations``; ``"ready"`` first) are
    tried in order: the first inside the joint limits whose task Jacobian has
    ``σ_min/σ_max ≥`` :data:`SINGULAR_RATIO` (the page shows no singularity warning there) is the
    answer. Otherwise a coordinate search starts from the model's ready pose (``"ready"``, else the
    first non-zero named pose, else zero; kept in the middle 80 % of each slider range, clear of
    the limits): one joint at a time, the
    step of 0.4 rad (then 0.2, 0.1; for a prismatic joint the same fraction of a turn of its slider
    range) that raises ``Σ log(σᵢ/σ_max + 10⁻⁶)`` most is taken — a measure that grows as any lost
    direction comes back, where ``σ_min/σ_max`` alone stays 0 at a double singularity — until
    ``σ_min/σ_max`` reaches :data:`READY_RATIO`: a pose near the ready pose, the same on every run.

    Parameters
    ----------
    robot : robokit.Robot
        The arm.

    Returns
    -------
    name : str
        The named pose's name, or ``"start"`` for a searched pose.
    q : numpy.ndarray, shape (n,)
        Joint values (rad / m).

    Examples
    --------
    The UR5 at zero and the PUMA's "qr" are singular; the Panda's ready pose is not:

    >>> import robokit
    >>> ready_pose(robokit.load("panda"))[0]
    'ready'
    >>> name, q = ready_pose(robokit.load("ur5"))
    >>> name, teach_readouts(robokit.load("ur5"), q)["level"]
    ('start', 'ok')
    """
    rows = task_rows(robot)
    types = _joint_types(robot)
    rng = _slider_ranges(robot, types)
    poses = _named_poses(robot)
    order = (["ready"] if "ready" in poses else []) + [k for k in poses if k != "ready"]
    lo, hi = robot.qlim[:, 0], robot.qlim[:, 1]
    for name in order:
        q = poses[name]
        if np.all(q >= lo) and np.all(q <= hi) and _conditioning(robot, q, rows)[0] >= SINGULAR_RATIO:
            return name, q.copy()
    start = next((poses[k] for k in order if np.any(poses[k] != 0)), np.zeros(robot.n))
    span = rng[:, 1] - rng[:, 0]
    rng = np.column_stack([rng[:, 0] + 0.1 * span, rng[:, 1] - 0.1 * span])  # clear of the limits
    q = np.clip(start, rng[:, 0], rng[:, 1])
    ratio, score = _conditioning(robot, q, rows)
    unit = np.array([1.0 if t == "R" else float(sp) / (2 * math.pi) for t, sp in zip(types, span)])
    for step in (0.4, 0.2, 0.1):
        while ratio < READY_RATIO:
            best = (ratio, score, q)
            for j in range(robot.n):
                for sign in (1.0, -1.0):
                    cand = q.copy()
                    cand[j] = min(max(cand[j] + sign * step * unit[j], rng[j, 0]), rng[j, 1])
                    r, sc = _conditioning(robot, cand, rows)
                    if sc > best[1] + 1e-9:
                        best = (r, sc, cand)
            if best[2] is q:
                break  # no step of this size helps: a smaller one
            ratio, score, q = best
        if ratio >= READY_RATIO:
            break
    return "start", q


def _frame_names(robot: Robot) -> list[str]:
    if robot.dh is not None:
        return [f"dh_{i}" for i in range(robot.dh.n + 1)] + ["tool"]
    names = [jn for jn in robot.joint_names if robot.model.existFrame(jn)]
    return names + [robot.tip]


class _RecordingWindow:
    """Stands in for meshcat's ViewerWindow: keeps the commands instead of sending them."""

    def __init__(self) -> None:
        self.commands: list[Any] = []

    def send(self, command: Any) -> None:
        self.commands.append(command.lower())


def _scene(robot: Robot, frame_names: Sequence[str], triad_scale: float, floor_half: float,  # floor_half: 1.1·reach
           mesh_cell: float, obstacles: Sequence[Any] = ()) -> tuple[list[Any], dict[str, str], dict[str, str]]:
    """meshcat commands that build the robot's scene, and its visuals' meshcat paths.

    The robot is loaded by Pinocchio's MeshcatVisualizer (meshes or primitives, with the
    URDF's colours) into a recording window; the frames are triads (labelled for DH models).
    """
    import contextlib
    import io
    import warnings

    meshcat = require("meshcat", "the teach pendant")
    g = require("meshcat.geometry", "the teach pendant")
    require("meshcat.path", "the teach pendant")
    import pinocchio as pin
    from pinocchio.visualize import MeshcatVisualizer

    from robokit.viz._meshes import decimated_visuals, draw_parts
    from robokit.viz._labels import label_sprite

    window = _RecordingWindow()
    vis = meshcat.Visualizer(window=window)
    visual = robot.visual_model if robot.visual_model is not None else pin.GeometryModel()
    viz = MeshcatVisualizer(robot.model, pin.GeometryModel(), visual)
    with warnings.catch_warnings(), contextlib.redirect_stdout(io.StringIO()):
        warnings.simplefilter("ignore")
        viz.initViewer(viewer=vis)
        viz.loadViewerModel(rootNodeName="robot")
    # a floor grid of our own under the robot, sized to its reach, in the base frame's z = 0
    # plane (meshcat's default 20 m grid is hidden)
    from robokit.viz._shapes import ground_grid_segments

    seg, _, _ = ground_grid_segments(floor_half / 1.1)
    vis["/Grid"].set_property("visible", False)
    vis["floor"].set_object(g.LineSegments(g.PointsGeometry(seg),
                                           g.LineBasicMaterial(color=0x8090A8, transparent=True, opacity=0.6)))
    paths = {go.name: vis[viz.getViewerNodeName(go, pin.GeometryType.VISUAL)].path.lower()
             for go in visual.geometryObjects}
    # mesh files: replaced by decimated triangle lists (far smaller than the files' text, and
    # placed exactly as Pinocchio reads them), one coloured part per material
    meshed = {paths[go.name]: parts for go, parts in decimated_visuals(visual, mesh_cell)}
    window.commands = [c for c in window.commands
                       if not (c.get("type") == "set_object" and c.get("path") in meshed)]
    for path, parts in meshed.items():
        draw_parts(meshcat.Visualizer.view_into(window, meshcat.path.Path(tuple(path.strip("/").split("/")))), parts)
    frame_paths = {}
    for name in frame_names:
        node = vis["frames"][name]
        big = name in ("tool", robot.tip)
        node["triad"].set_object(g.triad(triad_scale * (1.4 if big else 1.0)))
        if robot.dh is not None:  # camera-facing sprites, drawn over the geometry, placed by the page
            vis["labels"][name].set_object(label_sprite(name, LABEL_HEIGHT * triad_scale))
        frame_paths[name] = node.path.lower()
    from robokit.viz._shapes import obstacle_geometry

    for k, o in enumerate(obstacles):
        geom, T = obstacle_geometry(o, k)
        vis["obstacles"][str(k)].set_object(geom, g.MeshLambertMaterial(color=0xC08040, opacity=0.6, transparent=True))
        vis["obstacles"][str(k)].set_transform(T)
    return window.commands, paths, frame_paths


def _pack(command: Any) -> str:
    import umsgpack

    return base64.b64encode(umsgpack.packb(command)).decode("ascii")


_UUID = re.compile(r"[0-9a-f]{8}-[0-9a-f]{4}-[0-9a-f]{4}-[0-9a-f]{4}-[0-9a-f]{12}", re.I)


def _short_uuids(commands: Sequence[Any]) -> list[Any]:
    """The commands with every UUID string (three.js names each geometry, material, texture and image
    of an object by one, 36 characters, and links them by it) replaced by a short id unique in the
    page (``u0``, ``u1``, …): the same links, a few kilobytes fewer."""
    ids: dict[str, str] = {}

    def walk(x: Any) -> Any:
        if isinstance(x, str) and _UUID.fullmatch(x):
            return ids.setdefault(x.lower(), f"u{len(ids)}")
        if isinstance(x, dict):
            return {k: walk(v) for k, v in x.items()}
        if isinstance(x, (list, tuple)):
            return [walk(v) for v in x]
        return x

    return [walk(c) for c in commands]


def _scene_entry(command: Any) -> str:
    """One meshcat command as the page's ``RK_SCENE`` holds it (JavaScript text): base64 msgpack (a
    string; binary mesh data stays binary), or the command itself as JSON when it holds no binary data
    and that is shorter — a frame label's PNG is already base64 text inside its data URL, which a
    second base64 would grow by a third."""
    packed = f'"{_pack(command)}"'
    try:
        plain = _script_json(command)
    except (TypeError, ValueError):  # bytes, arrays: msgpack only
        return packed
    return plain if len(plain) < len(packed) else packed


#: Direction the teach page looks from (azimuth, elevation in degrees, base frame): a 3/4 view.
CAMERA_AZIMUTH, CAMERA_ELEVATION = 40.0, 22.0


def _camera(points: np.ndarray, pad: float) -> dict:
    """The teach page's camera data for the reach points ``points`` (K, 3) (base frame, m).

    ``points``: the vertices of the points' convex hull (a perspective view of the hull is
    the hull of the projected vertices, so they are all the framing needs); ``pad``: how far
    (m) the links' geometry reaches beyond those frame origins; ``lo``/``hi``: the padded
    bounding box; ``direction``: unit vector from the target towards the camera (the 3/4 view
    of :data:`CAMERA_AZIMUTH`, :data:`CAMERA_ELEVATION`). The page fits target and distance to
    its canvas (``RKMath.fitCamera``); ``target``/``position`` frame the padded bounding sphere
    in a 75° cone, used until the page has measured its canvas.
    """
    from scipy.spatial import ConvexHull, QhullError

    try:
        hull = points[ConvexHull(points).vertices]
    except (QhullError, ValueError):  # flat (a planar arm) or too few points: keep them all
        hull = points
    lo, hi = points.min(axis=0) - pad, points.max(axis=0) + pad
    az, el = math.radians(CAMERA_AZIMUTH), math.radians(CAMERA_ELEVATION)
    d = np.array([math.cos(el) * math.cos(az), math.cos(el) * math.sin(az), math.sin(el)])
    centre = 0.5 * (lo + hi)
    radius = 0.5 * float(np.linalg.norm(hi - lo))
    dist = radius / math.sin(0.5 * math.radians(75.0))  # the bounding sphere inside the view cone
    return {"points": np.round(hull, 6).tolist(), "pad": pad, "lo": lo.tolist(), "hi": hi.tolist(),
            "direction": d.tolist(), "target": centre.tolist(), "position": (centre + dist * d).tolist()}


def teach_parameters(robot: Robot) -> dict:
    """The robot's data the teach pendant's readouts need (``teach_math.js``'s ``readouts``).

    Parameters
    ----------
    robot : :class:`robokit.Robot`
        The arm (n joints).

    Returns
    -------
    dict
        Plain JSON-able values: ``n``; ``rows`` (task rows of the Jacobian, :func:`task_rows`); ``joints`` (per joint:
        ``name``, ``type`` 'R'/'P', slider range ``lo``/``hi`` in rad/m — the joint limits, or
        ±180° / ±1 m without limits — and ``limited``); ``singular_ratio`` and
        ``singular_tol`` (:data:`SINGULAR_RATIO`, :data:`SINGULAR_TOL`).

    Examples
    --------
    >>> import robokit
    >>> teach_parameters(robokit.load("twolink"))["rows"]
    [3, 4]
    """
    types = _joint_types(robot)
    rng = _slider_ranges(robot, types)
    return {
        "n": robot.n,
        "rows": task_rows(robot),
        "joints": [{"name": robot.joint_names[i], "type": types[i], "lo": float(rng[i, 0]), "hi": float(rng[i, 1]),
                    "limited": bool(np.isfinite(robot.qlim[i]).all())} for i in range(robot.n)],
        "singular_ratio": SINGULAR_RATIO,
        "singular_tol": SINGULAR_TOL,
    }


def teach_data(robot: Robot, q: ArrayLike | None = None, mesh_cell: float = 0.002, world: Any = None) -> dict:
    """Everything the teach page needs about ``robot``, as plain JSON-able values.

    Parameters
    ----------
    robot : robokit.Robot
        The arm (n joints).
    q : array_like, shape (n,), optional
        Initial joint values (rad / m; default the opening pose of :func:`ready_pose`).
    mesh_cell : float
        Cube side (m) of the mesh decimation (see :mod:`robokit.viz._meshes`).
    world : robokit.collision.World, optional
        The robot among obstacles: the obstacles are drawn and the page shows the collision
        state (:func:`robokit.viz.clearance.clearance_page_data`).

    Returns
    -------
    dict
        ``name``, ``n``, ``tip``; ``joints`` (per joint: ``name``, ``type`` 'R'/'P',
        ``lo``/``hi`` slider range in rad/m, ``limited``); ``rows`` (task rows of the Jacobian,
        :func:`task_rows`); ``poses`` (named poses, rad/m); ``q0`` (initial joint values);
        ``visuals`` and ``frames`` (per object: meshcat ``path``, parent joint count ``k`` and
        home pose ``T`` (4×4, at q = 0, mesh scale included)); ``camera`` (the reach box
        ``lo``/``hi`` and view ``direction`` the page fits its camera to, and a first
        ``target``/``position``, base frame, m); ``scale`` (triad length, m); ``collision``
        (None without a world, else the page data of the clearance module plus the
        obstacles' meshcat ``obstacle_paths``).

    Examples
    --------
    >>> import robokit
    >>> d = teach_data(robokit.load("twolink"))
    >>> d["n"], d["rows"], d["collision"]
    (2, [3, 4], None)
    """
    import pinocchio as pin

    types = _joint_types(robot)
    rng = _slider_ranges(robot, types)
    zero = np.zeros(robot.n)
    poses = _named_poses(robot)
    if q is None:
        name0, q0 = ready_pose(robot)
        if name0 not in poses:
            poses = {name0: q0, **poses}  # a button to come back to it
    else:
        q0 = np.asarray(q, dtype=float)
        if q0.shape != (robot.n,):
            raise InputError(f"q: {robot.name} has {robot.n} joints, got {q0.size} values")
        if not np.isfinite(q0).all():
            raise InputError("q: contains NaN or infinite values")
        robot.check_radians(q0, "q")
    frame_names = _frame_names(robot)

    # points that frame the camera: the frames' origins at q0, at the named poses and at
    # random configurations, so that the robot stays in view wherever the sliders take it
    rand = np.random.default_rng(0).uniform(rng[:, 0], rng[:, 1], size=(64, robot.n))
    pts = [robot.frame_poses(np.clip(p, rng[:, 0], rng[:, 1])) for p in [q0, *poses.values(), *rand]]
    P = np.array([T[:3, 3] for d in pts for T in d.values()])
    P = P[P[:, 2] >= P[: len(pts[0]), 2].min() - 1e-9]  # what goes below the base's level is left out
    size = float(max(np.ptp(P, axis=0).max(), 0.2))
    scale = 0.1 * size
    obstacles = tuple(world.obstacles) if world is not None else ()
    commands, paths, frame_paths = _scene(robot, frame_names, scale, 1.1 * float(np.hypot(P[:, 0], P[:, 1]).max()),
                                          mesh_cell, obstacles)
    collision = None
    if world is not None:
        from robokit.viz.clearance import clearance_page_data

        collision = clearance_page_data(world)
        collision["obstacle_paths"] = [f"/meshcat/obstacles/{k}" for k in range(len(obstacles))]

    data = robot.model.createData()
    pin.forwardKinematics(robot.model, data, pin.neutral(robot.model))
    visuals = []
    if robot.visual_model is not None:
        gdata = robot.visual_model.createData()
        pin.updateGeometryPlacements(robot.model, data, robot.visual_model, gdata)
        for gid, go in enumerate(robot.visual_model.geometryObjects):
            T = gdata.oMg[gid].homogeneous @ np.diag(np.r_[np.asarray(go.meshScale, float).ravel(), 1.0])
            visuals.append({"path": paths[go.name], "k": int(go.parentJoint), "T": T.tolist()})
    poses0 = robot.frame_poses(zero)
    frames = []
    for name in frame_names:
        fid = robot.frame_id(name)
        frames.append({"name": name, "path": frame_paths[name], "k": int(robot.model.frames[fid].parentJoint),
                       "T": poses0[name].tolist()})
    # labels: the page puts each above its frame's origin, stacked where origins coincide
    # (robokit.viz._labels.label_offsets, redone in the page at every configuration)
    labels = [{"path": f"/meshcat/labels/{nm}", "frame": i, "height": LABEL_HEIGHT * scale}
              for i, nm in enumerate(frame_names)] if robot.dh is not None else []
    params = teach_parameters(robot)
    rows = params["rows"]
    return {
        **params,
        "name": robot.name,
        "tip": robot.tip,
        "row_names": [ROW_NAMES[r] for r in rows],
        "row_symbols": list(ROW_SYMBOLS),
        "poses": {k: v.tolist() for k, v in poses.items()},
        "q0": q0.tolist(),
        "visuals": visuals,
        "frames": frames,
        "labels": labels,
        "camera": _camera(P, max(0.05, 0.06 * size)),
        "scale": scale,
        "collision": collision,
        "_commands": commands,
    }


# --------------------------------------------------------------------------- readouts (Python)
def teach_readouts(robot: Robot, q: ArrayLike) -> dict:
    """The teach pendant's quantities at joint values ``q``, computed with Pinocchio.

    Parameters
    ----------
    robot : robokit.Robot
        The arm (n joints).
    q : array_like, shape (n,)
        Joint values (rad / m).

    Returns
    -------
    dict
        ``T`` (4×4 tool pose in the base frame), ``xyz`` (m), ``rpy`` (rad,
        ``R = Rz(y) Ry(p) Rx(r)``), ``quat`` (``(w, x, y, z)``, w ≥ 0), ``J`` (6×n geometric
        Jacobian, rows ``(ω; v)``, base axes), ``rows`` (the task rows), ``w`` (√det(J_t J_tᵀ)),
        ``cond`` (σ_max/σ_min, ∞ when singular: σ_min < ``SINGULAR_TOL``), ``sigma_min``,
        ``level`` ("ok", "near" or "singular"), ``direction`` (the lost direction, task-row
        components, dominant one positive), ``direction_name``, ``margins`` (n,: distance to
        the nearer limit, ∞ for unlimited joints), ``margin`` (their minimum) and
        ``margin_joint`` (its joint's name).

    Examples
    --------
    >>> import numpy as np, robokit
    >>> teach_readouts(robokit.load("ur5"), np.zeros(6))["level"]
    'singular'
    """
    import pinocchio as pin

    from robokit.kinematics.velocity import manipulability

    q = np.asarray(q, dtype=float)
    if q.shape != (robot.n,):
        raise InputError(f"q: expected {robot.n} joint values for {robot.name}, got shape {q.shape}")
    T = robot.frame_pose(q)
    J = robot.jacobian(q, reference="local_world_aligned")
    rows = task_rows(robot)
    Jt = J[rows]
    U, s, _ = np.linalg.svd(Jt)
    m = Jt.shape[0]
    sig = np.zeros(m)
    sig[: len(s)] = s
    smax, smin = float(sig[0]), float(sig[-1])
    ratio = smin / smax if smax > 0 else 0.0
    level = "singular" if smin < SINGULAR_TOL else ("near" if ratio < SINGULAR_RATIO else "ok")
    d = U[:, -1].copy()
    k = int(np.argmax(np.abs(d)))
    if d[k] < 0:
        d = -d
    quat = pin.Quaternion(T[:3, :3]).normalized()
    wxyz = np.array([quat.w, quat.x, quat.y, quat.z])
    if wxyz[0] < 0:
        wxyz = -wxyz
    lo, hi = robot.qlim[:, 0], robot.qlim[:, 1]
    margins = np.minimum(q - lo, hi - q)
    margins[~np.isfinite(margins)] = np.inf
    j = int(np.argmin(margins))
    return {
        "T": T, "xyz": T[:3, 3].copy(), "rpy": np.asarray(pin.rpy.matrixToRpy(T[:3, :3])), "quat": wxyz,
        "J": J, "rows": rows, "w": manipulability(Jt, "yoshikawa"),
        "cond": smax / smin if smin >= SINGULAR_TOL and Jt.shape[1] >= m else math.inf,
        "sigma_min": smin, "level": level, "direction": d,
        "direction_name": f"{ROW_NAMES[rows[k]]} ({d[k]:.2f})",
        "margins": margins, "margin": float(margins[j]), "margin_joint": robot.joint_names[j],
    }


# --------------------------------------------------------------------------- the page
def _asset(name: str) -> str:
    return resources.files("robokit.viz").joinpath(name).read_text(encoding="utf-8")


def _script(name: str) -> str:
    """One of robokit's own scripts as the page inlines it, minified by ``rjsmin`` (comments and
    layout removed; strings, regular expressions and the meaning of line breaks kept); the files in
    ``robokit/viz`` are the readable source."""
    rjsmin = require("rjsmin", "the teach pendant")
    return str(rjsmin.jsmin(_asset(name)))


def _meshcat_bundle() -> str:
    meshcat = require("meshcat", "the teach pendant")

    return (Path(meshcat.__file__).parent / "viewer" / "dist" / "main.min.js").read_text(encoding="utf-8")


#: Characters of a JSON text that could end or confuse the HTML element it is embedded in
#: (``</script>``, ``<!--``, ``]]>``, ``&`` entities) or a JavaScript string (U+2028/9):
#: written as JSON ``\\uXXXX`` escapes, which JSON.parse reads back unchanged.
_SCRIPT_ESCAPES = {"<": "\\u003c", ">": "\\u003e", "&": "\\u0026", "\u2028": "\\u2028", "\u2029": "\\u2029"}


def _script_json(obj: Any) -> str:
    """JSON safe to put inside a ``<script>`` element: no ``<``, ``>``, ``&``, U+2028 or U+2029
    (escaped inside strings, where alone they can occur; JSON's structure never holds them)."""
    text = json.dumps(obj, separators=(",", ":"), allow_nan=False)
    for ch, esc in _SCRIPT_ESCAPES.items():
        text = text.replace(ch, esc)
    return text


def teach_html(model: Robot | DHTable | str | os.PathLike[str], q: ArrayLike | None = None,
               obstacles: Sequence[Any] | None = None, padding: float = 0.0, wasm: bytes | None = None) -> str:
    """The teach page of ``model``: one self-contained HTML page that works offline from a file.

    Meshcat's three.js bundle, the robot's meshes and the page's script are embedded; nothing
    is fetched. Sliders, named-pose buttons, the 3-D view and the live readouts described in
    the module docstring; a URL fragment ``#q=q1,q2,…`` (rad/m) overrides ``q`` when the page
    opens, values outside the slider range being clamped (wrapped for unlimited revolute
    joints).

    Parameters
    ----------
    model : robokit.Robot, DHTable, str or path
        Anything ``robokit.load`` accepts.
    q : array_like, shape (n,), optional
        Initial joint values (rad / m; default the opening pose of :func:`ready_pose`, clear of any singularity).
    obstacles : sequence of robokit.collision shapes, optional
        Obstacles (base frame) to draw. With them (an empty list included) the page shows
        the collision state of a :class:`robokit.collision.World` of the robot: links in
        contact turn red and a readout gives the minimum distance (m) and the nearest or
        colliding pair — computed in the page for capsule models (DH robots) among boxes,
        spheres and cylinders (:mod:`robokit.viz.clearance`); for a robot with collision
        meshes, or a mesh obstacle, the readout says that this needs the notebook teach
        pendant (Python).
    padding : float
        The World's padding (m, inflation of the robot's geometry).
    wasm : bytes
        The robot's generated C compiled to WebAssembly
        (:func:`robokit.codegen.wasm.wasm_module`'s ``.wasm``; ``robokit teach`` compiles it), embedded
        as base64. Required (the default None is refused): the page has no other implementation of
        the kinematics. The page's tool pose, Jacobian and placements come from the module (the
        controller's own C), and the fragment ``#T=t11,t12,…,t44`` (16 numbers, row-major,
        the tool pose in the base frame; ``#q=…&T=…``: start at q, then go to T) solves the
        closed-form IK in the module and moves to the solution nearest the current joint
        values; the element ``rk-ik`` gets ``data-count``, ``data-solutions`` (every solution,
        in ``ik_analytic``'s order), ``data-labels``, ``data-within`` and ``data-chosen`` (the
        index shown, -1 when out of reach).

    Returns
    -------
    str
        The HTML page.

    Raises
    ------
    robokit.errors.InputError
        Without ``wasm``.

    Examples
    --------
    >>> from robokit.codegen.wasm import wasm_module
    >>> page = teach_html("twolink", wasm=wasm_module(rk.load("twolink")).wasm)
    >>> page.startswith("<!DOCTYPE html>")
    True
    """
    from robokit.description.loading import load

    robot = load(model)
    if wasm is None:
        raise InputError("wasm: the teach page computes with the robot's generated C compiled to WebAssembly; pass "
                         "wasm=robokit.codegen.wasm.wasm_module(robot).wasm (robokit teach does)")
    world = None
    if obstacles is not None:
        from robokit.collision import World

        world = World(robot, obstacles, padding=padding)
    d = teach_data(robot, q, world=world)
    commands = d.pop("_commands")
    scene = "[" + ",".join(_scene_entry(c) for c in _short_uuids(commands)) + "]"
    title = _html.escape(f"robokit teach — {robot.name}")
    module = (  # base64 holds no character that could end the element
        f"<script id=\"rk-wasm\" type=\"application/octet-stream\">{base64.b64encode(bytes(wasm)).decode('ascii')}"
        f"</script>\n<script>\n{_script('teach_wasm.js')}\n</script>\n")
    return (
        "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n"
        f"<title>{title}</title>\n<style>\n{_asset('teach.css')}\n</style>\n</head>\n<body>\n"
        f"{_asset('teach_body.html')}\n"
        f"<script>\n{_meshcat_bundle()}\n</script>\n"
        f"<script id=\"rk-robot\" type=\"application/json\">{_script_json(d)}</script>\n"
        f"<script>var RK_SCENE = {scene};</script>\n"
        f"<script>\n{_script('teach_math.js')}\n</script>\n"
        f"{module}"
        f"<script>\n{_script('teach.js')}\n</script>\n"
        "</body>\n</html>\n"
    )


# --------------------------------------------------------------------------- notebook
def _readouts_html(robot: Robot, r: dict) -> str:
    """The readouts of :func:`teach_readouts` as a small HTML block (for the notebook widget)."""
    deg = np.degrees
    rows = r["rows"]
    head = "".join(f"<th>q{i + 1}</th>" for i in range(robot.n))
    body = "".join(
        f"<tr><th>{ROW_SYMBOLS[i]}</th>" + "".join(f"<td>{v:+.4f}</td>" for v in r["J"][i]) + "</tr>" for i in range(6))
    if r["level"] == "ok":
        sing = "<span style='color:#2a7'>no singularity nearby</span>"
    else:
        word = "Singular" if r["level"] == "singular" else "Near a singularity"
        sing = (f"<b style='color:#c30'>{word}:</b> lost direction {r['direction_name']}, "
                f"u = [{', '.join(f'{v:+.3f}' for v in r['direction'])}] on rows "
                f"({', '.join(ROW_SYMBOLS[i] for i in rows)})")
    j = robot.joint_names.index(r["margin_joint"])
    types = _joint_types(robot)
    marg = r["margin"]
    marg_txt = "∞ (no limits)" if not np.isfinite(marg) else (
        f"{deg(marg):.2f}°" if types[j] == "R" else f"{marg * 1000:.1f} mm")
    cond = "∞" if not np.isfinite(r["cond"]) else f"{r['cond']:.4g}"
    return (
        "<div style='font:12px monospace'>"
        f"<b>tool</b> p = [{', '.join(f'{v:+.4f}' for v in r['xyz'])}] m, "
        f"rpy = [{', '.join(f'{v:+.2f}' for v in deg(r['rpy']))}]°, "
        f"quat (w,x,y,z) = [{', '.join(f'{v:+.4f}' for v in r['quat'])}]<br>"
        f"<table style='border-collapse:collapse'><tr><th></th>{head}</tr>{body}</table>"
        f"w = √det(J<sub>t</sub>J<sub>t</sub>ᵀ) = {r['w']:.5g}, cond = {cond}, σ<sub>min</sub> = {r['sigma_min']:.3g}<br>"
        f"{sing}<br>joint-limit margin: {marg_txt} ({r['margin_joint']})</div>"
    )


def _collision_html(c: dict) -> str:
    """The collision readout of :func:`robokit.viz.clearance.clearance` as a small HTML block."""
    def pair(p: Sequence[str]) -> str:
        return _html.escape(f"{p[0]} – {p[1]}")

    if c["pairs"]:
        return (f"<div style='font:12px monospace;color:#a42a1b'><b>In contact:</b> "
                f"{', '.join(pair(p) for p in c['pairs'])} (distance {c['distance']:.4f} m)</div>")
    if c["closest"] is None:
        return "<div style='font:12px monospace'>collision: no pair to check</div>"
    return (f"<div style='font:12px monospace;color:#1e7b3c'>minimum distance {c['distance']:.4f} m "
            f"({pair(c['closest'])})</div>")


#: The notebook pendant's drag view (an anywidget front end): the teach page, with the robot's
#: module, in a frame; the q it posts ({rk: "teach-q"}) goes to the widget's ``q`` and from there
#: to Python, and a ``q`` set in Python is posted into the page ({rk: "teach-set-q"}). The page's
#: first message is its opening q (the q it was written at, possibly older than the model's: a
#: ``set_q`` before the view was shown, a view shown again): it is answered with the model's q and
#: never sent to Python; until then a q from Python waits in the model (a message would be lost on
#: a page still loading).
_DRAG_ESM = """
export default {
  render({ model, el }) {
    const frame = document.createElement("iframe");
    frame.style.cssText = "width:100%;border:0;height:" + model.get("height") + "px";
    frame.srcdoc = model.get("page");
    let last = null;  // the q the page and the model agree on; null until the page has opened
    const toPage = () => {
      last = JSON.stringify(model.get("q"));
      frame.contentWindow.postMessage({ rk: "teach-set-q", q: model.get("q") }, "*");
    };
    const fromPage = (ev) => {
      if (ev.source !== frame.contentWindow || !ev.data || ev.data.rk !== "teach-q") { return; }
      const text = JSON.stringify(ev.data.q);
      if (last === null) {  // the page's opening q: the model's wins
        if (text === JSON.stringify(model.get("q"))) { last = text; } else { toPage(); }
        return;
      }
      if (text === last) { return; }
      last = text;
      model.set("q", ev.data.q);
      model.save_changes();
    };
    const fromPython = () => {
      if (last === null || JSON.stringify(model.get("q")) === last || !frame.contentWindow) { return; }
      toPage();
    };
    window.addEventListener("message", fromPage);
    model.on("change:q", fromPython);
    el.appendChild(frame);
    return () => { window.removeEventListener("message", fromPage); model.off("change:q", fromPython); };
  }
};
"""
_DRAG_VIEW: Any = None


def _drag_view(page: str, q: list[float], height: int) -> Any:
    """The drag view widget (anywidget) showing ``page`` at joint values ``q``."""
    global _DRAG_VIEW
    if _DRAG_VIEW is None:
        anywidget = require("anywidget", "dragging the tool in the notebook pendant")
        import traitlets

        class DragView(anywidget.AnyWidget):  # type: ignore[name-defined]
            _esm = _DRAG_ESM
            page = traitlets.Unicode("").tag(sync=True)
            q = traitlets.List(traitlets.Float()).tag(sync=True)
            height = traitlets.Int(560).tag(sync=True)

        _DRAG_VIEW = DragView
    return _DRAG_VIEW(page=page, q=q, height=height)


def teach_widget(scene: Any, q: ArrayLike | None = None, height: int = 420, world: Any = None,
                 wasm: bytes | None = None) -> Any:
    """A notebook teach pendant on a :class:`robokit.viz.Scene`.

    ipywidgets sliders (degrees for revolute joints, metres for prismatic ones), named-pose
    buttons, the scene's live meshcat view (an iframe of its server) and the readouts of
    :func:`teach_readouts`. Moving a slider redraws the robot and its frames in the scene and
    recomputes the readouts. With a ``world``, its obstacles are drawn and, on every change,
    Python computes the collision state with the World (:func:`robokit.viz.clearance.clearance`):
    the visuals of links in contact turn red and the readout shows the minimum distance (m)
    and the nearest (or colliding) pair.

    Dragging the tool needs the robot's module (``wasm``) and anywidget (the ``notebooks``
    extra): the pendant then shows the teach page of :func:`teach_html` above the readouts, its
    gizmo, ghost arms and IK running in the browser on the module, and every q the page reaches
    moves the sliders, the live scene and the Python readouts (and ``set_q`` moves the page).
    Without them the pendant says once, above the readouts, what to pass or install: the live
    view above is drawn by the Python meshcat server, which sends no pointer events back.

    Parameters
    ----------
    scene : robokit.viz.Scene
        The scene (and its robot) to drive.
    q : array_like, shape (n,), optional
        Initial joint values (rad / m; default the opening pose of :func:`ready_pose`; clamped to the slider range).
    height : int
        Height of the 3-D view (px).
    world : robokit.collision.World, optional
        The scene's robot among obstacles (its ``robot`` must be the scene's).
    wasm : bytes, optional
        The robot's generated C compiled to WebAssembly
        (``robokit.codegen.wasm.wasm_module(scene.robot).wasm``): with it, and anywidget
        installed, the pendant gets the teach page's drag.

    Returns
    -------
    ipywidgets.VBox
        With ``.set_q(q)`` (all joints at once, rad/m), ``.readouts`` (the latest
        :func:`teach_readouts` dict), ``.collision`` (the latest ``clearance`` dict, or
        None without a world), ``.painted`` (names of the visuals drawn red), ``.drag`` (the
        drag view, an anywidget with the page's ``q``, or None) and ``.drag_note`` (the
        sentence shown when there is no drag view, else "").

    Examples
    --------
    >>> from robokit.viz import Scene
    >>> pendant = Scene("puma560").teach()   # doctest: +SKIP
    >>> pendant.set_q([0, 0.5, -0.5, 0, 0, 0])   # doctest: +SKIP
    """
    W = require("ipywidgets", "the notebook teach pendant")

    robot = scene.robot
    types = _joint_types(robot)
    rng = _slider_ranges(robot, types)
    unit = np.array([180.0 / math.pi if t == "R" else 1.0 for t in types])
    q_open = ready_pose(robot)[1] if q is None else np.asarray(q, dtype=float)
    if q_open.shape != (robot.n,):
        raise InputError(f"q: expected {robot.n} joint values for {robot.name}, got shape {q_open.shape}")
    q_start = np.clip(q_open, rng[:, 0], rng[:, 1])
    if world is not None and world.robot is not robot:
        raise InputError("world: its robot is not the scene's robot (build the World from scene.robot)")
    names = _frame_names(robot)
    scene.show(q_start).frames(names, labels=robot.dh is not None)
    if world is not None and world.obstacles:
        scene.obstacles(world.obstacles)
    sliders = [
        W.FloatSlider(value=float(q_start[i] * unit[i]), min=float(rng[i, 0] * unit[i]), max=float(rng[i, 1] * unit[i]),
                      step=0.1 if types[i] == "R" else 0.001, description=f"q{i + 1} {robot.joint_names[i]}",
                      readout_format=".1f" if types[i] == "R" else ".3f", continuous_update=True,
                      style={"description_width": "initial"},  # the whole joint name, never cut
                      layout=W.Layout(width="460px"))
        for i in range(robot.n)
    ]
    out = W.HTML()
    view = W.HTML(f'<iframe src="{_html.escape(scene.vis.url())}" '
                  f'style="width:100%;height:{int(height)}px;border:0"></iframe>')
    box = W.VBox()
    state = {"busy": False}

    box.collision = None
    box.painted = []
    visuals = list(robot.visual_model.geometryObjects) if robot.visual_model is not None else []
    painted: set[int] = set()  # indices of the visuals drawn red

    def paint(c: dict) -> None:
        import pinocchio as pin

        hit = {i for i, go in enumerate(visuals) if int(go.parentJoint) in c["joints"]}
        for i in sorted(hit - painted):
            scene.vis[scene.viz.getViewerNodeName(visuals[i], pin.GeometryType.VISUAL)].set_property(
                "color", [0.878, 0.188, 0.165, 1.0])
        for i in sorted(painted - hit):  # back to the model's own colours and materials
            scene.viz.loadViewerGeometryObject(visuals[i], pin.GeometryType.VISUAL)
        painted.clear()
        painted.update(hit)
        box.painted = sorted(visuals[i].name for i in hit)

    # the drag view: the teach page with the module, in the browser (see the docstring)
    drag = None
    box.drag_note = ""
    if wasm is None:
        box.drag_note = ("Dragging the tool: the view above is drawn by Python's meshcat server, which sends no "
                         "pointer events back; the drag runs in the teach page, on the robot's C compiled to "
                         "WebAssembly. Pass wasm=robokit.codegen.wasm.wasm_module(scene.robot).wasm to "
                         "scene.teach() to have it here, or write the page with robokit teach MODEL.")
    elif not available("anywidget"):
        box.drag_note = ("Dragging the tool needs anywidget to run the teach page here: "
                         "pip install 'robokit[notebooks]'. Or write the page with robokit teach MODEL.")
    else:
        page = teach_html(robot, q_start, obstacles=None if world is None else list(world.obstacles),
                          padding=0.0 if world is None else float(world.padding), wasm=wasm)
        drag = _drag_view(page, [float(v) for v in q_start], int(height) + 240)
    box.drag = drag

    def redraw(qv: np.ndarray) -> None:
        if drag is not None:  # the page follows the pendant (not an event back to it)
            busy, state["busy"] = state["busy"], True
            try:
                drag.q = [float(v) for v in qv]
            finally:
                state["busy"] = busy
        if world is not None:
            from robokit.viz.clearance import clearance

            box.collision = clearance(world, qv)
            paint(box.collision)
        scene.show(qv)
        scene.move_frames(qv)
        box.readouts = teach_readouts(robot, qv)
        out.value = _readouts_html(robot, box.readouts) + (_collision_html(box.collision) if world is not None else "")

    def on_change(_change: Any) -> None:
        if not state["busy"]:
            redraw(np.array([s.value for s in sliders]) / unit)

    def set_q(qv: ArrayLike) -> None:
        qc = np.clip(np.asarray(qv, dtype=float), rng[:, 0], rng[:, 1])
        state["busy"] = True
        try:
            for s, v, u in zip(sliders, qc, unit):
                s.value = float(v * u)
        finally:
            state["busy"] = False
        redraw(qc)

    def on_drag(change: Any) -> None:  # a q from the page (a drag, a ghost clicked, its sliders)
        qv = np.asarray(change["new"], dtype=float)
        if not state["busy"] and qv.shape == (robot.n,) and np.isfinite(qv).all():
            set_q(qv)

    if drag is not None:
        drag.observe(on_drag, names="q")
    for s in sliders:
        s.observe(on_change, names="value")
    buttons = []
    for name, pose in _named_poses(robot).items():
        b = W.Button(description=name, layout=W.Layout(width="auto"))
        b.on_click(lambda _b, p=pose: set_q(p))
        buttons.append(b)
    extra = [drag] if drag is not None else [W.HTML(f"<div style='font:12px sans-serif;color:#667'>"
                                                     f"{_html.escape(box.drag_note)}</div>")]
    box.children = [W.HBox(buttons), W.HBox([W.VBox(sliders), view]), *extra, out]  # the readouts stay last
    box.set_q = set_q
    redraw(q_start)
    return box
