"""The one programmatic model builder (robokit.description.model_builder) against Pinocchio's own URDF parser.

The same URDF is read twice: by ``pinocchio.buildModelFromXML`` / ``buildGeomFromUrdfString``, and by
``description_from_urdf`` → ``build_model`` (no URDF text reaches Pinocchio). Every frame (name, type,
parents, placement, inertia), joint (model type, placement, inertia), limit and geometry object must be the
same, the numbers to the last bit; forward kinematics, Jacobians, RNEA and the mass matrix agree to 1e-12
at random configurations.
Robots: the shipped models' URDFs and five example-robot-data arms (a continuous-joint arm, kinova, among
them: its continuous joints must come out as Pinocchio's unbounded revolute joints, nq = 2).
"""
import dataclasses
import math

import numpy as np
import pytest

from robokit.description.model_builder import (Description, FrameSpec, Geometry, Inertial, Joint, Link, Pose,
                                               build_model)
from robokit.description.urdf_check import read_urdf
from robokit.description.urdf_description import description_from_urdf
from robokit.errors import InputError

pin = pytest.importorskip("pinocchio")

LIMIT_FIELDS = ("lowerPositionLimit", "upperPositionLimit", "lowerEffortLimit", "upperEffortLimit",
                "lowerVelocityLimit", "upperVelocityLimit", "damping", "lowerDryFrictionLimit",
                "upperDryFrictionLimit", "armature", "rotorInertia", "rotorGearRatio", "positionLimitMargin")


def _urdf_paths():
    from robokit.description.models import model_path

    out = [(n, str(model_path(n, ".urdf"))) for n in ("twolink", "rrr", "puma560")]
    try:
        import example_robot_data as erd
    except ImportError:  # pragma: no cover - the test extra installs it
        return out
    from os.path import join

    for name in ("ur5", "panda", "kinova", "z1", "xarm7"):
        cls = erd.robots_loader.ROBOTS[name]  # the file's path, as the loader finds it, without building the robot
        rel = join(cls.path, cls.urdf_subpath, cls.urdf_filename)
        out.append((name, join(erd.robots_loader.getModelPath(rel), rel)))
    return out


URDF_PATHS = _urdf_paths()


def assert_same_model(mine, ref, atol=0.0):
    """The same frames, joints, inertias and limits; by default to the last bit (a URDF is read as Pinocchio's
    parser reads it: urdfdom's rpy quaternion, Eigen's products — an exact zero there is an exact zero here),
    else to ``atol`` (a model built from exact matrices against one parsed from the same robot's rpy text)."""
    def same(a, b, err_msg=""):
        if atol:
            np.testing.assert_allclose(a, b, rtol=0, atol=atol, err_msg=err_msg)
        else:
            np.testing.assert_array_equal(a, b, err_msg=err_msg)
    assert [f.name for f in mine.frames] == [f.name for f in ref.frames]
    for a, b in zip(mine.frames, ref.frames):
        assert (a.type, a.parentJoint, a.parentFrame) == (b.type, b.parentJoint, b.parentFrame), a.name
        same(a.placement.homogeneous, b.placement.homogeneous, err_msg=a.name)
        same(a.inertia.matrix(), b.inertia.matrix(), err_msg=a.name)
    assert list(mine.names) == list(ref.names)
    for j in range(ref.njoints):
        assert mine.joints[j].shortname() == ref.joints[j].shortname(), ref.names[j]
        same(mine.jointPlacements[j].homogeneous, ref.jointPlacements[j].homogeneous, err_msg=ref.names[j])
        same(mine.inertias[j].matrix(), ref.inertias[j].matrix(), err_msg=ref.names[j])
    for attr in LIMIT_FIELDS:
        np.testing.assert_array_equal(np.asarray(getattr(mine, attr)), np.asarray(getattr(ref, attr)), err_msg=attr)
    np.testing.assert_array_equal(mine.gravity.vector, ref.gravity.vector)


