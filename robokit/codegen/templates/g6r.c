/* robokit: the general 6R closed-form IK, robot-independent part (see g6r.h). Each routine is
   the C of one step of robokit.ik.general_6r / robokit.kernels.general_6r (same names, same
   order), or a small dense linear-algebra routine written from the textbook (Golub & Van Loan,
   Matrix Computations, 4th ed.: one-sided Jacobi SVD 8.6.3, Householder QR 5.2, LU with partial
   pivoting 3.4, Hessenberg reduction 7.4.3, Francis double-shift QR 7.5.5, balancing 7.5.7).
   Lengths are in units of the arm's scale. No allocation, no static state: the matrices live in
   the caller's workspace (g6r_work below, G6R_WORKSPACE_DOUBLES doubles), reused phase by phase,
   so that the whole call path fits a 12 KB RTOS stack with the workspace on it. */
#include <math.h>
#include <string.h>
#include "g6r.h"

/* The workspace. u is reused phase by phase (offsets in doubles):
   matrices: P u[0..405) r u[405..540) the target's map u[540..765) (its factors in u[0..450) first),
             the side tensor's levels u[765..840);
   pencil:   P, r; Q u[540..652) its Householder factors u[652..764) + u[764..772) N u[772..856);
             then Q's SVD in place, V u[652..716), 4 rows of Q's pseudo-inverse u[716..772);
             then Sigma u[540..702);
   companion: A's LU u[0..144), the 24 x 24 companion matrix u[144..720);
   deflation: L(i) in the companion matrix's first 12 rows, its null vectors u[0..96) (then
             rows of M u[0..128)), the invariant subspace's basis u[720..912);
   eigenvalues: the matrix, wr u[720..744), wi u[744..768), Householder vectors u[768..816);
   per eigenvalue: L(y) u[0..144), the polish's Jacobians and vectors u[144..300),
             fill_joint's u[300..332). */
typedef struct {
    double abc[3][6][9]; /* A, B, C of the 12 x 12 pencil: rows e and 6 + e (the same, times x_b) */
    double K[4][3][9];   /* rows 2, 5, 6, 7 of Q's pseudo-inverse times the three-joint side */
    double u[912];
} g6r_work;

enum { g6r_size_check = 1 / (int)(sizeof(g6r_work) == sizeof(double) * G6R_WORKSPACE_DOUBLES) };

/* ---------------------------------------------------------------- dense linear algebra */

/* One-sided Jacobi SVD (Hestenes; Golub & Van Loan 8.6.3) of the m x n row-major matrix a
   (overwritten): plane rotations make the columns mutually orthogonal, accumulated in v (n x n,
   row-major). Then the singular values are the column norms: the p-th largest is
   norms[order[p]], its left singular vector column order[p] of a divided by it, its right one
   column order[p] of v (nothing is moved). n <= 14. */
static void g6r_svd(int m, int n, double *a, double *v, double norms[14], int order[14])
{
    int sweep, p, q, i, rotated = 1;
    for (i = 0; i < n * n; ++i) {
        v[i] = 0.0;
    }
    for (i = 0; i < n; ++i) {
        v[i * n + i] = 1.0;
    }
    for (sweep = 0; sweep < 60 && rotated; ++sweep) {
        rotated = 0;
        for (p = 0; p < n - 1; ++p) {
            for (q = p + 1; q < n; ++q) {
                double al = 0.0, be = 0.0, ga = 0.0, zeta, t, c, s;
                for (i = 0; i < m; ++i) {
                    const double x = a[i * n + p], y = a[i * n + q];
                    al += x * x;
                    be += y * y;
                    ga += x * y;
                }
                if (ga == 0.0 || fabs(ga) <= 1e-15 * sqrt(al * be)) {
                    continue;
                }
                rotated = 1;
                /* the rotation that zeroes the (p, q) entry of the 2 x 2 Gram matrix */
                zeta = (be - al) / (2.0 * ga);
                t = (zeta >= 0.0 ? 1.0 : -1.0) / (fabs(zeta) + sqrt(1.0 + zeta * zeta));
                c = 1.0 / sqrt(1.0 + t * t);
                s = c * t;
                for (i = 0; i < m; ++i) {
                    const double x = a[i * n + p], y = a[i * n + q];
                    a[i * n + p] = c * x - s * y;
                    a[i * n + q] = s * x + c * y;
                }
                for (i = 0; i < n; ++i) {
                    const double x = v[i * n + p], y = v[i * n + q];
                    v[i * n + p] = c * x - s * y;
                    v[i * n + q] = s * x + c * y;
                }
            }
        }
    }
    for (p = 0; p < n; ++p) {
        double s2 = 0.0;
        for (i = 0; i < m; ++i) {
            s2 += a[i * n + p] * a[i * n + p];
        }
        norms[p] = sqrt(s2);
        order[p] = p;
    }
    for (p = 1; p < n; ++p) {  /* insertion sort, decreasing */
        const int o = order[p];
        q = p - 1;
        while (q >= 0 && norms[order[q]] < norms[o]) {
            order[q + 1] = order[q];
            --q;
        }
        order[q + 1] = o;
    }
}

/* The conditioning tests (sigma_min / sigma_max against a threshold) without vectors: Householder
   bidiagonalisation (Golub-Kahan; Golub & Van Loan 5.4.8), then Sturm counts of the Golub-Kahan
   tridiagonal [[0, B^T], [B, 0]] (zero diagonal, off-diagonals d1, e1, d2, ..., dn; its
   eigenvalues are +-sigma_i), which place the singular values to high relative accuracy (Demmel
   & Kahan 1990). The solver only compares the ratios with thresholds, so these routines answer
   the comparison (one or two counts) instead of computing the ratio. */
static double g6r_house(int n, const double *x, int stride, double *vv);
static int g6r_gk_count(const double *c, int len, double mu)
{
    /* the number of eigenvalues below mu of the len x len tridiagonal with zero diagonal and
       off-diagonal c (len - 1): the negative pivots of its LDL^T - mu I (Sylvester's law of inertia) */
    double q = -mu;
    int i, count = q < 0.0;
    for (i = 1; i < len; ++i) {
        if (q == 0.0) {
            q = -1e-300;
        }
        q = -mu - c[i - 1] * c[i - 1] / q;
        count += q < 0.0;
    }
    return count;
}

/* Householder bidiagonalisation of the m x n row-major a (overwritten), m >= n: c (2n - 1) the
   off-diagonal of the Golub-Kahan tridiagonal (d1, e1, d2, e2, ..., dn); returns a Gershgorin
   bound on sigma_max */
static double g6r_bidiagonal(int m, int n, double *a, double c[24])
{
    double vv[14], bound = 0.0;
    int k, i, j;
    for (k = 0; k < n; ++k) {
        /* left reflection: zero column k below the diagonal */
        double beta = g6r_house(m - k, a + k * n + k, n, vv);
        for (j = k; j < n; ++j) {
            double s = 0.0;
            for (i = k; i < m; ++i) {
                s += vv[i - k] * a[i * n + j];
            }
            s *= beta;
            for (i = k; i < m; ++i) {
                a[i * n + j] -= s * vv[i - k];
            }
        }
        c[2 * k] = a[k * n + k];
        if (k < n - 2) {
            /* right reflection: zero row k right of the superdiagonal */
            beta = g6r_house(n - k - 1, a + k * n + k + 1, 1, vv);
            for (i = k; i < m; ++i) {
                double s = 0.0;
                for (j = k + 1; j < n; ++j) {
                    s += a[i * n + j] * vv[j - k - 1];
                }
                s *= beta;
                for (j = k + 1; j < n; ++j) {
                    a[i * n + j] -= s * vv[j - k - 1];
                }
            }
        }
        if (k < n - 1) {
            c[2 * k + 1] = a[k * n + k + 1];
        }
    }
    for (k = 0; k < 2 * n - 1; ++k) {
        const double mu = fabs(c[k]) + (k + 1 < 2 * n - 1 ? fabs(c[k + 1]) : 0.0);
        bound = mu > bound ? mu : bound;
    }
    return bound;
}

/* whether sigma_min < tol * sigma_max for the m x n row-major matrix a (overwritten), m >= n,
   n <= 12, for two thresholds t1 <= t2: bit 0 of the result for t1, bit 1 for t2. sigma_max lies
   between the bidiagonal's largest entry and the Gershgorin bound: a Sturm count at t times either
   end decides, except when sigma_min lies between the two; then sigma_max is found by bisection to
   1e-7 relative and counted at. */
