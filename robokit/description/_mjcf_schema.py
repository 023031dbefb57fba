r"""MuJoCo's XML schema: which elements and attributes an MJCF file may hold, and :func:`check_schema`.

MuJoCo refuses a file that names an element or attribute its schema does not know ("Schema
violation: unrecognized element / attribute"), or that repeats an element the schema allows once
(a second ``<inertial>`` in a body, a second ``<flag>`` in ``<option>``). Such a file has no meaning,
so robokit refuses it too, with one line naming the file, the element and the body it sits in.

:data:`_TABLE` lists, for every element of the MJCF XML reference, the elements it may hold and
their attributes: one line per element, indented by its depth, then its multiplicity — ``!`` once,
``?`` at most once, ``*`` any number, ``R`` any number and recursive (a ``<body>`` holds bodies, a
``<default>`` defaults) — then its attributes (continuation lines carry more). The names are the
facts of MuJoCo's XML reference (https://mujoco.readthedocs.io/en/stable/XMLreference.html) as
MuJoCo 4.0.1 prints its schema (``mujoco.mj_printSchema``); ``tests/formats/test_mjcf_refusals.py``
compares the table with the installed MuJoCo's.

What MuJoCo's schema leaves out and its reader treats itself, checked here as the reader does:

* ``<worldbody>`` holds what a ``<body>`` holds but takes no attribute, no joint and no inertial;
* ``<frame>`` (in a body, the world body or another frame) takes any attribute and holds what its
  body holds; a ``<frame>`` directly in ``<mujoco>`` is read by MuJoCo as nothing;
* ``<replicate>`` holds what its body holds (robokit then refuses it: it does not expand it);
* ``<include file>`` anywhere (robokit has replaced it by the file's children before this check).
"""
from __future__ import annotations

import xml.etree.ElementTree as ET
from dataclasses import dataclass, field
from pathlib import Path
from typing import Iterator

from robokit.errors import InputError

__all__ = ["check_schema", "check_names", "check_references", "element_attributes"]

