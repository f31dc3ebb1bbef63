"""Calibration: a real robot's parameters θ from measured poses, what the data cannot identify, and
where to measure.

The robot is commanded rest lengths L0 (winch exit to platform, the ``physical`` mode of
``cdpr.models.equilibrium``) and settles at the equilibrium P*(θ, L0); a tracker measures the pose
y. The estimate is the maximum a posteriori (MAP) of θ under a Gaussian prior around the nominal
robot (``map_residual``): a weakly identified parameter stays near its prior instead of running away.
The Jacobian of the residual is exact, from the implicit-function sensitivities dP*/dθ
(``cdpr.models.sensitivity``), with the encoder offsets' column dP*/do = J^-1 dF/dL0
(``offset_sensitivities``); no finite differences inside the fit.

Models (``MODELS``): ``exact`` is the robot file as it is (pulley kinematics and Hooke elasticity);
``standard`` is the straight-line model, every pulley a fixed point (h = r_p = 0) and the cables
rigid, realised as the physical equilibrium with E multiplied by ``STANDARD_STIFFENING`` (the
stretch drops below a micrometre; the redundant robot still settles on its taut cables).

Winches: on a robot file with ``winch:`` (every cable) the data's lengths are the rest lengths the
controller was asked for; it turns each drum to the angle of the model that neglects the exit
point's motion (Métillon 2022 eq. 32), so the drum realises L0 = W(L_cmd) =
``drive.realised_rest_lengths`` (the length error δl of eq. 31). The exact model maps every
command through W before the equilibrium and its Jacobian carries the chain rule (dL0/dL_cmd on the
offsets, dL0/dd on the dead lengths); the standard model knows no drum (``without_winches``).

Encoder data (``L_enc1..L_encm`` = rest length + an unknown offset per cable): with elastic cables
and no measured tension every set of lengths has an equilibrium for every θ, so a sample without a
measured pose gives no equation in the exact model; such samples are counted and left out, and
with none left the fit refuses with one line naming the way out (measure poses, or ``--model
standard`` for a rigid self-calibration of a point mass, ``self_calibrate_standard``, whose gauge
it reports). Measured tensions (``t1_N..tm_N``, point mass and 6-DoF platform alike) add m rows
(t_meas - t(θ, L0)) / σ_t per sample, which make encoder-only samples equations: the tensions fix
the pose through the balance, Hooke's law then the rest lengths (``tension_sensitivities``).

Identifiability (``identifiability``): singular values of the measurement rows scaled by the
prior (rows / σ, columns × prior sd), the rank (> 1e-9 s_max), the condition number, the weakest
directions in words, and each parameter's posterior-to-prior sd ratio: identified (≤ 0.3), partly
(≤ 0.8) or prior-dominated (> 0.8).

The package, one module a concept (the names below are re-exported here, ``__all__``):

- ``data``: the samples (``Data``), reading and checking the CSV table (``read_data``) and the
  table back (``data_frame``); a spool robot's motor-angle samples (``MotorData``,
  ``read_motor_data``, ``is_motor_table``).
- ``model``: the robot the fit moves (``model_robot``, ``MODELS``), its drums
  (``realised_lengths``), its commands (``commanded_lengths``) and the equilibria of every robot (``equilibria``).
- ``problem``: the MAP residuals and their exact Jacobians (``Problem``,
  ``map_residual``, ``tension_sensitivities``).
- ``motor``: the motor-angle model of a spool robot (a Hangprinter: ``SpoolModel``), its MAP
  problem with every position a nuisance (``motor_problem``) and each position solved from its
  readings (``solve_positions``).
- ``estimator``: priors (``parse_priors``, ``prior_sd``, ``parse_motor_priors``), the MAP fit
  (``fit``), the rigid self-calibration (``self_calibrate_standard``) and the motor-angle fit
  (``fit_motor``).
- ``result``: the ``Calibration`` a fit returns (``MotorCalibration`` from motor angles) and the
  calibrated robot file's text (``robot_file_text``, both kinds).
- ``identify``: identifiability and its words (``identifiability``, ``direction_words``, ``below_one``).
- ``prediction``: a robot against measured samples (``check``, ``check_motor``).
- ``cv``: the K-fold cross-validation of a motor-angle calibration (``cross_validate``).
- ``synthetic``: simulated measurements (``simulate``, ``perturbed``, ``random_poses``,
  ``simulate_motor``).
- ``design``: the measurement plan (``plan``, ``d_optimal``).

This layer writes no file: ``cdpr.pipeline.calibration_files`` writes the data table and the
calibrated robot (atomically, ``cdpr.io``), the command line its reports.

References
----------
Paty, T., Binaud, N., Caro, S., Segonds, S. (2021). Cable-driven parallel robot modelling considering
pulley kinematics and cable elasticity. Mechanism and Machine Theory 159, 104263 (eq. 3-5, 10-14).
Tarantola, A. (2005). Inverse Problem Theory and Methods for Model Parameter Estimation, SIAM,
section 3.2 (least squares with a Gaussian prior, posterior covariance).
Atkinson, A. C., Donev, A. N. (1992). Optimum Experimental Designs, Oxford, ch. 11 (D-optimality)
and 15 (exchange algorithms).
"""

