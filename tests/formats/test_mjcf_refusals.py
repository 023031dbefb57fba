"""MJCF that MuJoCo refuses is refused by robokit, with one line naming the file and the element;
MJCF that MuJoCo reads is read.

A file MuJoCo's compiler refuses has no meaning: robokit reading it would give numbers no engine
agrees with. Each case below is a small file; the test asserts MuJoCo's verdict first (so a case
that a new MuJoCo accepts shows up here) and then robokit's. The schema table robokit checks names
against (``robokit/description/_mjcf_schema.py``) is compared with the installed MuJoCo's own.
"""
import re
import warnings

import pytest

import robokit
from robokit.description import _mjcf_schema
from robokit.description.mjcf_compile import compile_mjcf
from robokit.errors import InputError

mujoco = pytest.importorskip("mujoco", reason="MuJoCo is the reference (pip install mujoco)")


def _body(inner, head="", tail=""):
    """A one-body robot (a hinge ``h`` and a sphere) with ``inner`` in its body."""
    return (f'<mujoco>{head}<worldbody><body name="b"><joint name="h" axis="0 0 1"/><geom size="0.1"/>{inner}'
            f'</body></worldbody>{tail}</mujoco>')


def _arm(inner):
    """A one-body robot whose body holds only ``inner`` (its joints, its inertial)."""
    return f'<mujoco><worldbody><body name="b">{inner}<geom size="0.1"/></body></worldbody></mujoco>'


HINGES = "".join(f'<joint name="j{i}" axis="0 0 1"/>' for i in range(7))
INERTIAL = '<inertial pos="0 0 0" mass="{m}" diaginertia="{d}"/>'

