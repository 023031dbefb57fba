r"""C for the closed-form IK of a planar arm of 1–3 joints (:mod:`robokit.ik.planar_solver` written out).

``NAME_ik_ex`` takes the target to the canonical chain's frame {0′} (``T₀₆ = base′⁻¹ T tool′⁻¹``,
as every generated IK), checks that the tool turns about the axes only and sits at the arm's
height, reads the tool's angle φ, and places the joints in the plane exactly as the Python solver
does — the same constants, the same operations in the same order, so the same solutions in the
same order with the same labels (to the last bits of ``atan2``/``hypot`` of the C library);
then wrapping, limits and de-duplication as every generated IK (``NAME_finish``). At most two
solutions (three joints: elbow down and up), one for one or two joints.
"""
from __future__ import annotations

import math
import re
from typing import Any

from robokit.codegen._c import CWriter, Val, atom, dot, lit, safe_comment
from robokit.ik.planar_solver import ANGLE_TOL, PLANAR_LABELS

__all__ = ["planar_code", "planar_max_solutions"]


def planar_max_solutions(n: int) -> int:
    """Most solutions of a planar arm of n joints: 2 for three joints (elbow down and up), else 1.

    Parameters
    ----------
    n : int
        Joints (1–3).

    Returns
    -------
    int
        ``NAME_MAX_SOLUTIONS``.
    """
    return 2 if n == 3 else 1


