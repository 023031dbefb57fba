"""The arms university courses and student teams own, as their makers publish them (tests/data/<maker>/SOURCE):
Trossen Robotics' Interbotix X-series (PincherX 100, WidowX 250 6DOF, ViperX 300 6DOF) from
``interbotix_xsarm_descriptions``, the ROBOTIS OpenManipulator-X from ``open_manipulator_description`` and
Elephant Robotics' myCobot 280 M5 from ``mycobot_description``.

Each is loaded as a user does, :func:`robokit.load` on the maker's file with the maker's launch arguments
(the packages found beside the file), and held against Pinocchio built directly from the ``xacro``
program's expansion of the same file with the same arguments (tests/support/xacro_reference.py), or on the
URDF file itself: the pose of every link frame, the tip's Jacobians in the three reference frames, M and
the gravity torques at random joint values within the file's limits (continuous joints at any angle), and
the position, velocity and effort limits. And what robokit says about what it does not model: the missing
meshes, the joints' friction, the grippers' locked mimic fingers, the myCobot's missing inertias, once each.
"""
from __future__ import annotations

import warnings
from pathlib import Path

import numpy as np
import pinocchio as pin
import pytest

import robokit
from xacro_reference import xacro_urdfs

DATA = Path(__file__).resolve().parents[1] / "data"
XS = "interbotix_xsarm_descriptions/urdf/"
OMX = "open_manipulator_description/urdf/open_manipulator_x/open_manipulator_x.urdf.xacro"
COBOT = "mycobot_description/urdf/mycobot_280_m5/mycobot_280_m5.urdf"

#: label -> (maker folder, file, xacro arguments, tip, joints)
ARMS = {
    "PincherX 100": ("interbotix", XS + "px100.urdf.xacro", {}, "px100/ee_gripper_link", 4),
    "WidowX 250 6DOF, named left, AR tag": (
        "interbotix", XS + "wx250s.urdf.xacro",
        {"robot_name": "left", "show_ar_tag": "true", "hardware_type": "fake", "use_world_frame": "true"},
        "left/ee_gripper_link", 6),
    "ViperX 300 6DOF": ("interbotix", XS + "vx300s.urdf.xacro", {}, "vx300s/ee_gripper_link", 6),
    "ViperX 300 6DOF without gripper": ("interbotix", XS + "vx300s.urdf.xacro", {"use_gripper": "false"},
                                        "vx300s/wrist_link", 5),
    # the gripper's bar left out: the chain's last joint is the gripper's continuous motor joint
    "PincherX 100 without gripper bar": ("interbotix", XS + "px100.urdf.xacro", {"show_gripper_bar": "false"},
                                         "px100/gripper_prop_link", 5),
    "OpenManipulator-X": ("robotis", OMX, {}, "end_effector_link", 4),
    "OpenManipulator-X, prefix, mock hardware": ("robotis", OMX, {"prefix": "l_", "use_mock_hardware": "true"},
                                                 "l_end_effector_link", 4),
    "myCobot 280 M5": ("elephant", COBOT, None, "joint6_flange", 6),
}


@pytest.fixture(scope="module")
def reference() -> dict[str, str]:
    """The URDF text each arm's engine reads: the xacro program's expansion (one subprocess for all), or the
    URDF file itself."""
    xacros = {k: (DATA / m, f, a) for k, (m, f, a, _, _) in ARMS.items() if a is not None}
    urdfs = xacro_urdfs(xacros)
    urdfs.update({k: (DATA / m / f).read_text() for k, (m, f, a, _, _) in ARMS.items() if a is None})
    return urdfs


def load(label: str) -> tuple[robokit.Robot, list[str]]:
    """The arm as a user loads it, and what robokit said."""
    maker, rel, args, _, _ = ARMS[label]
    with warnings.catch_warnings(record=True) as said:
        warnings.simplefilter("always")
        robot = robokit.load(DATA / maker / rel, xacro_args=args or None)
    return robot, [str(w.message) for w in said]


def configuration(model: pin.Model, joints: list, q: np.ndarray) -> np.ndarray:
    """Pinocchio's configuration for robokit's joint angles ``q`` (a continuous joint as cos, sin), the
    other joints at Pinocchio's neutral."""
    qf = pin.neutral(model)
    for j, x in zip(joints, q):
        qf[j.idx_q:j.idx_q + j.nq] = (np.cos(x), np.sin(x)) if j.nq == 2 else x
    return qf


