"""The teach page's closed-form IK: ``#q=...&T=...`` solved by the robot's generated C compiled to
WebAssembly (robokit.codegen.wasm) in headless Chromium, against ``robokit.ik_analytic``; its tool
pose and Jacobian (from the module) against Pinocchio."""
import json

import numpy as np
import pytest

import robokit
from robokit._optional import available
from robokit.viz.teach import teach_html
from tests.viz.test_teach import needs_chromium, nums, run_harness, run_page, teach_page

needs_zig = pytest.mark.skipif(not available("ziglang"), reason="ziglang (the viz extra) not installed")
TOL = 1e-9


def _fmt(x):
    return ",".join(repr(float(v)) for v in np.ravel(x))


#: the arms of #44's "Done when": PUMA, UR5, a general 6R arm (JACO2's DH table), a modified-DH arm
#: (the PUMA in Craig's table) and a calibrated arm (the PUMA with every placement perturbed); and the
#: course's planar arms (the planar closed form: one solution for two joints, two for three)
ARMS = ["puma560", "ur5", "jaco2_6n", "puma_craig", "puma_calibrated", "twolink", "rrr"]


@pytest.fixture(scope="module")
def pages(tmp_path_factory):
    """One page per arm, written on first use (with its module; zig caches the compile)."""
    from tests.viz.test_wasm import _load

    out = {}
    folder = tmp_path_factory.mktemp("teach-ik")

    def get(name):
        if name not in out:
            robot = _load(name)
            path = folder / f"{name}.html"
            path.write_text(teach_page(robot), encoding="utf-8")
            out[name] = (robot, path)
        return out[name]

    return get


# Drives the page in an iframe through its URL fragment: for each case, location.hash =
# "#q=START&T=TARGET" (start at q, then go to T, as a user's link would); after the page's own
# hashchange handler has run, records what the page wrote.
_TARGETS_JS = """
var got = [], i = 0;
function frag(c) { return "#q=" + c.q.map(String).join(",") + "&T=" + c.T.map(String).join(","); }
function run() {
  var f = document.getElementById("page"), w = f.contentWindow, d = w.document;
  if (!w.RKTeach || !d.getElementById("rk-q") || !d.getElementById("rk-q").dataset.q) { setTimeout(run, 100); return; }
  w.addEventListener("hashchange", function () {
    var ik = d.getElementById("rk-ik").dataset;
    got.push({ status: ik.status, count: ik.count, solutions: ik.solutions, labels: ik.labels, within: ik.within,
               chosen: ik.chosen, q: d.getElementById("rk-q").dataset.q, t: d.getElementById("rk-pose").dataset.t,
               source: d.getElementById("rk-pose").dataset.source, j: d.getElementById("rk-jacobian").dataset.j });
    i++;
    if (i < CASES.length) { setTimeout(function () { w.location.hash = frag(CASES[i]); }, 0); }
    else { document.getElementById("out").textContent = JSON.stringify(got); }
  });
  w.location.hash = frag(CASES[0]);
}
window.addEventListener("load", function () { setTimeout(run, 100); });
"""


