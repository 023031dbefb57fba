"""Reading a URDF file robokit did not write: checks with clear messages before Pinocchio sees it.

Pinocchio's URDF parser (urdfdom) accepts files that are not physical — a negative or NaN
mass, an inertia tensor that is not positive semi-definite, a zero joint axis, limits with
lower > upper — and prints its own complaints on the process's stderr. :func:`read_urdf`
checks each of these and raises :class:`robokit.InputError` naming the file and the link or
joint, and returns the document with every mesh reference resolved:

* ``package://pkg/path`` is looked up in the package roots (the URDF's folder and its
  ancestors, plus any ``package_dirs`` given): ``<root>/pkg/path`` or, when a root is the
  package itself (``<root>/package.xml`` with that name, or a folder of that name), ``<root>/path``;
  then at any depth below each ``package_dirs`` folder, as colcon finds a workspace's packages
  (:func:`robokit.description.meshes.package_below`);
* a relative path is taken from the URDF's folder;
* a mesh that resolves outside the URDF's folder and the package roots (an absolute path,
  ``../``, ``file://``) is refused unless ``allow_outside_meshes=True``;
* a mesh file that does not exist, is not a regular file (a FIFO, ``/dev/zero``) or is larger
  than :data:`robokit.description.meshes.MAX_MESH_BYTES` is dropped from the geometry with a
  warning naming it (and the size).

Mimic joints are reported (``mimic`` in the result) so that the loader can refuse one on
the chain (robokit's joints are independent) and lock one off it.

Drake's URDF dialect: a ``<transmission>`` whose first ``<actuator>`` holds
``<drake:rotor_inertia value>`` and/or ``<drake:gear_ratio value>`` gives its joint Drake's reflected
rotor inertia (:mod:`robokit.description.reflected`), read by the rules of Drake's URDF parser
(``ParseTransmission``): only a ``<type>`` (or legacy ``type`` attribute) containing
``SimpleTransmission`` counts (another type Drake ignores, with a warning); the rotor inertia
defaults to 0 and the gear ratio to 1, and ``<mechanicalReduction>`` plays no part (Drake warns when
it is not 1); a fixed joint or a joint whose ``<limit effort>`` is 0 gets no actuator and so no
inertia (no ``<limit>`` or no ``effort``: Drake's effort limit is unlimited); a negative effort
limit, a missing ``value``, a missing ``<type>``, actuator name or joint, or a joint that is not
defined is an error in Drake and an :class:`~robokit.errors.InputError` here. They are in
``rotors``; the loader turns them into ``model.armature``.

Nothing is dropped silently: every element the file holds that robokit's model does not use
(:data:`MODELLED` lists what it uses) — ``<transmission>`` (but those giving Drake's rotor
inertia), ``<ros2_control>``, ``<gazebo>`` (and its plugins), ``<sensor>``, a joint's
``<safety_controller>``, ``<calibration>`` and nonzero ``<dynamics damping/friction>``, a link's
``<contact>``, anything unknown — is listed in ``unmodelled``, one note per element kind, which the
loader shows once; so are Drake's other extensions deeper in the file, its ``drake:`` attributes
(``<limit drake:acceleration>``) and elements (``<drake:proximity_properties>`` in a
``<collision>``, ``<drake:declare_convex>`` in a ``<mesh>``), in one note.
"""
from __future__ import annotations

import math
import os
import warnings
import xml.etree.ElementTree as ET
from dataclasses import dataclass, field
from pathlib import Path
from typing import Iterable, Literal, NoReturn, Sequence

import numpy as np

from robokit._io import read_input_text
from robokit._stack import outside_level
from robokit._xml import parse_xml
from robokit.description.limits import check_joint_count
from robokit.description.meshes import (MAX_TOTAL_MESH_BYTES, without_meshes, allowed_roots, is_inside, mesh_file_problem,
                                         package_below, package_name)
from robokit.description.reflected import DrakeRotor
from robokit.description.urdf_description import color_problem
from robokit.errors import InputError, RobokitWarning

__all__ = ["MAX_URDF_BYTES", "UrdfDocument", "read_urdf"]

#: Largest URDF robokit reads (the largest example-robot-data URDF is about 300 kB).
MAX_URDF_BYTES = 20 << 20

#: Largest magnitude of an origin coordinate, mass or inertia entry accepted (SI units).
MAX_MAGNITUDE = 1e12

