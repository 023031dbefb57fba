"""robokit view and the scene layer: pages are written (or not), bad input exits 2, the
live viewer starts and stops, and the robot is visible in a real (headless) browser."""
import shutil
import subprocess
import tempfile
from pathlib import Path

import numpy as np
import pytest
from shared_robots import robot as shared_robot

from robokit.cli import main as cli_main
from robokit.viz import LiveViewer, Scene, view_html

CHROMIUM = shutil.which("chromium") or shutil.which("chromium-browser")


def _cli(args, capsys):
    rc = cli_main(args)
    return (rc,) + capsys.readouterr()


def test_view_writes_self_contained_page(tmp_path, capsys):
    out = tmp_path / "puma.html"
    Q = np.linspace(np.zeros(6), [0.5, -0.3, 0.4, 0.2, 0.3, 0.1], 20)
    np.save(tmp_path / "traj.npy", Q)
    rc, stdout, err = _cli(["view", "puma560", "-q", "0.1", "-0.2", "0.3", "0", "0.4", "0", "--frames",
                            "--trajectory", str(tmp_path / "traj.npy"), "-o", str(out)], capsys)
    assert rc == 0 and out.exists()
    page = out.read_text()
    assert page.lstrip().lower().startswith("<!doctype html") or "<html" in page[:200].lower()
    assert "http://127.0.0.1" not in page.split("<script")[0]  # no server address needed to view it
    assert "animation" in page.lower() or "set_animation" in page.lower()


BAD = [
    (["view", "no_such_robot"], "unknown robot"),
    (["view", "puma560", "-q", "0.1", "0.2"], "6 joints"),
    (["view", "twolink", "--trajectory", "MISSING.csv"], "not found"),
]


@pytest.mark.parametrize("args,needle", BAD)
def test_bad_input_exit_2_and_no_file(args, needle, tmp_path, capsys):
    out = tmp_path / "x.html"
    args = [a.replace("MISSING.csv", str(tmp_path / "missing.csv")) for a in args]
    rc, stdout, err = _cli(args + ["-o", str(out)], capsys)
    assert rc == 2 and needle in err and err.count("\n") == 1
    assert not out.exists() and not list(tmp_path.glob(".x.html*"))


def test_unreadable_trajectory_file(tmp_path, capsys):
    bad = tmp_path / "bad.csv"
    bad.write_text("q1,q2\n0.1,0.2\n0.3,abc\n")
    rc, _, err = _cli(["view", "twolink", "--trajectory", str(bad), "-o", str(tmp_path / "x.html")], capsys)
    assert rc == 2 and "cannot read" in err and not (tmp_path / "x.html").exists()
    wrong = tmp_path / "wrong.csv"
    wrong.write_text("0.1,0.2,0.3\n")
    rc, _, err = _cli(["view", "twolink", "--trajectory", str(wrong), "-o", str(tmp_path / "x.html")], capsys)
    assert rc == 2 and "expected (K, 2)" in err


def test_live_viewer_starts_and_stops():
    viewer = LiveViewer()
    try:
        assert viewer.url.startswith("http://127.0.0.1:")
        proc = viewer.process
        assert proc is not None and proc.poll() is None
    finally:
        viewer.close()
    assert proc.poll() is not None  # the server process has exited


def test_scene_drawings_and_bad_input():
    with Scene("twolink") as s:
        s.show([0.3, 0.5]).frames().point("p", [0.5, 0.5, 0]).frame("f", np.eye(4))
        s.path("line", [[0, 0, 0], [1, 1, 0], [1.5, 0.2, 0]]).velocity_ellipsoid()
        with pytest.raises(ValueError, match="q"):
            s.show([0.1])
        with pytest.raises(ValueError, match="points"):
            s.path("bad", [[0, 0, 0]])
        with pytest.raises(ValueError, match="frames"):
            s.frames(["nope"])
        assert len(s.html()) > 1000


def _screenshot(page: Path, png: Path):
    with tempfile.TemporaryDirectory(ignore_cleanup_errors=True) as profile:
        subprocess.run(
            [CHROMIUM, "--headless", "--no-sandbox", "--disable-gpu", "--enable-unsafe-swiftshader",
             "--use-angle=swiftshader", "--disable-quic", "--no-first-run", "--disable-background-networking",
             "--disable-component-update", "--disable-sync", f"--user-data-dir={profile}", "--window-size=800,600",
             "--virtual-time-budget=15000", f"--screenshot={png}", f"file://{page}"],
            capture_output=True, timeout=120, check=False)
    from PIL import Image

    return np.asarray(Image.open(png).convert("RGB"), dtype=float)


