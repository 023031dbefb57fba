"""docs/getting-started.md runs as written and prints what its comments say.

The page promises: "Every example on this page runs as written once robokit is installed (...) the
printed numbers are the real output, rounded". Its ```python blocks build on each other; here they
run in order as one script, in a fresh interpreter in a temporary folder, and every top-level
``print(...)`` is recorded with its line. Each is compared with the comment the page gives it:

* ``# ... about X`` — for a round-off size (X < 1e-9) the value is at most 10·X; otherwise the value,
  rounded to X's significant digits, is X;
* a comment on the following lines (``# [[ 0.9659 ...``) — the printed text, line by line;
* any other comment — the printed text (or its repr, for a string) is the comment or starts it,
  followed by a space (``# 6 joints``).

The ``robokit view`` command line of the page is run too (exit 0, the page written).
"""
import io
import json
import os
import re
import shlex
import subprocess
import sys
import tokenize
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
PAGE = ROOT / "docs" / "getting-started.md"

pytest.importorskip("meshcat", reason="the page's Scene sample needs robokit[viz]")
pytest.importorskip("matplotlib", reason="the page's plot needs robokit[plot]")

def _print_call(line):
    """(arguments, comment) of a top-level ``print(...)  # comment`` line, else None."""
    if not line.startswith("print("):
        return None
    tokens = list(tokenize.generate_tokens(io.StringIO(line + "\n").readline))
    comment = next((t for t in tokens if t.type == tokenize.COMMENT), None)
    code = line[:comment.start[1]].rstrip() if comment else line.rstrip()
    assert code.endswith(")"), line
    return code[len("print("):-1], (comment.string[1:].strip() if comment else "")


def _blocks():
    return re.findall(r"```python\n(.*?)```", PAGE.read_text(encoding="utf-8"), flags=re.S)


def _script():
    """The page's Python as one script, each top-level print replaced by a recorder; and the
    expected text of each recorded print, by its number."""
    lines = "".join(_blocks()).splitlines()
    out, expected = ["_RK_SHOWN = []"], {}
    for i, line in enumerate(lines):
        call = _print_call(line)
        if call is None:
            out.append(line)
            continue
        args, comment = call
        k = len(expected)
        if not comment:  # the expected output is the comment block that follows
            block = []
            for nxt in lines[i + 1:]:
                if not nxt.startswith("# "):
                    break
                block.append(nxt[2:])
            comment = "\n".join(block)
        expected[k] = comment
        out.append(f"_RK_SHOWN.append(({k}, (lambda *a: ' '.join(map(str, a)))({args}), "
                   f"(lambda *a: a[0] if len(a) == 1 and isinstance(a[0], str) else None)({args})))")
    out.append("import json, sys; sys.stdout.write('\\nRK-SHOWN ' + json.dumps(_RK_SHOWN) + '\\n')")
    return "\n".join(out) + "\n", expected


def _matches(printed: str, as_str, comment: str) -> bool:
    about = re.search(r"\babout ([-+0-9.eE]+)", comment)
    if about:
        x, v = float(about.group(1)), float(printed)
        if abs(x) < 1e-9:
            return 0 <= abs(v) <= 10 * abs(x)
        digits = len(re.sub(r"[^0-9]", "", f"{x:e}".split("e")[0]).rstrip("0")) or 1
        return float(f"{v:.{digits - 1}e}") == x
    if "\n" in comment:
        return [ln.split() for ln in printed.splitlines()] == [ln.split() for ln in comment.splitlines()]
    candidates = [printed] + ([repr(as_str)] if as_str is not None else [])
    return any(comment == c or comment.startswith(c + " ") for c in candidates)


def test_the_page_has_its_samples():
    script, expected = _script()
    assert len(_blocks()) >= 6 and len(expected) >= 12


def test_every_printed_value_is_what_the_page_says(tmp_path):
    script, expected = _script()
    env = dict(os.environ, MPLBACKEND="Agg")
    env["PYTHONPATH"] = os.pathsep.join([str(ROOT), env.get("PYTHONPATH", "")]).rstrip(os.pathsep)
    p = subprocess.run([sys.executable, "-c", script], cwd=tmp_path, env=env, capture_output=True, text=True,
                       timeout=600)
    assert p.returncode == 0, p.stderr[-3000:]
    shown = json.loads(p.stdout.rsplit("RK-SHOWN ", 1)[1])
    assert [k for k, _, _ in shown] == list(range(len(expected)))
    wrong = [f"print #{k}: the page says {expected[k]!r}, robokit printed {printed!r}"
             for k, printed, as_str in shown if not _matches(printed, as_str, expected[k])]
    assert not wrong, "\n".join(wrong)
    for name in ("quintic.png", "puma.html"):  # the files the page writes
        assert (tmp_path / name).stat().st_size > 0, name


