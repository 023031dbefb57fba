r"""Newton–Euler dynamics in product-of-exponentials form (Lecture 7, seed 004 §4, Modern Robotics ch. 8).

Model (Modern Robotics), the ``Mlist, Glist, Slist`` of every function here: ``Mlist`` (n+1, 4, 4),
``Mlist[i]`` the pose of link frame {i+1} (at the centre of mass) in frame {i}, metres, and
``Mlist[n]`` the end-effector frame in {n}; ``Glist`` (n, 6, 6), ``Glist[i]`` the spatial inertia
of link i+1 in its centre-of-mass frame, angular first ``[[I, 0], [0, m 1]]`` (kg·m², kg);
``Slist`` (6, n) the space-frame screw axes of the joints, one column ``(ω; v)`` each. Wrenches
``(m, f)`` are angular first; ``Ftip`` is the wrench the end-effector applies *to the
environment*, expressed in the end-effector frame (N·m, N). ``g`` (3,) is gravity in the base
(space) frame, m/s², e.g. ``[0, 0, -9.81]``. Joint values are in rad (m for a prismatic joint),
rates in rad/s (m/s), accelerations in rad/s² (m/s²), torques in N·m (N). The functions'
docstrings refer to these definitions as "the module docstring".

With ``Aᵢ = Ad_{M₀ᵢ⁻¹} Sᵢ`` (joint i's screw in frame {i}, ``M₀ᵢ = Mlist[0]⋯Mlist[i−1]``) and
``T_{i,i−1} = e^{−[Aᵢ]θᵢ} Mlist[i−1]⁻¹``:

forward iterations (i = 1..n), with ``V₀ = 0``, ``V̇₀ = (0, −g)`` (gravity as a base acceleration):
    ``Vᵢ = Ad_{T_{i,i−1}} V_{i−1} + Aᵢ θ̇ᵢ``
    ``V̇ᵢ = Ad_{T_{i,i−1}} V̇_{i−1} + ad_{Vᵢ} Aᵢ θ̇ᵢ + Aᵢ θ̈ᵢ``
backward iterations (i = n..1), with ``F_{n+1} = Ftip``, ``T_{n+1,n} = Mlist[n]⁻¹``:
    ``Fᵢ = Ad_{T_{i+1,i}}ᵀ F_{i+1} + Gᵢ V̇ᵢ − ad_{Vᵢ}ᵀ Gᵢ Vᵢ``,  ``τᵢ = Fᵢᵀ Aᵢ``.

The mass matrix uses the composite-rigid-body algorithm in the same frames
(``Kᵢ = Gᵢ + Ad_{T_{i+1,i}}ᵀ K_{i+1} Ad_{T_{i+1,i}}``, ``M_{ji} = A_jᵀ (Ad …)ᵀ Kᵢ Aᵢ``), which
equals n calls of inverse dynamics with unit accelerations, at a fraction of the cost.
The recursions run as compiled loops (:mod:`robokit.kernels.dynamics`, the parallel batched
kernels for (N, n) input); this module checks the arguments, validating a model's constants
once and remembering them (by their bytes).
"""
from __future__ import annotations

from math import hypot
from types import ModuleType
from typing import Any

import numpy as np
from numpy.typing import ArrayLike

from robokit._arrays import as_array, as_scalar, as_vector, kernel_arrays
from robokit._units import TURN, check_radians, radian_ranges, revolute_columns, surely_radians
from robokit.errors import InputError
from robokit.kinematics.poe import screw_exponentials
from robokit.spatial import lie

__all__ = [
    "inverse_dynamics",
    "mass_matrix",
    "vel_quadratic_forces",
    "gravity_forces",
    "end_effector_forces",
    "forward_dynamics",
    "euler_step",
    "inverse_dynamics_trajectory",
    "forward_dynamics_trajectory",
]

_MODELS: dict = {}
_kd = None  # robokit.kernels.dynamics, imported on first use


def _kernels() -> ModuleType:
    global _kd
    from robokit.kernels import dynamics

    _kd = dynamics
    return dynamics


_ZEROS: dict = {}


def _zeros(n: int) -> np.ndarray:
    """A shared zero vector of length n (the kernels never write their inputs; it stays writeable
    because the compiled signatures take writeable arrays)."""
    z = _ZEROS.get(n)
    if z is None:
        z = _ZEROS[n] = np.zeros(n)
    return z


