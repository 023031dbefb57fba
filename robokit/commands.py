"""The commands of the ``robokit`` command line: each runs one job through the library, writes its
file and says on stderr what it wrote. Argument parsing is in :mod:`robokit.cli`; the work is
in the modules these functions call. Errors propagate as exceptions (the CLI turns them into
one line and an exit status).

The parameters of the commands that read a scene file (``obstacles``, ``--obstacles``):

* ``convex`` (``--convex``) — check the convex hulls of the robot's collision meshes instead of
  the meshes (faster, conservative);
* ``describe_world`` (``--describe-world``) — print the world and its self-collision pairs on
  stdout before the work starts;
* ``allow_outside_meshes`` (``--allow-outside-meshes``) — read the scene's mesh files wherever
  it says; by default they must be in the scene file's folder (or in a folder given with
  ``--package-path``, for the commands that take it).
"""
from __future__ import annotations

import os
import sys
from pathlib import Path
from typing import TYPE_CHECKING, Any, Mapping, Sequence

import numpy as np
from numpy.typing import ArrayLike

from robokit._arrays import MAX_MAGNITUDE
from robokit._io import atomic_write, check_not_an_input, check_output_file, check_output_folder
from robokit.errors import InputError

if TYPE_CHECKING:
    from robokit.description.dh import DHTable
    from robokit.description.robot import Robot

__all__ = ["convert_command", "view_command", "teach_command", "workspace_command", "capability_view_command",
           "calibrate_command", "codegen_command", "plan_command"]


def _output_file(output: str | os.PathLike[str], suffixes: tuple[str, ...]) -> Path:
    """The ``-o`` path, checked before any work: the right extension, an existing folder, not a folder."""
    out = Path(output)
    if out.suffix.lower() not in suffixes:
        raise InputError(f"-o: expected a {' or '.join(suffixes)} file, got {str(out)!r}")
    return check_output_file(out, "-o")


def _degrees_note(robot: Any, q: ArrayLike, flag: str, state: bool = False) -> None:
    """A ``robokit: note:`` (a :class:`~robokit.errors.DegreesWarning`) when joint values typed on the
    command line (``q`` (n,)), or the rows of a file it names (``q`` (N, n)), look like degrees (docs/conventions.md: beyond a full turn and past the limits).
    ``flag`` names where they came from: the option, or the data file.

    The library's own check stays silent here — the values pass through robokit's commands, which
    it takes for values robokit computed — although they are the user's, typed after ``flag``."""
    import warnings

    from robokit.errors import DegreesWarning

    values = np.asarray(q, dtype=float)
    if values.shape[-1:] != (robot.n,) or values.ndim > 2 or not np.all(np.isfinite(values)):
        return  # the shape and finiteness errors are reported where the values are used
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", DegreesWarning)
        looks = robot.check_radians(values, flag, state=state)
    if looks:
        warnings.warn(f"{flag}: values beyond a full turn and past the joint limits of {robot.name}: this looks like "
                      f"degrees; robokit takes radians (45 degrees is 0.785)", DegreesWarning, stacklevel=2)


