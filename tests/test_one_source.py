"""One source for each algorithm: the screw exponential, the PoE forward kinematics and the DH
forward kinematics are written once, in the compiled kernels (``robokit/kernels/lie.py``,
``poe.py``, ``dh.py``), which run as plain Python under ``NUMBA_DISABLE_JIT`` and carry the
lecture's derivation; every other module calls them.

The check is mechanical, on the source (AST), so a new copy anywhere fails here. In every
function outside ``robokit/kernels/``:

* **a transform formula** — a function that calls ``sin`` and ``cos`` *and* builds a 4×4 array
  (``eye(4)``, ``zeros((…, 4, 4))``, ``empty``/``ones`` likewise, or a 4×4 list literal): that is
  how a screw exponential or a DH link transform is written;
* **an FK loop** — a ``for``/``while`` loop that multiplies 4×4 matrices (``@``, ``dot``,
  ``matmul``) *and*, in the same loop, calls ``sin``/``cos`` or an exponential/link-transform
  function of its own (:data:`FORMULAS`): that is how a chain is composed joint by joint.

Composing the kernel's factors (``screw_exponentials`` of ``robokit.kinematics.poe``) with
placements is not flagged: the formula is the kernel's. What remains is listed in
:data:`ALLOWED` with the reason; an entry that no longer matches fails too.
"""
from __future__ import annotations

import ast
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1] / "robokit"

TRIG = {"sin", "cos"}
#: Functions that compute a joint's transform from its angle (not the kernel's entry points).
FORMULAS = {"exp6", "matrix_exp_6", "exp_se3", "expm", "dh_transform", "dh_link_transform", "link_transform"}
PRODUCTS = {"dot", "matmul"}

#: (module path, function) → why it may keep its own formula or loop.
ALLOWED = {
    ("robokit/spatial/lie.py", "_exp6_one"):
        "the spatial library (layer 1, below the kernels: it cannot call them) behind the seed "
        "library's matrix_exp_6 and lie.exp6; robokit validate compares it with Pinocchio's exp6 "
        "(robokit/validation/spatial.py). A second Python screw exponential, kept for the layering",
    ("robokit/ik/rrr_pose.py", "_fk"):
        "the RRR arm's FK written out in closed form (c1, s23, …) for its IK's residual check: a remaining "
        "copy the DH kernel could replace (ik/ is another session's area today)",
    ("robokit/ik/_dh_chain.py", "_rx4"): "an elementary rotation about x (the DH chain's fixed twists), no joint",
    ("robokit/ik/_dh_chain.py", "_rz4"): "an elementary rotation about z (the DH chain's fixed offsets), no joint",
    ("robokit/calibration/chain.py", "frames"):
        "the calibration chain X₁ e^{[A₁]q₁} X₂ ⋯ through the spatial library's exp6. Moved onto the kernel's "
        "exponentials (equal to rounding), the calibrated robot's inertia placement "
        "changed by ~1e-2 N·m in rnea between two calibrations of the same data (tests/calibration/test_cli.py): "
        "a conditioning question of the calibration to settle first, so it stays for now",
    ("robokit/description/dh.py", "dh_transform"):
        "one link's DH matrix, used while a DH robot is loaded: loading stays free of numba "
        "(tests/test_lazy_import.py); test_dh_transform_is_the_kernels_link_transform holds it equal to the kernel",
    ("robokit/collision/scene.py", "pose_from_xyz_rpy"): "a scene file's xyz/rpy pose, no joint",
    ("robokit/validation/spatial.py", "checks"):
        "robokit validate's table: matrix_exp_6 against Pinocchio's exp6 over sampled twists (a loop over "
        "samples, not joints)",
}
#: Not Python: emitters of another language (each checked against Pinocchio on its own) are not scanned.
OTHER_LANGUAGES = {
    "robokit/codegen/": "the C emitters write C source (the generated FK/IK is compiled and compared with Pinocchio)",
    "robokit/viz/teach_math.js": "the teach page's JavaScript (tests/viz/test_teach_math.py runs it against Pinocchio)",
}


def _called(node: ast.AST) -> set[str]:
    out = set()
    for n in ast.walk(node):
        if isinstance(n, ast.Call):
            f = n.func
            out.add(f.attr if isinstance(f, ast.Attribute) else f.id if isinstance(f, ast.Name) else "")
    return out


def _is_4x4(n: ast.AST) -> bool:
    if not isinstance(n, ast.Call):
        return False
    name = n.func.attr if isinstance(n.func, ast.Attribute) else getattr(n.func, "id", "")
    a = n.args[0] if n.args else None
    if name == "eye":
        return isinstance(a, ast.Constant) and a.value == 4
    if name in ("zeros", "empty", "ones") and isinstance(a, ast.Tuple) and len(a.elts) >= 2:
        return all(isinstance(e, ast.Constant) and e.value == 4 for e in a.elts[-2:])
    if name == "array" and isinstance(a, ast.List) and len(a.elts) == 4:
        return all(isinstance(r, ast.List) and len(r.elts) == 4 for r in a.elts)
    return False


