"""MJCF read with MuJoCo's compiler rules, checked against MuJoCo itself.

Every test file below exercises one rule of the compiler (inertia from geoms, bounds, balance,
total mass, defaults, frames, orientations, meshes, joints). For each, robokit's per-body mass,
centre of mass and inertia tensor are compared with MuJoCo's ``body_mass``/``body_ipos``/
``body_inertia``/``body_iquat``, and robokit's mass matrix and inverse dynamics with MuJoCo's
``mj_fullM`` and ``mj_inverse`` at random states. MuJoCo's ``qfrc_inverse`` holds
M q̈ + c + g (armature included in M, as in robokit) minus its passive force −b q̇, so the
comparison adds damping·q̇ to robokit's RNEA; springs and constraints are switched off in MuJoCo.
"""
import struct

import numpy as np
import pytest

import robokit
from robokit.description.mjcf_compile import compile_mjcf
from robokit.errors import InputError

mujoco = pytest.importorskip("mujoco", reason="MuJoCo is the reference (pip install mujoco)")

TOL = 1e-9


def _mj_model(path):
    m = mujoco.MjModel.from_xml_path(str(path))
    m.opt.disableflags |= int(mujoco.mjtDisableBit.mjDSBL_CONSTRAINT) | int(mujoco.mjtDisableBit.mjDSBL_SPRING)
    return m


def _full(inertia, iquat):
    R = np.zeros(9)
    mujoco.mju_quat2Mat(R, np.asarray(iquat, dtype=float))
    R = R.reshape(3, 3)
    return R @ np.diag(inertia) @ R.T


def body_differences(path):
    """Largest relative difference of mass, centre of mass and inertia tensor over the bodies."""
    m = _mj_model(path)
    c = compile_mjcf(path)
    by_name = {b.name: b for b in c.bodies}
    worst = 0.0
    for i in range(1, m.nbody):
        name = mujoco.mj_id2name(m, mujoco.mjtObj.mjOBJ_BODY, i)
        b = by_name[name] if name is not None else c.bodies[i]
        scale_m = max(1e-300, m.body_mass[i])  # relative to the body's own size: a small body counts
        scale_i = max(1e-300, np.abs(m.body_inertia[i]).max())
        worst = max(worst, abs(b.mass - m.body_mass[i]) / scale_m,
                    np.abs(b.ipos - m.body_ipos[i]).max(),
                    np.abs(_full(b.inertia, b.iquat) - _full(m.body_inertia[i], m.body_iquat[i])).max() / scale_i)
    return worst


def dynamics_differences(path, samples=8, seed=0, armature=True, **load):
    """Largest relative difference of M and inverse dynamics (robokit vs MuJoCo)."""
    robot = robokit.load(path, reflected_inertia=armature, **load)
    m = _mj_model(path)
    d = mujoco.MjData(m)
    order = [j.name for b in compile_mjcf(path).bodies for j in b.joints]  # MuJoCo's joint order
    jids = [order.index(n) for n in robot.joint_names]
    assert all(mujoco.mj_id2name(m, mujoco.mjtObj.mjOBJ_JOINT, j) in (n, None) for j, n in zip(jids, robot.joint_names))
    qa, va = [m.jnt_qposadr[j] for j in jids], [m.jnt_dofadr[j] for j in jids]
    rng = np.random.default_rng(seed)
    worst = 0.0
    for _ in range(samples):
        q = robot.random_configuration(rng)
        qd, qdd = rng.normal(size=robot.n), rng.normal(size=robot.n)
        d.qpos[:], d.qvel[:], d.qacc[:] = m.qpos0, 0.0, 0.0
        d.qpos[qa], d.qvel[va], d.qacc[va] = q, qd, qdd
        mujoco.mj_inverse(m, d)
        M = np.zeros((m.nv, m.nv))
        mujoco.mj_fullM(m, d, M)
        M_mj = M[np.ix_(va, va)]
        tau_mj = d.qfrc_inverse[va] - m.dof_damping[va] * qd
        M_rk, tau_rk = robot.crba(q), robot.rnea(q, qd, qdd)
        if not armature:  # robokit left the armature out; MuJoCo always has it
            M_rk, tau_rk = M_rk + np.diag(m.dof_armature[va]), tau_rk + m.dof_armature[va] * qdd
        worst = max(worst, np.abs(M_rk - M_mj).max() / max(1e-300, np.abs(M_mj).max()),
                    np.abs(tau_rk - tau_mj).max() / max(1e-300, np.abs(tau_mj).max()))
    return worst


def _write(tmp_path, name, xml):
    path = tmp_path / name
    path.write_text(xml)
    return path


ARM = """<mujoco model="{name}">
  <compiler {compiler}/>
  <option gravity="0.3 -1.2 -9.81"/>
  {defaults}
  <asset>{assets}</asset>
  <worldbody>
    <body name="base" pos="0.1 0 0.2" euler="5 10 15">
      <geom type="box" size="0.1 0.1 0.05"/>
      <body name="l1" pos="0 0 0.1">
        <joint name="j1" axis="0 0 1" range="-90 90" armature="0.02" damping="0.3"/>
        {l1}
        <body name="l2" pos="0.05 0 0.2" quat="0.9 0.1 0.3 -0.2">
          <joint name="j2" axis="0 1 0.2" range="-120 60" armature="0.01"/>
          {l2}
          <body name="l3" pos="0.3 0 0" xyaxes="0 1 0 -1 0.1 0">
            <joint name="j3" type="slide" axis="1 0 0" range="-0.1 0.2" armature="0.5" damping="2"/>
            {l3}
            <site name="tool" pos="0.1 0 0"/>
          </body>
        </body>
      </body>
    </body>
  </worldbody>
</mujoco>
"""

PRIMS = """<geom type="capsule" fromto="0 0 0 0.3 0.02 0.01" size="0.04"/>
<geom type="sphere" pos="0.3 0 0" size="0.05"/>
<geom type="ellipsoid" size="0.03 0.05 0.07" pos="0.1 0.1 0" euler="10 20 30"/>
<geom type="cylinder" fromto="0 0 0.05 0 0.1 0.05" size="0.03" density="2700"/>
<geom type="box" size="0.02 0.03 0.04" pos="0 0 0.1" axisangle="1 1 0 30" mass="0.4"/>"""

