"""The fold starts the calibrated IK's projected closed form gives at a pose (for the tests of
robokit.kernels.closed_form.FOLD_STARTS / FOLD_IMAG in tests/calibration and tests/codegen)."""
import math

import numpy as np

from robokit.ik.closed_form import AnalyticIK
from robokit.kernels import calibrated_ik as kci, closed_form as kcf


def fold_starts(robot, T):
    """(fold starts, positions at a fold of the joint-3 quartic, the least |cos θ₅| − 1 of a wrist
    that cannot reach the orientation) of the projected arm's closed form for the calibrated IK at T;
    for three parallel axes (its elbow's and shoulder's fold starts) (fold starts, 0, inf)."""
    arm = AnalyticIK(robot).calibrated
    Kn = arm._KC[kci._LEN:]
    ci, cf, C, post, T06, raw, codes, degen, qq, s = kcf._unpack(Kn, np.ascontiguousarray(T))
    fold = np.array([np.inf, 1.0, 0.0])
    if arm._kind != kcf.PIEPER:
        n = kcf._parallel_axes(cf, T06, 0.0, raw, codes, degen, s, fold)
        return int(np.count_nonzero(codes[:n, 2] >= kcf.FOLD_CODE)), 0, math.inf
    n = kcf._pieper(ci, cf, C, T06, 0.0, raw, codes, degen, s, fold)
    npos = kcf._pieper_position(ci, cf, C, T06, np.empty((16, 3)), np.empty((16, 2), np.int64),
                                np.empty(16, np.bool_), np.empty((16, 3)), np.empty((16, 6)), np.empty(50),
                                np.empty((2, 4)), fold)
    return int(np.count_nonzero(codes[:n, 2] >= kcf.FOLD_CODE)), npos - int(fold[2]), float(fold[0])
