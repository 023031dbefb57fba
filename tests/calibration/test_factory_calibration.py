"""A real UR5e as its owner has it: Universal Robots' own description package (ur_description's
``ur.urdf.xacro``) with the factory calibration UR's ``calibration_correction`` tool extracted from
that robot's controller (tests/data/ur_calibration/SOURCE), passed as the package's
``kinematics_params`` argument the way a ROS launch file passes it.

The robot's joint placements are off the nominal UR5e by up to 3.5 mrad and 0.68 mm, so its axes
are nearly, not exactly, those of a three-parallel-axes arm: ``ik_analytic`` detects the structure
and returns the calibrated arm's exact solutions. Checked against the xacro program's own expansion
read by Pinocchio, against a 500-start numerical sweep, and (the generated C) against Python.
"""
import shutil
import warnings
from pathlib import Path

import numpy as np
import pinocchio as pin
import pytest

import robokit
from robokit.errors import DegreesWarning, InputError, RobokitWarning
from robokit.ik import ik_analytic, ik_analytic_kind
from shared_robots import factory_ur5e

DATA = Path(__file__).resolve().parents[1] / "data"
XACRO = DATA / "ur_description" / "urdf" / "ur.urdf.xacro"
CALIBRATION = DATA / "ur_calibration" / "ur5e_factory_calibration.yaml"
DEFAULT = DATA / "ur_description" / "config" / "ur5e" / "default_kinematics.yaml"


def angle_dist(a, b):
    d = np.asarray(a, float) - np.asarray(b, float)
    return float(np.abs(np.angle(np.exp(1j * d))).max())


def load(calibration, package_dirs=(DATA,)):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RobokitWarning)  # (its meshes are not copied)
        return robokit.load(XACRO, xacro_args={"ur_type": "ur5e", "name": "ur", "kinematics_params": str(calibration)},
                            package_dirs=list(package_dirs))


@pytest.fixture(scope="module")
def ur5e():
    return factory_ur5e()


def xacro_program(calibration):
    """The xacro program's expansion of the same file and arguments (ROS's package lookup pointed at
    tests/data), read by Pinocchio: an independent reading of the calibrated robot."""
    import subprocess
    import sys

    script = (
        "import os, sys, types\n"
        "packages = types.ModuleType('ament_index_python.packages')\n"
        "packages.get_package_share_directory = lambda name: os.path.join(sys.argv[1], name)\n"
        "index = types.ModuleType('ament_index_python'); index.packages = packages\n"
        "sys.modules['ament_index_python'], sys.modules['ament_index_python.packages'] = index, packages\n"
        "import xacro\n"
        "sys.stdout.write(xacro.process_file(sys.argv[2], mappings={'ur_type': 'ur5e', 'name': 'ur',"
        " 'kinematics_params': sys.argv[3]}).toxml())\n")
    run = subprocess.run([sys.executable, "-c", script, str(DATA), str(XACRO), str(calibration)],
                         capture_output=True, text=True, timeout=120, check=False)
    assert run.returncode == 0, run.stderr[-2000:]
    return pin.buildModelFromXML(run.stdout)


def test_the_calibration_file_the_user_names_is_read_wherever_it_is(tmp_path):
    """The file is outside every folder robokit reads a description's files from (the xacro file's
    folder, its package, package_dirs): named by the user as an argument's value, it is read; the
    robot is the xacro program's, to 1e-12, and not the default UR5e."""
    home = tmp_path / "home"
    home.mkdir()
    mine = shutil.copy(CALIBRATION, home / "my_robot_calibration.yaml")
    robot = load(mine)
    model = xacro_program(mine)
    data = model.createData()
    tip = model.getFrameId(robot.tip)
    default = load(DEFAULT)
    rng = np.random.default_rng(3)
    moved = 0.0
    for _ in range(20):
        q = robot.random_configuration(rng)
        pin.framesForwardKinematics(model, data, q)
        assert np.abs(robot.frame_pose(q) - data.oMf[tip].homogeneous).max() < 1e-12
        moved = max(moved, float(np.abs(robot.frame_pose(q)[:3, 3] - default.frame_pose(q)[:3, 3]).max()))
    assert moved > 5e-4  # the calibration was applied: the tool is not where the default model puts it


def test_a_file_the_user_did_not_name_is_still_refused_outside_the_folders(tmp_path):
    """Naming one file does not open the folder: a description that reads another file beside it
    is refused, and the message says how to allow it."""
    home = tmp_path / "home"
    home.mkdir()
    shutil.copy(CALIBRATION, home / "mine.yaml")
    other = shutil.copy(CALIBRATION, home / "other.yaml")
    arm = tmp_path / "pkg" / "arm.urdf.xacro"
    arm.parent.mkdir()
    arm.write_text(f"""<?xml version="1.0"?>
<robot name="arm" xmlns:xacro="http://www.ros.org/wiki/xacro">
  <xacro:arg name="calibration" default=""/>
  <link name="base_${{xacro.load_yaml('{other}')['kinematics']['hash']}}"/>
</robot>
""")
    with pytest.raises(InputError) as err:
        robokit.load(arm, xacro_args={"calibration": str(home / "mine.yaml")})
    message = str(err.value)
    assert "other.yaml" in message and "is outside the file's folder" in message
    assert "package_dirs" in message and "xacro argument" in message


