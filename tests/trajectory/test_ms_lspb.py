"""ms_trajectory's quirks (faithful to Corke's mstraj, kept) and ms_lspb_trajectory, the plain
trajectory a student expects: against a closed form written here, the lecture's LSPB through via
points (Craig's formulas, lspb_via_trajectory) and the properties that define it."""
import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import robokit as rk
from robokit.trajectory import lspb_via_trajectory, ms_lspb_trajectory

README = dict(dt=0.05, tacc=0.5, qdmax=0.5)
VIA = np.array([[0, 0], [1, 0], [1, 1]], dtype=float)


def test_the_readme_quirks_of_mstraj_are_what_the_readme_says():
    """The faithful function keeps mstraj's numbers: peak speed 0.672 > qdmax, first sample 0.004, first
    via time −0.05 s (and lines slower than qdmax: 1/2.25)."""
    ms = rk.ms_trajectory(VIA, **README)
    assert abs(ms.qd).max() == pytest.approx(0.672, abs=5e-4)
    assert ms.q[0, 0] == pytest.approx(0.004, abs=5e-4) and ms.t[0] == 0.0
    assert ms.info["via_times"][0] == pytest.approx(-0.05)
    assert abs(ms.qd[~ms.info["in_blend"], 0]).max() == pytest.approx(1 / 2.25)


def _closed_form(t):
    """The README example by hand: parabolic blends of 0.5 s (|a| = 0.5/0.5 = 1) around the via points,
    lines at 0.5 passing (0,0) at 0.25 s, (1,0) at 2.25 s, (1,1) at 4.25 s; the end at 4.5 s."""
    x = np.piecewise(t, [t < 0.5, (t >= 0.5) & (t < 2.0), (t >= 2.0) & (t < 2.5), t >= 2.5],
                     [lambda s: 0.5 * s ** 2, lambda s: 0.5 * (s - 0.25),
                      lambda s: 1 + 0.5 * (s - 2.25) - 0.5 * (s - 2.0) ** 2, 1.0])
    y = np.piecewise(t, [t < 2.0, (t >= 2.0) & (t < 2.5), (t >= 2.5) & (t < 4.0), t >= 4.0],
                     [0.0, lambda s: 0.5 * (s - 2.0) ** 2, lambda s: 0.5 * (s - 2.25),
                      lambda s: 1 + 0.5 * (s - 4.25) - 0.5 * (s - 4.0) ** 2])
    return np.column_stack([x, y])


def test_plain_trajectory_equals_the_closed_form():
    tr = ms_lspb_trajectory(VIA, **README)
    assert tr.t[0] == 0.0 and tr.t[-1] == 4.5 and np.allclose(np.diff(tr.t), 0.05)
    assert np.abs(tr.q - _closed_form(tr.t)).max() < 1e-12
    assert np.array_equal(tr.q[0], VIA[0]) and np.array_equal(tr.q[-1], VIA[-1])
    assert abs(tr.qd).max() == 0.5  # exactly qdmax, never above
    assert tr.info["via_times"].tolist() == [0.0, 2.25, 4.5]


def test_plain_trajectory_equals_the_lectures_lspb_through_via_points():
    """The same motion from Craig's formulas (durations between via-point times, blend accelerations
    |ΔV|/tacc): the first and last segments' special formulas give back blend times equal to tacc."""
    P = np.array([[0.0, 1.0], [1.2, -0.5], [1.5, 1.1], [0.5, 1.5]])
    tacc, qdmax = 0.4, np.array([0.8, 1.1])
    tr = ms_lspb_trajectory(P, dt=0.01, tacc=tacc, qdmax=qdmax)
    V = tr.info["velocities"]
    dV = np.diff(np.vstack([np.zeros(2), V, np.zeros(2)]), axis=0)
    assert np.all(np.abs(dV) > 0)  # Craig's scheme needs a non-zero acceleration everywhere
    craig = lspb_via_trajectory(P, np.diff(tr.info["via_times"]), np.abs(dV) / tacc, t=tr.t)
    assert np.allclose(craig.info["blend_times"], tacc, atol=1e-9)
    assert np.abs(craig.q - tr.q).max() < 1e-9 and np.abs(craig.qd - tr.qd).max() < 1e-9


@settings(max_examples=40, deadline=None)
@given(st.integers(2, 5), st.integers(1, 3), st.integers(0, 2**31 - 1), st.just(0.0) | st.floats(0.01, 0.8),
       st.booleans())
def test_plain_trajectory_properties(m, n, seed, tacc, by_speed):
    rng = np.random.default_rng(seed)
    P = rng.uniform(-2, 2, (m, n))
    qdmax = rng.uniform(0.3, 2.0, n)
    if by_speed:
        tr = ms_lspb_trajectory(P, dt=0.01, tacc=tacc, qdmax=qdmax)
        T = tr.info["segment_times"]
        line = np.abs(tr.info["velocities"]) / qdmax
        assert np.allclose(line.max(axis=1)[T > tacc], 1.0)  # the slowest axis at its limit on every line
        assert np.all(np.abs(tr.qd) <= qdmax * (1 + 1e-12))  # and nowhere faster
    else:
        T = rng.uniform(tacc, tacc + 2.0, m - 1)
        tr = ms_lspb_trajectory(P, dt=0.01, tacc=tacc, tsegment=T)
    assert tr.t[0] == 0.0 and np.array_equal(tr.q[0], P[0]) and np.array_equal(tr.q[-1], P[-1])
    assert np.all(np.diff(tr.info["via_times"]) > 0)
    # velocity and acceleration are the derivatives of the position (differences on a fine grid, on the
    # intervals that cross no blend edge, where a piece ends)
    f = ms_lspb_trajectory(P, dt=1e-4, tacc=tacc, tsegment=tr.info["segment_times"])
    edges = np.concatenate([f.info["line_times"] - tacc / 2, f.info["line_times"] + tacc / 2])
    ok = ~np.any((f.t[:-1, None] < edges) & (edges <= f.t[1:, None]), axis=1)
    h = np.diff(f.t)[:, None]
    v_fd = np.diff(f.q, axis=0) / h
    mid = 0.5 * (f.qd[1:] + f.qd[:-1])
    assert np.abs(v_fd - mid)[ok].max() < 1e-6 * max(1.0, np.abs(f.qd).max())
    if tacc > 0:
        assert np.all(tr.qd[[0, -1]] == 0)  # from rest, to rest
        a_fd = np.diff(f.qd, axis=0) / h
        assert np.abs(a_fd - f.qdd[1:])[ok].max() < 1e-6 * max(1.0, np.abs(f.qdd).max())


def test_bad_input_is_named():
    with pytest.raises(rk.InputError, match="qdmax/tsegment"):
        ms_lspb_trajectory(VIA, dt=0.05, tacc=0.5)
    with pytest.raises(rk.InputError, match="tsegment: segment 1 lasts"):
        ms_lspb_trajectory(VIA, dt=0.05, tacc=0.5, tsegment=[1.0, 0.3])
    with pytest.raises(rk.InputError, match="qdmax"):
        ms_lspb_trajectory(VIA, dt=0.05, tacc=0.5, qdmax=[0.5, -1])
