"""xacro files: expanded without ROS, packages found by robokit, checked against the same
robot written out by hand as plain URDF (loaded by Pinocchio directly)."""
import json
import shutil
from pathlib import Path

import numpy as np
import pinocchio as pin
import pytest

import robokit
from robokit.cli import main as cli_main
from robokit.description.xacro_files import expand_xacro, find_package

PLAIN = {}


@pytest.fixture(autouse=True)
def _plain(plain_urdf):
    PLAIN["urdf"] = plain_urdf


def _reference(l1=0.4, m2=1.5):
    model = pin.buildModelFromXML(PLAIN["urdf"](l1, m2))
    return model, model.createData()


def _agree(robot, l1=0.4, m2=1.5, samples=20):
    """Largest difference of tip FK, crba and rnea between robot and the hand-written URDF."""
    model, data = _reference(l1, m2)
    fid = model.getFrameId("tool")
    rng = np.random.default_rng(3)
    worst = 0.0
    for _ in range(samples):
        q = robot.random_configuration(rng)
        v, a = rng.normal(size=3), rng.normal(size=3)
        pin.framesForwardKinematics(model, data, q)
        worst = max(worst, np.abs(robot.frame_pose(q, "tool") - data.oMf[fid].homogeneous).max())
        M = pin.crba(model, data, q)
        M = np.triu(M) + np.triu(M, 1).T
        worst = max(worst, np.abs(robot.crba(q) - M).max())
        worst = max(worst, np.abs(robot.rnea(q, v, a) - pin.rnea(model, data, q, v, a)).max())
    return worst


def test_defaults_match_hand_written_urdf(xacro_ws):
    robot = robokit.load(xacro_ws / "urdf" / "demo.urdf.xacro", tip="tool")
    assert robot.n == 3 and robot.joint_names == ("j1", "j2", "j3")
    assert _agree(robot) < 1e-12


def test_argument_override_changes_the_robot(xacro_ws):
    path = xacro_ws / "urdf" / "demo.urdf.xacro"
    robot = robokit.load(path, tip="tool", xacro_args={"l1": "0.7", "m2": 2.5})
    assert _agree(robot, l1=0.7, m2=2.5) < 1e-12
    # and it really is a different robot from the defaults
    assert np.abs(robot.frame_pose(np.zeros(3)) - robokit.load(path, tip="tool").frame_pose(np.zeros(3))).max() > 0.29


def test_package_mesh_is_resolved_to_the_stl(xacro_ws):
    robot = robokit.load(xacro_ws / "urdf" / "demo.urdf.xacro")
    paths = {Path(g.meshPath) for g in robot.visual_model.geometryObjects}
    assert paths == {(xacro_ws / "meshes" / "link.stl").resolve()}
    text = expand_xacro(xacro_ws / "urdf" / "demo.urdf.xacro")
    assert "package://" not in text and "$(" not in text


def test_package_path_for_a_file_outside_the_workspace(xacro_ws, tmp_path):
    elsewhere = tmp_path / "elsewhere"
    elsewhere.mkdir()
    shutil.copy(xacro_ws / "urdf" / "demo.urdf.xacro", elsewhere / "demo.urdf.xacro")
    with pytest.raises(ValueError, match="demo_description.*not found"):
        robokit.load(elsewhere / "demo.urdf.xacro")
    robot = robokit.load(elsewhere / "demo.urdf.xacro", tip="tool", package_dirs=[xacro_ws.parent])
    assert _agree(robot) < 1e-12
    assert find_package("demo_description", [xacro_ws.parent]) == xacro_ws.resolve()
    # the package folder itself, and a folder named differently from the package
    renamed = tmp_path / "other_name"
    shutil.copytree(xacro_ws, renamed)
    assert find_package("demo_description", [renamed]) == renamed.resolve()


