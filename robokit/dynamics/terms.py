r"""The terms of the dynamic equation and what changes them (Lectures 7–8).

``τ = M(q) q̈ + C(q, q̇) q̇ + g(q) + τ_f(q̇) + Jᵀ F_tip``

* :func:`coriolis_matrix` — a factorisation C(q, q̇) with ``C q̇ = c(q, q̇)`` and ``Ṁ − 2C``
  skew-symmetric, from the PoE model: with each link's body Jacobian Jᵢ, spatial inertia Gᵢ
  and twist Vᵢ = Jᵢ q̇, ``C = Σᵢ Jᵢᵀ (Gᵢ J̇ᵢ + Bᵢ Jᵢ)`` where
  ``Bᵢ = ½ (−ad_{Vᵢ}ᵀ Gᵢ + Gᵢ ad_{Vᵢ} + X(Gᵢ Vᵢ))`` is skew and satisfies ``Bᵢ Vᵢ = −ad_{Vᵢ}ᵀ Gᵢ Vᵢ``
  (X(h) the matrix with ``X(h) V = −ad_Vᵀ h``); ``J̇ᵢ`` column j is ``ad_{Jᵢ,j} Σ_{k>j} Jᵢ,k q̇_k``.
* :func:`friction_torques` — viscous and Coulomb friction of the DH file's drives (Lecture 8).
* :func:`add_payload` — a payload rigidly held by the tool changes the last link's inertia.
* :func:`base_wrench` — the wrench the base must supply to the arm.
* :func:`cartesian_dynamics` — Λ, μ, p of the operational-space equation (Lecture 7) and the
  dynamic manipulability measures.
* :func:`total_energy`, :func:`integrate` — energy and Euler/Taylor (the lecture's)/RK4 integration of the course
  forward dynamics (e.g. the PUMA 560 collapsing under gravity).
"""
from __future__ import annotations

import numpy as np

from robokit._arrays import as_array, as_scalar, as_vector
from robokit.dynamics.newton_euler import _model, forward_dynamics, inverse_dynamics
from robokit.spatial import lie

__all__ = [
    "coriolis_matrix",
    "friction_torques",
    "add_payload",
    "base_wrench",
    "CartesianDynamics",
    "cartesian_dynamics",
    "total_energy",
    "integrate",
]




def _X(h):
    """X(h) with X(h) V = −ad_Vᵀ h for every twist V (h a wrench (m, f))."""
    X = np.zeros((6, 6))
    X[:3, :3] = -lie.hat(h[:3])
    X[:3, 3:] = -lie.hat(h[3:])
    X[3:, :3] = -lie.hat(h[3:])
    return X


def _link_jacobians(m, theta):
    """Body Jacobians Jᵢ (n, 6, n) of the link frames {1..n} (Modern Robotics frames)."""
    n = m.n
    Ad = m.transforms(theta)  # Ad_{T_{i,i−1}}
    J = np.zeros((n, 6, n))
    for i in range(n):
        if i > 0:
            J[i, :, :i] = Ad[i] @ J[i - 1, :, :i]
        J[i, :, i] = m.AT[i]
    return J