def _multiplies(node: ast.AST) -> bool:
    for n in ast.walk(node):
        if isinstance(n, (ast.BinOp, ast.AugAssign)) and isinstance(n.op, ast.MatMult):
            return True
        if isinstance(n, ast.Call) and _called(n) & PRODUCTS:
            return True
    return False


def scan(root: Path = ROOT) -> dict[tuple[str, str], list[str]]:
    """(module path, function) → what it writes of its own ("a transform formula", "an FK loop")."""
    found: dict[tuple[str, str], list[str]] = {}
    for path in sorted(root.rglob("*.py")):
        rel = path.relative_to(root.parent).as_posix()
        if rel.startswith("robokit/kernels/") or any(rel.startswith(p) for p in OTHER_LANGUAGES):
            continue
        for fn in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            if not isinstance(fn, (ast.FunctionDef, ast.AsyncFunctionDef)):
                continue
            kinds = []
            if _called(fn) & TRIG and any(_is_4x4(n) for n in ast.walk(fn)):
                kinds.append("a transform formula")
            loops = [n for n in ast.walk(fn) if isinstance(n, (ast.For, ast.While))]
            if any(_multiplies(L) and _called(L) & (TRIG | FORMULAS) for L in loops):
                kinds.append("an FK loop")
            if kinds:
                found[(rel, fn.name)] = kinds
    return found


def test_no_module_writes_its_own_exponential_or_fk_loop():
    found = scan()
    bad = [f"{m}: {fn} writes {' and '.join(k)}" for (m, fn), k in sorted(found.items()) if (m, fn) not in ALLOWED]
    assert not bad, ("call the kernels (robokit.kernels.lie.exp_screw through robokit.kinematics.poe."
                     "screw_exponentials, robokit.kernels.poe, robokit.kernels.dh) instead:\n" + "\n".join(bad))
    stale = sorted(set(ALLOWED) - set(found))
    assert not stale, f"ALLOWED entries that no longer match (delete them): {stale}"


def test_the_scan_finds_a_copy(tmp_path):
    """The signature fires on the two shapes a copy takes (so the test above can fail)."""
    pkg = tmp_path / "robokit" / "mine"
    pkg.mkdir(parents=True)
    (pkg / "copy.py").write_text(
        "import numpy as np\n"
        "def exp(w, th):\n"
        "    T = np.eye(4); T[0, 0] = np.cos(th); T[0, 1] = -np.sin(th)\n"
        "    return T\n"
        "def fk(table, q):\n"
        "    T = np.eye(4)\n"
        "    for i, l in enumerate(table):\n"
        "        T = T @ dh_transform(l.a, l.alpha, l.d, q[i])\n"
        "    return T\n")
    found = scan(tmp_path / "robokit")
    assert found == {("robokit/mine/copy.py", "exp"): ["a transform formula"],
                     ("robokit/mine/copy.py", "fk"): ["an FK loop"]}


def test_the_entry_points_are_the_kernels():
    """The public FK entry points give the kernels' own numbers (bit for bit where they are the same call)."""
    import numpy as np

    import robokit as rk
    from robokit.kernels.dh import dh_fk, pack_dh
    from robokit.kernels.poe import fkin_space_batch
    from robokit.kinematics.poe import screw_exponentials
    from robokit.workspace.grid import tool_positions

    robot = rk.load("puma560")
    Q = np.random.default_rng(0).uniform(-1.5, 1.5, (4, 6))
    P, modified, base, tool = pack_dh(robot.dh)[:4]
    for q in Q:
        np.testing.assert_array_equal(robot.dh.fk(q), dh_fk(P, modified, base, tool, q))
    M, S = np.array(robot.poe.M), np.array(robot.poe.Slist)  # writeable copies, as the kernels take them
    np.testing.assert_array_equal(tool_positions(robot.poe, Q), fkin_space_batch(M, S, Q)[:, :3, 3])
    # and against Pinocchio (independent): the PoE product of the kernel's factors
    E = screw_exponentials(S, Q)
    T = E[:, 0] @ E[:, 1] @ E[:, 2] @ E[:, 3] @ E[:, 4] @ E[:, 5] @ M
    np.testing.assert_allclose(T, robot.frame_pose(Q), atol=1e-12)


def test_dh_transform_is_the_kernels_link_transform():
    """The one DH link matrix written outside the kernels (description.dh.dh_transform, numba-free for
    loading) equals the kernel's on random rows of both conventions."""
    import numpy as np

    from robokit.description.dh import dh_transform
    from robokit.kernels.dh import dh_frames

    rng = np.random.default_rng(7)
    for _ in range(50):
        a, alpha, d, theta = rng.uniform(-3, 3, 4)
        for k, conv in enumerate(("standard", "modified")):
            row = np.array([[a, alpha, d, theta, 0.0]])
            K = dh_frames(row, k, np.eye(4), np.zeros(1))[1]
            assert np.allclose(dh_transform(a, alpha, d, theta, conv), K, rtol=0, atol=1e-15)