def assert_same_dynamics(mine, ref, seed=0, samples=5):
    rng = np.random.default_rng(seed)
    d, dr = mine.createData(), ref.createData()
    lo, hi = np.maximum(ref.lowerPositionLimit, -3.0), np.minimum(ref.upperPositionLimit, 3.0)
    for _ in range(samples):
        q = pin.randomConfiguration(ref, lo, hi)
        v, a = rng.normal(size=ref.nv), rng.normal(size=ref.nv)
        pin.framesForwardKinematics(mine, d, q)
        pin.framesForwardKinematics(ref, dr, q)
        for i in range(ref.nframes):
            np.testing.assert_allclose(d.oMf[i].homogeneous, dr.oMf[i].homogeneous, atol=1e-12)
        np.testing.assert_allclose(pin.computeJointJacobians(mine, d, q), pin.computeJointJacobians(ref, dr, q),
                                   atol=1e-12)
        np.testing.assert_allclose(pin.rnea(mine, d, q, v, a), pin.rnea(ref, dr, q, v, a), atol=1e-12)
        np.testing.assert_allclose(pin.crba(mine, d, q), pin.crba(ref, dr, q), atol=1e-12)


@pytest.mark.parametrize("name,path", URDF_PATHS, ids=[n for n, _ in URDF_PATHS])
def test_builder_equals_pinocchio_urdf_parser(name, path):
    doc = read_urdf(path)
    ref = pin.buildModelFromXML(doc.xml)
    model, visual, collision, notes = build_model(description_from_urdf(doc.xml, path))
    assert notes == []
    assert_same_model(model, ref)
    assert_same_dynamics(model, ref)
    for gtype, mine in ((pin.GeometryType.VISUAL, visual), (pin.GeometryType.COLLISION, collision)):
        theirs = pin.buildGeomFromUrdfString(ref, doc.xml, gtype, package_dirs=doc.package_dirs)
        assert [o.name for o in mine.geometryObjects] == [o.name for o in theirs.geometryObjects]
        for a, b in zip(mine.geometryObjects, theirs.geometryObjects):
            assert (a.parentJoint, a.parentFrame, a.meshPath, a.overrideMaterial) == \
                (b.parentJoint, b.parentFrame, b.meshPath, b.overrideMaterial), a.name
            assert type(a.geometry) is type(b.geometry), a.name
            np.testing.assert_allclose(a.placement.homogeneous, b.placement.homogeneous, atol=1e-12)
            np.testing.assert_allclose(a.meshScale, b.meshScale)
            np.testing.assert_allclose(a.meshColor, b.meshColor)


def test_continuous_joints_are_unbounded_revolute():
    """kinova's joints 1, 4, 6 are continuous: nq = 2 each, as the URDF parser makes them."""
    path = dict(URDF_PATHS).get("kinova")
    if path is None:
        pytest.skip("example-robot-data not installed")
    desc = dataclasses.replace(description_from_urdf(read_urdf(path).xml), geometries=())  # no meshes to read
    model = build_model(desc)[0]
    kinds = [model.joints[j].shortname() for j in range(1, model.njoints)]
    assert kinds.count("JointModelRUBZ") == 3
    assert (model.nq, model.nv) == (9, 6)


def _arm(**joint2):
    link = Link("l", Inertial(1.0, (0.5, 0.0, 0.0), (0.01, 0, 0, 0.02, 0, 0.02)))
    return Description("arm", (Link("base"), link, Link("m", Inertial(2.0, (0.2, 0.1, 0.0)))),
                       (Joint("j1", "revolute", "base", "l", lower=-2, upper=2),
                        Joint("j2", joint2.pop("kind", "revolute"), "l", "m", Pose(translation=(1.0, 0, 0)),
                              lower=-1, upper=1, **joint2)))


def test_armature_adds_reflected_inertia_to_m_and_rnea():
    """Joint.armature lands in model.armature: M gains it on the diagonal, RNEA gains armature·q̈ (crba/rnea)."""
    plain = build_model(_arm())[0]
    geared = build_model(_arm(armature=0.35))[0]
    q, v, a = np.array([0.3, -0.4]), np.array([0.5, 0.1]), np.array([1.5, -2.0])
    dp, dg = plain.createData(), geared.createData()
    np.testing.assert_allclose(pin.crba(geared, dg, q) - pin.crba(plain, dp, q), np.diag([0.0, 0.35]), atol=1e-14)
    np.testing.assert_allclose(pin.rnea(geared, dg, q, v, a) - pin.rnea(plain, dp, q, v, a), [0.0, 0.35 * -2.0],
                               atol=1e-14)


