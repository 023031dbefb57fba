"""Craig's DH Newton–Euler, the Coriolis matrix, friction, payload, base wrench, Cartesian
dynamics and energy — against Pinocchio, finite differences and hand-computed cases."""
import importlib.util
import pathlib

import numpy as np
import pinocchio as pin
import pytest

import robokit as rk
from shared_robots import robot as shared_robot
from robokit.dynamics import (
    add_payload, base_wrench, cartesian_dynamics, coriolis_matrix, dh_inverse_dynamics, friction_torques, integrate,
    total_energy,
)


def _factory():
    spec = importlib.util.spec_from_file_location("desc_conftest", pathlib.Path(__file__).parents[1] / "description" / "conftest.py")
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod.make_random_dh_table


@pytest.fixture(scope="module")
def robots():
    rng = np.random.default_rng(9)
    make = _factory()
    out = {n: shared_robot(n) for n in ["twolink", "rrr", "puma560", "ur5", "panda", "kinova"]}
    out["random_standard"] = rk.load(make(rng, 5, "standard", prismatic=(1, 3)))
    out["random_modified"] = rk.load(make(rng, 5, "modified", prismatic=(0, 2)))
    return out


def rel(a, b):
    return np.abs(np.asarray(a) - b).max() / max(1.0, np.abs(b).max())


@pytest.mark.parametrize("name", ["twolink", "rrr", "puma560", "random_standard", "random_modified"])
def test_craig_newton_euler_vs_rnea(name, robots):
    r = robots[name]
    rng = np.random.default_rng(0)
    for _ in range(100):
        q, dq, ddq, F = r.random_configuration(rng), rng.normal(size=r.n), rng.normal(size=r.n), rng.normal(size=6)
        ref = r.rnea(q, dq, ddq) + r.jacobian(q, reference="local").T @ F
        assert rel(dh_inverse_dynamics(r.dh, q, dq, ddq, F_tip=F, trace=False), ref) < 1e-9


@pytest.mark.parametrize("name", ["twolink", "puma560", "ur5", "panda", "kinova"])
def test_coriolis_matrix(name, robots):
    r = robots[name]
    p = r.poe
    rng = np.random.default_rng(1)
    for _ in range(30):
        q, dq = r.random_configuration(rng), rng.normal(size=r.n)
        C = coriolis_matrix(q, dq, p.Mlist, p.Glist, p.Slist)
        assert rel(C @ dq, r.nonlinear_effects(q, dq) - r.gravity_torques(q)) < 1e-9
        assert rel(C, pin.computeCoriolisMatrix(r.model, r.model.createData(), r.q_pin(q), dq)) < 1e-9
        h = 1e-6  # Ṁ by finite differences along q̇
        Md = (rk.mass_matrix(q + h * dq, p.Mlist, p.Glist, p.Slist) - rk.mass_matrix(q - h * dq, p.Mlist, p.Glist, p.Slist)) / (2 * h)
        N = Md - 2 * C
        assert np.abs(N + N.T).max() < 1e-7 * max(1.0, np.abs(Md).max())


def test_twolink_closed_form_B_C_and_payload(robots):
    r = robots["twolink"]
    p = r.poe
    l1, l2, m1, m2 = r.dh.links[0].a, r.dh.links[1].a, r.dh.links[0].mass, r.dh.links[1].mass
    q, dq = np.array([0.3, 1.1]), np.array([0.7, -0.4])
    s2 = np.sin(q[1])
    c_lecture = np.array([-2 * m2 * l1 * l2 * s2 * dq[0] * dq[1] - m2 * l1 * l2 * s2 * dq[1] ** 2,
                          m2 * l1 * l2 * s2 * dq[0] ** 2])  # B[q̇q̇] + C[q̇²] of Lecture 7
    assert np.allclose(coriolis_matrix(q, dq, p.Mlist, p.Glist, p.Slist) @ dq, c_lecture)
    # a point payload at the tool of the point-mass arm acts as extra mass m2
    mp = 0.7
    G2 = add_payload(p.Mlist, p.Glist, mp)
    c1, c2, c12 = np.cos(q[0]), np.cos(q[1]), np.cos(q.sum())
    m2p = m2 + mp
    M_ref = np.array([[l2**2 * m2p + 2 * l1 * l2 * m2p * c2 + l1**2 * (m1 + m2p), l2**2 * m2p + l1 * l2 * m2p * c2],
                      [l2**2 * m2p + l1 * l2 * m2p * c2, l2**2 * m2p]])
    g_ref = 9.81 * np.array([m2p * l2 * c12 + (m1 + m2p) * l1 * c1, m2p * l2 * c12])
    assert np.allclose(rk.mass_matrix(q, p.Mlist, G2, p.Slist), M_ref)
    assert np.allclose(rk.gravity_forces(q, r.gravity, p.Mlist, G2, p.Slist), g_ref)


