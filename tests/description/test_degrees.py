"""Degrees do not pass silently: every entry point taking joint values warns once (DegreesWarning)
when a revolute value lies beyond a full turn and past its limits — against a rule written here
from the docs (joint kinds from Pinocchio's joint models, limits from the file), never from
robokit's own ranges."""
import math
import warnings

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import robokit as rk
from shared_robots import robot
from robokit.errors import DegreesWarning, RobokitWarning

DEG = np.array([0.0, 45.0, -90.0, 0.0, 30.0, 0.0])  # the PUMA's "ready" pose, typed in degrees
RAD = np.deg2rad(DEG)
TURN = 2 * math.pi



def degree_warnings(fn, *args, **kwargs):
    """The DegreesWarnings that calling fn gives (every one recorded)."""
    with warnings.catch_warnings(record=True) as rec:
        warnings.simplefilter("always")
        fn(*args, **kwargs)
    return [w for w in rec if issubclass(w.category, DegreesWarning)]


def assert_one(ws, name):
    assert len(ws) == 1, [str(w.message) for w in ws]
    msg = str(ws[0].message)
    assert msg.startswith(f"{name}: ") and "degrees" in msg and "rk.deg2rad" in msg, msg
    assert ws[0].filename == __file__, ws[0].filename  # pointed at the user's call


def test_the_issue_example_warns_once_and_radians_do_not():
    """``rk.load("puma560").frame_pose([0, 45, -90, 0, 30, 0])`` returned a pose silently."""
    puma = robot("puma560")
    assert issubclass(DegreesWarning, RobokitWarning)
    for q in (DEG.tolist(), DEG.copy(), DEG.astype(np.float32), DEG.astype(int)):  # every input form
        assert_one(degree_warnings(puma.frame_pose, q), "q")
    assert degree_warnings(puma.frame_pose, RAD) == []
    assert np.allclose(rk.deg2rad(DEG), RAD) and np.allclose(rk.rad2deg(RAD), DEG)
    assert rk.deg2rad(180) == math.pi and isinstance(rk.deg2rad(180), float)


def test_solve_ik_seed_in_degrees_is_named():
    """``solve_ik(q0=...)`` in degrees was clipped to the limits without a word."""
    puma = robot("puma560")
    T = puma.frame_pose(RAD)
    assert_one(degree_warnings(rk.solve_ik, puma, T, q0=DEG), "q0")
    assert degree_warnings(rk.solve_ik, puma, T, q0=RAD) == []


