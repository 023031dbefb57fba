r"""Capability (reachability) maps: the dexterous workspace of Lecture 5, computed at scale.

Lecture 5 distinguishes the *reachable* workspace (positions the tool reaches in at least
one orientation) from the *dexterous* workspace (positions it reaches in every
orientation). A capability map (Zacharias, Borst and Hirzinger, "Capturing robot workspace
structure: representing robot capabilities", IROS 2007; the "reachability index" of ROS
Reuleaux) measures the space in between: a voxel grid over the reachable space and, for each
voxel centre ``c``, the *index*

.. math::  D(c) = \frac{1}{K}\,\#\{k : \text{IK succeeds for } (R_k, c)\}

over a fixed, uniform set of K tool orientations ``R_k``
(:mod:`robokit.workspace.orientations`). ``D = 1``: the dexterous workspace; ``D > 0``: the
reachable workspace (as far as the orientation set resolves it).

How it is computed:

1. the grid and its pre-pass (:mod:`robokit.workspace.grid`): voxels the tool never comes
   near are dropped before any IK;
2. the marked voxels, in lexicographic order of their lattice index, are cut into chunks of
   ``chunk_size`` voxels; each chunk is one task: the worker rebuilds the robot from its
   :class:`~robokit.description.spec.RobotSpec` (``robokit.load(robot.spec)``: a name, a file
   with its options, or a DH table as text — never a Pinocchio object), builds the chunk's ``chunk_size × K`` target poses and answers
   them with :func:`robokit.workspace.ik_success`. Memory therefore grows with the chunk,
   never with ``M × K``;
3. tasks run in-process (``client="serial"``) or on Dask (a ``LocalCluster`` of one
   single-threaded process per core by default, or any ``distributed.Client``), at most two
   per worker in flight. The random numbers of the numerical IK are seeded per chunk
   (``SeedSequence([seed, chunk])``), so the map is identical bit for bit wherever it runs;
4. with a ``store`` folder, each finished chunk is written there as ``chunk_00042.npz``
   (atomically) beside the marker ``robokit-store.json``, which holds the fingerprint of
   every parameter that affects the result. A rerun with the same parameters reads the
   finished chunks back (each checked; a damaged one is recomputed with a note) and
   computes only the rest; a store with another fingerprint has its chunks removed first.
   The folder must be robokit's own and is locked while a run uses it
   (:mod:`robokit.workspace.store`). ``robokit workspace`` uses ``MAP.npz.chunks`` and
   removes it once ``MAP.npz`` is written.
"""
from __future__ import annotations

import hashlib
import io
import json
import pickle
import os
import time
import warnings
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Callable, TYPE_CHECKING

import numpy as np
from numpy.typing import ArrayLike

from robokit._optional import require
from robokit._io import atomic_write
from robokit._arrays import as_int
from robokit.workspace.map_robot import MapRobot, map_robot_of
from robokit.errors import InputError, InputTypeError, RobokitWarning
from robokit.workspace.mapfile import Member
from robokit.workspace.store import ChunkStore

if TYPE_CHECKING:
    from robokit.description.dh import DHTable
    from robokit.description.robot import Robot
    from robokit.description.spec import RobotSpec

__all__ = ["CapabilityMap", "capability_map", "MAX_MAP_BYTES"]

#: The map-file members that describe the robot (:mod:`robokit.workspace.map_robot`), read and
#: checked with the map's own members.
ROBOT_MEMBERS = {
    "robot_kind": Member((), "U", required=False),
    "robot_model": Member((), "U", required=False),
    "robot_tip": Member((), "U", required=False),
    "robot_dh": Member((), "U", required=False, max_text=1_000_000),  # a DH table's YAML text
    "robot_joint_types": Member((None,), "U", required=False),
    "robot_joint_placements": Member((None, 4, 4), "f", required=False),
    "robot_joint_axes": Member((None, 3), "f", required=False),
    "robot_tip_placement": Member((4, 4), "f", required=False),
}

