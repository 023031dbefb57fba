"""Every area of ``robokit validate`` runs and every one of its rows passes (one test per area).

The rows compare the course implementations with Pinocchio (and MuJoCo when installed); this
is the main job's own check, area by area, so a failing area names itself.
"""
import numpy as np
import pytest

from robokit.validation import AREAS, iter_rows

IDS = [module for _, module in AREAS]

#: Rows of each area computed so far in this session (the docs test below reuses them).
_ROWS: dict = {}


def _area_rows(area):
    if area not in _ROWS:
        ((_, rows),) = list(iter_rows(seed=0, areas=[area]))
        _ROWS[area] = rows
    return _ROWS[area]


@pytest.mark.parametrize("area", AREAS, ids=IDS)
def test_validation_area_rows_pass(area):
    rows = _area_rows(area)
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


def _mask_error_column(line: str) -> str:
    """A streamed row's last line with its ``max error`` cell blanked (the digits past the
    tolerance can differ between machines; everything else is fixed by the seed)."""
    from robokit.validation import _WIDTHS

    start = sum(w + 2 for w in _WIDTHS[:3])
    return (line[:start] + " " * _WIDTHS[3] + line[start + _WIDTHS[3]:]).rstrip()


def test_cli_docs_sample_is_a_real_run():
    """docs/cli.md's sample of ``robokit validate`` shows rows the command really prints, in its
    real layout, and the count on its summary line is the real number of rows."""
    import re
    from pathlib import Path

    from robokit.validation import _line, _row_cells

    text = (Path(__file__).parents[2] / "docs" / "cli.md").read_text(encoding="utf-8")
    section = text[text.index("## `robokit validate`"):]
    block = section[section.index("```text\nquantity"):]
    block = block[len("```text\n"):block.index("\n```")]
    lines = block.splitlines()
    assert lines[0].startswith("quantity") and set(lines[1].replace(" ", "")) == {"-"}
    *shown, dots, summary = lines[2:]
    assert dots == "..."
    rows = [r for area in AREAS for r in _area_rows(area)]
    printed = {_mask_error_column(_line(_row_cells(r)).splitlines()[-1]): _line(_row_cells(r)) for r in rows}
    i = 0
    while i < len(shown):  # a row is its wrapped first lines plus the line with the other columns
        j = i
        while len(shown[j]) <= len(shown[j].split("  ")[0]) + 1 and j + 1 < len(shown):
            j += 1
        entry = "\n".join(shown[i:j + 1])
        key = _mask_error_column(shown[j])
        assert key in printed, f"docs/cli.md shows a row robokit validate does not print:\n{entry}"
        assert printed[key].splitlines()[:-1] == shown[i:j], f"the row wraps differently:\n{entry}"
        i = j + 1
    m = re.fullmatch(r"(\d+) passed, 0 failed  \([\d.]+ s\)", summary)
    assert m, summary
    has_mujoco = any(r.quantity.startswith("MuJoCo") for r in rows)
    if has_mujoco:  # the sample was taken with every extra installed
        assert int(m.group(1)) == len(rows)
