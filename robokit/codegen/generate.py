r"""``robokit codegen``: a robot's FK, Jacobian, closed-form IK, gravity and inverse dynamics as C99.

:func:`generate_c` turns a :class:`robokit.Robot` into the text of ``NAME.h`` and ``NAME.c``;
:func:`write_c` writes both into a folder (each atomically, and the pair all or nothing).
The code is generated from the robot's own parameters — ``robot.poe`` (``M``, ``Slist``,
``Mlist``, ``Glist``) for kinematics and dynamics, the closed-form solver's constants for the
IK — so it computes what the Python functions compute.
"""
from __future__ import annotations

import math
import os
import re
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from robokit._io import atomic_write
from robokit.codegen._c import CWriter, c_string, lit, safe_comment, to_float32
from robokit.codegen.dynamics import emit_rnea
from robokit.codegen.ik import emit_ik
from robokit.codegen.kinematics import emit_fk, emit_jacobian
from robokit.errors import InputError

__all__ = ["CSource", "generate_c", "write_c", "c_name", "C_KEYWORDS"]

#: Reserved words of C99 (and C11's, which a C99 name should avoid too).
C_KEYWORDS = frozenset("""
auto break case char const continue default do double else enum extern float for goto if inline int long
register restrict return short signed sizeof static struct switch typedef union unsigned void volatile while
_Bool _Complex _Imaginary _Alignas _Alignof _Atomic _Generic _Noreturn _Static_assert _Thread_local
""".split())

_C_IDENT = re.compile(r"^[A-Za-z_][A-Za-z0-9_]*$")


@dataclass(frozen=True)
class CSource:
    """The generated files of :func:`generate_c`.

    Attributes
    ----------
    name : str
        The C prefix NAME of every function (see :func:`c_name`).
    header : str
        Text of ``NAME.h``.
    source : str
        Text of ``NAME.c``.
    has_ik : bool
        Whether ``NAME_ik`` is defined (the arm has a closed form).
    ik_note : str
        Why there is no IK, or which closed-form method it uses.

    Examples
    --------
    >>> src = generate_c(rk.load("twolink"))
    >>> src.name, src.has_ik, "void twolink_fk(" in src.header
    ('twolink', False, True)
    """

    name: str
    header: str
    source: str
    has_ik: bool
    ik_note: str


def c_name(robot_name: str, name: str | None = None) -> str:
    """The C prefix NAME of the generated functions.

    Parameters
    ----------
    robot_name : str
        The robot's name (``Robot.name``).
    name : str or None
        An explicit prefix (``--name``); it must be a C identifier and not a C keyword.

    Returns
    -------
    str
        ``name`` if given, else the robot's name lower-cased with every character that cannot
        be in a C identifier replaced by ``_`` (``"UR5e arm"`` → ``"ur5e_arm"``; a name that
        would start with a digit gets a leading ``r``).

    Raises
    ------
    InputError
        If ``name`` is not a C identifier or is a keyword.

    Examples
    --------
    >>> c_name("PUMA-560")
    'puma_560'
    """
    if name is not None:
        if not _C_IDENT.match(name):
            raise InputError(f"--name: {name!r} is not a C identifier (letters, digits and _, not starting "
                             "with a digit)")
        if name in C_KEYWORDS:
            raise InputError(f"--name: {name!r} is a C keyword")
        return name
    out = re.sub(r"[^a-z0-9_]", "_", robot_name.lower())
    if not out or out[0].isdigit():
        out = "r" + out
    if out in C_KEYWORDS:
        out += "_robot"
    return out


def _version() -> str:
    from importlib.metadata import PackageNotFoundError, version

    try:
        return version("robokit")
    except PackageNotFoundError:  # pragma: no cover - a source tree never installed
        return "0+unknown"


def _armature(robot: Any) -> np.ndarray:
    arm = np.asarray(getattr(robot.model, "armature", np.zeros(robot.n)), dtype=float).reshape(-1)
    return arm if arm.shape == (robot.n,) else np.zeros(robot.n)


