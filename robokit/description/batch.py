r"""A Robot's answers for many configurations at once: q of shape (N, n) in, stacked results out.

Which engine answers each (measured in ``benchmarks/kernels.py``; see the docs' performance notes):

* ``frame_pose`` (tip), ``jacobian`` (tip), ``crba`` — robokit's compiled course kernels
  (:mod:`robokit.kernels`: the PoE product of exponentials, the space Jacobian, the composite-
  rigid-body recursion) over the Robot's PoE parameters, parallel over configurations. Pinocchio
  has no batched FK, Jacobian or CRBA in Python, and a Python loop over it is slower.
* ``rnea``, ``aba`` — Pinocchio's ``rneaInParallel``/``abaInParallel`` over a ``ModelPool`` with
  ``threads`` OpenMP threads (about 1 µs per UR5 configuration on one thread).

Every result equals the per-configuration method to 1e-12 (tests/description/test_batch.py).

Parameters shared by this module's functions:

* ``robot`` (Robot) — the robot; each function names the parameters of it that it uses.
* ``Q`` (array_like, shape (N, n)) — joint values, one configuration per row (rad or m).
* ``frame`` (str or None) — must be None or the robot's tip: batched calls answer for the tip only.
* ``threads`` (int) — OpenMP threads of Pinocchio's ``rneaInParallel``/``abaInParallel``
  (default 1; must be positive).
"""
from __future__ import annotations

from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import ArrayLike
from robokit._arrays import as_joints, kernel_array
from robokit.frames import Frame, reference_or_default
from robokit.errors import InputError

if TYPE_CHECKING:
    from robokit.description.robot import Robot

__all__ = ["batch_frame_pose", "batch_jacobian", "batch_crba", "batch_rnea", "batch_aba"]


def _rows(robot: Robot, Q: ArrayLike, name: str) -> np.ndarray:
    rows = as_joints(Q, robot.n, name, robot.name, batch=True)
    if name == "q":  # rows of a path or a log: continuous joints may wind (robokit._units)
        robot.check_radians(rows, name, state=True)
    return rows


def _tip_only(robot: Robot, frame: str | None) -> None:
    if frame is not None and frame != robot.tip:
        raise InputError(f"frame: batched calls answer for the tip {robot.tip!r} only, got {frame!r}")


def batch_frame_pose(robot: Robot, Q: ArrayLike, frame: str | None = None) -> np.ndarray:
    """Tip poses for many configurations (compiled PoE kernel ``T = e^{[S₁]q₁} ⋯ e^{[Sₙ]qₙ} M``).

    Parameters
    ----------
    robot, Q, frame
        As in the module docstring (the robot's PoE ``M`` and ``Slist`` are used).

    Returns
    -------
    numpy.ndarray, shape (N, 4, 4)
        Tip pose in the base frame for each row of ``Q`` (m), as :meth:`Robot.frame_pose`.

    Examples
    --------
    The planar arm (links 1 m and 0.8 m) stretched out, then turned 90° at the shoulder:

    >>> T = batch_frame_pose(rk.load("twolink"), [[0.0, 0.0], [np.pi / 2, 0.0]])
    >>> T[:, :2, 3].round(4).tolist()
    [[1.8, 0.0], [0.0, 1.8]]
    """
    from robokit.kernels.poe import fkin_space_batch

    _tip_only(robot, frame)
    Q = _rows(robot, Q, "q")
    p = robot.poe  # read-only views; kernel_array gives the kernel their writeable arrays (no copy)
    return fkin_space_batch(kernel_array(p.M), kernel_array(p.Slist), Q)


