"""robokit.kinematics — forward kinematics, Jacobians and velocity kinematics (Lectures 4, 6, 7; seed §3).

``poe``: the seed functions ``fkin_body``, ``fkin_space``, ``jacobian_body``, ``jacobian_space``
(also batched). ``dh``: the Jacobian of a DH table by outward velocity propagation and joint
torques by inward static-force propagation; ``dh_trace``: every step of the outward velocity
iteration (``dh_velocity_trace``). ``velocity``: numerical and analytical Jacobians,
twist/wrench transforms, manipulability and singularities, resolved-rate control.
"""
from robokit.kinematics.dh import *  # noqa: F401,F403
from robokit.kinematics.dh import __all__ as _dh_all
from robokit.kinematics.dh_trace import DHVelocityTrace, dh_velocity_trace
from robokit.kinematics.poe import *  # noqa: F401,F403
from robokit.kinematics.poe import __all__ as _poe_all
from robokit.kinematics.velocity import *  # noqa: F401,F403
from robokit.kinematics.velocity import __all__ as _vel_all
from robokit.kinematics.velocity import jacobian_to_frame  # noqa: F401  (deprecated alias, not in __all__)

__all__ = list(_poe_all) + list(_dh_all) + list(_vel_all) + ["DHVelocityTrace", "dh_velocity_trace"]
