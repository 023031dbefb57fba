"""ms_trajectory (seed 004 §5, Corke's mstraj): hand-checked cases, sample counts, continuity, bad input."""
import numpy as np
import pytest
from hypothesis import assume, given, settings, strategies as st

from robokit import Trajectory, ms_trajectory

VIA = np.array([[4.0, 1.0], [4.0, 4.0], [5.0, 2.0], [2.0, 5.0]])


def test_two_axis_qdmax_case_by_hand():
    """dt = 1, tacc = 1, qdmax = (2, 1), start (4, 1); the same numbers appear in the
    Robotics Toolbox's own test of mstraj (generated there with the MATLAB version).

    By hand: tacc = 1, half blend 1. Segment durations: (4,1)→(4,1): max(1 + 0) = 1 ≤ 2·tacc → 2;
    (4,1)→(4,4): 1 + ceil(3/1) = 4; (4,4)→(5,2): 1 + max(ceil(.5), ceil(2)) = 3;
    (5,2)→(2,5): 1 + max(ceil(1.5), ceil(3)) = 4. Each segment: one blend sample (the blend
    end, q_prev + 1·velocity), then the line at local times 2 … tseg − 1; one final blend
    sample at the goal.
    """
    tr = ms_trajectory(VIA, dt=1, tacc=1, qdmax=[2, 1], q0=[4, 1])
    expected = np.array(
        [
            [4, 1],
            [4, 1.75],
            [4, 2.5],
            [4, 3.25],
            [4 + 1 / 3, 4 - 2 / 3],
            [4 + 2 / 3, 4 - 4 / 3],
            [4.25, 2.75],
            [3.5, 3.5],
            [2.75, 4.25],
            [2, 5],
        ]
    )
    assert isinstance(tr, Trajectory)
    np.testing.assert_allclose(tr.q, expected, atol=1e-12)
    np.testing.assert_array_equal(tr.t, np.arange(10.0))
    np.testing.assert_array_equal(tr.info["segment_times"], [2, 4, 3, 4])
    np.testing.assert_array_equal(tr.info["slowest"], [0, 1, 1, 1])


def test_two_axis_tsegment_case_by_hand():
    # tsegment = (2, 1, 3, 4): the first two segments are too short for a linear part; with
    # one-step blends the blend ends q_prev + tacc2·velocity are still the samples.
    tr = ms_trajectory(VIA, dt=1, tacc=1, tsegment=[2, 1, 3, 4], q0=[4, 1])
    expected = np.array([[4, 1], [4, 4], [4 + 1 / 3, 4 - 2 / 3], [4 + 2 / 3, 4 - 4 / 3], [4.25, 2.75], [3.5, 3.5], [2.75, 4.25], [2, 5]])
    np.testing.assert_allclose(tr.q, expected, atol=1e-12)
    assert tr.t.shape == (8,) and tr.qd.shape == tr.qdd.shape == (8, 2)


def test_single_axis_two_segments_blend_by_hand():
    """Points 0 → 1 → 0.5, dt = 0.25, tacc = 0.5, qdmax = 2 (all exact in binary).

    tacc2 = 0.25. Segment 1: 0.25 + ceil(1/2/0.25)·0.25 = 0.75 ≤ 2·tacc → tseg = 1, velocity 1.
    Segment 2: 0.5 + 0.25 = 0.75 → tseg = 1, velocity −0.5.
    Samples: first half blend ends at 0.25; line at 0.5, 0.75; blend over 0.5 s from
    (0.75, v=1) to (1 − 0.25·0.5 = 0.875, v=−0.5): the quintic with zero end accelerations
    has midpoint (p0+p1)/2 + 5T(v0 − v1)/32 = 0.8125 + 5·0.5·1.5/32 = 0.9296875, then its end
    0.875; line at 0.75, 0.625; final blend ends at 0.5.
    """
    tr = ms_trajectory([[0.0], [1.0], [0.5]], dt=0.25, tacc=0.5, qdmax=2.0)
    np.testing.assert_allclose(tr.q[:, 0], [0.25, 0.5, 0.75, 0.9296875, 0.875, 0.75, 0.625, 0.5], atol=1e-12)
    np.testing.assert_allclose(tr.qd[[0, 1, 2, 4, 5, 6, 7], 0], [1, 1, 1, -0.5, -0.5, -0.5, 0], atol=1e-12)
    np.testing.assert_allclose(tr.qdd[[1, 2, 4, 5, 6], 0], 0, atol=1e-12)  # lines, and blend ends
    # the via point 1.0 is approached, not passed
    assert tr.q[:, 0].max() < 1.0 - 0.05
    # the lines pass the via points at info["via_times"]: 0 at t = −dt (the start, not a sample),
    # 1 at t = 0.75, 0.5 at t = 1.75
    np.testing.assert_allclose(tr.info["via_times"], [-0.25, 0.75, 1.75])


