r"""C for every closed-form IK solution, from the constants of robokit's closed-form solvers.

The generated ``NAME_ik`` is :func:`robokit.ik_analytic` written out for one robot: the
same method (chosen from the joint axes by :func:`robokit.ik_analytic_kind`), the same
constants, the same branches in the same order, the same wrapping, limit flags,
de-duplication and labels. Only the branches the robot needs are emitted.

* **Spherical wrist** (Pieper, Lecture 5): the target in the canonical chain
  ``T₀₆ = base′⁻¹ T tool′⁻¹``; the wrist centre ``W = T₀₆ ⁶W``; joint 3 from a polynomial
  in ``u = tan(θ₃/2)`` (or d₃) whose coefficients are linear in ``(r², r, h², h, 1)``,
  ``h = W_z − d₁``, ``r = ‖W‖² − …`` — degree 2 when ``a₁ = 0`` or ``sin α₁ = 0``, else the
  quartic; θ₂ from ``a cos θ + b sin θ = c``, θ₁ from an atan2; then the wrist angles from
  ``R₃ᵀR₀₆``. The quartic's real roots come from Ferrari's closed form (the resolvent
  cubic's largest root, two quadratics) followed by the three Newton steps robokit's Python
  applies to its companion-matrix eigenvalues, listed by increasing u as Python sorts them; a
  complex pair whose imaginary part is below 1e-6 (1 + |real part|) counts as two real roots,
  as in Python. Where the closed form is not trustworthy (a nearly biquadratic quartic, or
  roots whose product does not give the quartic back) the roots are isolated numerically instead,
  between the roots of the derivative, by safeguarded Newton steps. Each solution is then
  checked (and if needed polished) on the wrist-centre equation as in Python.
* **General 6R** (any other arm of six revolute joints): :mod:`robokit.codegen.ik_general`.
* **Three parallel axes** (UR family): θ₁ from ``a cos θ + b sin θ = c``, θ₅ from the
  direction of the parallel axes seen from the tool, θ₆ from an atan2, θ₂–θ₄ from the
  planar 2-link arm.
* **Planar** arms of 1–3 joints (and one prismatic joint): :mod:`robokit.codegen.ik_planar`.
* Both read backwards when the structure is at the base: the C solves ``T⁻¹`` with the
  reversed chain and maps ``q = −q′`` in reverse order.

Every case of Pieper's positioning equation is generated (joints 1–3 revolute or prismatic:
``RR-quartic``, ``RR-a1``, ``RR-s1``, ``PR-quartic``, ``PR-c1``, ``RP-quartic``, ``RP-c1``,
``PP``). Not generated (``NAME_HAS_IK 0`` with the reason in the header): arms with no closed
form in robokit, and the general 6R method with ``--float32`` (double only).
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any


from robokit.codegen._c import CWriter, Val, c_string, lin, lit, safe_comment, snap
from robokit.codegen import ik_calibrated, ik_general, ik_planar
from robokit.codegen._solver_constants import IKConstants, ik_constants
from robokit.ik.pieper import PieperConstants
from robokit.codegen.kinematics import Pose, compose

__all__ = ["IKCode", "emit_ik", "MAX_SOLUTIONS"]

#: Most distinct solutions any of the closed forms returns (4 positions × 2 wrists).
MAX_SOLUTIONS = 8
#: Rows before de-duplication: at most 8 in every case, kept in the caller's ``q`` (8 rows). Pieper:
#: at most 4 joint-3 values (the quartic's roots; or, degree-deficient, its roots and θ₃ = π), 1
#: joint-2 candidate each for a quartic case, at most 2 joint-3 values × 2 candidates for a
#: quadratic case; 2 wrists each. Three parallel axes: 2 × 2 × 2. (The guard ``nr < _RAW`` only
#: keeps the writes inside ``q``.)
_RAW = MAX_SOLUTIONS


@dataclass
class IKCode:
    """The IK part of the generated files (what :func:`emit_ik` returns).

    Attributes
    ----------
    has_ik : bool
        Whether ``NAME_ik`` is emitted.
    note : str
        Why not, or which closed-form method it uses.
    max_solutions : int
        Rows of the solution array (``NAME_MAX_SOLUTIONS``).
    header_lines : list of str
        Lines added to ``NAME.h``.
    source : str
        The C code added to ``NAME.c``.
    labels : list of str
        The solution labels, indexed by the label code the C function reports.

    Examples
    --------
    >>> code = emit_ik(rk.load("puma560"), "puma560")
    >>> code.has_ik, code.max_solutions, code.labels[0]
    (True, 8, 'right, elbow down, no flip')
    """

    has_ik: bool
    note: str
    max_solutions: int
    header_lines: list[str] = field(default_factory=list)
    source: str = ""
    labels: list[str] = field(default_factory=list)
    method_line: str = ""  # the header's "Inverse kinematics:" line (which method, or why none)


class _Tol:
    """Tolerance literals: robokit's own in double; in float their square roots (float's
    precision is about the square root of double's), and 1e-30 for 1e-300."""

    def __init__(self, float32: bool) -> None:
        self.float32 = float32

    def __call__(self, x: float) -> str:
        if not self.float32:
            return lit(x)
        if x < 1e-100:
            return lit(1e-30)
        return lit(math.sqrt(x)) if x < 1e-3 else lit(x)


def emit_ik(robot: Any, prefix: str, float32: bool = False, nominal: Any = None) -> IKCode:
    """The closed-form IK part of the generated files (see the module docstring).

    Parameters
    ----------
    robot : :class:`robokit.Robot`
        The robot; its closed-form solver is built (and cached) by ``ik_analytic_kind``.
    prefix : str
        The C prefix NAME.
    float32 : bool
        Tolerances for ``float`` code (the square roots of robokit's double ones).
    nominal : optional
        The nominal structure of a calibrated or nearly special arm (``robokit.ik_analytic``'s
        ``nominal``; default: recorded or detected).

    Returns
    -------
    IKCode
        ``has_ik`` False (and ``note`` the reason) when no C is generated; else the header
        declarations, the source (``NAME_ik``, ``NAME_ik_ex``, the label table) and the labels.

    Examples
    --------
    >>> import robokit
    >>> emit_ik(robokit.load("puma560"), "puma560").labels[0]
    'right, elbow down, no flip'
    """
    k = ik_constants(robot, nominal)
    if k.calibrated is not None:  # a calibrated arm: the projected arm's closed form + Newton on NAME_fk
        code = ik_calibrated.calibrated_code(k, prefix, _Tol(float32), _Emitter, IKCode)
        code.method_line = (f"{safe_comment(k.calibrated['method'])}: the closed form of the nominal structure "
                            f"({_method_line(k, True)}) gives the starts, Newton's method on NAME_fk finishes "
                            f"them, up to {code.max_solutions} solutions")
        return code
    if k.method is None:
        code = IKCode(False, "no closed form: " + safe_comment(k.reason), 1)
    elif k.method == "general 6R":
        code = (IKCode(False, ik_general.FLOAT32_NOTE, 1) if float32
                else _GeneralEmitter(k, prefix, _Tol(False)).code())
    elif k.method == "planar":
        code = ik_planar.planar_code(k, prefix, _Tol(float32), _Emitter, IKCode)
    elif k.method not in ("spherical wrist", "three parallel axes"):
        code = IKCode(False, f"robokit has a closed form ({safe_comment(k.method)}) but no C emitter for it yet; "
                             "use robokit.ik_analytic", 1)
    else:
        code = _Emitter(k, prefix, _Tol(float32)).code()
    code.method_line = _method_line(k, code.has_ik)
    return code


def _method_line(k: IKConstants, has_ik: bool) -> str:
    """Which method NAME_ik implements, for the header's top comment."""
    if not has_ik:
        return "none generated (see NAME_HAS_IK below for the reason)"
    rev = ", on the chain read from the tool back to the base" if k.reversed else ""
    if k.method == "general 6R":
        return ("general 6R (Raghavan-Roth elimination, Manocha-Canny 24 x 24 eigenproblem by Francis QR, Newton "
                "polish), up to 16 solutions")
    if k.method == "planar":
        assert k.planar is not None  # the planar method's constants
        m = ik_planar.planar_max_solutions(k.planar.n)
        return f"planar arm of {k.planar.n} joint{'s' if k.planar.n > 1 else ''} (Lecture 5), up to {m} solution{'s' if m > 1 else ''}"
    if k.method == "spherical wrist":
        assert k.pieper is not None  # the spherical wrist's constants
        deg = k.pieper.deg
        roots = ("the quartic's roots by Ferrari's closed form" if deg == 4
                 else f"a polynomial of degree {deg} in closed form")
        return f"Pieper's method (spherical wrist, Lecture 5), {roots}{rev}, up to 8 solutions"
    return f"three parallel axes (Lecture 5){rev}, up to 8 solutions"


