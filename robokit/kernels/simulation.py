r"""Closed-loop simulation stepped inside compiled code (Lecture 8, Modern Robotics ch. 11).

Two loops, each one kernel: the controller law, the plant's forward dynamics (the
articulated-body recursion of :mod:`robokit.kernels.dynamics`) and the integrator all run
without returning to Python between steps.

* :func:`simulate_control` — the seed's computed-torque loop with model error (Modern Robotics'
  ``SimulateControl``): per control period ``τ = M̃(θ)(θ̈_d + K_p e + K_i (∫e + e) + K_d ė) + h̃(θ, θ̇)``
  by Newton–Euler on the estimated model, then ``intRes`` Euler steps of the true plant.
* :func:`simulate_robot` — :func:`robokit.control.simulate` for the built-in controllers
  (``kind``: 0 PD + gravity compensation, 1 model feedforward + PD, 2 computed torque with an
  optional integral term, 3 independent-joint P/PI cascade), the plant with reflected motor
  inertia (added to each joint's ``Dᵢ``), viscous + Coulomb friction and a tip wrench,
  integrated by RK4 or explicit Euler with ``substeps`` steps per control period; the tip wrench
  of a period is resisted through ``J_b(q_k)ᵀ F_k`` at the period's start, held like the torque.

Both return a status instead of raising, so the Python wrapper can raise the same errors as
the Python loop: ``-1`` finished; ``k ≥ 0`` diverged during control period k (a non-finite state
or ``|q̇| > 10⁶``); ``-(k + 2)`` the controller produced a non-finite torque at period k
(``simulate_robot``) or the plant's inertia is not positive definite (``simulate_control``).
Arguments are C-contiguous float64 arrays (int64 for flags and counts).
"""
from __future__ import annotations

import math

import numpy as np

from robokit.kernels._jit import njit
from robokit.kernels.dynamics import aba_into, aba_workspace, link_screws, link_transforms, rnea_into, workspace

__all__ = ["simulate_control", "simulate_robot"]

_A1 = "float64[::1]"
_A2 = "float64[:, ::1]"
_A3 = "float64[:, :, ::1]"


@njit
def model_scratch(Mlist: np.ndarray, Slist: np.ndarray) -> tuple:
    """(A, Minv, Tl, E, V, Vd, v6, Ia, P, C, U, du, X3) for one model: constants and scratch."""
    n = Slist.shape[1]
    A, Minv, Tl, E, V, Vd, v6, K, X = workspace(n)
    link_screws(Mlist, Slist, A, Minv)
    Ia, P, C, U, du, X3 = aba_workspace(n)
    return A, Minv, Tl, E, V, Vd, v6, Ia, P, C, U, du, X3


@njit
def bad_state(q: np.ndarray, dq: np.ndarray) -> bool:
    """True when q or q̇ is not finite or some |q̇ᵢ| > 10⁶ (the divergence test of the Python loops)."""
    for i in range(q.shape[0]):
        if not (math.isfinite(q[i]) and math.isfinite(dq[i])) or abs(dq[i]) > 1e6:
            return True
    return False


@njit(f"Tuple(({_A2}, {_A2}, int64))({_A1}, {_A1}, {_A1}, {_A2}, {_A3}, {_A3}, {_A2}, {_A2}, {_A2}, {_A2}, "
      f"{_A1}, {_A3}, {_A3}, {_A1}, {_A1}, {_A1}, float64, int64)", interpret_while_compiling=False)
def simulate_control(thetalist: np.ndarray, dthetalist: np.ndarray, g: np.ndarray, Ftipmat: np.ndarray,
                     Mlist: np.ndarray, Glist: np.ndarray, Slist: np.ndarray, thetamatd: np.ndarray,
                     dthetamatd: np.ndarray, ddthetamatd: np.ndarray, gtilde: np.ndarray, Mtildelist: np.ndarray,
                     Gtildelist: np.ndarray, Kp: np.ndarray, Ki: np.ndarray, Kd: np.ndarray, dt: float,
                     intRes: int) -> tuple[np.ndarray, np.ndarray, int]:
    """(taumat, thetamat, status): the seed's computed-torque loop (see the module docstring)."""
    N, n = thetamatd.shape
    taumat = np.zeros((N, n))
    thetamat = np.zeros((N, n))
    A, Minv, Tl, E, V, Vd, v6, Ia, P, C, U, du, X3 = model_scratch(Mlist, Slist)
    Ac, Minvc, Tlc, Ec, Vc, Vdc, v6c, _, _, _, _, _, _ = model_scratch(Mtildelist, Slist)
    theta, dtheta = thetalist.copy(), dthetalist.copy()
    eint, e, a, tau, ddtheta = np.zeros(n), np.empty(n), np.empty(n), np.empty(n), np.empty(n)
    zero6, zeros = np.zeros(6), np.zeros(n)
    h = dt / intRes
    for i in range(N):
        for j in range(n):
            e[j] = thetamatd[i, j] - theta[j]
            a[j] = ddthetamatd[i, j] + Kp[j] * e[j] + Ki[j] * (eint[j] + e[j]) + Kd[j] * (dthetamatd[i, j] - dtheta[j])
        link_transforms(Ac, Minvc, theta, Tlc, Ec)
        rnea_into(Ac, Tlc, Gtildelist, dtheta, a, gtilde, zero6, Vc, Vdc, v6c, tau)  # M̃ a + h̃
        for j in range(n):
            if not math.isfinite(tau[j]) or abs(tau[j]) > 1e12:
                return taumat, thetamat, i
        for _ in range(intRes):
            link_transforms(A, Minv, theta, Tl, E)
            if not aba_into(A, Tl, Glist, dtheta, tau, g, Ftipmat[i], zeros, V, v6, Ia, P, C, U, du, X3, ddtheta):
                return taumat, thetamat, -(i + 2)
            for j in range(n):
                theta[j], dtheta[j] = theta[j] + h * dtheta[j], dtheta[j] + h * ddtheta[j]
            if bad_state(theta, dtheta):
                return taumat, thetamat, i
        for j in range(n):
            taumat[i, j] = tau[j]
            thetamat[i, j] = theta[j]
            eint[j] = eint[j] + dt * (thetamatd[i, j] - theta[j])  # MR: the error after the period
    return taumat, thetamat, -1


