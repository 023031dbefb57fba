"""Drive-train dynamics of the PUMA 560 against Corke's toolbox (roboticstoolbox-python's Puma560,
an independent implementation carrying the same published parameters), the lecture's Coriolis
numbers, and the lecture's integration step."""
import numpy as np
import pytest

import robokit
from robokit.dynamics import (coriolis_matrix, dynamic_manipulability, forward_dynamics_with_drives,
                              inertia_with_drives, integrate, reflected_inertia, rne_with_drives)
from robokit.dynamics.newton_euler import vel_quadratic_forces

rtb = pytest.importorskip("roboticstoolbox")

QN = np.array([0.0, np.pi / 4, np.pi, 0.0, np.pi / 4, 0.0])  # the lecture's (Corke's) nominal pose


@pytest.fixture(scope="module")
def puma():
    return robokit.load("puma560")


@pytest.fixture(scope="module")
def p560():
    return rtb.models.DH.Puma560()


def test_lecture_coriolis_numbers(puma):
    P = puma.poe
    dq = 0.5 * np.ones(6)
    C_lec = coriolis_matrix(QN, dq, P.Mlist, P.Glist, P.Slist, method="lecture")
    C_chr = coriolis_matrix(QN, dq, P.Mlist, P.Glist, P.Slist)
    assert C_lec[0, 1] == pytest.approx(-0.9115, abs=5e-5)  # the lecture's printed C₁₂
    assert C_chr[0, 1] == pytest.approx(-0.6453, abs=5e-5)
    c = vel_quadratic_forces(QN, dq, P.Mlist, P.Glist, P.Slist)
    np.testing.assert_allclose(C_lec @ dq, c, atol=1e-10)
    np.testing.assert_allclose(C_chr @ dq, c, atol=1e-10)
    # the Christoffel one is the passive one: Ṁ − 2C skew (Ṁ by central differences)
    h = 1e-6
    Md = (puma.crba(QN + h * dq) - puma.crba(QN - h * dq)) / (2 * h)
    S = Md - 2 * C_chr
    np.testing.assert_allclose(S, -S.T, atol=1e-6)


def test_lecture_coriolis_on_random_states(puma):
    P = puma.poe
    rng = np.random.default_rng(3)
    for _ in range(3):
        q, dq = rng.uniform(-2, 2, 6), rng.uniform(-2, 2, 6)
        C = coriolis_matrix(q, dq, P.Mlist, P.Glist, P.Slist, method="lecture")
        np.testing.assert_allclose(C @ dq, puma.nonlinear_effects(q, dq) - puma.gravity_torques(q), atol=1e-9)
    with pytest.raises(ValueError, match="method"):
        coriolis_matrix(q, dq, P.Mlist, P.Glist, P.Slist, method="other")


def test_rne_and_inertia_with_drives_match_corke(puma, p560):
    rng = np.random.default_rng(7)
    for _ in range(4):
        q, dq, ddq = rng.uniform(-2, 2, (3, 6))
        np.testing.assert_allclose(rne_with_drives(puma, q, dq, ddq), p560.rne(q, dq, ddq), atol=1e-9)
        np.testing.assert_allclose(inertia_with_drives(puma, q), p560.inertia(q), atol=1e-9)
        tau = rng.uniform(-20, 20, 6)
        ddq_fd = forward_dynamics_with_drives(puma, q, dq, tau)
        np.testing.assert_allclose(rne_with_drives(puma, q, dq, ddq_fd), tau, atol=1e-8)
    # without drives the terms reduce to the rigid body
    np.testing.assert_allclose(rne_with_drives(puma, q, dq, ddq, motor_inertia=False, friction=False),
                               puma.rnea(q, dq, ddq), rtol=0, atol=1e-12 * max(1.0, np.abs(puma.rnea(q, dq, ddq)).max()))


def test_reflected_inertia_lecture_formula(puma, p560):
    """ᵐJⱼ = Jmⱼ + Mⱼⱼ/Gⱼ², with M the arm's own inertia: Corke's inertia minus G²Jm on the diagonal."""
    Jm = np.array([l.Jm for l in p560.links])
    G = np.array([l.G for l in p560.links])
    for q in (QN, np.zeros(6)):
        M_arm = np.diag(p560.inertia(q)) - G**2 * Jm
        np.testing.assert_allclose(reflected_inertia(puma, q), Jm + M_arm / G**2, rtol=1e-10)


def test_dynamic_manipulability_matches_corke_asada(puma, p560):
    for q in (QN, np.array([0.3, 0.5, -0.2, 0.4, 1.0, 0.2])):
        assert dynamic_manipulability(puma, q, "asada") == pytest.approx(p560.manipulability(q, method="asada"), rel=1e-8)
    # Yoshikawa's dynamic measure: √det(J M⁻¹ M⁻ᵀ Jᵀ) = |det J| / |det M| for a square J
    J = puma.jacobian(QN, reference="local_world_aligned")
    M = inertia_with_drives(puma, QN)
    assert dynamic_manipulability(puma, QN, "yoshikawa") == pytest.approx(abs(np.linalg.det(J) / np.linalg.det(M)), rel=1e-8)


def test_drive_functions_reject_urdf_robot_and_bad_shapes(puma):
    ur5 = robokit.load("ur5")
    with pytest.raises(ValueError, match="DH table"):
        inertia_with_drives(ur5, np.zeros(6))
    with pytest.raises(ValueError, match="ddq"):
        rne_with_drives(puma, np.zeros(6), np.zeros(6), np.zeros(5))


def test_lecture_taylor_step_is_second_order_accurate(puma):
    """The lecture's step q + q̇Δt + ½q̈Δt²: position error shrinks like Δt² (global) vs RK4 reference."""
    P = puma.poe
    g = np.array([0, 0, -9.81])
    q0 = np.array([0.0, 0.4, -0.3, 0.0, 0.5, 0.0])
    zero = lambda t, q, dq: np.zeros(6)  # noqa: E731  free fall under gravity
    _, Qref, _ = integrate(q0, np.zeros(6), zero, g, P.Mlist, P.Glist, P.Slist, 0.0025, 80, method="rk4")
    errs = []
    for dt, k in ((0.02, 10), (0.01, 20)):
        _, Q, D = integrate(q0, np.zeros(6), zero, g, P.Mlist, P.Glist, P.Slist, dt, k, method="taylor")
        errs.append(np.abs(Q[-1] - Qref[-1]).max())
    # first step from rest: exactly q0 + ½ q̈ Δt²
    from robokit.dynamics.newton_euler import forward_dynamics
    a0 = forward_dynamics(q0, np.zeros(6), np.zeros(6), g, np.zeros(6), P.Mlist, P.Glist, P.Slist)
    _, Q1, D1 = integrate(q0, np.zeros(6), zero, g, P.Mlist, P.Glist, P.Slist, 0.01, 1, method="taylor")
    np.testing.assert_allclose(Q1[1], q0 + 0.5 * a0 * 0.01**2, atol=1e-14)
    np.testing.assert_allclose(D1[1], a0 * 0.01, atol=1e-14)
    assert errs[1] < errs[0] / 1.7  # converges (first order in velocity, as Euler)