#: id → (file, text robokit's message names): each refused by MuJoCo and by robokit
REFUSED = {
    # joints of one body
    "seven dofs in one body": (_arm(HINGES), "<body name='b'>: more than 6 degrees of freedom"),
    "ball then four slides": (_arm('<joint name="s" type="ball"/>' + '<joint type="slide"/>' * 4),
                              "more than 6 degrees of freedom"),
    "free joint and hinge": (_arm('<freejoint name="f"/><joint name="h"/>'), "more than 6 degrees of freedom"),
    "hinge after ball": (_arm('<joint name="s" type="ball"/><joint name="h"/>'), "hinge joint 'h' follows ball joint 's'"),
    "ball after ball": (_arm('<joint name="s" type="ball"/><joint name="t" type="ball"/>'),
                        "ball joint 't' follows ball joint 's'"),
    # the schema: attributes and elements MuJoCo does not know
    "unknown attribute on a joint": (_body('<joint name="k" spring="1"/>'), "<joint name='k'> in <body name='b'>"),
    "unknown attribute on a body": ('<mujoco><worldbody><body name="b" colour="red"><joint/><geom size="0.1"/>'
                                    '</body></worldbody></mujoco>', "<body name='b'> in <worldbody>: MuJoCo has no attribute 'colour'"),
    "unknown attribute on a geom": (_body('<geom name="g" size="0.1" colour="red"/>'), "<geom name='g'> in <body name='b'>"),
    "unknown attribute on an inertial": (_arm('<joint/><inertial pos="0 0 0" mass="1" diaginertia="1 1 1" com="0"/>'),
                                         "<inertial> in <body name='b'>"),
    "unknown attribute on a site": (_body('<site name="s" colour="red"/>'), "<site name='s'>"),
    "unknown attribute on the compiler": (_body("", head='<compiler angles="radian"/>'), "<compiler>: MuJoCo has no "
                                          "attribute 'angles'"),
    "unknown attribute on option": (_body("", head='<option gravty="0 0 -1"/>'), "<option>: MuJoCo has no attribute"),
    "unknown attribute on a flag": (_body("", head='<option><flag gravty="disable"/></option>'), "<flag>"),
    "unknown attribute on size": (_body("", head='<size njnt="3"/>'), "<size>"),
    "unknown attribute on the root": (_body("").replace("<mujoco>", '<mujoco version="3">'), "<mujoco>"),
    "unknown attribute on a default joint": (_body("", head='<default><joint spring="1"/></default>'), "<joint>"),
    "a name on a default joint": (_body("", head='<default><joint name="x"/></default>'), "<joint name='x'>"),
    "unknown attribute on an actuator": (_body("", tail='<actuator><motor joint="h" torque="1"/></actuator>'),
                                         "<motor>: MuJoCo has no attribute 'torque'"),
    "unknown attribute on a mesh asset": (_body("", head='<asset><mesh name="m" vertex="0 0 0 1 0 0 0 1 0 0 0 1" '
                                                'unit="mm"/></asset>'), "<mesh name='m'>"),
    "a namespaced attribute": (_body('<geom xmlns:x="urn:x" x:extra="1" size="0.1"/>'), "'{urn:x}extra'"),
    "unknown element in a body": (_body("<spring/>"), "<spring> in <body name='b'>"),
    "unknown element at the top": (_body("", head="<physics/>"), "<physics> in <mujoco>"),
    "unknown element in a joint": (_body('<joint name="k"><limit/></joint>'), "<limit> in <body name='b'>: MuJoCo "
                                   "knows no element <limit> inside <joint>"),
    "unknown element in a frame": (_body("<frame><spring/></frame>"), "<spring> in <body name='b'>"),
    "a body in a default": (_body("", head="<default><body/></default>"), "<body> in <default>"),
    "a composite (gone from MuJoCo)": (_body("<composite/>"), "<composite>"),
    "two inertials in a body": (_arm('<joint/>' + INERTIAL.format(m=1, d="1 1 1") * 2),
                                "<body name='b'>: more than one <inertial>"),
    "two flags in option": (_body("", head='<option><flag gravity="disable"/><flag energy="enable"/></option>'),
                            "more than one <flag>"),
    "two joints in one default": (_body("", head='<default><joint damping="1"/><joint armature="1"/></default>'),
                                  "more than one <joint>"),
    "attributes on the worldbody": ('<mujoco><worldbody name="w"><body name="b"><joint/><geom size="0.1"/></body>'
                                    '</worldbody></mujoco>', "<worldbody> has attributes (name)"),
    "a joint in the worldbody": ('<mujoco><worldbody><joint name="w"/><body name="b"><joint/><geom size="0.1"/>'
                                 '</body></worldbody></mujoco>', "<joint name='w'> in <worldbody>"),
    "a joint in a frame of the worldbody": ('<mujoco><worldbody><frame><joint name="w"/></frame><body name="b">'
                                            '<joint/><geom size="0.1"/></body></worldbody></mujoco>',
                                            "<joint name='w'> in <worldbody>"),
    "an inertial in the worldbody": ('<mujoco><worldbody><inertial pos="0 0 0" mass="1" diaginertia="1 1 1"/>'
                                     '<body name="b"><joint/><geom size="0.1"/></body></worldbody></mujoco>',
                                     "<inertial> in <worldbody>"),
    # keywords
    "an option keyword": (_body("", head='<option integrator="euler"/>'), "<option integrator='euler'>"),
    "a flag keyword": (_body("", head='<option><flag gravity="off"/></option>'), "<flag gravity='off'>"),
    "a site type": (_body('<site name="s" type="cube"/>'), "<site name='s'> type='cube'"),
    "a plane site": (_body('<site name="s" type="plane"/>'), "<site name='s'> type='plane'"),
    "a geom condim": (_body('<geom name="g" size="0.1" condim="2"/>'), "<geom name='g'> condim=2"),
    "an eulerseq letter, where an euler is read": (
        '<mujoco><compiler eulerseq="xyw"/><worldbody><body name="b" euler="10 20 30"><joint/><geom size="0.1"/>'
        '</body></worldbody></mujoco>', "<body name='b'>: euler: euler sequence can only contain"),
    "an eulerseq of two letters": (_body("", head='<compiler eulerseq="xy"/>'), "exactly 3 characters"),
    # counts of numbers
    "a site with four sizes": (_body('<site name="s" size="1 1 1 1"/>'), "<site name='s'> attribute size"),
    # sizes
    "a sphere of radius 0": (_body('<geom name="g" size="0"/>'), "<geom name='g'>: a sphere needs size[0] > 0"),
    "a capsule without half-length": (_body('<geom name="g" type="capsule" size="0.1"/>'), "size[1] > 0"),
    "a box of two sizes": (_body('<geom name="g" type="box" size="0.1 0.1"/>'), "a box needs size[2] > 0"),
    "a geom without size": (_body('<geom name="g"/>'), "<geom name='g'>: a sphere needs size[0] > 0"),
    "a site of size 0": (_body('<site name="s" size="0"/>'), "<site name='s'>: a sphere needs size[0] > 0"),
    "a site box with a zero side": (_body('<site name="s" type="box" size="0.1 0 0.1"/>'), "a box needs size[1] > 0"),
    "a site fromto on a sphere": (_body('<site name="s" fromto="0 0 0 1 0 0"/>'), "fromto requires capsule"),
    "a site fromto and pos": (_body('<site name="s" type="capsule" pos="1 0 0" fromto="0 0 0 1 0 0"/>'),
                              "both pos and fromto"),
    "a site fromto of one point": (_body('<site name="s" type="capsule" fromto="0 0 0 0 0 0"/>'), "too close"),
    # what moves and what does not
    "a plane on a moving body": (_body('<geom name="p" type="plane" size="1 1 1"/>'),
                                 "<geom name='p'> in <body name='b'>: a plane only on a body that does not move"),
    "a plane below a moving body": (_body('<body name="c"><geom name="p" type="plane" size="1 1 1"/></body>'),
                                    "<geom name='p'> in <body name='c'>"),
    "a mocap body below another": (_body('<body name="c" mocap="true"><geom size="0.1"/></body>'),
                                   "<body name='c'>: a mocap body must be a child of <worldbody>"),
    "a mocap body with a joint": ('<mujoco><worldbody><body name="m" mocap="true"><joint/><geom size="0.1"/></body>'
                                  '</worldbody></mujoco>', "<body name='m'>: a mocap body"),
    # mass and inertia of moving bodies
    "a massless moving body": ('<mujoco><worldbody><body name="b"><joint/></body></worldbody></mujoco>',
                               "<body name='b'>: a body with a joint needs mass and inertia"),
    "a moving body of mass 0": (_arm('<joint/>' + INERTIAL.format(m=0, d="1 1 1")), "<body name='b'>: a body with a "
                                "joint needs mass"),
    "a moving body of negative mass": (_arm('<joint/>' + INERTIAL.format(m=-1, d="1 1 1")), "<body name='b'>"),
    "a moving body with a zero moment": (_arm('<joint/>' + INERTIAL.format(m=1, d="1 1 0")), "<body name='b'>"),
    "a moving body of mass 1e-16": (_arm('<joint/>' + INERTIAL.format(m=1e-16, d="1 1 1")), "<body name='b'>"),
    "a massless body above a moving child": (
        '<mujoco><worldbody><body name="b"><joint/><body name="c"><joint/><geom size="0.1"/></body></body>'
        '</worldbody></mujoco>', "<body name='b'>: a body with a joint needs mass"),
    "a massless geom only": ('<mujoco><worldbody><body name="b"><joint/><geom size="0.1" mass="0"/></body>'
                             '</worldbody></mujoco>', "<body name='b'>"),
    # repeated names
    "two bodies of one name": ('<mujoco><worldbody><body name="b"><joint/><geom size="0.1"/></body><body name="b">'
                               '<geom size="0.1"/></body></worldbody></mujoco>', "two <body> elements named 'b'"),
    "a body named world": (_body('<body name="world"><geom size="0.1"/></body>'), "two <body> elements named 'world'"),
    "two geoms of one name": (_body('<geom name="g" size="0.1"/><geom name="g" size="0.1"/>'),
                              "two <geom> elements named 'g'"),
    "two sites of one name": (_body('<site name="s"/><site name="s"/>'), "two <site> elements named 's'"),
    "a joint and a free joint of one name": (
        '<mujoco><worldbody><body name="a"><freejoint name="j"/><geom size="0.1"/><body name="c"><joint name="j"/>'
        '<geom size="0.1"/></body></body></worldbody></mujoco>', "two <joint> elements named 'j'"),
    "two actuators of one name": (_body("", tail='<actuator><motor name="a" joint="h"/><position name="a" joint="h"/>'
                                        '</actuator>'), "two actuator (<position>) elements named 'a'"),
    "two frames of one name": (_body('<frame name="f"/><frame name="f"/>'), "two <frame> elements named 'f'"),
    "two materials of one name": (_body("", head='<asset><material name="m"/><material name="m"/></asset>'),
                                  "two <material> elements named 'm'"),
    # references to objects the file does not define
    "an actuator on a missing joint": (_body("", tail='<actuator><motor name="a" joint="j9"/></actuator>'),
                                       "<motor name='a'> joint='j9': no joint named 'j9'"),
    "an actuator on a body's name": (_body("", tail='<actuator><motor joint="b"/></actuator>'), "no joint named 'b'"),
    "a sensor on a missing site": (_body("", tail='<sensor><touch name="t" site="s9"/></sensor>'), "no site named 's9'"),
    "a frame sensor on a missing body": (_body("", tail='<sensor><framepos objtype="body" objname="c"/></sensor>'),
                                         "no body named 'c'"),
    "an equality on a missing body": (_body("", tail='<equality><weld body1="b" body2="c"/></equality>'),
                                      "body2='c': no body named 'c'"),
    "a pair of a missing geom": (_body('<geom name="g" size="0.1"/>', tail='<contact><pair geom1="g" geom2="x"/>'
                                       '</contact>'), "geom2='x'"),
    "a tendon through a missing site": (_body('<site name="s"/>', tail='<tendon><spatial name="t"><site site="s"/>'
                                              '<site site="s9"/></spatial></tendon>'), "<spatial><site> site='s9'"),
    "a geom of a missing material": (_body('<geom name="g" size="0.1" material="steel"/>'),
                                     "<geom name='g'> material='steel': no material named 'steel'"),
    "a default's missing material": (_body('<geom name="g" size="0.1"/>', head='<default><geom material="steel"/>'
                                           '</default>'), "<geom name='b/geom0'> material='steel'"),
    "a material of a missing texture": (_body("", head='<asset><material name="m" texture="wood"/></asset>'),
                                        "<material name='m'> texture='wood'"),
    # files of assets no geom uses (Menagerie's Sawyer without pedestal.obj: MuJoCo refused it, robokit loaded it)
    "an unused mesh whose file is missing": (_body("", head='<asset><mesh name="pedestal" file="pedestal.obj"/></asset>'),
                                             "<mesh name='pedestal'> file='pedestal.obj'"),
    "an unused texture whose file is missing": (_body("", head='<asset><texture name="t" type="2d" file="wood.png"/>'
                                                      '</asset>'), "<texture name='t'> file='wood.png'"),
    "a cube texture's side whose file is missing": (_body("", head='<asset><texture name="c" type="cube" '
                                                          'fileright="r.png"/></asset>'), "fileright='r.png'"),
    "an unused height field whose file is missing": (_body("", head='<asset><hfield name="h" file="h.png" '
                                                           'size="1 1 1 1"/></asset>'), "<hfield name='h'> file='h.png'"),
    "a skin whose file is missing": (_body("", tail='<deformable><skin name="s" file="s.skn"/></deformable>'),
                                     "<skin name='s'> file='s.skn'"),
    "a light on a missing body": (_body('<light name="l" target="c"/>'), "<light name='l'> target='c'"),
    # keyframes
    "a key of two positions for one joint": (_body("", tail='<keyframe><key name="k" qpos="1 2"/></keyframe>'),
                                             "<key name='k'> qpos: 2 numbers, the model has 1"),
    "a key of a control without actuators": (_body("", tail='<keyframe><key name="k" ctrl="1"/></keyframe>'),
                                             "<key name='k'> ctrl: 1 numbers, the model has 0"),
}


