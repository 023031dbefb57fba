"""Nothing dropped silently: every URDF element robokit reads but does not model is listed once,
in one note per kind (a RobokitWarning, kept in ``robot.notes``); zero-valued ``<dynamics>`` and
modelled elements are not. The same file through xacro lists each once too."""
import sys
import warnings
from pathlib import Path

import pytest

import robokit
from robokit.errors import RobokitWarning

sys.path.insert(0, str(Path(__file__).parent))
from urdf_text import arm, inertial, joint, link  # noqa: E402

EXTRA = """
<transmission name="t1"><type>transmission_interface/SimpleTransmission</type>
  <joint name="j1"><hardwareInterface>EffortJointInterface</hardwareInterface></joint></transmission>
<transmission name="t2"><type>transmission_interface/SimpleTransmission</type></transmission>
<ros2_control name="arm" type="system"><hardware><plugin>mock_components/GenericSystem</plugin></hardware></ros2_control>
<gazebo><plugin filename="libgazebo_ros2_control.so" name="gazebo_ros2_control"/></gazebo>
<gazebo reference="l1"><material>Gazebo/Orange</material></gazebo>
<sensor name="cam" type="camera"><parent link="l3"/></sensor>
<frobnicator/>
"""

#: Each kind of element and a word its note must carry.
KINDS = {
    "<transmission> (2)": "transmissions",
    "<ros2_control>": "mock_components/GenericSystem",
    "<gazebo> (2)": "libgazebo_ros2_control.so",
    "<sensor>": "camera",
    "<frobnicator>": "not part of robokit's model",
    "<safety_controller> of joint 'j1'": "soft limits",
    "<calibration> of joint 'j2'": "calibration",
    "<dynamics> of joints 'j2', 'finger_joint'": "damping=0.7",
    "<contact> of link 'l3'": "contact",
}


def _text():
    finger = link("finger", inertial(0.05, 1e-5, 1e-5, 1e-5))
    mimic = joint("finger_joint", "l2", "finger", xyz="0.2 0 0", axis="1 0 0",
                  extra='<mimic joint="j2"/><dynamics damping="0.7" friction="0.1"/>')
    text = arm(extra_links=[finger], extra_joints=[mimic], extra=EXTRA)
    text = text.replace('<joint name="j1" type="revolute">', '<joint name="j1" type="revolute">'
                        '<safety_controller soft_lower_limit="-2" soft_upper_limit="2" k_position="10" k_velocity="1"/>'
                        '<dynamics damping="0" friction="0"/>')  # zeros: nothing is left out, no note
    text = text.replace('<joint name="j2" type="revolute">', '<joint name="j2" type="revolute">'
                        '<calibration rising="0.1"/><dynamics damping="0.7"/>')
    return text.replace('<link name="l3">', '<link name="l3"><contact><lateral_friction value="1"/></contact>')


def _notes(path, **kw):
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        robot = robokit.load(path, tip="l3", **kw)
    return robot, [str(w.message) for w in caught if issubclass(w.category, RobokitWarning)]


def _check_each_once(found, path):
    for kind, word in KINDS.items():
        hits = [m for m in found if kind in m]
        assert len(hits) == 1, (kind, hits)
        assert word in hits[0] and str(path) in hits[0]
    assert sum("finger_joint" in m and "mimic" in m for m in found) == 1  # the locked mimic joint: its own note
    assert not any("<dynamics> of joint 'j1'" in m or "'j1', " in m and "<dynamics>" in m for m in found)
    for modelled in ("<link>", "<inertial>", "<visual>", "<limit>", "<axis>", "<origin>", "<material>"):
        assert not any(f": {modelled} " in m or f": {modelled}(" in m for m in found)


def test_urdf_lists_every_unmodelled_element_once(tmp_path):
    path = tmp_path / "busy.urdf"
    path.write_text(_text())
    robot, found = _notes(path)
    _check_each_once(found, path)
    assert all(m in robot.notes for m in found if "read but not modelled" in m)


def test_xacro_lists_every_unmodelled_element_once(tmp_path):
    pytest.importorskip("xacro")
    path = tmp_path / "busy.urdf.xacro"
    path.write_text(_text().replace('<robot name="arm">', '<robot name="arm" xmlns:xacro="http://www.ros.org/wiki/xacro">'))
    _, found = _notes(path)
    for kind in KINDS:  # the xacro expander notes <gazebo>, <transmission>, <ros2_control> in its words
        tag = kind.split(">")[0] + ">"
        assert sum(tag in m for m in found) == 1, (tag, [m for m in found if tag in m])


