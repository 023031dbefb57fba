"""One ``reference=`` vocabulary for every Jacobian: each accepted name gives, in every function
that takes it, the matrix Pinocchio's ``computeFrameJacobian`` gives with the matching
``ReferenceFrame`` (world = space Jacobian, local = body Jacobian, local_world_aligned = the
lecture's geometric Jacobian), and tip-wrench torques equal ``Jᵀ F`` with that Jacobian.
"""
from __future__ import annotations

import numpy as np
import pinocchio as pin
import pytest

import robokit as rk
from robokit._arrays import REFERENCES, check_reference
from robokit.description.batch import batch_jacobian
from robokit.errors import InputError
from robokit.kinematics import dh_jacobian, dh_static_torques

PIN = {"world": pin.ReferenceFrame.WORLD, "local": pin.ReferenceFrame.LOCAL,
       "local_world_aligned": pin.ReferenceFrame.LOCAL_WORLD_ALIGNED}

#: A modified-DH (Craig) arm with a prismatic joint, a base and a tool offset: every branch of the DH code.
CRAIG_YAML = """\
name: craig_rpr
convention: modified
angle_unit: deg
base: {xyz: [0.1, -0.2, 0.3], rpy: [10, -20, 30]}
tool: {xyz: [0.05, 0.0, 0.12], rpy: [0, 90, 0]}
links:
  - {joint: R, a: 0.0, alpha: 0, d: 0.4, theta: 0}
  - {joint: P, a: 0.2, alpha: -90, d: 0.1, theta: 15}
  - {joint: R, a: 0.3, alpha: 45, d: 0.0, theta: 0}
"""


@pytest.fixture(scope="module")
def robots(tmp_path_factory):
    path = tmp_path_factory.mktemp("ref") / "craig_rpr.yaml"
    path.write_text(CRAIG_YAML)
    return {"puma560": rk.load("puma560"), "rrr": rk.load("rrr"), "craig_rpr": rk.load(str(path))}


def _pin_jacobian(robot, q, canonical):
    """Pinocchio's frame Jacobian of the tip, reordered to angular rows first (ω; v)."""
    data = robot.model.createData()
    J = pin.computeFrameJacobian(robot.model, data, robot.q_pin(q), robot.tip_id, PIN[canonical])
    return np.vstack([J[3:], J[:3]])


def _configurations(robot, k=3, seed=0):
    rng = np.random.default_rng(seed)
    return rng.uniform(-1.5, 1.5, size=(k, robot.n))


def test_every_name_maps_onto_one_pinocchio_frame():
    assert set(REFERENCES.values()) == set(PIN)
    assert {check_reference(c) for c in PIN} == set(PIN)  # the canonical names map to themselves
    for lecture, canonical in [("base", "local_world_aligned"), ("tool", "local"), ("space", "world"),
                               ("body", "local")]:
        assert check_reference(lecture) == canonical


@pytest.mark.parametrize("bad", ["World", "spatial", "", None, 0])
def test_unknown_reference_lists_the_accepted_names(robots, bad):
    table = robots["rrr"].dh
    calls = (lambda: dh_jacobian(table, np.zeros(3), bad),
             lambda: robots["rrr"].jacobian(np.zeros(3), reference=bad),
             lambda: dh_static_torques(table, np.zeros(3), np.ones(6), reference=bad),
             lambda: batch_jacobian(robots["rrr"], np.zeros((2, 3)), reference=bad))
    for call in calls:
        with pytest.raises(InputError, match=r"reference: expected one of 'world', .*'base'"):
            call()


@pytest.mark.parametrize("name", sorted(REFERENCES))
@pytest.mark.parametrize("model", ["puma560", "rrr", "craig_rpr"])
def test_every_function_equals_pinocchio(robots, model, name):
    robot = robots[model]
    canonical = REFERENCES[name]
    Q = _configurations(robot)
    F = np.array([0.3, -0.2, 0.5, 2.0, -1.0, 4.0])  # (n, f): moment, force
    for q in Q:
        J_pin = _pin_jacobian(robot, q, canonical)
        np.testing.assert_allclose(robot.jacobian(q, reference=name), J_pin, atol=1e-9)
        np.testing.assert_allclose(dh_jacobian(robot.dh, q, name), J_pin, atol=1e-9)
        np.testing.assert_allclose(dh_static_torques(robot.dh, q, F, reference=name), J_pin.T @ F, atol=1e-9)
    J_batch = np.stack([_pin_jacobian(robot, q, canonical) for q in Q])
    np.testing.assert_allclose(robot.jacobian(Q, reference=name), J_batch, atol=1e-9)
    np.testing.assert_allclose(batch_jacobian(robot, Q, reference=name), J_batch, atol=1e-9)


def test_defaults_are_unchanged(robots):
    robot = robots["puma560"]
    q = _configurations(robot)[0]
    J_world, J_lwa, J_local = (_pin_jacobian(robot, q, c) for c in ("world", "local_world_aligned", "local"))
    np.testing.assert_allclose(robot.jacobian(q), J_world, atol=1e-9)
    np.testing.assert_allclose(dh_jacobian(robot.dh, q), J_lwa, atol=1e-9)
    F = np.arange(1.0, 7.0)
    np.testing.assert_allclose(dh_static_torques(robot.dh, q, F), J_local.T @ F, atol=1e-9)


@pytest.mark.parametrize("name", sorted(REFERENCES))
def test_symbolic_jacobian_equals_pinocchio(robots, name):
    from robokit.symbolic import SymbolicArm

    robot = robots["craig_rpr"]
    arm = SymbolicArm.from_dh_table(robot.dh)
    J = arm.lambdify(arm.jacobian(name, simplify=False))
    for q in _configurations(robot, k=2, seed=1):
        J_pin = _pin_jacobian(robot, q, REFERENCES[name])
        np.testing.assert_allclose(np.asarray(J(q), dtype=float), J_pin, atol=1e-9)
