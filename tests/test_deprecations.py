"""robokit's deprecations live in one module, each with the release that removes it.

Read from the source (AST), so a deprecation added anywhere else fails here:

* no module but ``robokit/_deprecation.py`` emits a ``DeprecationWarning`` or ``FutureWarning``
  itself: they all go through ``deprecated_alias``, ``warn``, ``warn_once``, ``renamed_argument``
  or ``robokit.frames`` (which use the registry);
* every key those are called with is in ``DEPRECATIONS`` (the renamed functions, keywords,
  frame words and changing defaults), and every entry of ``DEPRECATIONS`` is used;
* every removal version is a later release than the package's.
"""
from __future__ import annotations

import ast
import re
from pathlib import Path

import robokit
from robokit._deprecation import DEPRECATIONS, FRAME_SYNONYMS

ROOT = Path(robokit.__file__).resolve().parent
HOME = ROOT / "_deprecation.py"


def _modules():
    for path in sorted(ROOT.rglob("*.py")):
        yield path, ast.parse(path.read_text(encoding="utf-8"))


def _name(func: ast.expr) -> str:
    return func.attr if isinstance(func, ast.Attribute) else func.id if isinstance(func, ast.Name) else ""


def _version(v: str) -> tuple[int, ...]:
    return tuple(int(x) for x in re.findall(r"\d+", v)[:3])


def test_only_the_deprecation_module_warns_about_deprecations():
    bad = []
    for path, tree in _modules():
        if path == HOME:
            continue
        for node in ast.walk(tree):
            if isinstance(node, ast.Call) and _name(node.func) == "warn":
                cats = {n.id for n in ast.walk(node) if isinstance(n, ast.Name)} | {
                    n.attr for n in ast.walk(node) if isinstance(n, ast.Attribute)}
                if cats & {"DeprecationWarning", "FutureWarning", "PendingDeprecationWarning"} and not (
                        isinstance(node.func, ast.Name) and node.func.id == "warn" and _imports_registry_warn(tree)):
                    bad.append(f"{path.relative_to(ROOT.parent)}:{node.lineno}")
    assert not bad, f"deprecation warnings outside robokit/_deprecation.py (use its helpers): {bad}"


def _imports_registry_warn(tree: ast.Module) -> bool:
    return any(isinstance(n, ast.ImportFrom) and n.module == "robokit._deprecation"
               and any(a.name == "warn" for a in n.names) for n in ast.walk(tree))


def _used_keys() -> set[str]:
    """Every registry key robokit's code names: aliases' old names, keys given to warn/warn_once/
    renamed_argument, ``<where>(reference omitted)`` of reference_or_default, and the frame words."""
    used = {f"reference={w!r}" for w in FRAME_SYNONYMS}
    for _, tree in _modules():
        for node in ast.walk(tree):
            if not isinstance(node, ast.Call):
                continue
            name = _name(node.func)
            consts = [a.value for a in node.args if isinstance(a, ast.Constant) and isinstance(a.value, str)]
            if name == "deprecated_alias" and len(consts) >= 1:
                used.add(consts[0])
            elif name in ("warn", "warn_once", "renamed_argument") and node.args and isinstance(node.args[0], ast.Constant):
                used.add(node.args[0].value)
            elif name == "reference_or_default" and len(node.args) >= 3 and isinstance(node.args[1], ast.Constant):
                used.add(f"{node.args[1].value}(reference omitted)")
    return used


def test_every_deprecation_is_registered_and_every_entry_used():
    used = _used_keys()
    missing = sorted(used - set(DEPRECATIONS))
    assert not missing, f"deprecations not in robokit._deprecation.DEPRECATIONS: {missing}"
    stale = sorted(set(DEPRECATIONS) - used)
    assert not stale, f"DEPRECATIONS entries nothing uses any more (delete them): {stale}"


def test_every_deprecation_has_a_later_removal_release():
    now = _version(robokit.__version__) if robokit.__version__[0].isdigit() else (0, 0, 0)
    for key, (replacement, removal) in DEPRECATIONS.items():
        assert replacement and re.fullmatch(r"\d+\.\d+\.\d+", removal), key
        assert _version(removal) > now, (key, removal, robokit.__version__)


def test_aliases_name_their_removal_release():
    import robokit.control
    import robokit.description
    import robokit.kinematics
    import robokit.trajectory

    for module, old in [(robokit.description, "rpy_to_matrix"), (robokit.kinematics, "jacobian_to_frame"),
                        (robokit.trajectory, "cartesian_to_joint"), (robokit.control, "reflect_to_joint")]:
        alias = getattr(module, old)
        assert alias.__removal__ == DEPRECATIONS[old][1]
        assert alias.__deprecated_for__ == DEPRECATIONS[old][0]
