"""The documentation site: `mkdocs build --strict` passes with no warning, and no file in the
repository points readers at a contract file that does not ship with it."""
import json
import os
import re
import shutil
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


@pytest.fixture(scope="module")
def built_site(tmp_path_factory):
    """The site, built once with ``mkdocs build --strict`` (skipped without the docs extra)."""
    pytest.importorskip("mkdocs", reason="mkdocs is not installed (pip install '.[docs]')")
    pytest.importorskip("mkdocstrings", reason="mkdocstrings is not installed (pip install '.[docs]')")
    pytest.importorskip("material", reason="mkdocs-material is not installed (pip install '.[docs]')")
    site = tmp_path_factory.mktemp("docs") / "site"
    env = dict(os.environ)
    # mkdocstrings must document this checkout's robokit, whatever is installed.
    env["PYTHONPATH"] = str(ROOT) + (os.pathsep + env["PYTHONPATH"] if env.get("PYTHONPATH") else "")
    env["NO_MKDOCS_2_WARNING"] = "1"
    proc = subprocess.run(
        [sys.executable, "-m", "mkdocs", "build", "--strict", "--site-dir", str(site)],
        cwd=ROOT, env=env, capture_output=True, text=True, timeout=600,
    )
    return site, proc.returncode, proc.stdout + proc.stderr


def test_mkdocs_build_strict(built_site):
    site, returncode, log = built_site
    warnings = [line for line in log.splitlines() if line.startswith(("WARNING", "ERROR"))]
    assert returncode == 0 and not warnings, f"mkdocs build --strict failed:\n{log[-4000:]}"
    assert (site / "index.html").is_file()
    # The API reference really was generated from the code (not an empty page).
    reference = (site / "reference" / "spatial" / "index.html").read_text(encoding="utf-8")
    assert "matrix_log_6" in reference
    _check_formulas_and_assets(site)


CHROMIUM = shutil.which("chromium") or shutil.which("chromium-browser")

# Added to a copy of a built page: once MathJax has typeset it, the first display formula's box (CSS
# pixels, the window's top-left origin) and the device pixel ratio go into the title, which --dump-dom
# shows. The screenshot run loads the same copy at the same window size: the same layout.
_BOX_SCRIPT = """<script>
window.addEventListener("load", function () {
  MathJax.startup.promise.then(function () {
    var el = document.querySelector(".arithmatex mjx-container[display='true']");
    var r = el.getBoundingClientRect();
    document.title = "RKBOX " + JSON.stringify([r.left, r.top, r.width, r.height, window.devicePixelRatio,
                                                el.getAttribute("jax")]);
  });
});
</script>"""


def _chromium(args, profile):
    return subprocess.run(
        [CHROMIUM, "--headless", "--no-sandbox", "--disable-gpu", "--enable-unsafe-swiftshader",
         "--use-angle=swiftshader", "--disable-quic", "--no-first-run", "--disable-background-networking",
         "--disable-component-update", "--disable-sync", f"--user-data-dir={profile}", "--window-size=1000,1400",
         "--hide-scrollbars", "--virtual-time-budget=20000", *args],
        capture_output=True, text=True, timeout=180)


def _dark_pixels(png, box):
    """How many pixels of the screenshot, inside ``box`` (left, top, width, height in device
    pixels), are dark (luminance below half): glyphs on the page's white background."""
    Image = pytest.importorskip("PIL.Image", reason="Pillow is not installed (it comes with matplotlib)")
    img = Image.open(png).convert("L")
    left, top, width, height = (int(round(v)) for v in box)
    region = img.crop((left, top, left + width, top + height))
    return sum(region.histogram()[:128]), width * height


@pytest.mark.skipif(CHROMIUM is None, reason="Debian's chromium is not installed (.ci/run installs it)")
def test_formulas_are_drawn_in_chromium(built_site, tmp_path):
    """Issue 40: MathJax typeset the formulas (``mjx-container`` present) but Chromium drew them
    blank, from ``file://`` and over HTTP (the CHTML fonts were never fetched). A built page with a
    display formula, screenshotted in headless Chromium both ways: the formula's box must hold dark
    pixels — at least 2 % of its area, where a blank box has none."""
    site, returncode, log = built_site
    assert returncode == 0, log[-2000:]
    page = site / "course" / "dynamics" / "index.html"
    copy = page.with_name("rk-pixels.html")
    copy.write_text(page.read_text(encoding="utf-8").replace("</body>", _BOX_SCRIPT + "</body>"), encoding="utf-8")

    import functools
    import http.server
    import threading

    class Quiet(http.server.SimpleHTTPRequestHandler):
        def log_message(self, *args):
            pass

    server = http.server.ThreadingHTTPServer(("127.0.0.1", 0), functools.partial(Quiet, directory=str(site)))
    threading.Thread(target=server.serve_forever, daemon=True).start()
    try:
        urls = {"file": copy.as_uri(),
                "http": f"http://127.0.0.1:{server.server_address[1]}/course/dynamics/rk-pixels.html"}
        for how, url in urls.items():
            dom = _chromium(["--dump-dom", url], tmp_path / f"{how}-dom")
            found = re.search(r"<title>RKBOX (\[.*?\])</title>", dom.stdout)
            assert found, f"{how}: MathJax did not finish typesetting: {dom.stderr[-1500:]}"
            left, top, width, height, ratio, jax = json.loads(found.group(1))
            assert width > 0 and height > 0 and 0 <= top and top + height < 1400, found.group(1)
            png = tmp_path / f"{how}.png"  # kept in pytest's temporary folder: look at it
            shot = _chromium([f"--screenshot={png}", url], tmp_path / f"{how}-shot")
            assert png.is_file(), shot.stderr[-1500:]
            dark, area = _dark_pixels(png, [v * ratio for v in (left, top, width, height)])
            assert dark >= 0.02 * area, f"{how}: the {jax} formula's box is blank ({dark} dark pixels of {area})"
    finally:
        server.shutdown()
        server.server_close()


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
    assert (site / "javascripts" / "mathjax" / "tex-svg.js").stat().st_size > 500_000


def test_formula_check_catches_a_stray_formula(tmp_path):
    page = tmp_path / "course" / "x.html"
    page.parent.mkdir(parents=True)
    (tmp_path / "javascripts" / "mathjax").mkdir(parents=True)
    (tmp_path / "javascripts" / "mathjax" / "tex-svg.js").write_bytes(b"x" * 600_000)
    page.write_text('<p><span class="arithmatex">\\(x\\)</span> fine</p>')
    _check_formulas_and_assets(tmp_path)
    page.write_text("<p>\\[\nc_2 = \\frac{1}{2}\n\\]</p>")  # a display block MathJax never sees
    with pytest.raises(AssertionError, match="outside arithmatex"):
        _check_formulas_and_assets(tmp_path)