#: Format version of the chunk store; part of the fingerprint.
_STORE_VERSION = 2
_SERIAL = ("serial", "local-process")

#: The most memory a capability map may need (bytes): its orientation set, one chunk's IK
#: targets and its grid (:func:`robokit.workspace.grid.reachable_voxels`); larger maps are refused
#: up front, saying how much they would need.
MAX_MAP_BYTES = 4 * 1024**3
#: Bytes per orientation of the set (a float64 3×3 matrix and the quaternions it is built from).
_BYTES_PER_ORIENTATION = 160
#: Bytes per IK problem of a chunk (its 4×4 float64 target and the solver's work arrays).
_BYTES_PER_PROBLEM = 256


@dataclass
class CapabilityMap:
    """A capability map: voxel centres and the fraction of tool orientations reachable there.

    Attributes
    ----------
    centres : (M, 3) ndarray
        Voxel centres in the base frame (m), lexicographic in their lattice index.
    index : (M,) ndarray
        Fraction of ``orientations`` for which IK succeeds at each centre, in [0, 1] (a
        multiple of 1/K). Voxels not in the map have index 0.
    orientations : (K, 3, 3) ndarray
        The tool orientations tried, in the base frame.
    resolution : float
        Voxel edge (m).
    robot : str
        The robot's name ("" when loaded from a file that does not store it).
    description : :class:`~robokit.workspace.map_robot.MapRobot` or None
        The robot as the map file stores it (its name, its DH table or its chain's geometry —
        never a path), so a viewer draws it without opening any file; None when unknown.
    parameters : dict
        Everything that determined the map (IK back end, planar or not, chunk size,
        pre-pass samples, seed, fingerprint).
    timings : dict
        Seconds spent in the pre-pass, the sweep and in total; IK problems solved; chunks
        computed and chunks read back from a store; workers.
    """

    centres: np.ndarray
    index: np.ndarray
    orientations: np.ndarray
    resolution: float
    robot: str = ""
    parameters: dict = field(default_factory=dict)
    timings: dict = field(default_factory=dict)
    description: MapRobot | None = None

    @property
    def dexterous(self) -> np.ndarray:
        """The dexterous workspace: centres reachable in every orientation of the set.

        Returns
        -------
        ndarray, shape (D, 3)
            The centres (m, base frame) with index 1.
        """
        return self.centres[self.index >= 1.0]

    @property
    def reachable(self) -> np.ndarray:
        """The reachable workspace as the map resolves it: centres reached in at least one orientation.

        Returns
        -------
        ndarray, shape (R, 3)
            The centres (m, base frame) with index > 0.
        """
        return self.centres[self.index > 0.0]

    def to_bytes(self, include_robot: bool = False) -> bytes:
        """The ``.npz`` file's bytes: ``centres``, ``index``, ``orientations``, ``resolution``.

        Parameters
        ----------
        include_robot : bool
            Also ``robot`` (the name) and the robot's ``description`` members
            (:mod:`robokit.workspace.map_robot`), so a viewer can draw the arm.

        Returns
        -------
        bytes
            An uncompressed ``.npz`` archive.

        Examples
        --------
        >>> import robokit
        >>> cmap = robokit.capability_map("rrr", 0.2, orientations=4, client="serial")
        >>> cmap.to_bytes()[:2]
        b'PK'
        """
        arrays = dict(centres=self.centres, index=self.index, orientations=self.orientations,
                      resolution=np.float64(self.resolution))
        if include_robot:
            arrays["robot"] = np.str_(self.robot)
            if self.description is not None:
                arrays.update(self.description.to_arrays())
        buf = io.BytesIO()
        np.savez(buf, **arrays)
        return buf.getvalue()

    def save(self, path: str | os.PathLike[str], include_robot: bool = False) -> Path:
        """Write the map to ``path`` (``.npz``) atomically (nothing half-written on failure).

        Parameters
        ----------
        path : str or path-like
            The file to write.
        include_robot : bool
            Store the robot's name and description too (:meth:`to_bytes`).

        Returns
        -------
        pathlib.Path
            ``path``: the ``.npz`` file, which :meth:`load` reads back.

        Examples
        --------
        >>> import robokit, tempfile, os
        >>> cmap = robokit.capability_map("rrr", 0.2, orientations=4, client="serial")
        >>> cmap.save(os.path.join(tempfile.mkdtemp(), "m.npz")).suffix
        '.npz'
        """
        return atomic_write(path, self.to_bytes(include_robot))

    @classmethod
    def load(cls, path: str | os.PathLike[str]) -> "CapabilityMap":
        """Read a map written by :meth:`save` or ``robokit workspace``.

        The file is checked before anything is allocated and its values after
        (:func:`robokit.workspace.mapfile.read_map_arrays`: a regular file, the members'
        headers, sizes, dtypes, finite values, index in [0, 1], rotations, a positive
        resolution).

        Parameters
        ----------
        path : path
            The ``.npz`` file (not a symbolic link).

        Returns
        -------
        CapabilityMap
            ``centres`` (M, 3) m, ``index`` (M,), ``orientations`` (K, 3, 3), ``resolution``
            m, ``robot`` (the stored name or ""); InputError naming the file and the member
            when a check fails.

        Examples
        --------
        >>> import robokit, tempfile, os
        >>> p = os.path.join(tempfile.mkdtemp(), "m.npz")
        >>> _ = robokit.capability_map("rrr", 0.2, orientations=4, client="serial").save(p)
        >>> CapabilityMap.load(p).orientations.shape
        (4, 3, 3)
        """
        from robokit.workspace.mapfile import read_map_arrays

        data = read_map_arrays(path, extra=ROBOT_MEMBERS)
        description, note = MapRobot.from_arrays(data, source=str(path))
        if note:
            warnings.warn(note, RobokitWarning, stacklevel=2)
        robot = description.name if description is not None else (str(data["robot"]) if "robot" in data else "")
        return cls(data["centres"], data["index"], data["orientations"], float(data["resolution"]), robot,
                   description=description)


