"""The C templates (robokit/codegen/templates): each compiles on its own with the strict gcc flags and
clang's -Weverything, ships as package data, and is what the generated file contains, verbatim."""
import fnmatch
import math
import re
import subprocess
import tomllib
from importlib import resources
from pathlib import Path

import pytest

import robokit
from robokit.codegen import generate_c, write_c
from robokit.codegen import ik_general

from .test_clang import CLANG_FLAGS
from .test_codegen import jaco2_table

ROOT = Path(__file__).resolve().parents[2]
TEMPLATES = ("g6r.c", "g6r.h")
GCC_STRICT = ("-std=c99", "-Wall", "-Wextra", "-Wpedantic", "-Wshadow", "-Werror")


def _copy(tmp_path):
    for name in TEMPLATES:
        (tmp_path / name).write_text(ik_general.template(name))
    return tmp_path / "g6r.c"


def test_template_compiles_alone_gcc(cc, tmp_path):
    """g6r.c (with its header) is a translation unit of its own: the strict flags, and -O2 for the
    flow-based warnings; g6r_solve is its only external symbol."""
    src = _copy(tmp_path)
    subprocess.run([cc, *GCC_STRICT, "-O2", "-c", str(src), "-o", str(tmp_path / "g6r.o")], check=True)
    out = subprocess.run(["nm", "-g", "--defined-only", str(tmp_path / "g6r.o")], capture_output=True,
                         text=True)
    if out.returncode == 0:
        assert [line.split()[-1] for line in out.stdout.splitlines()] == ["g6r_solve"]


def test_template_compiles_alone_clang(clang, tmp_path):
    src = _copy(tmp_path)
    res = subprocess.run([clang, *CLANG_FLAGS, "-c", str(src), "-o", str(tmp_path / "g6r.o")],
                         capture_output=True, text=True)
    assert res.returncode == 0, res.stderr


def test_the_header_alone_compiles(cc, tmp_path):
    _copy(tmp_path)
    (tmp_path / "use.c").write_text('#include "g6r.h"\nint g6r_size(void);\n'
                                    "int g6r_size(void) { return G6R_WORKSPACE_DOUBLES; }\n")
    subprocess.run([cc, *GCC_STRICT, "-c", str(tmp_path / "use.c"), "-o", str(tmp_path / "use.o")], check=True)


def test_templates_are_package_data():
    """importlib.resources finds them (as an installed wheel would), and pyproject's package-data for
    robokit.codegen covers every file of the folder."""
    folder = resources.files("robokit.codegen").joinpath("templates")
    names = sorted(p.name for p in folder.iterdir() if p.name.endswith((".c", ".h")))
    assert names == sorted(TEMPLATES)
    data = tomllib.loads((ROOT / "pyproject.toml").read_text())["tool"]["setuptools"]["package-data"]
    patterns = data["robokit.codegen"]
    assert all(any(fnmatch.fnmatch(f"templates/{n}", p) for p in patterns) for n in names)


def test_generated_file_inlines_the_template_verbatim(tmp_path):
    """NAME.c holds g6r.h and g6r.c unchanged (the per-arm numbers are a const g6r_arm after them,
    no token is replaced inside the algorithm), and is still one self-contained .c + .h pair."""
    src = generate_c(robokit.load(jaco2_table()))
    body = ik_general.template("g6r.c")
    head, tail = body.split('#include "g6r.h"\n')
    assert head in src.source and tail in src.source and ik_general.template("g6r.h") in src.source
    assert "static const g6r_arm jaco2_6n_g6_arm" in src.source
    assert f"double d[{ik_general.workspace_doubles()}];" in src.header
    h_path, c_path = write_c(src, tmp_path)
    assert sorted(p.name for p in tmp_path.iterdir()) == sorted([h_path.name, c_path.name])
    assert '#include "g6r.h"' not in src.source


def test_the_turned_variable_is_the_documented_angle():
    """The half-angle turn written in g6r.c is tan(delta / 2) for ik_general's delta (the docs' 1.1 rad)."""
    m = re.search(r"const double t = ([0-9.e+-]+);", ik_general.template("g6r.c"))
    assert m is not None
    assert float(m.group(1)) == math.tan(0.5 * ik_general._ROT_DELTA)
