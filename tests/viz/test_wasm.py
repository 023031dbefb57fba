"""The robot's generated C compiled to WebAssembly (robokit.codegen.wasm), run in Node: its FK,
joint frames, the page's placements, Jacobian and gravity against Pinocchio, every closed-form IK
solution against ``robokit.ik_analytic`` (same order, labels, limit flags), at random configurations,
on shipped arms and on arms the repository does not ship (modified DH, general 6R, calibrated)."""
import json
import shutil
import subprocess
from importlib import resources
from pathlib import Path

import numpy as np
import pytest

import robokit
from shared_robots import robot as shared_robot
from robokit._optional import available

NODE = shutil.which("node")
needs_node = pytest.mark.skipif(NODE is None, reason="node not installed (CI installs it)")
needs_zig = pytest.mark.skipif(not available("ziglang"), reason="ziglang (the viz extra) not installed")
WASM_JS = Path(str(resources.files("robokit.viz").joinpath("teach_wasm.js")))
ROBOTS = ["puma560", "ur5", "jaco2_6n", "puma_craig", "puma_calibrated"]
TOL = 1e-9

_modules: dict = {}


def _load(name):
    if name == "jaco2_6n":  # a general 6R arm (offset wrist): the IK by elimination
        from tests.ik.test_general_6r import jaco2_table

        return robokit.load(jaco2_table())
    if name == "puma_calibrated":  # every joint placement, the base and the tool off by up to 2 mrad / 2 mm
        from tests.codegen.test_codegen import calibrated_arm

        return calibrated_arm("puma560", 1)
    if name == "puma_craig":  # the PUMA 560 in modified DH (Craig's table), no joint limits
        from robokit.description.dh import DHLink, DHTable

        h = np.pi / 2
        a, alpha, d = [0, 0, 0.4318, 0.0203, 0, 0], [0, -h, 0, -h, h, -h], [0, 0, 0.15005, 0.4318, 0, 0]
        return robokit.load(DHTable("puma_craig", "modified", tuple(
            DHLink("R", a=a[i], alpha=alpha[i], d=d[i]) for i in range(6))))
    return shared_robot(name)


def module(name):
    from robokit.codegen.wasm import wasm_module

    if name not in _modules:
        robot = _load(name)
        _modules[name] = (robot, wasm_module(robot))
    return _modules[name]


# reads {"wasm": base64, "qs": [...], "Ts": [...]} on stdin, prints what the module computes
_RUNNER = """
var RKWasm = require(process.argv[1]);
var input = JSON.parse(require("fs").readFileSync(0, "utf8"));
var k = RKWasm.load(RKWasm.decode(input.wasm));
process.stdout.write(JSON.stringify({
  n: k.n, hasIk: k.hasIk, labels: k.labels,
  fk: input.qs.map(k.fk), joints: input.qs.map(k.jointPoses), placements: input.qs.map(k.placements), jacobian: input.qs.map(k.jacobian), gravity: input.qs.map(k.gravity),
  ik: input.Ts.map(function (T) { return k.ik(T, 0); })
}));
"""


def run_node(wasm_b64, qs, Ts):
    res = subprocess.run([NODE, "-e", _RUNNER, str(WASM_JS)], input=json.dumps(
        {"wasm": wasm_b64, "qs": [list(map(float, q)) for q in qs], "Ts": [np.ravel(T).tolist() for T in Ts]}),
        capture_output=True, text=True, timeout=120)
    assert res.returncode == 0, res.stderr[-2000:]
    return json.loads(res.stdout)


def random_qs(robot, count, seed, wrist_clear=False):
    """``count`` random joint vectors inside the limits (±π where a joint has none); with
    ``wrist_clear``, |q5| ≥ 0.1 rad: ik_analytic of the calibrated PUMA (calibrated_arm("puma560", 1))
    returns no solution at FK([-2.274, -1.851, -0.976, 2.109, -0.024, 3.277]), 24 mrad from the wrist
    singularity — a defect of robokit.ik.calibrated reported to the lead, not of the module."""
    lo, hi = np.array(robot.qlim, dtype=float).T
    lo, hi = np.where(np.isfinite(lo), lo, -np.pi), np.where(np.isfinite(hi), hi, np.pi)
    rng = np.random.default_rng(seed)
    out = []
    while len(out) < count:
        q = rng.uniform(lo, hi)
        if not wrist_clear or abs(q[4]) >= 0.1:
            out.append(q)
    return np.array(out)


def test_module_imports_nothing_and_is_small():
    """A page instantiates it with an empty import object; it stays far below the page's budget."""
    if NODE is None or not available("ziglang"):
        pytest.skip("needs node and ziglang")
    _, m = module("puma560")
    assert m.wasm[:4] == b"\0asm"
    out = subprocess.run([NODE, "-e", "var m = new WebAssembly.Module(require('fs').readFileSync(0));"
                          "process.stdout.write(JSON.stringify(WebAssembly.Module.imports(m)))"],
                         input=m.wasm, capture_output=True, timeout=60)
    assert out.returncode == 0, out.stderr
    assert json.loads(out.stdout) == []
    assert len(m.wasm) < 100_000


