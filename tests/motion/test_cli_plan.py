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
