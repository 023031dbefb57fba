r"""``robokit.load``: one table from a file's suffix (or a name's kind) to the loader of that format.

=====================  ====================================================  ==========================
input                  loader                                                options it takes
=====================  ====================================================  ==========================
``*.yaml``, ``*.yml``  :func:`~robokit.description.dh_robots.load_dh_file`    —
``*.urdf``             :func:`~robokit.description.urdf_files.load_urdf`      ``package_dirs``,
                                                                             ``allow_outside_meshes``,
                                                                             ``reflected_inertia``
``*.xacro``            :func:`~robokit.description.xacro_files.load_xacro`    ``package_dirs``,
                                                                             ``xacro_args``,
                                                                             ``allow_outside_meshes``,
                                                                             ``reflected_inertia``
``*.xml``              :func:`~robokit.description.mjcf.load_mjcf`            ``package_dirs``,
                                                                             ``allow_outside_meshes``,
                                                                             ``reflected_inertia``
``*.sdf``, ``*.world`` :func:`~robokit.description.sdf.load_sdf`              ``package_dirs``,
                                                                             ``allow_outside_meshes``,
                                                                             ``reflected_inertia``
a shipped model name   :func:`~robokit.description.dh_robots.load_shipped`    —
an example-robot-data  :func:`~robokit.description.example_robots.load_example_robot`  —
name
=====================  ====================================================  ==========================

``tip`` goes to every loader (a DH robot's tip is always ``tool``). An option the format does
not use is refused (``InputError`` naming the option and the formats that take it), so a
misplaced option is never silently ignored. ``strict`` applies to every format read from a
file (and to example-robot-data): a link whose inertia is physically impossible, which loads
with a :class:`~robokit.errors.PhysicalityWarning`, is refused with an ``InputError``.

Every robot carries the :class:`~robokit.description.spec.RobotSpec` it was loaded from
(``robot.spec``); ``load(spec)`` dispatches on ``spec.kind`` to the same loader with the same
arguments and so rebuilds an equal robot, in this process or another one.
"""
from __future__ import annotations

import os
from pathlib import Path

import numpy as np
from typing import Any, Callable, Mapping, Sequence

from robokit.description.builder import strict_loading
from robokit.description.catalogue import FORMAT_NAMES, ModelCatalogue, ModelInfo, unknown_model_hint
from robokit.description.dh import DHTable
from robokit.description.dh_robots import load_dh_file, load_dh_text, load_shipped, robot_from_dh
from robokit.description.example_robots import EXAMPLE_ROBOT_TIPS, example_robot_names, load_example_robot
from robokit.description.mjcf import load_mjcf
from robokit.description.models import shipped_models
from robokit.description.robot import Robot
from robokit.description.sdf import load_sdf
from robokit.description.spec import RobotSpec
from robokit.description.urdf_files import load_urdf, load_urdf_text
from robokit.description.xacro_files import load_xacro
from robokit.errors import InputError

__all__ = ["load", "FILE_LOADERS", "spec_of"]

#: File suffix → (loader, the options of :func:`load` it takes). The longest matching suffix
#: wins (``arm.urdf.xacro`` is a xacro file).
FILE_LOADERS: dict[str, tuple[Callable[..., Robot], tuple[str, ...]]] = {
    ".yaml": (load_dh_file, ()),
    ".yml": (load_dh_file, ()),
    ".urdf": (load_urdf, ("package_dirs", "allow_outside_meshes", "reflected_inertia")),
    ".xacro": (load_xacro, ("package_dirs", "xacro_args", "allow_outside_meshes", "reflected_inertia")),
    ".xml": (load_mjcf, ("package_dirs", "allow_outside_meshes", "reflected_inertia")),
    ".sdf": (load_sdf, ("package_dirs", "allow_outside_meshes", "reflected_inertia")),
    ".world": (load_sdf, ("package_dirs", "allow_outside_meshes", "reflected_inertia")),
}

