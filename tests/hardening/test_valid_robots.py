"""Valid inputs that used to fail: the one-joint robot, YAML 1.2 numbers, the vehicle controllers."""
import json
import math

import numpy as np
import pytest
from hardening_support import (
    PEND_G,
    PEND_L,
    PEND_LC,
    PEND_M,
    PENDULUM_YAML,
    assert_one_line_error,
    pendulum_urdf,
    run_cli,
    tmp_leftovers,
)

import robokit

PEND_IYY = 0.01  # the link's inertia about the joint axis direction, at its COM (both files)
THETAS = np.array([-2.0, -0.7, 0.0, 0.4, 1.3, 2.9])


def _check_pendulum(robot):
    """FK, Jacobian, gravity torque and mass of a pendulum robot against the closed forms."""
    assert robot.n == 1
    for th in THETAS:
        c, s = math.cos(th), math.sin(th)
        T = robot.frame_pose([th])
        np.testing.assert_allclose(T[:3, 3], [PEND_L * c, 0.0, PEND_L * s], atol=1e-12)
        # tool x axis along the link: (cos θ, 0, sin θ)
        np.testing.assert_allclose(T[:3, 0], [c, 0.0, s], atol=1e-12)
        # geometric Jacobian (ω; v of the tip), base axes: ω = −ŷ, v = ω × p
        J = robot.jacobian([th], reference="local_world_aligned")
        np.testing.assert_allclose(J[:, 0], [0, -1, 0, -PEND_L * s, 0, PEND_L * c], atol=1e-12)
        # gravity torque of a link whose COM is l_c out: m g l_c cos θ
        np.testing.assert_allclose(robot.gravity_torques([th]), [PEND_M * PEND_G * PEND_LC * c], atol=1e-12)
        np.testing.assert_allclose(robot.rnea([th], [0.0], [0.0]), [PEND_M * PEND_G * PEND_LC * c], atol=1e-12)
        # mass about the joint: I_yy + m l_c² (parallel axes)
        np.testing.assert_allclose(robot.crba([th]), [[PEND_IYY + PEND_M * PEND_LC**2]], atol=1e-12)


@pytest.mark.parametrize("kind", ["yaml", "urdf"])
def test_one_joint_robot_loads_views_and_converts(kind, write, tmp_path):
    src = write("pendulum.yaml", PENDULUM_YAML) if kind == "yaml" else write("pendulum.urdf", pendulum_urdf())
    robot = robokit.load(src)
    _check_pendulum(robot)

    page = tmp_path / "page.html"
    r = run_cli("view", src, "-o", page)
    assert r.rc == 0, r.err
    assert "Traceback" not in r.err
    html = page.read_text(encoding="utf-8")
    assert "<html" in html.lower() and len(html) > 1000

    outs = ["robot.urdf"] if kind == "yaml" else ["robot.json", "robot.yaml"]
    for name in outs:
        out = tmp_path / name
        r = run_cli("convert", src, "-o", out)
        assert r.rc == 0, r.err
        if name.endswith(".json"):
            poe = json.loads(out.read_text())
            M = np.array(poe["M"])
            np.testing.assert_allclose(M[:3, 3], [PEND_L, 0, 0], atol=1e-12)
            S = np.array(poe["Slist"])
            assert S.shape == (6, 1)
            np.testing.assert_allclose(S[:, 0], [0, -1, 0, 0, 0, 0], atol=1e-12)  # axis −ŷ through the origin
        else:
            _check_pendulum(robokit.load(out))  # the converted file is the same robot
    assert tmp_leftovers(tmp_path) == []


def test_one_joint_urdf_prints_its_dh_table(write):
    r = run_cli("convert", write("pendulum.urdf", pendulum_urdf()))
    assert r.rc == 0, r.err
    assert "nan" not in r.out.lower()
    assert "FK residual" in r.out


