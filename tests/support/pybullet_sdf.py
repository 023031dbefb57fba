"""A robokit robot held against PyBullet's ``loadSDF`` of an SDFormat file, in one place.

PyBullet parses the file with its own importer (TinyXML2) and computes with its own recursions, so
it is independent of robokit's SDFormat reader. :func:`assert_matches_pybullet_sdf` loads the file,
gives every link back the inertia the file writes (``loadSDF`` keeps a link's mass and inertial pose
but replaces its inertia tensor by a small sphere's; the file's moments are read here, with
ElementTree, from the file's own text, and set with ``changeDynamics`` — which takes a diagonal
only, so each tensor must be diagonal in its inertial frame), then at each state compares

* every link's centre of mass (``getLinkState``, double) with robokit's link pose times the file's
  inertial offset, and the link frame's rotation (PyBullet's centre-of-mass frame turned back by the
  inertial frame's rotation; its own link frame comes back rounded to float32);
* every link's Jacobian at the link origin (``calculateJacobian`` with ``localPosition`` 0, measured
  from the link frame; rows in the axes of the base's centre-of-mass frame, turned to the world's);
* the mass matrix (``calculateMassMatrix``), inverse dynamics and the gravity torques
  (``calculateInverseDynamics``, with the gravity vector in those same base axes).

Poses and Jacobians to ``atol``; M, τ and g relative to their largest entry, to ``rtol`` (PyBullet
diagonalizes inertias with Jacobi iterations: 10⁻¹⁶ without products of inertia). Imported as
``pybullet_sdf`` (tests/conftest.py puts tests/support on sys.path); used by
tests/description/test_sdf.py, tests/description/test_sdf_custom.py and
tests/formats/test_xml_comments.py.
"""
from __future__ import annotations

import xml.etree.ElementTree as ET
from pathlib import Path
from typing import Iterable

import numpy as np
import pytest


def file_inertials(path: str | Path) -> dict[str, tuple[np.ndarray, list[float]]]:
    """``{link: (centre of mass in the link frame, [ixx, iyy, izz])}`` read from the file's text: each
    ``<inertial><pose>`` relative to its link (no ``relative_to``), each tensor diagonal."""
    out = {}
    for link in ET.parse(path).getroot().iter("link"):
        inertial = link.find("inertial")
        if inertial is None:
            continue
        pose = inertial.find("pose")
        assert pose is None or not pose.get("relative_to"), "the helper reads inertial poses relative to the link"
        values = (pose.text or "").split() if pose is not None else []
        xyz = [float(v) for v in values[:3]] if values else [0.0] * 3
        ine = {k: float(inertial.findtext(f"inertia/{k}", "0")) for k in ("ixx", "iyy", "izz", "ixy", "ixz", "iyz")}
        assert ine["ixy"] == ine["ixz"] == ine["iyz"] == 0.0, f"{link.get('name')}: changeDynamics sets diagonals only"
        out[link.get("name", "")] = (np.array(xyz), [ine["ixx"], ine["iyy"], ine["izz"]])
    return out


def _pose(p, position, quaternion) -> np.ndarray:
    T = np.eye(4)
    T[:3, :3] = np.reshape(p.getMatrixFromQuaternion(quaternion), (3, 3))
    T[:3, 3] = position
    return T


