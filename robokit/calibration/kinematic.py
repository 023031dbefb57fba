r"""Kinematic calibration: the arm's geometry fitted to measured tool poses or positions.

Error model (per-joint SE(3) errors on the joint-placement form of the product of exponentials,
:mod:`robokit.calibration.chain`):

.. math::

    T(q; δ) = X_1 e^{[δ_1]} e^{[A_1] q_1} \; X_2 e^{[δ_2]} e^{[A_2] q_2} \cdots
              X_n e^{[δ_n]} e^{[A_n] q_n}\; X_{n+1} e^{[δ_{n+1}]}

Each δᵢ ∈ ℝ⁶ (angular first, in the frame the placement ends in) is a complete small error of
one rigid transform, so *every* small geometric error is representable: a joint axis displaced or
tilted in any direction (two nominally parallel axes tilted toward each other included — the
case where DH parameters jump, the "DH discontinuity"), joint offsets (δᵢ's rotation about a
revolute axis), the base transform (δ₁) and the tool transform (δ_{n+1}).

The 6(n+1) parameters are redundant: a rotation about a revolute joint's axis and a translation
along it commute with the joint's motion and act like an error of the next placement (four such
directions for a prismatic joint). The identifiable combinations are found from the data by QR
with column pivoting of the column-scaled identification Jacobian (Okamura & Park 1996 count
4R + 2P + 6 of them for pose data; with positions only, the three tool rotations drop out); the
others stay nominal and are reported in words.

Identification Jacobian. With ``Pᵢ(q)`` the pose in the base frame of the frame δᵢ acts in
(``X_1 e^{[A_1]q_1} ⋯ X_i``; the tool frame for δ_{n+1}), a change δᵢ moves the tool by the
spatial twist ``Ad_{Pᵢ} δᵢ``; in the measured quantities (rotation error ω in base axes, tool
position p)

.. math::

    \begin{pmatrix} ω \\ Δp \end{pmatrix} = \begin{pmatrix} 1 & 0 \\ -[p] & 1 \end{pmatrix}
    \mathrm{Ad}_{P_i}\, δ_i .

Levenberg–Marquardt (Marquardt's scaling) on the residual
``r = (log(R_meas R_predᵀ), p_meas − p_pred)`` (positions only: the last three rows), each step
absorbed into the placements (``Xᵢ ← Xᵢ e^{[δᵢ]}``) and the Jacobian re-linearised there.
"""
from __future__ import annotations

import math
import warnings
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import ArrayLike

from robokit._optional import require
from robokit._arrays import as_array, as_count, as_scalar
from robokit.calibration.chain import JointChain, chain_from_robot, robot_from_chain
from robokit.errors import InputError, RobokitWarning
from robokit.spatial import lie

if TYPE_CHECKING:
    from robokit.description.robot import Robot

__all__ = ["calibrate", "CalibrationResult", "Identifiability", "RMS", "identification_jacobian",
           "pose_residuals", "parameter_names"]

_COMPONENTS = ("rx", "ry", "rz", "tx", "ty", "tz")
#: Relative size (of the largest pivot of the column-scaled Jacobian) below which a direction is
#: taken as not identified by the data.
RANK_TOL = 1e-8


class RMS(float):
    """A root-mean-square error: the float is the position RMS (m); ``.orientation`` is the
    orientation RMS (rad) for pose data, None for positions only.

    ``position = sqrt(mean_k ‖p_meas,k − p_pred,k‖²)``,
    ``orientation = sqrt(mean_k ‖log(R_meas,k R_pred,kᵀ)‖²)``.

    Attributes
    ----------
    position : float
        Position RMS, m (also the float's own value; the first constructor argument).
    orientation : float or None
        Orientation RMS, rad (None: position data only; the second constructor argument,
        default None).

    Examples
    --------
    >>> e = RMS(0.002, 0.001)
    >>> float(e), e.position, e.orientation, e
    (0.002, 0.002, 0.001, 0.002 m, 0.001 rad)
    """

    orientation: float | None

    def __new__(cls, position: float, orientation: float | None = None) -> RMS:
        obj = super().__new__(cls, position)
        obj.orientation = orientation
        return obj

    @property
    def position(self) -> float:
        """The position RMS (m)."""
        return float(self)

    def __repr__(self) -> str:
        if self.orientation is None:
            return f"{float(self):.3g} m"
        return f"{float(self):.3g} m, {self.orientation:.3g} rad"


