r"""Odometry, landmarks and a range–bearing sensor, EKF localisation and EKF SLAM (Lecture 9).

Odometry increments ``δ = (δ_d, δ_θ)`` (distance, heading change) drive the motion model

    f(x, δ, v) = (x + (δ_d + v_d) cos(θ + δ_θ + v_θ), y + (δ_d + v_d) sin(θ + δ_θ + v_θ), θ + δ_θ + v_θ),

with odometry noise ``v ~ N(0, V)``. This is the *turn-then-move* order (``order="turn-move"``, the
default, as the lecture's three-vector form writes it). Corke's book applies the two in the other
order, *move-then-turn* (``order="move-turn"``):

    f(x, δ, v) = (x + (δ_d + v_d) cos θ, y + (δ_d + v_d) sin θ, θ + δ_θ + v_θ)

(the lecture's matrix product ``ξ T_x(δ_d) R(δ_θ)`` is this order; for small steps the two agree
to first order). Every function and filter taking odometry accepts ``order``. A range–bearing sensor sees landmark i at
``z = (√((x_i − x)² + (y_i − y)²), atan2(y_i − y, x_i − x) − θ) + w``, ``w ~ N(0, W)``.

EKF (as Lecture 9 writes it): prediction ``x̂ ← f(x̂, δ, 0)``, ``P ← F_x P F_xᵀ + F_v V F_vᵀ``;
update with the innovation ``ν = z − h(x̂)`` (bearing wrapped to (−π, π]),
``S = H_x P H_xᵀ + H_w W H_wᵀ``, ``K = P H_xᵀ S⁻¹``, ``x̂ ← x̂ + K ν`` and the Joseph form
``P ← (I − K H_x) P (I − K H_x)ᵀ + K W Kᵀ``. EKF SLAM augments the state with the landmark
positions; a new landmark is initialised from its first observation,
``x_i = (x + r cos(θ + β), y + r sin(θ + β))``, with the insertion Jacobians G_x, G_z.
"""
from __future__ import annotations

import math

import numpy as np
from numpy.typing import ArrayLike

from robokit._arrays import FloatVector, as_array, as_matrix, as_vector
from robokit.mobile.vehicle import angdiff
from robokit.errors import InputError

__all__ = [
    "odometry_model",
    "odometry_jacobians",
    "Odometry",
    "LandmarkMap",
    "RangeBearingSensor",
    "EKFLocalization",
    "EKFSLAM",
    "error_ellipse",
]


_ORDERS = ("turn-move", "move-turn")


def _check_order(order: str) -> str:
    if order not in _ORDERS:
        raise InputError(f"order: expected 'turn-move' or 'move-turn', got {order!r}")
    return order


def odometry_model(x: FloatVector, delta: FloatVector, v: FloatVector = (0.0, 0.0), order: str = "turn-move") -> np.ndarray:
    """``f(x, δ, v)`` of the module docstring: the pose after an odometry increment (Lecture 9).

    Parameters
    ----------
    x : (3,) array_like
        Pose (x, y, θ) in the world frame (m, m, rad).
    delta : (2,) array_like
        Odometry increment (δ_d, δ_θ): distance travelled (m) and heading change (rad).
    v : (2,) array_like, default (0, 0)
        Odometry noise added to δ (m, rad).
    order : {"turn-move", "move-turn"}
        "turn-move" (default, the lecture's three-vector form): turn by δ_θ, then move δ_d along the
        new heading; "move-turn" (Corke's book): move along the old heading, then turn.

    Returns
    -------
    (3,) ndarray
        The new pose (x, y, θ), θ wrapped to (−π, π].

    Examples
    --------
    Turn 90° then drive 1 m from the origin facing +x: the vehicle ends at (0, 1) facing +y.

    >>> odometry_model([0, 0, 0], [1.0, np.pi / 2]).round(4)
    array([0.    , 1.    , 1.5708])
    >>> odometry_model([0, 0, 0], [1.0, np.pi / 2], order="move-turn").round(4)
    array([1.    , 0.    , 1.5708])
    """
    _check_order(order)
    d = delta[0] + v[0]
    th = x[2] + delta[1] + v[1]
    heading = th if order == "turn-move" else x[2]
    return np.array([x[0] + d * math.cos(heading), x[1] + d * math.sin(heading), angdiff(th)])


