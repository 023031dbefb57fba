"""The lecture's worked tables: every step of the outward velocity iteration (Lecture 6) and of
Craig's Newton–Euler (Lecture 7), checked against Pinocchio on the generated URDF's ``dh_<i>``
frames (velocities, accelerations, the force each link receives from its parent); plus the L4
homework's common-normal twist and the elementary rotations."""
import importlib.util
import math
import pathlib

import numpy as np
import pinocchio as pin
import pytest
from hypothesis import given, settings, strategies as st

import robokit as rk
from robokit.dynamics import dh_inverse_dynamics
from robokit.kinematics import dh_velocity_trace
from robokit.spatial import common_normal, elementary_rotation

_spec = importlib.util.spec_from_file_location(
    "desc_conftest", pathlib.Path(__file__).parents[1] / "description" / "conftest.py")
_mod = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(_mod)
make_random_dh_table = _mod.make_random_dh_table

CASES = [("standard", ()), ("modified", ()), ("standard", (1, 3)), ("modified", (0, 4))]


def _pin_state(robot, q, dq, ddq, gravity):
    model, data = robot.model, robot.model.createData()
    model.gravity.linear = np.asarray(gravity, float)
    qp = robot.q_pin(q)
    pin.rnea(model, data, qp, dq, ddq)  # leaves the joint forces data.f
    pin.forwardKinematics(model, data, qp, dq, ddq)  # v, a (gravity-free) for the frame queries
    pin.updateFramePlacements(model, data)
    return model, data


@pytest.mark.parametrize("convention,prismatic", CASES)
def test_velocity_trace_matches_pinocchio_frame_velocities(convention, prismatic):
    rng = np.random.default_rng(11)
    table = make_random_dh_table(rng, 5, convention, prismatic=prismatic)
    robot = rk.load(table)
    for _ in range(5):
        q, dq = robot.random_configuration(rng), rng.normal(size=5)
        tr = dh_velocity_trace(table, q, dq)
        assert tr.omega.shape == tr.v.shape == (6, 3)
        model, data = _pin_state(robot, q, dq, np.zeros(5), np.zeros(3))
        for i in range(6):
            fid = model.getFrameId(f"dh_{i}")
            V = pin.getFrameVelocity(model, data, fid, pin.LOCAL)
            assert np.abs(tr.omega[i] - V.angular).max() < 1e-12
            assert np.abs(tr.v[i] - V.linear).max() < 1e-12


@pytest.mark.parametrize("convention,prismatic", CASES)
def test_dynamics_trace_matches_pinocchio_step_by_step(convention, prismatic):
    rng = np.random.default_rng(12)
    n = 5
    table = make_random_dh_table(rng, n, convention, prismatic=prismatic)
    robot = rk.load(table)
    g = np.array([0.3, -0.5, -9.81])
    for _ in range(4):
        q, dq, ddq = robot.random_configuration(rng), rng.normal(size=n), rng.normal(size=n)
        tau, tr = dh_inverse_dynamics(table, q, dq, ddq, gravity=g, trace=True)
        assert np.abs(tau - dh_inverse_dynamics(table, q, dq, ddq, gravity=g, trace=False)).max() <= 1e-12 * max(1.0, np.abs(tau).max())
        model, data = _pin_state(robot, q, dq, ddq, g)
        assert np.abs(tau - data.tau).max() <= 1e-9 * max(1.0, np.abs(tau).max())
        for i in range(n):
            fid = model.getFrameId(f"dh_{i + 1}")
            oMf = data.oMf[fid]
            R0 = oMf.rotation
            a = pin.getFrameClassicalAcceleration(model, data, fid, pin.LOCAL)
            assert np.abs(tr.omega[i] - pin.getFrameVelocity(model, data, fid, pin.LOCAL).angular).max() < 1e-12
            assert np.abs(tr.domega[i] - a.angular).max() < 1e-10
            assert np.abs(tr.dv[i] - (a.linear - R0.T @ g)).max() < 1e-10  # v̇₀ = −g
            # the centre of mass: a point of frame {i}
            pc = np.asarray(table.links[i].com, float)
            expect = a.linear - R0.T @ g + np.cross(tr.domega[i], pc) + np.cross(tr.omega[i], np.cross(tr.omega[i], pc))
            assert np.abs(tr.dv_com[i] - expect).max() < 1e-10
            assert np.abs(tr.F[i] - table.links[i].mass * tr.dv_com[i]).max() < 1e-10
            # what link i receives from link i-1: Pinocchio's joint force, moved to frame {i}
            j = model.getJointId(f"joint_{i + 1}")
            f_dh = (oMf.inverse() * data.oMi[j]).act(data.f[j])
            assert np.abs(tr.f[i] - f_dh.linear).max() < 1e-9
            assert np.abs(tr.n[i] - f_dh.angular).max() < 1e-9