class _Emitter:
    #: The calibrated arm's projected closed form: also its fold starts (robokit.kernels.closed_form.FOLD_STARTS;
    #: NAME_ik_starts(..., fold)), set by robokit.codegen.ik_calibrated.
    fold = False

    def __init__(self, k: IKConstants, prefix: str, tol: _Tol) -> None:
        self.k, self.P, self.tol = k, prefix, tol
        if k.method == "spherical wrist":
            self.shoulders = ["right, ", "left, ", "shoulder singular, "] if k.kinds[0] == "R" else [""]
            self.elbows = ["d3 +, ", "d3 \u2212, "] if k.kinds[2] == "P" else ["elbow down, ", "elbow up, "]
        else:
            self.shoulders = ["right, ", "left, "]
            self.elbows = ["elbow down, ", "elbow up, "]
        self.wrists = ["no flip", "flip", "wrist singular"]
        suffix = " (chain reversed)" if k.reversed else ""
        self.labels = [s + e + w + suffix for s in self.shoulders for e in self.elbows for w in self.wrists]

    # ------------------------------------------------------------------ pieces
    def label_index(self, s: str, e: str, w: str) -> str:
        """C expression of the label index from the C expressions of the three parts' indices."""
        ne, nw = len(self.elbows), len(self.wrists)
        return f"(({s}) * {ne} + ({e})) * {nw} + ({w})"

    def helpers(self) -> str:
        P, t = self.P, self.tol
        return f"""
/* angle wrapped to (-pi, pi] */
static double {P}_wrap(double a)
{{
    double w = fmod(a + {lit(math.pi)}, {lit(2 * math.pi)});
    if (w <= 0.0) {{
        w += {lit(2 * math.pi)};
    }}
    return w - {lit(math.pi)};
}}

/* Lecture 5: every t in (-pi, pi] with a cos t + b sin t = c, by u = tan(t/2):
   (a + c) u^2 - 2 b u + (c - a) = 0. Returns the number of roots, -1 when every t solves it. */
static int {P}_trig_roots(double a, double b, double c, double tol, double t[2])
{{
    const double r2 = a * a + b * b;
    double disc, sq, A, C, qq;
    if (r2 < {t(1e-300)}) {{
        return c == 0.0 ? -1 : 0;
    }}
    disc = r2 - c * c;
    if (disc < -tol * r2) {{
        return 0;
    }}
    sq = disc > 0.0 ? sqrt(disc) : 0.0;
    A = a + c;
    C = c - a;
    qq = b + (b >= 0.0 ? sq : -sq);
    if (qq == 0.0) {{
        t[0] = A != 0.0 ? 0.0 : {lit(math.pi)};
        return 1;
    }}
    t[0] = {P}_wrap(2.0 * atan2(qq, A));
    t[1] = {P}_wrap(2.0 * atan2(C, qq));
    return sq == 0.0 ? 1 : 2;
}}
"""

    def poly_helpers(self) -> str:
        """Real roots of a polynomial of degree ≤ 4 (coefficients low → high)."""
        P, t = self.P, self.tol
        near_arg, near_init, near_else = "", "", ""
        if self.fold:  # the real parts of complex pairs near the real line too (robokit.kernels.closed_form._roots)
            assert self.k.pieper is not None and self.k.calibrated is not None
            fi = float(self.k.calibrated["fold_imag"])
            near = (f"2.0 * im[i] <= {lit(math.tanh(fi))} * (1.0 + x * x + im[i] * im[i])" if self.k.pieper.kinds[2] == "R"
                    else f"im[i] <= {lit(fi)} * (1.0 + fabs(x))")
            near_arg = ", double near[2], int *nn"
            near_init = "\n    *nn = 0;"
            near_else = f""" else if (im[i] > 0.0 && {near}) {{
            int j = *nn;  /* a pair near the real line: its real part (increasing), a fold start */
            while (j > 0 && near[j - 1] > x) {{
                near[j] = near[j - 1];
                --j;
            }}
            near[j] = x;
            ++*nn;
        }}"""
        # float: a quartic with a large root (the roots' product |c0/c4| above 1, as where tan(th3/2) is in the
        # thousands, th3 near pi) loses its small roots to float's precision in the closed form; solved in
        # v = 1/u (the coefficients reversed) the large root is the small one, and each is then polished on c
        flip = self.tol.float32 and not self.fold
        ferrari = "quartic_closed" if flip else "quartic_roots"
        wrapper = f"""
/* float: the real roots of c[0] + ... + c[4] u^4, increasing; where |c[0]| > |c[4]| (the roots' product
   above 1: a large root, which float's closed form computes at the cost of the small ones) those of the
   reversed quartic in v = 1/u, inverted and polished on c. -1 as {P}_quartic_closed. */
static int {P}_quartic_roots(const double c[5], double out[4])
{{
    double rv[5], v[4];
    int i, j, n;
    if (!(fabs(c[0]) > fabs(c[4]))) {{
        return {P}_quartic_closed(c, out);
    }}
    for (i = 0; i < 5; ++i) {{
        rv[i] = c[4 - i];
    }}
    n = {P}_quartic_closed(rv, v);
    for (i = 0; i < n; ++i) {{
        const double u = {P}_newton_poly(c, 4, 1.0 / v[i]);  /* v = 0 is no root: rv[0] = c[4] != 0 */
        j = i;
        while (j > 0 && out[j - 1] > u) {{  /* insertion: increasing */
            out[j] = out[j - 1];
            --j;
        }}
        out[j] = u;
    }}
    return n;
}}
""" if flip else ""
        return f"""
/* value of the polynomial c[0] + c[1] x + ... + c[deg] x^deg (Horner) */
static double {P}_poly(const double c[5], int deg, double x)
{{
    double p = c[deg];
    int i;
    for (i = deg - 1; i >= 0; --i) {{
        p = p * x + c[i];
    }}
    return p;
}}

/* the root of c in [lo, hi] where c changes sign: bisection guarded Newton steps */
static double {P}_refine(const double c[5], int deg, double lo, double hi, double x, double tol)
{{
    double d[5];
    double plo = {P}_poly(c, deg, lo);
    int i, it;
    for (i = 1; i <= deg; ++i) {{
        d[i - 1] = (double)i * c[i];
    }}
    for (it = 0; it < 200; ++it) {{
        const double p = {P}_poly(c, deg, x);
        const double dp = {P}_poly(d, deg - 1, x);
        double next;
        if (p == 0.0) {{
            return x;
        }}
        if ((p < 0.0) == (plo < 0.0)) {{
            lo = x;
            plo = p;
        }} else {{
            hi = x;
        }}
        next = dp != 0.0 ? x - p / dp : 0.5 * (lo + hi);
        if (!(next > lo && next < hi)) {{
            next = 0.5 * (lo + hi);
        }}
        if (fabs(next - x) <= tol * (1.0 + fabs(x)) || hi - lo <= tol * (1.0 + fabs(x))) {{
            return next;
        }}
        x = next;
    }}
    return x;
}}

/* Newton steps on the polynomial from t (at most 3, as robokit's Python after its eigenvalues);
   a step that would raise |p| or move t by more than 1e-4 (1 + |t|) is not taken: the start is
   a root already, and at a double root p / p' is round-off over round-off */
static double {P}_newton_poly(const double c[5], int deg, double t)
{{
    double p = {P}_poly(c, deg, t);
    int it, k;
    for (it = 0; it < 3; ++it) {{
        double dp = 0.0, q = c[deg], step, next, pn;
        for (k = deg - 1; k >= 0; --k) {{
            dp = dp * t + q;
            q = q * t + c[k];
        }}
        if (dp == 0.0) {{
            break;
        }}
        step = p / dp;
        next = t - step;
        pn = {P}_poly(c, deg, next);
        if (fabs(pn) > fabs(p) || fabs(step) > {t(1e-4)} * (1.0 + fabs(t))) {{
            break;  /* a polish only: never a jump (to another root) */
        }}
        t = next;
        p = pn;
        if (fabs(step) <= {t(1e-15)} * (1.0 + fabs(t))) {{
            break;
        }}
    }}
    return t;
}}

/* Lecture 5's quartic in closed form (Ferrari): the real roots of c[0] + ... + c[4] x^4, increasing,
   each polished by Newton steps. x = y - a/4 gives y^4 + p y^2 + q y + r; with m the largest root
   of the resolvent cubic m^3 + p m^2 + (p^2/4 - r) m - q^2/8 = 0 (trigonometric or Cardano form),
   y^4 + p y^2 + q y + r = (y^2 + p/2 + m)^2 - 2m (y - q/(4m))^2: two quadratics. As robokit's
   Python (companion eigenvalues), a complex pair with |imag| <= 1e-6 (1 + |real|) counts as two
   real roots at its real part. Returns -1 when the closed form is not trustworthy (q ~ 0, or the
   four roots do not multiply back to the quartic): the caller then isolates the roots numerically. */
static int {P}_{ferrari}(const double c[5], double out[4]{near_arg})
{{
    const double a = c[3] / c[4], b = c[2] / c[4], cc = c[1] / c[4], d = c[0] / c[4];
    const double p = b - 0.375 * a * a;
    const double q = cc - 0.5 * a * b + 0.125 * a * a * a;
    const double r = d - 0.25 * a * cc + 0.0625 * a * a * b - 0.01171875 * a * a * a * a;
    const double A = p, B = 0.25 * p * p - r, C = -0.125 * q * q;
    const double P3 = B - A * A / 3.0, Q3 = 2.0 * A * A * A / 27.0 - A * B / 3.0 + C;
    const double disc = 0.25 * Q3 * Q3 + P3 * P3 * P3 / 27.0;
    const double size = 1.0 + fabs(a) + sqrt(fabs(b)) + sqrt(sqrt(fabs(d))) + cbrt(fabs(cc));
    double m, s, re[4], im[4];
    int i, k, n = 0;{near_init}
    /* the largest real root of the resolvent cubic (z = m + A/3: z^3 + P3 z + Q3 = 0) */
    if (disc > 0.0) {{
        const double sq = sqrt(disc);
        m = cbrt(-0.5 * Q3 + sq) + cbrt(-0.5 * Q3 - sq) - A / 3.0;
    }} else {{
        const double rr = sqrt(-P3 / 3.0);
        double arg = rr > 0.0 ? -0.5 * Q3 / (rr * rr * rr) : 0.0;
        arg = arg > 1.0 ? 1.0 : (arg < -1.0 ? -1.0 : arg);
        m = 2.0 * rr * cos(acos(arg) / 3.0) - A / 3.0;
    }}
    for (k = 0; k < 2; ++k) {{  /* two Newton steps on the cubic */
        const double f = ((m + A) * m + B) * m + C, df = (3.0 * m + 2.0 * A) * m + B;
        if (df != 0.0) {{
            m -= f / df;
        }}
    }}
    if (!(m > {t(1e-10)} * size * size)) {{
        return -1;  /* q ~ 0 (nearly biquadratic): the split below divides by sqrt(2m) */
    }}
    s = sqrt(2.0 * m);
    for (k = 0; k < 2; ++k) {{  /* y^2 -+ s y + (p/2 + m +- q/(2s)) = 0 */
        const double sg = k == 0 ? 1.0 : -1.0;
        const double e = 0.5 * p + m + sg * 0.5 * q / s;
        const double dq = s * s - 4.0 * e;
        const double mid = 0.5 * sg * s;
        if (dq >= 0.0) {{
            const double sq = sqrt(dq);
            const double y1 = mid + (sg >= 0.0 ? 0.5 * sq : -0.5 * sq);  /* the larger in size first */
            re[2 * k] = y1;
            re[2 * k + 1] = y1 != 0.0 ? e / y1 : mid - (sg >= 0.0 ? 0.5 * sq : -0.5 * sq);
            im[2 * k] = im[2 * k + 1] = 0.0;
        }} else {{
            re[2 * k] = re[2 * k + 1] = mid;
            im[2 * k] = 0.5 * sqrt(-dq);
            im[2 * k + 1] = -im[2 * k];
        }}
    }}
    /* Vieta: the product of (y - y_i) must give back y^4 + p y^2 + q y + r, coefficient by
       coefficient, to 1e-9 of the same product of (|y| + |y_i|) (an ill-conditioned resolvent
       root, as at a double root of the quartic, fails this) */
    {{
        double pr[5] = {{1.0, 0.0, 0.0, 0.0, 0.0}}, pi[5] = {{0.0, 0.0, 0.0, 0.0, 0.0}};
        double mg[5] = {{1.0, 0.0, 0.0, 0.0, 0.0}};
        const double want[4] = {{r, q, p, 0.0}};
        int deg;
        for (i = 0; i < 4; ++i) {{  /* multiply by (y - y_i): pr/pi hold the coefficients, high first */
            const double mag = sqrt(re[i] * re[i] + im[i] * im[i]);
            for (deg = i + 1; deg >= 1; --deg) {{
                const double xr = pr[deg] - (re[i] * pr[deg - 1] - im[i] * pi[deg - 1]);
                const double xi = pi[deg] - (re[i] * pi[deg - 1] + im[i] * pr[deg - 1]);
                pr[deg] = xr;
                pi[deg] = xi;
                mg[deg] += mag * mg[deg - 1];
            }}
        }}
        for (k = 1; k <= 4; ++k) {{  /* pr[k] is the coefficient of y^(4-k) */
            if (fabs(pr[k] - want[4 - k]) > {t(1e-9)} * mg[k] || fabs(pi[k]) > {t(1e-9)} * mg[k]) {{
                return -1;
            }}
        }}
    }}
    for (i = 0; i < 4; ++i) {{
        const double x = re[i] - 0.25 * a;
        if (fabs(im[i]) <= {t(1e-6)} * (1.0 + fabs(x))) {{
            double t0 = {P}_newton_poly(c, 4, x);
            int j = n;
            while (j > 0 && out[j - 1] > t0) {{  /* insertion: increasing */
                out[j] = out[j - 1];
                --j;
            }}
            out[j] = t0;
            ++n;
        }}{near_else}
    }}
    return n;
}}
{wrapper}
/* every real root of c (degree deg <= 4, c[deg] != 0), increasing: the roots of the derivative
   split the line into pieces where c is monotonic; a piece whose ends differ in sign holds one
   root. A root of the derivative where c vanishes (to round-off) is a double root. Bottom up (no
   recursion, for a small stack): the linear derivative's root, then each derivative's roots from
   the next one's, up to c's. */
static int {P}_real_roots(const double c[5], int deg, double out[5], double tol)
{{
    double cur[5], crit[5];
    int i, j, k, nc, nr = 1;
    for (k = 1; k <= deg; ++k) {{
        double bound = 0.0, lo, scale = 0.0;
        for (i = 0; i <= deg; ++i) {{  /* cur: the (deg - k)-th derivative of c (degree k) */
            cur[i] = c[i];
        }}
        for (j = deg; j > k; --j) {{
            for (i = 1; i <= j; ++i) {{
                cur[i - 1] = (double)i * cur[i];
            }}
        }}
        if (k == 1) {{
            out[0] = -cur[0] / cur[1];
            continue;
        }}
        nc = nr;  /* the critical points (the derivative's roots) only bound the pieces */
        for (i = 0; i < nc; ++i) {{
            crit[i] = out[i];
        }}
        nr = 0;
        for (i = 0; i < k; ++i) {{
            const double r = fabs(cur[i] / cur[k]);
            bound = r > bound ? r : bound;
            scale = fabs(cur[i]) > scale ? fabs(cur[i]) : scale;
        }}
        scale = fabs(cur[k]) > scale ? fabs(cur[k]) : scale;
        bound += 1.0;  /* Cauchy's bound on the roots */
        lo = -bound;
        for (i = 0; i <= nc; ++i) {{
            const double hi = i < nc ? crit[i] : bound;
            const double plo = {P}_poly(cur, k, lo), phi = {P}_poly(cur, k, hi);
            if (hi > lo && ((plo < 0.0 && phi > 0.0) || (plo > 0.0 && phi < 0.0))) {{
                /* start an outer piece next to its critical point, an inner one in its middle */
                double x0 = i == 0 && nc > 0 ? hi - 1.0 : (i == nc && nc > 0 ? lo + 1.0 : 0.5 * (lo + hi));
                if (!(x0 > lo && x0 < hi)) {{
                    x0 = 0.5 * (lo + hi);
                }}
                out[nr++] = {P}_refine(cur, k, lo, hi, x0, k == deg ? tol : {t(1e-9)});
            }} else if (i < nc && fabs(phi) <= {t(1e-14)} * scale * (1.0 + fabs(hi)) * (1.0 + fabs(hi))) {{
                if (nr == 0 || out[nr - 1] < hi) {{  /* the roots so far are <= lo <= hi: "not equal" */
                    out[nr++] = hi;  /* a double root at a critical point */
                }}
            }}
            lo = hi > lo ? hi : lo;
        }}
    }}
    return nr;
}}
"""

    def finish(self, max_solutions: int = MAX_SOLUTIONS, repeats: bool = True) -> str:
        """Wrapping, limits, de-duplication and labels (``ClosedFormModel._finish``); ``repeats``
        False when no label can occur twice (the repeat number is then always 1, no counter table)."""
        k, P, n = self.k, self.P, len(self.k.rev)  # 6, or a planar arm's 1-3
        lines = []
        for j in range(n):
            if k.rev[j]:
                lines.append(f"        qq[{j}] = rows[r][{j}];")
                lines.append(f"        if (qq[{j}] > {lit(math.pi)} || qq[{j}] <= -{lit(math.pi)}) {{\n"
                             f"            qq[{j}] = remainder(qq[{j}], {lit(2 * math.pi)});  /* exact: same as "
                             f"remainder on (-pi, pi] */\n"
                             f"            if (qq[{j}] <= -{lit(math.pi)}) {{  /* remainder's result is >= -pi: "
                             f"this is == -pi */\n                qq[{j}] = {lit(math.pi)};\n"
                             f"            }}\n        }}")
            else:
                lines.append(f"        qq[{j}] = rows[r][{j}];")
        if k.lims is not None:
            for j, (lo, hi) in enumerate(k.lims):
                if math.isinf(lo) and math.isinf(hi):
                    continue
                if k.rev[j]:
                    two = lit(2 * math.pi)
                    lines.append(f"""        if (qq[{j}] < {lit(lo)} || qq[{j}] > {lit(hi)}) {{
            if ({lit(lo)} <= qq[{j}] + {two} && qq[{j}] + {two} <= {lit(hi)}) {{
                qq[{j}] += {two};  /* limits wider than +-pi: the shifted angle is inside */
            }} else if ({lit(lo)} <= qq[{j}] - {two} && qq[{j}] - {two} <= {lit(hi)}) {{
                qq[{j}] -= {two};
            }} else {{
                inside = 0;
            }}
        }}""")
                else:
                    lines.append(f"        if (qq[{j}] < {lit(lo)} || qq[{j}] > {lit(hi)}) {{\n"
                                 f"            inside = 0;\n        }}")
        same = []
        for j in range(n):
            if k.rev[j]:
                same.append(f"{P}_same_angle(qq[{j}], q[{n} * m + {j}], {self.tol(1e-9)})")
            else:
                same.append(f"fabs(qq[{j}] - q[{n} * m + {j}]) < {self.tol(1e-9)}")
        same_c = "\n                && ".join(same)
        body = "\n".join(lines)
        count_decl = f"    int count[{len(self.labels)}];\n" if repeats else ""
        count_init = "    memset(count, 0, sizeof count);\n" if repeats else ""
        count_add = "        count[lab[r]] += 1;\n" if repeats else ""
        count_of = "count[lab[r]]" if repeats else "1  /* every label is unique */"
        same_angle = f"""
/* |remainder(a - b, 2 pi)| < tol, for a, b within (-3 pi, 3 pi) (wrapped or shifted by 2 pi) */
static int {P}_same_angle(double a, double b, double tol)
{{
    const double d = fabs(a - b);
    return d < tol || fabs(d - {lit(2 * math.pi)}) < tol || fabs(d - {lit(4 * math.pi)}) < tol
        || fabs(d - {lit(6 * math.pi)}) < tol;
}}
""" if any(k.rev[:n]) else ""  # (an arm of one prismatic joint has no angle)
        return f"""{same_angle}
/* ik_analytic's last step: revolute angles wrapped to (-pi, pi] (or shifted by 2 pi into wider
   limits), the within-limits flag, duplicates dropped (angles compared modulo 2 pi), and the
   repeat number of a label that occurs twice (" #2"). */
static int {P}_finish(const double rows[][{n}], const int lab[], const int deg[], int nr, double q[], int info[])
{{
{count_decl}    int r, m, nk = 0;
{count_init}    for (r = 0; r < nr && nk < {max_solutions}; ++r) {{
        double qq[{n}];
        int inside = 1, dup = 0, j;
{body}
        for (m = 0; m < nk && !dup; ++m) {{
            dup = {same_c};
        }}
        if (dup) {{
            continue;
        }}
        for (j = 0; j < {n}; ++j) {{
            q[{n} * nk + j] = qq[j];
        }}
{count_add}        if (info) {{
            info[4 * nk] = lab[r];
            info[4 * nk + 1] = {count_of};
            info[4 * nk + 2] = inside;
            info[4 * nk + 3] = deg[r];
        }}
        ++nk;
    }}
    return nk;
}}
"""

    def target(self, w: CWriter) -> Pose:
        """Emit T₀₆ (the pose to reach with the canonical chain) from the input T."""
        k = self.k
        T = Pose([[f"T[{4 * i + j}]" for j in range(3)] for i in range(3)], [f"T[{4 * i + 3}]" for i in range(3)])
        if k.reversed:
            w.comment("the chain read backwards reaches T^-1: R^T, -R^T p")
            Rt: list[list[Val]] = [[T.R[j][i] for j in range(3)] for i in range(3)]
            p = [w.let(f"ti{i}", lin([(-1.0, f"{T.R[0][i]} * {T.p[0]}"), (-1.0, f"{T.R[1][i]} * {T.p[1]}"),
                                      (-1.0, f"{T.R[2][i]} * {T.p[2]}")])) for i in range(3)]
            T = Pose(Rt, p)
        w.comment("the pose reached by Z1 X1 ... Z6: T06 = base'^-1 T tool'^-1 (constants of the DH chain)")
        if k.base_inv is not None:
            T = compose(w, Pose.const(k.base_inv), T, "tb")
        if k.tool_inv is not None:
            T = compose(w, T, Pose.const(k.tool_inv), "t06")
        return T

    def declare(self) -> list[str]:
        P = self.P
        return [
            f"/* Closed-form inverse kinematics ({safe_comment(self.k.method or '')}; Lecture 5): every solution for",
            f"   the tool pose T, one row of {P}_N values each, {P}_ik returning how many (0: out of reach).",
            "   The same solutions, in the same order, with the same labels as robokit's ik_analytic.",
            "   Revolute angles in (-pi, pi] (or shifted by 2 pi into wider limits). */",
            f"int {P}_ik(const double T[16], double q[{P}_MAX_SOLUTIONS * {P}_N]);",
            "",
            f"/* The same with, per solution k, info[4k..4k+3] = (label index into {P}_ik_label_names, repeat",
            "   number (2 or more: ik_analytic's label ends in \" #repeat\"), within joint limits (0/1),",
            "   degenerate: a free angle was set at a singularity (0/1)); info may be a null pointer.",
            "   wrist_ref: the value of the free joint at a wrist singularity (ik_analytic's wrist_ref). */",
            f"int {P}_ik_ex(const double T[16], double wrist_ref, double q[{P}_MAX_SOLUTIONS * {P}_N], "
            f"int info[4 * {P}_MAX_SOLUTIONS]);",
            "",
            f"#define {P}_IK_LABEL_COUNT {len(self.labels)}",
            f"extern const char *const {P}_ik_label_names[{P}_IK_LABEL_COUNT];",
            f"extern const int {P}_ik_label_count;",
            f"extern const int {P}_ik_max_solutions;",
            "",
        ]

    def tables(self) -> str:
        P = self.P
        names = ",\n    ".join(c_string(x) for x in self.labels)
        return (f"const char *const {P}_ik_label_names[{P}_IK_LABEL_COUNT] = {{\n    {names}\n}};\n"
                f"const int {P}_ik_label_count = {P}_IK_LABEL_COUNT;\n"
                f"const int {P}_ik_max_solutions = {P}_MAX_SOLUTIONS;\n")

    def code(self) -> IKCode:
        k, P = self.k, self.P
        w = CWriter()
        T06 = self.target(w)
        target = w.text()
        if k.method == "spherical wrist":
            solve = _pieper(self, T06)
        else:
            solve = _parallel(self, T06)
        post = ""
        if k.reversed:
            post = """    /* back to the robot's own joints: q = -q' in reverse order */
    for (ir = 0; ir < nr; ++ir) {
        for (jr = 0; jr < 3; ++jr) {
            const double tmp = rows[ir][jr];
            rows[ir][jr] = -rows[ir][5 - jr];
            rows[ir][5 - jr] = -tmp;
        }
    }
"""
        if k.flip is not None and any(k.flip):
            neg = [j for j, f in enumerate(k.flip) if f]
            post += "    /* flipped joints (theta = offset - q) were solved as q' = -q */\n"
            post += "    for (ir = 0; ir < nr; ++ir) {\n"
            post += "".join(f"        rows[ir][{j}] = -rows[ir][{j}];\n" for j in neg)
            post += "    }\n"
        sign = (-1 if k.reversed else 1) * (-1 if k.free_flipped else 1)
        wref = "-wrist_ref" if sign < 0 else "wrist_ref"
        src = [self.tables()]
        quartic = k.pieper is not None and k.pieper.deg == 4
        if not (k.pieper is not None and k.pieper.case in ("RR-quartic", "PR-quartic", "RP-quartic", "RP-c1", "PP")):
            src.append(self.helpers())  # a cos t + b sin t = c
        if k.method == "spherical wrist":
            if quartic:
                src.append(self.poly_helpers())
            src.append(_pieper_helpers(self, quartic))
        if self.fold and k.method != "spherical wrist":
            src.append(_parallel_free_helpers(self))
        src.append(self.finish())
        if self.fold:  # the calibrated arm's starts: NAME_ik_ex's rows, with fold starts (info's flag 3) when fold
            head = f"""
/* the starts of the calibrated arm's IK: NAME_ik_ex's solutions, and with fold set its fold starts
   (robokit.kernels.closed_form.FOLD_STARTS; info[4k + 3] = 3, not solutions of this arm) */
static int {P}_ik_starts(const double T[16], double wrist_ref, double q[{P}_MAX_SOLUTIONS * {P}_N],
                         int info[4 * {P}_MAX_SOLUTIONS], int fold)
{{"""
            void_fold = "    (void)fold;\n"
            tail = f"""
/* every closed-form solution (Lecture 5), see {P}.h */
int {P}_ik_ex(const double T[16], double wrist_ref, double q[{P}_MAX_SOLUTIONS * {P}_N], int info[4 * {P}_MAX_SOLUTIONS])
{{
    return {P}_ik_starts(T, wrist_ref, q, info, 0);
}}
"""
        else:
            head = f"""
/* every closed-form solution (Lecture 5), see {P}.h */
int {P}_ik_ex(const double T[16], double wrist_ref, double q[{P}_MAX_SOLUTIONS * {P}_N], int info[4 * {P}_MAX_SOLUTIONS])
{{"""
            void_fold, tail = "", ""
        src.append(f"""{head}
    double (*rows)[6] = (double (*)[6])q;  /* in place: {P}_finish reads row r before it writes row <= r */
    int lab[{_RAW}], deg[{_RAW}];
    int nr = 0, ir, jr;
    const double ref = {wref};
{target}
{solve}
{post}    (void)ir;
    (void)jr;
    (void)ref;
{void_fold}    return {P}_finish((const double (*)[6])rows, lab, deg, nr, q, info);
}}
{tail}
int {P}_ik(const double T[16], double q[{P}_MAX_SOLUTIONS * {P}_N])
{{
    return {P}_ik_ex(T, 0.0, q, 0);
}}
""")
        return IKCode(True, f"closed form: {safe_comment(k.reason)}", MAX_SOLUTIONS, self.declare(),
                      "\n".join(src), self.labels)


