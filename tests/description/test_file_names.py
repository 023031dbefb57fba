"""Every name robokit reports is in the file: the default tip, ``robot.frame_names`` (the keys of
``frame_poses``), the joints, the locked joints, the collision table's links. The file's names
are read here with ElementTree, independently of robokit. Also: the repr names the format."""
import sys
import warnings
import xml.etree.ElementTree as ET
from pathlib import Path

import numpy as np
import pytest

import robokit
from robokit.collision import World, self_collision_pairs

sys.path.insert(0, str(Path(__file__).parent))
from urdf_text import arm, inertial, joint, link, sphere  # noqa: E402


def _names_in(path):
    """Every name="..." of a link or joint (URDF) / body, joint, site, geom (MJCF) in the file."""
    root = ET.parse(path).getroot()
    tags = {"link", "joint"} if root.tag == "robot" else {"body", "joint", "site", "geom"}
    return {el.get("name") for el in root.iter() if el.tag in tags and el.get("name")}


def _reported(robot):
    names = {robot.tip, *robot.frame_names, *robot.joint_names, *robot.locked_joints}
    pairs = self_collision_pairs(robot)
    for a, b in pairs.checked + pairs.adjacent + pairs.always:
        names |= {a, b}
    return names


def _quiet_load(path, **kw):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return robokit.load(path, **kw)


def test_a_joint_and_its_link_sharing_a_name(tmp_path):
    """A fixed joint named after its child link (example-robot-data's Z1 does this) and a
    revolute joint named after its child, with a branch that must be locked: Pinocchio's
    buildReducedModel looks frames up by name alone and threw on such a model."""
    finger = link("finger", inertial(0.05, 1e-5, 1e-5, 1e-5) + sphere(0.02))
    tool = link("tool", inertial(0.1, 1e-4, 1e-4, 1e-4))
    text = arm(extra_links=[finger, tool],
               extra_joints=[joint("finger_joint", "l2", "finger", xyz="0.2 0 0.05", axis="1 0 0"),
                             joint("tool", "l3", "tool", "fixed", xyz="0.3 0 0")])
    text = text.replace('name="j3"', 'name="l3"')  # the joint to l3 is called l3 too
    path = tmp_path / "shared.urdf"
    path.write_text(text)
    robot = _quiet_load(path, tip="tool")
    assert robot.locked_joints == ("finger_joint",) and robot.joint_names == ("j1", "j2", "l3")
    assert _reported(robot) <= _names_in(path)
    import pinocchio as pin

    raw = pin.buildModelFromUrdf(str(path))  # the body frames of the raw model are the reference
    q = np.array([0.3, -0.7, 1.1])
    q_raw = np.zeros(raw.nq)
    for name, v in zip(robot.joint_names, q):
        q_raw[raw.joints[raw.getJointId(name)].idx_q] = v
    data = raw.createData()
    pin.framesForwardKinematics(raw, data, q_raw)
    for name in ("tool", "l3"):
        ref = data.oMf[raw.getFrameId(name, pin.FrameType.BODY)].homogeneous
        assert np.allclose(robot.frame_pose(q, name), ref, atol=1e-12)
        assert np.allclose(robot.frame_poses(q)[name], ref, atol=1e-12)


def test_the_default_tip_and_frames_of_a_pinocchio_model_with_invented_names():
    """pybullet_data's thrower.xml ends in seven unnamed MJCF bodies: Pinocchio's MJCF parser calls
    each '<parent>Bis' (all one name) and gives every body without a joint a fixed joint
    '<body>_fixed'. Given the file's names, the builder chooses the tip among them and reports
    no other frame."""
    pybullet_data = pytest.importorskip("pybullet_data")
    import pinocchio as pin

    from robokit.description.builder import build_robot, choose_tip
    from robokit.description.spec import RobotSpec

    path = Path(pybullet_data.getDataPath()) / "mjcf" / "thrower.xml"
    model = pin.buildModelFromMJCF(str(path))
    invented = {f.name for f in model.frames} - _names_in(path)
    assert "wrist_roll_linkBis" in invented and "fingertip_fixed" in invented  # what Pinocchio adds
    assert choose_tip(model)[0] == "wrist_roll_linkBis"  # without the file's names
    names = _names_in(path)
    assert choose_tip(model, names)[0] == "fingertip"
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        robot = build_robot("thrower", model, None, [None, None], {}, RobotSpec("mjcf", path=str(path)), names=names)
    assert robot.tip == "fingertip" and set(robot.frame_names) <= names
    assert set(robot.frame_poses(np.zeros(robot.n))) == set(robot.frame_names)
    with pytest.raises(robokit.InputError) as err:
        robot.frame_pose(np.zeros(robot.n), "nope")
    assert "Bis" not in str(err.value) and "_fixed" not in str(err.value)


def test_a_joint_name_the_file_lacks_is_noted():
    import pinocchio as pin

    from robokit.description.builder import build_robot
    from robokit.description.spec import RobotSpec

    model = pin.Model()
    j = model.addJoint(0, pin.JointModelRZ(), pin.SE3.Identity(), "bodyJoint_0")  # Pinocchio's name for an unnamed joint
    model.appendBodyToJoint(j, pin.Inertia.FromSphere(1.0, 0.1), pin.SE3.Identity())
    model.addJointFrame(j)
    model.addBodyFrame("body", j, pin.SE3.Identity(), model.getFrameId("bodyJoint_0"))
    with pytest.warns(robokit.RobokitWarning, match="joint names not in the file .*: bodyJoint_0"):
        robot = build_robot("x", model, None, [None, None], {}, RobotSpec("mjcf", path="/x.xml"), names={"body"})
    assert robot.tip == "body" and robot.frame_names == ("body",)


@pytest.mark.parametrize("name", ["ur5", "panda", "z1"])
def test_example_robot_data_names_are_its_urdfs(name):
    import example_robot_data as erd

    loader = erd.ROBOTS[name]()
    robot = robokit.load(name)
    assert _reported(robot) <= _names_in(loader.df_path)


@pytest.mark.parametrize("file", ["kuka_iiwa/model.urdf", "xarm/xarm6_robot.urdf", "franka_panda/panda.urdf"])
def test_pybullet_urdf_names(file):
    pybullet_data = pytest.importorskip("pybullet_data")
    path = Path(pybullet_data.getDataPath()) / file
    robot = _quiet_load(path)
    assert _reported(robot) <= _names_in(path)
    assert World(robot).describe()  # the collision table names links of the file (checked in _reported)


def test_repr_names_the_format(tmp_path):
    from robokit.description.mjcf_write import mjcf_from_robot

    twolink = robokit.load("twolink")
    assert repr(twolink).endswith("DH standard)")
    assert "URDF of example-robot-data;" in repr(robokit.load("ur5"))
    urdf = tmp_path / "arm.urdf"
    urdf.write_text(arm())
    assert ", URDF;" in repr(robokit.load(urdf))
    xacro = tmp_path / "arm.urdf.xacro"
    xacro.write_text(arm().replace('<robot name="arm">', '<robot name="arm" xmlns:xacro="http://www.ros.org/wiki/xacro">'))
    assert ", xacro;" in repr(robokit.load(xacro))
    mjcf = tmp_path / "twolink.xml"
    mjcf.write_text(mjcf_from_robot(twolink)[0])
    assert ", MJCF;" in repr(_quiet_load(mjcf))
    import pinocchio as pin

    hand_built = robokit.Robot("rrr", pin.buildModelFromUrdf(str(urdf)), "l3")
    assert "Pinocchio model;" in repr(hand_built)