@njit
def plant_accel(q: np.ndarray, dq: np.ndarray, tau: np.ndarray, Glist: np.ndarray, g: np.ndarray, F: np.ndarray,
                arm: np.ndarray, B: np.ndarray, Tc: np.ndarray, use_fric: int, sc: tuple,
                taup: np.ndarray, out: np.ndarray) -> None:
    """out ← q̈ of the plant: ABA at (q, q̇) under τ − τ_f(q̇), the tip wrench F and the armature."""
    A, Minv, Tl, E, V, Vd, v6, Ia, P, C, U, du, X3 = sc
    for j in range(q.shape[0]):
        taup[j] = tau[j]
        if use_fric:
            f = B[j] * dq[j]
            if dq[j] > 0:
                f += Tc[j, 0]
            elif dq[j] < 0:
                f += Tc[j, 1]
            taup[j] -= f
    link_transforms(A, Minv, q, Tl, E)
    aba_into(A, Tl, Glist, dq, taup, g, F, arm, V, v6, Ia, P, C, U, du, X3, out)


@njit
def controller_rnea(q: np.ndarray, dq: np.ndarray, a: np.ndarray, Gc: np.ndarray, gc: np.ndarray,
                    armc: np.ndarray, sc: tuple, zero6: np.ndarray, out: np.ndarray) -> None:
    """out ← the controller model's inverse dynamics M(q) a + c(q, q̇) + g(q) (+ armature · a)."""
    A, Minv, Tl, E, V, Vd, v6, _, _, _, _, _, _ = sc
    link_transforms(A, Minv, q, Tl, E)
    rnea_into(A, Tl, Gc, dq, a, gc, zero6, V, Vd, v6, out)
    for j in range(q.shape[0]):
        out[j] += armc[j] * a[j]


@njit(f"Tuple(({_A2}, {_A2}, {_A2}, int64))({_A1}, {_A1}, {_A1}, {_A2}, {_A2}, {_A2}, {_A3}, {_A3}, {_A2}, {_A1}, "
      f"{_A1}, {_A1}, {_A2}, int64, {_A2}, int64, {_A3}, {_A3}, {_A2}, {_A1}, {_A1}, {_A1}, {_A1}, {_A1}, {_A1}, "
      "int64, int64, int64, int64)", interpret_while_compiling=False)