def test_the_matcher_tells_right_from_wrong():
    assert _matches("2.220446049250313e-16", None, "about 2e-16")
    assert not _matches("3e-15", None, "about 2e-16")
    assert _matches("0.0027392824578060097", None, "Yoshikawa's sqrt(det(J Jᵀ)), here about 0.0027")
    assert _matches("0.0027392824578060097", None, "about 0.0027")
    assert not _matches("0.0031", None, "about 0.0027")
    assert _matches("6", None, "6 joints") and not _matches("7", None, "6 joints")
    assert _matches("left, elbow up", "left, elbow up", "'left, elbow up'")
    assert not _matches("left, elbow up", "left, elbow up", "'right, elbow down, no flip'")


def test_the_page_command_line_runs(tmp_path):
    text = PAGE.read_text(encoding="utf-8")
    lines = [ln.strip() for b in re.findall(r"```sh\n(.*?)```", text, flags=re.S) for ln in b.splitlines()
             if ln.strip().startswith("robokit view")]
    assert lines
    env = dict(os.environ, MPLBACKEND="Agg")
    env["PYTHONPATH"] = os.pathsep.join([str(ROOT), env.get("PYTHONPATH", "")]).rstrip(os.pathsep)
    for line in lines:
        argv = shlex.split(line.partition("#")[0])[1:]
        p = subprocess.run([sys.executable, "-m", "robokit.cli", *argv], cwd=tmp_path, env=env, capture_output=True,
                           text=True, timeout=600)
        assert p.returncode == 0, (line, p.stderr[-2000:])
        out = argv[argv.index("-o") + 1]
        assert (tmp_path / out).stat().st_size > 0


def test_course_ik_batch_sample_runs_without_deprecation(tmp_path):
    """docs/course/inverse-kinematics-closed-form.md's batch sample called ``robot.frame_pose`` on
    (1000, 6) joint values, deprecated (DeprecationWarning: use frame_pose_batch). The page's blocks
    run in order with DeprecationWarning as an error; the batch's solutions reproduce each pose by
    Pinocchio's FK of the shipped PUMA URDF."""
    page = (ROOT / "docs" / "course" / "inverse-kinematics-closed-form.md").read_text(encoding="utf-8")
    block = next(b for b in re.findall(r"```python\n(.*?)```", page, flags=re.S) if "ik_analytic_batch" in b)
    script = ("import warnings; warnings.simplefilter('error', DeprecationWarning)\n"
              "import numpy as np, robokit, pinocchio as pin\nfrom robokit.description.models import models_dir\n"
              "robot = robokit.load('puma560')\n" + block +
              "m = pin.buildModelFromUrdf(str(models_dir() / 'puma560.urdf')); d = m.createData()\n"
              "f = m.getFrameId('tool'); err = 0.0\n"
              "for i in range(0, len(Ts), 97):\n"
              "    for q in Q[i, :counts[i]]:\n"
              "        pin.framesForwardKinematics(m, d, q); err = max(err, abs(d.oMf[f].homogeneous - Ts[i]).max())\n"
              "assert counts.min() >= 1 and err < 1e-9, (counts.min(), err)\nprint('ok')\n")
    env = dict(os.environ, MPLBACKEND="Agg")
    env["PYTHONPATH"] = os.pathsep.join([str(ROOT), env.get("PYTHONPATH", "")]).rstrip(os.pathsep)
    p = subprocess.run([sys.executable, "-c", script], cwd=tmp_path, env=env, capture_output=True, text=True,
                       timeout=600)
    assert p.returncode == 0 and "ok" in p.stdout, p.stderr[-3000:]


def test_loading_page_shows_the_real_unknown_robot_message():
    """docs/loading.md quotes ``rk.load("iiwa")``'s error; its list of file suffixes had fallen
    behind the loader's (.sdf and .world were missing). The quoted text, its line breaks joined,
    is the message robokit raises."""
    import robokit

    page = (ROOT / "docs" / "loading.md").read_text(encoding="utf-8")
    quoted = re.search(r'>>> rk\.load\("iiwa"\)\nInputError: (.*?)\n```', page, flags=re.S).group(1)
    with pytest.raises(robokit.InputError) as info:
        robokit.load("iiwa")
    assert " ".join(quoted.split()) == " ".join(str(info.value).split())
