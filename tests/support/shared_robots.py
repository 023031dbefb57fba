"""Robots loaded once per test process, for the tests that only read them.

A Robot never changes after ``robokit.load`` returns it (docs/caches.md), so a test that computes
with a robot (FK, Jacobians, dynamics, IK, pages) may use the one another test module loaded: loading
an example-robot-data arm reads and checks its meshes, seconds each (on the 2-core CI machine, under
load: ur5 about 3 s, panda 5 s, kinova 6.5 s, z1 8.5 s), and the suite loaded ur5 114 times and panda
52 times in-process. Tests of loading itself (its warnings, errors, notes, a fresh robot's derived
values) call ``robokit.load``. Imported as ``shared_robots`` (tests/conftest.py puts tests/support on
sys.path)."""
from __future__ import annotations

import functools

import robokit


@functools.cache
def robot(name: str) -> robokit.Robot:
    """``robokit.load(name)``, once per process and name."""
    return robokit.load(name)


DATA = __import__("pathlib").Path(__file__).resolve().parents[1] / "data"


@functools.cache
def factory_ur5e() -> robokit.Robot:
    """A real UR5e with its factory calibration (tests/data/ur_calibration), read through Universal Robots'
    xacro package the way its launch files pass the file (``kinematics_params``), once per process."""
    import warnings

    with warnings.catch_warnings():
        warnings.simplefilter("ignore", robokit.RobokitWarning)  # (the package's meshes are not in the test data)
        return robokit.load(DATA / "ur_description" / "urdf" / "ur.urdf.xacro", package_dirs=[DATA],
                            xacro_args={"ur_type": "ur5e", "name": "ur",
                                        "kinematics_params": str(DATA / "ur_calibration" / "ur5e_factory_calibration.yaml")})


def true_errors(n, rng, size=2e-3):
    """Per-placement SE(3) errors (rad, m), each component uniform in ±size."""
    return rng.uniform(-size, size, (n + 1, 6))


@functools.cache
def calibrated(name: str, seed: int) -> tuple[robokit.Robot, robokit.Robot]:
    """(nominal, calibrated): ``robokit.calibrate`` of the nominal ``name`` on 40 noise-free poses of a true
    arm with errors up to 2 mrad / 2 mm (:func:`true_errors` from ``default_rng(seed)``), once per process."""
    import warnings

    import numpy as np

    from robokit.calibration import chain_from_robot

    nominal = robot(name)
    rng = np.random.default_rng(seed)
    true = chain_from_robot(nominal).perturbed(true_errors(nominal.n, rng))
    Q = np.array([nominal.random_configuration(rng) for _ in range(40)])
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", robokit.RobokitWarning)
        res = robokit.calibrate(nominal, Q, true.fk(Q))
    assert res.rms_after < 1e-9  # the true arm is representable: calibration recovers it
    return nominal, res.robot


def benchmark_arms_off_by(size: float) -> dict[str, robokit.Robot]:
    """The arms of ``benchmarks/calibrated_ik`` (a PUMA 560, a UR5 and its random Pieper arm, built as
    there from ``default_rng(0)`` in that order), every joint placement, the base and the tool off by up to
    ``size`` (rad, m); the benchmark's are ``size`` = 2e-3."""
    import numpy as np

    from robokit.calibration import chain_from_robot, robot_from_chain
    from robokit.description.dh import DHLink, DHTable

    rng = np.random.default_rng(0)
    pieper = DHTable("pieper", "standard", (
        DHLink("R", a=0.2, alpha=1.1, d=0.4), DHLink("R", a=0.5, alpha=-0.6, d=0.1),
        DHLink("R", a=0.1, alpha=1.9, d=-0.05), DHLink("R", a=0.0, alpha=-1.3, d=0.35),
        DHLink("R", a=0.0, alpha=0.9, d=0.0), DHLink("R", a=0.02, alpha=0.0, d=0.12)))
    out = {}
    for name, model in (("puma560", "puma560"), ("ur5", "ur5"), ("pieper", pieper)):
        nominal = robokit.load(model)
        out[name] = robot_from_chain(nominal, chain_from_robot(nominal).perturbed(rng.uniform(-size, size, (7, 6))))
    return out


#: A configuration of the benchmark's calibrated random Pieper arm (``benchmark_arms_off_by(2e-3)["pieper"]``,
#: draw 625 of ``default_rng(102)``) where a fold position's oblique wrist misses by |cos θ₅| − 1 = 0.28
#: (closed_form.FOLD_POSITION_WRIST): the arm's roots there were missing without a warning.
PIEPER_FOLD_POSITION_WRIST = [-2.85949563904747, 1.4814951679468136, -3.1161356503366093, -0.7091959744379821,
                              3.1178353574787296, -1.1140014288872808]


