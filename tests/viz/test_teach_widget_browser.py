"""The notebook pendant's drag view, front end in headless Chromium: the widget's real ES module
(``_DRAG_ESM``, anywidget's ``render({model, el})``) runs in a host page written here that plays
anywidget's part (a model with get/set/on/off/save_changes holding the widget's own synced state,
taken from a real ``Scene.teach(wasm=...)``), frames the teach page, and both directions of its
postMessage link are checked against ``ik_analytic`` and the values set.

Chromium is driven in real time over the DevTools protocol on a pipe (``--remote-debugging-pipe``),
not with ``--virtual-time-budget``: with a virtual-time budget, a message posted between the host
and its framed page made the run time grow with the budget. Every wait has a hard timeout."""
import json
import os
import select
import signal
import subprocess
import tempfile
import time

import numpy as np
import pytest

import robokit
from robokit._optional import available
from tests.viz.test_teach import CHROMIUM

TOL = 1e-9
DEADLINE = 60.0  # s, the whole browser run (a few seconds when idle)

# The host: anywidget's part. The model keeps the widget's synced state; set() fires "change:KEY"
# when the value changes (as anywidget's Backbone model does, whoever sets it); save_changes()
# records what would go to Python. The ESM is imported from a Blob URL and rendered into #widget.
_HOST = """<!DOCTYPE html><html><body><div id="widget"></div>
<script>window.onerror = (m) => { window.RKOut = JSON.stringify({ error: "host: " + m }); };</script>
<script type="module">
const STATE = __STATE__, ESM = __ESM__;
const handlers = {}, saved = [];
const model = {
  get(k) { return STATE[k]; },
  set(k, v) {
    if (JSON.stringify(STATE[k]) === JSON.stringify(v)) { return; }
    STATE[k] = v;
    (handlers["change:" + k] || []).slice().forEach((f) => f());
  },
  on(name, f) { (handlers[name] = handlers[name] || []).push(f); },
  off(name, f) { handlers[name] = (handlers[name] || []).filter((g) => g !== f); },
  save_changes() { saved.push(JSON.parse(JSON.stringify(STATE.q))); },
};
const url = URL.createObjectURL(new Blob([ESM], { type: "text/javascript" }));
const widget = (await import(url)).default;
window.RKHost = { model, saved, cleanup: widget.render({ model, el: document.getElementById("widget") }) };
model.set("q", __EARLY_Q__);  // a q from Python while the framed page is still loading
</script><script>__STEPS__</script></body></html>
"""

# The steps, run in the host once the framed page is up (the result, or the error, in window.RKOut): (1) a target set in the page through its
# drag entry point; wait until the host's model has a new q (what Python would receive); (2) the
# host sets q as Python's set_q does; wait until the page's rk-q shows it.
_STEPS = """
(async () => {
  const until = async (f, what) => {
    const t0 = Date.now();
    while (!f()) {
      if (Date.now() - t0 > 20000) { throw new Error("timed out waiting for " + what); }
      await new Promise((r) => setTimeout(r, 50));
    }
  };
  await until(() => window.RKHost, "the widget's render");
  const frame = document.querySelector("#widget iframe");
  const page = () => frame.contentWindow, el = (id) => page().document.getElementById(id);
  await until(() => page() && page().rkDrag && el("rk-q") && el("rk-q").dataset.q, "the framed page");
  const same = (text, q) => text.split(",").every((v, i) => Number(v) === q[i]);
  await until(() => same(el("rk-q").dataset.q, RKHost.model.get("q")), "the page at the model's q");
  await new Promise((r) => setTimeout(r, 300));  // any message the page's opening would (wrongly) send
  const out = { height: frame.style.height, q0: el("rk-q").dataset.q, savedAtStart: RKHost.saved.length };
  page().rkDrag(__TARGET__);
  await until(() => RKHost.saved.length > out.savedAtStart, "a q from the page in the host's model");
  await new Promise((r) => setTimeout(r, 300));  // any further message the link would (wrongly) send
  out.ik = Object.assign({}, el("rk-ik").dataset);
  out.pageQ1 = el("rk-q").dataset.q;
  out.saved1 = RKHost.saved.slice();
  out.model1 = RKHost.model.get("q");
  RKHost.model.set("q", __SET_Q__);
  await until(() => el("rk-q").dataset.q !== out.pageQ1, "the host's q in the page");
  await new Promise((r) => setTimeout(r, 300));
  out.pageQ2 = el("rk-q").dataset.q;
  out.saved2 = RKHost.saved.slice();
  out.model2 = RKHost.model.get("q");
  return JSON.stringify(out);
})().then((text) => { window.RKOut = text; }, (e) => { window.RKOut = JSON.stringify({ error: String(e) }); });
"""


