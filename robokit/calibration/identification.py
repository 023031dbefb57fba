r"""Dynamic identification: inertial and friction parameters from measured motions and torques.

``τ = Y_b(q, q̇, q̈) π_b`` (the base regressor of :mod:`robokit.calibration.regressor`: rigid-body
Newton–Euler plus viscous and Coulomb friction per joint) is solved for the base parameters by
weighted least squares, in two passes (Gautier's method): ordinary least squares, then each joint's
rows weighted by ``1/σⱼ`` with ``σⱼ² = ‖rⱼ‖² / (N − r/n)`` the variance of that joint's residual,
so that a noisy joint does not dominate a clean one.

Physical consistency. A set of standard parameters can be a real rigid body only if each link's
pseudo-inertia

.. math::

    J_i = \begin{pmatrix} Σ & h \\ hᵀ & m \end{pmatrix}, \quad Σ = \tfrac12 \mathrm{tr}(I)\,1 − I,
    \quad h = m c

(I about the joint origin) is positive semidefinite — which says m ≥ 0 and that the inertia about
the centre of mass has non-negative principal moments satisfying the triangle inequality
(Wensing, Kim & Slotine 2017). ``check_physical_consistency`` tests the set closest to the nominal
parameters that has the identified base parameters; with ``physically_consistent=True`` the
nearest consistent set is computed: each ``J_i = L_i L_iᵀ`` (L lower triangular, so J ⪰ 0 by
construction) and the weighted torque residual plus a small pull toward the nominal parameters
(1e-2 per parameter, relative to its size: it fixes the directions the data cannot see) is
minimised with ``scipy.optimize.least_squares``
— a constrained least squares by parametrisation, not a semidefinite program.

Velocities and accelerations from measured positions: :func:`joint_derivatives` — a zero-phase
Butterworth low-pass filter (``scipy.signal.filtfilt``: forward and backward, so no delay) and
second-order central differences (``numpy.gradient``).
"""
from __future__ import annotations

import math
import warnings
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import ArrayLike

from robokit._arrays import as_array, as_count
from robokit.calibration.chain import JointChain, chain_from_robot
from robokit.calibration.regressor import BaseParameters, base_parameters, full_regressor, standard_parameters
from robokit.errors import InputError, RobokitWarning

if TYPE_CHECKING:
    from robokit.description.robot import Robot

__all__ = ["identify_dynamics", "IdentificationResult", "check_physical_consistency", "joint_derivatives",
           "pseudo_inertia"]


#: Most function evaluations of the physically consistent fit (``max_evaluations``).
MAX_EVALUATIONS = 100_000
#: Largest regressor ``identify_dynamics`` builds (bytes): 2 GiB is 500,000 samples of a 6-joint arm
#: without friction, 400,000 with.
MAX_REGRESSOR_BYTES = 2 << 30

def pseudo_inertia(pi_link: ArrayLike) -> np.ndarray:
    """The 4×4 pseudo-inertia ``[[½tr(I)1 − I, m c], [(m c)ᵀ, m]]`` of one link's ten parameters.

    Parameters
    ----------
    pi_link : array_like, shape (10,)
        ``(m, m c_x, m c_y, m c_z, I_xx, I_xy, I_yy, I_xz, I_yz, I_zz)``, I about the frame origin.

    Returns
    -------
    ndarray, shape (4, 4)
        Positive semidefinite exactly when the parameters are those of a physical body.

    Examples
    --------
    >>> import numpy as np
    >>> from robokit.calibration import pseudo_inertia
    >>> J = pseudo_inertia([1.0, 0, 0, 0, 0.1, 0, 0.1, 0, 0, 0.1])
    >>> bool(np.all(np.linalg.eigvalsh(J) >= 0))
    True
    """
    p = np.asarray(pi_link, dtype=float)
    m, h = p[0], p[1:4]
    I = np.array([[p[4], p[5], p[7]], [p[5], p[6], p[8]], [p[7], p[8], p[9]]])
    J = np.empty((4, 4))
    J[:3, :3] = 0.5 * np.trace(I) * np.eye(3) - I
    J[:3, 3] = J[3, :3] = h
    J[3, 3] = m
    return J


