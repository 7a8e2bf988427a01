"""The fit on data the estimate never saw: a free run of the vehicle from
the held-out log's first state of each segment, driven by the log's
recorded force held over each interval (the simulator's plant step, every
segment in one ``neurov._core.rk4_segments`` call), against the measured body velocities.

Only the velocities are compared: the position and heading of a free run
drift without a controller however good the model (they integrate the
velocity error), while the velocities' dynamics are damped."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from neurov.identification.log import Log
from neurov.identification.output_error import Segment, simulate_segments

__all__ = ["HeldOut", "free_run", "held_out", "nrmse_fit"]

Array = NDArray[np.float64]


def free_run(vehicle: Any, log: Log, substeps: int = 1) -> Array:
    """The body velocities (N, 6) of a free run over each segment of `log`."""
    segs = [Segment(log, a, b - 1 - a) for a, b in log.segments]
    starts = np.array([log.nu[a] for a, _ in log.segments])
    out = np.full_like(log.nu, np.nan)
    out[np.concatenate([np.arange(a, b) for a, b in log.segments])] = simulate_segments(vehicle, segs, starts,
                                                                                     substeps)
    return out


def nrmse_fit(measured: Array, simulated: Array) -> Array:
    """Fit % per DOF, 100 (1 - ||y - y_sim|| / ||y - mean(y)||) (1 is a
    perfect fit; negative: worse than the mean); NaN for a DOF that did not move."""
    ok = np.all(np.isfinite(simulated), axis=1)
    y, s = measured[ok], simulated[ok]
    spread = np.linalg.norm(y - y.mean(axis=0), axis=0)
    err = np.linalg.norm(y - s, axis=0)
    with np.errstate(invalid="ignore", divide="ignore"):
        return np.where(spread > 1e-12, 100.0 * (1.0 - err / np.where(spread > 0, spread, 1.0)), np.nan)


@dataclass(frozen=True)
class HeldOut:
    """A held-out log's measured velocities and the free runs on it."""

    source: str
    t: Array
    measured: Array
    fitted_run: Array
    template_run: Array

    @property
    def fit(self) -> Array:
        """The fitted vehicle's fit % per DOF."""
        return nrmse_fit(self.measured, self.fitted_run)

    @property
    def template_fit(self) -> Array:
        return nrmse_fit(self.measured, self.template_run)


def held_out(log: Log, fitted: Any, template: Any, substeps: int = 1) -> HeldOut:
    return HeldOut(log.source, log.t, log.nu, free_run(fitted, log, substeps),
                   free_run(template, log, substeps))
