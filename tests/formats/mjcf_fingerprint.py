"""Fingerprints of the Pinocchio models robokit's MJCF loader builds, to compare two builders.

``python tests/formats/mjcf_fingerprint.py`` writes ``tests/data/mjcf_fingerprints.json``: for
each MJCF robot below, the model ``load_mjcf`` hands to ``build_robot`` (every frame's name, type,
parent joint, parent frame and placement; every joint's model, placement, limits, armature and
damping; every joint's inertia; every visual and collision geometry's name, frame, placement,
shape and drawing data) and the collision masks. The stored file was made with the MJCF loader's
own Pinocchio construction (``robokit/description/_mjcf_model.py`` at main 6fccad0), before the
loader went through :func:`robokit.description.model_builder.build_model`;
``test_mjcf_builder.py`` compares the current loader with it.
"""
from __future__ import annotations

import json
import sys
import tempfile
from pathlib import Path
from typing import Any
from unittest import mock

import numpy as np

OUT = Path(__file__).resolve().parents[1] / "data" / "mjcf_fingerprints.json"

#: Three links; links 2 and 3 sit 0.15 m above link 1, a sphere hangs from link 3's end down to link 1's
#: height (class ``ghost_class``: masks 2/2, or the default 1/1).
CONTACT_ARM = """<mujoco model="contacts"><compiler angle="radian"/><default><geom contype="1" conaffinity="1"/>
  <default class="ghost"><geom contype="2" conaffinity="2"/></default></default><worldbody>
  <body name="l1"><joint name="j1" axis="0 0 1"/><geom name="g1" type="capsule" fromto="0 0 0 0.3 0 0" size="0.03"/>
    <body name="l2" pos="0.3 0 0.15"><joint name="j2" axis="0 0 1"/>
      <geom name="g2" type="capsule" fromto="0 0 0 0.3 0 0" size="0.03"/>
      <body name="l3" pos="0.3 0 0"><joint name="j3" axis="0 0 1"/>
        <geom name="g3" type="capsule" fromto="0 0 0 0.3 0 0" size="0.03"/>
        <geom name="ball" class="{ghost_class}" type="sphere" pos="0.3 0 -0.15" size="0.05"/>
        <site name="tip" pos="0.3 0 0"/></body></body></body></worldbody></mujoco>"""

#: Inline MJCF robots: each exercises a part of the construction (several joints per body with
#: anchors and ref, jointless bodies, sites, frames, primitives, meshes, contact masks, groups).
INLINE = {
    "multi": """<mujoco model="multi"><worldbody><body name="a" pos="0 0 0.1">
      <joint name="x" type="slide" axis="1 0 0" ref="0.05" range="-0.2 0.3"/>
      <joint name="y" type="slide" axis="0 1 0.3"/>
      <joint name="rz" axis="0 0 1" pos="0.05 0 0" ref="20"/>
      <geom type="box" size="0.05 0.04 0.03" pos="0.1 0 0"/>
      <body name="b" pos="0.2 0 0"><joint name="h1" axis="0 1 0" pos="0 0 0.02" ref="-15" damping="0.5"/>
        <joint name="h2" axis="1 0 0" pos="0.01 0.02 0" armature="0.1"/>
        <geom type="capsule" fromto="0 0 0 0.2 0 0" size="0.02"/><site name="tip" pos="0.2 0 0"/></body>
    </body></worldbody></mujoco>""",
    "welded": """<mujoco model="welded"><compiler angle="radian"/><option gravity="0.3 -1.2 -9.81"/><worldbody>
      <body name="base" pos="0.1 0 0.2" euler="0.1 0.2 0.3"><geom type="box" size="0.1 0.1 0.05" group="3"/>
        <site name="s0" pos="0 0 0.1"/>
        <body name="l1" pos="0 0 0.1"><joint name="j1" axis="0 0 1" range="-1.5 1.5" armature="0.02" damping="0.3"/>
          <geom type="ellipsoid" size="0.03 0.05 0.07" pos="0.1 0.1 0" euler="0.1 0.2 0.3" rgba="1 0 0 1"/>
          <site name="s1" pos="0.1 0 0"/><site name="s2" pos="0.2 0 0" euler="0 1 0"/>
          <body name="w1" pos="0.05 0 0.2" quat="0.9 0.1 0.3 -0.2"><geom type="sphere" size="0.03" contype="0" conaffinity="0"/>
            <body name="w2" pos="0.1 0 0"><site name="s3"/><geom type="cylinder" size="0.02 0.05" contype="2" conaffinity="4"/>
              <body name="l2" pos="0.3 0 0" xyaxes="0 1 0 -1 0.1 0"><joint name="j2" axis="0 1 0.2" ref="0.3"/>
                <geom type="capsule" fromto="0 0 0 0.2 0 0" size="0.02" group="4"/>
                <body name="l3" pos="0.3 0 0"><joint name="j3" type="slide" axis="1 0 0" range="-0.1 0.2" armature="0.5"/>
                  <geom type="box" size="0.02 0.03 0.04" mass="0.4"/><site name="tool" pos="0.1 0 0"/>
                </body></body></body></body></body></body>
      <body name="other" pos="1 0 0"><geom type="sphere" size="0.1"/></body></worldbody></mujoco>""",
    "contacts": CONTACT_ARM.format(ghost_class="ghost"),
}

