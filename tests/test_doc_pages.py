"""Every page of the documentation runs as a reader reads it, and shows what its code prints.

Each page's ```python blocks run in order as one script (one namespace, like a notebook) in a fresh
interpreter in a temporary folder; every value the page shows — a ``print(...)``'s comment, the comment
lines or the ```text block below it, a ``>>>`` example's output, a ``# SomeWarning: ...`` line — is
compared with what the code printed (the rules: tests/support/doc_pages.py). docs/getting-started.md is
run the same way by tests/test_getting_started.py, which checks the files it writes too.

A page that works on files of the reader's own (``robokit.load("arm.xml")``, a package under ``~/ws/src``)
gets stand-ins for them before it runs, in its folder (which is also its home folder ``~`` when the page
names files there): ``STAND_INS``
makes each from a file the repository has, a file a page shows, or a few lines written here. A page whose
code reads what a command line on it writes (``robokit convert ur5 -o ur5.json``) has that command run first.
"""
from __future__ import annotations

import importlib.util
import re
import shutil
import subprocess
import sys
from dataclasses import dataclass
from pathlib import Path

import doc_pages
import pytest

ROOT = Path(__file__).resolve().parents[1]
DOCS = ROOT / "docs"
DATA = ROOT / "tests" / "data"


@dataclass(frozen=True)
class Page:
    requires: tuple[str, ...] = ()   # modules the page imports beyond robokit's core (else: skipped)
    shows: int = 0                   # at least this many values shown (a page that shows none: 0)
    writes: tuple[str, ...] = ()     # files the page writes in its folder
    stand_ins: tuple[str, ...] = ()  # the reader's files it uses (STAND_INS), made before it runs
    commands: tuple[str, ...] = ()   # robokit command lines of the page, run before its Python
    home: bool = False               # its folder is its home folder too (the page names ~/...)


def _page_block(page: str, language: str, holding: str) -> str:
    """The ```language block of ``page`` that holds the text ``holding``."""
    text = (DOCS / page).read_text(encoding="utf-8")
    return next(b for b in re.findall(rf"^```{language}\n(.*?)^```", text, flags=re.S | re.M) if holding in b)


# A reader's own xacro description with the arguments docs/formats/xacro.md passes (prefix, use_gripper).
_ARM_XACRO = """<?xml version="1.0"?>
<robot name="arm" xmlns:xacro="http://www.ros.org/wiki/xacro">
  <xacro:arg name="prefix" default=""/>
  <xacro:arg name="use_gripper" default="true"/>
  <xacro:property name="p" value="$(arg prefix)"/>
  <xacro:macro name="arm_link" params="name">
    <link name="${name}">
      <inertial><origin xyz="0.2 0 0"/><mass value="1.0"/>
        <inertia ixx="0.001" iyy="0.01" izz="0.01" ixy="0" ixz="0" iyz="0"/></inertial>
    </link>
  </xacro:macro>
  <link name="${p}base_link"/>
  <xacro:arm_link name="${p}link1"/>
  <xacro:arm_link name="${p}link2"/>
  <joint name="${p}joint1" type="revolute">
    <parent link="${p}base_link"/><child link="${p}link1"/><origin xyz="0 0 0.1"/><axis xyz="0 0 1"/>
    <limit lower="-3" upper="3" effort="10" velocity="2"/>
  </joint>
  <joint name="${p}joint2" type="revolute">
    <parent link="${p}link1"/><child link="${p}link2"/><origin xyz="0.4 0 0"/><axis xyz="0 1 0"/>
    <limit lower="-2" upper="2" effort="10" velocity="2"/>
  </joint>
  <link name="${p}tool0"/>
  <joint name="${p}tool0_joint" type="fixed">
    <parent link="${p}link2"/><child link="${p}tool0"/><origin xyz="0.4 0 0"/>
  </joint>
  <xacro:if value="$(arg use_gripper)">
    <link name="${p}gripper"/>
    <joint name="${p}gripper_joint" type="fixed"><parent link="${p}tool0"/><child link="${p}gripper"/></joint>
  </xacro:if>
</robot>
"""

