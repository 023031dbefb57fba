r"""Is a tool pose reachable? The IK back end of capability maps, chosen per robot.

Three back ends, tried in this order (:func:`ik_backend` says which one a robot gets):

``"planar"``
    Arms whose joints are all revolute about parallel axes (normal ``n``) with 2 or 3
    joints: a vectorised closed form. In plane coordinates, with ``r_i`` a point of axis i,
    ``d_i = r_{i+1} − r_i`` (``r_{N+1}`` the tool point) and ``ψ_i = ±θ_i`` (the sign of
    ``ω_i · n``), forward kinematics is ``p = r₁ + Σ_i Rot(ψ₁+…+ψ_i) d_i`` and the tool turns
    by ``φ = ψ₁+…+ψ_N`` (Lecture 5). Two joints: ``Rot(ψ₁) d₁ = p − r₁ − Rot(φ) d₂`` has a
    solution iff that vector has length ``|d₁|``. Three joints: the wrist point
    ``w = p − r₁ − Rot(φ) d₃`` is placed by the two-link solution
    ``cos(B − A) = (|w|² − l₁² − l₂²)/(2 l₁ l₂)`` (elbow ±). A solution counts when every
    angle, shifted by a multiple of 2π, lies inside the joint limits and its forward
    kinematics reproduces the target (1e-9 relative to the arm's size).
``"closed form"``
    Arms that ``robokit.ik_analytic`` solves (spherical wrists, three parallel axes): a
    pose is reachable when one of its solutions is within the limits and its forward
    kinematics (Pinocchio) reproduces the target to 1e-6.
``"numeric"``
    Everything else: Levenberg–Marquardt with random restarts (``robokit.solve_ik``, or the
    compiled ``robokit.kernels.ik.solve_poe_ik`` when it is installed; one adapter,
    :func:`_numeric_success`). A failure after the restarts is counted as unreachable, so a
    numeric capability index is a lower bound of the true one.
"""
from __future__ import annotations

from typing import TYPE_CHECKING, Any, Callable, cast

import numpy as np
from numpy.typing import ArrayLike
from robokit._arrays import as_int
from robokit.errors import InputError

if TYPE_CHECKING:
    from robokit.description.poe import PoEParams
    from robokit.description.robot import Robot

__all__ = ["ik_success", "ik_backend"]

#: Restarts of the numerical IK per target (after the first attempt).
DEFAULT_RESTARTS = 20
_PLANAR_TOL = 1e-9