@pytest.mark.parametrize("case", list(REFUSED), ids=list(REFUSED))
def test_what_mujoco_refuses_robokit_refuses(case, tmp_path):
    xml, named = REFUSED[case]
    with pytest.raises(ValueError):
        mujoco.MjModel.from_xml_string(xml)
    path = tmp_path / "arm.xml"
    path.write_text(xml)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        with pytest.raises(InputError) as err:
            robokit.load(path)
    message = str(err.value)
    assert "\n" not in message
    assert message.startswith(f"{path}:"), message
    assert named in message, message


#: id → file: each read by MuJoCo and compiled by robokit (several were refused by robokit, or
#: nearly so, before: they mark where MuJoCo's rules stop)
ACCEPTED = {
    "a key of fewer positions, velocities and controls than the model (MuJoCo fills them up; Menagerie's xArm 6)":
        _body('<body name="c" pos="0 0 0.3"><joint name="h2" axis="0 1 0"/><geom size="0.1"/></body>',
              tail='<actuator><motor joint="h"/><motor joint="h2"/></actuator>'
                   '<keyframe><key name="k" qpos="0.5" qvel="1" ctrl="1"/></keyframe>'),
    "six dofs in one body": _arm("".join(f'<joint name="j{i}" axis="0 0 1"/>' for i in range(6))),
    "a ball after a hinge": _arm('<joint name="h"/><joint name="s" type="ball"/>'),
    "slides after a ball": _arm('<joint name="s" type="ball"/>' + '<joint type="slide"/>' * 3),
    "any attribute on a frame": _body('<frame label="x" pos="0 0 0.1"><site name="s"/></frame>'),
    "an inertial in a frame beside the body's": _arm('<joint/>' + INERTIAL.format(m=1, d="1 1 1") +
                                                     '<frame>' + INERTIAL.format(m=2, d="1 1 1") + '</frame>'),
    "a frame at the top level": _body("", head='<frame><body name="ghost"/></frame>'),
    "an unused eulerseq letter": _body("", head='<compiler eulerseq="xyw"/>'),
    "a massless moving body with a massive welded child": _arm(
        '<joint/>' + INERTIAL.format(m=0, d="0 0 0") + '<body name="c">' + INERTIAL.format(m=1, d="1 1 1") +
        '</body>'),
    "a massless moving body with a massive body welded deeper": _arm(
        '<joint/><body name="c"><body name="d">' + INERTIAL.format(m=1, d="1 1 1") + '</body></body>'),
    "a plane on a body that does not move": '<mujoco><worldbody><body name="floor"><geom type="plane" size="1 1 1"/>'
                                            '</body><body name="b"><joint/><geom size="0.1"/></body></worldbody>'
                                            '</mujoco>',
    "a body and its joint of one name": _arm('<joint name="b"/>'),
    "a site named like its body": _body('<site name="b"/>'),
    "a texture and a material of one name": _body("", head='<asset><texture name="m" builtin="checker" width="8" '
                                                  'height="8" type="2d"/><material name="m" texture="m"/></asset>'),
    "a pair and an exclude of one name": _body('<geom name="g" size="0.1"/>', tail='<contact><exclude name="p" '
                                               'body1="world" body2="b"/></contact>'),
    "a site capsule of one size": _body('<site name="s" type="capsule" size="0.1"/>'),
    "a key of the right sizes": _body("", tail='<actuator><motor joint="h"/></actuator><keyframe><key qpos="0.1" '
                                      'qvel="0" ctrl="1"/></keyframe>'),
    "an unused default material": _body("", head='<default><default class="steel"><geom material="steel"/></default>'
                                        '</default>'),
    "the option keywords": _body("", head='<option integrator="implicitfast" cone="elliptic" jacobian="sparse" '
                                 'solver="CG"><flag gravity="enable" contact="disable"/></option>'),
    "two compilers and two worldbodies": '<mujoco><compiler angle="radian"/><compiler autolimits="true"/><worldbody>'
                                         '<body name="b"><joint/><geom size="0.1"/></body></worldbody><worldbody/>'
                                         '</mujoco>',
}


