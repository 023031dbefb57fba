"""The compiled PoE IK on UR5, Panda and PUMA 560: 200 reachable targets each from random initial
guesses; the success rate is reported and every success is checked with Pinocchio's FK to 1e-9
and against the joint limits."""
import numpy as np
import pytest

import robokit as rk
from shared_robots import robot as shared_robot
from robokit.kernels.ik import solve_poe_ik


@pytest.mark.parametrize("name", ["ur5", "panda", "puma560"])
def test_ik_reachable_targets(name, capsys):
    r = shared_robot(name)
    p = r.poe
    rng = np.random.default_rng(11)
    N = 200
    successes = 0
    for k in range(N):
        T = r.frame_pose(r.random_configuration(rng))  # reachable: the pose of a random configuration
        q0 = r.random_configuration(rng)
        q, ok, iterations, restarts = solve_poe_ik(p.M, p.Slist, T, q0, r.qlim.copy(), 1e-10, 30, 200, k)
        assert iterations >= 0 and 0 <= restarts <= 200
        if ok:
            successes += 1
            assert np.abs(r.frame_pose(q) - T).max() < 1e-9  # Pinocchio's FK, not the solver's
            assert np.all(q >= r.qlim[:, 0]) and np.all(q <= r.qlim[:, 1])
    with capsys.disabled():
        print(f"\n{name}: IK success {successes}/{N} = {100 * successes / N:.1f} %")
    assert successes >= 0.99 * N


def test_ik_unreachable_and_deterministic():
    r = rk.load("ur5")
    p = r.poe
    T = np.eye(4)
    T[:3, 3] = [5.0, 0.0, 0.0]  # far outside the UR5's reach (about 1 m)
    q, ok, it, rs = solve_poe_ik(p.M, p.Slist, T, np.zeros(6), r.qlim.copy(), 1e-10, 20, 3, 0)
    assert not ok and rs == 3 and q.shape == (6,)
    T = r.frame_pose(np.array([0.3, -1.0, 1.2, -0.5, 0.4, 0.2]))
    a = solve_poe_ik(p.M, p.Slist, T, np.ones(6), r.qlim.copy(), 1e-10, 30, 50, 5)
    b = solve_poe_ik(p.M, p.Slist, T, np.ones(6), r.qlim.copy(), 1e-10, 30, 50, 5)
    assert a[1] and np.array_equal(a[0], b[0]) and a[2:] == b[2:]  # same seed, same answer


def test_ik_limits_are_respected():
    r = rk.load("ur5")
    p = r.poe
    qlim = np.tile([-1.0, 1.0], (6, 1))
    rng = np.random.default_rng(3)
    for k in range(20):
        T = r.frame_pose(rng.uniform(-1, 1, 6))
        q, ok, _, _ = solve_poe_ik(p.M, p.Slist, T, np.zeros(6), qlim, 1e-10, 30, 100, k)
        assert np.all(np.abs(q) <= 1.0)
        if ok:
            assert np.abs(r.frame_pose(q) - T).max() < 1e-9


def test_ik_bad_input():
    p = rk.load("twolink").poe
    with pytest.raises(ValueError, match="q0"):
        solve_poe_ik(p.M, p.Slist, np.eye(4), np.zeros(3), np.zeros((2, 2)))
    with pytest.raises(ValueError, match="qlim"):
        solve_poe_ik(p.M, p.Slist, np.eye(4), np.zeros(2), np.array([[1.0, -1.0], [0.0, 1.0]]))
    with pytest.raises(ValueError, match="tol"):
        solve_poe_ik(p.M, p.Slist, np.eye(4), np.zeros(2), np.zeros((2, 2)), tol=-1.0)
