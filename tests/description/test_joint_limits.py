"""Joint limits beyond ±1e12 (issue 39, class 2): robot files write "unlimited" as ±1e16, ±3.4e38,
±1e308. One rule (robokit.description.limits.unbounded_limits): such a side means no limit (±inf, as
Pinocchio writes a joint without limits), with one note; a limit on the wrong side beyond 1e12
leaves no range and is refused. Was: OverflowError in Robot.random_configuration, exit 3 from
codegen, view and teach. Checked against the closed form of the one-joint pendulum (the limits
change nothing else) and, for the CLI, under an address-space limit."""
import math
import sys
import warnings
from pathlib import Path

import numpy as np
import pytest


import hardening_support as hs  # noqa: E402
import limited_cli as r2  # noqa: E402

import robokit  # noqa: E402
from robokit.errors import RobokitWarning  # noqa: E402


def _pendulum(tmp_path, lower, upper, jtype="revolute", name="pendulum"):
    text = hs.urdf_text(
        links=[hs.link("base"), hs.link("arm", mass=str(hs.PEND_M), com=f"{hs.PEND_LC} 0 0"), hs.link("tip")],
        joints=[hs.joint("shoulder", "base", "arm", jtype=jtype, axis="0 -1 0", lower=lower, upper=upper),
                hs.joint("tip_joint", "arm", "tip", "fixed", xyz=f"{hs.PEND_L} 0 0")], name=name)
    p = tmp_path / f"{name}.urdf"
    p.write_text(text)
    return p


def _mjcf(tmp_path, lo, hi):
    p = tmp_path / "hinge.xml"
    p.write_text(f'<mujoco model="hinge"><compiler angle="radian"/><worldbody><body name="arm">'
                 f'<joint name="shoulder" type="hinge" axis="0 -1 0" limited="true" range="{lo} {hi}"/>'
                 f'<geom type="capsule" fromto="0 0 0 0.5 0 0" size="0.02" mass="2"/></body></worldbody></mujoco>')
    return p


@pytest.mark.parametrize("lower, upper, expected", [
    ("-1e308", "1e308", (-math.inf, math.inf)),
    ("-1e16", "1e16", (-math.inf, math.inf)),           # the usual URDF "unlimited"
    ("-3.4e38", "1.5", (-math.inf, 1.5)),               # one side only
    ("-0.5", "1.7976931348623157e308", (-0.5, math.inf)),
])
def test_huge_limits_mean_no_limit_with_one_note(tmp_path, lower, upper, expected):
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        robot = robokit.load(_pendulum(tmp_path, lower, upper))
    notes = [str(w.message) for w in caught if issubclass(w.category, RobokitWarning) and "no limit" in str(w.message)]
    assert len(notes) == 1 and "'shoulder'" in notes[0] and "pendulum.urdf" in notes[0]
    assert tuple(robot.qlim[0]) == expected
    assert tuple(robot.model.lowerPositionLimit) + tuple(robot.model.upperPositionLimit) == expected
    rng = np.random.default_rng(0)
    for _ in range(20):  # was: OverflowError (the range 2e308 is not a double)
        q = robot.random_configuration(rng)
        lo = expected[0] if math.isfinite(expected[0]) else -math.pi
        hi = expected[1] if math.isfinite(expected[1]) else math.pi
        assert np.isfinite(q).all() and lo <= q[0] <= hi
        # the limits change nothing else: the tip is the closed form (l cos θ, 0, l sin θ)
        np.testing.assert_allclose(robot.frame_pose(q)[:3, 3], [hs.PEND_L * math.cos(q[0]), 0.0,
                                                                hs.PEND_L * math.sin(q[0])], atol=1e-12)


def test_limits_within_the_bound_are_kept(tmp_path):
    robot = robokit.load(_pendulum(tmp_path, "-1e12", "1e11"))
    assert tuple(robot.qlim[0]) == (-1e12, 1e11) and robot.notes == ()


def test_mjcf_huge_range_follows_the_same_rule(tmp_path):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        robot = robokit.load(_mjcf(tmp_path, "-1e300", "1e300"))
    assert tuple(robot.qlim[0]) == (-math.inf, math.inf)
    assert any("no limit" in n for n in robot.notes)
    assert np.isfinite(robot.random_configuration(0)).all()


@pytest.mark.parametrize("lower, upper, side", [("1e300", "1e308", "lower"), ("-1e308", "-1e300", "upper")])
def test_a_limit_beyond_the_bound_on_the_wrong_side_is_refused(tmp_path, lower, upper, side):
    with pytest.raises(robokit.InputError, match=rf"pendulum.urdf: joint 'shoulder': {side} limit .* out of range"):
        robokit.load(_pendulum(tmp_path, lower, upper))