RULES = {
    "from_geoms_true": dict(compiler='inertiafromgeom="true"', l1=PRIMS,
                            l2='<inertial pos="0 0 0" mass="9" diaginertia="1 1 1"/>' + PRIMS,
                            l3='<geom type="box" fromto="0 0 0 0.2 0 0.05" size="0.02 0.03"/>'),
    "from_geoms_auto": dict(compiler='inertiafromgeom="auto"', l1=PRIMS,
                            l2='<inertial pos="0.1 0 0" mass="2" diaginertia="0.01 0.02 0.025"/>' + PRIMS,
                            l3='<geom type="ellipsoid" fromto="0 0 0 0.2 0.1 0" size="0.02 0.03"/>'),
    "from_geoms_false": dict(compiler='inertiafromgeom="false" boundmass="0.1" boundinertia="0.001"', l1=PRIMS,
                             l2='<inertial pos="0.1 0 0" mass="2" diaginertia="0.01 0.02 0.025"/>',
                             l3='<geom type="sphere" size="0.05"/>'),
    "shell": dict(compiler="", l1=PRIMS.replace("<geom ", '<geom shellinertia="true" '),
                  l2='<geom type="capsule" size="0.03 0.1" shellinertia="true" euler="90 0 0"/>',
                  l3='<geom type="ellipsoid" size="0.02 0.03 0.04" shellinertia="true"/>'
                     '<geom type="box" size="0.02 0.03 0.04" pos="0.05 0 0" shellinertia="true"/>'),
    "groups": dict(compiler='inertiagrouprange="0 2"', l1=PRIMS.replace("<geom ", '<geom group="3" ', 2),
                   l2=PRIMS, l3='<geom size="0.04" group="5"/><geom size="0.02" pos="0.1 0 0"/>'),
    "bounds": dict(compiler='boundmass="0.5" boundinertia="0.02"', l1="", l2='<geom size="0.001"/>',
                   l3='<inertial pos="0 0 0" mass="0.001" diaginertia="1e-6 1e-6 1e-6"/>'),
    "balance": dict(compiler='balanceinertia="true"', l1=PRIMS,
                    l2='<inertial pos="0 0.1 0" mass="3" diaginertia="0.01 0.01 0.05" euler="10 0 0"/>',
                    l3='<inertial pos="0 0 0" mass="1" fullinertia="0.1 0.01 0.01 0.001 0.002 0.003"/>'),
    "totalmass": dict(compiler='settotalmass="12"', l1=PRIMS, l2=PRIMS,
                      l3='<inertial pos="0 0 0" mass="1" fullinertia="0.02 0.03 0.04 0.001 0.002 0.003"/>'),
    "totalmass_fused": dict(compiler='settotalmass="12" fusestatic="true"', l1=PRIMS,
                            l2=PRIMS + '<body name="static" pos="0.1 0 0" euler="0 30 0">' + PRIMS + "</body>",
                            l3='<geom size="0.03"/>'),
    "radian_zyx": dict(compiler='angle="radian" eulerseq="ZYX"',
                       l1='<geom type="box" size="0.02 0.03 0.04" euler="0.3 0.2 0.1" pos="0.1 0 0"/>'
                          '<geom type="capsule" size="0.02 0.1" zaxis="1 1 0"/>',
                       l2=PRIMS.replace('axisangle="1 1 0 30"', 'axisangle="1 1 0 0.5"'),
                       l3='<inertial pos="0 0 0" mass="1" diaginertia="0.01 0.02 0.025" euler="0.1 0.2 0.3"/>'),
    "fullinertia": dict(compiler="", l1='<inertial pos="0.01 0 0" mass="1.5" fullinertia="0.05 0.06 0.07 0.001 '
                                        '-0.002 0.003"/>',
                        l2='<inertial pos="0 0 0.1" mass="2" fullinertia="0.02 0.05 0.06 0.001 0.002 0.003"/>',
                        l3=PRIMS),
}


def _rule_file(tmp_path, rule, defaults="", assets="", body=None):
    """The three-link arm of ``RULES[rule]``, or of ``body`` (a rule's dict) written as ``rule``.xml."""
    r = RULES[rule] if body is None else body
    return _write(tmp_path, f"{rule}.xml", ARM.format(name=rule, compiler=r["compiler"], defaults=defaults,
                                                      assets=assets, l1=r["l1"], l2=r["l2"], l3=r["l3"]))


@pytest.mark.parametrize("rule", sorted(RULES))
def test_each_compiler_rule_gives_mujocos_bodies_and_dynamics(rule, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)  # MuJoCo 4 logs its deprecation of settotalmass to ./MUJOCO_LOG.TXT
    path = _rule_file(tmp_path, rule)
    assert body_differences(path) < TOL
    assert dynamics_differences(path) < TOL


def test_geom_masses_are_not_zero_when_mujoco_computes_them(tmp_path):
    """The defect of issue 38: geoms, no <inertial>, the robot came out massless."""
    path = _rule_file(tmp_path, "from_geoms_true")
    robot = robokit.load(path)
    m = mujoco.MjModel.from_xml_path(str(path))
    assert all(robot.model.inertias[j].mass > 0.1 for j in range(1, robot.model.njoints))
    assert abs(sum(robot.model.inertias[j].mass for j in range(robot.model.njoints)) - m.body_mass.sum()) < 1e-12


DEFAULTS = """<default>
    <geom density="500" contype="1" conaffinity="1"/>
    <joint damping="0.1"/>
    <default class="heavy"><geom density="7800" size="0.03 0.08"/>
      <default class="heavier"><geom type="capsule" density="11000"/><joint armature="0.05" damping="0.4"/></default>
    </default>
    <default class="turned"><geom euler="0 90 0" type="cylinder"/></default>
  </default>"""


def test_default_classes_childclass_and_frames(tmp_path):
    xml = f"""<mujoco model="classes"><compiler angle="radian"/>{DEFAULTS}<worldbody>
      <frame pos="0 0.1 0" euler="0 0 0.3">
        <body name="a" childclass="heavy">
          <joint name="ja" axis="0 0 1"/>
          <geom size="0.05"/>
          <geom class="turned" size="0.02 0.1" quat="1 0 0 0"/>
          <frame pos="0.1 0 0" zaxis="0 1 1" childclass="heavier">
            <geom pos="0 0 0.05"/>
            <body name="b" pos="0.2 0 0">
              <joint name="jb" axis="1 0 0" pos="0 0 0.05"/>
              <geom/>
              <frame euler="0.2 0.1 0"><site name="s" pos="0.1 0 0"/><geom class="main" size="0.04"/></frame>
            </body>
          </frame>
        </body>
      </frame></worldbody></mujoco>"""
    path = _write(tmp_path, "classes.xml", xml)
    assert body_differences(path) < TOL
    assert dynamics_differences(path) < TOL
    robot = robokit.load(path)
    m = mujoco.MjModel.from_xml_path(str(path))
    assert robot.tip == "s"
    assert np.allclose(robot.model.armature, m.dof_armature) and np.allclose(robot.model.damping, m.dof_damping)


def test_several_joints_per_body_with_anchors_and_ref(tmp_path):
    from tests.formats.mjcf_fingerprint import INLINE

    xml = INLINE["multi"]  # also in the builder's fingerprint corpus
    path = _write(tmp_path, "multi.xml", xml)
    robot = robokit.load(path)
    assert robot.joint_names == ("x", "y", "rz", "h1", "h2")
    assert dynamics_differences(path) < TOL
    # poses: at qpos, robokit's tip frame is MuJoCo's site
    m, rng = _mj_model(path), np.random.default_rng(3)
    d = mujoco.MjData(m)
    for _ in range(5):
        q = robot.random_configuration(rng)
        d.qpos[:] = q
        mujoco.mj_kinematics(m, d)
        T = robot.frame_pose(q)
        assert np.abs(T[:3, 3] - d.site_xpos[0]).max() < 1e-12
        assert np.abs(T[:3, :3] - d.site_xmat[0].reshape(3, 3)).max() < 1e-12


