"""robokit.ik — inverse kinematics.

``analytic``: closed-form solvers returning every solution (2-link, RRR, spherical wrist,
PUMA 560). ``closed_form``: ``ik_analytic`` for any arm whose geometry has a closed form
(Pieper's method for a spherical wrist — ``pieper`` —, the UR family's three parallel
axes — ``parallel_axes``, and every other 6R arm — ``general_6r``, Raghavan–Roth /
Manocha–Canny), ``ik_analytic_kind`` to ask which applies. ``paden_kahan``: the
Lecture 5 building blocks (``solve_trig``, Paden–Kahan subproblems 1–3). ``rrr_pose``:
the homework RRR arm with a full pose. ``numeric``: the seed library's Newton–Raphson
``ikin_body``/``ikin_space`` and a robust Levenberg–Marquardt ``solve_ik`` with joint
limits and restarts for any Robot.
``transpose``: the lecture's Jacobian-transpose iteration with viscous joint dampers.
"""
from robokit.ik.analytic import *  # noqa: F401,F403
from robokit.ik.analytic import __all__ as _analytic_all
from robokit.ik.closed_form import *  # noqa: F401,F403
from robokit.ik.closed_form import __all__ as _closed_form_all
from robokit.ik.paden_kahan import *  # noqa: F401,F403
from robokit.ik.paden_kahan import __all__ as _paden_kahan_all
from robokit.ik.rrr_pose import *  # noqa: F401,F403
from robokit.ik.rrr_pose import __all__ as _rrr_pose_all
from robokit.ik.numeric import *  # noqa: F401,F403
from robokit.ik.numeric import __all__ as _numeric_all
from robokit.ik.transpose import *  # noqa: F401,F403
from robokit.ik.transpose import __all__ as _transpose_all
from robokit.ik.workspace import *  # noqa: F401,F403
from robokit.ik.workspace import __all__ as _workspace_all

__all__ = (list(_analytic_all) + list(_closed_form_all) + list(_paden_kahan_all) + list(_rrr_pose_all)
           + list(_numeric_all) + list(_workspace_all) + list(_transpose_all))
