r"""The small geometry MuJoCo's compiler does, done the same way (private to the MJCF reader).

MuJoCo's compiler keeps orientations as unit quaternions ``(w, x, y, z)`` and reduces every
inertia tensor it sums or is given in full to a principal frame and three principal moments
(decreasing). MuJoCo 4 computes that decomposition to rounding error for bodies (robokit's tests
measure ``R diag(I) Rᵀ`` against the tensor at 1e-16: :func:`principal_axes`); a mesh's inertia it
reduces by Jacobi rotations stopped at a relative tolerance of 1e-7, which leaves its frame up to
about 1e-7 rad short of the principal axes, and robokit stops them the same way
(:func:`jacobi_principal_axes`); older MuJoCo releases stopped their Jacobi iteration about 1e-6
rad short for bodies too, which moved the simulated tensor by up to ~1e-10 of its size. The compiler's quaternion conventions are written out here as MuJoCo writes them (the
normalisation that leaves a vector alone within 1e-14 of unit length, the minimal rotation
taking z to a vector, the frame to quaternion conversion), on Python floats and short tuples.
"""
from __future__ import annotations

import math
from typing import Sequence

#: MuJoCo's mjEPS and mjMINVAL.
EPS, MINVAL = 1e-14, 1e-15

Vec = tuple[float, float, float]
Quat = tuple[float, float, float, float]
Mat = tuple[float, float, float, float, float, float, float, float, float]  # row-major 3×3

IDENTITY: Quat = (1.0, 0.0, 0.0, 0.0)


def normalized(v: Sequence[float]) -> tuple[tuple[float, ...], float]:
    """(v / |v|, |v|) as MuJoCo normalises: left alone within 1e-14 of unit length, and a
    vector shorter than sqrt(1e-14) returned unchanged with norm 0."""
    nrm = sum(x * x for x in v)
    if nrm < EPS:
        return tuple(float(x) for x in v), 0.0
    nrm = math.sqrt(nrm)
    if abs(nrm - 1.0) > EPS:
        return tuple(float(x) / nrm for x in v), nrm
    return tuple(float(x) for x in v), nrm


def unit_quat(q: Sequence[float]) -> Quat:
    """A quaternion normalised as MuJoCo does (a zero quaternion stays zero)."""
    w, x, y, z = normalized(q)[0]
    return (w, x, y, z)


def quat_to_matrix(q: Sequence[float]) -> Mat:
    """The rotation matrix (row-major) of a unit quaternion (w, x, y, z)."""
    if q[0] == 1 and q[1] == 0 and q[2] == 0 and q[3] == 0:
        return (1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0)
    q00, q01, q02, q03 = q[0] * q[0], q[0] * q[1], q[0] * q[2], q[0] * q[3]
    q11, q12, q13 = q[1] * q[1], q[1] * q[2], q[1] * q[3]
    q22, q23, q33 = q[2] * q[2], q[2] * q[3], q[3] * q[3]
    return (q00 + q11 - q22 - q33, 2 * (q12 - q03), 2 * (q13 + q02),
            2 * (q12 + q03), q00 - q11 + q22 - q33, 2 * (q23 - q01),
            2 * (q13 - q02), 2 * (q23 + q01), q00 - q11 - q22 + q33)


def quat_mul(a: Sequence[float], b: Sequence[float]) -> Quat:
    """The product a·b, normalised as MuJoCo does."""
    return unit_quat((a[0] * b[0] - a[1] * b[1] - a[2] * b[2] - a[3] * b[3],
                      a[0] * b[1] + a[1] * b[0] + a[2] * b[3] - a[3] * b[2],
                      a[0] * b[2] - a[1] * b[3] + a[2] * b[0] + a[3] * b[1],
                      a[0] * b[3] + a[1] * b[2] - a[2] * b[1] + a[3] * b[0]))


def mat_vec(m: Sequence[float], v: Sequence[float]) -> Vec:
    """m·v for a row-major 3×3 m."""
    return (m[0] * v[0] + m[1] * v[1] + m[2] * v[2], m[3] * v[0] + m[4] * v[1] + m[5] * v[2],
            m[6] * v[0] + m[7] * v[1] + m[8] * v[2])


