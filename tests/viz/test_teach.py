"""The teach page: its numbers (computed by the page's JavaScript in headless Chromium) against
Pinocchio; its scene data, its mesh decimation and its command line."""
import json
import math
import os
import shutil
import subprocess
import tempfile
from html.parser import HTMLParser
from pathlib import Path

import numpy as np
import pytest

import robokit
from shared_robots import robot
from robokit.cli import main as cli_main
from robokit.viz._meshes import cluster_decimate, mesh_parts
from robokit.viz.teach import NAMED_POSES, teach_data, teach_html, teach_readouts

ROBOTS = ["puma560", "ur5", "panda", "twolink"]
CHROMIUM = shutil.which("chromium") or ("/usr/bin/chromium" if os.path.exists("/usr/bin/chromium") else None)
needs_chromium = pytest.mark.skipif(CHROMIUM is None, reason="chromium not installed (apt-get install chromium)")

_pages = {}


def teach_page(model, **kw):
    """teach_html of a robot with its module (robokit.codegen.wasm, as robokit teach compiles it)."""
    from robokit.codegen.wasm import wasm_module

    r = robokit.load(model)
    return teach_html(r, wasm=wasm_module(r).wasm, **kw)


def page(name, tmp_dir):
    if name not in _pages:
        p = Path(tmp_dir) / f"teach_{name}.html"
        p.write_text(teach_page(robot(name)), encoding="utf-8")
        _pages[name] = p
    return _pages[name]


@pytest.fixture(scope="module")
def pages_dir():
    d = tempfile.mkdtemp(prefix="robokit-teach-test-")
    yield d
    shutil.rmtree(d, ignore_errors=True)
    _pages.clear()


class _Data(HTMLParser):
    """Collects the data- attributes of the elements with an id."""

    def __init__(self):
        super().__init__()
        self.by_id = {}

    def handle_starttag(self, tag, attrs):
        a = dict(attrs)
        if "id" in a:
            self.by_id[a["id"]] = a


def run_page(path: Path, q=None, fragment: str = "") -> dict:
    """Open the page in headless Chromium (with ``#q=...``, then ``fragment``'s further parts,
    e.g. ``"&T=..."``) and return its elements' attributes."""
    frag = ("" if q is None else "#q=" + ",".join(repr(float(v)) for v in q)) + fragment
    if frag and not frag.startswith("#"):
        frag = "#" + frag.lstrip("&")
    with tempfile.TemporaryDirectory(ignore_cleanup_errors=True) as profile:
        out = subprocess.run(
            [CHROMIUM, "--headless", "--no-sandbox", "--disable-gpu", "--enable-unsafe-swiftshader",
             "--use-angle=swiftshader", "--disable-quic", "--no-first-run", "--disable-background-networking",
             "--disable-component-update", "--disable-sync", f"--user-data-dir={profile}",
             "--virtual-time-budget=15000", "--dump-dom", path.resolve().as_uri() + frag],
            capture_output=True, text=True, timeout=180)
    assert out.returncode == 0, out.stderr[-2000:]
    parser = _Data()
    parser.feed(out.stdout)
    assert "rk-pose" in parser.by_id and "data-t" in parser.by_id["rk-pose"], "the page's script did not run"
    return parser.by_id


def nums(s):
    return np.array([float(x) for x in s.split(",")]) if s else np.zeros(0)


def test_twolink_rows_and_named_poses():
    """The planar arm's measures use (vx, vy); the PUMA page offers the lecture's named poses."""
    d = teach_data(robot("twolink"))
    assert d["rows"] == [3, 4]
    p = teach_data(robot("puma560"))
    assert set(NAMED_POSES["puma560"]) <= set(p["poses"])
    assert np.allclose(p["poses"]["qr"], [0, np.pi / 2, -np.pi / 2, 0, 0, 0])
    assert np.allclose(p["poses"]["qn"], [0, np.pi / 4, np.pi, 0, np.pi / 4, 0])


