"""Measurement data on hostile input (issue 39, classes 6 and 7): every parser error of the data
readers is an InputError naming the file, the line and the column; a number is what the docs say
(robokit._table: no `1_0`, no digits of other scripts); measurements are bounded in magnitude like
robot files (1e12); every size argument is checked before anything is allocated; API errors name
the argument. The CLI cases run in a subprocess under a 3 GB address-space limit (a safety net,
never a timing) and must give exit 2 and one ``robokit: error:`` line."""
import numpy as np
import pytest
import limited_cli as r2
from calibration_support import configurations, motions
from hardening_support import assert_one_line_error

import robokit
from robokit._table import parse_number
from robokit.calibration import read_calibration_csv, write_calibration_csv
from robokit.trajectory.core import MAX_SAMPLES

HEADER = "q1,q2,q3,x,y,z"


def _rows(robot, k=30, seed=0, scale=1.0):
    rng = np.random.default_rng(seed)
    q = configurations(robot, k, rng)
    p = robot.frame_pose(q)[:, :3, 3] * scale
    return [",".join(repr(float(v)) for v in [*qk, *pk]) for qk, pk in zip(q, p)]


def _csv(tmp_path, lines, name="d.csv"):
    p = tmp_path / name
    p.write_text("\n".join(lines) + "\n", encoding="utf-8")
    return p


# ------------------------------------------------------------------ class 6: parser errors name line and column
@pytest.mark.parametrize("cell, line, column", [
    ("9" * 131_073, 4, 2),          # over csv's field limit: was csv.Error, exit 3
    ("0.1\x00", 3, 2),              # a NUL byte: csv.Error "line contains NUL"
    ('"0.5', 5, 2),                 # an unterminated quote: csv read the rest of the file as one cell
    ("0.5 0.5", 4, 2),
])
def test_parser_errors_name_the_file_line_and_column(robots, tmp_path, cell, line, column):
    robot = robots("rrr")
    rows = _rows(robot)
    k = line - 2
    cells = rows[k].split(",")
    cells[column - 1] = cell
    rows[k] = ",".join(cells)
    p = _csv(tmp_path, [HEADER, *rows])
    with pytest.raises(robokit.InputError) as e:
        read_calibration_csv(p, 3)
    msg = str(e.value)
    assert str(p) in msg and f"line {line}" in msg and f"column {column}" in msg, msg
    assert len(msg) < 400


@pytest.mark.parametrize("text", ["1_0", "١٢", "１２", "0x10", "inf", "-nan", "1e999", "٣.٥", "1,5", "", "1e", "+-1"])
def test_only_documented_numbers_are_numbers(text):
    """Python's float accepts `1_0`, Arabic-Indic and full-width digits, `inf` and `nan`; robokit's one
    number parser accepts what the docs say a number is."""
    with pytest.raises(robokit.InputError, match="line 2, column 3"):
        parse_number(text, "d.csv: line 2, column 3")


@pytest.mark.parametrize("text, value", [("-0.5", -0.5), (" 12 ", 12.0), (".25", 0.25), ("1.5e-3", 1.5e-3),
                                         ("2E+04", 2e4), ("+7.", 7.0), ("\t3\t", 3.0)])
def test_documented_numbers_parse_as_python_reads_them(text, value):
    assert parse_number(text, "d.csv: line 1, column 1") == value


