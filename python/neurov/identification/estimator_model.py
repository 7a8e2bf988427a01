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
with the log: the model and the measurement then see the same estimator.
Between the DVL's updates the EKF's depth updates move the linear velocity
a little (half-way between two DVL samples, through the covariance of
position and velocity); those rows are not updates, and the model moves by
the log's own step there (held_moves)."""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from neurov.identification.log import Log

__all__ = ["ANGULAR", "LINEAR", "held_moves", "refresh_rows", "staircase", "through_updates"]

Array = NDArray[np.float64]

# A row whose linear-velocity step is below this fraction of the typical
# update's (the median step of the rows above it) is not a DVL update: between
# DVL samples the EKF's depth updates move it too. Measured on
# bluerov2_excitation_realistic (perturbed vehicle, 60 s, seeds 0-9): the
# depth sensor's moves reach 29 % of the typical update at most, 0.1 % of
# them above a fifth; 1.6 % of the rows with a DVL sample fall below a fifth
# (1 % are the DVL's dropouts). The rule before, 5 % of the steps' 90th
# percentile (about 5.5 % of the typical update), took 7-9 % of the depth
# rows for updates and biased -X_udot by +2 %. Too high a fraction costs
# little: a DVL step taken for another sensor's move is copied from the log
# (held_moves).
HELD = 0.2
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
    if axes == ANGULAR:
        fresh = step > HELD_RATES * (np.percentile(step[1:], 90) if len(step) > 1 else 0.0)
    else:
        fresh = step > HELD * _typical_update(step[1:])
    for a, _ in log.segments:
        fresh[a] = True
    return fresh


def _typical_update(step: Array) -> float:
    """The median of the steps above HELD times it: from the largest step
    down, a fixed point that settles on the updates' cluster however few
    rows they are (a 1 Hz DVL in a 20 Hz log is 5 % of them)."""
    moved = step[step > 0]
    if not len(moved):
        return 0.0
    typical = float(moved.max())
    for _ in range(50):
        nxt = float(np.median(moved[moved >= HELD * typical]))
        if nxt == typical:
            break
        typical = nxt
    return typical


def staircase(log: Log) -> bool:
    """Whether the log's linear velocity is held between sensor updates."""
    return bool(np.mean(refresh_rows(log)) < STAIRCASE) if len(log.t) > 8 else False


def held_moves(log: Log, fresh: NDArray[np.bool_], axes: slice = LINEAR) -> Array:
    """(N, n) the log's own step into each row that is not a sensor update
    (zero on the updates): what the estimator's other sensors moved it by
    between two updates."""
    step = np.zeros((len(log.t), axes.stop - axes.start))
    step[1:] = np.diff(log.nu[:, axes], axis=0)
    step[fresh] = 0.0
    return step


def through_updates(pred: Array, lengths: NDArray[np.int64], fresh: NDArray[np.bool_], gain: Array,
                    e0: Array, moves: Array | None = None) -> Array:
    """The estimator's output for the model's velocities `pred`
    (sum(lengths), n): segments of `lengths` rows stacked, each from its
    state `e0[i]` (S, n) at its row 0, moved by `gain` (n,) toward `pred`
    on the `fresh` rows (sum(lengths),) and by `moves` (sum(lengths), n;
    default none: held) on the others (a segment's row 0 is its start,
    neither). The segments are updated together: one numpy step per update
    of the segment with the most, then each row takes the state after its
    segment's latest update plus the moves since."""
    lengths = np.asarray(lengths, dtype=np.int64)
    n_seg = len(lengths)
    seg = np.repeat(np.arange(n_seg), lengths)
    first = np.concatenate([[0], np.cumsum(lengths)[:-1]]).astype(np.int64)
    update = np.asarray(fresh, dtype=bool).copy()
    update[first] = False
    width = pred.shape[1]
    drift = np.zeros((len(seg), width)) if moves is None else np.array(moves, dtype=np.float64)
    drift[update] = 0.0
    drift[first] = 0.0
    # moved[j]: the moves of row j's segment up to row j (differences within a segment only).
    moved = np.cumsum(drift, axis=0)
    counted = np.cumsum(update)
    # rank[j]: the updates of row j's segment up to row j (0: none yet, the start e0).
    rank = counted - (counted[first] - update[first])[seg]
    most = int(rank.max()) if len(rank) else 0
    rows = np.full((n_seg, most), -1, dtype=np.int64)
    at = np.flatnonzero(update)
    rows[seg[at], rank[at] - 1] = at
    # since[i, k]: the row of segment i's k-th update (k = 0: its start).
    since = np.concatenate([first[:, None], rows], axis=1)
    state = np.empty((n_seg, most + 1, width))
    e = np.array(e0, dtype=np.float64).reshape(n_seg, width)
    state[:, 0] = e
    for k in range(most):
        live = rows[:, k] >= 0
        r = rows[live, k]
        e_pre = e[live] + moved[r] - moved[since[live, k]]
        e[live] = e_pre + gain * (pred[r] - e_pre)
        state[:, k + 1] = e
    return state[seg, rank] + moved - moved[since[seg, rank]]
