"""Helpers of the second hardening round: the CLI in a subprocess under resource limits (a
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
