"""The README's samples run as written, each on the install it names.

Every ```python block starts with ``# needs: the core install`` or ``# needs: robokit[EXTRA]``;
every ``robokit ...`` line of the ```sh blocks runs on the core install unless its comment starts
with ``[EXTRA]``. What is checked, in a fresh interpreter per sample, in a temporary folder:

1. the sample runs with only the install it names importable: every top-level module installed here
   whose distribution that install does not bring is hidden (``sys.modules[name] = None``, so
   importing it fails as if it were not installed). The install is robokit's core requirements
   plus those of the named extras (from the installed robokit's metadata, i.e. pyproject.toml),
   closed over their own requirements as installed here. That is how "on the install it names" is
   simulated: a fresh environment with only that install is not built (it would take minutes and
   the network), so the packages' versions are this environment's, and a module that imports
   itself under another name than its distribution's could slip through;
2. it exits 0 and every file a command names with ``-o`` exists and is not empty;
3. with the named extra's own packages hidden as well, the sample stops with robokit's one-line
   message naming the extra (``MissingExtraError`` ... ``pip install 'robokit[EXTRA]'``; status 2
   and one ``robokit: error:`` line from the command line), never a bare ``ModuleNotFoundError``.

Input files that command lines read (``scene.yaml``, ``tracker.csv``, and ``traj.csv``, which the
``plan`` line writes: each line runs on its own) are made here (:data:`INPUTS`): a scene of two
obstacles, tool poses of the nominal PUMA 560 at 40 random configurations with 0.1 mm / 1 mrad of
noise, and a straight-line joint trajectory.
"""
import functools
import importlib.metadata as md
import os
import re
import shlex
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from packaging.requirements import Requirement
from packaging.utils import canonicalize_name

ROOT = Path(__file__).resolve().parents[1]
README = (ROOT / "README.md").read_text(encoding="utf-8")
NEEDS = re.compile(r"# needs: (?:the core install|robokit\[([a-z,]+)\])")


def _python_samples():
    out = []
    for code in re.findall(r"```python\n(.*?)```", README, flags=re.S):
        m = NEEDS.match(code)
        out.append((tuple(m.group(1).split(",")) if m and m.group(1) else (), code, m is not None))
    return out


def _sh_samples():
    out = []
    for block in re.findall(r"```sh\n(.*?)```", README, flags=re.S):
        for ln in block.splitlines():
            if ln.strip().startswith("robokit "):
                cmd, _, comment = ln.partition("#")
                m = re.match(r"\s*\[([a-z,]+)\]", comment)
                out.append((tuple(m.group(1).split(",")) if m else (), cmd.strip()))
    return out


PY = _python_samples()
SH = _sh_samples()

SCENE = """obstacles:
  - type: box
    name: wall
    size: [0.05, 0.6, 0.6]
    pose: {xyz: [0.55, 0.35, 0.3]}
  - type: sphere
    radius: 0.1
    pose: {xyz: [0.3, -0.4, 0.9]}
"""


def _tracker(path: Path) -> None:
    import robokit
    from robokit.calibration import write_calibration_csv
    from robokit.spatial import matrix_exp_6, vec_to_se3

    puma = robokit.load("puma560")
    rng = np.random.default_rng(3)
    q = np.array([puma.random_configuration(rng) for _ in range(40)])
    T = puma.frame_pose(q)
    noise = [matrix_exp_6(vec_to_se3(np.r_[rng.normal(0, 1e-3, 3), rng.normal(0, 1e-4, 3)])) for _ in q]
    write_calibration_csv(path, q, np.einsum("kij,kjl->kil", T, np.array(noise)))


def _trajectory(path: Path) -> None:
    """What ``robokit plan`` writes: a header and one row of joint values per 1/30 s (a straight line)."""
    q = np.linspace([0, 0.3, -0.3, 0, 0, 0], [1.4, 0.3, -0.3, 0, 0, 0], 40)
    path.write_text("q1,q2,q3,q4,q5,q6\n" + "\n".join(",".join(f"{v:.6g}" for v in row) for row in q) + "\n")


INPUTS = {"scene.yaml": lambda p: p.write_text(SCENE), "tracker.csv": _tracker, "traj.csv": _trajectory}

# Hides modules, as if their distributions were not installed.
PROBE = "import sys\nfor _name in {hide!r}:\n    sys.modules[_name] = None\ndel _name\n"
CLI = "import sys\nfrom robokit.cli import main\nsys.exit(main(sys.argv[1:]))\n"


def _env():
    env = dict(os.environ, MPLBACKEND="Agg")
    env["PYTHONPATH"] = os.pathsep.join([str(ROOT), env.get("PYTHONPATH", "")]).rstrip(os.pathsep)
    return env


def _direct(extras) -> list[str]:
    """The requirement strings of robokit's core (extras=()) or of the named extras, self-references
    (``robokit[viz,plot]``) expanded."""
    reqs = [Requirement(r) for r in md.requires("robokit") or []]
    out, todo, seen = [r for r in reqs if r.marker is None], list(extras), set()
    if extras:
        out = []
    while todo:
        e = todo.pop()
        if e in seen:
            continue
        seen.add(e)
        for r in reqs:
            if r.marker is not None and r.marker.evaluate({"extra": e}):
                if canonicalize_name(r.name) == "robokit":
                    todo += sorted(r.extras)
                else:
                    out.append(r)
    return out


