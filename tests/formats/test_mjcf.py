"""MJCF in and out, checked against MuJoCo itself (it defines the format), and the MuJoCo
dynamics comparisons on the shipped models, example-robot-data arms and test robots."""
import warnings

import numpy as np
import pinocchio as pin
import pytest

import robokit
from shared_robots import robot as shared_robot
from robokit.cli import main as cli_main
from robokit.description.mjcf import first_body_placement
from robokit.description.mjcf_write import joint_armature_damping, mjcf_from_robot

mujoco = pytest.importorskip("mujoco", reason="MuJoCo is an optional extra (pip install mujoco)")

from robokit.validation.mujoco_check import compare_with_mujoco  # noqa: E402

MUJOCO_WORST = []


@pytest.fixture(autouse=True)
def _share_worst(mujoco_worst):
    global MUJOCO_WORST
    MUJOCO_WORST = mujoco_worst

TOL = 1e-9

# A first body with no joint, offset and rotated (Pinocchio 4.1 drops that placement), gravity
# along −y, a hinge with armature and damping, an unaligned hinge, a slide joint, a site.
ARM_XML = """<mujoco model="test_arm">
  <compiler angle="degree"/>
  <option gravity="0 -9.81 0"/>
  <worldbody>
    <light pos="0 0 3"/>
    <geom type="plane" size="2 2 0.1"/>
    <body name="base" pos="0.1 0.2 0.05" {orientation}>
      <inertial pos="0 0 0" mass="3" diaginertia="0.1 0.1 0.1"/>
      <geom type="cylinder" size="0.06 0.05"/>
      <body name="upper" pos="0 0 0.1">
        <joint name="shoulder" type="hinge" axis="0 0 1" range="-150 150" armature="0.3" damping="0.7"/>
        <inertial pos="0.12 0.01 0" mass="2" fullinertia="0.02 0.05 0.06 0.001 0.002 0.003"/>
        <geom type="capsule" fromto="0 0 0 0.3 0 0" size="0.03"/>
        <body name="fore" pos="0.3 0 0" euler="0 30 0">
          <joint name="elbow" type="hinge" axis="0 1 1" range="-90 90" armature="0.05"/>
          <inertial pos="0.1 0 0.01" mass="1.2" diaginertia="0.004 0.01 0.012"/>
          <geom type="box" size="0.1 0.02 0.02" pos="0.1 0 0"/>
          <body name="slider" pos="0.2 0 0">
            <joint name="extend" type="slide" axis="1 0 0" range="-0.05 0.15" armature="0.8" damping="2"/>
            <inertial pos="0.05 0 0" mass="0.5" diaginertia="0.001 0.002 0.002"/>
            <site name="tool" pos="0.1 0 0.02" euler="0 0 45"/>
          </body>
        </body>
      </body>
    </body>
  </worldbody>
  <actuator><motor joint="shoulder"/></actuator>
</mujoco>
"""

ORIENTATIONS = {
    "euler": 'euler="10 -20 35"',
    "quat": 'quat="0.9 0.1 -0.2 0.3"',
    "axisangle": 'axisangle="1 2 3 40"',
    "xyaxes": 'xyaxes="0 1 0 -1 0 0.2"',
    "zaxis": 'zaxis="0.3 -0.4 1"',
    "none": "",
}


def _poses_vs_mujoco(robot, path, samples=10):
    """Largest difference of every named body and site pose between robokit and MuJoCo."""
    m = mujoco.MjModel.from_xml_path(str(path))
    d = mujoco.MjData(m)
    rng = np.random.default_rng(1)
    worst = 0.0
    for _ in range(samples):
        q = robot.random_configuration(rng)
        for jn, qi in zip(robot.joint_names, q):
            d.qpos[m.jnt_qposadr[mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_JOINT, jn)]] = qi
        mujoco.mj_kinematics(m, d)
        poses = robot.frame_poses(q)
        for b in range(1, m.nbody):
            T = poses[mujoco.mj_id2name(m, mujoco.mjtObj.mjOBJ_BODY, b)]
            worst = max(worst, np.abs(T[:3, 3] - d.xpos[b]).max(), np.abs(T[:3, :3] - d.xmat[b].reshape(3, 3)).max())
        for s in range(m.nsite):
            T = poses[mujoco.mj_id2name(m, mujoco.mjtObj.mjOBJ_SITE, s)]
            worst = max(worst, np.abs(T[:3, 3] - d.site_xpos[s]).max(),
                        np.abs(T[:3, :3] - d.site_xmat[s].reshape(3, 3)).max())
    return worst


