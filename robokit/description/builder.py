r"""Building a :class:`~robokit.description.robot.Robot` from a Pinocchio model: the pieces every loader shares.

* :func:`choose_tip` — the default tip frame of a kinematic tree (the longest chain; an
  error listing the ends when two chains tie);
* :func:`serial_chain` — the chain root → tip, every other joint locked at its neutral
  value and its bodies merged (``pinocchio.buildReducedModel``);
* :func:`build_robot` — both of the above, the checks a chain must pass (at least one moving
  joint, no ``<mimic>`` joint on it), the physicality of every link that moves with the chain
  (:mod:`robokit.description.inertia`: one :class:`~robokit.errors.PhysicalityWarning` per
  impossible link, an :class:`~robokit.errors.InputError` under ``strict``) and the
  :class:`~robokit.description.spec.RobotSpec` the robot carries.

Names
    Every name robokit reports — the default tip, ``robot.frame_names`` (the keys of
    ``frame_poses``), the joints — is one the description gives. Pinocchio's parsers add
    names of their own: ``universe`` (the world frame, index 0) for every format, and for MJCF
    ``<parent>Bis`` (an unnamed body; all unnamed children of one body share it),
    ``<body>_fixed`` (the fixed joint of a body without a joint) and ``<body>Joint_<k>`` (an
    unnamed joint). A loader passes the names its file holds (``names=``); the default tip is
    then chosen among them and only they are reported (a frame Pinocchio named stays in
    ``robot.model`` for Pinocchio's use); a joint of the chain with an invented name is listed
    in a note.

The format modules (:mod:`~robokit.description.urdf_files`, :mod:`~robokit.description.xacro_files`,
:mod:`~robokit.description.mjcf`, :mod:`~robokit.description.example_robots`,
:mod:`~robokit.description.dh_robots`) read their files into a Pinocchio model and call
:func:`build_robot`; :func:`robokit.description.loading.load` picks the format.
"""
from __future__ import annotations

from contextlib import contextmanager
from contextvars import ContextVar
from typing import AbstractSet, Any, Iterable, Iterator, Mapping

import numpy as np
from numpy.typing import ArrayLike

from robokit._stack import outside_level
from robokit.description.frames import frame_index
from robokit.description.inertia import link_inertias, physicality_problem
from robokit.description.robot import Robot
from robokit.description.spec import RobotSpec
from robokit.errors import InputError, PhysicalityWarning, RobokitWarning

__all__ = ["choose_tip", "default_tip", "serial_chain", "build_robot", "strict_loading", "physicality_problems"]

#: Whether :func:`build_robot` refuses a physically impossible link (set by
#: ``robokit.load(..., strict=True)`` through :func:`strict_loading`, so that every format's
#: loader obeys it without an argument of its own).
_STRICT: ContextVar[bool] = ContextVar("robokit_strict_loading", default=False)


@contextmanager
def strict_loading(strict: bool = True) -> Iterator[None]:
    """Within this block, :func:`build_robot` raises :class:`~robokit.errors.InputError` where it
    would warn :class:`~robokit.errors.PhysicalityWarning` (``robokit.load(..., strict=True)``).

    Parameters
    ----------
    strict : bool
        Refuse (True) or warn (False).

    Yields
    ------
    None

    Examples
    --------
    >>> with strict_loading():
    ...     rk.load("ur5").n        # a physical robot loads as ever
    6
    """
    token = _STRICT.set(bool(strict))
    try:
        yield
    finally:
        _STRICT.reset(token)

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


def _deepest_body_frame(model: Any, joint: int, names: AbstractSet[str] | None = None) -> str | None:
    """The deepest body frame on ``joint`` (the last of equally deep ones) — among the frames
    named in ``names`` when given, else (no named body there) the joint's own frame if named."""
    best, best_depth = None, -1
    for fid, fr in enumerate(model.frames):
        if fr.parentJoint == joint and fr.type == _body_type() and (names is None or fr.name in names):
            d = _frame_depth(model, fid)
            if d >= best_depth:
                best, best_depth = fr.name, d
    if best is None and names is not None and model.names[joint] in names and joint != 0:
        return str(model.names[joint])
    return best