def test_dynamics_trace_with_tip_wrench_and_print():
    table = rk.load("puma560").dh
    rng = np.random.default_rng(3)
    q, dq, ddq, F = rng.normal(size=(4, 6))[:, :6]
    F = rng.normal(size=6)
    tau, tr = dh_inverse_dynamics(table, q, dq, ddq, F_tip=F, trace=True)
    assert np.abs(tau - dh_inverse_dynamics(table, q, dq, ddq, F_tip=F, trace=False)).max() <= 1e-12 * max(1.0, np.abs(tau).max())
    text = str(tr)
    assert text.count("\n") == 1 + 1 + 6 * 8 + 0 and "τ6 =" in text
    for sym in ("ω_i", "ω̇_i", "v̇_i", "v̇_Ci", "F_i", "N_i", "f_i", "n_i"):
        assert sym in text


def test_velocity_trace_twolink_homework_numbers():
    # a planar 2R arm, a1 = a2 = 1: at q = (0, π/2), q̇ = (1, 1), frame {2}'s origin (the hand) moves at
    # v = J q̇ with J = [[-s1 - s12, -s12], [c1 + c12, c12]] = [[-1, -1], [1, 0]]: v_base = (-2, 1)
    from robokit.description.dh import DHLink, DHTable

    t = DHTable("planar", "standard", (DHLink("R", 1.0, 0.0, 0.0, 0.0), DHLink("R", 1.0, 0.0, 0.0, 0.0)))
    tr = dh_velocity_trace(t, [0.0, math.pi / 2], [1.0, 1.0])
    R02 = elementary_rotation("z", math.pi / 2)
    assert np.allclose(R02 @ tr.v[2], [-2.0, 1.0, 0.0], atol=1e-12)
    assert np.allclose(tr.omega[2], [0, 0, 2.0]) and np.allclose(tr.v[1], [0, 1.0, 0])


@settings(max_examples=60, deadline=None, derandomize=True)
@given(st.lists(st.floats(-1, 1), min_size=12, max_size=12))
def test_common_normal_twist_is_the_dh_alpha(x):
    p1, z1, p2, z2 = (np.array(x[k:k + 3]) for k in range(0, 12, 3))
    if min(np.linalg.norm(z1), np.linalg.norm(z2)) < 1e-3:
        return
    c = common_normal(p1, z1, p2, z2)
    assert -math.pi < c.alpha <= math.pi
    # rotating ẑ₁ by α about the normal's direction gives ẑ₂ (Rodrigues, independent of the code)
    k, u1, u2 = c.direction, z1 / np.linalg.norm(z1), z2 / np.linalg.norm(z2)
    rot = rk.matrix_exp_3(rk.vec_to_so3(k * c.alpha))
    assert np.abs(rot @ u1 - u2).max() < 1e-7


def test_common_normal_twist_special_cases():
    assert common_normal([0, 0, 0], [0, 0, 1], [1, 0, 0], [0, 0, 1]).alpha == 0.0          # parallel
    assert common_normal([0, 0, 0], [0, 0, 1], [1, 0, 0], [0, 0, -1]).alpha == math.pi     # antiparallel
    assert math.isclose(common_normal([0, 0, 0], [0, 0, 1], [0, 0, 0], [0, 1, 0]).alpha, -math.pi / 2) \
        or math.isclose(common_normal([0, 0, 0], [0, 0, 1], [0, 0, 0], [0, 1, 0]).alpha, math.pi / 2)


@pytest.mark.parametrize("axis,index", [("x", 0), ("y", 1), ("z", 2), (0, 0), (1, 1), (2, 2), (np.int64(2), 2)])
def test_elementary_rotation_axes(axis, index):
    a = 0.7
    R = elementary_rotation(axis, a)
    e = np.eye(3)[index]
    assert np.allclose(R @ e, e)  # the axis is fixed
    assert np.allclose(R, rk.matrix_exp_3(rk.vec_to_so3(e * a)), atol=1e-15)


@pytest.mark.parametrize("bad", [3, -1, "q", "X", "xy", True, 1.0, None, [0]])
def test_elementary_rotation_refuses_other_axes(bad):
    with pytest.raises(ValueError, match="axis"):
        elementary_rotation(bad, 0.1)


def test_the_contract_form_returns_the_torques_and_the_steps():
    """``tau, trace = dh_inverse_dynamics(table, q, dq, ddq)``: the default is ``trace=True`` (it was False, and
    that call then failed to unpack, or on a two-joint arm unpacked the torques silently). The torques against
    Pinocchio's ``rnea`` on the robot built from the table; ``trace=False`` gives the same torques alone."""
    import inspect

    assert inspect.signature(dh_inverse_dynamics).parameters["trace"].default is True
    rng = np.random.default_rng(3)
    for n in (2, 6):
        table = make_random_dh_table(rng, n, "standard")
        robot = rk.load(table)
        q, dq, ddq = rng.normal(size=(3, n))
        out = dh_inverse_dynamics(table, q, dq, ddq)
        assert isinstance(out, tuple) and len(out) == 2
        tau, steps = out
        ref = robot.rnea(q, dq, ddq)
        assert np.abs(tau - ref).max() <= 1e-9 * max(1.0, np.abs(ref).max())
        assert steps.omega.shape == (n, 3)
        assert np.abs(dh_inverse_dynamics(table, q, dq, ddq, trace=False) - tau).max() <= 1e-12 * max(1.0, np.abs(tau).max())
