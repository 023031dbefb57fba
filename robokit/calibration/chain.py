r"""A serial chain as joint placements and joint screws — the geometry calibration adjusts.

For a robot with n one-degree-of-freedom joints the tool pose in the base frame is

.. math::

    T(q) = X_1\, e^{[A_1] q_1}\; X_2\, e^{[A_2] q_2} \cdots X_n\, e^{[A_n] q_n}\; X_{n+1}

* ``X_i`` (4×4, i = 1..n) — the pose of joint i's frame in joint i−1's frame at q = 0 (``X_1``
  is joint 1's frame in the base frame: it holds the base transform);
* ``A_i`` (6,) — joint i's unit screw in its own frame, angular first ``(ω, v)``: ``(ω̂, 0)`` for a
  revolute joint (the frame's origin is on the axis), ``(0, v̂)`` for a prismatic one;
* ``X_{n+1}`` — the tool frame in joint n's frame.

This is Pinocchio's joint-placement form of the product of exponentials (Lecture 4): the same
arm as ``M`` and the space screws ``Sᵢ = Ad_{X_1 ⋯ X_i} A_i``, but every joint carries its own
frame, so a small error of any joint's position or direction is a small change of one ``X_i``.

The inertias stay attached to the joint frames (each link's mass, centre of mass and inertia in
joint i's frame), so a calibrated chain keeps the nominal dynamics of every link.
"""
from __future__ import annotations

import re
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any
from xml.sax.saxutils import quoteattr

import numpy as np

from robokit.description.dh import rpy_from_matrix
from robokit.description.reflected import DRAKE_XMLNS, drake_transmission
from robokit.spatial import lie
from robokit.errors import InputError

if TYPE_CHECKING:
    from robokit.description.robot import Robot

__all__ = ["JointChain", "chain_from_robot", "chain_urdf", "robot_from_chain"]


@dataclass(frozen=True, eq=False)
class JointChain:
    """Joint placements and screws of a serial chain (see the module docstring).

    Attributes
    ----------
    placements : ndarray, shape (n + 1, 4, 4)
        ``X_1 … X_n`` (joint i's frame in joint i−1's frame at q = 0; ``X_1`` in the base frame)
        and ``X_{n+1}``, the tool frame in joint n's frame. Metres.
    axes : ndarray, shape (n, 6)
        Unit screw ``A_i`` of each joint in its own frame, angular first ``(ω, v)``.
    kinds : tuple of str
        ``"R"`` (revolute) or ``"P"`` (prismatic) per joint.

    Examples
    --------
    >>> import numpy as np, robokit
    >>> from robokit.calibration import chain_from_robot
    >>> robot = robokit.load("puma560")
    >>> chain = chain_from_robot(robot)
    >>> bool(np.allclose(chain.fk(np.zeros((1, 6)))[0], robot.frame_pose(np.zeros(6))))
    True
    """

    placements: np.ndarray
    axes: np.ndarray
    kinds: tuple

    @property
    def n(self) -> int:
        """Number of joints."""
        return int(self.axes.shape[0])

    def fk(self, q: np.ndarray) -> np.ndarray:
        """Tool poses ``T(q) = X_1 e^{[A_1]q_1} X_2 ⋯ e^{[A_n]q_n} X_{n+1}`` in the base frame.

        Parameters
        ----------
        q : numpy.ndarray, shape (K, n)
            As for :meth:`frames`: ``fk(q)`` is the last row of ``frames(q)``.

        Returns
        -------
        numpy.ndarray, shape (K, 4, 4)
            The tool poses, m.

        Examples
        --------
        >>> robot = rk.load("twolink")
        >>> chain_from_robot(robot).fk(np.array([[0.0, np.pi / 2]]))[0][:2, 3].round(4).tolist()
        [1.0, 0.8]
        """
        return self.frames(q)[-1]

    def frames(self, q: np.ndarray) -> np.ndarray:
        """Poses in the base frame of the frames the errors act in.

        Row i (i = 0..n−1) is ``P_{i+1} = X_1 e^{[A_1]q_1} ⋯ X_{i+1}`` — joint i+1's frame before
        its own motion; row n is the tool frame ``T(q)``; row n + 1 repeats it (so the tool's
        error frame is row n as well).

        Parameters
        ----------
        q : numpy.ndarray, shape (K, n)
            Joint values, one configuration per row (rad, m).

        Returns
        -------
        numpy.ndarray, shape (n + 2, K, 4, 4)
            The frames, m.

        Examples
        --------
        >>> F = chain_from_robot(rk.load("twolink")).frames(np.zeros((1, 2)))
        >>> F.shape, F[1, 0, :3, 3].tolist(), F[2, 0, :3, 3].tolist()   # joint 2 at 1 m, the tool at 1.8 m
        ((4, 1, 4, 4), [1.0, 0.0, 0.0], [1.8, 0.0, 0.0])
        """
        q = np.asarray(q, dtype=float)
        K = q.shape[0]
        out = np.empty((self.n + 2, K, 4, 4))
        T = np.broadcast_to(self.placements[0], (K, 4, 4)).copy()
        for i in range(self.n):
            out[i] = T
            T = T @ lie.exp6(self.axes[i][None, :] * q[:, i:i + 1])
            T = T @ self.placements[i + 1]
        out[self.n] = T
        out[self.n + 1] = T
        return out

    def perturbed(self, delta: np.ndarray) -> JointChain:
        """The chain with every placement moved by its own small SE(3) error: ``X_i ← X_i e^{[δ_i]}``.

        Parameters
        ----------
        delta : numpy.ndarray, shape (n + 1, 6) or (6(n + 1),)
            One twist ``δ_i = (ω, v)`` per placement (rad, m), in the placement's child frame.

        Returns
        -------
        JointChain
            A new chain (this one is unchanged).

        Examples
        --------
        Lengthening the tool placement by 1 cm moves the tool 1 cm along the last link:

        >>> chain = chain_from_robot(rk.load("twolink"))
        >>> delta = np.zeros((3, 6)); delta[2, 3] = 0.01
        >>> round(float(chain.perturbed(delta).fk(np.zeros((1, 2)))[0][0, 3]), 6)
        1.81
        """
        delta = np.asarray(delta, dtype=float).reshape(self.n + 1, 6)
        return JointChain(self.placements @ lie.exp6(delta), self.axes.copy(), self.kinds)


