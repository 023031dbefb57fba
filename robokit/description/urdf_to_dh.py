r"""URDF → DH: standard and modified DH tables of any serial chain (Lecture 4).

From the joint axes at the zero configuration (each a line: a point and a unit direction, in the
URDF root frame), the DH frames are placed on the common normals between consecutive axes:

* standard (Spong/Corke): ``z_{i}`` is the axis of joint i+1; the origin of frame {i} is where the
  common normal of axes i and i+1 meets axis i+1, and ``x_i`` points along that normal, from
  axis i to axis i+1. Frame {0} sits on axis 1 at the foot of the perpendicular from the root
  origin, with ``x_0 = x_1`` (so θ₁ = 0 and d₁ is the height of the first normal — UR5's d₁). Frame {N} has ``z_N ∥ z_{N−1}`` (α_N = 0) and its origin at the tip,
  ``x_N`` pointing from axis N to the tip (``x_{N−1}`` when the tip is on the axis).
* modified (Craig): ``z_i`` is the axis of joint i; the origin of frame {i} is where the common
  normal of axes i and i+1 meets axis i, ``x_i`` along it. Frame {0} coincides with frame {1} at
  the zero configuration (a₀ = α₀ = d₁ = θ₁ = 0); frame {N} sits where the tip projects onto
  axis N, ``x_N`` toward the tip (``x_{N−1}`` projected when the tip is on the axis).

Special cases, and the choices made (documented free choices of the convention):

* skew axes: the unique common normal; a > 0;
* intersecting axes: a = 0, origin at the intersection, ``x = ±(z_i × z_{i+1})/‖·‖`` with the sign
  that keeps x closest to the previous frame's x (so θ offsets stay near 0);
* parallel axes: the normal is free to slide; it is taken through the previous frame's origin
  (standard) or through the point where the previous x axis meets the axis (modified), so that
  d = 0 there — offsets stay small;
* coincident axes: a = α = 0 and ``x`` is kept from the previous frame;
* prismatic joints: only the direction of the axis matters; its line is taken through the joint
  frame's origin, and the DH offset d is whatever reproduces the zero configuration.

The base transform (root → frame {0}) and the tool transform (frame {N} → tip) make the table
exact; joint offsets θᵢ (revolute) or dᵢ (prismatic) reproduce the URDF's zero configuration.
Each link's mass, centre of mass and inertia are carried into its DH frame (the body moved by
joint i is rigidly attached to DH frame {i} in both conventions), so URDF → DH → URDF keeps the
dynamics. The result is verified by DH forward kinematics against Pinocchio at random
configurations; the residual is reported.
"""
from __future__ import annotations

from dataclasses import dataclass

from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import ArrayLike

from robokit.description.dh import DHLink, DHTable
from robokit.spatial.lines import common_normal
from robokit.errors import InputError
from robokit._deprecation import deprecated_alias

if TYPE_CHECKING:
    from robokit.description.robot import Robot

__all__ = ["dh_from_urdf", "dh_from_lines", "URDFToDH", "format_dh_table", "joint_axes"]

_EPS = 1e-9


def _unit(v: np.ndarray) -> np.ndarray:
    return v / np.linalg.norm(v)


def joint_axes(robot: Robot) -> list[tuple[np.ndarray, np.ndarray, str]]:
    """Joint axes of a Robot's chain at q = 0, as lines in the root frame.

    Directions are the space screw axes' ω (revolute) or v (prismatic); a revolute axis passes
    through the joint frame's origin (a prismatic one is taken through it too).

    Parameters
    ----------
    robot : Robot
        The serial chain.

    Returns
    -------
    list of (numpy.ndarray, numpy.ndarray, str)
        One ``(point (3,), unit direction (3,), kind)`` per joint, root to tip; the point in m,
        root frame; kind ``"R"`` or ``"P"``.

    Examples
    --------
    >>> [(p.tolist(), w.tolist(), k) for p, w, k in joint_axes(rk.load("twolink"))]
    [([0.0, 0.0, 0.0], [0.0, 0.0, 1.0], 'R'), ([1.0, 0.0, 0.0], [0.0, 0.0, 1.0], 'R')]
    """
    import pinocchio as pin

    model = robot.model
    data = model.createData()
    pin.forwardKinematics(model, data, pin.neutral(model))
    S = robot.poe.Slist
    axes = []
    for i in range(robot.n):
        o = data.oMi[i + 1].translation.copy()
        w, v = S[:3, i], S[3:, i]
        if np.linalg.norm(w) > 0.5:
            axes.append((o, _unit(w), "R"))
        else:
            axes.append((o, _unit(v), "P"))
    return axes


