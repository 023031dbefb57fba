"""An immutable Robot: assignment raises, public arrays are read-only, changed copies come from
``with_limits``/``with_tool`` with their own RobotSpec — and every robot, of every format, calibrated
or changed, is rebuilt by ``robokit.load(robot.spec)`` in a fresh process with the same kinematics and
dynamics (compared with the original's Pinocchio answers in this process)."""
import json
import pickle
import subprocess
import sys
import warnings

import numpy as np
import pytest

import robokit
from shared_robots import robot as shared_robot
from robokit.calibration.chain import chain_from_robot
from robokit.description import models_dir
from robokit.errors import InputError, RobokitWarning

from tests.description.test_spec import write_mjcf, write_xacro_package

DATA = __import__("pathlib").Path(__file__).resolve().parents[1] / "data"
T_TOOL = np.array([[0.0, -1.0, 0.0, 0.01], [1.0, 0.0, 0.0, 0.02], [0.0, 0.0, 1.0, 0.15], [0.0, 0.0, 0.0, 1.0]])

PUBLIC = ["name", "model", "data", "visual_model", "collision_model", "tip", "tip_id", "dh", "poe", "n",
          "joint_names", "qlim", "gravity", "configurations", "locked_joints", "source", "frame_names", "notes",
          "spec", "nominal", "contact_rules", "brand_new_attribute"]


def test_assignment_raises_naming_the_attribute_and_the_copies():
    robot = robokit.load("puma560")
    for name in PUBLIC:
        with pytest.raises(AttributeError, match=f"'{name}'.*with_limits.*with_tool"):
            setattr(robot, name, None)
    with pytest.raises(AttributeError, match="'qlim'"):
        del robot.qlim
    for arr in (robot.qlim, robot.gravity, *robot.configurations.values()):
        assert not arr.flags.writeable
        with pytest.raises(ValueError, match="read-only"):
            arr[0] = 0.0
    with pytest.raises(TypeError):
        robot.configurations["x"] = np.zeros(robot.n)  # a read-only mapping
    assert isinstance(robot.notes, tuple) and isinstance(robot.frame_names, tuple)


POE_ARRAYS = ["M", "Slist", "Blist", "Mlist", "Glist", "qlim", "gravity"]


def _pinocchio(robot, q, dq, ddq):
    """Pinocchio's own answers on a fresh Data: tip pose, Jacobian (rows ω; v, LOCAL_WORLD_ALIGNED),
    τ by RNEA, the mass matrix."""
    import pinocchio as pin

    m = robot.model
    d = m.createData()
    pin.forwardKinematics(m, d, q)
    T = pin.updateFramePlacement(m, d, robot.tip_id).homogeneous
    J = pin.computeFrameJacobian(m, d, q, robot.tip_id, pin.LOCAL_WORLD_ALIGNED)
    return T, np.vstack([J[3:], J[:3]]), pin.rnea(m, d, q, dq, ddq), pin.crba(m, d, q)