def _tip_candidates(model: Any, children: Mapping[int, list[int]], names: AbstractSet[str] | None = None,
                    mimic: AbstractSet[str] = frozenset()) -> list[tuple[str, int]]:
    """(leaf frame, joints from the root) for every leaf joint of the kinematic tree. A leaf whose chain
    holds a ``mimic`` joint (a tip robokit refuses) stands for the joint its gripper hangs on: the one
    nearest the root on that chain below which every branch has at most one joint of its own."""
    def own(j: int) -> int:  # joints that move on their own in the deepest branch from j down
        return (model.names[j] not in mimic) + max((own(c) for c in children[j]), default=0)

    out = []
    for j in range(1, model.njoints):
        if not children[j]:
            chain = _chain_to(model, j)
            if any(model.names[k] in mimic for k in chain):
                j = next((k for k in chain if all(own(c) <= 1 for c in children[k])), j)
                chain = _chain_to(model, j)
            name = _deepest_body_frame(model, j, names)
            if name is not None and (name, len(chain)) not in out:
                out.append((name, len(chain)))
    return sorted(out, key=lambda c: (-c[1], c[0]))


def _chain_to(model: Any, j: int) -> list[int]:
    """The joints from the root to joint ``j`` (``j`` included), root first."""
    chain = []
    while j != 0:
        chain.append(j)
        j = model.parents[j]
    return chain[::-1]


def _check_one_dof(model: Any, chain: list[int], where: str) -> None:
    """Refuse the first joint of ``chain`` that is not a one-degree-of-freedom revolute/prismatic/continuous
    joint (a floating base, a ball), saying ``where`` it is."""
    for j in chain:
        sn = model.joints[j].shortname()
        if sn not in _ONE_DOF:
            kind = "floating base" if sn == "JointModelFreeFlyer" else sn
            raise InputError(
                f"model: joint {model.names[j]!r} {where} is a {kind}; robokit handles fixed-base serial chains of "
                "revolute, prismatic and continuous joints"
            )


def choose_tip(model: Any, names: AbstractSet[str] | None = None,
               mimic: AbstractSet[str] = frozenset()) -> tuple[str, str]:
    """The default tip frame of a model and a note saying how it was chosen ("" if obvious).

    From the root, follow the joints while each has exactly one child joint. At a branch:
    if every branch is a single joint (a gripper's fingers), the tip is the deepest body frame
    fixed to the current joint; if exactly one branch is longer than all others, follow it
    (the longest chain — an arm rather than a head, a caster or a sensor); if two or more
    branches tie for longest (two arms, four legs), there is no sensible default and
    :class:`~robokit.errors.InputError` lists the candidate tips with their chain lengths.
    Lengths count the joints that move on their own: a ``mimic`` joint follows another and adds
    none, so a gripper's linkage (Robotiq's 2F-85: one finger joint and five mimic joints, two deep)
    counts as fingers.

    The tip is a body frame of that joint, the deepest one (a tool flange fixed to the last
    link), chosen among ``names`` when given — never a frame Pinocchio named.

    Parameters
    ----------
    model : pinocchio.Model
        The kinematic tree.
    names : set of str, optional
        The names the description gives (links, bodies, joints, frames); None: every frame.
    mimic : set of str, optional
        The names of the file's mimic joints (URDF ``<mimic>``).

    Returns
    -------
    tip : str
        The tip frame's name.
    note : str
        How it was chosen ("" when the chain has no branch to choose between).

    Examples
    --------
    >>> choose_tip(rk.load("rrr").model)      # one chain: its end, no note
    ('tool', '')
    """
    children: dict[int, list[int]] = {j: [] for j in range(model.njoints)}
    for j in range(1, model.njoints):
        children[model.parents[j]].append(j)

    def depth(j: int) -> int:
        return (model.names[j] not in mimic) + max((depth(c) for c in children[j]), default=0)

    j, chose = 0, False
    while children[j]:
        if len(children[j]) == 1:
            j = children[j][0]
            continue
        depths = sorted(((depth(c), c) for c in children[j]), reverse=True)
        if depths[0][0] <= 1 and j != 0:
            break  # fingers
        if depths[0][0] == depths[1][0]:
            # every end's chain runs through the trunk: a floating base there is said first
            _check_one_dof(model, _chain_to(model, j), "which every chain of the tree runs through,")
            cands = _tip_candidates(model, children, names, mimic)
            shown = ", ".join(f"{name} ({d} joint{'s' if d != 1 else ''})" for name, d in cands[:10])
            raise InputError(
                f"tip: the robot is a tree with {len(cands)} ends and no single longest chain; choose one "
                f"with tip= (--tip): {shown}"
            )
        j, chose = depths[0][1], True
    tip = _deepest_body_frame(model, j, names)
    while tip is None and j != 0 and names is not None:  # nothing named on the last joint: its parent's
        j = model.parents[j]
        tip = _deepest_body_frame(model, j, names)
    if tip is None:
        raise InputError("model: no body frame found for the chain's tip")
    note = f"the robot is a tree; chose its longest chain, to {tip!r} (give --tip for another)" if chose else ""
    return tip, note