_TABLE = """
mujoco ! model
  compiler * alignfree angle assetdir autolimits balanceinertia boundinertia boundmass conflict
             coordinate discardvisual eulerseq fitaabb fusestatic inertiafromgeom inertiagrouprange
             meshdir passthrough savecanonical savecompiled saveinertial settotalmass strippath
             texturedir usethread
    lengthrange ? accel interval inttotal maxforce mode timeconst timestep tolrange useexisting
                  uselimit
  option * actuatorgroupdisable ccd_iterations ccd_tolerance cone density gravity impratio
           integrator iterations jacobian ls_iterations ls_tolerance magnetic noslip_iterations
           noslip_tolerance o_friction o_margin o_solimp o_solref sdf_initpoints sdf_iterations
           sleep_tolerance solver timestep tolerance viscosity wind
    flag ? actuation autoreset clampctrl constraint contact damper diagexact energy equality
           eulerdamp filterparent frictionloss fwdinv gravity invdiscrete ipc island limit midphase
           multiccd nativeccd override refsafe sensor sleep speculative spring warmstart
  size * memory nconmax njmax nkey nstack nuser_actuator nuser_body nuser_cam nuser_geom nuser_jnt
         nuser_sensor nuser_site nuser_tendon nuserdata
  statistic * center extent meaninertia meanmass meansize
  visual *
    global ? azimuth bvactive cameraid elevation ellipsoidinertia fovy glow ipd linewidth offheight
             offwidth orthographic realtime
    quality ? numquads numslices numstacks offsamples shadowsize
    headlight ? active ambient diffuse specular
    map ? actuatortendon alpha fogend fogstart force haze shadowclip shadowscale stiffness
          stiffnessrot torque zfar znear
    scale ? actuatorlength actuatorwidth camera com connect constraint contactheight contactwidth
            forcewidth framelength framewidth frustum jointlength jointwidth light selectpoint
            slidercrank
    rgba ? actuator actuatornegative actuatorpositive bv bvactive camera com connect constraint
           contactforce contactfriction contactgap contactpoint contacttorque crankbroken fog force
           frustum haze inertia joint light rangefinder selectpoint slidercrank
  default R class
    mesh ? inertia maxhullvert scale
    texture ? builtin colorspace embed gridlayout gridsize height hflip mark markrgb nchannel random
              rgb1 rgb2 type vflip width
    material ? emission metallic reflectance rgba roughness shininess specular texrepeat texture
               texuniform
      layer * role texture
    joint ? actuatorfrclimited actuatorfrcrange actuatorgravcomp armature axis damping frictionloss
            group limited margin pos range ref solimpfriction solimplimit solreffriction solreflimit
            springdamper springref springyield stiffness type user
    geom ? adhesion axisangle castshadow conaffinity condim contype density euler fitscale fluidcoef
           fluidshape friction fromto gap group hfield margin mass material mesh pos priority quat
           rgba shellinertia size solimp solmix solref surfacevel type user xyaxes zaxis
    site ? axisangle euler fromto group material mesh pos quat rgba size type user xyaxes zaxis
    camera ? axisangle euler focal focalpixel fovy ipd mode output pos principal principalpixel
             projection quat resolution sensorsize user xyaxes zaxis
    light ? active ambient attenuation bulbradius castshadow cutoff diffuse dir directional exponent
            intensity mode pos range softness specular type
    pair ? adhesion condim friction gap margin solimp solref solreffriction
    equality ? active solimp solref
    tendon ? actuatorfrclimited actuatorfrcrange armature damping frictionloss group limited margin
             material range rgba solimpfriction solimplimit solreffriction solreflimit springlength
             springyield stiffness user width
    general ? actdim actearly actlimited actrange armature biasprm biastype cranklength ctrllimited
              ctrlrange damping delay dynprm dyntype ffrange forcelimited forcerange gainprm
              gaintype gear group inheritrange input interp nsample user velrange
    motor ? armature cranklength ctrllimited ctrlrange damping delay forcelimited forcerange gear
            group interp nsample user
    position ? armature cranklength ctrllimited ctrlrange damping dampratio delay forcelimited
               forcerange gear group inheritrange interp kp kv nsample timeconst user
    velocity ? armature cranklength ctrllimited ctrlrange damping delay forcelimited forcerange gear
               group interp kv nsample user
    intvelocity ? actlimited actrange armature cranklength ctrllimited ctrlrange damping dampratio
                  delay forcelimited forcerange gear group inheritrange interp kp kv nsample user
    orientation ? ctrlrange dampratio delay forcelimited forcerange group input interp kp kv nsample
                  user
    pid ? armature cranklength ctrllimited ctrlrange damping dampratio delay ffrange forcelimited
          forcerange gear group imax inheritrange input interp ki kp kv nsample posrange slewmax
          user velrange
    damper ? armature cranklength ctrlrange damping delay forcelimited forcerange gear group interp
             kv nsample user
    cylinder ? area armature bias cranklength ctrllimited ctrlrange damping delay diameter
               forcelimited forcerange gear group interp nsample timeconst user
    muscle ? armature cranklength ctrllimited ctrlrange damping delay force forcelimited forcerange
             fpmax fvmax gear group interp lmax lmin nsample range scale timeconst user vmax
    adhesion ? ctrlrange delay forcelimited forcerange gain group interp nsample user
    dcmotor ? armature cogging controller cranklength ctrllimited ctrlrange damping delay gear group
              inductance input interp lugre motorconst nominal nsample resistance saturation thermal
              user
  extension *
    plugin * plugin
      instance * name
        config * key value
  asset *
    mesh * builtin class content_type face file inertia material maxhullvert name normal params
           refpos refquat scale smoothnormal texcoord vertex
      plugin * instance plugin
        config * key value
    hfield * content_type elevation file name ncol nrow size
    skin * face file group inflate material name rgba texcoord vertex
      bone * bindpos bindquat body vertid vertweight
    texture * builtin class colorspace content_type embed file fileback filedown filefront fileleft
              fileright fileup gridlayout gridsize height hflip mark markrgb name nchannel random
              rgb1 rgb2 type vflip width
    material * class emission metallic name reflectance rgba roughness shininess specular texrepeat
               texture texuniform
      layer * role texture
    model * content_type file name
  (world)body R axisangle childclass euler fuse gravcomp mocap name pos quat simple sleep user
                xyaxes zaxis
    inertial ? axisangle diaginertia euler fullinertia mass pos quat xyaxes zaxis
    joint * actuatorfrclimited actuatorfrcrange actuatorgravcomp armature axis class damping
            frictionloss group limited margin name pos range ref solimpfriction solimplimit
            solreffriction solreflimit springdamper springref springyield stiffness type user
    freejoint * align group name
    geom * adhesion axisangle castshadow class conaffinity condim contype density euler fitscale
           fluidcoef fluidshape friction fromto gap group hfield margin mass material mesh name pos
           priority quat rgba shellinertia size solimp solmix solref surfacevel type user xyaxes
           zaxis
      plugin * instance plugin
        config * key value
    attach * body frame model prefix
    site * axisangle class euler fromto group material mesh name pos quat rgba size type user xyaxes
           zaxis
    camera * axisangle class euler focal focalpixel fovy ipd mode name output pos principal
             principalpixel projection quat resolution sensorsize target user xyaxes zaxis
    light * active ambient attenuation bulbradius castshadow class cutoff diffuse dir directional
            exponent intensity mode name pos range softness specular target texture type
    plugin * instance plugin
      config * key value
    flexcomp * axisangle cellcount count dim dof element euler file flatskin group inertiabox mass
               material mesh name origin point pos quat radius rgba rigid scale spacing texcoord
               type xyaxes zaxis
      edge ? damping equality solimp solref stiffness
      elasticity ? damping elastic2d poisson section sectionsize shear thickness yield young
      contact ? activelayers conaffinity condim contype friction gap margin passive priority
                selfcollide solimp solmix solref
      pin * grid gridrange id range
      plugin * instance plugin
        config * key value
  deformable *
    flex * body cellcount dim dof element elemtexcoord flatskin group material name node nodecoord
           radius rgba texcoord vertex
      contact ? activelayers conaffinity condim contype friction gap margin passive priority
                selfcollide solimp solmix solref
      edge ? damping stiffness
      elasticity ? damping elastic2d poisson section sectionsize shear thickness yield young
    skin * face file group inflate material name rgba texcoord vertex
      bone * bindpos bindquat body vertid vertweight
  contact *
    pair * adhesion class condim friction gap geom1 geom2 margin name solimp solref solreffriction
    exclude * body1 body2 name
  tendon *
    spatial * actuatorfrclimited actuatorfrcrange armature class damping frictionloss group limited
              margin material name range rgba solimpfriction solimplimit solreffriction solreflimit
              springlength springyield stiffness user width
      site * site
      geom * geom sidesite
      pulley * divisor
    fixed * actuatorfrclimited actuatorfrcrange armature class damping frictionloss group limited
            margin name range solimpfriction solimplimit solreffriction solreflimit springlength
            springyield stiffness user
      joint * coef joint
  equality *
    connect * active anchor body1 body2 class name site1 site2 solimp solref
    weld * active anchor body1 body2 class name relpose site1 site2 solimp solref torquescale
    joint * active class joint1 joint2 name polycoef solimp solref
    tendon * active class name polycoef solimp solref tendon1 tendon2
    flex * active class flex name solimp solref
    flexstrain * active cell class flex name solimp solref
  actuator *
    general * actdim actearly actlimited actrange armature biasprm biastype body class cranklength
              cranksite ctrllimited ctrlrange damping delay dynprm dyntype ffrange forcelimited
              forcerange gainprm gaintype gear group inheritrange input interp joint jointinparent
              lengthrange name nsample refsite site slidersite tendon user velrange
    motor * armature class cranklength cranksite ctrllimited ctrlrange damping delay forcelimited
            forcerange gear group interp joint jointinparent lengthrange name nsample refsite site
            slidersite tendon user
    position * armature class cranklength cranksite ctrllimited ctrlrange damping dampratio delay
               forcelimited forcerange gear group inheritrange interp joint jointinparent kp kv
               lengthrange name nsample refsite site slidersite tendon timeconst user
    velocity * armature class cranklength cranksite ctrllimited ctrlrange damping delay forcelimited
               forcerange gear group interp joint jointinparent kv lengthrange name nsample refsite
               site slidersite tendon user
    intvelocity * actlimited actrange armature class cranklength cranksite ctrllimited ctrlrange
                  damping dampratio delay forcelimited forcerange gear group inheritrange interp
                  joint jointinparent kp kv lengthrange name nsample refsite site slidersite tendon
                  user
    orientation * class ctrlrange dampratio delay forcelimited forcerange group input interp joint
                  kp kv name nsample refsite site user
    pid * armature class cranklength cranksite ctrllimited ctrlrange damping dampratio delay ffrange
          forcelimited forcerange gear group imax inheritrange input interp joint jointinparent ki
          kp kv lengthrange name nsample posrange refsite site slewmax slidersite tendon user
          velrange
    damper * armature class cranklength cranksite ctrlrange damping delay forcelimited forcerange
             gear group interp joint jointinparent kv lengthrange name nsample refsite site
             slidersite tendon user
    cylinder * area armature bias class cranklength cranksite ctrllimited ctrlrange damping delay
               diameter forcelimited forcerange gear group interp joint jointinparent lengthrange
               name nsample refsite site slidersite tendon timeconst user
    muscle * armature class cranklength cranksite ctrllimited ctrlrange damping delay force
             forcelimited forcerange fpmax fvmax gear group interp joint jointinparent lengthrange
             lmax lmin name nsample range scale slidersite tausmooth tendon timeconst user vmax
    adhesion * body class ctrlrange delay forcelimited forcerange gain group interp name nsample
               user
    dcmotor * armature class cogging controller cranklength cranksite ctrllimited ctrlrange damping
              delay gear group inductance input interp joint jointinparent lengthrange lugre
              motorconst name nominal nsample refsite resistance saturation site slidersite tendon
              thermal user
    plugin * actdim actearly actlimited actrange armature class cranklength cranksite ctrllimited
             ctrlrange damping delay dynprm dyntype forcelimited forcerange gear group instance
             interp joint jointinparent lengthrange name nsample plugin site slidersite tendon user
      config * key value
  sensor *
    touch * cutoff delay interp interval name noise nsample site user
    accelerometer * cutoff delay interp interval name noise nsample site user
    velocimeter * cutoff delay interp interval name noise nsample site user
    gyro * cutoff delay interp interval name noise nsample site user
    force * cutoff delay interp interval name noise nsample site user
    torque * cutoff delay interp interval name noise nsample site user
    magnetometer * cutoff delay interp interval name noise nsample site user
    camprojection * camera cutoff delay interp interval name noise nsample site user
    rangefinder * camera cutoff data delay interp interval name noise nsample site user
    jointpos * cutoff delay interp interval joint name noise nsample user
    jointvel * cutoff delay interp interval joint name noise nsample user
    tendonpos * cutoff delay interp interval name noise nsample tendon user
    tendonvel * cutoff delay interp interval name noise nsample tendon user
    actuatorpos * actuator cutoff delay interp interval name noise nsample user
    actuatorvel * actuator cutoff delay interp interval name noise nsample user
    actuatorfrc * actuator cutoff delay interp interval name noise nsample user
    jointactuatorfrc * cutoff delay interp interval joint name noise nsample user
    tendonactuatorfrc * cutoff delay interp interval name noise nsample tendon user
    ballquat * cutoff delay interp interval joint name noise nsample user
    ballangvel * cutoff delay interp interval joint name noise nsample user
    jointlimitpos * cutoff delay interp interval joint name noise nsample user
    jointlimitvel * cutoff delay interp interval joint name noise nsample user
    jointlimitfrc * cutoff delay interp interval joint name noise nsample user
    tendonlimitpos * cutoff delay interp interval name noise nsample tendon user
    tendonlimitvel * cutoff delay interp interval name noise nsample tendon user
    tendonlimitfrc * cutoff delay interp interval name noise nsample tendon user
    framepos * cutoff delay interp interval name noise nsample objname objtype refname reftype user
    framequat * cutoff delay interp interval name noise nsample objname objtype refname reftype user
    framexaxis * cutoff delay interp interval name noise nsample objname objtype refname reftype
                 user
    frameyaxis * cutoff delay interp interval name noise nsample objname objtype refname reftype
                 user
    framezaxis * cutoff delay interp interval name noise nsample objname objtype refname reftype
                 user
    framelinvel * cutoff delay interp interval name noise nsample objname objtype refname reftype
                  user
    frameangvel * cutoff delay interp interval name noise nsample objname objtype refname reftype
                  user
    framelinacc * cutoff delay interp interval name noise nsample objname objtype user
    frameangacc * cutoff delay interp interval name noise nsample objname objtype user
    subtreecom * body cutoff delay interp interval name noise nsample user
    subtreelinvel * body cutoff delay interp interval name noise nsample user
    subtreeangmom * body cutoff delay interp interval name noise nsample user
    insidesite * cutoff delay enclosed interp interval name noise nsample objname objtype site user
    distance * body1 body2 cutoff delay geom1 geom2 interp interval name noise nsample user
    normal * body1 body2 cutoff delay geom1 geom2 interp interval name noise nsample user
    fromto * body1 body2 cutoff delay geom1 geom2 interp interval name noise nsample user
    contact * body1 body2 cutoff data delay geom1 geom2 interp interval name noise nsample num
              reduce site subtree1 subtree2 user
    e_potential * cutoff delay interp interval name noise nsample user
    e_kinetic * cutoff delay interp interval name noise nsample user
    clock * cutoff delay interp interval name noise nsample user
    tactile * cutoff delay geom interp interval mesh name nsample user
    user * cutoff datatype dim name needstage noise objname objtype user
    plugin * cutoff instance name objname objtype plugin refname reftype user
      config * key value
  custom *
    numeric * data name size
    text * data name
    tuple * name
      element * objname objtype prm
  keyframe *
    key * act ctrl mpos mquat name plastic qpos qvel time
"""