def _params_from_pseudo(J: np.ndarray) -> np.ndarray:
    S, h, m = J[:3, :3], J[:3, 3], J[3, 3]
    I = np.trace(S) * np.eye(3) - S
    return np.array([m, h[0], h[1], h[2], I[0, 0], I[0, 1], I[1, 1], I[0, 2], I[1, 2], I[2, 2]])


def check_physical_consistency(pi: ArrayLike, tol: float = 0.0) -> list[str]:
    """What is physically impossible in a set of standard parameters: one line per problem.

    Parameters
    ----------
    pi : array_like, shape (10n,)
        Standard inertial parameters (no friction entries: ``standard_parameters[:10 * n]``).
    tol : float
        Tolerance on the conditions (kg, kg·m²).

    Returns
    -------
    list of str
        Empty when every link has a positive mass and an inertia about its centre of mass that is
        positive definite and satisfies the triangle inequality (each principal moment at most the
        sum of the other two); otherwise e.g. ``"link 3: mass -0.2 kg is not positive"``.

    Examples
    --------
    >>> from robokit.calibration import check_physical_consistency
    >>> check_physical_consistency([1.0, 0, 0, 0, 0.1, 0, 0.1, 0, 0, 0.3])
    ['link 1: principal moments [0.1, 0.1, 0.3] kg·m² break the triangle inequality']
    """
    p = np.asarray(pi, dtype=float)
    n = p.size // 10
    if p.ndim != 1 or p.size != 10 * n or n == 0:
        raise InputError(f"pi: expected 10n standard inertial parameters (shape (10n,)), got shape {p.shape}")
    out = []
    for i in range(n):
        q = p[10 * i:10 * i + 10]
        m = q[0]
        if m <= tol:
            out.append(f"link {i + 1}: mass {m:.4g} kg is not positive")
            continue
        c = q[1:4] / m
        I_O = np.array([[q[4], q[5], q[7]], [q[5], q[6], q[8]], [q[7], q[8], q[9]]])
        I_C = I_O - m * (c @ c * np.eye(3) - np.outer(c, c))
        lam = np.sort(np.linalg.eigvalsh(I_C))
        shown = "[" + ", ".join(f"{x:.4g}" for x in lam) + "]"
        rel = tol + 1e-12 * float(abs(lam).max())
        if lam[0] <= rel:
            out.append(f"link {i + 1}: inertia about the centre of mass is not positive definite "
                       f"(principal moments {shown} kg·m²)")
        elif lam[2] > lam[0] + lam[1] + rel:
            out.append(f"link {i + 1}: principal moments {shown} kg·m² break the triangle inequality")
    return out