def test_unknown_argument_is_rejected(xacro_ws):
    with pytest.raises(ValueError, match=r"unknown xacro argument\(s\) l9; the file declares l1, m2"):
        robokit.load(xacro_ws / "urdf" / "demo.urdf.xacro", xacro_args={"l9": "1"})


def test_gazebo_elements_are_noted(xacro_ws):
    with pytest.warns(UserWarning, match=r"<gazebo> read but not modelled: simulator settings"):
        robokit.load(xacro_ws / "urdf" / "demo.urdf.xacro")


def test_xacro_options_only_for_xacro_files():
    with pytest.raises(ValueError, match="apply to .xacro files"):
        robokit.load("rrr", xacro_args={"a": "1"})


def test_cli_convert_with_arguments_and_package_path(xacro_ws, tmp_path, capsys):
    src = tmp_path / "copy.urdf.xacro"
    shutil.copy(xacro_ws / "urdf" / "demo.urdf.xacro", src)
    out = tmp_path / "demo.json"
    rc = cli_main(["convert", str(src), "-o", str(out), "--tip", "tool", "--xacro-arg", "l1:=0.7",
                   "--package-path", str(xacro_ws.parent)])
    assert rc == 0, capsys.readouterr().err
    M = np.array(json.loads(out.read_text())["M"])
    model, data = _reference(l1=0.7)
    pin.framesForwardKinematics(model, data, np.zeros(3))
    assert np.abs(M - data.oMf[model.getFrameId("tool")].homogeneous).max() < 1e-12


def test_cli_view_and_mjcf_export(xacro_ws, tmp_path, capsys):
    src = xacro_ws / "urdf" / "demo.urdf.xacro"
    page = tmp_path / "demo.html"
    assert cli_main(["view", str(src), "-o", str(page)]) == 0, capsys.readouterr().err
    assert page.stat().st_size > 1000 and "<html" in page.read_text()[:2000].lower()
    mjcf = tmp_path / "demo.xml"
    assert cli_main(["convert", str(src), "-o", str(mjcf), "--tip", "tool", "--xacro-arg", "m2:=2.5"]) == 0
    assert 'type="slide"' in mjcf.read_text() and "link.stl" in mjcf.read_text()
    back = robokit.load(mjcf, tip="tool")
    assert _agree(back, m2=2.5) < 1e-12


BAD_XACRO = {
    "missing_include.xacro": ('<robot name="a" xmlns:xacro="http://www.ros.org/wiki/xacro"><link name="b"/>\n'
                              '  <xacro:include filename="not_there.xacro"/></robot>',
                              ["missing_include.xacro", "line 2", "<xacro:include>", "not_there.xacro"]),
    "undefined_arg.xacro": ('<robot name="a" xmlns:xacro="http://www.ros.org/wiki/xacro">\n<link name="b"/>\n'
                            '<link name="$(arg nope)"/></robot>',
                            ["undefined_arg.xacro", "line 3", "<link>", "$(arg nope)"]),
    "bad_xml.xacro": ('<robot name="a" xmlns:xacro="http://www.ros.org/wiki/xacro">\n<link name="b">\n</robot>',
                      ["bad_xml.xacro:3:", "not well-formed"]),
    "no_package.xacro": ('<robot name="a" xmlns:xacro="http://www.ros.org/wiki/xacro">\n'
                         '<xacro:include filename="$(find no_such_pkg)/x.xacro"/></robot>',
                         ["no_package.xacro", "line 2", "no_such_pkg", "not found"]),
    "undefined_property.xacro": ('<robot name="a" xmlns:xacro="http://www.ros.org/wiki/xacro">\n<link name="b">\n'
                                 '<inertial><mass value="${nothing * 2}"/></inertial></link></robot>',
                                 ["undefined_property.xacro", "line 3", "<mass>", "nothing"]),
    # Interbotix's interbotix_arm.urdf.xacro (branch descriptions_arm_macros): the undefined property's name
    # is an argument's name on the line above; the error named that line (line 2) before
    "undefined_property_named_above.xacro": ('<robot name="a" xmlns:xacro="http://www.ros.org/wiki/xacro">\n'
                                             '  <xacro:arg name="robot_model" default="px100"/>\n'
                                             '  <xacro:arg name="robot_name" default="${robot_model}"/>\n'
                                             '<link name="b"/></robot>',
                                             ["undefined_property_named_above.xacro", "line 3", "<xacro:arg>",
                                              "robot_model"]),
    "missing_param.xacro": ('<robot name="a" xmlns:xacro="http://www.ros.org/wiki/xacro">\n'
                            '<xacro:macro name="seg" params="x"><link name="${x}"/></xacro:macro>\n<xacro:seg/></robot>',
                            ["missing_param.xacro", "line 3", "<xacro:seg>", "x"]),
}


