"""neurov: adaptive neural-network control for underwater vehicles.

The physics and control laws live in the compiled core (``neurov._core``, C++
with Eigen); this package re-exports it and adds files, scenarios and plots.
"""

from typing import TYPE_CHECKING

from neurov import centres, errors, trajectories
from neurov._core import (
    MAX_CENTRES,
    MAX_SUBSTEPS,
    MAX_WAVE_COMPONENTS,
    THETA_NAMES,
    ComputedTorqueConfig,
    ComputedTorqueController,
    LinearAdaptiveConfig,
    LinearAdaptiveController,
    allocate_thrust,
    run_closed_loop,
    NNAdaptiveConfig,
    NNAdaptiveController,
    PDConfig,
    PDController,
    PIDConfig,
    PIDController,
    RbfNetwork,
    ReferenceModel,
    RefusedStepPolicy,
    RobustModification,
    Saturation,
    SensorFaultKind,
    SimulationConfig,
    SlidingModeConfig,
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
from neurov.controller import Controller
from neurov.simulator import Observation, Simulator
from neurov.errors import NeurovError, RefusedStepsWarning, ValidationError, VehicleFileError
from neurov import weights  # noqa: F401  (attaches NNAdaptiveController.save/load)
from neurov.identification import identify
from neurov.load import load_result

__all__ = [
    "MAX_CENTRES",
    "MAX_SUBSTEPS",
    "MAX_WAVE_COMPONENTS",
    "THETA_NAMES",
    "CommandSpec",
    "Controller",
    "ControllerSpec",
    "CurrentStep",
    "Disturbance",
    "Observation",
    "Result",
    "Scenario",
    "ScenarioError",
    "SensorFault",
    "Simulator",
    "ThrusterFailure",
    "allocate_thrust",
    "load_result",
    "load_scenario",
    "run_closed_loop",
    "simulate",
    "simulate_many",
    "trajectories",
    "ComputedTorqueConfig",
    "ComputedTorqueController",
    "LinearAdaptiveConfig",
    "LinearAdaptiveController",
    "NNAdaptiveConfig",
    "NNAdaptiveController",
    "PDConfig",
    "PDController",
    "PIDConfig",
    "PIDController",
    "RbfNetwork",
    "RefusedStepPolicy",
    "RefusedStepsWarning",
    "Saturation",
    "SensorFaultKind",
    "SimulationConfig",
    "ReferenceModel",
    "RobustModification",
    "SlidingModeConfig",
    "SlidingModeController",
    "Status",
    "NeurovError",
    "ValidationError",
    "Vehicle",
    "VehicleFileError",
    "__version__",
    "centres",
    "errors",
    "identify",
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
    "tune",
]

_check_kernel_request()

if TYPE_CHECKING:
    import os
    from typing import Any

    from neurov.tuning import Tuning, TuneOutcome


def tune(tuning: "str | os.PathLike[str] | Tuning", out_dir: "str | os.PathLike[str]",
         **options: "Any") -> "TuneOutcome":
    """Tunes the controllers of a tuning file: :func:`neurov.tuning.tune`
    (imported here on first use: Optuna is an optional dependency, and
    ``import neurov`` stays cheap)."""
    from neurov.tuning import tune as _tune

    return _tune(tuning, out_dir, **options)
