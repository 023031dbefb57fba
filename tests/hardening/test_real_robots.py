"""Real robots from example-robot-data: trees get no silent default tip, floating-base arms are fixed."""
import json
import re
import warnings

import numpy as np
import pytest
from hardening_support import assert_one_line_error

import robokit


def _erd_kinematic_model(name):
    """The Pinocchio model of an example-robot-data robot's URDF as example-robot-data builds it
    (a free-flyer root where it declares one), read directly by Pinocchio without geometry."""
    from os.path import join

    import example_robot_data as erd
    import pinocchio as pin
    from example_robot_data.utils import getModelPath

    loader = erd.ROBOTS[name]
    rel = join(loader.path, loader.urdf_subpath, loader.urdf_filename)
    path = join(loader.model_path or getModelPath(rel), rel)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        if loader.free_flyer:
            return pin.buildModelFromUrdf(path, pin.JointModelFreeFlyer())
        return pin.buildModelFromUrdf(path)


def _moving_joints_to(model, frame) -> int:
    """Joints with a degree of freedom between the root and ``frame`` (Pinocchio's tree, counted here)."""
    j = model.frames[model.getFrameId(frame)].parentJoint
    n = 0
    while j != 0:
        n += model.joints[j].nv > 0
        j = model.parents[j]
    return n


# the end of each robot's arm, which must be among the candidates listed
ARM_ENDS = {"baxter": "gripper", "tiago": "hand_", "alex_nub_hands": "Nub"}


@pytest.mark.parametrize("name", sorted(ARM_ENDS))
def test_tree_robot_without_tip_lists_candidates_and_loads_with_one(name, tmp_path, main_cli):
    out = tmp_path / f"{name}.json"
    r = main_cli("convert", name, "-o", out)
    line = assert_one_line_error(r, name, "--tip")
    assert not out.exists()
    cands = re.findall(r"([A-Za-z0-9_]+) \((\d+) joints?\)", line)
    assert len(cands) >= 2, line
    assert any(ARM_ENDS[name] in c for c, _ in cands), line
    # the chain lengths listed are the ones of the robot's own kinematic tree
    model = _erd_kinematic_model(name)
    for frame, n in cands:
        assert _moving_joints_to(model, frame) == int(n), (frame, n)
    tip, n = next((c, int(k)) for c, k in cands if ARM_ENDS[name] in c)
    r = main_cli("convert", name, "--tip", tip, "-o", out)
    assert r.rc == 0, r.err
    poe = json.loads(out.read_text())
    assert poe["tip"] == tip and len(poe["joint_names"]) == n


@pytest.mark.parametrize("name", ["so100", "so101"])
def test_floating_base_arm_loads_with_its_base_fixed_and_its_chain_is_the_arm(name, tmp_path, main_cli):
    if name == "so100":  # (so101's meshes take seconds to load: its CLI run is the same code)
        out = tmp_path / f"{name}.json"
        r = main_cli("convert", name, "-o", out)
        assert r.rc == 0, r.err
        notes = [ln for ln in r.err.splitlines() if ln.startswith("robokit: note:")]
        assert any("floating base" in ln and "fixed" in ln for ln in notes), r.err
    with pytest.warns(robokit.errors.RobokitWarning, match="floating base"):
        robot = robokit.load(name)
    assert robot.n == 6 and robot.model.nq == 6
    assert robot.joint_names[0] == "shoulder_pan" and "elbow_flex" in robot.joint_names
    assert all(robot.model.joints[j].shortname() != "JointModelFreeFlyer" for j in range(1, robot.model.njoints))
    # FK against example-robot-data's own floating model with the base at the identity
    import pinocchio as pin

    full = _erd_kinematic_model(name)
    assert full.joints[1].shortname() == "JointModelFreeFlyer"  # what example-robot-data gives
    data = full.createData()
    rng = np.random.default_rng(3)
    for _ in range(5):
        th = robot.random_configuration(rng)
        q = pin.neutral(full)
        for jn, v in zip(robot.joint_names, th):
            q[full.joints[full.getJointId(jn)].idx_q] = v
        pin.framesForwardKinematics(full, data, q)
        np.testing.assert_allclose(robot.frame_pose(th), data.oMf[full.getFrameId(robot.tip)].homogeneous,
                                   atol=1e-12)


def test_cassie_gives_one_line_exit_2(tmp_path, main_cli):
    out = tmp_path / "cassie.json"
    assert_one_line_error(main_cli("convert", "cassie", "-o", out), "cassie")
    assert not out.exists()
