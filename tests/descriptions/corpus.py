r"""The description corpus: every robot file robokit can be handed, through load → FK, J, RNEA, M,
against the format's own engine.

Run ``python -m tests.descriptions.corpus`` (``--markdown`` for the table of docs/loading.md);
``tests/descriptions/test_corpus.py`` runs the same and fails on any disagreement.

What is in it
    * every description vendored under ``tests/data/`` (found by suffix, so files added later join:
      ``.urdf``; ``.xacro`` — a ``*.urdf.xacro``, or any ``.xacro`` with a sidecar; ``.xml`` with a
      ``<mujoco>`` root; ``.sdf``). A format robokit has no loader for is skipped with the reason.
      A sidecar ``<file>.corpus.yaml`` (:func:`sidecar`) says what the file needs: xacro argument
      sets (one row each), the tip(s) of a tree, ``package_dirs``, an SDF's URDF twin and why
      PyBullet cannot read it — or ``skip:`` with the reason a file is not a robot on its own (an
      included part, an end effector without a moving joint). A file without a sidecar that does
      not load is a failure: discovery never drops a robot silently;
    * the example-robot-data robots robokit loads with its default tip (:data:`ERD_ROBOTS`;
      ``--discover-erd`` re-derives the list);
    * the fixed-base serial arms of ``pybullet_data`` (:data:`PYBULLET_DATA`).

The engines (each independent of robokit; the chain's joints by name, the others locked at zero —
in MuJoCo at ``qpos0``, where the file draws them)
    * **Pinocchio on the raw file** (URDF, the xacro program's expansion, example-robot-data's own
      model with the armature its SRDF gives; a URDF in Drake's dialect with the reflected inertia of
      its transmissions as armature, :func:`drake_urdf_reflected_inertia`): the whole tree, ``framesForwardKinematics``,
      ``computeFrameJacobian`` (LOCAL_WORLD_ALIGNED), ``rnea`` and ``crba``, the chain's rows and
      columns taken out — no reduction;
    * **PyBullet** (URDF and xacro with visuals and collisions stripped, ``useFixedBase``,
      ``URDF_USE_INERTIA_FROM_FILE``; SDF with ``loadSDF``): ``calculateMassMatrix``,
      ``calculateInverseDynamics``, ``calculateJacobian`` and ``getLinkState(...,
      computeForwardKinematics=1)``. Two conventions of PyBullet 3.2.7, measured: the link frame it
      returns (``worldLinkFramePosition``/``Orientation``) is rounded to float32 (1.261 comes back
      1.2610000371932983), so the link frame is rebuilt from the centre-of-mass pose (double) and the
      link's local inertial frame; ``calculateJacobian``'s ``localPosition`` is taken about the
      URDF link frame's origin (its guide says the centre of mass; 2e-16 agreement with Pinocchio
      at the origin, 2e-2 off at the centre of mass). For example-robot-data, PyBullet reads the
      URDF alone: the SRDF's armature (``rotorInertia · rotorGearRatio²``) is added to its M and
      ``armature · q̈`` to its torques. Everything is compared in the world frame, where robokit
      reports: an SDF model's ``<pose>`` places the robot for both (pybullet_data's kuka
      ``model.sdf`` stands at 0 −2.3 0.7; FK relative to the base link would be off by that);
    * **Pinocchio on an SDF's URDF twin** (the sidecar's ``twin``), the joints' armature set to
      Drake's ``drake:rotor_inertia · drake:gear_ratio²`` read from the SDF's text, as Drake adds
      it (:func:`drake_reflected_inertia`);
    * **MuJoCo** (MJCF): ``mj_fullM`` and ``mj_inverse`` (armature included) with contacts,
      constraints and passive forces (damping, springs) disabled — robokit's dynamics are
      rigid-body plus armature — ``mj_jacBody``/``mj_jacSite`` and ``xpos``/``xmat``.

Errors are relative to each quantity's scale over the samples (FK position to the largest
distance of the tip from the base, rotation absolute; J, τ and M to their largest entry), and
must be at most :data:`TOLERANCE`.
"""
from __future__ import annotations

import argparse
import datetime
import functools
import os
import platform
import re
import sys
import tempfile
import time
import types
import warnings
import xml.etree.ElementTree as ET
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Callable

import numpy as np

ROOT = Path(__file__).resolve().parents[2]
DATA = ROOT / "tests" / "data"
#: Largest relative error accepted, every quantity, every engine.
TOLERANCE = 1e-9
#: Random states per robot and engine.
SAMPLES = 4
SEED = 0

#: example-robot-data robots robokit loads with its default tip (found by ``--discover-erd``).
ERD_ROBOTS = ("anymal_kinova", "asr_twodof", "b1_z1", "bluevolta_bravo7_gripper", "bluevolta_bravo7_no_ee",
              "borinot", "bravo7_gripper", "bravo7_no_ee", "double_pendulum", "double_pendulum_continuous",
              "double_pendulum_simple", "falcon_bravo7_gripper", "falcon_bravo7_no_ee", "finger_edu", "hextilt",
              "kinova", "panda", "panda_collision", "so100", "so101", "talos_arm", "tiago_no_hand", "ur10",
              "ur10_limited", "ur3", "ur3_gripper", "ur3_limited", "ur5", "ur5_gripper", "ur5_limited", "xarm7",
              "z1")

#: The fixed-base serial arms of pybullet_data (path under pybullet_data, tip or None).
PYBULLET_DATA = (
    ("kuka_iiwa/model.urdf", None), ("kuka_iiwa/model_vr_limits.urdf", None), ("kuka_iiwa/model_for_sdf.urdf", None),
    ("xarm/xarm6_robot.urdf", None), ("xarm/xarm6_robot_white.urdf", None), ("franka_panda/panda.urdf", None),
    ("TwoJointRobot_w_fixedJoints.urdf", None), ("TwoJointRobot_wo_fixedJoints.urdf", None),
    ("mjcf/reacher.xml", None), ("mjcf/pusher.xml", None), ("mjcf/striker.xml", None), ("mjcf/thrower.xml", None),
    ("kuka_iiwa/model.sdf", None),
)

#: (source, engine) → why it does not agree yet. An entry that agrees fails the test (remove it).
KNOWN: dict[tuple[str, str], str] = {
}

QUANTITIES = ("FK", "J", "RNEA", "M")