@pytest.mark.skipif(CHROMIUM is None, reason="Debian's chromium is not installed (.ci/run installs it)")
@pytest.mark.parametrize("model", ["puma560", "ur5"])
def test_robot_visible_in_headless_chromium(model, tmp_path):
    page = tmp_path / f"{model}.html"
    page.write_text(view_html(model))
    # the empty scene, rendered the same way with the same camera
    with Scene(model) as s:
        s.show()
        s.frame_camera()
        s.vis["robot"].delete()
        empty = tmp_path / "empty.html"
        empty.write_text(s.html())
    img = _screenshot(page, tmp_path / "robot.png")
    ref = _screenshot(empty, tmp_path / "empty.png")
    assert img.shape == ref.shape == (600, 800, 3)
    changed = np.abs(img - ref).max(axis=2) > 30
    fraction = changed.mean()
    print(f"{model}: {fraction:.1%} of the pixels differ from the empty scene")
    assert fraction > 0.02, f"only {fraction:.2%} of the pixels show the robot"


class _Recorder:
    """Stands in for meshcat's window: keeps the commands a Scene sends (no server)."""

    def __init__(self):
        self.commands = []

    def send(self, command):
        self.commands.append(command.lower())


def _recorded_scene(model):
    import meshcat

    rec = _Recorder()
    return Scene(model, vis=meshcat.Visualizer(window=rec)), rec


def test_frame_labels_face_the_camera_and_stay_readable():
    """--frames labels are three.js sprites (always turned to the camera: never mirrored), drawn
    over the geometry (no depth test), upright above their origins, apart from each other where
    the PUMA's wrist frames coincide, and a few percent of the robot's size."""
    import robokit

    puma = robokit.load("puma560")
    scene, rec = _recorded_scene(puma)
    q = np.array([0, 0.785, -1.571, 0, 0.524, 0])
    scene.show(q).frames()
    names = [f"dh_{i}" for i in range(7)] + ["tool"]
    objs = {c["path"]: c["object"] for c in rec.commands if c["type"] == "set_object"}
    moves = {c["path"]: np.array(c["matrix"]).reshape(4, 4).T for c in rec.commands if c["type"] == "set_transform"}
    poses = puma.frame_poses(q)
    size = np.ptp(np.array([T[:3, 3] for T in poses.values()]), axis=0).max()
    tops = []
    for name in names:
        obj = objs[f"/meshcat/labels/{name}"]
        assert obj["object"]["type"] == "Sprite"
        mat = obj["materials"][0]
        assert mat["type"] == "SpriteMaterial" and mat["depthTest"] is False and "map" in mat
        height = np.array(obj["object"]["matrix"]).reshape(4, 4)[1, 1]
        assert 0.02 < height / size < 0.1, (name, height, size)
        T = moves[f"/meshcat/labels/{name}"]
        assert np.allclose(T[:3, :3], np.eye(3))  # not turned with the frame
        lift = T[:3, 3] - poses[name][:3, 3]
        assert np.allclose(lift[:2], 0) and lift[2] >= 0.8 * height, (name, lift)
        tops.append(T[:3, 3])
        assert np.abs(np.array(objs[f"/meshcat/frames/{name}/triad"]["object"]["matrix"]) - np.eye(4).ravel()).max() < 1e-12
    tops = np.array(tops)
    gaps = np.linalg.norm(tops[:, None] - tops[None], axis=2) + np.eye(len(tops))
    assert gaps.min() > 0.9 * height  # dh_4, dh_5, dh_6 and tool share an origin: a column of labels, not a pile
    assert not any(o["object"]["type"] == "Mesh" for p, o in objs.items() if p.startswith("/meshcat/labels"))


