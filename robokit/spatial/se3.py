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
from robokit.spatial.so3 import SO3_TOLERANCE, _check_group, _distance_so3, project_to_SO3
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
    """Return ``T`` as a 4×4 float array, or raise :class:`~robokit.errors.InputError` if it is not in SE(3).

    The rotation block must be within ``tol`` of SO(3) and the last row ``[0, 0, 0, 1]``.

    Parameters
    ----------
    T : (4, 4) array_like
        The candidate pose.
    name : str
        The argument's name in the error message.
    tol : float
        Largest accepted distance to SE(3) (:func:`distance_to_SE3`; default 1e-6).

    Returns
    -------
    (4, 4) ndarray
        ``T`` as float64.

    Examples
    --------
    >>> check_transform(np.eye(4)).shape
    (4, 4)
    """
    return _check_group(T, name, 4, _distance_se3, "a homogeneous transform", "SE(3)", tol)


def Rp_to_trans(R: ArrayLike, p: ArrayLike) -> np.ndarray:
    """The 4×4 pose ``T = [[R, p], [0, 1]]`` from a rotation and a position (seed 004 §2).

    Parameters
    ----------
    R : (3, 3) array_like
        Orientation of the moving frame in the reference frame (checked to be a rotation).
    p : (3,) array_like
        Position of its origin in the reference frame (m).

    Returns
    -------
    (4, 4) ndarray
        The homogeneous transform.

    Examples
    --------
    A frame rotated 90° about z and moved to (1, 2, 3): its x axis points along the reference y.

    >>> T = Rp_to_trans([[0, -1, 0], [1, 0, 0], [0, 0, 1]], [1, 2, 3])
    >>> T @ [1, 0, 0, 1]                    # the point x = 1 of the moving frame
    array([1., 3., 3., 1.])
    """
    from robokit.spatial.so3 import check_rotation

    R = check_rotation(R, "R")
    p = as_vector(p, "p", 3)
    T = np.eye(4)
    T[:3, :3] = R
    T[:3, 3] = p
    return T


def trans_to_Rp(T: ArrayLike) -> tuple[np.ndarray, np.ndarray]:
    """Split a 4×4 pose into its rotation and position (seed 004 §2).

    Parameters
    ----------
    T : (4, 4) array_like
        The pose to split (checked: see :mod:`robokit.spatial`).

    Returns
    -------
    R : (3, 3) ndarray
        Rotation block (a copy).
    p : (3,) ndarray
        Position column (a copy, m).

    Examples
    --------
    >>> R, p = trans_to_Rp([[1, 0, 0, 0.5], [0, 1, 0, 0], [0, 0, 1, 2], [0, 0, 0, 1]])
    >>> p
    array([0.5, 0. , 2. ])
    """
    T = check_transform(T, "T")
    return T[:3, :3].copy(), T[:3, 3].copy()


def trans_inv(T: ArrayLike) -> np.ndarray:
    """Inverse of a pose: ``T⁻¹ = [[Rᵀ, −Rᵀp], [0, 1]]`` (seed 004 §2).

    Parameters
    ----------
    T : (4, 4) array_like
        ``T_a_b``, a homogeneous transform (checked).

    Returns
    -------
    (4, 4) ndarray
        ``T_b_a``.

    Examples
    --------
    >>> T = Rp_to_trans([[0, -1, 0], [1, 0, 0], [0, 0, 1]], [1, 2, 3])
    >>> trans_inv(T)[:3, 3]                 # −Rᵀp
    array([-2.,  1., -3.])
    >>> bool(np.allclose(trans_inv(T) @ T, np.eye(4)))
    True
    """
    T = check_transform(T, "T")
    return lie.inv(T)


def vec_to_se3(V: ArrayLike) -> np.ndarray:
    """The 4×4 matrix ``[V] = [[[ω], v], [0, 0]]`` of a twist ``V = (ω, v)`` (seed 004 §2).

    Parameters
    ----------
    V : (6,) array_like
        Twist, angular part first: ω (rad/s), v (m/s).

    Returns
    -------
    (4, 4) ndarray
        ``[V]`` ∈ se(3).

    Examples
    --------
    >>> vec_to_se3([0, 0, 1, 1, 2, 3])
    array([[ 0., -1.,  0.,  1.],
           [ 1.,  0., -0.,  2.],
           [-0.,  0.,  0.,  3.],
           [ 0.,  0.,  0.,  0.]])
    """
    return _se3_matrix(as_vector(V, "V", 6))


