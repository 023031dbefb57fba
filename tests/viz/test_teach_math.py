"""The teach page's presentation math (``teach_math.js``, DOM-free, run with Node) checked directly
against Pinocchio and numpy: its readouts over the robot's own module (pose, RPY, quaternion, Jacobian,
w, cond, σ_min, level, lost direction, margins) against ``teach_readouts`` (Pinocchio), its SVD, RPY and
quaternion on random inputs against numpy / Pinocchio, the fragment parser, the camera fit."""
import json
import math
import shutil
import subprocess
from importlib import resources
from pathlib import Path

import numpy as np
import pytest

from robokit._optional import available

NODE = shutil.which("node")
needs_node = pytest.mark.skipif(NODE is None, reason="node not installed (CI installs it)")
MATH_JS = Path(str(resources.files("robokit.viz").joinpath("teach_math.js")))
WASM_JS = Path(str(resources.files("robokit.viz").joinpath("teach_wasm.js")))
needs_zig = pytest.mark.skipif(not available("ziglang"), reason="ziglang (the viz extra) not installed")


def _stanford():
    """A spatial R-R-P-R-R-R arm (Stanford-like) with one prismatic joint, as a DH table."""
    from robokit.description.dh import DHLink, DHTable

    h = math.pi / 2
    links = (DHLink(joint="R", d=0.4, alpha=-h, qlim=(-3, 3)), DHLink(joint="R", d=0.15, alpha=h, qlim=(-2, 2)),
             DHLink(joint="P", alpha=0.0, qlim=(0.1, 0.8)), DHLink(joint="R", alpha=-h),
             DHLink(joint="R", alpha=h, qlim=(-2, 2)), DHLink(joint="R", d=0.1))
    return DHTable("stanford", "standard", links)


def _robots():
    import robokit

    return {"puma560": robokit.load("puma560"), "ur5": robokit.load("ur5"), "panda": robokit.load("panda"),
            "twolink": robokit.load("twolink"), "stanford": robokit.load(_stanford())}


def _inf_to_none(x):
    return [None if not math.isfinite(v) else float(v) for v in np.ravel(x)]


def reference_case(robot, q) -> dict:
    """The page's data and ``teach_readouts`` (Pinocchio) at q, JSON-able (∞ → null)."""
    from robokit.viz.teach import teach_parameters, teach_readouts

    r = teach_readouts(robot, q)
    sv = np.linalg.svd(r["J"][r["rows"]], compute_uv=False)
    return {"robot": robot.name, "params": teach_parameters(robot), "q": [float(v) for v in q],
            "T": np.asarray(r["T"]).ravel().tolist(), "rpy": [float(v) for v in r["rpy"]],
            "quat": [float(v) for v in r["quat"]], "J": np.asarray(r["J"]).tolist(), "w": float(r["w"]),
            "cond": None if not math.isfinite(r["cond"]) else float(r["cond"]), "sigma_min": r["sigma_min"],
            "sigma": sv.tolist(), "level": r["level"], "direction": [float(v) for v in r["direction"]],
            "margins": _inf_to_none(r["margins"]),
            "margin_joint": r["margin_joint"] if math.isfinite(r["margin"]) else None}


def reference_cases(robot) -> list:
    """Zero (singular for several arms), the PUMA's "qr", and random configurations away from the
    RPY gimbal lock."""
    qs = [np.zeros(robot.n)]
    rng = np.random.default_rng([7, len(robot.name)])
    lo, hi = np.clip(robot.qlim[:, 0], -3, 3), np.clip(robot.qlim[:, 1], -3, 3)
    while len(qs) < 4:
        q = rng.uniform(lo, hi)
        if abs(robot.frame_pose(q)[2, 0]) < 0.99:  # |pitch| well below 90°
            qs.append(q)
    if robot.name == "puma560":
        qs.append(np.array([0.0, math.pi / 2, -math.pi / 2, 0.0, 0.0, 0.0]))
    return [reference_case(robot, q) for q in qs]


@pytest.fixture(scope="module")
def cases():
    """Per robot: its module (base64) and its reference cases."""
    from robokit.codegen.wasm import wasm_module

    return [(wasm_module(robot).base64(), reference_cases(robot)) for robot in _robots().values()]


