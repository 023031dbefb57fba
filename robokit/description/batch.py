r"""A Robot's answers for many configurations at once: q of shape (N, n) in, stacked results out.

Which engine answers each (measured in ``benchmarks/kernels.py``; see the docs' performance notes):

* ``frame_pose`` (tip), ``jacobian`` (tip), ``crba`` — robokit's compiled course kernels
  (:mod:`robokit.kernels`: the PoE product of exponentials, the space Jacobian, the composite-
  rigid-body recursion) over the Robot's PoE parameters, parallel over configurations. Pinocchio
  has no batched FK, Jacobian or CRBA in Python, and a Python loop over it is slower.
* ``rnea``, ``aba`` — Pinocchio's ``rneaInParallel``/``abaInParallel`` over a ``ModelPool`` with
  ``threads`` OpenMP threads (about 1 µs per UR5 configuration on one thread).

Every result equals the per-configuration method to 1e-12 (tests/description/test_batch.py).
"""
from __future__ import annotations

from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import ArrayLike
from robokit._arrays import as_joints, check_reference
from robokit.errors import InputError

if TYPE_CHECKING:
    from robokit.description.robot import Robot

__all__ = ["batch_frame_pose", "batch_jacobian", "batch_crba", "batch_rnea", "batch_aba"]


def _rows(robot: Robot, Q: ArrayLike, name: str) -> np.ndarray:
    return as_joints(Q, robot.n, name, robot.name, batch=True)


def _tip_only(robot: Robot, frame: str | None) -> None:
    if frame is not None and frame != robot.tip:
        raise InputError(f"frame: batched calls answer for the tip {robot.tip!r} only, got {frame!r}")


def batch_frame_pose(robot: Robot, Q: ArrayLike, frame: str | None = None) -> np.ndarray:
    """(N, 4, 4) tip poses (compiled PoE kernel)."""
    from robokit.kernels.poe import fkin_space_batch

    _tip_only(robot, frame)
    Q = _rows(robot, Q, "q")
    p = robot.poe
    return fkin_space_batch(np.ascontiguousarray(p.M), np.ascontiguousarray(p.Slist), Q)


def batch_jacobian(robot: Robot, Q: ArrayLike, frame: str | None = None, reference: str = "world") -> np.ndarray:
    """(N, 6, n) tip Jacobians, angular rows first (compiled PoE kernel): "world" = the space
    Jacobian J_s; "local" = ``Ad_{T⁻¹} J_s``; "local_world_aligned" = ``[[I, 0], [−[p], I]] J_s``."""
    from robokit.kernels.poe import fkin_space_batch, jacobian_space_batch
    from robokit.spatial import lie

    _tip_only(robot, frame)
    reference = check_reference(reference)
    Q = _rows(robot, Q, "q")
    p = robot.poe
    Slist = np.ascontiguousarray(p.Slist)
    Js = jacobian_space_batch(Slist, Q)
    if reference == "world":
        return Js
    T = fkin_space_batch(np.ascontiguousarray(p.M), Slist, Q)
    if reference == "local":
        return lie.adjoint(lie.inv(T)) @ Js
    out = Js.copy()  # v of the tip origin: v_s − p × ω = v_s + [ω] p ... i.e. v_o = v_s + ω × p
    out[:, 3:, :] = Js[:, 3:, :] + np.cross(Js[:, :3, :], T[:, :3, 3][:, :, None], axis=1)
    return out


def batch_crba(robot: Robot, Q: ArrayLike) -> np.ndarray:
    """(N, n, n) mass matrices (compiled composite-rigid-body kernel; the motors' armature of the
    Pinocchio model, if any, added on the diagonal)."""
    from robokit.kernels.dynamics import mass_matrix_batch

    Q = _rows(robot, Q, "q")
    p = robot.poe
    M = mass_matrix_batch(Q, np.ascontiguousarray(p.Mlist), np.ascontiguousarray(p.Glist),
                          np.ascontiguousarray(p.Slist))
    arm = np.asarray(robot.model.armature, dtype=float)[: robot.n]
    if np.any(arm):
        M = M + np.diag(arm)
    return M


def _pool(robot: Robot, threads: int) -> tuple[Any, int]:
    threads = int(threads)
    if threads < 1:
        raise InputError(f"threads: expected a positive integer, got {threads}")
    cache = robot.__dict__.setdefault("_pools", {})
    if threads not in cache:
        cache[threads] = robot._pin.ModelPool(robot.model, threads)
    return cache[threads], threads


def _q_pin_columns(robot: Robot, Q: np.ndarray) -> np.ndarray:
    if robot.model.nq == robot.n:
        return np.asfortranarray(Q.T)
    return np.asfortranarray(np.stack([robot.q_pin(q) for q in Q], axis=1))


def batch_rnea(robot: Robot, Q: ArrayLike, dQ: ArrayLike, ddQ: ArrayLike, threads: int = 1) -> np.ndarray:
    """(N, n) inverse dynamics, Pinocchio's ``rneaInParallel`` on ``threads`` threads."""
    Q, dQ, ddQ = _rows(robot, Q, "q"), _rows(robot, dQ, "dq"), _rows(robot, ddQ, "ddq")
    if not (Q.shape == dQ.shape == ddQ.shape):
        raise InputError(f"q, dq, ddq: expected equal shapes, got {Q.shape}, {dQ.shape}, {ddQ.shape}")
    pool, threads = _pool(robot, threads)
    tau = robot._pin.rneaInParallel(threads, pool, _q_pin_columns(robot, Q), np.asfortranarray(dQ.T),
                                    np.asfortranarray(ddQ.T))
    return np.ascontiguousarray(np.asarray(tau).T)


def batch_aba(robot: Robot, Q: ArrayLike, dQ: ArrayLike, tau: ArrayLike, threads: int = 1) -> np.ndarray:
    """(N, n) forward dynamics, Pinocchio's ``abaInParallel`` on ``threads`` threads."""
    Q, dQ, tau = _rows(robot, Q, "q"), _rows(robot, dQ, "dq"), _rows(robot, tau, "tau")
    if not (Q.shape == dQ.shape == tau.shape):
        raise InputError(f"q, dq, tau: expected equal shapes, got {Q.shape}, {dQ.shape}, {tau.shape}")
    pool, threads = _pool(robot, threads)
    ddq = robot._pin.abaInParallel(threads, pool, _q_pin_columns(robot, Q), np.asfortranarray(dQ.T),
                                   np.asfortranarray(tau.T))
    return np.ascontiguousarray(np.asarray(ddq).T)
