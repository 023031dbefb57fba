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
    """Jacobian (6×n, rows (ω; v) in the base frame) of any forward kinematics by central differences.

    Column j is ``ω_j = vee(Ṙ Rᵀ)``, ``v_j = ṗ`` with the derivatives
    ``(f(q + h e_j) − f(q − h e_j)) / 2h`` (Lecture 6: the Jacobian by perturbation). Accurate to
    about h².

    Parameters
    ----------
    fk : callable or robot
        A function q (n,) → 4×4 pose of the tool in the base frame, or a robot (its ``frame_pose``).
    q : (n,) array_like
        Joint values (rad, m).
    h : float
        Perturbation (> 0).

    Returns
    -------
    (6, n) ndarray
        The geometric Jacobian, v of the tool origin, base axes (rad/s and m/s per unit rate).

    Examples
    --------
    >>> robot = rk.load("twolink")
    >>> q = np.array([0.3, 0.7])
    >>> bool(np.allclose(numerical_jacobian(robot, q), geometric_jacobian(robot, q), atol=1e-8))
    True
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
    """E(φ) (3×3) with ``ω = E(φ) φ̇``: Euler-angle rates to the angular velocity in base axes (Lecture 6).

    With the axes ``e₁, e₂, e₃`` of the sequence:

    * intrinsic, ``R = R₁(a) R₂(b) R₃(c)``: ``E = [e₁, R₁(a) e₂, R₁(a) R₂(b) e₃]``;
    * extrinsic, ``R = R₃(c) R₂(b) R₁(a)``: ``E = [R₃(c) R₂(b) e₁, R₃(c) e₂, e₃]``

    (differentiate R and read ``ω`` off ``Ṙ Rᵀ = S(ω)``). ZYX gives
    ``[[0, −sα, cα cβ], [0, cα, sα cβ], [1, 0, −sβ]]`` (singular at cos β = 0); ZYZ
    ``[[0, −sφ, cφ sθ], [0, cφ, sφ sθ], [1, 0, cθ]]`` (the Lecture 6 homework's B(Γ), singular at
    sin θ = 0); the lecture's roll–pitch–yaw ``R = Rx(θr) Ry(θp) Rz(θy)`` is intrinsic "XYZ" with
    ``φ = (θr, θp, θy)`` and ``B(Γ) = [[1, 0, sθp], [0, cθr, −cθp sθr], [0, sθr, cθp cθr]]``.
    The matrix is singular when the first and third axes line up (Tait–Bryan b = ±π/2, proper
    Euler b ∈ {0, π}).

    Parameters
    ----------
    angles : (3,) array_like
        ``φ = (a, b, c)`` (rad) of the sequence ``seq``.
    seq : str
        Any of the 12 sequences (``robokit.spatial.EULER_SEQUENCES``: "XYZ", "ZYX", "ZYZ", …).
    tol : float
        Unused here (kept for the signature :func:`analytical_jacobian` shares).
    extrinsic : bool
        Fixed axes instead of moving axes (see :func:`robokit.spatial.matrix_from_euler`).

    Returns
    -------
    (3, 3) ndarray
        E(φ).

    Examples
    --------
    >>> euler_rate_matrix([0.0, 0.0, 0.0], "ZYX")          # at zero: columns z, y, x
    array([[0., 0., 1.],
           [0., 1., 0.],
           [1., 0., 0.]])
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
    """``J_a = blockdiag(E(φ)⁻¹, I) J``: rows (φ̇; ṗ) — Euler-angle rates and linear velocity (Lecture 6).

    The lecture writes the same with the rows in the order (v; ω): ``J_a = blockdiag(I, B(Γ)⁻¹) J``;
    robokit keeps angular rows first. Where E(φ) is singular (|det E| < tol: β = ±π/2 for ZYX,
    θ = 0 or π for ZYZ) :class:`~robokit.errors.InputError` says "representation singularity" — the
    analytical Jacobian does not exist there even though the arm may be far from any singularity.

    Parameters
    ----------
    J : (6, n) array_like
        Geometric Jacobian (ω; v) in the base frame.
    angles : (3,) array_like
        The current Euler angles of the tool orientation in the sequence ``seq`` (rad).
    seq : str
        Any of the 12 sequences.
    tol : float
        Threshold on |det E(φ)|.
    extrinsic : bool
        Fixed axes instead of moving axes.

    Returns
    -------
    (6, n) ndarray
        Rows (φ̇; ṗ) per unit joint rate (rad/s, m/s).

    Examples
    --------
    >>> robot = rk.load("puma560")
    >>> q = np.array([0.1, -0.5, 0.4, 0.3, 0.6, -0.2])
    >>> J = robot.jacobian(q, reference="local_world_aligned")
    >>> Ja = analytical_jacobian(J, rk.matrix_to_euler(robot.frame_pose(q)[:3, :3]), "ZYX")
    >>> bool(np.allclose(euler_rate_matrix(rk.matrix_to_euler(robot.frame_pose(q)[:3, :3])) @ Ja[:3], J[:3]))
    True
    """
    J = as_matrix(J, "J", 6, None)
    E = euler_rate_matrix(angles, seq, extrinsic=extrinsic)
    d = float(np.linalg.det(E))
    if abs(d) < tol:
        raise InputError(f"angles: representation singularity of {seq} Euler angles (det E = {d:.2e}); "
                         "E(φ) has no inverse here")
    return np.vstack([np.linalg.solve(E, J[:3]), J[3:]])


