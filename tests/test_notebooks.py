"""Every notebook in notebooks/ runs top to bottom in a fresh kernel, with no error, no
warning in its outputs, and stays small once executed.

The notebooks are stored with their outputs stripped (checked here); this test executes them
in memory (nothing is written back) with the test suite's Python, in a temporary folder (the
pages that views write beside the notebook land there).
"""
import json
from pathlib import Path

import pytest

NOTEBOOKS = sorted((Path(__file__).resolve().parents[1] / "notebooks").glob("*.ipynb"))


def test_there_are_notebooks():
    assert len(NOTEBOOKS) >= 5


@pytest.mark.parametrize("path", NOTEBOOKS, ids=[p.name for p in NOTEBOOKS])
def test_notebook_runs(path, tmp_path):
    import nbformat
    from nbclient import NotebookClient

    raw = json.loads(path.read_text(encoding="utf-8"))
    for cell in raw["cells"]:
        if cell["cell_type"] == "code":
            assert not cell.get("outputs"), f"{path.name}: outputs must be stripped in the repository"
    nb = nbformat.reads(path.read_text(encoding="utf-8"), as_version=4)
    client = NotebookClient(nb, timeout=300, kernel_name="python3", resources={"metadata": {"path": str(tmp_path)}})
    client.execute()
    outputs = [o for c in nb.cells if c.cell_type == "code" for o in c.get("outputs", [])]
    errors = [o for o in outputs if o.get("output_type") == "error"]
    assert not errors
    warned = [o.get("text", "") for o in outputs if o.get("output_type") == "stream" and o.get("name") == "stderr"
              and "Warning" in o.get("text", "")]
    assert not warned, f"{path.name}: warnings in the outputs: {warned[0][:300]}"
    size = len(nbformat.writes(nb).encode("utf-8"))
    assert size < 3_000_000, f"{path.name}: {size / 1e6:.1f} MB once executed (views must be files, not embedded)"


@pytest.mark.parametrize("path", NOTEBOOKS, ids=[p.name for p in NOTEBOOKS])
def test_notebook_file_is_valid_without_warnings(path):
    """The stored file validates with no nbformat warning (e.g. MissingIDFieldWarning: cells
    without ids, which Jupyter and nbmake report on every run)."""
    import warnings

    import nbformat

    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        nb = nbformat.read(path, as_version=4)
        nbformat.validate(nb)
    names = sorted({w.category.__name__ for w in caught})
    assert not names, f"{path.name}: {names} — normalise it (nbformat.read then nbformat.write)"
    raw = json.loads(path.read_text(encoding="utf-8"))
    assert all("id" in cell for cell in raw["cells"]), f"{path.name}: cells without ids"
