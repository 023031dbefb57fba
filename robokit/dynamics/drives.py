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
  equation above, its mass matrix, and ``q̈ = (M + G²Jm)⁻¹(τ − c − g − τ_f)``. Their flags
  ``friction`` and ``coulomb`` (both True by default) keep the friction ``τ_f = G² B q̇ + |G|
  T_c(sign q̇)`` (:func:`friction_torque` referred to the joint): ``friction=False`` drops both
  terms, ``coulomb=False`` the Coulomb term alone.
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
    """The drive data of ``robot``: motor inertia, gear ratio, viscous and Coulomb friction, motor side.

    Parameters
    ----------
    robot : Robot
        A :class:`robokit.Robot` loaded from a DH file (``robot.dh`` not None).

    Returns
    -------
    Jm : (n,) ndarray
        Motor (rotor) inertia, kg·m².
    G : (n,) ndarray
        Gear ratio, motor turns per joint turn (signed).
    B : (n,) ndarray
        Viscous friction, N·m·s/rad.
    Tc : (n, 2) ndarray
        Coulomb friction levels ``(Tc⁺, Tc⁻)``, N·m.

    Raises
    ------
    InputError
        When the robot has no DH table (hence no drive data).

    Examples
    --------
    The PUMA 560's joint 1 (the numbers of Corke's model):

    >>> Jm, G, B, Tc = drive_parameters(rk.load("puma560"))
    >>> float(Jm[0]), float(G[0]), Tc[0].tolist()
    (0.0002, -62.6111, [0.395, -0.435])
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
    """Joint friction ``B q̇ + T_c(sign q̇)`` — the one friction law of robokit (Lecture 7).

    The lecture's ``Q_f = B q̇ + Q_C``: viscous B and Coulomb levels Tc (Tc⁺ for q̇ > 0, Tc⁻ for
    q̇ < 0, 0 at rest; the negative level is usually negative, Corke's convention), all on the joint
    side. The value is the torque friction consumes (the motor supplies it).

    Parameters
    ----------
    dq : (n,) array_like
        Joint rates (rad/s).
    B : (n,) array_like
        Viscous coefficients (N·m·s/rad).
    Tc : (n, 2) array_like
        Coulomb levels ``(Tc⁺, Tc⁻)`` (N·m).
    coulomb : bool, optional
        Include the Coulomb term; default True.

    Returns
    -------
    (n,) ndarray
        Friction torques (N·m).

    Examples
    --------
    >>> friction_torque([1.0, -1.0], [0.1, 0.1], [[0.2, -0.2], [0.2, -0.2]])
    array([ 0.3, -0.3])
    """
    dq = np.asarray(dq, dtype=float)
    Tc = np.asarray(Tc, dtype=float).reshape(-1, 2)
    tau = np.multiply(np.asarray(B, dtype=float), dq)
    if coulomb:
        tau = tau + np.where(dq > 0, Tc[:, 0], np.where(dq < 0, Tc[:, 1], 0.0))
    return tau


def joint_drive_parameters(table: DHTable) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The drives of a DH table referred to the joints (Lecture 8).

    ``ˡB = G² ᵐB``, ``ˡτ_C = |G| ᵐτ_C``, ``ˡJ = G² ᵐJ``.

    Parameters
    ----------
    table : DHTable
        A DH table with drive data (Jm, G, B, Tc per link; zeros when absent).

    Returns
    -------
    B : (n,) ndarray
        Joint-side viscous friction ``G² B`` (N·m·s/rad).
    Tc : (n, 2) ndarray
        Joint-side Coulomb levels ``|G| Tc`` (N·m).
    Jm : (n,) ndarray
        Joint-side (reflected) motor inertia ``G² Jm`` (kg·m²).

    Examples
    --------
    The PUMA 560's joint 1: its rotor of 2e-4 kg·m² behind a 62.6:1 gearbox weighs 0.784 kg·m² at the
    joint:

    >>> B, Tc, Jm = joint_drive_parameters(rk.load("puma560").dh)
    >>> round(float(Jm[0]), 4)
    0.784
    """
    G = np.array([float(l.G) for l in table.links])
    B = np.array([float(l.B) for l in table.links])
    Tc = np.array([np.asarray(l.Tc, dtype=float) for l in table.links]).reshape(-1, 2)
    Jm = np.array([float(l.Jm) for l in table.links])
    return G * G * B, np.abs(G)[:, None] * Tc, G * G * Jm


