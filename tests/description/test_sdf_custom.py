"""Files robokit refused while their engines read them ("not well-formed XML"), read as the engines read
them; each engine of these formats parses with TinyXML2 (libsdformat for Gazebo and Drake, urdfdom,
MuJoCo, PyBullet).

* Prefixed names without an ``xmlns`` declaration — ``gz:expressed_in="…"`` attributes and custom
  elements such as ``<drake:joint_damping>``, ``<ignition:…>``, ``<gz:…>``: libsdformat takes a name
  holding ``:`` for a custom element or attribute and keeps it without reading it. robokit reads the
  rest of the file, names every custom element in its "read but not modelled" note and computes the
  same numbers as for the file without them, which PyBullet's ``loadSDF`` also reads
  (tests/support/pybullet_sdf.py: link poses, Jacobians, M, inverse dynamics, gravity, to 1e-12).
* Whitespace, and a byte-order mark after it, before ``<?xml …?>`` (TinyXML2 skips both; expat wants
  the declaration first): SDFormat against PyBullet, URDF against Pinocchio (urdfdom) on the raw file,
  MJCF against MuJoCo on the raw file. A comment before the declaration stays refused, as all three
  refuse it.
* URDF with undeclared prefixes against Pinocchio on the raw file; MJCF with one is refused, as
  MuJoCo refuses a prefixed name, now with the reason.
* A prefix means what it spells, as in Drake (which looks ``drake:rotor_inertia`` up by that name):
  an undeclared ``drake:rotor_inertia`` is Drake's reflected inertia; another prefix bound to Drake's
  namespace URI is not.
"""
import time
import warnings

import numpy as np
import pytest

import robokit
from mujoco_site import assert_matches_mujoco_site  # tests/support
from pybullet_sdf import assert_matches_pybullet_sdf, file_inertials  # tests/support
from robokit._xml import parse_xml
from robokit.errors import InputError, RobokitWarning

pin = pytest.importorskip("pinocchio")

BOM = "\ufeff"
DECL = '<?xml version="1.0" encoding="UTF-8"?>'
TETRA = "v 0 0 0\nv 0.1 0 0\nv 0 0.1 0\nv 0 0 0.1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n"

# An arm written as makers write SDFormat for Gazebo and Drake, every custom part in {braces}: the
# twin (all of them left out) is what PyBullet and robokit read for the reference numbers.
ARM = """{lead}<sdf version="1.9"><model name="arm">
  <plugin filename="gz-sim-joint-state-publisher-system" name="gz::sim::systems::JointStatePublisher"{a1}/>
  {e1}
  <link name="base"{a2}><inertial><mass>0</mass><inertia><ixx>0</ixx><iyy>0</iyy><izz>0</izz></inertia></inertial></link>
  <link name="upper"><pose>0 0 0.3 0 0 0</pose>
    <inertial><pose>0.02 0.01 0.15 0 0 0</pose><mass>2.5</mass>
      <inertia><ixx>0.03</ixx><iyy>0.035</iyy><izz>0.01</izz></inertia></inertial>
    <collision name="c"><geometry><box><size>0.1 0.1 0.3</size></box></geometry>
      <surface><friction><ode><mu>1</mu><mu2>0</mu2><fdir1{a3}>1 0 0</fdir1></ode></friction></surface></collision>
    <visual name="v"><geometry>{e2}<box><size>0.1 0.1 0.3</size></box></geometry></visual>
    <visual name="m"><geometry><mesh><uri>tetra.obj</uri>{e3}</mesh></geometry></visual>
    {e4}
  </link>
  <link name="fore"><pose>0.05 0 0.6 0.3 0 0</pose>
    <inertial><pose>0.2 0 0.01 0 0 0</pose><mass>1.4</mass>
      <inertia><ixx>0.004</ixx><iyy>0.02</iyy><izz>0.021</izz></inertia></inertial></link>
  <link name="hand"><pose>0.45 0.02 0.63 0.3 0 0.2</pose>
    <inertial><pose>0.03 0 0 0 0 0</pose><mass>0.6</mass>
      <inertia><ixx>0.001</ixx><iyy>0.0012</iyy><izz>0.0009</izz></inertia></inertial></link>
  <joint name="shoulder" type="revolute"><parent>base</parent><child>upper</child>
    <axis><xyz>0 0 1</xyz><limit><lower>-3</lower><upper>3</upper>{e5}</limit></axis>{e6}</joint>
  <joint name="elbow" type="revolute"><parent>upper</parent><child>fore</child>
    <axis><xyz>0 1 0</xyz><limit><lower>-2.5</lower><upper>2.5</upper></limit></axis>{e7}</joint>
  <joint name="slide" type="prismatic"><parent>fore</parent><child>hand</child>
    <axis><xyz>1 0 0</xyz><limit><lower>-0.1</lower><upper>0.2</upper></limit></axis></joint>
</model></sdf>
"""
CUSTOM = {
    "lead": f"\n  {BOM}\n{DECL}\n",  # whitespace, a byte-order mark, whitespace, then the declaration
    "a1": ' gz:expressed_in="base"',
    "e1": '<gz:system_priority>10</gz:system_priority><gz::physics_hint gz::order="1"/>',  # '::' is a name too
    "a2": ' gz:collide_bitmask="0x01"',
    "a3": ' gz:expressed_in="base"',  # gz-physics reads it by this literal name: contact friction
    "e2": "<gz:lod>2</gz:lod>",       # no shape: the box is
    "e3": "<drake:declare_convex/>",
    "e4": "<ignition:wind_sensitive>true</ignition:wind_sensitive>",
    "e5": "<drake:acceleration>8</drake:acceleration>",
    "e6": "<drake:joint_damping>0.3</drake:joint_damping>",  # no element of Drake's: Drake refuses the file
    "e7": '<drake:controller_gains p="100" d="5"/>',
}
PLAIN = dict.fromkeys(CUSTOM, "")


