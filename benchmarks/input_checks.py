"""What reading robot files safely costs: robokit's bounded, checked readers beside the plain
parsers they guard, measured in the same run.

* XML check: :func:`robokit._xml.check_xml` (one streaming expat pass: no DTD, depth, element
  count) beside ``xml.etree.ElementTree.fromstring`` of the same bytes, on a UR5 URDF.
* URDF: ``robokit.description.urdf_check.read_urdf`` (bounded read, XML check, every physical
  check, meshes resolved and confined) beside ``ElementTree.parse`` and Pinocchio's
  ``buildModelFromUrdf``.
* xacro: ``expand_xacro`` (every expression through robokit's interpreter, files confined and
  bounded) beside the plain ``xacro.process_file``, on a 7-joint macro arm and on the makers'
  packages in ``tests/data`` (Universal Robots' UR5e, Franka's FR3 with its hand; the plain
  program finds their packages through a stub ``ament_index_python`` set up here).
* One expression: robokit's :func:`~robokit.description.xacro_safety.evaluate` beside
  ``eval`` of the compiled expression (what xacro does).

``.venv/bin/python -m benchmarks.input_checks [--quick]``. Times are medians (see
``benchmarks/_harness.py``); nothing is asserted.
"""
from __future__ import annotations

import math
import sys
import tempfile
import xml.etree.ElementTree as ET
from pathlib import Path

from benchmarks._harness import fmt_time, machine, table, time_call

_ARM = """<?xml version="1.0"?>
<robot name="arm" xmlns:xacro="http://www.ros.org/wiki/xacro">
<xacro:property name="l" value="0.3"/>
<xacro:property name="m" value="${2.0 * l}"/>
<xacro:arg name="prefix" default="a_"/>
<xacro:macro name="seg" params="i parent ln:=${l} axis:=z">
  <link name="$(arg prefix)link${i}">
    <inertial><origin xyz="0 0 ${ln / 2}"/><mass value="${m / (i + 1)}"/>
      <inertia ixx="${m * ln ** 2 / 12}" iyy="${m * ln ** 2 / 12}" izz="${1e-3}" ixy="0" iyz="0" ixz="0"/></inertial>
    <visual><geometry><cylinder radius="${0.04 + 0.005 * (6 - i)}" length="${ln}"/></geometry></visual>
  </link>
  <joint name="$(arg prefix)joint${i}" type="revolute">
    <parent link="${parent}"/><child link="$(arg prefix)link${i}"/>
    <origin xyz="0 0 ${ln if i > 0 else 0.1}" rpy="${radians(90) if i % 2 else 0} 0 0"/>
    <axis xyz="${'0 0 1' if axis == 'z' else '0 1 0'}"/>
    <limit lower="${-pi}" upper="${pi}" effort="${50 / (i + 1)}" velocity="${math.radians(180)}"/>
  </joint>
</xacro:macro>
<link name="base"/>
<xacro:seg i="0" parent="base"/>
<xacro:seg i="1" parent="$(arg prefix)link0" axis="y"/>
<xacro:seg i="2" parent="$(arg prefix)link1" ln="${l * 0.8}"/>
<xacro:seg i="3" parent="$(arg prefix)link2" axis="y"/>
<xacro:seg i="4" parent="$(arg prefix)link3"/>
<xacro:seg i="5" parent="$(arg prefix)link4" axis="y" ln="0.1"/>
<xacro:seg i="6" parent="$(arg prefix)link5" ln="0.05"/>
</robot>
"""


