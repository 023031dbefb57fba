"""The compiled DH kernels against Pinocchio (shipped DH models, random tables of both conventions
with prismatic joints, and DH tables extracted from URDF arms) and batched against per-call."""
import importlib.util
import pathlib

import numpy as np
import pytest

import robokit as rk
from shared_robots import robot as shared_robot
from robokit.kernels import dh as kdh


def _random_table_factory():
    spec = importlib.util.spec_from_file_location(
        "desc_conftest_k", pathlib.Path(__file__).parents[1] / "description" / "conftest.py")
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod.make_random_dh_table


def _cases():
    make = _random_table_factory()
    out = [(name, rk.load(name)) for name in ("twolink", "rrr", "puma560")]
    for conv in ("standard", "modified"):
        table = make(np.random.default_rng(7), 6, conv, prismatic=(1, 4))
        out.append((f"random-{conv}", rk.load(table)))
    return out


@pytest.fixture(scope="module")
def cases():
    return _cases()


def test_dh_kernels_vs_pinocchio(cases):
    rng = np.random.default_rng(0)
    for name, r in cases:
        packed = kdh.pack_dh(r.dh)
        P, mod, base, tool = packed[:4]
        g = r.gravity.copy()  # writeable, as the kernels take it
        for _ in range(30):
            q = r.random_configuration(rng)
            dq, ddq, F = rng.normal(size=r.n), rng.normal(size=r.n), rng.normal(size=6)
            assert np.abs(kdh.dh_fk(P, mod, base, tool, q) - r.frame_pose(q)).max() < 1e-9, name
            Jl = r.jacobian(q, reference="local")
            assert np.abs(kdh.dh_jacobian(P, mod, base, tool, q, 0)
                          - r.jacobian(q, reference="local_world_aligned")).max() < 1e-9, name
            assert np.abs(kdh.dh_jacobian(P, mod, base, tool, q, 1) - Jl).max() < 1e-9, name
            assert np.abs(kdh.dh_static_torques(P, mod, base, tool, q, F) - Jl.T @ F).max() < 1e-9, name
            tau = kdh.dh_inverse_dynamics(*packed, q, dq, ddq, g, F)
            ref = r.rnea(q, dq, ddq) + Jl.T @ F
            assert np.abs(tau - ref).max() <= 1e-9 * max(1.0, np.abs(ref).max()), name


@pytest.mark.parametrize("arm", ["ur5", "panda"])
@pytest.mark.parametrize("convention", ["standard", "modified"])
def test_dh_kernels_on_tables_from_urdf(arm, convention):
    r = shared_robot(arm)
    res = rk.dh_from_urdf(r, convention=convention)
    assert res.exact
    P, mod, base, tool = kdh.pack_dh(res.table)[:4]
    rng = np.random.default_rng(1)
    for _ in range(30):
        q = r.random_configuration(rng)
        assert np.abs(kdh.dh_fk(P, mod, base, tool, q) - r.frame_pose(q)).max() < 1e-9
        Jl = r.jacobian(q, reference="local")
        assert np.abs(kdh.dh_jacobian(P, mod, base, tool, q, 1) - Jl).max() < 1e-9
        assert np.abs(kdh.dh_jacobian(P, mod, base, tool, q, 0)
                      - r.jacobian(q, reference="local_world_aligned")).max() < 1e-9
        F = rng.normal(size=6)
        assert np.abs(kdh.dh_static_torques(P, mod, base, tool, q, F) - Jl.T @ F).max() < 1e-9


def test_dh_batched_equal_per_call(cases):
    rng = np.random.default_rng(2)
    for name, r in cases:
        packed = kdh.pack_dh(r.dh)
        P, mod, base, tool = packed[:4]
        g = r.gravity.copy()  # writeable, as the kernels take it
        N = 150
        Q = np.ascontiguousarray([r.random_configuration(rng) for _ in range(N)])
        D, A, F = rng.normal(size=(N, r.n)), rng.normal(size=(N, r.n)), rng.normal(size=(N, 6))
        fk = kdh.dh_fk_batch(P, mod, base, tool, Q)
        J0 = kdh.dh_jacobian_batch(P, mod, base, tool, Q, 0)
        J1 = kdh.dh_jacobian_batch(P, mod, base, tool, Q, 1)
        st = kdh.dh_static_torques_batch(P, mod, base, tool, Q, F)
        tau = kdh.dh_inverse_dynamics_batch(*packed, Q, D, A, g, F)
        for k in range(N):
            pairs = [(fk[k], kdh.dh_fk(P, mod, base, tool, Q[k])),
                     (J0[k], kdh.dh_jacobian(P, mod, base, tool, Q[k], 0)),
                     (J1[k], kdh.dh_jacobian(P, mod, base, tool, Q[k], 1)),
                     (st[k], kdh.dh_static_torques(P, mod, base, tool, Q[k], F[k])),
                     (tau[k], kdh.dh_inverse_dynamics(*packed, Q[k], D[k], A[k], g, F[k]))]
            for got, want in pairs:
                assert np.abs(got - want).max() <= 1e-12 * max(1.0, np.abs(want).max()), name


def test_seed_dh_functions_use_checks(cases):
    from robokit.dynamics import dh_inverse_dynamics
    from robokit.kinematics import dh_jacobian, dh_static_torques

    table = dict(cases)["puma560"].dh
    with pytest.raises(ValueError, match="q"):
        dh_jacobian(table, np.zeros(5))
    with pytest.raises(ValueError, match="NaN"):
        dh_static_torques(table, np.array([np.nan] + [0.0] * 5), np.zeros(6))
    with pytest.raises(ValueError, match="reference"):
        dh_jacobian(table, np.zeros(6), reference="spatial")  # "world" is accepted now
    with pytest.raises(ValueError, match="dq"):
        dh_inverse_dynamics(table, np.zeros(6), np.zeros(3), np.zeros(6), trace=False)
    assert dh_jacobian(table, [0, 0, 0, 0, 0, 0]).shape == (6, 6)  # lists are converted


def test_kernels_name_a_bad_joint_vector(cases):
    """The DH and PoE kernels' own checks (one shared check since the one-source work): the message
    names the argument and what each value belongs to, compiled or not."""
    from robokit.kernels import poe as kp

    r = dict(cases)["puma560"]
    P, mod, base, tool = (np.array(a) if isinstance(a, np.ndarray) else a for a in kdh.pack_dh(r.dh)[:4])
    with pytest.raises(ValueError, match=r"^q: expected one joint value per row of the DH table$"):
        kdh.dh_fk(P, mod, base, tool, np.zeros(5))
    with pytest.raises(ValueError, match=r"^q: contains NaN or infinite values$"):
        kdh.dh_frames(P, mod, base, np.array([0.0, np.inf, 0.0, 0.0, 0.0, 0.0]))
    M, S = np.array(r.poe.M), np.array(r.poe.Slist)
    with pytest.raises(ValueError, match=r"^thetalist: expected one joint value per screw axis \(column of the screw list\)$"):
        kp.fkin_space(M, S, np.zeros(7))
    with pytest.raises(ValueError, match=r"^thetalist: contains NaN or infinite values$"):
        kp.fkin_body(M, S, np.full(6, np.nan))