#: Largest identification Jacobian ``calibrate`` builds (bytes; float64 (K·m, 6(n+1))): 1 GiB is
#: about 530,000 poses of a 6R arm. The CSV reader's 200,000 rows stay well below it.
MAX_JACOBIAN_BYTES = 1 << 30

def parameter_names(robot: Robot) -> list[str]:
    """Names of the 6(n+1) error parameters: ``"<joint>.rx"`` … ``"<joint>.tz"`` for the placement
    of each joint (the first one is the base → joint 1 transform), then ``"tool.rx"`` … ``"tool.tz"``.

    Parameters
    ----------
    robot : Robot
        The nominal robot (its joint names label the blocks).

    Returns
    -------
    list of str
        Rotations ``r*`` (rad) about and translations ``t*`` (m) along the axes of the frame the
        placement ends in (the joint's own frame at q = 0, or the tool frame).

    Examples
    --------
    >>> import robokit
    >>> from robokit.calibration import parameter_names
    >>> parameter_names(robokit.load("twolink"))[-1]
    'tool.tz'
    """
    blocks = [str(n) for n in robot.joint_names] + ["tool"]
    return [f"{b}.{c}" for b in blocks for c in _COMPONENTS]


def identification_jacobian(chain: JointChain, q: np.ndarray, positions_only: bool = False) -> np.ndarray:
    r"""The identification Jacobian of the per-joint SE(3) error model at ``chain`` (δ = 0).

    Parameters
    ----------
    chain : JointChain
        The current geometry.
    q : ndarray, shape (K, n)
        Joint values (rad, m).
    positions_only : bool
        Keep only the position rows.

    Returns
    -------
    ndarray, shape (K, 6, 6(n+1)) or (K, 3, 6(n+1))
        ``∂(ω, p)/∂δ``: rows ω (the tool's small rotation, base axes, rad) then p (tool position,
        base frame, m); columns δ₁ … δ_{n+1}, each ``(rx, ry, rz, tx, ty, tz)``; block i is
        ``[[1, 0], [−[p], 1]] Ad_{Pᵢ}`` (see the module docstring).

    Examples
    --------
    >>> import numpy as np, robokit
    >>> from robokit.calibration import chain_from_robot, identification_jacobian
    >>> J = identification_jacobian(chain_from_robot(robokit.load("rrr")), np.zeros((2, 3)))
    >>> J.shape
    (2, 6, 24)
    """
    F = chain.frames(q)  # (n+2, K, 4, 4): P_1..P_n, T, T
    n = chain.n
    K = F.shape[1]
    p = F[n, :, :3, 3]
    shift = np.zeros((K, 6, 6))
    shift[:, :3, :3] = np.eye(3)
    shift[:, 3:, 3:] = np.eye(3)
    shift[:, 3:, :3] = -lie.hat(p)
    blocks = np.einsum("kab,ikbc->kaic", shift, lie.adjoint(F[np.r_[0:n, n]]))  # (K, 6, n+1, 6)
    J = blocks.reshape(K, 6, 6 * (n + 1))
    return J[:, 3:] if positions_only else J


def pose_residuals(chain: JointChain, q: np.ndarray, measured: np.ndarray) -> np.ndarray:
    """Residuals (K, 6) ``(log(R_meas R_predᵀ), p_meas − p_pred)`` (rad, m) or (K, 3) ``p_meas − p_pred``
    for measured positions (K, 3), predictions from ``chain.fk(q)``.

    Parameters
    ----------
    chain : JointChain
        The geometry predicting the tool poses.
    q : ndarray, shape (K, n)
        Joint values.
    measured : ndarray, shape (K, 4, 4) or (K, 3)
        Measured tool poses or positions in the base frame.

    Returns
    -------
    ndarray, shape (K, 6) or (K, 3)

    Examples
    --------
    >>> import numpy as np, robokit
    >>> from robokit.calibration import chain_from_robot, pose_residuals
    >>> chain = chain_from_robot(robokit.load("rrr"))
    >>> q = np.zeros((1, 3))
    >>> float(np.abs(pose_residuals(chain, q, chain.fk(q))).max())
    0.0
    """
    T = chain.fk(q)
    if measured.ndim == 2:
        return measured - T[:, :3, 3]
    w = lie.log3(measured[:, :3, :3] @ np.swapaxes(T[:, :3, :3], 1, 2))
    return np.concatenate([w, measured[:, :3, 3] - T[:, :3, 3]], axis=1)


