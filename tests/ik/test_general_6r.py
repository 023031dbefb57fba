"""The general 6R closed form (Raghavan–Roth / Manocha–Canny), checked against Pinocchio and
against a numerical IK from many seeds.

Every solution must reach the pose through the robot's Pinocchio model (``frame_pose``) to
1e-9, the generating configuration must be among them, and every distinct solution that the
compiled Levenberg–Marquardt solver finds from 200 random seeds must be among them (so none
is missed). Arms: the Kinova JACO² 6-DOF with its offset ("non-spherical") wrist from
Kinova's DH table, random general 6R arms in both conventions, and special arms (spherical
wrist, UR) made general by small offsets.
"""
import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import robokit
from shared_robots import elbow_singular as _elbow_singular, gen3_lite as _gen3_lite, robot as shared_robot
from robokit.description.dh import DHLink, DHTable, matrix_from_rpy
from robokit.ik import ik_analytic, ik_analytic_kind

TOL = 1e-9


def angle_dist(a, b):
    d = np.asarray(a, float) - np.asarray(b, float)
    return float(np.abs(np.angle(np.exp(1j * d))).max())


def check(robot, q_true, T, sols):
    """Every solution reaches T (Pinocchio), the generator is among them, all distinct."""
    for s in sols:
        assert np.abs(robot.frame_pose(s.q) - T).max() < TOL, s.label
        inside = bool(np.all(s.q >= robot.qlim[:, 0] - 1e-12) and np.all(s.q <= robot.qlim[:, 1] + 1e-12))
        assert s.within_limits == inside
    for i in range(len(sols)):
        for j in range(i):
            assert angle_dist(sols[i].q, sols[j].q) > 1e-9
    assert len({s.label for s in sols}) == len(sols)
    if q_true is not None:
        assert min(angle_dist(s.q, q_true) for s in sols) < 1e-7


def numerical_solutions(robot, T, seeds=200, rng=0):
    """Distinct solutions the compiled LM solver finds from ``seeds`` random starts."""
    rng = np.random.default_rng(rng)
    found = []
    for _ in range(seeds):
        r = robokit.solve_ik(robot, T, q0=rng.uniform(-np.pi, np.pi, robot.n), method="compiled", max_restarts=0)
        if r.success and not any(angle_dist(r.q, f) < 1e-6 for f in found):
            found.append(r.q)
    return found


def assert_none_missed(robot, T, sols, seeds=200):
    found = numerical_solutions(robot, T, seeds)
    assert found, "the numerical IK found nothing: the check would be empty"
    for f in found:
        assert min(angle_dist(f, s.q) for s in sols) < 1e-6, f"numerical solution {f} not returned"


WIDE = np.array([-2 * np.pi, 2 * np.pi])  # limits that let the numerical solver reach every angle


# ---------------------------------------------------------------- the Kinova JACO² (offset wrist)
def jaco2_table():
    """Kinova JACO² 6-DOF non-spherical (j2n6s300), classic DH, from Kinova's "JACO² 6 DOF
    Advanced Specification Guide" (as also used by WPI's jaco_kinematics): D1 = 0.2755,
    D2 = 0.4100, D3 = 0.2073, D4 = D5 = 0.0741, D6 = 0.1600, e2 = 0.0098 m, aa = 30°."""
    D1, D2, D3, D4, D5, D6, e2 = 0.2755, 0.4100, 0.2073, 0.0741, 0.0741, 0.1600, 0.0098
    aa = math.radians(30.0)
    k = math.sin(aa) / math.sin(2 * aa)
    d4b, d5b, d6b = D3 + k * D4, k * D4 + k * D5, k * D5 + D6
    alpha = [math.pi / 2, math.pi, math.pi / 2, 2 * aa, 2 * aa, math.pi]
    a = [0.0, D2, 0.0, 0.0, 0.0, 0.0]
    d = [D1, 0.0, -e2, -d4b, -d5b, -d6b]
    return DHTable("jaco2_6n", "standard", tuple(DHLink("R", a=a[i], alpha=alpha[i], d=d[i], qlim=WIDE)
                                                  for i in range(6)))


@pytest.fixture(scope="module")
def jaco():
    return robokit.load(jaco2_table())


