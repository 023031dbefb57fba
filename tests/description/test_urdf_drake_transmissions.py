"""Drake's URDF dialect: a ``<transmission>``'s ``drake:rotor_inertia`` and ``drake:gear_ratio`` give
the joint the reflected inertia ``rotor_inertia · gear_ratio²`` that Drake's MultibodyPlant adds to
M's diagonal and to inverse dynamics; robokit puts it in ``model.armature``.

References independent of robokit's reading:

* Drake's own iiwa14 URDF (tests/data/sdf/drake_iiwa14): Pinocchio's ``buildModelFromUrdf`` of the
  file plus ``diag(rotor_inertia · gear_ratio²)`` computed here from the numbers in the file, and
  robokit's load of the SDF twin (the SDFormat reader, a separate path);
* small URDFs written here, each expected value from the numbers the test wrote, by the rules of
  Drake's URDF parser (``ParseTransmission``; measured with pydrake 1.51.1: a zero effort limit or a
  fixed joint gets no actuator, no ``<limit>``/no ``effort`` is unlimited, ``<mechanicalReduction>``
  plays no part, a non-SimpleTransmission type is ignored, a missing ``value`` is an error).
"""
import math
import sys
import warnings
import xml.etree.ElementTree as ET
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import robokit
from robokit.errors import InputError, RobokitWarning

pin = pytest.importorskip("pinocchio")

DATA = Path(__file__).resolve().parents[1] / "data" / "sdf" / "drake_iiwa14"
IIWA_URDF, IIWA_SDF = DATA / "iiwa14_no_collision.urdf", DATA / "iiwa14_no_collision.sdf"


def load_quiet(*args, **kw):
    """robokit.load with the notes collected: (robot, [note text])."""
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        robot = robokit.load(*args, **kw)
    return robot, [str(w.message) for w in caught if issubclass(w.category, RobokitWarning)]


def _file_reflected(path):
    """Joint → rotor_inertia · gear_ratio² read from the transmissions' text (every joint of the iiwa file
    has effort > 0 and a SimpleTransmission: checked here)."""
    root = ET.parse(path).getroot()
    ns = "{http://drake.mit.edu}"
    out = {}
    for tr in root.findall("transmission"):
        assert "SimpleTransmission" in tr.findtext("type")
        act = tr.find("actuator")
        out[tr.find("joint").get("name")] = (float(act.find(f"{ns}rotor_inertia").get("value"))
                                             * float(act.find(f"{ns}gear_ratio").get("value")) ** 2)
    for j in root.findall("joint"):
        if j.get("name") in out:
            assert float(j.find("limit").get("effort")) > 0
    return out