# ------------------------------------------------------------------------------------- engines
Quantities = tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]  # T (4, 4), J (6, n) ω first, τ (n,), M (n, n)


class PinocchioEngine:
    """Pinocchio on the whole model as the file describes it; the chain's entries taken out."""

    name = "Pinocchio"

    def __init__(self, model: Any, robot: Any, fixed: dict[str, float] | None = None) -> None:
        import pinocchio as pin

        self.pin, self.model, self.data = pin, model, model.createData()
        self.joints = [model.joints[model.getJointId(jn)] for jn in robot.joint_names]
        #: joints off the chain not at 0: (joint model, value) — a URDF's mimic joints (:func:`mimic_positions`)
        self.fixed = [(model.joints[model.getJointId(jn)], v) for jn, v in (fixed or {}).items()
                      if model.existJointName(jn) and jn not in robot.joint_names]
        self.iv = [jm.idx_v for jm in self.joints]
        body = pin.FrameType.BODY
        self.fid = (model.getFrameId(robot.tip, body) if model.existFrame(robot.tip, body)
                    else [k for k, f in enumerate(model.frames) if f.name == robot.tip][0])
        self.model.gravity.linear = np.asarray(robot.gravity, dtype=float)

    def __call__(self, q: np.ndarray, dq: np.ndarray, ddq: np.ndarray) -> Quantities:
        pin, model, data = self.pin, self.model, self.data
        qf, v, a = pin.neutral(model), np.zeros(model.nv), np.zeros(model.nv)
        for jm, qi in self.fixed:
            qf[jm.idx_q:jm.idx_q + jm.nq] = [np.cos(qi), np.sin(qi)] if jm.nq == 2 else [qi]
        for jm, qi, dqi, ddqi in zip(self.joints, q, dq, ddq):
            if jm.nq == 2:  # continuous: (cos, sin)
                qf[jm.idx_q], qf[jm.idx_q + 1] = np.cos(qi), np.sin(qi)
            else:
                qf[jm.idx_q] = qi
            v[jm.idx_v], a[jm.idx_v] = dqi, ddqi
        pin.framesForwardKinematics(model, data, qf)
        T = data.oMf[self.fid].homogeneous.copy()
        J = pin.computeFrameJacobian(model, data, qf, self.fid, pin.LOCAL_WORLD_ALIGNED)[:, self.iv]
        tau = pin.rnea(model, data, qf, v, a)[self.iv]
        M = pin.crba(model, data, qf)
        M = np.triu(M) + np.triu(M, 1).T
        return T, np.vstack([J[3:], J[:3]]), tau, M[np.ix_(self.iv, self.iv)]


class _silent_fds:
    """Send what C code writes on fd 1 and 2 to /dev/null while active."""

    def __enter__(self) -> None:
        sys.stdout.flush()
        sys.stderr.flush()
        self.saved = [os.dup(1), os.dup(2)]
        null = os.open(os.devnull, os.O_WRONLY)
        os.dup2(null, 1)
        os.dup2(null, 2)
        os.close(null)

    def __exit__(self, *exc: Any) -> None:
        for fd, saved in zip((1, 2), self.saved):
            os.dup2(saved, fd)
            os.close(saved)


def _stripped_urdf(text: str, folder: Path) -> Path:
    """The URDF without visuals and collisions (PyBullet reads inertias from the file, so its
    geometry only costs time and prints mesh warnings) nor ``<gazebo>`` elements (simulator settings
    PyBullet does not use; its importer 3.2.7 refuses the whole file on Kinova's Robotiq 2F-85
    ``<gazebo reference=...><material>Gazebo/Black</material></gazebo>``: XML_ERROR_PARSING_ATTRIBUTE),
    one element a line: PyBullet 3.2.7's XML reader refuses some long one-line files
    ("XML_ERROR_PARSING", line 1; the xacro program's expansion of Interbotix's vx300s written by
    ``ET.tostring``, 15 kB)."""
    root = ET.fromstring(text)
    for el in root.iter("link"):
        for tag in ("visual", "collision"):
            for g in el.findall(tag):
                el.remove(g)
    for g in root.findall("gazebo"):
        root.remove(g)
    ET.indent(root)
    path = folder / "robot.urdf"
    path.write_text(ET.tostring(root, encoding="unicode"))
    return path


def pybullet_reading(text: str) -> tuple[str, list[str]]:
    """The URDF as PyBullet 3.2.7's importer reads it, and what it changed: a link without an
    ``<inertial>`` gets 1 kg and the identity inertia (the URDF spec: no mass), and a link whose
    principal moments break the triangle inequality gets a zero inertia, its mass kept
    (``BulletUrdfImporter.cpp``: "Bad inertia tensor properties, setting inertia to zero")."""
    root = ET.fromstring(text)
    notes = []
    for el in root.iter("link"):
        ine = el.find("inertial")
        if ine is None:
            el.append(ET.fromstring('<inertial><mass value="1"/>'
                                    '<inertia ixx="1" iyy="1" izz="1" ixy="0" ixz="0" iyz="0"/></inertial>'))
            notes.append(f"{el.get('name')}: no <inertial>, 1 kg")
            continue
        tensor = ine.find("inertia")
        if tensor is None:
            continue
        g = {k: float(tensor.get(k, 0.0)) for k in ("ixx", "iyy", "izz", "ixy", "ixz", "iyz")}
        I = np.array([[g["ixx"], g["ixy"], g["ixz"]], [g["ixy"], g["iyy"], g["iyz"]], [g["ixz"], g["iyz"], g["izz"]]])
        lam = np.sort(np.linalg.eigvalsh(I))
        if lam[0] + lam[1] < lam[2]:
            for k in g:
                tensor.set(k, "0")
            notes.append(f"{el.get('name')}: triangle inequality broken, inertia 0")
    return ET.tostring(root, encoding="unicode"), notes


def _pose(p: Any, pos: Any, quat: Any) -> np.ndarray:
    T = np.eye(4)
    T[:3, :3] = np.array(p.getMatrixFromQuaternion(quat)).reshape(3, 3)
    T[:3, 3] = pos
    return T


