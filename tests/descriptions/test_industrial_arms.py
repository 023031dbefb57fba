"""Industrial arms as ROS-Industrial publishes them (KUKA, ABB, FANUC, Stäubli; tests/data/<maker>/SOURCE),
loaded with :func:`robokit.load` from the makers' own xacro files and held against Pinocchio built
directly from the ``xacro`` program's expansion of the same files.

The reference is independent of robokit: the ``xacro`` program runs in a subprocess whose ``$(find
pkg)`` is answered by a stub ``ament_index_python.packages`` (ROS 2's package index) mapping each
package name to its vendored folder, and ``pinocchio.buildModelFromXML`` reads its output (robokit
reads URDF with its own reader). Compared at random joint values within the file's limits: the pose
of every link frame, the space, body and geometric Jacobians of the tip, M and the gravity torques
(to 1e-12 of each quantity's largest entry), the position, velocity and effort limits; and what
robokit says once about what it does not model (no inertia at all, locked mimic joints, missing
meshes).
"""
from __future__ import annotations

import warnings
from pathlib import Path

import numpy as np
import pinocchio as pin
import pytest

import robokit
from xacro_reference import xacro_urdfs

DATA = Path(__file__).resolve().parents[1] / "data"

#: label -> (maker folder under tests/data, xacro file inside it, tip, whether the file gives inertias)
ARMS = {
    "KUKA KR 6 R900 sixx": ("kuka", "kuka_kr6_support/urdf/kr6r900sixx.xacro", "tool0", False),
    "KUKA KR 210 L150": ("kuka", "kuka_kr210_support/urdf/kr210l150.xacro", "tool0", True),
    "ABB IRB 2400": ("abb", "abb_irb2400_support/urdf/irb2400.xacro", "tool0", False),
    "ABB IRB 6640-185/280": ("abb", "abb_irb6640_support/urdf/irb6640_185_280.xacro", "tool0", False),
    "FANUC LR Mate 200iD": ("fanuc", "fanuc_lrmate200id_support/urdf/lrmate200id.xacro", "tool0", False),
    "FANUC M-430iA/2P": ("fanuc", "fanuc_m430ia_support/urdf/m430ia2p.xacro", "tool0", False),
    "Staubli RX160": ("staubli", "staubli_rx160_support/urdf/rx160.xacro", "tool0", True),
}


@pytest.fixture(scope="module")
def reference() -> dict[str, str]:
    """The xacro program's URDF of every arm (one subprocess for all)."""
    return xacro_urdfs({k: (DATA / m, f) for k, (m, f, _, _) in ARMS.items()})


def load(label: str) -> tuple[robokit.Robot, list[str]]:
    """The arm as a user loads it (the file alone: its packages are found beside it), and what robokit said."""
    maker, rel, _, _ = ARMS[label]
    with warnings.catch_warnings(record=True) as said:
        warnings.simplefilter("always")
        robot = robokit.load(DATA / maker / rel)
    return robot, [str(w.message) for w in said]


