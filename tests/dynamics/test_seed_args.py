"""The seed functions with the argument types the Modern Robotics book and the course use (issue 42, item 6).

``Mlist``/``Glist`` as Python lists or tuples of arrays, nested Python lists, read-only and
transposed (strided) arrays, integer arrays: each must reach the compiled kernel as packed
float64 arrays after one conversion — the kernel (a numba dispatcher) is never handed a list, a
read-only or a strided array, so no call goes through a failed dispatch (which costs hundreds of
µs) — and give exactly the result of the same call on packed arrays; that result agrees with
modern_robotics (an independent implementation) and bad values are still named.
"""
import numpy as np
import pytest

import robokit as rk
from robokit.errors import InputError
from robokit.kernels import dynamics as kd
from robokit.kernels import poe as kp

KERNELS = [(kd, "inverse_dynamics"), (kd, "mass_matrix"), (kd, "forward_dynamics"), (kd, "forward_dynamics_crba"),
           (kd, "inverse_dynamics_batch"), (kd, "mass_matrix_batch"), (kp, "fkin_space"), (kp, "fkin_body"),
           (kp, "jacobian_space"), (kp, "jacobian_body"), (kp, "fkin_space_batch"), (kp, "jacobian_space_batch")]


@pytest.fixture(scope="module")
def ur5():
    return rk.load("ur5")


@pytest.fixture
def spy(monkeypatch):
    """Every call of a kernel, with the arguments it was given: each must be what the kernel's
    signature takes (float64 ndarray, C-contiguous, writeable), never a list."""
    calls = []
    for module, name in KERNELS:
        kernel = getattr(module, name)

        def wrapped(*args, _kernel=kernel, _name=name):
            calls.append((_name, args))
            for a in args:
                assert type(a) is np.ndarray, f"{_name} was handed a {type(a).__name__}"
                assert a.dtype == np.float64 and a.flags.c_contiguous and a.flags.writeable, (_name, a.flags)
            return _kernel(*args)

        monkeypatch.setattr(module, name, wrapped)
    return calls


def _readonly(a):
    a = np.array(a)
    a.flags.writeable = False
    return a


def _variants(p, q):
    """(label, M, Slist, Blist, Mlist, Glist, thetalist) in the types a user may pass."""
    book_S = np.array(p.Slist.T.tolist()).T  # the book writes the screws as rows and transposes: strided
    book_B = np.array(p.Blist.T.tolist()).T
    return [
        ("book", p.M.tolist(), book_S, book_B, [m.copy() for m in p.Mlist], [G.copy() for G in p.Glist], q.copy()),
        ("tuples", p.M, p.Slist, p.Blist, tuple(p.Mlist), tuple(p.Glist), tuple(q.tolist())),
        ("nested lists", p.M.tolist(), p.Slist.tolist(), p.Blist.tolist(), p.Mlist.tolist(), p.Glist.tolist(),
         q.tolist()),
        ("read-only", _readonly(p.M), _readonly(p.Slist), _readonly(p.Blist), _readonly(p.Mlist),
         _readonly(p.Glist), _readonly(q)),
        ("Fortran order", np.asfortranarray(p.M), np.asfortranarray(p.Slist), np.asfortranarray(p.Blist),
         np.asfortranarray(p.Mlist), np.asfortranarray(p.Glist), q[::-1].copy()[::-1]),
    ]


def _all_calls(M, S, B, Ml, Gl, th, dth, v, g, F):
    return {
        "fkin_space": lambda: rk.fkin_space(M, S, th),
        "fkin_body": lambda: rk.fkin_body(M, B, th),
        "jacobian_space": lambda: rk.jacobian_space(S, th),
        "jacobian_body": lambda: rk.jacobian_body(B, th),
        "inverse_dynamics": lambda: rk.inverse_dynamics(th, dth, v, g, F, Ml, Gl, S),
        "mass_matrix": lambda: rk.mass_matrix(th, Ml, Gl, S),
        "vel_quadratic_forces": lambda: rk.vel_quadratic_forces(th, dth, Ml, Gl, S),
        "gravity_forces": lambda: rk.gravity_forces(th, g, Ml, Gl, S),
        "end_effector_forces": lambda: rk.end_effector_forces(th, F, Ml, Gl, S),
        "forward_dynamics": lambda: rk.forward_dynamics(th, dth, v, g, F, Ml, Gl, S),
        "forward_dynamics crba": lambda: rk.forward_dynamics(th, dth, v, g, F, Ml, Gl, S, method="crba"),
    }


