"""Dragging the tool on the teach page (headless Chromium): the gizmo's rotation rings and arrows
(synthetic pointer drags through the page's own picking), the ghost arms of every IK branch and
a click on one, branch changes where branches meet, the out-of-reach state, and the damped-least-
squares drag of an arm without a closed form. Each page is opened once; one harness script does
all its steps and the test compares what the page wrote with Pinocchio's FK, ``ik_analytic`` and
the collision World (coal)."""
import json

import numpy as np
import pytest

import robokit
from robokit._optional import available
from robokit.viz.teach import teach_html
from tests.viz.test_teach import needs_chromium, nums, run_harness

needs_zig = pytest.mark.skipif(not available("ziglang"), reason="ziglang (the viz extra) not installed")
TOL = 1e-9


def _fmt(x):
    return ",".join(repr(float(v)) for v in np.ravel(x))


def _page(robot, path, **kw):
    from robokit.codegen.wasm import wasm_module

    path.write_text(teach_html(robot, wasm=wasm_module(robot).wasm, **kw), encoding="utf-8")
    return path


# The harness's helpers: wait for the page, pointer events on its canvas, a snapshot of its state.
_HELPERS = """
var w, d, cv, out = {};
function ready() {
  w = document.getElementById("page").contentWindow; d = w.document;  // the loaded page's, once it is there
  return w.RKTeach && d.getElementById("rk-q") && d.getElementById("rk-q").dataset.q &&
         d.getElementById("rk-gizmo") && d.getElementById("rk-gizmo").dataset.handles;
}
function data(id) { return Object.assign({}, d.getElementById(id).dataset); }
function ev(type, X, Y) {
  cv.dispatchEvent(new w.PointerEvent(type, { clientX: X, clientY: Y, bubbles: true, cancelable: true, pointerId: 1,
                                              isPrimary: true, button: 0, buttons: type === "pointerup" ? 0 : 1 }));
}
function snap() {
  var b = d.getElementById("rk-branch");
  return { q: data("rk-q").q, t: data("rk-pose").t, ik: data("rk-ik"), gizmo: data("rk-gizmo"), ghosts: data("rk-ghosts"),
           badge: b.hidden ? "" : b.textContent, badgeClass: b.className, text: d.getElementById("rk-ik").textContent,
           buttons: d.querySelectorAll("#rk-branches button").length };
}
// drag a gizmo handle: press on it, move `px` pixels along `dir` (page pixels) in 3 steps, release
function dragHandle(modes, dirOf, px) {  // the first of `modes` that the page can grab here
  var g = data("rk-gizmo"), hs = JSON.parse(g.handles), c = [Number(g.x), Number(g.y)];
  var mode = modes.filter(function (m) { return hs[m]; })[0], h = hs[mode];
  if (!h) { return { error: "no handle among " + modes + ": " + g.handles }; }
  var dir = dirOf(h, c), len = Math.hypot(dir[0], dir[1]);
  dir = [dir[0] / len, dir[1] / len];
  var before = snap();
  ev("pointerdown", h[0], h[1]);
  for (var k = 1; k <= 3; k++) { ev("pointermove", h[0] + dir[0] * px * k / 3, h[1] + dir[1] * px * k / 3); }
  ev("pointerup", h[0] + dir[0] * px, h[1] + dir[1] * px);
  return { before: before, after: snap() };
}
function along(h, c) { return [h[0] - c[0], h[1] - c[1]]; }        // an arrow: away from the centre
function around(h, c) { return [-(h[1] - c[1]), h[0] - c[0]]; }    // a ring: along its tangent
function start(steps) {
  (function poll() {
    if (!ready()) { setTimeout(poll, 100); return; }
    cv = d.querySelector("#meshcat-pane canvas");
    try { steps(); } catch (e) { out.error = String(e) + " | " + e.stack; }  // reported by the test
    document.getElementById("out").textContent = JSON.stringify(out);
  })();
}
"""

_UR5_STEPS = """
start(function () {
  // a path through the wrist singularity (q5 = 0), through the gizmo's entry point
  out.path = PATH.map(function (T) { w.rkDrag(T); return snap(); });
  // rotate about the tool's z with its ring, then move along the tool's x with its arrow
  out.turn = dragHandle(["turn-z"], around, 40);
  out.move = dragHandle(["move-x", "move-y", "move-z"], along, 25);
  // a target with 8 branches: the ghosts; then a click on another one (the page's picking)
  w.rkDrag(TARGET);
  out.ghosts = snap();
  var sols = JSON.parse(out.ghosts.ik.within), chosen = Number(out.ghosts.ik.chosen), pick = -1, at = null;
  for (var k = 0; k < sols.length && pick < 0; k++) {
    if (k !== chosen && sols[k]) { at = w.RKTeach.ghostPoint(k); if (at) { pick = k; } }
  }
  out.pick = pick;
  if (at) { ev("pointerdown", at[0], at[1]); ev("pointerup", at[0], at[1]); }
  out.clicked = snap();
  // out of reach
  w.rkDrag(FAR);
  out.far = snap();
});
"""


