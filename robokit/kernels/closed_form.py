r"""The closed-form inverse kinematics of Lecture 5 in compiled code: Pieper's spherical wrist
and the three-parallel-axes (UR) method, per pose and batched over (N, 4, 4) targets.

This module **is** the algorithm — the one implementation of both methods, in Python and
compiled alike (``NUMBA_DISABLE_JIT=1`` runs this very source as plain Python; the tests check
every solution against Pinocchio). :mod:`robokit.ik.pieper` and :mod:`robokit.ik.parallel_axes`
only build the constants (:class:`robokit.ik.pieper.PieperConstants`,
:class:`robokit.ik.parallel_axes.ParallelAxesConstants`) and call the raw-row kernels here
(``pieper_position``/``pieper_wrist``/``pieper_rows``, ``parallel_axes_position``/
``parallel_axes_wrist``/``parallel_axes_rows``: the position and wrist sub-problems of
:class:`robokit.ik.solver.ClosedFormSolver`). Pieper's method covers every case: revolute or
prismatic joints 1–3 (``ci[1]``: 0 RR-quartic, 1 RR-a1, 2 RR-s1, 3 PR-quartic, 4 PR-c1,
5 RP-quartic, 6 RP-c1, 7 PP). Over flat arrays:

* the solver's constants are computed once per robot by the solver objects
  (``PieperSolver.kernel_constants()``, ``ParallelAxesSolver.kernel_constants()``: an int
  array ``ci`` — which method and case —, a float array ``cf`` — the DH numbers and the
  polynomial's pieces — and the (5, 5) coefficient matrix ``C`` of the position polynomial)
  and packed by :func:`pack_constants`, with the pre/post transforms that turn the tip pose
  into the canonical chain's target ``T₀₆ = pre · T · post`` (or ``pre · T⁻¹ · post`` when
  the chain is read from the tool) and the per-joint post-processing, into one array ``K``;
* :func:`closed_form_solve` takes ``K`` and the pose and returns every solution, the
  post-processing of :func:`robokit.ik.solution.solutions_from_rows` included (flipped
  joints, wrapping to (−π, π], the ±2π shift into wide limits, the within-limits flag,
  duplicates dropped), with its branch code;
* :func:`closed_form_batch` runs it over N targets with ``prange``.

Branch codes (one row of ``codes`` per solution): ``[shoulder, elbow, wrist]`` with
shoulder 0 "right", 1 "left", 2 "shoulder singular", 3 none (prismatic joint 1); elbow 0
"elbow down", 1 "elbow up", 2 "d3 +", 3 "d3 −"; wrist 0 "no flip", 1 "flip", 2 "wrist
singular". The label strings are built in Python from these.

Position polynomial roots (Pieper, general case): the quartic in u = tan(θ₃/2) is solved as
the eigenvalues of its companion matrix (complex, so numba's ``eigvals`` never changes
domain), real ones polished by Newton steps on the polynomial; quadratics in closed form.

Example (``AnalyticIK`` packs the constants; ``ik_analytic`` and ``ik_analytic_batch`` call
these kernels)::

    >>> import numpy as np, robokit
    >>> from robokit.ik.closed_form import AnalyticIK
    >>> robot = robokit.load("puma560")
    >>> K = AnalyticIK(robot)._kernel[0]
    >>> closed_form_solve(K, robot.frame_pose(np.full(6, 0.3)), 0.0)[:, :6].shape
    (8, 6)
"""
from __future__ import annotations

import math
from typing import Any

import numpy as np

from robokit.kernels._jit import machine_code, njit, prange

__all__ = ["closed_form_solve", "closed_form_batch", "pieper_solve", "parallel_axes_solve", "pieper_batch",
           "pieper_position", "pieper_wrist", "pieper_rows", "parallel_axes_position",
           "parallel_axes_wrist", "parallel_axes_rows",
           "parallel_axes_batch", "pieper_solve_into", "parallel_axes_solve_into", "solve_into_entry", "pack_constants",
           "K_SIZE",
           "OUT_COLS", "MAX_ROWS", "PIEPER", "PARALLEL_AXES"]

#: The most rows one pose can produce before duplicates are dropped.
MAX_ROWS = 16
PIEPER = 0
PARALLEL_AXES = 1

_PI = math.pi
_TWO_PI = 2.0 * math.pi
#: The calibrated IK's fold starts (:func:`_pieper` with ``fold``, its entry 1 set): the arm itself,
#: not quite the projected one, may have two roots where the projected arm just has none; these
#: rows are where its polish starts looking for them. At a wrist's fold: a position whose wrist
#: (twists not right angles) misses the orientation by |cos θ₅| − 1 up to ``FOLD_STARTS`` still
#: gives two rows, at θ₅ = ±√(2 (|cos θ₅| − 1)) from the fold (θ₅ = 0 or π). At a position's fold:
#: a complex pair of roots t = a ± ib of the joint-3 polynomial gives a position at t = a when the
#: pair's joint-3 values are within ``FOLD_IMAG`` of the real line: for a revolute joint 3 (t =
#: tan(θ₃/2)) |Im 2 atan(a + ib)| = atanh(2b/(1 + a² + b²)) ≤ FOLD_IMAG rad; for a prismatic one
#: b ≤ FOLD_IMAG (1 + |a|) (m). At the three-parallel-axes method's elbow fold (:func:`_parallel_axes`
#: with ``fold``): a θ₁ and θ₅ whose planar 2-link elbow misses by |cos θ₃| − 1 up to ``FOLD_STARTS``
#: gives two rows, at θ₃ = ±√(2 (|cos θ₃| − 1)) from the fold (θ₃ = 0 or π); at its shoulder's fold,
#: where no θ₁ solves a cos θ₁ + b sin θ₁ = c (the wrist centre just inside the cylinder of radius the
#: shoulder offset about axis 1) but |c| / √(a² + b²) − 1 is at most ``FOLD_STARTS``, the two θ₁ at
#: ±√(2 (|c| / √(a² + b²) − 1)) from the fold (measured on a real UR5e's factory calibration: 3 of
#: 9,000 random reachable poses had no start without them). Such rows have ``FOLD_CODE`` added to
#: their wrist code.
#: Both windows are for the arms whose starts are off by up to ``robokit.ik.calibrated.ERROR_MEASURED``;
#: the calibrated kernel's fold switch (``fold[1]``) is the factor both are multiplied by for an arm
#: farther from its structure (:func:`robokit.ik.calibrated.search_constants`).
FOLD_STARTS = 0.1
FOLD_IMAG = 0.2
#: A fold position (a complex pair's real part) is itself off from the arm's position by about the square
#: root of the pair's imaginary part, so its wrist's window is wider: |cos θ₅| − 1 up to this. Measured on
#: the benchmark's calibrated random Pieper arm (3,000 random poses of ``default_rng(102)``, a 500-start
#: sweep each): one pose's fold position missed the orientation by 0.28, where the arm has two roots (the
#: generating configuration one of them), lost without a warning; with 0.5 none lost, one more pose
#: searched.
FOLD_POSITION_WRIST = 0.5
FOLD_CODE = 3
#: Where the three-parallel-axes method's wrist is near its singularity (ρ, the length θ₆ is taken from,
#: below ``FREE_WRIST`` times the fold switch ``fold[1]``), its θ₆ is as far off as the arm's errors
#: divided by ρ; so where the elbow misses by more than ``FOLD_STARTS`` at that θ₆, the calibrated IK
#: tries the θ₆ at which it comes nearest (:func:`_free_t6`: ``FREE_SAMPLES`` values, then
#: ``FREE_ITERATIONS`` golden-section steps), its rows fold starts: on the calibrated UR5 of the tests,
#: 33 of 3,000 random poses with θ₅ within 3 mrad of its singularity had no start (every elbow missed
#: by 0.12–0.9 at the θ₆ of a direction a few 1e-3 long), each within 0.01 of reaching at that θ₆,
#: the arm's roots 0.1–0.5 rad from it.
FREE_WRIST = 0.02
FREE_SAMPLES, FREE_ITERATIONS = 48, 40
#: Scratch sizes (floats, ints) of the position step and of Pieper's method (:func:`_pieper_position`, :func:`_pieper`).
_POS_WORK = 35

# layout of the float constants (Pieper)
_TH0, _D0, _CA, _SA = 0, 6, 12, 17
_A1, _A2, _D1, _D2 = 22, 23, 24, 25
_W3, _W6, _F, _KA, _KB, _V, _SCALE = 26, 29, 32, 41, 44, 47, 50
_PHI, _NF2, _KIND = 51, 57, 60  # φ₁, φ₂ (prismatic joint 2), ‖f‖², joints 1–3 revolute (1/0)
# layout of the float constants (parallel axes), after th0, d0, ca, sa as above
_PA_A1, _PA_A2, _PA_A3, _PA_A4, _PA_A5, _PA_D1, _PA_D5, _PA_D6, _PA_KW, _PA_W6, _PA_S2, _PA_SIG = (
    22, 23, 24, 25, 26, 27, 28, 29, 30, 31, 34, 35)


@njit
def _wrap(a: float) -> float:
    """(−π, π], as :func:`robokit.spatial.wrap_angle`."""
    w = np.fmod(a + _PI, _TWO_PI)
    if w <= 0.0:
        w += _TWO_PI
    return w - _PI


