r"""Velocity kinematics of Lecture 6: numerical and analytical Jacobians, velocity and wrench
transforms, manipulability and singularities, resolved-rate motion control.

Jacobians here are geometric, rows ``(ω; v)`` with v the velocity of the frame's origin, in the
base frame unless said otherwise (Pinocchio's LOCAL_WORLD_ALIGNED), as the course writes them.

The functions that take a Jacobian ``J`` first (:func:`jacobian_in_frame`, :func:`manipulability`,
:func:`velocity_ellipsoid`, :func:`force_ellipsoid`, :func:`singularity`, :func:`resolved_rate`)
also take a robot followed by its joint values q in its place: ``f(robot, q, ...)`` (and
``frame=``, default the tip) uses the robot's geometric Jacobian at q,
``robot.jacobian(q, frame, reference="local_world_aligned")``. :func:`manipulability_at`,
:func:`velocity_ellipsoid_at` and :func:`resolved_rate_at` do the same with ``robot``, ``q`` and
``frame`` named in their signatures.
"""
from __future__ import annotations

import functools
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any, Callable, TypeVar, cast

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
    "force_ellipsoid",
    "singularity",
    "resolved_rate",
    "joint_limit_gradient",
]


def numerical_jacobian(fk: Callable[[np.ndarray], ArrayLike] | RobotLike, q: ArrayLike, h: float = 1e-6) -> np.ndarray:
    """Geometric Jacobian of any forward kinematics by central differences (Lecture 6).

    Column j is ``ω_j = vee(Ṙ Rᵀ)``, ``v_j = ṗ`` with the derivatives
    ``(f(q + h e_j) − f(q − h e_j)) / 2h`` (the Jacobian by perturbation); accurate to about h².

    Parameters
    ----------
    fk : callable or robot
        A function q (n,) → (4, 4) pose in the base frame, or a robot (its ``frame_pose``, the tool).
    q : (n,) array_like
        Joint values (rad / m) where the Jacobian is taken.
    h : float, optional
        Perturbation of each joint (rad / m), positive; default 1e-6.

    Returns
    -------
    (6, n) ndarray
        Rows ``(ω; v)``: angular velocity and velocity of the frame's origin per unit joint rate,
        base-frame axes (Pinocchio's LOCAL_WORLD_ALIGNED).

    Raises
    ------
    InputError
        When ``fk`` is neither callable nor a robot, or ``q``/``h`` are invalid.

    Examples
    --------
    It agrees with the analytic geometric Jacobian of the planar two-link arm:

    >>> robot = rk.load("twolink")
    >>> bool(np.allclose(numerical_jacobian(robot, [0.3, 0.5]), geometric_jacobian(robot, [0.3, 0.5]),
    ...                  atol=1e-8))
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


_Fn = TypeVar("_Fn", bound=Callable[..., Any])


def _is_robot(x: object) -> bool:
    """A robot (anything with ``n`` and ``jacobian``, a :class:`~robokit.description.protocol.RobotLike`)."""
    return not isinstance(x, (np.ndarray, list, tuple, str, bytes)) and hasattr(x, "jacobian") and hasattr(x, "n")


def _robot_jacobian(robot: Any, args: tuple, kwargs: dict, frame: str | None, name: str) -> tuple[np.ndarray, Any, tuple]:
    """(J, q, the other positional arguments) of a call ``name(robot, q, ...)``: J the robot's
    geometric Jacobian at q (base axes, rows (ω; v), v of the frame origin)."""
    if args:
        q, args = args[0], args[1:]
    elif "q" in kwargs:
        q = kwargs.pop("q")
    else:
        raise InputError(f"q: {name}(robot, q, ...) takes the joint values after the robot")
    return robot.jacobian(q, frame, reference="local_world_aligned"), q, args


def _jacobian_or_robot(fn: _Fn) -> _Fn:
    """Let ``fn(J, ...)`` also be called ``fn(robot, q, ..., frame=None)``: J is then the robot's
    geometric Jacobian at q, ``robot.jacobian(q, frame, reference="local_world_aligned")``."""
    @functools.wraps(fn)
    def _call(J: Any, *args: Any, frame: str | None = None, **kwargs: Any) -> Any:
        if _is_robot(J):
            J, _, args = _robot_jacobian(J, args, kwargs, frame, fn.__name__)
        elif frame is not None:
            raise InputError(f"frame: {fn.__name__} takes frame= with a robot (as {fn.__name__}(robot, q, frame=...)), "
                             "not with a Jacobian")
        return fn(J, *args, **kwargs)

    return cast(_Fn, _call)


def euler_rate_matrix(angles: ArrayLike, seq: str = "ZYX", tol: float = 1e-9, extrinsic: bool = False) -> np.ndarray:
    """The matrix E(φ) with ``ω = E(φ) φ̇``: Euler-angle rates to the angular velocity in base axes.

    With the axes ``e₁, e₂, e₃`` of the sequence (differentiate R and read ω off
    ``Ṙ Rᵀ = S(ω)``, Lecture 6):

    * intrinsic, ``R = R₁(a) R₂(b) R₃(c)``: ``E = [e₁, R₁(a) e₂, R₁(a) R₂(b) e₃]``;
    * extrinsic, ``R = R₃(c) R₂(b) R₁(a)``: ``E = [R₃(c) R₂(b) e₁, R₃(c) e₂, e₃]``.

    ZYX gives ``[[0, −sα, cα cβ], [0, cα, sα cβ], [1, 0, −sβ]]`` (singular at cos β = 0); ZYZ
    ``[[0, −sφ, cφ sθ], [0, cφ, sφ sθ], [1, 0, cθ]]`` (the Lecture 6 homework's B(Γ), singular at
    sin θ = 0); the lecture's roll–pitch–yaw ``R = Rx(θr) Ry(θp) Rz(θy)`` is intrinsic "XYZ" with
    ``φ = (θr, θp, θy)`` and ``B(Γ) = [[1, 0, sθp], [0, cθr, −cθp sθr], [0, sθr, cθp cθr]]``.
    E is singular when the first and third axes line up (Tait–Bryan b = ±π/2, proper Euler
    b ∈ {0, π}).

    Parameters
    ----------
    angles : (3,) array_like
        ``φ = (a, b, c)`` in rad, in the order of ``seq``.
    seq : str, optional
        Any of the 12 sequences (``robokit.EULER_SEQUENCES``: "XYZ", "ZYX", "ZYZ", …); default "ZYX".
    tol : float, optional
        Unused here; kept for the signature shared with :func:`analytical_jacobian`.
    extrinsic : bool, optional
        Fixed (extrinsic) axes instead of moving (intrinsic) axes, as
        :func:`robokit.matrix_from_euler`; default False.

    Returns
    -------
    (3, 3) ndarray
        E(φ); column k is the base-frame axis of the k-th angle's rotation.

    Examples
    --------
    ZYX at φ = 0: the yaw rate turns about z, the pitch rate about y, the roll rate about x:

    >>> euler_rate_matrix([0, 0, 0], "ZYX")
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


