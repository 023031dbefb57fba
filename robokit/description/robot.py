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
from math import hypot
from pathlib import Path
from types import MappingProxyType
from typing import TYPE_CHECKING, Any, Callable, Hashable, Iterable, Mapping

import numpy as np
from numpy.typing import ArrayLike

from robokit._arrays import as_joints, ndim
from robokit._deprecation import warn_once
from robokit._units import check_radians, fast_bounds, radian_ranges, revolute_columns
from robokit.errors import InputError
from robokit.frames import Frame, reference_or_default
from robokit.description.dh import DHTable
from robokit.description.frames import frame_index
from robokit.description.limits import unbounded_limits
from robokit.description.poe import PoEParams, poe_from_model

if TYPE_CHECKING:
    from robokit.description.spec import RobotSpec

_F64 = np.dtype(np.float64)
_ND = np.ndarray
_INF = float("inf")

__all__ = ["Robot", "check_robot_radians"]

#: The writer behind :meth:`Robot.save`, :func:`robokit.description.save.save_robot`: registered by that
#: module, which ``robokit.description`` imports (it needs the loaders, and they need the Robot).
_WRITER: list[Callable[[Robot, str | os.PathLike[str]], Path]] = []


class Robot:
    """One serial robot: Pinocchio model and data, PoE parameters, DH table when it has one.

    Made by :func:`robokit.load`; the constructor takes a chain model built by
    :func:`robokit.description.builder.serial_chain`.

    A Robot is **immutable**: assigning any attribute raises ``AttributeError``, and ``qlim``,
    ``gravity``, the ``configurations`` and the arrays of ``poe`` are read-only. A changed robot is
    a new one (:meth:`with_limits`, :meth:`with_tool`, each with its own ``spec``); what is computed from a
    robot is computed once and kept with it (:meth:`derived`). The one mutable part is ``data``,
    Pinocchio's workspace, which every call reuses: a Robot is not thread-safe (give each thread
    its own, ``robokit.load(robot.spec)``, or use the ``*_batch`` methods). Its ``model`` is
    Pinocchio's object: do not edit it in place.

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
    spec : RobotSpec, optional
        The spec that rebuilds it (the loaders give it).

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
        ``Glist``), read-only arrays.
    n : int
        Number of joint angles (a continuous joint counts as one).
    joint_names : tuple of str
        The n joint names, root to tip.
    qlim : numpy.ndarray, shape (n, 2)
        Joint limits, rad or m (±inf for continuous joints, and on a side whose limit in the
        file is beyond ±1e12: :func:`~robokit.description.limits.unbounded_limits`); read-only
        (other limits: :meth:`with_limits`).
    gravity : numpy.ndarray, shape (3,)
        Gravity in the base frame, m/s²; read-only.
    configurations : mapping of str to numpy.ndarray
        Named configurations (joint angles, read-only), ``"zero"`` always.
    locked_joints : tuple of str
        The joints locked off the chain.
    source : str
        Where it came from.
    frame_names : tuple of str
        The frames robokit reports (``frame_poses``' keys, the frames a message lists): for a
        robot loaded from a file, the frames its file names (Pinocchio's own names, such as
        ``universe``, left out; they stay in ``model``); for a Robot built by hand, every frame.
    notes : tuple of str
        What the loader did on the user's behalf or found questionable (each was also warned
        once as a :class:`~robokit.errors.RobokitWarning`).
    spec : RobotSpec or None
        The :class:`~robokit.description.spec.RobotSpec` that rebuilds it
        (``robokit.load(robot.spec)``), for loaded, calibrated and changed (``with_limits``,
        ``with_tool``) robots alike; None for a Robot built by hand from a model.
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

    spec: RobotSpec | None = None  # given by the loaders (robokit.description.builder.build_robot)
    contact_rules: Any = None  # an MJCF robot's contact filter (robokit.description.mjcf.ContactRules)
    #: The nominal arm of a calibrated robot (a Robot, or the RobotSpec that loads it), else None:
    #: its structure gives the calibrated arm's exact IK (:mod:`robokit.ik.calibrated`).
    nominal: Robot | RobotSpec | None = None

    def __init__(self, name: str, model: Any, tip: str, *, visual_model: Any = None, collision_model: Any = None,
                 dh: DHTable | None = None, configurations: Mapping[str, ArrayLike] | None = None,
                 locked_joints: Iterable[str] = (), source: str = "", spec: RobotSpec | None = None) -> None:
        import pinocchio as pin

        self._pin = pin
        self._derived: dict[Any, Any] = {}  # what derived() computed once from this frozen robot
        self.name = name
        self.model = model
        self.data = model.createData()
        self.visual_model = visual_model
        self.collision_model = collision_model
        self.tip = tip
        self.tip_id = frame_index(model, tip)
        if dh is not None:  # the robot's own copy of the table, its arrays read-only like the robot's
            from dataclasses import replace

            dh = replace(dh, base=_read_only(dh.base), tool=_read_only(dh.tool), gravity=_read_only(dh.gravity))
        self.dh = dh
        if spec is not None:
            self.spec = spec
        limit_notes = unbounded_limits(model, source or name)  # ±1e16, ±1e308 ... mean no limit
        # the PoE parameters are shown read-only: views of the arrays poe_from_model built, which only the
        # compiled kernels are given (robokit._arrays.kernel_array/kernel_arrays pass a read-only view's
        # writeable base, as their signatures take it: no copy per call)
        self.poe: PoEParams = _frozen_poe(poe_from_model(model, tip))
        self.n = model.nv
        self.joint_names = self.poe.joint_names
        self.qlim = _read_only(self.poe.qlim)  # a read-only copy
        self.gravity = _read_only(model.gravity.linear)
        self.locked_joints = tuple(locked_joints)
        self.source = source
        self.notes: tuple[str, ...] = tuple(limit_notes)  # what was done on the user's behalf (printed by the CLI)
        self.frame_names: tuple[str, ...] = tuple(dict.fromkeys(f.name for f in model.frames))  # build_robot narrows
        if limit_notes:
            import warnings

            from robokit._stack import outside_level
            from robokit.errors import RobokitWarning

            for note in limit_notes:
                warnings.warn(note, RobokitWarning, stacklevel=outside_level())
        self._same_coords = model.nq == model.nv
        self._cont = [(jm.idx_q, jm.idx_v) for jm in list(model.joints)[1:] if jm.nq == 2]
        self._lin = [(jm.idx_q, jm.idx_v) for jm in list(model.joints)[1:] if jm.nq == 1]
        configs = {"zero": np.zeros(self.n)}
        for k, v in (configurations or {}).items():
            configs[k] = np.asarray(v, dtype=float)
        self.configurations: Mapping[str, np.ndarray] = MappingProxyType(
            {k: _read_only(v) for k, v in configs.items()})
        self._frame_ids: dict[str, int] = {}
        self._shape = (self.n,)
        # radians, not degrees (robokit._units): the plausible range of each joint's value in a
        # one-off configuration, and in a state (batches, trajectories, seeds: continuous joints
        # exempt, their multi-turn values are legitimate there)
        revolute = revolute_columns(self.poe.Slist)
        continuous = np.zeros(self.n, dtype=bool)
        for _, iv in self._cont:
            continuous[iv] = True
        self._deg_lo, self._deg_hi = radian_ranges(revolute, self.qlim)
        self._deg_state = radian_ranges(revolute, self.qlim, exempt=continuous)
        # the fast paths' test of q (_fast): hypot(*q) <= r (one C call; NaN or inf fail it), or every entry
        # in [lo1, hi1] (hypot finite), implies that q is finite and passes the degrees check
        self._r1, self._lo1, self._hi1 = fast_bounds(self._deg_lo, self._deg_hi)
        self._plain = self._same_coords and self.n > 1  # Pinocchio's q is θ and its Jacobian is 6×n
        self._ref_frames: dict[object, Any] = {}  # Frame.WORLD / "world" → pin.ReferenceFrame.WORLD, … (looked up once)
        self._swap = np.r_[3:6, 0:3]  # Pinocchio's (v, ω) rows → robokit's (ω, v)
        # Pinocchio's functions the fast paths call, looked up once (one attribute read per call instead of two)
        self._fk, self._frame_placement, self._frame_jacobian = (
            pin.forwardKinematics, pin.updateFramePlacement, pin.computeFrameJacobian)
        self._rnea, self._crba, self._aba, self._gravity = pin.rnea, pin.crba, pin.aba, pin.computeGeneralizedGravity
        object.__setattr__(self, "_sealed", True)

    # ------------------------------------------------------------ immutability
    def __setattr__(self, name: str, value: Any) -> None:
        if "_sealed" in self.__dict__:
            raise AttributeError(_frozen_message(name))
        object.__setattr__(self, name, value)

    def __delattr__(self, name: str) -> None:
        raise AttributeError(_frozen_message(name))

    def _amend(self, **attrs: Any) -> Robot:
        """Set the attributes a loader fills in after construction (``spec``, ``frame_names``,
        ``notes``, ``nominal``, ``contact_rules``) before the robot leaves the loader; returns it.
        Nothing else may call this: a robot handed out never changes."""
        allowed = {"spec", "frame_names", "notes", "nominal", "contact_rules"}
        bad = sorted(set(attrs) - allowed)
        if bad:
            raise AttributeError(_frozen_message(bad[0]))
        for key, value in attrs.items():
            object.__setattr__(self, key, tuple(value) if key in ("frame_names", "notes") else value)
        return self

    def derived(self, key: Hashable, build: Callable[[], Any]) -> Any:
        """A value computed once from this robot (its frozen model) and kept with it.

        A Robot never changes, so what is computed from it never goes stale: the closed-form
        solver's constants, the collision pairs, thread pools … are built on first use by
        ``build()`` and returned by every later call with the same ``key``. They live as long as
        the robot (no module-level cache keyed by the robot's identity).

        Parameters
        ----------
        key : hashable
            Names the value (a string, or a tuple of the builder's name and its hashable options).
        build : callable
            Computes it (no arguments); called once per key.

        Returns
        -------
        object
            ``build()``'s result, the same object on every call.

        Examples
        --------
        >>> robot = rk.load("twolink")
        >>> a = robot.derived("home", lambda: robot.frame_pose(np.zeros(2)))
        >>> a is robot.derived("home", lambda: None)
        True
        """
        try:
            return self._derived[key]
        except KeyError:
            value = self._derived[key] = build()
            return value

    # ------------------------------------------------------------ changed copies
    def with_limits(self, qlim: ArrayLike) -> Robot:
        """A copy of the robot with other joint limits (the robot itself never changes).

        Parameters
        ----------
        qlim : array_like, shape (n, 2)
            Lower and upper limit of each joint, rad or m (±inf: unlimited; a continuous joint
            takes only (−inf, inf)).

        Returns
        -------
        Robot
            A new robot: the same model but for the limits (its DH table's too), and a
            ``spec`` that rebuilds it (``robokit.load(copy.spec)``; None when this robot has none).

        Examples
        --------
        >>> robot = rk.load("twolink")
        >>> tight = robot.with_limits([[-0.5, 0.5], [-1.0, 1.0]])
        >>> tight.qlim.tolist(), robot.qlim.tolist() == tight.qlim.tolist()
        ([[-0.5, 0.5], [-1.0, 1.0]], False)
        """
        from dataclasses import replace

        from robokit._arrays import as_array

        lim = np.array(as_array(qlim, "qlim", (self.n, 2), finite=False), dtype=float)
        if np.isnan(lim).any():
            raise InputError("qlim: NaN in the limits")
        for i in range(self.n):
            lo, hi = lim[i]
            if not lo <= hi:
                raise InputError(f"qlim: joint {self.joint_names[i]!r}: lower limit {lo:g} above upper limit {hi:g}")
        model = self._pin.Model(self.model)
        lower, upper = model.lowerPositionLimit.copy(), model.upperPositionLimit.copy()
        for jm in list(model.joints)[1:]:
            lo, hi = lim[jm.idx_v]
            if jm.nq == 2:
                if np.isfinite(lo) or np.isfinite(hi):
                    raise InputError(f"qlim: joint {self.joint_names[jm.idx_v]!r} is continuous; its limits "
                                     "can only be (-inf, inf)")
                continue
            lower[jm.idx_q], upper[jm.idx_q] = lo, hi
        model.lowerPositionLimit, model.upperPositionLimit = lower, upper
        dh = self.dh
        if dh is not None:
            dh = replace(dh, links=tuple(replace(link, qlim=lim[i].copy()) for i, link in enumerate(dh.links)))
        spec = None if self.spec is None else replace(self.spec, limits=tuple(
            (float(lo), float(hi)) for lo, hi in lim))
        return self._copy(model, self.tip, dh, spec, self.frame_names)

    def with_tool(self, T_tip_tool: ArrayLike, name: str = "tcp") -> Robot:
        """A copy of the robot whose tip is a new frame ``name`` fixed to the current tip.

        Parameters
        ----------
        T_tip_tool : array_like, shape (4, 4)
            Pose of the new tool frame in the current tip frame (rotation, translation in m).
        name : str, optional
            The new frame's name (default ``"tcp"``); it must not name a frame of the robot.

        Returns
        -------
        Robot
            A new robot with ``tip == name`` (its DH table's ``tool`` composed with the
            offset), and a ``spec`` that rebuilds it (None when this robot has none).

        Examples
        --------
        >>> robot = rk.load("twolink")
        >>> T = np.eye(4); T[0, 3] = 0.1  # 10 cm further along the last link
        >>> longer = robot.with_tool(T)
        >>> longer.tip, longer.frame_pose([0.0, 0.0])[:3, 3].round(4).tolist()
        ('tcp', [1.9, 0.0, 0.0])
        """
        from dataclasses import replace

        from robokit.spatial.se3 import check_transform

        T = np.array(check_transform(T_tip_tool, "T_tip_tool"), dtype=float)
        if not isinstance(name, str) or not name:
            raise InputError(f"name: expected a non-empty frame name, got {name!r}")
        if self.model.existFrame(name):
            raise InputError(f"name: {self.name} already has a frame {name!r}; give another name")
        pin = self._pin
        model = pin.Model(self.model)
        tip = model.frames[self.tip_id]
        placement = tip.placement * pin.SE3(T[:3, :3].copy(), T[:3, 3].copy())
        model.addFrame(pin.Frame(name, tip.parentJoint, self.tip_id, placement, pin.FrameType.OP_FRAME))
        dh = None if self.dh is None else replace(self.dh, tool=np.asarray(self.dh.tool, dtype=float) @ T)
        spec = None if self.spec is None else replace(self.spec, tools=(
            *self.spec.tools, (name, tuple(float(x) for x in T.ravel()))))
        return self._copy(model, name, dh, spec, (*self.frame_names, name))

    def _copy(self, model: Any, tip: str, dh: DHTable | None, spec: RobotSpec | None,
              frame_names: tuple[str, ...]) -> Robot:
        """A new Robot on ``model`` with this one's geometry, names, notes and origin."""
        out = Robot(self.name, model, tip, visual_model=self.visual_model, collision_model=self.collision_model,
                    dh=dh, configurations=dict(self.configurations), locked_joints=self.locked_joints,
                    source=self.source if spec is None else spec.describe(), spec=spec)
        return out._amend(frame_names=frame_names, notes=self.notes, nominal=self.nominal,
                          contact_rules=self.contact_rules)

    # --------------------------------------------------------------- coordinates
    def q_pin(self, q: ArrayLike) -> np.ndarray:
        """Pinocchio's configuration vector (nq,) for joint values q (n,).

        A continuous (unbounded revolute) joint is two numbers in Pinocchio, (cos θ, sin θ); every
        other joint is its value. Without continuous joints the two vectors are the same.

        Parameters
        ----------
        q : array_like, shape (n,)
            Joint values (rad for revolute, m for prismatic joints), taken as they are: no shape,
            finiteness or degrees check (the other methods check theirs).

        Returns
        -------
        numpy.ndarray, shape (model.nq,)
            The configuration Pinocchio's algorithms take.

        Examples
        --------
        >>> robot = rk.load("twolink")
        >>> robot.q_pin([0.1, 0.2]).tolist()
        [0.1, 0.2]
        """
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
        """Joint values q (n,) of a Pinocchio configuration (nq,): the inverse of :meth:`q_pin`.

        Parameters
        ----------
        q_pin : array_like, shape (model.nq,)
            A Pinocchio configuration ((cos θ, sin θ) for each continuous joint).

        Returns
        -------
        numpy.ndarray, shape (n,)
            Joint values, rad or m (continuous joints as atan2(sin, cos), in (−π, π]).

        Examples
        --------
        >>> robot = rk.load("twolink")
        >>> robot.q_from_pin(robot.q_pin([0.1, 0.2])).tolist()
        [0.1, 0.2]
        """
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
        """Pinocchio's frame id of ``frame``.

        Parameters
        ----------
        frame : str or None
            A frame name of the model (None: the tip).

        Returns
        -------
        int
            The index into ``model.frames``; :class:`~robokit.errors.InputError` listing frames if unknown.

        Examples
        --------
        >>> robot = rk.load("twolink")
        >>> robot.frame_id(None) == robot.frame_id("tool") == robot.tip_id
        True
        """
        if frame is None:
            return self.tip_id
        fid = self._frame_ids.get(frame)
        if fid is None:
            if not self.model.existFrame(frame):
                raise InputError(f"frame: no frame {frame!r} in {self.name}; frames: "
                                 f"{', '.join(self.frame_names[-15:])}")
            fid = self._frame_ids[frame] = frame_index(self.model, frame)
        return fid

    def _check_q(self, q: ArrayLike, name: str = "q") -> np.ndarray:
        q = as_joints(q, self.n, name, self.name)
        if name == "q":
            check_radians(q, self._deg_lo, self._deg_hi, name, self.name)
        return q

    def check_radians(self, q: ArrayLike, name: str = "q", *, state: bool = False) -> bool:
        """Warn once (:class:`robokit.errors.DegreesWarning`) when joint values look like degrees.

        A revolute value beyond a full turn (±2π rad) and past its joint's limits, or past the
        limits by more than a turn (see :mod:`robokit._units`); prismatic joints are never
        checked. Every method taking a configuration runs this check; functions taking one for
        this robot (IK seeds, trajectories' end points, simulations) call it.

        Parameters
        ----------
        q : array_like, shape (n,) or (N, n)
            Joint values (rad / m), finite.
        name : str
            The argument's name, for the message.
        state : bool
            The values are states that may wind (a seed, a trajectory's points, rows of a log):
            continuous joints are exempt.

        Returns
        -------
        bool
            True when a value looks like degrees (it warned, unless robokit itself made the call).

        Examples
        --------
        >>> import warnings
        >>> with warnings.catch_warnings():
        ...     warnings.simplefilter("ignore")
        ...     rk.load("puma560").check_radians([0, 45, -90, 0, 30, 0])
        True
        """
        lo, hi = self._deg_state if state else (self._deg_lo, self._deg_hi)
        return check_radians(np.asarray(q, dtype=float), lo, hi, name, self.name)

    def _fast(self, q: object) -> bool:
        """The fast paths' one test: ``q`` is a float64 (n,) ndarray, finite, that passes the degrees
        check (:meth:`check_radians`) without computing it — ``hypot(*q) ≤ r`` (one C call; NaN and
        inf fail it), or every entry within ``[lo₁, hi₁]`` with ``hypot`` finite (see
        :func:`robokit._units.fast_bounds`). False sends the caller to the checked path, which gives
        the same answer or the error."""
        if type(q) is not _ND or q.dtype is not _F64 or q.shape != self._shape:
            return False
        t = q.tolist()
        h = hypot(*t)
        if h <= self._r1:
            return True
        if h < _INF:  # finite (NaN fails the comparison): the extremes of the sorted list, both in [lo₁, hi₁]
            t.sort()  # one C call on the list tolist made (min and max are two slower ones)
            return self._lo1 <= t[0] and t[-1] <= self._hi1
        return False

    def _dynamics(self, fn: Callable[..., np.ndarray], method: str, q: ArrayLike, dq: ArrayLike, x: ArrayLike,
                  x_name: str, threads: int) -> np.ndarray:
        """:meth:`rnea` (``fn`` Pinocchio's rnea, x = q̈ named ``"ddq"``) and :meth:`aba` (aba, x = τ,
        ``"tau"``). The fast path: float64 (n,) arrays straight to Pinocchio (which returns a new
        array); a NaN or inf in dq or x reaches the result, so one test of the result stands for
        theirs (hypot: inf or NaN for a non-finite entry, never an overflow). Else an (N, n) q goes
        to the batch (deprecated), and anything else is checked vector by vector before Pinocchio's
        answer."""
        if (type(dq) is type(x) is _ND and dq.dtype is x.dtype is _F64
                and dq.shape == x.shape == self._shape and self._fast(q)):
            out = fn(self.model, self.data, q if self._same_coords else self.q_pin(q), dq, x)
            if hypot(*out.tolist()) < _INF:
                return out
        elif ndim(q, "q") == 2:
            # the registry keys written out (tests/test_deprecations.py reads them from the source)
            if method == "rnea":
                warn_once("Robot.rnea((N, n) q)")
            else:
                warn_once("Robot.aba((N, n) q)")
            return _batch(method, self, q, dq, x, threads)
        q, dq, x = self._check_q(q), self._check_q(dq, "dq"), self._check_q(x, x_name)
        return fn(self.model, self.data, self.q_pin(q), dq, x)

    # ------------------------------------------------------------ fast answers
    def frame_pose(self, q: ArrayLike, frame: str | None = None) -> np.ndarray:
        """Pose of ``frame`` in the root frame at joint values q (forward kinematics, Pinocchio).

        Parameters
        ----------
        q : array_like, shape (n,)
            Joint values (rad or m). For many configurations call :meth:`frame_pose_batch` (an
            (N, n) ``q`` still goes there, with a ``DeprecationWarning``, until robokit 0.4.0).
        frame : str or None, optional
            A frame name (None: the tip).

        Returns
        -------
        numpy.ndarray, shape (4, 4)
            ``T_base_frame``: rotation and position (m) of the frame in the root frame.

        Examples
        --------
        The planar arm (link lengths 1 and 0.8) stretched along x, then with the elbow at 90°:

        >>> robot = rk.load("twolink")
        >>> robot.frame_pose([0.0, 0.0])[:3, 3].round(4).tolist()
        [1.8, 0.0, 0.0]
        >>> robot.frame_pose([0.0, np.pi / 2])[:3, 3].round(4).tolist()
        [1.0, 0.8, 0.0]
        """
        if self._fast(q):
            qp = q if self._same_coords else self.q_pin(q)
        elif ndim(q, "q") == 2:
            warn_once("Robot.frame_pose((N, n) q)")
            return _batch("frame_pose", self, q, frame)
        else:
            qp = self.q_pin(self._check_q(q))
        model, data = self.model, self.data
        self._fk(model, data, qp)
        return self._frame_placement(model, data, self.tip_id if frame is None else self.frame_id(frame)).homogeneous

    def frame_poses(self, q: ArrayLike) -> dict[str, np.ndarray]:
        """Poses (4×4, in the root frame) of the frames :attr:`frame_names`, by name, at θ.

        Parameters
        ----------
        q : array_like, shape (n,)
            Joint values (rad for revolute, m for prismatic joints).

        Returns
        -------
        dict of str to numpy.ndarray, shape (4, 4)
            Frame name → its pose in the root frame (m).

        Examples
        --------
        >>> poses = rk.load("twolink").frame_poses([0.0, 0.0])
        >>> poses["dh_1"][:3, 3].round(4).tolist(), poses["tool"][:3, 3].round(4).tolist()
        ([1.0, 0.0, 0.0], [1.8, 0.0, 0.0])
        """
        pin = self._pin
        pin.framesForwardKinematics(self.model, self.data, self.q_pin(self._check_q(q)))
        return {name: self.data.oMf[self.frame_id(name)].homogeneous for name in self.frame_names}

    def jacobian(self, q: ArrayLike, frame: str | None = None, reference: Frame | str | None = None) -> np.ndarray:
        """6×n Jacobian of ``frame`` at θ, **angular rows first** (ω; v).

        Parameters
        ----------
        q : array_like, shape (n,)
            Joint values (rad or m); for many configurations :meth:`jacobian_batch`.
        frame : str or None, optional
            The frame whose motion is described (None: the tip).
        reference : Frame or str, optional
            Where the twist is expressed (:class:`robokit.Frame`, the *Conventions* page):
            ``Frame.WORLD`` — the space Jacobian (twist of the frame taken at the root origin, root
            axes); ``Frame.LOCAL`` — the body Jacobian (frame's own axes, at its origin);
            ``Frame.LOCAL_WORLD_ALIGNED`` — the course's geometric Jacobian (ω and the velocity of
            the frame origin, root axes), the one default of robokit (used when omitted; before
            0.3 this method defaulted to WORLD: pass ``reference=Frame.WORLD`` for that result).

        Returns
        -------
        numpy.ndarray, shape (6, n)
            Rows (ω; v): rad/s and m/s per unit joint rate.

        Examples
        --------
        >>> import robokit as rk
        >>> robot = rk.load("twolink")
        >>> robot.jacobian([0.0, 0.0], reference=rk.Frame.LOCAL_WORLD_ALIGNED)[3:5].round(4).tolist()
        [[0.0, 0.0], [1.8, 0.8]]
        """
        rf = self._ref_frames.get(reference)
        if rf is not None and frame is None and self._plain and self._fast(q):
            # the fast path (tip frame, finite float64 (n,) q, no continuous joints): one Pinocchio call
            # and the (v; ω) → (ω; v) row swap into a new array, nothing else
            return self._frame_jacobian(self.model, self.data, q, self.tip_id, rf).take(self._swap, 0)
        if rf is None:
            # the shared vocabulary (robokit.Frame) mapped onto Pinocchio's, looked up once per spelling
            rf = self._ref_frames[reference] = reference_or_default(reference, "Robot.jacobian").pinocchio
        if self._fast(q):
            qp = q if self._same_coords else self.q_pin(q)
        elif ndim(q, "q") == 2:
            warn_once("Robot.jacobian((N, n) q)")
            return _batch("jacobian", self, q, frame, reference_or_default(reference, "Robot.jacobian"))
        else:
            qp = self.q_pin(self._check_q(q))
        fid = self.tip_id if frame is None else self.frame_id(frame)
        J = self._frame_jacobian(self.model, self.data, qp, fid, rf)
        return J.reshape(6, self.n).take(self._swap, axis=0)  # (a one-joint chain's 6×1 comes back as (6,))

    def rnea(self, q: ArrayLike, dq: ArrayLike, ddq: ArrayLike, threads: int = 1) -> np.ndarray:
        """Inverse dynamics τ = M(q)q̈ + c(q, q̇) + g(q), Pinocchio's RNEA.

        Parameters
        ----------
        q, dq, ddq : array_like, shape (n,)
            Joint values, rates and accelerations (rad, rad/s, rad/s²; m, m/s, m/s² for prismatic
            joints); for many states :meth:`rnea_batch`.
        threads : int, optional
            Deprecated with (N, n) inputs (:meth:`rnea_batch` takes it).

        Returns
        -------
        numpy.ndarray, shape (n,)
            Joint torques (N·m) or forces (N).

        Examples
        --------
        Held still and horizontal, the arm needs its gravity torques:

        >>> robot = rk.load("twolink")
        >>> robot.rnea([0.0, 0.0], [0.0, 0.0], [0.0, 0.0]).round(4)
        array([46.107, 11.772])
        """
        return self._dynamics(self._rnea, "rnea", q, dq, ddq, "ddq", threads)

    def crba(self, q: ArrayLike) -> np.ndarray:
        """Mass matrix M(q), Pinocchio's CRBA (both triangles filled).

        Parameters
        ----------
        q : array_like, shape (n,)
            Joint values (rad or m); for many configurations :meth:`crba_batch`.

        Returns
        -------
        numpy.ndarray, shape (n, n)
            The symmetric positive-definite joint-space inertia (kg·m², kg).

        Examples
        --------
        >>> rk.load("twolink").crba([0.0, 0.0]).round(4)
        array([[6.86, 2.16],
               [2.16, 0.96]])
        """
        # Pinocchio's Python crba returns a new, symmetric array: its binding mirrors the upper triangle
        # the algorithm computes into the lower one (make_symmetric in bindings/python/algorithm/expose-crba.cpp)
        if self._fast(q):
            return self._crba(self.model, self.data, q if self._same_coords else self.q_pin(q))
        if ndim(q, "q") == 2:
            warn_once("Robot.crba((N, n) q)")
            return _batch("crba", self, q)
        return self._crba(self.model, self.data, self.q_pin(self._check_q(q)))

    def aba(self, q: ArrayLike, dq: ArrayLike, tau: ArrayLike, threads: int = 1) -> np.ndarray:
        """Forward dynamics q̈ = M⁻¹(τ − c − g), Pinocchio's ABA.

        Parameters
        ----------
        q, dq, tau : array_like, shape (n,)
            Joint values (rad, m), rates (rad/s, m/s) and torques (N·m, N); for many states
            :meth:`aba_batch`.
        threads : int, optional
            Deprecated with (N, n) inputs (:meth:`aba_batch` takes it).

        Returns
        -------
        numpy.ndarray, shape (n,)
            Joint accelerations (rad/s², m/s²).

        Examples
        --------
        Torques equal to gravity's hold the arm still:

        >>> robot = rk.load("twolink")
        >>> bool(abs(robot.aba([0.0, 0.0], [0.0, 0.0], robot.gravity_torques([0.0, 0.0]))).max() < 1e-9)
        True
        """
        return self._dynamics(self._aba, "aba", q, dq, tau, "tau", threads)

    def gravity_torques(self, q: ArrayLike) -> np.ndarray:
        """Gravity torques g(q): what the joints must apply to hold the arm still at q.

        Parameters
        ----------
        q : array_like, shape (n,)
            Joint values (rad for revolute, m for prismatic joints); for many configurations
            :meth:`rnea_batch` with zero rates and accelerations.

        Returns
        -------
        numpy.ndarray, shape (n,)
            Torques (N·m) or forces (N).

        Examples
        --------
        >>> rk.load("twolink").gravity_torques([0.0, 0.0]).round(4)
        array([46.107, 11.772])
        """
        if self._fast(q):
            return self._gravity(self.model, self.data, q if self._same_coords else self.q_pin(q))  # a new array
        return self._gravity(self.model, self.data, self.q_pin(self._check_q(q)))

    # ------------------------------------------------------------ batches
    def frame_pose_batch(self, Q: ArrayLike, frame: str | None = None) -> np.ndarray:
        """Tip poses for many configurations at once (compiled PoE kernel).

        Parameters
        ----------
        Q : array_like, shape (N, n)
            Joint values, one configuration per row (rad or m).
        frame : str or None, optional
            None or the tip: batches answer for the tip only.

        Returns
        -------
        numpy.ndarray, shape (N, 4, 4)
            ``T_base_tip`` for each row, as :meth:`frame_pose` (m).

        Examples
        --------
        >>> robot = rk.load("twolink")
        >>> robot.frame_pose_batch([[0.0, 0.0], [0.0, np.pi / 2]])[:, :2, 3].round(4).tolist()
        [[1.8, 0.0], [1.0, 0.8]]
        """
        from robokit.description.batch import batch_frame_pose

        return batch_frame_pose(self, Q, frame)

    def jacobian_batch(self, Q: ArrayLike, frame: str | None = None,
                       reference: Frame | str | None = None) -> np.ndarray:
        """Tip Jacobians for many configurations at once, angular rows first (compiled PoE kernel).

        Parameters
        ----------
        Q : array_like, shape (N, n)
            Configurations as rows of joint values (rad or m).
        frame : str or None, optional
            Must be None or the tip's name (a batch answers for the tip only).
        reference : Frame or str, optional
            As :meth:`jacobian` (default ``Frame.LOCAL_WORLD_ALIGNED``).

        Returns
        -------
        numpy.ndarray, shape (N, 6, n)
            One Jacobian per row, rows (ω; v).

        Examples
        --------
        >>> rk.load("twolink").jacobian_batch([[0.0, 0.0]])[0, 3:5].round(4).tolist()
        [[0.0, 0.0], [1.8, 0.8]]
        """
        from robokit.description.batch import batch_jacobian

        return batch_jacobian(self, Q, frame, reference_or_default(reference, "Robot.jacobian"))

    def rnea_batch(self, Q: ArrayLike, dQ: ArrayLike, ddQ: ArrayLike, threads: int = 1) -> np.ndarray:
        """Inverse dynamics for many states at once (Pinocchio's ``rneaInParallel``).

        Parameters
        ----------
        Q, dQ, ddQ : array_like, shape (N, n)
            Joint values, rates and accelerations, one state per row (rad, rad/s, rad/s²; m for prismatic).
        threads : int, optional
            Threads of ``rneaInParallel``.

        Returns
        -------
        numpy.ndarray, shape (N, n)
            Joint torques (N·m) or forces (N), as :meth:`rnea` per row.

        Examples
        --------
        >>> z = np.zeros((2, 2))
        >>> rk.load("twolink").rnea_batch(z, z, z).round(4).tolist()
        [[46.107, 11.772], [46.107, 11.772]]
        """
        from robokit.description.batch import batch_rnea

        return batch_rnea(self, Q, dQ, ddQ, threads)

    def crba_batch(self, Q: ArrayLike) -> np.ndarray:
        """Mass matrices for many configurations at once (compiled composite-rigid-body kernel).

        Parameters
        ----------
        Q : array_like, shape (N, n)
            Joint values, one configuration per row (rad or m).

        Returns
        -------
        numpy.ndarray, shape (N, n, n)
            M(q) for each row, as :meth:`crba` (kg·m², kg).

        Examples
        --------
        >>> rk.load("twolink").crba_batch([[0.0, 0.0]])[0].round(4).tolist()
        [[6.86, 2.16], [2.16, 0.96]]
        """
        from robokit.description.batch import batch_crba

        return batch_crba(self, Q)

    def aba_batch(self, Q: ArrayLike, dQ: ArrayLike, tau: ArrayLike, threads: int = 1) -> np.ndarray:
        """Forward dynamics for many states at once (Pinocchio's ``abaInParallel``).

        Parameters
        ----------
        Q, dQ, tau : array_like, shape (N, n)
            Joint values, rates and torques, one state per row (rad, rad/s, N·m; m, m/s, N).
        threads : int, optional
            Threads of ``abaInParallel``.

        Returns
        -------
        numpy.ndarray, shape (N, n)
            Joint accelerations, as :meth:`aba` per row (rad/s², m/s²).

        Examples
        --------
        >>> robot = rk.load("twolink")
        >>> z = np.zeros((1, 2))
        >>> bool(abs(robot.aba_batch(z, z, robot.gravity_torques([0.0, 0.0])[None])).max() < 1e-9)
        True
        """
        from robokit.description.batch import batch_aba

        return batch_aba(self, Q, dQ, tau, threads)

    def nonlinear_effects(self, q: ArrayLike, dq: ArrayLike) -> np.ndarray:
        """Coriolis, centrifugal and gravity torques c(q, q̇) + g(q) (Pinocchio's nonLinearEffects).

        Parameters
        ----------
        q : array_like, shape (n,)
            Joint values (rad for revolute, m for prismatic joints).
        dq : array_like, shape (n,)
            Joint rates (rad/s, m/s).

        Returns
        -------
        numpy.ndarray, shape (n,)
            Torques (N·m) or forces (N): τ for q̈ = 0.

        Examples
        --------
        >>> rk.load("twolink").nonlinear_effects([0.0, 0.0], [0.0, 0.0]).round(4)
        array([46.107, 11.772])
        """
        q = self.q_pin(self._check_q(q))
        return self._pin.nonLinearEffects(self.model, self.data, q, self._check_q(dq, "dq")).copy()

    def random_configuration(self, rng: int | np.random.Generator | None = None) -> np.ndarray:
        """Joint values drawn uniformly inside the limits ([−π, π] for unlimited joints).

        Parameters
        ----------
        rng : int, numpy.random.Generator or None, optional
            A seed or a generator (None: fresh entropy).

        Returns
        -------
        numpy.ndarray, shape (n,)
            Joint values (rad or m), each within ``qlim``.

        Examples
        --------
        >>> robot = rk.load("twolink")
        >>> q = robot.random_configuration(0)
        >>> q.shape, bool(((robot.qlim[:, 0] <= q) & (q <= robot.qlim[:, 1])).all())
        ((2,), True)
        """
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

    #: ``spec.kind`` → the format the repr names.
    _FORMATS = {"urdf": "URDF", "xacro": "xacro", "mjcf": "MJCF", "sdf": "SDF", "calibrated": "calibrated URDF", "example-robot-data":
                "URDF of example-robot-data"}

    def __repr__(self) -> str:
        if self.dh is not None:
            kind = f"DH {self.dh.convention}"
        else:
            spec_kind = self.spec.kind if self.spec is not None else None
            fmt = self._FORMATS.get(spec_kind or "", spec_kind.upper() if spec_kind else "Pinocchio model")
            kind = f"{fmt}; its DH table: robokit.dh_from_urdf(robot).table"
        return f"Robot({self.name!r}, {self.n} joints, tip={self.tip!r}, {kind})"



def _batch(method: str, robot: Robot, *args: Any) -> np.ndarray:
    """The deprecated (N, n) path of ``Robot.<method>``: :mod:`robokit.description.batch`'s function,
    called through this private frame so that the degrees check names the user's call."""
    from robokit.description import batch

    fn: Callable[..., np.ndarray] = getattr(batch, f"batch_{method}")
    return fn(robot, *args)


def _read_only(a: ArrayLike) -> np.ndarray:
    """A read-only float64 copy of ``a``."""
    out = np.array(a, dtype=float)
    out.setflags(write=False)
    return out


def _frozen_poe(poe: PoEParams) -> PoEParams:
    """``poe`` with every array replaced by a read-only view of it (the arrays themselves stay
    writeable, for the kernels: :func:`robokit._arrays.writeable_base`)."""
    from dataclasses import fields, replace

    views = {}
    for f in fields(poe):
        a = getattr(poe, f.name)
        if isinstance(a, np.ndarray):
            v = a.view()
            v.flags.writeable = False
            views[f.name] = v
    return replace(poe, **views)


def _frozen_message(name: str) -> str:
    return (f"Robot is immutable: cannot set or delete {name!r}; make a changed copy with "
            "robot.with_limits(qlim) (joint limits) or robot.with_tool(T_tip_tool) (a tool frame), "
            "or load another robot")


def check_robot_radians(robot: Any, q: ArrayLike, name: str, *, state: bool = True) -> bool:
    """The degrees check (:mod:`robokit._units`) of joint values given for ``robot``.

    For a :class:`Robot`, :meth:`Robot.check_radians`; for another RobotLike (which says nothing
    of its joint kinds) every joint is checked as revolute against its ``qlim`` — a value beyond a
    full turn and past its limits.

    Parameters
    ----------
    robot : Robot or RobotLike
        The robot the values are for.
    q, name
        As in :meth:`Robot.check_radians`.
    state : bool
        As in :meth:`Robot.check_radians`, but True by default: the callers pass IK seeds,
        trajectories' points and simulations' states.

    Returns
    -------
    bool
        As :meth:`Robot.check_radians` returns it.

    Examples
    --------
    >>> check_robot_radians(rk.load("ur5"), np.zeros(6), "q0")
    False
    """
    if isinstance(robot, Robot):
        return robot.check_radians(q, name, state=state)
    qlim = np.asarray(getattr(robot, "qlim", np.full((int(robot.n), 2), [-np.inf, np.inf])), dtype=float)
    lo, hi = radian_ranges(np.ones(len(qlim), dtype=bool), qlim)
    return check_radians(np.asarray(q, dtype=float), lo, hi, name, str(getattr(robot, "name", "")))