def test_autolimits_and_limited(tmp_path):
    base = """<mujoco><compiler autolimits="{auto}"/><worldbody><body name="a">
      <joint name="j" axis="0 0 1" range="-30 30" {limited}/><geom size="0.1"/></body></worldbody></mujoco>"""
    path = _write(tmp_path, "limits.xml", base.format(auto="true", limited=""))
    assert np.allclose(robokit.load(path).qlim, [[-np.pi / 6, np.pi / 6]])
    path = _write(tmp_path, "unlimited.xml", base.format(auto="false", limited='limited="false"'))
    assert np.isinf(robokit.load(path).qlim).all()
    path = _write(tmp_path, "refused.xml", base.format(auto="false", limited=""))
    with pytest.raises(ValueError):
        mujoco.MjModel.from_xml_path(str(path))
    with pytest.raises(InputError, match="limited"):
        robokit.load(path)


def _binary_stl(path, vertices, triangles):
    with open(path, "wb") as f:
        f.write(b"\0" * 80 + struct.pack("<i", len(triangles)))
        for t in triangles:
            f.write(struct.pack("<3f", 0, 0, 0))
            for k in t:
                f.write(struct.pack("<3f", *vertices[k]))
            f.write(b"\0\0")


def _l_prism():
    """A non-convex L-shaped prism (an L in xy extruded 0.05 m along z), outward triangles."""
    L = [(0, 0), (0.2, 0), (0.2, 0.05), (0.05, 0.05), (0.05, 0.15), (0, 0.15)]
    v = [(x, y, 0.0) for x, y in L] + [(x, y, 0.05) for x, y in L]
    n = len(L)
    tris = [(0, 2, 1), (0, 3, 2), (0, 5, 3), (3, 5, 4)]
    tris += [(a + n, b + n, c + n) for a, c, b in tris]
    for i in range(n):
        j = (i + 1) % n
        tris += [(i, j, j + n), (i, j + n, i + n)]
    return np.array(v), np.array(tris)


@pytest.mark.parametrize("mode", ["legacy", "exact", "convex", "shell"])
def test_mesh_inertia(mode, tmp_path):
    v, t = _l_prism()
    _binary_stl(tmp_path / "ell.stl", v, t)
    (tmp_path / "quad.obj").write_text("v 0 0 0\nv 0.1 0 0\nv 0.1 0.1 0\nv 0 0.1 0\nv 0 0 0.1\nv 0.1 0 0.1\n"
                                       "v 0.1 0.1 0.1\nv 0 0.1 0.1\nf 1 4 3 2\nf 5 6 7 8\nf 1 2 6 5\nf 2 3 7 6\n"
                                       "f 3 4 8 7\nf 4 1 5 8\n")
    assets = (f'<mesh name="ell" file="ell.stl" inertia="{mode}" scale="1.5 1 0.8" refpos="0.01 0 0"/>'
              f'<mesh name="cube" file="quad.obj" inertia="{mode}"/>'
              '<mesh name="tet" vertex="0 0 0 0.1 0 0 0 0.1 0 0 0 0.1"/>')
    rule = dict(compiler="", l1='<geom type="mesh" mesh="ell" euler="10 0 0"/>',
                l2='<geom type="mesh" mesh="cube" pos="0.1 0 0"/><geom type="mesh" mesh="tet" mass="0.3"/>',
                l3='<geom mesh="ell"/><geom type="box" mesh="cube" pos="0.1 0 0"/>')
    path = _rule_file(tmp_path, "_mesh", assets=assets, body=rule)
    assert body_differences(path) < TOL
    assert dynamics_differences(path) < TOL


def _prism_obj(section, twist=0.0, height=0.15, bumps=None):
    """An OBJ prism of the polygon ``section`` (counter-clockwise, in metres): bottom and top written
    as one polygon each, the sides as quads; the top turned by ``twist`` radians (the side quads are
    then not planar, their diagonals of different lengths)."""
    c, s = np.cos(twist), np.sin(twist)
    dz = np.zeros(len(section)) if bumps is None else bumps  # caps not planar
    bottom = [(x, y, -z) for (x, y), z in zip(section, dz)]
    top = [(c * x - s * y, s * x + c * y, height + z) for (x, y), z in zip(section, dz)]
    lines = [f"v {x} {y} {z}" for x, y, z in bottom + top]
    n = len(section)
    lines.append("f " + " ".join(str(i + 1) for i in reversed(range(n))))
    lines.append("f " + " ".join(str(n + i + 1) for i in range(n)))
    lines += [f"f {i + 1} {(i + 1) % n + 1} {n + (i + 1) % n + 1} {n + i + 1}" for i in range(n)]
    return "\n".join(lines) + "\n"


_ELL = [(0.2, 0.0), (0.2, 0.1), (0.1, 0.1), (0.1, 0.2), (0.0, 0.2), (0.0, 0.0)]


@pytest.mark.parametrize("twist", [0.3, -0.3, 1.0])
def test_obj_quads_are_split_along_the_shorter_diagonal_as_in_mujoco(twist, tmp_path):
    """MuJoCo splits an OBJ quad along its shorter diagonal; robokit split every quad along 0–2,
    which changes a mesh's volume and inertia when the quad is not planar. Twisted boxes, every
    face a quad: robokit's triangles are MuJoCo's own (``mesh_face``), vertex for vertex."""
    from robokit.description._mjcf_mesh import read_mesh_file

    path = tmp_path / "box.obj"
    path.write_text(_prism_obj([(0.0, 0.0), (0.2, 0.0), (0.25, 0.1), (0.0, 0.1)], twist))
    (tmp_path / "box.xml").write_text('<mujoco><asset><mesh name="m" file="box.obj"/></asset><worldbody><body name="b">'
                                      '<joint name="h"/><geom type="mesh" mesh="m"/></body></worldbody></mujoco>')
    m = mujoco.MjModel.from_xml_path(str(tmp_path / "box.xml"))
    theirs = m.mesh_face[m.mesh_faceadr[0]:m.mesh_faceadr[0] + m.mesh_facenum[0]]
    _, mine = read_mesh_file(path)
    assert m.mesh_vertnum[0] == 8
    assert sorted(map(tuple, mine.tolist())) == sorted(map(tuple, theirs.tolist()))