@pytest.mark.parametrize("name", ["ur5", "puma560", "panda"])
def test_poe_arrays_are_read_only_and_the_kernels_answer_as_pinocchio(name):
    """robot.poe's arrays refuse in-place edits; the compiled kernels that take them (the batch
    methods, the seed functions, the compiled IK, the workspace's FK) answer as Pinocchio does, and as
    they do on writeable copies of the same arrays, bit for bit."""
    from robokit._arrays import kernel_array
    from robokit.workspace.grid import tool_positions

    robot = shared_robot(name)
    p = robot.poe
    for field in POE_ARRAYS:
        arr = getattr(p, field)
        assert not arr.flags.writeable, field
        before = arr.copy()
        with pytest.raises(ValueError, match="read-only"):
            arr[(0,) * arr.ndim] = 1.0
        with pytest.raises(ValueError, match="read-only"):
            arr += 1.0
        assert np.array_equal(arr, before)
        base = kernel_array(arr)  # what the kernels are given: the writeable array behind the view, no copy
        assert base.flags.writeable and base is kernel_array(arr) and np.array_equal(base, arr)
    copies = {f: getattr(p, f).copy() for f in POE_ARRAYS}
    rng = np.random.default_rng(3)
    Q = np.array([robot.random_configuration(rng) for _ in range(4)])
    dQ, ddQ = rng.normal(size=Q.shape), rng.normal(size=Q.shape)
    Tb, Jb, Mb = robot.frame_pose_batch(Q), robot.jacobian_batch(Q), robot.crba_batch(Q)
    P = tool_positions(p, Q)
    z6 = np.zeros(6)
    for k, (q, dq, ddq) in enumerate(zip(Q, dQ, ddQ)):
        T, J, tau, M = _pinocchio(robot, q, dq, ddq)
        assert np.abs(Tb[k] - T).max() <= 1e-12 * max(1.0, np.abs(T).max())
        assert np.abs(P[k] - T[:3, 3]).max() <= 1e-12 * max(1.0, np.abs(T).max())
        assert np.abs(Jb[k] - J).max() <= 1e-12 * max(1.0, np.abs(J).max())
        assert np.abs(Mb[k] - M).max() <= 1e-12 * np.abs(M).max()
        T_seed = robokit.fkin_space(p.M, p.Slist, q)
        tau_seed = robokit.inverse_dynamics(q, dq, ddq, robot.gravity, z6, p.Mlist, p.Glist, p.Slist)
        M_seed = robokit.mass_matrix(q, p.Mlist, p.Glist, p.Slist)
        assert np.abs(T_seed - T).max() <= 1e-12 * max(1.0, np.abs(T).max())
        assert np.abs(tau_seed - tau).max() <= 1e-9 * max(1.0, np.abs(tau).max())
        assert np.abs(M_seed - M).max() <= 1e-9 * np.abs(M).max()
        # the same numbers as from writeable copies (the path robot.poe took before it was read-only)
        assert np.array_equal(T_seed, robokit.fkin_space(copies["M"], copies["Slist"], q))
        assert np.array_equal(tau_seed, robokit.inverse_dynamics(q, dq, ddq, np.array(robot.gravity), z6,
                                                                 copies["Mlist"], copies["Glist"], copies["Slist"]))
        assert np.array_equal(M_seed, robokit.mass_matrix(q, copies["Mlist"], copies["Glist"], copies["Slist"]))
    T = robot.frame_pose(Q[0])
    sol = robokit.solve_ik(robot, T, q0=Q[0] + 0.05, method="compiled")
    assert sol.success and np.abs(robot.frame_pose(sol.q) - T).max() < 1e-9
    for field in POE_ARRAYS:  # nothing wrote into them
        assert np.array_equal(getattr(p, field), copies[field]), field


def test_kernel_array_passes_only_a_whole_view_of_a_writeable_array():
    """A read-only view with its base's shape and strides is the base read the same way: passed as is;
    any other read-only array (a slice, a transposed view, a read-only array of its own) is copied."""
    from robokit._arrays import kernel_array, kernel_arrays, writeable_base

    a = np.arange(12.0).reshape(3, 4).copy()  # owns its memory (a reshape is a view of the arange)
    whole = a.view()
    whole.flags.writeable = False
    assert writeable_base(whole) is a and kernel_array(whole) is a
    assert kernel_arrays((whole, np.zeros(2)), (2, 1))[0] is a
    owned = a.copy()
    owned.flags.writeable = False  # read-only memory of its own: its views have no writeable base
    for ro in (a[:, 1:], a[1:], a.T, a[::-1], owned):
        ro = ro.view()
        ro.flags.writeable = False
        assert writeable_base(ro) is None
        out = kernel_array(ro)
        assert out.flags.writeable and out.flags.c_contiguous and np.array_equal(out, ro)
        assert not np.shares_memory(out, a) and not np.shares_memory(out, owned)