def test_child_placement_and_extra_frames():
    """A child link off its joint frame (SDFormat) and an OP_FRAME: poses by hand."""
    off = Pose.from_xyz_rpy([0.0, 0.2, 0.0], [0.0, 0.0, 0.5])
    desc = Description("arm", (Link("base"), Link("l", Inertial(1.0))),
                       (Joint("j", "revolute", "base", "l", Pose(translation=(0, 0, 1.0)), child_placement=off),),
                       frames=(FrameSpec("tcp", "l", Pose(translation=(0.1, 0, 0))), FrameSpec("mark", None)))
    model = build_model(desc)[0]
    data = model.createData()
    q = np.array([0.7])
    pin.framesForwardKinematics(model, data, q)
    Rz = np.eye(4)
    Rz[:2, :2] = [[math.cos(0.7), -math.sin(0.7)], [math.sin(0.7), math.cos(0.7)]]
    T_l = Pose(translation=(0, 0, 1.0)).matrix @ Rz @ off.matrix
    np.testing.assert_allclose(data.oMf[model.getFrameId("l")].homogeneous, T_l, atol=1e-14)
    np.testing.assert_allclose(data.oMf[model.getFrameId("tcp")].homogeneous,
                               T_l @ Pose(translation=(0.1, 0, 0)).matrix, atol=1e-14)
    assert model.frames[model.getFrameId("tcp")].type == pin.FrameType.OP_FRAME
    np.testing.assert_allclose(data.oMf[model.getFrameId("mark")].homogeneous, np.eye(4))


def test_geometry_names_and_placement():
    desc = Description("g", (Link("base"),), geometries=(
        Geometry("base", "box", Pose(translation=(0, 0, 0.1)), (0.1, 0.2, 0.3), color=(1, 0, 0, 1)),
        Geometry("base", "capsule", Pose(), (0.05, 0.4), collision=True),
        Geometry("base", "sphere", Pose(), (0.1,))))
    _, visual, collision, _ = build_model(desc)
    assert [o.name for o in visual.geometryObjects] == ["base_0", "base_1"]
    assert [o.name for o in collision.geometryObjects] == ["base_0"]
    box = visual.geometryObjects[0]
    np.testing.assert_allclose(2 * box.geometry.halfSide, [0.1, 0.2, 0.3])
    assert box.overrideMaterial and box.meshPath == "BOX"
    assert collision.geometryObjects[0].meshPath == "CAPSULE"


def test_missing_mesh_is_left_out_with_a_note(tmp_path):
    desc = Description("g", (Link("base"),), geometries=(Geometry("base", "mesh", mesh=str(tmp_path / "no.stl")),))
    _, visual, _, notes = build_model(desc)
    assert len(visual.geometryObjects) == 0 and len(notes) == 1 and "not found" in notes[0]


@pytest.mark.parametrize("desc,message", [
    (Description("x", (Link("a"), Link("a"))), "defined twice"),
    (Description("x", (Link("a"), Link("b")), (Joint("j", "screw", "a", "b"),)), "'screw' joint"),
    (Description("x", (Link("a"), Link("b")), (Joint("j", "revolute", "a", "c"),)), "not defined"),
    (Description("x", (Link("a"), Link("b")), (Joint("j", "revolute", "a", "b", lower=1, upper=0),)), "above"),
    (Description("x", (Link("a"), Link("b")), (Joint("j", "prismatic", "a", "b", axis=(0, 0, 0)),)), "zero"),
    (Description("x", (Link("a"), Link("b")), (Joint("j", "fixed", "a", "b"), Joint("k", "fixed", "b", "a"))),
     "loop"),
    (Description("x", (Link("a"), Link("b"), Link("c")),
                 (Joint("j", "fixed", "a", "c"), Joint("k", "fixed", "b", "c"))), "child of two joints"),
    (Description("x", (Link("a"), Link("b")), (Joint("j", "revolute", "a", "b", frame=False),)), "always a frame"),
    (Description("x", (Link("a", frame=False),)), "has no frame"),
    (Description("x", (Link("a"), Link("b", frame=False), Link("c")),
                 (Joint("j", "revolute", "a", "b"), Joint("k", "revolute", "b", "c")),
                 (FrameSpec("f", "b"),)), "not a link with a frame"),
    (Description("x", (Link("a"), Link("b", frame=False), Link("c")),
                 (Joint("j", "revolute", "a", "b"), Joint("k", "revolute", "b", "c")),
                 geometries=(Geometry("b", "sphere", size=(0.1,)),)), "no such link with a frame"),
    (Description("x", (Link("a"),), geometries=(Geometry("a", "trimesh", vertices=np.eye(3),
                                                         faces=np.array([[0, 1, 3]])),)), "vertex indices"),
])
def test_refused_descriptions(desc, message):
    with pytest.raises(InputError, match=message):
        build_model(desc)