def _rms(res: np.ndarray) -> RMS:
    if res.shape[1] == 3:
        return RMS(math.sqrt(float(np.mean(np.sum(res**2, axis=1)))))
    return RMS(math.sqrt(float(np.mean(np.sum(res[:, 3:] ** 2, axis=1)))),
               math.sqrt(float(np.mean(np.sum(res[:, :3] ** 2, axis=1)))))


@dataclass(frozen=True)
class Identifiability:
    """What the data can identify of the error model.

    Attributes
    ----------
    parameters : int
        Number of error parameters, 6(n+1).
    rank : int
        Number of independent combinations the data identify (the parameters solved for).
    structural_rank : int
        Number a rich data set identifies for this arm and this kind of measurement (from many
        random configurations of the nominal arm).
    condition_number : float
        Condition number of the column-scaled identification Jacobian restricted to the identified
        parameters (σ_max/σ_min; each column scaled to unit norm, so units do not matter).
    identified : tuple of str
        The parameters solved for (see :func:`parameter_names`).
    unidentified : tuple of str
        One line per parameter that stays nominal, saying how it acts on the measurements: not
        at all, or like a combination of identified parameters (which the data cannot separate
        from it).
    singular_values : ndarray
        Singular values of the column-scaled Jacobian (all parameters), largest first.
    """

    parameters: int
    rank: int
    structural_rank: int
    condition_number: float
    identified: tuple
    unidentified: tuple
    singular_values: np.ndarray = field(repr=False)

    def __str__(self) -> str:
        lines = [f"identifiable: {self.rank} of {self.parameters} error parameters "
                 f"(a rich data set: {self.structural_rank}); condition number {self.condition_number:.3g}"]
        if self.rank < self.structural_rank:
            lines.append(f"the data separate only {self.rank} of the {self.structural_rank} identifiable combinations: "
                         "measure more, and more varied, configurations")
        lines += [f"  stays nominal: {u}" for u in self.unidentified]
        return "\n".join(lines)


