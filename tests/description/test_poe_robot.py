"""URDF → PoE export, the Robot type and `robokit convert`, against Pinocchio.

PoE forward kinematics is recomputed here from the exported screws with robokit's
matrix_exp_6 (itself checked against pinocchio.exp6), and the Newton–Euler torques from
Mlist/Glist with the `modern_robotics` package (an independent implementation).
"""
import json
import subprocess
import sys

import numpy as np
import pinocchio as pin
import pytest

import robokit
from robokit.cli import main as cli_main

ALL = ["twolink", "rrr", "puma560", "ur5", "panda", "z1", "xarm7", "kinova"]


def poe_fk(poe, theta):
    T = np.eye(4)
    for i, th in enumerate(theta):
        T = T @ robokit.matrix_exp_6(robokit.vec_to_se3(poe.Slist[:, i] * th))
    return T @ poe.M


@pytest.mark.parametrize("name", ALL)
def test_poe_fk_equals_pinocchio(name, robots):
    r = robots(name)
    rng = np.random.default_rng(0)
    for _ in range(100):
        th = r.random_configuration(rng)
        assert np.abs(poe_fk(r.poe, th) - r.frame_pose(th)).max() < 1e-9
        Tb = r.poe.M.copy()
        for i, t in enumerate(th):
            Tb = Tb @ robokit.matrix_exp_6(robokit.vec_to_se3(r.poe.Blist[:, i] * t))
        assert np.abs(Tb - r.frame_pose(th)).max() < 1e-9


@pytest.mark.parametrize("name", ALL)
def test_poe_newton_euler_equals_rnea(name, robots):
    mr = pytest.importorskip("modern_robotics")
    r = robots(name)
    rng = np.random.default_rng(1)
    for _ in range(20):
        th, dth, ddth = r.random_configuration(rng), rng.normal(size=r.n), rng.normal(size=r.n)
        tau = r.rnea(th, dth, ddth)
        ref = mr.InverseDynamics(th, dth, ddth, r.gravity, np.zeros(6), list(r.poe.Mlist), list(r.poe.Glist), r.poe.Slist)
        assert np.abs(tau - ref).max() <= 1e-9 * max(1.0, np.abs(tau).max())


def test_poe_json_armature_with_newton_euler_equals_rnea(tmp_path, capsys):
    """talos_arm's SRDF gives six joints a reflected rotor inertia of 0.1 (example-robot-data's loader puts it
    in model.armature). The JSON's Mlist/Glist hold the rigid bodies: Newton-Euler from them (modern_robotics)
    equals Pinocchio's rnea on example-robot-data's own model with the armature set to zero, and with the
    JSON's 'armature' times q-ddot added equals rnea with it; convert says so in a note. The JSON had no
    armature (Newton-Euler from it was off by 0.1 q-ddot per joint) while the loader's note said it was in
    the RNEA."""
    mr = pytest.importorskip("modern_robotics")
    erd = pytest.importorskip("example_robot_data")
    js = tmp_path / "talos_arm.json"
    rc, _, err = _cli(["convert", "talos_arm", "-o", str(js)], capsys)
    assert rc == 0 and "'armature'" in err
    d = json.loads(js.read_text())
    ref = erd.load("talos_arm").model
    assert [ref.names[j] for j in range(1, ref.njoints)] == d["joint_names"]
    np.testing.assert_array_equal(d["armature"], ref.armature)
    assert np.count_nonzero(ref.armature) == 6
    bare = ref.copy()
    bare.armature[:] = 0.0
    Mlist, Glist, Slist = [np.array(m) for m in d["Mlist"]], [np.array(g) for g in d["Glist"]], np.array(d["Slist"])
    rng = np.random.default_rng(3)
    for _ in range(5):
        q, dq, ddq = rng.uniform(-1, 1, 7), rng.normal(size=7), rng.normal(size=7)
        ne = mr.InverseDynamics(q, dq, ddq, ref.gravity.linear, np.zeros(6), Mlist, Glist, Slist)
        tau = pin.rnea(ref, ref.createData(), q, dq, ddq)
        assert np.abs(ne - pin.rnea(bare, bare.createData(), q, dq, ddq)).max() <= 1e-9 * max(1.0, np.abs(tau).max())
        assert np.abs(ne + np.array(d["armature"]) * ddq - tau).max() <= 1e-9 * max(1.0, np.abs(tau).max())