static int g6r_sv_below(int m, int n, double *a, double t1, double t2)
{
    double c[24], lo = 0.0, hi, smax = 0.0;
    const double bound = g6r_bidiagonal(m, n, a, c);
    const double ts[2] = {t1, t2};
    int k, it, out = 0;
    if (bound == 0.0) {
        return 3;
    }
    for (k = 0; k < 2 * n - 1; ++k) {  /* sigma_max >= every entry of the bidiagonal */
        lo = fabs(c[k]) > lo ? fabs(c[k]) : lo;
    }
    for (k = 0; k < 2; ++k) {
        if (g6r_gk_count(c, 2 * n, ts[k] * lo) - n >= 1) {
            out |= 1 << k;  /* sigma_min < t lo <= t sigma_max */
            continue;
        }
        if (g6r_gk_count(c, 2 * n, ts[k] * bound) - n == 0) {
            continue;  /* sigma_min >= t bound >= t sigma_max */
        }
        if (!(smax > 0.0)) {  /* the largest, to 1e-7 relative: #{sigma < mu} = count(mu) - n reaches n */
            double l = lo;
            hi = bound;
            for (it = 0; it < 100 && hi - l > 1e-7 * hi; ++it) {
                const double mid = 0.5 * (l + hi);
                if (g6r_gk_count(c, 2 * n, mid) - n >= n) {
                    hi = mid;
                } else {
                    l = mid;
                }
            }
            smax = hi;
        }
        if (g6r_gk_count(c, 2 * n, ts[k] * smax) - n >= 1) {
            out |= 1 << k;
        }
    }
    return out;
}

/* whether sigma_min > tol * sigma_max holds for sure (one Sturm count; 0 may be a false alarm) */
static int g6r_well_conditioned(int m, int n, double *a, double tol)
{
    double c[24];
    const double bound = g6r_bidiagonal(m, n, a, c);
    return bound > 0.0 && g6r_gk_count(c, 2 * n, tol * bound) - n == 0;
}

/* LU factorisation with partial pivoting (Golub & Van Loan 3.4) of the n x n row-major a, in
   place; piv[k] the row swapped with k. A zero pivot is replaced by a tiny one (the caller
   wants a null vector by inverse iteration, or has checked the conditioning). */
static void g6r_lu(int n, double *a, int *piv)
{
    int k, i, j;
    double big = 0.0;
    for (i = 0; i < n * n; ++i) {
        big = fabs(a[i]) > big ? fabs(a[i]) : big;
    }
    for (k = 0; k < n; ++k) {
        int p = k;
        double best = fabs(a[k * n + k]);
        for (i = k + 1; i < n; ++i) {
            if (fabs(a[i * n + k]) > best) {
                best = fabs(a[i * n + k]);
                p = i;
            }
        }
        piv[k] = p;
        if (p != k) {
            for (j = 0; j < n; ++j) {
                const double t = a[k * n + j];
                a[k * n + j] = a[p * n + j];
                a[p * n + j] = t;
            }
        }
        if (a[k * n + k] == 0.0) {
            a[k * n + k] = 1e-300 + 1e-18 * big;
        }
        for (i = k + 1; i < n; ++i) {
            const double l = a[i * n + k] / a[k * n + k];
            a[i * n + k] = l;
            for (j = k + 1; j < n; ++j) {
                a[i * n + j] -= l * a[k * n + j];
            }
        }
    }
}

/* solve (LU) x = b in place, LU and piv from g6r_lu */
static void g6r_lu_solve(int n, const double *lu, const int *piv, double *b)
{
    int i, j;
    for (i = 0; i < n; ++i) {
        const double t = b[piv[i]];
        b[piv[i]] = b[i];
        b[i] = t;
    }
    for (i = 0; i < n; ++i) {
        for (j = 0; j < i; ++j) {
            b[i] -= lu[i * n + j] * b[j];
        }
    }
    for (i = n - 1; i >= 0; --i) {
        for (j = i + 1; j < n; ++j) {
            b[i] -= lu[i * n + j] * b[j];
        }
        b[i] /= lu[i * n + i];
    }
}

/* A Householder vector (Golub & Van Loan 5.1.3): (I - beta v v^T) x = (+-|x|, 0, ..., 0), v[0] = 1 */
static double g6r_house(int n, const double *x, int stride, double *vv)
{
    double sigma = 0.0, mu, x0 = x[0], v0;
    int i;
    for (i = 1; i < n; ++i) {
        sigma += x[i * stride] * x[i * stride];
    }
    vv[0] = 1.0;
    for (i = 1; i < n; ++i) {
        vv[i] = x[i * stride];
    }
    if (sigma == 0.0) {
        return 0.0;
    }
    mu = sqrt(x0 * x0 + sigma);
    v0 = x0 <= 0.0 ? x0 - mu : -sigma / (x0 + mu);
    for (i = 1; i < n; ++i) {
        vv[i] /= v0;
    }
    return 2.0 * v0 * v0 / (sigma + v0 * v0);
}

/* the left null space of the 14 x 8 matrix q (row-major, overwritten): the last 6 columns of the
   orthogonal factor of its Householder QR (Golub & Van Loan 5.2.1), n (14 x 6, row-major);
   vs (8 x 14) and betas (8) hold the reflections */
static void g6r_left_null_space(double r[14 * 8], double n[14 * 6], double vs[8 * 14], double betas[8])
{
    int j, i, k, e;
    for (j = 0; j < 8; ++j) {
        double *vv = vs + 14 * j;
        const double beta = g6r_house(14 - j, r + j * 8 + j, 8, vv);
        betas[j] = beta;
        for (k = j; k < 8; ++k) {  /* r <- (I - beta v v^T) r on rows j.. */
            double s = 0.0;
            for (i = j; i < 14; ++i) {
                s += vv[i - j] * r[i * 8 + k];
            }
            s *= beta;
            for (i = j; i < 14; ++i) {
                r[i * 8 + k] -= s * vv[i - j];
            }
        }
    }
    /* columns 8..13 of H_0 H_1 ... H_7: apply the reflections to the unit vectors, last first */
    for (e = 0; e < 6; ++e) {
        double x[14];
        memset(x, 0, sizeof x);
        x[8 + e] = 1.0;
        for (j = 7; j >= 0; --j) {
            double s = 0.0;
            for (i = j; i < 14; ++i) {
                s += vs[14 * j + i - j] * x[i];
            }
            s *= betas[j];
            for (i = j; i < 14; ++i) {
                x[i] -= s * vs[14 * j + i - j];
            }
        }
        for (i = 0; i < 14; ++i) {
            n[i * 6 + e] = x[i];
        }
    }
}

/* Eigenvalues (wr + i wi) of the n x n row-major matrix h (destroyed), n <= 24: balancing by
   powers of 2 (Parlett-Reinsch; Golub & Van Loan 7.5.7), Householder reduction to upper
   Hessenberg form (7.4.3), then Francis double-shift QR steps (7.5.5) with deflation at small
   subdiagonal entries, on the active window only (eigenvalues are all we need). Returns 0, or
   -1 if the iteration did not converge. */
