"""`robokit codegen`: the generated C99, compiled with the strict flags (-Werror), against Pinocchio
(pose, Jacobian, gravity, rnea) and against robokit's ik_analytic (same solutions, order, labels,
flags) on the shipped models, example-robot-data arms and random DH arms (both conventions,
prismatic and flipped joints, masses). The C is loaded through ctypes."""
import math
import re
from dataclasses import replace
import subprocess
import warnings

import numpy as np
import pytest
from hypothesis import HealthCheck, Phase, assume, given, settings
from hypothesis import strategies as st

import robokit
from shared_robots import DATA, ODD_DOUBLE, ODD_MISSING, factory_ur5e, robot as shared_robot
from calibrated_folds import fold_starts
from robokit.cli import main
from robokit.codegen import c_name, generate_c, write_c
from robokit.description.dh import DHLink, DHTable, matrix_from_rpy
from robokit.ik import ik_analytic, ik_analytic_kind

SETTINGS = dict(max_examples=4, deadline=None, derandomize=True, phases=[Phase.explicit, Phase.generate],
                suppress_health_check=[HealthCheck.function_scoped_fixture, HealthCheck.too_slow])
MATH = {"sin", "cos", "sincos", "atan", "atan2", "acos", "cbrt", "sqrt", "hypot", "fabs", "fmod", "remainder",
        "floor", "memset", "memcpy"}
MATH |= {f + "f" for f in MATH}


@pytest.fixture(scope="module")
def models():
    return {name: shared_robot(name) for name in ("twolink", "rrr", "puma560", "ur5", "panda", "kinova")}


def check_dynamics_and_kinematics(robot, lib, samples=6, seed=0):
    """The C against Pinocchio (through the Robot) at random q, qd, qdd."""
    rng = np.random.default_rng(seed)
    f32 = lib.float32
    for _ in range(samples):
        q = robot.random_configuration(rng)
        qd, qdd = rng.normal(size=robot.n), rng.normal(size=robot.n)
        T = robot.frame_pose(q)
        J = robot.jacobian(q, reference="local_world_aligned")
        g = robot.gravity_torques(q)
        tau = robot.rnea(q, qd, qdd)
        if f32:
            q32 = q.astype(np.float32).astype(float)  # the C sees float inputs
            T, J = robot.frame_pose(q32), robot.jacobian(q32, reference="local_world_aligned")
            g, tau = robot.gravity_torques(q32), robot.rnea(q32, qd.astype(np.float32), qdd.astype(np.float32))
            tol = lambda ref: 1e-4 * max(1.0, float(np.abs(ref).max()))  # noqa: E731
        else:
            tol = lambda ref: 1e-12 * max(1.0, float(np.abs(ref).max()))  # noqa: E731
        assert np.abs(lib.fk(q) - T).max() <= tol(T)
        oMi = joint_frames(robot, q32 if f32 else q)
        assert np.abs(lib.joint_poses(q) - oMi).max() <= tol(oMi)
        assert np.abs(lib.jacobian(q) - J).max() <= tol(J)
        assert np.abs(lib.gravity(q) - g).max() <= tol(g)
        assert np.abs(lib.rnea(q, qd, qdd) - tau).max() <= tol(tau)


def joint_frames(robot, q):
    """(n, 4, 4): Pinocchio's data.oMi[1..n] at q (each joint frame's pose in the base frame)."""
    import pinocchio as pin

    data = robot.model.createData()
    pin.forwardKinematics(robot.model, data, robot.q_pin(q))
    return np.array([data.oMi[k].homogeneous for k in range(1, robot.n + 1)])


def closed_form_solver(robot):
    """robokit's closed-form solver object of ``robot`` (its constants are what the C is built from)."""
    import robokit.ik as rik

    if hasattr(rik, "analytic_ik"):
        return rik.analytic_ik(robot).solver
    ik_analytic_kind(robot)
    return robot._closed_form.solver


def _dist(a, b, rev):
    d = np.asarray(a, float) - np.asarray(b, float)
    d[rev] = np.remainder(d[rev] + np.pi, 2 * np.pi) - np.pi
    return float(np.abs(d).max())


def check_ik(robot, lib, poses, tol=1e-9, nominal=None):
    """The C returns ik_analytic's solutions: in order, with the same labels and flags (the
    quartic's roots included: both list them by increasing tan(θ₃/2)); a calibrated arm's merged
    solution is labelled in C by its first branch only. Where a calibrated arm's nominal structure
    gives no start, ik_analytic returns the general 6R method's solutions and the C none: there the
    calibrated path itself (which the C mirrors) must return none too. ``tol``: the joints' tolerance, or
    a function of (T, Python's solution, the C's q) giving it per solution (see _conditioned)."""
    from robokit.ik.closed_form import analytic_ik

    rev = np.abs(robot.poe.Slist[:3]).sum(axis=0) > 0.5
    for T in poses:
        py = ik_analytic(robot, T, nominal=nominal)
        c = lib.ik(T)
        cal = analytic_ik(robot, nominal).calibrated if nominal is not False else None
        if cal is not None and not c and py and all(s.label.startswith("solution ") for s in py):
            assert cal._solve_checked(np.ascontiguousarray(T, dtype=float), 0.0) == []
            continue
        added = 0  # an odd count completed by the general 6R method's roots (Python only): last, "solution k of m"
        while cal is not None and added < len(py) - 1 and py[-1 - added].label.startswith("solution ") \
                and not py[0].label.startswith("solution "):
            added += 1
        if added:
            assert cal.parity and len(c) % 2 == 1 and len(c) == len(py) - added
            py = py[:-added]
        assert len(c) == len(py), ([s.label for s in py], [x[1] for x in c])
        for s, (q, label, inside, degen) in zip(py, c):
            assert label == s.label or (s.label.startswith(label + " (merged with ") and degen)
            assert (inside, degen) == (s.within_limits, s.degenerate)
            assert _dist(q, s.q, rev) < (tol(T, s, q) if callable(tol) else tol), label
        for q, *_ in c:  # and every C solution reaches T (Pinocchio, and the generated NAME_fk)
            assert np.abs(robot.frame_pose(q) - T).max() < 1e-9
            if not lib.float32:
                assert np.abs(lib.fk(q) - T).max() < 1e-9


# ------------------------------------------------------------------ shipped and example arms
@pytest.mark.parametrize("name", ["twolink", "rrr", "puma560", "ur5", "panda", "kinova"])
def test_kinematics_and_dynamics_match_pinocchio(models, build, name):
    robot = models[name]
    check_dynamics_and_kinematics(robot, build(robot))


@pytest.mark.parametrize("name", ["puma560", "ur5", "panda"])
def test_float32_matches_to_1e_4(models, build, name):
    robot = models[name]
    lib = build(robot, float32=True)
    check_dynamics_and_kinematics(robot, lib)
    text = (lib.path.parent / f"{lib.name}.c").read_text() + (lib.path.parent / f"{lib.name}.h").read_text()
    code = re.sub(r"/\*.*?\*/", "", text, flags=re.S)
    assert "double" not in code
    assert not re.search(r"\b(sin|cos|atan2|sqrt|fabs)\(", code)


@pytest.mark.parametrize("name", ["puma560", "ur5", "kinova"])
def test_ik_matches_ik_analytic(models, build, name):
    robot = models[name]
    lib = build(robot)
    assert lib.has_ik and lib.max_solutions == 8
    rng = np.random.default_rng(1)
    check_ik(robot, lib, [robot.frame_pose(robot.random_configuration(rng)) for _ in range(30)])


@pytest.mark.parametrize("name", ["lite6.xml", "xarm6.urdf"])
def test_ik_of_makers_arms_with_rounded_right_angles(build, name):
    """UFACTORY's Lite 6 (MuJoCo Menagerie's MJCF: an exact spherical wrist, axes 2 and 3 7e-6 rad
    from parallel, so the DH table's d2 = d3 = 27 km) and xArm 6 (the general 6R method) from
    tests/data/ufactory: the C returns ik_analytic's solutions, each reaching the pose (Pinocchio,
    1e-9), the generating configuration among them. Before, the C's position quadratic of the Lite 6
    was 1e-6 m off as robokit's was, and at 4 of these 30 poses the xArm 6's C returned nothing."""
    from pathlib import Path

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # the URDF's zero inertias
        robot = robokit.load(Path(__file__).resolve().parents[1] / "data" / "ufactory" / name)
    lib = build(robot)
    rng = np.random.default_rng(0)
    qs = [robot.random_configuration(rng) for _ in range(30)]
    check_ik(robot, lib, [robot.frame_pose(q) for q in qs])
    rev = np.ones(6, bool)
    for q in qs:
        assert min((_dist(c[0], q, rev) for c in lib.ik(robot.frame_pose(q))), default=np.inf) < 1e-7


def test_ik_out_of_reach_and_singular(models, build):
    robot = models["puma560"]
    lib = build(robot)
    far = np.eye(4)
    far[:3, 3] = [5.0, 0.0, 0.0]
    assert lib.ik(far) == [] and ik_analytic(robot, far) == []
    q = np.array([0.3, -0.4, 0.2, 0.5, 0.0, -0.2])  # q5 = 0: the wrist singularity
    check_ik(robot, lib, [robot.frame_pose(q)])


