"""Helpers of the hardening suite: run the CLI (in a subprocess or in-process), write small
robot files, and check the one-line error contract of ``robokit`` (docs/hardening.md).
Imported by the tests as ``hardening_support`` (tests/conftest.py puts tests/support on sys.path)."""
from __future__ import annotations

import math
import os
import re
import subprocess
import sys
from dataclasses import dataclass
from pathlib import Path

import numpy as np

#: The repository root (this file is tests/support/hardening_support.py): subprocesses import robokit from here.
REPO = Path(__file__).resolve().parents[2]

#: A generous hang guard for a subprocess (never a timing assertion).
HANG_GUARD = 60


def subprocess_env(**extra) -> dict:
    env = dict(os.environ)
    env["PYTHONPATH"] = str(REPO) + (os.pathsep + env["PYTHONPATH"] if env.get("PYTHONPATH") else "")
    env.setdefault("MPLBACKEND", "Agg")
    env.update(extra)
    return env


@dataclass
class Run:
    rc: int
    out: str
    err: str

    @property
    def err_lines(self) -> list[str]:
        return [ln for ln in self.err.splitlines() if ln.strip()]

    @property
    def error_line(self) -> str:
        """The one error line (the last line; notes may precede it)."""
        return self.err_lines[-1] if self.err_lines else ""


def run_cli(*args, cwd=None, timeout=HANG_GUARD, env=None) -> Run:
    """``python -m robokit.cli ARGS`` in a subprocess with PYTHONPATH = the repository root."""
    p = subprocess.run([sys.executable, "-m", "robokit.cli", *map(str, args)], cwd=cwd, capture_output=True, check=False,
                       text=True, timeout=timeout, env=env or subprocess_env())
    return Run(p.returncode, p.stdout, p.stderr)


def run_main(args, capture) -> Run:
    """``robokit.cli.main(args)`` in-process; stderr/stdout captured by pytest's capfd/capsys."""
    import robokit.cli

    capture.readouterr()
    rc = robokit.cli.main([str(a) for a in args])
    cap = capture.readouterr()
    return Run(rc, cap.out, cap.err)


#: robokit._optional's notice when importing an optional package takes over two seconds (a loaded
#: machine, a first use), and its closing line: progress, not part of the error
_SLOW_IMPORT = re.compile(r"robokit: .*importing \S+ \(its first use in this process.*\.\.\.|robokit: \S+ imported in [0-9.]+ s"
                          r"|robokit: \.\.\. still importing \S+, [0-9.]+ s")


def assert_one_line_error(run: Run, *names, rc: int = 2) -> str:
    """Exit ``rc``; stderr: only ``robokit: note:`` lines before exactly one ``robokit:`` line of at
    most ~400 characters naming every string in ``names``; no traceback, no urdfdom "Error:" line."""
    assert run.rc == rc, f"exit {run.rc}, expected {rc}; stderr:\n{run.err}"
    lines = run.err_lines
    assert lines, "nothing on stderr"
    *notes, last = lines
    for ln in notes:  # notes, warnings, and the notice of an optional package's slow first import
        assert ln.startswith(("robokit: note:", "robokit: warning:")) or _SLOW_IMPORT.fullmatch(ln), \
            f"unexpected stderr line {ln!r}"
    assert last.startswith("robokit:"), last
    assert not last.startswith("robokit: note:"), f"no error line after the notes: {run.err!r}"
    assert len(last) <= 420, f"message of {len(last)} characters"
    assert "Traceback" not in run.err
    for ln in run.err.splitlines():  # urdfdom's own "Error: ..." lines, Python warnings: none
        assert ln.startswith("robokit:"), f"stray stderr line {ln!r}"
    for name in names:
        assert str(name) in last, f"{name!r} not named in {last!r}"
    return last


def tmp_leftovers(folder: Path) -> list[str]:
    """Hidden temporary files the atomic writer could leave (``.NAME.*.tmp``)."""
    return sorted(p.name for p in Path(folder).iterdir() if p.name.startswith(".") and p.name.endswith(".tmp"))


