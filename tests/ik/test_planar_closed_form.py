"""ik_analytic on planar arms of one to three joints (and one prismatic joint), against Pinocchio.

The arms are random DH tables in both conventions — twists 0 or π (parallel or antiparallel
axes), random lengths, offsets, joint offsets, flipped joints, base and tool frames — loaded as
Robots (URDF → Pinocchio), so the check goes through Pinocchio's kinematics, not the solver's
own. Every solution must reach the target pose through ``robot.frame_pose``; the configuration
that generated it must be among them; a numerical sweep (``solve_ik`` from many random starts)
must find nothing else; a pose the arm cannot take (tilted off its plane, lifted off it, or out
of reach) gives [].
"""
import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import robokit
from robokit.description.dh import DHLink, DHTable, matrix_from_rpy
from robokit.errors import InputError
from robokit.ik import ik_analytic, ik_analytic_batch, ik_analytic_kind
from tests.ik.test_closed_form import angle_dist

TOL = 1e-9


def planar_table(seed, convention, n, flips=False, prismatic=False, limits=True):
    rng = np.random.default_rng(seed)
    rows = []
    for i in range(n):
        row = {"joint": "P" if prismatic else "R", "a": rng.uniform(0.2, 0.7) * rng.choice([-1, 1]),
               "alpha": float(rng.choice([0.0, np.pi])), "d": rng.uniform(-0.3, 0.3),
               "theta": rng.uniform(-np.pi, np.pi), "flip": bool(flips and rng.random() < 0.5)}
        if limits:
            row["qlim"] = np.array([-0.5, 0.5]) if prismatic else np.sort(rng.uniform(-3.5, 3.5, 2))
        rows.append(row)
    base, tool = np.eye(4), np.eye(4)
    base[:3, :3], base[:3, 3] = matrix_from_rpy(rng.uniform(-1, 1, 3)), rng.uniform(-0.2, 0.2, 3)
    tool[:3, :3], tool[:3, 3] = matrix_from_rpy(rng.uniform(-1, 1, 3)), rng.uniform(-0.2, 0.2, 3)
    return DHTable(f"planar{n}_{seed}", convention, tuple(DHLink(**r) for r in rows), base=base, tool=tool)


def check(robot, q, T, sols):
    rev = np.array([l.joint == "R" for l in robot.dh.links])
    for s in sols:
        assert np.abs(robot.frame_pose(s.q) - T).max() < TOL, s.label
        inside = bool(np.all(s.q >= robot.qlim[:, 0] - 1e-12) and np.all(s.q <= robot.qlim[:, 1] + 1e-12))
        assert s.within_limits == inside
        assert np.all(s.q[rev] > -np.pi - 1e-12) or not s.within_limits or np.any(robot.qlim[rev, 0] < -np.pi)
    for i in range(len(sols)):
        for j in range(i):
            assert angle_dist(sols[i].q, sols[j].q, rev) > 1e-9
    assert len({s.label for s in sols}) == len(sols)
    if q is not None:
        assert min(angle_dist(s.q, q, rev) for s in sols) < 1e-7


@settings(max_examples=30, deadline=None)
@given(st.integers(0, 2**31), st.sampled_from(["standard", "modified"]), st.sampled_from([1, 2, 3]), st.booleans())
def test_random_planar_arms_against_pinocchio(seed, convention, n, flips):
    robot = robokit.load(planar_table(seed, convention, n, flips))
    assert ik_analytic_kind(robot).method == "planar"
    rng = np.random.default_rng(seed + 7)
    for _ in range(4):
        q = rng.uniform(-np.pi, np.pi, n)
        T = robot.frame_pose(q)
        sols = ik_analytic(robot, T)
        check(robot, q, T, sols)
        assert len(sols) == (2 if n == 3 else 1)