# ----------------------------------------------------------------------------- robot descriptions
def _describe(robot_arg: Any, robot: Robot) -> RobotSpec:
    """The picklable description the workers rebuild the robot from: its RobotSpec (never a
    Pinocchio object), whatever format it was loaded from."""
    from robokit.errors import InputError

    if robot.spec is None:
        raise InputError(f"robot: {robot.name!r} was built by hand from a Pinocchio model and has no RobotSpec "
                         "for the workers; pass what robokit.load reads (a name, a file, a DHTable, a RobotSpec)")
    return robot.spec


def _check_bounded(robot: Robot) -> None:
    """Refuse an arm with an unlimited prismatic joint: its reachable space has no bound, so no grid
    covers it (an unlimited revolute joint is fine: a turn covers it)."""
    from robokit._units import revolute_columns
    from robokit.errors import InputError

    qlim = np.asarray(robot.qlim, dtype=float)
    for i, revolute in enumerate(revolute_columns(robot.poe.Slist)):
        if not revolute and not np.isfinite(qlim[i]).all():
            raise InputError(f"robot: joint {robot.joint_names[i]!r} is prismatic with no limits "
                             f"({qlim[i, 0]:g} to {qlim[i, 1]:g} m), so the arm reaches without bound and no map "
                             "covers it; give the joint limits (DH qlim, URDF/MJCF joint range)")


def _description_digest(desc: RobotSpec) -> str:
    """Fingerprint of a robot description: the spec's fields and the bytes of the file it names."""
    import dataclasses

    h = hashlib.sha256()
    h.update(json.dumps(dataclasses.asdict(desc), sort_keys=True).encode())
    if desc.kind == "shipped":
        from robokit.description.models import models_dir

        files = [models_dir() / f"{desc.name}.yaml"]
    else:
        files = [Path(desc.path)] if desc.path is not None and desc.kind != "dh" else []
    for p in files:
        if p.is_file():
            h.update(p.read_bytes())
    return h.hexdigest()


