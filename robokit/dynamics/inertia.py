r"""Inertia tensors of simple bodies, the parallel-axis theorem and rotation of a tensor (Lecture 7).

The inertia tensor of a body about a point A, in the axes of a frame {A}, is (Lecture 7)

.. math::

    {}^A I = \begin{pmatrix} I_{xx} & -I_{xy} & -I_{xz} \\ -I_{xy} & I_{yy} & -I_{yz} \\
             -I_{xz} & -I_{yz} & I_{zz} \end{pmatrix},\quad
    I_{xx} = \iiint_V (y^2 + z^2)\,\rho\,dv,\ \ldots,\quad I_{xy} = \iiint_V x y\,\rho\,dv,\ \ldots

(the moments on the diagonal, the *negated* products of inertia off it). All tensors here are
3×3 float arrays in kg·m², lengths in m, masses in kg.

* Solid bodies of uniform density about their centre of mass, in their principal axes:
  :func:`inertia_box`, :func:`inertia_cylinder`, :func:`inertia_sphere`, :func:`inertia_rod`.
* :func:`parallel_axis` — the tensor about another point: ``ᴬI = ᶜI + m (p_cᵀ p_c I₃ − p_c p_cᵀ)``
  with p_c the centre of mass in {A} (Lecture 7; e.g. ``ᴬI_zz = ᶜI_zz + m (x_c² + y_c²)``,
  ``ᴬI_xy = ᶜI_xy − m x_c y_c``).
* :func:`rotate_inertia` — the same tensor in rotated axes: ``ᴬI = ᴬR_B ᴮI ᴬR_Bᵀ``.

Example: the lecture's box of sides w (x), l (y), h (z) with a corner at the origin of {A} and its
edges along the axes is ``parallel_axis(inertia_box(m, w, l, h), m, [w/2, l/2, h/2])``, whose
diagonal is ``m/3 (l² + h²), m/3 (w² + h²), m/3 (l² + w²)`` and off-diagonal ``−m w l / 4`` etc.
"""
from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike

from robokit._arrays import as_matrix, as_scalar, as_vector
from robokit.spatial.so3 import check_rotation
from robokit.errors import InputError

__all__ = [
    "inertia_box",
    "inertia_cylinder",
    "inertia_sphere",
    "inertia_rod",
    "parallel_axis",
    "rotate_inertia",
]

_AXES = {"x": 0, "y": 1, "z": 2}


def _axis(axis: str) -> int:
    if not isinstance(axis, str) or axis.lower() not in _AXES:
        raise InputError(f"axis: expected 'x', 'y' or 'z', got {axis!r}")
    return _AXES[axis.lower()]


def _sizes(**sizes: float) -> list[float]:
    """The mass and dimensions of a primitive body, each a finite non-negative float (else
    :class:`InputError` naming the argument), in the order given."""
    return [as_scalar(v, name, nonnegative=True) for name, v in sizes.items()]


def inertia_box(mass: float, lx: float, ly: float, lz: float) -> np.ndarray:
    """Inertia of a uniform solid box about its centre, axes along its edges (Lecture 7).

    ``diag(m (l_y² + l_z²)/12, m (l_x² + l_z²)/12, m (l_x² + l_y²)/12)`` — the lecture's integrals
    ``I_xx = ∭ (y² + z²) ρ dv`` over ``[−l_x/2, l_x/2] × …``; products of inertia vanish by
    symmetry.

    Parameters
    ----------
    mass : float
        Mass (kg), non-negative.
    lx, ly, lz : float
        Edge lengths along x, y, z (m), non-negative.

    Returns
    -------
    (3, 3) ndarray
        The inertia tensor (kg·m²) about the centre of mass, in the box's axes.

    Examples
    --------
    A 12 kg unit cube: ``12 × (1 + 1)/12 = 2`` about every axis:

    >>> inertia_box(12.0, 1.0, 1.0, 1.0)
    array([[2., 0., 0.],
           [0., 2., 0.],
           [0., 0., 2.]])
    """
    m, a, b, c = _sizes(mass=mass, lx=lx, ly=ly, lz=lz)
    return m / 12.0 * np.diag([b * b + c * c, a * a + c * c, a * a + b * b])


def inertia_cylinder(mass: float, radius: float, length: float, axis: str = "z") -> np.ndarray:
    """Inertia of a uniform solid cylinder about its centre, its axis along ``axis`` (Lecture 7).

    About the cylinder's axis ``m r²/2``; about any diameter through the centre ``m (3 r² + L²)/12``.

    Parameters
    ----------
    mass : float
        Mass (kg).
    radius, length : float
        Radius and length (m).
    axis : {"x", "y", "z"}, optional
        Direction of the cylinder's axis; default "z".

    Returns
    -------
    (3, 3) ndarray
        Diagonal inertia tensor (kg·m²) about the centre of mass.

    Raises
    ------
    InputError
        On a negative value or an unknown axis.

    Examples
    --------
    A 2 kg disc of radius 0.1 m (length 0): ``m r²/2 = 0.01`` about its axis, half that across:

    >>> inertia_cylinder(2.0, 0.1, 0.0)
    array([[0.005, 0.   , 0.   ],
           [0.   , 0.005, 0.   ],
           [0.   , 0.   , 0.01 ]])
    """
    m, r, L = _sizes(mass=mass, radius=radius, length=length)
    k = _axis(axis)
    d = np.full(3, m * (3.0 * r * r + L * L) / 12.0)
    d[k] = 0.5 * m * r * r
    return np.diag(d)


