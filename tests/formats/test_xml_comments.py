"""A comment holding ``--`` is not XML 1.0, yet every engine of URDF, MJCF and SDFormat reads it
(urdfdom, MuJoCo, libsdformat and PyBullet parse with TinyXML), and makers write one: gz-sim's
example worlds carry ``<!-- gz service ... --reqtype ... -->``, ROS files ``<!-- ---- links ---- -->``.
robokit read none of these files ("not well-formed XML (invalid token)"); it now reads them as the
engines do, and gives their numbers. The xacro program parses with expat and refuses such a file:
so does robokit's xacro loader."""
import warnings

import numpy as np
import pinocchio as pin
import pytest

import robokit
from mujoco_site import assert_matches_mujoco_site  # tests/support
from pybullet_sdf import assert_matches_pybullet_sdf  # tests/support
from robokit._xml import check_xml, parse_xml, tolerant_comments
from robokit.errors import InputError

COMMENT = "<!-- ---- run: gz sim --playback ~/log --- -->"

URDF = f"""<robot name="c">{COMMENT}<link name="base"/>
<link name="a"><inertial><origin xyz="0.05 0 0.01"/><mass value="1.5"/>
  <inertia ixx="0.01" iyy="0.02" izz="0.03" ixy="0.001" ixz="0" iyz="0"/></inertial></link>
<link name="b"><inertial><origin xyz="0.1 0 0"/><mass value="0.7"/>
  <inertia ixx="0.004" iyy="0.005" izz="0.006" ixy="0" ixz="0" iyz="0"/></inertial></link>
<joint name="j1" type="revolute"><parent link="base"/><child link="a"/><origin xyz="0 0 0.2"/>
  <axis xyz="0 0 1"/><limit lower="-3" upper="3" effort="10" velocity="1"/></joint>
{COMMENT}
<joint name="j2" type="revolute"><parent link="a"/><child link="b"/><origin xyz="0.3 0 0" rpy="0.2 0 0"/>
  <axis xyz="0 1 0"/><limit lower="-3" upper="3" effort="10" velocity="1"/></joint>
</robot>"""

MJCF = f"""<mujoco model="c">{COMMENT}<worldbody>
  <body name="a" pos="0 0 0.2"><joint name="j1" axis="0 0 1" armature="0.1"/>
    <inertial pos="0.05 0 0.01" mass="1.5" fullinertia="0.02 0.025 0.03 0.001 0 0"/>
    <body name="b" pos="0.3 0 0" euler="0.2 0 0"><joint name="j2" axis="0 1 0"/>
      <inertial pos="0.1 0 0" mass="0.7" diaginertia="0.004 0.005 0.006"/>{COMMENT}
      <site name="tip" pos="0.2 0 0"/></body></body></worldbody></mujoco>"""

SDF = f"""<sdf version="1.6">{COMMENT}<model name="c">
  <link name="base"><inertial><mass>0</mass><inertia><ixx>0</ixx><iyy>0</iyy><izz>0</izz></inertia></inertial></link>
  <link name="a"><pose>0 0 0.2 0 0 0</pose><inertial><pose>0.05 0 0.01 0 0 0</pose><mass>1.5</mass>
    <inertia><ixx>0.01</ixx><iyy>0.02</iyy><izz>0.03</izz></inertia></inertial></link>
  <link name="b"><pose>0.3 0 0.2 0 0 0</pose><inertial><pose>0.1 0 0 0 0 0</pose><mass>0.7</mass>
    <inertia><ixx>0.004</ixx><iyy>0.005</iyy><izz>0.006</izz></inertia></inertial></link>{COMMENT}
  <joint name="j1" type="revolute"><parent>base</parent><child>a</child><axis><xyz>0 0 1</xyz><limit><lower>-3</lower><upper>3</upper></limit></axis></joint>
  <joint name="j2" type="revolute"><parent>a</parent><child>b</child><axis><xyz>0 1 0</xyz><limit><lower>-3</lower><upper>3</upper></limit></axis></joint>
</model></sdf>"""


def _load(path, **kw):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return robokit.load(path, **kw)


def _states(robot, seed=0, count=5):
    rng = np.random.default_rng(seed)
    for _ in range(count):
        yield robot.random_configuration(rng), rng.normal(size=robot.n), rng.normal(size=robot.n)


