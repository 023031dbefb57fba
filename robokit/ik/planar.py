r"""Planar arms in closed form, vectorised: every joint revolute about parallel axes (Lecture 5).

In plane coordinates, with ``r_i`` a point of axis i, ``d_i = r_{i+1} − r_i`` (``r_{N+1}`` the
tool point) and ``ψ_i = ±θ_i`` (the sign of ``ω_i · n``, n the axes' common direction),
forward kinematics is ``p = r₁ + Σ_i Rot(ψ₁+…+ψ_i) d_i`` and the tool turns by
``φ = ψ₁+…+ψ_N``. Two joints: ``Rot(ψ₁) d₁ = p − r₁ − Rot(φ) d₂`` has a solution iff that
vector has length ``|d₁|``. Three joints: the wrist point ``w = p − r₁ − Rot(φ) d₃`` is
placed by the two-link solution ``cos(B − A) = (|w|² − l₁² − l₂²)/(2 l₁ l₂)`` (elbow ±).
A solution counts when every angle, shifted by a multiple of 2π, lies inside the joint
limits and its forward kinematics reproduces the target (1e-9 relative to the arm's size).

:func:`planar_reason` says whether a robot is such an arm (and why not);
:class:`PlanarChain` holds its plane geometry and answers for many targets at once
(``success``, used by capability maps) or one (``solutions``, used by ``solve_ik``).
"""
from __future__ import annotations

from typing import TYPE_CHECKING, cast

import numpy as np
from numpy.typing import ArrayLike

if TYPE_CHECKING:
    from robokit.description.poe import PoEParams
    from robokit.description.robot import Robot

__all__ = ["PlanarChain", "planar_chain", "planar_reason"]

_PLANAR_TOL = 1e-9


