"""Every area of ``robokit validate`` runs and every one of its rows passes (one test per area).

The rows compare the course implementations with Pinocchio (and MuJoCo when installed); this
is the main job's own check, area by area, so a failing area names itself.
"""
import numpy as np
import pytest

from robokit.validation import AREAS, iter_rows

IDS = [module for _, module in AREAS]


@pytest.mark.parametrize("area", AREAS, ids=IDS)
def test_validation_area_rows_pass(area):
    ((_, rows),) = list(iter_rows(seed=0, areas=[area]))
    if area[1] == "mujoco" and not rows:
        pytest.skip("mujoco is not installed: no MuJoCo rows")
    assert rows, f"{area}: no rows"
    failed = [(r.quantity, r.model, r.max_error, r.tolerance, r.error) for r in rows if not r.passed]
    assert not failed, failed


def test_a_failing_row_fails_the_run():
    """The table's verdict is not vacuous: a row above its tolerance or with NaN fails."""
    from robokit.validation import CheckRow

    assert not CheckRow("x", "-", 10, 2e-9, 1e-9).passed
    assert not CheckRow("x", "-", 10, float("nan"), 1e-9).passed
    assert not CheckRow("x", "-", 0, 0.0, 1e-9).passed  # no case compared is no pass
    assert CheckRow("x", "-", 10, 5e-10, 1e-9).passed
    assert np.isfinite(CheckRow("x", "-", 1, 0.0, 1e-9).tolerance)
