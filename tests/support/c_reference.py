"""The generated C of a maker's arm held against Pinocchio on the maker's own URDF (the xacro program's
expansion): built with gcc's strict flags into a shared library, then FK, the tip Jacobian, gravity, RNEA
and the closed-form IK compared at random configurations. Shared by the makers' codegen tests."""
import ctypes
import subprocess
import warnings

import numpy as np
import pinocchio as pin

from robokit.ik import ik_analytic
from xacro_reference import configuration

D = ctypes.POINTER(ctypes.c_double)


def build(gcc, folder, name="arm"):
    """``folder/name.c`` compiled with ``-std=c99 -Wall -Wextra -Wpedantic -Werror`` into a shared library
    (asserted to build), loaded with ctypes."""
    lib_path = folder / f"{name}.so"
    run = subprocess.run([gcc, "-std=c99", "-Wall", "-Wextra", "-Wpedantic", "-Werror", "-O1", "-shared", "-fPIC",
                          "-o", str(lib_path), str(folder / f"{name}.c"), "-lm"], capture_output=True, text=True)
    assert run.returncode == 0, run.stderr
    return ctypes.CDLL(str(lib_path))


def compare(lib, urdf, robot, header, *, tip=None, samples=25, lo=None, hi=None, rnea=True, ik=True,
            gravity_floor=1.0, count_ik=True, min_solutions=0):
    """Assert the library ``arm_*`` agrees with Pinocchio built from ``urdf`` at ``samples`` configurations
    drawn by ``default_rng(4)`` between ``lo`` and ``hi`` (default: the file's limits): the tip pose and its
    Jacobian (LOCAL_WORLD_ALIGNED, angular rows first in the C) to 1e-12, gravity and RNEA to 1e-12 of their
    largest entry (at least ``gravity_floor``), and with ``ik`` every C solution reaching the pose to 1e-9, as
    many as ``ik_analytic`` returns (``count_ik``) and at least ``min_solutions``. ``header``: the C header's
    text (its ``arm_MAX_SOLUTIONS``)."""
    model = pin.buildModelFromXML(urdf)
    data = model.createData()
    n = robot.n
    joints = [model.joints[model.getJointId(j)] for j in robot.joint_names]
    iq, iv = [j.idx_q for j in joints], [j.idx_v for j in joints]
    fid = model.getFrameId(tip or robot.tip)
    most = int(header.split("#define arm_MAX_SOLUTIONS ")[1].split()[0])
    lo = model.lowerPositionLimit[iq] if lo is None else lo
    hi = model.upperPositionLimit[iq] if hi is None else hi

    def fk(q):
        qf = configuration(model, joints, q)
        pin.framesForwardKinematics(model, data, qf)
        return qf, data.oMf[fid].homogeneous.copy()

    rng = np.random.default_rng(4)
    for _ in range(samples):
        q = np.ascontiguousarray(rng.uniform(lo, hi))
        qd, qdd = np.ascontiguousarray(rng.normal(size=n)), np.ascontiguousarray(rng.normal(size=n))
        qf, T = fk(q)
        Tc, Jc, gc, tc = np.zeros(16), np.zeros(6 * n), np.zeros(n), np.zeros(n)
        lib.arm_fk(q.ctypes.data_as(D), Tc.ctypes.data_as(D))
        lib.arm_jacobian(q.ctypes.data_as(D), Jc.ctypes.data_as(D))
        lib.arm_gravity(q.ctypes.data_as(D), gc.ctypes.data_as(D))
        assert np.abs(Tc.reshape(4, 4) - T).max() < 1e-12
        J = pin.computeFrameJacobian(model, data, qf, fid, pin.LOCAL_WORLD_ALIGNED)[:, iv]
        assert np.abs(Jc.reshape(6, n) - np.vstack([J[3:], J[:3]])).max() < 1e-12
        g = pin.computeGeneralizedGravity(model, data, qf)[iv]
        assert np.abs(gc - g).max() <= 1e-12 * max(np.abs(g).max(), gravity_floor)
        if rnea:
            lib.arm_rnea(q.ctypes.data_as(D), qd.ctypes.data_as(D), qdd.ctypes.data_as(D), tc.ctypes.data_as(D))
            v, a = np.zeros(model.nv), np.zeros(model.nv)
            v[iv], a[iv] = qd, qdd
            tau = pin.rnea(model, data, qf, v, a)[iv]
            assert np.abs(tc - tau).max() <= 1e-12 * max(np.abs(tau).max(), gravity_floor)
        if not ik:
            continue
        Tr = np.ascontiguousarray(T.ravel())
        qs = np.zeros(most * n)
        k = lib.arm_ik(Tr.ctypes.data_as(D), qs.ctypes.data_as(D))
        assert k >= min_solutions
        if count_ik:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")  # a pose near a singularity is said; the count is what is compared
                assert k == len(ik_analytic(robot, T))  # the same number of solutions as the Python closed form
        for s in qs.reshape(most, n)[:k]:
            assert np.abs(fk(s)[1] - T).max() < 1e-9
