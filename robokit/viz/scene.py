r"""meshcat scenes of robots, on top of Pinocchio's meshcat visualizer.

A :class:`Scene` draws one :class:`robokit.Robot` with Pinocchio's ``MeshcatVisualizer``
(URDF meshes and primitives are loaded by Pinocchio, not re-implemented here) and adds the
course's pictures: the DH frames ``dh_0..dh_N`` and the tool as labelled triads, points,
frames, polylines, the tool's velocity ellipsoid, and animations of joint trajectories.
The camera is aimed at the robot's bounding box so that it fills the view.

Headless use: ``Scene(robot).show(q).html()`` returns one self-contained page (meshcat's
static HTML with the meshes embedded), which opens from a file with no server; in a
notebook, ``scene.notebook()`` shows the same page inline. A meshcat server is started on
loopback for the scene (meshcat records the scene there) and stopped by ``close()``.
"""
from __future__ import annotations

import io
import os
import subprocess
from pathlib import Path
from typing import TYPE_CHECKING, Any, Iterable

import numpy as np
from numpy.typing import ArrayLike
from robokit.errors import InputError

from robokit._optional import require
from robokit.viz._labels import label_offsets, label_sprite

#: A frame label's height, per unit of triad length.
LABEL_HEIGHT = 0.45

if TYPE_CHECKING:
    from robokit.description.dh import DHTable
    from robokit.description.robot import Robot

__all__ = ["Scene", "camera_offset", "MESHCAT_FOV"]


def start_server() -> tuple[subprocess.Popen, str, str]:
    """Start a meshcat server on 127.0.0.1 that dies with this process.

    Returns ``(process, zmq_url, web_url)``. See :mod:`robokit.viz._server`.
    """
    import atexit
    import re
    import subprocess
    import sys

    proc = subprocess.Popen(
        [sys.executable, "-u", "-m", "robokit.viz._server", str(os.getpid())],
        stdout=subprocess.PIPE, stderr=subprocess.DEVNULL, stdin=subprocess.DEVNULL,
        start_new_session=True,  # a notebook's interrupt must not stop the viewer
    )
    atexit.register(stop_server, proc)
    assert proc.stdout is not None  # stdout=PIPE
    urls: dict[str, str] = {}
    while len(urls) < 2:
        line = proc.stdout.readline().decode("utf-8", "replace").strip()
        if not line and proc.poll() is not None:
            raise RuntimeError(f"the meshcat server exited at start (status {proc.returncode})")
        m = re.match(r"(zmq_url|web_url)=(\S+)", line)
        if m:
            urls[m.group(1)] = m.group(2)
    proc.stdout.close()
    return proc, urls["zmq_url"], urls["web_url"]


def new_visualizer(zmq_url: str | None = None) -> Any:
    """A meshcat Visualizer: connected to ``zmq_url``, or to a new loopback server of its own
    (:func:`start_server`; then ``vis.window.server_proc`` is that process)."""
    import contextlib

    meshcat = require("meshcat", "the viewer")

    proc = None
    if zmq_url is None:
        proc, zmq_url, _ = start_server()
    try:
        with contextlib.redirect_stdout(io.StringIO()):  # meshcat prints a banner
            vis = meshcat.Visualizer(zmq_url=zmq_url)
    except BaseException:
        stop_server(proc)
        raise
    vis.window.server_proc = proc
    return vis


def stop_server(proc: subprocess.Popen | None) -> None:
    """Terminate a meshcat server process and wait for it to exit (kill if it does not)."""
    if proc is not None and proc.poll() is None:
        proc.terminate()
        try:
            proc.wait(timeout=5)
        except Exception:  # pragma: no cover
            proc.kill()
            proc.wait(timeout=5)
    elif proc is not None:
        proc.wait()


#: meshcat's default camera: vertical field of view, degrees.
MESHCAT_FOV = 75.0