def odometry_jacobians(x: FloatVector, delta: FloatVector, order: str = "turn-move") -> tuple[np.ndarray, np.ndarray]:
    """``(F_x, F_v)``: ∂f/∂x and ∂f/∂v of :func:`odometry_model` at v = 0, for either order.

    turn-move: ``F_x = [[1, 0, −δ_d s], [0, 1, δ_d c], [0, 0, 1]]``, ``F_v = [[c, −δ_d s], [s, δ_d c], [0, 1]]``
    with c, s of θ + δ_θ (the lecture's); move-turn: the same F_x with c, s of θ, and
    ``F_v = [[c, 0], [s, 0], [0, 1]]``.

    Parameters
    ----------
    x : (3,) array_like
        Pose (x, y, θ) (m, m, rad) where the Jacobians are taken.
    delta : (2,) array_like
        Odometry increment (δ_d, δ_θ) (m, rad).
    order : {"turn-move", "move-turn"}
        As for :func:`odometry_model`.

    Returns
    -------
    F_x : (3, 3) ndarray
        ∂f/∂x.
    F_v : (3, 2) ndarray
        ∂f/∂v (columns: distance noise, heading noise).

    Examples
    --------
    Driving 2 m along +x: a heading error moves the end point sideways by 2 m per rad.

    >>> Fx, Fv = odometry_jacobians([0, 0, 0], [2.0, 0.0])
    >>> Fx[:, 2].tolist(), Fv[:, 1].tolist()
    ([-0.0, 2.0, 1.0], [-0.0, 2.0, 1.0])
    """
    _check_order(order)
    th = x[2] + delta[1] if order == "turn-move" else x[2]
    c, s, d = math.cos(th), math.sin(th), delta[0]
    Fx = np.array([[1.0, 0.0, -d * s], [0.0, 1.0, d * c], [0.0, 0.0, 1.0]])
    if order == "turn-move":
        Fv = np.array([[c, -d * s], [s, d * c], [0.0, 1.0]])
    else:
        Fv = np.array([[c, 0.0], [s, 0.0], [0.0, 1.0]])
    return Fx, Fv


class Odometry:
    """A vehicle's odometer: the true increment plus zero-mean Gaussian noise.

    Parameters
    ----------
    V : (2, 2) array_like
        Noise covariance of (δ_d, δ_θ) (m², rad²), positive semi-definite.
    rng : int, numpy.random.Generator or None
        Seed or generator of the noise.
    """

    def __init__(self, V: ArrayLike, rng: int | np.random.Generator | None = None) -> None:
        self.V = as_matrix(V, "V", 2, 2)
        if np.linalg.eigvalsh(self.V).min() < 0:
            raise InputError("V: expected a positive semi-definite covariance")
        self.rng = np.random.default_rng(rng)

    def measure(self, delta: ArrayLike) -> np.ndarray:
        """The measured increment: ``δ + v``, ``v ~ N(0, V)``.

        Parameters
        ----------
        delta : array_like, shape (2,)
            The true increment (distance m, heading change rad).

        Returns
        -------
        ndarray, shape (2,)
            The noisy increment.
        """
        return np.asarray(delta, float) + self.rng.multivariate_normal(np.zeros(2), self.V)


class LandmarkMap:
    """Point landmarks in the plane.

    Parameters
    ----------
    points : (N, 2) array_like
        Landmark positions in the world frame (m).
    """

    def __init__(self, points: ArrayLike) -> None:
        self.points = as_array(points, "points", (None, 2))

    @classmethod
    def random(cls, n: int, size: float = 10.0, rng: int | np.random.Generator | None = None) -> "LandmarkMap":
        """``n`` landmarks uniform in the square [−size, size]².

        Parameters
        ----------
        n : int
            How many.
        size : float
            Half the square's side, m.
        rng : int or numpy.random.Generator, optional
            Seed or generator.

        Returns
        -------
        LandmarkMap
        """
        return cls(np.random.default_rng(rng).uniform(-size, size, (int(n), 2)))

    def __len__(self) -> int:
        return len(self.points)


