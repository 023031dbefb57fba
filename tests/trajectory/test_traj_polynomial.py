"""Cubic, quintic and via-point cubics (Lecture 3) against the lecture's linear systems and by properties."""
import numpy as np
import pytest
from hypothesis import given, settings, strategies as st

from robokit.trajectory import cubic_coefficients, cubic_trajectory, cubic_via_trajectory, quintic_coefficients, quintic_trajectory, via_point_velocities

TOL = 1e-12


def poly(c, t, der=0):
    """Evaluate ascending coefficients c (d+1,) at t, derivative `der` (independent of the package)."""
    p = np.polynomial.polynomial.Polynomial(c)
    return p.deriv(der)(t) if der else p(t)


def test_cubic_coefficients_solve_the_lectures_4x4_system():
    rng = np.random.default_rng(1)
    for _ in range(20):
        th0, thf, v0, vf = rng.normal(size=4)
        T = rng.uniform(0.2, 5.0)
        # θ0 = a0; θf = a0 + a1 T + a2 T² + a3 T³; θ̇0 = a1; θ̇f = a1 + 2 a2 T + 3 a3 T²
        M = np.array([[1, 0, 0, 0], [1, T, T**2, T**3], [0, 1, 0, 0], [0, 1, 2 * T, 3 * T**2]])
        ref = np.linalg.solve(M, [th0, thf, v0, vf])
        np.testing.assert_allclose(cubic_coefficients(th0, thf, T, v0, vf)[:, 0], ref, rtol=1e-10, atol=1e-10)


def test_cubic_rest_to_rest_is_the_lecture_closed_form():
    # a2 = 3(θf − θ0)/tf², a3 = −2(θf − θ0)/tf³
    c = cubic_coefficients(0.3, 1.7, 2.0)[:, 0]
    np.testing.assert_allclose(c, [0.3, 0.0, 3 * 1.4 / 4, -2 * 1.4 / 8], rtol=0, atol=TOL)


def test_quintic_coefficients_solve_the_lectures_6x6_system():
    rng = np.random.default_rng(2)
    for _ in range(20):
        s0, sT, v0, vT, a0, aT = rng.normal(size=6)
        T = rng.uniform(0.2, 4.0)
        M = np.array(
            [
                [0, 0, 0, 0, 0, 1],
                [T**5, T**4, T**3, T**2, T, 1],
                [0, 0, 0, 0, 1, 0],
                [5 * T**4, 4 * T**3, 3 * T**2, 2 * T, 1, 0],
                [0, 0, 0, 2, 0, 0],
                [20 * T**3, 12 * T**2, 6 * T, 2, 0, 0],
            ]
        )
        ABCDEF = np.linalg.solve(M, [s0, sT, v0, vT, a0, aT])
        got = quintic_coefficients(s0, sT, T, v0, vT, a0, aT)[:, 0]
        np.testing.assert_allclose(got[::-1], ABCDEF, rtol=1e-9, atol=1e-9)


@settings(max_examples=60, deadline=None)
@given(
    st.lists(st.floats(-3, 3), min_size=6, max_size=6),
    st.floats(0.1, 10.0),
)
def test_quintic_trajectory_boundary_conditions(vals, T):
    q0, qf, v0, vf, a0, af = vals
    tr = quintic_trajectory(q0, qf, T, t=7, qd0=v0, qdf=vf, qdd0=a0, qddf=af)
    scale = 1 + max(abs(x) for x in vals) * max(1.0, T) ** 2
    assert tr.t[0] == 0.0 and tr.t[-1] == T
    assert tr.q[0, 0] == q0 and tr.qd[0, 0] == v0 and abs(tr.qdd[0, 0] - a0) <= 1e-15 * scale
    assert abs(tr.q[-1, 0] - qf) <= 1e-11 * scale
    assert abs(tr.qd[-1, 0] - vf) <= 1e-11 * scale
    assert abs(tr.qdd[-1, 0] - af) <= 1e-11 * scale


