"""The ``robokit`` command: argument parsing and the exit-status contract; the work is done
by the modules.

Exit status:

* 0 — success;
* 1 — a check failed (``robokit validate``);
* 2 — bad input (an :class:`robokit.errors.InputError`, or an ``OSError`` on a file the
  user named): one line on stderr starting ``robokit:``, naming the file / link / joint /
  key, no traceback, nothing written;
* 3 — any other exception, whatever raised it (a bug in robokit or a dependency): a short
  "please report" line;
  ``--debug`` shows the traceback;
* 130 — interrupted (Ctrl-C), 143 — terminated (SIGTERM); no file is left half-written and
  no viewer server outlives the command.
"""
from __future__ import annotations

import argparse
import os
import re
import signal
import sys
from types import FrameType
from typing import NoReturn, Sequence, TextIO

#: Longest message printed for an error (a value echoed back never makes a huge line).
MAX_MESSAGE = 400

EXIT_OK, EXIT_FAILED, EXIT_INPUT, EXIT_INTERNAL = 0, 1, 2, 3
EXIT_SIGINT, EXIT_SIGTERM = 130, 143


class _Parser(argparse.ArgumentParser):
    #: The values argparse reads as negative numbers, not as options: besides its own ``-2`` and ``-.5``,
    #: an exponent (``-1e-3``) and ``-inf``/``-nan`` (which ``float`` reads), so that ``--goal 1 2 -inf``
    #: reaches robokit's own check of the values and its error names the option.
    NEGATIVE_NUMBER = re.compile(r"^-(?:(?:\d+\.?\d*|\.\d+)(?:e[-+]?\d+)?|inf(?:inity)?|nan)\Z", re.IGNORECASE)

    def __init__(self, *args: object, **kwargs: object) -> None:
        super().__init__(*args, **kwargs)  # type: ignore[arg-type]
        self._negative_number_matcher = self.NEGATIVE_NUMBER

    def error(self, message: str) -> NoReturn:
        """argparse's own usage errors: one ``robokit: error:`` line (naming the subcommand), exit 2."""
        sub = self.prog[len("robokit"):].strip() if self.prog.startswith("robokit") else self.prog
        raise _UsageError(f"robokit: error: {sub + ': ' if sub else ''}{message}")


class _UsageError(Exception):
    pass


class _Terminated(BaseException):
    """SIGTERM, turned into an exception so that clean-up code runs."""


def _version() -> str:
    from importlib.metadata import PackageNotFoundError, version

    try:
        return version("robokit")
    except PackageNotFoundError:  # pragma: no cover - a source tree never installed
        return "0+unknown"


def _add_format_options(parser: argparse.ArgumentParser) -> None:
    """xacro options shared by the commands that load a robot (formats: xacro)."""
    g = parser.add_argument_group("xacro files")
    g.add_argument("--xacro-arg", action="append", default=[], metavar="NAME:=VALUE",
                   help="value of a xacro argument (repeatable)")
    g.add_argument("--package-path", action="append", default=[], metavar="DIR",
                   help="folder searched for <pkg>/package.xml for $(find pkg) and package://, and for SDFormat "
                        "model:// folders (repeatable)")
    parser.add_argument_group("MJCF, SDFormat, URDF and xacro files").add_argument(
        "--no-reflected-inertia", action="store_true",
        help="leave out the joints' reflected rotor inertia (MJCF armature; Drake's drake:rotor_inertia x "
             "drake:gear_ratio^2 of an SDFormat joint or a URDF transmission), modelled by default as MuJoCo "
             "and Drake do")


def _add_outside_meshes(parser: argparse.ArgumentParser, scene: bool = True) -> None:
    """``--allow-outside-meshes``: the robot's file (:func:`_format_options`) and, for the commands that read
    a scene file (robokit.collision.load_scene), the scene's may name mesh files anywhere (``workspace``'s
    workers rebuild the robot from its spec, which carries the flag)."""
    whose = "the robot's and the scene's" if scene else "the robot's"
    parser.add_argument("--allow-outside-meshes", action="store_true",
                        help=f"read {whose} mesh files wherever the files say (default: only inside the file's "
                             "folder, its package and the --package-path folders)")