_JOINT_TYPES = {"revolute", "continuous", "prismatic", "fixed", "floating", "planar"}

#: The children of ``<robot>``, ``<link>`` and ``<joint>`` that robokit's model uses (a joint's
#: ``<mimic>`` is handled by the loader: refused on the chain, locked off it, with a note).
MODELLED = {
    "robot": {"link", "joint", "material"},
    "link": {"inertial", "visual", "collision"},
    "joint": {"origin", "parent", "child", "axis", "limit", "mimic"},
}

#: Why an element is not modelled, by tag (others: "not part of robokit's model").
_WHY = {
    "transmission": ("actuator transmissions without Drake's drake:rotor_inertia/drake:gear_ratio add nothing to "
                     "robokit's rigid-body model"),
    "mechanicalReduction": ("Drake's URDF parser takes the reflected inertia's gear ratio from drake:gear_ratio alone "
                            "(it warns about a mechanicalReduction other than 1), and so does robokit"),
    "drake": "not part of robokit's model",
    "ros2_control": "controller hardware interfaces are not part of robokit's model",
    "gazebo": "simulator settings and plugins are not part of robokit's model",
    "sensor": "sensors are not part of robokit's model",
    "safety_controller": "soft limits are not applied; robot.qlim holds the <limit> values",
    "calibration": "calibration reference positions are not applied",
    "dynamics": ("robokit's dynamics (rnea, crba, aba) are rigid-body only; the values stay in "
                 "robot.model.damping and robot.model.friction"),
    "joint_properties": "joint damping/friction are not part of robokit's rigid-body dynamics",
    "contact": "contact and friction parameters are not part of robokit's model",
}


@dataclass
class UrdfDocument:
    """A checked URDF, as :func:`read_urdf` returns it.

    Attributes
    ----------
    path : pathlib.Path
        The file it was read from (or that names it, for a xacro expansion).
    xml : str
        The URDF text, mesh references resolved to absolute paths.
    name : str
        The ``<robot name>``.
    mimic : dict of str to str
        ``{joint: the joint it mimics}``.
    mimic_terms : dict of str to (float, float)
        ``{joint: (multiplier, offset)}`` of each ``<mimic>``: the joint's value is multiplier × the
        value of the joint it mimics + offset (defaults 1 and 0, as urdfdom reads them).
    package_dirs : list of pathlib.Path
        Folders searched for ``package://`` names.
    warnings : list of str
        One line per remark (e.g. a mesh not found or too large: the link is drawn without it);
        also issued as :class:`~robokit.errors.RobokitWarning`.
    names : frozenset of str
        Every link and joint name of the file (the names robokit may report).
    unmodelled : list of (str, str)
        ``(tag, note)``: one note per kind of element read but not modelled (not issued here;
        the loader shows them).
    rotors : list of DrakeRotor
        Drake's rotor inertia and gear ratio of the joints a ``<transmission>`` gives them (module
        docstring); the loader adds ``rotor_inertia · gear_ratio²`` to their armature.

    Examples
    --------
    >>> from robokit.description.models import model_path
    >>> doc = read_urdf(model_path("twolink", ".urdf"))
    >>> doc.name, doc.mimic, doc.warnings, doc.unmodelled, doc.rotors
    ('twolink', {}, [], [], [])
    """

    path: Path
    xml: str
    name: str
    mimic: dict = field(default_factory=dict)
    package_dirs: list = field(default_factory=list)
    warnings: list = field(default_factory=list)
    names: frozenset = frozenset()
    unmodelled: list = field(default_factory=list)
    rotors: list = field(default_factory=list)
    mimic_terms: dict = field(default_factory=dict)


def _fail(path: str | os.PathLike[str], msg: str) -> NoReturn:
    if len(msg) > 300:
        msg = msg[:297] + "..."
    raise InputError(f"{path}: {msg}")


def _floats(text: str | None, count: int, path: str | os.PathLike[str], where: str) -> list[float]:
    parts = (text or "").split()
    if len(parts) != count:
        _fail(path, f"{where}: expected {count} numbers, got {text!r}")
    try:
        values = [float(p) for p in parts]
    except ValueError:
        _fail(path, f"{where}: expected {count} numbers, got {text!r}")
    if not all(math.isfinite(v) for v in values):
        _fail(path, f"{where}: expected finite numbers, got {text!r}")
    _check_magnitude(values, path, where)
    return values


