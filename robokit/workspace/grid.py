r"""The voxel grid of a capability map and its reachability pre-pass.

Voxel centres sit on the lattice ``resolution · (i, j, k)`` (integers i, j, k) in the base
frame, so the same resolution always gives the same centres. For a planar arm the lattice
is two-dimensional, ``height · n + resolution · (i u + j v)`` in the tool's plane (see
:class:`robokit.ik.planar.PlanarChain`).

Pre-pass (cheap, before any IK): tool positions are computed by forward kinematics (product
of exponentials, batched) at configurations drawn uniformly inside the joint limits (±π for
unlimited joints) from a fixed seed; every voxel that contains a sampled position is marked,
and the marked set is grown by one voxel in every direction (the 3×3×3, or 3×3, block), so
that a voxel whose centre is reachable but which no sample happened to hit is still
evaluated. Only the marked voxels get the orientation sweep; the others are not in the map
(their index is 0). The number of samples defaults to 10 per voxel of the sampled bounding
box (at least 20 000, at most 4 000 000).
"""
from __future__ import annotations

from typing import Any, Callable, TYPE_CHECKING

import numpy as np
from numpy.typing import ArrayLike
from robokit._arrays import kernel_array
from robokit.errors import InputError


if TYPE_CHECKING:
    from robokit.description.poe import PoEParams
    from robokit.description.robot import Robot

__all__ = ["reachable_voxels"]

_BATCH = 8192
#: Bytes per voxel of the grid and the map at their peak (grown int64 codes and their sorted
#: copy, int64 keys, float64 centres, counts and index).
GRID_BYTES_PER_VOXEL = 56
_MAX_BOX_VOXELS = 200_000_000


def tool_positions(poe: PoEParams, Q: np.ndarray) -> np.ndarray:
    """(B, 3) tool positions in the base frame at joint angles Q (B, n): ``e^{[S₁]θ₁}⋯e^{[Sₙ]θₙ} M``,
    by the compiled PoE kernel (:func:`robokit.kernels.poe.fkin_space_batch`, robokit's one PoE FK)."""
    from robokit.kernels.poe import fkin_space_batch

    # writeable, as the kernel takes them (a Robot's read-only poe: the arrays behind its views, no copy)
    M = kernel_array(poe.M, float)
    S = kernel_array(poe.Slist, float)
    return fkin_space_batch(M, S, kernel_array(Q, float))[:, :3, 3]


def _ranges(qlim: ArrayLike) -> tuple[np.ndarray, np.ndarray]:
    qlim = np.asarray(qlim, dtype=float)
    lo = np.where(np.isfinite(qlim[:, 0]), qlim[:, 0], -np.pi)
    hi = np.where(np.isfinite(qlim[:, 1]), qlim[:, 1], np.pi)
    return lo, hi


def reach_ball(poe: PoEParams, qlim: ArrayLike) -> tuple[np.ndarray, float]:
    """A ball (centre (3,), radius) containing every tool position: rotations keep lengths, so
    ``|p − r₁| ≤ Σ|r_{i+1} − r_i|`` over points r_i on the revolute axes (the tool point last),
    plus the travel of each prismatic joint."""
    S = np.asarray(poe.Slist, dtype=float)
    lo, hi = _ranges(qlim)
    points, travel = [], 0.0
    for i in range(S.shape[1]):
        w = S[:3, i]
        if np.linalg.norm(w) > 1e-12:
            points.append(np.cross(w, S[3:, i]) / float(w @ w))
        else:
            travel += max(abs(lo[i]), abs(hi[i])) * float(np.linalg.norm(S[3:, i]))
    points.append(np.asarray(poe.M, dtype=float)[:3, 3])
    P = np.array(points)
    return P[0], float(np.linalg.norm(np.diff(P, axis=0), axis=1).sum() + travel)


def _sampler(qlim: ArrayLike, seed: int | np.random.Generator | None) -> Callable[[int], np.ndarray]:
    lo, hi = _ranges(qlim)
    rng = np.random.default_rng(seed)
    return lambda m: rng.uniform(lo, hi, size=(m, len(lo)))