def test_jaco_is_general_6r(jaco):
    kind = ik_analytic_kind(jaco)
    assert kind.method == "general 6R"
    assert "axes 4–6 do not intersect" in kind.reason


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_jaco_every_solution(jaco, seed):
    rng = np.random.default_rng(seed)
    q = rng.uniform(-np.pi, np.pi, 6)
    T = jaco.frame_pose(q)
    sols = ik_analytic(jaco, T)
    check(jaco, q, T, sols)
    assert_none_missed(jaco, T, sols)
    assert all(s.label.startswith("solution ") for s in sols)


def test_jaco_from_its_urdf(tmp_path):
    """The same arm as a URDF (no DH table on the Robot): solved through dh_from_urdf's table."""
    from robokit.description.urdf_gen import urdf_from_dh

    path = tmp_path / "jaco2_6n.urdf"
    path.write_text(urdf_from_dh(jaco2_table()), encoding="utf-8")
    robot = robokit.load(str(path))
    assert robot.dh is None
    assert ik_analytic_kind(robot).method == "general 6R"
    q = np.array([0.3, 2.1, 1.2, -0.7, 1.9, 0.4])
    T = robot.frame_pose(q)
    check(robot, q, T, ik_analytic(robot, T))


def test_example_robot_data_kinova_keeps_the_spherical_wrist_method():
    """example-robot-data's "kinova" is the j2s6s200: a spherical wrist (Pieper, faster)."""
    robot = shared_robot("kinova")
    assert ik_analytic_kind(robot).method == "spherical wrist"


def test_unreachable_pose_gives_empty_list(jaco):
    T = np.eye(4)
    T[:3, 3] = [3.0, 0.0, 0.0]  # 3 m away; the arm is about 1 m long
    assert ik_analytic(jaco, T) == []


def test_joint_angles_at_pi(jaco):
    """θ = π is the half-angle variable's point at infinity: solutions there are still found."""
    for j in range(6):
        q = np.array([0.4, 1.9, 1.1, -0.6, 2.2, 0.3])
        q[j] = math.pi
        T = jaco.frame_pose(q)
        check(jaco, q, T, ik_analytic(jaco, T))


# ---------------------------------------------------------------- random general arms
def random_general_arm(seed, convention):
    rng = np.random.default_rng(seed)
    rows = tuple(DHLink("R", a=rng.uniform(-0.5, 0.5), alpha=rng.uniform(-np.pi, np.pi), d=rng.uniform(-0.5, 0.5),
                        theta=rng.uniform(-np.pi, np.pi), qlim=WIDE) for _ in range(6))
    base, tool = np.eye(4), np.eye(4)
    base[:3, :3], base[:3, 3] = matrix_from_rpy(rng.uniform(-1, 1, 3)), rng.uniform(-0.2, 0.2, 3)
    tool[:3, :3], tool[:3, 3] = matrix_from_rpy(rng.uniform(-1, 1, 3)), rng.uniform(-0.1, 0.1, 3)
    return DHTable(f"g{seed}", convention, rows, base=base, tool=tool)


@settings(max_examples=12, deadline=None, derandomize=True)
@given(st.integers(0, 2**31), st.sampled_from(["standard", "modified"]))
def test_random_general_arms(seed, convention):
    robot = robokit.load(random_general_arm(seed, convention))
    assert ik_analytic_kind(robot).method == "general 6R"
    q = np.random.default_rng(seed + 1).uniform(-np.pi, np.pi, 6)
    T = robot.frame_pose(q)
    sols = ik_analytic(robot, T)
    check(robot, q, T, sols)
    assert len(sols) <= 16 and len(sols) % 2 == 0  # real roots of a real polynomial of degree 16, in pairs


@pytest.mark.parametrize("seed, convention", [(3, "standard"), (4, "modified")])
def test_random_general_arms_numerical_ik_finds_no_other(seed, convention):
    robot = robokit.load(random_general_arm(seed, convention))
    q = np.random.default_rng(seed).uniform(-np.pi, np.pi, 6)
    T = robot.frame_pose(q)
    sols = ik_analytic(robot, T)
    check(robot, q, T, sols)
    assert_none_missed(robot, T, sols)


