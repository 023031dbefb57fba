r"""Every step of Craig's recursive Newton–Euler on a DH table (Lecture 7), for checking a hand
derivation row by row: ``dh_inverse_dynamics(table, q, dq, ddq, trace=True)`` returns
``(tau, trace)``.

The recursion is the one of :mod:`robokit.dynamics.dh_newton_euler` (which runs it compiled),
written here as plain numpy so that each intermediate can be kept:

outward, i = 1 … n (frame {i} axes; ``ⁱ⁺¹R_i`` from frame {i} to {i+1}, ``ⁱpᵢ₊₁`` the origin of
{i+1} in {i}):

    ω, ω̇, v̇ of frame {i} (v̇₀ = −g: gravity as an upward acceleration of the base),
    v̇_Cᵢ = ω̇ᵢ × p_Cᵢ + ωᵢ × (ωᵢ × p_Cᵢ) + v̇ᵢ,   Fᵢ = mᵢ v̇_Cᵢ,   Nᵢ = I_Cᵢ ω̇ᵢ + ωᵢ × I_Cᵢ ωᵢ;

inward, i = n … 1 (``f_{n+1}``, ``n_{n+1}`` the tool's wrench on the environment):

    fᵢ = ⁱRᵢ₊₁ fᵢ₊₁ + Fᵢ,   nᵢ = Nᵢ + ⁱRᵢ₊₁ nᵢ₊₁ + p_Cᵢ × Fᵢ + ⁱpᵢ₊₁ × ⁱRᵢ₊₁ fᵢ₊₁,

fᵢ, nᵢ being the force and the moment (about the origin of frame {i}) that link i−1 exerts on
link i, in frame {i} axes. The joint torque is the component of the moment about the joint axis:
``τᵢ = nᵢ·ẑ`` (modified convention; ``fᵢ·ẑ`` prismatic), or ``ẑ·(R nᵢ + p × R fᵢ)`` in frame {i−1}
(standard; ``ẑ·R fᵢ`` prismatic).
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import ArrayLike

from robokit._arrays import as_vector
from robokit.kinematics.dh_trace import format_trace, link_transforms

if TYPE_CHECKING:
    from robokit.description.dh import DHTable

__all__ = ["DHDynamicsTrace", "dh_newton_euler_trace"]

_Z = np.array([0.0, 0.0, 1.0])


@dataclass(frozen=True)
class DHDynamicsTrace:
    """The intermediate quantities of Craig's Newton–Euler (:func:`dh_newton_euler_trace`).

    One row per link i = 1..n, each in frame {i}'s axes (Lecture 7's symbols). ``print(trace)`` is
    the per-link table.

    Attributes
    ----------
    omega, domega : (n, 3) ndarray
        ⁱωᵢ (rad/s) and ⁱω̇ᵢ (rad/s²).
    dv : (n, 3) ndarray
        ⁱv̇ᵢ, the acceleration of the origin of frame {i} (m/s², gravity included as v̇₀ = −g).
    dv_com : (n, 3) ndarray
        v̇_Cᵢ, the acceleration of link i's centre of mass (m/s²).
    F, N : (n, 3) ndarray
        The inertial force mᵢ v̇_Cᵢ (N) and moment I_Cᵢ ω̇ᵢ + ωᵢ × I_Cᵢ ωᵢ (N·m).
    f, n : (n, 3) ndarray
        ⁱfᵢ (N), ⁱnᵢ (N·m): the force and moment link i−1 exerts on link i, about the origin of
        frame {i}.
    tau : (n,) ndarray
        The joint torques/forces (N·m / N).
    convention : str
        "standard" or "modified".
    """

    omega: np.ndarray
    domega: np.ndarray
    dv: np.ndarray
    dv_com: np.ndarray
    F: np.ndarray
    N: np.ndarray
    f: np.ndarray
    n: np.ndarray
    tau: np.ndarray
    convention: str

    def __str__(self) -> str:
        rows = [("ω_i (rad/s)", self.omega), ("ω̇_i (rad/s²)", self.domega), ("v̇_i (m/s²)", self.dv),
                ("v̇_Ci (m/s²)", self.dv_com), ("F_i (N)", self.F), ("N_i (N·m)", self.N),
                ("f_i (N)", self.f), ("n_i (N·m)", self.n)]
        body = format_trace(f"Newton–Euler iterations ({self.convention} DH), frame {{i}} axes", rows,
                            self.omega.shape[0])
        taus = "  ".join(f"τ{i + 1} = {float(t) + 0.0:.6g}" for i, t in enumerate(self.tau))
        return f"{body}\n{taus}"


def dh_newton_euler_trace(table: DHTable, q: ArrayLike, dq: ArrayLike, ddq: ArrayLike,
                          gravity: ArrayLike | None = None,
                          F_tip: ArrayLike | None = None) -> tuple[np.ndarray, DHDynamicsTrace]:
    """Craig's recursive Newton–Euler on a DH table, every intermediate kept (Lecture 7).

    Parameters
    ----------
    table : DHTable
        Standard or modified, R and P joints, with the links' masses, centres of mass (frame {i})
        and inertias (about the COM, frame-{i} axes).
    q, dq, ddq : (n,) array_like
        Joint values, rates and accelerations (rad, m).
    gravity : (3,) array_like, optional
        In base_link (default the table's gravity), m/s².
    F_tip : (6,) array_like, optional
        The wrench (moment; force) the tool exerts on the environment, in the tool frame.

    Returns
    -------
    tau : (n,) ndarray
        Joint torques/forces (N·m, N), equal to :func:`robokit.dynamics.dh_inverse_dynamics`.
    trace : DHDynamicsTrace
        The outward and inward quantities per link.

    Examples
    --------
    The planar two-link arm held horizontal: gravity enters as an upward base acceleration
    (v̇ = 9.81 m/s² along y), so the inertial forces are the weights m₁g = 19.62 N and
    m₂g = 14.715 N, and joint 1 transmits both (34.335 N); ``print(tr)`` shows the whole table:

    >>> tau, tr = dh_newton_euler_trace(rk.load("twolink").dh, [0, 0], [0, 0], [0, 0])
    >>> tau.round(4), tr.F[:, 1].round(4), round(float(tr.f[0, 1]), 4)
    (array([46.107, 11.772]), array([19.62 , 14.715]), 34.335)
    """
    nj = table.n
    q = as_vector(q, "q", nj)
    dq = as_vector(dq, "dq", nj)
    ddq = as_vector(ddq, "ddq", nj)
    g = as_vector(table.gravity if gravity is None else gravity, "gravity", 3)
    Ft = as_vector(np.zeros(6) if F_tip is None else F_tip, "F_tip", 6)
    modified = table.convention == "modified"
    signs = np.array([-1.0 if getattr(link, "flip", False) else 1.0 for link in table.links])
    Ts = link_transforms(table, q)
    base, tool = np.asarray(table.base, float), np.asarray(table.tool, float)

    omega, domega, dv, dv_com, Fs, Ns = (np.zeros((nj, 3)) for _ in range(6))
    w, wd, vd = np.zeros(3), np.zeros(3), base[:3, :3].T @ (-g)
    for i, T in enumerate(Ts):
        R, p = T[:3, :3], T[:3, 3]
        rate, acc = signs[i] * dq[i], signs[i] * ddq[i]
        prismatic = table.links[i].joint == "P"
        th, thd = (0.0, 0.0) if prismatic else (rate, acc)
        if modified:
            w_new = R.T @ w + th * _Z
            wd_new = R.T @ wd + np.cross(R.T @ w, th * _Z) + thd * _Z
            vd_new = R.T @ (np.cross(wd, p) + np.cross(w, np.cross(w, p)) + vd)
            if prismatic:
                vd_new = vd_new + 2.0 * np.cross(w_new, rate * _Z) + acc * _Z
        else:
            w1 = w + th * _Z
            wd1 = wd + np.cross(w, th * _Z) + thd * _Z
            a = vd + np.cross(wd1, p) + np.cross(w1, np.cross(w1, p))
            if prismatic:
                a = a + 2.0 * np.cross(w1, rate * _Z) + acc * _Z
            w_new, wd_new, vd_new = R.T @ w1, R.T @ wd1, R.T @ a
        w, wd, vd = w_new, wd_new, vd_new
        link = table.links[i]
        pc = np.asarray(link.com, float)
        I = link.inertia_matrix
        omega[i], domega[i], dv[i] = w, wd, vd
        dv_com[i] = np.cross(wd, pc) + np.cross(w, np.cross(w, pc)) + vd
        Fs[i] = link.mass * dv_com[i]
        Ns[i] = I @ wd + np.cross(w, I @ w)

    f_all, n_all, tau = np.zeros((nj, 3)), np.zeros((nj, 3)), np.zeros(nj)
    # the tool's wrench on the environment, carried into frame {n} about its origin
    f_out = tool[:3, :3] @ Ft[3:]
    n_out = tool[:3, :3] @ Ft[:3] + np.cross(tool[:3, 3], f_out)
    p_next = np.zeros(3)  # origin of the next frame in this one (the next wrench is already about it)
    for i in range(nj - 1, -1, -1):
        pc = np.asarray(table.links[i].com, float)
        f = f_out + Fs[i]
        nm = Ns[i] + n_out + np.cross(pc, Fs[i]) + np.cross(p_next, f_out)
        f_all[i], n_all[i] = f, nm
        R, p = Ts[i][:3, :3], Ts[i][:3, 3]
        prismatic = table.links[i].joint == "P"
        if modified:
            tau[i] = f[2] if prismatic else nm[2]
        else:
            tau[i] = (R @ f)[2] if prismatic else (R @ nm + np.cross(p, R @ f))[2]
        tau[i] *= signs[i]
        f_out, n_out, p_next = R @ f, R @ nm, p
    trace = DHDynamicsTrace(omega, domega, dv, dv_com, Fs, Ns, f_all, n_all, tau.copy(), table.convention)
    return tau, trace
