"""One confinement rule for every file a robot description names (URDF, xacro and MJCF meshes,
MJCF ``meshdir``/``include``), mesh files checked before they are read, and no parser but
robokit's reads an MJCF file."""
import os

import numpy as np
import pytest

import hardening_support as hs


@pytest.fixture
def layout(tmp_path):
    """tmp/pkg (the robot's folder, with meshes/inside.stl) and tmp/outside/box.stl."""
    import trimesh

    pkg, outside = tmp_path / "pkg", tmp_path / "outside"
    (pkg / "meshes").mkdir(parents=True)
    outside.mkdir()
    box = trimesh.creation.box((0.1, 0.1, 0.1))
    box.export(pkg / "meshes" / "inside.stl")
    box.export(outside / "box.stl")
    (pkg / "meshes" / "link.stl").symlink_to(outside / "box.stl")  # inside by name, outside in fact
    return pkg, outside


def _urdf(mesh):
    return hs.urdf_text(
        links=[hs.link("base"), hs.link("arm", mass="1", extra=f'<visual><geometry><mesh filename="{mesh}"/>'
                                                              '</geometry></visual>')],
        joints=[hs.joint("j", "base", "arm")])


def _mjcf(mesh, meshdir=None, include=None):
    comp = f'<compiler meshdir="{meshdir}"/>' if meshdir else ""
    inc = f'<include file="{include}"/>' if include else ""
    return (f'<mujoco model="m">{comp}{inc}<asset><mesh name="mm" file="{mesh}"/></asset><worldbody>'
            '<body name="b"><joint name="j" axis="0 0 1"/><geom type="mesh" mesh="mm" mass="1"/></body>'
            '</worldbody></mujoco>')


def _refs(outside):
    return {"relative ../": "../outside/box.stl", "absolute": str(outside / "box.stl"),
            "symlink out": "meshes/link.stl"}


@pytest.mark.parametrize("fmt", ["urdf", "xacro", "mjcf"])
@pytest.mark.parametrize("ref", ["relative ../", "absolute", "symlink out"])
def test_outside_mesh_is_refused_by_every_format(fmt, ref, layout, main_cli):
    pkg, outside = layout
    mesh = _refs(outside)[ref]
    if fmt == "urdf":
        src = pkg / "r.urdf"
        src.write_text(_urdf(mesh if ref != "absolute" else f"file://{mesh}"))
    elif fmt == "xacro":
        src = pkg / "r.urdf.xacro"
        src.write_text(_urdf(mesh))
    else:
        src = pkg / "r.xml"
        src.write_text(_mjcf(mesh))
    run = main_cli("convert", src, "-o", pkg / "o.json")
    hs.assert_one_line_error(run, src.name, "outside")
    assert not (pkg / "o.json").exists()


@pytest.mark.parametrize("fmt", ["urdf", "xacro", "mjcf"])
def test_inside_mesh_loads_and_outside_one_only_when_allowed(fmt, layout):
    """The same robot loads with its mesh inside the folder, and with the outside mesh only with
    allow_outside_meshes=True; its FK is the one-joint closed form either way."""
    from robokit.description.loading import load

    pkg, outside = layout
    for mesh, allow in (("meshes/inside.stl", False), (str(outside / "box.stl"), True)):
        src = pkg / {"urdf": "r.urdf", "xacro": "r.urdf.xacro", "mjcf": "r.xml"}[fmt]
        src.write_text(_urdf(mesh) if fmt != "mjcf" else _mjcf(mesh))
        robot = load(src, allow_outside_meshes=allow)
        assert robot.n == 1
        assert robot.visual_model is not None and robot.visual_model.ngeoms >= 1
        T = robot.frame_pose([0.3])
        assert np.allclose(T[:3, :3], [[np.cos(0.3), -np.sin(0.3), 0], [np.sin(0.3), np.cos(0.3), 0], [0, 0, 1]])


