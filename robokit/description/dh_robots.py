r"""Robots from DH tables: a shipped model, a DH ``.yaml`` file, a :class:`DHTable` in memory.

The table becomes the layout :func:`robokit.description.urdf_gen.urdf_from_dh` writes as URDF
(frames ``dh_0`` … ``dh_N`` and ``tool``), built directly by the model builder
(:func:`robokit.description.urdf_gen.description_from_dh` →
:func:`robokit.description.model_builder.build_model`, no URDF text in between); the robot's tip
is ``tool`` and ``robot.dh`` is the table. The robot's :class:`~robokit.description.spec.RobotSpec`
carries the table itself as YAML text (angles in rad), so ``robokit.load(robot.spec)`` rebuilds the same table without
reading the file again; a shipped model is carried by its name.
"""
from __future__ import annotations

import os
from pathlib import Path

import numpy as np

from robokit.description.dh import DHTable
from robokit.description.models import models_dir, shipped_models
from robokit.description.robot import Robot
from robokit.description.spec import RobotSpec
from robokit.errors import InputError

__all__ = ["robot_from_dh", "load_dh_file", "load_shipped", "load_dh_text"]


def _check_tip(tip: str | None) -> None:
    if tip not in (None, "tool"):
        raise InputError(f"tip: a DH model's tip is its 'tool' frame, got {tip!r}")


def robot_from_dh(table: DHTable, spec: RobotSpec | None = None) -> Robot:
    """The :class:`Robot` of a DH table (tip ``tool``).

    Parameters
    ----------
    table : DHTable
        The table (standard or modified convention).
    spec : RobotSpec, optional
        What the robot is recorded as; default ``RobotSpec("dh", text=table.to_yaml_str("rad"))``.

    Returns
    -------
    Robot
        ``robot.dh is table``; frames ``dh_0`` … ``dh_N``, ``tool``.

    Examples
    --------
    >>> import robokit
    >>> table = robokit.load("rrr").dh
    >>> robot_from_dh(table).n
    3
    """
    from robokit.description.model_builder import build_model
    from robokit.description.urdf_gen import description_from_dh

    if not isinstance(table, DHTable):
        raise InputError(f"table: expected a DHTable, got {type(table).__name__}")
    from robokit.description.limits import check_joint_count

    check_joint_count(len(table.links), table.name, "links (joints)")  # before Pinocchio builds anything
    if spec is None:
        spec = RobotSpec("dh", text=table.to_yaml_str(angle_unit="rad"))
    model, visual, collision, _ = build_model(description_from_dh(table))  # cylinders only: no mesh notes
    robot = Robot(table.name, model, "tool", visual_model=visual, collision_model=collision, dh=table,
                  source=spec.describe(), spec=spec)
    return robot


def load_dh_text(text: str, source: str = "<DH YAML>", spec: RobotSpec | None = None) -> Robot:
    """The robot of a DH table given as YAML text, parsed by robokit's strict YAML loader.

    Parameters
    ----------
    text : str
        A DH file's contents (the DH file format page of the documentation).
    source : str
        Names the text in error messages.
    spec : RobotSpec, optional
        Recorded on the robot (default: a ``"dh"`` spec of the parsed table).

    Returns
    -------
    Robot
        Built by :func:`robot_from_dh` from the parsed table; ``robot.spec`` is ``spec``
        (default ``RobotSpec("dh", text=text)``).

    Raises
    ------
    InputError
        Text that is not a valid DH file (naming ``source``, the link and the key).

    Examples
    --------
    >>> robot = load_dh_text("name: one\\nconvention: standard\\nangle_unit: rad\\n"
    ...                      "links:\\n  - {joint: R, a: 1, alpha: 0, d: 0, theta: 0}\\n")
    >>> robot.n
    1
    """
    from robokit._yaml import load_yaml_text

    if not isinstance(text, str):
        raise InputError(f"text: expected the DH table's YAML text, got {type(text).__name__}")
    table = DHTable.from_dict(load_yaml_text(text, source=source), source=source)
    return robot_from_dh(table, spec if spec is not None else RobotSpec("dh", text=text))


def load_dh_file(path: str | os.PathLike[str], tip: str | None = None) -> Robot:
    """The robot of a DH ``.yaml`` file (see :func:`robot_from_dh`).

    Parameters
    ----------
    path : str or Path
        The DH file.
    tip : None or "tool"
        A DH robot's tip is always its ``tool`` frame.

    Returns
    -------
    Robot
        ``robot.spec`` holds the table as YAML text and the file's absolute path.

    Raises
    ------
    InputError
        A missing or invalid file (naming the file, the link and the key), another ``tip``.

    Examples
    --------
    >>> from robokit.description.models import model_path
    >>> robot = load_dh_file(model_path("twolink"))
    >>> robot.n, robot.tip, robot.frame_pose([0.0, 0.0])[:3, 3].round(4).tolist()
    (2, 'tool', [1.8, 0.0, 0.0])
    """
    _check_tip(tip)
    path = Path(path)
    table = DHTable.from_yaml(path)
    return robot_from_dh(table, RobotSpec("dh", path=os.path.abspath(path),
                                          text=table.to_yaml_str(angle_unit="rad")))


def load_shipped(name: str, tip: str | None = None) -> Robot:
    """A model shipped with robokit (``models/<name>.yaml``) by name.

    Parameters
    ----------
    name : str
        One of :func:`robokit.description.models.shipped_models` (``twolink``, ``rrr``, ``puma560``, …).
    tip : None or "tool"

    Returns
    -------
    Robot
        ``robot.spec == RobotSpec("shipped", name=name)``.

    Examples
    --------
    >>> load_shipped("puma560").n
    6
    """
    _check_tip(tip)
    if name not in shipped_models():
        raise InputError(f"model: no shipped model {name!r}; available: {', '.join(shipped_models())}")
    table = DHTable.from_yaml(models_dir() / f"{name}.yaml")
    return robot_from_dh(table, RobotSpec("shipped", name=name))