class PyBulletEngine:
    """PyBullet on a URDF (or SDF) file: its own parser and its own recursions."""

    name = "PyBullet"

    def __init__(self, path: Path, robot: Any, sdf: bool = False, armature: np.ndarray | None = None,
                 reading: tuple[Path, list[str]] | None = None, in_base: bool = False,
                 fixed: dict[str, float] | None = None) -> None:
        import pybullet as p

        #: Results in PyBullet's world frame (the default), where robokit reports too: both place the
        #: model where the file does (an SDF model's <pose>; a URDF's base at the origin). ``in_base``:
        #: relative to the base link instead, to hold an SDF with a model pose against a URDF twin.
        self.in_base = in_base

        #: (the file as PyBullet reads it, what its importer changed) when that is not the file
        self.reading = reading if reading and reading[1] else None

        self.p = p
        with _silent_fds():  # PyBullet prints its build time and importer warnings from C
            self.cid = p.connect(p.DIRECT)
            if sdf:
                self.body = p.loadSDF(str(path), physicsClientId=self.cid)[0]
            else:
                self.body = p.loadURDF(str(path), useFixedBase=True, flags=p.URDF_USE_INERTIA_FROM_FILE,
                                       physicsClientId=self.cid)
        self.gravity = np.asarray(robot.gravity, dtype=float)  # in robokit's world frame
        movable, names, links = [], {}, {}
        for i in range(p.getNumJoints(self.body, physicsClientId=self.cid)):
            info = p.getJointInfo(self.body, i, physicsClientId=self.cid)
            links[info[12].decode()] = i
            if info[2] in (p.JOINT_REVOLUTE, p.JOINT_PRISMATIC):
                names[info[1].decode()] = len(movable)
                movable.append(i)
        self.movable = movable
        self.dofs = [names[jn] for jn in robot.joint_names]
        #: joints off the chain not at 0 (a URDF's mimic joints, :func:`mimic_positions`): (dof, value)
        self.fixed = [(names[jn], v) for jn, v in (fixed or {}).items() if jn in names and jn not in robot.joint_names]
        base_name = p.getBodyInfo(self.body, physicsClientId=self.cid)[0].decode()
        self.tip = -1 if robot.tip == base_name else links[robot.tip]
        self.floating = sdf and p.getDynamicsInfo(self.body, -1, physicsClientId=self.cid)[0] != 0.0
        self.armature = armature
        self.dynamics = True  # False: M and τ not comparable (see _sdf_inertias)
        if sdf:
            self.dynamics = self._sdf_inertias(path, {**links, base_name: -1})

    def _sdf_inertias(self, path: Path, links: dict[str, int]) -> bool:
        """PyBullet's ``loadSDF`` keeps an SDF link's mass and inertial pose but not its inertia
        tensor (it puts a small sphere's there, 2/5·m·(0.1·scale)²·...): the file's moments are set
        back with ``changeDynamics`` — possible only when each tensor is diagonal in its inertial
        frame; False if one is not (M and τ are then not compared)."""
        p = self.p
        for el in ET.parse(path).getroot().iter("link"):
            ine = el.find("inertial/inertia")
            name = el.get("name", "")
            if ine is None or name not in links:
                continue
            value = {k: float(ine.findtext(k, "0")) for k in ("ixx", "iyy", "izz", "ixy", "ixz", "iyz")}
            if value["ixy"] or value["ixz"] or value["iyz"]:
                return False
            p.changeDynamics(self.body, links[name], localInertiaDiagonal=[value["ixx"], value["iyy"], value["izz"]],
                             physicsClientId=self.cid)
        return True

    def _link_frame(self, link: int) -> np.ndarray:
        p, cid = self.p, self.cid
        if link == -1:
            com = p.getBasePositionAndOrientation(self.body, physicsClientId=cid)
        else:
            st = p.getLinkState(self.body, link, computeForwardKinematics=1, physicsClientId=cid)
            com = (st[0], st[1])  # double; st[4], st[5] (the link frame) come back rounded to float32
        local = p.getDynamicsInfo(self.body, link, physicsClientId=cid)[3:5]
        return _pose(p, *com) @ np.linalg.inv(_pose(p, *local))

    def __call__(self, q: np.ndarray, dq: np.ndarray, ddq: np.ndarray) -> Quantities:
        p, cid = self.p, self.cid
        pos, vel, acc = (np.zeros(len(self.movable)) for _ in range(3))
        for k, v in self.fixed:
            pos[k] = v
        pos[self.dofs], vel[self.dofs], acc[self.dofs] = q, dq, ddq
        for k, i in enumerate(self.movable):
            p.resetJointState(self.body, i, float(pos[k]), physicsClientId=cid)
        base = self._link_frame(-1) if self.in_base else np.eye(4)
        Rb = base[:3, :3]
        Rc = _pose(p, *p.getBasePositionAndOrientation(self.body, physicsClientId=cid))[:3, :3]
        T = np.linalg.inv(base) @ self._link_frame(self.tip)
        lin, ang = p.calculateJacobian(self.body, self.tip, [0.0, 0.0, 0.0], pos.tolist(), [0.0] * len(pos),
                                       [0.0] * len(pos), physicsClientId=cid)
        off = 6 if self.floating else 0  # a floating base's six dofs come first
        R = Rb.T @ Rc  # PyBullet's Jacobian is in the axes of the base's centre-of-mass frame
        J = np.vstack([R @ np.array(ang)[:, off:], R @ np.array(lin)[:, off:]])[:, self.dofs]
        M = np.array(p.calculateMassMatrix(self.body, pos.tolist(), physicsClientId=cid))[off:, off:]
        # its inverse dynamics reads the gravity vector in those axes too
        p.setGravity(*(R.T @ np.asarray(self.gravity, dtype=float)), physicsClientId=cid)
        tau = np.array(p.calculateInverseDynamics(self.body, pos.tolist(), vel.tolist(), acc.tolist(),
                                                  physicsClientId=cid))[off:]
        M, tau = M[np.ix_(self.dofs, self.dofs)], tau[self.dofs]
        if not self.dynamics:
            M, tau = np.full_like(M, np.nan), np.full_like(tau, np.nan)
        if self.armature is not None:
            M = M + np.diag(self.armature)
            tau = tau + self.armature * ddq
        return T, J, tau, M

    def close(self) -> None:
        self.p.disconnect(physicsClientId=self.cid)


