"""``robokit calibrate MODEL DATA.csv -o OUT``: the written robot, and bad data files (exit 2, one line naming
the line and column, nothing written)."""
import dataclasses
import os

import numpy as np
import pinocchio as pin
import pytest
from calibration_support import configurations
from hardening_support import assert_one_line_error, run_cli, run_main, tmp_leftovers

import robokit
from robokit.calibration import chain_from_robot, write_calibration_csv
from robokit.description import DHTable


@pytest.fixture(scope="module")
def puma(robots):
    return robots("puma560")


def tilted_true_arm(robot, rng):
    return chain_from_robot(robot).perturbed(rng.normal(0.0, 2e-3, (robot.n + 1, 6)))


def write_data(path, robot, true_fk, K, rng, poses=True):
    q = configurations(robot, K, rng)
    T = true_fk(q)
    write_calibration_csv(path, q, T if poses else T[:, :3, 3])
    return q


def test_urdf_output_loads_and_matches(puma, tmp_path, capfd):
    rng = np.random.default_rng(1)
    true = tilted_true_arm(puma, rng)
    data = tmp_path / "poses.csv"
    q = write_data(data, puma, true.fk, 40, rng)
    out = tmp_path / "cal.urdf"
    run = run_main(["calibrate", "puma560", data, "-o", out], capfd)
    assert run.rc == 0, run.err
    assert "RMS before:" in run.out and "RMS after:" in run.out and "mrad" in run.out
    res = robokit.calibrate(puma, q, true.fk(q))
    unseen = configurations(puma, 10, rng)
    # Pinocchio on the written file
    model = pin.buildModelFromUrdf(str(out))
    data_ = model.createData()
    names = [model.names[j] for j in range(1, model.njoints)]
    assert names == [f"joint_{i}" for i in range(1, 7)]
    fid = model.getFrameId("tool")
    assert model.existFrame("base_link") and all(model.existFrame(f"dh_{i}") for i in range(7))
    for qk in unseen:
        pin.framesForwardKinematics(model, data_, qk)
        np.testing.assert_allclose(data_.oMf[fid].homogeneous, res.robot.frame_pose(qk), atol=1e-9)
        np.testing.assert_allclose(data_.oMf[fid].homogeneous, true.fk(qk[None])[0], atol=1e-7)
    # yourdfpy on the written file
    import yourdfpy

    urdf = yourdfpy.URDF.load(str(out), load_meshes=False, build_scene_graph=True)
    for qk in unseen[:3]:
        urdf.update_cfg({f"joint_{i + 1}": qk[i] for i in range(6)})
        np.testing.assert_allclose(urdf.get_transform("tool", "base_link"), res.robot.frame_pose(qk), atol=1e-9)
    # the nominal inertias are kept
    np.testing.assert_allclose(res.robot.rnea(unseen[0], unseen[1], unseen[2]),
                               robokit.load(str(out)).rnea(unseen[0], unseen[1], unseen[2]), atol=1e-8)


def test_dh_yaml_only_for_a_dh_arm(puma, tmp_path, capfd):
    rng = np.random.default_rng(2)
    # a true arm that is still a DH arm: the DH parameters, base and tool perturbed, joints 2 ∥ 3 kept
    links = []
    for i, l in enumerate(puma.dh.links):
        links.append(dataclasses.replace(l, a=l.a + rng.normal(0, 2e-3), d=l.d + rng.normal(0, 2e-3),
                                         theta=l.theta + rng.normal(0, 2e-3),
                                         alpha=l.alpha + (0.0 if i == 1 else rng.normal(0, 2e-3))))
    base = np.eye(4)
    base[:3, 3] = rng.normal(0, 5e-3, 3)
    table = DHTable("puma_true", "standard", tuple(links), base=base, tool=puma.dh.tool)
    data = tmp_path / "dh.csv"
    write_data(data, puma, lambda q: np.array([table.fk(qk) for qk in q]), 40, rng)
    out = tmp_path / "cal.yaml"
    run = run_main(["calibrate", "puma560", data, "-o", out], capfd)
    assert run.rc == 0, run.err
    back = robokit.load(str(out))
    for qk in configurations(puma, 10, rng):
        np.testing.assert_allclose(back.frame_pose(qk), table.fk(qk), atol=1e-7)
    # a tilted arm (joints 2 and 3 no longer parallel): refused, nothing written, URDF suggested
    data2 = tmp_path / "tilted.csv"
    write_data(data2, puma, tilted_true_arm(puma, rng).fk, 40, rng)
    out2 = tmp_path / "tilted.yaml"
    run = run_main(["calibrate", "puma560", data2, "-o", out2], capfd)
    assert_one_line_error(run, "URDF", "DH")
    assert not out2.exists() and tmp_leftovers(tmp_path) == []


def test_positions_only_and_limit_notes(puma, tmp_path, capfd):
    rng = np.random.default_rng(3)
    true = tilted_true_arm(puma, rng)
    q = configurations(puma, 30, rng)
    q[4, 1] = 3.0  # beyond joint 2's limit of the model (±110°)
    data = tmp_path / "pos.csv"
    write_calibration_csv(data, q, true.fk(q)[:, :3, 3])
    out = tmp_path / "cal.urdf"
    run = run_main(["calibrate", "puma560", data, "-o", out], capfd)
    assert run.rc == 0, run.err
    assert "robokit: note:" in run.err and "'q2'" in run.err and "line 6" in run.err
    assert "mrad" not in run.out
    assert out.exists()