static int g6r_eigenvalues(int n, double *h, double *wr, double *wi, double scratch[48])
{
    double *vv = scratch, *sv = scratch + 24;
    int i, j, k, lo, hi, its, done = 0;
    /* balancing: D^-1 H D with D a diagonal of powers of 2 making row and column norms alike */
    while (!done) {
        done = 1;
        for (i = 0; i < n; ++i) {
            double c = 0.0, r = 0.0, f = 1.0, g, s;
            for (j = 0; j < n; ++j) {
                if (j != i) {
                    c += fabs(h[j * n + i]);
                    r += fabs(h[i * n + j]);
                }
            }
            if (c == 0.0 || r == 0.0 || !(c + r < HUGE_VAL)) {
                continue;  /* nothing to balance (or not finite: the QR below fails and says so) */
            }
            g = r / 2.0;
            s = c + r;
            while (c < g) {
                f *= 2.0;
                c *= 4.0;
            }
            g = r * 2.0;
            while (c >= g) {
                f /= 2.0;
                c /= 4.0;
            }
            if ((c + r) / f < 0.95 * s) {
                done = 0;
                for (j = 0; j < n; ++j) {
                    h[i * n + j] /= f;
                    h[j * n + i] *= f;
                }
            }
        }
    }
    /* Hessenberg form: Householder reflections from the left and the right */
    for (k = 0; k < n - 2; ++k) {
        const int len = n - k - 1;
        const double beta = g6r_house(len, h + (k + 1) * n + k, n, vv);
        if (beta == 0.0) {
            continue;
        }
        for (j = k; j < n; ++j) {  /* from the left, row by row (contiguous): s = beta v^T H */
            sv[j] = 0.0;
        }
        for (i = 0; i < len; ++i) {
            const double *row = h + (k + 1 + i) * n;
            for (j = k; j < n; ++j) {
                sv[j] += vv[i] * row[j];
            }
        }
        for (j = k; j < n; ++j) {
            sv[j] *= beta;
        }
        for (i = 0; i < len; ++i) {
            double *row = h + (k + 1 + i) * n;
            for (j = k; j < n; ++j) {
                row[j] -= sv[j] * vv[i];
            }
        }
        for (i = 0; i < n; ++i) {
            double s = 0.0;
            for (j = 0; j < len; ++j) {
                s += h[i * n + k + 1 + j] * vv[j];
            }
            s *= beta;
            for (j = 0; j < len; ++j) {
                h[i * n + k + 1 + j] -= s * vv[j];
            }
        }
        for (i = k + 2; i < n; ++i) {
            h[i * n + k] = 0.0;
        }
    }
    /* Francis double-shift QR on the window [lo, hi] */
    hi = n - 1;
    its = 0;
    while (hi >= 0) {
        /* deflation: the lowest l with h[l][l-1] negligible beside its neighbours (with zero
           diagonals, as in a companion matrix, beside the next subdiagonal entries), refined by
           the criterion of Ahues & Tisseur (1997) that also weighs h[l-1][l] */
        for (lo = hi; lo > 0; --lo) {
            const double sub = fabs(h[lo * n + lo - 1]);
            double tst = fabs(h[(lo - 1) * n + lo - 1]) + fabs(h[lo * n + lo]);
            if (sub <= 1e-300) {
                h[lo * n + lo - 1] = 0.0;
                break;
            }
            if (tst == 0.0) {
                tst = (lo - 2 >= 0 ? fabs(h[(lo - 1) * n + lo - 2]) : 0.0) + (lo + 1 < n ? fabs(h[(lo + 1) * n + lo]) : 0.0);
            }
            if (sub <= 2.220446049250313e-16 * tst) {
                const double sup = fabs(h[(lo - 1) * n + lo]);
                const double dd = fabs(h[(lo - 1) * n + lo - 1] - h[lo * n + lo]), hh = fabs(h[lo * n + lo]);
                const double ab = sub > sup ? sub : sup, ba = sub > sup ? sup : sub;
                const double aa = hh > dd ? hh : dd, bb = hh > dd ? dd : hh;
                const double ss = aa + ab;
                const double rhs = 2.220446049250313e-16 * (bb * (aa / ss));
                if (ba * (ab / ss) <= (rhs > 1e-300 ? rhs : 1e-300)) {
                    h[lo * n + lo - 1] = 0.0;
                    break;
                }
            }
        }
        if (lo == hi) {  /* a 1 x 1 block: a real eigenvalue */
            wr[hi] = h[hi * n + hi];
            wi[hi] = 0.0;
            --hi;
            its = 0;
        } else if (lo == hi - 1) {  /* a 2 x 2 block: two real or a complex pair */
            const double a = h[(hi - 1) * n + hi - 1], b = h[(hi - 1) * n + hi];
            const double c = h[hi * n + hi - 1], d = h[hi * n + hi];
            const double p = 0.5 * (a - d), disc = p * p + b * c;
            if (disc >= 0.0) {
                const double z = p + (p >= 0.0 ? sqrt(disc) : -sqrt(disc));
                wr[hi - 1] = d + z;
                wr[hi] = z != 0.0 ? d - b * c / z : d;
                wi[hi - 1] = wi[hi] = 0.0;
            } else {
                wr[hi - 1] = wr[hi] = d + p;
                wi[hi - 1] = sqrt(-disc);
                wi[hi] = -sqrt(-disc);
            }
            hi -= 2;
            its = 0;
        } else {
            double s, t, x, y, z;
            int m;
            if (++its > 40 * n) {
                return -1;
            }
            if (its % 10 == 0) {  /* exceptional shifts (ad hoc ones, as in LAPACK's dlahqr): break cycles */
                const int top = its % 20 == 10;
                const double e = top ? fabs(h[(lo + 1) * n + lo]) + fabs(h[(lo + 2) * n + lo + 1])
                                     : fabs(h[hi * n + hi - 1]) + fabs(h[(hi - 1) * n + hi - 2]);
                const double h11 = 0.75 * e + (top ? h[lo * n + lo] : h[hi * n + hi]), h12 = -0.4375 * e;
                s = 2.0 * h11;
                t = h11 * h11 - h12 * e;
            } else {  /* the eigenvalues of the trailing 2 x 2 block as the shifts */
                s = h[(hi - 1) * n + hi - 1] + h[hi * n + hi];
                t = h[(hi - 1) * n + hi - 1] * h[hi * n + hi] - h[(hi - 1) * n + hi] * h[hi * n + hi - 1];
            }
            /* first column of (H - s1)(H - s2): the bulge */
            x = h[lo * n + lo] * h[lo * n + lo] + h[lo * n + lo + 1] * h[(lo + 1) * n + lo] - s * h[lo * n + lo] + t;
            y = h[(lo + 1) * n + lo] * (h[lo * n + lo] + h[(lo + 1) * n + lo + 1] - s);
            z = h[(lo + 1) * n + lo] * h[(lo + 2) * n + lo + 1];
            for (m = lo; m <= hi - 1; ++m) {  /* chase the bulge down the subdiagonal */
                const int three = m < hi - 1;
                const int c0 = m > lo ? m - 1 : lo, r1 = m + 3 < hi ? m + 3 : hi;
                double xs[3], v3[3], beta, v1, v2;
                xs[0] = x;
                xs[1] = y;
                xs[2] = z;
                /* the reflection I - beta v v^T, v = (1, v1, v2), taking (x, y, z) to (*, 0, 0) */
                beta = g6r_house(three ? 3 : 2, xs, 1, v3);
                v1 = v3[1];
                v2 = three ? v3[2] : 0.0;
                if (beta != 0.0 && three) {
                    const double bv1 = beta * v1, bv2 = beta * v2;
                    for (j = c0; j <= hi; ++j) {  /* from the left: rows m .. m+2 */
                        double *g = h + m * n + j;
                        const double sum = g[0] + v1 * g[n] + v2 * g[2 * n];
                        g[0] -= beta * sum;
                        g[n] -= bv1 * sum;
                        g[2 * n] -= bv2 * sum;
                    }
                    for (i = lo; i <= r1; ++i) {  /* from the right: columns m .. m+2 */
                        double *g = h + i * n + m;
                        const double sum = g[0] + v1 * g[1] + v2 * g[2];
                        g[0] -= beta * sum;
                        g[1] -= bv1 * sum;
                        g[2] -= bv2 * sum;
                    }
                } else if (beta != 0.0) {  /* the last step: a 2-vector reflection */
                    const double bv1 = beta * v1;
                    for (j = c0; j <= hi; ++j) {
                        double *g = h + m * n + j;
                        const double sum = g[0] + v1 * g[n];
                        g[0] -= beta * sum;
                        g[n] -= bv1 * sum;
                    }
                    for (i = lo; i <= r1; ++i) {
                        double *g = h + i * n + m;
                        const double sum = g[0] + v1 * g[1];
                        g[0] -= beta * sum;
                        g[1] -= bv1 * sum;
                    }
                }
                if (three) {
                    x = h[(m + 1) * n + m];
                    y = h[(m + 2) * n + m];
                    z = m < hi - 2 ? h[(m + 3) * n + m] : 0.0;
                }
            }
        }
    }
    return 0;
}

/* ---------------------------------------------------------------- the loop equation */

/* (the start vectors f(l, p) = (l, p, p.p, l.p, l x p, (p.p) l - 2 (l.p) p, 1) of both sides are in the tables) */

/* Rz(sign th) v split into its cos th (which = 0), sin th (1) and constant (2) parts: out, one of
   them (the four 3-vector blocks turn) */
static void g6r_rz_part(const double v[15], double sign, int which, double out[15])
{
    int k;
    static const int blocks[4] = {0, 3, 8, 11};
    for (k = 0; k < 15; ++k) {
        out[k] = which == 2 ? v[k] : 0.0;
    }
    for (k = 0; k < 4; ++k) {
        const int b = blocks[k];
        const double x = v[b], y = v[b + 1];
        if (which == 0) {
            out[b] = x;
            out[b + 1] = y;
        } else if (which == 1) {
            out[b] = -sign * y;
            out[b + 1] = sign * x;
        } else {
            out[b] = 0.0;
            out[b + 1] = 0.0;
        }
    }
}

/* v <- M x for a 15 x 15 row-major M */
static void g6r_mv15(const double *M, const double x[15], double v[15])
{
    int r, m;
    for (r = 0; r < 15; ++r) {
        double acc = 0.0;
        for (m = 0; m < 15; ++m) {
            acc += M[r * 15 + m] * x[m];
        }
        v[r] = acc;
    }
}

/* row t (15) of a side's tensor to the rows of P (3 x 15 x 9) or r (15 x 9) that perm (count
   entries, entry i * 9 + m for column m of block i) takes from it */
static void g6r_scatter(const double row[15], int t, const int *perm, int count, double *dst)
{
    int j, k;
    for (j = 0; j < count; ++j) {
        if (perm[j] == t) {
            for (k = 0; k < 15; ++k) {
                dst[((j / 9) * 15 + k) * 9 + j % 9] = row[k];
            }
        }
    }
}

/* one side of the loop equation as a tensor over its joints' (cos, sin, 1):
   Ms[k] Rz(+-th_{k-1}) ... Ms[1] Rz(+-th_0) Ms[0] f, row i0 + 3 i1 + 9 i2 (3^k rows of 15), each
   row scattered into dst by perm as it is made (depth first: one vector per level, no tensor);
   scratch: 75 doubles */