def _harness(tmp_path, page, q0, script, **values):
    harness = tmp_path / "harness.html"
    js = "".join(f"var {k} = {json.dumps(v)};\n" for k, v in values.items())
    harness.write_text(
        '<!DOCTYPE html><html><body><iframe id="page" width="1200" height="800" src="'
        + page.resolve().as_uri() + "#q=" + _fmt(q0) + '"></iframe><pre id="out"></pre><script>' + js + _HELPERS
        + script + "</script></body></html>", encoding="utf-8")
    got = run_harness(harness)
    assert "error" not in got, got["error"]
    return got


@pytest.fixture(scope="module")
def ur5_run(tmp_path_factory):
    if not available("ziglang"):
        pytest.skip("ziglang (the viz extra) not installed")
    from tests.viz.test_teach import CHROMIUM

    if CHROMIUM is None:
        pytest.skip("chromium not installed")
    tmp = tmp_path_factory.mktemp("teach-drag")
    robot = robokit.load("ur5")
    page = _page(robot, tmp / "ur5.html")
    q_a = np.array([0.3, -1.2, 1.5, -1.9, 0.3, 0.4])
    q_b = q_a + np.array([0.1, 0.1, -0.1, 0.1, -0.6, 0.1])  # q5 from +0.3 to -0.3
    qpath = q_a + np.outer(np.linspace(0.0, 1.0, 20), q_b - q_a)  # 20 poses: q5 is never exactly 0
    target_q = np.array([-0.6, -1.0, 1.2, -1.4, 0.9, 0.3])
    far = robot.frame_pose(target_q)
    far[:3, 3] += [5.0, 0.0, 0.0]  # far beyond the UR5's reach (0.85 m)
    got = _harness(tmp, page, q_a, _UR5_STEPS, PATH=[robot.frame_pose(q).ravel().tolist() for q in qpath],
                   TARGET=robot.frame_pose(target_q).ravel().tolist(), FAR=far.ravel().tolist())
    return robot, qpath, target_q, got


@needs_chromium
@needs_zig
def test_path_through_the_wrist_singularity_changes_branch_once_where_branches_meet(ur5_run):
    """Along a straight joint path whose q5 crosses 0 (where the wrist's flip and no-flip
    branches meet), the page's q follows the path itself (to 1e-9) and records exactly one branch
    change, at the crossing, from and to ``ik_analytic``'s labels there, by one path step."""
    robot, qpath, _, got = ur5_run
    qs = np.array([nums(s["q"]) for s in got["path"]])
    np.testing.assert_allclose(qs, qpath, rtol=0, atol=TOL)
    change = [s["ik"]["branchChange"] for s in got["path"]]
    cross = int(np.nonzero(np.diff(np.sign(qpath[:, 4])))[0][0]) + 1  # first pose with q5 < 0
    assert change == ["false"] * cross + ["true"] + ["false"] * (len(qpath) - cross - 1)

    def label_of(q):
        ref = robokit.ik_analytic(robot, robot.frame_pose(q))
        return ref[int(np.argmin([np.abs(r.q - q).max() for r in ref]))].label

    at = got["path"][cross]
    assert at["ik"]["branchFrom"] == label_of(qpath[cross - 1]) and at["ik"]["branchTo"] == label_of(qpath[cross])
    assert at["ik"]["branchFrom"] != at["ik"]["branchTo"]
    step = np.abs(np.diff(qpath, axis=0)).max()
    assert float(at["ik"]["branchGap"]) <= step + TOL
    assert "branch change" in at["text"] and "rk-branch-change" in at["badgeClass"]
    assert all(s["ik"]["status"] == "ok" for s in got["path"])


