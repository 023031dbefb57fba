"""solve_ik on real robots: converges, respects joint limits, reports unreachable targets."""
import numpy as np
import pytest

import robokit as rk
from shared_robots import robot as shared_robot
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
    with pytest.raises(ValueError, match="T"):
        solve_ik(r, np.ones((4, 4)))
    with pytest.raises(ValueError, match="weights"):
        solve_ik(r, np.eye(4), weights=[1, 1])


@pytest.mark.parametrize("name", ["ur5", "puma560", "panda"])
def test_solve_ik_methods_all_reach_the_pose_inside_the_limits(name):
    """auto (closed form where the arm has one, else compiled LM), compiled and the Pinocchio LM
    reference all reproduce Pinocchio's pose to 1e-9, inside the limits."""
    robot = shared_robot(name)
    rng = np.random.default_rng(7)
    for _ in range(15):
        T = robot.frame_pose(robot.random_configuration(rng))
        for method in ("auto", "compiled", "lm"):
            res = rk.solve_ik(robot, T, method=method, rng=3)
            assert res.success, (name, method)
            assert np.abs(robot.frame_pose(res.q) - T).max() < 1e-9
            assert np.all(res.q >= robot.qlim[:, 0] - 1e-12) and np.all(res.q <= robot.qlim[:, 1] + 1e-12)


def test_solve_ik_auto_uses_the_closed_form_nearest_the_seed():
    robot = rk.load("puma560")
    q_true = np.array([0.3, -0.4, 0.5, 0.2, 0.6, -0.1])
    T = robot.frame_pose(q_true)
    res = rk.solve_ik(robot, T, q0=q_true + 0.01)
    assert res.iterations == 0 and res.restarts == 0  # no iteration: the closed form
    assert np.abs(res.q - q_true).max() < 1e-9  # of the 8 solutions, the one next to the seed
    sols = [s.q for s in rk.ik_analytic(robot, T) if s.within_limits]
    far = max(sols, key=lambda q: np.abs(q - q_true).max())
    res_far = rk.solve_ik(robot, T, q0=far)
    assert np.abs(res_far.q - far).max() < 1e-9


def test_solve_ik_analytic_refuses_an_arm_without_a_closed_form():
    panda = rk.load("panda")
    with pytest.raises(ValueError, match="closed form"):
        rk.solve_ik(panda, panda.frame_pose(np.zeros(7)), method="analytic")
    with pytest.raises(ValueError, match="method"):
        rk.solve_ik(panda, panda.frame_pose(np.zeros(7)), method="newton")


class _PlanarTwoLink:
    """A hand-written RobotLike (no Pinocchio): a planar 2R arm with unit links in the xy plane."""

    n = 2
    qlim = np.array([[-np.pi, np.pi], [-np.pi, np.pi]])

    def frame_pose(self, q, frame=None):
        a, b = q[0], q[0] + q[1]
        T = np.eye(4)
        T[:2, :2] = [[np.cos(b), -np.sin(b)], [np.sin(b), np.cos(b)]]
        T[:2, 3] = [np.cos(a) + np.cos(b), np.sin(a) + np.sin(b)]
        return T

    def jacobian(self, q, frame=None, reference="world"):
        assert reference == "local_world_aligned"  # position-only IK asks for the geometric Jacobian
        a, b = q[0], q[0] + q[1]
        J = np.zeros((6, 2))
        J[2] = 1.0  # ω_z
        J[3] = [-np.sin(a) - np.sin(b), -np.sin(b)]
        J[4] = [np.cos(a) + np.cos(b), np.cos(b)]
        return J


def test_solve_ik_accepts_any_robotlike_and_refuses_other_objects():
    from robokit.description import RobotLike

    arm = _PlanarTwoLink()
    assert isinstance(arm, RobotLike)
    res = solve_ik(arm, np.array([1.2, 0.7, 0.0]), q0=[0.3, 0.5], position_only=True, rng=0)
    assert res.success and np.allclose(arm.frame_pose(res.q)[:3, 3], [1.2, 0.7, 0.0], atol=1e-9)
    # the closed form of the lecture's 2-link arm has the same answer among its two elbows
    sols = rk.ik.ik_planar_2link(1.2, 0.7, 1.0, 1.0)
    assert min(np.abs(np.asarray(s.q) - res.q).max() for s in sols) < 1e-7
    with pytest.raises(TypeError, match="robot"):
        solve_ik(object(), np.eye(4))


def test_contract_argument_order_q0_third(monkeypatch):
    """``solve_ik(robot, T, q0)`` (the documented order) starts from q0: on a UR5 (8 closed-form branches)
    and a Panda (redundant, numeric) the answer is the configuration q0 sits next to, checked with
    Pinocchio's own forward kinematics. The third argument was ``frame``, so this call crashed inside
    (numpy's 'truth value of an array is ambiguous'). The keyword ``T=`` works; the former order
    ``(robot, T, frame, q0)`` and ``target=`` still work with a DeprecationWarning; a non-string frame is
    refused naming ``frame``."""
    import pinocchio as pin

    rng = np.random.default_rng(7)
    for name in ("ur5", "panda"):
        r = shared_robot(name)
        q_true = r.random_configuration(rng)
        data = r.model.createData()
        pin.framesForwardKinematics(r.model, data, r.q_pin(q_true))
        T = data.oMf[r.model.getFrameId(r.tip)].homogeneous.copy()
        q0 = q_true + 1e-3
        for res in (solve_ik(r, T, q0), solve_ik(r, T=T, q0=q0), rk.solve_ik(r, T, q0, max_restarts=0)):
            assert res.success
            pin.framesForwardKinematics(r.model, data, r.q_pin(res.q))
            np.testing.assert_allclose(data.oMf[r.model.getFrameId(r.tip)].homogeneous, T, atol=1e-9)
            if name == "ur5":  # the closed form: the branch nearest q0, q_true itself
                np.testing.assert_allclose(np.angle(np.exp(1j * (res.q - q_true))), 0.0, atol=1e-9)
            else:  # Panda (redundant): Levenberg-Marquardt from q0 stays next to it
                assert np.abs(res.q - q_true).max() < 1e-2
        monkeypatch.setattr("robokit._deprecation._WARNED", set())  # each robot's calls warn again
        with pytest.warns(DeprecationWarning):
            old = solve_ik(r, T, r.tip, q0)
        with pytest.warns(DeprecationWarning):
            kw = solve_ik(r, target=T, q0=q0)
        np.testing.assert_allclose(old.q, solve_ik(r, T, q0, r.tip).q, atol=1e-12)
        np.testing.assert_allclose(kw.q, solve_ik(r, T, q0).q, atol=1e-12)
    with pytest.raises(ValueError, match="give T= only"):
        solve_ik(r, T, target=T)
    with pytest.raises(TypeError, match="frame"):
        solve_ik(r, T, q0, np.zeros(3))