# ---------------------------------------------------------------- almost special arms
def puma_with_offset(eps):
    """Corke's PUMA 560 (spherical wrist) with axes 4 and 5 moved eps apart (a₄ = eps)."""
    table = robokit.load("puma560").dh
    rows = list(table.links)
    rows[3] = DHLink("R", eps, rows[3].alpha, rows[3].d, rows[3].theta, qlim=WIDE)
    rows = [DHLink("R", r.a, r.alpha, r.d, r.theta, qlim=WIDE) for r in rows]
    return DHTable(f"puma_eps{eps:g}", table.convention, tuple(rows), base=table.base, tool=table.tool)


@pytest.mark.parametrize("eps", [1e-6, 1e-4, 1e-2])
@pytest.mark.parametrize("nominal", [False, None])
def test_spherical_wrist_off_by_a_little(eps, nominal):
    """nominal=False: the general 6R method; by default the spherical wrist is detected and its
    closed form polished (robokit.ik.calibrated): both find every solution."""
    robot = robokit.load(puma_with_offset(eps))
    method = ik_analytic_kind(robot, nominal=nominal).method
    assert method == ("general 6R" if nominal is False else "calibrated spherical wrist")
    q = np.array([0.3, -0.6, 0.4, 0.8, 0.7, -0.5])
    T = robot.frame_pose(q)
    sols = ik_analytic(robot, T, nominal=nominal)
    check(robot, q, T, sols)
    assert len(sols) >= 8  # the 8 of the exact PUMA survive a small offset
    assert_none_missed(robot, T, sols)


def ur5_with_tilt(angle):
    """The UR5 (three parallel axes) with axis 3 tilted by ``angle`` rad (α₂ += angle)."""
    from robokit.description.urdf_to_dh import dh_from_urdf

    table = dh_from_urdf(shared_robot("ur5"), "standard").table
    rows = [DHLink("R", r.a, r.alpha + (angle if i == 1 else 0.0), r.d, r.theta, qlim=WIDE)
            for i, r in enumerate(table.links)]
    return DHTable("ur5_tilt", "standard", tuple(rows), base=table.base, tool=table.tool)


@pytest.mark.parametrize("nominal", [False, None])
def test_ur5_with_axes_off_by_a_milliradian(nominal):
    robot = robokit.load(ur5_with_tilt(1e-3))
    method = ik_analytic_kind(robot, nominal=nominal).method
    assert method == ("general 6R" if nominal is False else "calibrated three parallel axes")
    q = np.array([0.4, -1.3, 1.2, -0.6, 1.1, 0.3])
    T = robot.frame_pose(q)
    sols = ik_analytic(robot, T, nominal=nominal)
    check(robot, q, T, sols)
    assert len(sols) >= 8
    assert_none_missed(robot, T, sols)


# ---------------------------------------------------------------- refusals
def test_seven_and_five_joint_arms_are_refused_with_the_reason():
    with pytest.raises(ValueError, match="7 joints"):
        ik_analytic(robokit.load("panda"), np.eye(4))
    rows = random_general_arm(7, "standard").links[:5]
    robot = robokit.load(DHTable("five", "standard", tuple(rows)))
    kind = ik_analytic_kind(robot)
    assert kind.method is None and "5 joints" in kind.reason
    with pytest.raises(ValueError, match="5 joints"):
        ik_analytic(robot, robot.frame_pose(np.zeros(5)))


def test_arm_with_coinciding_axes_is_refused():
    """Axes 1 and 2 on one line (α₁ = 0, a₁ = 0): joints 1 and 2 add up, a continuum of solutions."""
    t = random_general_arm(8, "standard")
    rows = list(t.links)
    rows[0] = DHLink("R", 0.0, 0.0, rows[0].d, rows[0].theta, qlim=WIDE)
    robot = robokit.load(DHTable("coincide", "standard", tuple(rows)))
    kind = ik_analytic_kind(robot)
    assert kind.method is None and "continuum" in kind.reason


def test_pivot_at_the_shifted_point_at_infinity(jaco):
    """A joint at π + γ (γ the half-angle variable's shift) makes the leading coefficient A
    singular for the reading that uses it as the eigenvalue: the half-angle variable is turned
    and the solutions are still all there."""
    from robokit.ik.general_6r import _GAMMA

    for j in range(6):
        q = np.array([0.4, 1.9, 1.1, -0.6, 2.2, 0.3])
        q[j] = math.pi + _GAMMA
        T = jaco.frame_pose(q)
        sols = ik_analytic(jaco, T)
        check(jaco, q, T, sols)
    assert_none_missed(jaco, T, sols)


