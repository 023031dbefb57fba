r"""A robot's chain as plain arrays, and the stick model drawn from them.

:func:`chain_geometry` reduces a :class:`~robokit.description.robot.Robot` to what its forward
kinematics needs — each joint's type, its placement in the previous joint's frame and its axis
in its own frame, and the tip frame's placement in the last joint's frame:

.. math::  {}^0T_{tip}(q) = \prod_{i=1}^{n} X_i \, \exp([\hat S_i] q_i) \; X_{tip},
           \qquad \hat S_i = (a_i, 0) \text{ (revolute) or } (0, a_i) \text{ (prismatic)}

(Lecture 3's product of joint placements and joint motions; Pinocchio's ``jointPlacements``).
:func:`stick_robot` builds a Robot back from those arrays alone, through the one model builder (no
URDF text): a cylinder on each joint axis and a segment from each joint to the next, so a
picture needs no file. A capability map
stores these arrays for robots that have no shipped or example-robot-data name and no DH
table, so ``robokit view MAP.npz`` draws the arm without opening any path.
"""
from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike

from robokit.description.mjcf_write import _joint_axis
from robokit.description.robot import Robot
from robokit.description.urdf_gen import MATERIALS, _cylinder_pose
from robokit.errors import InputError

__all__ = ["chain_geometry", "stick_robot", "MAX_STICK_JOINTS"]

#: The most joints a stick model may have (a serial manipulator has a few dozen at most).
MAX_STICK_JOINTS = 256


def chain_geometry(robot: Robot) -> dict[str, np.ndarray]:
    """The arrays that fix a robot's forward kinematics (module docstring).

    Parameters
    ----------
    robot : Robot

    Returns
    -------
    dict
        ``joint_types`` (n,) str, ``"R"`` or ``"P"``; ``joint_placements`` (n, 4, 4), joint i's
        frame in joint i−1's frame at q = 0 (joint 0: the root), m; ``joint_axes`` (n, 3) unit
        axes in each joint's own frame; ``tip_placement`` (4, 4), the tip frame in the last
        joint's frame, m.

    Examples
    --------
    >>> import robokit
    >>> g = chain_geometry(robokit.load("rrr"))
    >>> g["joint_placements"].shape
    (3, 4, 4)
    """
    model = robot.model
    n = model.njoints - 1
    types, axes = [], []
    for j in range(1, n + 1):
        kind, axis = _joint_axis(model, j)
        types.append("R" if kind == "hinge" else "P")
        axes.append(axis)
    tip = model.frames[robot.tip_id]
    X_tip = np.asarray(tip.placement.homogeneous, dtype=float)
    if tip.parentJoint != n:  # a tip frame on an earlier joint: express it in the last joint's frame
        raise InputError(f"robot: the tip {robot.tip!r} is not on the chain's last joint")
    return {
        "joint_types": np.array(types, dtype="<U1"),
        "joint_placements": np.array([model.jointPlacements[j].homogeneous for j in range(1, n + 1)], dtype=float),
        "joint_axes": np.array(axes, dtype=float).reshape(n, 3),
        "tip_placement": X_tip,
    }


def _checked(joint_types: ArrayLike, joint_placements: ArrayLike, joint_axes: ArrayLike,
             tip_placement: ArrayLike) -> tuple[list[str], np.ndarray, np.ndarray, np.ndarray]:
    types = np.asarray(joint_types)
    if types.ndim != 1 or types.dtype.kind not in "US":
        raise InputError(f"joint_types: expected a 1-D array of 'R'/'P' strings, got dtype {types.dtype} "
                         f"shape {types.shape}")
    n = len(types)
    if not 1 <= n <= MAX_STICK_JOINTS:
        raise InputError(f"joint_types: expected 1 to {MAX_STICK_JOINTS} joints, got {n}")
    names = [str(t) for t in types.tolist()]
    bad = sorted({t for t in names if t not in ("R", "P")})
    if bad:
        raise InputError(f"joint_types: expected 'R' or 'P', got {bad[:3]}")
    arrays = []
    for arg, value, shape in (("joint_placements", joint_placements, (n, 4, 4)), ("joint_axes", joint_axes, (n, 3)),
                              ("tip_placement", tip_placement, (4, 4))):
        a = np.asarray(value)
        if a.dtype.kind not in "fiu":
            raise InputError(f"{arg}: expected real numbers, got dtype {a.dtype}")
        a = a.astype(float)
        if a.shape != shape:
            raise InputError(f"{arg}: expected shape {shape}, got {a.shape}")
        if not np.isfinite(a).all():
            raise InputError(f"{arg}: contains NaN or infinite values")
        arrays.append(a)
    X, A, X_tip = arrays
    for arg, Ts in (("joint_placements", X), ("tip_placement", X_tip[None])):
        R = Ts[:, :3, :3]
        err = np.abs(np.einsum("kij,kil->kjl", R, R) - np.eye(3)).max()
        if err > 1e-6 or np.any(np.linalg.det(R) < 0) or np.any(np.abs(Ts[:, 3] - [0, 0, 0, 1]) > 0):
            raise InputError(f"{arg}: not rigid transforms (rotation not orthonormal or last row not 0 0 0 1)")
        if np.abs(Ts[:, :3, 3]).max() > 1e3:
            raise InputError(f"{arg}: translations larger than 1 km")
    norms = np.linalg.norm(A, axis=1)
    if np.any(np.abs(norms - 1.0) > 1e-6):
        raise InputError("joint_axes: expected unit vectors")
    return names, X, A / norms[:, None], X_tip