def _val(coef: Any, kind: str, x: str, c: str, s: str) -> Val:
    """C of a coefficient triple at joint 3's value: k₀ + k₁ cos θ + k₂ sin θ, or k₀ + k₁ d + k₂ d²."""
    k0, k1, k2 = (float(v) for v in coef)
    if kind == "R":
        return lin([(k1, c), (k2, s)], k0)
    return lin([(k1, x), (k2, f"{x} * {x}")], k0)


def _pieper_helpers(e: _Emitter, quartic: bool) -> str:
    k, P, t = e.k, e.P, e.tol
    sv = k.pieper
    assert sv is not None  # the spherical wrist's constants
    ca, sa = list(sv.ca), list(sv.sa)
    w3 = list(sv.w3)
    a1, a2 = sv.a1, sv.a2
    th0, d0 = k.th0, k.d0
    ang = []
    for i in range(3):
        if k.kinds[i] == "R":
            ang.append(f"    th[{i}] = {lit(th0[i])} + q[{i}];\n    dd[{i}] = {lit(d0[i])};")
        else:
            ang.append(f"    th[{i}] = {lit(th0[i])};\n    dd[{i}] = {lit(d0[i])} + q[{i}];")
    angles = "\n".join(ang)
    ca4, sa4, ca5, sa5 = ca[3], sa[3], ca[4], sa[4]
    kk = sa4 * sa5
    right = ca4 == 0.0 and ca5 == 0.0

    def s5_near(cond: str) -> str:
        """|sin th5| from the wrist direction's length across axis 4 near the singularity (the kernel's
        closed_form._wrist_angles): 1 - cos^2 th5 loses its digits there."""
        if not abs(sa5) > 0.5:
            return ""
        return f"""
    yp = {lit(-ca4 * sa5)} * c5 + {lit(-sa4 * ca5)};
    if ({cond}s5 < 0.5 && fabs(yp) <= 0.5 * rho) {{  /* near the singularity: rho^2 = (sin al5 s5)^2 + yp^2 */
        s5 = sqrt(rho * rho - yp * yp) / {lit(abs(sa5))};
    }}"""
    if right:
        c5s5 = f"""    c5 = -mz / {lit(kk)};  /* right-angled wrist (ZYZ type): |s5| = rho */
    s5 = rho;"""
    elif e.fold:
        assert k.calibrated is not None  # (the fold starts are the calibrated arm's)
        c5s5 = f"""    c5 = ({lit(ca4 * ca5)} - mz) / {lit(kk)};
    if (fabs(c5) > 1.0 + {t(1e-10)}) {{  /* out of reach of an oblique wrist */
        const double gap = fabs(c5) - 1.0;
        /* (fold 2: a fold position's wrist, whose window is wider: FOLD_POSITION_WRIST) */
        if (!fold || gap > (fold == 2 ? {lit(float(k.calibrated["fold_position_wrist"]))} : {lit(float(k.calibrated["fold_starts"]))})) {{
            return 0;
        }}
        fc = {k.calibrated["fold_code"]};  /* near its fold: two starts, th5 = +-sqrt(2 gap) from it */
        c5 = copysign(cos(sqrt(2.0 * gap)), c5);
    }}
    c5 = c5 > 1.0 ? 1.0 : (c5 < -1.0 ? -1.0 : c5);
    s5 = sqrt(1.0 - c5 * c5 > 0.0 ? 1.0 - c5 * c5 : 0.0);""" + s5_near("fc == 0 && ")
    else:
        c5s5 = f"""    c5 = ({lit(ca4 * ca5)} - mz) / {lit(kk)};
    if (fabs(c5) > 1.0 + {t(1e-10)}) {{
        return 0;  /* out of reach of an oblique wrist */
    }}
    c5 = c5 > 1.0 ? 1.0 : (c5 < -1.0 ? -1.0 : c5);
    s5 = sqrt(1.0 - c5 * c5 > 0.0 ? 1.0 - c5 * c5 : 0.0);""" + s5_near("")
    rots_m = [f"    const double ct[3] = {{cos(th[0]), cos(th[1]), cos(th[2])}};\n"
              f"    const double st[3] = {{sin(th[0]), sin(th[1]), sin(th[2])}};"]
    for i in range(3):
        rots_m.append(f"""    c = ct[{i}];
    s = st[{i}];
    x = c * mx + s * my; my = c * my - s * mx; mx = x;
    x = c * ex + s * ey; ey = c * ey - s * ex; ex = x;""")
        if sa[i] != 0.0 or ca[i] != 1.0:
            rots_m.append(f"""    x = {lit(ca[i])} * my + {lit(sa[i])} * mz; mz = {lit(ca[i])} * mz - {lit(sa[i])} * my; my = x;
    x = {lit(ca[i])} * ey + {lit(sa[i])} * ez; ez = {lit(ca[i])} * ez - {lit(sa[i])} * ey; ey = x;""")
    rots_n = []
    for i in (2, 1, 0):
        if sa[i] != 0.0 or ca[i] != 1.0:
            rots_n.append(f"    x = {lit(ca[i])} * ny - {lit(sa[i])} * nz; nz = {lit(sa[i])} * ny + {lit(ca[i])} * nz; "
                          f"ny = x;")
        rots_n.append(f"    c = ct[{i}];\n    s = st[{i}];\n"
                      f"    x = c * nx - s * ny; ny = s * nx + c * ny; nx = x;")
    gamma_ca4 = lit(ca4)
    fold_arg = ", int fold" if e.fold else ""
    fold_decl = "int i, fc = 0;" + ("\n    (void)fold;" if right else "") if e.fold else "int i;"
    fold_add = f" + fc" if e.fold else ""
    text = f"""
/* joint values q1..q3 -> rotation angles th and offsets dd of joints 1-3 */
static void {P}_angles(const double q[3], double th[3], double dd[3])
{{
{angles}
}}

@@CHECK_START@@
/* the wrist centre of joints 1-3 (frame 0'): Rz(th1)Tz(d1) Rx(al1)Tx(a1) Rz(th2)Tz(d2) Rx(al2)Tx(a2) Rz(th3) (3W + d3 z) */
static void {P}_wrist_point(const double th[3], const double dd[3], double p[3])
{{
    double c = cos(th[2]), s = sin(th[2]);
    double x = c * {lit(w3[0])} - s * {lit(w3[1])}, y = s * {lit(w3[0])} + c * {lit(w3[1])}, z = {lit(w3[2])} + dd[2], u;
    x += {lit(a2)};
    u = {lit(ca[1])} * y - {lit(sa[1])} * z; z = {lit(sa[1])} * y + {lit(ca[1])} * z; y = u;
    c = cos(th[1]); s = sin(th[1]);
    z += dd[1];
    u = c * x - s * y; y = s * x + c * y; x = u;
    x += {lit(a1)};
    u = {lit(ca[0])} * y - {lit(sa[0])} * z; z = {lit(sa[0])} * y + {lit(ca[0])} * z; y = u;
    c = cos(th[0]); s = sin(th[0]);
    z += dd[0];
    p[0] = c * x - s * y;
    p[1] = s * x + c * y;
    p[2] = z;
}}

/* largest error of the wrist centre at q against W */
static double {P}_wrist_error(const double q[3], const double W[3])
{{
    double th[3], dd[3], p[3], e0, e1, e2;
    {P}_angles(q, th, dd);
    {P}_wrist_point(th, dd, p);
    e0 = fabs(W[0] - p[0]);
    e1 = fabs(W[1] - p[1]);
    e2 = fabs(W[2] - p[2]);
    return e0 > e1 ? (e0 > e2 ? e0 : e2) : (e1 > e2 ? e1 : e2);
}}

/* Newton steps on the wrist-centre equation W(q1, q2, q3) = W (central-difference Jacobian);
   returns the remaining error */
static double {P}_polish(double q[3], const double W[3])
{{
    double err = HUGE_VAL;
    int it, j, i;
    for (it = 0; it < 4; ++it) {{
        double th[3], dd[3], p[3], e[3], J[3][3], det, dq[3];
        {P}_angles(q, th, dd);
        {P}_wrist_point(th, dd, p);
        for (i = 0; i < 3; ++i) {{
            e[i] = W[i] - p[i];
        }}
        err = fabs(e[0]) > fabs(e[1]) ? fabs(e[0]) : fabs(e[1]);
        err = fabs(e[2]) > err ? fabs(e[2]) : err;
        if (err <= {t(1e-13)} * {lit(k.scale)} || it == 3) {{
            break;
        }}
        for (j = 0; j < 3; ++j) {{
            double qp[3], qm[3], pp[3], pm[3];
            for (i = 0; i < 3; ++i) {{
                qp[i] = q[i];
                qm[i] = q[i];
            }}
            qp[j] += {t(1e-7)};
            qm[j] -= {t(1e-7)};
            {P}_angles(qp, th, dd);
            {P}_wrist_point(th, dd, pp);
            {P}_angles(qm, th, dd);
            {P}_wrist_point(th, dd, pm);
            for (i = 0; i < 3; ++i) {{
                J[i][j] = (pp[i] - pm[i]) / (2.0 * {t(1e-7)});
            }}
        }}
        det = J[0][0] * (J[1][1] * J[2][2] - J[1][2] * J[2][1]) - J[0][1] * (J[1][0] * J[2][2] - J[1][2] * J[2][0])
            + J[0][2] * (J[1][0] * J[2][1] - J[1][1] * J[2][0]);
        if (det == 0.0) {{
            break;
        }}
        /* Cramer's rule */
        dq[0] = (e[0] * (J[1][1] * J[2][2] - J[1][2] * J[2][1]) - J[0][1] * (e[1] * J[2][2] - J[1][2] * e[2])
                 + J[0][2] * (e[1] * J[2][1] - J[1][1] * e[2])) / det;
        dq[1] = (J[0][0] * (e[1] * J[2][2] - J[1][2] * e[2]) - e[0] * (J[1][0] * J[2][2] - J[1][2] * J[2][0])
                 + J[0][2] * (J[1][0] * e[2] - e[1] * J[2][0])) / det;
        dq[2] = (J[0][0] * (J[1][1] * e[2] - e[1] * J[2][1]) - J[0][1] * (J[1][0] * e[2] - e[1] * J[2][0])
                 + e[0] * (J[1][0] * J[2][1] - J[1][1] * J[2][0])) / det;
        for (i = 0; i < 3; ++i) {{
            q[i] += dq[i];
        }}
    }}
    return err;
}}

@@CHECK_END@@
/* Lecture 5, the wrist: every (th4, th5, th6) with Rz(th4)Rx(al4)Rz(th5)Rx(al5)Rz(th6) = R3^T R06,
   R3 = Rz(th1)Rx(al1)Rz(th2)Rx(al2)Rz(th3)Rx(al3). out[k] = rotation angles, flip[k] = 0 no flip /
   1 flip / 2 wrist singular (axes 4 and 6 aligned: th4 = q4_ref + offset, flagged degenerate). */
static int {P}_wrist(const double th[3], const double R[9], double q4_ref, double out[2][3], int flip[2]{fold_arg})
{{
    double mx = R[2], my = R[5], mz = R[8], ex = R[0], ey = R[3], ez = R[6];
    double nx = 0.0, ny = 0.0, nz = 1.0, c, s, x, row0, row1, rho, c5, s5, am, ar, sg;
    const double yp_c = {lit(-ca4 * sa5)}, yp_0 = {lit(-sa4 * ca5)}, b_c = {lit(sa4 * ca5)}, b_0 = {lit(ca4 * sa5)};
    double yp, b;
    {fold_decl}
    /* m = R3^T z6 and e = R3^T x6 */
{chr(10).join(rots_m)}
    /* n4 = R3 e3: axis 4 in frame 0' */
{chr(10).join(rots_n)}
    row0 = R[0] * nx + R[3] * ny + R[6] * nz;
    row1 = R[1] * nx + R[4] * ny + R[7] * nz;
    rho = sqrt(mx * mx + my * my);  /* |sin| of the angle between axes 4 and 6 */
{c5s5}
    if (rho <= {t(1e-10)}) {{
        const double th4 = q4_ref + {lit(th0[3])};
        const double gamma = atan2({gamma_ca4} * s5, c5);
        const double sk = mz > 0.0 ? 1.0 : -1.0;
        out[0][0] = th4;
        out[0][1] = atan2(s5, c5);
        out[0][2] = sk * (atan2(ey, ex) - th4 - gamma);
        flip[0] = 2;
        return 1;
    }}
    am = atan2(my, mx);
    ar = atan2(row1, row0);
    yp = yp_c * c5 + yp_0;
    b = b_c * c5 + b_0;
    for (i = 0; i < 2; ++i) {{
        sg = i == 0 ? s5 : -s5;
        out[i][0] = am - atan2(yp, {lit(sa5)} * sg);
        out[i][1] = atan2(sg, c5);
        out[i][2] = atan2(b, {lit(sa4)} * sg) - ar;
        if (rho < {lit(1e-4)}) {{
            /* near the singularity th4 and th6 are each taken from vectors of length rho (their rounding / rho
               off), their sum from the whole rotation: th6 from what th4 and th5 leave of it */
            double x6 = ex, y6 = ey, z6 = ez, c6 = cos(out[i][0]), s6 = sin(out[i][0]);
            x = c6 * x6 + s6 * y6;
            y6 = c6 * y6 - s6 * x6;
            x6 = x;
            x = {lit(ca4)} * y6 + {lit(sa4)} * z6;
            z6 = {lit(ca4)} * z6 - {lit(sa4)} * y6;
            y6 = x;
            c6 = cos(out[i][1]);
            s6 = sin(out[i][1]);
            x = c6 * x6 + s6 * y6;
            y6 = c6 * y6 - s6 * x6;
            x6 = x;
            y6 = {lit(ca5)} * y6 + {lit(sa5)} * z6;
            out[i][2] = atan2(y6, x6);
        }}
        flip[i] = (sg * {lit(kk)} > 0.0 ? 0 : 1){fold_add};
        if (s5 == 0.0) {{
            return 1;
        }}
    }}
    return 2;
}}
"""
    a, rest = text.split("@@CHECK_START@@")
    mid, b = rest.split("@@CHECK_END@@")
    if not quartic:  # the check and polish are for the quartic's numerical roots only
        mid = ""
    return a + mid + b