@needs_node
@needs_zig
@pytest.mark.parametrize("name", ROBOTS)
def test_fk_jacobian_gravity_against_pinocchio(name):
    """And the joint frames (Pinocchio's oMi) and the page's placements: P[0] = I, P[k] = the
    product of the first k exponentials (robokit.fkin_space, another implementation), which carries
    every visual from its pose at q = 0 to Pinocchio's placement."""
    import pinocchio as pin

    from robokit import fkin_space

    robot, m = module(name)
    qs = random_qs(robot, 20, seed=7)
    out = run_node(m.base64(), qs, [])
    assert out["n"] == robot.n and out["hasIk"] is True
    data = robot.model.createData()
    data0 = robot.model.createData()
    pin.forwardKinematics(robot.model, data0, pin.neutral(robot.model))
    S = robot.poe.Slist
    for q, T, J, tau, joints, P in zip(qs, out["fk"], out["jacobian"], out["gravity"], out["joints"],
                                       out["placements"]):
        np.testing.assert_allclose(np.reshape(T, (4, 4)), robot.frame_pose(q), rtol=0, atol=TOL)
        pin.forwardKinematics(robot.model, data, robot.q_pin(q))
        assert len(joints) == robot.n and len(P) == robot.n + 1
        np.testing.assert_array_equal(np.reshape(P[0], (4, 4)), np.eye(4))
        for k in range(1, robot.n + 1):
            np.testing.assert_allclose(np.reshape(joints[k - 1], (4, 4)), data.oMi[k].homogeneous, rtol=0, atol=TOL)
            Pk = np.reshape(P[k], (4, 4))
            np.testing.assert_allclose(Pk, fkin_space(np.eye(4), S[:, :k], q[:k]), rtol=0, atol=TOL)
            np.testing.assert_allclose(Pk @ data0.oMi[k].homogeneous, data.oMi[k].homogeneous, rtol=0, atol=TOL)
        np.testing.assert_allclose(np.array(J), robot.jacobian(q, reference="local_world_aligned"), rtol=0, atol=TOL)
        g = pin.computeGeneralizedGravity(robot.model, data, q)
        np.testing.assert_allclose(tau, g, rtol=0, atol=TOL * max(1.0, float(np.abs(g).max())))


@needs_node
@needs_zig
@pytest.mark.parametrize("name", ROBOTS)
def test_every_ik_solution_equals_ik_analytic(name):
    robot, m = module(name)
    qs = random_qs(robot, 20, seed=11, wrist_clear=name == "puma_calibrated")
    Ts = [robot.frame_pose(q) for q in qs]
    out = run_node(m.base64(), [], Ts)
    for q, T, sols in zip(qs, Ts, out["ik"]):
        ref = robokit.ik_analytic(robot, T)
        assert len(sols) == len(ref) > 0
        for s, r in zip(sols, ref):
            assert s["label"] == r.label
            assert s["withinLimits"] == r.within_limits and s["degenerate"] == r.degenerate
            np.testing.assert_allclose(s["q"], r.q, rtol=0, atol=TOL)
        # the configuration the target came from is one of them (up to whole turns)
        d = [np.abs(np.angle(np.exp(1j * (np.array(s["q"]) - q)))).max() for s in sols]
        assert min(d) < 1e-7
        # and each solution reaches the target (Pinocchio's FK)
        for s in sols:
            np.testing.assert_allclose(robot.frame_pose(s["q"]), T, rtol=0, atol=1e-8)


@needs_node
@needs_zig
def test_dls_follows_a_small_step_of_a_redundant_arm():
    """Panda (7 joints, no closed form): damped least squares in the module reaches a target a
    small step away (Pinocchio's FK of the result) and moves only in the row space of J."""
    from robokit.codegen.wasm import wasm_module

    robot = robokit.load("panda")
    m = wasm_module(robot)
    q0 = np.array([0.1, -0.4, 0.2, -2.0, 0.1, 1.6, 0.5])
    T = robot.frame_pose(q0 + np.array([0.03, -0.02, 0.04, 0.02, -0.03, 0.01, 0.02]))
    script = ("var RKWasm = require(process.argv[1]); var i = JSON.parse(require('fs').readFileSync(0, 'utf8'));"
              "var k = RKWasm.load(RKWasm.decode(i.wasm));"
              "process.stdout.write(JSON.stringify([k.hasIk, k.ik(i.T, 0), k.dls(i.T, i.q, 0.01, 200, 1e-12)]))")
    res = subprocess.run([NODE, "-e", script, str(WASM_JS)], capture_output=True, text=True, timeout=120,
                         input=json.dumps({"wasm": m.base64(), "T": T.ravel().tolist(), "q": q0.tolist()}))
    assert res.returncode == 0, res.stderr[-2000:]
    has_ik, ik, dls = json.loads(res.stdout)
    assert has_ik is False and ik is None
    assert dls["steps"] > 0
    q = np.array(dls["q"])
    np.testing.assert_allclose(robot.frame_pose(q), T, rtol=0, atol=TOL)
    # no null-space motion: q − q0 stays (to first order) in the row space of J(q0)
    J = robot.jacobian(q0, reference="local_world_aligned")
    dq = q - q0
    null = np.linalg.svd(J)[2][-1]
    # (the step that generated T has 14 % of its length along J's null space; DLS's has 0.2 %)
    assert abs(null @ dq) < 0.02 * np.linalg.norm(dq)
