r"""C for the general 6R closed form (``NAME_ik`` of an arm with no special structure).

:func:`robokit.ik_analytic` solves any 6R arm without a spherical wrist or three parallel axes
(an offset wrist such as the Kinova Jaco's) by the Raghavan–Roth elimination and the
Manocha–Canny eigenproblem (:mod:`robokit.ik.general_6r`): up to 16 solutions. The C follows
:meth:`robokit.ik.general_6r.GeneralSixR.solve` step for step, one C function per Python step
(the names are the Python ones). The algorithm does not depend on the arm and is a real C file,
``robokit/codegen/templates/g6r.c`` with its header ``g6r.h`` (compiled on their own by the
tests), which :func:`routines` copies verbatim into ``NAME.c``; this module writes only the
arm's numbers, as ``static const`` tables and one ``const g6r_arm`` (:func:`tables`), and the
per-robot entry points. The steps:

1. the loop equation's 14 quantities on both sides (``matrices``: the side without the target
   is a per-arm ``static const`` table, the side with it is built per pose from the per-arm
   15 × 15 maps and the target's map ``f_pose``);
2. θ of two joints eliminated with the left null space of the 14 × 8 matrix Q (Householder QR)
   and its pseudo-inverse (one-sided Jacobi SVD), giving the 12 × 12 quadratic matrix
   polynomial ``A x² + B x + C`` (``pencil``);
3. its eigenvalues as those of the 24 × 24 companion matrix ``[[0, I], [−A⁻¹C, −A⁻¹B]]``
   (LU with partial pivoting, balancing, Hessenberg reduction, Francis double-shift QR), less
   the pairs x = ±i first where the reading has them (``deflate``: four pairs when the pivot is
   the joint of its group farthest from the eliminated one, a 16 × 16 iteration);
   where A is near singular (σ_min/σ_max ≤ 1e-10) Python takes the generalised eigenproblem
   (QZ) and the C turns the half-angle variable by a fixed angle instead
   (``x = (y + t)/(1 − t y)``), which gives the same roots with a regular leading matrix —
   simpler than a QZ in C and as robust, since only the roots (then polished) are used;
4. per real eigenvalue the null vector of ``A x² + B x + C`` (inverse iteration), the
   back-substitution, the eliminated joint, Newton polish on the pose (geometric Jacobian,
   SVD least squares as numpy's ``lstsq``), convergence test;
5. the next three readings of the loop when the pose is badly conditioned for the best one,
   duplicates merged, the solutions ordered by q₃ then q₁, q₂, q₄, q₅, q₆ (as Python, so the
   order does not depend on the order in which the eigenvalues are found), the "singular"
   flag, then ``ik_analytic``'s wrapping, limit flags and labels (``"solution k of m"``);
6. for an arm whose DH table's offsets are kilometres (``robokit.ik.closed_form.ILL_DH``, the Kinova
   Gen3 lite), as :meth:`robokit.ik.general_6r.ArmPolish.finish`: each solution polished on the arm's
   own kinematics by the calibrated arms' ``NAME_cal_polish``
   (:func:`robokit.codegen.ik_calibrated.polish_code`), rows that do not reach the acceptance dropped,
   copies merged, the labels renumbered (``NAME_g6_arm_finish``, :func:`arm_polish_code`).

The per-arm numbers come from :class:`robokit.ik.GeneralSixRConstants` (the frozen record of
``GeneralSixR.export_constants()``, the same numbers the Python solver uses): the scaled DH
chain, the tolerances, the four best readings' tables.
With ``--float32`` no IK is generated (``NAME_HAS_IK 0``): the elimination squares the
conditioning of the pose (σ_min/σ_max of Q down to 1e-6 on ordinary poses), beyond what
single precision resolves.
"""
from __future__ import annotations

import math
import re
from functools import lru_cache
from importlib import resources
from typing import Any

import numpy as np

from robokit.codegen._c import CWriter, lit, safe_comment
from robokit.codegen._solver_constants import IKConstants
from robokit.codegen.ik_calibrated import polish_code

__all__ = ["MAX_SOLUTIONS_6R", "FLOAT32_NOTE", "arm_polish_code", "general_6r_labels", "emit_general_6r"]

#: Most solutions of a general 6R arm (the degree of its characteristic polynomial).
MAX_SOLUTIONS_6R = 16

#: Why ``--float32`` has no general 6R IK (written into the header).
FLOAT32_NOTE = ("robokit has a closed form (general 6R) but its C is generated in double only: the elimination's "
                "14 x 8 and 12 x 12 matrices reach condition numbers of 1e6 on ordinary poses, beyond float; "
                "generate without --float32 or use robokit.ik_analytic")

_ROT_DELTA = 1.1  # rad: the fixed turn of the half-angle variable used when A is near singular (g6r.c: tan(delta/2))


