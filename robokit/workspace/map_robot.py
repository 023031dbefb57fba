r"""The robot a capability map file describes — as data, never as a path to follow.

A map written by :meth:`CapabilityMap.save <robokit.workspace.capability.CapabilityMap.save>`
(``include_robot=True``, what ``robokit workspace`` writes) carries its robot so that
``robokit view MAP.npz`` can draw it without opening any file the map names:

==========================  ============================================================
the robot was loaded from   the map stores
==========================  ============================================================
a shipped model             its name (``robot_kind = "shipped"``, ``robot_model``)
example-robot-data          its name and tip (``"example-robot-data"``)
a DH table (file or memory) the table as YAML text (``"dh"``, ``robot_dh``), read back by
                            robokit's strict YAML loader
anything else (URDF, xacro, the chain's geometry (``"chain"``): ``robot_joint_types`` (n,),
MJCF)                       ``robot_joint_placements`` (n, 4, 4), ``robot_joint_axes`` (n, 3),
                            ``robot_tip_placement`` (4, 4), drawn as a stick model
                            (:func:`robokit.description.stick.stick_robot`)
==========================  ============================================================

plus ``robot`` (the name, for titles). A name is only ever looked up in robokit's own model
list or example-robot-data's registry; a map that names its robot any other way (an older map
whose ``robot`` is a path) is drawn without the robot, with a note to pass ``--robot FILE`` —
the one way a path reaches the loader is the user typing it.
"""
from __future__ import annotations

from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any, Mapping

import numpy as np

from robokit.errors import InputError

if TYPE_CHECKING:
    from robokit.description.robot import Robot

__all__ = ["MapRobot", "map_robot_of", "MAP_ROBOT_KINDS"]

#: What a map may say its robot is.
MAP_ROBOT_KINDS = ("shipped", "example-robot-data", "dh", "chain")
_CHAIN_KEYS = ("joint_types", "joint_placements", "joint_axes", "tip_placement")
_MAX_TEXT = 1 << 20  # characters of a name or a DH table (the YAML loader's own cap)


