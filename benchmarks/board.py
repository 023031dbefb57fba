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


DRIVER = r"""
#include <stdint.h>
#include <stdio.h>
#include "@P@.h"

#define SYST_CSR (*(volatile uint32_t *)0xE000E010u)
#define SYST_RVR (*(volatile uint32_t *)0xE000E014u)
#define SYST_CVR (*(volatile uint32_t *)0xE000E018u)
#define PAINT_WORDS (72 * 1024 / 4)

@INPUTS@
static @T@ out[@OUT@];
static int info[4 * 16];
@WS@
static int which;
static volatile @T@ sink;

static void call(void)
{
    int i = which;
    switch (i >> 8) {
    case 0: @P@_fk(&Q[@N@ * (i & 255)], out); break;
    case 1: @P@_jacobian(&Q[@N@ * (i & 255)], out); break;
    case 2: @P@_gravity(&Q[@N@ * (i & 255)], out); break;
    case 3: @P@_rnea(&Q[@N@ * (i & 255)], &QD[@N@ * (i & 255)], &QDD[@N@ * (i & 255)], out); break;
    default: @IKCALL@ break;
    }
    sink = out[0];
}

/* two instructions per iteration: the calibration of SysTick ticks against executed instructions */
static void spin(uint32_t n)
{
    __asm__ volatile("1: subs %0, %0, #1\n\tbne 1b" : "+r"(n) : : "cc");
}

static uint32_t ticks(void (*f)(uint32_t), uint32_t arg)
{
    uint32_t t0, t1;
    SYST_CVR = 0u;
    t0 = SYST_CVR;
    f(arg);
    t1 = SYST_CVR;
    return (t0 - t1) & 0xFFFFFFu;
}

static void run(uint32_t reps)
{
    uint32_t r;
    int k;
    for (r = 0; r < reps; ++r) {
        for (k = 0; k < @K@; ++k) {
            which = (which & ~255) | k;
            call();
        }
    }
}

/* the deepest stack word one call overwrites, in bytes below this function's frame */
static uint32_t __attribute__((noinline)) stack_used(void)
{
    volatile uint32_t *top, *p;
    __asm__ volatile("mov %0, sp" : "=r"(top));
    top -= 16;  /* below this frame; volatile: no memset call (it would paint its own frame) */
    for (p = top - PAINT_WORDS; p < top; ++p) {
        *p = 0xA5A5A5A5u;
    }
    call();
    for (p = top - PAINT_WORDS; p < top && *p == 0xA5A5A5A5u; ++p) {
    }
    return (uint32_t)(top - p) * 4u + 64u;
}

int main(void)
{
    const char *names[5] = {"fk", "jacobian", "gravity", "rnea", "ik"};
    uint32_t cal, f, reps, t, s, smax;
    int k;
    SYST_RVR = 0xFFFFFFu;
    SYST_CSR = 5u;  /* enabled, processor clock, no interrupt */
    cal = ticks(spin, 1000000u);
    printf("calibration %lu ticks for 2000000 instructions\n", (unsigned long)cal);
    for (f = 0; f < (@HAS_IK@ ? 5u : 4u); ++f) {
        which = (int)(f << 8);
        smax = 0u;
        for (k = 0; k < @K@; ++k) {
            which = (int)(f << 8) | k;
            s = stack_used();
            smax = s > smax ? s : smax;
        }
        which = (int)(f << 8);
        reps = f == 4u ? @IKREPS@ : 200u;
        t = ticks(run, reps);
        printf("%s %lu %lu %lu\n", names[f], (unsigned long)t, (unsigned long)(reps * @K@), (unsigned long)smax);
    }
    return 0;
}
"""


def _c_array(name: str, values, ctype: str) -> str:
    import numpy as np

    suffix = "f" if ctype == "float" else ""
    body = ", ".join(repr(float(v)) + suffix for v in np.ravel(values))
    return f"static const {ctype} {name}[{np.size(values)}] = {{{body}}};"


