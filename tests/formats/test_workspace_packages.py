"""Packages found at any depth below a ``package_dirs`` folder, as colcon and catkin find a workspace's
packages: the makers' repositories (ROS-Industrial's kuka_experimental, abb, fanuc, …) hold one folder
per package, so a workspace's ``src/`` holds them two levels down (``src/<repository>/<package>``).
Before, only ``src/<package>`` was looked at and a user's cell including a maker's macro was refused
(``package 'kuka_kr6_support' not found``) with ``package_dirs=["src"]``."""
from pathlib import Path

import pytest

import robokit
from robokit.description import meshes
from robokit.description.meshes import package_below
from robokit.description.xacro_files import find_package

DATA = Path(__file__).resolve().parents[1] / "data"


def _package(folder: Path, name: str) -> Path:
    folder.mkdir(parents=True, exist_ok=True)
    (folder / "package.xml").write_text(f"<package><name>{name}</name></package>")
    return folder


def test_nested_packages_found_as_colcon_finds_them(tmp_path):
    src = tmp_path / "src"
    deep = _package(src / "vendor" / "repo" / "arm_description", "arm_description")
    # a package inside a package is not one (colcon does not look there); ignored and hidden folders are skipped
    _package(src / "other_pkg" / "nested", "nested_pkg")
    _package(src / "ignored" / "skipped_pkg", "skipped_pkg")
    (src / "ignored" / "COLCON_IGNORE").write_text("")
    _package(src / ".hidden" / "hidden_pkg", "hidden_pkg")
    _package(src / "other_pkg", "other_pkg")
    assert find_package("arm_description", [src]) == deep.resolve()
    assert package_below(src, "arm_description") == (deep.resolve(), False)
    for name in ("nested_pkg", "skipped_pkg", "hidden_pkg"):
        assert package_below(src, name) == (None, False)
        with pytest.raises(robokit.InputError, match=f"package '{name}' not found"):
            find_package(name, [src])


def test_the_search_is_bounded_and_says_so(tmp_path, monkeypatch):
    src = tmp_path / "src"
    for i in range(6):
        (src / f"d{i}").mkdir(parents=True)
    _package(src / "d5" / "late_pkg", "late_pkg")
    monkeypatch.setattr(meshes, "MAX_PACKAGE_SEARCH", 4)
    assert package_below(src, "late_pkg") == (None, True)
    monkeypatch.setattr("robokit.description.xacro_files.MAX_PACKAGE_SEARCH", 4)
    with pytest.raises(robokit.InputError, match="stopped after 4 folders: give the folder that holds the package"):
        find_package("late_pkg", [src])


def test_a_urdf_package_mesh_found_below_package_dirs(tmp_path):
    """A plain URDF whose ``package://`` mesh lives in a package two levels below ``package_dirs``: read
    (no note that it is missing)."""
    import warnings

    src = tmp_path / "src"
    pkg = _package(src / "vendor_repo" / "arm_meshes", "arm_meshes")
    (pkg / "meshes").mkdir()
    (pkg / "meshes" / "box.stl").write_text(
        "solid b\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 0\nendloop\nendfacet\nendsolid b\n")
    urdf = tmp_path / "elsewhere" / "arm.urdf"
    urdf.parent.mkdir()
    urdf.write_text(
        '<robot name="a"><link name="base"/><link name="l1"><visual><geometry>'
        '<mesh filename="package://arm_meshes/meshes/box.stl"/></geometry></visual>'
        '<inertial><mass value="1"/><inertia ixx="0.1" iyy="0.1" izz="0.1" ixy="0" ixz="0" iyz="0"/></inertial></link>'
        '<joint name="j1" type="revolute"><parent link="base"/><child link="l1"/><axis xyz="0 0 1"/>'
        '<limit lower="-1" upper="1" effort="1" velocity="1"/></joint></robot>')
    with warnings.catch_warnings(record=True) as said:
        warnings.simplefilter("always")
        robot = robokit.load(urdf, package_dirs=[src])
    assert robot.n == 1
    assert not [w for w in said if "not found" in str(w.message)], [str(w.message) for w in said]
    with warnings.catch_warnings(record=True) as said:
        warnings.simplefilter("always")
        robokit.load(urdf)  # without package_dirs the mesh is not found: one note says so
    assert [w for w in said if "not found" in str(w.message)]