_MONOMIALS: dict[str, list[Val]] = {
    "RR-quartic": ["r * r", "r", "h * h", "h", 1.0], "RR-a1": ["r", 1.0], "RR-s1": ["h", 1.0],
    "RP-quartic": ["r", "h * h", "h", 1.0], "RP-c1": ["h", 1.0],
    "PR-quartic": ["X * X", "yp * yp", "yp", 1.0], "PR-c1": ["yp", 1.0], "PP": ["X", 1.0]}


def _pieper_polynomial(e: _Emitter, sv: PieperConstants, T06: Pose) -> tuple[str, list[Val]]:
    """C of the wrist centre W, its invariants (h, r; or x′, y′, X for a prismatic joint 1) and the
    joint-3 polynomial's coefficients pc[]; returns the C and W's three entries."""
    C = [list(row) for row in sv.C]
    w6 = [snap(x) for x in sv.w6]
    case, deg, kind3 = sv.case, sv.deg, sv.kinds[2]
    w = CWriter()
    R = T06.R
    W = [w.let(f"W{i}", lin([(w6[0], R[i][0]), (w6[1], R[i][1]), (w6[2], R[i][2]), (1.0, T06.p[i])]))
         for i in range(3)]
    for i in range(3):
        w.line(f"W[{i}] = {_c(W[i])};")
        for j in range(3):
            w.line(f"R06[{3 * i + j}] = {_c(R[i][j])};")
    if sv.kinds[0] == "R":
        w.comment("wrist centre W = T06 6W; Lecture 5: h = Wz - d1, r = Wx^2 + Wy^2 + h^2 (invariant under joint 1)")
        w.line(f"const double h = {_c(lin([(1.0, W[2])], -sv.d1))};")
        w.line(f"const double r = {_c(W[0])} * {_c(W[0])} + {_c(W[1])} * {_c(W[1])} + h * h;")
    else:
        c0, s0 = math.cos(sv.th0[0]), math.sin(sv.th0[0])
        w.comment("wrist centre W = T06 6W; prismatic joint 1: (x', y') = W in frame 0' turned by th1's offset")
        w.line(f"const double xp = {_c(lin([(c0, W[0]), (s0, W[1])]))};")
        w.line(f"const double yp = {_c(lin([(-s0, W[0]), (c0, W[1])]))};")
        w.line(f"const double X = xp - {lit(sv.a1)};")
    w.comment(f"joint 3 from a polynomial of degree {deg} in {'u = tan(th3/2)' if kind3 == 'R' else 'd3'} "
              f"({case}): its coefficients are linear in these monomials of W")
    for j in range(deg + 1):
        terms: list[tuple[float, Val]] = [(C[m][j], mk) for m, mk in enumerate(_MONOMIALS[case])]
        w.line(f"pc[{j}] = {_c(lin(terms))};")
    return w.text(), W