def test_dh_round_trip_yaml_urdf_poe_fk(robots):
    for name in ("twolink", "rrr", "puma560"):
        r = robots(name)
        rng = np.random.default_rng(2)
        for _ in range(100):
            th = r.random_configuration(rng)
            assert np.abs(poe_fk(r.poe, th) - r.dh.fk(th)).max() < 1e-9


def test_robot_methods_match_raw_pinocchio(robots):
    r = robots("kinova")  # continuous joints: nq = 9, nv = 6
    assert r.model.nq == 9 and r.n == 6
    rng = np.random.default_rng(3)
    th = r.random_configuration(rng)
    q = r.q_pin(th)
    assert np.allclose(r.q_from_pin(q), th)
    data = r.model.createData()
    pin.framesForwardKinematics(r.model, data, q)
    assert np.allclose(r.frame_pose(th), data.oMf[r.tip_id].homogeneous)
    J = pin.computeFrameJacobian(r.model, data, q, r.tip_id, pin.ReferenceFrame.LOCAL)
    assert np.allclose(r.jacobian(th, reference="local"), np.vstack([J[3:], J[:3]]))
    dth, tau = rng.normal(size=6), rng.normal(size=6)
    assert np.allclose(r.aba(th, dth, tau), pin.aba(r.model, data, q, dth, tau))
    M = r.crba(th)
    assert np.allclose(M, M.T) and np.allclose(M @ r.aba(th, dth, tau) + r.nonlinear_effects(th, dth), tau)
    # finite differences: the world-aligned Jacobian's v rows are d(position)/dθ
    Jl = r.jacobian(th, reference="local_world_aligned")
    h = 1e-6
    for j in range(6):
        e = np.zeros(6)
        e[j] = h
        dp = (r.frame_pose(th + e)[:3, 3] - r.frame_pose(th - e)[:3, 3]) / (2 * h)
        assert np.allclose(Jl[3:, j], dp, atol=1e-7)


def test_locked_fingers_and_default_tips(robots):
    panda = robots("panda")
    assert panda.n == 7 and panda.tip == "panda_hand_tcp"
    assert set(panda.locked_joints) == {"panda_finger_joint1", "panda_finger_joint2"}
    assert robots("ur5").tip == "tool0" and robots("puma560").tip == "tool"
    with pytest.raises(ValueError, match="no frame"):
        robokit.load("ur5", tip="nonexistent_frame")
    with pytest.raises(ValueError, match="unknown robot"):
        robokit.load("no_such_robot")


FLOATING_URDF = """<?xml version="1.0"?>
<robot name="flying">
  <link name="world"/>
  <link name="body"><inertial><mass value="1"/><inertia ixx="1" ixy="0" ixz="0" iyy="1" iyz="0" izz="1"/></inertial></link>
  <joint name="float" type="floating"><parent link="world"/><child link="body"/></joint>
  <link name="arm"><inertial><mass value="1"/><inertia ixx="1" ixy="0" ixz="0" iyy="1" iyz="0" izz="1"/></inertial></link>
  <joint name="j1" type="revolute"><parent link="body"/><child link="arm"/><axis xyz="0 0 1"/>
    <limit lower="-1" upper="1" effort="1" velocity="1"/></joint>
</robot>
"""


def _cli(args, capsys):
    rc = cli_main(args)
    out, err = capsys.readouterr()
    return rc, out, err


