"""LSPB (Lecture 3): symmetry, peak velocity, feasibility, and the lecture's multi-segment worked example."""
import math

import numpy as np
import pytest
from hypothesis import given, settings, strategies as st

from robokit.trajectory import lspb_trajectory, lspb_via_trajectory


def central_fd(tr):
    h = tr.t[1] - tr.t[0]
    return (tr.q[2:] - tr.q[:-2]) / (2 * h), h


@pytest.mark.parametrize("kw", [dict(acceleration=3.0), dict(blend_time=0.4), dict(max_velocity=0.8), {}])
def test_lspb_symmetric_with_stated_peak_and_rest_ends(kw):
    q0, qf, tf = 0.2, 1.4, 2.0
    tr = lspb_trajectory(q0, qf, tf, t=2001, **kw)
    q = tr.q[:, 0]
    # symmetric about (tf/2, (q0+qf)/2): q(tf − t) = q0 + qf − q(t)
    np.testing.assert_allclose(q[::-1], q0 + qf - q, atol=1e-12)
    np.testing.assert_allclose(tr.qd[::-1, 0], tr.qd[:, 0], atol=1e-12)
    assert q[0] == q0 and abs(q[-1] - qf) < 1e-12
    assert tr.qd[0, 0] == 0.0 and abs(tr.qd[-1, 0]) < 1e-12
    V = tr.info["velocity"][0]
    tb = tr.info["blend_time"][0]
    a = tr.info["acceleration"][0]
    assert abs(tr.qd[:, 0].max() - V) < 1e-12  # the stated peak is reached and never exceeded
    assert abs(V - (qf - q0) / (tf - tb)) < 1e-12  # V = (θf − θ0)/(tf − tb)
    assert abs(V - a * tb) < 1e-12  # V = θ̈ tb
    if "acceleration" in kw:
        assert a == pytest.approx(kw["acceleration"], rel=1e-12)
        # the lecture's formula t_b = t/2 − √(θ̈²t² − 4θ̈(θf − θ0))/(2θ̈)
        A = kw["acceleration"]
        assert tb == pytest.approx(tf / 2 - math.sqrt(A**2 * tf**2 - 4 * A * (qf - q0)) / (2 * A), rel=1e-12)
    if "blend_time" in kw:
        assert tb == kw["blend_time"]
    if "max_velocity" in kw:
        assert V == pytest.approx(kw["max_velocity"], rel=1e-12)
    if not kw:
        assert V == pytest.approx(1.5 * (qf - q0) / tf, rel=1e-12)
    fd, h = central_fd(tr)
    np.testing.assert_allclose(fd, tr.qd[1:-1], atol=a * h)  # C1: finite differences of q match qd


def test_lspb_phases_have_constant_acceleration():
    tr = lspb_trajectory(1.0, -1.0, 4.0, t=401, acceleration=1.0)
    tb = tr.info["blend_time"][0]
    a = tr.info["acceleration"][0]
    assert a == -1.0  # sign follows the motion
    t, qdd = tr.t, tr.qdd[:, 0]
    np.testing.assert_allclose(qdd[t < tb - 1e-9], a)
    np.testing.assert_allclose(qdd[(t > tb + 1e-9) & (t < 4 - tb - 1e-9)], 0.0)
    np.testing.assert_allclose(qdd[t > 4 - tb + 1e-9], -a)


def test_lspb_feasibility_limit_is_triangular_and_below_it_errors():
    tf, d = 2.0, 1.5
    amin = 4 * d / tf**2
    tr = lspb_trajectory(0.0, d, tf, t=201, acceleration=amin)
    assert tr.info["blend_time"][0] == pytest.approx(tf / 2, rel=1e-9)  # no linear segment
    assert abs(tr.q[100, 0] - d / 2) < 1e-12
    with pytest.raises(ValueError, match=r"acceleration.*too small.*4\|θf − θ0\|/tf² = 1\.5"):
        lspb_trajectory(0.0, d, tf, acceleration=0.99 * amin)


def test_lspb_multi_axis_independent_axes_and_stationary_axis():
    tr = lspb_trajectory([0.0, 1.0, 2.0], [1.0, 1.0, -2.0], 2.0, t=11, acceleration=[2.0, 1.0, 8.0])
    assert tr.q.shape == (11, 3)
    np.testing.assert_allclose(tr.q[:, 1], 1.0)
    np.testing.assert_allclose(tr.qd[:, 1], 0.0)
    np.testing.assert_allclose(tr.q[-1], [1.0, 1.0, -2.0], atol=1e-12)


@pytest.mark.parametrize(
    "kw, word",
    [
        (dict(acceleration=0.1), "acceleration"),
        (dict(acceleration=-1.0), "acceleration"),
        (dict(blend_time=1.5), "blend_time"),
        (dict(blend_time=0.0), "blend_time"),
        (dict(max_velocity=0.4), "max_velocity"),  # < |Δ|/tf = 0.5: cannot arrive in time
        (dict(max_velocity=1.2), "max_velocity"),  # > 2|Δ|/tf = 1.0
        (dict(acceleration=1.0, blend_time=0.5), "at most one"),
    ],
)
def test_lspb_bad_input(kw, word):
    with pytest.raises(ValueError, match=word):
        lspb_trajectory(0.0, 1.0, 2.0, **kw)


def test_lspb_zero_duration():
    with pytest.raises(ValueError, match="tf"):
        lspb_trajectory(0.0, 1.0, 0.0)


