"""robokit.workspace — capability (reachability) maps: the dexterous workspace at scale.

Modules: ``sampling`` (the reachable workspace by sampling forward kinematics:
``sample_workspace``, ``plot_workspace``), ``orientations`` (uniform orientation sets on SO(3) and in the plane), ``grid``
(voxel lattice and the forward-kinematics pre-pass), ``reach`` (is a pose reachable? the IK
back end per robot), ``capability`` (the map, chunked on Dask, resumable), ``plot``
(matplotlib slices and the meshcat view of a map).
"""
from robokit.workspace.capability import *  # noqa: F401,F403
from robokit.workspace.capability import __all__ as _capability_all
from robokit.workspace.orientations import *  # noqa: F401,F403
from robokit.workspace.orientations import __all__ as _orientations_all
from robokit.workspace.reach import *  # noqa: F401,F403
from robokit.workspace.reach import __all__ as _reach_all
from robokit.workspace.plot import *  # noqa: F401,F403
from robokit.workspace.plot import __all__ as _plot_all
from robokit.workspace.sampling import *  # noqa: F401,F403
from robokit.workspace.sampling import __all__ as _sampling_all

__all__ = list(_capability_all) + list(_orientations_all) + list(_reach_all) + list(_plot_all) + list(_sampling_all)
