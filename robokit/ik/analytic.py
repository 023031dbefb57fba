r"""Closed-form inverse kinematics with every solution (Lecture 5, seed 003 eqs. 15–17).

Each solver returns a list of :class:`IKSolution` — every configuration that reaches the
target, each flagged ``within_limits`` against the joint limits — and an empty list when
the target is out of reach (never an exception for an unreachable target). Angles are in
radians and wrapped to (−π, π].

Solvers
-------
``ik_planar_2link``   planar 2-link arm (elbow up/down), Lecture 5 algebraic solution:
                      c₂ = (x² + y² − l₁² − l₂²)/(2l₁l₂), s₂ = ±√(1 − c₂²),
                      θ₁ = atan2(y, x) − atan2(k₂, k₁), k₁ = l₁ + l₂c₂, k₂ = l₂s₂.
``ik_planar_rrr``     planar RRR with orientation φ: the wrist point (x − l₃cφ, y − l₃sφ)
                      by the 2-link solution, θ₃ = φ − θ₁ − θ₂ (Lecture 5).
``ik_spherical_wrist`` ZYZ wrist ³R₆ = Rz(θ₄) Ry(θ₅) Rz(θ₆), both branches (seed 003, eq. 16–17).
``ik_rrr_position``   the Lecture 5 homework arm (spatial RRR, Craig's convention,
                      α₁ = 90°), target position only: up to 4 solutions.
``ik_puma560``        PUMA 560-type arm (standard DH, Corke's/Paul's frame assignment) by
                      Pieper's method: wrist centre → θ₁, θ₂, θ₃ (left/right, elbow up/down),
                      then the spherical wrist → θ₄, θ₅, θ₆ (flip/no flip): all 8.
"""
from __future__ import annotations

import math
from typing import TYPE_CHECKING, Any, Iterable, cast

import numpy as np
from numpy.typing import ArrayLike

from robokit._arrays import as_scalar, as_vector
from robokit._deprecation import renamed_argument
from robokit._units import TURN, check_radians
from robokit.errors import InputError
from robokit.ik.closed_form import analytic_ik
from robokit.ik.solution import IKSolution, _qlim_or_none, _within, check_pose
from robokit.spatial.so3 import check_rotation
from robokit.spatial.basics import wrap_angle

if TYPE_CHECKING:
    from robokit.description.dh import DHTable

__all__ = [
    "ik_planar_2link",
    "ik_planar_rrr",
    "ik_spherical_wrist",
    "ik_rrr_position",
    "ik_puma560",
    "select_solution",
]

_TWO_PI = 2.0 * np.pi




_UNSET: Any = object()  # "not given" for the former keyword names

def _two_link_core(x: float, y: float, l1: float, l2: float) -> list[tuple[float, float, str]]:
    """Both (θ₁, θ₂) of a planar 2-link arm reaching (x, y); [] if out of reach."""
    r2 = x * x + y * y
    c2 = (r2 - l1 * l1 - l2 * l2) / (2.0 * l1 * l2)
    tol = 1e-12
    if c2 > 1.0 + tol or c2 < -1.0 - tol:
        return []
    c2 = min(1.0, max(-1.0, c2))
    s2_abs = np.sqrt(max(0.0, 1.0 - c2 * c2))
    out = []
    for sign, label in ((1.0, "elbow down"), (-1.0, "elbow up")):
        s2 = sign * s2_abs
        k1, k2 = l1 + l2 * c2, l2 * s2
        t1 = np.arctan2(y, x) - np.arctan2(k2, k1)
        t2 = np.arctan2(s2, c2)
        out.append((float(wrap_angle(t1)), float(wrap_angle(t2)), label))
        if s2_abs == 0.0:  # stretched or folded: both branches coincide
            break
    return out