def _check_magnitude(values: Sequence[float], path: str | os.PathLike[str], where: str) -> None:
    """Refuse a finite number so large that FK and dynamics overflow to inf/NaN (joint limits exempt:
    URDFs write ±1e16 for "unlimited")."""
    if any(abs(v) > MAX_MAGNITUDE for v in values):
        _fail(path, f"{where}: a value is out of range (at most {MAX_MAGNITUDE:g} in magnitude; SI units), "
                    f"got {' '.join(f'{v:g}' for v in values)}")


def _float_attr(el: ET.Element, name: str, path: str | os.PathLike[str], where: str,
                default: float | None = None) -> float:
    text = el.get(name)
    if text is None:
        if default is None:
            _fail(path, f"{where}: missing attribute '{name}'")
        return default
    try:
        v = float(text)
    except ValueError:
        _fail(path, f"{where}: attribute '{name}' is not a number ({text!r})")
    if math.isnan(v):
        _fail(path, f"{where}: attribute '{name}' is NaN")
    return v


def _check_name(name: str | None, path: str | os.PathLike[str], what: str) -> None:
    if not name or not name.isprintable() or len(name) > 200:
        shown = repr(name) if name is None or len(repr(name)) <= 60 else repr(name)[:57] + "..."
        _fail(path, f"{what}: expected a printable name (at most 200 characters), got {shown}")


def _package_roots(path: Path, package_dirs: Sequence[str | os.PathLike[str]] | None) -> list[Path]:
    roots = [Path(p).resolve() for p in (package_dirs or [])]
    folder = path.parent.resolve()
    roots.append(folder)
    roots.extend(folder.parents)
    return roots


def _allowed_roots(path: Path, package_dirs: Sequence[str | os.PathLike[str]] | None) -> list[Path]:
    """Folders a mesh may be read from without ``allow_outside_meshes`` (one rule for every format:
    :func:`robokit.description.meshes.allowed_roots`)."""
    return allowed_roots(path, package_dirs)


def _inside(p: Path, roots: Iterable[Path]) -> bool:
    return is_inside(p, roots)


def _resolve_mesh(uri: str, path: Path, roots: list[Path], allowed: list[Path],
                  package_dirs: Sequence[str | os.PathLike[str]] | None = None) -> tuple[Path | None, str]:
    """(resolved absolute path or None, reason) for a mesh filename attribute; a ``package://`` name
    not found in ``roots`` is looked for at any depth below ``package_dirs`` (as colcon finds a
    workspace's packages)."""
    folder = path.parent.resolve()
    if uri.startswith("package://"):
        rest = uri[len("package://"):]
        pkg, _, rel = rest.partition("/")
        for root in roots:
            for cand in (root / pkg / rel, root / rel if (root.name == pkg or _is_package(root, pkg)) else None):
                if cand is not None and cand.is_file():
                    return cand.resolve(), ""
        for d in package_dirs or ():
            found, _ = package_below(Path(d).expanduser(), pkg)
            if found is not None and (found / rel).is_file():
                return (found / rel).resolve(), ""
        return None, "not found in the package roots"
    p = Path(uri[len("file://"):]) if uri.startswith("file://") else Path(uri)
    cand = p if p.is_absolute() else folder / p
    cand = cand.resolve()
    return cand, ("" if _inside(cand, allowed) else "outside")


def _is_package(root: Path, pkg: str) -> bool:
    manifest = root / "package.xml"
    if not manifest.is_file():
        return False
    return package_name(manifest) == pkg