@dataclass
class _Node:
    tag: str
    mult: str
    attrs: frozenset[str]
    children: dict[str, "_Node"] = field(default_factory=dict)


def _parse(table: str) -> _Node:
    root = _Node("", "*", frozenset())
    stack: list[tuple[int, _Node]] = [(-1, root)]
    rows: list[tuple[int, str, str, list[str]]] = []
    for line in table.splitlines():
        if not line.strip():
            continue
        depth = (len(line) - len(line.lstrip(" "))) // 2
        words = line.split()
        if len(words) >= 2 and words[1] in ("!", "?", "*", "R"):
            rows.append((depth, words[0], words[1], words[2:]))
        else:  # a continuation line: more attributes of the row above
            rows[-1][3].extend(words)
    for depth, tag, mult, attrs in rows:
        while stack[-1][0] >= depth:
            stack.pop()
        node = _Node(tag, mult, frozenset(attrs))
        stack[-1][1].children[tag] = node
        stack.append((depth, node))
    return root.children["mujoco"]


_ROOT = _parse(_TABLE)
_BODY = _ROOT.children["(world)body"]
#: elements the reader, not the schema, handles (module docstring)
_TRANSPARENT = ("frame", "replicate")


def element_attributes(*path: str) -> frozenset[str]:
    """The attributes MuJoCo reads on the element at ``path`` below ``<mujoco>``.

    Parameters
    ----------
    *path : str
        Element tags from a child of ``<mujoco>`` down (``"worldbody"`` and ``"body"`` are the
        same entry; a body nests bodies to any depth).

    Returns
    -------
    frozenset of str

    Examples
    --------
    >>> sorted(element_attributes("worldbody", "body", "inertial"))
    ['axisangle', 'diaginertia', 'euler', 'fullinertia', 'mass', 'pos', 'quat', 'xyaxes', 'zaxis']
    >>> "name" in element_attributes("default", "joint")
    False
    """
    node = _ROOT
    for tag in path:  # (a tag MuJoCo does not know gives no attribute)
        node = _child(node, tag) or _Node(tag, "*", frozenset())
    return node.attrs


