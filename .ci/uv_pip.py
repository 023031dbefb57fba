"""Install into this interpreter's environment with uv, configured the way pip is configured here.

``python .ci/uv_pip.py UV ARGS...`` runs ``UV pip install --python <this interpreter> ARGS...``
(``ARGS`` as ``pip install`` takes them: ``-e .``, ``-r FILE``, ``--upgrade pip``). The Makefile
uses it when uv is available: uv installs the same packages faster than pip (measured in the Makefile).

uv reads none of pip's configuration (pip.conf files, ``PIP_*`` variables), and machines configure
pip: CI's, for one, gives it a local mirror as extra indexes, find-links and a constraints file.
This script asks pip for its configuration (``python -m pip config list``: every file and ``PIP_*``
variable, an ``install`` section over ``global``, a variable over both, as pip applies them) and
hands each setting that decides what gets installed to uv. Two of uv's defaults differ from pip's
and are set to pip's:

* ``--index-strategy unsafe-best-match``: pip takes the best version found on any index; uv by
  default takes a package from the first index that has it (an older release on a mirror would win);
* ``--compile-bytecode``: pip writes every installed module's ``.pyc``; uv by default writes none,
  and where ``PYTHONDONTWRITEBYTECODE`` is set (as on CI's machines) every later process would then
  compile from source each module it imports (``import numpy, scipy, numba, pinocchio, matplotlib,
  sympy`` measured 6.7 s instead of 2.2 s).

A setting it does not know, or cannot give uv, makes it run pip instead (saying which), so that
nothing pip is told is silently dropped.
"""
from __future__ import annotations

import os
import re
import subprocess
import sys

# pip option -> uv option; a value holding several (whitespace-separated) gives one each
_LISTS = {
    "extra-index-url": "--extra-index-url",
    "find-links": "--find-links",
    "constraint": "--constraints",
    "trusted-host": "--allow-insecure-host",
    "only-binary": "--only-binary",
    "no-binary": "--no-binary",
}
_SINGLE = {"index-url": "--index-url"}
_FLAGS = {"no-index": "--no-index", "pre": "--prerelease=allow"}
# pip options that change how pip talks or reports, not what it installs (uv keeps its own cache)
_HARMLESS = {
    "disable-pip-version-check", "progress-bar", "quiet", "verbose", "no-color", "no-input",
    "cache-dir", "no-cache-dir", "retries", "root-user-action", "require-virtualenv", "log",
    "exists-action",
}
_TRUE = {"1", "true", "yes", "on"}


def pip_config(python: str) -> dict[str, str]:
    """pip's effective setting for ``pip install``, by option name (``extra-index-url``: ``...``)."""
    out = subprocess.run([python, "-m", "pip", "config", "list"], capture_output=True, text=True, check=True).stdout
    by_section: dict[str, dict[str, str]] = {}
    for line in out.splitlines():
        m = re.fullmatch(r"([^.=]*)\.([^=]+)='(.*)'", line.strip())
        if m is None:
            raise ValueError(f"unexpected line from pip config list: {line!r}")
        by_section.setdefault(m.group(1), {})[m.group(2)] = m.group(3)
    settings: dict[str, str] = {}
    # pip's order, the later one winning; another command's section ([download], [wheel]) is not install's
    for section in ("global", "install", ":env:"):
        settings.update(by_section.get(section, {}))
    return settings


def uv_options(settings: dict[str, str]) -> tuple[list[str], dict[str, str]]:
    """uv's options and environment for pip's settings; ValueError names a setting uv cannot take."""
    args = ["--index-strategy", "unsafe-best-match", "--compile-bytecode"]
    env: dict[str, str] = {}
    for key, value in sorted(settings.items()):
        key = key.replace("_", "-")
        if key in _LISTS:
            for item in value.split():
                args += [_LISTS[key], item]
        elif key in _SINGLE:
            args += [_SINGLE[key], value]
        elif key in _FLAGS:
            if value.strip().lower() in _TRUE:
                args.append(_FLAGS[key])
        elif key == "cert":
            env["SSL_CERT_FILE"] = value  # what uv reads for a CA bundle
        elif key == "proxy":
            env["HTTPS_PROXY"] = env["HTTP_PROXY"] = value
        elif key in ("timeout", "default-timeout"):
            env["UV_HTTP_TIMEOUT"] = value
        elif key not in _HARMLESS:
            raise ValueError(f"pip's setting {key!r} = {value!r}")
    return args, env


def main(argv: list[str]) -> int:
    if len(argv) < 2:
        raise SystemExit(__doc__)
    uv, pip_args = argv[0], argv[1:]
    try:
        args, env = uv_options(pip_config(sys.executable))
    except (ValueError, subprocess.CalledProcessError) as e:
        print(f"uv_pip.py: installing with pip: uv cannot be given {e}", file=sys.stderr)
        cmd = [sys.executable, "-m", "pip", "install", *pip_args]
        return subprocess.run(cmd).returncode
    cmd = [uv, "pip", "install", "--python", sys.executable, *args, *pip_args]
    print(" ".join(cmd), file=sys.stderr)
    return subprocess.run(cmd, env={**os.environ, **env}).returncode


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
