"""Helpers of the calibration tests (on sys.path through conftest.py): the arms built here."""
import numpy as np

import robokit
from robokit.description import DHLink, DHTable


def prismatic_arm():
    """A 3-joint R-P-R arm with masses (a prismatic joint in the middle), built here."""
    links = (
        DHLink("R", a=0.1, alpha=np.pi / 2, d=0.3, mass=2.0, com=np.array([0.0, -0.05, 0.0]),
               inertia=np.array([0.02, 0.01, 0.02, 0, 0, 0]), qlim=np.array([-2.5, 2.5])),
        DHLink("P", a=0.0, alpha=-np.pi / 2, d=0.2, theta=0.3, mass=1.5, com=np.array([0.0, 0.0, -0.1]),
               inertia=np.array([0.01, 0.01, 0.005, 0, 0, 0]), qlim=np.array([0.0, 0.4])),
        DHLink("R", a=0.15, alpha=0.0, d=0.05, mass=0.8, com=np.array([-0.07, 0.0, 0.0]),
               inertia=np.array([0.002, 0.004, 0.004, 0, 0, 0]), qlim=np.array([-3.0, 3.0])),
    )
    tool = np.eye(4)
    tool[:3, 3] = [0.05, 0.0, 0.02]
    return robokit.load(DHTable("rpr", "standard", links, tool=tool))


def configurations(robot, K, rng):
    return np.array([robot.random_configuration(rng) for _ in range(K)])


def perturbed_inertias(robot, rng, name="true"):
    """A "true" arm: the robot's geometry with every link's mass, centre of mass and inertia changed
    (a physical body: positive mass, a positive-definite inertia)."""
    import pinocchio as pin

    from robokit.description.robot import Robot

    model = pin.Model(robot.model)
    for j in range(1, robot.n + 1):
        Y = model.inertias[j]
        A = rng.normal(0, 0.05, (3, 3))
        model.inertias[j] = pin.Inertia(float(Y.mass) * rng.uniform(0.8, 1.2) + 0.3, Y.lever + rng.normal(0, 0.02, 3),
                                        Y.inertia + A @ A.T + 0.01 * np.eye(3))
    return Robot(name, model, robot.tip)


def motions(robot, N, rng):
    q = configurations(robot, N, rng)
    dq, ddq = rng.standard_normal((2, N, robot.n))
    return q, dq, ddq
