"""The independent reference of the makers' xacro arms (tests/data/<maker>): the ``xacro`` program's own
expansion of each file, in a subprocess where ``ament_index_python`` maps each vendored package name to its
folder, and Pinocchio built directly on that URDF (not through robokit)."""
import json
import subprocess
import sys

import numpy as np
import pinocchio as pin

_SCRIPT = r"""
import json, os, sys, types
cases = json.loads(sys.argv[1])
folders = {}
for maker in {m for m, _, _ in cases.values()}:
    for name in os.listdir(maker):
        if os.path.isfile(os.path.join(maker, name, "package.xml")):
            folders[name] = os.path.join(maker, name)
packages = types.ModuleType("ament_index_python.packages")
packages.get_package_share_directory = lambda name: folders[name]
index = types.ModuleType("ament_index_python")
index.packages = packages
sys.modules["ament_index_python"], sys.modules["ament_index_python.packages"] = index, packages
import xacro
sys.stdout.write(json.dumps({k: xacro.process_file(os.path.join(m, f), mappings=a).toxml()
                            for k, (m, f, a) in cases.items()}))
"""


def xacro_urdfs(cases):
    """{label: URDF text} of ``cases`` {label: (maker folder, xacro file inside it[, {xacro argument: value}])},
    one subprocess for all. The maker folder holds the packages (``$(find pkg)`` is the folder ``pkg`` in it);
    the arguments are the xacro program's ``name:=value`` mappings."""
    spec = {k: [str(c[0]), str(c[1]), dict(c[2]) if len(c) > 2 else {}] for k, c in cases.items()}
    run = subprocess.run([sys.executable, "-c", _SCRIPT, json.dumps(spec)],
                         capture_output=True, text=True, timeout=120, check=False)
    assert run.returncode == 0, run.stderr[-3000:]
    return json.loads(run.stdout)


def pinocchio_fk(urdf, robot):
    """(fk, lo, hi) of Pinocchio on ``urdf``: fk(q) the pose (4, 4) of ``robot.tip`` for robokit's joint
    vector q (the joints found by name, the others at Pinocchio's neutral; a continuous joint, which
    Pinocchio holds as (cos q, sin q), from its angle), lo/hi the file's limits of those joints (−inf/inf
    for a continuous joint)."""
    model = pin.buildModelFromXML(urdf)
    data = model.createData()
    joints = [model.joints[model.getJointId(j)] for j in robot.joint_names]
    fid = model.getFrameId(robot.tip)

    def fk(q):
        pin.framesForwardKinematics(model, data, configuration(model, joints, q))
        return data.oMf[fid].homogeneous.copy()

    lo = np.array([model.lowerPositionLimit[j.idx_q] if j.nq == 1 else -np.inf for j in joints])
    hi = np.array([model.upperPositionLimit[j.idx_q] if j.nq == 1 else np.inf for j in joints])
    return fk, lo, hi


def configuration(model, joints, q):
    """Pinocchio's configuration vector of ``model`` with ``joints`` (its joint models) at the angles or
    lengths ``q`` and every other joint at neutral."""
    qf = pin.neutral(model)
    for jm, value in zip(joints, q):
        qf[jm.idx_q:jm.idx_q + jm.nq] = [np.cos(value), np.sin(value)] if jm.nq == 2 else [value]
    return qf
