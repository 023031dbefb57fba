"""The generated C on a Cortex-M4F: cross-compiled with arm-none-eabi-gcc (hard float, the strict
flags, float32 also -Wdouble-promotion), linked with the startup file and linker script users copy
(examples/cortex-m4/), run under QEMU's mps2-an386 with semihosting, and compared on the host with
Pinocchio (FK, Jacobian, gravity, rnea) and robokit's ik_analytic (every solution, same order and
labels, each reaching the pose through Pinocchio). Double to 1e-12 relative, float32 to 1e-4.

Skips, saying why, only where the cross toolchain or QEMU is missing (.ci/run installs Debian's
gcc-arm-none-eabi, libnewlib-arm-none-eabi and qemu-system-arm)."""
import numpy as np
import pytest

import robokit
from benchmarks.board import cross_compile, missing_tools, run_qemu
from robokit.codegen import generate_c, write_c
from robokit.ik import ik_analytic

from .test_codegen import _dist, calibrated_arm, jaco2_table

# Fixed configurations (rad or m), the same for every arm (cut to its joint count).
CONFIGS = np.array([[0.1, -0.5, 0.3, 0.4, 0.6, -0.2, 0.7],
                    [-1.2, 0.8, -0.4, 1.9, -0.9, 2.5, -0.3],
                    [2.0, 0.25, 1.1, -2.2, 1.3, 0.05, 1.0]])


@pytest.fixture(scope="session")
def arm_tools():
    why = missing_tools()
    if why:
        pytest.skip(why)


def _c_array(name, values, ctype):
    suffix = "f" if ctype == "float" else ""
    body = ", ".join(repr(float(v)) + suffix for v in np.ravel(values))
    return f"static const {ctype} {name}[{np.size(values)}] = {{{body}}};"


def driver(robot, P, has_ik, ctype, q, qd, qdd, poses, workspace=False):
    """main.c: every function at the fixed inputs, each output printed with %.17g, one line per call."""
    n, k, m = robot.n, len(q), len(poses)
    lines = ["#include <stdio.h>", f'#include "{P}.h"',
             _c_array("Q", q, ctype), _c_array("QD", qd, ctype), _c_array("QDD", qdd, ctype),
             _c_array("POSES", poses, ctype) if m else "",
             f"static void put(const char *what, int i, const {ctype} *x, int len)", "{", "    int j;",
             '    printf("%s %d", what, i);', "    for (j = 0; j < len; ++j) {",
             '        printf(" %.17g", (double)x[j]);', "    }", '    printf("\\n");', "}",
             "int main(void)", "{", "    int i;",
             f"    {ctype} T[16], J[6 * {n}], tau[{n}];"]
    if has_ik:
        lines += [f"    static {ctype} sols[{P}_MAX_SOLUTIONS * {n}];", f"    static int info[4 * {P}_MAX_SOLUTIONS];"]
    if workspace:  # the general 6R's NAME_ik_ws with a static workspace: the same output as NAME_ik_ex
        lines += [f"    static {P}_ik_workspace ws;"]
    lines += [f"    for (i = 0; i < {k}; ++i) {{",
              f"        {P}_fk(&Q[{n} * i], T); put(\"fk\", i, T, 16);",
              f"        {P}_jacobian(&Q[{n} * i], J); put(\"jacobian\", i, J, {6 * n});",
              f"        {P}_gravity(&Q[{n} * i], tau); put(\"gravity\", i, tau, {n});",
              f"        {P}_rnea(&Q[{n} * i], &QD[{n} * i], &QDD[{n} * i], tau); put(\"rnea\", i, tau, {n});",
              "    }"]
    if has_ik:
        lines += [f"    for (i = 0; i < {m}; ++i) {{",
                  f"        int s, c = {P}_ik_ex(&POSES[16 * i], 0.0{'f' if ctype == 'float' else ''}, sols, info);",
                  '        printf("ik %d %d\\n", i, c);',
                  "        for (s = 0; s < c; ++s) {",
                  f'            printf("sol %d %s|%d|%d|%d", i, {P}_ik_label_names[info[4 * s]], info[4 * s + 1], '
                  "info[4 * s + 2], info[4 * s + 3]);",
                  f"            put(\"\", s, &sols[{n} * s], {n});",
                  "        }", "    }"]
    if workspace:
        lines += [f"    for (i = 0; i < {m}; ++i) {{",
                  f"        int s, c = {P}_ik_ws(&POSES[16 * i], 0.0, sols, info, &ws);",
                  '        printf("ikws %d %d\\n", i, c);',
                  "        for (s = 0; s < c; ++s) {",
                  f"            put(\"ikws_sol\", i, &sols[{n} * s], {n});",
                  "        }", "    }"]
    lines += ['    printf("done\\n");', "    return 0;", "}", ""]
    return "\n".join(lines)


