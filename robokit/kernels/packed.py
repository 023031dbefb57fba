r"""A PoE model packed once into one read-only array, and the kernels that take it (issue 42, item 2).

The seed-function kernels (:mod:`robokit.kernels.poe`, :mod:`robokit.kernels.dynamics`) take the
model as the Modern Robotics book writes it — ``Mlist``, ``Glist``, ``Slist`` — and on every call
check it, derive its constants (the link-frame screws ``Aᵢ = Ad_{M₀ᵢ⁻¹} Sᵢ`` and ``Mlist[i]⁻¹``) and
allocate about ten scratch arrays; numba's dispatch of their eight array arguments and the boxing
of a new result array come on top. For a robot whose model does not change, :func:`pack_model`
does the checks and the constants **once**, into one float64 array, and the kernels here take
that array, the joint vectors and the output array to write: four or five arguments per
dispatch, a few small scratch arrays per call, no result boxed by numba (the caller allocates it:
numba's boxing of a returned array costs more than that, measured). The dynamics results are
those of the seed kernels bit for bit: the same recursions (:func:`robokit.kernels.dynamics.rnea_into`
and friends) on the same constants. FK and the space Jacobian use the chain factored once into
joint frames (:func:`joint_frames_into`, :func:`chain_into`): the same pose to rounding.

Layout of the packed array (float64, read-only), n joints::

    [0] MAGIC   [1] n   [2:5] gravity g   [5:8] reserved (0)
    S (6, n)   space screws           B (6, n)   body screws (B = Ad_{M⁻¹} S)
    A (6, n)   link-frame screws      M (4, 4)   home pose of the end-effector (space form)
    Minv (n+1, 4, 4)  Mlist[i]⁻¹      G (n, 6, 6)  spatial inertias     armature (n,)
    Z (n, 3)  per joint (kind, k, h)  C (n+1, 4, 4)  the factored chain's constant factors

A packed array is read-only: no kernel writes it, and several threads may share it (the
kernels allocate their scratch per call). The per-configuration kernels check the lengths and
finiteness of their vectors (``ValueError``); the two batch kernels (:func:`dynamics_batch`,
:func:`matrix_batch`) check the shapes but not the values (their caller does), like the seed
kernels' batches.

Example::

    >>> import robokit
    >>> from robokit.kernels.packed import pack_model
    >>> p = robokit.load("twolink").poe
    >>> pm = pack_model(p.Mlist, p.Glist, p.Slist, [0, -9.81, 0])
    >>> pm.rnea(np.array([0, np.pi / 2]), np.array([1.0, 0]), np.zeros(2)).round(4)
    array([34.335,  1.2  ])
"""
from __future__ import annotations

import math

import numpy as np

from robokit.kernels._jit import njit, prange
from robokit.kernels.dynamics import (
    aba_into, check_model, check_vector, crba_into, forward_dynamics_into, link_transforms, rnea_into,
)
from robokit.kernels.lie import PRISMATIC_TOL, adjoint_screw, copy44, inv_t, mul_tt, mul_tt_inplace, set_identity
from robokit.kernels.poe import (
    SERIAL_BELOW, block_range, fkin_body_into, jacobian_body_into, n_blocks,
)

__all__ = [
    "PackedModel", "pack_model", "MAGIC", "packed_size", "pack_into",
    "rnea", "gravity", "crba", "aba", "forward_dynamics_crba", "fk_space", "fk_body", "jacobian_space",
    "jacobian_body", "dynamics_batch", "matrix_batch", "RNEA", "ABA", "FK", "JACOBIAN", "CRBA",
]

#: The first entry of every packed array (a check that an array is one).
MAGIC = 4242.0625
_HEAD = 8

_P = "Array(float64, 1, 'C', readonly=True)"  # the packed model
_A1 = "float64[::1]"
_A2 = "float64[:, ::1]"
_A3 = "float64[:, :, ::1]"


@njit
def packed_size(n: int) -> int:
    """Length of the packed array of an n-joint model."""
    return _HEAD + 18 * n + 16 + 16 * (n + 1) + 36 * n + n + 3 * n + 16 * (n + 1)


@njit
def pack_into(Mlist: np.ndarray, Glist: np.ndarray, Slist: np.ndarray, g: np.ndarray, armature: np.ndarray,
              out: np.ndarray) -> None:
    """out (packed_size(n),) ← the packed model (layout: the module docstring). The model is not
    checked here (:func:`pack` does)."""
    n = Slist.shape[1]
    out[0] = MAGIC
    out[1] = n
    for i in range(3):
        out[2 + i] = g[i]
    for i in range(5, _HEAD):
        out[i] = 0.0
    o = _HEAD
    S = out[o:o + 6 * n].reshape((6, n))
    B = out[o + 6 * n:o + 12 * n].reshape((6, n))
    A = out[o + 12 * n:o + 18 * n].reshape((6, n))
    o += 18 * n
    M = out[o:o + 16].reshape((4, 4))
    o += 16
    Minv = out[o:o + 16 * (n + 1)].reshape((n + 1, 4, 4))
    o += 16 * (n + 1)
    G = out[o:o + 36 * n].reshape((n, 6, 6))
    o += 36 * n
    for r in range(6):
        for c in range(n):
            S[r, c] = Slist[r, c]
    # A and Minv exactly as dynamics.link_screws computes them (the seed kernels' constants)
    W = np.empty((3, 4, 4))
    M0i, M0i_inv, tmp = W[0], W[1], W[2]
    set_identity(M0i)
    for i in range(n):
        mul_tt_inplace(M0i, Mlist[i], tmp)
        inv_t(M0i, M0i_inv)
        adjoint_screw(M0i_inv, Slist, i, A, i)
    for i in range(n + 1):
        inv_t(Mlist[i], Minv[i])
    # the home pose M = Mlist[0] ⋯ Mlist[n] unless the caller packed its own (see pack), B = Ad_{M⁻¹} S
    mul_tt_inplace(M0i, Mlist[n], tmp)
    copy44(M0i, M)
    inv_t(M, M0i_inv)
    for i in range(n):
        adjoint_screw(M0i_inv, Slist, i, B, i)
    for k in range(n):
        for r in range(6):
            for c in range(6):
                G[k, r, c] = Glist[k, r, c]
    for i in range(n):
        out[o + i] = armature[i]


