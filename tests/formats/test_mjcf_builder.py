"""The MJCF loader goes through the one model builder (``model_builder.build_model``).

Two references: the models the loader's former own Pinocchio construction built
(``tests/data/mjcf_fingerprints.json``, made by ``python tests/formats/mjcf_fingerprint.py`` at
main 6fccad0, before the change), and MuJoCo itself for what that corpus lacks (ball and free
joints). The MuJoCo comparisons of mass matrix, inverse dynamics and site poses are in
``test_mjcf.py``, ``test_mjcf_compiler.py`` and ``tests/descriptions``.
"""
import json
import tempfile
from pathlib import Path

import numpy as np
import pytest

from tests.formats import mjcf_fingerprint as mf

mujoco = pytest.importorskip("mujoco", reason="MuJoCo is the reference (pip install mujoco)")

STORED = json.loads(mf.OUT.read_text())


@pytest.fixture(scope="module")
def current():
    with tempfile.TemporaryDirectory() as tmp:
        return {name: mf.built(path) for name, path in mf.sources(Path(tmp)).items()}


def _same(new, ref, where):
    """Equal structure and strings; numbers equal to 1e-12 of their scale (the stored file is
    exact: a number differing by rounding on another CPU is the only slack)."""
    if isinstance(ref, dict):
        assert set(new) == set(ref), where
        for k in ref:
            _same(new[k], ref[k], f"{where}/{k}")
    elif isinstance(ref, list) and ref and all(isinstance(x, (int, float)) and not isinstance(x, bool) for x in ref):
        a, b = np.asarray(new, dtype=float), np.asarray(ref, dtype=float)
        scale = max(1.0, float(np.abs(b[np.isfinite(b)]).max(initial=0.0)))
        np.testing.assert_allclose(a, b, rtol=0.0, atol=1e-12 * scale, err_msg=where)
    elif isinstance(ref, list):
        assert len(new) == len(ref), where
        for k, (x, y) in enumerate(zip(new, ref)):
            _same(x, y, f"{where}[{k}]")
    else:
        assert new == ref, where


@pytest.mark.parametrize("name", sorted(STORED))
def test_mjcf_model_is_what_the_former_construction_built(name, current):
    if name not in current:
        pytest.skip(f"{name}: its source is not installed")
    new, ref = current[name], STORED[name]
    # deliberate differences, in what only drawing uses: a primitive carries the builder's
    # overrideMaterial=True with its rgba (Pinocchio's URDF parser's convention; the viewer uses the
    # flag for mesh files only), and a collision shape now carries its geom's rgba (was black)
    for go, was in zip(new["visual"], ref["visual"]):
        if go["meshPath"] == "":
            go["overrideMaterial"] = was["overrideMaterial"]
    for go, was in zip(new["collision"], ref["collision"]):
        go["meshColor"], go["overrideMaterial"] = was["meshColor"], was["overrideMaterial"]
    _same(new, ref, name)


def test_fingerprints_cover_several_joints_welds_sites_meshes_and_masks():
    """The stored corpus exercises every part of the construction (so the test above means something)."""
    frames = {n: [(f["name"], f["type"]) for f in fp["frames"]] for n, fp in STORED.items()}
    assert ("a", "BODY") in frames["multi"] and sum(t == "JOINT" for _, t in frames["multi"]) == 5
    assert not any(t == "FIXED_JOINT" for n, fp in frames.items() for name, t in fp if name != "universe")
    assert [n for n, t in frames["welded"] if t == "OP_FRAME"] == ["s0", "s1", "s2", "s3", "tool"]
    assert any(g["meshPath"].endswith(".stl") for g in STORED["ur5"]["visual"])
    assert STORED["contacts"]["masks"]["ball"][:2] == [2, 2]


def _write(tmp_path, xml):
    path = tmp_path / "robot.xml"
    path.write_text(xml)
    return path


def _built(path):
    from robokit.description.mjcf_compile import compile_mjcf
    from robokit.description.mjcf_description import description_from_mjcf
    from robokit.description.model_builder import build_model

    return build_model(description_from_mjcf(compile_mjcf(path), 1))[0]


@pytest.mark.parametrize("top", ['<freejoint name="free"/>', '<joint name="hinge0" axis="0 1 0" pos="0 0 0.1"/>'])
def test_ball_and_free_joints_place_bodies_as_mujoco(top, tmp_path):
    import pinocchio as pin

    xml = f"""<mujoco><worldbody><body name="a" pos="0.1 0.2 0.3" euler="10 20 30">{top}
      <geom type="box" size="0.1 0.05 0.02"/>
      <body name="b" pos="0.3 0 0"><joint name="ball" type="ball" pos="0 0 0.05"/><geom size="0.05"/>
        <body name="c" pos="0.2 0 0"><joint name="h" axis="0 0 1" ref="30"/><joint name="s" type="slide" axis="1 1 0"/>
          <geom type="capsule" fromto="0 0 0 0.2 0 0" size="0.02"/><site name="tip" pos="0.2 0 0"/></body></body>
    </body></worldbody></mujoco>"""
    path = _write(tmp_path, xml)
    model = _built(path)
    names = [f.name for f in model.frames]
    assert [n for n, f in zip(names, model.frames) if f.type == pin.FrameType.BODY] == ["a", "b", "c"]
    m = mujoco.MjModel.from_xml_path(str(path))
    d, data = mujoco.MjData(m), model.createData()
    free, ball = int(mujoco.mjtJoint.mjJNT_FREE), int(mujoco.mjtJoint.mjJNT_BALL)
    rng = np.random.default_rng(4)
    for _ in range(5):
        qpos = rng.uniform(-1, 1, m.nq)
        for j in range(m.njnt):  # unit quaternions for the ball and free joints
            a, kind = m.jnt_qposadr[j], int(m.jnt_type[j])
            k = a + 3 if kind == free else a
            if kind in (free, ball):
                qpos[k:k + 4] /= np.linalg.norm(qpos[k:k + 4])
        d.qpos[:] = qpos
        mujoco.mj_kinematics(m, d)
        q = qpos.copy()
        for j in range(m.njnt):  # Pinocchio's quaternion is (x, y, z, w), MuJoCo's (w, x, y, z)
            a, kind = m.jnt_qposadr[j], int(m.jnt_type[j])
            k = a + 3 if kind == free else a
            if kind in (free, ball):
                q[k:k + 4] = np.r_[qpos[k + 1:k + 4], qpos[k]]
        pin.framesForwardKinematics(model, data, q)
        for body in ("a", "b", "c"):
            T = data.oMf[model.getFrameId(body)]
            i = mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_BODY, body)
            assert np.allclose(T.translation, d.xpos[i], atol=1e-12)
            assert np.allclose(T.rotation, d.xmat[i].reshape(3, 3), atol=1e-12)
        T = data.oMf[model.getFrameId("tip")]
        assert np.allclose(T.translation, d.site_xpos[0], atol=1e-12)
