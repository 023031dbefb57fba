"""The compiled closed-form IK (robokit.kernels.closed_form, the one implementation of Pieper's
and the three-parallel-axes methods) checked against Pinocchio.

Every solution must reach the pose to 1e-9 through the robot's Pinocchio model
(``robot.frame_pose``), which does not go through the solver, and the solver's original pose
must be among them. The packed path (``AnalyticIK.solve`` with ``use_kernel``: solve and
post-process in the kernel) must give the same solutions as the solver's rows post-processed
in Python (``use_kernel = False``: ``solutions_from_rows``) — same count, order, labels, limit
flags, degenerate flags, joint values to 1e-9.
The batched form must equal the per-pose one, and ``NUMBA_DISABLE_JIT=1`` must run the same
source to the same answers.
"""
import json
import math
import os
import subprocess
import sys

import numpy as np
import pytest
from hypothesis import assume, given, settings
from hypothesis import strategies as st

import robokit
from shared_robots import robot as shared_robot
from robokit.description.dh import DHLink, DHTable, matrix_from_rpy
from robokit.errors import InputError
from robokit.ik import AnalyticIK, ik_analytic, ik_analytic_batch
from robokit.ik.backends import ClosedFormBackend

TOL = 1e-9


def wrapped_diff(a, b, revolute):
    d = np.asarray(a, float) - np.asarray(b, float)
    d[revolute] = np.angle(np.exp(1j * d[revolute]))
    return float(np.abs(d).max()) if d.size else 0.0


def compare(robot, ik, T, wrist_ref=0.0):
    """Compiled == Python reference, and every solution reaches T in Pinocchio."""
    assert ik._kernel is not None, "the compiled path should cover this arm"
    ik.use_kernel = True
    fast = ik.solve(T, wrist_ref)
    ik.use_kernel = False
    try:
        ref = ik.solve(T, wrist_ref)
    finally:
        ik.use_kernel = True
    rev = np.array(ik._revolute)
    assert [s.label for s in fast] == [s.label for s in ref]
    assert [s.within_limits for s in fast] == [s.within_limits for s in ref]
    assert [s.degenerate for s in fast] == [s.degenerate for s in ref]
    for a, b in zip(fast, ref):
        assert a.q.shape == (6,)
        assert wrapped_diff(a.q, b.q, rev) < TOL
        assert np.abs(robot.frame_pose(a.q) - T).max() < TOL, a.label
    return fast


def random_q(rng, kinds):
    q = rng.uniform(-np.pi, np.pi, 6)
    for i, k in enumerate(kinds):
        if k == "P":
            q[i] = rng.uniform(-0.5, 0.5)
    return q


def _base_tool(rng):
    base, tool = np.eye(4), np.eye(4)
    base[:3, :3], base[:3, 3] = matrix_from_rpy(rng.uniform(-1, 1, 3)), rng.uniform(-0.2, 0.2, 3)
    tool[:3, :3], tool[:3, 3] = matrix_from_rpy(rng.uniform(-1, 1, 3)), rng.uniform(-0.1, 0.1, 3)
    return base, tool


def spherical_arm(seed, convention, kinds, oblique, a1_zero=False):
    """A random 6-joint spherical-wrist DH table (axes 4–6 meeting), with base and tool."""
    rng = np.random.default_rng(seed)
    rows = []
    for i in range(6):
        al = rng.uniform(-np.pi, np.pi) if oblique else rng.choice([-np.pi / 2, np.pi / 2])
        rows.append({"joint": kinds[i] if i < 3 else "R", "a": rng.uniform(-0.5, 0.5), "alpha": al,
                     "d": rng.uniform(-0.5, 0.5), "theta": rng.uniform(-np.pi, np.pi)})
    w = (3, 4) if convention == "standard" else (4, 5)
    rows[w[0]]["a"] = rows[w[1]]["a"] = 0.0
    rows[4]["d"] = 0.0
    for i in w:
        while abs(math.sin(rows[i]["alpha"])) < 0.3:
            rows[i]["alpha"] = rng.uniform(-np.pi, np.pi)
    if a1_zero:  # the quadratic case a₁ = 0 (the PUMA's)
        rows[0 if convention == "standard" else 1]["a"] = 0.0
    base, tool = _base_tool(rng)
    return DHTable(f"sph{seed}", convention, tuple(DHLink(**r) for r in rows), base=base, tool=tool)