def chain_from_robot(robot: Robot) -> JointChain:
    """The :class:`JointChain` of a :class:`robokit.Robot`'s Pinocchio chain (base → tip).

    Parameters
    ----------
    robot : Robot
        Any loaded robot (DH file, URDF, example-robot-data); its tip frame is the tool.

    Returns
    -------
    JointChain
        Placements from ``model.jointPlacements`` and the tip frame's placement, screws from
        each joint's motion subspace at q = 0 in its own frame.

    Examples
    --------
    >>> import robokit
    >>> from robokit.calibration import chain_from_robot
    >>> chain_from_robot(robokit.load("rrr")).kinds
    ('R', 'R', 'R')
    """
    import pinocchio as pin

    model = robot.model
    data = model.createData()
    q0 = pin.neutral(model)
    pin.computeJointJacobians(model, data, q0)
    n = robot.n
    placements = np.empty((n + 1, 4, 4))
    axes = np.zeros((n, 6))
    kinds = []
    for i in range(n):
        j = i + 1
        placements[i] = model.jointPlacements[j].homogeneous
        S = np.asarray(pin.getJointJacobian(model, data, j, pin.ReferenceFrame.LOCAL)).reshape(6, -1)[:, i]
        w, v = S[3:], S[:3]
        if np.linalg.norm(w) > 0.5:
            axes[i, :3] = w / np.linalg.norm(w)
            kinds.append("R")
        else:
            axes[i, 3:] = v / np.linalg.norm(v)
            kinds.append("P")
    tip = model.frames[robot.tip_id]
    if tip.parentJoint != n:
        raise InputError(f"robot: the tip frame {robot.tip!r} is not on the last joint of the chain")
    placements[n] = tip.placement.homogeneous
    return JointChain(placements, axes, tuple(kinds))


def _f(x: float) -> str:
    x = float(x)
    return "0" if x == 0.0 else repr(x)


def _origin(T: np.ndarray) -> str:
    xyz = " ".join(_f(v) for v in T[:3, 3])
    rpy = " ".join(_f(v) for v in rpy_from_matrix(T[:3, :3]))
    return f'<origin xyz="{xyz}" rpy="{rpy}"/>'


_DH_FRAME = re.compile(r"dh_\d+")