class _Pipe:
    """Chromium's DevTools protocol over ``--remote-debugging-pipe`` (fd 3 in, fd 4 out,
    NUL-terminated JSON), with a deadline on every read."""

    def __init__(self, url: str, profile: str):
        self.to_r, self.to_w = os.pipe()      # we write, Chromium reads (its fd 3)
        self.from_r, self.from_w = os.pipe()  # Chromium writes (its fd 4), we read
        self.proc = subprocess.Popen(
            [CHROMIUM, "--headless", "--no-sandbox", "--disable-gpu", "--enable-unsafe-swiftshader",
             "--use-angle=swiftshader", "--disable-quic", "--no-first-run", "--disable-background-networking",
             "--disable-component-update", "--disable-sync", f"--user-data-dir={profile}",
             "--window-size=1200,900", "--allow-file-access-from-files", "--remote-debugging-pipe", url],
            stdin=subprocess.DEVNULL, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL,
            pass_fds=(3, 4), preexec_fn=self._fds, start_new_session=True)
        os.close(self.to_r)
        os.close(self.from_w)
        self.buf, self.n = b"", 0

    def _fds(self) -> None:  # in the child: our pipe ends at fds 3 and 4
        os.dup2(self.to_r, 3)
        os.dup2(self.from_w, 4)

    def call(self, method: str, deadline: float, session: str | None = None, **params):
        self.n += 1
        msg = {"id": self.n, "method": method, "params": params}
        if session:
            msg["sessionId"] = session
        os.write(self.to_w, json.dumps(msg).encode() + b"\0")
        while True:
            while b"\0" not in self.buf:
                left = deadline - time.monotonic()
                if left <= 0 or not select.select([self.from_r], [], [], left)[0]:
                    raise TimeoutError(f"Chromium did not answer {method} in time")
                chunk = os.read(self.from_r, 1 << 20)
                if not chunk:
                    raise RuntimeError(f"Chromium closed the pipe during {method}")
                self.buf += chunk
            raw, self.buf = self.buf.split(b"\0", 1)
            reply = json.loads(raw)
            if reply.get("id") == self.n:
                if "error" in reply:
                    raise RuntimeError(f"{method}: {reply['error']}")
                return reply["result"]

    def close(self) -> None:
        # Browser.close lets Chromium flush and leave its profile; its helper processes (renderer,
        # GPU, crashpad) are in its own session and are killed with it if it does not exit in time,
        # so that none of them still writes into the profile while the directory is removed.
        try:
            self.call("Browser.close", time.monotonic() + 5)
        except (TimeoutError, RuntimeError, OSError):
            pass
        try:
            self.proc.wait(timeout=10)
        except subprocess.TimeoutExpired:
            pass
        try:
            os.killpg(self.proc.pid, signal.SIGKILL)
        except ProcessLookupError:
            pass
        self.proc.wait(timeout=10)
        os.close(self.to_w)
        os.close(self.from_r)


def _run_host(host_path) -> dict:
    deadline = time.monotonic() + DEADLINE
    with tempfile.TemporaryDirectory(ignore_cleanup_errors=True) as profile:
        cdp = _Pipe(host_path.resolve().as_uri(), profile)
        try:
            while True:  # the page target of the URL given on the command line
                pages = [t for t in cdp.call("Target.getTargets", deadline)["targetInfos"] if t["type"] == "page"]
                if pages:
                    break
                time.sleep(0.1)
            session = cdp.call("Target.attachToTarget", deadline, targetId=pages[0]["targetId"], flatten=True)["sessionId"]
            while True:  # poll the host's result (a navigation may replace the context meanwhile)
                try:
                    r = cdp.call("Runtime.evaluate", deadline, session=session, expression="window.RKOut || ''",
                                 returnByValue=True)
                except RuntimeError as e:
                    if "context" not in str(e):
                        raise
                    r = {}
                text = r.get("result", {}).get("value")
                if text:
                    break
                time.sleep(0.1)
        finally:
            cdp.close()
    got = json.loads(text)
    assert "error" not in got, got["error"]
    return got