static void g6r_side_tensor(const double *const Ms[4], const double *signs, int k, const double f[15],
                            const int *perm, int count, double *dst, double *scratch)
{
    double (*lev)[15] = (double (*)[15])scratch, *part = scratch + 60;
    int dig[3] = {0, 0, 0}, total = 1, t, j;
    g6r_mv15(Ms[0], f, lev[0]);
    for (j = 0; j < k; ++j) {
        total *= 3;
    }
    for (t = 0; t < total; ++t) {
        /* the digits of t, the first joint's the most significant; levels from the first that changed */
        int rem = t, from = 0, idx = 0, w = 1;
        for (j = k - 1; j >= 0; --j) {
            const int dj = rem % 3;
            if (t > 0 && dj != dig[j]) {
                from = j;
            }
            dig[j] = dj;
            rem /= 3;
        }
        for (j = from; j < k; ++j) {
            g6r_rz_part(lev[j], signs[j], dig[j], part);
            g6r_mv15(Ms[j + 1], part, lev[j + 1]);
        }
        for (j = 0; j < k; ++j) {
            idx += dig[j] * w;
            w *= 3;
        }
        g6r_scatter(lev[k], idx, perm, count, dst);
    }
}

/* the 15 x 15 map of f(l, p) under the rigid motion T (or T^-1): F_translation(p) F_rotation(R) */
static void g6r_f_pose(const double T[16], int inverse, double out[225], double Ft[225])
{
    double R[3][3], p[3], tt;
    int i, k, b, c, m;
    static const int blocks[4] = {0, 3, 8, 11};
    for (i = 0; i < 3; ++i) {
        for (k = 0; k < 3; ++k) {
            R[i][k] = inverse ? T[4 * k + i] : T[4 * i + k];
        }
    }
    for (i = 0; i < 3; ++i) {
        const double acc = R[i][0] * T[3] + R[i][1] * T[7] + R[i][2] * T[11];
        p[i] = inverse ? -acc : T[4 * i + 3];
    }
    tt = p[0] * p[0] + p[1] * p[1] + p[2] * p[2];
    memset(Ft, 0, sizeof(double) * 225);
    for (i = 0; i < 15; ++i) {
        Ft[i * 15 + i] = 1.0;
    }
    for (i = 0; i < 3; ++i) {
        Ft[(3 + i) * 15 + 14] = p[i];
        Ft[6 * 15 + 3 + i] = 2.0 * p[i];
        Ft[7 * 15 + i] = p[i];
        Ft[(11 + i) * 15 + 7] = -2.0 * p[i];
        for (k = 0; k < 3; ++k) {
            Ft[(11 + i) * 15 + k] = (i == k ? tt : 0.0) - 2.0 * p[i] * p[k];
        }
    }
    Ft[6 * 15 + 14] = tt;
    /* l x p -> l x p + l x t ; (p.p) l - 2 (l.p) p -> ... + 2 t x (l x p) */
    Ft[8 * 15 + 1] = p[2];
    Ft[8 * 15 + 2] = -p[1];
    Ft[9 * 15 + 0] = -p[2];
    Ft[9 * 15 + 2] = p[0];
    Ft[10 * 15 + 0] = p[1];
    Ft[10 * 15 + 1] = -p[0];
    Ft[11 * 15 + 9] = -2.0 * p[2];
    Ft[11 * 15 + 10] = 2.0 * p[1];
    Ft[12 * 15 + 8] = 2.0 * p[2];
    Ft[12 * 15 + 10] = -2.0 * p[0];
    Ft[13 * 15 + 8] = -2.0 * p[1];
    Ft[13 * 15 + 9] = 2.0 * p[0];
    memset(out, 0, sizeof(double) * 225);
    for (i = 0; i < 15; ++i) {
        out[i * 15 + 6] = Ft[i * 15 + 6];
        out[i * 15 + 7] = Ft[i * 15 + 7];
        out[i * 15 + 14] = Ft[i * 15 + 14];
        for (b = 0; b < 4; ++b) {
            for (c = 0; c < 3; ++c) {
                double acc = 0.0;
                for (m = 0; m < 3; ++m) {
                    acc += Ft[i * 15 + blocks[b] + m] * R[m][c];
                }
                out[i * 15 + blocks[b] + c] = acc;
            }
        }
    }
}

/* c = a b for 15 x 15 row-major matrices */
static void g6r_mul15(const double *a, const double *b, double *c)
{
    int i, j, k;
    for (i = 0; i < 15; ++i) {
        for (j = 0; j < 15; ++j) {
            double acc = 0.0;
            for (k = 0; k < 15; ++k) {
                acc += a[i * 15 + k] * b[k * 15 + j];
            }
            c[i * 15 + j] = acc;
        }
    }
}

/* _Arrangement.matrices: P (3 x 15 x 9), the three-joint side with the pivot first, and
   r (15 x 9), the two-joint side, for the scaled target T06s. u: the workspace's u (P, r and the
   target's map at the offsets of g6r_work's comment) */
static void g6r_matrices(const g6r_reading *rd, const double T06s[16], double *u)
{
    double *P = u, *r = u + 405, *Wmap = u + 540, *tmp = u + 225;
    const double *Ms[4];
    int i;
    g6r_f_pose(T06s, !rd->w_inverse, Wmap, u);  /* W = T06^-1: its map, or T06's for W^-1 */
    if (rd->pre) {  /* pre F(W) post (a null pointer: the identity) */
        g6r_mul15(rd->pre, Wmap, tmp);
    } else {
        memcpy(tmp, Wmap, sizeof(double) * 225);
    }
    if (rd->post) {
        g6r_mul15(tmp, rd->post, Wmap);
    } else {
        memcpy(Wmap, tmp, sizeof(double) * 225);
    }
    for (i = 0; i <= rd->nw; ++i) {
        Ms[i] = i == rd->w_index ? Wmap : rd->Ms + 225 * i;
    }
    /* the side with the target, made row by row into P or r; the constant side copied */
    if (rd->three_has_w) {
        g6r_side_tensor(Ms, rd->signs, rd->nw, rd->f, rd->perm3, 27, P, u + 765);
        for (i = 0; i < 9; ++i) {
            g6r_scatter(rd->const_side + 15 * i, i, rd->perm2, 9, r);
        }
    } else {
        g6r_side_tensor(Ms, rd->signs, rd->nw, rd->f, rd->perm2, 9, r, u + 765);
        for (i = 0; i < 27; ++i) {
            g6r_scatter(rd->const_side + 15 * i, i, rd->perm3, 27, P);
        }
    }
}

/* out[i * orow + i3 * oi3 + m] = sum_k W[i * wr + k * wk] P[i3][k][m] (i < nrow, k < 14; P: 3 x 15 x 9) */
static void g6r_project(const double *W, int nrow, int wr, int wk, const double *P, double *out, int orow, int oi3)
{
    int i, i3, m, k;
    for (i = 0; i < nrow; ++i) {
        for (i3 = 0; i3 < 3; ++i3) {
            for (m = 0; m < 9; ++m) {
                double acc = 0.0;
                for (k = 0; k < 14; ++k) {
                    acc += W[i * wr + k * wk] * P[(i3 * 15 + k) * 9 + m];
                }
                out[i * orow + i3 * oi3 + m] = acc;
            }
        }
    }
}

/* kernels.general_6r.pencil: A x^2 + B x + C (w->abc: rows e and 6 + e of each 12 x 12 matrix,
   g6r_entry) with x = tan(phi/2), th_pivot = phi + gamma; the three-joint side with the two-joint
   side's constant moved over (in P, in place) times rows 2, 5, 6, 7 of the pseudo-inverse of the
   14 x 8 matrix Q of the two-joint side (w->K). Returns sigma_min / sigma_max of Q. */
