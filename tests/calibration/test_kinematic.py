"""Kinematic calibration: synthetic "true" arms (random per-joint SE(3) errors, base and tool errors,
held here) generate the measurements; the calibrated robot must predict the true arm."""
import math

import numpy as np
import pytest
from calibration_support import configurations
from hypothesis import given, settings
from hypothesis import strategies as st

import robokit
from robokit.calibration import chain_from_robot, identification_jacobian, parameter_names, pose_residuals
from robokit.errors import InputError
from robokit.spatial import lie


def true_chain(robot, rng, size=2e-3):
    """The nominal chain with every placement (base and tool included) moved by a random SE(3) error."""
    return chain_from_robot(robot).perturbed(rng.normal(0.0, size, (robot.n + 1, 6)))


def expected_rank(robot, positions_only):
    """Okamura & Park / Everett: 4 per revolute, 2 per prismatic joint, 6 for the base and tool
    (pose data); positions only: the tool's three rotations drop out."""
    kinds = chain_from_robot(robot).kinds
    r = 4 * kinds.count("R") + 2 * kinds.count("P") + 6
    return r - 3 if positions_only else r


@pytest.mark.parametrize("name", ["puma560", "ur5", "rpr"])
def test_identification_jacobian_matches_finite_differences(robots, name):
    robot = robots(name)
    rng = np.random.default_rng(3)
    chain = true_chain(robot, rng, 1e-2)
    q = configurations(robot, 4, rng)
    J = identification_jacobian(chain, q)
    T0 = chain.fk(q)
    h = 1e-6
    P = 6 * (robot.n + 1)
    for j in range(P):
        d = np.zeros(P)
        d[j] = h
        Tp, Tm = chain.perturbed(d).fk(q), chain.perturbed(-d).fk(q)
        dw = (lie.log3(Tp[:, :3, :3] @ np.swapaxes(T0[:, :3, :3], 1, 2))
              - lie.log3(Tm[:, :3, :3] @ np.swapaxes(T0[:, :3, :3], 1, 2))) / (2 * h)
        dp = (Tp[:, :3, 3] - Tm[:, :3, 3]) / (2 * h)
        np.testing.assert_allclose(J[:, :3, j], dw, atol=1e-7)
        np.testing.assert_allclose(J[:, 3:, j], dp, atol=1e-7)
    np.testing.assert_array_equal(identification_jacobian(chain, q, positions_only=True), J[:, 3:])


@pytest.mark.parametrize("name,positions_only", [("puma560", False), ("puma560", True), ("ur5", False),
                                                 ("rpr", False), ("rpr", True)])
def test_noiseless_data_recover_the_true_arm(robots, name, positions_only):
    robot = robots(name)
    rng = np.random.default_rng(7)
    true = true_chain(robot, rng)
    q = configurations(robot, 40, rng)
    measured = true.fk(q)
    if positions_only:
        measured = measured[:, :3, 3]
    res = robokit.calibrate(robot, q, measured)
    assert res.converged
    assert res.rms_before > 1e-3
    assert res.rms_after < 1e-10
    assert res.identifiability.rank == res.identifiability.structural_rank == expected_rank(robot, positions_only)
    unseen = configurations(robot, 30, rng)
    T_cal, T_true = res.robot.frame_pose(unseen), true.fk(unseen)
    np.testing.assert_allclose(T_cal[:, :3, 3], T_true[:, :3, 3], atol=1e-7)
    if not positions_only:
        np.testing.assert_allclose(T_cal, T_true, atol=1e-7)
        assert res.rms_after.orientation < 1e-10
    else:
        assert res.rms_after.orientation is None
        assert any("tool.rx: has no effect" in u for u in res.identifiability.unidentified)
    assert len(res.identifiability.unidentified) == 6 * (robot.n + 1) - res.identifiability.rank


def test_dh_discontinuity_tilted_parallel_axes(robots):
    """PUMA joints 2 and 3 are parallel; in the true arm joint 3's axis is tilted 1e-3 rad toward joint 2
    (a rotation about the common normal): DH parameters jump there, the per-joint errors do not."""
    robot = robots("puma560")
    chain = chain_from_robot(robot)
    S0 = robot.poe.Slist
    assert abs(abs(S0[:3, 1] @ S0[:3, 2]) - 1) < 1e-12  # nominally parallel
    delta = np.zeros((robot.n + 1, 6))
    delta[2, :3] = [1e-3, 0.0, 0.0]  # joint 3's frame tilted about its x axis (the common normal)
    true = chain.perturbed(delta)
    rng = np.random.default_rng(11)
    q = configurations(robot, 30, rng)
    res = robokit.calibrate(robot, q, true.fk(q))
    unseen = configurations(robot, 20, rng)
    np.testing.assert_allclose(res.robot.frame_pose(unseen), true.fk(unseen), atol=1e-7)
    # the calibrated axes are tilted by 1e-3 rad, as in the true arm
    S = res.robot.poe.Slist
    tilt = math.acos(min(1.0, abs(S[:3, 1] @ S[:3, 2])))
    assert abs(tilt - 1e-3) < 1e-9


