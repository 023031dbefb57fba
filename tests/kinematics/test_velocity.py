"""DH propagation Jacobians, static forces, numerical/analytical Jacobians, transforms,
manipulability and resolved-rate control — against Pinocchio, finite differences and closed forms."""
import re

import numpy as np

from robokit.control import track_line
import pytest

import robokit as rk
from shared_robots import robot as shared_robot
from robokit.kinematics import (
    analytical_jacobian, dh_jacobian, dh_static_torques, euler_rate_matrix, jacobian_in_frame,
    manipulability, manipulability_at, numerical_jacobian, resolved_rate, singularity, twist_transform,
    velocity_ellipsoid, wrench_transform,
)


@pytest.fixture(scope="module")
def robots():
    return {n: shared_robot(n) for n in ["twolink", "rrr", "puma560", "ur5", "panda", "z1", "xarm7"]}


@pytest.mark.parametrize("name", ["twolink", "rrr", "puma560"])
def test_propagation_jacobian_and_static_forces_vs_pinocchio(name, robots):
    r = robots[name]
    rng = np.random.default_rng(0)
    for _ in range(100):
        q = r.random_configuration(rng)
        Jb = dh_jacobian(r.dh, q, "base")
        Jt = dh_jacobian(r.dh, q, "tool")
        assert np.abs(Jb - r.jacobian(q, reference="local_world_aligned")).max() < 1e-9
        assert np.abs(Jt - r.jacobian(q, reference="local")).max() < 1e-9
        R = r.frame_pose(q)[:3, :3]
        assert np.abs(jacobian_in_frame(Jb, R.T) - Jt).max() < 1e-12  # the 6×6 change of frame
        F = rng.normal(size=6)
        assert np.abs(dh_static_torques(r.dh, q, F, reference="local") - Jt.T @ F).max() < 1e-9  # τ = Jᵀ F


@pytest.mark.parametrize("convention", ["standard", "modified"])
def test_propagation_random_tables_with_prismatic(convention, random_dh_table_factory):
    rng = np.random.default_rng(1)
    table = random_dh_table_factory(rng, 6, convention, prismatic=(1, 4))
    r = rk.load(table)
    for _ in range(100):
        q = r.random_configuration(rng)
        assert np.abs(dh_jacobian(table, q) - r.jacobian(q, reference="local_world_aligned")).max() < 1e-9
        F = rng.normal(size=6)
        assert np.abs(dh_static_torques(table, q, F, reference="local") - r.jacobian(q, reference="local").T @ F).max() < 1e-9


@pytest.fixture(scope="session")
def random_dh_table_factory():
    import importlib.util
    import pathlib

    spec = importlib.util.spec_from_file_location("desc_conftest",
                                                  pathlib.Path(__file__).parents[1] / "description" / "conftest.py")
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod.make_random_dh_table


@pytest.mark.parametrize("name", ["puma560", "ur5", "panda", "z1", "xarm7"])
def test_numerical_jacobian_matches(name, robots):
    r = robots[name]
    rng = np.random.default_rng(2)
    for _ in range(20):
        q = r.random_configuration(rng)
        Jn = numerical_jacobian(r.frame_pose, q)
        assert np.abs(Jn - r.jacobian(q, reference="local_world_aligned")).max() < 1e-7


def test_analytical_jacobian_euler_rates(robots):
    r = robots["puma560"]
    rng = np.random.default_rng(3)
    for seq in ("ZYX", "ZYZ"):
        for _ in range(20):
            q = r.random_configuration(rng)
            R = r.frame_pose(q)[:3, :3]
            phi = rk.spatial.euler_from_matrix(R, seq)
            Ja = analytical_jacobian(r.jacobian(q, reference="local_world_aligned"), phi, seq)
            # finite differences of the Euler angles along each joint
            h = 1e-6
            for j in range(6):
                e = np.zeros(6)
                e[j] = h
                d = (rk.spatial.euler_from_matrix(r.frame_pose(q + e)[:3, :3], seq)
                     - rk.spatial.euler_from_matrix(r.frame_pose(q - e)[:3, :3], seq)) / (2 * h)
                d = (d + np.pi / h) % (2 * np.pi / (2 * h)) - np.pi / h if np.abs(d).max() > 1e5 else d
                assert np.allclose(Ja[:3, j], d, atol=1e-5)
        w = np.array([0.3, -0.2, 0.5])
        assert np.allclose(euler_rate_matrix([0.4, 0.3, 0.1], seq) @ np.linalg.solve(euler_rate_matrix([0.4, 0.3, 0.1], seq), w), w)
    with pytest.raises(ValueError, match="representation singularity"):
        analytical_jacobian(np.eye(6), [0.2, np.pi / 2, 0.1], "ZYX")
    with pytest.raises(ValueError, match="representation singularity"):
        analytical_jacobian(np.eye(6), [0.2, 0.0, 0.1], "ZYZ")


