"""Small frictions a student meets (issue 33's audit), each checked against something independent."""
import numpy as np
import pytest

import robokit as rk
from robokit.kinematics import dh_static_torques, numerical_jacobian
from robokit.trajectory import lspb_via_trajectory


def test_static_torques_take_the_wrench_in_base_axes():
    r = rk.load("puma560")
    rng = np.random.default_rng(4)
    for _ in range(10):
        q, F = r.random_configuration(rng), rng.normal(size=6)
        J = r.jacobian(q, reference="local_world_aligned")  # Pinocchio: (ω; v) of the tool, base axes
        assert np.abs(dh_static_torques(r.dh, q, F, reference="base") - J.T @ F).max() < 1e-10
        Jl = r.jacobian(q, reference="local")
        assert np.abs(dh_static_torques(r.dh, q, F, reference="local") - Jl.T @ F).max() < 1e-10
    # "world" is part of the shared vocabulary (test_reference_vocabulary.py); unknown names fail
    with pytest.raises(ValueError, match="reference"):
        dh_static_torques(r.dh, q, F, reference="spatial")


def test_numerical_jacobian_accepts_a_robot():
    r = rk.load("rrr")
    q = np.array([0.3, -0.4, 0.8])
    assert np.abs(numerical_jacobian(r, q) - r.jacobian(q, reference="local_world_aligned")).max() < 1e-7
    with pytest.raises(ValueError, match="fk"):
        numerical_jacobian(42, q)


def test_rot_inv_of_a_transform_points_to_trans_inv():
    with pytest.raises(ValueError, match="trans_inv"):
        rk.rot_inv(np.eye(4))


def test_lspb_via_points_as_a_single_axis_list():
    one = lspb_via_trajectory([5.0, 15.0, 40.0], [1.0, 1.0], 80.0)
    col = lspb_via_trajectory([[5.0], [15.0], [40.0]], [1.0, 1.0], 80.0)
    assert one.q.shape == col.q.shape and np.array_equal(one.q, col.q)
    # the lecture's worked example: blend times 0.134, 0.254, 0.388 s (Craig §7.3, degrees)
    assert np.allclose(one.info["blend_times"][:, 0], [0.134, 0.254, 0.388], atol=5e-4)


def test_cartesian_dynamics_lecture_names():
    from robokit.dynamics import cartesian_dynamics

    r = rk.load("puma560")
    q, dq = np.array([0.1, 0.7, -0.5, 0.3, 0.9, 0.2]), np.full(6, 0.3)
    cd = cartesian_dynamics(r, q, dq)
    # M_x = (J M⁻¹ Jᵀ)⁻¹ from Pinocchio's M and J (independent of the function's own algebra)
    J, M = r.jacobian(q, reference="local_world_aligned"), r.crba(q)
    assert np.abs(cd.M_x - np.linalg.inv(J @ np.linalg.solve(M, J.T))).max() < 1e-6 * np.abs(cd.M_x).max()
    assert cd.V_x is cd.mu and cd.G_x is cd.p