def _normal(p1: np.ndarray, z1: np.ndarray, p2: np.ndarray, z2: np.ndarray, ref: np.ndarray,
            x_prev: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(foot on line 1, foot on line 2, x direction) of the DH normal from line 1 to line 2
    (:func:`robokit.common_normal`, with the DH choices of the module docstring).

    ref: the point on line 1 used when the lines are parallel; x_prev: the sign of x for intersecting
    lines, and x itself (projected) when the lines coincide.
    """
    cn = common_normal(p1, z1, p2, z2, ref=ref, tol=_EPS)
    if cn.kind in ("skew", "parallel"):
        return cn.foot1, cn.foot2, cn.direction
    if cn.kind == "intersecting":  # x = ±(z1 × z2), the sign closest to the previous x
        x = cn.direction
        return cn.foot1, cn.foot1, (-x if x @ x_prev < 0 else x)
    x = x_prev - (x_prev @ z1) * z1  # coincident: keep the previous x
    if np.linalg.norm(x) < 1e-9:
        x = cn.direction
    return cn.foot1, cn.foot1, _unit(x)


def _frame(o: ArrayLike, x: np.ndarray, z: np.ndarray) -> np.ndarray:
    T = np.eye(4)
    x = _unit(x - (x @ z) * z)
    T[:3, 0], T[:3, 1], T[:3, 2], T[:3, 3] = x, np.cross(z, x), z, o
    return T


def _params(T: np.ndarray, convention: str) -> tuple[float, float, float, float]:
    """(a, alpha, d, theta) of a link transform in the given convention."""
    if convention == "standard":
        th = np.arctan2(T[1, 0], T[0, 0])
        al = np.arctan2(T[2, 1], T[2, 2])
        return T[0, 3] * np.cos(th) + T[1, 3] * np.sin(th), al, T[2, 3], th
    al = np.arctan2(-T[1, 2], T[2, 2])
    th = np.arctan2(-T[0, 1], T[0, 0])
    return T[0, 3], al, -T[1, 3] * np.sin(al) + T[2, 3] * np.cos(al), th


def _clean(x: float) -> float:
    return 0.0 if abs(x) < 1e-12 else float(x)


@dataclass
class URDFToDH:
    """Result of :func:`dh_from_urdf`: the table and how well it reproduces the robot.

    Attributes
    ----------
    table : DHTable
        The extracted table, with the base and tool transforms that make it exact.
    residual : float
        Largest entry-wise difference between the table's tool pose and Pinocchio's over the
        sampled configurations (m for the translation, dimensionless for the rotation).
    samples : int
        Number of random configurations checked.
    exact : bool
        Property: ``residual ≤ 1e-9``.

    Examples
    --------
    >>> res = dh_from_urdf(rk.load("puma560"), samples=20)
    >>> res.exact, res.table.n
    (True, 6)
    """

    table: DHTable
    residual: float
    samples: int

    @property
    def exact(self) -> bool:
        """True when the table reproduces the robot to 1e-9 (``residual ≤ 1e-9``)."""
        return self.residual <= 1e-9


def _dh_frames(axes: list[tuple[np.ndarray, np.ndarray, str]], tip_o: np.ndarray, convention: str) -> list[np.ndarray]:
    """The DH frames {0} … {N} (4×4 poses in the root frame at q = 0) of the joint axes ``axes``
    (lines) and the tip origin ``tip_o``, placed as the module docstring says."""
    n = len(axes)
    frames = []
    if convention == "standard":
        # frames {1..N−1}: normals between axes i and i+1; frame {0} on axis 1
        p1, z1, _ = axes[0]
        ref = p1 + ((np.zeros(3) - p1) @ z1) * z1  # root origin projected onto axis 1
        x_prev = np.array([1.0, 0.0, 0.0])
        inner = []
        prev_origin = ref
        for i in range(n - 1):
            (pa, za, _), (pb, zb, _) = axes[i], axes[i + 1]
            fa, fb, x = _normal(pa, za, pb, zb, prev_origin, x_prev)
            inner.append((fa, fb, x, zb))
            prev_origin, x_prev = fb, x
        if inner:
            _, _, x1, _ = inner[0]
            frames.append(_frame(ref, x1, z1))  # frame {0}: on axis 1 below/above the root origin, x₀ = x₁
        else:
            frames.append(_frame(ref, np.array([1.0, 0.0, 0.0]) if abs(z1[0]) < 0.9 else np.array([0.0, 1.0, 0.0]), z1))
        for fa, fb, x, zb in inner:
            frames.append(_frame(fb, x, zb))
        # frame {N}: z_N ∥ z_{N−1}, origin at the tip, x from axis N toward the tip
        pN, zN, _ = axes[-1]
        foot = pN + ((tip_o - pN) @ zN) * zN
        radial = tip_o - foot
        x_last = frames[-1][:3, 0]
        if np.linalg.norm(radial) > _EPS:
            frames.append(_frame(tip_o, radial, zN))
        else:
            frames.append(_frame(foot, x_last, zN))
    else:
        x_prev = np.array([1.0, 0.0, 0.0])
        meet = None
        for i in range(n):
            p, z, _ = axes[i]
            ref = p + (((meet if meet is not None else np.zeros(3)) - p) @ z) * z
            if i < n - 1:
                pb, zb, _ = axes[i + 1]
                fa, fb, x = _normal(p, z, pb, zb, ref, x_prev)
                frames.append(_frame(fa, x, z))
                meet, x_prev = fb, x
            else:
                foot = p + ((tip_o - p) @ z) * z
                radial = tip_o - foot
                x = radial if np.linalg.norm(radial) > _EPS else (x_prev if np.linalg.norm(
                    x_prev - (x_prev @ z) * z) > 1e-9 else np.cross(z, [1.0, 0.0, 0.0]))
                origin = foot
                if meet is not None and np.linalg.norm(np.cross(axes[i - 1][1], z)) < 1e-9 and np.linalg.norm(radial) <= _EPS:
                    origin = p + ((meet - p) @ z) * z
                frames.append(_frame(origin, x, z))
        frames.insert(0, frames[0].copy())  # frame {0} = frame {1} at zero
    return frames


def dh_from_lines(axes: list[tuple[np.ndarray, np.ndarray, str]], T_tip: np.ndarray, name: str = "arm",
                  qlim: np.ndarray | None = None) -> DHTable:
    """The standard DH table (kinematics only) of a chain given by its joint axes at q = 0.

    The same frames as :func:`dh_from_urdf` (module docstring), from the lines alone: for an arm
    built from geometry rather than loaded (e.g. an arm with its structure restored,
    :mod:`robokit.ik.calibrated`). Masses and inertias are zero.

    Parameters
    ----------
    axes : list of (numpy.ndarray, numpy.ndarray, str)
        Per joint ``(point (3,), unit direction (3,), kind "R"/"P")`` in the root frame at q = 0, m
        (as :func:`joint_axes` returns them; a revolute joint turns about the line by the right-hand
        rule, a prismatic one slides along the direction).
    T_tip : numpy.ndarray, shape (4, 4)
        The tip pose at q = 0 in the root frame, m.
    name : str
        The table's name.
    qlim : numpy.ndarray, shape (n, 2), optional
        Joint limits (rad, m); rows with an infinite bound give no limit.

    Returns
    -------
    DHTable
        Standard convention; its FK at q equals the chain's (joint i moving about axis i by q_i).

    Examples
    --------
    >>> robot = rk.load("puma560")
    >>> table = dh_from_lines(joint_axes(robot), robot.frame_pose(np.zeros(6)))
    >>> q = np.array([0.1, -0.4, 0.3, 0.5, -0.2, 0.7])
    >>> bool(np.allclose(table.fk(q), robot.frame_pose(q), atol=1e-12))
    True
    """
    n = len(axes)
    T_tip = np.asarray(T_tip, dtype=float)
    frames = _dh_frames(axes, T_tip[:3, 3], "standard")
    links = []
    for i in range(n):
        a, al, d, th = _params(np.linalg.inv(frames[i]) @ frames[i + 1], "standard")
        lim = None
        if qlim is not None and np.isfinite(qlim[i]).all():
            lim = np.array(qlim[i], dtype=float)
        links.append(DHLink(axes[i][2], _clean(a), _clean(al), _clean(d), _clean(th), lim))
    tool = np.linalg.inv(frames[-1]) @ T_tip
    return DHTable(name, "standard", tuple(links), np.array([0.0, 0.0, -9.81]), frames[0], tool)


def dh_from_urdf(robot: Robot, convention: str = "standard", samples: int = 200,
               rng: int | np.random.Generator | None = 0) -> URDFToDH:
    """DH table (either convention) of a Robot's chain root → tip, with base and tool transforms.

    Frames are placed on the common normals of consecutive joint axes at q = 0 (Lecture 4; the
    choices for parallel, intersecting and coincident axes are in the module docstring). The table
    is checked by DH forward kinematics against Pinocchio at ``samples`` random configurations.

    Parameters
    ----------
    robot : Robot or str
        A :class:`robokit.Robot`, or anything ``robokit.load`` accepts (a URDF path or an
        example-robot-data name).
    convention : {"standard", "modified"}, optional
        Standard (Spong/Corke, default) or modified (Craig) DH.
    samples : int, optional
        Number of random configurations for the check (default 200).
    rng : int, numpy.random.Generator or None, optional
        Seed or generator for those configurations (default 0: reproducible).

    Returns
    -------
    URDFToDH
        ``.table`` (a :class:`DHTable`, lengths in m, angles in rad), ``.residual`` (the largest
        pose error found) and ``.exact`` (residual ≤ 1e-9).

    Examples
    --------
    The two parallel axes of the planar arm give a = 1 m and 0.8 m, α = 0:

    >>> res = dh_from_urdf(rk.load("twolink"), samples=20)
    >>> [(l.a, l.alpha) for l in res.table.links], res.exact
    ([(1.0, 0.0), (0.8, 0.0)], True)
    """
    from robokit.description.loading import load
    from robokit.description.robot import Robot

    if convention not in ("standard", "modified"):
        raise InputError(f"convention: expected 'standard' or 'modified', got {convention!r}")
    robot = robot if isinstance(robot, Robot) else load(robot)
    axes = joint_axes(robot)
    n = len(axes)
    T_tip = robot.frame_pose(np.zeros(n))
    frames = _dh_frames(axes, T_tip[:3, 3], convention)
    base = frames[0]
    links = _links(robot, axes, frames, convention)
    tool = np.linalg.inv(frames[-1]) @ T_tip
    table = DHTable(robot.name, convention, tuple(links), np.asarray(robot.gravity, float), base, tool)
    residual = _check(robot, table, samples, rng)
    return URDFToDH(table, residual, samples)


def _links(robot: Robot, axes: list[tuple[np.ndarray, np.ndarray, str]], frames: list[np.ndarray],
           convention: str) -> list[DHLink]:
    import pinocchio as pin

    model = robot.model
    data = model.createData()
    pin.forwardKinematics(model, data, pin.neutral(model))
    links = []
    for i in range(len(axes)):
        T = np.linalg.inv(frames[i]) @ frames[i + 1]
        a, al, d, th = _params(T, convention)
        # the body moved by joint i+1 is attached to DH frame {i+1}: carry its inertia there
        Y = model.inertias[i + 1]
        T_dh_joint = np.linalg.inv(frames[i + 1]) @ data.oMi[i + 1].homogeneous
        R = T_dh_joint[:3, :3]
        # a massless body has no centre of mass (its rotational inertia is the same about any point)
        com = R @ Y.lever + T_dh_joint[:3, 3] if Y.mass > 0 else np.zeros(3)
        I = R @ Y.inertia @ R.T
        inertia = np.array([I[0, 0], I[1, 1], I[2, 2], I[0, 1], I[1, 2], I[0, 2]])
        lo, hi = robot.qlim[i]
        qlim = np.array([lo, hi]) if np.isfinite(lo) and np.isfinite(hi) else None
        links.append(DHLink(axes[i][2], _clean(a), _clean(al), _clean(d), _clean(th), qlim, float(Y.mass),
                            np.array([_clean(c) for c in com]), np.array([_clean(v) for v in inertia]),
                            name=robot.joint_names[i]))
    return links


def _check(robot: Robot, table: DHTable, samples: int, rng: int | np.random.Generator | None) -> float:
    rng = np.random.default_rng(rng)
    worst = 0.0
    for _ in range(int(samples)):
        q = robot.random_configuration(rng)
        err = float(np.abs(table.fk(q) - robot.frame_pose(q)).max())
        if not np.isfinite(err):  # Python's max() would drop a NaN
            return float("inf")
        worst = max(worst, err)
    return worst


def format_dh_table(table: DHTable, digits: int = 5) -> str:
    """The table as the lecture writes it: ``table.to_text(digits)``.

    One row per joint (lengths in m, angles in degrees, ``+ q`` on the joint variable), then the
    base and tool transforms when they are not the identity (without them the table alone does not
    reproduce the robot's tool pose).

    Parameters
    ----------
    table : DHTable
        The table to print.
    digits : int, optional
        Decimals of the lengths in m (default 5); angles in degrees get ``digits − 2``.

    Returns
    -------
    str
        The printable table, one line per row.

    Examples
    --------
    >>> print(format_dh_table(rk.load("twolink").dh, 3))
    # twolink: standard DH
    i  joint  a_i [m]  alpha_i [deg]  d_i [m]  theta_i [deg]
    -  -----  -------  -------------  -------  -------------
    1      R    1.000            0.0    0.000        0.0 + q
    2      R    0.800            0.0    0.000        0.0 + q
    """
    return table.to_text(digits)


def urdf_to_dh_text(robot: Robot, convention: str = "standard", as_yaml: bool = True) -> str:
    """Text for ``robokit convert``: the YAML file (refused for an inexact table), or the printed
    table with its residual (printed either way, an inexact one marked as such)."""
    res = dh_from_urdf(robot, convention)
    if as_yaml and not res.exact:
        raise InputError(f"{robot.name}: the DH table reproduces the URDF only to {res.residual:.2e} "
                         f"(> 1e-9); not written")
    if as_yaml:
        # the residual of the table as written: the file writes an angle within 1e-9° of a whole degree as
        # that degree, which moves a file's truncated π/2 (the myCobot 280's 1.5708) by up to 1e-11 m
        import yaml

        body = res.table.to_yaml_str("deg")
        written = _check(robot, DHTable.from_dict(yaml.safe_load(body)), res.samples, 0)
        if written > 1e-9:
            raise InputError(f"{robot.name}: the DH table as written reproduces the URDF only to {written:.2e} "
                             f"(> 1e-9); not written")
        header = (f"# DH table of {robot.name} (root → {robot.tip}), extracted by robokit; "
                  f"FK matches the URDF to {max(written, res.residual):.1e} at {res.samples} random configurations\n")
        return header + body
    verdict = "" if res.exact else " — NOT exact (> 1e-9): this table only approximates the URDF"
    return format_dh_table(res.table) + f"# FK residual vs the URDF: {res.residual:.1e}{verdict}\n"

# Former names (before the X_from_Y rule): they warn and call the new function.
urdf_to_dh = deprecated_alias(dh_from_urdf, "urdf_to_dh")
