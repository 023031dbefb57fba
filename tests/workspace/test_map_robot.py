"""Capability maps of robots from every format (shipped to Dask workers by RobotSpec), and map
files that describe their robot as data: viewing a map never opens a path it names."""
import os
import warnings
from pathlib import Path

import numpy as np
import pytest

import robokit
from robokit.cli import main as cli_main
from robokit.description import load, models_dir
from robokit.errors import InputError, RobokitWarning
from robokit.workspace import CapabilityMap, capability_map
from robokit.workspace.map_robot import MapRobot, map_robot_of

ROOT = Path(__file__).resolve().parents[2]

PLANAR_MJCF = """<mujoco model="planar_mjcf">
  <compiler angle="radian"/>
  <worldbody>
    <body name="l1">
      <joint name="j1" type="hinge" axis="0 0 1" range="-2.5 2.5"/>
      <inertial pos="0.2 0 0" mass="1" diaginertia="0.001 0.01 0.01"/>
      <body name="l2" pos="0.4 0 0">
        <joint name="j2" type="hinge" axis="0 0 1" range="-2.5 2.5"/>
        <inertial pos="0.15 0 0" mass="1" diaginertia="0.001 0.01 0.01"/>
        <body name="l3" pos="0.3 0 0">
          <joint name="j3" type="hinge" axis="0 0 1" range="-2.5 2.5"/>
          <inertial pos="0.1 0 0" mass="0.5" diaginertia="0.001 0.005 0.005"/>
          <site name="tool" pos="0.2 0 0"/>
        </body>
      </body>
    </body>
  </worldbody>
</mujoco>
"""

XACRO = """<?xml version="1.0"?>
<robot name="planar_xacro" xmlns:xacro="http://www.ros.org/wiki/xacro">
  <xacro:arg name="l1" default="0.4"/>
  <xacro:macro name="seg" params="name">
    <link name="${name}">
      <inertial><mass value="1"/><inertia ixx="0.01" iyy="0.01" izz="0.01" ixy="0" ixz="0" iyz="0"/></inertial>
    </link>
  </xacro:macro>
  <link name="base_link"/>
  <xacro:seg name="link1"/>
  <xacro:seg name="link2"/>
  <xacro:seg name="link3"/>
  <link name="tool"/>
  <joint name="j1" type="revolute"><parent link="base_link"/><child link="link1"/>
    <axis xyz="0 0 1"/><limit lower="-2.5" upper="2.5" effort="1" velocity="1"/></joint>
  <joint name="j2" type="revolute"><parent link="link1"/><child link="link2"/>
    <origin xyz="$(arg l1) 0 0"/><axis xyz="0 0 1"/><limit lower="-2.5" upper="2.5" effort="1" velocity="1"/></joint>
  <joint name="j3" type="revolute"><parent link="link2"/><child link="link3"/>
    <origin xyz="0.3 0 0"/><axis xyz="0 0 1"/><limit lower="-2.5" upper="2.5" effort="1" velocity="1"/></joint>
  <joint name="tool_joint" type="fixed"><parent link="link3"/><child link="tool"/><origin xyz="0.2 0 0"/></joint>
</robot>
"""


@pytest.fixture(scope="module")
def cluster():
    distributed = pytest.importorskip("distributed")
    env = dict(os.environ)
    os.environ["PYTHONPATH"] = os.pathsep.join([str(ROOT)] + [p for p in env.get("PYTHONPATH", "").split(os.pathsep)
                                                             if p])
    try:
        with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None,
                                      silence_logs=40) as lc, distributed.Client(lc) as client:
            yield client
    finally:
        os.environ.clear()
        os.environ.update(env)


@pytest.fixture()
def files(tmp_path):
    mjcf = tmp_path / "planar.xml"
    mjcf.write_text(PLANAR_MJCF)
    pkg = tmp_path / "ws" / "planar_pkg"
    (pkg / "urdf").mkdir(parents=True)
    (pkg / "package.xml").write_text("<package><name>planar_pkg</name></package>")
    xacro = pkg / "urdf" / "planar.urdf.xacro"
    xacro.write_text(XACRO)
    return mjcf, xacro


