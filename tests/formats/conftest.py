"""Fixtures for the format tests: a small xacro description package written into a tmp
folder, an ASCII STL writer, and a summary line with the largest MuJoCo difference."""
import itertools

import numpy as np
import pytest

#: largest MuJoCo-vs-robokit difference seen in this session: (error, what)
MUJOCO_WORST = []


def pytest_terminal_summary(terminalreporter):
    if MUJOCO_WORST:
        err, what = max(MUJOCO_WORST)
        terminalreporter.write_line(f"MuJoCo comparisons: {len(MUJOCO_WORST)} robots, largest difference "
                                    f"{err:.2e} ({what})")


def write_box_stl(path, size=(0.1, 0.05, 0.05)):
    """An ASCII STL of a box centred at the origin (12 triangles), written by hand."""
    hx, hy, hz = (s / 2 for s in size)
    corners = np.array(list(itertools.product((-hx, hx), (-hy, hy), (-hz, hz))))
    hull_faces = []
    for axis in range(3):
        for sign in (-1, 1):
            idx = [i for i, c in enumerate(corners) if np.sign(c[axis]) == sign]
            a, b, c, d = idx  # binary order: a square as (a, b, d, c)
            hull_faces += [(a, b, d), (a, d, c)]
    lines = ["solid box"]
    for tri in hull_faces:
        p = corners[list(tri)]
        nrm = np.cross(p[1] - p[0], p[2] - p[0])
        centre = p.mean(axis=0)
        if nrm @ centre < 0:  # outward normals, counter-clockwise
            p = p[[0, 2, 1]]
            nrm = -nrm
        nrm = nrm / np.linalg.norm(nrm)
        lines.append(f"  facet normal {nrm[0]:.6f} {nrm[1]:.6f} {nrm[2]:.6f}")
        lines.append("    outer loop")
        lines += [f"      vertex {v[0]:.6f} {v[1]:.6f} {v[2]:.6f}" for v in p]
        lines.append("    endloop")
        lines.append("  endfacet")
    lines.append("endsolid box")
    path.write_text("\n".join(lines) + "\n")
    return path


MACROS = """<?xml version="1.0"?>
<robot xmlns:xacro="http://www.ros.org/wiki/xacro">
  <xacro:macro name="arm_link" params="name length mass">
    <link name="${name}">
      <inertial>
        <origin xyz="${length / 2} 0 0" rpy="0 0 0"/>
        <mass value="${mass}"/>
        <inertia ixx="${mass * 0.001}" iyy="${mass * length * length / 12}" izz="${mass * length * length / 12}"
                 ixy="0" ixz="0" iyz="0"/>
      </inertial>
      <visual>
        <origin xyz="${length / 2} 0 0"/>
        <geometry><mesh filename="package://demo_description/meshes/link.stl"/></geometry>
      </visual>
    </link>
  </xacro:macro>
</robot>
"""

MAIN = """<?xml version="1.0"?>
<robot name="demo" xmlns:xacro="http://www.ros.org/wiki/xacro">
  <xacro:arg name="l1" default="0.4"/>
  <xacro:arg name="m2" default="1.5"/>
  <xacro:property name="l2" value="0.3"/>
  <xacro:property name="h" value="0.2"/>
  <xacro:include filename="$(find demo_description)/urdf/macros.xacro"/>
  <link name="base_link"/>
  <xacro:arm_link name="link1" length="$(arg l1)" mass="2.0"/>
  <xacro:arm_link name="link2" length="${l2}" mass="$(arg m2)"/>
  <xacro:arm_link name="link3" length="0.1" mass="0.5"/>
  <joint name="j1" type="revolute">
    <parent link="base_link"/><child link="link1"/>
    <origin xyz="0 0 ${h}" rpy="1.5707963267948966 0 0"/><axis xyz="0 1 0"/>
    <limit lower="-3" upper="3" effort="10" velocity="2"/>
  </joint>
  <joint name="j2" type="revolute">
    <parent link="link1"/><child link="link2"/>
    <origin xyz="$(arg l1) 0 0" rpy="0 0 0.3"/><axis xyz="0 0 1"/>
    <limit lower="-2" upper="2" effort="10" velocity="2"/>
  </joint>
  <joint name="j3" type="prismatic">
    <parent link="link2"/><child link="link3"/>
    <origin xyz="${l2} 0 0"/><axis xyz="1 0 0"/>
    <limit lower="0" upper="0.2" effort="10" velocity="2"/>
  </joint>
  <link name="tool"/>
  <joint name="tool_joint" type="fixed"><parent link="link3"/><child link="tool"/><origin xyz="0.1 0 0"/></joint>
  <gazebo reference="link1"/>
</robot>
"""