def _format_options(args: argparse.Namespace, model: object = None) -> dict:
    """``load`` keyword arguments from --xacro-arg/--package-path, and --allow-outside-meshes for a robot
    file ``model`` whose meshes the loader confines (empty when none applies)."""
    xargs = {}
    for item in getattr(args, "xacro_arg", None) or []:
        name, sep, value = item.partition(":=")
        if not sep or not name.strip():
            raise _UsageError(f"robokit: error: --xacro-arg: expected NAME:=VALUE, got {item!r}")
        xargs[name.strip()] = value
    paths = getattr(args, "package_path", None) or []
    out = {k: v for k, v in (("xacro_args", xargs), ("package_dirs", paths)) if v}
    if getattr(args, "no_reflected_inertia", False):
        out["reflected_inertia"] = False
    if getattr(args, "allow_outside_meshes", False):
        from robokit.description.loading import file_takes

        if file_takes(model, "allow_outside_meshes"):
            out["allow_outside_meshes"] = True
    return out


def _build_parser() -> argparse.ArgumentParser:
    p = _Parser(
        prog="robokit",
        description="A robotics course's derivations for serial manipulators, checked against Pinocchio.",
        epilog="Exit status: 0 success, 1 a check failed, 2 bad input, 3 internal error.",
    )
    p.add_argument("--version", action="version", version=f"robokit {_version()}")
    p.add_argument("--debug", action="store_true", help="show the traceback of an internal error")
    sub = p.add_subparsers(dest="command", metavar="COMMAND", parser_class=_Parser)

    v = sub.add_parser("validate", help="course implementations against Pinocchio; exit 0 only if all agree")
    v.add_argument("model", nargs="?", metavar="MODEL",
                   help="only this robot (a .urdf/.xacro/.xml/.sdf/.yaml file, a shipped model or an "
                        "example-robot-data name): its kinematics, dynamics and ik rows")
    v.add_argument("--tip", help="tip frame of MODEL's chain (default: the arm's end effector, see the docs)")
    _add_format_options(v)
    _add_outside_meshes(v, scene=False)
    v.add_argument("--json", action="store_true", help="print the table as JSON")
    v.add_argument("--seed", type=int, default=0, help="random seed for the samples (default 0)")
    v.add_argument("--area", action="append", metavar="AREA",
                   help="only this area (spatial, description, kinematics, dynamics, ik, trajectory); repeatable")

    c = sub.add_parser("convert", help="any robot -> URDF (DH models), PoE JSON, DH YAML or MJCF")
    c.add_argument("input", help="a shipped model (puma560, ...), a .yaml DH file, a .urdf/.xacro/.xml/.sdf file, "
                                 "or an example-robot-data name (ur5, panda, ...)")
    c.add_argument("-o", "--output", help="output file: .urdf (a DH model's URDF), .json (PoE parameters), .yaml (DH "
                                          "table) or .xml (MJCF); without it the DH table is printed")
    c.add_argument("--tip", help="tip frame of the chain (default: the arm's end effector, see the docs)")
    c.add_argument("--convention", choices=("standard", "modified"), default="standard",
                   help="DH convention when writing a DH table (default standard)")
    _add_format_options(c)
    _add_outside_meshes(c, scene=False)

    w = sub.add_parser("view", help="write a self-contained meshcat HTML page of a model")
    w.add_argument("model", help="shipped model name, .yaml, .urdf or example-robot-data name")
    w.add_argument("-o", "--output", required=True, help="output .html file")
    w.add_argument("-q", "--q", nargs="+", type=float, default=None, help="joint configuration (rad / m)")
    w.add_argument("--tip", help="tip frame of the chain (URDF input)")
    w.add_argument("--frames", action="store_true", help="draw the DH frames and the tool frame")
    w.add_argument("--trajectory", help="a .csv/.npy file of joint configurations (one row per sample) to animate")
    w.add_argument("--fps", type=float, default=30.0, help="animation frame rate for --trajectory")
    w.add_argument("--obstacles", help="scene YAML file of obstacles to draw")
    _add_outside_meshes(w)
    w.add_argument("--robot", metavar="MODEL", help="the robot to draw with a capability map (MAP.npz); default: "
                   "the robot the map describes (a path stored in a map is never opened)")
    _add_format_options(w)

    t = sub.add_parser("teach", help="a self-contained teach-pendant page: joint sliders, 3-D view, live readouts")
    t.add_argument("model", help="shipped model name, .yaml, .urdf or example-robot-data name")
    t.add_argument("-o", "--output", help="output .html file (default: a temporary file, opened in the browser)")
    t.add_argument("--tip", help="tip frame of the chain (URDF input)")
    t.add_argument("--obstacles", help="scene YAML file of obstacles: drawn, with links in contact in red and the "
                   "minimum distance shown")
    _add_outside_meshes(t)
    _add_format_options(t)

    # capability maps (robokit.workspace)
    cm = sub.add_parser("workspace", help="capability map: per voxel, the fraction of tool orientations reachable")
    cm.add_argument("robot", help="shipped model name, .yaml, .urdf or example-robot-data name")
    cm.add_argument("--resolution", type=float, required=True, help="voxel size (m)")
    cm.add_argument("--orientations", type=int, default=100, help="number of tool orientations K (default 100)")
    cm.add_argument("--scheduler", help="Dask scheduler address (tcp://host:port); default: local worker processes")
    cm.add_argument("--dashboard", action="store_true", help="serve the local cluster's Dask dashboard on 127.0.0.1")
    cm.add_argument("--obstacles", help="scene YAML file of obstacles: count collision-free solutions only")
    cm.add_argument("--tip", help="tip frame of the chain: the tool (URDF, xacro, MJCF, SDFormat input)")
    _add_outside_meshes(cm)
    _add_format_options(cm)
    cm.add_argument("--convex", action="store_true", help="convex hulls of the robot's collision meshes "
                    "(faster, conservative); implies collision checking")
    cm.add_argument("--describe-world", action="store_true",
                    help="print the collision world and its self-collision pairs on stdout")
    cm.add_argument("-o", "--output", required=True, help="output .npz file")

    # kinematic calibration (robokit.calibration)
    cal = sub.add_parser("calibrate", help="calibrate a robot's geometry from measured tool poses or positions (CSV)")
    cal.add_argument("model", help="shipped model name, .yaml, .urdf or example-robot-data name")
    cal.add_argument("data", help="CSV with a header: q1..qn, x, y, z[, qw, qx, qy, qz] (base frame; m, rad)")
    cal.add_argument("-o", "--output", required=True, help="output .urdf (always) or .yaml (a DH arm only)")
    cal.add_argument("--tip", help="tip frame of the chain (URDF input)")
    _add_format_options(cal)
    _add_outside_meshes(cal, scene=False)
    g = sub.add_parser("codegen", help="C99 for a controller: FK, Jacobian, closed-form IK, gravity, RNEA")
    g.add_argument("model", help="shipped model name, .yaml, .urdf, .xacro, MJCF .xml or example-robot-data name")
    g.add_argument("-o", "--output", required=True, help="output folder, created if missing (NAME.h and NAME.c go there)")
    g.add_argument("--float32", action="store_true", help="float instead of double everywhere (single-precision FPUs)")
    g.add_argument("--name", help="C prefix of the functions and macros (default: the robot's name)")
    g.add_argument("--tip", help="tip frame of the chain (URDF input)")
    _add_format_options(g)
    _add_outside_meshes(g, scene=False)

    # collision-free planning (robokit.motion)
    pl = sub.add_parser("plan", help="a collision-free, time-optimal joint trajectory (RRT-Connect + TOPP-RA) to CSV")
    pl.add_argument("model", help="shipped model name, a .yaml/.urdf/.xacro/.xml/.sdf file or example-robot-data name")
    pl.add_argument("--start", nargs="+", type=float, required=True, help="start joint values (rad / m)")
    goal = pl.add_mutually_exclusive_group(required=True)
    goal.add_argument("--goal", nargs="+", type=float,
                      help="goal joint values (rad / m); for a robot of other than 6 joints also x y z roll pitch "
                           "yaw of the tip (m, rad)")
    goal.add_argument("--goal-pose", nargs=6, type=float, metavar=("X", "Y", "Z", "ROLL", "PITCH", "YAW"),
                      help="goal pose of the tip in the base frame (m, rad), for any robot")
    pl.add_argument("--obstacles", help="scene YAML file of obstacles")
    _add_outside_meshes(pl)
    pl.add_argument("--convex", action="store_true",
                    help="convex hulls of the robot's collision meshes (faster, conservative)")
    pl.add_argument("--describe-world", action="store_true",
                    help="print the collision world and its self-collision pairs on stdout")
    pl.add_argument("--vmax", type=float, default=1.0, help="joint velocity limit (rad/s, default 1)")
    pl.add_argument("--amax", type=float, default=2.0, help="joint acceleration limit (rad/s², default 2)")
    pl.add_argument("--dt", type=float, default=1 / 30, help="time step of the CSV rows (s, default 1/30)")
    pl.add_argument("--seed", type=int, default=0, help="random seed (default 0)")
    pl.add_argument("--tip", help="tip frame of the chain (URDF input)")
    pl.add_argument("-o", "--output", required=True, help="output .csv file")
    _add_format_options(pl)
    return p