class MujocoEngine:
    """MuJoCo on an MJCF file: its compiler, its recursions, passive forces and contacts off."""

    name = "MuJoCo"

    def __init__(self, path: Path, robot: Any) -> None:
        import mujoco as mj

        self.mj = mj
        self.m = mj.MjModel.from_xml_path(str(path))
        bits = mj.mjtDisableBit
        for flag in ("mjDSBL_CONTACT", "mjDSBL_CONSTRAINT", "mjDSBL_PASSIVE", "mjDSBL_SPRING", "mjDSBL_DAMPER"):
            if hasattr(bits, flag):  # MuJoCo ≥ 3.3 splits PASSIVE into SPRING and DAMPER
                self.m.opt.disableflags |= int(getattr(bits, flag))
        self.d = mj.MjData(self.m)
        ids = [mj.mj_name2id(self.m, mj.mjtObj.mjOBJ_JOINT, jn) for jn in robot.joint_names]
        if min(ids) < 0:
            raise LookupError(f"MuJoCo has no joint of these names: {robot.joint_names}")
        self.qadr = [int(self.m.jnt_qposadr[j]) for j in ids]
        self.dadr = [int(self.m.jnt_dofadr[j]) for j in ids]
        self.body = mj.mj_name2id(self.m, mj.mjtObj.mjOBJ_BODY, robot.tip)
        self.site = mj.mj_name2id(self.m, mj.mjtObj.mjOBJ_SITE, robot.tip) if self.body < 0 else -1
        if self.body < 0 and self.site < 0:
            raise LookupError(f"MuJoCo has no body or site {robot.tip!r}")

    def __call__(self, q: np.ndarray, dq: np.ndarray, ddq: np.ndarray) -> Quantities:
        mj, m, d = self.mj, self.m, self.d
        d.qpos[:] = m.qpos0  # every other joint at qpos0 (a hinge or slide at its ref), as robokit locks them
        d.qvel[:] = 0.0
        d.qpos[self.qadr], d.qvel[self.dadr] = q, dq
        mj.mj_forward(m, d)  # (it overwrites qacc with the forward dynamics' answer)
        jacp, jacr = np.zeros((3, m.nv)), np.zeros((3, m.nv))
        T = np.eye(4)
        if self.body >= 0:
            T[:3, :3], T[:3, 3] = d.xmat[self.body].reshape(3, 3), d.xpos[self.body]
            mj.mj_jacBody(m, d, jacp, jacr, self.body)
        else:
            T[:3, :3], T[:3, 3] = d.site_xmat[self.site].reshape(3, 3), d.site_xpos[self.site]
            mj.mj_jacSite(m, d, jacp, jacr, self.site)
        M = np.zeros((m.nv, m.nv))
        if hasattr(d, "qM"):  # MuJoCo 3: mj_fullM(m, dst, qM); MuJoCo 4: mj_fullM(m, d, dst)
            mj.mj_fullM(m, M, d.qM)
        else:
            mj.mj_fullM(m, d, M)
        d.qacc[:] = 0.0
        d.qacc[self.dadr] = ddq
        mj.mj_inverse(m, d)
        J = np.vstack([jacr, jacp])[:, self.dadr]
        return T, J, d.qfrc_inverse[self.dadr].copy(), M[np.ix_(self.dadr, self.dadr)]


# ----------------------------------------------------------------------------------- the xacro program
#: Folders the stub ROS package lookup of :func:`xacro_program` searches.
PACKAGE_ROOTS = [DATA]


def _package_folder(name: str) -> str:
    manifests = [m for root in PACKAGE_ROOTS if root.is_dir() for m in sorted(root.rglob("package.xml"))]
    for manifest in manifests:
        try:
            if ET.parse(manifest).getroot().findtext("name", "").strip() == name:
                return str(manifest.parent)
        except ET.ParseError:
            continue
    raise LookupError(f"no package {name!r} under {', '.join(map(str, PACKAGE_ROOTS))}")


def xacro_program(path: Path, args: dict[str, str]) -> str:
    """The URDF the xacro program (PyPI's ``xacro``) expands ``path`` to, ROS 2's package lookup
    answered from the packages under ``tests/data`` (a stub ``ament_index_python``, for this
    process only). Each file and argument set is expanded once (both engines of a row read it)."""
    return _xacro_program(path, tuple(sorted(args.items())), tuple(PACKAGE_ROOTS))


@functools.lru_cache(maxsize=64)
def _xacro_program(path: Path, items: tuple[tuple[str, str], ...], roots: tuple[Path, ...]) -> str:
    # ``roots`` (PACKAGE_ROOTS) is only part of the cache key: a test points the lookup elsewhere
    if "ament_index_python" not in sys.modules:
        pkg, sub = types.ModuleType("ament_index_python"), types.ModuleType("ament_index_python.packages")
        sub.get_package_share_directory = _package_folder  # type: ignore[attr-defined]
        pkg.packages = sub  # type: ignore[attr-defined]
        sys.modules["ament_index_python"], sys.modules["ament_index_python.packages"] = pkg, sub
    import xacro
    from xacro import substitution_args

    # xacrodoc (pulled in by roboticstoolbox) replaces xacro's $(find) at import; whichever test ran
    # before in this process, $(find) here is the program's own lookup through the stub above
    saved = substitution_args._eval_find
    substitution_args._eval_find = _package_folder
    try:
        doc = xacro.process_file(str(path), mappings=dict(items))
    finally:
        substitution_args._eval_find = saved
    return doc.toxml()


# ------------------------------------------------------------------------------------- the cases
@dataclass
class Case:
    """One robot of the corpus: how robokit loads it and which engines it is held against."""

    label: str
    fmt: str
    source: str
    load: Callable[[], Any]
    engines: list[Callable[[Any, Path], Any]] = field(default_factory=list)
    skip: str = ""


@dataclass
class Row:
    """One robot against one engine: the largest relative error of each quantity."""

    label: str
    fmt: str
    source: str
    n: int
    engine: str
    errors: dict[str, float] = field(default_factory=dict)
    seconds: float = 0.0
    problem: str = ""  # a load or engine failure
    known: str = ""
    note: str = ""  # how the engine reads the file differently (PyBullet's importer), accounted for
    warned: tuple[str, ...] = ()  # links robokit warned about (PhysicalityWarning), from robot.notes

    @property
    def worst(self) -> float:
        return max(self.errors.values()) if self.errors else float("inf")

    @property
    def ok(self) -> bool:
        return not self.problem and self.worst <= TOLERANCE