def test_joint_cap():
    links = tuple(Link(f"l{i}") for i in range(200))
    joints = tuple(Joint(f"j{i}", "revolute", f"l{i}", f"l{i + 1}") for i in range(199))
    with pytest.raises(InputError, match="199 moving joints; robokit reads robots of at most 128 joints"):
        build_model(Description("snake", links, joints))
    fixed = tuple(Joint(f"j{i}", "fixed", f"l{i}", f"l{i + 1}") for i in range(199))
    assert build_model(Description("rod", links, fixed))[0].nq == 0  # frames only: allowed


FLOATING_PLANAR_URDF = """<robot name="bases">
  <link name="world"/>
  <link name="cart"><inertial><mass value="2"/><inertia ixx="0.1" iyy="0.2" izz="0.3" ixy="0" ixz="0" iyz="0"/>
  </inertial></link>
  <link name="puck"><inertial><origin xyz="0.1 0 0"/><mass value="1"/>
    <inertia ixx="0.01" iyy="0.02" izz="0.03" ixy="0" ixz="0" iyz="0"/></inertial></link>
  <link name="arm"><inertial><origin xyz="0 0 0.2"/><mass value="0.5"/>
    <inertia ixx="0.004" iyy="0.004" izz="0.001" ixy="0" ixz="0" iyz="0"/></inertial></link>
  <joint name="free" type="floating"><parent link="world"/><child link="cart"/><origin xyz="0 0 1" rpy="0 0 0.3"/>
  </joint>
  <joint name="slide" type="planar"><parent link="cart"/><child link="puck"/><origin xyz="0.2 0 0" rpy="0.1 0 0"/>
    <axis xyz="0 1 0"/></joint>
  <joint name="j1" type="revolute"><parent link="puck"/><child link="arm"/><origin xyz="0 0 0.1"/><axis xyz="0 0 1"/>
    <limit lower="-2" upper="2" effort="10" velocity="3"/></joint>
</robot>"""


def test_floating_and_planar_joints_as_the_urdf_parser_makes_them():
    """A free-flyer and a planar joint (whatever its axis: urdfdom's planar joint moves in its frame's xy plane)
    come out as Pinocchio's parser makes them: joint models, limits (unbounded but the unit part at ±1.01)."""
    ref = pin.buildModelFromXML(FLOATING_PLANAR_URDF)
    model, _, _, notes = build_model(description_from_urdf(FLOATING_PLANAR_URDF))
    assert notes == []
    assert [model.joints[j].shortname() for j in (1, 2)] == ["JointModelFreeFlyer", "JointModelPlanar"]
    assert_same_model(model, ref)
    assert_same_dynamics(model, ref)


def test_loading_a_urdf_never_calls_pinocchios_urdf_parser(monkeypatch):
    """Every URDF robot (and so every xacro one) is built by build_model: with Pinocchio's URDF parser made to
    fail, the shipped PUMA still loads, and its model equals the parser's (built before the patch)."""
    import robokit as rk
    from robokit.description.models import model_path

    path = model_path("puma560", ".urdf")
    ref = pin.buildModelFromXML(read_urdf(path).xml)

    def refuse(*args, **kwargs):
        raise AssertionError("Pinocchio's URDF parser was called")

    for name in ("buildModelFromXML", "buildModelFromUrdf", "buildGeomFromUrdfString", "buildGeomFromUrdf"):
        monkeypatch.setattr(pin, name, refuse)
    robot = rk.load(str(path))
    assert_same_model(robot.model, ref)
    assert_same_dynamics(robot.model, ref)


@pytest.mark.parametrize("name", ["ur5", "panda", "talos_arm", "kinova"])
def test_example_robot_data_urdf_robots_equal_its_own_loader(name):
    """example-robot-data's URDF robots are built by the one builder; what its loader adds from the SRDF (reference
    posture, rotor inertia as armature — talos_arm has it —, the collision pairs the SRDF leaves) comes out as
    the package's own loader (Pinocchio's URDF parser + its SRDF reader) makes it."""
    erd = pytest.importorskip("example_robot_data")
    from robokit.description.example_robots import _built_from_urdf

    ref = erd.load(name)
    model, visual, collision, q0 = _built_from_urdf(erd.ROBOTS[name])
    assert_same_model(model, ref.model)
    assert_same_dynamics(model, ref.model)
    np.testing.assert_array_equal(q0, ref.q0)
    assert [o.name for o in collision.geometryObjects] == [o.name for o in ref.collision_model.geometryObjects]
    pairs = [(p.first, p.second) for p in collision.collisionPairs]
    assert pairs == [(p.first, p.second) for p in ref.collision_model.collisionPairs]
    assert [o.name for o in visual.geometryObjects] == [o.name for o in ref.visual_model.geometryObjects]


