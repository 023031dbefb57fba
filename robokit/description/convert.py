"""``robokit convert``: DH YAML → URDF, URDF (or example-robot-data name) → PoE JSON or DH YAML.

Every output is written atomically: a failure leaves no file behind. Bad input raises
``ValueError`` with a one-line message (the CLI prints it and exits with status 2).
"""
from __future__ import annotations

import json
import math
import os
from pathlib import Path
from typing import TYPE_CHECKING, Mapping, Sequence

from robokit.errors import InputError
from robokit._io import atomic_write, check_not_an_input, check_output_file

if TYPE_CHECKING:
    from robokit.description.robot import Robot

__all__ = ["convert"]


def _locked_note(robot: Robot) -> list[str]:
    """The note on the joints locked off the chain, unless the loader's own notes say where it holds them
    (the MJCF loader: at MuJoCo's qpos0, each with its value)."""
    said = f"{robot.name}: joints off the chain to {robot.tip!r}"
    if not robot.locked_joints or any(n.startswith(said) for n in robot.notes):
        return []
    return [f"{said} locked at their neutral value and their bodies merged: {', '.join(robot.locked_joints)}"]


def _armature_note(robot: Robot) -> list[str]:
    """The note that Mlist/Glist leave the joints' reflected rotor inertia to the JSON's ``armature``."""
    arm = robot.poe.armature
    if not arm.any():
        return []
    return [f"{robot.name}: Mlist/Glist hold the rigid bodies only; the joints' reflected rotor inertia is the JSON's "
            f"'armature' ({', '.join(f'{n} {a:g}' for n, a in zip(robot.joint_names, arm) if a)}): Pinocchio's "
            f"rnea on this chain is their Newton-Euler torques plus armature * ddq"]


def _dh_table_note(robot: Robot) -> list[str]:
    """The note on what a DH table extracted from a file cannot hold: the joints' velocity and effort limits,
    damping and friction (robokit gives a robot loaded from a DH file placeholder limits, velocity 10 and
    effort 1000)."""
    model = robot.model
    iv = [model.joints[model.getJointId(j)].idx_v for j in robot.joint_names]
    held = []
    for what, values in (("velocity limits", model.velocityLimit), ("effort limits", model.effortLimit),
                         ("damping", model.damping), ("friction", model.friction)):
        v = [float(x) for x in values[iv]]
        if any(math.isfinite(x) and x != 0 for x in v):
            held.append(f"{what} {', '.join(f'{x:g}' for x in v)}")
    if not held:
        return []
    return [f"{robot.name}: not written, a DH table has no place for them: {'; '.join(held)} (per joint); "
            "robokit loads a DH file with placeholder limits (velocity 10, effort 1000 in SI units)"]


