r"""The unicycle and the differential-drive vehicle (Lecture 9, beside the bicycle model).

State ``x = (x, y, θ)`` (m, m, rad) of the vehicle's reference point (the middle of the wheel
axle) in the world frame; inputs ``u = (v, ω)``: forward speed (m/s) and turn rate (rad/s):

    ẋ = v cos θ,   ẏ = v sin θ,   θ̇ = ω

with the same non-holonomic constraint as the bicycle, ``ẏ cos θ − ẋ sin θ = 0``. Unlike the
bicycle it can turn on the spot (v = 0, ω ≠ 0). For constant (v, ω) over a step the motion is an arc
of radius v/ω, integrated exactly by :meth:`UnicycleModel.step`. A bicycle with wheelbase L and
steering γ is the unicycle with ``ω = (v / L) tan γ``.

A differential drive (two wheels of radius r on an axle of track W, wheel speeds ``ω_L, ω_R`` in
rad/s) is a unicycle with

    v = r (ω_R + ω_L) / 2,     ω = r (ω_R − ω_L) / W,

and conversely ``ω_R = (v + ω W/2) / r``, ``ω_L = (v − ω W/2) / r``.

:class:`UnicycleModel` has the same ``limit``/``deriv``/``step`` interface as
:class:`robokit.BicycleModel`, so :func:`robokit.run_vehicle` runs it with any controller that
returns (v, ω).
"""
from __future__ import annotations


import numpy as np
from numpy.typing import ArrayLike

from robokit._arrays import as_scalar, as_vector
from robokit.mobile.vehicle import _HeadingModel

__all__ = ["UnicycleModel", "DifferentialDrive"]


class UnicycleModel(_HeadingModel):
    """Unicycle: ``ẋ = v cos θ, ẏ = v sin θ, θ̇ = ω``, inputs u = (v, ω) (Lecture 9).

    Parameters
    ----------
    speed_max : float
        Speed limit (m/s, > 0).
    omega_max : float
        Turn-rate limit (rad/s, > 0).

    Examples
    --------
    Half a turn at v = 1 m/s, ω = 1 rad/s (π s): a semicircle of radius v/ω = 1 m.

    >>> UnicycleModel().step([0, 0, 0], [1.0, 1.0], np.pi).round(4)
    array([0.    , 2.    , 3.1416])
    """

    def __init__(self, speed_max: float = 5.0, omega_max: float = 4.0) -> None:
        self.speed_max = as_scalar(speed_max, "speed_max", positive=True)
        self.omega_max = as_scalar(omega_max, "omega_max", positive=True)

    def limit(self, u: ArrayLike) -> np.ndarray:
        """Inputs (v, ω) clipped to the limits.

        Parameters
        ----------
        u : array_like, shape (2,)

        Returns
        -------
        ndarray, shape (2,)
        """
        v, w = as_vector(u, "u", 2)
        return np.array([np.clip(v, -self.speed_max, self.speed_max), np.clip(w, -self.omega_max, self.omega_max)])

    def _turn_rate(self, v: float, w: float) -> float:
        return w  # the unicycle's second input is its turn rate


class DifferentialDrive(UnicycleModel):
    """A differential-drive vehicle: two wheels on one axle, a unicycle with
    ``v = r (ω_R + ω_L)/2``, ``ω = r (ω_R − ω_L)/W``.

    Inputs to ``step``/``deriv`` are (v, ω) as for the unicycle (the wheel-speed limit is applied
    through them); :meth:`wheel_speeds` and :meth:`body_velocity` convert.

    Parameters
    ----------
    r : float
        Wheel radius (m, > 0).
    W : float
        Track: distance between the wheels (m, > 0).
    wheel_max : float
        Wheel-speed limit (rad/s, > 0).

    Examples
    --------
    >>> dd = DifferentialDrive(0.1, 0.5)
    >>> dd.body_velocity([10, 10]).tolist()          # both wheels at 10 rad/s: straight ahead at 1 m/s
    [1.0, 0.0]
    >>> dd.wheel_speeds([0.0, 1.0]).tolist()          # turning on the spot at 1 rad/s
    [-2.5, 2.5]
    """

    def __init__(self, r: float, W: float, wheel_max: float = 50.0) -> None:
        self.r = as_scalar(r, "r", positive=True)
        self.W = as_scalar(W, "W", positive=True)
        self.wheel_max = as_scalar(wheel_max, "wheel_max", positive=True)
        super().__init__(speed_max=self.r * self.wheel_max, omega_max=2 * self.r * self.wheel_max / self.W)

    def body_velocity(self, wheels: ArrayLike) -> np.ndarray:
        """(v, ω) from the wheel speeds ``(ω_L, ω_R)`` (rad/s): ``v = r(ω_R + ω_L)/2``, ``ω = r(ω_R − ω_L)/W``.

        Parameters
        ----------
        wheels : array_like, shape (2,)
            Left and right wheel speeds, rad/s.

        Returns
        -------
        ndarray, shape (2,)
            Forward speed v (m/s) and turn rate ω (rad/s).
        """
        wl, wr = as_vector(wheels, "wheels", 2)
        return np.array([self.r * (wr + wl) / 2.0, self.r * (wr - wl) / self.W])

    def wheel_speeds(self, u: ArrayLike) -> np.ndarray:
        """``(ω_L, ω_R)`` (rad/s) for the body velocity u = (v, ω): ``(v ∓ ωW/2)/r``.

        Parameters
        ----------
        u : array_like, shape (2,)
            Forward speed (m/s) and turn rate (rad/s).

        Returns
        -------
        ndarray, shape (2,)
            Left and right wheel speeds, rad/s.
        """
        v, w = as_vector(u, "u", 2)
        return np.array([(v - w * self.W / 2.0) / self.r, (v + w * self.W / 2.0) / self.r])

    def limit(self, u: ArrayLike) -> np.ndarray:
        """(v, ω) scaled down together so that neither wheel exceeds ``wheel_max`` (the path's curvature is kept).

        Parameters
        ----------
        u : array_like, shape (2,)
            The demanded body velocity (v, ω), as for :meth:`wheel_speeds`.

        Returns
        -------
        ndarray, shape (2,)
            The achievable (v, ω).
        """
        v, w = as_vector(u, "u", 2)
        wheels = self.wheel_speeds([v, w])
        k = max(1.0, float(np.abs(wheels).max()) / self.wheel_max)
        return np.array([v / k, w / k])
