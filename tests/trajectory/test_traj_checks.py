"""The trajectory rows of ``robokit validate`` run and pass."""
import numpy as np

from robokit.trajectory.checks import checks


def test_trajectory_validation_rows_pass():
    rows = checks(np.random.default_rng(0))
    assert len(rows) >= 5
    failed = [(r.quantity, r.max_error, r.error) for r in rows if not r.passed]
    assert not failed, failed
