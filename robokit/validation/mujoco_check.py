r"""MuJoCo as a second, independent reference for robokit's kinematics and dynamics.

A robot is written as MJCF (:func:`robokit.description.mjcf_write.mjcf_from_robot`) — or an MJCF
file is taken as it is — and compiled by MuJoCo; at random states ``(q, q̇, q̈)`` MuJoCo's

* body and site poses (``mj_kinematics``: ``xpos``/``xmat``, ``site_xpos``/``site_xmat``),
* mass matrix (``mj_fullM`` after ``mj_forward``), which includes the joints' armature,
* bias forces ``qfrc_bias = c(q, q̇) + g(q)``,
* inverse dynamics ``qfrc_inverse`` (``mj_inverse``), ``M q̈ + c + g + b q̇`` with the
  joints' damping ``b`` (MuJoCo's passive force is ``−b q̇``),

are compared with Pinocchio's (the :class:`robokit.Robot` methods) and with the course
code (:func:`robokit.mass_matrix` and :func:`robokit.inverse_dynamics` on ``robot.poe``),
with the same gravity and contacts and constraints disabled. Armature and damping are those
of :func:`~robokit.description.mjcf_write.joint_armature_damping` (``G² Jm`` and ``G² B`` for a
DH file), added to the references where they do not already include them.

MuJoCo's compiler refuses some inertials (a moving body with no mass, a point mass, a
tensor that breaks ``A + B ≥ C``); the MJCF writer stores the exact values in
``<custom><numeric>`` and :func:`mujoco_model` puts them into the compiled ``MjModel``
(``body_mass``, ``body_ipos``, ``body_iquat``, ``body_inertia``) before comparing; the bodies
concerned are listed in the result. MuJoCo is an optional dependency (the ``mujoco`` extra,
``pip install 'robokit[mujoco]'``); :func:`import_mujoco` returns None when it is absent, and the
comparisons raise robokit's one-line ``MissingExtraError`` naming the extra.
"""
from __future__ import annotations

import os
from dataclasses import dataclass, field
from types import ModuleType
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import ArrayLike
from robokit.errors import InputError

if TYPE_CHECKING:
    from robokit.description.dh import DHTable
    from robokit.description.robot import Robot

__all__ = ["import_mujoco", "mujoco_model", "compare_with_mujoco", "MujocoComparison"]


def import_mujoco() -> ModuleType | None:
    """The ``mujoco`` module, or None if it is not installed.

    Returns
    -------
    module or None
        ``mujoco`` when it imports.
    """
    try:
        import mujoco
    except ImportError:
        return None
    return mujoco


def _require() -> ModuleType:
    from robokit._optional import require

    mj: ModuleType = require("mujoco", "MuJoCo comparisons")
    return mj


def _quat_from_matrix(R: ArrayLike) -> np.ndarray:
    import pinocchio as pin

    x, y, z, w = pin.Quaternion(np.asarray(R, dtype=float)).coeffs()
    return np.array([w, x, y, z])


def mujoco_model(mjcf_text: str) -> tuple[Any, list[str]]:
    """Compile MJCF text with MuJoCo, restore robokit's exact inertials, disable contacts.

    Parameters
    ----------
    mjcf_text : str
        An MJCF document (mesh files referenced by absolute path).

    Returns
    -------
    model : mujoco.MjModel
        With ``opt.disableflags`` including contact and constraint.
    restored : list of str
        Bodies whose inertial was set from ``<custom><numeric name="robokit_inertial:BODY">``.

    Examples
    --------
    >>> from robokit.description.mjcf_write import mjcf_from_robot
    >>> m, restored = mujoco_model(mjcf_from_robot(rk.load("twolink"))[0])
    >>> m.nq, restored
    (2, ['link_1', 'link_2'])
    """
    mj = _require()
    from robokit.description.mjcf import CUSTOM_INERTIAL_PREFIX

    m = mj.MjModel.from_xml_string(mjcf_text)
    restored = []
    for i in range(m.nnumeric):
        name = mj.mj_id2name(m, mj.mjtObj.mjOBJ_NUMERIC, i) or ""
        if not name.startswith(CUSTOM_INERTIAL_PREFIX):
            continue
        body = name[len(CUSTOM_INERTIAL_PREFIX):]
        bid = mj.mj_name2id(m, mj.mjtObj.mjOBJ_BODY, body)
        if bid < 0:
            continue
        adr, size = m.numeric_adr[i], m.numeric_size[i]
        d = np.array(m.numeric_data[adr: adr + size])
        mass, c, (xx, yy, zz, xy, xz, yz) = d[0], d[1:4], d[4:10]
        ev, V = np.linalg.eigh(np.array([[xx, xy, xz], [xy, yy, yz], [xz, yz, zz]]))
        if np.linalg.det(V) < 0:
            V[:, 0] = -V[:, 0]
        m.body_mass[bid] = mass
        m.body_ipos[bid] = c
        m.body_iquat[bid] = _quat_from_matrix(V)
        m.body_inertia[bid] = np.maximum(ev, 0.0)  # zero moments come out as ±1e-17
        restored.append(body)
    m.opt.disableflags |= int(mj.mjtDisableBit.mjDSBL_CONTACT) | int(mj.mjtDisableBit.mjDSBL_CONSTRAINT)
    return m, restored


