"""Stack on the Cortex-M4 (an RTOS task's budget): every generated function's frame is at most 2 KB in
double (gcc -fstack-usage, arm-none-eabi-gcc -O2; FK, Jacobian, gravity and RNEA call nothing else
in the file, so that is their whole call path), except the general-6R IK, whose NAME_ik_ws needs at
most 12 KB for its whole call path through the generated file (-fcallgraph-info=su); NAME_ik /
NAME_ik_ex add the NAME_ik_workspace they keep on their stack. Library calls (libm, soft-float) are not in the static figure;
tests/codegen/test_board.py measures the run-time high-water mark of NAME_ik_ws under QEMU."""
import subprocess

import pytest

import robokit
from benchmarks.board import CPU, STRICT, missing_tools, stack_paths
from robokit.codegen import generate_c, write_c

from .test_clang import prismatic_arm, quartic_arm
from .test_codegen import calibrated_arm, jaco2_table

ARMS = {"twolink": lambda: "twolink", "rrr": lambda: "rrr", "puma560": lambda: "puma560", "ur5": lambda: "ur5",
        "panda": lambda: "panda", "jaco2": jaco2_table, "quartic": quartic_arm, "stanford": prismatic_arm,
        "calibrated_puma560": lambda: calibrated_arm("puma560", 1), "calibrated_ur5": lambda: calibrated_arm("ur5", 2)}
FRAME, G6R_PATH = 2048, 12 * 1024


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
    assert general == (name == "jaco2")
    for fn in (f"{P}_fk", f"{P}_jacobian", f"{P}_gravity", f"{P}_rnea"):  # leaves: the frame is the path
        assert stack[fn][1] <= FRAME, (fn, stack[fn])
    if general:  # the IK's helpers are covered by the call path of NAME_ik_ws
        assert stack[f"{P}_ik_ws"][1] <= G6R_PATH, stack[f"{P}_ik_ws"]
    else:  # every function's own frame (the closed form's call path: docs/codegen.md's table)
        for fn, (frame, _) in stack.items():
            assert frame <= FRAME, (fn, frame)