def test_drake_iiwa14_urdf_equals_pinocchio_plus_the_files_reflected_inertia_and_the_sdf_twin():
    robot, notes = load_quiet(IIWA_URDF)
    twin, _ = load_quiet(IIWA_SDF)
    extra = _file_reflected(IIWA_URDF)
    assert sorted(extra) == sorted(robot.joint_names)
    np.testing.assert_allclose(extra["iiwa_joint_1"], 1.321e-4 * 160 ** 2)  # 3.38 kg·m², the defect's size
    ref = pin.buildModelFromUrdf(str(IIWA_URDF))
    ref.gravity.linear = robot.gravity
    data = ref.createData()
    idx = [ref.joints[ref.getJointId(jn)].idx_v for jn in robot.joint_names]
    arm = np.zeros(ref.nv)
    for jn, value in extra.items():
        arm[ref.joints[ref.getJointId(jn)].idx_v] = value
    rng = np.random.default_rng(11)
    for _ in range(5):
        q = robot.random_configuration(rng)
        dq, ddq = rng.normal(size=7), rng.normal(size=7)
        qf, vf, af = pin.neutral(ref), np.zeros(ref.nv), np.zeros(ref.nv)
        qf[idx], vf[idx], af[idx] = q, dq, ddq
        M_ref = pin.crba(ref, data, qf)
        M_ref = np.triu(M_ref) + np.triu(M_ref, 1).T
        tau_ref = pin.rnea(ref, data, qf, vf, af)
        np.testing.assert_allclose(robot.crba(q), (M_ref + np.diag(arm))[np.ix_(idx, idx)], rtol=0, atol=1e-9)
        np.testing.assert_allclose(robot.rnea(q, dq, ddq), (tau_ref + arm * af)[idx], rtol=0, atol=1e-9)
        np.testing.assert_allclose(robot.crba(q), twin.crba(q), rtol=0, atol=1e-9)
        np.testing.assert_allclose(robot.rnea(q, dq, ddq), twin.rnea(q, dq, ddq), rtol=0, atol=1e-9)
    reflected = [n for n in notes if "reflected rotor inertia" in n]
    assert len(reflected) == 1 and "iiwa_joint_5 1.321" in reflected[0] and str(IIWA_URDF) in reflected[0]
    assert not any("<transmission>" in n for n in notes)  # every transmission is modelled
    assert [n for n in notes if "drake:acceleration" in n] == [n for n in notes if "Drake's URDF extensions" in n]
    assert sum("<limit drake:acceleration> ×7" in n for n in notes) == 1
    assert robot.spec.reflected_inertia is True and robokit.load(robot.spec).model.armature.tolist() == \
        robot.model.armature.tolist()


def test_drake_iiwa14_urdf_without_reflected_inertia_is_pinocchios_model():
    robot, notes = load_quiet(IIWA_URDF, reflected_inertia=False)
    np.testing.assert_array_equal(robot.model.armature, np.zeros(7))
    assert sum("read but left out (reflected_inertia=False)" in n for n in notes) == 1
    assert not any("added to M" in n for n in notes)
    assert robot.spec.reflected_inertia is False
    again = robokit.load(robot.spec)
    assert again.spec.reflected_inertia is False and not again.model.armature.any()
    assert "reflected_inertia=False" in repr(robot.spec)


# --------------------------------------------------------------------------- small files written here
BASE = """<?xml version="1.0"?>
<robot name="a" xmlns:drake="http://drake.mit.edu">
<link name="base"/>
<link name="l1"><inertial><origin xyz="0.1 0 0"/><mass value="2"/>
  <inertia ixx="0.01" iyy="0.02" izz="0.03" ixy="0" ixz="0" iyz="0"/></inertial></link>
<link name="l2"><inertial><origin xyz="0.2 0 0"/><mass value="1"/>
  <inertia ixx="0.01" iyy="0.01" izz="0.01" ixy="0" ixz="0" iyz="0"/></inertial></link>
<joint name="j1" type="{kind1}"><parent link="base"/><child link="l1"/><axis xyz="0 0 1"/>{limit1}</joint>
<joint name="j2" type="revolute"><parent link="l1"/><child link="l2"/><origin xyz="0.3 0 0"/><axis xyz="0 1 0"/>
  <limit lower="-2" upper="2" effort="{effort2}" velocity="1"/></joint>
{extra}
</robot>
"""
LIMIT = '<limit lower="-2" upper="2" effort="{effort}" velocity="1"/>'


def transmission(joint, rotor='<drake:rotor_inertia value="0.0002"/>', gear='<drake:gear_ratio value="50"/>',
                 kind="<type>transmission_interface/SimpleTransmission</type>", name=None, attr="", more=""):
    name = name or f"t_{joint}"
    return (f'<transmission name="{name}"{attr}>{kind}<joint name="{joint}"/>'
            f'<actuator name="m_{name}">{more}{rotor}{gear}</actuator></transmission>')


def write(tmp_path, extra, kind1="revolute", limit1=LIMIT.format(effort=10), effort2=10, name="a.urdf"):
    path = tmp_path / name
    path.write_text(BASE.format(kind1=kind1, limit1=limit1, effort2=effort2, extra=extra))
    return path