@dataclass
class MujocoComparison:
    """Largest absolute differences (max entry over the samples) between MuJoCo and robokit.

    What :func:`compare_with_mujoco` returns.

    Attributes
    ----------
    robot : str
        The robot's name.
    samples : int
        Number of states compared.
    fk : float
        Body/site positions (m) and rotation matrices.
    M_pinocchio, M_course : float
        Mass matrix, against Pinocchio's and against the course's (kg·m²).
    bias_pinocchio, bias_course : float
        Bias forces ``c + g`` (N·m).
    inverse_pinocchio, inverse_course : float
        Inverse dynamics torques (N·m).
    frames : int
        How many bodies/sites were compared.
    restored : list of str
        Bodies whose exact inertial was put into the MjModel.
    worst : float
        Property: the largest of all the differences.
    """

    robot: str
    samples: int
    fk: float
    M_pinocchio: float
    M_course: float
    bias_pinocchio: float
    bias_course: float
    inverse_pinocchio: float
    inverse_course: float
    frames: int
    restored: list = field(default_factory=list)

    @property
    def worst(self) -> float:
        """The largest of all the differences."""
        return max(self.fk, self.M_pinocchio, self.M_course, self.bias_pinocchio, self.bias_course,
                   self.inverse_pinocchio, self.inverse_course)


