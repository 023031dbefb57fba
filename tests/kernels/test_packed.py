"""The packed-model kernels (robokit.kernels.packed) against Pinocchio on random arms (revolute and
prismatic joints, 1…12 joints: RNEA, gravity, CRBA, ABA with armature, the frame pose and its
WORLD Jacobian, to 1e-9 of the quantity's scale), bit for bit against the seed kernels they share
their recursions with, batches against the per-call kernels; the packed array is read-only, the
object immutable, bad models and bad vectors refused."""
import pickle

import numpy as np
import pinocchio as pin
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from robokit.description.poe import poe_from_model
from robokit.errors import InputError
from robokit.kernels import dynamics as kd
from robokit.kernels import packed as kpk
from robokit.kernels import poe as kp
from tests.kernels.test_aba import random_chain


def _rel(a, b):
    return np.abs(np.asarray(a) - b).max() / max(1.0, np.abs(b).max())


def _packed(model, armature=None):
    p = poe_from_model(model, "tip")
    return p, kpk.pack_model(p.Mlist, p.Glist, p.Slist, model.gravity.linear, M=p.M, armature=armature)


@settings(max_examples=15, deadline=None, derandomize=True)
@given(seed=st.integers(0, 2**31 - 1), n=st.integers(1, 12))
def test_packed_kernels_match_pinocchio(seed, n):
    model = random_chain(seed, n)
    rng = np.random.default_rng(seed)
    arm = rng.uniform(0.0, 0.5, n)
    p, pm = _packed(model, armature=arm)
    model.armature = arm  # Pinocchio's aba adds the armature to the joint-space inertia, as ours does
    data = model.createData()
    fid = model.getFrameId("tip")
    for _ in range(3):
        q, dq, a = rng.uniform(-2, 2, n), rng.normal(size=n), rng.normal(size=n)
        tau = pin.rnea(model, data, q, dq, a).copy()
        # rnea / crba without the armature: Pinocchio's rnea and crba do add it, ours do not
        assert _rel(pm.rnea(q, dq, a), tau - arm * a) < 1e-9
        assert _rel(pm.gravity_torques(q), pin.computeGeneralizedGravity(model, data, q)) < 1e-9
        M = pin.crba(model, data, q).copy().reshape(n, n)
        M = np.triu(M) + np.triu(M, 1).T - np.diag(arm)
        assert _rel(pm.crba(q), M) < 1e-9
        assert _rel(pm.aba(q, dq, tau), a) < 1e-9
        pin.forwardKinematics(model, data, q)
        assert _rel(pm.fk(q), pin.updateFramePlacement(model, data, fid).homogeneous) < 1e-9
        J = pin.computeFrameJacobian(model, data, q, fid, pin.WORLD).reshape(6, n)  # (6,) when n = 1
        assert _rel(pm.jacobian(q), np.vstack([J[3:], J[:3]])) < 1e-9
        T = pm.fk(q)
        Ad = np.zeros((6, 6))
        R = T[:3, :3].T
        Ad[:3, :3] = Ad[3:, 3:] = R
        p_ = -R @ T[:3, 3]
        Ad[3:, :3] = np.array([[0, -p_[2], p_[1]], [p_[2], 0, -p_[0]], [-p_[1], p_[0], 0]]) @ R
        assert _rel(pm.jacobian_body(q), Ad @ pm.jacobian(q)) < 1e-9


def test_packed_equals_the_seed_kernels_bit_for_bit():
    model = random_chain(7, 7)
    p, pm = _packed(model)
    Ml, Gl, Sl = (np.ascontiguousarray(x) for x in (p.Mlist, p.Glist, p.Slist))
    g, z6 = np.ascontiguousarray(model.gravity.linear), np.zeros(6)
    rng = np.random.default_rng(1)
    q, dq, a = rng.uniform(-2, 2, (3, 7))
    assert np.array_equal(pm.rnea(q, dq, a), kd.inverse_dynamics(q, dq, a, g, z6, Ml, Gl, Sl))
    assert np.array_equal(pm.crba(q), kd.mass_matrix(q, Ml, Gl, Sl))
    assert np.array_equal(pm.aba(q, dq, a), kd.forward_dynamics(q, dq, a, g, z6, Ml, Gl, Sl))
    assert np.array_equal(pm.forward_dynamics_crba(q, dq, a), kd.forward_dynamics_crba(q, dq, a, g, z6, Ml, Gl, Sl))
    # FK and the Jacobian: the factored product (one joint frame per axis), the same to rounding
    assert _rel(pm.fk(q), kp.fkin_space(np.array(p.M), Sl, q)) < 1e-13
    assert _rel(pm.jacobian(q), kp.jacobian_space(Sl, q)) < 1e-13


@pytest.mark.parametrize("N", [5, 300])  # serial below SERIAL_BELOW rows, parallel blocks above
def test_packed_batches_equal_the_per_call_kernels(N):
    n = 5
    model = random_chain(3, n)
    p, pm = _packed(model, armature=np.full(n, 0.1))
    rng = np.random.default_rng(N)
    Q, D, A = (rng.uniform(-2, 2, (N, n)) for _ in range(3))
    assert np.array_equal(pm.rnea_many(Q, D, A), [pm.rnea(Q[k], D[k], A[k]) for k in range(N)])
    assert np.array_equal(pm.aba_many(Q, D, A), [pm.aba(Q[k], D[k], A[k]) for k in range(N)])
    assert np.array_equal(pm.crba_many(Q), [pm.crba(Q[k]) for k in range(N)])
    assert np.array_equal(pm.fk_many(Q), [pm.fk(Q[k]) for k in range(N)])
    assert np.array_equal(pm.jacobian_many(Q), [pm.jacobian(Q[k]) for k in range(N)])
    with pytest.raises(ValueError, match="out"):
        kpk.matrix_batch(pm.data, kpk.CRBA, Q, np.empty((N, 6, n)))
    with pytest.raises(ValueError, match="shape"):
        pm.rnea_many(Q, D[:-1], A)


def test_packed_model_is_immutable_and_refuses_bad_input():
    model = random_chain(5, 3)
    p, pm = _packed(model)
    assert not pm.data.flags.writeable
    with pytest.raises(ValueError):
        pm.data[0] = 1.0
    with pytest.raises(AttributeError):
        pm.n = 4
    again = pickle.loads(pickle.dumps(pm))
    assert again.n == 3 and np.array_equal(again.data, pm.data) and not again.data.flags.writeable
    q = np.zeros(3)
    with pytest.raises(ValueError, match="thetalist"):
        pm.rnea(np.zeros(2), q, q)
    with pytest.raises(ValueError, match="dthetalist"):
        pm.rnea(q, np.array([0.0, np.nan, 0.0]), q)
    with pytest.raises(ValueError, match="not a packed model"):
        kpk.joints(np.zeros(40))
    bad_G = np.array(p.Glist)
    bad_G[0, 0, 1] += 1.0  # not symmetric
    with pytest.raises(InputError, match="Glist"):
        kpk.pack_model(p.Mlist, bad_G, p.Slist, [0, 0, -9.81])
    with pytest.raises(InputError, match="gravity"):
        kpk.pack_model(p.Mlist, p.Glist, p.Slist, [0, -9.81])
