"""Scene files and obstacle meshes on hostile input (issue 39, classes 9, 10, 11, 14).

* 9: a mesh's triangles are counted from its bytes before any parser runs (a 4 MB OBJ of polygon
  fans makes 2.2 million triangles; 36 MB made 18 million, 2.5 GB and exit 3), in every mesh
  reader: scene obstacles, a robot's meshes, the teach page. The counts are checked against what
  trimesh makes of small files (an independent parser).
* 10: scene mesh paths are confined like a robot's meshes, before anything is opened, with one
  message whether or not the file exists.
* 11: mesh coordinates beyond 1e12 never reach coal (whose eigen solver printed seven lines).
* 14: obstacle sizes, radii, lengths, poses and the padding are bounded like robot numbers.

The CLI cases run in a subprocess under a 3 GB address-space limit (a safety net, never a timing)
and must give exit 2 and exactly one ``robokit: error:`` line (C++ output on fd 2 included)."""
import io
import re
import struct
import sys
from pathlib import Path

import numpy as np
import pytest
from hypothesis import example, given, settings
from hypothesis import strategies as st


import hardening_support as hs  # noqa: E402
import limited_cli as r2  # noqa: E402

import robokit  # noqa: E402
from robokit.collision import Box, Cylinder, Mesh, Sphere, World, load_scene, pose_from_xyz_rpy  # noqa: E402
from robokit.description.mesh_size import MAX_MESH_TRIANGLES, check_mesh_bytes, mesh_counts  # noqa: E402

trimesh = pytest.importorskip("trimesh")

PLAN = ["plan", "twolink", "--start", "0", "0", "--goal", "1", "1"]


def _scene(folder, *obstacles, name="scene.yaml", padding=None):
    p = Path(folder) / name
    head = "" if padding is None else f"padding: {padding}\n"
    p.write_text(head + "obstacles:\n" + "".join(f"  - {o}\n" for o in obstacles))
    return p


# ----------------------------------------------------------------------------- fan files
def _obj_fan(lines, k):
    return b"v 0 0 0\nv 1 0 0\nv 0 1 0\n" + (b"f " + b" ".join(b"%d" % (1 + i % 3) for i in range(k)) + b"\n") * lines


def _ply_ascii_fan(faces, k):
    head = f"ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n" \
           f"element face {faces}\nproperty list uchar int vertex_indices\nend_header\n"
    return (head + "0 0 0\n1 0 0\n0 1 0\n" + (f"{k} " + " ".join(str(i % 3) for i in range(k)) + "\n") * faces).encode()


def _ply_binary_fan(faces, k):
    head = f"ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\nproperty float y\n" \
           f"property float z\nelement face {faces}\nproperty list ushort int vertex_indices\nend_header\n"
    verts = struct.pack("<9f", 0, 0, 0, 1, 0, 0, 0, 1, 0)
    face = struct.pack("<H", k) + struct.pack(f"<{k}i", *[i % 3 for i in range(k)])
    return head.encode() + verts + face * faces


def _dae_polylist(k, instances=1):
    nodes = "".join(f'<node id="n{i}"><instance_geometry url="#g"/></node>' for i in range(instances))
    return (f'<?xml version="1.0"?><COLLADA xmlns="http://www.collada.org/2005/11/COLLADASchema" version="1.4.1">'
            f'<library_geometries><geometry id="g"><mesh><source id="p"><float_array id="pa" count="9">'
            f'0 0 0 1 0 0 0 1 0</float_array><technique_common><accessor source="#pa" count="3" stride="3">'
            f'<param name="X" type="float"/><param name="Y" type="float"/><param name="Z" type="float"/>'
            f'</accessor></technique_common></source><vertices id="v"><input semantic="POSITION" source="#p"/>'
            f'</vertices><polylist count="1"><input semantic="VERTEX" source="#v" offset="0"/><vcount>{k}</vcount>'
            f'<p>{" ".join(str(i % 3) for i in range(k))}</p></polylist></mesh></geometry></library_geometries>'
            f'<library_visual_scenes><visual_scene id="s">{nodes}</visual_scene></library_visual_scenes>'
            f'<scene><instance_visual_scene url="#s"/></scene></COLLADA>').encode()


