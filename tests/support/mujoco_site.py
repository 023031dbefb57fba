"""One comparison of a robot robokit loaded from an MJCF file with MuJoCo's own reading of the same
file (tests of reading a file as MuJoCo's XML parser reads it: comments holding ``--``, whitespace
before the declaration). Imported as ``mujoco_site`` (tests/conftest.py puts tests/support on sys.path)."""
from __future__ import annotations

import numpy as np
import pytest


def assert_matches_mujoco_site(robot, path, states, site: int = 0, atol: float = 1e-12) -> int:
    """At each (q, dq, ddq) of ``states``: the tip's pose against MuJoCo's site ``site``, the Jacobian
    (robokit's angular rows first) against ``mj_jacSite``, M against ``mj_fullM`` and inverse dynamics
    against ``mj_inverse`` (constraints off), absolute ``atol``, no relative slack; MuJoCo reads the
    raw file at ``path``. Returns the number of states compared."""
    mujoco = pytest.importorskip("mujoco")
    m = mujoco.MjModel.from_xml_path(str(path))
    m.opt.disableflags |= int(mujoco.mjtDisableBit.mjDSBL_CONSTRAINT)
    d = mujoco.MjData(m)
    n = 0
    for q, dq, ddq in states:
        d.qpos[:], d.qvel[:], d.qacc[:] = q, dq, ddq
        mujoco.mj_inverse(m, d)
        M = np.zeros((m.nv, m.nv))
        if hasattr(d, "qM"):  # MuJoCo 3: mj_fullM(m, dst, qM); MuJoCo 4: mj_fullM(m, d, dst)
            try:
                mujoco.mj_fullM(m, M, d.qM)
            except TypeError:
                mujoco.mj_fullM(m, d, M)
        else:
            mujoco.mj_fullM(m, d, M)
        jacp, jacr = np.zeros((3, m.nv)), np.zeros((3, m.nv))
        mujoco.mj_jacSite(m, d, jacp, jacr, site)
        T = robot.frame_pose(q)
        np.testing.assert_allclose(T[:3, 3], d.site_xpos[site], rtol=0, atol=atol)
        np.testing.assert_allclose(T[:3, :3], d.site_xmat[site].reshape(3, 3), rtol=0, atol=atol)
        np.testing.assert_allclose(robot.jacobian(q), np.vstack([jacr, jacp]), rtol=0, atol=atol)
        np.testing.assert_allclose(robot.crba(q), M, rtol=0, atol=atol)
        np.testing.assert_allclose(robot.rnea(q, dq, ddq), d.qfrc_inverse, rtol=0, atol=atol)
        n += 1
    return n
