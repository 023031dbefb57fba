"""World(convex=True): the convex hulls of the UR5's collision meshes.

Checked three ways: against python-fcl on hulls built independently by trimesh (Qhull through
scipy) from the same mesh files; conservative against the mesh world on sampled configurations
(a hull contains its mesh: never "free" where the meshes touch, never farther); and a world
shipped as plain data (``state``/``pickle``) answers as the original."""
import pickle
import sys
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import robokit
from robokit.collision import Box, Sphere, World, WorldState
from robokit.errors import InputError

sys.path.insert(0, str(Path(__file__).parent))
from _fcl_ref import FclWorld  # noqa: E402


def _T(xyz):
    T = np.eye(4)
    T[:3, 3] = xyz
    return T


@pytest.fixture(scope="module")
def ur5():
    return robokit.load("ur5")


@pytest.fixture(scope="module")
def worlds(ur5):
    obstacles = [Box([0.1, 1.0, 1.0], _T([0.55, 0, 0.3]), name="wall"), Sphere(0.1, _T([0, 0.45, 0.5]))]
    return World(ur5, obstacles), World(ur5, obstacles, convex=True)


def _qs(robot, n, seed):
    rng = np.random.default_rng(seed)
    return np.array([robot.random_configuration(rng) for _ in range(n)])


def test_hulls_against_fcl_on_trimesh_hulls(ur5, worlds):
    trimesh = pytest.importorskip("trimesh")
    _, hull = worlds
    assert hull.geometry == "convex hulls of the collision meshes"
    meshes = {}
    for go in ur5.collision_model.geometryObjects:
        if go.meshPath and Path(go.meshPath).is_file():
            tm = trimesh.load(go.meshPath, force="mesh")
            tm.apply_scale(np.asarray(go.meshScale))
            ch = tm.convex_hull
            meshes[go.name] = (np.asarray(ch.vertices), np.asarray(ch.faces))
    assert len(meshes) == 7  # every link but the ee box
    ref = FclWorld(hull, meshes=meshes)
    free = hit = 0
    for q in _qs(ur5, 40, 3):
        pd = ref.pair_distances(q)
        flags = [h for h, _ in pd]
        d_free = [d for h, d in pd if not h]
        if not any(flags) and min(d_free) > 0.01:
            # fcl's BVH of the hull's triangles: the distance between separated hulls
            assert not hull.in_collision(q)
            assert hull.distance(q) == pytest.approx(min(d_free), abs=1e-6)
            free += 1
        elif any(h and d < -0.01 for h, d in pd):
            assert hull.in_collision(q)
            hit += 1
    assert free >= 5 and hit >= 5, (free, hit)


def test_convex_is_conservative_on_sampled_configurations(ur5, worlds):
    mesh, hull = worlds
    qs = _qs(ur5, 40, 11)
    m_hit, h_hit = mesh.in_collision(qs), hull.in_collision(qs)
    assert m_hit.sum() >= 5  # the implication is exercised
    assert not np.any(m_hit & ~h_hit)  # in collision as meshes ⇒ in collision as hulls
    assert h_hit.sum() > m_hit.sum()  # and the hulls are strictly more cautious here
    assert np.all(hull.distance(qs) <= mesh.distance(qs) + 1e-9)
    # the colliding pairs of the meshes are among those of the hulls
    for q, pairs_m, pairs_h in zip(qs, mesh.colliding_pairs(qs), hull.colliding_pairs(qs)):
        assert set(pairs_m) <= set(pairs_h), q


@settings(max_examples=25, deadline=None, derandomize=True)
@given(u=st.lists(st.floats(0.0, 1.0), min_size=6, max_size=6))
def test_convex_is_conservative_property(ur5, worlds, u):
    mesh, hull = worlds
    lim = np.clip(np.asarray(ur5.qlim, dtype=float), -np.pi, np.pi)
    q = lim[:, 0] + np.asarray(u) * (lim[:, 1] - lim[:, 0])
    assert hull.distance(q) <= mesh.distance(q) + 1e-9
    assert (not mesh.in_collision(q)) or hull.in_collision(q)


def test_the_robot_is_left_untouched_and_hulls_are_cached(ur5, worlds):
    import coal
    assert all(isinstance(g.geometry, (coal.BVHModelBase, coal.Box)) for g in ur5.collision_model.geometryObjects)
    a, b = World(ur5, convex=True), World(ur5, convex=True)
    ga = [g.geometry for g in a.geometry_model.geometryObjects]
    gb = [g.geometry for g in b.geometry_model.geometryObjects]
    assert any(isinstance(g, coal.ConvexBase) for g in ga)
    assert all(x is y for x, y in zip(ga, gb) if isinstance(x, coal.ConvexBase))
    # same self pairs as the meshes (the filter is the robot's, not the geometry's)
    assert a.self_pairs is worlds[0].self_pairs


def test_describe_and_repr_say_the_geometry(ur5, worlds):
    mesh, hull = worlds
    assert "robot geometry: collision meshes" in repr(mesh)
    assert "convex hulls of the collision meshes" in repr(hull)
    text = hull.describe()
    assert "convex=True" in text and "obstacle wall" in text and "sphere_0" in text
    for a, b in hull.self_pairs.checked:
        assert f"{a} – {b}" in text
    assert "skipped, adjacent" in text and "upper_arm_link–forearm_link" in text
    puma = World(robokit.load("puma560"), convex=True)
    assert puma.geometry == "capsules" and "no effect" in puma.describe()