def test_with_limits_gives_a_new_robot_and_leaves_the_original():
    robot = robokit.load("ur5")
    before = robot.qlim.copy()
    lim = np.tile([-1.0, 1.0], (robot.n, 1))
    lim[2] = [-0.5, np.inf]
    tight = robot.with_limits(lim)
    assert tight is not robot and np.array_equal(tight.qlim, lim) and np.array_equal(robot.qlim, before)
    # Pinocchio's own model of the copy carries the limits (its random configurations respect them)
    assert np.array_equal(tight.model.lowerPositionLimit, lim[:, 0])
    assert np.array_equal(tight.model.upperPositionLimit, lim[:, 1])
    assert tight.spec.limits == tuple(map(tuple, lim.tolist())) and robot.spec.limits == ()
    q = tight.random_configuration(0)
    assert np.array_equal(tight.frame_pose(q), robot.frame_pose(q))
    with pytest.raises(InputError, match="qlim"):
        robot.with_limits(np.zeros((robot.n - 1, 2)))
    with pytest.raises(InputError, match="lower limit"):
        robot.with_limits(np.tile([1.0, -1.0], (robot.n, 1)))
    dh = robokit.load("puma560")
    dh_tight = dh.with_limits(np.tile([-0.3, 0.3], (6, 1)))
    assert np.array_equal(dh_tight.dh.qlim, np.tile([-0.3, 0.3], (6, 1))) and not np.array_equal(dh.dh.qlim, dh_tight.dh.qlim)
    T = dh.frame_pose(np.full(6, 0.9))  # reachable only outside the new limits
    assert any(s.within_limits for s in robokit.ik_analytic(dh, T))
    assert not any(s.within_limits for s in robokit.ik_analytic(dh_tight, T))


@pytest.mark.parametrize("name", ["puma560", "ur5"])
def test_with_tool_moves_the_tip_by_the_offset(name):
    """Against properties of rigid bodies, with Pinocchio's answers for the original tip:
    T_tool = T_tip · T_offset, ω the same, v_tool = v_tip + ω × (p_tool − p_tip)."""
    robot = robokit.load(name)
    tool = robot.with_tool(T_TOOL)
    assert tool.tip == "tcp" and "tcp" in tool.frame_names and robot.tip != "tcp"
    assert tool.spec.tools == (("tcp", tuple(T_TOOL.ravel().tolist())),)
    rng = np.random.default_rng(5)
    for _ in range(5):
        q = robot.random_configuration(rng)
        T0, T1 = robot.frame_pose(q), tool.frame_pose(q)
        assert np.abs(T1 - T0 @ T_TOOL).max() < 1e-12
        J0, J1 = robot.jacobian(q), tool.jacobian(q)
        r = T1[:3, 3] - T0[:3, 3]
        assert np.abs(J1[:3] - J0[:3]).max() < 1e-12
        assert np.abs(J1[3:] - (J0[3:] + np.cross(J0[:3].T, r).T)).max() < 1e-12
        tau = robot.rnea(q, q, q)
        assert np.abs(tool.rnea(q, q, q) - tau).max() <= 1e-12 * np.abs(tau).max()  # a frame carries no mass
    with pytest.raises(InputError, match="already has a frame 'tcp'"):
        tool.with_tool(np.eye(4))
    if robot.dh is not None:  # the DH table's tool follows, so the closed form solves for the new tip
        q = np.array([0.1, -0.4, 0.3, 0.5, 0.6, -0.2])
        sols = robokit.ik_analytic(tool, tool.frame_pose(q))
        assert any(np.allclose(s.q, q, atol=1e-9) for s in sols)


# ------------------------------------------------------------------ round trip in a fresh process
_CHILD = r"""
import json, pickle, sys, warnings
import numpy as np
import robokit
warnings.simplefilter("ignore")
specs, qs = pickle.loads(sys.stdin.buffer.read())
out = {}
for kind, spec in specs.items():
    r = robokit.load(spec)
    rows = []
    for q in qs[kind]:
        q = np.asarray(q)
        rows.append([r.frame_pose(q).tolist(), r.jacobian(q).tolist(), r.rnea(q, 0.5 * q, -q).tolist()])
    out[kind] = {"spec_equal": r.spec == spec, "n": r.n, "tip": r.tip, "rows": rows}
print(json.dumps(out))
"""


def _calibrated():
    nominal = robokit.load("puma560")
    rng = np.random.default_rng(11)
    true = chain_from_robot(nominal).perturbed(rng.normal(scale=1e-3, size=(nominal.n + 1, 6)))
    Q = np.array([nominal.random_configuration(rng) for _ in range(30)])
    return robokit.calibrate(nominal, Q, true.fk(Q)).robot