def _pieper_joint3_roots(e: _Emitter, sv: PieperConstants) -> str:
    """C of the polynomial's real roots as joint-3 values x3s[] (the kernel's ``_roots``)."""
    P, t = e.P, e.tol
    deg, kind3 = sv.deg, sv.kinds[2]
    ang = "2.0 * atan(ts[i])" if kind3 == "R" else "ts[i]"
    extra = (f"""        if (dg < {deg}) {{
            x3s[nx3++] = {lit(math.pi)};  /* the root u = infinity (th3 = pi) of the degree-deficient polynomial */
        }}""" if kind3 == "R" else "")
    fold = e.fold and deg == 4
    near = ", tsn, &nn" if fold else ""
    roots_deg = (f""" else if (dg >= 3) {{
            nt = dg == 4 ? {P}_quartic_roots(pc, ts{near}) : -1;  /* the quartic in closed form (Ferrari) */
            if (nt < 0) {{
                nt = {P}_real_roots(pc, dg, ts, {t(1e-15)});  /* or numerically: real roots, increasing */{
                    chr(10) + "                nn = 0;  /* (no fold starts then)" + " */" if fold else ""}
            }}
        }}""" if deg == 4 else "")
    ang_n = "2.0 * atan(tsn[i])" if kind3 == "R" else "tsn[i]"
    fold_x3 = (f"""
        nreal = nx3;  /* the fold starts' joint-3 values after the real roots (robokit.kernels.closed_form._roots) */
        for (i = 0; i < (fold ? nn : 0); ++i) {{
            x3s[nx3++] = {ang_n};
        }}""" if fold else "")
    free3 = lit(sv.th0[2]) if kind3 == "R" else "0.0"
    return f"""    /* its real roots (robokit's _roots: trailing coefficients below 1e-11 of the largest dropped) */
    for (i = 0; i <= {deg}; ++i) {{
        scale = fabs(pc[i]) > scale ? fabs(pc[i]) : scale;
    }}
    if (scale == 0.0) {{
        x3s[nx3++] = {free3};  /* identically satisfied: joint 3 free, the documented choice q3 = 0 */
        degenerate = 1;
    }} else {{
        while (dg > 0 && fabs(pc[dg]) <= {t(1e-11)} * scale) {{
            --dg;
        }}
        if (dg == 1) {{
            ts[0] = -pc[0] / pc[1];
            nt = 1;
        }} else if (dg == 2) {{
            const double disc = pc[1] * pc[1] - 4.0 * pc[2] * pc[0];
            const double big = pc[1] * pc[1] > fabs(4.0 * pc[2] * pc[0]) ? pc[1] * pc[1] : fabs(4.0 * pc[2] * pc[0]);
            if (!(disc < -{t(1e-12)} * (big > {t(1e-300)} ? big : {t(1e-300)}))) {{
                const double sq = sqrt(disc > 0.0 ? disc : 0.0);
                const double qv = -0.5 * (pc[1] + (pc[1] >= 0.0 ? sq : -sq));
                if (qv != 0.0) {{
                    ts[0] = qv / pc[2];
                    ts[1] = pc[0] / qv;
                    nt = 2;
                }} else {{
                    ts[0] = 0.0;
                    nt = 1;
                }}
            }}
        }}{roots_deg}
        for (i = 0; i < nt; ++i) {{
            x3s[nx3++] = {ang};
        }}
{extra}{fold_x3}
    }}"""


