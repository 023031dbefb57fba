"""``--allow-outside-meshes`` for the robot's own file on the command line: a URDF whose meshes lie outside
its folder and package (``../meshes`` beside a ``urdf/`` folder without a package.xml) was refused by every
command, and only Python's ``allow_outside_meshes=True`` read it. Now the flag reads it in convert,
calibrate, codegen, view, teach and plan; without it the refusal names the flag. The reference is the robot
loaded in Python with ``allow_outside_meshes=True``."""
import json
import struct

import numpy as np
import pytest

import robokit


@pytest.fixture
def outside(tmp_path):
    (tmp_path / "meshes").mkdir()
    (tmp_path / "urdf").mkdir()
    (tmp_path / "meshes" / "part.stl").write_bytes(
        b"\0" * 80 + struct.pack("<I12fH", 1, 0, 0, 1, 0, 0, 0, 0.1, 0, 0, 0, 0.1, 0, 0))
    geo = '<geometry><mesh filename="../meshes/part.stl"/></geometry>'
    link = ('<inertial><mass value="1"/><inertia ixx="0.01" iyy="0.01" izz="0.01" ixy="0" ixz="0" iyz="0"/>'
            f'</inertial><visual>{geo}</visual><collision>{geo}</collision>')
    joints = "".join(f'<joint name="j{i}" type="revolute"><parent link="l{i - 1}"/><child link="l{i}"/>'
                     f'<origin xyz="0 0 {0.2 if i > 1 else 0}" rpy="{(i % 2) * 1.5707963267948966} 0 0"/>'
                     '<axis xyz="0 0 1"/><limit lower="-3" upper="3" effort="10" velocity="2"/></joint>'
                     for i in range(1, 7))
    links = '<link name="l0"/>' + "".join(f'<link name="l{i}">{link}</link>' for i in range(1, 7))
    path = tmp_path / "urdf" / "arm.urdf"
    path.write_text(f'<robot name="arm">{links}{joints}</robot>')
    return path


def test_without_the_flag_the_refusal_names_it(outside, tmp_path, main_cli):
    r = main_cli("convert", str(outside), "-o", str(tmp_path / "arm.json"))
    assert r.rc == 2 and "--allow-outside-meshes" in r.err and "outside" in r.err, r.err


def test_convert_codegen_and_calibrate_read_the_robot_with_the_flag(outside, tmp_path, main_cli):
    robot = robokit.load(str(outside), allow_outside_meshes=True)
    assert robot.collision_model.ngeoms == 6
    r = main_cli("convert", str(outside), "-o", str(tmp_path / "arm.json"), "--allow-outside-meshes")
    assert r.rc == 0, r.err
    poe = json.loads((tmp_path / "arm.json").read_text())
    assert np.allclose(np.array(poe["M"]), robot.poe.M, rtol=0, atol=1e-15)
    r = main_cli("codegen", str(outside), "-o", str(tmp_path / "c"), "--allow-outside-meshes")
    assert r.rc == 0 and (tmp_path / "c" / "arm.h").exists(), r.err
    rng = np.random.default_rng(0)
    qs = np.array([robot.random_configuration(rng) for _ in range(12)])
    rows = [",".join(f"q{i + 1}" for i in range(6)) + ",x,y,z"]
    rows += [",".join(repr(float(v)) for v in [*q, *robot.frame_pose(q)[:3, 3]]) for q in qs]
    (tmp_path / "m.csv").write_text("\n".join(rows) + "\n")
    r = main_cli("calibrate", str(outside), str(tmp_path / "m.csv"), "-o", str(tmp_path / "cal.urdf"),
                 "--allow-outside-meshes")
    assert r.rc == 0, r.err