def plain_urdf(l1=0.4, m2=1.5):
    """The same robot as MAIN, written out by hand (no xacro): the independent reference."""
    def link(name, length, mass):
        return (f'<link name="{name}"><inertial><origin xyz="{length / 2} 0 0"/><mass value="{mass}"/>'
                f'<inertia ixx="{mass * 0.001}" iyy="{mass * length * length / 12}" izz="{mass * length * length / 12}" '
                f'ixy="0" ixz="0" iyz="0"/></inertial></link>')
    return f"""<robot name="demo"><link name="base_link"/>{link("link1", l1, 2.0)}{link("link2", 0.3, m2)}
{link("link3", 0.1, 0.5)}
<joint name="j1" type="revolute"><parent link="base_link"/><child link="link1"/>
<origin xyz="0 0 0.2" rpy="1.5707963267948966 0 0"/><axis xyz="0 1 0"/><limit lower="-3" upper="3" effort="10" velocity="2"/></joint>
<joint name="j2" type="revolute"><parent link="link1"/><child link="link2"/><origin xyz="{l1} 0 0" rpy="0 0 0.3"/>
<axis xyz="0 0 1"/><limit lower="-2" upper="2" effort="10" velocity="2"/></joint>
<joint name="j3" type="prismatic"><parent link="link2"/><child link="link3"/><origin xyz="0.3 0 0"/><axis xyz="1 0 0"/>
<limit lower="0" upper="0.2" effort="10" velocity="2"/></joint>
<link name="tool"/><joint name="tool_joint" type="fixed"><parent link="link3"/><child link="tool"/><origin xyz="0.1 0 0"/></joint>
</robot>"""


@pytest.fixture(scope="session")
def mujoco_worst():
    """Append ``(error, what)`` for each MuJoCo comparison; the largest is printed at the end."""
    return MUJOCO_WORST


def make_dh_table(rng, n, convention, prismatic=(), drives=False):
    """A random DH table with inertias (prismatic joints at the indices in ``prismatic``), and
    motor inertia, gear ratio and viscous friction on every joint if ``drives``."""
    from robokit.description.dh import DHLink, DHTable

    links = []
    for i in range(n):
        A = rng.normal(size=(3, 3))
        I = A @ A.T * 0.01 + np.eye(3) * 0.005
        joint = "P" if i in prismatic else "R"
        links.append(DHLink(joint, float(rng.uniform(-0.4, 0.4)), float(rng.uniform(-np.pi, np.pi)),
                            float(rng.uniform(-0.3, 0.3)), float(rng.uniform(-np.pi, np.pi)),
                            np.array([-0.5, 0.5]) if joint == "P" else None, float(rng.uniform(0.5, 3.0)),
                            rng.normal(size=3) * 0.1, np.array([I[0, 0], I[1, 1], I[2, 2], I[0, 1], I[1, 2], I[0, 2]]),
                            Jm=1e-4 * (i + 1) if drives else 0.0, G=30.0 + i if drives else 1.0,
                            B=1e-3 if drives else 0.0))
    base = np.eye(4)
    base[:3, 3] = rng.normal(size=3) * 0.2
    tool = np.eye(4)
    tool[:3, 3] = rng.normal(size=3) * 0.1
    return DHTable("random_arm", convention, tuple(links), np.array([0.0, 0.0, -9.81]), base, tool)


@pytest.fixture(name="dh_table")
def dh_table_fixture():
    """:func:`make_dh_table` as a fixture."""
    return make_dh_table


@pytest.fixture(name="plain_urdf")
def plain_urdf_fixture():
    """:func:`plain_urdf`, the hand-written reference URDF text, as a fixture."""
    return plain_urdf


@pytest.fixture
def xacro_ws(tmp_path):
    """A workspace ``ws/src/demo_description`` (package.xml, urdf/demo.urdf.xacro including
    urdf/macros.xacro through $(find ...), meshes/link.stl used through package://)."""
    pkg = tmp_path / "ws" / "src" / "demo_description"
    (pkg / "urdf").mkdir(parents=True)
    (pkg / "meshes").mkdir()
    (pkg / "package.xml").write_text('<?xml version="1.0"?>\n<package format="3"><name>demo_description</name>'
                                     "<version>0.1.0</version></package>\n")
    (pkg / "urdf" / "macros.xacro").write_text(MACROS)
    (pkg / "urdf" / "demo.urdf.xacro").write_text(MAIN)
    write_box_stl(pkg / "meshes" / "link.stl")
    return pkg
