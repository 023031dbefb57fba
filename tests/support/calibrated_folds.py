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


#: Configurations of the suite's calibrated UR5 (``shared_robots.calibrated("ur5", 2)``; ``default_rng(300)``:
#: draws of random configurations with θ₅ redrawn within 3 mrad of its singularity at every other draw) where, near the wrist's
#: singularity, the projected arm's θ₆ (from a direction a few 1e-3 long) is far from the arm's and
#: every elbow misses by more than the fold starts' window (33 of 3,000 such near-singular draws had no
#: start at all; the first is draw 822, the pose of the general method's test before).
UR5_FREE_WRIST = [
    [-6.097088124678061, -2.4447867094205846, -0.07971101273569436, 4.8251377569183465, -0.0027800233706754872,
     2.12722578454448],
    [6.187202062957459, -5.765610248787899, -0.10697327224229491, 4.621419745303653, 0.0011243988430799995,
     -2.2689770613654536],
    [0.23593318250380513, -2.50656008613383, -0.27894638658711246, -0.9531197606863886, -0.0009575752660218543,
     -3.767474576485674],
    [1.6733243191326919, -2.8258150132817956, -0.3554070237299043, 3.7950037318138463, 0.0023660264456727437,
     2.546079101862892]]