class RangeBearingSensor:
    """Range–bearing sensor: ``z = (r, β) + w``, ``w ~ N(0, W)`` (Lecture 9).

    ``r`` is the distance to the landmark (m), ``β`` its bearing from the vehicle's x axis (rad, in
    (−π, π]).

    Parameters
    ----------
    landmarks : LandmarkMap
        The landmarks it can see.
    W : (2, 2) array_like
        Measurement noise covariance (m², rad²).
    max_range : float, optional
        Landmarks farther than this (m) are not visible.
    fov : float, optional
        Field of view (rad), centred on the vehicle's x axis.
    rng : int, numpy.random.Generator or None
        Seed or generator of the noise.

    Examples
    --------
    A landmark at (3, 4) seen from the origin facing +y: 5 m away, bearing atan2(4, 3) − 90°.

    >>> RangeBearingSensor.h([0, 0, np.pi / 2], [3.0, 4.0]).round(4)
    array([ 5.    , -0.6435])
    """

    def __init__(self, landmarks: LandmarkMap, W: ArrayLike, max_range: float | None = None, fov: float | None = None,
                 rng: int | np.random.Generator | None = None) -> None:
        self.map = landmarks
        self.W = as_matrix(W, "W", 2, 2)
        self.max_range, self.fov = max_range, fov
        self.rng = np.random.default_rng(rng)

    @staticmethod
    def h(x: FloatVector, p: FloatVector) -> np.ndarray:
        """Noise-free measurement of the landmark at p from pose x.

        Parameters
        ----------
        x : array_like, shape (3,)
            Vehicle pose (x, y, θ), m and rad.
        p : array_like, shape (2,)
            Landmark position, m.

        Returns
        -------
        ndarray, shape (2,)
            Range (m) and bearing relative to the heading (rad, wrapped).
        """
        dx, dy = p[0] - x[0], p[1] - x[1]
        return np.array([math.hypot(dx, dy), angdiff(math.atan2(dy, dx), x[2])])

    @staticmethod
    def jacobians(x: FloatVector, p: FloatVector) -> tuple[np.ndarray, np.ndarray]:
        """``(H_x, H_p)``: ∂h/∂x (2×3) and ∂h/∂p (2×2); ``H_w`` is the identity.

        Parameters
        ----------
        x : array_like, shape (3,)
            Vehicle pose (x, y, θ).
        p : array_like, shape (2,)
            Landmark position.

        Returns
        -------
        H_x : ndarray, shape (2, 3)
        H_p : ndarray, shape (2, 2)
        """
        dx, dy = p[0] - x[0], p[1] - x[1]
        r2 = dx * dx + dy * dy
        r = math.sqrt(r2)
        Hx = np.array([[-dx / r, -dy / r, 0.0], [dy / r2, -dx / r2, -1.0]])
        Hp = np.array([[dx / r, dy / r], [-dy / r2, dx / r2]])
        return Hx, Hp

    def visible(self, x: FloatVector) -> list[int]:
        """Indices of the landmarks within range and field of view of pose x.

        Parameters
        ----------
        x : array_like, shape (3,)
            Vehicle pose.

        Returns
        -------
        list of int
        """
        out = []
        for i, p in enumerate(self.map.points):
            r, b = self.h(x, p)
            if self.max_range is not None and r > self.max_range:
                continue
            if self.fov is not None and abs(b) > self.fov / 2:
                continue
            out.append(i)
        return out

    def measure(self, x: FloatVector, i: int) -> np.ndarray:
        """A noisy measurement of landmark i from the true pose x.

        Parameters
        ----------
        x : array_like, shape (3,)
            The true vehicle pose.
        i : int
            The landmark's index in the map.

        Returns
        -------
        ndarray, shape (2,)
            Range (m) and bearing (rad, wrapped), with noise drawn from N(0, W).
        """
        z = self.h(x, self.map.points[i]) + self.rng.multivariate_normal(np.zeros(2), self.W)
        z[1] = angdiff(z[1])
        return z


def _joseph(P: np.ndarray, K: np.ndarray, H: np.ndarray, W: np.ndarray) -> np.ndarray:
    I = np.eye(P.shape[0])
    A = I - K @ H
    P = A @ P @ A.T + K @ W @ K.T
    return 0.5 * (P + P.T)


def _innovation(z: np.ndarray, x: np.ndarray, p: np.ndarray) -> np.ndarray:
    """ν = z − h(x, p) of a range–bearing measurement z of the landmark p, bearing wrapped."""
    nu = z - RangeBearingSensor.h(x, p)
    nu[1] = angdiff(nu[1])
    return nu