def parallel_arm(seed, convention):
    """A random 6R DH table with axes 2–4 parallel and axes 5, 6 meeting, with base and tool."""
    rng = np.random.default_rng(seed)
    a = rng.uniform(0.1, 0.6, 6) * rng.choice([-1, 1], 6)
    d = rng.uniform(-0.3, 0.3, 6)
    th = rng.uniform(-np.pi, np.pi, 6)
    al = rng.uniform(0.4, 2.7, 6) * rng.choice([-1, 1], 6)
    al[1], al[2] = rng.choice([0.0, np.pi]), rng.choice([0.0, np.pi])
    a[4] = 0.0
    if convention == "modified":
        a, al = np.r_[rng.uniform(-0.2, 0.2), a[:5]], np.r_[rng.uniform(-1, 1), al[:5]]
    links = tuple(DHLink("R", a[i], al[i], d[i], th[i]) for i in range(6))
    base, tool = _base_tool(rng)
    return DHTable(f"par{seed}", convention, links, base=base, tool=tool)


# ---------------------------------------------------------------- shipped and example arms
@pytest.mark.parametrize("name", ["puma560", "ur3", "ur5", "ur10"])
def test_shipped_arms_compiled_equals_python(name):
    robot = shared_robot(name)
    ik = AnalyticIK(robot)
    rng = np.random.default_rng(7)
    counts = []
    for _ in range(25):
        q = robot.random_configuration(rng)
        T = robot.frame_pose(q)
        sols = compare(robot, ik, T)
        counts.append(len(sols))
        assert min(wrapped_diff(s.q, q, np.array(ik._revolute)) for s in sols) < 1e-7
    assert max(counts) == 8
    # out of reach: nothing, on both paths
    T = robot.frame_pose(np.zeros(6))
    T[:3, 3] += 10.0
    assert compare(robot, ik, T) == []


@pytest.mark.parametrize("name, q", [("puma560", [0.3, -0.4, 0.2, 0.7, 0.0, -0.5]),
                                     ("ur5", [0.3, -1.0, 1.2, -0.5, 0.0, 0.2])])
@pytest.mark.parametrize("wrist_ref", [0.0, 0.8])
def test_wrist_singularity_same_choice(name, q, wrist_ref):
    robot = shared_robot(name)
    ik = AnalyticIK(robot)
    sols = compare(robot, ik, robot.frame_pose(np.array(q)), wrist_ref)
    singular = [s for s in sols if "wrist singular" in s.label]
    assert singular and all(s.degenerate for s in singular)


# ---------------------------------------------------------------- random arms (both conventions)
@settings(max_examples=20, deadline=None, derandomize=True)
@given(st.integers(0, 2**31), st.sampled_from(["standard", "modified"]), st.sampled_from(["RRR", "RRP"]),
       st.booleans(), st.booleans())
def test_random_spherical_wrist_arms(seed, convention, kinds, oblique, a1_zero):
    robot = robokit.load(spherical_arm(seed, convention, kinds, oblique, a1_zero))
    ik = AnalyticIK(robot)
    assume(ik.method == "spherical wrist")  # right-angled twists can confine the wrist centre
    rng = np.random.default_rng(seed + 1)
    for _ in range(3):
        q = random_q(rng, kinds)
        T = robot.frame_pose(q)
        sols = compare(robot, ik, T)
        assert min(wrapped_diff(s.q, q, np.array(ik._revolute)) for s in sols) < 1e-7


@settings(max_examples=15, deadline=None, derandomize=True)
@given(st.integers(0, 2**31), st.sampled_from(["standard", "modified"]))
def test_random_three_parallel_axes_arms(seed, convention):
    robot = robokit.load(parallel_arm(seed, convention))
    ik = AnalyticIK(robot)
    assert ik.method == "three parallel axes"
    rng = np.random.default_rng(seed + 1)
    for _ in range(3):
        q = rng.uniform(-np.pi, np.pi, 6)
        T = robot.frame_pose(q)
        sols = compare(robot, ik, T)
        assert min(wrapped_diff(s.q, q, np.ones(6, bool)) for s in sols) < 1e-7


