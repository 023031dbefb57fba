"""The makers' own xacro packages, every robot and option they offer, expanded by robokit and
compared with the xacro program's own expansion of the same files.

The data are Universal Robots' ``ur_description`` and Franka's ``franka_description`` as
published (tests/data/*/SOURCE; no meshes). The reference is the ``xacro`` program itself, run in
a subprocess whose ``$(find pkg)`` is answered by a stub ``ament_index_python.packages`` module
(ROS 2's package index) mapping the package names to the vendored folders — the stub lives in
this test only; robokit finds packages itself through ``package_dirs``.

For each robot/option: the URDF robokit expands equals the program's expansion element by
element, and the robot robokit loads gives the same pose of every link frame, the same tip
Jacobian and the same RNEA as Pinocchio on the program's expansion, to 1e-12 (relative to the
quantity's scale) at random joint values.
"""
from __future__ import annotations

import functools
import json
import subprocess
import sys
import warnings
import xml.etree.ElementTree as ET
from pathlib import Path

import numpy as np
import pinocchio as pin
import pytest

import robokit
from robokit.cli import main as cli_main
from robokit.description.xacro_files import expand_xacro

DATA = Path(__file__).resolve().parents[1] / "data"
UR = "ur_description/urdf/ur.urdf.xacro"
UR_TYPES = ("ur3", "ur3e", "ur5", "ur5e", "ur10", "ur10e", "ur16e", "ur20", "ur30")


def _franka(robot: str) -> str:
    return f"franka_description/robots/{robot}/{robot}.urdf.xacro"


#: name -> (file under tests/data, xacro arguments, tip or None)
CASES: dict[str, tuple[str, dict[str, str], str | None]] = {
    **{t: (UR, {"ur_type": t, "name": "ur"}, None) for t in UR_TYPES},
    "ur5e tf_prefix safety_limits": (UR, {"ur_type": "ur5e", "name": "left", "tf_prefix": "left_",
                                          "safety_limits": "true"}, None),
    "ur10e mocked hardware": ("ur_description/urdf/ur_mocked.urdf.xacro", {"ur_type": "ur10e", "name": "ur"}, None),
    **{f"{r} hand={h}": (_franka(r), {"hand": h}, None) for r in ("fr3", "fp3", "fer") for h in ("true", "false")},
    "fr3 arm_prefix": (_franka("fr3"), {"arm_prefix": "left"}, None),
    "fer no_prefix with_sc": (_franka("fer"), {"no_prefix": "true", "with_sc": "true", "hand": "false"}, None),
    "fr3 ros2_control": (_franka("fr3"), {"ros2_control": "true", "robot_ip": "10.0.0.2"}, None),
    "fp3 gazebo": (_franka("fp3"), {"gazebo": "true"}, None),
    "multi_arm (right arm)": ("franka_description/robots/multi_arm/multi_arm.urdf.xacro", {}, "right_fr3_hand_tcp"),
}

_REFERENCE = r"""
import json, os, sys, types
data, cases = sys.argv[1], json.loads(sys.argv[2])
packages = types.ModuleType("ament_index_python.packages")
packages.get_package_share_directory = lambda name: os.path.join(data, name)
index = types.ModuleType("ament_index_python")
index.packages = packages
sys.modules["ament_index_python"], sys.modules["ament_index_python.packages"] = index, packages
import xacro
out = {}
for name, (path, args) in cases.items():
    out[name] = xacro.process_file(os.path.join(data, path), mappings=dict(args)).toxml()
sys.stdout.write(json.dumps(out))
"""


@pytest.fixture(scope="module")
def reference() -> dict[str, str]:
    """The xacro program's expansion of every case (one subprocess for all)."""
    cases = {name: (path, args) for name, (path, args, _) in CASES.items()}
    run = subprocess.run([sys.executable, "-c", _REFERENCE, str(DATA), json.dumps(cases)], capture_output=True,
                         text=True, timeout=300, check=False)
    assert run.returncode == 0, run.stderr[-3000:]
    return json.loads(run.stdout)


