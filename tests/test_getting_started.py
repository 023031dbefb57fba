"""docs/getting-started.md runs as written and prints what its comments say.

The page promises: "Every example on this page runs as written once robokit is installed (...) the
printed numbers are the real output, rounded". Its ```python blocks build on each other; here they
run in order as one script, in a fresh interpreter in a temporary folder, and every value the page
shows — ``print(...)  # 6 joints``, ``# ... about X``, a printed array in the comment lines below — is
compared with what the code printed, by the rules of tests/support/doc_pages.py (which runs every
other page of the documentation the same way: tests/test_doc_pages.py).

The ``robokit view`` command line of the page is run too (exit 0, the page written).
"""
import os
import re
import shlex
import subprocess
import sys
from pathlib import Path

import doc_pages
import pytest

ROOT = Path(__file__).resolve().parents[1]
PAGE = ROOT / "docs" / "getting-started.md"

pytest.importorskip("meshcat", reason="the page's Scene sample needs robokit[viz]")
pytest.importorskip("matplotlib", reason="the page's plot needs robokit[plot]")


def test_the_page_has_its_samples():
    text = PAGE.read_text(encoding="utf-8")
    assert len(doc_pages.python_blocks(text)) >= 6
    assert len(doc_pages.shown_values(doc_pages.page_code(text))) >= 12


def test_every_printed_value_is_what_the_page_says(tmp_path):
    run = doc_pages.run_page(PAGE, tmp_path)
    assert run.returncode == 0, run.stderr[-3000:]
    wrong = run.mismatches()
    assert not wrong, "\n\n".join(wrong)
    for name in ("quintic.png", "puma.html"):  # the files the page writes
        assert (tmp_path / name).stat().st_size > 0, name


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
