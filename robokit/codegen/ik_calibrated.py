r"""C for the exact IK of a calibrated or nearly special arm (:mod:`robokit.ik.calibrated` written out).

``NAME_ik`` of such an arm is the algorithm of :mod:`robokit.kernels.calibrated_ik`, step for step:

1. ``NAME_nominal_ik_ex``: the closed form of the *projected* arm (the arm with its nominal structure
   restored, built by :mod:`robokit.ik.calibrated`), emitted by :mod:`robokit.codegen.ik` from that
   arm's constants — one start per branch, its label and degenerate flag; when it gives fewer than
   8, also for the pose moved about the shoulder by the kernel's ``RELAX_MOVES`` (starts of the
   branches the projected arm just misses; the Python kernel skips those solves where it can show
   they add no branch, the C always solves them: the same starts either way);
2. each start polished by Newton's method with the kernel's second-order correction on the arm's own
   kinematics — the generated ``NAME_fk`` and ``NAME_jacobian`` (the robot's product of
   exponentials) — with the spatial pose error (the error transform's logarithm to second order
   near the target), the Jacobian factored by 3 × 3 blocks or else with pivoting,
   Levenberg–Marquardt steps where a step fails, steps no longer than ``MAX_STEP``;
3. a start that reaches a solution found already, or none, tried again from the mirrored start;
   merged branches flag their solution degenerate;
4. the near-singular search from the same points as the kernel's (solutions the polish moved far,
   vanished branches, singular choices; every branch's solution where the pose is near singular):
   the roots along the near-singular direction (inverse iteration on ``J̃ᵀJ̃``) from the kernel's
   ``EXPLORE_STEPS``, then along the curve of near-solutions (``NAME_cal_trace_step``: predictor
   along that direction, Gauss–Newton across it; its point, directions and last error norms in
   ``TRACE_ROWS`` free rows of ``q``). In float32 neither the curve nor the branches' solutions are
   searched (the error along that curve is below float's tolerance: its points would pass for roots),
   so near singular poses float32 can return fewer solutions than double;
5. an odd number of solutions of an arm of revolute joints: the closest two within the kernel's
   ``DOUBLE`` are one double root, the later dropped (``NAME_cal_double``; where none are, Python adds
   the general 6R method's missing roots, which the C does not have);
6. wrapping, limits, de-duplication and label repeats as every generated IK (``NAME_finish``).

For a small stack (an RTOS task's 2 KB on a Cortex-M4) the starts, the search points and the
solutions all live in the caller's ``q`` (16 rows): each row holds in turn a start and what it gave;
in the rare case where every row holds a solution or a search point still to come, the search stops
where Python's would go on.

Same solutions, in the same order, as :func:`robokit.ik_analytic` (to the polish's tolerance); the
label of a merged solution is its first branch's (Python adds " (merged with …)"). In float32 the
tolerances are the square roots of the double ones (the polish stops near float's precision).
"""
from __future__ import annotations

import math
from typing import Any

from robokit.codegen._c import lit, safe_comment

__all__ = ["calibrated_code", "polish_code"]


