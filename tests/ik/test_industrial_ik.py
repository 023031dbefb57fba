"""ik_analytic on industrial arms as ROS-Industrial publishes them (tests/data/<maker>/SOURCE): KUKA KR 6
R900 sixx and KR 210 L150, ABB IRB 2400 and IRB 6640-185/280, FANUC LR Mate 200iD, Stäubli RX160
(spherical wrists, solved by Pieper's method) and the FANUC M-430iA/2P (wrist axes that do not meet:
the general 6R method).

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
ARMS = {
    "KUKA KR 6 R900 sixx": ("kuka", "kuka_kr6_support/urdf/kr6r900sixx.xacro", "spherical wrist"),
    "KUKA KR 210 L150": ("kuka", "kuka_kr210_support/urdf/kr210l150.xacro", "spherical wrist"),
    "ABB IRB 2400": ("abb", "abb_irb2400_support/urdf/irb2400.xacro", "spherical wrist"),
    "ABB IRB 6640-185/280": ("abb", "abb_irb6640_support/urdf/irb6640_185_280.xacro", "spherical wrist"),
    "FANUC LR Mate 200iD": ("fanuc", "fanuc_lrmate200id_support/urdf/lrmate200id.xacro", "spherical wrist"),
    "FANUC M-430iA/2P": ("fanuc", "fanuc_m430ia_support/urdf/m430ia2p.xacro", "general 6R"),
    "Staubli RX160": ("staubli", "staubli_rx160_support/urdf/rx160.xacro", "spherical wrist"),
}
POSES = 50


@pytest.fixture(scope="module")
def reference():
    return xacro_urdfs({k: (DATA / m, f) for k, (m, f, _) in ARMS.items()})


@pytest.mark.parametrize("label", list(ARMS))
def test_every_solution_exact_and_none_missed(label, reference):
    maker, rel, kind = ARMS[label]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # no meshes here, no inertias in most of these files
        robot = robokit.load(DATA / maker / rel)
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


@pytest.mark.parametrize("label", ["KUKA KR 210 L150", "FANUC LR Mate 200iD"])
def test_near_the_wrist_singularity_still_exact(label, reference):
    """θ₅ within 1e-10..1e-6 rad of the wrist singularity (axes 4 and 6 nearly lined up). Before, θ₄ and
    θ₆ were each taken from a vector of length ~θ₅ (each off by its rounding / θ₅) and |sin θ₅| from
    1 − cos² θ₅: solutions up to 2e-6 off the pose (2e-16 / θ₅), not marked degenerate. Now θ₆ is what θ₄
    and θ₅ leave of the whole rotation and |sin θ₅| comes from the wrist direction across axis 4."""
    maker, rel, _ = ARMS[label]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        robot = robokit.load(DATA / maker / rel)
    fk, lo, hi = pinocchio_fk(reference[label], robot)
    rng = np.random.default_rng(9)
    for q5 in (3e-10, 1e-9, 3e-9, 1e-8, 3e-8, 1e-7, 1e-6):
        for _ in range(6):
            q = rng.uniform(lo, hi)
            q[4] = q5 * rng.choice([-1.0, 1.0])
            T = fk(q)
            sols = ik_analytic(robot, T)
            assert sols
            for s in sols:
                assert np.abs(fk(s.q) - T).max() < 1e-9, (q5, s.label)