def convert_command(input: str | os.PathLike[str], output: str | os.PathLike[str] | None, tip: str | None = None,
                    convention: str = "standard", **load_options: Any) -> int:
    """``robokit convert IN -o OUT``: convert a robot description; notes on stderr.

    DH YAML → URDF, URDF (or an example-robot-data name) → PoE JSON, DH YAML, MJCF; without ``output``
    the DH table is printed (a DH model's own, or the one extracted from a URDF).

    Parameters
    ----------
    input : str or path-like
        A DH ``.yaml``, ``.urdf``, xacro or MJCF file, or a model name ``robokit.load`` accepts.
    output : str, path-like or None
        The file to write (its suffix chooses the format), written atomically; None prints the DH table
        on stdout (a DH model's own table; a URDF's extracted one, with its residual).
    tip : str, optional
        Tip frame of the chain (default: the last link).
    convention : {"standard", "modified"}
        DH convention of an extracted table.
    **load_options
        Passed to the loader (e.g. ``package_dirs``, ``xacro_args``).

    Returns
    -------
    int
        The exit status, 0 (errors raise).
    """
    from robokit.description.convert import convert

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
                 fps: float = 30.0, tip: str | None = None, obstacles: str | os.PathLike[str] | None = None,
                 allow_outside_meshes: bool = False,
                 package_dirs: Sequence[str | os.PathLike[str]] | None = None) -> int:
    """``robokit view MODEL -o OUT.html``: write a self-contained meshcat page of the model.

    Parameters
    ----------
    model : Robot, DHTable, str or path-like
        Anything ``robokit.load`` accepts.
    output : str or path-like
        The ``.html`` page to write (atomically).
    q : (n,) array_like, optional
        The configuration drawn (rad, m); default the zero configuration.
    frames : bool
        Draw the DH / joint frames.
    trajectory : str or path-like, optional
        A CSV or ``.npy`` file of configurations (K, n) to animate.
    fps : float
        Frames per second of the animation (> 0).
    tip : str, optional
        Tip frame.
    obstacles : str or path-like, optional
        A scene YAML file whose obstacles are drawn.
    allow_outside_meshes : bool
        As in the module docstring.
    package_dirs : sequence of str or path-like, optional
        More folders the scene's mesh files may be in (``--package-path``).

    Returns
    -------
    int
        The exit status, 0 (errors raise).
    """
    from robokit.description.loading import load
    from robokit.viz.view import load_trajectory, view_html

    out = _output_file(output, (".html", ".htm"))
    if not (fps > 0 and np.isfinite(fps)):
        raise InputError(f"--fps: expected a positive frame rate, got {fps:g}")
    if q is not None and not np.all(np.isfinite(q)):
        raise InputError("-q: contains NaN or infinite values")
    robot = load(model, tip=tip)
    if q is not None:
        _degrees_note(robot, q, "-q")
    Q = load_trajectory(trajectory, robot.n) if trajectory else None
    if Q is not None:
        _degrees_note(robot, Q, "--trajectory", state=True)  # its rows, as the file gives them
    obs = None
    if obstacles:
        from robokit.collision import load_scene

        obs = load_scene(obstacles, package_dirs=package_dirs, allow_outside_meshes=allow_outside_meshes)[0]
    page = view_html(robot, q=q, frames=frames, trajectory=Q, fps=fps, obstacles=obs)
    atomic_write(out, page)
    print(f"wrote {out} ({len(page.encode('utf-8')) / 1e6:.1f} MB)", file=sys.stderr)
    return 0


def teach_command(model: Robot | DHTable | str | os.PathLike[str], output: str | os.PathLike[str] | None = None,
                  q: ArrayLike | None = None, open_browser: bool = True,
                  obstacles: str | os.PathLike[str] | None = None, allow_outside_meshes: bool = False,
                  package_dirs: Sequence[str | os.PathLike[str]] | None = None) -> int:
    """The ``robokit teach`` command: write the teach page (:func:`robokit.viz.teach.teach_html`).

    Parameters
    ----------
    model : robokit.Robot, DHTable, str or path
        Anything ``robokit.load`` accepts.
    output : str or path, optional
        The ``.html``/``.htm`` file to write (atomically). Without it the page goes to a new
        temporary file, which is opened in the web browser (``webbrowser``); its path is in
        the message on stderr.
    q : array_like, shape (n,), optional
        Initial joint values (rad / m).
    open_browser : bool
        Open the temporary page (only without ``output``).
    obstacles : str or path, optional
        A scene YAML file (as ``robokit plan`` reads it): the page draws its obstacles and
        shows the collision state (links in contact red, the minimum distance).
    allow_outside_meshes : bool
        As in the module docstring (``package_dirs`` are the folders given; the page embeds the
        meshes).
    package_dirs : sequence of str or path-like, optional
        More folders the scene's mesh files may be in (``--package-path``).

    Returns
    -------
    int
        The exit status, 0 (bad input raises ``InputError``).

    Examples
    --------
    >>> teach_command("puma560", "puma.html", obstacles="scene.yaml")   # doctest: +SKIP
    0
    """
    import tempfile
    import webbrowser

    from robokit._names import safe_stem
    from robokit._optional import require
    from robokit.description.loading import load
    from robokit.viz.teach import teach_html

    if output is not None:
        _output_file(output, (".html", ".htm"))
    robot = load(model)
    obs, padding = None, 0.0
    if obstacles:
        from robokit.collision import load_scene

        obs, padding = load_scene(obstacles, package_dirs=package_dirs, allow_outside_meshes=allow_outside_meshes)
    require("meshcat", "the teach pendant")  # the page's own extra first: one line when it is missing
    from robokit.codegen.wasm import wasm_module

    wasm = wasm_module(robot).wasm  # the page computes with the module: without ziglang, one line naming the extra
    page = teach_html(robot, q=q, obstacles=obs, padding=padding, wasm=wasm)
    if output is not None:
        atomic_write(output, page)
        print(f"wrote {output} ({len(page.encode('utf-8')) / 1e6:.1f} MB)", file=sys.stderr)
        return 0
    fd, tmp = tempfile.mkstemp(prefix=f"robokit-teach-{safe_stem(robot.name)}-", suffix=".html")
    os.close(fd)
    atomic_write(tmp, page)
    print(f"wrote {tmp} ({len(page.encode('utf-8')) / 1e6:.1f} MB); opening it in the browser", file=sys.stderr)
    if open_browser:
        webbrowser.open(Path(tmp).resolve().as_uri())
    return 0


