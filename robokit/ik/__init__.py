"""robokit.ik — inverse kinematics: closed-form solvers with every solution (``analytic``)."""
from robokit.ik.analytic import *  # noqa: F401,F403
from robokit.ik.analytic import __all__ as _analytic_all

__all__ = list(_analytic_all)
