"""neurov: adaptive neural-network control for underwater vehicles.

The physics and control laws live in the compiled core (``neurov._core``, C++
with Eigen); this package re-exports it and adds files, scenarios and plots.
"""

from typing import TYPE_CHECKING

from neurov import errors
from neurov.config import trajectories
from neurov.laws import centres
from neurov._core import (
    BUILT_IN_CONTROLLERS as _BUILT_IN_CONTROLLERS,
    MAX_CENTRES,
    MAX_SUBSTEPS,
    MAX_WAVE_COMPONENTS,
    THETA_NAMES,
    allocate_thrust,
    run_closed_loop,
    RbfNetwork,
    ReferenceModel,
    RefusedStepPolicy,
    RobustModification,
    Saturation,
    SensorFaultKind,
    SimulationConfig,
    Status,
    Vehicle,
    VehicleParameters,
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
from neurov.config.scenario import (
    CommandSpec,
    ControllerSpec,
    CurrentStep,
    Disturbance,
    Scenario,
    ScenarioError,
    SensorFault,
    ThrusterFailure,
)
from neurov.kernels import check_kernel_request as _check_kernel_request
from neurov.laws.protocol import Controller
from neurov.running.stepper import Observation, Simulator
from neurov.errors import NeurovError, RefusedStepsWarning, ValidationError, VehicleFileError
from neurov.laws import weights  # noqa: F401  (attaches NNAdaptiveController.save/load)
from neurov import bridges  # noqa: F401  (lends the bridges to the layers beneath them: neurov.hooks)
from neurov.identification import identify
from neurov.results.load import load_result
from neurov.config.reading import load_scenario
from neurov.results.timeseries import Result
from neurov.running.many import simulate_many
from neurov.running.simulation import simulate

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
    "RbfNetwork",
    "RefusedStepPolicy",
    "RefusedStepsWarning",
    "Saturation",
    "SensorFaultKind",
    "SimulationConfig",
    "ReferenceModel",
    "RobustModification",
    "Status",
    "NeurovError",
    "ValidationError",
    "Vehicle",
    "VehicleFileError",
    "VehicleParameters",
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

# The controller classes and their configurations, from the C++ list of
# built-in controllers (neurov._core.BUILT_IN_CONTROLLERS).
_CONTROLLER_CLASSES = {c.__name__: c for cls in _BUILT_IN_CONTROLLERS.values() for c in (cls, cls.Config)}
globals().update(_CONTROLLER_CLASSES)
__all__ += list(_CONTROLLER_CLASSES)

_check_kernel_request()

if TYPE_CHECKING:
    # Type checkers do not run the loop above: they read the controller
    # classes from the stub of the compiled module.
    from neurov._core_controllers import *  # noqa: F403
    import os
    from typing import Any

    from neurov.tuning import Tuning, TuneOutcome


def tune(tuning: "str | os.PathLike[str] | Tuning", out_dir: "str | os.PathLike[str]",
         **options: "Any") -> "TuneOutcome":
    """Tunes the controllers of a tuning file: :func:`neurov.tuning.tune`
    (imported here on first use: Optuna is an optional dependency, and
    ``import neurov`` stays cheap)."""
    # Deferred: neurov.tuning needs Optuna and pandas.
    from neurov.tuning import tune as _tune

    return _tune(tuning, out_dir, **options)
