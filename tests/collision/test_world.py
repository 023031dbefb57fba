"""World's collision and distance answers against python-fcl on the same geometry (placed with
Pinocchio's FK), on configurations that clearly collide or clearly do not (margin 2 cm)."""
import sys
from pathlib import Path

import numpy as np
import pytest

import robokit
from robokit.collision import Box, Cylinder, Mesh, Sphere, World, self_collision_pairs
from robokit.errors import InputError

sys.path.insert(0, str(Path(__file__).parent))
from _fcl_ref import FclWorld  # noqa: E402

MARGIN = 0.02


def _T(xyz, rz=0.0):
    T = np.eye(4)
    c, s = np.cos(rz), np.sin(rz)
    T[:3, :3] = [[c, -s, 0], [s, c, 0], [0, 0, 1]]
    T[:3, 3] = xyz
    return T


@pytest.fixture(scope="module")
def puma():
    return robokit.load("puma560")


@pytest.fixture(scope="module")
def ur5():
    return robokit.load("ur5")


def _scene():
    return [Box([0.1, 1.0, 1.0], _T([0.6, 0, 0.3], 0.3), name="wall"), Sphere(0.15, _T([0, 0.5, 0.5])),
            Cylinder(0.1, 0.8, _T([-0.5, -0.3, 0.2]))]


def _compare(world, ref, qs, margin=MARGIN):
    checked = {"hit": 0, "free": 0}
    for q in qs:
        pd = ref.pair_distances(q)
        hit = any(h for h, _ in pd)
        free_d = [d for h, d in pd if not h]
        clear_free = not hit and min(free_d) > margin
        clear_hit = hit and any(h and d < -margin for h, d in pd) or (hit and all(d < 0 for h, d in pd if h))
        if clear_free:
            assert not world.in_collision(q)
            assert world.distance(q) == pytest.approx(min(free_d), abs=1e-6)
            assert world.colliding_pairs(q) == []
            checked["free"] += 1
        elif clear_hit:
            assert world.in_collision(q)
            assert world.distance(q) <= 0
            names = world._names
            want = {(names[i], names[j]) for (i, j), (h, _) in zip(world._pairs, pd) if h}
            assert set(world.colliding_pairs(q)) == want
            checked["hit"] += 1
    return checked


def test_primitives_against_fcl(puma):
    w = World(puma, _scene())
    ref = FclWorld(w)
    qs = np.array([puma.random_configuration(k) for k in range(60)])
    c = _compare(w, ref, qs)
    assert c["hit"] >= 5 and c["free"] >= 5, c
    # the batch form agrees with the single calls
    np.testing.assert_array_equal(w.in_collision(qs[:10]), [w.in_collision(q) for q in qs[:10]])
    np.testing.assert_allclose(w.distance(qs[:5]), [w.distance(q) for q in qs[:5]])
    assert len(w.colliding_pairs(qs[:4])) == 4


def test_meshes_against_fcl(ur5, tmp_path):
    trimesh = pytest.importorskip("trimesh")
    box = trimesh.creation.icosphere(subdivisions=2, radius=0.12)
    path = tmp_path / "ball.stl"
    box.export(path)
    m = Mesh(path, _T([0.3, 0.3, 0.4]), name="ball")
    w = World(ur5, [m, Box([0.1, 1.0, 1.0], _T([0.6, 0, 0.3]), name="wall")])
    ref = FclWorld(w, meshes={"obstacle:ball": (m.vertices, m.faces)})
    # the UR5's own links sit ~1.4 cm apart in many poses: "clearly free" is 1 cm here
    qs = np.array([ur5.random_configuration(k) for k in range(30)])
    c = _compare(w, ref, qs, margin=0.01)
    assert c["hit"] >= 3 and c["free"] >= 3, c


def test_folded_ur5_collides_with_itself(ur5):
    w = World(ur5)
    ref = FclWorld(w)
    for q in ([0, -1.57, 2.9, 0, 0, 0], [0, 0, 2.9, 0, 0, 0]):
        assert w.in_collision(q)
        assert any(h for h, _ in ref.pair_distances(q))
        assert ("upper_arm_link", "wrist_1_link") in w.colliding_pairs(q)
    q_up = [0, -1.57, 0, -1.57, 0, 0]
    assert not w.in_collision(q_up)
    pd = ref.pair_distances(q_up)
    assert not any(h for h, _ in pd)
    assert w.distance(q_up) == pytest.approx(min(d for _, d in pd), abs=1e-6)


def test_self_pairs_rules(puma, ur5):
    for r in (puma, ur5):
        p = self_collision_pairs(r)
        assert p is self_collision_pairs(r)  # cached
        links = [f.name for f in r.model.frames]
        for a, b in p.checked:
            assert a in links and b in links and a != b
        assert not set(p.checked) & set(p.adjacent)
        assert "checked" in str(p)
    # adjacent links of a serial chain are never checked
    ur = self_collision_pairs(ur5)
    assert ("upper_arm_link", "forearm_link") in ur.adjacent


