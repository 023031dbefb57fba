"""ik_analytic on industrial arms as their makers publish them for ROS 2 (tests/data/<maker>/SOURCE): the
Techman TM5-900 (UR-type: three parallel axes), the DENSO VS-060 (spherical wrist, Pieper's method) and
the Dobot ME6 (UR-type, but its right angles written 1.5708: the calibrated three parallel axes
method), loaded from the makers' xacro
files with the arguments a user passes.

At random configurations within the file's limits, the pose is computed by Pinocchio on the ``xacro``
program's own expansion of the file (not through robokit); every solution must reach it to 1e-9 there,
the generating configuration must be among them, and every distinct solution that robokit's compiled
Levenberg–Marquardt solver finds from 300 uniform starts (joint limits ignored) must be returned.
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
DENSO = "denso_robot_descriptions/urdf/denso_robot.urdf.xacro"
ARMS = {
    "Techman TM5-900": ("techman", "tm_description/xacro/tm5-900.urdf.xacro", {}, "three parallel axes"),
    "DENSO VS-060": ("denso", DENSO, {"model": "vs060"}, "spherical wrist"),
    "Dobot ME6": ("dobot", "cra_description/urdf/me6_robot.xacro", {}, "calibrated three parallel axes"),
}
POSES = 15


@pytest.fixture(scope="module")
def reference():
    return xacro_urdfs({k: (DATA / m, f, a) for k, (m, f, a, _) in ARMS.items()})


@pytest.mark.parametrize("label", list(ARMS))
def test_every_solution_exact_and_none_missed(label, reference):
    maker, rel, args, kind = ARMS[label]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # no meshes here
        robot = robokit.load(DATA / maker / rel, xacro_args=args or None)
    assert ik_analytic_kind(robot).method == kind
    fk, lo, hi = pinocchio_fk(reference[label], robot)
    rng = np.random.default_rng(2)
    roots = 0
    for i in range(POSES):
        q = rng.uniform(lo, hi)
        T = fk(q)
        sols = ik_analytic(robot, T)
        for s in sols:
            assert np.abs(fk(s.q) - T).max() < 1e-9, s.label
        assert sols and min(angle_dist(s.q, q) for s in sols) < 1e-7, "the generating configuration is missing"
        found = sweep(robot, T, 300, i)
        for f in found:
            assert min(angle_dist(f, s.q) for s in sols) < 1e-6, f"numerical solution {f} not returned"
        roots += len(found)
    assert roots >= 4 * POSES  # the sweep found roots: the check is not empty


def test_a_reachable_pose_at_the_wrist_singularity_is_never_answered_with_silence(reference):
    """The ME6 at θ₅ = 0 (axes 4 and 6 in line: the nominal structure's solutions form a continuum). Its
    axes 5 and 6 miss by 8.6e-8 m, and at such poses the calibrated closed form gives no start and the
    general 6R method no root: ik_analytic returned [] for a pose the arm reaches (made from q), without a
    word (3 of 20 random poses at θ₅ = 0, 1 of 20 at 1e-8). Until those poses are solved, an empty answer
    at a pose within reach says so; every solution returned reaches T."""
    maker, rel, args, _ = ARMS["Dobot ME6"]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        robot = robokit.load(DATA / maker / rel, xacro_args=args or None)
    fk, lo, hi = pinocchio_fk(reference["Dobot ME6"], robot)
    rng = np.random.default_rng(9)
    empty = 0
    for _ in range(20):
        q = rng.uniform(lo, hi)
        q[4] = 0.0
        T = fk(q)  # reached, by q
        with warnings.catch_warnings(record=True) as said:
            warnings.simplefilter("always")
            sols = ik_analytic(robot, T)
        for s in sols:
            assert np.abs(fk(s.q) - T).max() < 1e-9, s.label
        if not sols:
            empty += 1
            assert any("no solution at this pose, which lies within the arm's reach" in str(w.message)
                       for w in said), [str(w.message) for w in said]
    assert empty  # such poses exist here: the check is not empty
