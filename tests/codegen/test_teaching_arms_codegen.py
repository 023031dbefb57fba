"""``robokit codegen`` on the arms courses and student teams own, from their makers' files
(tests/data/<maker>/SOURCE) with the makers' launch arguments given on the command line: the C compiled with
``gcc -std=c99 -Wall -Wextra -Wpedantic -Werror``, and its forward kinematics, Jacobian, gravity torques,
inverse dynamics and (where there is one) closed-form IK held against Pinocchio built directly from the
``xacro`` program's expansion of the same file with the same arguments (the myCobot's URDF file itself), at
random configurations within the file's limits."""
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
    lib_path = tmp_path / "arm.so"
    build = subprocess.run([gcc, "-std=c99", "-Wall", "-Wextra", "-Wpedantic", "-Werror", "-O1", "-shared", "-fPIC",
                            "-o", str(lib_path), str(tmp_path / "arm.c"), "-lm"], capture_output=True, text=True)
    assert build.returncode == 0, build.stderr
    lib = ctypes.CDLL(str(lib_path))
    D = ctypes.POINTER(ctypes.c_double)

    text = path.read_text() if args is None else xacro_urdfs({label: (DATA / maker, rel, args)})[label]
    model = pin.buildModelFromXML(text)
    data = model.createData()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        robot = robokit.load(path, TIPS.get(label), xacro_args=args or None)
    joints = [model.joints[model.getJointId(j)] for j in robot.joint_names]
    iq, iv = [j.idx_q for j in joints], [j.idx_v for j in joints]
    fid = model.getFrameId(TIPS.get(label, robot.tip))
    header = (tmp_path / "arm.h").read_text()
    assert f"#define arm_HAS_IK {int(has_ik)}" in header and f"#define arm_N {n}" in header
    most = int(header.split("#define arm_MAX_SOLUTIONS ")[1].split()[0])

    def fk(q):
        qf = pin.neutral(model)
        qf[iq] = q
        pin.framesForwardKinematics(model, data, qf)
        return qf, data.oMf[fid].homogeneous.copy()

    rng = np.random.default_rng(4)
    for _ in range(20):
        q = np.ascontiguousarray(rng.uniform(model.lowerPositionLimit[iq], model.upperPositionLimit[iq]))
        qd, qdd = np.ascontiguousarray(rng.normal(size=n)), np.ascontiguousarray(rng.normal(size=n))
        qf, T = fk(q)
        Tc, Jc, gc, tc = np.zeros(16), np.zeros(6 * n), np.zeros(n), np.zeros(n)
        lib.arm_fk(q.ctypes.data_as(D), Tc.ctypes.data_as(D))
        lib.arm_jacobian(q.ctypes.data_as(D), Jc.ctypes.data_as(D))
        lib.arm_gravity(q.ctypes.data_as(D), gc.ctypes.data_as(D))
        lib.arm_rnea(q.ctypes.data_as(D), qd.ctypes.data_as(D), qdd.ctypes.data_as(D), tc.ctypes.data_as(D))
        assert np.abs(Tc.reshape(4, 4) - T).max() < 1e-12
        J = pin.computeFrameJacobian(model, data, qf, fid, pin.LOCAL_WORLD_ALIGNED)[:, iv]
        assert np.abs(Jc.reshape(6, n) - np.vstack([J[3:], J[:3]])).max() < 1e-12
        g = pin.computeGeneralizedGravity(model, data, qf)[iv]
        assert np.abs(gc - g).max() <= 1e-12 * np.abs(g).max()
        v, a = np.zeros(model.nv), np.zeros(model.nv)
        v[iv], a[iv] = qd, qdd
        tau = pin.rnea(model, data, qf, v, a)[iv]
        assert np.abs(tc - tau).max() <= 1e-12 * np.abs(tau).max()
        if has_ik:
            Tr = np.ascontiguousarray(T.ravel())
            qs = np.zeros(most * n)
            k = lib.arm_ik(Tr.ctypes.data_as(D), qs.ctypes.data_as(D))
            assert k == len(ik_analytic(robot, T)) > 0  # as many solutions as the Python closed form
            for s in qs.reshape(most, n)[:k]:
                assert np.abs(fk(s)[1] - T).max() < 1e-9