def test_convert_documented_commands(tmp_path, capsys):
    out = tmp_path / "p.urdf"
    rc, _, _ = _cli(["convert", str(robokit.description.models_dir() / "puma560.yaml"), "-o", str(out)], capsys)
    assert rc == 0 and pin.buildModelFromUrdf(str(out)).nq == 6
    js = tmp_path / "ur5.json"
    rc, _, _ = _cli(["convert", "ur5", "-o", str(js)], capsys)
    assert rc == 0
    d = json.loads(js.read_text())
    assert set(d) == {"M", "Slist", "Blist", "Mlist", "Glist", "joint_names", "tip", "armature"}
    assert d["armature"] == [0.0] * 6
    assert np.array(d["Slist"]).shape == (6, 6) and len(d["Mlist"]) == 7 and d["tip"] == "tool0"
    rc, _, err = _cli(["convert", "panda", "-o", str(tmp_path / "panda.json")], capsys)
    assert rc == 0 and "panda_finger_joint1" in err


def _bad_cases(tmp_path):
    cases = []
    good = (robokit.description.models_dir() / "twolink.yaml").read_text()
    for label, text in [
        ("missing key", good.replace("a: 0.8, ", "")),
        ("unknown key", good.replace("theta: 0, qlim", "thetta: 0, theta: 0, qlim", 1)),
        ("wrong joint type", good.replace("joint: R", "joint: Q", 1)),
        ("negative mass", good.replace("mass: 2.0", "mass: -2.0")),
        ("non-PD inertia", good.replace("mass: 2.0, com: [0, 0, 0]", "mass: 2.0, com: [0, 0, 0], inertia: [1, 1, -3, 0, 0, 0]")),
        ("wrong list length", good.replace("com: [0, 0, 0]", "com: [0, 0]", 1)),
    ]:
        p = tmp_path / f"{label.replace(' ', '_')}.yaml"
        p.write_text(text)
        cases.append((label, [str(p)], ".urdf"))
    broken = tmp_path / "broken.urdf"
    broken.write_text("<robot name='x'><link name='a'></robot")
    cases.append(("URDF that does not parse", [str(broken)], ".json"))
    flying = tmp_path / "flying.urdf"
    flying.write_text(FLOATING_URDF)
    cases.append(("floating base", [str(flying), "--tip", "arm"], ".json"))
    cases.append(("tip that does not exist", ["ur5", "--tip", "no_such_link"], ".json"))
    cases.append(("unknown model", ["no_such_robot"], ".json"))
    cases.append(("wrong output type", ["ur5"], ".txt"))
    return cases


def test_bad_inputs_exit_2_one_line_nothing_written(tmp_path, capsys):
    for label, args, suffix in _bad_cases(tmp_path):
        out = tmp_path / f"out_{label.replace(' ', '_')}{suffix}"
        rc, stdout, err = _cli(["convert", *args, "-o", str(out)], capsys)
        assert rc == 2, label
        assert err.count("\n") == 1 and err.startswith("robokit: error:"), (label, err)
        assert not out.exists(), label
        assert not list(tmp_path.glob(f".{out.name}*")), label  # no temporary left behind
    rc, _, err = _cli(["convert", "ur5", "-o", str(tmp_path / "missing_dir" / "x.json")], capsys)
    assert rc == 2 and "does not exist" in err


def test_console_script_subprocess(tmp_path):
    exe = [sys.executable, "-m", "robokit.cli"]
    res = subprocess.run(exe + ["convert", "no_such_robot", "-o", str(tmp_path / "x.json")],
                         capture_output=True, text=True, timeout=120)
    assert res.returncode == 2 and res.stderr.count("\n") == 1 and "Traceback" not in res.stderr
    assert not (tmp_path / "x.json").exists()


def test_poe_params_built_without_armature_have_none():
    """``PoEParams`` gained ``armature``; one built as before (nine fields) has zeros there, and equals the
    loaded robot's own where that robot has no reflected rotor inertia."""
    from robokit.description.poe import PoEParams

    p = robokit.load("puma560").poe
    q = PoEParams(p.M, p.Slist, p.Blist, p.Mlist, p.Glist, p.joint_names, p.tip, p.qlim, p.gravity)
    assert q.armature.shape == (6,) and not q.armature.any()
    assert q.to_json_dict() == p.to_json_dict()