def _pieper_joint2_revolute(e: _Emitter, sv: PieperConstants, cs3: tuple[str, str]) -> str:
    """C of the candidates (q2, g1, g2, g3) for one joint-3 value when joint 2 is revolute: θ₂ from
    the r and h equations (RR-quartic, PR-quartic), from eq. b (RR-a1) or from eq. a (RR-s1, PR-c1)."""
    P, t = e.P, e.tol
    case, kind3, th0 = sv.case, sv.kinds[2], sv.th0
    ca1, sa1, a1, d2 = sv.ca[0], sv.sa[0], sv.a1, sv.d2
    if sv.kinds[0] == "R":
        assert sv.Ka is not None  # revolute joints 1 and 2
        ab = (f"""        const double F3 = {_f([(1.0, "f3")], d2)};
        const double ra = r - ({_c(_val(sv.Ka, kind3, "x3", *cs3))}), rb = {_f([(1.0, "h"), (-ca1, "F3")])};""")
        sa_, sb_ = 2.0 * a1, sa1
    else:
        ab = (f"""        const double F3 = {_f([(1.0, "f3")], d2)};
        const double ra = X, rb = {_f([(1.0, "yp"), (sa1, "F3")])};""")
        sa_, sb_ = 1.0, ca1
    if case in ("RR-quartic", "PR-quartic"):
        th2 = f"""        if (f1 * f1 + f2 * f2 > {t(1e-24)} * {lit(sv.scale * sv.scale)}) {{
            const double A = ra / {lit(sa_)}, B = rb / {lit(sb_)};
            t2s[0] = atan2(f1 * B - f2 * A, f1 * A + f2 * B);
        }} else {{
            t2s[0] = {lit(th0[1])};
            degenerate = 1;
        }}
        nt2 = 1;"""
    elif case == "RR-a1":  # sb (F2 c2 + F1 s2) = rb
        th2 = f"        nt2 = {P}_trig_roots({_f([(sb_, 'f2')])}, {_f([(sb_, 'f1')])}, rb, {t(1e-10)}, t2s);"
    else:  # RR-s1, PR-c1: sa (F1 c2 - F2 s2) = ra
        th2 = f"        nt2 = {P}_trig_roots({_f([(sa_, 'f1')])}, {_f([(-sa_, 'f2')])}, ra, {t(1e-10)}, t2s);"
    return f"""{ab}
        double t2s[2];
        int nt2, i2;
        (void)ra;
        (void)rb;
{th2}
        if (nt2 < 0) {{
            t2s[0] = {lit(th0[1])};
            nt2 = 1;
            degenerate = 1;
        }}
        for (i2 = 0; i2 < nt2; ++i2) {{
            const double cc2 = cos(t2s[i2]), ss2 = sin(t2s[i2]);
            const double uu = ss2 * f1 + cc2 * f2;
            cq2[nc] = {_f([(1.0, "t2s[i2]")], -th0[1])};
            cg1[nc] = {_f([(1.0, "cc2 * f1"), (-1.0, "ss2 * f2")], a1)};
            cg2[nc] = {_f([(ca1, "uu"), (-sa1, "F3")])};
            cg3[nc] = {_f([(sa1, "uu"), (ca1, "F3")])};
            ++nc;
        }}"""


def _pieper_joint2_prismatic(e: _Emitter, sv: PieperConstants, cs3: tuple[str, str]) -> str:
    """C of the candidates (q2, g1, g2, g3) for one joint-3 value when joint 2 is prismatic: its
    offset D from the h equation (RP-quartic), from the r equation's quadratic (RP-c1) or from y′ (PP)."""
    t = e.tol
    case, kind3, d0 = sv.case, sv.kinds[2], sv.d0
    ca1, sa1, a1 = sv.ca[0], sv.sa[0], sv.a1
    assert sv.phi is not None  # prismatic joint 2
    pc1, pc2 = sv.phi
    pv = (f"""        const double p1 = {_c(_val(pc1, kind3, "x3", *cs3))};
        const double p2 = {_c(_val(pc2, kind3, "x3", *cs3))};
        double Ds[2];
        int nD = 0, iD;""")
    if case == "RP-quartic":
        dcode = f"        Ds[nD++] = (h - {lit(sa1)} * p2) / {lit(ca1)} - f3;"
    elif case == "RP-c1":  # D^2 + 2 f3 D + (a1^2 + |f|^2 + 2 a1 p1 - r) = 0
        dcode = f"""        {{
            const double nf2 = {_c(_val(sv.nf2, kind3, "x3", *cs3))};
            const double B = 2.0 * f3, C0 = {lit(a1 * a1)} + nf2 + {lit(2.0 * a1)} * p1 - r;
            const double disc = B * B - 4.0 * C0;
            const double big = B * B > fabs(4.0 * C0) ? B * B : fabs(4.0 * C0);
            if (!(disc < -{t(1e-12)} * (big > {t(1e-300)} ? big : {t(1e-300)}))) {{
                const double sq = sqrt(disc > 0.0 ? disc : 0.0);
                const double qv = -0.5 * (B + (B >= 0.0 ? sq : -sq));
                if (qv == 0.0) {{
                    Ds[nD++] = 0.0;
                }} else {{
                    Ds[nD++] = qv;
                    if (sq > 0.0) {{
                        Ds[nD++] = C0 / qv;
                    }}
                }}
            }}
        }}"""
    else:  # PP
        dcode = f"        Ds[nD++] = ({lit(ca1)} * p2 - yp) / {lit(sa1)} - f3;"
    return f"""{pv}
{dcode}
        for (iD = 0; iD < nD; ++iD) {{
            const double D = Ds[iD];
            cq2[nc] = {_f([(1.0, "D")], -d0[1])};
            cg1[nc] = {_f([(1.0, "p1")], a1)};
            cg2[nc] = {_f([(ca1, "p2"), (-sa1, "(f3 + D)")])};
            cg3[nc] = {_f([(sa1, "p2"), (ca1, "(f3 + D)")])};
            ++nc;
        }}"""


def _pieper_joint1(e: _Emitter, sv: PieperConstants, W: list[Val]) -> str:
    """C of q1: θ₁ by atan2 (a shoulder singularity when W is on axis 1), or d₁ for a prismatic joint 1."""
    t, th0, d0 = e.tol, sv.th0, sv.d0
    if sv.kinds[0] == "R":
        return f"""            if (sqrt(cg1[ic] * cg1[ic] + cg2[ic] * cg2[ic]) <= {t(1e-12)} * {lit(sv.scale)}) {{
                q123[0] = 0.0;
                singular1 = 1;
            }} else {{
                q123[0] = {_f([(1.0, "atan2(W[1], W[0])"), (-1.0, "atan2(cg2[ic], cg1[ic])")], -th0[0])};
            }}"""
    return f"            q123[0] = {_f([(1.0, _c(W[2])), (-1.0, 'cg3[ic]')], -d0[0])};"


def _pieper_accept(e: _Emitter, sv: PieperConstants) -> str:
    """C that checks a root of the quartic (a spurious one dropped, a close one polished); the
    closed-form roots of degree ≤ 2 need no check (an arm whose DH table would make them lose precision
    is solved by the calibrated path: robokit.ik.closed_form.ILL_DH)."""
    P, t = e.P, e.tol
    if sv.deg != 4:
        return "            /* closed-form roots (degree <= 2): the back-substitution is exact */"
    return f"""            err = {P}_wrist_error(q123, W);
            if (err > {t(1e-12)} * {lit(sv.scale)}) {{
                if (err > {t(1e-5)} * {lit(sv.scale)}) {{
                    continue;  /* a spurious root */
                }}
                err = {P}_polish(q123, W);
                if (err > {t(1e-11)} * {lit(sv.scale)}) {{
                    continue;
                }}
            }}"""


def _pieper_labels(sv: PieperConstants) -> tuple[str, str]:
    """C of the shoulder and elbow label indices si, ei of one position branch."""
    if sv.kinds[0] == "R":
        shoulder = "            si = singular1 ? 2 : (cos(th[0]) * W[0] + sin(th[0]) * W[1] >= 0.0 ? 0 : 1);"
    else:
        shoulder = "            si = 0;"
    if sv.kinds[2] == "P":
        elbow = f"            ei = {_f([(1.0, 'q123[2]')], sv.d0[2])} >= 0.0 ? 0 : 1;"
    else:
        a2f = sv.a2 if sv.a2 != 0.0 else 1.0
        elbow = (f"            ei = {_f([(sv.v[0] * a2f, 'sin(th[2])'), (sv.v[1] * a2f, 'cos(th[2])')])} > 0.0 ? 0 : 1;"
                 "  /* elbow down / up */")
    return shoulder, elbow


