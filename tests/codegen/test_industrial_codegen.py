"""``robokit codegen`` on industrial arms as ROS-Industrial publishes them (tests/data/<maker>/SOURCE): the
command line on the maker's xacro file, the C compiled with ``gcc -std=c99 -Wall -Wextra -Wpedantic
-Werror``, and its forward kinematics, Jacobian, gravity torques and closed-form IK held against
Pinocchio built directly from the ``xacro`` program's expansion of the same file (not through robokit)
at random configurations within the file's limits."""
import shutil
import warnings
from pathlib import Path

import pytest

import robokit
from robokit.cli import main as cli_main
from c_reference import build, compare  # tests/support
from xacro_reference import xacro_urdfs

DATA = Path(__file__).resolve().parents[1] / "data"
ARMS = {  # label -> (maker, file, whether the file gives inertias)
    "KUKA KR 210 L150": ("kuka", "kuka_kr210_support/urdf/kr210l150.xacro", True),
    "FANUC M-430iA/2P": ("fanuc", "fanuc_m430ia_support/urdf/m430ia2p.xacro", False),  # general 6R in C
    "Staubli RX160": ("staubli", "staubli_rx160_support/urdf/rx160.xacro", True),
}


@pytest.mark.parametrize("label", list(ARMS))
def test_codegen_of_the_makers_file_agrees_with_pinocchio(label, tmp_path, capsys):
    gcc = shutil.which("gcc")
    if gcc is None:
        pytest.skip("no gcc on this machine (CI installs it)")
    maker, rel, has_mass = ARMS[label]
    path = DATA / maker / rel
    assert cli_main(["codegen", str(path), "-o", str(tmp_path), "--name", "arm"]) == 0
    err = capsys.readouterr().err
    # one note per thing not modelled: the missing meshes, and the missing inertias where there are none
    assert err.count("mesh files not found") == 1
    assert err.count("has mass (the file gives none)") == (0 if has_mass else 1)
    lib = build(gcc, tmp_path)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        robot = robokit.load(path)
    header = (tmp_path / "arm.h").read_text()
    assert "#define arm_HAS_IK 1" in header and "#define arm_N 6" in header
    compare(lib, xacro_urdfs({label: (DATA / maker, rel)})[label], robot, header)
