"""The Makefile keeps one environment: robokit is installed once (editable) and again only when
pyproject.toml changes; each target adds the extras it needs without reinstalling robokit (issue 40:
``make docs`` while ``make test`` ran printed "Uninstalling robokit-0.2.0").

Run on a copy of the Makefile with a stand-in ``.venv/bin/python`` that records every command it is
given (pip, pytest, robokit) instead of running it — only ``.ci/extra_requirements.py`` runs for real,
with this interpreter, on the installed robokit's metadata. So this checks what make asks pip to do,
not pip itself. With uv (``make UV=...``, a stand-in uv recording its commands) the same installs go
through ``.ci/uv_pip.py``, which hands uv pip's configuration; that translation is checked on a pip
configuration written here."""
import importlib.util
import os
import shutil
import stat
import subprocess
import sys
import time
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
pytestmark = pytest.mark.skipif(shutil.which("make") is None, reason="make not installed")


def _project(tmp_path: Path) -> Path:
    proj = tmp_path / "proj"
    (proj / ".ci").mkdir(parents=True)
    shutil.copy(ROOT / "Makefile", proj / "Makefile")
    shutil.copy(ROOT / "pyproject.toml", proj / "pyproject.toml")
    shutil.copy(ROOT / ".ci" / "extra_requirements.py", proj / ".ci" / "extra_requirements.py")
    shutil.copy(ROOT / ".ci" / "uv_pip.py", proj / ".ci" / "uv_pip.py")
    bin_ = proj / ".venv" / "bin"
    bin_.mkdir(parents=True)
    log = proj / "log.txt"
    stand_in = (f"#!/bin/sh\ncase \"$1\" in .ci/extra_requirements.py|.ci/uv_pip.py) exec {sys.executable} \"$@\";; esac\n"
                f"echo \"$(basename \"$0\") $*\" >> {log}\n")
    for name in ("python", "robokit", "mkdocs", "jupyter", "uv"):
        (bin_ / name).write_text(stand_in)
        (bin_ / name).chmod((bin_ / name).stat().st_mode | stat.S_IXUSR)
    return proj


def _make(proj: Path, *targets: str, uv: str = "") -> list[str]:
    log = proj / "log.txt"
    log.write_text("")
    p = subprocess.run(["make", "-s", f"UV={uv}", *targets], cwd=proj, capture_output=True, text=True, timeout=120,
                       env={k: v for k, v in os.environ.items() if not k.startswith("MAKE")})
    assert p.returncode == 0, p.stdout + p.stderr
    return [line for line in log.read_text().splitlines() if line]


def test_robokit_is_installed_once_and_extras_are_added_next_to_it(tmp_path):
    proj = _project(tmp_path)
    first = _make(proj, "test")
    installs = [c for c in first if " pip install" in c]
    assert sum(" -e ." in c for c in installs) == 1, installs  # robokit, editable, once
    assert all(" -e " not in c or c.endswith(" -e .") for c in installs), installs  # never -e '.[extra]'
    extras = sorted(c.split(" -r ")[1] for c in installs if " -r " in c)
    assert extras == [".venv/.extra-all.txt", ".venv/.extra-bench.txt", ".venv/.extra-docs.txt",
                      ".venv/.extra-test.txt"], installs
    assert "mkdocs-material>=9.5" in (proj / ".venv/.extra-docs.txt").read_text().split("\n")
    assert "pin>=4.1" in (proj / ".venv/.extra-docs.txt").read_text().split("\n")  # robokit's pins kept
    pytest_run = [c for c in first if " -m pytest" in c]
    assert pytest_run == ["python -m pytest -n 2 --durations=20"]  # not -q: the item count and closing count show
    # the other targets: nothing installed again, only what is missing
    assert not any("pip" in c for c in _make(proj, "docs")), "make docs reinstalled something"
    assert not any("pip" in c for c in _make(proj, "demo", "bench", "test"))
    notebooks = [c for c in _make(proj, "notebooks") if "pip" in c]
    assert len(notebooks) == 1 and notebooks[0].endswith("-r .venv/.extra-notebooks.txt"), notebooks
    # pyproject.toml changed: robokit reinstalled once, the extras brought up to date with -r
    time.sleep(1.1)
    (proj / "pyproject.toml").touch()
    again = [c for c in _make(proj, "docs") if "pip" in c]
    assert len(again) == 2 and again[0].endswith("-e .") and again[1].endswith("-r .venv/.extra-docs.txt"), again


