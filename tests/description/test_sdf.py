"""SDFormat files (robokit.description.sdf) against independent engines and hand computations.

* ``pybullet_data/kuka_iiwa/model.sdf`` (a world with one model, SDFormat 1.6) against PyBullet's own
  ``loadSDF``: link poses, ``calculateMassMatrix``, ``calculateInverseDynamics``, to 1e-9;
* a test arm written for these tests (tests/data/sdf/arm: ``relative_to`` frames, a ``<frame>``, an
  axis expressed in the model frame, a nested model, an ``<include>`` of ``model://wrist``) against
  Pinocchio's URDF parser on the same arm written by hand as URDF, to 1e-9;
* Drake's iiwa14 SDF (tests/data/sdf/drake_iiwa14) with ``drake:rotor_inertia``/``drake:gear_ratio``
  against its URDF twin read by Pinocchio plus ``rotor_inertia · gear_ratio²`` computed here from the
  file's text;
* SDFormat 1.4–1.6 axis rules and ``placement_frame``, by hand;
* hostile twins (an include outside the package folders, an include cycle, deep nesting, a huge file,
  entities, too many joints) refused with one line.
"""
import math
import os
import pickle
import subprocess
import sys
import warnings
import xml.etree.ElementTree as ET
from pathlib import Path

import numpy as np
import pytest

import robokit
from pybullet_sdf import assert_matches_pybullet_sdf  # tests/support
from robokit.errors import InputError, RobokitWarning

pin = pytest.importorskip("pinocchio")

DATA = Path(__file__).resolve().parents[1] / "data" / "sdf"
ARM, ARM_MODELS = DATA / "arm" / "arm.sdf", DATA / "arm" / "models"
IIWA = DATA / "drake_iiwa14" / "iiwa14_no_collision.sdf"


def load_quiet(*args, **kw):
    """robokit.load with the notes collected: (robot, [note text])."""
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        robot = robokit.load(*args, **kw)
    return robot, [str(w.message) for w in caught if issubclass(w.category, RobokitWarning)]


def rot(axis, angle):
    a = np.asarray(axis, float) / np.linalg.norm(axis)
    K = np.array([[0, -a[2], a[1]], [a[2], 0, -a[0]], [-a[1], a[0], 0]])
    return np.eye(3) + math.sin(angle) * K + (1 - math.cos(angle)) * K @ K


# --------------------------------------------------------------------------- PyBullet
def test_kuka_iiwa_model_sdf_equals_pybullet_loadsdf():
    """Link poses, Jacobians, M, inverse dynamics and gravity torques of pybullet_data's kuka model.sdf
    equal PyBullet's, to 1e-9 (tests/support/pybullet_sdf.py: PyBullet's loadSDF recomputes each link's
    inertia, so the file's, diagonal in axes aligned with the link here, is set back from its text)."""
    pytest.importorskip("pybullet")
    import pybullet_data

    path = Path(pybullet_data.getDataPath()) / "kuka_iiwa" / "model.sdf"
    robot, notes = load_quiet(path)
    assert robot.n == 7 and robot.joint_names == tuple(f"lbr_iiwa_joint_{i}" for i in range(1, 8))
    assert any("world gravity is SDFormat's default" in n for n in notes)
    np.testing.assert_array_equal(robot.gravity, [0.0, 0.0, -9.8])
    rng = np.random.default_rng(7)
    states = [(robot.random_configuration(rng), rng.normal(size=7), rng.normal(size=7)) for _ in range(5)]
    assert assert_matches_pybullet_sdf(robot, path, states, atol=1e-9) == 5


# Gazebo writes "no limit" as ±1.79769e+308 (its wheel joints: gz-sim's vehicles, sdformat's
# test/integration/model/robot/model.sdf) or inf (sdformat's test/sdf/joint_axis_infinite_limits.sdf);
# libsdformat, Drake and PyBullet read both. The base has no mass: PyBullet then fixes it.
UNLIMITED_SDF = """<sdf version="1.6"><model name="wheels">
  <link name="base"><inertial><mass>0</mass><inertia><ixx>0</ixx><iyy>0</iyy><izz>0</izz></inertia></inertial></link>
  <link name="a"><pose>0.1 0 0.2 0 0 0</pose><inertial><pose>0.02 0 0 0 0 0</pose><mass>1</mass>
    <inertia><ixx>0.01</ixx><iyy>0.02</iyy><izz>0.03</izz></inertia></inertial></link>
  <link name="b"><pose>0.1 0.3 0.2 0 0 0</pose><inertial><pose>0 0.1 0 0 0 0</pose><mass>0.5</mass>
    <inertia><ixx>0.004</ixx><iyy>0.005</iyy><izz>0.006</izz></inertia></inertial></link>
  <joint name="j1" type="revolute"><parent>base</parent><child>a</child>
    <axis><xyz>0 0 1</xyz><limit><lower>-1.79769e+308</lower><upper>1.79769e+308</upper></limit></axis></joint>
  <joint name="j2" type="revolute"><parent>a</parent><child>b</child>
    <axis><xyz>0 1 0</xyz><limit><lower>-inf</lower><upper>inf</upper><effort>inf</effort><velocity>inf</velocity></limit>
    </axis></joint>
</model></sdf>"""


