r"""The joint actuator of Lecture 8: a DC motor behind a current amplifier and a gearbox.

The amplifier makes a current proportional to the control voltage, the motor a torque
proportional to the current (Lecture 8):

    i = K_a u,      τ_m = K_m i = K_m K_a u,

and the motor shaft, with total inertia J and viscous friction B (motor side), obeys

    J ω̇ + B ω + τ_c(ω) = K_m K_a u − τ_d,

with Coulomb friction τ_c and a disturbance torque τ_d. Without Coulomb friction its Laplace
transform gives the transfer function ``Ω(s)/U(s) = K_m K_a / (J s + B)``: a first-order lag of
DC gain ``K_m K_a / B`` and time constant ``J / B``, whose response to a voltage step u is
``ω(t) = (K_m K_a u / B)(1 − e^{−B t / J})``.

A gearbox of ratio G (motor turns per joint turn) between motor and link gives, seen from the
link side (Lecture 8): ``ˡJ = G² ᵐJ``, ``ˡB = G² ᵐB``, ``ˡτ_C = G ᵐτ_C``, ``ˡτ = G ᵐτ``,
``ˡθ̇ = ᵐθ̇ / G``, ``ˡθ̈ = ᵐθ̈ / G`` (:func:`joint_from_motor`); the motor of joint j sees the
effective inertia ``J = J_m + M_jj / G²`` (:func:`effective_inertia`).

Units: V, A, N·m, kg·m², N·m·s/rad, rad/s.
"""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
from numpy.typing import ArrayLike

from robokit._arrays import as_scalar, as_vector
from robokit.errors import InputError
from robokit._deprecation import deprecated_alias

__all__ = ["DCMotor", "joint_from_motor", "effective_inertia"]


