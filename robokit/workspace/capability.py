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
   ``chunk_size`` voxels; each chunk is one task: the worker rebuilds the robot from a
   picklable description (a DH table, or a shipped/example-robot-data name or file path —
   never a Pinocchio object), builds the chunk's ``chunk_size × K`` target poses and answers
   them with :func:`robokit.workspace.ik_success`. Memory therefore grows with the chunk,
   never with ``M × K``;
3. tasks run in-process (``client="serial"``) or on Dask (a ``LocalCluster`` of one
   single-threaded process per core by default, or any ``distributed.Client``), at most two
   per worker in flight. The random numbers of the numerical IK are seeded per chunk
   (``SeedSequence([seed, chunk])``), so the map is identical bit for bit wherever it runs;
4. with a ``store`` folder, each finished chunk is written there as ``chunk_00042.npz``
   (atomically) next to ``params.json``, the fingerprint of every parameter that affects the
   result. A rerun with the same parameters reads the finished chunks back and computes
   only the rest; a store with another fingerprint is emptied first. ``robokit workspace``
   uses ``MAP.npz.chunks`` and removes it once ``MAP.npz`` is written.
"""
from __future__ import annotations

import hashlib
import io
import json
import os
import shutil
import time
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Callable, TYPE_CHECKING

import numpy as np
from numpy.typing import ArrayLike

from robokit._io import atomic_write
from robokit._arrays import as_int
from robokit.errors import InputError, InputTypeError

if TYPE_CHECKING:
    from robokit.description.dh import DHTable
    from robokit.description.robot import Robot

__all__ = ["CapabilityMap", "capability_map"]

#: Format version of the chunk store; part of the fingerprint.
_STORE_VERSION = 1
_SERIAL = ("serial", "local-process")


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

    @property
    def dexterous(self) -> np.ndarray:
        """(D, 3) centres reachable in every orientation (index 1): the dexterous workspace."""
        return self.centres[self.index >= 1.0]

    @property
    def reachable(self) -> np.ndarray:
        """(R, 3) centres reachable in at least one orientation of the set (index > 0)."""
        return self.centres[self.index > 0.0]

    def to_bytes(self, include_robot: bool = False) -> bytes:
        """The ``.npz`` file's bytes: ``centres``, ``index``, ``orientations``, ``resolution``
        (and ``robot``, the name, when ``include_robot``)."""
        arrays = dict(centres=self.centres, index=self.index, orientations=self.orientations,
                      resolution=np.float64(self.resolution))
        if include_robot:
            arrays["robot"] = np.str_(self.robot)
        buf = io.BytesIO()
        np.savez(buf, **arrays)
        return buf.getvalue()

    def save(self, path: str | os.PathLike[str], include_robot: bool = False) -> Path:
        """Write the map to ``path`` (``.npz``) atomically; see :meth:`to_bytes`."""
        return atomic_write(path, self.to_bytes(include_robot))

    @classmethod
    def load(cls, path: str | os.PathLike[str]) -> "CapabilityMap":
        """Read a map written by :meth:`save` or ``robokit workspace``; ValueError naming the file if it is not one."""
        p = Path(path)
        if not p.is_file():
            raise InputError(f"map: file {str(p)!r} not found")
        try:
            with np.load(p, allow_pickle=False) as z:
                data = {k: z[k] for k in z.files}
        except (OSError, ValueError) as exc:
            raise InputError(f"map: cannot read {str(p)!r} as an .npz file: {exc}") from None
        missing = [k for k in ("centres", "index", "orientations", "resolution") if k not in data]
        if missing:
            raise InputError(f"map: {str(p)!r} is not a capability map (missing {', '.join(missing)})")
        C, D, R = data["centres"], data["index"], data["orientations"]
        if C.ndim != 2 or C.shape[1] != 3 or D.shape != (len(C),) or R.ndim != 3 or R.shape[1:] != (3, 3):
            raise InputError(f"map: {str(p)!r} has inconsistent shapes: centres {C.shape}, index {D.shape}, "
                             f"orientations {R.shape}")
        robot = str(data["robot"]) if "robot" in data else ""
        return cls(C.astype(float), D.astype(float), R.astype(float), float(data["resolution"]), robot)


# ----------------------------------------------------------------------------- robot descriptions
def _describe(robot_arg: Any, robot: Robot) -> tuple:
    """A picklable description the workers rebuild the robot from (never a Pinocchio object)."""
    from robokit.description.dh import DHTable

    if isinstance(robot_arg, DHTable):
        return ("dh", robot_arg)
    if robot.dh is not None:
        return ("dh", robot.dh)
    src = str(robot.source)
    if src.startswith("example-robot-data:"):
        return ("load", src.split(":", 1)[1], robot.tip)
    if Path(src).suffix.lower() == ".urdf" and Path(src).is_file():
        return ("load", str(Path(src).resolve()), robot.tip)
    raise InputError(f"robot: cannot describe {robot.name!r} (source {src!r}) for the workers; "
                     "pass a shipped model name, a .yaml/.urdf path, an example-robot-data name or a DHTable")


def _description_digest(desc: tuple) -> str:
    h = hashlib.sha256()
    if desc[0] == "dh":
        h.update(desc[1].to_yaml_str(angle_unit="rad").encode())
    else:
        h.update(repr(desc).encode())
        p = Path(desc[1])
        if p.is_file():
            h.update(p.read_bytes())
    return h.hexdigest()


_WORKER_CACHE: dict = {}


def _backend_for(desc: tuple, restarts: int) -> Any:
    """The robot and IK back end of ``desc``, built once per process."""
    key = (_description_digest(desc), restarts)
    hit = _WORKER_CACHE.get(key)
    if hit is None:
        from robokit.description.robot import load
        from robokit.workspace.reach import _Backend

        robot = load(desc[1]) if desc[0] == "dh" else load(desc[1], tip=desc[2])
        hit = _WORKER_CACHE[key] = _Backend(robot, restarts)
    return hit


def _chunk_counts(desc: tuple, centres: np.ndarray, orientations: np.ndarray, restarts: int, seed: int, chunk: int) -> np.ndarray:
    """The task: for (m, 3) centres, how many of the K orientations IK reaches, (m,) int64."""
    backend = _backend_for(desc, restarts)
    m, K = len(centres), len(orientations)
    T = np.zeros((m, K, 4, 4))
    T[:, :, :3, :3] = orientations[None]
    T[:, :, :3, 3] = centres[:, None, :]
    T[:, :, 3, 3] = 1.0
    rng = np.random.default_rng(np.random.SeedSequence([int(seed), int(chunk)]))
    ok = backend.success(T.reshape(m * K, 4, 4), rng)
    return ok.reshape(m, K).sum(axis=1).astype(np.int64)


# ----------------------------------------------------------------------------- chunk store
class _Store:
    """A folder of finished chunks: ``params.json`` and ``chunk_00000.npz`` … (see the module docstring)."""

    def __init__(self, path: str | os.PathLike[str], fingerprint: str, params: dict) -> None:
        self.path = Path(path)
        self.fp = fingerprint
        meta = self.path / "params.json"
        if self.path.exists() and not self.path.is_dir():
            raise InputError(f"store: {str(self.path)!r} exists and is not a folder")
        if self.path.is_dir():
            try:
                old = json.loads(meta.read_text(encoding="utf-8")).get("fingerprint")
            except (OSError, ValueError):
                old = None
            if old != fingerprint:  # other parameters (or not a store of ours): start afresh
                for f in self.path.glob("chunk_*.npz"):
                    f.unlink()
        else:
            if not (self.path.parent if str(self.path.parent) else Path(".")).is_dir():
                raise InputError(f"store: folder {str(self.path.parent)!r} does not exist")
            self.path.mkdir()
        atomic_write(meta, json.dumps({"fingerprint": fingerprint, "parameters": params}, indent=1, sort_keys=True))

    def _file(self, chunk: int) -> Path:
        return self.path / f"chunk_{chunk:05d}.npz"

    def read(self, chunk: int, centres: np.ndarray) -> np.ndarray | None:
        f = self._file(chunk)
        if not f.is_file():
            return None
        try:
            with np.load(f, allow_pickle=False) as z:
                if str(z["fingerprint"]) != self.fp or not np.array_equal(z["centres"], centres):
                    return None
                return z["counts"].astype(np.int64)
        except (OSError, ValueError, KeyError):
            return None  # damaged: recompute

    def write(self, chunk: int, centres: np.ndarray, counts: np.ndarray) -> None:
        buf = io.BytesIO()
        np.savez(buf, counts=counts, centres=centres, fingerprint=np.str_(self.fp))
        atomic_write(self._file(chunk), buf.getvalue())

    def remove(self) -> None:
        shutil.rmtree(self.path, ignore_errors=True)


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


def capability_map(robot: Robot | DHTable | str | os.PathLike[str], resolution: float, orientations: int | ArrayLike = 100, client: Any = None, *, store: str | os.PathLike[str] | bool | None = None,
                   chunk_size: int | None = None, samples: int | None = None, seed: int = 0,
                   restarts: int | None = None, progress: bool | None = None) -> CapabilityMap:
    """Capability map of ``robot``'s tip: per voxel, the fraction of K orientations it reaches.

    Parameters
    ----------
    robot : :class:`robokit.Robot`, :class:`robokit.DHTable`, or a name/path ``robokit.load`` accepts
        The arm; its tip frame is the tool.
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
    >>> cmap.index.max()
    1.0
    """
    from robokit.description.robot import load
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
    desc = _describe(robot, rob)
    kind = ik_backend(rob)
    chain = planar_chain(rob)
    if chain is not None and chain.n < 2:
        chain = None
    R = _orientation_set(orientations, chain)
    K = len(R)
    if chunk_size is None:
        chunk_size = max(1, 4096 // K)
    chunk_size = as_int(chunk_size, "chunk_size", minimum=1)
    if samples is not None:
        samples = as_int(samples, "samples", minimum=1)

    with _Cluster(client) as cl:
        return _capability_map(rob, desc, kind, chain, R, res, cl.client, store, int(chunk_size), samples,
                               int(seed), int(restarts), progress, t0)


def _capability_map(rob: Robot, desc: tuple, kind: str, chain: Any, R: np.ndarray, res: float, client: Any, store: Any, chunk_size: int, samples: int | None, seed: int, restarts: int, progress: bool | None, t0: float) -> CapabilityMap:
    from robokit.workspace.grid import reachable_voxels

    K = len(R)

    keys, used = reachable_voxels(rob, res, samples=samples, seed=int(seed), chain=chain)
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
    fingerprint = hashlib.sha256(json.dumps(params, sort_keys=True).encode()).hexdigest()
    params["fingerprint"] = fingerprint
    st = _Store(store, fingerprint, params) if store is not None else None

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
                finish(c, _chunk_counts(desc, centres[sl], R, restarts, seed, c))
                bar.advance(task)
        elif todo:
            workers = _run_dask(client, todo, lambda c: centres[c * chunk_size: min(M, (c + 1) * chunk_size)],
                                desc, R, restarts, seed, finish, lambda: bar.advance(task), fingerprint)
    t_sweep = time.perf_counter() - t1
    index = counts / K
    timings = dict(prepass=t_pre, sweep=t_sweep, total=time.perf_counter() - t0,
                   problems=computed[0] * K,
                   chunks=len(todo), chunks_resumed=resumed, workers=workers)
    return CapabilityMap(centres, index, R, res, rob.name, params, timings)


class _Cluster:
    """The Dask client for a call: None (serial), the caller's Client, or one made here (closed on exit)."""

    def __init__(self, client: Any) -> None:
        self.client: Any = None
        self.cluster: Any = None
        self.own = False
        if isinstance(client, str) and client in _SERIAL:
            return
        import logging

        from distributed import Client, LocalCluster

        if client is None:
            self.cluster = LocalCluster(n_workers=os.cpu_count() or 1, threads_per_worker=1, processes=True,
                                        dashboard_address=None, silence_logs=logging.ERROR)
            self.client, self.own = Client(self.cluster), True
        elif isinstance(client, str):
            try:
                self.client, self.own = Client(client, timeout="10s"), True
            except (OSError, TimeoutError, ValueError) as exc:
                raise OSError(f"scheduler: cannot connect to {client!r}: {_first_line(exc)}") from None
        else:
            self.client = client

    def __enter__(self) -> _Cluster:
        return self

    def __exit__(self, *exc: object) -> None:
        if self.own:
            self.client.close()
        if self.cluster is not None:
            self.cluster.close()


def _first_line(exc: BaseException) -> str:
    text = str(exc).strip()
    return text.splitlines()[0] if text else type(exc).__name__


def _run_dask(client: Any, todo: list[int], centres_of: Callable[[int], np.ndarray], desc: tuple, R: np.ndarray, restarts: int, seed: int, finish: Callable[[int, np.ndarray], None], advance: Callable[[], None], fingerprint: str) -> int:
    """Run the chunks ``todo`` on Dask, at most two tasks per worker in flight; returns the worker count."""
    from distributed import as_completed

    workers = max(1, len(client.scheduler_info().get("workers", {})))
    limit = 2 * workers
    pending = list(todo)
    ac = as_completed()
    futures = {}

    def submit() -> None:
        c = pending.pop(0)
        f = client.submit(_chunk_counts, desc, centres_of(c), R, restarts, seed, c,
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