@dataclass(frozen=True, eq=False)
class CalibrationResult:
    """Result of :func:`calibrate`.

    Attributes
    ----------
    robot : Robot
        The calibrated robot (Pinocchio model of the calibrated geometry, nominal inertias); its
        ``frame_pose(q)`` predicts the measurements.
    nominal : Robot
        The robot calibrated.
    chain : JointChain
        The calibrated geometry.
    delta : ndarray, shape (n + 1, 6)
        The identified errors δᵢ of each placement (rad, m; zero where not identified), such that
        the calibrated placements are ``Xᵢ e^{[δᵢ]}`` (compounded over the iterations, then
        expressed once from the nominal: ``δᵢ = log(X_i,nom⁻¹ X_i,cal)``).
    rms_before, rms_after : RMS
        Position RMS (m) — and ``.orientation`` (rad) for pose data — of the nominal and of the
        calibrated robot on the data.
    residuals_before, residuals : ndarray, shape (K, 6) or (K, 3)
        Per-sample residuals ``(ω, Δp)`` (pose data) or ``Δp`` (positions): measured minus predicted.
    identifiability : Identifiability
        Rank, condition number, what stays nominal.
    iterations : int
        Levenberg–Marquardt iterations taken.
    converged : bool
        Whether the step fell below tolerance.

    Examples
    --------
    The ``rrr`` arm measured with a 1 mm offset along x: calibration absorbs it.

    >>> robot = rk.load("rrr")
    >>> Q = np.random.default_rng(0).uniform(-1.5, 1.5, (20, 3))
    >>> res = rk.calibrate(robot, Q, robot.frame_pose_batch(Q)[:, :3, 3] + [0.001, 0.0, 0.0])
    >>> float(res.rms_before) > 9e-4, float(res.rms_after) < 1e-9
    (True, True)
    """

    robot: Any
    nominal: Any
    chain: JointChain
    delta: np.ndarray
    rms_before: RMS
    rms_after: RMS
    residuals_before: np.ndarray
    residuals: np.ndarray
    identifiability: Identifiability
    iterations: int
    converged: bool

    def summary(self) -> str:
        """A few lines: before/after RMS, identifiability, what stays nominal.

        Returns
        -------
        str
            The text (also ``str(result)``).

        Examples
        --------
        >>> robot = rk.load("rrr")
        >>> Q = np.random.default_rng(0).uniform(-1.5, 1.5, (20, 3))
        >>> res = rk.calibrate(robot, Q, robot.frame_pose_batch(Q)[:, :3, 3] + [0.001, 0.0, 0.0])
        >>> res.summary().splitlines()[0]
        'calibrated rrr: 20 samples; RMS before 0.001 m, after ... m'
        """
        return (f"calibrated {self.nominal.name}: {len(self.residuals)} samples; RMS before {self.rms_before!r}, "
                f"after {self.rms_after!r}\n{self.identifiability}")

    def __str__(self) -> str:
        return self.summary()

    def plot(self, ax: Any = None) -> Any:
        """Bar plot (log scale) of the per-sample position error before and after calibration (mm); a
        second axes with the orientation error (mrad) for pose data. Returns the matplotlib Figure.

        Parameters
        ----------
        ax : matplotlib Axes, optional
            Draw the position errors there (no orientation axes) instead of a new figure.

        Returns
        -------
        matplotlib.figure.Figure
            The figure drawn into.

        Examples
        --------
        >>> import matplotlib
        >>> matplotlib.use("Agg")
        >>> robot = rk.load("rrr")
        >>> Q = np.random.default_rng(0).uniform(-1.5, 1.5, (20, 3))
        >>> res = rk.calibrate(robot, Q, robot.frame_pose_batch(Q)[:, :3, 3] + [0.001, 0.0, 0.0])
        >>> type(res.plot()).__name__
        'Figure'
        """
        plt = require("matplotlib.pyplot", "CalibrationResult.plot")
        poses = self.residuals.shape[1] == 6
        axes: list[Any]
        if ax is None:
            fig, grid = plt.subplots(2 if poses else 1, 1, figsize=(8, 5 if poses else 3), squeeze=False,
                                     constrained_layout=True)
            axes = list(grid[:, 0])
        else:
            axes = [ax]
            fig = ax.figure
        k = np.arange(len(self.residuals))
        pos = slice(3, 6) if poses else slice(0, 3)
        before = 1e3 * np.linalg.norm(self.residuals_before[:, pos], axis=1)
        after = 1e3 * np.linalg.norm(self.residuals[:, pos], axis=1)
        axes[0].bar(k - 0.2, before, 0.4, label=f"nominal (RMS {1e3 * self.rms_before:.3g} mm)")
        axes[0].bar(k + 0.2, after, 0.4, label=f"calibrated (RMS {1e3 * self.rms_after:.3g} mm)")
        axes[0].set_ylabel("position error (mm)")
        for a in axes:
            a.set_yscale("log")  # before and after differ by orders of magnitude
        axes[0].legend()
        if poses and len(axes) > 1:
            axes[1].bar(k - 0.2, 1e3 * np.linalg.norm(self.residuals_before[:, :3], axis=1), 0.4, label="nominal")
            axes[1].bar(k + 0.2, 1e3 * np.linalg.norm(self.residuals[:, :3], axis=1), 0.4, label="calibrated")
            axes[1].set_ylabel("orientation error (mrad)")
            axes[1].legend()
        axes[-1].set_xlabel("sample")
        return fig


def _check_measured(measured: ArrayLike, K: int) -> np.ndarray:
    m = as_array(measured, "measured", bounded=True)
    if m.shape == (K, 3):
        return m
    if m.shape == (K, 4, 4):
        R = m[:, :3, :3]
        err = np.abs(R @ np.swapaxes(R, 1, 2) - np.eye(3)).max(axis=(1, 2))
        bad = np.flatnonzero((err > 1e-6) | (np.linalg.det(R) < 0) | (np.abs(m[:, 3] - [0, 0, 0, 1]).max(axis=1) > 1e-9))
        if bad.size:
            raise InputError(f"measured: pose {int(bad[0])} is not a rigid transform (rotation not orthonormal "
                             "to 1e-6, or last row not [0, 0, 0, 1])")
        return m
    raise InputError(f"measured: expected shape ({K}, 4, 4) (tool poses) or ({K}, 3) (tool positions) for "
                     f"{K} joint vectors, got {m.shape}")


