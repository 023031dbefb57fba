r"""The Robot type and ``load``: one robot, its Pinocchio model, its course parameters.

A :class:`Robot` holds a serial chain root → tip as a Pinocchio ``Model`` (joints off the
chain — a gripper's fingers — locked at their neutral value and their bodies merged), one
``Data`` workspace reused by every call, the chain's product-of-exponentials parameters
(:class:`~robokit.description.poe.PoEParams`) and, for robots described by a DH file, the
:class:`~robokit.description.dh.DHTable`.

All methods take **joint angles** θ (n,) — one number per joint, continuous joints
included — and convert to Pinocchio's configuration q internally (a continuous joint's
q is (cos θ, sin θ)). Jacobians are returned **angular first**, ``(ω; v)``.

``load(name_or_path)`` accepts a shipped model name (``models/<name>.yaml``), a DH
``.yaml`` file, a ``.urdf`` file, or an example-robot-data name (``ur5``, ``panda``, ``z1``,
``xarm7``, ``kinova``, …).
"""
from __future__ import annotations

import os
from pathlib import Path
from typing import Any, Iterable, Literal, Mapping, Sequence

import numpy as np
from numpy.typing import ArrayLike

from robokit._arrays import as_joints, ndim
from robokit.description.dh import DHTable
from robokit.description.poe import PoEParams, poe_from_model
from robokit.errors import InputError, RobokitWarning

__all__ = ["Robot", "load", "serial_chain", "choose_tip", "EXAMPLE_ROBOT_TIPS"]

#: Default tip frames of the example-robot-data arms (the last link of the arm's chain,
#: a gripper's fingers excluded).
EXAMPLE_ROBOT_TIPS = {
    "ur3": "tool0",
    "ur5": "tool0",
    "ur10": "tool0",
    "panda": "panda_hand_tcp",
    "z1": "link06",
    "xarm7": "link_eef",
    "kinova": "j2s6s200_end_effector",
}

_ONE_DOF = {
    "JointModelRX", "JointModelRY", "JointModelRZ", "JointModelRevoluteUnaligned",
    "JointModelRUBX", "JointModelRUBY", "JointModelRUBZ", "JointModelRevoluteUnboundedUnaligned",
    "JointModelPX", "JointModelPY", "JointModelPZ", "JointModelPrismaticUnaligned",
}


def _frame_depth(model: Any, fid: int) -> int:
    depth = 0
    while model.frames[fid].parentFrame != fid and fid != 0:
        fid = model.frames[fid].parentFrame
        depth += 1
    return depth


def _deepest_body_frame(model: Any, joint: int) -> str | None:
    best, best_depth = None, -1
    for fid, fr in enumerate(model.frames):
        if fr.parentJoint == joint and fr.type == _body_type():
            d = _frame_depth(model, fid)
            if d >= best_depth:
                best, best_depth = fr.name, d
    return best


def _tip_candidates(model: Any, children: Mapping[int, list[int]]) -> list[tuple[str, int]]:
    """(leaf frame, joints from the root) for every leaf joint of the kinematic tree."""
    out = []
    for j in range(1, model.njoints):
        if not children[j]:
            depth, k = 0, j
            while k != 0:
                depth, k = depth + 1, model.parents[k]
            name = _deepest_body_frame(model, j)
            if name is not None:
                out.append((name, depth))
    return sorted(out, key=lambda c: (-c[1], c[0]))