def camera_offset(points: ArrayLike, fill: float = 0.75, azimuth: float = 45.0,
                  elevation: float = 25.0) -> tuple[np.ndarray, np.ndarray]:
    """Where a meshcat camera looking at ``points`` frames them: the target and the camera's offset.

    The target c is the centre of the points' bounding box; the camera looks at it from the
    direction ``d`` (``azimuth`` about z from x, ``elevation`` above the xy plane) with z up, at
    the smallest distance D at which every point's perspective projection lies within ``fill``
    of the half-height of meshcat's 75° view — and of its half-width, taken as equal (a window
    at least as wide as tall): ``D = max_p (|p·r| or |p·u|)/(fill·tan 37.5°) − p·f`` over the
    points p (relative to c), f = −d the viewing direction, r and u the camera's right and up axes.

    Parameters
    ----------
    points : array_like, shape (K, 3)
        What must be in view (base frame, m).
    fill : float
        Fraction of the half-view the farthest point reaches, in (0, 1].
    azimuth, elevation : float
        View direction, degrees (elevation clamped to ±85°: the camera keeps z up).

    Returns
    -------
    centre : numpy.ndarray, shape (3,)
        The target (m).
    offset : numpy.ndarray, shape (3,)
        Camera position minus target (m), ``D·d``.

    Examples
    --------
    >>> c, off = camera_offset([[0, 0, 0], [1, 0, 0]], elevation=90)
    >>> c.tolist(), bool(off[2] > 0)
    ([0.5, 0.0, 0.0], True)
    """
    P = np.asarray(points, dtype=float).reshape(-1, 3)
    lo, hi = P.min(axis=0), P.max(axis=0)
    centre = 0.5 * (lo + hi)
    el = np.deg2rad(float(np.clip(elevation, -85.0, 85.0)))
    az = np.deg2rad(float(azimuth))
    d = np.array([np.cos(el) * np.cos(az), np.cos(el) * np.sin(az), np.sin(el)])
    f = -d
    r = np.cross(f, [0.0, 0.0, 1.0])
    r /= np.linalg.norm(r)
    u = np.cross(r, f)
    X = P - centre
    k = float(fill) * np.tan(0.5 * np.deg2rad(MESHCAT_FOV))
    need = np.maximum(np.abs(X @ r), np.abs(X @ u)) / k - X @ f
    dist = max(float(need.max()), 0.2)
    return centre, dist * d