def batch_jacobian(robot: Robot, Q: ArrayLike, frame: str | None = None,
                   reference: Frame | str | None = None) -> np.ndarray:
    """Tip Jacobians for many configurations (compiled PoE kernel), angular rows first.

    Parameters
    ----------
    robot, Q, frame
        As in the module docstring (the robot's PoE ``Slist``, and ``M`` unless ``reference`` is
        ``Frame.WORLD``, are used).
    reference : Frame or str, optional
        :class:`robokit.Frame` (the *Conventions* page): ``Frame.WORLD``: the space Jacobian ``J_s``
        (twist of the tip in the base frame); ``Frame.LOCAL``: the body Jacobian ``Ad_{T⁻¹} J_s``
        (tip axes); ``Frame.LOCAL_WORLD_ALIGNED``: ``[[I, 0], [−[p], I]] J_s`` — ω and the velocity
        of the tip origin in base axes (the course's geometric Jacobian, robokit's one default).
        Omitted: LOCAL_WORLD_ALIGNED (before 0.3 this function defaulted to WORLD).

    Returns
    -------
    numpy.ndarray, shape (N, 6, n)
        One Jacobian per row of ``Q``: rows ``(ω; v)`` (rad/s and m/s per unit joint rate).

    Examples
    --------
    At q = 0 the tip origin (1.8, 0, 0) moves along +y at 1.8 m/s per rad/s of joint 1:

    >>> J = batch_jacobian(rk.load("twolink"), [[0.0, 0.0]], reference="local_world_aligned")
    >>> J[0, 3:5].round(4).tolist()
    [[0.0, 0.0], [1.8, 0.8]]
    """
    from robokit.kernels.poe import fkin_space_batch, jacobian_space_batch
    from robokit.spatial import lie

    _tip_only(robot, frame)
    reference = reference_or_default(reference, "batch_jacobian")
    Q = _rows(robot, Q, "q")
    p = robot.poe
    Slist = kernel_array(p.Slist)
    Js = jacobian_space_batch(Slist, Q)
    if reference == "world":
        return Js
    T = fkin_space_batch(kernel_array(p.M), Slist, Q)
    if reference == "local":
        return lie.adjoint(lie.inv(T)) @ Js
    out = Js.copy()  # v of the tip origin: v_s − p × ω = v_s + [ω] p ... i.e. v_o = v_s + ω × p
    out[:, 3:, :] = Js[:, 3:, :] + np.cross(Js[:, :3, :], T[:, :3, 3][:, :, None], axis=1)
    return out


def batch_crba(robot: Robot, Q: ArrayLike) -> np.ndarray:
    """Joint-space mass matrices for many configurations (compiled composite-rigid-body kernel).

    The motors' armature of the Pinocchio model, if any, is added on the diagonal.

    Parameters
    ----------
    robot, Q
        As in the module docstring (the robot's PoE ``Mlist``/``Glist``/``Slist`` and its Pinocchio
        model's armature are used).

    Returns
    -------
    numpy.ndarray, shape (N, n, n)
        Symmetric positive-definite ``M(q)`` per row (kg·m² for revolute joints), as
        :meth:`Robot.crba`.

    Examples
    --------
    Point masses 2 kg at (1, 0) and 1.5 kg at (1.8, 0): ``M₂₂ = m₂ l₂² = 0.96``,
    ``M₁₁ = m₁ l₁² + m₂ (l₁ + l₂)² = 6.86``:

    >>> M = batch_crba(rk.load("twolink"), [[0.0, 0.0]])
    >>> M[0].round(4).tolist()
    [[6.86, 2.16], [2.16, 0.96]]
    """
    from robokit.kernels.dynamics import mass_matrix_batch

    Q = _rows(robot, Q, "q")
    p = robot.poe
    M = mass_matrix_batch(Q, kernel_array(p.Mlist), kernel_array(p.Glist), kernel_array(p.Slist))
    arm = np.asarray(robot.model.armature, dtype=float)[: robot.n]
    if np.any(arm):
        M = M + np.diag(arm)
    return M


def _pool(robot: Robot, threads: int) -> tuple[Any, int]:
    threads = int(threads)
    if threads < 1:
        raise InputError(f"threads: expected a positive integer, got {threads}")
    import pinocchio as pin

    return robot.derived(("model_pool", threads), lambda: pin.ModelPool(robot.model, threads)), threads