@pytest.mark.parametrize("name", ROBOTS)
def test_scene_placement_formula_matches_pinocchio(name):
    """The exported home poses, carried by e^{[S1]q1}…e^{[Sk]qk}, land where Pinocchio puts each
    visual and frame (this is what the page's script does; the browser test checks the script)."""
    import pinocchio as pin

    from robokit import fkin_space

    r = robot(name)
    d = teach_data(r)
    q = r.random_configuration(1)
    S = r.poe.Slist  # the screw axes: P_k(q) = e^[S1]q1 ... e^[Sk]qk (what KIN.placements gives)
    data = r.model.createData()
    pin.forwardKinematics(r.model, data, r.q_pin(q))
    gdata = r.visual_model.createData()
    pin.updateGeometryPlacements(r.model, data, r.visual_model, gdata)
    for v, go in zip(d["visuals"], r.visual_model.geometryObjects):
        k = v["k"]
        T = fkin_space(np.array(v["T"]), S[:, :k], q[:k]) if k else np.array(v["T"])
        expected = gdata.oMg[r.visual_model.getGeometryId(go.name)].homogeneous @ np.diag(np.r_[go.meshScale, 1])
        assert np.abs(T - expected).max() < 1e-9, go.name
    poses = r.frame_poses(q)
    for f in d["frames"]:
        k = f["k"]
        T = fkin_space(np.array(f["T"]), S[:, :k], q[:k]) if k else np.array(f["T"])
        assert np.abs(T - poses[f["name"]]).max() < 1e-9, f["name"]


@needs_chromium
@pytest.mark.parametrize("name", ROBOTS)
def test_page_numbers_agree_with_pinocchio(name, pages_dir):
    """Pose, RPY, quaternion, Jacobian, manipulability, condition number and the placed scene,
    as the page computes and shows them, against Pinocchio to 1e-9."""
    import pinocchio as pin

    r = robot(name)
    q = r.random_configuration(7)
    el = run_page(page(name, pages_dir), q)
    assert np.abs(nums(el["rk-q"]["data-q"]) - q).max() == 0.0  # inside the limits: taken as given

    T = r.frame_pose(q)
    assert np.abs(nums(el["rk-pose"]["data-t"]).reshape(4, 4) - T).max() < 1e-9
    assert np.abs(nums(el["rk-pose"]["data-xyz"]) - T[:3, 3]).max() < 1e-9
    R_page = pin.rpy.rpyToMatrix(*nums(el["rk-pose"]["data-rpy"]))
    assert np.abs(R_page - T[:3, :3]).max() < 1e-9
    quat = nums(el["rk-pose"]["data-quat"])
    ref = pin.Quaternion(T[:3, :3])
    ref = np.array([ref.w, ref.x, ref.y, ref.z]) * (1 if ref.w >= 0 else -1)
    assert np.abs(quat - ref).max() < 1e-9

    J = r.jacobian(q, reference="local_world_aligned")  # (ω; v), v of the tool origin, base axes
    assert np.abs(nums(el["rk-jacobian"]["data-j"]).reshape(6, r.n) - J).max() < 1e-9

    rows = teach_data(r)["rows"]
    Jt = J[rows]
    w_ref = math.sqrt(max(np.linalg.det(Jt @ Jt.T), 0.0))
    assert abs(float(el["rk-manip"]["data-value"]) - w_ref) < 1e-9
    s = np.linalg.svd(Jt, compute_uv=False)
    assert abs(float(el["rk-cond"]["data-value"]) - s[0] / s[-1]) < 1e-9 * s[0] / s[-1]

    lo, hi = r.qlim.T
    margins = np.where(np.isfinite(lo) & np.isfinite(hi), np.minimum(q - lo, hi - q), np.inf)
    assert np.allclose(nums(el["rk-margin"]["data-margins"]), margins, atol=1e-12, rtol=0)

    # the 3-D scene: every visual where Pinocchio places it (mesh scale included)
    placed = json.loads(el["rk-scene-poses"]["data-poses"])
    data = r.model.createData()
    pin.forwardKinematics(r.model, data, r.q_pin(q))
    gdata = r.visual_model.createData()
    pin.updateGeometryPlacements(r.model, data, r.visual_model, gdata)
    for v, go in zip(teach_data(r)["visuals"], r.visual_model.geometryObjects):
        expected = gdata.oMg[r.visual_model.getGeometryId(go.name)].homogeneous @ np.diag(np.r_[go.meshScale, 1])
        assert np.abs(np.array(placed[v["path"]]).reshape(4, 4) - expected).max() < 1e-9, go.name


