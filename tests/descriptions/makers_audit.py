r"""Makers' robot packages against their own engines, every link frame included.

Run ``python -m tests.descriptions.makers_audit CASES.py [--samples 20] [--json out.jsonl]``.
``CASES.py`` defines ``CASES``, a list of dicts::

    CASES = [dict(maker="Stäubli", label="tx90", path="/ws/staubli_tx90_support/urdf/tx90.xacro",
                  package_dirs=["/ws"], xacro_args={}, tip=None)]

(``package_dirs``: folders holding the maker's package folders, given to robokit and to the xacro
program's ``$(find)``; ``xacro_args``: the maker's launch arguments; ``tip``: for a tree.)

Each robot is loaded with :func:`robokit.load` as its maker's launch file loads it, then held
against the file's own engine (:mod:`tests.descriptions.corpus`'s engines) at random states within
the limits: for URDF and xacro, Pinocchio on the raw text (the xacro program's expansion), the
whole tree, the chain's rows and columns taken out; for MJCF, MuJoCo itself. Compared: the tip
pose, the pose of every frame robokit has that the engine names too (every link of the chain, and
the links fixed to it), the Jacobian, M, gravity and inverse dynamics, relative to each quantity's
largest entry (poses: position to the largest tip distance, rotation absolute). A robot robokit
refuses is tried on the engine, so that a refusal the engine does not share shows up. The fetched
repositories are not part of the project: this runs where they are, not in CI.
"""
from __future__ import annotations

import argparse
import json
import runpy
import sys
import warnings
from pathlib import Path
from typing import Any

import numpy as np

from tests.descriptions import corpus


def _urdf_text(path: Path, args: dict[str, str], roots: list[Path]) -> str:
    if path.suffix == ".xacro":
        corpus.PACKAGE_ROOTS[:] = roots
        return corpus.xacro_program(path, args)
    return path.read_text()


def _pinocchio(robot: Any, text: str) -> tuple[Any, Any]:
    """Pinocchio's model of the whole text (Drake's reflected inertia as armature) and the frames it
    shares with ``robot``, as (engine, frame ids by name)."""
    import pinocchio as pin

    model = pin.buildModelFromXML(text)
    for jn, value in corpus.drake_urdf_reflected_inertia(text).items():
        if model.existJointName(jn):
            model.armature[model.joints[model.getJointId(jn)].idx_v] = value
    engine = corpus.PinocchioEngine(model, robot)
    body = pin.FrameType.BODY
    frames = {f: model.getFrameId(f, body) for f in robot.frame_names if model.existFrame(f, body)}
    return engine, lambda: {f: engine.data.oMf[k].homogeneous.copy() for f, k in frames.items()}


def _mujoco(robot: Any, path: Path) -> tuple[Any, Any]:
    engine = corpus.MujocoEngine(path, robot)
    mj = engine.mj
    ids = {f: mj.mj_name2id(engine.m, mj.mjtObj.mjOBJ_BODY, f) for f in robot.frame_names}
    ids = {f: k for f, k in ids.items() if k >= 0}

    def poses() -> dict[str, np.ndarray]:
        out = {}
        for f, k in ids.items():
            T = np.eye(4)
            T[:3, :3], T[:3, 3] = engine.d.xmat[k].reshape(3, 3), engine.d.xpos[k]
            out[f] = T
        return out

    return engine, poses


def compare(robot: Any, engine: Any, frames: Any, samples: int = 20, seed: int = 1) -> dict[str, float]:
    """Largest relative difference of the tip pose, the shared frames' poses, J, M, gravity and RNEA.

    Parameters
    ----------
    robot : robokit.Robot
        The robot as robokit loaded it.
    engine : callable
        ``engine(q, dq, ddq) -> (T, J, tau, M)`` (:mod:`tests.descriptions.corpus`'s engines).
    frames : callable
        The engine's poses of the shared frames after its last call, by name.
    samples : int
        Random states within the limits.
    seed : int
        Of the states.

    Returns
    -------
    dict of str to float
        ``tip``, ``frames`` (the largest over the shared frames), ``J``, ``M``, ``gravity``,
        ``RNEA``; ``nframes`` the number of shared frames.
    """
    rng = np.random.default_rng(seed)
    pairs, reach = [], 1e-3
    for _ in range(samples):
        q = robot.random_configuration(rng)
        dq, ddq = rng.standard_normal(robot.n), rng.standard_normal(robot.n)
        T, J, tau, M = engine(q, dq, ddq)
        g = engine(q, 0 * dq, 0 * ddq)[2]
        theirs = frames()
        mine = {f: robot.frame_pose(q, f) for f in theirs}
        ours = (robot.frame_pose(q), robot.jacobian(q, reference="local_world_aligned").reshape(6, robot.n),
                robot.rnea(q, dq, ddq), robot.crba(q), robot.gravity_torques(q))
        pairs.append(((T, J, tau, M, g, theirs), ours + (mine,)))
        reach = max(reach, float(np.linalg.norm(T[:3, 3])))

    def pose(a: np.ndarray, b: np.ndarray) -> float:
        return max(float(np.abs(a[:3, :3] - b[:3, :3]).max()), float(np.abs(a[:3, 3] - b[:3, 3]).max()) / reach)

    out = {"tip": max(pose(o[0], t[0]) for t, o in pairs),
           "frames": max((pose(o[5][f], t[5][f]) for t, o in pairs for f in t[5]), default=0.0)}
    for key, k in (("J", 1), ("RNEA", 2), ("M", 3), ("gravity", 4)):
        scale = max(max(float(np.abs(t[k]).max()) for t, _ in pairs), 1e-300)
        out[key] = max(float(np.abs(o[k] - t[k]).max()) for t, o in pairs) / scale
    out["nframes"] = len(pairs[0][0][5])
    return out