@dataclass(frozen=True, eq=False)
class IdentificationResult:
    """Result of :func:`identify_dynamics`.

    Attributes
    ----------
    robot : Robot
        The robot whose model was identified (its geometry; its inertias are the nominal ones).
    base : BaseParameters
        The base-parameter structure (``base.meaning()`` — each as a combination of standard ones).
    base_parameters : ndarray, shape (r,)
        Identified base parameters (from the consistent set when ``physically_consistent``).
    base_parameters_ls : ndarray, shape (r,)
        The weighted least-squares estimate.
    standard_deviation : ndarray, shape (r,)
        Standard deviation of each least-squares base parameter, ``σ² diag((WᵀW)⁻¹)`` on the weighted
        problem.
    standard_parameters : ndarray, shape (12n,)
        One full set (inertial then friction, :func:`standard_parameter_names`) with these base
        parameters: the nearest to the nominal one, or the nearest physically consistent set.
    condition_number : float
        Condition number of the data's base regressor (σ_max/σ_min).
    weights : ndarray, shape (n,)
        Per-joint weights 1/σⱼ of the second pass.
    rms_residual : ndarray, shape (n,)
        Per-joint RMS of ``τ − Y_b π_b`` on the data (N·m or N).
    consistency : list of str
        :func:`check_physical_consistency` of ``standard_parameters`` (empty: consistent).
    method : str
        How ``standard_parameters`` was chosen.
    """

    robot: Any
    base: BaseParameters
    base_parameters: np.ndarray
    base_parameters_ls: np.ndarray
    standard_deviation: np.ndarray
    standard_parameters: np.ndarray
    condition_number: float
    weights: np.ndarray
    rms_residual: np.ndarray
    consistency: list
    method: str
    _chain: JointChain = field(repr=False)

    @property
    def friction(self) -> np.ndarray:
        """(n, 2) viscous and Coulomb friction per joint, from ``standard_parameters``."""
        n = self.robot.n
        return self.standard_parameters[10 * n:].reshape(n, 2)

    @property
    def physically_consistent(self) -> bool:
        """True when ``standard_parameters`` is a physical set (see ``consistency``)."""
        return not self.consistency

    def predict(self, q: ArrayLike, dq: ArrayLike, ddq: ArrayLike) -> np.ndarray:
        """Joint torques (N, n) of the identified model ``Y_b(q, q̇, q̈) π_b`` (rigid body + friction).

        Parameters
        ----------
        q, dq, ddq : array_like, shape (N, n) (or (n,))
            Joint positions, velocities, accelerations.

        Returns
        -------
        ndarray, shape (N, n) (or (n,))
            Joint torques (N·m, N).

        Examples
        --------
        Continuing :func:`identify_dynamics`'s example (``rrr`` with viscous friction 0.1):

        >>> robot = rk.load("rrr")
        >>> q, dq, ddq = np.random.default_rng(0).uniform(-1, 1, (3, 200, 3))
        >>> res = rk.identify_dynamics(robot, q, dq, ddq, robot.rnea_batch(q, dq, ddq) + 0.1 * dq)
        >>> bool(np.allclose(res.predict(q[0], dq[0], ddq[0]), robot.rnea(q[0], dq[0], ddq[0]) + 0.1 * dq[0]))
        True
        """
        n = self.robot.n
        one = np.ndim(q) == 1
        arrs = [_samples(a, name, n) for a, name in ((q, "q"), (dq, "dq"), (ddq, "ddq"))]
        N = arrs[0].shape[0]
        if any(a.shape[0] != N for a in arrs):
            raise InputError(f"q, dq, ddq: expected the same number of rows, got {[a.shape[0] for a in arrs]}")
        W = full_regressor(self._chain, arrs[0], arrs[1], arrs[2], self.robot.gravity,
                           self.base.count > 0 and len(self.base.names) == 12 * n)[:, :, self.base.independent]
        tau = W @ self.base_parameters
        return tau[0] if one else tau

    def to_robot(self, name: str | None = None) -> Any:
        """A :class:`robokit.Robot` with the robot's geometry and ``standard_parameters``' inertias.

        Its rigid-body dynamics (``rnea``, ``crba``, …) equal this model without friction:
        ``to_robot().rnea(q, dq, ddq) + friction = predict(q, dq, ddq)`` — for computed-torque control
        with the identified model. Use ``physically_consistent=True`` when its forward dynamics
        (``aba``) are needed: a non-physical set can make the mass matrix indefinite.

        Parameters
        ----------
        name : str, optional
            Name of the new robot (default ``robot.name + "_identified"``).

        Returns
        -------
        Robot
            The same geometry with the identified inertias.

        Raises
        ------
        InputError
            A link whose identified set no rigid body can carry (a first moment with zero mass).

        Examples
        --------
        >>> robot = rk.load("rrr")
        >>> q, dq, ddq = np.random.default_rng(0).uniform(-1, 1, (3, 200, 3))
        >>> res = rk.identify_dynamics(robot, q, dq, ddq, robot.rnea_batch(q, dq, ddq) + 0.1 * dq)
        >>> twin = res.to_robot()
        >>> twin.name, bool(np.allclose(twin.rnea(q[0], dq[0], ddq[0]) + 0.1 * dq[0], robot.rnea(q[0], dq[0], ddq[0]) + 0.1 * dq[0]))
        ('rrr_identified', True)
        """
        import pinocchio as pin

        from robokit.description.robot import Robot

        n = self.robot.n
        model = pin.Model(self.robot.model)
        scale = max(float(np.abs(self.standard_parameters[:10 * n]).max()), 1e-300)
        for j in range(n):
            model.inertias[j + 1] = _link_inertia(self.standard_parameters[10 * j:10 * j + 10], j + 1, scale)
        return Robot(name or f"{self.robot.name}_identified", model, self.robot.tip,
                     source=f"identified from {self.robot.source or self.robot.name}")

    def table(self) -> str:
        """The base parameters, one per line: value, relative standard deviation, meaning.

        Returns
        -------
        str
            A header line, then one line per base parameter (value in SI units, σ in % of it, the
            combination of standard parameters it stands for).

        Examples
        --------
        >>> robot = rk.load("rrr")
        >>> q, dq, ddq = np.random.default_rng(0).uniform(-1, 1, (3, 200, 3))
        >>> res = rk.identify_dynamics(robot, q, dq, ddq, robot.rnea_batch(q, dq, ddq) + 0.1 * dq)
        >>> print(res.table().splitlines()[1])
                0.85   ...  m1·c1x + 0.5·m2 + 0.5·m3
        """
        lines = [f"{'value':>12} {'σ %':>7}  base parameter (standard parameters in joint frames, about the "
                 "joint origin)"]
        for v, s, meaning in zip(self.base_parameters, self.standard_deviation, self.base.meaning()):
            rel = 100 * s / abs(v) if v != 0 else math.inf
            lines.append(f"{v:12.5g} {rel:7.2g}  {meaning}")
        return "\n".join(lines)

    def __str__(self) -> str:
        status = "physically consistent" if not self.consistency else "; ".join(self.consistency)
        return (f"identified {self.base.count} base parameters of {self.robot.name}; condition number "
                f"{self.condition_number:.3g}; RMS torque residual per joint "
                f"{np.array2string(self.rms_residual, precision=3)}; {status}\n{self.table()}")


