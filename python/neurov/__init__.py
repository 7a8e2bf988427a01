"""neurov: adaptive neural-network control for underwater vehicles.

The physics and control laws live in the compiled core (``neurov._core``, C++
with Eigen); this package re-exports it and adds files, scenarios and plots.
"""

from neurov import centres, trajectories
from neurov._core import (
    THETA_NAMES,
    LinearAdaptiveController,
    allocate_thrust,
    run_closed_loop,
    NNAdaptiveController,
    PDController,
    PIDController,
    RbfNetwork,
    ReferenceModel,
    SlidingModeController,
    Status,
    Vehicle,
    __version__,
    is_near_singularity,
    jacobian,
    jacobian_dot,
    jacobian_inverse,
    regressor,
    regressor_parameters,
    rk4_step,
    rotation,
    singularity_threshold,
    tracking_error,
)
from neurov.scenario import (
    CommandSpec,
    ControllerSpec,
    CurrentStep,
    Disturbance,
    Scenario,
    ScenarioError,
    SensorFault,
    ThrusterFailure,
    load_scenario,
)
from neurov.kernels import check_kernel_request as _check_kernel_request
from neurov.simulation import Result, simulate, simulate_many
from neurov.vehicle_file import VehicleFileError

__all__ = [
    "THETA_NAMES",
    "CommandSpec",
    "ControllerSpec",
    "CurrentStep",
    "Disturbance",
    "Result",
    "Scenario",
    "ScenarioError",
    "SensorFault",
    "ThrusterFailure",
    "allocate_thrust",
    "load_scenario",
    "run_closed_loop",
    "simulate",
    "simulate_many",
    "trajectories",
    "LinearAdaptiveController",
    "NNAdaptiveController",
    "PDController",
    "PIDController",
    "RbfNetwork",
    "ReferenceModel",
    "SlidingModeController",
    "Status",
    "Vehicle",
    "VehicleFileError",
    "__version__",
    "centres",
    "is_near_singularity",
    "jacobian",
    "jacobian_dot",
    "jacobian_inverse",
    "regressor",
    "regressor_parameters",
    "rk4_step",
    "rotation",
    "singularity_threshold",
    "tracking_error",
]

_check_kernel_request()