def _close(a, b, tol):
    """Equal to ``tol`` (absolute; the caller scales it to the quantity), equal infinities/None included."""
    a = np.array([np.inf if v is None else v for v in np.ravel(a)], dtype=float)
    b = np.array([np.inf if v is None else v for v in np.ravel(b)], dtype=float)
    if a.shape != b.shape:
        return False
    same = a == b  # equal infinities included
    diff = np.abs(np.where(same, 0.0, a) - np.where(same, 0.0, b))
    return bool(np.all(same | (diff <= tol)))


def scales(case: dict) -> dict:
    """Each readout's scale, so that a tolerance is relative to the size of the quantity.

    Lengths (T's translation, J's linear rows, prismatic margins) and angles are compared relative
    to the largest entry (at least 1: rotation entries and unit axes); w = Πσᵢ relative to
    σ_max^m (a σᵢ perturbed by ε·σ_max moves w by at most that much); cond = σ_max/σ_min relative
    to cond·(1 + cond), since σ_min is known only to ε·σ_max — its relative error grows with cond."""
    def big(x):
        return max([1.0] + [abs(float(v)) for v in np.ravel(x) if v is not None and math.isfinite(v)])

    s = case["sigma"]
    cond = case["cond"]
    return {"q": big(case["q"]), "T": big(case["T"]), "rpy": math.pi, "quat": 1.0, "J": big(case["J"]),
            "w": max(max(s), 1e-300) ** len(s), "sigma_min": max(max(s), 1e-300), "direction": 1.0,
            "margins": big(case["margins"]), "cond": 1.0 if cond is None else cond * (1.0 + cond)}



def test_tolerance_scales_with_the_quantity(cases):
    """The comparison below is relative: a change of 1e-10 of a quantity's scale is caught whatever
    its size, a round-off change of 1e-14 of it is not."""
    case = next(c for _, cs in cases for c in cs if c["robot"] == "panda" and c["cond"] and c["cond"] > 100)
    scale = scales(case)
    for key in ("cond", "T", "w"):
        x = np.array([np.nan if v is None else v for v in np.ravel(case[key])], dtype=float)
        assert _close(x * (1 + 1e-14), case[key], 1e-12 * scale[key]), key
        assert not _close(x + 1e-10 * scale[key], case[key], 1e-12 * scale[key]), key


NODE_CHECK = r"""
const M = require(process.argv[1]), W = require(process.argv[2]);
const input = JSON.parse(require("fs").readFileSync(process.argv[3], "utf8"));
const inf = (x) => (x === null ? Infinity : x);
const out = [].concat.apply([], input.map(function (robot) {
 const kin = W.load(W.decode(robot[0]));
 return robot[1].map(function (c) {
  const P = c.params;
  const R = { n: P.n, rows: P.rows, joints: P.joints, singular_tol: P.singular_tol, singular_ratio: P.singular_ratio };
  const r = M.readouts(R, c.q, kin);
  // angles: the same mod 2 pi (a roll of +pi and one of -pi are one rotation; round-off picks either)
  const dAngle = (a, b) => Math.max.apply(null, a.map((v, i) => Math.abs(Math.atan2(Math.sin(v - b[i]), Math.cos(v - b[i])))));
  const d = (a, b) => Math.max.apply(null, a.map((v, i) => (v === inf(b[i]) ? 0 : Math.abs(v - inf(b[i])))).concat([0]));
  const J = [].concat.apply([], r.J), Jg = [].concat.apply([], c.J);
  // the lost direction is defined when the smallest singular value is simple
  const s = c.sigma, simple = s.length < 2 || s[s.length - 2] - s[s.length - 1] > 1e-6;
  return { robot: c.robot, T: d(r.T, c.T), rpy: dAngle(r.rpy, c.rpy), quat: d(r.quat, c.quat), J: d(J, Jg),
           w: Math.abs(r.w - c.w), cond: (c.cond === null ? (r.cond === Infinity ? 0 : 1) : Math.abs(r.cond - c.cond) / c.cond),
           sigma_min: Math.abs(r.sigmaMin - c.sigma_min),
           direction: simple ? d(r.direction, c.direction) : 0,
           margins: d(r.margins, c.margins), level: r.level === c.level,
           margin_joint: (r.marginJoint < 0 ? null : P.joints[r.marginJoint].name) === c.margin_joint };
 });
}));
process.stdout.write(JSON.stringify(out));
"""


def _node(script: str, *args) -> object:
    p = subprocess.run([NODE, "-e", script, "--", *map(str, args)], capture_output=True, text=True, timeout=60)
    assert p.returncode == 0, p.stderr[-2000:]
    return json.loads(p.stdout)