def ik_planar_2link(x: float, y: float, l1: float, l2: float, qlim: ArrayLike | None = None) -> list[IKSolution]:
    """All joint angles (θ₁, θ₂) of a planar 2-link arm whose tip reaches (x, y).

    Lecture 5's algebraic solution: ``c₂ = (x² + y² − l₁² − l₂²)/(2 l₁ l₂)``, ``s₂ = ±√(1 − c₂²)``,
    ``θ₁ = atan2(y, x) − atan2(l₂ s₂, l₁ + l₂ c₂)``.

    Parameters
    ----------
    x, y : float
        Target of the tip in the base frame, m.
    l1, l2 : float
        Link lengths, m (> 0).
    qlim : array_like, shape (2, 2), optional
        Joint limits ``[[lo₁, hi₁], [lo₂, hi₂]]`` in rad, used for ``within_limits``.

    Returns
    -------
    list of IKSolution
        Up to two solutions, ``q`` (2,) in rad wrapped to (−π, π]: ``"elbow down"`` (θ₂ > 0) and
        ``"elbow up"`` (θ₂ < 0) — with the base x axis horizontal and y up; one at the workspace
        boundary; [] if unreachable.

    Examples
    --------
    >>> [(s.q.round(4).tolist(), s.label) for s in ik_planar_2link(1.0, 1.0, 1.0, 1.0)]
    [([0.0, 1.5708], 'elbow down'), ([1.5708, -1.5708], 'elbow up')]
    >>> ik_planar_2link(3.0, 0.0, 1.0, 1.0)
    []
    """
    x, y = as_scalar(x, "x"), as_scalar(y, "y")
    l1, l2 = as_scalar(l1, "l1", positive=True), as_scalar(l2, "l2", positive=True)
    qlim = _qlim_or_none(qlim, 2)
    sols = []
    for t1, t2, label in _two_link_core(x, y, l1, l2):
        q = np.array([t1, t2])
        sols.append(IKSolution(q, _within(q, qlim), label))
    return sols


def ik_planar_rrr(x: float, y: float, phi: float, l1: float, l2: float, l3: float,
                  qlim: ArrayLike | None = None) -> list[IKSolution]:
    """All (θ₁, θ₂, θ₃) of a planar RRR arm with tool pose (x, y, φ), φ = θ₁ + θ₂ + θ₃.

    Geometric form of Lecture 5: the wrist point (x − l₃ cos φ, y − l₃ sin φ) is reached
    by the 2-link sub-arm (:func:`ik_planar_2link`), and θ₃ = φ − θ₁ − θ₂.

    Parameters
    ----------
    x, y : float
        Tool position in the base frame, m.
    phi : float
        Tool orientation (angle of the last link from the base x axis), rad.
    l1, l2, l3 : float
        Link lengths, m (> 0).
    qlim : array_like, shape (3, 2), optional
        Joint limits in rad, used for ``within_limits``.

    Returns
    -------
    list of IKSolution
        Up to two solutions (elbow down/up), ``q`` (3,) in rad; [] if unreachable.

    Examples
    --------
    Both solutions put the last link at φ = 90° and the tip at (1, 1):

    >>> sols = ik_planar_rrr(1.0, 1.0, np.pi / 2, 1.0, 1.0, 0.5)
    >>> [round(float(s.q.sum()), 4) for s in sols]
    [1.5708, 1.5708]
    >>> q = sols[0].q
    >>> x = np.cos(q[0]) + np.cos(q[0] + q[1]) + 0.5 * np.cos(q.sum())
    >>> y = np.sin(q[0]) + np.sin(q[0] + q[1]) + 0.5 * np.sin(q.sum())
    >>> round(float(x), 6), round(float(y), 6)
    (1.0, 1.0)
    """
    x, y, phi = as_scalar(x, "x"), as_scalar(y, "y"), as_scalar(phi, "phi")
    l1, l2 = as_scalar(l1, "l1", positive=True), as_scalar(l2, "l2", positive=True)
    l3 = as_scalar(l3, "l3", nonnegative=True)
    qlim = _qlim_or_none(qlim, 3)
    wx, wy = x - l3 * np.cos(phi), y - l3 * np.sin(phi)
    sols = []
    for t1, t2, label in _two_link_core(wx, wy, l1, l2):
        q = np.array([t1, t2, float(wrap_angle(phi - t1 - t2))])
        sols.append(IKSolution(q, _within(q, qlim), label))
    return sols


