"""One-call plots: they build, with the expected panels and lines, under the Agg backend."""
import matplotlib

matplotlib.use("Agg")

import numpy as np  # noqa: E402
import pytest  # noqa: E402
from matplotlib.figure import Figure  # noqa: E402

from robokit import joint_trajectory, ms_trajectory, screw_trajectory  # noqa: E402
from robokit.trajectory import (  # noqa: E402
    cartesian_line_trajectory, cubic_trajectory, plot_path_3d, plot_trajectory)


def test_plot_trajectory_three_panels_one_line_per_axis(tmp_path):
    tr = cubic_trajectory([0, 1, 2], [1, 0, 0], 2.0)
    fig = plot_trajectory(tr, title="cubic")
    assert isinstance(fig, Figure)
    assert len(fig.axes) == 3
    assert [len(ax.lines) for ax in fig.axes] == [3, 3, 3]
    np.testing.assert_array_equal(fig.axes[1].lines[0].get_ydata(), tr.qd[:, 0])
    fig.savefig(tmp_path / "cubic.png")
    assert (tmp_path / "cubic.png").stat().st_size > 1000


def test_plot_marks_via_points_of_ms_trajectory():
    tr = ms_trajectory([[0.0, 0.0], [1.0, 2.0], [2.0, 0.0]], dt=0.05, tacc=0.4, qdmax=1.0)
    fig = plot_trajectory(tr)
    assert len(fig.axes[0].lines) == 2 + 2  # two axes + via markers for each
    np.testing.assert_allclose(fig.axes[0].lines[2].get_xdata(), tr.info["via_times"])


def test_plot_path_3d_from_trajectory_or_pose_list(tmp_path):
    T1 = np.eye(4)
    T1[:3, 3] = [0.4, 0.1, 0.3]
    tr = cartesian_line_trajectory(np.eye(4), T1, 1.0, t=21)
    fig = plot_path_3d(tr, frames=3)
    assert isinstance(fig, Figure)
    assert fig.axes[0].name == "3d"
    fig.savefig(tmp_path / "path.png")
    fig2 = plot_path_3d(screw_trajectory(np.eye(4), T1, 1.0, 10, 5))
    assert isinstance(fig2, Figure)


def test_plot_errors():
    with pytest.raises(ValueError, match="traj"):
        plot_trajectory(joint_trajectory([0], [1], 1.0, 5, 3))
    with pytest.raises(ValueError, match="poses"):
        plot_path_3d(cubic_trajectory(0, 1, 1.0))
    with pytest.raises(ValueError, match="labels"):
        plot_trajectory(cubic_trajectory([0, 1], [1, 0], 1.0), labels=["a"])
