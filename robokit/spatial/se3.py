r"""Rigid motions: SE(3), se(3), twists, the exponential and logarithm, adjoints (Lecture 2, seed 004 §2).

A pose ``T = [[R, p], [0, 1]]`` (4×4) maps coordinates in a moving frame to the reference
frame. A twist ``V = (ω, v)`` (6-vector, angular first) has the 4×4 matrix form
``[V] = [[[ω], v], [0, 0]]``. A screw axis ``S`` is a twist with ‖ω‖ = 1, or ω = 0 and ‖v‖ = 1.

Formulas (Modern Robotics, ch. 3):
    exp([S]θ) = [[exp([ω]θ), G(θ) v], [0, 1]],  G(θ) = Iθ + (1 − cos θ)[ω] + (θ − sin θ)[ω]²
    log T: [ω]θ = log R, v = G⁻¹(θ) p,  G⁻¹(θ)/θ = I/θ − [ω]/2 + (1/θ − cot(θ/2)/2)[ω]²
    Ad_T = [[R, 0], [[p]R, R]],  ad_V = [[[ω], 0], [[v], [ω]]]
"""
from __future__ import annotations

import numpy as np

from robokit._arrays import as_matrix, as_vector
from robokit.spatial import lie
from robokit.spatial.so3 import SO3_TOLERANCE, _distance_so3, project_to_SO3
from numpy.typing import ArrayLike
from robokit.errors import InputError

__all__ = [
    "trans_inv",
    "vec_to_se3",
    "se3_to_vec",
    "axis_ang_6",
    "matrix_exp_6",
    "matrix_log_6",
    "Rp_to_trans",
    "trans_to_Rp",
    "adjoint",
    "ad",
    "project_to_SE3",
    "distance_to_SE3",
    "test_if_SE3",
    "check_transform",
]


def check_transform(T: ArrayLike, name: str = "T", tol: float = SO3_TOLERANCE) -> np.ndarray:
    """Return ``T`` as a 4×4 float array, or raise ``ValueError`` if it is not in SE(3).

    The rotation block must be within ``tol`` of SO(3) and the last row ``[0, 0, 0, 1]``.
    """
    T = as_matrix(T, name, 4, 4)
    d = _distance_se3(T)
    if d > tol:
        raise InputError(f"{name}: not a homogeneous transform (distance to SE(3) {d:.3g} > {tol:g})")
    return T


def Rp_to_trans(R: ArrayLike, p: ArrayLike) -> np.ndarray:
    """The 4×4 pose ``[[R, p], [0, 1]]`` from a rotation R (3×3) and a position p (3,).

    Example: ``Rp_to_trans(np.eye(3), [1, 2, 3])`` is a pure translation.
    """
    from robokit.spatial.so3 import check_rotation

    R = check_rotation(R, "R")
    p = as_vector(p, "p", 3)
    T = np.eye(4)
    T[:3, :3] = R
    T[:3, 3] = p
    return T


def trans_to_Rp(T: ArrayLike) -> tuple[np.ndarray, np.ndarray]:
    """Split a 4×4 pose into ``(R, p)`` (copies, 3×3 and (3,))."""
    T = check_transform(T, "T")
    return T[:3, :3].copy(), T[:3, 3].copy()


def trans_inv(T: ArrayLike) -> np.ndarray:
    """Inverse of a pose: ``[[Rᵀ, −Rᵀp], [0, 1]]``."""
    T = check_transform(T, "T")
    return lie.inv(T)


def vec_to_se3(V: ArrayLike) -> np.ndarray:
    """The 4×4 matrix ``[V] = [[[ω], v], [0, 0]]`` of a twist ``V = (ω, v)``."""
    V = as_vector(V, "V", 6)
    m = np.zeros((4, 4))
    m[:3, :3] = lie.hat(V[:3])
    m[:3, 3] = V[3:]
    return m


def se3_to_vec(se3mat: ArrayLike) -> np.ndarray:
    """The twist ``(ω, v)`` of a 4×4 se(3) matrix (inverse of ``vec_to_se3``)."""
    m = as_matrix(se3mat, "se3mat", 4, 4)
    return np.array([m[2, 1], m[0, 2], m[1, 0], m[0, 3], m[1, 3], m[2, 3]])