def _radians(m: _Model, th: np.ndarray, name: str = "thetalist") -> np.ndarray:
    """The degrees check of the seed library (robokit._units) on checked joint values; returns them."""
    check_radians(th, m.deg_lo, m.deg_hi, name)
    return th


def _c(a: np.ndarray) -> np.ndarray:
    """``a`` C-contiguous and writeable, as the kernels' signatures take it (a copy only when needed)."""
    a = np.ascontiguousarray(a)
    return a if a.flags.writeable else a.copy()


#: Dimensions of the one-configuration kernels' arguments: five vectors and the model
#: (θ, θ̇, θ̈ or τ, g, F_tip, Mlist, Glist, Slist); and of the mass matrix's (θ and the model).
_NDIMS_8 = (1, 1, 1, 1, 1, 3, 3, 2)
_NDIMS_MM = (1, 3, 3, 2)
_NDIMS_5 = (1, 1, 3, 3, 2)


def _fast(kernel: Any, arguments: tuple, ndims: tuple, *before: Any) -> Any:
    """The fast path of the seed functions: ``kernel(*before, *arguments)`` after at most one
    conversion of each argument (lists, tuples, read-only or strided arrays; ``ndims`` their
    dimensions), the kernel checking the vectors and the model itself; None when an argument is
    refused or the joint values may be degrees (the caller's full checks then name the problem,
    or warn)."""
    args = kernel_arrays(arguments, ndims)
    if args is None or not surely_radians(args[0]):
        return None
    try:
        return kernel(*before, *args)
    except ValueError:  # a bad value or size
        return None


def _rnea_special(which: str, th: np.ndarray, x: np.ndarray, Ml: np.ndarray, Gl: np.ndarray,
                  Sl: np.ndarray) -> np.ndarray:
    """The Newton–Euler kernel with all but one of θ̇, g, F_tip zero, and θ̈ zero:
    :func:`vel_quadratic_forces` (``which`` "c": x is θ̇), :func:`gravity_forces` ("g": x is g)
    and :func:`end_effector_forces` ("F": x is F_tip)."""
    z = _zeros(Sl.shape[1])
    k = _kd or _kernels()
    if which == "c":
        return k.inverse_dynamics(th, x, z, _zeros(3), _zeros(6), Ml, Gl, Sl)
    if which == "g":
        return k.inverse_dynamics(th, z, z, x, _zeros(6), Ml, Gl, Sl)
    return k.inverse_dynamics(th, z, z, _zeros(3), x, Ml, Gl, Sl)


class _Model:
    """Constants of one (Mlist, Glist, Slist) model."""

    def __init__(self, Mlist: np.ndarray, Glist: np.ndarray, Slist: np.ndarray) -> None:
        n = Slist.shape[1]
        self.n = n
        self.Mlist = _c(Mlist)  # the validated constants, as the kernels take them
        self.Glist = _c(Glist)
        self.Slist = _c(Slist)
        self.Minv = np.array([lie.inv(M) for M in Mlist])  # (n+1, 4, 4)
        self.G = np.array(Glist)  # (n, 6, 6)
        M0i = np.eye(4)
        A = np.empty((6, n))
        for i in range(n):
            M0i = M0i @ Mlist[i]
            A[:, i] = lie.adjoint(lie.inv(M0i)[None])[0] @ Slist[:, i]
        self.A = A
        self.AT = np.ascontiguousarray(A.T)  # rows Aᵢ
        self.Ad_tip = lie.adjoint(self.Minv[n][None])[0]  # Ad_{T_{n+1,n}}
        self.deg_lo, self.deg_hi = radian_ranges(revolute_columns(Slist))  # every revolute column at ±2π

    def transforms(self, theta: np.ndarray) -> np.ndarray:
        """Ad_{T_{i,i−1}} for i = 1..n: (n, 6, 6)."""
        T = screw_exponentials(self.A, -theta) @ self.Minv[: self.n]
        return lie.adjoint(T)


_SEEN: dict = {}  # id(Slist) -> (Mlist, Glist, Slist, their bytes, the model): the last arrays seen