def _js(value) -> str:
    """A JSON literal safe inside a <script> element (the page holds its own </script> tags)."""
    return json.dumps(value).replace("</", "<\\/")


def _nums(s: str) -> np.ndarray:
    return np.array([float(x) for x in s.split(",")])


@pytest.mark.skipif(CHROMIUM is None, reason="chromium not installed (apt-get install chromium)")
def test_drag_view_front_end_links_page_and_model_both_ways(tmp_path):
    """The widget's ES module, rendered by a host that plays anywidget, with the state of a real
    ``Scene.teach(wasm=...)`` (the PUMA page with its module, q, height), whose q was set after
    the page was written (``set_q`` before the pendant is shown) and again while the framed page
    loads: the page opens at the model's latest q and sends Python nothing back; then


    1. a target set in the framed page (``rkDrag(T)``, the gizmo's entry point) reaches the host
       model's q, saved once (what Python receives), equal to ``ik_analytic``'s solution nearest the
       starting q (the page's rule) to 1e-9, which is the q that generated T; fed to the pendant
       as anywidget's comm would, it moves the live scene there;
    2. the host setting q (as ``set_q`` does) moves the page's q (its ``rk-q``) to exactly that
       value, and nothing echoes back to Python."""
    pytest.importorskip("ipywidgets")
    pytest.importorskip("anywidget")
    if not available("ziglang"):
        pytest.skip("ziglang (the viz extra) not installed")
    from robokit.codegen.wasm import wasm_module
    from robokit.viz import Scene

    robot = robokit.load("puma560")
    q_page = np.array([0.1, 0.6, -0.5, 0.3, 0.4, 0.1])
    q_start = np.array([0.2, 0.4, -0.3, 0.5, 0.6, -0.2])
    q_goal = q_start + np.array([0.05, -0.04, 0.03, -0.06, 0.05, 0.04])  # T's own branch: the nearest
    q_set = [0.1, 0.3, -0.2, 0.4, 0.5, -0.1]
    T = robot.frame_pose(q_goal)
    with Scene(robot) as scene:
        pendant = scene.teach(q_page, wasm=wasm_module(robot).wasm)
        pendant.set_q(q_page + 0.1)  # before the view is shown (the page was written at q_page)
        view = pendant.drag
        state = {k: getattr(view, k) for k in ("page", "q", "height")}  # the synced state anywidget sends
        host = tmp_path / "host.html"
        steps = _STEPS.replace("__TARGET__", json.dumps(T.ravel().tolist())).replace("__SET_Q__", json.dumps(q_set))
        host.write_text(_HOST.replace("__EARLY_Q__", json.dumps(q_start.tolist())).replace("__STEPS__", steps)
                        .replace("__STATE__", _js(state)).replace("__ESM__", _js(view._esm)), encoding="utf-8")
        got = _run_host(host)

        assert got["height"] == f"{state['height']}px"
        # the page, written at q_page, opened at the model's latest q and sent Python nothing
        np.testing.assert_array_equal(_nums(got["q0"]), q_start)
        assert got["savedAtStart"] == 0

        # (1) page -> host model -> Python
        ref = robokit.ik_analytic(robot, T)
        k = int(np.argmin([np.sum((r.q - q_start) ** 2) for r in ref]))
        assert got["ik"]["count"] == str(len(ref)) and got["ik"]["chosen"] == str(k)
        np.testing.assert_allclose(ref[k].q, q_goal, rtol=0, atol=TOL)
        assert len(got["saved1"]) == 1  # one drag, one message to Python
        np.testing.assert_allclose(got["saved1"][0], ref[k].q, rtol=0, atol=TOL)
        assert got["model1"] == got["saved1"][0]
        np.testing.assert_array_equal(_nums(got["pageQ1"]), got["model1"])
        view.q = got["model1"]  # as anywidget's comm sets the trait
        np.testing.assert_allclose(scene.q, ref[k].q, rtol=0, atol=TOL)
        np.testing.assert_allclose(pendant.readouts["xyz"], T[:3, 3], rtol=0, atol=TOL)

        # (2) host model (Python's set_q) -> page, with no echo
        np.testing.assert_array_equal(_nums(got["pageQ2"]), q_set)
        assert got["model2"] == q_set
        assert got["saved2"] == got["saved1"]