def friction_torques(table: DHTable, dq: ArrayLike) -> np.ndarray:
    """Joint friction torques of a DH table's drives: ``G² B q̇ + |G| T_c(sign q̇)`` per joint.

    Motor-side viscous B and Coulomb T_c referred through the gear ratio G (Corke's convention).

    Parameters
    ----------
    table : DHTable
        A DH table with drive data.
    dq : (n,) array_like
        Joint rates (rad/s).

    Returns
    -------
    (n,) ndarray
        Friction torques at the joints (N·m); 0 for joints at rest.

    Examples
    --------
    PUMA 560 joint 1 turning at 1 rad/s: ``G² B + |G| Tc⁺`` (5.8018 + 24.7314 N·m):

    >>> friction_torques(rk.load("puma560").dh, [1, 0, 0, 0, 0, 0]).round(4)
    array([30.5332,  0.    ,  0.    ,  0.    ,  0.    ,  0.    ])
    """
    dq = as_vector(dq, "dq", table.n)
    B, Tc, _ = joint_drive_parameters(table)
    return friction_torque(dq, B, Tc)


def _friction(G: np.ndarray, B: np.ndarray, Tc: np.ndarray, dq: np.ndarray, coulomb: bool) -> np.ndarray:
    return friction_torque(dq, G * G * B, np.abs(G)[:, None] * Tc, coulomb)