def ik_spherical_wrist(R36: ArrayLike, wrist_ref: float = 0.0, *, theta4_ref: Any = _UNSET) -> list[IKSolution]:
    """Both ZYZ solutions (θ₄, θ₅, θ₆) of a spherical wrist, ³R₆ = Rz(θ₄) Ry(θ₅) Rz(θ₆).

    Seed 003, eqs. 15–17, with ³R₆ = [n s a]:
    θ₅ ∈ (0, π): θ₄ = atan2(a_y, a_x), θ₅ = atan2(√(a_x² + a_y²), a_z), θ₆ = atan2(s_z, −n_z);
    θ₅ ∈ (−π, 0): θ₄ = atan2(−a_y, −a_x), θ₅ = atan2(−√(a_x² + a_y²), a_z), θ₆ = atan2(−s_z, n_z).

    Degenerate case (θ₅ = 0 or π, the axes of joints 4 and 6 aligned): only θ₄ ± θ₆ is
    determined. The documented choice: θ₄ = ``wrist_ref`` (default 0, or pass the current
    θ₄ to avoid a jump) and θ₆ takes the rest; one solution is returned, flagged
    ``degenerate``.

    Parameters
    ----------
    R36 : array_like, shape (3, 3)
        Orientation of the wrist's last frame in the frame before it (a rotation matrix).
    wrist_ref : float, optional
        θ₄ taken at the degenerate case, rad (default 0). (Formerly ``theta4_ref=``, deprecated.)

    Returns
    -------
    list of IKSolution
        Two solutions (``"no flip"``: θ₅ > 0, ``"flip"``: θ₅ < 0), ``q`` (3,) in rad wrapped to
        (−π, π]; one ``"wrist singular"`` solution at the degenerate case.

    Examples
    --------
    >>> from robokit.spatial import elementary_rotation as rot
    >>> sols = ik_spherical_wrist(rot("z", 0.3) @ rot("y", 0.5) @ rot("z", 0.7))
    >>> [(s.q.round(4).tolist(), s.label) for s in sols]
    [([0.3, 0.5, 0.7], 'no flip'), ([-2.8416, -0.5, -2.4416], 'flip')]
    >>> [(s.label, s.degenerate) for s in ik_spherical_wrist(np.eye(3))]
    [('wrist singular', True)]
    """
    R = check_rotation(R36, "R36")
    wrist_ref = renamed_argument("ik_spherical_wrist(theta4_ref=)", wrist_ref, theta4_ref, _UNSET,
                                 "ik_spherical_wrist", default=0.0)
    t4_ref = as_scalar(wrist_ref, "wrist_ref")
    return [IKSolution(cast(np.ndarray, wrap_angle(np.array(q))), True, label, degenerate)
            for q, label, degenerate in _wrist(R, t4_ref)]


def _wrist(R: np.ndarray, t4_ref: float) -> list[tuple[tuple[float, float, float], str, bool]]:
    """(q, label, degenerate) triples of the ZYZ wrist (no input checks; plain floats)."""
    ax, ay, az = R[0, 2], R[1, 2], R[2, 2]
    sx, sy, sz = R[0, 1], R[1, 1], R[2, 1]
    nx, ny, nz = R[0, 0], R[1, 0], R[2, 0]
    s5 = math.hypot(ax, ay)
    if s5 < 1e-10:
        if az > 0:  # θ5 = 0: R = Rz(θ4 + θ6)
            total = math.atan2(ny, nx)
            return [((t4_ref, 0.0, total - t4_ref), "wrist singular", True)]
        diff = math.atan2(-sx, sy)  # θ5 = π: R = Rz(θ4 − θ6) Ry(π)
        return [((t4_ref, math.pi, t4_ref - diff), "wrist singular", True)]
    return [((math.atan2(ay, ax), math.atan2(s5, az), math.atan2(sz, -nz)), "no flip", False),
            ((math.atan2(-ay, -ax), math.atan2(-s5, az), math.atan2(-sz, nz)), "flip", False)]