def load_notes(path, **kw):
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        robot = robokit.load(path, **kw)
    return robot, [str(w.message) for w in caught if issubclass(w.category, RobokitWarning)]


def states(robot, seed=0, count=6):
    rng = np.random.default_rng(seed)
    return [(robot.random_configuration(rng), rng.normal(size=robot.n), rng.normal(size=robot.n))
            for _ in range(count)]


@pytest.fixture
def arm(tmp_path):
    (tmp_path / "tetra.obj").write_text(TETRA)
    custom, plain = tmp_path / "arm.sdf", tmp_path / "arm_plain.sdf"
    custom.write_text(ARM.format(**CUSTOM), encoding="utf-8")
    plain.write_text(ARM.format(**PLAIN), encoding="utf-8")
    return custom, plain


def test_custom_elements_and_attributes_read_as_libsdformat_reads_them(arm):
    """The arm with gz:/drake:/ignition: names (no xmlns) and whitespace and a BOM before its declaration
    loads, with the numbers of the file without them — robokit's and PyBullet's, to 1e-12."""
    custom, plain = arm
    robot, notes = load_notes(custom)
    twin, twin_notes = load_notes(plain)
    assert robot.joint_names == twin.joint_names == ("shoulder", "elbow", "slide")
    for q, dq, ddq in states(robot, 1):
        for frame in ("upper", "fore", "hand"):
            np.testing.assert_array_equal(robot.frame_pose(q, frame), twin.frame_pose(q, frame))
            np.testing.assert_array_equal(robot.jacobian(q, frame), twin.jacobian(q, frame))
        np.testing.assert_array_equal(robot.crba(q), twin.crba(q))
        np.testing.assert_array_equal(robot.rnea(q, dq, ddq), twin.rnea(q, dq, ddq))
        np.testing.assert_array_equal(robot.gravity_torques(q), twin.gravity_torques(q))
    assert assert_matches_pybullet_sdf(robot, plain, states(robot), rtol=1e-12) == 6
    assert len(robot.visual_model.geometryObjects) == len(twin.visual_model.geometryObjects) == 2  # the box drawn


