"""Every course function that takes a Jacobian also takes (robot, q): the same numbers as from the
Jacobian Pinocchio computes (LOCAL_WORLD_ALIGNED, rows swapped to (ω; v)), built here directly."""
import numpy as np
import pinocchio as pin
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import robokit as rk
from shared_robots import robot
from robokit.kinematics import (analytical_jacobian, force_ellipsoid, jacobian_in_frame, manipulability,
                                resolved_rate, singularity, velocity_ellipsoid)



def pin_jacobian(r, q, frame=None):
    """The geometric Jacobian from Pinocchio itself (no robokit method), rows (ω; v)."""
    data = r.model.createData()
    fid = r.model.getFrameId(frame or r.tip)
    J = pin.computeFrameJacobian(r.model, data, r.q_pin(q), fid, pin.ReferenceFrame.LOCAL_WORLD_ALIGNED)
    return np.vstack([J[3:], J[:3]])


def test_the_issue_call_works():
    """``rk.kinematics.manipulability(panda, q)`` said "J: expected an array of real numbers"."""
    panda = robot("panda")
    q = panda.configurations["ready"]
    s = np.linalg.svd(pin_jacobian(panda, q), compute_uv=False)
    assert manipulability(panda, q) == pytest.approx(np.prod(s), rel=1e-12)
    with pytest.raises(rk.InputError, match="^q: manipulability"):
        manipulability(panda)
    with pytest.raises(rk.InputError, match="^frame:"):
        manipulability(pin_jacobian(panda, q), frame="panda_link5")


@settings(max_examples=15, deadline=None)
@given(st.sampled_from(["panda", "ur5", "puma560", "twolink"]), st.integers(0, 2**31 - 1),
       st.sampled_from(["yoshikawa", "condition", "inverse_condition", "min_singular"]),
       st.sampled_from(["full", "translation", "rotation"]))
def test_robot_form_equals_the_jacobian_form(name, seed, kind, part):
    r = robot(name)
    q = r.random_configuration(seed)
    J = pin_jacobian(r, q)
    assert manipulability(r, q, kind, part) == pytest.approx(manipulability(J, kind, part), rel=1e-9, abs=1e-12)
    assert manipulability(r, q, kind=kind, part=part) == manipulability(r, q, kind, part)
    for fn in (velocity_ellipsoid, force_ellipsoid):
        for p in ("translation", "rotation"):
            (ra, Ua), (rb, Ub) = fn(r, q, p), fn(J, p)
            assert np.allclose(ra, rb, rtol=1e-9, atol=1e-12)
            assert np.allclose(np.abs(Ua.T @ Ub).diagonal()[np.isfinite(ra) & (ra > 1e-9)], 1.0, atol=1e-6)
    rep_r, rep_j = singularity(r, q), singularity(J)
    assert rep_r.rank == rep_j.rank and rep_r.sigma_min == pytest.approx(rep_j.sigma_min, abs=1e-12)
    V = np.array([0.1, -0.2, 0.3, 0.05, 0.0, -0.1])
    assert np.allclose(resolved_rate(r, q, V, "dls", damping=0.01), resolved_rate(J, V, "dls", damping=0.01),
                       atol=1e-9)
    R = r.frame_pose(q)[:3, :3].T
    assert np.allclose(jacobian_in_frame(r, q, R), jacobian_in_frame(J, R), atol=1e-12)


def test_frame_argument_takes_another_frame():
    r = robot("panda")
    q = r.configurations["ready"]
    J5 = pin_jacobian(r, q, "panda_link5")
    assert manipulability(r, q, part="translation", frame="panda_link5") == pytest.approx(
        manipulability(J5, part="translation"), rel=1e-12)


def test_force_ellipsoid_is_dual_to_the_velocity_ellipsoid():
    """A force on the ellipsoid's surface, F = rᵢ uᵢ, needs unit joint torque ‖Jᵀ F‖ = 1 (the definition),
    and its radii are 1/σ of the closed-form planar J_v; a lost direction has radius ∞."""
    r = robot("twolink")
    for q2 in (0.3, 1.2, 2.5):
        q = np.array([0.4, q2])
        radii, axes = force_ellipsoid(r, q, "translation")
        Jv = pin_jacobian(r, q)[3:]
        for i in range(3):
            if np.isfinite(radii[i]):
                assert np.linalg.norm(Jv.T @ (radii[i] * axes[:, i])) == pytest.approx(1.0, rel=1e-9)
            else:
                assert np.allclose(Jv.T @ axes[:, i], 0.0, atol=1e-12)  # no torque resists it
        l1, l2 = 1.0, 0.8
        s1, s12, c1, c12 = np.sin(0.4), np.sin(0.4 + q2), np.cos(0.4), np.cos(0.4 + q2)
        J2 = np.array([[-l1 * s1 - l2 * s12, -l2 * s12], [l1 * c1 + l2 * c12, l2 * c12]])
        sig = np.sqrt(np.linalg.eigvalsh(J2 @ J2.T))  # ascending
        assert np.allclose(np.sort(radii[np.isfinite(radii)]), np.sort(1.0 / sig), rtol=1e-9)


def test_analytical_jacobian_from_the_robot():
    """(robot, q, seq): the Euler angles of the tool at q, E(φ)⁻¹ on the angular rows — against a finite
    difference of the Euler angles along the joint motion."""
    r = robot("ur5")
    q = np.array([0.3, -0.8, 1.1, -0.4, 0.9, 0.2])
    Ja = analytical_jacobian(r, q, "ZYX")
    from robokit.spatial import euler_from_matrix

    h = 1e-6
    for j in range(6):
        dq = np.zeros(6)
        dq[j] = h
        dphi = (euler_from_matrix(r.frame_pose(q + dq)[:3, :3], "ZYX")
                - euler_from_matrix(r.frame_pose(q - dq)[:3, :3], "ZYX")) / (2 * h)
        assert np.allclose(Ja[:3, j], dphi, atol=1e-6)


def test_models_lists_names_and_formats():
    cat = rk.models()
    import example_robot_data as erd

    assert set(cat) == {"twolink", "rrr", "puma560"} | set(erd.ROBOTS)
    assert {".yaml", ".urdf", ".xacro", ".xml"} <= set(cat.formats)
    text = repr(cat)
    assert text.startswith("robokit.load knows ") and "panda" in text and "example-robot-data" in text
    assert "reads files:" in text.splitlines()[-1]
    assert "<table>" in cat._repr_html_()
    assert all(r.note for r in cat.rows if r.name in ("ur5", "panda"))


@pytest.mark.parametrize("name,needle", [("Panda", "did you mean 'panda'"), ("PUMA560", "did you mean 'puma560'"),
                                         ("ur_5", "did you mean 'ur5'"), ("iiwa", "iiwa14.xml"),
                                         ("KUKA", "KUKA LBR iiwa"), ("ur5e", "ur_type"), ("gen3", "gen3.xml")])
def test_unknown_names_suggest_the_nearest(name, needle):
    with pytest.raises(rk.InputError) as e:
        rk.load(name)
    msg = str(e.value)
    assert msg.startswith(f"model: unknown robot {name!r}") and needle in msg and "rk.models()" in msg