# docs/formats/xacro.md's demo_description: its main file is the page's; the macro file, which the page
# elides, makes one link with an inertia.
_DEMO_MACROS = """<?xml version="1.0"?>
<robot xmlns:xacro="http://www.ros.org/wiki/xacro">
  <xacro:macro name="arm_link" params="name length mass">
    <link name="${name}">
      <inertial><origin xyz="${length / 2} 0 0"/><mass value="${mass}"/>
        <inertia ixx="${mass * 0.001}" iyy="${mass * length * length / 12}" izz="${mass * length * length / 12}"
                 ixy="0" ixz="0" iyz="0"/></inertial>
    </link>
  </xacro:macro>
</robot>
"""


def _write(path: Path, text: str) -> None:
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(text, encoding="utf-8")


def _arm_urdf(folder: Path) -> None:
    from robokit.description.xacro_files import expand_xacro

    _write(folder / "src.urdf.xacro", _ARM_XACRO)
    _write(folder / "arm.urdf", expand_xacro(folder / "src.urdf.xacro", {}, None))
    (folder / "src.urdf.xacro").unlink()


def _arm_xacro(folder: Path) -> None:
    _write(folder / "arm.urdf.xacro", _ARM_XACRO)
    (folder / "ws" / "src").mkdir(parents=True, exist_ok=True)


def _slider_arm() -> str:
    return _page_block("formats/mjcf.md", "xml", 'model="slider_arm"')


def _demo_description(folder: Path) -> None:
    pkg = folder / "ws" / "src" / "demo_description"
    _write(pkg / "package.xml", '<package format="3"><name>demo_description</name><version>0.1.0</version></package>')
    _write(pkg / "urdf" / "macros.xacro", _DEMO_MACROS)
    _write(pkg / "urdf" / "demo.urdf.xacro", _page_block("formats/xacro.md", "xml", '<robot name="demo"'))


def _pusher(folder: Path) -> None:
    import pybullet_data

    shutil.copy(Path(pybullet_data.getDataPath()) / "mjcf" / "pusher.xml", folder / "pusher.xml")


#: The reader's files a page uses, by name: how each stand-in is made in the page's folder.
STAND_INS = {
    "my_arm.yaml": lambda f: shutil.copy(ROOT / "models" / "rrr.yaml", f / "my_arm.yaml"),
    "arm.urdf": _arm_urdf,  # a URDF with a tool0 frame
    "arm.urdf.xacro": _arm_xacro,  # with the ~/ws/src its loader names
    "arm.xml": lambda f: _write(f / "arm.xml", _slider_arm()),  # docs/formats/mjcf.md's example
    "slider_arm.xml": lambda f: _write(f / "slider_arm.xml", _slider_arm()),
    "pusher.xml": _pusher,  # pybullet_data's gym arm
    # an SDFormat model including model://wrist, which ~/models holds
    "model.sdf": lambda f: (shutil.copy(DATA / "sdf" / "arm" / "arm.sdf", f / "model.sdf"),
                            shutil.copytree(DATA / "sdf" / "arm" / "models", f / "models", dirs_exist_ok=True)),
    "iiwa14.sdf": lambda f: shutil.copy(DATA / "sdf" / "drake_iiwa14" / "iiwa14_no_collision.sdf", f / "iiwa14.sdf"),
    "iiwa14_no_collision.urdf": lambda f: shutil.copy(DATA / "sdf" / "drake_iiwa14" / "iiwa14_no_collision.urdf",
                                                      f / "iiwa14_no_collision.urdf"),  # Drake's URDF
    # the makers' description packages (without their meshes) under ~/ws/src
    "ur_description": lambda f: shutil.copytree(DATA / "ur_description", f / "ws" / "src" / "ur_description"),
    # a UR5e's factory calibration where calibration_correction wrote it (tests/data/ur_calibration/SOURCE)
    "my_robot_calibration.yaml": lambda f: shutil.copy(DATA / "ur_calibration" / "ur5e_factory_calibration.yaml",
                                                       f / "my_robot_calibration.yaml"),
    "franka_description": lambda f: shutil.copytree(DATA / "franka_description",
                                                    f / "ws" / "src" / "franka_description"),
    "demo_description": _demo_description,
    # the teaching arms' repositories under ~/ws/src, each package in its own folder as the makers lay them out
    "interbotix_xsarm_descriptions": lambda f: shutil.copytree(
        DATA / "interbotix" / "interbotix_xsarm_descriptions",
        f / "ws" / "src" / "interbotix_ros_manipulators" / "interbotix_ros_xsarms" / "interbotix_xsarm_descriptions"),
    "open_manipulator": lambda f: shutil.copytree(DATA / "robotis", f / "ws" / "src" / "open_manipulator",
                                                  ignore=shutil.ignore_patterns("LICENSE", "SOURCE")),
    # Kinova's and Niryo's repositories as cloned into ~/ws/src (tests/data/kinova/ros_kortex, tests/data/niryo)
    "ros_kortex": lambda f: shutil.copytree(DATA / "kinova" / "ros_kortex", f / "ws" / "src" / "ros_kortex"),
    "ned_ros": lambda f: shutil.copytree(DATA / "niryo", f / "ws" / "src" / "ned_ros"),
}


