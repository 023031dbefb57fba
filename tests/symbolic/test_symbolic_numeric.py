"""Symbolic FK, Jacobians and dynamics of the shipped twolink and rrr models, lambdified, against
the numeric course code and Pinocchio at random configurations (1e-9)."""
import numpy as np
import pytest

import robokit as rk
from robokit.symbolic import SymbolicArm


@pytest.fixture(scope="module", params=["twolink", "rrr"])
def case(request):
    robot = rk.load(request.param)
    arm = SymbolicArm.from_dh_table(robot.dh)
    links = robot.dh.links
    inertias = [l.inertia_matrix for l in links]
    # numeric entries: simplification only costs time here (the lecture-form tests cover it)
    dyn = arm.dynamics([l.mass for l in links], [l.com for l in links], inertias, gravity=robot.gravity,
                       simplify=False)
    return robot, arm, dyn


def test_fk_and_jacobians(case):
    robot, arm, _ = case
    fk = arm.lambdify(arm.fk(simplify=False))
    Jb_base = arm.lambdify(arm.jacobian("base", simplify=False))
    Jb_tool = arm.lambdify(arm.jacobian("tool", simplify=False))
    rng = np.random.default_rng(0)
    for _ in range(50):
        q = robot.random_configuration(rng)
        T = robot.frame_pose(q)
        assert np.abs(fk(q) - T).max() < 1e-9
        assert np.abs(fk(q) - rk.fkin_space(robot.poe.M, robot.poe.Slist, q)).max() < 1e-9
        assert np.abs(Jb_base(q) - robot.jacobian(q, reference="local_world_aligned")).max() < 1e-9
        assert np.abs(Jb_tool(q) - robot.jacobian(q, reference="local")).max() < 1e-9


def test_dynamics(case):
    robot, arm, dyn = case
    M = arm.lambdify(dyn.M)
    V = arm.lambdify(dyn.V)
    G = arm.lambdify(dyn.G)
    p = robot.poe
    rng = np.random.default_rng(1)
    for _ in range(50):
        q, dq = robot.random_configuration(rng), rng.normal(size=robot.n)
        assert np.abs(M(q) - robot.crba(q)).max() < 1e-9
        assert np.abs(M(q) - rk.mass_matrix(q, p.Mlist, p.Glist, p.Slist)).max() < 1e-9
        assert np.abs(G(q).ravel() - robot.gravity_torques(q)).max() < 1e-9
        c_ref = robot.nonlinear_effects(q, dq) - robot.gravity_torques(q)
        assert np.abs(V(q, dq).ravel() - c_ref).max() < 1e-9
        assert np.abs(V(q, dq).ravel() - rk.vel_quadratic_forces(q, dq, p.Mlist, p.Glist, p.Slist)).max() < 1e-9
