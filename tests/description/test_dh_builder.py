"""DH robots built by the model builder (no URDF text) equal Pinocchio's URDF parser on the URDF robokit writes
for the same table: frames, joints, inertias, limits, geometry, and FK/J/RNEA/M to 1e-12 — the shipped models
and random tables of both conventions with prismatic joints."""
import numpy as np
import pytest

import robokit
from robokit.description.model_builder import build_model
from robokit.description.urdf_gen import description_from_dh, urdf_from_dh

from tests.description.conftest import make_random_dh_table
from tests.description.test_model_builder import assert_same_dynamics, assert_same_model

pin = pytest.importorskip("pinocchio")


def _tables():
    out = [robokit.load(n).dh for n in ("twolink", "rrr", "puma560")]
    for conv in ("standard", "modified"):
        for seed in range(3):
            out.append(make_random_dh_table(np.random.default_rng(seed), 5, conv, prismatic=(2,) if seed else ()))
    return out


@pytest.mark.parametrize("table", _tables(), ids=lambda t: f"{t.name}-{t.convention}")
def test_dh_description_equals_its_urdf(table):
    xml = urdf_from_dh(table)
    ref = pin.buildModelFromXML(xml)
    ref.gravity.linear = np.asarray(table.gravity, dtype=float)
    # a joint the table gives no qlim: the URDF text writes ±π (R) or ±1 m (P), the robot is unlimited
    lower, upper = ref.lowerPositionLimit.copy(), ref.upperPositionLimit.copy()
    for i, link in enumerate(table.links):
        if link.qlim is None:
            k = ref.joints[ref.getJointId(f"joint_{i + 1}")].idx_q
            assert (lower[k], upper[k]) == ((-np.pi, np.pi) if link.joint == "R" else (-1.0, 1.0))
            lower[k], upper[k] = -np.inf, np.inf
    ref.lowerPositionLimit, ref.upperPositionLimit = lower, upper
    model, visual, collision, notes = build_model(description_from_dh(table))
    assert notes == [] and len(collision.geometryObjects) == 0
    assert_same_model(model, ref, atol=1e-12)  # exact matrices against the rpy text urdf_from_dh writes
    assert_same_dynamics(model, ref)
    theirs = pin.buildGeomFromUrdfString(ref, xml, pin.GeometryType.VISUAL)
    assert [o.name for o in visual.geometryObjects] == [o.name for o in theirs.geometryObjects]
    for a, b in zip(visual.geometryObjects, theirs.geometryObjects):
        assert (a.parentJoint, a.parentFrame, a.meshPath) == (b.parentJoint, b.parentFrame, b.meshPath)
        np.testing.assert_allclose(a.placement.homogeneous, b.placement.homogeneous, atol=1e-12)
        np.testing.assert_allclose(a.meshColor, b.meshColor)


def test_loaded_dh_robot_uses_the_builder():
    robot = robokit.load("puma560")
    ref = pin.buildModelFromXML(urdf_from_dh(robot.dh))
    ref.gravity.linear = robot.gravity
    assert_same_model(robot.model, ref, atol=1e-12)
