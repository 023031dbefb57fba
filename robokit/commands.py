"""The commands of the ``robokit`` command line: each runs one job through the library, writes its
file and says on stderr what it wrote. Argument parsing is in :mod:`robokit.cli`; the work is
in the modules these functions call. Errors propagate as exceptions (the CLI turns them into
one line and an exit status).
"""
from __future__ import annotations

import os
import shutil
import sys
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import ArrayLike

from robokit._io import atomic_write
from robokit.errors import InputError

if TYPE_CHECKING:
    from robokit.description.dh import DHTable
    from robokit.description.robot import Robot

__all__ = ["convert_command", "view_command", "teach_command", "workspace_command", "capability_view_command"]


def _output_file(output: str | os.PathLike[str], suffixes: tuple[str, ...]) -> Path:
    """The ``-o`` path, checked before any work: the right extension, an existing folder, not a folder."""
    out = Path(output)
    if out.suffix.lower() not in suffixes:
        raise InputError(f"-o: expected a {' or '.join(suffixes)} file, got {str(out)!r}")
    if not (out.parent if str(out.parent) else Path(".")).is_dir():
        raise InputError(f"-o: folder {str(out.parent)!r} does not exist")
    if out.is_dir():
        raise InputError(f"-o: {str(out)!r} is a folder")
    return out


def convert_command(input: str | os.PathLike[str], output: str | os.PathLike[str] | None, tip: str | None = None,
                    convention: str = "standard", **load_options: Any) -> int:
    """``robokit convert``: write ``output`` (or print a DH table); notes on stderr. Returns 0."""
    from robokit.description.convert import convert

    if output is None and Path(str(input)).suffix.lower() in (".yaml", ".yml"):
        raise InputError("-o/--output: required (e.g. -o robot.urdf)")
    text, notes = convert(input, output, tip=tip, convention=convention, **load_options)
    for note in notes:
        print(f"robokit: note: {note}", file=sys.stderr)
    if output is None:
        sys.stdout.write(text)
    else:
        print(f"wrote {output}", file=sys.stderr)
    return 0


def view_command(model: Robot | DHTable | str | os.PathLike[str], output: str | os.PathLike[str],
                 q: ArrayLike | None = None, frames: bool = False, trajectory: str | os.PathLike[str] | None = None,
                 fps: float = 30.0, tip: str | None = None) -> int:
    """The ``robokit view`` command: write the page to ``output``; return the exit status."""
    from robokit.description.robot import load
    from robokit.viz.view import load_trajectory, view_html

    out = _output_file(output, (".html", ".htm"))
    if not (fps > 0 and np.isfinite(fps)):
        raise InputError(f"--fps: expected a positive frame rate, got {fps:g}")
    if q is not None and not np.all(np.isfinite(q)):
        raise InputError("-q: contains NaN or infinite values")
    robot = load(model, tip=tip)
    Q = load_trajectory(trajectory, robot.n) if trajectory else None
    page = view_html(robot, q=q, frames=frames, trajectory=Q, fps=fps)
    atomic_write(out, page)
    print(f"wrote {out} ({len(page.encode('utf-8')) / 1e6:.1f} MB)", file=sys.stderr)
    return 0


def teach_command(model: Robot | DHTable | str | os.PathLike[str], output: str | os.PathLike[str] | None = None,
                  q: ArrayLike | None = None, open_browser: bool = True) -> int:
    """The ``robokit teach`` command: write the page to ``output`` (an .html file) and return 0.

    Without ``output`` the page goes to a new temporary file, which is opened in the web
    browser (``webbrowser``); its path is returned in the message on stdout.
    """
    import tempfile
    import webbrowser

    from robokit.description.robot import load
    from robokit.viz.teach import teach_html

    if output is not None:
        _output_file(output, (".html", ".htm"))
    robot = load(model)
    page = teach_html(robot, q=q)
    if output is not None:
        atomic_write(output, page)
        print(f"wrote {output} ({len(page.encode('utf-8')) / 1e6:.1f} MB)", file=sys.stderr)
        return 0
    fd, tmp = tempfile.mkstemp(prefix=f"robokit-teach-{robot.name}-", suffix=".html")
    import os

    os.close(fd)
    atomic_write(tmp, page)
    print(f"wrote {tmp} ({len(page.encode('utf-8')) / 1e6:.1f} MB); opening it in the browser", file=sys.stderr)
    if open_browser:
        webbrowser.open(Path(tmp).resolve().as_uri())
    return 0


def workspace_command(robot: str, output: str | os.PathLike[str], resolution: float, orientations: int = 100,
                      scheduler: str | None = None) -> int:
    """The ``robokit workspace`` command: compute the map and write ``output`` (``.npz``); return the exit status.

    The four arrays ``centres``, ``index``, ``orientations``, ``resolution`` are written
    atomically. Finished chunks go to ``OUTPUT.chunks/`` while the map is computed (an
    interrupted run started again with the same arguments resumes there); the folder is
    removed once the map is written. ``scheduler``: a Dask scheduler address
    (``tcp://host:port``), or None for a local cluster of one worker process per core.
    """
    from robokit.workspace.capability import capability_map

    out = _output_file(output, (".npz",))
    if not (np.isfinite(resolution) and resolution > 0):
        raise InputError(f"--resolution: expected a positive voxel size in m, got {resolution:g}")
    if orientations < 1:
        raise InputError(f"--orientations: expected a positive count, got {orientations}")
    if scheduler is not None and not scheduler.strip():
        raise InputError("--scheduler: empty address")
    store = out.with_name(out.name + ".chunks")
    cmap = capability_map(robot, resolution, orientations=orientations, client=scheduler, store=store)
    cmap.save(out)
    shutil.rmtree(store, ignore_errors=True)
    t = cmap.timings
    print(f"wrote {out}: {len(cmap.centres)} voxels, {len(cmap.dexterous)} dexterous (index 1), "
          f"{t['problems']} IK problems in {t['total']:.1f} s", file=sys.stderr)
    return 0


def capability_view_command(path: str | os.PathLike[str], output: str | os.PathLike[str]) -> int:
    """``robokit view MAP.npz -o OUT.html``: the meshcat page of a capability map, written atomically."""
    from robokit.workspace.plot import capability_html

    out = _output_file(output, (".html", ".htm"))
    page = capability_html(path)
    atomic_write(out, page)
    print(f"wrote {out} ({len(page.encode('utf-8')) / 1e6:.1f} MB)", file=sys.stderr)
    return 0