@pytest.mark.parametrize("kind", sorted(ORIENTATIONS))
def test_first_jointless_body_is_placed_as_mujoco_places_it(kind, tmp_path):
    path = tmp_path / f"arm_{kind}.xml"
    path.write_text(ARM_XML.format(orientation=ORIENTATIONS[kind]))
    robot = robokit.load(path)
    assert robot.tip == "tool" and robot.joint_names == ("shoulder", "elbow", "extend")
    assert _poses_vs_mujoco(robot, path) < 1e-12
    # the placement robokit restores is MuJoCo's own body_pos / body_quat
    m = mujoco.MjModel.from_xml_path(str(path))
    name, X = first_body_placement(path)
    R = np.zeros(9)
    mujoco.mju_quat2Mat(R, m.body_quat[1])
    assert name == "base"
    assert np.abs(X[:3, 3] - m.body_pos[1]).max() < 1e-15 and np.abs(X[:3, :3] - R.reshape(3, 3)).max() < 1e-12


def test_pinocchio_alone_misplaces_the_first_body(tmp_path):
    """The defect robokit corrects (if a later Pinocchio fixes it, robokit leaves the model alone)."""
    path = tmp_path / "arm.xml"
    path.write_text(ARM_XML.format(orientation=""))
    model = pin.buildModelFromMJCF(str(path))
    data = model.createData()
    pin.framesForwardKinematics(model, data, pin.neutral(model))
    raw = data.oMf[model.getFrameId("upper")].translation
    fixed = robokit.load(path).frame_pose(np.zeros(3), "upper")[:3, 3]
    if np.allclose(raw, fixed):
        pytest.skip("this Pinocchio places the first body correctly")
    assert np.allclose(fixed - raw, [0.1, 0.2, 0.05])


def test_armature_gravity_and_limits_are_read(tmp_path):
    path = tmp_path / "arm.xml"
    path.write_text(ARM_XML.format(orientation=ORIENTATIONS["euler"]))
    robot = robokit.load(path)
    arm, damp = joint_armature_damping(robot)
    assert np.array_equal(arm, [0.3, 0.05, 0.8]) and np.array_equal(damp, [0.7, 0.0, 2.0])
    assert np.array_equal(robot.gravity, [0.0, -9.81, 0.0])
    m = mujoco.MjModel.from_xml_path(str(path))
    assert np.allclose(robot.qlim, m.jnt_range, rtol=0, atol=1e-15)  # slide range in m, hinge ranges in rad
    assert np.allclose(robot.qlim[2], [-0.05, 0.15], rtol=0, atol=1e-15)


def test_ignored_elements_are_noted(tmp_path):
    path = tmp_path / "arm.xml"
    path.write_text(ARM_XML.format(orientation="").replace("</worldbody>", '<body name="extra" pos="1 0 0">'
                    '<joint name="x" type="hinge"/><inertial pos="0 0 0" mass="1" diaginertia="1 1 1"/></body>'
                    "</worldbody>"))
    with pytest.warns(UserWarning) as record:
        robokit.load(path)
    msgs = " | ".join(str(w.message) for w in record)
    assert "<actuator> ignored (motor)" in msgs and "<body name='extra'> ignored" in msgs


def _record(c, what):
    MUJOCO_WORST.append((c.worst, what))
    return c.worst


def test_mujoco_on_the_test_file_itself(tmp_path):
    """MuJoCo reading the file vs robokit reading it: armature, damping, a slide joint, the
    jointless first body, gravity along −y."""
    path = tmp_path / "arm.xml"
    path.write_text(ARM_XML.format(orientation=ORIENTATIONS["axisangle"]))
    robot = robokit.load(path)
    c = compare_with_mujoco(robot, path.read_text(), samples=30, rng=0)
    assert c.frames == 5  # base, upper, fore, slider bodies and the tool site
    assert _record(c, "test_arm MJCF file") < TOL, c