def test_custom_elements_are_named_once_and_attributes_pass_silently(arm):
    """Each custom element is named in the one "read but not modelled" note, where it stands (a damping
    Drake does not have, gains, an acceleration limit, a convex-hull declaration with what it changes);
    custom attributes, which libsdformat keeps without a word (gz:expressed_in: contact friction,
    inside the <surface> already named), add nothing."""
    custom, plain = arm
    _, notes = load_notes(custom)
    _, twin_notes = load_notes(plain)
    unmodelled = [n for n in notes if "read but not modelled" in n]
    assert len(unmodelled) == 1
    for key in ("<drake:joint_damping> in <joint>", "<drake:controller_gains> in <joint>",
                "<drake:acceleration> in <limit>", "<ignition:wind_sensitive> in <link>",
                "<gz:system_priority> in <model>", "<gz::physics_hint> in <model>",
                "<drake:declare_convex> in <mesh>"):
        assert key in unmodelled[0], key
    assert "convex hull" in unmodelled[0] and "convex=True" in unmodelled[0]
    assert "<gz:lod>" not in unmodelled[0]  # inside <geometry>, beside the shape: user data, no shape
    assert not any("expressed_in" in n or "collide_bitmask" in n or "gz::order" in n for n in notes)
    # everything else is said of the twin too, word for word
    others = {n.replace("arm_plain.sdf", "arm.sdf") for n in twin_notes if "read but not modelled" not in n}
    assert {n for n in notes if "read but not modelled" not in n} == others


def test_a_custom_element_in_geometry_is_no_shape(tmp_path):
    """A custom element beside the shape is user data, declared or not (the box is drawn; robokit took
    the first child for the shape and drew nothing); Drake's own <drake:capsule> is a custom element to
    libsdformat: alone, it is not drawn, and noted."""
    (tmp_path / "tetra.obj").write_text(TETRA)
    declared = tmp_path / "lod.sdf"
    declared.write_text(ARM.format(**{**PLAIN, "e2": "<gz:lod>2</gz:lod>"}).replace(
        '<sdf version="1.9">', '<sdf version="1.9" xmlns:gz="http://gazebosim.org/schema">'))
    robot, notes = load_notes(declared)
    assert len(robot.visual_model.geometryObjects) == 2 and not any("not drawn" in n for n in notes)
    path = tmp_path / "cap.sdf"
    path.write_text(ARM.format(**PLAIN).replace(
        "<box><size>0.1 0.1 0.3</size></box></geometry></visual>",
        "<drake:capsule><radius>0.05</radius><length>0.2</length></drake:capsule></geometry></visual>"))
    robot, notes = load_notes(path)
    assert any("<drake:capsule> geometry (not drawn)" in n for n in notes)
    assert len(robot.visual_model.geometryObjects) == 1  # the mesh


# --------------------------------------------------------------------------- what stands before <?xml?>
URDF = """<robot name="r"><link name="base"/>
<link name="a"{a}><inertial><origin xyz="0.05 0 0.01" rpy="0.1 0 0"/><mass value="1.5"/>
  <inertia ixx="0.01" iyy="0.02" izz="0.03" ixy="0.001" ixz="0" iyz="0"/></inertial>{e}</link>
<link name="b"><inertial><origin xyz="0.1 0 0"/><mass value="0.7"/>
  <inertia ixx="0.004" iyy="0.005" izz="0.006" ixy="0" ixz="0" iyz="0"/></inertial></link>
<joint name="j1" type="revolute"><parent link="base"/><child link="a"/><origin xyz="0 0 0.2"/>
  <axis xyz="0 0 1"/><limit lower="-3" upper="3" effort="10" velocity="1"{la}/></joint>
<joint name="j2" type="revolute"><parent link="a"/><child link="b"/><origin xyz="0.3 0 0" rpy="0.2 0 0"/>
  <axis xyz="0 1 0"/><limit lower="-3" upper="3" effort="10" velocity="1"/></joint>
<link name="tip"/><joint name="t" type="fixed"><parent link="b"/><child link="tip"/><origin xyz="0.2 0 0"/></joint>
{r}</robot>"""
MJCF = """<mujoco model="m"><worldbody>
  <body name="a" pos="0 0 0.2"><joint name="j1" axis="0 0 1"/>
    <inertial pos="0.05 0 0.01" mass="1.5" fullinertia="0.02 0.025 0.03 0.001 0 0"/>
    <body name="b" pos="0.3 0 0" euler="0.2 0 0"><joint name="j2" axis="0 1 0"/>
      <inertial pos="0.1 0 0" mass="0.7" diaginertia="0.004 0.005 0.006"/>
      <site name="tip" pos="0.2 0 0"/></body></body></worldbody></mujoco>"""
LEADS = {"whitespace": f"\n\n  {DECL}\n", "whitespace, BOM": f"\r\n{BOM}{DECL}\n",
         "BOM, whitespace": f"{BOM} \n\t{DECL}\n", "whitespace, BOM, whitespace": f"\n{BOM}\n  {DECL}\n"}


