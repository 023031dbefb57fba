"""Wrong answers reported as right: a URDF → DH table that is not exact, unphysical URDF data
accepted, mimic joints treated as independent."""
import re

import numpy as np
import pytest
from hardening_support import (
    assert_one_line_error,
    dh_fk_reference,
    joint,
    link,
    pendulum_urdf,
    tmp_leftovers,
    urdf_text,
)

import robokit


def _two_joint_urdf(rpy: str) -> str:
    """Two revolute z axes 0.5 m apart along x, the second twisted by ``rpy`` (nearly parallel)."""
    return urdf_text(
        links=[link("base"), link("l1", mass=1.0), link("l2", mass=1.0), link("tip")],
        joints=[joint("j1", "base", "l1"), joint("j2", "l1", "l2", xyz="0.5 0 0", rpy=rpy),
                joint("tj", "l2", "tip", "fixed", xyz="0.4 0 0")],
        name="twist")


def _independent_error(robot, table, n=60) -> float:
    """Largest entry-wise error of the DH table's FK (composed here) against Pinocchio's."""
    rng = np.random.default_rng(7)
    err = 0.0
    for _ in range(n):
        q = rng.uniform(-3, 3, robot.n)
        err = max(err, float(np.abs(dh_fk_reference(table, q) - robot.frame_pose(q)).max()))
    return err


# twists of 1e-8 rad between consecutive axes: about the common normal (an exact table exists),
# about the axis joining them (the axes meet 5e7 m away: no exact double-precision table), both,
# and the second axis flipped by nearly π
TWISTS = ["1e-8 0 0", "0 1e-8 0", "1e-8 1e-8 0", "0 3.14159264 0", "0 1e-12 0"]


@pytest.mark.parametrize("convention", ["standard", "modified"])
@pytest.mark.parametrize("rpy", TWISTS)
def test_urdf_to_dh_on_nearly_parallel_axes_reports_an_honest_residual(rpy, convention, write):
    robot = robokit.load(write("twist.urdf", _two_joint_urdf(rpy)))
    res = robokit.dh_from_urdf(robot, convention)
    t = res.table
    numbers = [v for ln in t.links for v in (ln.a, ln.alpha, ln.d, ln.theta)]
    assert np.isfinite(numbers).all() and np.isfinite(t.base).all() and np.isfinite(t.tool).all()
    assert np.isfinite(res.residual)
    err = _independent_error(robot, t)
    if err > 1e-9:
        assert not res.exact and res.residual > 1e-9, (err, res.residual)
    if res.exact:
        assert err <= 1e-9, (err, res.residual)
    # the reported residual is a real measurement, not a placeholder: same order as ours
    assert res.residual >= 0.1 * err


@pytest.mark.parametrize("rpy", ["0 1e-8 0", "1e-8 0 0"])
def test_convert_urdf_prints_table_and_true_residual_and_refuses_inexact_yaml(rpy, write, tmp_path, main_cli):
    src = write("twist.urdf", _two_joint_urdf(rpy))
    robot = robokit.load(src)
    err = _independent_error(robot, robokit.dh_from_urdf(robot).table)
    r = main_cli("convert", src)
    assert r.rc == 0, r.err
    assert "nan" not in r.out.lower()
    m = re.search(r"FK residual vs the URDF: ([0-9.eE+-]+)", r.out)
    assert m, r.out
    printed = float(m.group(1))
    out = tmp_path / "twist.yaml"
    ry = main_cli("convert", src, "-o", out)
    if err > 1e-9:  # inexact: the printed residual says so; the YAML is refused and not written
        assert printed > 1e-9 and "NOT exact" in r.out
        assert_one_line_error(ry, "twist", "1e-9")
        assert not out.exists()
    else:
        assert printed <= 1e-9
        assert ry.rc == 0, ry.err
        back = robokit.DHTable.from_yaml(out)
        assert _independent_error(robot, back) <= 1e-9
    assert tmp_leftovers(tmp_path) == []


UNPHYSICAL = {
    "negative_mass": ({"mass": "-1"}, ["'arm'", "mass"]),
    "nan_mass": ({"mass": "nan"}, ["'arm'", "NaN"]),
    "inf_mass": ({"mass": "inf"}, ["'arm'", "mass"]),
    "non_psd_inertia": ({"inertia": "1 1 1 5 0 0"}, ["'arm'", "positive semi-definite"]),
    "nan_inertia": ({"inertia": "nan 1 1 0 0 0"}, ["'arm'", "inertia"]),
}