# ----------------------------------------------------------------------------- planar geometry
class PlanarChain:
    """The plane geometry of an arm whose joints are revolute about parallel axes.

    normal : (3,) unit normal n (the first joint's axis); u, v : (3,) in-plane unit axes
    (u the base x axis projected on the plane, or y/z if x is along n), n = u × v;
    height : n · p_tool (m), the plane the tool point moves in; signs : (N,) ±1, ω_i · n;
    r : (N, 2) a point of each axis, plane coordinates (m); d : (N, 2) link vectors
    r_{i+1} − r_i, the last one to the tool point; R0 : (3, 3) tool orientation at θ = 0;
    qlim : (N, 2).
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
        return len(self.signs)

    def to_plane(self, P: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(B, 2) plane coordinates and (B,) heights of (B, 3) base-frame points."""
        return np.stack([P @ self.u, P @ self.v], axis=1), P @ self.normal

    def from_plane(self, xy: np.ndarray) -> np.ndarray:
        """(B, 3) base-frame points of (B, 2) plane coordinates at the tool's height."""
        return self.height * self.normal + xy[:, :1] * self.u + xy[:, 1:2] * self.v

    def fk(self, psi: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(B, 2) tool points and (B,) tool angles of (B, N) plane angles ψ."""
        acc = np.cumsum(psi, axis=1)
        c, s = np.cos(acc), np.sin(acc)
        p = self.r[0] + np.stack([(c * self.d[:, 0] - s * self.d[:, 1]).sum(1),
                                  (s * self.d[:, 0] + c * self.d[:, 1]).sum(1)], axis=1)
        return p, acc[:, -1]

    def _in_limits(self, psi: np.ndarray) -> np.ndarray:
        """True where the joint angles θ = sign·ψ, shifted by a multiple of 2π, fit the limits."""
        theta = psi * self.signs
        lo, hi = self.qlim[:, 0], self.qlim[:, 1]
        eps = 1e-12
        # the smallest θ + 2πm ≥ lo − eps, then test it against hi
        m = np.ceil((lo - eps - theta) / (2 * np.pi))
        m = np.where(np.isfinite(m), m, 0.0)
        shifted = theta + 2 * np.pi * m
        ok = np.where(np.isfinite(lo), shifted <= hi + eps, True)
        return cast(np.ndarray, ok.all(axis=1))

    def success(self, targets: np.ndarray) -> np.ndarray:
        """(B,) bool: which of the (B, 4, 4) target poses the planar arm reaches."""
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

        found = np.zeros(B, dtype=bool)
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
        for psi, mask in zip(candidates, masks):
            pf, phif = self.fk(psi)
            close = np.linalg.norm(pf - xy, axis=1) < tol
            dphi = np.abs(np.angle(np.exp(1j * (phif - phi))))
            found |= mask & close & (dphi < 1e-9) & self._in_limits(psi)
        return found & ok_frame


def planar_chain(robot: Robot) -> PlanarChain | None:
    """The :class:`PlanarChain` of ``robot`` if all its joints are revolute about parallel axes, else None."""
    poe = robot.poe
    S = np.asarray(poe.Slist, dtype=float)
    w = S[:3].T
    norms = np.linalg.norm(w, axis=1)
    if np.any(np.abs(norms - 1.0) > 1e-9):  # a prismatic joint
        return None
    if np.any(np.linalg.norm(np.cross(w, w[0]), axis=1) > 1e-9):
        return None
    return PlanarChain(poe, robot.qlim)


# ----------------------------------------------------------------------------- back end choice
def _analytic() -> Callable[..., Any]:
    """The closed-form solver :func:`robokit.ik.closed_form.ik_analytic`."""
    from robokit.ik.closed_form import ik_analytic

    return ik_analytic


def _has_closed_form(robot: Robot) -> bool:
    solve = _analytic()
    if solve is None:
        return False
    try:
        solve(robot, robot.frame_pose(np.zeros(robot.n)))
    except ValueError:  # no closed form for this geometry
        return False
    return True


def ik_backend(robot: Robot) -> str:
    """Which IK back end :func:`ik_success` uses for ``robot``.

    Returns
    -------
    str
        ``"planar"``, ``"closed form"`` or ``"numeric"`` (see the module docstring).

    Examples
    --------
    >>> import robokit
    >>> ik_backend(robokit.load("rrr"))
    'planar'
    """
    chain = planar_chain(robot)
    if chain is not None and chain.n in (2, 3) and np.all(np.linalg.norm(chain.d[: chain.n - 1], axis=1) > 1e-9):
        return "planar"
    if _has_closed_form(robot):
        return "closed form"
    return "numeric"


class _Backend:
    """One robot's IK back end, built once and reused for every chunk."""

    def __init__(self, robot: Robot, restarts: int = DEFAULT_RESTARTS) -> None:
        self.robot = robot
        self.kind = ik_backend(robot)
        self.restarts = int(restarts)
        self.chain = planar_chain(robot) if self.kind == "planar" else None
        qlim = np.asarray(robot.qlim, dtype=float)
        self.lo = np.where(np.isfinite(qlim[:, 0]), qlim[:, 0], -np.pi)
        self.hi = np.where(np.isfinite(qlim[:, 1]), qlim[:, 1], np.pi)
        self.tol_fk = 1e-6 * max(1.0, float(np.abs(robot.poe.M[:3, 3]).sum()))

    def success(self, targets: np.ndarray, rng: np.random.Generator) -> np.ndarray:
        if self.kind == "planar":
            assert self.chain is not None  # kind is 'planar' only when the arm has a planar chain
            return self.chain.success(targets)
        out = np.zeros(len(targets), dtype=bool)
        if self.kind == "closed form":
            solve = _analytic()
            for b, T in enumerate(targets):
                for sol in solve(self.robot, T):
                    if sol.within_limits and np.abs(self.robot.frame_pose(sol.q) - T).max() < self.tol_fk:
                        out[b] = True
                        break
            return out
        for b, T in enumerate(targets):
            out[b] = _numeric_success(self.robot, T, rng.uniform(self.lo, self.hi), rng, self.restarts)
        return out


def _kernel_solver() -> Callable[..., Any] | None:
    """The compiled PoE IK (``robokit.kernels.ik.solve_poe_ik``) if installed, else None."""
    try:
        from robokit.kernels.ik import solve_poe_ik
    except ImportError:
        return None
    return solve_poe_ik


def _numeric_success(robot: Robot, T: np.ndarray, q0: np.ndarray, rng: np.random.Generator, restarts: int) -> bool:
    """The one adapter between capability maps and numerical IK: True if IK converges on ``T``.

    Uses the compiled kernel when it is importable, else :func:`robokit.solve_ik`; both are
    seeded from ``rng`` (so a chunk's answers depend only on the chunk's seed)."""
    kernel = _kernel_solver()
    if kernel is not None:
        poe = robot.poe
        _, ok, _, _ = kernel(poe.M, poe.Slist, T, q0, np.asarray(robot.qlim, dtype=float), 1e-10, 60, restarts,
                             int(rng.integers(2**31 - 1)))
        return bool(ok)
    from robokit.ik.numeric import solve_ik

    return bool(solve_ik(robot, T, q0=q0, max_restarts=restarts, rng=rng).success)


def ik_success(robot: Robot, targets: ArrayLike, *, rng: int | np.random.Generator | None = None, restarts: int = DEFAULT_RESTARTS) -> np.ndarray:
    """Which target poses of the tip does ``robot`` reach (inside its joint limits)?

    Parameters
    ----------
    robot : :class:`robokit.Robot` or anything ``robokit.load`` accepts
    targets : (B, 4, 4) array
        Target poses of the tip frame in the base frame (m).
    rng : numpy Generator or int, optional
        Seeds the numerical back end's initial guesses and restarts (unused by the closed forms).
    restarts : int
        Random restarts of the numerical back end per target.

    Returns
    -------
    (B,) bool ndarray

    Notes
    -----
    The back end is chosen per robot (:func:`ik_backend`): a vectorised planar closed form,
    ``robokit.ik_analytic``, or numerical IK (whose failures count as unreachable).

    Examples
    --------
    >>> import numpy as np, robokit
    >>> robot = robokit.load("rrr")
    >>> T = robot.frame_pose(np.array([0.3, -0.2, 0.5]))
    >>> ik_success(robot, T[None]).tolist()
    [True]
    """
    from robokit.description.robot import load

    robot = load(robot)
    T = np.asarray(targets, dtype=float)
    if T.ndim != 3 or T.shape[1:] != (4, 4):
        raise InputError(f"targets: expected shape (B, 4, 4), got {T.shape}")
    if not np.isfinite(T).all():
        raise InputError("targets: contains NaN or infinite values")
    restarts = as_int(restarts, "restarts", minimum=0)
    return _Backend(robot, restarts).success(T, np.random.default_rng(rng))
