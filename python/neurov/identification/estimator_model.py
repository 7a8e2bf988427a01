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

The same filter holds its body rates as states and moves them at each gyro
sample (every row here) by a gain K just below 1: e[k] = e[k-1] + K (g[k] -
e[k-1]), a lag of (1 - K) / K periods. Measured on
``nerov_excitation_realistic`` (seed 0, 60 s): the rate error regresses on
the angular acceleration as a lag of 2.5 ms (K about 0.95), small, but it
read as 1.4 % more rotational added mass on NEROV (whose added inertia is a
small part of its total), enough to leave -K_pdot and -N_rdot uncovered
in every run; with the true rates in the same log the bias is gone.

So when a log's linear velocity is a staircase (an estimator's output),
stage 2 passes the model's velocities through the same updates, linear
and angular each on its own update rows (where the log's velocity moved),
each axis with a gain fitted with the parameters, before comparing them
with the log: the model and the measurement then see the same estimator."""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from neurov.identification.log import Log

__all__ = ["ANGULAR", "LINEAR", "refresh_rows", "staircase", "through_updates"]

Array = NDArray[np.float64]

# A row whose linear-velocity step is below this fraction of the typical
# (90th percentile) step is a held row, not a sensor update (between DVL
# samples the EKF's other updates still move it a little).
HELD = 0.05
# For the rates, updated by a gyro at most rows, a held row is one that did
# not move at all: a rate passing through its extremum moves by far less than
# 5 % of a typical step at a genuine update (marked held, the noise-free
# tests missed the truth by 1e-4).
HELD_RATES = 1e-9
# A log with fewer updates than this fraction of its rows is a staircase.
STAIRCASE = 0.75
# The velocities each update model covers (its gains fitted per axis).
LINEAR = slice(0, 3)
ANGULAR = slice(3, 6)


def refresh_rows(log: Log, axes: slice = LINEAR) -> NDArray[np.bool_]:
    """(N,) True where the log's velocity on `axes` (LINEAR: u, v, w;
    ANGULAR: p, q, r) moved (a sensor update), False where it was held from
    the row before; each segment's first row is True (its value is the
    filter's state the segment starts from)."""
    step = np.zeros(len(log.t))
    step[1:] = np.linalg.norm(np.diff(log.nu[:, axes], axis=0), axis=1)
    typical = np.percentile(step[1:], 90) if len(step) > 1 else 0.0
    fresh = step > (HELD_RATES if axes == ANGULAR else HELD) * typical
    for a, _ in log.segments:
        fresh[a] = True
    return fresh


def staircase(log: Log) -> bool:
    """Whether the log's linear velocity is held between sensor updates."""
    return bool(np.mean(refresh_rows(log)) < STAIRCASE) if len(log.t) > 8 else False


def through_updates(pred: Array, lengths: NDArray[np.int64], fresh: NDArray[np.bool_], gain: Array,
                    e0: Array) -> Array:
    """The estimator's output for the model's velocities `pred`
    (sum(lengths), n): segments of `lengths` rows stacked, each from its
    state `e0[i]` (S, n) at its row 0, held on rows not `fresh`
    (sum(lengths),), moved by `gain` (n,) toward `pred` on the fresh ones
    (a segment's row 0 is its start, never an update). The segments are
    updated together: one numpy step per update of the segment with the
    most, then each row takes the state after its segment's latest update."""
    lengths = np.asarray(lengths, dtype=np.int64)
    n_seg = len(lengths)
    seg = np.repeat(np.arange(n_seg), lengths)
    first = np.concatenate([[0], np.cumsum(lengths)[:-1]]).astype(np.int64)
    update = np.asarray(fresh, dtype=bool).copy()
    update[first] = False
    counted = np.cumsum(update)
    # rank[j]: the updates of row j's segment up to row j (0: none yet, the start e0).
    rank = counted - (counted[first] - update[first])[seg]
    most = int(rank.max()) if len(rank) else 0
    rows = np.full((n_seg, most), -1, dtype=np.int64)
    at = np.flatnonzero(update)
    rows[seg[at], rank[at] - 1] = at
    width = pred.shape[1]
    state = np.empty((n_seg, most + 1, width))
    e = np.array(e0, dtype=np.float64).reshape(n_seg, width)
    state[:, 0] = e
    for k in range(most):
        live = rows[:, k] >= 0
        e[live] = e[live] + gain * (pred[rows[live, k]] - e[live])
        state[:, k + 1] = e
    return state[seg, rank]
