"""``robokit validate MODEL``: the robot rows (kinematics, dynamics, ik) on one robot, loaded as every
command loads one — here Kinova's Gen3 from the maker's xacro file with its arguments (tests/data/kinova/
ros_kortex/SOURCE). Before, ``validate`` took no robot: ``robokit validate gen3.xacro`` exited 2
("unrecognized arguments")."""
import json
from pathlib import Path

from robokit.cli import main as cli_main

GEN3 = Path(__file__).resolve().parents[1] / "data" / "kinova" / "ros_kortex" / "kortex_description" / "robots" / "gen3.xacro"


def test_validate_a_xacro_robot_with_its_arguments(capsys):
    assert cli_main(["validate", str(GEN3), "--xacro-arg", "dof:=6", "--xacro-arg", "vision:=false", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    rows = out["rows"]
    assert out["passed"] and {r["model"] for r in rows} == {"gen3"}
    quantities = [r["quantity"] for r in rows]
    for q in ("fkin_space / fkin_body vs Pinocchio FK", "mass_matrix (PoE CRBA) vs pinocchio.crba",
              "forward_dynamics vs pinocchio.aba", "ik_analytic (calibrated spherical wrist): every solution vs Pinocchio FK",
              "ik_analytic: the generating q is among the solutions"):
        assert q in quantities, quantities
    assert all(r["cases"] > 0 and r["max_error"] <= r["tolerance"] for r in rows)


def test_an_arm_without_a_closed_form_has_no_ik_rows_and_says_why(capsys):
    assert cli_main(["validate", str(GEN3), "--xacro-arg", "vision:=false", "--area", "ik", "--area", "kinematics"]) == 0
    captured = capsys.readouterr()
    assert "gen3: no ik rows (no closed-form inverse kinematics: the arm has 7 joints" in captured.err
    assert "ik_analytic" not in captured.out and "3 passed, 0 failed" in captured.out


def test_options_that_need_a_model_and_areas_that_compare_none(capsys):
    assert cli_main(["validate", "--area", "spatial", "--tip", "tool0"]) == 2
    assert "apply to a MODEL" in capsys.readouterr().err
    assert cli_main(["validate", "rrr", "--area", "spatial"]) == 2
    assert "the areas that compare a robot (MODEL) are kinematics, dynamics, ik" in capsys.readouterr().err


def test_an_arm_without_mass_compares_what_is_defined(capsys):
    """KUKA's KR 6 R900 sixx file gives no <inertial> (tests/data/kuka/SOURCE): M is zero, so forward dynamics
    is not defined. The dynamics rows compare what is (inverse dynamics, M, gravity: all zero on both sides)
    and say why forward dynamics is left out; before MODEL came, such an arm could not be given, and with it
    the whole dynamics area raised ('the mass matrix is not positive definite') and failed."""
    kr6 = Path(__file__).resolve().parents[1] / "data" / "kuka" / "kuka_kr6_support" / "urdf" / "kr6r900sixx.xacro"
    assert cli_main(["validate", str(kr6), "--area", "dynamics", "--json"]) == 0
    rows = json.loads(capsys.readouterr().out)["rows"]
    quantities = [r["quantity"] for r in rows]
    assert "forward_dynamics vs pinocchio.aba" not in quantities and len(rows) == 4, quantities
    mass = next(r for r in rows if r["quantity"].startswith("mass_matrix"))
    assert mass["note"].startswith("M singular at 50 of 50 samples") and mass["passed"]