def _robots(tmp):
    return {
        "urdf": lambda: robokit.load(models_dir() / "puma560.urdf"),
        "xacro": lambda: robokit.load(write_xacro_package(tmp), package_dirs=[tmp / "ws"], xacro_args={"l1": "0.55"}),
        "mjcf": lambda: robokit.load(write_mjcf(tmp)),
        "sdf": lambda: robokit.load(DATA / "sdf" / "drake_iiwa14" / "iiwa14_no_collision.sdf"),
        "dh yaml": lambda: robokit.load(models_dir() / "puma560.yaml"),
        "example-robot-data": lambda: robokit.load("panda"),
        "calibrated": _calibrated,
        "with_limits": lambda: robokit.load("ur5").with_limits(np.tile([-2.0, 2.0], (6, 1))),
        "with_tool": lambda: robokit.load("ur5").with_tool(T_TOOL).with_limits(np.tile([-3.0, 3.0], (6, 1))),
        "calibrated with_tool": lambda: _calibrated().with_tool(T_TOOL, "probe"),
    }


KINDS = ["urdf", "xacro", "mjcf", "sdf", "dh yaml", "example-robot-data", "calibrated", "with_limits", "with_tool",
         "calibrated with_tool"]


@pytest.fixture(scope="module")
def round_trip(tmp_path_factory):
    """The robots here, and what a fresh Python process computes from their specs alone."""
    tmp = tmp_path_factory.mktemp("frozen")
    rng = np.random.default_rng(7)
    robots, qs = {}, {}
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RobokitWarning)
        for kind, make in _robots(tmp).items():
            robots[kind] = make()
            qs[kind] = [robots[kind].random_configuration(rng) for _ in range(3)]
    specs = {k: r.spec for k, r in robots.items()}
    proc = subprocess.run([sys.executable, "-c", _CHILD], input=pickle.dumps((specs, qs)), capture_output=True,
                          timeout=300, cwd=tmp)
    assert proc.returncode == 0, proc.stderr.decode()[-3000:]
    return robots, qs, json.loads(proc.stdout.decode().strip().splitlines()[-1])


@pytest.mark.parametrize("kind", KINDS)
def test_every_robot_round_trips_through_its_spec_in_a_fresh_process(kind, round_trip):
    robots, qs, child = round_trip
    robot, got = robots[kind], child[kind]
    assert robot.spec is not None and got["spec_equal"] and (got["n"], got["tip"]) == (robot.n, robot.tip)
    for q, (T, J, tau) in zip(qs[kind], got["rows"]):
        T0, J0, tau0 = robot.frame_pose(q), robot.jacobian(q), robot.rnea(q, 0.5 * q, -q)
        assert np.abs(np.array(T) - T0).max() <= 1e-12 * max(1.0, np.abs(T0).max())
        assert np.abs(np.array(J) - J0).max() <= 1e-12 * max(1.0, np.abs(J0).max())
        assert np.abs(np.array(tau) - tau0).max() <= 1e-12 * max(1.0, np.abs(tau0).max())


@pytest.mark.parametrize("name", ["ur5", "kinova"])
def test_crba_is_the_full_symmetric_matrix(name):
    """Robot.crba returns Pinocchio's array as is (its binding fills both triangles); checked against
    the upper triangle CRBA computes, mirrored here, and against the composite-rigid-body kernel."""
    import pinocchio as pin

    robot = shared_robot(name)
    rng = np.random.default_rng(2)
    for _ in range(5):
        q = robot.random_configuration(rng)
        M = robot.crba(q)
        data = robot.model.createData()
        pin.crba(robot.model, data, robot.q_pin(q))
        upper = np.triu(data.M)
        assert np.array_equal(M, upper + np.triu(upper, 1).T)
        assert np.abs(M - robot.crba_batch(q[None])[0]).max() <= 1e-12 * np.abs(M).max()