def _dispatch(args: argparse.Namespace) -> int:
    if args.command == "validate":
        from robokit.validation import main as validate_main

        if args.model is None and (args.tip or _format_options(args)):
            from robokit.errors import InputError

            raise InputError("--tip, --xacro-arg, --package-path and --no-reflected-inertia apply to a MODEL")
        return validate_main(as_json=args.json, seed=args.seed, areas=args.area, model=args.model, tip=args.tip,
                             **_format_options(args, args.model))
    if args.command == "convert":
        from robokit.commands import convert_command

        return convert_command(args.input, args.output, tip=args.tip, convention=args.convention,
                               **_format_options(args, args.input))
    if args.command == "view":
        from robokit.commands import view_command

        if str(args.model).lower().endswith(".npz"):  # a capability map (robokit workspace)
            from robokit.commands import capability_view_command

            robot = args.robot
            opts = _format_options(args, robot)
            if robot is not None and (opts or args.tip):
                from robokit.description.loading import load

                robot = load(robot, tip=args.tip, **opts)
            return capability_view_command(args.model, args.output, robot=robot)
        if args.robot is not None:
            from robokit.errors import InputError

            raise InputError("--robot: applies to capability maps (MAP.npz); give the robot as MODEL")
        opts = _format_options(args, args.model)
        if opts:  # formats: a xacro robot with arguments/packages is loaded here
            from robokit.description.loading import load

            args.model = load(args.model, tip=args.tip, **opts)
        return view_command(args.model, args.output, q=args.q, frames=args.frames,
                            trajectory=args.trajectory, fps=args.fps, tip=args.tip, obstacles=args.obstacles,
                            allow_outside_meshes=args.allow_outside_meshes, package_dirs=args.package_path or None)
    if args.command == "teach":
        from robokit.commands import teach_command

        model = args.model
        opts = _format_options(args, args.model)
        if opts or args.tip:
            from robokit.description.loading import load

            model = load(args.model, tip=args.tip, **opts)
        return teach_command(model, args.output, obstacles=args.obstacles,
                             allow_outside_meshes=args.allow_outside_meshes, package_dirs=args.package_path or None)
    if args.command == "workspace":
        from robokit.commands import workspace_command

        robot = args.robot
        opts = _format_options(args, robot)
        if opts or args.tip:  # loaded here: its spec carries the options to the workers
            from robokit.description.loading import load

            robot = load(robot, tip=args.tip, **opts)
        return workspace_command(robot, args.output, args.resolution, args.orientations, args.scheduler,
                                 dashboard=args.dashboard, obstacles=args.obstacles, convex=args.convex,
                                 describe_world=args.describe_world, allow_outside_meshes=args.allow_outside_meshes)
    if args.command == "calibrate":
        from robokit.commands import calibrate_command

        return calibrate_command(args.model, args.data, args.output, tip=args.tip, **_format_options(args, args.model))
    if args.command == "codegen":
        from robokit.commands import codegen_command

        return codegen_command(args.model, args.output, float32=args.float32, name=args.name, tip=args.tip,
                               **_format_options(args, args.model))
    if args.command == "plan":
        from robokit.commands import plan_command

        opts = _format_options(args, args.model)
        opts.pop("allow_outside_meshes", None)  # plan_command takes it for the scene's meshes too
        return plan_command(args.model, args.start, args.goal, args.output, goal_pose=args.goal_pose,
                            obstacles=args.obstacles,
                            vmax=args.vmax, amax=args.amax, dt=args.dt, seed=args.seed, tip=args.tip,
                            convex=args.convex, describe_world=args.describe_world,
                            allow_outside_meshes=args.allow_outside_meshes, **opts)
    raise _UsageError(f"robokit: error: unknown command {args.command!r}")