#: Spec kind → how ``load(spec)`` rebuilds the robot.
_SPEC_LOADERS: dict[str, Callable[[RobotSpec], Robot]] = {
    "shipped": lambda s: load_shipped(s.name or "", s.tip),
    "example-robot-data": lambda s: load_example_robot(s.name or "", s.tip),
    "dh": lambda s: load_dh_text(s.text or "", source=s.describe(), spec=s),
    "urdf": lambda s: load_urdf(s.path or "", s.tip, package_dirs=s.package_dirs or None,
                                allow_outside_meshes=s.allow_outside_meshes, reflected_inertia=s.reflected_inertia),
    "xacro": lambda s: load_xacro(s.path or "", s.tip, package_dirs=s.package_dirs or None,
                                  xacro_args=s.xacro_mapping or None, allow_outside_meshes=s.allow_outside_meshes,
                                  reflected_inertia=s.reflected_inertia),
    "mjcf": lambda s: load_mjcf(s.path or "", s.tip, package_dirs=s.package_dirs or None,
                                allow_outside_meshes=s.allow_outside_meshes,
                                reflected_inertia=s.reflected_inertia),
    "sdf": lambda s: load_sdf(s.path or "", s.tip, package_dirs=s.package_dirs or None,
                              allow_outside_meshes=s.allow_outside_meshes, reflected_inertia=s.reflected_inertia),
    "calibrated": lambda s: load_urdf_text(s.text or "", s, s.tip or "tool", s.gravity or None),
}


def _from_spec(spec: RobotSpec) -> Robot:
    """The robot ``spec`` describes: its description loaded, then its tools and limits added."""
    robot = _SPEC_LOADERS[spec.kind](spec.base)
    for name, values in spec.tools:
        robot = robot.with_tool(np.array(values, dtype=float).reshape(4, 4), name)
    if spec.limits:
        if len(spec.limits) != robot.n:
            raise InputError(f"spec: limits for {len(spec.limits)} joints, but {robot.name} has {robot.n}")
        robot = robot.with_limits(np.array(spec.limits, dtype=float))
    return robot


def _file_loader(path: Path) -> tuple[str, Callable[..., Robot], tuple[str, ...]] | None:
    name = path.name.lower()
    hits = [suffix for suffix in FILE_LOADERS if name.endswith(suffix)]
    if not hits:
        return None
    suffix = max(hits, key=len)
    return (suffix, *FILE_LOADERS[suffix])


def file_takes(name_or_path: object, option: str) -> bool:
    """Whether :func:`load` takes ``option`` for ``name_or_path`` (by its suffix, :data:`FILE_LOADERS`): the
    command line passes ``--allow-outside-meshes`` to the robot only where it applies.

    Parameters
    ----------
    name_or_path : object
        What would be loaded (a path, a model name, a Robot: anything; its ``str`` is looked at).
    option : str
        A keyword argument of :func:`load`.

    Returns
    -------
    bool
        False for a shipped model, an example-robot-data name or a file format that does not take it.

    Examples
    --------
    >>> file_takes("arm.urdf.xacro", "xacro_args"), file_takes("puma560", "allow_outside_meshes")
    (True, False)
    """
    found = _file_loader(Path(str(name_or_path)))
    return found is not None and option in found[2]


#: The value of each :func:`load` option that means "not given".
_UNSET: dict[str, Any] = {"package_dirs": None, "xacro_args": None, "allow_outside_meshes": False, "reflected_inertia": True}


def _given(key: str, value: Any) -> bool:
    """Whether a :func:`load` option holds a value other than "not given"."""
    return value is not None and value != () and value != {} and not (key in _UNSET and value == _UNSET[key])


def _options_for(what: str, accepted: tuple[str, ...], options: Mapping[str, Any]) -> dict[str, Any]:
    given = {k: v for k, v in options.items() if _given(k, v)}
    for key in given:
        if key not in accepted:
            takes = sorted(s for s, (_, acc) in FILE_LOADERS.items() if key in acc)
            raise InputError(f"{key}: apply to {', '.join(takes)} files, not to {what}")
    return given