def _frame_less_pair():
    """One arm twice: with every link a BODY frame and every fixed joint a FIXED_JOINT frame, and with
    link ``mid`` frame-less (two joints of one MJCF body) and the weld ``w`` frame-less."""
    turn = Pose.from_xyz_rpy([0.1, 0.2, 0.3], [0.3, -0.2, 0.1])
    links = (Link("base", Inertial(2.0, (0.0, 0.0, 0.1), (0.1, 0.0, 0.0, 0.1, 0.0, 0.1))), Link("mid"),
             Link("l1", Inertial(1.0, (0.2, 0.0, 0.0), (0.01, 0.001, 0.0, 0.02, 0.0, 0.03))),
             Link("tool", Inertial(0.5, (0.0, 0.05, 0.0), (0.001, 0.0, 0.0, 0.001, 0.0, 0.001))))
    joints = (Joint("j1", "revolute", "base", "mid", turn, Pose.from_xyz_rpy([0, 0, 0], [0.0, 0.0, -0.4]),
                    axis=(0.0, 0.0, 1.0), lower=-2, upper=2),
              Joint("j2", "prismatic", "mid", "l1", Pose(translation=(0.0, 0.1, 0.0)),
                    Pose(translation=(0.0, -0.1, 0.05)), axis=(1.0, 1.0, 0.0), lower=-0.1, upper=0.3),
              Joint("w", "fixed", "l1", "tool", turn))
    frames = (FrameSpec("tip", "tool", Pose(translation=(0.0, 0.0, 0.1))), FrameSpec("s", "l1"))
    ordinary = Description("arm", links, joints, frames)
    lean = Description("arm", tuple(dataclasses.replace(k, frame=k.name != "mid") for k in links),
                       tuple(dataclasses.replace(j, frame=j.name != "w") for j in joints), frames,
                       frames_with_links=True)
    return ordinary, lean


def test_frame_less_links_and_welds_change_frames_only():
    """The frame-less options drop the BODY frame of ``mid`` and the FIXED_JOINT frame of ``w``, hang the
    frames on the frames that remain, add each FrameSpec after its link; joints, inertias, kinematics and
    dynamics stay those of the ordinary layout (itself checked against Pinocchio's URDF parser above)."""
    ordinary, lean = (build_model(d)[0] for d in _frame_less_pair())
    names = [f.name for f in lean.frames]
    assert names == ["universe", "base", "j1", "j2", "l1", "s", "tool", "tip"]
    assert [f.name for f in ordinary.frames] == ["universe", "base", "j1", "mid", "j2", "l1", "w", "tool", "tip", "s"]
    parent = {f.name: lean.frames[f.parentFrame].name for f in lean.frames}
    assert parent["j2"] == "j1" and parent["tool"] == "l1" and parent["s"] == "l1" and parent["tip"] == "tool"
    for i in range(ordinary.njoints):
        assert lean.jointPlacements[i].isApprox(ordinary.jointPlacements[i], 1e-14)
        assert lean.inertias[i].isApprox(ordinary.inertias[i], 1e-14)
    d1, d2 = ordinary.createData(), lean.createData()
    rng = np.random.default_rng(0)
    for _ in range(5):
        q, v, a = rng.uniform(-0.1, 0.1, 2), rng.normal(size=2), rng.normal(size=2)
        pin.framesForwardKinematics(ordinary, d1, q)
        pin.framesForwardKinematics(lean, d2, q)
        for name in ("l1", "tool", "tip", "s"):
            assert np.allclose(d1.oMf[ordinary.getFrameId(name)].homogeneous,
                               d2.oMf[lean.getFrameId(name)].homogeneous, atol=1e-12)
        assert np.allclose(pin.crba(ordinary, d1, q), pin.crba(lean, d2, q), atol=1e-12)
        assert np.allclose(pin.rnea(ordinary, d1, q, v, a), pin.rnea(lean, d2, q, v, a), atol=1e-12)


