"""The spatial layer against Pinocchio, scipy's Rotation and closed forms; hypothesis round trips;
every edge case the seed function library promises (the "Poses and rotations" page of the documentation)."""
import numpy as np
import pinocchio as pin
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.spatial.transform import Rotation as Rot

import robokit as rk

unit = st.lists(st.floats(-1, 1), min_size=3, max_size=3).map(np.array).filter(lambda v: np.linalg.norm(v) > 1e-3)
angle = st.floats(0, np.pi)
small = st.floats(0, 1e-6)
vec3 = st.lists(st.floats(-5, 5), min_size=3, max_size=3).map(np.array)
SETTINGS = settings(max_examples=150, deadline=None)


def axis(v):
    return v / np.linalg.norm(v)


@SETTINGS
@given(unit, st.one_of(angle, small, st.floats(np.pi - 1e-6, np.pi)))
def test_so3_exp_log_round_trip_and_pinocchio(v, th):
    w = axis(v) * th
    R = rk.matrix_exp_3(rk.vec_to_so3(w))
    assert np.abs(R - pin.exp3(w)).max() < 1e-12
    L = rk.so3_to_vec(rk.matrix_log_3(R))
    assert abs(np.linalg.norm(L) - th) < 1e-9
    assert np.abs(rk.matrix_exp_3(rk.vec_to_so3(L)) - R).max() < 1e-12
    if th < np.pi - 1e-6:
        assert np.abs(L - w).max() < 1e-9  # log∘exp = id away from π


def _exp6_exact(V):
    """exp([V]) in 40-digit arithmetic (Modern Robotics eq. 3.88, no series): the exact reference."""
    import mpmath as mp

    with mp.workdps(40):
        w, v = mp.matrix([mp.mpf(float(x)) for x in V[:3]]), mp.matrix([mp.mpf(float(x)) for x in V[3:]])
        t = mp.sqrt(sum(x * x for x in w))
        W = mp.matrix([[0, -w[2], w[1]], [w[2], 0, -w[0]], [-w[1], w[0], 0]])
        if t == 0:
            R, G = mp.eye(3), mp.eye(3)
        else:
            R = mp.eye(3) + mp.sin(t) / t * W + (1 - mp.cos(t)) / t**2 * W * W
            G = mp.eye(3) + (1 - mp.cos(t)) / t**2 * W + (t - mp.sin(t)) / t**3 * W * W
        p = G * v
        return np.array([[float(R[i, j]) for j in range(3)] + [float(p[i])] for i in range(3)] + [[0, 0, 0, 1.0]])


@SETTINGS
@given(unit, st.one_of(angle, small, st.floats(1e-6, 1e-2)), vec3)
def test_se3_exp_log_round_trip_and_pinocchio(v, th, lin):
    V = np.r_[axis(v) * th, lin]
    T = rk.matrix_exp_6(rk.vec_to_se3(V))
    exact = _exp6_exact(V)
    # a few roundings of the largest entry (|p| <= 5√3 (1 + θ)); (1 − cos θ)/θ² written directly
    # lost ~1e-12 at θ ≈ 1e-4 here
    assert np.abs(T - exact).max() < 1e-14 * (1 + np.abs(lin).max())
    # Pinocchio's exp6 has its own rounding near θ ~ 1e-4 (up to 2.3e-12 against the exact value, seen
    # at θ = 1.24e-4, |v| ≈ 6.5): agreement within 1e-12 beyond Pinocchio's own error
    P = pin.exp6(pin.Motion(lin, axis(v) * th)).homogeneous
    assert np.abs(T - P).max() < 1e-12 + np.abs(P - exact).max()
    L = rk.se3_to_vec(rk.matrix_log_6(T))
    assert np.abs(rk.matrix_exp_6(rk.vec_to_se3(L)) - T).max() < 1e-9
    if th < np.pi - 1e-6:
        assert np.abs(L - V).max() < 1e-9


