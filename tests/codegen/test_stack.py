"""Stack on the Cortex-M4 (an RTOS task's budget), summed along the call graph of the generated file
(gcc -fstack-usage -fcallgraph-info=su, arm-none-eabi-gcc -O2): every generated function's whole
call path is at most 2 KB in double, except the general-6R IK, whose whole call path is at most
12 KB for NAME_ik_ws and for NAME_ik / NAME_ik_ex alike (those two hold the NAME_ik_workspace on
their own stack), the calibrated arms' NAME_ik_ex included (their starts live in the caller's q). Library
calls (libm, soft-float) are not in the static figure;
The Gen3 lite's general-6R IK finishes its solutions with the calibrated arms' polish (its helpers
within 2 KB, the whole path within the 12 KB). tests/codegen/test_board.py measures the run-time high-water mark of NAME_ik_ws under QEMU."""
import subprocess

import pytest

import robokit
from benchmarks.board import CPU, STRICT, missing_tools, stack_paths
from shared_robots import gen3_lite
from robokit.codegen import generate_c, write_c

from .test_clang import prismatic_arm, quartic_arm
from .test_codegen import calibrated_arm, jaco2_table

ARMS = {"twolink": lambda: "twolink", "rrr": lambda: "rrr", "puma560": lambda: "puma560", "ur5": lambda: "ur5",
        "panda": lambda: "panda", "jaco2": jaco2_table, "quartic": quartic_arm, "stanford": prismatic_arm,
        "calibrated_puma560": lambda: calibrated_arm("puma560", 1), "calibrated_ur5": lambda: calibrated_arm("ur5", 2),
        "gen3_lite": gen3_lite}
FRAME, G6R_PATH = 2048, 12 * 1024
IK_WORKSPACE = 8 * 1182  # NAME_IK_WORKSPACE_SIZE (templates/g6r.h: G6R_WORKSPACE_DOUBLES doubles)


@pytest.fixture(scope="module")
def arm_gcc():
    why = missing_tools()
    if why:
        pytest.skip(why)


@pytest.mark.parametrize("name", list(ARMS))
def test_stack_fits_an_rtos_task(arm_gcc, tmp_path, name):
    arm = ARMS[name]()
    robot = arm if isinstance(arm, robokit.Robot) else robokit.load(arm)
    src = generate_c(robot)
    _, c_path = write_c(src, tmp_path)
    res = subprocess.run(["arm-none-eabi-gcc", *CPU, *STRICT, "-O2", "-fstack-usage", "-fcallgraph-info=su", "-c",
                          c_path.name, "-o", "x.o"], cwd=tmp_path, capture_output=True, text=True)
    assert res.returncode == 0, res.stderr
    stack = stack_paths((tmp_path / "x.ci").read_text())
    P = src.name
    assert f"{P}_fk" in stack and f"{P}_rnea" in stack  # the file was read
    general = f"{P}_ik_ws" in src.header
    assert general == (name in ("jaco2", "gen3_lite"))
    for fn in (f"{P}_fk", f"{P}_jacobian", f"{P}_gravity", f"{P}_rnea"):  # leaves: the frame is the path
        assert stack[fn][1] <= FRAME, (fn, stack[fn])
    ik = (f"{P}_ik", f"{P}_ik_ex", f"{P}_ik_ws") if general else ()
    for fn in ik:  # the whole path, with the workspace on the stack for NAME_ik and NAME_ik_ex
        assert stack[fn][1] <= G6R_PATH, (fn, stack[fn])
    if general:
        assert stack[f"{P}_ik_ex"][0] > IK_WORKSPACE  # the workspace is on that stack (the path counts it)
    for fn, (frame, path) in stack.items():
        if fn in ik or fn.startswith("g6r_"):  # the general IK's helpers: inside its 12 KB path
            continue
        assert frame <= FRAME, (fn, frame)
        assert path <= FRAME, (fn, path)