class _EKF:
    """The pose filter shared by :class:`EKFLocalization` and :class:`EKFSLAM` (Lecture 9).

    The state ``.x`` starts with the pose (x, y, θ); anything after it (SLAM's landmarks) does
    not move with the vehicle. ``.P`` is its covariance.
    """

    def __init__(self, x0: ArrayLike, P0: ArrayLike, V: ArrayLike, W: ArrayLike, order: str) -> None:
        self.x = as_vector(x0, "x0", 3).copy()
        self.P = as_matrix(P0, "P0", 3, 3).copy()
        self.V, self.W = as_matrix(V, "V", 2, 2), as_matrix(W, "W", 2, 2)
        self.order = _check_order(order)

    def predict(self, delta: FloatVector) -> None:
        """Prediction with the odometry increment δ = (δ_d, δ_θ): the pose moves, x ← f(x, δ), any
        landmarks in the state stay; ``P ← F P Fᵀ + F_v V F_vᵀ`` with ``F = diag(F_x, I)`` (the
        odometry noise enters the pose block only).

        Parameters
        ----------
        delta : array_like, shape (2,)
            Distance (m) and heading change (rad) measured by odometry.

        Returns
        -------
        None
            ``self.x`` and ``self.P`` are updated.
        """
        Fx, Fv = odometry_jacobians(self.x[:3], delta, self.order)
        self.x = np.r_[odometry_model(self.x[:3], delta, order=self.order), self.x[3:]]
        n = len(self.x)
        F = np.eye(n)
        F[:3, :3] = Fx
        self.P = F @ self.P @ F.T
        self.P[:3, :3] += Fv @ self.V @ Fv.T

    def _correct(self, nu: np.ndarray, H: np.ndarray) -> None:
        # Kalman gain K = P Hᵀ S⁻¹, S = H P Hᵀ + W; x ← x + K ν (heading wrapped); Joseph-form P
        S = H @ self.P @ H.T + self.W
        K = self.P @ H.T @ np.linalg.inv(S)
        self.x = self.x + K @ nu
        self.x[2] = angdiff(self.x[2])
        self.P = _joseph(self.P, K, H, self.W)


class EKFLocalization(_EKF):
    """EKF localisation with a known landmark map (Lecture 9).

    Prediction with odometry (:meth:`predict`), update with range–bearing measurements of known
    landmarks (:meth:`update`, Joseph-form covariance); the estimate is ``.x`` (3,), its
    covariance ``.P`` (3, 3).

    Parameters
    ----------
    x0 : (3,) array_like
        Initial pose estimate (x, y, θ) (m, m, rad).
    P0 : (3, 3) array_like
        Its covariance.
    V : (2, 2) array_like
        Odometry noise covariance the filter assumes (m², rad²).
    W : (2, 2) array_like
        Sensor noise covariance the filter assumes (m², rad²).
    landmarks : LandmarkMap
        The known map.
    order : {"turn-move", "move-turn"}
        The odometry model's order (:func:`odometry_model`).
    """

    def __init__(self, x0: ArrayLike, P0: ArrayLike, V: ArrayLike, W: ArrayLike, landmarks: LandmarkMap, order: str = "turn-move") -> None:
        super().__init__(x0, P0, V, W, order)
        self.map = landmarks

    def update(self, z: ArrayLike, i: int) -> np.ndarray:
        """Update with the measurement z = (r, β) of landmark i (Joseph form of the covariance update).

        Parameters
        ----------
        z : array_like, shape (2,)
            Range (m) and bearing (rad) of the landmark.
        i : int
            The landmark's index in the map.

        Returns
        -------
        ndarray, shape (2,)
            The innovation ν = z − h(x, p_i), bearing wrapped to (−π, π].
        """
        p = self.map.points[i]
        nu = _innovation(np.asarray(z, float), self.x, p)
        Hx, _ = RangeBearingSensor.jacobians(self.x, p)
        self._correct(nu, Hx)
        return nu