@njit(inline=True)
def _rem(v: float) -> float:
    """IEEE remainder of v by 2π (``math.remainder``). Inside (−π, π) that is v itself (the quotient
    rounds to 0), returned without the division: most joint values and differences are there."""
    if -_PI < v < _PI:
        return v
    n = v / _TWO_PI
    k = float(math.floor(n + 0.5))
    if k - n == 0.5 and k % 2.0 != 0.0:  # a tie: round half to even
        k -= 1.0
    return v - k * _TWO_PI


@njit
def _trig_roots(a: float, b: float, c: float, tol: float, out: np.ndarray) -> int:
    """Roots of a cos θ + b sin θ = c into ``out``; their count, or −1 when every θ solves it
    (as ``robokit.ik.paden_kahan._trig_roots``)."""
    r2 = a * a + b * b
    if r2 < 1e-300:
        return -1 if c == 0.0 else 0
    disc = r2 - c * c
    if disc < -tol * r2:
        return 0
    sq = math.sqrt(disc) if disc > 0.0 else 0.0
    A, C = a + c, c - a
    q = b + (sq if b >= 0.0 else -sq)
    if q == 0.0:
        out[0] = 0.0 if A != 0.0 else _PI
        return 1
    out[0] = _wrap(2.0 * math.atan2(q, A))
    if sq == 0.0:
        return 1
    out[1] = _wrap(2.0 * math.atan2(C, q))
    return 2


@njit
def _val(cf: np.ndarray, k: int, x: float, rev: bool, c: float, s: float) -> float:
    """Value of the coefficient triple cf[k:k+3] at θ (revolute: (cos, sin)) or q (prismatic)."""
    if rev:
        return cf[k] + cf[k + 1] * c + cf[k + 2] * s
    return cf[k] + (cf[k + 1] + cf[k + 2] * x) * x


@njit
def _newton_poly(c: np.ndarray, deg: int, t: float) -> float:
    for _ in range(3):
        p, dp = 0.0, 0.0
        for j in range(deg, -1, -1):
            dp = dp * t + p
            p = p * t + c[j]
        if dp == 0.0:
            break
        step = p / dp
        t -= step
        if abs(step) <= 1e-15 * (1.0 + abs(t)):
            break
    return t


@njit
def _roots(c: np.ndarray, ndeg: int, rev: bool, out: np.ndarray, fold: Any) -> int:
    """Real roots of Σ c_k t^k (k ≤ ndeg) as joint-3 values into ``out``; count, −1 if c ≡ 0.
    ``fold``: None, or :func:`_pieper`'s; with its entry 1 set, a quartic's complex pairs a ± ib
    within ``FOLD_IMAG`` of the real line add a at the end, ascending (``out`` (6,)), and entry 2
    is set to the number of real roots before them."""
    scale = 0.0
    for j in range(ndeg + 1):
        scale = max(scale, abs(c[j]))
    if scale == 0.0:
        return -1
    deg = ndeg
    while deg > 0 and abs(c[deg]) <= 1e-11 * scale:
        deg -= 1
    extra = rev and deg < ndeg
    n = 0
    nf = 0
    ts = out  # the roots t are sorted in place, then turned into joint values entry by entry
    if deg == 1:
        ts[0] = -c[0] / c[1]
        n = 1
    elif deg == 2:
        A, B, C0 = c[2], c[1], c[0]
        disc = B * B - 4.0 * A * C0
        if disc >= -1e-12 * max(B * B, abs(4.0 * A * C0), 1e-300):
            sq = math.sqrt(max(disc, 0.0))
            q = -0.5 * (B + (sq if B >= 0.0 else -sq))
            if q != 0.0:
                ts[0], ts[1] = q / A, C0 / q
                n = 2
            else:
                ts[0] = 0.0
                n = 1
    elif deg > 2:
        comp = np.zeros((deg, deg), dtype=np.complex128)
        for j in range(deg):
            comp[0, j] = -c[deg - 1 - j] / c[deg]
        for j in range(1, deg):
            comp[j, j - 1] = 1.0
        ev = np.linalg.eigvals(comp)
        for z in ev:
            if abs(z.imag) <= 1e-6 * (1.0 + abs(z.real)):
                t = _newton_poly(c, deg, z.real)
                k = n  # insertion: the real roots ascending (as the Python solver sorts them)
                while k > 0 and ts[k - 1] > t:
                    ts[k] = ts[k - 1]
                    k -= 1
                ts[k] = t
                n += 1
        if fold is not None:
            if fold[1] != 0.0 and deg == 4:
                for z in ev:  # a complex pair near the real line: its real part (ascending), after the real roots
                    a, b = z.real, z.imag
                    # the window grows with fold[1] (an arm farther from its structure: robokit.ik.calibrated)
                    near = ((2.0 * b <= math.tanh(FOLD_IMAG * fold[1]) * (1.0 + a * a + b * b)) if rev
                            else b <= FOLD_IMAG * fold[1] * (1.0 + abs(a)))
                    if b > 1e-6 * (1.0 + abs(a)) and near:
                        k = nf
                        while k > 0 and ts[4 + k - 1] > a:
                            ts[4 + k] = ts[4 + k - 1]
                            k -= 1
                        ts[4 + k] = a
                        nf += 1
    for j in range(n):
        out[j] = 2.0 * math.atan(ts[j]) if rev else ts[j]
    if extra:
        out[n] = _PI
        n += 1
    if fold is not None:
        fold[2] = n
        for j in range(nf):  # n + j ≤ 4 + j: no entry is overwritten before it is read
            out[n] = 2.0 * math.atan(ts[4 + j]) if rev else ts[4 + j]
            n += 1
    return n


@njit
def _angles(cf: np.ndarray, q: np.ndarray, th: np.ndarray, dd: np.ndarray) -> None:
    """Rotation angles and offsets of joints 1–3 at joint values q (kinds: ``cf[_KIND:_KIND + 3]``)."""
    for i in range(3):
        if cf[_KIND + i] != 0.0:
            th[i], dd[i] = cf[_TH0 + i] + q[i], cf[_D0 + i]
        else:
            th[i], dd[i] = cf[_TH0 + i], cf[_D0 + i] + q[i]


@njit
def _wrist_point(cf: np.ndarray, th: np.ndarray, dd: np.ndarray, W: np.ndarray) -> None:
    """⁰W for the rotation angles th and offsets dd of joints 1–3."""
    c3, s3 = math.cos(th[2]), math.sin(th[2])
    x, y, z = cf[_W3], cf[_W3 + 1], cf[_W3 + 2] + dd[2]
    x, y = c3 * x - s3 * y, s3 * x + c3 * y
    x += cf[_A2]
    c, s = cf[_CA + 1], cf[_SA + 1]
    y, z = c * y - s * z, s * y + c * z
    c2, s2 = math.cos(th[1]), math.sin(th[1])
    z += dd[1]
    x, y = c2 * x - s2 * y, s2 * x + c2 * y
    x += cf[_A1]
    c, s = cf[_CA], cf[_SA]
    y, z = c * y - s * z, s * y + c * z
    c1, s1 = math.cos(th[0]), math.sin(th[0])
    z += dd[0]
    W[0], W[1], W[2] = c1 * x - s1 * y, s1 * x + c1 * y, z


@njit
def _polish(cf: np.ndarray, q: np.ndarray, W: np.ndarray) -> float:
    """Newton steps (central-difference Jacobian, least squares) on ⁰W(q₁..q₃) = W; q in place."""
    th, dd, p = np.empty(3), np.empty(3), np.empty(3)
    p2, p3, qq = np.empty(3), np.empty(3), np.empty(3)
    J = np.empty((3, 3))
    e = np.empty((3, 1))
    err = np.inf
    scale = cf[_SCALE]
    for it in range(4):
        _angles(cf, q, th, dd)
        _wrist_point(cf, th, dd, p)
        for k in range(3):
            e[k, 0] = W[k] - p[k]
        err = max(abs(e[0, 0]), abs(e[1, 0]), abs(e[2, 0]))
        if err <= 1e-13 * scale or it == 3:
            break
        h = 1e-7
        for j in range(3):
            qq[:] = q
            qq[j] += h
            _angles(cf, qq, th, dd)
            _wrist_point(cf, th, dd, p2)
            qq[j] -= 2 * h
            _angles(cf, qq, th, dd)
            _wrist_point(cf, th, dd, p3)
            for k in range(3):
                J[k, j] = (p2[k] - p3[k]) / (2 * h)
        # the 3×3 Newton step by Cramer's rule (the Python solver's least squares, without
        # compiling LAPACK's: J is square); a numerically singular J ends the polishing
        c0 = J[1, 1] * J[2, 2] - J[1, 2] * J[2, 1]
        c1 = J[1, 2] * J[2, 0] - J[1, 0] * J[2, 2]
        c2 = J[1, 0] * J[2, 1] - J[1, 1] * J[2, 0]
        det = J[0, 0] * c0 + J[0, 1] * c1 + J[0, 2] * c2
        size = 1.0
        for j in range(3):
            size *= math.sqrt(J[0, j] ** 2 + J[1, j] ** 2 + J[2, j] ** 2)
        if abs(det) <= 1e-12 * size:
            break
        for j in range(3):
            A = J.copy()
            A[0, j], A[1, j], A[2, j] = e[0, 0], e[1, 0], e[2, 0]
            dj = (A[0, 0] * (A[1, 1] * A[2, 2] - A[1, 2] * A[2, 1]) - A[0, 1] * (A[1, 0] * A[2, 2] - A[1, 2] * A[2, 0])
                  + A[0, 2] * (A[1, 0] * A[2, 1] - A[1, 1] * A[2, 0]))
            q[j] += dj / det
    return err


