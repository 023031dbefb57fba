"""Robot.save of a URDF robot into another folder keeps its meshes: a relative mesh path is rewritten
relative to the saved file (before, it was written as the file gave it, so the saved robot reloaded with
a "mesh files not found" note and without its collision shapes: collision checks then saw nothing on
those links). And a note on meshes not found says when collision shapes are among them.

The references are the robot loaded from its own file (its geometry objects, and coal's distances in a
World of it) and the files themselves (each rewritten path resolves to the file the source names)."""
import os
import struct
import warnings
import xml.etree.ElementTree as ET
from pathlib import Path

import numpy as np
import pytest

import robokit
from robokit.collision import Box, World
from robokit.errors import InputError, RobokitWarning


def _stl(path: Path, scale: float) -> None:
    """A closed tetrahedron (binary STL) of edge ``scale`` at the origin."""
    v = np.array([[0, 0, 0], [scale, 0, 0], [0, scale, 0], [0, 0, scale]], dtype=float)
    faces = [(0, 2, 1), (0, 1, 3), (0, 3, 2), (1, 2, 3)]
    with open(path, "wb") as f:
        f.write(b"\0" * 80 + struct.pack("<I", len(faces)))
        for a, b, c in faces:
            n = np.cross(v[b] - v[a], v[c] - v[a])
            f.write(struct.pack("<12fH", *(n / np.linalg.norm(n)), *v[a], *v[b], *v[c], 0))


def _urdf(mesh_uri: str) -> str:
    geo = f'<geometry><mesh filename="{mesh_uri}"/></geometry>'
    link = (f'<inertial><mass value="1"/><inertia ixx="0.01" iyy="0.01" izz="0.01" ixy="0" ixz="0" iyz="0"/>'
            f'</inertial><visual>{geo}</visual><collision>{geo}</collision>')
    return (f'<robot name="arm"><link name="base"/><link name="l1">{link}</link><link name="l2">{link}</link>'
            '<joint name="j1" type="revolute"><parent link="base"/><child link="l1"/><axis xyz="0 0 1"/>'
            '<limit lower="-2" upper="2" effort="1" velocity="1"/></joint>'
            '<joint name="j2" type="revolute"><parent link="l1"/><child link="l2"/><origin xyz="0.3 0 0"/>'
            '<axis xyz="0 1 0"/><limit lower="-2" upper="2" effort="1" velocity="1"/></joint></robot>')


@pytest.fixture
def arm(tmp_path):
    (tmp_path / "a" / "meshes").mkdir(parents=True)
    _stl(tmp_path / "a" / "meshes" / "part.stl", 0.1)
    path = tmp_path / "a" / "arm.urdf"
    path.write_text(_urdf("meshes/part.stl"))
    return path


def _meshes(robot):
    return sorted((g.name, os.path.realpath(g.meshPath)) for m in (robot.visual_model, robot.collision_model)
                  for g in m.geometryObjects)


def _distances(robot):
    pose = np.eye(4)
    pose[:3, 3] = (0.45, 0.0, 0.1)
    world = World(robot, obstacles=[Box((0.2, 0.2, 0.2), pose)])
    rng = np.random.default_rng(0)
    return np.array([world.distance(robot.random_configuration(rng)) for _ in range(5)])


def _quiet_load(path, **kw):
    with warnings.catch_warnings():
        warnings.simplefilter("error", RobokitWarning)  # a mesh not found would be a warning
        return robokit.load(str(path), **kw)


def test_a_robot_saved_in_another_folder_keeps_its_meshes(arm, tmp_path):
    robot = _quiet_load(arm)
    (tmp_path / "b").mkdir()
    with pytest.warns(RobokitWarning, match=r"1 mesh file\(s\) outside its folder \(load it with allow_outside_meshes"):
        out = robot.save(tmp_path / "b" / "arm.urdf")
    names = [m.get("filename") for m in ET.parse(out).getroot().iter("mesh")]
    assert names == ["../a/meshes/part.stl"] * 4
    assert all((out.parent / n).resolve() == (arm.parent / "meshes" / "part.stl").resolve() for n in names)
    with pytest.raises(InputError, match="outside the URDF's folder.*allow_outside_meshes=True"):
        robokit.load(str(out))
    back = _quiet_load(out, allow_outside_meshes=True)
    assert _meshes(back) == _meshes(robot) and len(_meshes(robot)) == 4
    d = _distances(robot)
    assert np.all(np.isfinite(d)) and np.array_equal(_distances(back), d)


def test_saved_above_its_meshes_it_reloads_without_a_note(arm, tmp_path):
    robot = _quiet_load(arm)
    with warnings.catch_warnings():
        warnings.simplefilter("error", RobokitWarning)
        out = robot.save(tmp_path / "arm.urdf")
    assert {m.get("filename") for m in ET.parse(out).getroot().iter("mesh")} == {"a/meshes/part.stl"}
    assert _meshes(_quiet_load(out)) == _meshes(robot)