def default_tip(model: Any, names: AbstractSet[str] | None = None) -> str:
    """The default tip frame of a model (see :func:`choose_tip`).

    Parameters
    ----------
    model : pinocchio.Model
    names : set of str, optional
        The names the description gives (the tip is one of them).

    Returns
    -------
    str
        The tip frame's name.

    Examples
    --------
    >>> default_tip(rk.load("rrr").model)
    'tool'
    """
    return choose_tip(model, names)[0]


def _body_type() -> Any:
    import pinocchio as pin

    return pin.FrameType.BODY


def serial_chain(model: Any, tip: str, geometry_models: Iterable[Any] = (),
                 names: AbstractSet[str] | None = None,
                 positions: Mapping[str, float] | None = None) -> tuple[Any, list[str], list[Any]]:
    """The chain root → ``tip`` of a Pinocchio model, other joints locked at neutral (or at ``positions``).

    Parameters
    ----------
    model : pinocchio.Model
        The kinematic tree.
    tip : str
        The tip frame.
    geometry_models : iterable of pinocchio.GeometryModel
        Reduced with the model (their objects re-attached to the chain's joints).
    names : set of str, optional
        The names the description gives: the frames an unknown tip's message lists.
    positions : dict of str to float, optional
        The value (rad or m) at which a joint off the chain is locked, by name (a URDF mimic joint's,
        :func:`build_robot`); every other locked joint is locked at Pinocchio's neutral (0).

    Returns
    -------
    chain_model : pinocchio.Model
    locked_joint_names : list of str
    geometry_models : list of pinocchio.GeometryModel

    Raises
    ------
    InputError
        A tip that does not exist (listing some that do) or a joint on the chain that is not
        a one-degree-of-freedom revolute/prismatic/continuous joint (e.g. a floating base).

    Examples
    --------
    The chain of the shipped 3-joint arm up to DH frame {2} locks joint 3:

    >>> import pinocchio as pin
    >>> from robokit.description.models import model_path
    >>> model = pin.buildModelFromUrdf(str(model_path("rrr", ".urdf")))
    >>> chain, locked, _ = serial_chain(model, "dh_2")
    >>> chain.nv, locked
    (2, ['joint_3'])
    """
    import pinocchio as pin

    if not model.existFrame(tip):
        bodies = [f.name for f in model.frames if f.type == pin.FrameType.BODY and (names is None or f.name in names)]
        shown = ", ".join(bodies[-12:])
        raise InputError(f"tip: no frame {tip!r}; frames include: {shown}")
    fid = frame_index(model, tip)
    chain = _chain_to(model, model.frames[fid].parentJoint)
    _check_one_dof(model, chain, f"on the chain to {tip!r}")
    lock = [j for j in range(1, model.njoints) if j not in chain]
    if not lock:
        return model, [], list(geometry_models)
    locked = [model.names[j] for j in lock]
    # Pinocchio's buildReducedModel looks frames up by name alone and throws when a joint and a link
    # share one (a URDF may name a fixed joint after its child link); the link's frame and any other
    # namesake but the joint's get a temporary unique name for the reduction and have it back after.
    seen: dict[str, int] = {}
    for f in model.frames:
        seen[f.name] = seen.get(f.name, 0) + 1
    renamed: dict[str, str] = {}
    if any(count > 1 for count in seen.values()):
        model = pin.Model(model)
        joint_types = (pin.FrameType.JOINT, pin.FrameType.FIXED_JOINT)
        for k, f in enumerate(model.frames):
            if seen[f.name] > 1 and not (f.type in joint_types and f.name in model.names or
                                         f.type == pin.FrameType.FIXED_JOINT and k == 0):
                tmp = f"{f.name}\x00{k}"
                renamed[tmp] = f.name
                model.frames[k].name = tmp
    q0 = pin.neutral(model)
    for jn, value in (positions or {}).items():
        jid = model.getJointId(jn) if model.existJointName(jn) else 0
        jm = model.joints[jid]
        if jid in lock and jm.nv == 1:  # one degree of freedom (a mimic on a planar joint means nothing)
            q0[jm.idx_q:jm.idx_q + jm.nq] = [np.cos(value), np.sin(value)] if jm.nq == 2 else [value]
    if geometry_models:
        reduced, geoms = pin.buildReducedModel(model, list(geometry_models), lock, q0)
    else:
        reduced, geoms = pin.buildReducedModel(model, lock, q0), []
    for f in reduced.frames:
        if f.name in renamed:
            f.name = renamed[f.name]
    return reduced, locked, list(geoms)


