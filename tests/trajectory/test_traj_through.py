"""Through points (pseudo via points), the seed's qdmax=[] idiom and the viapoints alias, and
multi-segment Cartesian paths with blends (finite differences, slerp on the linear parts)."""
import numpy as np
import pytest

from robokit.spatial.euler import matrix_from_euler
from robokit.spatial.lie import log3
from robokit.trajectory import ms_cartesian_trajectory, ms_through_trajectory, ms_trajectory, through_viapoints


def _polyline_distance(Q, p):
    """Smallest distance from p to the polyline through the samples Q (exact on linear parts)."""
    a, b = Q[:-1], Q[1:]
    ab = b - a
    t = np.clip(np.einsum("ij,ij->i", p - a, ab) / np.maximum(np.einsum("ij,ij->i", ab, ab), 1e-300), 0, 1)
    return float(np.min(np.linalg.norm(a + t[:, None] * ab - p, axis=1)))


VIA = np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [2.5, 1.5]])


@pytest.mark.parametrize("timing", ["qdmax", "tsegment"])
def test_path_passes_exactly_through_the_points(timing):
    kw = {"qdmax": [0.5, 0.5]} if timing == "qdmax" else {"tsegment": [2.0, 2.0, 3.0]}
    tr = ms_through_trajectory(VIA, 0.01, 0.4, **kw)
    for p in VIA[1:-1]:
        assert _polyline_distance(tr.q, p) < 1e-12
    # at the reported times the path is at the points (linear interpolation between samples)
    for tt, p in zip(tr.info["through_times"], VIA[1:-1]):
        q = np.array([np.interp(tt, tr.t, tr.q[:, j]) for j in range(2)])
        np.testing.assert_allclose(q, p, atol=1e-12)
    # the ordinary multi-segment trajectory only approaches them (Lecture 3)
    plain = ms_trajectory(VIA, 0.01, 0.4, **kw)
    assert _polyline_distance(plain.q, VIA[1]) > 1e-3
    np.testing.assert_allclose(tr.q[-1], VIA[-1])


def test_through_viapoints_geometry():
    pts, frac = through_viapoints(VIA, [1], 0.2)
    assert len(pts) == 5
    np.testing.assert_allclose(0.5 * (pts[1] + pts[2]), VIA[1])  # P is the midpoint of P⁻P⁺
    u = (pts[2] - pts[1]) / np.linalg.norm(pts[2] - pts[1])
    np.testing.assert_allclose(u, np.array([1.0, 1.0]) / np.sqrt(2))  # the bisector of (1,0) and (0,1)
    assert frac[0] == (0.0, pytest.approx(0.2)) and frac[1][0] == pytest.approx(0.2)
    with pytest.raises(ValueError, match="through"):
        through_viapoints(VIA, [0])
    with pytest.raises(ValueError, match="distance"):
        through_viapoints(VIA, [1], 5.0)


def test_seed_idioms_empty_qdmax_and_viapoints_alias():
    a = ms_trajectory(VIA, 0.05, 0.2, [], [2.0, 2.0, 2.0])
    b = ms_trajectory(viapoints=VIA, dt=0.05, tacc=0.2, tsegment=[2.0, 2.0, 2.0])
    c = ms_trajectory(VIA, 0.05, 0.2, tsegment=[2.0, 2.0, 2.0])
    np.testing.assert_array_equal(a.q, c.q)
    np.testing.assert_array_equal(b.q, c.q)
    d = ms_trajectory(VIA, 0.05, 0.2, qdmax=0.5, tsegment=[])
    np.testing.assert_array_equal(d.q, ms_trajectory(VIA, 0.05, 0.2, qdmax=0.5).q)
    with pytest.raises(TypeError, match="viapoints"):
        ms_trajectory(VIA, 0.05, 0.2, qdmax=0.5, viapoints=VIA)
    with pytest.raises(ValueError, match="exactly one"):
        ms_trajectory(VIA, 0.05, 0.2, [], [])


def _pose(eul, p):
    T = np.eye(4)
    T[:3, :3] = matrix_from_euler(eul, "ZYX")
    T[:3, 3] = p
    return T


POSES = np.array([_pose([0, 0, 0], [0.4, 0.0, 0.3]), _pose([0.8, 0.2, 0.0], [0.4, 0.3, 0.5]),
                  _pose([0.8, -0.4, 0.6], [0.1, 0.4, 0.4])])


def test_cartesian_multisegment_velocity_matches_finite_differences_and_hits_the_ends():
    tr = ms_cartesian_trajectory(POSES, 0.0005, 0.3, speed=0.3, angular_speed=1.0)
    np.testing.assert_allclose(tr.poses[-1], POSES[-1], atol=1e-12)
    np.testing.assert_allclose(tr.poses[0][:3, 3], tr.q[0, 3:])
    # ω by central differences of R: vee(Ṙ Rᵀ); the O(dt² · jerk) difference error is ≤ 1e-4 at dt = 0.5 ms
    dt = tr.t[1] - tr.t[0]
    for k in range(5, len(tr.t) - 5, 97):
        dR = (tr.poses[k + 1, :3, :3] - tr.poses[k - 1, :3, :3]) / (2 * dt)
        W = dR @ tr.poses[k, :3, :3].T
        np.testing.assert_allclose(tr.qd[k, :3], [W[2, 1], W[0, 2], W[1, 0]], atol=1e-4)
        np.testing.assert_allclose(tr.qd[k, 3:], (tr.q[k + 1, 3:] - tr.q[k - 1, 3:]) / (2 * dt), atol=1e-4)
    # speed limits hold on the linear parts (blends may be faster, as mstraj)
    lin = ~tr.info["in_blend"]
    assert np.abs(tr.qd[lin, 3:]).max() <= 0.3 + 1e-9
    assert np.linalg.norm(tr.qd[lin, :3], axis=1).max() <= 1.0 + 1e-9
    # the angular velocity is continuous (blended)
    assert np.linalg.norm(np.diff(tr.qd[:, :3], axis=0), axis=1).max() < 0.02


def test_cartesian_linear_parts_are_slerps_about_a_fixed_axis():
    tr = ms_cartesian_trajectory(POSES, 0.01, 0.2, tsegment=[2.0, 2.0])
    s = tr.info["s"]
    on_first = (~tr.info["in_blend"]) & (s[:, 0] > 0) & (s[:, 0] < 1) & (s[:, 1] == 0)
    assert on_first.sum() > 10
    R0 = POSES[0, :3, :3]
    w = log3(R0.T @ POSES[1, :3, :3])
    for k in np.nonzero(on_first)[0]:
        rel = log3(R0.T @ tr.poses[k, :3, :3])
        np.testing.assert_allclose(np.cross(rel, w), 0.0, atol=1e-12)  # same axis
    with pytest.raises(ValueError, match="speed"):
        ms_cartesian_trajectory(POSES, 0.01, 0.2, speed=0.3)