@settings(max_examples=15, deadline=None)
@given(st.integers(0, 2**31), st.sampled_from(["standard", "modified"]), st.sampled_from([1, 2, 3]))
def test_poses_off_the_plane_or_out_of_reach_give_none(seed, convention, n):
    robot = robokit.load(planar_table(seed, convention, n))
    rng = np.random.default_rng(seed)
    T = robot.frame_pose(rng.uniform(-np.pi, np.pi, n))
    axis = robot.frame_pose(np.zeros(n))  # the plane's normal, base frame: joint 1's axis
    normal = robot.jacobian(np.zeros(n))[:3, 0]
    tilted = T.copy()
    u = np.cross(normal, rng.normal(size=3))
    u /= np.linalg.norm(u)
    c, s = math.cos(1e-6), math.sin(1e-6)
    K = np.array([[0, -u[2], u[1]], [u[2], 0, -u[0]], [-u[1], u[0], 0]])
    tilted[:3, :3] = (np.eye(3) + s * K + (1 - c) * K @ K) @ T[:3, :3]
    lifted = T.copy()
    lifted[:3, 3] += 1e-6 * normal
    far = T.copy()
    far[:3, 3] = axis[:3, 3] + 100.0 * np.cross(normal, u)
    for pose in (tilted, lifted, far):
        assert ik_analytic(robot, pose) == []


def test_shipped_planar_arms_and_the_lecture_functions():
    """The course's two-link and RRR arms: the solutions are those of Lecture 5's ik_planar_2link /
    ik_planar_rrr in the plane, the one reaching the tool's angle (two-link) or both (RRR)."""
    two = robokit.load("twolink")
    for q in ([0.3, 0.5], [2.0, -1.1], [-2.5, 0.2]):
        T = two.frame_pose(np.array(q))
        sols = ik_analytic(two, T)
        lecture = robokit.ik.ik_planar_2link(T[0, 3], T[1, 3], 1.0, 0.8)
        assert len(sols) == 1
        match = [s for s in lecture if np.allclose(s.q, sols[0].q, atol=1e-12)]
        assert len(match) == 1 and match[0].label == sols[0].label
    rrr = robokit.load("rrr")
    q = np.array([0.3, 0.5, -0.2])
    T = rrr.frame_pose(q)
    phi = math.atan2(T[1, 0], T[0, 0])
    lecture = robokit.ik.ik_planar_rrr(T[0, 3], T[1, 3], phi, 0.5, 0.4, 0.2)
    sols = ik_analytic(rrr, T)
    assert [s.label for s in sols] == [s.label for s in lecture] == ["elbow down", "elbow up"]
    for a, b in zip(sols, lecture):
        assert angle_dist(a.q, b.q, np.ones(3, bool)) < 1e-12


@pytest.mark.parametrize("n", [2, 3])
def test_a_sweep_of_numerical_ik_finds_no_other_solution(n):
    robot = robokit.load(planar_table(5, "standard", n, limits=False))
    rng = np.random.default_rng(3)
    q = rng.uniform(-np.pi, np.pi, n)
    T = robot.frame_pose(q)
    sols = ik_analytic(robot, T)
    rev = np.ones(n, bool)
    for _ in range(60):
        res = robokit.solve_ik(robot, T, rng.uniform(-np.pi, np.pi, n), method="lm")
        if res.success:
            assert np.abs(robot.frame_pose(np.angle(np.exp(1j * res.q))) - T).max() < 1e-6
            assert min(angle_dist(s.q, res.q, rev) for s in sols) < 1e-5


def test_stretched_and_folded_three_joint_arm():
    robot = robokit.load("rrr")
    T = robot.frame_pose(np.array([0.4, 0.0, 0.3]))  # stretched: elbow up and down meet
    sols = ik_analytic(robot, T)
    check(robot, np.array([0.4, 0.0, 0.3]), T, sols)
    assert 1 <= len(sols) <= 2 and not any(s.degenerate for s in sols)
    # folded onto axis 1 (l1 = l2): joint 1 is free and takes wrist_ref
    rows = [DHLink(joint="R", a=0.5), DHLink(joint="R", a=0.5), DHLink(joint="R", a=0.2)]
    folded = robokit.load(DHTable("folded", "standard", tuple(rows)))
    q = np.array([0.7, np.pi, -0.4])
    T = folded.frame_pose(q)
    for ref in (0.0, 1.2):
        sols = ik_analytic(folded, T, ref)
        assert len(sols) == 1 and sols[0].degenerate
        assert abs(sols[0].q[0] - ref) < 1e-12
        assert np.abs(folded.frame_pose(sols[0].q) - T).max() < TOL