def test_cli_data_readers_exit_2_with_one_line(robots, tmp_path):
    """Both CSV readers of the command line (calibrate's data, view's --trajectory), each fed a cell
    over 131,072 characters and an underscore number: exit 2, one line naming line and column."""
    robot = robots("rrr")
    rows = _rows(robot)
    long_cell = _csv(tmp_path, [HEADER, rows[0], rows[1].replace(rows[1].split(",")[1], "7" * 200_000, 1), *rows[2:]],
                     "long.csv")
    underscore = _csv(tmp_path, [HEADER, *rows[:5], "1_0" + rows[5][rows[5].index(","):], *rows[6:]], "under.csv")
    traj_long = _csv(tmp_path, ["q1,q2,q3", "0,0,0", "0," + "7" * 200_000 + ",0"], "t_long.csv")
    traj_digits = _csv(tmp_path, ["# a comment", "q1,q2,q3", "0,0,0", "", "0,٣,0"], "t_digits.csv")
    out = tmp_path / "o.urdf"
    runs = r2.run_many([["calibrate", "rrr", long_cell, "-o", out], ["calibrate", "rrr", underscore, "-o", out],
                        ["view", "rrr", "--trajectory", traj_long, "-o", tmp_path / "v.html"],
                        ["view", "rrr", "--trajectory", traj_digits, "-o", tmp_path / "v.html"]])
    assert_one_line_error(runs[0], "long.csv", "line 3", "16384")
    assert_one_line_error(runs[1], "under.csv", "line 7", "column 1", "'q1'", "not a number")
    assert_one_line_error(runs[2], "t_long.csv", "line 3", "16384")
    assert_one_line_error(runs[3], "t_digits.csv", "line 5", "column 2", "not a number")
    assert not out.exists() and not (tmp_path / "v.html").exists()


def test_scene_yaml_errors_name_line_and_column(tmp_path):
    from robokit.collision import load_scene

    p = tmp_path / "scene.yaml"
    for text, where in (("obstacles:\n  - {type: box, size: [1, 1, 1]\n", "line 3, column 1"),
                        ("obstacles:\n  - type: box\n    size: [1, 1, 1]\n   pose: 3\n", "line 4, column 4")):
        p.write_text(text)
        with pytest.raises(robokit.InputError, match=where):
            load_scene(p)


# ------------------------------------------------------------------ class 7: measurements bounded, sizes checked
@pytest.mark.parametrize("scale, column", [(1e300, 5), (1e13, 4)])
def test_cli_absurd_measurements_exit_2(robots, tmp_path, scale, column):
    """Finite but absurd positions (1e300 m printed `RMS before: inf mm` and wrote a URDF; 1e13 m
    gave a meaningless fit): refused naming line and column, like a robot file's numbers."""
    robot = robots("rrr")
    rows = _rows(robot, scale=scale)
    p = _csv(tmp_path, [HEADER, *rows])
    out = tmp_path / "o.urdf"
    run = r2.run_limited("calibrate", "rrr", p, "-o", out)
    msg = assert_one_line_error(run, "d.csv", "line 2", "out of range")
    assert "column" in msg and not out.exists()


def test_measurements_within_the_bound_calibrate(robots, tmp_path):
    robot = robots("rrr")
    q = configurations(robot, 30, np.random.default_rng(1))
    res = robokit.calibrate(robot, q, robot.frame_pose(q)[:, :3, 3])
    assert res.rms_after < 1e-9


@pytest.mark.parametrize("call, argument", [
    (lambda r, q, m: robokit.calibrate(r, q, m * 1e300), "measured"),
    (lambda r, q, m: robokit.calibrate(r, q * 1e13, m), "q"),
    (lambda r, q, m: robokit.calibrate(r, q, m, max_iterations=2.5), "max_iterations"),
    (lambda r, q, m: robokit.calibrate(r, q, m, max_iterations=True), "max_iterations"),
    (lambda r, q, m: robokit.calibrate(r, q, m, orientation_weight=1e300), "orientation_weight"),
])
def test_calibrate_arguments_are_bounded(robots, call, argument):
    robot = robots("rrr")
    q = configurations(robot, 30, np.random.default_rng(2))
    with pytest.raises(robokit.InputError, match=rf"^{argument}\b"):
        call(robot, q, robot.frame_pose(q)[:, :3, 3])