def test_extra_requirements_expands_extras_and_refuses_unknown_ones():
    p = subprocess.run([sys.executable, str(ROOT / ".ci" / "extra_requirements.py"), "all"], capture_output=True,
                       text=True, check=True)
    reqs = p.stdout.split("\n")
    for dist in ("pin", "sympy", "toppra", "ompl", "mujoco", "jupyterlab", "xacro", "dask", "meshcat"):
        assert any(r.startswith(dist) for r in reqs), dist
    assert not any(r.startswith("robokit") for r in reqs)
    bad = subprocess.run([sys.executable, str(ROOT / ".ci" / "extra_requirements.py"), "nope"], capture_output=True,
                         text=True)
    assert bad.returncode != 0 and "no extra 'nope'" in bad.stderr


def test_with_uv_the_same_installs_go_through_uv_with_pips_choices(tmp_path):
    proj = _project(tmp_path)
    uv = str(proj / ".venv" / "bin" / "uv")
    installs = [c for c in _make(proj, "test", uv=uv) if c.startswith("uv ")]
    assert all(c.startswith("uv pip install --python ") for c in installs), installs
    assert all("--index-strategy unsafe-best-match --compile-bytecode" in c for c in installs), installs
    assert [c.split()[-1] for c in installs if " -e " in c] == ["."]  # robokit, editable, once
    extras = sorted(c.split(" -r ")[1] for c in installs if " -r " in c)
    assert extras == [".venv/.extra-all.txt", ".venv/.extra-bench.txt", ".venv/.extra-docs.txt",
                      ".venv/.extra-test.txt"], installs
    assert not any("pip" in c for c in _make(proj, "docs", uv=uv)), "make docs reinstalled something"


def _uv_pip():
    spec = importlib.util.spec_from_file_location("uv_pip", ROOT / ".ci" / "uv_pip.py")
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_uv_is_given_pips_configuration_as_pip_applies_it(tmp_path, monkeypatch):
    # pip's rules: the install section over global, a PIP_* variable over both; another command's
    # section does not apply to pip install
    conf = tmp_path / "pip.conf"
    conf.write_text("[global]\nindex-url = https://global.invalid/simple\nfind-links = /from-global\n"
                    "[install]\nfind-links = /from-install-a /from-install-b\n[download]\nno-index = true\n")
    for name in [k for k in os.environ if k.startswith("PIP_")]:
        monkeypatch.delenv(name)
    monkeypatch.setenv("PIP_CONFIG_FILE", str(conf))
    monkeypatch.setenv("PIP_INDEX_URL", "https://env.invalid/simple")
    uv_pip = _uv_pip()
    settings = uv_pip.pip_config(sys.executable)
    assert settings["index-url"] == "https://env.invalid/simple"
    assert settings["find-links"] == "/from-install-a /from-install-b"
    assert "no-index" not in settings
    args, env = uv_pip.uv_options({"index-url": "https://i.invalid/simple", "extra-index-url": "file:///a file:///b",
                                   "find-links": "/w", "constraint": "/c.txt", "no-index": "false",
                                   "cert": "/ca.pem", "disable-pip-version-check": "1"})
    assert args == ["--index-strategy", "unsafe-best-match", "--compile-bytecode", "--constraints", "/c.txt",
                    "--extra-index-url", "file:///a", "--extra-index-url", "file:///b", "--find-links", "/w",
                    "--index-url", "https://i.invalid/simple"]
    assert env == {"SSL_CERT_FILE": "/ca.pem"}
    # a setting uv cannot be given is named (the script then installs with pip)
    with pytest.raises(ValueError, match="'target'"):
        uv_pip.uv_options({"target": "/somewhere"})