@needs_chromium
@needs_zig
def test_ring_drag_turns_the_tool_about_its_axis_and_the_arm_follows(ur5_run):
    """A pointer drag along the z ring (the page's picking finds it): the new pose turns about the
    tool's own z (z column and origin kept to 1e-9, x turned), the chosen solution reaches it
    (Pinocchio's FK of the page's q equals the target to 1e-9); then the x arrow moves the
    origin along the tool's x with the orientation kept."""
    robot, _, _, got = ur5_run
    for step in ("turn", "move"):
        assert "error" not in got[step], got[step]
        after = got[step]["after"]
        assert after["ik"]["status"] == "ok"
        q_page = nums(after["q"])
        target = nums(after["ik"]["target"]).reshape(4, 4)
        np.testing.assert_allclose(robot.frame_pose(q_page), target, rtol=0, atol=TOL)
        np.testing.assert_allclose(nums(after["t"]).reshape(4, 4), target, rtol=0, atol=TOL)
    assert got["turn"]["after"]["gizmo"]["mode"] == "turn-z"
    b, a = (nums(got["turn"][k]["t"]).reshape(4, 4) for k in ("before", "after"))
    np.testing.assert_allclose(a[:3, 3], b[:3, 3], rtol=0, atol=TOL)
    np.testing.assert_allclose(a[:3, 2], b[:3, 2], rtol=0, atol=TOL)
    assert np.arccos(np.clip(a[:3, 0] @ b[:3, 0], -1, 1)) > 0.05  # turned by a visible angle
    axis = "xyz".index(got["move"]["after"]["gizmo"]["mode"][-1])  # the arrow the page could grab
    b, a = (nums(got["move"][k]["t"]).reshape(4, 4) for k in ("before", "after"))
    np.testing.assert_allclose(a[:3, :3], b[:3, :3], rtol=0, atol=TOL)
    dp = a[:3, 3] - b[:3, 3]
    assert np.linalg.norm(dp) > 1e-3
    assert np.linalg.norm(np.cross(dp, b[:3, axis])) <= TOL * max(1.0, np.linalg.norm(dp))


@needs_chromium
@needs_zig
def test_ghosts_are_the_branches_and_a_click_selects_one(ur5_run):
    """After a drag to a target: one ghost arm per solution, with ``ik_analytic``'s labels and
    limit flags (and a button each); a synthetic click on another ghost, through the page's
    picking, takes that branch: data-chosen, the page's q (to 1e-9) and the tool still there."""
    robot, _, target_q, got = ur5_run
    T = robot.frame_pose(target_q)
    ref = robokit.ik_analytic(robot, T)
    g = got["ghosts"]
    assert int(g["ghosts"]["count"]) == int(g["ik"]["count"]) == len(ref) == g["buttons"] >= 4
    assert json.loads(g["ghosts"]["labels"]) == json.loads(g["ik"]["labels"]) == [r.label for r in ref]
    assert json.loads(g["ghosts"]["status"]) == ["ok" if r.within_limits else "limits" for r in ref]
    assert g["ghosts"]["chosen"] == g["ik"]["chosen"]
    k = got["pick"]
    assert k >= 0 and k != int(g["ik"]["chosen"]) and ref[k].within_limits
    c = got["clicked"]
    assert c["ik"]["chosen"] == c["ghosts"]["chosen"] == str(k)
    assert c["ik"]["branchChange"] == "chosen" and c["ik"]["branchTo"] == ref[k].label
    q_page = nums(c["q"])
    np.testing.assert_allclose(q_page, ref[k].q, rtol=0, atol=TOL)
    np.testing.assert_allclose(robot.frame_pose(q_page), T, rtol=0, atol=TOL)
    assert int(c["ghosts"]["count"]) == len(ref)  # the same target's branches, still drawn


@needs_chromium
@needs_zig
def test_out_of_reach_drag_keeps_the_arm_and_turns_the_gizmo_red(ur5_run):
    _, _, _, got = ur5_run
    before, far = got["clicked"], got["far"]
    assert far["ik"]["status"] == "unreachable" and far["ik"]["count"] == "0" and far["ik"]["chosen"] == "-1"
    assert far["q"] == before["q"]  # the arm stays, exactly
    assert far["gizmo"]["reachable"] == "false" and before["gizmo"]["reachable"] == "true"
    assert far["ghosts"]["count"] == "0" and far["buttons"] == 0
    assert "out of reach" in far["text"] and "out of reach" in far["badge"]


_DLS_STEPS = """
start(function () {
  out.move = dragHandle(["move-z", "move-x", "move-y"], along, 20);
  out.turn = dragHandle(["turn-x", "turn-y", "turn-z"], around, 25);
});
"""