@pytest.mark.parametrize("k", [0, 1, 2])
def test_log3_at_pi_all_three_branches(k):
    w = np.eye(3)[k] * np.pi
    R = rk.matrix_exp_3(rk.vec_to_so3(w))
    L = rk.so3_to_vec(rk.matrix_log_3(R))
    assert np.allclose(np.abs(L), np.abs(w), atol=1e-12) and np.allclose(rk.matrix_exp_3(rk.vec_to_so3(L)), R)
    R_near = pin.exp3(np.eye(3)[k] * (np.pi - 1e-9))
    assert abs(np.linalg.norm(rk.so3_to_vec(rk.matrix_log_3(R_near))) - (np.pi - 1e-9)) < 1e-9


def test_identity_and_pure_translation():
    assert np.allclose(rk.matrix_log_3(np.eye(3)), 0)
    T = rk.matrix_exp_6(rk.vec_to_se3([0, 0, 0, 1, 2, 3]))
    assert np.allclose(T, [[1, 0, 0, 1], [0, 1, 0, 2], [0, 0, 1, 3], [0, 0, 0, 1]])
    assert np.allclose(rk.se3_to_vec(rk.matrix_log_6(T)), [0, 0, 0, 1, 2, 3])
    S, th = rk.axis_ang_6([0, 0, 0, 0, 0, 2])
    assert np.allclose(S, [0, 0, 0, 0, 0, 1]) and th == 2.0
    S, th = rk.axis_ang_6([0, 0, 2, 1, 0, 0])
    assert np.allclose(S, [0, 0, 1, 0.5, 0, 0]) and th == 2.0
    T = rk.matrix_exp_6(rk.vec_to_se3([np.pi, 0, 0, 0, 1, 0]))
    assert np.allclose(rk.matrix_exp_6(rk.matrix_log_6(T)), T)


def test_projection_and_distance():
    rng = np.random.default_rng(0)
    R = Rot.random(random_state=1).as_matrix()
    noisy = R + 0.01 * rng.normal(size=(3, 3))
    P = rk.project_to_SO3(noisy)
    assert rk.test_if_SO3(P) and rk.distance_to_SO3(P) < 1e-12
    reflection = np.diag([1.0, 1.0, -1.0]) @ R  # det −1
    Pr = rk.project_to_SO3(reflection)
    assert np.isclose(np.linalg.det(Pr), 1.0)
    d_best = np.linalg.norm(Pr - reflection)
    for Q in Rot.random(2000, random_state=2).as_matrix():  # no sampled rotation is closer
        assert np.linalg.norm(Q - reflection) >= d_best - 1e-9
    assert rk.distance_to_SO3(reflection) >= 1e3 and not rk.test_if_SO3(reflection)
    T = np.eye(4)
    T[:3, :3] = reflection
    assert rk.distance_to_SE3(T) >= 1e3
    mr_example = np.array([[1.0, 0, 0, 1.2], [0, 0.1, -0.95, 1.5], [0, 1.0, 0.1, -0.9], [0, 0, 0.1, 0.98]])
    assert abs(rk.distance_to_SE3(mr_example) - 0.134931) < 1e-6  # Modern Robotics' documented value
    assert rk.test_if_SE3(rk.project_to_SE3(mr_example))


def test_adjoint_ad_inverse_against_pinocchio():
    rng = np.random.default_rng(3)
    for _ in range(50):
        M = pin.SE3.Random()
        T = M.homogeneous
        X = rng.normal(size=6)
        a = M.act(pin.Motion(X[3:], X[:3]))
        assert np.allclose(rk.adjoint(T) @ X, np.r_[a.angular, a.linear])
        V = rng.normal(size=6)
        b = pin.Motion(V[3:], V[:3]).cross(pin.Motion(X[3:], X[:3]))
        assert np.allclose(rk.ad(V) @ X, np.r_[b.angular, b.linear])
        assert np.allclose(rk.trans_inv(T), M.inverse().homogeneous)
        R, p = rk.trans_to_Rp(T)
        assert np.allclose(rk.Rp_to_trans(R, p), T) and np.allclose(rk.rot_inv(R), R.T)