def _child(node: _Node, tag: str) -> _Node | None:
    if (node is _ROOT and tag == "worldbody") or (node is _BODY and tag == "body"):
        return _BODY
    if tag == "default" and node.tag == "default":
        return node
    return node.children.get(tag)


def _label(elem: ET.Element) -> str:
    name = elem.get("name")
    return f"<{elem.tag} name={name!r}>" if name else f"<{elem.tag}>"


def check_schema(root: ET.Element, path: str | Path) -> None:
    """Refuse what MuJoCo's schema refuses: an element or attribute it does not know, an element
    repeated where one is allowed, and what its reader refuses in ``<worldbody>`` (module docstring).

    Parameters
    ----------
    root : xml.etree.ElementTree.Element
        The ``<mujoco>`` element, includes expanded.
    path : str or Path
        The file, for the message.

    Raises
    ------
    InputError
        One line naming the file, the element and where it sits.

    Examples
    --------
    >>> check_schema(ET.fromstring('<mujoco><worldbody><body name="b"><joint name="j" spring="1"/>'
    ...                            '</body></worldbody></mujoco>'), "arm.xml")
    Traceback (most recent call last):
    ...
    robokit.errors.InputError: arm.xml: <joint name='j'> in <body name='b'>: MuJoCo has no attribute 'spring' on <joint> and refuses the file (unrecognized attribute)
    """
    def where(elem: ET.Element, owner: str) -> str:
        return f"{path}: {_label(elem)}" + (f" in {owner}" if owner else "")

    def attributes(elem: ET.Element, node: _Node, owner: str) -> None:
        for key in elem.attrib:
            if key not in node.attrs:
                raise InputError(f"{where(elem, owner)}: MuJoCo has no attribute {key!r} on <{elem.tag}> and refuses "
                                 "the file (unrecognized attribute)")

    def walk(elem: ET.Element, node: _Node, owner: str, world: bool) -> None:
        counts: dict[str, int] = {}
        for child in elem:
            if not isinstance(child.tag, str):
                continue  # a comment or processing instruction
            tag = child.tag
            if node is _BODY and tag in _TRANSPARENT or tag == "include":
                if tag == "include" and set(child.attrib) - {"file"}:
                    attributes(child, _Node("include", "*", frozenset({"file"})), owner)
                walk(child, node, owner, world)  # its children count as the body's (MuJoCo's reader)
                continue
            if node is _ROOT and tag == "frame":
                continue  # MuJoCo reads a top-level <frame> as nothing
            sub = _child(node, tag)
            if sub is None:
                raise InputError(f"{where(child, _label(elem) if not owner else owner)}: MuJoCo knows no element "
                                 f"<{tag}> inside <{elem.tag}> and refuses the file (unrecognized element)")
            if world and tag in ("joint", "freejoint", "inertial"):
                raise InputError(f"{where(child, '<worldbody>')}: the world body cannot have "
                                 f"{'inertia' if tag == 'inertial' else 'joints'} (MuJoCo refuses the file)")
            counts[tag] = counts.get(tag, 0) + 1
            if sub.mult in ("?", "!") and counts[tag] > 1:
                raise InputError(f"{path}: {_label(elem)}{f' in {owner}' if owner and owner != _label(elem) else ''}: "
                                 f"more than one <{tag}>; MuJoCo allows one and refuses the file")
            if tag == "worldbody":
                if child.attrib:
                    raise InputError(f"{path}: <worldbody> has attributes ({', '.join(child.attrib)}); the world "
                                     "body cannot have attributes (MuJoCo refuses the file)")
                walk(child, sub, "<worldbody>", True)
                continue
            attributes(child, sub, owner)
            inner = _label(child) if tag == "body" else owner
            walk(child, sub, inner, world and tag != "body")

    if root.tag != "mujoco":
        return
    attributes(root, _ROOT, "")
    walk(root, _ROOT, "", False)