def test_payload_with_offset_matches_pinocchio(robots):
    r = robots["ur5"]
    p = r.poe
    com = np.array([0.02, -0.01, 0.05])
    I = np.diag([0.01, 0.02, 0.015])
    G2 = add_payload(p.Mlist, p.Glist, 1.3, com, I)
    model = r.model.copy()
    fid = r.tip_id
    frame = model.frames[fid]
    Y = pin.Inertia(1.3, frame.placement.act(com), frame.placement.rotation @ I @ frame.placement.rotation.T)
    model.appendBodyToJoint(frame.parentJoint, Y, pin.SE3.Identity())
    data = model.createData()
    rng = np.random.default_rng(2)
    for _ in range(10):
        q, dq, ddq = r.random_configuration(rng), rng.normal(size=6), rng.normal(size=6)
        assert rel(rk.inverse_dynamics(q, dq, ddq, r.gravity, np.zeros(6), p.Mlist, G2, p.Slist),
                   pin.rnea(model, data, q, dq, ddq)) < 1e-9


def test_friction_hand_computed(robots):
    t = robots["puma560"].dh
    dq = np.array([0.5, -0.2, 0.0, 1.0, -1.0, 0.3])
    tau = friction_torques(t, dq)
    l = t.links[0]
    assert np.isclose(tau[0], l.G**2 * l.B * 0.5 + abs(l.G) * l.Tc[0])
    l = t.links[1]
    assert np.isclose(tau[1], l.G**2 * l.B * -0.2 + abs(l.G) * l.Tc[1])
    assert tau[2] == 0.0


def test_base_wrench(robots):
    for name in ("puma560", "ur5"):
        r = robots[name]
        p = r.poe
        rng = np.random.default_rng(3)
        marm = sum(Y.mass for Y in list(r.model.inertias)[1:])
        for _ in range(10):
            q, dq, ddq = r.random_configuration(rng), rng.normal(size=r.n), rng.normal(size=r.n)
            W = base_wrench(q, dq, ddq, r.gravity, np.zeros(6), p.Mlist, p.Glist, p.Slist)
            d = r.model.createData()
            pin.centerOfMass(r.model, d, r.q_pin(q), dq, ddq)
            assert np.abs(W[3:] - (d.mass[0] * d.acom[0] - marm * r.gravity)).max() < 1e-9  # Newton for the arm
        W0 = base_wrench(q, np.zeros(r.n), np.zeros(r.n), r.gravity, np.zeros(6), p.Mlist, p.Glist, p.Slist)
        assert np.allclose(W0[3:], -marm * r.gravity)  # at rest: the weight
        # joint 1 of both arms turns about the base z axis: the base's moment about z is joint 1's torque
        assert np.isclose(W0[2], r.rnea(q, np.zeros(r.n), np.zeros(r.n))[0], atol=1e-9)


