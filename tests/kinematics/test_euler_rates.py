"""Analytical (Euler-rate) Jacobians for all 12 sequences, intrinsic and extrinsic, against finite
differences of the Euler angles of the forward kinematics; the lecture's RPY and ZYZ matrices."""
import numpy as np
import pytest

import robokit
from robokit.kinematics.velocity import analytical_jacobian, euler_rate_matrix
from robokit.mobile.vehicle import angdiff
from robokit.spatial.euler import EULER_SEQUENCES, euler_from_matrix, matrix_from_euler


@pytest.fixture(scope="module")
def puma():
    return robokit.load("puma560")


@pytest.mark.parametrize("extrinsic", [False, True])
@pytest.mark.parametrize("seq", EULER_SEQUENCES)
def test_omega_equals_E_phidot(seq, extrinsic):
    """S(ω) = Ṙ Rᵀ with Ṙ by central differences along a random direction of the angles."""
    rng = np.random.default_rng(abs(hash((seq, extrinsic))) % 2**32)
    phi = rng.uniform(-1.2, 1.2, 3)
    phi[1] = rng.uniform(0.3, 1.2) if seq[0] != seq[2] else rng.uniform(0.4, 2.7)
    dphi = rng.normal(size=3)
    h = 1e-6
    Rp = matrix_from_euler(phi + h * dphi, seq, extrinsic)
    Rm = matrix_from_euler(phi - h * dphi, seq, extrinsic)
    W = (Rp - Rm) / (2 * h) @ matrix_from_euler(phi, seq, extrinsic).T
    w = np.array([W[2, 1], W[0, 2], W[1, 0]])
    np.testing.assert_allclose(euler_rate_matrix(phi, seq, extrinsic=extrinsic) @ dphi, w, atol=1e-8)


@pytest.mark.parametrize("extrinsic", [False, True])
@pytest.mark.parametrize("seq", EULER_SEQUENCES)
def test_analytical_jacobian_finite_differences_on_puma(puma, seq, extrinsic):
    q = np.array([0.3, -0.5, 0.4, 0.7, -0.9, 0.5])
    R = puma.frame_pose(q)[:3, :3]
    phi = euler_from_matrix(R, seq, extrinsic)
    E = euler_rate_matrix(phi, seq, extrinsic=extrinsic)
    if abs(np.linalg.det(E)) < 0.05:  # too close to this sequence's gimbal lock for differences
        pytest.skip("near the representation singularity")
    J = puma.jacobian(q, reference="local_world_aligned")
    Ja = analytical_jacobian(J, phi, seq, extrinsic=extrinsic)
    h = 1e-6
    num = np.empty((6, 6))
    for j in range(6):
        e = np.zeros(6)
        e[j] = h
        Tp, Tm = puma.frame_pose(q + e), puma.frame_pose(q - e)
        a_p = euler_from_matrix(Tp[:3, :3], seq, extrinsic)
        a_m = euler_from_matrix(Tm[:3, :3], seq, extrinsic)
        num[:3, j] = angdiff(a_p, a_m) / (2 * h)
        num[3:, j] = (Tp[:3, 3] - Tm[:3, 3]) / (2 * h)
    np.testing.assert_allclose(Ja, num, atol=1e-6)


def test_lecture_rpy_and_zyz_matrices():
    r, p, y = 0.3, -0.7, 1.1
    c, s = np.cos, np.sin
    B_rpy = np.array([[1, 0, s(p)], [0, c(r), -c(p) * s(r)], [0, s(r), c(p) * c(r)]])  # Lecture 6, R = Rx Ry Rz
    np.testing.assert_allclose(euler_rate_matrix([r, p, y], "XYZ"), B_rpy, atol=1e-15)
    ph, th, ps = 0.4, 0.9, -1.3
    B_zyz = np.array([[0, -s(ph), c(ph) * s(th)], [0, c(ph), s(ph) * s(th)], [1, 0, c(th)]])  # homework
    np.testing.assert_allclose(euler_rate_matrix([ph, th, ps], "ZYZ"), B_zyz, atol=1e-15)
    Binv = np.array([[-c(ph) * c(th) / s(th), -c(th) * s(ph) / s(th), 1], [-s(ph), c(ph), 0],
                     [c(ph) / s(th), s(ph) / s(th), 0]])
    np.testing.assert_allclose(np.linalg.inv(euler_rate_matrix([ph, th, ps], "ZYZ")), Binv, atol=1e-12)


def test_representation_singularity_and_bad_sequence():
    J = np.eye(6)
    with pytest.raises(ValueError, match="representation singularity"):
        analytical_jacobian(J, [0.2, np.pi / 2, 0.1], "XYZ")
    with pytest.raises(ValueError, match="representation singularity"):
        analytical_jacobian(J, [0.2, 0.0, 0.1], "XZX", extrinsic=True)
    with pytest.raises(ValueError, match="seq"):
        euler_rate_matrix([0, 0, 0], "XXY")