@pytest.mark.parametrize("kwargs, argument", [
    ({"max_evaluations": -5}, "max_evaluations"),          # was scipy's ValueError
    ({"max_evaluations": 10**9}, "max_evaluations"),
    ({"tau_scale": 1e300}, "tau"),
    ({"ddq_scale": 1e14}, "ddq"),
    ({"nominal_scale": 1e300}, "nominal"),
])
def test_identify_dynamics_arguments_are_bounded(robots, kwargs, argument):
    robot = robots("rrr")
    q, dq, ddq = motions(robot, 60, np.random.default_rng(3))
    tau = robot.rnea(q, dq, ddq) * kwargs.pop("tau_scale", 1.0)
    ddq = ddq * kwargs.pop("ddq_scale", 1.0)
    if "nominal_scale" in kwargs:
        kwargs["nominal"] = np.ones(10 * robot.n) * kwargs.pop("nominal_scale")
    with pytest.raises(robokit.InputError, match=rf"^{argument}\b"):
        robokit.identify_dynamics(robot, q, dq, ddq, tau, physically_consistent=True, **kwargs)


def test_identify_dynamics_refuses_a_huge_regressor_before_building_it(robots, monkeypatch):
    import robokit.calibration.identification as ident

    robot = robots("rrr")
    q, dq, ddq = motions(robot, 60, np.random.default_rng(4))
    monkeypatch.setattr(ident, "MAX_REGRESSOR_BYTES", 1000)  # 60 samples of a 3-joint arm need 51,840 bytes
    monkeypatch.setattr(ident, "full_regressor", lambda *a, **k: pytest.fail("the regressor was built"))
    with pytest.raises(robokit.InputError, match="regressor of"):
        robokit.identify_dynamics(robot, q, dq, ddq, robot.rnea(q, dq, ddq))


@pytest.mark.parametrize("kwargs, argument", [
    ({"samples": 10**10}, "samples"),          # was a 74 GiB allocation
    ({"samples": MAX_SAMPLES + 1}, "samples"),
    ({"samples": 500.0}, "samples"),
    ({"duration": 1e300}, "duration"),
    ({"qd_max": 1e300}, "qd_max"),
    ({"qdd_max": [1.0, 1e13, 1.0]}, "qdd_max"),
    ({"max_evaluations": -5}, "max_evaluations"),
    ({"harmonics": 2.5}, "harmonics"),
    ({"qlim": [[-1e300, 1], [-1, 1], [-1, 1]]}, "qlim"),
])
def test_excitation_trajectory_arguments_are_checked_before_allocation(kwargs, argument):
    kw = {"duration": 5.0, "harmonics": 3, "max_evaluations": 5}
    kw.update(kwargs)
    with pytest.raises(robokit.InputError, match=rf"^{argument}\b"):
        robokit.excitation_trajectory("rrr", **kw)


def test_trajectory_generators_bound_their_sample_counts():
    """The same rule for the trajectory generators' integer sample counts (`t=N`)."""
    from robokit.trajectory import lspb_trajectory, quintic_trajectory

    for gen in (lspb_trajectory, quintic_trajectory):
        with pytest.raises(robokit.InputError, match=rf"^t: 10000000000 samples.*{MAX_SAMPLES}"):
            gen(0.0, 1.0, 2.0, t=10**10)
        assert len(gen(0.0, 1.0, 2.0, t=11).q) == 11


def test_write_then_read_round_trip(robots, tmp_path):
    """write_calibration_csv writes only what read_calibration_csv reads (repr of floats is a number)."""
    robot = robots("rrr")
    q = configurations(robot, 10, np.random.default_rng(5))
    T = robot.frame_pose(q)
    T[:, :3, 3] *= 1e-300  # tiny positions print as 1e-301: a number
    p = write_calibration_csv(tmp_path / "w.csv", q, T)
    q2, T2 = read_calibration_csv(p, 3)
    np.testing.assert_array_equal(q2, q)
    np.testing.assert_allclose(T2, T, atol=1e-9)