def general_6r_labels() -> list[str]:
    """The label table of the general 6R C: index ``((m − 1) m / 2 + k − 1) · 2 + singular``.

    Returns
    -------
    list of str
        ``"solution k of m"`` and ``"solution k of m, singular"`` for 1 ≤ k ≤ m ≤ 16.

    Examples
    --------
    >>> general_6r_labels()[:3]
    ['solution 1 of 1', 'solution 1 of 1, singular', 'solution 1 of 2']
    """
    out = []
    for m in range(1, MAX_SOLUTIONS_6R + 1):
        for k in range(1, m + 1):
            out.append(f"solution {k} of {m}")
            out.append(f"solution {k} of {m}, singular")
    return out


def _table(name: str, values: Any, per_line: int = 15) -> str:
    flat = [float(x) for x in np.asarray(values, dtype=float).reshape(-1)]
    body = ",\n    ".join(", ".join(lit(x) for x in flat[i:i + per_line]) for i in range(0, len(flat), per_line))
    return f"static const double {name}[{len(flat)}] = {{\n    {body}\n}};"


def _ints(values: Any) -> str:
    return "{" + ", ".join(str(int(x)) for x in np.asarray(values).reshape(-1)) + "}"


def template(name: str) -> str:
    """The text of a C template shipped in ``robokit/codegen/templates`` (``g6r.h``, ``g6r.c``)."""
    return _template(name)


@lru_cache(maxsize=None)
def _template(name: str) -> str:
    return resources.files("robokit.codegen").joinpath("templates").joinpath(name).read_text(encoding="utf-8")


def workspace_doubles() -> int:
    """``G6R_WORKSPACE_DOUBLES`` of ``templates/g6r.h``: the size of ``NAME_ik_workspace`` in doubles."""
    m = re.search(r"G6R_WORKSPACE_DOUBLES = (\d+)", template("g6r.h"))
    assert m is not None, "templates/g6r.h defines G6R_WORKSPACE_DOUBLES"
    return int(m.group(1))


def tables(k: IKConstants, P: str) -> str:
    """The per-arm constants: the readings' tables and the ``const g6r_arm`` (C text, after the template)."""
    sv = k.general
    assert sv is not None, "the general 6R method's constants"
    inits = []
    out = [f"/* general 6R: the canonical chain Z1 X1 ... Z6 with lengths divided by the scale {lit(sv.scale)} m; "
           "the readings of the loop equation, the best first (GeneralSixR.export_constants()) */"]
    for i, rd in enumerate(sv.readings):
        Ms = np.array(rd.Ms, dtype=float)
        Ms[rd.w_index] = 0.0  # replaced per pose
        nw = len(rd.signs)
        pre_id = bool(np.array_equal(rd.pre, np.eye(15)))  # the identity: a null pointer, no product
        post_id = bool(np.array_equal(rd.post, np.eye(15)))
        out += [f"/* reading {i}: pivot joint {rd.roles[0] + 1}, eliminated joint {rd.roles[5] + 1} */",
                _table(f"{P}_g6_r{i}_const", rd.const), _table(f"{P}_g6_r{i}_Ms", Ms),
                "" if pre_id else _table(f"{P}_g6_r{i}_pre", rd.pre),
                "" if post_id else _table(f"{P}_g6_r{i}_post", rd.post),
                _table(f"{P}_g6_r{i}_signs", rd.signs), _table(f"{P}_g6_r{i}_f", rd.f), ""]
        inits.append(f"    {{{_ints(rd.roles)}, {int(rd.three_has_w)}, {nw}, {rd.w_index}, "
                     f"{int(rd.w_inverse)}, {rd.deflate}, 0, {P}_g6_r{i}_const, {P}_g6_r{i}_Ms, "
                     f"{'0' if pre_id else f'{P}_g6_r{i}_pre'}, {'0' if post_id else f'{P}_g6_r{i}_post'}, "
                     f"{P}_g6_r{i}_signs, {P}_g6_r{i}_f, {_ints(rd.perm3)}, {_ints(rd.perm2)}}}")
    out.append(f"static const g6r_reading {P}_g6_readings[{len(inits)}] = {{\n" + ",\n".join(inits) + "\n};")

    def row(values: Any) -> str:
        return "{" + ", ".join(lit(float(x)) for x in values) + "}"

    out.append(f"""static const g6r_arm {P}_g6_arm = {{
    {row(sv.a)},
    {row(sv.d)},
    {row(math.cos(x) for x in sv.alpha)},
    {row(math.sin(x) for x in sv.alpha)},
    {row(sv.th0)},
    {lit(math.cos(sv.gamma))}, {lit(math.sin(sv.gamma))}, {lit(sv.gamma)},
    {lit(sv.x0)},
    {lit(sv.imag_tol)}, {lit(sv.converged)}, {lit(sv.same)}, {lit(sv.poor)},
    {P}_g6_readings, {len(inits)}, 0
}};""")
    return "\n".join(out) + "\n"