def test_saved_in_its_own_folder_the_text_is_the_files(arm):
    robot = _quiet_load(arm).with_limits(np.array([[-1.0, 1.0], [-0.5, 0.5]]))
    out = robot.save(arm.parent / "limited.urdf")
    assert {m.get("filename") for m in ET.parse(out).getroot().iter("mesh")} == {"meshes/part.stl"}
    back = _quiet_load(out)
    assert _meshes(back) == _meshes(robot) and np.array_equal(back.qlim, robot.qlim)


def test_a_package_mesh_found_from_the_source_only_is_named_with_the_package_dirs_to_give(tmp_path):
    pkg = tmp_path / "ws" / "arm_description"
    (pkg / "meshes").mkdir(parents=True)
    (pkg / "urdf").mkdir()
    (pkg / "package.xml").write_text('<package format="3"><name>arm_description</name><version>1.0.0</version>'
                                     '<description>x</description><maintainer email="a@b.c">a</maintainer>'
                                     '<license>MIT</license></package>')
    _stl(pkg / "meshes" / "part.stl", 0.1)
    (pkg / "urdf" / "arm.urdf").write_text(_urdf("package://arm_description/meshes/part.stl"))
    robot = _quiet_load(pkg / "urdf" / "arm.urdf")
    (tmp_path / "out").mkdir()
    with pytest.warns(RobokitWarning, match=r"package_dirs=\[" + repr(str((tmp_path / "ws").resolve())).replace("\\", "\\\\")):
        out = robot.save(tmp_path / "out" / "arm.urdf")
    assert {m.get("filename") for m in ET.parse(out).getroot().iter("mesh")} == {
        "package://arm_description/meshes/part.stl"}
    assert _meshes(_quiet_load(out, package_dirs=[str(tmp_path / "ws")])) == _meshes(robot)


def test_a_collision_mesh_not_found_is_said_to_leave_the_collision_checks(tmp_path):
    (tmp_path / "meshes").mkdir()
    _stl(tmp_path / "meshes" / "part.stl", 0.1)
    text = _urdf("meshes/part.stl").replace('<collision><geometry><mesh filename="meshes/part.stl"/>',
                                             '<collision><geometry><mesh filename="meshes/gone.stl"/>', 1)
    (tmp_path / "one.urdf").write_text(text)
    with pytest.warns(RobokitWarning) as got:
        robot = robokit.load(str(tmp_path / "one.urdf"))
    said = " ".join(str(w.message) for w in got)
    assert "link 'l1' collision 'meshes/gone.stl'" in said and "collision checks go without it" in said
    assert robot.collision_model.ngeoms == 1  # l2's shape only: l1 has none left
    (tmp_path / "two.urdf").write_text(text.replace("meshes/part.stl", "meshes/gone.stl"))
    with pytest.warns(RobokitWarning) as got:
        robokit.load(str(tmp_path / "two.urdf"))
    said = " ".join(str(w.message) for w in got)
    assert "4 mesh files not found" in said and "collision checks go without 2 of them (links 'l1', 'l2'" in said


def test_a_visual_mesh_not_found_says_nothing_of_collision(tmp_path):
    (tmp_path / "meshes").mkdir()
    _stl(tmp_path / "meshes" / "part.stl", 0.1)
    text = _urdf("meshes/part.stl").replace('<visual><geometry><mesh filename="meshes/part.stl"/>',
                                             '<visual><geometry><mesh filename="meshes/gone.stl"/>')
    (tmp_path / "v.urdf").write_text(text)
    with pytest.warns(RobokitWarning) as got:
        robokit.load(str(tmp_path / "v.urdf"))
    said = " ".join(str(w.message) for w in got)
    assert "2 mesh files not found" in said and "drawn without them" in said and "collision" not in said.replace(
        "link 'l1' visual", "")


def test_an_sdf_collision_mesh_not_found_is_said_to_leave_the_collision_checks(tmp_path):
    sdf = ('<sdf version="1.9"><model name="m"><link name="base"/><link name="l1"><inertial><mass>1</mass>'
           '<inertia><ixx>0.01</ixx><iyy>0.01</iyy><izz>0.01</izz></inertia></inertial>'
           '<collision name="c"><geometry><mesh><uri>gone.stl</uri></mesh></geometry></collision></link>'
           '<joint name="j1" type="revolute"><parent>base</parent><child>l1</child><axis><xyz>0 0 1</xyz>'
           '</axis></joint></model></sdf>')
    (tmp_path / "m.sdf").write_text(sdf)
    with pytest.warns(RobokitWarning) as got:
        robokit.load(str(tmp_path / "m.sdf"))
    said = " ".join(str(w.message) for w in got)
    assert "1 mesh file(s) not found" in said and "collision checks go without 1 of them (links 'l1'" in said