# ---------------------------------------------------------------- the elimination's pieces
@settings(max_examples=20, deadline=None, derandomize=True)
@given(st.integers(0, 2**31))
def test_the_14_quantities_map_linearly_under_a_rigid_motion(seed):
    """f(l, p) = (l, p, p·p, l·p, l×p, (p·p)l − 2(l·p)p, 1): f(R l, R p + t) = F(T) f(l, p), with
    F(T) the 15 × 15 map used on both sides of the loop equation (Raghavan & Roth)."""
    from scipy.spatial.transform import Rotation

    from robokit.kernels.general_6r import f_pose, fvec

    rng = np.random.default_rng(seed)
    l = rng.standard_normal(3)
    l /= np.linalg.norm(l)
    p = rng.uniform(-1, 1, 3)
    T = np.eye(4)
    T[:3, :3], T[:3, 3] = Rotation.random(random_state=seed % 2**32).as_matrix(), rng.uniform(-1, 1, 3)
    f, g, F = np.empty(15), np.empty(15), np.empty((15, 15))
    fvec(*l, *p, f)
    fvec(*(T[:3, :3] @ l), *(T[:3, :3] @ p + T[:3, 3]), g)
    f_pose(T, False, F)
    assert np.abs(F @ f - g).max() < 1e-12
    Ti = np.linalg.inv(T)
    fvec(*(Ti[:3, :3] @ l), *(Ti[:3, :3] @ p + Ti[:3, 3]), g)
    f_pose(T, True, F)
    assert np.abs(F @ f - g).max() < 1e-12


@pytest.mark.parametrize("seed", [11, 12])
def test_every_reading_of_the_loop_holds_at_the_true_configuration(seed):
    """All 36 readings (eliminated joint, side, pivot): both sides of the 14 equations agree at
    the configuration that generated the pose — an independent check of each coefficient build."""
    from robokit.ik.closed_form import analytic_ik as _model

    robot = robokit.load(random_general_arm(seed, "standard" if seed % 2 else "modified"))
    model = _model(robot)
    solver = model.solver
    q = np.random.default_rng(seed).uniform(-np.pi, np.pi, 6)
    T06 = model.chain.target_06(robot.frame_pose(q))
    T06s = T06.copy()
    T06s[:3, 3] /= solver.scale
    th = q + solver.elim.th0

    def b(t):
        return np.array([math.cos(t), math.sin(t), 1.0])

    assert len(solver.elim.arrangements) == 36
    for arr in solver.elim.arrangements:
        P, r = arr.matrices(T06s)
        lhs = np.einsum("i,ikm->km", b(th[arr.pivot]), P) @ np.outer(b(th[arr.others[0]]), b(th[arr.others[1]])).ravel()
        rhs = r @ np.outer(b(th[arr.pair[0]]), b(th[arr.pair[1]])).ravel()
        assert np.abs(lhs - rhs)[:14].max() < 1e-10, (arr.j, arr.n1, arr.piv)


def test_singular_poses_of_the_jaco(jaco):
    """Configurations on a grid of right angles (many of them singular: axes 4 and 6 parallel
    at q₅ = π, axes 2 and 3 always parallel): never an empty answer for a reachable pose, every
    solution reaches it, and the generating configuration is among them unless it is singular
    (a known limit: at a singular configuration the double root or continuum it sits on can be
    lost; the isolated solutions of the pose are still returned)."""
    rng = np.random.default_rng(0)
    missed = 0
    for _ in range(30):
        q = rng.choice([0.0, math.pi / 2, math.pi, -math.pi / 2], 6)
        T = jaco.frame_pose(q)
        sols = ik_analytic(jaco, T)
        assert sols, q
        check(jaco, None, T, sols)
        if min(angle_dist(s.q, q) for s in sols) > 1e-6:
            missed += 1
            sv = np.linalg.svd(jaco.jacobian(q), compute_uv=False)
            assert sv[-1] < 1e-8 * sv[0], q  # only a singular generator may be missed
    assert missed < 5



