"""robokit's layering, enforced: every module imports only its own layer or the ones below it,
and no private name (``_x``) is imported from another subpackage.

Layers, bottom to top: the helpers (``_arrays``, ``_io``, ``_yaml``, ``errors``); ``spatial``
(no robot in it); ``kernels`` (the compiled recursions); ``description`` (DH tables, files,
the Robot); ``kinematics``; ``dynamics``; ``ik``; ``trajectory``; ``control``, ``mobile`` and
``symbolic``; ``viz``; ``workspace``; ``validation``; ``commands`` and ``cli``.
"""
import ast
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1] / "robokit"

LAYER = {
    "_arrays": 0, "_io": 0, "_xml": 0, "_yaml": 0, "errors": 0,
    "spatial": 1,
    "kernels": 2,
    "description": 3, "models": 3,
    "kinematics": 4,
    "dynamics": 5,
    "ik": 6,
    "trajectory": 7,
    "control": 8, "mobile": 8, "symbolic": 8,
    "viz": 9,
    "workspace": 10,
    "validation": 11,
    "commands": 12, "cli": 12,
}


def _unit(module: str) -> str:
    parts = module.split(".")
    return parts[1] if len(parts) > 1 and parts[0] == "robokit" else ""


def _modules():
    for path in sorted(ROOT.rglob("*.py")):
        rel = path.relative_to(ROOT.parent).with_suffix("")
        name = ".".join(rel.parts)
        if name == "robokit.__init__":
            continue  # the package root re-exports the public names of every layer
        yield name.removesuffix(".__init__"), path


def _imports(path: Path):
    tree = ast.parse(path.read_text(encoding="utf-8"))
    for node in ast.walk(tree):
        if isinstance(node, ast.ImportFrom) and node.module and node.level == 0:
            if node.module == "robokit":
                yield node.lineno, "robokit", [a.name for a in node.names]
            elif node.module.startswith("robokit."):
                yield node.lineno, node.module, [a.name for a in node.names]
        elif isinstance(node, ast.Import):
            for a in node.names:
                if a.name == "robokit" or a.name.startswith("robokit."):
                    yield node.lineno, a.name, []


MODULES = list(_modules())


def test_every_unit_has_a_layer():
    units = {_unit(name) for name, _ in MODULES}
    assert units <= set(LAYER), sorted(units - set(LAYER))


@pytest.mark.parametrize("name,path", MODULES, ids=[m for m, _ in MODULES])
def test_imports_point_down(name, path):
    me = _unit(name)
    bad = []
    for line, target, names in _imports(path):
        unit = _unit(target)
        if target == "robokit":
            bad.append(f"line {line}: imports the package root 'robokit' (import the subpackage instead)")
            continue
        if LAYER[unit] > LAYER[me]:
            bad.append(f"line {line}: {target} ({unit}, layer {LAYER[unit]}) is above {me} (layer {LAYER[me]})")
        if unit != me:
            private = [n for n in names if n.startswith("_") and not n.startswith("__")]
            if private:
                bad.append(f"line {line}: private name(s) {private} from another subpackage {target}")
    assert not bad, "\n".join(bad)
