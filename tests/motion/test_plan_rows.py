"""`robokit plan` output size (issue 39, class 8): the rows of the CSV are estimated and bounded by
the trajectory reader's rule (robokit.viz.view.MAX_TRAJECTORY_ROWS) before any is made. Was:
`--dt 1e-9` or `--vmax 1e-9` allocated 11-226 GiB (exit 3). The CLI runs under a 3 GB
address-space limit (a safety net, never a timing)."""
import sys
from pathlib import Path

import pytest


import hardening_support as hs  # noqa: E402
import limited_cli as r2  # noqa: E402

from robokit.viz.view import MAX_TRAJECTORY_ROWS, load_trajectory  # noqa: E402

pytest.importorskip("ompl")

PLAN = ["plan", "twolink", "--start", "0", "0", "--goal", "1", "1"]


def test_absurd_steps_and_limits_exit_2_before_allocating(tmp_path):
    out = tmp_path / "p.csv"
    argvs = [PLAN + ["--vmax", "1e-9", "-o", out],      # estimated before planning (joint goal)
             PLAN + ["--dt", "1e-9", "-o", out],        # estimated before planning
             PLAN + ["--amax", "1e-12", "-o", out],     # known from the retimed duration, before any row
             PLAN + ["--dt", "1e-300", "-o", out],
             PLAN + ["--vmax", "1e300", "-o", out],     # bounded like every number (1e12)
             PLAN + ["--dt", "nan", "-o", out]]
    runs = r2.run_many(argvs)
    for run in runs[:4]:
        hs.assert_one_line_error(run, "rows", str(MAX_TRAJECTORY_ROWS))
    hs.assert_one_line_error(runs[4], "--vmax")
    hs.assert_one_line_error(runs[5], "--dt")
    assert list(tmp_path.iterdir()) == []


def test_a_trajectory_just_within_the_rule_is_written_and_reads_back(tmp_path):
    """A small step that stays under the rule still works, and the file is one the viewer reads."""
    out = tmp_path / "p.csv"
    run = r2.run_limited(*PLAN, "--dt", "2e-5", "-o", out)
    assert run.rc == 0, run.err
    Q = load_trajectory(out, 2)
    assert 10_000 < len(Q) <= MAX_TRAJECTORY_ROWS
    assert abs(Q[0]).max() < 1e-9 and abs(Q[-1] - 1.0).max() < 1e-9