def _quiet_load(*args: Any, **kw: Any) -> Any:
    import robokit

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return robokit.load(*args, **kw)


def _rel(path: Path) -> str:
    try:
        return str(path.relative_to(ROOT))
    except ValueError:
        return str(path)


def _named(name: str, make: Callable[[Any, Path], Any]) -> Callable[[Any, Path], Any]:
    make.engine_name = name  # type: ignore[attr-defined]  # for the row when building the engine fails
    return make


def _urdf_engines(text_of: Callable[[], str]) -> list[Callable[[Any, Path], Any]]:
    """Pinocchio and PyBullet on the URDF text, each with Drake's reflected inertia of the file's
    transmissions (:func:`drake_urdf_reflected_inertia`) as the joints' armature."""
    def pin_engine(robot: Any, tmp: Path) -> Any:
        import pinocchio as pin

        text = text_of()
        model = pin.buildModelFromXML(text)
        for jn, value in drake_urdf_reflected_inertia(text).items():
            if model.existJointName(jn):
                model.armature[model.joints[model.getJointId(jn)].idx_v] = value
        return PinocchioEngine(model, robot, fixed=mimic_positions(text))

    def pb_engine(robot: Any, tmp: Path) -> Any:
        text = text_of()
        extra = drake_urdf_reflected_inertia(text)
        arm = np.array([extra.get(jn, 0.0) for jn in robot.joint_names])
        return _pybullet_on(text, robot, tmp, armature=arm if arm.any() else None, fixed=mimic_positions(text))

    return [_named("Pinocchio", pin_engine), _named("PyBullet", pb_engine)]


def _pybullet_on(text: str, robot: Any, tmp: Path, armature: np.ndarray | None = None,
                 fixed: dict[str, float] | None = None) -> PyBulletEngine:
    """PyBullet on the URDF ``text``; the file as its importer reads it kept for the comparison."""
    read, notes = pybullet_reading(text)
    (tmp / "read").mkdir()
    reading = (_stripped_urdf(read, tmp / "read"), notes)
    return PyBulletEngine(_stripped_urdf(text, tmp), robot, armature=armature, reading=reading, fixed=fixed)


def mimic_positions(text: str) -> dict[str, float]:
    """Where a URDF puts its ``<mimic>`` joints when every other joint is at 0: ``multiplier × (the value
    of the joint it follows) + offset`` (urdfdom's defaults 1 and 0), read from the text with ElementTree.
    Neither engine reads ``<mimic>`` (Pinocchio's parser treats such a joint as independent unless asked,
    and then refuses a mimic joint declared before the joint it follows, as Kinova's files do); the
    engines put these joints here, off the chain. A mimic joint that follows a joint of the chain stays
    where that joint's 0 puts it (robokit holds it there and says so)."""
    terms = {}
    for el in ET.fromstring(text).iter("joint"):
        m = el.find("mimic")
        if m is not None:
            terms[el.get("name")] = (m.get("joint"), float(m.get("multiplier", 1.0)), float(m.get("offset", 0.0)))

    def value(joint: str, depth: int = 0) -> float:
        if joint not in terms or depth > len(terms):
            return 0.0
        leader, multiplier, offset = terms[joint]
        return multiplier * value(leader, depth + 1) + offset

    return {j: value(j) for j in terms}


def _mjcf_engines(path: Path) -> list[Callable[[Any, Path], Any]]:
    return [_named("MuJoCo", lambda robot, tmp: MujocoEngine(path, robot))]


def _has_loader(suffix: str) -> bool:
    from robokit.description.loading import FILE_LOADERS

    return suffix in FILE_LOADERS


@dataclass
class Sidecar:
    """What ``<file>.corpus.yaml`` beside a description says about it (module docstring)."""

    args: list[dict[str, str]] = field(default_factory=lambda: [{}])  # xacro arguments, one row each
    tips: list[str | None] = field(default_factory=lambda: [None])  # one row each; None: robokit's default
    package_dirs: list[Path] = field(default_factory=list)  # for <include>/package:// (relative to the file)
    skip: str = ""  # why the file is not a robot to compare (an included part, no moving joint)
    twin: Path | None = None  # an SDF's URDF twin: Pinocchio on it is the SDF's engine
    no_pybullet: str = ""  # why PyBullet cannot be the SDF's engine (a row says so)


def sidecar(path: Path) -> Sidecar | None:
    """The sidecar ``<file>.corpus.yaml`` of ``path``, or None. Either a list of xacro argument
    mappings, or a mapping with any of ``args`` (that list), ``tip`` (a name or a list of names),
    ``package_dirs`` (folders relative to the file), ``skip`` (the reason, shown in the table) and,
    for an SDF, ``twin`` (its URDF twin, beside it) and ``no_pybullet`` (why ``loadSDF`` cannot
    read it)."""
    side = path.with_name(path.name + ".corpus.yaml")
    if not side.is_file():
        return None
    import yaml

    doc = yaml.safe_load(side.read_text())
    doc = {"args": doc} if isinstance(doc, list) or doc is None else doc
    keys = ("args", "tip", "package_dirs", "skip", "twin", "no_pybullet")
    unknown = set(doc) - set(keys)
    if unknown:
        raise ValueError(f"{side}: unknown keys {sorted(unknown)} ({', '.join(keys)})")
    tips = doc.get("tip")
    return Sidecar(args=[{str(k): str(v) for k, v in (a or {}).items()} for a in doc.get("args") or [{}]],
                   tips=[str(t) for t in tips] if isinstance(tips, list) else [tips if tips is None else str(tips)],
                   package_dirs=[path.parent / d for d in doc.get("package_dirs") or []],
                   skip=str(doc.get("skip") or ""), twin=path.parent / doc["twin"] if doc.get("twin") else None,
                   no_pybullet=str(doc.get("no_pybullet") or ""))


def _labelled(label: str, tip: str | None) -> str:
    return f"{label} → {tip}" if tip else label