@functools.lru_cache(maxsize=None)
def _closure(extras) -> frozenset:
    """Canonical names of every distribution the install brings: robokit, its core requirements,
    the named extras' requirements, and everything those require (as installed here)."""
    todo = [(r, frozenset(r.extras)) for r in _direct(()) + _direct(extras)]
    dists = {"robokit"}
    seen = set()
    while todo:
        req, wanted = todo.pop()
        name = canonicalize_name(req.name)
        if (name, wanted) in seen:
            continue
        seen.add((name, wanted))
        dists.add(name)
        try:
            sub = md.requires(name) or []
        except md.PackageNotFoundError:
            continue
        for s in sub:
            r = Requirement(s)
            envs = [{"extra": e} for e in wanted] or [{"extra": ""}]
            if r.marker is None or any(r.marker.evaluate(env) for env in envs):
                todo.append((r, frozenset(r.extras)))
    return frozenset(dists)


@functools.lru_cache(maxsize=None)
def _modules() -> dict:
    """Top-level module name -> canonical names of the distributions installed here that provide it."""
    return {m: {canonicalize_name(d) for d in ds} for m, ds in md.packages_distributions().items()
            if not m.startswith("_")}  # not interpreter hooks (.pth files, an editable install's finder)


def _import_names(extras) -> list[str]:
    """The top-level module names of the distributions the named extras add directly."""
    wanted = {canonicalize_name(r.name) for r in _direct(extras)}
    return sorted(m for m, ds in _modules().items() if ds & wanted)


def _not_in(extras) -> list[str]:
    """The top-level modules installed here that the install (core + ``extras``) does not bring."""
    allowed = _closure(tuple(extras))
    return sorted(m for m, ds in _modules().items() if not ds & allowed and m not in ("robokit",))


def _run(tmp_path, code, argv=(), hide=()):
    probe = PROBE.replace("{hide!r}", repr(sorted(hide)))
    return subprocess.run([sys.executable, "-c", probe + code, *argv], cwd=tmp_path, env=_env(), capture_output=True,
                          text=True, timeout=600)


def _inputs(argv, tmp_path):
    outputs = {argv[i + 1] for i, a in enumerate(argv[:-1]) if a in ("-o", "--output")}
    for name, make in INPUTS.items():
        if name in argv and name not in outputs:
            make(tmp_path / name)


def test_readme_has_code_and_every_sample_names_its_install():
    assert len(PY) >= 6 and len(SH) >= 10
    assert all(tagged for _, _, tagged in PY), [code.splitlines()[0] for _, code, tagged in PY if not tagged]
    extras = set(md.metadata("robokit").get_all("Provides-Extra"))
    for need in {e for n, _, _ in PY for e in n} | {e for n, _ in SH for e in n}:
        assert need in extras, need
    # the README's list of commands covers every subcommand
    from robokit.cli import _build_parser

    sub = next(a for a in _build_parser()._actions if a.__class__.__name__ == "_SubParsersAction")
    assert set(sub.choices) <= {line.split()[1] for _, line in SH if len(line.split()) > 1}


@pytest.mark.parametrize("needs, code", [(n, c) for n, c, _ in PY], ids=[f"python-{i}" for i in range(len(PY))])
def test_readme_python_sample_runs_on_the_install_it_names(needs, code, tmp_path):
    p = _run(tmp_path, code, hide=_not_in(needs))
    assert p.returncode == 0, p.stderr[-2000:]


@pytest.mark.parametrize("needs, line", SH, ids=[f"sh-{i}" for i in range(len(SH))])
def test_readme_command_runs_on_the_install_it_names(needs, line, tmp_path):
    argv = shlex.split(line)[1:]
    _inputs(argv, tmp_path)
    p = _run(tmp_path, CLI, argv, hide=_not_in(needs))
    assert p.returncode == 0, (line, p.stderr[-2000:])
    for i, a in enumerate(argv):  # every file the line says it writes exists and is not empty
        if a in ("-o", "--output"):
            target = tmp_path / argv[i + 1]
            assert (any(target.iterdir()) if target.is_dir() else target.stat().st_size > 0), line


NEED_EXTRAS = [(n, c, None) for n, c, _ in PY if n] + [(n, None, line) for n, line in SH if n]


@pytest.mark.parametrize("needs, code, line", NEED_EXTRAS, ids=[f"extra-{i}" for i in range(len(NEED_EXTRAS))])
def test_without_its_extra_a_sample_says_which_to_install(needs, code, line, tmp_path):
    hide = set(_not_in(needs)) | set(_import_names(needs))
    assert _import_names(needs)
    if code is not None:
        p = _run(tmp_path, code, hide=hide)
        last = p.stderr.strip().splitlines()[-1]
        assert p.returncode != 0 and last.startswith("robokit.errors.MissingExtraError:"), p.stderr[-2000:]
    else:
        argv = shlex.split(line)[1:]
        _inputs(argv, tmp_path)
        p = _run(tmp_path, CLI, argv, hide=hide)
        lines = p.stderr.strip().splitlines()
        assert p.returncode == 2 and len(lines) == 1 and lines[0].startswith("robokit: error:"), p.stderr[-2000:]
        last = lines[0]
    assert any(f"pip install 'robokit[{e}]'" in last for e in needs), last