def test_yaml_exponent_numbers_read_as_floats(write):
    from robokit._yaml import load_yaml_text

    doc = load_yaml_text("a: 2e-4\nb: 1.5E3\nc: 1e308\nd: -1.5e+3\n")
    assert doc == {"a": 2e-4, "b": 1500.0, "c": 1e308, "d": -1500.0}
    assert all(type(v) is float for v in doc.values())
    text = PENDULUM_YAML.replace("a: 0.5,", "a: 2e-4,").replace("d: 0,", "d: 1.5E3,")
    table = robokit.DHTable.from_yaml(write("numbers.yaml", text))
    link = table.links[0]
    assert isinstance(link.a, float) and link.a == 2e-4
    assert link.d == 1500.0


def test_yaml_1e308_length_or_mass_refused_by_name_not_turned_into_nan(write, main_cli):
    # 1e308 is a float, but a link that long (or that heavy) makes FK and gravity overflow to inf/NaN
    for key, old, new in (("a", "a: 0.5,", "a: 1e308,"), ("mass", "mass: 2.0,", "mass: 1e308,")):
        p = write(f"big_{key}.yaml", PENDULUM_YAML.replace(old, new))
        with pytest.raises(robokit.InputError, match=rf"link 1, key '{key}'.*out of range"):
            robokit.load(p)
        assert_one_line_error(main_cli("convert", p, "-o", p.with_suffix(".urdf")), p.name, f"'{key}'")


def test_yaml_number_beyond_double_refused_as_not_finite(write):
    p = write("huge.yaml", PENDULUM_YAML.replace("a: 0.5,", "a: 1e309,"))
    with pytest.raises(robokit.InputError) as ei:
        robokit.DHTable.from_yaml(p)
    msg = str(ei.value)
    assert str(p) in msg and "link 1" in msg and "'a'" in msg and "finite" in msg
    assert_one_line_error(run_cli("convert", p, "-o", p.with_suffix(".urdf")), "huge.yaml", "'a'")
    assert not p.with_suffix(".urdf").exists()


def test_pure_pursuit_with_kh_2_starting_45_degrees_off_runs():
    # target runs along the x axis at 1 m/s; the vehicle starts behind it, heading 45° off the path
    pp = robokit.mobile.PurePursuit(lambda t: (2.0 + t, 0.0), d_star=1.0, Kh=2.0)
    model = robokit.mobile.BicycleModel(L=1.0)
    run = robokit.mobile.run_vehicle(model, pp, [0.0, 0.0, math.radians(45)], T=20.0, dt=0.05)
    assert np.isfinite(run.x).all() and np.isfinite(run.u).all()
    # every input respects the limits, and the vehicle ends up chasing the target along the path
    assert np.all(np.abs(run.u[:, 1]) <= model.steer_max + 1e-15)
    assert np.all(np.abs(run.u[:, 0]) <= model.speed_max + 1e-15)
    x_end = run.x[-1]
    assert abs(x_end[1]) < 0.1 and abs(robokit.mobile.angdiff(x_end[2])) < 0.1
    assert abs(pp.error(run.t[-1], x_end)) < 0.2


@pytest.mark.parametrize("gamma", [math.pi / 2, -math.pi / 2])
def test_bicycle_limit_clips_steering_of_plus_minus_pi_over_2(gamma):
    model = robokit.mobile.BicycleModel(L=1.0, steer_max=math.radians(60))
    v, g = model.limit([1.0, gamma])
    assert v == 1.0 and g == math.copysign(model.steer_max, gamma)
    x1 = model.step([0.0, 0.0, 0.0], [1.0, gamma], 0.1)
    assert np.isfinite(x1).all()
    # the exact arc at the clipped angle: radius L / tan(60°)
    R = 1.0 / math.tan(model.steer_max)
    w = math.copysign(1.0 / R, gamma)
    np.testing.assert_allclose(x1, [R * math.sin(0.1 / R), math.copysign(R * (1 - math.cos(0.1 / R)), gamma), w * 0.1],
                               atol=1e-12)