@needs_chromium
@needs_zig
def test_arm_without_closed_form_follows_the_gizmo_by_damped_least_squares(tmp_path):
    """The Panda (7 joints, no closed form): dragging the z arrow and the x ring runs the module's
    damped-least-squares steps from the current q; the page says so, draws no ghost, and its q
    reaches the dragged pose (Pinocchio's FK, 1e-9)."""
    robot = robokit.load("panda")
    page = _page(robot, tmp_path / "panda.html")
    q0 = np.array([0.1, -0.4, 0.2, -2.0, 0.1, 1.6, 0.5])
    got = _harness(tmp_path, page, q0, _DLS_STEPS)
    for step in ("move", "turn"):
        assert "error" not in got[step], got[step]
        assert got[step]["after"]["gizmo"]["mode"] in (["move-z", "move-x", "move-y"] if step == "move" else ["turn-x", "turn-y", "turn-z"])
        after = got[step]["after"]
        assert after["ik"]["status"] == "dls" and int(after["ik"]["steps"]) > 0
        assert "no closed-form IK" in after["text"] and "null space" in after["text"]
        assert after["ghosts"]["count"] == "0" and after["gizmo"]["reachable"] == "true"
        target = nums(after["ik"]["target"]).reshape(4, 4)
        np.testing.assert_allclose(robot.frame_pose(nums(after["q"])), target, rtol=0, atol=TOL)
    b, a = (nums(got["move"][k]["t"]).reshape(4, 4) for k in ("before", "after"))
    assert np.linalg.norm(a[:3, 3] - b[:3, 3]) > 1e-3
    np.testing.assert_allclose(a[:3, :3], b[:3, :3], rtol=0, atol=TOL)


@needs_chromium
@needs_zig
def test_ghosts_marked_by_limits_and_collisions_like_the_world(tmp_path):
    """On the PUMA page with obstacles, the ghosts' marks agree with ``ik_analytic``'s limit flags
    and with the collision World (coal) at each branch: 'ok' exactly when within the limits and
    collision-free."""
    from tests.viz.test_teach import _collision_world, run_page

    world = _collision_world()
    robot = world.robot
    rng = np.random.default_rng(11)
    lo, hi = np.array(robot.qlim, dtype=float).T
    for _ in range(200):  # a target whose branches are mixed: some free, some in contact (clear of 1 mm)
        T = robot.frame_pose(rng.uniform(lo, hi))
        ref = robokit.ik_analytic(robot, T)
        dist = [world.distance(r.q) for r in ref]
        if len(ref) == 8 and min(abs(x) for x in dist) > 1e-3 and any(x < 0 for x in dist) and any(x > 0 for x in dist):
            break
    else:
        pytest.fail("no target with mixed branches found")
    page = _page(robot, tmp_path / "puma_world.html", obstacles=world.obstacles)
    d = run_page(page, np.array([0.2, 0.3, -0.4, 0.5, 0.6, 0.7]), "&T=" + _fmt(T))
    g = d["rk-ghosts"]
    assert int(g["data-count"]) == int(d["rk-ik"]["data-count"]) == len(ref)
    expect = []
    for r, x in zip(ref, dist):
        marks = ([] if r.within_limits else ["limits"]) + (["collision"] if x < 0 else [])
        expect.append("+".join(marks) or "ok")
    assert json.loads(g["data-status"]) == expect
    assert json.loads(g["data-labels"]) == [r.label for r in ref]


def test_notebook_pendant_follows_its_drag_view_and_says_once_when_it_has_none():
    """Python's half: a q arriving from the drag view (as anywidget's comm sets it) moves the
    sliders, the live scene and the readouts (Pinocchio's, through teach_readouts); set_q moves
    the view. Without the module the pendant has no drag view and says why, in one line."""
    pytest.importorskip("ipywidgets")
    pytest.importorskip("anywidget")
    if not available("ziglang"):
        pytest.skip("ziglang (the viz extra) not installed")
    from robokit.codegen.wasm import wasm_module
    from robokit.viz import Scene
    from robokit.viz.teach import teach_readouts

    robot = robokit.load("puma560")
    with Scene(robot) as scene:
        pendant = scene.teach(wasm=wasm_module(robot).wasm)
        assert pendant.drag is not None and pendant.drag_note == "" and pendant.drag in pendant.children
        assert "rk-wasm" in pendant.drag.page
        q = np.array([0.2, 0.4, -0.3, 0.5, 0.6, -0.2])
        pendant.drag.q = q.tolist()
        np.testing.assert_allclose(scene.q, q, rtol=0, atol=0)
        ref = teach_readouts(robot, q)
        np.testing.assert_allclose(pendant.readouts["xyz"], ref["xyz"], rtol=0, atol=1e-12)
        np.testing.assert_allclose(pendant.readouts["J"], ref["J"], rtol=0, atol=1e-12)
        pendant.set_q([0.1] * 6)
        assert pendant.drag.q == [0.1] * 6
        plain = scene.teach()
        assert plain.drag is None and "wasm=" in plain.drag_note
        notes = [c for c in plain.children if getattr(c, "value", None) is not None and "Dragging the tool" in c.value]
        assert len(notes) == 1