@pytest.mark.parametrize("ext, data", [
    ("obj", _obj_fan(3, 50)), ("obj", b"v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nf 1 2 4 3\nf 1/1 2/2 3/3\n"),
    ("ply", _ply_ascii_fan(4, 30)), ("ply", _ply_binary_fan(4, 30)), ("dae", _dae_polylist(40, instances=3)),
    ("stl", None), ("off", None), ("glb", None),
])
def test_counted_triangles_bound_what_trimesh_makes(ext, data):
    """The count from the bytes is at least what trimesh (an independent parser) builds, and close."""
    if data is None:
        mesh = trimesh.creation.icosphere(3)
        data = mesh.export(file_type=ext)
        data = data.encode() if isinstance(data, str) else data
    v, t = mesh_counts(data, ext)
    parsed = trimesh.load(io.BytesIO(data), file_type=ext, force="mesh", process=False)
    assert len(parsed.faces) <= t <= max(3 * len(parsed.faces), 10)
    assert v >= 3


@pytest.mark.parametrize("ext, data", [
    ("obj", _obj_fan(1100, 2002)),              # 2.2 million triangles from 4.4 MB
    ("ply", _ply_ascii_fan(1100, 2002)),
    ("ply", _ply_binary_fan(550, 4000)),
    ("dae", _dae_polylist(40_002, instances=60)),  # one polygon placed 60 times
])
def test_polygon_fans_beyond_the_bound_are_refused_before_parsing(ext, data, monkeypatch):
    def no_parse(*a, **k):
        raise AssertionError("the file was parsed")

    monkeypatch.setattr(trimesh, "load", no_parse)
    with pytest.raises(robokit.InputError, match=rf"fan\.{ext}: mesh of \d+ triangles.*at most {MAX_MESH_TRIANGLES}"):
        check_mesh_bytes(data, ext, f"fan.{ext}")


def test_compressed_and_uncounted_formats(tmp_path):
    with pytest.raises(robokit.InputError, match="compressed"):
        check_mesh_bytes(b"PK\x03\x04" + b"\0" * 100, "3mf", "a.3mf")
    check_mesh_bytes(b"\0" * 1000, "3ds", "a.3ds")  # one triangle per byte at most: 1000 is fine
    with pytest.raises(robokit.InputError, match="format robokit does not count"):
        check_mesh_bytes(b"\0" * (MAX_MESH_TRIANGLES + 1), "3ds", "a.3ds")


def test_cli_scene_fans_exit_2_in_bounded_memory(tmp_path):
    (tmp_path / "fan.obj").write_bytes(_obj_fan(1100, 2002))
    (tmp_path / "fan.ply").write_bytes(_ply_binary_fan(550, 4000))
    a = _scene(tmp_path, "{type: mesh, path: fan.obj}", name="a.yaml")
    b = _scene(tmp_path, "{type: mesh, path: fan.ply}", name="b.yaml")
    runs = r2.run_many([PLAN + ["--obstacles", a, "-o", tmp_path / "p.csv"],
                        ["teach", "twolink", "--obstacles", b, "-o", tmp_path / "t.html"]])
    hs.assert_one_line_error(runs[0], "fan.obj", "triangles")
    hs.assert_one_line_error(runs[1], "fan.ply", "triangles")
    assert not (tmp_path / "p.csv").exists() and not (tmp_path / "t.html").exists()


def test_robot_and_teach_page_meshes_follow_the_same_bound(tmp_path):
    """A URDF naming a fan mesh: the mesh is not read (a note with its count) and the robot loads;
    the teach page's mesh reader refuses the same file by its count."""
    import warnings

    from robokit.viz._meshes import mesh_parts

    (tmp_path / "fan.obj").write_bytes(_obj_fan(1100, 2002))
    urdf = tmp_path / "arm.urdf"
    urdf.write_text(hs.pendulum_urdf(extra='<visual><geometry><mesh filename="fan.obj"/></geometry></visual>'))
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        robot = robokit.load(urdf)
    assert any("fan.obj" in str(w.message) and "triangles" in str(w.message) for w in caught)
    assert len(robot.visual_model.geometryObjects) == 0
    with pytest.raises(robokit.InputError, match="fan.obj: mesh of 2200000 triangles"):
        mesh_parts(tmp_path / "fan.obj", 0.002)