def analytical_jacobian(J: ArrayLike | RobotLike, angles: ArrayLike, seq: str = "ZYX", tol: float = 1e-9,
                        extrinsic: bool = False, *, frame: str | None = None) -> np.ndarray:
    """Analytical Jacobian ``J_a = blockdiag(E(φ)⁻¹, I) J`` (Lecture 6): rows (φ̇; ṗ).

    (The lecture writes the same with the rows in the order (v; ω): ``J_a = blockdiag(I, B(Γ)⁻¹) J``;
    robokit keeps angular rows first.) It does not exist where E(φ) is singular (β = ±π/2 for ZYX,
    θ = 0 or π for ZYZ) even when the arm is far from any singularity.

    Parameters
    ----------
    J : (6, n) array_like, or a robot
        Geometric Jacobian ``(ω; v)`` in the base frame (:func:`geometric_jacobian`) — or a robot
        followed by its joint values: ``analytical_jacobian(robot, q, seq)`` takes the robot's
        geometric Jacobian at q and the Euler angles of its tool (``frame``) orientation there.
    angles : (3,) array_like
        The current Euler angles (rad) of the tool orientation in the sequence ``seq`` (with a
        robot: its joint values q, rad / m).
    seq : str, optional
        Any of the 12 Euler sequences; default "ZYX" (see :func:`euler_rate_matrix`).
    tol : float, optional
        Threshold on ``|det E|`` below which the angles are a representation singularity.
    extrinsic : bool, optional
        Fixed axes instead of moving axes; default False.
    frame : str, optional
        With a robot: the frame (default its tip).

    Returns
    -------
    (6, n) ndarray
        Rows ``(φ̇; ṗ)``: Euler-angle rates (rad/s) and tool-origin velocity (m/s, base axes) per
        unit joint rate.

    Raises
    ------
    InputError
        ``"representation singularity"`` where ``|det E(φ)| < tol``, or on bad shapes.

    Examples
    --------
    For ZYX at φ = 0 the Euler rates are (ω_z, ω_y, ω_x): the planar arm turns only in yaw:

    >>> J = geometric_jacobian(rk.load("twolink"), [0, np.pi / 2])
    >>> analytical_jacobian(J, [0, 0, 0], "ZYX")[:3]
    array([[1., 1.],
           [0., 0.],
           [0., 0.]])

    The same from the robot and its joint values (the tool's yaw there is π/2):

    >>> analytical_jacobian(rk.load("twolink"), [0, np.pi / 2], "ZYX")[:3] + 0.0   # (+ 0.0: no −0)
    array([[1., 1.],
           [0., 0.],
           [0., 0.]])
    """
    if _is_robot(J):
        robot = cast("RobotLike", J)
        J = robot.jacobian(angles, frame, reference="local_world_aligned")
        from robokit.spatial.euler import euler_from_matrix

        angles = cast(np.ndarray, euler_from_matrix(robot.frame_pose(angles, frame)[:3, :3], seq, extrinsic=extrinsic))
    elif frame is not None:
        raise InputError("frame: analytical_jacobian takes frame= with a robot (analytical_jacobian(robot, q, ...)), "
                         "not with a Jacobian")
    J = as_matrix(J, "J", 6, None)
    E = euler_rate_matrix(angles, seq, extrinsic=extrinsic)
    d = float(np.linalg.det(E))
    if abs(d) < tol:
        raise InputError(f"angles: representation singularity of {seq} Euler angles (det E = {d:.2e}); "
                         "E(φ) has no inverse here")
    return np.vstack([np.linalg.solve(E, J[:3]), J[3:]])


