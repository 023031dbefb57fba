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


import hardening_support as hs  # noqa: E402
import limited_cli as r2  # noqa: E402

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


# ------------------------------------------------------------------ class 5: an existing NAME.h
def _sparse(path, size):
    with open(path, "wb") as f:
        f.truncate(size)  # a sparse file: 6 GB of zeros that occupy no disk


@pytest.mark.parametrize("kind", ["symlink", "file"])
def test_cli_keeps_a_huge_existing_header_without_reading_it(tmp_path, kind):
    """A 6 GB twolink.h (sparse) in the output folder, itself or behind a symbolic link: codegen
    writes the pair under a 3 GB address-space limit (was: the old header read whole, MemoryError,
    exit 3), never writes through the link, and leaves nothing else behind."""
    out = tmp_path / "out"
    out.mkdir()
    big = (tmp_path / "elsewhere.h") if kind == "symlink" else (out / "twolink.h")
    _sparse(big, 6 << 30)
    if kind == "symlink":
        (out / "twolink.h").symlink_to(big)
    run = r2.run_limited("codegen", "twolink", "-o", out)
    assert run.rc == 0, run.err
    h = out / "twolink.h"
    assert not h.is_symlink() and "twolink_fk" in h.read_text()
    assert sorted(p.name for p in out.iterdir()) == ["twolink.c", "twolink.h"]
    if kind == "symlink":
        assert big.stat().st_size == 6 << 30  # the link's target is untouched


@pytest.mark.parametrize("kind", ["symlink", "file"])
def test_failed_source_write_puts_the_old_header_back_as_it_was(tmp_path, monkeypatch, kind):
    """The pair is all or nothing: when NAME.c cannot be written the old NAME.h comes back, a
    symbolic link as the same link (not the file it points to)."""
    import robokit.codegen.generate as gen

    target = tmp_path / "target.h"
    target.write_text("/* the user's own */\n")
    h = tmp_path / "twolink.h"
    if kind == "symlink":
        h.symlink_to(target)
    else:
        h.write_text("/* old */\n")
    real = gen.atomic_write

    def failing(path, data):
        if str(path).endswith(".c"):
            raise OSError(28, "No space left on device", str(path))
        return real(path, data)

    monkeypatch.setattr(gen, "atomic_write", failing)
    with pytest.raises(OSError):
        write_c(generate_c(robokit.load("twolink")), tmp_path)
    if kind == "symlink":
        assert h.is_symlink() and os.readlink(h) == str(target)
    else:
        assert h.read_text() == "/* old */\n"
    assert target.read_text() == "/* the user's own */\n"
    assert sorted(p.name for p in tmp_path.iterdir()) == sorted(["target.h", "twolink.h"])


def test_without_hard_links_a_huge_old_header_is_not_read(tmp_path, monkeypatch):
    """Where hard links fail, the old header is copied only when small, read with O_NOFOLLOW."""
    import robokit.codegen.generate as gen

    def no_link(*a, **k):
        raise OSError(1, "Operation not permitted")

    monkeypatch.setattr(gen.os, "link", no_link)
    h = tmp_path / "twolink.h"
    _sparse(h, gen.MAX_KEPT_BYTES + 1)
    assert gen._keep_aside(h) is None
    h.unlink()
    h.write_text("/* old */\n")
    aside = gen._keep_aside(h)
    assert aside is not None and aside.read_text() == "/* old */\n"


# ------------------------------------------------------------------ class 4: representable constants
@pytest.mark.parametrize("float32", [True, False])
@pytest.mark.parametrize("field, value, named", [
    ("xyz", "0.5 4.9e-324 0", "tool frame 'tip'"),        # the fixed tip offset: a double subnormal
    ("xyz", "0.5 1e-40 0", "tool frame 'tip'"),           # a float subnormal (a normal double)
    ("mass", "1e-40", "the link of joint 'shoulder': mass"),
    ("lower", "-1e-300", "joint 'shoulder': limits"),
])
def test_constants_outside_the_target_type_are_refused_naming_the_key(tmp_path, float32, field, value, named):
    """Every constant written must be 0 or a normal number of the target type (was: `1e-40f` kept as
    a subnormal, `4.9e-324f` truncated to zero — an error under -Werror)."""
    robot = robokit.load(_urdf(tmp_path, **{field: value}))
    small = abs(float(value.split()[1] if field == "xyz" else value))
    if not float32 and small > 2.3e-308:  # a normal double: double C is fine
        generate_c(robot, float32=False)
        return
    with pytest.raises(robokit.InputError, match=re.escape(named)):
        generate_c(robot, float32=float32)


def test_every_written_literal_is_checked_naming_where_it_is():
    """The catch-all behind the named checks: a folded constant beyond float's range (1e+39) or
    below it (4.9e-324) in any function, table or macro is refused naming it."""
    from robokit.codegen._c import check_literals

    check_literals("void a_fk(const float q[1], float T[16])\n{\n    T[0] = 3.0e38f * q[0];\n}\n", True, "a.c")
    with pytest.raises(robokit.InputError, match=r"a_rnea holds the constant 1e\+39"):
        check_literals("void a_rnea(const float q[1], float tau[1])\n{\n    tau[0] = 1e+39f * q[0];  /* 1e99 */\n}\n",
                       True, "a.c")
    with pytest.raises(robokit.InputError, match=r"a_JOINT0_LOWER holds the constant 4.9e-324"):
        check_literals("#define a_JOINT0_LOWER 4.9e-324\n", False, "a.h")
    check_literals('/* 1e999 */ const char *const a_names[1] = {"1e999"};\n', True, "a.c")  # comments, strings


def test_cli_float32_constants_exit_2_naming_the_link_and_nothing_is_written(tmp_path, cc):
    out = tmp_path / "out"
    out.mkdir()
    tiny_inertia = _urdf(tmp_path, name="tiny", mass="1e-40")
    tiny_offset = _urdf(tmp_path, name="offset", xyz="0.5 1e-40 0")
    runs = r2.run_many([["codegen", tiny_inertia, "-o", out, "--float32"],
                        ["codegen", tiny_offset, "-o", out, "--float32"],
                        ["codegen", tiny_offset, "-o", out]])
    hs.assert_one_line_error(runs[0], "shoulder", "mass")
    hs.assert_one_line_error(runs[1], "tool frame 'tip'")
    assert sorted(p.name for p in out.iterdir()) == ["offset.c", "offset.h"]  # from the third run only
    assert runs[2].rc == 0  # double C holds 1e-40
    subprocess.run([cc, "-std=c99", "-Wall", "-Wextra", "-Wpedantic", "-Werror", "-c", str(out / "offset.c"),
                    "-o", str(tmp_path / "offset.o")], check=True)
