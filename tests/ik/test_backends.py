"""The IK back ends as objects: each says whether it supports a problem and why not, solve_ik records
which one answered (result.method) and never swaps one silently, capability maps use the same list,
and solve_ik is deterministic by default."""
import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import robokit as rk
from shared_robots import robot as shared_robot
from robokit.description.dh import DHLink, DHTable
from robokit.errors import InputError
from robokit.ik.backends import BACKENDS, IKProblem, backend, reach_backend
from robokit.workspace import ik_backend


@pytest.fixture(scope="module")
def robots():
    return {name: shared_robot(name) for name in ("puma560", "ur5", "panda", "rrr", "twolink")}


def _pinocchio_ok(robot, res, T):
    assert res.success
    assert np.abs(robot.frame_pose(res.q) - T).max() < 1e-9  # Pinocchio's FK, independent of the back end
    assert np.all(res.q >= robot.qlim[:, 0] - 1e-12) and np.all(res.q <= robot.qlim[:, 1] + 1e-12)


def test_the_documented_order():
    assert [b.name for b in BACKENDS] == ["analytic", "planar", "compiled", "lm"]
    with pytest.raises(InputError, match="method: expected 'auto' or one of 'analytic', 'planar'"):
        backend("newton")


@pytest.mark.parametrize("name, auto", [("puma560", "analytic"), ("ur5", "analytic"), ("rrr", "planar"),
                                        ("twolink", "planar"), ("panda", "compiled")])
def test_auto_records_the_back_end_that_answered(robots, name, auto):
    robot = robots[name]
    rng = np.random.default_rng(3)
    for _ in range(3):
        T = robot.frame_pose(robot.random_configuration(rng))
        res = rk.solve_ik(robot, T)
        assert res.method == auto
        _pinocchio_ok(robot, res, T)
        assert set(res.tried) == {b.name for b in BACKENDS[: [b.name for b in BACKENDS].index(auto)]}
    assert ik_backend(robot) == auto  # the capability maps' choice is the same list's


@pytest.mark.parametrize("name, methods", [("puma560", ["analytic", "compiled", "lm"]),
                                           ("rrr", ["planar", "compiled", "lm"]),
                                           ("panda", ["compiled", "lm"])])
def test_each_back_end_named_explicitly_answers_itself(robots, name, methods):
    robot = robots[name]
    T = robot.frame_pose(robot.random_configuration(np.random.default_rng(9)))
    for m in methods:
        res = rk.solve_ik(robot, T, method=m)
        assert res.method == m
        _pinocchio_ok(robot, res, T)


def test_position_only_other_frames_and_robotlikes_go_to_lm(robots):
    ur5 = robots["ur5"]
    q = np.array([0.3, -0.9, 1.1, 0.2, 0.5, -0.4])
    p = ur5.frame_pose(q)[:3, 3]
    res = rk.solve_ik(ur5, p, position_only=True)
    assert res.method == "lm" and res.success and np.abs(ur5.frame_pose(res.q)[:3, 3] - p).max() < 1e-9
    assert "position" in res.tried["analytic"] and "position" in res.tried["compiled"]
    for m in ("analytic", "planar", "compiled"):
        with pytest.raises(InputError, match=f"method: '{m}' does not support this problem: .*position"):
            rk.solve_ik(ur5, p, position_only=True, method=m)


def test_weights_on_a_closed_form_arm_never_switch_silently(robots):
    ur5 = robots["ur5"]
    q = np.array([0.3, -0.9, 1.1, 0.2, 0.5, -0.4])
    T = ur5.frame_pose(q)
    # positive weights: the exact solution has zero weighted error, the closed form answers
    res = rk.solve_ik(ur5, T, weights=[1, 1, 1, 2, 2, 2])
    assert res.method == "analytic"
    _pinocchio_ok(ur5, res, T)
    # a zero weight leaves a rotation free: another problem; the closed form says why, LM answers
    res = rk.solve_ik(ur5, T, weights=[1, 1, 0, 1, 1, 1])
    assert res.method == "lm" and "zero entry" in res.tried["analytic"] and "weights" in res.tried["compiled"]
    with pytest.raises(InputError, match="'analytic' does not support this problem: .*zero entry"):
        rk.solve_ik(ur5, T, weights=[1, 1, 0, 1, 1, 1], method="analytic")
    with pytest.raises(InputError, match="'compiled' does not support this problem: .*weights"):
        rk.solve_ik(ur5, T, weights=[1, 1, 1, 1, 1, 1], method="compiled")
    with pytest.raises(InputError, match="'compiled' does not support this problem: .*time budget"):
        rk.solve_ik(robots["panda"], robots["panda"].frame_pose(np.zeros(7)), time_budget=1.0, method="compiled")
    res = rk.solve_ik(robots["panda"], robots["panda"].frame_pose(np.full(7, 0.2)), time_budget=5.0)
    assert res.method == "lm" and "time budget" in res.tried["compiled"] and res.success


def test_an_arm_without_a_closed_form_says_why(robots):
    panda = robots["panda"]
    with pytest.raises(InputError, match="'analytic' does not support this problem: no closed form: the arm has 7"):
        rk.solve_ik(panda, panda.frame_pose(np.zeros(7)), method="analytic")
    with pytest.raises(InputError, match="'planar'.*not a planar arm"):
        rk.solve_ik(panda, panda.frame_pose(np.zeros(7)), method="planar")