def _q_pin_columns(robot: Robot, Q: np.ndarray) -> np.ndarray:
    if robot.model.nq == robot.n:
        return np.asfortranarray(Q.T)
    return np.asfortranarray(np.stack([robot.q_pin(q) for q in Q], axis=1))


def _in_parallel(robot: Robot, algorithm: str, Q: ArrayLike, dQ: ArrayLike, X: ArrayLike, x_name: str,
                 threads: int) -> np.ndarray:
    """Pinocchio's ``algorithm`` (``rneaInParallel`` or ``abaInParallel``) on rows of (q, q̇, x),
    x = q̈ or τ named ``x_name`` in messages: the rows checked, then one (N, n) result."""
    Q, dQ, X = _rows(robot, Q, "q"), _rows(robot, dQ, "dq"), _rows(robot, X, x_name)
    if not (Q.shape == dQ.shape == X.shape):
        raise InputError(f"q, dq, {x_name}: expected equal shapes, got {Q.shape}, {dQ.shape}, {X.shape}")
    pool, threads = _pool(robot, threads)
    out = getattr(robot._pin, algorithm)(threads, pool, _q_pin_columns(robot, Q), np.asfortranarray(dQ.T),
                                         np.asfortranarray(X.T))
    return np.ascontiguousarray(np.asarray(out).reshape(robot.n, -1).T)  # N = 1 comes back as (n,)


def batch_rnea(robot: Robot, Q: ArrayLike, dQ: ArrayLike, ddQ: ArrayLike, threads: int = 1) -> np.ndarray:
    """Inverse dynamics for many configurations: Pinocchio's ``rneaInParallel`` on ``threads`` threads.

    Parameters
    ----------
    robot : Robot
        As in the module docstring (its Pinocchio model is used).
    Q, dQ, ddQ : array_like, shape (N, n)
        Rows of joint values (``Q``, module docstring), velocities (rad/s or m/s) and
        accelerations (rad/s² or m/s²).
    threads : int, optional
        As in the module docstring.

    Returns
    -------
    numpy.ndarray, shape (N, n)
        Joint torques (N·m) or forces (N), ``τ = M(q) q̈ + C(q, q̇) q̇ + g(q)``, the model's gravity.

    Examples
    --------
    At rest, stretched along x under gravity −9.81 m/s² along y: ``τ₂ = 9.81 · 1.5 · 0.8`` and
    ``τ₁ = 9.81 · (2 · 1 + 1.5 · 1.8)``:

    >>> Z = np.zeros((1, 2))
    >>> batch_rnea(rk.load("twolink"), Z, Z, Z).round(4).tolist()
    [[46.107, 11.772]]
    """
    return _in_parallel(robot, "rneaInParallel", Q, dQ, ddQ, "ddq", threads)


def batch_aba(robot: Robot, Q: ArrayLike, dQ: ArrayLike, tau: ArrayLike, threads: int = 1) -> np.ndarray:
    """Forward dynamics for many configurations: Pinocchio's ``abaInParallel`` on ``threads`` threads.

    Parameters
    ----------
    robot : Robot
        As in the module docstring (its Pinocchio model is used).
    Q, dQ, tau : array_like, shape (N, n)
        Rows of joint values (``Q``, module docstring), velocities (rad/s or m/s) and torques
        (N·m) or forces (N).
    threads : int, optional
        As in the module docstring.

    Returns
    -------
    numpy.ndarray, shape (N, n)
        Joint accelerations ``q̈ = M(q)⁻¹ (τ − C(q, q̇) q̇ − g(q))``.

    Examples
    --------
    Holding the gravity torques keeps the arm at rest:

    >>> robot = rk.load("twolink")
    >>> Z = np.zeros((1, 2))
    >>> np.allclose(batch_aba(robot, Z, Z, [[46.107, 11.772]]), 0.0)
    True
    """
    return _in_parallel(robot, "abaInParallel", Q, dQ, tau, "tau", threads)