@pytest.mark.parametrize("seed", range(12))
def test_obj_polygons_are_split_into_mujocos_triangles(seed, tmp_path):
    """MuJoCo's own split of OBJ polygons of 5 to 14 vertices, triangle for triangle (``mesh_face``):
    prisms of random star-shaped sections, away from the origin (MuJoCo's ear test looks at it),
    their caps not planar, their sides twisted."""
    from robokit.description._mjcf_mesh import read_mesh_file

    rng = np.random.default_rng(seed)
    n = int(rng.integers(5, 15))
    angles = np.sort(rng.uniform(0.0, 2 * np.pi, n))
    radii = rng.uniform(0.03, 0.1, n)
    centre = rng.uniform(-0.3, 0.3, 2)
    section = [(centre[0] + r * np.cos(a), centre[1] + r * np.sin(a)) for a, r in zip(angles, radii)]
    path = tmp_path / "star.obj"
    path.write_text(_prism_obj(section, twist=0.2, bumps=rng.uniform(-0.01, 0.01, n)))
    (tmp_path / "star.xml").write_text('<mujoco><asset><mesh name="m" file="star.obj" inertia="shell"/></asset>'
                                       '<worldbody><body name="b"><joint name="h"/><geom type="mesh" mesh="m"/>'
                                       '</body></worldbody></mujoco>')
    m = mujoco.MjModel.from_xml_path(str(tmp_path / "star.xml"))
    theirs = m.mesh_face[m.mesh_faceadr[0]:m.mesh_faceadr[0] + m.mesh_facenum[0]]
    _, mine = read_mesh_file(path)
    assert m.mesh_vertnum[0] == 2 * n
    np.testing.assert_array_equal(mine, theirs)


def test_obj_polygons_too_costly_to_split_are_refused_in_bounded_time(tmp_path):
    """MuJoCo's ear clipping costs up to n² tries for a polygon of n vertices: a file of forty
    1000-gons is refused, naming the file and the bound, before it takes long."""
    import time

    from robokit.description._mjcf_mesh import read_mesh_file

    ring = [f"v {np.cos(a)} {np.sin(a)} 0" for a in np.linspace(0.0, 2 * np.pi, 1000, endpoint=False)]
    path = tmp_path / "disks.obj"
    path.write_text("\n".join(ring + ["f " + " ".join(str(i + 1) for i in range(1000))] * 40) + "\n")
    t0 = time.perf_counter()
    with pytest.raises(InputError, match=r"disks\.obj:\d+: its polygons take too long to split"):
        read_mesh_file(path)
    assert time.perf_counter() - t0 < 10


@pytest.mark.parametrize("mode", ["legacy", "exact", "shell"])
def test_obj_polygons_of_any_size_give_mujocos_bodies(mode, tmp_path):
    """MuJoCo 4.0.1 reads OBJ polygons of five and more vertices (MuJoCo Menagerie's ARX L5 has an
    11-gon in camera.obj, which robokit refused: "MuJoCo reads triangles and quads only"). Prisms
    of an L-shaped (non-convex) hexagon, written from three starting vertices — from (0.2, 0) a fan
    would leave the polygon — and of a pentagon: mass, centre of mass, inertia and dynamics."""
    pentagon = [(0.1 * np.cos(a), 0.1 * np.sin(a)) for a in np.linspace(0.0, 2 * np.pi, 6)[:-1]]
    for k, section in enumerate((_ELL, _ELL[1:] + _ELL[:1], _ELL[2:] + _ELL[:2], pentagon)):
        (tmp_path / f"p{k}.obj").write_text(_prism_obj(section))
    assets = "".join(f'<mesh name="p{k}" file="p{k}.obj" inertia="{mode}"/>' for k in range(4))
    rule = dict(compiler="", l1='<geom type="mesh" mesh="p0"/>', l2='<geom type="mesh" mesh="p1" euler="10 0 0"/>',
                l3='<geom type="mesh" mesh="p2" pos="0.05 0 0"/><geom type="mesh" mesh="p3" pos="0 0.1 0"/>')
    path = _rule_file(tmp_path, "_polygons", assets=assets, body=rule)
    assert body_differences(path) < TOL
    assert dynamics_differences(path) < TOL


def test_fitted_primitives_with_fitaabb(tmp_path):
    v, t = _l_prism()
    _binary_stl(tmp_path / "ell.stl", v, t)
    xml = """<mujoco><compiler fitaabb="true"/><asset><mesh name="ell" file="ell.stl"/></asset><worldbody>
      <body name="a"><joint axis="0 0 1"/><geom type="capsule" mesh="ell"/><geom type="box" mesh="ell" fitscale="1.2"/>
        <body name="b" pos="0.2 0 0"><joint axis="0 1 0"/><geom type="cylinder" mesh="ell"/><geom mesh="ell"/></body>
      </body></worldbody></mujoco>"""
    path = _write(tmp_path, "fit.xml", xml)
    assert body_differences(path) < TOL
    assert dynamics_differences(path) < TOL


def test_ascii_stl_is_refused_like_mujoco(tmp_path):
    (tmp_path / "a.stl").write_text("solid a\nendsolid a\n")
    path = _write(tmp_path, "ascii.xml", '<mujoco><asset><mesh file="a.stl"/></asset><worldbody><body name="b">'
                  '<joint/><geom type="mesh" mesh="a"/></body></worldbody></mujoco>')
    with pytest.raises(InputError, match="binary STL"):
        robokit.load(path)


def test_unbalanced_inertia_is_refused_without_balanceinertia(tmp_path):
    path = _write(tmp_path, "bad.xml", '<mujoco><worldbody><body name="b"><joint/><inertial pos="0 0 0" mass="1" '
                  'diaginertia="0.01 0.01 0.05"/></body></worldbody></mujoco>')
    with pytest.raises(ValueError):
        mujoco.MjModel.from_xml_path(str(path))
    with pytest.raises(InputError, match="'b'.*A \\+ B >= C"):
        robokit.load(path)


PYBULLET_ARMS = ["pusher", "striker", "thrower"]


@pytest.mark.parametrize("name", PYBULLET_ARMS)
def test_gym_arms_of_pybullet_data(name):
    pybullet_data = pytest.importorskip("pybullet_data")
    from pathlib import Path

    path = Path(pybullet_data.getDataPath()) / "mjcf" / f"{name}.xml"
    assert body_differences(path) < TOL
    assert dynamics_differences(path, samples=20) < TOL
    assert dynamics_differences(path, samples=5, armature=False) < TOL
    robot = robokit.load(path)
    assert robot.tip == "fingertip" and "MJCF" in repr(robot)
    assert sum(robot.model.inertias[j].mass > 1e-3 for j in range(1, 8)) >= (6 if name != "thrower" else 0)
    names = {f.name for f in robot.model.frames}
    if name == "thrower":  # unnamed bodies under wrist_roll_link, named from their parent and place
        assert {"wrist_roll_link/body1", "wrist_roll_link/body4"} <= names
        assert not any(n.endswith("Bis") for n in names)


def test_armature_option_and_note(tmp_path):
    path = _rule_file(tmp_path, "from_geoms_auto")
    with pytest.warns(UserWarning, match="armature"):
        robot = robokit.load(path)
    bare = robokit.load(path, reflected_inertia=False)
    assert bare.spec.reflected_inertia is False and robokit.load(bare.spec).spec.reflected_inertia is False
    q = robot.random_configuration(0)
    assert np.allclose(robot.crba(q) - bare.crba(q), np.diag([0.02, 0.01, 0.5]), rtol=0, atol=1e-15)
    with pytest.raises(InputError, match="reflected_inertia"):
        robokit.load("rrr", reflected_inertia=False)