def test_mjcf_and_xacro_robots_get_maps_on_a_cluster_equal_to_serial(cluster, files):
    mjcf, xacro = files
    kw = dict(orientations=6, chunk_size=20)
    for robot in (load(mjcf), load(xacro, xacro_args={"l1": "0.5"})):
        assert robot.spec.kind in ("mjcf", "xacro")
        serial = capability_map(robot, 0.1, client="serial", **kw)
        dask = capability_map(robot, 0.1, client=cluster, **kw)
        assert dask.timings["workers"] == 2 and serial.timings["chunks"] >= 4
        assert np.array_equal(serial.centres, dask.centres) and np.array_equal(serial.index, dask.index)
        assert 0 < serial.index.max() and serial.index.min() < serial.index.max()
        # a reachable voxel is within the arm's reach (0.9 m, or 1.0 m with l1 = 0.5) plus half a voxel diagonal
        reach = 0.9 if robot.spec.kind == "mjcf" else 1.0
        assert np.linalg.norm(serial.reachable, axis=1).max() <= reach + 0.1 * np.sqrt(3) / 2
    # the xacro argument reached the workers: the map with the default l1 = 0.4 is another map
    default = capability_map(xacro, 0.1, client=cluster, **kw)
    assert not np.array_equal(default.centres, dask.centres) or not np.array_equal(default.index, dask.index)


@pytest.mark.parametrize("what", ["shipped", "dh table", "example-robot-data", "mjcf", "xacro", "urdf"])
def test_the_map_file_carries_its_robot_and_viewing_rebuilds_it_from_that(what, files, tmp_path):
    mjcf, xacro = files
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RobokitWarning)
        robot = {"shipped": lambda: load("rrr"), "dh table": lambda: load(load("puma560").dh),
                 "example-robot-data": lambda: load("ur5"), "mjcf": lambda: load(mjcf),
                 "xacro": lambda: load(xacro), "urdf": lambda: load(models_dir() / "puma560.urdf")}[what]()
    kind = {"shipped": "shipped", "dh table": "dh", "example-robot-data": "example-robot-data"}.get(what, "chain")
    desc = map_robot_of(robot)
    assert desc.kind == kind
    cmap = CapabilityMap(np.zeros((1, 3)), np.ones(1), np.eye(3)[None], 0.1, robot.name, description=desc)
    out = cmap.save(tmp_path / "m.npz", include_robot=True)
    with np.load(out, allow_pickle=False) as z:  # plain arrays: no pickled objects
        assert all(z[k].dtype != object for k in z.files)
        assert not any(str(robot.spec.path or "\0") in str(z[k]) for k in z.files if z[k].dtype.kind == "U")
    back = CapabilityMap.load(out)
    assert back.description == desc and back.robot == robot.name
    drawn = back.description.robot()
    rng = np.random.default_rng(0)
    for _ in range(3):
        q = robot.random_configuration(rng)
        assert np.allclose(drawn.frame_pose(q), robot.frame_pose(q), rtol=0, atol=1e-9)


def _fail_on_any_load(monkeypatch, seen):
    """Make every robot loader record its argument and refuse."""
    import robokit.description.dh_robots as dh_robots
    import robokit.description.example_robots as example_robots
    import robokit.description.loading as loading
    import robokit.description.mjcf as mjcf
    import robokit.description.urdf_files as urdf_files
    import robokit.description.xacro_files as xacro_files

    def trap(name):
        def f(*args, **kwargs):
            seen.append((name, args))
            raise AssertionError(f"{name} called with {args}")
        return f

    for mod, attr in ((loading, "load"), (xacro_files, "load_xacro"), (xacro_files, "expand_xacro"),
                      (urdf_files, "load_urdf"), (urdf_files, "_from_urdf_file"), (mjcf, "load_mjcf"),
                      (dh_robots, "load_dh_file"), (example_robots, "load_example_robot")):
        monkeypatch.setattr(mod, attr, trap(f"{mod.__name__}.{attr}"))
    for table in (loading.FILE_LOADERS,):
        for suffix, (fn, opts) in list(table.items()):
            monkeypatch.setitem(table, suffix, (trap(f"FILE_LOADERS[{suffix}]"), opts))


