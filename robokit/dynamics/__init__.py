"""robokit.dynamics — rigid-body dynamics (Lectures 7–8, seed 004 §4).

``newton_euler``: the seed functions in product-of-exponentials form (Newton–Euler inverse
dynamics, composite-rigid-body mass matrix, forward dynamics, trajectories).
``dh_newton_euler``: Craig's recursive Newton–Euler on a DH table (both conventions);
``dh_trace``: the same iterations with every intermediate kept (``trace=True``).
``coriolis``: the Coriolis matrix (Christoffel, Ṁ − 2C skew; or the lecture's factorisation).
``loads``: payloads and the base wrench. ``cartesian``: operational-space dynamics.
``integration``: energy and Euler/Taylor/RK4 integration (one stepper for robokit).
``inertia``: inertia tensors of a box, cylinder, sphere and rod, parallel axes, rotated axes.
``drives``: the drive train — the one friction law, motor inertia and friction in the dynamics
of a DH robot, reflected inertia, dynamic manipulability.
``twolink``: Lecture 7's two-link closed form.
"""
from robokit.dynamics.cartesian import *  # noqa: F401,F403
from robokit.dynamics.cartesian import __all__ as _cartesian_all
from robokit.dynamics.coriolis import *  # noqa: F401,F403
from robokit.dynamics.coriolis import __all__ as _coriolis_all
from robokit.dynamics.dh_newton_euler import *  # noqa: F401,F403
from robokit.dynamics.dh_newton_euler import __all__ as _dh_all
from robokit.dynamics.dh_trace import *  # noqa: F401,F403
from robokit.dynamics.dh_trace import __all__ as _dh_trace_all
from robokit.dynamics.drives import *  # noqa: F401,F403
from robokit.dynamics.drives import __all__ as _drives_all
from robokit.dynamics.inertia import *  # noqa: F401,F403
from robokit.dynamics.inertia import __all__ as _inertia_all
from robokit.dynamics.integration import *  # noqa: F401,F403
from robokit.dynamics.integration import __all__ as _integration_all
from robokit.dynamics.loads import *  # noqa: F401,F403
from robokit.dynamics.loads import __all__ as _loads_all
from robokit.dynamics.newton_euler import *  # noqa: F401,F403
from robokit.dynamics.newton_euler import __all__ as _ne_all
from robokit.dynamics.twolink import *  # noqa: F401,F403
from robokit.dynamics.twolink import __all__ as _twolink_all

__all__ = (list(_ne_all) + list(_dh_all) + list(_dh_trace_all) + list(_coriolis_all) + list(_loads_all) + list(_cartesian_all)
           + list(_integration_all) + list(_twolink_all) + list(_inertia_all) + list(_drives_all))