def test_docstring_case_tsegment():
    # tacc = 0.2 → tacc2 = 0.1: seg 1: 1 blend sample + line 0.2 … 0.9 (8); seg 2: 2 blend samples
    # + 8 line samples; final blend: 1 sample → 20
    tr = ms_trajectory([[0.0], [1.0], [3.0]], dt=0.1, tacc=0.2, tsegment=[1.0, 1.0])
    assert len(tr) == 20
    np.testing.assert_allclose(tr.q[:9, 0], np.arange(1, 10) / 10, atol=1e-12)
    # blend from (0.9, v=1) to (1.2, v=2) over 0.2 s, midpoint 1.05 + 5·0.2·(1 − 2)/32
    assert tr.q[9, 0] == pytest.approx(1.05 - 5 * 0.2 / 32, abs=1e-12)
    assert tr.q[-1, 0] == 3.0


def test_blend_time_rounds_up_to_whole_steps_like_mstraj():
    # tacc = 0.25 at dt = 0.1 rounds up to 3 steps (0.3 s); its half, 0.15, up to 2 steps
    tr = ms_trajectory([[0.0], [1.0]], dt=0.1, tacc=0.25, tsegment=[2.0])
    assert tr.info["tacc"][0] == pytest.approx(0.3)
    # half blend: 2 samples; line at steps 3 … round((2 − 0.2)/0.1) = 18: 16 samples; final half blend: 2
    assert len(tr) == 20


def test_initial_and_final_velocity():
    tr = ms_trajectory([[0.0, 0.0], [1.0, 2.0], [2.0, 0.0]], dt=0.05, tacc=0.3, qdmax=[1.0, 2.0], qd0=[0.2, 0.0], qdf=[0.0, -0.3])
    np.testing.assert_allclose(tr.qd[-1], [0.0, -0.3], atol=1e-12)
    np.testing.assert_allclose(tr.q[-1], [2.0, 0.0], atol=1e-12)


@st.composite
def grid_problem(draw):
    """Everything on the time grid: dt = 1/64 s, tacc = 2h·dt, segments ≥ (2h+1)·dt."""
    n = draw(st.integers(1, 3))
    ns = draw(st.integers(1, 4))
    h = draw(st.sampled_from([0, 4, 6, 8]))
    P = np.array(draw(st.lists(st.lists(st.floats(-2, 2), min_size=n, max_size=n), min_size=ns + 1, max_size=ns + 1)))
    steps = draw(st.lists(st.integers(2 * h + 1, 2 * h + 40), min_size=ns, max_size=ns))
    return P, 1 / 64, 2 * h / 64, np.array(steps) / 64


@settings(max_examples=80, deadline=None)
@given(grid_problem())
def test_random_via_points_count_continuity_and_goal(problem):
    P, dt, tacc, tseg = problem
    tr = ms_trajectory(P, dt, tacc, tsegment=tseg)
    # on the grid, the samples cover the planned time exactly: K·dt = Σ tsegment
    assert len(tr) == round(tseg.sum() / dt)
    np.testing.assert_allclose(tr.t, dt * np.arange(len(tr)))
    np.testing.assert_allclose(tr.q[-1], P[-1], atol=1e-12)
    if tacc > 0:
        np.testing.assert_allclose(tr.qd[-1], 0.0, atol=1e-9)
    # C1: by the mean-value theorem |Δq/dt − qd| ≤ dt/2·max|qdd| for a curve with these
    # derivatives (the sampled max of |qdd| is within a few % of the true one at 8+ samples per
    # blend, hence the margin); a jump in q or qd would be far larger
    if tacc > 0:
        amax = np.abs(tr.qdd).max() + 1e-12
        step = np.diff(tr.q, axis=0) / dt
        assert np.all(np.abs(step - tr.qd[:-1]) <= 0.75 * dt * amax + 1e-9)
        # C2: |Δqdd| ≤ dt·max|jerk|, and a quintic blend's jerk is at most ~ 60/8·|Δv|/T² … just
        # check no jump larger than the blend's whole acceleration swing
        assert np.all(np.abs(np.diff(tr.qdd, axis=0)) <= amax * (1 + 1e-9))
        # the interior via points where the direction changes are not passed through
        vt = tr.info["via_times"]
        for k in range(1, P.shape[0] - 1):
            d_in, d_out = P[k] - P[k - 1], P[k + 1] - P[k]
            if np.linalg.norm(d_in) > 0.1 and np.linalg.norm(d_out) > 0.1 and abs(np.dot(d_in, d_out)) < 0.99 * np.linalg.norm(d_in) * np.linalg.norm(d_out):
                near = np.abs(tr.t - vt[k]) <= tacc / 2 + 1e-9
                assert np.min(np.linalg.norm(tr.q[near] - P[k], axis=1)) > 1e-6