def test_cubic_trajectory_multi_axis_and_finite_differences():
    q0, qf = np.array([0.0, 1.0, -2.0]), np.array([1.0, -1.0, 0.5])
    tr = cubic_trajectory(q0, qf, 1.5, t=3001, qd0=[0.5, 0, 0], qdf=[0, -0.2, 1.0])
    assert tr.q.shape == tr.qd.shape == tr.qdd.shape == (3001, 3)
    np.testing.assert_array_equal(tr.q[0], q0)
    np.testing.assert_allclose(tr.q[-1], qf, atol=TOL)
    np.testing.assert_allclose(tr.qd[0], [0.5, 0, 0], atol=TOL)
    np.testing.assert_allclose(tr.qd[-1], [0, -0.2, 1.0], atol=TOL)
    h = tr.t[1] - tr.t[0]
    fd = (tr.q[2:] - tr.q[:-2]) / (2 * h)  # central differences: exact for cubics up to h² q''' / 6
    np.testing.assert_allclose(fd, tr.qd[1:-1], atol=1e-5)
    fdd = (tr.qd[2:] - tr.qd[:-2]) / (2 * h)
    np.testing.assert_allclose(fdd, tr.qdd[1:-1], atol=1e-6)


def test_cubic_trajectory_example_values():
    tr = cubic_trajectory(0.0, 1.0, 2.0, t=3)
    # θ = 3/4 t² − 1/4 t³: θ(1) = 0.5, θ̇(1) = 1.5 − 0.75
    np.testing.assert_allclose(tr.q[:, 0], [0, 0.5, 1.0], atol=TOL)
    np.testing.assert_allclose(tr.qd[:, 0], [0, 0.75, 0.0], atol=TOL)
    np.testing.assert_allclose(tr.qdd[:, 0], [1.5, 0.0, -1.5], atol=TOL)


# ---------------------------------------------------------------- via points


def test_heuristic_rule_of_lecture_3():
    # slopes: +1, +2 (same sign → mean 1.5), then −1 (sign change → 0), then 0 (zero slope → 0)
    P = np.array([[0.0], [1.0], [3.0], [2.0], [2.0]])
    v = via_point_velocities(P, [0, 1, 2, 3, 4], "heuristic", qd0=0.3, qdf=-0.1)
    np.testing.assert_array_equal(v[:, 0], [0.3, 1.5, 0.0, 0.0, -0.1])


def test_continuous_acceleration_matches_the_lectures_8_equation_system():
    th0, thv, thg = 0.2, 1.3, -0.4
    t1, t2 = 1.2, 0.7
    # unknowns a10 a11 a12 a13 a20 a21 a22 a23 (the lecture's equations, with its typo a12→a13 fixed)
    M = np.zeros((8, 8))
    b = np.zeros(8)
    M[0, 0] = 1; b[0] = th0
    M[1, :4] = [1, t1, t1**2, t1**3]; b[1] = thv
    M[2, 4] = 1; b[2] = thv
    M[3, 4:] = [1, t2, t2**2, t2**3]; b[3] = thg
    M[4, 1] = 1  # zero start velocity
    M[5, 4:] = [0, 1, 2 * t2, 3 * t2**2]  # zero end velocity
    M[6, :4] = [0, 1, 2 * t1, 3 * t1**2]; M[6, 5] = -1  # velocity continuity
    M[7, :4] = [0, 0, 2, 6 * t1]; M[7, 6] = -2  # acceleration continuity
    a = np.linalg.solve(M, b)
    tr = cubic_via_trajectory([[th0], [thv], [thg]], [0.0, t1, t1 + t2], t=5, velocities="continuous")
    C = tr.info["coefficients"][:, :, 0]
    np.testing.assert_allclose(C[0], a[:4], atol=1e-12)
    np.testing.assert_allclose(C[1], a[4:], atol=1e-12)


def _jumps(coeffs, times):
    """Left/right value, velocity and acceleration at every interior via point, from the coefficients."""
    out = []
    h = np.diff(times)
    for k in range(len(h) - 1):
        for der in range(3):
            left = np.array([poly(coeffs[k, :, j], h[k], der) for j in range(coeffs.shape[2])])
            right = np.array([poly(coeffs[k + 1, :, j], 0.0, der) for j in range(coeffs.shape[2])])
            out.append((der, left, right))
    return out


@st.composite
def via_problems(draw):
    m = draw(st.integers(2, 6))
    n = draw(st.integers(1, 3))
    P = np.array(draw(st.lists(st.lists(st.floats(-3, 3), min_size=n, max_size=n), min_size=m, max_size=m)))
    dts = np.array(draw(st.lists(st.floats(0.2, 3.0), min_size=m - 1, max_size=m - 1)))
    return P, np.concatenate([[0.5], 0.5 + np.cumsum(dts)])


