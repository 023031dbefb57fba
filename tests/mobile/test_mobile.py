"""Mobile robots (Lecture 9): the bicycle's circles, Jacobians by finite differences, controllers
converge, EKF exact without noise and consistent (NEES) with noise, SLAM converges, ellipses."""
import math

import numpy as np
import pytest
from scipy.stats import chi2

import robokit as rk
from robokit.mobile import (
    BicycleModel, EKFLocalization, EKFSLAM, FollowLine, LandmarkMap, MoveToPoint, Odometry, PurePursuit,
    RangeBearingSensor, error_ellipse, odometry_jacobians, odometry_model, run_vehicle,
)


def test_circle_radius_L_over_tan_gamma():
    m = BicycleModel(L=2.0)
    gamma = 0.3
    R = 2.0 / math.tan(gamma)
    x = np.zeros(3)
    pts = [x]
    for _ in range(200):
        x = m.step(x, [1.0, gamma], 0.05)
        pts.append(x)
    P = np.array(pts)
    centre = np.array([0.0, R])  # to the left of the start, perpendicular to the heading
    assert np.abs(np.linalg.norm(P[:, :2] - centre, axis=1) - R).max() < 1e-9
    # Euler integration of the same ODE stays within its O(dt) error
    xe = np.zeros(3)
    for _ in range(2000):
        xe = xe + 0.005 * m.deriv(xe, [1.0, gamma])
    assert abs(np.linalg.norm(xe[:2] - centre) - R) < 0.05
    d = m.deriv([0, 0, 0.4], [1.0, 0.2])
    assert abs(m.sideways_velocity([0, 0, 0.4], d)) < 1e-15
    # a demanded γ = ±π/2 (undefined for the model) is clipped to the steering limit like any other
    assert np.allclose(m.step(x, [1.0, np.pi / 2], 0.1), m.step(x, [1.0, m.steer_max], 0.1), atol=0, rtol=0)
    assert np.allclose(m.limit([1.0, -np.pi / 2]), [1.0, -m.steer_max], atol=0, rtol=0)


def test_jacobians_against_finite_differences():
    rng = np.random.default_rng(0)
    h = 1e-6
    for _ in range(20):
        x, delta, p = rng.normal(size=3), rng.normal(size=2) * 0.3, rng.normal(size=2) * 5
        Fx, Fv = odometry_jacobians(x, delta)
        for j in range(3):
            e = np.zeros(3); e[j] = h
            num = (odometry_model(x + e, delta) - odometry_model(x - e, delta)) / (2 * h)
            num[2] = rk.mobile.angdiff(num[2] * 2 * h) / (2 * h)
            assert np.allclose(Fx[:, j], num, atol=1e-6)
        for j in range(2):
            e = np.zeros(2); e[j] = h
            num = (odometry_model(x, delta, e) - odometry_model(x, delta, -e)) / (2 * h)
            assert np.allclose(Fv[:, j], num, atol=1e-6)
        Hx, Hp = RangeBearingSensor.jacobians(x, p)
        for j in range(3):
            e = np.zeros(3); e[j] = h
            d = RangeBearingSensor.h(x + e, p) - RangeBearingSensor.h(x - e, p)
            d[1] = rk.mobile.angdiff(d[1])
            assert np.allclose(Hx[:, j], d / (2 * h), atol=1e-6)
        for j in range(2):
            e = np.zeros(2); e[j] = h
            d = RangeBearingSensor.h(x, p + e) - RangeBearingSensor.h(x, p - e)
            d[1] = rk.mobile.angdiff(d[1])
            assert np.allclose(Hp[:, j], d / (2 * h), atol=1e-6)


def test_controllers_converge():
    m = BicycleModel(L=1.0)
    run = run_vehicle(m, MoveToPoint((5.0, 5.0), Kv=0.5, Kh=1.5), [0, 0, 0], 40.0, 0.05,
                      stop=lambda t, x: math.hypot(x[0] - 5, x[1] - 5) < 0.05)
    assert math.hypot(run.x[-1, 0] - 5, run.x[-1, 1] - 5) < 0.05
    line = FollowLine((1.0, -2.0, 4.0), v=1.0, Kd=0.5, Kh=1.0)
    run = run_vehicle(m, line, [0, 0, 0], 40.0, 0.05)
    assert abs(line.distance(run.x[-1])) < 1e-3 and abs(line.distance(run.x[0])) > 1.0

    def path(t):  # a target moving on a circle of radius 5 at 0.5 m/s
        return 5 * math.cos(0.1 * t), 5 * math.sin(0.1 * t)

    pp = PurePursuit(path, d_star=1.0, Kv=1.0, Ki=0.5, Kh=2.0)
    run = run_vehicle(m, pp, [0, 0, 0], 80.0, 0.05)
    errs = [abs(pp.error(t, x)) for t, x in zip(run.t[-200:], run.x[-200:])]
    assert max(errs) < 0.05


