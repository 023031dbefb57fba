r"""The seed library's control functions (seed 004 §6), Modern Robotics semantics.

``computed_torque`` evaluates one control law step with the *estimated* model;
``simulate_control`` runs it in closed loop on the *true* plant:

    τ = M̃(θ)(θ̈_d + K_p e + K_i (eint + e) + K_d ė) + h̃(θ, θ̇),   e = θ_d − θ,

where M̃ and h̃ (Coriolis, centrifugal and gravity terms) come from ``Mtildelist``,
``Gtildelist`` and ``gtilde``, while the plant uses ``Mlist``, ``Glist`` and ``g``. The
plant is integrated with ``intRes`` Euler steps of ``dt/intRes`` per control period, and
the integral of the error is accumulated as ``eint ← eint + e·dt`` (seed 004, MR 11.4).
"""
from __future__ import annotations

from typing import NoReturn

import numpy as np
from numpy.typing import ArrayLike

from robokit._arrays import as_array, as_matrix, as_scalar, as_vector, kernel_array
from robokit._units import check_radians, radian_ranges, revolute_columns
from robokit.control.controllers import gains
from robokit.errors import InputError

__all__ = ["computed_torque", "simulate_control"]


def _diverged(i: int, dt: float, taumat: np.ndarray, thetamat: np.ndarray) -> NoReturn:
    from robokit.errors import DivergenceError

    raise DivergenceError(
        f"simulate_control: the closed loop diverged in period {i} (t = {i * dt:g} s); the gains, dt or intRes "
        "make it unstable (the result so far is in .partial as (taumat, thetamat))",
        (taumat[:i].copy(), thetamat[:i].copy()),
    )


def _radians(Slist: ArrayLike, **values: np.ndarray) -> None:
    """The degrees check (robokit._units) of joint values for the screw axes ``Slist``: the first
    argument that looks like degrees is warned of (one warning per call)."""
    n = next(iter(values.values())).shape[-1]
    lo, hi = radian_ranges(revolute_columns(as_matrix(Slist, "Slist", 6, n)))
    for name, v in values.items():
        if check_radians(v, lo, hi, name):
            return


def computed_torque(thetalist: ArrayLike, dthetalist: ArrayLike, eint: ArrayLike, g: ArrayLike, Mlist: ArrayLike,
                    Glist: ArrayLike, Slist: ArrayLike, thetalistd: ArrayLike, dthetalistd: ArrayLike,
                    ddthetalistd: ArrayLike, Kp: ArrayLike, Ki: ArrayLike, Kd: ArrayLike) -> np.ndarray:
    """Joint torques of the computed-torque (PID) law, Modern Robotics eq. 11.35 (seed 004 §6).

    ``τ = M̃(θ)(θ̈_d + K_p e + K_i (eint + e) + K_d ė) + h̃(θ, θ̇)`` with ``e = θ_d − θ``, computed as
    one :func:`robokit.inverse_dynamics` call on the (estimated) model with no tip wrench; the
    integral term includes the current error, as in Modern Robotics' ``ComputedTorque``.

    Parameters
    ----------
    thetalist, dthetalist : (n,) array_like
        Measured joint values θ (rad) and rates θ̇ (rad/s).
    eint : (n,) array_like
        Time integral of the error so far (rad·s).
    g : (3,) array_like
        Gravity in the base frame (m/s²) of the controller's model.
    Mlist : (n+1, 4, 4) array_like
        The controller's (estimated) model: link frames at the centres of mass, each in the previous
        one (Modern Robotics form, metres).
    Glist : (n, 6, 6) array_like
        Spatial inertias of the links in their centre-of-mass frames (kg·m², kg).
    Slist : (6, n) array_like
        Space-frame screw axes, one column per joint, ``(ω; v)``.
    thetalistd, dthetalistd, ddthetalistd : (n,) array_like
        Desired θ_d (rad), θ̇_d (rad/s), θ̈_d (rad/s²).
    Kp, Ki, Kd : float or (n,) array_like
        Gains (1/s², 1/s³, 1/s), scalars or one per joint; finite and non-negative.

    Returns
    -------
    (n,) ndarray
        τ (N·m; N for prismatic joints).

    Raises
    ------
    InputError
        On a wrong length, a negative or non-finite gain, or a bad model.

    Examples
    --------
    The planar two-link arm at rest, horizontal (θ = 0), asked to be 0.1 rad further on joint 1 with
    Kp = 20: ``τ = M(0) (20 × 0.1, 0) + g(0)`` with ``M(0) = [[6.86, 2.16], [2.16, 0.96]]`` and
    ``g(0) = (46.107, 11.772)``:

    >>> p = rk.load("twolink").poe
    >>> z = np.zeros(2)
    >>> computed_torque(z, z, z, [0, -9.81, 0], p.Mlist, p.Glist, p.Slist, [0.1, 0], z, z,
    ...                 20, 0, 18).round(4)
    array([59.827, 16.092])
    """
    from robokit.dynamics import inverse_dynamics

    theta = as_vector(thetalist, "thetalist")
    n = len(theta)
    dtheta = as_vector(dthetalist, "dthetalist", n)
    thd = as_vector(thetalistd, "thetalistd", n)
    _radians(Slist, thetalist=theta, thetalistd=thd)
    e = thd - theta
    edot = as_vector(dthetalistd, "dthetalistd", n) - dtheta
    a = (as_vector(ddthetalistd, "ddthetalistd", n) + gains(Kp, n, "Kp") * e
         + gains(Ki, n, "Ki") * (as_vector(eint, "eint", n) + e) + gains(Kd, n, "Kd") * edot)
    # M(θ) a + h(θ, θ̇) is inverse dynamics with θ̈ = a and no tip wrench
    return inverse_dynamics(theta, dtheta, a, g, np.zeros(6), Mlist, Glist, Slist)