def read_urdf(path: str | os.PathLike[str], package_dirs: Sequence[str | os.PathLike[str]] | None = None,
              allow_outside_meshes: bool = False, text: str | None = None,
              unphysical_inertias: list[str] | None = None) -> UrdfDocument:
    """Read and check a URDF file (see the module docstring for what is checked).

    Parameters
    ----------
    path : str or os.PathLike
        The URDF file (at most :data:`MAX_URDF_BYTES`).
    package_dirs : sequence of path-like, optional
        Folders where ``package://`` names are looked up (besides the file's own package).
    allow_outside_meshes : bool, optional
        Read meshes outside the file's folder, its package and ``package_dirs`` (default False).
    text : str or None, optional
        The URDF's text when it does not come from ``path`` itself (a xacro expansion);
        ``path`` then only names it and anchors relative mesh paths.
    unphysical_inertias : list of str, optional
        When given, an inertia tensor that is not positive semi-definite is described in this list
        (one line each) instead of refused: for curated collections robokit loads by name, whose
        files Pinocchio's parser has always accepted (example-robot-data's TIAGo antenna links).

    Returns
    -------
    UrdfDocument
        The checked text and what was learnt on the way; a bad file raises
        :class:`~robokit.errors.InputError` naming the file and the element.

    Examples
    --------
    >>> from robokit.description.models import model_path
    >>> read_urdf(model_path("rrr", ".urdf")).xml.count('type="revolute"')    # three joints
    3
    """
    path = Path(path)
    if text is not None:
        raw = text.encode("utf-8")
        if len(raw) > MAX_URDF_BYTES:
            raise InputError(f"{path}: expanded URDF too large ({len(raw)} bytes; at most {MAX_URDF_BYTES})")
    else:
        raw = read_input_text(path, MAX_URDF_BYTES, "a URDF file").encode("utf-8")
    return _check(path, raw, package_dirs, allow_outside_meshes, unphysical_inertias)


