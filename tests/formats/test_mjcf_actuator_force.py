"""An MJCF joint's ``actuatorfrcrange`` is its effort limit: MuJoCo clamps the total actuator force on the
joint to it, and MuJoCo's URDF reader writes a URDF's ``<limit effort>`` there. robokit reads a limited,
symmetric range as ``model.effortLimit`` (before: ignored, the limit inf) with MuJoCo's rules for
``actuatorfrclimited`` (``auto``: limited when the range is not empty and the compiler's autolimits is on),
checked against MuJoCo itself; an asymmetric range is noted, not read."""
import warnings

import numpy as np
import pytest

import robokit

mujoco = pytest.importorskip("mujoco", reason="MuJoCo is the reference (pip install mujoco)")

ARM = """<mujoco model="forces">
  <compiler angle="radian" autolimits="true"/>
  <default><default class="strong"><joint actuatorfrcrange="-40 40"/></default></default>
  <worldbody>
    <body name="l1"><inertial pos="0.1 0 0" mass="1" diaginertia="0.01 0.02 0.02"/>
      <joint name="auto" axis="0 0 1" actuatorfrcrange="-2.5 2.5"/>
      <body name="l2" pos="0.2 0 0"><inertial pos="0.1 0 0" mass="1" diaginertia="0.01 0.02 0.02"/>
        <joint name="explicit" axis="0 1 0" actuatorfrclimited="true" actuatorfrcrange="-7 7"/>
        <body name="l3" pos="0.2 0 0"><inertial pos="0.1 0 0" mass="1" diaginertia="0.01 0.02 0.02"/>
          <joint name="off" axis="0 1 0" actuatorfrclimited="false" actuatorfrcrange="-3 3"/>
          <body name="l4" pos="0.2 0 0"><inertial pos="0.1 0 0" mass="1" diaginertia="0.01 0.02 0.02"/>
            <joint name="by_class" class="strong" axis="1 0 0"/>
            <body name="l5" pos="0.1 0 0"><inertial pos="0.05 0 0" mass="0.5" diaginertia="0.01 0.01 0.01"/>
              <joint name="none" type="slide" axis="1 0 0" range="0 0.1"/>
              <body name="l6" pos="0.1 0 0"><inertial pos="0.05 0 0" mass="0.5" diaginertia="0.01 0.01 0.01"/>
                <joint name="asymmetric" axis="0 0 1" actuatorfrcrange="-1 3"/>
                <site name="tip" pos="0.1 0 0"/>
              </body></body></body></body></body></body>
  </worldbody>
</mujoco>
"""


def test_the_effort_limit_is_mujocos_actuator_force_range(tmp_path):
    path = tmp_path / "forces.xml"
    path.write_text(ARM)
    m = mujoco.MjModel.from_xml_path(str(path))
    with warnings.catch_warnings(record=True) as said:
        warnings.simplefilter("always")
        robot = robokit.load(path, "tip")
    for name in robot.joint_names:
        j = m.joint(name)
        lo, hi = m.jnt_actfrcrange[j.id]
        got = robot.model.effortLimit[robot.model.joints[robot.model.getJointId(name)].idx_v]
        if m.jnt_actfrclimited[j.id] and lo == -hi:
            assert got == hi, name
        else:
            assert got == np.inf, name
    assert robot.model.effortLimit.tolist() == [2.5, 7.0, np.inf, 40.0, np.inf, np.inf]  # MuJoCo's, as above
    notes = [str(w.message) for w in said if "actuatorfrcrange" in str(w.message)]
    assert len(notes) == 1 and "'asymmetric'" in notes[0] and "-1 3" in notes[0], notes


@pytest.mark.parametrize("compiler, joint, message", [
    ('autolimits="false"', 'actuatorfrcrange="-2 2"', "actuatorfrcrange but not actuatorfrclimited"),
    ('autolimits="true"', 'actuatorfrclimited="true"', r"actuatorfrcrange\[0\] should be smaller"),
    ('autolimits="true"', 'actuatorfrclimited="maybe"', "expected true, false or auto"),
])
def test_what_mujoco_refuses_robokit_refuses(tmp_path, compiler, joint, message):
    text = (f'<mujoco><compiler {compiler}/><worldbody><body name="b"><inertial pos="0 0 0" mass="1" '
            f'diaginertia="1 1 1"/><joint name="j" axis="0 0 1" {joint}/></body></worldbody></mujoco>')
    path = tmp_path / "bad.xml"
    path.write_text(text)
    if "maybe" not in joint:
        with pytest.raises(ValueError):
            mujoco.MjModel.from_xml_string(text)
    with pytest.raises(robokit.InputError, match=message):
        robokit.load(path)
