"""robokit.description — robot descriptions: DH tables and files, DH → URDF, URDF → PoE, the Robot type.

Modules: ``dh`` (DHTable, YAML format, DH forward kinematics), ``urdf_gen`` (DH → URDF),
``poe`` (URDF chain → Modern Robotics PoE parameters), ``robot`` (Robot, load), ``protocol``
(``RobotLike``, the interface robot-taking functions accept), ``models`` (the shipped models),
``urdf_check``/``xacro_files``/``mjcf`` (reading files robokit did not write), ``convert``
(conversions between the formats).
"""
from robokit.description.dh import *  # noqa: F401,F403
from robokit.description.dh import __all__ as _dh_all
from robokit.description.models import *  # noqa: F401,F403
from robokit.description.models import __all__ as _models_all
from robokit.description.poe import *  # noqa: F401,F403
from robokit.description.poe import __all__ as _poe_all
from robokit.description.protocol import *  # noqa: F401,F403
from robokit.description.protocol import __all__ as _protocol_all
from robokit.description.robot import *  # noqa: F401,F403
from robokit.description.robot import __all__ as _robot_all
from robokit.description.urdf_gen import *  # noqa: F401,F403
from robokit.description.urdf_gen import __all__ as _urdf_gen_all
from robokit.description.urdf_to_dh import *  # noqa: F401,F403
from robokit.description.urdf_to_dh import __all__ as _urdf_to_dh_all

__all__ = (list(_dh_all) + list(_urdf_gen_all) + list(_poe_all) + list(_robot_all) + list(_models_all)
           + list(_urdf_to_dh_all) + list(_protocol_all))