def vendored_cases(data: Path = DATA) -> list[Case]:
    """Every description under ``data``, by suffix (module docstring). A file that is not a robot
    on its own is skipped only when its sidecar says why; anything else that fails to load fails."""
    cases: list[Case] = []
    for path in sorted(data.rglob("*")) if data.is_dir() else []:
        name = path.name.lower()
        if not path.is_file():
            continue
        src = _rel(path)
        fmt = ("URDF" if name.endswith(".urdf") else "xacro" if name.endswith(".xacro") else
               "SDF" if name.endswith(".sdf") else "MJCF" if name.endswith(".xml") and _is_mjcf(path) else "")
        side = sidecar(path) if fmt else None
        if not fmt or (fmt == "xacro" and side is None and not name.endswith(".urdf.xacro")):
            continue  # not a description (a xacro without a sidecar nor .urdf.xacro: a macro file)
        side = side or Sidecar()
        stem = path.name.split(".")[0] if fmt == "xacro" else path.stem
        if side.skip:
            cases.append(Case(stem, fmt, src, lambda: None, skip=side.skip))
            continue
        if fmt in ("xacro", "SDF") and not _has_loader("." + name.rsplit(".", 1)[1]):
            cases.append(Case(stem, fmt, src, lambda: None,
                              skip=f"robokit has no {fmt} loader (.{name.rsplit('.', 1)[1]} not in FILE_LOADERS)"))
            continue
        dirs = side.package_dirs or None
        for tip in side.tips:
            label = _labelled(stem, tip)
            if fmt == "URDF":
                cases.append(Case(label, fmt, src, lambda p=path, t=tip: _quiet_load(p, t, package_dirs=dirs),
                                  _urdf_engines(lambda p=path: p.read_text())))
            elif fmt == "MJCF":
                cases.append(Case(label, fmt, src, lambda p=path, t=tip: _quiet_load(p, t), _mjcf_engines(path)))
            elif fmt == "SDF":
                cases.append(_sdf_case(path, src, tip, dirs, label, side))
            else:
                for args in side.args:
                    shown = " ".join(f"{k}:={v}" for k, v in sorted(args.items()))

                    def text_of(p: Path = path, a: dict[str, str] = args) -> str:
                        return xacro_program(p, a)

                    cases.append(Case(f"{label} {shown}".strip(), fmt, src,
                                      lambda p=path, a=args, t=tip: _quiet_load(p, t, xacro_args=a or None),
                                      _urdf_engines(text_of)))
    return cases


def _is_mjcf(path: Path) -> bool:
    try:
        return ET.parse(path).getroot().tag == "mujoco"
    except ET.ParseError:
        return False


def _sdf_case(path: Path, src: str, tip: str | None = None, package_dirs: list[Path] | None = None,
              label: str | None = None, side: Sidecar | None = None) -> Case:
    """An SDF against PyBullet's ``loadSDF`` and, when it has a URDF twin, Pinocchio on the twin with
    Drake's reflected inertia (:func:`drake_reflected_inertia`) as the joints' armature."""
    label, side = label or path.stem, side or Sidecar()
    if not _has_loader(".sdf"):
        return Case(label, "SDF", src, lambda: None, skip="robokit has no SDF loader (.sdf not in FILE_LOADERS)")
    engines = []
    if side.twin is not None:
        twin = side.twin

        def pin_engine(robot: Any, tmp: Path) -> Any:
            import pinocchio as pin

            model = pin.buildModelFromUrdf(str(twin))
            for jn, value in drake_reflected_inertia(path).items():
                model.armature[model.joints[model.getJointId(jn)].idx_v] = value
            engine = PinocchioEngine(model, robot)
            engine.name = "Pinocchio (URDF twin)"
            return engine

        engines.append(_named("Pinocchio (URDF twin)", pin_engine))
    if side.no_pybullet:
        engines.append(_unavailable("PyBullet", side.no_pybullet))
    else:
        engines.append(_named("PyBullet", lambda robot, tmp: PyBulletEngine(path, robot, sdf=True)))
    return Case(label, "SDF", src, lambda: _quiet_load(path, tip, package_dirs=package_dirs), engines)


def drake_reflected_inertia(path: Path) -> dict[str, float]:
    """Joint name → ``drake:rotor_inertia · drake:gear_ratio²``, read from the SDF's text, as Drake's
    parser makes it the reflected inertia of the joint's actuator (none for a joint whose
    ``<limit><effort>`` is 0: Drake adds no actuator there). Joints of nested models are not scoped
    here: the twins in tests/data have none with rotor data."""
    ns = "{http://drake.mit.edu}"
    out = {}
    for joint in ET.parse(path).getroot().iter("joint"):
        rotor, gear = joint.findtext(f"{ns}rotor_inertia"), joint.findtext(f"{ns}gear_ratio")
        effort = joint.findtext("axis/limit/effort")
        if rotor is None or (effort is not None and float(effort) == 0.0):
            continue
        out[joint.get("name", "")] = float(rotor) * float(gear if gear is not None else 1.0) ** 2
    return out


def drake_urdf_reflected_inertia(text: str) -> dict[str, float]:
    """Joint name → ``drake:rotor_inertia · drake:gear_ratio²`` of a URDF's transmissions, by the rules of
    Drake's URDF parser (its ``ParseTransmission``): a transmission whose ``<type>`` (or ``type``
    attribute) contains ``SimpleTransmission``; its first ``<actuator>``'s ``value`` attributes (0 and 1
    when absent); none on a fixed joint or one whose ``<limit effort>`` is 0 (no limit or no effort:
    unlimited, actuated). Read with ElementTree, the ``drake`` prefix declared as Drake's files do."""
    ns = "{http://drake.mit.edu}"
    root = ET.fromstring(text)
    joints = {j.get("name"): j for j in root.findall("joint")}
    out = {}
    for tr in root.findall("transmission"):
        kind = tr.findtext("type") if tr.find("type") is not None else tr.get("type", "")
        actuator = tr.find("actuator")
        joint = joints.get(tr.find("joint").get("name")) if tr.find("joint") is not None else None
        if "SimpleTransmission" not in (kind or "") or actuator is None or joint is None:
            continue
        rotor, gear = actuator.find(f"{ns}rotor_inertia"), actuator.find(f"{ns}gear_ratio")
        limit = joint.find("limit")
        effort = float(limit.get("effort", "inf")) if limit is not None else float("inf")
        if (rotor is None and gear is None) or joint.get("type") == "fixed" or effort == 0.0:
            continue
        r = float(rotor.get("value")) if rotor is not None else 0.0
        g = float(gear.get("value")) if gear is not None else 1.0
        out[joint.get("name")] = r * g * g
    return out


