"""Symbolic derivations against the closed forms written in the lecture notes (seed 000).

The expected expressions below are typed in from the lecture text (Lecture 4 homework,
Lecture 6 homework, Lecture 7), not produced by robokit.
"""
import numpy as np
import pytest
import sympy as sp

from robokit.symbolic import SymbolicArm, shorthand, to_latex

l1, l2, m1, m2, g = sp.symbols("l1 l2 m1 m2 g", positive=True)


def _zero(expr):
    return sp.simplify(sp.expand_trig(sp.Matrix(expr))) == sp.zeros(*sp.Matrix(expr).shape)


@pytest.fixture(scope="module")
def twolink():
    return SymbolicArm([(l1, 0, 0, 0), (l2, 0, 0, 0)])


@pytest.fixture(scope="module")
def twolink_dyn(twolink):
    # point masses at the link ends, gravity along −y in the plane of motion (Lecture 7)
    return twolink.dynamics([m1, m2], [(0, 0, 0), (0, 0, 0)], gravity=(0, -g, 0))


def test_twolink_mass_matrix_lecture7(twolink, twolink_dyn):
    q1, q2 = twolink.q
    c2 = sp.cos(q2)
    M_lecture = sp.Matrix(
        [
            [l2**2 * m2 + 2 * l1 * l2 * m2 * c2 + l1**2 * (m1 + m2), l2**2 * m2 + l1 * l2 * m2 * c2],
            [l2**2 * m2 + l1 * l2 * m2 * c2, l2**2 * m2],
        ]
    )
    assert _zero(twolink_dyn.M - M_lecture)


def test_twolink_gravity_and_coefficients_lecture7(twolink, twolink_dyn):
    q1, q2 = twolink.q
    c1, c12, s2 = sp.cos(q1), sp.cos(q1 + q2), sp.sin(q2)
    G_lecture = sp.Matrix([m2 * l2 * g * c12 + (m1 + m2) * l1 * g * c1, m2 * l2 * g * c12])
    B_lecture = sp.Matrix([[-2 * m2 * l1 * l2 * s2], [0]])
    C_lecture = sp.Matrix([[0, -m2 * l1 * l2 * s2], [m2 * l1 * l2 * s2, 0]])
    assert _zero(twolink_dyn.G - G_lecture)
    assert _zero(twolink_dyn.B - B_lecture)
    assert _zero(twolink_dyn.Ccf - C_lecture)


def test_twolink_full_torque_lecture7(twolink, twolink_dyn):
    """τ₁, τ₂ as written out in Lecture 7 (Lagrangian example)."""
    q1, q2 = twolink.q
    d1, d2 = twolink.dq
    a1, a2 = sp.symbols("ddq1 ddq2", real=True)
    c1, c2, s2, c12 = sp.cos(q1), sp.cos(q2), sp.sin(q2), sp.cos(q1 + q2)
    tau1 = (m2 * l2**2 * (a1 + a2) + m2 * l1 * l2 * c2 * (2 * a1 + a2) + (m1 + m2) * l1**2 * a1
            - m2 * l1 * l2 * s2 * d2**2 - 2 * m2 * l1 * l2 * s2 * d1 * d2 + m2 * l2 * g * c12 + (m1 + m2) * l1 * g * c1)
    tau2 = m2 * l1 * l2 * c2 * a1 + m2 * l1 * l2 * s2 * d1**2 + m2 * l2 * g * c12 + m2 * l2**2 * (a1 + a2)
    assert _zero(twolink_dyn.tau(sp.Matrix([a1, a2])) - sp.Matrix([tau1, tau2]))


def test_twolink_jacobian_lecture6(twolink):
    q1, q2 = twolink.q
    s1, c1, s12, c12 = sp.sin(q1), sp.cos(q1), sp.sin(q1 + q2), sp.cos(q1 + q2)
    J_lecture = sp.Matrix([[-l1 * s1 - l2 * s12, -l2 * s12], [l1 * c1 + l2 * c12, l2 * c12]])
    J = twolink.jacobian("base")
    assert _zero(J[3:5, :] - J_lecture)
    assert J[:3, :] == sp.Matrix([[0, 0], [0, 0], [1, 1]])