def coriolis_matrix(thetalist, dthetalist, Mlist, Glist, Slist, method: str = "christoffel") -> np.ndarray:
    """The n×n Coriolis matrix C(θ, θ̇) with ``C θ̇ = c(θ, θ̇)``, in one of two factorisations.

    Arguments in Modern Robotics form (see :func:`robokit.inverse_dynamics`); θ, θ̇ (n,) rad, rad/s.
    The velocity-product torque ``c(θ, θ̇) = Σⱼₖ cᵢⱼₖ θ̇ⱼ θ̇ₖ`` is a quadratic form in θ̇; C is not
    unique, only ``C θ̇`` is.

    method : "christoffel" (default) — the Christoffel-symbol matrix ``Cₖⱼ = Σᵢ Γᵢⱼₖ θ̇ᵢ`` of the mass
    matrix, the one with ``Ṁ − 2C`` skew-symmetric (computed from the link body Jacobians, see the
    module docstring); "lecture" — the factorisation the lecture prints (Corke's toolbox, from
    Newton–Euler runs with ``θ̈ = 0`` and no gravity): column k collects the centripetal term of
    θ̇ₖ and every Coriolis product θ̇ⱼθ̇ₖ with j < k,
    ``C[:, k] = c(eₖ) θ̇ₖ + Σ_{j<k} (c(eⱼ + eₖ) − c(eⱼ) − c(eₖ)) θ̇ⱼ``,
    where ``c(u)`` is the velocity-product torque at joint rates u.

    For the PUMA 560 at the lecture's nominal pose ``qn = (0, π/4, π, 0, π/4, 0)`` with all
    rates 0.5 rad/s, ``C₁₂`` is −0.9115 (lecture) and −0.6453 (Christoffel); ``C θ̇`` agrees.

    Example: ``coriolis_matrix(q, dq, robot.poe.Mlist, robot.poe.Glist, robot.poe.Slist, "lecture")``.
    """
    if method not in ("christoffel", "lecture"):
        raise ValueError(f"method: expected 'christoffel' or 'lecture', got {method!r}")
    m = _model(Mlist, Glist, Slist)
    th = as_vector(thetalist, "thetalist", m.n)
    dth = as_vector(dthetalist, "dthetalist", m.n)
    n = m.n
    if method == "lecture":
        return _coriolis_lecture(th, dth, Mlist, Glist, Slist, n)
    J = _link_jacobians(m, th)
    C = np.zeros((n, n))
    for i in range(n):
        Ji = J[i]
        V = Ji @ dth
        Jd = np.zeros((6, n))
        for j in range(i + 1):
            rel = Ji[:, j + 1:i + 1] @ dth[j + 1:i + 1]
            Jd[:, j] = lie.ad(Ji[:, j]) @ rel
        G = m.G[i]
        adV = lie.ad(V)
        B = 0.5 * (-adV.T @ G + G @ adV + _X(G @ V))
        C += Ji.T @ (G @ Jd + B @ Ji)
    return C


def _coriolis_lecture(th, dth, Mlist, Glist, Slist, n):
    """The lecture's (Corke's) factorisation, from velocity-product torques c(u) (θ̈ = 0, g = 0)."""
    z3, z6, zn = np.zeros(3), np.zeros(6), np.zeros(n)

    def c(u):
        return inverse_dynamics(th, u, zn, z3, z6, Mlist, Glist, Slist)

    eye = np.eye(n)
    Csq = np.column_stack([c(eye[j]) for j in range(n)])  # c(eⱼ): the θ̇ⱼ² coefficients
    C = Csq * dth  # centripetal: column j times θ̇ⱼ
    for j in range(n):
        for k in range(j + 1, n):
            C[:, k] += (c(eye[j] + eye[k]) - Csq[:, j] - Csq[:, k]) * dth[j]
    return C


def friction_torques(table, dq) -> np.ndarray:
    """Joint friction torques (n,) of a DH table's drives: ``G² B q̇ + |G| T_c(sign q̇)`` per joint
    (motor-side viscous B and Coulomb T_c referred through the gear ratio G, Corke's convention)."""
    dq = as_vector(dq, "dq", table.n)
    return np.array([l.joint_friction(v) for l, v in zip(table.links, dq)])