@dataclass(frozen=True)
class DCMotor:
    """A DC motor with its current amplifier (Lecture 8).

    ``i = K_a u``, ``τ_m = K_m K_a u`` and ``J ω̇ + B ω + τ_c(ω) = K_m K_a u − τ_d``: methods
    ``current``, ``torque``, ``transfer_function`` (``K_m K_a / (J s + B)``), ``time_constant``
    (J/B), ``dc_gain`` (K_m K_a / B), ``step_response`` (closed form), ``acceleration`` and
    ``simulate`` (RK4, Coulomb friction included).

    Attributes
    ----------
    Ka : float
        Amplifier transconductance (A/V), positive.
    Km : float
        Torque constant (N·m/A), positive.
    J : float
        Total inertia on the motor shaft (kg·m², e.g. :func:`effective_inertia`), positive.
    B : float
        Viscous friction (N·m·s/rad, motor side), non-negative.
    Tc : (2,) tuple, optional
        Coulomb friction for positive and negative speed (N·m, motor side, the second usually
        negative); default none.

    Examples
    --------
    After one time constant J/B the speed reaches 1 − 1/e ≈ 63 % of its final value K_m K_a u / B:

    >>> motor = DCMotor(Ka=1.0, Km=0.228, J=3.3e-4, B=8.2e-4)
    >>> round(motor.time_constant, 4), round(motor.dc_gain, 2)
    (0.4024, 278.05)
    >>> w = motor.step_response([motor.time_constant], 1.0)
    >>> round(float(w[0] / motor.dc_gain), 4)
    0.6321
    """

    Ka: float
    Km: float
    J: float
    B: float
    Tc: tuple = field(default=(0.0, 0.0))

    def __post_init__(self) -> None:
        as_scalar(self.Ka, "Ka", positive=True)
        as_scalar(self.Km, "Km", positive=True)
        as_scalar(self.J, "J", positive=True)
        as_scalar(self.B, "B", nonnegative=True)
        as_vector(self.Tc, "Tc", 2)

    def current(self, u: ArrayLike) -> np.ndarray:
        """Motor current ``i = K_a u`` (A) for control voltage u (V).

        Parameters
        ----------
        u : float or array_like
            Control voltage(s), V.

        Returns
        -------
        ndarray
            Current(s), A, the shape of ``u``.
        """
        return self.Ka * np.asarray(u, dtype=float)

    def torque(self, u: ArrayLike) -> np.ndarray:
        """Motor torque ``τ = K_m K_a u`` (N·m) for control voltage u (V).

        Parameters
        ----------
        u : float or array_like
            As for :meth:`current`.

        Returns
        -------
        ndarray
            Torque(s), N·m (motor side), the shape of ``u``.
        """
        return self.Km * self.Ka * np.asarray(u, dtype=float)

    def transfer_function(self) -> tuple[np.ndarray, np.ndarray]:
        """The speed-from-voltage transfer function ``Ω(s)/U(s) = K_m K_a / (J s + B)``.

        Returns
        -------
        num, den : ndarray
            Polynomial coefficients in s, highest power first.
        """
        return np.array([self.Km * self.Ka]), np.array([self.J, self.B])

    @property
    def time_constant(self) -> float:
        """``J / B`` (s); infinite without viscous friction."""
        return self.J / self.B if self.B > 0 else float("inf")

    @property
    def dc_gain(self) -> float:
        """Steady speed per volt ``K_m K_a / B`` (rad/s/V); infinite without viscous friction."""
        return self.Km * self.Ka / self.B if self.B > 0 else float("inf")

    def step_response(self, t: ArrayLike, u: float = 1.0, omega0: float = 0.0) -> np.ndarray:
        """Closed-form speed (rad/s) after a voltage step u at t = 0, no Coulomb friction:
        ``ω(t) = ω_∞ + (ω₀ − ω_∞) e^{−B t / J}``, ``ω_∞ = K_m K_a u / B`` (``ω₀ + K_m K_a u t / J`` when B = 0).

        Parameters
        ----------
        t : array_like, shape (K,)
            Times, s (≥ 0).
        u : float
            The step's voltage, V.
        omega0 : float
            The speed at t = 0, rad/s.

        Returns
        -------
        ndarray, shape (K,)
            The speed at each time, rad/s.
        """
        t = np.asarray(t, dtype=float)
        u = as_scalar(u, "u")
        K = self.Km * self.Ka * u
        if self.B == 0:
            return omega0 + K * t / self.J
        w_inf = K / self.B
        return w_inf + (omega0 - w_inf) * np.exp(-self.B * t / self.J)

    def acceleration(self, omega: float, u: float, tau_d: float = 0.0) -> float:
        """The motor equation ``ω̇ = (K_m K_a u − B ω − τ_c(ω) − τ_d) / J`` (rad/s²).

        Parameters
        ----------
        omega : float
            Speed, rad/s (its sign picks the Coulomb friction τ_c; none at rest).
        u : float
            Control voltage, V.
        tau_d : float
            Disturbance torque, N·m (motor side).

        Returns
        -------
        float
            The angular acceleration, rad/s².
        """
        tc = self.Tc[0] if omega > 0 else (self.Tc[1] if omega < 0 else 0.0)
        return (self.Km * self.Ka * u - self.B * omega - tc - tau_d) / self.J

    def simulate(self, t: ArrayLike, u: ArrayLike, omega0: float = 0.0, tau_d: ArrayLike | None = None,
                 substeps: int = 10) -> np.ndarray:
        """Speed ω by numerical integration (RK4) of the motor equation, Coulomb friction included.

        Parameters
        ----------
        t : array_like, shape (K,)
            Strictly increasing times, s.
        u : float or array_like, shape (K,)
            Voltages, V, each held over the interval that starts at its time.
        omega0 : float
            The speed at ``t[0]``, rad/s.
        tau_d : array_like, shape (K,), optional
            Disturbance torques, N·m (motor side), held like ``u``; None: none.
        substeps : int
            RK4 steps per interval.

        Returns
        -------
        ndarray, shape (K,)
            The speed at each time, rad/s.

        Raises
        ------
        InputError
            Times that do not increase strictly.
        """
        t = as_vector(t, "t")
        if np.any(np.diff(t) <= 0):
            raise InputError("t: times must increase strictly")
        uu = np.broadcast_to(np.asarray(u, dtype=float), t.shape)
        dd = np.zeros_like(t) if tau_d is None else np.broadcast_to(np.asarray(tau_d, dtype=float), t.shape)
        w = np.empty_like(t)
        w[0] = omega0
        for k in range(len(t) - 1):
            h = (t[k + 1] - t[k]) / substeps
            x = w[k]
            for _ in range(int(substeps)):
                k1 = self.acceleration(x, uu[k], dd[k])
                k2 = self.acceleration(x + 0.5 * h * k1, uu[k], dd[k])
                k3 = self.acceleration(x + 0.5 * h * k2, uu[k], dd[k])
                k4 = self.acceleration(x + h * k3, uu[k], dd[k])
                x = x + h / 6 * (k1 + 2 * k2 + 2 * k3 + k4)
            w[k + 1] = x
        return w


