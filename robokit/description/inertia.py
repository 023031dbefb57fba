r"""Is a link's inertia physically possible? One check for every format and for the MJCF writer.

A rigid body of mass :math:`m` has, about its centre of mass, a symmetric inertia tensor
:math:`I_C` with principal moments :math:`I_1 \le I_2 \le I_3`. A body made of matter has

* :math:`m \ge 0`, and :math:`I_C = 0` when :math:`m = 0` (no matter, no rotational inertia);
* :math:`I_1 \ge 0` (:math:`I_C` positive semi-definite; a point mass or a thin rod has zero
  moments, which is the limit of real bodies and allowed);
* the triangle inequality :math:`I_1 + I_2 \ge I_3` — for every permutation, which for sorted
  moments is this one: with :math:`I_k = \int (r^2 - x_k^2)\,dm`, :math:`I_1 + I_2 - I_3 =
  2\int x_3^2\,dm \ge 0`.

:func:`physicality_problem` returns what is wrong (the inequality with its numbers) or None.
The tolerance is relative to the moments (:data:`PHYSICALITY_RTOL` times the largest), so that
a flat plate or a ring, which sits on the boundary :math:`I_1 + I_2 = I_3`, is not flagged for
the rounding of its printed digits; below ``mass · PHYSICALITY_LENGTH²`` a moment is rounding
(a point mass written with ``1e-35`` entries); ``atol`` adds the rounding of a value that was
computed (a link's inertia recovered from a merged body, :func:`link_inertias`).

:func:`link_inertias` recovers each link's own inertia from a Pinocchio model (Pinocchio's
parsers add the inertia of a link fixed to a moving one to that joint's body, and keep it on
the fixed joint's frame), so that a warning names the link the file gives the number for.
:func:`principal_moments` and :func:`triangle_margin` are shared with the MJCF writer
(:mod:`robokit.description.mjcf_write`), which needs the same test with MuJoCo's margins.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import ArrayLike

__all__ = ["PHYSICALITY_RTOL", "PHYSICALITY_LENGTH", "principal_moments", "triangle_margin", "physicality_problem", "LinkInertia",
           "link_inertias"]

#: Tolerance of :func:`physicality_problem`, relative to the largest principal moment: a
#: violation smaller than this (the rounding of values printed with 6–7 significant digits)
#: is not reported.
PHYSICALITY_RTOL = 1e-6

#: Moments below ``mass · PHYSICALITY_LENGTH²`` (kg·m²) are rounding, whatever their sign: no
#: body of matter is resolved at that size (a file writing ``ixz="2.4e-35"`` for a 1.3 kg head
#: means zero).
PHYSICALITY_LENGTH = 1e-6

#: Relative size of the rounding left by subtracting inertias (float64 sums of a few terms).
_SUBTRACTION_EPS = 1e-12


def principal_moments(inertia: ArrayLike) -> np.ndarray:
    """The principal moments of a symmetric 3×3 inertia tensor, ascending.

    Parameters
    ----------
    inertia : array_like, shape (3, 3)
        kg·m², about the centre of mass.

    Returns
    -------
    numpy.ndarray, shape (3,)
        ``I1 ≤ I2 ≤ I3``.

    Examples
    --------
    >>> principal_moments(np.diag([3.0, 1.0, 2.0])).tolist()
    [1.0, 2.0, 3.0]
    """
    I = np.asarray(inertia, dtype=float)
    return np.sort(np.linalg.eigvalsh(0.5 * (I + I.T)))


def triangle_margin(moments: ArrayLike) -> float:
    """``I1 + I2 − I3`` of the principal moments (sorted or not): negative when the triangle
    inequality is broken.

    Parameters
    ----------
    moments : array_like, shape (3,)
        Principal moments, kg·m².

    Returns
    -------
    float
        kg·m²; the smallest of ``Ia + Ib − Ic`` over the three permutations.

    Examples
    --------
    >>> triangle_margin([0.1, 0.1, 0.3])    # a rod-like body that cannot exist
    -0.09999999999999998
    """
    a, b, c = np.sort(np.asarray(moments, dtype=float))
    return float(a + b - c)


def _g(x: float) -> str:
    return f"{x:.6g}"


def physicality_problem(mass: float, inertia: ArrayLike, rtol: float = PHYSICALITY_RTOL,
                        atol: float = 0.0, mass_atol: float = 0.0) -> str | None:
    """What makes a body's inertia physically impossible, or None if nothing does.

    Parameters
    ----------
    mass : float
        kg.
    inertia : array_like, shape (3, 3)
        Rotational inertia about the centre of mass, kg·m².
    rtol : float
        Tolerance relative to the largest principal moment (:data:`PHYSICALITY_RTOL`).
    atol : float
        Absolute tolerance on the moments added to the relative one (kg·m²): the rounding of a
        computed value.
    mass_atol : float
        A mass below this in magnitude counts as zero (kg).

    Returns
    -------
    str or None
        The violated condition with its numbers, e.g. ``"principal moments (0.1, 0.1, 0.3)
        kg·m² break the triangle inequality I1 + I2 ≥ I3: 0.1 + 0.1 = 0.2 < 0.3"``.

    Examples
    --------
    >>> physicality_problem(1.0, np.diag([0.1, 0.1, 0.3]))
    'principal moments (0.1, 0.1, 0.3) kg·m² break the triangle inequality I1 + I2 ≥ I3: 0.1 + 0.1 = 0.2 < 0.3'
    >>> physicality_problem(2.0, np.zeros((3, 3))) is None      # a point mass
    True
    >>> physicality_problem(0.0, np.eye(3) * 0.1)
    'mass 0 kg with a nonzero rotational inertia (principal moments (0.1, 0.1, 0.1) kg·m²): not positive definite'
    """
    m = float(mass)
    lam = principal_moments(inertia)
    big = float(np.abs(lam).max())
    tol = rtol * big + atol + max(m, 0.0) * PHYSICALITY_LENGTH ** 2
    shown = f"({', '.join(_g(x) for x in lam)}) kg·m²"
    if m < -mass_atol:
        return f"mass {_g(m)} kg is negative: not positive definite"
    if abs(m) <= mass_atol and big > tol:
        return f"mass 0 kg with a nonzero rotational inertia (principal moments {shown}): not positive definite"
    if lam[0] < -tol:
        return f"principal moment I1 = {_g(lam[0])} kg·m² < 0 (principal moments {shown}): not positive definite"
    if lam[0] + lam[1] < lam[2] - tol:
        return (f"principal moments {shown} break the triangle inequality I1 + I2 ≥ I3: "
                f"{_g(lam[0])} + {_g(lam[1])} = {_g(lam[0] + lam[1])} < {_g(lam[2])}")
    return None


@dataclass(frozen=True)
class LinkInertia:
    """One link's own inertia, as its file states it (see :func:`link_inertias`).

    Attributes
    ----------
    link : str
        The link's (body's) name.
    joint : int
        The Pinocchio joint that carries it.
    mass : float
        kg.
    inertia : numpy.ndarray, shape (3, 3)
        About the centre of mass, kg·m².
    atol, mass_atol : float
        The rounding of the moments (kg·m²) and of the mass (kg) recovered by subtraction (0
        when read as they are).
    """

    link: str
    joint: int
    mass: float
    inertia: np.ndarray
    atol: float
    mass_atol: float


def _about_com(p: np.ndarray) -> tuple[float, np.ndarray]:
    """(mass, inertia about the centre of mass) of Pinocchio dynamic parameters
    ``(m, m c, Ixx, Ixy, Iyy, Ixz, Iyz, Izz)`` about the frame origin."""
    m = float(p[0])
    I = np.array([[p[4], p[5], p[7]], [p[5], p[6], p[8]], [p[7], p[8], p[9]]], dtype=float)
    if m > 0:
        c = p[1:4] / m
        I = I - m * (float(c @ c) * np.eye(3) - np.outer(c, c))
    return m, I


def link_inertias(model: Any) -> list[LinkInertia]:
    """Every link's own inertia in a Pinocchio model built from a robot file.

    Pinocchio's URDF and MJCF parsers keep the inertia of a link attached by a fixed joint on
    that fixed joint's frame and add it to the moving joint's body; the moving link's own
    inertia is that body minus those frames' inertias. Links with neither mass nor inertia
    are left out.

    Parameters
    ----------
    model : pinocchio.Model
        The whole kinematic tree as the file describes it.

    Returns
    -------
    list of LinkInertia
        The fixed links (in frame order), then each joint's moving link; joint 0 (the world)
        included.

    Examples
    --------
    >>> import pinocchio as pin
    >>> from robokit.description.models import model_path
    >>> [(li.link, li.mass) for li in link_inertias(pin.buildModelFromUrdf(str(model_path("twolink", ".urdf"))))]
    [('link_1', 2.0), ('link_2', 1.5)]
    """
    import pinocchio as pin

    fixed, body, joint_type = pin.FrameType.FIXED_JOINT, pin.FrameType.BODY, pin.FrameType.JOINT
    rest = [np.asarray(model.inertias[j].toDynamicParameters(), dtype=float).ravel() for j in range(model.njoints)]
    scale = [np.abs(r) for r in rest]  # the magnitudes summed into each joint's body, per parameter
    children: dict[int, list[int]] = {}
    for fid, f in enumerate(model.frames):
        children.setdefault(f.parentFrame, []).append(fid)
    out = []
    for fid, f in enumerate(model.frames):
        if f.type not in (fixed, body) or (f.type == body and f.parentJoint != 0):
            continue  # a moving link's body frame carries no inertia of its own in Pinocchio
        p = np.asarray(f.inertia.toDynamicParameters(), dtype=float).ravel()
        if not np.any(p):
            continue
        name = f.name
        if f.type == fixed:  # the link is the body frame that hangs from this fixed joint
            kids = [model.frames[k].name for k in children.get(fid, []) if model.frames[k].type == body and k != fid]
            name = kids[0] if kids else f.name
        out.append(LinkInertia(name, int(f.parentJoint), float(f.inertia.mass), np.array(f.inertia.inertia), 0.0, 0.0))
        moved = np.asarray(f.placement.act(f.inertia).toDynamicParameters(), dtype=float).ravel()
        rest[f.parentJoint] = rest[f.parentJoint] - moved
        scale[f.parentJoint] = np.maximum(scale[f.parentJoint], np.abs(moved))
    for j in range(1, model.njoints):
        p = rest[j]
        mass_atol = _SUBTRACTION_EPS * float(scale[j][0])
        atol = _SUBTRACTION_EPS * float(scale[j][4:].max())  # moments about the joint: m c² included
        if abs(p[0]) <= mass_atol and float(np.abs(p[4:]).max()) <= atol:
            continue
        name = model.names[j]
        if model.existFrame(name, joint_type):
            jf = model.getFrameId(name, joint_type)
            kids = [model.frames[k].name for k in children.get(jf, []) if model.frames[k].type == body]
            name = kids[0] if kids else name
        m, I = _about_com(p)
        out.append(LinkInertia(name, j, m, I, atol, mass_atol))
    return out
