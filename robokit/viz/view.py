"""``robokit view``: a self-contained meshcat HTML page of a model, optionally animated.

Nothing is written unless everything succeeded (the page is written atomically).
Trajectory files: ``.npy`` (a (K, n) array) or ``.csv`` (K rows of n joint values, comma
separated; lines starting with ``#`` are comments; a first row that is not numeric is taken
as a header and skipped).
"""
from __future__ import annotations

import os
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import ArrayLike
from robokit.errors import InputError

if TYPE_CHECKING:
    from robokit.description.dh import DHTable
    from robokit.description.robot import Robot


__all__ = ["view_html", "load_trajectory"]


def load_trajectory(path: str | os.PathLike[str], n: int) -> np.ndarray:
    """Read a (K, n) joint trajectory from ``.npy`` or ``.csv``; ValueError naming the file otherwise."""
    p = Path(path)
    if not p.is_file():
        raise InputError(f"--trajectory: file {str(p)!r} not found")
    try:
        if p.suffix.lower() == ".npy":
            Q = np.load(p, allow_pickle=False)
        elif p.suffix.lower() == ".csv":
            lines = [ln for ln in p.read_text(encoding="utf-8").splitlines() if ln.strip() and not ln.startswith("#")]
            rows = []
            for k, ln in enumerate(lines):
                try:
                    rows.append([float(x) for x in ln.split(",")])
                except ValueError:
                    if k == 0:
                        continue  # header
                    raise InputError(f"line {k + 1} is not numbers") from None
            Q = np.array(rows, dtype=float)
        else:
            raise InputError("expected a .npy or .csv file")
    except (OSError, ValueError, UnicodeDecodeError) as exc:
        raise InputError(f"--trajectory: cannot read {str(p)!r}: {exc}") from None
    Q = np.asarray(Q, dtype=float)
    if Q.ndim != 2 or Q.shape[1] != n or len(Q) == 0:
        raise InputError(f"--trajectory: {str(p)!r} has shape {Q.shape}; expected (K, {n}) joint values")
    if not np.all(np.isfinite(Q)):
        raise InputError(f"--trajectory: {str(p)!r} contains NaN or infinite values")
    return Q


def view_html(model: Robot | DHTable | str | os.PathLike[str], q: ArrayLike | None = None, frames: bool = False,
              trajectory: ArrayLike | None = None, fps: float = 30.0,
              tip: str | None = None) -> str:
    """The HTML page of ``model`` (anything ``robokit.load`` accepts) at ``q``, with DH frames
    and/or a (K, n) trajectory animation; the camera framed on the robot."""
    from robokit.description.robot import load
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
        scene.frame_camera()
        return scene.html()