def test_twist_and_wrench_transforms():
    rng = np.random.default_rng(4)
    T_ab = rk.matrix_exp_6(rk.vec_to_se3(rng.normal(size=6)))
    V_b = rng.normal(size=6)
    F_b = rng.normal(size=6)
    V_a = twist_transform(T_ab) @ V_b
    F_a = wrench_transform(T_ab) @ F_b
    assert np.isclose(V_a @ F_a, V_b @ F_b)  # power is frame independent
    # the velocity of a body point computed in both frames agrees
    p_b = rng.normal(size=3)
    p_a = T_ab[:3, :3] @ p_b + T_ab[:3, 3]
    v_point_b = V_b[3:] + np.cross(V_b[:3], p_b)
    v_point_a = V_a[3:] + np.cross(V_a[:3], p_a)
    assert np.allclose(T_ab[:3, :3] @ v_point_b, v_point_a)


def test_manipulability_two_link_closed_form(robots):
    r = robots["twolink"]
    l1, l2 = r.dh.links[0].a, r.dh.links[1].a
    for t2 in np.linspace(-np.pi, np.pi, 37):
        J = r.jacobian([0.4, t2], reference="local_world_aligned")[3:5]  # planar rows (truncated)
        assert abs(manipulability(J) - abs(l1 * l2 * np.sin(t2))) < 1e-12
    for t2 in (0.0, np.pi):
        J = r.jacobian([0.4, t2], reference="local_world_aligned")[3:5]
        assert manipulability(J) < 1e-15 and singularity(J).singular
    rep = singularity(r.jacobian([0.0, 0.0], reference="local_world_aligned")[3:5])
    assert rep.rank == 1 and abs(rep.lost_direction[0]) > 0.99  # stretched along x: x motion lost


@pytest.mark.parametrize("call, want", [
    (lambda J: manipulability(J), "a 2-D array of shape (m, n)"),
    (lambda J: manipulability(J, part="translation"), "a 6-row Jacobian (ω; v), shape (6, n)"),
    (lambda J: velocity_ellipsoid(J), "a 6-row Jacobian (ω; v), shape (6, n)"),
    (lambda J: singularity(J), "a 2-D array of shape (m, n)"),
    (lambda J: resolved_rate(J, np.zeros(6)), "a 2-D array of shape (m, n)"),
])
def test_a_jacobian_that_is_not_2d_is_named_with_the_shapes_accepted(call, want):
    """``manipulability(np.ones(6))`` said "J: expected shape (n, n)": a square Jacobian, which it does not
    need (any (m, n); 6 rows for the translation or rotation part). The error names J, the shapes the
    function takes and the shape given, and for a flat vector says what a one-joint Jacobian is."""
    with pytest.raises(rk.InputError) as info:
        call(np.ones(6))
    msg = str(info.value)
    assert msg.startswith("J: expected ") and want in msg and "got shape (6,)" in msg and "(6, 1)" in msg, msg
    assert "(n, n)" not in msg
    for bad, got in ((np.ones((2, 3, 4)), "got shape (2, 3, 4)"), (5.0, "got the number 5.0")):
        with pytest.raises(rk.InputError, match=r"^J: expected .*" + re.escape(got) + "$"):
            call(bad)
    assert manipulability(np.ones((2, 3)) + np.eye(2, 3)) > 0  # a non-square Jacobian is fine


