"""Capability maps against closed forms: orientation sets, planar 2R and 3R arms (Lecture 5)."""
import numpy as np
import pytest

import robokit
from robokit.description.dh import DHLink, DHTable
from robokit.workspace import (CapabilityMap, capability_map, ik_backend, ik_success, planar_rotations,
                               super_fibonacci_rotations)


def planar_arm(*lengths, qlim=None):
    """A planar arm: standard DH, parallel z axes, link lengths a_i, joints limited to ±π (or qlim)."""
    links = tuple(DHLink(joint="R", a=float(l), qlim=None if qlim is None else np.array(qlim, float))
                  for l in lengths)
    return DHTable(f"planar{len(lengths)}r", "standard", links)


def wrap(a):
    return np.angle(np.exp(1j * np.asarray(a)))


# ----------------------------------------------------------------------------- orientation sets
def test_super_fibonacci_rotations_are_rotations_and_deterministic():
    R = super_fibonacci_rotations(500)
    assert R.shape == (500, 3, 3)
    assert np.allclose(R @ np.transpose(R, (0, 2, 1)), np.eye(3), atol=1e-12)
    assert np.allclose(np.linalg.det(R), 1.0)
    assert np.array_equal(R, super_fibonacci_rotations(500))


def test_super_fibonacci_rotations_are_uniform():
    # Haar measure on SO(3): E[R] = 0 and E[R_ij R_kl] = δ_ik δ_jl / 3
    R = super_fibonacci_rotations(2000)
    assert np.abs(R.mean(axis=0)).max() < 5e-3
    V = R.reshape(len(R), 9)
    assert np.abs(V.T @ V / len(R) - np.eye(9) / 3).max() < 5e-3
    # covering: every rotation lies within a small angle of the set (K = 1000: a ball of
    # radius 0.27 rad around each point would cover SO(3) exactly once)
    S = super_fibonacci_rotations(1000)
    rng = np.random.default_rng(1)
    q = rng.normal(size=(300, 4))
    q /= np.linalg.norm(q, axis=1, keepdims=True)
    from robokit.workspace.orientations import _matrices_from_quaternions

    X = _matrices_from_quaternions(q)
    tr = np.einsum("aij,bij->ab", X, S)  # trace(Xᵀ S)
    angle = np.arccos(np.clip((tr.max(axis=1) - 1) / 2, -1, 1))
    assert angle.max() < 0.6


def test_planar_rotations_closed_form():
    R = planar_rotations(8, [0, 0, 2.0])
    phi = 2 * np.pi * np.arange(8) / 8
    expected = np.zeros((8, 3, 3))
    expected[:, 0, 0] = expected[:, 1, 1] = np.cos(phi)
    expected[:, 1, 0], expected[:, 0, 1] = np.sin(phi), -np.sin(phi)
    expected[:, 2, 2] = 1
    assert np.allclose(R, expected, atol=1e-15)


@pytest.mark.parametrize("bad, exc", [(0, ValueError), (-3, ValueError), (2.5, TypeError), (True, TypeError)])
def test_orientation_count_checked(bad, exc):
    with pytest.raises(exc, match="orientations"):
        super_fibonacci_rotations(bad)


# ----------------------------------------------------------------------------- ik_success
def test_ik_success_reaches_fk_poses_and_refuses_far_ones():
    rng = np.random.default_rng(3)
    for name in ("rrr", "puma560"):
        robot = robokit.load(name)
        Q = np.array([robot.random_configuration(rng) for _ in range(4)])
        T = np.array([robot.frame_pose(q) for q in Q])
        assert ik_success(robot, T, rng=0, restarts=50).all()
        far = T.copy()
        far[:, :3, 3] += 10.0
        assert not ik_success(robot, far, rng=0).any()


def test_planar_backend_refuses_tilted_and_off_plane_poses():
    robot = robokit.load(planar_arm(0.5, 0.4, 0.2))
    assert ik_backend(robot) == "planar"
    T = robot.frame_pose(np.array([0.3, 0.2, -0.4]))
    tilted = T.copy()
    tilted[:3, :3] = T[:3, :3] @ np.array([[1, 0, 0], [0, 0, -1], [0, 1, 0]])
    lifted = T.copy()
    lifted[2, 3] += 0.01
    assert ik_success(robot, np.array([T, tilted, lifted])).tolist() == [True, False, False]