def _cylinder(p0: np.ndarray, p1: np.ndarray, radius: float, material: str) -> str:
    """A ``<visual>`` cylinder from p0 to p1 (link frame, m); "" when they coincide."""
    d = p1 - p0
    length = float(np.linalg.norm(d))
    if length < 1e-9:
        return ""
    z = d / length
    ref = np.array([1.0, 0.0, 0.0]) if abs(z[0]) < 0.9 else np.array([0.0, 1.0, 0.0])
    x = np.cross(ref, z)
    x /= np.linalg.norm(x)
    T = np.eye(4)
    T[:3, :3] = np.column_stack([x, np.cross(z, x), z])
    T[:3, 3] = 0.5 * (p0 + p1)
    return (f'<visual>{_origin(T)}<geometry><cylinder radius="{_f(radius)}" length="{_f(length)}"/></geometry>'
            f'<material name="{material}"/></visual>')


def _carried_frames(robot: Robot, nominal: JointChain, chain: JointChain) -> list[tuple[str, int, np.ndarray]]:
    """The nominal robot's ``dh_<k>`` frames as (name, parent joint, placement in the new chain).

    A frame that coincided with the next joint's frame (standard DH: frame {i} has z on joint i+1)
    or with the tool moves with it; any other keeps its placement on its joint."""
    import pinocchio as pin

    out = []
    for fr in robot.model.frames:
        if fr.type != pin.FrameType.BODY or not _DH_FRAME.fullmatch(fr.name) or fr.name == robot.tip:
            continue
        j = int(fr.parentJoint)
        P = fr.placement.homogeneous
        if np.allclose(P, nominal.placements[j], atol=1e-12):
            P = chain.placements[j]
        out.append((fr.name, j, P))
    return out


def chain_urdf(robot: Robot, chain: JointChain, name: str | None = None) -> str:
    r"""URDF text of ``robot`` with its geometry replaced by ``chain`` (the robot's inertias kept).

    Parameters
    ----------
    robot : Robot
        The nominal robot: inertias (in each joint's frame), joint limits, the ``dh_<k>`` frames.
    chain : JointChain
        The (calibrated) geometry, with the same joints as ``robot``.
    name : str, optional
        The URDF robot name (default: ``robot.name``).

    Returns
    -------
    str
        A URDF: root ``base_link``; joints ``joint_1 … joint_n`` (revolute, continuous or
        prismatic) with ``<origin>`` ``X_i`` and ``<axis>`` the screw's direction; link ``link_i``
        moved by joint i carrying the nominal mass, centre of mass and inertia, and simple visuals (a
        cylinder on the joint axis, a segment to the next joint or the tool); a massless ``tool``
        link fixed at ``X_{n+1}``; the nominal robot's ``dh_<k>`` frames as massless fixed links
        (a frame that was joint k+1's frame, or the tool's, follows it); a joint with a reflected
        rotor inertia (``robot.model.armature``) gets a Drake ``<transmission>`` holding it
        (:func:`robokit.description.reflected.drake_transmission`), which robokit and Drake read back
        as that armature.

    Examples
    --------
    >>> import robokit
    >>> from robokit.calibration import chain_from_robot, chain_urdf
    >>> robot = robokit.load("rrr")
    >>> chain_urdf(robot, chain_from_robot(robot)).count("<joint name=\"joint_")
    3
    """
    nominal = chain_from_robot(robot)
    if chain.n != robot.n or chain.kinds != nominal.kinds:
        raise InputError(f"chain: expected {robot.n} joints of kinds {nominal.kinds}, got {chain.kinds}")
    model = robot.model
    n = robot.n
    # simple visuals, sized from the arm: a cylinder on each joint axis, a segment to the next joint
    reach = max([float(np.linalg.norm(chain.placements[i][:3, 3])) for i in range(n + 1)] + [0.1])
    r_joint = max(0.01, 0.08 * reach)
    armature = [float(model.armature[model.joints[i + 1].idx_v]) for i in range(n)]
    xmlns = f" {DRAKE_XMLNS}" if any(armature) else ""
    lines = ['<?xml version="1.0"?>', f"<robot name={quoteattr(name or robot.name)}{xmlns}>",
             '  <material name="robokit_joint"><color rgba="0.95 0.55 0.1 1"/></material>',
             '  <material name="robokit_link"><color rgba="0.55 0.6 0.7 1"/></material>',
             '  <link name="base_link"/>']
    for i in range(n):
        j = i + 1
        Y = model.inertias[j]
        inertial = ""
        if Y.mass > 0 or np.any(Y.inertia != 0):
            I = Y.inertia
            inertial = (f'<inertial><origin xyz="{" ".join(_f(c) for c in Y.lever)}" rpy="0 0 0"/>'
                        f'<mass value="{_f(Y.mass)}"/><inertia ixx="{_f(I[0, 0])}" ixy="{_f(I[0, 1])}" '
                        f'ixz="{_f(I[0, 2])}" iyy="{_f(I[1, 1])}" iyz="{_f(I[1, 2])}" izz="{_f(I[2, 2])}"/>'
                        "</inertial>")
        direction = chain.axes[i, :3] if chain.kinds[i] == "R" else chain.axes[i, 3:]
        visual = _cylinder(-1.2 * r_joint * direction, 1.2 * r_joint * direction, r_joint, "robokit_joint")
        visual += _cylinder(np.zeros(3), chain.placements[j][:3, 3], 0.45 * r_joint, "robokit_link")
        lines.append(f'  <link name="link_{j}">{inertial}{visual}</link>')
        lo, hi = robot.qlim[i]
        if chain.kinds[i] == "R":
            axis = chain.axes[i, :3]
            jtype = "revolute" if np.isfinite(lo) and np.isfinite(hi) else "continuous"
        else:
            axis = chain.axes[i, 3:]
            jtype = "prismatic"
        limit = ""
        if jtype != "continuous":
            limit = f'<limit lower="{_f(lo)}" upper="{_f(hi)}" effort="1000" velocity="10"/>'
        else:
            limit = '<limit effort="1000" velocity="10"/>'
        parent = "base_link" if j == 1 else f"link_{j - 1}"
        lines.append(f'  <joint name="joint_{j}" type="{jtype}"><parent link="{parent}"/><child link="link_{j}"/>'
                     f'{_origin(chain.placements[i])}<axis xyz="{" ".join(_f(a) for a in axis)}"/>{limit}</joint>')
    for fname, j, P in _carried_frames(robot, nominal, chain):
        parent = "base_link" if j == 0 else f"link_{j}"
        lines.append(f'  <link name="{fname}"/>')
        lines.append(f'  <joint name="{parent}_to_{fname}" type="fixed"><parent link="{parent}"/>'
                     f'<child link="{fname}"/>{_origin(P)}</joint>')
    lines.append('  <link name="tool"/>')
    lines.append(f'  <joint name="link_{n}_to_tool" type="fixed"><parent link="link_{n}"/><child link="tool"/>'
                 f"{_origin(chain.placements[n])}</joint>")
    # the reflected rotor inertia, as Drake's URDF dialect holds it (every joint above has effort 1000)
    lines += [f"  {drake_transmission(f'joint_{i + 1}', a)}" for i, a in enumerate(armature) if a]
    lines.append("</robot>")
    return "\n".join(lines) + "\n"