#: Relative difference of two columns' remaining norms below which :func:`_pivoted_qr` counts them as
#: tied and takes the earlier column: exactly dependent parameters (joint 1's rz and joint 2's ry of an arm
#: whose axes meet) have equal norms up to round-off, which differs between BLAS builds and processors.
PIVOT_TIE = 1e-9


def _pivoted_qr(A: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """R and the column order of a QR factorization of ``A`` with column pivoting (Householder, the
    column with the largest remaining norm first, as LAPACK's geqp3 chooses), the norms computed anew at
    every step and ties (within :data:`PIVOT_TIE`) taken in column order — the same pivots on every
    machine, where LAPACK's choice among equal norms follows the round-off of the BLAS it runs on.

    Examples
    --------
    >>> A = np.array([[1.0, 2.0, 2.0], [0.0, 0.0, 0.0], [0.0, 0.0, 0.0]])   # columns 2 and 3 equal
    >>> R, piv = _pivoted_qr(A)
    >>> piv.tolist(), np.allclose(np.abs(R[0]), np.abs(A[0, piv]))
    ([1, 0, 2], True)
    """
    W = np.array(A, dtype=float)
    m, n = W.shape
    piv = np.arange(n)
    for k in range(min(m, n)):
        norms = np.linalg.norm(W[k:, k:], axis=0)
        top = norms.max()
        if top == 0.0:
            break
        tied = np.flatnonzero(norms >= top * (1.0 - PIVOT_TIE))
        j = k + int(tied[np.argmin(piv[k + tied])])
        W[:, [k, j]] = W[:, [j, k]]
        piv[[k, j]] = piv[[j, k]]
        x = W[k:, k]
        alpha = -math.copysign(float(np.linalg.norm(x)), float(x[0]))
        v = x.copy()
        v[0] -= alpha
        vv = float(v @ v)
        if vv > 0.0:
            W[k:, k:] -= np.outer(v, (2.0 / vv) * (v @ W[k:, k:]))
        W[k + 1:, k] = 0.0
        W[k, k] = alpha
    return np.triu(W[:min(m, n)]), piv


def _scaled_qr(J: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray, int]:
    """Column norms, pivot order, R of the pivoted QR of the column-scaled J (:func:`_pivoted_qr`),
    numerical rank."""
    norms = np.linalg.norm(J, axis=0)
    scale = np.where(norms > 1e-12 * max(norms.max(), 1e-300), norms, np.inf)
    # J is tall (K·m rows, 6(n+1) columns): its R without Q first (LAPACK geqrf, no Q formed),
    # then the pivoted QR of that small R — the same pivots and R, since orthogonal factors from
    # the left change no column norm — instead of a pivoted QR that forms the tall Q
    R0 = np.asarray(np.linalg.qr(J / scale, mode="r"))
    R, piv = _pivoted_qr(R0)
    d = np.abs(np.diag(R))
    rank = int(np.sum(d > RANK_TOL * d[0])) if d.size and d[0] > 0 else 0
    return scale, piv, R, rank


def _structural_rank(chain: JointChain, robot: Robot, positions_only: bool, rng: np.random.Generator) -> int:
    """Rank of the identification Jacobian of a generic arm near ``chain``: many random configurations
    of the chain moved by a small random error (1e-3 rad and m), so that a nominal coincidence
    (a tool exactly on the wrist axes) does not hide parameters the real arm's data identify."""
    P = 6 * (chain.n + 1)
    K = max(3 * P, 30)
    Q = np.array([robot.random_configuration(rng) for _ in range(K)])
    chain = chain.perturbed(1e-3 * rng.standard_normal((chain.n + 1, 6)))
    J = identification_jacobian(chain, Q, positions_only).reshape(-1, P)
    return _scaled_qr(J)[3]


def _describe_unidentified(J: np.ndarray, scale: np.ndarray, piv: np.ndarray, rank: int,
                           names: list[str]) -> list[str]:
    active = piv[:rank]
    out = []
    colnorm = np.linalg.norm(J, axis=0)
    big = colnorm.max() if colnorm.size else 1.0
    rest = [j for j in sorted(piv[rank:]) if colnorm[j] > 1e-9 * big]
    betas = np.linalg.lstsq(J[:, active], J[:, rest], rcond=None)[0] if rest else np.zeros((rank, 0))
    for j in sorted(piv[rank:]):
        if colnorm[j] <= 1e-9 * big:
            out.append(f"{names[j]}: has no effect on these measurements")
            continue
        beta = betas[:, rest.index(j)]
        order = np.argsort(-np.abs(beta * colnorm[active]))
        terms = [f"{beta[k]:+.3g}·{names[active[k]]}" for k in order[:4]
                 if abs(beta[k]) * colnorm[active[k]] > 1e-2 * colnorm[j]]
        out.append(f"{names[j]}: acts like {' '.join(terms)} (not separable from them)")
    return out


def calibrate(robot: Robot | str, q: ArrayLike, measured: ArrayLike, *, orientation_weight: float = 1.0,
              max_iterations: int = 100, tolerance: float = 1e-12,
              rng: int | np.random.Generator | None = 0) -> CalibrationResult:
    r"""Calibrate a robot's geometry from measured tool poses or tool positions.

    Identifies per-joint SE(3) errors of the joint placements, the base and the tool (see the
    module docstring: any small geometric error is representable, nearly parallel axes included)
    by Levenberg–Marquardt on the pose residual with the analytical identification Jacobian;
    parameter combinations the data cannot separate stay nominal.

    Parameters
    ----------
    robot : Robot or str
        The nominal robot (anything :func:`robokit.load` accepts); its tip frame is the tool.
    q : array_like, shape (K, n)
        Joint values at the K measurements (rad, m).
    measured : array_like, shape (K, 4, 4) or (K, 3)
        Measured tool poses, or tool positions only (a laser tracker, a camera marker), in the
        robot's base frame (m).
    orientation_weight : float
        Pose data: metres per radian of orientation error in the cost (the orientation rows of the
        residual and the Jacobian are multiplied by it). For the maximum-likelihood fit use
        σ_position / σ_orientation of your instrument; the default 1 m/rad weighs 1 mrad like 1 mm.
    max_iterations : int
        Levenberg–Marquardt iterations at most.
    tolerance : float
        Stop when the step's largest entry (rad, m) is below it.
    rng : int or numpy.random.Generator or None
        Seed of the random configurations used to find the structural rank.

    Returns
    -------
    CalibrationResult
        ``.robot`` (the calibrated Robot), ``.rms_before``, ``.rms_after`` (m; ``.orientation`` in
        rad for poses), ``.residuals`` (K, 6) or (K, 3), ``.identifiability``, ``.plot()``.

    Raises
    ------
    InputError
        Wrong shapes, NaN, a value beyond 1e12 in magnitude (bounded like every number of a robot
        file), a measured pose that is not a rigid transform, fewer equations (3 per position, 6
        per pose) than identifiable parameters, or an identification Jacobian larger than
        :data:`MAX_JACOBIAN_BYTES` — each naming the argument.

    Examples
    --------
    >>> import numpy as np, robokit
    >>> robot = robokit.load("puma560")
    >>> Q = np.array([robot.random_configuration(i) for i in range(30)])
    >>> res = robokit.calibrate(robot, Q, robot.frame_pose_batch(Q))
    >>> res.rms_after < 1e-9
    True
    """
    from robokit.description import load

    robot = load(robot)
    n = robot.n
    Q = as_array(q, "q", bounded=True)
    if Q.ndim != 2 or Q.shape[1] != n:
        raise InputError(f"q: expected shape (K, {n}) for {robot.name}, got {Q.shape}")
    K = Q.shape[0]
    meas = _check_measured(measured, K)
    positions_only = meas.ndim == 2
    m = 3 if positions_only else 6
    max_iterations = as_count(max_iterations, "max_iterations", 1, 100_000)
    orientation_weight = as_scalar(orientation_weight, "orientation_weight", positive=True, bounded=True)
    tolerance = as_scalar(tolerance, "tolerance", nonnegative=True, bounded=True)
    if K * m * 6 * (n + 1) * 8 > MAX_JACOBIAN_BYTES:
        raise InputError(f"q: {K} samples make an identification Jacobian of "
                         f"{K * m * 6 * (n + 1) * 8 / 2**30:.1f} GiB for {robot.name}; robokit builds at most "
                         f"{MAX_JACOBIAN_BYTES / 2**30:.0f} GiB (use fewer samples)")
    row_w = np.ones(m) if positions_only else np.r_[[orientation_weight] * 3, [1.0] * 3]

    def weighted_jacobian(chain: JointChain) -> np.ndarray:
        return (identification_jacobian(chain, Q, positions_only) * row_w[None, :, None]).reshape(K * m, P)

    nominal = chain_from_robot(robot)
    P = 6 * (n + 1)
    names = parameter_names(robot)
    r_struct = _structural_rank(nominal, robot, positions_only, np.random.default_rng(rng))
    if K * m < r_struct:
        need = -(-r_struct // m)
        kind = "positions" if positions_only else "poses"
        raise InputError(f"measured: {K} {kind} give {K * m} equations for {r_struct} identifiable parameters of "
                         f"{robot.name}; at least {need} samples are needed (several times more for a good fit)")
    res0 = pose_residuals(nominal, Q, meas)
    chain = nominal
    res = res0 * row_w
    cost = float(np.sum(res**2))
    mu = 1e-3
    converged = False
    it = 0
    for it in range(1, max_iterations + 1):
        # the identifiable set is found again at every linearisation point: an arm whose tool sits
        # exactly on its wrist axes (nominal) lets position data see the wrist's errors only once
        # the tool offset has been identified
        Jfull = weighted_jacobian(chain)
        scale, piv, _, rank = _scaled_qr(Jfull)
        active = np.sort(piv[:rank])
        J = Jfull[:, active] / scale[active]
        g = J.T @ res.reshape(-1)
        H = J.T @ J
        D = np.diag(np.diag(H)) + 1e-15 * np.eye(len(active))
        accepted = small = False
        for _ in range(30):
            step = np.linalg.solve(H + mu * D, g)
            delta = np.zeros(P)
            delta[active] = step / scale[active]
            trial = chain.perturbed(delta)
            r_try = pose_residuals(trial, Q, meas) * row_w
            c_try = float(np.sum(r_try**2))
            if c_try <= cost:
                chain, res, accepted = trial, r_try, True
                small = float(np.abs(delta).max()) < tolerance or cost - c_try <= 1e-15 * max(cost, 1e-300)
                cost = c_try
                mu = max(mu / 10.0, 1e-12)
                break
            mu *= 10.0
        if not accepted or small:
            converged = True
            break
    Jf = weighted_jacobian(chain)
    scale, piv, R, rank = _scaled_qr(Jf)
    active = np.sort(piv[:rank])
    # the singular values of the scaled J are those of its R (J/scale·Π = Q·R, Q orthonormal),
    # and those of its identified columns those of R's first `rank` columns
    sv = np.linalg.svd(R, compute_uv=False)
    sv = np.r_[sv, np.zeros(P - sv.size)]  # fewer rows than parameters: the rest are zero
    svs = np.linalg.svd(R[:, :rank], compute_uv=False)
    cond = float(svs[0] / svs[-1]) if svs.size and svs[-1] > 0 else float("inf")
    ident = Identifiability(P, rank, r_struct, cond, tuple(names[j] for j in active),
                            tuple(_describe_unidentified(Jf, scale, piv, rank, names)), sv)
    if rank < r_struct:
        warnings.warn(f"calibrate: the data identify {rank} of the {r_struct} parameter combinations of "
                      f"{robot.name}; the others stay nominal (see .identifiability)", RobokitWarning, stacklevel=2)
    X_nom, X_cal = nominal.placements, chain.placements
    delta_total = lie.log6(lie.inv(X_nom) @ X_cal)
    calibrated = robot_from_chain(robot, chain)
    res_robot = pose_residuals(chain_from_robot(calibrated), Q, meas)
    return CalibrationResult(calibrated, robot, chain, delta_total, _rms(res0), _rms(res_robot), res0, res_robot,
                             ident, it, converged)