#: One of robokit's two module-level caches (docs/caches.md): a Dask worker process's robot and IK
#: back end per (description digest, restarts). A task ships only the RobotSpec; without this each
#: task would load and analyse the robot again. Keyed by value (the description's bytes), never by id.
_WORKER_CACHE: dict = {}


def _backend_for(desc: RobotSpec, restarts: int) -> Any:
    """The robot and IK back end of ``desc``, built once per process."""
    key = (_description_digest(desc), restarts)
    hit = _WORKER_CACHE.get(key)
    if hit is None:
        from robokit.description.loading import load
        from robokit.workspace.reach import _Backend

        # the caller loaded this robot and said its notes (missing meshes, locked joints, ...) once: a
        # worker's rebuild from the spec says nothing again (before, each note came once more per worker)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", RobokitWarning)
            robot = load(desc)
        hit = _WORKER_CACHE[key] = _Backend(robot, restarts)
    return hit


def _chunk_counts(desc: RobotSpec, centres: np.ndarray, orientations: np.ndarray, restarts: int, seed: int, chunk: int,
                  world: Any = None) -> np.ndarray:
    """The task: for (m, 3) centres, how many of the K orientations IK reaches, (m,) int64."""
    backend = _backend_for(desc, restarts)
    m, K = len(centres), len(orientations)
    T = np.zeros((m, K, 4, 4))
    T[:, :, :3, :3] = orientations[None]
    T[:, :, :3, 3] = centres[:, None, :]
    T[:, :, 3, 3] = 1.0
    rng = np.random.default_rng(np.random.SeedSequence([int(seed), int(chunk)]))
    if world is None:
        ok = backend.success(T.reshape(m * K, 4, 4), rng)
    else:
        ok = _collision_free_success(backend.robot, world, T.reshape(m * K, 4, 4), restarts, rng)
    return ok.reshape(m, K).sum(axis=1).astype(np.int64)


def _world_state(world: Any, robot: Robot) -> Any:
    """The plain data a ``robokit.collision.World`` is rebuilt from in the workers
    (:meth:`~robokit.collision.World.state`: obstacles, padding, convex, self-collision pairs;
    no coal object is ever pickled)."""
    if world is None:
        return None
    from robokit.collision import World
    from robokit.errors import InputError
    if not isinstance(world, World):
        raise InputError(f"world: expected a robokit.collision.World, got {type(world).__name__}")
    if world.robot.name != robot.name:
        raise InputError(f"world: built for {world.robot.name!r}, not for {robot.name!r}")
    return world.state()


def _collision_free_success(robot: Robot, world: Any, T: np.ndarray, restarts: int, rng: np.random.Generator) -> np.ndarray:
    """Per pose: reached by an IK solution inside the limits that is collision-free in the world
    (rebuilt once per process from its state ``world``)."""
    from robokit.collision import World
    from robokit.ik.closed_form import ik_analytic, ik_analytic_kind
    from robokit.ik.numeric import solve_ik

    # rebuilt once per robot (the worker's, by its spec) and world state, and kept with the robot
    key = ("collision world", hashlib.sha256(pickle.dumps(world)).hexdigest())
    w = robot.derived(key, lambda: World.from_state(world, robot=robot))
    closed = robot.n == 6 and ik_analytic_kind(robot).method is not None
    out = np.zeros(len(T), dtype=bool)
    for k, Tk in enumerate(T):
        if closed:
            out[k] = any(s.within_limits and s.collision_free for s in ik_analytic(robot, Tk, world=w))
        else:
            out[k] = solve_ik(robot, Tk, world=w, max_restarts=restarts, rng=rng).success
    return out


