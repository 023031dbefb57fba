"""``robokit workspace`` on a maker's file says each of the file's notes once: the workers rebuild the robot
from its spec, and that rebuild says nothing again. Before, Interbotix's PincherX 100 (tests/data/interbotix)
printed its four notes (missing meshes, <ros2_control>, <dynamics>, the locked mimic finger) twice with the
serial scheduler and once more per worker process of a local cluster."""
from pathlib import Path

from robokit.cli import main

PX100 = Path(__file__).resolve().parents[1] / "data" / "interbotix" / "interbotix_xsarm_descriptions" / "urdf" / \
    "px100.urdf.xacro"


def test_each_note_once(tmp_path, capsys):
    out = tmp_path / "px100.npz"
    assert main(["workspace", str(PX100), "--resolution", "0.2", "--orientations", "4", "--scheduler", "serial",
                 "-o", str(out)]) == 0
    err = capsys.readouterr().err
    for note in ("mesh files not found", "<ros2_control>", "<dynamics> of joints", "mimic joints off the chain"):
        assert err.count(note) == 1, (note, err)
    assert out.is_file()
