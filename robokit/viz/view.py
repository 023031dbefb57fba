"""``robokit view``: a self-contained meshcat HTML page of a model, optionally animated.

Nothing is written unless everything succeeded (the page is written atomically).
Trajectory files: ``.npy`` (a (K, n) array) or ``.csv`` (K rows of n joint values, comma
separated; lines starting with ``#`` are comments; a first row that is not numeric is taken
as a header and skipped; numbers as :mod:`robokit._table` reads them, every bad cell named by
line and column).
"""
from __future__ import annotations

import os
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import ArrayLike
from robokit.errors import InputError

if TYPE_CHECKING:
    from robokit.description.dh import DHTable
    from robokit.description.robot import Robot


__all__ = ["view_html", "load_trajectory", "MAX_TRAJECTORY_ROWS"]

#: Most samples (rows) a trajectory file may hold — and ``robokit plan`` writes: 10⁵ frames are 55
#: minutes at 30 fps, and the page stays below about 100 MB for a 6-joint arm.
MAX_TRAJECTORY_ROWS = 100_000
#: Largest trajectory file read (bytes).
MAX_TRAJECTORY_BYTES = 64 << 20


def load_trajectory(path: str | os.PathLike[str], n: int) -> np.ndarray:
    """Read a (K, n) joint trajectory from ``.npy`` or ``.csv`` (see the module docstring).

    Parameters
    ----------
    path : str or Path
        A regular file of at most :data:`MAX_TRAJECTORY_BYTES` bytes and
        :data:`MAX_TRAJECTORY_ROWS` rows; a ``.npy`` file must hold a real (K, n) array (its
        header is checked before the data are read).
    n : int
        Joints of the robot.

    Returns
    -------
    numpy.ndarray
        (K, n) joint values (rad / m).

    Raises
    ------
    InputError
        ``--trajectory: …`` naming the file and what was wrong (rows beyond the limit with their count).

    Examples
    --------
    >>> load_trajectory("wave.csv", 6).shape   # doctest: +SKIP
    (120, 6)
    """
    import io

    from robokit._arrays import MAX_MAGNITUDE
    from robokit._io import decode_utf8, read_input_bytes
    from robokit._table import NUMBER, number_row, table_lines

    p = Path(path)
    if not os.path.lexists(p):
        raise InputError(f"--trajectory: file {str(p)!r} not found")
    try:
        raw = read_input_bytes(p, MAX_TRAJECTORY_BYTES, "a trajectory file")
    except InputError as exc:
        raise InputError(f"--trajectory: {exc}") from None
    try:
        if p.suffix.lower() == ".npy":
            f = io.BytesIO(raw)
            version = np.lib.format.read_magic(f)
            reader = np.lib.format.read_array_header_1_0 if version == (1, 0) else np.lib.format.read_array_header_2_0
            shape, _, dtype = reader(f)
            if dtype.kind not in "fiu" or dtype.hasobject:
                raise InputError(f"expected real numbers, got dtype {dtype}")
            if len(shape) != 2 or shape[1] != n:
                raise InputError(f"has shape {shape}; expected (K, {n}) joint values")
            if shape[0] > MAX_TRAJECTORY_ROWS:
                raise InputError(f"has {shape[0]} rows; at most {MAX_TRAJECTORY_ROWS}")
            f.seek(0)
            Q = np.load(f, allow_pickle=False)
        elif p.suffix.lower() == ".csv":
            source = f"--trajectory: cannot read {str(p)!r}"
            rows: list[list[float]] = []
            for k, (line, cells) in enumerate(table_lines(decode_utf8(raw, p), source)):
                if k == 0 and not all(NUMBER.fullmatch(c) for c in cells):
                    continue  # a header
                if len(rows) >= MAX_TRAJECTORY_ROWS:
                    raise InputError(f"has more than {MAX_TRAJECTORY_ROWS} rows; at most {MAX_TRAJECTORY_ROWS}")
                if len(cells) != n:
                    raise InputError(f"{source}: line {line}: {len(cells)} values; expected (K, {n}) joint values")
                rows.append(number_row(cells, source, line))
            Q = np.array(rows, dtype=float).reshape(len(rows), n)
        else:
            raise InputError("expected a .npy or .csv file")
    except InputError as exc:
        msg = str(exc)
        raise InputError(msg if msg.startswith("--trajectory") else f"--trajectory: {str(p)!r} {msg}"
                         if msg.startswith("has ") else f"--trajectory: cannot read {str(p)!r}: {msg}") from None
    except (OSError, ValueError, EOFError) as exc:
        raise InputError(f"--trajectory: cannot read {str(p)!r}: {exc}") from None
    Q = np.asarray(Q, dtype=float)
    if Q.ndim != 2 or Q.shape[1] != n or len(Q) == 0:
        raise InputError(f"--trajectory: {str(p)!r} has shape {Q.shape}; expected (K, {n}) joint values")
    if not np.all(np.isfinite(Q)):
        raise InputError(f"--trajectory: {str(p)!r} contains NaN or infinite values")
    if np.abs(Q).max() > MAX_MAGNITUDE:
        raise InputError(f"--trajectory: {str(p)!r} holds {np.abs(Q).max():g}, out of range (at most "
                         f"{MAX_MAGNITUDE:g} in magnitude; rad, m)")
    return Q


def view_html(model: Robot | DHTable | str | os.PathLike[str], q: ArrayLike | None = None, frames: bool = False,
              trajectory: ArrayLike | None = None, fps: float = 30.0,
              tip: str | None = None, obstacles: Any = None) -> str:
    """The self-contained HTML page of ``robokit view``: the robot, framed, on a ground grid.

    Parameters
    ----------
    model : robokit.Robot, DHTable, str or path
        Anything ``robokit.load`` accepts.
    q : array_like, shape (n,), optional
        The configuration shown (rad / m; default zero).
    frames : bool
        Draw the DH frames (or the joint frames) and the tool frame as labelled triads (the
        labels are camera-facing sprites).
    trajectory : array_like, shape (K, n), optional
        Joint configurations to animate (rad / m).
    fps : float
        Animation frame rate (samples per second).
    tip : str, optional
        Tip frame of the chain (URDF input).
    obstacles : sequence of robokit.collision shapes, optional
        Box, Sphere, Cylinder, Mesh obstacles drawn at their poses (base frame).

    Returns
    -------
    str
        The HTML page (meshcat's static page, meshes embedded; no server needed).

    Examples
    --------
    >>> page = view_html("puma560", frames=True)   # doctest: +SKIP
    """
    from robokit.description.loading import load
    from robokit.viz.scene import Scene

    robot = load(model, tip=tip)
    if q is not None:
        q = np.asarray(q, dtype=float)
        if q.shape != (robot.n,):
            raise InputError(f"-q: {robot.name} has {robot.n} joints, got {q.size} values")
    with Scene(robot) as scene:
        scene.show(q)
        if frames:
            scene.frames()
        if trajectory is not None:
            scene.animate(trajectory, fps=fps)
        if obstacles:
            scene.obstacles(obstacles)
        scene.frame_camera()
        return scene.html()