def _simulate(seed, noise=True, steps=150):
    rng = np.random.default_rng(seed)
    lm = LandmarkMap.random(20, 10.0, rng=1)
    V = np.diag([0.02, np.deg2rad(0.5)]) ** 2
    W = np.diag([0.1, np.deg2rad(1.0)]) ** 2
    sensor = RangeBearingSensor(lm, W, max_range=8.0, rng=rng)
    odo = Odometry(V, rng=rng)
    x_true = np.array([0.0, -3.0, 0.0])
    ekf = EKFLocalization(x_true, np.diag([1e-6, 1e-6, 1e-8]), V, W, lm)
    nees = []
    delta = np.array([0.1, 0.015])  # the true odometry increment per step (the lecture's motion model)
    for k in range(steps):
        x_true = odometry_model(x_true, delta)
        ekf.predict(odo.measure(delta) if noise else delta)
        vis = sensor.visible(x_true)
        if vis and k % 2 == 0:
            i = vis[k % len(vis)]
            z = sensor.measure(x_true, i) if noise else RangeBearingSensor.h(x_true, lm.points[i])
            ekf.update(z, i)
        e = ekf.x - x_true
        e[2] = rk.mobile.angdiff(e[2])
        nees.append(e @ np.linalg.solve(ekf.P, e))
        if not noise:
            assert np.abs(e).max() < 1e-9
    return np.array(nees)


def test_ekf_without_noise_is_exact():
    _simulate(0, noise=False)


def test_ekf_nees_consistent():
    runs = 40
    N = np.array([_simulate(100 + r) for r in range(runs)])  # (runs, steps)
    lo, hi = chi2.ppf(0.005, 3 * runs) / runs, chi2.ppf(0.995, 3 * runs) / runs
    avg_final = N[:, -1].mean()
    assert lo < avg_final < hi, (lo, avg_final, hi)
    inside = np.mean((N.mean(axis=0) > lo) & (N.mean(axis=0) < hi))
    assert inside > 0.9  # at (almost) every time step the run-averaged NEES is consistent


def test_ekf_slam_converges():
    rng = np.random.default_rng(7)
    lm = LandmarkMap.random(8, 6.0, rng=2)
    V = np.diag([0.01, np.deg2rad(0.3)]) ** 2
    W = np.diag([0.05, np.deg2rad(0.5)]) ** 2
    sensor = RangeBearingSensor(lm, W, rng=rng)
    odo = Odometry(V, rng=rng)
    x_true = np.array([0.0, -3.0, 0.0])
    slam = EKFSLAM(x_true, np.diag([1e-8, 1e-8, 1e-10]), V, W)
    first_err, first_cov = {}, {}
    delta = np.array([0.1, 0.03])
    for k in range(600):
        x_true = odometry_model(x_true, delta)
        slam.predict(odo.measure(delta))
        i = k % len(lm)
        slam.update(sensor.measure(x_true, i), i)
        if i not in first_cov:  # just inserted from its first observation
            kk = slam.landmark_index[i]
            first_cov[i] = np.trace(slam.P[kk:kk + 2, kk:kk + 2])
    for i in range(len(lm)):
        kk = slam.landmark_index[i]
        assert np.trace(slam.P[kk:kk + 2, kk:kk + 2]) < 0.5 * first_cov[i]  # uncertainty shrinks
        assert np.linalg.norm(slam.landmark(i) - lm.points[i]) < 0.15
    assert len(slam.x) == 3 + 2 * len(lm)


def test_error_ellipse_axes():
    pts, radii, axes = error_ellipse(np.diag([4.0, 1.0]), [1, 2], n_sigma=2.0)
    assert np.allclose(radii, [2.0, 4.0])
    assert np.allclose(np.abs(axes[:, 1]), [1, 0])
    Rt = np.array([[math.cos(0.5), -math.sin(0.5)], [math.sin(0.5), math.cos(0.5)]])
    P = Rt @ np.diag([9.0, 0.25]) @ Rt.T
    pts, radii, axes = error_ellipse(P, [0, 0], 1.0, points=400)
    assert np.allclose(radii, [0.5, 3.0])
    assert np.allclose(abs(axes[:, 1] @ Rt[:, 0]), 1.0)
    q = np.einsum("ki,ij,kj->k", pts, np.linalg.inv(P), pts)
    assert np.allclose(q, 1.0)  # every point is on the 1-σ contour
    with pytest.raises(ValueError, match="P"):
        error_ellipse([[1, 2], [0, 1]])


def test_bad_input():
    with pytest.raises(ValueError, match="L"):
        BicycleModel(L=0)
    with pytest.raises(ValueError, match="steer_max"):
        BicycleModel(steer_max=np.pi / 2)
    with pytest.raises(ValueError, match="x0"):
        run_vehicle(BicycleModel(), MoveToPoint((1, 1)), [0, 0], 1.0)


def test_plot_estimation():
    from robokit.mobile import plot_estimation

    path = np.c_[np.linspace(0, 5, 30), np.zeros(30), np.zeros(30)]
    est = path + 0.01
    covs = [np.diag([0.01, 0.02, 0.001])] * 30
    fig = plot_estimation(path, est, covs, landmarks=[[1, 1], [3, -1]], every=10)
    ax = fig.axes[0]
    assert len(ax.lines) == 2 + 3 + 1  # true, estimate, 3 ellipses, landmarks
    assert np.allclose(ax.lines[0].get_xdata(), path[:, 0])


@pytest.mark.parametrize("args,match", [((1.0, -2.0, 4.0), "one tuple"), (((0, 0, 1),), "both be zero"),
                                        (((1, 2),), "shape"), (((1, 2, 3), 1.0, -1.0), "Kd"),
                                        (((1, 2, float("nan")),), "line")])
def test_follow_line_refuses_bad_lines_at_construction(args, match):
    from robokit.mobile import FollowLine

    with pytest.raises(ValueError, match=match):
        FollowLine(*args)