def test_puma_singularities(robots):
    r = robots["puma560"]
    wrist = np.array([0.3, -0.4, 0.5, 0.2, 0.0, 0.1])  # θ5 = 0: axes 4 and 6 aligned
    assert manipulability_at(r, wrist) < 1e-12 and singularity(r.jacobian(wrist, reference="local_world_aligned")).singular
    # elbow singularity: forearm in line with the upper arm (the wrist centre at full reach),
    # a3 s3 + d4 c3 = 0 with a3 c3 − d4 s3 = ρ: θ3 = −atan2(d4, a3)
    a3, d4 = r.dh.links[2].a, r.dh.links[3].d
    t3 = -np.arctan2(d4, a3)
    elbow = np.array([0.2, -0.3, t3, 0.1, 0.7, 0.0])
    w_elbow = manipulability_at(r, elbow)
    assert w_elbow < 1e-12, w_elbow
    assert manipulability_at(r, np.array([0.2, -0.3, 0.9, 0.1, 0.7, 0.0])) > 1e-4
    radii, axes = velocity_ellipsoid(r.jacobian(np.array([0.2, -0.3, 0.9, 0.1, 0.7, 0.0]), reference="local_world_aligned"))
    assert radii.shape == (3,) and np.allclose(axes.T @ axes, np.eye(3))


def test_dls_bounded_near_singularity_and_null_space(robots):
    r = robots["twolink"]
    V = np.array([0.1, 0.0])
    dq_p, dq_d = [], []
    for t2 in (1e-2, 1e-4, 1e-6):
        J = r.jacobian([0.3, t2], reference="local_world_aligned")[3:5]
        dq_p.append(np.linalg.norm(resolved_rate(J, V, "pinv")))
        dq_d.append(np.linalg.norm(resolved_rate(J, V, "dls", damping=0.05, adaptive=True)))
    assert dq_p[-1] > 1e3 * dq_p[0] / 10 and max(dq_d) < 10  # pinv blows up, DLS stays bounded
    panda = robots["panda"]  # redundant: 7 joints
    rng = np.random.default_rng(5)
    for _ in range(20):
        q = panda.random_configuration(rng)
        J = panda.jacobian(q, reference="local_world_aligned")
        V = rng.normal(size=6)
        z = rng.normal(size=7)
        dq0 = resolved_rate(J, V)
        dq1 = resolved_rate(J, V, z=z)
        assert np.abs(J @ dq1 - V).max() < 1e-9 and np.abs(J @ (dq1 - dq0)).max() < 1e-9
        assert np.linalg.norm(dq1 - dq0) > 1e-3


def test_track_line_tracks(robots):
    r = robots["ur5"]
    q0 = np.array([0.2, -1.2, 1.5, -1.8, -1.5, 0.3])
    p0 = r.frame_pose(q0)[:3, 3]
    # the feedback gain K makes the lag of the Euler-integrated loop O(dt·|p̈|/K)
    slow = track_line(r, q0, p0 + np.array([0.1, -0.15, 0.1]), duration=1.0, dt=0.002, gain=5.0)
    res = track_line(r, q0, p0 + np.array([0.1, -0.15, 0.1]), duration=1.0, dt=0.002, gain=50.0)
    assert res.error.max() < 0.3 * slow.error.max()
    assert res.error.max() < 1e-4 and res.error[-1] < 1e-5
    assert np.linalg.norm(res.p[-1] - (p0 + np.array([0.1, -0.15, 0.1]))) < 1e-4


def test_one_call_helpers_for_any_robot(robots):
    from robokit.kinematics import resolved_rate_at, velocity_ellipsoid_at

    r = robots["panda"]
    q = r.random_configuration(np.random.default_rng(6))
    J = r.jacobian(q, reference="local_world_aligned")
    radii, axes = velocity_ellipsoid_at(r, q)
    assert np.allclose(radii, np.linalg.svd(J[3:], compute_uv=False))
    V = np.array([0.0, 0.0, 0.1, 0.05, 0.0, 0.0])
    dq = resolved_rate_at(r, q, V)
    assert np.allclose(J @ dq, V)
    assert manipulability_at(r, q, part="translation") > 0