def load(name_or_path: str | os.PathLike[str] | Robot | DHTable | RobotSpec, tip: str | None = None, *,
         package_dirs: Sequence[str | os.PathLike[str]] | None = None, xacro_args: Mapping[str, str] | None = None,
         allow_outside_meshes: bool = False, reflected_inertia: bool = True, strict: bool = False) -> Robot:
    """Load a robot: a shipped model name, a DH ``.yaml``, a ``.urdf``, a ``.xacro``/``.urdf.xacro``,
    an MJCF ``.xml``, an SDFormat ``.sdf``/``.world``, an example-robot-data name, a :class:`DHTable`
    or a :class:`RobotSpec`.

    Parameters
    ----------
    name_or_path : str, Path, Robot, DHTable or RobotSpec
        What to load (see the table in :mod:`robokit.description.loading`). A Robot is returned
        as it is; a RobotSpec (``robot.spec`` of a robot loaded before, possibly in another
        process) is rebuilt with the options it holds.
    tip : str, optional
        The chain's tip frame (default: ``"tool"`` for DH models, the arm's end-effector frame
        for example-robot-data arms, else the end of the chain — of the longest chain for a
        tree, see :func:`~robokit.description.builder.choose_tip`).
    package_dirs : sequence of str or Path, optional
        Folders searched for ROS packages: ``package://pkg/...`` meshes of a URDF, xacro or
        SDFormat file, ``$(find pkg)`` in a xacro file (a folder holding ``<pkg>/package.xml``, or
        the package at any depth below it as colcon finds a workspace's packages; the file's own
        folder and the folders above it are always searched), and the folders of
        SDFormat ``model://NAME`` includes.
    xacro_args : dict of str to str, optional
        xacro argument values (``{"name": "value"}``), xacro files only.
    allow_outside_meshes : bool
        Read meshes that a URDF names outside its folder, its package and ``package_dirs``
        (absolute paths, ``../`` out of the package); refused by default.
    reflected_inertia : bool
        Model each joint's reflected rotor inertia in M and inverse dynamics (default True):
        MJCF's joint ``armature``, as MuJoCo adds it, and Drake's ``drake:rotor_inertia ·
        drake:gear_ratio²`` — of an SDFormat joint, or of a URDF (or xacro) ``<transmission>``'s
        actuator — as Drake adds it. False leaves it out.
    strict : bool
        Refuse a robot with a physically impossible link inertia (not positive definite, or
        principal moments breaking the triangle inequality) instead of loading it with a
        :class:`~robokit.errors.PhysicalityWarning` per link. A DH table's inertias are the
        course's parameter sets and are not checked.

    Returns
    -------
    Robot
        With ``robot.spec``, the :class:`RobotSpec` that rebuilds it (``load(robot.spec)``),
        and ``robot.source``, its human-readable form.

    Raises
    ------
    InputError
        An unknown name, a file the format's loader refuses, an option the format does not
        take, options given together with a RobotSpec (the spec holds its own); with
        ``strict=True``, a physically impossible link.

    Examples
    --------
    >>> import numpy as np, robokit
    >>> robot = robokit.load("puma560")
    >>> robot.frame_pose(np.zeros(6)).shape
    (4, 4)
    >>> robokit.load(robot.spec).n
    6
    """
    if not isinstance(strict, (bool, np.bool_)):
        raise InputError(f"strict: expected True or False, got {strict!r}")
    with strict_loading(bool(strict)):
        return _load(name_or_path, tip, package_dirs=package_dirs, xacro_args=xacro_args,
                     allow_outside_meshes=allow_outside_meshes, reflected_inertia=reflected_inertia)


