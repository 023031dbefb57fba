"""robokit.dynamics — rigid-body dynamics (Lectures 7–8, seed 004 §4).

``newton_euler``: the seed functions in product-of-exponentials form (Newton–Euler inverse
dynamics, composite-rigid-body mass matrix, forward dynamics, trajectories).
``dh_newton_euler``: Craig's recursive Newton–Euler on a DH table (both conventions).
``terms``: Coriolis matrix (Ṁ − 2C skew), friction, payload, base wrench, Cartesian dynamics,
energy and Euler/Taylor/RK4 integration.
``inertia``: inertia tensors of a box, cylinder, sphere and rod, parallel axes, rotated axes.
``drives``: motor inertia and friction in the dynamics of a DH robot, reflected inertia,
dynamic manipulability.
"""
from robokit.dynamics.dh_newton_euler import *  # noqa: F401,F403
from robokit.dynamics.dh_newton_euler import __all__ as _dh_all
from robokit.dynamics.newton_euler import *  # noqa: F401,F403
from robokit.dynamics.newton_euler import __all__ as _ne_all
from robokit.dynamics.terms import *  # noqa: F401,F403
from robokit.dynamics.terms import __all__ as _terms_all
from robokit.dynamics.drives import *  # noqa: F401,F403
from robokit.dynamics.drives import __all__ as _drives_all
from robokit.dynamics.inertia import *  # noqa: F401,F403
from robokit.dynamics.inertia import __all__ as _inertia_all
from robokit.dynamics.twolink import *  # noqa: F401,F403
from robokit.dynamics.twolink import __all__ as _twolink_all

__all__ = list(_ne_all) + list(_dh_all) + list(_terms_all) + list(_twolink_all) + list(_inertia_all) + list(_drives_all)