@needs_node
@needs_zig
def test_page_readouts_over_the_module_equal_pinocchio(cases, tmp_path):
    """teach_math.js's readouts over the robot's module (pose, RPY, quaternion, Jacobian, w, cond,
    σ_min, level, lost direction, margins) equal teach_readouts (Pinocchio, numpy's SVD) to 1e-9 of
    each quantity's scale, on five arms (a prismatic joint, a planar arm, a redundant one)."""
    path = tmp_path / "cases.json"
    path.write_text(json.dumps(cases), encoding="utf-8")
    results = _node(NODE_CHECK, MATH_JS, WASM_JS, path)
    flat = [c for _, cs in cases for c in cs]
    assert len(results) == len(flat) >= 15
    levels = {c["level"] for c in flat}
    assert {"ok", "singular"} <= levels  # both branches are exercised
    for r, case in zip(results, flat):
        scale = scales(case)
        for key in ("T", "rpy", "quat", "J", "w", "sigma_min", "direction", "margins"):
            assert r[key] <= 1e-9 * scale[key], (r["robot"], key, r[key])
        # the script's cond entry is already relative: |Δcond| / cond
        assert r["cond"] <= 1e-9 * (1.0 if case["cond"] is None else 1.0 + case["cond"]), (r["robot"], "cond", r["cond"])
        assert r["level"] and r["margin_joint"], r


PRESENTATION = r"""
const M = require(process.argv[1]);
const I = JSON.parse(require("fs").readFileSync(process.argv[2], "utf8"));
process.stdout.write(JSON.stringify({
  svd: I.matrices.map(function (A) { return M.svdLeft(A); }),
  rpy: I.poses.map(M.rpy), quat: I.poses.map(M.quaternion)
}));
"""


@needs_node
def test_svd_rpy_and_quaternion_against_numpy_and_pinocchio(tmp_path):
    """RKMath.svdLeft on random 6×n and 3×n matrices (rank-deficient ones included) against
    numpy's SVD (singular values; each left singular vector of a simple singular value up to
    sign); RKMath.rpy against pinocchio.rpy.matrixToRpy and RKMath.quaternion against
    pinocchio.Quaternion (w ≥ 0) on random rotations, near the gimbal lock and near w = 0 included."""
    import pinocchio as pin

    rng = np.random.default_rng(12)
    mats = []
    for m, n in [(6, 6), (6, 7), (6, 3), (3, 2), (2, 2), (6, 6)]:
        A = rng.normal(size=(m, n)) * rng.uniform(0.1, 2.0)
        mats.append(A)
    low = rng.normal(size=(6, 3)) @ rng.normal(size=(3, 6))  # rank 3
    mats += [low, np.diag([3.0, 2.0, 1.0, 1e-12, 0.5, 0.0])]
    Rs = [pin.exp3(rng.normal(size=3) * rng.uniform(0.1, 3.0)) for _ in range(20)]
    Rs += [pin.rpy.rpyToMatrix(0.3, math.pi / 2 - 1e-7, -0.4), pin.exp3(np.array([math.pi - 1e-9, 0.0, 0.0]))]
    poses = []
    for R in Rs:
        T = np.eye(4)
        T[:3, :3] = R
        poses.append(T.ravel().tolist())
    path = tmp_path / "in.json"
    path.write_text(json.dumps({"matrices": [A.tolist() for A in mats], "poses": poses}), encoding="utf-8")
    out = _node(PRESENTATION, MATH_JS, path)
    for A, sv in zip(mats, out["svd"]):
        U, s, _ = np.linalg.svd(A)
        m = A.shape[0]
        s_full = np.zeros(m)
        s_full[: len(s)] = s
        got = np.array([x["s"] for x in sv])
        np.testing.assert_allclose(got, s_full, rtol=0, atol=1e-12 * max(1.0, s[0]))
        for i in range(m):
            others = np.delete(s_full, i)
            if np.min(np.abs(others - s_full[i])) > 1e-6 * max(1.0, s[0]):  # a simple singular value
                assert abs(abs(np.dot(sv[i]["u"], U[:, i])) - 1.0) < 1e-9, (i, s_full)
    for R, rpy, quat in zip(Rs, out["rpy"], out["quat"]):
        np.testing.assert_allclose(pin.rpy.rpyToMatrix(*rpy), R, rtol=0, atol=1e-9)
        if abs(R[2, 0]) < 0.999:  # away from the gimbal lock the angles themselves are unique
            np.testing.assert_allclose(rpy, pin.rpy.matrixToRpy(R), rtol=0, atol=1e-9)
        ref = pin.Quaternion(R).normalized()
        ref = np.array([ref.w, ref.x, ref.y, ref.z])
        ref = ref if ref[0] >= 0 else -ref
        if ref[0] > 1e-6:  # w = 0: q and -q both have w >= 0
            np.testing.assert_allclose(quat, ref, rtol=0, atol=1e-12)
        np.testing.assert_allclose(pin.Quaternion(quat[0], *quat[1:]).toRotationMatrix(), R, rtol=0, atol=1e-12)