def reachable_voxels(robot: Robot, resolution: float, *, samples: int | None = None, seed: int = 0, chain: Any = None,
                     max_bytes: float | None = None) -> tuple[np.ndarray, int]:
    """Integer lattice keys of the voxels the pre-pass marks (see the module docstring).

    Parameters
    ----------
    robot : :class:`robokit.Robot`
    resolution : float
        Voxel edge (m).
    samples : int, optional
        Forward-kinematics samples (default: 10 per voxel of the bounding box, clipped to
        [20 000, 4 000 000]).
    seed : int
        Seed of the configuration samples.
    chain : :class:`robokit.ik.planar.PlanarChain`, optional
        For a planar arm: keys are 2-D plane coordinates.
    max_bytes : float, optional
        Refuse (``InputError``, before sampling) when the grid could need more memory than
        this: ``GRID_BYTES_PER_VOXEL · 3^d · min(box, samples)`` bytes, ``box`` the voxels of
        the sampled bounding box (the marked voxels grown by one in every direction, their
        keys, centres, counts and index).

    Returns
    -------
    keys : (M, d) int64 ndarray
        Sorted (lexicographically) lattice indices, d = 3 (or 2 for a planar arm).
    samples : int
        The number of samples used.

    Examples
    --------
    >>> import robokit
    >>> keys, used = reachable_voxels(robokit.load("ur5"), 0.2)
    >>> keys.shape[1]
    3
    """
    poe = robot.poe
    draw = _sampler(robot.qlim, seed)
    centre, radius = reach_ball(poe, robot.qlim)
    if chain is not None:
        centre = chain.to_plane(centre[None])[0][0]
    # lattice keys inside the ball's box, encoded as one int64 each (cheap to sort and grow)
    lo = np.floor((centre - radius) / resolution).astype(np.int64) - 2
    size = np.full(len(lo), int(np.ceil(2 * radius / resolution)) + 5, dtype=np.int64)
    dims = len(lo)
    if float(np.prod(size.astype(float))) > 2.0**62:
        raise InputError(f"resolution: {resolution:g} m is too fine for an arm of reach {radius:.3g} m")
    stride = np.cumprod(np.r_[1, size[::-1][:-1]])[::-1].astype(np.int64)

    def codes_of(Q: np.ndarray) -> np.ndarray:
        P = tool_positions(poe, Q)
        if chain is not None:
            P = chain.to_plane(P)[0]
        return np.unique((np.rint(P / resolution).astype(np.int64) - lo) @ stride)

    pilot = draw(4096)
    pk = np.rint(tool_positions(poe, pilot) / resolution) if chain is None else \
        np.rint(chain.to_plane(tool_positions(poe, pilot))[0] / resolution)
    box = float(np.prod(pk.max(axis=0) - pk.min(axis=0) + 3))
    if box > _MAX_BOX_VOXELS:
        raise InputError(f"resolution: a map at {resolution:g} m spans about {box:.3g} voxels and would need "
                         f"more than {GRID_BYTES_PER_VOXEL * box / 1e9:.3g} GB; robokit refuses maps above "
                         f"{_MAX_BOX_VOXELS:.0e} voxels (use a coarser resolution)")
    if samples is None:
        samples = int(min(max(10 * box, 20_000), 4_000_000))
    if max_bytes is not None:
        most = 3**dims * min(box, float(samples))
        need = GRID_BYTES_PER_VOXEL * most
        if need > max_bytes:
            raise InputError(f"resolution: a map at {resolution:g} m may hold {most:.3g} voxels and need about "
                             f"{need / 1e9:.3g} GB; robokit refuses maps above {max_bytes / 1e9:.3g} GB "
                             "(use a coarser resolution)")
    found = [codes_of(pilot)]
    left = int(samples) - len(pilot)
    while left > 0:
        m = min(left, _BATCH)
        found.append(codes_of(draw(m)))
        left -= m
        if len(found) > 8:
            found = [np.unique(np.concatenate(found))]
    codes = np.unique(np.concatenate(found))
    del found
    # grow by one voxel in every direction
    offsets = np.stack(np.meshgrid(*[np.arange(-1, 2)] * dims, indexing="ij"), axis=-1).reshape(-1, dims) @ stride
    codes = np.unique((codes[:, None] + offsets[None, :]).ravel())
    keys = np.empty((len(codes), dims), dtype=np.int64)
    rest = codes
    for k in range(dims):
        keys[:, k], rest = np.divmod(rest, stride[k])
    keys += lo
    return keys, int(samples)
