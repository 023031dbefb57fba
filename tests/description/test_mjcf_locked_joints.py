"""MJCF joints off the chain are held where MuJoCo's model holds them: at ``qpos0``.

MuJoCo's model as the file draws it is at ``qpos0``: a hinge or slide at its ``ref`` (in the
compiler's angle unit for a hinge, from a ``<default>`` class too), a ball at the identity (the
body as written). A gripper's fingers locked off the chain are held there, so that the chain's
kinematics and dynamics are MuJoCo's with the locked joints at ``qpos0`` and the chain's joints
at any value: every body and site pose, the mass matrix's chain block (``mj_fullM``), gravity
torques (``qfrc_bias`` at zero velocity) and inverse dynamics (``mj_rne`` plus armature) — and
one note says which joints are held, at what. A free joint below the top level MuJoCo refuses,
and so does robokit.
"""
import math
import warnings

import numpy as np
import pytest

import robokit
from robokit.errors import InputError, RobokitWarning

mujoco = pytest.importorskip("mujoco", reason="MuJoCo is the reference (pip install mujoco)")

#: the compiler element of each angle unit (no element: MuJoCo's default, degrees)
COMPILERS = {"radian": '<compiler angle="radian"/>', "degree": '<compiler angle="degree"/>', "default": ""}


def gripper(unit="radian"):
    """A three-hinge arm (``j1`` with a ``ref`` of its own) ending in a hand whose fingers are off the
    chain to ``tool``: ``fa`` takes its ``ref`` from the ``finger`` class, ``fb`` overrides it, the
    distal body of ``fa`` has two hinges with ``ref``, ``sl`` is a slide with ``ref`` and ``cam``
    a ball. Angles written in ``unit``."""
    def angle(deg):
        return f"{math.radians(deg):.17g}" if unit == "radian" else f"{deg:g}"

    return f"""<mujoco model="gripper">{COMPILERS[unit]}
  <default><default class="finger"><joint axis="0 1 0" ref="{angle(40)}"/></default></default>
  <worldbody>
    <body name="base" pos="0 0 0.1"><geom type="cylinder" size="0.05 0.05" mass="2"/>
      <body name="upper" pos="0 0 0.1"><joint name="j1" axis="0 0 1" ref="{angle(20)}"/>
        <geom type="capsule" fromto="0 0 0 0.3 0 0.05" size="0.03" mass="1.5"/>
        <body name="fore" pos="0.3 0 0.05"><joint name="j2" axis="0 1 0"/>
          <geom type="capsule" fromto="0 0 0 0.25 0 0" size="0.025" mass="1"/>
          <body name="hand" pos="0.25 0 0" euler="{angle(10)} 0 {angle(-30)}"><joint name="j3" axis="1 0 0"/>
            <geom type="box" pos="0.03 0 0" size="0.03 0.04 0.02" mass="0.4"/><site name="tool" pos="0.12 0 0"/>
            <body name="finger_a" pos="0.06 0.03 0"><joint name="fa" class="finger"/>
              <geom type="box" pos="0.04 0 0" size="0.04 0.008 0.008" mass="0.15"/><site name="fa_tip" pos="0.08 0 0"/>
              <body name="fa_distal" pos="0.08 0 0">
                <joint name="fa2" axis="0 0 1" ref="{angle(25)}"/>
                <joint name="fa3" axis="0 1 0" pos="0.01 0 0" ref="{angle(-15)}"/>
                <geom type="box" pos="0.03 0 0" size="0.03 0.006 0.006" mass="0.05"/>
              </body>
            </body>
            <body name="finger_b" pos="0.06 -0.03 0"><joint name="fb" class="finger" ref="{angle(-50)}"/>
              <geom type="box" pos="0.04 0 0.01" size="0.04 0.008 0.008" mass="0.15"/>
            </body>
            <body name="slider" pos="0 0 0.03"><joint name="sl" type="slide" axis="1 0 1" ref="0.03"/>
              <geom type="box" size="0.02 0.02 0.01" mass="0.2"/>
            </body>
            <body name="camera" pos="0.02 0 -0.03"><joint name="cam" type="ball" pos="0 0 0.01"/>
              <geom type="box" pos="0.02 0 0" size="0.02 0.01 0.01" mass="0.1"/>
            </body>
          </body>
        </body>
      </body>
    </body>
  </worldbody>
</mujoco>"""


#: the joints ``gripper`` locks, and the values (rad or m) MuJoCo's qpos0 holds its hinges and slide at
LOCKED = {"fa": math.radians(40), "fa2": math.radians(25), "fa3": math.radians(-15), "fb": math.radians(-50),
          "sl": 0.03, "cam": None}