def simulate_control(thetalist: ArrayLike, dthetalist: ArrayLike, g: ArrayLike, Ftipmat: ArrayLike, Mlist: ArrayLike,
                     Glist: ArrayLike, Slist: ArrayLike, thetamatd: ArrayLike, dthetamatd: ArrayLike,
                     ddthetamatd: ArrayLike, gtilde: ArrayLike, Mtildelist: ArrayLike, Gtildelist: ArrayLike,
                     Kp: ArrayLike, Ki: ArrayLike, Kd: ArrayLike, dt: float,
                     intRes: int, *, compiled: bool = True) -> tuple[np.ndarray, np.ndarray]:
    """Closed-loop computed-torque simulation with model error (seed 004 §6, MR ``SimulateControl``).

    At each control period k the law of :func:`computed_torque` (on the estimated model
    ``gtilde``, ``Mtildelist``, ``Gtildelist``) gives τ, held while the true plant (``g``,
    ``Mlist``, ``Glist``) is integrated with ``intRes`` Euler steps of ``dt/intRes``; the error
    integral is updated with the error at the end of the period (``eint ← eint + e·dt``). Unlike
    Modern Robotics' version it plots nothing; use :func:`robokit.control.plot.plot_tracking`.

    Parameters
    ----------
    thetalist, dthetalist : (n,) array_like
        Initial joint values (rad) and rates (rad/s).
    g : (3,) array_like
        True gravity in the base frame (m/s²).
    Ftipmat : (N, 6) array_like
        Tip wrench ``(m, f)`` at each period, end-effector frame (N·m, N).
    Mlist : (n+1, 4, 4) array_like
        The true plant: link frames at the centres of mass, each in the previous one (Modern
        Robotics form, metres).
    Glist : (n, 6, 6) array_like
        Spatial inertias of the links in their centre-of-mass frames (kg·m², kg).
    Slist : (6, n) array_like
        Space-frame screw axes, one column per joint, ``(ω; v)``.
    thetamatd, dthetamatd, ddthetamatd : (N, n) array_like
        Desired trajectory sampled every ``dt`` (rad, rad/s, rad/s²).
    gtilde : (3,) array_like
        The controller's gravity estimate (m/s²).
    Mtildelist : (n+1, 4, 4) array_like
        The controller's estimated link frames.
    Gtildelist : (n, 6, 6) array_like
        The controller's estimated spatial inertias.
    Kp, Ki, Kd : float or (n,) array_like
        Gains (1/s², 1/s³, 1/s).
    dt : float
        Control period (s), positive.
    intRes : int
        Euler steps of the plant per period (≥ 1).
    compiled : bool, optional
        True (default) steps the whole loop — control law, Newton–Euler on the estimated model,
        articulated-body forward dynamics of the plant, Euler steps — inside one compiled kernel
        (:mod:`robokit.kernels.simulation`); False runs the same loop in Python over
        :func:`robokit.inverse_dynamics` and :func:`robokit.forward_dynamics` (equal to 1e-12).

    Returns
    -------
    taumat : (N, n) ndarray
        The commanded torques, row k over period k (N·m).
    thetamat : (N, n) ndarray
        The actual joint values at the end of each period (row k: after integrating period k), as
        in Modern Robotics.

    Raises
    ------
    DivergenceError
        When the closed loop blows up (the result so far is in ``.partial``).
    InputError
        On bad arguments or a plant mass matrix that is not positive definite.

    Examples
    --------
    A 3-step trajectory holding the planar two-link arm horizontal, with a perfect model: the
    torques are the gravity torques and the arm does not move:

    >>> p = rk.load("twolink").poe
    >>> g, N = [0, -9.81, 0], 3
    >>> Z = np.zeros((N, 2))
    >>> taumat, thetamat = simulate_control([0, 0], [0, 0], g, np.zeros((N, 6)), p.Mlist, p.Glist, p.Slist,
    ...                                     Z, Z, Z, g, p.Mlist, p.Glist, 20, 10, 18, 0.01, 8)
    >>> taumat.shape, thetamat.shape
    ((3, 2), (3, 2))
    >>> taumat[0].round(4), bool(np.allclose(thetamat, 0))
    (array([46.107, 11.772]), True)
    """
    from robokit.dynamics import forward_dynamics, inverse_dynamics

    theta = as_vector(thetalist, "thetalist").copy()
    n = len(theta)
    dtheta = as_vector(dthetalist, "dthetalist", n).copy()
    thetamatd = as_array(thetamatd, "thetamatd", (None, n))
    N = thetamatd.shape[0]
    dthetamatd = as_array(dthetamatd, "dthetamatd", (N, n))
    ddthetamatd = as_array(ddthetamatd, "ddthetamatd", (N, n))
    Ftipmat = as_array(Ftipmat, "Ftipmat", (N, 6))
    dt = as_scalar(dt, "dt", positive=True)
    intRes = int(intRes)
    if intRes < 1:
        raise InputError(f"intRes: expected a positive integer, got {intRes}")
    Kp, Ki, Kd = gains(Kp, n, "Kp"), gains(Ki, n, "Ki"), gains(Kd, n, "Kd")
    _radians(Slist, thetalist=theta, thetamatd=thetamatd)
    if compiled:
        from robokit.dynamics.newton_euler import checked_model
        from robokit.kernels.simulation import simulate_control as kernel

        Ml, Gl, Sl = checked_model(Mlist, Glist, Slist)
        Mt, Gt, _ = checked_model(Mtildelist, Gtildelist, Slist)
        c = kernel_array  # writeable too: a robot's gravity is read-only
        taumat, thetamat, status = kernel(c(theta), c(dtheta), c(as_vector(g, "g", 3)), c(Ftipmat), Ml, Gl, Sl,
                                          c(thetamatd), c(dthetamatd), c(ddthetamatd),
                                          c(as_vector(gtilde, "gtilde", 3)), Mt, Gt, c(Kp), c(Ki), c(Kd), dt, intRes)
        if status >= 0:
            _diverged(int(status), dt, taumat, thetamat)
        if status < -1:
            raise InputError("Glist: the plant's mass matrix is not positive definite along the trajectory "
                             "(a joint drives no inertia)")
        return taumat, thetamat
    h = dt / intRes
    eint = np.zeros(n)
    taumat = np.empty((N, n))
    thetamat = np.empty((N, n))
    zero6 = np.zeros(6)
    for i in range(N):
        e = thetamatd[i] - theta
        a = ddthetamatd[i] + Kp * e + Ki * (eint + e) + Kd * (dthetamatd[i] - dtheta)
        tau = inverse_dynamics(theta, dtheta, a, gtilde, zero6, Mtildelist, Gtildelist, Slist)
        if not np.isfinite(tau).all() or np.abs(tau).max() > 1e12:
            _diverged(i, dt, taumat, thetamat)
        for _ in range(intRes):
            ddtheta = forward_dynamics(theta, dtheta, tau, g, Ftipmat[i], Mlist, Glist, Slist)
            theta, dtheta = theta + h * dtheta, dtheta + h * ddtheta
            if not (np.isfinite(theta).all() and np.isfinite(dtheta).all()) or np.abs(dtheta).max() > 1e6:
                _diverged(i, dt, taumat, thetamat)
        taumat[i] = tau
        thetamat[i] = theta
        eint = eint + dt * (thetamatd[i] - theta)  # MR: the error after the period
    return taumat, thetamat