def test_planar_backend_respects_joint_limits():
    # joints limited to [0, 90°]: a pose needing θ₂ < 0 for both elbows is refused
    robot = robokit.load(planar_arm(0.5, 0.5, qlim=[0, np.pi / 2]))
    inside = robot.frame_pose(np.array([0.3, 0.5]))
    elbow_back = robot.frame_pose(np.array([0.3, -0.5]))
    assert ik_success(robot, np.array([inside, elbow_back])).tolist() == [True, False]


def test_ik_success_checks_its_input():
    with pytest.raises(ValueError, match="targets"):
        ik_success("rrr", np.eye(4))
    with pytest.raises(ValueError, match="targets"):
        ik_success("rrr", np.full((1, 4, 4), np.nan))


# ----------------------------------------------------------------------------- planar 2R
def test_planar_2r_index_is_the_closed_form():
    """Equal links l: the tool angle at a point (r, α) is φ± = α ± acos(r / 2l) (isosceles
    triangle), so at most 2 of the K angles 2πk/K are reached — except at the origin, where
    the folded arm (θ₂ = π) points the tool anywhere (index 1)."""
    l, K, res = 0.5, 6, 0.05
    cmap = capability_map(planar_arm(l, l), res, orientations=K, client="serial")
    C = cmap.centres
    assert np.allclose(C[:, 2], 0.0)
    r = np.hypot(C[:, 0], C[:, 1])
    alpha = np.arctan2(C[:, 1], C[:, 0])
    phik = 2 * np.pi * np.arange(K) / K
    expected = np.zeros(len(C))
    inside = (r > 1e-12) & (r < 2 * l)
    half = np.arccos(np.clip(r / (2 * l), -1, 1))
    for sign in (1, -1):
        gap = np.abs(wrap((alpha + sign * half)[:, None] - phik[None, :]))
        assert not np.any((gap > 1e-10) & (gap < 1e-6))  # no ambiguous centre
        hit = (gap < 1e-10) & inside[:, None]
        expected += hit.sum(axis=1)
    # both branches coincide on the outer circle r = 2l: one solution, counted once
    on_rim = np.abs(r - 2 * l) < 1e-12
    expected[on_rim] = np.sum(np.abs(wrap(alpha[on_rim, None] - phik[None, :])) < 1e-10, axis=1)
    expected[r < 1e-12] = K
    assert np.array_equal(cmap.index, expected / K)
    assert cmap.index.max() == 1.0 and cmap.index[r < 1e-12] == 1.0
    assert np.isclose(cmap.index[np.argmin(np.hypot(C[:, 0] - 0.5, C[:, 1]))], 2 / K)  # φ± = ±60°
    assert len(cmap.dexterous) == 1
    # reachable set: every lattice point strictly inside the disc r < 2l is in the map, none far outside
    g = np.arange(-25, 26) * res
    X, Y = np.meshgrid(g, g)
    want = np.hypot(X, Y) < 2 * l - res
    have = {(round(x / res), round(y / res)) for x, y in C[:, :2]}
    assert all((round(x / res), round(y / res)) in have for x, y in zip(X[want], Y[want]))
    assert r.max() <= 2 * l + 2 * res * np.sqrt(2)


# ----------------------------------------------------------------------------- planar 3R
L1, L2, L3 = 0.5, 0.4, 0.2