try:
    from hypothesis import example, given, settings, strategies as st
except ImportError:  # pragma: no cover
    given = None


if given is not None:
    _sizes = st.floats(0.01, 0.2)
    _geom = st.tuples(st.sampled_from(["sphere", "capsule", "cylinder", "box", "ellipsoid"]),
                      st.tuples(_sizes, _sizes, _sizes), st.tuples(*[st.floats(-0.2, 0.2)] * 3),
                      st.tuples(*[st.floats(-180, 180)] * 3), st.booleans(), st.floats(100, 8000))

    @settings(max_examples=25, deadline=None)
    @given(st.lists(_geom, min_size=1, max_size=4))
    # found by this test in a CI rehearsal: a centre of mass 2⁻²³ m off the body's origin, which MuJoCo's
    # compiler takes for the origin (body_sameframe; robokit's M was 3e-8 off, 5e-7 relative)
    @example([("sphere", (0.125, 0.125, 0.125), (0.0, 0.0, 1.192092896e-07), (0.0, 0.0, 0.0), False, 100.0)])
    def test_random_geom_bodies_match_mujoco(geoms):
        import tempfile
        from pathlib import Path

        text = "".join(f'<geom type="{t}" size="{s[0]} {s[1]} {s[2]}" pos="{p[0]} {p[1]} {p[2]}" '
                       f'euler="{e[0]} {e[1]} {e[2]}" shellinertia="{str(sh).lower()}" density="{rho}"/>'
                       for t, s, p, e, sh, rho in geoms)
        xml = (f'<mujoco><worldbody><body name="a"><joint axis="0 1 0"/>{text}<body name="b" pos="0.3 0 0">'
               f'<joint axis="1 0 0"/>{text}</body></body></worldbody></mujoco>')
        with tempfile.TemporaryDirectory() as tmp:
            path = Path(tmp, "rand.xml")
            path.write_text(xml)
            try:
                mujoco.MjModel.from_xml_path(str(path))
            except ValueError:
                return  # a body MuJoCo itself refuses (e.g. A + B < C from shells)
            assert body_differences(path) < TOL
            assert dynamics_differences(path, samples=3) < TOL


@pytest.mark.parametrize("com, quat", [
    ("0 0 9.99e-7", "1 0 0 0"),      # within MuJoCo's frame tolerance: the centre of mass is the origin
    ("0 0 1e-6", "1 0 0 0"),         # at it: it is not
    ("-4e-7 8e-7 0", "1 0 9e-7 0"),  # both within: the body frame is the inertial frame
    ("0.05 0 0", "1 0 9e-7 0"),      # the orientation within, the centre of mass not (rotation only)
    ("0.05 0 0", "1 0 1.1e-6 0"),    # neither
    ("0 0 0", "-1 9e-7 0 0"),        # the other sign of the quaternion
])
def test_an_inertial_frame_within_the_compilers_tolerance_of_the_body_is_the_body_as_in_mujoco(tmp_path, com, quat):
    xml = ('<mujoco><worldbody><body name="a"><joint axis="0 1 0"/><inertial pos="0.02 0 0.1" mass="2" '
           'diaginertia="0.01 0.02 0.03"/><body name="b" pos="0.3 0 0"><joint axis="1 0 0"/>'
           f'<inertial pos="{com}" quat="{quat}" mass="3" diaginertia="0.4 0.3 0.2"/>'
           '<body name="c" pos="0 0.2 0"><joint axis="0 0 1"/><geom type="box" size="0.05 0.02 0.01" '
           f'pos="{com}" density="500"/></body></body></body></worldbody></mujoco>')
    path = _write(tmp_path, "sameframe.xml", xml)
    assert body_differences(path) < TOL
    assert dynamics_differences(path) < TOL


def _contact_arm(tmp_path, ghost_class):
    """Three links; links 2 and 3 sit 0.15 m above link 1, a sphere hangs from link 3's end
    down to link 1's height (class ``ghost_class``: masks 2/2, or the default 1/1)."""
    from tests.formats.mjcf_fingerprint import CONTACT_ARM

    xml = CONTACT_ARM.format(ghost_class=ghost_class)  # the "ghost" one is in the builder's fingerprint corpus
    return _write(tmp_path, f"contacts_{ghost_class}.xml", xml)


def _mujoco_contacts(path, q):
    m = mujoco.MjModel.from_xml_path(str(path))
    d = mujoco.MjData(m)
    d.qpos[:] = q
    mujoco.mj_forward(m, d)
    return {frozenset((mujoco.mj_id2name(m, mujoco.mjtObj.mjOBJ_GEOM, c.geom1),
                       mujoco.mj_id2name(m, mujoco.mjtObj.mjOBJ_GEOM, c.geom2))) for c in d.contact[:d.ncon]}


def test_world_honours_contype_conaffinity(tmp_path):
    from robokit.collision import World

    # folded so that link 3's end is above the middle of link 1: the ball overlaps link 1's capsule
    c3 = (0.15 ** 2 - 0.18) / 0.18
    q3 = np.arccos(c3)
    q = np.array([0.0, np.pi - np.arctan2(0.3 * np.sin(q3), 0.3 + 0.3 * c3), q3])
    ghost, solid = _contact_arm(tmp_path, "ghost"), _contact_arm(tmp_path, "main")
    rules = robokit.load(ghost).contact_rules
    assert rules.why("g1", "g3") is None                   # (1 & 1): MuJoCo tests the pair
    assert "contype/conaffinity" in rules.why("g1", "ball")  # (1 & 2) | (2 & 1) = 0
    assert "parent" in rules.why("g2", "g3")
    # the pair MuJoCo never tests is not checked, and says why
    world = World(robokit.load(ghost))
    assert frozenset(("l1", "l3")) in {frozenset(p) for p in world.self_pairs.checked}  # g1–g3 is
    reasons = [why for _, _, why in world.self_pairs.excluded]
    assert any("g1 and ball" in r and "contype/conaffinity" in r for r in reasons)
    assert "g1 and ball" in world.describe()
    assert frozenset(("g1", "ball")) not in _mujoco_contacts(ghost, q)
    assert world.colliding_pairs(q) == [] and not world.in_collision(q)
    # the same ball with the default masks: MuJoCo tests it, finds the contact, and so does World
    world = World(robokit.load(solid))
    assert frozenset(("g1", "ball")) in _mujoco_contacts(solid, q)
    assert ("l1", "l3") in world.colliding_pairs(q) and world.in_collision(q)


def test_hostile_meshes_are_refused_in_bounded_time(tmp_path):
    """A binary STL whose header claims a billion triangles, and a mesh path out of the folder."""
    import time

    with open(tmp_path / "huge.stl", "wb") as f:
        f.write(b"\0" * 80 + struct.pack("<i", 10 ** 9) + b"\0" * 50)
    path = _write(tmp_path, "huge.xml", '<mujoco><asset><mesh file="huge.stl"/></asset><worldbody><body name="b">'
                  '<joint/><geom type="mesh" mesh="huge"/></body></worldbody></mujoco>')
    t0 = time.perf_counter()
    with pytest.raises(InputError, match="binary STL"):
        robokit.load(path)
    assert time.perf_counter() - t0 < 5
    path = _write(tmp_path, "out.xml", '<mujoco><asset><mesh file="../../etc/passwd.stl"/></asset><worldbody>'
                  '<body name="b"><joint/><geom type="mesh" mesh="passwd"/></body></worldbody></mujoco>')
    with pytest.raises(InputError, match="outside"):
        robokit.load(path)


