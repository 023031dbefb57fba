"""PhysicalityWarning: one per link whose inertia no body of matter has, naming the link and the
violated inequality; ``strict=True`` refuses; physical robots load silently.

Expected values come from the numbers the test files state (eigenvalues computed here with
numpy from the URDF's own ``<inertia>``), never from robokit."""
import sys
import warnings
import xml.etree.ElementTree as ET
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings, strategies as st

import robokit
from robokit.description.inertia import link_inertias, physicality_problem
from robokit.errors import InputError, PhysicalityWarning

sys.path.insert(0, str(Path(__file__).parent))
from urdf_text import arm, inertial, joint, link  # noqa: E402

pybullet_data = pytest.importorskip("pybullet_data")
XARM6 = Path(pybullet_data.getDataPath()) / "xarm" / "xarm6_robot.urdf"


def _load(path, **kw):
    """(robot, [PhysicalityWarning messages]) of one load, every warning recorded."""
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        robot = robokit.load(path, **kw)
    return robot, [str(w.message) for w in caught if issubclass(w.category, PhysicalityWarning)]


def _file_moments(path):
    """{link: sorted principal moments} straight from a URDF's <inertia> elements."""
    out = {}
    for el in ET.parse(path).getroot().findall("link"):
        ine = el.find("inertial/inertia")
        if ine is None:
            continue
        g = {k: float(ine.get(k, 0.0)) for k in ("ixx", "iyy", "izz", "ixy", "ixz", "iyz")}
        I = np.array([[g["ixx"], g["ixy"], g["ixz"]], [g["ixy"], g["iyy"], g["iyz"]], [g["ixz"], g["iyz"], g["izz"]]])
        out[el.get("name")] = np.sort(np.linalg.eigvalsh(I))
    return out


def test_xarm6_links_2_and_3_break_the_triangle_inequality():
    moments = _file_moments(XARM6)
    broken = sorted(n for n, l in moments.items() if l[0] + l[1] < l[2])
    assert broken == ["link2", "link3"]  # the file's own numbers, checked with numpy
    robot, found = _load(XARM6)
    assert len(found) == 2
    for name, msg in zip(broken, found):
        l = moments[name]
        assert f"link {name!r}" in msg and "triangle inequality I1 + I2 ≥ I3" in msg
        assert f"{l[0] + l[1]:.6g} < {l[2]:.6g}" in msg
    assert sum(1 for n in robot.notes if "triangle" in n) == 2
    with pytest.raises(InputError, match=r"strict=True refuses it.*'link2'.*'link3'"):
        robokit.load(XARM6, strict=True)


@pytest.mark.parametrize("name", ["ur5", "panda", "rrr", "twolink", "puma560"])
def test_physical_robots_and_dh_tables_load_without_warning(name):
    robot, found = _load(name, strict=True)
    assert found == [] and robot.n > 0


def test_shipped_urdfs():
    """rrr and twolink (point masses) are physical; PUMA 560 as published (Armstrong et al.) gives
    link 1 an inertia about its axis but no mass and link 3 moments that break the triangle
    inequality — its URDF says so (its DH table, the course's parameter set, is not checked)."""
    from robokit.description.models import model_path

    for name in ("rrr", "twolink"):
        assert _load(model_path(name, ".urdf"))[1] == []
    moments = _file_moments(model_path("puma560", ".urdf"))
    l1, l3 = moments["link_1"], moments["link_3"]
    assert l1.max() > 0 and l3[0] + l3[1] < l3[2]
    _, found = _load(model_path("puma560", ".urdf"))
    assert len(found) == 2
    assert "link 'link_1': mass 0 kg with a nonzero rotational inertia" in found[0]
    assert "link 'link_3'" in found[1] and f"< {l3[2]:.6g}" in found[1]


CASES = {
    # link l2's inertial, what the warning must say
    "triangle": (inertial(1.0, 0.1, 0.1, 0.3), "0.1 + 0.1 = 0.2 < 0.3"),
    "massless with inertia": (inertial(0.0, 0.1, 0.1, 0.1), "mass 0 kg with a nonzero rotational inertia"),
    "triangle off-axis": (inertial(1.0, 0.2, 0.2, 0.2, ixy=0.15, xyz="0.1 0.2 0", rpy="0.3 0.2 0.1"),
                          "break the triangle inequality"),
}


@pytest.mark.parametrize("case", sorted(CASES))
def test_one_warning_naming_the_link_and_the_inequality(tmp_path, case):
    body, expected = CASES[case]
    path = tmp_path / "arm.urdf"
    path.write_text(arm({"l2": body}))
    robot, found = _load(path)
    assert len(found) == 1 and f"link 'l2': " in found[0] and expected in found[0]
    assert str(path) in found[0]
    with pytest.raises(InputError, match="'l2'"):
        robokit.load(path, strict=True)


def test_off_axis_case_is_really_broken():
    # ixx = iyy = izz = 0.2, ixy = 0.15: moments 0.05, 0.2, 0.35 → 0.05 + 0.2 < 0.35
    l = np.sort(np.linalg.eigvalsh(np.array([[0.2, 0.15, 0], [0.15, 0.2, 0], [0, 0, 0.2]])))
    assert np.allclose(l, [0.05, 0.2, 0.35]) and l[0] + l[1] < l[2]


