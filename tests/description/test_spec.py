"""RobotSpec: every loader records one; it pickles, and load(spec) rebuilds an equal robot."""
import pickle
import warnings

import numpy as np
import pytest

import robokit
from robokit.description import RobotSpec, load, models_dir
from robokit.description.xacro_files import expand_xacro, find_package, load_xacro
from robokit.errors import InputError

MJCF = """<mujoco model="spec_arm">
  <compiler angle="radian"/>
  <option gravity="0 0 -9.81"/>
  <worldbody>
    <body name="l1" pos="0 0 0.1">
      <joint name="j1" type="hinge" axis="0 0 1" range="-3 3"/>
      <inertial pos="0 0 0.15" mass="1" diaginertia="0.01 0.01 0.002"/>
      <geom type="capsule" fromto="0 0 0 0 0 0.3" size="0.03"/>
      <body name="l2" pos="0 0 0.3">
        <joint name="j2" type="hinge" axis="0 1 0" range="-2 2"/>
        <inertial pos="0.15 0 0" mass="1" diaginertia="0.002 0.01 0.01"/>
        <body name="l3" pos="0.3 0 0">
          <joint name="j3" type="slide" axis="1 0 0" range="0 0.2"/>
          <inertial pos="0.1 0 0" mass="0.5" diaginertia="0.001 0.005 0.005"/>
          <site name="tool" pos="0.2 0 0"/>
        </body>
      </body>
    </body>
  </worldbody>
</mujoco>
"""

XACRO = """<?xml version="1.0"?>
<robot name="spec_xacro" xmlns:xacro="http://www.ros.org/wiki/xacro">
  <xacro:arg name="l1" default="0.4"/>
  <xacro:property name="l2" value="0.3"/>
  <xacro:macro name="seg" params="name">
    <link name="${name}">
      <inertial><mass value="1"/><inertia ixx="0.01" iyy="0.01" izz="0.01" ixy="0" ixz="0" iyz="0"/></inertial>
    </link>
  </xacro:macro>
  <link name="base_link"/>
  <xacro:seg name="link1"/>
  <xacro:seg name="link2"/>
  <link name="tool"/>
  <joint name="j1" type="revolute"><parent link="base_link"/><child link="link1"/>
    <origin xyz="0 0 0"/><axis xyz="0 0 1"/><limit lower="-3" upper="3" effort="1" velocity="1"/></joint>
  <joint name="j2" type="revolute"><parent link="link1"/><child link="link2"/>
    <origin xyz="$(arg l1) 0 0"/><axis xyz="0 0 1"/><limit lower="-3" upper="3" effort="1" velocity="1"/></joint>
  <joint name="tool_joint" type="fixed"><parent link="link2"/><child link="tool"/><origin xyz="${l2} 0 0"/></joint>
</robot>
"""


def write_mjcf(folder):
    path = folder / "spec_arm.xml"
    path.write_text(MJCF)
    return path


def write_xacro_package(folder):
    """``folder/ws/spec_pkg`` (a package with package.xml) holding ``urdf/arm.urdf.xacro``."""
    pkg = folder / "ws" / "spec_pkg"
    (pkg / "urdf").mkdir(parents=True)
    (pkg / "package.xml").write_text("<package><name>spec_pkg</name></package>")
    path = pkg / "urdf" / "arm.urdf.xacro"
    path.write_text(XACRO)
    return path


def _table():
    return robokit.DHTable.from_yaml(models_dir() / "puma560.yaml")


def _cases(tmp_path):
    xacro = write_xacro_package(tmp_path)
    return {
        "shipped": lambda: load("rrr"),
        "dh file": lambda: load(models_dir() / "twolink.yaml"),
        "dh table": lambda: load(_table()),
        "urdf": lambda: load(models_dir() / "puma560.urdf", tip="dh_5"),
        "xacro": lambda: load(xacro, package_dirs=[tmp_path / "ws"], xacro_args={"l1": "0.55"}),
        "mjcf": lambda: load(write_mjcf(tmp_path)),
        "example-robot-data": lambda: load("ur5"),
    }


KINDS = ["shipped", "dh file", "dh table", "urdf", "xacro", "mjcf", "example-robot-data"]
SPEC_KIND = {"shipped": "shipped", "dh file": "dh", "dh table": "dh", "urdf": "urdf", "xacro": "xacro",
             "mjcf": "mjcf", "example-robot-data": "example-robot-data"}


def _same_robot(a, b):
    assert (a.name, a.n, a.tip, tuple(a.joint_names)) == (b.name, b.n, b.tip, tuple(b.joint_names))
    assert np.array_equal(a.qlim, b.qlim) and np.array_equal(a.gravity, b.gravity)
    rng = np.random.default_rng(3)
    for _ in range(5):
        q = a.random_configuration(rng)
        assert np.allclose(a.frame_pose(q), b.frame_pose(q), rtol=0, atol=1e-12)
        assert np.allclose(a.rnea(q, q, q), b.rnea(q, q, q), rtol=0, atol=1e-9)