# ----------------------------------------------------------------------------- the map
def _check_resolution(resolution: object) -> float:
    if isinstance(resolution, bool) or not isinstance(resolution, (int, float, np.integer, np.floating)):
        raise InputTypeError(f"resolution: expected a number of metres, got {type(resolution).__name__}")
    r = float(resolution)
    if not (np.isfinite(r) and r > 0):
        raise InputError(f"resolution: expected a positive voxel size in m, got {resolution!r}")
    return r


def _orientation_set(orientations: int | ArrayLike, chain: Any) -> np.ndarray:
    from robokit.workspace.orientations import planar_rotations, super_fibonacci_rotations

    if isinstance(orientations, (int, np.integer)) and not isinstance(orientations, bool):
        if chain is not None:
            return planar_rotations(int(orientations), chain.normal, chain.R0)
        return super_fibonacci_rotations(int(orientations))
    if isinstance(orientations, bool) or np.ndim(orientations) != 3:
        raise InputTypeError(f"orientations: expected a count K or a (K, 3, 3) array, got {type(orientations).__name__}")
    R = np.asarray(orientations, dtype=float)
    if R.shape[1:] != (3, 3) or len(R) == 0:
        raise InputError(f"orientations: expected shape (K, 3, 3) with K ≥ 1, got {R.shape}")
    if not np.isfinite(R).all():
        raise InputError("orientations: contains NaN or infinite values")
    err = np.abs(R @ np.transpose(R, (0, 2, 1)) - np.eye(3)).max(axis=(1, 2))
    if np.any(err > 1e-6) or np.any(np.linalg.det(R) < 0):
        k = int(np.argmax(err))
        raise InputError(f"orientations: matrix {k} is not a rotation (‖RRᵀ − I‖ = {err[k]:.2g})")
    return np.ascontiguousarray(R)


def _progress(total: int, enabled: bool | None) -> tuple[Any, Any]:
    """A rich progress bar on stderr counting chunks (a no-op when stderr is not a terminal)."""
    from rich.console import Console
    from rich.progress import BarColumn, MofNCompleteColumn, Progress, TextColumn, TimeRemainingColumn

    console = Console(stderr=True)
    show = console.is_terminal if enabled is None else bool(enabled)
    return Progress(TextColumn("capability map"), BarColumn(), MofNCompleteColumn(), TextColumn("chunks"),
                    TimeRemainingColumn(), console=console, disable=not show, transient=False), total


