r"""What the arm carries and what it pushes on its base (Lecture 7).

* :func:`add_payload` — a payload rigidly held by the tool changes the last link's inertia;
* :func:`base_wrench` — the wrench the base must supply to the arm (Newton–Euler's outward pass
  continued to the base).
"""
from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike

from typing import Any

from robokit._arrays import as_array, as_scalar, as_vector
from robokit._deprecation import renamed_argument
from robokit.errors import InputError
from robokit.dynamics.newton_euler import _model, _radians
from robokit.spatial import lie

__all__ = ["add_payload", "base_wrench"]

_UNSET: Any = object()  # "not given" (base_wrench's former keyword Ftip=)


def add_payload(Mlist: ArrayLike, Glist: ArrayLike, mass: float, com: ArrayLike = (0.0, 0.0, 0.0),
                inertia: ArrayLike | None = None) -> np.ndarray:
    """Glist with a payload rigidly held at the end-effector frame added to the last link (Lecture 7).

    The spatial inertia moves between frames as ``G_a = Ad_{T_ba}ᵀ G_b Ad_{T_ba}`` (T_ba: pose of a
    in b); Mlist is unchanged (the link frame stays where it is).

    Parameters
    ----------
    Mlist : (n+1, 4, 4) array_like
        Link frames (Modern Robotics form); ``Mlist[n]`` places the end-effector in the last link.
    Glist : (n, 6, 6) array_like
        Spatial inertias of the links.
    mass : float
        Payload mass (kg), non-negative.
    com : (3,) array_like, optional
        Payload centre of mass in the end-effector frame (m); default the frame's origin.
    inertia : (3, 3) array_like, optional
        Rotational inertia about the payload's centre of mass, end-effector axes (kg·m²); default 0
        (a point mass).

    Returns
    -------
    (n, 6, 6) ndarray
        A new Glist (the input is not modified).

    Examples
    --------
    Half a kilogram in the planar two-link arm's hand (at its tip): the elbow now holds
    (1.5 + 0.5) kg × 0.8 m × g:

    >>> p = rk.load("twolink").poe
    >>> G2 = add_payload(p.Mlist, p.Glist, 0.5)
    >>> rk.gravity_forces([0, 0], [0, -9.81, 0], p.Mlist, G2, p.Slist).round(4)
    array([54.936, 15.696])
    """
    Mlist = as_array(Mlist, "Mlist", (None, 4, 4))
    Glist = np.array(as_array(Glist, "Glist", (len(Mlist) - 1, 6, 6)))
    mass = as_scalar(mass, "mass", nonnegative=True)
    com = as_vector(com, "com", 3)
    I = np.zeros((3, 3)) if inertia is None else as_array(inertia, "inertia", (3, 3))
    Gp = np.zeros((6, 6))
    Gp[:3, :3] = I
    Gp[3:, 3:] = mass * np.eye(3)
    # pose of the last link frame {n} in the payload frame {p}: {p} = {ee} translated by com
    T_ee_p = np.eye(4)
    T_ee_p[:3, 3] = com
    T_n_ee = Mlist[-1]
    T_n_p = T_n_ee @ T_ee_p
    T_p_n = np.linalg.inv(T_n_p)
    A = lie.adjoint(T_p_n[None])[0]
    Glist[-1] = Glist[-1] + A.T @ Gp @ A
    return Glist


def base_wrench(thetalist: ArrayLike, dthetalist: ArrayLike, ddthetalist: ArrayLike, g: ArrayLike,
                F_tip: ArrayLike = _UNSET, Mlist: ArrayLike = _UNSET, Glist: ArrayLike = _UNSET,
                Slist: ArrayLike = _UNSET, *, Ftip: ArrayLike = _UNSET) -> np.ndarray:
    """The wrench the base must apply to the arm, in the base frame {0} at its origin (Lecture 7).

    From the backward Newton–Euler pass: the wrench transmitted through joint 1, ``F₁``, carried to
    frame {0} with ``Ad_{T_{1,0}}ᵀ``. At rest it balances the arm's weight: ``f = −(Σ mᵢ) g``.

    Parameters
    ----------
    thetalist, dthetalist, ddthetalist : (n,) array_like
        Joint values, rates and accelerations (rad, rad/s, rad/s²).
    g : (3,) array_like
        Gravity in the base frame (m/s²).
    F_tip : (6,) array_like
        Wrench ``(m, f)`` the end-effector applies to the environment, in its frame (N·m, N).
        (Formerly ``Ftip=``, deprecated.)
    Mlist, Glist, Slist : (n+1, 4, 4), (n, 6, 6), (6, n) array_like
        The model: link frames (m), spatial inertias (kg·m², kg), screw axes (:mod:`robokit.dynamics.newton_euler`).

    Returns
    -------
    (6,) ndarray
        ``(m, f)``: moment about the base origin (N·m) and force (N), base axes.

    Examples
    --------
    The planar two-link arm held horizontal: the base pushes up with the weight
    (2 + 1.5) kg × 9.81 m/s² and twists with the shoulder torque (46.107 N·m, see
    :func:`robokit.gravity_forces`):

    >>> p = rk.load("twolink").poe
    >>> base_wrench([0, 0], [0, 0], [0, 0], [0, -9.81, 0], np.zeros(6), p.Mlist, p.Glist, p.Slist).round(4)
    array([ 0.   ,  0.   , 46.107,  0.   , 34.335,  0.   ])
    """
    F_tip = renamed_argument("base_wrench(Ftip=)", F_tip, Ftip, _UNSET, "base_wrench")
    if any(x is _UNSET for x in (F_tip, Mlist, Glist, Slist)):
        raise InputError("base_wrench: F_tip, Mlist, Glist and Slist are required")
    m = _model(Mlist, Glist, Slist)
    n = m.n
    th = _radians(m, as_vector(thetalist, "thetalist", n))
    dth = as_vector(dthetalist, "dthetalist", n)
    ddth = as_vector(ddthetalist, "ddthetalist", n)
    g = as_vector(g, "g", 3)
    Ftip = as_vector(F_tip, "F_tip", 6)
    Ad = m.transforms(th)
    A, G = m.AT, m.G
    V = np.zeros(6)
    Vd = np.r_[0.0, 0.0, 0.0, -g]
    Vs, Vds = [], []
    for i in range(n):
        V = Ad[i] @ V + A[i] * dth[i]
        Vd = Ad[i] @ Vd + (lie.ad(V) @ A[i]) * dth[i] + A[i] * ddth[i]
        Vs.append(V)
        Vds.append(Vd)
    F = Ftip
    Ad_next = m.Ad_tip
    for i in range(n - 1, -1, -1):
        F = Ad_next.T @ F + G[i] @ Vds[i] - lie.ad(Vs[i]).T @ G[i] @ Vs[i]
        Ad_next = Ad[i]
    # F is F₁ (in frame {1}); carried to {0}. The gravity used here is an upward base acceleration,
    # so F already contains the weight.
    return Ad[0].T @ F
