r"""The drive train in the dynamics of a Robot loaded from a DH file (Lectures 7–8).

Each joint j is driven by a motor through a gearbox of ratio G (motor turns per joint turn).
The DH file gives, per link, the motor inertia ``Jm`` (kg·m², motor side), the gear ratio ``G``,
the motor-side viscous friction ``B`` (N·m·s/rad) and the Coulomb friction ``Tc = (Tc⁺, Tc⁻)``
(N·m, motor side). Referred to the joint (Lecture 8: ``ˡJ = G² ᵐJ``, ``ˡB = G² ᵐB``,
``ˡτ_C = G ᵐτ_C``, ``ˡθ̇ = ᵐθ̇ / G``) they add to the rigid-body equation

    τ = (M(q) + diag(G² Jm)) q̈ + c(q, q̇) + g(q) + G² B q̇ + |G| T_c(sign q̇),

where ``T_c(sign q̇)`` is Tc⁺ for q̇ > 0, Tc⁻ for q̇ < 0 and 0 at rest (Lecture 7:
``Q_f = B q̇ + Q_C``). This is what Corke's toolbox computes with ``rne``/``inertia`` for its DH
models (its Puma560 carries exactly the numbers of ``models/puma560.yaml``).

The inertia one motor sees (Lecture 7–8) is ``ᵐJⱼ = Jmⱼ + Mⱼⱼ(q) / Gⱼ²`` (:func:`reflected_inertia`).

* :func:`drive_parameters` — the (n,) arrays Jm, G, B and the (n, 2) array Tc of a robot.
* :func:`rne_with_drives`, :func:`inertia_with_drives`, :func:`forward_dynamics_with_drives` — the
  equation above, its mass matrix, and ``q̈ = (M + G²Jm)⁻¹(τ − c − g − τ_f)``.
* :func:`reflected_inertia` — the motor-side inertia of every joint.
* :func:`dynamic_manipulability` — Asada's and Yoshikawa's measures with the drives' inertia.

The rigid-body parts (M, c, g) come from the Robot (Pinocchio); a robot without a DH table has no
drive data and raises ``ValueError``.
"""
from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import ArrayLike

from robokit._arrays import as_vector
from robokit.errors import InputError

if TYPE_CHECKING:
    from robokit.description.dh import DHTable
    from robokit.description.robot import Robot

__all__ = [
    "drive_parameters",
    "joint_drive_parameters",
    "friction_torque",
    "friction_torques",
    "rne_with_drives",
    "inertia_with_drives",
    "forward_dynamics_with_drives",
    "reflected_inertia",
    "dynamic_manipulability",
]


def drive_parameters(robot: Robot) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """``(Jm, G, B, Tc)`` of ``robot``'s drives: (n,), (n,), (n,) and (n, 2) arrays, motor side.

    robot : a :class:`robokit.Robot` loaded from a DH file (``robot.dh`` not None).
    Example: ``drive_parameters(robokit.load("puma560"))[1][0]`` is −62.6111 (joint 1's gear ratio).
    """
    dh = getattr(robot, "dh", None)
    if dh is None:
        raise InputError(f"robot: {getattr(robot, 'name', robot)!r} has no DH table, hence no drive data "
                         "(Jm, G, B, Tc come from the DH file)")
    Jm = np.array([float(l.Jm) for l in dh.links])
    G = np.array([float(l.G) for l in dh.links])
    B = np.array([float(l.B) for l in dh.links])
    Tc = np.array([np.asarray(l.Tc, dtype=float) for l in dh.links]).reshape(-1, 2)
    return Jm, G, B, Tc