def test_frames_follow_the_trajectory_animation():
    """``robokit view --frames --trajectory``: the triads and their labels move with the robot in
    every frame of the animation, at the poses Pinocchio gives the frames at that row (they stayed
    where the robot was first shown while the robot moved)."""
    import pinocchio as pin

    import robokit

    puma = robokit.load("puma560")
    scene, rec = _recorded_scene(puma)
    Q = np.linspace([0.0, 0.0, 0.0, 0.0, 0.0, 0.0], [0.8, -0.5, 0.7, 1.0, -0.6, 0.9], 7)
    scene.show(Q[0]).frames().animate(Q, fps=10)
    names = [f"dh_{i}" for i in range(7)] + ["tool"]
    anims = [c for c in rec.commands if c["type"] == "set_animation"]
    assert len(anims) == 1
    clips = {a["path"]: {t["name"]: t["keys"] for t in a["clip"]["tracks"]} for a in anims[0]["animations"]}
    model = puma.model
    data = model.createData()
    for k, q in enumerate(Q):
        pin.framesForwardKinematics(model, data, pin.integrate(model, pin.neutral(model), q))
        for name in names:
            ref = data.oMf[model.getFrameId(name)]
            track = clips[f"/meshcat/frames/{name}"]
            (pos,) = [key["value"] for key in track[".position"] if key["time"] == k]
            (quat,) = [key["value"] for key in track[".quaternion"] if key["time"] == k]  # x, y, z, w
            np.testing.assert_allclose(pos, ref.translation, rtol=0, atol=1e-12)
            R = pin.Quaternion(quat[3], quat[0], quat[1], quat[2]).toRotationMatrix()
            np.testing.assert_allclose(R, ref.rotation, rtol=0, atol=1e-12)
            (label,) = [key["value"] for key in clips[f"/meshcat/labels/{name}"][".position"] if key["time"] == k]
            lift = np.asarray(label) - ref.translation
            assert np.allclose(lift[:2], 0, atol=1e-12) and lift[2] > 0, (k, name, lift)


@pytest.mark.parametrize("model", ["puma560", "ur5"])
def test_ground_grid_lies_under_the_robot_sized_to_its_reach(model):
    """The view's grid: a square in the base's z = 0 plane, centred on the base, as wide as the
    robot's horizontal reach (checked on 300 other random configurations) plus a margin; meshcat's
    20 m grid is hidden."""
    robot = shared_robot(model)
    scene, rec = _recorded_scene(robot)
    scene.show().frame_camera()
    floor = [c for c in rec.commands if c["type"] == "set_object" and c["path"] == "/meshcat/floor"][-1]
    arr = floor["object"]["geometries"][0]["data"]["attributes"]["position"]["array"]  # msgpack ext: float32 bytes
    pts = np.frombuffer(arr.data, dtype=np.float32).reshape(-1, 3).astype(float)
    half, spacing = scene.grid["half"], scene.grid["spacing"]
    assert np.allclose(pts[:, 2], 0.0)
    assert np.allclose(pts[:, :2].min(axis=0), -half, atol=1e-6) and np.allclose(pts[:, :2].max(axis=0), half, atol=1e-6)
    rng = np.random.default_rng(123)
    reach = max(np.hypot(T[0, 3], T[1, 3]) for _ in range(300) for T in robot.frame_poses(robot.random_configuration(rng)).values())
    assert 1.0 * reach <= half <= 1.25 * reach + spacing, (half, reach)
    assert 4 <= half / spacing <= 12
    hidden = [c for c in rec.commands if c["type"] == "set_property" and c["path"] == "/Grid"]
    assert hidden and hidden[-1]["property"] == "visible" and hidden[-1]["value"] is False


def test_pages_carry_decimated_meshes_and_the_live_scene_keeps_the_files():
    """Scene.html() writes meshes (visual and collision) decimated as the teach page does (the UR5's
    page was 10 MB with its mesh files as they are): the same cluster_decimate parts, a fraction of the
    size; the live scene gets its full meshes back."""
    import base64
    import re

    import umsgpack

    from robokit.viz._meshes import decimated_visuals

    with Scene("ur5") as s:
        s.show()
        full = s.html(None)
        page = s.html()
        again = s.html(None)
        geometry = (s.viz.visual_model, s.viz.collision_model)
    assert len(page) < 0.4 * len(full), (len(page), len(full))
    assert len(again) == len(full)  # restored
    # the page's triangle meshes are the decimated parts; no mesh file is left in it
    def objects(html):
        blobs = re.findall(r'fetch\("data:application/octet-binary;base64,([A-Za-z0-9+/=]+)"\)', html)
        out = []
        for d in (umsgpack.unpackb(base64.b64decode(b)) for b in blobs):
            if d.get("type") == "set_object":
                o = d["object"]
                out.append((d["path"], o.get("object", {}).get("type"), [g.get("type") for g in o.get("geometries", [])]))
        return out

    def mesh_files(objs):
        return [p for p, kind, geoms in objs if kind == "_meshfile_object" or "_meshfile" in geoms]

    assert mesh_files(objects(full))  # the check below can fail
    in_page = objects(page)
    assert mesh_files(in_page) == []
    parts = [p for p, kind, geoms in in_page if "/part" in p and geoms == ["BufferGeometry"]]
    assert len(parts) == sum(len(p) for model in geometry for _, p in decimated_visuals(model)) > 0