def test_one_prismatic_joint():
    robot = robokit.load(planar_table(2, "standard", 1, prismatic=True))
    assert ik_analytic_kind(robot).method == "planar"
    for q in (-0.3, 0.1, 0.7):
        T = robot.frame_pose(np.array([q]))
        sols = ik_analytic(robot, T)
        assert len(sols) == 1 and abs(sols[0].q[0] - q) < 1e-12
        assert sols[0].within_limits == (q <= 0.5)
    T = robot.frame_pose(np.array([0.1]))
    T[:3, 3] += 1e-6 * np.cross(robot.jacobian(np.zeros(1))[3:, 0], [0.3, 0.4, 0.5])
    assert ik_analytic(robot, T) == []


def test_arms_without_the_planar_closed_form_are_refused_naming_why():
    rows = [DHLink(joint="R", a=0.5, alpha=0.3), DHLink(joint="R", a=0.4)]
    with pytest.raises(InputError, match="axis 2 is not parallel to axis 1"):
        ik_analytic(robokit.load(DHTable("oblique", "standard", tuple(rows))), np.eye(4))
    rows = [DHLink(joint="R", a=0.5), DHLink(joint="P", a=0.4)]
    with pytest.raises(InputError, match="joint 2 is prismatic"):
        ik_analytic(robokit.load(DHTable("rp", "standard", tuple(rows))), np.eye(4))
    rows = [DHLink(joint="R", a=0.0, d=0.3), DHLink(joint="R", a=0.4)]
    with pytest.raises(InputError, match="axes 1 and 2 coincide"):
        ik_analytic(robokit.load(DHTable("coaxial", "standard", tuple(rows))), np.eye(4))
    with pytest.raises(InputError, match="7 joints"):
        ik_analytic(robokit.load("panda"), np.eye(4))


def test_batch_and_urdf_forms_agree():
    table = planar_table(9, "modified", 3, flips=True)
    robot = robokit.load(table)
    rng = np.random.default_rng(1)
    Ts = np.stack([robot.frame_pose(rng.uniform(-np.pi, np.pi, 3)) for _ in range(5)])
    Q, counts = ik_analytic_batch(robot, Ts)
    assert Q.shape[2] == 3
    for i, T in enumerate(Ts):
        sols = ik_analytic(robot, T)
        assert counts[i] == len(sols)
        for k, s in enumerate(sols):
            assert np.array_equal(Q[i, k], s.q)


URDF = """<robot name="tilted_planar">
  <link name="base"/>
  <joint name="j1" type="revolute"><parent link="base"/><child link="l1"/>
    <origin xyz="0.1 -0.2 0.3" rpy="0.2 -0.4 0.7"/><axis xyz="1 2 2"/>
    <limit lower="-2" upper="2" effort="1" velocity="1"/></joint>
  <link name="l1"/>
  <joint name="j2" type="revolute"><parent link="l1"/><child link="l2"/>
    <origin xyz="0.5 0.1 -0.2"/><axis xyz="-1 -2 -2"/>
    <limit lower="-3" upper="3" effort="1" velocity="1"/></joint>
  <link name="l2"/>
  <joint name="j3" type="continuous"><parent link="l2"/><child link="l3"/>
    <origin xyz="0.2 0.4 0.05"/><axis xyz="1 2 2"/></joint>
  <link name="l3"/>
  <joint name="tool" type="fixed"><parent link="l3"/><child link="tip"/>
    <origin xyz="0.15 -0.05 0.1" rpy="0.3 0.2 -0.1"/></joint>
  <link name="tip"/>
</robot>
"""


@pytest.mark.filterwarnings("ignore:.*no body on the chain")
def test_a_urdf_planar_arm_in_a_tilted_plane(tmp_path):
    """Axes along (1, 2, 2)/3 (joint 2 the other way), offsets out of the plane, a continuous joint:
    read through the URDF's own frames (dh_from_urdf), checked against Pinocchio."""
    path = tmp_path / "tilted.urdf"
    path.write_text(URDF)
    robot = robokit.load(str(path))
    assert robot.dh is None and ik_analytic_kind(robot).method == "planar"
    rng = np.random.default_rng(4)
    for _ in range(10):
        q = np.array([rng.uniform(-2, 2), rng.uniform(-3, 3), rng.uniform(-np.pi, np.pi)])
        T = robot.frame_pose(q)
        sols = ik_analytic(robot, T)
        assert len(sols) == 2
        for s in sols:
            assert np.abs(robot.frame_pose(s.q) - T).max() < TOL
        assert min(angle_dist(s.q, q, np.ones(3, bool)) for s in sols) < 1e-7
