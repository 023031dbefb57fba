"""Validation rows for dynamics: the course's PoE Newton–Euler, CRBA and forward dynamics vs Pinocchio."""
from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike

from robokit.validation.core import CheckRow, models, robot as load

SAMPLES = 50


def _rel(a: ArrayLike, b: np.ndarray) -> float:
    return float(np.abs(np.asarray(a) - np.asarray(b)).max() / max(1.0, np.abs(b).max()))


def checks(rng: np.random.Generator) -> list[CheckRow]:
    from robokit.dynamics.newton_euler import forward_dynamics, gravity_forces, inverse_dynamics, mass_matrix

    rows = []
    z6 = np.zeros(6)
    for name in models():
        r = load(name)
        p = r.poe
        args = (p.Mlist, p.Glist, p.Slist)
        e_id = e_m = e_g = e_fd = 0.0
        n_fd = 0
        for _ in range(SAMPLES):
            q, dq, ddq = r.random_configuration(rng), rng.normal(size=r.n), rng.normal(size=r.n)
            tau = rng.normal(size=r.n) * 5
            e_id = max(e_id, _rel(inverse_dynamics(q, dq, ddq, r.gravity, z6, *args), r.rnea(q, dq, ddq)))
            M = r.crba(q)
            e_m = max(e_m, _rel(mass_matrix(q, *args), M))
            e_g = max(e_g, _rel(gravity_forces(q, r.gravity, *args), r.gravity_torques(q)))
            if np.linalg.eigvalsh(M).min() > 1e-12 * max(1.0, np.abs(M).max()):  # else no forward dynamics
                n_fd += 1
                e_fd = max(e_fd, _rel(forward_dynamics(q, dq, tau, r.gravity, z6, *args), r.aba(q, dq, tau)))
        singular = (f"M singular at {SAMPLES - n_fd} of {SAMPLES} samples (a joint drives no mass: the file gives "
                    "none there), forward dynamics not compared there" if n_fd < SAMPLES else "")
        rows += [
            CheckRow("inverse_dynamics (PoE Newton–Euler) vs pinocchio.rnea", name, SAMPLES, e_id, 1e-9, "rel, max entry"),
            CheckRow("mass_matrix (PoE CRBA) vs pinocchio.crba", name, SAMPLES, e_m, 1e-9, "rel, max entry", singular),
            CheckRow("gravity_forces vs computeGeneralizedGravity", name, SAMPLES, e_g, 1e-9, "rel, max entry"),
        ]
        if n_fd:
            rows.append(CheckRow("forward_dynamics vs pinocchio.aba", name, n_fd, e_fd, 1e-9, "rel, max entry"))
    import pinocchio as pin

    from robokit.dynamics.dh_newton_euler import dh_inverse_dynamics
    from robokit.dynamics.coriolis import coriolis_matrix

    for name in models():
        r = load(name)
        p = r.poe
        e_c = e_dh = 0.0
        data = r.model.createData()
        for _ in range(SAMPLES):
            q, dq, ddq = r.random_configuration(rng), rng.normal(size=r.n), rng.normal(size=r.n)
            Cp = pin.computeCoriolisMatrix(r.model, data, r.q_pin(q), dq)
            e_c = max(e_c, _rel(coriolis_matrix(q, dq, p.Mlist, p.Glist, p.Slist), Cp))
            if r.dh is not None:
                e_dh = max(e_dh, _rel(dh_inverse_dynamics(r.dh, q, dq, ddq, trace=False), r.rnea(q, dq, ddq)))
        rows.append(CheckRow("coriolis_matrix (PoE, Ṁ − 2C skew) vs computeCoriolisMatrix", name, SAMPLES, e_c, 1e-9,
                             "rel, max entry"))
        if r.dh is not None:
            rows.append(CheckRow("DH Newton–Euler (Craig) vs pinocchio.rnea", name, SAMPLES, e_dh, 1e-9,
                                 "rel, max entry"))
    return rows
