"""The solutions ``ik_analytic`` returns from the compiled path (read lazily from the kernel's one
output array) behave as plain :class:`robokit.IKSolution` objects: the same fields and values as
the Python reference solver's, frozen, ``==``/``repr`` as a dataclass, ``dataclasses.replace``,
``copy`` and ``pickle`` giving plain IKSolutions, each ``q`` its own row (editing one leaves the
others and a second solve alone), ``extra`` a dict of its own, and an in-place edit of the robot's
limits seen by the next solve."""
import copy
import dataclasses
import pickle

import numpy as np
import pytest

import robokit
from robokit import IKSolution
from robokit.ik import AnalyticIK, ik_analytic


@pytest.fixture(scope="module", params=["puma560", "ur5"])
def arm(request):
    return robokit.load(request.param)


def _plain(s):
    return IKSolution(np.array(s.q), s.within_limits, s.label, s.degenerate)


def test_fields_match_the_python_reference(arm):
    T = arm.frame_pose(np.array([0.3, -0.6, 0.5, 0.4, 0.7, -0.2]))
    ik = AnalyticIK(arm)
    fast = ik.solve(T)
    ik.use_kernel = False
    ref = ik.solve(T)
    assert len(fast) == len(ref) > 0
    for a, b in zip(fast, ref):
        assert isinstance(a, IKSolution)
        assert (a.label, a.within_limits, a.degenerate, a.collision_free) == (b.label, b.within_limits,
                                                                               b.degenerate, None)
        assert type(a.within_limits) is bool and type(a.degenerate) is bool
        assert a.q.shape == (6,) and a.q.dtype == np.float64
        assert np.abs(arm.frame_pose(a.q) - T).max() < 1e-9
        assert a.q is a.q  # the same array on every read
        assert repr(a) == repr(_plain(a))


def test_frozen_replace_copy_pickle(arm):
    s = ik_analytic(arm, arm.frame_pose(np.full(6, 0.4)))[0]
    with pytest.raises(dataclasses.FrozenInstanceError):
        s.q = np.zeros(6)
    with pytest.raises(dataclasses.FrozenInstanceError):
        s.label = "x"
    r = dataclasses.replace(s, label="mine")
    assert type(r) is IKSolution and r.label == "mine" and np.array_equal(r.q, s.q)
    assert r.within_limits == s.within_limits and r.degenerate == s.degenerate
    for other in (copy.copy(s), copy.deepcopy(s), pickle.loads(pickle.dumps(s))):
        assert type(other) is IKSolution
        assert other.label == s.label and np.array_equal(other.q, s.q) and other.within_limits == s.within_limits
    assert [f.name for f in dataclasses.fields(s)] == [f.name for f in dataclasses.fields(IKSolution)]


def test_rows_are_independent(arm):
    T = arm.frame_pose(np.full(6, 0.4))
    sols = ik_analytic(arm, T)
    before = [np.array(s.q) for s in sols]
    sols[0].q[:] = 99.0
    sols[0].extra["note"] = 1
    assert all(np.array_equal(s.q, b) for s, b in zip(sols[1:], before[1:]))
    assert all(s.extra == {} for s in sols[1:]) and sols[0].extra == {"note": 1}
    again = ik_analytic(arm, T)
    assert all(np.array_equal(s.q, b) for s, b in zip(again, before))


def test_a_copy_with_other_limits_is_seen():
    arm = robokit.load("puma560")
    q = np.array([0.3, -0.6, 0.5, 0.4, 0.7, -0.2])
    T = arm.frame_pose(q)
    assert sum(s.within_limits for s in ik_analytic(arm, T)) > 1
    qlim = arm.qlim.copy()
    qlim[0] = [q[0] - 1e-3, q[0] + 1e-3]
    arm = arm.with_limits(qlim)
    inside = [s for s in ik_analytic(arm, T) if s.within_limits]
    assert inside and all(abs(s.q[0] - q[0]) <= 1e-3 + 1e-12 for s in inside)


def test_equality_with_plain_solutions():
    arm = robokit.load("puma560")
    s = ik_analytic(arm, arm.frame_pose(np.full(6, 0.4)))[0]
    plain = IKSolution(s.q, s.within_limits, s.label, s.degenerate)
    assert s == plain and plain == s and s == s
    assert s != IKSolution(s.q, s.within_limits, s.label + "x", s.degenerate)