# ---------------------------------------------------------------- the compiled pipeline's linear algebra
# (robokit.kernels.general_6r has its own eigenvalues, SVD, singular value ratios, LU: each
# checked against numpy's LAPACK, an independent implementation)
@settings(max_examples=30, deadline=None, derandomize=True)
@given(st.integers(0, 2**31), st.sampled_from(["dense", "companion", "clustered"]))
def test_eigenvalues_match_lapack(seed, kind):
    """Balancing + Hessenberg + Francis double-shift QR against numpy.linalg.eigvals: dense
    matrices, the 24 × 24 companion shape of the solver (zero and identity blocks) and matrices
    with clustered eigenvalues (a double root split by 1e-8, as on nearly special arms)."""
    from robokit.kernels.general_6r import eigenvalues

    rng = np.random.default_rng(seed)
    n = 24
    if kind == "dense":
        M = rng.standard_normal((n, n)) * 10.0 ** rng.uniform(-3, 3)
    elif kind == "companion":
        M = np.zeros((n, n))
        M[:12, 12:] = np.eye(12)
        M[12:] = rng.standard_normal((12, n))
    else:
        lam = rng.standard_normal(n)
        lam[1] = lam[0] + 1e-8
        S = rng.standard_normal((n, n)) + 3 * np.eye(n)
        M = S @ np.diag(lam) @ np.linalg.inv(S)
    wr, wi = np.empty(n), np.empty(n)
    assert eigenvalues(M.copy(), wr, wi) == 0
    ours = np.sort_complex(wr + 1j * wi)
    ref = np.linalg.eigvals(M)
    scale = np.abs(ref).max()
    # every eigenvalue has its partner in the other set: to 1e-9 of the spectrum's size, and to
    # 1e-6 for the clustered pair (a perturbation ε moves a double root by about √ε)
    tol = (1e-6 if kind == "clustered" else 1e-9) * scale
    for z in ref:
        assert np.abs(ours - z).min() < tol, (z, ours)
    for z in ours:
        assert np.abs(ref - z).min() < tol, (z, ref)


@settings(max_examples=30, deadline=None, derandomize=True)
@given(st.integers(0, 2**31), st.sampled_from([(12, 12), (14, 8), (6, 6)]), st.floats(-12, 0))
def test_singular_values_match_lapack(seed, shape, log_cond):
    """sv_ratio (Sturm bisection on the Golub–Kahan form) and the one-sided Jacobi SVD against
    numpy.linalg.svd, down to condition numbers of 1e12."""
    from robokit.kernels.general_6r import _svd_jacobi, sv_ratio

    rng = np.random.default_rng(seed)
    m, n = shape
    U, _ = np.linalg.qr(rng.standard_normal((m, m)))
    V, _ = np.linalg.qr(rng.standard_normal((n, n)))
    s = np.sort(10.0 ** rng.uniform(log_cond, 0.0, n))[::-1]
    s[0], s[-1] = 1.0, 10.0 ** log_cond
    A = U[:, :n] @ np.diag(s) @ V.T * 3.7
    ref = np.linalg.svd(A, compute_uv=False)
    # the bisection's 1e-7 relative, plus rounding: σ_min is known to about ε σ_max either way
    assert abs(sv_ratio(A.copy()) - ref[-1] / ref[0]) < 1e-6 * ref[-1] / ref[0] + 1e-14
    sv, Uo, Vo = np.empty(n), np.empty((m, n)), np.empty((n, n))
    _svd_jacobi(A.copy(), sv, Uo, Vo)
    assert np.abs(sv - ref).max() < 1e-13 * ref[0] * n
    assert np.abs(Uo @ np.diag(sv) @ Vo.T - A).max() < 1e-13 * ref[0] * n
    assert np.abs(Vo.T @ Vo - np.eye(n)).max() < 1e-12