def _samples(a: ArrayLike, name: str, n: int) -> np.ndarray:
    arr = as_array(a, name, bounded=True)
    if arr.ndim == 1:
        arr = arr[None, :]
    if arr.ndim != 2 or arr.shape[1] != n:
        raise InputError(f"{name}: expected shape (N, {n}), got {np.shape(a)}")
    return arr


def _nearest_with_base(C: np.ndarray, pi_b: np.ndarray, pi_nom: np.ndarray) -> np.ndarray:
    """The π closest to π_nom (Euclidean) with C π = π_b.

    Only the parameters some base parameter involves (the non-zero columns of C) move: the others
    (e.g. the mass of a first link turning about a fixed vertical axis) keep their nominal values
    exactly. Solving over every column gives those the same answer in exact arithmetic, but in
    floating point a least-squares solver leaves round-off there (±1e-17; its exact value follows the
    BLAS code path taken, which can change from one process to the next — e.g. with the alignment of
    the solver's work buffers — so the result was run-dependent), enough to turn a nominal mass of 0
    into −2e-19 kg or leave a first moment of 1e-17 over a mass of 0: a centre of mass h/m = ±inf.
    """
    seen = np.any(C != 0.0, axis=0)
    out = np.array(pi_nom, dtype=float)
    if seen.any():
        d, *_ = np.linalg.lstsq(C[:, seen], pi_b - C @ pi_nom, rcond=None)
        out[seen] += d
    return out