def test_argument_types_reach_the_kernel_packed_and_give_the_packed_result(ur5, spy):
    p = ur5.poe
    rng = np.random.default_rng(42)
    q, dq, v, F = (rng.normal(size=6) for _ in range(4))
    g = np.array([0.0, 0.0, -9.81])
    packed = {k: f() for k, f in _all_calls(p.M, p.Slist, p.Blist, p.Mlist, p.Glist, q, dq, v, g, F).items()}
    for label, M, S, B, Ml, Gl, th in _variants(p, q):
        vecs = [x.tolist() if label == "nested lists" else tuple(x) if label == "tuples" else x for x in (dq, v, g, F)]
        if label == "read-only":
            vecs = [_readonly(x) for x in vecs]
        spy.clear()
        for name, f in _all_calls(M, S, B, Ml, Gl, th, *vecs).items():
            out = f()
            assert np.array_equal(out, packed[name]), (label, name)  # exactly: the same kernel on the same numbers
        assert len(spy) == len(packed), (label, [c[0] for c in spy])  # one kernel call each: no checked detour


def test_lists_of_arrays_changed_in_place_are_seen(ur5, spy):
    """A list of arrays is read afresh on every call (nothing is remembered by the list's identity):
    an element written to, or replaced, gives the new answer."""
    p = ur5.poe
    q = np.full(6, 0.3)
    Ml, Gl = [m.copy() for m in p.Mlist], [G.copy() for G in p.Glist]
    M0 = rk.mass_matrix(q, Ml, Gl, p.Slist)
    Gl[2] *= 2.0  # in place: the same list, the same element object
    heavier = p.Glist.copy()
    heavier[2] *= 2.0
    assert np.array_equal(rk.mass_matrix(q, Ml, Gl, p.Slist), rk.mass_matrix(q, p.Mlist, heavier, p.Slist))
    Gl[2] = p.Glist[2].copy()  # an element replaced
    assert np.array_equal(rk.mass_matrix(q, Ml, Gl, p.Slist), M0)
    Ml[1][0, 3] += 0.1  # a link frame moved in place
    moved = p.Mlist.copy()
    moved[1, 0, 3] += 0.1
    assert np.array_equal(rk.inverse_dynamics(q, q, q, [0, 0, -9.81], np.zeros(6), Ml, Gl, p.Slist),
                          rk.inverse_dynamics(q, q, q, np.array([0, 0, -9.81]), np.zeros(6), moved, p.Glist, p.Slist))


def test_book_arguments_agree_with_modern_robotics(ur5):
    mr = pytest.importorskip("modern_robotics")
    p = ur5.poe
    rng = np.random.default_rng(3)
    Ml, Gl = list(p.Mlist), list(p.Glist)
    S = np.array(p.Slist.T.tolist()).T
    g = np.array([0.0, 0.0, -9.81])
    for _ in range(3):
        q, dq, ddq, F = (rng.normal(size=6) for _ in range(4))
        tau = mr.InverseDynamics(q, dq, ddq, g, F, Ml, Gl, S)
        assert np.allclose(rk.inverse_dynamics(q, dq, ddq, g, F, Ml, Gl, S), tau, rtol=0, atol=1e-9 * max(1, abs(tau).max()))
        Mm = mr.MassMatrix(q, Ml, Gl, S)
        assert np.allclose(rk.mass_matrix(q, Ml, Gl, S), Mm, rtol=0, atol=1e-9 * abs(Mm).max())
        T = mr.FKinSpace(p.M, S, q)
        assert np.allclose(rk.fkin_space(p.M.tolist(), S, list(q)), T, rtol=0, atol=1e-12)