def test_left_null_space_and_null_vector():
    """The Householder left null space of a 14 × 8 matrix is orthonormal and annihilates it; the
    inverse-iteration null vector of A y² + B y + C at a root of its determinant is one."""
    from robokit.kernels.general_6r import _left_null_space, null_vector

    rng = np.random.default_rng(4)
    Q = rng.standard_normal((14, 8))
    N = np.empty((14, 6))
    _left_null_space(Q, N)
    assert np.abs(N.T @ Q).max() < 1e-13 * np.abs(Q).max()
    assert np.abs(N.T @ N - np.eye(6)).max() < 1e-13
    full = np.linalg.svd(Q)[0][:, 8:]  # LAPACK's basis of the same space
    assert np.abs(full @ (full.T @ N) - N).max() < 1e-12
    work = rng.standard_normal((3, 12, 12))
    for y in (0.3, -2.5):  # a root at y: shift C so that A y² + B y + C has a null vector
        v0 = rng.standard_normal(12)
        L = work[0] * y * y + work[1] * y + work[2]
        work[2] -= np.outer(L @ v0, v0) / (v0 @ v0)
        v = np.empty(12)
        null_vector(work, y, v)
        L = work[0] * y * y + work[1] * y + work[2]
        assert np.linalg.norm(L @ v) < 1e-10 * np.linalg.norm(L)
        assert abs(abs(v @ v0) / np.linalg.norm(v0) - 1.0) < 1e-10


def test_the_solve_is_one_kernel_that_also_runs_as_plain_python(jaco):
    """One compiled call per pose (robokit.kernels.general_6r.solve_pose) with the per-arm
    tables kept on the solver; the same kernel run as plain Python (what NUMBA_DISABLE_JIT
    runs) gives the same rows."""
    from robokit.ik.closed_form import analytic_ik
    from robokit.kernels._jit import interpreted
    from robokit.kernels.general_6r import solve_pose

    model = analytic_ik(jaco)
    el = model.solver.elim
    assert len(el.kreadings[0]) == 4 and el.kreadings[0].shape[1] == 47  # the 4 best readings, packed once
    q = np.array([0.4, 1.9, 1.1, -0.6, 2.2, 0.3])
    T06s = model.chain.target_06(jaco.frame_pose(q))
    T06s[:3, 3] /= model.solver.scale
    out_c, out_p = np.empty((96, 7)), np.empty((96, 7))
    m = solve_pose(el.kchain, el.ktol, *el.kreadings, T06s, out_c)
    assert interpreted(solve_pose)(el.kchain, el.ktol, *el.kreadings, T06s, out_p) == m > 0
    assert np.abs(out_c[:m] - out_p[:m]).max() < 1e-9
    T = np.full((4, 4), np.nan)
    assert solve_pose(el.kchain, el.ktol, *el.kreadings, T, out_c) == 0  # not a pose: no solution


def _reading_pencil_and_companion(arr, T06s):
    """(A, B, C) of one reading at the scaled pose, and its 24 × 24 companion matrix (A regular)."""
    from robokit.kernels.general_6r import companion, pencil

    P, r = arr.matrices(T06s)
    work = np.empty((3, 12, 12))
    pencil(P, r, math.cos(0.6180339887498949), math.sin(0.6180339887498949), work, np.empty((3, 14, 9)),
           np.empty((8, 14)))
    M = np.empty((24, 24))
    assert companion(work, M) > 1e-10
    return work, M