def test_planar_3r_index_counts_wrist_positions_in_the_annulus():
    """Tool at p with angle φ ⇔ wrist w = p − l₃(cos φ, sin φ) in the two-link annulus
    |l₁ − l₂| ≤ |w| ≤ l₁ + l₂ (unlimited joints): the index is that count over the K angles."""
    K, res = 12, 0.05
    cmap = capability_map(planar_arm(L1, L2, L3), res, orientations=K, client="serial")
    C = cmap.centres[:, :2]
    phik = 2 * np.pi * np.arange(K) / K
    W = C[:, None, :] - L3 * np.stack([np.cos(phik), np.sin(phik)], axis=1)[None]
    dist = np.linalg.norm(W, axis=2)
    lo, hi = abs(L1 - L2), L1 + L2
    clear = (np.abs(dist - lo) > 1e-9) & (np.abs(dist - hi) > 1e-9)
    keep = clear.all(axis=1)
    assert keep.mean() > 0.95
    expected = ((dist >= lo) & (dist <= hi)).sum(axis=1) / K
    assert np.array_equal(cmap.index[keep], expected[keep])


def test_planar_3r_dexterous_region_is_the_lecture_annulus():
    """Dexterous (every orientation) ⇔ the whole circle of wrist points of radius l₃ about p
    lies in the annulus: r + l₃ ≤ l₁ + l₂ and |r − l₃| ≥ |l₁ − l₂|, i.e. r ≤ l₁ + l₂ − l₃ = 0.7
    and (r ≤ l₃ − |l₁ − l₂| = 0.1 or r ≥ l₃ + |l₁ − l₂| = 0.3). Reach: r ≤ l₁ + l₂ + l₃ = 1.1."""
    K, res = 16, 0.05
    cmap = capability_map(planar_arm(L1, L2, L3), res, orientations=K, client="serial")
    r = np.linalg.norm(cmap.centres, axis=1)
    band = 0.05
    dexterous = ((r <= L1 + L2 - L3) & ((r <= L3 - abs(L1 - L2)) | (r >= L3 + abs(L1 - L2))))
    assert np.all(cmap.index[dexterous] == 1.0)
    not_dexterous = ((r > L1 + L2 - L3 + band) | ((r > L3 - abs(L1 - L2) + band) & (r < L3 + abs(L1 - L2) - band)))
    assert np.all(cmap.index[not_dexterous & (r < L1 + L2 + L3)] < 1.0)
    assert np.all(cmap.index[r > L1 + L2 + L3] == 0.0)
    assert np.all(cmap.index[r < L1 + L2 + L3 - band] > 0.0)
    assert not_dexterous.sum() > 50 and dexterous.sum() > 50


# ----------------------------------------------------------------------------- the object and its input checks
def test_map_round_trip_and_contract(tmp_path):
    cmap = capability_map("rrr", 0.1, orientations=8, client="serial")
    assert cmap.centres.shape == (len(cmap.index), 3) and cmap.orientations.shape == (8, 3, 3)
    assert cmap.resolution == 0.1 and cmap.robot == "rrr" and np.all((cmap.index >= 0) & (cmap.index <= 1))
    assert {"prepass", "sweep", "total", "problems"} <= set(cmap.timings)
    cmap.save(tmp_path / "m.npz")
    with np.load(tmp_path / "m.npz") as z:
        assert sorted(z.files) == ["centres", "index", "orientations", "resolution"]
    back = CapabilityMap.load(tmp_path / "m.npz")
    assert np.array_equal(back.centres, cmap.centres) and np.array_equal(back.index, cmap.index)
    assert CapabilityMap.load(cmap.save(tmp_path / "n.npz", include_robot=True)).robot == "rrr"


@pytest.mark.parametrize("kwargs, exc, word", [
    (dict(resolution=-0.1), ValueError, "resolution"),
    (dict(resolution=float("nan")), ValueError, "resolution"),
    (dict(resolution="1"), TypeError, "resolution"),
    (dict(resolution=0.1, orientations=0), ValueError, "orientations"),
    (dict(resolution=0.1, orientations=np.ones((2, 3, 3))), ValueError, "orientations"),
    (dict(resolution=0.1, chunk_size=0), ValueError, "chunk_size"),
    (dict(resolution=0.1, client=3), TypeError, "client"),
    (dict(resolution=1e-5), ValueError, "resolution"),
])
def test_bad_input_is_named(kwargs, exc, word):
    kwargs.setdefault("client", "serial")
    with pytest.raises(exc, match=word):
        capability_map("rrr", **kwargs)
