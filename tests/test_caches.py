"""Module-level caches cannot grow silently (read from the source, by AST).

A Robot is immutable, so what is computed from one lives with it (``Robot.derived``) and no module
keeps a table of robots keyed by their identity. This test lists every module-level mutable
container and every ``functools`` cache decorator of the package and checks each against the
inventory below, where it has a kind and a reason: a new one fails here until it is added — and
the kind ``cache`` (values computed from robot data and kept for later calls) holds at most two
purposes, each documented in docs/caches.md.
"""
from __future__ import annotations

import ast
from pathlib import Path

import robokit

ROOT = Path(robokit.__file__).resolve().parent
DOCS = ROOT.parent / "docs" / "caches.md"

#: module:name → (kind, purpose). Kinds: "cache" (robot data kept between calls: at most two
#: purposes), "memo" (a pure function of a string, nothing of a robot), "registry" (code registered
#: at import or compile time), "state" (once-per-process flags).
INVENTORY: dict[str, tuple[str, str]] = {
    # the two caches (docs/caches.md)
    "kinematics/poe.py:_VALIDATED": ("cache", "seed arguments"),
    "dynamics/newton_euler.py:_MODELS": ("cache", "seed arguments"),
    "dynamics/newton_euler.py:_SEEN": ("cache", "seed arguments"),
    "dynamics/newton_euler.py:_ZEROS": ("cache", "seed arguments"),
    "_arrays.py:_SEEN": ("cache", "seed arguments"),
    "workspace/capability.py:_WORKER_CACHE": ("cache", "a Dask worker's robots"),
    # not robot data
    "description/xacro_expr.py:_parse": ("memo", "syntax trees of xacro expressions, by their text"),
    "codegen/ik_general.py:_template": ("memo", "the shipped C templates' text, by file name"),
    "validation/core.py:_loaded": ("memo", "the shipped models by name, for one `robokit validate` run"),
    "kernels/_jit.py:_TWINS": ("registry", "compiled kernels"),
    "kernels/_jit.py:_TWIN_GLOBALS": ("registry", "compiled kernels"),
    "kernels/_jit.py:_TYPES": ("registry", "compiled kernels"),
    "kernels/_jit.py:_ACCEPTED": ("registry", "compiled kernels"),
    "kernels/_jit.py:_KERNELS": ("registry", "compiled kernels"),
    "kernels/_jit.py:_COMPILED": ("registry", "compiled kernels"),
    "description/robot.py:_WRITER": ("registry", "the writer behind Robot.save"),
    "kernels/_cache.py:_DIGESTS": ("memo", "the digest of a kernel folder's sources, by its path (once per process)"),
    "__init__.py:_HOME": ("state", "the package's lazily imported names"),
    "_deprecation.py:_WARNED": ("state", "deprecations warned once per process"),
    "motion/plan.py:_SEEDED": ("state", "OMPL's one seed per process"),
}

_MUTABLE_CALLS = {"dict", "set", "list", "OrderedDict", "defaultdict", "WeakKeyDictionary", "WeakValueDictionary",
                  "WeakSet"}


def _is_mutable_container(value: ast.expr) -> bool:
    if isinstance(value, (ast.Dict, ast.Set, ast.List)):
        return not (value.keys if isinstance(value, ast.Dict) else value.elts)  # an empty literal is filled later
    if isinstance(value, ast.Call):
        func = value.func
        name = func.attr if isinstance(func, ast.Attribute) else func.id if isinstance(func, ast.Name) else ""
        return name in _MUTABLE_CALLS and not value.args  # dict(...) of something is a constant table
    return False


def _module_caches() -> dict[str, int]:
    """module:name → line of every module-level empty mutable container and functools cache."""
    found = {}
    for path in sorted(ROOT.rglob("*.py")):
        rel = path.relative_to(ROOT).as_posix()
        tree = ast.parse(path.read_text(encoding="utf-8"))
        for node in tree.body:
            if isinstance(node, ast.Assign) and _is_mutable_container(node.value):
                for target in node.targets:
                    if isinstance(target, ast.Name):
                        found[f"{rel}:{target.id}"] = node.lineno
            elif isinstance(node, ast.AnnAssign) and node.value is not None and _is_mutable_container(node.value):
                if isinstance(node.target, ast.Name):
                    found[f"{rel}:{node.target.id}"] = node.lineno
            elif isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)):
                for dec in node.decorator_list:
                    text = ast.unparse(dec)
                    if "lru_cache" in text or text.endswith("cache") or "cached_property" in text:
                        found[f"{rel}:{node.name}"] = node.lineno
    return found


def test_every_module_level_cache_is_in_the_inventory():
    found = _module_caches()
    new = sorted(set(found) - set(INVENTORY))
    assert not new, (f"module-level containers/caches not in tests/test_caches.py's inventory (a Robot never "
                     f"changes: keep robot data with it, Robot.derived): {[f'{k} (line {found[k]})' for k in new]}")
    gone = sorted(set(INVENTORY) - set(found))
    assert not gone, f"inventory entries no longer in the code (delete them): {gone}"


def test_at_most_two_caches_each_documented():
    purposes = sorted({purpose for kind, purpose in INVENTORY.values() if kind == "cache"})
    assert len(purposes) <= 2, purposes
    text = DOCS.read_text(encoding="utf-8")
    for name, (kind, purpose) in INVENTORY.items():
        if kind == "cache":
            assert name.split(":")[1] in text and purpose.lower() in text.lower(), (name, purpose)


def test_no_module_keeps_robots_by_identity():
    """No module-level table is indexed by ``id(...)`` (of a robot, a table, an array) but the
    compiled-kernel registry's (dispatchers are module constants: their ids are never reused), the
    seed library's last-arrays check (it holds the arrays and compares their bytes) and the nested-list
    conversions of the seed arguments (each kept with a snapshot of the list it came from, reused only
    while the argument still compares equal to it)."""
    allowed = {"kernels/_jit.py", "dynamics/newton_euler.py", "_arrays.py"}
    bad = []
    for path in sorted(ROOT.rglob("*.py")):
        rel = path.relative_to(ROOT).as_posix()
        if rel in allowed:
            continue
        tree = ast.parse(path.read_text(encoding="utf-8"))
        module_names = {t.id for n in tree.body if isinstance(n, (ast.Assign, ast.AnnAssign))
                        for t in (n.targets if isinstance(n, ast.Assign) else [n.target]) if isinstance(t, ast.Name)}
        for node in ast.walk(tree):
            key = None
            if isinstance(node, ast.Subscript) and isinstance(node.value, ast.Name) and node.value.id in module_names:
                key = node.slice
            elif (isinstance(node, ast.Call) and isinstance(node.func, ast.Attribute)
                  and isinstance(node.func.value, ast.Name) and node.func.value.id in module_names
                  and node.func.attr in ("get", "setdefault", "pop") and node.args):
                key = node.args[0]
            if key is not None and any(isinstance(c, ast.Call) and isinstance(c.func, ast.Name) and c.func.id == "id"
                                       for c in ast.walk(key)):
                bad.append(f"{rel}:{node.lineno}")
    assert not bad, f"module-level tables keyed by id(): {bad}"