@pytest.mark.parametrize("seq", rk.spatial.EULER_SEQUENCES)
@pytest.mark.parametrize("extrinsic", [False, True])
def test_euler_all_24_vs_scipy(seq, extrinsic):
    rng = np.random.default_rng(4)
    proper = seq[0] == seq[2]
    for _ in range(100):
        ang = rng.uniform(-np.pi, np.pi, 3)
        ang[1] = rng.uniform(0.05, np.pi - 0.05) if proper else rng.uniform(-1.5, 1.5)
        R = rk.spatial.matrix_from_euler(ang, seq, extrinsic)
        ref = Rot.from_euler(seq.lower() if extrinsic else seq, ang).as_matrix()
        assert np.abs(R - ref).max() < 1e-12
        back, gimbal = rk.spatial.euler_from_matrix(R, seq, extrinsic, return_gimbal=True)
        assert not gimbal
        assert np.abs(np.angle(np.exp(1j * (back - ang)))).max() < 1e-9


@pytest.mark.parametrize("seq", rk.spatial.EULER_SEQUENCES)
@pytest.mark.parametrize("extrinsic", [False, True])
def test_euler_gimbal_lock_documented_choice(seq, extrinsic):
    proper = seq[0] == seq[2]
    for mid in ((0.0, np.pi) if proper else (np.pi / 2, -np.pi / 2)):
        ang = np.array([0.7, mid, -0.4])
        R = rk.spatial.matrix_from_euler(ang, seq, extrinsic)
        back, gimbal = rk.spatial.euler_from_matrix(R, seq, extrinsic, return_gimbal=True)
        assert gimbal
        assert back[0 if extrinsic else 2] == 0.0  # the last rotation applied carries no angle
        assert np.abs(rk.spatial.matrix_from_euler(back, seq, extrinsic) - R).max() < 1e-12


def test_seed_zyx_is_intrinsic_zyx():
    ang = [0.3, -0.7, 1.1]
    assert np.allclose(rk.euler_to_matrix(ang), rk.spatial.matrix_from_euler(ang, "ZYX"))
    R = rk.euler_to_matrix([0.3, np.pi / 2, 0.2])
    a = rk.matrix_to_euler(R)
    assert a[2] == 0.0 and np.allclose(rk.euler_to_matrix(a), R)


@SETTINGS
@given(unit, angle)
def test_quaternions(v, th):
    q = rk.spatial.quaternion_from_axis_angle(v, th)
    R = rk.spatial.matrix_from_axis_angle(v, th)
    assert np.allclose(rk.spatial.matrix_from_quaternion(q), R, atol=1e-12)
    ref = Rot.from_matrix(R).as_quat()  # scipy is scalar last
    q2 = rk.spatial.quaternion_from_matrix(R)
    assert np.allclose(q2, np.r_[ref[3], ref[:3]] * np.sign(ref[3] or 1.0), atol=1e-12) or np.allclose(
        q2, -np.r_[ref[3], ref[:3]], atol=1e-12)
    ax, an = rk.spatial.axis_angle_from_quaternion(q)
    assert abs(an - th) < 1e-9 and (th < 1e-9 or np.allclose(ax, axis(v), atol=1e-9))
    vv = np.array([0.3, -0.2, 0.9])
    assert np.allclose(rk.spatial.quaternion_rotate(q, vv), R @ vv)
    p = rk.spatial.quaternion_from_axis_angle([0, 0, 1], 0.4)
    assert np.allclose(rk.spatial.matrix_from_quaternion(rk.spatial.quaternion_multiply(p, q)), rk.spatial.matrix_from_quaternion(p) @ R)
    assert np.allclose(rk.spatial.quaternion_multiply(q, rk.spatial.quaternion_conjugate(q)), [1, 0, 0, 0])