@njit
def _wrist_angles(cf: np.ndarray, cs: np.ndarray, T: np.ndarray, q4_ref: float, out: np.ndarray,
                  flips: np.ndarray, fold: Any, window: float = FOLD_STARTS) -> int:
    """(θ₄, θ₅, θ₆) rows into ``out`` (2, 3) and wrist codes into ``flips``; their count
    (as ``PieperSolver.wrist_angles``). ``cs``: cos θ₁, sin θ₁, cos θ₂, sin θ₂, cos θ₃, sin θ₃
    (:func:`_cos_sin`, computed once per position). ``fold``: None, or :func:`_pieper`'s: its entry
    0 keeps the least |cos θ₅| − 1 of the wrists that cannot reach the orientation (twists not
    right angles: |cos θ₅| > 1; the calibrated IK says when that is near its fold); with its entry
    1 set, such a wrist short by at most ``FOLD_STARTS`` gives the two fold starts (wrist codes +
    ``FOLD_CODE``)."""
    mx, my, mz = T[0, 2], T[1, 2], T[2, 2]
    ex, ey, ez = T[0, 0], T[1, 0], T[2, 0]
    for i in range(3):
        c, s_ = cs[2 * i], cs[2 * i + 1]
        mx, my = c * mx + s_ * my, c * my - s_ * mx
        ex, ey = c * ex + s_ * ey, c * ey - s_ * ex
        c, s_ = cf[_CA + i], cf[_SA + i]
        my, mz = c * my + s_ * mz, c * mz - s_ * my
        ey, ez = c * ey + s_ * ez, c * ez - s_ * ey
    nx, ny, nz = 0.0, 0.0, 1.0
    for i in range(2, -1, -1):
        c, s_ = cf[_CA + i], cf[_SA + i]
        ny, nz = c * ny - s_ * nz, s_ * ny + c * nz
        c, s_ = cs[2 * i], cs[2 * i + 1]
        nx, ny = c * nx - s_ * ny, s_ * nx + c * ny
    row0 = T[0, 0] * nx + T[1, 0] * ny + T[2, 0] * nz
    row1 = T[0, 1] * nx + T[1, 1] * ny + T[2, 1] * nz
    ca4, sa4, ca5, sa5 = cf[_CA + 3], cf[_SA + 3], cf[_CA + 4], cf[_SA + 4]
    k = sa4 * sa5
    rho = math.hypot(mx, my)
    fcode = 0
    if ca4 == 0.0 and ca5 == 0.0:
        c5, s5 = -mz / k, rho
    else:
        c5 = (ca4 * ca5 - mz) / k
        if abs(c5) > 1.0 + 1e-10:
            if fold is None:
                return 0
            short = abs(c5) - 1.0
            fold[0] = min(fold[0], short)
            if fold[1] == 0.0 or short > window * fold[1]:
                return 0
            fcode = FOLD_CODE  # near the fold: two starts, θ₅ = ±√(2 short) from it
            c5 = math.copysign(math.cos(math.sqrt(2.0 * short)), c5)
        c5 = max(-1.0, min(1.0, c5))
        s5 = math.sqrt(max(0.0, 1.0 - c5 * c5))
        yp0 = -ca4 * sa5 * c5 - sa4 * ca5
        if fcode == 0 and s5 < 0.5 and abs(sa5) > 0.5 and abs(yp0) <= 0.5 * rho:
            # |sin θ₅| from the wrist direction's length across axis 4 (ρ² = (sin α₅ sin θ₅)² + yp²),
            # not from 1 − cos² θ₅, which loses its digits near the singularity
            s5 = math.sqrt(rho * rho - yp0 * yp0) / abs(sa5)
    if rho <= 1e-10:
        th4_ref = q4_ref + cf[_TH0 + 3]
        gamma = math.atan2(ca4 * s5, c5)
        sk = 1.0 if mz > 0.0 else -1.0
        out[0, 0] = th4_ref
        out[0, 1] = math.atan2(s5, c5)
        out[0, 2] = sk * (math.atan2(ey, ex) - th4_ref - gamma)
        flips[0] = 2
        return 1
    am = math.atan2(my, mx)
    ar = math.atan2(row1, row0)
    yp = -ca4 * sa5 * c5 - sa4 * ca5
    b_ = sa4 * c5 * ca5 + ca4 * sa5
    n = 0
    t5 = math.atan2(s5, c5)
    for j in range(2):
        s = s5 if j == 0 else -s5
        out[n, 0] = am - math.atan2(yp, sa5 * s)
        out[n, 1] = t5 if j == 0 else -t5  # atan2(−s, c) = −atan2(s, c) exactly (IEEE atan2 is odd in y)
        out[n, 2] = math.atan2(b_, sa4 * s) - ar
        if rho < 1e-4:
            # near the singularity θ₄ and θ₆ are each taken from vectors of length ρ (their rounding
            # / ρ off), their sum from the whole rotation: θ₆ from what θ₄ and θ₅ leave of it
            x, y, z = ex, ey, ez
            c, s_ = math.cos(out[n, 0]), math.sin(out[n, 0])
            x, y = c * x + s_ * y, c * y - s_ * x
            y, z = ca4 * y + sa4 * z, ca4 * z - sa4 * y
            c, s_ = math.cos(out[n, 1]), math.sin(out[n, 1])
            x, y = c * x + s_ * y, c * y - s_ * x
            y = ca5 * y + sa5 * z
            out[n, 2] = math.atan2(y, x)
        flips[n] = (0 if s * k > 0.0 else 1) + fcode
        n += 1
        if s5 == 0.0:
            break
    return n


@njit
def _cos_sin(th: np.ndarray, cs: np.ndarray) -> None:
    """cos θ₁, sin θ₁, cos θ₂, sin θ₂, cos θ₃, sin θ₃ into ``cs`` (6,)."""
    for i in range(3):
        cs[2 * i], cs[2 * i + 1] = math.cos(th[i]), math.sin(th[i])


@njit
def _scratch() -> tuple:
    """Every scratch array of one solve, from seven allocations, 2D ones sliced by rows (a numba
    ``reshape`` costs as much as an allocation): ``F6`` (2·MAX_ROWS, 6) raw rows | cos/sin of
    θ₁–θ₃; ``F4`` (10, 4) target | product | position candidates; ``F3`` (2·MAX_ROWS + 2, 3)
    q₁–q₃ | θ₁–θ₃ | wrist angles; ``I3`` (2·MAX_ROWS, 3) raw codes | position codes; ``iw`` (8,)
    ci | wrist codes or θ₁ shoulders; ``bw`` (2·MAX_ROWS,) raw | position degenerate flags; ``fw``
    the position step's floats (:data:`_POS_WORK`), qq (6), θ₁ and θ₅ roots (4)."""
    return (np.empty((2 * MAX_ROWS, 6)), np.empty((10, 4)), np.empty((2 * MAX_ROWS + 2, 3)),
            np.empty((2 * MAX_ROWS, 3), dtype=np.int64), np.empty(8, dtype=np.int64),
            np.empty(2 * MAX_ROWS, dtype=np.bool_), np.empty(_POS_WORK + 10))


@njit
def _raw_rows() -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Buffers for a solver's raw rows: q (MAX_ROWS, 6), branch codes (MAX_ROWS, 3), degenerate (MAX_ROWS,)."""
    return (np.empty((MAX_ROWS, 6)), np.empty((MAX_ROWS, 3), dtype=np.int64), np.empty(MAX_ROWS, dtype=np.bool_))


