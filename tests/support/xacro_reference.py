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
for maker in {c[0] for c in cases.values()}:
    for name in os.listdir(maker):
        if os.path.isfile(os.path.join(maker, name, "package.xml")):
            folders[name] = os.path.join(maker, name)
packages = types.ModuleType("ament_index_python.packages")
packages.get_package_share_directory = lambda name: folders[name]
index = types.ModuleType("ament_index_python")
index.packages = packages
sys.modules["ament_index_python"], sys.modules["ament_index_python.packages"] = index, packages
import xacro
sys.stdout.write(json.dumps({k: xacro.process_file(os.path.join(c[0], c[1]), mappings=c[2] if len(c) > 2 else None).toxml()
                             for k, c in cases.items()}))
"""


def xacro_urdfs(cases):
    """{label: URDF text} of ``cases`` {label: (maker folder, xacro file inside it)} or {label: (maker
    folder, xacro file, {argument: value})} (the arguments as ``xacro name:=value`` passes them), one
    subprocess for all."""
    run = subprocess.run([sys.executable, "-c", _SCRIPT,
                          json.dumps({k: [str(c[0]), *c[1:]] for k, c in cases.items()})],
                         capture_output=True, text=True, timeout=120, check=False)
    assert run.returncode == 0, run.stderr[-3000:]
    return json.loads(run.stdout)


def pinocchio_fk(urdf, robot):
    """(fk, lo, hi) of Pinocchio on ``urdf``: fk(q) the pose (4, 4) of ``robot.tip`` for robokit's joint
    vector q (the joints found by name, the others at Pinocchio's neutral), lo/hi the file's limits of
    those joints."""
    model = pin.buildModelFromXML(urdf)
    data = model.createData()
    iq = [model.joints[model.getJointId(j)].idx_q for j in robot.joint_names]
    fid = model.getFrameId(robot.tip)

    def fk(q):
        qf = pin.neutral(model)
        qf[iq] = q
        pin.framesForwardKinematics(model, data, qf)
        return data.oMf[fid].homogeneous.copy()

    return fk, np.asarray(model.lowerPositionLimit[iq]), np.asarray(model.upperPositionLimit[iq])