def test_unlimited_joints_as_gazebo_writes_them_equal_pybullet(tmp_path):
    """±1.79769e+308 and ±inf limits load as no limit (were refused: "numbers must be finite and at
    most 1e17 in size"); poses, Jacobians, M, inverse dynamics and gravity are PyBullet loadSDF's."""
    p = pytest.importorskip("pybullet")
    path = tmp_path / "wheels.sdf"
    path.write_text(UNLIMITED_SDF)
    robot, _ = load_quiet(path)
    assert robot.joint_names == ("j1", "j2")
    assert np.all(np.isinf(robot.qlim)) and robot.qlim[0, 0] < 0 < robot.qlim[0, 1]
    assert np.isinf(robot.model.velocityLimit[1]) and np.isinf(robot.model.effortLimit[1])
    with pytest.raises(InputError, match="expected a number"):
        (tmp_path / "nan.sdf").write_text(UNLIMITED_SDF.replace("<upper>inf</upper>", "<upper>nan</upper>"))
        robokit.load(tmp_path / "nan.sdf")
    cid = p.connect(p.DIRECT)
    try:
        body = p.loadSDF(str(path), physicsClientId=cid)[0]
        for i in range(2):
            lo, hi = p.getJointInfo(body, i, physicsClientId=cid)[8:10]
            assert lo <= -1e16 and hi >= 1e16
    finally:
        p.disconnect(cid)
    rng = np.random.default_rng(3)
    states = [(rng.uniform(-7, 7, size=2), rng.normal(size=2), rng.normal(size=2))  # beyond ±2π: nothing bounds them
              for _ in range(5)]
    assert assert_matches_pybullet_sdf(robot, path, states) == 5


# --------------------------------------------------------------------------- the test arm
ARM_LINKS = ("base", "link1", "forearm::link2", "forearm::link3", "wrist::link4", "wrist::tool")


@pytest.fixture(scope="module")
def arm():
    robot, notes = load_quiet(ARM, package_dirs=[ARM_MODELS])
    return robot, notes


def test_arm_sdf_equals_its_urdf_twin(arm):
    """relative_to frames, a <frame>, an axis in the model frame, a nested model and an include: FK of every
    link, the Jacobian, M and RNEA equal Pinocchio's on the hand-written URDF twin, to 1e-9."""
    robot, _ = arm
    ref = pin.buildModelFromUrdf(str(ARM.with_suffix(".urdf")))
    data = ref.createData()
    assert robot.joint_names == ("j1", "j2", "forearm::j3", "j4")
    assert robot.tip == "wrist::tool"
    assert robot.model.joints[4].shortname() == "JointModelRUBZ" and robot.model.nq == 5  # j4 is continuous
    rng = np.random.default_rng(3)
    for _ in range(5):
        q = robot.random_configuration(rng)
        dq, ddq = rng.normal(size=4), rng.normal(size=4)
        qp = robot.q_pin(q)
        pin.framesForwardKinematics(ref, data, qp)
        for name in ARM_LINKS:
            np.testing.assert_allclose(robot.frame_pose(q, name), data.oMf[ref.getFrameId(name)].homogeneous,
                                       atol=1e-9)
        pin.computeJointJacobians(ref, data, qp)
        J_ref = pin.getFrameJacobian(ref, data, ref.getFrameId("wrist::tool"), pin.LOCAL_WORLD_ALIGNED)
        J = robot.jacobian(q, "wrist::tool", reference="local_world_aligned")
        np.testing.assert_allclose(J, np.vstack([J_ref[3:], J_ref[:3]]), atol=1e-9)
        np.testing.assert_allclose(robot.crba(q), pin.crba(ref, data, qp), atol=1e-9)
        np.testing.assert_allclose(robot.rnea(q, dq, ddq), pin.rnea(ref, data, qp, dq, ddq), atol=1e-9)
    for attr in ("lowerPositionLimit", "upperPositionLimit", "effortLimit", "velocityLimit", "damping",
                 "upperDryFrictionLimit"):
        np.testing.assert_array_equal(getattr(robot.model, attr), getattr(ref, attr), err_msg=attr)


def test_arm_frames_are_where_the_file_puts_them(arm):
    """<frame> elements are operational frames: elbow_mount is 0.3 m up link1 turned 0.3 rad about z;
    wrist::tcp is 0.02 m along the tool's z; forearm::wrist_base is where the wrist is included."""
    robot, _ = arm
    q = np.array([0.4, -0.7, 0.05, 1.1])
    T_l1 = robot.frame_pose(q, "link1")
    T_em = np.eye(4)
    T_em[:3, :3], T_em[:3, 3] = rot([0, 0, 1], 0.3), [0, 0, 0.3]
    np.testing.assert_allclose(robot.frame_pose(q, "elbow_mount"), T_l1 @ T_em, atol=1e-12)
    np.testing.assert_allclose(robot.frame_pose(q, "wrist::tcp"), robot.frame_pose(q, "wrist::tool") @
                               np.array([[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 0.02], [0, 0, 0, 1.0]]), atol=1e-12)
    qz = q.copy()
    qz[3] = 0.0  # j4 at zero: link4 sits at the include's pose
    np.testing.assert_allclose(robot.frame_pose(qz, "forearm::wrist_base"), robot.frame_pose(qz, "wrist::link4"),
                               atol=1e-12)


