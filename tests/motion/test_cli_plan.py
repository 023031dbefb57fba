"""robokit plan: a scene YAML, a CSV the viewer reads, one-line errors with exit 2."""
import numpy as np
import pytest

import robokit
from robokit.cli import main
from robokit.collision import Box, World, load_scene
from robokit.errors import InputError

pytest.importorskip("ompl")

SCENE = """\
padding: 0.0
obstacles:
  - type: box
    name: wall
    size: [0.4, 0.05, 0.8]
    pose: {xyz: [0.45, 0.35, 0.4], rpy: [0, 0, 0]}
  - type: sphere
    radius: 0.05
    pose: {xyz: [-0.6, -0.6, 0.2]}
"""


def test_scene_yaml(tmp_path):
    p = tmp_path / "scene.yaml"
    p.write_text(SCENE)
    obs, pad = load_scene(p)
    assert pad == 0.0 and [o.name for o in obs] == ["wall", ""]
    assert isinstance(obs[0], Box) and obs[0].size.tolist() == [0.4, 0.05, 0.8]
    np.testing.assert_allclose(obs[0].pose[:3, 3], [0.45, 0.35, 0.4])
    for bad, msg in [("obstacles: [{type: cone}]", "type"), ("obstacles: [{type: box, size: [1, 1, 1], colour: 1}]", "colour"),
                     ("obstacles: [{type: sphere}]", "radius"), ("walls: []", "walls"),
                     ("obstacles: [{type: box, size: [1, -1, 1]}]", "size")]:
        p.write_text(bad)
        with pytest.raises(InputError, match=msg):
            load_scene(p)


def test_plan_command_writes_a_collision_free_csv(tmp_path, capsys):
    scene = tmp_path / "scene.yaml"
    scene.write_text(SCENE)
    out = tmp_path / "traj.csv"
    rc = main(["plan", "puma560", "--start", "0", "0.3", "-0.3", "0", "0", "0",
               "--goal", "1.4", "0.3", "-0.3", "0", "0", "0", "--obstacles", str(scene), "-o", str(out)])
    assert rc == 0
    from robokit.viz.view import load_trajectory
    r = robokit.load("puma560")
    Q = load_trajectory(out, 6)
    np.testing.assert_allclose(Q[0], [0, 0.3, -0.3, 0, 0, 0], atol=1e-9)
    np.testing.assert_allclose(Q[-1], [1.4, 0.3, -0.3, 0, 0, 0], atol=1e-9)
    obs, _ = load_scene(scene)
    assert not World(r, obs).in_collision(Q).any()
    capsys.readouterr()
    bad = tmp_path / "bad.csv"
    rc = main(["plan", "puma560", "--start", "0", "0", "0", "0", "0", "0", "--goal", "1", "2", "-o", str(bad)])
    err = capsys.readouterr().err
    assert rc == 2 and err.startswith("robokit: error: --goal") and not bad.exists()


def test_plan_takes_the_xacro_options_of_every_command(tmp_path, capsys):
    """A maker's xacro with its launch arguments (Interbotix's WidowX 250 6DOF named ``left``, its package
    given with --package-path as a workspace holds it): ``robokit plan`` refused --xacro-arg and
    --package-path ("unrecognized arguments", exit 2) though every other command that loads a robot takes
    them. The goal pose is Pinocchio's on the xacro program's expansion with the same argument, and the
    plan's last row reaches it there."""
    import pinocchio as pin
    from pathlib import Path

    from robokit.viz.view import load_trajectory
    from xacro_reference import xacro_urdfs

    data = Path(__file__).resolve().parents[1] / "data" / "interbotix"
    rel = "interbotix_xsarm_descriptions/urdf/wx250s.urdf.xacro"
    model = pin.buildModelFromXML(xacro_urdfs({"left": (data, rel, {"robot_name": "left"})})["left"])
    joints = ["waist", "shoulder", "elbow", "forearm_roll", "wrist_angle", "wrist_rotate"]
    iq = [model.joints[model.getJointId(j)].idx_q for j in joints]
    pin_data, fid = model.createData(), model.getFrameId("left/ee_gripper_link")

    def fk(q):
        qf = pin.neutral(model)
        qf[iq] = q
        pin.framesForwardKinematics(model, pin_data, qf)
        return pin_data.oMf[fid].homogeneous.copy()

    T = fk([0.6, -0.3, 0.4, 0.2, 0.5, -0.4])
    rpy = pin.rpy.matrixToRpy(T[:3, :3])
    out = tmp_path / "traj.csv"
    rc = main(["plan", str(data / rel), "--xacro-arg", "robot_name:=left", "--package-path", str(data),
               "--start", "0", "0", "0", "0", "0", "0", "--goal-pose", *map(str, [*T[:3, 3], *rpy]), "-o", str(out)])
    assert rc == 0, capsys.readouterr().err
    Q = load_trajectory(out, 6)
    assert np.abs(Q[0]).max() == 0 and np.abs(fk(Q[-1]) - T).max() < 1e-6  # the CSV's 10 digits