@settings(max_examples=40, deadline=None)
@given(
    st.lists(st.lists(st.floats(-3, 3), min_size=2, max_size=2), min_size=2, max_size=5),
    st.floats(0.1, 2.0),
    st.sampled_from([0.0, 0.2, 0.5, 1.0]),
)
def test_random_qdmax_respects_speed_and_reaches_goal(points, vmax, tacc):
    P = np.array(points)
    assume(tacc > 0 or np.any(P[1:] != P[0]))  # otherwise there is nothing to sample (ValueError)
    tr = ms_trajectory(P, 0.05, tacc, qdmax=vmax)
    np.testing.assert_allclose(tr.q[-1], P[-1], atol=1e-9)
    # the straight parts never exceed the limit (durations are rounded up to whole steps)
    lines = ~tr.info["in_blend"]
    assert np.all(tr.qdd[lines] == 0)
    assert np.all(np.abs(tr.qd[lines]) <= vmax * (1 + 1e-9))
    assert np.all(tr.info["segment_times"] >= 2 * tr.info["tacc"] - 1e-12)


@pytest.mark.parametrize(
    "kwargs, word",
    [
        (dict(dt=1, tacc=1), "qdmax/tsegment.*neither"),
        (dict(dt=1, tacc=1, qdmax=[2, 1], tsegment=[1, 2, 3, 4]), "qdmax/tsegment.*both"),
        (dict(dt=1, tacc=1, tsegment=[3, 4]), "tsegment"),
        (dict(dt=1, tacc=1, qdmax=[2, 1, 3]), "qdmax"),
        (dict(dt=1, tacc=[1, 2, 3, 4, 5], qdmax=[2, 1]), "tacc"),
        (dict(dt=1, tacc=-1, qdmax=[2, 1]), "tacc"),
        (dict(dt=0, tacc=1, qdmax=[2, 1]), "dt"),
        (dict(dt=-0.1, tacc=1, qdmax=[2, 1]), "dt"),
        (dict(dt=1, tacc=1, qdmax=[2, 0]), "qdmax"),
        (dict(dt=1, tacc=1, qdmax=[2, 1], q0=[1, 2, 3]), "q0"),
        (dict(dt=1, tacc=1, qdmax=[2, 1], qd0=[1, 2, 3], q0=[1, 2]), "qd0"),
        (dict(dt=1, tacc=1, qdmax=[2, 1], qdf=[1, 2, 3], q0=[1, 2]), "qdf"),
        (dict(dt=1, tacc=1, tsegment=[1, 0, 3, 4], q0=[4, 1]), "tsegment"),
    ],
)
def test_bad_input_names_the_argument(kwargs, word):
    with pytest.raises(ValueError, match=word):
        ms_trajectory(VIA, **kwargs)


def test_bad_viapoint_shapes():
    with pytest.raises(ValueError, match="viapoint.*reshape"):
        ms_trajectory([0.0, 1.0, 2.0], 0.1, 0.2, qdmax=1.0)
    with pytest.raises(ValueError, match="viapoint"):
        ms_trajectory([[0.0, 1.0]], 0.1, 0.2, qdmax=1.0)


def test_segment_too_short_for_its_blends_is_refused():
    # segment 2 lasts one step: no linear part, and the next blend spans 4 steps — mstraj would
    # start that blend from a stale point and jump; we refuse with the argument named
    with pytest.raises(ValueError, match=r"tsegment.*segment 1.*too short"):
        ms_trajectory([[0.0], [1.0], [2.0], [3.0]], dt=0.1, tacc=0.4, tsegment=[1.0, 0.1, 1.0])


def test_qdmax_bounds_the_straight_parts_and_the_docs_example_peaks_in_a_blend():
    """docs/course/trajectories.md's example: the velocity is the slope of the samples (not the
    function's own qd), on the straight parts within qdmax, and above it inside the first half
    blend, where the docs say it peaks (1.21 rad/s at t = 0.14 s)."""
    tr = ms_trajectory([[1.0, 0.5], [2.0, -0.5], [0.0, 0.0]], dt=0.01, tacc=0.5,
                       qdmax=[1.0, 1.0], q0=[0.0, 0.0])
    blend = tr.info["in_blend"]
    q = np.vstack([[0.0, 0.0], tr.q])  # the start is one step before the first sample
    slope = np.diff(q, axis=0) / 0.01  # secant velocity of step k ends at sample k
    on_line = ~blend & np.r_[False, ~blend[:-1]]  # both ends of the step on a straight part
    assert np.all(np.abs(slope[on_line]) <= 1.0 + 1e-9)
    assert np.all(np.abs(tr.qd[~blend]) <= 1.0 + 1e-9)
    peak = np.abs(tr.qd[:, 0]).argmax()
    assert blend[peak] and tr.t[peak] < 0.25  # inside the first half blend
    assert abs(tr.qd[peak, 0]) > 1.2  # above qdmax, as the docs say
    assert abs(abs(tr.qd[peak, 0]) - 1.21) < 0.005 and abs(tr.t[peak] - 0.14) < 0.011