@pytest.mark.parametrize("case", sorted(UNPHYSICAL))
def test_unphysical_urdf_inertial_refused_naming_file_and_link(case, write, tmp_path, main_cli):
    kw, names = UNPHYSICAL[case]
    src = write(f"{case}.urdf", pendulum_urdf(**kw))
    with pytest.raises(robokit.InputError) as ei:
        robokit.load(src)
    assert str(src) in str(ei.value) and "'arm'" in str(ei.value)
    out = tmp_path / "out.json"
    assert_one_line_error(main_cli("convert", src, "-o", out), f"{case}.urdf", *names)
    assert not out.exists()


JOINT_FAULTS = {
    "zero_axis": (lambda t: t.replace('<axis xyz="0 -1 0"/>', '<axis xyz="0 0 0"/>'), "axis is zero"),
    "tiny_axis": (lambda t: t.replace('<axis xyz="0 -1 0"/>', '<axis xyz="0 1e-12 0"/>'), "axis is zero"),
    "lower_above_upper": (lambda t: t.replace('lower="-3" upper="3"', 'lower="2" upper="1"'), "lower limit 2"),
    "nan_limit": (lambda t: t.replace('lower="-3"', 'lower="nan"'), "NaN"),
    "negative_effort": (lambda t: t.replace('effort="10"', 'effort="-1"'), "effort"),
}


@pytest.mark.parametrize("case", sorted(JOINT_FAULTS))
def test_bad_urdf_joint_axis_or_limits_refused_naming_file_and_joint(case, write, tmp_path, main_cli):
    mutate, what = JOINT_FAULTS[case]
    text = mutate(pendulum_urdf())
    assert text != pendulum_urdf()
    src = write(f"{case}.urdf", text)
    out = tmp_path / "out.json"
    assert_one_line_error(main_cli("convert", src, "-o", out), f"{case}.urdf", "'shoulder'", what)
    assert not out.exists()


def _mimic_urdf(on_chain: bool) -> str:
    links = [link("base"), link("a", mass=1.0), link("b", mass=1.0), link("c", mass=1.0), link("finger", mass=0.1)]
    joints = [joint("j1", "base", "a"), joint("j2", "a", "b", xyz="1 0 0"), joint("j3", "b", "c", xyz="1 0 0")]
    if on_chain:
        joints[2] = joint("j3", "b", "c", xyz="1 0 0", extra='<mimic joint="j2" multiplier="1" offset="0"/>')
        joints.append(joint("fj", "a", "finger", xyz="0 0.1 0"))
    else:
        joints.append(joint("fj", "a", "finger", xyz="0 0.1 0", extra='<mimic joint="j1"/>'))
    return urdf_text(links=links, joints=joints, name="mimicbot")


def test_mimic_joint_on_the_chain_refused(write, tmp_path, main_cli):
    src = write("mimic_on.urdf", _mimic_urdf(True))
    with pytest.raises(robokit.InputError, match="mimic"):
        robokit.load(src, tip="c")
    out = tmp_path / "out.json"
    assert_one_line_error(main_cli("convert", src, "--tip", "c", "-o", out), "mimic_on.urdf", "'j3'", "'j2'")
    assert not out.exists()


def test_mimic_joint_off_the_chain_locked_with_a_note(write, tmp_path, main_cli):
    src = write("mimic_off.urdf", _mimic_urdf(False))
    with pytest.warns(robokit.errors.RobokitWarning, match="mimic"):
        robot = robokit.load(src, tip="c")
    assert list(robot.joint_names) == ["j1", "j2", "j3"]
    assert "fj" in robot.locked_joints
    # the chain is three parallel z axes 1 m apart: planar FK closed form
    q = np.array([0.3, -0.8, 0.5])
    x = np.cos(q[0]) + np.cos(q[0] + q[1])
    y = np.sin(q[0]) + np.sin(q[0] + q[1])
    np.testing.assert_allclose(robot.frame_pose(q)[:3, 3], [x, y, 0], atol=1e-12)
    out = tmp_path / "out.json"
    r = main_cli("convert", src, "--tip", "c", "-o", out)
    assert r.rc == 0, r.err
    assert any(ln.startswith("robokit: note:") and "mimic" in ln and "fj" in ln for ln in r.err.splitlines())
    assert out.exists()