_PLAYER_HARNESS = """
<pre id="rk-test-out"></pre>
<script>
(function () {
  var log = [], box = document.getElementById("rk-player"), button = document.getElementById("rk-play");
  function state(label) {
    // one frame of meshcat's loop by hand (a headless browser draws frames when it likes): advances the
    // animation by the time since the last one when it plays, nothing when it is paused
    var a = viewer.animator;
    a.update();
    var t = a.actions.reduce(function (m, x) { return Math.max(m, x.time); }, 0);
    var r = button.getBoundingClientRect(), s = getComputedStyle(box);
    log.push({label: label, playing: box.dataset.playing, time: t,
              duration: Number(box.dataset.duration), text: button.textContent,
              rect: [r.left, r.top, r.right, r.bottom], view: [innerWidth, innerHeight],
              visible: s.display !== "none" && s.visibility !== "hidden" && Number(s.opacity) > 0});
    document.getElementById("rk-test-out").textContent = JSON.stringify(log);
  }
  // steps 0.7 s apart (the first once the animation is loaded)
  var steps = [
    [function () { return Number(box.dataset.duration) > 0; }, function () { state("open"); }],
    [function () { return true; }, function () { state("later"); button.click(); }],
    [function () { return true; }, function () { state("paused"); }],
    [function () { return true; }, function () { state("still paused"); button.click(); }],
    [function () { return true; }, function () { state("playing again"); }],
  ];
  function run(i, waited) {
    if (i >= steps.length) { return; }
    if (!steps[i][0]() && waited < 8000) { setTimeout(function () { run(i, waited + 100); }, 100); return; }
    steps[i][1]();
    setTimeout(function () { run(i + 1, 0); }, 700);
  }
  run(0, 0);
})();
</script>
"""


@pytest.mark.skipif(CHROMIUM is None, reason="Debian's chromium is not installed (.ci/run installs it)")
def test_trajectory_page_has_a_visible_play_pause_control(tmp_path):
    """The trajectory page had no visible play control (only meshcat's "Open Controls"): now a button
    in the viewport plays it (time advances), pauses it (time stands still) and plays it again."""
    import html as html_mod
    import json
    import re

    from browser_support import dump_dom

    Q = np.linspace(np.zeros(6), [1.0, -0.6, 0.8, 0.4, 0.9, 0.3], 300)  # 10 s at 30 fps
    page = view_html("puma560", trajectory=Q, fps=30.0)
    assert page.count('id="rk-play"') == 1 and 'id="rk-play"' not in view_html("puma560")  # only when animated
    i = page.rfind("</body>")
    path = tmp_path / "traj.html"
    path.write_text(page[:i] + _PLAYER_HARNESS + page[i:])
    dom = dump_dom(path.as_uri(), budget_ms=30000)
    m = re.search(r'<pre id="rk-test-out">(.*?)</pre>', dom, re.S)
    assert m and m.group(1), dom[-2000:]
    log = {s["label"]: s for s in json.loads(html_mod.unescape(m.group(1)))}
    assert len(log) == 5, log
    opened = log["open"]
    x0, y0, x1, y1 = opened["rect"]
    w, h = opened["view"]
    assert opened["visible"] and 0 <= x0 < x1 <= w and 0 <= y0 < y1 <= h, opened  # on screen, not folded away
    assert opened["duration"] == pytest.approx(299 / 30.0, abs=0.05)
    assert opened["playing"] == "true" and "Pause" in opened["text"]
    assert log["later"]["time"] > opened["time"]  # it plays
    assert log["paused"]["playing"] == "false" and "Play" in log["paused"]["text"]
    assert log["still paused"]["time"] == log["paused"]["time"]  # paused: time stands still
    assert log["playing again"]["playing"] == "true" and log["playing again"]["time"] > log["still paused"]["time"]