def calibrated_code(k: Any, prefix: str, tol: Any, emitter: Any, ikcode: Any) -> Any:
    """The IK part of the generated files for a calibrated arm.

    Parameters
    ----------
    k : IKConstants
        Constants of the projected arm's closed form, ``k.calibrated`` the polish's numbers.
    prefix : str
        The C prefix NAME.
    tol : callable
        Tolerance literals (robokit's in double, their square roots in float).
    emitter : type
        The closed-form emitter class of :mod:`robokit.codegen.ik`.
    ikcode : type
        :class:`robokit.codegen.ik.IKCode`.

    Returns
    -------
    IKCode
    """
    c = k.calibrated
    P = prefix
    nom = emitter(k, f"{P}_nominal", tol)
    nom.fold = True  # its fold starts too (NAME_nominal_ik_starts)
    nom_code = nom.code()
    first_call = (f"{P}_nominal_ik_starts(T, wrist_ref, q, ninfo, 1)" if nom.fold
                  else f"{P}_nominal_ik_ex(T, wrist_ref, q, ninfo)")
    fin = emitter(k, P, tol)
    labels = nom.labels
    max_rows = int(c["max_rows"])
    sh = c["shoulder"]
    relax = ", ".join(f"{{{lit(float(fr))}, {lit(float(fl))}}}" for fr, fl in c["relax"])
    axis1 = [lit(float(v)) for v in c["axis1"]]
    steps = ", ".join(lit(float(f)) for f in c["explore_steps"])
    t = tol
    # an arm of revolute joints: an odd number of solutions holds a double root twice (NAME_cal_double)
    parity = (f"if (ns & 1) {{  /* an odd number: a double root reached twice? */\n        ns = {P}_cal_double(rows, lab, "
              f"deg, ns);\n    }}\n    ") if c["parity"] else ""
    double_fn = f"""/* an odd number n of solutions (rows 0 .. n - 1, labels lab, degenerate flags deg) of an arm of revolute
   joints, which off its nominal structure has an even number (the real roots of a polynomial of degree 16):
   the closest two, when within {c["double"]:g} in every joint (modulo 2 pi), are one double root reached
   twice; the later is dropped, the earlier flagged degenerate (robokit.kernels.calibrated_ik.DOUBLE). The
   new number of solutions. In a frame of its own. */
static {P}_CAL_NOINLINE int {P}_cal_double(double rows[][6], int lab[], int deg[], int n)
{{
    double best = {t(c["double"])};
    int a, b, j, keep = 0, drop = 0;
    for (b = 1; b < n; ++b) {{
        for (a = 0; a < b; ++a) {{
            double d = 0.0;
            for (j = 0; j < 6; ++j) {{
                const double e = fabs(remainder(rows[a][j] - rows[b][j], {lit(2 * math.pi)}));
                d = e > d ? e : d;
            }}
            if (d < best) {{
                best = d;
                keep = a;
                drop = b;
            }}
        }}
    }}
    if (drop == 0) {{
        return n;
    }}
    deg[keep] = 1;
    for (a = drop; a < n - 1; ++a) {{
        for (j = 0; j < 6; ++j) {{
            rows[a][j] = rows[a + 1][j];
        }}
        lab[a] = lab[a + 1];
        deg[a] = deg[a + 1];
    }}
    return n - 1;
}}

""" if c["parity"] else ""
    header = [f"#define {P}_nominal_N {P}_N  /* the projected arm's closed form: the starts of {P}_ik */",
              f"#define {P}_nominal_MAX_SOLUTIONS 8", ""] + nom_code.header_lines + [
        f"/* Inverse kinematics of this calibrated arm ({safe_comment(c['method'])}): every solution for the",
        f"   tool pose T, one row of {P}_N values each, {P}_ik returning how many (0: out of reach). The",
        f"   closed form of the nominal structure ({P}_nominal_ik) gives one start per branch; Newton's",
        f"   method on {P}_fk / {P}_jacobian finishes each. The same solutions, in the same order, as",
        "   robokit's ik_analytic. Revolute angles in (-pi, pi] (or shifted by 2 pi into wider limits). */",
        *([f"/* An arm of revolute joints off its nominal structure has an even number of solutions (the real roots",
           f"   of a polynomial of degree 16): an odd number from {P}_ik means one was not found (near a singular",
           "   configuration; ik_analytic then adds the general 6R method's). */"] if c["parity"] else []),
        f"int {P}_ik(const double T[16], double q[{P}_MAX_SOLUTIONS * {P}_N]);",
        "",
        f"/* The same with, per solution k, info[4k..4k+3] = (label index into {P}_ik_label_names (the",
        "   branch of the nominal structure), repeat number (2 or more: the label ends in \" #repeat\"),",
        "   within joint limits (0/1), degenerate: near a singularity — branches merged, or a root found",
        "   by the search there (0/1)); info may be a null pointer. wrist_ref: the free joint's value at",
        "   a singularity of the nominal structure (ik_analytic's wrist_ref). */",
        f"int {P}_ik_ex(const double T[16], double wrist_ref, double q[{P}_MAX_SOLUTIONS * {P}_N], "
        f"int info[4 * {P}_MAX_SOLUTIONS]);",
        "",
        f"#define {P}_IK_LABEL_COUNT {len(labels)}",
        f"extern const char *const {P}_ik_label_names[{P}_IK_LABEL_COUNT];",
        f"extern const int {P}_ik_label_count;",
        f"extern const int {P}_ik_max_solutions;",
        "",
    ]
    R = lit(float(c["reach"]))
    # the curve of near-solutions is followed, and the branches' solutions are search points, in double
    # only: in float the pose error along that curve is below float's tolerance, so its points would
    # pass for roots (float's condition asks for more free rows than there are; its search points are
    # those of the starts)
    trace_free = max_rows if tol.float32 else int(c["trace_rows"])
    # which solutions' singular values are checked: the first one's stands for the pose's, or (an arm farther
    # from its structure: robokit.ik.calibrated.search_constants) each one's until one is near singular
    sigma = lit(float(c["sigma_explore"]))
    if c.get("every"):
        first_gate = ""
        solution_gate = f"""            if (gate != 3 && {P}_cal_sigma_bound(s0) > {sigma}) {{
                continue;  /* this solution surely is not near a singular configuration */
            }}
"""
    else:
        first_gate = """            if (gate == 1) {
                break;  /* the pose is not near a singular configuration */
            }
"""
        solution_gate = f"""            if (gate == 0) {{
                gate = 1;
                if ({P}_cal_sigma_bound(s0) > {sigma}) {{
                    break;  /* surely not near a singular configuration */
                }}
            }}
"""
    solutions_searched = "0 * nsol" if tol.float32 else f"({P}_IK_FULL_SEARCH ? nsol : 0)"
    # the 3 x 3 block factorization, emitted twice: for the polish and for the bound at the first solution
    # (each copy is inlined into its one caller, so the polish's frame does not grow by a call)
    block_factor2 = _block_factor_code(P, c, "2", "/* the same for {P}_cal_sigma_bound */\n".replace("{P}", P))
    polish = polish_code(P, c, t, block_factor2)
    src = [nom_code.source, fin.tables(), fin.finish(max_rows), f"""
/* the near-singular search starts from the branches' solutions too where the pose is near singular, and
   follows the curve of near-solutions (as robokit's ik_analytic): a pose near a singular configuration can
   then take 5-100x a common pose's time. Compile with -D{P}_IK_FULL_SEARCH=0 for a shorter worst case:
   the search then starts only from the points the polish of the starts gives, along straight lines (the
   solutions only the full search finds are missing; the others are unchanged) */
#ifndef {P}_IK_FULL_SEARCH
#define {P}_IK_FULL_SEARCH 1
#endif
/* not inlined (gcc, clang): the frames of the search's helpers do not add up along {P}_ik_ex's call path */
#if defined(__GNUC__)
#define {P}_CAL_NOINLINE __attribute__((noinline))
#define {P}_CAL_INLINE __attribute__((always_inline)) inline
#else
#define {P}_CAL_NOINLINE
#define {P}_CAL_INLINE
#endif
{polish}/* H = J^T J + 1e-12 I (J 6 x 6) */
static void {P}_cal_gram(const double J[36], double H[36])
{{
    int i, j, r;
    for (i = 0; i < 6; ++i) {{
        for (j = i; j < 6; ++j) {{
            double acc = 0.0;
            for (r = 0; r < 6; ++r) {{
                acc += J[6 * r + i] * J[6 * r + j];
            }}
            H[6 * i + j] = acc;
            H[6 * j + i] = acc;
        }}
        H[6 * i + i] += 1e-12;
    }}
}}

/* the joint direction along which the Jacobian at q is closest to singular: inverse iteration on
   H = Jt^T Jt + 1e-12 I (Jt the space Jacobian with its velocity rows divided by the reach), 4 steps
   from (1, ..., 1) with H^-1 = L^-T L^-1 from one factorization; returns the estimate of Jt's smallest
   singular value (0 when H is not positive definite) */
static {P}_CAL_NOINLINE double {P}_cal_null_direction(const double q[6], double v[6])
{{
    double J[36], H[36], L[36], x[6], tmp[6];
    double *const T = H, *const sc = H + 16;  /* scratch in H until it is built */
    int i, j, r, it, cc, kk;
    for (i = 0; i < 6; ++i) {{
        sc[i] = sin(q[i]);
        sc[6 + i] = cos(q[i]);
    }}
    {P}_cal_fkj(q, sc, T, J);
    for (r = 18; r < 36; ++r) {{
        J[r] /= {R};
    }}
    {P}_cal_gram(J, H);
    for (i = 0; i < 36; ++i) {{
        L[i] = H[i];
    }}
    for (i = 0; i < 6; ++i) {{
        v[i] = 1.0;
    }}
    if (!{P}_cal_chol_factor(L)) {{
        return 0.0;
    }}
    for (cc = 0; cc < 5; ++cc) {{  /* L^-1 over L, column by column */
        for (i = cc + 1; i < 6; ++i) {{
            double acc = 0.0;
            for (kk = cc; kk < i; ++kk) {{
                acc += L[6 * i + kk] * (kk > cc ? tmp[kk] : L[6 * cc + cc]);
            }}
            tmp[i] = -acc * L[6 * i + i];
        }}
        for (i = cc + 1; i < 6; ++i) {{
            L[6 * i + cc] = tmp[i];
        }}
    }}
    for (it = 0; it < 4; ++it) {{
        double norm = 0.0;
        for (i = 0; i < 6; ++i) {{
            double acc = 0.0;
            for (kk = 0; kk <= i; ++kk) {{
                acc += L[6 * i + kk] * v[kk];
            }}
            tmp[i] = acc;
        }}
        for (i = 0; i < 6; ++i) {{
            double acc = 0.0;
            for (kk = i; kk < 6; ++kk) {{
                acc += L[6 * kk + i] * tmp[kk];
            }}
            x[i] = acc;
            norm += acc * acc;
        }}
        norm = 1.0 / sqrt(norm);
        for (i = 0; i < 6; ++i) {{
            v[i] = x[i] * norm;
        }}
    }}
    {{
        double rq = 0.0;
        for (i = 0; i < 6; ++i) {{
            for (j = 0; j < 6; ++j) {{
                rq += v[i] * H[6 * i + j] * v[j];
            }}
        }}
        return sqrt(rq > 0.0 ? rq : 0.0);
    }}
}}

/* a lower bound of the smallest singular value of Jt at q (robokit.kernels.calibrated_ik._sigma_bound):
   1 / |Jt^-1|_F, Jt^-1 written out from the block factors, J^-1 = [[D^-1 + K M, -K S^-1], [-M, S^-1]]
   with M = S^-1 J_v,p D^-1 (its velocity columns times the reach); 0 where J does not factor by blocks */
static {P}_CAL_NOINLINE double {P}_cal_sigma_bound(const double q[6])
{{
    double J[36], B[36], G[18], sc[12];
    double *const T = G;  /* (16 of G's 18, until J is factored) */
    double omega = 0.0, vel = 0.0;
    int i, p, r, cc;
    for (i = 0; i < 6; ++i) {{
        sc[i] = sin(q[i]);
        sc[6 + i] = cos(q[i]);
    }}
    {P}_cal_fkj(q, sc, T, J);
    if (!{P}_cal_block_factor2(J, B, &p)) {{
        return 0.0;
    }}
    for (r = 0; r < 3; ++r) {{
        for (cc = 0; cc < 3; ++cc) {{
            G[3 * r + cc] = J[6 * (3 + r) + p] * B[cc] + J[6 * (3 + r) + p + 1] * B[6 + cc]
                + J[6 * (3 + r) + p + 2] * B[12 + cc];
        }}
    }}
    for (r = 0; r < 3; ++r) {{
        for (cc = 0; cc < 3; ++cc) {{
            G[9 + 3 * r + cc] = B[6 * (3 + r)] * G[cc] + B[6 * (3 + r) + 1] * G[3 + cc] + B[6 * (3 + r) + 2] * G[6 + cc];
        }}
    }}
    for (r = 0; r < 3; ++r) {{
        for (cc = 0; cc < 3; ++cc) {{
            const double a = B[6 * r + cc] + B[6 * r + 3] * G[9 + cc] + B[6 * r + 4] * G[12 + cc] + B[6 * r + 5] * G[15 + cc];
            const double b = B[6 * r + 3] * B[18 + cc] + B[6 * r + 4] * B[24 + cc] + B[6 * r + 5] * B[30 + cc];
            omega += a * a + G[9 + 3 * r + cc] * G[9 + 3 * r + cc];
            vel += b * b + B[6 * (3 + r) + cc] * B[6 * (3 + r) + cc];
        }}
    }}
    return 1.0 / sqrt(omega + vel * {R} * {R});
}}

/* one step along the curve of near-solutions (robokit.kernels.calibrated_ik._trace): qp = q, vp = v,
   q += TRACE_STEP v, then TRACE_PULL Gauss-Newton corrections across v (v updated before the last one
   to the near-null direction of its Jacobian: two steps of inverse iteration from v, its sign kept);
   *r = the scaled pose error's norm before the last correction; 0 when a factorization fails */
static {P}_CAL_NOINLINE int {P}_cal_trace_step(const double Td[16], double q[6], double qp[6], double v[6],
                                               double vp[6], double *r)
{{
    double J[36], H[36], F[6], g[6], y[6], sc[12], rot, pos;
    double *const T = H;  /* (until H is built) */
    int i, j, it, k2;
    for (j = 0; j < 6; ++j) {{
        qp[j] = q[j];
        q[j] += {lit(float(c["trace_step"]))} * v[j];
        vp[j] = v[j];
    }}
    for (it = 0; it < {int(c["trace_pull"])}; ++it) {{
        double acc;
        for (i = 0; i < 6; ++i) {{
            sc[i] = sin(q[i]);
            sc[6 + i] = cos(q[i]);
        }}
        {P}_cal_fkj(q, sc, T, J);
        (void){P}_cal_error(T, Td, F, &rot, &pos);
        for (i = 3; i < 6; ++i) {{
            F[i] /= {R};
            for (j = 0; j < 6; ++j) {{
                J[6 * i + j] /= {R};
            }}
        }}
        if (it == {int(c["trace_pull"]) - 1}) {{  /* the curve's direction here */
            {P}_cal_gram(J, H);
            if (!{P}_cal_chol_factor(H)) {{
                return 0;
            }}
            for (k2 = 0; k2 < 2; ++k2) {{
                double norm = 0.0;
                {P}_cal_chol_solve(H, v, y);
                for (i = 0; i < 6; ++i) {{
                    norm += y[i] * y[i];
                }}
                norm = 1.0 / sqrt(norm);
                for (i = 0; i < 6; ++i) {{
                    v[i] = y[i] * norm;
                }}
            }}
            acc = 0.0;
            for (j = 0; j < 6; ++j) {{
                acc += v[j] * vp[j];
            }}
            if (acc < 0.0) {{
                for (j = 0; j < 6; ++j) {{
                    v[j] = -v[j];
                }}
            }}
        }}
        for (i = 0; i < 6; ++i) {{  /* J P, P = I - v v^T */
            acc = 0.0;
            for (j = 0; j < 6; ++j) {{
                acc += J[6 * i + j] * v[j];
            }}
            for (j = 0; j < 6; ++j) {{
                J[6 * i + j] -= acc * v[j];
            }}
        }}
        {P}_cal_normal(J, F, H, g);  /* H = (J P)^T (J P) + v v^T + 1e-12 I, g = (J P)^T F */
        for (i = 0; i < 6; ++i) {{
            for (j = 0; j < 6; ++j) {{
                H[6 * i + j] += v[i] * v[j];
            }}
            H[6 * i + i] += 1e-12;
        }}
        if (!{P}_cal_chol_factor(H)) {{
            return 0;
        }}
        {P}_cal_chol_solve(H, g, y);
        *r = 0.0;
        for (i = 0; i < 6; ++i) {{
            *r += F[i] * F[i];
            q[i] += y[i];
        }}
    }}
    *r = sqrt(*r);
    return 1;
}}

/* the squared distance of two joint vectors (revolute differences modulo 2 pi) */
static double {P}_cal_dist2(const double a[6], const double b[6])
{{
    double s = 0.0;
    int j;
    for (j = 0; j < 6; ++j) {{
        double d = a[j] - b[j];
        if ({P}_joint_type[j] == 0) {{
            d = remainder(d, {lit(2 * math.pi)});
        }}
        s += d * d;
    }}
    return s;
}}

/* two joint vectors within {c["same"]:g} (rad or m; revolute angles modulo 2 pi): one solution; the
   solutions are the rows rows[sol[0]], ..., rows[sol[n - 1]] */
static int {P}_cal_find(const double q[6], const double rows[][6], const signed char sol[], int n)
{{
    int kk, j;
    for (kk = 0; kk < n; ++kk) {{
        int same = 1;
        for (j = 0; j < 6 && same; ++j) {{
            double d = q[j] - rows[sol[kk]][j];
            if ({P}_joint_type[j] == 0) {{
                d = remainder(d, {lit(2 * math.pi)});
            }}
            same = d < {t(c["same"])} && d > -{t(c["same"])};
        }}
        if (same) {{
            return kk;
        }}
    }}
    return -1;
}}

/* a root the near-singular search found: into the first free row, solution ns, with its search point's
   label (labdeg[ns]), degenerate (labdeg[MAX_ROWS + ns]); inlined (gcc, clang: a call's arguments
   would cost NAME_ik_ex's frame 8 bytes of its 2 KB call path) */
static {P}_CAL_INLINE void {P}_cal_keep(const double qq[6], int code, double rows[][6], signed char state[], signed char sol[],
                         int labdeg[], int ns)
{{
    int j, fr = 0;
    while (state[fr] != 0) {{
        ++fr;
    }}
    for (j = 0; j < 6; ++j) {{
        rows[fr][j] = qq[j];
    }}
    state[fr] = 1;
    sol[ns] = (signed char)fr;
    labdeg[ns] = code;
    labdeg[{max_rows} + ns] = 1;
}}

{double_fn}/* NAME_finish in a frame of its own (not live together with the polish's) */
static {P}_CAL_NOINLINE int {P}_cal_finish(const double rows[][6], const int lab[], const int deg[], int n,
                                          double q[], int info[])
{{
    return {P}_finish(rows, lab, deg, n, q, info);
}}

/* the f-th relaxed pose (robokit.kernels.calibrated_ik.RELAX_MOVES): Tr = T with its position moved by
   reach (f_r u_r + f_l u_l), u_r from the shoulder point to the tool (v, of length dist), u_l its part across
   joint 1's axis a (v - h a, of length rho), written (c_r + c_l) v - c_l h a; 0 where the move has no direction.
   In a frame of its own (not live together with the polish's). */
static {P}_CAL_NOINLINE int {P}_cal_relaxed(const double T[16], int f, double Tr[16])
{{
    static const double relax[][2] = {{{relax}}};  /* (toward the shoulder point, toward axis 1) */
    const double vx = T[3] - {lit(float(sh[0]))}, vy = T[7] - {lit(float(sh[1]))}, vz = T[11] - {lit(float(sh[2]))};
    const double h = vx * {axis1[0]} + vy * {axis1[1]} + vz * {axis1[2]}, dist2 = vx * vx + vy * vy + vz * vz;
    const double cr = relax[f][0] * {R}, cl = relax[f][1] * {R};
    const double dist = sqrt(dist2), rho = sqrt(dist2 - h * h > 0.0 ? dist2 - h * h : 0.0);
    double c1, c2, k, m;
    int j;
    if (((cr < 0.0 || cr > 0.0) && !(dist > 0.0)) || ((cl < 0.0 || cl > 0.0) && !(rho > 0.0))) {{
        return 0;
    }}
    c1 = (cr < 0.0 || cr > 0.0) ? cr / dist : 0.0;
    c2 = (cl < 0.0 || cl > 0.0) ? cl / rho : 0.0;
    k = c1 + c2;
    m = c2 * h;
    for (j = 0; j < 16; ++j) {{
        Tr[j] = T[j];
    }}
    Tr[3] = T[3] + (k * vx - m * {axis1[0]});
    Tr[7] = T[7] + (k * vy - m * {axis1[1]});
    Tr[11] = T[11] + (k * vz - m * {axis1[2]});
    return 1;
}}

/* every solution (see {P}.h). For a small stack (an RTOS task's) everything per row lives in the
   caller's q: the closed form's starts, each row then reused for what its start gave (a solution, a
   point the search starts from, or nothing: free), the search's solutions in free rows; at the end
   the solutions are put in order (sol) and NAME_finish works in place. On the stack: per row its
   label, flags and state, the row numbers of the solutions (sol) and of the search points (seed). */
int {P}_ik_ex(const double T[16], double wrist_ref, double q[{P}_MAX_SOLUTIONS * {P}_N], int info[4 * {P}_MAX_SOLUTIONS])
{{
    static const double steps[] = {{{steps}}};
    double tmp[18];  /* the relaxed pose (16); then a point qq, the mirrored point q2, the start s0 */
    double *const qq = tmp, *const q2 = tmp + 6, *const s0 = tmp + 12;
    double (*rows)[6] = (double (*)[6])q;
    double *const v = q2;  /* the near-singular direction, once q2 is no longer needed */
    int labdeg[2 * {max_rows}];  /* first the closed form's info (4 per row), then lab and deg */
    int *const lab = labdeg, *const deg = labdeg + {max_rows}, *const ninfo = labdeg;
    signed char nlab[{max_rows}], ndeg[{max_rows}];
    /* state bits: 1 a solution, 2 a search point still to come, 4 a trace's scratch, 8 a solution searched
       around already (as a search point); 0 free */
    signed char sol[{max_rows}], seed[{max_rows}], state[{max_rows}];
    signed char *const tr = ndeg;  /* a trace's rows, once the starts' flags are read */
    int m, m0, me, r, j, kk, f, ns = 0, nseed = 0, mb = 0, pass, nsol, gate = 0;  /* gate: 1 checked, 2 near singular */
    double rp[2];  /* a polish's orientation and position errors */
    m = {first_call};
    for (r = 0; r < m; ++r) {{
        nlab[r] = (signed char)ninfo[4 * r];
        ndeg[r] = (signed char)ninfo[4 * r + 3];  /* 3: a fold start */
        mb += ndeg[r] != 3;
    }}
    if (mb < {int(c["generic_rows"])}) {{  /* a branch missing: the pose moved about the shoulder gives its start */
        for (f = 0; f < {len(c["relax"])}; ++f) {{
            double *const Tr = tmp;
            int start = 0;
            for (r = 0; r < m && f >= {len(c["radial"])}; ++r) {{
                start = start || ndeg[r] != 3;  /* (a fold start is not one) */
            }}
            if (start || !{P}_cal_relaxed(T, f, Tr)) {{
                continue;  /* the sideways and corner moves only for a pose without a start; or no direction */
            }}
            /* the (at most 8) rows written from row m0 on fit in q; the new branches move up to row m */
            m0 = m;
            if (m0 > {max_rows} - 8) {{
                break;
            }}
            me = {P}_nominal_ik_ex(Tr, wrist_ref, &q[6 * m0], ninfo);
            for (kk = 0; kk < me; ++kk) {{
                int have = 0;
                for (r = 0; r < m; ++r) {{
                    have = have || (nlab[r] == ninfo[4 * kk] && ndeg[r] != 3);  /* (not a fold start's) */
                }}
                if (!have && m < {max_rows}) {{
                    for (j = 0; j < 6; ++j) {{
                        q[6 * m + j] = q[6 * (m0 + kk) + j];
                    }}
                    nlab[m] = (signed char)ninfo[4 * kk];
                    ndeg[m] = 2;  /* a start from a relaxed pose */
                    ++m;
                }}
            }}
        }}
    }}
    for (r = 0; r < {max_rows}; ++r) {{
        state[r] = 0;
    }}
    for (pass = 0; pass < 2; ++pass)  /* the fold starts last */
    for (r = 0; r < m; ++r) {{
        double moved = 0.0;
        int ok, hit = -1, dg = ndeg[r] != 0, point, stalled = 0, at = r;
        const int relaxed = ndeg[r] >= 2, fold = ndeg[r] == 3;
        if (fold != pass) {{
            continue;
        }}
        for (j = 0; j < 6; ++j) {{
            s0[j] = rows[r][j];
            qq[j] = s0[j];
        }}
        {P}_cal_polish(T, qq, relaxed ? {int(c["explore_max_steps"])} : {int(c["max_steps"])}, &rp[0], &rp[1]);
        for (j = 0; j < 6; ++j) {{
            moved = fabs(qq[j] - s0[j]) > moved ? fabs(qq[j] - s0[j]) : moved;
        }}
        ok = rp[0] < {t(c["tol_accept"])} && rp[1] < {t(c["tol_accept"])};
        if (ok) {{
            hit = {P}_cal_find(qq, (const double (*)[6])rows, sol, ns);
        }}
        if (!ok || hit >= 0) {{  /* a root found already, or none: once more from the mirrored start */
            for (j = 0; j < 6; ++j) {{
                q2[j] = 2.0 * s0[j] - qq[j];
            }}
            {P}_cal_polish(T, q2, relaxed ? {int(c["explore_max_steps"])} : {int(c["max_steps"])}, &rp[0], &rp[1]);
            if (rp[0] < {t(c["tol_accept"])} && rp[1] < {t(c["tol_accept"])}
                && {P}_cal_find(q2, (const double (*)[6])rows, sol, ns) < 0) {{
                /* the first polish failed: where it stalled is the search point, in the first free row past
                   the starts (in this loop only earlier stalled points take those: Python counts them) */
                for (at = m; at < {max_rows} && state[at] != 0; ++at) {{
                }}
                stalled = !ok && at < {max_rows};
                for (j = 0; j < 6; ++j) {{
                    if (stalled) {{
                        rows[at][j] = qq[j];
                    }}
                    qq[j] = q2[j];
                }}
                ok = 1;
                hit = -1;
                dg = 1;
            }} else if (!ok && rp[0] < {t(c["tol_accept"])} && rp[1] < {t(c["tol_accept"])}) {{
                hit = {P}_cal_find(q2, (const double (*)[6])rows, sol, ns);
                ok = 1;
            }}
        }}
        /* a search point: the point reached, in this row (its start is used up) */
        point = moved > {lit(float(c["explore"]))} || hit >= 0 || (dg && !relaxed) || (!ok && !relaxed) || (fold && ok)
            || stalled;
        if (point || (ok && hit < 0)) {{
            for (j = 0; j < 6; ++j) {{
                rows[r][j] = qq[j];
            }}
        }}
        if (point) {{
            at = stalled ? at : r;  /* (here, not above: gcc's frame stays 8 bytes smaller, 2,040 B down the path) */
            nlab[at] = nlab[r];  /* (a stalled point's row: its branch's label) */
            seed[nseed] = (signed char)at;
            ++nseed;
            state[at] = 2;
            if (hit >= 0) {{
                state[sol[hit]] |= 8;  /* that solution is this search point */
            }}
        }}
        if (ok && hit < 0) {{
            sol[ns] = (signed char)r;
            lab[ns] = nlab[r];
            deg[ns] = dg;
            ++ns;
            state[r] = point && !stalled ? 1 | 2 | 8 : 1;
        }} else if (ok && !fold) {{  /* two branches reach one root: they merge here */
            deg[hit] = 1;
        }}
    }}
    /* every root along the near-singular direction and curve there: from the search points, then from
       the branches' solutions where the pose is near singular (the first one not searched already
       checked, the others where it or a search point was) */
    nsol = ns;
    for (kk = 0; kk < nseed + {solutions_searched}; ++kk) {{
        double big = 0.0, sk;
        int st, pending, code;
        if (kk < nseed) {{
            pending = nseed - kk - 1;
            for (j = 0; j < 6; ++j) {{
                s0[j] = rows[seed[kk]][j];
            }}
            code = nlab[seed[kk]];
            if (!(state[seed[kk]] & 1)) {{
                state[seed[kk]] = 0;  /* its row is free now */
            }}
        }} else {{
            const int i = kk - nseed;
            if (state[sol[i]] & 8) {{
                continue;  /* a search point above already */
            }}
{first_gate}            pending = 0;
            for (j = 0; j < 6; ++j) {{
                s0[j] = rows[sol[i]][j];
            }}
{solution_gate}            code = lab[i];
        }}
        sk = {P}_cal_null_direction(s0, v);
        if (sk > {lit(float(c["sigma_explore"]))}) {{
            continue;  /* not near a singular configuration */
        }}
        gate = 3;
        for (j = 0; j < 6; ++j) {{
            big = fabs(v[j]) > big ? fabs(v[j]) : big;
        }}
        for (st = 0; st < (int)(sizeof steps / sizeof steps[0]) && ns < {max_rows}; ++st) {{
            for (j = 0; j < 6; ++j) {{
                qq[j] = s0[j] + steps[st] * ({lit(0.25 * math.pi)} / big) * v[j];
            }}
            {P}_cal_polish(T, qq, {int(c["explore_max_steps"])}, &rp[0], &rp[1]);
            if (rp[0] < {t(c["tol_accept"])} && rp[1] < {t(c["tol_accept"])}
                && {P}_cal_find(qq, (const double (*)[6])rows, sol, ns) < 0) {{
                int fr = 0;
                while (fr < {max_rows} && state[fr] != 0) {{
                    ++fr;
                }}
                if (fr == {max_rows}) {{  /* every row holds a solution or a search point still to come */
                    break;
                }}
                {P}_cal_keep(qq, code, rows, state, sol, labdeg, ns++);
            }}
        }}
        if ({P}_IK_FULL_SEARCH && {max_rows} - ns - pending > {trace_free}) {{  /* the curve, both ways */
            int nt = 0, sgn;
            for (f = 0; f < {max_rows} && nt < {int(c["trace_rows"])}; ++f) {{
                if (state[f] == 0) {{
                    tr[nt++] = (signed char)f;
                    state[f] = 4;
                }}
            }}
            for (sgn = 0; sgn < 2; ++sgn) {{
                /* the curve's point, previous point, direction, previous direction, and (the error's
                   norm at the point, at the previous point, at the one before) in the rows tr[0..4] */
                double *const tq = rows[tr[0]], *const tqp = rows[tr[1]], *const tr3 = rows[tr[4]];
                int closed = 0;
                tr3[1] = HUGE_VAL;
                tr3[2] = HUGE_VAL;
                for (j = 0; j < 6; ++j) {{
                    tq[j] = s0[j];
                    rows[tr[2]][j] = sgn ? -v[j] : v[j];
                }}
                for (st = 0; st < {int(c["trace_steps"])}; ++st) {{
                    if (!{P}_cal_trace_step(T, tq, tqp, rows[tr[2]], rows[tr[3]], &tr3[0])) {{
                        break;
                    }}
                    if (tr3[1] < tr3[2] && tr3[1] <= tr3[0]) {{  /* the error's local minimum along the curve */
                        for (j = 0; j < 6; ++j) {{
                            qq[j] = tqp[j];
                        }}
                        {P}_cal_polish(T, qq, {int(c["explore_max_steps"])}, &rp[0], &rp[1]);
                        if (rp[0] < {t(c["tol_accept"])} && rp[1] < {t(c["tol_accept"])}
                            && ns < {max_rows} - pending - {int(c["trace_rows"])}
                            && {P}_cal_find(qq, (const double (*)[6])rows, sol, ns) < 0) {{
                            {P}_cal_keep(qq, code, rows, state, sol, labdeg, ns++);
                        }}
                    }}
                    tr3[2] = tr3[1];
                    tr3[1] = tr3[0];
                    if (st >= 2 && {P}_cal_dist2(tq, s0) < {lit(float(c["trace_step"]) ** 2)}) {{
                        closed = 1;  /* back at the start: the other way is the same curve */
                        break;
                    }}
                }}
                if (closed) {{
                    break;
                }}
            }}
            for (f = 0; f < nt; ++f) {{
                state[tr[f]] = 0;
            }}
        }}
    }}
    for (kk = 0; kk < ns; ++kk) {{  /* the solutions in order: solution kk into row kk */
        const int from = sol[kk];
        if (from != kk) {{
            for (j = 0; j < 6; ++j) {{
                const double x = rows[kk][j];
                rows[kk][j] = rows[from][j];
                rows[from][j] = x;
            }}
            for (r = kk + 1; r < ns; ++r) {{
                if (sol[r] == kk) {{
                    sol[r] = (signed char)from;
                }}
            }}
        }}
    }}
    {parity}return {P}_cal_finish((const double (*)[6])rows, lab, deg, ns, q, info);
}}

int {P}_ik(const double T[16], double q[{P}_MAX_SOLUTIONS * {P}_N])
{{
    return {P}_ik_ex(T, 0.0, q, 0);
}}
"""]
    note = f"closed form: {safe_comment(c['reason'])}"
    return ikcode(True, note, max_rows, header, "\n".join(src), labels)