#: Every page with Python blocks, but docs/getting-started.md (tests/test_getting_started.py).
PAGES = {
    "codegen.md": Page(shows=2),
    "conventions.md": Page(shows=1),
    "formats/mjcf.md": Page(requires=("mujoco", "pybullet_data"), shows=4, stand_ins=("arm.xml", "pusher.xml",
                                                                                     "slider_arm.xml")),
    "formats/poe-json.md": Page(shows=1, commands=("convert ur5 -o ur5.json",)),
    "formats/sdf.md": Page(shows=1, stand_ins=("model.sdf", "iiwa14.sdf"), home=True),
    "formats/urdf.md": Page(shows=1, stand_ins=("iiwa14_no_collision.urdf",)),
    "formats/xacro.md": Page(shows=5, stand_ins=("arm.urdf.xacro", "ur_description", "franka_description",
                                                 "demo_description", "my_robot_calibration.yaml",
                                                 "interbotix_xsarm_descriptions", "open_manipulator", "ros_kortex",
                                                 "ned_ros"), home=True),
    "loading.md": Page(shows=4, stand_ins=("my_arm.yaml", "arm.urdf", "arm.urdf.xacro", "arm.xml", "model.sdf"),
                       home=True),
    "teach.md": Page(requires=("meshcat", "ipywidgets", "ziglang"), shows=1),
    "course/calibration.md": Page(requires=("matplotlib",), shows=7),
    "course/capability-maps.md": Page(requires=("matplotlib", "distributed"), shows=2),
    "course/control.md": Page(requires=("matplotlib",), shows=1, writes=("tracking.png",)),
    "course/dh-forward-kinematics.md": Page(shows=1),
    "course/dynamics.md": Page(shows=2),
    "course/inverse-kinematics-closed-form.md": Page(shows=6),
    "course/inverse-kinematics.md": Page(shows=4),
    "course/jacobians.md": Page(shows=1),
    "course/mobile.md": Page(shows=1),
    "course/motion.md": Page(requires=("toppra", "ompl"), shows=11),
    "course/spatial.md": Page(shows=1),
    "course/symbolic.md": Page(requires=("sympy",), shows=3),
    "course/trajectories.md": Page(requires=("matplotlib",), shows=6, writes=("via.png", "line.png")),
    "course/urdf-to-dh.md": Page(shows=2, writes=("ur5.yaml",)),
    "course/visualisation.md": Page(requires=("meshcat",), writes=("puma_move.html",)),
}


def _pages_with_python():
    return sorted(str(p.relative_to(DOCS)) for p in DOCS.rglob("*.md")
                  if doc_pages.python_blocks(p.read_text(encoding="utf-8")))


def test_every_page_with_python_is_run():
    missing = set(_pages_with_python()) - set(PAGES) - {"getting-started.md"}
    assert not missing, f"pages whose Python no test runs (add them to PAGES): {sorted(missing)}"