@dataclass(frozen=True)
class MapRobot:
    """The robot of a capability map, as the map file stores it (module docstring).

    Attributes
    ----------
    kind : str
        One of :data:`MAP_ROBOT_KINDS`.
    name : str
        The robot's name (a title; never a path).
    model : str
        The shipped or example-robot-data name ("" otherwise).
    tip : str
        The tip frame ("" for the default).
    dh_yaml : str
        The DH table as YAML text (kind ``"dh"``).
    chain : dict of str to ndarray
        The stick model's arrays (kind ``"chain"``; see
        :func:`robokit.description.stick.chain_geometry`).

    Examples
    --------
    >>> import robokit
    >>> map_robot_of(robokit.load("rrr"))
    MapRobot(kind='shipped', name='rrr', model='rrr', tip='', dh_yaml='')
    """

    kind: str
    name: str = ""
    model: str = ""
    tip: str = ""
    dh_yaml: str = ""
    chain: dict[str, np.ndarray] = field(default_factory=dict, compare=False, repr=False)

    def to_arrays(self) -> dict[str, np.ndarray]:
        """The ``.npz`` entries of this description.

        Returns
        -------
        dict of str to ndarray
            ``robot``, ``robot_kind`` and the members of that kind (``robot_model``,
            ``robot_tip``, ``robot_dh`` or the chain's ``robot_joint_*`` arrays).

        Examples
        --------
        >>> import robokit
        >>> sorted(map_robot_of(robokit.load("puma560")).to_arrays())[:2]
        ['robot', 'robot_kind']
        """
        out = {"robot": np.str_(self.name), "robot_kind": np.str_(self.kind)}
        if self.kind in ("shipped", "example-robot-data"):
            out["robot_model"] = np.str_(self.model)
            out["robot_tip"] = np.str_(self.tip)
        elif self.kind == "dh":
            out["robot_dh"] = np.str_(self.dh_yaml)
        else:
            out["robot_tip"] = np.str_(self.tip)
            for key in _CHAIN_KEYS:
                out[f"robot_{key}"] = np.asarray(self.chain[key])
        return out

    @classmethod
    def from_arrays(cls, data: Mapping[str, np.ndarray], source: str = "map") -> tuple[MapRobot | None, str]:
        """The description in a map file's arrays, and a note ("" if none) when there is none to use.

        Parameters
        ----------
        data : mapping of str to ndarray
            The ``.npz`` file's arrays.
        source : str
            Names the file in errors and notes.

        Returns
        -------
        MapRobot or None, str
            None and a note when the map has no robot robokit may draw from it (no robot, or an
            older map that names it by a path).

        Raises
        ------
        InputError
            Entries of the wrong type or size, an unknown kind.

        Examples
        --------
        >>> import numpy as np
        >>> MapRobot.from_arrays({"robot": np.str_("/tmp/evil.urdf.xacro")})[0] is None
        True
        """
        def text(key: str) -> str:
            if key not in data:
                return ""
            a = np.asarray(data[key])
            if a.ndim != 0 or a.dtype.kind != "U" or a.dtype.itemsize // 4 > _MAX_TEXT:
                raise InputError(f"{source}: entry {key!r} is not a text of at most {_MAX_TEXT} characters")
            return str(a)

        name = text("robot")
        if "robot_kind" not in data:
            if not name:
                return None, ""
            if _is_known_name(name):
                return cls("shipped" if _is_shipped(name) else "example-robot-data", name, model=name), ""
            return None, (f"{source}: the map names its robot {name!r} but carries no description of it; "
                          "robokit does not open files a map names: drawn without the robot (pass --robot FILE, "
                          "or robot= in Python, to draw it)")
        kind = text("robot_kind")
        if kind not in MAP_ROBOT_KINDS:
            raise InputError(f"{source}: robot_kind must be one of {', '.join(MAP_ROBOT_KINDS)}, got {kind!r}")
        if kind in ("shipped", "example-robot-data"):
            model = text("robot_model")
            if not (_is_shipped(model) if kind == "shipped" else _is_example_robot(model)):
                return None, (f"{source}: the map's robot {model!r} is not a {kind} name robokit knows; drawn "
                              "without the robot (pass --robot FILE to draw it)")
            return cls(kind, name, model=model, tip=text("robot_tip")), ""
        if kind == "dh":
            return cls(kind, name, dh_yaml=text("robot_dh")), ""
        chain = {}
        for key in _CHAIN_KEYS:
            if f"robot_{key}" not in data:
                raise InputError(f"{source}: a 'chain' robot needs robot_{key}")
            chain[key] = np.asarray(data[f"robot_{key}"])
        return cls(kind, name, tip=text("robot_tip"), chain=chain), ""

    def robot(self) -> Robot:
        """The :class:`~robokit.description.robot.Robot` this description draws: the named model,
        the DH table, or the stick model of the chain. No file path is ever opened.

        Returns
        -------
        Robot
            Built anew on each call: the shipped or example-robot-data model loaded by name, the
            DH table by :func:`~robokit.description.dh_robots.load_dh_text`, the chain by
            :func:`~robokit.description.stick.stick_robot`.

        Raises
        ------
        InputError
            A DH table or chain arrays that are not valid.

        Examples
        --------
        >>> MapRobot("shipped", "rrr", model="rrr").robot().n
        3
        """
        if self.kind == "shipped":
            from robokit.description.dh_robots import load_shipped

            return load_shipped(self.model)
        if self.kind == "example-robot-data":
            from robokit.description.example_robots import load_example_robot

            return load_example_robot(self.model, self.tip or None)
        if self.kind == "dh":
            from robokit.description.dh_robots import load_dh_text

            return load_dh_text(self.dh_yaml, source=f"the map's DH table of {self.name!r}")
        from robokit.description.stick import stick_robot

        return stick_robot(self.name, tip=self.tip or "tip", **self.chain)


def _is_shipped(name: str) -> bool:
    from robokit.description.models import shipped_models

    return name in shipped_models()


def _is_example_robot(name: str) -> bool:
    from robokit.description.example_robots import example_robot_names

    return name.isidentifier() and name in example_robot_names()


def _is_known_name(name: str) -> bool:
    return _is_shipped(name) or _is_example_robot(name)


def map_robot_of(robot: Robot) -> MapRobot:
    """The description a map stores of ``robot`` (module docstring).

    Parameters
    ----------
    robot : Robot

    Returns
    -------
    MapRobot

    Examples
    --------
    >>> import robokit
    >>> map_robot_of(robokit.load(robokit.load("rrr").dh)).kind
    'dh'
    """
    spec: Any = robot.spec
    if spec is not None and spec.kind == "shipped":
        return MapRobot("shipped", robot.name, model=spec.name)
    if spec is not None and spec.kind == "example-robot-data":
        return MapRobot("example-robot-data", robot.name, model=spec.name, tip=spec.tip or "")
    if spec is not None and spec.kind == "dh" and spec.text is not None:
        return MapRobot("dh", robot.name, dh_yaml=spec.text)
    if robot.dh is not None:
        return MapRobot("dh", robot.name, dh_yaml=robot.dh.to_yaml_str(angle_unit="rad"))
    from robokit.description.stick import chain_geometry

    return MapRobot("chain", robot.name, tip=robot.tip, chain=chain_geometry(robot))