def routines() -> str:
    """The robot-independent C (``templates/g6r.h`` and ``g6r.c``, verbatim, ``g6r_solve`` static)."""
    body = template("g6r.c").replace('#include "g6r.h"\n', template("g6r.h"), 1)
    return ("/* ---- robokit/codegen/templates/g6r.h and g6r.c (the general 6R IK, robot-independent) ---- */\n"
            "#define G6R_API static\n" + body)


def emit_general_6r(e: Any, T06_code: str, T06: Any) -> str:
    """The body of ``NAME_ik_ex`` for a general 6R arm: the target, the solve, the flips.

    Parameters
    ----------
    e : the IK emitter (:mod:`robokit.codegen.ik`), with ``k`` (IKConstants) and ``P``.
    T06_code : str
        C lines computing the canonical target's temporaries.
    T06 : Pose
        The canonical target's entries as C expressions.

    Returns
    -------
    str
        C statements (inside ``NAME_ik_ex``) filling ``rows``, ``lab``, ``deg``, ``nr``.
    """
    k, P = e.k, e.P
    assert k.general is not None, "the general 6R method's constants"
    scale = k.general.scale
    w = CWriter()
    R, p = T06.R, T06.p
    for i in range(3):
        for j in range(3):
            v = R[i][j]
            w.line(f"T06s[{4 * i + j}] = {lit(v) if isinstance(v, float) else v};")
        v = p[i]
        w.line(f"T06s[{4 * i + 3}] = ({lit(v) if isinstance(v, float) else v}) / {lit(scale)};")
    w.line("T06s[12] = T06s[13] = T06s[14] = 0.0;")
    w.line("T06s[15] = 1.0;")
    flips = ""
    if k.flip is not None and any(k.flip):
        neg = [j for j, f in enumerate(k.flip) if f]
        flips = ("    /* flipped joints (theta = offset - q) were solved as q' = -q */\n"
                 "    for (ir = 0; ir < nr; ++ir) {\n"
                 + "".join(f"        rows[ir][{j}] = -rows[ir][{j}];\n" for j in neg) + "    }\n")
    finish = ""
    if k.arm_polish is not None:
        finish = ("    /* the DH table's offsets are kilometres: every solution finished on the arm's own kinematics */\n"
                  f"    nr = {P}_g6_arm_finish(T, rows, lab, deg, nr);\n")
    return f"""    {{
    double T06s[16];
{T06_code}
    /* the target of Z1 X1 ... Z6, lengths in units of the arm's scale */
{w.text()}
    nr = g6r_solve(&{P}_g6_arm, T06s, rows, lab, deg, ws->d);
    }}
{flips}{finish}"""


def arm_polish_code(k: IKConstants, P: str, tol: Any) -> str:
    """C of ``NAME_g6_arm_finish``: :meth:`robokit.ik.general_6r.ArmPolish.finish` written out, for a
    general 6R arm whose DH table's offsets are kilometres (``k.arm_polish`` set; empty otherwise).

    Each solution is polished by ``NAME_cal_polish`` (:func:`robokit.codegen.ik_calibrated.polish_code`,
    the C of :func:`robokit.kernels.calibrated_ik.polish`) on the arm's product of exponentials, rows
    whose polish does not reach the acceptance are dropped, rows that reach one root (every joint
    within ``same``, revolute angles modulo 2π) are merged (the first kept, flagged degenerate when a
    merged one was) and the labels renumbered ``"solution k of m"`` (", singular" kept).

    Parameters
    ----------
    k : IKConstants
        The general 6R arm's constants, ``k.arm_polish`` the polish's numbers
        (:meth:`robokit.ik.general_6r.ArmPolish.export_constants`).
    P : str
        The C prefix NAME.
    tol : callable
        Tolerance literals (:mod:`robokit.codegen.ik`).

    Returns
    -------
    str
        C function definitions (none when the arm has no such polish).
    """
    c = k.arm_polish
    if c is None:
        return ""
    t = tol
    rev = [bool(r) for r in c["revolute"]]
    same = []
    for j in range(6):
        d = f"rows[kk][{j}] - qq[{j}]"
        d = f"remainder({d}, {lit(2 * math.pi)})" if rev[j] else d
        same.append(f"fabs({d}) < {t(c['same'])}")
    same_c = "\n                && ".join(same)
    return f"""/* not inlined (gcc, clang): the polish's frame is not added to {P}_ik_ws's */
#if defined(__GNUC__)
#define {P}_CAL_NOINLINE __attribute__((noinline))
#else
#define {P}_CAL_NOINLINE
#endif
{polish_code(P, c, tol)}/* robokit.ik.general_6r.ArmPolish.finish: the general 6R method's n solutions (rows, labels lab,
   singular flags deg) each polished on the arm's own kinematics ({P}_cal_polish, at most {int(c["max_steps"])} steps), a row
   whose errors do not reach {c["tol_accept"]:g} dropped, rows within {c["same"]:g} of a kept one (modulo 2 pi) merged into it
   (flagged degenerate when a merged one was), the labels renumbered "solution k of m" (", singular" kept).
   The new number of solutions. In a frame of its own. */
static {P}_CAL_NOINLINE int {P}_g6_arm_finish(const double T[16], double rows[][6], int lab[], int deg[], int n)
{{
    double qq[6], rot, pos;
    int r, kk, j, m = 0;
    for (r = 0; r < n; ++r) {{
        for (j = 0; j < 6; ++j) {{
            qq[j] = rows[r][j];
        }}
        {P}_cal_polish(T, qq, {int(c["max_steps"])}, &rot, &pos);
        if (!(rot < {t(c["tol_accept"])} && pos < {t(c["tol_accept"])})) {{
            continue;  /* no root of the arm here: a near miss of the DH table's chain */
        }}
        for (kk = 0; kk < m; ++kk) {{
            if ({same_c}) {{
                break;
            }}
        }}
        if (kk < m) {{
            deg[kk] = deg[kk] || deg[r];
            continue;
        }}
        for (j = 0; j < 6; ++j) {{  /* (row m <= r: row r is read already) */
            rows[m][j] = qq[j];
        }}
        lab[m] = lab[r];
        deg[m] = deg[r];
        ++m;
    }}
    for (kk = 0; kk < m; ++kk) {{  /* "solution kk+1 of m", its ", singular" kept (general_6r_labels) */
        lab[kk] = ((m - 1) * m / 2 + kk) * 2 + (lab[kk] & 1);
    }}
    return m;
}}

"""


