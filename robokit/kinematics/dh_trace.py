r"""Every step of the outward velocity iteration on a DH table (Lecture 6), for checking a hand
derivation row by row.

With ``ⁱRᵢ₊₁`` and ``ⁱpᵢ₊₁`` the rotation and origin of frame {i+1} in frame {i}, ẑ = (0, 0, 1),
and the base at rest (ω₀ = v₀ = 0 in frame {0}):

modified (Craig) convention — joint i+1 moves about ẑ of frame {i+1}::

    ⁱ⁺¹ωᵢ₊₁ = ⁱ⁺¹Rᵢ ⁱωᵢ + θ̇ᵢ₊₁ ẑ
    ⁱ⁺¹vᵢ₊₁ = ⁱ⁺¹Rᵢ (ⁱvᵢ + ⁱωᵢ × ⁱpᵢ₊₁) + ḋᵢ₊₁ ẑ

standard convention — joint i+1 moves about ẑ of frame {i}: the same in frame {i} with
``ω' = ⁱωᵢ + θ̇ᵢ₊₁ ẑ``, ``v' = ⁱvᵢ + ω' × ⁱpᵢ₊₁ + ḋᵢ₊₁ ẑ``, then rotated into {i+1}.

Row i of ``omega``/``v`` is frame {i} (row 0 the base frame {0}, at rest); the tool frame is not
included. The compiled :func:`robokit.kinematics.dh_jacobian` runs the same recursion.
"""
from __future__ import annotations

import unicodedata
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import ArrayLike

from robokit._arrays import as_vector

if TYPE_CHECKING:
    from robokit.description.dh import DHTable

__all__ = ["DHVelocityTrace", "dh_velocity_trace", "dh_link_transform", "format_trace"]

_Z = np.array([0.0, 0.0, 1.0])


def dh_link_transform(a: float, alpha: float, d: float, theta: float, modified: bool) -> np.ndarray:
    """ⁱ⁻¹Tᵢ (4×4) of one DH row (Lecture 4).

    Standard ``Rz(θ) Tz(d) Tx(a) Rx(α)``; modified (Craig) ``Rx(α) Tx(a) Rz(θ) Tz(d)``.

    Parameters
    ----------
    a, alpha, d, theta : float
        The row's link length (m), twist (rad), offset (m) and angle (rad, the joint value already
        added); for the modified convention a and α are a_{i−1}, α_{i−1}.
    modified : bool
        True for the modified convention.

    Returns
    -------
    (4, 4) ndarray
        The pose of frame {i} in frame {i−1}.

    Examples
    --------
    >>> dh_link_transform(1.0, 0.0, 0.0, np.pi / 2, False)[:3, 3].round(4)
    array([0., 1., 0.])
    """
    ct, st, ca, sa = np.cos(theta), np.sin(theta), np.cos(alpha), np.sin(alpha)
    if modified:
        return np.array([[ct, -st, 0.0, a], [st * ca, ct * ca, -sa, -sa * d],
                         [st * sa, ct * sa, ca, ca * d], [0.0, 0.0, 0.0, 1.0]])
    return np.array([[ct, -st * ca, st * sa, a * ct], [st, ct * ca, -ct * sa, a * st],
                     [0.0, sa, ca, d], [0.0, 0.0, 0.0, 1.0]])


def link_transforms(table: DHTable, q: np.ndarray) -> list[np.ndarray]:
    """The n link transforms ⁱ⁻¹Tᵢ(qᵢ) of a table (a flipped joint enters as −qᵢ)."""
    Ts = []
    for link, qi in zip(table.links, q):
        qi = -qi if getattr(link, "flip", False) else qi
        d, theta = (link.d + qi, link.theta) if link.joint == "P" else (link.d, link.theta + qi)
        Ts.append(dh_link_transform(link.a, link.alpha, d, theta, table.convention == "modified"))
    return Ts


def _shown(text: str) -> int:
    """Columns ``text`` takes on a terminal (combining marks such as the dot of ω̇ take none)."""
    return sum(not unicodedata.combining(ch) for ch in text)