def polish_code(P: str, c: Any, tol: Any, block_factor2: str = "") -> str:
    """C of ``NAME_cal_polish`` and its helpers: :func:`robokit.kernels.calibrated_ik.polish` written out
    for one arm (the pose error, ``NAME_cal_fkj`` on the arm's local transforms, the Newton step by 3 × 3
    blocks or LU, Levenberg–Marquardt by Cholesky). Used by the calibrated arm's IK and by the general 6R
    IK of an arm whose DH table's offsets are kilometres (:mod:`robokit.codegen.ik_general`). The caller
    defines ``NAME_CAL_NOINLINE`` before it.

    Parameters
    ----------
    P : str
        The C prefix NAME.
    c : mapping
        The polish's numbers: ``tol_stop``, ``log_near``, ``second_order``, ``block_axes``,
        ``block_schur``, ``max_step``, ``frames``, ``kinds``, ``pitches``
        (``CalibratedArm.export_constants()``, ``ArmPolish.export_constants()``).
    tol : callable
        Tolerance literals (robokit's in double, their square roots in float).
    block_factor2 : str
        C inserted after ``NAME_cal_block_factor`` (the calibrated arm's second copy of it).

    Returns
    -------
    str
        C function definitions, ending with ``NAME_cal_polish``.
    """
    t = tol
    fkj = _fkj_code(P, c["frames"], c["kinds"], c["pitches"])
    block_factor = _block_factor_code(P, c, "", "")
    return f"""/* the spatial twist that moves T to Td (robokit.kernels.calibrated_ik._error): with A = Rd R^T,
   s = vee(A - A^T)/2 = sin(theta) u and dp = pd - p: near Td (|s| < LOG_NEAR, trace(A) > 1) the log of
   X = Td T^-1 to second order, w = (theta/sin theta) s, v = u - w x u/2 + k w x (w x u) with
   u = pd - A p, theta/sin theta = 1 + |s|^2/6 + 3|s|^4/40, k = 1/12 + |w|^2/720; else w = s,
   v = dp - w x p. *rot = |s| (2 - |s| beyond pi/2), *pos = |dp|; returns (rot^2 + pos^2)/2 */
static double {P}_cal_error(const double T[16], const double Td[16], double F[6], double *rot, double *pos)
{{
    const double a00 = Td[0] * T[0] + Td[1] * T[1] + Td[2] * T[2];
    const double a01 = Td[0] * T[4] + Td[1] * T[5] + Td[2] * T[6];
    const double a02 = Td[0] * T[8] + Td[1] * T[9] + Td[2] * T[10];
    const double a10 = Td[4] * T[0] + Td[5] * T[1] + Td[6] * T[2];
    const double a11 = Td[4] * T[4] + Td[5] * T[5] + Td[6] * T[6];
    const double a12 = Td[4] * T[8] + Td[5] * T[9] + Td[6] * T[10];
    const double a20 = Td[8] * T[0] + Td[9] * T[1] + Td[10] * T[2];
    const double a21 = Td[8] * T[4] + Td[9] * T[5] + Td[10] * T[6];
    const double a22 = Td[8] * T[8] + Td[9] * T[9] + Td[10] * T[10];
    const double sx = 0.5 * (a21 - a12), sy = 0.5 * (a02 - a20), sz = 0.5 * (a10 - a01);
    const double px = T[3], py = T[7], pz = T[11];
    const double dx = Td[3] - px, dy = Td[7] - py, dz = Td[11] - pz;
    const double s2 = sx * sx + sy * sy + sz * sz;
    const double tr = a00 + a11 + a22;
    if (s2 < {lit(float(c["log_near"]) ** 2)} && tr > 1.0) {{
        const double f = 1.0 + s2 * ({lit(1.0 / 6.0)} + s2 * 0.075);
        const double wx = f * sx, wy = f * sy, wz = f * sz;
        const double k = {lit(1.0 / 12.0)} + (wx * wx + wy * wy + wz * wz) * {lit(1.0 / 720.0)};
        const double ux = Td[3] - (a00 * px + a01 * py + a02 * pz);
        const double uy = Td[7] - (a10 * px + a11 * py + a12 * pz);
        const double uz = Td[11] - (a20 * px + a21 * py + a22 * pz);
        const double cx = wy * uz - wz * uy, cy = wz * ux - wx * uz, cz = wx * uy - wy * ux;
        F[0] = wx;
        F[1] = wy;
        F[2] = wz;
        F[3] = ux - 0.5 * cx + k * (wy * cz - wz * cy);
        F[4] = uy - 0.5 * cy + k * (wz * cx - wx * cz);
        F[5] = uz - 0.5 * cz + k * (wx * cy - wy * cx);
    }} else {{
        F[0] = sx;
        F[1] = sy;
        F[2] = sz;
        F[3] = dx - (sy * pz - sz * py);
        F[4] = dy - (sz * px - sx * pz);
        F[5] = dz - (sx * py - sy * px);
    }}
    *rot = sqrt(s2);
    if (tr < 1.0) {{
        *rot = 2.0 - *rot;
    }}
    *pos = sqrt(dx * dx + dy * dy + dz * dz);
    return 0.5 * (*rot * *rot + *pos * *pos);
}}

{fkj}
/* out = 1/2 sum_(i<j) d_i d_j [J_i, J_j] (twists' bracket [(w, v), (w', v')] = (w x w', w x v' - w' x v)):
   the second-order term of the pose error's change along d (Baker-Campbell-Hausdorff), summed as
   sum_j [P_(j-1), d_j J_j] with the running sum P_j = sum_(i<=j) d_i J_i */
static void {P}_cal_second_order(const double J[36], const double d[6], double out[6])
{{
    double pw0 = 0.0, pw1 = 0.0, pw2 = 0.0, pv0 = 0.0, pv1 = 0.0, pv2 = 0.0;
    double o0 = 0.0, o1 = 0.0, o2 = 0.0, o3 = 0.0, o4 = 0.0, o5 = 0.0;
    int j;
    for (j = 0; j < 6; ++j) {{
        const double dj = d[j];
        const double bw0 = dj * J[j], bw1 = dj * J[6 + j], bw2 = dj * J[12 + j];
        const double bv0 = dj * J[18 + j], bv1 = dj * J[24 + j], bv2 = dj * J[30 + j];
        o0 += pw1 * bw2 - pw2 * bw1;
        o1 += pw2 * bw0 - pw0 * bw2;
        o2 += pw0 * bw1 - pw1 * bw0;
        o3 += (pw1 * bv2 - pw2 * bv1) - (bw1 * pv2 - bw2 * pv1);
        o4 += (pw2 * bv0 - pw0 * bv2) - (bw2 * pv0 - bw0 * pv2);
        o5 += (pw0 * bv1 - pw1 * bv0) - (bw0 * pv1 - bw1 * pv0);
        pw0 += bw0;
        pw1 += bw1;
        pw2 += bw2;
        pv0 += bv0;
        pv1 += bv1;
        pv2 += bv2;
    }}
    out[0] = 0.5 * o0;
    out[1] = 0.5 * o1;
    out[2] = 0.5 * o2;
    out[3] = 0.5 * o3;
    out[4] = 0.5 * o4;
    out[5] = 0.5 * o5;
}}

/* out (3 x 3 at out[o0 + 6 r + c]) = the inverse of the 3 x 3 block of M (6 columns) at row r0, column c0,
   by its adjugate; returns the determinant (0: nothing written) */
static double {P}_cal_inverse3(const double *M, int r0, int c0, double *out, int o0)
{{
    const double a00 = M[6 * r0 + c0], a01 = M[6 * r0 + c0 + 1], a02 = M[6 * r0 + c0 + 2];
    const double a10 = M[6 * r0 + 6 + c0], a11 = M[6 * r0 + 7 + c0], a12 = M[6 * r0 + 8 + c0];
    const double a20 = M[6 * r0 + 12 + c0], a21 = M[6 * r0 + 13 + c0], a22 = M[6 * r0 + 14 + c0];
    const double b00 = a11 * a22 - a12 * a21, b01 = a02 * a21 - a01 * a22, b02 = a01 * a12 - a02 * a11;
    const double b10 = a12 * a20 - a10 * a22, b11 = a00 * a22 - a02 * a20, b12 = a02 * a10 - a00 * a12;
    const double b20 = a10 * a21 - a11 * a20, b21 = a01 * a20 - a00 * a21, b22 = a00 * a11 - a01 * a10;
    const double det = a00 * b00 + a01 * b10 + a02 * b20;
    double inv;
    if (!(det > 0.0 || det < 0.0)) {{
        return 0.0;
    }}
    inv = 1.0 / det;
    out[o0] = b00 * inv;
    out[o0 + 1] = b01 * inv;
    out[o0 + 2] = b02 * inv;
    out[o0 + 6] = b10 * inv;
    out[o0 + 7] = b11 * inv;
    out[o0 + 8] = b12 * inv;
    out[o0 + 12] = b20 * inv;
    out[o0 + 13] = b21 * inv;
    out[o0 + 14] = b22 * inv;
    return det;
}}

{block_factor}{block_factor2}/* x = J^-1 e from {P}_cal_block_factor's B and p (x may be e: e is read before x is written) */
static void {P}_cal_block_solve(const double J[36], const double B[36], int p, const double *e, double *x)
{{
    const int o = 3 - p;
    const double y0 = B[0] * e[0] + B[1] * e[1] + B[2] * e[2];
    const double y1 = B[6] * e[0] + B[7] * e[1] + B[8] * e[2];
    const double y2 = B[12] * e[0] + B[13] * e[1] + B[14] * e[2];
    const double r0 = e[3] - (J[18 + p] * y0 + J[19 + p] * y1 + J[20 + p] * y2);
    const double r1 = e[4] - (J[24 + p] * y0 + J[25 + p] * y1 + J[26 + p] * y2);
    const double r2 = e[5] - (J[30 + p] * y0 + J[31 + p] * y1 + J[32 + p] * y2);
    const double x0 = B[18] * r0 + B[19] * r1 + B[20] * r2;
    const double x1 = B[24] * r0 + B[25] * r1 + B[26] * r2;
    const double x2 = B[30] * r0 + B[31] * r1 + B[32] * r2;
    x[o] = x0;
    x[o + 1] = x1;
    x[o + 2] = x2;
    x[p] = y0 - (B[3] * x0 + B[4] * x1 + B[5] * x2);
    x[p + 1] = y1 - (B[9] * x0 + B[10] * x1 + B[11] * x2);
    x[p + 2] = y2 - (B[15] * x0 + B[16] * x1 + B[17] * x2);
}}

/* A = the LU factors of J (6 x 6) with partial pivoting (the diagonal as reciprocals), piv = the row
   swapped into each column; 0 when a pivot is below 1e-12 of the largest entry */
static int {P}_cal_lu_factor(const double J[36], double A[36], int piv[6])
{{
    double big = 0.0, small;
    int r, cc, kk, p;
    for (r = 0; r < 36; ++r) {{
        A[r] = J[r];
        big = fabs(J[r]) > big ? fabs(J[r]) : big;
    }}
    if (!(big > 0.0)) {{
        return 0;
    }}
    small = {t(1e-12)} * big;
    for (cc = 0; cc < 6; ++cc) {{
        double best = fabs(A[6 * cc + cc]), inv;
        p = cc;
        for (r = cc + 1; r < 6; ++r) {{
            if (fabs(A[6 * r + cc]) > best) {{
                p = r;
                best = fabs(A[6 * r + cc]);
            }}
        }}
        if (best <= small) {{
            return 0;
        }}
        piv[cc] = p;
        if (p != cc) {{
            for (kk = cc; kk < 6; ++kk) {{
                const double tmp = A[6 * cc + kk];
                A[6 * cc + kk] = A[6 * p + kk];
                A[6 * p + kk] = tmp;
            }}
        }}
        inv = 1.0 / A[6 * cc + cc];
        A[6 * cc + cc] = inv;
        for (r = cc + 1; r < 6; ++r) {{
            const double f = A[6 * r + cc] * inv;
            A[6 * r + cc] = f;
            for (kk = cc + 1; kk < 6; ++kk) {{
                A[6 * r + kk] -= f * A[6 * cc + kk];
            }}
        }}
    }}
    return 1;
}}

/* x = J^-1 e from {P}_cal_lu_factor (x may be e) */
static void {P}_cal_lu_solve(const double A[36], const int piv[6], const double *e, double *x)
{{
    int r, cc, kk;
    for (r = 0; r < 6; ++r) {{
        x[r] = e[r];
    }}
    for (cc = 0; cc < 6; ++cc) {{
        if (piv[cc] != cc) {{
            const double tmp = x[cc];
            x[cc] = x[piv[cc]];
            x[piv[cc]] = tmp;
        }}
        for (r = cc + 1; r < 6; ++r) {{
            x[r] -= A[6 * r + cc] * x[cc];
        }}
    }}
    for (r = 5; r >= 0; --r) {{
        double acc = x[r];
        for (kk = r + 1; kk < 6; ++kk) {{
            acc -= A[6 * r + kk] * x[kk];
        }}
        x[r] = acc * A[6 * r + r];
    }}
}}

/* x = the step that zeroes the pose error F to second order (robokit.kernels.calibrated_ik._newton_step):
   d = J^-1 F, then for {lit(float(c["second_order"][0]))} < max|d| <= {lit(float(c["second_order"][1]))} x = J^-1 (F - B(d, d)/2) unless that
   changes d by more than max|d|/2; J factored once, by blocks or else with pivoting, in A (the caller's
   scratch); 0 when J is singular for this purpose */
static int {P}_cal_newton_step(const double J[36], const double F[6], double x[6], double A[36])
{{
    double d[6], big = 0.0;  /* x also holds F - B(d, d)/2: both solves may work in place */
    int piv[6], p = 0, i;
    const int blocked = {P}_cal_block_factor(J, A, &p);
    if (!blocked && !{P}_cal_lu_factor(J, A, piv)) {{
        return 0;
    }}
    if (blocked) {{
        {P}_cal_block_solve(J, A, p, F, d);
    }} else {{
        {P}_cal_lu_solve(A, piv, F, d);
    }}
    for (i = 0; i < 6; ++i) {{
        big = fabs(d[i]) > big ? fabs(d[i]) : big;
    }}
    if ({lit(float(c["second_order"][0]))} < big && big <= {lit(float(c["second_order"][1]))}) {{
        double change = 0.0;
        {P}_cal_second_order(J, d, x);
        for (i = 0; i < 6; ++i) {{
            x[i] = F[i] - x[i];
        }}
        if (blocked) {{
            {P}_cal_block_solve(J, A, p, x, x);
        }} else {{
            {P}_cal_lu_solve(A, piv, x, x);
        }}
        for (i = 0; i < 6; ++i) {{
            change = fabs(x[i] - d[i]) > change ? fabs(x[i] - d[i]) : change;
        }}
        if (change <= 0.5 * big) {{
            return 1;
        }}
    }}
    for (i = 0; i < 6; ++i) {{
        x[i] = d[i];
    }}
    return 1;
}}

/* H = L L^T in place (H symmetric 6 x 6; its lower triangle becomes L, the diagonal stored as
   reciprocals); 0 when H is not positive definite */
static int {P}_cal_chol_factor(double H[36])
{{
    int i, j, kk;
    for (j = 0; j < 6; ++j) {{
        double s = H[6 * j + j], inv;
        for (kk = 0; kk < j; ++kk) {{
            s -= H[6 * j + kk] * H[6 * j + kk];
        }}
        if (!(s > 0.0)) {{
            return 0;
        }}
        inv = 1.0 / sqrt(s);
        H[6 * j + j] = inv;
        for (i = j + 1; i < 6; ++i) {{
            s = H[6 * i + j];
            for (kk = 0; kk < j; ++kk) {{
                s -= H[6 * i + kk] * H[6 * j + kk];
            }}
            H[6 * i + j] = s * inv;
        }}
    }}
    return 1;
}}

/* x = (L L^T)^-1 b from {P}_cal_chol_factor's L (x may be b) */
static void {P}_cal_chol_solve(const double L[36], const double b[6], double x[6])
{{
    int i, kk;
    for (i = 0; i < 6; ++i) {{
        double s = b[i];
        for (kk = 0; kk < i; ++kk) {{
            s -= L[6 * i + kk] * x[kk];
        }}
        x[i] = s * L[6 * i + i];
    }}
    for (i = 5; i >= 0; --i) {{
        double s = x[i];
        for (kk = i + 1; kk < 6; ++kk) {{
            s -= L[6 * kk + i] * x[kk];
        }}
        x[i] = s * L[6 * i + i];
    }}
}}

/* H = J^T J and g = J^T F (J 6 x 6): the normal equations of J x = F */
static void {P}_cal_normal(const double J[36], const double F[6], double H[36], double g[6])
{{
    int i, j, r;
    for (i = 0; i < 6; ++i) {{
        double acc = 0.0;
        for (r = 0; r < 6; ++r) {{
            acc += J[6 * r + i] * F[r];
        }}
        g[i] = acc;
        for (j = i; j < 6; ++j) {{
            acc = 0.0;
            for (r = 0; r < 6; ++r) {{
                acc += J[6 * r + i] * J[6 * r + j];
            }}
            H[6 * i + j] = acc;
            H[6 * j + i] = acc;
        }}
    }}
}}

/* Newton's method with the second-order correction (Levenberg-Marquardt where a step fails) on the pose
   error, q updated in place;
   the sines and cosines computed once, then carried through the steps ({P}_cal_advance) */
static {P}_CAL_NOINLINE void {P}_cal_polish(const double Td[16], double q[6], int max_steps, double *rot, double *pos)
{{
    /* for a small stack, one scratch buffer: while a step is computed, the eliminated copy of J or the
       normal matrix H; while it is tried, the trial pose T, its sines and cosines sct, its error Ft and
       the trial point. The trial's Jacobian is written over J, which is recomputed from (q, sc), the
       same numbers, when the step is refused. */
    double J[36], F[6], sc[12], step[6], buf[40];
    double *const T = buf, *const sct = buf + 16, *const Ft = buf + 28, *const trial = buf + 34, *const H = buf;
    double err, lam = 0.0, rt, pt;
    int it, i;
    for (i = 0; i < 6; ++i) {{
        sc[i] = sin(q[i]);
        sc[6 + i] = cos(q[i]);
    }}
    {P}_cal_fkj(q, sc, T, J);
    err = {P}_cal_error(T, Td, F, rot, pos);
    for (it = 0; it < max_steps; ++it) {{
        double longest = 0.0, e2;
        int solved = 0;
        if (*rot < {t(c["tol_stop"])} && *pos < {t(c["tol_stop"])}) {{
            break;
        }}
        if (lam == 0.0) {{
            solved = {P}_cal_newton_step(J, F, step, buf);
        }}
        if (!solved) {{
            double *const g = step, big = 0.0;  /* the Cholesky solve overwrites g with the step */
            if (lam == 0.0) {{
                lam = 1e-9;
            }}
            {P}_cal_normal(J, F, H, g);
            for (i = 0; i < 6; ++i) {{
                big = H[6 * i + i] > big ? H[6 * i + i] : big;
            }}
            for (i = 0; i < 6; ++i) {{
                H[6 * i + i] += lam * big;
            }}
            if (!{P}_cal_chol_factor(H)) {{
                lam *= 10.0;
                if (lam > 1e3) {{
                    break;
                }}
                continue;
            }}
            {P}_cal_chol_solve(H, g, step);
        }}
        for (i = 0; i < 6; ++i) {{
            longest = fabs(step[i]) > longest ? fabs(step[i]) : longest;
        }}
        if (longest > {lit(float(c["max_step"]))}) {{
            const double shrink = {lit(float(c["max_step"]))} / longest;
            for (i = 0; i < 6; ++i) {{
                step[i] *= shrink;
            }}
        }}
        for (i = 0; i < 6; ++i) {{
            trial[i] = q[i] + step[i];
        }}
        {P}_cal_advance(sc, step, sct);
        {P}_cal_fkj(trial, sct, T, J);
        e2 = {P}_cal_error(T, Td, Ft, &rt, &pt);
        if (e2 < err) {{
            for (i = 0; i < 6; ++i) {{
                q[i] = trial[i];
                F[i] = Ft[i];
            }}
            for (i = 0; i < 12; ++i) {{
                sc[i] = sct[i];
            }}
            err = e2;
            *rot = rt;
            *pos = pt;
            if (lam > 0.0) {{
                lam = lam > 1e-9 ? lam * 0.1 : 0.0;
            }}
        }} else {{
            lam = lam == 0.0 ? 1e-9 : lam * 10.0;
            if (lam > 1e3) {{
                break;
            }}
            {P}_cal_fkj(q, sc, T, J);  /* J at q again */
        }}
    }}
}}

"""