@njit
def _first(n: int, Q: np.ndarray, codes: np.ndarray, degen: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Copies of the first n raw rows (what the raw-row kernels return to Python)."""
    return Q[:n].copy(), codes[:n].copy(), degen[:n].copy()


@njit
def _quad_roots(A: float, B: float, C: float, out: np.ndarray) -> int:
    """Real roots of A x² + B x + C (A ≠ 0) into ``out`` (the cancellation-free pair); their count."""
    disc = B * B - 4.0 * A * C
    if disc < -1e-12 * max(B * B, abs(4.0 * A * C), 1e-300):
        return 0
    sq = math.sqrt(max(disc, 0.0))
    qv = -0.5 * (B + (sq if B >= 0.0 else -sq))
    if qv == 0.0:
        out[0] = 0.0
        return 1
    out[0] = qv / A
    if sq > 0.0:
        out[1] = C / qv
        return 2
    return 1


@njit
def _pieper_position(ci: np.ndarray, cf: np.ndarray, C: np.ndarray, T: np.ndarray, Q3: np.ndarray,
                     codes: np.ndarray, degen: np.ndarray, TH: np.ndarray, CS: np.ndarray, fw: np.ndarray,
                     cand: np.ndarray, fold: Any) -> int:
    """Pieper's position sub-problem: every (q₁, q₂, q₃) placing the wrist centre ⁰W = T·⁶W.

    Writes per branch the joint values into ``Q3`` (rows of 3), the shoulder and elbow codes into
    ``codes`` (rows of 2), the degenerate flag into ``degen``, the rotation angles θ₁–θ₃ into
    ``TH`` and their cosines and sines (:func:`_cos_sin`, what the wrist step needs) into ``CS``
    (rows of 6); ``fw`` (at least ``_POS_WORK`` floats) and ``cand`` (2, 4) are scratch; returns
    the number of branches. ``fold``: None, or :func:`_pieper`'s (with its entry 1 set, the
    positions of :func:`_roots`' near-real complex pairs follow the exact ones, unchecked; entry 2
    is set to the number of exact ones). Cases (``ci[1]``): 0 RR-quartic,
    1 RR-a1, 2 RR-s1, 3 PR-quartic, 4 PR-c1, 5 RP-quartic, 6 RP-c1, 7 PP (the kinds of joints 1, 2;
    ``PieperConstants.case``)."""
    case, rev3, deg, nrows = ci[1], ci[2] == 1, ci[3], ci[4]
    rev1, rev2 = case <= 2 or case == 5 or case == 6, case <= 4
    scale = cf[_SCALE]
    w6x, w6y, w6z = cf[_W6], cf[_W6 + 1], cf[_W6 + 2]
    # scratch, carved from fw (no allocation per call)
    W, m, coeffs, roots3 = fw[0:3], fw[3:8], fw[8:13], fw[13:19]
    th2s, q = fw[19:21], fw[21:24]
    th, dd, p, Ds = fw[24:27], fw[27:30], fw[30:33], fw[33:35]
    W[0] = T[0, 0] * w6x + T[0, 1] * w6y + T[0, 2] * w6z + T[0, 3]
    W[1] = T[1, 0] * w6x + T[1, 1] * w6y + T[1, 2] * w6z + T[1, 3]
    W[2] = T[2, 0] * w6x + T[2, 1] * w6y + T[2, 2] * w6z + T[2, 3]
    Wx, Wy, Wz = W[0], W[1], W[2]
    ca1, sa1, a1 = cf[_CA], cf[_SA], cf[_A1]
    m[:] = 0.0
    h, r, X, yp = 0.0, 0.0, 0.0, 0.0
    if rev1:  # rotating about axis 1 keeps h and r
        h = Wz - cf[_D1]
        r = Wx * Wx + Wy * Wy + h * h
    else:  # prismatic joint 1: W in frame 0′ turned by θ₁'s offset
        c0, s0 = math.cos(cf[_TH0]), math.sin(cf[_TH0])
        yp = -s0 * Wx + c0 * Wy
        X = c0 * Wx + s0 * Wy - a1
    if case == 0:
        m[0], m[1], m[2], m[3], m[4] = r * r, r, h * h, h, 1.0
    elif case == 1:
        m[0], m[1] = r, 1.0
    elif case == 2 or case == 6:
        m[0], m[1] = h, 1.0
    elif case == 3:
        m[0], m[1], m[2], m[3] = X * X, yp * yp, yp, 1.0
    elif case == 4:
        m[0], m[1] = yp, 1.0
    elif case == 5:
        m[0], m[1], m[2], m[3] = r, h * h, h, 1.0
    else:
        m[0], m[1] = X, 1.0
    coeffs[:] = 0.0
    for j in range(deg + 1):
        acc = 0.0
        for k in range(nrows):
            acc += m[k] * C[k, j]
        coeffs[j] = acc
    nr = _roots(coeffs, deg, rev3, roots3, fold)
    check = deg == 4  # roots from the companion matrix: verify (and polish) each triple
    degenerate = False
    nreal = nr
    if nr < 0:  # the equation holds for every joint-3 value: the documented choice q₃ = 0
        roots3[0] = cf[_TH0 + 2] if rev3 else 0.0
        nr = 1
        nreal = 1
        degenerate = True
    elif fold is not None:
        nreal = int(fold[2])  # then the fold positions' joint-3 values
    # cand: (q₂, g₁, g₂, g₃) per candidate
    n = 0
    nexact = -1
    for ir in range(nr):
        if ir == nreal:
            nexact = n
        x3 = roots3[ir]
        c3, s3 = (math.cos(x3), math.sin(x3)) if rev3 else (0.0, 0.0)
        f1 = _val(cf, _F, x3, rev3, c3, s3)
        f2 = _val(cf, _F + 3, x3, rev3, c3, s3)
        f3 = _val(cf, _F + 6, x3, rev3, c3, s3)
        q3 = x3 - cf[_TH0 + 2] if rev3 else x3
        nc = 0
        if rev2:
            F3 = f3 + cf[_D2]
            if rev1:
                sa_, ra = 2.0 * a1, r - _val(cf, _KA, x3, rev3, c3, s3)
                sb_, rb = sa1, h - ca1 * F3
            else:
                sa_, ra = 1.0, X
                sb_, rb = ca1, yp + sa1 * F3
            if case == 0 or case == 3:
                n2 = f1 * f1 + f2 * f2
                if n2 > 1e-24 * scale * scale:
                    A, B = ra / sa_, rb / sb_
                    th2s[0] = math.atan2(f1 * B - f2 * A, f1 * A + f2 * B)
                else:
                    th2s[0] = cf[_TH0 + 1]
                    degenerate = True
                n2s = 1
            elif case == 1:  # θ₂ from eq. b: sb(F₂c₂ + F₁s₂) = rb
                n2s = _trig_roots(sb_ * f2, sb_ * f1, rb, 1e-10, th2s)
            else:  # RR-s1, PR-c1: θ₂ from eq. a: sa(F₁c₂ − F₂s₂) = ra
                n2s = _trig_roots(sa_ * f1, -sa_ * f2, ra, 1e-10, th2s)
            if n2s < 0:
                th2s[0] = cf[_TH0 + 1]
                n2s = 1
                degenerate = True
            for i2 in range(n2s):
                t2 = th2s[i2]
                c2, s2 = math.cos(t2), math.sin(t2)
                u = s2 * f1 + c2 * f2
                cand[nc, 0], cand[nc, 1] = t2 - cf[_TH0 + 1], a1 + c2 * f1 - s2 * f2
                cand[nc, 2], cand[nc, 3] = ca1 * u - sa1 * F3, sa1 * u + ca1 * F3
                nc += 1
        else:  # prismatic joint 2: its offset D enters h linearly and r quadratically
            p1 = _val(cf, _PHI, x3, rev3, c3, s3)
            p2 = _val(cf, _PHI + 3, x3, rev3, c3, s3)
            if case == 5:
                Ds[0] = (h - sa1 * p2) / ca1 - f3
                nD = 1
            elif case == 6:
                nf2 = _val(cf, _NF2, x3, rev3, c3, s3)
                nD = _quad_roots(1.0, 2.0 * f3, a1 * a1 + nf2 + 2.0 * a1 * p1 - r, Ds)
            else:
                Ds[0] = (ca1 * p2 - yp) / sa1 - f3
                nD = 1
            for iD in range(nD):
                D = Ds[iD]
                cand[nc, 0], cand[nc, 1] = D - cf[_D0 + 1], a1 + p1
                cand[nc, 2], cand[nc, 3] = ca1 * p2 - sa1 * (f3 + D), sa1 * p2 + ca1 * (f3 + D)
                nc += 1
        for ic in range(nc):
            g1, g2, g3 = cand[ic, 1], cand[ic, 2], cand[ic, 3]
            singular1 = False
            if rev1:
                if math.hypot(g1, g2) <= 1e-12 * scale:
                    t1, singular1 = cf[_TH0], True
                else:
                    t1 = math.atan2(Wy, Wx) - math.atan2(g2, g1)
                q[0] = t1 - cf[_TH0]
            else:
                q[0] = Wz - cf[_D0] - g3
            q[1], q[2] = cand[ic, 0], q3
            if check and ir < nreal:
                _angles(cf, q, th, dd)
                _wrist_point(cf, th, dd, p)
                err = max(abs(W[0] - p[0]), abs(W[1] - p[1]), abs(W[2] - p[2]))
                if err > 1e-12 * scale:
                    if err > 1e-5 * scale:
                        continue  # a spurious root (a complex pair taken as real)
                    err = _polish(cf, q, W)
                    if err > 1e-11 * scale:
                        continue
            if n >= Q3.shape[0]:
                break
            _angles(cf, q, th, dd)
            cs = CS[n]
            _cos_sin(th, cs)
            # labels: shoulder from frame 1's x axis, elbow from the sign of the normal's cross product
            if not rev1:
                codes[n, 0] = 3
            elif singular1:
                codes[n, 0] = 2
            else:
                codes[n, 0] = 0 if cs[0] * W[0] + cs[1] * W[1] >= 0.0 else 1
            if not rev3:
                codes[n, 1] = 2 if cf[_D0 + 2] + q[2] >= 0.0 else 3
            else:
                e = (cs[5] * cf[_V] + cs[4] * cf[_V + 1]) * (cf[_A2] if cf[_A2] != 0.0 else 1.0)
                codes[n, 1] = 0 if e > 0.0 else 1
            for j in range(3):
                Q3[n, j] = q[j]
                TH[n, j] = th[j]
            degen[n] = degenerate or singular1
            n += 1
    if fold is not None:
        fold[2] = n if nexact < 0 else nexact
    return n


@njit
def _pieper(ci: np.ndarray, cf: np.ndarray, C: np.ndarray, T: np.ndarray, q4_ref: float, Q: np.ndarray,
            codes: np.ndarray, degen: np.ndarray, s: tuple, fold: Any) -> int:
    """Pieper's method (every case of :func:`_pieper_position`, then the wrist's two branches
    of each position): raw rows into Q, codes, degen; their count. ``s``: the scratch of
    :func:`_scratch`; ``fold``: None (compiles none of it), or the calibrated IK's (3,) float64:
    entry 0 the least shortfall of a wrist (:func:`_wrist_angles`; the caller sets it to inf),
    entry 1 set (1.0) by the caller for fold starts (``FOLD_STARTS``), entry 2 scratch."""
    F6, F4, F3, I3, iw, bw, fw = s
    Q3, TH, wa = F3[0:MAX_ROWS], F3[MAX_ROWS:2 * MAX_ROWS], F3[2 * MAX_ROWS:2 * MAX_ROWS + 2]
    CS, pcodes, flips, pdegen = F6[MAX_ROWS:], I3[MAX_ROWS:], iw[6:8], bw[MAX_ROWS:]
    npos = _pieper_position(ci, cf, C, T, Q3, pcodes, pdegen, TH, CS, fw, F4[8:10], fold)
    nexact = npos
    if fold is not None:
        nexact = int(fold[2])  # the positions from here on are fold starts
    n = 0
    for b in range(npos):
        # (a fold position is itself off by about the square root of its pair's imaginary part: its
        # wrist's window is wider, FOLD_POSITION_WRIST)
        nw = _wrist_angles(cf, CS[b], T, q4_ref, wa, flips, fold, FOLD_POSITION_WRIST if b >= nexact else FOLD_STARTS)
        if b >= nexact:
            for k in range(nw):
                if flips[k] < FOLD_CODE:
                    flips[k] += FOLD_CODE
        for k in range(nw):
            if n >= Q.shape[0]:
                break
            Q[n, 0], Q[n, 1], Q[n, 2] = Q3[b, 0], Q3[b, 1], Q3[b, 2]
            Q[n, 3] = wa[k, 0] - cf[_TH0 + 3]
            Q[n, 4] = wa[k, 1] - cf[_TH0 + 4]
            Q[n, 5] = wa[k, 2] - cf[_TH0 + 5]
            codes[n, 0], codes[n, 1], codes[n, 2] = pcodes[b, 0], pcodes[b, 1], flips[k]
            degen[n] = pdegen[b] or flips[k] == 2
            n += 1
    return n


@njit
def pieper_position(ci: np.ndarray, cf: np.ndarray, C: np.ndarray,
                    T06: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Pieper's position sub-problem for the canonical chain's target T06 (no base′/tool′, no
    reversal): ``(q (m, 3), codes (m, 2) shoulder/elbow, degenerate (m,), θ₁–θ₃ (m, 3))``."""
    Q3 = np.empty((MAX_ROWS, 3))
    codes = np.empty((MAX_ROWS, 2), dtype=np.int64)
    degen = np.empty(MAX_ROWS, dtype=np.bool_)
    TH = np.empty((MAX_ROWS, 3))
    n = _pieper_position(ci, cf, C, T06, Q3, codes, degen, TH, np.empty((MAX_ROWS, 6)), np.empty(_POS_WORK),
                         np.empty((2, 4)), None)
    return Q3[:n].copy(), codes[:n].copy(), degen[:n].copy(), TH[:n].copy()