@pytest.mark.parametrize("label", list(ARMS))
def test_arm_matches_pinocchio_on_the_makers_file(label, reference):
    robot, said = load(label)
    _, _, _, tip, n = ARMS[label]
    assert robot.tip == tip and robot.n == n
    model = pin.buildModelFromXML(reference[label])
    data = model.createData()
    joints = [model.joints[model.getJointId(j)] for j in robot.joint_names]
    iv = [j.idx_v for j in joints]
    continuous = np.array([j.nq == 2 for j in joints])
    iq = [j.idx_q for j in joints]
    lo = np.where(continuous, -np.inf, model.lowerPositionLimit[iq])
    hi = np.where(continuous, np.inf, model.upperPositionLimit[iq])
    assert np.array_equal(np.asarray(robot.qlim, float), np.c_[lo, hi])
    rv = [robot.model.joints[robot.model.getJointId(j)].idx_v for j in robot.joint_names]
    assert np.array_equal(robot.model.velocityLimit[rv], model.velocityLimit[iv])
    assert np.array_equal(robot.model.effortLimit[rv], model.effortLimit[iv])

    body = pin.FrameType.BODY
    links = [f for f in robot.frame_names if model.existFrame(f, body)]
    assert tip in links and len(links) >= n + 1  # the root and every moving link at least
    fid = model.getFrameId(tip, body)
    frames = {pin.WORLD: robokit.Frame.WORLD, pin.LOCAL: robokit.Frame.LOCAL,
              pin.LOCAL_WORLD_ALIGNED: robokit.Frame.LOCAL_WORLD_ALIGNED}
    has_mass = ARMS[label][0] != "elephant"
    rng = np.random.default_rng(7)
    worst = dict(pose=0.0, J=0.0, M=0.0, g=0.0)
    for _ in range(12):
        q = rng.uniform(np.maximum(lo, -4.0), np.minimum(hi, 4.0))  # a continuous joint beyond ±π too
        qf = configuration(model, joints, q)
        pin.framesForwardKinematics(model, data, qf)
        for f in links:
            worst["pose"] = max(worst["pose"], np.abs(robot.frame_pose(q, f)
                                                      - data.oMf[model.getFrameId(f, body)].homogeneous).max())
        for ref, rk_ref in frames.items():
            J = pin.computeFrameJacobian(model, data, qf, fid, ref)[:, iv]
            J = np.vstack([J[3:], J[:3]])  # robokit: angular rows first
            worst["J"] = max(worst["J"], np.abs(robot.jacobian(q, reference=rk_ref) - J).max() / np.abs(J).max())
        M = pin.crba(model, data, qf)
        M = (np.triu(M) + np.triu(M, 1).T)[np.ix_(iv, iv)]
        g = pin.computeGeneralizedGravity(model, data, qf)[iv]
        if has_mass:
            worst["M"] = max(worst["M"], np.abs(robot.crba(q) - M).max() / np.abs(M).max())
            worst["g"] = max(worst["g"], np.abs(robot.gravity_torques(q) - g).max() / np.abs(g).max())
        else:  # the file gives no inertia: both are exactly zero, and robokit says so
            assert not M.any() and not g.any()
            assert not robot.crba(q).any() and not robot.gravity_torques(q).any()
    assert max(worst.values()) < 1e-12, worst

    assert sum("mesh files not found" in s for s in said) == 1, said  # meshes not vendored: one note
    assert sum("has mass (the file gives none)" in s for s in said) == (0 if has_mass else 1), said


@pytest.mark.parametrize("label, mimic, friction", [
    ("PincherX 100", "right_finger", "friction=0.1"),
    ("OpenManipulator-X, prefix, mock hardware", "l_gripper_right_joint", "damping=0.7"),
])
def test_what_robokit_says_once(label, mimic, friction):
    """The gripper's mimic finger is locked off the chain (Pinocchio's model has it at zero too), the
    joints' <dynamics> are kept but not in the rigid-body dynamics, the <ros2_control> block is not part of
    the model: one note each."""
    robot, said = load(label)
    assert mimic in robot.locked_joints
    notes = [s for s in said if "mimic joints off the chain locked" in s]
    assert len(notes) == 1 and mimic in notes[0], said
    notes = [s for s in said if "<dynamics> of joints" in s]
    assert len(notes) == 1 and friction in notes[0], said
    assert sum("<ros2_control>" in s for s in said) == 1, said
    assert len(said) == len(set(said))


def test_the_mycobot_urdf_says_what_it_is():
    """The myCobot's ``.urdf`` holds a ``<xacro:property>`` (ROS' URDF parser skips it) and velocity="0"
    on every joint: robokit says the first once and keeps the file's zero (as Pinocchio does)."""
    robot, said = load("myCobot 280 M5")
    assert sum("<xacro:property> read but not modelled" in s for s in said) == 1, said
    assert not robot.model.velocityLimit.any() and (robot.model.effortLimit == 1000.0).all()


