"""``robokit codegen`` on industrial arms as their makers publish them for ROS 2
(tests/data/<maker>/SOURCE): the command line on the maker's xacro file (with ``--xacro-arg`` where the
file needs one), the C compiled with ``gcc -std=c99 -Wall -Wextra -Wpedantic -Werror``, and its forward
kinematics, Jacobian, gravity torques and closed-form IK held against Pinocchio built directly from the
``xacro`` program's expansion of the same file (not through robokit) at random configurations within the
file's limits."""
import ctypes
import shutil
import subprocess
import warnings
from pathlib import Path

import numpy as np
import pinocchio as pin
import pytest

import robokit
from robokit.cli import main as cli_main
from robokit.ik import ik_analytic
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
    lib_path = tmp_path / "arm.so"
    build = subprocess.run([gcc, "-std=c99", "-Wall", "-Wextra", "-Wpedantic", "-Werror", "-O1", "-shared", "-fPIC",
                            "-o", str(lib_path), str(tmp_path / "arm.c"), "-lm"], capture_output=True, text=True)
    assert build.returncode == 0, build.stderr
    lib = ctypes.CDLL(str(lib_path))
    D = ctypes.POINTER(ctypes.c_double)

    text = xacro_urdfs({label: (DATA / maker, rel, args)})[label]
    model = pin.buildModelFromXML(text)
    data = model.createData()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        robot = robokit.load(path, xacro_args=args or None)
    joints = [model.joints[model.getJointId(j)] for j in robot.joint_names]
    iq, iv = [j.idx_q for j in joints], [j.idx_v for j in joints]
    fid = model.getFrameId(robot.tip)
    header = (tmp_path / "arm.h").read_text()
    assert "#define arm_HAS_IK 1" in header and "#define arm_N 6" in header
    most = int(header.split("#define arm_MAX_SOLUTIONS ")[1].split()[0])

    def fk(q):
        qf = pin.neutral(model)
        qf[iq] = q
        pin.framesForwardKinematics(model, data, qf)
        return qf, data.oMf[fid].homogeneous.copy()

    rng = np.random.default_rng(4)
    for _ in range(25):
        q = np.ascontiguousarray(rng.uniform(model.lowerPositionLimit[iq], model.upperPositionLimit[iq]))
        qf, T = fk(q)
        Tc, Jc, gc = np.zeros(16), np.zeros(36), np.zeros(6)
        lib.arm_fk(q.ctypes.data_as(D), Tc.ctypes.data_as(D))
        lib.arm_jacobian(q.ctypes.data_as(D), Jc.ctypes.data_as(D))
        lib.arm_gravity(q.ctypes.data_as(D), gc.ctypes.data_as(D))
        assert np.abs(Tc.reshape(4, 4) - T).max() < 1e-12
        J = pin.computeFrameJacobian(model, data, qf, fid, pin.LOCAL_WORLD_ALIGNED)[:, iv]
        assert np.abs(Jc.reshape(6, 6) - np.vstack([J[3:], J[:3]])).max() < 1e-12
        g = pin.computeGeneralizedGravity(model, data, qf)[iv]
        assert np.abs(g).max() > 1e-2  # these files give inertias
        assert np.abs(gc - g).max() <= 1e-12 * np.abs(g).max()
        Tr = np.ascontiguousarray(T.ravel())
        qs = np.zeros(most * 6)
        k = lib.arm_ik(Tr.ctypes.data_as(D), qs.ctypes.data_as(D))
        assert k == len(ik_analytic(robot, T))  # the same number of solutions as the Python closed form
        assert k >= 1
        for s in qs.reshape(most, 6)[:k]:
            assert np.abs(fk(s)[1] - T).max() < 1e-9