def test_slerp_fixed_axis_on_so3():
    q0 = rk.spatial.quaternion_from_axis_angle([0, 0, 1], 0.2)
    q1 = rk.spatial.quaternion_from_matrix(rk.spatial.matrix_from_axis_angle([1, 1, 0], 2.5) @ rk.spatial.matrix_from_quaternion(q0))
    s = np.linspace(0, 1, 21)
    Q = rk.spatial.quaternion_slerp(q0, q1, s)
    R0 = rk.spatial.matrix_from_quaternion(q0)
    axes = []
    for k, q in enumerate(Q):
        R = rk.spatial.matrix_from_quaternion(q)
        assert rk.distance_to_SO3(R) < 1e-12
        if k:
            ax, an = rk.spatial.axis_angle_from_matrix(R @ R0.T)
            axes.append(ax)
            assert abs(an - s[k] * 2.5) < 1e-9  # constant angular rate
    assert np.allclose(axes, axes[0], atol=1e-9)  # one fixed axis
    ref = pin.Quaternion(q0[0], *q0[1:]).slerp(0.3, pin.Quaternion(q1[0], *q1[1:]))
    assert np.allclose(rk.spatial.matrix_from_quaternion(rk.spatial.quaternion_slerp(q0, q1, 0.3)), ref.matrix())


def test_two_vectors_and_se2():
    R = rk.spatial.matrix_from_two_vectors([0, 1, 0], [0, 0, 1])
    assert np.allclose(R, np.eye(3))
    with pytest.raises(ValueError, match="orthogonal"):
        rk.spatial.matrix_from_two_vectors([0, 1, 0], [0, 1, 1])
    p1, p2 = np.array([1.0, 2.0, 0.5]), np.array([-0.3, 0.4, 2.9])
    T = rk.spatial.se2_from_pose(p1) @ rk.spatial.se2_from_pose(p2)
    assert np.allclose(rk.spatial.se2_compose(p1, p2), rk.spatial.pose_from_se2(T))
    assert np.allclose(rk.spatial.se2_compose(p1, rk.spatial.se2_inverse(p1)), [0, 0, 0], atol=1e-12)
    pts = np.array([[1.0, 0.0], [0.0, 2.0]])
    expect = (rk.spatial.se2_from_pose(p1) @ np.c_[pts, np.ones(2)].T).T[:, :2]
    assert np.allclose(rk.spatial.se2_transform_points(p1, pts), expect)


BAD = [
    (rk.normalize, ([0, 0, 0],), "V"),
    (rk.matrix_log_3, (np.ones((3, 3)),), "R"),
    (rk.matrix_log_6, (np.eye(3),), "T"),
    (rk.vec_to_so3, ([1, 2],), "omg"),
    (rk.matrix_exp_6, ([[np.nan] * 4] * 4,), "se3mat"),
    (rk.adjoint, (np.diag([1, 1, 2, 1]),), "T"),
    (rk.axis_ang_3, ([0, 0, 0],), "expc3"),
    (rk.spatial.euler_from_matrix, (np.eye(3), "ABC"), "seq"),
    (rk.spatial.quaternion_from_matrix, (2 * np.eye(3),), "R"),
    (rk.spatial.matrix_from_quaternion, ([1, 1, 0, 0],), "q"),
    (rk.spatial.se2_from_pose, ([1, 2],), "pose"),
]


@pytest.mark.parametrize("fn,args,name", BAD, ids=[b[0].__name__ for b in BAD])
def test_bad_input_names_the_argument(fn, args, name):
    with pytest.raises(ValueError) as info:
        fn(*args)
    assert str(info.value).startswith(name)


def test_unit_vector_is_the_direction_and_refuses_zero():
    from robokit.spatial import unit_vector

    v = np.array([3.0, -4.0, 12.0])
    u = unit_vector(v, "axis")
    assert np.isclose(np.linalg.norm(u), 1.0, atol=1e-15) and np.allclose(u * 13.0, v, atol=1e-14)
    with pytest.raises(ValueError, match="axis"):
        unit_vector([0.0, 0.0, 1e-13], "axis")