@pytest.mark.parametrize("name", ["puma560", "ur5"])
def test_float32_ik_reaches_the_pose(models, build, name):
    robot = models[name]
    lib = build(robot, float32=True)
    rng = np.random.default_rng(2)
    full = 0
    for _ in range(20):
        T = robot.frame_pose(robot.random_configuration(rng))
        py, c = ik_analytic(robot, T), lib.ik(T)
        full += len(c) == len(py)
        for q, label, *_ in c:  # no spurious solution: each is near ik_analytic's one of that label
            ref = [s for s in py if s.label == label]
            assert ref and _dist(q, ref[0].q, np.ones(robot.n, bool)) < 1e-2
    assert full >= 18


def test_float32_quartic_with_a_large_root_keeps_its_small_roots(build):
    """A spherical-wrist arm whose joint-3 quartic has a root near tan(θ₃/2) = 3,000 (θ₃ near π) at
    some poses: float's closed form lost the three other roots there (2 solutions of 8, the generating
    configuration not among them, at 4 of 300 random poses); the quartic is now solved in 1/u where its
    roots' product is above 1. Every pose of 300: ik_analytic's count, each solution within 1e-2 of
    a double one, a different one each (away from the wrist's singularity), and reaching the pose
    (Pinocchio) to float's precision."""
    d = math.radians
    rows = [(0.15, -90, 0.45, 10), (0.6, 0, 0.05, -90), (0.1, -90, 0.0, 0), (0.0, 90, 0.55, 0), (0.0, -90, 0.0, 0),
            (0.0, 0, 0.09, 25)]
    base, tool = np.eye(4), np.eye(4)
    base[:3, :3], base[:3, 3] = matrix_from_rpy([d(5), d(-10), d(40)]), [0.2, 0.1, 0.5]
    tool[:3, :3], tool[:3, 3] = matrix_from_rpy([d(30), 0.0, d(-20)]), [0.01, 0.02, 0.12]
    links = tuple(DHLink("R", a=a, alpha=d(al), d=dd, theta=d(th), mass=1.0) for a, al, dd, th in rows)
    robot = robokit.load(DHTable("sw6", "standard", links, base=base, tool=tool))
    assert closed_form_solver(robot).case == "RR-quartic"
    lib = build(robot, float32=True)
    rng = np.random.default_rng(0)
    qs = [np.array([-0.0335, 1.429, 0.827, -0.573, -0.690, 1.089])] + [robot.random_configuration(rng) for _ in range(300)]
    for q in qs:
        T = robot.frame_pose(q)
        py, c = ik_analytic(robot, T), lib.ik(T.astype(np.float32).astype(float))
        assert len(c) == len(py)
        for qc, label, *_ in c:  # (the label may differ where its sign is within float's precision of 0)
            ref = min(py, key=lambda s: _dist(qc, s.q, np.ones(6, bool)))
            # near the wrist's singularity float splits θ₄ and θ₆ loosely (and the pose within 1e-3)
            regular = abs(math.sin(ref.q[4])) > 1e-2
            if regular:
                assert _dist(qc, ref.q, np.ones(6, bool)) < 1e-2
            assert np.abs(robot.frame_pose(qc) - T).max() < (1e-4 if regular else 1e-3)
        apart = all(_dist(a.q[:3], b.q[:3], np.ones(3, bool)) > 0.05 for i, a in enumerate(py) for b in py[:i]
                    if not np.allclose(a.q[:3], b.q[:3]))  # (branches about to merge: float tells them apart loosely)
        if apart and all(abs(math.sin(s.q[4])) > 1e-2 for s in py):  # one C solution for each
            assert len({min(range(len(py)), key=lambda k: _dist(qc, py[k].q, np.ones(6, bool))) for qc, *_ in c}) == len(py)
    T = robot.frame_pose(qs[0])
    assert min(_dist(qc, qs[0], np.ones(6, bool)) for qc, *_ in lib.ik(T.astype(np.float32).astype(float))) < 1e-3


def test_arm_without_closed_form_has_no_ik(models, build):
    lib = build(models["panda"])
    assert not lib.has_ik
    header = (lib.path.parent / "panda.h").read_text()
    assert "#define panda_HAS_IK 0" in header and "the arm has 7 joints" in header
    assert "panda_ik" not in re.sub(r"/\*.*?\*/", "", header, flags=re.S)
    with pytest.raises(ValueError):
        ik_analytic(models["panda"], np.eye(4))


def test_header_macros_and_tables(models, build):
    robot = models["ur5"]
    lib = build(robot)
    h = (lib.path.parent / "ur5.h").read_text()
    for macro in ("ur5_N 6", "ur5_HAS_IK 1", "ur5_MAX_SOLUTIONS 8", "ur5_JOINT0_TYPE 0", "ur5_JOINT5_UPPER"):
        assert f"#define {macro}" in h
    for text in ("void ur5_fk(const double q[ur5_N], double T[16]);",
                 "void ur5_jacobian(const double q[ur5_N], double J[6 * ur5_N]);",
                 "int ur5_ik(const double T[16], double q[ur5_MAX_SOLUTIONS * ur5_N]);",
                 "void ur5_gravity(const double q[ur5_N], double tau[ur5_N]);",
                 "void ur5_rnea(const double q[ur5_N], const double qd[ur5_N], const double qdd[ur5_N], "
                 "double tau[ur5_N]);", "robokit", "LOCAL_WORLD_ALIGNED", "'tool0'"):
        assert text in h
    import ctypes

    qlim = (ctypes.c_double * 12).in_dll(lib.lib, "ur5_qlim")
    assert np.allclose(np.array(qlim).reshape(6, 2), robot.qlim)
    types = (ctypes.c_int * 6).in_dll(lib.lib, "ur5_joint_type")
    assert list(types) == [0] * 6


def test_only_math_symbols_are_needed(models, build, nm):
    for name, f32 in (("puma560", False), ("ur5", False), ("panda", False), ("puma560", True), ("twolink", False),
                      ("rrr", False), ("rrr", True)):
        lib = build(models[name], float32=f32)
        out = subprocess.run([nm, "-u", str(lib.path.with_suffix(".o"))], capture_output=True, text=True,
                             check=True).stdout
        undefined = {line.split()[-1] for line in out.splitlines() if line.strip()}
        assert undefined <= MATH, undefined - MATH


# ------------------------------------------------------------------ random DH arms
def random_table(seed, convention, kinds, structure=None, n=None, oblique=True):
    """A random DH table: lengths, twists, offsets, flips, masses, base and tool; ``structure``
    "wrist" makes axes 4–6 meet, "parallel" makes axes 2–4 parallel with axes 5, 6 meeting."""
    rng = np.random.default_rng(seed)
    n = n or len(kinds)
    rows = []
    for i in range(n):
        I = rng.uniform(0.01, 0.1, 3)
        al = rng.uniform(-np.pi, np.pi) if oblique else rng.choice([-np.pi / 2, np.pi / 2, 0.0])
        rows.append({"joint": kinds[i], "a": rng.uniform(-0.5, 0.5), "alpha": al,
                     "d": rng.uniform(-0.5, 0.5), "theta": rng.uniform(-np.pi, np.pi),
                     "mass": rng.uniform(0.5, 3.0), "com": rng.uniform(-0.1, 0.1, 3),
                     "inertia": np.r_[I, 0.1 * rng.uniform(-1, 1, 3) * I.min()],
                     "flip": bool(rng.integers(2)) and structure is None})
    if structure == "wrist":
        w = (3, 4) if convention == "standard" else (4, 5)
        rows[w[0]]["a"] = rows[w[1]]["a"] = 0.0
        rows[4]["d"] = 0.0
        for i in w:
            while abs(math.sin(rows[i]["alpha"])) < 0.3:
                rows[i]["alpha"] = rng.uniform(-np.pi, np.pi)
    if structure == "parallel":
        a = rng.uniform(0.1, 0.6, 6) * rng.choice([-1, 1], 6)
        al = rng.uniform(0.4, 2.7, 6) * rng.choice([-1, 1], 6)
        al[1], al[2] = rng.choice([0.0, np.pi]), rng.choice([0.0, np.pi])
        a[4] = 0.0
        if convention == "modified":
            a, al = np.r_[rng.uniform(-0.2, 0.2), a[:5]], np.r_[rng.uniform(-1, 1), al[:5]]
        for i in range(6):
            rows[i]["a"], rows[i]["alpha"] = a[i], al[i]
    base, tool = np.eye(4), np.eye(4)
    base[:3, :3], base[:3, 3] = matrix_from_rpy(rng.uniform(-1, 1, 3)), rng.uniform(-0.2, 0.2, 3)
    tool[:3, :3], tool[:3, 3] = matrix_from_rpy(rng.uniform(-1, 1, 3)), rng.uniform(-0.1, 0.1, 3)
    return DHTable(f"Arm-{seed}", convention, tuple(DHLink(**r) for r in rows), base=base, tool=tool)