def _check(path: Path, raw: bytes, package_dirs: Sequence[str | os.PathLike[str]] | None,
           allow_outside_meshes: bool, unphysical_inertias: list[str] | None = None) -> UrdfDocument:
    # bounded (no DTD/entities, depth and element count capped); names as urdfdom (TinyXML2) reads them,
    # a prefix declared or not
    root = parse_xml(raw, path, namespaces=False)
    if root.tag != "robot":
        _fail(path, f"expected a <robot> root element, got <{root.tag}>")
    check_joint_count(len(root.findall("joint")), path, "<joint> elements")
    name = root.get("name") or path.stem
    _check_name(name, path, "robot name")

    links: dict[str, ET.Element] = {}
    for el in root.findall("link"):
        lname = el.get("name")
        _check_name(lname, path, "a <link>'s name")
        assert lname is not None  # _check_name refused a missing name
        if lname in links:
            _fail(path, f"link {lname!r} is defined twice")
        links[lname] = el
        inertial = el.find("inertial")
        if inertial is None:
            continue
        where = f"link {lname!r}, <inertial>"
        mass_el = inertial.find("mass")
        mass = _float_attr(mass_el, "value", path, f"{where} <mass>") if mass_el is not None else 0.0
        if not math.isfinite(mass) or mass < 0:
            _fail(path, f"{where}: mass must be a finite non-negative number, got {mass:g}")
        _check_magnitude([mass], path, f"{where} <mass>")
        ine = inertial.find("inertia")
        if ine is not None:
            keys = ("ixx", "iyy", "izz", "ixy", "iyz", "ixz")
            ixx, iyy, izz, ixy, iyz, ixz = (_float_attr(ine, k, path, f"{where} <inertia>", 0.0) for k in keys)
            if not all(math.isfinite(v) for v in (ixx, iyy, izz, ixy, iyz, ixz)):
                _fail(path, f"{where}: inertia values must be finite")
            _check_magnitude([ixx, iyy, izz, ixy, iyz, ixz], path, f"{where} <inertia>")
            I = np.array([[ixx, ixy, ixz], [ixy, iyy, iyz], [ixz, iyz, izz]])
            ev = np.linalg.eigvalsh(I)
            if ev.min() < -1e-9 * max(1.0, float(abs(ev).max())):
                why = (f"{where}: inertia tensor is not positive semi-definite "
                       f"(eigenvalues {', '.join(f'{v:.3g}' for v in ev)})")
                if unphysical_inertias is None:
                    _fail(path, why)
                unphysical_inertias.append(f"{path}: {why}")
        origin = inertial.find("origin")
        if origin is not None:
            for key in ("xyz", "rpy"):
                if origin.get(key) is not None:
                    _floats(origin.get(key), 3, path, f"{where} <origin {key}>")

    colors = []  # the colours urdfdom cannot take: noted, as urdfdom logs them
    top_materials: set[str] = set()
    for mat in root.findall("material"):
        mname = mat.get("name", "")
        if mname in top_materials:
            _fail(path, f"material {mname!r} is defined twice at the top level (urdfdom refuses the robot)")
        top_materials.add(mname)
        problem = color_problem(mat)
        if problem:
            colors.append(f"material {mname!r}: {problem}")
    for lname, el in links.items():
        for mat in el.findall("visual/material"):
            problem = color_problem(mat)
            if problem:
                colors.append(f"link {lname!r} <visual> material {mat.get('name', '')!r}: {problem}")

    joints = {}
    mimic = {}
    mimic_terms = {}
    children = set()
    for el in root.findall("joint"):
        jname = el.get("name")
        _check_name(jname, path, "a <joint>'s name")
        if jname in joints:
            _fail(path, f"joint {jname!r} is defined twice")
        joints[jname] = el
        where = f"joint {jname!r}"
        jtype = el.get("type")
        if jtype not in _JOINT_TYPES:
            _fail(path, f"{where}: unknown type {jtype!r} (expected one of {', '.join(sorted(_JOINT_TYPES))})")
        for tag in ("parent", "child"):
            sub = el.find(tag)
            link = sub.get("link") if sub is not None else None
            if link is None:
                _fail(path, f"{where}: missing <{tag} link=...>")
            if link not in links:
                _fail(path, f"{where}: {tag} link {link!r} is not defined")
        child_el = el.find("child")
        assert child_el is not None  # checked in the loop above
        child = child_el.get("link")
        if child in children:
            _fail(path, f"{where}: link {child!r} is the child of two joints")
        children.add(child)
        origin = el.find("origin")
        if origin is not None:
            for key in ("xyz", "rpy"):
                if origin.get(key) is not None:
                    _floats(origin.get(key), 3, path, f"{where} <origin {key}>")
        if jtype in ("revolute", "continuous", "prismatic"):
            axis_el = el.find("axis")
            axis = _floats(axis_el.get("xyz"), 3, path, f"{where} <axis xyz>") if axis_el is not None else [1, 0, 0]
            if np.linalg.norm(axis) < 1e-9:
                _fail(path, f"{where}: the joint axis is zero")
        if jtype in ("revolute", "prismatic"):
            lim = el.find("limit")
            if lim is None:
                _fail(path, f"{where}: a {jtype} joint needs a <limit> (lower, upper, effort, velocity)")
            lo = _float_attr(lim, "lower", path, f"{where} <limit>", 0.0)
            hi = _float_attr(lim, "upper", path, f"{where} <limit>", 0.0)
            if lo > hi:
                _fail(path, f"{where}: lower limit {lo:g} is above the upper limit {hi:g}")
            for key in ("effort", "velocity"):
                v = _float_attr(lim, key, path, f"{where} <limit>", 0.0)
                if v < 0:
                    _fail(path, f"{where}: {key} limit must be non-negative, got {v:g}")
        m = el.find("mimic")
        if m is not None:
            target = m.get("joint")
            if not target:
                _fail(path, f"{where}: <mimic> without a joint")
            mimic[jname] = target
            terms = (_float_attr(m, "multiplier", path, f"{where} <mimic>", 1.0),
                     _float_attr(m, "offset", path, f"{where} <mimic>", 0.0))
            if not all(map(math.isfinite, terms)):
                _fail(path, f"{where}: <mimic> multiplier and offset must be finite")
            mimic_terms[jname] = terms
    for jname, target in mimic.items():
        if target not in joints:
            _fail(path, f"joint {jname!r}: mimics {target!r}, which is not defined")
    roots = [ln for ln in links if ln not in children]
    if len(roots) != 1:
        _fail(path, f"expected one root link, found {len(roots)}: {', '.join(roots[:8])}")

    # Meshes: resolve every reference; refuse escapes, drop (and name) missing files.
    pkg_roots = _package_roots(path, package_dirs)
    allowed = _allowed_roots(path, package_dirs)
    notes = []
    missing: list[str] = []
    mesh_bytes = 0
    for lname, el in links.items():
        for kind in ("visual", "collision"):
            for geo_el in list(el.findall(kind)):
                mesh = geo_el.find("geometry/mesh")
                if mesh is None:
                    continue
                uri = mesh.get("filename") or ""
                resolved, reason = _resolve_mesh(uri, path, pkg_roots, allowed, package_dirs)
                if reason == "outside" and not allow_outside_meshes:
                    _fail(path, f"link {lname!r}: mesh {uri!r} is outside the URDF's folder, its package and the "
                                "package folders given (allow_outside_meshes=True reads it; --allow-outside-meshes on the "
                                "command line)")
                if resolved is None or not os.path.exists(resolved):
                    missing.append(f"link {lname!r} {kind} {uri!r}")
                    el.remove(geo_el)
                    continue
                problem = mesh_file_problem(resolved)
                if problem is None and kind == "visual":
                    mesh_bytes += resolved.stat().st_size
                    if mesh_bytes > MAX_TOTAL_MESH_BYTES:
                        problem = f"the robot's meshes exceed {MAX_TOTAL_MESH_BYTES >> 20} MiB in total"
                if problem is not None:
                    notes.append(f"link {lname!r}: {kind} mesh {uri!r} not read ({problem}); "
                                 f"{without_meshes(kind == 'collision', 1)}")
                    el.remove(geo_el)
                    continue
                mesh.set("filename", str(resolved))
    if len(missing) == 1:
        notes.insert(0, f"mesh not found ({missing[0]}); {without_meshes(missing[0].split()[2] == 'collision', 1)}")
    elif missing:  # a description whose meshes were not shipped: one note, not one per mesh
        shown = ", ".join(missing[:2]) + (", ..." if len(missing) > 2 else "")
        lost = [m.split()[1] for m in missing if m.split()[2] == "collision"]
        notes.insert(0, f"{len(missing)} mesh files not found ({shown}); the robot is drawn without them "
                        "(kinematics and dynamics do not need them)" + (
                            f"; collision checks go without {len(lost)} of them (links "
                            f"{', '.join(dict.fromkeys(lost))} are checked without those shapes)" if lost else ""))
    if colors:
        notes.append(f"{'; '.join(colors[:3])}{f' and {len(colors) - 3} more' if len(colors) > 3 else ''}: "
                     "read as urdfdom reads it (four numbers from 0 to 1, else black, or no colour where a "
                     "part is not such a number); only the drawing depends on it")
    for note in notes:
        warnings.warn(f"{path}: {note}", RobokitWarning, stacklevel=outside_level())
    rotors, read, unmodelled = _drake_transmissions(root, path, joints)
    unmodelled = _unmodelled(root, path, read) + unmodelled + _drake_extensions(root, path, read)
    xml = ET.tostring(root, encoding="unicode")
    return UrdfDocument(path, xml, name, mimic, [str(r) for r in pkg_roots], notes,
                        frozenset(links) | frozenset(joints), unmodelled, rotors, mimic_terms)