#: the name space of an element by its parent: elements of one kind share names (MuJoCo's object types)
_SECTION_KIND = {"actuator": "actuator", "sensor": "sensor", "tendon": "tendon", "equality": "equality"}
_KIND = {"freejoint": "joint", "worldbody": "body"}
#: assets MuJoCo names after their file when the file gives no name
_FILE_NAMED = ("mesh", "skin", "hfield", "texture")


def _kind(tag: str, section: str | None) -> str:
    return _SECTION_KIND.get(section or "", _KIND.get(tag, tag))


def _walk(root: ET.Element) -> Iterator[tuple[ET.Element, ET.Element, str | None]]:
    """(element, its parent, the top-level section it sits in) outside ``<default>``."""
    def walk(elem: ET.Element, section: str | None) -> Iterator[tuple[ET.Element, ET.Element, str | None]]:
        for child in elem:
            if not isinstance(child.tag, str) or child.tag == "default":
                continue
            yield child, elem, section
            yield from walk(child, child.tag if elem is root else section)

    return walk(root, None)


def check_names(root: ET.Element, path: str | Path) -> dict[str, set[str]]:
    """Refuse two objects of one kind with one name (two geoms named ``g``, a body named ``world``),
    as MuJoCo does ("repeated name"); bodies, joints, geoms, sites and the other kinds each have their
    own names, so a body and its joint may share one.

    Parameters
    ----------
    root : xml.etree.ElementTree.Element
        The ``<mujoco>`` element, includes expanded.
    path : str or Path
        The file, for the message.

    Returns
    -------
    dict of str to set of str
        The names of each kind (``"body"``, ``"joint"``, ``"geom"``, ``"site"``, ``"mesh"``, ...).

    Raises
    ------
    InputError
        Naming the file, the kind and the name.

    Examples
    --------
    >>> check_names(ET.fromstring('<mujoco><worldbody><body name="a"><geom name="g"/><geom name="g"/>'
    ...                           '</body></worldbody></mujoco>'), "arm.xml")
    Traceback (most recent call last):
    ...
    robokit.errors.InputError: arm.xml: two <geom> elements named 'g'; MuJoCo refuses repeated names within a kind
    """
    seen: dict[str, set[str]] = {"body": {"world"}}
    for elem, parent, section in _walk(root):
        if parent is root:
            continue
        kind = _kind(elem.tag, section)
        name = elem.get("name")
        if not name and section == "asset" and elem.tag in _FILE_NAMED and elem.get("file"):
            name = Path(elem.get("file", "")).stem
        if name:
            names = seen.setdefault(kind, set())
            if name in names:
                what = f"<{elem.tag}>" if kind == elem.tag else f"{kind} (<{elem.tag}>)"
                raise InputError(f"{path}: two {what} elements named {name!r}; MuJoCo refuses repeated names "
                                 "within a kind")
            names.add(name)
    return seen


