"""Collaborative arms as their makers publish them (tests/data/kinova/ros_kortex/SOURCE, tests/data/niryo/SOURCE):
Kinova's Gen3 in 7 and 6 joints (``kortex_description/robots/gen3.xacro`` with the package's own arguments
``dof``, ``vision``, ``gripper``) and Niryo's Ned2, loaded with :func:`robokit.load` as a user does and held
against Pinocchio built directly from the ``xacro`` program's expansion of the same files with the same
arguments (tests/support/xacro_reference.py).

Compared at random joint values within the file's limits (continuous joints over a turn): the pose of every
link frame, the tip's Jacobians, M and the gravity torques to 1e-12 of each quantity's largest entry; the
position, velocity and effort limits (a continuous joint unbounded); what robokit says once. With a gripper
the mimic joints are off the chain: each is locked where the file puts it when the joint it follows is at 0
(``multiplier · 0 + offset``), which the Gen3 lite's fingers (offset 0.149 rad) show.
"""
from __future__ import annotations

import warnings
import xml.etree.ElementTree as ET
from pathlib import Path

import numpy as np
import pinocchio as pin
import pytest

import robokit
from xacro_reference import configuration, xacro_urdfs

DATA = Path(__file__).resolve().parents[1] / "data"
KORTEX = DATA / "kinova" / "ros_kortex"
GEN3 = "kortex_description/robots/gen3.xacro"
NIRYO = DATA / "niryo"
NED2 = "niryo_robot_description/urdf/ned2"

#: label -> (packages folder, xacro file in it, xacro arguments, tip given (None: robokit's default),
#: expected tip, number of joints, continuous joints (indices))
ARMS = {
    "Gen3 7-DoF": (KORTEX, GEN3, {"vision": "false"}, None, "tool_frame", 7, (0, 2, 4, 6)),
    "Gen3 7-DoF, vision module": (KORTEX, GEN3, {}, None, "tool_frame", 7, (0, 2, 4, 6)),
    "Gen3 6-DoF": (KORTEX, GEN3, {"dof": "6", "vision": "false"}, None, "tool_frame", 6, (0, 3, 5)),
    "Gen3 7-DoF, Robotiq 2F-85": (KORTEX, GEN3, {"gripper": "robotiq_2f_85", "vision": "false"}, None,
                                  "tool_frame", 7, (0, 2, 4, 6)),
    "Ned2": (NIRYO, f"{NED2}/niryo_ned2.urdf.xacro", {}, None, "tool_link", 6, ()),
    "Ned2, gripper and camera": (NIRYO, f"{NED2}/niryo_ned2_gripper1_n_camera.urdf.xacro", {}, None,
                                 "base_gripper_1", 6, ()),
}


@pytest.fixture(scope="module")
def reference() -> dict[str, str]:
    """The xacro program's URDF of every arm (one subprocess for all)."""
    return xacro_urdfs({k: (m, f, a) for k, (m, f, a, *_) in ARMS.items()})


def load(label: str) -> tuple[robokit.Robot, list[str]]:
    """The arm as a user loads it (the file and the arguments: the packages are found beside it), and what
    robokit said."""
    folder, rel, args, tip, *_ = ARMS[label]
    with warnings.catch_warnings(record=True) as said:
        warnings.simplefilter("always")
        robot = robokit.load(folder / rel, tip, xacro_args=args or None)
    return robot, [str(w.message) for w in said]


def mimic_positions(text: str) -> dict[str, float]:
    """Each ``<mimic>`` joint's value with every other joint at 0, read from the URDF text: multiplier ×
    (the value of the joint it follows) + offset (urdfdom's defaults 1 and 0)."""
    terms = {el.get("name"): (m.get("joint"), float(m.get("multiplier", 1)), float(m.get("offset", 0)))
             for el in ET.fromstring(text).iter("joint") for m in el.findall("mimic")}

    def value(j: str) -> float:
        return terms[j][1] * value(terms[j][0]) + terms[j][2] if j in terms else 0.0

    return {j: value(j) for j in terms}


