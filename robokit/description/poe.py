r"""URDF → product-of-exponentials parameters (Modern Robotics form).

For a serial chain root → tip with n one-degree-of-freedom joints (revolute, prismatic,
continuous), at the zero configuration:

* ``M`` — the tip frame's pose in the root frame;
* ``Slist`` (6×n) — the joints' screw axes in the root frame, columns ``(ω, v)``, with
  ``v = −ω × p`` for a revolute joint through the point p and ``(0, v̂)`` for a prismatic one;
  so that ``T(θ) = e^{[S₁]θ₁} ⋯ e^{[Sₙ]θₙ} M`` (Lecture 4, Modern Robotics ch. 4);
* ``Blist = Ad_{M⁻¹} Slist`` — the same axes in the tip frame;
* ``Mlist`` (n+1) — ``Mlist[i]`` is the pose of the centre-of-mass frame {i+1} of link i+1
  in frame {i} (frame {0} = the root, frame {n+1} = the tip); ``Glist`` (n) — each link's
  6×6 spatial inertia ``[[I_c, 0], [0, m 1]]`` in its centre-of-mass frame.

The centre-of-mass frame of a link is parallel to its joint frame (so ``I_c`` need not be
diagonal). A link's inertia is everything rigidly attached to its joint — Pinocchio merges
fixed-joint children and (through ``buildReducedModel``) locked joints' bodies — so the
Newton–Euler torques from ``Mlist``/``Glist`` equal ``pinocchio.rnea`` on the chain (plus
``armature · q̈`` when the joints have a reflected rotor inertia, which no link inertia can hold).
Twists, wrenches and spatial inertias are angular first.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import ArrayLike
from robokit.spatial import lie
from robokit.description.frames import frame_index
from robokit.errors import InputError


__all__ = ["PoEParams", "poe_from_model"]


@dataclass(frozen=True)
class PoEParams:
    """Product-of-exponentials parameters of a serial chain (see the module docstring).

    ``T(θ) = e^{[S₁]θ₁} ⋯ e^{[Sₙ]θₙ} M = M e^{[B₁]θ₁} ⋯ e^{[Bₙ]θₙ}`` (Modern Robotics ch. 4).

    Attributes
    ----------
    M : numpy.ndarray, shape (4, 4)
        Tip pose in the root frame at q = 0 (m).
    Slist : numpy.ndarray, shape (6, n)
        Space screw axes, one column per joint, rows ``(ω, v)``, root frame.
    Blist : numpy.ndarray, shape (6, n)
        Body screw axes ``Ad_{M⁻¹} Slist``, tip frame.
    Mlist : numpy.ndarray, shape (n + 1, 4, 4)
        ``Mlist[i]``: pose of link i+1's centre-of-mass frame in the previous one; ``Mlist[n]``
        the tip in link n's centre-of-mass frame.
    Glist : numpy.ndarray, shape (n, 6, 6)
        Spatial inertia ``[[I_c, 0], [0, m 1]]`` of each link in its centre-of-mass frame
        (kg·m², kg).
    joint_names : tuple of str
        The n joint names, root to tip.
    tip : str
        Name of the tip frame.
    qlim : numpy.ndarray, shape (n, 2)
        Joint limits (rad or m; ±inf for continuous joints).
    gravity : numpy.ndarray, shape (3,)
        Gravity acceleration in the root frame, m/s².
    armature : numpy.ndarray, shape (n,)
        Each joint's reflected rotor inertia (Pinocchio's ``model.armature``: an SRDF's rotor
        parameters, Drake's transmissions, MJCF's armature; kg·m², kg for a prismatic joint),
        0 for most robots (and when not given). ``Mlist``/``Glist`` hold the rigid bodies only: Pinocchio's ``rnea``
        on the chain is their Newton–Euler torques plus ``armature · q̈`` (and ``crba`` their
        mass matrix plus ``diag(armature)``).

    Examples
    --------
    >>> poe = rk.load("twolink").poe
    >>> poe.Slist.shape, poe.M[:3, 3].round(4).tolist()
    ((6, 2), [1.8, 0.0, 0.0])
    """

    M: np.ndarray
    Slist: np.ndarray
    Blist: np.ndarray
    Mlist: np.ndarray
    Glist: np.ndarray
    joint_names: tuple
    tip: str
    qlim: np.ndarray
    gravity: np.ndarray
    armature: np.ndarray = None  # type: ignore[assignment]  # None: zeros (n,), set in __post_init__

    def __post_init__(self) -> None:
        if self.armature is None:  # built without one (PoEParams was constructed without armature before)
            object.__setattr__(self, "armature", np.zeros(self.Slist.shape[1]))

    @property
    def n(self) -> int:
        """Number of joints n (columns of ``Slist``)."""
        return self.Slist.shape[1]

    def to_json_dict(self) -> dict:
        """The JSON object of ``robokit convert IN.urdf -o OUT.json`` (the PoE JSON format page of the
        documentation).

        Returns
        -------
        dict
            ``M`` (4×4), ``Slist``, ``Blist`` (6×n), ``Mlist`` (n+1 4×4), ``Glist`` (n 6×6) as nested
            lists, ``joint_names`` (n), ``tip``, ``armature`` (n; Pinocchio's ``rnea`` is the
            Newton–Euler torques of ``Mlist``/``Glist`` plus ``armature · q̈``).

        Examples
        --------
        >>> d = rk.load("twolink").poe.to_json_dict()
        >>> sorted(d), len(d["Mlist"]), d["tip"], d["armature"]
        (['Blist', 'Glist', 'M', 'Mlist', 'Slist', 'armature', 'joint_names', 'tip'], 3, 'tool', [0.0, 0.0])
        """
        return {
            "M": self.M.tolist(),
            "Slist": self.Slist.tolist(),
            "Blist": self.Blist.tolist(),
            "Mlist": [m.tolist() for m in self.Mlist],
            "Glist": [g.tolist() for g in self.Glist],
            "joint_names": list(self.joint_names),
            "tip": self.tip,
            "armature": self.armature.tolist(),
        }


def poe_from_model(model: Any, tip: str, gravity: ArrayLike | None = None) -> PoEParams:
    """PoE parameters of a Pinocchio ``model`` that is a serial chain of 1-dof joints.

    The space screw axes are the columns of the world Jacobian at the neutral configuration
    (reordered to ``(ω, v)``), ``Blist = Ad_{M⁻¹} Slist``; ``Mlist``/``Glist`` come from the joints'
    inertias so that Newton–Euler on them equals ``pinocchio.rnea`` (module docstring).

    Parameters
    ----------
    model : pinocchio.Model
        A model whose joints 1..n form one chain in order (as made by
        :func:`robokit.description.builder.serial_chain`).
    tip : str
        Name of the tip frame (must exist in the model).
    gravity : array_like, shape (3,), optional
        Gravity in the root frame, m/s² (default: the model's gravity).

    Returns
    -------
    PoEParams
        ``M``, ``Slist``, ``Blist``, ``Mlist``, ``Glist``, joint names, limits, gravity and the joints'
        armature.

    Examples
    --------
    >>> robot = rk.load("twolink")
    >>> poe = poe_from_model(robot.model, robot.tip)
    >>> poe.Slist[:, 1].round(4).tolist()    # joint 2: ω = z, through (1, 0, 0): v = −ω × p
    [0.0, 0.0, 1.0, 0.0, -1.0, 0.0]
    """
    import pinocchio as pin

    if not model.existFrame(tip):
        raise InputError(f"tip: no frame {tip!r} in the model")
    n = model.njoints - 1
    if model.nv != n:
        raise InputError(f"model: expected {n} one-dof joints, got nv = {model.nv}")
    for j in range(1, model.njoints):
        if model.parents[j] != j - 1:
            raise InputError("model: joints do not form one chain in order")
    data = model.createData()
    q0 = pin.neutral(model)
    pin.forwardKinematics(model, data, q0)
    pin.computeJointJacobians(model, data, q0)
    pin.updateFramePlacements(model, data)
    fid = frame_index(model, tip)
    M = data.oMf[fid].homogeneous.copy()
    Jw = np.asarray(data.J).reshape(6, -1).copy()  # world-frame joint Jacobian at zero: columns are space screws (v, ω)
    Slist = np.vstack([Jw[3:], Jw[:3]])
    Blist = lie.adjoint(lie.inv(M)) @ Slist
    Mlist = np.empty((n + 1, 4, 4))
    Glist = np.zeros((n, 6, 6))
    prev = np.eye(4)
    for i in range(n):
        j = i + 1
        Y = model.inertias[j]
        T_com = data.oMi[j].homogeneous.copy()
        T_com[:3, 3] = T_com[:3, :3] @ Y.lever + T_com[:3, 3]
        Mlist[i] = lie.inv(prev) @ T_com
        prev = T_com
        Glist[i, :3, :3] = Y.inertia  # about the centre of mass, joint-frame axes
        Glist[i, 3:, 3:] = Y.mass * np.eye(3)
    Mlist[n] = lie.inv(prev) @ M
    names = tuple(model.names[j] for j in range(1, model.njoints))
    qlim = np.empty((n, 2))
    for i in range(n):
        jm = model.joints[i + 1]
        if jm.nq == 1:
            qlim[i] = model.lowerPositionLimit[jm.idx_q], model.upperPositionLimit[jm.idx_q]
        else:  # continuous joint: an angle with no limit
            qlim[i] = -np.inf, np.inf
    g = np.array(model.gravity.linear) if gravity is None else np.asarray(gravity, dtype=float)
    armature = np.array([float(model.armature[model.joints[j].idx_v]) for j in range(1, model.njoints)])
    return PoEParams(M, Slist, Blist, Mlist, Glist, names, tip, qlim, g, armature)
