r"""Building a :class:`~robokit.description.robot.Robot` from a Pinocchio model: the pieces every loader shares.

* :func:`choose_tip` — the default tip frame of a kinematic tree (the longest chain; an
  error listing the ends when two chains tie);
* :func:`serial_chain` — the chain root → tip, every other joint locked at its neutral
  value and its bodies merged (``pinocchio.buildReducedModel``);
* :func:`build_robot` — both of the above, the checks a chain must pass (at least one moving
  joint, no ``<mimic>`` joint on it) and the :class:`~robokit.description.spec.RobotSpec`
  the robot carries.

The format modules (:mod:`~robokit.description.urdf_files`, :mod:`~robokit.description.xacro_files`,
:mod:`~robokit.description.mjcf`, :mod:`~robokit.description.example_robots`,
:mod:`~robokit.description.dh_robots`) read their files into a Pinocchio model and call
:func:`build_robot`; :func:`robokit.description.loading.load` picks the format.
"""
from __future__ import annotations

from typing import Any, Iterable, Mapping

from numpy.typing import ArrayLike

from robokit.description.robot import Robot
from robokit.description.spec import RobotSpec
from robokit.errors import InputError, RobokitWarning

__all__ = ["choose_tip", "default_tip", "serial_chain", "build_robot"]

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
    :class:`~robokit.errors.InputError` lists the candidate tips with their chain lengths.

    Parameters
    ----------
    model : pinocchio.Model
        The kinematic tree.

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
    """The default tip frame of a model (see :func:`choose_tip`).

    Parameters
    ----------
    model : pinocchio.Model

    Returns
    -------
    str
        The tip frame's name.

    Examples
    --------
    >>> default_tip(rk.load("rrr").model)
    'tool'
    """
    return choose_tip(model)[0]


def _body_type() -> Any:
    import pinocchio as pin

    return pin.FrameType.BODY


def serial_chain(model: Any, tip: str, geometry_models: Iterable[Any] = ()) -> tuple[Any, list[str], list[Any]]:
    """The chain root → ``tip`` of a Pinocchio model, other joints locked at neutral.

    Parameters
    ----------
    model : pinocchio.Model
        The kinematic tree.
    tip : str
        The tip frame.
    geometry_models : iterable of pinocchio.GeometryModel
        Reduced with the model (their objects re-attached to the chain's joints).

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


def one_line(exc: BaseException) -> str:
    """The first line of an exception's message (at most 200 characters), or its type's name."""
    text = str(exc).strip()
    return text.splitlines()[0][:200] if text else type(exc).__name__


def build_robot(name: str, model: Any, tip: str | None, geoms: list[Any], configurations: Mapping[str, ArrayLike],
                spec: RobotSpec, notes: Iterable[str] = (), mimic: Mapping[str, str] | None = None) -> Robot:
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

    Returns
    -------
    Robot

    Raises
    ------
    InputError
        The chain has no moving joint, or a mimic joint is on it.

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
    robot.spec = spec
    robot.notes.extend(notes)
    for note in notes:
        warnings.warn(note, RobokitWarning, stacklevel=3)
    return robot