def test_ball_joint_ellipsoid_and_trimesh():
    import coal

    box = np.array([[x, y, z] for x in (0, 1) for y in (0, 1) for z in (0, 1)], dtype=float)
    faces = np.array([[0, 1, 3], [0, 3, 2], [4, 6, 7], [4, 7, 5], [0, 4, 5], [0, 5, 1],
                      [2, 3, 7], [2, 7, 6], [0, 2, 6], [0, 6, 4], [1, 5, 7], [1, 7, 3]])
    desc = Description("ball", (Link("a"), Link("b", Inertial(1.0, (0.1, 0.0, 0.0), (0.1, 0, 0, 0.1, 0, 0.1)))),
                       (Joint("shoulder", "ball", "a", "b", Pose(translation=(0.0, 0.0, 0.5))),),
                       geometries=(Geometry("b", "ellipsoid", size=(0.1, 0.2, 0.3), name="egg"),
                                   Geometry("b", "trimesh", collision=True, mesh="/x/box.stl", scale=(2.0, 2.0, 2.0),
                                            vertices=box, faces=faces)))
    model, visual, collision, _ = build_model(desc)
    assert model.joints[1].shortname() == "JointModelSpherical" and (model.nq, model.nv) == (4, 3)
    assert model.upperPositionLimit.tolist() == [1.01] * 4
    egg = visual.geometryObjects[0]
    assert egg.name == "egg" and np.allclose(egg.geometry.radii, [0.1, 0.2, 0.3])
    mesh = collision.geometryObjects[0]
    assert (mesh.name, mesh.meshPath, mesh.meshScale.tolist()) == ("b_0", "/x/box.stl", [2.0, 2.0, 2.0])
    assert mesh.geometry.num_tris == 12 and np.allclose(np.asarray(mesh.geometry.vertices()), box)
    # the unit cube's triangles: a sphere of radius 1e-9 centred 0.5 outside a face is 0.5 - 1e-9 away (coal's
    # distance, independent of the builder)
    request, result = coal.DistanceRequest(), coal.DistanceResult()
    d = coal.distance(mesh.geometry, coal.Transform3s(), coal.Sphere(1e-9),
                      coal.Transform3s(np.eye(3), np.array([0.5, 0.5, 1.5])), request, result)
    assert abs(d - (0.5 - 1e-9)) < 1e-10


def test_continuous_joint_about_an_unaligned_axis_equals_pinocchios_parser(tmp_path):
    """A continuous joint whose axis is not x, y or z (normalised as the parser normalises it) is Pinocchio's
    unbounded unaligned revolute joint: the model equals the URDF parser's (to an ulp), with the same
    kinematics and dynamics, and robokit.load reads the file (it raised Boost's ArgumentError, the binding of
    that joint taking no axis)."""
    import robokit as rk

    urdf = """<robot name="tilted">
  <link name="base"/>
  <link name="l1"><inertial><origin xyz="0.1 0.02 -0.03" rpy="0.2 -0.1 0.4"/><mass value="1.3"/>
    <inertia ixx="0.02" iyy="0.03" izz="0.04" ixy="0.001" iyz="-0.002" ixz="0.003"/></inertial></link>
  <link name="l2"><inertial><origin xyz="0.2 0 0.05"/><mass value="0.7"/>
    <inertia ixx="0.01" iyy="0.02" izz="0.02" ixy="0" iyz="0" ixz="0"/></inertial></link>
  <link name="tip"/>
  <joint name="j1" type="continuous"><parent link="base"/><child link="l1"/>
    <origin xyz="0 0 0.3" rpy="0.1 0.2 0.3"/><axis xyz="0.3 -0.4 1.2"/></joint>
  <joint name="j2" type="continuous"><parent link="l1"/><child link="l2"/>
    <origin xyz="0.4 0.1 0" rpy="-0.5 0 0.2"/><axis xyz="1 1 0"/></joint>
  <joint name="fix" type="fixed"><parent link="l2"/><child link="tip"/><origin xyz="0.3 0 0"/></joint>
</robot>"""
    ref = pin.buildModelFromXML(urdf)
    assert [ref.joints[j].shortname() for j in (1, 2)] == ["JointModelRevoluteUnboundedUnaligned"] * 2
    model = build_model(description_from_urdf(urdf))[0]
    assert_same_model(model, ref, atol=1e-15)  # the rotated inertial's products may round differently by an ulp
    assert_same_dynamics(model, ref)
    path = tmp_path / "tilted.urdf"
    path.write_text(urdf)
    robot = rk.load(str(path))
    q = np.array([0.7, -2.1])
    data = ref.createData()
    pin.framesForwardKinematics(ref, data, np.array([np.cos(0.7), np.sin(0.7), np.cos(-2.1), np.sin(-2.1)]))
    np.testing.assert_allclose(robot.frame_pose(q), data.oMf[ref.getFrameId("tip")].homogeneous, atol=1e-12)