def _fkj_code(P: str, frames: Any, kinds: Any, pitches: Any) -> str:
    """C of ``NAME_cal_fkj`` and ``NAME_cal_advance``: :func:`robokit.kernels.calibrated_ik.fk_jacobian`
    and ``_advance`` written out for this arm, the local transforms as literals (terms with a zero
    factor left out)."""
    def prod(terms: list[tuple[str, float]], add: str | None = None) -> str:
        parts = []
        for name, a in terms:
            if a == 0.0:
                continue
            parts.append(name if a == 1.0 else f"-{name}" if a == -1.0 else f"{name} * {lit(a)}")
        if add is not None:
            parts.append(add)
        if not parts:
            return "0.0"
        return " + ".join(parts).replace("+ -", "- ")

    R = [["r00", "r01", "r02", "px"], ["r10", "r11", "r12", "py"], ["r20", "r21", "r22", "pz"]]
    L0 = frames[0]
    body = [f"    double {R[r][c]} = {lit(float(L0[r, c]))};" for r in range(3) for c in range(4)]
    body.append("    double a, b, cq;")
    for i in range(7):
        if i > 0:
            A = frames[i]
            body.append("    {")
            for r in range(3):
                new = [prod([(R[r][k], float(A[k, c])) for k in range(3)], R[r][3] if c == 3 else None)
                       for c in range(4)]
                body.append(f"        const double n{r}0 = {new[0]}, n{r}1 = {new[1]}, n{r}2 = {new[2]}, "
                            f"n{r}3 = {new[3]};")
            for r in range(3):
                body.append(f"        {R[r][0]} = n{r}0; {R[r][1]} = n{r}1; {R[r][2]} = n{r}2; {R[r][3]} = n{r}3;")
            body.append("    }")
        if i == 6:
            break
        h = float(pitches[i])
        hz = (lambda k: f" + {lit(h)} * r{k}2") if h != 0.0 else (lambda k: "")
        if int(kinds[i]) == 0:
            body += [f"    J[{i}] = r02;", f"    J[{6 + i}] = r12;", f"    J[{12 + i}] = r22;",
                     f"    J[{18 + i}] = py * r22 - pz * r12{hz(0)};", f"    J[{24 + i}] = pz * r02 - px * r22{hz(1)};",
                     f"    J[{30 + i}] = px * r12 - py * r02{hz(2)};",
                     f"    a = sc[{i}];", f"    cq = sc[{6 + i}];"]
            for r in range(3):
                body.append(f"    b = cq * r{r}0 + a * r{r}1;")
                body.append(f"    r{r}1 = cq * r{r}1 - a * r{r}0;")
                body.append(f"    r{r}0 = b;")
            if h != 0.0:
                body += [f"    px += {lit(h)} * q[{i}] * r02;", f"    py += {lit(h)} * q[{i}] * r12;",
                         f"    pz += {lit(h)} * q[{i}] * r22;"]
        else:
            body += [f"    J[{i}] = 0.0;", f"    J[{6 + i}] = 0.0;", f"    J[{12 + i}] = 0.0;",
                     f"    J[{18 + i}] = r02;", f"    J[{24 + i}] = r12;", f"    J[{30 + i}] = r22;",
                     f"    px += q[{i}] * r02;", f"    py += q[{i}] * r12;", f"    pz += q[{i}] * r22;"]
    body += [f"    T[{4 * r + c}] = {R[r][c]};" for r in range(3) for c in range(4)]
    body += ["    T[12] = 0.0;", "    T[13] = 0.0;", "    T[14] = 0.0;", "    T[15] = 1.0;"]
    uses_q = any(int(k) != 0 for k in kinds) or any(float(h) != 0.0 for h in pitches)
    rev = [i for i in range(6) if int(kinds[i]) == 0]
    adv = []
    for i in range(6):
        if i in rev:
            adv.append(f"    {P}_cal_rotate(sc[{i}], sc[{6 + i}], step[{i}], &out[{i}], &out[{6 + i}]);")
        else:
            adv += [f"    out[{i}] = sc[{i}];", f"    out[{6 + i}] = sc[{6 + i}];"]
    nl = "\n"
    return f"""/* the tip pose T and the space Jacobian J (w rows first, v of the point at the base origin) of this
   arm at q, the revolute joints' sines in sc[0..5] and cosines in sc[6..11]: its product of
   exponentials rewritten with one frame per joint axis, T = L0 Z1(q1) L1 ... Z6(q6) L6 (Zi a turn
   about z or a slide along it), the Jacobian's columns read off the running product */
static void {P}_cal_fkj(const double q[6], const double sc[12], double T[16], double J[36])
{{
{nl.join(body)}
{"" if uses_q else "    (void)q;"}
}}

/* sin and cos of (x + d) from s = sin x, c = cos x; a step below 0.02 rad by Taylor series */
static void {P}_cal_rotate(double s, double c, double d, double *so, double *co)
{{
    double sd, cd;
    if (d > -0.02 && d < 0.02) {{
        const double d2 = d * d;
        sd = d * (1.0 - d2 * ({lit(1 / 6)} - d2 * ({lit(1 / 120)} - d2 * {lit(1 / 5040)})));
        cd = 1.0 - d2 * (0.5 - d2 * ({lit(1 / 24)} - d2 * ({lit(1 / 720)} - d2 * {lit(1 / 40320)})));
    }} else {{
        sd = sin(d);
        cd = cos(d);
    }}
    *so = s * cd + c * sd;
    *co = c * cd - s * sd;
}}

/* the sines and cosines of q + step from those of q */
static void {P}_cal_advance(const double sc[12], const double step[6], double out[12])
{{
{nl.join(adv)}
}}
"""