@pytest.mark.parametrize("oblique", [True, False])
@pytest.mark.parametrize("kinds", ["PRR", "RPR", "PPR", "PRP", "RPP"])
def test_prismatic_joint_1_or_2_compiled(kinds, oblique):
    """Every position case of Pieper's method runs in the kernel: PR- and RP- quartic (oblique
    twists) and their cos α₁ = 0 cases (right-angled twists), PP."""
    for seed in range(4):
        table = spherical_arm(5 + seed, "standard", kinds, oblique)
        robot = robokit.load(table)
        ik = AnalyticIK(robot)
        if ik.method != "spherical wrist":
            continue
        rng = np.random.default_rng(2 + seed)
        for _ in range(3):
            q = random_q(rng, kinds)
            sols = compare(robot, ik, robot.frame_pose(q))
            assert min(wrapped_diff(s.q, q, np.array(ik._revolute)) for s in sols) < 1e-7


def test_the_prismatic_arms_cover_every_position_case():
    """The arms of test_prismatic_joint_1_or_2_compiled reach every case with a prismatic joint 1 or 2."""
    cases = set()
    for kinds in ("PRR", "RPR", "PPR", "PRP", "RPP"):
        for oblique in (True, False):
            for seed in range(4):
                ik = AnalyticIK(spherical_arm(5 + seed, "standard", kinds, oblique))
                if ik.method == "spherical wrist":
                    cases.add(ik.solver.constants().case)
    assert {"PR-quartic", "PR-c1", "RP-quartic", "RP-c1", "PP"} <= cases, cases


def test_limits_wider_than_pi_and_flags_match():
    table = spherical_arm(9, "standard", "RRR", True)
    links = tuple(DHLink(l.joint, l.a, l.alpha, l.d, l.theta, qlim=(-1.0, 5.0) if i == 0 else (-2.0, 2.0))
                  for i, l in enumerate(table.links))
    table = DHTable("lim", "standard", links, base=table.base, tool=table.tool)
    robot = robokit.load(table)
    ik = AnalyticIK(robot)
    rng = np.random.default_rng(3)
    flags = set()
    for _ in range(10):
        q = random_q(rng, "RRR")
        q[0] = rng.uniform(3.2, 4.9)
        sols = compare(robot, ik, robot.frame_pose(q))
        flags |= {s.within_limits for s in sols}
        assert any(s.q[0] > math.pi for s in sols)  # shifted by 2π into the wide limits
    assert flags == {True, False}


def test_chain_read_from_the_tool_compiled():
    """An arm whose spherical group is at the base (the chain is solved reversed)."""
    from robokit.ik._dh_chain import DHChain

    for table in (spherical_arm(3, "standard", "RRR", True), parallel_arm(4, "standard")):
        rc = DHChain(table).reversed()
        rows = [DHLink(rc.kinds[0], 0.0, 0.0, rc.d0[0], rc.th0[0])]
        rows += [DHLink(rc.kinds[i], rc.a[i - 1], rc.alpha[i - 1], rc.d0[i], rc.th0[i]) for i in range(1, 6)]
        robot = robokit.load(DHTable("rev", "modified", tuple(rows), base=rc.base, tool=rc.tool))
        ik = AnalyticIK(robot)
        assert ik.reversed
        rng = np.random.default_rng(5)
        for _ in range(4):
            sols = compare(robot, ik, robot.frame_pose(rng.uniform(-np.pi, np.pi, 6)), 0.3)
            assert sols and all("(chain reversed)" in s.label for s in sols)