def _se3_matrix(V: np.ndarray) -> np.ndarray:
    # [V] = [[[ω], v], [0, 0]] of a checked (6,) twist
    m = np.zeros((4, 4))
    m[:3, :3] = lie.hat(V[:3])
    m[:3, 3] = V[3:]
    return m


def se3_to_vec(se3mat: ArrayLike) -> np.ndarray:
    """The twist ``(ω, v)`` of a 4×4 se(3) matrix (inverse of :func:`vec_to_se3`).

    Parameters
    ----------
    se3mat : (4, 4) array_like
        ``[V]``; only the lower-left entries of its skew block are read.

    Returns
    -------
    (6,) ndarray
        ``(ω, v)``.

    Examples
    --------
    >>> se3_to_vec(vec_to_se3([1, 2, 3, 4, 5, 6]))
    array([1., 2., 3., 4., 5., 6.])
    """
    m = as_matrix(se3mat, "se3mat", 4, 4)
    return np.array([m[2, 1], m[0, 2], m[1, 0], m[0, 3], m[1, 3], m[2, 3]])


def axis_ang_6(expc6: ArrayLike) -> tuple[np.ndarray, float]:
    """Split exponential coordinates ``Sθ`` (6-vector) into the screw axis S and θ (seed 004 §2).

    θ = ‖ω‖, or ‖v‖ when ω = 0 (pure translation).

    Parameters
    ----------
    expc6 : (6,) array_like
        Exponential coordinates ``Sθ = (ωθ, vθ)``; not the zero vector
        (:class:`~robokit.errors.InputError`).

    Returns
    -------
    S : (6,) ndarray
        The screw axis (‖ω‖ = 1, or ω = 0 and ‖v‖ = 1).
    theta : float
        Distance along the screw: rad (or m for a pure translation).

    Examples
    --------
    >>> axis_ang_6([0, 0, 0, 0, 0, 2])           # pure translation of 2 m along z
    (array([0., 0., 0., 0., 0., 1.]), 2.0)
    >>> S, theta = axis_ang_6([0, 0, 3, 0, 0, 1])
    >>> S, theta
    (array([0.    , 0.    , 1.    , 0.    , 0.    , 0.3333]), 3.0)
    """
    V = as_vector(expc6, "expc6", 6)
    theta = float(np.linalg.norm(V[:3]))
    if theta == 0.0:
        theta = float(np.linalg.norm(V[3:]))
    if theta == 0.0:
        raise InputError("expc6: the zero vector has no screw axis")
    return V / theta, theta


def matrix_exp_6(se3mat: ArrayLike) -> np.ndarray:
    """The pose ``exp([S]θ) = [[exp([ω]θ), G(θ) v], [0, 1]]`` of a 4×4 se(3) matrix (Modern Robotics ch. 3).

    ``G(θ) = Iθ + (1 − cos θ)[ω] + (θ − sin θ)[ω]²``; exact for pure translation (ω = 0).

    Parameters
    ----------
    se3mat : (4, 4) array_like
        ``[S]θ`` ∈ se(3).

    Returns
    -------
    (4, 4) ndarray
        The pose T ∈ SE(3).

    Examples
    --------
    A half turn about the z axis through (1, 0, 0) carries the origin to (2, 0, 0):

    >>> S = [0, 0, 1, 0, -1, 0]                  # ω = z, v = −ω × q with q = (1, 0, 0)
    >>> matrix_exp_6(vec_to_se3(np.pi * np.array(S)))[:3, 3].round(4)
    array([2., 0., 0.])
    """
    return lie.exp6(se3_to_vec(se3mat))


def matrix_log_6(T: ArrayLike) -> np.ndarray:
    """The 4×4 se(3) matrix ``[S]θ`` with ``exp([S]θ) = T`` and rotation angle θ ∈ [0, π] (seed 004 §2).

    ``[ω]θ = log R``, ``v = G⁻¹(θ) p``. A pure translation gives ``[[0, p], [0, 0]]``; θ = π follows
    :func:`matrix_log_3`'s axis choice.

    Parameters
    ----------
    T : (4, 4) array_like
        A pose (checked: :class:`~robokit.errors.InputError` if not in SE(3)).

    Returns
    -------
    (4, 4) ndarray
        ``[S]θ`` ∈ se(3).

    Examples
    --------
    >>> T = [[1, 0, 0, 1], [0, 1, 0, 2], [0, 0, 1, 3], [0, 0, 0, 1]]
    >>> se3_to_vec(matrix_log_6(T))             # pure translation
    array([0., 0., 0., 1., 2., 3.])
    >>> V = np.array([0.1, -0.4, 0.8, 1.0, 0.5, -2.0])
    >>> bool(np.allclose(se3_to_vec(matrix_log_6(matrix_exp_6(vec_to_se3(V)))), V))
    True
    """
    return _se3_matrix(lie.log6(check_transform(T, "T")))