def test_the_repair_changes_only_comments_and_keeps_positions():
    text = "<r>\n<!-- a -- b\n--->\n<![CDATA[ <!-- -- --> ]]><x/></r>"
    fixed = tolerant_comments(text)
    assert len(fixed) == len(text) and fixed.count("\n") == text.count("\n")
    assert "<![CDATA[ <!-- -- --> ]]>" in fixed
    assert parse_xml(text, "t.xml").find("x") is not None
    assert tolerant_comments(text.encode()) == fixed.encode()
    with pytest.raises(InputError, match="t.xml:2:"):  # strict XML, as the xacro program reads it
        check_xml(text, "t.xml")
    with pytest.raises(InputError, match="t.xml:2:"):  # what is not a comment is still refused
        parse_xml("<r>\n<a></b></r>", "t.xml")


def test_urdf_equals_pinocchio_on_the_raw_file(tmp_path):
    path = tmp_path / "c.urdf"
    path.write_text(URDF)
    robot = _load(path, tip="b")
    model = pin.buildModelFromUrdf(str(path))  # urdfdom reads the comments
    data = model.createData()
    fid = model.getFrameId("b", pin.FrameType.BODY)
    for q, dq, ddq in _states(robot):
        pin.framesForwardKinematics(model, data, q)
        np.testing.assert_allclose(robot.frame_pose(q), data.oMf[fid].homogeneous, atol=1e-12)
        np.testing.assert_allclose(robot.rnea(q, dq, ddq), pin.rnea(model, data, q, dq, ddq), atol=1e-12)
        np.testing.assert_allclose(robot.crba(q), np.triu(pin.crba(model, data, q)) +
                                   np.triu(pin.crba(model, data, q), 1).T, atol=1e-12)


def test_mjcf_equals_mujoco(tmp_path):
    path = tmp_path / "c.xml"
    path.write_text(MJCF)
    robot = _load(path)
    assert robot.tip == "tip"
    assert assert_matches_mujoco_site(robot, path, _states(robot)) > 0  # MuJoCo reads the comments


def test_sdf_equals_pybullet_loadsdf(tmp_path):
    path = tmp_path / "c.sdf"
    path.write_text(SDF)
    robot = _load(path)
    inertials = {"a": (np.array([0.05, 0, 0.01]), [0.01, 0.02, 0.03]),  # ElementTree refuses the comments
                 "b": (np.array([0.1, 0, 0]), [0.004, 0.005, 0.006])}
    assert assert_matches_pybullet_sdf(robot, path, _states(robot), inertials=inertials) == 5  # PyBullet reads them


def test_xacro_refuses_as_the_xacro_program_does(tmp_path):
    xacro = pytest.importorskip("xacro")
    path = tmp_path / "c.urdf.xacro"
    path.write_text(URDF.replace('<robot name="c">', '<robot name="c" xmlns:xacro="http://www.ros.org/wiki/xacro">'))
    with pytest.raises(Exception):
        xacro.process_file(str(path))
    with pytest.raises(InputError, match="not well-formed"):
        _load(path, tip="b")


def test_many_unterminated_comments_do_not_hang_the_reading(tmp_path):
    """The blanking is one pass: a file of 250,000 ``<!--`` and no ``-->`` (1 MB, within the size limit)
    took time quadratic in their number with the first version (a regular expression restarted at each
    one: 32,000 of them took 18 s); now it is refused as not well-formed, at once. A child process with
    a deadline, so that a regression fails rather than hangs the suite."""
    import subprocess
    import sys

    path = tmp_path / "many.urdf"
    path.write_bytes(b"<robot name='x'>" + b"<!--" * 250_000)
    code = ("import robokit, sys\ntry:\n    robokit.load(sys.argv[1])\nexcept robokit.InputError as e:\n"
            "    print('refused:', e)\n")
    run = subprocess.run([sys.executable, "-c", code, str(path)], capture_output=True, text=True, timeout=120)
    assert run.returncode == 0 and "refused:" in run.stdout and "many.urdf" in run.stdout, run.stdout + run.stderr
    assert tolerant_comments(b"<r><!-- a --b ---><![CDATA[ <!-- -- --> ]]></r>") == \
        b"<r><!-- a - b  --><![CDATA[ <!-- -- --> ]]></r>"