def test_the_structure_is_detected(ur5e):
    kind = ik_analytic_kind(ur5e)
    assert kind.method == "calibrated three parallel axes"
    assert kind.reason.startswith("detected")


def test_every_root_a_sweep_finds_is_returned_exactly(ur5e):
    """30 random poses: each returned solution reaches the pose through Pinocchio's model of the
    xacro program's expansion to 1e-9, the generating configuration is among them, and every distinct
    root robokit's compiled Levenberg–Marquardt finds from 500 starts is returned."""
    from robokit.kernels.ik import solve_poe_ik

    model = xacro_program(CALIBRATION)
    data = model.createData()
    tip = model.getFrameId(ur5e.tip)
    rng = np.random.default_rng(11)
    wide = np.tile([-4 * np.pi, 4 * np.pi], (6, 1))
    flagged = 0
    for _ in range(30):
        q_true = ur5e.random_configuration(rng)
        T = ur5e.frame_pose(q_true)
        with warnings.catch_warnings(record=True) as said:
            warnings.simplefilter("always", RobokitWarning)
            sols = ik_analytic(ur5e, T)
        flagged += bool(said)
        assert sols and min(angle_dist(s.q, q_true) for s in sols) < 1e-7
        for s in sols:
            pin.framesForwardKinematics(model, data, s.q)
            assert np.abs(data.oMf[tip].homogeneous - T).max() < 1e-9, s.label
        found = []
        for k in range(500):
            q, ok, _, _ = solve_poe_ik(ur5e.poe.M, ur5e.poe.Slist, T, rng.uniform(-np.pi, np.pi, 6), wide,
                                       tol=1e-11, max_iterations=60, max_restarts=0, seed=k)
            with warnings.catch_warnings():  # the sweep's joints roam ±4π on purpose
                warnings.simplefilter("ignore", DegreesWarning)
                reached = ok and np.abs(ur5e.frame_pose(q) - T).max() < 1e-9
            if reached and not any(angle_dist(q, f) < 1e-6 for f in found):
                found.append(q)
        assert found, "the sweep found nothing: the check would be empty"
        for f in found:
            assert min(angle_dist(f, s.q) for s in sols) < 1e-6, "a root of the sweep is not returned"
    assert flagged < 30  # most poses are regular: the check is not only of the near-singular search


@pytest.mark.parametrize("q", [
    [-1.830102417, -0.2687234546, -2.3058744141, -1.4019897329, -2.8103473066, -2.367468033],
    [-2.749637714, -0.5890611943, -1.9812215698, -0.6257365543, 2.8589655377, 0.6780366921],
    [1.4384359007, -0.6140311801, -1.7635328024, -1.2515467507, 3.0040061768, 0.0172771545]])
def test_with_the_wrist_centre_near_the_shoulder_offset_cylinder_the_roots_are_found(ur5e, q):
    """Three of 9,000 random reachable poses of this robot put its wrist centre just inside the
    projected arm's shoulder-offset cylinder (no θ₁ for the projected arm: 0.8–1.8 % inside): the
    shoulder's fold starts give every root the sweep finds, with the nominal labels (before them, the
    calibrated path returned none and ``ik_analytic`` fell back to the general 6R method)."""
    from robokit.ik.closed_form import analytic_ik
    from robokit.kernels import calibrated_ik as kci, closed_form as kcf
    from robokit.kernels.ik import solve_poe_ik

    T = ur5e.frame_pose(np.array(q))
    cal = analytic_ik(ur5e).calibrated
    parts = kcf._unpack(cal._KC[kci._LEN:], np.ascontiguousarray(T))
    assert kcf._parallel_shoulders(parts[1], parts[4], np.empty(2), np.empty(2, dtype=np.int64)) == 0
    sols = cal._solve_checked(np.ascontiguousarray(T), 0.0)
    assert sols and not any(s.label.startswith("solution ") for s in sols)
    rng = np.random.default_rng(5)
    wide = np.tile([-4 * np.pi, 4 * np.pi], (6, 1))
    for k in range(500):
        x, ok, _, _ = solve_poe_ik(ur5e.poe.M, ur5e.poe.Slist, T, rng.uniform(-np.pi, np.pi, 6), wide,
                                   tol=1e-11, max_iterations=60, max_restarts=0, seed=k)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", DegreesWarning)
            reached = ok and np.abs(ur5e.frame_pose(x) - T).max() < 1e-9
        if reached:
            assert min(angle_dist(x, s.q) for s in sols) < 1e-6, "a root of the sweep is not returned"
    assert min(angle_dist(q, s.q) for s in sols) < 1e-7
