"""The calibration's pivoted QR (robokit.calibration.kinematic._pivoted_qr) chooses the same parameters on
every machine: ties between columns of equal norm (parameters that act exactly alike) go to the earlier
column, whatever the round-off. Before, LAPACK's geqp3 chose, and a fresh machine with another processor
printed other parameters for the same data (docs/course/calibration.md's sample: joint_2.ry instead of
joint_1.rz staying nominal). The references: LAPACK's pivots where there is no tie, the Gram matrix of the
pivoted columns, and the active set under round-off-sized perturbations of the data."""
import numpy as np
import pytest
import scipy.linalg
from hypothesis import given, settings
from hypothesis import strategies as st

import robokit
from robokit.calibration import chain_from_robot
from robokit.calibration.kinematic import _pivoted_qr, _scaled_qr, identification_jacobian


@settings(max_examples=60, deadline=None)
@given(seed=st.integers(0, 2**32 - 1), m=st.integers(2, 40), n=st.integers(2, 40))
def test_without_ties_the_pivots_are_lapacks_and_r_factors_the_pivoted_columns(seed, m, n):
    rng = np.random.default_rng(seed)
    A = rng.standard_normal((m, n)) * rng.uniform(0.1, 10.0, n)
    R, piv = _pivoted_qr(A)
    _, R2, piv2 = scipy.linalg.qr(A, pivoting=True, mode="economic")
    k = min(m, n)
    assert sorted(piv.tolist()) == list(range(n))
    assert piv[:k - 1].tolist() == piv2[:k - 1].tolist()  # (the last pivot of a square matrix: any order)
    AP = A[:, piv]
    assert np.abs(R.T @ R - AP.T @ AP).max() <= 1e-12 * np.abs(AP.T @ AP).max()
    assert np.allclose(np.abs(np.diag(R)), np.abs(np.diag(R2[:, :k])) if k == n else np.abs(np.diag(R2)), rtol=1e-10)
    assert np.all(np.tril(R, -1) == 0.0)


def test_equal_columns_go_to_the_earlier_one():
    rng = np.random.default_rng(0)
    A = rng.standard_normal((8, 5))
    A[:, 3] = A[:, 1]  # column 3 acts exactly like column 1
    A[:, 1] *= 10.0  # (and the largest, so the tie is at the first step)
    A[:, 3] *= 10.0
    _, piv = _pivoted_qr(A)
    assert piv[0] == 1 and 3 not in piv[:4]


def test_the_parameters_solved_for_do_not_depend_on_round_off():
    """The PUMA 560's identification Jacobian (joint_1.rz and joint_2.ry act alike, among others):
    perturbed by a few units of round-off (as another BLAS or processor computes it), the same
    parameters are solved for every time."""
    robot = robokit.load("puma560")
    chain = chain_from_robot(robot)
    rng = np.random.default_rng(1)
    q = np.array([robot.random_configuration(rng) for _ in range(50)])
    J = identification_jacobian(chain, q).reshape(-1, 6 * (robot.n + 1))
    _, piv, _, rank = _scaled_qr(J)
    active = sorted(piv[:rank].tolist())
    assert rank == 30
    for _ in range(20):
        Jp = J * (1.0 + 4e-16 * rng.standard_normal(J.shape))
        _, piv_p, _, rank_p = _scaled_qr(Jp)
        assert rank_p == rank and sorted(piv_p[:rank].tolist()) == active


@pytest.mark.parametrize("tie_first", [True, False])
def test_a_near_tie_beyond_round_off_is_decided_by_the_norms(tie_first):
    """Columns whose norms differ by more than round-off (1e-6 here) are not a tie: the larger is taken
    first, wherever it stands."""
    A = np.zeros((3, 2))
    A[0] = [1.0, 1.0 + 1e-6] if tie_first else [1.0 + 1e-6, 1.0]
    _, piv = _pivoted_qr(A)
    assert piv[0] == (1 if tie_first else 0)