def _model(Mlist: Any, Glist: Any, Slist: Any) -> _Model:
    """The validated model of (Mlist, Glist, Slist), remembered by the arrays' contents.

    The same three array objects with unchanged bytes (compared, not hashed: the cheap test on
    every call) give the remembered model; anything else is looked up by its bytes, or checked."""
    seen = _SEEN.get(id(Slist))
    if (seen is not None and seen[0] is Mlist and seen[1] is Glist and seen[2] is Slist
            and Slist.tobytes() == seen[5] and Mlist.tobytes() == seen[3] and Glist.tobytes() == seen[4]):
        return seen[6]
    m = _model_lookup(Mlist, Glist, Slist)
    if type(Mlist) is np.ndarray and type(Glist) is np.ndarray and type(Slist) is np.ndarray:
        if len(_SEEN) > 32:
            _SEEN.clear()
        _SEEN[id(Slist)] = (Mlist, Glist, Slist, Mlist.tobytes(), Glist.tobytes(), Slist.tobytes(), m)
    return m


def _model_lookup(Mlist: Any, Glist: Any, Slist: Any) -> _Model:
    if all(type(a) is np.ndarray and a.dtype == np.float64 for a in (Mlist, Glist, Slist)):
        hit = _MODELS.get((Mlist.tobytes(), Glist.tobytes(), Slist.tobytes()))
        if hit is not None and hit.n == Slist.shape[1] and Mlist.shape == (hit.n + 1, 4, 4):
            return hit  # already validated constants
    Slist = as_array(Slist, "Slist", (6, None))
    n = Slist.shape[1]
    frames, inertias = np.shape(Mlist), np.shape(Glist)
    if (len(frames) == 3 and frames[1:] == (4, 4) and len(inertias) == 3 and inertias[1:] == (6, 6)
            and frames[0] == inertias[0] + 1 and inertias[0] != n):  # Mlist and Glist agree, Slist does not
        raise InputError(f"Slist: expected {inertias[0]} columns (Mlist has {frames[0]} frames, Glist "
                         f"{inertias[0]} inertias: {inertias[0]} joints), got shape {Slist.shape}")
    Mlist = as_array(Mlist, "Mlist", (n + 1, 4, 4))
    Glist = as_array(Glist, "Glist", (n, 6, 6))
    key = (Mlist.tobytes(), Glist.tobytes(), Slist.tobytes())
    m = _MODELS.get(key)
    if m is None:
        if np.abs(Mlist[:, 3, :] - np.array([0.0, 0.0, 0.0, 1.0])).max() > 1e-9:
            raise InputError("Mlist: expected homogeneous transforms (last row [0, 0, 0, 1])")
        if np.abs(Glist - np.swapaxes(Glist, 1, 2)).max() > 1e-9 * max(1.0, np.abs(Glist).max()):
            raise InputError("Glist: expected symmetric 6×6 spatial inertias")
        if len(_MODELS) > 32:
            _MODELS.clear()
        m = _MODELS[key] = _Model(Mlist, Glist, Slist)
    return m