from cdpr.analyses.calibration.cv import (
    cross_validate,
    fold_of,
)
from cdpr.analyses.calibration.data import (
    ORIENTATION,
    POSE,
    SIGMA_DEFAULT,
    SIGMA_RAD_DEFAULT,
    SIGMA_T_DEFAULT,
    Data,
    MotorData,
    data_columns,
    data_frame,
    is_motor_table,
    read_data,
    read_motor_data,
)
from cdpr.analyses.calibration.design import (
    LOGDET_TIE,
    candidates,
    d_optimal,
    default_box,
    info_rows,
    plan,
    plan_sd,
)
from cdpr.analyses.calibration.estimator import (
    DEFAULT_PRIORS,
    OUTLIER,
    RELATIVE,
    SIGMA_L_DEFAULT,
    check_model_groups,
    ev0_positions,
    fit,
    fit_motor,
    parse_motor_priors,
    parse_priors,
    prior_sd,
    self_calibrate_standard,
    standard_lengths,
    usable,
)
from cdpr.analyses.calibration.identify import (
    IDENTIFIED,
    PARTLY,
    RANK_TOL,
    TIE_DIGITS,
    below_one,
    direction_words,
    identifiability,
    identifiability_without,
    sparse_basis,
)
from cdpr.analyses.calibration.model import (
    ALL_MODELS,
    COMMANDS,
    DRUM_RANGE,
    MODELS,
    STANDARD_STIFFENING,
    commanded_lengths,
    differentiable,
    equilibria,
    equilibrium_engine,
    executed_lengths,
    model_robot,
    realised_lengths,
    without_winches,
)
from cdpr.analyses.calibration.motor import (
    MOTOR_GROUPS,
    MOTOR_MODELS,
    SpoolModel,
)
from cdpr.analyses.calibration.prediction import (
    check,
    check_motor,
    predict_samples,
)
from cdpr.analyses.calibration.problem import (
    Problem,
    log_right_jacobian_inverse,
    map_residual,
    offset_sensitivities,
    orientation_residual,
    tension_sensitivities,
)
from cdpr.analyses.calibration.result import (
    Calibration,
    MotorCalibration,
    motor_robot_mapping,
    robot_file_text,
)
from cdpr.analyses.calibration.synthetic import (
    equilibrium_flags,
    perturbed,
    random_poses,
    simulate,
    simulate_motor,
)

__all__ = [
    "ALL_MODELS",
    "COMMANDS",
    "Calibration",
    "DEFAULT_PRIORS",
    "DRUM_RANGE",
    "Data",
    "IDENTIFIED",
    "LOGDET_TIE",
    "MODELS",
    "MOTOR_GROUPS",
    "MOTOR_MODELS",
    "MotorCalibration",
    "MotorData",
    "ORIENTATION",
    "OUTLIER",
    "PARTLY",
    "POSE",
    "Problem",
    "RANK_TOL",
    "RELATIVE",
    "SIGMA_DEFAULT",
    "SIGMA_L_DEFAULT",
    "SIGMA_RAD_DEFAULT",
    "SIGMA_T_DEFAULT",
    "STANDARD_STIFFENING",
    "SpoolModel",
    "TIE_DIGITS",
    "candidates",
    "check",
    "below_one",
    "check_model_groups",
    "check_motor",
    "commanded_lengths",
    "cross_validate",
    "d_optimal",
    "data_columns",
    "data_frame",
    "default_box",
    "differentiable",
    "direction_words",
    "equilibria",
    "equilibrium_engine",
    "equilibrium_flags",
    "ev0_positions",
    "executed_lengths",
    "fit",
    "fit_motor",
    "fold_of",
    "identifiability",
    "identifiability_without",
    "info_rows",
    "is_motor_table",
    "log_right_jacobian_inverse",
    "map_residual",
    "model_robot",
    "motor_robot_mapping",
    "offset_sensitivities",
    "orientation_residual",
    "parse_motor_priors",
    "parse_priors",
    "perturbed",
    "plan",
    "plan_sd",
    "predict_samples",
    "prior_sd",
    "random_poses",
    "read_data",
    "read_motor_data",
    "realised_lengths",
    "robot_file_text",
    "self_calibrate_standard",
    "simulate",
    "simulate_motor",
    "sparse_basis",
    "standard_lengths",
    "tension_sensitivities",
    "usable",
    "without_winches",
]