def run_case(case: dict[str, Any], samples: int = 20) -> dict[str, Any]:
    """Load one case with robokit and hold it against its engine.

    Parameters
    ----------
    case : dict
        ``maker``, ``label``, ``path``; optional ``package_dirs``, ``xacro_args``, ``tip``.
    samples : int
        Random states.

    Returns
    -------
    dict
        The case with ``n``, ``tip_used``, ``engine`` and ``errors`` (:func:`compare`), or
        ``refused`` (robokit's message) and ``engine_accepts`` (True, or the engine's message).
    """
    import robokit

    path = Path(case["path"])
    args = dict(case.get("xacro_args") or {})
    roots = [Path(p) for p in case.get("package_dirs") or []]
    row: dict[str, Any] = {k: str(v) if isinstance(v, Path) else v for k, v in case.items()}
    options: dict[str, Any] = {}
    if path.suffix != ".xml":
        options["package_dirs"] = [str(p) for p in roots]
    if path.suffix == ".xacro":
        options["xacro_args"] = args
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            robot = robokit.load(path, case.get("tip"), **options)
    except Exception as exc:
        row["refused"] = f"{type(exc).__name__}: {exc}"
        try:
            if path.suffix == ".xml":
                import mujoco

                mujoco.MjModel.from_xml_path(str(path))
            else:
                import pinocchio as pin

                pin.buildModelFromXML(_urdf_text(path, args, roots))
            row["engine_accepts"] = True
        except Exception as engine_exc:
            row["engine_accepts"] = f"{type(engine_exc).__name__}: {engine_exc}"
        return row
    row.update(n=robot.n, tip_used=robot.tip)
    if path.suffix == ".xml":
        row["engine"] = "MuJoCo"
        engine, frames = _mujoco(robot, path)
    else:
        row["engine"] = "xacro + Pinocchio" if path.suffix == ".xacro" else "Pinocchio"
        engine, frames = _pinocchio(robot, _urdf_text(path, args, roots))
    row["errors"] = compare(robot, engine, frames, samples)
    return row


def main(argv: list[str] | None = None) -> int:
    """Run the cases of a file and print one line per robot.

    Parameters
    ----------
    argv : list of str, optional
        ``CASES.py [--samples N] [--json OUT]``.

    Returns
    -------
    int
        1 if a robot disagrees with its engine by more than 1e-9 or robokit refuses one its engine
        accepts, else 0.
    """
    parser = argparse.ArgumentParser(prog="python -m tests.descriptions.makers_audit")
    parser.add_argument("cases")
    parser.add_argument("--samples", type=int, default=20)
    parser.add_argument("--json")
    ns = parser.parse_args(argv)
    cases = runpy.run_path(ns.cases)["CASES"]
    bad = 0
    out = open(ns.json, "w", encoding="utf-8") if ns.json else None
    for case in cases:
        row = run_case(case, ns.samples)
        if out:
            out.write(json.dumps(row) + "\n")
        if "errors" in row:
            e = row["errors"]
            worst = max(v for k, v in e.items() if k != "nframes")
            bad += worst > corpus.TOLERANCE
            print(f"{row['maker']:12} {row['label']:40} n={row['n']} {row['engine']:18} "
                  + " ".join(f"{k}={v:.0e}" for k, v in e.items() if k != "nframes") + f" ({e['nframes']} frames)")
        else:
            bad += row["engine_accepts"] is True
            print(f"{row['maker']:12} {row['label']:40} refused: {row['refused'][:160]} | engine: "
                  f"{'accepts' if row['engine_accepts'] is True else 'refuses too'}")
    if out:
        out.close()
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