def axis_ang_6(expc6: ArrayLike) -> tuple[np.ndarray, float]:
    """Split exponential coordinates ``Sθ`` (6-vector) into the screw axis S and θ.

    θ = ‖ω‖, or ‖v‖ when ω = 0 (pure translation). Raises ``ValueError`` for the zero
    vector. Example: ``axis_ang_6([0, 0, 0, 0, 0, 2])`` → ``([0, 0, 0, 0, 0, 1], 2.0)``.
    """
    V = as_vector(expc6, "expc6", 6)
    theta = float(np.linalg.norm(V[:3]))
    if theta == 0.0:
        theta = float(np.linalg.norm(V[3:]))
    if theta == 0.0:
        raise InputError("expc6: the zero vector has no screw axis")
    return V / theta, theta


def matrix_exp_6(se3mat: ArrayLike) -> np.ndarray:
    """The pose ``exp([S]θ)`` of a 4×4 se(3) matrix (closed form, exact for pure translation).

    Example: ``matrix_exp_6(vec_to_se3([0, 0, 0, 1, 2, 3]))`` is the translation (1, 2, 3).
    """
    m = as_matrix(se3mat, "se3mat", 4, 4)
    return lie.exp6(np.array([m[2, 1], m[0, 2], m[1, 0], m[0, 3], m[1, 3], m[2, 3]]))


def matrix_log_6(T: ArrayLike) -> np.ndarray:
    """The 4×4 se(3) matrix ``[S]θ`` with ``exp([S]θ) = T`` and rotation angle θ ∈ [0, π].

    A pure translation gives ``[[0, p], [0, 0]]``; θ = π follows ``matrix_log_3``'s axis
    choice. Raises ``ValueError`` if T is not in SE(3).
    """
    T = check_transform(T, "T")
    V = lie.log6(T)
    m = np.zeros((4, 4))
    m[:3, :3] = lie.hat(V[:3])
    m[:3, 3] = V[3:]
    return m


def adjoint(T: ArrayLike) -> np.ndarray:
    """The 6×6 adjoint ``Ad_T = [[R, 0], [[p]R, R]]`` mapping twists: ``V_a = Ad_{T_ab} V_b``."""
    T = check_transform(T, "T")
    return lie.adjoint(T)


def ad(V: ArrayLike) -> np.ndarray:
    """The 6×6 ``ad_V = [[[ω], 0], [[v], [ω]]]`` of a twist ``V = (ω, v)`` (Lie bracket ``ad_V W = [V, W]``)."""
    return lie.ad(as_vector(V, "V", 6))


def project_to_SE3(mat: ArrayLike) -> np.ndarray:
    """The SE(3) matrix nearest to ``mat``: the rotation block projected to SO(3) (SVD), p kept."""
    M = as_matrix(mat, "mat", 4, 4)
    T = np.eye(4)
    T[:3, :3] = project_to_SO3(M[:3, :3])
    T[:3, 3] = M[:3, 3]
    return T


def _distance_se3(M: np.ndarray) -> float:
    d = _distance_so3(M[:3, :3])
    if d >= 1e9:
        return d
    last = M[3] - (0.0, 0.0, 0.0, 1.0)
    return float(np.sqrt(d * d + last @ last))


def distance_to_SE3(mat: ArrayLike) -> float:
    """Distance of a 4×4 matrix from SE(3), as Modern Robotics defines it.

    With R the top-left block: if det R > 0, ``‖[[RᵀR, 0], [last row]] − I‖_F`` (the position
    column does not count); else the large value 1e9.
    """
    return _distance_se3(as_matrix(mat, "mat", 4, 4))


def test_if_SE3(mat: ArrayLike) -> bool:
    """True if ``distance_to_SE3(mat) < 1e-3``."""
    return bool(distance_to_SE3(mat) < 1e-3)


test_if_SE3.__test__ = False  # type: ignore[attr-defined]
