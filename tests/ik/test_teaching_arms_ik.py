"""Inverse kinematics of the arms courses and student teams own, loaded from their makers' files
(tests/data/<maker>/SOURCE): the Interbotix WidowX 250 6DOF and ViperX 300 6DOF (spherical wrists) and the
myCobot 280 M5 (a UR-type arm) in closed form; the PincherX 100, the OpenManipulator-X (4 joints) and the
ViperX 300 without its gripper (5 joints), which have none here, by ``solve_ik``.

Poses are computed by Pinocchio on the ``xacro`` program's expansion of the maker's file (the URDF file
itself for the myCobot), not through robokit. A closed form's every solution must reach the pose there to
1e-9, the generating configuration must be among them and every distinct solution robokit's compiled
Levenberg–Marquardt solver finds from 200 uniform starts must be returned. A 4- or 5-joint arm gets a
refusal that says so, never a wrong answer; ``solve_ik`` reaches random reachable poses inside the limits
and reports failure for an orientation the arm cannot take.
"""
import warnings
from pathlib import Path

import numpy as np
import pytest

import robokit
from robokit.ik import ik_analytic, ik_analytic_kind
from ik_sweep import angle_dist, sweep
from xacro_reference import pinocchio_fk, xacro_urdfs

DATA = Path(__file__).resolve().parents[1] / "data"
XS = "interbotix_xsarm_descriptions/urdf/"
OMX = "open_manipulator_description/urdf/open_manipulator_x/open_manipulator_x.urdf.xacro"
COBOT = "mycobot_description/urdf/mycobot_280_m5/mycobot_280_m5.urdf"
#: label -> (maker, file, xacro arguments or None for a URDF file, closed form or None)
ARMS = {
    "WidowX 250 6DOF": ("interbotix", XS + "wx250s.urdf.xacro", {}, "spherical wrist"),
    "ViperX 300 6DOF, named right": ("interbotix", XS + "vx300s.urdf.xacro", {"robot_name": "right"},
                                     "spherical wrist"),
    "myCobot 280 M5": ("elephant", COBOT, None, "three parallel axes"),
    "PincherX 100": ("interbotix", XS + "px100.urdf.xacro", {}, None),
    "OpenManipulator-X": ("robotis", OMX, {}, None),
    "ViperX 300 6DOF without gripper": ("interbotix", XS + "vx300s.urdf.xacro", {"use_gripper": "false"}, None),
}
CLOSED = [k for k, v in ARMS.items() if v[3]]
NUMERIC = [k for k, v in ARMS.items() if not v[3]]


@pytest.fixture(scope="module")
def reference():
    urdfs = xacro_urdfs({k: (DATA / m, f, a) for k, (m, f, a, _) in ARMS.items() if a is not None})
    urdfs.update({k: (DATA / m / f).read_text() for k, (m, f, a, _) in ARMS.items() if a is None})
    return urdfs


def load(label):
    maker, rel, args, _ = ARMS[label]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # no meshes here, locked fingers, friction
        return robokit.load(DATA / maker / rel, xacro_args=args or None)


@pytest.mark.parametrize("label", CLOSED)
def test_every_closed_form_solution_exact_and_none_missed(label, reference):
    robot = load(label)
    assert ik_analytic_kind(robot).method == ARMS[label][3]
    fk, lo, hi = pinocchio_fk(reference[label], robot)
    rng = np.random.default_rng(3)
    roots = 0
    for i in range(15):
        q = rng.uniform(lo, hi)
        T = fk(q)
        sols = ik_analytic(robot, T)
        for s in sols:
            assert np.abs(fk(s.q) - T).max() < 1e-9, s.label
            assert s.within_limits == bool(np.all((s.q >= lo) & (s.q <= hi)))
        assert sols and min(angle_dist(s.q, q) for s in sols) < 1e-7, "the generating configuration is missing"
        found = sweep(robot, T, 200, i)
        for f in found:
            assert min(angle_dist(f, s.q) for s in sols) < 1e-6, f"numerical solution {f} not returned"
        roots += len(found)
    assert roots >= 2 * 15  # the sweep found roots: the check is not empty


@pytest.mark.parametrize("label", NUMERIC)
def test_no_closed_form_is_a_clear_refusal(label):
    robot = load(label)
    kind = ik_analytic_kind(robot)
    assert kind.method is None and f"{robot.n} joints" in kind.reason
    with pytest.raises(robokit.InputError, match=f"{robot.n} joints.*solve_ik"):
        ik_analytic(robot, robot.frame_pose(np.zeros(robot.n)))


@pytest.mark.parametrize("label", NUMERIC)
def test_solve_ik_reaches_reachable_poses_and_says_when_it_cannot(label, reference):
    robot = load(label)
    fk, lo, hi = pinocchio_fk(reference[label], robot)
    rng = np.random.default_rng(5)
    for i in range(15):
        T = fk(rng.uniform(lo, hi))
        res = robokit.solve_ik(robot, T, rng=i)
        assert res.success and np.abs(fk(res.q) - T).max() < 1e-9
        assert np.all((res.q >= lo) & (res.q <= hi))
        p = fk(rng.uniform(lo, hi))[:3, 3]
        res = robokit.solve_ik(robot, p, position_only=True, rng=i)
        assert res.success and np.abs(fk(res.q)[:3, 3] - p).max() < 1e-9
    # the reached pose turned 0.5 rad about the tool's x axis: an orientation these arms cannot take
    c, s = np.cos(0.5), np.sin(0.5)
    for i in range(4):
        T = fk(rng.uniform(lo, hi))
        T[:3, :3] = T[:3, :3] @ np.array([[1, 0, 0], [0, c, -s], [0, s, c]])
        res = robokit.solve_ik(robot, T, rng=i, max_restarts=3)
        assert not res.success and np.all((res.q >= lo) & (res.q <= hi))
