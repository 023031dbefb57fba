r"""Monte Carlo localisation (a particle filter) and the scalar uncertainty of an estimate (Lecture 9).

The particle filter represents the belief about the pose ``x = (x, y, θ)`` by N particles ``xᵢ``
with weights ``wᵢ`` (Σ wᵢ = 1), using the same models as the EKF of
:mod:`robokit.mobile.estimation`:

* prediction: each particle moves by the odometry increment with its own noise sample,
  ``xᵢ ← f(xᵢ, δ, vᵢ)``, ``vᵢ ~ N(0, V)`` (either odometry order);
* update with a range–bearing measurement z of landmark j: ``wᵢ ← wᵢ · exp(−½ νᵢᵀ W⁻¹ νᵢ)`` with
  ``νᵢ = z − h(xᵢ, p_j)`` (bearing wrapped to (−π, π]), then normalised;
* systematic resampling (:func:`systematic_resample`) when the effective sample size
  ``N_eff = 1 / Σ wᵢ²`` drops below ``resample_threshold · N``: one uniform draw
  ``u ~ U[0, 1/N)`` and the N evenly spaced pointers ``u + k/N`` pick particles from the cumulative
  weights, so particle i is copied ⌊N wᵢ⌋ or ⌈N wᵢ⌉ times; weights reset to 1/N.

The estimate is the weighted mean (the circular mean for θ) and the weighted covariance
(θ deviations wrapped). All randomness comes from the filter's own seeded generator.

:func:`uncertainty` gives the lecture's scalar measures of a covariance: ``det P = Π λᵢ`` and the
area of the 1-σ error ellipse ``π r₁ r₂``, ``rᵢ = √λᵢ`` of the (x, y) block.
"""
from __future__ import annotations

import math

import numpy as np
from numpy.typing import ArrayLike

from robokit._arrays import as_matrix, as_scalar, as_vector
from robokit.mobile.estimation import LandmarkMap, _check_order
from robokit.mobile.vehicle import angdiff
from robokit.errors import InputError

__all__ = ["ParticleFilter", "systematic_resample", "uncertainty"]


def systematic_resample(weights: ArrayLike, rng: int | np.random.Generator | None = None) -> np.ndarray:
    """Indices of the particles kept by systematic resampling of ``weights`` (Lecture 9).

    One uniform draw ``u ~ U[0, 1/N)``; pointer k = ``u + k/N`` selects the first particle whose
    cumulative weight exceeds it. Each particle i appears ⌊N wᵢ⌋ or ⌈N wᵢ⌉ times.

    Parameters
    ----------
    weights : (N,) array_like
        Non-negative weights with a positive sum (normalised here).
    rng : int, numpy.random.Generator or None
        Seed or generator of the one uniform draw.

    Returns
    -------
    (N,) ndarray of int
        Indices into the particles, ascending.

    Examples
    --------
    >>> systematic_resample([0.5, 0.5, 0, 0], rng=1).tolist()
    [0, 0, 1, 1]
    """
    w = as_vector(weights, "weights")
    if np.any(w < 0) or w.sum() <= 0:
        raise InputError("weights: expected non-negative weights with a positive sum")
    w = w / w.sum()
    n = len(w)
    rng = np.random.default_rng(rng)
    pointers = (rng.random() + np.arange(n)) / n
    cum = np.cumsum(w)
    cum[-1] = 1.0
    return np.searchsorted(cum, pointers, side="right")


def uncertainty(P: ArrayLike, kind: str = "det") -> float:
    """A scalar uncertainty of a covariance P (Lecture 9).

    Parameters
    ----------
    P : (m, m) array_like
        Symmetric covariance (e.g. the 3×3 pose covariance).
    kind : {"det", "area"}
        "det" — ``det P = Π λᵢ``; "area" — the area ``π r₁ r₂`` of the 1-σ error ellipse of the
        (x, y) block ``P[:2, :2]``, ``rᵢ = √λᵢ`` (m²).

    Returns
    -------
    float
        ``det P`` or the ellipse's area (m²), as ``kind`` says.

    Examples
    --------
    Standard deviations 2 m and 1 m: the 1-σ ellipse has area π · 2 · 1.

    >>> round(uncertainty(np.diag([4.0, 1.0]), "area") / np.pi, 4)
    2.0
    """
    P = as_matrix(P, "P")
    if P.shape[0] != P.shape[1]:
        raise InputError(f"P: expected a square covariance, got shape {P.shape}")
    if np.abs(P - P.T).max() > 1e-9 * max(1.0, np.abs(P).max()):
        raise InputError("P: expected a symmetric covariance")
    if kind == "det":
        return float(np.linalg.det(P))
    if kind == "area":
        if P.shape[0] < 2:
            raise InputError("P: the ellipse area needs at least a 2×2 (x, y) block")
        lam = np.linalg.eigvalsh(P[:2, :2])
        if lam.min() < -1e-12:
            raise InputError("P: expected a positive semi-definite covariance")
        return float(math.pi * math.sqrt(max(lam[0], 0.0) * max(lam[1], 0.0)))
    raise InputError(f"kind: expected 'det' or 'area', got {kind!r}")


