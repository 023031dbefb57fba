"""The ``robokit`` command: argument parsing only; the work is done by the modules.

Exit status: 0 success, 1 a check failed, 2 bad input (one line on stderr, no traceback,
nothing half-written).
"""
from __future__ import annotations

import argparse
import sys


class _Parser(argparse.ArgumentParser):
    def error(self, message):  # argparse's own usage errors: one line, exit 2
        raise _UsageError(f"{self.prog}: {message}")


class _UsageError(Exception):
    pass


def _build_parser() -> argparse.ArgumentParser:
    p = _Parser(prog="robokit", description="Course robotics derivations, checked against Pinocchio.")
    sub = p.add_subparsers(dest="command", required=True, parser_class=_Parser)

    v = sub.add_parser("validate", help="course implementations against Pinocchio; exit 0 only if all agree")
    v.add_argument("--json", action="store_true", help="print the table as JSON")
    v.add_argument("--seed", type=int, default=0, help="random seed for the samples (default 0)")

    c = sub.add_parser("convert", help="DH YAML -> URDF, or URDF/example-robot-data name -> PoE JSON or DH YAML")
    c.add_argument("input", help="a .yaml DH file, a .urdf file, or an example-robot-data name (ur5, panda, ...)")
    c.add_argument("-o", "--output", help="output file: .urdf, .json (PoE parameters) or .yaml (DH table)")
    c.add_argument("--tip", help="tip frame of the chain (default: the last link of the chain)")
    c.add_argument("--convention", choices=("standard", "modified"), default="standard",
                   help="DH convention when writing a DH table (default standard)")

    w = sub.add_parser("view", help="write a self-contained meshcat HTML page of a model")
    w.add_argument("model", help="shipped model name, .yaml, .urdf or example-robot-data name")
    w.add_argument("-o", "--output", required=True, help="output .html file")
    w.add_argument("-q", "--q", nargs="+", type=float, default=None, help="joint configuration (rad / m)")
    w.add_argument("--frames", action="store_true", help="draw the DH frames and the tool frame")
    w.add_argument("--trajectory", help="a .csv/.npy file of joint configurations (one row per sample) to animate")
    w.add_argument("--fps", type=float, default=30.0, help="animation frame rate for --trajectory")

    t = sub.add_parser("teach", help="a self-contained teach-pendant page: joint sliders, 3-D view, live readouts")
    t.add_argument("model", help="shipped model name, .yaml, .urdf or example-robot-data name")
    t.add_argument("-o", "--output", help="output .html file (default: a temporary file, opened in the browser)")
    return p


def _dispatch(args) -> int:
    if args.command == "validate":
        from robokit.validate import main as validate_main

        return validate_main(as_json=args.json, seed=args.seed)
    if args.command == "convert":
        from robokit.description.convert import convert_cli

        return convert_cli(args.input, args.output, tip=args.tip, convention=args.convention)
    if args.command == "view":
        from robokit.viz.view import view_cli

        return view_cli(args.model, args.output, q=args.q, frames=args.frames,
                        trajectory=args.trajectory, fps=args.fps)
    if args.command == "teach":
        from robokit.viz.teach import teach_cli

        return teach_cli(args.model, args.output)
    raise _UsageError(f"robokit: unknown command {args.command!r}")


def main(argv=None) -> int:
    """Entry point of the console script; returns the exit status."""
    try:
        args = _build_parser().parse_args(argv)
        return _dispatch(args)
    except _UsageError as exc:
        print(str(exc), file=sys.stderr)
        return 2
    except (ValueError, TypeError, FileNotFoundError, KeyError, OSError) as exc:
        msg = str(exc).strip().splitlines()[0] if str(exc).strip() else type(exc).__name__
        print(f"robokit: error: {msg}", file=sys.stderr)
        return 2


if __name__ == "__main__":
    sys.exit(main())