def compare_with_mujoco(robot: Robot | DHTable | str | os.PathLike[str], mjcf: str | None = None, samples: int = 20,
                        rng: int | np.random.Generator | None = None) -> MujocoComparison:
    """Compare MuJoCo with Pinocchio and the course code on one robot (see the module docstring).

    Parameters
    ----------
    robot : Robot or str
        A :class:`robokit.Robot` or anything :func:`robokit.load` reads.
    mjcf : str, optional
        MJCF text of the same robot (default: written by ``mjcf_from_robot``). Its joints are
        matched to the robot's by name.
    samples : int
        Number of random states ``(q, q̇, q̈)``: q uniform in the limits, q̇ and q̈ standard
        normal.
    rng : numpy Generator or seed, optional
        Draws the sampled states (None: fresh entropy).

    Returns
    -------
    MujocoComparison

    Raises
    ------
    MissingExtraError
        MuJoCo not installed (an ``ImportError`` naming the ``mujoco`` extra).
    ValueError
        The MJCF's joints do not match the robot's.

    Examples
    --------
    MuJoCo and robokit agree on the planar arm to rounding:

    >>> bool(compare_with_mujoco("twolink", samples=5, rng=0).worst < 1e-9)
    True
    """
    mj = _require()
    from robokit.description.mjcf_write import joint_armature_damping, mjcf_from_robot
    from robokit.description.loading import load
    from robokit.description.robot import Robot
    from robokit.dynamics.newton_euler import inverse_dynamics, mass_matrix

    if not isinstance(robot, Robot):
        robot = load(robot)
    rng = np.random.default_rng(rng)
    text = mjcf if mjcf is not None else mjcf_from_robot(robot)[0]
    m, restored = mujoco_model(text)
    d = mj.MjData(m)
    n = robot.n
    if m.nv != n:
        raise InputError(f"mjcf: MuJoCo has {m.nv} degrees of freedom, {robot.name} has {n} joints")
    qadr_list, dadr_list = [], []
    for jn in robot.joint_names:
        jid = mj.mj_name2id(m, mj.mjtObj.mjOBJ_JOINT, jn)
        if jid < 0:
            raise InputError(f"mjcf: no joint {jn!r} in the MuJoCo model")
        qadr_list.append(m.jnt_qposadr[jid])
        dadr_list.append(m.jnt_dofadr[jid])
    qadr, dadr = np.array(qadr_list), np.array(dadr_list)
    arm, damp = joint_armature_damping(robot)
    idx = [robot.model.joints[j].idx_v for j in range(1, robot.model.njoints)]
    arm_pin = arm - np.array(robot.model.armature)[idx]  # what Pinocchio's crba/rnea do not already hold
    poe = robot.poe
    g = robot.gravity
    if not np.allclose(m.opt.gravity, g, rtol=0, atol=1e-12):
        raise InputError(f"mjcf: MuJoCo gravity {m.opt.gravity.tolist()} differs from the robot's {g.tolist()}")

    frame_names = {f.name for f in robot.model.frames}
    bodies = [(b, mj.mj_id2name(m, mj.mjtObj.mjOBJ_BODY, b)) for b in range(1, m.nbody)]
    bodies = [(b, nm) for b, nm in bodies if nm in frame_names]
    sites = []
    for s in range(m.nsite):
        nm = mj.mj_id2name(m, mj.mjtObj.mjOBJ_SITE, s) or ""
        if nm in frame_names:
            sites.append((s, nm))
        elif nm == f"{robot.tip}_site":
            sites.append((s, robot.tip))

    err = dict(fk=0.0, Mp=0.0, Mc=0.0, bp=0.0, bc=0.0, ip=0.0, ic=0.0)
    M_mj = np.zeros((m.nv, m.nv))
    zeros6 = np.zeros(6)
    for _ in range(samples):
        q = robot.random_configuration(rng)
        v = rng.standard_normal(n)
        a = rng.standard_normal(n)
        d.qpos[:] = 0.0
        d.qpos[qadr] = q
        d.qvel[:] = 0.0
        d.qvel[dadr] = v
        mj.mj_forward(m, d)
        mj.mj_fullM(m, d, M_mj)
        M = M_mj[np.ix_(dadr, dadr)]
        bias = d.qfrc_bias[dadr].copy()
        poses = robot.frame_poses(q)
        for b, nm in bodies:
            T = poses[nm]
            err["fk"] = max(err["fk"], np.abs(d.xpos[b] - T[:3, 3]).max(),
                            np.abs(d.xmat[b].reshape(3, 3) - T[:3, :3]).max())
        for s, nm in sites:
            T = poses[nm]
            err["fk"] = max(err["fk"], np.abs(d.site_xpos[s] - T[:3, 3]).max(),
                            np.abs(d.site_xmat[s].reshape(3, 3) - T[:3, :3]).max())
        d.qacc[:] = 0.0
        d.qacc[dadr] = a
        mj.mj_inverse(m, d)
        tau = d.qfrc_inverse[dadr].copy()

        M_pin = robot.crba(q) + np.diag(arm_pin)
        M_crs = mass_matrix(q, poe.Mlist, poe.Glist, poe.Slist) + np.diag(arm)
        b_pin = robot.nonlinear_effects(q, v)
        b_crs = inverse_dynamics(q, v, np.zeros(n), g, zeros6, poe.Mlist, poe.Glist, poe.Slist)
        t_pin = robot.rnea(q, v, a) + arm_pin * a + damp * v
        t_crs = inverse_dynamics(q, v, a, g, zeros6, poe.Mlist, poe.Glist, poe.Slist) + arm * a + damp * v
        for key, x, y in (("Mp", M, M_pin), ("Mc", M, M_crs), ("bp", bias, b_pin), ("bc", bias, b_crs),
                          ("ip", tau, t_pin), ("ic", tau, t_crs)):
            err[key] = max(err[key], float(np.abs(x - y).max()))
    return MujocoComparison(robot.name, samples, err["fk"], err["Mp"], err["Mc"], err["bp"], err["bc"], err["ip"],
                            err["ic"], len(bodies) + len(sites), restored)
