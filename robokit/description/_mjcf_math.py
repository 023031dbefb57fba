r"""The small geometry MuJoCo's compiler does, done the same way (private to the MJCF reader).

MuJoCo's compiler keeps orientations as unit quaternions ``(w, x, y, z)`` and reduces every
inertia tensor it sums or is given in full to a principal frame and three principal moments
(decreasing). MuJoCo 4 computes that decomposition to rounding error for bodies (robokit's tests
measure ``R diag(I) Rᵀ`` against the tensor at 1e-16), not for meshes (MuJoCo 4.0.1's mesh frame
is up to about 1e-7 rad short of the principal axes); older MuJoCo releases stopped their Jacobi
iteration about 1e-6 rad short, which moved the simulated tensor by up to ~1e-10 of its
size. The compiler's quaternion conventions are written out here as MuJoCo writes them (the
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