def _link_inertia(p: np.ndarray, link: int, scale: float) -> Any:
    """A Pinocchio inertia with one link's ten standard parameters (I about the joint origin).

    Pinocchio stores (m, c, I_C), so ``c = h/m`` and ``I_C = I_O − m([c]ᵀ[c])``: a link with m = 0 and
    h = 0 (a massless link with a rotational inertia, as in Corke's PUMA 560) is kept as such; a set
    that (m, c, I_C) cannot carry to 1e-9 of the arm's parameter scale (m = 0 with h ≠ 0, or a mass
    so small that c is enormous) is refused, naming the link.
    """
    import pinocchio as pin

    m, h = float(p[0]), np.asarray(p[1:4], dtype=float)
    I_O = np.array([[p[4], p[5], p[7]], [p[5], p[6], p[8]], [p[7], p[8], p[9]]], dtype=float)
    Y = None
    if m != 0.0 or not h.any():  # set field by field: Pinocchio's constructor refuses a non-physical I_C
        c = h / m if m != 0.0 else np.zeros(3)
        Y = pin.Inertia.Zero()
        Y.mass, Y.lever = m, c
        Y.inertia = I_O - m * (float(c @ c) * np.eye(3) - np.outer(c, c))
    if Y is None or not np.all(np.abs(np.asarray(Y.toDynamicParameters()) - p) <= 1e-9 * scale):
        raise InputError(f"to_robot: link {link}'s identified parameters (mass {m:.3g} kg, first moment "
                         f"{np.array2string(h, precision=3)} kg·m) are not those of a rigid body a Robot can "
                         "carry (a first moment without mass); identify with physically_consistent=True")
    return Y


def _consistent_fit(Ww: np.ndarray, tw: np.ndarray, C: np.ndarray, pi0: np.ndarray, pi_nom: np.ndarray,
                    n: int, pull: float, max_evaluations: int) -> np.ndarray:
    """Nearest physically consistent standard set: J_i = L_i L_iᵀ, friction free (see the module docstring)."""
    from scipy.optimize import least_squares

    tri = np.tril_indices(4)
    x0 = []
    for i in range(n):
        J = pseudo_inertia(pi0[10 * i:10 * i + 10])
        w, V = np.linalg.eigh(J)
        floor = 1e-6 * max(float(np.abs(w).max()), 1e-6)
        J = (V * np.maximum(w, floor)) @ V.T
        x0.append(np.linalg.cholesky(J)[tri])
    x0.append(pi0[10 * n:])
    x = np.concatenate(x0)
    Wb = Ww @ C  # weighted full regressor (through the base parameters): rows of unit noise variance
    # the pull toward the nominal parameters, relative to each parameter's size (a floor per kind:
    # masses, first moments, inertias, friction), so that it only decides what the data cannot
    kinds = [np.r_[[10 * i for i in range(n)]], np.r_[[10 * i + k for i in range(n) for k in (1, 2, 3)]],
             np.r_[[10 * i + k for i in range(n) for k in range(4, 10)]], np.arange(10 * n, pi_nom.size)]
    size = np.abs(pi_nom).astype(float)
    for idx in kinds:
        if idx.size:
            floor = 1e-2 * float(np.abs(pi_nom[idx]).mean()) or 1e-2
            size[idx] = np.maximum(size[idx], floor)
    reg = pull / size
    eps = 1e-9 * max(float(np.abs(pi_nom[:10 * n]).max()), 1e-9)  # keeps J ≻ 0, off the boundary

    def params(x: np.ndarray) -> np.ndarray:
        out = np.empty(12 * n)
        for i in range(n):
            L = np.zeros((4, 4))
            L[tri] = x[10 * i:10 * i + 10]
            out[10 * i:10 * i + 10] = _params_from_pseudo(L @ L.T + eps * np.eye(4))
        out[10 * n:] = x[10 * n:]
        return out

    def fun(x: np.ndarray) -> np.ndarray:
        p = params(x)
        return np.concatenate([Wb @ p - tw, reg * (p - pi_nom)])

    def jac(x: np.ndarray) -> np.ndarray:
        # J = L Lᵀ + ε1 and π(J) is linear: ∂π/∂L_ab = π(E_ab Lᵀ + L E_ba)
        dp = np.zeros((12 * n, x.size))
        for i in range(n):
            L = np.zeros((4, 4))
            L[tri] = x[10 * i:10 * i + 10]
            for k, (a, b) in enumerate(zip(*tri)):
                dJ = np.zeros((4, 4))
                dJ[a, :] += L[:, b]
                dJ[:, a] += L[:, b]
                dp[10 * i:10 * i + 10, 10 * i + k] = _params_from_pseudo(dJ)
        dp[10 * n:, 10 * n:] = np.eye(x.size - 10 * n)
        return np.vstack([Wb @ dp, reg[:, None] * dp])

    sol = least_squares(fun, x, jac=jac, method="trf", max_nfev=max_evaluations, x_scale="jac")
    return params(sol.x)