def rne_with_drives(robot: Robot, q: ArrayLike, dq: ArrayLike, ddq: ArrayLike, *, motor_inertia: bool = True,
                    friction: bool = True,
                    coulomb: bool = True) -> np.ndarray:
    """Joint torques including the drives (Lectures 7–8).

    ``τ = M q̈ + c + g + G² Jm q̈ + G² B q̇ + |G| T_c(sign q̇)``, what Corke's ``rne`` computes.

    Parameters
    ----------
    robot : Robot
        A :class:`robokit.Robot` loaded from a DH file; gravity is the robot's.
    q, dq, ddq : (n,) array_like
        Joint angles (rad), rates (rad/s), accelerations (rad/s²).
    motor_inertia : bool, optional
        Include the reflected motor inertia ``G² Jm q̈``; default True.
    friction, coulomb : bool, optional
        Which terms of τ_f to add to τ (module docstring).

    Returns
    -------
    (n,) ndarray
        τ (N·m; N for prismatic joints).

    Examples
    --------
    Accelerating PUMA 560 joint 1 at 1 rad/s² from rest needs 0.784 N·m more than the arm alone:
    its rotor's ``G² Jm``:

    >>> puma = rk.load("puma560")
    >>> q, dq, ddq = np.zeros(6), np.zeros(6), np.array([1.0, 0, 0, 0, 0, 0])
    >>> (rne_with_drives(puma, q, dq, ddq) - puma.rnea(q, dq, ddq)).round(4)
    array([0.784, 0.   , 0.   , 0.   , 0.   , 0.   ])
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
    """Joint-space inertia seen by the joints with the motors: ``M(q) + diag(G² Jm)`` (Lecture 8).

    Symmetric positive definite; equals Corke's ``inertia(q)``.

    Parameters
    ----------
    robot : Robot
        A :class:`robokit.Robot` loaded from a DH file.
    q : (n,) array_like
        Joint angles (rad).

    Returns
    -------
    (n, n) ndarray
        The inertia matrix (kg·m²).

    Examples
    --------
    The diagonal grows by each joint's reflected rotor inertia ``G² Jm``:

    >>> puma = rk.load("puma560")
    >>> (inertia_with_drives(puma, np.zeros(6)) - puma.crba(np.zeros(6))).diagonal().round(4)
    array([0.784 , 2.3248, 0.5769, 0.1908, 0.1707, 0.1941])
    """
    q = as_vector(q, "q", robot.n)
    Jm, G, _, _ = drive_parameters(robot)
    return robot.crba(q) + np.diag(G * G * Jm)


def forward_dynamics_with_drives(robot: Robot, q: ArrayLike, dq: ArrayLike, tau: ArrayLike, *, friction: bool = True,
                                 coulomb: bool = True) -> np.ndarray:
    """Joint accelerations ``q̈ = (M + G²Jm)⁻¹ (τ − c(q, q̇) − g(q) − τ_f(q̇))`` (Lecture 7).

    Forward dynamics with the drives' inertia and friction τ_f; the inverse of
    :func:`rne_with_drives`.

    Parameters
    ----------
    robot : Robot
        A :class:`robokit.Robot` loaded from a DH file.
    q, dq, tau : (n,) array_like
        Joint angles (rad), rates (rad/s) and torques (N·m).
    friction, coulomb : bool, optional
        Which terms of τ_f to subtract from τ (module docstring).

    Returns
    -------
    (n,) ndarray
        q̈ (rad/s²).

    Examples
    --------
    >>> puma = rk.load("puma560")
    >>> qn, dq, ddq = [0, np.pi / 4, np.pi, 0, np.pi / 4, 0], np.full(6, 0.5), [1, -1, 0.5, 0, 0.2, 0.1]
    >>> forward_dynamics_with_drives(puma, qn, dq, rne_with_drives(puma, qn, dq, ddq)).round(4)
    array([ 1. , -1. ,  0.5,  0. ,  0.2,  0.1])
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
    """The inertia each motor sees: ``ᵐJⱼ = Jmⱼ + Mⱼⱼ(q) / Gⱼ²`` (motor side; Lecture 7).

    Parameters
    ----------
    robot : Robot
        A :class:`robokit.Robot` loaded from a DH file.
    q : (n,) array_like
        Joint angles (rad); M is the rigid-body mass matrix of the arm (without motors).

    Returns
    -------
    (n,) ndarray
        Motor-side inertia per joint (kg·m²).

    Examples
    --------
    For the PUMA 560 at the nominal pose the arm adds ``M₂₂/G₂² ≈ 1.8e-4`` kg·m² to joint 2's rotor
    ``Jm = 2e-4`` kg·m²: through a 108:1 gearbox the motor sees the arm's inertia divided by ≈ 11600:

    >>> puma = rk.load("puma560")
    >>> qn = [0, np.pi / 4, np.pi, 0, np.pi / 4, 0]
    >>> round(float(reflected_inertia(puma, qn)[1]) * 1e4, 2)
    3.8
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
      accelerations reachable with unit joint torque ``QᵀQ = 1`` (``ν̇ = J M⁻¹ Q`` at q̇ = 0, no
      gravity).

    Parameters
    ----------
    robot : Robot
        A :class:`robokit.Robot`.
    q : (n,) array_like
        Joint angles (rad).
    method : {"asada", "yoshikawa"}, optional
        The measure; default "asada".
    drives : bool, optional
        Include ``diag(G² Jm)`` in M (a robot without a DH table needs ``drives=False``); default True.
    frame : str, optional
        Frame name; default the robot's tip.

    Returns
    -------
    float
        The measure (dimensionless for "asada").

    Raises
    ------
    InputError
        On an unknown ``method``, or ``drives=True`` for a robot without drive data.

    Examples
    --------
    Equal to Corke's ``manipulability(qn, method="asada")`` for the PUMA 560; the heavy rotors make
    the arm's inertia far more isotropic:

    >>> puma = rk.load("puma560")
    >>> qn = [0, np.pi / 4, np.pi, 0, np.pi / 4, 0]
    >>> a = dynamic_manipulability(puma, qn, "asada")
    >>> bool(0 < a < 1), bool(a > dynamic_manipulability(puma, qn, "asada", drives=False))
    (True, True)
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