def one_line(exc: BaseException) -> str:
    """The first line of an exception's message (at most 200 characters), or its type's name."""
    text = str(exc).strip()
    return text.splitlines()[0][:200] if text else type(exc).__name__


def _chain_joints(model: Any, tip: str) -> set[int]:
    j = model.frames[frame_index(model, tip)].parentJoint
    out = set()
    while j != 0:
        out.add(j)
        j = model.parents[j]
    return out


def physicality_problems(model: Any, tip: str) -> list[tuple[str, str]]:
    """The links that move with the chain root → ``tip`` and whose inertia is physically
    impossible (:func:`~robokit.description.inertia.physicality_problem`).

    A link counts when it moves with the chain: it is carried by a joint of the chain or by a
    joint locked off it whose nearest chain joint is not the world. A link fixed to the world
    (the base, or a branch locked to it) enters no quantity robokit computes and is not checked.

    Parameters
    ----------
    model : pinocchio.Model
        The whole tree as the file describes it (before the chain is cut out).
    tip : str
        The chain's tip frame.

    Returns
    -------
    list of (str, str)
        ``(link, what is wrong)`` in the model's order.

    Examples
    --------
    >>> import pinocchio as pin
    >>> from robokit.description.models import model_path
    >>> physicality_problems(pin.buildModelFromUrdf(str(model_path("rrr", ".urdf"))), "tool")
    []
    """
    chain = _chain_joints(model, tip)
    out = []
    for li in link_inertias(model):
        j = li.joint
        while j != 0 and j not in chain:
            j = model.parents[j]
        if j == 0:
            continue
        problem = physicality_problem(li.mass, li.inertia, atol=li.atol, mass_atol=li.mass_atol)
        if problem is not None:
            out.append((li.link, problem))
    return out


def _mimic_positions(mimic: Mapping[str, str], terms: Mapping[str, tuple[float, float]]) -> dict[str, float]:
    """The value of each mimic joint when every joint that is not a mimic joint is at 0: multiplier × the
    value of the joint it follows + offset, through chains of mimic joints (a cycle counts as 0); the
    joints whose value is not 0."""
    values: dict[str, float] = {}

    def value(joint: str, seen: frozenset[str]) -> float:
        if joint not in mimic or joint in seen:
            return 0.0
        if joint not in values:
            multiplier, offset = terms.get(joint, (1.0, 0.0))
            values[joint] = multiplier * value(mimic[joint], seen | {joint}) + offset
        return values[joint]

    for joint in mimic:
        value(joint, frozenset())
    return {j: v for j, v in values.items() if v != 0.0}


