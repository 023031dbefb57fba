"""The composite-rigid-body kernel (computed in the base frame: one inertia transform per link and
six products per entry) against Pinocchio's ``crba`` on random chains of 1–40 joints at random
configurations, per call and batched, plus the properties of a mass matrix (symmetric, positive
definite) and the lecture's forward dynamics built on it (CRBA + Cholesky) against ``aba``."""
import numpy as np
import pinocchio as pin
from hypothesis import given, settings
from hypothesis import strategies as st

from robokit.description.poe import poe_from_model
from robokit.kernels import dynamics as kd


def _model(n, seed):
    """A chain of n revolute joints about random axes, random placements and physical inertias."""
    rng = np.random.default_rng(seed)
    model = pin.Model()
    parent = 0
    for i in range(n):
        quat = rng.normal(size=4)
        quat /= np.linalg.norm(quat)
        place = pin.SE3(pin.Quaternion(*quat).toRotationMatrix(), rng.uniform(-0.2, 0.2, 3))
        axis = rng.normal(size=3)
        parent = model.addJoint(parent, pin.JointModelRevoluteUnaligned(axis / np.linalg.norm(axis)), place, f"j{i}")
        L = rng.normal(size=(3, 3))
        model.appendBodyToJoint(parent, pin.Inertia(rng.uniform(0.2, 3.0), rng.uniform(-0.1, 0.1, 3),
                                                    L @ L.T * 0.05 + 0.01 * np.eye(3)), pin.SE3.Identity())
    model.addFrame(pin.Frame("tip", parent, 0, pin.SE3(np.eye(3), np.array([0.0, 0.0, 0.1])), pin.FrameType.OP_FRAME))
    p = poe_from_model(model, "tip")
    c = np.ascontiguousarray
    return model, model.createData(), (c(p.Mlist), c(p.Glist), c(p.Slist))


@settings(max_examples=25, deadline=None, derandomize=True)
@given(n=st.integers(1, 40), seed=st.integers(0, 10_000))
def test_mass_matrix_matches_pinocchio(n, seed):
    model, data, args = _model(n, seed)
    rng = np.random.default_rng(seed)
    Q = rng.uniform(-np.pi, np.pi, (3, n))
    batch = kd.mass_matrix_batch(Q, *args)
    for k, q in enumerate(Q):
        Mp = pin.crba(model, data, q)
        Mp = np.triu(Mp) + np.triu(Mp, 1).T
        M = kd.mass_matrix(q, *args)
        scale = max(1.0, float(np.abs(Mp).max()))
        assert np.abs(M - Mp).max() <= 1e-9 * scale
        assert np.array_equal(M, M.T)
        assert np.linalg.eigvalsh(M).min() > 0.0
        assert np.abs(batch[k] - M).max() <= 1e-12 * scale
        dq, tau = rng.normal(size=n), rng.normal(size=n)
        g, F = np.array([0.0, 0.0, -9.81]), np.zeros(6)
        ddq = kd.forward_dynamics_crba(q, dq, tau, g, F, *args)
        model.gravity.linear = g
        ref = pin.aba(model, data, q, dq, tau)
        assert np.abs(ddq - ref).max() <= 1e-9 * max(1.0, float(np.abs(ref).max()))