def _entry_points():
    """(name of the argument, call with degrees, call with radians) for every entry point."""
    puma, ur5 = robot("puma560"), robot("ur5")
    p = puma.poe
    z, g, F = np.zeros(6), p.gravity, np.zeros(6)
    T = puma.frame_pose(RAD)
    Q = lambda q: np.array([q, q * 0.5])  # noqa: E731 — two rows
    yield "frame_pose", "q", lambda q: puma.frame_pose(q)
    yield "frame_pose batch", "q", lambda q: puma.frame_pose_batch(Q(q))
    yield "frame_pose frame", "q", lambda q: puma.frame_pose(q, "dh_3")
    yield "frame_poses", "q", lambda q: puma.frame_poses(q)
    yield "jacobian", "q", lambda q: puma.jacobian(q)
    yield "jacobian lwa", "q", lambda q: ur5.jacobian(q, reference="local_world_aligned")
    yield "jacobian batch", "q", lambda q: ur5.jacobian_batch(Q(q))
    yield "rnea", "q", lambda q: puma.rnea(q, z, z)
    yield "rnea batch", "q", lambda q: puma.rnea_batch(Q(q), Q(z), Q(z))
    yield "crba", "q", lambda q: puma.crba(q)
    yield "aba", "q", lambda q: puma.aba(q, z, z)
    yield "gravity_torques", "q", lambda q: puma.gravity_torques(q)
    yield "nonlinear_effects", "q", lambda q: puma.nonlinear_effects(q, z)
    yield "fkin_space", "thetalist", lambda q: rk.fkin_space(p.M, p.Slist, q)
    yield "fkin_space batch", "thetalist", lambda q: rk.fkin_space(p.M, p.Slist, Q(q))
    yield "fkin_body", "thetalist", lambda q: rk.fkin_body(p.M, p.Blist, q.tolist())
    yield "jacobian_space", "thetalist", lambda q: rk.jacobian_space(p.Slist, q)
    yield "jacobian_body", "thetalist", lambda q: rk.jacobian_body(p.Blist, q)
    yield "ikin_body", "thetalist0", lambda q: rk.ikin_body(p.Blist, p.M, T, q, 1e-3, 1e-3)
    yield "ikin_space", "thetalist0", lambda q: rk.ikin_space(p.Slist, p.M, T, q, 1e-3, 1e-3)
    yield "inverse_dynamics", "thetalist", lambda q: rk.inverse_dynamics(q, z, z, g, F, p.Mlist, p.Glist, p.Slist)
    yield "inverse_dynamics batch", "thetalist", lambda q: rk.inverse_dynamics(Q(q), Q(z), Q(z), g, F, p.Mlist,
                                                                              p.Glist, p.Slist)
    yield "mass_matrix", "thetalist", lambda q: rk.mass_matrix(q, p.Mlist, p.Glist, p.Slist)
    yield "vel_quadratic_forces", "thetalist", lambda q: rk.vel_quadratic_forces(q, z, p.Mlist, p.Glist, p.Slist)
    yield "gravity_forces", "thetalist", lambda q: rk.gravity_forces(q, g, p.Mlist, p.Glist, p.Slist)
    yield "end_effector_forces", "thetalist", lambda q: rk.end_effector_forces(q, F, p.Mlist, p.Glist, p.Slist)
    yield "forward_dynamics", "thetalist", lambda q: rk.forward_dynamics(q, z, z, g, F, p.Mlist, p.Glist, p.Slist)
    yield "inverse_dynamics_trajectory", "thetamat", lambda q: rk.inverse_dynamics_trajectory(
        Q(q), Q(z), Q(z), g, Q(F), p.Mlist, p.Glist, p.Slist)
    yield "forward_dynamics_trajectory", "thetalist", lambda q: rk.forward_dynamics_trajectory(
        q, z, Q(z), g, Q(F), p.Mlist, p.Glist, p.Slist, 0.01, 1)
    yield "coriolis_matrix", "thetalist", lambda q: rk.dynamics.coriolis_matrix(q, z, p.Mlist, p.Glist, p.Slist)
    yield "base_wrench", "thetalist", lambda q: rk.dynamics.base_wrench(q, z, z, g, F, p.Mlist, p.Glist, p.Slist)
    yield "computed_torque", "thetalist", lambda q: rk.computed_torque(q, z, z, g, p.Mlist, p.Glist, p.Slist,
                                                                      RAD, z, z, 1.0, 0.0, 1.0)
    yield "computed_torque desired", "thetalistd", lambda q: rk.computed_torque(RAD, z, z, g, p.Mlist, p.Glist,
                                                                               p.Slist, q, z, z, 1.0, 0.0, 1.0)
    yield "simulate_control", "thetalist", lambda q: rk.simulate_control(
        q, z, g, Q(F), p.Mlist, p.Glist, p.Slist, Q(q), Q(z), Q(z), g, p.Mlist, p.Glist, 1.0, 0.0, 1.0, 0.01, 1)
    yield "joint_trajectory", "thetastart", lambda q: rk.joint_trajectory(q, z, 1.0, 3, 5)
    yield "joint_trajectory end", "thetaend", lambda q: rk.joint_trajectory(z, q, 1.0, 3, 5)
    yield "solve_ik", "q0", lambda q: rk.solve_ik(puma, T, q0=q)
    yield "ik_jacobian_transpose", "q0", lambda q: rk.ik.ik_jacobian_transpose(puma, T, q, max_iterations=2)
    yield "select_solution", "q_ref", lambda q: rk.ik.select_solution(rk.ik_analytic(puma, T), q)
    yield "ik_analytic wrist_ref", "wrist_ref", lambda q: rk.ik_analytic(puma, T, wrist_ref=float(q[1]))
    yield "simulate", "trajectory.q", lambda q: rk.simulate(
        puma, rk.control.ComputedTorque(puma, Kp=10.0), rk.trajectory.quintic_trajectory(q, q, 0.01, t=[0, 0.005, 0.01]))
    yield "simulate q0", "q0", lambda q: rk.simulate(
        puma, rk.control.ComputedTorque(puma, Kp=10.0), rk.trajectory.quintic_trajectory(RAD, RAD, 0.01, t=[0, 0.01]), q0=q)
    yield "track_line", "q0", lambda q: rk.control.track_line(puma, q, puma.frame_pose(RAD)[:3, 3], 0.01, dt=0.005)
    yield "joint_trajectory_from_cartesian", "q0", lambda q: rk.trajectory.joint_trajectory_from_cartesian(
        puma, rk.trajectory.cartesian_line_trajectory(T, T, tf=0.1, t=[0.0, 0.1]), q0=q)