def _mimic_locks(mimic: Mapping[str, str], positions: Mapping[str, float], joints: list[str],
                 locked: list[str]) -> str:
    """The locked mimic ``joints`` as the note names them: each with its value where not 0; those that
    follow a joint on the chain (directly or through other mimic joints) said to stay where that joint's
    0 puts them."""
    def leader(joint: str) -> str:
        seen = {joint}
        while joint in mimic and mimic[joint] not in seen:
            joint = mimic[joint]
            seen.add(joint)
        return joint

    shown = ", ".join(f"{j} (at {positions[j]:.6g})" if j in positions else j for j in joints)
    follow: dict[str, list[str]] = {}
    for j in joints:
        if leader(j) not in locked and leader(j) not in mimic:
            follow.setdefault(leader(j), []).append(j)
    for lead, js in follow.items():
        them = "it" if len(js) == 1 else "them"
        shown += (f"; the file has {', '.join(js)} follow {lead!r}, a joint of the chain: robokit holds {them} "
                  f"where {lead} = 0 puts {them} (the links beyond do not move with {lead})")
    return shown


def build_robot(name: str, model: Any, tip: str | None, geoms: list[Any], configurations: Mapping[str, ArrayLike],
                spec: RobotSpec, notes: Iterable[str] = (), mimic: Mapping[str, str] | None = None,
                names: AbstractSet[str] | None = None,
                joint_values: Mapping[str, Mapping[str, float]] | None = None,
                mimic_terms: Mapping[str, tuple[float, float]] | None = None) -> Robot:
    """The :class:`Robot` of the chain root → ``tip`` of a Pinocchio ``model``.

    Parameters
    ----------
    name : str
        The robot's name.
    model : pinocchio.Model
        The whole kinematic tree as the file describes it.
    tip : str or None
        Tip frame; None chooses one (:func:`choose_tip`, with a note when the robot is a tree).
    geoms : list
        ``[visual, collision]`` ``pinocchio.GeometryModel`` (each may be None).
    configurations : dict of str to (n,) array
        Named joint configurations of the chain.
    spec : RobotSpec
        What the robot was loaded from; ``robot.spec``, and ``robot.source`` is its
        :meth:`~RobotSpec.describe`.
    notes : iterable of str
        What the loader did on the user's behalf; kept in ``robot.notes`` and warned as
        :class:`~robokit.errors.RobokitWarning`.
    mimic : dict, optional
        ``{joint: joint it mimics}`` of the file's ``<mimic>`` joints.
    names : set of str, optional
        Every name the file gives (links, bodies, joints, frames, sites). The default tip is
        chosen among them and ``robot.frame_names`` holds only them (module docstring); None
        reports every frame of the model but Pinocchio's ``universe``.
    joint_values : dict of str to dict of str to float, optional
        Named configurations the file gives joint by joint (SDFormat's ``<initial_position>``):
        each becomes ``configurations[name]`` over the chain's joints (0 for a joint it does not
        name); a value on a joint off the chain, which is locked at 0, is named in a note.
    mimic_terms : dict of str to (float, float), optional
        ``{joint: (multiplier, offset)}`` of the ``<mimic>`` joints (URDF; 1 and 0 where not given): a
        mimic joint off the chain is locked where the file puts it when every joint it follows is at 0,
        multiplier × that value + offset (its offset, for a joint that mimics a locked one).

    Returns
    -------
    Robot
        Its ``notes`` hold the loader's notes, then one line per physically impossible link
        (each also warned as :class:`~robokit.errors.PhysicalityWarning`).

    Raises
    ------
    InputError
        The chain has no moving joint, or a mimic joint is on it; a physically impossible link
        when loading strictly (:func:`strict_loading`, ``robokit.load(..., strict=True)``).

    Examples
    --------
    >>> import pinocchio as pin
    >>> from robokit.description.models import model_path
    >>> path = str(model_path("rrr", ".urdf"))
    >>> robot = build_robot("rrr", pin.buildModelFromUrdf(path), "dh_2", [None, None], {},
    ...                     RobotSpec("urdf", path=path))
    >>> robot.n, robot.locked_joints, robot.frame_pose([0.0, 0.0])[:3, 3].round(4).tolist()   # 0.5 + 0.4 m
    (2, ('joint_3',), [0.9, 0.0, 0.0])
    """
    import warnings

    source = spec.describe()
    notes = list(notes)
    if tip is None:
        tip, note = choose_tip(model, names, frozenset(mimic or ()))
        if note:
            notes.append(f"{name}: {note}")
    valid = [g for g in geoms if g is not None]
    positions = _mimic_positions(mimic or {}, mimic_terms or {})
    chain, locked, new_geoms = serial_chain(model, tip, valid, names, positions)
    if chain.nv == 0:
        raise InputError(f"{source}: the chain to {tip!r} has no moving joint; robokit needs at least one")
    for jn, target in (mimic or {}).items():
        if jn not in locked:
            raise InputError(
                f"{source}: joint {jn!r} mimics {target!r} and is on the chain to {tip!r}; robokit's joints are "
                "independent — remove the <mimic> or choose another tip"
            )
    if mimic and any(j in locked for j in mimic):
        notes.append(f"{name}: mimic joints off the chain locked: "
                     f"{_mimic_locks(mimic, positions, [j for j in mimic if j in locked], locked)}")
    if names is not None:
        invented = [j for j in list(chain.names)[1:] if j not in names] + [j for j in locked if j not in names]
        if invented:
            notes.append(f"{source}: joint names not in the file (given by Pinocchio's parser to unnamed joints): "
                         f"{', '.join(invented)}")
    # a DH table's inertias are the course's parameter sets and are not checked (PUMA 560 as published has a
    # massless link 1 with an inertia); a robot calibrated from a DH table carries the same inertias
    from_dh = (spec is not None and spec.kind == "calibrated" and spec.nominal is not None
               and spec.nominal.kind in ("shipped", "dh"))
    bad = [] if from_dh else physicality_problems(model, tip)
    if bad and _STRICT.get():
        shown = "; ".join(f"link {link!r}: {problem}" for link, problem in bad)
        raise InputError(f"{source}: physically impossible inertia (strict=True refuses it): {shown}")
    physical = [f"{source}: link {link!r}: {problem}" for link, problem in bad]
    if all(chain.inertias[i].mass == 0.0 for i in range(1, chain.njoints)):
        # (most ROS-Industrial arm macros: no <inertial> anywhere) — every dynamics result would be zero
        notes.append(f"{source}: no body on the chain to {tip!r} has mass (the file gives none): its mass matrix, "
                     f"gravity torques and inverse dynamics are all zero")
    configurations = dict(configurations)
    for cname, values in (joint_values or {}).items():
        on_chain = list(chain.names)[1:]
        if any(values.get(j, 0.0) != 0.0 for j in on_chain):
            configurations[cname] = np.array([float(values.get(j, 0.0)) for j in on_chain])
        off = [f"{j} {v:g}" for j, v in values.items() if j not in on_chain and v != 0.0]
        if off:
            notes.append(f"{name}: the file's {cname!r} values of joints off the chain to {tip!r} ignored (they are "
                         f"locked at 0): {', '.join(off)}")
    it = iter(new_geoms)
    geoms = [next(it) if g is not None else None for g in geoms]
    robot = Robot(name, chain, tip, visual_model=geoms[0], collision_model=geoms[1],
                  configurations=configurations, locked_joints=locked, source=source)
    robot._amend(spec=spec, frame_names=dict.fromkeys(f.name for k, f in enumerate(chain.frames)
                                                      if (f.name in names if names is not None else k != 0)),
                 notes=(*robot.notes, *notes, *physical))
    for note in notes:
        warnings.warn(note, RobokitWarning, stacklevel=outside_level())
    for note in physical:
        warnings.warn(note, PhysicalityWarning, stacklevel=outside_level())
    return robot