def urdf_reference(path, robot, frame="tip"):
    """Pinocchio's own URDF parser (urdfdom, TinyXML2) on the raw file: FK, Jacobian, M, RNEA, gravity."""
    model = pin.buildModelFromUrdf(str(path))
    model.gravity.linear = robot.gravity
    data = model.createData()
    fid = model.getFrameId(frame)
    for q, dq, ddq in states(robot):
        pin.computeJointJacobians(model, data, q)
        pin.framesForwardKinematics(model, data, q)
        J = pin.getFrameJacobian(model, data, fid, pin.ReferenceFrame.LOCAL_WORLD_ALIGNED)
        M = pin.crba(model, data, q)
        np.testing.assert_allclose(robot.frame_pose(q, frame), data.oMf[fid].homogeneous, rtol=0, atol=1e-12)
        np.testing.assert_allclose(robot.jacobian(q, frame), np.vstack([J[3:], J[:3]]), rtol=0, atol=1e-12)
        np.testing.assert_allclose(robot.crba(q), np.triu(M) + np.triu(M, 1).T, rtol=0, atol=1e-12)
        np.testing.assert_allclose(robot.rnea(q, dq, ddq), pin.rnea(model, data, q, dq, ddq), rtol=0, atol=1e-12)
        np.testing.assert_allclose(robot.gravity_torques(q), pin.computeGeneralizedGravity(model, data, q),
                                   rtol=0, atol=1e-12)


@pytest.mark.parametrize("lead", LEADS, ids=list(LEADS))
def test_urdf_with_whitespace_before_the_declaration_equals_pinocchio(tmp_path, lead):
    path = tmp_path / "r.urdf"
    path.write_text(LEADS[lead] + URDF.format(a="", e="", la="", r=""), encoding="utf-8")
    robot, _ = load_notes(path, tip="tip")
    urdf_reference(path, robot)  # urdfdom reads the raw file


@pytest.mark.parametrize("lead", LEADS, ids=list(LEADS))
def test_mjcf_with_whitespace_before_the_declaration_equals_mujoco(tmp_path, lead):
    path = tmp_path / "m.xml"
    path.write_text(LEADS[lead] + MJCF, encoding="utf-8")
    robot, _ = load_notes(path)
    assert assert_matches_mujoco_site(robot, path, states(robot)) > 0  # MuJoCo reads the raw file


def test_sdf_with_whitespace_before_the_declaration_equals_pybullet(arm):
    """The plain twin with each lead: PyBullet (TinyXML2) and robokit read it, same numbers."""
    _, plain = arm
    text = plain.read_text(encoding="utf-8")
    inertials = file_inertials(plain)  # ElementTree (expat) refuses the leads
    for lead in LEADS.values():
        plain.write_text(lead + text, encoding="utf-8")
        robot, _ = load_notes(plain)
        assert assert_matches_pybullet_sdf(robot, plain, states(robot, 2, 2), rtol=1e-12, inertials=inertials) == 2


def test_what_stands_before_the_declaration_as_tinyxml2_reads_it():
    """Whitespace, a BOM, whitespace: the declaration and the BOM blanked, every line and column kept
    (bytes: byte for byte; text: character for character); a document expat reads as it is comes back
    unchanged; a comment before the declaration stays refused, as TinyXML2 (XML_ERROR_PARSING_DECLARATION)
    refuses it; 20 MB of whitespace take no time (no backtracking)."""
    from robokit._xml import tolerant_start

    text = f"\n {BOM}\n{DECL}\n<r><a/></r>"
    fixed = tolerant_start(text)
    assert len(fixed) == len(text) and fixed.count("\n") == text.count("\n") and fixed.endswith("\n<r><a/></r>")
    raw = text.encode("utf-8")
    assert len(tolerant_start(raw)) == len(raw) and tolerant_start(raw).strip() == b"<r><a/></r>"
    for same in (f"{DECL}<r/>", f"{BOM}{DECL}<r/>", "<r/>", f"{BOM}<r/>", f"<!-- c -->{DECL}<r/>"):
        assert tolerant_start(same) is same
    assert parse_xml(text, "t.xml").find("a") is not None
    with pytest.raises(InputError, match=r"t.xml:2:1: not well-formed XML \(XML or text declaration not at start"):
        parse_xml(f"<!-- c -->\n{DECL}<r/>", "t.xml")
    with pytest.raises(InputError, match=r"t.xml:3:"):  # positions are the file's
        parse_xml(f"\n  {DECL}\n<r><a></b></r>", "t.xml")
    start = time.perf_counter()
    assert tolerant_start(b" " * (20 << 20) + b"<r/>") is not None
    assert time.perf_counter() - start < 5