def robot_from_chain(robot: Robot, chain: JointChain, name: str | None = None) -> Robot:
    """A :class:`robokit.Robot` with ``chain``'s geometry and ``robot``'s inertias, limits, gravity and
    reflected rotor inertias (armature).

    Parameters
    ----------
    robot : Robot
        The nominal robot.
    chain : JointChain
        Its calibrated geometry.
    name : str, optional
        Name of the new robot (default ``robot.name + "_calibrated"``).

    Returns
    -------
    Robot
        Built by Pinocchio from :func:`chain_urdf` (tip frame ``tool``), so its ``frame_pose``,
        Jacobians and dynamics are Pinocchio's on the calibrated geometry. ``robot.nominal`` is the
        nominal robot (its structure gives the exact IK, :mod:`robokit.ik.calibrated`);
        ``robot.spec`` is a ``"calibrated"`` :class:`~robokit.description.spec.RobotSpec` carrying the
        URDF, the gravity and the nominal's spec, so ``robokit.load(robot.spec)`` rebuilds it in any
        process; ``robot.save(path)`` writes it.

    Examples
    --------
    >>> import numpy as np, robokit
    >>> from robokit.calibration import chain_from_robot, robot_from_chain
    >>> robot = robokit.load("rrr")
    >>> same = robot_from_chain(robot, chain_from_robot(robot))
    >>> bool(np.allclose(same.frame_pose([0.1, 0.2, 0.3]), robot.frame_pose([0.1, 0.2, 0.3])))
    True
    """
    from robokit.description.spec import RobotSpec
    from robokit.description.urdf_files import load_urdf_text

    name = name or f"{robot.name}_calibrated"
    xml = chain_urdf(robot, chain, name)
    gravity = tuple(float(g) for g in np.asarray(robot.gravity, dtype=float))
    spec = RobotSpec("calibrated", name=name, tip="tool", text=xml, nominal=robot.spec, gravity=gravity)
    return load_urdf_text(xml, spec, "tool", gravity, nominal=robot)