def worst_errors(robot: robokit.Robot, text: str, samples: int = 20) -> dict[str, float]:
    """The largest errors of robokit against Pinocchio on ``text`` (the joints off the chain where the file
    puts them with its other joints at 0): every link frame's pose (absolute), the tip's Jacobians, M and
    gravity (relative to each one's largest entry)."""
    model = pin.buildModelFromXML(text)
    data = model.createData()
    joints = [model.joints[model.getJointId(j)] for j in robot.joint_names]
    iv = [j.idx_v for j in joints]
    mimic = [(model.joints[model.getJointId(j)], v) for j, v in mimic_positions(text).items()]
    lo, hi = np.asarray(robot.qlim, float).T
    lo, hi = np.where(np.isfinite(lo), lo, -np.pi), np.where(np.isfinite(hi), hi, np.pi)
    body = pin.FrameType.BODY
    links = [f for f in robot.frame_names if model.existFrame(f, body)]
    assert robot.tip in links and len(links) >= robot.n + 2
    fid = model.getFrameId(robot.tip, body)
    frames = {pin.WORLD: robokit.Frame.WORLD, pin.LOCAL: robokit.Frame.LOCAL,
              pin.LOCAL_WORLD_ALIGNED: robokit.Frame.LOCAL_WORLD_ALIGNED}
    rng = np.random.default_rng(11)
    worst = dict(pose=0.0, J=0.0, M=0.0, g=0.0)
    for _ in range(samples):
        q = rng.uniform(lo, hi)
        qf = configuration(model, joints, q)
        for jm, v in mimic:  # off the chain: where the file puts them
            qf[jm.idx_q:jm.idx_q + jm.nq] = [np.cos(v), np.sin(v)] if jm.nq == 2 else [v]
        pin.framesForwardKinematics(model, data, qf)
        for f in links:
            err = np.abs(robot.frame_pose(q, f) - data.oMf[model.getFrameId(f, body)].homogeneous).max()
            worst["pose"] = max(worst["pose"], err)
        for ref, rk_ref in frames.items():
            J = pin.computeFrameJacobian(model, data, qf, fid, ref)[:, iv]
            J = np.vstack([J[3:], J[:3]])  # robokit: angular rows first
            worst["J"] = max(worst["J"], np.abs(robot.jacobian(q, reference=rk_ref) - J).max() / np.abs(J).max())
        M = pin.crba(model, data, qf)
        M = (np.triu(M) + np.triu(M, 1).T)[np.ix_(iv, iv)]
        g = pin.computeGeneralizedGravity(model, data, qf)[iv]
        worst["M"] = max(worst["M"], np.abs(robot.crba(q) - M).max() / np.abs(M).max())
        worst["g"] = max(worst["g"], np.abs(robot.gravity_torques(q) - g).max() / np.abs(g).max())
    return worst


@pytest.mark.parametrize("label", list(ARMS))
def test_arm_matches_pinocchio_on_the_xacro_program_output(label, reference):
    robot, said = load(label)
    *_, tip, n, continuous = ARMS[label]
    assert robot.tip == tip and robot.n == n
    model = pin.buildModelFromXML(reference[label])
    assert [model.names[model.getJointId(j)] for j in robot.joint_names] == [f"joint_{i + 1}" for i in range(n)]
    joints = [model.joints[model.getJointId(j)] for j in robot.joint_names]
    # limits: a continuous joint (Pinocchio holds it as cos, sin: two coordinates) is unbounded
    assert [i for i, j in enumerate(joints) if j.nq == 2] == list(continuous)
    qlim = np.asarray(robot.qlim, float)
    for i, j in enumerate(joints):
        if j.nq == 2:
            assert qlim[i].tolist() == [-np.inf, np.inf]
        else:
            assert qlim[i].tolist() == [model.lowerPositionLimit[j.idx_q], model.upperPositionLimit[j.idx_q]]
    iv = [j.idx_v for j in joints]
    rv = [robot.model.joints[robot.model.getJointId(j)].idx_v for j in robot.joint_names]
    assert np.array_equal(robot.model.velocityLimit[rv], model.velocityLimit[iv])
    assert np.array_equal(robot.model.effortLimit[rv], model.effortLimit[iv])
    assert np.all(model.effortLimit[iv] > 0) and np.all(model.velocityLimit[iv] > 0)

    worst = worst_errors(robot, reference[label])
    assert max(worst.values()) < 1e-12, worst

    meshes = [s for s in said if "mesh files not found" in s]
    assert len(meshes) == 1, said  # the meshes are not vendored: one note, not one per mesh
    assert not any("has mass (the file gives none)" in s for s in said)  # both makers give inertias


def test_what_robokit_says_about_the_grippers():
    """Once each: the Robotiq 2F-85's five mimic joints locked off the chain (its finger_joint, which they
    follow, is locked too: the gripper is open), the Ned2 gripper's <gazebo> and <transmission> elements."""
    robot, said = load("Gen3 7-DoF, Robotiq 2F-85")
    mimic = [s for s in said if "mimic joints off the chain locked" in s]
    assert len(mimic) == 1, said
    for j in ("left_inner_knuckle_joint", "left_inner_finger_joint", "right_outer_knuckle_joint",
              "right_inner_knuckle_joint", "right_inner_finger_joint"):
        assert j in mimic[0] and j in robot.locked_joints
    assert "finger_joint" in robot.locked_joints and "(at " not in mimic[0]  # offsets 0: all at 0
    robot, said = load("Ned2, gripper and camera")
    assert set(robot.locked_joints) == {"joint_base_to_mors_1", "joint_base_to_mors_2"}
    assert sum("<gazebo>" in s for s in said) == 1 and sum("<transmission>" in s for s in said) == 1, said


def test_a_finger_tip_behind_a_mimic_joint_is_refused_with_the_reason():
    """A tip on the gripper's linkage puts a mimic joint on the chain; robokit's joints are independent, so
    it refuses, naming the joint (an explicit refusal, not a silently free finger joint)."""
    folder, rel, args, *_ = ARMS["Gen3 7-DoF, Robotiq 2F-85"]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        with pytest.raises(robokit.InputError, match="'left_inner_finger_joint' mimics 'finger_joint'"):
            robokit.load(folder / rel, "left_inner_finger_pad", xacro_args=args)