def choose_tip(model: Any) -> tuple[str, str]:
    """The default tip frame of a model and a note saying how it was chosen ("" if obvious).

    From the root, follow the joints while each has exactly one child joint. At a branch:
    if every branch is a single joint (a gripper's fingers), the tip is the deepest body frame
    fixed to the current joint; if exactly one branch is longer than all others, follow it
    (the longest chain — an arm rather than a head, a caster or a sensor); if two or more
    branches tie for longest (two arms, four legs), there is no sensible default and
    ``ValueError`` lists the candidate tips with their chain lengths.
    """
    children: dict[int, list[int]] = {j: [] for j in range(model.njoints)}
    for j in range(1, model.njoints):
        children[model.parents[j]].append(j)

    def depth(j: int) -> int:
        return 1 + max((depth(c) for c in children[j]), default=0)

    j, chose = 0, False
    while children[j]:
        if len(children[j]) == 1:
            j = children[j][0]
            continue
        depths = sorted(((depth(c), c) for c in children[j]), reverse=True)
        if depths[0][0] <= 1 and j != 0:
            break  # fingers
        if depths[0][0] == depths[1][0]:
            cands = _tip_candidates(model, children)
            shown = ", ".join(f"{name} ({d} joint{'s' if d != 1 else ''})" for name, d in cands[:10])
            raise InputError(
                f"tip: the robot is a tree with {len(cands)} ends and no single longest chain; choose one "
                f"with tip= (--tip): {shown}"
            )
        j, chose = depths[0][1], True
    tip = _deepest_body_frame(model, j)
    if tip is None:
        raise InputError("model: no body frame found for the chain's tip")
    note = f"the robot is a tree; chose its longest chain, to {tip!r} (give --tip for another)" if chose else ""
    return tip, note


def default_tip(model: Any) -> str:
    """The default tip frame of a model (see :func:`choose_tip`)."""
    return choose_tip(model)[0]


def _body_type() -> Any:
    import pinocchio as pin

    return pin.FrameType.BODY


def serial_chain(model: Any, tip: str, geometry_models: Iterable[Any] = ()) -> tuple[Any, list[str], list[Any]]:
    """The chain root → ``tip`` of a Pinocchio model, other joints locked at neutral.

    Returns ``(chain_model, locked_joint_names, geometry_models)``. Raises ``ValueError`` for
    a tip that does not exist (listing some that do) or a joint on the chain that is not a
    one-degree-of-freedom revolute/prismatic/continuous joint (e.g. a floating base).
    """
    import pinocchio as pin

    if not model.existFrame(tip):
        bodies = [f.name for f in model.frames if f.type == pin.FrameType.BODY]
        shown = ", ".join(bodies[-12:])
        raise InputError(f"tip: no frame {tip!r}; frames include: {shown}")
    fid = model.getFrameId(tip)
    chain = []
    j = model.frames[fid].parentJoint
    while j != 0:
        chain.append(j)
        j = model.parents[j]
    chain.reverse()
    for j in chain:
        sn = model.joints[j].shortname()
        if sn not in _ONE_DOF:
            kind = "floating base" if sn == "JointModelFreeFlyer" else sn
            raise InputError(
                f"model: joint {model.names[j]!r} on the chain to {tip!r} is a {kind}; robokit handles fixed-base "
                "serial chains of revolute, prismatic and continuous joints"
            )
    lock = [j for j in range(1, model.njoints) if j not in chain]
    if not lock:
        return model, [], list(geometry_models)
    q0 = pin.neutral(model)
    if geometry_models:
        reduced, geoms = pin.buildReducedModel(model, list(geometry_models), lock, q0)
        return reduced, [model.names[j] for j in lock], list(geoms)
    reduced = pin.buildReducedModel(model, lock, q0)
    return reduced, [model.names[j] for j in lock], []