def test_arm_notes_and_geometry(arm):
    robot, notes = arm
    unmodelled = [n for n in notes if "read but not modelled" in n]
    assert len(unmodelled) == 1 and "<plugin> in <model>" in unmodelled[0] and "<sensor> in <link>" in unmodelled[0]
    assert any("base fixed to the world" in n for n in notes)
    vis = {o.name: o for o in robot.visual_model.geometryObjects}
    assert set(vis) == {"base_0", "forearm::link3_0", "wrist::link4_0"}
    np.testing.assert_allclose(vis["base_0"].meshColor, [0.3, 0.3, 0.35, 1.0], atol=1e-7)
    np.testing.assert_allclose(2 * vis["forearm::link3_0"].geometry.halfSide, [0.1, 0.05, 0.05])
    col = robot.collision_model.geometryObjects
    assert [o.name for o in col] == ["link1_0"] and col[0].meshPath == "CYLINDER"


def test_arm_spec_rebuilds_in_another_process(arm, tmp_path):
    """robot.spec (kind 'sdf', with the package folder) rebuilds the same arm in a fresh process."""
    robot, _ = arm
    assert robot.spec.kind == "sdf" and robot.spec.package_dirs == (str(ARM_MODELS.resolve()),)
    spec_file = tmp_path / "spec.pkl"
    spec_file.write_bytes(pickle.dumps(robot.spec))
    q = np.array([0.3, 0.2, 0.1, -0.5])
    code = ("import pickle, sys, warnings, numpy as np, robokit; warnings.simplefilter('ignore'); "
            "r = robokit.load(pickle.loads(open(sys.argv[1], 'rb').read())); q = np.array(sys.argv[2:], float); "
            "print(repr(np.r_[r.frame_pose(q).ravel(), r.crba(q).ravel()].tolist()))")
    out = subprocess.run([sys.executable, "-c", code, str(spec_file), *map(str, q)], capture_output=True, text=True,
                         check=True, timeout=120, cwd=tmp_path)
    values = np.array(eval(out.stdout.strip().splitlines()[-1]))
    np.testing.assert_allclose(values, np.r_[robot.frame_pose(q).ravel(), robot.crba(q).ravel()], atol=1e-14)


def test_convert_an_sdf_from_the_command_line(tmp_path):
    """`robokit convert arm.sdf --package-path models -o arm.json` goes through load."""
    from robokit.cli import main

    out = tmp_path / "arm.json"
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        assert main(["convert", str(ARM), "--package-path", str(ARM_MODELS), "-o", str(out)]) == 0
    assert "forearm::j3" in out.read_text()


# --------------------------------------------------------------------------- Drake's iiwa14
def _drake_reflected(path):
    """rotor_inertia · gear_ratio² per joint, from the file's text."""
    tree = ET.parse(path)
    ns = "{http://drake.mit.edu}"
    return np.array([float(j.findtext(f"{ns}rotor_inertia")) * float(j.findtext(f"{ns}gear_ratio")) ** 2
                     for j in tree.getroot().iter("joint")])


def test_drake_iiwa14_reflected_inertia():
    """M and RNEA of the SDF = the URDF twin's (Pinocchio) + diag(rotor_inertia · gear_ratio²), as Drake adds it;
    reflected_inertia=False gives the twin's exactly; one note names the joints and values."""
    robot, notes = load_quiet(IIWA)
    plain, plain_notes = load_quiet(IIWA, reflected_inertia=False)
    ref = pin.buildModelFromUrdf(str(IIWA.with_suffix(".urdf")))
    ref.gravity.linear = robot.gravity
    data = ref.createData()
    extra = _drake_reflected(IIWA)
    np.testing.assert_allclose(extra, [160 ** 2 * 1.321e-4] * 4 + [100 ** 2 * 1.321e-4] + [160 ** 2 * 4.54e-5] * 2)
    rng = np.random.default_rng(5)
    for _ in range(4):
        q = robot.random_configuration(rng)
        dq, ddq = rng.normal(size=7), rng.normal(size=7)
        M_twin, tau_twin = pin.crba(ref, data, q), pin.rnea(ref, data, q, dq, ddq)
        pin.framesForwardKinematics(ref, data, q)
        np.testing.assert_allclose(robot.frame_pose(q), data.oMf[ref.getFrameId("iiwa_link_7")].homogeneous,
                                   atol=1e-9)
        np.testing.assert_allclose(robot.crba(q), M_twin + np.diag(extra), atol=1e-9)
        np.testing.assert_allclose(robot.rnea(q, dq, ddq), tau_twin + extra * ddq, atol=1e-9)
        np.testing.assert_allclose(plain.crba(q), M_twin, atol=1e-9)
        np.testing.assert_allclose(plain.rnea(q, dq, ddq), tau_twin, atol=1e-9)
    reflected = [n for n in notes if "reflected rotor inertia" in n]
    assert len(reflected) == 1 and "iiwa_joint_5 1.321" in reflected[0] and "reflected_inertia=False" in reflected[0]
    assert any("drake:acceleration" in n for n in notes)  # read, not modelled
    assert any("left out" in n for n in plain_notes)
    assert plain.spec.reflected_inertia is False and robot.spec.reflected_inertia is True


def test_reflected_inertia_only_on_actuated_joints(tmp_path):
    """Drake adds no actuator (so no rotor inertia) to a joint with <effort>0: noted, not modelled."""
    path = tmp_path / "two.sdf"
    path.write_text(_two_joint_sdf(effort2="0", extra2="<drake:rotor_inertia>0.01</drake:rotor_inertia>"
                                   "<drake:gear_ratio>10</drake:gear_ratio>"))
    robot, notes = load_quiet(path)
    np.testing.assert_array_equal(robot.model.armature, [0.0, 0.0])
    assert any("Drake does not actuate" in n and "j2" in n for n in notes)


