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

Nothing is imported until it is used (PEP 562: the module's ``__getattr__``): ``import robokit``
loads neither numba nor Pinocchio nor a subpackage, and ``robokit.load`` (or ``from robokit import
load``) imports ``robokit.description`` on first access. Every name of ``__all__`` works either way,
``dir(robokit)`` lists them, and type checkers see the imports of the ``TYPE_CHECKING`` block.
"""
from __future__ import annotations

import importlib
from typing import TYPE_CHECKING, Any

#: The subpackages reached as ``robokit.NAME`` (imported on first access).
_SUBPACKAGES = ("spatial", "description", "kinematics", "dynamics", "ik", "trajectory", "control", "mobile",
                "workspace", "calibration", "collision", "motion", "viz", "validation", "symbolic", "codegen",
                "kernels")

#: Each top-level name that is not a subpackage -> the module that defines it.
_HOME: dict[str, str] = {}
for _module, _names in {
    "robokit.calibration": ("CalibrationResult", "IdentificationResult", "calibrate", "excitation_trajectory",
                            "identify_dynamics"),
    "robokit.control": ("SimResult", "computed_torque", "simulate", "simulate_control"),
    "robokit.description": ("DHLink", "DHTable", "PoEParams", "Robot", "RobotLike", "RobotSpec", "dh_from_urdf",
                            "load", "urdf_to_dh"),
    "robokit.dynamics": ("end_effector_forces", "euler_step", "forward_dynamics", "forward_dynamics_trajectory",
                         "gravity_forces", "inverse_dynamics", "inverse_dynamics_trajectory", "mass_matrix",
                         "vel_quadratic_forces"),
    "robokit.errors": ("DegreesWarning", "DivergenceError", "InputError", "PhysicalityWarning", "RobokitError",
                       "RobokitWarning"),
    "robokit.description.loading": ("models",),
    "robokit.frames": ("Frame",),
    "robokit.ik": ("IKResult", "IKSolution", "ik_analytic", "ik_analytic_kind", "ikin_body", "ikin_space",
                   "solve_ik"),
    "robokit.kinematics": ("fkin_body", "fkin_space", "jacobian_body", "jacobian_space"),
    "robokit.spatial": ("Rp_to_trans", "ad", "adjoint", "axis_ang_3", "axis_ang_6", "distance_to_SE3",
                        "distance_to_SO3", "euler_to_matrix", "matrix_exp_3", "matrix_exp_6", "matrix_log_3",
                        "matrix_log_6", "matrix_to_euler", "near_zero", "normalize", "project_to_SE3",
                        "project_to_SO3", "rot_inv", "se3_to_vec", "so3_to_vec", "test_if_SE3", "test_if_SO3",
                        "trans_inv", "trans_to_Rp", "vec_to_se3", "vec_to_so3", "deg2rad", "rad2deg"),
    "robokit.trajectory": ("Trajectory", "cartesian_trajectory", "cubic_time_scaling", "joint_trajectory",
                           "ms_trajectory", "quintic_time_scaling", "screw_trajectory"),
    "robokit.workspace": ("CapabilityMap", "capability_map"),
    "robokit.motion": ("plan", "retime"),
}.items():
    _HOME.update(dict.fromkeys(_names, _module))
del _module, _names


if TYPE_CHECKING:  # what the names above are, for type checkers, IDEs and the docs
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
    from robokit.description.loading import models
    from robokit.frames import Frame
    from robokit.errors import DegreesWarning, DivergenceError, InputError, PhysicalityWarning, RobokitError, RobokitWarning
    from robokit.ik import IKResult, IKSolution, ik_analytic, ik_analytic_kind, ikin_body, ikin_space, solve_ik
    from robokit.kinematics import fkin_body, fkin_space, jacobian_body, jacobian_space
    from robokit.spatial import (
        Rp_to_trans,
        ad,
        adjoint,
        axis_ang_3,
        axis_ang_6,
        deg2rad,
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
        rad2deg,
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
    "load", "models", "solve_ik", "ik_analytic", "ik_analytic_kind", "capability_map", "simulate", "dh_from_urdf",
    "calibrate", "identify_dynamics", "excitation_trajectory", "plan", "retime",
    # main types
    "Robot", "RobotLike", "RobotSpec", "DHTable", "DHLink", "PoEParams", "Trajectory", "IKSolution", "IKResult",
    "SimResult", "CapabilityMap", "CalibrationResult", "IdentificationResult", "Frame",
    # errors and warnings
    "RobokitError", "InputError", "DivergenceError", "RobokitWarning", "PhysicalityWarning", "DegreesWarning",
    # units
    "deg2rad", "rad2deg",
    # the subpackages
    "spatial", "description", "kinematics", "dynamics", "ik", "trajectory", "control", "mobile", "workspace",
    "calibration", "collision", "motion",
]


def __getattr__(name: str) -> Any:
    """Import a top-level name's module on first access (PEP 562) and keep the name here."""
    if name in _SUBPACKAGES:
        value: Any = importlib.import_module(f"robokit.{name}")
    elif name in _HOME:
        value = getattr(importlib.import_module(_HOME[name]), name)
    elif name == "__version__":
        from importlib.metadata import PackageNotFoundError, version

        try:
            value = version("robokit")
        except PackageNotFoundError:  # pragma: no cover - a source tree that was never installed
            value = "0+unknown"
    else:
        raise AttributeError(f"module 'robokit' has no attribute {name!r}")
    globals()[name] = value
    return value


def __dir__() -> list[str]:
    # not robokit.symbolic: importing it needs sympy (the symbolic extra), and tools that getattr
    # every name dir() lists (inspect.getmembers, completion) must not fail without it
    return sorted(set(globals()) | set(__all__) | set(_SUBPACKAGES) - {"symbolic"} | {"__version__"})