@njit(f"{_A1}({_A3}, {_A3}, {_A2}, {_A1}, {_A1}, {_A2})")
def pack(Mlist: np.ndarray, Glist: np.ndarray, Slist: np.ndarray, g: np.ndarray, armature: np.ndarray,
         M: np.ndarray) -> np.ndarray:
    """The packed model (a new writeable array: :func:`pack_model` makes it read-only) after the
    seed kernels' checks of the model (``ValueError``); ``M`` (4, 4) the home pose of the
    end-effector, or a (0, 0) array for the product of ``Mlist``."""
    check_model(Mlist, Glist, Slist)
    n = Slist.shape[1]
    check_vector(g, np.int64(3), np.int64(3))
    if armature.shape[0] != n or not np.all(np.isfinite(armature)):
        raise ValueError("armature: expected one finite value per joint")
    out = np.empty(packed_size(n))
    pack_into(Mlist, Glist, Slist, g, armature, out)
    Mh = home(out, n)
    if M.shape[0] == 4 and M.shape[1] == 4:
        copy44(M, Mh)
        Minv = np.empty((4, 4))
        inv_t(Mh, Minv)
        B = body_screws(out, n)
        for i in range(n):
            adjoint_screw(Minv, Slist, i, B, i)
    o = _HEAD + 18 * n + 16 + 16 * (n + 1) + 37 * n
    joint_frames_into(Slist, Mh, out[o:o + 3 * n].reshape((n, 3)),
                      out[o + 3 * n:o + 3 * n + 16 * (n + 1)].reshape((n + 1, 4, 4)))
    return out


@njit
def joint_frames_into(S: np.ndarray, M: np.ndarray, Z: np.ndarray, C: np.ndarray) -> None:
    """The joint frames of the fast FK and Jacobian: for joint i a frame Fᵢ (home pose, space
    coordinates) with its origin on the joint's axis and z along it, so that
    ``e^{[Sᵢ]θ} = Fᵢ Zᵢ(θ) Fᵢ⁻¹`` with ``Zᵢ(θ)`` a rotation about z by ``kᵢθ`` and a translation
    along z by ``hᵢkᵢθ`` (revolute, pitch hᵢ, ``kᵢ = ‖ωᵢ‖``) or a translation along z by ``kᵢθ``
    (prismatic, ``kᵢ = ‖vᵢ‖``). Then ``e^{[S₁]θ₁} ⋯ e^{[Sₙ]θₙ} M = C₀ Z₁ C₁ Z₂ ⋯ Zₙ Cₙ`` with
    ``C₀ = F₁``, ``Cᵢ = Fᵢ⁻¹ Fᵢ₊₁``, ``Cₙ = Fₙ⁻¹ M``: one cheap factor and one rigid product per
    joint, no screw exponential. Z (n, 3) ← (kind: 0 revolute / 1 prismatic, k, h); C (n+1, 4, 4)."""
    n = S.shape[1]
    W = np.empty((2, 4, 4))
    F, prev_inv = W[0], W[1]
    set_identity(prev_inv)
    for i in range(n):
        wx, wy, wz = S[0, i], S[1, i], S[2, i]
        vx, vy, vz = S[3, i], S[4, i], S[5, i]
        nw = math.sqrt(wx * wx + wy * wy + wz * wz)
        qx = qy = qz = 0.0
        if nw >= PRISMATIC_TOL:
            zx, zy, zz = wx / nw, wy / nw, wz / nw
            ux, uy, uz = vx / nw, vy / nw, vz / nw
            Z[i, 0], Z[i, 1], Z[i, 2] = 0.0, nw, zx * ux + zy * uy + zz * uz
            qx, qy, qz = zy * uz - zz * uy, zz * ux - zx * uz, zx * uy - zy * ux  # ω̂ × v̂: on the axis
        else:
            nv = math.sqrt(vx * vx + vy * vy + vz * vz)
            zx, zy, zz = (vx / nv, vy / nv, vz / nv) if nv > 0.0 else (0.0, 0.0, 1.0)
            Z[i, 0], Z[i, 1], Z[i, 2] = 1.0, nv, 0.0
        # x: the coordinate axis least along z, made perpendicular to it; y = z × x
        ax, ay, az = abs(zx), abs(zy), abs(zz)
        ex, ey, ez = (1.0, 0.0, 0.0) if ax <= ay and ax <= az else ((0.0, 1.0, 0.0) if ay <= az else (0.0, 0.0, 1.0))
        d = ex * zx + ey * zy + ez * zz
        xx, xy, xz = ex - d * zx, ey - d * zy, ez - d * zz
        nx = math.sqrt(xx * xx + xy * xy + xz * xz)
        xx, xy, xz = xx / nx, xy / nx, xz / nx
        yx, yy, yz = zy * xz - zz * xy, zz * xx - zx * xz, zx * xy - zy * xx
        F[0, 0], F[0, 1], F[0, 2], F[0, 3] = xx, yx, zx, qx
        F[1, 0], F[1, 1], F[1, 2], F[1, 3] = xy, yy, zy, qy
        F[2, 0], F[2, 1], F[2, 2], F[2, 3] = xz, yz, zz, qz
        F[3, 0], F[3, 1], F[3, 2], F[3, 3] = 0.0, 0.0, 0.0, 1.0
        mul_tt(prev_inv, F, C[i])
        inv_t(F, prev_inv)
    mul_tt(prev_inv, M, C[n])