def _first(el: ET.Element, tag: str) -> ET.Element | None:
    """The first child named ``tag`` as written (``drake:rotor_inertia``: the file is read with names as
    TinyXML2 reads them, so ElementTree's path syntax, which takes ``drake:`` for a namespace, is not used)."""
    return next((c for c in el if c.tag == tag), None)


def _drake_transmissions(root: ET.Element, path: Path, joints: dict[str | None, ET.Element]
                         ) -> tuple[list[DrakeRotor], dict[int, str], list[tuple[str, str]]]:
    """Drake's rotor inertia and gear ratio of the joints, by the rules of Drake's URDF parser (module
    docstring). Returns the rotors; the elements read, by ``id`` (a transmission that gives them; its
    rotor elements), with what a note says about them (``""``: nothing, the reflected-inertia note does);
    and a note on ``<mechanicalReduction>`` values other than 1 in those transmissions."""
    rotors: list[DrakeRotor] = []
    read: dict[int, str] = {}
    reductions: list[str] = []
    driven: dict[str, str] = {}
    for tr in root.findall("transmission"):
        actuator = _first(tr, "actuator")
        if actuator is None:
            continue
        rotor_el, gear_el = _first(actuator, "drake:rotor_inertia"), _first(actuator, "drake:gear_ratio")
        if rotor_el is None and gear_el is None:
            continue  # no rotor: Drake's actuator adds nothing to M or inverse dynamics
        tname = tr.get("name") or "?"
        where = f"transmission {tname!r}"
        type_el = _first(tr, "type")
        ttype = (type_el.text or "") if type_el is not None else tr.get("type")
        if ttype is None:
            _fail(path, f"{where}: no <type> (Drake's URDF parser requires one to read drake:rotor_inertia)")
        for el in (rotor_el, gear_el):
            if el is not None:
                read[id(el)] = ""
        if "SimpleTransmission" not in ttype:
            read[id(tr)] = f"{tname}: {ttype.strip()!r} is no SimpleTransmission, so Drake ignores its drake:rotor_inertia"
            continue
        read[id(tr)] = ""
        if not actuator.get("name"):
            _fail(path, f"{where}: <actuator> without a name (Drake's URDF parser requires one)")
        joint_el = _first(tr, "joint")
        jname = joint_el.get("name") if joint_el is not None else None
        if not jname:
            _fail(path, f"{where}: no <joint name=...> (Drake's URDF parser requires one)")
        if jname not in joints:
            _fail(path, f"{where}: joint {jname!r} is not defined")
        if jname in driven:
            _fail(path, f"{where}: joint {jname!r} is driven by transmission {driven[jname]!r} too; robokit reads one "
                        "drake:rotor_inertia per joint")
        driven[jname] = tname
        jel = joints[jname]
        kind = jel.get("type") or ""
        if kind in ("floating", "planar"):
            _fail(path, f"{where}: joint {jname!r} is {kind}; robokit reads Drake's rotor inertia on revolute, "
                        "continuous and prismatic joints")
        effort = math.inf  # Drake's effort limit when the joint gives none
        lim = _first(jel, "limit")
        if kind != "fixed" and lim is not None and lim.get("effort") is not None:
            effort = _float_attr(lim, "effort", path, f"joint {jname!r} <limit>")
            if effort < 0:
                _fail(path, f"{where}: joint {jname!r} has a negative effort limit ({effort:g}); Drake's URDF parser "
                            "refuses it")
        rotor = gear = None
        if kind != "fixed" and effort != 0.0:  # Drake reads the values only for an actuator it creates
            values: list[float | None] = []
            for el, tag in ((rotor_el, "drake:rotor_inertia"), (gear_el, "drake:gear_ratio")):
                if el is None:
                    values.append(None)
                    continue
                v = _float_attr(el, "value", path, f"{where} <actuator> <{tag}>")
                if not math.isfinite(v) or v < 0:
                    _fail(path, f"{where} <actuator> <{tag}>: value must be a finite number >= 0, got {v:g}")
                _check_magnitude([v], path, f"{where} <actuator> <{tag}>")
                values.append(v)
            rotor, gear = values
            for el in (tr, actuator):
                red = _first(el, "mechanicalReduction")
                text = (red.text or "").strip() if red is not None else ""
                if text and not _is_one(text):  # Drake: one number, 1
                    reductions.append(f"{tname} {text}")
        rotors.append(DrakeRotor(jname, "fixed" if kind == "fixed" else kind, effort, rotor, gear))
    notes = []
    if reductions:
        notes.append(("mechanicalReduction", f"{path}: <mechanicalReduction> of transmissions {', '.join(reductions)} "
                                             f"read but not modelled: {_WHY['mechanicalReduction']}"))
    return rotors, read, notes


