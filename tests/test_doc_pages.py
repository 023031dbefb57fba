"""Every page of the documentation runs as a reader reads it, and shows what its code prints.

Each page's ```python blocks run in order as one script (one namespace, like a notebook) in a fresh
interpreter in a temporary folder; every value the page shows — a ``print(...)``'s comment, the comment
lines or the ```text block below it, a ``>>>`` example's output, a ``# SomeWarning: ...`` line — is
compared with what the code printed (the rules: tests/support/doc_pages.py). docs/getting-started.md is
run the same way by tests/test_getting_started.py, which checks the files it writes too.

A page that loads files of the reader's own (``robokit.load("arm.xml")``) gets them in its folder before it
runs: ``FILES`` says which, each made from a file the repository has or that the page itself shows.
"""
from __future__ import annotations

import importlib.util
from dataclasses import dataclass, field
from pathlib import Path

import doc_pages
import pytest

ROOT = Path(__file__).resolve().parents[1]
DOCS = ROOT / "docs"


@dataclass(frozen=True)
class Page:
    requires: tuple[str, ...] = ()   # modules the page imports beyond robokit's core (else: skipped)
    shows: int = 0                   # at least this many values shown (a page that shows none: 0)
    writes: tuple[str, ...] = ()     # files the page writes in its folder
    env: dict[str, str] = field(default_factory=dict)


#: Every page with Python blocks, but docs/getting-started.md (tests/test_getting_started.py).
PAGES = {
    "course/calibration.md": Page(requires=("matplotlib",), shows=7),
    "course/capability-maps.md": Page(requires=("matplotlib", "distributed"), shows=2),
    "course/control.md": Page(requires=("matplotlib",), shows=1, writes=("tracking.png",)),
    "course/dh-forward-kinematics.md": Page(shows=1),
    "course/dynamics.md": Page(shows=2),
    "course/inverse-kinematics-closed-form.md": Page(shows=6),
    "course/inverse-kinematics.md": Page(shows=4),
    "course/jacobians.md": Page(shows=1),
    "course/mobile.md": Page(shows=1),
    "course/motion.md": Page(requires=("toppra", "ompl"), shows=11),
    "course/spatial.md": Page(shows=1),
    "course/symbolic.md": Page(requires=("sympy",), shows=3),
    "course/trajectories.md": Page(requires=("matplotlib",), shows=6, writes=("via.png", "line.png")),
    "course/urdf-to-dh.md": Page(shows=2, writes=("ur5.yaml",)),
    "course/visualisation.md": Page(requires=("meshcat",), writes=("puma_move.html",)),
}


def _pages_with_python():
    return sorted(str(p.relative_to(DOCS)) for p in DOCS.rglob("*.md")
                  if doc_pages.python_blocks(p.read_text(encoding="utf-8")))


def test_every_page_with_python_is_run():
    missing = set(_pages_with_python()) - set(PAGES) - {"getting-started.md"}
    assert not missing, f"pages whose Python no test runs (add them to PAGES): {sorted(missing)}"


@pytest.mark.parametrize("name", sorted(PAGES))
def test_page_runs_and_shows_what_it_prints(name, tmp_path):
    page = PAGES[name]
    for module in page.requires:
        if importlib.util.find_spec(module) is None:
            pytest.skip(f"{name} needs {module}")
    run = doc_pages.run_page(DOCS / name, tmp_path, env=page.env)
    assert run.returncode == 0, f"{name} does not run as written:\n{run.stderr[-4000:]}"
    wrong = run.mismatches()
    assert not wrong, f"{name} shows what its code does not print:\n\n" + "\n\n".join(wrong)
    assert len(run.shown) >= page.shows, f"{name} shows {len(run.shown)} values, expected at least {page.shows}"
    for written in page.writes:
        assert (tmp_path / written).stat().st_size > 0, written


def test_the_matcher_tells_right_from_wrong():
    m = doc_pages.matches
    assert m("2.220446049250313e-16", "about 2e-16")
    assert not m("3e-15", "about 2e-16")
    assert m("0.0027392824578060097", "Yoshikawa's sqrt(det(J Jᵀ)), here about 0.0027")
    assert not m("0.0031", "about 0.0027")
    assert m("6", "6 joints") and not m("7", "6 joints") and not m("6", "60 joints")
    assert m("(1000, 8, 6) 2 8", "(1000, 8, 6) 2 8: up to 8") and not m("(1000, 8, 6) 2 8", "(1000, 8, 6) 2 80")
    assert m("left, elbow up", "'left, elbow up'")
    assert not m("left, elbow up", "'right, elbow down, no flip'")
    # several numbers: as many printed, each rounding to the shown one; 0 stands for round-off
    assert m("[0.8        0.66666667]", "about [0.8, 0.667] on the straight parts: ≤ qdmax")
    assert not m("[0.8        0.67666667]", "about [0.8, 0.667] on the straight parts")
    assert not m("[0.8        0.66666667 1.]", "about [0.8, 0.667]")
    assert m("0.5 [0. 0.] [0.   2.25 4.5 ]", "about 0.5, [0, 0], [0, 2.25, 4.5]")
    assert m("[0.00401778 1e-17]", "about [0.004, 0]") and not m("[0.00401778 0.1]", "about [0.004, 0]")
    assert m("-0.05000000000000002", "about -0.05 s: the start lies before t = 0")
    # several lines: line by line, whitespace not significant
    assert m("[[0.8 0.3]\n [0.8 0.3]]", "[[0.8  0.3]\n [0.8 0.3]]")
    assert not m("[[0.8 0.3]\n [0.8 0.31]]", "[[0.8 0.3]\n [0.8 0.3]]")
    assert not m("[[0.8 0.3]]", "[[0.8 0.3]\n [0.8 0.3]]")


def test_what_a_page_shows_is_found_in_its_code():
    text = ('```python\nimport warnings\nx = 2\nprint(x)  # 2\nprint(x + 1)  # three:\n# 3\nprint(x)\n'
            'for i in range(2):\n    print(i)\n# 0\n# 1\n'
            'y = x  # not shown: no print\n# nor this\nwarnings.warn("w", UserWarning)\n# UserWarning: w\n```\n\n'
            '```python\n>>> x * 2\n4\n>>> z = 5\n```\n\n```python\nprint(x)\n```\n\n```text\n2\n```\n')
    shown = doc_pages.shown_values(doc_pages.page_code(text))
    assert [(s.kind, s.text) for _, _, s in shown.values()] == [
        ("out", "2"), ("out", "3"), ("out", "0\n1"), ("warn", "UserWarning: w"), ("out", "4"), ("out", "2")]


def test_a_wrong_page_is_caught(tmp_path):
    page = tmp_path / "page.md"
    page.write_text('```python\nimport warnings\nprint(1 + 1)  # 3\nprint([1, 2])  # [1, 2]\n'
                    'warnings.warn("careful", UserWarning)\n# UserWarning: carefree\n```\n', encoding="utf-8")
    run = doc_pages.run_page(page, tmp_path)
    assert run.returncode == 0, run.stderr
    wrong = run.mismatches()
    assert len(wrong) == 2 and "shows\n3\nthe code printed\n2" in wrong[0] and "carefree" in wrong[1], wrong
