"""Closed-form IK for any arm that has one (Pieper, UR family), checked against Pinocchio.

Every returned solution must reproduce the target through the robot's Pinocchio model
(``robot.frame_pose``), the configuration that generated the target must be among the
solutions, and solutions found by the numerical solver from random seeds must be among
them too (so none is missed). Random arms are generated as DH tables in both conventions
and loaded as Robots (URDF → Pinocchio), so the check does not go through the solver's
own DH product.
"""
import math

import numpy as np
import pytest
from hypothesis import HealthCheck, assume, given, settings
from hypothesis import strategies as st

import robokit
from shared_robots import robot as shared_robot
from robokit.description.dh import DHLink, DHTable, matrix_from_rpy
from robokit.ik import AnalyticIK, ik_analytic, ik_analytic_kind, ik_puma560

TOL = 1e-9


def angle_dist(a, b, revolute):
    d = np.asarray(a, float) - np.asarray(b, float)
    d[revolute] = np.angle(np.exp(1j * d[revolute]))
    return float(np.abs(d).max())


def check_solutions(robot, q_true, T, sols):
    """Every solution reproduces T (Pinocchio FK); the generator is among them; all distinct."""
    rev = np.array([l.joint == "R" for l in robot.dh.links]) if robot.dh is not None else np.ones(robot.n, bool)
    for s in sols:
        assert np.abs(robot.frame_pose(s.q) - T).max() < TOL, s.label
        assert np.all(s.q[rev] > -np.pi - 1e-12)
        inside = bool(np.all(s.q >= robot.qlim[:, 0] - 1e-12) and np.all(s.q <= robot.qlim[:, 1] + 1e-12))
        assert s.within_limits == inside
    for i in range(len(sols)):
        for j in range(i):
            assert angle_dist(sols[i].q, sols[j].q, rev) > 1e-9
    assert len({s.label for s in sols}) == len(sols)
    if q_true is not None:
        assert min(angle_dist(s.q, q_true, rev) for s in sols) < 1e-7
    return rev


# ---------------------------------------------------------------- shipped and example arms
@pytest.fixture(scope="module")
def puma():
    return robokit.load("puma560")


@pytest.fixture(scope="module", params=["ur3", "ur5", "ur10"])
def ur(request):
    return shared_robot(request.param)


def test_kinds_are_detected_from_the_axes(puma):
    assert ik_analytic_kind(puma).method == "spherical wrist"
    assert ik_analytic_kind(shared_robot("ur5")).method == "three parallel axes"
    kind = ik_analytic_kind(shared_robot("panda"))
    assert not kind and "7 joints" in kind.reason
    with pytest.raises(ValueError, match="7 joints"):
        ik_analytic(shared_robot("panda"), np.eye(4))


@settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(st.integers(0, 2**31))
def test_puma_eight_solutions(puma, seed):
    rng = np.random.default_rng(seed)
    q = rng.uniform(-np.pi, np.pi, 6)
    T = puma.frame_pose(q)
    sols = ik_analytic(puma, T)
    check_solutions(puma, q, T, sols)
    if abs(math.sin(q[4])) > 1e-3:
        assert len(sols) == 8  # PUMA 560 in general position (Craig §4.7; Paul 1981)
        labels = {s.label for s in sols}
        assert labels == {f"{a}, {e}, {w}" for a in ("left", "right") for e in ("elbow up", "elbow down")
                          for w in ("flip", "no flip")}


def test_puma560_wrapper_gives_the_general_solutions(puma):
    rng = np.random.default_rng(7)
    for _ in range(20):
        q = rng.uniform(-np.pi, np.pi, 6)
        T = puma.frame_pose(q)
        a = ik_analytic(puma, T)
        b = ik_puma560(puma.dh, T)
        assert len(a) == len(b) == 8
        for s in b:
            assert min(angle_dist(s.q, t.q, np.ones(6, bool)) for t in a) < 1e-12