# ---------------------------------------------------------------- batched
@pytest.mark.parametrize("name", ["puma560", "ur5"])
def test_batch_equals_per_pose(name):
    robot = shared_robot(name)
    rng = np.random.default_rng(11)
    Ts = np.stack([robot.frame_pose(robot.random_configuration(rng)) for _ in range(40)])
    Ts[3, :3, 3] += 10.0  # out of reach
    Q, counts = ik_analytic_batch(robot, Ts)
    assert Q.shape == (40, int(counts.max()), 6) and counts[3] == 0
    _, within, _ = AnalyticIK(robot).solve_batch(Ts)
    for i, T in enumerate(Ts):
        sols = ik_analytic(robot, T)
        assert counts[i] == len(sols)
        assert np.array_equal(Q[i, : counts[i]], np.array([s.q for s in sols]).reshape(-1, 6))
        assert within[i, : counts[i]].tolist() == [s.within_limits for s in sols]
        assert np.isnan(Q[i, counts[i]:]).all()
    # the Python reference gives the same arrays
    ik = AnalyticIK(robot)
    ik.use_kernel = False
    Qp, wp, cp = ik.solve_batch(Ts[:8])
    assert np.array_equal(cp, counts[:8])
    assert np.nanmax(np.abs(np.angle(np.exp(1j * (Qp - Q[:8, : Qp.shape[1]]))))) < TOL


def test_batch_bad_input():
    robot = robokit.load("ur5")
    with pytest.raises(InputError, match="Ts: expected shape"):
        ik_analytic_batch(robot, np.eye(4))
    Ts = np.stack([np.eye(4)] * 3)
    Ts[1, 0, 0] = 2.0
    with pytest.raises(InputError, match=r"Ts\[1\]"):
        ik_analytic_batch(robot, Ts)
    with pytest.raises(ValueError, match="7 joints"):
        ik_analytic_batch(robokit.load("panda"), Ts[:1])
    Q, counts = ik_analytic_batch(robot, np.zeros((0, 4, 4)))
    assert Q.shape == (0, 0, 6) and counts.shape == (0,)


def test_reaches_batched_route_matches_per_target():
    robot = robokit.load("ur5")
    rng = np.random.default_rng(1)
    Ts = np.stack([robot.frame_pose(robot.random_configuration(rng)) for _ in range(20)])
    Ts[::4, :3, 3] *= 3.0  # some out of reach
    got = ClosedFormBackend().reaches(robot, Ts, np.random.default_rng(0), 0)
    want = [any(s.within_limits for s in ik_analytic(robot, T)) for T in Ts]
    assert got.tolist() == want and 0 < sum(want) < 20


def test_bad_pose_single():
    robot = robokit.load("puma560")
    T = np.eye(4)
    T[0, 1] = 0.5
    with pytest.raises(InputError, match="T"):
        ik_analytic(robot, T)
    # a list or a non-contiguous view is checked and converted
    T = robot.frame_pose(np.full(6, 0.2))
    big = np.zeros((4, 8))
    big[:, ::2] = T
    assert len(ik_analytic(robot, big[:, ::2])) == len(ik_analytic(robot, T.tolist())) == 8


# ---------------------------------------------------------------- NUMBA_DISABLE_JIT runs the same source
_SCRIPT = """
import json, numpy as np, robokit
from robokit.ik import AnalyticIK
out = {}
for name in ("puma560", "ur5"):
    robot = robokit.load(name)
    ik = AnalyticIK(robot)
    rng = np.random.default_rng(3)
    Ts = np.stack([robot.frame_pose(robot.random_configuration(rng)) for _ in range(3)])
    out[name] = [[s.q.tolist() + [s.label] for s in ik.solve(T)] for T in Ts]
    out[name + " batch"] = ik.solve_batch(Ts)[0].tolist()
print(json.dumps(out))
"""


def test_numba_disable_jit_runs_the_same_source():
    env = dict(os.environ, NUMBA_DISABLE_JIT="1")
    res = subprocess.run([sys.executable, "-c", _SCRIPT], capture_output=True, text=True, env=env, timeout=300)
    assert res.returncode == 0, res.stderr
    plain = json.loads(res.stdout.strip().splitlines()[-1])
    compiled = json.loads(subprocess.run([sys.executable, "-c", _SCRIPT], capture_output=True, text=True,
                                         timeout=300).stdout.strip().splitlines()[-1])
    for key in plain:
        if key.endswith("batch"):
            assert np.allclose(np.array(plain[key]), np.array(compiled[key]), atol=TOL, equal_nan=True)
            continue
        for a, b in zip(plain[key], compiled[key], strict=True):
            assert [r[-1] for r in a] == [r[-1] for r in b]
            assert np.allclose([r[:-1] for r in a], [r[:-1] for r in b], atol=TOL)