def test_padding_inflates(puma):
    wall = Box([0.1, 1.0, 1.0], _T([0.6, 0, 0.3]), name="wall")
    q = np.zeros(6)
    d0 = World(puma, [wall]).distance(q)
    w = World(puma, [wall], padding=0.01)
    assert w.distance(q) <= d0 - 0.01 + 1e-12
    assert not World(puma, [wall], padding=0.0).in_collision([0, 0, 0, 0, 0, 0])


def test_bad_input(puma, tmp_path):
    with pytest.raises(InputError, match="size"):
        Box([0.1, -1, 1])
    with pytest.raises(InputError, match="radius"):
        Sphere(0)
    with pytest.raises(InputError, match="pose"):
        Sphere(0.1, np.ones((4, 4)))
    with pytest.raises(InputError, match="path"):
        Mesh(tmp_path)
    with pytest.raises(InputError, match="path"):
        Mesh(tmp_path / "missing.stl")
    w = World(puma)
    with pytest.raises(InputError, match="q"):
        w.in_collision(np.zeros(5))
    with pytest.raises(InputError, match="obstacles"):
        World(puma, ["box"])


def test_ik_with_a_world(puma):
    wall = Box([0.4, 0.05, 0.8], _T([0.45, 0.35, 0.4]), name="wall")
    w = World(puma, [wall])
    q_goal = np.array([1.4, 0.3, -0.3, 0, 0, 0])
    T = puma.frame_pose(q_goal)
    sols = robokit.ik_analytic(puma, T, world=w)
    assert all(s.collision_free is None for s in robokit.ik_analytic(puma, T))
    flags = [s.collision_free for s in sols]
    assert True in flags and False in flags  # the wall blocks some branches
    ref = FclWorld(w)
    for s in sols:
        assert s.collision_free == (not any(h for h, _ in ref.pair_distances(s.q)))
    # the documented positional form ik_analytic(robot, T, world) (the third parameter is wrist_ref, which
    # refused a World): the same solutions and python-fcl's flags
    positional = robokit.ik_analytic(puma, T, w)
    assert [s.label for s in positional] == [s.label for s in sols]
    for s, p in zip(sols, positional):
        np.testing.assert_array_equal(p.q, s.q)
        assert p.collision_free == (not any(h for h, _ in ref.pair_distances(p.q)))
    # and its "no world", ik_analytic(robot, T, None): the solutions without collision flags
    bare = robokit.ik_analytic(puma, T, None)
    assert [s.label for s in bare] == [s.label for s in sols] and all(s.collision_free is None for s in bare)
    for s, b in zip(sols, bare):
        np.testing.assert_array_equal(b.q, s.q)
    res = robokit.solve_ik(puma, T, world=w, q0=[0, 0.3, -0.3, 0, 0, 0])
    assert res.success and res.method == "analytic" and not w.in_collision(res.q)
    np.testing.assert_allclose(puma.frame_pose(res.q), T, atol=1e-9)


def test_capability_map_counts_collision_free_only(puma):
    import pickle
    floor = Box([3.0, 3.0, 0.1], _T([0, 0, -0.1]), name="floor")  # top 5 cm below the base
    w = World(puma, [floor])
    assert pickle.loads(pickle.dumps(floor)).size.tolist() == floor.size.tolist()  # shipped to workers
    a = robokit.capability_map(puma, 0.3, 8, client="serial")
    b = robokit.capability_map(puma, 0.3, 8, client="serial", world=w)
    np.testing.assert_array_equal(a.centres, b.centres)
    assert np.all(b.index <= a.index + 1e-12)
    assert b.index.sum() < a.index.sum()  # the floor takes some poses away
    # an independent recount of a few voxels: any in-limit branch free by python-fcl
    ref = FclWorld(w)
    R = b.orientations
    low = np.flatnonzero(a.index > 0)
    for i in low[np.argsort(a.centres[low, 2])][:6]:  # the lowest voxels: where the floor matters
        T = np.eye(4)
        T[:3, 3] = b.centres[i]
        n_ok = 0
        for Rk in R:
            T[:3, :3] = Rk
            sols = robokit.ik_analytic(puma, T)
            n_ok += any(s.within_limits and not any(h for h, _ in ref.pair_distances(s.q)) for s in sols)
        assert b.index[i] == pytest.approx(n_ok / len(R))


def test_capsule_resting_in_a_box_at_every_angle(puma):
    """Pinocchio's default requests (no contacts) missed this contact at some q1; World enables contacts."""
    w = World(puma, [Box([3.0, 3.0, 0.1], _T([0, 0, -0.05]), name="floor")])
    ref = FclWorld(w)
    for q1 in np.linspace(-2.5, 2.5, 11):
        q = np.array([q1, 0, 0, 0, 0, 0])
        assert any(h for h, _ in ref.pair_distances(q))
        assert w.in_collision(q) and ("link_1", "floor") in w.colliding_pairs(q)
        assert w.distance(q) == pytest.approx(-0.0241848, abs=1e-6)  # the capsule radius, 0 m above the floor top