@njit
def pieper_wrist(cf: np.ndarray, th: np.ndarray, T06: np.ndarray, q4_ref: float) -> tuple[np.ndarray, np.ndarray]:
    """Pieper's wrist sub-problem for the rotation angles θ₁–θ₃ ``th``: ``(θ₄, θ₅, θ₆ (m, 3), wrist codes (m,))``."""
    out = np.empty((2, 3))
    flips = np.empty(2, dtype=np.int64)
    cs = np.empty(6)
    _cos_sin(th, cs)
    n = _wrist_angles(cf, cs, T06, q4_ref, out, flips, None)
    return out[:n].copy(), flips[:n].copy()


@njit
def pieper_rows(ci: np.ndarray, cf: np.ndarray, C: np.ndarray, T06: np.ndarray,
                q4_ref: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Every raw row of Pieper's method for the canonical chain's target T06 (before wrapping,
    limits and de-duplication): ``(q (m, 6), codes (m, 3), degenerate (m,))``."""
    Q, codes, degen = _raw_rows()
    n = _pieper(ci, cf, C, T06, q4_ref, Q, codes, degen, _scratch(), None)
    return _first(n, Q, codes, degen)


@njit(inline=True)
def _shoulder_equation(cf: np.ndarray, T: np.ndarray) -> tuple[float, float, float, float, float]:
    """Step 1's equation a cos θ₁ + b sin θ₁ = c (W's coordinate along the parallel axes): (a, b, c), and
    W's x and y, which give each root its shoulder code (:func:`_shoulder_codes`)."""
    Wx = T[0, 0] * cf[_PA_W6] + T[0, 1] * cf[_PA_W6 + 1] + T[0, 2] * cf[_PA_W6 + 2] + T[0, 3]
    Wy = T[1, 0] * cf[_PA_W6] + T[1, 1] * cf[_PA_W6 + 1] + T[1, 2] * cf[_PA_W6 + 2] + T[1, 3]
    Wz = T[2, 0] * cf[_PA_W6] + T[2, 1] * cf[_PA_W6 + 1] + T[2, 2] * cf[_PA_W6 + 2] + T[2, 3]
    ca1, sa1 = cf[_CA], cf[_SA]
    return -sa1 * Wy, sa1 * Wx, cf[_PA_KW] - ca1 * (Wz - cf[_PA_D1]), Wx, Wy


@njit(inline=True)
def _shoulder_codes(cf: np.ndarray, Wx: float, Wy: float, t1s: np.ndarray, shoulders: np.ndarray, n1: int) -> None:
    """Each θ₁'s shoulder code: 0 where W lies on the side of axis 1 its normal points to, else 1."""
    for i1 in range(n1):
        c1, s1 = math.cos(t1s[i1]), math.sin(t1s[i1])
        shoulders[i1] = 0 if (c1 * Wx + s1 * Wy) * cf[_SA] >= 0.0 else 1


@njit
def _parallel_shoulders(cf: np.ndarray, T: np.ndarray, t1s: np.ndarray, shoulders: np.ndarray) -> int:
    """Step 1 of the three-parallel-axes method: every θ₁ (rotation angle) into ``t1s`` and its
    shoulder code into ``shoulders``; their count."""
    a, b, c, Wx, Wy = _shoulder_equation(cf, T)
    n1 = max(_trig_roots(a, b, c, 1e-10, t1s), 0)
    _shoulder_codes(cf, Wx, Wy, t1s, shoulders, n1)
    return n1


@njit
def _shoulder_folds(cf: np.ndarray, T: np.ndarray, window: float, t1s: np.ndarray, shoulders: np.ndarray) -> int:
    """The calibrated IK's fold starts of step 1 where it has no θ₁: a cos θ₁ + b sin θ₁ = c with
    |c| / √(a² + b²) − 1 = short ≤ ``window``: the two θ₁ at ±√(2 short) from the fold (where
    a cos θ₁ + b sin θ₁ comes nearest c), each with its shoulder code as :func:`_parallel_shoulders`
    gives it; their count (0 outside the window)."""
    a, b, c, Wx, Wy = _shoulder_equation(cf, T)
    r = math.sqrt(a * a + b * b)
    if r < 1e-150:
        return 0
    short = abs(c) / r - 1.0
    if short > window:
        return 0
    fold = math.atan2(b, a) if c > 0.0 else math.atan2(-b, -a)
    d = math.sqrt(2.0 * max(short, 0.0))
    t1s[0], t1s[1] = _wrap(fold + d), _wrap(fold - d)
    _shoulder_codes(cf, Wx, Wy, t1s, shoulders, 2)
    return 2


@njit(inline=True)
def _parallel_plane(cf: np.ndarray, T: np.ndarray, c1: float, s1: float, c5: float, s5: float, c6: float,
                    s6: float) -> tuple[float, float]:
    """Frame 4's origin in the plane of the three parallel axes (x, y), for θ₁, θ₅, θ₆ given by their
    cosines and sines (:func:`_parallel_complete`'s step 4)."""
    ca1, sa1, ca5, sa5 = cf[_CA], cf[_SA], cf[_CA + 4], cf[_SA + 4]
    a1, a4, a5, d1, d5, d6 = cf[_PA_A1], cf[_PA_A4], cf[_PA_A5], cf[_PA_D1], cf[_PA_D5], cf[_PA_D6]
    ox, oy, oz = -a4, 0.0, 0.0
    ox, oy, oz = c5 * ox + s5 * oy, -s5 * ox + c5 * oy, oz - d5
    ox, oy, oz = ox - a5, ca5 * oy + sa5 * oz, -sa5 * oy + ca5 * oz
    ox, oy, oz = c6 * ox + s6 * oy, -s6 * ox + c6 * oy, oz - d6
    O0 = T[0, 3] + T[0, 0] * ox + T[0, 1] * oy + T[0, 2] * oz - a1 * c1
    O1 = T[1, 3] + T[1, 0] * ox + T[1, 1] * oy + T[1, 2] * oz - a1 * s1
    O2 = T[2, 3] + T[2, 0] * ox + T[2, 1] * oy + T[2, 2] * oz - d1
    return c1 * O0 + s1 * O1, -s1 * ca1 * O0 + c1 * ca1 * O1 + sa1 * O2