def test_rrr_modified_dh_lecture4_homework():
    """Lecture 4 homework: ⁰T₁…³T_E of a spatial RRR arm in Craig's convention."""
    L1, L2, L3 = sp.symbols("L1 L2 L3")
    arm = SymbolicArm([(0, 0, 0, 0), (L1, sp.pi / 2, 0, 0), (L2, 0, 0, 0)], convention="modified",
                      tool=sp.Matrix([[1, 0, 0, L3], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]]))
    q1, q2, q3 = arm.q
    C1, S1, C2, S2, C3, S3 = sp.cos(q1), sp.sin(q1), sp.cos(q2), sp.sin(q2), sp.cos(q3), sp.sin(q3)
    T12_lecture = sp.Matrix([[C2, -S2, 0, L1], [0, 0, -1, 0], [S2, C2, 0, 0], [0, 0, 0, 1]])
    assert _zero(arm.link_transform(2) - T12_lecture)
    BTE_lecture = sp.Matrix(
        [
            [C1 * C2 * C3 - C1 * S2 * S3, -C1 * C2 * S3 - C1 * C3 * S2, S1,
             C1 * C2 * C3 * L3 - C1 * S2 * S3 * L3 + C1 * C2 * L2 + C1 * L1],
            [C2 * C3 * S1 - S1 * S2 * S3, -C2 * S1 * S3 - C3 * S1 * S2, -C1,
             C2 * C3 * S1 * L3 - S1 * S2 * S3 * L3 + C2 * S1 * L2 + S1 * L1],
            [C3 * S2 + C2 * S3, -S2 * S3 + C2 * C3, 0, C3 * S2 * L3 + C2 * S3 * L3 + S2 * L2],
            [0, 0, 0, 1],
        ]
    )
    T = arm.fk()
    assert _zero(T - BTE_lecture)
    # the lecture's shorthand form: C₁C₂₃ in the corner, as Lecture 5 writes it
    assert "c_{23}" in to_latex(T) and "c_{1}" in to_latex(T)


def test_skew_property_with_inertias():
    """Ṁ − 2C is skew-symmetric for a spatial 3-joint arm with symbolic-free inertias."""
    arm = SymbolicArm([(0, sp.pi / 2, sp.Rational(1, 3), 0), (sp.Rational(1, 2), 0, 0, 0), (sp.Rational(2, 5), 0, 0, 0)])
    inertias = [np.diag([0.1, 0.2, 0.15]), [[0.05, 0.01, 0], [0.01, 0.07, 0.0], [0, 0, 0.03]], np.diag([0.02, 0.02, 0.01])]
    dyn = arm.dynamics([2, 1.5, 1], [(0, 0.05, 0), (-0.25, 0, 0.01), (-0.2, 0, 0)], inertias, simplify=False)
    Mdot = sum((dyn.M.diff(qi) * dqi for qi, dqi in zip(arm.q, arm.dq)), sp.zeros(3, 3))
    N = sp.lambdify([list(arm.q), list(arm.dq)], Mdot - 2 * dyn.C)
    rng = np.random.default_rng(3)
    for _ in range(5):
        A = np.array(N(rng.normal(size=3), rng.normal(size=3)), dtype=float)
        assert np.abs(A + A.T).max() < 1e-12
        assert np.abs(A).max() > 1e-6  # not trivially zero


def test_shorthand_and_latex(twolink):
    q1, q2 = twolink.q
    e = sp.cos(q1 + q2) + sp.sin(q1)
    assert shorthand(e) == sp.Symbol("c_{12}") + sp.Symbol("s_{1}")
    tex = to_latex(twolink.fk())
    assert tex.startswith("\\left[") and "c_{12}" in tex and "s_{12}" in tex


def test_dynamics_refuses_six_joints_and_bad_input():
    arm = SymbolicArm([(0, 0, 0, 0)] * 6)
    with pytest.raises(ValueError, match="numeric dynamics"):
        arm.dynamics([1] * 6, [(0, 0, 0)] * 6)
    with pytest.raises(ValueError, match="rows"):
        SymbolicArm([(1, 0, 0)])
    with pytest.raises(ValueError, match="joint_types"):
        SymbolicArm([(1, 0, 0, 0)], "X")
    with pytest.raises(ValueError, match="convention"):
        SymbolicArm([(1, 0, 0, 0)], convention="craig")
    with pytest.raises(ValueError, match="extra_symbols"):
        SymbolicArm([(l1, 0, 0, 0)]).lambdify(SymbolicArm([(l1, 0, 0, 0)]).fk())
