r"""Where a robot came from, as a small frozen value: :class:`RobotSpec`.

Every loader of :mod:`robokit.description.loading` records on the robot it returns
(``robot.spec``) everything needed to build the same robot again: the kind of description,
the file (an absolute path) or the name, the tip frame, the package folders and the xacro
arguments, and — for a DH table — the table itself as YAML text. A spec holds only strings,
booleans and tuples, so it pickles, hashes and compares by value; ``robokit.load(spec)``
rebuilds an equal robot in any process (a Dask worker, a pool of processes), which is how
capability maps ship their robot to the workers.

``robot.source`` is the human-readable form of the spec (:meth:`RobotSpec.describe`).
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Mapping

from robokit.errors import InputError

__all__ = ["RobotSpec", "SPEC_KINDS"]

#: The kinds of robot description a spec may name.
SPEC_KINDS = ("shipped", "dh", "urdf", "xacro", "mjcf", "sdf", "example-robot-data", "calibrated")


@dataclass(frozen=True)
class RobotSpec:
    """A frozen, picklable recipe for one robot: ``robokit.load(spec)`` rebuilds it.

    Attributes
    ----------
    kind : str
        One of :data:`SPEC_KINDS`: ``"shipped"`` (a model of ``models/``, by name), ``"dh"`` (a
        DH table, carried as YAML text), ``"urdf"``, ``"xacro"``, ``"mjcf"``, ``"sdf"`` (a file,
        by absolute path), ``"example-robot-data"`` (by name) or ``"calibrated"`` (a robot whose
        geometry :func:`robokit.calibrate` fitted: its URDF carried as text, with the nominal arm's
        spec and the gravity).
    name : str or None
        The model name (``"shipped"``, ``"example-robot-data"``; the robot's name for
        ``"calibrated"``); None otherwise.
    path : str or None
        Absolute path of the file (``"urdf"``, ``"xacro"``, ``"mjcf"``, and ``"dh"`` when the
        table was read from a file — for the human-readable form only: the table is ``text``).
    tip : str or None
        The tip frame asked for (None: the loader's default).
    package_dirs : tuple of str
        Absolute folders searched for ROS packages (``"urdf"``, ``"xacro"``, ``"sdf"``).
    xacro_args : tuple of (str, str)
        The xacro argument values, sorted by name (``"xacro"``).
    allow_outside_meshes : bool
        Whether meshes outside the file's package were allowed (``"urdf"``).
    reflected_inertia : bool
        Whether the joints' reflected rotor inertia is in M and inverse dynamics (``"mjcf"``:
        MuJoCo's joint ``armature``; ``"sdf"``, ``"urdf"``, ``"xacro"`` and ``"calibrated"``: Drake's
        ``rotor_inertia · gear_ratio²``); default True.
    text : str or None
        The DH table as YAML text, angles in rad (``"dh"``): parsed by the strict YAML loader
        when the spec is loaded, so a rebuilt table is the same table even if the file changed;
        the URDF text (``"calibrated"``), read under the same checks as a URDF file.
    nominal : RobotSpec or None
        ``"calibrated"``: the spec of the arm the calibration started from (its structure gives
        the calibrated arm's exact IK, :mod:`robokit.ik.calibrated`); None when unknown.
    gravity : tuple of float
        ``"calibrated"``: the gravity vector (3 values, m/s², base frame), which a URDF cannot hold.
    tools : tuple of (str, tuple of float)
        Tool frames added by :meth:`robokit.Robot.with_tool`, in order: the frame's name and its pose
        in the tip before it (16 numbers, row-major; m). ``load`` adds them to the robot it builds.
    limits : tuple of (float, float)
        Joint limits given by :meth:`robokit.Robot.with_limits` (one pair per joint, rad or m; ±inf
        unlimited), applied after the tools; ``()`` keeps the description's limits.

    Examples
    --------
    >>> import pickle, robokit
    >>> robot = robokit.load("rrr")
    >>> robot.spec
    RobotSpec(kind='shipped', name='rrr')
    >>> robokit.load(pickle.loads(pickle.dumps(robot.spec))).n
    3
    """

    kind: str
    name: str | None = None
    path: str | None = None
    tip: str | None = None
    package_dirs: tuple[str, ...] = ()
    xacro_args: tuple[tuple[str, str], ...] = ()
    allow_outside_meshes: bool = False
    text: str | None = None
    reflected_inertia: bool = True
    nominal: RobotSpec | None = None
    gravity: tuple[float, ...] = ()
    tools: tuple[tuple[str, tuple[float, ...]], ...] = ()
    limits: tuple[tuple[float, float], ...] = ()

    def __post_init__(self) -> None:
        if self.kind not in SPEC_KINDS:
            raise InputError(f"spec: kind must be one of {', '.join(SPEC_KINDS)}, got {self.kind!r}")
        for field_name in ("name", "path", "tip", "text"):
            value = getattr(self, field_name)
            if value is not None and not isinstance(value, str):
                raise InputError(f"spec: {field_name} must be a string or None, got {type(value).__name__}")
        if not isinstance(self.package_dirs, tuple) or not all(isinstance(d, str) for d in self.package_dirs):
            raise InputError("spec: package_dirs must be a tuple of strings")
        if not isinstance(self.xacro_args, tuple) or not all(
                isinstance(kv, tuple) and len(kv) == 2 and all(isinstance(x, str) for x in kv)
                for kv in self.xacro_args):
            raise InputError("spec: xacro_args must be a tuple of (name, value) string pairs")
        for flag in ("allow_outside_meshes", "reflected_inertia"):
            if not isinstance(getattr(self, flag), bool):
                raise InputError(f"spec: {flag} must be a bool")
        if self.nominal is not None and not isinstance(self.nominal, RobotSpec):
            raise InputError(f"spec: nominal must be a RobotSpec or None, got {type(self.nominal).__name__}")
        if not isinstance(self.gravity, tuple) or len(self.gravity) not in (0, 3) or not all(
                isinstance(g, float) for g in self.gravity):
            raise InputError("spec: gravity must be () or a tuple of 3 floats")
        if not isinstance(self.tools, tuple) or not all(
                isinstance(t, tuple) and len(t) == 2 and isinstance(t[0], str) and isinstance(t[1], tuple)
                and len(t[1]) == 16 and all(isinstance(x, float) for x in t[1]) for t in self.tools):
            raise InputError("spec: tools must be a tuple of (name, 16 floats) pairs")
        if not isinstance(self.limits, tuple) or not all(
                isinstance(lim, tuple) and len(lim) == 2 and all(isinstance(x, float) for x in lim)
                for lim in self.limits):
            raise InputError("spec: limits must be a tuple of (lower, upper) float pairs")
        needs = {"shipped": "name", "example-robot-data": "name", "dh": "text",
                 "urdf": "path", "xacro": "path", "mjcf": "path", "sdf": "path", "calibrated": "text"}[self.kind]
        if getattr(self, needs) is None:
            raise InputError(f"spec: a {self.kind!r} spec needs {needs}")

    @property
    def xacro_mapping(self) -> dict[str, str]:
        """The xacro arguments as a dict (``{}`` for other kinds)."""
        return dict(self.xacro_args)

    @property
    def base(self) -> RobotSpec:
        """The spec without the tools and limits added by ``with_tool``/``with_limits`` (itself when none)."""
        if not self.tools and not self.limits:
            return self
        from dataclasses import replace

        return replace(self, tools=(), limits=())

    def describe(self) -> str:
        """Human-readable origin (this is ``robot.source``).

        Returns
        -------
        str
            ``models/<name>.yaml`` for a shipped model, ``example-robot-data:<name>``, the file's
            path for a file, ``DH table <name>`` for a table built in memory.

        Examples
        --------
        >>> RobotSpec("example-robot-data", name="ur5").describe()
        'example-robot-data:ur5'
        """
        if self.tools or self.limits:
            changes = [f"tool {name!r}" for name, _ in self.tools] + (["other joint limits"] if self.limits else [])
            return f"{self.base.describe()} with {', '.join(changes)}"
        if self.kind == "shipped":
            return f"models/{self.name}.yaml"
        if self.kind == "example-robot-data":
            return f"example-robot-data:{self.name}"
        if self.kind == "calibrated":
            return f"calibrated from {self.nominal.describe()}" if self.nominal is not None else "<calibrated robot>"
        if self.path is not None:
            return self.path
        return "<DHTable>"

    def __repr__(self) -> str:
        shown = [f"kind={self.kind!r}"]
        for key in ("name", "path", "tip"):
            value = getattr(self, key)
            if value is not None:
                shown.append(f"{key}={value!r}")
        if self.package_dirs:
            shown.append(f"package_dirs={self.package_dirs!r}")
        if self.xacro_args:
            shown.append(f"xacro_args={self.xacro_args!r}")
        if self.allow_outside_meshes:
            shown.append("allow_outside_meshes=True")
        if self.text is not None:
            what = "URDF" if self.kind == "calibrated" else "DH YAML"
            shown.append(f"text=<{len(self.text)} characters of {what}>")
        if not self.reflected_inertia:
            shown.append("reflected_inertia=False")
        if self.nominal is not None:
            shown.append(f"nominal={self.nominal!r}")
        if self.tools:
            shown.append(f"tools=<{', '.join(repr(name) for name, _ in self.tools)}>")
        if self.limits:
            shown.append(f"limits=<{len(self.limits)} joints>")
        return f"RobotSpec({', '.join(shown)})"


def xacro_args_tuple(xacro_args: Mapping[str, object] | None) -> tuple[tuple[str, str], ...]:
    """``xacro_args`` as the sorted tuple of string pairs a spec holds."""
    return tuple(sorted((str(k), str(v)) for k, v in (xacro_args or {}).items()))
