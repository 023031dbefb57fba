"""How far an arm is from a closed-form structure, as ik_analytic_kind measures and reports it.

The TheRobotStudio SO-ARM100 (``Simulation/SO100/so100.urdf``) has axes 2–4 exactly parallel and
axes 5 and 6 2 cm apart — 11 % of its reach, ten times the distance up to which an arm counts as a
calibrated UR-type arm. robokit used to call it "calibrated three parallel axes" and report that its
axes 5 and 6 "miss by up to 3.4e-21 m": the distance was measured after the meeting axes had been
moved onto their meeting point. The factory-calibrated UR5e's axes 5 and 6, which pass 7e-05 m
from a common point, were reported 1.2e-16 m off. Here the distance an arm reports is held against the distance between
the two joint axes that Pinocchio's model of the arm gives (the screw axes of its world-frame
Jacobian at q = 0), not against robokit's own DH extraction.
"""
import math
import re
import warnings

import numpy as np
import pinocchio as pin
import pytest

import robokit
from robokit.description.dh import DHLink, DHTable


def ur5_with_wrist_offset(a5: float) -> robokit.Robot:
    """The UR5's DH table with axes 5 and 6 ``a5`` apart (the UR's own: 0, they meet)."""
    a = (0.0, -0.425, -0.39225, 0.0, a5, 0.0)
    d = (0.089159, 0.0, 0.0, 0.10915, 0.09465, 0.0823)
    alpha = (math.pi / 2, 0.0, 0.0, math.pi / 2, -math.pi / 2, 0.0)
    links = tuple(DHLink("R", a=a[i], d=d[i], alpha=alpha[i]) for i in range(6))
    return robokit.load(DHTable(f"ur5_a5_{a5:g}", "standard", links))


def axes_distance(robot: robokit.Robot, i: int, j: int) -> float:
    """The distance between joint axes i and j (0-based) at q = 0, from Pinocchio's world-frame
    Jacobian: column k is the screw (v, ω) of axis k, a point on it is ω × v."""
    model, data = robot.model, robot.model.createData()
    q = pin.neutral(model)
    J = pin.computeJointJacobians(model, data, q)
    lines = []
    for k in (i, j):
        v, w = J[:3, k], J[3:, k]
        w = w / np.linalg.norm(w)
        lines.append((np.cross(w, v), w))
    (p1, w1), (p2, w2) = lines
    n = np.cross(w1, w2)
    return float(abs((p2 - p1) @ n) / np.linalg.norm(n))


def reported_miss(reason: str) -> float:
    return float(re.search(r"the axes that should meet pass up to ([0-9.e+-]+) m from a common point", reason).group(1))


def test_a_calibrated_arm_reports_how_far_its_meeting_axes_miss():
    robot = ur5_with_wrist_offset(2e-4)
    kind = robokit.ik_analytic_kind(robot)
    assert kind.method == "calibrated three parallel axes"
    true = axes_distance(robot, 4, 5)
    assert true == pytest.approx(2e-4, rel=1e-9)
    # two lines pass half their distance from the point midway between them (2 digits in the reason)
    assert reported_miss(kind.reason) == pytest.approx(true / 2, rel=0.01)


def test_an_arm_whose_meeting_axes_miss_by_more_than_the_tolerance_is_not_a_calibrated_one():
    robot = ur5_with_wrist_offset(0.05)  # 5 % of the reach; the tolerance is 1 %
    true = axes_distance(robot, 4, 5)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        kind = robokit.ik_analytic_kind(robot)
    assert kind.method == "general 6R"
    assert f"axes 5 and 6 do not intersect (distance {true:.3g} m)" in kind.reason
    # axes 2–4 stay exactly parallel, which would make the general method's eigenproblem degenerate: it
    # eliminates on the arm with them turned and polishes on the arm (tests/ik/test_general_6r.py), and says so
    assert "axes 2–4 are exactly parallel" in kind.reason and "polishes every root on the arm itself" in kind.reason
    assert not [w for w in caught if issubclass(w.category, robokit.RobokitWarning)]


def test_an_arm_off_every_structure_says_nothing_about_degenerate_axes():
    rng = np.random.default_rng(7)
    links = tuple(DHLink("R", a=rng.uniform(0.05, 0.4), d=rng.uniform(-0.2, 0.2), alpha=rng.uniform(-3, 3))
                  for _ in range(6))
    with warnings.catch_warnings():
        warnings.simplefilter("error", robokit.RobokitWarning)
        kind = robokit.ik_analytic_kind(robokit.load(DHTable("random", "standard", links)))
    assert kind.method == "general 6R" and "exactly parallel" not in kind.reason
