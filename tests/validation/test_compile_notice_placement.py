"""`robokit validate` on a new machine: the "compiling course kernels in the background" line used to
land in the middle of the table (stderr between stdout's rows). It now comes after the table: the
command's output, stdout and stderr in one stream as a terminal shows them, has no robokit notice
between the header and the summary."""
import os
import re
import signal
import subprocess
import sys

from robokit.cli import main as cli_main


def test_the_compile_notice_comes_after_the_table(tmp_path):
    env = dict(os.environ, NUMBA_CACHE_DIR=str(tmp_path / "numba-cache"), ROBOKIT_COMPILE="background")
    proc = subprocess.run([sys.executable, "-m", "robokit.cli", "validate", "--area", "kinematics"],
                          stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, env=env, cwd=tmp_path,
                          timeout=900)
    out = proc.stdout
    for pid in {int(p) for p in re.findall(r"\(pid (\d+)", out)}:  # the worker this run started
        try:
            os.kill(pid, signal.SIGTERM)
        except ProcessLookupError:
            pass
    assert proc.returncode == 0, out[-3000:]
    lines = out.splitlines()
    head = next(i for i, ln in enumerate(lines) if ln.startswith("quantity"))
    summary = next(i for i, ln in enumerate(lines) if re.match(r"\d+ passed, \d+ failed", ln))
    assert head < summary
    inside = [ln for ln in lines[head:summary] if ln.startswith("robokit:")]
    assert inside == [], inside
    notices = [i for i, ln in enumerate(lines) if ln.startswith("robokit: compiling course kernels in the background")]
    assert notices and all(i > summary for i in notices), out[-3000:]  # a cold cache: the notice exists, after


def test_unknown_area_is_named(capsys):
    assert cli_main(["validate", "--area", "kinematic"]) == 2
    err = capsys.readouterr().err
    assert "--area: unknown area 'kinematic'" in err and "kinematics" in err and err.count("\n") == 1