@njit
def _free_t6(cf: np.ndarray, T: np.ndarray, c1: float, s1: float, c5: float, s5: float) -> float:
    """The θ₆ at which the planar elbow comes nearest to reaching frame 4's origin (least
    |x² + y² − a₂² − a₃²|, i.e. least |cos θ₃|), θ₁ and θ₅ given: the calibrated IK's start where the
    wrist is near its singularity (``FREE_WRIST``). x and y are affine in (cos θ₆, sin θ₆), so three
    points give them; the least of ``FREE_SAMPLES`` equally spaced values, then golden-section search
    (``FREE_ITERATIONS``) within one spacing of it."""
    x0, y0 = _parallel_plane(cf, T, c1, s1, c5, s5, 1.0, 0.0)
    xp, yp = _parallel_plane(cf, T, c1, s1, c5, s5, -1.0, 0.0)
    xh, yh = _parallel_plane(cf, T, c1, s1, c5, s5, 0.0, 1.0)
    xa, ya = 0.5 * (x0 + xp), 0.5 * (y0 + yp)
    xu, yu = 0.5 * (x0 - xp), 0.5 * (y0 - yp)
    xv, yv = xh - xa, yh - ya
    k2 = cf[_PA_A2] * cf[_PA_A2] + cf[_PA_A3] * cf[_PA_A3]
    h = _TWO_PI / FREE_SAMPLES
    best, tb = math.inf, 0.0
    for k in range(FREE_SAMPLES):
        th = k * h - _PI
        c, s = math.cos(th), math.sin(th)
        x, y = xa + xu * c + xv * s, ya + yu * c + yv * s
        f = abs(x * x + y * y - k2)
        if f < best:
            best, tb = f, th
    lo, hi = tb - h, tb + h
    g = 0.5 * (math.sqrt(5.0) - 1.0)
    for _ in range(FREE_ITERATIONS):
        a, b = hi - g * (hi - lo), lo + g * (hi - lo)
        ca, sa, cb, sb = math.cos(a), math.sin(a), math.cos(b), math.sin(b)
        xa_, ya_ = xa + xu * ca + xv * sa, ya + yu * ca + yv * sa
        xb_, yb_ = xa + xu * cb + xv * sb, ya + yu * cb + yv * sb
        if abs(xa_ * xa_ + ya_ * ya_ - k2) <= abs(xb_ * xb_ + yb_ * yb_ - k2):
            hi = b
        else:
            lo = a
    return 0.5 * (lo + hi)


@njit
def _parallel_complete(cf: np.ndarray, T: np.ndarray, t1: float, shoulder: int, q6_ref: float, Q: np.ndarray,
                       codes: np.ndarray, degen: np.ndarray, n: int, t5s: np.ndarray, fold: Any = None,
                       folded: bool = False) -> int:
    """Steps 2–4 for one θ₁ (θ₅, θ₆, the planar θ₂–θ₄): raw rows appended to Q, codes, degen
    from row n; the new row count. ``t5s``: scratch for the θ₅ roots (2,). ``fold``: None (compiles
    none of it), or the calibrated IK's (:func:`_pieper`'s): with its entry 1 set, an elbow short of
    reaching by at most ``FOLD_STARTS`` gives the two fold starts (wrist codes + ``FOLD_CODE``), and
    where it misses by more with the wrist near its singularity, θ₆ is tried again (``FREE_WRIST``);
    ``folded``: θ₁ is a shoulder's fold start (:func:`_shoulder_folds`), so every row is one."""
    r00, r01, r02 = T[0, 0], T[0, 1], T[0, 2]
    r10, r11, r12 = T[1, 0], T[1, 1], T[1, 2]
    r20, r21, r22 = T[2, 0], T[2, 1], T[2, 2]
    ca1, sa1 = cf[_CA], cf[_SA]
    ca4, sa4, ca5, sa5 = cf[_CA + 3], cf[_SA + 3], cf[_CA + 4], cf[_SA + 4]
    a2, a3, sig, sgn2 = cf[_PA_A2], cf[_PA_A3], cf[_PA_SIG], cf[_PA_S2]
    right_angles = ca4 == 0.0 and ca5 == 0.0
    c1, s1 = math.cos(t1), math.sin(t1)
    ux, uy, uz = sa1 * s1, -sa1 * c1, ca1
    utx = sig * (r00 * ux + r10 * uy + r20 * uz)
    uty = sig * (r01 * ux + r11 * uy + r21 * uz)
    utz = sig * (r02 * ux + r12 * uy + r22 * uz)
    rho = math.hypot(utx, uty)
    if right_angles:
        c5r = -utz / (sa4 * sa5)
        if rho > 1e-10:
            t5s[0], t5s[1] = math.atan2(rho, c5r), math.atan2(-rho, c5r)
            n5 = 2
        else:
            t5s[0] = math.atan2(0.0, c5r)
            n5 = 1
    else:
        n5 = _trig_roots(-sa4 * sa5, 0.0, utz - ca4 * ca5, 1e-10, t5s)
    for i5 in range(max(n5, 0)):
        t5 = t5s[i5]
        c5, s5 = math.cos(t5), math.sin(t5)
        vx, vy = s5 * sa4, ca5 * c5 * sa4 + sa5 * ca4
        if rho <= 1e-10:
            t6, degenerate = cf[_TH0 + 5] + q6_ref, True
        else:
            t6, degenerate = math.atan2(vy, vx) - math.atan2(uty, utx), False
        fc = FOLD_CODE if folded else 0
        for attempt in range(2):
            c6, s6 = math.cos(t6), math.sin(t6)
            gx0, gy0, gz0 = c5, -ca5 * s5, sa5 * s5
            gxa, gxb, gxc = c6 * gx0 + s6 * gy0, -s6 * gx0 + c6 * gy0, gz0
            X0 = r00 * gxa + r01 * gxb + r02 * gxc
            X1 = r10 * gxa + r11 * gxb + r12 * gxc
            X2 = r20 * gxa + r21 * gxb + r22 * gxc
            x, y = _parallel_plane(cf, T, c1, s1, c5, s5, c6, s6)
            phi = math.atan2(-s1 * ca1 * X0 + c1 * ca1 * X1 + sa1 * X2, c1 * X0 + s1 * X1)
            c3 = (x * x + y * y - a2 * a2 - a3 * a3) / (2.0 * a2 * a3)
            if attempt == 1 or abs(c3) <= 1.0 + 1e-10:
                break
            if fold is None:
                break
            if fold[1] == 0.0 or abs(c3) - 1.0 <= FOLD_STARTS * fold[1] or rho >= FREE_WRIST * fold[1]:
                break
            # the elbow misses by more than the fold starts' window, the wrist near its singularity: θ₆
            # where the elbow comes nearest reaching (FREE_WRIST), its rows fold starts
            t6 = _free_t6(cf, T, c1, s1, c5, s5)
            fc = FOLD_CODE
        if abs(c3) > 1.0 + 1e-10:
            if fold is None:
                continue
            if fold[1] == 0.0 or abs(c3) - 1.0 > FOLD_STARTS * fold[1]:
                continue
            fc = FOLD_CODE  # the elbow just short of reaching: two starts, th3 = +-sqrt(2 short) from its fold
            s3f = math.sqrt(2.0 * (abs(c3) - 1.0))
            c3 = 1.0 if c3 > 0.0 else -1.0
            s3a = s3f
        else:
            c3 = max(-1.0, min(1.0, c3))
            s3a = math.sqrt(max(0.0, 1.0 - c3 * c3))
        wrist = (2 if degenerate else (0 if s5 * sa4 * sa5 > 0.0 else 1)) + fc
        base = math.atan2(y, x)
        for k3 in range(2 if s3a > 0.0 else 1):
            s3 = (s3a if k3 == 0 else -s3a) if s3a > 0.0 else 0.0
            psi = math.atan2(s3, c3)
            t2 = base - math.atan2(a3 * s3, a2 + a3 * c3)
            t3, t4 = sgn2 * psi, sig * (phi - t2 - psi)
            if n >= Q.shape[0]:
                break
            Q[n, 0] = t1 - cf[_TH0]
            Q[n, 1] = t2 - cf[_TH0 + 1]
            Q[n, 2] = t3 - cf[_TH0 + 2]
            Q[n, 3] = t4 - cf[_TH0 + 3]
            Q[n, 4] = t5 - cf[_TH0 + 4]
            Q[n, 5] = t6 - cf[_TH0 + 5]
            codes[n, 0] = shoulder
            codes[n, 1] = 0 if a2 * a3 * s3 > 0.0 else 1
            codes[n, 2] = wrist
            degen[n] = degenerate
            n += 1
    return n


@njit
def _parallel_axes(cf: np.ndarray, T: np.ndarray, q6_ref: float, Q: np.ndarray, codes: np.ndarray,
                   degen: np.ndarray, s: tuple, fold: Any = None) -> int:
    """The three-parallel-axes method (step 1, then steps 2–4 of each θ₁): raw rows; their count.
    ``s``: the scratch of :func:`_scratch`; ``fold``: :func:`_parallel_complete`'s."""
    fw, iw = s[6], s[4]
    t1s, t5s, shoulders = fw[_POS_WORK + 6:_POS_WORK + 8], fw[_POS_WORK + 8:_POS_WORK + 10], iw[6:8]
    n1 = _parallel_shoulders(cf, T, t1s, shoulders)
    folded = False
    if n1 == 0 and fold is not None:  # no θ₁: a shoulder's fold starts, near its fold
        if fold[1] != 0.0:
            n1 = _shoulder_folds(cf, T, FOLD_STARTS * fold[1], t1s, shoulders)
            folded = n1 > 0
    n = 0
    for i1 in range(n1):
        n = _parallel_complete(cf, T, t1s[i1], shoulders[i1], q6_ref, Q, codes, degen, n, t5s, fold, folded)
    return n


