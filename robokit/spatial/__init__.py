"""robokit.spatial — rotations and rigid motions; no robot in here.

Modules: ``basics`` (near_zero, normalize), ``so3`` (SO(3)/so(3), ZYX Euler of the seed
library), ``se3`` (SE(3)/se(3), adjoints), ``euler`` (all 12 sequences, intrinsic and
extrinsic), ``quaternion`` (scalar first), ``axis_angle`` (Rodrigues, two-vector), ``se2``
(planar poses), ``lines`` (the common normal of two lines). Twists are ``(ω, v)``, angular first; quaternions ``(w, x, y, z)``.

A parameter ``R`` of these modules is a 3×3 rotation matrix and ``T`` a 4×4 homogeneous
transform, checked on entry by :func:`~robokit.spatial.so3.check_rotation` and
:func:`~robokit.spatial.se3.check_transform` (distance to SO(3) ≤ 1e-6, last row
``[0, 0, 0, 1]``; :class:`~robokit.errors.InputError` otherwise); each function's docstring
says only what its ``R`` or ``T`` is to it.
"""
from robokit.spatial.basics import *  # noqa: F401,F403
from robokit.spatial.basics import __all__ as _basics_all
from robokit.spatial.so3 import *  # noqa: F401, F403
from robokit.spatial.so3 import __all__ as _so3_all
from robokit.spatial.se3 import *  # noqa: F401, F403
from robokit.spatial.se3 import __all__ as _se3_all

from robokit.spatial.euler import *  # noqa: F401,F403
from robokit.spatial.euler import __all__ as _euler_all
from robokit.spatial.quaternion import *  # noqa: F401,F403
from robokit.spatial.quaternion import __all__ as _quat_all
from robokit.spatial.axis_angle import *  # noqa: F401,F403
from robokit.spatial.axis_angle import __all__ as _aa_all
from robokit.spatial.se2 import *  # noqa: F401,F403
from robokit.spatial.se2 import __all__ as _se2_all
from robokit.spatial.lines import *  # noqa: F401,F403
from robokit.spatial.lines import __all__ as _lines_all

__all__ = (list(_basics_all) + list(_so3_all) + list(_se3_all) + list(_euler_all) + list(_quat_all)
           + list(_aa_all) + list(_se2_all) + list(_lines_all))