def _one_line(exc: BaseException) -> str:
    text = str(exc).strip()
    msg = text.splitlines()[0].strip() if text else type(exc).__name__
    if len(msg) > MAX_MESSAGE:
        msg = msg[: MAX_MESSAGE - 3] + "..."
    return msg


def _is_input_error(exc: BaseException) -> bool:
    """Exit status 2 or 3 by the exception's type only: :class:`robokit.errors.InputError` (every
    deliberate check raises it) and ``OSError`` (a file the user named cannot be read or written)
    are bad input; anything else — a plain ``ValueError`` included — is a bug."""
    from robokit.errors import InputError

    return isinstance(exc, (InputError, OSError))


def _show_warning(message: Warning | str, category: type[Warning], filename: str, lineno: int,
                  file: TextIO | None = None, line: str | None = None) -> None:
    """Warnings as one line each: ``robokit: note: ...`` (robokit's own) or ``robokit: warning: ...``
    (others, and a physically impossible inertia)."""
    from robokit.errors import PhysicalityWarning, RobokitWarning

    kind = "note" if issubclass(category, RobokitWarning) and not issubclass(category, PhysicalityWarning) else "warning"
    text = " ".join(str(message).split())
    if len(text) > MAX_MESSAGE:
        text = text[: MAX_MESSAGE - 3] + "..."
    print(f"robokit: {kind}: {text}", file=sys.stderr)


