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

from robokit._io import atomic_write, check_output_folder, make_output_folder
from robokit.codegen._c import RANGES, CWriter, c_string, check_literals, lit, out_of_range, safe_comment, to_float32
from robokit.codegen.dynamics import emit_rnea
from robokit.codegen.ik import emit_ik
from robokit.codegen.kinematics import emit_fk, emit_jacobian, emit_joint_poses
from robokit.errors import InputError

__all__ = ["CSource", "generate_c", "write_c", "c_name", "C_KEYWORDS", "STANDARD_HEADERS"]

#: Reserved words of C99 (and C11's, which a C99 name should avoid too).
C_KEYWORDS = frozenset("""
auto break case char const continue default do double else enum extern float for goto if inline int long
register restrict return short signed sizeof static struct switch typedef union unsigned void volatile while
_Bool _Complex _Imaginary _Alignas _Alignof _Atomic _Generic _Noreturn _Static_assert _Thread_local
""".split())

#: A C identifier; always used with ``fullmatch`` (``$`` would accept a trailing newline).
_C_IDENT = re.compile(r"[A-Za-z_][A-Za-z0-9_]*")

#: Every standard header of C (C89 to C23) and POSIX (POSIX.1-2024 and the headers earlier
#: issues had) that sits at the top of the include path, without ``.h``, and the top-level headers
#: those include in glibc, newlib and GCC's and Clang's own headers (``features.h``,
#: ``alloca.h``, ``newlib.h``, …; found with ``cc -M``). ``NAME.h`` written into
#: a folder given to the compiler with ``-I`` would shadow the system header of the same name for
#: the whole build (``#include <math.h>`` would find ``DIR/math.h``), and on a case-insensitive
#: file system ``Math.h`` does too: the generated file names never equal one of these, compared
#: case-insensitively (:func:`c_name`).
STANDARD_HEADERS = frozenset("""
assert complex ctype errno fenv float inttypes iso646 limits locale math setjmp signal stdalign stdarg
stdatomic stdbit stdbool stdckdint stddef stdint stdio stdlib stdnoreturn string tgmath threads time uchar
wchar wctype
aio cpio devctl dirent dlfcn endian fcntl fmtmsg fnmatch ftw glob grp iconv langinfo libgen libintl monetary
mqueue ndbm netdb nl_types poll pthread pwd regex sched search semaphore spawn strings stropts syslog tar
termios trace ucontext ulimit unistd utime utmpx wordexp
features alloca syslimits __stddef_max_align_t _ansi _newlib_version newlib malloc
""".split())


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
    ('twolink', True, True)
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
        If ``name`` is not a C identifier (the whole string: a trailing newline is not part of
        one), is a keyword, or is the name of a standard C or POSIX header
        (:data:`STANDARD_HEADERS`, any case: ``NAME.h`` would shadow ``<NAME.h>``). A robot's own
        name that is a keyword or a header name gets ``_robot`` appended instead.

    Examples
    --------
    >>> c_name("PUMA-560")
    'puma_560'
    >>> c_name("math")   # math.h would shadow <math.h>
    'math_robot'
    """
    if name is not None:
        if not isinstance(name, str) or not _C_IDENT.fullmatch(name):
            raise InputError(f"--name: {name!r:.80} is not a C identifier (letters, digits and _, not starting "
                             "with a digit)")
        if name in C_KEYWORDS:
            raise InputError(f"--name: {name!r} is a C keyword")
        if name.lower() in STANDARD_HEADERS:
            raise InputError(f"--name: {name!r} would write {name}.h, which shadows the standard header "
                             f"<{name.lower()}.h> for every file compiled with -I on its folder; choose another name")
        return name
    out = re.sub(r"[^a-z0-9_]", "_", robot_name.lower())
    if not out or out[0].isdigit():
        out = "r" + out
    if out in C_KEYWORDS or out in STANDARD_HEADERS:
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
        ``NAME_joint_poses(q, T[16*NAME_N])`` (joint k's frame pose in the base frame, Pinocchio's
        ``data.oMi[k]``, k = 1..n), ``NAME_jacobian(q, J[6*NAME_N])`` (rows (ω; v), base axes, v of
        the tool origin),
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
    _check_parameters(robot, float32)
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
    h.append(f"/* Joint frames: T[16*(k-1) .. 16*k-1] = pose of joint k's frame in the base frame at q,")
    h.append(f" * k = 1..N (Pinocchio's data.oMi[k]: the frame the joint's axis, its child link's inertia")
    h.append(f" * and geometry are attached to). */")
    h.append(f"void {P}_joint_poses(const double q[{P}_N], double T[16 * {P}_N]);")
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
    emit_joint_poses(w, poe.Slist, _joint_homes(robot), kinds, names)
    s.append(_function(f"void {P}_joint_poses(const double q[{P}_N], double T[16 * {P}_N])", w,
                       "every joint frame's pose in the base frame (Pinocchio's oMi[1..N])"))
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
    check_literals(header, float32, f"{P}.h")
    check_literals(source, float32, f"{P}.c")
    return CSource(P, header, source, ik.has_ik, ik.note)


def _joint_homes(robot: Any) -> np.ndarray:
    """(n, 4, 4): each joint frame's pose in the base frame at q = 0 (Pinocchio's ``oMi[1..n]``)."""
    import pinocchio as pin

    data = robot.model.createData()
    pin.forwardKinematics(robot.model, data, pin.neutral(robot.model))
    return np.array([data.oMi[k].homogeneous for k in range(1, robot.n + 1)])


def _check_parameters(robot: Any, float32: bool) -> None:
    """Refuse a robot whose own numbers the target type cannot hold as normal numbers
    (:data:`~robokit.codegen._c.RANGES`: beyond it the C does not compile under ``-Werror``; a
    nonzero value below it becomes 0, or a subnormal that single-precision FPUs flush to zero),
    naming the joint or link and the key. The numbers are the model's as loaded: each joint's
    placement, finite limits and armature, each link's mass, centre of mass and inertia, the tool
    frame's placement, gravity. Rotation entries within 1e-14 of 0 are round-off the emitters write
    as 0 (:func:`~robokit.codegen._c.snap`). :func:`~robokit.codegen._c.check_literals` then checks
    every constant written, the folded ones included."""
    model = robot.model
    qlim = np.asarray(robot.poe.qlim, dtype=float)
    arm = _armature(robot)
    tip = model.frames[robot.tip_id]
    items: list[tuple[str, Any]] = [
        (f"the tool frame {tip.name!r}: position", tip.placement.translation),
        (f"the tool frame {tip.name!r}: rotation", _unsnapped(tip.placement.rotation)),
        ("gravity", model.gravity.linear)]
    for i in range(robot.n):
        jn = str(model.names[i + 1])
        Y, X = model.inertias[i + 1], model.jointPlacements[i + 1]
        items += [(f"joint {jn!r}: origin xyz", X.translation),
                  (f"joint {jn!r}: origin rotation", _unsnapped(X.rotation)),
                  (f"joint {jn!r}: limits", qlim[i][np.isfinite(qlim[i])]),
                  (f"joint {jn!r}: armature", arm[i]),
                  (f"the link of joint {jn!r}: mass", Y.mass),
                  (f"the link of joint {jn!r}: centre of mass", Y.lever),
                  (f"the link of joint {jn!r}: inertia", Y.inertia)]
    for what, values in items:
        for x in np.asarray(values, dtype=float).reshape(-1):
            if out_of_range(x, float32):
                kind = "float" if float32 else "double"
                tiny, huge = RANGES[float32]
                raise InputError(f"codegen{' --float32' if float32 else ''}: {robot.name}: {what} holds {x:.6g}, "
                                 f"outside {kind}'s normal range ({tiny:.3g} to {huge:.3g} in magnitude); write 0 "
                                 "for a negligible value" + (" or generate double C" if float32 else ""))


def _unsnapped(R: Any) -> np.ndarray:
    """The entries of a rotation the emitters keep (round-off within 1e-14 of 0 is written as 0)."""
    R = np.asarray(R, dtype=float).reshape(-1)
    return R[np.abs(R) >= 1e-14]


def _limit(x: float) -> str:
    if math.isinf(x):
        return "HUGE_VAL" if x > 0 else "(-HUGE_VAL)"
    return f"({lit(x)})" if x < 0 else lit(x)


#: Largest old ``NAME.h`` copied to be put back if writing ``NAME.c`` fails, where the file system
#: has no hard links (with hard links nothing is copied or read, whatever the size).
MAX_KEPT_BYTES = 16 << 20


def write_c(src: CSource, folder: str | os.PathLike[str]) -> tuple[Path, Path]:
    r"""Write ``NAME.h`` and ``NAME.c`` into ``folder``: both or neither.

    Each file is written atomically (:func:`robokit._io.atomic_write`: a symbolic link at either
    name is replaced, never written through; a replaced file keeps its mode). An existing
    ``NAME.h`` is kept aside under a second name (a hard link: nothing is read, whatever its size,
    and a symbolic link is kept as the link) until ``NAME.c`` is written, and put back if that fails.

    Parameters
    ----------
    src : CSource
        From :func:`generate_c`.
    folder : path
        The output folder; created, with its missing parents, when it does not exist.

    Returns
    -------
    (Path, Path)
        The header and source paths.

    Raises
    ------
    InputError
        If ``folder`` (or a folder above it) is a file, or cannot be created.

    Examples
    --------
    >>> import tempfile
    >>> with tempfile.TemporaryDirectory() as tmp:
    ...     h, c = write_c(generate_c(rk.load("twolink")), tmp)
    ...     print(h.name, c.name, "#include \"twolink.h\"" in c.read_text())
    twolink.h twolink.c True
    """
    out = check_output_folder(folder)
    h_path, c_path = out / f"{src.name}.h", out / f"{src.name}.c"
    for p in (h_path, c_path):
        if p.is_dir():
            raise InputError(f"-o: {str(p)!r} exists and is a folder")
    make_output_folder(out)
    saved = _keep_aside(h_path)
    try:
        atomic_write(h_path, src.header)
        try:
            atomic_write(c_path, src.source)
        except BaseException:  # the pair is all or nothing: put the header back as it was
            if saved is None:
                h_path.unlink(missing_ok=True)
            else:
                os.replace(saved, h_path)
                saved = None
            raise
    finally:
        if saved is not None:
            saved.unlink(missing_ok=True)
    return h_path, c_path


def _keep_aside(path: Path) -> Path | None:
    """A second name for whatever is at ``path`` (a hard link to the file itself, or to the
    symbolic link itself — never to what it points to), so that it can be put back with one
    rename; None when nothing is there. Nothing is read: keeping a 6 GB file costs what keeping a
    small one costs. On a file system without hard links the old entry is copied instead: a
    symbolic link as a link, a regular file of at most :data:`MAX_KEPT_BYTES` read with
    ``O_NOFOLLOW``; anything else is not kept (it is replaced like any output)."""
    import secrets
    import stat

    try:
        st = os.lstat(path)
    except FileNotFoundError:
        return None
    aside = path.with_name(f".{path.name}.{secrets.token_hex(4)}.old")
    try:
        os.link(path, aside, follow_symlinks=False)
        return aside
    except OSError:
        pass
    if stat.S_ISLNK(st.st_mode):
        os.symlink(os.readlink(path), aside)
        return aside
    if not stat.S_ISREG(st.st_mode) or st.st_size > MAX_KEPT_BYTES:
        return None
    fd = os.open(path, os.O_RDONLY | os.O_NOFOLLOW | getattr(os, "O_NONBLOCK", 0) | getattr(os, "O_CLOEXEC", 0))
    try:
        data = os.read(fd, MAX_KEPT_BYTES + 1)
    finally:
        os.close(fd)
    if len(data) > MAX_KEPT_BYTES:
        return None
    atomic_write(aside, data)
    return aside