ENTRY = list(_entry_points())


@pytest.mark.parametrize("label,name,call", ENTRY, ids=[e[0] for e in ENTRY])
def test_every_entry_point_warns_once_for_degrees_and_never_for_radians(label, name, call):
    if label == "ik_analytic wrist_ref":
        assert_one(degree_warnings(call, np.array([0.0, 90.0])), name)
        assert degree_warnings(call, np.array([0.0, 1.5])) == []
        return
    assert_one(degree_warnings(call, DEG.copy()), name)
    assert degree_warnings(call, RAD.copy()) == []


def test_plan_and_retime_name_their_arguments():
    """Trajectories' end points (plan's start and goal, retime's path) are joint values."""
    pytest.importorskip("ompl")
    pytest.importorskip("toppra")
    from robokit.collision import World

    puma = robot("puma560")
    w = World(puma, [])
    def plan_from_degrees():
        with pytest.raises(rk.InputError, match="q_start"):  # then refused: outside the limits
            rk.plan(puma, DEG, RAD, w)

    assert_one(degree_warnings(plan_from_degrees), "q_start")
    assert_one(degree_warnings(lambda: rk.retime(puma, np.array([RAD * 0, DEG]), vmax=1.0, amax=1.0)), "path")
    assert degree_warnings(lambda: rk.retime(puma, np.array([RAD * 0, RAD]), vmax=1.0, amax=1.0)) == []


def test_robokits_own_iterations_stay_silent():
    """Values robokit computes itself (a Newton iteration that wanders beyond a turn, a
    simulation's state) never warn: only the user's arguments are checked."""
    p = robot("puma560").poe
    far = p.M.copy()
    far[:3, 3] = [5.0, 5.0, 5.0]  # out of reach: the iteration diverges through large angles
    assert degree_warnings(rk.ikin_body, p.Blist, p.M, far, RAD, 1e-6, 1e-6) == []


# ----------------------------------------------------------------------------- the rule, independently
_URDF = """<?xml version="1.0"?>
<robot name="mixed">
  <link name="base"/><link name="l1"><inertial><mass value="1"/><inertia ixx="0.01" iyy="0.01" izz="0.01" ixy="0" ixz="0" iyz="0"/></inertial></link>
  <link name="l2"><inertial><mass value="1"/><inertia ixx="0.01" iyy="0.01" izz="0.01" ixy="0" ixz="0" iyz="0"/></inertial></link>
  <link name="l3"><inertial><mass value="1"/><inertia ixx="0.01" iyy="0.01" izz="0.01" ixy="0" ixz="0" iyz="0"/></inertial></link>
  <link name="l4"><inertial><mass value="1"/><inertia ixx="0.01" iyy="0.01" izz="0.01" ixy="0" ixz="0" iyz="0"/></inertial></link>
  <joint name="j1" type="revolute"><parent link="base"/><child link="l1"/><axis xyz="0 0 1"/>
    <limit lower="-2.5" upper="2.5" effort="10" velocity="1"/></joint>
  <joint name="j2" type="continuous"><parent link="l1"/><child link="l2"/><origin xyz="0.3 0 0"/><axis xyz="0 1 0"/></joint>
  <joint name="j3" type="prismatic"><parent link="l2"/><child link="l3"/><origin xyz="0.3 0 0"/><axis xyz="1 0 0"/>
    <limit lower="0" upper="20" effort="10" velocity="1"/></joint>
  <joint name="j4" type="revolute"><parent link="l3"/><child link="l4"/><origin xyz="0.3 0 0"/><axis xyz="0 0 1"/>
    <limit lower="-9.5" upper="9.5" effort="10" velocity="1"/></joint>
</robot>
"""


