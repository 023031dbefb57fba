"""robokit.calibration — fitting the course's models to a real arm.

Modules: ``chain`` (a serial chain as joint placements and screws; the calibrated URDF),
``kinematic`` (``calibrate``: geometric calibration from measured tool poses or positions),
``regressor`` (Newton–Euler linear in the inertial parameters, friction, base parameters),
``identification`` (``identify_dynamics``, physical consistency, derivatives of measured
positions), ``excitation`` (``excitation_trajectory``: optimised finite Fourier series),
``data`` (the calibration CSV file of ``robokit calibrate``).
"""
from robokit.calibration.chain import JointChain, chain_from_robot, chain_urdf, robot_from_chain
from robokit.calibration.data import read_calibration_csv, write_calibration_csv
from robokit.calibration.excitation import excitation_trajectory, fourier_series
from robokit.calibration.identification import (
    IdentificationResult,
    check_physical_consistency,
    identify_dynamics,
    joint_derivatives,
    pseudo_inertia,
)
from robokit.calibration.kinematic import (
    RMS,
    CalibrationResult,
    Identifiability,
    calibrate,
    identification_jacobian,
    parameter_names,
    pose_residuals,
)
from robokit.calibration.regressor import (
    BaseParameters,
    base_parameters,
    friction_regressor,
    full_regressor,
    inertial_regressor,
    standard_parameter_names,
    standard_parameters,
)

__all__ = ["JointChain", "chain_from_robot", "chain_urdf", "robot_from_chain", "calibrate", "CalibrationResult",
           "Identifiability", "RMS", "identification_jacobian", "parameter_names", "pose_residuals",
           "identify_dynamics", "IdentificationResult", "check_physical_consistency", "joint_derivatives",
           "pseudo_inertia", "excitation_trajectory", "fourier_series", "BaseParameters", "base_parameters",
           "friction_regressor", "full_regressor", "inertial_regressor", "standard_parameter_names",
           "standard_parameters", "read_calibration_csv", "write_calibration_csv"]