ROBOTS = ["twolink", "rrr", "puma560", "ur5", "panda", "z1", "xarm7", "kinova"]


@pytest.mark.parametrize("name", ROBOTS)
def test_mujoco_agrees_with_pinocchio_and_course_code(name):
    c = compare_with_mujoco(name, samples=15, rng=7)
    assert c.frames >= 3
    if name == "puma560":  # armature G²Jm, damping G²B; links 1 and 3 carry inertials MuJoCo's compiler refuses
        assert sorted(c.restored) == ["link_1", "link_3"]
    assert _record(c, name) < TOL, c


def test_mujoco_on_dh_robot_with_prismatic_joint_and_armature(dh_table):
    robot = robokit.load(dh_table(np.random.default_rng(11), 4, "modified", prismatic=(1,), drives=True))
    arm, damp = joint_armature_damping(robot)
    assert np.all(arm > 0) and np.all(damp > 0)
    text, _ = mjcf_from_robot(robot)
    assert text.count('type="slide"') == 1 and text.count("armature=") == 4
    c = compare_with_mujoco(robot, text, samples=20, rng=2)
    assert _record(c, "random modified-DH RPRR with armature") < TOL, c


@pytest.mark.parametrize("name", ["twolink", "rrr", "puma560"])
def test_dh_to_mjcf_round_trip_equals_dh_to_urdf(name, tmp_path, capsys):
    out = tmp_path / f"{name}.xml"
    assert cli_main(["convert", name, "-o", str(out)]) == 0
    err = capsys.readouterr().err
    if name == "puma560":
        assert "link_3" in err and "Coulomb" in err  # what MuJoCo alone sees differently is said
    mujoco.MjModel.from_xml_path(str(out))  # MuJoCo accepts the file
    via_urdf = shared_robot(name)
    via_mjcf = robokit.load(out)
    assert via_mjcf.tip == "tool" and via_mjcf.n == via_urdf.n
    arm, _ = joint_armature_damping(via_urdf)
    rng = np.random.default_rng(5)
    worst = 0.0
    for _ in range(30):
        q = via_urdf.random_configuration(rng)
        v, a = rng.normal(size=via_urdf.n), rng.normal(size=via_urdf.n)
        worst = max(worst, np.abs(via_mjcf.frame_pose(q) - via_urdf.frame_pose(q)).max())
        # the MJCF carries the armature G²Jm, which Pinocchio's crba/rnea include
        worst = max(worst, np.abs(via_mjcf.crba(q) - via_urdf.crba(q) - np.diag(arm)).max())
        worst = max(worst, np.abs(via_mjcf.rnea(q, v, a) - via_urdf.rnea(q, v, a) - arm * a).max())
    assert worst < 1e-12


def test_dh_round_trip_with_prismatic_joint(dh_table, tmp_path):
    table = dh_table(np.random.default_rng(4), 5, "standard", prismatic=(2,))
    robot = robokit.load(table)
    path = tmp_path / "rand.xml"
    path.write_text(mjcf_from_robot(robot)[0])
    back = robokit.load(path)
    rng = np.random.default_rng(0)
    for _ in range(20):
        q = robot.random_configuration(rng)
        v, a = rng.normal(size=5), rng.normal(size=5)
        assert np.abs(back.frame_pose(q) - robot.frame_pose(q)).max() < 1e-12
        M, tau = robot.crba(q), robot.rnea(q, v, a)
        assert np.abs(back.crba(q) - M).max() <= 1e-12 * max(1.0, np.abs(M).max())
        assert np.abs(back.rnea(q, v, a) - tau).max() <= 1e-12 * max(1.0, np.abs(tau).max())


def test_view_of_an_mjcf_file(tmp_path, capsys):
    path = tmp_path / "arm.xml"
    path.write_text(ARM_XML.format(orientation=ORIENTATIONS["euler"]))
    page = tmp_path / "arm.html"
    assert cli_main(["view", str(path), "-o", str(page)]) == 0, capsys.readouterr().err
    assert page.stat().st_size > 1000