@pytest.mark.parametrize("tree", ['<body name="a" childclass="nope"><geom size="0.1"/></body>',
                                  '<frame childclass="nope"><body name="a"><geom size="0.1"/></body></frame>'])
def test_an_unknown_childclass_is_refused_on_a_body_and_on_a_frame(tree, tmp_path):
    path = _write(tmp_path, "unknown_class.xml", f"<mujoco><worldbody>{tree}</worldbody></mujoco>")
    with pytest.raises(Exception):  # MuJoCo refuses the file too
        mujoco.MjModel.from_xml_path(str(path))
    with pytest.raises(InputError, match="childclass='nope': no such default class"):
        compile_mjcf(path)


# dm_control's finger.xml (suite/finger.xml) names a body, its joint and a geom alike: MuJoCo keeps
# one namespace per kind, Pinocchio's model then has a BODY and a JOINT frame called 'distal'.
SHARED_NAMES = """<mujoco model="finger">
  <default>
    <joint type="hinge" axis="0 -1 0"/>
    <default class="finger"><joint damping="2.5" limited="true"/></default>
  </default>
  <worldbody>
    <body name="proximal" pos="-.2 0 .4" childclass="finger">
      <joint name="proximal" range="-110 110" ref="-90"/>
      <geom name="proximal" type="capsule" size=".03" fromto="0 0 0 0 0 -.17"/>
      <body name="distal" pos="0 0 -.18" childclass="finger">
        <joint name="distal" range="-110 110"/>
        <geom name="distal" type="capsule" size=".028" fromto="0 0 0 0 0 -.16"/>
        {site}
      </body>
    </body>
  </worldbody>
</mujoco>
"""


@pytest.mark.parametrize("site", ['<site name="touch" pos=".01 0 -.17"/>', ""])
def test_a_body_and_its_joint_of_one_name(site, tmp_path):
    """The default tip is found (was: Pinocchio's 'Several frames match the filter' from the
    loader), and the tip, M and inverse dynamics are MuJoCo's."""
    path = _write(tmp_path, "finger.xml", SHARED_NAMES.format(site=site))
    robot = robokit.load(path)
    assert robot.joint_names == ("proximal", "distal")
    assert robot.tip == ("touch" if site else "distal")
    assert dynamics_differences(path) < TOL
    m = _mj_model(path)
    d = mujoco.MjData(m)
    rng = np.random.default_rng(0)
    for _ in range(5):
        q = robot.random_configuration(rng)
        d.qpos[:] = q
        mujoco.mj_kinematics(m, d)
        body = mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_BODY, "distal")
        T = robot.frame_pose(q, "distal")  # the body, not the joint
        assert np.abs(T[:3, 3] - d.xpos[body]).max() < 1e-12
        assert np.abs(T[:3, :3] - d.xmat[body].reshape(3, 3)).max() < 1e-12
        if site:
            T = robot.frame_pose(q)
            assert np.abs(T[:3, 3] - d.site_xpos[0]).max() < 1e-12


@pytest.mark.parametrize("site_name, tip", [("j2", "j2"), ("hand", "hand"), ("grip", "grip")])
def test_a_site_named_like_a_joint_or_a_body(site_name, tip, tmp_path):
    """A name means the body, else the site, never the joint frame (was: a site called like its
    body's joint was the joint frame, 0.1 m from MuJoCo's site; a site called like its body was
    the default tip but posed as the body)."""
    xml = f"""<mujoco model="s"><worldbody><body name="a" pos="0 0 0.1"><joint name="j1" axis="0 0 1"/>
      <geom type="capsule" size=".03" fromto="0 0 0 0.3 0 0"/>
      <body name="hand" pos="0.3 0 0"><joint name="j2" axis="0 1 0"/><geom type="box" size=".05 .05 .05"/>
        <site name="{site_name}" pos="0.1 0 0.02"/></body></body></worldbody></mujoco>"""
    path = _write(tmp_path, "s.xml", xml)
    robot = robokit.load(path)
    assert robot.tip == tip
    m = _mj_model(path)
    d = mujoco.MjData(m)
    kind, i = ((mujoco.mjtObj.mjOBJ_BODY, 2) if tip == "hand" else (mujoco.mjtObj.mjOBJ_SITE, 0))
    assert mujoco.mj_id2name(m, kind, i) == tip
    for q in ([0.0, 0.0], [0.3, -1.2], [2.0, 0.7]):
        d.qpos[:] = q
        mujoco.mj_kinematics(m, d)
        p, R = (d.xpos[i], d.xmat[i]) if kind == mujoco.mjtObj.mjOBJ_BODY else (d.site_xpos[i], d.site_xmat[i])
        for T in (robot.frame_pose(q), robokit.load(path, tip=tip).frame_pose(q), robot.frame_pose(q, tip)):
            assert np.abs(T[:3, 3] - p).max() < 1e-12 and np.abs(T[:3, :3] - R.reshape(3, 3)).max() < 1e-12


# Sites and geoms within MuJoCo's frame tolerance of their body's frame or of its inertial frame
# (site_sameframe / geom_sameframe): MuJoCo's kinematics places them at that frame, or gives them its
# orientation. Each (pos, quat) below is one such case, with the body's inertial frame at
# (0.05, 0.02, 0.01) turned by IQUAT, and one just past the tolerance.
IQUAT = "0.9238795325112867 0 0.3826834323650898 0"
_NEAR = [
    ("4e-7 -9e-7 0", "1 0 0 0"),                                     # the body's frame
    ("0.1 0.2 0.3", "1 5e-7 0 0"),                                   # the body's orientation
    ("0.0500005 0.02 0.0099996", "0.9238799 0 0.3826830 0"),         # the inertial frame
    ("0.1 0.2 0.3", "-0.9238792 0 -0.3826839 0"),                    # its orientation (the other sign)
    ("0.1 0.2 0.3", "0.9238795 1.1e-6 0.3826834 0"),                 # past it: as written
    ("1.1e-6 0 0", "1 0 0 0"),                                       # its position past it: as written
]


def _near_frames_file(tmp_path):
    sites = "".join(f'<site name="s{k}" pos="{p}" quat="{q}"/>' for k, (p, q) in enumerate(_NEAR))
    geoms = "".join(f'<geom name="g{k}" type="box" size="0.01 0.02 0.03" pos="{p}" quat="{q}" mass="0"/>'
                    for k, (p, q) in enumerate(_NEAR))
    xml = ('<mujoco><worldbody><body name="a"><joint axis="0 1 0"/>'
           f'<inertial pos="0.05 0.02 0.01" quat="{IQUAT}" mass="2" diaginertia="0.03 0.02 0.015"/>'
           f'{sites}{geoms}<body name="b" pos="0.3 0 0"><joint axis="1 0 0"/>'
           '<inertial pos="0 0 0" quat="1 0 0 5e-7" mass="1" diaginertia="0.01 0.01 0.01"/>'
           '<site name="tip" pos="3e-7 0 0" quat="1 0 0 0"/></body></body></worldbody></mujoco>')
    return _write(tmp_path, "near_frames.xml", xml)