def stick_robot(name: str, joint_types: ArrayLike, joint_placements: ArrayLike, joint_axes: ArrayLike,
                tip_placement: ArrayLike, tip: str = "tip") -> Robot:
    """A Robot built from :func:`chain_geometry`'s arrays alone: same kinematics, stick geometry.

    Parameters
    ----------
    name : str
        The robot's name (text only; it never names a file).
    joint_types : (n,) array of str
        ``"R"`` (revolute) or ``"P"`` (prismatic), 1 ≤ n ≤ :data:`MAX_STICK_JOINTS`.
    joint_placements : (n, 4, 4) array
        Joint i's frame in joint i−1's frame at q = 0, m.
    joint_axes : (n, 3) array
        Unit axis of each joint in its own frame.
    tip_placement : (4, 4) array
        The tip frame in the last joint's frame, m.
    tip : str
        Name of the tip frame (``"tip"`` if it is empty or one of the generated link names).

    Returns
    -------
    Robot
        Links ``base_link``, ``link_1`` … ``link_n``, the tip; joints ``joint_1`` …; no mass;
        ``robot.spec`` None (it was not loaded from a description).

    Raises
    ------
    InputError
        Arrays of the wrong type, shape or size, non-finite, or not rigid transforms.

    Examples
    --------
    >>> import numpy as np, robokit
    >>> arm = robokit.load("rrr")
    >>> stick = stick_robot(arm.name, **chain_geometry(arm))
    >>> bool(np.allclose(stick.frame_pose([0.1, 0.2, 0.3]), arm.frame_pose([0.1, 0.2, 0.3])))
    True
    """
    from robokit.description.model_builder import Description, Geometry, Joint, Link, Pose, build_model

    types, X, A, X_tip = _checked(joint_types, joint_placements, joint_axes, tip_placement)
    if not isinstance(name, str) or not isinstance(tip, str):
        raise InputError("name, tip: expected strings")
    n = len(types)
    generated = {"base_link"} | {f"link_{i}" for i in range(1, n + 1)}
    safe_tip = tip if tip and tip not in generated else "tip"
    scale = max(float(np.abs(X[:, :3, 3]).max(initial=0.0)), float(np.abs(X_tip[:3, 3]).max()), 0.1)
    r_joint = max(0.01, 0.08 * scale)
    r_link = 0.45 * r_joint
    links, joints, geoms = [Link("base_link")], [], []
    for i in range(1, n + 1):
        a = A[i - 1]
        nxt = (X[i] if i < n else X_tip)[:3, 3]
        for p0, p1, radius, material in ((-1.2 * r_joint * a, 1.2 * r_joint * a, r_joint, "robokit_joint"),
                                         (np.zeros(3), nxt, r_link, "robokit_link")):
            c = _cylinder_pose(p0, p1)
            if c is not None:
                geoms.append(Geometry(f"link_{i}", "cylinder", Pose.from_matrix(c[0]), (radius, c[1]),
                                      color=MATERIALS[material]))
        links.append(Link(f"link_{i}"))
        kind = "revolute" if types[i - 1] == "R" else "prismatic"
        limit = 1e3 if kind == "prismatic" else 2 * np.pi
        joints.append(Joint(f"joint_{i}", kind, "base_link" if i == 1 else f"link_{i - 1}", f"link_{i}",
                            Pose.from_matrix(X[i - 1]), axis=(float(a[0]), float(a[1]), float(a[2])),
                            lower=-limit, upper=limit, effort=1000.0, velocity=10.0))
    links.append(Link(safe_tip))
    joints.append(Joint(f"link_{n}_to_tip", "fixed", f"link_{n}", safe_tip, Pose.from_matrix(X_tip)))
    model, visual, _, _ = build_model(Description(name or "robot", tuple(links), tuple(joints),
                                                  geometries=tuple(geoms)))
    return Robot(name or "robot", model, safe_tip, visual_model=visual, collision_model=None,
                 source=f"stick model of {name or 'robot'} (joint placements and axes)")