def _on_sigterm(signum: int, frame: FrameType | None) -> NoReturn:
    raise _Terminated()


def main(argv: Sequence[str] | None = None) -> int:
    """Entry point of the console script; returns the exit status (see the module docstring)."""
    argv = sys.argv[1:] if argv is None else list(argv)
    debug = "--debug" in argv
    argv = [a for a in argv if a != "--debug"]  # accepted anywhere on the line
    previous = None
    try:
        previous = signal.signal(signal.SIGTERM, _on_sigterm)
    except ValueError:  # not the main thread (e.g. called from a test runner's worker thread)
        previous = None
    import warnings

    saved_showwarning = warnings.showwarning
    warnings.showwarning = _show_warning
    try:
        parser = _build_parser()
        args = parser.parse_args(argv)
        from robokit.kernels import compile_mode

        compile_mode()  # a bad ROBOKIT_COMPILE is refused before any work starts
        if args.command is None:
            parser.print_help(sys.stderr)
            return EXIT_INPUT
        return _dispatch(args)
    except _UsageError as exc:
        print(_one_line(exc), file=sys.stderr)
        return EXIT_INPUT
    except KeyboardInterrupt:
        print("robokit: interrupted", file=sys.stderr)
        return EXIT_SIGINT
    except _Terminated:
        print("robokit: terminated", file=sys.stderr)
        return EXIT_SIGTERM
    except BrokenPipeError:  # output piped into e.g. `head`, which stopped reading
        try:
            devnull = os.open(os.devnull, os.O_WRONLY)
            os.dup2(devnull, sys.stdout.fileno())
        except (OSError, ValueError):  # pragma: no cover
            pass
        return 141
    except SystemExit:
        raise
    except Exception as exc:  # noqa: BLE001 - the boundary: every exception gets one line
        if _is_input_error(exc):
            print(f"robokit: error: {_one_line(exc)}", file=sys.stderr)
            return EXIT_INPUT
        if debug:
            import traceback

            traceback.print_exc()
        print(f"robokit: internal error ({type(exc).__name__}: {_one_line(exc)}) — please report it with the "
              "command you ran; rerun with --debug for the traceback", file=sys.stderr)
        return EXIT_INTERNAL
    finally:
        warnings.showwarning = saved_showwarning
        if previous is not None:
            signal.signal(signal.SIGTERM, previous)


if __name__ == "__main__":
    sys.exit(main())