class ParticleFilter:
    """Monte Carlo localisation with a known landmark map (module docstring, Lecture 9).

    Attributes after construction: ``particles`` (N, 3) poses (m, m, rad), ``weights`` (N,); the
    estimate :attr:`x` (3,) and covariance :attr:`P` (3, 3).

    Parameters
    ----------
    n_particles : int
        Number N of particles (≥ 1).
    x0 : (3,) array_like
        Mean of the initial belief (x, y, θ) (m, m, rad); particles are drawn from N(x0, P0).
    P0 : (3, 3) array_like
        Covariance of the initial belief.
    V : (2, 2) array_like
        Odometry noise covariance used to move the particles (m², rad²).
    W : (2, 2) array_like
        Sensor noise covariance of the likelihood (m², rad²).
    landmarks : LandmarkMap
        The known map.
    rng : int, numpy.random.Generator or None
        Seed or generator of all the filter's randomness.
    order : {"turn-move", "move-turn"}
        Odometry order (:func:`robokit.mobile.odometry_model`).
    resample_threshold : float
        Resample when ``N_eff < threshold · N`` (1 resamples after every update).
    particles : (N, 3) array_like, optional
        Initial particles given directly (e.g. uniform over the map for global localisation);
        then x0 and P0 are ignored.

    Examples
    --------
    >>> lm = LandmarkMap([[5.0, 0.0], [0.0, 5.0]])
    >>> pf = ParticleFilter(200, [0, 0, 0], np.diag([0.01, 0.01, 0.001]), np.diag([1e-4, 1e-4]),
    ...                     np.diag([0.01, 1e-4]), lm, rng=0)
    >>> pf.predict([1.0, 0.0])
    >>> bool(np.abs(pf.x - [1.0, 0.0, 0.0]).max() < 0.05)
    True
    """

    def __init__(self, n_particles: int, x0: ArrayLike, P0: ArrayLike, V: ArrayLike, W: ArrayLike, landmarks: LandmarkMap, rng: int | np.random.Generator | None = None, order: str = "turn-move",
                 resample_threshold: float = 0.5, particles: ArrayLike | None = None) -> None:
        self.rng = np.random.default_rng(rng)
        self.N = int(n_particles)
        if self.N < 1:
            raise InputError(f"n_particles: expected a positive count, got {n_particles!r}")
        self.V, self.W = as_matrix(V, "V", 2, 2), as_matrix(W, "W", 2, 2)
        self.Winv = np.linalg.inv(self.W)
        self.map = landmarks
        self.order = _check_order(order)
        self.threshold = as_scalar(resample_threshold, "resample_threshold", nonnegative=True)
        if particles is not None:
            self.particles = as_matrix(particles, "particles", self.N, 3).copy()
        else:
            x0 = as_vector(x0, "x0", 3)
            P0 = as_matrix(P0, "P0", 3, 3)
            self.particles = self.rng.multivariate_normal(x0, P0, self.N)
        self.particles[:, 2] = angdiff(self.particles[:, 2])
        self.weights = np.full(self.N, 1.0 / self.N)

    def predict(self, delta: ArrayLike) -> None:
        """Move every particle by the odometry increment δ = (δ_d, δ_θ) with its own noise sample.

        Parameters
        ----------
        delta : array_like, shape (2,)
            Distance (m) and heading change (rad).

        Returns
        -------
        None
            ``self.particles`` are moved.
        """
        d0, t0 = as_vector(delta, "delta", 2)
        v = self.rng.multivariate_normal(np.zeros(2), self.V, self.N)
        x = self.particles
        d = d0 + v[:, 0]
        th = x[:, 2] + t0 + v[:, 1]
        heading = th if self.order == "turn-move" else x[:, 2]
        self.particles = np.column_stack([x[:, 0] + d * np.cos(heading), x[:, 1] + d * np.sin(heading), angdiff(th)])

    def update(self, z: ArrayLike, i: int) -> float:
        """Weight the particles by the likelihood of the measurement z = (r, β) of landmark i; resample
        when the effective sample size is below ``threshold · N``.

        Parameters
        ----------
        z : array_like, shape (2,)
            Range (m) and bearing (rad).
        i : int
            The landmark's index in the map.

        Returns
        -------
        float
            N_eff = 1 / Σ wᵢ² before resampling.
        """
        z = as_vector(z, "z", 2)
        p = self.map.points[i]
        dx, dy = p[0] - self.particles[:, 0], p[1] - self.particles[:, 1]
        nu = np.column_stack([z[0] - np.hypot(dx, dy), angdiff(z[1] - (np.arctan2(dy, dx) - self.particles[:, 2]))])
        logl = -0.5 * np.einsum("ij,jk,ik->i", nu, self.Winv, nu)
        logw = np.log(np.maximum(self.weights, 1e-300)) + logl
        w = np.exp(logw - logw.max())
        self.weights = w / w.sum()
        n_eff = 1.0 / float(np.sum(self.weights**2))
        if n_eff < self.threshold * self.N:
            self.resample()
        return n_eff

    def resample(self) -> None:
        """Systematic resampling; the weights become uniform."""
        idx = systematic_resample(self.weights, self.rng)
        self.particles = self.particles[idx]
        self.weights = np.full(self.N, 1.0 / self.N)

    @property
    def x(self) -> np.ndarray:
        """The estimate (3,): weighted mean of x, y and the circular mean of θ."""
        w = self.weights
        th = math.atan2(float(w @ np.sin(self.particles[:, 2])), float(w @ np.cos(self.particles[:, 2])))
        return np.array([w @ self.particles[:, 0], w @ self.particles[:, 1], th])

    @property
    def P(self) -> np.ndarray:
        """The weighted covariance (3×3) of the particles about :attr:`x` (θ deviations wrapped)."""
        d = self.particles - self.x
        d[:, 2] = angdiff(d[:, 2])
        return (self.weights[:, None] * d).T @ d