def test_exported_meshes_are_stl_files_mujoco_reads(tmp_path):
    text, notes = mjcf_from_robot("ur5")
    assert "<mesh " in text and ".dae" not in text
    assert any(".dae" in n for n in notes)
    m = mujoco.MjModel.from_xml_string(text)
    assert m.nmesh > 0


BAD_MJCF = {
    "bad_xml.xml": ("<mujoco>\n<worldbody>\n<body name='a'>\n</worldbody></mujoco>", ["bad_xml.xml:4:", "not well-formed"]),
    "urdf_root.xml": ('<robot name="r"><link name="a"/></robot>', ["urdf_root.xml", "<robot>", "<mujoco>"]),
    "empty.xml": ("<mujoco><worldbody/></mujoco>", ["empty.xml", "no <body>"]),
    "bad_pos.xml": ('<mujoco><worldbody><body name="b" pos="1 x 2"><body name="c"><joint type="hinge"/>'
                    '<inertial pos="0 0 0" mass="1" diaginertia="1 1 1"/></body></body></worldbody></mujoco>',
                    ["bad_pos.xml", "<body name='b'>", "pos='1 x 2'"]),
    "bad_quat.xml": ('<mujoco><worldbody><body name="b" quat="1 0 0"><body name="c"><joint type="hinge"/>'
                     '<inertial pos="0 0 0" mass="1" diaginertia="1 1 1"/></body></body></worldbody></mujoco>',
                     ["bad_quat.xml", "<body name='b'>", "quat", "expected 4 numbers"]),
    "free.xml": ('<mujoco><worldbody><body name="b"><freejoint/><inertial pos="0 0 0" mass="1" diaginertia="1 1 1"/>'
                 "</body></worldbody></mujoco>", ["floating base"]),
    # an ant: a free root and two equal legs was told to choose a tip, and every tip was then refused as floating
    "free_tree.xml": ('<mujoco><worldbody><body name="torso"><freejoint name="root"/><geom size="0.2"/>'
                      + "".join(f'<body name="leg{k}" pos="{k} 0 0"><joint name="hip{k}"/><geom size="0.1"/>'
                                f'<body name="foot{k}" pos="0.3 0 0"><joint name="knee{k}"/><geom size="0.1"/></body></body>'
                                for k in (1, 2))
                      + "</body></worldbody></mujoco>", ["'root'", "floating base", "every chain"]),
}


@pytest.mark.parametrize("name", sorted(BAD_MJCF))
def test_malformed_mjcf_one_line_exit_2(name, tmp_path, capsys):
    text, expected = BAD_MJCF[name]
    src = tmp_path / name
    src.write_text(text)
    out = tmp_path / "out.json"
    rc = cli_main(["convert", str(src), "-o", str(out)])
    err = capsys.readouterr().err
    lines = err.strip().splitlines()
    assert rc == 2 and len(lines) == 1 and lines[0].startswith("robokit: error:"), err
    for piece in expected:
        assert piece in lines[0], (piece, lines[0])
    assert not out.exists() and list(tmp_path.iterdir()) == [src]


def test_mjcf_output_is_atomic(tmp_path, capsys):
    out = tmp_path / "missing_dir" / "x.xml"
    assert cli_main(["convert", "rrr", "-o", str(out)]) == 2
    assert "does not exist" in capsys.readouterr().err
    good = tmp_path / "rrr.xml"
    good.write_text("previous")
    assert cli_main(["convert", "no_such_robot", "-o", str(good)]) == 2
    assert good.read_text() == "previous"