@pytest.mark.parametrize("name", ["ur5", "panda"])
def test_fast_paths_answer_as_pinocchio_in_new_arrays(name):
    """The one-configuration methods on float64 (n,) arrays (the fast paths: q inside the ball
    ``hypot(q) ≤ r``, or outside it with every entry in ``[lo₁, hi₁]``) and on lists (the checked
    path) give Pinocchio's numbers bit for bit, each call a new array; NaN and inf in q, dq or q̈
    take the checked path (its error)."""
    import pinocchio as pin

    robot = shared_robot(name)
    rng = np.random.default_rng(9)
    r1, lo1, hi1 = robot._r1, robot._lo1, robot._hi1
    inside = rng.uniform(-1, 1, robot.n)
    inside *= 0.5 * r1 / np.linalg.norm(inside)
    outside = np.full(robot.n, 0.9 * hi1)  # hypot > r, every entry within [lo₁, hi₁]: the sorted test
    outside[::2] = 0.9 * lo1
    assert np.hypot.reduce(outside) > r1
    for q in (inside, outside, robot.random_configuration(rng)):
        dq, ddq = rng.normal(size=robot.n), rng.normal(size=robot.n)
        T, J, tau, M = _pinocchio(robot, q, dq, ddq)
        d = robot.model.createData()
        ddq_pin = pin.aba(robot.model, d, q, dq, tau)
        g = pin.computeGeneralizedGravity(robot.model, d, q)
        for arg in (q, q.tolist()):
            with warnings.catch_warnings():
                warnings.simplefilter("error")  # no degrees warning on these radians
                got = [robot.frame_pose(arg), robot.jacobian(arg), robot.rnea(arg, dq, ddq), robot.crba(arg),
                       robot.aba(arg, dq, tau), robot.gravity_torques(arg)]
            again = [robot.frame_pose(arg), robot.jacobian(arg), robot.rnea(arg, dq, ddq), robot.crba(arg),
                     robot.aba(arg, dq, tau), robot.gravity_torques(arg)]
            for a, b, want in zip(got, again, (T, J, tau, M, ddq_pin, g)):
                assert np.array_equal(a, want) and np.array_equal(b, want)
                assert a is not b and not np.shares_memory(a, b)  # a new array each call, not a reused buffer
    for bad in (np.nan, np.inf):
        q = np.zeros(robot.n)
        q[1] = bad
        for call in (lambda: robot.frame_pose(q), lambda: robot.jacobian(q), lambda: robot.crba(q),
                     lambda: robot.gravity_torques(q), lambda: robot.rnea(q, np.zeros(robot.n), np.zeros(robot.n)),
                     lambda: robot.rnea(np.zeros(robot.n), np.zeros(robot.n), q),
                     lambda: robot.aba(np.zeros(robot.n), q, np.zeros(robot.n))):
            with pytest.raises(InputError, match="NaN or infinite"):
                call()


def test_a_dh_robots_table_is_read_only_and_its_ik_follows_pinocchio():
    """The DH table a robot holds is its own copy with read-only base, tool and gravity: an in-place
    edit raises (before, it changed the closed-form IK's frames while Pinocchio's FK stayed), and the
    table given to the robot is left as it was."""
    import dataclasses

    from robokit.description.robot import Robot

    robot = robokit.load("puma560")
    for name in ("base", "tool", "gravity"):
        with pytest.raises(ValueError, match="read-only"):
            getattr(robot.dh, name)[..., 0] = 1.0
    # a robot built from a user's writeable table copies it: the user's arrays stay writeable
    table = dataclasses.replace(robot.dh, base=np.array(robot.dh.base), tool=np.array(robot.dh.tool))
    again = Robot(robot.name, robot.model, robot.tip, dh=table)
    assert table.base.flags.writeable and not again.dh.base.flags.writeable
    table.base[0, 3] += 0.1  # the user's edit does not reach the robot
    q = np.linspace(-0.8, 0.9, 6)
    T = again.frame_pose(q)
    sols = robokit.ik_analytic(again, T)
    assert any(np.abs(np.asarray(s.q) - q).max() < 1e-9 for s in sols)
    for s in sols:
        assert np.abs(again.frame_pose(np.asarray(s.q)) - T).max() < 1e-9
