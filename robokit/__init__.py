"""robokit: a robotics course's derivations for serial manipulators, checked against Pinocchio.

Conventions, said once: SI units; arrays are float64 ``numpy.ndarray``; twists and
wrenches are ordered angular first, ``(ω, v)`` and ``(m, f)``; quaternions are scalar
first, ``(w, x, y, z)``.

The seed function library (``near_zero`` … ``simulate_control``) and the main types are
re-exported here, so ``from robokit import matrix_log_6`` works. Each subpackage lists
its public names in ``__all__``.
"""
from robokit.errors import RobokitError, InputError

from robokit.spatial import *  # noqa: F401,F403
from robokit.spatial import __all__ as _spatial_all
from robokit.description import *  # noqa: F401,F403
from robokit.description import __all__ as _description_all
from robokit.kinematics import *  # noqa: F401,F403
from robokit.kinematics import __all__ as _kinematics_all
from robokit.dynamics import *  # noqa: F401,F403
from robokit.dynamics import __all__ as _dynamics_all
from robokit.ik import *  # noqa: F401,F403
from robokit.ik import __all__ as _ik_all
from robokit.trajectory import *  # noqa: F401,F403
from robokit.trajectory import __all__ as _trajectory_all
from robokit.control import *  # noqa: F401,F403
from robokit.control import __all__ as _control_all
from robokit.mobile import *  # noqa: F401,F403
from robokit.mobile import __all__ as _mobile_all
from robokit.workspace import *  # noqa: F401,F403
from robokit.workspace import __all__ as _workspace_all

try:
    from importlib.metadata import PackageNotFoundError as _NotFound, version as _version

    __version__ = _version("robokit")
except _NotFound:  # pragma: no cover - running from a source tree that was never installed
    __version__ = "0+unknown"

__all__ = (
    ["RobokitError", "InputError"]
    + list(_spatial_all)
    + list(_description_all)
    + list(_kinematics_all)
    + list(_dynamics_all)
    + list(_ik_all)
    + list(_trajectory_all)
    + list(_control_all)
    + list(_mobile_all)
    + list(_workspace_all)
)