class EKFSLAM(_EKF):
    """EKF SLAM: the vehicle pose and the landmark positions estimated together (Lecture 9).

    The state ``.x`` is ``(x, y, θ, x₁, y₁, x₂, y₂, …)`` with covariance ``.P``; a landmark is added
    at its first observation (``x_i = (x + r cos(θ + β), y + r sin(θ + β))`` with the insertion
    Jacobians G_x, G_z). ``landmark_index[i]`` is the position of landmark i in the state.

    Parameters
    ----------
    x0 : (3,) array_like
        Initial pose estimate (m, m, rad).
    P0 : (3, 3) array_like
        Its covariance.
    V : (2, 2) array_like
        Odometry noise covariance (m², rad²).
    W : (2, 2) array_like
        Sensor noise covariance (m², rad²).
    order : {"turn-move", "move-turn"}
        As for :class:`EKFLocalization`.
    """

    def __init__(self, x0: ArrayLike, P0: ArrayLike, V: ArrayLike, W: ArrayLike, order: str = "turn-move") -> None:
        super().__init__(x0, P0, V, W, order)
        self.landmark_index: dict[int, int] = {}

    def landmark(self, i: int) -> np.ndarray:
        """Estimated position of landmark i.

        Parameters
        ----------
        i : int
            The landmark's identifier (as passed to :meth:`update`).

        Returns
        -------
        ndarray, shape (2,)
            Its (x, y) in the world, m.
        """
        k = self.landmark_index[i]
        return self.x[k:k + 2].copy()

    def update(self, z: ArrayLike, i: int) -> np.ndarray:
        """Update with the measurement z = (r, β) of landmark i (inserting it into the state if new).

        Parameters
        ----------
        z : array_like, shape (2,)
            As for :meth:`EKFLocalization.update`.
        i : int
            The landmark's identifier.

        Returns
        -------
        ndarray, shape (2,)
            The innovation (zeros when the landmark was just inserted).
        """
        z = np.asarray(z, float)
        if i not in self.landmark_index:
            th = self.x[2] + z[1]
            c, s = math.cos(th), math.sin(th)
            p = self.x[:2] + z[0] * np.array([c, s])
            Gx = np.array([[1.0, 0.0, -z[0] * s], [0.0, 1.0, z[0] * c]])
            Gz = np.array([[c, -z[0] * s], [s, z[0] * c]])
            n = len(self.x)
            P = np.zeros((n + 2, n + 2))
            P[:n, :n] = self.P
            P[n:, :3] = Gx @ self.P[:3, :3]
            P[n:, 3:n] = Gx @ self.P[:3, 3:n]
            P[:n, n:] = P[n:, :n].T
            P[n:, n:] = Gx @ self.P[:3, :3] @ Gx.T + Gz @ self.W @ Gz.T
            self.x = np.r_[self.x, p]
            self.P = P
            self.landmark_index[i] = n
            return np.zeros(2)
        k = self.landmark_index[i]
        p = self.x[k:k + 2]
        nu = _innovation(z, self.x[:3], p)
        Hx, Hp = RangeBearingSensor.jacobians(self.x[:3], p)
        H = np.zeros((2, len(self.x)))
        H[:, :3] = Hx
        H[:, k:k + 2] = Hp
        self._correct(nu, H)
        return nu


def error_ellipse(P: ArrayLike, mean: ArrayLike = (0.0, 0.0), n_sigma: float = 1.0, points: int = 100) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Points on the ellipse ``(x − μ)ᵀ P⁻¹ (x − μ) = n_sigma²`` of a 2×2 covariance (Lecture 9).

    Axes along the eigenvectors of P with half-lengths ``n_sigma √λᵢ``.

    Parameters
    ----------
    P : (2, 2) array_like
        Symmetric positive semi-definite covariance (m²).
    mean : (2,) array_like
        Centre μ (m).
    n_sigma : float
        Size in standard deviations.
    points : int
        Number of points on the ellipse.

    Returns
    -------
    pts : (points, 2) ndarray
        The ellipse, closed (first point = last), in the frame of ``mean`` (m).
    radii : (2,) ndarray
        Half-lengths of the axes, ascending (m).
    axes : (2, 2) ndarray
        Unit axis vectors (columns), in the order of ``radii``.

    Examples
    --------
    >>> pts, radii, axes = error_ellipse(np.diag([4.0, 1.0]), n_sigma=2.0)
    >>> radii.round(4)
    array([2., 4.])
    """
    P = as_matrix(P, "P", 2, 2)
    if np.abs(P - P.T).max() > 1e-12 * max(1.0, np.abs(P).max()):
        raise InputError("P: expected a symmetric covariance")
    lam, vec = np.linalg.eigh(P)
    if lam.min() < 0:
        raise InputError("P: expected a positive semi-definite covariance")
    radii = n_sigma * np.sqrt(lam)
    a = np.linspace(0, 2 * np.pi, int(points))
    pts = (vec @ (radii[:, None] * np.vstack([np.cos(a), np.sin(a)]))).T + np.asarray(mean, float)[:2]
    return pts, radii, vec