def _world(robot: Any, obstacles: str | os.PathLike[str] | None, convex: bool, describe: bool,
           allow_outside_meshes: bool = False) -> Any:
    """The collision world of a command: the scene file's obstacles and padding, meshes or hulls;
    its description printed on stdout when ``describe`` (``--describe-world``)."""
    from robokit.collision import World, load_scene

    obs, padding = load_scene(obstacles, allow_outside_meshes=allow_outside_meshes) if obstacles else ([], 0.0)
    world = World(robot, obs, padding, convex=convex)
    if describe:
        print(world.describe())
    return world


def workspace_command(robot: str | Robot, output: str | os.PathLike[str], resolution: float, orientations: int = 100,
                      scheduler: str | None = None, dashboard: bool = False,
                      obstacles: str | os.PathLike[str] | None = None, convex: bool = False,
                      describe_world: bool = False, allow_outside_meshes: bool = False) -> int:
    """``robokit workspace ROBOT --resolution R -o MAP.npz``: compute a capability map and write it.

    The four arrays ``centres``, ``index``, ``orientations``, ``resolution`` are written
    atomically. Finished chunks go to ``OUTPUT.chunks/`` while the map is computed (an
    interrupted run started again with the same arguments resumes there); the folder is
    removed once the map is written (:mod:`robokit.workspace.store`: only a folder robokit
    made, holding only its chunk files, is ever used or removed).

    Parameters
    ----------
    robot : str or Robot
        A model name or file ``robokit.load`` accepts, or a robot it loaded (the command line loads a
        file given with ``--tip``, xacro arguments, package folders or ``--allow-outside-meshes``
        itself; the workers rebuild it from its spec, which carries them).
    output : str or path-like
        The ``.npz`` file to write.
    resolution : float
        Voxel edge length (m, > 0).
    orientations : int
        Number K of tool orientations tried per voxel (≥ 1).
    scheduler : str, optional
        A Dask scheduler address (``tcp://host:port``), or None for a local cluster of one worker
        process per core (TLS with per-run credentials).
    dashboard : bool
        Serve the local cluster's dashboard on 127.0.0.1.
    obstacles : str or path-like, optional
        A scene YAML file: only collision-free solutions count (self-collisions and the scene's
        obstacles).
    convex, describe_world, allow_outside_meshes : bool
        As in the module docstring.

    Returns
    -------
    int
        The exit status, 0 once the map is written and its chunk folder removed (errors raise).
    """
    from robokit.description.loading import load
    from robokit.workspace.capability import capability_map
    from robokit.workspace.store import remove_store

    out = _output_file(output, (".npz",))
    if not (np.isfinite(resolution) and resolution > 0):
        raise InputError(f"--resolution: expected a positive voxel size in m, got {resolution:g}")
    if orientations < 1:
        raise InputError(f"--orientations: expected a positive count, got {orientations}")
    if scheduler is not None and not scheduler.strip():
        raise InputError("--scheduler: empty address")
    store = out.with_name(out.name + ".chunks")
    world = None
    if obstacles or convex or describe_world:
        rob = load(robot)
        world = _world(rob, obstacles, convex, describe_world, allow_outside_meshes)
        robot = rob
        if not (obstacles or convex):  # --describe-world alone prints, it does not change the map
            print("(not used for the map: give --obstacles or --convex for collision-free counts)")
            world = None
    cmap = capability_map(robot, resolution, orientations=orientations, client=scheduler, store=store,
                          dashboard=dashboard, world=world)
    cmap.save(out)
    remove_store(store)  # only robokit's own marker and chunk files are ever deleted
    t = cmap.timings
    print(f"wrote {out}: {len(cmap.centres)} voxels, {len(cmap.dexterous)} dexterous (index 1), "
          f"{t['problems']} IK problems in {t['total']:.1f} s", file=sys.stderr)
    return 0