static double g6r_pencil(const g6r_arm *arm, g6r_work *w)
{
    static const double G[3][3] = {{1.0, 0.0, -1.0}, {0.0, 2.0, 0.0}, {1.0, 0.0, 1.0}};
    static const int rows4[4] = {2, 5, 6, 7};
    double *u = w->u, *P = u, *r = u + 405, *Q = u + 540, *vs = u + 652, *betas = u + 764, *N = u + 772;
    double *V = u + 652, *pinv = u + 716;
    double (*sig)[6][9] = (double (*)[6][9])(u + 540);
    double norms[14], ratio;
    int order[14], i, j, k, m, e;
    for (k = 0; k < 14; ++k) {  /* the two-joint side's constant moved over */
        P[(2 * 15 + k) * 9 + 8] -= r[k * 9 + 8];
    }
    /* N: the left null space of Q (Householder QR, Q overwritten) */
    for (k = 0; k < 14; ++k) {
        for (j = 0; j < 8; ++j) {
            Q[k * 8 + j] = r[k * 9 + j];
        }
    }
    g6r_left_null_space(Q, N, vs, betas);
    /* Q = U S V^T (Q again, overwritten): the pseudo-inverse (singular values below 1e-14 s_max
       dropped); of it only rows 2, 5, 6, 7 are used (the back substitution's four monomials) */
    for (k = 0; k < 14; ++k) {
        for (j = 0; j < 8; ++j) {
            Q[k * 8 + j] = r[k * 9 + j];
        }
    }
    g6r_svd(14, 8, Q, V, norms, order);
    ratio = norms[order[0]] > 0.0 ? norms[order[7]] / norms[order[0]] : 0.0;
    for (i = 0; i < 4; ++i) {
        for (k = 0; k < 14; ++k) {
            double acc = 0.0;
            for (j = 0; j < 8; ++j) {
                const int o = order[j];
                if (norms[o] > 1e-14 * norms[order[0]]) {
                    const double uk = Q[k * 8 + o] * (norms[o] > 0.0 ? 1.0 / norms[o] : 0.0);
                    acc += V[rows4[i] * 8 + o] * uk / norms[o];
                }
            }
            pinv[i * 14 + k] = acc;
        }
    }
    g6r_project(pinv, 4, 14, 1, P, &w->K[0][0][0], 27, 9);
    /* Sigma_i3 = N^T P'_i3 with N the left null space of Q: theta 1, 2 eliminated */
    g6r_project(N, 6, 1, 6, P, &sig[0][0][0], 9, 54);
    /* th = phi + gamma, x = tan(phi/2), and the half-angle monomials of the other two joints:
       6 equations and the same times x_b, in the 12 monomials x_b^i x_c^j (i <= 3, j <= 2) */
    memset(w->abc, 0, sizeof w->abc);
    for (e = 0; e < 6; ++e) {
        for (m = 0; m < 9; ++m) {
            const double sc = sig[0][e][m] * arm->gc + sig[1][e][m] * arm->gs;
            const double ss = -sig[0][e][m] * arm->gs + sig[1][e][m] * arm->gc;
            const double s1 = sig[2][e][m];
            const double c2 = s1 - sc, c1 = 2.0 * ss, c0 = s1 + sc;
            const int i4 = m / 3, i5 = m % 3;
            int j4, j5;
            if (c0 == 0.0 && c1 == 0.0 && c2 == 0.0) {
                continue;
            }
            for (j4 = 0; j4 < 3; ++j4) {
                const double g4 = G[i4][j4];
                if (g4 == 0.0) {
                    continue;
                }
                for (j5 = 0; j5 < 3; ++j5) {
                    const double g = g4 * G[i5][j5];
                    if (g == 0.0) {
                        continue;
                    }
                    w->abc[0][e][j4 * 3 + j5] += g * c2;
                    w->abc[1][e][j4 * 3 + j5] += g * c1;
                    w->abc[2][e][j4 * 3 + j5] += g * c0;
                }
            }
        }
    }
    return ratio;
}

/* entry (i, j) of the 12 x 12 matrix kk (0: A, 1: B, 2: C): row e < 6 is the equation e on the
   columns 0..8, row 6 + e the same times x_b (columns 3..11) */
static double g6r_entry(const double abc[3][6][9], int kk, int i, int j)
{
    if (i < 6) {
        return j < 9 ? abc[kk][i][j] : 0.0;
    }
    return j >= 3 ? abc[kk][i - 6][j - 3] : 0.0;
}

/* whether sigma_min / sigma_max of the 12 x 12 matrix a x^2 + b x + c is below tol (L: 144 doubles of scratch) */
static int g6r_irregular(const double abc[3][6][9], double x, double tol, double L[144])
{
    int i, j;
    for (i = 0; i < 12; ++i) {
        for (j = 0; j < 12; ++j) {
            L[i * 12 + j] = g6r_entry(abc, 0, i, j) * x * x + g6r_entry(abc, 1, i, j) * x + g6r_entry(abc, 2, i, j);
        }
    }
    return g6r_sv_below(12, 12, L, tol, tol) & 1;
}

/* kernels.general_6r.companion: M = [[0, I], [-A^-1 C, -A^-1 B]] (24 x 24) when A is regular
   (LU with partial pivoting, in lu: 144 doubles) unless sigma_min / sigma_max of A is below t1
   (bit 0 of the result; bit 1: below t2 >= t1) */
static int g6r_companion(const double abc[3][6][9], double M[576], double lu[144], double t1, double t2)
{
    int below;
    double *X;
    int piv[12], i, j, k;
    for (i = 0; i < 144; ++i) {  /* M's storage as scratch for A's singular values */
        M[i] = g6r_entry(abc, 0, i / 12, i % 12);
    }
    below = g6r_sv_below(12, 12, M, t1, t2);
    if (below & 1) {
        return below;
    }
    for (i = 0; i < 144; ++i) {
        lu[i] = g6r_entry(abc, 0, i / 12, i % 12);
    }
    g6r_lu(12, lu, piv);
    /* -A^-1 [C B] in M's lower half: the 24 right-hand sides solved together, row by row (the same
       operations on each column as g6r_lu_solve) */
    memset(M, 0, sizeof(double) * 288);
    for (i = 0; i < 12; ++i) {
        for (j = 0; j < 12; ++j) {
            M[(12 + i) * 24 + j] = g6r_entry(abc, 2, i, j);
            M[(12 + i) * 24 + 12 + j] = g6r_entry(abc, 1, i, j);
        }
        M[i * 24 + 12 + i] = 1.0;
    }
    X = M + 288;
    for (i = 0; i < 12; ++i) {
        if (piv[i] != i) {
            for (j = 0; j < 24; ++j) {
                const double tmp = X[piv[i] * 24 + j];
                X[piv[i] * 24 + j] = X[i * 24 + j];
                X[i * 24 + j] = tmp;
            }
        }
    }
    for (i = 0; i < 12; ++i) {
        for (k = 0; k < i; ++k) {
            const double l = lu[i * 12 + k];
            for (j = 0; j < 24; ++j) {
                X[i * 24 + j] -= l * X[k * 24 + j];
            }
        }
    }
    for (i = 11; i >= 0; --i) {
        for (k = i + 1; k < 12; ++k) {
            const double l = lu[i * 12 + k];
            for (j = 0; j < 24; ++j) {
                X[i * 24 + j] -= l * X[k * 24 + j];
            }
        }
        for (j = 0; j < 24; ++j) {
            X[i * 24 + j] /= lu[i * 12 + i];
        }
    }
    for (i = 0; i < 288; ++i) {
        X[i] = -X[i];
    }
    return below;
}

/* swaps lines a and b (rows: step 12, stride 1; columns: step 1, stride 12) of the 12 x 12 row-major
   matrices re and im alike: entry t of line l is at l * step + t * stride */
static void g6r_swap_lines(double *re, double *im, int a, int b, int step, int stride)
{
    int t;
    for (t = 0; t < 12; ++t) {
        const int x = a * step + t * stride, y = b * step + t * stride;
        double s = re[x];
        re[x] = re[y];
        re[y] = s;
        s = im[x];
        im[x] = im[y];
        im[y] = s;
    }
}

/* kernels.general_6r.deflate: the eigenvalues x = +-i removed from the companion matrix M (24 x 24,
   row-major) of a x^2 + b x + c; returns the new size n, M's first n * n entries then holding the
   n x n matrix of the other eigenvalues (row-major). When the pivot is the joint of its group
   farthest from the eliminated one, L(i) = c - a + i b is singular with four null vectors (the
   half-angle substitution's points at infinity); other readings have none, or fewer on special
   arms. Each null vector v = p + i q (|v| = 1) gives the eigenvectors (v, +-i v) of M, whose
   real span Z = [p, q; -q, p] is invariant (checked: M Z = Z Lambda to 1e-12 of M's largest
   entry). With p the rows of Z picked by Gauss-Jordan elimination with row pivoting, q the
   others and G = Z_q Z_p^-1 (entries at most 1e4), the similarity S = [[I, 0], [G, I]] (in the
   order p, q) makes M block triangular, S^-1 M S = [[*, *], [0, M_qq - G M_pq]], and that
   trailing block keeps the other eigenvalues. The null vectors by Gaussian elimination of L(i)
   with complete pivoting (pivots below 1e-11 of the largest entry end it; at most
   G6R_DEFLATE_MAX of them used). L(i) is kept in M's first 12 rows, [0 I] (rebuilt after), the
   null vectors in u[0..96) (then M_pq in u[0..128)), Z in u[720..912). Returns 24 with M as
   built when L(i) is regular or a check fails. */