def _load(path, **kw):
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        robot = robokit.load(path, tip="tool", **kw)
    return robot, [str(w.message) for w in caught if issubclass(w.category, RobokitWarning)]


class MuJoCoAt:
    """MuJoCo on the same file: every joint at ``qpos0`` but the chain's, which take ``q``."""

    def __init__(self, path, robot):
        self.m = mujoco.MjModel.from_xml_path(str(path))
        self.d = mujoco.MjData(self.m)
        ids = [mujoco.mj_name2id(self.m, mujoco.mjtObj.mjOBJ_JOINT, jn) for jn in robot.joint_names]
        self.qadr = [int(self.m.jnt_qposadr[j]) for j in ids]
        self.dadr = [int(self.m.jnt_dofadr[j]) for j in ids]

    def forward(self, q, dq=None):
        m, d = self.m, self.d
        d.qpos[:], d.qvel[:], d.qacc[:] = m.qpos0, 0.0, 0.0
        d.qpos[self.qadr] = q
        if dq is not None:
            d.qvel[self.dadr] = dq
        mujoco.mj_forward(m, d)
        return d

    def mass_matrix(self, q):
        self.forward(q)
        M = np.zeros((self.m.nv, self.m.nv))
        if hasattr(self.d, "qM"):  # MuJoCo 3: mj_fullM(m, dst, qM); MuJoCo 4: mj_fullM(m, d, dst)
            mujoco.mj_fullM(self.m, M, self.d.qM)
        else:
            mujoco.mj_fullM(self.m, self.d, M)
        return M[np.ix_(self.dadr, self.dadr)]

    def gravity(self, q):
        return self.forward(q).qfrc_bias[self.dadr].copy()

    def rnea(self, q, dq, ddq):
        d = self.forward(q, dq)
        d.qacc[:] = 0.0
        d.qacc[self.dadr] = ddq
        out = np.zeros(self.m.nv)
        mujoco.mj_rne(self.m, d, 1, out)  # rigid bodies only: mj_inverse adds armature · q̈ as below
        return out[self.dadr] + self.m.dof_armature[self.dadr] * ddq


def _largest_differences(robot, path, samples=8):
    """The largest difference from MuJoCo of the body and site poses, M, gravity torques and RNEA."""
    ref = MuJoCoAt(path, robot)
    m = ref.m
    rng = np.random.default_rng(7)
    err = dict(poses=0.0, M=0.0, g=0.0, rnea=0.0)
    for _ in range(samples):
        q = rng.uniform(-np.pi, np.pi, robot.n)
        dq, ddq = rng.standard_normal(robot.n), rng.standard_normal(robot.n)
        d = ref.forward(q)
        poses = robot.frame_poses(q)
        for kind, n, xpos, xmat in ((mujoco.mjtObj.mjOBJ_BODY, m.nbody, d.xpos, d.xmat),
                                    (mujoco.mjtObj.mjOBJ_SITE, m.nsite, d.site_xpos, d.site_xmat)):
            for i in range(1 if kind == mujoco.mjtObj.mjOBJ_BODY else 0, n):
                T = poses[mujoco.mj_id2name(m, kind, i)]
                err["poses"] = max(err["poses"], np.abs(T[:3, 3] - xpos[i]).max(),
                                   np.abs(T[:3, :3] - xmat[i].reshape(3, 3)).max())
        err["M"] = max(err["M"], np.abs(robot.crba(q) - ref.mass_matrix(q)).max())
        err["g"] = max(err["g"], np.abs(robot.gravity_torques(q) - ref.gravity(q)).max())
        err["rnea"] = max(err["rnea"], np.abs(robot.rnea(q, dq, ddq) - ref.rnea(q, dq, ddq)).max())
    return err


@pytest.mark.parametrize("unit", sorted(COMPILERS))
def test_locked_joints_are_held_at_mujocos_qpos0(unit, tmp_path):
    path = tmp_path / "gripper.xml"
    path.write_text(gripper(unit))
    robot, _ = _load(path)
    assert list(robot.joint_names) == ["j1", "j2", "j3"] and set(robot.locked_joints) == set(LOCKED)
    m = mujoco.MjModel.from_xml_path(str(path))
    for jn, held in LOCKED.items():  # the file's qpos0 is what the test means it to be
        j = mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_JOINT, jn)
        if held is not None:
            assert m.qpos0[m.jnt_qposadr[j]] == pytest.approx(held, abs=1e-12)
    err = _largest_differences(robot, path)
    assert max(err.values()) < 1e-12, err