def rotate(q: Sequence[float], v: Sequence[float]) -> Vec:
    """v rotated by the unit quaternion q."""
    if v[0] == 0 and v[1] == 0 and v[2] == 0:
        return (0.0, 0.0, 0.0)
    if q[0] == 1 and q[1] == 0 and q[2] == 0 and q[3] == 0:
        return (float(v[0]), float(v[1]), float(v[2]))
    t = (q[0] * v[0] + q[2] * v[2] - q[3] * v[1], q[0] * v[1] + q[3] * v[0] - q[1] * v[2],
         q[0] * v[2] + q[1] * v[1] - q[2] * v[0])
    return (v[0] + 2 * (q[2] * t[2] - q[3] * t[1]), v[1] + 2 * (q[3] * t[0] - q[1] * t[2]),
            v[2] + 2 * (q[1] * t[1] - q[2] * t[0]))


def compose(pos: Sequence[float], quat: Sequence[float], child_pos: Sequence[float],
            child_quat: Sequence[float]) -> tuple[Vec, Quat]:
    """The pose (pos, quat) ∘ (child_pos, child_quat): a child frame expressed in the parent's parent."""
    v = mat_vec(quat_to_matrix(quat), child_pos)
    return (pos[0] + v[0], pos[1] + v[1], pos[2] + v[2]), quat_mul(quat, child_quat)


def conj(q: Sequence[float]) -> Quat:
    """The conjugate (inverse rotation) of a unit quaternion."""
    return (q[0], -q[1], -q[2], -q[3])


def z_to_quat(vec: Sequence[float]) -> Quat:
    """The minimal rotation taking (0, 0, 1) to the direction of ``vec`` (MuJoCo's rule, also
    for ``vec`` along −z: a half turn about x)."""
    axis, s = normalized((-vec[1], vec[0], 0.0))  # (0, 0, 1) × vec
    if s < 1e-10:
        axis = (1.0, 0.0, 0.0)
    ang = math.atan2(s, vec[2])
    c, sn = math.cos(ang / 2), math.sin(ang / 2)
    return (c, axis[0] * sn, axis[1] * sn, axis[2] * sn)


def frame_to_quat(x: Sequence[float], y: Sequence[float], z: Sequence[float]) -> Quat:
    """The quaternion of the rotation whose columns are the unit vectors x, y, z."""
    m = (x, y, z)  # m[c][r]
    if m[0][0] + m[1][1] + m[2][2] > 0:
        w = 0.5 * math.sqrt(1 + m[0][0] + m[1][1] + m[2][2])
        q = (w, 0.25 * (m[1][2] - m[2][1]) / w, 0.25 * (m[2][0] - m[0][2]) / w, 0.25 * (m[0][1] - m[1][0]) / w)
    elif m[0][0] > m[1][1] and m[0][0] > m[2][2]:
        a = 0.5 * math.sqrt(1 + m[0][0] - m[1][1] - m[2][2])
        q = (0.25 * (m[1][2] - m[2][1]) / a, a, 0.25 * (m[1][0] + m[0][1]) / a, 0.25 * (m[2][0] + m[0][2]) / a)
    elif m[1][1] > m[2][2]:
        b = 0.5 * math.sqrt(1 - m[0][0] + m[1][1] - m[2][2])
        q = (0.25 * (m[2][0] - m[0][2]) / b, 0.25 * (m[1][0] + m[0][1]) / b, b, 0.25 * (m[2][1] + m[1][2]) / b)
    else:
        c = 0.5 * math.sqrt(1 - m[0][0] - m[1][1] + m[2][2])
        q = (0.25 * (m[0][1] - m[1][0]) / c, 0.25 * (m[2][0] + m[0][2]) / c, 0.25 * (m[2][1] + m[1][2]) / c, c)
    return unit_quat(q)


def orientation(kind: str, values: Sequence[float], degree: bool, eulerseq: str) -> Quat | str:
    """The quaternion of one of MJCF's orientation alternatives (``axisangle``, ``xyaxes``,
    ``zaxis``, ``euler``), or the reason it is invalid (a string, as MuJoCo's compiler says it)."""
    if kind == "axisangle":
        axis, n = normalized(values[:3])
        if n < EPS:
            return "axisangle too small"
        ang = values[3] / 180.0 * math.pi if degree else float(values[3])
        s = math.sin(ang / 2)
        return (math.cos(ang / 2), s * axis[0], s * axis[1], s * axis[2])
    if kind == "xyaxes":
        x, n = normalized(values[:3])
        if n < EPS:
            return "xaxis too small"
        d = x[0] * values[3] + x[1] * values[4] + x[2] * values[5]
        y, n = normalized((values[3] - x[0] * d, values[4] - x[1] * d, values[5] - x[2] * d))
        if n < EPS:
            return "yaxis too small"
        z, n = normalized((x[1] * y[2] - x[2] * y[1], x[2] * y[0] - x[0] * y[2], x[0] * y[1] - x[1] * y[0]))
        if n < EPS:
            return "cross(xaxis, yaxis) too small"
        return frame_to_quat(x, y, z)
    if kind == "zaxis":
        z, n = normalized(values)
        if n < EPS:
            return "zaxis too small"
        return z_to_quat(z)
    if kind == "euler":
        q: Quat = IDENTITY
        for axis_name, a in zip(eulerseq, values):
            a = a / 180.0 * math.pi if degree else float(a)
            r = [math.cos(a / 2), 0.0, 0.0, 0.0]
            if axis_name.lower() not in "xyz":
                return "euler sequence can only contain x, y, z, X, Y, Z"
            r["xyz".index(axis_name.lower()) + 1] = math.sin(a / 2)
            q = quat_mul(q, r) if axis_name.islower() else quat_mul(r, q)  # moving axes post-multiply
        return unit_quat(q)
    return f"unknown orientation {kind!r}"