def _is_one(text: str) -> bool:
    try:
        return float(text) == 1.0
    except ValueError:
        return False


def _drake_extensions(root: ET.Element, path: Path, read: dict[int, str]) -> list[tuple[str, str]]:
    """One note on Drake's extensions robokit does not model below the elements :func:`_unmodelled` lists:
    ``drake:`` attributes anywhere (``<limit drake:acceleration>``) and ``drake:`` elements deeper than a
    link's or joint's children (``<drake:declare_convex>`` in a ``<mesh>``), each kind counted."""
    listed = {id(c) for c in root}
    for kind in ("link", "joint"):
        for el in root.findall(kind):
            listed.update(id(c) for c in el)
    counts: dict[str, int] = {}
    for el in root.iter():
        if not isinstance(el.tag, str):
            continue
        for attr in el.attrib:
            if attr.startswith("drake:"):
                key = f"<{el.tag} {attr}>"
                counts[key] = counts.get(key, 0) + 1
        for child in el:
            if isinstance(child.tag, str) and child.tag.startswith("drake:") and id(child) not in listed \
                    and id(child) not in read:
                key = f"<{child.tag}> in <{el.tag}>"
                counts[key] = counts.get(key, 0) + 1
    if not counts:
        return []
    shown = ", ".join(k + (f" ×{n}" if n > 1 else "") for k, n in sorted(counts.items()))
    return [("drake", f"{path}: Drake's URDF extensions {shown} read but not modelled: {_WHY['drake']}")]