def _pieper(e: _Emitter, T06: Pose) -> str:
    """Body of the Pieper solve (the kernel's ``pieper_position`` then the wrist): rows[], lab[], deg[], nr."""
    P = e.P
    sv = e.k.pieper
    assert sv is not None  # the spherical wrist's constants
    th0, kind3 = sv.th0, sv.kinds[2]
    body, W = _pieper_polynomial(e, sv, T06)
    cs3 = ("c3", "s3") if kind3 == "R" else ("", "")
    fvals = [f"        const double {name} = {_c(_val(coef, kind3, 'x3', *cs3))};"
             for name, coef in (("f1", sv.f[0]), ("f2", sv.f[1]), ("f3", sv.f[2]))]
    cands = _pieper_joint2_revolute(e, sv, cs3) if sv.kinds[1] == "R" else _pieper_joint2_prismatic(e, sv, cs3)
    shoulder, elbow = _pieper_labels(sv)
    q3 = _f([(1.0, "x3")], -th0[2]) if kind3 == "R" else "x3"
    accept = _pieper_accept(e, sv)
    if e.fold:  # fold starts (robokit.kernels.closed_form.FOLD_STARTS): flagged 3, their wrist code less 3
        # nreal: the joint-3 values before the fold positions' (all of them until the quartic's roots set it)
        if sv.deg == 4:
            decl = "\n    double tsn[2];\n    int nn = 0, nreal = 1 << 30;\n    (void)tsn;"
            accept = "            if (!fpos) {\n" + "\n".join("    " + ln for ln in accept.splitlines()) + "\n            }"
        else:
            decl = "\n    const int nreal = 1 << 30;  /* (no fold positions: no quartic) */"
        fold_pos = "            const int fpos = i3 >= nreal;  /* a fold position: unchecked */\n"
        assert e.k.calibrated is not None  # (the fold starts are the calibrated arm's)
        fc = int(e.k.calibrated["fold_code"])
        wrist = f"nw = {P}_wrist(th, R06, ref, wr, fl, fold ? 1 + fpos : 0);"
        rowflags = f"""                const int fs = fpos || fl[iw] >= {fc};
                const int wc = fl[iw] >= {fc} ? fl[iw] - {fc} : fl[iw];
                lab[nr] = {e.label_index("si", "ei", "wc")};
                deg[nr] = fs ? 3 : (wc == 2 || degenerate || singular1);"""
    else:
        decl, fold_pos = "", ""
        wrist = f"nw = {P}_wrist(th, R06, ref, wr, fl);"
        rowflags = f"""                lab[nr] = {e.label_index("si", "ei", "fl[iw]")};
                deg[nr] = fl[iw] == 2 || degenerate || singular1;"""
    return f"""    {{
    double pc[5], ts[5], x3s[6], W[3], R06[9];
    double scale = 0.0;
    int dg = {sv.deg}, nt = 0, nx3 = 0, degenerate = 0, i, i3;{decl}
{body}
    (void)W;
{_pieper_joint3_roots(e, sv)}
    /* every joint-3 value: joints 2 and 1 by back-substitution, then the wrist's two branches */
    for (i3 = 0; i3 < nx3; ++i3) {{
        const double x3 = x3s[i3];
        const double c3 = cos(x3), s3 = sin(x3);
        double cq2[2], cg1[2], cg2[2], cg3[2];
        int nc = 0, ic;
{chr(10).join(fvals)}
        (void)c3;
        (void)s3;
        (void)f1;
        (void)f2;
        (void)f3;
        (void)cg1;
        (void)cg2;
        (void)cg3;
{cands}
        for (ic = 0; ic < nc; ++ic) {{
            double q123[3], err = 0.0, th[3], dd[3], wr[2][3];
            int singular1 = 0, fl[2], nw, iw, si, ei;
{fold_pos}{_pieper_joint1(e, sv, W)}
            q123[1] = cq2[ic];
            q123[2] = {q3};
            (void)err;
{accept}
            {P}_angles(q123, th, dd);
{shoulder}
{elbow}
            {wrist}
            for (iw = 0; iw < nw && nr < {_RAW}; ++iw) {{
                rows[nr][0] = q123[0];
                rows[nr][1] = q123[1];
                rows[nr][2] = q123[2];
                rows[nr][3] = {_f([(1.0, "wr[iw][0]")], -th0[3])};
                rows[nr][4] = {_f([(1.0, "wr[iw][1]")], -th0[4])};
                rows[nr][5] = {_f([(1.0, "wr[iw][2]")], -th0[5])};
{rowflags}
                ++nr;
            }}
            (void)singular1;
        }}
    }}
    }}
"""


def _f(terms: list[tuple[float, str]], const: float = 0.0) -> str:
    """Σ cₖ·xₖ + const as folded C (no ``0.0 * x``, no ``- 0.0``)."""
    return _c(lin([(c, x) for c, x in terms], const))


def _c(v: Val) -> str:
    return lit(v) if isinstance(v, float) else v


def _parallel_free_helpers(e: _Emitter) -> str:
    """``NAME_free_t6`` of a calibrated three-parallel-axes arm (robokit.kernels.closed_form._free_t6 and
    ``_parallel_plane``, in the same steps): the theta6 at which the elbow comes nearest reaching."""
    k, P = e.k, e.P
    sv = k.parallel
    assert sv is not None and k.calibrated is not None
    ca1, sa1, ca5, sa5 = sv.ca[0], sv.sa[0], sv.ca[4], sv.sa[4]
    n, iters = int(k.calibrated["free_samples"]), int(k.calibrated["free_iterations"])
    return f"""
/* frame 4's origin in the plane of the parallel axes for th1, th5, th6 given by their cosines and sines */
static void {P}_plane(const double R[9], const double p[3], double c1, double s1, double c5, double s5, double c6,
                      double s6, double *x, double *y)
{{
    double ox = {lit(-sv.a4)}, oy = 0.0, oz = 0.0, tmp, O0, O1, O2;
    tmp = c5 * ox + s5 * oy; oy = -s5 * ox + c5 * oy; ox = tmp; oz = oz - {lit(sv.d5)};
    ox = ox - {lit(sv.a5)}; tmp = {lit(ca5)} * oy + {lit(sa5)} * oz; oz = {lit(-sa5)} * oy + {lit(ca5)} * oz; oy = tmp;
    tmp = c6 * ox + s6 * oy; oy = -s6 * ox + c6 * oy; ox = tmp; oz = oz - {lit(sv.d6)};
    O0 = p[0] + R[0] * ox + R[1] * oy + R[2] * oz - {lit(sv.a1)} * c1;
    O1 = p[1] + R[3] * ox + R[4] * oy + R[5] * oz - {lit(sv.a1)} * s1;
    O2 = p[2] + R[6] * ox + R[7] * oy + R[8] * oz - {lit(sv.d1)};
    *x = c1 * O0 + s1 * O1;
    *y = -s1 * {lit(ca1)} * O0 + c1 * {lit(ca1)} * O1 + {lit(sa1)} * O2;
}}

/* |x^2 + y^2 - a2^2 - a3^2| at th6 = t, x and y affine in (cos t, sin t) */
static double {P}_free_gap(const double g[6], double t)
{{
    const double c = cos(t), s = sin(t);
    const double x = g[0] + g[1] * c + g[2] * s, y = g[3] + g[4] * c + g[5] * s;
    return fabs(x * x + y * y - {lit(sv.a2 * sv.a2 + sv.a3 * sv.a3)});
}}

/* the calibrated arm's theta6 where its wrist is near its singularity: where the elbow comes nearest
   reaching (the least of {n} equally spaced values, then {iters} golden-section steps within one spacing) */
static double {P}_free_t6(const double R[9], const double p[3], double c1, double s1, double c5, double s5)
{{
    double x0, y0, xp, yp, xh, yh, g[6], best = 0.0, tb = 0.0, lo, hi;
    int k;
    {P}_plane(R, p, c1, s1, c5, s5, 1.0, 0.0, &x0, &y0);
    {P}_plane(R, p, c1, s1, c5, s5, -1.0, 0.0, &xp, &yp);
    {P}_plane(R, p, c1, s1, c5, s5, 0.0, 1.0, &xh, &yh);
    g[0] = 0.5 * (x0 + xp);
    g[1] = 0.5 * (x0 - xp);
    g[2] = xh - g[0];
    g[3] = 0.5 * (y0 + yp);
    g[4] = 0.5 * (y0 - yp);
    g[5] = yh - g[3];
    for (k = 0; k < {n}; ++k) {{
        const double th = (double)k * {lit(2.0 * math.pi / n)} - {lit(math.pi)};
        const double f = {P}_free_gap(g, th);
        if (k == 0 || f < best) {{
            best = f;
            tb = th;
        }}
    }}
    lo = tb - {lit(2.0 * math.pi / n)};
    hi = tb + {lit(2.0 * math.pi / n)};
    for (k = 0; k < {iters}; ++k) {{
        const double a = hi - {lit(0.5 * (math.sqrt(5.0) - 1.0))} * (hi - lo), b = lo + {lit(0.5 * (math.sqrt(5.0) - 1.0))} * (hi - lo);
        if ({P}_free_gap(g, a) <= {P}_free_gap(g, b)) {{
            hi = b;
        }} else {{
            lo = a;
        }}
    }}
    return 0.5 * (lo + hi);
}}
"""