def run_on_board(robot, folder, float32):
    """Generate, cross-compile (-O2, strict flags), run under QEMU; the inputs and the parsed output."""
    src = generate_c(robot, float32=float32)
    P, n = src.name, robot.n
    write_c(src, folder)
    ctype = "float" if float32 else "double"
    cast = (lambda x: np.asarray(x, np.float32).astype(float)) if float32 else (lambda x: np.asarray(x, float))
    q = cast(CONFIGS[:, :n])
    rng = np.random.default_rng(3)
    qd, qdd = cast(rng.normal(size=q.shape)), cast(rng.normal(size=q.shape))
    poses = cast([robot.frame_pose(x) for x in q]) if src.has_ik else np.zeros((0, 4, 4))
    workspace = f"{P}_ik_ws(" in src.header
    (folder / "main.c").write_text(driver(robot, P, src.has_ik, ctype, q, qd, qdd, poses, workspace))
    elf = cross_compile([folder / "main.c", folder / f"{P}.c"], folder / "app.elf", float32, include=[folder])
    stdout = run_qemu(elf, timeout=120)
    assert stdout.rstrip().endswith("done"), stdout[-2000:]
    out, ik, ikws = {}, {}, {}
    for line in stdout.splitlines():
        head, _, rest = line.partition(" ")
        if head == "ik":
            i, c = map(int, rest.split())
            ik[i] = []
        elif head == "sol":
            i, rest = rest.split(" ", 1)
            meta, _, nums = rest.rpartition("|")[0], None, rest.rpartition("|")[2]
            label, rep, inside = meta.split("|")
            degen, s, *vals = nums.split()
            text = label + (f" #{rep}" if int(rep) > 1 else "")
            ik[int(i)].append((np.array(vals, float), text, inside == "1", degen == "1"))
        elif head == "ikws":
            ikws[int(rest.split()[0])] = []
        elif head == "ikws_sol":
            i, *vals = rest.split()
            ikws[int(i)].append(np.array(vals, float))
        elif head in ("fk", "jacobian", "gravity", "rnea"):
            i, *vals = rest.split()
            out[head, int(i)] = np.array(vals, float)
    return dict(q=q, qd=qd, qdd=qdd, poses=poses, out=out, ik=ik, ikws=ikws, has_ik=src.has_ik)


ARMS = {"puma560": lambda: robokit.load("puma560"), "ur5": lambda: robokit.load("ur5"),
        "rrr": lambda: robokit.load("rrr"), "twolink": lambda: robokit.load("twolink"),
        "jaco2_6n": lambda: robokit.load(jaco2_table()),
        # a PUMA 560 with every joint placement, the base and the tool off by up to 2 mrad / 2 mm, as
        # robokit.calibrate builds its result: the polished closed form (robokit.ik.calibrated) on the M4
        "calibrated_puma560": lambda: calibrated_arm("puma560", 1)}
CASES = [("puma560", False), ("ur5", False), ("rrr", False), ("twolink", False), ("jaco2_6n", False),
         ("calibrated_puma560", False), ("puma560", True), ("ur5", True), ("rrr", True), ("calibrated_puma560", True)]


@pytest.fixture(scope="module")
def board_runs(arm_tools, tmp_path_factory):
    cache = {}

    def get(name, float32):
        if (name, float32) not in cache:
            robot = ARMS[name]()
            folder = tmp_path_factory.mktemp(f"board_{name}_{'f' if float32 else 'd'}")
            cache[name, float32] = (robot, run_on_board(robot, folder, float32))
        return cache[name, float32]

    return get


@pytest.mark.parametrize("name,float32", CASES, ids=[f"{n}-{'float' if f else 'double'}" for n, f in CASES])
def test_board_matches_pinocchio(board_runs, name, float32):
    robot, run = board_runs(name, float32)
    rel = 1e-4 if float32 else 1e-12
    for i, q in enumerate(run["q"]):
        qd, qdd = run["qd"][i], run["qdd"][i]
        refs = {"fk": robot.frame_pose(q).ravel(),
                "jacobian": robot.jacobian(q, reference="local_world_aligned").ravel(),
                "gravity": robot.gravity_torques(q), "rnea": robot.rnea(q, qd, qdd)}
        for what, ref in refs.items():
            got = run["out"][what, i]
            assert got.shape == ref.shape, what
            err = np.abs(got - ref).max()
            assert err <= rel * max(1.0, np.abs(ref).max()), (what, i, err)


@pytest.mark.parametrize("name,float32", [c for c in CASES if c[0] in ("puma560", "ur5", "jaco2_6n",
                                                                      "calibrated_puma560")],
                         ids=lambda v: v if isinstance(v, str) else ("float" if v else "double"))
def test_board_ik_matches_ik_analytic(board_runs, name, float32):
    robot, run = board_runs(name, float32)
    assert run["has_ik"]
    rev = np.abs(robot.poe.Slist[:3]).sum(axis=0) > 0.5
    scale = max(1.0, float(np.abs(robot.frame_pose(np.zeros(robot.n))[:3, 3]).sum()))
    for i, T in enumerate(run["poses"]):
        py, c = ik_analytic(robot, T), run["ik"][i]
        if float32:  # float IK may merge or miss a branch near a boundary (docs/codegen.md): each one reaches T
            assert len(c) >= 1
            for q, *_ in c:
                assert np.abs(robot.frame_pose(q) - T).max() <= 1e-3 * scale
            continue
        assert [x[1] for x in c] == [s.label for s in py]
        for s, (q, label, inside, degen) in zip(py, c):
            assert (inside, degen) == (s.within_limits, s.degenerate), label
            assert _dist(q, s.q, rev) <= 1e-9, label
            assert np.abs(robot.frame_pose(q) - T).max() <= 1e-12 * scale, label
        assert any(_dist(q, run["q"][i], rev) <= 1e-9 for q, *_ in c)  # the configuration T came from
        if name == "jaco2_6n":  # NAME_ik_ws with a caller's workspace: bit for bit NAME_ik_ex
            assert len(run["ikws"][i]) == len(c) and all(np.array_equal(a, b[0]) for a, b in zip(run["ikws"][i], c))
