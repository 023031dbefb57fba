"""The typed ik -> codegen contract (robokit.ik.closed_form_constants): frozen records, and numbers
that mean what they say, checked against Pinocchio's joint axes (not against the solver)."""
import dataclasses

import numpy as np
import pinocchio as pin
import pytest

import robokit
from robokit.ik import ClosedFormConstants, closed_form_constants
from robokit.ik.parallel_axes import ParallelAxesConstants
from robokit.ik.pieper import PieperConstants


def _axis_distances(robot, q, W, joints):
    """Distance (m) of the base-frame point W from each joint's axis at q, from Pinocchio's
    world-frame Jacobian: column (v₀, ω) with v₀ = −ω × r for a point r on the axis."""
    model, data = robot.model, robot.data
    qp = q if model.nq == model.nv else robot.q_pin(q)
    pin.computeJointJacobians(model, data, qp)
    J = pin.getJointJacobian(model, data, model.njoints - 1, pin.ReferenceFrame.WORLD)
    return [float(np.linalg.norm(np.cross(J[3:, j], W) + J[:3, j])) for j in joints]


@pytest.mark.parametrize("name, kind, joints", [("puma560", PieperConstants, (3, 4, 5)),
                                                ("ur5", ParallelAxesConstants, (4, 5))])
def test_wrist_point_lies_on_the_axes_it_names(name, kind, joints):
    robot = robokit.load(name)
    c = closed_form_constants(robot)
    assert isinstance(c, ClosedFormConstants) and isinstance(c.solver, kind) and not c.reversed
    tool_inv = np.eye(4) if c.tool_inv is None else np.array(c.tool_inv)
    rng = np.random.default_rng(4)
    for _ in range(5):
        q = robot.random_configuration(rng)
        W = (robot.frame_pose(q) @ tool_inv @ np.r_[c.solver.w6, 1.0])[:3]  # W = T · tool′⁻¹ · ⁶W
        assert max(_axis_distances(robot, q, W, joints)) < 1e-9


def test_records_are_frozen_and_say_why_not():
    c = closed_form_constants(robokit.load("puma560"))
    with pytest.raises(dataclasses.FrozenInstanceError):
        c.method = "x"
    with pytest.raises(dataclasses.FrozenInstanceError):
        c.solver.deg = 4
    panda = closed_form_constants(robokit.load("panda"))
    assert panda.method is None and "7 joints" in panda.reason and panda.solver is None


def test_kernel_packing_reads_the_record():
    """The kernel's arrays are the record's numbers (one source for the kernel and the C)."""
    ik = robokit.ik.analytic_ik(robokit.load("puma560"))
    c = ik.solver.constants()
    ci, cf, C = ik.solver.kernel_constants()
    assert cf[0:6].tolist() == list(c.th0) and cf[29:32].tolist() == list(c.w6)
    assert C[: len(c.C), : c.deg + 1].tolist() == [list(r) for r in c.C]


def test_general_6r_record_is_typed_frozen_and_means_what_it_says():
    """The general 6R method's constants are a frozen record (no mapping): its chain, rebuilt here
    from the DH formula Z(θ, d) X(a, α), reaches Pinocchio's pose; codegen reads that record."""
    import math

    from robokit.codegen._solver_constants import ik_constants
    from robokit.ik import GeneralSixRConstants, GeneralSixRReading

    rng = np.random.default_rng(3)
    table = robokit.DHTable("g", "standard", tuple(robokit.DHLink(
        "R", a=rng.uniform(-0.5, 0.5), alpha=rng.uniform(-3, 3), d=rng.uniform(-0.5, 0.5)) for _ in range(6)))
    robot = robokit.load(table)
    c = closed_form_constants(robot)
    g = c.solver
    assert c.method == "general 6R" and isinstance(g, GeneralSixRConstants)
    assert len(g.readings) == 4 and all(isinstance(r, GeneralSixRReading) for r in g.readings)
    with pytest.raises(dataclasses.FrozenInstanceError):
        g.scale = 2.0
    with pytest.raises(dataclasses.FrozenInstanceError):
        g.readings[0].deflate = 0
    hash(g)  # immutable all the way down (tuples)
    assert ik_constants(robot).general == g  # what the C emitter reads

    def Z(t, d):
        return np.array([[math.cos(t), -math.sin(t), 0, 0], [math.sin(t), math.cos(t), 0, 0], [0, 0, 1, d],
                         [0, 0, 0, 1]])

    def X(a, al):
        return np.array([[1, 0, 0, a], [0, math.cos(al), -math.sin(al), 0], [0, math.sin(al), math.cos(al), 0],
                         [0, 0, 0, 1]])

    base_inv = np.eye(4) if c.base_inv is None else np.array(c.base_inv)
    tool_inv = np.eye(4) if c.tool_inv is None else np.array(c.tool_inv)
    sign = [-1.0 if f else 1.0 for f in (c.flip or [False] * 6)]
    assert not c.reversed
    for _ in range(5):
        q = rng.uniform(-np.pi, np.pi, 6)
        T = np.eye(4)
        for i in range(6):
            T = T @ Z(g.th0[i] + sign[i] * q[i], g.d[i] * g.scale)
            if i < 5:
                T = T @ X(g.a[i] * g.scale, g.alpha[i])
        assert np.abs(T - base_inv @ robot.frame_pose(q) @ tool_inv).max() < 1e-12