@pytest.mark.parametrize("case", list(ACCEPTED), ids=list(ACCEPTED))
def test_what_mujoco_reads_robokit_compiles(case, tmp_path):
    xml = ACCEPTED[case]
    mujoco.MjModel.from_xml_string(xml)
    path = tmp_path / "arm.xml"
    path.write_text(xml)
    compile_mjcf(path)


def _mujoco_schema():
    """(path of tags, multiplicity) → attributes, from the installed MuJoCo's printed schema."""
    out, stack = {}, []
    for line in mujoco.mj_printSchema(False, True).splitlines():
        m = re.match(r"^( *)(\S+) \((.)\)\s*(.*)", line)
        if m:
            depth = len(m.group(1)) // 3
            stack[depth:] = [m.group(2)]
            key = tuple(stack)
            out[key] = (m.group(3), set(m.group(4).split()))
        elif line.strip():
            out[key][1].update(line.split())
    return out


def _robokit_schema():
    out = {}

    def walk(node, path):
        for tag, child in node.children.items():
            out[path + (tag,)] = (child.mult, set(child.attrs))
            walk(child, path + (tag,))

    out[("mujoco",)] = (_mjcf_schema._ROOT.mult, set(_mjcf_schema._ROOT.attrs))
    walk(_mjcf_schema._ROOT, ("mujoco",))
    return out


