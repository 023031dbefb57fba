"""ik_analytic on collaborative arms as their makers publish them (tests/data/kinova/ros_kortex/SOURCE,
tests/data/niryo/SOURCE): the Kinova Gen3 6-DoF (axes written with rounded right angles, wrist axes 0.18 mm
from a common point: the calibrated spherical-wrist closed form) and the Niryo Ned2 (wrist axes 6.2 mm
apart: the general 6R method), loaded from the makers' xacro files with their arguments; the Gen3 7-DoF,
which has no closed form.

At random configurations within the file's limits (continuous joints over a turn), the pose is computed by
Pinocchio on the ``xacro`` program's own expansion of the file (not through robokit); every solution must
reach it to 1e-9 there, the generating configuration must be among them, and every distinct solution that
robokit's compiled Levenberg–Marquardt solver finds from 300 uniform starts (joint limits ignored) must be
returned.
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
KORTEX = DATA / "kinova" / "ros_kortex"
ARMS = {  # label -> (packages folder, xacro file, xacro arguments, closed form)
    "Gen3 6-DoF": (KORTEX, "kortex_description/robots/gen3.xacro", {"dof": "6", "vision": "false"},
                   "calibrated spherical wrist"),
    "Ned2": (DATA / "niryo", "niryo_robot_description/urdf/ned2/niryo_ned2.urdf.xacro", {}, "general 6R"),
}
POSES = 30


@pytest.fixture(scope="module")
def reference():
    return xacro_urdfs({k: (m, f, a) for k, (m, f, a, _) in ARMS.items()})


def load(folder, rel, args):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # no meshes here
        return robokit.load(folder / rel, xacro_args=args or None)


@pytest.mark.parametrize("label", list(ARMS))
def test_every_solution_exact_and_none_missed(label, reference):
    folder, rel, args, kind = ARMS[label]
    robot = load(folder, rel, args)
    assert ik_analytic_kind(robot).method == kind
    fk, lo, hi = pinocchio_fk(reference[label], robot)
    lo, hi = np.where(np.isfinite(lo), lo, -np.pi), np.where(np.isfinite(hi), hi, np.pi)
    rng = np.random.default_rng(2)
    roots = 0
    for i in range(POSES):
        q = rng.uniform(lo, hi)
        T = fk(q)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")  # a pose near a singularity is said; the solutions are checked here
            sols = ik_analytic(robot, T)
        for s in sols:
            assert np.abs(fk(s.q) - T).max() < 1e-9, s.label
        assert sols and min(angle_dist(s.q, q) for s in sols) < 1e-7, "the generating configuration is missing"
        found = sweep(robot, T, 300, i)
        for f in found:
            assert min(angle_dist(f, s.q) for s in sols) < 1e-6, f"numerical solution {f} not returned"
        roots += len(found)
    assert roots >= 4 * POSES  # the sweep found roots: the check is not empty


def test_the_seven_joint_gen3_has_no_closed_form_and_says_why():
    robot = load(KORTEX, "kortex_description/robots/gen3.xacro", {"vision": "false"})
    kind = ik_analytic_kind(robot)
    assert kind.method is None and "7 joints" in kind.reason and "solve_ik" in kind.reason
    with pytest.raises(robokit.InputError, match="no closed-form inverse kinematics: the arm has 7 joints"):
        ik_analytic(robot, robot.frame_pose(np.zeros(7)))