# ----------------------------------------------------------------------------- class 10: confinement
def test_scene_mesh_paths_are_confined_with_one_message(tmp_path):
    """An absolute path, ../ out of the folder (an existing file and a missing one), a symlink out:
    the same refusal, before anything is opened (no "not found" vs "not supported" oracle)."""
    inside, outside = tmp_path / "scene", tmp_path / "elsewhere"
    inside.mkdir()
    outside.mkdir()
    trimesh.creation.box([0.1, 0.1, 0.1]).export(outside / "secret.stl")
    (inside / "link.stl").symlink_to(outside / "secret.stl")
    messages = []
    for path in ("/etc/passwd", "/proc/self/environ", "../elsewhere/secret.stl", "../elsewhere/missing.stl",
                 str(outside / "secret.stl"), "link.stl"):
        p = _scene(inside, f"{{type: mesh, path: '{path}'}}")
        with pytest.raises(robokit.InputError) as e:
            load_scene(p)
        messages.append(str(e.value).replace(repr(path), "PATH"))
    assert len(set(messages)) == 1 and "outside the scene file's folder" in messages[0], messages
    obs, _ = load_scene(p, allow_outside_meshes=True)  # the user's explicit choice
    assert len(obs[0].faces) == 12
    p = _scene(inside, "{type: mesh, path: '../elsewhere/secret.stl'}")
    obs, _ = load_scene(p, package_dirs=[outside])  # a folder the user gave
    assert len(obs[0].faces) == 12


def test_cli_teach_does_not_embed_an_outside_mesh(tmp_path):
    inside = tmp_path / "scene"
    inside.mkdir()
    trimesh.creation.box([0.1, 0.1, 0.1]).export(tmp_path / "secret.stl")
    scene = _scene(inside, "{type: mesh, path: ../secret.stl}")
    out = tmp_path / "t.html"
    runs = r2.run_many([["teach", "twolink", "--obstacles", scene, "-o", out],
                        ["view", "twolink", "--obstacles", _scene(inside, "{type: mesh, path: /etc/passwd}",
                                                                   name="b.yaml"), "-o", out],
                        ["teach", "twolink", "--obstacles", scene, "--allow-outside-meshes", "-o", out]])
    hs.assert_one_line_error(runs[0], "scene.yaml", "outside", "--allow-outside-meshes")
    hs.assert_one_line_error(runs[1], "b.yaml", "outside")
    assert runs[2].rc == 0, runs[2].err
    assert out.exists()


# ----------------------------------------------------------------------------- classes 11 and 14: numbers
@pytest.mark.parametrize("make, argument", [
    (lambda: Box([1e300, 1, 1]), "size"),
    (lambda: Box([1, 1, 1], pose_from_xyz_rpy([1e308, 0, 0], [0, 0, 0])), "xyz"),
    (lambda: Sphere(1e13), "radius"),
    (lambda: Cylinder(0.1, 1e300), "length"),
    (lambda: Sphere(0.1, pose_from_xyz_rpy([0, 0, 0], [1e300, 0, 0])), "rpy"),
    (lambda: Sphere(0.1, np.diag([1.0, 1.0, 1.0, 1.0]) + np.eye(4, k=3) * 1e13), "pose"),
])
def test_obstacle_numbers_are_bounded_like_robot_numbers(make, argument):
    with pytest.raises(robokit.InputError, match=rf"^{argument}\b.*out of range"):
        make()


def test_obstacles_at_the_bound_work_with_coal():
    """1e12 m is accepted, and coal answers sensibly there (the far box is far, the near one is hit)."""
    robot = robokit.load("twolink")
    far = Box([1.0, 1.0, 1.0], pose_from_xyz_rpy([1e12, 0, 0], [0, 0, 0]), "far")
    big = Box([1e12, 1e12, 1e12], name="big")
    assert not World(robot, [far]).in_collision(np.zeros(2))
    assert World(robot, [big]).in_collision(np.zeros(2))


@pytest.mark.parametrize("coords", ["1e300", "1e13"])
def test_mesh_coordinates_beyond_the_bound_never_reach_coal(tmp_path, coords):
    p = tmp_path / "m.obj"
    p.write_text(f"v 0 0 0\nv {coords} 0 0\nv 0 {coords} 0\nv 0 0 1\nf 1 2 3\nf 1 2 4\n")
    with pytest.raises(robokit.InputError, match="m.obj: a vertex coordinate of .* out of range"):
        Mesh(p)