@pytest.mark.parametrize("positions_only", [False, True])
def test_noisy_data_reach_the_noise_floor(robots, positions_only):
    """With σ noise on every measured coordinate (m, rad), least squares leaves on average
    σ²·(K·m − r) of squared residual for K samples of m coordinates and r identified parameters:
    RMS per sample σ·sqrt((K·m − r)/K). rms_after must be within 20 % of it."""
    robot = robots("puma560")
    rng = np.random.default_rng(5)
    true = true_chain(robot, rng)
    K, sigma = 100, 1e-4
    q = configurations(robot, K, rng)
    T = true.fk(q)
    p_noisy = T[:, :3, 3] + rng.normal(0, sigma, (K, 3))
    if positions_only:
        measured = p_noisy
        m = 3
    else:
        R = lie.exp3(rng.normal(0, sigma, (K, 3))) @ T[:, :3, :3]
        measured = T.copy()
        measured[:, :3, :3] = R
        measured[:, :3, 3] = p_noisy
        m = 6
    res = robokit.calibrate(robot, q, measured)
    r = res.identifiability.rank
    floor = sigma * math.sqrt((K * m - r) / K)
    total = math.hypot(res.rms_after, res.rms_after.orientation or 0.0)
    assert abs(total / floor - 1) < 0.2, (total, floor)
    unseen = configurations(robot, 50, rng)
    err = np.linalg.norm(res.robot.frame_pose(unseen)[:, :3, 3] - true.fk(unseen)[:, :3, 3], axis=1)
    assert err.max() < 10 * sigma  # the model error left is of the order of the noise
    assert res.residuals.shape == (K, m)


def test_residuals_and_names(robots):
    robot = robots("rrr")
    rng = np.random.default_rng(2)
    true = true_chain(robot, rng)
    q = configurations(robot, 20, rng)
    res = robokit.calibrate(robot, q, true.fk(q))
    np.testing.assert_allclose(res.residuals_before, pose_residuals(chain_from_robot(robot), q, true.fk(q)))
    assert math.isclose(res.rms_before, math.sqrt(np.mean(np.sum(res.residuals_before[:, 3:] ** 2, axis=1))))
    names = parameter_names(robot)
    assert len(names) == 6 * (robot.n + 1) and names[0].endswith(".rx") and names[-1] == "tool.tz"
    assert set(res.identifiability.identified) <= set(names)
    text = str(res)
    assert "RMS before" in text and "stays nominal" in text
    fig = res.plot()
    assert len(fig.axes) == 2
    import matplotlib.pyplot as plt

    plt.close(fig)


def test_bad_input(robots):
    robot = robots("rrr")
    rng = np.random.default_rng(0)
    q = configurations(robot, 10, rng)
    T = robot.frame_pose(q)
    with pytest.raises(InputError, match="q: expected shape"):
        robokit.calibrate(robot, q[:, :2], T)
    with pytest.raises(InputError, match="measured: expected shape"):
        robokit.calibrate(robot, q, T[:5])
    bad = T.copy()
    bad[3, :3, :3] *= 1.01
    with pytest.raises(InputError, match="measured: pose 3 is not a rigid transform"):
        robokit.calibrate(robot, q, bad)
    nan = q.copy()
    nan[0, 0] = np.nan
    with pytest.raises(InputError, match="NaN"):
        robokit.calibrate(robot, nan, T)
    with pytest.raises(InputError, match="at least .* samples are needed"):
        robokit.calibrate(robot, q[:2], T[:2])


def test_orientation_weight_is_maximum_likelihood(robots):
    """Orientation noise 10× the position noise (in rad vs m): weighting the orientation rows by
    σ_p/σ_o gives a better model than the unit weight (on unseen configurations), and the weight
    does not change a noiseless fit."""
    robot = robots("puma560")
    rng = np.random.default_rng(21)
    true = true_chain(robot, rng)
    K = 40
    q = configurations(robot, K, rng)
    T = true.fk(q)
    res0 = robokit.calibrate(robot, q, T, orientation_weight=0.1)
    unseen = configurations(robot, 40, rng)
    np.testing.assert_allclose(res0.robot.frame_pose(unseen), true.fk(unseen), atol=1e-7)
    errs = {}
    for w in (1.0, 0.1):
        e = []
        for trial in range(2):
            r2 = np.random.default_rng(100 + trial)
            meas = T.copy()
            meas[:, :3, 3] += r2.normal(0, 1e-4, (K, 3))
            meas[:, :3, :3] = lie.exp3(r2.normal(0, 1e-3, (K, 3))) @ T[:, :3, :3]
            res = robokit.calibrate(robot, q, meas, orientation_weight=w)
            e.append(np.linalg.norm(res.robot.frame_pose(unseen)[:, :3, 3] - true.fk(unseen)[:, :3, 3], axis=1).mean())
        errs[w] = np.mean(e)
    assert errs[0.1] < 0.8 * errs[1.0]
    with pytest.raises(InputError, match="orientation_weight"):
        robokit.calibrate(robot, q, T, orientation_weight=0.0)


@settings(max_examples=12, deadline=None, derandomize=True)
@given(seed=st.integers(0, 2**31 - 1), name=st.sampled_from(["rrr", "rpr", "twolink"]),
       size=st.floats(1e-4, 2e-2), positions_only=st.booleans())
def test_any_small_error_is_recovered(robots, seed, name, size, positions_only):
    """Property: for any random true arm near the nominal one (errors from 0.1 mm / 0.1 mrad to 2 cm / 20 mrad),
    noiseless data give a calibrated robot that predicts the measured quantity on unseen configurations."""
    robot = robots(name)
    rng = np.random.default_rng(seed)
    true = true_chain(robot, rng, size)
    q = configurations(robot, 25, rng)
    T = true.fk(q)
    res = robokit.calibrate(robot, q, T[:, :3, 3] if positions_only else T)
    unseen = configurations(robot, 10, rng)
    got, want = res.robot.frame_pose(unseen), true.fk(unseen)
    if positions_only:
        np.testing.assert_allclose(got[:, :3, 3], want[:, :3, 3], atol=1e-7)
    else:
        np.testing.assert_allclose(got, want, atol=1e-7)