def _parallel(e: _Emitter, T06: Pose) -> str:
    """Body of the three-parallel-axes solve (UR family)."""
    k, P, t = e.k, e.P, e.tol
    sv = k.parallel
    assert sv is not None  # the three-parallel-axes constants
    ca, sa = list(sv.ca), list(sv.sa)
    ca1, sa1, ca4, sa4, ca5, sa5 = ca[0], sa[0], ca[3], sa[3], ca[4], sa[4]
    s2, sig = sv.s2, sv.sig
    a1, a2, a3, a4, a5 = sv.a1, sv.a2, sv.a3, sv.a4, sv.a5
    d1, d5, d6, KW = sv.d1, sv.d5, sv.d6, sv.KW
    w6 = [snap(x) for x in sv.w6]
    th0 = list(sv.th0)
    right = ca4 == 0.0 and ca5 == 0.0
    w = CWriter()
    R, p = T06.R, T06.p
    W = [w.let(f"W{i}", lin([(w6[0], R[i][0]), (w6[1], R[i][1]), (w6[2], R[i][2]), (1.0, p[i])])) for i in range(3)]
    body = w.text()
    if right:
        t5 = f"""            const double c5r = -utz / {lit(sa4 * sa5)};
            if (rho > {t(1e-10)}) {{
                t5s[0] = atan2(rho, c5r);
                t5s[1] = atan2(-rho, c5r);
                nt5 = 2;
            }} else {{
                t5s[0] = atan2(0.0, c5r);
                nt5 = 1;
            }}"""
    else:
        t5 = f"""            nt5 = {P}_trig_roots({lit(-sa4 * sa5)}, 0.0, utz - {lit(ca4 * ca5)}, {t(1e-10)}, t5s);
            if (nt5 < 0) {{
                nt5 = 0;
            }}"""
    r = [[_c(x) for x in row] for row in R]
    pp = [_c(x) for x in p]
    if e.fold:  # the calibrated arm's elbow fold starts (robokit.kernels.closed_form._parallel_complete)
        assert k.calibrated is not None  # (the fold starts are the calibrated arm's)
        elbow = f"""            if (fabs(c3) > 1.0 + {t(1e-10)}) {{
                if (!fold || fabs(c3) - 1.0 > {lit(float(k.calibrated["fold_starts"]))}) {{
                    continue;
                }}
                fs = 1;  /* the elbow just short of reaching: two starts, th3 = +-sqrt(2 short) from its fold */
                s3a = sqrt(2.0 * (fabs(c3) - 1.0));
                c3 = c3 > 0.0 ? 1.0 : -1.0;
            }} else {{
                c3 = c3 > 1.0 ? 1.0 : (c3 < -1.0 ? -1.0 : c3);
                s3a = sqrt(1.0 - c3 * c3 > 0.0 ? 1.0 - c3 * c3 : 0.0);
            }}"""
    else:
        elbow = f"""            if (fabs(c3) > 1.0 + {t(1e-10)}) {{
                continue;
            }}
            c3 = c3 > 1.0 ? 1.0 : (c3 < -1.0 ? -1.0 : c3);
            s3a = sqrt(1.0 - c3 * c3 > 0.0 ? 1.0 - c3 * c3 : 0.0);"""
    compute = f"""            {{
                const double c6 = cos(t6), s6 = sin(t6);
                /* x4 in frame 6: Rz(-th6) Rx(-al5) Rz(-th5) e1 */
                gx0 = c5;
                gy0 = {lit(-ca5)} * s5;
                gz0 = {lit(sa5)} * s5;
                gx = c6 * gx0 + s6 * gy0;
                gy = -s6 * gx0 + c6 * gy0;
                gz = gz0;
                /* frame 4's origin in frame 6 */
                ox = {lit(-a4)};
                oy = 0.0;
                oz = 0.0;
                tmp = c5 * ox + s5 * oy; oy = -s5 * ox + c5 * oy; ox = tmp; oz = oz - {lit(d5)};
                ox = ox - {lit(a5)}; tmp = {lit(ca5)} * oy + {lit(sa5)} * oz; oz = {lit(-sa5)} * oy + {lit(ca5)} * oz; oy = tmp;
                tmp = c6 * ox + s6 * oy; oy = -s6 * ox + c6 * oy; ox = tmp; oz = oz - {lit(d6)};
            }}
            X0 = {r[0][0]} * gx + {r[0][1]} * gy + {r[0][2]} * gz;
            X1 = {r[1][0]} * gx + {r[1][1]} * gy + {r[1][2]} * gz;
            X2 = {r[2][0]} * gx + {r[2][1]} * gy + {r[2][2]} * gz;
            O0 = {pp[0]} + {r[0][0]} * ox + {r[0][1]} * oy + {r[0][2]} * oz - {lit(a1)} * c1;
            O1 = {pp[1]} + {r[1][0]} * ox + {r[1][1]} * oy + {r[1][2]} * oz - {lit(a1)} * s1;
            O2 = {pp[2]} + {r[2][0]} * ox + {r[2][1]} * oy + {r[2][2]} * oz - {lit(d1)};
            /* the planar 3R arm in the frame after X1: angle phi = th2 + th3 + th4, 2-link (a2, a3) */
            phi = atan2(-s1 * {lit(ca1)} * X0 + c1 * {lit(ca1)} * X1 + {lit(sa1)} * X2, c1 * X0 + s1 * X1);
            x = c1 * O0 + s1 * O1;
            y = -s1 * {lit(ca1)} * O0 + c1 * {lit(ca1)} * O1 + {lit(sa1)} * O2;
            c3 = (x * x + y * y - {lit(a2 * a2 + a3 * a3)}) / {lit(2.0 * a2 * a3)};
"""
    if e.fold:  # where the elbow misses and the wrist is near its singularity, theta6 again (_free_t6)
        assert k.calibrated is not None
        inner = "".join("    " + line + "\n" if line else "\n" for line in compute.splitlines())
        rm = ", ".join(r[i][j] for i in range(3) for j in range(3))
        compute = f"""            for (attempt = 0;; ++attempt) {{  /* (twice at most: the test below breaks at attempt 1) */
{inner}                if (attempt == 1 || fabs(c3) <= 1.0 + {t(1e-10)} || !fold
                    || fabs(c3) - 1.0 <= {lit(float(k.calibrated["fold_starts"]))} || rho >= {lit(float(k.calibrated["free_wrist"]))}) {{
                    break;
                }}
                {{  /* the elbow misses by more than the fold starts' window, the wrist near its singularity:
                    theta6 where the elbow comes nearest reaching, its rows fold starts */
                    const double Rm[9] = {{{rm}}};
                    const double pm[3] = {{{pp[0]}, {pp[1]}, {pp[2]}}};
                    t6 = {P}_free_t6(Rm, pm, c1, s1, c5, s5);
                    fs = 1;
                }}
            }}
"""
    ta, tb, tc = f"{lit(-sa1)} * {_c(W[1])}", f"{lit(sa1)} * {_c(W[0])}", f"{lit(KW)} - {lit(ca1)} * ({_c(W[2])} - {lit(d1)})"
    if e.fold:  # the calibrated arm's shoulder fold starts (robokit.kernels.closed_form._shoulder_folds)
        assert k.calibrated is not None  # (the fold starts are the calibrated arm's)
        shoulder = f"""
    int i1, f1 = 0;
    if (nt1 <= 0 && fold) {{  /* no th1: the wrist centre just inside the shoulder offset's cylinder? */
        const double fa = {ta}, fb = {tb}, fcc = {tc};
        const double fr = sqrt(fa * fa + fb * fb);
        if (fr >= {t(1e-150)} && fabs(fcc) / fr - 1.0 <= {lit(float(k.calibrated["fold_starts"]))}) {{
            const double gap = fabs(fcc) / fr - 1.0;
            const double th = fcc > 0.0 ? atan2(fb, fa) : atan2(-fb, -fa);
            const double dd = sqrt(2.0 * (gap > 0.0 ? gap : 0.0));
            t1s[0] = {P}_wrap(th + dd);  /* two starts, th1 = +-sqrt(2 gap) from its fold */
            t1s[1] = {P}_wrap(th - dd);
            nt1 = 2;
            f1 = 1;
        }}
    }}"""
    else:
        shoulder = """
    int i1;"""
    return f"""    {{
{body}
    double t1s[2];
    int nt1 = {P}_trig_roots({ta}, {tb}, {tc}, {t(1e-10)}, t1s);{shoulder}
    /* Lecture 5, three parallel axes: th1 from W's coordinate along the parallel axes */
    for (i1 = 0; i1 < nt1; ++i1) {{
        const double t1 = t1s[i1];
        const double c1 = cos(t1), s1 = sin(t1);
        const int si = ({_c(W[0])} * c1 + {_c(W[1])} * s1) * {lit(sa1)} >= 0.0 ? 0 : 1;
        const double ux = {lit(sa1)} * s1, uy = {lit(-sa1)} * c1, uz = {lit(ca1)};
        /* u seen from the tool: th5 (wrist flip / no flip), th6 */
        const double utx = {lit(sig)} * ({r[0][0]} * ux + {r[1][0]} * uy + {r[2][0]} * uz);
        const double uty = {lit(sig)} * ({r[0][1]} * ux + {r[1][1]} * uy + {r[2][1]} * uz);
        const double utz = {lit(sig)} * ({r[0][2]} * ux + {r[1][2]} * uy + {r[2][2]} * uz);
        const double rho = sqrt(utx * utx + uty * uty);
        double t5s[2];
        int nt5, i5;
        {{
{t5}
        }}
        for (i5 = 0; i5 < nt5; ++i5) {{
            const double t5 = t5s[i5];
            const double c5 = cos(t5), s5 = sin(t5);
            const double vx = s5 * {lit(sa4)}, vy = {lit(ca5 * sa4)} * c5 + {lit(sa5 * ca4)};
            double t6, gx0, gy0, gz0, gx, gy, gz, ox, oy, oz, tmp, X0, X1, X2, O0, O1, O2, phi, x, y, c3, s3a, base;
            int degenerate, wi, k3, n3{", fs = f1, attempt" if e.fold else ""};
            if (rho <= {t(1e-10)}) {{
                t6 = {_f([(1.0, "ref")], th0[5])};
                degenerate = 1;
            }} else {{
                t6 = atan2(vy, vx) - atan2(uty, utx);
                degenerate = 0;
            }}
{compute}{elbow}
            wi = degenerate ? 2 : (s5 * {lit(sa4 * sa5)} > 0.0 ? 0 : 1);
            base = atan2(y, x);
            n3 = s3a > 0.0 ? 2 : 1;
            for (k3 = 0; k3 < n3 && nr < {_RAW}; ++k3) {{
                const double s3 = k3 == 0 ? s3a : -s3a;
                const double psi = atan2(s3, c3);
                const double t2 = base - atan2({lit(a3)} * s3, {lit(a2)} + {lit(a3)} * c3);
                const double t3 = {lit(s2)} * psi, t4 = {lit(sig)} * (phi - t2 - psi);
                const int ei = {lit(a2 * a3)} * s3 > 0.0 ? 0 : 1;
                rows[nr][0] = {_f([(1.0, "t1")], -th0[0])};
                rows[nr][1] = {_f([(1.0, "t2")], -th0[1])};
                rows[nr][2] = {_f([(1.0, "t3")], -th0[2])};
                rows[nr][3] = {_f([(1.0, "t4")], -th0[3])};
                rows[nr][4] = {_f([(1.0, "t5")], -th0[4])};
                rows[nr][5] = {_f([(1.0, "t6")], -th0[5])};
                lab[nr] = {e.label_index("si", "ei", "wi")};
                deg[nr] = {"fs ? 3 : degenerate" if e.fold else "degenerate"};
                ++nr;
            }}
        }}
    }}
    }}
"""


class _GeneralEmitter(_Emitter):
    """``NAME_ik`` of a general 6R arm (:mod:`robokit.codegen.ik_general`)."""

    def __init__(self, k: IKConstants, prefix: str, tol: _Tol) -> None:
        self.k, self.P, self.tol = k, prefix, tol
        self.labels = ik_general.general_6r_labels()

    def declare(self) -> list[str]:
        return ik_general.declare(self.P)

    def code(self) -> IKCode:
        k, P = self.k, self.P
        w = CWriter()
        T06 = self.target(w)
        solve = ik_general.emit_general_6r(self, w.text(), T06)
        n_max = ik_general.MAX_SOLUTIONS_6R
        src = [self.tables(), ik_general.routines(), ik_general.tables(k, P), self.finish(n_max, repeats=False)]
        if k.arm_polish is not None:
            src.append(ik_general.arm_polish_code(k, P, self.tol))
        src.append(f"""
/* every closed-form solution of the general 6R arm, see {P}.h */
int {P}_ik_ws(const double T[16], double wrist_ref, double q[{P}_MAX_SOLUTIONS * {P}_N], int info[4 * {P}_MAX_SOLUTIONS],
              {P}_ik_workspace *ws)
{{
    double (*rows)[6] = (double (*)[6])q;  /* in place: {P}_finish reads row r before it writes row <= r */
    int lab[{n_max}], deg[{n_max}];
    int nr = 0, ir;
    (void)wrist_ref;  /* no free joint in the general case */
{solve}    (void)ir;
    return {P}_finish((const double (*)[6])rows, lab, deg, nr, q, info);
}}

int {P}_ik_ex(const double T[16], double wrist_ref, double q[{P}_MAX_SOLUTIONS * {P}_N], int info[4 * {P}_MAX_SOLUTIONS])
{{
    {P}_ik_workspace ws;  /* on the stack: {P}_ik_ws takes the caller's */
    return {P}_ik_ws(T, wrist_ref, q, info, &ws);
}}

int {P}_ik(const double T[16], double q[{P}_MAX_SOLUTIONS * {P}_N])
{{
    return {P}_ik_ex(T, 0.0, q, 0);
}}
""")
        return IKCode(True, ik_general.note(k), n_max, self.declare(), "\n".join(src), self.labels)
