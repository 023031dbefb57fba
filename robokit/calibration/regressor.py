r"""Newton–Euler linear in the inertial parameters: the regressor ``τ = Y(q, q̇, q̈) π`` (Lecture 7).

Standard parameters. Link i (the body moved by joint i) has ten, in **joint i's frame** (the
frame of :mod:`robokit.calibration.chain`, Pinocchio's joint frame), about **that frame's
origin** (Pinocchio's order):

``πᵢ = (m, m c_x, m c_y, m c_z, I_xx, I_xy, I_yy, I_xz, I_yz, I_zz)``,

with ``I = I_C + m([c]ᵀ[c])`` the inertia about the origin (``I_C`` about the centre of mass c).
The spatial inertia about the origin, angular first, is linear in them:

.. math::

    G_i = \begin{pmatrix} I & [m c] \\ -[m c] & m 1 \end{pmatrix}, \qquad
    G V = Φ(V)\, π, \quad
    Φ(ω, v) = \begin{pmatrix} 0 & -[v] & L(ω) \\ v & [ω] & 0 \end{pmatrix}

(``L(ω)`` the 3×6 matrix with ``I ω = L(ω)(I_xx, I_xy, I_yy, I_xz, I_yz, I_zz)``). The course's
Newton–Euler recursion in body frames (Modern Robotics ch. 8),

* forward, ``V₀ = 0``, ``V̇₀ = (0, −g)``: ``Vᵢ = Ad_{T_{i,i−1}} V_{i−1} + Aᵢ q̇ᵢ``,
  ``V̇ᵢ = Ad_{T_{i,i−1}} V̇_{i−1} + ad_{Vᵢ} Aᵢ q̇ᵢ + Aᵢ q̈ᵢ``;
* each link's own wrench ``Gᵢ V̇ᵢ − ad_{Vᵢ}ᵀ Gᵢ Vᵢ = Kᵢ πᵢ`` with
  ``Kᵢ = Φ(V̇ᵢ) − ad_{Vᵢ}ᵀ Φ(Vᵢ)`` (6×10);
* backward, ``Fᵢ = Kᵢ πᵢ + Ad_{T_{i+1,i}}ᵀ F_{i+1}``, ``τⱼ = Aⱼᵀ Fⱼ``,

gives the block ``Y_{ji} = Aⱼᵀ Ad_{T_{j+1,j}}ᵀ ⋯ Ad_{T_{i,i−1}}ᵀ Kᵢ`` for i ≥ j (zero for i < j).

Friction per joint, viscous and Coulomb: ``τ_f,j = f_v,j q̇ⱼ + f_c,j sign(q̇ⱼ)`` — two more columns
per joint.

Base parameters. Some columns of Y are zero or combinations of others for every motion (a
link's inertia about an axis that never turns, masses that only ever appear together). QR with
column pivoting of Y stacked over many random motions (columns scaled to unit norm) gives its rank
r; the r independent columns ``Y₁`` kept are the first ones in the standard order (link 1 first,
by Gram–Schmidt), so that — as in Khalil & Dombre's regrouping — a later link's parameters are
grouped into earlier ones and the choice does not depend on the samples. The others satisfy
``Y₂ = Y₁ β``, so ``Y π = Y₁ (π₁ + β π₂)``: the r base parameters ``π_b = π₁ + β π₂`` are what
data can identify (Gautier & Khalil 1990).
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from robokit._arrays import kernel_arrays
from robokit.calibration.chain import JointChain, chain_from_robot
from robokit.kinematics.poe import screw_exponentials
from robokit.spatial import lie

if TYPE_CHECKING:
    from robokit.description.robot import Robot

__all__ = ["inertial_regressor", "friction_regressor", "full_regressor", "standard_parameters", "standard_parameter_names",
           "BaseParameters", "base_parameters"]

#: Relative pivot size below which a regressor column counts as dependent.
BASE_TOL = 1e-8


def _phi(V: np.ndarray) -> np.ndarray:
    """Φ(V) (N, 6, 10): ``G V = Φ(V) π`` for twists V (N, 6)."""
    w, v = V[:, :3], V[:, 3:]
    N = V.shape[0]
    out = np.zeros((N, 6, 10))
    out[:, 3:, 0] = v
    out[:, :3, 1:4] = -lie.hat(v)
    out[:, 3:, 1:4] = lie.hat(w)
    wx, wy, wz = w[:, 0], w[:, 1], w[:, 2]
    out[:, 0, 4], out[:, 0, 5], out[:, 0, 7] = wx, wy, wz
    out[:, 1, 5], out[:, 1, 6], out[:, 1, 8] = wx, wy, wz
    out[:, 2, 7], out[:, 2, 8], out[:, 2, 9] = wx, wy, wz
    return out


def inertial_regressor(chain: JointChain, q: np.ndarray, dq: np.ndarray, ddq: np.ndarray,
                       gravity: np.ndarray) -> np.ndarray:
    r"""The Newton–Euler regressor Y (N, n, 10n): ``τ = Y π`` for the standard parameters π (10n,).

    Parameters
    ----------
    chain : JointChain
        The arm's geometry (:func:`robokit.calibration.chain_from_robot`).
    q, dq, ddq : ndarray, shape (N, n)
        Joint positions (rad, m), velocities, accelerations.
    gravity : ndarray, shape (3,)
        Gravity in the base frame (m/s²), e.g. ``robot.gravity``.

    Returns
    -------
    ndarray, shape (N, n, 10n)
        Columns per link as in the module docstring (joint-frame parameters about the joint
        origin, Pinocchio's order); equal to ``pinocchio.computeJointTorqueRegressor``.
        Computed by the compiled kernel :func:`robokit.kernels.regressor.inertial_regressor`.

    Examples
    --------
    >>> import numpy as np, robokit
    >>> from robokit.calibration import chain_from_robot, inertial_regressor, standard_parameters
    >>> robot = robokit.load("rrr")
    >>> q = np.full((1, 3), 0.3)
    >>> Y = inertial_regressor(chain_from_robot(robot), q, q, q, robot.gravity)
    >>> bool(np.allclose(Y[0] @ standard_parameters(robot), robot.rnea(q[0], q[0], q[0])))
    True
    """
    args = kernel_arrays((chain.placements, chain.axes, q, dq, ddq, gravity), (3, 2, 2, 2, 2, 1))
    if args is not None:
        X, A, Q, dQ, ddQ, g = args
        n = A.shape[0]
        if (A.shape[1] == 6 and X.shape == (n + 1, 4, 4) and Q.shape[1] == n and dQ.shape == Q.shape
                and ddQ.shape == Q.shape and g.shape == (3,)):
            from robokit.kernels import regressor as kr

            kernel = kr.inertial_regressor
            if not getattr(kernel, "signatures", None) and hasattr(kernel, "signatures") and Q.shape[0]:
                # no machine code yet (a new process): one sample loads it from numba's cache or hands it
                # to the background compile; meanwhile a large batch runs in numpy, not as plain Python
                kernel(X, A, Q[:1], dQ[:1], ddQ[:1], g)
            if getattr(kernel, "signatures", None):  # (none under NUMBA_DISABLE_JIT: numpy below)
                return kernel(X, A, Q, dQ, ddQ, g)
    return _inertial_regressor_numpy(chain, q, dq, ddq, gravity)


def _inertial_regressor_numpy(chain: JointChain, q: np.ndarray, dq: np.ndarray, ddq: np.ndarray,
                              gravity: np.ndarray) -> np.ndarray:
    """:func:`inertial_regressor` in numpy over the batch (the same recursion; what the kernel replaced,
    kept as its reference and for arguments the kernel does not take)."""
    q, dq, ddq = (np.asarray(a, dtype=float) for a in (q, dq, ddq))
    N, n = q.shape
    T_back = np.empty((n, N, 4, 4))  # T_{i,i-1}
    K = np.empty((n, N, 6, 10))
    V = np.zeros((N, 6))
    dV = np.zeros((N, 6))
    dV[:, 3:] = -np.asarray(gravity, dtype=float)
    E = screw_exponentials(np.ascontiguousarray(chain.axes.T), q)  # (N, n, 4, 4): e^{[A_i]q_i}, the kernel's
    for i in range(n):
        A = chain.axes[i]
        T = chain.placements[i] @ E[:, i]  # T_{i-1,i}
        Ti = lie.inv(T)
        T_back[i] = Ti
        Ad = lie.adjoint(Ti)
        V = (Ad @ V[:, :, None])[:, :, 0] + A[None, :] * dq[:, i:i + 1]
        adV = lie.ad(V)
        dV = (Ad @ dV[:, :, None])[:, :, 0] + (adV @ A) * dq[:, i:i + 1] + A[None, :] * ddq[:, i:i + 1]
        K[i] = _phi(dV) - np.swapaxes(adV, 1, 2) @ _phi(V)
    Y = np.zeros((N, n, 10 * n))
    AdT_t = np.swapaxes(lie.adjoint(T_back), -1, -2)  # Ad_{T_{i,i-1}}ᵀ
    for i in range(n):
        U = K[i]
        for j in range(i, -1, -1):
            Y[:, j, 10 * i:10 * i + 10] = chain.axes[j] @ U
            if j > 0:
                U = AdT_t[j] @ U  # Ad_{T_{j,j-1}}ᵀ U
    return Y


def friction_regressor(dq: np.ndarray) -> np.ndarray:
    """Friction columns (N, n, 2n): ``τ_f,j = f_v,j q̇ⱼ + f_c,j sign(q̇ⱼ)``; parameters ordered
    ``(f_v,1, f_c,1, f_v,2, f_c,2, …)`` (N·m·s/rad and N·m, or N·s/m and N).

    Parameters
    ----------
    dq : ndarray, shape (N, n)
        Joint velocities.

    Returns
    -------
    ndarray, shape (N, n, 2n)

    Examples
    --------
    >>> import numpy as np
    >>> from robokit.calibration import friction_regressor
    >>> friction_regressor(np.array([[2.0, -1.0]]))[0]
    array([[ 2.,  1.,  0.,  0.],
           [ 0.,  0., -1., -1.]])
    """
    dq = np.asarray(dq, dtype=float)
    N, n = dq.shape
    out = np.zeros((N, n, 2 * n))
    j = np.arange(n)
    out[:, j, 2 * j] = dq
    out[:, j, 2 * j + 1] = np.sign(dq)
    return out


def standard_parameters(robot: Robot) -> np.ndarray:
    """The robot's standard inertial parameters π (10n,) (see the module docstring: joint frames,
    about the joint origin, Pinocchio's order), from its Pinocchio model.

    Parameters
    ----------
    robot : Robot

    Returns
    -------
    ndarray, shape (10n,)

    Examples
    --------
    >>> import robokit
    >>> from robokit.calibration import standard_parameters
    >>> float(standard_parameters(robokit.load("puma560"))[10])   # m₂ (kg)
    17.4
    """
    return np.concatenate([robot.model.inertias[j].toDynamicParameters() for j in range(1, robot.n + 1)])


def standard_parameter_names(n: int, friction: bool = True) -> list[str]:
    """Names of the standard parameters of an n-joint arm (``m3``, ``m3·c3x``, ``I3xx`` …, then
    ``fv3``, ``fc3`` with friction); link i's quantities are in joint i's frame.

    Parameters
    ----------
    n : int
        Number of joints.
    friction : bool
        Append the 2n friction parameters.

    Returns
    -------
    list of str

    Examples
    --------
    >>> from robokit.calibration import standard_parameter_names
    >>> standard_parameter_names(1)
    ['m1', 'm1·c1x', 'm1·c1y', 'm1·c1z', 'I1xx', 'I1xy', 'I1yy', 'I1xz', 'I1yz', 'I1zz', 'fv1', 'fc1']
    """
    names = []
    for i in range(1, n + 1):
        names += [f"m{i}", f"m{i}·c{i}x", f"m{i}·c{i}y", f"m{i}·c{i}z", f"I{i}xx", f"I{i}xy", f"I{i}yy",
                  f"I{i}xz", f"I{i}yz", f"I{i}zz"]
    if friction:
        for i in range(1, n + 1):
            names += [f"fv{i}", f"fc{i}"]
    return names


def _fmt(c: float) -> str:
    r = round(c)
    return f"{int(r)}" if abs(c - r) < 1e-9 else f"{c:.4g}"


@dataclass(frozen=True)
class BaseParameters:
    """The base-parameter structure of an arm (see the module docstring).

    Attributes
    ----------
    independent : ndarray of int, shape (r,)
        Columns of the full regressor (inertial then friction, see
        :func:`standard_parameter_names`) kept: ``Y_b = Y[:, :, independent]``.
    dependent : ndarray of int
        The other columns.
    beta : ndarray, shape (r, len(dependent))
        ``Y[:, :, dependent] = Y_b β``; base parameters ``π_b = π[independent] + β π[dependent]``.
    names : list of str
        The standard parameters' names.
    """

    independent: np.ndarray
    dependent: np.ndarray
    beta: np.ndarray
    names: list

    @property
    def count(self) -> int:
        """Number of base parameters r."""
        return int(self.independent.size)

    @property
    def matrix(self) -> np.ndarray:
        """C (r, p): ``π_b = C π`` for the full parameter vector π (inertial and friction)."""
        C = np.zeros((self.count, len(self.names)))
        C[np.arange(self.count), self.independent] = 1.0
        C[:, self.dependent] = self.beta
        return C

    def of(self, pi: np.ndarray) -> np.ndarray:
        """Base parameters ``π_b = C π = π[independent] + β π[dependent]`` of a full parameter vector.

        Parameters
        ----------
        pi : numpy.ndarray, shape (p,)
            Full parameter vector: the 10 inertial parameters per link, then the friction ones
            (:func:`standard_parameter_names`).

        Returns
        -------
        numpy.ndarray, shape (r,)
            The base parameters; ``Y[:, :, independent] @ π_b`` equals ``Y @ π`` for every motion.

        Examples
        --------
        >>> robot = rk.load("twolink")
        >>> bp = base_parameters(robot)
        >>> q = np.random.default_rng(0).normal(size=(5, 2))
        >>> Y = full_regressor(chain_from_robot(robot), q, q, q, robot.gravity)
        >>> pi = np.r_[standard_parameters(robot), np.full(4, 0.1)]
        >>> np.allclose(Y[:, :, bp.independent] @ bp.of(pi), Y @ pi)
        True
        """
        return self.matrix @ np.asarray(pi, dtype=float)

    def meaning(self) -> list[str]:
        """Each base parameter as a combination of standard ones.

        Returns
        -------
        list of str
            One string per base parameter, e.g. ``"I2xx + 0.432·m3·c3y + …"`` (names of
            :func:`standard_parameter_names`; coefficients in SI units).

        Examples
        --------
        For the planar arm with a 1 m first link, joint 1 only ever sees ``I1zz + m2·l1²``:

        >>> base_parameters(rk.load("twolink")).meaning()[:3]
        ['m1·c1x + m2', 'm1·c1y', 'I1zz + m2']
        """
        out = []
        for k, col in enumerate(self.independent):
            terms = [self.names[col]]
            for j, dep in enumerate(self.dependent):
                c = self.beta[k, j]
                if abs(c) > 1e-9:
                    sign = "−" if c < 0 else "+"
                    mag = abs(c)
                    terms.append(f"{sign} {self.names[dep]}" if abs(mag - 1) < 1e-9 else
                                 f"{sign} {_fmt(mag)}·{self.names[dep]}")
            out.append(" ".join(terms))
        return out


def base_parameters(robot: Robot, samples: int | None = None, rng: int | np.random.Generator | None = 0,
                    friction: bool = True) -> BaseParameters:
    """The base parameters of a robot's Newton–Euler (+ friction) model, by QR with column pivoting.

    Parameters
    ----------
    robot : Robot
        The arm (geometry and gravity; its inertias do not matter).
    samples : int, optional
        Random motions (q inside the limits, q̇, q̈ ~ N(0, 1)) stacked (default: enough for the
        10n + 2n columns three times over).
    rng : int or numpy.random.Generator or None
        Seed of the random motions (the structure does not depend on it).
    friction : bool
        Include the friction columns.

    Returns
    -------
    BaseParameters
        Which columns are independent, and the combinations β of the others.

    Examples
    --------
    >>> import robokit
    >>> from robokit.calibration import base_parameters
    >>> bp = base_parameters(robokit.load("puma560"))
    >>> bp.count
    48
    """
    import scipy.linalg

    rng = np.random.default_rng(rng)
    n = robot.n
    p = 10 * n + (2 * n if friction else 0)
    N = samples if samples is not None else max(3 * p // n + 10, 30)
    chain = chain_from_robot(robot)
    q = np.array([robot.random_configuration(rng) for _ in range(N)])
    dq, ddq = rng.standard_normal((N, n)), rng.standard_normal((N, n))
    W = full_regressor(chain, q, dq, ddq, robot.gravity, friction).reshape(N * n, p)
    norms = np.linalg.norm(W, axis=0)
    big = norms.max()
    zero = norms <= 1e-10 * big
    scale = np.where(zero, 1.0, norms)
    Ws = np.where(zero, 0.0, W / scale)
    _, R, piv = scipy.linalg.qr(Ws, mode="economic", pivoting=True)
    d = np.abs(np.diag(R))
    r = int(np.sum(d > BASE_TOL * d[0]))
    # which r columns: the first independent ones in the standard order (Gram–Schmidt, link 1 first),
    # so a later link's parameters are regrouped into earlier ones and the choice does not depend
    # on the random samples; the pivoted choice if round-off makes the two disagree
    kept: list[int] = []
    basis = np.zeros((Ws.shape[0], 0))
    for j in range(p):
        v = Ws[:, j]
        if zero[j]:
            continue
        for _ in range(2):
            v = v - basis @ (basis.T @ v)
        if np.linalg.norm(v) > 1e-6:
            kept.append(j)
            basis = np.column_stack([basis, v / np.linalg.norm(v)])
    ind = np.array(kept) if len(kept) == r else np.sort(piv[:r])
    dep = np.setdiff1d(np.arange(p), ind)
    beta, *_ = np.linalg.lstsq(W[:, ind], W[:, dep], rcond=None)
    beta[np.abs(beta) < 1e-10] = 0.0
    return BaseParameters(ind, dep, beta, standard_parameter_names(n, friction))


def full_regressor(chain: JointChain, q: np.ndarray, dq: np.ndarray, ddq: np.ndarray, gravity: np.ndarray,
                   friction: bool = True) -> np.ndarray:
    """Inertial and friction regressor side by side: ``τ = Y [π; f]``.

    :func:`inertial_regressor` (10 standard parameters per link) followed by
    :func:`friction_regressor` (viscous and Coulomb per joint).

    Parameters
    ----------
    chain : JointChain
        The arm's geometry (:func:`robokit.calibration.chain_from_robot`).
    q, dq, ddq : numpy.ndarray, shape (N, n)
        Joint positions (rad, m), velocities, accelerations.
    gravity : numpy.ndarray, shape (3,)
        Gravity in the base frame, m/s² (e.g. ``robot.gravity``).
    friction : bool, optional
        Append the friction columns (default True).

    Returns
    -------
    numpy.ndarray, shape (N, n, 12n) or (N, n, 10n) without friction
        Columns: the 10n inertial parameters (link by link), then ``(f_v,1, f_c,1, …)``.

    Examples
    --------
    With every viscous and Coulomb coefficient 0.5, the torque is Pinocchio's plus
    ``0.5 (q̇ + sign q̇)``:

    >>> robot = rk.load("rrr")
    >>> q = np.full((1, 3), 0.3)
    >>> Y = full_regressor(chain_from_robot(robot), q, q, q, robot.gravity)
    >>> Y.shape
    (1, 3, 36)
    >>> pi = np.r_[standard_parameters(robot), np.full(6, 0.5)]
    >>> np.allclose(Y[0] @ pi, robot.rnea(q[0], q[0], q[0]) + 0.5 * (q[0] + np.sign(q[0])))
    True
    """
    Y = inertial_regressor(chain, q, dq, ddq, gravity)
    if not friction:
        return Y
    return np.concatenate([Y, friction_regressor(dq)], axis=2)