def geometric_jacobian(robot: Robot, q: ArrayLike) -> np.ndarray:
    """Geometric Jacobian of the robot's tool point, base axes, rows ``(ω; v)`` (Lecture 6).

    ``ω = J_ω q̇`` is the tool's angular velocity and ``v = J_v q̇`` the velocity of the tool frame's
    origin, both in base-frame axes (the lecture stacks them as (v; ω); robokit keeps angular rows
    first). Built from the product-of-exponentials space Jacobian ``J_s``: column i is
    ``(ω_i, v_i + ω_i × p)`` with p the tool position, i.e. ``(zᵢ, zᵢ × (p − oᵢ))`` for a revolute
    joint and ``(0, zᵢ)`` for a prismatic one.

    Parameters
    ----------
    robot : Robot
        A :class:`robokit.Robot` (its ``poe`` parameters; the tip is the tool).
    q : (n,) array_like
        Joint values (rad / m).

    Returns
    -------
    (6, n) ndarray
        Rows ``(ω; v)`` in base axes, rad/s and m/s per unit joint rate (Pinocchio's
        LOCAL_WORLD_ALIGNED Jacobian of the tip frame).

    Examples
    --------
    The planar two-link arm (l₁ = 1, l₂ = 0.8) at q = (0, π/2): the v rows x, y are the lecture's
    ``J_v = [[−l₁s₁ − l₂s₁₂, −l₂s₁₂], [l₁c₁ + l₂c₁₂, l₂c₁₂]]``:

    >>> geometric_jacobian(rk.load("twolink"), [0, np.pi / 2])[3:5].round(4)
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
    """The 6×6 map of twists from frame b's axes to frame a's: ``V_a = Ad_{T_ab} V_b`` (Lecture 6).

    For two frames on the same body, or a frame on another body rigidly fixed to it.

    Parameters
    ----------
    T_a_b : (4, 4) array_like
        Pose of frame b in frame a (metres).

    Returns
    -------
    (6, 6) ndarray
        ``Ad_{T_ab} = [[R, 0], [[p] R, R]]``, acting on twists ``(ω; v)``.

    Examples
    --------
    A spin of 1 rad/s about the z axis of a frame b placed at x = 1 m: seen from a, the point at
    a's origin moves at 1 m/s along −y:

    >>> T_a_b = np.array([[1., 0, 0, 1], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]])
    >>> twist_transform(T_a_b) @ [0, 0, 1, 0, 0, 0]
    array([ 0.,  0.,  1.,  0., -1.,  0.])
    """
    return lie.adjoint(check_transform(T_a_b, "T_a_b"))


def wrench_transform(T_a_b: ArrayLike) -> np.ndarray:
    """The 6×6 map of wrenches from frame b's axes to frame a's: ``F_a = Ad_{T_ba}ᵀ F_b``.

    The same physical force, its moment taken about a's origin (Lecture 6).

    Parameters
    ----------
    T_a_b : (4, 4) array_like
        As for :func:`twist_transform`.

    Returns
    -------
    (6, 6) ndarray
        ``Ad_{T_ab⁻¹}ᵀ``, acting on wrenches ``(m; f)`` (N·m, N).

    Examples
    --------
    1 N along y applied at b's origin, 1 m along x from a's origin, has a moment of 1 N·m about z
    at a:

    >>> T_a_b = np.array([[1., 0, 0, 1], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]])
    >>> wrench_transform(T_a_b) @ [0, 0, 0, 0, 1, 0]
    array([0., 0., 1., 0., 1., 0.])
    """
    return lie.adjoint(lie.inv(check_transform(T_a_b, "T_a_b"))).T


@_jacobian_or_robot
def jacobian_in_frame(J: ArrayLike, R: ArrayLike) -> np.ndarray:
    """Re-express a geometric Jacobian ``(ω; v)`` in rotated axes: ``blockdiag(R, R) J``.

    With R = R_tool_base (= R_base_toolᵀ) a base-frame Jacobian becomes the tool-frame one, and vice
    versa with R_base_tool; the point whose velocity v is stays the same, only the axes rotate.

    Parameters
    ----------
    J : (6, n) array_like, or a robot
        Jacobian with rows ``(ω; v)``; or a robot followed by q (see the module docstring).
    R : (3, 3) array_like
        Rotation from J's axes to the new axes (``R_new_old``).

    Returns
    -------
    (6, n) ndarray
        The same Jacobian in the new axes.

    Examples
    --------
    The planar two-link arm at q = (0, π/2): its tool is turned by 90° about z, so in tool axes joint
    2 moves the tip along the tool's y axis and joint 1 along (1, 0.8):

    >>> robot = rk.load("twolink")
    >>> J = geometric_jacobian(robot, [0, np.pi / 2])
    >>> R_tool_base = robot.frame_pose([0, np.pi / 2])[:3, :3].T
    >>> bool(np.allclose(jacobian_in_frame(J, R_tool_base)[3:5], [[1, 0], [0.8, 0.8]]))
    True
    >>> bool(np.allclose(jacobian_in_frame(robot, [0, np.pi / 2], R_tool_base), jacobian_in_frame(J, R_tool_base)))
    True
    """
    J = as_matrix(J, "J", 6, None)
    R = as_matrix(R, "R", 3, 3)
    return np.vstack([R @ J[:3], R @ J[3:]])


def _jacobian(J: ArrayLike, part: str = "full") -> np.ndarray:
    """``J`` as a 2-D float array, or an error saying what a Jacobian is here and what came instead."""
    arr = as_array(J, "J")
    if arr.ndim != 2:
        want = ("a 6-row Jacobian (ω; v), shape (6, n)" if part in ("translation", "rotation") else
                "a Jacobian, a 2-D array of shape (m, n) (a row per task coordinate, a column per joint)")
        got = f"shape {arr.shape}" if arr.ndim else f"the number {float(arr)!r}"
        hint = f"; one joint's column is a ({arr.shape[0]}, 1) Jacobian" if arr.ndim == 1 else ""
        raise InputError(f"J: expected {want}, got {got}{hint}")
    return arr


def _rows(J: ArrayLike, part: str) -> np.ndarray:
    J = _jacobian(J, part)
    if part == "full":
        return J
    if J.shape[0] != 6:
        raise InputError(f"part: {part!r} needs a 6-row Jacobian (ω; v), got shape {J.shape}")
    if part == "translation":
        return J[3:]
    if part == "rotation":
        return J[:3]
    raise InputError(f"part: expected 'full', 'translation' or 'rotation', got {part!r}")


@_jacobian_or_robot
def manipulability(J: ArrayLike, kind: str = "yoshikawa", part: str = "full") -> float:
    """A manipulability measure of a Jacobian, or of its translation or rotation rows (Lecture 6).

    Parameters
    ----------
    J : (m, n) array_like, or a robot
        A Jacobian; a 6-row one ``(ω; v)`` when ``part`` is not "full". Or a robot followed by q (see the module docstring).
    kind : {"yoshikawa", "condition", "inverse_condition", "min_singular"}, optional
        ``"yoshikawa"`` (default) — ``w = √det(J Jᵀ)``, the product of the singular values (0 at a
        singularity); ``"condition"`` — ``σ_max / σ_min`` (∞ at a singularity);
        ``"inverse_condition"`` — ``σ_min / σ_max`` (the ratio of the shortest to the longest
        ellipsoid axis); ``"min_singular"`` — ``σ_min``.
    part : {"full", "translation", "rotation"}, optional
        Which rows: all (default), the v rows or the ω rows of a 6-row Jacobian.

    Returns
    -------
    float
        The measure (units of the rows chosen; with fewer joints than rows: 0, or ∞ for
        "condition").

    Raises
    ------
    InputError
        On an unknown ``kind``/``part``, or a ``part`` other than "full" of a non-6-row Jacobian.

    Examples
    --------
    For the planar two-link arm's 2×2 translational Jacobian ``w = |l₁ l₂ sin θ₂|``, here
    1 × 0.8 × sin(π/2):

    >>> J = geometric_jacobian(rk.load("twolink"), [0, np.pi / 2])
    >>> round(manipulability(J[3:5]), 4)
    0.8

    From a robot and its joint values (here the Panda's ready pose, all six rows):

    >>> panda = rk.load("panda")
    >>> round(manipulability(panda, panda.configurations["ready"]), 4)
    0.0802
    >>> round(manipulability(panda, panda.configurations["ready"], kind="condition"), 2)
    8.18
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


@_jacobian_or_robot
def velocity_ellipsoid(J: ArrayLike, part: str = "translation") -> tuple[np.ndarray, np.ndarray]:
    """Axes and radii of the velocity ellipsoid ``{J q̇ : ‖q̇‖ ≤ 1}`` of the chosen rows (Lecture 6).

    Parameters
    ----------
    J : (m, n) array_like, or a robot
        A Jacobian; a 6-row one ``(ω; v)`` unless ``part="full"``. Or a robot followed by q (see the module docstring).
    part : {"translation", "rotation", "full"}, optional
        Which rows (default the translation rows v).

    Returns
    -------
    radii : (k,) ndarray
        The singular values, descending (m/s or rad/s per unit joint-rate norm); k = 3 for
        "translation"/"rotation", m for "full". Zero along lost directions.
    axes : (k, k) ndarray
        The left singular vectors as columns: the ellipsoid's axes in J's (base) axes.

    Examples
    --------
    The planar arm's 2×2 J_v: the radii multiply to the manipulability ``l₁ l₂ |sin θ₂|``:

    >>> J = geometric_jacobian(rk.load("twolink"), [0, np.pi / 2])
    >>> radii, axes = velocity_ellipsoid(J[3:5], part="full")
    >>> radii.round(4), round(float(np.prod(radii)), 4)
    (array([1.3972, 0.5726]), 0.8)
    >>> velocity_ellipsoid(rk.load("twolink"), [0, np.pi / 2])[0].round(4)   # its (v_x, v_y, v_z) rows
    array([1.3972, 0.5726, 0.    ])
    """
    A = _rows(J, part)
    U, s, _ = np.linalg.svd(A)
    radii = np.zeros(A.shape[0])
    radii[: len(s)] = s
    return radii, U


@_jacobian_or_robot
def force_ellipsoid(J: ArrayLike, part: str = "translation") -> tuple[np.ndarray, np.ndarray]:
    """Axes and radii of the force ellipsoid ``{F : ‖Jᵀ F‖ ≤ 1}`` of the chosen rows (Lecture 6).

    The wrenches the tool can exert (or resist) with unit joint-torque norm: by the duality
    ``τ = Jᵀ F`` its axes are the velocity ellipsoid's and its radii the inverse singular values
    ``1/σᵢ`` — long where the velocity ellipsoid is short. Along a lost direction (σ = 0) the arm
    resists any force without torque: the radius is ∞.

    Parameters
    ----------
    J : (m, n) array_like, or a robot
        A Jacobian; a 6-row one ``(ω; v)`` unless ``part="full"``. Or a robot followed by q (see the module docstring).
    part : {"translation", "rotation", "full"}, optional
        Which rows (default the translation rows v: forces; "rotation": moments).

    Returns
    -------
    radii : (k,) ndarray
        ``1/σᵢ`` in the order of :func:`velocity_ellipsoid`'s axes (ascending), N (or N·m) per
        unit joint-torque norm; ∞ along lost directions.
    axes : (k, k) ndarray
        The axes as columns (the left singular vectors of J's rows), in J's (base) axes.

    Examples
    --------
    The planar arm at q = (0, π/2): radii 1/1.3972 and 1/0.5726, and ∞ along z (a planar arm
    holds any vertical force without torque):

    >>> radii, axes = force_ellipsoid(rk.load("twolink"), [0, np.pi / 2])
    >>> radii.round(4)
    array([0.7157, 1.7465,    inf])
    """
    radii, axes = velocity_ellipsoid(J, part)
    with np.errstate(divide="ignore"):
        return np.where(radii > 0, 1.0 / np.where(radii > 0, radii, 1.0), np.inf), axes


_NAMES = ("rotation about x", "rotation about y", "rotation about z",
          "translation along x", "translation along y", "translation along z")


@dataclass
class SingularityReport:
    """The result of :func:`singularity`.

    Attributes
    ----------
    rank : int
        Number of singular values above the tolerance.
    sigma_min : float
        The smallest singular value (0 when there are fewer columns than rows).
    singular : bool
        ``sigma_min < tol``.
    lost_direction : (m,) ndarray
        Unit left singular vector of ``sigma_min``: the twist ``(ω; v)`` (for a 6-row J) the arm
        cannot produce, signed so that its largest component is positive.
    description : str
        Its dominant component in words, e.g. ``"translation along x (0.98)"``.
    """

    rank: int
    sigma_min: float
    singular: bool
    lost_direction: np.ndarray
    description: str


@_jacobian_or_robot
def singularity(J: ArrayLike, tol: float = 1e-9) -> SingularityReport:
    """Rank test of a Jacobian and the Cartesian direction it cannot produce (Lecture 6).

    The lost direction is the left singular vector of the smallest singular value — the twist
    ``(ω; v)`` the arm cannot move along — described by its dominant component.

    Parameters
    ----------
    J : (m, n) array_like, or a robot
        A Jacobian, usually 6×n with rows ``(ω; v)`` (other row counts: directions by index). Or a robot followed by q (see the module docstring).
    tol : float, optional
        Singular values below this count as zero; default 1e-9.

    Returns
    -------
    SingularityReport
        Rank, smallest singular value, whether singular, the lost direction and its description.

    Examples
    --------
    The PUMA 560 at q = 0 has its wrist aligned (θ₅ = 0: the axes of joints 4 and 6 coincide) and
    loses one rotation; bending the wrist restores full rank:

    >>> puma = rk.load("puma560")
    >>> report = singularity(puma.jacobian(np.zeros(6), reference="local_world_aligned"))
    >>> report.rank, report.singular, report.description
    (5, True, 'rotation about x (1.00)')
    >>> singularity(puma.jacobian([0, 0.5, -0.3, 0, 0.7, 0], reference="local_world_aligned")).rank
    6
    >>> singularity(puma, np.zeros(6)).description   # the same from the robot and q
    'rotation about x (1.00)'
    """
    A = _jacobian(J)
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


@_jacobian_or_robot
def resolved_rate(J: ArrayLike, V: ArrayLike, method: str = "pinv", damping: float = 0.05, adaptive: bool = False,
                  epsilon: float = 0.05, z: ArrayLike | None = None, rcond: float = 1e-12) -> np.ndarray:
    """Joint velocities for a desired Cartesian twist (Lecture 6): ``q̇ = J⁺V + (I − J⁺J) z``.

    Parameters
    ----------
    J : (m, n) array_like, or a robot
        Jacobian (m ≤ 6 rows; use the rows that matter, e.g. the 2 planar rows of the 2-link arm).
        Or a robot followed by q, then V (6,) (see the module docstring).
    V : (m,) array_like
        Desired twist in J's rows and axes (rad/s, m/s).
    method : {"pinv", "dls", "damped_inverse"}, optional
        ``"pinv"`` (default) — Moore–Penrose; ``"dls"`` — damped least squares
        ``q̇ = Jᵀ(JJᵀ + λ²I)⁻¹V``; ``"damped_inverse"`` — the lecture's ``q̇ = (J + pI)⁻¹ V`` for a
        square J, which leaves an error ``J q̇ − V = −p q̇`` that accumulates in the end-effector
        position, as the lecture warns.
    damping : float, optional
        λ (or λ_max when adaptive) for "dls", p for "damped_inverse"; default 0.05.
    adaptive : bool, optional
        For "dls": ``λ² = λ_max² (1 − (σ_min/ε)²)`` when σ_min < ε, else 0 (undamped away from
        singularities).
    epsilon : float, optional
        ε of the adaptive damping; default 0.05.
    z : (n,) array_like, optional
        Joint velocity projected into the null space (redundant arms: secondary tasks such as
        :func:`joint_limit_gradient`); it leaves the task twist unchanged.
    rcond : float, optional
        Cut-off of the pseudo-inverse's small singular values.

    Returns
    -------
    (n,) ndarray
        q̇ (rad/s, m/s).

    Raises
    ------
    InputError
        On an unknown method, a non-square J for "damped_inverse", or bad shapes.

    Examples
    --------
    To move the tip of the planar arm at q = (0, π/2) (tip at (1, 0.8)) along +y at 1 m/s:

    >>> J = geometric_jacobian(rk.load("twolink"), [0, np.pi / 2])
    >>> dq = resolved_rate(J[3:5], [0, 1])
    >>> dq.round(4), (J[3:5] @ dq).round(4)
    (array([ 1., -1.]), array([0., 1.]))
    >>> resolved_rate(rk.load("twolink"), [0, np.pi / 2], [0, 0, 0, 0, 1, 0]).round(4)   # (robot, q, V)
    array([ 1., -1.])
    """
    J = _jacobian(J)
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
    """``−∇H`` for ``H = ½ Σ ((qᵢ − q̄ᵢ)/(q_maxᵢ − q_minᵢ))²``: a null-space velocity toward mid-range.

    Pass it as ``z`` to :func:`resolved_rate`; joints with infinite or empty ranges are left alone.

    Parameters
    ----------
    q : (n,) array_like
        Joint values (rad / m).
    qlim : (n, 2) array_like
        Lower and upper limit of each joint (may be ±inf).

    Returns
    -------
    (n,) ndarray
        ``−(qᵢ − q̄ᵢ) / (q_maxᵢ − q_minᵢ)²`` (0 for unlimited joints), q̄ the middle of the range.

    Examples
    --------
    A joint at 1 in [−2, 2] is pushed back by 1/4²; one at 0.5 in [−1, 1] by 0.5/2²:

    >>> joint_limit_gradient([1.0, 0.5], [[-2, 2], [-1, 1]])
    array([-0.0625, -0.125 ])
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
    """:func:`manipulability` of the robot's base-frame geometric Jacobian at q, in one call.

    Parameters
    ----------
    robot, q : RobotLike, (n,) array_like
        The robot and its joint values (rad / m) (see the module docstring).
    kind, part : str, optional
        As :func:`manipulability`.
    frame : str, optional
        See the module docstring (default the robot's tip).

    Returns
    -------
    float
        ``manipulability(J, kind, part)`` of that Jacobian J at q.

    Examples
    --------
    The planar arm's translation rows are 3×2 (two joints cannot span x, y and z), so its
    "translation" measure is 0 however the arm stands:

    >>> robot = rk.load("twolink")
    >>> manipulability_at(robot, [0, np.pi / 2], part="translation")
    0.0
    """
    return manipulability(robot.jacobian(q, frame, reference="local_world_aligned"), kind, part)


def velocity_ellipsoid_at(robot: RobotLike, q: ArrayLike, part: str = "translation",
                          frame: str | None = None) -> tuple[np.ndarray, np.ndarray]:
    """:func:`velocity_ellipsoid` of the robot's base-frame geometric Jacobian at q.

    Parameters
    ----------
    robot, q : RobotLike, (n,) array_like
        The robot and its joint values (rad / m) (see the module docstring).
    part : {"translation", "rotation", "full"}, optional
        Which rows (default translation).
    frame : str, optional
        See the module docstring (default the robot's tip).

    Returns
    -------
    radii : ndarray
        Semi-axes (descending), base-frame units of the rows.
    axes : ndarray
        The axes as columns, base-frame axes.

    Examples
    --------
    The planar arm's ellipsoid is flat in z (a zero third radius):

    >>> radii, axes = velocity_ellipsoid_at(rk.load("twolink"), [0, np.pi / 2])
    >>> radii.round(4)
    array([1.3972, 0.5726, 0.    ])
    """
    return velocity_ellipsoid(robot.jacobian(q, frame, reference="local_world_aligned"), part)


def resolved_rate_at(robot: RobotLike, q: ArrayLike, V: ArrayLike, frame: str | None = None,
                     **kwargs: Any) -> np.ndarray:
    """Joint velocities of ``robot`` at q for a desired twist, via :func:`resolved_rate`.

    Parameters
    ----------
    robot, q : RobotLike, (n,) array_like
        The robot and its joint values (rad / m) (see the module docstring).
    V : (6,) array_like
        Desired twist ``(ω; v)`` of the frame origin, base axes (rad/s, m/s).
    frame : str, optional
        See the module docstring (default the robot's tip).
    **kwargs
        ``method``, ``damping``, ``adaptive``, ``epsilon``, ``z``, ``rcond`` as :func:`resolved_rate`.

    Returns
    -------
    (n,) ndarray
        q̇ (rad/s, m/s), the least-squares solution when V is not reachable exactly.

    Examples
    --------
    >>> resolved_rate_at(rk.load("twolink"), [0, np.pi / 2], [0, 0, 0, 0, 1, 0]).round(4)
    array([ 1., -1.])
    """
    return resolved_rate(robot.jacobian(q, frame, reference="local_world_aligned"), V, **kwargs)


__all__ += ["manipulability_at", "velocity_ellipsoid_at", "resolved_rate_at", "SingularityReport"]

# Former names (before the X_from_Y rule): they warn and call the new function.
jacobian_to_frame = deprecated_alias(jacobian_in_frame, "jacobian_to_frame")