# ------------------------------------------------------------------ views of a packed array
@njit
def joints(P: np.ndarray) -> int:
    """n, after checking that P is a packed array (``ValueError`` otherwise)."""
    n = int(P[1]) if P.shape[0] > _HEAD else -1
    if n < 1 or P[0] != MAGIC or P.shape[0] != packed_size(n):
        raise ValueError("model: not a packed model (robokit.kernels.packed.pack_model)")
    return n


@njit
def link_screws_of(P: np.ndarray, n: int) -> np.ndarray:
    """View A (6, n) of a packed array: the joint screws in the link frames."""
    o = _HEAD + 12 * n
    return P[o:o + 6 * n].reshape((6, n))


@njit
def inverse_links(P: np.ndarray, n: int) -> np.ndarray:
    """View Minv (n+1, 4, 4) of a packed array: ``Mlist[i]⁻¹``."""
    o = _HEAD + 18 * n + 16
    return P[o:o + 16 * (n + 1)].reshape((n + 1, 4, 4))


@njit
def inertias(P: np.ndarray, n: int) -> np.ndarray:
    """View G (n, 6, 6) of a packed array: the spatial inertias."""
    o = _HEAD + 18 * n + 16 + 16 * (n + 1)
    return P[o:o + 36 * n].reshape((n, 6, 6))


@njit
def armature_of(P: np.ndarray, n: int) -> np.ndarray:
    """View (n,) of a packed array: the armature."""
    o = _HEAD + 18 * n + 16 + 16 * (n + 1) + 36 * n
    return P[o:o + n]


@njit
def home(P: np.ndarray, n: int) -> np.ndarray:
    """View M (4, 4) of a packed array: the end-effector's home pose."""
    o = _HEAD + 18 * n
    return P[o:o + 16].reshape((4, 4))


@njit
def joint_factors(P: np.ndarray, n: int) -> tuple[np.ndarray, np.ndarray]:
    """Views Z (n, 3) and C (n+1, 4, 4) of a packed array (:func:`joint_frames_into`)."""
    o = _HEAD + 18 * n + 16 + 16 * (n + 1) + 37 * n
    return P[o:o + 3 * n].reshape((n, 3)), P[o + 3 * n:o + 3 * n + 16 * (n + 1)].reshape((n + 1, 4, 4))