@settings(max_examples=80, deadline=None)
@given(via_problems(), st.sampled_from(["heuristic", "continuous"]))
def test_via_cubics_pass_the_points_with_C1_or_C2(problem, method):
    P, times = problem
    tr = cubic_via_trajectory(P, times, t=times, velocities=method)
    scale = 1 + np.abs(P).max() / np.diff(times).min() ** 2
    # every point passed exactly at its time (samples at the via times)
    np.testing.assert_allclose(tr.q, P, atol=1e-12 * scale)
    np.testing.assert_allclose(tr.qd[0], 0, atol=1e-12 * scale)
    np.testing.assert_allclose(tr.qd[-1], 0, atol=1e-9 * scale)
    for der, left, right in _jumps(tr.info["coefficients"], times):
        if der == 2 and method == "heuristic":
            continue  # the heuristic promises C1 only
        np.testing.assert_allclose(left, right, atol=1e-9 * scale)


def test_via_cubics_given_velocities_method_1():
    P = np.array([[0.0, 1.0], [1.0, 0.0], [0.5, 0.5]])
    V = np.array([[0.1, 0.0], [0.7, -0.3], [0.0, 0.2]])
    tr = cubic_via_trajectory(P, [0, 1, 2], t=[0.0, 1.0, 2.0], velocities=V)
    np.testing.assert_allclose(tr.q, P, atol=TOL)
    np.testing.assert_allclose(tr.qd, V, atol=TOL)


def test_via_cubics_continuous_acceleration_numerically():
    P = np.array([[0.0], [1.0], [0.2], [2.0]])
    tr = cubic_via_trajectory(P, [0, 1, 2.5, 3], t=6001, velocities="continuous")
    h = tr.t[1] - tr.t[0]
    fd = (tr.q[2:] - tr.q[:-2]) / (2 * h)
    np.testing.assert_allclose(fd, tr.qd[1:-1], atol=1e-5)
    # acceleration has no jumps: consecutive samples differ by at most h · max|jerk| (jerk = 6 a3)
    max_jerk = np.abs(6 * tr.info["coefficients"][:, 3, 0]).max()
    assert np.abs(np.diff(tr.qdd[:, 0])).max() <= 1.001 * h * max_jerk
    heur = cubic_via_trajectory(P, [0, 1, 2.5, 3], t=6001, velocities="heuristic")
    assert np.abs(np.diff(heur.qdd[:, 0])).max() > 1.0  # the heuristic does jump in acceleration


# ---------------------------------------------------------------- bad input


@pytest.mark.parametrize(
    "call, word",
    [
        (lambda: cubic_trajectory(0, 1, 0.0), "tf"),
        (lambda: cubic_trajectory(0, 1, -1.0), "tf"),
        (lambda: cubic_trajectory([0, 1], [1, 2, 3], 1.0), "qf"),
        (lambda: cubic_trajectory([0, 1], [1, 2], 1.0, qd0=[1, 2, 3]), "qd0"),
        (lambda: quintic_trajectory(0, 1, 1.0, t=[0.0, 0.5, 0.4]), "t"),
        (lambda: quintic_trajectory(0, 1, 1.0, t=[0.0, 1.5]), "t"),
        (lambda: quintic_trajectory(0, 1, 1.0, t=1), "t"),
        (lambda: cubic_via_trajectory([[0], [1], [2]], [0, 1, 1]), "times"),
        (lambda: cubic_via_trajectory([[0], [1], [2]], [0, 2, 1]), "times"),
        (lambda: cubic_via_trajectory([[0], [1], [2]], [0, 1]), "times"),
        (lambda: cubic_via_trajectory([[[0.0]], [[1.0]]], [0, 1]), "viapoints"),  # 3-D (a 1-D list is one axis)
        (lambda: cubic_via_trajectory([[0], [1]], [0, 1], velocities="magic"), "^velocities: "),
        (lambda: cubic_via_trajectory([[0], [1]], [0, 1], velocities=[[0], [0]], qd0=1), "qd0"),
        (lambda: cubic_via_trajectory([[0], [1]], [0, 1], velocities=[[0, 1], [0, 1]]), "velocities"),
        (lambda: cubic_trajectory(0, np.nan, 1.0), "qf"),
    ],
)
def test_bad_input_names_the_argument(call, word):
    with pytest.raises(ValueError, match=word):
        call()
