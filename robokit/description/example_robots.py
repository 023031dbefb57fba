r"""Robots of example-robot-data, by name: :func:`load_example_robot` (``robokit.load("ur5")``).

The models come from the ``example-robot-data-loaders`` package (its ``load(name)`` gives a
Pinocchio ``RobotWrapper``); robokit keeps the chain to the arm's tip (:data:`EXAMPLE_ROBOT_TIPS`)
with the fingers locked, and records the name on ``robot.spec``.
"""
from __future__ import annotations

from typing import Any, Literal

import numpy as np

from robokit.description.builder import build_robot, choose_tip, one_line
from robokit.description.frames import frame_index
from robokit.description.robot import Robot
from robokit.description.spec import RobotSpec
from robokit.errors import InputError

__all__ = ["load_example_robot", "example_robot_names", "EXAMPLE_ROBOT_TIPS"]

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


def load_example_robot(name: str, tip: str | None = None) -> Robot:
    """An arm of example-robot-data by name (``ur5``, ``panda``, ``z1``, ``xarm7``, ``kinova``, …).

    A robot that example-robot-data gives a floating base is loaded with its base fixed to the
    world (a note says so); the tip defaults to :data:`EXAMPLE_ROBOT_TIPS` for the arms listed
    there, else to :func:`~robokit.description.builder.choose_tip`'s choice. The robot's
    ``"ready"`` configuration is example-robot-data's ``q0`` when that is not zero.

    Parameters
    ----------
    name : str
        A key of ``example_robot_data.ROBOTS``.
    tip : str, optional
        The chain's tip frame.

    Returns
    -------
    Robot
        ``robot.spec == RobotSpec("example-robot-data", name=name, tip=tip)``.

    Raises
    ------
    InputError
        example-robot-data missing or failing to load the model; a tree with no default tip.

    Examples
    --------
    >>> robot = load_example_robot("ur5")
    >>> robot.n, robot.tip
    (6, 'tool0')
    """
    try:
        import example_robot_data as erd
    except ImportError:
        raise InputError(f"model {name!r}: example-robot-data is not installed "
                         "(pip install example-robot-data-loaders)") from None

    spec = RobotSpec("example-robot-data", name=name, tip=tip)
    if name not in getattr(erd, "ROBOTS", {}):
        raise InputError(f"model: {name!r} is not an example-robot-data name (e.g. ur5, panda, z1, xarm7, kinova)")

    loader = erd.ROBOTS[name]
    notes = []
    if getattr(loader, "free_flyer", False):
        # Loaded with its base fixed to the world: a fixed-base arm (so100) is then what its
        # URDF describes; a mobile or legged robot's limbs are then chains like any other.
        notes.append(f"{name}: example-robot-data gives it a floating base; loaded with the base fixed "
                     "to the world")
    try:
        with _quiet():
            built = _built_from_urdf(loader, notes) if getattr(loader, "urdf_filename", "") else None
            if built is None:  # an SDFormat robot: example-robot-data's loader (Pinocchio's SDF parser)
                wrapper = type(loader.__name__, (loader,), {"free_flyer": False})().robot
                built = (wrapper.model, wrapper.visual_model, wrapper.collision_model, getattr(wrapper, "q0", None))
    except InputError:
        raise
    except Exception as exc:  # a dependency's failure is still one robokit line
        raise InputError(f"model {name!r}: example-robot-data could not load it ({one_line(exc)})") from None
    model, visual_model, collision_model, q0 = built
    # The URDF's own names: Pinocchio's URDF parser names frames and joints after the file's
    # links and joints and adds only the world frame 'universe' (frame 0).
    names = frozenset(f.name for f in list(model.frames)[1:]) | frozenset(list(model.names)[1:])
    tip = tip or EXAMPLE_ROBOT_TIPS.get(name)
    if tip is None:
        try:
            tip, note = choose_tip(model, names)
        except ValueError as exc:
            raise InputError(f"model {name!r}: {exc}") from None
        if note:
            notes.append(f"{name}: {note}")
    configurations = {}
    chain_names = []
    if model.existFrame(tip):
        j = model.frames[frame_index(model, tip)].parentJoint
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
    if chain_names:
        arm = [(jn, float(model.armature[model.joints[model.getJointId(jn)].idx_v])) for jn in chain_names]
        arm = [(jn, a) for jn, a in arm if a != 0.0]
        if arm:  # the SRDF's rotor inertia · gear ratio², which Pinocchio adds to M and RNEA
            shown = ", ".join(f"{jn} {a:.4g}" for jn, a in arm)
            notes.append(f"{name}: reflected rotor inertia (example-robot-data's SRDF: rotorInertia · "
                         f"rotorGearRatio²) is in M and RNEA as armature: {shown} (kg·m²; kg for a prismatic joint)")
    return build_robot(name, model, tip, [visual_model, collision_model], configurations,
                       spec, notes, names=names)


def _built_from_urdf(loader: Any, notes: list[str] | None = None) -> tuple[Any, Any, Any, Any]:
    """An example-robot-data URDF robot built as every URDF robot is (read and checked by
    :func:`~robokit.description.urdf_check.read_urdf`, built by the one model builder), with what
    example-robot-data's loader adds from the robot's SRDF: the reference posture ``q0``, the
    rotor parameters (``armature`` = rotor inertia · gear ratio²) and the collision pairs the SRDF
    does not disable. An inertia tensor that is not positive semi-definite (example-robot-data's
    TIAGo antenna links), which a URDF file robokit is given is refused for, is built as the
    package's own loader builds it and said in ``notes``. Returns (model, visual, collision, q0 or
    None)."""
    from os.path import join

    import example_robot_data as erd
    import pinocchio as pin

    from robokit.description.model_builder import build_model
    from robokit.description.urdf_check import read_urdf
    from robokit.description.urdf_description import description_from_urdf

    rel = join(loader.path, loader.urdf_subpath, loader.urdf_filename)
    root = loader.model_path or erd.robots_loader.getModelPath(rel)
    path = join(root, rel)
    unphysical: list[str] = []
    doc = read_urdf(path, package_dirs=[join(root, "../..")], unphysical_inertias=unphysical)
    if notes is not None:
        notes.extend(unphysical)
    model, visual, collision, _ = build_model(description_from_urdf(doc.xml, path))
    q0 = None
    if loader.srdf_filename:
        srdf = join(root, loader.path, loader.srdf_subpath, loader.srdf_filename)
        q0 = erd.robots_loader.readParamsFromSrdf(model, srdf, False, loader.has_rotor_parameters,
                                                  loader.ref_posture)
        collision.addAllCollisionPairs()
        pin.removeCollisionPairs(model, collision, srdf, False)
    return model, visual, collision, q0


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


def example_robot_names() -> list[str]:
    """The names example-robot-data can load, sorted ([] when it is not installed).

    Returns
    -------
    list of str

    Examples
    --------
    >>> {"ur5", "panda"} <= set(example_robot_names())
    True
    """
    try:
        import example_robot_data as erd

        return sorted(getattr(erd, "ROBOTS", {}).keys())
    except Exception:  # pragma: no cover
        return []