def _elements(text: str) -> list[tuple[str, list[tuple[str, str]], str]]:
    """Document order of (tag, sorted attributes, stripped text): comments and layout ignored."""
    return [(e.tag, sorted(e.attrib.items()), (e.text or "").strip()) for e in ET.fromstring(text).iter()]


@functools.lru_cache(maxsize=None)
def _load(name: str) -> robokit.Robot:
    """The robot of a case (loaded once per session; the tests only read it)."""
    path, args, tip = CASES[name]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", robokit.RobokitWarning)
        return robokit.load(DATA / path, tip=tip, xacro_args=args, package_dirs=[DATA])


@pytest.mark.parametrize("name", sorted(CASES))
def test_robokit_expands_and_loads_what_the_xacro_program_expands(name, reference):
    path, args, _ = CASES[name]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", robokit.RobokitWarning)
        ours = expand_xacro(DATA / path, args, [DATA])
    assert _elements(ours) == _elements(reference[name])

    robot = _load(name)
    model = pin.buildModelFromXML(reference[name])
    data = model.createData()
    joints = [model.joints[model.getJointId(j)] for j in robot.joint_names]
    iv = [j.idx_v for j in joints]
    links = [f.name for f in robot.model.frames if f.type == pin.FrameType.BODY]
    assert set(links) == {f.name for f in model.frames if f.type == pin.FrameType.BODY}
    tip = model.getFrameId(robot.tip)
    rng = np.random.default_rng(sum(map(ord, name)))
    for _ in range(3):
        q = robot.random_configuration(rng)
        dq, ddq = rng.normal(size=robot.n), rng.normal(size=robot.n)
        q_ref, v_ref, a_ref = pin.neutral(model), np.zeros(model.nv), np.zeros(model.nv)
        for j, angle in zip(joints, q):  # a continuous joint (UR3's wrist 3) is (cos, sin) in Pinocchio
            q_ref[j.idx_q:j.idx_q + j.nq] = [np.cos(angle), np.sin(angle)] if j.nq == 2 else [angle]
        v_ref[iv], a_ref[iv] = dq, ddq
        pin.framesForwardKinematics(model, data, q_ref)
        for link in links:
            want = data.oMf[model.getFrameId(link)].homogeneous
            scale = max(1.0, np.abs(want[:3, 3]).max())
            assert np.abs(robot.frame_pose(q, link) - want).max() < 1e-12 * scale, link
        J = pin.computeFrameJacobian(model, data, q_ref, tip, pin.WORLD)[:, iv]
        J = np.vstack([J[3:], J[:3]])  # robokit: angular rows first
        assert np.abs(robot.jacobian(q, reference="world") - J).max() < 1e-12 * max(1.0, np.abs(J).max())
        tau = pin.rnea(model, data, q_ref, v_ref, a_ref)[iv]
        assert np.abs(robot.rnea(q, dq, ddq) - tau).max() < 1e-12 * max(1.0, np.abs(tau).max())


def test_every_ur_type_the_package_lists_is_tested():
    """The package names its robot types in a comment of ur.urdf.xacro; all of them are cases."""
    text = (DATA / UR).read_text()
    listed = text.split("possible 'ur_type' values:")[1].split("-->")[0]
    assert {t.strip() for t in listed.split(",")} == set(UR_TYPES)


def test_options_change_the_robot():
    """The options reach the robot: the prefix renames every link, the hand adds links, the types
    differ in size (so equal answers above are not the same robot compared with itself)."""
    fr3 = _load("fr3 hand=true")
    assert fr3.tip == "fr3_hand_tcp" and _load("fr3 hand=false").tip == "fr3_link8"
    assert all(f.name.startswith("left_") for f in _load("fr3 arm_prefix").model.frames if f.name != "universe"
               and f.name not in ("base", "base_joint"))
    reach = {t: np.linalg.norm(_load(t).frame_pose(np.zeros(6))[:3, 3]) for t in ("ur3", "ur30")}
    assert reach["ur30"] > 2 * reach["ur3"]


