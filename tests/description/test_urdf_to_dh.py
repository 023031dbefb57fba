"""URDF → DH: exact FK in both conventions, shipped tables recovered, UR5 matches the
manufacturer's table, dynamics kept through URDF → DH YAML → URDF, geometry special cases."""
import numpy as np
import pytest

import robokit as rk
from shared_robots import robot as shared_robot
from robokit.description.dh import DHTable
from robokit.description.urdf_to_dh import _normal, format_dh_table, dh_from_urdf

MODELS = ["twolink", "rrr", "puma560", "ur5", "panda", "z1", "xarm7", "kinova"]


@pytest.fixture(scope="module")
def robots():
    return {n: shared_robot(n) for n in MODELS}


@pytest.mark.parametrize("name", MODELS)
@pytest.mark.parametrize("convention", ["standard", "modified"])
def test_fk_of_extracted_table_equals_pinocchio(name, convention, robots):
    r = robots[name]
    res = dh_from_urdf(r, convention, samples=10)
    rng = np.random.default_rng(0)
    for _ in range(200):
        q = r.random_configuration(rng)
        assert np.abs(res.table.fk(q) - r.frame_pose(q)).max() < 1e-9
    assert res.exact and res.table.convention == convention


@pytest.mark.parametrize("name", ["twolink", "rrr", "puma560"])
def test_shipped_tables_recovered(name, robots):
    orig = robots[name].dh
    got = dh_from_urdf(robots[name], "standard", samples=5).table
    for a, b in zip(got.links, orig.links):
        assert np.isclose(a.a, b.a, atol=1e-12) and np.isclose(a.alpha, b.alpha, atol=1e-12)
        assert np.isclose(a.d, b.d, atol=1e-12) and np.isclose(np.cos(a.theta - b.theta), 1.0)
        assert np.isclose(a.mass, b.mass) and np.allclose(a.com, b.com, atol=1e-12)
        assert np.allclose(a.inertia, b.inertia, atol=1e-12)


def test_ur5_matches_manufacturer_table(robots):
    t = dh_from_urdf(robots["ur5"], "standard", samples=5).table
    a = [abs(l.a) for l in t.links]
    d = [abs(l.d) for l in t.links]
    # Universal Robots' published UR5 DH parameters (up to sign conventions)
    assert np.allclose(a, [0, 0.425, 0.39225, 0, 0, 0], atol=1e-6)
    assert np.allclose(d, [0.089159, 0, 0, 0.10915, 0.09465, 0.0823], atol=1e-6)
    assert np.allclose(np.abs([np.degrees(l.alpha) for l in t.links]), [90, 0, 0, 90, 90, 0], atol=1e-9)


@pytest.mark.parametrize("name", ["ur5", "panda"])
@pytest.mark.parametrize("convention", ["standard", "modified"])
def test_round_trip_keeps_dynamics(name, convention, robots, tmp_path):
    r = robots[name]
    table = dh_from_urdf(r, convention, samples=5).table
    path = tmp_path / f"{name}.yaml"
    table.save(path)
    back = rk.load(path)  # YAML → URDF (urdf_from_dh) → Pinocchio
    rng = np.random.default_rng(1)
    for _ in range(50):
        q, dq, ddq = r.random_configuration(rng), rng.normal(size=r.n), rng.normal(size=r.n)
        ref = r.rnea(q, dq, ddq)
        assert np.abs(back.rnea(q, dq, ddq) - ref).max() <= 1e-9 * max(1.0, np.abs(ref).max())
        assert np.abs(back.frame_pose(q) - r.frame_pose(q)).max() < 1e-9


def test_geometry_special_cases():
    z = np.array([0.0, 0.0, 1.0])
    x = np.array([1.0, 0.0, 0.0])
    # skew: axis z through 0 and axis x through (0, 0, 1) shifted by 0.5 in y
    f1, f2, nx = _normal(np.zeros(3), z, np.array([0, 0.5, 1.0]), x, np.zeros(3), x)
    assert np.allclose(f1, [0, 0, 1]) and np.allclose(f2, [0, 0.5, 1]) and np.allclose(nx, [0, 1, 0])
    # intersecting: a = 0, x = ±z1 × z2 with the sign nearest the previous x
    f1, f2, nx = _normal(np.zeros(3), z, np.array([0, 0, 1.0]), x, np.zeros(3), np.array([0, 1.0, 0]))
    assert np.allclose(f1, f2) and np.allclose(f1, [0, 0, 1]) and np.allclose(nx, [0, 1, 0])
    f1, f2, nx = _normal(np.zeros(3), z, np.array([0, 0, 1.0]), x, np.zeros(3), np.array([0, -1.0, 0]))
    assert np.allclose(nx, [0, -1, 0])
    # parallel: through the reference point (d = 0 there)
    f1, f2, nx = _normal(np.zeros(3), z, np.array([1.0, 0, 0]), z, np.array([0, 0, 0.3]), x)
    assert np.allclose(f1, [0, 0, 0.3]) and np.allclose(f2, [1, 0, 0.3]) and np.allclose(nx, [1, 0, 0])
    # coincident: the previous x is kept
    f1, f2, nx = _normal(np.zeros(3), z, np.array([0, 0, 2.0]), z, np.zeros(3), np.array([0, 1.0, 0]))
    assert np.allclose(f1, f2) and np.allclose(nx, [0, 1, 0])


def test_prismatic_chain_round_trip(tmp_path):
    """A Stanford-arm-like RRPRRR DH table → URDF → DH reproduces the FK (prismatic joint 3)."""
    from robokit.description.dh import DHLink

    rows = [(0, -np.pi / 2, 0.412, 0, "R"), (0, np.pi / 2, 0.154, 0, "R"), (0, 0, 0.3, -np.pi / 2, "P"),
            (0, -np.pi / 2, 0, 0, "R"), (0, np.pi / 2, 0, 0, "R"), (0, 0, 0.263, 0, "R")]
    t = DHTable("stanford", "standard", tuple(DHLink(j, a, al, d, th, np.array([-0.5, 0.5]) if j == "P" else None,
                                                     1.0, np.zeros(3), np.array([0.01, 0.01, 0.01, 0, 0, 0]))
                                              for a, al, d, th, j in rows))
    r = rk.load(t)
    for conv in ("standard", "modified"):
        res = dh_from_urdf(r, conv, samples=100)
        assert res.exact, res.residual
        assert [l.joint for l in res.table.links] == ["R", "R", "P", "R", "R", "R"]


def test_cli_prints_and_writes(tmp_path, capsys):
    from robokit.cli import main

    assert main(["convert", "ur5"]) == 0
    out = capsys.readouterr().out
    assert "0.39225" in out and "standard DH" in out
    dest = tmp_path / "panda.yaml"
    assert main(["convert", "panda", "--convention", "modified", "-o", str(dest)]) == 0
    t = DHTable.from_yaml(dest)
    assert t.convention == "modified" and t.n == 7
    assert "alpha_{i-1}" in format_dh_table(t)