HEADER = "q1,q2,q3,q4,q5,q6,x,y,z,qw,qx,qy,qz"
ROW = "0.1,0.2,0.3,0.4,0.5,0.6,0.5,0.1,0.9,1.0,0.0,0.0,0.0"


def _rows(k=40, rng=None):
    rng = rng or np.random.default_rng(0)
    out = []
    for _ in range(k):
        q = rng.uniform(-1, 1, 6)
        w = rng.normal(size=4)
        w /= np.linalg.norm(w)
        out.append(",".join(repr(float(v)) for v in [*q, *rng.uniform(-1, 1, 3), *w]))
    return out


BAD = {
    "short row": (lambda r: [HEADER, *r[:3], "0.1,0.2,0.3", *r[3:]], ["line 5", "expected 13 columns, got 3"]),
    "NaN": (lambda r: [HEADER, *r[:2], r[2].replace(r[2].split(",")[7], "nan", 1), *r[3:]], ["line 4", "'y'"]),
    "non-numeric": (lambda r: [HEADER, r[0], r[1].replace(r[1].split(",")[0], "abc", 1), *r[2:]],
                    ["line 3", "'q1'", "not a number"]),
    "wrong names": (lambda r: [HEADER.replace("x,y,z", "x,y,w"), *r], ["line 1", "'z'"]),
    "wrong count": (lambda r: ["q1,q2,x,y,z", *r], ["line 1", "expected 9 columns", "or 13", "got 5"]),
    "too few samples": (lambda r: [HEADER, *r[:3]], ["samples are needed"]),
    "quaternion": (lambda r: [HEADER, *r[:6], ROW.replace("1.0,0.0,0.0,0.0", "1.01,0.0,0.0,0.0"), *r[6:]],
                   ["line 8", "qw", "quaternion norm", "1e-06"]),
    "empty": (lambda r: [], ["empty file"]),
    "header only": (lambda r: [HEADER], ["no measurement rows"]),
}


@pytest.mark.parametrize("case", sorted(BAD))
def test_bad_data_files(tmp_path, capfd, case):
    make, names = BAD[case]
    data = tmp_path / "bad.csv"
    data.write_text("\n".join(make(_rows())) + "\n")
    out = tmp_path / "out.urdf"
    run = run_main(["calibrate", "puma560", data, "-o", out], capfd)
    assert_one_line_error(run, *names)
    assert not out.exists() and tmp_leftovers(tmp_path) == []


def test_not_a_regular_file_and_bad_output(tmp_path, capfd):
    fifo = tmp_path / "pipe.csv"
    os.mkfifo(fifo)
    run = run_main(["calibrate", "puma560", fifo, "-o", tmp_path / "o.urdf"], capfd)
    assert_one_line_error(run, "not a regular file")
    run = run_main(["calibrate", "puma560", tmp_path, "-o", tmp_path / "o.urdf"], capfd)
    assert_one_line_error(run, "not a regular file")
    data = tmp_path / "d.csv"
    data.write_text("\n".join([HEADER, *_rows()]) + "\n")
    run = run_main(["calibrate", "puma560", data, "-o", tmp_path / "o.json"], capfd)
    assert_one_line_error(run, "-o", ".urdf")
    assert not (tmp_path / "o.urdf").exists()


def test_console_command_in_a_fresh_process(tmp_path):
    """``python -m robokit.cli calibrate`` in a subprocess: a good file (exit 0, URDF written, RMS on stdout)
    and a bad one (exit 2, one line)."""
    robot = robokit.load("rrr")
    rng = np.random.default_rng(9)
    true = tilted_true_arm(robot, rng)
    data = tmp_path / "rrr.csv"
    write_data(data, robot, true.fk, 20, rng, poses=False)
    run = run_cli("calibrate", "rrr", data, "-o", tmp_path / "rrr.urdf")
    assert run.rc == 0, run.err
    assert "RMS after:" in run.out and (tmp_path / "rrr.urdf").is_file()
    data.write_text("q1,q2,q3,x,y,z\n0,0,0,1,2\n")
    run = run_cli("calibrate", "rrr", data, "-o", tmp_path / "bad.urdf")
    assert_one_line_error(run, "line 2", "expected 6 columns, got 5")
    assert not (tmp_path / "bad.urdf").exists()


def test_a_data_file_in_degrees_gets_the_degrees_note(puma, tmp_path, capfd):
    """``robokit calibrate`` named joint values outside the limits column by column, but, unlike ``view -q``,
    ``--start``, ``--goal`` and ``view --trajectory``, never said they look like degrees. The same
    measurements with their joint columns in degrees: one degrees note naming the file; in radians, none."""
    rng = np.random.default_rng(4)
    q = configurations(puma, 40, rng)
    T = chain_from_robot(puma).fk(q)
    for values, noted in ((np.degrees(q), True), (q, False)):
        data = tmp_path / "poses.csv"
        write_calibration_csv(data, values, T)
        run = run_main(["calibrate", "puma560", data, "-o", tmp_path / "cal.urdf"], capfd)
        assert run.rc == 0, run.err
        notes = [ln for ln in run.err.splitlines() if ln.startswith("robokit: note:") and "looks like degrees" in ln]
        assert len(notes) == (1 if noted else 0), run.err
        assert not noted or notes[0].startswith(f"robokit: note: {data}: "), notes