def test_reflected_inertia_option_refused_for_other_formats():
    with pytest.raises(InputError, match="reflected_inertia"):
        robokit.load("rrr", reflected_inertia=False)


# --------------------------------------------------------------------------- SDFormat rules, by hand
def _two_joint_sdf(version="1.9", axis2="<xyz>0 0 1</xyz>", pose2="", child_pose="0 0 0.5 0 0 0", effort2="10",
                   extra2=""):
    return f"""<sdf version="{version}" xmlns:drake="http://drake.mit.edu"><model name="two">
      <link name="base"/>
      <link name="a"><pose>0 0 0.2 0 0 0</pose><inertial><mass>1</mass></inertial></link>
      <link name="b"><pose>{child_pose}</pose><inertial><mass>1</mass></inertial></link>
      <joint name="j1" type="revolute"><parent>base</parent><child>a</child><axis><xyz>0 0 1</xyz></axis></joint>
      <joint name="j2" type="revolute"><parent>a</parent><child>b</child>{pose2}
        <axis>{axis2}<limit><effort>{effort2}</effort></limit></axis>{extra2}</joint>
    </model></sdf>"""


@pytest.mark.parametrize("version,use_parent,axis_in_model", [
    ("1.4", "", True),          # SDFormat 1.4: the axis is in the model frame
    ("1.6", "", False),         # 1.5-1.6: in the joint frame ...
    ("1.6", "<use_parent_model_frame>true</use_parent_model_frame>", True),  # ... unless asked
    ("1.9", "", False),
])
def test_axis_frame_by_version(tmp_path, version, use_parent, axis_in_model):
    """Link b is turned 90° about x, so its joint frame's z is the model's -y: the axis xyz 0 0 1 means
    the model's z (1.4, use_parent_model_frame) or the joint's z = the model's -y."""
    path = tmp_path / "two.sdf"
    path.write_text(_two_joint_sdf(version, f"<xyz>0 0 1</xyz>{use_parent}",
                                   child_pose="0 0 0.5 1.5707963267948966 0 0"))
    robot, _ = load_quiet(path)
    t = 0.6
    R_b0 = rot([1, 0, 0], math.pi / 2)
    axis_world = np.array([0, 0, 1.0]) if axis_in_model else R_b0 @ [0, 0, 1.0]
    np.testing.assert_allclose(robot.frame_pose([0.0, t], "b")[:3, :3], rot(axis_world, t) @ R_b0, atol=1e-12)
    np.testing.assert_allclose(robot.frame_pose([0.0, t], "b")[:3, 3], [0, 0, 0.5], atol=1e-12)


def test_joint_pose_defaults_to_the_child_frame(tmp_path):
    """A joint <pose> 0.1 along the child's x (no relative_to): the child swings about that point."""
    path = tmp_path / "two.sdf"
    path.write_text(_two_joint_sdf(pose2="<pose>0.1 0 0 0 0 0</pose>"))
    robot, _ = load_quiet(path)
    t = 0.8
    pivot = np.array([0.1, 0, 0.5])
    expected = pivot + rot([0, 0, 1], t) @ (np.array([0, 0, 0.5]) - pivot)
    np.testing.assert_allclose(robot.frame_pose([0.0, t], "b")[:3, 3], expected, atol=1e-12)


def test_placement_frame_and_world_include(tmp_path):
    """A world including model://two with <placement_frame>b</placement_frame> and a pose: link b lands at
    that pose, everything else follows; the world's <gravity> is used."""
    (tmp_path / "two").mkdir()
    (tmp_path / "two" / "model.sdf").write_text(_two_joint_sdf())
    (tmp_path / "w.sdf").write_text("""<sdf version="1.9"><world name="w"><gravity>0 0 -9.5</gravity>
      <include><uri>model://two</uri><placement_frame>b</placement_frame><pose>1 2 3 0 0 0.5</pose></include>
      <light name="sun" type="directional"/></world></sdf>""")
    robot, notes = load_quiet(tmp_path / "w.sdf")
    np.testing.assert_allclose(robot.gravity, [0, 0, -9.5])
    T = robot.frame_pose([0.0, 0.0], "b")
    np.testing.assert_allclose(T[:3, 3], [1, 2, 3], atol=1e-12)
    np.testing.assert_allclose(T[:3, :3], rot([0, 0, 1], 0.5), atol=1e-12)
    np.testing.assert_allclose(robot.frame_pose([0.0, 0.0], "base")[:3, 3], [1, 2, 2.5], atol=1e-12)
    assert any("<light> in <world>" in n for n in notes)


def test_merged_include(tmp_path):
    """<include merge="true">: the included elements join the parent's scope (no ``two::`` prefix)."""
    (tmp_path / "two").mkdir()
    (tmp_path / "two" / "model.sdf").write_text(_two_joint_sdf())
    (tmp_path / "m.sdf").write_text("""<sdf version="1.9"><model name="m">
      <include merge="true"><uri>model://two</uri></include></model></sdf>""")
    robot, _ = load_quiet(tmp_path / "m.sdf")
    assert robot.joint_names == ("j1", "j2")


# --------------------------------------------------------------------------- refused, one line each
def _refused(path, *match, **kw):
    with pytest.raises(InputError) as info:
        load_quiet(path, **kw)
    msg = str(info.value)
    assert "\n" not in msg and len(msg) < 420, msg
    for m in match:
        assert m in msg, msg
    return msg


