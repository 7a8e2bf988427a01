"""What the run plots draw of a long run: a few thousand rows per line keep
every peak; 432,000 (a day at 5 Hz) only cost time and memory.

:func:`for_plotting` splits the time axis into equal buckets and keeps, in
each, its first and last row and every row where a drawn quantity (a DOF of
η, η_d or η − η_d, of τ demanded or applied, a thrust, the adaptive norm) is
at its minimum or maximum in that bucket. So the drawn envelope of every line
is exact at the bucket's resolution (a spike of one sample still shows); the
shape between a bucket's extremes is not kept. Runs of at most
:data:`MAX_PLOT_ROWS` rows are drawn whole. The rows kept are rows of the run
(all quantities at one instant), so the X-Y path stays a path.
"""

from __future__ import annotations

import dataclasses

import numpy as np
from numpy.typing import NDArray

from neurov.result import SERIES, Result

__all__ = ["MAX_PLOT_ROWS", "for_plotting", "kept_rows"]

MAX_PLOT_ROWS = 40_000
"""At most this many rows of a run are drawn (see :func:`for_plotting`)."""


def _extremes(values: NDArray[np.float64], size: int) -> NDArray[np.int64]:
    """Row indices of each column's minimum and maximum in each bucket of
    `size` consecutive rows of the 2-D `values` (the last bucket may be
    shorter)."""
    rows = values.shape[0]
    full = rows // size
    out = []
    if full:
        blocks = values[: full * size].reshape(full, size, -1)
        offsets = (np.arange(full) * size)[:, None]
        out += [np.argmin(blocks, axis=1) + offsets, np.argmax(blocks, axis=1) + offsets]
    if rows > full * size:
        tail = values[full * size:]
        out += [np.argmin(tail, axis=0) + full * size, np.argmax(tail, axis=0) + full * size]
    return np.concatenate([o.ravel() for o in out])


def kept_rows(result: Result, max_rows: int = MAX_PLOT_ROWS) -> NDArray[np.int64]:
    """Sorted indices of the rows :func:`for_plotting` keeps: every row if
    the run has at most `max_rows`, else at most `max_rows` (or, if more,
    one bucket's: two per drawn column and two)."""
    if max_rows < 2:
        raise ValueError(f"argument 'max_rows' must be >= 2, got {max_rows}")
    rows = len(result.t)
    if rows <= max_rows:
        return np.arange(rows)
    drawn = [result.eta, result.eta_d, result.error, result.tau_demanded, result.tau_applied,
             result.thrusts, result.adaptive_norm[:, None]]
    columns = sum(a.shape[1] for a in drawn)
    # Each bucket keeps up to 2 rows per column plus its first and last row.
    buckets = max(1, max_rows // (2 * columns + 2))
    size = -(-rows // buckets)
    starts = np.arange(0, rows, size)
    ends = np.minimum(starts + size, rows) - 1
    with np.errstate(invalid="ignore"):
        picks = [starts, ends] + [_extremes(a, size) for a in drawn if a.shape[1]]
    return np.unique(np.concatenate(picks))


def for_plotting(result: Result, max_rows: int = MAX_PLOT_ROWS) -> Result:
    """`result` itself if it has at most `max_rows` rows, else a Result of
    the rows :func:`kept_rows` picks (``extra["plotted_rows_of"]`` holds the
    run's row count). Its metrics are not the run's: take those from
    `result`."""
    keep = kept_rows(result, max_rows)
    if len(keep) == len(result.t):
        return result
    changes = {name: getattr(result, name)[keep] for name in SERIES}
    return dataclasses.replace(result, **changes, extra={**result.extra, "plotted_rows_of": len(result.t)})