@pytest.mark.parametrize("label", list(ARMS))
def test_arm_matches_pinocchio_on_the_xacro_program_output(label, reference):
    robot, said = load(label)
    model = pin.buildModelFromXML(reference[label])
    data = model.createData()
    assert robot.tip == ARMS[label][2] and robot.n == 6
    joints = [model.joints[model.getJointId(j)] for j in robot.joint_names]
    iq, iv = [j.idx_q for j in joints], [j.idx_v for j in joints]
    # the chain is the file's: its six actuated joints from base_link to tool0, in order
    assert [model.names[model.getJointId(j)] for j in robot.joint_names] == list(robot.joint_names)
    lo, hi = model.lowerPositionLimit[iq], model.upperPositionLimit[iq]
    assert np.array_equal(np.asarray(robot.qlim, float), np.c_[lo, hi])
    rv = [robot.model.joints[robot.model.getJointId(j)].idx_v for j in robot.joint_names]
    assert np.array_equal(robot.model.velocityLimit[rv], model.velocityLimit[iv])
    assert np.array_equal(robot.model.effortLimit[rv], model.effortLimit[iv])

    body = pin.FrameType.BODY
    links = [f for f in robot.frame_names if model.existFrame(f, body)]
    assert robot.tip in links and len(links) >= 8  # base_link, link_1..link_6 (or link1..), flange/tool0
    fid = model.getFrameId(robot.tip, body)
    frames = {
        pin.WORLD: robokit.Frame.WORLD, pin.LOCAL: robokit.Frame.LOCAL,
        pin.LOCAL_WORLD_ALIGNED: robokit.Frame.LOCAL_WORLD_ALIGNED,
    }
    has_mass = ARMS[label][3]
    rng = np.random.default_rng(11)
    worst = dict(pose=0.0, J=0.0, M=0.0, g=0.0)
    for _ in range(20):
        q = rng.uniform(lo, hi)
        qf = pin.neutral(model)
        qf[iq] = q
        pin.framesForwardKinematics(model, data, qf)
        for f in links:
            worst["pose"] = max(worst["pose"], np.abs(robot.frame_pose(q, f) - data.oMf[model.getFrameId(f, body)].homogeneous).max())
        for ref, rk_ref in frames.items():
            J = pin.computeFrameJacobian(model, data, qf, fid, ref)[:, iv]
            J = np.vstack([J[3:], J[:3]])  # robokit: angular rows first
            worst["J"] = max(worst["J"], np.abs(robot.jacobian(q, reference=rk_ref) - J).max() / np.abs(J).max())
        M = pin.crba(model, data, qf)
        M = (np.triu(M) + np.triu(M, 1).T)[np.ix_(iv, iv)]
        g = pin.computeGeneralizedGravity(model, data, qf)[iv]
        if has_mass:
            worst["M"] = max(worst["M"], np.abs(robot.crba(q) - M).max() / np.abs(M).max())
            worst["g"] = max(worst["g"], np.abs(robot.gravity_torques(q) - g).max() / np.abs(g).max())
        else:  # the file gives no inertia: both are exactly zero, and robokit says so
            assert not M.any() and not g.any()
            assert not robot.crba(q).any() and not robot.gravity_torques(q).any()
    assert max(worst.values()) < 1e-12, worst

    massless = [s for s in said if "has mass (the file gives none)" in s]
    assert len(massless) == (0 if has_mass else 1), said
    meshes = [s for s in said if "mesh files not found" in s]
    assert len(meshes) == 1, said  # the meshes are not vendored: one note, not one per mesh


def test_locked_mimic_joints_are_noted_once():
    """The IRB 6640's counterbalance cylinder and piston are mimic joints on a branch off the chain:
    locked at zero (what Pinocchio's model gives them too), said once."""
    robot, said = load("ABB IRB 6640-185/280")
    assert set(robot.locked_joints) >= {"joint_cylinder", "joint_piston"}
    notes = [s for s in said if "mimic joints off the chain locked" in s]
    assert len(notes) == 1 and "joint_cylinder" in notes[0] and "joint_piston" in notes[0]


def test_the_makers_packages_are_found_from_a_workspace_folder():
    """A user's own cell includes the makers' macros with ``$(find ...)`` from another folder; its
    packages sit two levels down in ``package_dirs`` (``src/<repository>/<package>``), the layout of
    a ROS workspace that holds the makers' repositories."""
    import tempfile

    with tempfile.TemporaryDirectory() as tmp:
        cell = Path(tmp, "cell.urdf.xacro")
        cell.write_text(
            '<robot name="cell" xmlns:xacro="http://wiki.ros.org/xacro">\n'
            '  <xacro:include filename="$(find kuka_kr6_support)/urdf/kr6r900sixx_macro.xacro"/>\n'
            '  <xacro:kuka_kr6r900sixx prefix="left_"/>\n'
            '  <link name="world"/>\n'
            '  <joint name="mount" type="fixed"><parent link="world"/><child link="left_base_link"/>'
            '<origin xyz="0 0.5 0.8" rpy="3.141592653589793 0 0"/></joint>\n'
            '</robot>\n')
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            robot = robokit.load(cell, package_dirs=[DATA])
            alone = robokit.load(DATA / "kuka" / ARMS["KUKA KR 6 R900 sixx"][1])
    assert robot.tip == "left_tool0" and robot.n == 6
    q = np.random.default_rng(0).uniform(-1, 1, 6)
    mount = np.diag([1.0, -1.0, -1.0, 1.0])
    mount[:3, 3] = [0, 0.5, 0.8]
    assert np.abs(robot.frame_pose(q) - mount @ alone.frame_pose(q)).max() < 1e-14