def convert(input: str | os.PathLike[str], output: str | os.PathLike[str] | None = None, tip: str | None = None,
            convention: str = "standard", *, xacro_args: Mapping[str, str] | None = None,
            package_dirs: Sequence[str | os.PathLike[str]] | None = None,
            reflected_inertia: bool = True, allow_outside_meshes: bool = False) -> tuple[str, list[str]]:
    """Convert a robot description and write the result (what ``robokit convert`` runs).

    * ``IN.yaml|NAME -o OUT.urdf`` — a DH model (a DH file or a shipped model) to URDF (see the URDF
      format page of the documentation);
    * ``IN.urdf|NAME -o OUT.json`` — PoE parameters ``M, Slist, Blist, Mlist, Glist,
      joint_names, tip`` of the chain root → ``tip`` (see the PoE JSON format page of the documentation);
    * ``IN.urdf|NAME -o OUT.yaml`` — a DH table of the chain (``convention``), when the
      URDF → DH converter finds an exact one (a DH model writes its own table);
    * ``ROBOT -o OUT.xml`` — MJCF for any robot ``robokit.load`` reads (DH file, URDF, xacro,
      MJCF, example-robot-data name), see :mod:`robokit.description.mjcf`.

    The file is written atomically: on any error nothing is written.

    Parameters
    ----------
    input : str or os.PathLike
        A DH ``.yaml``, ``.urdf``, ``.xacro``, MJCF ``.xml`` file, a shipped model name or an
        example-robot-data name.
    output : str or os.PathLike or None, optional
        The file to write; its suffix picks the format (``.urdf``, ``.json``, ``.yaml``/``.yml``,
        ``.xml``). None: nothing is written, and the text is the DH table as the lecture prints it
        (what ``robokit convert IN`` prints without ``-o``).
    tip : str or None, optional
        Tip frame of the chain for URDF-like input (default: the end of the longest chain).
    convention : {"standard", "modified"}, optional
        DH convention of a ``.yaml`` output extracted from a URDF (default ``"standard"``).
    xacro_args : mapping of str to str, optional
        Arguments of a xacro file, passed to ``robokit.load``.
    package_dirs : sequence of path-like, optional
        Folders where ``package://`` names are looked up, passed to ``robokit.load``.
    reflected_inertia : bool, optional
        Passed to ``robokit.load`` when False (``--no-reflected-inertia``: MJCF, SDFormat, URDF and
        xacro input without the joints' reflected rotor inertia).
    allow_outside_meshes : bool, optional
        Passed to ``robokit.load`` when True (``--allow-outside-meshes``: the robot file's meshes read
        wherever it names them).

    Returns
    -------
    text : str
        The text written (or that would be written).
    notes : list of str
        Human-readable remarks for stderr (e.g. joints locked off the chain).

    Examples
    --------
    >>> import json, pathlib, tempfile
    >>> with tempfile.TemporaryDirectory() as tmp:
    ...     text, notes = convert("twolink", pathlib.Path(tmp, "twolink.json"))
    >>> poe = json.loads(text)
    >>> poe["M"][0][3], len(poe["Slist"]), notes
    (1.8, 6, [])
    """
    from robokit.description.dh import DHTable
    from robokit.description.loading import load
    from robokit.description.urdf_gen import urdf_from_dh

    src = str(input)
    in_suffix = Path(src).suffix.lower()
    out = check_output_file(output) if output is not None else None
    if out is not None:
        check_not_an_input(out, src)
    out_suffix = out.suffix.lower() if out is not None else None
    notes: list[str] = []
    if out_suffix == ".xml":  # formats: MJCF out, for anything load() reads
        from robokit.description.mjcf_write import mjcf_from_robot

        robot = load(src, tip=tip, xacro_args=xacro_args, package_dirs=package_dirs,
                     reflected_inertia=reflected_inertia, allow_outside_meshes=allow_outside_meshes)
        text, notes = mjcf_from_robot(robot)
        notes[:0] = _locked_note(robot)
    elif out_suffix not in (".urdf", ".json", ".yaml", ".yml", None):
        assert out is not None
        raise InputError(f"output: robokit writes .urdf (a DH model's URDF), .json (PoE parameters), .yaml (a DH "
                         f"table) or .xml (MJCF), got {out.name!r}")
    elif in_suffix in (".yaml", ".yml") and out_suffix == ".urdf":
        if tip is not None:
            raise InputError("--tip: applies to URDF input only (a DH model's tip is its 'tool' frame)")
        text = urdf_from_dh(DHTable.from_yaml(src))
    else:
        robot = load(src, tip=tip, xacro_args=xacro_args, package_dirs=package_dirs,
                     reflected_inertia=reflected_inertia, allow_outside_meshes=allow_outside_meshes)
        notes += _locked_note(robot)
        if out_suffix == ".json":
            text = json.dumps(robot.poe.to_json_dict(), indent=1) + "\n"
            notes += _armature_note(robot)
        elif out_suffix == ".urdf":
            if robot.dh is None:
                raise InputError(f"output: {robot.name} is not a DH model, and robokit writes URDF from DH tables; "
                                 f"write .json (PoE), .yaml (its DH table, when it has an exact one) or .xml (MJCF)")
            text = urdf_from_dh(robot.dh)
        elif robot.dh is not None:  # a DH model: its own table
            text = robot.dh.to_yaml_str() if out_suffix is not None else robot.dh.to_text() + "\n"
        else:
            from robokit.description.urdf_to_dh import urdf_to_dh_text

            text = urdf_to_dh_text(robot, convention=convention, as_yaml=out_suffix is not None)
            if out_suffix is not None:
                notes += _dh_table_note(robot)
    if out is not None:
        atomic_write(out, text)
    return text, notes
