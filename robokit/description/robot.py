r"""The Robot type: one robot, its Pinocchio model, its course parameters.

A :class:`Robot` holds a serial chain root → tip as a Pinocchio ``Model`` (joints off the
chain — a gripper's fingers — locked at their neutral value and their bodies merged), one
``Data`` workspace reused by every call, the chain's product-of-exponentials parameters
(:class:`~robokit.description.poe.PoEParams`) and, for robots described by a DH file, the
:class:`~robokit.description.dh.DHTable`.

All methods take **joint angles** θ (n,) — one number per joint, continuous joints
included — and convert to Pinocchio's configuration q internally (a continuous joint's
q is (cos θ, sin θ)). Jacobians are returned **angular first**, ``(ω; v)``.

Robots are made by :func:`robokit.load` (:mod:`robokit.description.loading`), which reads
a shipped model name, a DH ``.yaml``, a ``.urdf``, a xacro file, an MJCF ``.xml`` or an
example-robot-data name, and records a :class:`~robokit.description.spec.RobotSpec` on
``robot.spec`` that rebuilds the same robot anywhere.
"""
from __future__ import annotations

import os
from math import isfinite
from pathlib import Path
from typing import TYPE_CHECKING, Any, Callable, Iterable, Mapping

import numpy as np
from numpy.typing import ArrayLike

from robokit._arrays import as_joints, check_reference, ndim
from robokit.errors import InputError
from robokit.description.dh import DHTable
from robokit.description.poe import PoEParams, poe_from_model

if TYPE_CHECKING:
    from robokit.description.spec import RobotSpec

_F64 = np.dtype(np.float64)

__all__ = ["Robot"]

#: The writer behind :meth:`Robot.save`, :func:`robokit.description.save.save_robot`: registered by that
#: module, which ``robokit.description`` imports (it needs the loaders, and they need the Robot).
_WRITER: list[Callable[[Robot, str | os.PathLike[str]], Path]] = []