#: The fixed-base MJCF arms of pybullet_data.
PYBULLET = ("mjcf/reacher.xml", "mjcf/pusher.xml", "mjcf/striker.xml", "mjcf/thrower.xml")

#: Shipped robots written as MJCF by robokit's writer (ur5: with STL meshes).
WRITTEN = ("twolink", "puma560", "ur5")


def _r(x: Any) -> list:
    return [float(v) for v in np.asarray(x, dtype=float).reshape(-1)]


def _shape(g: Any) -> dict:
    kind = type(g).__name__
    out: dict[str, Any] = {"type": kind}
    for attr in ("radius", "halfLength", "halfSide", "radii"):
        if hasattr(g, attr):
            out[attr] = _r(getattr(g, attr))
    if hasattr(g, "num_vertices"):
        out["num_vertices"], out["num_tris"] = int(g.num_vertices), int(g.num_tris)
        v = np.asarray(g.vertices())
        out["vertex_sum"] = _r(v.sum(axis=0)) if len(v) else [0.0, 0.0, 0.0]
    return out


#: Pinocchio's meshPath of a primitive (no file), fingerprinted as ""
_PRIMITIVES = ("", "BOX", "SPHERE", "CYLINDER", "CAPSULE", "ELLIPSOID")


def _geoms(gm: Any) -> list:
    if gm is None:
        return []
    return [{"name": go.name, "joint": int(go.parentJoint), "frame": int(go.parentFrame),
             "placement": _r(go.placement.homogeneous[:3]), "shape": _shape(go.geometry),
             "meshPath": "" if go.meshPath in _PRIMITIVES else Path(go.meshPath).name, "meshScale": _r(go.meshScale), "meshColor": _r(go.meshColor),
             "overrideMaterial": bool(go.overrideMaterial)} for go in gm.geometryObjects]


def fingerprint(model: Any, geoms: list, masks: dict) -> dict:
    """The JSON-able fingerprint of a model, its ``[visual, collision]`` and collision masks."""
    frames = [{"name": f.name, "type": str(f.type), "joint": int(f.parentJoint), "parent": int(f.parentFrame),
               "placement": _r(f.placement.homogeneous[:3])} for f in model.frames]
    joints = [{"name": model.names[i], "model": model.joints[i].shortname(), "parent": int(model.parents[i]),
               "placement": _r(model.jointPlacements[i].homogeneous[:3]),
               "inertia": [float(model.inertias[i].mass)] + _r(model.inertias[i].lever) + _r(model.inertias[i].inertia)}
              for i in range(model.njoints)]
    return {"name": model.name, "gravity": _r(model.gravity.linear), "frames": frames, "joints": joints,
            "lower": _r(model.lowerPositionLimit), "upper": _r(model.upperPositionLimit),
            "effort": _r(model.effortLimit), "velocity": _r(model.velocityLimit),
            "armature": _r(model.armature), "damping": _r(model.damping),
            "visual": _geoms(geoms[0]), "collision": _geoms(geoms[1]),
            "masks": {k: list(v) for k, v in sorted(masks.items())}}


def built(path: Path) -> dict:
    """The fingerprint of what ``load_mjcf(path)`` hands to ``build_robot``."""
    import warnings

    from robokit.description import mjcf

    seen: dict[str, Any] = {}
    real = mjcf.build_robot

    def spy(name: str, model: Any, tip: Any, geoms: list, *args: Any, **kw: Any) -> Any:
        seen["model"], seen["geoms"] = model, geoms
        return real(name, model, tip, geoms, *args, **kw)

    with mock.patch.object(mjcf, "build_robot", spy), warnings.catch_warnings():
        warnings.simplefilter("ignore")
        robot = mjcf.load_mjcf(path, allow_outside_meshes=True)  # the written ur5 names meshes of its package
    return fingerprint(seen["model"], seen["geoms"], dict(robot.contact_rules.masks))


def sources(tmp: Path) -> dict[str, Path]:
    """Every robot of the fingerprint corpus, by name, as a file (written under ``tmp``)."""
    out = {}
    for name, xml in INLINE.items():
        out[name] = tmp / f"{name}.xml"
        out[name].write_text(xml)
    try:
        import pybullet_data

        for rel in PYBULLET:
            out[Path(rel).stem] = Path(pybullet_data.getDataPath()) / rel
    except ImportError:
        pass
    from robokit.description.mjcf_write import mjcf_from_robot

    for name in WRITTEN:
        folder = tmp / name
        folder.mkdir()
        out[name] = folder / f"{name}.xml"
        out[name].write_text(mjcf_from_robot(name)[0])
    return out


def main() -> int:
    with tempfile.TemporaryDirectory() as tmp:
        prints = {name: built(path) for name, path in sources(Path(tmp)).items()}
    OUT.write_text(json.dumps(prints, indent=0, sort_keys=True) + "\n")
    print(f"wrote {OUT} ({len(prints)} robots)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