def simulate_robot(q0: np.ndarray, dq0: np.ndarray, t: np.ndarray, q_des: np.ndarray, dq_des: np.ndarray,
                   ddq_des: np.ndarray, Mlist: np.ndarray, Glist: np.ndarray, Slist: np.ndarray, g: np.ndarray,
                   arm: np.ndarray, B: np.ndarray, Tc: np.ndarray, use_fric: int, F: np.ndarray, kind: int,
                   Mc: np.ndarray, Gc: np.ndarray, Sc: np.ndarray, gc: np.ndarray, armc: np.ndarray, Kp: np.ndarray,
                   Kv: np.ndarray, Ki: np.ndarray, J_nom: np.ndarray, velocity_ff: int, use_gravity: int,
                   substeps: int, method: int) -> tuple[np.ndarray, np.ndarray, np.ndarray, int]:
    """(Q, DQ, TAU, status) over the K control instants of t (see the module docstring); F (K, 6)
    the tip wrench per period; method 0 RK4, 1 explicit Euler."""
    K, n = q_des.shape
    Q, DQ, TAU = np.zeros((K, n)), np.zeros((K, n)), np.zeros((K, n))
    sp = model_scratch(Mlist, Slist)
    sc = model_scratch(Mc, Sc)
    q, dq = q0.copy(), dq0.copy()
    tau, taup, integral, ev, a, zeros, zero6 = (np.empty(n), np.empty(n), np.zeros(n), np.empty(n), np.empty(n),
                                                np.zeros(n), np.zeros(6))
    k1v, k2v, k3v, k4v, qa, dqa = np.empty(n), np.empty(n), np.empty(n), np.empty(n), np.empty(n), np.empty(n)
    tau_k, zero3 = np.empty(n), np.zeros(3)
    h = (t[1] - t[0]) / substeps
    for k in range(K):
        for j in range(n):
            Q[k, j], DQ[k, j] = q[j], dq[j]
        # the controller law at t_k
        if kind == 0:  # PD + gravity compensation
            controller_rnea(q, zeros, zeros, Gc, gc, armc, sc, zero6, tau)
            for j in range(n):
                tau[j] = Kp[j] * (q_des[k, j] - q[j]) + Kv[j] * (dq_des[k, j] - dq[j]) + tau[j]
        elif kind == 1:  # inverse dynamics along the desired trajectory + PD
            controller_rnea(q_des[k], dq_des[k], ddq_des[k], Gc, gc, armc, sc, zero6, tau)
            for j in range(n):
                tau[j] = tau[j] + Kp[j] * (q_des[k, j] - q[j]) + Kv[j] * (dq_des[k, j] - dq[j])
        elif kind == 2:  # computed torque
            for j in range(n):
                a[j] = (ddq_des[k, j] + Kv[j] * (dq_des[k, j] - dq[j]) + Kp[j] * (q_des[k, j] - q[j])
                        + Ki[j] * integral[j])
            controller_rnea(q, dq, a, Gc, gc, armc, sc, zero6, tau)
        else:  # independent joints: position P around a velocity P/PI loop on a nominal inertia
            for j in range(n):
                ev[j] = Kp[j] * (q_des[k, j] - q[j]) + (dq_des[k, j] if velocity_ff else 0.0) - dq[j]
                tau[j] = J_nom[j] * (Kv[j] * ev[j] + Ki[j] * integral[j])
            if use_gravity:
                controller_rnea(q, zeros, zeros, Gc, gc, armc, sc, zero6, a)
                for j in range(n):
                    tau[j] = tau[j] + a[j]
        for j in range(n):
            if not math.isfinite(tau[j]):
                return Q, DQ, TAU, -(k + 2)
            TAU[k, j] = tau[j]
        if k == K - 1:
            break
        dtk = t[k + 1] - t[k]
        for j in range(n):  # the controller's state advances once per period, from the state at t_k
            if kind == 2:
                integral[j] = integral[j] + dtk * (q_des[k, j] - q[j])
            elif kind == 3:
                integral[j] = integral[j] + dtk * ev[j]
        # the tip wrench is resisted through J_b(q_k)ᵀ F_k, held over the period like the torque
        # (as the Python loop does): Newton–Euler with no motion and no gravity gives J_bᵀ F
        A, Minv, Tl, E, V, Vd, v6 = sp[0], sp[1], sp[2], sp[3], sp[4], sp[5], sp[6]
        link_transforms(A, Minv, q, Tl, E)
        rnea_into(A, Tl, Glist, zeros, zeros, zero3, F[k], V, Vd, v6, taup)
        for j in range(n):
            tau_k[j] = tau[j] - taup[j]
        Fk = zero6
        for _ in range(substeps):
            if method == 1:
                plant_accel(q, dq, tau_k, Glist, g, Fk, arm, B, Tc, use_fric, sp, taup, k1v)
                for j in range(n):
                    q[j], dq[j] = q[j] + h * dq[j], dq[j] + h * k1v[j]
                continue
            plant_accel(q, dq, tau_k, Glist, g, Fk, arm, B, Tc, use_fric, sp, taup, k1v)
            for j in range(n):
                qa[j], dqa[j] = q[j] + 0.5 * h * dq[j], dq[j] + 0.5 * h * k1v[j]
            plant_accel(qa, dqa, tau_k, Glist, g, Fk, arm, B, Tc, use_fric, sp, taup, k2v)
            for j in range(n):
                qa[j] = q[j] + 0.5 * h * (dq[j] + 0.5 * h * k1v[j])
                dqa[j] = dq[j] + 0.5 * h * k2v[j]
            plant_accel(qa, dqa, tau_k, Glist, g, Fk, arm, B, Tc, use_fric, sp, taup, k3v)
            for j in range(n):
                qa[j] = q[j] + h * (dq[j] + 0.5 * h * k2v[j])
                dqa[j] = dq[j] + h * k3v[j]
            plant_accel(qa, dqa, tau_k, Glist, g, Fk, arm, B, Tc, use_fric, sp, taup, k4v)
            for j in range(n):
                k2q = dq[j] + 0.5 * h * k1v[j]
                k3q = dq[j] + 0.5 * h * k2v[j]
                k4q = dq[j] + h * k3v[j]
                q[j] = q[j] + h / 6.0 * (dq[j] + 2.0 * k2q + 2.0 * k3q + k4q)
                dq[j] = dq[j] + h / 6.0 * (k1v[j] + 2.0 * k2v[j] + 2.0 * k3v[j] + k4v[j])
        if bad_state(q, dq):
            return Q, DQ, TAU, k
    return Q, DQ, TAU, -1
