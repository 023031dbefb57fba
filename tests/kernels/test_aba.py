"""Articulated-body forward dynamics (the default of ``forward_dynamics``) and the lecture's
CRBA + Cholesky form, both against Pinocchio's ``aba`` (1e-9) on random arms of 1…30 joints and
on the shipped / example robots; batched rows against the per-call kernel (1e-12)."""
import numpy as np
import pinocchio as pin
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import robokit as rk
from shared_robots import robot as shared_robot
from robokit.description.poe import poe_from_model
from robokit.errors import InputError
from robokit.kernels import dynamics as kd


def random_chain(seed, n):
    """A Pinocchio chain of n joints (revolute or prismatic about random unit axes) with random
    placements and random physical inertias, and a 'tip' frame on the last joint."""
    rng = np.random.default_rng(seed)
    model = pin.Model()
    parent = 0
    for i in range(n):
        quat = rng.normal(size=4)
        quat /= np.linalg.norm(quat)
        R = pin.Quaternion(*quat).toRotationMatrix()
        place = pin.SE3(R, rng.uniform(-0.3, 0.3, 3))
        axis = rng.normal(size=3)
        axis /= np.linalg.norm(axis)
        joint = pin.JointModelPrismaticUnaligned(axis) if rng.random() < 0.2 else pin.JointModelRevoluteUnaligned(axis)
        parent = model.addJoint(parent, joint, place, f"j{i}")
        L = rng.normal(size=(3, 3))
        inertia = L @ L.T * 0.05 + 0.01 * np.eye(3)
        model.appendBodyToJoint(parent, pin.Inertia(rng.uniform(0.2, 3.0), rng.uniform(-0.1, 0.1, 3), inertia),
                                pin.SE3.Identity())
    model.addFrame(pin.Frame("tip", parent, 0, pin.SE3(np.eye(3), np.array([0.0, 0.0, 0.1])), pin.FrameType.OP_FRAME))
    return model


def _c(*arrays):
    return [np.array(a, dtype=float, order="C") for a in arrays]  # writeable copies, as the kernels take them


def _rel(a, b):
    return np.abs(a - b).max() / max(1.0, np.abs(b).max())


@settings(max_examples=30, deadline=None, derandomize=True)
@given(seed=st.integers(0, 2**31 - 1), n=st.integers(1, 30))
def test_aba_and_crba_match_pinocchio_on_random_arms(seed, n):
    model = random_chain(seed, n)
    data = model.createData()
    p = poe_from_model(model, "tip")
    Ml, Gl, Sl = _c(p.Mlist, p.Glist, p.Slist)
    g = np.ascontiguousarray(model.gravity.linear)
    rng = np.random.default_rng(seed)
    for _ in range(3):
        q, dq, tau = rng.uniform(-2, 2, n), rng.normal(size=n), rng.normal(size=n) * 3
        ref = pin.aba(model, data, q, dq, tau).copy()
        assert _rel(kd.forward_dynamics(q, dq, tau, g, np.zeros(6), Ml, Gl, Sl), ref) < 1e-9
        assert _rel(kd.forward_dynamics_crba(q, dq, tau, g, np.zeros(6), Ml, Gl, Sl), ref) < 1e-9


@pytest.mark.parametrize("name", ["ur5", "panda", "puma560", "rrr", "twolink", "kinova"])
def test_forward_dynamics_methods_match_pinocchio_with_tip_wrench(name):
    r = shared_robot(name)
    p = r.poe
    rng = np.random.default_rng(3)
    for _ in range(10):
        q, dq, tau, F = r.random_configuration(rng), rng.normal(size=r.n), rng.normal(size=r.n) * 5, rng.normal(size=6)
        Jb = r.jacobian(q, reference="local")
        ref = r.aba(q, dq, tau - Jb.T @ F)  # Ftip is the wrench the tip applies to the environment
        for method in ("aba", "crba"):
            dd = rk.forward_dynamics(q, dq, tau, r.gravity, F, p.Mlist, p.Glist, p.Slist, method=method)
            assert _rel(dd, ref) < 1e-9


def test_batched_aba_equals_per_call():
    r = rk.load("panda")
    Ml, Gl, Sl = _c(r.poe.Mlist, r.poe.Glist, r.poe.Slist)
    g = r.gravity.copy()  # writeable, as the kernels take it
    rng = np.random.default_rng(5)
    N = 300  # above the serial threshold: the parallel path
    Q = np.array([r.random_configuration(rng) for _ in range(N)])
    D, T, F = rng.normal(size=(N, r.n)), rng.normal(size=(N, r.n)), rng.normal(size=(N, 6))
    out = kd.forward_dynamics_batch(Q, D, T, g, F, Ml, Gl, Sl)
    for k in range(0, N, 37):
        assert np.abs(out[k] - kd.forward_dynamics(Q[k], D[k], T[k], g, F[k], Ml, Gl, Sl)).max() < 1e-12


def test_method_is_checked():
    p = rk.load("twolink").poe
    with pytest.raises(InputError, match="method"):
        rk.forward_dynamics([0, 0], [0, 0], [0, 0], [0, 0, -9.81], np.zeros(6), p.Mlist, p.Glist, p.Slist,
                            method="lu")
