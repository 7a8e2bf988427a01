"""The estimator between the vehicle and its log, modelled in stage 2.

An EKF that fuses a DVL at a few Hz with a kinematic model (it does not
know the forces) holds its linear velocity between the DVL's samples and, at
each, moves it part of the way to the sample: in the log the velocity is a
staircase, e[k] = e[k-1] between samples and e[k] = (1 - K) e[k-1] + K d[k]
at a sample d[k] of the true velocity (K the filter's gain there). Measured
on ``bluerov2_excitation_realistic`` (a 5 Hz DVL logged at 20 Hz): the step
held for 4 rows, the sample landing within 0.01 m/s (the DVL's noise) of the
true velocity at its row, K about 0.86. Read as the vehicle's velocity, the
staircase lags the motion by about 0.1 s, which reads as extra inertia.

So when a log's linear velocity is a staircase, stage 2 passes the model's
velocity through the same update (the rows where the log's velocity moved,
each with a gain per axis fitted with the parameters) before comparing it
with the log: the model and the measurement then see the same estimator."""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from neurov.identification.log import Log

__all__ = ["refresh_rows", "staircase", "through_updates"]

Array = NDArray[np.float64]

# A row whose linear-velocity step is below this fraction of the typical
# (90th percentile) step is a held row, not a sensor update.
HELD = 0.05
# A log with fewer updates than this fraction of its rows is a staircase.
STAIRCASE = 0.75


def refresh_rows(log: Log) -> NDArray[np.bool_]:
    """(N,) True where the log's linear velocity moved (a sensor update),
    False where it was held from the row before; each segment's first row
    is True (its value is the filter's state the segment starts from)."""
    step = np.zeros(len(log.t))
    step[1:] = np.linalg.norm(np.diff(log.nu[:, :3], axis=0), axis=1)
    typical = np.percentile(step[1:], 90) if len(step) > 1 else 0.0
    fresh = step > HELD * typical
    for a, _ in log.segments:
        fresh[a] = True
    return fresh


def staircase(log: Log) -> bool:
    """Whether the log's linear velocity is held between sensor updates."""
    return bool(np.mean(refresh_rows(log)) < STAIRCASE) if len(log.t) > 8 else False


def through_updates(pred: Array, fresh: NDArray[np.bool_], gain: Array, e0: Array) -> Array:
    """The estimator's output (steps + 1, 3) for the model's linear velocity
    `pred` (steps + 1, 3) over one segment: from the state `e0` at its row
    0, held on rows not `fresh`, moved by `gain` (3,) toward `pred` on the
    fresh ones."""
    out = np.empty_like(pred)
    e = np.array(e0, dtype=np.float64)
    out[0] = e
    for j in range(1, len(pred)):
        if fresh[j]:
            e = e + gain * (pred[j] - e)
        out[j] = e
    return out