def principal_axes(full: Sequence[float]) -> tuple[Vec, Quat]:
    """Principal moments (decreasing) and principal frame (a right-handed rotation, as a unit
    quaternion) of a symmetric 3×3 given row-major, computed exactly (LAPACK's symmetric
    eigensolver), as MuJoCo 4 computes them."""
    import numpy as np

    w, V = np.linalg.eigh(np.array(full, dtype=float).reshape(3, 3))
    w, V = w[::-1], V[:, ::-1]
    if np.linalg.det(V) < 0:
        V[:, 2] = -V[:, 2]
    q = frame_to_quat(tuple(V[:, 0]), tuple(V[:, 1]), tuple(V[:, 2]))
    return (float(w[0]), float(w[1]), float(w[2])), q


#: MuJoCo 4's relative tolerance when it reduces a *mesh's* inertia to principal axes
#: (:func:`jacobi_principal_axes`). Measured on MuJoCo 4.0.1: with it, 60 random convex STL meshes and
#: robosuite's Fourier/Inspire hand meshes give MuJoCo's ``body_inertia``/``body_iquat`` to 2.5e-15 of the
#: tensor, where the exact axes were up to 9.5e-8 off (1e-8 or 1e-6 leave 20 and 25 of the 60 off).
MESH_EIG_RELTOL = 1e-7
#: cos(π/4) as MuJoCo's compiler writes it (15 digits): the quarter turn that swaps two principal axes.
_COS_QUARTER_TURN = 0.707106781186548


def jacobi_principal_axes(full: Sequence[float], reltol: float) -> tuple[Vec, Quat]:
    """Principal moments and frame of a symmetric 3×3 (row-major) by Jacobi rotations accumulated in a
    quaternion, stopped as MuJoCo's compiler stops them — its reduction of a mesh's inertia, which ends
    short of the exact axes (by up to about ``reltol`` rad of the tensor's scale over the gap between its
    moments).

    From the identity: with ``D = Rᵀ A R`` (R the frame so far), take the off-diagonal entry of largest
    magnitude (ties: (0, 1), then (0, 2), then (1, 2)); stop when it is at most ``reltol`` (at least
    4e-15) times the largest |entry| of A, or after 500 rotations; else turn the frame about the third
    axis by the angle that zeroes it (``t = tan θ`` the smaller root of ``t² + 2τt − 1 = 0``,
    ``τ = (D_cc − D_rr) / 2D_rc``, the quaternion from ``tan(θ/2)``). The diagonal of the last ``D`` gives
    the moments, then put in decreasing order by three passes of a bubble sort (pairs (0, 1), (1, 2),
    (0, 1); a pair is swapped when the second exceeds the first by more than the scale times
    ``max(reltol, 1e-12)``), each swap turning the frame a quarter turn about the third axis, so that it
    stays right-handed.

    Parameters
    ----------
    full : sequence of 9 float
        The symmetric matrix, row-major.
    reltol : float
        The relative stopping tolerance (:data:`MESH_EIG_RELTOL` for meshes).

    Returns
    -------
    (tuple of 3 float, tuple of 4 float)
        The moments (decreasing, up to the swap tolerance) and the frame as a unit quaternion (w, x, y, z).
    """
    a = tuple(float(x) for x in full)
    scale = max(abs(x) for x in a)
    tol = scale * max(reltol, 4e-15)
    q: Quat = IDENTITY
    ev = [a[0], a[4], a[8]]
    for _ in range(500):
        r = quat_to_matrix(q)
        rt = (r[0], r[3], r[6], r[1], r[4], r[7], r[2], r[5], r[8])
        d = _mat_mul(_mat_mul(rt, a), r)
        ev = [d[0], d[4], d[8]]
        if abs(d[1]) > abs(d[2]) and abs(d[1]) > abs(d[5]):
            row, col, axis = 0, 1, 2
        elif abs(d[2]) > abs(d[5]):
            row, col, axis = 0, 2, 1
        else:
            row, col, axis = 1, 2, 0
        off = d[3 * row + col]
        if abs(off) <= tol:
            break
        tau = (d[4 * col] - d[4 * row]) / (2.0 * off)
        root = math.sqrt(1.0 + tau * tau)
        t = 1.0 / (tau + root) if tau >= 0 else -1.0 / (-tau + root)
        half = t / (1.0 + math.sqrt(1.0 + t * t))  # tan(θ/2)
        w = 1.0 / math.sqrt(1.0 + half * half)
        turn = [w, 0.0, 0.0, 0.0]
        turn[axis + 1] = (half if axis == 1 else -half) * w
        q = unit_quat(quat_mul(q, turn))
    eps = scale * max(reltol, 1e-12)
    for j in (0, 1, 0):
        if ev[j] + eps < ev[j + 1]:
            ev[j], ev[j + 1] = ev[j + 1], ev[j]
            turn = [_COS_QUARTER_TURN, 0.0, 0.0, 0.0]
            turn[(j + 2) % 3 + 1] = _COS_QUARTER_TURN
            q = unit_quat(quat_mul(q, turn))
    return (ev[0], ev[1], ev[2]), q