def test_include_outside_the_package_folders_is_refused(tmp_path):
    outside = tmp_path / "elsewhere" / "two"
    outside.mkdir(parents=True)
    (outside / "model.sdf").write_text(_two_joint_sdf())
    top = tmp_path / "robot" / "arm.sdf"
    top.parent.mkdir()
    for uri in ("../elsewhere/two/model.sdf", f"file://{outside / 'model.sdf'}", "/etc/hostname"):
        top.write_text(f'<sdf version="1.9"><model name="arm"><include><uri>{uri}</uri></include></model></sdf>')
        if uri == "/etc/hostname" and not os.path.exists(uri):
            continue
        _refused(top, "outside the file's folder, its package and the package folders given")
    # found through package_dirs, it is read
    top.write_text('<sdf version="1.9"><model name="arm"><include><uri>model://two</uri></include></model></sdf>')
    _refused(top, "not found")
    robot, _ = load_quiet(top, package_dirs=[tmp_path / "elsewhere"])
    assert robot.joint_names == ("two::j1", "two::j2")


def test_mesh_outside_is_refused(tmp_path):
    top = tmp_path / "m.sdf"
    top.write_text('<sdf version="1.9"><model name="m"><link name="a"><visual name="v"><geometry><mesh>'
                   '<uri>/etc/passwd</uri></mesh></geometry></visual></link></model></sdf>')
    _refused(top, "outside")


def test_include_cycle_is_refused(tmp_path):
    for a, b in (("a", "b"), ("b", "a")):
        (tmp_path / f"{a}.sdf").write_text(f'<sdf version="1.9"><model name="{a}"><link name="l"/>'
                                           f'<include><uri>{b}.sdf</uri><name>{b}x</name></include></model></sdf>')
    _refused(tmp_path / "a.sdf", "include cycle", "a.sdf -> b.sdf -> a.sdf")


def test_deep_nesting_is_refused(tmp_path):
    depth = 100
    text = "".join(f'<model name="m{i}">' for i in range(depth)) + '<link name="l"/>' + "</model>" * depth
    (tmp_path / "deep.sdf").write_text(f'<sdf version="1.9">{text}</sdf>')
    _refused(tmp_path / "deep.sdf", "nested deeper than 64")


def test_deep_include_chain_is_refused(tmp_path):
    for i in range(30):
        (tmp_path / f"f{i}.sdf").write_text(f'<sdf version="1.9"><model name="m{i}"><link name="l"/>'
                                            f'<include><uri>f{i + 1}.sdf</uri></include></model></sdf>')
    _refused(tmp_path / "f0.sdf", "includes nested deeper than 20")


def test_huge_file_is_refused(tmp_path):
    path = tmp_path / "huge.sdf"
    with open(path, "wb") as f:
        f.write(b'<sdf version="1.9"><model name="m"><link name="l"/>')
        f.seek((20 << 20) + 10)
        f.write(b"</model></sdf>")
    _refused(path, "huge.sdf")


def test_entities_are_refused(tmp_path):
    path = tmp_path / "lol.sdf"
    path.write_text('<?xml version="1.0"?><!DOCTYPE sdf [<!ENTITY a "aaaa">]><sdf version="1.9"><model name="&a;">'
                    '<link name="l"/></model></sdf>')
    _refused(path, "DOCTYPE")


def test_too_many_joints_are_refused(tmp_path):
    links = "".join(f'<link name="l{i}"/>' for i in range(200))
    joints = "".join(f'<joint name="j{i}" type="fixed"><parent>l{i}</parent><child>l{i + 1}</child></joint>'
                     for i in range(199))
    (tmp_path / "snake.sdf").write_text(f'<sdf version="1.9"><model name="s">{links}{joints}</model></sdf>')
    _refused(tmp_path / "snake.sdf", "at most 128 joints")


@pytest.mark.parametrize("body,message", [
    ('<link name="a"><pose relative_to="b"/></link><link name="b"><pose relative_to="a"/></link>', "loop"),
    ('<link name="a"><pose relative_to="nowhere"/></link>', "'nowhere'"),
    ('<link name="a"/><link name="b"/><joint name="j" type="ball"><parent>a</parent><child>b</child></joint>',
     "'ball' joint"),
    ('<static>true</static><link name="a"/>', "static"),
    ('<link name="a"/><link name="a"/>', "used twice"),
])
def test_bad_models_are_refused(tmp_path, body, message):
    (tmp_path / "bad.sdf").write_text(f'<sdf version="1.9"><model name="m">{body}</model></sdf>')
    _refused(tmp_path / "bad.sdf", message)


def test_world_with_two_models_is_refused(tmp_path):
    (tmp_path / "w.sdf").write_text('<sdf version="1.9"><world name="w"><model name="a"><link name="l"/></model>'
                                    '<model name="b"><link name="l"/></model></world></sdf>')
    _refused(tmp_path / "w.sdf", "2 models", "a, b")


def test_too_many_links_are_refused(tmp_path):
    links = "".join(f'<link name="l{i}"/>' for i in range(300))
    (tmp_path / "dust.sdf").write_text(f'<sdf version="1.9"><model name="s">{links}</model></sdf>')
    _refused(tmp_path / "dust.sdf", "300 links")


