"""robokit.description — robot descriptions: DH tables and files, DH → URDF, URDF → PoE, the Robot type, loading.

Modules: ``dh`` (DHTable, YAML format, DH forward kinematics), ``urdf_gen`` (DH → URDF),
``poe`` (URDF chain → Modern Robotics PoE parameters), ``robot`` (the Robot type), ``protocol``
(``RobotLike``, the interface robot-taking functions accept), ``models`` (the shipped models),
``spec`` (``RobotSpec``, the frozen recipe that rebuilds a robot), ``loading`` (``load``: the table
from suffix to loader), one module per format — ``dh_robots`` (DH tables and shipped models),
``urdf_files``, ``xacro_files``, ``mjcf`` (reading MJCF), ``mjcf_write`` (writing it),
``example_robots`` (example-robot-data) — the ``builder`` they share (tip choice, serial chain),
``urdf_check`` (the checks of files robokit did not write) and ``convert`` (conversions between
the formats).
"""
from robokit.description.builder import *  # noqa: F401,F403
from robokit.description.builder import __all__ as _builder_all
from robokit.description.dh import *  # noqa: F401,F403
from robokit.description.dh import __all__ as _dh_all
from robokit.description.example_robots import EXAMPLE_ROBOT_TIPS
from robokit.description.loading import *  # noqa: F401,F403
from robokit.description.loading import __all__ as _loading_all
from robokit.description.models import *  # noqa: F401,F403
from robokit.description.models import __all__ as _models_all
from robokit.description.poe import *  # noqa: F401,F403
from robokit.description.poe import __all__ as _poe_all
from robokit.description.protocol import *  # noqa: F401,F403
from robokit.description.protocol import __all__ as _protocol_all
from robokit.description.robot import *  # noqa: F401,F403
from robokit.description.robot import __all__ as _robot_all
from robokit.description import save as _save  # noqa: F401  (registers Robot.save's writer)
from robokit.description.spec import *  # noqa: F401,F403
from robokit.description.spec import __all__ as _spec_all
from robokit.description.urdf_gen import *  # noqa: F401,F403
from robokit.description.urdf_gen import __all__ as _urdf_gen_all
from robokit.description.urdf_to_dh import *  # noqa: F401,F403
from robokit.description.urdf_to_dh import __all__ as _urdf_to_dh_all
# Former names (deprecated aliases that warn; not in __all__).
from robokit.description.dh import matrix_to_rpy, rpy_to_matrix  # noqa: F401
from robokit.description.urdf_gen import dh_to_urdf  # noqa: F401
from robokit.description.urdf_to_dh import urdf_to_dh  # noqa: F401

__all__ = (list(_dh_all) + list(_urdf_gen_all) + list(_poe_all) + list(_robot_all) + list(_models_all)
           + list(_urdf_to_dh_all) + list(_protocol_all) + list(_spec_all) + list(_loading_all)
           + list(_builder_all) + ["EXAMPLE_ROBOT_TIPS"])