def test_state_ships_as_plain_data(ur5, worlds):
    _, hull = worlds
    state = hull.state()
    assert isinstance(state, WorldState) and state.spec == ur5.spec and state.convex
    blob = pickle.dumps(hull)
    assert b"coal" not in blob and b"pinocchio" not in blob  # no coal/Pinocchio object is pickled
    back = pickle.loads(blob)
    assert back.convex and back.obstacle_names == hull.obstacle_names and back.self_pairs == hull.self_pairs
    qs = _qs(ur5, 8, 5)
    np.testing.assert_array_equal(back.in_collision(qs), hull.in_collision(qs))
    np.testing.assert_allclose(back.distance(qs), hull.distance(qs), atol=1e-12)
    same = World.from_state(state, robot=ur5)
    assert same.robot is ur5 and same.self_pairs is state.self_pairs


def test_from_state_does_not_recompute_the_self_pairs(ur5, worlds, monkeypatch):
    import robokit.collision.world as world_module

    state = worlds[1].state()

    def refuse(robot):
        raise AssertionError("self-collision pairs recomputed")

    monkeypatch.setattr(world_module, "self_collision_pairs", refuse)
    fresh = robokit.load("ur5")  # a new robot object: nothing cached for it
    w = World.from_state(state, robot=fresh)
    q = np.zeros(6)
    assert w.distance(q) == pytest.approx(worlds[1].distance(q), abs=1e-12)
    with pytest.raises(AssertionError, match="recomputed"):
        World(fresh)


def test_bad_convex_and_state(ur5):
    with pytest.raises(InputError, match="convex"):
        World(ur5, convex="yes")
    with pytest.raises(InputError, match="state"):
        World.from_state((), robot=ur5)
    puma_state = World(robokit.load("puma560")).state()
    with pytest.raises(InputError, match="robot"):
        World.from_state(puma_state, robot=ur5)
    import dataclasses
    wrong = dataclasses.replace(World(ur5).state(), robot="puma560")
    with pytest.raises(InputError, match="self-collision pairs"):
        World.from_state(wrong, robot=robokit.load("puma560"))


URDF = """<robot name="flat2">
 <link name="base"/>
 <link name="l1"><collision><origin xyz="0 0 0.2"/><geometry><mesh filename="block.stl"/></geometry></collision>
  <inertial><mass value="1"/><inertia ixx="0.01" iyy="0.01" izz="0.01" ixy="0" ixz="0" iyz="0"/></inertial></link>
 <link name="l2"><collision><geometry><mesh filename="plate.stl"/></geometry></collision>
  <inertial><mass value="1"/><inertia ixx="0.01" iyy="0.01" izz="0.01" ixy="0" ixz="0" iyz="0"/></inertial></link>
 <link name="tool"/>
 <joint name="j1" type="revolute"><parent link="base"/><child link="l1"/><axis xyz="0 0 1"/>
  <limit lower="-3" upper="3" effort="1" velocity="1"/></joint>
 <joint name="j2" type="revolute"><parent link="l1"/><child link="l2"/><origin xyz="0 0 0.4"/><axis xyz="0 1 0"/>
  <limit lower="-3" upper="3" effort="1" velocity="1"/></joint>
 <joint name="jt" type="fixed"><parent link="l2"/><child link="tool"/><origin xyz="0.3 0 0"/></joint>
</robot>"""


def test_a_flat_mesh_is_kept_and_a_two_link_arm_has_no_self_pairs(tmp_path):
    """Qhull cannot wrap a flat plate (coal's wrapper would crash): it stays a mesh, and says so.
    The arm's only two links are adjacent: no self pair to sample."""
    trimesh = pytest.importorskip("trimesh")
    import coal
    trimesh.creation.box([0.1, 0.1, 0.4]).export(tmp_path / "block.stl")
    plate = trimesh.Trimesh([[0, 0, 0], [0.3, 0, 0], [0, 0.3, 0], [0.3, 0.3, 0]], [[0, 1, 2], [1, 3, 2]], process=False)
    plate.export(tmp_path / "plate.stl")
    (tmp_path / "flat2.urdf").write_text(URDF)
    robot = robokit.load(tmp_path / "flat2.urdf")
    lid = Box([1.0, 1.0, 0.1], _T([0.4, 0, 0.5]), name="lid")  # 5 cm above the plate at q = 0
    mesh, hull = World(robot, [lid]), World(robot, [lid], convex=True)
    assert hull.self_pairs.checked == [] and hull.self_pairs.adjacent == [("l1", "l2")]
    kinds = [type(g.geometry) for g in hull.geometry_model.geometryObjects][:2]
    assert issubclass(kinds[0], coal.ConvexBase) and issubclass(kinds[1], coal.BVHModelBase)
    assert "kept as meshes (flat, no convex hull): l2_0" in hull.describe()
    qs = np.array([[a, b] for a in np.linspace(-3, 3, 7) for b in np.linspace(-3, 3, 7)])
    assert mesh.distance(np.zeros(2)) == pytest.approx(0.05, abs=1e-8)  # GJK at tolerance 1e-9: a few 1e-9
    assert np.all(hull.distance(qs) <= mesh.distance(qs) + 1e-9)
    assert not np.any(mesh.in_collision(qs) & ~hull.in_collision(qs))