def test_slide_range_from_a_default_class(tmp_path):
    """Slide ranges are metres whatever <compiler angle> says, also when set by a default class."""
    path = tmp_path / "classes.xml"
    path.write_text("""<mujoco><default><joint damping="0.1"/><default class="rail"><joint type="slide" range="-0.1 0.3"/>
      </default></default>
      <worldbody><body name="a"><joint name="turn" type="hinge" axis="0 0 1" range="-45 45"/>
        <inertial pos="0 0 0" mass="1" diaginertia="0.1 0.1 0.1"/>
        <body name="b" pos="0.2 0 0" childclass="rail"><joint name="rail" axis="1 0 0"/>
          <inertial pos="0 0 0" mass="1" diaginertia="0.1 0.1 0.1"/></body></body></worldbody></mujoco>""")
    robot = robokit.load(path)
    m = mujoco.MjModel.from_xml_path(str(path))
    assert np.allclose(robot.qlim, m.jnt_range, rtol=0, atol=1e-15)
    assert np.allclose(joint_armature_damping(robot)[1], m.dof_damping, rtol=0, atol=0)


PASSIVE_ARM = """<mujoco model="passive_arm">
  <compiler angle="radian"/>
  <default><joint damping="0.1" stiffness="1" frictionloss="0.1" armature="0.1"/></default>
  <worldbody>
    <body name="l1" pos="0 0 0.1">
      <inertial pos="0.1 0 0" mass="1" diaginertia="0.01 0.02 0.03"/>
      <joint name="j1" axis="0 0 1"/>
      <body name="l2" pos="0.2 0 0" quat="0.7071068 0.7071068 0 0">
        <inertial pos="0.1 0.02 0" mass="0.5" diaginertia="0.004 0.005 0.006"/>
        <joint name="j2" axis="0 0 1"/>
        <body name="l3" pos="0.2 0 0">
          <inertial pos="0.05 0 0.01" mass="0.3" diaginertia="0.001 0.002 0.002"/>
          <joint name="j3" axis="0 1 0" stiffness="10" springdamper="0 0"/>
          <site name="tip" pos="0.1 0 0"/>
        </body>
      </body>
    </body>
  </worldbody>
</mujoco>
"""


def test_joint_friction_and_springs_are_noted_once_per_attribute(tmp_path):
    """AgileX's PiPER in MuJoCo Menagerie (agilex_piper/piper.xml) gives every joint frictionloss and
    stiffness through its <default>: robokit printed one note per joint and attribute (18 for the
    PiPER), without saying why. Now one note per attribute lists the joints and values, and the
    robot is MuJoCo's rigid-body dynamics (passive forces and constraints off in MuJoCo)."""
    path = tmp_path / "passive.xml"
    path.write_text(PASSIVE_ARM)
    with pytest.warns(UserWarning) as record:
        robot = robokit.load(path)
    said = [str(w.message) for w in record if "<joint>" in str(w.message)]
    assert said == [
        f"{path}: <joint> frictionloss of joints 'j1', 'j2', 'j3' [0.1] ignored: robokit's rigid-body dynamics "
        "has no joint friction (MuJoCo applies it through its constraint solver); the values stay in "
        "robot.model.friction, as a URDF's <dynamics friction>",
        f"{path}: <joint> stiffness of joints 'j1', 'j2', 'j3' [1, 10] ignored: robokit's rigid-body dynamics has "
        "no joint springs (a passive force in MuJoCo, not part of its bias force or mass matrix)"]
    mujoco = pytest.importorskip("mujoco")
    m = mujoco.MjModel.from_xml_path(str(path))
    m.opt.disableflags |= int(mujoco.mjtDisableBit.mjDSBL_CONSTRAINT)
    for flag in ("mjDSBL_PASSIVE", "mjDSBL_SPRING", "mjDSBL_DAMPER"):
        m.opt.disableflags |= int(getattr(mujoco.mjtDisableBit, flag, 0))
    rng = np.random.default_rng(3)
    d = mujoco.MjData(m)
    for _ in range(5):
        q, dq, ddq = rng.uniform(-2, 2, 3), rng.standard_normal(3), rng.standard_normal(3)
        d.qpos[:], d.qvel[:], d.qacc[:] = q, dq, ddq
        mujoco.mj_inverse(m, d)
        np.testing.assert_allclose(robot.rnea(q, dq, ddq), d.qfrc_inverse, rtol=0, atol=1e-12)
        np.testing.assert_allclose(robot.rnea(q, dq, np.zeros(3)), d.qfrc_bias, rtol=0, atol=1e-12)