def add_payload(Mlist, Glist, mass, com=(0.0, 0.0, 0.0), inertia=None):
    """Glist with a payload rigidly held at the end-effector frame added to the last link.

    mass : kg; com : (3,) payload centre of mass in the end-effector frame (m); inertia : 3×3
    about the payload's centre of mass, end-effector axes (default 0: a point mass).
    The spatial inertia moves between frames as ``G_a = Ad_{T_ba}ᵀ G_b Ad_{T_ba}`` (T_ba: pose of a
    in b). Returns a new (n, 6, 6) Glist; Mlist is unchanged (the link frame stays where it is).
    """
    Mlist = as_array(Mlist, "Mlist", (None, 4, 4))
    Glist = as_array(Glist, "Glist", (len(Mlist) - 1, 6, 6)).copy()
    mass = as_scalar(mass, "mass", nonnegative=True)
    com = as_vector(com, "com", 3)
    I = np.zeros((3, 3)) if inertia is None else as_array(inertia, "inertia", (3, 3))
    Gp = np.zeros((6, 6))
    Gp[:3, :3] = I
    Gp[3:, 3:] = mass * np.eye(3)
    # pose of the last link frame {n} in the payload frame {p}: {p} = {ee} translated by com
    T_ee_p = np.eye(4)
    T_ee_p[:3, 3] = com
    T_n_ee = Mlist[-1]
    T_n_p = T_n_ee @ T_ee_p
    T_p_n = np.linalg.inv(T_n_p)
    A = lie.adjoint(T_p_n[None])[0]
    Glist[-1] = Glist[-1] + A.T @ Gp @ A
    return Glist


def base_wrench(thetalist, dthetalist, ddthetalist, g, Ftip, Mlist, Glist, Slist) -> np.ndarray:
    """The wrench (m, f) (6,) the base must apply to the arm, in the base frame {0} at its origin.

    From the backward Newton–Euler pass: the wrench transmitted through joint 1, ``F₁``, carried
    to frame {0} with ``Ad_{T_{1,0}}ᵀ``. At rest it balances the arm's weight: f = −(Σ mᵢ) g.
    """
    m = _model(Mlist, Glist, Slist)
    n = m.n
    th = as_vector(thetalist, "thetalist", n)
    dth = as_vector(dthetalist, "dthetalist", n)
    ddth = as_vector(ddthetalist, "ddthetalist", n)
    g = as_vector(g, "g", 3)
    Ftip = as_vector(Ftip, "Ftip", 6)
    Ad = m.transforms(th)
    A, G = m.AT, m.G
    V = np.zeros(6)
    Vd = np.r_[0.0, 0.0, 0.0, -g]
    Vs, Vds = [], []
    for i in range(n):
        V = Ad[i] @ V + A[i] * dth[i]
        Vd = Ad[i] @ Vd + (lie.ad(V) @ A[i]) * dth[i] + A[i] * ddth[i]
        Vs.append(V)
        Vds.append(Vd)
    F = Ftip
    Ad_next = m.Ad_tip
    for i in range(n - 1, -1, -1):
        F = Ad_next.T @ F + G[i] @ Vds[i] - lie.ad(Vs[i]).T @ G[i] @ Vs[i]
        Ad_next = Ad[i]
    # F is F₁ (in frame {1}); carried to {0}. The gravity used here is an upward base acceleration,
    # so F already contains the weight.
    return Ad[0].T @ F


class CartesianDynamics:
    """Operational-space terms at one state (Lecture 7): ``F = Λ(q) ẍ + μ(q, q̇) + p(q)``.

    Lambda (6×6 or m×m) ``(J M⁻¹ Jᵀ)⁻¹``; mu ``Λ (J M⁻¹ c − J̇ q̇)``; p ``Λ J M⁻¹ g``; plus the
    dynamic manipulability measures: ``yoshikawa = √det(J (MᵀM)⁻¹ Jᵀ)`` (Yoshikawa's dynamic
    manipulability) and ``asada`` = ratio of the smallest to the largest eigenvalue of Λ (the
    isotropy of Asada's generalized inertia ellipsoid), with ``inertia_axes``/``inertia_radii``
    of that ellipsoid (eigenvectors, √eigenvalues of Λ).
    """

    def __init__(self, Lambda, mu, p, yoshikawa, asada, inertia_radii, inertia_axes):
        self.Lambda, self.mu, self.p = Lambda, mu, p
        self.yoshikawa, self.asada = yoshikawa, asada
        self.inertia_radii, self.inertia_axes = inertia_radii, inertia_axes


