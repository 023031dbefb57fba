"""robokit.control — joint controllers of Lecture 8, a Pinocchio-based simulator, the seed
library's ``computed_torque``/``simulate_control``, and tracking plots; the DC motor and gearbox model
(``motor``), gain design and step-response measures (``design``), and independent joint control
simulated through the motor model (``independent``), resolved-rate tracking of a straight line
(``line``)."""
from robokit.control.controllers import *  # noqa: F401,F403
from robokit.control.controllers import __all__ as _ctrl_all
from robokit.control.design import *  # noqa: F401,F403
from robokit.control.design import __all__ as _design_all
from robokit.control.independent import *  # noqa: F401,F403
from robokit.control.independent import __all__ as _indep_all
from robokit.control.line import *  # noqa: F401,F403
from robokit.control.line import __all__ as _line_all
from robokit.control.motor import *  # noqa: F401,F403
from robokit.control.motor import __all__ as _motor_all
from robokit.control.motor import reflect_to_joint  # noqa: F401  (deprecated alias, not in __all__)
from robokit.control.plot import *  # noqa: F401,F403
from robokit.control.plot import __all__ as _plot_all
from robokit.control.seed import *  # noqa: F401,F403
from robokit.control.seed import __all__ as _seed_all
from robokit.control.simulate import *  # noqa: F401,F403
from robokit.control.simulate import __all__ as _sim_all

__all__ = list(_ctrl_all) + list(_sim_all) + list(_seed_all) + list(_plot_all) + list(_motor_all) + list(_design_all) + list(_indep_all) + list(_line_all)