# ----------------------------------------------------------------------------- robot files
#: The one-joint pendulum: a revolute joint about −y at the base (θ > 0 lifts the link), a 0.5 m
#: link of mass 2 kg with its centre of mass 0.25 m out along x, the tip at x = 0.5 m; gravity
#: −9.81 ẑ. Closed forms: tip (l cos θ, 0, l sin θ); gravity torque m g l_c cos θ; M = I_yy + m l_c².
PEND_L, PEND_LC, PEND_M, PEND_G = 0.5, 0.25, 2.0, 9.81


def urdf_text(joints=None, links=None, name="bot") -> str:
    """A URDF from lists of link and joint XML snippets."""
    return f'<?xml version="1.0"?>\n<robot name="{name}">\n' + "\n".join(links or []) + "\n" + "\n".join(joints or []) + "\n</robot>\n"


def link(name, mass=None, inertia="0.001 0.01 0.01 0 0 0", com="0 0 0", extra="") -> str:
    if mass is None:
        return f'<link name="{name}">{extra}</link>'
    ixx, iyy, izz, ixy, iyz, ixz = inertia.split()
    return (f'<link name="{name}"><inertial><origin xyz="{com}"/><mass value="{mass}"/>'
            f'<inertia ixx="{ixx}" iyy="{iyy}" izz="{izz}" ixy="{ixy}" iyz="{iyz}" ixz="{ixz}"/></inertial>{extra}</link>')


def joint(name, parent, child, jtype="revolute", axis="0 0 1", xyz="0 0 0", rpy="0 0 0", lower="-3", upper="3",
          extra="") -> str:
    lim = f'<limit lower="{lower}" upper="{upper}" effort="10" velocity="5"/>' if jtype in ("revolute", "prismatic") else ""
    ax = f'<axis xyz="{axis}"/>' if jtype not in ("fixed",) else ""
    return (f'<joint name="{name}" type="{jtype}"><parent link="{parent}"/><child link="{child}"/>'
            f'<origin xyz="{xyz}" rpy="{rpy}"/>{ax}{lim}{extra}</joint>')


def pendulum_urdf(**link_kw) -> str:
    kw = {"mass": str(PEND_M), "com": f"{PEND_LC} 0 0"}
    kw.update(link_kw)
    return urdf_text(
        links=[link("base"), link("arm", **kw), link("tip")],
        joints=[joint("shoulder", "base", "arm", axis="0 -1 0"),
                joint("tip_joint", "arm", "tip", "fixed", xyz=f"{PEND_L} 0 0")],
        name="pendulum")


#: The same pendulum as a standard-DH table: frame {1} at the link's end, the COM at −0.25 x₁;
#: the base frame rpy (90°, 0, 0) puts z₀ along −y of the world.
PENDULUM_YAML = f"""\
name: pendulum
convention: standard
gravity: [0, 0, -9.81]
base: {{xyz: [0, 0, 0], rpy: [1.5707963267948966, 0, 0]}}
links:
  - {{joint: R, a: {PEND_L}, alpha: 0, d: 0, theta: 0, qlim: [-3, 3], mass: {PEND_M}, com: [{-PEND_LC}, 0, 0],
     inertia: [0.001, 0.01, 0.01, 0, 0, 0]}}
"""


# ----------------------------------------------------------------------------- independent DH FK
def _rot(axis, t):
    c, s = math.cos(t), math.sin(t)
    R = np.eye(4)
    i, j = {"x": (1, 2), "z": (0, 1)}[axis]
    R[i, i], R[i, j], R[j, i], R[j, j] = c, -s, s, c
    return R


def _trans(axis, v):
    T = np.eye(4)
    T["xyz".index(axis), 3] = v
    return T


def dh_fk_reference(table, q) -> np.ndarray:
    """The tool pose of a DH table composed from elementary motions (Rz Tz Tx Rx, or Rx Tx Rz Tz
    for the modified convention): an implementation independent of robokit's dh_transform."""
    T = np.asarray(table.base, dtype=float).copy()
    for link, qi in zip(table.links, q):
        qi = -qi if link.flip else qi
        th, d = (link.theta + qi, link.d) if link.joint == "R" else (link.theta, link.d + qi)
        if table.convention == "standard":
            T = T @ _rot("z", th) @ _trans("z", d) @ _trans("x", link.a) @ _rot("x", link.alpha)
        else:
            T = T @ _rot("x", link.alpha) @ _trans("x", link.a) @ _rot("z", th) @ _trans("z", d)
    return T @ np.asarray(table.tool, dtype=float)