def _unavailable(name: str, reason: str) -> Callable[[Any, Path], Any]:
    """An engine that cannot read the file: its row is skipped with ``reason``."""
    def make(robot: Any, tmp: Path) -> Any:
        raise _Unavailable(reason)

    return _named(name, make)


class _Unavailable(Exception):
    """An engine cannot read this file (the sidecar's reason): the row is skipped, not failed."""


def erd_cases(names: tuple[str, ...] = ERD_ROBOTS) -> list[Case]:
    """The example-robot-data robots against Pinocchio on example-robot-data's own model (its
    SRDF's armature included) and PyBullet on the URDF file."""
    try:
        import example_robot_data as erd
    except ImportError:
        return [Case("example-robot-data", "URDF", "example-robot-data", lambda: None,
                     skip="example-robot-data is not installed")]
    from example_robot_data.robots_loader import getModelPath

    def urdf_of(name: str) -> Path:
        """The URDF example-robot-data builds ``name`` from (without building it: the loader's
        constructor loads every mesh)."""
        cls = erd.ROBOTS[name]
        rel = os.path.join(cls.path, cls.urdf_subpath, cls.urdf_filename)
        return Path(cls.model_path or getModelPath(rel), rel)

    cases = []
    for name in names:

        def model_of(name: str = name) -> Any:
            import pinocchio as pin

            cls = erd.ROBOTS[name]
            if getattr(cls, "has_rotor_parameters", False) and not getattr(cls, "free_flyer", False):
                with warnings.catch_warnings():  # the SRDF's rotor inertias and gear ratios: erd's own model
                    warnings.simplefilter("ignore")
                    return erd.load(name).model
            return pin.buildModelFromUrdf(str(urdf_of(name)))  # a floating base fixed, as robokit loads it

        def pin_engine(robot: Any, tmp: Path, model_of: Callable[[], Any] = model_of) -> Any:
            return PinocchioEngine(model_of(), robot)

        def pb_engine(robot: Any, tmp: Path, name: str = name, model_of: Callable[[], Any] = model_of) -> Any:
            model = model_of()
            arm = np.array([model.armature[model.joints[model.getJointId(jn)].idx_v] for jn in robot.joint_names])
            return _pybullet_on(urdf_of(name).read_text(), robot, tmp, armature=arm if arm.any() else None)

        cases.append(Case(name, "URDF (example-robot-data)", f"example-robot-data:{name}",
                          lambda name=name: _quiet_load(name),
                          [_named("Pinocchio", pin_engine), _named("PyBullet", pb_engine)]))
    return cases


def pybullet_data_cases(entries: tuple[tuple[str, str | None], ...] = PYBULLET_DATA) -> list[Case]:
    try:
        import pybullet_data
    except ImportError:
        return [Case("pybullet_data", "URDF", "pybullet_data", lambda: None, skip="pybullet is not installed")]
    root = Path(pybullet_data.getDataPath())
    cases = []
    for rel, tip in entries:
        path, src = root / rel, f"pybullet_data/{rel}"
        if rel.endswith(".urdf"):
            cases.append(Case(path.stem if path.stem != "model" else f"{path.parent.name}/{path.stem}", "URDF", src,
                              lambda p=path, t=tip: _quiet_load(p, t), _urdf_engines(lambda p=path: p.read_text())))
        elif rel.endswith(".xml"):
            cases.append(Case(path.stem, "MJCF", src, lambda p=path, t=tip: _quiet_load(p, t), _mjcf_engines(path)))
        elif rel.endswith(".sdf"):
            case = _sdf_case(path, src)
            case.label = f"{path.parent.name}/{path.stem}"
            cases.append(case)
    return cases


def all_cases() -> list[Case]:
    return vendored_cases() + erd_cases() + pybullet_data_cases()


# ------------------------------------------------------------------------------------- running
def compare(robot: Any, engine: Any, samples: int = SAMPLES, seed: int = SEED) -> dict[str, float]:
    """The largest relative error of FK (tip), J, RNEA and M of ``robot`` against ``engine``."""
    rng = np.random.default_rng(seed)
    got, ref = [], []
    for _ in range(samples):
        q = robot.random_configuration(rng)
        dq, ddq = rng.standard_normal(robot.n), rng.standard_normal(robot.n)
        mine = (robot.frame_pose(q), robot.jacobian(q, reference="local_world_aligned").reshape(6, robot.n),
                robot.rnea(q, dq, ddq), robot.crba(q))
        got.append(mine)
        ref.append(engine(q, dq, ddq))
    out = {}
    reach = max(max(float(np.linalg.norm(r[0][:3, 3])) for r in ref), 1e-3)
    out["FK"] = max(max(float(np.abs(g[0][:3, :3] - r[0][:3, :3]).max()),
                        float(np.abs(g[0][:3, 3] - r[0][:3, 3]).max()) / reach) for g, r in zip(got, ref))
    for k, key in ((1, "J"), (2, "RNEA"), (3, "M")):
        if any(np.isnan(r[k]).any() for r in ref):
            continue  # the engine cannot give it (a row note says why)
        scale = max(max(float(np.abs(r[k]).max()) for r in ref), 1e-300)
        out[key] = max(float(np.abs(g[k] - r[k]).max()) for g, r in zip(got, ref)) / scale
    return out


def _moving_changes(robot: Any, reading: tuple[Path, list[str]] | None) -> list[str]:
    """The importer's changes to links that move with the chain (a link fixed to the world
    enters no result). A change reads ``"<link>: <what>"``; a link name may itself hold colons
    (SDFormat's scoped ``forearm::link2``), so the name ends at the last ``": "``."""
    if not reading:
        return []
    moving = {f.name for f in robot.model.frames if f.parentJoint != 0}
    return [c for c in reading[1] if c.rsplit(": ", 1)[0] in moving]


