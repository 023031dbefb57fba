"""``import robokit`` is lazy (PEP 562): it loads no subpackage, no numba, no Pinocchio; every public
name still works as ``robokit.X``, ``from robokit import X`` and in ``dir(robokit)``. These are
properties checked in fresh interpreters (subprocesses), not timings: the start-up times are in
``benchmarks/startup.py``."""
import ast
import json
import os
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
HEAVY = ("numba", "llvmlite", "pinocchio", "scipy", "yaml", "rich")


def _fresh(code: str, **env: str) -> str:
    p = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, cwd=ROOT, timeout=300,
                       env={**os.environ, **env})
    assert p.returncode == 0, p.stderr[-3000:]
    return p.stdout.strip().splitlines()[-1]


def test_import_robokit_loads_no_subpackage_and_no_numba():
    code = ("import sys, robokit; print(sorted(m for m in sys.modules if m.split('.')[0] in "
            f"{HEAVY!r} or (m.startswith('robokit.') and m != 'robokit.errors')))")
    assert _fresh(code) == "[]"


def test_version_and_help_load_no_numba():
    code = ("import sys, contextlib, io, robokit.cli as c\n"
            "for a in (['--version'], ['--help']):\n"
            "    with contextlib.redirect_stdout(io.StringIO()):\n"
            "        try: c.main(a)\n"
            "        except SystemExit: pass\n"
            f"print(sorted(m for m in sys.modules if m.split('.')[0] in {HEAVY[:3]!r}))")
    assert _fresh(code) == "[]"


def test_numba_loads_with_the_first_kernel_call_not_before():
    """Loading a robot (Pinocchio) does not load numba; the first seed function that runs a
    compiled kernel does (ROBOKIT_COMPILE=off: no compile, the cached or interpreted kernel runs)."""
    code = ("import sys, numpy as np, robokit\n"
            "r = robokit.load('twolink'); before = 'numba' in sys.modules\n"
            "T = robokit.fkin_space(np.eye(4), np.array([[0, 0, 1, 0, 0, 0.0]]).T, np.array([0.3]))\n"
            "print(json.dumps([before, 'numba' in sys.modules, float(T[0, 0])]))")
    before, after, c = json.loads(_fresh("import json\n" + code, ROBOKIT_COMPILE="off"))
    assert before is False and after is True and c == pytest.approx(0.955336489125606)


def robokit_all():
    import robokit

    return robokit.__all__


def test_every_public_name_resolves_both_ways():
    """Each name of ``__all__`` (and the documented subpackages) as ``robokit.X`` and as
    ``from robokit import X``, in a fresh interpreter each way; both give the same object, which is
    defined in robokit; ``dir()`` lists them all (but ``symbolic``, which needs sympy to import, so
    that ``inspect.getmembers(robokit)`` works without the extra); an unknown name is an AttributeError."""
    code = ("import importlib, json, robokit\n"
            "names = list(robokit.__all__) + ['viz', 'validation', 'symbolic', 'codegen', 'kernels', '__version__']\n"
            "attr = {n: getattr(robokit, n) for n in names}\n"
            "ns = {}\n"
            "for n in names: exec(f'from robokit import {n} as x', ns); assert ns['x'] is attr[n], n\n"
            "bad = [n for n, v in attr.items() if n != '__version__' and not "
            "(getattr(v, '__name__', '').startswith('robokit') or getattr(v, '__module__', '').startswith('robokit'))]\n"
            "missing = sorted(set(names) - set(dir(robokit)) - {'symbolic'})\n"
            "try:\n    robokit.no_such_name\n    err = None\nexcept AttributeError as e:\n    err = str(e)\n"
            "print(json.dumps([len(names), bad, missing, err, robokit.__version__]))")
    count, bad, missing, err, version = json.loads(_fresh(code))
    assert count == len(robokit_all()) + 6 and bad == [] and missing == []
    assert err == "module 'robokit' has no attribute 'no_such_name'"
    assert version and version[0].isdigit()


def test_lazy_table_and_type_checking_imports_agree():
    """The name → module table that ``__getattr__`` uses and the ``TYPE_CHECKING`` imports (what
    mypy, IDEs and the docs read) list the same names from the same modules, and cover ``__all__``."""
    import robokit

    tree = ast.parse((ROOT / "robokit" / "__init__.py").read_text(encoding="utf-8"))
    block = next(n for n in tree.body if isinstance(n, ast.If) and getattr(n.test, "id", "") == "TYPE_CHECKING")
    typed = {}
    for node in block.body:
        if isinstance(node, ast.ImportFrom) and node.module == "robokit":
            typed.update({a.name: f"robokit.{a.name}" for a in node.names})
        elif isinstance(node, ast.ImportFrom):
            typed.update({a.name: node.module for a in node.names})
    lazy = dict(robokit._HOME)
    lazy.update({s: f"robokit.{s}" for s in robokit._SUBPACKAGES if s in typed})
    assert typed == lazy
    assert set(robokit.__all__) <= set(typed)
