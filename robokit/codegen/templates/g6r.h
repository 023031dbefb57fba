/* robokit: the general 6R closed-form IK (Raghavan-Roth elimination, Manocha-Canny eigenproblem),
   the robot-independent part. robokit.codegen writes this file and g6r.c verbatim into a generated
   NAME.c (with G6R_API defined as static), followed by the arm's constants as a const g6r_arm;
   the tests also compile g6r.c on its own. Step for step as robokit.ik.general_6r.GeneralSixR.solve
   (see docs/codegen.md, "General 6R"). */
#ifndef G6R_API
#define G6R_API extern
#endif

/* One reading of the loop equation (GeneralSixR's _Arrangement): the side without the target as
   its constant tensor, the side with it as its 15 x 15 maps (slot w_index: pre F(W) post per pose). */
typedef struct {
    int roles[6];    /* joints: pivot (eigenvalue), b, c (eigenvector), d, e (14 x 8 system), eliminated */
    int three_has_w; /* the target is on the three-joint side */
    int nw;          /* joints on the target's side (2 or 3) */
    int w_index, w_inverse;
    int deflate, pad_;        /* the eigenvalue pairs x = +-i removed (0: none tried; g6r_deflate); padding */
    const double *const_side; /* (3^(5 - nw) x 15) */
    const double *Ms;         /* (nw + 1) x 15 x 15 (slot w_index unused) */
    const double *pre, *post; /* 15 x 15, or a null pointer for the identity */
    const double *signs, *f;  /* nw signs of the joint rotations; the start vector (15) */
    int perm3[27], perm2[9];  /* the rows of P and r in the two sides' tensors */
} g6r_reading;

/* The per-arm constants (GeneralSixR.export_constants()): the canonical chain Z1 X1 ... Z6 with
   lengths divided by the arm's scale, the solver's tolerances and its best readings. */
typedef struct {
    double a[6], d[6], ca[6], sa[6], th0[6]; /* a, d (scaled), cos and sin of alpha, theta offsets */
    double gc, gs, gamma;                     /* the pivot's turn gamma and its cosine and sine */
    double x0;                                /* where the pencil's regularity is measured */
    double imag_tol, converged, same, poor;   /* tolerances: real eigenvalue, converged pose error,
                                                 same solution, badly conditioned reading */
    const g6r_reading *readings;              /* the best first */
    int nread, pad_;                          /* how many readings (1..4); padding */
} g6r_arm;

/* Scratch: every matrix of the elimination and the eigenproblem, G6R_WORKSPACE_DOUBLES doubles
   (9.2 KB); no state is kept in it between calls. G6R_DEFLATE_MAX: the most eigenvalue pairs
   x = +-i removed before the eigenvalue iteration (kernels.general_6r.DEFLATE_MAX). */
enum { G6R_WORKSPACE_DOUBLES = 1182, G6R_MAX_SOLUTIONS = 16, G6R_DEFLATE_MAX = 4 };

/* Every solution of the arm for the scaled target T06s (Z1 X1 ... Z6, lengths / scale): rows
   (q = theta - th0 wrapped to [-pi, pi), ordered by q3, then q1, q2, q4, q5, q6, at most
   G6R_MAX_SOLUTIONS), and per row its label index ((m - 1) m / 2 + k) * 2 + singular and the
   singular flag. ws: G6R_WORKSPACE_DOUBLES doubles, not overlapping rows. Returns how many (0: out
   of reach, or not a pose). */
G6R_API int g6r_solve(const g6r_arm *arm, const double T06s[16], double rows[G6R_MAX_SOLUTIONS][6], int lab[], int deg[],
                      double *ws);