FRAGMENTS = r"""
const M = require(process.argv[1]);
const tests = JSON.parse(process.argv[2]);
process.stdout.write(JSON.stringify(tests.map(function (t) {
  try { return M.parseFragment(t[0], t[1]); } catch (e) { return { threw: String(e) }; }
})));
"""


@needs_node
def test_js_fragment_parser_never_throws_and_says_what_it_ignored():
    bad = ["#q=%E0%A4%A", "#q=%", "#q=1,2,NaN", "#q=1,2", "#q=1,2,3,4", "#q=1,2,1e999", "#q=,,",
           "#q=1,2,0x10", "#q=1;2;3", "#q=" + "9," * 5000 + "9", "#q=1,2,3%00", "#x=1&q=a,b,c"]
    good = [("#q=0.5,-1e-3,2", [0.5, -1e-3, 2.0]), ("#a=b&q=1,%202,3", [1.0, 2.0, 3.0]), ("#q=+1.,.5,-0", [1.0, 0.5, 0.0])]
    none = ["", "#", "#qq=1,2,3", None]
    res = _node(FRAGMENTS, MATH_JS, json.dumps([[f, 3] for f in bad + [g for g, _ in good] + none]))
    for f, r in zip(bad, res):
        assert "threw" not in r, (f, r)
        assert r["q"] is None and r["given"] and "ignored" in r["problem"] and len(r["problem"]) < 200, (f, r)
    for (f, want), r in zip(good, res[len(bad):]):
        assert r["q"] == want and r["problem"] == "", (f, r)
    for f, r in zip(none, res[len(bad) + len(good):]):
        assert r == {"q": None, "given": False, "problem": ""}, (f, r)


TARGETS = r"""
const M = require(process.argv[1]);
const tests = JSON.parse(process.argv[2]);
process.stdout.write(JSON.stringify(tests.map(function (t) {
  try { return M.parseTarget(t); } catch (e) { return { threw: String(e) }; }
})));
"""


def _distance_to_se3(T):
    """Modern Robotics' distance of a 4x4 matrix to SE(3), in numpy: ‖[[RᵀR, 0], [last row]] − I‖_F
    when det R > 0 (the position column does not count), else 1e9."""
    T = np.asarray(T, float).reshape(4, 4)
    R = T[:3, :3]
    if np.linalg.det(R) <= 0:
        return 1e9
    A = np.zeros((4, 4))
    A[:3, :3] = R.T @ R
    A[3] = T[3]
    return float(np.linalg.norm(A - np.eye(4)))


@needs_node
def test_js_target_parser_takes_poses_and_refuses_matrices_that_are_not():
    """``#T=`` names a tool pose: 16 numbers that are not (close to) a homogeneous transform — a
    scaled, sheared or mirrored rotation block, a last row other than 0 0 0 1 — are ignored with a
    message, as a malformed fragment is, rather than handed to the IK (whose solutions cannot reach
    them: robokit.ik_analytic refuses such a T). Poses, those rounded to 6 decimals included, are
    taken as written. Reference: numpy's distance to SE(3) (accepted up to 1e-3, MR's test_if_SE3)."""
    import pinocchio as pin

    rng = np.random.default_rng(12)
    poses = []
    for _ in range(20):
        T = pin.SE3.Random().homogeneous
        T[:3, 3] *= rng.uniform(0.1, 3.0)
        poses.append(T)
    rounded = [np.round(T, 6) for T in poses[:10]]
    S = np.diag([2.0, 2.0, 2.0, 1.0])
    bad = [S @ poses[0], poses[1] @ S, poses[2].copy(), poses[3].copy(), poses[4].copy(), poses[5].copy(),
           np.zeros((4, 4)), np.eye(4) * 1e-3]
    bad[2][:3, 0] *= -1  # a mirror: det R = -1
    bad[3][3] = [0.0, 0.0, 0.1, 1.0]  # a projective last row
    bad[4][0, 1] += 0.01  # sheared
    bad[5][3, 3] = 2.0
    for B in bad:
        assert _distance_to_se3(B) > 1e-3
    for T in poses + rounded:
        assert _distance_to_se3(T) <= 1e-3
    frag = lambda T: "#T=" + ",".join(repr(float(x)) for x in np.ravel(T))  # noqa: E731
    res = _node(TARGETS, MATH_JS, json.dumps([frag(T) for T in poses + rounded + bad]))
    for T, r in zip(poses + rounded, res):
        assert "threw" not in r and r["problem"] == "" and r["given"], r
        np.testing.assert_array_equal(r["T"], np.ravel(T))
    for B, r in zip(bad, res[len(poses) + len(rounded):]):
        assert "threw" not in r, r
        assert r["T"] is None and r["given"] and "ignored" in r["problem"] and "pose" in r["problem"], (B, r)
        assert len(r["problem"]) < 200, r