@pytest.mark.parametrize("case", ["meshdir absolute", "meshdir ../", "include outside", "include absolute"])
def test_mjcf_directories_and_includes_are_confined(case, layout, main_cli):
    pkg, outside = layout
    (outside / "inc.xml").write_text('<mujoco><default/></mujoco>')
    text = {
        "meshdir absolute": _mjcf("box.stl", meshdir=str(outside)),
        "meshdir ../": _mjcf("box.stl", meshdir="../outside"),
        "include outside": _mjcf("meshes/inside.stl", include="../outside/inc.xml"),
        "include absolute": _mjcf("meshes/inside.stl", include=str(outside / "inc.xml")),
    }[case]
    src = pkg / "r.xml"
    src.write_text(text)
    run = main_cli("convert", src, "-o", pkg / "o.json")
    hs.assert_one_line_error(run, "r.xml", "outside")


def test_mjcf_include_is_bounded_and_counted(layout, main_cli):
    """An include inside the folder is read with the same bounds: a DTD in it is refused, and
    its joints count toward the limit."""
    pkg, _ = layout
    (pkg / "bad.xml").write_text('<?xml version="1.0"?><!DOCTYPE m [<!ENTITY a "x">]><mujoco/>')
    src = pkg / "r.xml"
    src.write_text(_mjcf("meshes/inside.stl", include="bad.xml"))
    hs.assert_one_line_error(main_cli("convert", src, "-o", pkg / "o.json"), "bad.xml", "DOCTYPE")
    joints = "".join(f'<body name="c{i}"><joint name="k{i}"/><geom size="0.1" mass="1"/></body>' for i in range(200))
    (pkg / "many.xml").write_text(f"<mujoco><worldbody>{joints}</worldbody></mujoco>")
    src.write_text(_mjcf("meshes/inside.stl", include="many.xml"))
    hs.assert_one_line_error(main_cli("convert", src, "-o", pkg / "o.json"), "r.xml", "at most 128 joints")


@pytest.mark.parametrize("kind", ["device", "fifo", "oversize"])
def test_unreadable_or_huge_mesh_is_not_read(kind, layout):
    """A URDF mesh that is a device, a FIFO or over 32 MB is dropped with a note naming it (the
    robot still loads); in MJCF it is refused (Pinocchio reads the file's meshes itself)."""
    from robokit.description.loading import load
    from robokit.errors import InputError, RobokitWarning

    pkg, _ = layout
    m = pkg / "meshes" / "bad.stl"
    if kind == "device":
        m.symlink_to("/dev/zero")
    elif kind == "fifo":
        os.mkfifo(m)
    else:
        with open(m, "wb") as f:
            f.truncate(40 << 20)
    src = pkg / "r.urdf"
    src.write_text(_urdf("meshes/bad.stl"))
    # allowed outside: a symlink to /dev/zero resolves outside the folder; the size check still holds
    with pytest.warns(RobokitWarning, match="bad.stl.*not read"):
        robot = load(src, allow_outside_meshes=True)
    assert robot.n == 1
    mj = pkg / "r.xml"
    mj.write_text(_mjcf("meshes/bad.stl"))
    with pytest.raises(InputError, match="bad.stl"):
        load(mj, allow_outside_meshes=True)


def test_pinocchio_reads_the_checked_mjcf_copy(layout, monkeypatch):
    """No parser but robokit's reads an MJCF file: Pinocchio's MJCF parser is never handed a path
    (robokit compiles the checked tree itself and builds the model from it); relative meshdir
    and includes still resolve (the mesh geometry is loaded from the package's own file)."""
    import pinocchio as pin

    from robokit.description.loading import load

    pkg, _ = layout
    (pkg / "sub").mkdir()
    (pkg / "sub" / "extra.xml").write_text('<mujoco><default><geom rgba="1 0 0 1"/></default></mujoco>')
    src = pkg / "r.xml"
    src.write_text(_mjcf("inside.stl", meshdir="meshes", include="sub/extra.xml"))
    seen = []

    def spy(filename, *a):
        seen.append(filename)
        raise AssertionError("Pinocchio's MJCF parser was called")

    monkeypatch.setattr(pin, "buildModelFromMJCF", spy)
    monkeypatch.setattr(pin, "buildGeomFromMJCF", spy)
    robot = load(src)
    assert seen == []
    paths = [go.meshPath for go in robot.visual_model.geometryObjects]
    assert np.allclose(robot.visual_model.geometryObjects[0].meshColor, [1, 0, 0, 1])  # the included default
    assert any(p.endswith("inside.stl") and p.startswith(str(pkg.resolve())) for p in paths), paths
