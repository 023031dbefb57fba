"""robokit: a robotics course's derivations for serial manipulators, checked against Pinocchio.

Conventions, said once: SI units; arrays are float64 ``numpy.ndarray``; twists and
wrenches are ordered angular first, ``(ω, v)`` and ``(m, f)``; quaternions are scalar
first, ``(w, x, y, z)``.

The top level holds the seed function library (``near_zero`` … ``simulate_control``, the
names of the course's function documentation), the main types and the entry points
(``load``, ``solve_ik``, ``ik_analytic``, ``capability_map``, ``calibrate``,
``identify_dynamics``, ``excitation_trajectory``). Everything else is reached
through its subpackage, one per course area: ``robokit.spatial``, ``robokit.description``,
``robokit.kinematics``, ``robokit.dynamics``, ``robokit.ik``, ``robokit.trajectory``,
``robokit.control``, ``robokit.mobile``, ``robokit.workspace``, ``robokit.viz``,
``robokit.validation``, ``robokit.calibration`` and ``robokit.symbolic`` (e.g. ``robokit.kinematics.dh_jacobian``).
"""
from robokit import calibration, control, description, dynamics, ik, kinematics, mobile, spatial, trajectory, workspace
from robokit.calibration import (
    CalibrationResult,
    IdentificationResult,
    calibrate,
    excitation_trajectory,
    identify_dynamics,
)
from robokit.control import SimResult, computed_torque, simulate, simulate_control
from robokit.description import DHLink, DHTable, PoEParams, Robot, RobotLike, RobotSpec, dh_from_urdf, load, urdf_to_dh
from robokit.dynamics import (
    end_effector_forces,
    euler_step,
    forward_dynamics,
    forward_dynamics_trajectory,
    gravity_forces,
    inverse_dynamics,
    inverse_dynamics_trajectory,
    mass_matrix,
    vel_quadratic_forces,
)
from robokit.errors import DivergenceError, InputError, RobokitError, RobokitWarning
from robokit.frames import Frame
from robokit.ik import IKResult, IKSolution, ik_analytic, ik_analytic_kind, ikin_body, ikin_space, solve_ik
from robokit.kinematics import fkin_body, fkin_space, jacobian_body, jacobian_space
from robokit.spatial import (
    Rp_to_trans,
    ad,
    adjoint,
    axis_ang_3,
    axis_ang_6,
    distance_to_SE3,
    distance_to_SO3,
    euler_to_matrix,
    matrix_exp_3,
    matrix_exp_6,
    matrix_log_3,
    matrix_log_6,
    matrix_to_euler,
    near_zero,
    normalize,
    project_to_SE3,
    project_to_SO3,
    rot_inv,
    se3_to_vec,
    so3_to_vec,
    test_if_SE3,
    test_if_SO3,
    trans_inv,
    trans_to_Rp,
    vec_to_se3,
    vec_to_so3,
)
from robokit.trajectory import (
    Trajectory,
    cartesian_trajectory,
    cubic_time_scaling,
    joint_trajectory,
    ms_trajectory,
    quintic_time_scaling,
    screw_trajectory,
)
from robokit.workspace import CapabilityMap, capability_map
from robokit import collision, motion
from robokit.motion import plan, retime

try:
    from importlib.metadata import PackageNotFoundError as _NotFound, version as _version

    __version__ = _version("robokit")
except _NotFound:  # pragma: no cover - running from a source tree that was never installed
    __version__ = "0+unknown"

#: The seed function library (the course's function documentation), in its order.
SEED_FUNCTIONS = (
    "near_zero", "normalize", "rot_inv", "trans_inv", "project_to_SO3", "project_to_SE3",
    "distance_to_SO3", "distance_to_SE3", "test_if_SO3", "test_if_SE3", "euler_to_matrix",
    "matrix_to_euler", "vec_to_so3", "so3_to_vec", "vec_to_se3", "se3_to_vec", "axis_ang_3",
    "axis_ang_6", "matrix_exp_3", "matrix_log_3", "matrix_exp_6", "matrix_log_6", "Rp_to_trans",
    "trans_to_Rp", "adjoint", "ad", "fkin_body", "fkin_space", "jacobian_body", "jacobian_space",
    "ikin_body", "ikin_space", "inverse_dynamics", "mass_matrix", "vel_quadratic_forces",
    "gravity_forces", "end_effector_forces", "forward_dynamics", "euler_step",
    "inverse_dynamics_trajectory", "forward_dynamics_trajectory", "cubic_time_scaling",
    "quintic_time_scaling", "joint_trajectory", "screw_trajectory", "cartesian_trajectory",
    "ms_trajectory", "computed_torque", "simulate_control",
)

__all__ = list(SEED_FUNCTIONS) + [
    # entry points
    "load", "solve_ik", "ik_analytic", "ik_analytic_kind", "capability_map", "simulate", "dh_from_urdf",
    "calibrate", "identify_dynamics", "excitation_trajectory", "plan", "retime",
    # main types
    "Robot", "RobotLike", "RobotSpec", "DHTable", "DHLink", "PoEParams", "Trajectory", "IKSolution", "IKResult",
    "SimResult", "CapabilityMap", "CalibrationResult", "IdentificationResult", "Frame",
    # errors and warnings
    "RobokitError", "InputError", "DivergenceError", "RobokitWarning",
    # the subpackages
    "spatial", "description", "kinematics", "dynamics", "ik", "trajectory", "control", "mobile", "workspace",
    "calibration", "collision", "motion",
]