def test_unsupported_reasons_are_asked_not_tried(robots):
    """unsupported() is a question (no solve attempted): it answers for a pose nobody can reach."""
    far = np.eye(4)
    far[:3, 3] = [9.0, 0.0, 0.0]
    for name, first in (("puma560", "analytic"), ("panda", "compiled"), ("rrr", "planar")):
        p = IKProblem.tip_pose(robots[name], far)
        supported = [b.name for b in BACKENDS if b.unsupported(p) is None]
        assert supported[0] == first and supported[-1] == "lm"
        assert reach_backend(robots[name]).name == first


def test_unreachable_pose_fails_inside_the_limits_with_every_reason(robots):
    puma = robots["puma560"]
    T = np.eye(4)
    T[:3, 3] = [5.0, 0.0, 0.0]
    res = rk.solve_ik(puma, T, max_restarts=2)
    assert not res.success and res.position_error > 1.0
    assert np.all(res.q >= puma.qlim[:, 0]) and np.all(res.q <= puma.qlim[:, 1])
    assert "no closed-form solution" in res.tried["analytic"]


def test_solve_ik_is_deterministic_by_default(robots):
    panda = robots["panda"]
    rng = np.random.default_rng(11)
    for _ in range(3):
        q = panda.random_configuration(rng)
        p = panda.frame_pose(q)[:3, 3]
        a = rk.solve_ik(panda, p, position_only=True, q0=np.full(7, 2.5))  # redundant: a 4-D set of answers
        b = rk.solve_ik(panda, p, position_only=True, q0=np.full(7, 2.5))
        assert a.success and np.array_equal(a.q, b.q)
        T = panda.frame_pose(q)
        c, d = rk.solve_ik(panda, T, q0=-q), rk.solve_ik(panda, T, q0=-q)
        assert c.method == "compiled" and np.array_equal(c.q, d.q)
        # the documented default is seed 0: passing it explicitly changes nothing
        e = rk.solve_ik(panda, T, q0=-q, rng=0)
        assert np.array_equal(c.q, e.q)
    with pytest.raises(InputError, match="rng"):
        rk.solve_ik(panda, panda.frame_pose(np.zeros(7)), rng="seed")


def test_planar_back_end_matches_the_lecture_closed_form(robots):
    """The planar back end's answers are among the lecture's two-link solutions (elbow up/down)."""
    arm = robots["twolink"]
    rng = np.random.default_rng(2)
    for _ in range(5):
        q = arm.random_configuration(rng)
        T = arm.frame_pose(q)
        res = rk.solve_ik(arm, T, q0=q + 0.05)
        assert res.method == "planar"
        _pinocchio_ok(arm, res, T)
        assert np.abs(np.angle(np.exp(1j * (res.q - q)))).max() < 1e-9  # the one next to q0


# ---------------------------------------------------------------------------- properties
@settings(max_examples=15, deadline=None, derandomize=True)
@given(st.integers(0, 2**31 - 1), st.sampled_from([2, 3]), st.sampled_from(["standard", "modified"]))
def test_planar_back_end_on_random_planar_arms(seed, n, convention):
    """Random planar 2R/3R arms (parallel axes, random lengths and offsets, a tilted base): the planar
    back end's answer reaches the pose by Pinocchio's FK, and ik_success agrees on the same pose."""
    rng = np.random.default_rng(seed)
    links = tuple(DHLink("R", a=float(rng.uniform(0.2, 1.0)), theta=float(rng.uniform(-np.pi, np.pi)),
                         qlim=np.array([-np.pi, np.pi])) for _ in range(n))
    base = np.eye(4)
    base[:3, 3] = rng.uniform(-0.5, 0.5, 3)
    c, s = np.cos(0.4), np.sin(0.4)
    base[:3, :3] = [[1, 0, 0], [0, c, -s], [0, s, c]]
    robot = rk.load(DHTable(f"planar{n}", convention, links, base=base))
    q = rng.uniform(-3.0, 3.0, n)
    T = robot.frame_pose(q)
    res = rk.solve_ik(robot, T)
    assert res.method == "planar"
    _pinocchio_ok(robot, res, T)
    assert rk.workspace.ik_success(robot, T[None]).tolist() == [True]
    off = T.copy()
    off[:3, 3] += 0.05 * base[:3, 2]  # off the arm's plane: unreachable, and said so without iterating
    assert rk.workspace.ik_success(robot, off[None]).tolist() == [False]
    assert not rk.solve_ik(robot, off, method="planar").success


def test_bad_options_name_the_argument(robots):
    ur5 = robots["ur5"]
    T = ur5.frame_pose(np.zeros(6))
    for kwargs, name in (({"max_restarts": -1}, "max_restarts"), ({"max_restarts": 2.5}, "max_restarts"),
                         ({"max_iterations": 0}, "max_iterations"), ({"damping": -1.0}, "damping"),
                         ({"time_budget": 0.0}, "time_budget"), ({"method": 3}, "method"),
                         ({"q0": np.zeros(5)}, "q0"), ({"weights": [1, 1, 1, 1, 1, -1]}, "weights")):
        with pytest.raises(InputError, match=name):
            rk.solve_ik(ur5, T, **kwargs)