def test_view_and_plan_read_the_robot_with_the_flag(outside, tmp_path, main_cli):
    r = main_cli("view", str(outside), "-o", str(tmp_path / "arm.html"), "--allow-outside-meshes")
    assert r.rc == 0 and (tmp_path / "arm.html").stat().st_size > 1000, r.err
    r = main_cli("plan", str(outside), "--start", *["0"] * 6, "--goal", *["0.3"] * 6, "-o", str(tmp_path / "p.csv"),
                 "--allow-outside-meshes")
    assert r.rc == 0 and (tmp_path / "p.csv").exists(), r.err


def test_the_flag_with_a_shipped_model_changes_nothing(tmp_path, main_cli):
    r = main_cli("convert", "puma560", "-o", str(tmp_path / "p.json"), "--allow-outside-meshes")
    assert r.rc == 0, r.err


def test_workspace_reads_the_robot_with_the_flag_and_its_tip(outside, tmp_path, main_cli):
    """``workspace`` took neither the flag for the robot's file nor --tip/--xacro-arg/--package-path (docs/cli.md
    says every command that loads a robot does): its workers rebuild the robot from its spec, which now
    carries them. The reference: the map of the robot loaded in Python with the same options."""
    args = ("--resolution", "0.25", "--orientations", "2", "--scheduler", "serial")
    r = main_cli("workspace", str(outside), *args, "-o", str(tmp_path / "no.npz"))
    assert r.rc == 2 and "--allow-outside-meshes" in r.err, r.err
    assert not (tmp_path / "no.npz").exists()
    r = main_cli("workspace", str(outside), *args, "--tip", "l5", "--allow-outside-meshes", "-o", str(tmp_path / "m.npz"))
    assert r.rc == 0, r.err
    robot = robokit.load(str(outside), tip="l5", allow_outside_meshes=True)
    assert robot.n == 5
    want = robokit.capability_map(robot, 0.25, orientations=2, client="serial")
    got = np.load(tmp_path / "m.npz")
    assert len(want.centres) > 0
    np.testing.assert_array_equal(got["centres"], want.centres)
    np.testing.assert_array_equal(got["index"], want.index)
    assert float(got["resolution"]) == 0.25


def test_workspace_takes_the_xacro_options(tmp_path, main_cli):
    """A xacro arm whose link length is a xacro argument: the map with ``--xacro-arg`` is the map of the robot
    xacro expands with that value, not with the default."""
    joints = "".join(f'<joint name="j{i}" type="revolute"><parent link="l{i - 1}"/><child link="l{i}"/>'
                     f'<origin xyz="${{L}} 0 0"/><axis xyz="0 0 1"/>'
                     '<limit lower="-3" upper="3" effort="10" velocity="2"/></joint>' for i in (1, 2))
    links = "".join(f'<link name="l{i}"><inertial><mass value="1"/><inertia ixx="0.01" iyy="0.01" izz="0.01" '
                    'ixy="0" ixz="0" iyz="0"/></inertial></link>' for i in range(3))
    path = tmp_path / "planar.urdf.xacro"
    path.write_text('<robot name="planar" xmlns:xacro="http://www.ros.org/wiki/xacro">'
                    f'<xacro:arg name="L" default="0.3"/><xacro:property name="L" value="$(arg L)"/>{links}{joints}</robot>')
    args = ("--resolution", "0.1", "--orientations", "4", "--scheduler", "serial")
    r = main_cli("workspace", str(path), *args, "--xacro-arg", "L:=0.5", "-o", str(tmp_path / "m.npz"))
    assert r.rc == 0, r.err
    want = robokit.capability_map(robokit.load(str(path), xacro_args={"L": "0.5"}), 0.1, orientations=4, client="serial")
    default = robokit.capability_map(robokit.load(str(path)), 0.1, orientations=4, client="serial")
    got = np.load(tmp_path / "m.npz")
    np.testing.assert_array_equal(got["centres"], want.centres)
    np.testing.assert_array_equal(got["index"], want.index)
    assert got["centres"].shape != default.centres.shape  # the argument changed the arm