def capability_view_command(path: str | os.PathLike[str], output: str | os.PathLike[str],
                            robot: Any = None) -> int:
    """``robokit view MAP.npz [--robot MODEL] -o OUT.html``: the meshcat page of a capability map,
    written atomically.

    Parameters
    ----------
    path : str or path-like
        The ``.npz`` map written by ``robokit workspace``.
    output : str or path-like
        The ``.html`` page to write.
    robot : optional
        The robot drawn with the map (anything ``robokit.load`` accepts); default the one the map
        describes without naming a file (:mod:`robokit.workspace.map_robot`), else none (with a note).

    Returns
    -------
    int
        The exit status, 0 (errors raise).
    """
    from robokit.workspace.plot import capability_html

    out = _output_file(output, (".html", ".htm"))
    page = capability_html(path, robot=robot)
    atomic_write(out, page)
    print(f"wrote {out} ({len(page.encode('utf-8')) / 1e6:.1f} MB)", file=sys.stderr)
    return 0


def calibrate_command(model: str | os.PathLike[str], data: str | os.PathLike[str], output: str | os.PathLike[str],
                      tip: str | None = None, **load_options: Any) -> int:
    """``robokit calibrate MODEL DATA.csv -o OUT.urdf|OUT.yaml``: calibrate, print the RMS before and
    after (stdout), write the calibrated robot atomically.

    A URDF is always possible (the calibrated joint placements, the nominal inertias); a DH YAML
    only when a DH table reproduces the calibrated arm to 1e-9 (checked after writing it to text
    and reading it back), else ``InputError`` saying to write a URDF. Nothing is written on error.

    Parameters
    ----------
    model : str or path-like
        The nominal robot (anything ``robokit.load`` accepts).
    data : str or path-like
        The CSV: a header row, columns ``q1..qn, x, y, z`` (m) optionally followed by ``qw, qx, qy, qz``.
    output : str or path-like
        ``.urdf`` or ``.yaml`` file to write.
    tip : str, optional
        Tip frame of the nominal robot.
    **load_options
        Passed to the loader.

    Returns
    -------
    int
        The exit status, 0 (errors raise).
    """
    from robokit.calibration import calibrate, read_calibration_csv
    from robokit.description import load
    from robokit.description.save import robot_text

    out = _output_file(output, (".urdf", ".yaml", ".yml"))
    check_not_an_input(out, model, data, what="-o")
    robot = load(model, tip=tip, **load_options)
    q, measured = read_calibration_csv(data, robot.n, robot.qlim)
    _degrees_note(robot, q, str(data), state=True)  # the file's joint columns, as it gives them
    res = calibrate(robot, q, measured)
    text = robot_text(res.robot, out.suffix, "-o")
    kind = "positions" if measured.ndim == 2 else "poses"
    print(f"calibrated {robot.name} from {len(q)} measured {kind}")
    for label, rms in (("before:", res.rms_before), ("after: ", res.rms_after)):
        rot = "" if rms.orientation is None else f" / {1e3 * rms.orientation:.4g} mrad"
        print(f"RMS {label} {1e3 * rms:.4g} mm{rot}")
    print(str(res.identifiability))
    atomic_write(out, text)
    print(f"wrote {out}", file=sys.stderr)
    return 0