# ------------------------------------------------ multi-segment LSPB: the lecture's example


def test_lecture_3_worked_example():
    """θ1 = 5°, θ2 = 15°, θ3 = 40°, t_d12 = t_d23 = 1 s, |θ̈| = 80°/s² (Lecture 3 / Craig ex. 7.4)."""
    tr = lspb_via_trajectory([[5.0], [15.0], [40.0]], [1.0, 1.0], 80.0, t=4001)
    inf = tr.info
    # first segment: t1 = t_d12 − √(t_d12² − 2(θ2 − θ1)/θ̈1), θ̇12 = (θ2 − θ1)/(t_d12 − t1/2)
    t1 = 1 - math.sqrt(1 - 2 * 10 / 80)
    v12 = 10 / (1 - t1 / 2)
    # last segment: θ̈3 = −80, t3 = t_d23 − √(t_d23² + 2(θ3 − θ2)/θ̈3), θ̇23 = (θ3 − θ2)/(t_d23 − t3/2)
    t3 = 1 - math.sqrt(1 + 2 * 25 / -80)
    v23 = 25 / (1 - t3 / 2)
    # middle blend: θ̈2 = SGN(θ̇23 − θ̇12)·80, t2 = (θ̇23 − θ̇12)/θ̈2
    t2 = (v23 - v12) / 80
    t12 = 1 - t1 - t2 / 2
    t23 = 1 - t3 - t2 / 2
    np.testing.assert_allclose(inf["blend_times"][:, 0], [t1, t2, t3], rtol=1e-12)
    np.testing.assert_allclose(inf["velocities"][:, 0], [v12, v23], rtol=1e-12)
    np.testing.assert_allclose(inf["linear_durations"][:, 0], [t12, t23], rtol=1e-12)
    np.testing.assert_array_equal(inf["accelerations"][:, 0], [80.0, 80.0, -80.0])
    # the rounded values printed in Craig's solution
    np.testing.assert_allclose(inf["blend_times"][:, 0], [0.134, 0.254, 0.388], atol=6e-4)
    np.testing.assert_allclose(inf["velocities"][:, 0], [10.72, 31.01], atol=6e-3)
    np.testing.assert_allclose(inf["linear_durations"][:, 0], [0.74, 0.485], atol=6e-3)
    # start and goal reached exactly at rest; the via point is approached, not passed
    q, t = tr.q[:, 0], tr.t
    assert q[0] == 5.0 and abs(q[-1] - 40.0) < 1e-12
    assert abs(tr.qd[0, 0]) < 1e-12 and abs(tr.qd[-1, 0]) < 1e-12
    assert abs(q[t == 1.0][0] - 15.0) > 0.5
    # both straight lines pass through the via point at its time
    lin1 = (t > t1 + 1e-6) & (t < 1 - t2 / 2 - 1e-6)
    np.testing.assert_allclose(q[lin1], 15 + v12 * (t[lin1] - 1), atol=1e-12)
    lin2 = (t > 1 + t2 / 2 + 1e-6) & (t < 2 - t3 - 1e-6)
    np.testing.assert_allclose(q[lin2], 15 + v23 * (t[lin2] - 1), atol=1e-12)
    fd = (q[2:] - q[:-2]) / (2 * (t[1] - t[0]))
    np.testing.assert_allclose(fd, tr.qd[1:-1, 0], atol=80 * (t[1] - t[0]))


def test_via_lspb_too_small_acceleration_errors():
    with pytest.raises(ValueError, match="acceleration.*first segment"):
        lspb_via_trajectory([[5.0], [15.0], [40.0]], [1.0, 1.0], 10.0)
    with pytest.raises(ValueError, match="durations"):
        lspb_via_trajectory([[5.0], [15.0], [40.0]], [1.0, 0.0], 80.0)
    with pytest.raises(ValueError, match="durations"):
        lspb_via_trajectory([[5.0], [15.0], [40.0]], [1.0], 80.0)


@st.composite
def via_lspb_problem(draw):
    m = draw(st.integers(2, 5))
    n = draw(st.integers(1, 2))
    P = np.array(draw(st.lists(st.lists(st.floats(-2, 2), min_size=n, max_size=n), min_size=m, max_size=m)))
    td = np.array(draw(st.lists(st.floats(0.5, 2.0), min_size=m - 1, max_size=m - 1)))
    return P, td


@settings(max_examples=60, deadline=None)
@given(via_lspb_problem())
def test_via_lspb_random_points(problem):
    P, td = problem
    # a generous acceleration keeps every blend short enough (feasible)
    acc = 40.0 * (1 + np.abs(np.diff(P, axis=0)).max()) / td.min() ** 2
    tr = lspb_via_trajectory(P, td, acc, t=2001)
    np.testing.assert_allclose(tr.q[0], P[0], atol=1e-12)
    np.testing.assert_allclose(tr.q[-1], P[-1], atol=1e-9)
    np.testing.assert_allclose(tr.qd[[0, -1]], 0.0, atol=1e-9)
    assert np.all(tr.info["linear_durations"] >= 0)
    h = tr.t[1] - tr.t[0]
    fd = (tr.q[2:] - tr.q[:-2]) / (2 * h)
    np.testing.assert_allclose(fd, tr.qd[1:-1], atol=acc * h)  # C1
    assert np.all(np.abs(tr.qdd) <= acc * (1 + 1e-12))  # accelerations never exceed the given magnitude