GRAVCOMP_ARM = """<mujoco model="compensated_arm">
  <compiler angle="radian"/>
  <option gravity="1 -4 -9.81"/>
  <default><default class="arm"><joint axis="0 0 1" armature="0.01" damping="0.2"/></default></default>
  <worldbody>
    <body name="base" childclass="arm" gravcomp="1">
      <inertial pos="0 0 0.05" mass="1" diaginertia="0.01 0.01 0.01"/>
      <body name="l1" pos="0 0 0.1" gravcomp="1">
        <inertial pos="0.1 0 0.02" mass="1" diaginertia="0.01 0.02 0.03"/>
        <joint name="j1"/>
        <body name="l2" pos="0.2 0 0" quat="0.7071068 0.7071068 0 0" gravcomp="0.5">
          <inertial pos="0.1 0.02 0" mass="0.5" diaginertia="0.004 0.005 0.006"/>
          <joint name="j2"/>
          <body name="l3" pos="0.2 0 0" gravcomp="1">
            <inertial pos="0.05 0 0.01" mass="0.3" diaginertia="0.001 0.002 0.002"/>
            <joint name="j3" axis="0 1 0" actuatorgravcomp="true"/>
            <site name="tip" pos="0.1 0 0"/>
          </body>
        </body>
      </body>
    </body>
  </worldbody>
</mujoco>
"""


def test_body_gravcomp_is_noted_once_for_every_body(tmp_path):
    """AgileX's PiPER in MuJoCo Menagerie (agilex_piper/piper.xml) sets gravcomp="1" on each of its
    9 bodies: robokit printed 9 notes, one per body, each saying only that gravcomp was ignored. Now
    one note lists the bodies and values and says what robokit computes instead: the bodies' full
    weight, which is MuJoCo's inverse dynamics with the compensation force (a passive force that
    mj_inverse leaves out) added back."""
    path = tmp_path / "gravcomp.xml"
    path.write_text(GRAVCOMP_ARM)
    with pytest.warns(UserWarning) as record:
        robot = robokit.load(path)
    said = [str(w.message) for w in record if "gravcomp" in str(w.message)]
    assert said == [
        f"{path}: <body> gravcomp of bodies 'base', 'l1', 'l2', 'l3' [1, 0.5] ignored: robokit's dynamics has no "
        "gravity compensation force (its gravity torques and inverse dynamics carry these bodies' full weight; "
        "MuJoCo counts the compensation as a passive force, which mj_inverse leaves out unless the joint has "
        "actuatorgravcomp)"]
    m = mujoco.MjModel.from_xml_path(str(path))
    m.opt.disableflags |= int(mujoco.mjtDisableBit.mjDSBL_CONSTRAINT)
    d = mujoco.MjData(m)
    rng = np.random.default_rng(5)
    for _ in range(5):
        q, dq, ddq = rng.uniform(-2, 2, 3), rng.standard_normal(3), rng.standard_normal(3)
        d.qpos[:], d.qvel[:], d.qacc[:] = q, dq, ddq
        mujoco.mj_inverse(m, d)
        assert np.abs(d.qfrc_passive + m.dof_damping * dq).max() > 0.1  # MuJoCo does compensate
        # qfrc_inverse is M q̈ + c + g minus the passive force: −b q̇, and the compensation except on j3,
        # whose compensation goes to its actuator (actuatorgravcomp); armature in M
        full = d.qfrc_inverse + d.qfrc_passive
        np.testing.assert_allclose(full, d.qfrc_inverse + d.qfrc_gravcomp * [1, 1, 0] - m.dof_damping * dq,
                                   rtol=0, atol=1e-12)
        np.testing.assert_allclose(robot.rnea(q, dq, ddq), full, rtol=0, atol=1e-12)