@pytest.mark.parametrize("seed", [6, 7, 11])
def test_the_roots_at_plus_minus_i_and_their_deflation(seed):
    """det(A x² + B x + C) has the factor (1 + x²)⁴ exactly for the readings whose pivot is the
    joint of its group farthest from the eliminated one (numpy's SVD of L(i), independent of the
    kernel's elimination); the deflated matrix keeps every other eigenvalue of the 24 × 24
    companion matrix (numpy's eig), and a reading without the roots is left alone."""
    from robokit.ik.closed_form import analytic_ik as _model
    from robokit.kernels.general_6r import deflate, nullity_at_i

    robot = robokit.load(random_general_arm(seed, "standard"))
    model = _model(robot)
    solver = model.solver
    rng = np.random.default_rng(seed)
    T06s = model.chain.target_06(robot.frame_pose(rng.uniform(-np.pi, np.pi, 6)))
    T06s[:3, 3] /= solver.scale
    kinds = set()
    for arr in solver.elim.arrangements[:12]:
        work, M = _reading_pencil_and_companion(arr, T06s)
        A, B, C = work
        sv = np.linalg.svd(-A + 1j * B + C, compute_uv=False)
        null = int((sv < 1e-10 * sv[0]).sum())
        assert null == (4 if arr.piv == 2 else 0), (arr.j, arr.n1, arr.piv, sv[-5:] / sv[0])
        assert nullity_at_i(work) == null
        # a clear gap (the count is not a threshold's accident): null ones at rounding, the others far above
        assert sv[12 - null - 1] > 1e-9 * sv[0] and (null == 0 or sv[-1] < 1e-13 * sv[0])
        full = np.linalg.eigvals(M)
        M0 = M.copy()
        n = deflate(work, M)
        assert n == 24 - 2 * null
        if null == 0:
            assert np.array_equal(M, M0)  # untouched
            kinds.add("kept")
            continue
        kinds.add("deflated")
        rest = np.linalg.eigvals(M[:n, :n])
        expected = np.concatenate([rest, [1j] * null, [-1j] * null])
        # the same 24 eigenvalues (as a multiset: match each one to its nearest, without reuse)
        left = list(full)
        for lam in expected:
            k = int(np.argmin([abs(lam - x) for x in left]))
            assert abs(lam - left[k]) < 1e-6 * (1 + abs(lam)), (lam, left[k])
            left.pop(k)
        # and the real ones (the candidates) to far better than the polish needs
        for lam in full[np.abs(full.imag) < 1e-9]:
            assert np.min(np.abs(rest - lam)) < 1e-9 * (1 + abs(lam))
    assert kinds == {"kept", "deflated"}


def test_the_solver_deflates_where_the_roots_are(jaco):
    """Each kept reading's deflate count is the null space of L(i) at a fresh pose (numpy's SVD):
    the Jaco's best readings have two pairs (its special geometry), the farthest pivots four."""
    from robokit.ik.closed_form import analytic_ik as _model

    model = _model(jaco)
    solver = model.solver
    rng = np.random.default_rng(5)
    for arr in solver.elim.arrangements[:4]:
        T06s = model.chain.target_06(jaco.frame_pose(rng.uniform(-np.pi, np.pi, 6)))
        T06s[:3, 3] /= solver.scale
        work, _ = _reading_pencil_and_companion(arr, T06s)
        A, B, C = work
        sv = np.linalg.svd(-A + 1j * B + C, compute_uv=False)
        assert arr.deflate == int((sv < 1e-10 * sv[0]).sum()) > 0
        assert arr.deflate == (4 if arr.piv == 2 else 2)
        assert arr.packed()[0][46] == arr.deflate


# ---------------------------------------------------------------- three exactly parallel axes, no special method
def parallel_run_table(seed, run, convention):
    """A random 6R arm whose axes run+1 … run+3 are exactly parallel (twists 0 or π between them) and
    that has no other structure (axes 5 and 6 do not meet, no spherical wrist)."""
    rng = np.random.default_rng(seed)
    links = []
    for i in range(6):
        alpha = float(rng.uniform(-3, 3))
        if i in ((run, run + 1) if convention == "standard" else (run + 1, run + 2)):
            alpha = float(rng.choice([0.0, math.pi]))
        links.append(DHLink("R", a=rng.uniform(0.05, 0.4), d=rng.uniform(-0.2, 0.2), alpha=alpha,
                            theta=rng.uniform(-1, 1), qlim=WIDE))
    return DHTable(f"parallel{run}_{seed}", convention, tuple(links))


def near_fold_configurations(robot, middle, rng, n):
    """n random configurations; every third with the run's middle joint near 0 (the run stretched out,
    where two pairs of roots come close)."""
    out = []
    for k in range(n):
        q = robot.random_configuration(rng)
        if k % 3 == 0:
            q[middle] *= 1e-3
        out.append(q)
    return out


