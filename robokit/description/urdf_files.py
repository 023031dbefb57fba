r"""URDF files: :func:`load_urdf` (``robokit.load("arm.urdf")``).

The file is read and checked by :mod:`robokit.description.urdf_check` (bounded size, names,
joint and link structure, meshes inside the file's package or ``package_dirs``), read into
a :class:`~robokit.description.model_builder.Description`
(:func:`~robokit.description.urdf_description.description_from_urdf`, urdfdom's rules) and built
by the one model builder (:func:`~robokit.description.model_builder.build_model`), as every format
is; the result equals Pinocchio's own URDF parser's model and geometry (the tests hold it so); a
mesh that cannot be read is left out with a note. The robot is the chain root → tip (:func:`robokit.description.builder.build_robot`).

A URDF in Drake's dialect gives a joint's ``<transmission>`` a rotor inertia and a gear ratio
(``<drake:rotor_inertia value>``, ``<drake:gear_ratio value>``); the reflected inertia
``rotor_inertia · gear_ratio²`` goes into ``model.armature`` as Drake adds it to M and inverse
dynamics (:mod:`robokit.description.reflected`, the rules in :mod:`robokit.description.urdf_check`),
with one note; ``reflected_inertia=False`` leaves it out.
"""
from __future__ import annotations

import os
from pathlib import Path

import numpy as np
from typing import Sequence

from robokit.description.builder import build_robot
from robokit.description.robot import Robot
from robokit.description.spec import RobotSpec
from robokit.errors import InputError

__all__ = ["load_urdf", "load_urdf_text", "absolute_dirs"]


def absolute_dirs(folders: Sequence[str | os.PathLike[str]] | None) -> tuple[str, ...]:
    """``folders`` as absolute path strings (``~`` expanded), the form a :class:`RobotSpec` holds.

    Parameters
    ----------
    folders : sequence of str or Path, or None

    Returns
    -------
    tuple of str

    Examples
    --------
    >>> absolute_dirs(["/opt/ws/src"])
    ('/opt/ws/src',)
    """
    return tuple(os.path.abspath(Path(d).expanduser()) for d in (folders or ()))


def load_urdf(path: str | os.PathLike[str], tip: str | None = None, *,
              package_dirs: Sequence[str | os.PathLike[str]] | None = None,
              allow_outside_meshes: bool = False, reflected_inertia: bool = True) -> Robot:
    """Load a URDF file as a :class:`~robokit.description.robot.Robot`.

    Parameters
    ----------
    path : str or Path
        A ``.urdf`` file.
    tip : str, optional
        The chain's tip frame (default: the end of the chain — of the longest chain for a
        tree, see :func:`~robokit.description.builder.choose_tip`).
    package_dirs : sequence of str or Path, optional
        Folders searched for the ROS packages of ``package://pkg/...`` mesh URIs.
    allow_outside_meshes : bool
        Read meshes the file names outside its folder, its package and ``package_dirs``
        (refused by default).
    reflected_inertia : bool
        Add Drake's reflected rotor inertia, ``drake:rotor_inertia · drake:gear_ratio²`` of a
        ``<transmission>``'s actuator, to the joint's armature, as Drake does (default True).

    Returns
    -------
    Robot
        With ``robot.spec == RobotSpec("urdf", path=<absolute path>, tip=tip, ...)``.

    Raises
    ------
    InputError
        Missing or malformed file, a check of :mod:`robokit.description.urdf_check`, a URDF
        Pinocchio cannot build, no serial chain to the tip.

    Examples
    --------
    >>> from robokit.description.models import model_path
    >>> robot = load_urdf(model_path("rrr", ".urdf"), tip="tool")
    >>> robot.n, robot.frame_pose(np.zeros(3))[:3, 3].round(4).tolist()   # 0.5 + 0.4 + 0.2 m
    (3, [1.1, 0.0, 0.0])
    """
    path = Path(path)
    if not path.exists():  # anything else (a FIFO, a device) is refused by the bounded reader
        raise InputError(f"{path}: file not found")
    return _from_urdf_file(path, tip, package_dirs=package_dirs, allow_outside_meshes=allow_outside_meshes,
                           reflected_inertia=reflected_inertia)


def load_urdf_text(text: str, spec: RobotSpec, tip: str | None = None, gravity: object = None,
                   nominal: Robot | RobotSpec | None = None) -> Robot:
    """A Robot from URDF text held in memory (a calibrated robot's spec), read under the checks of
    a URDF file; ``robot.nominal`` is ``nominal``, else the spec's nominal (loaded when first needed).

    Parameters
    ----------
    text : str
        The URDF (no meshes outside the robot: it has no folder).
    spec : RobotSpec
        What the robot is recorded as (``robot.spec``).
    tip : str, optional
        The tip frame.
    gravity : array_like, shape (3,), optional
        Gravity in the base frame, m/s² (a URDF cannot hold it; default Pinocchio's (0, 0, −9.81)).
    nominal : Robot or RobotSpec, optional
        The arm the calibration started from (default ``spec.nominal``).

    Returns
    -------
    Robot

    Examples
    --------
    >>> from robokit.description.models import model_path
    >>> text = model_path("rrr", ".urdf").read_text()
    >>> load_urdf_text(text, RobotSpec("calibrated", name="rrr", text=text), tip="tool").n
    3
    """
    robot = _from_urdf_file(Path(f"<{spec.name or 'robot'}>.urdf"), tip, text=text, spec=spec, gravity=gravity,
                            reflected_inertia=spec.reflected_inertia)
    return robot._amend(nominal=spec.nominal if nominal is None else nominal)


def _from_urdf_file(path: Path, tip: str | None, package_dirs: Sequence[str | os.PathLike[str]] | None = None,
                    allow_outside_meshes: bool = False, text: str | None = None,
                    spec: RobotSpec | None = None, gravity: object = None, reflected_inertia: bool = True) -> Robot:
    """A Robot from a URDF file (or the URDF ``text`` a xacro file expanded to, named by ``path``,
    with that file's ``spec``)."""
    from robokit.description.model_builder import build_model
    from robokit.description.reflected import drake_reflected_inertia
    from robokit.description.urdf_check import read_urdf
    from robokit.description.urdf_description import description_from_urdf

    doc = read_urdf(path, package_dirs=package_dirs, allow_outside_meshes=allow_outside_meshes, text=text)
    armature, reflected_notes = drake_reflected_inertia(doc.rotors, reflected_inertia, path)
    model, visual, collision, notes = build_model(description_from_urdf(doc.xml, str(path), armature))
    if gravity is not None:
        model.gravity.linear = np.asarray(gravity, dtype=float)
    geoms = [visual, collision]
    if spec is None:
        spec = RobotSpec("urdf", path=os.path.abspath(path), tip=tip, package_dirs=absolute_dirs(package_dirs),
                         allow_outside_meshes=bool(allow_outside_meshes), reflected_inertia=bool(reflected_inertia))
    notes.extend(reflected_notes)
    notes.extend(note for _, note in doc.unmodelled)
    return build_robot(doc.name, model, tip, geoms, {}, spec, notes, mimic=doc.mimic, names=doc.names,
                       mimic_terms=doc.mimic_terms)