def test_every_worldbody_section_is_read(tmp_path):
    """MuJoCo merges every <worldbody> of a file into the world, in order. A scene that includes an
    arm's file after its own <worldbody> was refused by robokit, which read only the first section:
    '<worldbody> has no <body>; nothing to load' when that section holds a floor, 'the chain to
    'table' has no moving joint' when it also holds a table (MuJoCo Menagerie's scene.xml files put
    the include first, so their floor section was the one skipped). Now the sections are read in
    order: the bodies are MuJoCo's, in MuJoCo's order, and the arm in the second section is the
    robot, with MuJoCo's tip pose, mass matrix and inverse dynamics."""
    (tmp_path / "arm.xml").write_text(PASSIVE_ARM.replace(' stiffness="1" frictionloss="0.1"', "")
                                      .replace(' stiffness="10" springdamper="0 0"', ""))
    path = tmp_path / "scene.xml"
    path.write_text("""<mujoco model="scene">
  <worldbody>
    <light pos="0 0 1.5" dir="0 0 -1" directional="true"/>
    <geom name="floor" size="0 0 0.05" type="plane"/>
    <body name="table" pos="0.5 0 0.3"><geom type="box" size="0.2 0.2 0.02"/></body>
  </worldbody>
  <include file="arm.xml"/>
  <worldbody>
    <body name="cup" pos="0.5 0 0.4"><geom size="0.03"/></body>
  </worldbody>
</mujoco>
""")
    from robokit.description.mjcf_compile import compile_mjcf
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        robot = robokit.load(path)
    m = mujoco.MjModel.from_xml_path(str(path))
    assert [b.name for b in compile_mjcf(path).bodies] == [
        mujoco.mj_id2name(m, mujoco.mjtObj.mjOBJ_BODY, i) for i in range(m.nbody)]
    assert robot.joint_names == ("j1", "j2", "j3") and robot.tip == "tip"
    m.opt.disableflags |= int(mujoco.mjtDisableBit.mjDSBL_CONSTRAINT)
    d = mujoco.MjData(m)
    rng = np.random.default_rng(6)
    for _ in range(5):
        q, dq, ddq = rng.uniform(-2, 2, 3), rng.standard_normal(3), rng.standard_normal(3)
        d.qpos[:], d.qvel[:], d.qacc[:] = q, dq, ddq
        mujoco.mj_inverse(m, d)
        M = np.zeros((3, 3))
        mujoco.mj_fullM(m, d, M)
        T = robot.frame_pose(q)
        np.testing.assert_allclose(T[:3, 3], d.site_xpos[0], rtol=0, atol=1e-12)
        np.testing.assert_allclose(T[:3, :3], d.site_xmat[0].reshape(3, 3), rtol=0, atol=1e-12)
        np.testing.assert_allclose(robot.crba(q), M, rtol=0, atol=1e-12)
        np.testing.assert_allclose(robot.rnea(q, dq, ddq), d.qfrc_inverse - m.dof_damping * dq, rtol=0, atol=1e-12)


def test_contact_excludes_are_read_so_not_noted_as_ignored(tmp_path):
    """robosuite's Baxter has only <contact><exclude> pairs, which robokit reads into
    ``robot.contact_rules``; the note said '<contact> ignored (exclude)'. A <pair>, which robokit does
    not model, is still noted."""
    xml = ('<mujoco><worldbody><body name="a"><joint name="j1"/><geom name="ga" size="0.1"/>'
           '<body name="b" pos="0.3 0 0"><joint name="j2"/><geom size="0.1"/></body></body>'
           '<body name="c" pos="1 0 0"><geom name="gc" size="0.1"/></body></worldbody>'
           '<contact><exclude body1="a" body2="b"/>{pair}</contact></mujoco>')
    path = tmp_path / "arm.xml"
    path.write_text(xml.format(pair=""))
    with warnings.catch_warnings(record=True) as record:
        warnings.simplefilter("always")
        robot = robokit.load(path)
    m = mujoco.MjModel.from_xml_path(str(path))
    assert m.nexclude == 1 and robot.contact_rules.excluded == {frozenset({"a", "b"})}
    assert not [w for w in record if "<contact>" in str(w.message)]
    path.write_text(xml.format(pair='<pair geom1="gc" geom2="ga"/>'))
    assert mujoco.MjModel.from_xml_path(str(path)).npair == 1
    with pytest.warns(UserWarning, match=r"<contact> ignored \(pair\)"):
        robokit.load(path)
