"""The compiled Newton–Euler regressor (robokit.kernels.regressor, issue 42 item 5) against Pinocchio's
computeJointTorqueRegressor and rnea (independent), and against the numpy recursion it replaced."""
import numpy as np
import pinocchio as pin
import pytest
from calibration_support import motions
from hypothesis import given, settings
from hypothesis import strategies as st

from robokit.calibration import chain_from_robot, inertial_regressor, standard_parameters
from robokit.calibration.regressor import _inertial_regressor_numpy
from robokit.kernels import regressor as kr

NAMES = ["puma560", "ur5", "rpr", "panda"]  # rpr: a prismatic joint in the middle


class _Spy:
    """The kernel, recording its calls (and showing its compiled signatures, as the wrapper reads them)."""

    def __init__(self, kernel):
        self.kernel, self.calls = kernel, []

    @property
    def signatures(self):
        return self.kernel.signatures

    def __call__(self, *args):
        self.calls.append(args)
        return self.kernel(*args)


@settings(max_examples=12, deadline=None, derandomize=True)
@given(name=st.sampled_from(NAMES), seed=st.integers(0, 2**31 - 1), scale=st.sampled_from([0.1, 1.0, 10.0]))
def test_kernel_equals_pinocchio_regressor_and_rnea(robots, name, seed, scale):
    robot = robots(name)
    rng = np.random.default_rng(seed)
    q, dq, ddq = motions(robot, 4, rng)
    dq, ddq = dq * scale, ddq * scale
    chain = chain_from_robot(robot)
    Y = kr.inertial_regressor(np.ascontiguousarray(chain.placements), np.ascontiguousarray(chain.axes), q,
                              np.ascontiguousarray(dq), np.ascontiguousarray(ddq), np.array(robot.gravity, float))  # a writeable copy, as the kernel takes it
    pi = standard_parameters(robot)
    for k in range(len(q)):
        qp = robot.q_pin(q[k])
        Yp = pin.computeJointTorqueRegressor(robot.model, robot.data, qp, dq[k], ddq[k])
        np.testing.assert_allclose(Y[k], Yp, rtol=0, atol=1e-12 * max(1.0, np.abs(Yp).max()))
        tau = pin.rnea(robot.model, robot.data, qp, dq[k], ddq[k])
        np.testing.assert_allclose(Y[k] @ pi, tau, rtol=0, atol=1e-12 * max(1.0, np.abs(Y[k]).max() * np.abs(pi).max()))


@pytest.mark.parametrize("name", NAMES)
def test_inertial_regressor_runs_the_kernel_and_matches_the_numpy_recursion(robots, name, monkeypatch):
    robot = robots(name)
    q, dq, ddq = motions(robot, 5, np.random.default_rng(7))
    chain = chain_from_robot(robot)
    spy = _Spy(kr.inertial_regressor)
    monkeypatch.setattr(kr, "inertial_regressor", spy)
    Y = inertial_regressor(chain, q.tolist(), dq, ddq, list(robot.gravity))  # lists converted once
    assert spy.calls and spy.calls[-1][2].shape == (5, robot.n)  # the whole batch in the kernel
    Yn = _inertial_regressor_numpy(chain, q, dq, ddq, robot.gravity)
    np.testing.assert_allclose(Y, Yn, rtol=0, atol=1e-12 * np.abs(Yn).max())
    assert inertial_regressor(chain, q[:0], dq[:0], ddq[:0], robot.gravity).shape == (0, robot.n, 10 * robot.n)