class Scene:
    """A meshcat scene of one robot.

    The drawing methods return the scene itself, so calls chain; their ``color`` arguments are
    0xRRGGBB integers.

    Parameters
    ----------
    robot : robokit.Robot, DHTable, str or path
        The robot (or anything ``robokit.load`` accepts).
    vis : meshcat.Visualizer, optional
        An existing visualizer to draw into (default: a new one with its own server on
        loopback, stopped by :meth:`close`).

    Attributes
    ----------
    robot : robokit.Robot
        The robot drawn.
    vis : meshcat.Visualizer
        The visualizer (``vis.url()`` is the live page).
    viz : pinocchio.visualize.MeshcatVisualizer
        Pinocchio's visualizer that loaded the robot's geometry.
    q : numpy.ndarray, shape (n,)
        The configuration shown (rad / m).
    grid : dict or None
        The ground grid drawn by :meth:`ground_grid` (``half``, ``spacing``, ``z``; m).

    Examples
    --------
    A scene starts a meshcat server on loopback (``close()`` or a ``with`` block stops it); the
    methods' examples below continue with this one:

    >>> s = Scene("twolink")
    >>> s.robot.name, s.q.tolist()
    ('twolink', [0.0, 0.0])
    """

    _views = 0  # pages written by notebook(), for unique file names

    def __init__(self, robot: Robot | DHTable | str | os.PathLike[str], vis: Any = None) -> None:
        from pinocchio.visualize import MeshcatVisualizer

        from robokit.description.loading import load

        from robokit.description.robot import Robot

        self.robot = robot if isinstance(robot, Robot) else load(robot)
        self._own = vis is None
        self.vis = new_visualizer() if vis is None else vis
        r = self.robot
        visual = r.visual_model
        collision = r.collision_model
        if visual is None:
            import pinocchio as pin

            visual = pin.GeometryModel()
        self.viz = MeshcatVisualizer(r.model, collision if collision is not None else visual.copy(), visual)
        self.viz.initViewer(viewer=self.vis)
        self.viz.loadViewerModel(rootNodeName="robot")
        self.q = np.zeros(r.n)
        self._extra_points: list[np.ndarray] = []
        self.grid: dict | None = None
        self._frames: tuple[list[str], float] = ([], 0.0)
        self._label_points: list[np.ndarray] = []
        self._animated = False  # animate() was called: pages get a visible play/pause control

    # ------------------------------------------------------------------ drawing
    def show(self, q: ArrayLike | None = None) -> Scene:
        """Draw the robot at joint values ``q``.

        Parameters
        ----------
        q : array_like, shape (n,), optional
            Joint values (rad / m; default zero).

        Returns
        -------
        Scene
            self (the calls chain).

        Examples
        --------
        >>> s.show([0.3, -0.6]).q.tolist()
        [0.3, -0.6]
        """
        q = np.zeros(self.robot.n) if q is None else np.asarray(q, dtype=float)
        if q.shape != (self.robot.n,):
            raise InputError(f"q: expected {self.robot.n} joint values for {self.robot.name}, got shape {q.shape}")
        if not np.all(np.isfinite(q)):
            raise InputError("q: contains NaN or infinite values")
        self.q = q
        self.viz.display(self.robot.q_pin(q))
        return self

    def frames(self, names: Iterable[str] | None = None, scale: float | None = None, labels: bool = True) -> Scene:
        """Draw triads (x red, y green, z blue) for frames of the robot at the current configuration.

        Parameters
        ----------
        names : iterable of str, optional
            Frame names (default: ``dh_0..dh_N`` and ``tool`` for DH robots, else the joint frames
            and the tip).
        scale : float, optional
            Triad length (m; default from the robot's size).
        labels : bool, optional
            Draw each frame's name above it (default True).

        Returns
        -------
        Scene
            self (the calls chain).

        Examples
        --------
        >>> s.frames(["dh_0", "tool"], scale=0.2) is s
        True
        """
        g = require("meshcat.geometry", "the viewer")

        r = self.robot
        if names is None:
            if r.dh is not None:
                names = [f"dh_{i}" for i in range(r.dh.n + 1)] + ["tool"]
            else:
                names = [r.model.frames[r.frame_id(n)].name for n in r.joint_names
                         if r.model.existFrame(n)] + [r.tip]
        poses = r.frame_poses(self.q)
        scale = scale or 0.12 * self._size()
        names = list(names)
        for name in names:
            if name not in poses:
                raise InputError(f"frames: no frame {name!r} in {r.name}")
        for name in names:
            node = self.vis["frames"][name]
            node["triad"].set_object(g.triad(scale))
            if labels:
                self.vis["labels"][name].set_object(label_sprite(name, LABEL_HEIGHT * scale))
        self._frames = (names, LABEL_HEIGHT * scale if labels else 0.0)
        return self.move_frames(self.q)

    def move_frames(self, q: ArrayLike) -> Scene:
        """Move the triads (and labels) drawn by :meth:`frames` to joint values ``q``.

        Labels stay upright above their frame's origin (stacked where origins coincide, see
        :func:`robokit.viz._labels.label_offsets`); they are camera-facing sprites.

        Parameters
        ----------
        q : array_like, shape (n,)
            Joint values (rad / m).

        Returns
        -------
        Scene
            self; the robot's drawing and ``q`` stay as they are (:meth:`show` moves those, not
            the triads).

        Examples
        --------
        >>> s.move_frames([0.3, -0.6]) is s
        True
        """
        tops = self._place_frames(self.vis, q)
        if tops is not None:
            self._label_points = tops
        return self

    def _place_frames(self, vis: Any, q: ArrayLike) -> list[np.ndarray] | None:
        """Set the transforms of the triads and labels of :meth:`frames` at ``q`` on ``vis`` (the
        scene's visualizer, or a frame of an animation); the labels' tops (for the camera), None
        without labels."""
        names, height = self._frames
        if not names:
            return None
        poses = self.robot.frame_poses(np.asarray(q, dtype=float))
        for name in names:
            vis["frames"][name].set_transform(poses[name])
        if not height > 0:
            return None
        origins = np.array([poses[nm][:3, 3] for nm in names])
        offsets = label_offsets(origins, height)
        for name, p, off in zip(names, origins, offsets):
            T = np.eye(4)
            T[:3, 3] = p + off
            vis["labels"][name].set_transform(T)
        return list(origins + offsets + [0.0, 0.0, 0.6 * height])

    def point(self, name: str, p: ArrayLike, radius: float = 0.015, color: int = 0xE04020) -> Scene:
        """A sphere at position ``p`` in the base frame.

        Parameters
        ----------
        name : str
            Its node name (``points/<name>``; the same name replaces it).
        p : array_like, shape (3,)
            Centre (m, base frame).
        radius : float, optional
            Radius (m).
        color : int, optional
            The sphere's colour (see :class:`Scene`).

        Returns
        -------
        Scene
            self (the calls chain).

        Examples
        --------
        >>> s.point("target", [1.0, 0.5, 0.0]) is s
        True
        """
        g = require("meshcat.geometry", "the viewer")

        p = np.asarray(p, dtype=float).reshape(3)
        self.vis["points"][name].set_object(g.Sphere(radius), g.MeshLambertMaterial(color=color))
        T = np.eye(4)
        T[:3, 3] = p
        self.vis["points"][name].set_transform(T)
        self._extra_points.append(p)
        return self

    def frame(self, name: str, T: ArrayLike, scale: float = 0.1) -> Scene:
        """A triad at the pose ``T`` in the base frame.

        Parameters
        ----------
        name : str
            Its node name (``poses/<name>``).
        T : array_like, shape (4, 4)
            The pose (m, base frame).
        scale : float, optional
            Triad length (m).

        Returns
        -------
        Scene
            self (the calls chain).

        Examples
        --------
        >>> s.frame("goal", np.eye(4), scale=0.2) is s
        True
        """
        g = require("meshcat.geometry", "the viewer")

        self.vis["poses"][name].set_object(g.triad(scale))
        self.vis["poses"][name].set_transform(np.asarray(T, dtype=float))
        return self

    def path(self, name: str, points: ArrayLike, color: int = 0x2060E0, linewidth: float = 3.0) -> Scene:
        """A polyline through ``points`` in the base frame.

        Parameters
        ----------
        name : str
            Its node name (``paths/<name>``).
        points : array_like, shape (K, 3)
            The vertices (m, base frame), K ≥ 2.
        color : int, optional
            The line's colour (see :class:`Scene`).
        linewidth : float, optional
            Line width (px, where the browser honours it).

        Returns
        -------
        Scene
            self (the calls chain).

        Examples
        --------
        >>> s.path("reach", [[1.8, 0, 0], [1.0, 0.8, 0], [0.2, 0.0, 0.0]]) is s
        True
        """
        g = require("meshcat.geometry", "the viewer")

        P = np.asarray(points, dtype=float)
        if P.ndim != 2 or P.shape[1] != 3 or len(P) < 2:
            raise InputError(f"points: expected shape (K, 3) with K >= 2, got {P.shape}")
        self.vis["paths"][name].set_object(
            g.Line(g.PointsGeometry(P.T.astype(np.float32)), g.LineBasicMaterial(color=color, linewidth=linewidth)))
        self._extra_points.extend(P)
        return self

    def velocity_ellipsoid(self, frame: str | None = None, scale: float = 0.2, color: int = 0x30B060) -> Scene:
        """The translational velocity ellipsoid ``{v = J_v q̇ : ‖q̇‖ ≤ 1}`` at the frame (default tip).

        Axes and radii from :func:`robokit.kinematics.velocity_ellipsoid_at` (the singular values
        and left singular vectors of J_v), radii times ``scale`` (m per m/s) so it fits the picture.

        Parameters
        ----------
        frame : str, optional
            The frame (default the tip).
        scale : float, optional
            m drawn per m/s of tool speed.
        color : int, optional
            The ellipsoid's colour (see :class:`Scene`).

        Returns
        -------
        Scene
            self (the calls chain).

        Examples
        --------
        >>> s.velocity_ellipsoid(scale=0.1) is s
        True
        """
        g = require("meshcat.geometry", "the viewer")

        from robokit.kinematics.velocity import velocity_ellipsoid_at

        radii, evecs = velocity_ellipsoid_at(self.robot, self.q, "translation", frame)
        radii = np.maximum(radii * scale, 1e-4)
        evecs = evecs.copy()
        if np.linalg.det(evecs) < 0:
            evecs[:, 0] = -evecs[:, 0]
        T = np.eye(4)
        T[:3, :3] = evecs
        T[:3, 3] = self.robot.frame_pose(self.q, frame)[:3, 3]
        self.vis["ellipsoid"].set_object(g.Ellipsoid(radii), g.MeshLambertMaterial(color=color, opacity=0.5,
                                                                                   transparent=True))
        self.vis["ellipsoid"].set_transform(T)
        return self

    def obstacles(self, obstacles: Iterable[Any], color: int = 0xC08040, opacity: float = 0.6) -> Scene:
        """Draw collision obstacles (:mod:`robokit.collision` Box, Sphere, Cylinder, Mesh) at their poses.

        Nodes are ``obstacles/<index>`` (an obstacle's name never becomes a scene path);
        :meth:`frame_camera` then frames the obstacles too.

        Parameters
        ----------
        obstacles : iterable of Box, Sphere, Cylinder, Mesh
            Shapes with their ``pose`` (4×4, base frame, m).
        color : int
            The shapes' colour (see :class:`Scene`).
        opacity : float
            In [0, 1]; below 1 the obstacles are see-through.

        Returns
        -------
        Scene
            self.

        Examples
        --------
        >>> scene.obstacles([Box([0.1, 1, 1])])  # doctest: +SKIP
        """
        g = require("meshcat.geometry", "the viewer")
        from robokit.viz._shapes import obstacle_geometry

        mat = g.MeshLambertMaterial(color=color, opacity=opacity, transparent=opacity < 1)
        for k, o in enumerate(obstacles):
            geom, T = obstacle_geometry(o, k)
            self.vis["obstacles"][str(k)].set_object(geom, mat)
            self.vis["obstacles"][str(k)].set_transform(T)
            # the obstacle's bounding sphere, for frame_camera
            kind = type(o).__name__
            if kind == "Mesh":
                V = np.asarray(o.vertices, dtype=float) @ T[:3, :3].T + T[:3, 3]
                c, rad = V.mean(axis=0), float(np.linalg.norm(V - V.mean(axis=0), axis=1).max())
            else:
                c = T[:3, 3]
                rad = (0.5 * float(np.linalg.norm(o.size)) if kind == "Box" else float(o.radius) if kind == "Sphere"
                       else float(np.hypot(o.radius, 0.5 * o.length)))
            self._extra_points.extend(c + rad * e for e in np.vstack([np.eye(3), -np.eye(3)]))
        return self

    def include(self, points: ArrayLike) -> Scene:
        """Make :meth:`frame_camera` frame these points too, drawing nothing.

        For content drawn straight into ``vis`` (a point cloud, say) that the camera should see.

        Parameters
        ----------
        points : array_like, shape (K, 3)
            Positions (m, base frame).

        Returns
        -------
        Scene
            self (the calls chain).

        Examples
        --------
        >>> s.include([[2.0, 2.0, 0.0], [-2.0, -2.0, 0.5]]) is s
        True
        """
        P = np.asarray(points, dtype=float)
        if P.ndim != 2 or P.shape[1] != 3 or not np.all(np.isfinite(P)):
            raise InputError(f"points: expected finite positions of shape (K, 3), got shape {P.shape}")
        self._extra_points.extend(P)
        return self

    def animate(self, Q: ArrayLike, t: ArrayLike | None = None, fps: float = 30.0) -> Scene:
        """Animate joint configurations, playable in the page.

        Parameters
        ----------
        Q : array_like, shape (K, n)
            The configurations (rad / m), one per frame.
        t : array_like, shape (K,), optional
            Their times (s, increasing); default one frame each at ``fps``.
        fps : float, optional
            Frames per second.

        Returns
        -------
        Scene
            self (the calls chain).

        Examples
        --------
        >>> s.animate(np.linspace([0.0, 0.0], [0.5, -1.0], 10), fps=10) is s
        True
        """
        Animation = require("meshcat.animation", "the viewer").Animation

        Q = np.asarray(Q, dtype=float)
        if Q.ndim != 2 or Q.shape[1] != self.robot.n or len(Q) < 1:
            raise InputError(f"Q: expected shape (K, {self.robot.n}), got {Q.shape}")
        if not np.all(np.isfinite(Q)):
            raise InputError("Q: contains NaN or infinite values")
        if not fps > 0:
            raise InputError(f"fps: expected a positive frame rate, got {fps!r}")
        if t is not None:
            t = np.asarray(t, dtype=float)
            if t.shape != (len(Q),) or np.any(np.diff(t) <= 0):
                raise InputError("t: expected increasing times, one per configuration")
            frames = np.round((t - t[0]) * fps).astype(int)
        else:
            frames = np.arange(len(Q))
        anim = Animation(default_framerate=fps)
        viewer = self.viz.viewer
        try:
            for k, q in zip(frames, Q):
                with anim.at_frame(self.vis, int(k)) as frame:
                    self.viz.viewer = frame
                    self.viz.display(self.robot.q_pin(q))
                    self._place_frames(frame, q)  # the triads and labels of frames() move with the robot
        finally:
            self.viz.viewer = viewer
        self.vis.set_animation(anim, play=True, repetitions=0)
        self._extra_points.extend(self.robot.frame_pose(q)[:3, 3] for q in Q[:: max(1, len(Q) // 20)])
        self._animated = True
        return self

    # ------------------------------------------------------------------ camera
    def _points(self) -> np.ndarray:
        poses = self.robot.frame_poses(self.q)
        P = np.array([T[:3, 3] for T in poses.values()])
        if self._extra_points:
            P = np.vstack([P, np.asarray(self._extra_points)])
        if self._label_points:
            P = np.vstack([P, np.asarray(self._label_points)])
        return P

    def _size(self) -> float:
        P = self._points()
        return float(max(np.ptp(P, axis=0).max(), 0.2))

    def ground_grid(self, spacing: float | None = None) -> Scene:
        """Draw a square ground grid under the robot, in the base frame's z = 0 plane.

        The grid is centred on the base and sized to the robot's reach: its half-width is the
        largest horizontal distance of any frame origin from the base over 256 random
        configurations (``numpy.random.default_rng(0)``, within the joint limits) and the
        configuration shown, plus 10 %, rounded up to a whole number of cells. meshcat's
        default 20 m grid (a thin band at the horizon from a 3/4 view) is hidden.

        Parameters
        ----------
        spacing : float, optional
            Cell size (m); default a round step giving about eight cells from the base to the
            edge (:func:`robokit.viz._shapes.ground_grid_segments`).

        Returns
        -------
        Scene
            self; ``self.grid`` is ``{"half": half-width (m), "spacing": cell (m), "z": 0.0}``.

        Examples
        --------
        >>> s.ground_grid().grid["z"]
        0.0
        """
        g = require("meshcat.geometry", "the viewer")
        from robokit.viz._shapes import ground_grid_segments

        r = self.robot
        rng = np.random.default_rng(0)
        pts = [self.robot.frame_poses(self.q)] + [r.frame_poses(r.random_configuration(rng)) for _ in range(256)]
        reach = max(float(np.hypot(T[0, 3], T[1, 3])) for d in pts for T in d.values())
        seg, half, spacing = ground_grid_segments(reach, spacing)
        self.vis["/Grid"].set_property("visible", False)
        self.vis["floor"].set_object(g.LineSegments(g.PointsGeometry(seg),
                                                    g.LineBasicMaterial(color=0x8090A8, transparent=True, opacity=0.7)))
        self.grid = {"half": half, "spacing": spacing, "z": 0.0}
        return self

    _SHIFTED = ("robot", "frames", "labels", "points", "paths", "poses", "ellipsoid", "obstacles", "floor", "/Grid", "/Axes")

    def frame_camera(self, fill: float = 0.75, azimuth: float = 45.0, elevation: float = 25.0) -> Scene:
        """Aim the camera at the robot (and everything drawn) so that it fills about ``fill`` of the view.

        meshcat 0.3's orbit controls always look at the world origin, so the scene content
        (robot, drawings, grid) is shifted by −c, c the centre of the points' bounding box, and
        the camera is placed in the direction (``azimuth``, ``elevation``; default a 3/4 view) at
        the distance where every point projects within ``fill`` of the view's half-height and
        half-width (:func:`camera_offset`).

        Parameters
        ----------
        fill : float
            Fraction of the view (0–1].
        azimuth, elevation : float
            View direction, degrees (base frame; elevation ≤ 85°).

        Returns
        -------
        Scene
            self (the calls chain).

        Examples
        --------
        >>> s.frame_camera(0.8) is s
        True
        """
        if self.grid is None:
            self.ground_grid()
        P = self._points()
        centre, offset = camera_offset(P, fill, azimuth, elevation)
        T = np.eye(4)
        T[:3, 3] = -centre
        for name in self._SHIFTED:
            self.vis[name].set_transform(T)
        # the camera object lives in a frame rotated so that three.js's "up" (y) is the world's z:
        # a world offset (x, y, z) is (x, z, −y) there
        self.vis["/Cameras/default/rotated/<object>"].set_property("position", [offset[0], offset[2], -offset[1]])
        return self

    # ------------------------------------------------------------------ output
    def html(self, mesh_cell: float | None = 0.002) -> str:
        """The scene as one self-contained HTML page (no server needed to view it).

        Meshes (visual and collision) go into the page decimated by vertex clustering with cubes of ``mesh_cell`` (m), as
        in the teach page (:mod:`robokit.viz._meshes`: every kept vertex within ``cell·√3`` of the
        surface, so at 2 mm the picture is unchanged): the Panda's page is 3.5 MB instead of 15.1 MB
        with its mesh files as they are, the UR5's 2.1 MB instead of 10.1 MB. The live scene keeps
        the full meshes. An animated scene's page has a visible play/pause button, a time slider
        and a clock in its lower-left corner.

        Parameters
        ----------
        mesh_cell : float or None, optional
            Cube side (m) of the decimation; None writes the mesh files as they are.

        Returns
        -------
        str
            The HTML page.

        Examples
        --------
        >>> with Scene("panda") as s:   # doctest: +SKIP
        ...     round(len(s.show().html()) / 1e6, 1)   # MB
        3.5
        """
        return self._with_player(self._page(mesh_cell))

    def _with_player(self, page: str) -> str:
        """The page with a visible play/pause button, time slider and clock when the scene is
        animated (meshcat's own controls hide behind "Open Controls")."""
        if not self._animated:
            return page
        from importlib import resources

        player = resources.files("robokit.viz").joinpath("player.html").read_text(encoding="utf-8")
        i = page.rfind("</body>")
        return page[:i] + player + page[i:] if i >= 0 else page + player

    def _page(self, mesh_cell: float | None) -> str:
        if mesh_cell is None:
            return self.vis.static_html()
        import pinocchio as pin

        from robokit.viz._meshes import decimated_visuals, draw_parts

        kinds = ((self.viz.visual_model, pin.GeometryType.VISUAL), (self.viz.collision_model, pin.GeometryType.COLLISION))
        swapped = [(go, parts, kind) for model, kind in kinds if model is not None
                   for go, parts in decimated_visuals(model, mesh_cell)]
        try:
            for go, parts, kind in swapped:
                node = self.vis[self.viz.getViewerNodeName(go, kind)]
                node.delete()  # the mesh file's object; the parts are drawn at the same node
                draw_parts(node, parts)
            self.viz.display(self.robot.q_pin(self.q))  # the nodes' placements, deleted with them
            return self.vis.static_html()
        finally:  # the live scene gets its full meshes back
            for go, _, kind in swapped:
                self.vis[self.viz.getViewerNodeName(go, kind)].delete()
                self.viz.loadViewerGeometryObject(go, kind)
            if swapped:
                self.viz.display(self.robot.q_pin(self.q))

    def notebook(self, height: int = 480, path: str | os.PathLike[str] | None = None) -> Any:
        """Show the scene in a Jupyter notebook: the self-contained page is written to a file
        (default ``robokit_views/<robot>-<k>.html`` beside the notebook, ``<robot>`` the robot's name
        made a plain file name by :func:`robokit._names.safe_stem`) and displayed in an
        ``IFrame``, so the executed notebook stays small (a meshed robot's page is 5–25 MB).

        Parameters
        ----------
        height : int, optional
            Height of the frame (px).
        path : str or path, optional
            Where to write the page (default as above).

        Returns
        -------
        IPython.display.IFrame
            The frame showing the written page.

        Examples
        --------
        >>> import tempfile, pathlib
        >>> view = s.notebook(height=300, path=pathlib.Path(tempfile.mkdtemp()) / "twolink.html")
        >>> view.height, view.src.endswith("twolink.html")
        (300, True)
        """
        IFrame = require("IPython.display", "showing a scene in a notebook").IFrame

        from robokit._io import atomic_write
        from robokit._names import safe_stem

        if path is None:
            folder = Path("robokit_views")
            folder.mkdir(exist_ok=True)
            Scene._views += 1
            path = folder / f"{safe_stem(self.robot.name)}-{Scene._views}.html"
        path = Path(path)
        atomic_write(path, self.html())
        return IFrame(src=str(path.as_posix()), width="100%", height=int(height))

    def teach(self, q: ArrayLike | None = None, height: int = 420, world: Any = None, wasm: bytes | None = None) -> Any:
        """A teach pendant in the notebook, driving this scene's live view.

        Joint sliders with the tool pose, Jacobian, manipulability, singularity and joint-limit
        readouts; with a ``world`` also its obstacles, links in contact in red and the
        minimum distance (see :func:`robokit.viz.teach.teach_widget`).

        Parameters
        ----------
        q : array_like, shape (n,), optional
            Initial joint values (rad / m).
        height : int
            Height of the 3-D view (px).
        world : robokit.collision.World, optional
            This scene's robot among obstacles (``World(scene.robot, obstacles)``).
        wasm : bytes, optional
            The robot's C as WebAssembly (``robokit.codegen.wasm.wasm_module(scene.robot).wasm``):
            with it (and anywidget) the pendant shows the teach page, whose tool you can drag.

        Returns
        -------
        ipywidgets.VBox
            The pendant (``.set_q``, ``.readouts``, ``.collision``, ``.drag``).

        Examples
        --------
        >>> scene = Scene("puma560")   # doctest: +SKIP
        >>> scene.teach()   # doctest: +SKIP
        """
        from robokit.viz.teach import teach_widget

        return teach_widget(self, q=q, height=height, world=world, wasm=wasm)

    def close(self) -> None:
        """Stop the meshcat server this scene started (if it started one).

        Returns
        -------
        None
            ``vis`` is None afterwards.

        Examples
        --------
        >>> s.close()
        >>> s.vis is None
        True
        """
        if self._own and self.vis is not None:
            stop_server(getattr(self.vis.window, "server_proc", None))
            self.vis = None

    def __enter__(self) -> Scene:
        return self

    def __exit__(self, *exc: Any) -> None:
        self.close()

    def __del__(self) -> None:  # pragma: no cover - best effort
        try:
            self.close()
        except Exception:
            pass