def test_a_plain_file_has_no_such_note(tmp_path):
    path = tmp_path / "plain.urdf"
    path.write_text(arm())
    assert _notes(path)[1] == []


def test_example_robot_data_rotor_inertia_is_modelled_and_noted():
    """example-robot-data gives TALOS's arm rotor inertias and gear ratios (its SRDF); Pinocchio adds
    rotorInertia · gearRatio² to M as armature. robokit keeps it, and says so once."""
    import example_robot_data as erd
    import numpy as np

    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        robot = robokit.load("talos_arm")
    notes = [str(w.message) for w in caught if "reflected rotor inertia" in str(w.message)]
    assert len(notes) == 1 and notes[0] in robot.notes
    model = erd.load("talos_arm").model
    expected = {model.names[j]: model.rotorInertia[model.joints[j].idx_v] * model.rotorGearRatio[model.joints[j].idx_v] ** 2
                for j in range(1, model.njoints)}
    for jn in robot.joint_names:
        if expected[jn]:
            assert f"{jn} {expected[jn]:.4g}" in notes[0]
    import pinocchio as pin

    rigid = pin.Model(robot.model)
    rigid.armature = np.zeros(rigid.nv)
    q = robot.random_configuration(0)
    M_rigid = pin.crba(rigid, rigid.createData(), q)
    M_rigid = np.triu(M_rigid) + np.triu(M_rigid, 1).T
    assert np.allclose(robot.crba(q) - M_rigid, np.diag([expected[jn] for jn in robot.joint_names]), atol=1e-12)


def test_a_chain_without_mass_says_so(tmp_path):
    """Most ROS-Industrial arm macros have no <inertial> at all: Pinocchio (on the raw file) then gives
    a zero mass matrix and zero torques, and so does robokit — one note says so. With a mass on the
    chain there is no such note (the base's mass alone does not move anything: still the note)."""
    import numpy as np
    import pinocchio as pin

    for bodies, massless in (({"base": "", "l1": "", "l2": "", "l3": ""}, True),
                             ({"l1": "", "l2": "", "l3": ""}, True),
                             ({"l1": "", "l2": ""}, False)):
        path = tmp_path / f"arm{len(bodies)}.urdf"
        path.write_text(arm(bodies))
        with warnings.catch_warnings(record=True) as seen:
            warnings.simplefilter("always")
            robot = robokit.load(str(path))
        said = [str(w.message) for w in seen if issubclass(w.category, RobokitWarning) and "has mass" in str(w.message)]
        assert len(said) == (1 if massless else 0), said
        assert any("has mass" in n for n in robot.notes) == massless
        raw = pin.buildModelFromUrdf(str(path))  # the file's own reading: zero exactly when the note says so
        q = np.array([0.3, -0.7, 1.1])
        M = pin.crba(raw, raw.createData(), q)
        assert (np.abs(M).max() == 0.0) == massless
        assert np.allclose(robot.crba(q), M, atol=1e-12)


def test_a_load_note_points_at_the_line_that_loaded_the_robot(tmp_path):
    """A note about the file (here: its meshes are not there) is attributed to the user's own call,
    not to the robokit reader several frames below it."""
    urdf = tmp_path / "arm.urdf"
    urdf.write_text("""<robot name="arm">
  <link name="base"/>
  <link name="l1"><visual><geometry><mesh filename="missing.stl"/></geometry></visual>
    <inertial><mass value="1"/><inertia ixx="0.1" iyy="0.1" izz="0.1" ixy="0" ixz="0" iyz="0"/></inertial></link>
  <joint name="j1" type="revolute"><parent link="base"/><child link="l1"/><axis xyz="0 0 1"/>
    <limit lower="-1" upper="1" effort="1" velocity="1"/></joint>
</robot>
""")
    import warnings as _w

    with _w.catch_warnings(record=True) as caught:
        _w.simplefilter("always")
        robokit.load(urdf)
    notes = [w for w in caught if issubclass(w.category, robokit.RobokitWarning) and "mesh" in str(w.message)]
    assert notes and all(w.filename == __file__ for w in notes), [(w.filename, w.lineno) for w in notes]