def geometric_jacobian(robot: Robot, q: ArrayLike) -> np.ndarray:
    """The geometric Jacobian (6×n) of the robot's tool point, base axes, rows ``(ω; v)`` (Lecture 6).

    ``ω = J_ω q̇`` is the tool's angular velocity and ``v = J_v q̇`` the velocity of the tool
    frame's origin, both in base-frame axes (the lecture stacks them as (v; ω); robokit keeps
    angular rows first). Built from the product-of-exponentials space Jacobian ``J_s``: column i
    is ``(ω_i, v_i + ω_i × p)`` with p the tool position, i.e. ``(zᵢ, zᵢ × (p − oᵢ))`` for a revolute
    joint and ``(0, zᵢ)`` for a prismatic one. Pinocchio's LOCAL_WORLD_ALIGNED (``reference="base"``).

    Parameters
    ----------
    robot : Robot
        A :class:`robokit.Robot` (its ``poe`` parameters; the tip is the tool).
    q : (n,) array_like
        Joint values (rad, m).

    Returns
    -------
    (6, n) ndarray
        Rows ω (rad/s) and v (m/s) per unit joint rate.

    Examples
    --------
    The twolink arm (a₁ = 1, a₂ = 0.8) at q = (0, 90°): the lecture's
    ``J_v = [[−a₁s₁ − a₂s₁₂, −a₂s₁₂], [a₁c₁ + a₂c₁₂, a₂c₁₂]]``.

    >>> geometric_jacobian(rk.load("twolink"), [0.0, np.pi / 2])[3:5].round(4)
    array([[-0.8, -0.8],
           [ 1. ,  0. ]])
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
    """The 6×6 map of twists ``(ω, v)`` expressed in frame b to frame a: ``V_a = Ad_{T_ab} V_b`` (Lecture 6).

    For two frames on the same body, or a frame on another body rigidly fixed to it.

    Parameters
    ----------
    T_a_b : (4, 4) array_like
        Pose of frame b in frame a (checked).

    Returns
    -------
    (6, 6) ndarray
        ``Ad_{T_ab}``.

    Examples
    --------
    Frame b 1 m along a's x, spinning about its z at 1 rad/s: a's origin sees v = (0, −1, 0).

    >>> twist_transform(rk.Rp_to_trans(np.eye(3), [1, 0, 0])) @ [0, 0, 1, 0, 0, 0]
    array([ 0.,  0.,  1.,  0., -1.,  0.])
    """
    return lie.adjoint(check_transform(T_a_b, "T_a_b"))


def wrench_transform(T_a_b: ArrayLike) -> np.ndarray:
    """The 6×6 map of wrenches ``(m, f)`` in frame b to frame a: ``F_a = Ad_{T_ba}ᵀ F_b`` (Lecture 6).

    The same physical force, its moment taken about a's origin.

    Parameters
    ----------
    T_a_b : (4, 4) array_like
        Pose of frame b in frame a (checked).

    Returns
    -------
    (6, 6) ndarray
        The wrench map.

    Examples
    --------
    10 N down (−z) at b, 1 m along a's x: about a's origin a moment of 10 N·m about +y.

    >>> wrench_transform(rk.Rp_to_trans(np.eye(3), [1, 0, 0])) @ [0, 0, 0, 0, 0, -10]
    array([  0.,  10.,   0.,   0.,   0., -10.])
    """
    return lie.adjoint(lie.inv(check_transform(T_a_b, "T_a_b"))).T


def jacobian_in_frame(J: ArrayLike, R: ArrayLike) -> np.ndarray:
    """Re-express a geometric Jacobian (ω; v) in rotated axes: ``blockdiag(R, R) J``.

    With R = R_tool_base (= R_base_toolᵀ) a base-frame Jacobian (``reference="base"``) becomes the
    tool-frame one (``reference="tool"``) and vice versa with R_base_tool; the point whose velocity v
    is does not change, only the axes rotate. (Formerly ``jacobian_to_frame``.)

    Parameters
    ----------
    J : (6, n) array_like
        Jacobian, rows (ω; v).
    R : (3, 3) array_like
        Rotation from the old axes to the new: new coordinates = R · old coordinates.

    Returns
    -------
    (6, n) ndarray
        The Jacobian in the new axes.

    Examples
    --------
    >>> robot = rk.load("puma560")
    >>> q = np.array([0.1, -0.5, 0.4, 0.3, 0.6, -0.2])
    >>> R_base_tool = robot.frame_pose(q)[:3, :3]
    >>> J_tool = jacobian_in_frame(robot.jacobian(q, reference="base"), R_base_tool.T)
    >>> bool(np.allclose(J_tool, robot.jacobian(q, reference="tool")))
    True
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
    """A manipulability measure of a Jacobian (or of its translation/rotation rows) (Lecture 6).

    Parameters
    ----------
    J : (m, n) array_like
        Jacobian; rows (ω; v) when ``part`` is not "full".
    kind : str
        "yoshikawa" — ``w = √det(J Jᵀ)`` (the product of the singular values; 0 at a singularity);
        "condition" — ``σ_max / σ_min`` (∞ at a singularity); "inverse_condition" — ``σ_min / σ_max``
        (the ratio of the shortest to the longest ellipsoid axis); "min_singular" — ``σ_min``.
    part : str
        "full", "translation" (rows v) or "rotation" (rows ω).

    Returns
    -------
    float
        The measure.

    Examples
    --------
    For the planar 2-link arm's translational Jacobian, ``w = |a₁ a₂ sin θ₂|`` (1 · 0.8 here):

    >>> J = rk.load("twolink").jacobian([0.4, np.pi / 2], reference="base")[3:5]
    >>> round(manipulability(J), 4)
    0.8
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
    """Axes and radii of the velocity ellipsoid ``{J q̇ : ‖q̇‖ ≤ 1}`` for the chosen rows (Lecture 6).

    Parameters
    ----------
    J : (6, n) or (m, n) array_like
        Jacobian, rows (ω; v) unless ``part="full"``.
    part : str
        "translation" (rows v, default), "rotation" (rows ω) or "full".

    Returns
    -------
    radii : (m,) ndarray
        The singular values, descending (m/s or rad/s per unit joint speed).
    axes : (m, m) ndarray
        The left singular vectors as columns: the axes' directions in the Jacobian's frame.

    Examples
    --------
    >>> radii, axes = velocity_ellipsoid(np.diag([2.0, 0.5]), "full")
    >>> radii
    array([2. , 0.5])
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
    """What :func:`singularity` found.

    Attributes
    ----------
    rank : int
        Number of singular values above the tolerance.
    sigma_min : float
        Smallest singular value.
    singular : bool
        ``sigma_min < tol``.
    lost_direction : (m,) ndarray
        Unit Cartesian direction (ω; v) the arm cannot move along (the left singular vector of σ_min).
    description : str
        Its dominant component in words, e.g. "translation along x (0.98)".
    """

    rank: int
    sigma_min: float
    singular: bool
    lost_direction: np.ndarray
    description: str