@pytest.mark.parametrize("name", sorted(BAD_XACRO))
def test_malformed_xacro_one_line_exit_2(name, tmp_path, capsys):
    text, expected = BAD_XACRO[name]
    src = tmp_path / name
    src.write_text(text)
    out = tmp_path / "out.xml"
    rc = cli_main(["convert", str(src), "-o", str(out)])
    err = capsys.readouterr().err
    assert rc == 2
    lines = err.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("robokit: error:"), err
    for piece in expected:
        assert piece in lines[0], (piece, lines[0])
    assert not out.exists() and list(tmp_path.iterdir()) == [src]


def test_missing_meshes_do_not_stop_the_load(tmp_path, capsys):
    """A description shipped without its meshes loads for kinematics and dynamics, with one note
    (not one per mesh) naming how many are missing; the chain is the hand-computed one."""
    meshes = "".join(f'<{kind}><geometry><mesh filename="package://gone/{kind}{i}.stl"/></geometry></{kind}>'
                     for i in range(3) for kind in ("visual", "collision"))
    src = tmp_path / "nomesh.urdf.xacro"
    src.write_text(f'<robot name="a" xmlns:xacro="http://www.ros.org/wiki/xacro"><link name="b"/>'
                   f'<link name="c">{meshes}</link><joint name="j" type="revolute"><parent link="b"/>'
                   '<child link="c"/><origin xyz="0 0 ${0.25 * 2}"/><axis xyz="0 0 1"/>'
                   '<limit lower="-1" upper="1" effort="1" velocity="1"/></joint></robot>')
    out = tmp_path / "o.json"
    assert cli_main(["convert", str(src), "-o", str(out)]) == 0
    notes = [line for line in capsys.readouterr().err.splitlines() if "mesh file" in line and "note:" in line]
    assert len(notes) == 1 and "6 mesh files not found" in notes[0] and "gone/visual0.stl" in notes[0], notes
    assert np.allclose(np.array(json.loads(out.read_text())["M"])[:3, 3], [0.0, 0.0, 0.5], atol=1e-15)


def test_bad_xacro_arg_syntax_exit_2(xacro_ws, tmp_path, capsys):
    rc = cli_main(["convert", str(xacro_ws / "urdf" / "demo.urdf.xacro"), "-o", str(tmp_path / "o.json"),
                   "--xacro-arg", "l1=0.7"])
    err = capsys.readouterr().err
    assert rc == 2 and len(err.strip().splitlines()) == 1 and "NAME:=VALUE" in err


def test_cli_view_with_xacro_arguments(xacro_ws, tmp_path, capsys):
    src = tmp_path / "outside.urdf.xacro"
    shutil.copy(xacro_ws / "urdf" / "demo.urdf.xacro", src)
    page = tmp_path / "v.html"
    rc = cli_main(["view", str(src), "-o", str(page), "--xacro-arg", "l1:=0.6", "--package-path", str(xacro_ws.parent)])
    assert rc == 0, capsys.readouterr().err
    assert page.stat().st_size > 1000