def main(argv=None) -> None:
    argv = list(sys.argv[1:] if argv is None else argv)
    quick = "--quick" in argv
    repeats = 3 if quick else 7
    import example_robot_data as erd
    import pinocchio as pin
    import xacro

    from robokit._xml import check_xml
    from robokit.description.urdf_check import read_urdf
    from robokit.description.xacro_files import expand_xacro
    from robokit.description.xacro_safety import evaluate

    ur5 = Path(erd.getModelPath("ur_description/urdf/ur5_robot.urdf")) / "ur_description/urdf/ur5_robot.urdf"
    raw = ur5.read_bytes()
    rows = []
    t_check = time_call(check_xml, raw, "ur5", repeats=repeats)
    t_et = time_call(ET.fromstring, raw, repeats=repeats)
    rows.append(["XML check (UR5 URDF)", fmt_time(t_check), "ElementTree.fromstring", fmt_time(t_et),
                 f"{t_check / t_et:.2f}"])
    t_read = time_call(read_urdf, ur5, repeats=repeats)
    t_parse = time_call(ET.parse, ur5, repeats=repeats)
    t_pin = time_call(pin.buildModelFromUrdf, str(ur5), repeats=repeats)
    rows.append(["read_urdf (UR5, all checks)", fmt_time(t_read), "ElementTree.parse", fmt_time(t_parse),
                 f"{t_read / t_parse:.2f}"])
    rows.append(["read_urdf (UR5, all checks)", fmt_time(t_read), "pinocchio.buildModelFromUrdf", fmt_time(t_pin),
                 f"{t_read / t_pin:.2f}"])
    with tempfile.TemporaryDirectory() as tmp:
        src = Path(tmp) / "arm.urdf.xacro"
        src.write_text(_ARM)
        t_ours = time_call(expand_xacro, src, repeats=repeats, target=0.2)
        t_plain = time_call(lambda: xacro.process_file(str(src)).toxml(), repeats=repeats, target=0.2)
    rows.append(["expand_xacro (7-joint macro arm)", fmt_time(t_ours), "xacro.process_file", fmt_time(t_plain),
                 f"{t_ours / t_plain:.2f}"])
    data = Path(__file__).resolve().parents[1] / "tests" / "data"
    _stub_package_index(data)
    for label, path, args in [("UR5e, ur_description", "ur_description/urdf/ur.urdf.xacro",
                               {"ur_type": "ur5e", "name": "ur"}),
                              ("FR3 + hand, franka_description", "franka_description/robots/fr3/fr3.urdf.xacro", {})]:
        t_ours = time_call(_quiet(expand_xacro), data / path, args, [data], repeats=repeats, target=0.2)
        t_plain = time_call(lambda: xacro.process_file(str(data / path), mappings=dict(args)).toxml(),
                            repeats=repeats, target=0.2)
        rows.append([f"expand_xacro ({label})", fmt_time(t_ours), "xacro.process_file", fmt_time(t_plain),
                     f"{t_ours / t_plain:.2f}"])
    expr = "m * len ** 2 / 12 + radians(90) if i % 2 else -pi"
    symbols = {"m": 0.6, "len": 0.3, "i": 3, "radians": math.radians, "pi": math.pi}
    code = compile(expr, "<expression>", "eval")
    t_eval = time_call(evaluate, expr, {"m": 0.6, "len": 0.3, "i": 3}, repeats=repeats)
    t_py = time_call(eval, code, {"__builtins__": {}}, symbols, repeats=repeats)
    rows.append(["evaluate (one expression)", fmt_time(t_eval), "eval (compiled)", fmt_time(t_py),
                 f"{t_eval / t_py:.1f}"])
    print(f"# Reading robot files safely\n\nmachine: {machine()}\n")
    print(table(["robokit", "time", "peer", "time", "ratio"], rows))


def _stub_package_index(data: Path) -> None:
    """ROS 2's package index for the plain xacro program: packages are the folders of ``data``."""
    import types

    packages = types.ModuleType("ament_index_python.packages")
    packages.get_package_share_directory = lambda name: str(data / name)  # type: ignore[attr-defined]
    index = types.ModuleType("ament_index_python")
    index.packages = packages  # type: ignore[attr-defined]
    sys.modules.setdefault("ament_index_python", index)
    sys.modules.setdefault("ament_index_python.packages", packages)


def _quiet(fn):
    """``fn`` with robokit's notes (missing meshes, duplicate YAML keys) silenced."""
    import warnings

    from robokit.errors import RobokitWarning

    def run(*args, **kwargs):
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", RobokitWarning)
            return fn(*args, **kwargs)
    return run


if __name__ == "__main__":
    main()
