"""Monte Carlo localisation: systematic resampling's counting property, convergence of a seeded
run to the true path, agreement with the EKF on the same data, and the uncertainty scalars."""
import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from robokit.mobile import (EKFLocalization, LandmarkMap, Odometry, ParticleFilter, RangeBearingSensor,
                            angdiff, error_ellipse, odometry_model, systematic_resample, uncertainty)


@settings(max_examples=60, deadline=None)
@given(st.lists(st.floats(0.0, 1.0), min_size=1, max_size=40), st.integers(0, 2**31))
def test_systematic_resampling_copies_floor_or_ceil(ws, seed):
    w = np.asarray(ws)
    if w.sum() <= 1e-9:
        w = w + 1.0
    w = w / w.sum()
    idx = systematic_resample(w, seed)
    counts = np.bincount(idx, minlength=len(w))
    assert counts.sum() == len(w)
    Nw = len(w) * w
    assert np.all(counts >= np.floor(Nw - 1e-9)) and np.all(counts <= np.ceil(Nw + 1e-9))


def _run(order, seed=1, steps=150, n=800):
    rng = np.random.default_rng(seed)
    lm = LandmarkMap.random(12, 10.0, rng=rng)
    V = np.diag([0.02**2, np.deg2rad(0.5) ** 2])
    W = np.diag([0.1**2, np.deg2rad(2.0) ** 2])
    odo = Odometry(V, rng=rng)
    sensor = RangeBearingSensor(lm, W, max_range=12.0, rng=rng)
    x_true = np.array([-4.0, -2.0, 0.3])
    P0 = np.diag([0.3**2, 0.3**2, np.deg2rad(10) ** 2])
    x0 = x_true + np.array([0.25, -0.2, 0.1])
    pf = ParticleFilter(n, x0, P0, V, W, lm, rng=seed, order=order)
    ekf = EKFLocalization(x0, P0, V, W, lm, order=order)
    delta = np.array([0.1, 0.02])
    err_pf, err_ekf, gap, dets = [], [], [], []
    for k in range(steps):
        x_true = odometry_model(x_true, delta, order=order)
        meas = odo.measure(delta)
        pf.predict(meas)
        ekf.predict(meas)
        vis = sensor.visible(x_true)
        if vis:
            i = vis[k % len(vis)]
            z = sensor.measure(x_true, i)
            pf.update(z, i)
            ekf.update(z, i)
        err_pf.append(np.hypot(*(pf.x[:2] - x_true[:2])))
        err_ekf.append(np.hypot(*(ekf.x[:2] - x_true[:2])))
        gap.append(np.hypot(*(pf.x[:2] - ekf.x[:2])))
        dets.append((uncertainty(pf.P), uncertainty(ekf.P)))
    return np.array(err_pf), np.array(err_ekf), np.array(gap), np.array(dets), pf, ekf, x_true


@pytest.mark.parametrize("order", ["turn-move", "move-turn"])
def test_particle_filter_converges_and_agrees_with_ekf(order):
    err_pf, err_ekf, gap, dets, pf, ekf, x_true = _run(order)
    # converges from a 0.32 m initial error to the noise level of the sensor
    assert err_pf[0] < 0.5
    assert err_pf[-50:].mean() < 0.1
    assert abs(angdiff(pf.x[2], x_true[2])) < np.deg2rad(3)
    # same data, same models: the two estimates are close and equally uncertain (within a factor)
    assert gap[-50:].mean() < 0.05
    ratio = dets[-50:, 0] / dets[-50:, 1]
    assert 0.2 < np.median(ratio) < 5.0
    # the particle cloud shrinks from the prior as measurements come in
    assert dets[-1, 0] < dets[0, 0]


def test_same_seed_same_run():
    a = _run("turn-move", seed=5, steps=30, n=200)[4]
    b = _run("turn-move", seed=5, steps=30, n=200)[4]
    np.testing.assert_array_equal(a.particles, b.particles)