def test_package_notes(tmp_path, capsys):
    """Loading the Franka arm: one note for its YAML's duplicate key (PyYAML's last-wins rule is
    used, as the xacro program reads it), one for all the meshes not shipped here."""
    path, args, _ = CASES["fr3 hand=true"]
    rc = cli_main(["convert", str(DATA / path), "-o", str(tmp_path / "o.json"), "--package-path", str(DATA)]
                          + [f"--xacro-arg={k}:={v}" for k, v in args.items()])
    notes = [line for line in capsys.readouterr().err.splitlines() if line.startswith("robokit: note:")]
    assert rc == 0
    dup = [n for n in notes if "duplicate key 'inertia'" in n]
    assert len(dup) == 1 and "lines 18 and 19" in dup[0] and "last value is used" in dup[0]
    assert len([n for n in notes if "mesh" in n]) == 1


@pytest.mark.parametrize("name, args, why", [
    ("fp3", {"ee_id": "cobot_pump"}, "expected one root link, found 2: base, fp3_cobot_pump"),
    ("fer", {"no_prefix": "true"}, "joint 'fer_hand_joint': parent link 'fer_link8' is not defined"),
])
def test_options_the_package_itself_gets_wrong_are_refused(name, args, why, tmp_path, capsys):
    """Two option sets of franka_description expand to a URDF that is not a robot (the xacro
    program's expansion is refused by urdfdom too): robokit refuses them with one line."""
    run = subprocess.run([sys.executable, "-c", _REFERENCE, str(DATA), json.dumps({"x": (_franka(name), args)})],
                         capture_output=True, text=True, timeout=300, check=True)
    with pytest.raises(ValueError):
        pin.buildModelFromXML(json.loads(run.stdout)["x"])
    rc = cli_main(["convert", str(DATA / _franka(name)), "-o", str(tmp_path / "o.json"), "--package-path", str(DATA)]
                  + [f"--xacro-arg={k}:={v}" for k, v in args.items()])
    err = capsys.readouterr().err.strip().splitlines()
    assert rc == 2 and err[-1].startswith("robokit: error:") and why in err[-1], err


def test_a_package_the_option_needs_is_looked_up_like_any_other(tmp_path, capsys):
    """fr3 with gazebo and ros2_control names a file of another package (franka_gazebo_bringup):
    without it, one line saying which package is missing; with a folder holding it, the robot loads."""
    path, args = DATA / _franka("fr3"), {"gazebo": "true", "ros2_control": "true"}
    with pytest.raises(robokit.InputError, match=r"\$\(find franka_gazebo_bringup\): package 'franka_gazebo_bringup' "
                                                 "not found"):
        _quiet_load(path, args, [DATA])
    extra = tmp_path / "franka_gazebo_bringup"
    extra.mkdir()
    (extra / "package.xml").write_text("<package><name>franka_gazebo_bringup</name></package>")
    robot = _quiet_load(path, args, [DATA, tmp_path])
    assert robot.n == 7 and robot.tip == "fr3_hand_tcp"


def _quiet_load(path, args, dirs):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", robokit.RobokitWarning)
        return robokit.load(path, xacro_args=args, package_dirs=dirs)


def test_paths_under_the_home_folder_load_as_the_docs_write_them(tmp_path, monkeypatch):
    """docs/formats/xacro.md loads "~/ws/src/ur_description/urdf/ur.urdf.xacro" with
    package_dirs=["~/ws/src"]: "~" is the home folder in the file's path as in package_dirs."""
    import shutil

    src = tmp_path / "ws" / "src"
    shutil.copytree(DATA / "ur_description", src / "ur_description")
    monkeypatch.setenv("HOME", str(tmp_path))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", robokit.RobokitWarning)
        ur = robokit.load("~/ws/src/ur_description/urdf/ur.urdf.xacro", xacro_args={"ur_type": "ur5e", "name": "ur"},
                          package_dirs=["~/ws/src"])
    q = np.linspace(-1.0, 1.0, 6)
    assert np.abs(ur.frame_pose(q) - _load("ur5e").frame_pose(q)).max() < 1e-15