def diagonal_gain(path, robot):
    """M(q) of robokit minus Pinocchio's own model of the file (no armature), at a few q: its diagonal,
    checked to be the only difference."""
    # urdfdom refuses a <limit> without effort (Drake and robokit read it); the effort is no part of M
    text = path.read_text().replace('<limit lower="-2" upper="2" velocity="1"/>',
                                    '<limit lower="-2" upper="2" effort="1" velocity="1"/>')
    ref = pin.buildModelFromXML(text)
    data = ref.createData()
    idx = [ref.joints[ref.getJointId(jn)].idx_v for jn in robot.joint_names]
    rng = np.random.default_rng(3)
    gains = []
    for _ in range(3):
        q = robot.random_configuration(rng)
        qf = pin.neutral(ref)
        for jn, qi in zip(robot.joint_names, q):
            jm = ref.joints[ref.getJointId(jn)]
            if jm.nq == 2:
                qf[jm.idx_q:jm.idx_q + 2] = np.cos(qi), np.sin(qi)
            else:
                qf[jm.idx_q] = qi
        M_ref = pin.crba(ref, data, qf)
        M_ref = (np.triu(M_ref) + np.triu(M_ref, 1).T)[np.ix_(idx, idx)]
        D = robot.crba(q) - M_ref
        np.testing.assert_allclose(D - np.diag(np.diag(D)), 0.0, atol=1e-12)
        gains.append(np.diag(D))
    np.testing.assert_allclose(gains[0], gains[1], atol=1e-12)
    return gains[0]


def test_reflected_inertia_on_each_driven_joint(tmp_path):
    path = write(tmp_path, transmission("j1") + transmission("j2", rotor='<drake:rotor_inertia value="1e-4"/>',
                                                             gear='<drake:gear_ratio value="120"/>'))
    robot, notes = load_quiet(path)
    np.testing.assert_allclose(diagonal_gain(path, robot), [2e-4 * 50 ** 2, 1e-4 * 120 ** 2], rtol=1e-12)
    assert sum("reflected rotor inertia" in n for n in notes) == 1


def test_a_zero_effort_joint_and_a_fixed_joint_get_none(tmp_path):
    """Drake adds no actuator to a joint whose effort limit is 0, nor to a fixed joint (its parser warns);
    a missing value there is no error, as Drake reads the values only for an actuator it creates."""
    extra = (transmission("j1") + transmission("j2", rotor="<drake:rotor_inertia/>")
             + '<link name="tool"/><joint name="fix" type="fixed"><parent link="l2"/><child link="tool"/></joint>'
             + transmission("fix"))
    path = write(tmp_path, extra, effort2=0)
    robot, notes = load_quiet(path, tip="tool")
    np.testing.assert_allclose(diagonal_gain(path, robot), [2e-4 * 50 ** 2, 0.0], rtol=1e-12)
    ignored = [n for n in notes if "Drake does not actuate" in n]
    assert len(ignored) == 1 and "j2" in ignored[0] and "fix" in ignored[0]
    assert not any("<transmission>" in n for n in notes)


@pytest.mark.parametrize("kind1, limit1", [("continuous", ""), ("revolute", '<limit lower="-2" upper="2" velocity="1"/>'),
                                           ("prismatic", LIMIT.format(effort=5))])
def test_no_limit_or_no_effort_is_unlimited_so_the_joint_is_driven(tmp_path, kind1, limit1):
    path = write(tmp_path, transmission("j1", gear=""), kind1=kind1, limit1=limit1)
    robot, _ = load_quiet(path)
    np.testing.assert_allclose(diagonal_gain(path, robot), [2e-4, 0.0], rtol=1e-12)  # gear ratio 1 by default