def test_cli_absurd_scene_numbers_exit_2_with_one_line(tmp_path):
    """Was: exit 2 after seven C++ `eigen: too many iterations` lines and numpy warnings (mesh at
    1e300), or accepted unchecked (box 1e300, xyz 1e308)."""
    (tmp_path / "huge.obj").write_text("v 0 0 0\nv 1e300 0 0\nv 0 1e300 0\nv 0 0 1e300\nf 1 2 3\nf 1 2 4\nf 1 3 4\n")
    scenes = [_scene(tmp_path, "{type: mesh, path: huge.obj}", name="mesh.yaml"),
              _scene(tmp_path, "{type: box, size: [1e300, 1, 1]}", name="box.yaml"),
              _scene(tmp_path, "{type: sphere, radius: 0.1, pose: {xyz: [1e308, 0, 0]}}", name="xyz.yaml"),
              _scene(tmp_path, "{type: sphere, radius: 0.1}", name="pad.yaml", padding="1e300")]
    runs = r2.run_many([PLAN + ["--obstacles", s, "-o", tmp_path / "p.csv"] for s in scenes[:3]]
                       + [["view", "twolink", "--obstacles", scenes[3], "-o", tmp_path / "v.html"]])
    for run, scene, word in zip(runs, scenes, ("vertex", "size", "xyz", "padding")):
        hs.assert_one_line_error(run, scene.name, word)
    # the same in a fresh process, where coal's C++ output would go to fd 2
    hs.assert_one_line_error(r2.run_limited(*PLAN, "--obstacles", scenes[0], "-o", tmp_path / "p.csv"), "vertex")
    assert not (tmp_path / "p.csv").exists()


def test_robot_mesh_coordinates_beyond_the_bound_are_not_read(tmp_path):
    """The same bound for a robot's meshes, found in the file's text before Pinocchio's loader (and
    coal) see it: the mesh is not read, with a note, and the robot loads; the teach page's reader
    refuses it too. Was: the page's decimation cast 1e300 to integers (three numpy warning lines)."""
    import warnings

    from robokit.viz._meshes import mesh_parts

    (tmp_path / "huge.obj").write_text("v 0 0 0\nv 1e300 0 0\nv 0 1e300 0\nf 1 2 3\n")
    (tmp_path / "far.obj").write_text("v 0 0 0\nv 12345678901234.5 0 0\nv 0 1 0\nf 1 2 3\n")
    for name, shown in (("huge.obj", "1e+300"), ("far.obj", "1.23457e+13")):
        urdf = tmp_path / "arm.urdf"
        urdf.write_text(hs.pendulum_urdf(extra=f'<visual><geometry><mesh filename="{name}"/></geometry></visual>'
                                               f'<collision><geometry><mesh filename="{name}"/></geometry></collision>'))
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            robot = robokit.load(urdf)
        notes = [str(w.message) for w in caught if name in str(w.message)]
        assert len(notes) == 2 and all(shown in n and "out of range" in n for n in notes), notes
        assert len(robot.visual_model.geometryObjects) == 0 and len(robot.collision_model.geometryObjects) == 0
        with pytest.raises(robokit.InputError, match=re.escape(f"{name}: a vertex coordinate of {shown}")):
            mesh_parts(tmp_path / name, 0.002)