# --------------------------------------------------------------------------- prefixes in URDF and MJCF
def test_urdf_with_undeclared_prefixes_equals_pinocchio(tmp_path):
    """urdfdom reads gz:/drake: names without xmlns; robokit too, naming the elements it does not model."""
    path = tmp_path / "r.urdf"
    path.write_text(URDF.format(a=' gz:self_collide="false"', e="<gz:sensor_hint/>", la=' drake:acceleration="3"',
                                r='<drake:collision_filter_group name="g"/>'))
    robot, notes = load_notes(path, tip="tip")
    urdf_reference(path, robot)
    assert any("<drake:collision_filter_group>" in n and "not modelled" in n for n in notes)
    assert any("<gz:sensor_hint> of link 'a'" in n for n in notes)


def test_mjcf_with_an_undeclared_prefix_is_refused_with_the_reason(tmp_path):
    """MuJoCo refuses a prefixed name, declared or not ("unrecognized attribute"); robokit keeps refusing
    an undeclared one, now saying why instead of a bare "not well-formed XML"."""
    mujoco = pytest.importorskip("mujoco")
    path = tmp_path / "m.xml"
    path.write_text(MJCF.replace('<body name="b"', '<body gz:foo="1" name="b"'))
    with pytest.raises(ValueError, match="gz:foo"):
        mujoco.MjModel.from_xml_path(str(path))
    with pytest.raises(InputError, match=r"m.xml:4:\d+: not well-formed XML \(unbound prefix"):
        robokit.load(path)


# --------------------------------------------------------------------------- a prefix means what it spells
DRAKE_JOINT = """<sdf version="1.9"{ns}><model name="two">
  <link name="base"/>
  <link name="a"><pose>0 0 0.2 0 0 0</pose><inertial><mass>1</mass></inertial></link>
  <joint name="j1" type="revolute"><parent>base</parent><child>a</child>
    <axis><xyz>0 0 1</xyz><limit><effort>10</effort></limit></axis>
    <{p}:rotor_inertia>2e-4</{p}:rotor_inertia><{p}:gear_ratio>100</{p}:gear_ratio></joint>
</model></sdf>"""


def test_drake_elements_are_drakes_by_their_written_name(tmp_path):
    """Drake looks ``drake:rotor_inertia`` up by that name (libsdformat keeps names as TinyXML2 reads them):
    written so without any xmlns it is Drake's reflected inertia, 2e-4 · 100² = 2 kg·m² on M's diagonal;
    under a prefix ``d`` bound to Drake's URI Drake ignores it ("Ignoring unsupported SDFormat element"),
    and robokit names it as not modelled instead of adding it."""
    base = tmp_path / "base.sdf"
    base.write_text(DRAKE_JOINT.format(ns="", p="drake").replace("<drake:rotor_inertia>2e-4</drake:rotor_inertia>"
                                                                 "<drake:gear_ratio>100</drake:gear_ratio>", ""))
    plain, _ = load_notes(base)
    bare = tmp_path / "bare.sdf"
    bare.write_text(DRAKE_JOINT.format(ns="", p="drake"))
    other = tmp_path / "other.sdf"
    other.write_text(DRAKE_JOINT.format(ns=' xmlns:d="http://drake.mit.edu"', p="d"))
    robot, notes = load_notes(bare)
    ignored, ignored_notes = load_notes(other)
    q = np.array([0.4])
    np.testing.assert_allclose(robot.crba(q), plain.crba(q) + 2.0, rtol=0, atol=1e-12)
    np.testing.assert_array_equal(ignored.crba(q), plain.crba(q))
    assert any("reflected rotor inertia" in n and "j1 2" in n for n in notes)
    assert any("<d:rotor_inertia> in <joint>" in n and "<d:gear_ratio> in <joint>" in n for n in ignored_notes)
    assert not any("reflected" in n for n in ignored_notes)