def test_prediction_spread_matches_linearised_covariance():
    """Without measurements, the particle covariance after one step matches F_v V F_vᵀ for a point prior."""
    lm = LandmarkMap([[0.0, 0.0]])
    V = np.diag([0.05**2, 0.02**2])
    for order in ("turn-move", "move-turn"):
        pf = ParticleFilter(40000, [1.0, 2.0, 0.4], np.zeros((3, 3)), V, np.eye(2), lm, rng=0, order=order)
        pf.predict([1.0, 0.1])
        ekf = EKFLocalization([1.0, 2.0, 0.4], np.zeros((3, 3)), V, np.eye(2), lm, order=order)
        ekf.predict([1.0, 0.1])
        np.testing.assert_allclose(pf.x, ekf.x, atol=3e-3)
        np.testing.assert_allclose(pf.P, ekf.P, atol=2e-4)


def test_odometry_orders_closed_forms():
    x = np.array([1.0, 2.0, 0.5])
    d, t = 0.7, 0.3
    tm = odometry_model(x, [d, t])
    mt = odometry_model(x, [d, t], order="move-turn")
    np.testing.assert_allclose(tm, [1 + d * math.cos(0.8), 2 + d * math.sin(0.8), 0.8])
    np.testing.assert_allclose(mt, [1 + d * math.cos(0.5), 2 + d * math.sin(0.5), 0.8])
    # move-then-turn is the SE(2) product ξ · T_x(δ_d) · R(δ_θ) (the lecture's matrix form)
    c, s = math.cos(x[2]), math.sin(x[2])
    T = np.array([[c, -s, x[0]], [s, c, x[1]], [0, 0, 1]]) @ np.array([[1, 0, d], [0, 1, 0], [0, 0, 1]]) \
        @ np.array([[math.cos(t), -math.sin(t), 0], [math.sin(t), math.cos(t), 0], [0, 0, 1]])
    np.testing.assert_allclose(mt, [T[0, 2], T[1, 2], math.atan2(T[1, 0], T[0, 0])], atol=1e-15)
    with pytest.raises(ValueError, match="order"):
        odometry_model(x, [d, t], order="sideways")


def test_odometry_jacobians_finite_differences():
    from robokit.mobile import odometry_jacobians

    x, delta, h = np.array([0.3, -0.2, 1.1]), np.array([0.4, -0.25]), 1e-6
    for order in ("turn-move", "move-turn"):
        Fx, Fv = odometry_jacobians(x, delta, order)
        for j in range(3):
            e = np.zeros(3)
            e[j] = h
            np.testing.assert_allclose((odometry_model(x + e, delta, order=order) - odometry_model(x - e, delta, order=order)) / (2 * h), Fx[:, j], atol=1e-8)
        for j in range(2):
            e = np.zeros(2)
            e[j] = h
            np.testing.assert_allclose((odometry_model(x, delta, e, order) - odometry_model(x, delta, -e, order)) / (2 * h), Fv[:, j], atol=1e-8)


def test_uncertainty_scalars():
    P = np.array([[0.5, 0.2, 0.0], [0.2, 0.3, 0.01], [0.0, 0.01, 0.1]])
    assert uncertainty(P) == pytest.approx(np.prod(np.linalg.eigvalsh(P)))
    pts, _, _ = error_ellipse(P[:2, :2], points=20001)
    x, y = pts[:, 0], pts[:, 1]
    polygon_area = 0.5 * abs(np.dot(x, np.roll(y, 1)) - np.dot(y, np.roll(x, 1)))
    assert uncertainty(P, "area") == pytest.approx(polygon_area, rel=1e-6)
    assert uncertainty(np.diag([4.0, 1.0]), "area") == pytest.approx(2 * np.pi)
    with pytest.raises(ValueError, match="kind"):
        uncertainty(P, "volume")
    with pytest.raises(ValueError, match="symmetric"):
        uncertainty(np.array([[1.0, 2.0], [0.0, 1.0]]))
