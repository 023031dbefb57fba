"""robokit.dynamics — rigid-body dynamics (Lectures 7–8, seed 004 §4).

``newton_euler``: the seed functions in product-of-exponentials form (Newton–Euler inverse
dynamics, composite-rigid-body mass matrix, forward dynamics, trajectories).
"""
from robokit.dynamics.newton_euler import *  # noqa: F401,F403
from robokit.dynamics.newton_euler import __all__ as _ne_all

__all__ = list(_ne_all)
