"""One frame vocabulary for every Jacobian: each :class:`robokit.Frame` (and each accepted
synonym) gives, in every function that takes it, the matrix Pinocchio's ``computeFrameJacobian``
gives with the matching ``ReferenceFrame`` (WORLD = space Jacobian, LOCAL = body Jacobian,
LOCAL_WORLD_ALIGNED = the lecture's geometric Jacobian), and tip-wrench torques equal ``Jᵀ F`` with
that Jacobian. The former words warn once per process; every function has the one default.
"""
from __future__ import annotations

import inspect
import subprocess
import sys

import numpy as np
import pinocchio as pin
import pytest

import robokit as rk
from robokit._arrays import REFERENCES, check_reference
from robokit.description.batch import batch_jacobian
from robokit.errors import InputError
from robokit.frames import DEFAULT_FRAME, Frame, as_frame
from robokit.kinematics import dh_jacobian, dh_static_torques

#: Every accepted spelling: the enum members, their values, Pinocchio's own members, the former words.
SPELLINGS = ([(f, f.value) for f in Frame] + [(f.value, f.value) for f in Frame]
             + [(getattr(pin.ReferenceFrame, f.name), f.value) for f in Frame]
             + [(w, c) for w, c in REFERENCES.items() if w not in {f.value for f in Frame}])
IDS = [repr(s) if isinstance(s, str) else f"{type(s).__name__}.{s.name}" for s, _ in SPELLINGS]

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


@pytest.mark.filterwarnings("ignore::DeprecationWarning")
def test_every_name_maps_onto_one_pinocchio_frame():
    assert set(REFERENCES.values()) == set(PIN)
    assert {check_reference(c) for c in PIN} == set(PIN)  # the canonical names map to themselves
    for lecture, canonical in [("base", "local_world_aligned"), ("tool", "local"), ("space", "world"),
                               ("body", "local")]:
        assert check_reference(lecture) == canonical


@pytest.mark.parametrize("bad", ["World", "spatial", "", 0, 1.5])
def test_unknown_reference_lists_the_accepted_names(robots, bad):
    table = robots["rrr"].dh
    calls = (lambda: dh_jacobian(table, np.zeros(3), bad),
             lambda: robots["rrr"].jacobian(np.zeros(3), reference=bad),
             lambda: dh_static_torques(table, np.zeros(3), np.ones(6), reference=bad),
             lambda: batch_jacobian(robots["rrr"], np.zeros((2, 3)), reference=bad))
    for call in calls:
        with pytest.raises(InputError, match=r"reference: expected a robokit.Frame .* 'world', .*'base'"):
            call()


@pytest.mark.filterwarnings("ignore::DeprecationWarning")
@pytest.mark.parametrize("name,canonical", SPELLINGS, ids=IDS)
@pytest.mark.parametrize("model", ["puma560", "rrr", "craig_rpr"])
def test_every_function_equals_pinocchio(robots, model, name, canonical):
    robot = robots[model]
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


def test_every_frame_taking_function_has_one_default(robots):
    """The Jacobian functions share one default (the contract): DEFAULT_FRAME, LOCAL_WORLD_ALIGNED —
    the lecture's geometric Jacobian, the generated C's. A reference left out gives that frame's
    result, compared with Pinocchio, and no warning."""
    import warnings

    from robokit.symbolic import SymbolicArm

    assert DEFAULT_FRAME is Frame.LOCAL_WORLD_ALIGNED
    for fn in (dh_jacobian, SymbolicArm.jacobian):
        assert inspect.signature(fn).parameters["reference"].default is DEFAULT_FRAME, fn
    robot = rk.load("puma560")
    q = _configurations(robot)[0]
    J_lwa = _pin_jacobian(robot, q, "local_world_aligned")
    F = np.arange(1.0, 7.0)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        np.testing.assert_allclose(robot.jacobian(q), J_lwa, atol=1e-9)
        np.testing.assert_allclose(batch_jacobian(robot, q[None]), J_lwa[None], atol=1e-9)
        np.testing.assert_allclose(dh_jacobian(robot.dh, q), J_lwa, atol=1e-9)
        np.testing.assert_allclose(dh_static_torques(robot.dh, q, F), J_lwa.T @ F, atol=1e-9)


def test_former_words_warn_once_per_word_per_process():
    """A fresh interpreter: "base" warns once however often it is used (and on the caller's line),
    "tool" warns once more, the canonical names and Frame members never warn."""
    code = """
import warnings, numpy as np
warnings.simplefilter("always")
import robokit as rk
from robokit.kinematics import dh_jacobian
r = rk.load("rrr"); q = np.zeros(3)
with warnings.catch_warnings(record=True) as w:
    warnings.simplefilter("always")
    for _ in range(3):
        dh_jacobian(r.dh, q, "base"); r.jacobian(q, reference="base"); dh_jacobian(r.dh, q, "tool")
    for f in rk.Frame:
        dh_jacobian(r.dh, q, f); r.jacobian(q, reference=f.value)
print(len(w), sorted(str(x.message).split(" ")[0] for x in w), {x.category.__name__ for x in w},
      {x.filename for x in w})
"""
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout
    assert out.strip() == "2 [\"reference='base'\", \"reference='tool'\"] {'DeprecationWarning'} {'<string>'}", out


def test_frame_mirrors_pinocchio():
    assert [f.name for f in Frame] == ["WORLD", "LOCAL", "LOCAL_WORLD_ALIGNED"]
    for f in Frame:
        assert f.pinocchio == getattr(pin.ReferenceFrame, f.name)
        assert as_frame(f.pinocchio) is f and as_frame(f.value) is f and f == f.value
    assert rk.Frame is Frame


@pytest.mark.filterwarnings("ignore::DeprecationWarning")
@pytest.mark.parametrize("name,canonical", SPELLINGS, ids=IDS)
def test_symbolic_jacobian_equals_pinocchio(robots, name, canonical):
    from robokit.symbolic import SymbolicArm

    robot = robots["craig_rpr"]
    arm = SymbolicArm.from_dh_table(robot.dh)
    J = arm.lambdify(arm.jacobian(name, simplify=False))
    for q in _configurations(robot, k=2, seed=1):
        J_pin = _pin_jacobian(robot, q, canonical)
        np.testing.assert_allclose(np.asarray(J(q), dtype=float), J_pin, atol=1e-9)