def test_command_line_refuses_with_one_line(tmp_path, capfd):
    """The CLI prints notes, then exactly one `robokit: error:` line naming the file, and exits 2."""
    from robokit.cli import main

    for a, b in (("a", "b"), ("b", "a")):
        (tmp_path / f"{a}.sdf").write_text(f'<sdf version="1.9"><model name="{a}"><link name="l"/>'
                                           f'<include><uri>{b}.sdf</uri><name>{b}x</name></include></model></sdf>')
    capfd.readouterr()
    assert main(["convert", str(tmp_path / "a.sdf"), "-o", str(tmp_path / "a.json")]) == 2
    err = [ln for ln in capfd.readouterr().err.splitlines() if ln.strip()]
    assert len(err) == 1 and err[0].startswith("robokit: error:") and "include cycle" in err[0] and "a.sdf" in err[0]
    assert not (tmp_path / "a.json").exists()


def test_unknown_parent_is_refused(tmp_path):
    (tmp_path / "bad.sdf").write_text('<sdf version="1.9"><model name="m"><link name="a"/><joint name="j" '
                                      'type="revolute"><parent>ghost</parent><child>a</child><axis><xyz>0 0 1</xyz>'
                                      '</axis></joint></model></sdf>')
    _refused(tmp_path / "bad.sdf", "joint 'j'", "'ghost'")


def test_joint_to_the_world(tmp_path):
    """A revolute joint whose parent is the world: no base link, no 'fixed to the world' note."""
    (tmp_path / "w.sdf").write_text('<sdf version="1.9"><model name="m"><pose>0 0 1 0 0 0</pose><link name="a">'
                                    '<pose>0.5 0 0 0 0 0</pose><inertial><mass>1</mass></inertial></link>'
                                    '<joint name="j" type="revolute"><parent>world</parent><child>a</child>'
                                    '<pose>-0.5 0 0 0 0 0</pose><axis><xyz>0 0 1</xyz></axis></joint></model></sdf>')
    robot, notes = load_quiet(tmp_path / "w.sdf")
    np.testing.assert_allclose(robot.frame_pose([math.pi / 2], "a")[:3, 3], [0, 0.5, 1], atol=1e-12)
    assert not any("fixed to the world" in n for n in notes)


def test_a_link_named_world_before_sdformat_1_7(tmp_path):
    """SDFormat 1.4-1.6: a sibling link named "world" is what <parent>world</parent> means (pybullet_data's wsg50
    grippers); 1.7 reserves the name."""
    body = ('<link name="world"><pose>0 0 0.3 0 0 0</pose></link><link name="a"><pose>0 0 0.3 0 0 0</pose>'
            '<inertial><mass>1</mass></inertial></link><joint name="j" type="prismatic"><parent>world</parent>'
            '<child>a</child><axis><xyz>1 0 0</xyz></axis></joint>')
    (tmp_path / "old.sdf").write_text(f'<sdf version="1.6"><model name="m">{body}</model></sdf>')
    robot, _ = load_quiet(tmp_path / "old.sdf")
    assert robot.model.existFrame("world")
    np.testing.assert_allclose(robot.frame_pose([0.2], "a")[:3, 3], [0.2, 0, 0.3], atol=1e-12)
    (tmp_path / "new.sdf").write_text(f'<sdf version="1.9"><model name="m">{body}</model></sdf>')
    _refused(tmp_path / "new.sdf", "reserved")


def test_initial_position_is_the_initial_configuration(tmp_path):
    """SDFormat's <axis><initial_position> (the joint's initial position; Gazebo does not apply it) is kept
    as robot.configurations["initial"] for the chain's joints; it changes no number, and a value on a
    joint off the chain, which is locked at 0, is named in a note."""
    path = tmp_path / "two.sdf"
    path.write_text(_two_joint_sdf(axis2="<xyz>0 0 1</xyz><initial_position>0.25</initial_position>"))
    robot, notes = load_quiet(path)
    assert list(robot.joint_names) == ["j1", "j2"]
    np.testing.assert_array_equal(robot.configurations["initial"], [0.0, 0.25])
    assert not any("<initial_position>" in n for n in notes)
    plain, _ = load_quiet(_write(tmp_path / "plain.sdf", _two_joint_sdf()))
    assert "initial" not in plain.configurations
    q = np.array([0.3, -0.4])
    np.testing.assert_array_equal(robot.frame_pose(q), plain.frame_pose(q))
    np.testing.assert_array_equal(robot.crba(q), plain.crba(q))
    off, notes = load_quiet(path, tip="a")
    assert "initial" not in off.configurations
    assert any("'initial' values of joints off the chain to 'a' ignored (they are locked at 0): j2 0.25" in n
               for n in notes)


def test_a_bad_initial_position_is_refused(tmp_path):
    path = _write(tmp_path / "two.sdf", _two_joint_sdf(axis2="<xyz>0 0 1</xyz><initial_position>up</initial_position>"))
    with pytest.raises(InputError, match=r"joint 'j2' <axis><initial_position>"):
        robokit.load(path)


@pytest.mark.parametrize("wind", ["true", "false"])
def test_enable_wind_is_noted_only_when_true(tmp_path, wind):
    """<enable_wind>true</enable_wind> names a force robokit does not model (noted); false changes nothing."""
    text = _two_joint_sdf().replace('<link name="base"/>', f'<link name="base"><enable_wind>{wind}</enable_wind></link>')
    _, notes = load_quiet(_write(tmp_path / "two.sdf", text))
    noted = any("<enable_wind>true</enable_wind> in <link> (wind forces)" in n for n in notes)
    assert noted == (wind == "true")


def _write(path, text):
    path.write_text(text)
    return path