def test_the_tolerance_is_relative_to_the_moments(tmp_path):
    """A thin disk sits on the boundary I1 + I2 = I3: its printed digits may fall either side by
    their rounding; 1e-9 relative is not reported, 1e-4 relative is."""
    c = 3.7e-4
    for excess, warned in ((1e-9, False), (1e-4, True)):
        path = tmp_path / f"disk{excess:g}.urdf"
        path.write_text(arm({"l3": inertial(0.5, c, c, 2 * c * (1 + excess))}))
        assert (len(_load(path)[1]) == 1) is warned
    tiny = tmp_path / "tiny.urdf"  # the same shape 1000 times smaller still warns: the scale does not matter
    tiny.write_text(arm({"l3": inertial(0.5, c * 1e-3, c * 1e-3, 2 * c * 1e-3 * (1 + 1e-4))}))
    assert len(_load(tiny)[1]) == 1


def test_a_fixed_child_is_checked_as_its_own_link(tmp_path):
    """A tool fixed to l3 with an impossible inertia: Pinocchio adds it to l3's body (whose sum
    may look fine); the warning names the tool."""
    tool = link("tool", inertial(0.2, 0.01, 0.01, 0.05))
    path = tmp_path / "tool.urdf"
    path.write_text(arm({"l3": inertial(3.0, 0.5, 0.5, 0.5)}, [tool], [joint("tool_joint", "l3", "tool", "fixed",
                                                                            xyz="0.3 0 0")]))
    _, found = _load(path)
    assert len(found) == 1 and "link 'tool'" in found[0] and "0.01 + 0.01 = 0.02 < 0.05" in found[0]


def test_a_locked_finger_moves_with_the_chain_and_is_checked_but_the_base_is_not(tmp_path):
    finger = link("finger", inertial(0.05, 0.001, 0.001, 0.01))
    base_bad = {"base": inertial(0.0, 1.0, 1.0, 1.0)}  # a static base PyBullet-style: enters no result
    path = tmp_path / "finger.urdf"
    path.write_text(arm(base_bad, [finger], [joint("jf", "l2", "finger", xyz="0.1 0 0")]))
    robot, found = _load(path, tip="l3")
    assert "jf" in robot.locked_joints
    assert len(found) == 1 and "link 'finger'" in found[0]


def test_a_programmatic_model_with_a_negative_moment_warns_through_the_builder():
    """The check lives in the builder, so any format (a Pinocchio model from MJCF, SDF, code) gets it."""
    import pinocchio as pin

    from robokit.description.builder import build_robot, strict_loading
    from robokit.description.spec import RobotSpec

    model = pin.Model()
    j = model.addJoint(0, pin.JointModelRZ(), pin.SE3.Identity(), "hinge")
    bad = pin.Inertia.FromDynamicParameters(np.array([1.0, 0, 0, 0, -0.01, 0, 0.1, 0, 0, 0.1]))  # m, mc, I
    model.appendBodyToJoint(j, bad, pin.SE3.Identity())
    model.addJointFrame(j)
    model.addBodyFrame("paddle", j, pin.SE3.Identity(), model.getFrameId("hinge"))
    spec = RobotSpec("urdf", path="/nonexistent/paddle.urdf")
    with pytest.warns(PhysicalityWarning, match=r"link 'paddle': principal moment I1 = -0.01 kg·m² < 0"):
        build_robot("paddle", model, "paddle", [None, None], {}, spec)
    with strict_loading(), pytest.raises(InputError, match="'paddle'"):
        build_robot("paddle", model, "paddle", [None, None], {}, spec)


# ------------------------------------------------------------------------ properties
def _random_body(rng_draw):
    """Mass and inertia about the COM of a random cloud of point masses (physical by construction)."""
    pts, masses = rng_draw
    pts, masses = np.asarray(pts), np.asarray(masses)
    m = masses.sum()
    c = (masses[:, None] * pts).sum(0) / m
    r = pts - c
    I = sum(mi * (ri @ ri * np.eye(3) - np.outer(ri, ri)) for mi, ri in zip(masses, r))
    return m, I


clouds = st.integers(2, 12).flatmap(lambda k: st.tuples(
    st.lists(st.lists(st.floats(-1, 1), min_size=3, max_size=3), min_size=k, max_size=k),
    st.lists(st.floats(0.01, 5.0), min_size=k, max_size=k)))


@settings(max_examples=200, deadline=None)
@given(clouds)
def test_any_cloud_of_point_masses_is_physical(cloud):
    m, I = _random_body(cloud)
    assert physicality_problem(m, I) is None


@settings(max_examples=25, deadline=None)
@given(st.lists(st.tuples(st.floats(0.1, 5.0), st.floats(1e-4, 1.0), st.floats(1e-4, 1.0), st.floats(1e-4, 1.0)),
                min_size=2, max_size=4))
def test_each_links_own_inertia_is_recovered_from_the_merged_body(bodies):
    """A moving link with links fixed to it: Pinocchio merges them; link_inertias gives back each
    link's mass and principal moments as the file states them."""
    import pinocchio as pin

    from urdf_text import urdf

    links = [link("base", inertial(1.0))]
    joints = []
    for k, (m, a, b, c) in enumerate(bodies):
        links.append(link(f"b{k}", inertial(m, a, b, c, xyz=f"0.{k} 0.1 0", rpy=f"0.{k} 0.2 0.3")))
        parent = "base" if k == 0 else "b0"
        kind = "revolute" if k == 0 else "fixed"
        joints.append(joint(f"j{k}", parent, f"b{k}", kind, xyz=f"0.1 0.{k} 0.2", rpy=f"0 0.{k} 0.5"))
    model = pin.buildModelFromXML(urdf(links, joints))
    got = {li.link: li for li in link_inertias(model)}
    for k, (m, a, b, c) in enumerate(bodies):
        li = got[f"b{k}"]
        assert abs(li.mass - m) <= 1e-12 * m
        assert np.allclose(np.sort(np.linalg.eigvalsh(li.inertia)), np.sort([a, b, c]), rtol=0, atol=1e-11)