#: A COLLADA triangle as Rhino and SketchUp export it: UUID ids, whose hyphen-separated parts
#: ``9e27`` and ``303287e80685`` read as 9e+27 and 3.03e+80690 (inf) when taken for numbers.
_UUID_DAE = """<?xml version="1.0" encoding="UTF-8"?>
<COLLADA xmlns="http://www.collada.org/2005/11/COLLADASchema" version="1.4.1">
  <asset><unit meter="1" name="meter"/><up_axis>Z_UP</up_axis></asset>
  <library_geometries>
    <geometry id="mesh-a0ec2a07-c575-44a5-9e27-303287e80685">
      <mesh>
        <source id="lib-position-a0ec2a07-c575-44a5-9e27-303287e80685">
          <float_array id="lib-position-array-a0ec2a07-c575-44a5-9e27-303287e80685" count="9">0 0 0 0.25 0 0 0 0.5 0.125</float_array>
          <technique_common><accessor source="#lib-position-array-a0ec2a07-c575-44a5-9e27-303287e80685" count="3" stride="3">
            <param name="X" type="float"/><param name="Y" type="float"/><param name="Z" type="float"/></accessor></technique_common>
        </source>
        <vertices id="lib-vertices-a0ec2a07-c575-44a5-9e27-303287e80685">
          <input semantic="POSITION" source="#lib-position-a0ec2a07-c575-44a5-9e27-303287e80685"/></vertices>
        <triangles count="1"><input semantic="VERTEX" source="#lib-vertices-a0ec2a07-c575-44a5-9e27-303287e80685" offset="0"/>
          <p>0 1 2</p></triangles>
      </mesh>
    </geometry>
  </library_geometries>
  <library_visual_scenes>
    <visual_scene id="scene-4e14-9f9a"><node id="node-4e14-9f9a"><instance_geometry url="#mesh-a0ec2a07-c575-44a5-9e27-303287e80685"/></node></visual_scene>
  </library_visual_scenes>
  <scene><instance_visual_scene url="#scene-4e14-9f9a"/></scene>
</COLLADA>
"""


def test_collada_ids_are_not_read_as_coordinates(tmp_path):
    """elephantrobotics' myCobot meshes (mycobot_ros2, mycobot_description) were dropped as 'a vertex
    coordinate of inf is out of range': the magnitude scan read the hyphen-separated parts of the
    exporter's UUID ids as numbers. The mesh is read, and its vertices are the file's own."""
    import warnings

    from robokit.viz._meshes import mesh_parts

    (tmp_path / "part.dae").write_text(_UUID_DAE)
    urdf = tmp_path / "arm.urdf"
    urdf.write_text(hs.pendulum_urdf(extra='<visual><geometry><mesh filename="part.dae"/></geometry></visual>'
                                           '<collision><geometry><mesh filename="part.dae"/></geometry></collision>'))
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        robot = robokit.load(urdf)
    assert not [str(w.message) for w in caught if "part.dae" in str(w.message)]
    assert len(robot.visual_model.geometryObjects) == 1 and len(robot.collision_model.geometryObjects) == 1
    (V, F, _), = mesh_parts(tmp_path / "part.dae", 1e-6)
    assert sorted(map(tuple, np.round(V, 12))) == [(0, 0, 0), (0, 0.5, 0.125), (0.25, 0, 0)]
    # a real coordinate beyond the bound is still found, between the same ids
    (tmp_path / "huge.dae").write_text(_UUID_DAE.replace("0.5 0.125", "-5e13 0.125"))
    with pytest.raises(robokit.InputError, match=re.escape("huge.dae: a vertex coordinate of 5e+13")):
        mesh_parts(tmp_path / "huge.dae", 0.002)


_NUMBER_PARTS = st.lists(st.one_of(
    st.sampled_from(["v", "f", "<float_array>", " ", "\n", ".", "-", "+", "e", "E", "x1", "ab"]),
    st.builds("".join, st.tuples(
        st.sampled_from(["", "-", "+"]), st.sampled_from(["7", "042", "123456789012", "1234567890123", "99999999999999"]),
        st.sampled_from(["", ".", ".5", ".25"]),
        st.sampled_from(["", "e11", "e12", "e+12", "E012", "e-12", "e13", "e99", "e100", "e+0300", "e9", "e"])))),
    max_size=40)


@settings(max_examples=300, deadline=None)
@given(_NUMBER_PARTS)
@example(["v", " ", "1234567890123", " ", "0"])
@example(["v", " ", "-1.5e12", "\n"])
@example(["v", " ", "2.5E+012", " ", "1e11"])
def test_mesh_magnitude_prefilter_never_changes_the_answer(parts):
    """The mesh text's magnitude check skips its full scan where the quick one (13 digits in a row or an
    exponent of 12 or more, no look-behind) finds nothing: the answer is the full scan's on any text —
    numbers of every size and exponent, glued to letters, dots and signs."""
    from robokit.description import mesh_size

    raw = "".join(parts).encode()
    full = 0.0
    for m in mesh_size._HUGE.finditer(raw):
        try:
            full = max(full, abs(float(m.group(0))))
        except ValueError:
            continue
    for ext in ("obj", "dae", "off"):
        assert mesh_size._largest_number(raw, ext) == full