def friction_torque(dq: ArrayLike, B: ArrayLike, Tc: ArrayLike, coulomb: bool = True) -> np.ndarray:
    """Joint friction ``B q̇ + T_c(sign q̇)`` (n,) — the one friction law of robokit (Lecture 7:
    ``Q_f = B q̇ + Q_C``): viscous B (n,) and Coulomb levels Tc (n, 2) (Tc⁺ for q̇ > 0, Tc⁻ for
    q̇ < 0, 0 at rest; the negative level is usually negative, Corke's convention), all on the
    joint side. The value is the torque friction consumes (the motor supplies it).

    Example: ``friction_torque([1.0, -1.0], [0.1, 0.1], [[0.2, -0.2], [0.2, -0.2]])`` → ``[0.3, -0.3]``.
    """
    dq = np.asarray(dq, dtype=float)
    Tc = np.asarray(Tc, dtype=float).reshape(-1, 2)
    tau = np.multiply(np.asarray(B, dtype=float), dq)
    if coulomb:
        tau = tau + np.where(dq > 0, Tc[:, 0], np.where(dq < 0, Tc[:, 1], 0.0))
    return tau


def joint_drive_parameters(table: DHTable) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The drives of a DH table referred to the joints: ``(G² B, |G| Tc, G² Jm)`` as (n,), (n, 2), (n,)
    arrays (Lecture 8: ``ˡB = G² ᵐB``, ``ˡτ_C = |G| ᵐτ_C``, ``ˡJ = G² ᵐJ``)."""
    G = np.array([float(l.G) for l in table.links])
    B = np.array([float(l.B) for l in table.links])
    Tc = np.array([np.asarray(l.Tc, dtype=float) for l in table.links]).reshape(-1, 2)
    Jm = np.array([float(l.Jm) for l in table.links])
    return G * G * B, np.abs(G)[:, None] * Tc, G * G * Jm


def friction_torques(table: DHTable, dq: ArrayLike) -> np.ndarray:
    """Joint friction torques (n,) of a DH table's drives: ``G² B q̇ + |G| T_c(sign q̇)`` per joint
    (motor-side viscous B and Coulomb T_c referred through the gear ratio G, Corke's convention)."""
    dq = as_vector(dq, "dq", table.n)
    B, Tc, _ = joint_drive_parameters(table)
    return friction_torque(dq, B, Tc)


def _friction(G: np.ndarray, B: np.ndarray, Tc: np.ndarray, dq: np.ndarray, coulomb: bool) -> np.ndarray:
    return friction_torque(dq, G * G * B, np.abs(G)[:, None] * Tc, coulomb)


def rne_with_drives(robot: Robot, q: ArrayLike, dq: ArrayLike, ddq: ArrayLike, *, motor_inertia: bool = True,
                    friction: bool = True,
                    coulomb: bool = True) -> np.ndarray:
    """Joint torques (n,) including the drives:
    ``τ = M q̈ + c + g + G² Jm q̈ + G² B q̇ + |G| T_c(sign q̇)`` (N·m; N for prismatic joints).

    q, dq, ddq : (n,) joint angles (rad), rates (rad/s), accelerations (rad/s²); gravity is the
    robot's. motor_inertia, friction, coulomb : include the reflected motor inertia, the viscous
    and the Coulomb friction (all by default, as Corke's ``rne``).

    Example: ``rne_with_drives(robokit.load("puma560"), q, dq, ddq)``.
    """
    n = robot.n
    q = as_vector(q, "q", n)
    dq = as_vector(dq, "dq", n)
    ddq = as_vector(ddq, "ddq", n)
    Jm, G, B, Tc = drive_parameters(robot)
    tau = robot.rnea(q, dq, ddq)
    if motor_inertia:
        tau = tau + G * G * Jm * ddq
    if friction:
        tau = tau + _friction(G, B, Tc, dq, coulomb)
    return tau


def inertia_with_drives(robot: Robot, q: ArrayLike) -> np.ndarray:
    """Joint-space inertia (n×n) seen by the joints with the motors: ``M(q) + diag(G² Jm)``.

    q : (n,) joint angles (rad). Symmetric positive definite; equals Corke's ``inertia(q)``.

    Example: ``inertia_with_drives(robokit.load("puma560"), np.zeros(6))[0, 0]`` includes joint 1's
    reflected rotor ``62.61² × 2e-4 ≈ 0.78`` kg·m².
    """
    q = as_vector(q, "q", robot.n)
    Jm, G, _, _ = drive_parameters(robot)
    return robot.crba(q) + np.diag(G * G * Jm)


def forward_dynamics_with_drives(robot: Robot, q: ArrayLike, dq: ArrayLike, tau: ArrayLike, *, friction: bool = True,
                                 coulomb: bool = True) -> np.ndarray:
    """Joint accelerations (n,) ``q̈ = (M + G²Jm)⁻¹ (τ − c(q, q̇) − g(q) − τ_f(q̇))`` (Lecture 7,
    forward dynamics, with the drives' inertia and friction τ_f).

    q, dq, tau : (n,) rad, rad/s, N·m. The inverse of :func:`rne_with_drives`.

    Example: ``forward_dynamics_with_drives(robot, q, dq, rne_with_drives(robot, q, dq, ddq))`` returns ddq.
    """
    n = robot.n
    q = as_vector(q, "q", n)
    dq = as_vector(dq, "dq", n)
    tau = as_vector(tau, "tau", n)
    _, G, B, Tc = drive_parameters(robot)
    rhs = tau - robot.nonlinear_effects(q, dq)
    if friction:
        rhs = rhs - _friction(G, B, Tc, dq, coulomb)
    return np.linalg.solve(inertia_with_drives(robot, q), rhs)


def reflected_inertia(robot: Robot, q: ArrayLike) -> np.ndarray:
    """The inertia (n,) each motor sees: ``ᵐJⱼ = Jmⱼ + Mⱼⱼ(q) / Gⱼ²`` (kg·m², motor side; Lecture 7).

    q : (n,) joint angles (rad); M is the rigid-body mass matrix of the arm (without motors).
    Example: for the PUMA 560 at the nominal pose the arm adds ``M₂₂/G₂² ≈ 1.8e-4`` kg·m² to joint 2's
    rotor ``Jm = 2e-4`` kg·m²: through a 108:1 gearbox the motor sees the arm's inertia divided by ≈ 11600.
    """
    q = as_vector(q, "q", robot.n)
    Jm, G, _, _ = drive_parameters(robot)
    return Jm + np.diag(robot.crba(q)) / (G * G)


def dynamic_manipulability(robot: Robot, q: ArrayLike, method: str = "asada", *, drives: bool = True,
                           frame: str | None = None) -> float:
    """A dynamic manipulability measure of ``robot`` at q (Lecture 7).

    With J the 6×n geometric Jacobian of ``frame`` (base axes, rows (ω; v)) and M the joint-space
    inertia (with the motors when ``drives``):

    * "asada" — the ratio of the smallest to the largest eigenvalue of the Cartesian inertia
      ``M_x = (J M⁻¹ Jᵀ)⁻¹`` (``= J⁻ᵀ M J⁻¹`` for a square J): 1 is isotropic, in [0, 1];
    * "yoshikawa" — ``√det(J M⁻¹ M⁻ᵀ Jᵀ)``, proportional to the volume of the ellipsoid of
      accelerations reachable with unit joint torque ``QᵀQ = 1`` (``ν̇ = J M⁻¹ Q`` at q̇ = 0, no gravity).

    drives : include ``diag(G² Jm)`` in M (a robot without a DH table needs ``drives=False``).

    Example: ``dynamic_manipulability(robokit.load("puma560"), qn, "asada")`` equals Corke's
    ``manipulability(qn, method="asada")``.
    """
    q = as_vector(q, "q", robot.n)
    M = inertia_with_drives(robot, q) if drives else robot.crba(q)
    J = robot.jacobian(q, frame, reference="local_world_aligned")
    A = J @ np.linalg.solve(M, J.T)  # J M⁻¹ Jᵀ
    if method == "asada":
        lam = np.linalg.eigvalsh(np.linalg.inv(0.5 * (A + A.T)))
        return float(lam[0] / lam[-1])
    if method == "yoshikawa":
        JMi = np.linalg.solve(M.T, J.T).T  # J M⁻¹
        return float(np.sqrt(max(0.0, np.linalg.det(JMi @ JMi.T))))
    raise InputError(f"method: expected 'asada' or 'yoshikawa', got {method!r}")
