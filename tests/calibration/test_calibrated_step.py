"""The calibrated IK's Newton step (:mod:`robokit.kernels.calibrated_ik`) against the Modern Robotics
library on random six-joint chains (the chains of ``test_calibrated_chain``: revolute joints with and
without a pitch, prismatic joints, nearly parallel and intersecting axes):

* the pose error near the target is the logarithm of the error transform ``Td T⁻¹`` to second order
  (its error is O(h³) in the size h of the error, where the first-order twist's is O(h²));
* the second-order term is the Baker–Campbell–Hausdorff term of the pose's change along a joint
  step d: ``log(T(q + d) T(q)⁻¹) = J d + ½ Σ_{i<j} dᵢ dⱼ [Jᵢ, Jⱼ] + O(d³)``;
* the 3 × 3 block elimination and the pivoted 6 × 6 one solve ``J x = e`` as numpy does;
* hence one step from a start h off leaves an error of order h³ (halving h divides it by about 8,
  where Newton's step divides it by 4).
"""
import numpy as np
import modern_robotics as mr
from hypothesis import example, given, settings
from hypothesis import strategies as st

from robokit.kernels import calibrated_ik as kci
from calibrated_chains import _chain, _pose_and_jacobian, _unit  # tests/support


def _twist(T, Td):
    """(ω, v) = log(Td T⁻¹), the Modern Robotics library's matrix logarithm."""
    V = mr.se3ToVec(mr.MatrixLog6(Td @ mr.TransInv(T)))
    return np.asarray(V, dtype=float)


def _packed(seed):
    S, M, q = _chain(seed)
    return S, M, q, kci.pack_arm(M, S, np.zeros((5, 6)), np.zeros(3), 1.0, 1e-12, 1e-10, 30)


@settings(max_examples=60, deadline=None, derandomize=True)
@given(seed=st.integers(0, 2**31 - 1))
def test_pose_error_is_the_logarithm_to_second_order(seed):
    S, M, q = _chain(seed)
    rng = np.random.default_rng(seed)
    T = mr.FKinSpace(M, S, q)
    u = _unit(rng.normal(size=6))
    misses = []
    for h in (4e-3, 2e-3):
        xi = h * u
        Td = mr.MatrixExp6(mr.VecTose3(xi)) @ T
        F = np.empty(6)
        kci._error.py_func(T, Td, F)
        exact = _twist(T, Td)
        assert np.abs(exact - xi).max() < 1e-12  # the reference: log(exp ξ) = ξ
        first = np.concatenate([exact[:3], Td[:3, 3] - T[:3, 3] - np.cross(exact[:3], T[:3, 3])])
        misses.append((np.abs(F - exact).max(), np.abs(first - exact).max()))
    (big, big1), (small, small1) = misses
    scale = 1.0 + np.abs(T[:3, 3]).max()
    assert big < 2.0 * (4e-3) ** 3 * scale ** 2  # third order: ≤ c h³
    assert big < 0.05 * big1 or big1 < 1e-12  # far below the first-order twist's miss (second order)
    assert small < big / 4.0 or big < 1e-13  # halving h: at least 4× smaller (8× for h³, up to rounding)


def test_pose_error_beyond_the_logarithms_range_is_the_first_order_twist():
    """Far from the target (orientation error above LOG_NEAR) the error is sin θ u and Δp − ω × p:
    zero only at the target, pointing the right way (a descent direction for the damped steps)."""
    rng = np.random.default_rng(3)
    T = mr.RpToTrans(mr.MatrixExp3(mr.VecToso3(rng.normal(size=3))), rng.uniform(-1, 1, 3))
    axis = _unit(rng.normal(size=3))
    Td = mr.MatrixExp6(mr.VecTose3(np.concatenate([0.3 * axis, [0.1, -0.2, 0.05]]))) @ T
    F = np.empty(6)
    _, rot, pos = kci._error.py_func(T, Td, F)
    w = F[:3]
    assert np.allclose(w, np.sin(0.3) * axis, atol=1e-12)
    assert np.isclose(rot, np.sin(0.3)) and np.isclose(pos, np.linalg.norm(Td[:3, 3] - T[:3, 3]))
    assert np.allclose(F[3:], Td[:3, 3] - T[:3, 3] - np.cross(w, T[:3, 3]), atol=1e-12)