def ik_rrr_position(p: ArrayLike, L1: float, L2: float, L3: float, qlim: ArrayLike | None = None) -> list[IKSolution]:
    """All (θ₁, θ₂, θ₃) of the Lecture 5 homework RRR arm reaching the tool position p.

    The arm (Craig's convention, Lecture 4/5 homework): ⁰T₁ = Rz(θ₁);
    ¹T₂ = Rx(90°) Tx(L₁) Rz(θ₂); ²T₃ = Tx(L₂) Rz(θ₃); the tool at L₃ along x₃. Its tool
    position is P = (C₁(L₁ + L₂C₂ + L₃C₂₃), S₁(L₁ + L₂C₂ + L₃C₂₃), L₂S₂ + L₃S₂₃).
    With ρ = ±√(P_x² + P_y²) (the sign choosing θ₁ or θ₁ + π), the 2-link problem
    (ρ − L₁, P_z) with links L₂, L₃ gives θ₂, θ₃: up to 4 solutions.

    Parameters
    ----------
    p : array_like, shape (3,)
        Tool position in the base frame, m.
    L1, L2, L3 : float
        The arm's lengths, m.
    qlim : array_like, shape (3, 2), optional
        Joint limits in rad, used for ``within_limits``.

    Returns
    -------
    list of IKSolution
        Up to four solutions, ``q`` (3,) in rad, labelled ``"front"``/``"back"`` and elbow
        down/up; [] if unreachable.

    Examples
    --------
    With all lengths 0.5 m, p = (1, 0, 0.5) asks the 2-link sub-arm for (0.5, 0.5) in front
    (reaching behind is too far):

    >>> [(s.q.round(4).tolist(), s.label) for s in ik_rrr_position([1.0, 0.0, 0.5], 0.5, 0.5, 0.5)]
    [([0.0, 0.0, 1.5708], 'front, elbow down'), ([0.0, 1.5708, -1.5708], 'front, elbow up')]
    """
    p = as_vector(p, "p", 3)
    L1 = as_scalar(L1, "L1", nonnegative=True)
    L2, L3 = as_scalar(L2, "L2", positive=True), as_scalar(L3, "L3", positive=True)
    qlim = _qlim_or_none(qlim, 3)
    r = float(np.hypot(p[0], p[1]))
    base_angle = float(np.arctan2(p[1], p[0])) if r > 1e-12 else 0.0
    sols = []
    for sign, side in ((1.0, "front"), (-1.0, "back")):
        t1 = base_angle if sign > 0 else base_angle + np.pi
        for t2, t3, label in _two_link_core(sign * r - L1, p[2], L2, L3):
            q = cast(np.ndarray, wrap_angle(np.array([t1, t2, t3])))
            sols.append(IKSolution(q, _within(q, qlim), f"{side}, {label}"))
        if r <= 1e-12:
            break  # on the axis of joint 1: θ₁ is free; the choice θ₁ = 0 covers both sides
    return sols


_PUMA_ALPHA = np.array([np.pi / 2, 0.0, -np.pi / 2, np.pi / 2, -np.pi / 2, 0.0])


def _puma_params(table: DHTable) -> tuple[float, float, float, float, float, float, np.ndarray]:
    """Check the PUMA 560 structure and return its constants (d1, a2, a3, d23, d4, d6, offsets)."""
    links = list(table.links)
    if len(links) != 6 or any(l.joint != "R" for l in links):
        raise InputError("table: ik_puma560 needs six revolute joints")
    if table.convention != "standard":
        raise InputError("table: ik_puma560 needs the standard DH convention (Corke's/Paul's PUMA 560 frames)")
    alpha = np.array([l.alpha for l in links])
    a = np.array([l.a for l in links])
    d = np.array([l.d for l in links])
    if np.abs(wrap_angle(alpha - _PUMA_ALPHA)).max() > 1e-9 or np.abs(a[[0, 3, 4, 5]]).max() > 1e-12 or abs(d[4]) > 1e-12:
        raise InputError(
            "table: not a PUMA 560-type arm (needs alpha = [90, 0, -90, 90, -90, 0] deg, a1 = a4 = a5 = a6 = 0, d5 = 0)"
        )
    offsets = np.array([l.theta for l in links])
    return d[0], a[1], a[2], d[1] + d[2], d[3], d[5], offsets