#: attributes that name another object, and its kind, by section (``None``: the body tree and assets)
_REFS: dict[str | None, dict[str, str]] = {
    None: {"target": "body", "texture": "texture"},
    "actuator": {"joint": "joint", "jointinparent": "joint", "site": "site", "refsite": "site", "cranksite": "site",
                 "slidersite": "site", "tendon": "tendon", "body": "body"},
    "sensor": {"site": "site", "joint": "joint", "body": "body", "body1": "body", "body2": "body", "geom": "geom",
               "geom1": "geom", "geom2": "geom", "tendon": "tendon", "actuator": "actuator", "camera": "camera"},
    "equality": {"body1": "body", "body2": "body", "site1": "site", "site2": "site", "joint1": "joint",
                 "joint2": "joint", "tendon1": "tendon", "tendon2": "tendon"},
    "tendon": {"joint": "joint", "site": "site", "sidesite": "site", "geom": "geom", "material": "material"},
    "contact": {"geom1": "geom", "geom2": "geom", "body1": "body", "body2": "body"},
}
#: sensor ``objtype`` keywords naming a kind robokit knows the names of
_OBJTYPES = {"body": "body", "xbody": "body", "geom": "geom", "site": "site", "camera": "camera"}


def check_references(root: ET.Element, path: str | Path, names: dict[str, set[str]]) -> None:
    """Refuse a reference to an object the file does not define (an actuator on joint ``j9``, a
    sensor on a missing site, a material naming no texture), as MuJoCo does. Geom and site
    materials and meshes, which default classes may give, are checked where they are compiled.

    Parameters
    ----------
    root : xml.etree.ElementTree.Element
        The ``<mujoco>`` element, includes expanded.
    path : str or Path
        The file, for the message.
    names : dict of str to set of str
        :func:`check_names`'s result.

    Raises
    ------
    InputError
        Naming the file, the element, the attribute and the missing name.
    """
    for elem, parent, section in _walk(root):
        refs = dict(_REFS.get(section, {}))
        if section in ("worldbody", "asset") and elem.tag in ("camera", "light", "material", "layer"):
            refs = _REFS[None]
        if section == "sensor" and elem.get("objtype") in _OBJTYPES:
            refs["objname"] = _OBJTYPES[elem.get("objtype", "")]
        if section == "sensor" and elem.get("reftype") in _OBJTYPES:
            refs["refname"] = _OBJTYPES[elem.get("reftype", "")]
        for key, kind in refs.items():
            value = elem.get(key)
            if value and value not in names.get(kind, set()):
                where = f"<{parent.tag}><{elem.tag}>" if section in ("tendon",) and parent.tag != "tendon" else ""
                raise InputError(f"{path}: {where or _label(elem)} {key}={value!r}: no {kind} named {value!r} "
                                 "(MuJoCo refuses the file)")
