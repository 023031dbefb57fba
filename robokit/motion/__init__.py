"""robokit.motion — limit-respecting, collision-free motion.

Modules: ``retime`` (time-optimal path parameterisation with TOPP-RA under velocity,
acceleration and torque limits), ``plan`` (joint-space RRT-Connect through OMPL, shortcut,
then retimed).
"""
from robokit.motion.plan import DEFAULT_RESOLUTION, goal_configurations, plan
from robokit.motion.retime import path_spline, retime

__all__ = ["retime", "path_spline", "plan", "goal_configurations", "DEFAULT_RESOLUTION"]
