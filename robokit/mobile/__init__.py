"""robokit.mobile — mobile robots of Lecture 9: the kinematic bicycle model and its controllers,
odometry (turn-then-move or move-then-turn), landmarks and a range–bearing sensor, EKF localisation
and EKF SLAM, error ellipses; Monte Carlo localisation (particle filter) and scalar uncertainty
(``particle``); the unicycle and differential drive (``unicycle``)."""
from robokit.mobile.estimation import *  # noqa: F401,F403
from robokit.mobile.estimation import __all__ as _est_all
from robokit.mobile.particle import *  # noqa: F401,F403
from robokit.mobile.particle import __all__ as _particle_all
from robokit.mobile.plot import *  # noqa: F401,F403
from robokit.mobile.plot import __all__ as _plot_all
from robokit.mobile.vehicle import *  # noqa: F401,F403
from robokit.mobile.unicycle import *  # noqa: F401,F403
from robokit.mobile.unicycle import __all__ as _uni_all
from robokit.mobile.vehicle import __all__ as _veh_all

__all__ = list(_veh_all) + list(_est_all) + list(_plot_all) + list(_particle_all) + list(_uni_all)
