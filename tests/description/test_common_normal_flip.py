"""common_normal against brute-force minimisation and its special cases; flipped joints in DH tables
against Corke's Jaco (roboticstoolbox-python) and through DH → URDF → Pinocchio."""
import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import robokit
from robokit.description.dh import DHLink, DHTable
from robokit.spatial.lines import common_normal

vec = st.lists(st.floats(-2, 2), min_size=3, max_size=3).map(np.array)


@settings(max_examples=60, deadline=None)
@given(vec, vec, vec, vec)
def test_skew_lines_feet_are_the_closest_points(p1, z1, p2, z2):
    if np.linalg.norm(z1) < 0.1 or np.linalg.norm(z2) < 0.1:
        return
    u1, u2 = z1 / np.linalg.norm(z1), z2 / np.linalg.norm(z2)
    if np.linalg.norm(np.cross(u1, u2)) < 0.05:
        return
    cn = common_normal(p1, z1, p2, z2)
    # perpendicular to both lines, on both lines, and the shortest connection (least squares in s, t)
    A = np.c_[u1, -u2]
    st_, *_ = np.linalg.lstsq(A, p2 - p1, rcond=None)
    best = np.linalg.norm(p1 + st_[0] * u1 - (p2 + st_[1] * u2))
    assert cn.length == pytest.approx(best, abs=1e-9)
    if cn.kind == "skew":
        assert abs(cn.direction @ u1) < 1e-9 and abs(cn.direction @ u2) < 1e-9
        np.testing.assert_allclose(cn.foot2 - cn.foot1, cn.length * cn.direction, atol=1e-9)
    np.testing.assert_allclose(np.cross(cn.foot1 - p1, u1), 0.0, atol=1e-9)
    np.testing.assert_allclose(np.cross(cn.foot2 - p2, u2), 0.0, atol=1e-9)


def test_special_cases():
    cn = common_normal([0, 0, 0], [1, 0, 0], [0, 0, 2], [0, 1, 0])
    assert cn.kind == "skew" and cn.length == pytest.approx(2.0)
    np.testing.assert_allclose(cn.direction, [0, 0, 1])
    cn = common_normal([1, 2, 3], [1, 0, 0], [1, 2, 3], [0, 0, 5])  # meeting at (1, 2, 3)
    assert cn.kind == "intersecting" and cn.length == 0.0
    np.testing.assert_allclose(cn.foot1, [1, 2, 3])
    np.testing.assert_allclose(cn.direction, [0, -1, 0])  # x̂ × ẑ
    cn = common_normal([0, 0, 0], [0, 0, 1], [3, 4, 7], [0, 0, -2], ref=[0, 0, 5])  # parallel
    assert cn.kind == "parallel" and cn.length == pytest.approx(5.0)
    np.testing.assert_allclose(cn.foot1, [0, 0, 5])
    np.testing.assert_allclose(cn.foot2, [3, 4, 5])
    cn = common_normal([0, 0, 0], [0, 0, 1], [0, 0, 4], [0, 0, 1])  # coincident
    assert cn.kind == "coincident" and cn.length == 0.0
    assert abs(cn.direction @ [0, 0, 1]) < 1e-12 and np.linalg.norm(cn.direction) == pytest.approx(1.0)
    with pytest.raises(ValueError, match="z2"):
        common_normal([0, 0, 0], [1, 0, 0], [0, 0, 0], [0, 0, 0])


def _jaco_table():
    """A DHTable with the numbers of roboticstoolbox's Jaco model (read from its link objects)."""
    rtb = pytest.importorskip("roboticstoolbox")
    r = rtb.models.DH.Jaco()
    links = tuple(DHLink("R", float(l.a), float(l.alpha), float(l.d), float(l.offset), flip=bool(l.isflip))
                  for l in r.links)
    assert links[0].flip and not any(l.flip for l in links[1:])
    return r, DHTable("jaco", "standard", links)


def test_flipped_dh_matches_corke_jaco_and_pinocchio():
    r, table = _jaco_table()
    robot = robokit.load(table)
    rng = np.random.default_rng(0)
    for _ in range(5):
        q = rng.uniform(-3, 3, 6)
        np.testing.assert_allclose(table.fk(q), r.fkine(q).A, atol=1e-12)
        np.testing.assert_allclose(robot.frame_pose(q), table.fk(q), atol=1e-12)


def test_flip_means_minus_q_and_round_trips_through_yaml(tmp_path):
    base = {"name": "t", "convention": "modified", "angle_unit": "rad",
            "links": [{"joint": "R", "a": 0.1, "alpha": 0.3, "d": 0.2, "theta": 0.4},
                      {"joint": "P", "a": 0.2, "alpha": -0.5, "d": 0.1, "theta": 0.0}]}
    flipped = {**base, "links": [dict(l, flip=True) for l in base["links"]]}
    A, B = DHTable.from_dict(base), DHTable.from_dict(flipped)
    q = np.array([0.7, 0.25])
    np.testing.assert_allclose(B.fk(q), A.fk(-q), atol=1e-15)
    np.testing.assert_allclose(robokit.load(B).frame_pose(q), B.fk(q), atol=1e-12)
    path = tmp_path / "t.yaml"
    B.save(path)
    again = DHTable.from_yaml(path)
    assert [l.flip for l in again.links] == [True, True]
    with pytest.raises(robokit.InputError, match="flip"):
        DHTable.from_dict({**base, "links": [dict(base["links"][0], flip="yes")]})
