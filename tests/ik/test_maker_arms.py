"""ik_analytic on arms as their makers publish them (tests/data/ufactory, see its SOURCE): the xArm
Lite 6 from UFACTORY's ROS 2 xacro and from MuJoCo Menagerie's MJCF, and the xArm 6 from the xacro.

Their right angles are written rounded (rpy 1.5708, quaternions to six digits): the Lite 6's axes 2
and 3 are 7.3e-6 rad from parallel, so the DH table robokit extracts has d₂ = d₃ = 27 km; the
xArm 6's twists are 3.7e-6 rad from 90°. Checked against independent references at random
configurations: every solution reaches the pose through Pinocchio (1e-9), the generating
configuration is among the solutions, and every distinct solution that robokit's compiled
Levenberg–Marquardt solver finds from 200 uniform starts (joint limits ignored) is returned.
"""
from pathlib import Path
import warnings

import numpy as np
import pytest

import robokit
from robokit.ik import ik_analytic, ik_analytic_kind
from ik_sweep import angle_dist, sweep

DATA = Path(__file__).resolve().parents[1] / "data" / "ufactory"


def load(name):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # e.g. the URDFs' zero inertias
        return robokit.load(DATA / name)


def check_pose(robot, q, seeds=200, rng=0):
    T = robot.frame_pose(q)
    sols = ik_analytic(robot, T)
    for s in sols:
        assert np.abs(robot.frame_pose(s.q) - T).max() < 1e-9, s.label
    assert sols and min(angle_dist(s.q, q) for s in sols) < 1e-7, "the generating configuration is missing"
    found = sweep(robot, T, seeds, rng)
    assert found, "the numerical sweep found nothing: the check would be empty"
    for f in found:
        assert min(angle_dist(f, s.q) for s in sols) < 1e-6, f"numerical solution {f} not returned"
    return sols


@pytest.mark.parametrize("name", ["lite6.urdf", "lite6.xml", "xarm6.urdf"])
def test_every_solution_exact_and_none_missed(name):
    """Before: the Lite 6's URDF was taken for an exact spherical wrist (its tolerances scaled by
    the DH table's 27 km) although axes 4–6 miss by 1e-7 m, and the MJCF's exact spherical wrist
    lost precision in the position quadratic (d₂² = 7e8 m² cancelling): solutions 1e-6 m off the
    pose at every configuration. The xArm 6 got no solution at all at 4 of 30 poses (the general 6R
    method's best reading has a 4-fold root at every pose there, its QR iteration did not converge
    and the other readings were not tried)."""
    robot = load(name)
    assert robot.n == 6
    rng = np.random.default_rng(0)
    for i in range(30):
        check_pose(robot, robot.random_configuration(rng), rng=i)


def test_lite6_urdf_wrist_is_not_taken_for_spherical():
    """The xacro's Lite 6: axes 4–6 pass 1.1e-7 m apart, not within the 1e-9 m of an exact spherical
    wrist (the arm is 0.8 m long), so the nominal structure's closed form finishes on the arm's own
    kinematics; the MJCF's wrist axes do meet (to 1e-16 m)."""
    urdf, mjcf = load("lite6.urdf"), load("lite6.xml")
    assert ik_analytic_kind(urdf).method == "calibrated spherical wrist"
    # the MJCF's wrist is exact, but its DH table's offsets (27 km) are too large for the closed form's
    # arithmetic near the elbow singularity: the same path (test_lite6_mjcf_near_its_elbow_singularity)
    kind = ik_analytic_kind(mjcf)
    assert kind.method == "calibrated spherical wrist" and "too large for its closed form's arithmetic" in kind.reason
    # the wrist's miss, measured on Pinocchio's joint axes at q = 0 (independent of the DH table):
    # the largest distance of axes 4–6 from the point nearest all three (least squares)
    S = urdf.poe.Slist
    lines = [(np.cross(S[:3, j], S[3:, j]), S[:3, j]) for j in (3, 4, 5)]  # (point on the axis, direction)
    projs = [np.eye(3) - np.outer(u, u) for _, u in lines]
    x = np.linalg.solve(sum(projs), sum(P @ p for P, (p, _) in zip(projs, lines)))
    miss = max(np.linalg.norm(P @ (x - p)) for P, (p, _) in zip(projs, lines))
    assert 1e-8 < miss < 1e-6


def test_xarm6_near_its_wrist_singularity():
    """q₅ within 1e-3 rad of 0 (axes 4 and 6 nearly lined up): still exact, the generating
    configuration returned, none of the sweep's solutions missed."""
    robot = load("xarm6.urdf")
    rng = np.random.default_rng(7)
    for k in range(6):
        q = robot.random_configuration(rng)
        q[4] = rng.uniform(-1e-3, 1e-3)
        check_pose(robot, q, rng=k)


def test_lite6_mjcf_near_its_elbow_singularity():
    """The MJCF's exact spherical wrist with axes 2 and 3 7.3e-6 rad from parallel: its DH table's
    offsets are 27 km, and the special closed form's roots cancel d₂² ≈ 7e8 m². Within 1e-3 rad of the
    elbow singularity (θ₃ where the Jacobian's smallest singular value is least, on a 0.5° grid) roots
    were lost at 4 of 15 poses and the generating configuration at 6. Such an arm is now solved as a
    nearly special one (closed_form.ILL_DH): exact, the generating configuration among the solutions,
    none of the sweep's missed."""
    robot = load("lite6.xml")
    rng = np.random.default_rng(3)
    grid = np.linspace(-np.pi, np.pi, 721)
    roots = 0
    for k in range(15):
        q = robot.random_configuration(rng)
        sigma = [np.linalg.svd(robot.jacobian(np.r_[q[:2], x, q[3:]]), compute_uv=False)[-1] for x in grid]
        q[2] = grid[int(np.argmin(sigma))] + rng.uniform(-1e-3, 1e-3)
        T = robot.frame_pose(q)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", robokit.RobokitWarning)  # (near singular: the search's warning)
            sols = ik_analytic(robot, T)
        for s in sols:
            assert np.abs(robot.frame_pose(s.q) - T).max() < 1e-9, s.label
        assert min(angle_dist(s.q, q) for s in sols) < 1e-7, "the generating configuration is missing"
        found = sweep(robot, T, 200, k)  # (near singular the sweep's starts may converge nowhere)
        for f in found:
            assert min(angle_dist(f, s.q) for s in sols) < 1e-6, f"numerical solution {f} not returned"
        roots += len(found)
    assert roots >= 15  # the sweep found roots at most poses: the check is not empty