def measure(robot, folder: Path, float32: bool = False) -> dict:
    """Code size, static and measured stack and instructions per call of each generated function."""
    import numpy as np

    from robokit.codegen import generate_c, write_c

    src = generate_c(robot, float32=float32)
    P, n = src.name, robot.n
    write_c(src, folder)
    ctype = "float" if float32 else "double"
    rng = np.random.default_rng(0)
    q = np.array([robot.random_configuration(rng) for _ in range(4)])
    qd, qdd = rng.normal(size=q.shape), rng.normal(size=q.shape)
    poses = np.array([robot.frame_pose(x) for x in q])
    general = f"{P}_ik_ws" in src.header
    ws = f"static {P}_ik_workspace ws;" if general else ""
    ikcall = (f"(void){P}_ik_ws(&POSES[16 * (i & 255)], 0.0, sols, info, &ws);" if general else
              f"(void){P}_ik_ex(&POSES[16 * (i & 255)], 0.0{'f' if float32 else ''}, sols, info);")
    inputs = "\n".join([_c_array("Q", q, ctype), _c_array("QD", qd, ctype), _c_array("QDD", qdd, ctype),
                        _c_array("POSES", poses, ctype), f"static {ctype} sols[16 * {n}];"])
    subs = {"@P@": P, "@N@": str(n), "@T@": ctype, "@OUT@": str(6 * n), "@K@": str(len(q)), "@INPUTS@": inputs,
            "@WS@": ws, "@IKCALL@": ikcall if src.has_ik else "", "@HAS_IK@": "1" if src.has_ik else "0",
            "@IKREPS@": "2u" if general else "50u"}
    text = DRIVER
    for key, val in subs.items():
        text = text.replace(key, val)
    (folder / "bench.c").write_text(text)
    flags = ("-Wno-double-promotion",) if float32 else ()  # the driver's printf; the robot's file is checked
    elf = cross_compile([folder / "bench.c", folder / f"{P}.c"], folder / "bench.elf", float32, flags, [folder])
    out = run_qemu(elf, icount=True, timeout=900)
    lines = [ln.split() for ln in out.splitlines()]
    cal = int(lines[0][1]) / 2000000.0  # ticks per instruction
    calls = {ln[0]: (int(ln[1]) / cal / int(ln[2]), int(ln[3])) for ln in lines[1:]}
    # static figures from the robot's object alone
    subprocess.run(["arm-none-eabi-gcc", *CPU, "-std=c99", "-O2", "-fstack-usage", "-fcallgraph-info=su", "-c",
                    f"{P}.c", "-o", f"{P}.o"], cwd=folder, check=True, capture_output=True)
    stack = stack_paths((folder / f"{P}.ci").read_text())
    nm = subprocess.run(["arm-none-eabi-nm", "--size-sort", "-S", f"{P}.o"], cwd=folder, check=True,
                        capture_output=True, text=True).stdout
    sizes = {ln.split()[3]: int(ln.split()[1], 16) for ln in nm.splitlines() if len(ln.split()) == 4}
    size = subprocess.run(["arm-none-eabi-size", f"{P}.o"], cwd=folder, check=True, capture_output=True,
                          text=True).stdout.splitlines()[1].split()
    four = [f"{P}_{f}" for f in ("fk", "jacobian", "gravity", "rnea")]
    tables = [f"{P}_{t}" for t in ("qlim", "joint_type", "joint_names")]
    ik_bytes = sum(v for k, v in sizes.items() if k not in four and k not in tables)
    rows = []
    for f in ("fk", "jacobian", "gravity", "rnea", "ik"):
        if f not in calls:
            continue
        fn = f"{P}_ik_ws" if (f == "ik" and general) else (f"{P}_ik_ex" if f == "ik" else f"{P}_{f}")
        code = sizes.get(fn, 0) if f != "ik" else ik_bytes
        frame, path = stack.get(fn, (0, 0))
        rows.append((fn, code, frame, path, calls[f][1], calls[f][0]))
    return dict(name=P, rows=rows, total=(int(size[0]), int(size[1]), int(size[2])),
                workspace=(ws and _sizeof_ws(folder, P)))


def _sizeof_ws(folder: Path, P: str) -> int:
    (folder / "ws.c").write_text(f'#include "{P}.h"\nconst unsigned ws_size = (unsigned){P}_IK_WORKSPACE_SIZE;\n')
    subprocess.run(["arm-none-eabi-gcc", *CPU, "-std=c99", "-O2", "-c", "ws.c", "-o", "ws.o"], cwd=folder,
                   check=True)
    nm = subprocess.run(["arm-none-eabi-objdump", "-s", "-j", ".rodata", "ws.o"], cwd=folder, check=True,
                        capture_output=True, text=True).stdout
    word = re.search(r"^ 0000 ([0-9a-f]{8})", nm, re.M).group(1)
    return int.from_bytes(bytes.fromhex(word), "little")


def _calibrated_puma():
    """A PUMA 560 with every joint placement, the base and the tool off by up to 2 mrad / 2 mm, built as
    ``robokit.calibrate`` builds its result (its IK: the polished closed form, ``robokit.ik.calibrated``)."""
    import numpy as np
    import robokit
    from robokit.calibration import chain_from_robot, robot_from_chain

    nominal = robokit.load("puma560")
    delta = np.random.default_rng(1).uniform(-2e-3, 2e-3, (nominal.n + 1, 6))
    return robot_from_chain(nominal, chain_from_robot(nominal).perturbed(delta))


def main(argv=None) -> None:
    """Print the table (``argv`` is accepted for ``python -m benchmarks``; there are no options)."""
    import robokit
    from benchmarks._harness import machine, table
    from benchmarks.codegen import _jaco_table

    why = missing_tools()
    if why:
        print(f"skipped: {why}")
        return
    cases = [("PUMA 560 (spherical wrist)", robokit.load("puma560"), False),
             ("UR5 (three parallel axes)", robokit.load("ur5"), False),
             ("Kinova Jaco² (general 6R)", robokit.load(_jaco_table()), False),
             ("PUMA 560 calibrated (errors ≤ 2 mrad / 2 mm)", _calibrated_puma(), False),
             ("PUMA 560, --float32", robokit.load("puma560"), True),
             ("UR5, --float32", robokit.load("ur5"), True)]
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        for label, robot, f32 in cases:
            folder = Path(tmp) / f"{robot.name}_{int(f32)}"
            folder.mkdir()
            r = measure(robot, folder, f32)
            note = f" (+ workspace {r['workspace']} B)" if r["workspace"] else ""
            for fn, code, frame, path, measured, instr in r["rows"]:
                rows.append((label, f"`{fn}`", code, frame, f"{path}{note if fn.endswith('_ik_ws') else ''}",
                             measured, f"{instr:,.0f}"))
            rows.append((label, f"whole `{r['name']}.o` (text/data/bss)", "/".join(map(str, r["total"])), "", "",
                         "", ""))
    print(f"{date.today().isoformat()}, {machine()}; arm-none-eabi-gcc -O2, Cortex-M4F hard float, QEMU mps2-an386 "
          "-icount shift=0\n")
    print(table(["robot", "function", "code (B)", "stack frame (B)", "stack, call path (B)",
                 "stack measured (B)", "instructions / call"], rows))


if __name__ == "__main__":
    main()