static int g6r_deflate(const double abc[3][6][9], double *M, double *u)
{
    double *kr = M, *ki = M + 144, *vr = u, *vi = u + 48, *sv = u, *Z = u + 720;
    double big = 0.0, top = 1.0, below = 0.0;
    int perm[12], used[24], rank = 12, r, r2, m, i, j, k, t, c;
    memset(M, 0, sizeof(double) * 288);
    for (i = 0; i < 6; ++i) {  /* rows i and 6 + i (g6r_entry): the same entries, 3 columns apart */
        for (j = 0; j < 9; ++j) {
            const double x = abc[2][i][j] - abc[0][i][j], y = abc[1][i][j];
            kr[i * 12 + j] = kr[(6 + i) * 12 + 3 + j] = x;
            ki[i * 12 + j] = ki[(6 + i) * 12 + 3 + j] = y;
            big = x * x + y * y > big ? x * x + y * y : big;
        }
    }
    for (i = 0; i < 12; ++i) {
        perm[i] = i;
    }
    for (k = 0; k < 12; ++k) {
        double best = -1.0, pr, pi;
        int p = k, q = k;
        for (i = k; i < 12; ++i) {
            for (j = k; j < 12; ++j) {
                const double m2 = kr[i * 12 + j] * kr[i * 12 + j] + ki[i * 12 + j] * ki[i * 12 + j];
                if (m2 > best) {
                    best = m2;
                    p = i;
                    q = j;
                }
            }
        }
        if (!(best > 1e-22 * big)) {
            rank = k;
            break;
        }
        g6r_swap_lines(kr, ki, k, p, 12, 1);  /* rows k, p */
        g6r_swap_lines(kr, ki, k, q, 1, 12);  /* columns k, q */
        t = perm[k];
        perm[k] = perm[q];
        perm[q] = t;
        pr = kr[k * 12 + k] / best;  /* 1 / pivot */
        pi = -ki[k * 12 + k] / best;
        for (i = k + 1; i < 12; ++i) {
            const double lr = kr[i * 12 + k] * pr - ki[i * 12 + k] * pi;
            const double li = kr[i * 12 + k] * pi + ki[i * 12 + k] * pr;
            for (j = k + 1; j < 12; ++j) {
                kr[i * 12 + j] -= lr * kr[k * 12 + j] - li * ki[k * 12 + j];
                ki[i * 12 + j] -= lr * ki[k * 12 + j] + li * kr[k * 12 + j];
            }
        }
    }
    r = 12 - rank < G6R_DEFLATE_MAX ? 12 - rank : G6R_DEFLATE_MAX;
    if (r == 0) {
        memset(M, 0, sizeof(double) * 288);  /* M's first rows again */
        for (i = 0; i < 12; ++i) {
            M[i * 24 + 12 + i] = 1.0;
        }
        return 24;
    }
    /* the null vectors (free unknown rank + t = 1, the others 0) by back-substitution */
    for (t = 0; t < r; ++t) {
        double yr[12], yi[12];
        const int f = rank + t;
        for (i = rank - 1; i >= 0; --i) {
            double sr = -kr[i * 12 + f], si = -ki[i * 12 + f], dd;
            for (j = i + 1; j < rank; ++j) {
                sr -= kr[i * 12 + j] * yr[j] - ki[i * 12 + j] * yi[j];
                si -= kr[i * 12 + j] * yi[j] + ki[i * 12 + j] * yr[j];
            }
            dd = kr[i * 12 + i] * kr[i * 12 + i] + ki[i * 12 + i] * ki[i * 12 + i];
            yr[i] = (sr * kr[i * 12 + i] + si * ki[i * 12 + i]) / dd;
            yi[i] = (si * kr[i * 12 + i] - sr * ki[i * 12 + i]) / dd;
        }
        for (j = rank; j < 12; ++j) {
            yr[j] = j == f ? 1.0 : 0.0;
            yi[j] = 0.0;
        }
        for (j = 0; j < 12; ++j) {  /* v[perm[j]] = y[j] */
            vr[t * 12 + perm[j]] = yr[j];
            vi[t * 12 + perm[j]] = yi[j];
        }
    }
    memset(M, 0, sizeof(double) * 288);
    for (i = 0; i < 12; ++i) {
        M[i * 24 + 12 + i] = 1.0;
    }
    for (i = 288; i < 576; ++i) {  /* M's largest entry (its first rows: 0 and 1) */
        top = fabs(M[i]) > top ? fabs(M[i]) : top;
    }
    /* Z (24 x 2r, row-major): the columns (p; -q) and (q; p) of each null vector, v scaled to |v| = 1 */
    r2 = 2 * r;
    for (t = 0; t < r; ++t) {
        double nrm = 0.0;
        for (i = 0; i < 12; ++i) {
            nrm += vr[t * 12 + i] * vr[t * 12 + i] + vi[t * 12 + i] * vi[t * 12 + i];
        }
        nrm = 1.0 / sqrt(nrm);
        for (i = 0; i < 12; ++i) {
            Z[i * r2 + 2 * t] = Z[(12 + i) * r2 + 2 * t + 1] = vr[t * 12 + i] * nrm;
            Z[i * r2 + 2 * t + 1] = vi[t * 12 + i] * nrm;
            Z[(12 + i) * r2 + 2 * t] = -vi[t * 12 + i] * nrm;
        }
    }
    /* the invariance check: M z = -z' and M z' = z for each pair (z, z') (rows 0..11 hold exactly) */
    for (i = 12; i < 24; ++i) {
        for (c = 0; c < r2; ++c) {
            double s = (c & 1) ? -Z[i * r2 + c - 1] : Z[i * r2 + c + 1];
            for (j = 0; j < 24; ++j) {
                s += M[i * 24 + j] * Z[j * r2 + c];
            }
            below = fabs(s) > below ? fabs(s) : below;
        }
    }
    if (!(below <= 1e-12 * top)) {
        return 24;
    }
    /* Gauss-Jordan on Z's columns with row pivoting: Z <- Z Z_p^-1, identity on the pivot rows
       p (used[i] = 1 + the column), G = Z_q Z_p^-1 on the others q */
    for (i = 0; i < 24; ++i) {
        used[i] = 0;
    }
    for (c = 0; c < r2; ++c) {
        double best = 0.0, inv;
        int p = -1;
        for (i = 0; i < 24; ++i) {
            if (!used[i] && fabs(Z[i * r2 + c]) > best) {
                best = fabs(Z[i * r2 + c]);
                p = i;
            }
        }
        if (p < 0) {
            return 24;
        }
        used[p] = 1 + c;
        inv = 1.0 / Z[p * r2 + c];
        for (i = 0; i < 24; ++i) {
            Z[i * r2 + c] *= inv;
        }
        for (j = 0; j < r2; ++j) {
            const double f = Z[p * r2 + j];
            if (j == c || f == 0.0) {
                continue;
            }
            for (i = 0; i < 24; ++i) {
                Z[i * r2 + j] -= f * Z[i * r2 + c];
            }
        }
    }
    below = 0.0;  /* the similarity's size: G's largest entry */
    for (i = 0; i < 24; ++i) {
        for (c = 0; c < r2 && !used[i]; ++c) {
            below = fabs(Z[i * r2 + c]) > below ? fabs(Z[i * r2 + c]) : below;
        }
    }
    if (!(below <= 1e4)) {
        return 24;
    }
    /* with S = [[I, 0], [G, I]] in the order (p, q): S^-1 M S = [[*, *], [0, M_qq - G M_pq]];
       M_pq (rows p, columns q) into u[0..128) first, then M_qq - G M_pq to the front of M, row
       by row (each entry is written at or before where it was read from) */
    m = 24 - r2;
    for (i = 0; i < 24; ++i) {
        if (used[i]) {
            int b = 0;
            for (j = 0; j < 24; ++j) {
                if (!used[j]) {
                    sv[(used[i] - 1) * m + b++] = M[i * 24 + j];
                }
            }
        }
    }
    k = 0;
    for (i = 0; i < 24; ++i) {
        int b = 0;
        if (used[i]) {
            continue;
        }
        for (j = 0; j < 24; ++j) {
            double x;
            if (used[j]) {
                continue;
            }
            x = M[i * 24 + j];
            for (c = 0; c < r2; ++c) {
                x -= Z[i * r2 + c] * sv[c * m + b];
            }
            M[k * m + b++] = x;
        }
        ++k;
    }
    return m;
}

/* the null vector v (12) of the (nearly) singular a y^2 + b y + c at a real eigenvalue y:
   inverse iteration (two LU solves; L: 144 doubles of scratch); for |y| > 1 the matrix divided by y^2 */
static void g6r_null_vector(const double abc[3][6][9], double y, double v[12], double L[144])
{
    double nrm;
    int piv[12], i, it;
    const int big = fabs(y) > 1.0;
    const double y1 = big ? 1.0 / y : y;
    memset(L, 0, sizeof(double) * 144);
    for (i = 0; i < 6; ++i) {  /* rows i and 6 + i: the same entries, 3 columns apart */
        int j;
        for (j = 0; j < 9; ++j) {
            const double a = abc[0][i][j], b = abc[1][i][j], c = abc[2][i][j];
            L[i * 12 + j] = L[(6 + i) * 12 + 3 + j] = big ? a + b * y1 + c * y1 * y1 : a * y * y + b * y + c;
        }
    }
    g6r_lu(12, L, piv);
    for (i = 0; i < 12; ++i) {
        v[i] = 1.0 / (1.0 + 0.1 * i);
    }
    for (it = 0; it < 2; ++it) {
        g6r_lu_solve(12, L, piv, v);
        nrm = 0.0;
        for (i = 0; i < 12; ++i) {
            nrm += v[i] * v[i];
        }
        nrm = nrm > 0.0 && nrm < HUGE_VAL ? 1.0 / sqrt(nrm) : 0.0;
        for (i = 0; i < 12; ++i) {
            v[i] *= nrm;
        }
    }
}

/* ---------------------------------------------------------------- kinematics of Z1 X1 ... Z6 */

/* T <- T Rz(th) Tz(d_i) for the 4 x 4 row-major T (its top three rows), c = cos th, s = sin th */
static void g6r_turn(const g6r_arm *arm, int i, double c, double s, double *T)
{
    int r;
    for (r = 0; r < 3; ++r) {
        const double x = T[4 * r], y = T[4 * r + 1];
        T[4 * r] = c * x + s * y;
        T[4 * r + 1] = -s * x + c * y;
        T[4 * r + 3] += arm->d[i] * T[4 * r + 2];
    }
}

