"""robokit.ik — inverse kinematics.

``solution``: :class:`IKSolution` and the checks the closed-form solvers share. ``analytic``:
closed-form solvers of the lecture returning every solution (2-link, RRR, spherical wrist,
PUMA 560). ``closed_form``: ``ik_analytic`` for any arm whose geometry has a closed form
(Pieper's method for a spherical wrist — ``pieper`` —, the UR family's three parallel
axes — ``parallel_axes``, and every other 6R arm — ``general_6r``, Raghavan–Roth /
Manocha–Canny, through ``closed_form.FALLBACK``), ``ik_analytic_kind`` to ask which applies, and
:class:`AnalyticIK`, the same solver as an object to hold. ``solver``: the interface
(``ClosedFormSolver``) every closed-form solver implements. ``constants``: the typed contract
with the code generators (``closed_form_constants``: each method's constants as a frozen
dataclass). ``paden_kahan``: the Lecture 5
building blocks (``solve_trig``, Paden–Kahan subproblems 1–3). ``rrr_pose``: the homework
RRR arm with a full pose. ``planar``: the vectorised closed form of planar 2R/3R arms.
``backends``: the IK back ends ``solve_ik`` tries in order (closed form, planar, compiled
LM, Pinocchio LM), each saying whether it supports a problem. ``numeric``: the seed
library's Newton–Raphson ``ikin_body``/``ikin_space`` and ``solve_ik`` for any Robot.
``transpose``: the lecture's Jacobian-transpose iteration with viscous joint dampers.
Workspace sampling (``sample_workspace``) lives in :mod:`robokit.workspace`.
"""
from robokit.ik.solution import *  # noqa: F401,F403
from robokit.ik.solution import __all__ as _solution_all
from robokit.ik.analytic import *  # noqa: F401,F403
from robokit.ik.analytic import __all__ as _analytic_all
from robokit.ik.closed_form import *  # noqa: F401,F403
from robokit.ik.closed_form import __all__ as _closed_form_all
from robokit.ik.constants import *  # noqa: F401,F403
from robokit.ik.constants import __all__ as _constants_all
from robokit.ik.solver import *  # noqa: F401,F403
from robokit.ik.solver import __all__ as _solver_all
from robokit.ik.paden_kahan import *  # noqa: F401,F403
from robokit.ik.paden_kahan import __all__ as _paden_kahan_all
from robokit.ik.rrr_pose import *  # noqa: F401,F403
from robokit.ik.rrr_pose import __all__ as _rrr_pose_all
from robokit.ik.planar import *  # noqa: F401,F403
from robokit.ik.planar import __all__ as _planar_all
from robokit.ik.numeric import *  # noqa: F401,F403
from robokit.ik.numeric import __all__ as _numeric_all
from robokit.ik.backends import *  # noqa: F401,F403
from robokit.ik.backends import __all__ as _backends_all
from robokit.ik.transpose import *  # noqa: F401,F403
from robokit.ik.transpose import __all__ as _transpose_all

__all__ = (list(_solution_all) + list(_analytic_all) + list(_closed_form_all) + list(_constants_all) + list(_solver_all)
           + list(_paden_kahan_all) + list(_rrr_pose_all) + list(_planar_all) + list(_numeric_all)
           + list(_backends_all) + list(_transpose_all))