def assert_matches_pybullet_sdf(robot, path: str | Path, states: Iterable[tuple[np.ndarray, np.ndarray, np.ndarray]],
                                *, atol: float = 1e-12, rtol: float = 1e-9,
                                inertials: dict[str, tuple[np.ndarray, list[float]]] | None = None) -> int:
    """Assert that ``robot`` computes what PyBullet's ``loadSDF`` of ``path`` computes at ``states``
    ((q, dq, ddq) in robokit's joint order); see the module docstring. ``path`` may be another file
    than the one robokit read (the same robot written without what PyBullet cannot read);
    ``inertials`` (as :func:`file_inertials` returns them) when ElementTree cannot read the file.

    Returns
    -------
    int
        The number of states compared (so that a caller can check it is not zero).
    """
    p = pytest.importorskip("pybullet")
    cid = p.connect(p.DIRECT)
    try:
        body = p.loadSDF(str(path), physicsClientId=cid)[0]
        links, movable, by_name = {}, [], {}
        for i in range(p.getNumJoints(body, physicsClientId=cid)):
            info = p.getJointInfo(body, i, physicsClientId=cid)
            links[info[12].decode()] = i
            if info[2] in (p.JOINT_REVOLUTE, p.JOINT_PRISMATIC):
                by_name[info[1].decode()] = len(movable)
                movable.append(i)
        assert sorted(by_name) == sorted(robot.joint_names), (by_name, robot.joint_names)
        dofs = [by_name[name] for name in robot.joint_names]  # robokit's joint k is PyBullet's dof dofs[k]
        inertials = file_inertials(path) if inertials is None else inertials
        for name, i in links.items():
            if name in inertials:
                p.changeDynamics(body, i, localInertiaDiagonal=inertials[name][1], physicsClientId=cid)
        g = np.asarray(robot.gravity, dtype=float)
        count = 0
        for q, dq, ddq in states:
            pos, vel, acc = (np.zeros(len(movable)) for _ in range(3))
            pos[dofs], vel[dofs], acc[dofs] = q, dq, ddq
            for k, i in enumerate(movable):
                p.resetJointState(body, i, float(pos[k]), float(vel[k]), physicsClientId=cid)
            R = _pose(p, *p.getBasePositionAndOrientation(body, physicsClientId=cid))[:3, :3]  # base COM axes
            zeros = [0.0] * len(movable)
            for name, i in links.items():
                T = robot.frame_pose(q, name)
                state = p.getLinkState(body, i, computeForwardKinematics=1, physicsClientId=cid)
                local = _pose(p, *p.getDynamicsInfo(body, i, physicsClientId=cid)[3:5])
                if name in inertials:
                    com = T[:3, :3] @ inertials[name][0] + T[:3, 3]
                    np.testing.assert_allclose(com, state[0], rtol=0, atol=atol, err_msg=f"centre of mass of {name}")
                R_link = (_pose(p, *state[:2]) @ np.linalg.inv(local))[:3, :3]
                np.testing.assert_allclose(T[:3, :3], R_link, rtol=0, atol=atol, err_msg=f"rotation of {name}")
                lin, ang = p.calculateJacobian(body, i, [0.0, 0.0, 0.0], pos.tolist(), zeros, zeros,
                                               physicsClientId=cid)
                off = np.shape(lin)[1] - len(movable)  # a floating base's six columns come first
                J = np.vstack([R @ np.array(ang)[:, off:], R @ np.array(lin)[:, off:]])[:, dofs]
                np.testing.assert_allclose(np.reshape(robot.jacobian(q, name), (6, -1)), J, rtol=0, atol=atol,
                                           err_msg=f"Jacobian of {name}")
            M = np.array(p.calculateMassMatrix(body, pos.tolist(), physicsClientId=cid))
            off = M.shape[0] - len(movable)
            M = M[off:, off:][np.ix_(dofs, dofs)]
            p.setGravity(*(R.T @ g), physicsClientId=cid)
            tau = np.array(p.calculateInverseDynamics(body, pos.tolist(), vel.tolist(), acc.tolist(),
                                                      physicsClientId=cid))[off:][dofs]
            grav = np.array(p.calculateInverseDynamics(body, pos.tolist(), zeros, zeros,
                                                       physicsClientId=cid))[off:][dofs]
            scale = max(np.abs(tau).max(), np.abs(grav).max())
            np.testing.assert_allclose(robot.crba(q), M, rtol=0, atol=rtol * np.abs(M).max(), err_msg="mass matrix")
            np.testing.assert_allclose(robot.rnea(q, dq, ddq), tau, rtol=0, atol=rtol * scale,
                                       err_msg="inverse dynamics")
            np.testing.assert_allclose(robot.gravity_torques(q), grav, rtol=0, atol=rtol * scale, err_msg="gravity")
            count += 1
        return count
    finally:
        p.disconnect(cid)