def test_sites_and_geoms_near_their_bodys_frames_are_placed_as_mujoco_places_them(tmp_path):
    import pinocchio as pin

    path = _near_frames_file(tmp_path)
    m = mujoco.MjModel.from_xml_path(str(path))
    assert list(m.site_sameframe[:len(_NEAR)]) == [1, 3, 2, 4, 0, 3]  # the cases are the ones meant
    assert list(m.geom_sameframe) == [1, 3, 2, 4, 0, 3]
    d = mujoco.MjData(m)
    robot = robokit.load(path, tip="tip")
    geo = pin.GeometryData(robot.collision_model)
    data = robot.model.createData()
    rng = np.random.default_rng(5)
    worst = 0.0
    for _ in range(5):
        q = robot.random_configuration(rng)
        d.qpos[:] = q
        mujoco.mj_kinematics(m, d)
        for k in range(m.nsite):
            name = mujoco.mj_id2name(m, mujoco.mjtObj.mjOBJ_SITE, k)
            T = robot.frame_pose(q, name)
            worst = max(worst, np.abs(T[:3, 3] - d.site_xpos[k]).max(), np.abs(T[:3, :3] - d.site_xmat[k].reshape(3, 3)).max())
        pin.forwardKinematics(robot.model, data, q)
        pin.updateGeometryPlacements(robot.model, data, robot.collision_model, geo)
        for k in range(m.ngeom):
            name = mujoco.mj_id2name(m, mujoco.mjtObj.mjOBJ_GEOM, k)
            X = geo.oMg[robot.collision_model.getGeometryId(name)]
            worst = max(worst, np.abs(X.translation - d.geom_xpos[k]).max(),
                        np.abs(X.rotation - d.geom_xmat[k].reshape(3, 3)).max())
    assert worst < 1e-12


def _convex_stl(path, rng):
    """A binary STL of the convex hull of 14 random points (float32, as STL stores them), sizes 3 mm–1 m."""
    import struct

    from robokit.description._mjcf_mesh import _hull_faces

    pts = rng.standard_normal((14, 3)) * rng.uniform(0.01, 0.3, 3) * 10 ** rng.uniform(-1, 0.5)
    pts = pts.astype(np.float32).astype(float)
    faces = _hull_faces(pts, "x")
    with open(path, "wb") as fh:
        fh.write(b"\0" * 80 + struct.pack("<i", len(faces)))
        for tri in faces:
            fh.write(struct.pack("<3f", 0, 0, 0) + b"".join(struct.pack("<3f", *pts[i]) for i in tri) + b"\0\0")


def test_mesh_principal_frames_are_mujocos_own(tmp_path):
    """MuJoCo 4 reduces a mesh's inertia to principal axes by Jacobi rotations it stops at a relative
    tolerance of 1e-7, short of the exact axes: robokit took the exact ones, and a body's tensor from a mesh
    was up to 9.5e-8 of its size off MuJoCo's (robosuite's hand meshes: M 1.2e-9 off). Each body's tensor
    relative to its own size (no floor: small bodies count), and each mesh geom's world frame, against
    MuJoCo's ``body_inertia``/``body_iquat`` and ``geom_xmat``."""
    import pinocchio as pin

    rng = np.random.default_rng(1)
    n = 24  # with the exact axes, 23 of these 24 are over 1e-12
    for k in range(n):
        _convex_stl(tmp_path / f"hull{k}.stl", rng)
    assets = "".join(f'<mesh name="m{k}" file="hull{k}.stl"/>' for k in range(n))
    bodies = "".join(f'<body name="b{k}" pos="0 0 0.1"><joint name="j{k}" axis="{k % 3 == 0:d} {k % 3 == 1:d} {k % 3 == 2:d}"/>'
                     f'<geom name="g{k}" type="mesh" mesh="m{k}" euler="{k} {2 * k} 0"/>' for k in range(n))
    path = _write(tmp_path, "hulls.xml", f'<mujoco><asset>{assets}</asset><worldbody>{bodies}'
                  + "</body>" * n + "</worldbody></mujoco>")
    m = mujoco.MjModel.from_xml_path(str(path))
    c = compile_mjcf(path)
    worst = 0.0
    for i in range(1, m.nbody):
        b = c.bodies[i]
        theirs = _full(m.body_inertia[i], m.body_iquat[i])
        worst = max(worst, np.abs(_full(b.inertia, b.iquat) - theirs).max() / np.abs(theirs).max())
    assert worst < 1e-12, worst
    robot = robokit.load(path)
    d = mujoco.MjData(m)
    d.qpos[:] = robot.random_configuration(rng)
    mujoco.mj_kinematics(m, d)
    data, geo = robot.model.createData(), pin.GeometryData(robot.collision_model)
    pin.forwardKinematics(robot.model, data, d.qpos.copy())
    pin.updateGeometryPlacements(robot.model, data, robot.collision_model, geo)
    frames = 0.0
    for k in range(m.ngeom):
        X = geo.oMg[robot.collision_model.getGeometryId(f"g{k}")]
        frames = max(frames, np.abs(X.translation - d.geom_xpos[k]).max(),
                     np.abs(X.rotation - d.geom_xmat[k].reshape(3, 3)).max())
    assert frames < 1e-12, frames


@pytest.mark.parametrize("ulps, swapped", [(1, False), (2, True)])
def test_near_equal_moments_keep_their_order_as_in_mujoco(tmp_path, ulps, swapped):
    """MuJoCo sorts a mesh's principal moments with a tolerance relative to the tensor's size (its
    Jacobi tolerance, 1e-7), not an absolute one: a box 0.1 m on each side but x longer by ``ulps``
    float32 steps has Iyy = Izz above Ixx by 7.5e-8 (one step: left in order, the frame the identity)
    or 1.5e-7 (two: swapped, the frame turned) of their size. robokit's frame and moments are MuJoCo's."""
    f32 = np.float32
    x = f32(0.1)
    for _ in range(ulps):
        x = np.nextafter(x, f32(1.0), dtype=f32)
    h = (x / 2, f32(0.05), f32(0.05))
    corners = [(sx * h[0], sy * h[1], sz * h[2]) for sx in (-1, 1) for sy in (-1, 1) for sz in (-1, 1)]
    faces = [(0, 1, 3), (0, 3, 2), (4, 6, 7), (4, 7, 5), (0, 4, 5), (0, 5, 1), (2, 3, 7), (2, 7, 6), (0, 2, 6),
             (0, 6, 4), (1, 5, 7), (1, 7, 3)]
    _binary_stl(tmp_path / "box.stl", corners, faces)
    path = _write(tmp_path, "box.xml", '<mujoco><asset><mesh name="box" file="box.stl"/></asset><worldbody>'
                  '<body name="b"><joint type="hinge" axis="0 0 1"/><geom type="mesh" mesh="box"/></body>'
                  '</worldbody></mujoco>')
    m = mujoco.MjModel.from_xml_path(str(path))
    ours = next(b for b in compile_mjcf(path).bodies if b.name == "b")
    assert (np.abs(m.body_iquat[1] - [1, 0, 0, 0]).max() > 0.1) == swapped  # MuJoCo's own behaviour, as stated
    assert np.abs(np.asarray(ours.iquat) - m.body_iquat[1]).max() < 1e-12
    assert np.abs(np.asarray(ours.inertia) - m.body_inertia[1]).max() < 1e-12 * m.body_inertia[1].max()


