"""A URDF visual's colour as urdfdom reads it, held against Pinocchio's geometry model of the same text.

Found loading Aubo's ``aubo_i5L.urdf`` (AuboRobot/aubo_robot): a ``<color rgba>`` of three numbers made
robokit refuse the robot ("expected 4 finite numbers", naming no file) while urdfdom — and so Pinocchio,
ROS and every URDF viewer — loads it (the colour black). urdfdom's rule, measured here case by case on
``pinocchio.buildGeomFromUrdfString``: ``rgba`` split at spaces, each part a number from 0 to 1; parts of
that kind but not four of them give black; a part that is not (out of range, NaN, hex, trailing letters,
a tab inside) leaves an in-place material undefined (no colour: the viewer's default) and a top-level
material black; a named material's first definition wins; a texture alone is black. Two top-level
materials of one name make urdfdom refuse the robot, and robokit too.
"""
import warnings

import numpy as np
import pytest

import robokit
from robokit.errors import InputError, RobokitWarning

pin = pytest.importorskip("pinocchio")

_INERTIAL = '<inertial><mass value="1"/><inertia ixx="0.1" iyy="0.1" izz="0.1" ixy="0" ixz="0" iyz="0"/></inertial>'

#: (material element, what it tests); each becomes one box visual of link l1, in this order.
VISUALS = (
    ('<material name="grey"><color rgba="0.25098 0.25098 0.25098"/></material>', "three numbers (Aubo i5L)"),
    ('<material name="grey"/>', "the three-number material by name"),
    ('<material name="top3"/>', "a top-level material of three numbers"),
    ('<material name="topx"/>', "a top-level material with a part that is not a number"),
    ('<material name="topneg"/>', "a top-level material below 0"),
    ('<material name="oor"><color rgba="1.5 0.5 0 1"/></material>', "a part above 1"),
    ('<material name="oor"/>', "its name afterwards: undefined"),
    ('<material name="oor"><color rgba="0.5 0.5 0 1"/></material>', "then defined properly"),
    ('<material name="five"><color rgba="0.1 0.2 0.3 0.4 0.5"/></material>', "five numbers"),
    ('<material name="two"><color rgba="0.5 0.5"/></material>', "two numbers"),
    ('<material name="two"><color rgba="0.1 0.1 0.1 1"/></material>', "the first definition wins"),
    ('<material name="empty"><color rgba=""/></material>', "no numbers"),
    ('<material name="nan"><color rgba="nan 0 0 1"/></material>', "NaN"),
    ('<material name="hex"><color rgba="0x1 1 1 1"/></material>', "hexadecimal"),
    ('<material name="trail"><color rgba="0.5abc 1 1 1"/></material>', "trailing letters"),
    ('<material name="tab"><color rgba="0.5&#9;1 1 1"/></material>', "a tab does not separate"),
    ('<material name="spaces"><color rgba="  0.1   0.2 0.3  0.4 "/></material>', "extra spaces"),
    ('<material name="norgba"><color/></material>', "a colour without rgba"),
    ('<material name="unknown"/>', "a name defined nowhere"),
    ('<material name="tex"><texture filename="a.png"/></material>', "a texture alone"),
    ('<material name="texbad"><texture filename="a.png"/><color rgba="2 0 0 1"/></material>',
     "a texture and a colour out of range"),
    ('<material name="tiny"><color rgba="1e-400 1 1 1"/></material>', "an underflowing number"),
    ('<material name="dup"><color rgba="0.9 0.2 0.3 1"/></material>', "a top-level name defined again in place"),
)


def _urdf(visuals=VISUALS, top=None):
    top = top if top is not None else (
        '<material name="top3"><color rgba="0.2 0.3 0.4"/></material>'
        '<material name="topx"><color rgba="0.2 0.3 x 1"/></material>'
        '<material name="topneg"><color rgba="-0.2 0.3 0.4 1"/></material>'
        '<material name="dup"><color rgba="0.1 0.2 0.3 1"/></material>')
    boxes = "".join(f'<visual><geometry><box size="0.1 0.1 0.1"/></geometry>{m}</visual>' for m, _ in visuals)
    return (f'<robot name="colors">{top}<link name="base">{_INERTIAL}</link><link name="l1">{_INERTIAL}{boxes}</link>'
            '<joint name="j1" type="revolute"><parent link="base"/><child link="l1"/><axis xyz="0 0 1"/>'
            '<limit lower="-1" upper="1" effort="1" velocity="1"/></joint></robot>')


def _load(tmp_path, text):
    path = tmp_path / "colors.urdf"
    path.write_text(text)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        robot = robokit.load(path)
    return robot, [str(w.message) for w in caught if issubclass(w.category, RobokitWarning)]


def test_visual_colors_as_pinocchio_reads_them(tmp_path):
    text = _urdf()
    robot, _ = _load(tmp_path, text)
    model = pin.buildModelFromXML(text)
    theirs = pin.buildGeomFromUrdfString(model, text, pin.GeometryType.VISUAL).geometryObjects
    mine = robot.visual_model.geometryObjects
    assert len(mine) == len(theirs) == len(VISUALS)
    for a, b, (_, what) in zip(mine, theirs, VISUALS):
        assert a.overrideMaterial == b.overrideMaterial, what
        np.testing.assert_allclose(a.meshColor, b.meshColor, rtol=1e-7, err_msg=what)


def test_aubo_three_number_color_loads_with_a_note(tmp_path):
    """The Aubo i5L's material, alone: the robot loads, and the note names the file, the link and the colour."""
    robot, notes = _load(tmp_path, _urdf(VISUALS[:1], top=""))
    assert robot.n == 1
    (note,) = [n for n in notes if "rgba" in n]
    assert str(tmp_path / "colors.urdf") in note and "link 'l1'" in note and "'0.25098 0.25098 0.25098'" in note


def test_well_formed_colors_get_no_note(tmp_path):
    _, notes = _load(tmp_path, _urdf(VISUALS[7:8] + VISUALS[16:17], top=""))
    assert not [n for n in notes if "rgba" in n]


def test_two_top_level_materials_of_one_name_are_refused(tmp_path):
    top = ('<material name="m"><color rgba="0.1 0.2 0.3 1"/></material>'
           '<material name="m"><color rgba="0.5 0.2 0.3 1"/></material>')
    text = _urdf(VISUALS[:0], top=top)
    with pytest.raises(ValueError):  # urdfdom: "material 'm' is not unique"
        pin.buildModelFromXML(text)
    with pytest.raises(InputError, match=r"colors\.urdf: material 'm' is defined twice"):
        _load(tmp_path, text)


def test_a_bad_box_size_names_the_file(tmp_path):
    text = _urdf(VISUALS[:0], top="").replace('<link name="l1">',
                                                '<link name="l1"><visual><geometry><box size="1 2"/></geometry></visual>')
    with pytest.raises(InputError, match=r"colors\.urdf: link 'l1' <visual> <box size>"):
        _load(tmp_path, text)