def random_poses(robot, seed, k=6):
    rng = np.random.default_rng(seed)
    out = []
    for _ in range(k):
        q = rng.uniform(-np.pi, np.pi, robot.n)
        q[np.abs(robot.poe.Slist[:3]).sum(axis=0) < 0.5] *= 0.15  # prismatic: ±0.5 m
        out.append(robot.frame_pose(q))
    return out


@settings(**SETTINGS)
@given(st.integers(0, 2**31), st.sampled_from(["standard", "modified"]), st.integers(1, 7),
       st.booleans())
def test_random_arms_kinematics_and_dynamics(build, seed, convention, n, prismatic):
    kinds = "".join("P" if (prismatic and i % 2 == 1) else "R" for i in range(n))
    robot = robokit.load(random_table(seed, convention, kinds))
    check_dynamics_and_kinematics(robot, build(robot), samples=4, seed=seed)


@settings(**{**SETTINGS, "max_examples": 5})
@given(st.integers(0, 2**31), st.sampled_from(["standard", "modified"]),
       st.sampled_from(["RRR", "RRP", "RPR", "PRR", "RPP", "PPR", "PRP", "PPP"]), st.booleans())
def test_random_spherical_wrist_arms_ik(build, seed, convention, kinds, oblique):
    robot = robokit.load(random_table(seed, convention, kinds + "RRR", "wrist", oblique=oblique))
    kind = ik_analytic_kind(robot)
    assume(kind.method is not None)  # right-angled twists can confine the wrist centre to a surface
    assert kind.method == "spherical wrist"
    lib = build(robot)
    assert lib.has_ik
    check_ik(robot, lib, random_poses(robot, seed, k=4))


@pytest.mark.parametrize("kinds, cases", [
    ("RR", {"RR-quartic", "RR-a1", "RR-s1"}), ("PR", {"PR-quartic", "PR-c1"}), ("RP", {"RP-quartic", "RP-c1"}),
    ("PP", {"PP"})])
def test_every_pieper_case(build, kinds, cases):
    """Each case of Pieper's positioning equation (robokit.ik.pieper) is met and solved by the C:
    a1 = 0 / sin al1 = 0 / cos al1 = 0 variants of random arms."""
    seen = set()
    for convention in ("standard", "modified"):
        for seed in (11, 12):
            table = random_table(seed, convention, kinds + "RRRR", "wrist")
            rows = list(table.links)
            i1 = 0 if convention == "standard" else 1  # the row holding a1, al1
            for change in ({}, {"a": 0.0}, {"alpha": 0.0}, {"alpha": np.pi / 2}):
                rr = rows[:i1] + [replace(rows[i1], **change)] + rows[i1 + 1:]
                robot = robokit.load(DHTable("case", convention, tuple(rr), base=table.base, tool=table.tool))
                if ik_analytic_kind(robot).method != "spherical wrist":
                    continue
                case = closed_form_solver(robot).case
                if case in seen:
                    continue
                seen.add(case)
                check_ik(robot, build(robot), random_poses(robot, 7, k=6))
    assert seen == cases


@settings(**SETTINGS)
@given(st.integers(0, 2**31), st.sampled_from(["standard", "modified"]))
def test_random_three_parallel_axes_arms_ik(build, seed, convention):
    robot = robokit.load(random_table(seed, convention, "RRRRRR", "parallel"))
    assert ik_analytic_kind(robot).method == "three parallel axes"
    check_ik(robot, build(robot), random_poses(robot, seed))


def planar_table(seed, convention, n, prismatic=False):
    """A random planar arm: twists 0 or π (parallel or antiparallel axes), flips, base and tool."""
    rng = np.random.default_rng(seed)
    rows = [DHLink(joint="P" if prismatic else "R", a=rng.uniform(0.2, 0.7) * rng.choice([-1, 1]),
                   alpha=float(rng.choice([0.0, np.pi])), d=rng.uniform(-0.3, 0.3), theta=rng.uniform(-np.pi, np.pi),
                   qlim=np.sort(rng.uniform(-3.5, 3.5, 2)) if not prismatic else np.array([-0.5, 0.5]),
                   flip=bool(rng.integers(2)), mass=1.0) for _ in range(n)]
    base, tool = np.eye(4), np.eye(4)
    base[:3, :3], base[:3, 3] = matrix_from_rpy(rng.uniform(-1, 1, 3)), rng.uniform(-0.2, 0.2, 3)
    tool[:3, :3], tool[:3, 3] = matrix_from_rpy(rng.uniform(-1, 1, 3)), rng.uniform(-0.2, 0.2, 3)
    return DHTable(f"planar{n}", convention, tuple(rows), base=base, tool=tool)


@pytest.mark.parametrize("name, m", [("twolink", 1), ("rrr", 2)])
def test_planar_ik_matches_ik_analytic(models, build, name, m):
    robot = models[name]
    lib = build(robot)
    assert lib.has_ik and lib.max_solutions == m
    rng = np.random.default_rng(2)
    poses = [robot.frame_pose(robot.random_configuration(rng)) for _ in range(30)]
    check_ik(robot, lib, poses)
    if name == "rrr":  # stretched (one solution) and a pose off the plane (none)
        check_ik(robot, lib, [robot.frame_pose(np.array([0.4, 0.0, -0.3]))])
    lifted = poses[0].copy()
    lifted[2, 3] += 1e-6
    assert lib.ik(lifted) == [] and ik_analytic(robot, lifted) == []


@settings(**{**SETTINGS, "max_examples": 6})
@given(st.integers(0, 2**31), st.sampled_from(["standard", "modified"]), st.sampled_from([1, 2, 3]), st.booleans())
def test_random_planar_arms_ik(build, seed, convention, n, prismatic):
    robot = robokit.load(planar_table(seed, convention, n, prismatic and n == 1))
    assert ik_analytic_kind(robot).method == "planar"
    lib = build(robot)
    assert lib.has_ik and lib.max_solutions == (2 if n == 3 else 1)
    poses = random_poses(robot, seed + 1)  # (the table's seed would draw q from the same stream: often stretched)
    check_ik(robot, lib, poses)
    assert all(len(lib.ik(T)) == (2 if n == 3 else 1) for T in poses)
    lib32 = build(robot, float32=True)
    for T in poses:  # float: every solution reaches the pose to float's precision
        sols = lib32.ik(T.astype(np.float32).astype(float))
        assert len(sols) == (2 if n == 3 else 1)
        for q, *_ in sols:
            assert np.abs(robot.frame_pose(q) - T).max() < 1e-4


def test_planar_folded_arm_takes_wrist_ref(build):
    links = tuple(DHLink(joint="R", a=a, mass=1.0) for a in (0.5, 0.5, 0.2))
    robot = robokit.load(DHTable("folded", "standard", links))
    lib = build(robot)
    T = robot.frame_pose(np.array([0.7, np.pi, -0.4]))
    for ref in (0.0, 1.2):
        py = ik_analytic(robot, T, ref)
        c = lib.ik(T, wrist_ref=ref)
        assert len(py) == len(c) == 1 and py[0].degenerate and c[0][3]
        assert _dist(c[0][0], py[0].q, np.ones(3, bool)) < 1e-12 and abs(c[0][0][0] - ref) < 1e-12


def _reversed(table):
    """The chain of ``table`` read from the tool to the base, as a modified-DH table."""
    from robokit.ik._dh_chain import DHChain  # the test's own construction (as in tests/ik)

    rc = DHChain(table).reversed()
    rows = [DHLink(rc.kinds[0], 0.0, 0.0, rc.d0[0], rc.th0[0])]
    rows += [DHLink(rc.kinds[i], rc.a[i - 1], rc.alpha[i - 1], rc.d0[i], rc.th0[i]) for i in range(1, 6)]
    return DHTable(f"{table.name}_rev", "modified", tuple(rows), base=rc.base, tool=rc.tool)


@pytest.mark.parametrize("structure", ["wrist", "parallel"])
def test_structures_counted_from_the_tool(build, structure):
    robot = robokit.load(_reversed(random_table(3, "standard", "RRRRRR", structure)))
    kind = ik_analytic_kind(robot)
    assert "from the tool back to the base" in kind.reason
    lib = build(robot)
    assert lib.labels[0].endswith("(chain reversed)")
    check_ik(robot, lib, random_poses(robot, 5))


def test_limits_wider_than_pi_and_continuous_joints(build, models):
    table = random_table(21, "standard", "RRRRRR", "wrist")
    rows = list(table.links)
    rows[0] = replace(rows[0], qlim=np.array([0.0, 2 * np.pi]))
    rows[2] = replace(rows[2], qlim=np.array([-1.0, 1.0]))
    robot = robokit.load(DHTable("wide", "standard", tuple(rows)))
    lib = build(robot)
    q = np.array([4.5, 0.3, -0.2, 0.5, 0.7, 0.1])
    check_ik(robot, lib, [robot.frame_pose(q)] + random_poses(robot, 3))
    flags = [x[2] for T in random_poses(robot, 4, 10) for x in lib.ik(T)]
    assert True in flags and False in flags  # limits are checked both ways
    kin = models["kinova"]  # continuous joints 1, 4, 6: no limits, one angle each
    assert np.isinf(kin.qlim).any()
    check_dynamics_and_kinematics(kin, build(kin), samples=3)


