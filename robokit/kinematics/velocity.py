r"""Velocity kinematics of Lecture 6: numerical and analytical Jacobians, velocity and wrench
transforms, manipulability and singularities, resolved-rate motion control.

Jacobians here are geometric, rows ``(ω; v)`` with v the velocity of the frame's origin, in the
base frame unless said otherwise (Pinocchio's LOCAL_WORLD_ALIGNED), as the course writes them.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING, Any, Callable

import numpy as np
from numpy.typing import ArrayLike

from robokit._arrays import as_array, as_matrix, as_scalar, as_vector
from robokit.errors import InputError
from robokit.spatial.se3 import check_transform
from robokit.spatial import lie
from robokit._deprecation import deprecated_alias

if TYPE_CHECKING:
    from robokit.description.protocol import RobotLike
    from robokit.description.robot import Robot

__all__ = [
    "numerical_jacobian",
    "euler_rate_matrix",
    "analytical_jacobian",
    "geometric_jacobian",
    "twist_transform",
    "wrench_transform",
    "jacobian_in_frame",
    "manipulability",
    "velocity_ellipsoid",
    "singularity",
    "resolved_rate",
    "joint_limit_gradient",
]


def numerical_jacobian(fk: Callable[[np.ndarray], ArrayLike] | RobotLike, q: ArrayLike, h: float = 1e-6) -> np.ndarray:
    """Jacobian (6×n, (ω; v) in the base frame) of any forward kinematics by central differences.

    fk : function q (n,) → 4×4 pose, or a robot (its ``frame_pose``, the tool); q : (n,);
    h : perturbation. Column j is
    ``ω_j = vee(Ṙ Rᵀ)``, ``v_j = ṗ`` with the derivatives ``(f(q + h e_j) − f(q − h e_j)) / 2h``
    (Lecture 6: the Jacobian by perturbation). Accurate to about h².
    """
    if not callable(fk):
        if not hasattr(fk, "frame_pose"):
            raise InputError(f"fk: expected a function q -> 4x4 pose or a robot, got {type(fk).__name__}")
        fk = fk.frame_pose
    q = as_vector(q, "q")
    h = as_scalar(h, "h", positive=True)
    T0 = np.asarray(fk(q), dtype=float)
    R0 = T0[:3, :3]
    J = np.empty((6, len(q)))
    for j in range(len(q)):
        e = np.zeros(len(q))
        e[j] = h
        Tp, Tm = np.asarray(fk(q + e), float), np.asarray(fk(q - e), float)
        dR = (Tp[:3, :3] - Tm[:3, :3]) / (2 * h)
        W = dR @ R0.T
        J[:3, j] = 0.5 * np.array([W[2, 1] - W[1, 2], W[0, 2] - W[2, 0], W[1, 0] - W[0, 1]])
        J[3:, j] = (Tp[:3, 3] - Tm[:3, 3]) / (2 * h)
    return J


def euler_rate_matrix(angles: ArrayLike, seq: str = "ZYX", tol: float = 1e-9, extrinsic: bool = False) -> np.ndarray:
    """E(φ) (3×3) with ``ω = E(φ) φ̇``: Euler-angle rates to the angular velocity (base axes).

    angles : (3,) ``φ = (a, b, c)`` (rad) of the sequence ``seq`` — any of the 12 sequences
    (``robokit.EULER_SEQUENCES``: "XYZ", "ZYX", "ZYZ", …); extrinsic : fixed axes instead of moving
    axes (see :func:`robokit.matrix_from_euler`). With the axes ``e₁, e₂, e₃`` of the sequence:

    * intrinsic, ``R = R₁(a) R₂(b) R₃(c)``: ``E = [e₁, R₁(a) e₂, R₁(a) R₂(b) e₃]``;
    * extrinsic, ``R = R₃(c) R₂(b) R₁(a)``: ``E = [R₃(c) R₂(b) e₁, R₃(c) e₂, e₃]``

    (differentiate R and read ``ω`` off ``Ṙ Rᵀ = S(ω)``, Lecture 6). Examples: ZYX
    ``[[0, −sα, cα cβ], [0, cα, sα cβ], [1, 0, −sβ]]`` (singular at cos β = 0); ZYZ
    ``[[0, −sφ, cφ sθ], [0, cφ, sφ sθ], [1, 0, cθ]]`` (the Lecture 6 homework's B(Γ), singular at
    sin θ = 0); the lecture's roll–pitch–yaw ``R = Rx(θr) Ry(θp) Rz(θy)`` is intrinsic "XYZ" with
    ``φ = (θr, θp, θy)`` and ``B(Γ) = [[1, 0, sθp], [0, cθr, −cθp sθr], [0, sθr, cθp cθr]]``.
    The matrix is singular when the first and third axes line up (Tait–Bryan b = ±π/2, proper
    Euler b ∈ {0, π}); :func:`analytical_jacobian` raises there (``tol`` is its threshold on det E).
    """
    from robokit.spatial.euler import check_sequence, elementary_rotation

    a, b, c = as_vector(angles, "angles", 3)
    seq = check_sequence(seq)
    i, j, k = ("XYZ".index(ch) for ch in seq)
    e = np.eye(3)
    if extrinsic:
        Rk = elementary_rotation(k, c)
        return np.column_stack([Rk @ elementary_rotation(j, b) @ e[i], Rk @ e[j], e[k]])
    Ri = elementary_rotation(i, a)
    return np.column_stack([e[i], Ri @ e[j], Ri @ elementary_rotation(j, b) @ e[k]])


def analytical_jacobian(J: ArrayLike, angles: ArrayLike, seq: str = "ZYX", tol: float = 1e-9,
                        extrinsic: bool = False) -> np.ndarray:
    """``J_a = blockdiag(E(φ)⁻¹, I) J``: rows (φ̇; ṗ) — Euler-angle rates and linear velocity.

    J : 6×n geometric Jacobian (ω; v) in the base frame; angles : the current Euler angles of
    the tool orientation in the sequence ``seq`` (any of the 12; ``extrinsic`` for fixed axes), see
    :func:`euler_rate_matrix`. (The lecture writes the same with the rows in the order (v; ω):
    ``J_a = blockdiag(I, B(Γ)⁻¹) J``; robokit keeps angular rows first.)
    Raises ``ValueError`` ("representation singularity") where E(φ) is singular
    (|det E| < tol: β = ±π/2 for ZYX, θ = 0 or π for ZYZ) — the analytical Jacobian does not
    exist there even though the arm itself may be far from any singularity.

    Example: ``analytical_jacobian(J, matrix_to_euler(R), "ZYX")``.
    """
    J = as_matrix(J, "J", 6, None)
    E = euler_rate_matrix(angles, seq, extrinsic=extrinsic)
    d = float(np.linalg.det(E))
    if abs(d) < tol:
        raise InputError(f"angles: representation singularity of {seq} Euler angles (det E = {d:.2e}); "
                         "E(φ) has no inverse here")
    return np.vstack([np.linalg.solve(E, J[:3]), J[3:]])


def geometric_jacobian(robot: Robot, q: ArrayLike) -> np.ndarray:
    """The geometric Jacobian (6×n) of the robot's tool point, world (base) axes, rows ``(ω; v)``.

    ``ω = J_ω q̇`` is the tool's angular velocity and ``v = J_v q̇`` the velocity of the tool
    frame's origin, both in base-frame axes (Lecture 6; the lecture stacks them as (v; ω) —
    robokit keeps angular rows first, like every twist in the package). Built from the
    product-of-exponentials space Jacobian ``J_s`` (whose linear rows are the velocity of the point
    at the base origin): column i is ``(ω_i, v_i + ω_i × p)`` with p the tool position, i.e. for a
    revolute joint ``(zᵢ, zᵢ × (p − oᵢ))`` and for a prismatic one ``(0, zᵢ)``.

    robot : a :class:`robokit.Robot` (its ``poe`` parameters, tip = the tool); q : (n,) rad/m.
    Example: for the planar 2-link arm the v rows x, y are the lecture's
    ``J_v = [[−a₁s₁ − a₂s₁₂, −a₂s₁₂], [a₁c₁ + a₂c₁₂, a₂c₁₂]]``.
    """
    from robokit.kinematics.poe import fkin_space, jacobian_space

    P = robot.poe
    q = as_vector(q, "q", P.Slist.shape[1])
    Js = jacobian_space(P.Slist, q)
    p = fkin_space(P.M, P.Slist, q)[:3, 3]
    Jg = Js.copy()
    Jg[3:] = Js[3:] + np.cross(Js[:3].T, p).T
    return Jg


def twist_transform(T_a_b: ArrayLike) -> np.ndarray:
    """The 6×6 map of twists ``(ω, v)`` expressed in frame b to frame a: ``V_a = Ad_{T_ab} V_b``.

    For two frames on the same body, or a frame on another body rigidly fixed to it (Lecture 6).
    """
    return lie.adjoint(check_transform(T_a_b, "T_a_b"))


def wrench_transform(T_a_b: ArrayLike) -> np.ndarray:
    """The 6×6 map of wrenches ``(m, f)`` expressed in frame b to frame a: ``F_a = Ad_{T_ba}ᵀ F_b``
    (the same physical force, its moment taken about a's origin)."""
    return lie.adjoint(lie.inv(check_transform(T_a_b, "T_a_b"))).T


def jacobian_in_frame(J: ArrayLike, R: ArrayLike) -> np.ndarray:
    """Re-express a geometric Jacobian (ω; v) in rotated axes: ``blockdiag(R, R) J``.

    With R = R_tool_base (= R_base_toolᵀ) a base-frame Jacobian becomes the tool-frame one and
    vice versa with R_base_tool (the origin of v is unchanged: only the axes rotate).
    """
    J = as_matrix(J, "J", 6, None)
    R = as_matrix(R, "R", 3, 3)
    return np.vstack([R @ J[:3], R @ J[3:]])


def _rows(J: ArrayLike, part: str) -> np.ndarray:
    J = as_array(J, "J", (None, None))
    if part == "full":
        return J
    if J.shape[0] != 6:
        raise InputError(f"part: {part!r} needs a 6-row Jacobian (ω; v), got shape {J.shape}")
    if part == "translation":
        return J[3:]
    if part == "rotation":
        return J[:3]
    raise InputError(f"part: expected 'full', 'translation' or 'rotation', got {part!r}")


def manipulability(J: ArrayLike, kind: str = "yoshikawa", part: str = "full") -> float:
    """A manipulability measure of the Jacobian (or of its translation/rotation rows).

    kind : "yoshikawa" — ``w = √det(J Jᵀ)`` (the product of the singular values; 0 at a
    singularity); "condition" — ``σ_max / σ_min`` (∞ at a singularity); "inverse_condition" —
    ``σ_min / σ_max`` (the ratio of the shortest to the longest ellipsoid axis); "min_singular"
    — ``σ_min``. part : "full", "translation" (rows v) or "rotation" (rows ω).
    For the planar 2-link arm's 2×2 translational Jacobian, ``w = |l₁ l₂ sin θ₂|``.
    """
    A = _rows(J, part)
    s = np.linalg.svd(A, compute_uv=False)
    m = A.shape[0]
    if kind == "yoshikawa":
        if A.shape[1] < m:
            return 0.0
        return float(np.prod(s[:m]))
    if kind == "condition":
        return float(s[0] / s[-1]) if s[-1] > 0 and A.shape[1] >= m else float("inf")
    if kind == "inverse_condition":
        return float(s[-1] / s[0]) if s[0] > 0 and A.shape[1] >= m else 0.0
    if kind == "min_singular":
        return float(s[-1]) if A.shape[1] >= m else 0.0
    raise InputError(f"kind: expected 'yoshikawa', 'condition', 'inverse_condition' or 'min_singular', got {kind!r}")


def velocity_ellipsoid(J: ArrayLike, part: str = "translation") -> tuple[np.ndarray, np.ndarray]:
    """Axes and radii of the velocity ellipsoid ``{J q̇ : ‖q̇‖ ≤ 1}`` for the chosen rows.

    Returns ``(radii, axes)``: radii (m,) = the singular values (descending), axes (m×m) = the
    left singular vectors as columns (directions in the base frame).
    """
    A = _rows(J, part)
    U, s, _ = np.linalg.svd(A)
    radii = np.zeros(A.shape[0])
    radii[: len(s)] = s
    return radii, U


_NAMES = ("rotation about x", "rotation about y", "rotation about z",
          "translation along x", "translation along y", "translation along z")


@dataclass
class SingularityReport:
    """rank, σ_min, whether singular (σ_min < tol), and the lost Cartesian direction (ω; v)."""

    rank: int
    sigma_min: float
    singular: bool
    lost_direction: np.ndarray
    description: str


def singularity(J: ArrayLike, tol: float = 1e-9) -> SingularityReport:
    """Rank test of a 6×n (or m×n) Jacobian and the Cartesian direction that cannot be produced.

    The lost direction is the left singular vector of the smallest singular value — the twist
    (ω; v) the arm cannot move along — described by its dominant component, e.g.
    "translation along x (0.98)".
    """
    A = as_array(J, "J", (None, None))
    U, s, _ = np.linalg.svd(A)
    m = A.shape[0]
    sig = np.zeros(m)
    sig[: len(s)] = s
    rank = int(np.sum(sig > tol))
    d = U[:, -1]
    k = int(np.argmax(np.abs(d)))
    if d[k] < 0:
        d = -d
    name = _NAMES[k] if m == 6 else f"direction {k}"
    return SingularityReport(rank, float(sig[-1]), bool(sig[-1] < tol), d, f"{name} ({d[k]:.2f})")


def resolved_rate(J: ArrayLike, V: ArrayLike, method: str = "pinv", damping: float = 0.05, adaptive: bool = False,
                  epsilon: float = 0.05, z: ArrayLike | None = None, rcond: float = 1e-12) -> np.ndarray:
    """Joint velocities for a desired Cartesian twist (Lecture 6): ``q̇ = J⁺V + (I − J⁺J) z``.

    J : m×n Jacobian (m ≤ 6; use the rows that matter, e.g. the 2 planar rows of the 2-link arm);
    V : (m,) desired twist; method : "pinv" (Moore–Penrose), "dls" (damped least squares
    ``q̇ = Jᵀ(JJᵀ + λ²I)⁻¹V``) or "damped_inverse" — the lecture's damped inverse
    ``q̇ = (J + pI)⁻¹ V`` for a square J, p a small constant added to the diagonal (it leaves an
    error ``J q̇ − V = −p q̇`` that accumulates in the end-effector position, as the lecture warns);
    damping : λ (or λ_max when adaptive) for "dls", p for "damped_inverse"; adaptive : λ² =
    λ_max² (1 − (σ_min/ε)²) when σ_min < ε, else 0 (undamped away from singularities);
    z : (n,) joint velocity projected into the null space (redundant arms: secondary tasks such
    as joint-limit avoidance), which leaves the task twist unchanged.
    """
    J = as_array(J, "J", (None, None))
    m, n = J.shape
    V = as_vector(V, "V", m)
    if method == "pinv":
        Jp = np.linalg.pinv(J, rcond=rcond)
    elif method == "dls":
        lam2 = as_scalar(damping, "damping", nonnegative=True) ** 2
        if adaptive:
            smin = np.linalg.svd(J, compute_uv=False)[-1] if m <= n else 0.0
            lam2 = lam2 * (1 - (smin / epsilon) ** 2) if smin < epsilon else 0.0
        # λ = 0 is the undamped limit, the pseudo-inverse (also at a singular J, where JJᵀ has no inverse)
        Jp = J.T @ np.linalg.inv(J @ J.T + lam2 * np.eye(m)) if lam2 > 0 else np.linalg.pinv(J, rcond=rcond)
    elif method == "damped_inverse":
        if m != n:
            raise InputError(f"J: the damped inverse (J + pI)⁻¹ needs a square Jacobian, got shape {J.shape}")
        p = as_scalar(damping, "damping", nonnegative=True)
        Jp = np.linalg.inv(J + p * np.eye(n))
    else:
        raise InputError(f"method: expected 'pinv', 'dls' or 'damped_inverse', got {method!r}")
    dq = Jp @ V
    if z is not None:
        z = as_vector(z, "z", n)
        dq = dq + (np.eye(n) - Jp @ J) @ z
    return dq


def joint_limit_gradient(q: ArrayLike, qlim: ArrayLike) -> np.ndarray:
    """``−∇H`` for ``H = ½ Σ ((qᵢ − q̄ᵢ)/(q_maxᵢ − q_minᵢ))²``: a null-space velocity pushing the joints
    toward the middle of their ranges (unlimited joints are left alone)."""
    q = as_vector(q, "q")
    qlim = as_array(qlim, "qlim", (len(q), 2), finite=False)
    span = qlim[:, 1] - qlim[:, 0]
    ok = np.isfinite(span) & (span > 0)
    g = np.zeros(len(q))
    mid = 0.5 * (qlim[:, 0] + qlim[:, 1])
    g[ok] = -(q[ok] - mid[ok]) / span[ok] ** 2
    return g


def manipulability_at(robot: RobotLike, q: ArrayLike, kind: str = "yoshikawa", part: str = "full",
                      frame: str | None = None) -> float:
    """:func:`manipulability` of ``robot``'s base-frame geometric Jacobian at q (one call)."""
    return manipulability(robot.jacobian(q, frame, reference="local_world_aligned"), kind, part)


def velocity_ellipsoid_at(robot: RobotLike, q: ArrayLike, part: str = "translation",
                          frame: str | None = None) -> tuple[np.ndarray, np.ndarray]:
    """:func:`velocity_ellipsoid` of ``robot`` at q (base-frame axes)."""
    return velocity_ellipsoid(robot.jacobian(q, frame, reference="local_world_aligned"), part)


def resolved_rate_at(robot: RobotLike, q: ArrayLike, V: ArrayLike, frame: str | None = None,
                     **kwargs: Any) -> np.ndarray:
    """Joint velocities of ``robot`` at q for the desired twist V (6,) = (ω; v of the frame origin,
    base axes); keyword arguments as :func:`resolved_rate`."""
    return resolved_rate(robot.jacobian(q, frame, reference="local_world_aligned"), V, **kwargs)


__all__ += ["manipulability_at", "velocity_ellipsoid_at", "resolved_rate_at", "SingularityReport"]

# Former names (before the X_from_Y rule): they warn and call the new function.
jacobian_to_frame = deprecated_alias(jacobian_in_frame, "jacobian_to_frame")