if given is not None:
    @settings(max_examples=200, deadline=None)
    @given(st.lists(st.floats(-1.0, 1.0), min_size=9, max_size=9), st.floats(-8.0, 2.0))
    @example([0.0] * 8 + [1e-5], 0.0)  # diag(1e-3, 1e-3, 1e-3 + 1e-10): left in order, as MuJoCo leaves it
    def test_the_compilers_jacobi_frame_diagonalises_to_its_tolerance(entries, log_scale):
        """:func:`jacobi_principal_axes` (the mesh frame, MuJoCo's rule): moments decreasing (to the swap
        tolerance); a right-handed unit quaternion; ``R diag(I) Rᵀ`` the matrix again to within the stopping
        tolerance (the off-diagonal entries left are at most reltol × scale, so the rebuilt matrix is within a
        few times that), and the moments LAPACK's within the same bound (Weyl: a symmetric perturbation of
        norm ε moves each eigenvalue at most ε — near a double eigenvalue the iteration stops that far off)."""
        from robokit.description._mjcf_math import MESH_EIG_RELTOL, jacobi_principal_axes, quat_to_matrix

        B = np.array(entries).reshape(3, 3)
        A = (B @ B.T + 1e-3 * np.eye(3)) * 10.0 ** log_scale  # symmetric positive definite, any size
        scale = np.abs(A).max()
        ev, q = jacobi_principal_axes(tuple(A.ravel()), MESH_EIG_RELTOL)
        assert abs(np.linalg.norm(q) - 1.0) < 1e-14
        R = np.array(quat_to_matrix(q)).reshape(3, 3)
        assert np.linalg.det(R) > 0
        swap = max(MESH_EIG_RELTOL, 1e-12) * scale  # MuJoCo 4's: test_near_equal_moments_keep_their_order_as_in_mujoco
        assert ev[0] + swap >= ev[1] and ev[1] + swap >= ev[2]
        assert np.abs(np.sort(ev) - np.linalg.eigvalsh(A)).max() <= 4 * MESH_EIG_RELTOL * scale
        assert np.abs(R @ np.diag(ev) @ R.T - A).max() <= 4 * MESH_EIG_RELTOL * scale


def test_a_file_that_includes_files_of_sibling_folders_loads_with_package_dirs(tmp_path):
    """MetaWorld's layout: ``assets/sawyer_xyz/<task>.xml`` includes ``../scene/...`` and
    ``../objects/assets/...`` and finds its meshes in ``../objects/meshes``. MuJoCo reads it; robokit
    refused it whatever the options (its MJCF loader had no ``package_dirs``)."""
    assets = tmp_path / "assets"
    for sub in ("task", "robot", "meshes"):
        (assets / sub).mkdir(parents=True)
    _binary_stl(assets / "meshes" / "ell.stl", *_l_prism())
    (assets / "robot" / "arm.xml").write_text(
        '<mujocoinclude><body name="a"><joint name="j1" axis="0 0 1" armature="0.1"/><geom type="mesh" mesh="ell"/>'
        '<body name="b" pos="0.3 0 0"><joint name="j2" axis="0 1 0"/><geom type="capsule" size="0.03 0.1"/>'
        '<site name="tip" pos="0 0 0.2"/></body></body></mujocoinclude>')
    (assets / "task" / "reach.xml").write_text(
        '<mujoco><compiler meshdir="../meshes"/><asset><mesh name="ell" file="ell.stl"/></asset>'
        '<worldbody><include file="../robot/arm.xml"/></worldbody></mujoco>')
    path = assets / "task" / "reach.xml"
    with pytest.raises(InputError, match=r"<mesh file='ell.stl'> is outside .*package_dirs="):
        robokit.load(path)
    with pytest.raises(InputError, match=r"<include file='../robot/arm.xml'> is outside .*package_dirs="):
        robokit.load(path, allow_outside_meshes=True)
    robot = robokit.load(path, tip="tip", package_dirs=[assets])
    assert robot.spec.package_dirs == (str(assets.resolve()),)
    assert robokit.load(robot.spec).joint_names == ("j1", "j2")
    m = _mj_model(path)
    d = mujoco.MjData(m)
    rng = np.random.default_rng(2)
    for _ in range(5):
        q, qd, qdd = rng.uniform(-2, 2, 2), rng.normal(size=2), rng.normal(size=2)
        d.qpos[:], d.qvel[:], d.qacc[:] = q, qd, qdd
        mujoco.mj_inverse(m, d)
        M = np.zeros((2, 2))
        mujoco.mj_fullM(m, d, M)
        assert np.abs(robot.crba(q) - M).max() < TOL * np.abs(M).max()
        assert np.abs(robot.rnea(q, qd, qdd) - d.qfrc_inverse).max() < TOL * np.abs(d.qfrc_inverse).max()
        T = robot.frame_pose(q, "tip")
        assert np.abs(T[:3, 3] - d.site_xpos[0]).max() < 1e-12


def test_a_large_texture_is_not_counted_as_a_mesh(tmp_path):
    """MetaWorld's ``textures/wood1.png`` (4.7 MB) was refused as "a mesh of a format robokit does not
    count" (the triangle budget, one triangle per byte, applied to every file the model names);
    robokit never reads a texture, and MuJoCo loads the file."""
    import zlib

    w = h = 1024  # noise does not compress: about 3 MB, over the budget of 2 000 000 "triangles"
    raw = b"".join(b"\0" + np.random.default_rng(k).integers(0, 256, 3 * w, dtype=np.uint8).tobytes() for k in range(h))

    def chunk(tag, data):
        return struct.pack(">I", len(data)) + tag + data + struct.pack(">I", zlib.crc32(tag + data) & 0xFFFFFFFF)

    (tmp_path / "wood.png").write_bytes(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, 8, 2, 0, 0, 0))
                                        + chunk(b"IDAT", zlib.compress(raw, 1)) + chunk(b"IEND", b""))
    assert (tmp_path / "wood.png").stat().st_size > 2_000_000
    path = _rule_file(tmp_path, "from_geoms_auto",
                      assets='<texture name="wood" type="2d" file="wood.png"/><material name="m" texture="wood"/>')
    assert dynamics_differences(path, samples=3) < TOL