def test_another_transmission_type_contributes_nothing_and_is_named(tmp_path):
    path = write(tmp_path, transmission("j1", kind="<type>transmission_interface/DifferentialTransmission</type>")
                 + transmission("j2", kind="", attr=' type="pr2_mechanism_model/SimpleTransmission"'))
    robot, notes = load_quiet(path)
    np.testing.assert_allclose(diagonal_gain(path, robot), [0.0, 2e-4 * 50 ** 2], rtol=1e-12)  # legacy attribute
    tr = [n for n in notes if "<transmission>" in n]
    assert len(tr) == 1 and "DifferentialTransmission" in tr[0] and "no SimpleTransmission" in tr[0]


def test_a_ros_transmission_stays_in_the_not_modelled_note(tmp_path):
    ros = ('<transmission name="t1"><type>transmission_interface/SimpleTransmission</type><joint name="j1">'
           '<hardwareInterface>EffortJointInterface</hardwareInterface></joint><actuator name="m1">'
           '<mechanicalReduction>100</mechanicalReduction></actuator></transmission>')
    path = write(tmp_path, ros)
    robot, notes = load_quiet(path)
    assert not robot.model.armature.any()
    tr = [n for n in notes if "<transmission>" in n]
    assert len(tr) == 1 and "without Drake's drake:rotor_inertia" in tr[0]
    assert not any("reflected" in n for n in notes)


def test_mechanical_reduction_is_not_the_gear_ratio(tmp_path):
    path = write(tmp_path, transmission("j1", gear="", more="<mechanicalReduction>50</mechanicalReduction>"))
    robot, notes = load_quiet(path)
    np.testing.assert_allclose(diagonal_gain(path, robot), [2e-4, 0.0], rtol=1e-12)
    assert sum("<mechanicalReduction>" in n and "t_j1 50" in n for n in notes) == 1


@pytest.mark.parametrize("extra, words", [
    (transmission("j1", rotor="<drake:rotor_inertia/>"), "t_j1' <actuator> <drake:rotor_inertia>: missing attribute 'value'"),
    (transmission("j1", gear='<drake:gear_ratio val="3"/>'), "<drake:gear_ratio>: missing attribute 'value'"),
    (transmission("j1", rotor='<drake:rotor_inertia value="-1e-4"/>'), "<drake:rotor_inertia>: value must be"),
    (transmission("j1", gear='<drake:gear_ratio value="-5"/>'), "<drake:gear_ratio>: value must be"),
    (transmission("j1", rotor='<drake:rotor_inertia value="nan"/>'), "is NaN"),
    (transmission("j1", kind=""), "transmission 't_j1': no <type>"),
    (transmission("nowhere"), "joint 'nowhere' is not defined"),
    (transmission("j1") + transmission("j1", name="again"), "driven by transmission 't_j1' too"),
    (transmission("j1").replace('<joint name="j1"/>', ""), "no <joint name=...>"),
])
def test_a_bad_drake_transmission_is_refused_naming_the_file_and_element(tmp_path, extra, words):
    path = write(tmp_path, extra)
    with pytest.raises(InputError) as err:
        robokit.load(path)
    assert str(path) in str(err.value) and words in str(err.value)


def test_a_negative_effort_limit_on_a_driven_continuous_joint_is_refused(tmp_path):
    path = write(tmp_path, transmission("j1"), kind1="continuous", limit1='<limit effort="-3" velocity="1"/>')
    with pytest.raises(InputError, match="negative effort limit"):
        robokit.load(path)


def test_reflected_inertia_false_leaves_it_out_and_says_so(tmp_path):
    path = write(tmp_path, transmission("j1"))
    robot, notes = load_quiet(path, reflected_inertia=False)
    assert not robot.model.armature.any()
    assert sum("left out (reflected_inertia=False)" in n for n in notes) == 1
    assert robokit.load(robot.spec).spec.reflected_inertia is False