def test_cartesian_dynamics(robots):
    r = robots["ur5"]
    rng = np.random.default_rng(4)
    q, dq = r.random_configuration(rng), rng.normal(size=6)
    cd = cartesian_dynamics(r, q, dq)
    J = r.jacobian(q, reference="local_world_aligned")
    M = r.crba(q)
    assert np.allclose(cd.Lambda, np.linalg.inv(J @ np.linalg.solve(M, J.T)))
    # F = Λ ẍ + μ + p reproduces τ = Jᵀ F for any q̈ (square, non-singular J)
    ddq = rng.normal(size=6)
    h = 1e-6
    Jd_dq = (r.jacobian(q + h * dq, reference="local_world_aligned") - r.jacobian(q - h * dq, reference="local_world_aligned")) / (2 * h) @ dq
    xdd = J @ ddq + Jd_dq
    F = cd.Lambda @ xdd + cd.mu + cd.p
    assert rel(J.T @ F, r.rnea(q, dq, ddq)) < 1e-6
    assert 0 < cd.asada <= 1 and cd.yoshikawa > 0


def test_energy_conserved_in_free_swing(robots):
    r = robots["twolink"]
    p = r.poe
    q0, dq0 = np.array([0.4, -0.3]), np.array([0.0, 0.0])
    T, Q, D = integrate(q0, dq0, lambda t, q, dq: np.zeros(2), r.gravity, p.Mlist, p.Glist, p.Slist, 1e-3, 1000, "rk4")
    E = np.array([total_energy(r, q, dq) for q, dq in zip(Q[::50], D[::50])])
    assert np.abs(Q[-1] - q0).max() > 0.1  # it really swung
    assert np.abs(E - E[0]).max() < 1e-8 * 100  # drift below 1e-6 J over 1 s (RK4, 1 ms)
    _, Qe, De = integrate(q0, dq0, lambda t, q, dq: np.zeros(2), r.gravity, p.Mlist, p.Glist, p.Slist, 1e-3, 1000, "euler")
    Ee = total_energy(r, Qe[-1], De[-1])
    assert abs(Ee - E[0]) > 100 * np.abs(E - E[0]).max()  # explicit Euler gains energy: much worse


def test_twolink_closed_form_against_recursive(robots):
    from robokit.dynamics import twolink_dynamics

    r = robots["twolink"]
    p = r.poe
    l1, l2, m1, m2 = r.dh.links[0].a, r.dh.links[1].a, r.dh.links[0].mass, r.dh.links[1].mass
    rng = np.random.default_rng(5)
    for _ in range(50):
        q, dq, ddq = rng.uniform(-np.pi, np.pi, 2), rng.normal(size=2), rng.normal(size=2)
        cf = twolink_dynamics(q, dq, l1, l2, m1, m2)
        assert np.allclose(cf["M"], r.crba(q)) and np.allclose(cf["G"], r.gravity_torques(q))
        assert np.allclose(cf["V"], rk.vel_quadratic_forces(q, dq, p.Mlist, p.Glist, p.Slist))
        assert np.allclose(cf["B"][:, 0] * dq[0] * dq[1] + cf["C"] @ dq**2, cf["V"])
        tau = cf["M"] @ ddq + cf["V"] + cf["G"]
        assert np.allclose(tau, dh_inverse_dynamics(r.dh, q, dq, ddq, trace=False)) and np.allclose(tau, r.rnea(q, dq, ddq))


def test_a_column_of_joint_values_is_named_as_not_a_batch():
    """A (6, 1) column was refused with "thetalist: expected shape (n, 6)", which reads as if six joints were
    too many; the message now gives both forms the function takes."""
    import robokit as rk
    from robokit.errors import InputError

    p = rk.load("puma560").poe
    with pytest.raises(InputError, match=r"thetalist: expected shape \(6,\) or \(N, 6\) for 6 joints, got shape \(6, 1\)"):
        rk.inverse_dynamics(np.zeros((6, 1)), np.zeros(6), np.zeros(6), [0, 0, -9.81], np.zeros(6), p.Mlist, p.Glist,
                            p.Slist)
    batch = rk.inverse_dynamics(np.zeros((2, 6)), np.zeros((2, 6)), np.zeros((2, 6)), [0, 0, -9.81], np.zeros(6),
                                p.Mlist, p.Glist, p.Slist)
    one = rk.inverse_dynamics(np.zeros(6), np.zeros(6), np.zeros(6), [0, 0, -9.81], np.zeros(6), p.Mlist, p.Glist, p.Slist)
    assert np.array_equal(batch, np.stack([one, one]))
