"""neurov: adaptive neural-network control for underwater vehicles.

The physics and control laws live in the compiled core (``neurov._core``, C++
with Eigen); this package re-exports it and adds files, scenarios and plots.
"""

from neurov import centres
from neurov._core import (
    THETA_NAMES,
    LinearAdaptiveController,
    NNAdaptiveController,
    PDController,
    RbfNetwork,
    ReferenceModel,
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
from neurov.vehicle_file import VehicleFileError

__all__ = [
    "THETA_NAMES",
    "LinearAdaptiveController",
    "NNAdaptiveController",
    "PDController",
    "RbfNetwork",
    "ReferenceModel",
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
