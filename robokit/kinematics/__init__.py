"""robokit.kinematics — forward kinematics and Jacobians (Lectures 4, 6, 7; seed 004 §3).

``poe``: the seed functions ``fkin_body``, ``fkin_space``, ``jacobian_body``, ``jacobian_space``
(also batched over a leading dimension of configurations).
"""
from robokit.kinematics.poe import *  # noqa: F401,F403
from robokit.kinematics.poe import __all__ as _poe_all

__all__ = list(_poe_all)