class Robot:
    """One serial robot: Pinocchio model and data, PoE parameters, DH table when it has one.

    Attributes
    ----------
    name : str; model, data : the chain's ``pinocchio.Model`` and its reused ``Data``;
    visual_model, collision_model : ``pinocchio.GeometryModel`` or None;
    tip : tip frame name; tip_id : its frame id; dh : :class:`DHTable` or None;
    poe : :class:`PoEParams`; n : number of joint angles; joint_names : (n,);
    qlim : (n, 2) joint limits (±inf for continuous joints); gravity : (3,);
    configurations : dict of named configurations (joint angles), "zero" always;
    locked_joints : names of the joints locked off the chain; source : where it came from.
    """

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
        if ndim(q, "q") == 2:
            from robokit.description.batch import batch_frame_pose

            return batch_frame_pose(self, q, frame)
        pin = self._pin
        q = self.q_pin(self._check_q(q))
        pin.forwardKinematics(self.model, self.data, q)
        return pin.updateFramePlacement(self.model, self.data, self.frame_id(frame)).homogeneous

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
        if ndim(q, "q") == 2:
            from robokit.description.batch import batch_jacobian

            return batch_jacobian(self, q, frame, reference)
        pin = self._pin
        try:
            rf = getattr(pin.ReferenceFrame, self._REFS[reference])
        except KeyError:
            raise InputError(f"reference: expected one of {sorted(self._REFS)}, got {reference!r}") from None
        q = self.q_pin(self._check_q(q))
        J = pin.computeFrameJacobian(self.model, self.data, q, self.frame_id(frame), rf)
        return J.reshape(6, self.n)[self._swap]  # (a one-joint chain's 6×1 comes back from Pinocchio as (6,))

    def rnea(self, q: ArrayLike, dq: ArrayLike, ddq: ArrayLike, threads: int = 1) -> np.ndarray:
        """Inverse dynamics τ = M(q)q̈ + c(q, q̇) + g(q) (n,), Pinocchio's RNEA; for (N, n)
        inputs, (N, n) through ``rneaInParallel`` on ``threads`` threads."""
        if ndim(q, "q") == 2:
            from robokit.description.batch import batch_rnea

            return batch_rnea(self, q, dq, ddq, threads)
        q = self.q_pin(self._check_q(q))
        dq, ddq = self._check_q(dq, "dq"), self._check_q(ddq, "ddq")
        return self._pin.rnea(self.model, self.data, q, dq, ddq).copy()

    def crba(self, q: ArrayLike) -> np.ndarray:
        """Mass matrix M(q) (n×n, symmetric), Pinocchio's CRBA; for q (N, n), (N, n, n) from the
        compiled composite-rigid-body kernel."""
        if ndim(q, "q") == 2:
            from robokit.description.batch import batch_crba

            return batch_crba(self, q)
        q = self.q_pin(self._check_q(q))
        M = self._pin.crba(self.model, self.data, q).copy()  # Pinocchio fills the upper triangle
        M[self._lower] = M.T[self._lower]
        return M

    def aba(self, q: ArrayLike, dq: ArrayLike, tau: ArrayLike, threads: int = 1) -> np.ndarray:
        """Forward dynamics q̈ = M⁻¹(τ − c − g) (n,), Pinocchio's ABA; for (N, n) inputs, (N, n)
        through ``abaInParallel`` on ``threads`` threads."""
        if ndim(q, "q") == 2:
            from robokit.description.batch import batch_aba

            return batch_aba(self, q, dq, tau, threads)
        q = self.q_pin(self._check_q(q))
        dq, tau = self._check_q(dq, "dq"), self._check_q(tau, "tau")
        return self._pin.aba(self.model, self.data, q, dq, tau).copy()

    def gravity_torques(self, q: ArrayLike) -> np.ndarray:
        """Gravity torques g(θ) (n,)."""
        q = self.q_pin(self._check_q(q))
        return self._pin.computeGeneralizedGravity(self.model, self.data, q).copy()

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

    def __repr__(self) -> str:
        kind = f"DH {self.dh.convention}" if self.dh is not None else "URDF"
        return f"Robot({self.name!r}, {self.n} joints, tip={self.tip!r}, {kind})"


def _from_dh(table: DHTable, source: str) -> Robot:
    import pinocchio as pin

    from robokit.description.limits import check_joint_count
    from robokit.description.urdf_gen import dh_to_urdf

    check_joint_count(len(table.links), source, "links (joints)")  # before Pinocchio builds anything
    xml = dh_to_urdf(table)
    model = pin.buildModelFromXML(xml)
    model.gravity.linear = np.asarray(table.gravity, dtype=float)
    try:
        visual = pin.buildGeomFromUrdfString(model, xml, pin.GeometryType.VISUAL)
        collision = pin.buildGeomFromUrdfString(model, xml, pin.GeometryType.COLLISION)
    except Exception:  # pragma: no cover - geometry is optional
        visual = collision = None
    return Robot(table.name, model, "tool", visual_model=visual, collision_model=collision, dh=table, source=source)