def _kinds(robot: Any) -> list[str]:
    """"R"/"P" per joint, from the screw axes (a prismatic joint's ω is zero)."""
    S = robot.poe.Slist
    return ["R" if float(np.linalg.norm(S[:3, i])) > 0.5 else "P" for i in range(S.shape[1])]


def _function(signature: str, body: CWriter, doc: str) -> str:
    body.prune()
    text = body.text()
    unused = [p for p in re.findall(r"(\w+)\[[^\]]*\][,)]", signature) if not re.search(rf"\b{p}\[", text)]
    voids = "".join(f"    (void){p};  /* not needed by this robot (e.g. massless links) */\n" for p in unused)
    return f"/* {doc} */\n{signature}\n{{\n{voids}{text}\n}}\n"


def generate_c(robot: Any, name: str | None = None, float32: bool = False, nominal: Any = None) -> CSource:
    r"""Generate the C99 files of a robot's controller functions.

    Parameters
    ----------
    robot : :class:`robokit.Robot`
        Any robot ``robokit.load`` returns (DH file of either convention, URDF, xacro, MJCF,
        example-robot-data name).
    name : str or None
        C prefix of every function and macro (default: :func:`c_name` of ``robot.name``).
    float32 : bool
        Write ``float`` instead of ``double`` everywhere (literals with ``f``, ``sinf`` …), for
        microcontrollers whose FPU is single precision.
    nominal : optional
        For a calibrated or nearly special arm, its nominal structure as :func:`robokit.ik_analytic`
        takes it (default: recorded on the robot, or detected; ``False``: none, the general 6R method).

    Returns
    -------
    CSource
        ``.header`` (NAME.h) and ``.source`` (NAME.c). The header declares, arrays row-major:
        ``NAME_fk(q, T[16])`` (the tip pose in the base frame, as ``Robot.frame_pose``),
        ``NAME_jacobian(q, J[6*NAME_N])`` (rows (ω; v), base axes, v of the tool origin),
        ``NAME_ik(T, q[NAME_MAX_SOLUTIONS*NAME_N])`` when ``NAME_HAS_IK`` (every closed-form
        solution, as ``ik_analytic``), ``NAME_gravity(q, tau)``, ``NAME_rnea(q, qd, qdd, tau)``
        (Pinocchio's rnea), and the macros ``NAME_N``, ``NAME_HAS_IK``, ``NAME_MAX_SOLUTIONS``,
        the joint limits and types. Units: m, rad, s, kg, N, N·m.

    Notes
    -----
    Kinematics from the product of exponentials ``T = e^{[S₁]q₁} ⋯ e^{[Sₙ]qₙ} M`` (Lecture 4),
    dynamics from the recursive Newton–Euler algorithm (Lecture 7), both with the robot's
    constants folded in; the IK from Pieper's method, the three-parallel-axes method
    (Lecture 5) or the general 6R elimination, see :mod:`robokit.codegen.ik` and
    :mod:`robokit.codegen.ik_general`.

    Examples
    --------
    >>> import robokit
    >>> src = generate_c(robokit.load("puma560"))
    >>> "int puma560_ik(const double T[16]" in src.header
    True
    """
    prefix = c_name(robot.name, name)
    poe = robot.poe
    n = int(poe.n)
    kinds = _kinds(robot)
    names = [str(x) for x in poe.joint_names]
    qlim = np.asarray(poe.qlim, dtype=float)
    P = prefix
    ik = emit_ik(robot, P, float32, nominal)

    # ------------------------------------------------------------------ header
    h: list[str] = []
    guard = f"ROBOKIT_{P.upper()}_H"
    frames = (f"base frame = the robot's root ({'DH base' if robot.dh is not None else 'URDF root link'}); "
              f"tool frame = {safe_comment(repr(robot.tip))}")
    rname = safe_comment(repr(robot.name))
    h.append("/*")
    h.append(f" * {P}.h - controller functions of the robot {rname} ({n} joints), generated by")
    h.append(f" * robokit {_version()} (`robokit codegen`) from {safe_comment(robot.source or 'a Python Robot')}.")
    h.append(" * Do not edit: regenerate from the robot description instead.")
    h.append(" *")
    h.append(" * Units: m, rad (revolute joints), m (prismatic joints), s, kg, N, N m.")
    h.append(f" * Frames: {frames}; poses are 4x4 homogeneous")
    h.append(" * transforms, row-major (T[4*i + j] is row i, column j). Jacobians are 6 x N, row-major,")
    h.append(" * rows (wx, wy, wz, vx, vy, vz) in base axes, v the velocity of the tool origin (Pinocchio's")
    h.append(" * LOCAL_WORLD_ALIGNED). Twists and wrenches are angular first.")
    h.append(f" * Scalar type: {'float (generated with --float32)' if float32 else 'double'}.")
    h.append(" * Every function is reentrant: no globals (only const tables), no allocation, no I/O.")
    h.append(f" * Inverse kinematics: {ik.method_line.replace('NAME', P)}")
    h.append(" */")
    h.append(f"#ifndef {guard}")
    h.append(f"#define {guard}")
    h.append("")
    h.append(f"#define {P}_N {n}  /* joints */")
    h.append(f"#define {P}_HAS_IK {1 if ik.has_ik else 0}  /* {ik.note} */")
    h.append(f"#define {P}_MAX_SOLUTIONS {ik.max_solutions}  /* "
             + (f"most solutions {P}_ik returns */" if ik.has_ik else "no IK: 1, so that arrays sized with it are valid C */"))
    h.append("")
    h.append("/* joint types: 0 revolute (rad), 1 prismatic (m); joint names in order: */")
    for i in range(n):
        h.append(f"#define {P}_JOINT{i}_TYPE {0 if kinds[i] == 'R' else 1}  /* {safe_comment(names[i])} */")
    h.append("")
    h.append("/* joint limits (rad or m); HUGE_VAL (from <math.h>) where unlimited (continuous joints) */")
    for i in range(n):
        lo, hi = qlim[i]
        h.append(f"#define {P}_JOINT{i}_LOWER {_limit(lo)}")
        h.append(f"#define {P}_JOINT{i}_UPPER {_limit(hi)}")
    h.append("")
    h.append("/* joint limits and types as tables (definitions in the .c file) */")
    h.append(f"extern const double {P}_qlim[{P}_N][2];")
    h.append(f"extern const int {P}_joint_type[{P}_N];")
    h.append(f"extern const char *const {P}_joint_names[{P}_N];")
    h.append("")
    h.append(f"/* Forward kinematics: T = pose of the tool frame in the base frame at joint values q. */")
    h.append(f"void {P}_fk(const double q[{P}_N], double T[16]);")
    h.append("")
    h.append(f"/* Geometric Jacobian (6 x N, rows (w; v)) at q. */")
    h.append(f"void {P}_jacobian(const double q[{P}_N], double J[6 * {P}_N]);")
    h.append("")
    h.extend(ik.header_lines)
    h.append(f"/* Gravity torques g(q) (N m or N), the model's gravity vector. */")
    h.append(f"void {P}_gravity(const double q[{P}_N], double tau[{P}_N]);")
    h.append("")
    h.append(f"/* Inverse dynamics tau = M(q) qdd + C(q, qd) qd + g(q) (recursive Newton-Euler). */")
    h.append(f"void {P}_rnea(const double q[{P}_N], const double qd[{P}_N], const double qdd[{P}_N], "
             f"double tau[{P}_N]);")
    h.append("")
    h.append(f"#endif /* {guard} */")
    header = "\n".join(h) + "\n"

    # ------------------------------------------------------------------ source
    s: list[str] = []
    s.append("/*")
    s.append(f" * {P}.c - generated by robokit {_version()} for {rname}; see {P}.h for units and frames.")
    s.append(" * Every constant below is the robot's own: the screw axes S_i and home pose M of its product")
    s.append(" * of exponentials, its link frames and inertias, its closed-form IK constants.")
    s.append(" */")
    s.append("#include <math.h>")
    s.append("#include <string.h>")
    s.append(f'#include "{P}.h"')
    s.append("")
    rows = ", ".join(f"{{{_limit(lo)}, {_limit(hi)}}}" for lo, hi in qlim)
    s.append(f"const double {P}_qlim[{P}_N][2] = {{{rows}}};")
    s.append(f"const int {P}_joint_type[{P}_N] = {{{', '.join('0' if k == 'R' else '1' for k in kinds)}}};")
    s.append(f"const char *const {P}_joint_names[{P}_N] = {{{', '.join(c_string(x) for x in names)}}};")
    s.append("")
    w = CWriter()
    emit_fk(w, poe.Slist, poe.M, kinds, names)
    s.append(_function(f"void {P}_fk(const double q[{P}_N], double T[16])", w,
                       "forward kinematics (Lecture 4, product of exponentials)"))
    w = CWriter()
    emit_jacobian(w, poe.Slist, poe.M, kinds, names)
    s.append(_function(f"void {P}_jacobian(const double q[{P}_N], double J[6 * {P}_N])", w,
                       "geometric Jacobian, rows (w; v), v of the tool origin, base axes"))
    if ik.has_ik:
        s.append(ik.source)
    else:
        s.append(f"/* no {P}_ik: {ik.note} */\n")
    arm = _armature(robot)
    w = CWriter()
    emit_rnea(w, poe.Mlist, poe.Glist, poe.Slist, kinds, np.asarray(poe.gravity, dtype=float), arm,
              velocities=False)
    s.append(_function(f"void {P}_gravity(const double q[{P}_N], double tau[{P}_N])", w,
                       "gravity torques: Newton-Euler with qd = qdd = 0 (velocity terms folded away)"))
    w = CWriter()
    emit_rnea(w, poe.Mlist, poe.Glist, poe.Slist, kinds, np.asarray(poe.gravity, dtype=float), arm)
    s.append(_function(f"void {P}_rnea(const double q[{P}_N], const double qd[{P}_N], const double qdd[{P}_N], "
                       f"double tau[{P}_N])", w, "inverse dynamics (Lecture 7, recursive Newton-Euler)"))
    source = "\n".join(s)
    if float32:
        header, source = to_float32(header), to_float32(source)
    return CSource(P, header, source, ik.has_ik, ik.note)


