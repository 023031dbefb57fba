"""The core install stays small: optional packages are imported only through
``robokit._optional.require`` (which names the extra), and ``import robokit`` imports none of them."""
from __future__ import annotations

import ast
import subprocess
import sys
import tomllib
from pathlib import Path

import pytest

from robokit._optional import EXTRAS, require
from robokit.errors import InputError, MissingExtraError

ROOT = Path(__file__).resolve().parents[1]
PKG = ROOT / "robokit"


def _type_checking_lines(tree: ast.AST) -> set[int]:
    lines: set[int] = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.If) and "TYPE_CHECKING" in ast.unparse(node.test):
            for sub in node.body:
                lines.update(range(sub.lineno, (sub.end_lineno or sub.lineno) + 1))
    return lines


def test_optional_packages_are_imported_only_through_require():
    offenders = []
    for path in sorted(PKG.rglob("*.py")):
        tree = ast.parse(path.read_text(), str(path))
        typing_only = _type_checking_lines(tree)
        for node in ast.walk(tree):
            if isinstance(node, ast.Import):
                names = [a.name for a in node.names]
            elif isinstance(node, ast.ImportFrom) and node.level == 0 and node.module:
                names = [node.module]
            else:
                continue
            for name in names:
                if name.split(".")[0] in EXTRAS and node.lineno not in typing_only:
                    offenders.append(f"{path.relative_to(ROOT)}:{node.lineno} imports {name}")
    # validation/mujoco_check.py asks whether MuJoCo is there (the MuJoCo rows are optional)
    offenders = [o for o in offenders if not o.startswith("robokit/validation/mujoco_check.py")]
    assert not offenders, "\n".join(offenders)


def test_import_robokit_pulls_in_no_optional_package():
    code = ("import sys, robokit, robokit.validation, robokit.cli; "
            f"print(sorted(m for m in sys.modules if m.split('.')[0] in {sorted(EXTRAS)!r}))")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True,
                         cwd=ROOT).stdout.strip()
    assert out == "[]", out


def test_core_dependencies_exclude_every_extra():
    project = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]
    core = {d.split(">")[0].split("=")[0].split("[")[0].strip().lower() for d in project["dependencies"]}
    dists = {dist.lower() for dist, _ in EXTRAS.values()}
    assert not core & dists, core & dists
    extras = project["optional-dependencies"]
    for top, (dist, extra) in EXTRAS.items():
        assert extra in extras, f"{top}: extra {extra!r} missing from pyproject"
        assert any(d.lower().startswith(dist.lower()) for d in extras[extra]), (top, extra)
    assert set(extras["all"][0].split("[")[1].rstrip("]").split(",")) >= {e for _, e in EXTRAS.values()}


def test_require_names_the_extra_when_missing(monkeypatch):
    monkeypatch.setitem(sys.modules, "sympy", None)  # importing it now raises ModuleNotFoundError
    with pytest.raises(MissingExtraError, match=r"pip install 'robokit\[symbolic\]'") as info:
        require("sympy", "robokit.symbolic")
    assert isinstance(info.value, ImportError) and isinstance(info.value, InputError)
    assert info.value.extra == "symbolic"


def test_cli_missing_extra_is_one_line_exit_2(tmp_path):
    # meshcat hidden from a child process: the viewer refuses in one line and writes nothing
    code = ("import sys; sys.modules['meshcat'] = None; import robokit.cli as c; "
            f"sys.exit(c.main(['view', 'twolink', '-o', {str(tmp_path / 'v.html')!r}]))")
    p = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, cwd=ROOT)
    assert p.returncode == 2, p.stderr
    lines = p.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("robokit: error:") and "robokit[viz]" in lines[0], p.stderr
    assert not (tmp_path / "v.html").exists()


def test_no_handler_rewrites_the_missing_extra_message():
    """The bypasses of issue 40: a handler that catches the ImportError of a ``require`` call (or
    raises a bare ImportError of its own) replaces robokit's message naming the extra with another
    one (``pip install xacro``, ``pip install mujoco``). Only ``except MissingExtraError`` (to add
    the file's name, keeping the extra) may wrap a ``require``."""
    offenders = []
    for path in sorted(PKG.rglob("*.py")):
        if path.name == "_optional.py":
            continue
        tree = ast.parse(path.read_text(), str(path))
        for node in ast.walk(tree):
            if isinstance(node, ast.Raise) and node.exc is not None:
                call = node.exc.func if isinstance(node.exc, ast.Call) else node.exc
                if isinstance(call, ast.Name) and call.id in ("ImportError", "ModuleNotFoundError"):
                    offenders.append(f"{path.relative_to(ROOT)}:{node.lineno} raises a bare {call.id}")
            if isinstance(node, ast.Try):
                calls_require = any(isinstance(n, ast.Call) and isinstance(n.func, ast.Name) and n.func.id == "require"
                                    for stmt in node.body for n in ast.walk(stmt))
                for h in node.handlers:
                    caught = ast.unparse(h.type) if h.type is not None else "everything"
                    if calls_require and "MissingExtraError" not in caught:
                        offenders.append(f"{path.relative_to(ROOT)}:{h.lineno} catches {caught} around require()")
    assert not offenders, "\n".join(offenders)


@pytest.mark.parametrize("hidden, code, extra", [
    ("sympy", "import robokit.symbolic", "symbolic"),
    ("xacro", "import pathlib, robokit; p = pathlib.Path('arm.urdf.xacro'); p.write_text('<robot name=\"a\"/>'); "
              "robokit.load(p)", "formats"),
    ("mujoco", "from robokit.validation.mujoco_check import mujoco_model; mujoco_model('<mujoco/>')", "mujoco"),
    ("toppra", "import robokit; robokit.retime(robokit.load('twolink'), [[0.0, 0.0], [1.0, 0.5]], 1.0, 2.0)", "motion"),
    ("matplotlib", "import robokit; robokit.trajectory.plot_trajectory(robokit.trajectory.quintic_trajectory("
                   "0.0, 1.0, 1.0))", "plot"),
])
def test_a_missing_extra_is_one_line_naming_it(hidden, code, extra, tmp_path):
    """In a fresh interpreter with the package hidden (``sys.modules[name] = None``): the error is
    robokit's ``MissingExtraError`` naming the extra, not a bare ``ModuleNotFoundError``."""
    p = subprocess.run([sys.executable, "-c", f"import sys; sys.modules[{hidden!r}] = None\n{code}"],
                       capture_output=True, text=True, cwd=tmp_path, timeout=300)
    last = p.stderr.strip().splitlines()[-1]
    assert p.returncode == 1 and last.startswith("robokit.errors.MissingExtraError:"), p.stderr[-2000:]
    assert f"pip install 'robokit[{extra}]'" in last, last