def format_trace(title: str, rows: list[tuple[str, np.ndarray]], n: int, first: int = 1) -> str:
    """The per-link table of a trace: for each frame i, one line per quantity with its x, y, z.

    Parameters
    ----------
    title : str
        First line.
    rows : list of (str, (n, 3) ndarray)
        The quantities: a label (e.g. "ω") and one row of x, y, z per frame.
    n : int
        Number of frames shown.
    first : int
        Index of the first frame (0 or 1).

    Returns
    -------
    str
        The table (values to 6 significant digits; |x| < 1e-12 shown as 0).

    Examples
    --------
    >>> print(format_trace("trace", [("ω", np.array([[0.0, 0.0, 1.5]]))], 1))
    trace
      i             x            y            z
      1  ω          0            0          1.5
    """
    width = max(_shown(name) for name, _ in rows)
    lines = [title, f"{'i':>3}  {'':<{width}}  {'x':>12} {'y':>12} {'z':>12}"]
    for i in range(n):
        for k, (name, arr) in enumerate(rows):
            x, y, z = (0.0 if abs(v) < 1e-12 else float(v) for v in arr[i])  # no "-0", no 1e-18 round-off
            label = f"{i + first:>3}" if k == 0 else "   "
            pad = " " * (width - _shown(name))
            lines.append(f"{label}  {name}{pad}  {x:>12.6g} {y:>12.6g} {z:>12.6g}")
    return "\n".join(lines)


@dataclass(frozen=True)
class DHVelocityTrace:
    """The outward velocity iteration of :func:`dh_velocity_trace`, frame by frame (Lecture 6).

    Row 0 is the base frame {0} (at rest), rows 1..n the DH frames {1}..{n}; ``print(trace)``
    shows the Lecture 6 table.

    Attributes
    ----------
    omega : (n+1, 3) ndarray
        ⁱωᵢ, the angular velocity of frame {i} in its own axes (rad/s).
    v : (n+1, 3) ndarray
        ⁱvᵢ, the velocity of the origin of frame {i} in its own axes (m/s).
    convention : str
        "standard" or "modified", the table's DH convention.
    """

    omega: np.ndarray
    v: np.ndarray
    convention: str

    def __str__(self) -> str:
        n = self.omega.shape[0]
        return format_trace(f"Outward velocity iteration ({self.convention} DH), frame {{i}} axes",
                            [("ω_i (rad/s)", self.omega), ("v_i (m/s)", self.v)], n, first=0)


def dh_velocity_trace(table: DHTable, q: ArrayLike, dq: ArrayLike) -> DHVelocityTrace:
    """ⁱωᵢ and ⁱvᵢ of every DH frame by outward velocity propagation (Lecture 6), each step kept.

    Parameters
    ----------
    table : DHTable
        Standard or modified convention, revolute and prismatic joints.
    q, dq : (n,) array_like
        Joint values (rad or m) and rates (rad/s or m/s).

    Returns
    -------
    DHVelocityTrace
        ``.omega``, ``.v``: (n+1, 3), row i for frame {i} in frame {i}'s axes (row 0: the base
        frame, at rest).

    Examples
    --------
    A planar two-link arm (standard DH, a₁ = a₂ = 1) at q = 0 with q̇ = (1, 0): frame {2} turns at
    1 rad/s and its origin moves at 2 m/s along y::

        >>> import robokit as rk
        >>> tr = dh_velocity_trace(rk.load("twolink").dh, [0, 0], [1, 0])  # doctest: +SKIP
        >>> tr.omega[2], tr.v[2]  # doctest: +SKIP
        (array([0., 0., 1.]), array([0., 2., 0.]))
    """
    n = table.n
    q = as_vector(q, "q", n)
    dq = as_vector(dq, "dq", n)
    modified = table.convention == "modified"
    omega = np.zeros((n + 1, 3))
    v = np.zeros((n + 1, 3))
    for i, T in enumerate(link_transforms(table, q)):
        R, p = T[:3, :3], T[:3, 3]
        rate = -dq[i] if getattr(table.links[i], "flip", False) else dq[i]
        th, dd = (0.0, rate) if table.links[i].joint == "P" else (rate, 0.0)
        w, vel = omega[i], v[i]
        if modified:
            omega[i + 1] = R.T @ w + th * _Z
            v[i + 1] = R.T @ (vel + np.cross(w, p)) + dd * _Z
        else:
            w1 = w + th * _Z
            omega[i + 1] = R.T @ w1
            v[i + 1] = R.T @ (vel + np.cross(w1, p) + dd * _Z)
    return DHVelocityTrace(omega, v, table.convention)