@pytest.mark.parametrize("named", ["payload", "missing"])
def test_a_map_naming_a_path_is_viewed_without_opening_it(named, tmp_path, monkeypatch, capsys):
    payload = tmp_path / "evil.urdf.xacro"
    if named == "payload":
        payload.write_text('<robot name="${__import__(\'os\').system(\'touch ' + str(tmp_path / "ran") + '\')}"/>')
    np.savez(tmp_path / "old.npz", centres=np.zeros((2, 3)), index=np.array([0.5, 1.0]), orientations=np.eye(3)[None],
             resolution=np.float64(0.1), robot=np.str_(str(payload)))
    seen = []
    _fail_on_any_load(monkeypatch, seen)
    page = tmp_path / "old.html"
    assert cli_main(["view", str(tmp_path / "old.npz"), "-o", str(page)]) == 0
    err = capsys.readouterr().err
    assert "--robot" in err and "does not open" in err
    assert seen == [] and not (tmp_path / "ran").exists()
    assert "<html" in page.read_text(encoding="utf-8")[:2000].lower()
    with pytest.warns(RobokitWarning, match="--robot"):
        assert CapabilityMap.load(tmp_path / "old.npz").description is None


def test_a_map_of_a_named_robot_is_drawn_by_name_only(tmp_path, monkeypatch):
    # an older map naming a shipped model by name only: drawn (a name is not a path)
    np.savez(tmp_path / "rrr.npz", centres=np.zeros((1, 3)), index=np.ones(1), orientations=np.eye(3)[None],
             resolution=np.float64(0.1), robot=np.str_("rrr"))
    assert CapabilityMap.load(tmp_path / "rrr.npz").description == MapRobot("shipped", "rrr", model="rrr")
    # a map claiming a shipped/example-robot-data name that is a path is refused as a name
    np.savez(tmp_path / "bad.npz", centres=np.zeros((1, 3)), index=np.ones(1), orientations=np.eye(3)[None],
             resolution=np.float64(0.1), robot=np.str_("x"), robot_kind=np.str_("example-robot-data"),
             robot_model=np.str_(str(tmp_path / "evil.urdf")), robot_tip=np.str_(""))
    with pytest.warns(RobokitWarning, match="not a example-robot-data name"):
        assert CapabilityMap.load(tmp_path / "bad.npz").description is None


def test_the_user_may_name_the_robot_with_dash_dash_robot(tmp_path, capsys):
    np.savez(tmp_path / "m.npz", centres=np.zeros((1, 3)), index=np.ones(1), orientations=np.eye(3)[None],
             resolution=np.float64(0.1))
    page, bare = tmp_path / "m.html", tmp_path / "bare.html"
    assert cli_main(["view", str(tmp_path / "m.npz"), "--robot", "rrr", "-o", str(page)]) == 0
    assert cli_main(["view", str(tmp_path / "m.npz"), "-o", str(bare)]) == 0
    assert page.stat().st_size > bare.stat().st_size  # the arm's geometry is in the page
    assert cli_main(["view", "rrr", "--robot", "rrr", "-o", str(page)]) == 2
    assert "--robot" in capsys.readouterr().err


@pytest.mark.parametrize("entries, word", [
    (dict(robot_kind=np.str_("path")), "robot_kind"),
    (dict(robot_kind=np.array([1, 2])), "robot_kind"),
    (dict(robot_kind=np.str_("chain")), "robot_joint_types"),
])
def test_bad_descriptions_are_refused(entries, word, tmp_path):
    np.savez(tmp_path / "m.npz", centres=np.zeros((1, 3)), index=np.ones(1), orientations=np.eye(3)[None],
             resolution=np.float64(0.1), robot=np.str_("x"), **entries)
    with pytest.raises(InputError, match=word):
        CapabilityMap.load(tmp_path / "m.npz")


@pytest.mark.parametrize("change, word", [
    (dict(joint_types=np.array(["R", "X"])), "joint_types"),
    (dict(joint_placements=np.full((2, 4, 4), np.nan)), "joint_placements"),
    (dict(joint_axes=np.zeros((2, 3))), "joint_axes"),
    (dict(joint_axes=np.ones((3, 3)) / np.sqrt(3)), "joint_axes"),
    (dict(tip_placement=2 * np.eye(4)), "tip_placement"),
    (dict(joint_types=np.array(["R"] * 100000), joint_placements=np.tile(np.eye(4), (100000, 1, 1)),
          joint_axes=np.tile([0.0, 0, 1], (100000, 1))), "joint_types"),
])
def test_a_stick_model_checks_its_arrays(change, word):
    from robokit.description.stick import stick_robot

    good = dict(joint_types=np.array(["R", "P"]), joint_placements=np.tile(np.eye(4), (2, 1, 1)),
                joint_axes=np.array([[0.0, 0, 1], [1.0, 0, 0]]), tip_placement=np.eye(4))
    assert stick_robot("ok", **good).n == 2
    with pytest.raises(InputError, match=word):
        stick_robot("bad", **{**good, **change})
