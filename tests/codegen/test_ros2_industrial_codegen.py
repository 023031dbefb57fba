"""``robokit codegen`` on industrial arms as their makers publish them for ROS 2
(tests/data/<maker>/SOURCE): the command line on the maker's xacro file (with ``--xacro-arg`` where the
file needs one), the C compiled with ``gcc -std=c99 -Wall -Wextra -Wpedantic -Werror``, and its forward
kinematics, Jacobian, gravity torques and closed-form IK held against Pinocchio built directly from the
``xacro`` program's expansion of the same file (not through robokit) at random configurations within the
file's limits."""
import shutil
import warnings
from pathlib import Path

import pytest

import robokit
from robokit.cli import main as cli_main
from c_reference import build, compare  # tests/support
from xacro_reference import xacro_urdfs

DATA = Path(__file__).resolve().parents[1] / "data"
DENSO = "denso_robot_descriptions/urdf/denso_robot.urdf.xacro"
ARMS = {  # label -> (maker, file, xacro arguments)
    "Techman TM5-900": ("techman", "tm_description/xacro/tm5-900.urdf.xacro", {}),  # three parallel axes in C
    "DENSO VS-060": ("denso", DENSO, {"model": "vs060"}),  # spherical wrist
    "Dobot ME6": ("dobot", "cra_description/urdf/me6_robot.xacro", {}),  # calibrated three parallel axes
}


@pytest.mark.parametrize("label", list(ARMS))
def test_codegen_of_the_makers_file_agrees_with_pinocchio(label, tmp_path, capsys):
    gcc = shutil.which("gcc")
    if gcc is None:
        pytest.skip("no gcc on this machine (CI installs it)")
    maker, rel, args = ARMS[label]
    path = DATA / maker / rel
    options = [o for k, v in args.items() for o in ("--xacro-arg", f"{k}:={v}")]
    assert cli_main(["codegen", str(path), "-o", str(tmp_path), "--name", "arm", *options]) == 0
    err = capsys.readouterr().err
    assert err.count("mesh files not found") == 1  # one note for the meshes not vendored
    assert "has mass (the file gives none)" not in err
    lib = build(gcc, tmp_path)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        robot = robokit.load(path, xacro_args=args or None)
    header = (tmp_path / "arm.h").read_text()
    assert "#define arm_HAS_IK 1" in header and "#define arm_N 6" in header
    compare(lib, xacro_urdfs({label: (DATA / maker, rel, args)})[label], robot, header, gravity_floor=0.0,
            min_solutions=1)
    assert max(abs(t) for t in robot.gravity_torques([0.3] * 6)) > 1e-2  # these files give inertias: not a 0 = 0 check