def test_cli_commands_on_huge_limits_succeed_with_one_note(tmp_path):
    """codegen, view and teach exited 3 (OverflowError); convert and plan accepted the file
    silently. Now all succeed and say once what they did."""
    big = _pendulum(tmp_path, "-1e308", "1e308", name="big")
    prismatic = _pendulum(tmp_path, "-1e16", "1e16", jtype="prismatic", name="slider")
    out = tmp_path / "c"
    out.mkdir()
    argvs = [["codegen", big, "-o", out], ["codegen", big, "-o", out, "--float32"],
             ["view", big, "-o", tmp_path / "v.html"], ["teach", big, "-o", tmp_path / "t.html"],
             ["convert", big, "-o", tmp_path / "b.json"], ["convert", big, "-o", tmp_path / "b.xml"],
             ["plan", big, "--start", "0", "--goal", "1", "-o", tmp_path / "p.csv"],
             ["view", prismatic, "-o", tmp_path / "s.html"], ["codegen", prismatic, "-o", out]]
    for argv, run in zip(argvs, r2.run_many(argvs)):
        assert run.rc == 0, (argv, run.err)
        notes = [ln for ln in run.err_lines if ln.startswith("robokit: note:") and "no limit" in ln]
        assert len(notes) == 1, (argv, run.err)
        assert "error" not in run.err and "Traceback" not in run.err and "overflow" not in run.err, (argv, run.err)
    header = (out / "big.h").read_text()  # the float32 run wrote last: unlimited is HUGE_VALF
    assert "#define big_JOINT0_LOWER (-HUGE_VALF)" in header and "#define big_JOINT0_UPPER HUGE_VALF" in header
    assert 'limited="false"' in (tmp_path / "b.xml").read_text()


def test_dh_joint_without_qlim_is_unlimited(tmp_path):
    """A DH file's joint without ``qlim`` is unlimited: ``robot.qlim`` is ±inf there (it was ±π for R and
    ±1 m for P, the numbers the generated URDF needs), so ``solve_ik`` reaches a pose that needs the
    prismatic joint at 1.6 m (it was clipped to 1 m and failed). The pose comes from the DH product
    written out here (modified convention, Craig) and the answer is checked with Pinocchio's FK of the
    generated URDF, whose frames ignore limits."""
    import pinocchio as pin

    path = tmp_path / "slider.yaml"
    path.write_text("name: slider\nconvention: modified\nangle_unit: rad\nlinks:\n"
                    "  - {joint: R, a: 0, alpha: 0, d: 0.3, theta: 0}\n"
                    "  - {joint: P, a: 0.2, alpha: 1.5707963267948966, d: 0.1, theta: 0}\n"
                    "  - {joint: R, a: 0.3, alpha: -1.5707963267948966, d: 0, theta: 0, qlim: [-1, 1]}\n")
    robot = robokit.load(str(path))
    np.testing.assert_array_equal(robot.qlim[:2], [[-np.inf, np.inf], [-np.inf, np.inf]])
    np.testing.assert_array_equal(robot.qlim[2], [-1.0, 1.0])

    def rx(t):
        c, s = np.cos(t), np.sin(t)
        return np.array([[1, 0, 0, 0], [0, c, -s, 0], [0, s, c, 0], [0, 0, 0, 1.0]])

    def rz(t):
        c, s = np.cos(t), np.sin(t)
        return np.array([[c, -s, 0, 0], [s, c, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1.0]])

    def tr(x, z):
        T = np.eye(4)
        T[0, 3], T[2, 3] = x, z
        return T

    q = np.array([0.4, 1.6, -0.5])
    T = (rx(0) @ tr(0, 0) @ rz(q[0]) @ tr(0, 0.3)) @ (rx(np.pi / 2) @ tr(0.2, 0) @ tr(0, 0.1 + q[1])) \
        @ (rx(-np.pi / 2) @ tr(0.3, 0) @ rz(q[2]))
    np.testing.assert_allclose(robot.frame_pose(q), T, atol=1e-12)
    res = robokit.solve_ik(robot, T, q + 0.05)
    assert res.success
    urdf = tmp_path / "slider.urdf"
    urdf.write_text(robokit.description.urdf_gen.urdf_from_dh(robot.dh))
    model = pin.buildModelFromUrdf(str(urdf))
    data = model.createData()
    pin.framesForwardKinematics(model, data, res.q)
    np.testing.assert_allclose(data.oMf[model.getFrameId("tool")].homogeneous, T, atol=1e-9)