@pytest.mark.skipif(mujoco.__version__ != "4.0.1", reason="robokit's table is MuJoCo 4.0.1's schema")
def test_the_schema_table_is_mujocos():
    assert _robokit_schema() == _mujoco_schema()


def test_every_element_of_the_schema_is_read_by_mujoco():
    """Each attribute of the table, on its element, passes MuJoCo's schema check (whatever else MuJoCo
    then says about the value): the table never refuses what MuJoCo's schema reads."""
    for attrs, xml in [(_mjcf_schema.element_attributes("worldbody", "body", "joint"),
                        '<mujoco><worldbody><body><joint {a}="1"/></body></worldbody></mujoco>'),
                       (_mjcf_schema.element_attributes("worldbody", "body", "geom"),
                        '<mujoco><worldbody><geom {a}="1"/></worldbody></mujoco>'),
                       (_mjcf_schema.element_attributes("compiler"), '<mujoco><compiler {a}="1"/></mujoco>')]:
        for a in sorted(attrs):
            try:
                mujoco.MjModel.from_xml_string(xml.format(a=a))
            except ValueError as e:
                assert "unrecognized attribute" not in str(e), (a, str(e))


def _png(path):
    """A 4×4 grey PNG (the smallest file MuJoCo reads as a texture or a height field)."""
    import struct
    import zlib

    def chunk(kind, data):
        return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data) & 0xFFFFFFFF)

    raw = b"".join(b"\x00" + bytes([128] * 4) for _ in range(4))
    path.write_bytes(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", 4, 4, 8, 0, 0, 0, 0))
                     + chunk(b"IDAT", zlib.compress(raw)) + chunk(b"IEND", b""))


@pytest.mark.parametrize("asset,folder", [('<hfield name="a" file="a.png" size="1 1 1 1"/>', "mesh"),
                                          ('<texture name="a" type="2d" file="a.png"/>', "tex")])
@pytest.mark.parametrize("where", ["mesh", "tex"])
def test_asset_files_are_looked_for_where_mujoco_looks(asset, folder, where, tmp_path):
    """A height field's file is in meshdir, a texture's in texturedir (MuJoCo 4.0.1): robokit finds an
    unused asset's file where MuJoCo does, and refuses it where MuJoCo does not find it."""
    for sub in ("mesh", "tex"):
        (tmp_path / sub).mkdir()
    _png(tmp_path / where / "a.png")
    path = tmp_path / "arm.xml"
    path.write_text(_body("", head=f'<compiler meshdir="mesh" texturedir="tex"/><asset>{asset}</asset>'))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        if where == folder:
            mujoco.MjModel.from_xml_path(str(path))
            assert robokit.load(path).n == 1
        else:
            with pytest.raises(ValueError):
                mujoco.MjModel.from_xml_path(str(path))
            with pytest.raises(InputError, match="file not found"):
                robokit.load(path)