def test_drake_extensions_deeper_in_the_file_are_noted_once(tmp_path):
    extra = transmission("j1")
    path = write(tmp_path, extra, limit1='<limit lower="-2" upper="2" effort="10" velocity="1" drake:acceleration="4"/>')
    text = path.read_text().replace(
        '<link name="l2">',
        '<link name="l2"><collision><geometry><box size="0.1 0.1 0.1"/></geometry>'
        '<drake:proximity_properties><drake:mu_static value="0.5"/></drake:proximity_properties></collision>'
        '<collision><geometry><box size="0.1 0.1 0.1"/></geometry><drake:proximity_properties/></collision>')
    text = text.replace('<joint name="j2" type="revolute">', '<joint name="j2" type="revolute"><drake:joint_damping/>')
    path.write_text(text)
    _, notes = load_quiet(path)
    drake = [n for n in notes if "Drake's URDF extensions" in n]
    assert len(drake) == 1, notes
    for part in ("<limit drake:acceleration>", "<drake:proximity_properties> in <collision> ×2",
                 "<drake:mu_static> in <drake:proximity_properties>"):
        assert part in drake[0]
    assert "rotor_inertia" not in drake[0] and "gear_ratio" not in drake[0]  # modelled
    assert sum("<drake:joint_damping> of joint 'j2'" in n for n in notes) == 1  # a joint's child: its own note


@settings(max_examples=25, deadline=None)
@given(kind=st.sampled_from(["revolute", "continuous", "prismatic"]),
       effort=st.sampled_from([None, 0.0, 0.5, 300.0]),
       rotor=st.one_of(st.none(), st.floats(0.0, 1e-2, allow_subnormal=False)),
       gear=st.one_of(st.none(), st.floats(0.0, 300.0, allow_subnormal=False)),
       simple=st.booleans())
def test_the_armature_is_drakes_rule_on_written_numbers(tmp_path_factory, kind, effort, rotor, gear, simple):
    """Whatever the joint kind, effort limit (none: unlimited), rotor inertia and gear ratio (either may be
    absent: 0 and 1) and transmission type, M grows on the joint's diagonal by exactly Drake's amount."""
    if rotor is None and gear is None:
        rotor = 1e-3
    r = "" if rotor is None else f'<drake:rotor_inertia value="{rotor!r}"/>'
    g = "" if gear is None else f'<drake:gear_ratio value="{gear!r}"/>'
    kind_el = "<type>transmission_interface/SimpleTransmission</type>" if simple else "<type>Other</type>"
    lim = ("" if kind == "continuous" else '<limit lower="-2" upper="2" velocity="1"/>') if effort is None \
        else f'<limit lower="-2" upper="2" effort="{effort!r}" velocity="1"/>'
    path = write(tmp_path_factory.mktemp("prop"), transmission("j1", rotor=r, gear=g, kind=kind_el), kind1=kind,
                 limit1=lim)
    robot, _ = load_quiet(path)
    driven = simple and effort != 0.0
    expected = (rotor or 0.0) * (1.0 if gear is None else gear) ** 2 if driven else 0.0
    np.testing.assert_allclose(diagonal_gain(path, robot)[0], expected, rtol=1e-12, atol=1e-15)
    assert math.isclose(float(robot.model.armature[0]), expected, rel_tol=1e-15, abs_tol=0.0)