@pytest.mark.parametrize("name", sorted(PAGES))
def test_page_runs_and_shows_what_it_prints(name, tmp_path):
    page = PAGES[name]
    for module in page.requires:
        if importlib.util.find_spec(module) is None:
            pytest.skip(f"{name} needs {module}")
    for stand_in in page.stand_ins:
        STAND_INS[stand_in](tmp_path)
    text = (DOCS / name).read_text(encoding="utf-8")
    env = {"HOME": str(tmp_path)} if page.home else {}
    for command in page.commands:
        assert f"robokit {command}" in text, f"{name} does not show the command line robokit {command}"
        argv = [sys.executable, "-m", "robokit.cli", *command.split()]
        done = subprocess.run(argv, cwd=tmp_path, capture_output=True, text=True, timeout=600,
                              env=doc_pages.environment(env))
        assert done.returncode == 0, done.stderr[-2000:]
    run = doc_pages.run_page(DOCS / name, tmp_path, env=env)
    assert run.returncode == 0, f"{name} does not run as written:\n{run.stderr[-4000:]}"
    wrong = run.mismatches()
    assert not wrong, f"{name} shows what its code does not print:\n\n" + "\n\n".join(wrong)
    assert len(run.shown) >= page.shows, f"{name} shows {len(run.shown)} values, expected at least {page.shows}"
    for written in page.writes:
        assert (tmp_path / written).stat().st_size > 0, written


def test_the_matcher_tells_right_from_wrong():
    m = doc_pages.matches
    assert m("2.220446049250313e-16", "about 2e-16")
    assert not m("3e-15", "about 2e-16")
    assert m("0.0027392824578060097", "Yoshikawa's sqrt(det(J Jᵀ)), here about 0.0027")
    assert not m("0.0031", "about 0.0027")
    assert m("6", "6 joints") and not m("7", "6 joints") and not m("6", "60 joints")
    assert m("(1000, 8, 6) 2 8", "(1000, 8, 6) 2 8: up to 8") and not m("(1000, 8, 6) 2 8", "(1000, 8, 6) 2 80")
    assert m("left, elbow up", "'left, elbow up'")
    assert not m("left, elbow up", "'right, elbow down, no flip'")
    # several numbers: as many printed, each rounding to the shown one; 0 stands for round-off
    assert m("[0.8        0.66666667]", "about [0.8, 0.667] on the straight parts: ≤ qdmax")
    assert not m("[0.8        0.67666667]", "about [0.8, 0.667] on the straight parts")
    assert not m("[0.8        0.66666667 1.]", "about [0.8, 0.667]")
    assert m("0.5 [0. 0.] [0.   2.25 4.5 ]", "about 0.5, [0, 0], [0, 2.25, 4.5]")
    assert m("[0.00401778 1e-17]", "about [0.004, 0]") and not m("[0.00401778 0.1]", "about [0.004, 0]")
    assert m("-0.05000000000000002", "about -0.05 s: the start lies before t = 0")
    # several lines: line by line, whitespace not significant
    assert m("[[0.8 0.3]\n [0.8 0.3]]", "[[0.8  0.3]\n [0.8 0.3]]")
    assert not m("[[0.8 0.3]\n [0.8 0.31]]", "[[0.8 0.3]\n [0.8 0.3]]")
    assert not m("[[0.8 0.3]]", "[[0.8 0.3]\n [0.8 0.3]]")


def test_what_a_page_shows_is_found_in_its_code():
    text = ('```python\nimport warnings\nx = 2\nprint(x)  # 2\nprint(x + 1)  # three:\n# 3\nprint(x)\n'
            'for i in range(2):\n    print(i)\n# 0\n# 1\n'
            'y = x  # not shown: no print\n# nor this\nwarnings.warn("w", UserWarning)\n# UserWarning: w\n```\n\n'
            '```python\n>>> x * 2\n4\n>>> z = 5\n```\n\n```python\nprint(x)\n```\n\n```text\n2\n```\n')
    shown = doc_pages.shown_values(doc_pages.page_code(text))
    assert [(s.kind, s.text) for _, _, s in shown.values()] == [
        ("out", "2"), ("out", "3"), ("out", "0\n1"), ("warn", "UserWarning: w"), ("out", "4"), ("out", "2")]


def test_a_wrong_page_is_caught(tmp_path):
    page = tmp_path / "page.md"
    page.write_text('```python\nimport warnings\nprint(1 + 1)  # 3\nprint([1, 2])  # [1, 2]\n'
                    'warnings.warn("careful", UserWarning)\n# UserWarning: carefree\n```\n', encoding="utf-8")
    run = doc_pages.run_page(page, tmp_path)
    assert run.returncode == 0, run.stderr
    wrong = run.mismatches()
    assert len(wrong) == 2 and "shows\n3\nthe code printed\n2" in wrong[0] and "carefree" in wrong[1], wrong
