"""robokit.ik — inverse kinematics.

``analytic``: closed-form solvers returning every solution (2-link, RRR, spherical wrist,
PUMA 560). ``numeric``: the seed library's Newton–Raphson ``ikin_body``/``ikin_space`` and
a robust Levenberg–Marquardt ``solve_ik`` with joint limits and restarts for any Robot.
``transpose``: the lecture's Jacobian-transpose iteration with viscous joint dampers.
"""
from robokit.ik.analytic import *  # noqa: F401,F403
from robokit.ik.analytic import __all__ as _analytic_all
from robokit.ik.numeric import *  # noqa: F401,F403
from robokit.ik.numeric import __all__ as _numeric_all
from robokit.ik.transpose import *  # noqa: F401,F403
from robokit.ik.transpose import __all__ as _transpose_all
from robokit.ik.workspace import *  # noqa: F401,F403
from robokit.ik.workspace import __all__ as _workspace_all

__all__ = list(_analytic_all) + list(_numeric_all) + list(_workspace_all) + list(_transpose_all)