# --------------------------------------------------------------------------- xacro, the command line, save
def test_a_xacro_expanding_to_drake_transmissions_gets_the_same(tmp_path):
    pytest.importorskip("xacro")
    macro = ('<xacro:macro name="drive" params="j g"><transmission name="t_${j}"><type>transmission_interface/'
             'SimpleTransmission</type><joint name="${j}"/><actuator name="m_${j}"><drake:rotor_inertia value="2e-4"/>'
             '<drake:gear_ratio value="${g}"/></actuator></transmission></xacro:macro><xacro:drive j="j1" g="50"/>'
             '<xacro:drive j="j2" g="${2*60}"/>')
    path = write(tmp_path, macro, name="a.urdf.xacro")
    path.write_text(path.read_text().replace('<robot name="a"', '<robot name="a" xmlns:xacro="http://www.ros.org/wiki/xacro"'))
    robot, notes = load_quiet(path)
    np.testing.assert_allclose(robot.model.armature, [2e-4 * 50 ** 2, 2e-4 * 120 ** 2], rtol=1e-12)
    assert sum("reflected rotor inertia" in n for n in notes) == 1
    assert not any("<transmission>" in n for n in notes)
    plain, notes = load_quiet(path, reflected_inertia=False)
    assert not plain.model.armature.any() and plain.spec.reflected_inertia is False
    assert robokit.load(plain.spec).spec.reflected_inertia is False


def test_the_command_line_flag_leaves_it_out_for_urdf_and_sdf(tmp_path, capsys):
    """``robokit convert IN -o OUT.xml`` writes each joint's armature; ``--no-reflected-inertia`` none
    (before, the flag crashed ``convert``: its loader took no such option)."""
    from robokit.cli import main

    expected = _file_reflected(IIWA_URDF)
    for src in (IIWA_URDF, IIWA_SDF):
        for flag in ([], ["--no-reflected-inertia"]):
            out = tmp_path / f"{src.suffix[1:]}{len(flag)}.xml"
            assert main(["convert", str(src), "-o", str(out), *flag]) == 0
            err = capsys.readouterr().err
            joints = {j.get("name"): float(j.get("armature", "0")) for j in ET.parse(out).getroot().iter("joint")}
            if flag:
                assert not any(joints.values()) and "left out (reflected_inertia=False)" in err
            else:
                for jn, value in expected.items():
                    assert math.isclose(joints[jn], value, rel_tol=1e-12), (jn, joints[jn], value)
                assert "reflected rotor inertia" in err


def test_a_saved_urdf_robot_and_a_calibrated_one_keep_the_reflected_inertia(tmp_path):
    robot, _ = load_quiet(IIWA_URDF)
    rng = np.random.default_rng(2)
    Q = np.array([robot.random_configuration(rng) for _ in range(25)])
    poses = np.array([robot.frame_pose(q) for q in Q])
    poses[:, :3, 3] += [2e-4, -1e-4, 3e-4]  # a base offset to fit
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        calibrated = robokit.calibrate(robot, Q, poses).robot
        saved = robokit.load(robot.save(tmp_path / "iiwa.urdf"))
        cal_saved = robokit.load(calibrated.save(tmp_path / "cal.urdf"), tip="tool")
        cal_spec = robokit.load(calibrated.spec)
    arm = np.array([_file_reflected(IIWA_URDF)[jn] for jn in robot.joint_names])
    for r in (saved, calibrated, cal_saved, cal_spec):
        np.testing.assert_allclose(r.model.armature, arm, rtol=0, atol=0)
    q = Q[0]
    np.testing.assert_allclose(saved.crba(q), robot.crba(q), rtol=0, atol=1e-12)
    np.testing.assert_allclose(cal_saved.crba(q), calibrated.crba(q), rtol=0, atol=1e-12)
    np.testing.assert_allclose(calibrated.crba(q), robot.crba(q), atol=1e-6)  # same inertias, a shifted base
    assert "drake:rotor_inertia" in (tmp_path / "cal.urdf").read_text()


def test_saving_a_robot_loaded_without_the_reflected_inertia_warns(tmp_path):
    robot, _ = load_quiet(IIWA_URDF, reflected_inertia=False)
    with pytest.warns(RobokitWarning, match="reflected_inertia=False"):
        robot.save(tmp_path / "iiwa.urdf")
    again, _ = load_quiet(tmp_path / "iiwa.urdf", reflected_inertia=False)
    assert not again.model.armature.any()


if __name__ == "__main__":  # pragma: no cover
    sys.exit(pytest.main([__file__, "-q"]))