class Robot:
    """One serial robot: Pinocchio model and data, PoE parameters, DH table when it has one.

    Made by :func:`robokit.load`; the constructor takes a chain model built by
    :func:`robokit.description.builder.serial_chain`.

    Parameters
    ----------
    name : str
        The robot's name.
    model : pinocchio.Model
        The serial chain root → tip (one-degree-of-freedom joints only).
    tip : str
        Name of the tip frame.
    visual_model, collision_model : pinocchio.GeometryModel or None, optional
        Geometry for the viewers and collision checks.
    dh : DHTable or None, optional
        The DH table the robot was built from.
    configurations : mapping of str to array_like, optional
        Named joint configurations (n,) besides ``"zero"``.
    locked_joints : iterable of str, optional
        Joints locked off the chain.
    source : str, optional
        Where the robot came from (shown in messages).

    Attributes
    ----------
    name : str
        The robot's name.
    model, data : pinocchio.Model, pinocchio.Data
        The chain's model and its reused workspace.
    visual_model, collision_model : pinocchio.GeometryModel or None
        Geometry, when the description has any.
    tip : str
        Tip frame name; ``tip_id`` its frame id.
    dh : DHTable or None
        The DH table for robots loaded from one.
    poe : PoEParams
        Product-of-exponentials parameters of the chain (``M``, ``Slist``, ``Blist``, ``Mlist``,
        ``Glist``).
    n : int
        Number of joint angles (a continuous joint counts as one).
    joint_names : tuple of str
        The n joint names, root to tip.
    qlim : numpy.ndarray, shape (n, 2)
        Joint limits, rad or m (±inf for continuous joints).
    gravity : numpy.ndarray, shape (3,)
        Gravity in the base frame, m/s².
    configurations : dict of str to numpy.ndarray
        Named configurations (joint angles), ``"zero"`` always.
    locked_joints : tuple of str
        The joints locked off the chain.
    source : str
        Where it came from.
    spec : RobotSpec or None
        The :class:`~robokit.description.spec.RobotSpec` that rebuilds it
        (``robokit.load(robot.spec)``); None for a Robot built by hand from a model.
    nominal : Robot or RobotSpec or None
        For a calibrated robot (:func:`robokit.calibrate`), the arm the calibration started from.

    Examples
    --------
    The shipped planar arm (links 1 m and 0.8 m): tip pose, geometric Jacobian (rows ω; v) and
    gravity torques when stretched (2 kg and 1.5 kg point masses, g = 9.81 m/s² along −y):

    >>> robot = rk.load("twolink")
    >>> robot.n, robot.joint_names, robot.frame_pose([0.0, np.pi / 2])[:2, 3].round(4).tolist()
    (2, ('joint_1', 'joint_2'), [1.0, 0.8])
    >>> robot.jacobian([0.0, 0.0], reference="local_world_aligned")[3:5].round(4).tolist()
    [[0.0, 0.0], [1.8, 0.8]]
    >>> robot.gravity_torques([0.0, 0.0]).round(4).tolist()
    [46.107, 11.772]
    """

    spec: RobotSpec | None = None  # set by the loaders (robokit.description.builder.build_robot)
    #: The nominal arm of a calibrated robot (a Robot, or the RobotSpec that loads it), else None:
    #: its structure gives the calibrated arm's exact IK (:mod:`robokit.ik.calibrated`).
    nominal: Robot | RobotSpec | None = None

    def __init__(self, name: str, model: Any, tip: str, *, visual_model: Any = None, collision_model: Any = None,
                 dh: DHTable | None = None, configurations: Mapping[str, ArrayLike] | None = None,
                 locked_joints: Iterable[str] = (), source: str = "") -> None:
        import pinocchio as pin

        self._pin = pin
        self.name = name
        self.model = model
        self.data = model.createData()
        self.visual_model = visual_model
        self.collision_model = collision_model
        self.tip = tip
        self.tip_id = model.getFrameId(tip)
        self.dh = dh
        self.poe: PoEParams = poe_from_model(model, tip)
        self.n = model.nv
        self.joint_names = self.poe.joint_names
        self.qlim = self.poe.qlim
        self.gravity = np.array(model.gravity.linear)
        self.locked_joints = tuple(locked_joints)
        self.source = source
        self.notes: list[str] = []  # what was done on the user's behalf (printed by the CLI)
        self._same_coords = model.nq == model.nv
        self._cont = [(jm.idx_q, jm.idx_v) for jm in list(model.joints)[1:] if jm.nq == 2]
        self._lin = [(jm.idx_q, jm.idx_v) for jm in list(model.joints)[1:] if jm.nq == 1]
        self.configurations = {"zero": np.zeros(self.n)}
        for k, v in (configurations or {}).items():
            self.configurations[k] = np.asarray(v, dtype=float)
        self._frame_ids: dict[str, int] = {}
        self._lower = np.tril_indices(self.n, -1)
        lower = np.tril_indices(self.n, -1)  # crba: flat indices of the strict lower triangle and its mirror
        self._lower_flat = np.ravel_multi_index(lower, (self.n, self.n))
        self._upper_flat = np.ravel_multi_index(lower[::-1], (self.n, self.n))
        self._shape = (self.n,)
        # the finiteness test of a fast-path q: a Python sum of its floats for short vectors (cheaper
        # than numpy's dot there); an overflow to inf only sends a finite q to the full checks
        self._small = self.n <= 16
        self._plain = self._same_coords and self.n > 1  # Pinocchio's q is θ and its Jacobian is 6×n
        self._ref_frames: dict[str, Any] = {}  # "world" → pin.ReferenceFrame.WORLD, … (looked up once)
        self._swap = np.r_[3:6, 0:3]  # Pinocchio's (v, ω) rows → robokit's (ω, v)

    # --------------------------------------------------------------- coordinates
    def q_pin(self, q: ArrayLike) -> np.ndarray:
        """Pinocchio configuration (nq,) of joint values q (n,) (a continuous joint's angle θ
        becomes (cos θ, sin θ))."""
        if self._same_coords:
            return np.asarray(q, dtype=float)
        q = np.asarray(q, dtype=float)
        q_pin = np.empty(self.model.nq)
        for iq, iv in self._lin:
            q_pin[iq] = q[iv]
        for iq, iv in self._cont:
            q_pin[iq], q_pin[iq + 1] = np.cos(q[iv]), np.sin(q[iv])
        return q_pin

    def q_from_pin(self, q_pin: ArrayLike) -> np.ndarray:
        """Joint values q (n,) of a Pinocchio configuration (nq,)."""
        q_pin = np.asarray(q_pin, dtype=float)
        if self._same_coords:
            return q_pin.copy()
        q = np.empty(self.n)
        for iq, iv in self._lin:
            q[iv] = q_pin[iq]
        for iq, iv in self._cont:
            q[iv] = np.arctan2(q_pin[iq + 1], q_pin[iq])
        return q

    def frame_id(self, frame: str | None) -> int:
        """Frame id of ``frame`` (None: the tip); ValueError listing frames if unknown."""
        if frame is None:
            return self.tip_id
        fid = self._frame_ids.get(frame)
        if fid is None:
            if not self.model.existFrame(frame):
                names = [f.name for f in self.model.frames]
                raise InputError(f"frame: no frame {frame!r} in {self.name}; frames: {', '.join(names[-15:])}")
            fid = self._frame_ids[frame] = self.model.getFrameId(frame)
        return fid

    def _check_q(self, q: ArrayLike, name: str = "q") -> np.ndarray:
        return as_joints(q, self.n, name, self.name)

    # ------------------------------------------------------------ fast answers
    def frame_pose(self, q: ArrayLike, frame: str | None = None) -> np.ndarray:
        """4×4 pose of ``frame`` (default the tip) in the root frame at joint values q (n,);
        for q of shape (N, n) (tip only), the (N, 4, 4) poses (see :mod:`robokit.description.batch`)."""
        pin = self._pin
        if (type(q) is np.ndarray and q.dtype is _F64 and q.shape == self._shape
                and isfinite(sum(q.tolist()) if self._small else q.dot(q))):
            pass  # finite float64 (n,) arrays: straight to Pinocchio
        elif ndim(q, "q") == 2:
            from robokit.description.batch import batch_frame_pose

            return batch_frame_pose(self, q, frame)
        else:
            q = self._check_q(q)
        q = q if self._same_coords else self.q_pin(q)
        pin.forwardKinematics(self.model, self.data, q)
        fid = self.tip_id if frame is None else self.frame_id(frame)
        return pin.updateFramePlacement(self.model, self.data, fid).homogeneous

    def frame_poses(self, q: ArrayLike) -> dict[str, np.ndarray]:
        """Poses (4×4) of every frame, by name, at θ."""
        pin = self._pin
        pin.framesForwardKinematics(self.model, self.data, self.q_pin(self._check_q(q)))
        return {f.name: self.data.oMf[i].homogeneous for i, f in enumerate(self.model.frames)}

    _REFS = {"world": "WORLD", "local": "LOCAL", "local_world_aligned": "LOCAL_WORLD_ALIGNED"}

    def jacobian(self, q: ArrayLike, frame: str | None = None, reference: str = "world") -> np.ndarray:
        """6×n Jacobian of ``frame`` at θ, **angular rows first** (ω; v).

        reference : "world" — the space Jacobian (twist of the frame expressed at the root
        origin, root axes); "local" — the body Jacobian (frame's own axes, at its origin);
        "local_world_aligned" — the geometric Jacobian of the course (ω and the velocity of
        the frame origin, root axes). For q of shape (N, n) (tip only), (N, 6, n).
        """
        rf = self._ref_frames.get(reference)
        if (rf is not None and frame is None and type(q) is np.ndarray and q.dtype is _F64 and q.shape == self._shape
                and self._plain and isfinite(sum(q.tolist()) if self._small else q.dot(q))):
            # the fast path (tip frame, finite float64 (n,) q, no continuous joints): one Pinocchio call
            # and the (v; ω) → (ω; v) row swap, nothing else
            return self._pin.computeFrameJacobian(self.model, self.data, q, self.tip_id, rf).take(self._swap, 0)
        pin = self._pin
        if rf is None:
            canonical = check_reference(reference)  # the shared vocabulary, mapped onto Pinocchio's names
            rf = self._ref_frames[reference] = getattr(pin.ReferenceFrame, self._REFS[canonical])
        if (type(q) is np.ndarray and q.dtype is _F64 and q.shape == self._shape
                and isfinite(sum(q.tolist()) if self._small else q.dot(q))):
            pass  # finite float64 (n,) arrays: straight to Pinocchio
        elif ndim(q, "q") == 2:
            from robokit.description.batch import batch_jacobian

            return batch_jacobian(self, q, frame, reference)
        else:
            q = self._check_q(q)
        q = q if self._same_coords else self.q_pin(q)
        fid = self.tip_id if frame is None else self.frame_id(frame)
        J = pin.computeFrameJacobian(self.model, self.data, q, fid, rf)
        return J.reshape(6, self.n).take(self._swap, axis=0)  # (a one-joint chain's 6×1 comes back as (6,))

    def rnea(self, q: ArrayLike, dq: ArrayLike, ddq: ArrayLike, threads: int = 1) -> np.ndarray:
        """Inverse dynamics τ = M(q)q̈ + c(q, q̇) + g(q) (n,), Pinocchio's RNEA; for (N, n)
        inputs, (N, n) through ``rneaInParallel`` on ``threads`` threads."""
        if (type(q) is type(dq) is type(ddq) is np.ndarray and q.dtype is dq.dtype is ddq.dtype is _F64
                and q.shape == dq.shape == ddq.shape == self._shape):
            # float64 (n,) arrays straight to Pinocchio (which returns a new array); a NaN or inf in
            # any input reaches the result, so one test of the result stands for three of the inputs
            tau = self._pin.rnea(self.model, self.data, q if self._same_coords else self.q_pin(q), dq, ddq)
            if isfinite(tau.dot(tau)):
                return tau
        elif ndim(q, "q") == 2:
            from robokit.description.batch import batch_rnea

            return batch_rnea(self, q, dq, ddq, threads)
        q, dq, ddq = self._check_q(q), self._check_q(dq, "dq"), self._check_q(ddq, "ddq")
        q = q if self._same_coords else self.q_pin(q)
        return self._pin.rnea(self.model, self.data, q, dq, ddq)

    def crba(self, q: ArrayLike) -> np.ndarray:
        """Mass matrix M(q) (n×n, symmetric), Pinocchio's CRBA; for q (N, n), (N, n, n) from the
        compiled composite-rigid-body kernel."""
        if (type(q) is np.ndarray and q.dtype is _F64 and q.shape == self._shape and self._plain
                and isfinite(sum(q.tolist()) if self._small else q.dot(q))):
            M = self._pin.crba(self.model, self.data, q)  # the fast path: a new array, its upper triangle filled
            if M.flags.c_contiguous:
                flat = M.ravel()  # a view of M
                flat[self._lower_flat] = flat[self._upper_flat]
                return M
        if (type(q) is np.ndarray and q.dtype is _F64 and q.shape == self._shape
                and isfinite(sum(q.tolist()) if self._small else q.dot(q))):
            pass  # finite float64 (n,) arrays: straight to Pinocchio
        elif ndim(q, "q") == 2:
            from robokit.description.batch import batch_crba

            return batch_crba(self, q)
        else:
            q = self._check_q(q)
        q = q if self._same_coords else self.q_pin(q)
        M = self._pin.crba(self.model, self.data, q)  # a new array; Pinocchio fills its upper triangle
        if not M.flags.c_contiguous:
            M = np.ascontiguousarray(M)
        flat = M.ravel()  # a view of M
        flat[self._lower_flat] = flat[self._upper_flat]
        return M

    def aba(self, q: ArrayLike, dq: ArrayLike, tau: ArrayLike, threads: int = 1) -> np.ndarray:
        """Forward dynamics q̈ = M⁻¹(τ − c − g) (n,), Pinocchio's ABA; for (N, n) inputs, (N, n)
        through ``abaInParallel`` on ``threads`` threads."""
        if (type(q) is type(dq) is type(tau) is np.ndarray and q.dtype is dq.dtype is tau.dtype is _F64
                and q.shape == dq.shape == tau.shape == self._shape):
            # as in rnea: one test of the (new) result stands for the inputs' finiteness
            ddq = self._pin.aba(self.model, self.data, q if self._same_coords else self.q_pin(q), dq, tau)
            if isfinite(ddq.dot(ddq)):
                return ddq
        elif ndim(q, "q") == 2:
            from robokit.description.batch import batch_aba

            return batch_aba(self, q, dq, tau, threads)
        q, dq, tau = self._check_q(q), self._check_q(dq, "dq"), self._check_q(tau, "tau")
        q = q if self._same_coords else self.q_pin(q)
        return self._pin.aba(self.model, self.data, q, dq, tau)

    def gravity_torques(self, q: ArrayLike) -> np.ndarray:
        """Gravity torques g(θ) (n,)."""
        if not (type(q) is np.ndarray and q.dtype is _F64 and q.shape == self._shape
                and isfinite(sum(q.tolist()) if self._small else q.dot(q))):
            q = self._check_q(q)
        q = q if self._same_coords else self.q_pin(q)
        return self._pin.computeGeneralizedGravity(self.model, self.data, q)  # a new array

    def nonlinear_effects(self, q: ArrayLike, dq: ArrayLike) -> np.ndarray:
        """c(θ, θ̇) + g(θ) (n,)."""
        q = self.q_pin(self._check_q(q))
        return self._pin.nonLinearEffects(self.model, self.data, q, self._check_q(dq, "dq")).copy()

    def random_configuration(self, rng: int | np.random.Generator | None = None) -> np.ndarray:
        """Joint angles drawn uniformly inside the limits ([−π, π] for unlimited joints)."""
        rng = np.random.default_rng(rng)
        lo = np.where(np.isfinite(self.qlim[:, 0]), self.qlim[:, 0], -np.pi)
        hi = np.where(np.isfinite(self.qlim[:, 1]), self.qlim[:, 1], np.pi)
        return rng.uniform(lo, hi)

    def save(self, path: str | os.PathLike[str]) -> Path:
        """Write the robot as ``.urdf`` (or ``.yaml`` when a DH table reproduces it exactly), atomically.

        See :mod:`robokit.description.save`: a calibrated robot writes its own URDF (calibrated joint
        placements, nominal inertias), a DH robot the URDF of its table, a URDF robot its file.

        Parameters
        ----------
        path : str or path-like
            The file; its folder must exist.

        Returns
        -------
        Path
            The file written.

        Examples
        --------
        >>> import tempfile, os
        >>> with tempfile.TemporaryDirectory() as tmp:
        ...     rk.load(rk.load("puma560").save(os.path.join(tmp, "arm.urdf"))).n
        6
        """
        return _WRITER[0](self, path)

    def __repr__(self) -> str:
        kind = f"DH {self.dh.convention}" if self.dh is not None else "URDF; its DH table: robokit.dh_from_urdf(robot).table"
        return f"Robot({self.name!r}, {self.n} joints, tip={self.tip!r}, {kind})"