def _load(name_or_path: str | os.PathLike[str] | Robot | DHTable | RobotSpec, tip: str | None, *,
          package_dirs: Sequence[str | os.PathLike[str]] | None, xacro_args: Mapping[str, str] | None,
          allow_outside_meshes: bool, reflected_inertia: bool) -> Robot:
    options = dict(package_dirs=package_dirs, xacro_args=xacro_args, allow_outside_meshes=allow_outside_meshes,
                   reflected_inertia=reflected_inertia)
    if isinstance(name_or_path, Robot):
        return name_or_path
    if isinstance(name_or_path, RobotSpec):
        given = [k for k, v in options.items() if _given(k, v)] + (["tip"] if tip else [])
        if given:
            raise InputError(f"{', '.join(given)}: a RobotSpec holds its own options; load(spec) takes none")
        return _from_spec(name_or_path)
    if isinstance(name_or_path, DHTable):
        _options_for("a DHTable", (), options)
        if tip not in (None, "tool"):
            raise InputError(f"tip: a DH model's tip is its 'tool' frame, got {tip!r}")
        return robot_from_dh(name_or_path)
    if not isinstance(name_or_path, (str, os.PathLike)):
        raise InputError(f"model: expected a name, a path, a Robot, a DHTable or a RobotSpec, "
                         f"got {type(name_or_path).__name__}")
    s = os.fspath(name_or_path)
    if not isinstance(s, str):
        raise InputError(f"model: expected a text path, got {s!r}")
    path = Path(s).expanduser() if s.startswith("~") else Path(s)  # "~/ws/src/...", as package_dirs take it
    found = _file_loader(path)
    if found is not None:
        suffix, loader, accepted = found
        return loader(path, tip, **_options_for(f"{suffix} files", accepted, options))
    if s in shipped_models():
        _options_for("shipped models", (), options)
        return load_shipped(s, tip)
    if s in example_robot_names():
        _options_for("example-robot-data models", (), options)
        return load_example_robot(s, tip)
    suffixes = ", ".join(dict.fromkeys(FILE_LOADERS))
    if s and path.is_dir():
        raise InputError(f"model: {s!r} is a folder; give a robot file in it ({suffixes}) or a model name")
    if s and path.is_file():
        raise InputError(f"model: {s!r} is not a robot file robokit reads: their names end in {suffixes}")
    hint = unknown_model_hint(s, shipped_models() + example_robot_names())
    raise InputError(f"model: unknown robot {s!r}" + (f"; {hint}" if hint else "")
                     + f"; rk.models() lists the names robokit.load knows, or give a file ({suffixes})")


def models() -> ModelCatalogue:
    """The names :func:`load` knows without a file, and the file formats it reads.

    The shipped DH models (``twolink``, ``rrr``, ``puma560``, …) and every example-robot-data
    name (an arm's note gives its default tip; a robot example-robot-data gives a floating base is
    loaded with the base fixed), then the file suffixes ``load`` reads.

    Returns
    -------
    ModelCatalogue
        A sequence of names (``"panda" in rk.models()``) with ``.rows`` (name, source, note) and
        ``.formats`` (suffix → what it holds); it prints as a table.

    Examples
    --------
    >>> cat = models()
    >>> {"puma560", "panda", "ur5"} <= set(cat), cat.rows[0].source
    (True, 'shipped DH table')
    >>> ".urdf" in cat.formats
    True
    """
    rows = [ModelInfo(n, "shipped DH table", "tip 'tool'") for n in shipped_models()]
    robots = _erd_loaders()
    for n in example_robot_names():
        loader = robots.get(n)
        note = f"arm, tip {EXAMPLE_ROBOT_TIPS[n]!r}" if n in EXAMPLE_ROBOT_TIPS else (
            "floating base (fixed when loaded)" if getattr(loader, "free_flyer", False) else "")
        rows.append(ModelInfo(n, "example-robot-data", note))
    return ModelCatalogue(rows, {suffix: FORMAT_NAMES.get(suffix, suffix) for suffix in FILE_LOADERS})


def _erd_loaders() -> dict:
    try:
        import example_robot_data as erd

        return dict(getattr(erd, "ROBOTS", {}))
    except ImportError:  # pragma: no cover - a core dependency
        return {}


def spec_of(robot: str | os.PathLike[str] | Robot | DHTable | RobotSpec) -> RobotSpec:
    """The :class:`RobotSpec` of ``robot`` (loading it when it is not a Robot or a spec).

    Parameters
    ----------
    robot : anything :func:`load` takes

    Returns
    -------
    RobotSpec

    Raises
    ------
    InputError
        A Robot built by hand from a Pinocchio model, which has no spec.

    Examples
    --------
    >>> spec_of("rrr")
    RobotSpec(kind='shipped', name='rrr')
    """
    if isinstance(robot, RobotSpec):
        return robot
    rob = load(robot)
    if rob.spec is None:
        raise InputError(f"robot: {rob.name!r} was built from a Pinocchio model, not loaded; it has no RobotSpec "
                         "(load it with robokit.load to ship it to other processes)")
    return rob.spec