@needs_chromium
def test_limits_clamp_and_singular_warning(pages_dir):
    """A q beyond a limit is clamped to it (margin 0); PUMA with θ5 = 0 and UR5 at zero are singular,
    and the lost direction is the left singular vector of σ_min (up to sign)."""
    r = robot("puma560")
    q = np.array([0.2, 3.0, -0.4, 0.3, 0.0, 0.1])  # q2 = 3 rad > 110°; θ5 = 0: the wrist is singular
    el = run_page(page("puma560", pages_dir), q)
    shown = nums(el["rk-q"]["data-q"])
    assert shown[1] == r.qlim[1, 1]
    assert np.array_equal(np.delete(shown, 1), np.delete(q, 1))
    assert float(el["rk-margin"]["data-value"]) == 0.0
    assert el["rk-margin"]["data-joint"] == r.joint_names[1]
    assert el["rk-sing"]["data-singular"] == "true"
    J = r.jacobian(shown, reference="local_world_aligned")
    U, s, _ = np.linalg.svd(J)
    assert s[-1] < 1e-9
    u = nums(el["rk-sing"]["data-direction"])
    assert abs(abs(u @ U[:, -1]) - 1) < 1e-9
    assert np.linalg.norm(J.T @ u) < 1e-9  # no joint velocity produces it

    el = run_page(page("ur5", pages_dir), np.zeros(6))
    assert el["rk-sing"]["data-singular"] == "true"
    assert float(el["rk-manip"]["data-value"]) < 1e-9

    el = run_page(page("puma560", pages_dir), [0.1, 0.5, -0.6, 0.2, 0.8, 0.3])
    assert el["rk-sing"]["data-singular"] == "false"


def test_python_readouts_agree_with_pinocchio():
    """teach_readouts (the notebook's numbers) against independent numpy/Pinocchio formulas."""
    import pinocchio as pin

    r = robot("ur5")
    q = r.random_configuration(3)
    out = teach_readouts(r, q)
    J = r.jacobian(q, reference="local_world_aligned")
    assert abs(out["w"] - math.sqrt(np.linalg.det(J @ J.T))) < 1e-9
    R = pin.rpy.rpyToMatrix(*out["rpy"])
    assert np.abs(R - r.frame_pose(q)[:3, :3]).max() < 1e-9
    sing = teach_readouts(r, np.zeros(6))
    assert sing["level"] == "singular"
    Jz = r.jacobian(np.zeros(6), reference="local_world_aligned")
    assert np.linalg.norm(Jz.T @ sing["direction"]) < 1e-9


def test_decimated_meshes_stay_on_the_original_surface():
    """Every decimated vertex lies within cell·√3 of a vertex Pinocchio loaded (coal/assimp), and
    every original vertex within cell·√3 of a decimated one: the same shape, in the same frame."""
    from scipy.spatial import cKDTree

    r = robot("ur5")
    cell = 0.002
    for go in r.visual_model.geometryObjects[:3]:
        geo = go.geometry
        orig = np.asarray(geo.vertices())
        parts = mesh_parts(go.meshPath, cell)
        dec = np.vstack([V for V, _, _ in parts])
        tol = cell * math.sqrt(3) + 1e-9
        assert cKDTree(orig).query(dec)[0].max() <= tol, go.name
        assert cKDTree(dec).query(orig)[0].max() <= tol, go.name
        assert sum(len(F) for _, F, _ in parts) < geo.num_tris


def test_cluster_decimate_keeps_a_coarse_mesh_and_drops_collapsed_triangles():
    V = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0.0001, 0, 0]], float)
    F = np.array([[0, 1, 2], [0, 3, 2], [1, 2, 0]])
    newV, newF = cluster_decimate(V, F, 0.01)
    assert len(newV) == 3 and len(newF) == 1  # [0, 3, 2] collapsed; [1, 2, 0] repeats [0, 1, 2]
    assert np.allclose(np.sort(newV, axis=0), np.sort(np.array([[5e-5, 0, 0], [1, 0, 0], [0, 1, 0]]), axis=0))
    with pytest.raises(ValueError):
        cluster_decimate(V, F, 0.0)