def ik_puma560(table: DHTable, T: ArrayLike, wrist_ref: float = 0.0, *, theta4_ref: Any = _UNSET) -> list[IKSolution]:
    """All 8 configurations of a PUMA 560-type arm reaching the tool pose T (Pieper's method).

    Method. With ⁰T₆ = base⁻¹ T tool⁻¹, the wrist centre p = ⁰p₆ − d₆ ⁰z₆ satisfies
    p_x = c₁X + s₁D, p_y = s₁X − c₁D, p_z = d₁ + Y with D = d₂ + d₃,
    X = a₂c₂ + a₃c₂₃ − d₄s₂₃, Y = a₂s₂ + a₃s₂₃ + d₄c₂₃. So θ₁ = atan2(p_y, p_x) + {asin(D/r),
    π − asin(D/r)} (right/left arm, r = √(p_x² + p_y²)); a₃c₃ − d₄s₃ =
    (X² + Y² − a₂² − a₃² − d₄²)/(2a₂) gives two θ₃ (elbow up/down); θ₂ = atan2(Y, X) −
    atan2(a₃s₃ + d₄c₃, a₂ + a₃c₃ − d₄s₃). Then ³R₆ = Rz(θ₄) Ry(−θ₅) Rz(θ₆) (the frames'
    α₄ = 90°, α₅ = −90°) gives the wrist flip/no-flip pair by :func:`ik_spherical_wrist`.
    This is the PUMA case of :func:`robokit.ik.closed_form.ik_analytic` (Pieper's general
    method, whose θ₃ equation is a quadratic here because a₁ = 0), with the PUMA structure
    checked first.

    Parameters
    ----------
    table : DHTable
        A standard-convention table with the PUMA structure (α = 90°, 0, −90°, 90°, −90°, 0;
        a₁ = a₄ = a₅ = a₆ = 0; d₅ = 0; any d₁, a₂, a₃, d₂ + d₃, d₄, d₆, θ offsets, base and tool
        transforms); anything else raises :class:`~robokit.errors.InputError`.
    T : array_like, shape (4, 4)
        Target pose of the tool frame in base_link, m (as ``table.fk`` returns it).
    wrist_ref : float, optional
        θ₄ taken at a wrist singularity, rad (default 0). (Formerly ``theta4_ref=``, deprecated.)

    Returns
    -------
    list of IKSolution
        Up to 8 solutions, ``q`` (6,) the joint variables in rad (θ = q + offset), wrapped to
        (−π, π], labelled arm (left/right), elbow (up/down) and wrist (flip/no flip); fewer at
        singular targets (where the wrist choice of :func:`ik_spherical_wrist` applies); [] if
        unreachable.

    Examples
    --------
    >>> table = rk.load("puma560").dh
    >>> q = np.array([0.1, 0.2, 0.3, 0.4, 0.5, 0.6])
    >>> sols = ik_puma560(table, table.fk(q))
    >>> len(sols), any(np.allclose(s.q, q) for s in sols)
    (8, True)
    >>> all(np.allclose(table.fk(s.q), table.fk(q)) for s in sols)
    True
    """
    store = getattr(table, "__dict__", {})
    if store.get("_puma_checked") is not table.links:
        _puma_params(table)  # the PUMA structure, checked once per table (its links are immutable)
        store["_puma_checked"] = table.links  # kept on the table: no module-level cache keyed by its id
    if theta4_ref is not _UNSET:
        wrist_ref = renamed_argument("ik_puma560(theta4_ref=)", wrist_ref, theta4_ref, _UNSET, "ik_puma560", default=0.0)
    ref = wrist_ref if type(wrist_ref) is float else as_scalar(wrist_ref, "wrist_ref")
    return analytic_ik(table).solve(check_pose(T), ref)








def select_solution(solutions: Iterable[IKSolution], q_ref: ArrayLike, weights: ArrayLike | None = None,
                    within_limits: bool = True, proximal_first: bool = False) -> IKSolution | None:
    """The solution closest to ``q_ref`` (Lecture 5's choice among multiple solutions).

    Distance: ``Σ wᵢ |wrap(qᵢ − q_refᵢ)|`` (angles compared modulo 2π).

    Parameters
    ----------
    solutions : iterable of IKSolution
        The candidates (e.g. from :func:`robokit.ik_analytic`).
    q_ref : array_like, shape (n,)
        The reference configuration (usually the current one), rad or m.
    weights : array_like, shape (n,), optional
        Per-joint weights wᵢ (default ones).
    within_limits : bool, optional
        Consider only the solutions inside the joint limits (default True).
    proximal_first : bool, optional
        Use wᵢ = n − i + 1 (ignored when ``weights`` is given), preferring to move the big
        proximal joints little (Lecture 5).

    Returns
    -------
    IKSolution or None
        The nearest solution; None when no candidate is left.

    Examples
    --------
    >>> sols = ik_planar_2link(1.0, 1.0, 1.0, 1.0)
    >>> select_solution(sols, [1.4, -1.4]).label
    'elbow up'
    """
    sols = [s for s in solutions if s.within_limits or not within_limits]
    if not sols:
        return None
    n = len(sols[0].q)
    q_ref = as_vector(q_ref, "q_ref", n)
    check_radians(q_ref, -TURN, TURN, "q_ref")  # the solutions' angles are wrapped: |q_ref| > 2π is degrees
    if weights is None:
        w = np.arange(n, 0, -1, dtype=float) if proximal_first else np.ones(n)
    else:
        w = as_vector(weights, "weights", n)
    costs = [float(np.sum(w * np.abs(wrap_angle(s.q - q_ref)))) for s in sols]
    return sols[int(np.argmin(costs))]
