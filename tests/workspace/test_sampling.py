"""Workspace sampling: the two-link annulus |l1 − l2| ≤ r ≤ l1 + l2 (Lecture 5)."""
import numpy as np
import pytest

from robokit.workspace.sampling import plot_workspace, sample_workspace


class PlanarTwoLink:
    """Minimal robot-like object: frame_pose of a planar 2-link arm (closed form)."""

    name = "planar2"

    def __init__(self, l1, l2, qlim):
        self.l1, self.l2, self.n, self.qlim = l1, l2, 2, np.asarray(qlim, float)

    def frame_pose(self, q, frame=None):
        a, b = q
        T = np.eye(4)
        T[:2, :2] = [[np.cos(a + b), -np.sin(a + b)], [np.sin(a + b), np.cos(a + b)]]
        T[0, 3] = self.l1 * np.cos(a) + self.l2 * np.cos(a + b)
        T[1, 3] = self.l1 * np.sin(a) + self.l2 * np.sin(a + b)
        return T


def test_two_link_annulus():
    l1, l2 = 1.0, 0.6
    robot = PlanarTwoLink(l1, l2, [(-np.pi, np.pi), (-np.pi, np.pi)])
    ws = sample_workspace(robot, 20000, rng=1)
    assert ws.planar
    assert ws.reach.min() >= abs(l1 - l2) - 1e-12
    assert ws.reach.max() <= l1 + l2 + 1e-12
    assert ws.reach.max() > l1 + l2 - 0.01 and ws.reach.min() < abs(l1 - l2) + 0.02
    true_area = np.pi * ((l1 + l2) ** 2 - (l1 - l2) ** 2)
    assert abs(ws.measure - true_area) / true_area < 0.1  # pixel count with the hole kept
    assert np.allclose(ws.lower[:2], [-(l1 + l2)] * 2, atol=0.02)


def test_limits_shrink_workspace_and_plot():
    robot = PlanarTwoLink(1.0, 1.0, [(0.0, np.pi / 2), (0.0, np.pi / 2)])
    ws = sample_workspace(robot, 3000, rng=2)
    assert np.all(ws.q >= 0) and np.all(ws.q <= np.pi / 2)
    assert ws.points[:, 1].min() >= -1e-12  # θ1, θ2 ∈ [0, π/2]: y ≥ 0
    fig = plot_workspace(ws)
    assert fig.axes


def test_bad_input():
    robot = PlanarTwoLink(1.0, 1.0, [(-1, 1), (-1, 1)])
    with pytest.raises(ValueError, match="n_samples"):
        sample_workspace(robot, 0)
    with pytest.raises(ValueError, match="cell"):
        sample_workspace(robot, 10, cell=-1.0)