# ------------------------------------------------------------------ names and the command line
def test_names():
    assert c_name("PUMA-560 arm") == "puma_560_arm"
    assert c_name("6dof") == "r6dof"
    assert c_name("x", "my_arm") == "my_arm"
    for bad in ("int", "9a", "a-b", ""):
        with pytest.raises(ValueError, match="--name"):
            c_name("x", bad)


def test_cli_writes_two_files_that_compile(tmp_path, cc, capsys):
    assert main(["codegen", "puma560", "-o", str(tmp_path)]) == 0
    assert sorted(p.name for p in tmp_path.iterdir()) == ["puma560.c", "puma560.h"]
    assert main(["codegen", "ur5", "-o", str(tmp_path), "--float32", "--name", "arm"]) == 0
    for stem, extra in (("puma560", []), ("arm", ["-Wdouble-promotion"])):
        subprocess.run([cc, "-std=c99", "-Wall", "-Wextra", "-Wpedantic", "-Werror", "-Wshadow", *extra, "-c",
                        str(tmp_path / f"{stem}.c"), "-o", str(tmp_path / f"{stem}.o")], check=True)
    assert "#define arm_HAS_IK 1" in (tmp_path / "arm.h").read_text()


def test_cli_gen3_lite_file(tmp_path, cc, capsys):
    """``robokit codegen`` on the Gen3 lite's URDF (a general 6R arm whose DH table is kilometres): the C
    finishes its solutions on the arm (NAME_g6_arm_finish), compiles with the strict flags and is the
    C generate_c writes for the robot the same file and tip load."""
    from shared_robots import gen3_lite

    path = DATA / "kinova" / "gen3_lite.urdf"
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", robokit.RobokitWarning)
        assert main(["codegen", str(path), "--tip", "end_effector_link", "-o", str(tmp_path)]) == 0
    text = (tmp_path / "gen3_lite.c").read_text()
    assert "nr = gen3_lite_g6_arm_finish(T, rows, lab, deg, nr);" in text
    assert text == generate_c(gen3_lite()).source
    subprocess.run([cc, "-std=c99", "-Wall", "-Wextra", "-Wpedantic", "-Werror", "-Wshadow", "-c",
                    str(tmp_path / "gen3_lite.c"), "-o", str(tmp_path / "gen3_lite.o")], check=True)