def singularity(J: ArrayLike, tol: float = 1e-9) -> SingularityReport:
    """Rank test of a Jacobian and the Cartesian direction that cannot be produced (Lecture 6).

    The lost direction is the left singular vector of the smallest singular value — the twist
    (ω; v) the arm cannot move along — described by its dominant component.

    Parameters
    ----------
    J : (6, n) or (m, n) array_like
        Jacobian.
    tol : float
        Singular when σ_min < tol.

    Returns
    -------
    SingularityReport
        ``.rank``, ``.sigma_min``, ``.singular``, ``.lost_direction``, ``.description``.

    Examples
    --------
    The twolink arm stretched out cannot move along its own length (the base x axis):

    >>> J = rk.load("twolink").jacobian([0.0, 0.0], reference="base")[3:5]
    >>> rep = singularity(J)
    >>> rep.singular, rep.rank, rep.lost_direction.round(4)
    (True, 1, array([ 1., -0.]))
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

    Parameters
    ----------
    J : (m, n) array_like
        Jacobian (m ≤ 6; use the rows that matter, e.g. the 2 planar rows of the 2-link arm).
    V : (m,) array_like
        Desired twist (the same rows; rad/s, m/s).
    method : str
        "pinv" (Moore–Penrose), "dls" (damped least squares ``q̇ = Jᵀ(JJᵀ + λ²I)⁻¹V``) or
        "damped_inverse" — the lecture's ``q̇ = (J + pI)⁻¹ V`` for a square J (it leaves an error
        ``J q̇ − V = −p q̇`` that accumulates in the end-effector position, as the lecture warns).
    damping : float
        λ (or λ_max when adaptive) for "dls", p for "damped_inverse".
    adaptive : bool
        "dls" only: λ² = λ_max² (1 − (σ_min/ε)²) when σ_min < ε, else 0 (undamped away from
        singularities).
    epsilon : float
        ε of the adaptive damping.
    z : (n,) array_like, optional
        Joint velocity projected into the null space (redundant arms: secondary tasks such as
        joint-limit avoidance, :func:`joint_limit_gradient`); it leaves the task twist unchanged.
    rcond : float
        Cut-off of the pseudo-inverse.

    Returns
    -------
    (n,) ndarray
        q̇ (rad/s, m/s).

    Examples
    --------
    The twolink arm at q = (0, 90°) moving its tip at 1 m/s along x:

    >>> J = rk.load("twolink").jacobian([0.0, np.pi / 2], reference="base")[3:5]
    >>> dq = resolved_rate(J, [1.0, 0.0])
    >>> (J @ dq).round(4)
    array([1., 0.])
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
    toward the middle of their ranges (unlimited joints are left alone).

    Parameters
    ----------
    q : (n,) array_like
        Joint values (rad, m).
    qlim : (n, 2) array_like
        Lower and upper limits (±inf where unlimited).

    Returns
    -------
    (n,) ndarray
        ``−(qᵢ − q̄ᵢ) / (q_maxᵢ − q_minᵢ)²`` (0 for unlimited joints).

    Examples
    --------
    >>> joint_limit_gradient([1.0, 0.0], [[-2.0, 2.0], [-np.inf, np.inf]])
    array([-0.0625,  0.    ])
    """
    q = as_vector(q, "q")
    qlim = as_array(qlim, "qlim", (len(q), 2), finite=False)
    span = qlim[:, 1] - qlim[:, 0]
    ok = np.isfinite(span) & (span > 0)
    g = np.zeros(len(q))
    mid = 0.5 * (qlim[ok, 0] + qlim[ok, 1])  # only where finite (−inf + inf would warn)
    g[ok] = -(q[ok] - mid) / span[ok] ** 2
    return g