@pytest.mark.parametrize("label, friction", [("PincherX 100", 0.1), ("OpenManipulator-X, prefix, mock hardware", 0.0)])
def test_mjcf_out_keeps_friction_and_effort_limits_as_mujoco_reads_the_urdf(label, friction, reference, tmp_path,
                                                                            capsys):
    """``robokit convert ARM -o arm.xml`` against MuJoCo reading the maker's URDF itself (the xacro program's
    expansion, meshes left out): per joint of the chain the same range, damping, dry friction
    (``frictionloss``, from ``<dynamics friction>``) and actuator force limit (``actuatorfrcrange``, from
    ``<limit effort>``). Before, the MJCF had neither (Interbotix's 0.1 N·m friction on joints whose effort
    limit is 1 to 2 N·m, and their effort limits, gone without a word); robokit reads the force range back
    as the effort limit and frictionloss as the dry friction (Pinocchio's on the URDF); and it says that MJCF
    has no velocity limits."""
    import re

    mujoco = pytest.importorskip("mujoco")
    from robokit.cli import main

    maker, rel, args, _, _ = ARMS[label]
    out = tmp_path / "arm.xml"
    argv = ["convert", str(DATA / maker / rel), "-o", str(out)]
    assert main(argv + [a for k, v in args.items() for a in ("--xacro-arg", f"{k}:={v}")]) == 0
    err = capsys.readouterr().err
    assert err.count("joint velocity limits not written") == 1
    urdf = re.sub(r"<visual>.*?</visual>|<collision>.*?</collision>|<ros2_control.*?</ros2_control>|"
                  r"<gazebo.*?</gazebo>|<transmission.*?</transmission>", "", reference[label], flags=re.S)
    ref, ours = mujoco.MjModel.from_xml_string(urdf), mujoco.MjModel.from_xml_path(str(out))
    robot, _ = load(label)
    for jn in robot.joint_names:
        a, b = (m.joint(jn) for m in (ref, ours))
        for m, j in ((ref, a), (ours, b)):
            assert m.jnt_limited[j.id] and m.jnt_actfrclimited[j.id]
        assert np.array_equal(a.range, b.range)
        assert np.array_equal(ref.jnt_actfrcrange[a.id], ours.jnt_actfrcrange[b.id])
        assert ref.dof_frictionloss[a.dofadr[0]] == ours.dof_frictionloss[b.dofadr[0]] == friction
        assert ref.dof_damping[a.dofadr[0]] == ours.dof_damping[b.dofadr[0]] > 0
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        back = robokit.load(out)  # and robokit reads its MJCF's effort limits back: the file's
    model = pin.buildModelFromXML(reference[label])
    iv = [model.joints[model.getJointId(j)].idx_v for j in robot.joint_names]
    assert np.array_equal(back.model.effortLimit, model.effortLimit[iv])
    # and its dry friction (frictionloss) back into model.friction, as the URDF's is (was dropped on reading)
    ib = [back.model.joints[back.model.getJointId(j)].idx_v for j in robot.joint_names]
    assert np.array_equal(back.model.friction[ib], model.friction[iv]) and (model.friction[iv] == friction).all()


def test_a_dh_table_out_says_what_it_cannot_hold(reference, tmp_path, capsys):
    """``robokit convert px100.urdf.xacro -o px100.yaml``: the DH table reproduces the file's kinematics
    (Pinocchio on the xacro program's URDF), but a DH file has no place for the joints' velocity and effort
    limits, damping or friction, and robokit loads it with placeholder limits (10 rad/s, 1000 N·m, where the
    PincherX 100's are π rad/s and 1 to 2 N·m). Before, nothing said so; now one note lists the file's values."""
    from robokit.cli import main

    maker, rel, _, _, _ = ARMS["PincherX 100"]
    out = tmp_path / "px100.yaml"
    assert main(["convert", str(DATA / maker / rel), "-o", str(out)]) == 0
    notes = [line for line in capsys.readouterr().err.splitlines() if "a DH table has no place" in line]
    model = pin.buildModelFromXML(reference["PincherX 100"])
    robot, _ = load("PincherX 100")
    iv = [model.joints[model.getJointId(j)].idx_v for j in robot.joint_names]
    listed = "; ".join(f"{what} {', '.join(f'{x:g}' for x in values[iv])}" for what, values in (
        ("velocity limits", model.velocityLimit), ("effort limits", model.effortLimit),
        ("damping", model.damping), ("friction", model.friction)))
    assert len(notes) == 1 and listed in notes[0], notes
    assert "velocity limits 3.14159, 3.14159, 3.14159, 3.14159; effort limits 1, 2, 2, 1" in listed
    table = robokit.load(out)
    assert table.model.velocityLimit.tolist() == [10.0] * 4  # the placeholders the note names
    data, fid = model.createData(), model.getFrameId(robot.tip)
    q = np.random.default_rng(1).uniform(*np.asarray(robot.qlim).T)
    qf = pin.neutral(model)
    qf[[model.joints[model.getJointId(j)].idx_q for j in robot.joint_names]] = q
    pin.framesForwardKinematics(model, data, qf)
    assert np.abs(table.frame_pose(q) - data.oMf[fid].homogeneous).max() < 1e-12


