"""The generated C on a Cortex-M4F (QEMU ``mps2-an386``): code size, stack and instructions per call.

For each robot the C files are generated and cross-compiled with ``arm-none-eabi-gcc -O2`` for
the Cortex-M4F (hard float: single-precision FPU, so ``double`` arithmetic is newlib's software
routines), linked with ``examples/cortex-m4/`` (the startup file and linker script users copy) and
run under ``qemu-system-arm -M mps2-an386 -icount shift=0`` with semihosting. Per function:

* **code** — the function's own bytes (``arm-none-eabi-nm --size-sort``) and, for the IK, the bytes
  of everything it calls in the generated file (its helpers and tables); the whole object's
  ``text``/``data``/``bss`` from ``arm-none-eabi-size`` is the row's total.
* **stack (static)** — gcc's ``-fstack-usage`` frame of the function, and its worst call path
  through the generated file's functions (``-fcallgraph-info=su``; library calls — libm, the
  soft-float routines — not included).
* **stack (measured)** — the run-time high-water mark of one call: the driver fills 64 KB below
  its stack pointer with a pattern, calls the function, and finds the deepest word overwritten
  (this includes libm and the soft-float routines, for the inputs used).
* **instructions per call** — with ``-icount shift=0`` QEMU advances its virtual clock by exactly
  one nanosecond per executed instruction; the driver reads the SysTick counter (which QEMU
  derives from that clock) around a loop of calls, and converts ticks to instructions with a
  calibration loop of known length (a ``subs``/``bne`` loop, two instructions per iteration) in
  the same run. Instructions, not cycles: on a real M4 a load costs 2 cycles, a taken branch 2–4,
  flash wait states more — count about 1.3–2 cycles per instruction.

Run: ``.venv/bin/python -m benchmarks.board`` (prints a Markdown table; asserts nothing). The
helpers (:func:`cross_compile`, :func:`stack_paths`, :func:`run_qemu`) are the ones
``tests/codegen/test_board.py`` and ``tests/codegen/test_stack.py`` use.
"""
from __future__ import annotations

import re
import shutil
import subprocess
import tempfile
from datetime import date
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
BOARD = ROOT / "examples" / "cortex-m4"
CPU = ("-mcpu=cortex-m4", "-mfpu=fpv4-sp-d16", "-mfloat-abi=hard", "-mthumb")
STRICT = ("-std=c99", "-Wall", "-Wextra", "-Wpedantic", "-Wshadow", "-Werror")
QEMU = ("-M", "mps2-an386", "-nographic", "-semihosting-config", "enable=on,target=native")


def missing_tools() -> str | None:
    """Why the board cannot be used here (None when the cross compiler, newlib and QEMU are installed)."""
    missing = [t for t in ("arm-none-eabi-gcc", "qemu-system-arm") if shutil.which(t) is None]
    if missing:
        return (f"{' and '.join(missing)} not installed (Debian: gcc-arm-none-eabi, libnewlib-arm-none-eabi, "
                "qemu-system-arm; .ci/run installs them)")
    probe = subprocess.run(["arm-none-eabi-gcc", *CPU, "--specs=rdimon.specs", "-print-file-name=librdimon.a"],
                           capture_output=True, text=True)
    if probe.returncode != 0 or not Path(probe.stdout.strip()).is_file():
        return "newlib's librdimon for arm-none-eabi not installed (Debian: libnewlib-arm-none-eabi)"
    return None


def cross_compile(sources, out: Path, float32: bool = False, extra=(), include=()) -> Path:
    """Compile and link ``sources`` with the startup file and linker script into ``out`` (an ELF file)."""
    warn = STRICT + (("-Wdouble-promotion",) if float32 else ())
    cmd = ["arm-none-eabi-gcc", *CPU, *warn, "-O2", *extra, "-nostartfiles", "--specs=rdimon.specs",
           "-T", str(BOARD / "mps2_an386.ld"), *(f"-I{i}" for i in include), str(BOARD / "startup.c"),
           *map(str, sources), "-lm", "-o", str(out)]
    res = subprocess.run(cmd, capture_output=True, text=True, cwd=out.parent)
    if res.returncode != 0:
        raise RuntimeError(f"{' '.join(cmd)} failed:\n{res.stderr}")
    return out


def run_qemu(elf: Path, icount: bool = False, timeout: float = 300.0) -> str:
    """Run ``elf`` on QEMU's mps2-an386; its semihosting output (raises if it does not exit with 0)."""
    cmd = ["qemu-system-arm", *QEMU, *(("-icount", "shift=0") if icount else ()), "-kernel", str(elf)]
    res = subprocess.run(cmd, capture_output=True, text=True, timeout=timeout)
    if res.returncode != 0:
        raise RuntimeError(f"{' '.join(cmd)} exited with {res.returncode}:\n{res.stdout[-2000:]}{res.stderr}")
    return res.stdout


def stack_paths(ci_text: str, self_recursion: int = 4) -> dict[str, tuple[int, int]]:
    """Per function of a gcc ``-fcallgraph-info=su`` file: (own frame, worst call path) in bytes.

    Library functions (no frame size in the file) count 0. A function calling itself (the quartic's
    root isolation, one level per polynomial degree) counts ``self_recursion`` times; any other
    cycle raises ValueError.
    """
    size: dict[str, int] = {}
    edges: dict[str, set[str]] = {}
    recursive: set[str] = set()
    for m in re.finditer(r'node: \{ title: "([^"]+)" label: "[^"]*?\\n[^"]*?\\n(\d+) bytes', ci_text):
        size[m.group(1)] = int(m.group(2))
    for m in re.finditer(r'edge: \{ sourcename: "([^"]+)" targetname: "([^"]+)"', ci_text):
        if m.group(1) != m.group(2):
            edges.setdefault(m.group(1), set()).add(m.group(2))
        else:
            recursive.add(m.group(1))
    memo: dict[str, int] = {}

    def worst(f: str, path: tuple[str, ...]) -> int:
        if f in path:
            raise ValueError("recursion: " + " -> ".join(path + (f,)))
        if f not in memo:
            own = size.get(f, 0) * (self_recursion if f in recursive else 1)
            memo[f] = own + max((worst(g, path + (f,)) for g in edges.get(f, ())), default=0)
        return memo[f]

    out: dict[str, tuple[int, int]] = {}
    for f in size:  # gcc's clones (f.constprop.0, f.isra.0) reported under f's name, the largest
        name = f.split(":")[-1].split(".")[0]
        old = out.get(name, (0, 0))
        out[name] = (max(old[0], size[f]), max(old[1], worst(f, ())))
    return out