def manipulability_at(robot: RobotLike, q: ArrayLike, kind: str = "yoshikawa", part: str = "full",
                      frame: str | None = None) -> float:
    """:func:`manipulability` of ``robot``'s base-frame geometric Jacobian at q (one call).

    Parameters
    ----------
    robot : RobotLike
        The robot (its ``jacobian(q, frame, reference="local_world_aligned")``).
    q : (n,) array_like
        Joint values (rad, m).
    kind, part : str
        As for :func:`manipulability`.
    frame : str, optional
        The frame (default: the tip).

    Returns
    -------
    float
        The measure.

    Examples
    --------
    The PUMA 560 at its wrist singularity (θ₅ = 0: axes 4 and 6 line up) and away from it:

    >>> puma = rk.load("puma560")
    >>> round(manipulability_at(puma, [0.1, -0.5, 0.4, 0.3, 0.0, -0.2]), 6)
    0.0
    >>> manipulability_at(puma, [0.1, -0.5, 0.4, 0.3, 0.6, -0.2]) > 0.01
    True
    """
    return manipulability(robot.jacobian(q, frame, reference="local_world_aligned"), kind, part)


def velocity_ellipsoid_at(robot: RobotLike, q: ArrayLike, part: str = "translation",
                          frame: str | None = None) -> tuple[np.ndarray, np.ndarray]:
    """:func:`velocity_ellipsoid` of ``robot``'s base-frame geometric Jacobian at q.

    Parameters
    ----------
    robot : RobotLike
        The robot.
    q : (n,) array_like
        Joint values (rad, m).
    part : str
        "translation" (default), "rotation" or "full".
    frame : str, optional
        The frame (default: the tip).

    Returns
    -------
    radii : ndarray
        Semi-axes, descending.
    axes : ndarray
        Their directions (columns), base axes.
    """
    return velocity_ellipsoid(robot.jacobian(q, frame, reference="local_world_aligned"), part)


def resolved_rate_at(robot: RobotLike, q: ArrayLike, V: ArrayLike, frame: str | None = None,
                     **kwargs: Any) -> np.ndarray:
    """Joint velocities of ``robot`` at q for the desired twist V of a frame (:func:`resolved_rate`).

    Parameters
    ----------
    robot : RobotLike
        The robot.
    q : (n,) array_like
        Joint values (rad, m).
    V : (6,) array_like
        Desired twist (ω; v of the frame origin), base axes (rad/s, m/s).
    frame : str, optional
        The frame (default: the tip).
    **kwargs
        As for :func:`resolved_rate` (method, damping, z, …).

    Returns
    -------
    (n,) ndarray
        q̇ (rad/s, m/s).
    """
    return resolved_rate(robot.jacobian(q, frame, reference="local_world_aligned"), V, **kwargs)


__all__ += ["manipulability_at", "velocity_ellipsoid_at", "resolved_rate_at", "SingularityReport"]

# Former names (before the X_from_Y rule): they warn and call the new function.
jacobian_to_frame = deprecated_alias(jacobian_in_frame, "jacobian_to_frame")