def test_bad_values_in_lists_are_still_named(ur5):
    p = ur5.poe
    q = np.zeros(6)
    Ml = [m.copy() for m in p.Mlist]
    Ml[3][0, 0] = np.nan
    with pytest.raises(InputError, match="Mlist"):
        rk.inverse_dynamics(q, q, q, [0, 0, -9.81], np.zeros(6), Ml, list(p.Glist), p.Slist)
    with pytest.raises(InputError, match="Glist"):
        rk.mass_matrix(q, list(p.Mlist), [G.tolist() for G in p.Glist[:5]], p.Slist)
    with pytest.raises(InputError, match="thetalist"):
        rk.fkin_space(p.M, p.Slist, [True] * 6)  # booleans refused, never cast
    with pytest.raises(InputError, match="thetalist"):
        rk.gravity_forces([0, 0, 0], [0, 0, -9.81], list(p.Mlist), list(p.Glist), p.Slist)



def test_bad_arguments_are_named_in_argument_order(ur5):
    """The full checks name the first bad argument in the order of the signature, one state or N of
    them; the single terms take one state only (an (N, n) θ is refused by its name)."""
    p = ur5.poe
    q, Q = np.zeros(6), np.zeros((4, 6))
    model = (p.Mlist, p.Glist, p.Slist)
    with pytest.raises(InputError, match="^g:"):  # g comes before Ftip, both bad
        rk.inverse_dynamics(q, q, q, [1, 2], [1], *model)
    with pytest.raises(InputError, match="^Ftip:"):  # in a batch Ftip is checked against N first
        rk.inverse_dynamics(Q, Q, Q, [1], np.zeros((2, 6)), *model)
    with pytest.raises(InputError, match="^taulist:"):
        rk.forward_dynamics(Q, Q, Q[:3], [0, 0, -9.81], np.zeros(6), *model, method="crba")
    for term, x in ((rk.vel_quadratic_forces, q), (rk.gravity_forces, [0, 0, -9.81]),
                    (rk.end_effector_forces, np.zeros(6))):
        with pytest.raises(InputError, match="^thetalist:"):
            term(Q, x, *model)

def test_read_only_batches(ur5):
    """(N, n) joint values that are read-only (e.g. ``np.load(mmap_mode='r')``) run the batched kernels."""
    p = ur5.poe
    Q = _readonly(np.random.default_rng(1).normal(size=(4, 6)))
    assert np.array_equal(rk.fkin_space(p.M, p.Slist, Q), rk.fkin_space(p.M, p.Slist, np.array(Q)))
    assert np.array_equal(rk.mass_matrix(Q, _readonly(p.Mlist), p.Glist, p.Slist), rk.mass_matrix(np.array(Q), p.Mlist, p.Glist, p.Slist))


def test_nested_lists_are_remembered_until_they_change(ur5):
    """A nested-list model is converted once and reused while it compares equal to what was converted;
    changed in place (a link's mass doubled) the next call converts it afresh and gives the new model's
    matrix, the same as the call on packed arrays of the changed model."""
    from robokit import _arrays

    p = ur5.poe
    Ml, Gl, Sl = p.Mlist.tolist(), p.Glist.tolist(), p.Slist.tolist()
    q = np.full(6, 0.3)
    first = rk.mass_matrix(q, Ml, Gl, Sl)
    assert np.array_equal(first, rk.mass_matrix(q, p.Mlist, p.Glist, p.Slist))
    assert id(Gl) in _arrays._SEEN
    assert np.array_equal(rk.mass_matrix(q, Ml, Gl, Sl), first)
    for i in (3, 4, 5):
        Gl[2][i][i] *= 2.0
    G2 = np.array(p.Glist)
    G2[2, 3:, 3:] *= 2.0
    changed = rk.mass_matrix(q, Ml, Gl, Sl)
    assert np.array_equal(changed, rk.mass_matrix(q, p.Mlist, G2, p.Slist))
    assert not np.allclose(changed, first)
    # a list of arrays at an id() remembered for a nested list (a freed list's id reused): the comparison
    # has no single truth value, the list is converted afresh
    arrays = [m.copy() for m in p.Mlist]
    _arrays._SEEN[id(arrays)] = _arrays._SEEN[id(Ml)]
    assert np.array_equal(rk.mass_matrix(q, arrays, Gl, Sl), changed)
    # lists holding booleans or numpy scalars are not remembered
    assert _arrays._snapshot([[1.0, True]]) is None and _arrays._snapshot([[1.0, np.float64(2)]]) is None