def test_cli_writes_the_page_and_rejects_bad_input(tmp_path, capsys):
    out = tmp_path / "twolink.html"
    assert cli_main(["teach", "twolink", "-o", str(out)]) == 0
    text = out.read_text(encoding="utf-8")
    assert "MeshCat.Viewer" in text and 'id="rk-robot"' in text
    assert "http://" not in text.split('id="rk-robot"')[1] and "https://" not in text.split('id="rk-robot"')[1]
    capsys.readouterr()
    assert cli_main(["teach", "no_such_robot", "-o", str(tmp_path / "x.html")]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith("robokit: ")
    assert not (tmp_path / "x.html").exists()
    assert cli_main(["teach", "twolink", "-o", str(tmp_path / "x.txt")]) == 2
    assert cli_main(["teach", "twolink", "-o", str(tmp_path / "nofolder" / "x.html")]) == 2
    assert sorted(p.name for p in tmp_path.iterdir()) == ["twolink.html"]


def test_cli_without_output_writes_a_temporary_page(monkeypatch, capsys):
    """Without -o the page goes to a new temporary file, which is handed to the web browser."""
    import webbrowser

    from robokit.commands import teach_command

    opened = []
    monkeypatch.setattr(webbrowser, "open", lambda url, *a, **k: opened.append(url))
    assert teach_command("twolink") == 0
    path = Path(capsys.readouterr().err.strip().split("wrote ")[1].split(" (")[0])
    try:
        assert path.is_file() and path.suffix == ".html"
        assert opened == [path.resolve().as_uri()]
        assert 'id="rk-robot"' in path.read_text(encoding="utf-8")
    finally:
        path.unlink(missing_ok=True)


# --------------------------------------------------------------------------- layout, in one browser run
SIZES = [(1280, 800), (1600, 1100), (800, 1000)]
#: the pose per robot: stretched out (UR5 and PUMA at zero reach sideways; the Panda leaning forward)
LAYOUT_Q = {"ur5": np.zeros(6), "puma560": np.zeros(6), "panda": np.array([0.0, 1.2, 0.0, -0.4, 0.0, 1.6, 0.8])}
RED = 0xE0302A

_HARNESS_JS = """
var got = {};
function poll() {
  var fr = document.querySelectorAll("iframe"), done = 0;
  fr.forEach(function (f, i) {
    try {
      var d = f.contentDocument, e = d && d.getElementById("rk-framing"), c = d && d.getElementById("rk-collision");
      if (e && e.dataset.robot) {
        var names = Array.prototype.map.call(d.querySelectorAll(".rk-joint-name"), function (n) {
          return { text: n.textContent, sw: n.scrollWidth, cw: n.clientWidth, sh: n.scrollHeight, ch: n.clientHeight,
                   overflow: getComputedStyle(n).textOverflow };
        });
        got[i] = { framing: Object.assign({}, e.dataset), names: names, collision: Object.assign({}, c.dataset),
                   collisionText: c.textContent };
        done++;
      }
    } catch (err) { got[i] = { error: String(err) }; done++; }
  });
  document.getElementById("out").textContent = JSON.stringify(got);
  if (done < fr.length) { setTimeout(poll, 200); }
}
window.addEventListener("load", function () { setTimeout(poll, 100); });
"""


def run_harness(harness: Path):
    """Open a harness page (pages in iframes, file access allowed) in headless Chromium and return
    the JSON its script wrote into ``<pre id="out">``."""
    import html as html_mod
    import re

    with tempfile.TemporaryDirectory(ignore_cleanup_errors=True) as profile:
        out = subprocess.run(
            [CHROMIUM, "--headless", "--no-sandbox", "--disable-gpu", "--enable-unsafe-swiftshader",
             "--use-angle=swiftshader", "--disable-quic", "--no-first-run", "--disable-background-networking",
             "--disable-component-update", "--disable-sync", f"--user-data-dir={profile}",
             "--allow-file-access-from-files", "--virtual-time-budget=40000", "--dump-dom", harness.as_uri()],
            capture_output=True, text=True, timeout=240)
    assert out.returncode == 0, out.stderr[-2000:]
    m = re.search(r'<pre id="out">(.*?)</pre>', out.stdout, re.S)
    assert m and m.group(1), out.stdout[-2000:]
    return json.loads(html_mod.unescape(m.group(1)))


def run_frames(frames, tmp_dir) -> list:
    """Open pages in iframes of given sizes ``[(path, q, (w, h)), …]`` in one headless Chromium run
    (a page's own layout at that viewport) and return each page's framing, joint-name and
    collision data as the page measured them."""
    tags = []
    for path, q, (w, h) in frames:
        frag = "" if q is None else "#q=" + ",".join(repr(float(v)) for v in q)
        tags.append(f'<iframe width="{w}" height="{h}" style="border:0;display:block" '
                    f'src="{path.resolve().as_uri()}{frag}"></iframe>')
    harness = Path(tmp_dir) / "harness.html"
    harness.write_text("<!DOCTYPE html><html><body>" + "".join(tags) + f"<pre id=out></pre><script>{_HARNESS_JS}"
                       "</script></body></html>", encoding="utf-8")
    got = run_harness(harness)
    assert len(got) == len(frames), f"only {len(got)} of {len(frames)} pages reported"
    return [got[str(i)] for i in range(len(frames))]


def _collision_world():
    from robokit.collision import Box, Cylinder, Sphere, World, pose_from_xyz_rpy

    obs = [Box([0.3, 0.4, 0.5], pose_from_xyz_rpy([0.6, 0.15, 0.55], [0.3, -0.2, 0.5]), name="crate"),
           Sphere(0.2, pose_from_xyz_rpy([-0.35, 0.4, 0.9], [0, 0, 0]), name="ball"),
           Cylinder(0.1, 0.9, pose_from_xyz_rpy([0.0, -0.55, 0.75], [0.4, 0.2, 0]), name="post")]
    return World(robot("puma560"), obs)


@needs_chromium
def test_layout_framing_names_and_collision_colours(pages_dir):
    """At 1280×800, 1600×1100 and 800×1000, the projected bounding box of the robot (three.js,
    at a stretched pose) lies inside the 3-D canvas (not under the side panel, the readouts or
    meshcat's controls) and fills a fair part of it; every slider label shows its full joint
    name (no clipping). On the PUMA page with obstacles, at a configuration where the World
    finds contacts, the page lists the same pairs and paints exactly the links in contact red; the
    UR5's page (collision meshes) says that the collision display needs the notebook."""
    layout = [(name, size) for name in LAYOUT_Q for size in SIZES]
    world = _collision_world()
    rng = np.random.default_rng(2)
    while True:
        q_hit = world.robot.random_configuration(rng)
        pairs = world.colliding_pairs(q_hit)
        if pairs and all(b in world.obstacle_names for _, b in pairs):
            break
    coll_page = Path(pages_dir) / "teach_puma_obstacles.html"
    coll_page.write_text(teach_page(world.robot, obstacles=world.obstacles), encoding="utf-8")
    mesh_page = Path(pages_dir) / "teach_ur5_obstacles.html"  # collision meshes: no fake numbers offline
    mesh_page.write_text(teach_page(robot("ur5"), obstacles=world.obstacles), encoding="utf-8")
    frames = [(page(name, pages_dir), LAYOUT_Q[name], size) for name, size in layout]
    frames += [(coll_page, q_hit, (1280, 800)), (mesh_page, None, (1280, 800))]
    results = run_frames(frames, pages_dir)
    mesh = results.pop()
    assert mesh["collision"]["supported"] == "false" and "notebook" in mesh["collisionText"], mesh["collision"]

    for (name, (w, h)), res in zip(layout, results):
        assert "error" not in res, res
        f = res["framing"]
        x0, y0, x1, y1 = nums(f["robot"])
        vx0, vy0, vx1, vy1 = nums(f["view"])
        assert np.allclose(nums(f["canvas"]), [vx1 - vx0, vy1 - vy0], atol=1.0), (name, w, h, f)
        where = (name, w, h, f["robot"], f["view"])
        assert vx0 - 0.5 <= x0 and x1 <= vx1 + 0.5 and vy0 - 0.5 <= y0 and y1 <= vy1 + 0.5, where
        for panel in (nums(f["side"]), nums(f["readouts"]), *map(np.array, json.loads(f["overlays"]))):
            px0, py0, px1, py1 = panel
            assert x1 <= px0 + 0.5 or px1 <= x0 + 0.5 or y1 <= py0 + 0.5 or py1 <= y0 + 0.5, (where, panel)
        assert max((x1 - x0) / (vx1 - vx0), (y1 - y0) / (vy1 - vy0)) > 0.15, where  # not a speck
        joints = robot(name).joint_names
        assert [n["text"] for n in res["names"]] == [f"q{i + 1} {j}" for i, j in enumerate(joints)]
        for n in res["names"]:
            assert n["sw"] <= n["cw"] and n["sh"] <= n["ch"] and n["overflow"] != "ellipsis", (name, w, n)

    c = results[-1]["collision"]
    assert c["supported"] == "true"
    assert sorted(map(tuple, json.loads(c["pairs"]))) == sorted(pairs)
    assert float(c["distance"]) <= 0 and world.distance(q_hit) <= 0  # in contact (depths: page estimate vs coal's EPA)
    hit_joints = {int(go.parentJoint) for go in world.geometry_model.geometryObjects
                  if any(go.name.startswith(a + "_capsule") for a, _ in pairs)}
    d = teach_data(world.robot, world=world)
    colours = json.loads(c["colours"])
    for v in d["visuals"]:
        assert (colours[v["path"]] == RED) == (v["k"] in hit_joints), (v["path"], v["k"], hit_joints)
    for k, nm in enumerate(world.obstacle_names):
        assert (colours[f"/meshcat/obstacles/{k}"] == RED) == any(nm == b for _, b in pairs)
    assert "In contact" in results[-1]["collisionText"]


def test_cli_obstacles_flag(tmp_path, capsys):
    """``robokit teach MODEL --obstacles scene.yaml``: the page carries the scene's obstacles and the
    collision data; a bad scene file exits 2 with one line and writes nothing."""
    scene = tmp_path / "scene.yaml"
    scene.write_text("padding: 0.01\nobstacles:\n  - type: sphere\n    name: ball\n    radius: 0.1\n"
                     "    pose: {xyz: [0.3, 0.3, 0.0], rpy: [0, 0, 0]}\n", encoding="utf-8")
    out = tmp_path / "rrr.html"
    assert cli_main(["teach", "rrr", "--obstacles", str(scene), "-o", str(out)]) == 0
    text = out.read_text(encoding="utf-8")
    data = json.loads(text.split('<script id="rk-robot" type="application/json">')[1].split("</script>")[0])
    c = data["collision"]
    assert c["supported"] and c["padding"] == 0.01 and c["obstacles_drawn"] == ["ball"]
    assert [g["name"] for g in c["geoms"] if g.get("type")] == ["ball"]
    capsys.readouterr()
    bad = tmp_path / "bad.yaml"
    bad.write_text("obstacles:\n  - type: box\n    colour: red\n", encoding="utf-8")
    assert cli_main(["teach", "rrr", "--obstacles", str(bad), "-o", str(tmp_path / "x.html")]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith("robokit: ")
    assert not (tmp_path / "x.html").exists()


@needs_chromium
def test_pages_open_at_a_ready_pose_clear_of_singularities(pages_dir):
    """Both teach pages opened at q = 0, singular for the UR5 and the PUMA: a red "Singular" banner
    was the first thing a student saw. Now the page (no #q) opens at ready_pose, where the page says
    "no singularity nearby" and Pinocchio's Jacobian agrees (σmin/σmax above the page's threshold)."""
    import pinocchio as pin

    from robokit.viz.teach import SINGULAR_RATIO, ready_pose, task_rows

    for name in ("ur5", "puma560"):
        r = robot(name)
        label, q = ready_pose(r)
        el = run_page(page(name, pages_dir))  # no fragment: the page's own opening pose
        assert np.array_equal(nums(el["rk-q"]["data-q"]), q), name
        assert el["rk-sing"]["data-level"] == "ok" and el["rk-sing"]["class"] == "rk-ok", (name, el["rk-sing"])
        assert el["rk-sing"]["data-singular"] == "false"
        data = r.model.createData()
        J = pin.computeFrameJacobian(r.model, data, q, r.tip_id, pin.ReferenceFrame.LOCAL_WORLD_ALIGNED)
        s = np.linalg.svd(np.vstack([J[3:], J[:3]])[task_rows(r)], compute_uv=False)
        assert s[-1] / s[0] >= SINGULAR_RATIO, (name, s)
        assert label in teach_data(r)["poses"]  # a button to come back to it
        assert np.all(q >= r.qlim[:, 0]) and np.all(q <= r.qlim[:, 1])
    assert ready_pose(robot("panda"))[0] == "ready"  # a model's own ready pose, when it is clear, is kept


def test_notebook_pendant_opens_at_the_ready_pose():
    pytest.importorskip("ipywidgets")
    from robokit.viz import Scene
    from robokit.viz.teach import ready_pose

    with Scene(robot("ur5")) as scene:
        pendant = scene.teach()
        assert np.allclose(scene.q, ready_pose(robot("ur5"))[1])
        assert pendant.readouts["level"] == "ok"
