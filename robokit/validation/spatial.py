"""Validation rows for the spatial layer: the seed functions against Pinocchio's Lie-group routines.

Samples: random rotations with angles uniform in [0, π], plus angles within 1e-6 of 0 and
of π and exactly π about random and coordinate axes; twists with those rotation parts and
random translations, plus pure translations. Pinocchio orders twists (v, ω); robokit (ω, v).
"""
from __future__ import annotations

import numpy as np

from robokit.validation.core import CheckRow

N = 3000


def _axes_angles(rng: np.random.Generator) -> tuple[np.ndarray, np.ndarray]:
    axes = rng.normal(size=(N, 3))
    axes /= np.linalg.norm(axes, axis=1, keepdims=True)
    angles = rng.uniform(0.0, np.pi, N)
    k = N // 6
    angles[:k] = rng.uniform(0, 1e-6, k)  # near 0
    angles[k:2 * k] = np.pi - rng.uniform(0, 1e-6, k)  # near π
    angles[2 * k:2 * k + 30] = np.pi  # exactly π
    axes[2 * k:2 * k + 3] = np.eye(3)  # … about the coordinate axes (the three branches)
    return axes, angles


def checks(rng: np.random.Generator) -> list[CheckRow]:
    import pinocchio as pin

    import robokit.spatial as rk

    axes, angles = _axes_angles(rng)
    e_exp3 = e_log3 = e_exp6 = e_log6 = e_adj = e_ad = e_inv = 0.0
    for w_hat, th in zip(axes, angles):
        w = w_hat * th
        R = rk.matrix_exp_3(rk.vec_to_so3(w))
        R_pin = pin.exp3(w)
        e_exp3 = max(e_exp3, np.abs(R - R_pin).max())
        # log: compare exp(log(R)) with R (the axis sign at exactly π is a free choice) and the angle
        L = rk.matrix_log_3(R_pin)
        e_log3 = max(e_log3, np.abs(rk.matrix_exp_3(L) - R_pin).max(),
                     abs(np.linalg.norm(rk.so3_to_vec(L)) - np.linalg.norm(pin.log3(R_pin))))
        v = rng.normal(size=3)
        V = np.r_[w, v]
        T = rk.matrix_exp_6(rk.vec_to_se3(V))
        M_pin = pin.exp6(pin.Motion(v, w))
        e_exp6 = max(e_exp6, np.abs(T - M_pin.homogeneous).max())
        L6 = rk.matrix_log_6(M_pin.homogeneous)
        e_log6 = max(e_log6, np.abs(rk.matrix_exp_6(L6) - M_pin.homogeneous).max())
        if th < np.pi - 1e-3:  # away from π the log is unique: compare with Pinocchio directly
            m = pin.log6(M_pin)
            e_log6 = max(e_log6, np.abs(rk.se3_to_vec(L6) - np.r_[m.angular, m.linear]).max())
        X = rng.normal(size=6)
        a = M_pin.act(pin.Motion(X[3:], X[:3]))
        e_adj = max(e_adj, np.abs(rk.adjoint(T) @ X - np.r_[a.angular, a.linear]).max())
        b = pin.Motion(v, w).cross(pin.Motion(X[3:], X[:3]))
        e_ad = max(e_ad, np.abs(rk.ad(V) @ X - np.r_[b.angular, b.linear]).max())
        e_inv = max(e_inv, np.abs(rk.trans_inv(T) - M_pin.inverse().homogeneous).max())
    # pure translations
    e_tr = 0.0
    for p in rng.normal(size=(200, 3)):
        T = rk.matrix_exp_6(rk.vec_to_se3(np.r_[0, 0, 0, p]))
        e_tr = max(e_tr, np.abs(T - pin.exp6(pin.Motion(p, np.zeros(3))).homogeneous).max(),
                   np.abs(rk.se3_to_vec(rk.matrix_log_6(T)) - np.r_[0, 0, 0, p]).max())
    ref = "abs, max entry"
    return [
        CheckRow("matrix_exp_3 vs pinocchio.exp3 (θ ∈ [0, π], near 0/π)", "-", N, e_exp3, 1e-9, ref),
        CheckRow("matrix_log_3: exp(log R) = R and θ vs pinocchio.log3", "-", N, e_log3, 1e-9, ref),
        CheckRow("matrix_exp_6 vs pinocchio.exp6", "-", N, e_exp6, 1e-9, ref),
        CheckRow("matrix_log_6 vs pinocchio.log6, exp(log T) = T", "-", N, e_log6, 1e-9, ref),
        CheckRow("exp/log_6 of pure translations vs pinocchio.exp6", "-", 200, e_tr, 1e-9, ref),
        CheckRow("adjoint(T) X vs pinocchio SE3.act(Motion)", "-", N, e_adj, 1e-9, ref),
        CheckRow("ad(V) X vs pinocchio Motion.cross", "-", N, e_ad, 1e-9, ref),
        CheckRow("trans_inv vs pinocchio SE3.inverse", "-", N, e_inv, 1e-9, ref),
    ]