@settings(max_examples=60, deadline=None, derandomize=True)
@given(seed=st.integers(0, 2**31 - 1))
def test_second_order_term_is_the_bch_term(seed):
    S, M, q = _chain(seed)
    rng = np.random.default_rng(seed + 1)
    u = _unit(rng.normal(size=6))
    J = np.asarray(mr.JacobianSpace(S, q), dtype=float)
    T = mr.FKinSpace(M, S, q)
    misses = []
    for h in (1e-2, 5e-3):
        d = h * u
        xi = _twist(T, mr.FKinSpace(M, S, q + d))
        B = np.empty(6)
        kci._second_order.py_func(J, d, B)
        misses.append((np.abs(xi - J @ d - B).max(), np.abs(xi - J @ d).max()))
    (big, big1), (small, small1) = misses
    assert big < 0.1 * big1  # the second-order term is most of what the linear term misses
    assert 5.0 < big / small < 11.0  # and what is left is third order (8×), where the linear term's is 4×
    assert 3.0 < big1 / small1 < 5.0


@settings(max_examples=80, deadline=None, derandomize=True)
@given(seed=st.integers(0, 2**31 - 1))
def test_block_and_pivoted_eliminations_solve_like_numpy(seed):
    S, _, q = _chain(seed)
    rng = np.random.default_rng(seed)
    J = np.asarray(mr.JacobianSpace(S, q), dtype=float)
    if rng.random() < 0.3:  # any matrix, not only a Jacobian
        J = rng.normal(size=(6, 6))
    e = rng.normal(size=6)
    cond = np.linalg.cond(J)
    if not cond < 1e8:
        return
    ref = np.linalg.solve(J, e)
    tol = 1e-14 * cond * (1.0 + np.abs(ref).max())
    A, piv, x = np.empty((6, 6)), np.empty(6), np.empty(6)
    assert kci._lu_factor.py_func(J, A, piv)
    kci._lu_solve.py_func(A, piv, e, x)
    assert np.abs(x - ref).max() < tol
    if kci._block_factor.py_func(J, np.empty((6, 6))) and np.abs(ref).max() > kci.SECOND_ORDER[1]:
        # the Newton step's own elimination by blocks (its factors in local variables); a step this long
        # gets no second-order correction: x = J⁻¹ e
        assert kci._newton_step.py_func(J, e, kci.scratch(), x)
        assert np.abs(x - ref).max() < 1e3 * tol  # no pivoting inside the blocks: a looser bound
        assert np.abs(J @ x - e).max() < 1e-9 * (1.0 + np.abs(e).max())


def test_block_elimination_refuses_singular_pivot_blocks():
    """Both triples of ω columns with two parallel axes: no 3 × 3 pivot block, the 6 × 6 elimination."""
    rng = np.random.default_rng(0)
    J = rng.normal(size=(6, 6))
    J[:3, 1] = J[:3, 0]
    J[:3, 4] = -J[:3, 3]
    assert not kci._block_factor.py_func(J, np.empty((6, 6)))
    A, piv = np.empty((6, 6)), np.empty(6)
    assert kci._lu_factor.py_func(J, A, piv)  # J itself is regular


def _one_step_error(C, q_star, start):
    Td, _ = _pose_and_jacobian(C, q_star)
    T, J = _pose_and_jacobian(C, start)
    F, x, work = np.empty(6), np.empty(6), kci.scratch()
    kci._error.py_func(T, Td, F)
    assert kci._newton_step.py_func(J, F, work, x)
    T1, _ = _pose_and_jacobian(C, start + x)
    e = np.empty(6)
    _, rot, pos = kci._error.py_func(T1, Td, e)
    return max(rot, pos)


@settings(max_examples=40, deadline=None, derandomize=True)
@given(seed=st.integers(0, 2**31 - 1))
@example(seed=4878)
def test_a_step_leaves_a_third_order_error(seed):
    S, M, q, C = _packed(seed)
    J = np.asarray(mr.JacobianSpace(S, q), dtype=float)
    if not np.linalg.cond(J) < 1e3:  # near a singular configuration the constants are large
        return
    rng = np.random.default_rng(seed)
    u = _unit(rng.normal(size=6))
    # steps of 1 and 0.5 mrad: in the asymptotic range of every arm drawn (at 4 and 2 mrad the ratio of a
    # strongly curved arm was still 31, its h⁴ terms not yet small: seed 4878, found at six times the
    # examples), and the error still far above rounding (about 4e-8 and 5e-9)
    e_big = _one_step_error(C, q, q + 1e-3 * u)
    e_small = _one_step_error(C, q, q + 5e-4 * u)
    if e_small < 1e-13:  # at rounding already
        return
    assert 5.0 < e_big / e_small < 11.0  # 8× for O(h³); Newton's step alone gives 4×