@pytest.mark.parametrize("version", ["1.7", "1.9", "1.11"])
def test_an_inertial_pose_relative_to_another_frame_is_refused(tmp_path, version):
    """libsdformat defines no relative_to on an inertial's pose: Gazebo ignores it (the pose stays in the link
    frame), Drake refuses the file (measured with Drake 1.58: "XML Attribute[relative_to] in element[pose] not
    defined in SDF"). The two readings give different masses' places, so robokit refuses rather than pick one."""
    body = ('<link name="a"><inertial><pose relative_to="f">0.1 0 0 0 0 0</pose><mass>1</mass></inertial></link>'
            '<frame name="f" attached_to="a"><pose>0 0 0.5 0 0 0</pose></frame>')
    (tmp_path / "bad.sdf").write_text(f'<sdf version="{version}"><model name="m">{body}</model></sdf>')
    _refused(tmp_path / "bad.sdf", "link 'a' <inertial>", "relative_to='f'", "link's frame")


def test_an_inertial_pose_relative_to_its_own_link_is_the_link_frame(tmp_path):
    """relative_to naming the inertial's own link (as onshape-to-robot writes it) means the same under every
    reading: loaded, said once, the centre of mass where the plain file puts it."""
    def arm(rel):
        return (f'<sdf version="1.9"><model name="m"><link name="b"/><link name="a"><pose>0 0 0.2 0 0 0</pose>'
                f'<inertial><pose{rel}>0.1 0.02 0 0 0.3 0</pose><mass>2</mass><inertia><ixx>0.01</ixx><iyy>0.02</iyy>'
                '<izz>0.02</izz></inertia></inertial></link><joint name="j" type="revolute"><parent>b</parent>'
                '<child>a</child><axis><xyz>0 1 0</xyz></axis></joint></model></sdf>')
    (tmp_path / "own.sdf").write_text(arm(' relative_to="a"'))
    (tmp_path / "plain.sdf").write_text(arm(""))
    with warnings.catch_warnings(record=True) as said:
        warnings.simplefilter("always")
        own = robokit.load(tmp_path / "own.sdf", tip="a")
    plain, _ = load_quiet(tmp_path / "plain.sdf", tip="a")
    assert sum("relative_to on <inertial><pose>" in str(w.message) for w in said) == 1
    q = np.array([0.7])
    assert np.array_equal(own.crba(q), plain.crba(q))
    assert np.array_equal(own.gravity_torques(q), plain.gravity_torques(q)) and abs(own.gravity_torques(q)[0]) > 0.1


MIMIC_SDF = """<sdf version='1.11'><model name='arm'>
<link name='base'><inertial><mass>1</mass><inertia><ixx>1</ixx><iyy>1</iyy><izz>1</izz></inertia></inertial></link>
<joint name='fix' type='fixed'><parent>world</parent><child>base</child></joint>
<link name='l1'><pose relative_to='j1'/><inertial><pose>0.1 0 0 0 0 0</pose><mass>2</mass>
<inertia><ixx>0.02</ixx><iyy>0.03</iyy><izz>0.025</izz></inertia></inertial></link>
<joint name='j1' type='revolute'><pose relative_to='base'>0 0 0.3 0 0 0</pose><parent>base</parent><child>l1</child>
<axis><xyz>0 1 0</xyz><limit><lower>-3</lower><upper>3</upper></limit></axis></joint>
<link name='l2'><pose relative_to='j2'/><inertial><pose>0.15 0 0 0 0 0</pose><mass>1</mass>
<inertia><ixx>0.004</ixx><iyy>0.01</iyy><izz>0.01</izz></inertia></inertial></link>
<joint name='j2' type='revolute'><pose relative_to='l1'>0.4 0 0 0 0 0</pose><parent>l1</parent><child>l2</child>
<axis><xyz>0 1 0</xyz><limit><lower>-3</lower><upper>3</upper></limit></axis></joint>
<link name='f1'><pose relative_to='jf1'/><inertial><pose>0.05 0 0 0 0 0</pose><mass>0.5</mass>
<inertia><ixx>0.001</ixx><iyy>0.001</iyy><izz>0.001</izz></inertia></inertial></link>
<joint name='jf1' type='revolute'><pose relative_to='l1'>0.2 0.1 0 0 0 0</pose><parent>l1</parent><child>f1</child>
<axis><xyz>0 1 0</xyz><limit><lower>-3</lower><upper>3</upper></limit></axis></joint>
<link name='f2'><pose relative_to='jf2'/><inertial><pose>0.05 0 0 0 0 0</pose><mass>0.5</mass>
<inertia><ixx>0.001</ixx><iyy>0.001</iyy><izz>0.001</izz></inertia></inertial></link>
<joint name='jf2' type='revolute'><pose relative_to='f1'>0.1 0 0 0 0 0</pose><parent>f1</parent><child>f2</child>
<axis><xyz>0 1 0</xyz><limit><lower>-3</lower><upper>3</upper></limit>
<mimic joint='jf1' axis='axis'><multiplier>2</multiplier><offset>0.5</offset><reference>0.1</reference></mimic></axis></joint>
</model></sdf>"""