def declare(P: str) -> list[str]:
    """The header lines of the general 6R ``NAME_ik``."""
    return [
        f"/* Closed-form inverse kinematics (general 6R: Raghavan-Roth elimination, Manocha-Canny eigenproblem):",
        f"   every solution for the tool pose T (up to {MAX_SOLUTIONS_6R}), one row of {P}_N values each, {P}_ik",
        "   returning how many (0: out of reach). The same solutions, in the same order (by q3, then q1, q2,",
        "   q4, q5, q6), with the same labels as robokit's ik_analytic. Revolute angles in (-pi, pi] (or",
        "   shifted by 2 pi into wider limits). Cost: tens of microseconds (a 24 x 24 eigenproblem). */",
        f"int {P}_ik(const double T[16], double q[{P}_MAX_SOLUTIONS * {P}_N]);",
        "",
        f"/* The same with, per solution k, info[4k..4k+3] = (label index into {P}_ik_label_names, repeat",
        "   number (always 1 here), within joint limits (0/1), singular Jacobian at a near-singular pose",
        "   (0/1)); info may be a null pointer. wrist_ref is unused (no free joint in the general case). */",
        f"int {P}_ik_ex(const double T[16], double wrist_ref, double q[{P}_MAX_SOLUTIONS * {P}_N], "
        f"int info[4 * {P}_MAX_SOLUTIONS]);",
        "",
        f"/* The scratch memory of {P}_ik_ws: every matrix of the elimination and the eigenproblem,",
        f"   {P}_IK_WORKSPACE_SIZE bytes. {P}_ik and {P}_ik_ex keep one on their stack (about 10 KB of stack in",
        f"   all); {P}_ik_ws takes one the caller owns (the functions keep no state in it between calls, so",
        "   any workspace not in use by another call at the same time will do). */",
        f"typedef struct {{\n    double d[{workspace_doubles()}];\n}} {P}_ik_workspace;",
        f"#define {P}_IK_WORKSPACE_SIZE (sizeof({P}_ik_workspace))",
        "",
        f"/* {P}_ik_ex with the caller's workspace: the same results; about 1 KB of stack (see the docs). */",
        f"int {P}_ik_ws(const double T[16], double wrist_ref, double q[{P}_MAX_SOLUTIONS * {P}_N], "
        f"int info[4 * {P}_MAX_SOLUTIONS], {P}_ik_workspace *ws);",
        "",
        f"#define {P}_IK_LABEL_COUNT {len(general_6r_labels())}",
        f"extern const char *const {P}_ik_label_names[{P}_IK_LABEL_COUNT];",
        f"extern const int {P}_ik_label_count;",
        f"extern const int {P}_ik_max_solutions;",
        "",
    ]


def note(k: IKConstants) -> str:
    """The ``NAME_HAS_IK`` comment."""
    return "closed form: " + safe_comment(k.reason) + " (C: Raghavan-Roth / Manocha-Canny, up to 16 solutions)"
