"""Viewer pages: a robot/joint name never becomes a path, and the teach page survives any name and
any URL fragment and says what it ignored."""
import json
import os
import shutil
import subprocess
import tempfile
from html.parser import HTMLParser
from pathlib import Path
from xml.sax.saxutils import quoteattr

import numpy as np
import pytest

import hardening_support as hs
from robokit._names import MAX_STEM, safe_stem


CHROMIUM = shutil.which("chromium") or ("/usr/bin/chromium" if os.path.exists("/usr/bin/chromium") else None)


needs_chromium = pytest.mark.skipif(CHROMIUM is None, reason="chromium not installed (apt-get install chromium)")


#: Names that end HTML comments/scripts, climb folders, or are not file names at all.
HOSTILE = ["../../X", "a/../../b", "/etc/passwd", "..", ".", "", "-rf", "x<!--</script><script>alert(1)</script>",
           "\u2028\u2029", "C:\\Windows\\x", "名前/../ロボット", "a\x00b", "~/x", "$HOME", "x" * 5000, "....//....//y"]


@pytest.mark.parametrize("name", HOSTILE, ids=range(len(HOSTILE)))
def test_safe_stem_is_one_plain_component(name, tmp_path):
    stem = safe_stem(name)
    assert 1 <= len(stem) <= MAX_STEM
    assert ".." not in stem and "/" not in stem and "\\" not in stem and not stem.startswith((".", "-"))
    assert all(c.isascii() and (c.isalnum() or c in "_.+-") for c in stem)
    p = tmp_path / f"{stem}.html"
    assert p.resolve().parent == tmp_path.resolve()  # a file of this folder, nothing else
    p.write_text("ok")


def _hostile_urdf(write, robot_name, joint_name="shoulder"):
    text = hs.pendulum_urdf().replace('name="pendulum"', "name=" + quoteattr(robot_name))
    return write("hostile.urdf", text.replace('name="shoulder"', "name=" + quoteattr(joint_name)))


def test_notebook_page_stays_in_robokit_views(tmp_path, monkeypatch):
    pytest.importorskip("IPython")
    import robokit
    from robokit.description.dh import DHLink, DHTable
    from robokit.viz import Scene

    work = tmp_path / "a" / "b"
    work.mkdir(parents=True)
    monkeypatch.chdir(work)
    robot = robokit.load(DHTable("../../X", "standard", (DHLink(a=0.3), DHLink(a=0.2))))
    with Scene(robot) as scene:
        frame = scene.notebook()
    written = [p for p in tmp_path.rglob("*") if p.is_file()]
    assert len(written) == 1 and written[0].parent == work / "robokit_views", written
    assert Path(frame.src).resolve() == written[0].resolve()


def test_teach_without_output_stays_in_the_temporary_folder(tmp_path, write):
    src = _hostile_urdf(write, "pend/../../../../escaped")
    tmp = tmp_path / "tmp" / "deep"
    tmp.mkdir(parents=True)
    before = {p for p in tmp_path.rglob("*")}
    run = hs.run_cli("teach", src, cwd=tmp_path, env=hs.subprocess_env(TMPDIR=str(tmp), BROWSER="true"))
    assert run.rc == 0, run.err
    new = [p for p in tmp_path.rglob("*") if p not in before and p.is_file()]
    assert len(new) == 1 and new[0].parent == tmp and new[0].name.startswith("robokit-teach-pend_escaped"), new
    assert not list(Path("/").glob("escaped*"))


class _Page(HTMLParser):
    """Script elements (type, text) and the text of the elements with an id."""

    def __init__(self):
        super().__init__()
        self.scripts, self.text, self.attrs, self._stack = [], {}, {}, []

    def handle_starttag(self, tag, attrs):
        a = dict(attrs)
        if tag == "script":
            self.scripts.append([a.get("type"), ""])
        self._stack.append((tag, a.get("id")))
        if a.get("id"):
            self.attrs[a["id"]] = a
            self.text.setdefault(a["id"], "")

    def handle_endtag(self, tag):
        while self._stack:
            t, _ = self._stack.pop()
            if t == tag:
                break

    def handle_data(self, data):
        if self._stack and self._stack[-1][0] == "script" and self.scripts:
            self.scripts[-1][1] += data
        for _, i in self._stack:
            if i:
                self.text[i] = self.text.get(i, "") + data