def _mat_mul(x: Sequence[float], y: Sequence[float]) -> Mat:
    """x·y of two row-major 3×3 matrices, each entry summed left to right."""
    return (x[0] * y[0] + x[1] * y[3] + x[2] * y[6], x[0] * y[1] + x[1] * y[4] + x[2] * y[7],
            x[0] * y[2] + x[1] * y[5] + x[2] * y[8], x[3] * y[0] + x[4] * y[3] + x[5] * y[6],
            x[3] * y[1] + x[4] * y[4] + x[5] * y[7], x[3] * y[2] + x[4] * y[5] + x[5] * y[8],
            x[6] * y[0] + x[7] * y[3] + x[8] * y[6], x[6] * y[1] + x[7] * y[4] + x[8] * y[7],
            x[6] * y[2] + x[7] * y[5] + x[8] * y[8])


def six_to_matrix(s: Sequence[float]) -> Mat:
    """(Ixx, Iyy, Izz, Ixy, Ixz, Iyz) as a row-major symmetric 3×3."""
    return (s[0], s[3], s[4], s[3], s[1], s[5], s[4], s[5], s[2])


def full_inertia(six: Sequence[float]) -> tuple[Quat, Vec] | str:
    """(principal frame, principal moments) of an inertia given as (xx, yy, zz, xy, xz, yz), or
    why MuJoCo refuses it."""
    ev, q = principal_axes(six_to_matrix(six))
    if ev[2] < EPS:
        return "inertia must have positive eigenvalues"
    return q, ev


def rotated_inertia(diag: Sequence[float], quat: Sequence[float]) -> tuple[float, ...]:
    """R diag(I) Rᵀ as (xx, yy, zz, xy, xz, yz), R the rotation of ``quat``."""
    m = quat_to_matrix(quat)
    t = (m[0] * diag[0], m[3] * diag[0], m[6] * diag[0], m[1] * diag[1], m[4] * diag[1], m[7] * diag[1],
         m[2] * diag[2], m[5] * diag[2], m[8] * diag[2])
    return (m[0] * t[0] + m[1] * t[3] + m[2] * t[6], m[3] * t[1] + m[4] * t[4] + m[5] * t[7],
            m[6] * t[2] + m[7] * t[5] + m[8] * t[8], m[0] * t[1] + m[1] * t[4] + m[2] * t[7],
            m[0] * t[2] + m[1] * t[5] + m[2] * t[8], m[3] * t[2] + m[4] * t[5] + m[5] * t[8])


def point_mass_inertia(mass: float, d: Sequence[float]) -> tuple[float, ...]:
    """The parallel-axis term of a mass at offset d, as (xx, yy, zz, xy, xz, yz)."""
    return (mass * (d[1] * d[1] + d[2] * d[2]), mass * (d[0] * d[0] + d[2] * d[2]),
            mass * (d[0] * d[0] + d[1] * d[1]), -mass * d[0] * d[1], -mass * d[0] * d[2], -mass * d[1] * d[2])