def _shown(names: Sequence[str], limit: int = 6) -> str:
    quoted = [repr(n) for n in names[:limit]]
    return ", ".join(quoted) + (f" and {len(names) - limit} more" if len(names) > limit else "")


def _nonzero(el: ET.Element, keys: Sequence[str]) -> list[str]:
    out = []
    for key in keys:
        try:
            if float(el.get(key) or 0.0) != 0.0:
                out.append(f"{key}={el.get(key)}")
        except ValueError:
            out.append(f"{key}={el.get(key)!r}")
    return out


def _unmodelled(root: ET.Element, path: Path, read: dict[int, str] | None = None) -> list[tuple[str, str]]:
    """One ``(tag, note)`` per kind of element the file holds and robokit's model does not use
    (a kind: a tag directly under ``<robot>``, or under its links, or under its joints); ``read``:
    the transmissions that give Drake's rotor inertia (left out) or hold it unused (the reason)."""
    read = read or {}
    found: dict[tuple[str, str], list[str]] = {}  # (where: "robot"/"link"/"joint", tag) → owners
    detail: dict[str, set[str]] = {}
    for el in root:
        if not isinstance(el.tag, str) or el.tag in MODELLED["robot"] or read.get(id(el)) == "":
            continue
        if read.get(id(el)):
            detail.setdefault(el.tag, set()).add(read[id(el)])
        found.setdefault(("robot", el.tag), []).append(el.get("name") or "")
        if el.tag in ("gazebo", "ros2_control"):
            for plugin in el.iter("plugin"):
                text = plugin.get("filename") or plugin.get("name") or (plugin.text or "").strip()
                detail.setdefault(el.tag, set()).add(text or "plugin")
        elif el.tag == "sensor":
            detail.setdefault(el.tag, set()).add(el.get("type") or "sensor")
    for kind in ("link", "joint"):
        for el in root.findall(kind):
            for child in el:
                if not isinstance(child.tag, str) or child.tag in MODELLED[kind]:
                    continue
                if child.tag == "dynamics":
                    values = _nonzero(child, ("damping", "friction"))
                    if not values:
                        continue  # zeros: nothing left out
                    detail.setdefault("dynamics", set()).update(values)
                found.setdefault((kind, child.tag), []).append(el.get("name") or "?")
    out = []
    for (where, tag), owners in found.items():
        if where == "robot":
            what = f"<{tag}>" + (f" ({len(owners)})" if len(owners) > 1 else "")
        else:
            what = f"<{tag}> of {where}{'s' if len(owners) > 1 else ''} {_shown(owners)}"
        extra = sorted(detail.get(tag, ()))
        if extra:
            what += f" [{', '.join(extra[:6])}{', …' if len(extra) > 6 else ''}]"
        why = _WHY.get(tag, "not part of robokit's model")
        out.append((tag, f"{path}: {what} read but not modelled: {why}"))
    return out


def capture_native_output() -> _NativeCapture:
    """Context manager that captures what C/C++ code writes to the process's stderr (fd 2)
    while it is active; the text is in ``.text`` afterwards. Used around Pinocchio's parsers
    so that urdfdom's own lines become part of robokit's one-line message."""
    return _NativeCapture()


class _NativeCapture:
    def __init__(self) -> None:
        self.text = ""

    def __enter__(self) -> _NativeCapture:
        import sys
        import tempfile

        try:
            sys.stderr.flush()
        except Exception:  # pragma: no cover
            pass
        self._tmp = tempfile.TemporaryFile()
        try:
            self._saved: int | None = os.dup(2)
            os.dup2(self._tmp.fileno(), 2)
        except OSError:  # pragma: no cover - no fd 2
            self._saved = None
        return self

    def __exit__(self, *exc: object) -> Literal[False]:
        if self._saved is not None:
            os.dup2(self._saved, 2)
            os.close(self._saved)
        self._tmp.seek(0)
        self.text = self._tmp.read(20000).decode("utf-8", "replace")
        self._tmp.close()
        return False

    def first_error(self) -> str:
        """The first meaningful line captured (urdfdom prints 'Error: ...')."""
        lines = [ln.strip() for ln in self.text.splitlines() if ln.strip()]
        for ln in lines:
            if "error" in ln.lower():
                return ln
        return lines[0] if lines else ""
