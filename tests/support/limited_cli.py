"""The CLI in a subprocess under resource limits (a
safety net so that a regression fails instead of swapping or hanging the machine — never a
timed assertion), and small hostile files."""
from __future__ import annotations

import resource
import subprocess
import sys

import hardening_support as hs

#: Address-space limit of a limited subprocess (robokit with Pinocchio and numba needs < 1.5 GB).
MEMORY_LIMIT = 3 << 30
#: Hang guard of a limited subprocess (seconds).
TIMEOUT = 120


def _limit() -> None:  # pragma: no cover - runs in the child
    resource.setrlimit(resource.RLIMIT_AS, (MEMORY_LIMIT, MEMORY_LIMIT))
    resource.setrlimit(resource.RLIMIT_CORE, (0, 0))


def run_limited(*args, cwd=None, env=None, timeout=TIMEOUT) -> hs.Run:
    """``python -m robokit.cli ARGS`` with RLIMIT_AS = 3 GB and a hang guard."""
    p = subprocess.run([sys.executable, "-m", "robokit.cli", *map(str, args)], cwd=cwd, capture_output=True,
                       check=False, text=True, timeout=timeout, env=env or hs.subprocess_env(), preexec_fn=_limit)
    return hs.Run(p.returncode, p.stdout, p.stderr)


XACRO_NS = 'xmlns:xacro="http://www.ros.org/wiki/xacro"'


def xacro_robot(body: str, name: str = "r") -> str:
    """A xacro document: ``body`` after one base link."""
    return f'<?xml version="1.0"?>\n<robot name="{name}" {XACRO_NS}>\n<link name="base"/>\n{body}\n</robot>\n'


def arm_links(n: int, prefix: str = "l") -> str:
    """URDF links and revolute joints of an n-joint chain from ``base``."""
    out = []
    parent = "base"
    for i in range(n):
        out.append(hs.link(f"{prefix}{i}", mass="1"))
        out.append(hs.joint(f"j{i}", parent, f"{prefix}{i}", xyz="0 0 0.1"))
        parent = f"{prefix}{i}"
    return "\n".join(out)


_DRIVER = r"""
import contextlib, io, json, sys, warnings
warnings.simplefilter("always")
import robokit.cli
out = []
for argv in json.loads(sys.argv[1]):
    err, std = io.StringIO(), io.StringIO()
    with contextlib.redirect_stderr(err), contextlib.redirect_stdout(std):
        rc = robokit.cli.main(argv)
    out.append([rc, std.getvalue(), err.getvalue()])
sys.__stdout__.write(json.dumps(out))
"""


def run_many(argvs, cwd=None, timeout=TIMEOUT) -> list:
    """Several ``robokit`` command lines in **one** limited subprocess (one import of robokit,
    Pinocchio and numba for all of them): a list of :class:`hardening_support.Run`."""
    import json

    p = subprocess.run([sys.executable, "-c", _DRIVER, json.dumps([[str(a) for a in argv] for argv in argvs])],
                       cwd=cwd, capture_output=True, check=False, text=True, timeout=timeout,
                       env=hs.subprocess_env(), preexec_fn=_limit)
    assert p.returncode == 0, f"driver exit {p.returncode}: {p.stderr[-2000:]}"
    return [hs.Run(rc, out, err) for rc, out, err in json.loads(p.stdout)]
