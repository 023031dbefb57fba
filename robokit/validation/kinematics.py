"""Validation rows for kinematics: PoE FK and Jacobians (course code) vs Pinocchio."""
from __future__ import annotations

import numpy as np

from robokit.validation.core import MODELS, SHIPPED, CheckRow, models, robot as load

SAMPLES = 100


def checks(rng: np.random.Generator) -> list[CheckRow]:
    from robokit.kinematics.poe import fkin_body, fkin_space, jacobian_body, jacobian_space

    rows = []
    for name in models():
        r = load(name)
        p = r.poe
        Q = np.array([r.random_configuration(rng) for _ in range(SAMPLES)])
        Ts = fkin_space(p.M, p.Slist, Q)
        Tb = fkin_body(p.M, p.Blist, Q)
        Js = jacobian_space(p.Slist, Q)
        Jb = jacobian_body(p.Blist, Q)
        e_fk = e_js = e_jb = 0.0
        for k, q in enumerate(Q):
            T = r.frame_pose(q)
            e_fk = max(e_fk, np.abs(Ts[k] - T).max(), np.abs(Tb[k] - T).max())
            e_js = max(e_js, np.abs(Js[k] - r.jacobian(q, reference="world")).max())
            e_jb = max(e_jb, np.abs(Jb[k] - r.jacobian(q, reference="local")).max())
        rows += [
            CheckRow("fkin_space / fkin_body vs Pinocchio FK", name, SAMPLES, e_fk, 1e-9, "abs, max entry"),
            CheckRow("jacobian_space vs computeFrameJacobian (WORLD)", name, SAMPLES, e_js, 1e-9, "abs, max entry"),
            CheckRow("jacobian_body vs computeFrameJacobian (LOCAL)", name, SAMPLES, e_jb, 1e-9, "abs, max entry"),
        ]
    from robokit.kinematics.dh import dh_jacobian, dh_static_torques

    for name in (SHIPPED if models() == MODELS else [m for m in models() if load(m).dh is not None]):
        r = load(name)
        assert r.dh is not None  # a shipped DH model (or the one robot validated, when it is one)
        e_b = e_t = e_f = 0.0
        for _ in range(SAMPLES):
            q = r.random_configuration(rng)
            e_b = max(e_b, np.abs(dh_jacobian(r.dh, q, "local_world_aligned") - r.jacobian(q, reference="local_world_aligned")).max())
            Jt = r.jacobian(q, reference="local")
            e_t = max(e_t, np.abs(dh_jacobian(r.dh, q, "local") - Jt).max())
            F = rng.normal(size=6)
            e_f = max(e_f, np.abs(dh_static_torques(r.dh, q, F, reference="local") - Jt.T @ F).max())
        rows += [
            CheckRow("DH propagation Jacobian (base) vs computeFrameJacobian (LOCAL_WORLD_ALIGNED)", name, SAMPLES,
                     e_b, 1e-9, "abs, max entry"),
            CheckRow("DH propagation Jacobian (tool) vs computeFrameJacobian (LOCAL)", name, SAMPLES, e_t, 1e-9,
                     "abs, max entry"),
            CheckRow("inward force propagation τ vs Jᵀ F (Pinocchio LOCAL Jacobian)", name, SAMPLES, e_f, 1e-9,
                     "abs, max entry"),
        ]
    return rows