def planar_code(k: Any, prefix: str, tol: Any, emitter: Any, ikcode: Any) -> Any:
    """The IK part of the generated files for a planar arm.

    Parameters
    ----------
    k : IKConstants
        The arm's closed-form constants (``k.planar`` the planar method's).
    prefix : str
        The C prefix NAME.
    tol : callable
        Tolerance literals (robokit's in double, their square roots in float).
    emitter : type
        The closed-form emitter class of :mod:`robokit.codegen.ik` (its target, label tables,
        declarations and ``NAME_finish``).
    ikcode : type
        The :class:`robokit.codegen.ik.IKCode` class.

    Returns
    -------
    IKCode
        The declarations, the source and the labels.
    """
    c = k.planar
    assert c is not None and not k.reversed  # a planar arm's constants; never read backwards
    P, n = prefix, c.n
    em = emitter(k, P, tol)
    em.labels = list(PLANAR_LABELS)
    m_max = planar_max_solutions(n)
    w = CWriter()
    T = em.target(w)
    w.comment("the tool's turn relative to q = 0, Rn = R R0^T: about z only (its third column e3), by phi")
    R0 = c.R0

    def rn(i: int, j: int) -> Val:
        return w.let(f"rn{i}{j}", dot(T.R[i], [R0[j][0], R0[j][1], R0[j][2]]))

    r00, r10, r02, r12, r22 = rn(0, 0), rn(1, 0), rn(0, 2), rn(1, 2), rn(2, 2)
    px, py, pz = (w.let(f"p{a}", T.p[i]) for i, a in enumerate("xyz"))
    ang = tol(ANGLE_TOL)
    lt = tol(c.tol_len)
    w.line(f"const double tilt = sqrt({_c(r02)} * {_c(r02)} + {_c(r12)} * {_c(r12)} + ({_c(r22)} - 1.0) * "
           f"({_c(r22)} - 1.0));")
    w.line(f"const double phi = atan2({_c(r10)}, {_c(r00)});")
    body: list[str] = []
    flip = k.flip or [False] * n

    def sg(i: int, expr: str) -> str:  # ±expr: sᵢ, and − for a flipped joint (solved as q′ = −q); exact
        plus = (c.signs[i] > 0) != bool(flip[i])
        return expr if plus else f"-{expr}" if _NAME.fullmatch(expr) else f"-({expr})"

    r1x, r1y = c.r1
    dx, dy = c.d[-1]
    if dx == 0.0 and dy == 0.0:
        w_of = "const double wx = x, wy = y;  /* the last link ends on its axis */"
    else:
        rx, ry = _combine(_term("c", dx), "-", _term("s", dy)), _combine(_term("s", dx), "+", _term("c", dy))
        w_of = ("const double c = cos(phi), s = sin(phi);\n        "
                f"const double wx = x - ({rx}), wy = y - ({ry});  /* p - r1 - Rot(phi) d_n */")
    if c.prismatic:
        body.append(f"""    (void)wrist_ref;
    if (!(tilt <= {ang}) || fabs(phi) > {ang}
        || hypot({_minus(_minus(_c(px), r1x), dx)}, {_minus(_minus(_c(py), r1y), dy)}) > {lt}) {{
        return 0;  /* not the orientation of q = 0, or off the joint's line */
    }}
    rows[0][0] = {sg(0, _minus(_c(pz), c.h))};
    lab[0] = 2;
    deg[0] = 0;
    nr = 1;""")
    else:
        body.append(f"""    if (!(tilt <= {ang}) || !(fabs({_minus(_c(pz), c.h)}) <= {lt})) {{
        return 0;  /* the tool tilted off the axes, or off the arm's plane */
    }}
    {{
        const double x = {_minus(_c(px), r1x)}, y = {_minus(_c(py), r1y)};
        {w_of}""")
        if n == 1:
            body.append(f"""        (void)wrist_ref;
        if (hypot(wx, wy) > {lt}) {{
            return 0;
        }}
        rows[0][0] = {sg(0, "phi")};
        lab[0] = 2;
        deg[0] = 0;
        nr = 1;
    }}""")
        elif n == 2:
            l1, b1, b2 = lit(c.lengths[0]), c.angles[0], c.angles[1]
            body.append(f"""        double psi1, psi2;
        (void)wrist_ref;
        if (fabs(hypot(wx, wy) - {l1}) > {lt}) {{
            return 0;  /* the second axis cannot be placed */
        }}
        psi1 = {_minus("atan2(wy, wx)", b1)};
        psi2 = phi - psi1;
        rows[0][0] = {sg(0, "psi1")};
        rows[0][1] = {sg(1, "psi2")};
        lab[0] = sin({_minus(_minus("psi2", -b2), b1)}) >= 0.0 ? 0 : 1;  /* the side the second link bends to */
        deg[0] = 0;
        nr = 1;
    }}""")
        else:
            l1, l2 = c.lengths[0], c.lengths[1]
            b1, b2 = c.angles[0], c.angles[1]
            tl = c.tol_len
            body.append(f"""        const double rw = hypot(wx, wy);
        if (rw > {lit(l1 + l2 + tl)} || rw < {lit(abs(l1 - l2) - tl)}) {{
            return 0;  /* the wrist point is out of the two links' reach */
        }}
        if (rw <= {lt}) {{  /* folded onto axis 1 (l1 = l2): joint 1 is free and takes wrist_ref */
            const double psi1 = {sg(0, "wrist_ref")}, psi2 = {lit(math.pi + b1 - b2)};
            rows[0][0] = wrist_ref;
            rows[0][1] = {sg(1, "psi2")};
            rows[0][2] = {sg(2, "phi - psi1 - psi2")};
            lab[0] = 0;
            deg[0] = 1;
            nr = 1;
        }} else {{
            const double cd = (wx * wx + wy * wy - {lit(l1 * l1)} - {lit(l2 * l2)}) / {lit(2.0 * l1 * l2)};
            const int merged = cd >= 1.0 || cd <= -1.0;  /* stretched or folded: one solution */
            const double delta = acos(cd > 1.0 ? 1.0 : (cd < -1.0 ? -1.0 : cd));
            const double aw = atan2(wy, wx);
            int kk;
            for (kk = 0; kk < (merged ? 1 : 2); ++kk) {{
                const double dl = kk == 0 ? delta : -delta;
                const double psi1 = {_minus(f"aw - atan2({lit(l2)} * sin(dl), {lit(l1)} + {lit(l2)} * cos(dl))", b1)};
                const double psi2 = {_minus(_minus("dl", -b1), b2)};
                const double psi3 = phi - psi1 - psi2;
                rows[kk][0] = {sg(0, "psi1")};
                rows[kk][1] = {sg(1, "psi2")};
                rows[kk][2] = {sg(2, "psi3")};
                lab[kk] = kk;  /* elbow down, elbow up */
                deg[kk] = 0;
            }}
            nr = kk;
        }}
    }}""")
    w.lines += "\n".join(body).split("\n")
    w.prune()  # the target's entries the planar method does not read
    code = w.text()
    src = [em.tables(), em.finish(m_max, repeats=False), f"""
/* every closed-form solution of the planar arm (Lecture 5), see {P}.h */
int {P}_ik_ex(const double T[16], double wrist_ref, double q[{P}_MAX_SOLUTIONS * {P}_N], int info[4 * {P}_MAX_SOLUTIONS])
{{
    double (*rows)[{n}] = (double (*)[{n}])q;  /* in place: {P}_finish reads row r before it writes row <= r */
    int lab[{m_max}], deg[{m_max}];
    int nr = 0;
{code}
    return {P}_finish((const double (*)[{n}])rows, lab, deg, nr, q, info);
}}

int {P}_ik(const double T[16], double q[{P}_MAX_SOLUTIONS * {P}_N])
{{
    return {P}_ik_ex(T, 0.0, q, 0);
}}
"""]
    return ikcode(True, f"closed form: {safe_comment(k.reason)}", m_max, em.declare(), "\n".join(src), em.labels)


def _c(v: Val) -> str:
    """A folded value as a C operand."""
    return lit(v) if isinstance(v, float) else v


_NAME = re.compile(r"[A-Za-z_][A-Za-z_0-9]*")


def _minus(expr: str, k: float) -> str:
    """C of ``expr − k`` (k a constant): expr itself for k = 0 (x − 0 = x), ``expr + |k|`` for k < 0
    (x − k and x + (−k) are the same IEEE operation)."""
    if k == 0.0:
        return expr
    return f"{expr} - {lit(k)}" if k > 0.0 else f"{expr} + {lit(-k)}"


def _combine(a: str, op: str, b: str) -> str:
    """C of ``a op b`` (op ``+`` or ``-``) with a zero term (``"0.0"``) dropped: ``a ± 0 = a``, ``0 − b = −b``."""
    if b == "0.0":
        return a
    if a == "0.0":
        return b if op == "+" else f"-{b}"
    return f"{a} {op} {b}"


def _term(name: str, k: float) -> str:
    """C of ``name · k`` (0.0 for k = 0, the product being ±0 there)."""
    return "0.0" if k == 0.0 else f"{name} * {atom(k)}"
