"""The self-collision table reports link pairs, each once: a link with two collision shapes, one
always inside another link and one that touches it only sometimes, is *checked* (that one shape
pair alone skipped), not listed both as checked and as always in contact; a link pair all of whose
shape pairs always touch is *always in contact* alone.

Expected classes from closed-form sphere distances: joint 2's centre c is fixed in space (joint 1
turns about the vertical through it); the base carries a sphere of radius 0.5 about c; l2 has two
spheres (radius 0.05) at c and 0.1 m from it; l3's origin is 0.4 m from c, its first sphere
(radius 0.05) there, its second (radius 0.2) 1.0 m further along l3's x axis, at distance
d(q3) = sqrt(0.4² + 1 + 0.8 cos q3) from c: contact iff d < 0.7, i.e. |q3| > acos(-0.8375) ≈ 2.564."""
import sys
import warnings
from pathlib import Path

import numpy as np
import pytest

import robokit
from robokit.collision import World, self_collision_pairs

sys.path.insert(0, str(Path(__file__).parents[1] / "description"))
from urdf_text import arm, inertial, sphere  # noqa: E402


@pytest.fixture(scope="module")
def robot(tmp_path_factory):
    path = tmp_path_factory.mktemp("pairs") / "two_shapes.urdf"
    path.write_text(arm({
        "base": inertial(2.0, 0.02, 0.02, 0.02) + sphere(0.5, "0 0 0.3"),
        "l2": inertial(1.0, 0.002, 0.015, 0.015, xyz="0.2 0 0") + sphere(0.05) + sphere(0.05, "0.1 0 0"),
        "l3": inertial(0.5, 0.001, 0.004, 0.004, xyz="0.15 0 0") + sphere(0.05) + sphere(0.2, "1.0 0 0"),
    }))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return robokit.load(path)


def _d(q3):
    return np.sqrt(0.16 + 1.0 + 0.8 * np.cos(q3))


def test_closed_form_classes():
    q3 = np.linspace(-3, 3, 6001)  # the joint's limits
    touching = _d(q3) < 0.5 + 0.2
    assert 0.05 < touching.mean() < 0.5  # l3's far sphere meets the base sphere sometimes
    assert 0.4 + 0.05 < 0.5 and 0.1 + 0.05 < 0.5  # l3's near sphere and both of l2's: always inside


def test_each_link_pair_once_in_one_class(robot):
    p = self_collision_pairs(robot)
    every = p.checked + p.adjacent + p.always
    assert len(every) == len({frozenset(x) for x in every})  # once each, whatever the order
    assert p.checked == [("base", "l3")] and p.partly == [("base", "l3", 1, 2)]
    assert p.always == [("base", "l2")] and ("l2", "l3") in p.adjacent
    assert len(p.index_pairs) == 1  # the far sphere of l3 against the base sphere
    text = World(robot).describe()
    assert text.count("base – l3") == 1 and "base–l3" not in text  # listed once, under checked
    assert "(1 of its 2 shape pairs in contact in every sample: those skipped)" in text
    assert "always in contact (1; every shape pair in every sample): base–l2" in text


def test_the_checked_shape_pair_sees_what_the_closed_form_says(robot):
    w = World(robot)
    for q3 in (0.0, 2.0, 2.5, 2.6, 2.9, -2.9):
        q = np.array([0.4, -0.3, q3])
        expected = bool(_d(q3) < 0.7)
        assert w.in_collision(q) is expected
        assert w.colliding_pairs(q) == ([("base", "l3")] if expected else [])