def _from_urdf_file(path: Path, tip: str | None, package_dirs: Sequence[str | os.PathLike[str]] | None = None,
                    allow_outside_meshes: bool = False, text: str | None = None) -> Robot:
    """A Robot from a URDF file (or the URDF ``text`` a xacro file expanded to, named by ``path``)."""
    import pinocchio as pin

    from robokit.description.urdf_check import capture_native_output, read_urdf

    doc = read_urdf(path, package_dirs=package_dirs, allow_outside_meshes=allow_outside_meshes, text=text)
    with capture_native_output() as cap:
        try:
            model = pin.buildModelFromXML(doc.xml)
        except Exception as exc:
            failed: Exception | None = exc
        else:
            failed = None
    if failed is not None:
        why = cap.first_error() or _one_line(failed)
        raise InputError(f"{path}: Pinocchio cannot read this URDF ({why})") from None
    geoms, notes = [], []
    for gtype in (pin.GeometryType.VISUAL, pin.GeometryType.COLLISION):
        with capture_native_output() as cap:
            try:
                geoms.append(pin.buildGeomFromUrdfString(model, doc.xml, gtype, package_dirs=doc.package_dirs))
                err = None
            except Exception as exc:
                geoms.append(None)
                err = cap.first_error() or _one_line(exc)
        if err:
            notes.append(f"{path}: {gtype.name.lower()} geometry not loaded ({err}); drawn without it")
    return _finish(doc.name, model, tip, geoms, {}, str(path), notes, mimic=doc.mimic)


def _one_line(exc: BaseException) -> str:
    text = str(exc).strip()
    return text.splitlines()[0][:200] if text else type(exc).__name__


def _finish(name: str, model: Any, tip: str | None, geoms: list[Any], configurations: Mapping[str, ArrayLike],
            source: str, notes: Iterable[str] = (), mimic: Mapping[str, str] | None = None) -> Robot:
    import warnings

    notes = list(notes)
    if tip is None:
        tip, note = choose_tip(model)
        if note:
            notes.append(f"{name}: {note}")
    valid = [g for g in geoms if g is not None]
    chain, locked, new_geoms = serial_chain(model, tip, valid)
    if chain.nv == 0:
        raise InputError(f"{source}: the chain to {tip!r} has no moving joint; robokit needs at least one")
    for jn, target in (mimic or {}).items():
        if jn not in locked:
            raise InputError(
                f"{source}: joint {jn!r} mimics {target!r} and is on the chain to {tip!r}; robokit's joints are "
                "independent — remove the <mimic> or choose another tip"
            )
    if mimic and any(j in locked for j in mimic):
        notes.append(f"{name}: mimic joints off the chain locked: {', '.join(j for j in mimic if j in locked)}")
    it = iter(new_geoms)
    geoms = [next(it) if g is not None else None for g in geoms]
    robot = Robot(name, chain, tip, visual_model=geoms[0], collision_model=geoms[1],
                  configurations=configurations, locked_joints=locked, source=source)
    robot.notes.extend(notes)
    for note in notes:
        warnings.warn(note, RobokitWarning, stacklevel=3)
    return robot


def _from_example_robot_data(name: str, tip: str | None) -> Robot:
    import example_robot_data as erd

    loader = erd.ROBOTS[name]
    notes = []
    try:
        with _quiet():
            if getattr(loader, "free_flyer", False):
                # Loaded with its base fixed to the world: a fixed-base arm (so100) is then what its
                # URDF describes; a mobile or legged robot's limbs are then chains like any other.
                wrapper = type(loader.__name__, (loader,), {"free_flyer": False})().robot
                notes.append(f"{name}: example-robot-data gives it a floating base; loaded with the base fixed "
                             "to the world")
            else:
                wrapper = erd.load(name)
    except Exception as exc:  # a dependency's failure is still one robokit line
        raise InputError(f"model {name!r}: example-robot-data could not load it ({_one_line(exc)})") from None
    model = wrapper.model
    tip = tip or EXAMPLE_ROBOT_TIPS.get(name)
    if tip is None:
        try:
            tip, note = choose_tip(model)
        except ValueError as exc:
            raise InputError(f"model {name!r}: {exc}") from None
        if note:
            notes.append(f"{name}: {note}")
    configurations = {}
    q0 = getattr(wrapper, "q0", None)
    chain_names = []
    if model.existFrame(tip):
        j = model.frames[model.getFrameId(tip)].parentJoint
        while j != 0:
            chain_names.append(model.names[j])
            j = model.parents[j]
        chain_names.reverse()
    if q0 is not None and chain_names and len(q0) == model.nq:
        angles = []
        for jn in chain_names:
            jm = model.joints[model.getJointId(jn)]
            qs = q0[jm.idx_q: jm.idx_q + jm.nq]
            angles.append(float(np.arctan2(qs[1], qs[0])) if jm.nq == 2 else float(qs[0]))
        if np.any(angles):
            configurations["ready"] = np.array(angles)
    return _finish(name, model, tip, [wrapper.visual_model, wrapper.collision_model], configurations,
                   f"example-robot-data:{name}", notes)