def codegen_command(model: str | os.PathLike[str], output: str | os.PathLike[str], float32: bool = False,
                    name: str | None = None, tip: str | None = None, **load_options: Any) -> int:
    """``robokit codegen MODEL -o DIR``: write ``NAME.h`` and ``NAME.c`` into the folder ``output``.

    The folder and the name are checked before the robot is loaded, and both files are written
    only once both are generated (nothing is written on bad input).

    Parameters
    ----------
    model : str or path-like
        Anything ``robokit.load`` accepts.
    output : str or path-like
        The output folder; created (parents too) once the source is generated.
    float32 : bool
        Emit ``float`` instead of ``double``.
    name : str, optional
        The C identifier prefix (default: the robot's name, made an identifier).
    tip : str, optional
        Tip frame.
    **load_options
        Passed to the loader.

    Returns
    -------
    int
        The exit status, 0 (errors raise).
    """
    from robokit.codegen import c_name, generate_c, write_c
    from robokit.description import load

    out = check_output_folder(output)  # created by write_c, once the source is generated
    if name is not None:
        c_name("", name)  # checks the identifier
    robot = load(model, tip=tip, **load_options)
    src = generate_c(robot, name=name, float32=float32)
    h_path, c_path = write_c(src, out)
    ik = "with" if src.has_ik else "without"
    print(f"wrote {h_path} and {c_path} ({robot.n} joints, {ik} closed-form IK)", file=sys.stderr)
    return 0


def _check_rows(duration: float, dt: float, bound: str = "") -> None:
    """Refuse a ``robokit plan`` output of more rows than a trajectory file may hold
    (:data:`robokit.viz.view.MAX_TRAJECTORY_ROWS`), from the duration, before any row is made."""
    from robokit.viz.view import MAX_TRAJECTORY_ROWS

    rows = duration / dt + 2.0
    if not rows <= MAX_TRAJECTORY_ROWS:
        raise InputError(f"--dt/--vmax/--amax: the trajectory would last {bound}{duration:.4g} s, {bound}{rows:.4g} rows of "
                         f"{dt:g} s; robokit writes at most {MAX_TRAJECTORY_ROWS} (what robokit view --trajectory "
                         "reads): raise --dt, --vmax or --amax")


