"""Run every benchmark and print its tables: ``.venv/bin/python -m benchmarks [--quick]``.

Each benchmark module has ``main(argv)``; they are run in turn in this process.
"""
import importlib
import sys

MODULES = ["benchmarks.startup", "benchmarks.targets", "benchmarks.kernels", "benchmarks.ik", "benchmarks.lm_damping", "benchmarks.ik_analytic", "benchmarks.ik_closed_form",
           "benchmarks.speed", "benchmarks.control", "benchmarks.calibration", "benchmarks.calibrated_ik", "benchmarks.motion",
           "benchmarks.input_checks", "benchmarks.degrees", "benchmarks.seed_args",
           "benchmarks.board", "benchmarks.teach_wasm"]


def main(argv=None):
    argv = list(sys.argv[1:] if argv is None else argv)
    for name in MODULES:
        try:
            mod = importlib.import_module(name)
        except ModuleNotFoundError as exc:
            if exc.name == name:
                continue
            raise
        print()
        mod.main(argv)


if __name__ == "__main__":
    main()