def checked_model(Mlist: ArrayLike, Glist: ArrayLike, Slist: ArrayLike) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The model (Mlist, Glist, Slist) checked once and remembered, as the compiled kernels take it.

    Parameters
    ----------
    Mlist : (n+1, 4, 4) link frames; Glist : (n, 6, 6) spatial inertias; Slist : (6, n) screw axes
        (Modern Robotics form; see the module docstring).

    Returns
    -------
    (Mlist, Glist, Slist) : C-contiguous float64 arrays (the same objects on every call with
    unchanged inputs). ``InputError`` names a wrong shape or a non-symmetric inertia.

    Example: ``Ml, Gl, Sl = checked_model(p.Mlist, p.Glist, p.Slist)`` for ``p = robokit.load("ur5").poe``.
    """
    m = _model(Mlist, Glist, Slist)
    return m.Mlist, m.Glist, m.Slist


def _vec(x: ArrayLike, name: str, n: int) -> np.ndarray:
    return as_vector(x, name, n)


def _checked(m: _Model, batch: bool, thetalist: ArrayLike, dthetalist: ArrayLike, x: ArrayLike, x_name: str,
             g: ArrayLike, Ftip: ArrayLike) -> tuple:
    """The full checks (which name the offending argument) of a state (θ, θ̇, x, g, F_tip) — x is
    θ̈ or τ, called ``x_name`` — for one configuration or, with ``batch``, N of them (θ (N, n),
    F_tip (6,) or (N, 6)): the arguments of a Newton–Euler kernel, model included."""
    c = _c
    if batch:
        if np.shape(thetalist)[1:] != (m.n,):  # a column (n, 1) is not a batch: say both forms
            raise InputError(f"thetalist: expected shape ({m.n},) or (N, {m.n}) for {m.n} joints, got shape "
                             f"{tuple(np.shape(thetalist))}")
        th = _radians(m, as_array(thetalist, "thetalist", (None, m.n)))
        N = th.shape[0]
        dth = as_array(dthetalist, "dthetalist", (N, m.n))
        xs = as_array(x, x_name, (N, m.n))
        F = as_array(Ftip, "Ftip", (N, 6) if np.ndim(Ftip) == 2 else (6,)).reshape(-1, 6)
        g = _vec(g, "g", 3)
    else:  # the same checks, in the order of the arguments
        th = _radians(m, _vec(thetalist, "thetalist", m.n))
        dth = _vec(dthetalist, "dthetalist", m.n)
        xs = _vec(x, x_name, m.n)
        g = _vec(g, "g", 3)
        F = _vec(Ftip, "Ftip", 6)
    return c(th), c(dth), c(xs), c(g), c(F), m.Mlist, m.Glist, m.Slist


def _rnea_checked(m: _Model, thetalist: ArrayLike, dthetalist: ArrayLike, ddthetalist: ArrayLike, g: ArrayLike,
                  Ftip: ArrayLike) -> np.ndarray:
    """Newton–Euler for one configuration after the full checks (which name the offending argument)."""
    return (_kd or _kernels()).inverse_dynamics(*_checked(m, False, thetalist, dthetalist, ddthetalist, "ddthetalist", g,
                                                                  Ftip))


def _rnea_one_term(which: str, thetalist: ArrayLike, x: ArrayLike, Mlist: ArrayLike, Glist: ArrayLike,
                   Slist: ArrayLike) -> np.ndarray:
    """One term of the inverse dynamics — c(θ, θ̇) (``which`` "c", x is θ̇), g(θ) ("g", x is g) or
    Jᵀ(θ) F_tip ("F", x is F_tip) — by the fast path, else after the full checks."""
    tau = _fast(_rnea_special, (thetalist, x, Mlist, Glist, Slist), _NDIMS_5, which)
    if tau is not None:
        return tau
    m = _model(Mlist, Glist, Slist)
    z = _zeros(m.n)
    if which == "c":
        return _rnea_checked(m, thetalist, x, z, _zeros(3), _zeros(6))
    if which == "g":
        return _rnea_checked(m, thetalist, z, z, x, _zeros(6))
    return _rnea_checked(m, thetalist, z, z, _zeros(3), x)


def inverse_dynamics(thetalist: ArrayLike, dthetalist: ArrayLike, ddthetalist: ArrayLike, g: ArrayLike,
                     Ftip: ArrayLike, Mlist: ArrayLike, Glist: ArrayLike, Slist: ArrayLike) -> np.ndarray:
    """Joint torques by the recursive Newton–Euler algorithm (Lecture 7, seed 004 §4, MR ch. 8).

    ``τ = M(θ)θ̈ + c(θ, θ̇) + g(θ) + Jᵀ(θ) F_tip``: the forward iterations for the link twists and
    accelerations (gravity as a base acceleration ``V̇₀ = (0, −g)``) and the backward iterations for
    the link wrenches, ``τᵢ = Fᵢᵀ Aᵢ`` (see the module docstring).

    Parameters
    ----------
    thetalist, dthetalist, ddthetalist : (n,) or (N, n) array_like
        Joint values, rates and accelerations (rad, rad/s, rad/s²; m, m/s, m/s² for prismatic
        joints), or N states at once (computed in parallel over the rows).
    g : (3,) array_like
        Gravity in the space (base) frame, m/s², e.g. ``[0, 0, -9.81]``.
    Ftip : (6,) or (N, 6) array_like
        Wrench ``(m, f)`` (N·m, N) the end-effector applies to the environment, in the
        end-effector frame.
    Mlist, Glist, Slist : array_like
        The model (the module docstring).

    Returns
    -------
    (n,) ndarray, or (N, n) for N states
        τ: N·m for revolute, N for prismatic joints.

    Raises
    ------
    InputError
        On a shape mismatch, non-finite values, a non-homogeneous ``Mlist`` or a non-symmetric
        ``Glist``; the message names the argument.

    Examples
    --------
    The course's planar two-link arm (``models/twolink.yaml``: point masses m₁ = 2 kg, m₂ = 1.5 kg
    at the link ends, l₁ = 1 m, l₂ = 0.8 m, gravity −y) at θ = (0, π/2), turning at θ̇₁ = 1 rad/s:
    τ₁ = (m₁ + m₂) g l₁ (link 2 points straight up) and τ₂ = m₂ l₁ l₂ θ̇₁² (the centrifugal pull):

    >>> p = rk.load("twolink").poe
    >>> inverse_dynamics([0, np.pi / 2], [1, 0], [0, 0], [0, -9.81, 0], np.zeros(6),
    ...                  p.Mlist, p.Glist, p.Slist).round(4)
    array([34.335,  1.2  ])
    """
    k = _kd or _kernels()
    tau = _fast(k.inverse_dynamics, (thetalist, dthetalist, ddthetalist, g, Ftip, Mlist, Glist, Slist), _NDIMS_8)
    if tau is not None:
        return tau
    m = _model(Mlist, Glist, Slist)
    batch = np.ndim(thetalist) == 2
    args = _checked(m, batch, thetalist, dthetalist, ddthetalist, "ddthetalist", g, Ftip)
    return (k.inverse_dynamics_batch if batch else k.inverse_dynamics)(*args)


def mass_matrix(thetalist: ArrayLike, Mlist: ArrayLike, Glist: ArrayLike, Slist: ArrayLike) -> np.ndarray:
    """The joint-space mass matrix M(θ) by the composite-rigid-body algorithm (Lecture 7, seed §4).

    Equal to n calls of :func:`inverse_dynamics` with unit accelerations and no gravity, velocity or
    tip wrench, at a fraction of the cost. Symmetric positive definite.

    Parameters
    ----------
    thetalist : (n,) or (N, n) array_like
        Joint values (rad / m), or N configurations at once.
    Mlist, Glist, Slist : array_like
        The model (the module docstring).

    Returns
    -------
    (n, n) ndarray, or (N, n, n) for N configurations
        M(θ) in kg·m² (revolute rows/columns) and kg (prismatic ones).

    Examples
    --------
    The planar two-link arm of :func:`inverse_dynamics`; Lecture 7 gives
    ``M = [[l₂²m₂ + 2l₁l₂m₂c₂ + l₁²(m₁ + m₂), l₂²m₂ + l₁l₂m₂c₂], [⋯, l₂²m₂]]``, at θ₂ = π/2
    ``[[4.46, 0.96], [0.96, 0.96]]``:

    >>> p = rk.load("twolink").poe
    >>> M = mass_matrix([0, np.pi / 2], p.Mlist, p.Glist, p.Slist)
    >>> M.round(4)
    array([[4.46, 0.96],
           [0.96, 0.96]])
    >>> bool(np.allclose(M, M.T)), bool(np.all(np.linalg.eigvalsh(M) > 0))
    (True, True)
    """
    k = _kd or _kernels()
    M = _fast(k.mass_matrix, (thetalist, Mlist, Glist, Slist), _NDIMS_MM)
    if M is not None:
        return M
    m = _model(Mlist, Glist, Slist)
    if np.ndim(thetalist) == 2:
        th = _c(_radians(m, as_array(thetalist, "thetalist", (None, m.n))))
        return k.mass_matrix_batch(th, m.Mlist, m.Glist, m.Slist)
    return k.mass_matrix(_c(_radians(m, _vec(thetalist, "thetalist", m.n))), m.Mlist, m.Glist, m.Slist)


def vel_quadratic_forces(thetalist: ArrayLike, dthetalist: ArrayLike, Mlist: ArrayLike, Glist: ArrayLike,
                         Slist: ArrayLike) -> np.ndarray:
    """Coriolis and centripetal torques ``c(θ, θ̇)``: inverse dynamics with θ̈ = 0, g = 0, F_tip = 0.

    Parameters
    ----------
    thetalist, dthetalist : (n,) array_like
        Joint values and rates (rad, rad/s; m, m/s).
    Mlist, Glist, Slist : array_like
        The model (the module docstring).

    Returns
    -------
    (n,) ndarray
        c(θ, θ̇) (N·m / N), quadratic in θ̇.

    Examples
    --------
    The planar two-link arm: ``c = (−m₂l₁l₂s₂(2θ̇₁θ̇₂ + θ̇₂²), m₂l₁l₂s₂θ̇₁²)``, at θ₂ = π/2 and
    θ̇ = (1, 1): ``(−1.2 × 3, 1.2)``:

    >>> p = rk.load("twolink").poe
    >>> vel_quadratic_forces([0, np.pi / 2], [1, 1], p.Mlist, p.Glist, p.Slist).round(4)
    array([-3.6,  1.2])
    """
    return _rnea_one_term("c", thetalist, dthetalist, Mlist, Glist, Slist)


def gravity_forces(thetalist: ArrayLike, g: ArrayLike, Mlist: ArrayLike, Glist: ArrayLike,
                   Slist: ArrayLike) -> np.ndarray:
    """Gravity torques ``g(θ)``: inverse dynamics with θ̇ = θ̈ = 0 and F_tip = 0 (Lecture 7, seed §4).

    Parameters
    ----------
    thetalist, g : (n,), (3,) array_like
        Joint values and gravity (the module docstring).
    Mlist, Glist, Slist : array_like
        The model (the module docstring); of ``Glist`` only the link masses act here (the frames
        of ``Mlist`` sit at the centres of mass).

    Returns
    -------
    (n,) ndarray
        The torques (N·m / N) that hold the arm still against gravity.

    Examples
    --------
    The planar two-link arm held horizontal (θ = 0, gravity −y): each joint carries every mass
    outboard of it times its lever arm, ``τ₁ = (m₁ + m₂) g l₁ + m₂ g l₂``, ``τ₂ = m₂ g l₂``:

    >>> p = rk.load("twolink").poe
    >>> gravity_forces([0, 0], [0, -9.81, 0], p.Mlist, p.Glist, p.Slist).round(4)
    array([46.107, 11.772])
    """
    return _rnea_one_term("g", thetalist, g, Mlist, Glist, Slist)


def end_effector_forces(thetalist: ArrayLike, Ftip: ArrayLike, Mlist: ArrayLike, Glist: ArrayLike,
                        Slist: ArrayLike) -> np.ndarray:
    """Torques ``Jᵀ(θ) F_tip`` that balance a tip wrench: inverse dynamics with no motion, no gravity.

    Parameters
    ----------
    thetalist, Ftip : (n,), (6,) array_like
        Joint values and the tip wrench (the module docstring).
    Mlist, Glist, Slist : array_like
        The model (the module docstring); ``Glist`` does not act here (no motion, no gravity).

    Returns
    -------
    (n,) ndarray
        τ = J_bᵀ F_tip (N·m / N).

    Examples
    --------
    The planar two-link arm stretched out (tip 1.8 m from joint 1, 0.8 m from joint 2) pushing
    10 N along the tip frame's y: ``τ = (1.8 × 10, 0.8 × 10)``:

    >>> p = rk.load("twolink").poe
    >>> end_effector_forces([0, 0], [0, 0, 0, 0, 10, 0], p.Mlist, p.Glist, p.Slist).round(4)
    array([18.,  8.])
    """
    return _rnea_one_term("F", thetalist, Ftip, Mlist, Glist, Slist)


def forward_dynamics(thetalist: ArrayLike, dthetalist: ArrayLike, taulist: ArrayLike, g: ArrayLike, Ftip: ArrayLike,
                     Mlist: ArrayLike, Glist: ArrayLike, Slist: ArrayLike, method: str = "aba") -> np.ndarray:
    """Joint accelerations ``θ̈ = M(θ)⁻¹ (τ − c(θ, θ̇) − g(θ) − Jᵀ F_tip)`` (Lecture 7, seed §4).

    Parameters
    ----------
    thetalist, dthetalist, taulist : (n,) or (N, n) array_like
        Joint values, rates and torques (rad, rad/s, N·m; m, m/s, N for prismatic joints), or N
        states at once (θ̈ is then (N, n), computed in parallel over the rows).
    g : (3,) array_like
        Gravity in the base frame (m/s²), e.g. ``[0, 0, -9.81]``.
    Ftip : (6,) or (N, 6) array_like
        Wrench ``(m, f)`` the end-effector applies to the environment, in its frame (N·m, N).
    Mlist, Glist, Slist : array_like
        The model (the module docstring).
    method : {"aba", "crba"}, optional
        ``"aba"`` (default) — Featherstone's articulated-body algorithm, O(n): an outward pass for
        the link twists, an inward pass for the articulated inertias
        ``Iᵃᵢ = Gᵢ + Σ Ad_{T}ᵀ (Iᵃ − U Uᵀ/D) Ad_{T}`` and bias forces, an outward pass for the
        accelerations (docs: course → dynamics, "Articulated-body forward dynamics");
        ``"crba"`` — the lecture's ``M⁻¹(τ − h)``: one Newton–Euler pass for ``h = c + g + JᵀF``,
        the composite-rigid-body mass matrix, a Cholesky solve, O(n²)–O(n³). Both agree with
        Pinocchio's ``aba`` to 1e-9.

    Returns
    -------
    (n,) ndarray, or (N, n) for N states
        θ̈ (rad/s², m/s²).

    Raises
    ------
    InputError
        On a bad argument, an unknown ``method``, or a mass matrix that is not positive definite.

    Examples
    --------
    Released at rest from horizontal with no torque, the planar two-link arm (point masses) starts
    in free fall: the elbow drops at g (θ̈₁ l₁ = −9.81 m/s²) and link 2 keeps its direction
    (θ̈₁ + θ̈₂ = 0). Forward dynamics undoes :func:`inverse_dynamics`:

    >>> p = rk.load("twolink").poe
    >>> g = [0, -9.81, 0]
    >>> forward_dynamics([0, 0], [0, 0], [0, 0], g, np.zeros(6), p.Mlist, p.Glist, p.Slist).round(4)
    array([-9.81,  9.81])
    >>> tau = inverse_dynamics([0.3, -0.4], [0.5, 1], [1, -2], g, np.zeros(6), p.Mlist, p.Glist, p.Slist)
    >>> forward_dynamics([0.3, -0.4], [0.5, 1], tau, g, np.zeros(6), p.Mlist, p.Glist, p.Slist).round(4)
    array([ 1., -2.])
    """
    if method not in ("aba", "crba"):
        raise InputError(f"method: expected 'aba' or 'crba', got {method!r}")
    k = _kd or _kernels()
    one, many = ((k.forward_dynamics, k.forward_dynamics_batch) if method == "aba"
                 else (k.forward_dynamics_crba, k.forward_dynamics_crba_batch))
    ddq = _fast(one, (thetalist, dthetalist, taulist, g, Ftip, Mlist, Glist, Slist), _NDIMS_8)
    if ddq is not None:
        return ddq
    m = _model(Mlist, Glist, Slist)
    batch = np.ndim(thetalist) == 2
    args = _checked(m, batch, thetalist, dthetalist, taulist, "taulist", g, Ftip)
    if batch:
        out = many(*args)
        if np.isnan(out).any():
            raise InputError("Glist: the mass matrix is not positive definite at some configuration "
                             "(a joint drives no inertia)")
        return out
    return one(*args)


def euler_step(thetalist: ArrayLike, dthetalist: ArrayLike, ddthetalist: ArrayLike,
               dt: float) -> tuple[np.ndarray, np.ndarray]:
    """One explicit Euler step (Modern Robotics' ``EulerStep``): ``(θ + dt θ̇, θ̇ + dt θ̈)``.

    The lecture's step keeps the second-order term, ``θ + θ̇Δt + ½θ̈Δt²``: that is
    :func:`robokit.dynamics.integrate` with ``method="taylor"`` (and ``"rk4"`` for fourth order).

    Parameters
    ----------
    thetalist, dthetalist, ddthetalist : (n,) array_like
        Joint values, rates and accelerations (rad, rad/s, rad/s²; or m, m/s, m/s²).
    dt : float
        Time step (s).

    Returns
    -------
    thetalistNext : (n,) ndarray
        ``θ + dt θ̇``.
    dthetalistNext : (n,) ndarray
        ``θ̇ + dt θ̈``.

    Examples
    --------
    >>> euler_step([0.0], [1.0], [2.0], 0.1)
    (array([0.1]), array([1.2]))
    """
    th = as_vector(thetalist, "thetalist")
    n = len(th)
    dth = as_vector(dthetalist, "dthetalist", n)
    ddth = as_vector(ddthetalist, "ddthetalist", n)
    dt = as_scalar(dt, "dt")
    return th + dt * dth, dth + dt * ddth


def inverse_dynamics_trajectory(thetamat: ArrayLike, dthetamat: ArrayLike, ddthetamat: ArrayLike, g: ArrayLike,
                                Ftipmat: ArrayLike, Mlist: ArrayLike, Glist: ArrayLike,
                                Slist: ArrayLike) -> np.ndarray:
    """Torques along a trajectory: row k of the result is :func:`inverse_dynamics` of row k (seed §4).

    Parameters
    ----------
    thetamat, dthetamat, ddthetamat : (N, n) array_like
        Joint values, rates and accelerations at N time steps (rad, rad/s, rad/s²).
    g : (3,) array_like
        Gravity in the base frame (m/s²).
    Ftipmat : (N, 6) array_like
        Tip wrench ``(m, f)`` at each step, end-effector frame (N·m, N).
    Mlist, Glist, Slist : array_like
        The model (the module docstring).

    Returns
    -------
    (N, n) ndarray
        τ at each step (N·m / N).

    Examples
    --------
    A 3-step trajectory of the planar two-link arm held horizontal: every row is the gravity torque
    of :func:`gravity_forces`:

    >>> p = rk.load("twolink").poe
    >>> Q = np.zeros((3, 2))
    >>> inverse_dynamics_trajectory(Q, Q, Q, [0, -9.81, 0], np.zeros((3, 6)), p.Mlist, p.Glist, p.Slist)
    array([[46.107, 11.772],
           [46.107, 11.772],
           [46.107, 11.772]])
    """
    m = _model(Mlist, Glist, Slist)
    Q = _radians(m, as_array(thetamat, "thetamat", (None, m.n)), "thetamat")
    N = Q.shape[0]
    dQ = as_array(dthetamat, "dthetamat", (N, m.n))
    ddQ = as_array(ddthetamat, "ddthetamat", (N, m.n))
    F = as_array(Ftipmat, "Ftipmat", (N, 6))
    g = _vec(g, "g", 3)
    if N == 0:
        return np.empty((0, m.n))
    c = _c
    k = _kd or _kernels()
    return k.inverse_dynamics_batch(c(Q), c(dQ), c(ddQ), c(g), c(F), m.Mlist, m.Glist, m.Slist)


def forward_dynamics_trajectory(thetalist: ArrayLike, dthetalist: ArrayLike, taumat: ArrayLike, g: ArrayLike,
                                Ftipmat: ArrayLike, Mlist: ArrayLike, Glist: ArrayLike, Slist: ArrayLike, dt: float,
                                intRes: int) -> tuple[np.ndarray, np.ndarray]:
    """Simulate the arm under a torque history by Euler integration (seed §4, Modern Robotics).

    Each torque row is held over ``[k dt, (k+1) dt)`` and integrated with ``intRes`` Euler steps of
    :func:`forward_dynamics` and :func:`euler_step`.

    Parameters
    ----------
    thetalist, dthetalist : (n,) array_like
        Initial joint values and rates (rad, rad/s; m, m/s).
    taumat : (N, n) array_like
        Joint torques, one row per time step (N·m / N).
    g : (3,) array_like
        Gravity in the base frame (m/s²).
    Ftipmat : (N, 6) array_like
        Tip wrench ``(m, f)`` at each step, end-effector frame (N·m, N).
    Mlist, Glist, Slist : array_like
        The model (the module docstring).
    dt : float
        Time step between rows (s), positive.
    intRes : int
        Euler steps per ``dt`` (≥ 1).

    Returns
    -------
    thetamat : (N, n) ndarray
        Joint values: row 0 is the initial state, row k+1 the state after applying torque row k
        (the last torque row is not applied, as in Modern Robotics).
    dthetamat : (N, n) ndarray
        Joint rates, rows as ``thetamat``.

    Examples
    --------
    The planar two-link arm released from horizontal with no torque, 3 rows 0.1 s apart: after
    0.1 s joint 1 turns at about −g t / l₁ ≈ −0.98 rad/s while link 2 keeps its direction:

    >>> p = rk.load("twolink").poe
    >>> th, dth = forward_dynamics_trajectory([0, 0], [0, 0], np.zeros((3, 2)), [0, -9.81, 0],
    ...                                       np.zeros((3, 6)), p.Mlist, p.Glist, p.Slist, 0.1, 10)
    >>> th.shape, dth.round(4)
    ((3, 2), array([[ 0.    ,  0.    ],
           [-0.9802,  0.9782],
           [-1.93  ,  1.853 ]]))
    """
    m = _model(Mlist, Glist, Slist)
    th = _radians(m, _vec(thetalist, "thetalist", m.n))
    dth = _vec(dthetalist, "dthetalist", m.n)
    tau = as_array(taumat, "taumat", (None, m.n))
    N = tau.shape[0]
    F = as_array(Ftipmat, "Ftipmat", (N, 6))
    g = _vec(g, "g", 3)
    dt = as_scalar(dt, "dt", positive=True)
    intRes = int(intRes)
    if intRes < 1:
        raise InputError(f"intRes: expected a positive integer, got {intRes}")
    if N == 0:
        return np.empty((0, m.n)), np.empty((0, m.n))
    c = _c
    k = _kd or _kernels()
    out = k.forward_dynamics_trajectory(c(th), c(dth), c(tau), c(g), c(F), m.Mlist, m.Glist, m.Slist, dt, intRes)
    return out[0], out[1]