def inertia_sphere(mass: float, radius: float, hollow: bool = False) -> np.ndarray:
    """Inertia of a uniform sphere about its centre: ``2/5 m r² I₃`` (solid) or ``2/3 m r² I₃`` (shell).

    Parameters
    ----------
    mass : float
        Mass (kg).
    radius : float
        Radius (m).
    hollow : bool, optional
        A thin spherical shell instead of a solid ball; default False.

    Returns
    -------
    (3, 3) ndarray
        Isotropic inertia tensor (kg·m²).

    Examples
    --------
    >>> float(inertia_sphere(5.0, 1.0)[0, 0]), float(inertia_sphere(3.0, 1.0, hollow=True)[0, 0])
    (2.0, 2.0)
    """
    m, r = _sizes(mass=mass, radius=radius)
    return (2.0 / 3.0 if hollow else 0.4) * m * r * r * np.eye(3)


def inertia_rod(mass: float, length: float, axis: str = "z") -> np.ndarray:
    """Inertia of a thin uniform rod about its centre, lying along ``axis`` (Lecture 7).

    ``m L²/12`` about the two axes across the rod, 0 about the rod itself (the limit of
    :func:`inertia_cylinder` as r → 0). Use :func:`parallel_axis` with ``p = (L/2)·axis`` for the rod
    about one end (``m L²/3``).

    Parameters
    ----------
    mass : float
        Mass (kg).
    length : float
        Length (m).
    axis : {"x", "y", "z"}, optional
        Direction of the rod; default "z".

    Returns
    -------
    (3, 3) ndarray
        Diagonal inertia tensor (kg·m²) about the centre of mass.

    Examples
    --------
    A 3 kg, 2 m rod along x: ``3 × 2²/12 = 1`` across it; about one end ``m L²/3 = 4``:

    >>> inertia_rod(3.0, 2.0, "x")
    array([[0., 0., 0.],
           [0., 1., 0.],
           [0., 0., 1.]])
    >>> float(parallel_axis(inertia_rod(3.0, 2.0, "x"), 3.0, [1, 0, 0])[2, 2])
    4.0
    """
    m, L = _sizes(mass=mass, length=length)
    d = np.full(3, m * L * L / 12.0)
    d[_axis(axis)] = 0.0
    return np.diag(d)


def _tensor(I: ArrayLike, name: str) -> np.ndarray:
    I = as_matrix(I, name, 3, 3)
    if np.abs(I - I.T).max() > 1e-9 * max(1.0, np.abs(I).max()):
        raise InputError(f"{name}: expected a symmetric 3×3 inertia tensor, got {I.tolist()}")
    return I


def parallel_axis(I_c: ArrayLike, mass: float, p_c: ArrayLike) -> np.ndarray:
    """The inertia about the origin of {A} from the inertia about the centre of mass (same axes).

    ``ᴬI = ᶜI + m (p_cᵀ p_c I₃ − p_c p_cᵀ)`` (Lecture 7, the parallel-axis theorem; e.g.
    ``ᴬI_zz = ᶜI_zz + m (x_c² + y_c²)``, ``ᴬI_xy = ᶜI_xy − m x_c y_c``).

    Parameters
    ----------
    I_c : (3, 3) array_like
        Inertia about the centre of mass, in {A}'s axes (kg·m²), symmetric.
    mass : float
        Mass (kg).
    p_c : (3,) array_like
        Position of the centre of mass in {A} (m).

    Returns
    -------
    (3, 3) ndarray
        The inertia about {A}'s origin, in {A}'s axes (kg·m²).

    Raises
    ------
    InputError
        When ``I_c`` is not a symmetric 3×3 matrix, or on a bad mass or position.

    Examples
    --------
    A 2 kg point mass at (1, 0, 0): ``m x² = 2`` about y and z, nothing about x:

    >>> parallel_axis(np.zeros((3, 3)), 2, [1, 0, 0])
    array([[0., 0., 0.],
           [0., 2., 0.],
           [0., 0., 2.]])
    """
    I = _tensor(I_c, "I_c")
    m = as_scalar(mass, "mass", nonnegative=True)
    p = as_vector(p_c, "p_c", 3)
    return I + m * (float(p @ p) * np.eye(3) - np.outer(p, p))


def rotate_inertia(I_b: ArrayLike, R_a_b: ArrayLike) -> np.ndarray:
    """The same inertia tensor expressed in the axes of {A}: ``ᴬI = ᴬR_B ᴮI ᴬR_Bᵀ`` (Lecture 7).

    The reference point does not change (combine with :func:`parallel_axis` to move it).

    Parameters
    ----------
    I_b : (3, 3) array_like
        Inertia in {B}'s axes (about some point), kg·m², symmetric.
    R_a_b : (3, 3) array_like
        Orientation of {B} in {A} (a rotation matrix).

    Returns
    -------
    (3, 3) ndarray
        The tensor in {A}'s axes (kg·m²).

    Examples
    --------
    A rod along z turned 90° about y lies along x:

    >>> R_a_b = np.array([[0.0, 0, 1], [0, 1, 0], [-1, 0, 0]])  # Ry(π/2)
    >>> bool(np.allclose(rotate_inertia(inertia_rod(3, 2, "z"), R_a_b), inertia_rod(3, 2, "x")))
    True
    """
    I = _tensor(I_b, "I_b")
    R = check_rotation(R_a_b, "R_a_b")
    return R @ I @ R.T
