"""neurov: adaptive neural-network control for underwater vehicles.

The physics and control laws live in the compiled core (``neurov._core``, C++
with Eigen); this package re-exports it and adds files, scenarios and plots.
"""

from neurov._core import (
    Status,
    Vehicle,
    __version__,
    is_near_singularity,
    jacobian,
    jacobian_dot,
    jacobian_inverse,
    rk4_step,
    rotation,
    singularity_threshold,
)
from neurov.vehicle_file import VehicleFileError

__all__ = [
    "Status",
    "Vehicle",
    "VehicleFileError",
    "__version__",
    "is_near_singularity",
    "jacobian",
    "jacobian_dot",
    "jacobian_inverse",
    "rk4_step",
    "rotation",
    "singularity_threshold",
]