@needs_chromium
@needs_zig
@pytest.mark.parametrize("name", ARMS)
def test_fragment_target_solves_every_branch_and_moves_to_the_nearest(pages, name, tmp_path):
    """10 targets #T= = FK of a random q (from a random start q, #q=...&T=...): data-count is
    ik_analytic's count, every solution equals Python's to 1e-9 (labels and limit flags too), the
    generating q is among them, data-chosen is the one nearest the start, and the page's q, pose
    and Jacobian (from the module) are Pinocchio's there. One browser run per arm."""
    from tests.viz.test_wasm import random_qs

    robot, path = pages(name)
    lo, hi = np.array(robot.qlim, dtype=float).T
    lo, hi = np.where(np.isfinite(lo), lo, -np.pi), np.where(np.isfinite(hi), hi, np.pi)
    seed = ARMS.index(name) + 3
    # the calibrated PUMA: |q5| >= 0.1 (see tests.viz.test_wasm.random_qs: a defect of ik_analytic there)
    q_gens = random_qs(robot, 10, seed, wrist_clear=name == "puma_calibrated")
    q_starts = random_qs(robot, 10, seed + 100)
    Ts = [robot.frame_pose(q) for q in q_gens]
    cases = [{"q": qs.tolist(), "T": T.ravel().tolist()} for qs, T in zip(q_starts, Ts)]
    harness = tmp_path / "targets.html"
    harness.write_text('<!DOCTYPE html><html><body><iframe id="page" width="1000" height="700" src="'
                       + path.resolve().as_uri() + '"></iframe><pre id="out"></pre><script>var CASES = '
                       + json.dumps(cases) + ";" + _TARGETS_JS + "</script></body></html>", encoding="utf-8")
    got = run_harness(harness)
    assert len(got) == 10
    for q_gen, q_start, T, ik in zip(q_gens, q_starts, Ts, got):
        assert ik["source"] == "wasm"
        ref = robokit.ik_analytic(robot, T)
        assert ik["status"] == "ok" and int(ik["count"]) == len(ref) > 0
        sols = np.array(json.loads(ik["solutions"]))
        np.testing.assert_allclose(sols, np.array([r.q for r in ref]), rtol=0, atol=TOL)
        assert json.loads(ik["labels"]) == [r.label for r in ref]
        assert json.loads(ik["within"]) == [r.within_limits for r in ref]
        # the generating q is among them (up to whole turns)
        wrapped = np.abs(np.angle(np.exp(1j * (sols - q_gen)))).max(axis=1)
        assert wrapped.min() < 1e-7
        chosen = int(ik["chosen"])
        assert chosen == int(np.argmin(np.linalg.norm(np.array([r.q for r in ref]) - q_start, axis=1)))
        # the page moved there (clamped into the sliders' range if that solution is outside the limits)
        q_page = nums(ik["q"])
        np.testing.assert_allclose(q_page, np.clip(ref[chosen].q, lo, hi), rtol=0, atol=TOL)
        # and its readouts, from the module, are Pinocchio's there
        np.testing.assert_allclose(nums(ik["t"]).reshape(4, 4), robot.frame_pose(q_page), rtol=0, atol=TOL)
        J = nums(ik["j"]).reshape(6, robot.n)
        np.testing.assert_allclose(J, robot.jacobian(q_page, reference="local_world_aligned"), rtol=0, atol=TOL)


@needs_chromium
@needs_zig
def test_out_of_reach_target_leaves_the_arm(pages):
    robot, path = pages("ur5")
    q0 = np.array([0.1, -1.0, 1.2, -0.5, 0.3, 0.2])
    T = robot.frame_pose(q0)
    T[:3, 3] += [5.0, 0.0, 0.0]  # far beyond the UR5's reach (0.85 m)
    assert robokit.ik_analytic(robot, T) == []
    d = run_page(path, q0, "&T=" + _fmt(T))
    ik = d["rk-ik"]
    assert ik["data-status"] == "unreachable" and ik["data-count"] == "0" and ik["data-chosen"] == "-1"
    np.testing.assert_allclose(nums(d["rk-q"]["data-q"]), q0, rtol=0, atol=0)


@needs_chromium
@needs_zig
def test_planar_arm_follows_a_target_off_its_plane_by_damped_least_squares(pages):
    """A target the planar RRR arm cannot take (lifted 5 cm off its plane): ik_analytic has no
    solution, and so does the page (count 0, no solutions); the arm still moves, by damped least
    squares, to where its tool is nearer the target than at the start (the position in the plane)."""
    robot, path = pages("rrr")
    q0 = np.array([0.2, 0.5, -0.3])
    T = robot.frame_pose(np.array([0.6, -0.4, 0.9]))
    T[2, 3] += 0.05  # off the plane z = 0
    assert robokit.ik_analytic(robot, T) == []
    d = run_page(path, q0, "&T=" + _fmt(T))
    ik = d["rk-ik"]
    assert ik["data-status"] == "dls-no-exact" and ik["data-count"] == "0" and ik["data-solutions"] == "[]"
    assert ik["data-chosen"] == "-1" and int(ik["data-steps"]) != 0
    q_page = nums(d["rk-q"]["data-q"])
    reached = robot.frame_pose(q_page)
    # in the plane the arm reaches the target's position and angle: only the lift remains
    np.testing.assert_allclose(reached[:2, 3], T[:2, 3], rtol=0, atol=1e-6)
    np.testing.assert_allclose(reached[:3, :3], T[:3, :3], rtol=0, atol=1e-6)
    np.testing.assert_allclose(nums(d["rk-pose"]["data-t"]).reshape(4, 4), reached, rtol=0, atol=TOL)