def test_one_note_names_the_locked_joints_and_where_they_are_held(tmp_path):
    path = tmp_path / "gripper.xml"
    path.write_text(gripper("degree"))
    robot, found = _load(path)
    hits = [n for n in found if "off the chain" in n]
    assert len(hits) == 1, found
    note = hits[0]
    assert note in robot.notes and "qpos0" in note and "'tool'" in note
    # each joint once, with its value in the file's own unit
    for shown in ("fa 40°", "fa2 25°", "fa3 -15°", "fb -50°", "sl 0.03 m", "cam (ball)"):
        assert note.count(shown + ",") + note.endswith(shown) == 1, (shown, note)
    path.write_text(gripper("radian"))
    _, found = _load(path)
    note, = [n for n in found if "off the chain" in n]
    assert f"fa {math.radians(40):g} rad" in note and "sl 0.03 m" in note
    text = gripper("radian")  # the hand without its fingers: nothing locked, no note
    start, end = text.index('<body name="finger_a"'), text.index("</worldbody>")
    path.write_text(text[:start] + "</body></body></body></body>" + text[end:])
    robot, found = _load(path)
    assert robot.locked_joints == () and not [n for n in found if "off the chain" in n]


def test_the_armature_note_names_the_chains_joints_only(tmp_path):
    """A finger's armature sits on the finger's own diagonal entry of MuJoCo's M, outside the chain's block."""
    path = tmp_path / "gripper.xml"
    path.write_text(gripper("radian").replace('<joint name="fa" class="finger"/>',
                                              '<joint name="fa" class="finger" armature="0.01"/>')
                    .replace('<joint name="j2" axis="0 1 0"/>', '<joint name="j2" axis="0 1 0" armature="0.2"/>'))
    robot, found = _load(path)
    note, = [n for n in found if "armature" in n]
    assert "(j2 0.2)" in note
    err = _largest_differences(robot, path)
    assert max(err.values()) < 1e-12, err


def test_convert_says_it_once(tmp_path, capsys):
    """``robokit convert`` of an MJCF file does not add its neutral-value note to the loader's."""
    from robokit.cli import main

    path = tmp_path / "gripper.xml"
    path.write_text(gripper("degree"))
    assert main(["convert", str(path), "--tip", "tool", "-o", str(tmp_path / "gripper.json")]) == 0
    err = capsys.readouterr().err
    assert err.count("off the chain") == 1 and "qpos0" in err, err


def test_a_free_joint_below_the_top_level_is_refused_as_mujoco_refuses_it(tmp_path):
    xml = ('<mujoco><worldbody><body name="a"><joint name="j1"/><geom size="0.1"/>'
           '<body name="b" pos="0.3 0 0"><freejoint name="f"/><geom size="0.05"/></body>'
           '<body name="c" pos="0.5 0 0"><joint name="j2"/><geom size="0.05"/></body></body></worldbody></mujoco>')
    path = tmp_path / "nested_free.xml"
    path.write_text(xml)
    with pytest.raises(ValueError, match="top level"):
        mujoco.MjModel.from_xml_path(str(path))
    with pytest.raises(InputError, match="<body name='b'>: its free joint hangs below body 'a'"):
        robokit.load(path)


def test_a_free_body_fused_to_the_world_is_held_where_it_is_drawn(tmp_path):
    """With ``fusestatic`` a free body below a static one is top-level for MuJoCo (its parent fused into
    the world): locked off the chain, it stays where the file draws it (MuJoCo's qpos0 is its pose)."""
    xml = ('<mujoco><compiler fusestatic="true" angle="radian"/><worldbody>'
           '<body name="base" pos="0 0 0.2" euler="0 0 0.5"><geom size="0.05" mass="1"/>'
           '<body name="l1" pos="0 0 0.1"><joint name="j1" axis="0 1 0"/>'
           '<geom type="capsule" fromto="0 0 0 0.3 0 0" size="0.02" mass="1"/><site name="tool" pos="0.3 0 0"/></body>'
           '<body name="box" pos="0.4 0.1 0" euler="0.3 0.2 0.1"><freejoint name="f"/>'
           '<geom type="box" size="0.03 0.02 0.01" mass="0.5"/><site name="box_corner" pos="0.03 0.02 0.01"/></body>'
           '</body></worldbody></mujoco>')
    path = tmp_path / "free_box.xml"
    path.write_text(xml)
    robot, _ = _load(path)
    assert robot.locked_joints == ("f",)
    err = _largest_differences(robot, path)
    assert max(err.values()) < 1e-12, err
