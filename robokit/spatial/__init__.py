"""robokit.spatial — rotations and rigid motions; no robot in here.

Modules: ``basics`` (near_zero, normalize), ``so3`` (SO(3)/so(3), ZYX Euler of the seed
library), ``se3`` (SE(3)/se(3), adjoints). Twists are ``(ω, v)``, angular first.
"""
from robokit.spatial.basics import *  # noqa: F401,F403
from robokit.spatial.basics import __all__ as _basics_all
from robokit.spatial.so3 import *  # noqa: F401,F403
from robokit.spatial.so3 import __all__ as _so3_all
from robokit.spatial.se3 import *  # noqa: F401,F403
from robokit.spatial.se3 import __all__ as _se3_all

__all__ = list(_basics_all) + list(_so3_all) + list(_se3_all)