def identify_dynamics(robot: Robot | str, q: ArrayLike, dq: ArrayLike, ddq: ArrayLike, tau: ArrayLike, *,
                      friction: bool = True, physically_consistent: bool = False,
                      nominal: ArrayLike | None = None, max_evaluations: int = 200) -> IdentificationResult:
    r"""Identify a robot's base inertial parameters and joint friction from measured motions and torques.

    Model: ``τ = Y(q, q̇, q̈) π + f_v q̇ + f_c sign(q̇)`` — the course's Newton–Euler written linear in
    the ten standard parameters of each link (joint frames, about the joint origin; see
    :mod:`robokit.calibration.regressor`), reduced to the base parameters by QR with column
    pivoting, solved by two-pass weighted least squares.

    Parameters
    ----------
    robot : Robot or str
        The arm (its geometry is used; its inertias are the nominal values the unidentifiable
        directions keep).
    q, dq, ddq : array_like, shape (N, n)
        Joint positions (rad, m), velocities (rad/s, m/s), accelerations (rad/s², m/s²) — e.g. from
        :func:`joint_derivatives` of measured positions.
    tau : array_like, shape (N, n)
        Measured joint torques (N·m) or forces (N).
    friction : bool
        Identify viscous and Coulomb friction per joint (default True).
    physically_consistent : bool
        Replace the least-squares estimate by the nearest physically consistent set (pseudo-inertias
        L Lᵀ ⪰ 0, ``scipy.optimize.least_squares``); its base parameters are then the result's.
    nominal : array_like, shape (10n,) or (12n,), optional
        Nominal standard parameters (default: the robot's, friction zero).
    max_evaluations : int
        Function evaluations at most of the consistent fit (1 to :data:`MAX_EVALUATIONS`).

    Returns
    -------
    IdentificationResult
        ``.predict(q, dq, ddq)`` (N, n), ``.base_parameters``, ``.base.meaning()``,
        ``.condition_number``, ``.consistency``, ``.standard_parameters``, ``.friction``.

    Raises
    ------
    InputError
        Wrong shapes, NaN, a value beyond 1e12 in magnitude (bounded like every number of a robot
        file), fewer torque equations than base parameters, a regressor larger than
        :data:`MAX_REGRESSOR_BYTES`, ``max_evaluations`` not a count in 1..100,000.

    Examples
    --------
    >>> import numpy as np, robokit
    >>> robot = robokit.load("rrr")
    >>> rng = np.random.default_rng(0)
    >>> q, dq, ddq = rng.uniform(-1, 1, (3, 200, 3))
    >>> tau = robot.rnea_batch(q, dq, ddq) + 0.1 * dq
    >>> res = robokit.identify_dynamics(robot, q, dq, ddq, tau)
    >>> bool(np.allclose(res.predict(q, dq, ddq), tau))
    True
    """
    from robokit.description import load

    robot = load(robot)
    n = robot.n
    max_evaluations = as_count(max_evaluations, "max_evaluations", 1, MAX_EVALUATIONS)
    Q, dQ, ddQ, T = (_samples(a, name, n) for a, name in ((q, "q"), (dq, "dq"), (ddq, "ddq"), (tau, "tau")))
    N = Q.shape[0]
    if any(a.shape[0] != N for a in (dQ, ddQ, T)):
        raise InputError(f"q, dq, ddq, tau: expected the same number of rows, got "
                         f"{[a.shape[0] for a in (Q, dQ, ddQ, T)]}")
    need = 8 * N * n * (12 * n if friction else 10 * n)  # the regressor W (N, n, p), float64
    if need > MAX_REGRESSOR_BYTES:
        raise InputError(f"q: {N} samples make a regressor of {need / 2**30:.1f} GiB for {robot.name}; robokit builds "
                         f"at most {MAX_REGRESSOR_BYTES / 2**30:.0f} GiB (use every k-th sample)")
    base = base_parameters(robot, friction=friction)
    r = base.count
    if N * n < r + n:
        raise InputError(f"q: {N} samples give {N * n} torque equations for {r} base parameters of {robot.name}; "
                         f"at least {-(-(r + n) // n)} samples are needed (many more for a good fit)")
    chain = chain_from_robot(robot)
    p = 12 * n if friction else 10 * n
    pi_nom = np.zeros(p)
    pi_nom[:10 * n] = standard_parameters(robot)
    if nominal is not None:
        nom = as_array(nominal, "nominal", bounded=True)
        if nom.shape not in ((10 * n,), (p,)):
            raise InputError(f"nominal: expected shape ({10 * n},) or ({p},), got {nom.shape}")
        pi_nom[:nom.size] = nom
    Wfull = full_regressor(chain, Q, dQ, ddQ, robot.gravity, friction)  # (N, n, p)
    Wb = Wfull[:, :, base.independent]
    sv = np.linalg.svd(Wb.reshape(N * n, r), compute_uv=False)
    cond = float(sv[0] / sv[-1]) if sv[-1] > 0 else math.inf
    if not sv[-1] > 1e-10 * sv[0]:
        import scipy.linalg

        Wn = Wb.reshape(N * n, r)
        norms = np.linalg.norm(Wn, axis=0)
        _, R, piv = scipy.linalg.qr(Wn / np.where(norms > 0, norms, 1.0), mode="economic", pivoting=True)
        d = np.abs(np.diag(R))
        weak = [base.meaning()[k] for k in piv[int(np.sum(d > 1e-10 * d[0])):]]
        warnings.warn(f"identify_dynamics: the data do not excite {len(weak)} base parameter(s) of {robot.name} "
                      f"(e.g. {weak[0]}); they stay at the least-norm solution — move every joint, in both "
                      "directions, with varied speeds (see excitation_trajectory)", RobokitWarning, stacklevel=2)
    # pass 1: ordinary least squares; pass 2: rows of joint j weighted by 1/σ_j
    pb, *_ = np.linalg.lstsq(Wb.reshape(N * n, r), T.reshape(-1), rcond=None)
    resid = T - Wb @ pb
    dof = max(N - r / n, 1.0)
    sigma = np.sqrt(np.sum(resid**2, axis=0) / dof)
    floor = max(1e-12 * float(sigma.max()), 1e-300)
    sigma = np.maximum(sigma, floor)
    w = 1.0 / sigma
    Ww = (Wb * w[None, :, None]).reshape(N * n, r)
    tw = (T * w[None, :]).reshape(-1)
    pb, *_ = np.linalg.lstsq(Ww, tw, rcond=None)
    rw = tw - Ww @ pb
    s2 = float(rw @ rw) / max(N * n - r, 1)
    try:
        cov = s2 * np.linalg.inv(Ww.T @ Ww)
        std = np.sqrt(np.maximum(np.diag(cov), 0.0))
    except np.linalg.LinAlgError:
        std = np.full(r, np.inf)
    C = base.matrix
    pi_std = _nearest_with_base(C, pb, pi_nom)
    method = "least squares; the standard set nearest the nominal one with these base parameters"
    pb_used = pb
    if physically_consistent:
        # ‖Ww π_b − tw‖² = ‖R π_b − Qᵀtw‖² + const (Ww = QR): the fit works on r rows, not N·n
        Qw, Rw = np.linalg.qr(Ww)
        pi_std = _consistent_fit(Rw, Qw.T @ tw, C, pi_std, pi_nom, n, 1e-2, max_evaluations)
        pb_used = C @ pi_std
        method = ("nearest physically consistent set: pseudo-inertias L Lᵀ, weighted torque residual + a 1e-2 "
                  "relative pull to the nominal parameters, scipy.optimize.least_squares")
    if not friction:
        pi_std = np.concatenate([pi_std, np.zeros(2 * n)])
    rms = np.sqrt(np.mean((T - Wb @ pb_used) ** 2, axis=0))
    return IdentificationResult(robot, base, pb_used, pb, std, pi_std, cond, w, rms,
                                check_physical_consistency(pi_std[:10 * n]), method, chain)