def cartesian_dynamics(robot, q, dq, frame: str | None = None, part: str = "full") -> CartesianDynamics:
    """:class:`CartesianDynamics` of ``robot`` at (q, q̇) for the frame's geometric Jacobian
    (base axes; ``part`` "full", "translation" or "rotation" selects the rows)."""
    import pinocchio as pin

    q = as_vector(q, "q", robot.n)
    dq = as_vector(dq, "dq", robot.n)
    rows = {"full": slice(0, 6), "rotation": slice(0, 3), "translation": slice(3, 6)}.get(part)
    if rows is None:
        raise ValueError(f"part: expected 'full', 'translation' or 'rotation', got {part!r}")
    J = robot.jacobian(q, frame, reference="local_world_aligned")[rows]
    M = robot.crba(q)
    g = robot.gravity_torques(q)
    c = robot.nonlinear_effects(q, dq) - g
    # J̇ q̇: the frame's classical acceleration at zero joint acceleration
    model, data = robot.model, robot.model.createData()
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


def total_energy(robot, q, dq) -> float:
    """Kinetic plus potential energy ``½ q̇ᵀ M q̇ + V(q)`` (J), V from the robot's gravity."""
    import pinocchio as pin

    q = as_vector(q, "q", robot.n)
    dq = as_vector(dq, "dq", robot.n)
    V = pin.computePotentialEnergy(robot.model, robot.model.createData(), robot.q_pin(q))
    return float(0.5 * dq @ robot.crba(q) @ dq + V)


def integrate(thetalist, dthetalist, taufun, g, Mlist, Glist, Slist, dt: float, steps: int, method: str = "rk4"):
    """Integrate the course forward dynamics ``θ̈ = M⁻¹(τ − c − g)`` with Euler, the lecture's step or RK4.

    method : "rk4" (default, fourth-order Runge–Kutta); "euler" (``θ ← θ + θ̇Δt``, ``θ̇ ← θ̇ + θ̈Δt``);
    "taylor" — the lecture's step (Lecture 7, forward dynamics)
    ``θ̇(t+Δt) = θ̇ + θ̈Δt``, ``θ(t+Δt) = θ + θ̇Δt + ½θ̈Δt²``.
    taufun : function (t, θ, θ̇) → τ (n,) (e.g. ``lambda t, q, dq: np.zeros(n)`` for a free
    fall); dt : step (s); steps : number of steps. Returns ``(t, thetamat, dthetamat)`` with
    ``steps + 1`` rows.
    """
    th = as_vector(thetalist, "thetalist").copy()
    dth = as_vector(dthetalist, "dthetalist", len(th)).copy()
    dt = as_scalar(dt, "dt", positive=True)
    if method not in ("rk4", "euler", "taylor"):
        raise ValueError(f"method: expected 'rk4', 'euler' or 'taylor', got {method!r}")
    z6 = np.zeros(6)

    def acc(t, a, b):
        return forward_dynamics(a, b, taufun(t, a, b), g, z6, Mlist, Glist, Slist)

    T = np.arange(int(steps) + 1) * dt
    Q = np.empty((len(T), len(th)))
    D = np.empty_like(Q)
    Q[0], D[0] = th, dth
    for k in range(int(steps)):
        t = T[k]
        if method == "euler":
            a = acc(t, th, dth)
            th, dth = th + dt * dth, dth + dt * a
        elif method == "taylor":
            a = acc(t, th, dth)
            th, dth = th + dt * dth + 0.5 * dt * dt * a, dth + dt * a
        else:
            k1q, k1v = dth, acc(t, th, dth)
            k2q, k2v = dth + 0.5 * dt * k1v, acc(t + 0.5 * dt, th + 0.5 * dt * k1q, dth + 0.5 * dt * k1v)
            k3q, k3v = dth + 0.5 * dt * k2v, acc(t + 0.5 * dt, th + 0.5 * dt * k2q, dth + 0.5 * dt * k2v)
            k4q, k4v = dth + dt * k3v, acc(t + dt, th + dt * k3q, dth + dt * k3v)
            th = th + dt / 6 * (k1q + 2 * k2q + 2 * k3q + k4q)
            dth = dth + dt / 6 * (k1v + 2 * k2v + 2 * k3v + k4v)
        Q[k + 1], D[k + 1] = th, dth
    return T, Q, D