@pytest.mark.parametrize("args, message", [
    (["nosuch_robot"], "unknown robot"),
    (["puma560", "--name", "int"], "C keyword"),
    (["puma560", "--name", "2x"], "not a C identifier"),
])
def test_cli_bad_input_exits_2_and_writes_nothing(tmp_path, capsys, args, message):
    assert main(["codegen", args[0], "-o", str(tmp_path), *args[1:]]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith("robokit: error:") and message in err[0]
    assert list(tmp_path.iterdir()) == []


def test_cli_output_must_be_a_folder(tmp_path, capsys):
    f = tmp_path / "file.txt"
    f.write_text("x")
    assert main(["codegen", "puma560", "-o", str(f)]) == 2
    assert main(["codegen", "puma560", "-o", str(f / "sub")]) == 2  # a folder under a file
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 2 and all(e.startswith("robokit: error: -o:") and "is a file" in e for e in err)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["file.txt"]


def test_cli_creates_the_output_folder_and_its_parents(tmp_path, monkeypatch, capsys):
    """The docs' first example, ``robokit codegen puma560 -o out/``, in a folder without ``out``;
    and a nested folder whose parents do not exist either. A refused model creates no folder."""
    monkeypatch.chdir(tmp_path)
    assert main(["codegen", "puma560", "-o", "out/"]) == 0
    assert sorted(p.name for p in (tmp_path / "out").iterdir()) == ["puma560.c", "puma560.h"]
    assert main(["codegen", "twolink", "-o", "build/firmware/arm"]) == 0
    assert (tmp_path / "build/firmware/arm/twolink.h").is_file()
    assert main(["codegen", "nosuch_robot", "-o", "never"]) == 2
    assert not (tmp_path / "never").exists()
    assert "wrote" in capsys.readouterr().err


def test_urdf_file_and_generated_source_is_deterministic(tmp_path, build):
    from robokit.description.urdf_gen import urdf_from_dh

    table = random_table(8, "modified", "RRPRRR")
    path = tmp_path / "arm.urdf"
    path.write_text(urdf_from_dh(table))
    robot = robokit.load(path)
    assert generate_c(robot).source == generate_c(robokit.load(path)).source
    check_dynamics_and_kinematics(robot, build(robot), samples=3)


def test_the_documented_workspace_task_compiles(tmp_path, cc):
    """The RTOS-task example of docs/codegen.md (NAME_ik_ws with a static workspace) compiles with the
    strict flags against the general-6R Jaco's files."""
    from pathlib import Path

    doc = (Path(__file__).resolve().parents[2] / "docs" / "codegen.md").read_text(encoding="utf-8")
    task = re.search(r"```c\n(static jaco2_6n_ik_workspace.*?)```", doc, flags=re.S).group(1)
    write_c(generate_c(robokit.load(jaco2_table())), tmp_path)
    (tmp_path / "task.c").write_text('#include "jaco2_6n.h"\n' + task)
    subprocess.run([cc, "-std=c99", "-Wall", "-Wextra", "-Wpedantic", "-Werror", "-Wshadow",
                    "-c", str(tmp_path / "task.c"), "-o", str(tmp_path / "task.o")], check=True)


def test_the_documented_main_c_compiles_and_runs(tmp_path, cc):
    from pathlib import Path

    doc = (Path(__file__).resolve().parents[2] / "docs" / "codegen.md").read_text(encoding="utf-8")
    main_c = re.search(r"```c\n(/\* main\.c.*?)```", doc, flags=re.S).group(1)
    assert main(["codegen", "puma560", "-o", str(tmp_path)]) == 0
    (tmp_path / "main.c").write_text(main_c)
    exe = tmp_path / "main"
    subprocess.run([cc, "-std=c99", "-Wall", "-Wextra", "-Wpedantic", "-Werror", "-Wshadow", "-O2",
                    str(tmp_path / "main.c"), str(tmp_path / "puma560.c"), "-o", str(exe), "-lm"], check=True)
    out = subprocess.run([str(exe)], capture_output=True, text=True)
    assert out.returncode == 0, out.stdout
    lines = out.stdout.splitlines()
    assert len(lines) == 5 and all("solutions, chose" in line for line in lines)


def test_mjcf_with_armature(tmp_path, build):
    """An MJCF file (robokit's own export of the PUMA, whose drives give joint armature): the rotor
    inertia enters Pinocchio's rnea, and the C's."""
    try:
        from robokit.description.mjcf_write import mjcf_from_robot
    except ImportError:  # before the MJCF reader and writer were split
        from robokit.description.mjcf_write import mjcf_from_robot

    text, _ = mjcf_from_robot(robokit.load("puma560"))
    path = tmp_path / "puma.xml"
    path.write_text(text)
    robot = robokit.load(path)
    assert np.abs(np.asarray(robot.model.armature)).max() > 0.1
    lib = build(robot)
    check_dynamics_and_kinematics(robot, lib, samples=3)
    check_ik(robot, lib, random_poses(robot, 9, k=3))


def test_flipped_joints(build):
    """DH joints with ``flip: true`` (θ = offset − q): FK, dynamics, and — where robokit's
    ik_analytic solves flipped joints (it reaches the pose) — the IK."""
    t = robokit.load("puma560").dh
    links = [replace(l, flip=(i in (1, 3, 4))) for i, l in enumerate(t.links)]
    robot = robokit.load(DHTable("pflip", t.convention, tuple(links), base=t.base, tool=t.tool))
    lib = build(robot)
    check_dynamics_and_kinematics(robot, lib, samples=3)
    poses = random_poses(robot, 4, k=4)
    if all(np.abs(robot.frame_pose(s.q) - T).max() < 1e-9 for T in poses for s in ik_analytic(robot, T)):
        check_ik(robot, lib, poses)


# ------------------------------------------------------------------ general 6R (no special structure)
def jaco2_table():
    """Kinova JACO² 6-DOF non-spherical (offset wrist), classic DH from Kinova's "JACO² 6 DOF Advanced
    Specification Guide" (the arm of tests/ik/test_general_6r.py), with masses for the dynamics."""
    D1, D2, D3, D4, D5, D6, e2 = 0.2755, 0.4100, 0.2073, 0.0741, 0.0741, 0.1600, 0.0098
    aa = math.radians(30.0)
    k = math.sin(aa) / math.sin(2 * aa)
    alpha = [math.pi / 2, math.pi, math.pi / 2, 2 * aa, 2 * aa, math.pi]
    a = [0.0, D2, 0.0, 0.0, 0.0, 0.0]
    d = [D1, 0.0, -e2, -(D3 + k * D4), -(k * D4 + k * D5), -(k * D5 + D6)]
    return DHTable("jaco2_6n", "standard", tuple(
        DHLink("R", a=a[i], alpha=alpha[i], d=d[i], qlim=np.array([-2 * np.pi, 2 * np.pi]) if i % 2 else None,
               mass=0.5, com=np.array([0.0, 0.0, 0.05]), inertia=np.array([0.01, 0.01, 0.005, 0, 0, 0]))
        for i in range(6)))


@pytest.fixture(scope="module")
def jaco():
    return robokit.load(jaco2_table())


def test_general_6r_jaco_matches_ik_analytic(jaco, build):
    """The offset-wrist Jaco: the same solutions, order, labels and flags as ik_analytic, each
    reaching the pose through Pinocchio and the generated jaco2_6n_fk; FK/dynamics as Pinocchio."""
    assert ik_analytic_kind(jaco).method == "general 6R"
    lib = build(jaco)
    assert lib.has_ik and lib.max_solutions == 16
    h = (lib.path.parent / "jaco2_6n.h").read_text()
    assert "#define jaco2_6n_HAS_IK 1" in h and "#define jaco2_6n_MAX_SOLUTIONS 16" in h
    assert "Inverse kinematics: general 6R (Raghavan-Roth" in h  # the top comment says which method
    rng = np.random.default_rng(4)
    poses = [jaco.frame_pose(rng.uniform(-np.pi, np.pi, 6)) for _ in range(12)]
    poses.append(jaco.frame_pose(np.array([np.pi, 0.3, np.pi, -0.4, np.pi, 0.2])))  # angles at pi
    check_ik(jaco, lib, poses)
    assert sum(len(lib.ik(T)) for T in poses) >= 4 * len(poses)  # a non-trivial check: several each
    far = np.eye(4)
    far[:3, 3] = [3.0, 0.0, 0.0]
    assert lib.ik(far) == [] and ik_analytic(jaco, far) == []
    for bad in (np.nan, np.inf, 1e300):  # not a pose (Python raises): the C returns 0, it does not hang
        T = np.eye(4)
        T[0, 3] = bad
        assert lib.ik(T) == []
    check_dynamics_and_kinematics(jaco, lib, samples=3)


@settings(**{**SETTINGS, "max_examples": 3})
@given(st.integers(0, 2**31), st.sampled_from(["standard", "modified"]))
def test_general_6r_random_arms_match_ik_analytic(build, seed, convention):
    """Random 6R arms (random twists, lengths, offsets, flipped joints, base and tool) in both DH
    conventions: the C solves every pose as ik_analytic does."""
    robot = robokit.load(random_table(seed, convention, "RRRRRR"))
    assume(ik_analytic_kind(robot).method == "general 6R")
    check_ik(robot, build(robot), random_poses(robot, seed, k=8))


def test_general_6r_with_three_exactly_parallel_axes_matches_ik_analytic(build):
    """The SO-100 (axes 2–4 exactly parallel, axes 5 and 6 apart: the general 6R method, its tables built
    for the arm with the run turned and every root polished on the arm, robokit.ik.general_6r.PARALLEL_TURN):
    the C solves every pose as ik_analytic does — the turned tables, the arm's own chain — with the run
    stretched out at every third pose (two pairs of roots close together)."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", robokit.RobokitWarning)  # (its floating base, fixed: a note)
        robot = robokit.load("so100")
    assert ik_analytic_kind(robot).method == "general 6R"
    rng = np.random.default_rng(9)
    qs = [robot.random_configuration(rng) for _ in range(9)]
    for q in qs[::3]:
        q[2] *= 1e-3
    poses = [robot.frame_pose(q) for q in qs]
    lib = build(robot)
    check_ik(robot, lib, poses)
    assert sum(len(lib.ik(T)) for T in poses) >= 4 * len(poses)


@pytest.mark.parametrize("seed", [6, 7])
def test_general_6r_deflated_eigenproblem_matches_ik_analytic(build, seed):
    """Arms whose best reading has the four root pairs x = ±i (pivot farthest from the eliminated
    joint: the C's eigenvalue iteration runs on 16 × 16), and the Jaco's two pairs: the C solves
    every pose as ik_analytic does (both deflate; tests/ik checks the deflation against LAPACK)."""
    from robokit.ik import analytic_ik

    rng = np.random.default_rng(seed)
    robot = robokit.load(DHTable(f"d{seed}", "standard", tuple(
        DHLink("R", a=rng.uniform(-0.5, 0.5), alpha=rng.uniform(-np.pi, np.pi), d=rng.uniform(-0.5, 0.5),
               theta=rng.uniform(-np.pi, np.pi), qlim=(-2 * np.pi, 2 * np.pi)) for _ in range(6))))
    assert ik_analytic_kind(robot).method == "general 6R"
    best = analytic_ik(robot).solver.elim.arrangements[0]
    assert (best.piv, best.deflate) == (2, 4)
    lib = build(robot)
    text = (lib.path.parent / f"{lib.name}.c").read_text()  # the C's first reading deflates four pairs
    assert re.search(r"_g6_readings\[\d\] = \{\n    \{\{[\d, ]+\}, \d, \d, \d, \d, 4, 0, ", text)
    check_ik(robot, lib, [robot.frame_pose(rng.uniform(-np.pi, np.pi, 6)) for _ in range(12)])


def _pose_gap(robot, q, T):
    """|(ω; v)| taking the tip's pose at q to T (root axes, v of the tip's origin: the geometric Jacobian's)."""
    P = robot.frame_pose(q)
    R = T[:3, :3] @ P[:3, :3].T
    w = 0.5 * np.array([R[2, 1] - R[1, 2], R[0, 2] - R[2, 0], R[1, 0] - R[0, 1]])
    return float(np.hypot(np.linalg.norm(w), np.linalg.norm(T[:3, 3] - P[:3, 3])))


def _conditioned(robot):
    """The joints' tolerance between Python's solution s and the C's q of one root, near a singular
    configuration: two solutions of one root whose poses are e₁ and e₂ off T differ, to first order, by
    (e₁ + e₂)/σ in the joints (σ the Jacobian's smallest singular value there): the polish stops at
    1e-12 of pose error (ARM_STOP), or where Newton stalls near a fold, up to 1e-10 (ARM_ACCEPT), and C and
    Python start it from the general 6R method's rows, which differ in their last digits (C's LAPACK-free
    eigenproblem). With σ down to 4e-8 at these poses, 1e-12/σ alone is 2.5e-5 rad. Twice that bound
    (the second-order term near a fold), at least 1e-9."""
    def tol(T, s, q):
        sigma = np.linalg.svd(robot.jacobian(s.q), compute_uv=False)[-1]
        return max(1e-9, 2.0 * (_pose_gap(robot, s.q, T) + _pose_gap(robot, q, T) + 2e-16) / sigma)
    return tol


def test_gen3_lite_c_near_its_elbow_singularity(build):
    """The Kinova Gen3 lite (axes 2 and 3 7.3e-6 rad from parallel: its DH table's offsets -38 km, which
    reproduce the arm only to ~1e-11 m): Python finishes every general 6R solution on the arm's own
    kinematics (robokit.ik.general_6r.ArmPolish), the C the same way (NAME_g6_arm_finish with the
    calibrated arm's NAME_cal_polish). With θ₃ within 2e-4 rad of its elbow singularity the C returns
    ik_analytic's solutions — the same count, order, labels and flags —, each reaching the pose to 1e-9
    (Pinocchio), the generating configuration among them; the joints agree to 1e-9 or, near singular
    configurations, to what their conditioning allows (_conditioned). Before, the C polished on the DH
    table only: its count differed from Python's at every one of these 15 poses, 4 of its solutions were
    1e-9 off the pose, and none was the generating configuration (1e-7 to 3e-6 rad off)."""
    from shared_robots import elbow_singular, gen3_lite

    robot = gen3_lite()
    lib = build(robot)
    rng = np.random.default_rng(0)
    poses, qs = [], []
    for _ in range(15):
        q = robot.random_configuration(rng)
        q[2] = elbow_singular(robot, q) + rng.uniform(-2e-4, 2e-4)
        poses.append(robot.frame_pose(q))
        qs.append(q)
    check_ik(robot, lib, poses, tol=_conditioned(robot))
    rev = [True] * 6
    for q, T in zip(qs, poses):
        assert min(_dist(x[0], q, rev) for x in lib.ik(T)) < 1e-7, "the generating configuration is missing"
    text = (lib.path.parent / f"{lib.name}.c").read_text()
    assert f"{lib.name}_g6_arm_finish(T, rows, lab, deg, nr);" in text


def test_gen3_lite_c_random_poses(build):
    """The Gen3 lite at random configurations (away from its elbow singularity): the C returns
    ik_analytic's solutions to 1e-9 in the joints, each reaching the pose to 1e-9."""
    from shared_robots import gen3_lite

    robot = gen3_lite()
    rng = np.random.default_rng(1)
    check_ik(robot, build(robot), [robot.frame_pose(robot.random_configuration(rng)) for _ in range(15)])


def test_general_6r_root_at_the_half_angle_infinity(jaco, build):
    """A solution with the eigenvalue joint exactly at the half-angle variable's infinity (θ = γ + π):
    A is singular, Python takes the generalised eigenproblem (QZ), the C the turned variable; both
    must find it."""
    from robokit.ik import analytic_ik

    sv = analytic_ik(jaco).solver.export_constants()
    th0 = sv["th0"]
    for reading in (0, 1):
        pivot = int(sv["arrangements"][reading]["roles"][0])
        q = np.array([0.4, -0.7, 1.1, 0.5, -0.9, 0.3])
        q[pivot] = math.remainder(sv["gamma"] + math.pi - th0[pivot], 2 * math.pi)
        T = jaco.frame_pose(q)
        lib = build(jaco)
        check_ik(jaco, lib, [T])
        if reading == 0:  # the generating configuration is among the C's solutions
            assert min(_dist(c[0], q, np.ones(6, bool)) for c in lib.ik(T)) < 1e-7


def test_general_6r_float32_has_no_ik_and_says_why(jaco, build, nm):
    lib = build(jaco, float32=True)
    assert not lib.has_ik
    h = (lib.path.parent / "jaco2_6n.h").read_text()
    assert "#define jaco2_6n_HAS_IK 0" in h and "general 6R" in h and "double only" in h
    check_dynamics_and_kinematics(jaco, lib, samples=2)
    for f32 in (False, True):  # only math functions, with and without the IK
        obj = build(jaco, float32=f32).path.with_suffix(".o")
        out = subprocess.run([nm, "-u", str(obj)], capture_output=True, text=True, check=True).stdout
        undefined = {line.split()[-1] for line in out.splitlines() if line.strip()}
        assert undefined <= MATH, undefined - MATH


def _poly_library(cc, folder, e, entry):
    """The emitter ``e``'s polynomial helpers (prefix ``t``) with the C function ``entry``, compiled and loaded."""
    import ctypes

    code = "#include <math.h>\n#include <string.h>\n" + e.poly_helpers() + "\n" + entry
    (folder / "q.c").write_text(code)
    subprocess.run([cc, "-std=c99", "-O1", "-fPIC", "-shared", "-Wno-unused-function", str(folder / "q.c"),
                    "-o", str(folder / "q.so"), "-lm"], check=True)
    return ctypes.CDLL(str(folder / "q.so"))


def test_quartic_root_finder_against_numpy(cc, tmp_path):
    """The generated quartic solver (Ferrari's closed form, its numerical fallback for nearly
    biquadratic quartics) against numpy's companion-matrix roots: random quartics, biquadratics
    (q = 0 exactly: the fallback), double roots and four close real roots."""
    import ctypes

    from robokit.codegen.ik import _Emitter, _Tol

    e = _Emitter.__new__(_Emitter)
    e.P, e.tol = "t", _Tol(False)
    lib = _poly_library(cc, tmp_path, e, "int roots4(const double c[5], double out[5])\n{\n"
                        "    int n = t_quartic_roots(c, out);\n    return n >= 0 ? n : t_real_roots(c, 4, out, 1e-15);\n}\n")
    P = ctypes.POINTER(ctypes.c_double)
    rng = np.random.default_rng(5)
    cases = [rng.normal(size=5) * 10.0 ** rng.uniform(-2, 2) for _ in range(300)]
    cases += [np.poly([r1, -r1, r2, -r2])[::-1] * s for r1, r2, s in rng.uniform(-3, 3, (40, 3))]  # q = 0
    cases += [np.poly([r, r, r + 1.5, r - 2.0])[::-1] for r in rng.uniform(-2, 2, 20)]  # a double root
    cases += [np.poly(r + np.array([0.0, 0.01, 0.02, 0.03]))[::-1] for r in rng.uniform(-2, 2, 20)]
    for c in cases:
        c = np.ascontiguousarray(c, dtype=float)
        out = np.zeros(5)
        n = lib.roots4(c.ctypes.data_as(P), out.ctypes.data_as(P))
        ref = np.roots(c[::-1])
        real = np.sort(ref[np.abs(ref.imag) <= 1e-6 * (1 + np.abs(ref.real))].real)
        got = out[:n]
        assert np.all(np.diff(got) >= 0.0)  # increasing
        for x in got:  # every root found is a root
            assert abs(np.polyval(c[::-1], x)) <= 1e-9 * np.abs(c).max() * max(1.0, abs(x)) ** 4
        for x in real:  # and no real root is missed (a double root may come once or twice)
            assert np.min(np.abs(got - x)) <= 1e-6 * (1 + abs(x)), (c, real, got)


def test_quartic_fold_starts_against_numpy(cc, tmp_path):
    """The calibrated arm's quartic solver also gives the real parts of the complex pairs near the real
    line (its fold starts: |Im 2 atan(t)| within closed_form.FOLD_IMAG), increasing: against numpy's
    companion-matrix roots and robokit's own kernel (``closed_form._roots``) on random quartics with a
    pair placed near the real line."""
    import ctypes
    import types

    from robokit.codegen.ik import _Emitter, _Tol
    from robokit.kernels import closed_form as kcf

    e = _Emitter.__new__(_Emitter)
    e.P, e.tol, e.fold = "t", _Tol(False), True
    e.k = types.SimpleNamespace(pieper=types.SimpleNamespace(kinds="RRRRRR"),
                                calibrated={"fold_imag": kcf.FOLD_IMAG})
    lib = _poly_library(cc, tmp_path, e, "int near4(const double c[5], double out[4], double near[2])\n{\n"
                        "    int nn;\n    return t_quartic_roots(c, out, near, &nn) < 0 ? -1 : nn;\n}\n")
    P = ctypes.POINTER(ctypes.c_double)
    rng = np.random.default_rng(6)
    checked = near_found = 0
    for _ in range(400):
        a, b = rng.normal(), 10.0 ** rng.uniform(-3, 0)  # a pair a ± ib, and two more roots (real or a pair)
        rest = rng.normal(size=2) if rng.uniform() < 0.5 else rng.normal() + np.array([1j, -1j]) * rng.uniform(0.01, 2)
        c = np.ascontiguousarray(np.real(np.poly([a + 1j * b, a - 1j * b, *rest]))[::-1] * rng.uniform(0.5, 5))
        out, near = np.zeros(4), np.zeros(2)
        nn = lib.near4(c.ctypes.data_as(P), out.ctypes.data_as(P), near.ctypes.data_as(P))
        if nn < 0:
            continue  # (Ferrari not trusted: the numerical fallback, which gives no fold starts)
        ref = np.roots(c[::-1])
        im = np.abs(np.arctanh(np.minimum(2 * ref.imag / (1 + ref.real ** 2 + ref.imag ** 2), 1 - 1e-16)))
        sure = (ref.imag > 1e-6 * (1 + np.abs(ref.real))) & (np.abs(im - kcf.FOLD_IMAG) > 1e-9)
        want = np.sort(ref.real[sure & (im < kcf.FOLD_IMAG)])
        if np.any((ref.imag > 0) & (np.abs(im - kcf.FOLD_IMAG) <= 1e-9)):
            continue  # on the margin itself: either answer is right
        checked += 1
        near_found += len(want) > 0
        assert nn == len(want), (c, ref, near[:nn])
        assert np.allclose(near[:nn], want, rtol=1e-6, atol=1e-9)
        fold, roots = np.array([np.inf, 1.0, 0.0]), np.zeros(6)  # the kernel's (its x3 = 2 atan t)
        n = kcf._roots(c, 4, True, roots, fold)
        assert n - int(fold[2]) == nn
        assert np.allclose(roots[int(fold[2]):n], 2 * np.arctan(want), atol=1e-9)
    assert checked >= 300 and near_found >= 100


@pytest.mark.parametrize("arm", ["puma_offset", "ur5_tilt"])
def test_general_6r_almost_special_arms(build, arm, tmp_path, cc):
    """Special arms made general by a tiny change — the PUMA's axes 4 and 5 1 µm apart, the UR5's
    axis 3 tilted by a milliradian —: badly conditioned readings (the next ones are solved too),
    solutions close together; the C still agrees with ik_analytic (general 6R with nominal=False)."""
    t = robokit.load("puma560").dh if arm == "puma_offset" else None
    if arm == "puma_offset":
        rows = [replace(l, a=l.a + (1e-6 if i == 3 else 0.0)) for i, l in enumerate(t.links)]
        table = DHTable("puma_eps", t.convention, tuple(rows), base=t.base, tool=t.tool)
    else:
        import importlib

        u2d = importlib.import_module("robokit.description.urdf_to_dh")
        extract = getattr(u2d, "dh_from_urdf", None) or u2d.urdf_to_dh  # the newer name where it exists
        u = extract(robokit.load("ur5"), "standard").table
        rows = [replace(l, alpha=l.alpha + (1e-3 if i == 1 else 0.0)) for i, l in enumerate(u.links)]
        table = DHTable("ur5_tilt", "standard", tuple(rows), base=u.base, tool=u.tool)
    robot = robokit.load(table)
    assert ik_analytic_kind(robot, nominal=False).method == "general 6R"
    rng = np.random.default_rng(6)
    poses = [robot.frame_pose(np.array([0.3, -0.6, 0.4, 0.8, 0.7, -0.5]))]
    poses += [robot.frame_pose(rng.uniform(-3, 3, 6)) for _ in range(3)]
    from robokit.codegen.build import compile_library

    lib = compile_library(generate_c(robot, nominal=False), tmp_path, robot.n, flags=("-O1",), compiler=cc)
    check_ik(robot, lib, poses, nominal=False)
    # by default the structure is detected: the polished closed form, in C as in Python
    assert ik_analytic_kind(robot).method.startswith("calibrated")
    check_ik(robot, build(robot), poses)


def test_float32_quartic_arm(build):
    """--float32 on a spherical-wrist arm whose positioning equation is the quartic (Ferrari's closed
    form in float: cbrtf, acosf; compiled with -Wdouble-promotion): every float solution is near one
    of ik_analytic's, and the counts agree on most poses."""
    rng = np.random.default_rng(11)
    rows = [DHLink("R", 0.0 if i in (3, 4) else rng.uniform(0.1, 0.5), rng.uniform(0.5, 2.5),
                   0.0 if i == 4 else rng.uniform(-0.4, 0.4), rng.uniform(-np.pi, np.pi)) for i in range(6)]
    robot = robokit.load(DHTable("quartic_arm", "standard", tuple(rows)))
    assert getattr(closed_form_solver(robot), "deg", 2) == 4
    lib = build(robot, float32=True)
    rng = np.random.default_rng(2)
    same = 0
    for _ in range(20):
        T = robot.frame_pose(robot.random_configuration(rng))
        py, c = ik_analytic(robot, T), lib.ik(T)
        same += len(c) == len(py)
        for q, *_ in c:
            assert min(_dist(q, s.q, np.ones(6, bool)) for s in py) < 1e-2
    assert same >= 18


# ------------------------------------------------------------------ calibrated arms (robokit.ik.calibrated)
def calibrated_arm(name_or_table, seed):
    """The nominal arm with every joint placement, the base and the tool off by up to 2 mrad / 2 mm, built
    the way robokit.calibrate builds its result (robot_from_chain: the nominal recorded on it)."""
    from robokit.calibration import chain_from_robot, robot_from_chain

    nominal = robokit.load(name_or_table)
    delta = np.random.default_rng(seed).uniform(-2e-3, 2e-3, (nominal.n + 1, 6))
    return robot_from_chain(nominal, chain_from_robot(nominal).perturbed(delta))


@pytest.fixture(scope="module")
def calibrated_arms():
    pieper = random_table(7, "standard", "RRRRRR", structure="wrist")
    return {"puma560": calibrated_arm("puma560", 1), "ur5": calibrated_arm("ur5", 2),
            "pieper": calibrated_arm(pieper, 3)}


def random_and_wrist_singular_poses(robot, seed, n):
    """n poses of random configurations, then 4 with joint 5 within 2 mrad of zero (the wrist of a
    spherical-wrist or UR arm near singular), from default_rng(seed)."""
    rng = np.random.default_rng(seed)
    poses = [robot.frame_pose(robot.random_configuration(rng)) for _ in range(n)]
    for _ in range(4):
        q = robot.random_configuration(rng)
        q[4] = rng.uniform(-2e-3, 2e-3)
        poses.append(robot.frame_pose(q))
    return poses


@pytest.mark.parametrize("name", ["puma560", "ur5", "pieper"])
def test_calibrated_arm_ik_matches_ik_analytic(calibrated_arms, build, name):
    """NAME_ik of a calibrated arm: the projected arm's closed form and Newton's method on NAME_fk give
    ik_analytic's solutions, in its order, to 1e-9 — near-singular poses (θ₅ within 2 mrad) included, and (the
    Pieper arm) four poses where fold starts give solutions."""
    robot = calibrated_arms[name]
    assert ik_analytic_kind(robot).method.startswith("calibrated")
    lib = build(robot)
    assert lib.has_ik and lib.max_solutions == 16
    poses = random_and_wrist_singular_poses(robot, 4, 20)
    if name == "pieper":  # and poses whose solutions include a fold start's (default_rng(500), these draws)
        rng = np.random.default_rng(500)
        draws = [robot.random_configuration(rng) for _ in range(2715)]
        folds = [robot.frame_pose(draws[i]) for i in (525, 1379, 1588, 2714)]
        assert all(fold_starts(robot, T)[0] > 0 for T in folds)
        poses += folds
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", robokit.RobokitWarning)
        check_ik(robot, lib, poses)


#: Configurations of the calibrated PUMA 560 (calibrated_arms) whose wrist centre lies just inside the
#: projected arm's cylinder about axis 1 (the shoulder offset d₃): there its closed form had no start, at
#: the pose nor moved toward or away from the shoulder point (15 of 3,000 random configurations,
#: default_rng(11)); the last one's wrist centre is at the outer sphere too.
PUMA_SIDEWAYS = [
    [-2.2736673832417282, -1.8508929114442656, -0.9755820128771249, 2.1087669776932323, -0.02380995266963981, 3.2769156584550707],
    [-0.3711870360892844, 1.4942012395642066, -1.3687404600895055, -4.20110488334455, 0.2182967221543055, -1.2665261099804153],
    [0.3434470355985204, -1.7385419580514254, -1.2091317244155273, -4.53344064017413, -1.3284287196954172, 1.9182351278936078],
    [-1.3126189330474625, -1.3465539982518495, -1.90839884457737, -1.1505072270381564, -0.41075998791346313, 0.9550873468707257],
    [-1.8366931198109024, -1.573091540549726, -1.4758291392626957, -0.6941753237198549, 1.4630947206871052, -4.614970825427825],
]


def test_calibrated_puma_beside_its_shoulder_cylinder(calibrated_arms, build):
    """At those poses the relaxed poses moved away from axis 1 (and at a corner also toward the shoulder)
    give the starts: ik_analytic's own path returns solutions (not the general 6R method's), each reaching
    the pose through Pinocchio, the generating configuration among them, nothing a numerical sweep finds
    missing; and the generated C returns the same solutions in the same order (before: none)."""
    from robokit.ik.closed_form import analytic_ik
    from robokit.kernels.ik import solve_poe_ik

    robot = calibrated_arms["puma560"]
    cal = analytic_ik(robot).calibrated
    lib = build(robot)
    rev = np.ones(6, bool)
    rng = np.random.default_rng(0)
    poe = robot.poe
    hits = 0
    for q in PUMA_SIDEWAYS:
        T = np.ascontiguousarray(robot.frame_pose(np.array(q)))
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", robokit.RobokitWarning)
            own = cal._solve_checked(T, 0.0)
            sols = ik_analytic(robot, T)
        assert own and [s.label for s in own] == [s.label for s in sols]
        assert not any(s.label.startswith("solution ") for s in sols)
        assert min(_dist(s.q, q, rev) for s in sols) < 1e-7
        for s in sols:
            assert np.abs(robot.frame_pose(s.q) - T).max() < 1e-9
        unlimited = np.array([[-np.inf, np.inf]] * 6)
        for k in range(100):  # a sweep: every root it finds is returned
            qs, ok = solve_poe_ik(poe.M, poe.Slist, T, rng.uniform(-np.pi, np.pi, 6), unlimited, 1e-12, 100, 0, k)[:2]
            if ok and np.abs(robot.frame_pose(np.angle(np.exp(1j * qs))) - T).max() < 1e-9:
                assert min(_dist(s.q, qs, rev) for s in sols) < 1e-6
                hits += 1
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", robokit.RobokitWarning)
            check_ik(robot, lib, [T])
    assert hits > 100  # the sweep converged from many of its starts


def test_calibrated_ur5_near_its_wrist_singularity_theta6_where_the_elbow_reaches(build):
    """The suite's calibrated UR5 (tests/calibration) at the poses where, near the wrist's singularity, the
    projected arm's θ₆ makes every elbow miss (calibrated_folds.UR5_FREE_WRIST): Python's calibrated path
    takes θ₆ where the elbow comes nearest reaching (closed_form.FREE_WRIST), and the generated C
    (NAME_free_t6) returns the same solutions in the same order (before: Python the general 6R method's,
    the C none)."""
    from calibrated_folds import UR5_FREE_WRIST
    from shared_robots import calibrated

    robot = calibrated("ur5", 2)[1]
    lib = build(robot)
    assert "_free_t6(" in (lib.path.parent / f"{lib.name}.c").read_text()
    poses = [robot.frame_pose(np.array(q)) for q in UR5_FREE_WRIST]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", robokit.RobokitWarning)
        for T in poses:
            sols = ik_analytic(robot, T)
            assert sols and not any(s.label.startswith("solution ") for s in sols)
            assert len(lib.ik(T)) == len(sols)
        check_ik(robot, lib, poses)


def test_calibrated_pieper_fold_positions_wrist_matches_ik_analytic(build):
    """The benchmark's calibrated random Pieper arm where a fold position's oblique wrist misses by more
    than FOLD_STARTS but within FOLD_POSITION_WRIST (shared_robots.PIEPER_FOLD_POSITION_WRIST): the C's
    NAME_wrist takes the wider window there too, and returns ik_analytic's solutions in its order — the
    generating configuration among them (before: both missing, in Python and in the C)."""
    from shared_robots import PIEPER_FOLD_POSITION_WRIST, benchmark_arms_off_by

    robot = benchmark_arms_off_by(2e-3)["pieper"]
    q = np.array(PIEPER_FOLD_POSITION_WRIST)
    T = robot.frame_pose(q)
    lib = build(robot)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", robokit.RobokitWarning)
        check_ik(robot, lib, [T])
    assert min(_dist(c[0], q, np.ones(6, bool)) for c in lib.ik(T)) < 1e-7


@pytest.mark.parametrize("name, q", ODD_DOUBLE, ids=[n for n, _ in ODD_DOUBLE])
def test_calibrated_double_root_is_one_solution_in_c(build, name, q):
    """Where Newton's method reached one double root twice (shared_robots.ODD_DOUBLE: an odd number of
    solutions, two of them 1.0e-7 and 2.4e-7 apart), NAME_cal_double keeps one, as the kernel does: the C
    returns ik_analytic's solutions in its order (before: one more, in both)."""
    from shared_robots import odd_arm

    robot = odd_arm(name)
    T = robot.frame_pose(np.array(q))
    lib = build(robot)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", robokit.RobokitWarning)
        check_ik(robot, lib, [T])
        assert len(lib.ik(T)) % 2 == 0


def test_calibrated_odd_count_in_c_lacks_only_the_general_methods_root(build):
    """Where the calibrated path finds an odd number of solutions (shared_robots.ODD_MISSING) ik_analytic adds
    the general 6R method's missing root, which the C does not have: the C returns every other solution
    of ik_analytic, in its order, and an odd number (the caller can tell: a calibrated arm of revolute
    joints has an even number)."""
    from shared_robots import odd_arm

    for name, q in ODD_MISSING:
        robot = odd_arm(name)
        T = robot.frame_pose(np.array(q))
        lib = build(robot)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", robokit.RobokitWarning)
            py = ik_analytic(robot, T)
            c = lib.ik(T)
            check_ik(robot, lib, [T])
        assert len(c) == len(py) - 1 and len(c) % 2 == 1 and py[-1].label.startswith("solution ")


def test_a_real_ur5e_factory_calibration_ik_matches_ik_analytic(build):
    """A UR5e as its owner has it (Universal Robots' xacro package with that robot's factory calibration,
    tests/data/ur_calibration): detected as nearly a three-parallel-axes arm; its NAME_ik returns
    ik_analytic's solutions, in order, to 1e-9, on 30 random poses and 4 with the wrist near singular."""
    robot = factory_ur5e()
    assert ik_analytic_kind(robot).method == "calibrated three parallel axes"
    lib = build(robot)
    assert lib.has_ik and lib.max_solutions == 16
    poses = random_and_wrist_singular_poses(robot, 8, 30)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", robokit.RobokitWarning)
        check_ik(robot, lib, poses)


def test_calibrated_ik_without_the_full_search(cc, tmp_path):
    """-DNAME_IK_FULL_SEARCH=0 (a shorter worst case on a controller: no search from the branches'
    solutions, no curve): every solution is one of ik_analytic's (to 1e-9, each reaching the pose); a
    solution is missing only at a pose where the search ran, i.e. where ik_analytic flags solutions
    degenerate — on the benchmark's calibrated PUMA 560 at 60 random poses and at the two poses near a
    singular position with ten roots (tests/calibration/test_calibrated_ik.py), where it lacks some."""
    from robokit.calibration import chain_from_robot, robot_from_chain
    from robokit.codegen.build import compile_library

    nominal = robokit.load("puma560")
    robot = robot_from_chain(nominal, chain_from_robot(nominal).perturbed(
        np.random.default_rng(0).uniform(-2e-3, 2e-3, (7, 6))))
    src = generate_c(robot)
    lib = compile_library(src, tmp_path, robot.n, flags=("-O1", f"-D{src.name}_IK_FULL_SEARCH=0"), compiler=cc)
    rev = np.abs(robot.poe.Slist[:3]).sum(axis=0) > 0.5
    rng = np.random.default_rng(21)
    fewer = 0
    special = [[0.3587434740072251, -3.6391722332065934, 1.6136949688695033, -2.063132292035656,
                0.010862402481855061, 1.8460531463552783],
               [-0.1745264778795888, 2.693780413081057, 2.236503694696615, 0.8281856202382324, -3.733881126767151,
                -2.7628273760039477]]
    for k, q0 in enumerate(special + [robot.random_configuration(rng) for _ in range(60)]):
        T = robot.frame_pose(np.asarray(q0))
        py, c = ik_analytic(robot, T), lib.ik(T)
        for q, label, _, _ in c:  # (a root the search finds can come with another search point's label)
            assert min(_dist(q, s.q, rev) for s in py) < 1e-9, label
            assert np.abs(robot.frame_pose(q) - T).max() < 1e-9
        if len(c) < len(py):
            assert any(s.degenerate for s in py)
        if k < 2:
            assert len(py) == 10
            fewer += len(c) < 10
    assert fewer == 2


@pytest.mark.parametrize("name", ["puma560", "ur5"])
def test_calibrated_arm_float32_ik(calibrated_arms, build, name):
    """--float32: every C solution is within 1e-3 rad of ik_analytic's solution of the same branch and
    reaches the pose to 1e-5 (relative to the reach); the counts agree on most poses."""
    robot = calibrated_arms[name]
    lib = build(robot, float32=True)
    rng = np.random.default_rng(5)
    full = 0
    for _ in range(20):
        T = robot.frame_pose(robot.random_configuration(rng))
        py, c = ik_analytic(robot, T), lib.ik(T)
        full += len(c) == len(py)
        for q, label, *_ in c:
            ref = [s for s in py if s.label.startswith(label)]
            assert ref and min(_dist(q, s.q, np.ones(robot.n, bool)) for s in ref) < 1e-3
            assert np.abs(robot.frame_pose(q) - T).max() < 1e-5 * max(1.0, float(np.abs(T[:3, 3]).max()))
    assert full >= 18


def test_cli_codegen_and_teach_of_a_calibrated_urdf(calibrated_arms, tmp_path, cc):
    """robokit codegen arm_calibrated.urdf: NAME_HAS_IK 1 and, compiled with the strict flags, the
    solutions of ik_analytic for the robot loaded from that file; robokit teach loads it."""
    from robokit.codegen.build import CLibrary

    robot = calibrated_arms["puma560"]
    urdf = robot.save(tmp_path / "arm_calibrated.urdf")
    (tmp_path / "c").mkdir()
    assert main(["codegen", str(urdf), "-o", str(tmp_path / "c")]) == 0
    name = c_name(robokit.load(str(urdf)).name)
    header = (tmp_path / "c" / f"{name}.h").read_text()
    assert f"#define {name}_HAS_IK 1" in header and "calibrated spherical wrist" in header
    so = tmp_path / "c" / f"{name}.so"
    subprocess.run([cc, "-std=c99", "-Wall", "-Wextra", "-Wpedantic", "-Werror", "-Wshadow", "-O1", "-fPIC",
                    "-shared", str(tmp_path / "c" / f"{name}.c"), "-o", str(so), "-lm"], check=True)
    loaded = robokit.load(str(urdf))
    src = generate_c(loaded)
    lib = CLibrary(so, src, loaded.n, False)
    rng = np.random.default_rng(8)
    check_ik(loaded, lib, [loaded.frame_pose(loaded.random_configuration(rng)) for _ in range(8)])
    page = tmp_path / "teach.html"
    assert main(["teach", str(urdf), "-o", str(page)]) == 0
    assert page.stat().st_size > 1000


@pytest.mark.parametrize("name", ["puma560", "KUKA KR 210 L150"])
def test_wrist_near_its_singularity_is_exact_in_c(build, name):
    """θ₅ within 3e-10..1e-6 rad of the wrist singularity, where θ₄ and θ₆ are each taken from a vector of
    length ~θ₅: NAME_wrist takes θ₆ from what θ₄ and θ₅ leave of the whole rotation and |sin θ₅| from the
    wrist direction across axis 4, as the kernel does (closed_form._wrist_angles). Every C solution reaches
    the pose to 1e-9 (Pinocchio) and equals ik_analytic's, in order (before: KUKA's KR 210 as its maker
    publishes it, 1.6e-7 off the pose at θ₅ = 1e-9 and 1e-6 at 1e-10)."""
    if name == "puma560":
        robot = shared_robot("puma560")
    else:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", robokit.RobokitWarning)  # (its meshes and inertias are not in the test data)
            robot = robokit.load(DATA / "kuka" / "kuka_kr210_support" / "urdf" / "kr210l150.xacro")
    lib = build(robot)
    rng = np.random.default_rng(11)
    for q5 in (3e-10, 1e-9, 1e-8, 1e-7, 1e-6):
        poses = []
        for _ in range(4):
            q = robot.random_configuration(rng)
            q[4] = q5 * rng.choice([-1.0, 1.0])
            poses.append(robot.frame_pose(q))
        # every C solution reaches its pose to 1e-9 (check_ik); θ₄ and θ₆ themselves are fixed by the pose only
        # to about the rounding of the wrist's orientation (the C's and Python's θ₁..θ₃ agree to ~1e-15) over θ₅
        # (their sum is well fixed), so that is how far C and Python can differ in those two joints
        check_ik(robot, lib, poses, tol=1e-9 + 1e-14 / q5)
