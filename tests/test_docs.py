"""The documentation site: `mkdocs build --strict` passes with no warning, and no file in the
repository points readers at a contract file that does not ship with it."""
import os
import re
import subprocess
import sys
from html.parser import HTMLParser
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]

# Places a user reads; none of them may send the reader to a file outside the repository.
SCANNED = ["robokit", "docs", "notebooks", "tests", "README.md"]
FORBIDDEN = re.compile(r"API\.md|\.\./shared")
TEXT_SUFFIXES = {".py", ".md", ".ipynb", ".yml", ".yaml", ".txt", ".toml", ".cfg", ".js", ".css", ".html"}


def _scanned_files():
    for entry in SCANNED:
        path = ROOT / entry
        if path.is_file():
            yield path
        elif path.is_dir():
            for p in sorted(path.rglob("*")):
                if p.is_file() and p.suffix in TEXT_SUFFIXES and "__pycache__" not in p.parts:
                    yield p


def test_no_file_cites_the_outside_contract():
    this_file = Path(__file__).resolve()
    offenders = []
    for p in _scanned_files():
        if p.resolve() == this_file:  # the pattern itself is written here
            continue
        text = p.read_text(encoding="utf-8", errors="replace")
        for lineno, line in enumerate(text.splitlines(), 1):
            if FORBIDDEN.search(line):
                offenders.append(f"{p.relative_to(ROOT)}:{lineno}: {line.strip()[:100]}")
    assert not offenders, "files cite a document that is not in the repository:\n" + "\n".join(offenders)


def test_forbidden_pattern_catches_what_it_should():
    # The scan above is only worth something if its pattern matches the citations it hunts.
    assert FORBIDDEN.search("see API" + ".md §2")
    assert FORBIDDEN.search("../" + "shared/DESIGN.md")
    assert not FORBIDDEN.search("see the DH file format page of the documentation")


def test_every_nav_page_exists():
    yaml = pytest.importorskip("yaml")
    config = yaml.safe_load((ROOT / "mkdocs.yml").read_text(encoding="utf-8"))

    def pages(node):
        if isinstance(node, str):
            yield node
        elif isinstance(node, list):
            for item in node:
                yield from pages(item)
        elif isinstance(node, dict):
            for value in node.values():
                yield from pages(value)

    missing = [p for p in pages(config["nav"]) if not (ROOT / "docs" / p).is_file()]
    assert not missing, f"nav entries without a page: {missing}"


def test_mkdocs_build_strict(tmp_path):
    pytest.importorskip("mkdocs", reason="mkdocs is not installed (pip install '.[docs]')")
    pytest.importorskip("mkdocstrings", reason="mkdocstrings is not installed (pip install '.[docs]')")
    pytest.importorskip("material", reason="mkdocs-material is not installed (pip install '.[docs]')")
    env = dict(os.environ)
    # mkdocstrings must document this checkout's robokit, whatever is installed.
    env["PYTHONPATH"] = str(ROOT) + (os.pathsep + env["PYTHONPATH"] if env.get("PYTHONPATH") else "")
    env["NO_MKDOCS_2_WARNING"] = "1"
    proc = subprocess.run(
        [sys.executable, "-m", "mkdocs", "build", "--strict", "--site-dir", str(tmp_path / "site")],
        cwd=ROOT, env=env, capture_output=True, text=True, timeout=600,
    )
    log = proc.stdout + proc.stderr
    warnings = [line for line in log.splitlines() if line.startswith(("WARNING", "ERROR"))]
    assert proc.returncode == 0 and not warnings, f"mkdocs build --strict failed:\n{log[-4000:]}"
    assert (tmp_path / "site" / "index.html").is_file()
    # The API reference really was generated from the code (not an empty page).
    reference = (tmp_path / "site" / "reference" / "spatial" / "index.html").read_text(encoding="utf-8")
    assert "matrix_log_6" in reference
    _check_formulas_and_assets(tmp_path / "site")


class _TextOutsideMath(HTMLParser):
    """Collects the text of a page that is outside ``arithmatex`` elements, code and scripts."""

    SKIP = {"code", "pre", "script", "style"}
    VOID = {"br", "img", "hr", "input", "meta", "link", "wbr", "source", "area", "base", "col", "embed", "param",
            "track"}

    def __init__(self) -> None:
        super().__init__(convert_charrefs=True)
        self.stack: list[bool] = []  # per open element: is it (inside) math or code?
        self.text: list[str] = []

    def handle_starttag(self, tag, attrs):
        if tag in self.VOID:
            return
        classes = (dict(attrs).get("class") or "").split()
        inside = bool(self.stack and self.stack[-1])
        self.stack.append(inside or tag in self.SKIP or "arithmatex" in classes)

    def handle_endtag(self, tag):
        if tag not in self.VOID and self.stack:
            self.stack.pop()

    def handle_data(self, data):
        if not (self.stack and self.stack[-1]):
            self.text.append(data)


# TeX outside math: a display/inline delimiter, or a control word MathJax would have typeset
_TEX = (r"\\\[|\\\(|\\(?:begin|end|frac|mathrm|mathbf|operatorname|dot|ddot|hat|sum|theta|omega|alpha|"
        r"beta|gamma|pi|cos|sin|big|qquad|quad|left|right|cdot|times|sqrt)\b")


def _check_formulas_and_assets(site):
    """Every formula of the built site sits in an ``arithmatex`` element (so MathJax typesets it)
    and MathJax comes from the site itself, not a CDN (so formulas render offline)."""
    bad = []
    for page in sorted(site.rglob("*.html")):
        if "reference" in page.parts:  # docstrings: code-like text, formulas not typeset there
            continue
        html = page.read_text(encoding="utf-8")
        assert "cdn.jsdelivr" not in html and "mathjax@" not in html, f"{page}: MathJax from a CDN"
        parser = _TextOutsideMath()
        parser.feed(html)
        stray = re.findall(_TEX, "".join(parser.text))
        if stray:
            bad.append(f"{page.relative_to(site)}: {len(stray)} formula fragment(s) outside arithmatex, e.g. {stray[0]}")
    assert not bad, "\n".join(bad)
    assert (site / "javascripts" / "mathjax" / "tex-chtml.js").stat().st_size > 500_000
    assert list((site / "javascripts" / "mathjax" / "output" / "chtml" / "fonts" / "woff-v2").glob("*.woff"))


def test_formula_check_catches_a_stray_formula(tmp_path):
    page = tmp_path / "course" / "x.html"
    page.parent.mkdir(parents=True)
    (tmp_path / "javascripts" / "mathjax" / "output" / "chtml" / "fonts" / "woff-v2").mkdir(parents=True)
    (tmp_path / "javascripts" / "mathjax" / "tex-chtml.js").write_bytes(b"x" * 600_000)
    (tmp_path / "javascripts" / "mathjax" / "output" / "chtml" / "fonts" / "woff-v2" / "a.woff").write_bytes(b"x")
    page.write_text('<p><span class="arithmatex">\\(x\\)</span> fine</p>')
    _check_formulas_and_assets(tmp_path)
    page.write_text("<p>\\[\nc_2 = \\frac{1}{2}\n\\]</p>")  # a display block MathJax never sees
    with pytest.raises(AssertionError, match="outside arithmatex"):
        _check_formulas_and_assets(tmp_path)
