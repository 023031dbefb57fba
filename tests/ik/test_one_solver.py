"""One implementation of Pieper's method, of the three-parallel-axes method and of the LM damping law
(issue 41): mechanical checks on the source (AST), so a second copy fails here.

* ``robokit/ik/pieper.py`` and ``robokit/ik/parallel_axes.py`` only build the constants: they
  solve no trigonometric equation (no ``atan2``/``acos``/``asin``/``atan``) and find no
  polynomial root (no ``roots``/``eigvals``/``eig``/``lstsq``) — the algorithm is
  :mod:`robokit.kernels.closed_form`, which they call;
* the damping ``λ`` of a Levenberg–Marquardt step is computed only by
  :mod:`robokit.kernels.lm_damping`: both LM loops call it, and no module scales a ``lam``
  variable by a constant of its own (Marquardt's ``λ/3``, ``10λ``).
"""
from __future__ import annotations

import ast
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2] / "robokit"
#: Modules that still scale a damping of their own, with the reason; an entry that no longer matches fails.
OTHER_DAMPING = {
    "kernels/calibrated_ik.py":
        "the calibrated arm's polish: Newton steps from a closed-form start, falling back to a damping "
        "relative to max diag(JᵀJ) (λ ← λ/10, 10λ) only when Newton fails; a local polish, not the global "
        "LM — its own module's owner (issue 43) decides whether it takes lm_damping",
}
SOLVING = {"atan2", "acos", "asin", "atan", "arctan2", "arccos", "arcsin", "roots", "eigvals", "eig", "lstsq"}


def _calls(tree: ast.AST) -> set[str]:
    out = set()
    for n in ast.walk(tree):
        if isinstance(n, ast.Call):
            f = n.func
            out.add(f.attr if isinstance(f, ast.Attribute) else getattr(f, "id", ""))
    return out


def test_the_python_solvers_only_build_constants():
    for name in ("pieper.py", "parallel_axes.py"):
        tree = ast.parse((ROOT / "ik" / name).read_text(encoding="utf-8"))
        assert not (_calls(tree) & SOLVING), (name, _calls(tree) & SOLVING)
        imported = {a.name for n in ast.walk(tree) if isinstance(n, ast.ImportFrom)
                    and n.module == "robokit.kernels.closed_form" for a in n.names}
        assert imported, f"{name} does not run robokit.kernels.closed_form"


def _scales_lam(tree: ast.AST) -> list[int]:
    """Lines where a name containing 'lam' is multiplied or divided by a number literal."""
    bad = []
    for n in ast.walk(tree):
        if isinstance(n, ast.AugAssign) and isinstance(n.op, (ast.Mult, ast.Div)):
            if "lam" in getattr(n.target, "id", "") and isinstance(n.value, ast.Constant):
                bad.append(n.lineno)
        if isinstance(n, ast.BinOp) and isinstance(n.op, (ast.Mult, ast.Div)):
            names = [getattr(s, "id", "") for s in (n.left, n.right)]
            if any("lam" in x for x in names) and any(isinstance(s, ast.Constant) for s in (n.left, n.right)):
                bad.append(n.lineno)
    return bad


def test_one_damping_law():
    for rel in ("ik/lm.py", "kernels/ik.py"):
        assert "lm_damping" in (ROOT / rel).read_text(encoding="utf-8"), rel
    found, allowed = [], set()
    for path in sorted(ROOT.rglob("*.py")):
        rel = path.relative_to(ROOT).as_posix()
        if path.name == "lm_damping.py":
            continue
        lines = _scales_lam(ast.parse(path.read_text(encoding="utf-8")))
        if lines and rel in OTHER_DAMPING:
            allowed.add(rel)
            continue
        found += [f"{rel}:{line}" for line in lines]
    assert not found, "a damping law outside robokit/kernels/lm_damping.py: " + ", ".join(found)
    assert allowed == set(OTHER_DAMPING), f"OTHER_DAMPING entries that no longer match: {set(OTHER_DAMPING) - allowed}"
