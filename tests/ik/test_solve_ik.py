"""solve_ik on real robots: converges, respects joint limits, reports unreachable targets."""
import numpy as np
import pytest

import robokit as rk
from robokit.ik import solve_ik


@pytest.fixture(scope="module", params=["ur5", "panda", "puma560", "kinova"])
def robot(request):
    return rk.load(request.param)


def inside(robot, q):
    return np.all(q >= robot.qlim[:, 0] - 1e-12) and np.all(q <= robot.qlim[:, 1] + 1e-12)


def test_random_reachable_targets(robot):
    rng = np.random.default_rng(0)
    ok = 0
    for _ in range(20):
        q_true = robot.random_configuration(rng)
        T = robot.frame_pose(q_true)
        res = solve_ik(robot, T, rng=1)
        assert inside(robot, res.q)  # never outside the limits, success or not
        if res.success:
            ok += 1
            assert np.abs(robot.frame_pose(res.q) - T).max() < 1e-9
            assert res.position_error < 1e-9 and res.orientation_error < 1e-9
    assert ok >= 19


def test_position_only_and_weights(robot):
    rng = np.random.default_rng(2)
    q_true = robot.random_configuration(rng)
    p = robot.frame_pose(q_true)[:3, 3]
    res = solve_ik(robot, p, position_only=True, rng=3)
    assert res.success and np.linalg.norm(robot.frame_pose(res.q)[:3, 3] - p) < 1e-9 and inside(robot, res.q)


def test_unreachable_reports_failure(robot):
    T = np.eye(4)
    T[:3, 3] = [5.0, 0.0, 0.0]
    res = solve_ik(robot, T, max_restarts=2, rng=0)
    assert not res.success and inside(robot, res.q) and res.position_error > 1.0


def test_bad_input():
    r = rk.load("twolink")
    with pytest.raises(ValueError, match="target"):
        solve_ik(r, np.ones((4, 4)))
    with pytest.raises(ValueError, match="weights"):
        solve_ik(r, np.eye(4), weights=[1, 1])
