"""plan around a wall: the straight line collides, the planned path does not — re-checked at
the documented resolution with python-fcl (independent of coal) on the same geometry."""
import sys
from pathlib import Path

import numpy as np
import pytest

import robokit
from robokit.collision import Box, World
from robokit.errors import InputError
from robokit.motion import plan

pytest.importorskip("ompl")
sys.path.insert(0, str(Path(__file__).parents[1] / "collision"))
from _fcl_ref import FclWorld  # noqa: E402

QA = np.array([0.0, 0.3, -0.3, 0, 0, 0])
QB = np.array([1.4, 0.3, -0.3, 0, 0, 0])


@pytest.fixture(scope="module")
def scene():
    r = robokit.load("puma560")
    T = np.eye(4)
    T[:3, 3] = [0.45, 0.35, 0.4]
    return r, World(r, [Box([0.4, 0.05, 0.8], T, name="wall")])


def _fcl_free(ref, q):
    return not any(h for h, _ in ref.pair_distances(q))


def test_plan_around_a_wall(scene):
    r, w = scene
    ref = FclWorld(w)
    line = QA + np.linspace(0, 1, 50)[:, None] * (QB - QA)
    assert not all(_fcl_free(ref, q) for q in line)  # the straight line goes through the wall
    tr = plan(r, QA, QB, w, vmax=1.0, amax=2.0, seed=0)
    np.testing.assert_allclose(tr.q[0], QA, atol=1e-9)
    np.testing.assert_allclose(tr.q[-1], QB, atol=1e-9)
    assert np.all(tr.q >= r.qlim[:, 0] - 1e-9) and np.all(tr.q <= r.qlim[:, 1] + 1e-9)
    # the whole spline, at the documented resolution, checked by python-fcl
    spline = tr.info["spline"]
    s = np.linspace(0, 1, 2001)
    q = spline(s)
    step = np.max(np.linalg.norm(np.diff(q, axis=0), axis=1))
    assert step <= tr.info["resolution"]
    assert all(_fcl_free(ref, x) for x in q[::2]) and all(_fcl_free(ref, x) for x in tr.q)
    assert np.all(np.abs(tr.qd) <= 1.0 * (1 + 1e-6)) and np.all(np.abs(tr.qdd) <= 2.0 * (1 + 1e-6))


def test_plan_to_a_pose(scene):
    r, w = scene
    T_goal = r.frame_pose(QB)
    tr = plan(r, QA, T_goal, w, seed=1)
    np.testing.assert_allclose(r.frame_pose(tr.q[-1]), T_goal, atol=1e-8)
    assert not w.in_collision(tr.q).any()


def test_bad_start_and_goal(scene):
    r, w = scene
    with pytest.raises(InputError, match="q_start"):
        plan(r, np.full(6, 9.0), QB, w)
    with pytest.raises(InputError, match="goal"):
        plan(r, QA, np.zeros(5), w)
    T = np.eye(4)
    T[:3, 3] = [5.0, 0, 0]
    with pytest.raises(InputError, match="goal"):
        plan(r, QA, T, w)
