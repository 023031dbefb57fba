"""``robokit codegen`` on collaborative arms as their makers publish them (tests/data/kinova/ros_kortex/SOURCE,
tests/data/niryo/SOURCE): the command line on the maker's xacro file with its arguments (``--xacro-arg
dof:=6``), the C compiled with ``gcc -std=c99 -Wall -Wextra -Wpedantic -Werror``, and its forward kinematics,
Jacobian, gravity torques, inverse dynamics and closed-form IK held against Pinocchio built directly from
the ``xacro`` program's expansion of the same file with the same arguments (not through robokit), at random
configurations within the file's limits (continuous joints over a turn)."""
import ctypes
import shutil
import warnings
from pathlib import Path

import numpy as np
import pinocchio as pin
import pytest

import robokit
from robokit.cli import main as cli_main
from c_reference import build, compare  # tests/support
from xacro_reference import xacro_urdfs

DATA = Path(__file__).resolve().parents[1] / "data"
GEN3 = (DATA / "kinova" / "ros_kortex", "kortex_description/robots/gen3.xacro")
ARMS = {  # label -> (packages folder, xacro file, xacro arguments, whether the C has a closed-form IK)
    "Gen3 6-DoF": (*GEN3, {"dof": "6", "vision": "false"}, True),  # calibrated spherical wrist in C
    "Gen3 7-DoF": (*GEN3, {"vision": "false"}, False),  # no closed form: FK, J, gravity, RNEA
    "Ned2": (DATA / "niryo", "niryo_robot_description/urdf/ned2/niryo_ned2.urdf.xacro", {}, True),  # general 6R
}


@pytest.fixture(scope="module")
def reference():
    return xacro_urdfs({k: (m, f, a) for k, (m, f, a, _) in ARMS.items()})


@pytest.mark.parametrize("label", list(ARMS))
def test_codegen_of_the_makers_file_agrees_with_pinocchio(label, reference, tmp_path, capsys):
    gcc = shutil.which("gcc")
    if gcc is None:
        pytest.skip("no gcc on this machine (CI installs it)")
    folder, rel, args, has_ik = ARMS[label]
    path = folder / rel
    xargs = [a for k, v in args.items() for a in ("--xacro-arg", f"{k}:={v}")]
    assert cli_main(["codegen", str(path), *xargs, "-o", str(tmp_path), "--name", "arm"]) == 0
    err = capsys.readouterr().err
    assert err.count("mesh files not found") == 1 and "has mass" not in err
    lib = build(gcc, tmp_path)
    model = pin.buildModelFromXML(reference[label])
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        robot = robokit.load(path, xacro_args=args or None)
    n = robot.n
    joints = [model.joints[model.getJointId(j)] for j in robot.joint_names]
    header = (tmp_path / "arm.h").read_text()
    assert f"#define arm_HAS_IK {int(has_ik)}" in header and f"#define arm_N {n}" in header
    # the C's limits are the file's: a continuous joint (two coordinates in Pinocchio) unbounded
    qlim = np.array((ctypes.c_double * 2 * n).in_dll(lib, "arm_qlim"))
    file_lim = [[model.lowerPositionLimit[j.idx_q], model.upperPositionLimit[j.idx_q]] if j.nq == 1
                else [-np.inf, np.inf] for j in joints]
    assert qlim.tolist() == file_lim
    lo, hi = np.asarray(robot.qlim, float).T
    lo, hi = np.where(np.isfinite(lo), lo, -np.pi), np.where(np.isfinite(hi), hi, np.pi)
    compare(lib, reference[label], robot, header, lo=lo, hi=hi, ik=has_ik)
