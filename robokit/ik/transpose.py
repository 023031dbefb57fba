r"""Inverse kinematics by the Jacobian transpose with a viscous damper at each joint (Lecture 6).

The lecture's picture: a spring pulls the end-effector toward the goal, the joints have no
motors, only viscous dampers. With the goal pose ``ξ*``, the current pose ``ξ_E⟨k⟩ = K(q⟨k⟩)`` and
the pose difference ``Δ(ξ_E, ξ*)`` expressed in the end-effector frame {E}:

    ᴱg⟨k⟩ = γ Δ(ξ_E, ξ*)                 (the spring's wrench at the end-effector)
    Q⟨k⟩  = ᴱJ(q⟨k⟩)ᵀ ᴱg⟨k⟩              (resolved into joint torques)
    q̇⟨k⟩  = Q⟨k⟩ / B                     (a viscous damper B at every joint)
    q⟨k+1⟩ = q⟨k⟩ + α q̇⟨k⟩

iterated until the pose difference vanishes. Here ``Δ = (δ_ω, δ_p)`` (angular first, robokit's
order): ``δ_ω`` is the rotation vector of ``R_Eᵀ R*`` and ``δ_p = R_Eᵀ (p* − p_E)`` — both in {E}'s
axes; ``ᴱJ`` is the end-effector-frame geometric Jacobian (rows (ω; v) of the tool origin in tool
axes, Pinocchio's LOCAL). Each step is a gradient step on ``½‖Δ‖²`` of size ``αγ/B``, so it is
robust far from the goal but converges only linearly (slowly near singularities): use
:func:`robokit.solve_ik` when speed matters.
"""
from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import ArrayLike

from robokit._arrays import as_scalar, as_vector
from robokit.description.robot import check_robot_radians
from robokit.ik.numeric import IKResult
from robokit.spatial.se3 import check_transform
from robokit.spatial import lie

if TYPE_CHECKING:
    from robokit.description.robot import Robot

__all__ = ["ik_jacobian_transpose"]


def ik_jacobian_transpose(robot: Robot, T_target: ArrayLike, q0: ArrayLike | None = None, *, gain: float = 1.0,
                          damper: float = 1.0, alpha: float = 0.5, tol: float = 1e-8, max_iterations: int = 20000,
                          frame: str | None = None) -> IKResult:
    """Joint angles reaching ``T_target`` by the lecture's Jacobian-transpose iteration (module docstring).

    ``q ← q + (αγ/B) ᴱJ(q)ᵀ Δ(q)``: a gradient step on ``½‖Δ‖²``, so it converges (linearly) only
    when the step ``αγ/B`` is below ``2/λ_max(ᴱJᵀ ᴱJ)`` — about 0.36 for the 1.8 m ``twolink``
    arm, whose iteration oscillates with the default 0.5. Joint limits are not enforced.

    Parameters
    ----------
    robot : Robot
        The robot.
    T_target : array_like, shape (4, 4)
        Goal pose of ``frame`` in the base frame, m.
    q0 : array_like, shape (n,), optional
        Start configuration, rad or m (default zeros).
    gain : float, optional
        Spring stiffness γ (N/m and N·m/rad on the normalised error; default 1, > 0).
    damper : float, optional
        Joint damping B (N·m·s/rad; default 1, > 0).
    alpha : float, optional
        Time step α, s (default 0.5, > 0).
    tol : float, optional
        Stop when ``‖Δ‖ < tol`` (rad and m mixed; default 1e-8).
    max_iterations : int, optional
        Iteration cap (default 20000).
    frame : str or None, optional
        The frame to place (default the tip).

    Returns
    -------
    IKResult
        ``method == "transpose"``, ``restarts == 0``; ``success`` False when the cap is reached
        (e.g. an unreachable goal; no exception).

    Examples
    --------
    >>> robot = rk.load("twolink")
    >>> res = ik_jacobian_transpose(robot, robot.frame_pose([0.5, 0.5]), [0.3, 0.8], alpha=0.2)
    >>> res.success, res.q.round(6).tolist(), res.method
    (True, [0.5, 0.5], 'transpose')
    """
    import time

    t0 = time.perf_counter()
    T = check_transform(T_target, "T_target")
    q = np.zeros(robot.n) if q0 is None else as_vector(q0, "q0", robot.n).copy()
    if q0 is not None:
        check_robot_radians(robot, q, "q0")
    step = as_scalar(alpha, "alpha", positive=True) * as_scalar(gain, "gain", positive=True) \
        / as_scalar(damper, "damper", positive=True)
    tol = as_scalar(tol, "tol", positive=True)
    R_t, p_t = T[:3, :3], T[:3, 3]

    def error(q: np.ndarray) -> np.ndarray:
        TE = robot.frame_pose(q, frame)
        RE = TE[:3, :3]
        return np.r_[lie.log3(RE.T @ R_t), RE.T @ (p_t - TE[:3, 3])]

    delta = error(q)
    k = 0
    while np.linalg.norm(delta) >= tol and k < int(max_iterations):
        J_E = robot.jacobian(q, frame, reference="local")  # (ω; v) in the tool frame
        Q = J_E.T @ delta  # joint torques of the spring wrench (γ folded into step)
        q = q + step * Q  # q̇ = Q / B, q ← q + α q̇
        delta = error(q)
        k += 1
    return IKResult(q=q, success=bool(np.linalg.norm(delta) < tol), residual=float(np.linalg.norm(delta)),
                    position_error=float(np.linalg.norm(delta[3:])), orientation_error=float(np.linalg.norm(delta[:3])),
                    iterations=k, restarts=0, seconds=time.perf_counter() - t0, method="transpose")