def plan_command(model: str | os.PathLike[str], start: ArrayLike, goal: ArrayLike | None,
                 output: str | os.PathLike[str], obstacles: str | os.PathLike[str] | None = None, vmax: float = 1.0, amax: float = 2.0,
                 dt: float = 1 / 30, seed: int = 0, tip: str | None = None, convex: bool = False,
                 describe_world: bool = False, allow_outside_meshes: bool = False,
                 goal_pose: ArrayLike | None = None, *, xacro_args: Mapping[str, str] | None = None,
                 package_dirs: Sequence[str | os.PathLike[str]] | None = None, reflected_inertia: bool = True) -> int:
    """``robokit plan MODEL --start … --goal …|--goal-pose … [--obstacles scene.yaml] [--convex] -o traj.csv``: plan a
    collision-free motion, retime it and write it as a CSV.

    The CSV has a header ``q1,…,qn`` and one row per ``dt`` seconds of the retimed trajectory
    (comment lines give the duration and dt), so ``robokit view MODEL --trajectory traj.csv
    --fps 1/dt`` plays it in real time. It has at most
    :data:`robokit.viz.view.MAX_TRAJECTORY_ROWS` rows: the count is estimated before planning
    (a joint goal: ``max |Δq| / vmax / dt``) and computed from the duration before any row is
    made, and a larger one is refused.

    Parameters
    ----------
    model : str or path-like
        Anything ``robokit.load`` accepts.
    start : (n,) array_like
        Start configuration (rad, m).
    goal : (n,) or (6,) array_like, or None
        Goal configuration, or (a robot of other than 6 joints) x y z roll pitch yaw (m, rad) of the
        tip pose in the base frame; None with ``goal_pose``.
    output : str or path-like
        The ``.csv`` file to write.
    obstacles : str or path-like, optional
        A scene YAML file (obstacles and padding).
    vmax, amax : float
        Joint velocity (rad/s) and acceleration (rad/s²) limits of the retiming.
    dt : float
        Sample period of the CSV (s, > 0).
    seed : int
        Seed of the sampling planner.
    tip : str, optional
        Tip frame.
    convex, describe_world, allow_outside_meshes : bool
        As in the module docstring.
    goal_pose : (6,) array_like, optional
        x y z roll pitch yaw (m, rad; URDF's fixed-axis roll, pitch, yaw) of the tip pose in the base
        frame, for any robot (``--goal-pose``); instead of ``goal``.
    xacro_args, package_dirs, reflected_inertia : optional
        Passed to ``robokit.load`` when given (``--xacro-arg``, ``--package-path``,
        ``--no-reflected-inertia``), as every command that loads a robot takes them.

    Returns
    -------
    int
        The exit status, 0 once the CSV is written (errors raise).
    """
    from robokit.collision import pose_from_xyz_rpy
    from robokit.description.loading import file_takes, load
    from robokit.errors import InputError
    from robokit.motion import plan
    from robokit.motion.plan import MAX_SEED

    out = _output_file(output, (".csv",))
    for flag, v, unit in (("--dt", dt, "s"), ("--vmax", vmax, "rad/s"), ("--amax", amax, "rad/s²")):
        if not (np.isfinite(v) and 0 < v <= MAX_MAGNITUDE):
            raise InputError(f"{flag}: expected a positive number of at most {MAX_MAGNITUDE:g} {unit}, got {v:g}")
    if not 0 <= seed <= MAX_SEED:
        raise InputError(f"--seed: expected an integer from 0 to {MAX_SEED}, got {seed}")
    # the flag reads the robot file's meshes too, where its format takes it (False means "not given")
    robot = load(model, tip=tip, allow_outside_meshes=allow_outside_meshes and file_takes(model, "allow_outside_meshes"),
                 xacro_args=xacro_args, package_dirs=package_dirs, reflected_inertia=reflected_inertia)
    q0 = np.asarray(start, dtype=float)
    if q0.shape != (robot.n,):
        raise InputError(f"--start: expected {robot.n} joint values for {robot.name}, got {q0.size}")
    if not np.all(np.isfinite(q0)):
        raise InputError("--start: contains NaN or infinite values")
    if (goal is None) == (goal_pose is None):
        raise InputError("--goal/--goal-pose: give one of them (joint values, or x y z roll pitch yaw of the tip)")
    flag = "--goal" if goal_pose is None else "--goal-pose"
    g = np.asarray(goal if goal_pose is None else goal_pose, dtype=float)
    if not np.all(np.isfinite(g)):
        raise InputError(f"{flag}: contains NaN or infinite values")
    if goal_pose is not None:
        if g.shape != (6,):
            raise InputError(f"--goal-pose: expected x y z roll pitch yaw, got {g.size} numbers")
        target: np.ndarray = pose_from_xyz_rpy(g[:3], g[3:])
    elif g.shape == (robot.n,):
        target = g
    elif g.shape == (6,):
        target = pose_from_xyz_rpy(g[:3], g[3:])
    else:
        raise InputError(f"--goal: expected {robot.n} joint values or x y z roll pitch yaw (--goal-pose), "
                         f"got {g.size} numbers")
    _degrees_note(robot, q0, "--start", state=True)
    if target.shape == (robot.n,):  # a joint goal: no motion is shorter than max |Δq| / vmax
        _degrees_note(robot, target, "--goal", state=True)
        _check_rows(float(np.max(np.abs(target - q0))) / vmax, dt, "at least ")
    world = _world(robot, obstacles, convex, describe_world, allow_outside_meshes)
    try:
        tr = plan(robot, q0, target, world, vmax=vmax, amax=amax, seed=seed)
    except InputError as exc:  # plan() names its arguments q_start and goal: name the options typed
        msg = str(exc)
        for name, option in (("q_start: ", "--start: "), ("goal: ", f"{flag}: ")):
            if msg.startswith(name):
                raise InputError(option + msg[len(name):]) from None
        raise
    _check_rows(float(tr.t[-1]), dt)
    t = np.arange(0.0, tr.t[-1], dt)
    t = np.r_[t, tr.t[-1]] if t[-1] < tr.t[-1] else t
    Q = np.column_stack([np.interp(t, tr.t, tr.q[:, j]) for j in range(robot.n)])
    lines = [f"# robokit plan {robot.name}: duration {tr.t[-1]:.6g} s, one row per {dt:.6g} s",
             ",".join(f"q{j + 1}" for j in range(robot.n))]
    lines += [",".join(f"{x:.10g}" for x in row) for row in Q]
    atomic_write(out, "\n".join(lines) + "\n")
    print(f"wrote {out}: {len(Q)} rows, {tr.t[-1]:.3f} s, {len(tr.info['waypoints'])} waypoints "
          f"after shortcutting", file=sys.stderr)
    return 0
