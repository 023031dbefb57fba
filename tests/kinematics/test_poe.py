"""Seed PoE kinematics against Pinocchio, finite differences and the adjoint identity."""
import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import robokit as rk
from shared_robots import robot as shared_robot

MODELS = ["twolink", "rrr", "puma560", "ur5", "panda", "z1", "xarm7", "kinova"]


@pytest.fixture(scope="module")
def loaded():
    return {name: shared_robot(name) for name in MODELS}


@pytest.mark.parametrize("name", MODELS)
def test_fk_and_jacobians_vs_pinocchio(name, loaded):
    r = loaded[name]
    p = r.poe
    rng = np.random.default_rng(0)
    for _ in range(100):
        th = r.random_configuration(rng)
        T = r.frame_pose(th)
        assert np.abs(rk.fkin_space(p.M, p.Slist, th) - T).max() < 1e-9
        assert np.abs(rk.fkin_body(p.M, p.Blist, th) - T).max() < 1e-9
        Js = rk.jacobian_space(p.Slist, th)
        Jb = rk.jacobian_body(p.Blist, th)
        assert np.abs(Js - r.jacobian(th, reference="world")).max() < 1e-9
        assert np.abs(Jb - r.jacobian(th, reference="local")).max() < 1e-9
        assert np.abs(Jb - rk.adjoint(rk.trans_inv(T)) @ Js).max() < 1e-9  # J_b = Ad_{T⁻¹} J_s


@pytest.mark.parametrize("name", ["puma560", "panda"])
def test_jacobian_vs_finite_differences(name, loaded):
    r = loaded[name]
    p = r.poe
    rng = np.random.default_rng(1)
    h = 1e-6
    for _ in range(20):
        th = r.random_configuration(rng)
        T = rk.fkin_space(p.M, p.Slist, th)
        Js = rk.jacobian_space(p.Slist, th)
        for j in range(r.n):
            e = np.zeros(r.n)
            e[j] = h
            dT = (rk.fkin_space(p.M, p.Slist, th + e) - rk.fkin_space(p.M, p.Slist, th - e)) / (2 * h)
            V = rk.se3_to_vec(dT @ rk.trans_inv(T))  # spatial twist [V_s] = Ṫ T⁻¹
            assert np.abs(V - Js[:, j]).max() < 1e-7


def test_batched_equals_per_call(loaded):
    r = loaded["ur5"]
    p = r.poe
    Q = np.random.default_rng(2).uniform(-np.pi, np.pi, (500, 6))
    for fn, args in ((rk.fkin_space, (p.M, p.Slist)), (rk.fkin_body, (p.M, p.Blist)),
                     (rk.jacobian_space, (p.Slist,)), (rk.jacobian_body, (p.Blist,))):
        B = fn(*args, Q)
        for k in (0, 17, 499):
            assert np.abs(B[k] - fn(*args, Q[k])).max() < 1e-12


@settings(max_examples=50, deadline=None)
@given(st.lists(st.floats(-10, 10), min_size=3, max_size=3), st.floats(-3, 3))
def test_prismatic_and_non_unit_screws(v, th):
    v = np.array(v)
    S = np.r_[0, 0, 0, v].reshape(6, 1)
    T = rk.fkin_space(np.eye(4), S, [th])
    assert np.allclose(T[:3, 3], th * v) and np.allclose(T[:3, :3], np.eye(3))
    w = np.array([0.0, 0.0, 2.0])  # a non-unit ω: exp([S]θ) of the raw twist
    S = np.r_[w, 0.5, -0.1, 0.3].reshape(6, 1)
    assert np.allclose(rk.fkin_space(np.eye(4), S, [th]), rk.matrix_exp_6(rk.vec_to_se3(S[:, 0] * th)), atol=1e-12)


def test_bad_input():
    S = np.eye(6)[:, :2]
    with pytest.raises(ValueError, match="thetalist"):
        rk.fkin_space(np.eye(4), S, [1, 2, 3])
    with pytest.raises(ValueError, match="Slist"):
        rk.jacobian_space(np.ones((5, 2)), [1, 2])
    with pytest.raises(ValueError, match="M"):
        rk.fkin_body(np.ones((4, 4)), S, [1, 2])
    with pytest.raises(ValueError, match="NaN"):
        rk.jacobian_body(S, [np.nan, 0])
