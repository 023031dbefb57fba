r"""Operational-space (Cartesian) dynamics (Lecture 7): ``Λ(q) ẍ + μ(q, q̇) + p(q) = F`` at a frame,
and the dynamic manipulability measures built on it."""
from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import ArrayLike

from robokit._arrays import as_vector
from robokit.errors import InputError

if TYPE_CHECKING:
    from robokit.description.robot import Robot

__all__ = ["CartesianDynamics", "cartesian_dynamics"]


class CartesianDynamics:
    """Operational-space terms at one state (Lecture 7): ``F = Λ(q) ẍ + μ(q, q̇) + p(q)``.

    The lecture writes the same equation ``F = M_x(q) ẍ + V_x(q, q̇) + G_x(q)``: ``M_x``, ``V_x`` and
    ``G_x`` are aliases of ``Lambda``, ``mu`` and ``p``. Built by :func:`cartesian_dynamics`.

    Attributes
    ----------
    Lambda : (m, m) ndarray
        ``(J M⁻¹ Jᵀ)⁻¹``, the Cartesian mass matrix (kg, kg·m²), m = 6, or 3 for one part.
    mu : (m,) ndarray
        ``Λ (J M⁻¹ c − J̇ q̇)``, the velocity-product wrench (N, N·m).
    p : (m,) ndarray
        ``Λ J M⁻¹ g``, the gravity wrench (N, N·m).
    yoshikawa : float
        Yoshikawa's dynamic manipulability ``√det(J (MᵀM)⁻¹ Jᵀ)``.
    asada : float
        Smallest over largest eigenvalue of Λ: the isotropy of Asada's generalized inertia
        ellipsoid (1 = isotropic).
    inertia_radii : (m,) ndarray
        √eigenvalues of Λ, ascending: the ellipsoid's radii.
    inertia_axes : (m, m) ndarray
        Eigenvectors of Λ as columns (base axes): the ellipsoid's axes.
    """

    @property
    def M_x(self) -> np.ndarray:
        """The lecture's Cartesian mass matrix M_x(q), = ``Lambda``."""
        return self.Lambda

    @property
    def V_x(self) -> np.ndarray:
        """The lecture's Cartesian velocity term V_x(q, q̇), = ``mu``."""
        return self.mu

    @property
    def G_x(self) -> np.ndarray:
        """The lecture's Cartesian gravity term G_x(q), = ``p``."""
        return self.p

    def __init__(self, Lambda: np.ndarray, mu: np.ndarray, p: np.ndarray, yoshikawa: float, asada: float,
                 inertia_radii: np.ndarray, inertia_axes: np.ndarray) -> None:
        self.Lambda, self.mu, self.p = Lambda, mu, p
        self.yoshikawa, self.asada = yoshikawa, asada
        self.inertia_radii, self.inertia_axes = inertia_radii, inertia_axes


def cartesian_dynamics(robot: Robot, q: ArrayLike, dq: ArrayLike, frame: str | None = None,
                       part: str = "full") -> CartesianDynamics:
    """:class:`CartesianDynamics` of ``robot`` at (q, q̇) for a frame's geometric Jacobian (Lecture 7).

    With J the frame's Jacobian (rows ``(ω; v)``, base axes), M, c, g from Pinocchio (CRBA and
    RNEA) and J̇q̇ the frame's classical acceleration at q̈ = 0.

    Parameters
    ----------
    robot : Robot
        A :class:`robokit.Robot`.
    q, dq : (n,) array_like
        Joint values and rates (rad, rad/s).
    frame : str, optional
        Frame name; default the robot's tip.
    part : {"full", "translation", "rotation"}, optional
        The Jacobian rows used: all six (default), v or ω. J must have full row rank.

    Returns
    -------
    CartesianDynamics
        Λ, μ, p and the dynamic manipulability measures.

    Raises
    ------
    InputError
        On a bad argument or an unknown ``part``.
    numpy.linalg.LinAlgError
        At a singularity of the chosen rows (``J M⁻¹ Jᵀ`` not invertible).

    Examples
    --------
    For a square J, ``Λ = J⁻ᵀ M J⁻¹`` and ``Jᵀ p`` is the gravity torque (PUMA 560 away from
    singularities):

    >>> puma = rk.load("puma560")
    >>> q = [0, 0.5, -0.3, 0, 0.7, 0]
    >>> cd = cartesian_dynamics(puma, q, np.zeros(6))
    >>> J = puma.jacobian(q, reference="local_world_aligned")
    >>> Ji = np.linalg.inv(J)
    >>> bool(np.allclose(cd.Lambda, Ji.T @ puma.crba(q) @ Ji))
    True
    >>> bool(np.allclose(J.T @ cd.p, puma.gravity_torques(q)))
    True
    """
    import pinocchio as pin

    q = as_vector(q, "q", robot.n)
    dq = as_vector(dq, "dq", robot.n)
    rows = {"full": slice(0, 6), "rotation": slice(0, 3), "translation": slice(3, 6)}.get(part)
    if rows is None:
        raise InputError(f"part: expected 'full', 'translation' or 'rotation', got {part!r}")
    J = robot.jacobian(q, frame, reference="local_world_aligned")[rows]
    M = robot.crba(q)
    g = robot.gravity_torques(q)
    c = robot.nonlinear_effects(q, dq) - g
    # J̇ q̇: the frame's classical acceleration at zero joint acceleration
    model, data = robot.model, robot.data  # the Robot's reused workspace
    pin.forwardKinematics(model, data, robot.q_pin(q), dq, np.zeros(model.nv))
    acc = pin.getFrameClassicalAcceleration(model, data, robot.frame_id(frame), pin.LOCAL_WORLD_ALIGNED)
    Jdqd = np.r_[acc.angular, acc.linear][rows]
    Minv_JT = np.linalg.solve(M, J.T)
    Lambda = np.linalg.inv(J @ Minv_JT)
    Lambda = 0.5 * (Lambda + Lambda.T)
    mu = Lambda @ (J @ np.linalg.solve(M, c) - Jdqd)
    p = Lambda @ (J @ np.linalg.solve(M, g))
    Minv = np.linalg.inv(M)
    JM = J @ Minv
    yosh = float(np.sqrt(max(0.0, np.linalg.det(JM @ JM.T))))
    lam, vec = np.linalg.eigh(Lambda)
    return CartesianDynamics(Lambda, mu, p, yosh, float(lam[0] / lam[-1]), np.sqrt(np.clip(lam, 0, None)), vec)