def _gear_ratios(G: ArrayLike) -> np.ndarray:
    # G as a float array, InputError when a ratio is 0 (the gearbox checks of the two functions below)
    G = np.asarray(G, dtype=float)
    if np.any(G == 0):
        raise InputError(f"G: a gear ratio cannot be 0, got {G}")
    return G


def joint_from_motor(G: ArrayLike, Jm: ArrayLike = 0.0, Bm: ArrayLike = 0.0,
                     tau_c: ArrayLike = 0.0) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Motor-side inertia, viscous friction and a torque seen from the joint through a gearbox G.

    ``(ˡJ, ˡB, ˡτ) = (G² Jm, G² Bm, G τ)`` (Lecture 8). Scalars or arrays (broadcast).

    Parameters
    ----------
    G : float or array_like
        Gear ratio (motor turns per joint turn), non-zero.
    Jm : float or array_like, optional
        Motor-side inertia (kg·m²).
    Bm : float or array_like, optional
        Motor-side viscous friction (N·m·s/rad).
    tau_c : float or array_like, optional
        A motor-side torque (N·m), e.g. Coulomb friction.

    Returns
    -------
    J, B, tau : ndarray
        The same three seen from the joint.

    Raises
    ------
    InputError
        When a gear ratio is 0.

    Examples
    --------
    >>> [float(x) for x in joint_from_motor(100, 2e-4, 1e-3, 0.1)]
    [2.0, 10.0, 10.0]
    """
    G = _gear_ratios(G)
    return G * G * np.asarray(Jm, float), G * G * np.asarray(Bm, float), G * np.asarray(tau_c, float)


def effective_inertia(Jm: ArrayLike, M_jj: ArrayLike, G: ArrayLike) -> np.ndarray:
    """The inertia the motor of joint j sees: ``J = J_m + M_jj / G²`` (motor side; Lecture 8).

    ``M_jj`` changes with the pose — "M₂₂ varies a lot" (Lecture 8).

    Parameters
    ----------
    Jm : float or array_like
        Rotor inertia (kg·m²).
    M_jj : float or array_like
        The arm's inertia about joint j (diagonal of M(q), kg·m²).
    G : float or array_like
        Gear ratio, as for :func:`joint_from_motor`.

    Returns
    -------
    ndarray
        Effective inertia on the motor shaft (kg·m²).

    Raises
    ------
    InputError
        As for :func:`joint_from_motor`.

    Examples
    --------
    A 2 kg·m² link behind a 100:1 gearbox adds only 2e-4 kg·m² to a 2e-4 kg·m² rotor:

    >>> float(effective_inertia(2e-4, 2.0, 100))
    0.0004
    """
    G = _gear_ratios(G)
    return np.asarray(Jm, float) + np.asarray(M_jj, float) / (G * G)

# Former names (before the X_from_Y rule): they warn and call the new function.
reflect_to_joint = deprecated_alias(joint_from_motor, "reflect_to_joint")