def test_load_yaml_of_a_missing_file_names_the_call_and_the_macro(tmp_path):
    """ROS-Industrial's Motoman ES165 (motoman_es_support/urdf/es165.xacro) passes its
    ``joint_velocities_file`` argument, empty by default, to ``xacro.load_yaml`` inside its macro; the
    xacro program fails there too ('Is a directory'), and robokit said only '<folder>: is a folder, not
    a YAML file', naming neither the call nor the macro."""
    import xacro

    (tmp_path / "arm_macro.xacro").write_text(
        '<robot xmlns:xacro="http://ros.org/wiki/xacro"><xacro:macro name="arm" params="velocities_file">'
        '<xacro:property name="v" value="${xacro.load_yaml(velocities_file)}"/>'
        '<link name="base_${v[\'joint_1\']}"/></xacro:macro></robot>')
    top = tmp_path / "arm.urdf.xacro"
    top.write_text('<robot name="arm" xmlns:xacro="http://ros.org/wiki/xacro">'
                   '<xacro:include filename="arm_macro.xacro"/><xacro:arg name="velocities" default=""/>'
                   '<xacro:arm velocities_file="$(arg velocities)"/></robot>')
    with pytest.raises(Exception):  # the xacro program refuses it as well
        xacro.process_file(str(top))
    with pytest.raises(robokit.InputError) as err:
        robokit.load(top)
    said = str(err.value)
    assert "\n" not in said
    assert "xacro.load_yaml('') (an empty file name: an argument not given?)" in said
    assert "is a folder, not a YAML file" in said and "macro arm" in said
    with pytest.raises(robokit.InputError, match=r"xacro\.load_yaml\('v\.yaml'\): .*v\.yaml: file not found .*macro arm"):
        robokit.load(top, xacro_args={"velocities": "v.yaml"})


def test_a_xacro_file_notes_what_is_not_modelled_as_its_expanded_urdf_does(tmp_path):
    """UFACTORY's xarm_description (xArm-Developer/xarm_ros2) loaded as xacro said '8 <gazebo>
    element(s) ignored (no meaning for the rigid-body model)', and the same robot's .urdf (Kinova's
    gen3_lite.urdf next to its xacro) '<gazebo> (8) [plugin] read but not modelled: simulator
    settings and plugins are not part of robokit's model': two wordings, and the xacro one without
    the plugins or why. The notes of a xacro file are now those of the URDF the xacro program expands
    it to, word for word (the file name aside)."""
    import warnings

    import xacro

    top = tmp_path / "arm.urdf.xacro"
    top.write_text("""<robot name="arm" xmlns:xacro="http://ros.org/wiki/xacro">
  <xacro:macro name="trans" params="j"><transmission name="${j}_t"><joint name="${j}"/></transmission></xacro:macro>
  <link name="base"/>
  <link name="l1"><inertial><mass value="1"/><inertia ixx="0.01" iyy="0.01" izz="0.01" ixy="0" ixz="0" iyz="0"/></inertial></link>
  <joint name="j1" type="revolute"><parent link="base"/><child link="l1"/><axis xyz="0 0 1"/>
    <limit lower="-1" upper="1" effort="1" velocity="1"/><dynamics damping="0.5"/></joint>
  <xacro:trans j="j1"/>
  <gazebo><plugin filename="libgazebo_ros2_control.so" name="gz"/></gazebo><gazebo reference="l1"/>
  <ros2_control name="arm" type="system"><hardware><plugin>mock_components/GenericSystem</plugin></hardware></ros2_control>
</robot>""")
    expanded = tmp_path / "arm.urdf"
    expanded.write_text(xacro.process_file(str(top)).toxml())

    def notes(path):
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            robokit.load(path)
        return sorted(str(w.message).replace(str(path), "FILE") for w in caught
                      if issubclass(w.category, robokit.RobokitWarning))

    said = notes(top)
    assert said == notes(expanded)
    assert ("FILE: <gazebo> (2) [libgazebo_ros2_control.so] read but not modelled: simulator settings and plugins "
            "are not part of robokit's model") in said
    assert not [n for n in said if "element(s) ignored" in n]