@njit
def parallel_axes_position(cf: np.ndarray, T06: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Step 1 for the canonical chain's target T06: ``(θ₁ rotation angles (m,), shoulder codes (m,))``."""
    t1s = np.empty(2)
    shoulders = np.empty(2, dtype=np.int64)
    n1 = _parallel_shoulders(cf, T06, t1s, shoulders)
    return t1s[:n1].copy(), shoulders[:n1].copy()


@njit
def parallel_axes_wrist(cf: np.ndarray, T06: np.ndarray, t1: float, shoulder: int,
                        q6_ref: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Steps 2–4 for one θ₁: raw rows ``(q (m, 6), codes (m, 3), degenerate (m,))``."""
    Q, codes, degen = _raw_rows()
    n = _parallel_complete(cf, T06, t1, shoulder, q6_ref, Q, codes, degen, 0, np.empty(2))
    return _first(n, Q, codes, degen)


@njit
def parallel_axes_rows(cf: np.ndarray, T06: np.ndarray, q6_ref: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Every raw row of the three-parallel-axes method: ``(q (m, 6), codes (m, 3), degenerate (m,))``."""
    Q, codes, degen = _raw_rows()
    n = _parallel_axes(cf, T06, q6_ref, Q, codes, degen, _scratch())
    return _first(n, Q, codes, degen)


@njit
def _mul44(A: np.ndarray, B: np.ndarray, out: np.ndarray) -> None:
    """``out = A · B`` (4×4; out distinct from A and B)."""
    for i in range(4):
        for j in range(4):
            out[i, j] = A[i, 0] * B[0, j] + A[i, 1] * B[1, j] + A[i, 2] * B[2, j] + A[i, 3] * B[3, j]


@njit
def _target(ci: np.ndarray, pre: np.ndarray, post: np.ndarray, T: np.ndarray, Tin: np.ndarray,
            tmp: np.ndarray) -> np.ndarray:
    """The canonical chain's target ``pre · T · post`` (T⁻¹ when the chain is reversed), written
    into (and returned as) the 4×4 scratch ``Tin``; ``tmp`` is 4×4 scratch too."""
    if ci[5] == 1:  # T⁻¹
        for i in range(3):
            for j in range(3):
                Tin[i, j] = T[j, i]
            Tin[i, 3] = -(T[0, i] * T[0, 3] + T[1, i] * T[1, 3] + T[2, i] * T[2, 3])
            Tin[3, i] = 0.0
        Tin[3, 3] = 1.0
    else:
        Tin[:, :] = T
    _mul44(pre, Tin, tmp)
    _mul44(tmp, post, Tin)
    return Tin


@njit
def _finish(ci: np.ndarray, post_q: np.ndarray, rows: np.ndarray, rcodes: np.ndarray, rdegen: np.ndarray,
            m: int, out: np.ndarray, qq: np.ndarray) -> int:
    """The raw rows' post-processing (as :func:`robokit.ik.solution.solutions_from_rows`), written
    into ``out`` (rows of q (6), within, branch code, degenerate: ``OUT_COLS``); the number of
    distinct solutions written. ``qq``: scratch (6,). Rows of ``out`` past that number are not
    touched (the batch's stay NaN)."""
    reverse = ci[5] == 1
    # post_q: row 0 the sign of each joint (−1: flipped or reversed), row 1 revolute (1/0),
    # rows 2, 3 the limits with their tolerance (±inf without), row 4 [has limits]
    has_lim = post_q[4, 0] != 0.0
    n = 0
    for k in range(m):
        for j in range(6):
            src = 5 - j if reverse else j
            v = post_q[0, j] * rows[k, src]
            if post_q[1, j] != 0.0:
                v = _rem(v)
                if v == -_PI:
                    v = _PI
            qq[j] = v
        inside = True
        if has_lim:
            for j in range(6):
                v, lo, hi = qq[j], post_q[2, j], post_q[3, j]
                if v < lo or v > hi:
                    rev = post_q[1, j] != 0.0
                    if rev and lo <= v + _TWO_PI <= hi:
                        qq[j] = v + _TWO_PI
                    elif rev and lo <= v - _TWO_PI <= hi:
                        qq[j] = v - _TWO_PI
                    else:
                        inside = False
        dup = False
        for o in range(n):
            same = True
            for j in range(6):
                d = qq[j] - out[o, j]
                if post_q[1, j] != 0.0:
                    d = _rem(d)
                if d >= 1e-9 or d <= -1e-9:
                    same = False
                    break
            if same:
                dup = True
                break
        if dup:
            continue
        for j in range(6):
            out[n, j] = qq[j]
        out[n, 6] = 1.0 if inside else 0.0
        out[n, 7] = rcodes[k, 0] * 100 + rcodes[k, 1] * 10 + rcodes[k, 2]
        out[n, 8] = 1.0 if rdegen[k] else 0.0
        n += 1
    return n


#: Layout of the packed constants ``K`` (one float64 array per robot, built by
#: :func:`pack_constants`): offsets of cf (64), C (5×5), pre (4×4), post (4×4), post_q (5×6), ci (6).
_K_CF, _K_C, _K_PRE, _K_POST, _K_PQ, _K_CI, K_SIZE = 0, 64, 89, 105, 121, 151, 157
#: Columns of a solve's output row: q (6), within (0/1), branch code s·100 + e·10 + w, degenerate (0/1).
OUT_COLS = 9


def pack_constants(ci: np.ndarray, cf: np.ndarray, C: np.ndarray, pre: np.ndarray, post: np.ndarray,
                   post_q: np.ndarray) -> np.ndarray:
    """The packed constants ``K`` (K_SIZE,) of one robot for :func:`closed_form_solve`.

    Parameters
    ----------
    ci : (6,) int
        ``[method (PIEPER/PARALLEL_AXES), case, joint 3 revolute, degree, rows of C, reversed]``.
    cf : (64,) float
        The solver's constants (layout: this module's ``_TH0`` … indices).
    C : (5, 5) float
        Position polynomial coefficients (Pieper), one row per monomial of the target.
    pre, post : (4, 4) float
        ``T₀₆ = pre · T · post`` (or ``pre · T⁻¹ · post`` when reversed): base′⁻¹ and tool′⁻¹.
    post_q : (5, 6) float
        Per joint: sign (−1 for a flipped joint or a reversed chain), revolute flag (1/0), lower
        and upper limit (tolerance included; ±inf without), and ``post_q[4, 0]`` = 1 with limits.

    Returns
    -------
    (K_SIZE,) ndarray

    Examples
    --------
    >>> import numpy as np
    >>> pack_constants(np.zeros(6, int), np.zeros(64), np.zeros((5, 5)), np.eye(4), np.eye(4),
    ...                np.zeros((5, 6))).shape
    (157,)
    """
    K = np.zeros(K_SIZE)
    K[_K_CF:_K_C] = cf
    K[_K_C:_K_PRE] = np.asarray(C, dtype=float).ravel()
    K[_K_PRE:_K_POST] = np.asarray(pre, dtype=float).ravel()
    K[_K_POST:_K_PQ] = np.asarray(post, dtype=float).ravel()
    K[_K_PQ:_K_CI] = np.asarray(post_q, dtype=float).ravel()
    K[_K_CI:K_SIZE] = np.asarray(ci, dtype=float)
    return K


@njit
def _rigid(T: np.ndarray) -> bool:
    """The quick rigid-transform test of :func:`robokit.ik.solution.check_pose`."""
    a, b, c, d, e, f, g, h, i = T[0, 0], T[0, 1], T[0, 2], T[1, 0], T[1, 1], T[1, 2], T[2, 0], T[2, 1], T[2, 2]
    dev = max(abs(a * a + d * d + g * g - 1.0), abs(b * b + e * e + h * h - 1.0), abs(c * c + f * f + i * i - 1.0),
              abs(a * b + d * e + g * h), abs(a * c + d * f + g * i), abs(b * c + e * f + h * i))
    det = a * (e * i - f * h) - b * (d * i - f * g) + c * (d * h - e * g)
    finite = math.isfinite(a + b + c + d + e + f + g + h + i + T[0, 3] + T[1, 3] + T[2, 3])
    return (finite and dev < 1e-9 and det > 0.0 and T[3, 0] == 0.0 and T[3, 1] == 0.0 and T[3, 2] == 0.0
            and T[3, 3] == 1.0)


@njit
def _unpack(K: np.ndarray, T: np.ndarray) -> tuple:
    """The start of one packed solve (:func:`pieper_solve_into`, :func:`parallel_axes_solve_into`,
    after the rigid-transform test): the constants read from ``K`` as views and the scratch of
    :func:`_scratch`. Returns ``(ci, cf, C, post_q, T06, rows, rcodes, rdegen, qq, s)``: T06 the
    canonical chain's target (:func:`_target`), rows/rcodes/rdegen the raw rows' buffers, qq
    :func:`_finish`'s scratch, ``s`` the scratch tuple (the method's own parts)."""
    s = _scratch()
    F6, F4, _, I3, iw, bw, fw = s
    ci = iw[0:6]
    for j in range(6):
        ci[j] = int(K[_K_CI + j])
    T06 = _target(ci, K[_K_PRE:_K_POST].reshape((4, 4)), K[_K_POST:_K_PQ].reshape((4, 4)), T, F4[0:4], F4[4:8])
    return (ci, K[_K_CF:_K_C], K[_K_C:_K_PRE].reshape((5, 5)), K[_K_PQ:_K_CI].reshape((5, 6)), T06,
            F6[0:MAX_ROWS], I3[0:MAX_ROWS], bw[0:MAX_ROWS], fw[_POS_WORK:_POS_WORK + 6], s)


@njit
def _pieper_packed(K: np.ndarray, T: np.ndarray, wrist_ref: float, out: np.ndarray) -> int:
    ci, cf, C, post_q, T06, rows, rcodes, rdegen, qq, s = _unpack(K, T)
    m = _pieper(ci, cf, C, T06, wrist_ref, rows, rcodes, rdegen, s, None)
    return _finish(ci, post_q, rows, rcodes, rdegen, m, out, qq)


@njit
def _parallel_axes_packed(K: np.ndarray, T: np.ndarray, wrist_ref: float, out: np.ndarray) -> int:
    ci, cf, _, post_q, T06, rows, rcodes, rdegen, qq, s = _unpack(K, T)
    m = _parallel_axes(cf, T06, wrist_ref, rows, rcodes, rdegen, s)
    return _finish(ci, post_q, rows, rcodes, rdegen, m, out, qq)


# Each method has its own kernels (only the structure a robot uses is compiled); what they share
# is in the helpers _solved and _batch_buffers.


@njit
def _solved(out: np.ndarray, n: int) -> np.ndarray:
    """The result of a ``*_solve`` kernel from its ``*_solve_into``'s: the first n rows of ``out``,
    or shape (0, 0) when n < 0 (T failed the rigid-transform test)."""
    if n < 0:
        return np.empty((0, 0))
    return out[:n].copy()


@njit
def _batch_buffers(N: int) -> tuple[np.ndarray, np.ndarray]:
    """A batch's output (N, MAX_ROWS, OUT_COLS), NaN, and its counts (N,), zero."""
    return np.full((N, MAX_ROWS, OUT_COLS), np.nan), np.zeros(N, dtype=np.int64)


@njit
def pieper_solve(K: np.ndarray, T: np.ndarray, wrist_ref: float) -> np.ndarray:
    """:func:`closed_form_solve` for a spherical wrist (its own kernel: only the structure a
    robot uses is compiled)."""
    out = np.empty((MAX_ROWS, OUT_COLS))
    return _solved(out, pieper_solve_into(K, T, wrist_ref, out))


@njit
def parallel_axes_solve(K: np.ndarray, T: np.ndarray, wrist_ref: float) -> np.ndarray:
    """:func:`closed_form_solve` for three parallel axes (its own kernel)."""
    out = np.empty((MAX_ROWS, OUT_COLS))
    return _solved(out, parallel_axes_solve_into(K, T, wrist_ref, out))


@njit
def pieper_solve_into(K: np.ndarray, T: np.ndarray, wrist_ref: float, out: np.ndarray) -> int:
    """:func:`pieper_solve` writing into ``out`` (MAX_ROWS, OUT_COLS) and returning the number of
    rows (−1 when T fails the quick rigid-transform test): no array crosses back into Python,
    which saves the boxing of a new array (about 0.8 µs of a 4 µs call)."""
    if not _rigid(T):
        return -1
    return _pieper_packed(K, T, wrist_ref, out)


@njit
def parallel_axes_solve_into(K: np.ndarray, T: np.ndarray, wrist_ref: float, out: np.ndarray) -> int:
    """:func:`parallel_axes_solve` writing into ``out``; as :func:`pieper_solve_into`."""
    if not _rigid(T):
        return -1
    return _parallel_axes_packed(K, T, wrist_ref, out)


@njit(parallel=True)
def pieper_batch(K: np.ndarray, Ts: np.ndarray, wrist_ref: float) -> tuple[np.ndarray, np.ndarray]:
    """:func:`closed_form_batch` for a spherical wrist."""
    out, counts = _batch_buffers(Ts.shape[0])
    for i in prange(Ts.shape[0]):
        counts[i] = _pieper_packed(K, Ts[i], wrist_ref, out[i])
    return out, counts


@njit(parallel=True)
def parallel_axes_batch(K: np.ndarray, Ts: np.ndarray, wrist_ref: float) -> tuple[np.ndarray, np.ndarray]:
    """:func:`closed_form_batch` for three parallel axes."""
    out, counts = _batch_buffers(Ts.shape[0])
    for i in prange(Ts.shape[0]):
        counts[i] = _parallel_axes_packed(K, Ts[i], wrist_ref, out[i])
    return out, counts


def solve_into_entry(kernel: Any) -> Any:
    """The machine code of a ``*_solve_into`` kernel for the one set of argument types robokit
    calls it with — K (n,) float64, T (4, 4) float64, wrist_ref float, out (MAX_ROWS, OUT_COLS)
    float64, arrays in C order — as a callable that skips numba's type dispatch (about 0.1 µs of a
    call), or None while the kernel has no machine code for them (not compiled yet, or running as
    plain Python: then call the kernel itself).

    The caller must pass exactly those types (the entry point converts without checking): C-order
    float64 arrays of those shapes and a Python float.

    Parameters
    ----------
    kernel : numba Dispatcher or function
        :func:`pieper_solve_into` or :func:`parallel_axes_solve_into`.

    Returns
    -------
    callable or None

    Examples
    --------
    >>> import numpy as np, robokit
    >>> from robokit.ik.closed_form import AnalyticIK
    >>> robot = robokit.load("puma560")
    >>> K, out = AnalyticIK(robot)._kernel[0], np.empty((MAX_ROWS, OUT_COLS))
    >>> T = robot.frame_pose(np.full(6, 0.3))
    >>> n = pieper_solve_into(K, T, 0.0, out)
    >>> entry = solve_into_entry(pieper_solve_into)
    >>> entry is None or entry(K, T, 0.0, out) == n
    True
    """
    return machine_code(kernel, "vmfm")


def closed_form_solve(K: np.ndarray, T: np.ndarray, wrist_ref: float) -> np.ndarray:
    r"""Every closed-form solution of one pose, in compiled code.

    Parameters
    ----------
    K : (K_SIZE,) float64
        The robot's packed constants (:func:`pack_constants`).
    T : (4, 4) float64
        Tip pose in the base frame (m).
    wrist_ref : float
        The free joint's value at a singularity (rad), in the sign of the solver's chain.

    Returns
    -------
    (m, 9) float64
        One row per distinct solution: q (6; rad, m — revolute joints wrapped to (−π, π] or
        shifted into limits wider than ±π), within limits (1/0), branch code
        ``shoulder·100 + elbow·10 + wrist`` (module docstring), degenerate (1/0).
        Shape (0, 9) when T is out of reach; **shape (0, 0) when T fails the quick
        rigid-transform test** (the caller then checks T properly).

    Notes
    -----
    Lecture 5: Pieper's decoupling / the three-parallel-axes method (see
    :mod:`robokit.ik.pieper`, :mod:`robokit.ik.parallel_axes`).

    Examples
    --------
    >>> import numpy as np, robokit
    >>> from robokit.ik.closed_form import AnalyticIK
    >>> robot = robokit.load("puma560")
    >>> K = AnalyticIK(robot)._kernel[0]
    >>> closed_form_solve(K, robot.frame_pose(np.full(6, 0.3)), 0.0).shape
    (8, 9)
    """
    return (pieper_solve if K[_K_CI] == PIEPER else parallel_axes_solve)(K, T, wrist_ref)


def closed_form_batch(K: np.ndarray, Ts: np.ndarray, wrist_ref: float) -> tuple[np.ndarray, np.ndarray]:
    r""":func:`closed_form_solve` over (N, 4, 4) targets, in parallel over targets (``prange``).

    Parameters
    ----------
    K : (K_SIZE,) float64
        Packed constants (:func:`pack_constants`).
    Ts : (N, 4, 4) float64
        Tip poses (m), each already checked to be a rigid transform.
    wrist_ref : float
        As in :func:`closed_form_solve`.

    Returns
    -------
    out : (N, 16, 9) float64
        Per target the rows of :func:`closed_form_solve`; rows past ``counts[i]`` are NaN.
    counts : (N,) int64
        Number of distinct solutions of each target.

    Examples
    --------
    >>> import numpy as np, robokit
    >>> from robokit.ik.closed_form import AnalyticIK
    >>> robot = robokit.load("ur5")
    >>> K = AnalyticIK(robot)._kernel[0]
    >>> out, counts = closed_form_batch(K, np.stack([robot.frame_pose(np.full(6, 0.3))] * 3), 0.0)
    >>> out.shape, counts.tolist()
    ((3, 16, 9), [8, 8, 8])
    """
    return (pieper_batch if K[_K_CI] == PIEPER else parallel_axes_batch)(K, Ts, wrist_ref)