NAME = "x<!--</script><script>alert(1)</script>&amp;]]>"


def test_teach_page_json_survives_any_name():
    """The embedded JSON block holds no '<', '>' or '&' and parses back to the exact names."""
    import robokit
    from robokit.description.dh import DHLink, DHTable
    from tests.viz.test_teach import teach_page

    name = NAME + "\u2028\u2029 -->"
    page = teach_page(robokit.load(DHTable(name, "standard", (DHLink(a=0.3), DHLink(a=0.2)))))
    p = _Page()
    p.feed(page)
    # meshcat, the robot's data, the scene, teach_math.js, the module (base64), teach_wasm.js, teach.js
    assert [t for t, _ in p.scripts] == [None, "application/json", None, None, "application/octet-stream", None, None]
    block = p.scripts[1][1]
    assert not set("<>&\u2028\u2029") & set(block)
    assert json.loads(block)["name"] == name
    assert not set("<>&\u2028\u2029") & set(p.scripts[2][1])  # the scene: base64, or JSON commands escaped alike
    assert page.count("</script>") == 7  # no element ended early, none injected


def run_page(path: Path, fragment: str) -> _Page:
    with tempfile.TemporaryDirectory(ignore_cleanup_errors=True) as profile:
        out = subprocess.run(
            [CHROMIUM, "--headless", "--no-sandbox", "--disable-gpu", "--enable-unsafe-swiftshader",
             "--use-angle=swiftshader", "--disable-quic", "--no-first-run", "--disable-background-networking",
             "--disable-component-update", "--disable-sync", f"--user-data-dir={profile}",
             "--virtual-time-budget=15000", "--dump-dom", path.resolve().as_uri() + fragment],
            capture_output=True, text=True, timeout=180)
    assert out.returncode == 0, out.stderr[-2000:]
    p = _Page()
    p.feed(out.stdout)
    return p


@pytest.fixture(scope="module")
def hostile_teach_page(tmp_path_factory):
    """``robokit teach`` (a subprocess) of the pendulum with a robot and a joint named to end the
    script and open a comment: written once, opened by each fragment test below (the page does not
    depend on the fragment; the command compiles the robot's WebAssembly, seconds)."""
    folder = tmp_path_factory.mktemp("hostile_teach")

    def write(name, text):
        (folder / name).write_text(text, encoding="utf-8")
        return folder / name

    src = _hostile_urdf(write, NAME, "j<!--</script>")
    page = folder / "teach.html"
    run = hs.run_cli("teach", src, "-o", page)
    assert run.rc == 0, run.err
    return page


@needs_chromium
@pytest.mark.parametrize("fragment, says", [
    ("#q=%E0%A4%A", "not valid percent-encoding; ignored"),
    ("#q=0.1,NaN", "expected 1 finite numbers"),  # NaN and the wrong count (more cases run under Node)
])
def test_teach_page_survives_hostile_name_and_fragment(fragment, says, hostile_teach_page):
    """A robot and joint named to end the script and open a comment, and a bad #q= fragment:
    the page's script runs (readouts present), shows the names as text and keeps saying what
    it ignored."""
    p = run_page(hostile_teach_page, fragment)
    assert "data-t" in p.attrs.get("rk-pose", {}), "the page's script did not run"
    T = np.array([float(x) for x in p.attrs["rk-pose"]["data-t"].split(",")]).reshape(4, 4)
    assert np.allclose(T[:3, 3], [hs.PEND_L, 0, 0], atol=1e-12)  # q = 0: the closed form
    assert p.text["rk-title"] == NAME
    assert says in p.text["rk-msg"], p.text["rk-msg"]
    assert "j<!--</script>" in p.text["rk-sliders"]
