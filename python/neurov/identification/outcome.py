"""What :func:`neurov.identification.fit.identify` returns: the fitted
parameters, their intervals, the reasons a parameter was left at the
template's value, the held-out fits and the warnings. Its own module, so that
the fit and the report (which prints it) both import it and neither the other."""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from neurov import _core
from neurov.config.vehicle_file import VehicleFile
from neurov.identification.heldout import HeldOut
from neurov.identification.log import Log
from neurov.identification.parameters import vehicle_parameters
from neurov.identification.survey import LogReport

__all__ = ["Identification"]

Array = NDArray[np.float64]


@dataclass
class Identification:
    """What :func:`~neurov.identification.fit.identify` found. theta is the full (24,) vector (the
    template's values where not fitted); interval is (24, 2) (NaN where not
    fitted); reasons says why a free parameter was left at the template's value."""

    template: VehicleFile
    logs: list[Log]
    theta_template: Array
    theta: Array
    theta_stage1: Array
    fitted: list[int]
    reasons: dict[int, str]
    interval: Array
    condition: float
    stages: str
    heldout: list[HeldOut] = field(default_factory=list)
    warnings: list[str] = field(default_factory=list)
    out: Path | None = None
    log_report: LogReport | None = None

    def parameters(self) -> dict[str, Any]:
        """The fitted vehicle's :class:`neurov.Vehicle` keyword arguments."""
        p = vehicle_parameters(self.template.parameters, self.theta)
        if self.template.displaced_volume is not None and 22 not in self.fitted:
            # W - B was not fitted: keep the template's volume, so that the
            # vehicle floats in each scenario's water as the template does.
            p.pop("buoyancy")
            p["displaced_volume"] = self.template.displaced_volume
        return p

    def vehicle(self) -> Any:
        return _core.Vehicle(**vehicle_parameters(self.template.parameters, self.theta))