def test_a_dh_table_header_tells_the_written_tables_error(tmp_path):
    """The myCobot 280's frames are turned by 1.5708, not π/2: its DH angles lie up to 8e-10° from whole
    degrees, which the DH file writes as whole degrees (moving the flange by about 1e-11 m). The file's
    header said the table matched the URDF to 1.0e-15; it now gives the written table's error, which
    Pinocchio on the URDF file confirms."""
    from robokit.cli import main

    maker, rel, _, _, _ = ARMS["myCobot 280 M5"]
    out = tmp_path / "mycobot.yaml"
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        assert main(["convert", str(DATA / maker / rel), "-o", str(out)]) == 0
        robot = robokit.load(DATA / maker / rel)
    claimed = float(out.read_text().splitlines()[0].split("FK matches the URDF to ")[1].split()[0])
    table = robokit.load(out)
    model = pin.buildModelFromXML((DATA / maker / rel).read_text())
    data, fid = model.createData(), model.getFrameId(robot.tip)
    iq = [model.joints[model.getJointId(j)].idx_q for j in robot.joint_names]
    rng = np.random.default_rng(2)
    worst = 0.0
    for _ in range(200):
        q = rng.uniform(*np.asarray(robot.qlim).T)
        qf = pin.neutral(model)
        qf[iq] = q
        pin.framesForwardKinematics(model, data, qf)
        worst = max(worst, np.abs(table.frame_pose(q) - data.oMf[fid].homogeneous).max())
    assert 1e-12 < worst <= 1e-9 and worst <= 2 * claimed, (worst, claimed)


def test_a_users_own_part_through_external_urdf_loc(tmp_path):
    """Interbotix's ``external_urdf_loc`` includes a file of the user's (a camera on the wrist) from
    wherever it is: read because the user named it. The camera's frame and its mass in M and gravity agree
    with Pinocchio on the xacro program's expansion with the same arguments."""
    part = tmp_path / "camera.urdf.xacro"
    part.write_text(
        '<robot xmlns:xacro="http://ros.org/wiki/xacro">\n'
        '  <joint name="camera_mount" type="fixed"><parent link="$(arg robot_name)/ee_arm_link"/>'
        '<child link="$(arg robot_name)/camera_link"/><origin xyz="-0.02 0 0.06" rpy="0 0.4 0"/></joint>\n'
        '  <link name="$(arg robot_name)/camera_link"><inertial><origin xyz="0 0 0.01"/><mass value="0.12"/>'
        '<inertia ixx="2e-4" iyy="1e-4" izz="2e-4" ixy="0" ixz="0" iyz="0"/></inertial></link>\n</robot>\n')
    args = {"robot_name": "arm", "external_urdf_loc": str(part)}
    rel = XS + "wx250s.urdf.xacro"
    model = pin.buildModelFromXML(xacro_urdfs({"cam": (DATA / "interbotix", rel, args)})["cam"])
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        robot = robokit.load(DATA / "interbotix" / rel, xacro_args=args)
        bare = robokit.load(DATA / "interbotix" / rel, xacro_args={"robot_name": "arm"})
    data = model.createData()
    joints = [model.joints[model.getJointId(j)] for j in robot.joint_names]
    iq, iv = [j.idx_q for j in joints], [j.idx_v for j in joints]
    fid = model.getFrameId("arm/camera_link", pin.FrameType.BODY)
    q = np.random.default_rng(3).uniform(*np.asarray(robot.qlim).T)
    qf = pin.neutral(model)
    qf[iq] = q
    pin.framesForwardKinematics(model, data, qf)
    assert np.abs(robot.frame_pose(q, "arm/camera_link") - data.oMf[fid].homogeneous).max() < 1e-15
    M = pin.crba(model, data, qf)
    M = (np.triu(M) + np.triu(M, 1).T)[np.ix_(iv, iv)]
    g = pin.computeGeneralizedGravity(model, data, qf)[iv]
    assert np.abs(robot.crba(q) - M).max() < 1e-12 * np.abs(M).max()
    assert np.abs(robot.gravity_torques(q) - g).max() < 1e-12 * np.abs(g).max()
    assert np.abs(bare.gravity_torques(q) - g).max() > 1e-3 * np.abs(g).max()  # the camera's 120 g is in
