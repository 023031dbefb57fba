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
    """The link transform ⁱ⁻¹Tᵢ of one DH row (Lecture 4).

    ``Rz(θ) Tz(d) Tx(a) Rx(α)`` (standard) or ``Rx(α) Tx(a) Rz(θ) Tz(d)`` (modified, Craig).

    Parameters
    ----------
    a : float
        Link length (m).
    alpha : float
        Link twist (rad).
    d : float
        Link offset (m), the joint value already added for a prismatic joint.
    theta : float
        Joint angle (rad), the joint value already added for a revolute joint.
    modified : bool
        True for the modified (Craig) convention, False for the standard one.

    Returns
    -------
    (4, 4) ndarray
        Pose of frame {i} in frame {i−1} (metres).

    Examples
    --------
    A 1 m link turned by 90°: frame {i} sits 1 m along y of frame {i−1}:

    >>> dh_link_transform(1.0, 0.0, 0.0, np.pi / 2, False)[:3, 3].round(4)
    array([0., 1., 0.])
    """
    from robokit.description.dh import dh_transform  # the compiled kernel's link transform

    return dh_transform(float(a), float(alpha), float(d), float(theta), "modified" if modified else "standard")


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
        First line of the table.
    rows : list of (str, (n, 3) ndarray)
        The quantities, each a name (with its unit) and one 3-vector per frame.
    n : int
        Number of frames (lines per quantity) to show.
    first : int, optional
        Index printed for the first frame; default 1.

    Returns
    -------
    str
        The table, one line per frame and quantity; values within 1e-12 of zero print as 0.

    Examples
    --------
    >>> print(format_trace("ω", [("ω_i", np.array([[0, 0, 1.0], [0, 0, 2.0]]))], 2))
    ω
      i              x            y            z
      1  ω_i         0            0            1
      2  ω_i         0            0            2
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
    """The outward velocity iteration of :func:`dh_velocity_trace`, frame by frame.

    ``print(trace)`` shows the Lecture 6 table.

    Attributes
    ----------
    omega : (n+1, 3) ndarray
        ⁱωᵢ, the angular velocity of frame {i} in its own axes (rad/s).
    v : (n+1, 3) ndarray
        ⁱvᵢ, the velocity of the origin of frame {i} in its own axes (m/s).
    convention : str
        "standard" or "modified". Row 0 is the base frame {0} (at rest), rows 1..n the DH frames.
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
    The course's planar two-link arm (standard DH, a₁ = 1 m, a₂ = 0.8 m) at q = 0 with q̇ = (1, 0):
    frame {2} turns at 1 rad/s and its origin, 1.8 m out, moves at 1.8 m/s along y:

    >>> tr = dh_velocity_trace(rk.load("twolink").dh, [0, 0], [1, 0])
    >>> tr.omega[2], tr.v[2]
    (array([0., 0., 1.]), array([0. , 1.8, 0. ]))
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