@njit
def chain_into(Z: np.ndarray, C: np.ndarray, q: np.ndarray, T: np.ndarray, J: np.ndarray, jacobian: bool) -> None:
    """T (4, 4) ← ``C₀ Z₁(q₁) C₁ ⋯ Zₙ(qₙ) Cₙ``, the end-effector pose (:func:`joint_frames_into`), and
    with ``jacobian`` J (6, n) ← the space Jacobian, rows (ω; v): column i is joint i's screw carried
    by ``P = C₀ Z₁ C₁ ⋯ Cᵢ₋₁`` (the frame Fᵢ moved by the joints before it) — with z P's z axis and
    p its origin, ``(kz, p × kz + hkz)`` (revolute) or ``(0, kz)`` (prismatic).

    ``Zᵢ(q)`` rotates the pose's x and y columns about z by kᵢq and shifts its origin along z by
    hᵢkᵢq (revolute), or by kᵢq (prismatic). The pose's top three rows are kept in twelve locals
    (registers) through the loop: half the time of the same products through a 4×4 array."""
    a0, a1, a2, a3 = C[0, 0, 0], C[0, 0, 1], C[0, 0, 2], C[0, 0, 3]
    b0, b1, b2, b3 = C[0, 1, 0], C[0, 1, 1], C[0, 1, 2], C[0, 1, 3]
    c0, c1, c2, c3 = C[0, 2, 0], C[0, 2, 1], C[0, 2, 2], C[0, 2, 3]
    for i in range(Z.shape[0]):
        k = Z[i, 1]
        revolute = Z[i, 0] == 0.0
        if jacobian:
            zx, zy, zz = k * a2, k * b2, k * c2
            if revolute:
                h = Z[i, 2]
                J[0, i], J[1, i], J[2, i] = zx, zy, zz
                J[3, i] = b3 * zz - c3 * zy + h * zx
                J[4, i] = c3 * zx - a3 * zz + h * zy
                J[5, i] = a3 * zy - b3 * zx + h * zz
            else:
                J[0, i], J[1, i], J[2, i] = 0.0, 0.0, 0.0
                J[3, i], J[4, i], J[5, i] = zx, zy, zz
        th = k * q[i]
        if revolute:
            s, c = math.sin(th), math.cos(th)
            d = Z[i, 2] * th
            a0, a1 = c * a0 + s * a1, c * a1 - s * a0
            b0, b1 = c * b0 + s * b1, c * b1 - s * b0
            c0, c1 = c * c0 + s * c1, c * c1 - s * c0
        else:
            d = th
        a3 += d * a2
        b3 += d * b2
        c3 += d * c2
        K = C[i + 1]
        k00, k01, k02, k03 = K[0, 0], K[0, 1], K[0, 2], K[0, 3]
        k10, k11, k12, k13 = K[1, 0], K[1, 1], K[1, 2], K[1, 3]
        k20, k21, k22, k23 = K[2, 0], K[2, 1], K[2, 2], K[2, 3]
        a0, a1, a2, a3 = (a0 * k00 + a1 * k10 + a2 * k20, a0 * k01 + a1 * k11 + a2 * k21,
                          a0 * k02 + a1 * k12 + a2 * k22, a0 * k03 + a1 * k13 + a2 * k23 + a3)
        b0, b1, b2, b3 = (b0 * k00 + b1 * k10 + b2 * k20, b0 * k01 + b1 * k11 + b2 * k21,
                          b0 * k02 + b1 * k12 + b2 * k22, b0 * k03 + b1 * k13 + b2 * k23 + b3)
        c0, c1, c2, c3 = (c0 * k00 + c1 * k10 + c2 * k20, c0 * k01 + c1 * k11 + c2 * k21,
                          c0 * k02 + c1 * k12 + c2 * k22, c0 * k03 + c1 * k13 + c2 * k23 + c3)
    T[0, 0], T[0, 1], T[0, 2], T[0, 3] = a0, a1, a2, a3
    T[1, 0], T[1, 1], T[1, 2], T[1, 3] = b0, b1, b2, b3
    T[2, 0], T[2, 1], T[2, 2], T[2, 3] = c0, c1, c2, c3
    T[3, 0], T[3, 1], T[3, 2], T[3, 3] = 0.0, 0.0, 0.0, 1.0


@njit
def body_screws(P: np.ndarray, n: int) -> np.ndarray:
    """View B (6, n) of a packed array."""
    return P[_HEAD + 6 * n:_HEAD + 12 * n].reshape((6, n))


# Scratch: separate small arrays (numba allocates one in ~15 ns, less than a reshaped view of a
# larger one costs, measured), only those each kernel needs.
@njit
def check_matrix_call(P: np.ndarray, q: np.ndarray, out: np.ndarray, rows: int, cols: int) -> int:
    """n, after checking P, q (n finite values) and out's shape (rows, cols), −1 standing for n."""
    n = joints(P)
    check_vector(q, n, np.int64(0))
    if out.shape[0] != (n if rows < 0 else rows) or out.shape[1] != (n if cols < 0 else cols):
        raise ValueError("out: expected shape (4, 4), (6, n) or (n, n), as the kernel returns")
    return n


@njit
def check_vectors_call(P: np.ndarray, q: np.ndarray, dq: np.ndarray, x: np.ndarray, which: int,
                       out: np.ndarray) -> int:
    """n, after checking P, q, q̇ and x (q̈: ``which`` 2, τ: 5; n finite values each) and out (n,)."""
    n = joints(P)
    check_vector(q, n, np.int64(0))
    check_vector(dq, n, np.int64(1))
    check_vector(x, n, which)
    check_out(out, n)
    return n


@njit
def check_out(out: np.ndarray, n: int) -> None:
    if out.shape[0] != n:
        raise ValueError("out: expected one entry per joint")


# ------------------------------------------------------------------ one configuration
# Scratch: a few small arrays per call, only those each kernel needs (numba allocates a small
# array in about 15 ns, less than a reshaped view of one larger array costs: measured). The
# link transforms' 4×4 temporary E is Tl[n], which link_transforms writes only at its end.
@njit(f"void({_P}, {_A1}, {_A1}, {_A1}, {_A1})")
def rnea(P: np.ndarray, q: np.ndarray, dq: np.ndarray, ddq: np.ndarray, out: np.ndarray) -> None:
    """out (n,) ← τ = M(q) q̈ + c(q, q̇) + g(q) by recursive Newton–Euler (gravity: the model's)."""
    rnea_at(P, check_vectors_call(P, q, dq, ddq, np.int64(2), out), q, dq, ddq, out)


@njit
def rnea_at(P: np.ndarray, n: int, q: np.ndarray, dq: np.ndarray, ddq: np.ndarray, out: np.ndarray) -> None:
    """out ← τ(q, q̇, q̈) on checked vectors: its scratch, the link transforms, the recursion."""
    A = link_screws_of(P, n)
    Tl = np.empty((n + 1, 4, 4))
    V = np.empty((2 * n, 6))
    v6 = np.zeros((7, 6))  # six temporaries and a zero tip wrench
    link_transforms(A, inverse_links(P, n), q, Tl, Tl[n])
    rnea_into(A, Tl, inertias(P, n), dq, ddq, P[2:5], v6[6], V[:n], V[n:], v6[:6], out)


