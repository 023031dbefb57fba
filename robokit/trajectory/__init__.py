"""robokit.trajectory — trajectories of Lecture 3 and seed 004 §5.

Modules: ``core`` (the ``Trajectory`` result type), ``polynomial`` (cubic, quintic,
cubics through via points), ``lspb`` (trapezoidal velocity, multi-segment LSPB of the
lecture), ``multisegment`` (``ms_trajectory``, Corke's ``mstraj``), ``timescaling``
(seed/Modern Robotics time scalings and point-to-point trajectories), ``cartesian``
(straight line with slerp orientation), ``through`` (through points via pseudo via points,
multi-segment Cartesian paths with blends), ``plot`` (one-call figures).
Every generator returns a :class:`Trajectory` with ``t`` (K,), ``q``/``qd``/``qdd`` (K, n),
except the seed functions ``joint_trajectory`` (N×n array) and ``screw_trajectory`` /
``cartesian_trajectory`` (list of 4×4), whose forms are fixed by the seed library.
"""
from robokit.trajectory.core import *  # noqa: F401,F403
from robokit.trajectory.core import __all__ as _core_all
from robokit.trajectory.polynomial import *  # noqa: F401,F403
from robokit.trajectory.polynomial import __all__ as _poly_all
from robokit.trajectory.lspb import *  # noqa: F401,F403
from robokit.trajectory.lspb import __all__ as _lspb_all
from robokit.trajectory.multisegment import *  # noqa: F401,F403
from robokit.trajectory.multisegment import __all__ as _ms_all
from robokit.trajectory.timescaling import *  # noqa: F401,F403
from robokit.trajectory.timescaling import __all__ as _ts_all
from robokit.trajectory.cartesian import *  # noqa: F401,F403
from robokit.trajectory.cartesian import __all__ as _cart_all
from robokit.trajectory.cartesian import cartesian_to_joint  # noqa: F401  (deprecated alias, not in __all__)
from robokit.trajectory.through import *  # noqa: F401,F403
from robokit.trajectory.through import __all__ as _through_all
from robokit.trajectory.plot import *  # noqa: F401,F403
from robokit.trajectory.plot import __all__ as _plot_all

__all__: list[str] = (
    list(_core_all) + list(_poly_all) + list(_lspb_all) + list(_ms_all) + list(_ts_all) + list(_cart_all) + list(_plot_all) + list(_through_all)
)
