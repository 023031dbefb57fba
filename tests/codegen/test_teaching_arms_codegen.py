"""``robokit codegen`` on the arms courses and student teams own, from their makers' files
(tests/data/<maker>/SOURCE) with the makers' launch arguments given on the command line: the C compiled with
``gcc -std=c99 -Wall -Wextra -Wpedantic -Werror``, and its forward kinematics, Jacobian, gravity torques,
inverse dynamics and (where there is one) closed-form IK held against Pinocchio built directly from the
``xacro`` program's expansion of the same file with the same arguments (the myCobot's URDF file itself), at
random configurations within the file's limits."""
import shutil
import warnings
from pathlib import Path

import pytest

import robokit
from robokit.cli import main as cli_main
from c_reference import build, compare  # tests/support
from xacro_reference import xacro_urdfs

DATA = Path(__file__).resolve().parents[1] / "data"
XS = "interbotix_xsarm_descriptions/urdf/"
ARMS = {  # label -> (maker, file, xacro arguments, joints, closed-form IK)
    "PincherX 100": ("interbotix", XS + "px100.urdf.xacro", {}, 4, False),
    "WidowX 250 6DOF, named left, tip ee_arm_link": ("interbotix", XS + "wx250s.urdf.xacro",
                                                     {"robot_name": "left"}, 6, True),
    "OpenManipulator-X, prefix": ("robotis", "open_manipulator_description/urdf/open_manipulator_x/"
                                  "open_manipulator_x.urdf.xacro", {"prefix": "l_"}, 4, False),
    # a URDF file (args None): UR-type IK in C; no inertia, so gravity and RNEA are zero as in Pinocchio
    "myCobot 280 M5": ("elephant", "mycobot_description/urdf/mycobot_280_m5/mycobot_280_m5.urdf", None, 6, True),
}
TIPS = {"WidowX 250 6DOF, named left, tip ee_arm_link": "left/ee_arm_link"}


@pytest.mark.parametrize("label", list(ARMS))
def test_codegen_of_the_makers_file_agrees_with_pinocchio(label, tmp_path, capsys):
    gcc = shutil.which("gcc")
    if gcc is None:
        pytest.skip("no gcc on this machine (CI installs it)")
    maker, rel, args, n, has_ik = ARMS[label]
    path = DATA / maker / rel
    argv = ["codegen", str(path), "-o", str(tmp_path), "--name", "arm"]
    argv += [a for k, v in (args or {}).items() for a in ("--xacro-arg", f"{k}:={v}")]
    argv += ["--tip", TIPS[label]] if label in TIPS else []
    assert cli_main(argv) == 0
    err = capsys.readouterr().err
    assert err.count("mesh files not found") == 1
    assert err.count("mimic joints off the chain locked") == (0 if args is None else 1)
    assert err.count("has mass (the file gives none)") == (1 if args is None else 0)
    lib = build(gcc, tmp_path)
    text = path.read_text() if args is None else xacro_urdfs({label: (DATA / maker, rel, args)})[label]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        robot = robokit.load(path, TIPS.get(label), xacro_args=args or None)
    header = (tmp_path / "arm.h").read_text()
    assert f"#define arm_HAS_IK {int(has_ik)}" in header and f"#define arm_N {n}" in header
    compare(lib, text, robot, header, tip=TIPS.get(label), samples=20, ik=has_ik, gravity_floor=0.0, min_solutions=1)