FIT = r"""
const M = require(process.argv[1]);
const cases = JSON.parse(process.argv[2]);
process.stdout.write(JSON.stringify(cases.map(c => M.fitCamera(c.points, c.pad, c.dir, c.fov, c.aspect, c.win))));
"""


@needs_node
def test_fit_camera_puts_every_point_inside_the_window_and_is_tight():
    """RKMath.fitCamera, checked by projecting with numpy: every point, grown by ``pad`` along the
    camera's right and up axes, lands inside the NDC window, in front of the camera, and the fit is
    tight (some point touches the window's edge in x or y)."""
    rng = np.random.default_rng(4)
    cases = []
    for _ in range(25):
        az, el = rng.uniform(-np.pi, np.pi), rng.uniform(0.1, 1.2)
        d = [np.cos(el) * np.cos(az), np.cos(el) * np.sin(az), np.sin(el)]
        xlo, ylo = -rng.uniform(0.6, 0.98), -rng.uniform(0.6, 0.98)
        cases.append({"points": (rng.normal(size=(int(rng.integers(2, 60)), 3)) * rng.uniform(0.1, 2, 3)).tolist(),
                      "pad": float(rng.uniform(0, 0.1)), "dir": d, "fov": float(rng.uniform(40, 90)),
                      "aspect": float(rng.uniform(0.5, 2.5)),
                      "win": {"xlo": xlo, "xhi": rng.uniform(0.6, 0.98), "ylo": ylo, "yhi": rng.uniform(0.6, 0.98)}})
    fits = _node(FIT, MATH_JS, json.dumps(cases))
    for c, f in zip(cases, fits):
        d = np.array(c["dir"]) / np.linalg.norm(c["dir"])
        right = np.cross(-d, [0, 0, 1.0])
        right /= np.linalg.norm(right)
        up = np.cross(right, -d)
        ty = math.tan(math.radians(c["fov"]) / 2)
        tx = ty * c["aspect"]
        t, pos = np.array(f["target"]), np.array(f["position"])
        assert np.allclose(pos - t, f["distance"] * d)
        w, pad = c["win"], c["pad"]
        worst = 0.0
        for p in np.array(c["points"]):
            for sx in (-pad, pad):
                for sy in (-pad, pad):
                    q = p + sx * right + sy * up + pad * d  # the nearest corner of the padded point
                    depth = (pos - q) @ d
                    assert depth > 0
                    x, y = (q - t) @ right / (depth * tx), (q - t) @ up / (depth * ty)
                    assert w["xlo"] - 1e-9 <= x <= w["xhi"] + 1e-9 and w["ylo"] - 1e-9 <= y <= w["yhi"] + 1e-9
                    worst = max(worst, x / w["xhi"], x / w["xlo"], y / w["yhi"], y / w["ylo"])
        assert worst > 1 - 1e-6, worst  # no closer camera would do


def test_scene_and_teach_do_not_import_each_other():
    import ast

    import robokit.viz.scene as scene_mod
    import robokit.viz.teach as teach_mod

    def imported(mod):
        tree = ast.parse(Path(mod.__file__).read_text(encoding="utf-8"))
        return {n.module for n in ast.walk(tree) if isinstance(n, ast.ImportFrom) and n.module}

    assert "robokit.viz.scene" not in imported(teach_mod)
    assert "robokit.viz.teach" in imported(scene_mod)  # one direction only