#: Configurations of the benchmark's calibrated arms (``benchmark_arms_off_by(2e-3)``; "ur5e": :func:`factory_ur5e`)
#: where ``ik_analytic`` found an odd number of solutions and the one missing was the configuration itself
#: (draws 2280 and 11306 of ``default_rng(4242)`` on the PUMA 560, 1888 on the UR5 and the UR5e): an arm of
#: revolute joints off its nominal structure has an even number (robokit.kernels.calibrated_ik.DOUBLE).
ODD_MISSING = [
    ("puma560", [-0.13424757411517074, -1.8446801467608538, 1.6639601401311195, 0.8817324211602928,
                 -1.3981602811090856, -1.226973136222937]),
    ("puma560", [1.4640401560619893, -1.6258816597101156, 1.6140121115473938, -2.3050655022269813,
                 1.419053851729352, -3.09661564767282]),
    ("ur5", [-4.019468316972308, -1.7436863189651755, 0.14534421724616475, 0.6074009567780445, 3.268878867650173,
             -0.35988639521504684]),
    ("ur5e", [-4.019468316972043, -1.7436863189650609, 0.14534421724615543, 0.6074009567780045, 3.268878867649958,
              -0.35988639521502286]),
]
#: ... and where an odd number came from one double root reached twice (two returned solutions 1.0e-7 and
#: 2.4e-7 apart; draw 2980 of ``default_rng(777)`` on the random Pieper arm, 11934 of ``(4242)`` on the UR5e).
ODD_DOUBLE = [
    ("pieper", [-0.6022658182936782, -3.100859162096359, 1.1817775647673274, -2.9276173902750284, 2.901509753600898,
                -0.11092869925286442]),
    ("ur5e", [4.406052027438484, 5.375558108289555, -3.020379183210178, 0.9561657060150957, 1.1580518573146792,
              3.7794841794579312]),
]


@functools.cache
def odd_arm(name: str) -> robokit.Robot:
    """The arm of an ``ODD_MISSING`` / ``ODD_DOUBLE`` entry, once per process."""
    return factory_ur5e() if name == "ur5e" else _benchmark_arms_2mm()[name]


@functools.cache
def _benchmark_arms_2mm() -> dict[str, robokit.Robot]:
    return benchmark_arms_off_by(2e-3)


@functools.cache
def gen3_lite() -> robokit.Robot:
    """The Kinova Gen3 lite as Kinova publishes it (tests/data/kinova, see its SOURCE), to its wrist's last
    link, once per process: axes 2 and 3 are 7.3e-6 rad from parallel, its DH table's offsets -38 km (the
    general 6R method finishes each solution on the arm: robokit.ik.general_6r.ArmPolish)."""
    import warnings

    with warnings.catch_warnings():
        warnings.simplefilter("ignore", robokit.RobokitWarning)  # (meshes not copied, ros2_control, gazebo)
        return robokit.load(DATA / "kinova" / "gen3_lite.urdf", tip="end_effector_link")


def elbow_singular(robot, q):
    """The Gen3 lite's θ₃ (the elbow joint, between the nearly parallel axes 2 and 3 and the wrist) where
    the Jacobian's smallest singular value is least for q's other joints: its least on a 0.5° grid, refined
    to 1e-10 (bounded scalar minimisation within one grid step). With the wrist offset, that angle moves
    with the wrist's joints, so it is found per configuration."""
    import math

    import numpy as np
    from scipy.optimize import minimize_scalar

    def sigma(x):
        return np.linalg.svd(robot.jacobian(np.r_[q[:2], x, q[3:]]), compute_uv=False)[-1]

    grid = np.linspace(-math.pi, math.pi, 721)
    x0 = grid[int(np.argmin([sigma(x) for x in grid]))]
    step = grid[1] - grid[0]
    return minimize_scalar(sigma, bounds=(x0 - step, x0 + step), method="bounded", options={"xatol": 1e-10}).x


#: A configuration of the benchmark's calibrated random Pieper arm (draw 6597 of ``default_rng(4242)``) where two
#: branches of the nominal structure merge (their starts, from a relaxed pose, reach other branches' roots) and
#: no other warning is said: the arm's pair of roots there — this configuration one of them — is missing
#: from ik_analytic (the general 6R method has them); measured once in 20,000 poses.
MERGED_MISS = [2.5119953262990418, -1.6511730683974035, -2.008436258073834, 0.5596342868061357, 2.9276402090771487,
               2.3190264846814257]