def run_case(case: Case, samples: int = SAMPLES) -> list[Row]:
    """Load ``case`` with robokit and hold it against each of its engines."""
    if case.skip:
        return [Row(case.label, case.fmt, case.source, 0, "—", problem=f"skipped: {case.skip}")]
    t0 = time.perf_counter()
    try:
        robot = case.load()
    except Exception as exc:  # the row says what went wrong; the test fails on it
        return [Row(case.label, case.fmt, case.source, 0, "—", problem=f"robokit: {type(exc).__name__}: {exc}"[:300])]
    load_s = time.perf_counter() - t0
    warned = tuple(n.split("link '")[1].split("'")[0] for n in robot.notes
                   if "link '" in n and ("not positive definite" in n or "triangle inequality" in n))
    rows = []
    for make in case.engines:
        t1 = time.perf_counter()
        row = Row(case.label, case.fmt, case.source, robot.n, "?", warned=warned)
        with tempfile.TemporaryDirectory(prefix="robokit-corpus-") as tmp:
            engine = None
            try:
                engine = make(robot, Path(tmp))
                row.engine = engine.name
                subject = robot
                changes = _moving_changes(robot, getattr(engine, "reading", None))
                if changes:  # robokit on the file as the engine reads it
                    subject = _quiet_load(engine.reading[0], robot.tip)
                    subject.model.armature = np.array(robot.model.armature)  # what example-robot-data's SRDF adds
                    row.note = "; ".join(changes)
                    row.engine = f"{engine.name}*"
                if not getattr(engine, "dynamics", True):
                    row.note = ("PyBullet's loadSDF ignores inertia tensors and a product of inertia cannot be set "
                                "back: FK and J only")
                row.errors = compare(subject, engine, samples)
            except _Unavailable as exc:
                row.engine = getattr(make, "engine_name", "?")
                row.problem = f"skipped: {exc}"
            except Exception as exc:
                row.engine = getattr(engine, "name", getattr(make, "engine_name", "?"))
                row.problem = f"{type(exc).__name__}: {exc}"[:300]
            finally:
                if engine is not None and hasattr(engine, "close"):
                    engine.close()
        row.known = KNOWN.get((case.source, row.engine.rstrip("*")), "")
        row.seconds = load_s + time.perf_counter() - t1
        rows.append(row)
    return rows


def run(cases: list[Case] | None = None, samples: int = SAMPLES) -> list[Row]:
    rows: list[Row] = []
    for case in all_cases() if cases is None else cases:
        rows.extend(run_case(case, samples))
    return rows


def _fmt(x: float) -> str:
    return "—" if x != x else f"{x:.1e}"


def table(rows: list[Row], markdown: bool = False) -> str:
    """The corpus table: robot, format, source, n, largest relative error per quantity, engine."""
    head = ["robot", "format", "source", "n", *QUANTITIES, "engine", "result"]
    if not markdown:
        head.insert(-1, "s")
    body = []
    notes: list[str] = []
    for r in rows:
        errs = [_fmt(r.errors.get(k, float("nan"))) for k in QUANTITIES]
        if r.problem.startswith("skipped"):
            result = r.problem
        elif r.problem:
            result = ("known: " + r.known) if r.known else "FAILED: " + r.problem
        elif r.ok:
            result = "ok (stale KNOWN entry)" if r.known else "ok"
        else:
            result = ("known: " + r.known) if r.known else f"FAILED (> {TOLERANCE:g})"
        if r.note:
            notes.append(f"{r.source}: {r.note}")
            result += f" [{len(notes)}]"
        cells = [r.label, r.fmt, r.source, str(r.n) if r.n else "—", *errs, r.engine, result]
        if not markdown:
            cells.insert(-1, f"{r.seconds:.1f}")
        body.append(cells)
    foot = ["", "PyBullet* — compared with robokit on the file as PyBullet's importer reads it (a link without "
                "<inertial> gets 1 kg and a unit inertia; a link whose principal moments break the triangle "
                "inequality gets a zero inertia):"] if notes else []
    foot += [f"[{k}] {n}" for k, n in enumerate(notes, 1)]
    if markdown:  # element names in code spans (bare, Markdown would take them for HTML)
        def md(text: str) -> str:
            return re.sub(r"(<[a-z_]+(?:\s[^<>`]*?)?/?>)", r"`\1`", text.replace("|", "\\|"))

        lines = ["| " + " | ".join(head) + " |", "|" + "|".join("---" for _ in head) + "|"]
        lines += ["| " + " | ".join(md(c) for c in row) + " |" for row in body]
        foot = [md(f) if not f.startswith("[") else "- " + md(f) for f in foot]
        foot[2:2] = [""] if foot else []  # a blank line before the list, or Markdown joins it to the paragraph
        return "\n".join(lines + foot)
    widths = [max(len(h), *(len(row[i]) for row in body)) if body else len(h) for i, h in enumerate(head)]
    widths[-1] = len(head[-1])
    fmt = "  ".join(f"{{:<{w}}}" for w in widths)
    return "\n".join([fmt.format(*head), fmt.format(*("-" * w for w in widths)), *(fmt.format(*row) for row in body),
                      *foot])


def header() -> str:
    return (f"robokit description corpus, {datetime.date.today().isoformat()}, {platform.node() or 'machine'} "
            f"({platform.machine()}, {os.cpu_count()} cores, Python {platform.python_version()}); "
            f"{SAMPLES} random states per row, relative errors, tolerance {TOLERANCE:g}")


def discover_erd() -> list[str]:
    """The example-robot-data names robokit loads with its default tip (slow: loads them all)."""
    import example_robot_data as erd

    out = []
    for name in sorted(erd.ROBOTS):
        try:
            _quiet_load(name)
        except Exception:
            continue
        out.append(name)
    return out


#: Where the test leaves the table for the terminal summary (tests/descriptions/conftest.py).
TABLE_FILE = Path(tempfile.gettempdir()) / "robokit-descriptions-corpus.txt"


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(prog="python -m tests.descriptions.corpus", description=__doc__.splitlines()[0])
    ap.add_argument("--markdown", action="store_true", help="print the table as Markdown (docs/loading.md)")
    ap.add_argument("--discover-erd", action="store_true", help="list the example-robot-data robots robokit loads")
    args = ap.parse_args(argv)
    if args.discover_erd:
        print(discover_erd())
        return 0
    t0 = time.perf_counter()
    rows = run()
    print(header())
    print(table(rows, markdown=args.markdown))
    bad = [r for r in rows if not r.ok and not r.known and not r.problem.startswith("skipped")]
    print(f"{len(rows)} rows, {len(bad)} failed, {time.perf_counter() - t0:.0f} s")
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