def test_teach_without_the_compiler_fails_with_one_line_naming_the_extra(tmp_path, capsys, monkeypatch):
    """The page computes only with the module: without ziglang, `robokit teach` says so in one line
    naming the extra, exits 2 and writes nothing (no page computing in another implementation)."""
    import sys

    from robokit.cli import main as cli_main

    monkeypatch.setitem(sys.modules, "ziglang", None)  # import ziglang -> ModuleNotFoundError
    out = tmp_path / "puma.html"
    assert cli_main(["teach", "puma560", "-o", str(out)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith("robokit: ") and "robokit[viz]" in err[0], err
    assert not out.exists()
    from robokit.errors import InputError, MissingExtraError
    from robokit.codegen.wasm import wasm_module

    with pytest.raises(MissingExtraError, match="robokit\\[viz\\]"):
        wasm_module(robokit.load("twolink"))
    with pytest.raises(InputError, match="wasm"):  # and the page is never written without its module
        teach_html(robokit.load("twolink"))


@needs_zig
def test_cli_embeds_the_module(tmp_path):
    from robokit.cli import main as cli_main

    out = tmp_path / "puma.html"
    assert cli_main(["teach", "puma560", "-o", str(out)]) == 0
    text = out.read_text(encoding="utf-8")
    module = text.split('<script id="rk-wasm" type="application/octet-stream">')[1].split("</script>")[0]
    assert 0 < len(module) < 64_000  # the robot's C as WebAssembly, base64: a few tens of kB
    assert "RKWasm" in text
    assert "http://" not in text.split('id="rk-robot"')[1] and "https://" not in text.split('id="rk-robot"')[1]


@needs_chromium
@needs_zig
def test_arm_without_closed_form_follows_by_damped_least_squares(tmp_path):
    robot = robokit.load("panda")
    path = tmp_path / "panda.html"
    path.write_text(teach_page(robot), encoding="utf-8")
    q0 = np.array([0.1, -0.4, 0.2, -2.0, 0.1, 1.6, 0.5])
    T = robot.frame_pose(q0 + np.array([0.03, -0.02, 0.04, 0.02, -0.03, 0.01, 0.02]))
    d = run_page(path, q0, "&T=" + _fmt(T))
    ik = d["rk-ik"]
    assert ik["data-status"] == "dls" and int(ik["data-steps"]) > 0 and ik["data-chosen"] == "0"
    q_page = nums(d["rk-q"]["data-q"])
    np.testing.assert_allclose(q_page, json.loads(ik["data-solutions"])[0], rtol=0, atol=0)
    np.testing.assert_allclose(robot.frame_pose(q_page), T, rtol=0, atol=TOL)
    np.testing.assert_allclose(nums(d["rk-pose"]["data-t"]).reshape(4, 4), T, rtol=0, atol=TOL)


# Drives the page in an iframe: 100 targets through RKTeach.goToTarget (the entry point of #T=
# and of the drag handle), then a drag of the handle with pointer events; writes what it saw.
_PATH_JS = """
function run() {
  var f = document.getElementById("page"), w = f.contentWindow, d = w.document;
  if (!w.RKTeach || !d.getElementById("rk-q") || !d.getElementById("rk-q").dataset.q ||
      !d.getElementById("rk-gizmo").dataset.x) { setTimeout(run, 100); return; }
  var qs = [], chosen = [];
  PATH.forEach(function (T) {
    w.RKTeach.goToTarget(T, "path");
    qs.push(d.getElementById("rk-q").dataset.q);
    chosen.push(d.getElementById("rk-ik").dataset.chosen);
  });
  var g = d.getElementById("rk-gizmo").dataset, cv = d.querySelector("#meshcat-pane canvas");
  var before = d.getElementById("rk-pose").dataset.t, x = Number(g.x), y = Number(g.y);
  var ev = function (type, X, Y) {
    cv.dispatchEvent(new w.PointerEvent(type, { clientX: X, clientY: Y, bubbles: true, cancelable: true,
                                                 pointerId: 1, isPrimary: true, button: 0, buttons: 1 }));
  };
  ev("pointerdown", x, y); ev("pointermove", x + 15, y - 5); ev("pointermove", x + 30, y - 10); ev("pointerup", x + 30, y - 10);
  var ik = d.getElementById("rk-ik").dataset;
  document.getElementById("out").textContent = JSON.stringify({
    qs: qs, chosen: chosen, before: before, after: d.getElementById("rk-pose").dataset.t,
    status: ik.status, target: ik.target || "", handle: [x, y] });
}
window.addEventListener("load", function () { setTimeout(run, 100); });
"""


@needs_chromium
@needs_zig
def test_smooth_path_and_drag_follow_one_branch(pages, tmp_path):
    """UR5 along a smooth path of 100 poses (FK of a joint-space segment away from singularities):
    the page's q follows the path's own branch, every step as small as the path's; then dragging
    the handle moves the tool's position and keeps its orientation (Pinocchio's FK of the page's q)."""
    robot, path = pages("ur5")
    q0 = np.array([0.3, -1.2, 1.5, -1.9, -1.2, 0.4])
    q1 = q0 + np.array([0.6, 0.3, -0.4, 0.5, 0.4, -0.6])
    s = np.linspace(0.0, 1.0, 100)
    qpath = q0 + np.outer(0.5 - 0.5 * np.cos(np.pi * s), q1 - q0)  # smooth start and stop
    Ts = [robot.frame_pose(q).ravel().tolist() for q in qpath]
    harness = tmp_path / "path.html"
    harness.write_text(
        '<!DOCTYPE html><html><body><iframe id="page" width="1200" height="800" src="'
        + path.resolve().as_uri() + "#q=" + _fmt(q0) + '"></iframe><pre id="out"></pre><script>var PATH = '
        + json.dumps(Ts) + ";" + _PATH_JS + "</script></body></html>", encoding="utf-8")
    got = run_harness(harness)
    qs = np.array([nums(x) for x in got["qs"]])
    np.testing.assert_allclose(qs, qpath, rtol=0, atol=TOL)  # the path's own branch, all along
    step = np.abs(np.diff(qpath, axis=0)).max()
    assert np.abs(np.diff(qs, axis=0)).max() <= step + TOL
    # the drag: a new position, the same orientation, the arm there
    before, after = nums(got["before"]).reshape(4, 4), nums(got["after"]).reshape(4, 4)
    assert got["status"] == "ok"
    assert np.linalg.norm(after[:3, 3] - before[:3, 3]) > 1e-3
    np.testing.assert_allclose(after[:3, :3], before[:3, :3], rtol=0, atol=TOL)
    np.testing.assert_allclose(after, nums(got["target"]).reshape(4, 4), rtol=0, atol=TOL)
    np.testing.assert_allclose(robot.frame_pose(qs[-1]), before, rtol=0, atol=TOL)


@needs_chromium
@needs_zig
def test_page_whose_module_does_not_load_says_so_and_shows_no_numbers(tmp_path):
    """A page whose module cannot be instantiated (here: its bytes corrupted) computes nothing in
    another implementation: it says why under the sliders and writes no pose."""
    from tests.viz.test_page_names import run_page as run_text

    text = teach_page(robokit.load("puma560"))
    head, rest = text.split('<script id="rk-wasm" type="application/octet-stream">', 1)
    path = tmp_path / "broken.html"
    path.write_text(head + '<script id="rk-wasm" type="application/octet-stream">AGFzbQEAAAAB' + rest.split("</script>", 1)[1],
                    encoding="utf-8")
    p = run_text(path, "#q=0.1,0.2,0.3,0.4,0.5,0.6")
    assert "cannot compute" in p.text.get("rk-msg", ""), p.text.get("rk-msg")
    assert "data-t" not in p.attrs.get("rk-pose", {})