@pytest.mark.parametrize("kind", KINDS)
def test_every_loader_records_a_spec_that_pickles_and_rebuilds_the_robot(kind, tmp_path):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        robot = _cases(tmp_path)[kind]()
        spec = robot.spec
        assert isinstance(spec, RobotSpec) and spec.kind == SPEC_KIND[kind]
        assert robot.source == spec.describe()
        back = pickle.loads(pickle.dumps(spec))
        assert back == spec and hash(back) == hash(spec)
        with pytest.raises(AttributeError):
            spec.kind = "urdf"  # frozen
        again = robokit.load(back)
    assert again.spec == spec
    _same_robot(robot, again)


def test_spec_holds_the_options_and_absolute_paths(tmp_path):
    xacro = write_xacro_package(tmp_path)
    robot = load(xacro, package_dirs=[tmp_path / "ws"],
                 xacro_args={"l1": 0.55})
    spec = robot.spec
    assert spec.path == str(xacro) and spec.package_dirs == (str(tmp_path / "ws"),)
    assert spec.xacro_args == (("l1", "0.55"),)
    # the argument reached the model: joint 2 sits l1 from joint 1
    assert robot.model.jointPlacements[2].translation[0] == pytest.approx(0.55, abs=0)
    # a DH spec carries the table itself: editing the file afterwards does not change the rebuilt robot
    src = tmp_path / "arm.yaml"
    src.write_text((models_dir() / "rrr.yaml").read_text())
    arm = load(src)
    src.write_text((models_dir() / "twolink.yaml").read_text())
    assert load(arm.spec).n == 3 and load(src).n == 2


def test_relative_paths_are_recorded_absolute(tmp_path, monkeypatch):
    write_mjcf(tmp_path)
    monkeypatch.chdir(tmp_path)
    spec = load("spec_arm.xml").spec
    assert spec.path == str(tmp_path / "spec_arm.xml")
    monkeypatch.chdir("/")
    assert load(spec).n == 3


@pytest.mark.parametrize("kwargs, word", [
    (dict(kind="zip"), "kind"),
    (dict(kind="urdf"), "path"),
    (dict(kind="dh"), "text"),
    (dict(kind="shipped", name=3), "name"),
    (dict(kind="xacro", path="/a.xacro", xacro_args={"a": "1"}), "xacro_args"),
    (dict(kind="urdf", path="/a.urdf", package_dirs=["/x"]), "package_dirs"),
])
def test_bad_specs_are_refused(kwargs, word):
    with pytest.raises(InputError, match=word):
        RobotSpec(**kwargs)


def test_load_spec_takes_no_options():
    spec = load("rrr").spec
    with pytest.raises(InputError, match="tip"):
        load(spec, tip="tool")
    with pytest.raises(InputError, match="package_dirs"):
        load(spec, package_dirs=["/tmp"])


@pytest.mark.parametrize("target, option", [
    ("rrr", dict(package_dirs=["/tmp"])),
    ("spec_arm.xml", dict(xacro_args={"a": "1"})),  # (an MJCF file takes package_dirs: its sibling folders)
    ("puma560.urdf", dict(xacro_args={"a": "1"})),
])
def test_options_a_format_does_not_take_are_refused(target, option, tmp_path):
    write_mjcf(tmp_path)
    (tmp_path / "puma560.urdf").write_text((models_dir() / "puma560.urdf").read_text())
    path = target if target == "rrr" else tmp_path / target
    with pytest.raises(InputError, match=f"{next(iter(option))}: apply to"):
        load(path, **option)


def test_package_path_is_the_deprecated_name_of_package_dirs(tmp_path):
    xacro = write_xacro_package(tmp_path)
    elsewhere = tmp_path / "elsewhere.urdf.xacro"  # outside the workspace: the package must be found by option
    elsewhere.write_text(XACRO.replace('<link name="base_link"/>',
                                       '<xacro:property name="p" value="$(find spec_pkg)"/><link name="base_link"/>'))
    ws = tmp_path / "ws"
    new = load_xacro(elsewhere, package_dirs=[ws])
    with pytest.warns(FutureWarning, match="package_dirs"):
        old = load_xacro(elsewhere, package_path=[ws])
    assert old.spec == new.spec
    with pytest.warns(FutureWarning):
        assert expand_xacro(elsewhere, package_path=[ws]) == expand_xacro(elsewhere, package_dirs=[ws])
    with pytest.warns(FutureWarning):
        assert find_package("spec_pkg", package_path=[ws]) == find_package("spec_pkg", [ws]) == xacro.parents[1]
    with pytest.raises(InputError, match="package_dirs only"):
        load_xacro(elsewhere, package_dirs=[ws], package_path=[ws])