def _limit(x: float) -> str:
    if math.isinf(x):
        return "HUGE_VAL" if x > 0 else "(-HUGE_VAL)"
    return f"({lit(x)})" if x < 0 else lit(x)


def write_c(src: CSource, folder: str | os.PathLike[str]) -> tuple[Path, Path]:
    r"""Write ``NAME.h`` and ``NAME.c`` into ``folder``: both or neither.

    Parameters
    ----------
    src : CSource
        From :func:`generate_c`.
    folder : path
        An existing folder.

    Returns
    -------
    (Path, Path)
        The header and source paths.

    Raises
    ------
    InputError
        If ``folder`` does not exist or is a file.

    Examples
    --------
    >>> import tempfile
    >>> with tempfile.TemporaryDirectory() as tmp:
    ...     h, c = write_c(generate_c(rk.load("twolink")), tmp)
    ...     print(h.name, c.name, "#include \"twolink.h\"" in c.read_text())
    twolink.h twolink.c True
    """
    out = Path(folder)
    if out.exists() and not out.is_dir():
        raise InputError(f"-o: {str(out)!r} is a file, not a folder")
    if not out.is_dir():
        raise InputError(f"-o: folder {str(out)!r} does not exist")
    h_path, c_path = out / f"{src.name}.h", out / f"{src.name}.c"
    for p in (h_path, c_path):
        if p.is_dir():
            raise InputError(f"-o: {str(p)!r} exists and is a folder")
    old_h = h_path.read_bytes() if h_path.is_file() else None
    atomic_write(h_path, src.header)
    try:
        atomic_write(c_path, src.source)
    except BaseException:  # the pair is all or nothing: put the header back as it was
        if old_h is None:
            h_path.unlink(missing_ok=True)
        else:
            atomic_write(h_path, old_h)
        raise
    return h_path, c_path
