"""``robokit codegen`` on collaborative arms as their makers publish them (tests/data/kinova/ros_kortex/SOURCE,
tests/data/niryo/SOURCE): the command line on the maker's xacro file with its arguments (``--xacro-arg
dof:=6``), the C compiled with ``gcc -std=c99 -Wall -Wextra -Wpedantic -Werror``, and its forward kinematics,
Jacobian, gravity torques, inverse dynamics and closed-form IK held against Pinocchio built directly from
the ``xacro`` program's expansion of the same file with the same arguments (not through robokit), at random
configurations within the file's limits (continuous joints over a turn)."""
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
from xacro_reference import configuration, xacro_urdfs

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
    lib_path = tmp_path / "arm.so"
    build = subprocess.run([gcc, "-std=c99", "-Wall", "-Wextra", "-Wpedantic", "-Werror", "-O1", "-shared", "-fPIC",
                            "-o", str(lib_path), str(tmp_path / "arm.c"), "-lm"], capture_output=True, text=True)
    assert build.returncode == 0, build.stderr
    lib = ctypes.CDLL(str(lib_path))
    D = ctypes.POINTER(ctypes.c_double)

    model = pin.buildModelFromXML(reference[label])
    data = model.createData()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        robot = robokit.load(path, xacro_args=args or None)
    n = robot.n
    joints = [model.joints[model.getJointId(j)] for j in robot.joint_names]
    iv = [j.idx_v for j in joints]
    fid = model.getFrameId(robot.tip)
    header = (tmp_path / "arm.h").read_text()
    assert f"#define arm_HAS_IK {int(has_ik)}" in header and f"#define arm_N {n}" in header
    most = int(header.split("#define arm_MAX_SOLUTIONS ")[1].split()[0])
    # the C's limits are the file's: a continuous joint (two coordinates in Pinocchio) unbounded
    qlim = np.array((ctypes.c_double * 2 * n).in_dll(lib, "arm_qlim"))
    file_lim = [[model.lowerPositionLimit[j.idx_q], model.upperPositionLimit[j.idx_q]] if j.nq == 1
                else [-np.inf, np.inf] for j in joints]
    assert qlim.tolist() == file_lim
    lo, hi = np.asarray(robot.qlim, float).T
    lo, hi = np.where(np.isfinite(lo), lo, -np.pi), np.where(np.isfinite(hi), hi, np.pi)

    def fk(q):
        qf = configuration(model, joints, q)
        pin.framesForwardKinematics(model, data, qf)
        return qf, data.oMf[fid].homogeneous.copy()

    rng = np.random.default_rng(4)
    for _ in range(25):
        q = np.ascontiguousarray(rng.uniform(lo, hi))
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
        assert np.abs(gc - g).max() <= 1e-12 * max(np.abs(g).max(), 1.0)
        v, a = np.zeros(model.nv), np.zeros(model.nv)
        v[iv], a[iv] = qd, qdd
        tau = pin.rnea(model, data, qf, v, a)[iv]
        assert np.abs(tc - tau).max() <= 1e-12 * max(np.abs(tau).max(), 1.0)
        if not has_ik:
            continue
        Tr = np.ascontiguousarray(T.ravel())
        qs = np.zeros(most * n)
        k = lib.arm_ik(Tr.ctypes.data_as(D), qs.ctypes.data_as(D))
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")  # a pose near a singularity is said; the count is what is compared
            assert k == len(ik_analytic(robot, T))  # the same number of solutions as the Python closed form
        for s in qs.reshape(most, n)[:k]:
            assert np.abs(fk(s)[1] - T).max() < 1e-9