class _quiet:
    """Silence C/C++ output on fd 2 and Python prints while a dependency loads a model."""

    def __enter__(self) -> _quiet:
        import contextlib
        import io

        from robokit.description.urdf_check import capture_native_output

        self._cap = capture_native_output()
        self._cap.__enter__()
        self._out = contextlib.redirect_stdout(io.StringIO())
        self._out.__enter__()
        return self

    def __exit__(self, *exc: Any) -> Literal[False]:
        self._out.__exit__(*exc)
        self._cap.__exit__(*exc)
        return False


def _example_robot_names() -> list[str]:
    try:
        import example_robot_data as erd

        return sorted(getattr(erd, "ROBOTS", {}).keys())
    except Exception:  # pragma: no cover
        return []


def load(name_or_path: str | os.PathLike[str] | Robot | DHTable, tip: str | None = None, *,
         package_dirs: Sequence[str | os.PathLike[str]] | None = None, xacro_args: Mapping[str, str] | None = None,
         allow_outside_meshes: bool = False) -> Robot:
    """Load a robot: a shipped model name, a DH ``.yaml``, a ``.urdf``, a ``.xacro``/``.urdf.xacro``,
    an MJCF ``.xml``, or an example-robot-data name.

    tip : the chain's tip frame (default: "tool" for DH models, the arm's end-effector
    frame for example-robot-data arms, else the end of the chain — of the longest chain for a
    tree, see :func:`choose_tip`).
    package_dirs : folders searched for ROS packages: ``package://pkg/...`` meshes of a URDF or
    xacro file, and ``$(find pkg)`` in a xacro file (a folder holding ``<pkg>/package.xml``;
    the file's own folder and the folders above it are always searched).
    xacro_args : dict of xacro argument values (``{"name": "value"}``), xacro files only.
    allow_outside_meshes : read meshes that a URDF names outside its folder, its package and
    ``package_dirs`` (absolute paths, ``../`` out of the package); refused by default.

    Example: ``robokit.load("puma560").frame_pose(np.zeros(6))``.
    """
    from robokit.description.models import models_dir, shipped_models

    if isinstance(name_or_path, Robot):
        return name_or_path
    if isinstance(name_or_path, DHTable):
        return _from_dh(name_or_path, "<DHTable>")
    s = str(name_or_path)
    path = Path(s)
    if path.suffix.lower() in (".yaml", ".yml"):
        if tip not in (None, "tool"):
            raise InputError(f"tip: a DH model's tip is its 'tool' frame, got {tip!r}")
        return _from_dh(DHTable.from_yaml(path), str(path))
    if path.name.lower().endswith(".xacro"):  # formats: xacro
        from robokit.description.xacro_files import load_xacro

        return load_xacro(path, tip, xacro_args=xacro_args, package_path=package_dirs,
                          allow_outside_meshes=allow_outside_meshes)
    if xacro_args:
        raise InputError(f"xacro_args: apply to .xacro files, got {s!r}")
    if path.suffix.lower() == ".xml":  # formats: MJCF
        from robokit.description.mjcf import load_mjcf

        return load_mjcf(path, tip, allow_outside_meshes=allow_outside_meshes)
    if path.suffix.lower() == ".urdf":
        if not path.exists():  # anything else (a FIFO, a device) is refused by the bounded reader
            raise InputError(f"{path}: file not found")
        return _from_urdf_file(path, tip, package_dirs=package_dirs, allow_outside_meshes=allow_outside_meshes)
    if s in shipped_models():
        return _from_dh(DHTable.from_yaml(models_dir() / f"{s}.yaml"), f"models/{s}.yaml")
    erd_names = _example_robot_names()
    if s in erd_names:
        return _from_example_robot_data(s, tip)
    raise InputError(
        f"model: unknown robot {s!r}; give a .yaml or .urdf file, a shipped model ({', '.join(shipped_models())}) "
        f"or an example-robot-data name (e.g. ur5, panda, z1, xarm7, kinova)"
    )