/* T <- T Tx(a_i) Rx(alpha_i) */
static void g6r_twist(const g6r_arm *arm, int i, double *T)
{
    int r;
    for (r = 0; r < 3; ++r) {
        const double y = T[4 * r + 1], z = T[4 * r + 2];
        T[4 * r + 3] += arm->a[i] * T[4 * r];
        T[4 * r + 1] = arm->ca[i] * y + arm->sa[i] * z;
        T[4 * r + 2] = -arm->sa[i] * y + arm->ca[i] * z;
    }
}

/* kernels.general_6r.fk_pose: the pose of Z1 X1 ... X5 Z6 at the rotation angles th (scaled) */
static void g6r_fk_pose(const g6r_arm *arm, const double th[6], double T[16])
{
    int i;
    memset(T, 0, sizeof(double) * 16);
    T[0] = T[5] = T[10] = T[15] = 1.0;
    for (i = 0; i < 6; ++i) {
        g6r_turn(arm, i, cos(th[i]), sin(th[i]), T);
        if (i < 5) {
            g6r_twist(arm, i, T);
        }
    }
}

/* kernels.general_6r.jacobian: geometric Jacobian (rows v; w, space frame, at T's origin) */
static void g6r_jacobian6(const g6r_arm *arm, const double th[6], const double T[16], double J[36])
{
    double G[16];
    int i;
    memset(G, 0, sizeof G);
    G[0] = G[5] = G[10] = G[15] = 1.0;
    for (i = 0; i < 6; ++i) {
        const double z0 = G[2], z1 = G[6], z2 = G[10];
        const double rx = T[3] - G[3], ry = T[7] - G[7], rz = T[11] - G[11];
        const double c = cos(th[i]), s = sin(th[i]);
        J[0 * 6 + i] = z1 * rz - z2 * ry;
        J[1 * 6 + i] = z2 * rx - z0 * rz;
        J[2 * 6 + i] = z0 * ry - z1 * rx;
        J[3 * 6 + i] = z0;
        J[4 * 6 + i] = z1;
        J[5 * 6 + i] = z2;
        g6r_turn(arm, i, c, s, G);
        if (i < 5) {
            g6r_twist(arm, i, G);
        }
    }
}

/* e = (p* - p, w) with exp([w]) = R* R^T; returns |e| */
static double g6r_pose_error(const double Tt[16], const double T[16], double e[6])
{
    double Re[3][3], tr, cth, wx, wy, wz, sth, th, fac;
    int i, j, k;
    for (i = 0; i < 3; ++i) {
        e[i] = Tt[4 * i + 3] - T[4 * i + 3];
    }
    for (i = 0; i < 3; ++i) {
        for (j = 0; j < 3; ++j) {
            double s = 0.0;
            for (k = 0; k < 3; ++k) {
                s += Tt[4 * i + k] * T[4 * j + k];
            }
            Re[i][j] = s;
        }
    }
    tr = Re[0][0] + Re[1][1] + Re[2][2];
    cth = 0.5 * (tr - 1.0);
    cth = cth > 1.0 ? 1.0 : (cth < -1.0 ? -1.0 : cth);
    wx = Re[2][1] - Re[1][2];
    wy = Re[0][2] - Re[2][0];
    wz = Re[1][0] - Re[0][1];
    sth = 0.5 * sqrt(wx * wx + wy * wy + wz * wz);
    th = atan2(sth, cth);
    fac = sth >= 1e-12 ? 0.5 * th / sth : 0.5;
    e[3] = fac * wx;
    e[4] = fac * wy;
    e[5] = fac * wz;
    return sqrt(e[0] * e[0] + e[1] * e[1] + e[2] * e[2] + e[3] * e[3] + e[4] * e[4] + e[5] * e[5]);
}

/* kernels.general_6r.polish: Newton-Raphson on the pose error; the step is the least-squares
   solution J dq = e (SVD, singular values below 1e-12 s_max dropped, as numpy's lstsq with
   rcond = 1e-12); a step that does not lower the error is not taken. Returns the error.
   scratch: 156 doubles. */
static double g6r_polish(const g6r_arm *arm, const double T06s[16], double th[6], int iters, double *scratch)
{
    double *J = scratch, *U = scratch + 36, *V = scratch + 72, *T = scratch + 108, *e = scratch + 124;
    double *trial = scratch + 130, *dq = scratch + 136, *norms = scratch + 142, err, nw;
    int it, i, j, order[14];
    g6r_fk_pose(arm, th, T);
    err = g6r_pose_error(T06s, T, e);
    for (it = 0; it < iters; ++it) {
        if (err < 1e-15) {
            break;
        }
        g6r_jacobian6(arm, th, T, J);
        memcpy(U, J, sizeof(double) * 36);
        if (g6r_well_conditioned(6, 6, U, 1e-10)) {
            /* well conditioned: the least-squares step is the solution of J dq = e (LU) */
            int piv[6];
            memcpy(dq, e, sizeof(double) * 6);
            g6r_lu(6, J, piv);
            g6r_lu_solve(6, J, piv, dq);
            for (i = 0; i < 6; ++i) {
                trial[i] = th[i] + dq[i];
            }
        } else {
            g6r_svd(6, 6, J, V, norms, order);
            for (i = 0; i < 6; ++i) {
                trial[i] = th[i];
            }
            for (j = 0; j < 6; ++j) {
                const int o = order[j];
                const double inv = norms[o] > 0.0 ? 1.0 / norms[o] : 0.0;
                double ue = 0.0;
                if (!(norms[o] > 1e-12 * norms[order[0]])) {
                    continue;
                }
                for (i = 0; i < 6; ++i) {
                    ue += J[i * 6 + o] * inv * e[i];
                }
                ue /= norms[o];
                for (i = 0; i < 6; ++i) {
                    trial[i] += V[i * 6 + o] * ue;
                }
            }
        }
        g6r_fk_pose(arm, trial, T);
        nw = g6r_pose_error(T06s, T, e);
        if (!(nw < err)) {
            g6r_fk_pose(arm, th, T);
            g6r_pose_error(T06s, T, e);
            break;
        }
        err = nw;
        for (i = 0; i < 6; ++i) {
            th[i] = trial[i];
        }
    }
    return err;
}

/* kernels.general_6r.fill_joint: th_j from the other five,
   Rz(th_j) = (Z1 X1 ... X_{j-1})^-1 T06 (X_j Z_{j+1} ... Z6)^-1 Tz(-d_j) */
static void g6r_fill_joint(const g6r_arm *arm, const double T06s[16], double th[6], int j, double *scratch)
{
    double *A = scratch, *B = scratch + 16, R1[3][3], r00 = 0.0, r10 = 0.0;
    int i, k, m;
    memset(A, 0, sizeof(double) * 16);
    memset(B, 0, sizeof(double) * 16);
    A[0] = A[5] = A[10] = A[15] = 1.0;
    B[0] = B[5] = B[10] = B[15] = 1.0;
    for (i = 0; i < 6; ++i) {
        const double c = cos(th[i]), s = sin(th[i]);
        if (i != j) {
            g6r_turn(arm, i, c, s, i > j ? B : A);
        }
        if (i < 5) {
            g6r_twist(arm, i, i >= j ? B : A);
        }
    }
    for (i = 0; i < 3; ++i) {  /* R1 = A_R^T R06 */
        for (k = 0; k < 3; ++k) {
            double acc = 0.0;
            for (m = 0; m < 3; ++m) {
                acc += A[4 * m + i] * T06s[4 * m + k];
            }
            R1[i][k] = acc;
        }
    }
    for (m = 0; m < 3; ++m) {  /* first column of R1 B_R^T */
        r00 += R1[0][m] * B[m];
        r10 += R1[1][m] * B[m];
    }
    th[j] = atan2(r10, r00);
}

/* kernels.general_6r._candidate: th (6) from the pivot's phi and the monomial vector
   V (4 x 3) ~ x_b^i x_c^j, then polished; returns the pose error */
