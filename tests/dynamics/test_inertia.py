"""Inertia tensors against numerical integration of the lecture's integrals, the lecture's
box-about-a-corner tensor, and the parallel-axis / rotation identities."""
import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from robokit.dynamics.inertia import (inertia_box, inertia_cylinder, inertia_rod, inertia_sphere,
                                      parallel_axis, rotate_inertia)
from robokit.spatial.euler import matrix_from_euler


def _tensor_from_points(pts, w):
    """Lecture 7: I_xx = ∑ (y² + z²) dm …, off-diagonal −∑ x y dm …"""
    x, y, z = pts.T
    Ixx, Iyy, Izz = (w * (y**2 + z**2)).sum(), (w * (x**2 + z**2)).sum(), (w * (x**2 + y**2)).sum()
    Ixy, Ixz, Iyz = (w * x * y).sum(), (w * x * z).sum(), (w * y * z).sum()
    return np.array([[Ixx, -Ixy, -Ixz], [-Ixy, Iyy, -Iyz], [-Ixz, -Iyz, Izz]])


def _midpoints(a, b, k):
    h = (b - a) / k
    return a + h * (np.arange(k) + 0.5), h


def test_box_against_midpoint_integration():
    m, lx, ly, lz = 3.0, 0.4, 0.7, 1.1
    k = 60
    xs, hx = _midpoints(-lx / 2, lx / 2, k)
    ys, hy = _midpoints(-ly / 2, ly / 2, k)
    zs, hz = _midpoints(-lz / 2, lz / 2, k)
    X, Y, Z = np.meshgrid(xs, ys, zs, indexing="ij")
    pts = np.c_[X.ravel(), Y.ravel(), Z.ravel()]
    rho = m / (lx * ly * lz)
    I_num = _tensor_from_points(pts, np.full(len(pts), rho * hx * hy * hz))
    # midpoint rule error is O(h²): relative 1e-3 is far below the size of any mistake in a formula
    np.testing.assert_allclose(inertia_box(m, lx, ly, lz), I_num, rtol=1e-3, atol=1e-12)


@pytest.mark.parametrize("axis", ["x", "y", "z"])
def test_cylinder_against_integration_in_cylindrical_coordinates(axis):
    m, r, L = 2.0, 0.15, 0.9
    k = 80
    rs, hr = _midpoints(0.0, r, k)
    ps, hp = _midpoints(0.0, 2 * np.pi, k)
    zs, hz = _midpoints(-L / 2, L / 2, k)
    R_, P_, Z_ = np.meshgrid(rs, ps, zs, indexing="ij")
    a, b, c = (R_ * np.cos(P_)).ravel(), (R_ * np.sin(P_)).ravel(), Z_.ravel()
    rho = m / (np.pi * r * r * L)
    w = rho * R_.ravel() * hr * hp * hz  # dv = r dr dφ dz
    order = {"z": (a, b, c), "x": (c, a, b), "y": (b, c, a)}[axis]
    I_num = _tensor_from_points(np.c_[order], w)
    np.testing.assert_allclose(inertia_cylinder(m, r, L, axis), I_num, rtol=2e-3, atol=1e-9)


def test_sphere_and_rod_closed_forms():
    # a solid sphere is the r → shell integral ∫ 2/3 (4πρ s²)s² ds = 2/5 m r²
    s, h = _midpoints(0.0, 1.0, 2000)
    m, r = 5.0, 1.0
    rho = m / (4 / 3 * np.pi)
    I = (2 / 3 * 4 * np.pi * rho * s**4 * h).sum()
    np.testing.assert_allclose(inertia_sphere(m, r), I * np.eye(3), rtol=1e-6)
    np.testing.assert_allclose(inertia_sphere(3.0, 2.0, hollow=True), 2 / 3 * 3 * 4 * np.eye(3))
    # rod: limit of a thin cylinder; about one end m L²/3
    np.testing.assert_allclose(inertia_rod(3.0, 2.0, "x"), inertia_cylinder(3.0, 0.0, 2.0, "x"))
    end = parallel_axis(inertia_rod(3.0, 2.0, "x"), 3.0, [1.0, 0, 0])
    np.testing.assert_allclose(np.diag(end), [0.0, 3.0 * 4 / 3, 3.0 * 4 / 3])


def test_lecture_box_about_a_corner():
    """Lecture 7's example: uniform box w × l × h with a corner at the origin."""
    m, w, l, h = 2.0, 0.3, 0.5, 0.8
    I = parallel_axis(inertia_box(m, w, l, h), m, [w / 2, l / 2, h / 2])
    lecture = np.array([
        [m / 3 * (l**2 + h**2), -m / 4 * w * l, -m / 4 * h * w],
        [-m / 4 * w * l, m / 3 * (w**2 + h**2), -m / 4 * h * l],
        [-m / 4 * h * w, -m / 4 * h * l, m / 3 * (l**2 + w**2)],
    ])
    np.testing.assert_allclose(I, lecture, rtol=1e-12)


angles = st.lists(st.floats(-3, 3), min_size=3, max_size=3)


@settings(max_examples=40, deadline=None)
@given(angles, st.lists(st.floats(-1, 1), min_size=3, max_size=3), st.floats(0.1, 5.0))
def test_rotation_and_parallel_axis_commute_with_point_masses(eul, p, m):
    """Point-mass clouds: rotating and shifting the cloud equals rotating/shifting its tensor."""
    rng = np.random.default_rng(0)
    pts = rng.normal(size=(7, 3))
    w = np.full(7, m / 7)
    pts = pts - (w[:, None] * pts).sum(0) / m  # centre of mass at the origin
    R = matrix_from_euler(eul, "ZYX")
    p = np.asarray(p)
    I_c = _tensor_from_points(pts, w)
    np.testing.assert_allclose(rotate_inertia(I_c, R), _tensor_from_points(pts @ R.T, w), atol=1e-12)
    np.testing.assert_allclose(parallel_axis(I_c, m, p), _tensor_from_points(pts + p, w), atol=1e-12)


def test_bad_input():
    with pytest.raises(ValueError, match="mass"):
        inertia_box(-1.0, 1, 1, 1)
    with pytest.raises(ValueError, match="axis"):
        inertia_cylinder(1.0, 1.0, 1.0, "w")
    with pytest.raises(ValueError, match="I_c"):
        parallel_axis(np.arange(9.0).reshape(3, 3), 1.0, [0, 0, 0])
    with pytest.raises(ValueError, match="R_a_b"):
        rotate_inertia(np.eye(3), 2 * np.eye(3))