def capability_map(robot: Robot | DHTable | RobotSpec | str | os.PathLike[str], resolution: float, orientations: int | ArrayLike = 100, client: Any = None, *, store: str | os.PathLike[str] | bool | None = None,
                   chunk_size: int | None = None, samples: int | None = None, seed: int = 0,
                   restarts: int | None = None, progress: bool | None = None,
                   dashboard: bool = False, world: Any = None) -> CapabilityMap:
    """Capability map of ``robot``'s tip: per voxel, the fraction of K orientations it reaches.

    Parameters
    ----------
    robot : :class:`robokit.Robot`, :class:`robokit.DHTable`, :class:`robokit.RobotSpec`, or a name/path ``robokit.load`` accepts
        The arm; its tip frame is the tool. Workers rebuild it from its ``robot.spec``, so a
        robot from any format robokit reads (DH, URDF, xacro, MJCF, example-robot-data) gets
        a map.
    resolution : float
        Voxel edge (m).
    orientations : int or (K, 3, 3) array
        A count K (a super-Fibonacci set on SO(3), or K angles about the plane normal for a
        planar arm; see :mod:`robokit.workspace.orientations`) or the rotations themselves
        (base frame). Default 100.
    client : None, ``"serial"``, a ``distributed.Client`` or a scheduler address
        Where the chunks run: None starts a ``LocalCluster`` (one single-threaded worker
        process per core) for this call; ``"serial"`` computes in this process without Dask;
        a Client or a ``"tcp://host:port"`` address uses that cluster. The map is the same in
        every case.
    store : path, optional
        A folder for finished chunks so that an interrupted run resumes (module docstring).
        Kept after the call; remove it once the map is saved.
    chunk_size : int, optional
        Voxels per task (default: about 4096 IK problems per task).
    samples : int, optional
        Forward-kinematics samples of the pre-pass (:func:`robokit.workspace.grid.reachable_voxels`).
    seed : int
        Seeds the pre-pass and the numerical IK (per chunk).
    restarts : int, optional
        Random restarts of the numerical IK per target (default 20).
    progress : bool, optional
        Show a progress bar of chunks on stderr (default: only when stderr is a terminal).
    dashboard : bool
        With ``client=None``: serve Dask's dashboard on 127.0.0.1 (its link is given as a note).
    world : :class:`robokit.collision.World`, optional
        Count only orientations reached by an IK solution inside the limits that is free of
        self- and obstacle collisions (closed form: any such branch; otherwise ``solve_ik``
        with ``world``). The world travels as plain data (``world.state()``: obstacles,
        padding, ``convex``, the self-collision pairs), each worker rebuilds it once, and the
        store's fingerprint includes it; the counts are the same in-process and on Dask.
        Slower than the plain map (one IK call per pose; ``World(..., convex=True)`` is the
        faster, conservative choice for mesh robots).

    Returns
    -------
    CapabilityMap
        ``.centres`` (M, 3) m, ``.index`` (M,) in [0, 1], ``.orientations`` (K, 3, 3),
        ``.resolution`` m; ``.dexterous`` are the centres with index 1.

    Notes
    -----
    Planar arms (revolute joints about parallel axes) get a grid in the tool's plane and the
    rotations about the plane normal as orientations: off-plane positions and tilted
    orientations are unreachable by construction, so sweeping them would only add zeros.

    Examples
    --------
    >>> import robokit
    >>> cmap = robokit.capability_map("rrr", 0.1, orientations=8, client="serial")
    >>> float(cmap.index.max()), cmap.orientations.shape
    (1.0, (8, 3, 3))

    Collision-free counts only (a floor under the PUMA's base):

    >>> from robokit.collision import Box, World, pose_from_xyz_rpy
    >>> puma = robokit.load("puma560")
    >>> floor = Box([3, 3, 0.1], pose_from_xyz_rpy([0, 0, -0.1], [0, 0, 0]), name="floor")
    >>> free = capability_map(puma, 0.4, orientations=4, client="serial", world=World(puma, [floor]))
    >>> bool(free.index.sum() < capability_map(puma, 0.4, orientations=4, client="serial").index.sum())
    True
    """
    from robokit.description.loading import load
    from robokit.workspace.reach import DEFAULT_RESTARTS, ik_backend, planar_chain

    t0 = time.perf_counter()
    res = _check_resolution(resolution)
    seed = as_int(seed, "seed", minimum=0)
    restarts = DEFAULT_RESTARTS if restarts is None else restarts
    restarts = as_int(restarts, "restarts", minimum=0)
    if not (client is None or isinstance(client, str) or hasattr(client, "submit")):
        raise InputTypeError(f"client: expected None, 'serial', a scheduler address or a distributed.Client, "
                        f"got {type(client).__name__}")
    rob = load(robot)
    _check_bounded(rob)
    desc = _describe(robot, rob)
    kind = ik_backend(rob)
    chain = planar_chain(rob)
    if chain is not None and chain.n < 2:
        chain = None
    K_asked = int(orientations) if isinstance(orientations, (int, np.integer)) else len(orientations)  # type: ignore[arg-type]
    if chunk_size is None:
        chunk_size = max(1, 4096 // max(K_asked, 1))
    if isinstance(chunk_size, bool) or not isinstance(chunk_size, (int, np.integer)) or chunk_size < 1:
        raise InputError(f"chunk_size: expected a positive integer, got {chunk_size!r}")
    fixed = K_asked * (_BYTES_PER_ORIENTATION + _BYTES_PER_PROBLEM * int(chunk_size))
    if fixed > MAX_MAP_BYTES:
        raise InputError(f"orientations: {K_asked} orientations ({int(chunk_size)} voxels per chunk) need about "
                         f"{fixed / 1e9:.3g} GB; robokit refuses maps above {MAX_MAP_BYTES / 1e9:.3g} GB "
                         "(fewer orientations)")
    R = _orientation_set(orientations, chain)
    if samples is not None and (isinstance(samples, bool) or not isinstance(samples, (int, np.integer))
                                or samples < 1):
        raise InputError(f"samples: expected a positive integer, got {samples!r}")

    if isinstance(store, bool):
        raise InputError(f"store: expected a folder path, got {store!r}")
    st = ChunkStore(store) if store is not None else None  # the folder checked and locked before any work
    try:
        with _Cluster(client, dashboard) as cl:
            return _capability_map(rob, desc, kind, chain, R, res, cl.client, st, int(chunk_size), samples,
                                   int(seed), int(restarts), progress, t0, MAX_MAP_BYTES - fixed,
                                   _world_state(world, rob))
    finally:
        if st is not None:
            st.close()


def _capability_map(rob: Robot, desc: RobotSpec, kind: str, chain: Any, R: np.ndarray, res: float, client: Any, st: ChunkStore | None, chunk_size: int, samples: int | None, seed: int, restarts: int, progress: bool | None, t0: float, max_bytes: float, world: Any = None) -> CapabilityMap:
    from robokit.workspace.grid import reachable_voxels

    K = len(R)

    keys, used = reachable_voxels(rob, res, samples=samples, seed=int(seed), chain=chain, max_bytes=max_bytes)
    if chain is not None:
        centres = chain.from_plane(keys.astype(float) * res)
    else:
        centres = keys.astype(float) * res
    t_pre = time.perf_counter() - t0
    M = len(centres)
    n_chunks = -(-M // int(chunk_size))
    params = dict(robot=rob.name, description=_description_digest(desc), resolution=res, K=K,
                  orientations=hashlib.sha256(R.tobytes()).hexdigest(), chunk_size=int(chunk_size),
                  samples=used, seed=int(seed), restarts=int(restarts), ik=kind, planar=chain is not None,
                  voxels=M, chunks=n_chunks, version=_STORE_VERSION)
    if world is not None:  # collision-free counts: a different map, a different store fingerprint
        params["world"] = hashlib.sha256(pickle.dumps(world)).hexdigest()
    fingerprint = hashlib.sha256(json.dumps(params, sort_keys=True).encode()).hexdigest()
    params["fingerprint"] = fingerprint
    if st is not None:
        st.begin(fingerprint, params, K)
    return _sweep(rob, centres, R, res, client, st, chunk_size, desc, restarts, seed, progress, params, t0, t_pre,
                  world)


def _sweep(rob: Robot, centres: np.ndarray, R: np.ndarray, res: float, client: Any, st: ChunkStore | None,
           chunk_size: int, desc: RobotSpec, restarts: int, seed: int, progress: bool | None, params: dict, t0: float,
           t_pre: float, world: Any = None) -> CapabilityMap:
    """The orientation sweep over the chunks (those not already in the store ``st``)."""
    K, M = len(R), len(centres)
    n_chunks = params["chunks"]
    fingerprint = params["fingerprint"]
    counts = np.zeros(M, dtype=np.int64)
    todo = []
    resumed = 0
    for c in range(n_chunks):
        sl = slice(c * chunk_size, min(M, (c + 1) * chunk_size))
        old = st.read(c, centres[sl]) if st is not None else None
        if old is not None:
            counts[sl] = old
            resumed += 1
        else:
            todo.append(c)

    computed = [0]

    def finish(c: int, result: np.ndarray) -> None:
        sl = slice(c * chunk_size, min(M, (c + 1) * chunk_size))
        result = np.asarray(result)
        if (result.shape != (sl.stop - sl.start,) or result.dtype.kind not in "iu"
                or result.min(initial=0) < 0 or result.max(initial=0) > K):
            raise InputError(f"scheduler: a worker returned an invalid result for chunk {c} "
                             f"(expected {sl.stop - sl.start} counts in [0, {K}])")
        counts[sl] = result
        computed[0] += len(result)
        if st is not None:
            st.write(c, centres[sl], result)

    t1 = time.perf_counter()
    bar, total = _progress(n_chunks, progress)
    workers = 1
    with bar:
        task = bar.add_task("chunks", total=total, completed=resumed)
        if client is None:
            for c in todo:
                sl = slice(c * chunk_size, min(M, (c + 1) * chunk_size))
                finish(c, _chunk_counts(desc, centres[sl], R, restarts, seed, c, world))
                bar.advance(task)
        elif todo:
            workers = _run_dask(client, todo, lambda c: centres[c * chunk_size: min(M, (c + 1) * chunk_size)],
                                desc, R, restarts, seed, finish, lambda: bar.advance(task), fingerprint, world)
    t_sweep = time.perf_counter() - t1
    index = counts / K
    timings = dict(prepass=t_pre, sweep=t_sweep, total=time.perf_counter() - t0,
                   problems=computed[0] * K,
                   chunks=len(todo), chunks_resumed=resumed, workers=workers)
    return CapabilityMap(centres, index, R, res, rob.name, params, timings, description=map_robot_of(rob))


class _Cluster:
    """The Dask client for a call: None (serial), the caller's Client, a scheduler address
    (probed and time-bounded, :func:`robokit.workspace.cluster.connect_scheduler`) or robokit's
    own TLS cluster (:func:`robokit.workspace.cluster.local_cluster`), closed on exit."""

    def __init__(self, client: Any, dashboard: bool = False) -> None:
        from robokit.workspace.cluster import connect_scheduler, local_cluster

        self.client: Any = None
        self.cluster: Any = None
        self.security: Any = None
        self.own = False
        if isinstance(client, str) and client in _SERIAL:
            return
        if client is None:
            self.cluster, self.client, self.security = local_cluster(os.cpu_count() or 1, dashboard)
            self.own = True
            if dashboard:
                warnings.warn(f"Dask dashboard: {self.client.dashboard_link}", RobokitWarning, stacklevel=3)
        elif isinstance(client, str):
            self.client, self.own = connect_scheduler(client), True
        else:
            self.client = client

    def __enter__(self) -> _Cluster:
        return self

    def __exit__(self, *exc: object) -> None:
        if self.own:
            self.client.close()
        if self.cluster is not None:
            self.cluster.close()


def _run_dask(client: Any, todo: list[int], centres_of: Callable[[int], np.ndarray], desc: RobotSpec, R: np.ndarray, restarts: int, seed: int, finish: Callable[[int, np.ndarray], None], advance: Callable[[], None], fingerprint: str, world: Any = None) -> int:
    """Run the chunks ``todo`` on Dask, at most two tasks per worker in flight; returns the worker count."""
    as_completed = require("distributed", "a capability map on a Dask cluster").as_completed

    workers = max(1, len(client.scheduler_info().get("workers", {})))
    limit = 2 * workers
    pending = list(todo)
    ac = as_completed()
    futures = {}

    def submit() -> None:
        c = pending.pop(0)
        f = client.submit(_chunk_counts, desc, centres_of(c), R, restarts, seed, c, world,
                          key=f"capability-{fingerprint[:16]}-{c:05d}")
        futures[f.key] = c
        ac.add(f)

    while pending and len(futures) < limit:
        submit()
    for f in ac:
        c = futures.pop(f.key)
        finish(c, f.result())
        f.release()
        advance()
        if pending:
            submit()
    return workers
