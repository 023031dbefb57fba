"""Shared fixtures for the description tests: loaded robots (once per session) and DH helpers."""
import numpy as np
import pytest

import robokit
from shared_robots import robot as shared_robot

ARM_NAMES = ["ur5", "panda", "z1", "xarm7", "kinova"]
SHIPPED = ["twolink", "rrr", "puma560"]


@pytest.fixture(scope="session")
def robots():
    """Every shipped model and example-robot-data arm, loaded once per process (shared_robots)."""
    return shared_robot


@pytest.fixture(scope="session")
def random_dh_table():
    """A factory: ``random_dh_table(rng, n, convention, prismatic=(), with_inertia=True)``."""
    return make_random_dh_table


def make_random_dh_table(rng, n, convention, prismatic=(), with_inertia=True, name="random_arm"):
    """A random DH table (any convention), revolute except the indices in ``prismatic``."""
    from robokit.description.dh import DHLink, DHTable

    links = []
    for i in range(n):
        joint = "P" if i in prismatic else "R"
        mass = float(rng.uniform(0.5, 3.0)) if with_inertia else 0.0
        A = rng.normal(size=(3, 3))
        I = A @ A.T * 0.01 + np.eye(3) * 0.005
        inertia = np.array([I[0, 0], I[1, 1], I[2, 2], I[0, 1], I[1, 2], I[0, 2]]) if with_inertia else np.zeros(6)
        links.append(DHLink(joint, float(rng.uniform(-0.4, 0.4)), float(rng.uniform(-np.pi, np.pi)),
                            float(rng.uniform(-0.3, 0.3)), float(rng.uniform(-np.pi, np.pi)),
                            np.array([-0.5, 0.5]) if joint == "P" else None, mass,
                            rng.normal(size=3) * 0.1 if with_inertia else np.zeros(3), inertia))
    base = np.eye(4)
    base[:3, :3] = robokit.matrix_exp_3(robokit.vec_to_so3(rng.normal(size=3)))
    base[:3, 3] = rng.normal(size=3) * 0.2
    tool = np.eye(4)
    tool[:3, :3] = robokit.matrix_exp_3(robokit.vec_to_so3(rng.normal(size=3)))
    tool[:3, 3] = rng.normal(size=3) * 0.1
    return DHTable(name, convention, tuple(links), np.array([0.0, 0.0, -9.81]), base, tool)