def test_a_mimic_joint_off_the_chain_is_locked_where_sdformat_puts_it(tmp_path):
    """SDFormat 1.11's <mimic>: follower = multiplier · (leader − reference) + offset. With its leader jf1
    locked at 0, jf2 (multiplier 2, offset 0.5, reference 0.1) sits at 2 · (0 − 0.1) + 0.5 = 0.3 rad. Before,
    robokit locked it at 0 (f2's frame 0.3 rad off; M and gravity off) and the three values were read by
    nothing, said by nothing. Reference: Pinocchio on the same arm written as URDF without the mimic, jf2
    set to 0.3 by hand."""
    import pinocchio as pin

    path = tmp_path / "arm.sdf"
    path.write_text(MIMIC_SDF)
    with warnings.catch_warnings(record=True) as said:
        warnings.simplefilter("always")
        robot = robokit.load(path, "l2")
    notes = [str(w.message) for w in said if "mimic joints off the chain locked" in str(w.message)]
    assert notes and "jf2 (at 0.3)" in notes[0], notes

    def rev(name, parent, child, xyz):
        return (f'<joint name="{name}" type="revolute"><parent link="{parent}"/><child link="{child}"/>'
                f'<origin xyz="{xyz}"/><axis xyz="0 1 0"/><limit lower="-3" upper="3" effort="1" velocity="1"/></joint>')

    def lnk(name, x, m, i):
        return (f'<link name="{name}"><inertial><origin xyz="{x} 0 0"/><mass value="{m}"/><inertia ixx="{i[0]}" '
                f'ixy="0" ixz="0" iyy="{i[1]}" iyz="0" izz="{i[2]}"/></inertial></link>')

    twin = ('<robot name="arm">' + lnk("base", 0, 1, (1, 1, 1)) + lnk("l1", 0.1, 2, (0.02, 0.03, 0.025))
            + lnk("l2", 0.15, 1, (0.004, 0.01, 0.01)) + lnk("f1", 0.05, 0.5, (0.001,) * 3)
            + lnk("f2", 0.05, 0.5, (0.001,) * 3) + rev("j1", "base", "l1", "0 0 0.3") + rev("j2", "l1", "l2", "0.4 0 0")
            + rev("jf1", "l1", "f1", "0.2 0.1 0") + rev("jf2", "f1", "f2", "0.1 0 0") + "</robot>")
    model = pin.buildModelFromXML(twin)
    data = model.createData()
    rng = np.random.default_rng(5)
    for _ in range(5):
        q = rng.uniform(-2, 2, 2)
        qf = pin.neutral(model)
        qf[[model.joints[model.getJointId(j)].idx_q for j in ("j1", "j2", "jf2")]] = [*q, 2 * (0 - 0.1) + 0.5]
        pin.framesForwardKinematics(model, data, qf)
        assert np.abs(robot.frame_pose(q, "f2") - data.oMf[model.getFrameId("f2")].homogeneous).max() < 1e-14
        iv = [model.joints[model.getJointId(j)].idx_v for j in ("j1", "j2")]
        M = pin.crba(model, data, qf)
        M = (np.triu(M) + np.triu(M, 1).T)[np.ix_(iv, iv)]
        assert np.abs(robot.crba(q) - M).max() < 1e-14
        assert np.abs(robot.gravity_torques(q) - pin.computeGeneralizedGravity(model, data, qf)[iv]).max() < 1e-13


def test_a_number_followed_by_more_text_is_read_as_libsdformat_reads_it(tmp_path):
    """libsdformat reads a scalar as a C++ stream does: the number the text starts with, the rest ignored,
    silently. Measured with Drake 1.58's libsdformat: ``<velocity>2.5"`` is 2.5, ``1 2`` is 1, ``1e-1x`` is
    0.1, ``abc`` an error — and Drake's own iiwa14_polytope_collision.sdf (RobotLocomotion/models) writes
    ``<velocity>2.356194490192345"</velocity>``, which robokit refused. Now read the same, said once; the
    arm's limits and dynamics are those of the file written cleanly."""
    def arm(vel, mass, damping):
        return (f'<sdf version="1.9"><model name="m"><link name="a"/><link name="b"><pose>0 0 0.1 0 0 0</pose>'
                f'<inertial><pose>0.2 0 0 0 0 0</pose><mass>{mass}</mass><inertia><ixx>0.01</ixx><iyy>0.02</iyy>'
                '<izz>0.02</izz></inertia></inertial></link><joint name="j" type="revolute"><parent>a</parent>'
                '<child>b</child><axis><xyz>0 1 0</xyz><limit><lower>-1</lower><upper>1</upper>'
                f'<velocity>{vel}</velocity><effort>3</effort></limit><dynamics><damping>{damping}</damping>'
                '</dynamics></axis></joint></model></sdf>')
    (tmp_path / "clean.sdf").write_text(arm("2.5", "1.5", "0.1"))
    (tmp_path / "loose.sdf").write_text(arm('2.5"', "1.5 2", "1e-1x"))
    clean, _ = load_quiet(tmp_path / "clean.sdf", tip="b")
    loose, notes = load_quiet(tmp_path / "loose.sdf", tip="b")
    said = [n for n in notes if "numbers read as libsdformat reads them" in n]
    assert len(said) == 1 and "<velocity> '2.5\"' as 2.5" in said[0] and "'1.5 2' as 1.5" in said[0], said
    assert loose.model.velocityLimit[0] == 2.5 and loose.model.damping[0] == 0.1
    q = np.array([0.4])
    assert np.array_equal(loose.crba(q), clean.crba(q)) and loose.crba(q)[0, 0] > 0.05
    (tmp_path / "bad.sdf").write_text(arm("fast", "1.5", "0.1"))
    _refused(tmp_path / "bad.sdf", "<velocity>", "expected a number", "'fast'")