static double g6r_candidate(const g6r_arm *arm, const g6r_reading *rd, const double T06s[16], const double V[4][3],
                            double phi, g6r_work *wk, double th[6])
{
    double mbc[9], best = -1.0, thb = 0.0, thc = 0.0, cp, sp, cb, sb, cc, scc, m2 = 0.0, m5 = 0.0,
           m6 = 0.0, m7 = 0.0, tb[3], tc[3];
    const double thp = phi + arm->gamma;
    int i, j, m;
    /* theta_b, theta_c as 2 atan2 of the ratio of neighbouring monomials (the largest pair) */
    for (i = 0; i < 3; ++i) {
        for (j = 0; j < 3; ++j) {
            const double w = V[i][j] * V[i][j] + V[i + 1][j] * V[i + 1][j];
            if (w > best) {
                best = w;
                thb = 2.0 * atan2(V[i + 1][j], V[i][j]);
            }
        }
    }
    best = -1.0;
    for (i = 0; i < 4; ++i) {
        for (j = 0; j < 2; ++j) {
            const double w = V[i][j] * V[i][j] + V[i][j + 1] * V[i][j + 1];
            if (w > best) {
                best = w;
                thc = 2.0 * atan2(V[i][j + 1], V[i][j]);
            }
        }
    }
    cb = cos(thb);
    sb = sin(thb);
    cc = cos(thc);
    scc = sin(thc);
    tb[0] = cb;
    tb[1] = sb;
    tb[2] = 1.0;
    tc[0] = cc;
    tc[1] = scc;
    tc[2] = 1.0;
    for (i = 0; i < 3; ++i) {
        for (j = 0; j < 3; ++j) {
            mbc[i * 3 + j] = tb[i] * tc[j];
        }
    }
    /* the two-joint side's monomials m12 = Q^+ P(th_p) m_bc (least squares, 14 equations): of it
       the four used, through K = (rows 2, 5, 6, 7 of Q^+) P */
    cp = cos(thp);
    sp = sin(thp);
    for (m = 0; m < 9; ++m) {
        m2 += (wk->K[0][0][m] * cp + wk->K[0][1][m] * sp + wk->K[0][2][m]) * mbc[m];
        m5 += (wk->K[1][0][m] * cp + wk->K[1][1][m] * sp + wk->K[1][2][m]) * mbc[m];
        m6 += (wk->K[2][0][m] * cp + wk->K[2][1][m] * sp + wk->K[2][2][m]) * mbc[m];
        m7 += (wk->K[3][0][m] * cp + wk->K[3][1][m] * sp + wk->K[3][2][m]) * mbc[m];
    }
    th[rd->roles[0]] = thp;
    th[rd->roles[1]] = thb;
    th[rd->roles[2]] = thc;
    th[rd->roles[3]] = atan2(m5, m2);
    th[rd->roles[4]] = atan2(m7, m6);
    th[rd->roles[5]] = 0.0;
    /* the eliminated joint from the other five, then Newton on the pose */
    g6r_fill_joint(arm, T06s, th, rd->roles[5], wk->u + 300);
    return g6r_polish(arm, T06s, th, 30, wk->u + 144);
}

/* the order of GeneralSixR.solve: by q3, then q1, q2, q4, q5, q6 */
static int g6r_before(const double a[6], const double b[6])
{
    static const int keys[6] = {2, 0, 1, 3, 4, 5};
    int k;
    for (k = 0; k < 6; ++k) {
        if (a[keys[k]] < b[keys[k]]) {
            return 1;
        }
        if (a[keys[k]] > b[keys[k]]) {
            return 0;
        }
    }
    return 0;
}

/* kernels.general_6r.distinct and the sort of GeneralSixR.solve, one candidate at a time: q =
   th - th0 wrapped to [-pi, pi) is dropped if it is within the tolerance of a kept row in every
   joint (modulo 2 pi), else inserted in order after the rows not after it (the order of a stable
   sort of the distinct rows in the order found). rows holds at most G6R_MAX_SOLUTIONS: beyond
   that (a near-continuum, see the docs) the last in order is dropped. Returns how many rows. */
static int g6r_add(const g6r_arm *arm, double rows[][6], int m, const double th[6])
{
    double q[6];
    int o, i, j;
    for (i = 0; i < 6; ++i) {
        const double v = th[i] - arm->th0[i];
        q[i] = v - 6.283185307179586 * floor((v + 3.141592653589793) / 6.283185307179586);
    }
    for (o = 0; o < m; ++o) {
        int close = 1;
        for (i = 0; i < 6 && close; ++i) {
            double dv = q[i] - rows[o][i];
            dv = dv - 6.283185307179586 * floor((dv + 3.141592653589793) / 6.283185307179586);
            close = fabs(dv) < arm->same;
        }
        if (close) {
            return m;
        }
    }
    if (m == G6R_MAX_SOLUTIONS && !g6r_before(q, rows[m - 1])) {
        return m;
    }
    j = m < G6R_MAX_SOLUTIONS ? m : m - 1;
    while (j > 0 && g6r_before(q, rows[j - 1])) {
        memcpy(rows[j], rows[j - 1], sizeof q);
        --j;
    }
    memcpy(rows[j], q, sizeof q);
    return m < G6R_MAX_SOLUTIONS ? m + 1 : m;
}

/* GeneralSixR._Elimination.candidates: the polished rotation angles of the solutions with one
   reading, added to rows (g6r_add; *m how many); *poor: whether the conditioning figure
   min(Q's, A's, the pencil's sigma_min / sigma_max) is below arm->poor. */
static void g6r_candidates(const g6r_arm *arm, const g6r_reading *rd, const double T06s[16], double rows[][6],
                           int *m, int *poor, g6r_work *w)
{
    /* the half-angle turn used when A is near singular: t = tan(1.1 / 2) (robokit.codegen.ik_general) */
    const double t = 0.6131052132881357;
    double *M = w->u + 144, *wr = w->u + 720, *wi = w->u + 744;
    int k, rotated = 0, i, singularA, n;
    /* 1-3: the 14 equations, theta 1, 2 eliminated, the 12 x 12 quadratic matrix polynomial */
    g6r_matrices(rd, T06s, w->u);
    *poor = g6r_pencil(arm, w) < arm->poor;
    /* 4: the eigenproblem, the companion matrix when A is regular */
    singularA = g6r_companion((const double (*)[6][9])w->abc, M, w->u, 1e-10, arm->poor);
    *poor = *poor || (singularA & 2) || g6r_irregular((const double (*)[6][9])w->abc, arm->x0, arm->poor, w->u);
    if (singularA & 1) {
        /* A near singular (a root near the half-angle's point at infinity): robokit's Python
           takes the generalised eigenproblem (QZ); the C turns the variable instead,
           x = (y + t) / (1 - t y), which moves that root to y = -1/t and gives the regular
           leading matrix A' = A - t B + t^2 C (the same roots, as angles) */
        for (i = 0; i < 54; ++i) {  /* in place: only the turned polynomial is used from here on */
            double *pa = &w->abc[0][0][0] + i, *pb = &w->abc[1][0][0] + i, *pc = &w->abc[2][0][0] + i;
            const double a = *pa, b = *pb, c = *pc;
            *pa = a - t * b + t * t * c;
            *pb = 2.0 * t * a + (1.0 - t * t) * b - 2.0 * t * c;
            *pc = t * t * a + t * b + c;
        }
        rotated = 1;
        if (g6r_companion((const double (*)[6][9])w->abc, M, w->u, 1e-10, 1e-10) & 1) {
            return;  /* singular in both variables: a continuum, no finite solution set */
        }
    }
    /* the roots x = +-i of the half-angle substitution (pivot outermost: four pairs) removed first */
    n = rd->deflate > 0 ? g6r_deflate((const double (*)[6][9])w->abc, M, w->u) : 24;
    if (g6r_eigenvalues(n, M, wr, wi, w->u + 768) != 0) {
        *poor = 1;  /* the QR iteration did not converge: the pose is solved with the next readings too */
        return;
    }
    /* 5-6: every eigenvalue real to the tolerance (as an angle): back-substitution, polish */
    for (k = 0; k < n; ++k) {
        const double lam = wr[k];
        const double imag = 2.0 * fabs(wi[k]) / (1.0 + lam * lam + wi[k] * wi[k]);
        double V[12], th[6], phi, err;  /* the null vector: the monomials x_b^i x_c^j at 3 i + j */
        if (imag > arm->imag_tol) {
            continue;
        }
        phi = rotated ? 2.0 * atan2(lam + t, 1.0 - t * lam) : 2.0 * atan(lam);
        g6r_null_vector((const double (*)[6][9])w->abc, lam, V, w->u);
        err = g6r_candidate(arm, rd, T06s, (const double (*)[3])V, phi, w, th);
        if (err < arm->converged) {
            *m = g6r_add(arm, rows, *m, th);
        }
    }
}

/* GeneralSixR.solve for the scaled target T06s (see g6r.h) */
G6R_API int g6r_solve(const g6r_arm *arm, const double T06s[16], double rows[G6R_MAX_SOLUTIONS][6], int lab[],
                      int deg[], double *ws)
{
    g6r_work *w = (g6r_work *)(void *)ws;
    int m = 0, a, i, j, poor, extra_poor;
    for (i = 0; i < 12; ++i) {
        if (!(fabs(T06s[i]) < HUGE_VAL)) {
            return 0;  /* not a pose (inf or NaN) */
        }
    }
    g6r_candidates(arm, &arm->readings[0], T06s, rows, &m, &poor, w);
    if (poor) {  /* badly conditioned for the best reading (near a singular pose): add the next ones */
        for (a = 1; a < arm->nread; ++a) {
            g6r_candidates(arm, &arm->readings[a], T06s, rows, &m, &extra_poor, w);
        }
    }
    for (i = 0; i < m; ++i) {
        int singular = 0;
        if (poor) {  /* near a singular pose: flag the solutions where the Jacobian is singular */
            double t6[6], T[16], *J = w->u;
            for (j = 0; j < 6; ++j) {
                t6[j] = rows[i][j] + arm->th0[j];
            }
            g6r_fk_pose(arm, t6, T);
            g6r_jacobian6(arm, t6, T, J);
            singular = g6r_sv_below(6, 6, J, 1e-8, 1e-8) & 1;
        }
        lab[i] = ((m - 1) * m / 2 + i) * 2 + singular;  /* "solution i+1 of m" (", singular") */
        deg[i] = singular;
    }
    return m;
}