@pytest.mark.parametrize("convention", ["standard", "modified"])
@pytest.mark.parametrize("run", [0, 1, 2, 3])
def test_three_exactly_parallel_axes_without_a_special_method_lose_no_root(run, convention):
    """Three consecutive axes exactly parallel make the elimination's eigenproblem degenerate (double and
    infinite roots): it lost about half the roots. Its tables are now built for the arm with the run
    turned (PARALLEL_TURN) and every root polished on the arm itself: each solution exact, the generating
    configuration among them, every root of a 200-start numerical sweep returned — at random poses and
    with the run stretched out."""
    from robokit.ik.general_6r import PARALLEL_TURN

    robot = robokit.load(parallel_run_table(10 + run, run, convention))
    kind = ik_analytic_kind(robot)
    assert kind.method == "general 6R"
    assert f"axes {run + 1}–{run + 3} are exactly parallel" in kind.reason and f"{PARALLEL_TURN:g} rad" in kind.reason
    rng = np.random.default_rng(run)
    for q in near_fold_configurations(robot, run + 1, rng, 6):
        T = robot.frame_pose(q)
        sols = ik_analytic(robot, T)
        check(robot, q, T, sols)
        assert_none_missed(robot, T, sols)


def test_the_so100_gets_every_root():
    """The SO-100 (example-robot-data; LeRobot's arm): axes 2–4 exactly parallel, axes 5 and 6 2 cm apart,
    so that neither special method takes it. Before, about half of a numerical sweep's roots were
    missing (with a warning); now every one, at 8 random poses, each exact."""
    import warnings

    with warnings.catch_warnings():
        warnings.simplefilter("ignore", robokit.RobokitWarning)  # (its floating base, fixed: a note)
        robot = robokit.load("so100")
    with warnings.catch_warnings():
        warnings.simplefilter("error", robokit.RobokitWarning)  # no "may miss some" any more
        assert ik_analytic_kind(robot).method == "general 6R"
    rng = np.random.default_rng(4)
    for q in near_fold_configurations(robot, 2, rng, 8):
        T = robot.frame_pose(q)
        sols = ik_analytic(robot, T)
        check(robot, q, T, sols)
        assert_none_missed(robot, T, sols)


def _check_gen3(robot, q, T, sols, seeds, rng):
    """Exact on Pinocchio, the generating configuration among the solutions (1e-7), an even number (a
    general 6R arm's real roots away from a double root), none of the sweep's roots missing."""
    from ik_sweep import sweep

    for s in sols:
        assert np.abs(robot.frame_pose(s.q) - T).max() < TOL, s.label
    assert sols and min(angle_dist(s.q, q) for s in sols) < 1e-7, "the generating configuration is missing"
    assert len(sols) % 2 == 0, f"{len(sols)} solutions"
    found = sweep(robot, T, seeds, rng)
    for f in found:
        assert min(angle_dist(f, s.q) for s in sols) < 1e-6, f"numerical solution {f} not returned"
    return len(found)


def test_gen3_lite_near_its_elbow_singularity():
    """The Gen3 lite's axes 2 and 3 are 7.3e-6 rad from parallel: its DH table's offsets are -38 km,
    and the table, rounded at that size, reproduces the arm (Pinocchio) only to ~1e-11 m. The general 6R
    method polished its solutions on that table: with θ₃ within 2e-4 rad of the elbow singularity the
    generating configuration was missing (1e-7 to 3e-6 rad off) at 29 of 30 measured poses, 10 had an
    odd number of solutions (unmerged copies of one root; near misses 3.5e-10 m off the pose, no root
    of the arm) and 3 of a 300-start sweep's 193 roots were not returned. Each solution is now finished
    on the arm's own kinematics (general_6r.ArmPolish): 1 of 30 missing (docs/course/inverse-kinematics-closed-form.md)."""
    robot = _gen3_lite()
    kind = ik_analytic_kind(robot)
    assert kind.method == "general 6R" and "finished by Newton's method on the arm's own kinematics" in kind.reason
    rng = np.random.default_rng(0)
    roots = 0
    for k in range(15):
        q = robot.random_configuration(rng)
        q[2] = _elbow_singular(robot, q) + rng.uniform(-2e-4, 2e-4)
        T = robot.frame_pose(q)
        roots += _check_gen3(robot, q, T, ik_analytic(robot, T), 300, k)
    assert roots >= 30  # the sweep found roots at most poses: the check is not empty


def test_gen3_lite_random_poses():
    """Away from the elbow singularity (random configurations): the same checks (they held before)."""
    robot = _gen3_lite()
    rng = np.random.default_rng(1)
    for k in range(8):
        q = robot.random_configuration(rng)
        T = robot.frame_pose(q)
        assert _check_gen3(robot, q, T, ik_analytic(robot, T), 200, k) > 0
