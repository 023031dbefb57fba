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


ASAN_DRIVER = r"""
#include <stdio.h>
#include <stdlib.h>
#include "@P@.h"
static const double POSES[][16] = {
@POSES@
};
int main(void)
{
    const int n = (int)(sizeof POSES / sizeof POSES[0]);
    double q1[@P@_MAX_SOLUTIONS * @P@_N], q2[@P@_MAX_SOLUTIONS * @P@_N];
    int info[4 * @P@_MAX_SOLUTIONS], k, total = 0;
    /* exactly NAME_IK_WORKSPACE_SIZE bytes on the heap: AddressSanitizer flags any access past it */
    @P@_ik_workspace *ws = (@P@_ik_workspace *)malloc(@P@_IK_WORKSPACE_SIZE);
    if (!ws) {
        return 2;
    }
    for (k = 0; k < n; ++k) {
        const int a = @P@_ik(POSES[k], q1), b = @P@_ik_ws(POSES[k], 0.0, q2, info, ws);
        if (a != b) {
            return 3;
        }
        total += a;
    }
    free(ws);
    printf("%d\n", total);
    return 0;
}
"""


@pytest.mark.parametrize("arm", ["jaco", "puma_offset"])
def test_general_6r_c_stays_in_its_workspace(cc, tmp_path, arm):
    """The generated general-6R IK under AddressSanitizer and UBSan, with NAME_ik_ws given a heap
    workspace of exactly NAME_IK_WORKSPACE_SIZE bytes: no access outside it or outside the stack
    buffers, on random poses, a pose with the eigenvalue joint at the half-angle's infinity (the
    turned variable) and an arm a hair from a spherical wrist (badly conditioned readings: all four
    readings solved); NAME_ik (workspace on its stack) returns as many solutions."""
    import numpy as np
    from dataclasses import replace

    from robokit.description.dh import DHTable
    from robokit.ik import analytic_ik, ik_analytic

    probe = subprocess.run([cc, "-fsanitize=address,undefined", "-x", "c", "-", "-o", str(tmp_path / "probe")],
                           input="int main(void) { return 0; }\n", capture_output=True, text=True)
    if probe.returncode != 0:
        pytest.skip(f"{cc} cannot build with -fsanitize=address,undefined here")
    if arm == "jaco":
        robot = robokit.load(jaco2_table())
        nominal = None
    else:
        t = robokit.load("puma560").dh
        rows = [replace(link, a=link.a + (1e-6 if i == 3 else 0.0)) for i, link in enumerate(t.links)]
        robot = robokit.load(DHTable("puma_eps", t.convention, tuple(rows), base=t.base, tool=t.tool))
        nominal = False
    rng = np.random.default_rng(8)
    qs = [rng.uniform(-np.pi, np.pi, 6) for _ in range(6)]
    if arm == "jaco":
        sv = analytic_ik(robot).solver.export_constants()
        pivot = int(sv["arrangements"][0]["roles"][0])
        q = np.array([0.4, -0.7, 1.1, 0.5, -0.9, 0.3])
        q[pivot] = math.remainder(sv["gamma"] + math.pi - sv["th0"][pivot], 2 * math.pi)
        qs.append(q)
    poses = [robot.frame_pose(q) for q in qs]
    src = generate_c(robot, nominal=nominal)
    P = src.name
    write_c(src, tmp_path)
    text = ",\n".join("    {" + ", ".join(repr(float(x)) for x in T.reshape(-1)) + "}" for T in poses)
    (tmp_path / "drv.c").write_text(ASAN_DRIVER.replace("@P@", P).replace("@POSES@", text))
    exe = tmp_path / "drv"
    subprocess.run([cc, "-std=c99", "-g", "-O1", "-fsanitize=address,undefined", "-fno-sanitize-recover=all",
                    f"-I{tmp_path}", str(tmp_path / "drv.c"), str(tmp_path / f"{P}.c"), "-o", str(exe), "-lm"],
                   check=True)
    res = subprocess.run([str(exe)], capture_output=True, text=True)
    assert res.returncode == 0, res.stderr[-3000:]
    expected = sum(len(ik_analytic(robot, T, nominal=nominal)) if nominal is not None else len(ik_analytic(robot, T))
                   for T in poses)
    assert int(res.stdout) == expected
