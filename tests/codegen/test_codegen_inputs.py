"""`robokit codegen` on hostile input (issue 39): names checked whole, file names that never shadow a
standard header, constants the target type can hold, an existing header kept without reading it.
The CLI cases run in a subprocess under an address-space limit (a safety net, never a timing) and
must give exit 2 and exactly one ``robokit: error:`` line."""
import ast
import os
import re
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "hardening"))

import hardening_support as hs  # noqa: E402
import round2_support as r2  # noqa: E402

import robokit  # noqa: E402
from robokit.codegen import STANDARD_HEADERS, c_name, generate_c, write_c  # noqa: E402

ROBOKIT = Path(robokit.__file__).resolve().parent


def _urdf(tmp_path, name="bot", lower="-3", upper="3", xyz="0.5 0 0", mass="2", ixx="0.001"):
    """The one-joint pendulum of the hardening suite with its limits, tip offset, mass and inertia
    replaced."""
    text = hs.urdf_text(
        links=[hs.link("base"), hs.link("arm", mass=mass, com="0.25 0 0", inertia=f"{ixx} 0.01 0.01 0 0 0"),
               hs.link("tip")],
        joints=[hs.joint("shoulder", "base", "arm", axis="0 -1 0", lower=lower, upper=upper),
                hs.joint("tip_joint", "arm", "tip", "fixed", xyz=xyz)],
        name=name)
    p = tmp_path / f"{name.strip() or 'bot'}.urdf"
    p.write_text(text)
    return p


# ------------------------------------------------------------------ class 1: names checked whole
@pytest.mark.parametrize("name", ["abc\n", "twolink\n", "_x\n", "a\nb"])
def test_name_with_a_newline_is_not_an_identifier(name):
    with pytest.raises(robokit.InputError, match="not a C identifier"):
        c_name("x", name)
    with pytest.raises(robokit.InputError, match="not a C identifier"):
        generate_c(robokit.load("twolink"), name=name)


def test_cli_name_with_a_trailing_newline_exits_2_and_writes_nothing(tmp_path):
    runs = r2.run_many([["codegen", "twolink", "-o", tmp_path, "--name", "abc\n"],
                        ["codegen", "twolink", "-o", tmp_path, "--name", "arm\n"]])
    for run in runs:
        hs.assert_one_line_error(run, "not a C identifier")
    assert list(tmp_path.iterdir()) == []


def _anchored_dollar(pattern: str) -> bool:
    """Whether a regular expression uses ``$`` as an anchor (not escaped, not in a class)."""
    k, in_class = 0, False
    while k < len(pattern):
        ch = pattern[k]
        if ch == "\\":
            k += 2
            continue
        if in_class:
            in_class = ch != "]"
        elif ch == "[":
            in_class = True
        elif ch == "$":
            return True
        k += 1
    return False


def test_no_regular_expression_in_robokit_anchors_with_dollar():
    """The mechanism behind class 1: a name is checked with ``fullmatch`` or ``\\Z``, never with
    ``$`` (which matches before a final newline). Every pattern literal given to ``re`` in robokit's
    source is scanned."""
    funcs = {"compile", "match", "search", "fullmatch", "sub", "subn", "split", "findall", "finditer"}
    found, scanned = [], 0
    for path in ROBOKIT.rglob("*.py"):
        tree = ast.parse(path.read_text(encoding="utf-8"))
        for node in ast.walk(tree):
            if (isinstance(node, ast.Call) and isinstance(node.func, ast.Attribute) and node.func.attr in funcs
                    and isinstance(node.func.value, ast.Name) and node.func.value.id == "re" and node.args
                    and isinstance(node.args[0], ast.Constant) and isinstance(node.args[0].value, str)):
                scanned += 1
                if _anchored_dollar(node.args[0].value):
                    found.append(f"{path.relative_to(ROBOKIT.parent)}:{node.lineno}")
    assert scanned > 20  # the scan sees robokit's patterns
    assert found == [], f"regular expressions anchored with $ (use fullmatch or \\Z): {found}"
    assert _anchored_dollar(r"^[a-z]+$") and not _anchored_dollar(r"[$]\$") and not _anchored_dollar(r"a\Z")


# ------------------------------------------------------------------ class 3: standard header names
def test_standard_header_list_is_complete_for_c11_and_posix():
    c11 = ("assert complex ctype errno fenv float inttypes iso646 limits locale math setjmp signal stdalign stdarg "
           "stdatomic stdbool stddef stdint stdio stdlib stdnoreturn string tgmath threads time uchar wchar wctype")
    posix = ("aio cpio dirent dlfcn fcntl fmtmsg fnmatch ftw glob grp iconv langinfo libgen monetary mqueue ndbm "
             "netdb nl_types poll pthread pwd regex sched search semaphore spawn strings stropts syslog tar termios "
             "trace ulimit unistd utime utmpx wordexp")
    assert set((c11 + " " + posix).split()) <= STANDARD_HEADERS


@pytest.mark.parametrize("robot_name", ["math", "string", "ERRNO", "Stdio", "unistd", "features"])
def test_a_robot_named_like_a_header_gets_another_file_name(tmp_path, robot_name):
    robot = robokit.load(_urdf(tmp_path, name=robot_name))
    src = generate_c(robot)
    assert src.name.lower() not in STANDARD_HEADERS and src.name == robot_name.lower() + "_robot"
    h, c = write_c(src, tmp_path)
    assert h.name == f"{robot_name.lower()}_robot.h"


@pytest.mark.parametrize("name", ["math", "String", "ERRNO", "pthread", "time"])
def test_name_of_a_standard_header_is_refused(name):
    with pytest.raises(robokit.InputError, match=rf"<{name.lower()}\.h>"):
        c_name("arm", name)


def test_cli_header_names_exit_2_and_the_default_name_compiles_with_minus_I(tmp_path, cc):
    """`--name math` / `--name Stdlib` exit 2 naming the header; a robot named `math` writes
    math_robot.h, and a file including <math.h> and the generated header compiles with -I on the
    folder (the system's math.h is the one found)."""
    urdf = _urdf(tmp_path, name="math")
    out = tmp_path / "out"
    out.mkdir()
    runs = r2.run_many([["codegen", urdf, "-o", out, "--name", "math"],
                        ["codegen", urdf, "-o", out, "--name", "Stdlib"],
                        ["codegen", urdf, "-o", out]])
    hs.assert_one_line_error(runs[0], "<math.h>")
    hs.assert_one_line_error(runs[1], "<stdlib.h>")
    assert runs[2].rc == 0, runs[2].err
    assert sorted(p.name for p in out.iterdir()) == ["math_robot.c", "math_robot.h"]
    main_c = tmp_path / "main.c"
    main_c.write_text('#include <math.h>\n#include "math_robot.h"\n'
                      "int main(void) { double q[1] = {0.5}, T[16]; math_robot_fk(q, T); return T[0] > cos(0.5) + 1e-9; }\n")
    subprocess.run([cc, "-std=c99", "-Wall", "-Werror", "-I", str(out), str(main_c), str(out / "math_robot.c"),
                    "-lm", "-o", str(tmp_path / "a.out")], check=True)
    assert subprocess.run([str(tmp_path / "a.out")], check=False).returncode == 0
