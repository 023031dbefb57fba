"""``robokit view``: a self-contained meshcat HTML page of a model, optionally animated.

Nothing is written unless everything succeeded (the page is written atomically).
Trajectory files: ``.npy`` (a (K, n) array) or ``.csv`` (K rows of n joint values, comma
separated; lines starting with ``#`` are comments; a first row that is not numeric is taken
as a header and skipped).
"""
from __future__ import annotations

import os
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import ArrayLike

if TYPE_CHECKING:
    from robokit.description.dh import DHTable
    from robokit.description.robot import Robot


__all__ = ["view_html", "load_trajectory", "MAX_TRAJECTORY_ROWS"]

#: Most configurations a ``--trajectory`` file may hold (an hour at 30 frames per second is 108 000).
MAX_TRAJECTORY_ROWS = 200_000


def _npy_shape(path: Path) -> tuple[int, ...]:
    """The shape a ``.npy`` file declares, checked from its header before anything is loaded:
    a real-number dtype and header plus data exactly the file's size (ValueError otherwise)."""
    import stat

    st = os.stat(path)
    if not stat.S_ISREG(st.st_mode):
        raise ValueError("not a regular file")
    with open(path, "rb") as f:
        version = np.lib.format.read_magic(f)
        if version == (1, 0):
            shape, _, dtype = np.lib.format.read_array_header_1_0(f, max_header_size=10_000)
        else:
            shape, _, dtype = np.lib.format.read_array_header_2_0(f, max_header_size=10_000)
        start = f.tell()
    if dtype.hasobject or dtype.kind not in "fiu" or dtype.fields is not None:
        raise ValueError(f"dtype {dtype.str!r}: expected real numbers")
    if start + int(np.prod(shape, dtype=object)) * dtype.itemsize != st.st_size:
        raise ValueError(f"its header declares shape {tuple(shape)}, which does not match the file's size")
    return tuple(shape)


def load_trajectory(path: str | os.PathLike[str], n: int) -> np.ndarray:
    """Read a (K, n) joint trajectory from ``.npy`` or ``.csv``; ValueError naming the file otherwise.

    At most :data:`MAX_TRAJECTORY_ROWS` configurations; a ``.npy`` file's header (shape,
    dtype, size) is checked before its data are loaded.
    """
    p = Path(path)
    if not p.is_file():
        raise ValueError(f"--trajectory: file {str(p)!r} not found")
    try:
        if p.suffix.lower() == ".npy":
            shape = _npy_shape(p)
            if len(shape) != 2 or shape[1] != n or not 0 < shape[0] <= MAX_TRAJECTORY_ROWS:
                raise ValueError(f"shape {shape}; expected (K, {n}) joint values with 1 ≤ K ≤ {MAX_TRAJECTORY_ROWS}")
            Q = np.load(p, allow_pickle=False)
        elif p.suffix.lower() == ".csv":
            lines = [ln for ln in p.read_text(encoding="utf-8").splitlines() if ln.strip() and not ln.startswith("#")]
            if len(lines) > MAX_TRAJECTORY_ROWS + 1:
                raise ValueError(f"{len(lines)} rows; at most {MAX_TRAJECTORY_ROWS} configurations")
            rows = []
            for k, ln in enumerate(lines):
                try:
                    rows.append([float(x) for x in ln.split(",")])
                except ValueError:
                    if k == 0:
                        continue  # header
                    raise ValueError(f"line {k + 1} is not numbers") from None
            Q = np.array(rows, dtype=float)
        else:
            raise ValueError("expected a .npy or .csv file")
    except (OSError, ValueError, UnicodeDecodeError) as exc:
        raise ValueError(f"--trajectory: cannot read {str(p)!r}: {exc}") from None
    Q = np.asarray(Q, dtype=float)
    if Q.ndim != 2 or Q.shape[1] != n or len(Q) == 0:
        raise ValueError(f"--trajectory: {str(p)!r} has shape {Q.shape}; expected (K, {n}) joint values")
    if not np.all(np.isfinite(Q)):
        raise ValueError(f"--trajectory: {str(p)!r} contains NaN or infinite values")
    return Q


def view_html(model: Robot | DHTable | str | os.PathLike[str], q: ArrayLike | None = None, frames: bool = False,
              trajectory: ArrayLike | None = None, fps: float = 30.0,
              tip: str | None = None, obstacles: Any = None) -> str:
    """The HTML page of ``model`` (anything ``robokit.load`` accepts) at ``q``, with DH frames
    and/or a (K, n) trajectory animation, and collision ``obstacles`` (robokit.collision
    shapes) drawn at their poses; the camera framed on the robot."""
    from robokit.description.loading import load
    from robokit.viz.scene import Scene

    robot = load(model, tip=tip)
    if q is not None:
        q = np.asarray(q, dtype=float)
        if q.shape != (robot.n,):
            raise ValueError(f"-q: {robot.name} has {robot.n} joints, got {q.size} values")
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