class PlanarChain:
    """The plane geometry of an arm whose joints are revolute about parallel axes.

    Parameters
    ----------
    poe : PoEParams
        The arm's space screws ``Slist`` (6, N) and home pose ``M`` (4, 4).
    qlim : (N, 2) array_like
        Joint limits (rad).

    Attributes
    ----------
    normal : (3,) ndarray
        Unit normal n of the plane (the first joint's axis), base frame.
    u, v : (3,) ndarray
        In-plane unit axes (u the base x axis projected on the plane, or y/z if x is along n),
        n = u × v.
    height : float
        ``n · p_tool`` (m): the plane the tool point moves in.
    signs : (N,) ndarray
        ±1 per joint, ``ω_i · n``.
    r : (N, 2) ndarray
        A point of each axis, plane coordinates (m).
    d : (N, 2) ndarray
        Link vectors ``r_{i+1} − r_i``, the last one to the tool point (m).
    R0 : (3, 3) ndarray
        Tool orientation at θ = 0.
    qlim : (N, 2) ndarray
        Joint limits (rad).

    Examples
    --------
    >>> import robokit
    >>> planar_chain(robokit.load("rrr")).n
    3
    """

    def __init__(self, poe: PoEParams, qlim: ArrayLike) -> None:
        S = np.asarray(poe.Slist, dtype=float)
        w = S[:3].T
        n = w[0] / np.linalg.norm(w[0])
        self.normal = n
        e = np.eye(3)
        k = int(np.argmin(np.abs(e @ n)))  # the base axis least aligned with n (x first on ties)
        u = e[k] - (e[k] @ n) * n
        self.u = u / np.linalg.norm(u)
        self.v = np.cross(n, self.u)
        self.signs = np.sign(w @ n)
        M = np.asarray(poe.M, dtype=float)
        self.R0 = M[:3, :3].copy()
        p_tool = M[:3, 3]
        self.height = float(n @ p_tool)
        pts = np.array([np.cross(w[i], S[3:, i]) for i in range(S.shape[1])])  # ω × v = point on the axis
        allp = np.vstack([pts, p_tool])
        plane = np.stack([allp @ self.u, allp @ self.v], axis=1)
        self.r = plane[:-1]
        self.d = np.diff(plane, axis=0)
        self.qlim = np.asarray(qlim, dtype=float)
        self.size = float(max(1.0, np.abs(plane).max() + np.linalg.norm(self.d, axis=1).sum()))

    @property
    def n(self) -> int:
        """Number of joints N."""
        return len(self.signs)

    def to_plane(self, P: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Plane coordinates of base-frame points.

        Parameters
        ----------
        P : numpy.ndarray, shape (B, 3)
            Points in the base frame, m.

        Returns
        -------
        xy : numpy.ndarray, shape (B, 2)
            Their coordinates along ``u`` and ``v``, m.
        height : numpy.ndarray, shape (B,)
            Their heights along ``normal``, m.

        Examples
        --------
        >>> chain = planar_chain(rk.load("rrr"))      # joints about z: the plane is x-y
        >>> xy, h = chain.to_plane(np.array([[1.0, 2.0, 3.0]]))
        >>> xy.tolist(), h.tolist()
        ([[1.0, 2.0]], [3.0])
        """
        return np.stack([P @ self.u, P @ self.v], axis=1), P @ self.normal

    def from_plane(self, xy: np.ndarray) -> np.ndarray:
        """Base-frame points of plane coordinates, at the tool's height.

        Parameters
        ----------
        xy : numpy.ndarray, shape (B, 2)
            Coordinates along ``u`` and ``v``, m.

        Returns
        -------
        numpy.ndarray, shape (B, 3)
            The points in the base frame, m.

        Examples
        --------
        >>> planar_chain(rk.load("rrr")).from_plane(np.array([[1.0, 2.0]])).tolist()
        [[1.0, 2.0, 0.0]]
        """
        return self.height * self.normal + xy[:, :1] * self.u + xy[:, 1:2] * self.v

    def fk(self, psi: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Planar forward kinematics: ``p = r₁ + Σ_i Rot(ψ₁+…+ψ_i) d_i``, ``φ = ψ₁+…+ψ_N``.

        Parameters
        ----------
        psi : numpy.ndarray, shape (B, N)
            Plane angles ψ (rad; ``ψ_i = signs_i · θ_i``).

        Returns
        -------
        p : numpy.ndarray, shape (B, 2)
            Tool points, plane coordinates (m).
        phi : numpy.ndarray, shape (B,)
            Tool angles, rad.

        Examples
        --------
        The 0.5 + 0.4 + 0.2 m arm stretched, then turned 90° at the first joint:

        >>> p, phi = planar_chain(rk.load("rrr")).fk(np.array([[0.0, 0.0, 0.0], [np.pi / 2, 0.0, 0.0]]))
        >>> p.round(4).tolist(), phi.round(4).tolist()
        ([[1.1, 0.0], [0.0, 1.1]], [0.0, 1.5708])
        """
        acc = np.cumsum(psi, axis=1)
        c, s = np.cos(acc), np.sin(acc)
        p = self.r[0] + np.stack([(c * self.d[:, 0] - s * self.d[:, 1]).sum(1),
                                  (s * self.d[:, 0] + c * self.d[:, 1]).sum(1)], axis=1)
        return p, acc[:, -1]

    def _shifted(self, psi: np.ndarray) -> np.ndarray:
        """θ = sign·ψ with each angle moved by a multiple of 2π to the smallest value ≥ lo − 1e-12
        (unlimited joints: wrapped to (−π, π])."""
        theta = psi * self.signs
        lo = self.qlim[:, 0]
        eps = 1e-12
        m = np.ceil((lo - eps - theta) / (2 * np.pi))
        wrapped = np.pi - np.mod(np.pi - theta, 2 * np.pi)
        return cast(np.ndarray, np.where(np.isfinite(m), theta + 2 * np.pi * np.where(np.isfinite(m), m, 0.0),
                                         wrapped))

    def _in_limits(self, psi: np.ndarray) -> np.ndarray:
        """True where the joint angles θ = sign·ψ, shifted by a multiple of 2π, fit the limits."""
        lo, hi = self.qlim[:, 0], self.qlim[:, 1]
        shifted = self._shifted(psi)
        ok = np.where(np.isfinite(lo), shifted <= hi + 1e-12, True)
        return cast(np.ndarray, ok.all(axis=1))

    def _candidates(self, targets: np.ndarray) -> tuple[list[np.ndarray], np.ndarray]:
        """(candidates, mask): every candidate's (B, N) plane angles ψ, and (B,) bool for the
        targets the planar arm can reach at all (in the plane, rotation about n)."""
        T = np.asarray(targets, dtype=float)
        B = len(T)
        tol = _PLANAR_TOL * self.size
        xy, h = self.to_plane(T[:, :3, 3])
        Rn = T[:, :3, :3] @ self.R0.T  # must be a rotation about n
        about_n = np.linalg.norm(Rn @ self.normal - self.normal, axis=1) < 1e-9
        ok_frame = about_n & (np.abs(h - self.height) < tol)
        Ru = Rn @ self.u
        phi = np.arctan2(Ru @ self.v, Ru @ self.u)
        p = xy - self.r[0]
        cphi, sphi = np.cos(phi), np.sin(phi)

        def rot(c: np.ndarray, s: np.ndarray, d: np.ndarray) -> np.ndarray:
            return np.stack([c * d[0] - s * d[1], s * d[0] + c * d[1]], axis=1)

        d1 = self.d[0]
        l1 = float(np.linalg.norm(d1))
        b1 = float(np.arctan2(d1[1], d1[0]))
        if self.n == 2:
            w = p - rot(cphi, sphi, self.d[1])
            near = np.abs(np.linalg.norm(w, axis=1) - l1) < tol
            psi1 = np.arctan2(w[:, 1], w[:, 0]) - b1
            candidates = [np.stack([psi1, phi - psi1], axis=1)]
            masks = [near]
        else:
            w = p - rot(cphi, sphi, self.d[2])
            d2 = self.d[1]
            l2 = float(np.linalg.norm(d2))
            b2 = float(np.arctan2(d2[1], d2[0]))
            rr = (w * w).sum(1)
            c = (rr - l1 * l1 - l2 * l2) / (2 * l1 * l2)
            near = np.abs(c) <= 1 + 1e-12
            delta = np.arccos(np.clip(c, -1.0, 1.0))
            candidates, masks = [], []
            for sgn in (1.0, -1.0):
                dl = sgn * delta
                A = np.arctan2(w[:, 1], w[:, 0]) - np.arctan2(l2 * np.sin(dl), l1 + l2 * np.cos(dl))
                psi1 = A - b1
                psi2 = dl + b1 - b2
                candidates.append(np.stack([psi1, psi2, phi - psi1 - psi2], axis=1))
                masks.append(near)
        good = []
        for psi, mask in zip(candidates, masks):
            pf, phif = self.fk(psi)
            close = np.linalg.norm(pf - xy, axis=1) < tol
            dphi = np.abs(np.angle(np.exp(1j * (phif - phi))))
            good.append(mask & close & (dphi < 1e-9) & ok_frame)
        return candidates, np.array(good).reshape(len(candidates), B)

    def success(self, targets: np.ndarray) -> np.ndarray:
        """(B,) bool: which of the (B, 4, 4) target poses the planar arm reaches inside its limits.

        Parameters
        ----------
        targets : (B, 4, 4) ndarray
            Tool poses in the base frame (m).

        Returns
        -------
        (B,) bool ndarray
        """
        candidates, good = self._candidates(targets)
        found = np.zeros(good.shape[1], dtype=bool)
        for psi, ok in zip(candidates, good):
            found |= ok & self._in_limits(psi)
        return found

    def solutions(self, T: np.ndarray) -> list[np.ndarray]:
        """Every joint configuration reaching the pose T, shifted into the limits.

        Each angle is moved by a multiple of 2π to the smallest value not below its lower
        limit; configurations outside the limits after that shift are dropped.

        Parameters
        ----------
        T : numpy.ndarray, shape (4, 4)
            Tool pose in the base frame, m.

        Returns
        -------
        list of numpy.ndarray, shape (N,)
            Joint values θ (rad): up to 2 for 3 joints (elbow ±), 1 for 2 joints; ``[]`` out of reach.

        Examples
        --------
        >>> robot = rk.load("rrr")
        >>> sols = planar_chain(robot).solutions(robot.frame_pose([0.3, 0.4, 0.5]))
        >>> [s.round(4).tolist() for s in sols]
        [[0.3, 0.4, 0.5], [0.655, -0.4, 0.945]]
        """
        candidates, good = self._candidates(np.asarray(T, dtype=float)[None])
        out = []
        for psi, ok in zip(candidates, good):
            if ok[0] and self._in_limits(psi)[0]:
                out.append(self._shifted(psi)[0])
        return out


def planar_chain(robot: Robot) -> PlanarChain | None:
    """The :class:`PlanarChain` of ``robot`` if all its joints are revolute about parallel axes, else None.

    Parameters
    ----------
    robot : :class:`robokit.Robot`
        The arm; its POE screw axes, home pose and joint limits are read.

    Returns
    -------
    PlanarChain or None
        The arm's plane, axis points, link vectors and limits; None when a joint is prismatic
        or the axes are not parallel.

    Examples
    --------
    >>> import robokit
    >>> planar_chain(robokit.load("puma560")) is None
    True
    """
    poe = robot.poe
    S = np.asarray(poe.Slist, dtype=float)
    w = S[:3].T
    norms = np.linalg.norm(w, axis=1)
    if np.any(np.abs(norms - 1.0) > 1e-9):  # a prismatic joint
        return None
    if np.any(np.linalg.norm(np.cross(w, w[0]), axis=1) > 1e-9):
        return None
    return PlanarChain(poe, robot.qlim)


def planar_reason(robot: Robot) -> str | None:
    """None if the planar closed form applies to ``robot``, else why not (one sentence).

    It applies to 2 or 3 revolute joints about parallel axes whose links (between
    consecutive axes) are not of zero length.

    Parameters
    ----------
    robot : :class:`robokit.Robot`
        The arm to check (through :func:`planar_chain`).

    Returns
    -------
    str or None
        None when the planar closed form applies; else the first condition that fails, in one
        sentence.

    Examples
    --------
    >>> import robokit
    >>> planar_reason(robokit.load("rrr")) is None
    True
    """
    chain = planar_chain(robot)
    if chain is None:
        return "not every joint is revolute about one common axis direction (a planar arm)"
    if chain.n not in (2, 3):
        return f"the planar closed form needs 2 or 3 joints, the arm has {chain.n}"
    if not np.all(np.linalg.norm(chain.d[: chain.n - 1], axis=1) > 1e-9):
        return "two consecutive joint axes coincide (a link of zero length)"
    return None
