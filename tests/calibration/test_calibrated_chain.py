"""The calibrated IK's packed chain (:func:`robokit.kernels.calibrated_ik.pack_arm`: one frame per
joint axis, consecutive frames related by ``Rx(α) Tr(a, b, 0) Rz(θ)``) against the Modern Robotics
library's product of exponentials and space Jacobian, on random six-joint chains: revolute joints
with and without a screw pitch, prismatic joints, and consecutive axes that intersect, are exactly
parallel, or are parallel up to 1e-14…1e-2 rad (where Denavit–Hartenberg parameters blow up). The
seven local transforms the generated C composes (:func:`local_transforms`) give the same pose."""
import numpy as np
import modern_robotics as mr
from hypothesis import given, settings
from hypothesis import strategies as st

from robokit.kernels import calibrated_ik as kci
from calibrated_chains import _chain, _pose_and_jacobian  # tests/support


@settings(max_examples=120, deadline=None, derandomize=True)
@given(seed=st.integers(0, 2**31 - 1))
def test_packed_chain_is_the_product_of_exponentials(seed):
    S, M, q = _chain(seed)
    C = kci.pack_arm(M, S, np.zeros((5, 6)), np.zeros(3), 1.0, 1e-12, 1e-10, 30)
    T, J = _pose_and_jacobian(C, q)
    scale = 1.0 + np.abs(M[:3, 3]).max()
    assert np.abs(T - mr.FKinSpace(M, S, q)).max() < 1e-12 * scale
    assert np.abs(J - mr.JacobianSpace(S, q)).max() < 1e-12 * scale
    # the local transforms the C composes: L0 Z1(q1) L1 ... Z6(q6) L6, Z the bare joint motion
    L = kci.local_transforms(C)
    T2 = np.eye(4)
    T2[:3] = L[0]
    for i in range(6):
        Z = np.eye(4)
        if C[kci.KINDS][i] == 0.0:
            Z[:3, :3] = mr.MatrixExp3(mr.VecToso3([0.0, 0.0, q[i]]))
            Z[2, 3] = C[kci.PITCHES][i] * q[i]
        else:
            Z[2, 3] = q[i]
        Li = np.eye(4)
        Li[:3] = L[i + 1]
        T2 = T2 @ Z @ Li
    assert np.abs(T2 - T).max() < 1e-12 * scale


def test_compiled_chain_matches_plain_python():
    S, M, q = _chain(7)
    C = kci.pack_arm(M, S, np.zeros((5, 6)), np.zeros(3), 1.0, 1e-12, 1e-10, 30)
    sc, T, J = np.empty((2, 6)), np.empty((4, 4)), np.empty((6, 6))
    kci._trig(C, q, sc)
    kci.fk_jacobian(C, q, sc, T, J)
    T0, J0 = _pose_and_jacobian(C, q)
    assert np.array_equal(T, T0) and np.array_equal(J, J0)