@njit(f"void({_P}, {_A1}, {_A1})")
def gravity(P: np.ndarray, q: np.ndarray, out: np.ndarray) -> None:
    """out (n,) ← g(q), the joint torques that hold the arm still against the model's gravity."""
    n = joints(P)
    check_vector(q, n, np.int64(0))
    check_out(out, n)
    z = np.zeros(n)
    rnea_at(P, n, q, z, z, out)


@njit(f"void({_P}, {_A1}, {_A2})")
def crba(P: np.ndarray, q: np.ndarray, out: np.ndarray) -> None:
    """out (n, n) ← M(q) by the composite-rigid-body algorithm (both triangles)."""
    n = check_matrix_call(P, q, out, -1, -1)
    A = link_screws_of(P, n)
    Tl = np.empty((n + 1, 4, 4))
    K = np.empty((n + 2, 6, 6))  # composite inertias, then crba's two 6×6 temporaries
    v6 = np.empty((1, 6))
    link_transforms(A, inverse_links(P, n), q, Tl, Tl[n])
    crba_into(A, Tl, inertias(P, n), K[:n], K[n:], v6, out)


@njit
def aba_scratch(n: int) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Tl (n+1, 4, 4), K (n+3, 6, 6): Iᵃ and aba's three 6×6 temporaries, R (4n+7, 6): V, P, C, U,
    six temporaries and a zero tip wrench (last row), du (n, 2)."""
    R = np.empty((4 * n + 7, 6))
    for c in range(6):
        R[4 * n + 6, c] = 0.0
    return np.empty((n + 1, 4, 4)), np.empty((n + 3, 6, 6)), R, np.empty((n, 2))


@njit(f"void({_P}, {_A1}, {_A1}, {_A1}, {_A1})")
def aba(P: np.ndarray, q: np.ndarray, dq: np.ndarray, tau: np.ndarray, out: np.ndarray) -> None:
    """out (n,) ← q̈ by the articulated-body algorithm (the model's armature added to each joint);
    ``ValueError`` when the mass matrix is not positive definite."""
    n = check_vectors_call(P, q, dq, tau, np.int64(5), out)
    A = link_screws_of(P, n)
    Tl, K, R, du = aba_scratch(n)
    link_transforms(A, inverse_links(P, n), q, Tl, Tl[n])
    if not aba_into(A, Tl, inertias(P, n), dq, tau, P[2:5], R[4 * n + 6], armature_of(P, n), R[:n], R[4 * n:4 * n + 6],
                    K[:n], R[n:2 * n], R[2 * n:3 * n], R[3 * n:4 * n], du, K[n:], out):
        raise ValueError("Glist: the mass matrix is not positive definite at this configuration "
                         "(a joint drives no inertia)")


@njit(f"void({_P}, {_A1}, {_A1}, {_A1}, {_A1})")
def forward_dynamics_crba(P: np.ndarray, q: np.ndarray, dq: np.ndarray, tau: np.ndarray, out: np.ndarray) -> None:
    """out (n,) ← q̈ = M(q)⁻¹ (τ − h(q, q̇)) by CRBA + Cholesky (the lecture's form; the armature is
    not used here: :func:`aba` adds it)."""
    n = check_vectors_call(P, q, dq, tau, np.int64(5), out)
    A = link_screws_of(P, n)
    Tl = np.empty((n + 1, 4, 4))
    K = np.empty((n + 2, 6, 6))
    V = np.empty((2 * n, 6))
    v6 = np.zeros((7, 6))
    ML = np.zeros((2, n, n))
    h = np.zeros((2, n))  # h and a zero vector
    link_transforms(A, inverse_links(P, n), q, Tl, Tl[n])
    if not forward_dynamics_into(A, Tl, inertias(P, n), dq, tau, P[2:5], v6[6], h[1], V[:n], V[n:], v6[:6], K[:n],
                                 K[n:], ML[0], ML[1], h[0], out):
        raise ValueError("Glist: the mass matrix is not positive definite at this configuration "
                         "(a joint drives no inertia)")


@njit(f"void({_P}, {_A1}, {_A2})")
def fk_space(P: np.ndarray, q: np.ndarray, out: np.ndarray) -> None:
    """out (4, 4) ← e^{[S₁]q₁} ⋯ e^{[Sₙ]qₙ} M, the end-effector pose."""
    n = check_matrix_call(P, q, out, 4, 4)
    Z, C = joint_factors(P, n)
    chain_into(Z, C, q, out, out, False)


@njit(f"void({_P}, {_A1}, {_A2})")
def fk_body(P: np.ndarray, q: np.ndarray, out: np.ndarray) -> None:
    """out (4, 4) ← M e^{[B₁]q₁} ⋯ e^{[Bₙ]qₙ}, the end-effector pose (body form)."""
    n = check_matrix_call(P, q, out, 4, 4)
    E = np.empty((4, 4))
    fkin_body_into(home(P, n), body_screws(P, n), q, out, E, E)


@njit(f"void({_P}, {_A1}, {_A2})")
def jacobian_space(P: np.ndarray, q: np.ndarray, out: np.ndarray) -> None:
    """out (6, n) ← the space Jacobian, rows (ω; v)."""
    n = check_matrix_call(P, q, out, 6, -1)
    Z, C = joint_factors(P, n)
    chain_into(Z, C, q, np.empty((4, 4)), out, True)


@njit(f"void({_P}, {_A1}, {_A2})")
def jacobian_body(P: np.ndarray, q: np.ndarray, out: np.ndarray) -> None:
    """out (6, n) ← the body Jacobian, rows (ω; v)."""
    n = check_matrix_call(P, q, out, 6, -1)
    W = np.empty((2, 4, 4))
    jacobian_body_into(body_screws(P, n), q, out, W[0], W[1], W[1])


# ------------------------------------------------------------------ N configurations, in parallel
@njit
def rnea_rows(lo: int, hi: int, P: np.ndarray, Q: np.ndarray, D: np.ndarray, DD: np.ndarray, out: np.ndarray) -> None:
    """out[k] ← τ for rows lo ≤ k < hi."""
    n = Q.shape[1]
    A, Minv, G = link_screws_of(P, n), inverse_links(P, n), inertias(P, n)
    Tl = np.empty((n + 1, 4, 4))
    V = np.empty((2 * n, 6))
    v6 = np.zeros((7, 6))
    for k in range(lo, hi):
        link_transforms(A, Minv, Q[k], Tl, Tl[n])
        rnea_into(A, Tl, G, D[k], DD[k], P[2:5], v6[6], V[:n], V[n:], v6[:6], out[k])


@njit
def crba_rows(lo: int, hi: int, P: np.ndarray, Q: np.ndarray, out: np.ndarray) -> None:
    """out[k] ← M(θ_k) for rows lo ≤ k < hi."""
    n = Q.shape[1]
    A, Minv, G = link_screws_of(P, n), inverse_links(P, n), inertias(P, n)
    Tl = np.empty((n + 1, 4, 4))
    K = np.empty((n + 2, 6, 6))
    v6 = np.empty((1, 6))
    for k in range(lo, hi):
        link_transforms(A, Minv, Q[k], Tl, Tl[n])
        crba_into(A, Tl, G, K[:n], K[n:], v6, out[k])


@njit
def aba_rows(lo: int, hi: int, P: np.ndarray, Q: np.ndarray, D: np.ndarray, T: np.ndarray, out: np.ndarray) -> None:
    """out[k] ← q̈ by the articulated-body algorithm for rows lo ≤ k < hi (NaN where some Dᵢ ≤ 0)."""
    n = Q.shape[1]
    A, Minv, G, arm = link_screws_of(P, n), inverse_links(P, n), inertias(P, n), armature_of(P, n)
    Tl, K, R, du = aba_scratch(n)
    for k in range(lo, hi):
        link_transforms(A, Minv, Q[k], Tl, Tl[n])
        aba_into(A, Tl, G, D[k], T[k], P[2:5], R[4 * n + 6], arm, R[:n], R[4 * n:4 * n + 6], K[:n], R[n:2 * n],
                 R[2 * n:3 * n], R[3 * n:4 * n], du, K[n:], out[k])


@njit
def fk_space_rows(lo: int, hi: int, P: np.ndarray, Q: np.ndarray, out: np.ndarray) -> None:
    """out[k] ← the end-effector pose of row k, for lo ≤ k < hi."""
    n = Q.shape[1]
    Z, C = joint_factors(P, n)
    for k in range(lo, hi):
        chain_into(Z, C, Q[k], out[k], out[k], False)


@njit
def jacobian_space_rows(lo: int, hi: int, P: np.ndarray, Q: np.ndarray, out: np.ndarray) -> None:
    """out[k] ← the space Jacobian of row k, for lo ≤ k < hi."""
    n = Q.shape[1]
    Z, C = joint_factors(P, n)
    T = np.empty((4, 4))
    for k in range(lo, hi):
        chain_into(Z, C, Q[k], T, out[k], True)


@njit
def check_batch(P: np.ndarray, Q: np.ndarray) -> int:
    """N, after checking that P is a packed array and Q (N, n) has its n columns."""
    n = joints(P)
    if Q.shape[1] != n:
        raise ValueError("thetas: expected one column per joint")
    return Q.shape[0]


#: ``which`` of :func:`dynamics_batch` and :func:`matrix_batch`.
RNEA, ABA = 0, 1
FK, JACOBIAN, CRBA = 0, 1, 2


@njit
def dynamics_rows(which: int, lo: int, hi: int, P: np.ndarray, Q: np.ndarray, D: np.ndarray, X: np.ndarray,
                  out: np.ndarray) -> None:
    """Rows lo ≤ k < hi of :func:`dynamics_batch`."""
    if which == RNEA:
        rnea_rows(lo, hi, P, Q, D, X, out)
    else:
        aba_rows(lo, hi, P, Q, D, X, out)


@njit
def matrix_rows(which: int, lo: int, hi: int, P: np.ndarray, Q: np.ndarray, out: np.ndarray) -> None:
    """Rows lo ≤ k < hi of :func:`matrix_batch`."""
    if which == FK:
        fk_space_rows(lo, hi, P, Q, out)
    elif which == JACOBIAN:
        jacobian_space_rows(lo, hi, P, Q, out)
    else:
        crba_rows(lo, hi, P, Q, out)


@njit(f"void({_P}, int64, {_A2}, {_A2}, {_A2}, {_A2})", parallel=True)
def dynamics_batch(P: np.ndarray, which: int, thetas: np.ndarray, dthetas: np.ndarray, xs: np.ndarray,
                   out: np.ndarray) -> None:
    """out (N, n) ← for the rows of thetas, dthetas, xs (N, n): τ by Newton–Euler (``which`` =
    :data:`RNEA`, xs the accelerations) or q̈ by the articulated-body algorithm (:data:`ABA`, xs the
    torques; a row whose mass matrix is not positive definite comes back NaN), in parallel over
    blocks of rows."""
    N = check_batch(P, thetas)
    if dthetas.shape != thetas.shape or xs.shape != thetas.shape or out.shape != thetas.shape:
        raise ValueError("dthetas, xs, out: expected the shape (N, n) of thetas")
    if N < SERIAL_BELOW:
        dynamics_rows(which, np.int64(0), N, P, thetas, dthetas, xs, out)
        return
    nb = n_blocks(N)
    for b in prange(nb):
        lo, hi = block_range(b, nb, N)
        dynamics_rows(which, lo, hi, P, thetas, dthetas, xs, out)


@njit(f"void({_P}, int64, {_A2}, {_A3})", parallel=True)
def matrix_batch(P: np.ndarray, which: int, thetas: np.ndarray, out: np.ndarray) -> None:
    """out ← for the rows of thetas (N, n): the end-effector poses (``which`` = :data:`FK`, out
    (N, 4, 4)), the space Jacobians (:data:`JACOBIAN`, (N, 6, n)) or the mass matrices (:data:`CRBA`,
    (N, n, n)), in parallel over blocks of rows."""
    N = check_batch(P, thetas)
    n = thetas.shape[1]
    rows, cols = (4, 4) if which == FK else ((6, n) if which == JACOBIAN else (n, n))
    if out.shape[0] != N or out.shape[1] != rows or out.shape[2] != cols:
        raise ValueError("out: expected (N, 4, 4) poses, (N, 6, n) Jacobians or (N, n, n) mass matrices")
    if N < SERIAL_BELOW:
        matrix_rows(which, np.int64(0), N, P, thetas, out)
        return
    nb = n_blocks(N)
    for b in prange(nb):
        lo, hi = block_range(b, nb, N)
        matrix_rows(which, lo, hi, P, thetas, out)


# ------------------------------------------------------------------ the Python object
class PackedModel:
    """An immutable PoE model packed once (:func:`pack_model`): ``n`` joints, the read-only packed
    array ``data`` the kernels of this module take, and one method per kernel that allocates the
    result and calls it. The methods check nothing in Python: their arguments must be C-contiguous,
    writeable float64 arrays of the documented shapes (numba raises ``TypeError`` otherwise);
    the kernel checks lengths and finiteness (``ValueError``). Angles in radians.
    """

    __slots__ = ("n", "data")
    n: int
    data: np.ndarray

    def __init__(self, data: np.ndarray) -> None:
        data = np.array(data, dtype=np.float64)  # a private copy, then read-only
        if data.ndim != 1 or data.shape[0] <= _HEAD or data[0] != MAGIC:
            raise ValueError("data: not a packed model")
        data.flags.writeable = False
        object.__setattr__(self, "data", data)
        object.__setattr__(self, "n", int(data[1]))

    def __setattr__(self, name: str, value: object) -> None:
        raise AttributeError("PackedModel is immutable")

    def __delattr__(self, name: str) -> None:
        raise AttributeError("PackedModel is immutable")

    def __reduce__(self) -> tuple[type, tuple[np.ndarray]]:
        return PackedModel, (np.array(self.data),)

    def __repr__(self) -> str:
        return f"PackedModel(n={self.n})"

    @property
    def gravity(self) -> np.ndarray:
        """The model's gravity (3,), m/s² (a copy)."""
        return np.array(self.data[2:5])

    def rnea(self, q: np.ndarray, dq: np.ndarray, ddq: np.ndarray) -> np.ndarray:
        """Joint torques (n,) by recursive Newton–Euler (:func:`rnea`)."""
        out = np.empty(self.n)
        rnea(self.data, q, dq, ddq, out)
        return out

    def gravity_torques(self, q: np.ndarray) -> np.ndarray:
        """Gravity torques g(q) (n,) (:func:`gravity`)."""
        out = np.empty(self.n)
        gravity(self.data, q, out)
        return out

    def crba(self, q: np.ndarray) -> np.ndarray:
        """Mass matrix M(q) (n, n), both triangles (:func:`crba`)."""
        out = np.empty((self.n, self.n))
        crba(self.data, q, out)
        return out

    def aba(self, q: np.ndarray, dq: np.ndarray, tau: np.ndarray) -> np.ndarray:
        """Joint accelerations (n,) by the articulated-body algorithm (:func:`aba`)."""
        out = np.empty(self.n)
        aba(self.data, q, dq, tau, out)
        return out

    def forward_dynamics_crba(self, q: np.ndarray, dq: np.ndarray, tau: np.ndarray) -> np.ndarray:
        """Joint accelerations (n,) by CRBA + Cholesky (:func:`forward_dynamics_crba`)."""
        out = np.empty(self.n)
        forward_dynamics_crba(self.data, q, dq, tau, out)
        return out

    def fk(self, q: np.ndarray) -> np.ndarray:
        """End-effector pose (4, 4) (:func:`fk_space`)."""
        out = np.empty((4, 4))
        fk_space(self.data, q, out)
        return out

    def jacobian(self, q: np.ndarray) -> np.ndarray:
        """Space Jacobian (6, n), rows (ω; v) (:func:`jacobian_space`)."""
        out = np.empty((6, self.n))
        jacobian_space(self.data, q, out)
        return out

    def rnea_many(self, Q: np.ndarray, dQ: np.ndarray, ddQ: np.ndarray) -> np.ndarray:
        """Joint torques (N, n) for the rows of Q, dQ, ddQ (N, n), in parallel (:func:`dynamics_batch`)."""
        out = np.empty(Q.shape)
        dynamics_batch(self.data, RNEA, Q, dQ, ddQ, out)
        return out

    def aba_many(self, Q: np.ndarray, dQ: np.ndarray, tau: np.ndarray) -> np.ndarray:
        """Joint accelerations (N, n) for the rows of Q, dQ, tau (N, n), in parallel; NaN rows where
        the mass matrix is not positive definite (:func:`dynamics_batch`)."""
        out = np.empty(Q.shape)
        dynamics_batch(self.data, ABA, Q, dQ, tau, out)
        return out

    def fk_many(self, Q: np.ndarray) -> np.ndarray:
        """End-effector poses (N, 4, 4) for the rows of Q (N, n), in parallel (:func:`matrix_batch`)."""
        out = np.empty((Q.shape[0], 4, 4))
        matrix_batch(self.data, FK, Q, out)
        return out

    def jacobian_many(self, Q: np.ndarray) -> np.ndarray:
        """Space Jacobians (N, 6, n) for the rows of Q (N, n), in parallel (:func:`matrix_batch`)."""
        out = np.empty((Q.shape[0], 6, self.n))
        matrix_batch(self.data, JACOBIAN, Q, out)
        return out

    def crba_many(self, Q: np.ndarray) -> np.ndarray:
        """Mass matrices (N, n, n) for the rows of Q (N, n), in parallel (:func:`matrix_batch`)."""
        out = np.empty((Q.shape[0], self.n, self.n))
        matrix_batch(self.data, CRBA, Q, out)
        return out

    def jacobian_body(self, q: np.ndarray) -> np.ndarray:
        """Body Jacobian (6, n), rows (ω; v) (:func:`jacobian_body`)."""
        out = np.empty((6, self.n))
        jacobian_body(self.data, q, out)
        return out


def _f64(x: object, name: str, ndim: int) -> np.ndarray:
    from robokit._arrays import as_array

    a = as_array(x, name)
    if a.ndim != ndim:
        raise ValueError(f"{name}: expected {ndim} dimensions, got shape {a.shape}")
    return np.ascontiguousarray(a, dtype=np.float64).copy()


def pack_model(Mlist: object, Glist: object, Slist: object, gravity: object, *, M: object = None,
               armature: object = None) -> PackedModel:
    """Pack a PoE model once for the kernels of this module.

    Parameters
    ----------
    Mlist : (n+1, 4, 4) array_like
        Link frames as the Modern Robotics book writes them (:mod:`robokit.kernels.dynamics`).
    Glist : (n, 6, 6) array_like
        Spatial inertias, angular first.
    Slist : (6, n) array_like
        Space screw axes.
    gravity : (3,) array_like
        Gravity in the base frame, m/s² (e.g. ``(0, 0, -9.81)``).
    M : (4, 4) array_like, optional
        The end-effector's home pose for :meth:`PackedModel.fk`; default the product of ``Mlist``.
    armature : (n,) array_like, optional
        Reflected motor inertia added to each joint by :meth:`PackedModel.aba`; default zeros.

    Returns
    -------
    PackedModel

    Raises
    ------
    robokit.errors.InputError
        When the model fails the seed kernels' checks (shapes, finiteness, homogeneous link
        frames, symmetric inertias), naming the argument.

    Examples
    --------
    >>> import robokit
    >>> p = robokit.load("twolink").poe
    >>> pack_model(p.Mlist, p.Glist, p.Slist, [0, -9.81, 0]).n
    2
    """
    from robokit.errors import InputError

    try:
        Ml, Gl, Sl = _f64(Mlist, "Mlist", 3), _f64(Glist, "Glist", 3), _f64(Slist, "Slist", 2)
        n = Sl.shape[1]
        g = _f64(gravity, "gravity", 1)
        if g.shape != (3,):
            raise ValueError(f"gravity: expected 3 values (m/s², base frame), got shape {g.shape}")
        arm = np.zeros(n) if armature is None else _f64(armature, "armature", 1)
        Mh = np.zeros((0, 0)) if M is None else _f64(M, "M", 2)
        return PackedModel(pack(Ml, Gl, Sl, g, arm, Mh))
    except ValueError as exc:
        raise InputError(str(exc)) from None