@settings(max_examples=40, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(st.integers(0, 2**31))
def test_ur_family(ur, seed):
    rng = np.random.default_rng(seed)
    q = rng.uniform(-np.pi, np.pi, 6)
    T = ur.frame_pose(q)
    sols = ik_analytic(ur, T)
    check_solutions(ur, q, T, sols)
    assert len(sols) % 2 == 0 and len(sols) <= 8 or abs(math.sin(q[4])) < 1e-6


def test_ur5_general_position_has_eight_and_numerical_ik_finds_no_other():
    robot = shared_robot("ur5")
    q = np.array([0.4, -1.3, 1.2, -0.6, 1.1, 0.3])
    T = robot.frame_pose(q)
    sols = ik_analytic(robot, T)
    check_solutions(robot, q, T, sols)
    assert len(sols) == 8  # Hawkins (2013), "Analytic inverse kinematics for the Universal Robots"
    rng = np.random.default_rng(0)
    found = set()
    for _ in range(40):
        res = robokit.solve_ik(robot, T, q0=rng.uniform(-np.pi, np.pi, 6))
        if not res.success:
            continue
        d = [angle_dist(res.q, s.q, np.ones(6, bool)) for s in sols]
        assert min(d) < 1e-6  # every numerical solution is one of the closed-form ones
        found.add(int(np.argmin(d)))
    assert len(found) >= 4  # the random seeds reached several branches


def test_puma_numerical_ik_finds_no_other(puma):
    q = np.array([0.3, -0.6, 0.5, 0.8, 0.9, -0.4])
    T = puma.frame_pose(q)
    sols = ik_analytic(puma, T)
    rng = np.random.default_rng(1)
    for _ in range(30):
        res = robokit.solve_ik(puma, T, q0=rng.uniform(-np.pi, np.pi, 6))
        if res.success:
            assert min(angle_dist(res.q, s.q, np.ones(6, bool)) for s in sols) < 1e-6


def test_unreachable_pose_gives_empty_list(puma, ur):
    T = np.eye(4)
    T[:3, 3] = [5.0, 0.0, 0.3]
    assert ik_analytic(puma, T) == []
    assert ik_analytic(ur, T) == []


def test_wrist_singularity_documented_choice(puma):
    q = np.array([0.3, -0.5, 0.4, 0.7, 0.0, 0.2])  # θ5 = 0: axes 4 and 6 aligned
    T = puma.frame_pose(q)
    sols = ik_analytic(puma, T, wrist_ref=0.7)
    check_solutions(puma, q, T, sols)
    sing = [s for s in sols if "wrist singular" in s.label]
    assert sing and all(s.degenerate and abs(s.q[3] - 0.7) < 1e-12 for s in sing)
    robot = shared_robot("ur5")
    q = np.array([0.5, -1.0, 1.3, -0.4, 0.0, 0.9])  # UR: axis 6 parallel to axes 2–4
    T = robot.frame_pose(q)
    sols = ik_analytic(robot, T, wrist_ref=0.9)
    check_solutions(robot, q, T, sols)
    sing = [s for s in sols if "wrist singular" in s.label]
    assert sing and all(s.degenerate and abs(s.q[5] - 0.9) < 1e-12 for s in sing)


def test_urdf_of_a_dh_model_goes_through_urdf_to_dh(tmp_path):
    from robokit.description.models import models_dir

    robot = robokit.load(str(models_dir() / "puma560.urdf"))
    assert robot.dh is None
    q = np.array([0.2, 0.4, -0.3, 1.0, -0.7, 0.5])
    T = robot.frame_pose(q)
    sols = ik_analytic(robot, T)
    check_solutions(robot, q, T, sols)
    assert len(sols) == 8


@pytest.mark.parametrize("name, method", [("kinova", "spherical wrist"), ("z1", "three parallel axes")])
def test_other_example_robot_data_arms(name, method):
    robot = shared_robot(name)  # URDFs; the kinova arm has continuous (unlimited) joints
    assert ik_analytic_kind(robot).method == method
    rng = np.random.default_rng(2)
    for _ in range(10):
        q = robot.random_configuration(rng)
        T = robot.frame_pose(q)
        check_solutions(robot, q, T, ik_analytic(robot, T))


def test_bad_input():
    with pytest.raises(TypeError, match="robot"):
        ik_analytic("puma560", np.eye(4))
    with pytest.raises(ValueError, match="T"):
        ik_analytic(robokit.load("puma560"), np.ones((4, 4)))


# ---------------------------------------------------------------- random spherical-wrist arms
def random_arm(seed, convention, kinds="RRR", oblique=True):
    """A 6-joint DH table with a spherical wrist, random lengths, twists, offsets, base, tool."""
    rng = np.random.default_rng(seed)
    rows = []
    for i in range(6):
        al = rng.uniform(-np.pi, np.pi) if oblique else rng.choice([-np.pi / 2, np.pi / 2])
        rows.append({"joint": kinds[i] if i < 3 else "R", "a": rng.uniform(-0.5, 0.5), "alpha": al,
                     "d": rng.uniform(-0.5, 0.5), "theta": rng.uniform(-np.pi, np.pi)})
    # axes 4, 5, 6 meet: zero the distances between them (standard rows 4, 5; modified rows 5, 6)
    w = (3, 4) if convention == "standard" else (4, 5)
    rows[w[0]]["a"] = rows[w[1]]["a"] = 0.0
    rows[4]["d"] = 0.0
    for i in w:  # keep consecutive wrist axes well apart
        while abs(math.sin(rows[i]["alpha"])) < 0.3:
            rows[i]["alpha"] = rng.uniform(-np.pi, np.pi)
    base, tool = np.eye(4), np.eye(4)
    base[:3, :3], base[:3, 3] = matrix_from_rpy(rng.uniform(-1, 1, 3)), rng.uniform(-0.2, 0.2, 3)
    tool[:3, :3], tool[:3, 3] = matrix_from_rpy(rng.uniform(-1, 1, 3)), rng.uniform(-0.1, 0.1, 3)
    return DHTable(f"arm{seed}", convention, tuple(DHLink(**r) for r in rows), base=base, tool=tool)


def random_q(rng, kinds):
    q = rng.uniform(-np.pi, np.pi, 6)
    for i, k in enumerate(kinds):
        if k == "P":
            q[i] = rng.uniform(-0.5, 0.5)
    return q


@settings(max_examples=25, deadline=None)
@given(st.integers(0, 2**31), st.sampled_from(["standard", "modified"]),
       st.sampled_from(["RRR", "RRP", "RPR", "PRR", "RPP", "PPR", "PRP", "PPP"]), st.booleans())
def test_random_spherical_wrist_arms(seed, convention, kinds, oblique):
    robot = robokit.load(random_arm(seed, convention, kinds, oblique))
    kind = ik_analytic_kind(robot)
    if kind.method is None:  # right-angled twists can confine the wrist centre to a surface
        assert "cannot move the wrist centre" in kind.reason and not oblique
        assume(False)
    assert kind.method == "spherical wrist"
    rng = np.random.default_rng(seed + 1)
    for _ in range(3):
        q = random_q(rng, kinds)
        T = robot.frame_pose(q)
        sols = ik_analytic(robot, T)
        check_solutions(robot, q, T, sols)
        assert len(sols) <= 8


@pytest.mark.parametrize("convention", ["standard", "modified"])
def test_random_general_arm_quartic_numerical_ik_finds_no_other(convention, tmp_path):
    table = random_arm(11, convention, "RRR", oblique=True)
    path = tmp_path / "arm.yaml"
    table.save(path, angle_unit="rad")
    robot = robokit.load(path)
    assert robot.dh is not None
    rng = np.random.default_rng(3)
    for _ in range(3):
        q = rng.uniform(-np.pi, np.pi, 6)
        T = robot.frame_pose(q)
        sols = ik_analytic(robot, T)
        check_solutions(robot, q, T, sols)
        assert AnalyticIK(robot).solver.case == "RR-quartic"  # a1 ≠ 0, sin α1 ≠ 0: the quartic
        for _ in range(12):
            res = robokit.solve_ik(robot, T, q0=rng.uniform(-np.pi, np.pi, 6))
            if res.success:
                assert min(angle_dist(res.q, s.q, np.ones(6, bool)) for s in sols) < 1e-6


def test_stanford_arm_rrp():
    # Stanford arm (Paul 1981; Spong, Hutchinson, Vidyasagar Table 3.4): standard DH,
    # alpha = -90, 90, 0, -90, 90, 0 deg; d2 = 0.154 m, d3 = q3 (prismatic), d6 = 0.263 m.
    rows = [("R", 0, -90, 0.412, 0), ("R", 0, 90, 0.154, 0), ("P", 0, 0, 0.0, -90),
            ("R", 0, -90, 0, 0), ("R", 0, 90, 0, 0), ("R", 0, 0, 0.263, 0)]
    links = tuple(DHLink(j, a, math.radians(al), d, math.radians(th)) for j, a, al, d, th in rows)
    robot = robokit.load(DHTable("stanford", "standard", links))
    assert ik_analytic_kind(robot).method == "spherical wrist"
    q = np.array([0.4, -0.7, 0.5, 0.3, 1.1, -0.8])
    T = robot.frame_pose(q)
    sols = ik_analytic(robot, T)
    check_solutions(robot, q, T, sols)
    assert len(sols) == 8  # 2 θ1 × 2 (θ2, d3) × 2 wrists


def test_offset_wrist_goes_to_the_general_method_with_the_distance():
    table = random_arm(5, "standard", "RRR", oblique=False)
    rows = list(table.links)
    rows[4] = DHLink("R", 0.06, rows[4].alpha, 0.0, rows[4].theta)  # a5 = 6 cm: axes 5, 6 miss
    robot = robokit.load(DHTable("offset", "standard", tuple(rows)))
    kind = ik_analytic_kind(robot)
    assert kind.method == "general 6R" and "axes 4–6 do not intersect: closest distance" in kind.reason
    q = np.array([0.3, -0.4, 0.8, 0.2, 0.9, -0.6])
    T = robot.frame_pose(q)
    check_solutions(robot, q, T, ik_analytic(robot, T))


def test_offset_wrist_with_a_prismatic_joint_is_refused_with_the_distance():
    table = random_arm(5, "standard", "RRP", oblique=False)
    rows = list(table.links)
    rows[4] = DHLink("R", 0.06, rows[4].alpha, 0.0, rows[4].theta)  # a5 = 6 cm: axes 5, 6 miss
    robot = robokit.load(DHTable("offset", "standard", tuple(rows)))
    kind = ik_analytic_kind(robot)
    assert kind.method is None and "axes 4–6 do not intersect" in kind.reason and "prismatic" in kind.reason
    with pytest.raises(ValueError, match="axes 4–6 do not intersect: closest distance"):
        ik_analytic(robot, robot.frame_pose(np.zeros(6)))


def test_limits_wider_than_pi_shift_into_range():
    table = random_arm(21, "standard", "RRR", oblique=False)
    rows = list(table.links)
    rows[0] = DHLink("R", rows[0].a, rows[0].alpha, rows[0].d, rows[0].theta, qlim=np.array([0.0, 2 * np.pi]))
    robot = robokit.load(DHTable("wide", "standard", tuple(rows)))
    q = np.array([4.5, 0.3, -0.2, 0.5, 0.7, 0.1])  # q1 beyond π, inside [0, 2π]
    T = robot.frame_pose(q)
    sols = ik_analytic(robot, T)
    best = min(sols, key=lambda s: angle_dist(s.q, q, np.ones(6, bool)))
    assert abs(best.q[0] - 4.5) < 1e-7  # shifted by 2π into the limits, not wrapped to −1.78
    check_solutions(robot, q, T, sols)


def random_parallel_arm(seed, convention):
    """A 6R DH table with axes 2–4 parallel (α₂, α₃ ∈ {0, π}: the z axes may point either way)
    and axes 5, 6 meeting (a₅ = 0); other twists and lengths random, with base and tool."""
    rng = np.random.default_rng(seed)
    a = rng.uniform(0.1, 0.6, 6) * rng.choice([-1, 1], 6)
    d = rng.uniform(-0.3, 0.3, 6)
    th = rng.uniform(-np.pi, np.pi, 6)
    al = rng.uniform(0.4, 2.7, 6) * rng.choice([-1, 1], 6)  # away from parallel
    al[1], al[2] = rng.choice([0.0, np.pi]), rng.choice([0.0, np.pi])
    a[4] = 0.0
    if convention == "modified":  # row i holds a_{i−1}, α_{i−1}
        a, al = np.r_[rng.uniform(-0.2, 0.2), a[:5]], np.r_[rng.uniform(-1, 1), al[:5]]
    links = tuple(DHLink("R", a[i], al[i], d[i], th[i]) for i in range(6))
    base, tool = np.eye(4), np.eye(4)
    base[:3, :3], base[:3, 3] = matrix_from_rpy(rng.uniform(-1, 1, 3)), rng.uniform(-0.2, 0.2, 3)
    tool[:3, :3], tool[:3, 3] = matrix_from_rpy(rng.uniform(-1, 1, 3)), rng.uniform(-0.1, 0.1, 3)
    return DHTable(f"par{seed}", convention, links, base=base, tool=tool)


@settings(max_examples=20, deadline=None)
@given(st.integers(0, 2**31), st.sampled_from(["standard", "modified"]))
def test_random_three_parallel_axes_arms(seed, convention):
    robot = robokit.load(random_parallel_arm(seed, convention))
    assert ik_analytic_kind(robot).method == "three parallel axes"
    rng = np.random.default_rng(seed + 1)
    for _ in range(4):
        q = rng.uniform(-np.pi, np.pi, 6)
        T = robot.frame_pose(q)
        sols = ik_analytic(robot, T)
        check_solutions(robot, q, T, sols)
        assert len(sols) <= 8


def reversed_table(table):
    """The DH table (modified convention) of ``table``'s chain read from the tool to the base:
    its tool pose at q′ is the inverse of the original's at q = −reverse(q′)."""
    from robokit.ik._dh_chain import DHChain

    rc = DHChain(table).reversed()
    rows = [DHLink(rc.kinds[0], 0.0, 0.0, rc.d0[0], rc.th0[0])]
    rows += [DHLink(rc.kinds[i], rc.a[i - 1], rc.alpha[i - 1], rc.d0[i], rc.th0[i]) for i in range(1, 6)]
    return DHTable(f"{table.name}_rev", "modified", tuple(rows), base=rc.base, tool=rc.tool)


@pytest.mark.parametrize("make, method", [(lambda: random_arm(3, "standard", "RRR"), "spherical wrist"),
                                          (lambda: random_parallel_arm(4, "standard"), "three parallel axes")])
def test_structures_counted_from_the_tool(make, method):
    table = make()
    rev = reversed_table(table)
    q = np.array([0.3, -0.8, 1.1, 0.4, -0.6, 2.0])
    assert np.abs(np.linalg.inv(rev.fk(-q[::-1])) - table.fk(q)).max() < 1e-12  # the construction itself
    robot = robokit.load(rev)
    kind = ik_analytic_kind(robot)
    assert kind.method == method and "from the tool back to the base" in kind.reason
    rng = np.random.default_rng(5)
    for _ in range(5):
        q = rng.uniform(-np.pi, np.pi, 6)
        T = robot.frame_pose(q)
        sols = ik_analytic(robot, T)
        check_solutions(robot, q, T, sols)