def _block_factor_code(P: str, c: Any, suffix: str, note: str) -> str:
    """C of the 3 × 3 block factorization of the polish's Jacobian, named NAME_cal_block_factor + suffix."""
    return note + f"""/* J (omega rows 0-2, v rows 3-5) factored by 3 x 3 blocks into B (6 x 6): pivot block D = the omega rows
   of joints p..p+2 spanning the larger volume (p = 3 or 0), the other joints o = 3 - p; B[0:3, 0:3] = D^-1,
   B[0:3, 3:6] = K = D^-1 J_w,o, B[3:6, 0:3] = S^-1 with S = J_v,o - J_v,p K; *p returned; 0 when D or S
   is near singular */
static int {P}_cal_block_factor{suffix}(const double J[36], double B[36], int *pp)
{{
    const double dw = J[3] * (J[10] * J[17] - J[11] * J[16]) - J[4] * (J[9] * J[17] - J[11] * J[15])
        + J[5] * (J[9] * J[16] - J[10] * J[15]);
    const double da = J[0] * (J[7] * J[14] - J[8] * J[13]) - J[1] * (J[6] * J[14] - J[8] * J[12])
        + J[2] * (J[6] * J[13] - J[7] * J[12]);
    const int p = fabs(dw) >= fabs(da) ? 3 : 0, o = 3 - p;
    double s = 0.0, det;
    int r, cc;
    if (!((fabs(dw) > fabs(da) ? fabs(dw) : fabs(da)) >= {lit(float(c["block_axes"]))})) {{
        return 0;
    }}
    (void){P}_cal_inverse3(J, 0, p, B, 0);
    for (r = 0; r < 3; ++r) {{
        for (cc = 0; cc < 3; ++cc) {{
            B[6 * r + 3 + cc] = B[6 * r] * J[o + cc] + B[6 * r + 1] * J[6 + o + cc] + B[6 * r + 2] * J[12 + o + cc];
        }}
    }}
    for (r = 0; r < 3; ++r) {{
        for (cc = 0; cc < 3; ++cc) {{
            const double v = J[6 * (3 + r) + o + cc] - (J[6 * (3 + r) + p] * B[3 + cc] + J[6 * (3 + r) + p + 1] * B[9 + cc]
                                                        + J[6 * (3 + r) + p + 2] * B[15 + cc]);
            B[6 * (3 + r) + 3 + cc] = v;
            s += v * v;
        }}
    }}
    det = {P}_cal_inverse3(B, 3, 3, B, 18);
    if (!(fabs(det) >= {lit(float(c["block_schur"]))} * s * sqrt(s))) {{
        return 0;
    }}
    *pp = p;
    return 1;
}}

"""
