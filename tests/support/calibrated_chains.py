"""Random six-joint chains for the calibrated IK's tests (``tests/calibration``): revolute joints with
and without a screw pitch, prismatic joints, and consecutive axes that intersect, are exactly
parallel, or are parallel up to 1e-14…1e-2 rad; and the packed chain's pose and Jacobian as plain
Python (:mod:`robokit.kernels.calibrated_ik`)."""
import numpy as np
import modern_robotics as mr

from robokit.kernels import calibrated_ik as kci


def _unit(v):
    return v / np.linalg.norm(v)


def _chain(seed):
    rng = np.random.default_rng(seed)
    S = np.zeros((6, 6))
    w = _unit(rng.normal(size=3))
    p = rng.uniform(-0.5, 0.5, 3)
    for i in range(6):
        case = rng.integers(0, 5)
        if i and case == 0:  # parallel to the previous axis, up to a small tilt
            tilt = 0.0 if rng.random() < 0.5 else 10.0 ** rng.uniform(-14, -2)
            w = _unit(w + tilt * _unit(np.cross(w, rng.normal(size=3))))
            p = p + rng.uniform(-0.5, 0.5, 3)
        elif i and case == 1:  # through the previous axis' point: intersecting
            w = _unit(rng.normal(size=3))
        else:
            w = _unit(rng.normal(size=3))
            p = rng.uniform(-0.5, 0.5, 3)
        if rng.random() < 0.15:  # prismatic
            S[3:, i] = _unit(rng.normal(size=3))
        else:
            h = 0.0 if rng.random() < 0.7 else rng.uniform(-0.2, 0.2)
            S[:3, i], S[3:, i] = w, -np.cross(w, p) + h * w
    M = mr.RpToTrans(mr.MatrixExp3(mr.VecToso3(rng.normal(size=3))), rng.uniform(-1, 1, 3))
    return S, M, rng.uniform(-np.pi, np.pi, 6)


def _pose_and_jacobian(C, q):
    sc, T, J = np.empty((2, 6)), np.empty((4, 4)), np.empty((6, 6))
    kci._trig.py_func(C, q, sc)
    kci.fk_jacobian.py_func(C, q, sc, T, J)
    return T, J