def test_mimic_joints_off_the_chain_are_locked_where_the_file_puts_them():
    """Kinova's Gen3 lite (tests/data/kinova/gen3_lite.urdf): its fingertip joints mimic the finger joint with
    multiplier -0.676 and offset 0.149 rad; with the finger joint locked at 0, the file puts them at 0.149.
    Before, robokit locked them at 0: the fingertip frames 0.149 rad off (0.1488 in a rotation entry), M
    6.4e-5 and gravity 1.6e-4 off relative to their largest entries, and the note said only "locked"."""
    with warnings.catch_warnings(record=True) as said:
        warnings.simplefilter("always")
        robot = robokit.load(DATA / "kinova" / "gen3_lite.urdf", "end_effector_link")
    text = (DATA / "kinova" / "gen3_lite.urdf").read_text()
    assert mimic_positions(text) == {"right_finger_tip_joint": 0.149, "left_finger_bottom_joint": 0.0,
                                     "left_finger_tip_joint": 0.149}
    worst = worst_errors(robot, text)
    assert max(worst.values()) < 1e-12, worst
    notes = [str(w.message) for w in said if "mimic joints off the chain locked" in str(w.message)]
    assert len(notes) == 1 and "right_finger_tip_joint (at 0.149)" in notes[0], notes


def test_a_mimic_joint_following_a_chain_joint_is_said_to_stay():
    """The ABB IRB 6640's counterbalance follows joint_2 of the chain; robokit holds it where joint_2 = 0
    puts it and says so in its one note (its links do not move with joint_2)."""
    with warnings.catch_warnings(record=True) as said:
        warnings.simplefilter("always")
        robokit.load(DATA / "abb" / "abb_irb6640_support/urdf/irb6640_185_280.xacro")
    notes = [str(w.message) for w in said if "mimic joints off the chain locked" in str(w.message)]
    assert len(notes) == 1 and "follow 'joint_2', a joint of the chain" in notes[0], notes


def test_a_gripper_linkage_of_mimic_joints_counts_as_fingers():
    """Kinova's Gen3 with the Robotiq 2F-85 (gen3.xacro gripper:=robotiq_2f_85): below the arm's last joint
    the gripper is a tree of one finger joint and five mimic joints, two deep. Before, robokit refused the
    file without tip= ("a tree with 4 ends and no single longest chain": left_inner_finger_pad,
    right_inner_finger_pad, left_inner_knuckle, right_inner_knuckle), and each of those tips puts a mimic
    joint on the chain, which it refuses too. A mimic joint moves with another, so it adds no length: the
    linkage counts as fingers and the tip is the arm's tool frame, the same robot as with tip="tool_frame"."""
    robot, said = load("Gen3 7-DoF, Robotiq 2F-85")
    assert robot.tip == "tool_frame" and robot.n == 7
    assert not any("chose its longest chain" in s for s in said)  # fingers: no choice to report
    folder, rel, args, *_ = ARMS["Gen3 7-DoF, Robotiq 2F-85"]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        given = robokit.load(folder / rel, "tool_frame", xacro_args=args)
    q = np.random.default_rng(3).uniform(-2.0, 2.0, 7)
    assert np.array_equal(robot.frame_pose(q), given.frame_pose(q))
    assert np.array_equal(robot.crba(q), given.crba(q))


DUAL = {side + "_" + k: v for side in ("left", "right") for k, v in
        {"arm": "gen3", "gripper": "robotiq_2f_85", "dof": "7", "vision": "false", "sim": "false",
         "prefix": side + "_"}.items()}


def test_two_arms_with_grippers_name_the_arms_tool_frames():
    """Kinova's kortex_dual_robots.xacro, two Gen3 with the Robotiq 2F-85: two equally long arms, so no
    default tip. Before, the refusal listed the eight ends of the grippers' linkages
    (left_left_inner_finger_pad (9 joints), ... right_right_inner_knuckle (8 joints)), each of which puts a
    mimic joint on the chain and is refused in turn; now it names the two arms' tool frames, and either
    loads (checked against Pinocchio on the xacro program's output)."""
    path = KORTEX / "kortex_description/multiple_robots/kortex_dual_robots.xacro"
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        with pytest.raises(robokit.InputError) as refused:
            robokit.load(path, xacro_args=DUAL)
        assert str(refused.value).endswith("choose one with tip= (--tip): left_tool_frame (7 joints), "
                                           "right_tool_frame (7 joints)")
        right = robokit.load(path, "right_tool_frame", xacro_args=DUAL)
    text = xacro_urdfs({"dual": (KORTEX, "kortex_description/multiple_robots/kortex_dual_robots.xacro", DUAL)})["dual"]
    assert right.n == 7 and right.joint_names[0] == "right_joint_1"
    worst = worst_errors(right, text, samples=5)
    assert max(worst.values()) < 1e-12, worst