def adjoint(T: ArrayLike) -> np.ndarray:
    """The 6×6 adjoint ``Ad_T = [[R, 0], [[p]R, R]]`` mapping twists: ``V_a = Ad_{T_ab} V_b`` (seed 004 §2).

    Parameters
    ----------
    T : (4, 4) array_like
        ``T_a_b``, a pose (checked).

    Returns
    -------
    (6, 6) ndarray
        ``Ad_{T_ab}``, for twists ordered (ω, v).

    Examples
    --------
    A frame b at p = (1, 0, 0) in a spinning at 1 rad/s about its own z: seen from a, the point at
    a's origin moves at v = p × ω = (0, −1, 0).

    >>> T_ab = Rp_to_trans(np.eye(3), [1, 0, 0])
    >>> adjoint(T_ab) @ [0, 0, 1, 0, 0, 0]
    array([ 0.,  0.,  1.,  0., -1.,  0.])
    """
    T = check_transform(T, "T")
    return lie.adjoint(T)


def ad(V: ArrayLike) -> np.ndarray:
    """The 6×6 ``ad_V = [[[ω], 0], [[v], [ω]]]`` of a twist ``V = (ω, v)`` (seed 004 §2).

    ``ad_V W`` is the Lie bracket ``[V, W]``; ``−ad_Vᵀ F`` appears in the Newton–Euler equations.

    Parameters
    ----------
    V : (6,) array_like
        Twist (ω, v).

    Returns
    -------
    (6, 6) ndarray
        ``ad_V``.

    Examples
    --------
    >>> V = np.array([0, 0, 1, 1, 0, 0])
    >>> bool(np.allclose(ad(V) @ V, 0))         # [V, V] = 0
    True
    >>> ad(V)[3:, :3]                           # the [v] block
    array([[ 0., -0.,  0.],
           [ 0.,  0., -1.],
           [-0.,  1.,  0.]])
    """
    return lie.ad(as_vector(V, "V", 6))


def project_to_SE3(mat: ArrayLike) -> np.ndarray:
    """The SE(3) matrix nearest to ``mat``: the rotation block projected to SO(3) (SVD), p kept.

    Parameters
    ----------
    mat : (4, 4) array_like
        Any real 4×4 matrix (its last row is replaced by [0, 0, 0, 1]).

    Returns
    -------
    (4, 4) ndarray
        A pose in SE(3).

    Examples
    --------
    >>> T = project_to_SE3([[1.01, 0, 0, 1], [0, 0.99, 0, 2], [0, 0, 1, 3], [0.1, 0, 0, 0.9]])
    >>> test_if_SE3(T), T[:3, 3].tolist()
    (True, [1.0, 2.0, 3.0])
    """
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

    Parameters
    ----------
    mat : (4, 4) array_like
        Any real 4×4 matrix.

    Returns
    -------
    float
        The distance (0 for a pose).

    Examples
    --------
    >>> distance_to_SE3(Rp_to_trans(np.eye(3), [5, 6, 7]))
    0.0
    """
    return _distance_se3(as_matrix(mat, "mat", 4, 4))


def test_if_SE3(mat: ArrayLike) -> bool:
    """Whether a 4×4 matrix is (close to) a pose: ``distance_to_SE3(mat) < 1e-3``.

    Parameters
    ----------
    mat
        As for :func:`distance_to_SE3`.

    Returns
    -------
    bool
        True for a homogeneous transform (to 1e-3).

    Examples
    --------
    >>> test_if_SE3(np.eye(4)), test_if_SE3(np.zeros((4, 4)))
    (True, False)
    """
    return bool(distance_to_SE3(mat) < 1e-3)


test_if_SE3.__test__ = False  # type: ignore[attr-defined]