@pytest.fixture(scope="module")
def mixed(tmp_path_factory):
    path = tmp_path_factory.mktemp("mixed") / "mixed.urdf"
    path.write_text(_URDF)
    return rk.load(path)


def _looks_like_degrees(q, kinds, lo, hi, state):
    """The documented rule: a revolute value beyond ±2π and past its limits, or past its limits by more
    than a turn; prismatic joints never; continuous joints at ±2π, exempt in states."""
    flagged = []
    for v, k, l, h in zip(q, kinds, lo, hi):
        if k == "P" or (k == "C" and state):
            flagged.append(False)
        elif k == "C":
            flagged.append(abs(v) > TURN)
        else:
            flagged.append((abs(v) > TURN and not (l <= v <= h)) or v < l - TURN or v > h + TURN)
    return any(flagged)


def test_mixed_robot_kinds_read_from_pinocchio(mixed):
    kinds = []
    for jm in list(mixed.model.joints)[1:]:
        short = jm.shortname()
        kinds.append("C" if "RUB" in short else "P" if short.startswith("JointModelP") else "R")
    assert kinds == ["R", "C", "P", "R"]
    assert np.allclose(mixed.qlim[[0, 2, 3]], [[-2.5, 2.5], [0, 20], [-9.5, 9.5]])


@settings(max_examples=60, deadline=None)
@given(st.lists(st.floats(-400, 400), min_size=4, max_size=4), st.booleans())
def test_warning_follows_the_documented_rule(mixed, values, batch):
    """On a robot with a limited, a continuous, a prismatic and a wide-range (±9.5 rad) joint: the
    fast paths and the full check warn exactly when the rule says a value looks like degrees."""
    q = np.array(values)
    kinds = ["R", "C", "P", "R"]
    lo, hi = mixed.qlim.T
    if batch:  # rows of a path: continuous joints may wind
        expected = _looks_like_degrees(q, kinds, lo, hi, state=True)
        got = degree_warnings(mixed.frame_pose, np.array([q * 0.0, q]))
    else:
        expected = _looks_like_degrees(q, kinds, lo, hi, state=False)
        got = degree_warnings(mixed.frame_pose, q)
        assert len(degree_warnings(mixed.jacobian, q)) == int(expected)
        assert len(degree_warnings(mixed.rnea, q, q * 0, q * 0)) == int(expected)
        assert len(degree_warnings(mixed.frame_pose, q.tolist())) == int(expected)
    assert len(got) == int(expected), (q, [str(w.message) for w in got])


def test_continuous_joints_wind_in_states_but_not_in_one_off_queries(mixed):
    q = np.array([0.5, 45.0, 1.0, 0.2])  # the continuous joint at 45
    assert_one(degree_warnings(mixed.frame_pose, q), "q")  # a one-off configuration: degrees
    assert degree_warnings(mixed.frame_pose, np.array([q, q])) == []  # rows of a path: a wound joint
    assert degree_warnings(rk.solve_ik, mixed, mixed.frame_pose(np.zeros(4)), q0=q, max_restarts=0) == []
    assert degree_warnings(mixed.frame_pose, np.array([0.0, 0.0, 15.0, 9.0])) == []  # 15 m; 9 rad inside ±9.5
    assert_one(degree_warnings(mixed.frame_pose, np.array([0.0, 0.0, 15.0, 30.0])), "q")