def joint_derivatives(t: ArrayLike, q: ArrayLike, cutoff: float, order: int = 4) -> tuple[np.ndarray, np.ndarray,
                                                                                            np.ndarray]:
    r"""Filtered positions, velocities and accelerations from measured joint positions.

    A zero-phase Butterworth low-pass filter of ``order`` and ``cutoff`` (Hz), applied forward and
    backward (``scipy.signal.filtfilt``: no phase lag, effective order doubled; the signal is extended
    at both ends by odd reflection over ``2·order/cutoff`` seconds), then second-order
    central differences ``q̇ₖ ≈ (q_{k+1} − q_{k−1}) / 2Δt`` (one-sided at the ends), twice.

    Parameters
    ----------
    t : array_like, shape (N,)
        Sample times (s), uniformly spaced.
    q : array_like, shape (N, n)
        Measured joint positions (rad, m).
    cutoff : float
        Cut-off frequency (Hz), below the Nyquist frequency ``1 / (2Δt)``; choose it a few times
        above the highest frequency of the motion (an excitation trajectory's top harmonic).
    order : int
        Butterworth order.

    Returns
    -------
    q_f, dq, ddq : ndarray, shape (N, n)
        Filtered positions, velocities, accelerations. About ``order/cutoff`` seconds at each end
        carry the filter's edge transients: drop them (or measure a periodic trajectory for one
        period more than you use).

    Examples
    --------
    >>> import numpy as np
    >>> from robokit.calibration import joint_derivatives
    >>> t = np.linspace(0, 2, 401)
    >>> q = np.sin(np.pi * t)[:, None]
    >>> _, dq, _ = joint_derivatives(t, q, cutoff=10.0)
    >>> bool(abs(dq[200, 0] - np.pi * np.cos(np.pi * t[200])) < 1e-3)
    True
    """
    from scipy.signal import butter, filtfilt

    tt = as_array(t, "t", (None,), bounded=True)
    Q = as_array(q, "q", bounded=True)
    if Q.ndim == 1:
        Q = Q[:, None]
    if Q.ndim != 2 or Q.shape[0] != tt.size:
        raise InputError(f"q: expected shape ({tt.size}, n) for {tt.size} times, got {np.shape(q)}")
    if tt.size < 3:
        raise InputError(f"t: expected at least 3 samples, got {tt.size}")
    dt = np.diff(tt)
    if np.any(dt <= 0) or np.abs(dt - dt.mean()).max() > 1e-6 * dt.mean():
        raise InputError("t: expected uniformly spaced, increasing times")
    h = float(dt.mean())
    nyq = 0.5 / h
    if not (isinstance(cutoff, (int, float, np.floating, np.integer)) and not isinstance(cutoff, bool)
            and 0 < cutoff < nyq):
        raise InputError(f"cutoff: expected a frequency in (0, {nyq:g}) Hz (the Nyquist frequency), got {cutoff!r}")
    if not (isinstance(order, int) and 1 <= order <= 10):
        raise InputError(f"order: expected an integer in 1..10, got {order!r}")
    b, a = butter(order, cutoff, fs=1.0 / h)
    pad = 3 * max(len(a), len(b))
    if tt.size <= pad:
        raise InputError(f"t: expected more than {pad} samples for an order-{order} filter, got {tt.size}")
    # odd extension at both ends over about two time constants of the filter (2·order/cutoff s)
    padlen = min(tt.size - 1, max(pad, int(round(2 * order / (cutoff * h)))))
    qf = filtfilt(b, a, Q, axis=0, padlen=padlen)
    dq = np.gradient(qf, h, axis=0, edge_order=2)
    ddq = np.gradient(dq, h, axis=0, edge_order=2)
    return qf, dq, ddq
