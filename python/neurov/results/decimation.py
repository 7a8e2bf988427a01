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

from neurov.results.timeseries import SERIES, Result

__all__ = ["MAX_PLOT_ROWS", "PlotRows", "bucket_rows", "for_plotting", "kept_rows"]

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


def _drawn(result: Result) -> list[NDArray[np.float64]]:
    """The quantities the run plots draw, as 2-D arrays of the rows."""
    return [result.eta, result.eta_d, result.error, result.tau_demanded, result.tau_applied,
            result.thrusts, result.adaptive_norm[:, None]]


def bucket_rows(rows: int, columns: int, max_rows: int = MAX_PLOT_ROWS) -> int:
    """Rows per bucket for a run of `rows` rows with `columns` drawn columns:
    each bucket keeps up to 2 rows per column plus its first and last row."""
    if max_rows < 2:
        raise ValueError(f"argument 'max_rows' must be >= 2, got {max_rows}")
    buckets = max(1, max_rows // (2 * columns + 2))
    return max(1, -(-rows // buckets))


def drawn_columns(thrusters: int) -> int:
    """Columns the run plots draw for a run with `thrusters` thrusters."""
    return 5 * 6 + thrusters + 1


def _picks(result: Result, size: int) -> NDArray[np.int64]:
    """Sorted indices of the rows kept in buckets of `size` rows from row 0."""
    rows = len(result.t)
    starts = np.arange(0, rows, size)
    ends = np.minimum(starts + size, rows) - 1
    with np.errstate(invalid="ignore"):
        picks = [starts, ends] + [_extremes(a, size) for a in _drawn(result) if a.shape[1]]
    return np.unique(np.concatenate(picks))


def kept_rows(result: Result, max_rows: int = MAX_PLOT_ROWS) -> NDArray[np.int64]:
    """Sorted indices of the rows :func:`for_plotting` keeps: every row if
    the run has at most `max_rows`, else at most `max_rows` (or, if more,
    one bucket's: two per drawn column and two)."""
    if max_rows < 2:
        raise ValueError(f"argument 'max_rows' must be >= 2, got {max_rows}")
    rows = len(result.t)
    if rows <= max_rows:
        return np.arange(rows)
    return _picks(result, bucket_rows(rows, drawn_columns(result.thrusts.shape[1]), max_rows))


def _take(result: Result, keep: NDArray[np.int64]) -> dict[str, NDArray[np.float64]]:
    return {name: getattr(result, name)[keep] for name in SERIES}


def for_plotting(result: Result, max_rows: int = MAX_PLOT_ROWS) -> Result:
    """`result` itself if it has at most `max_rows` rows, else a Result of
    the rows :func:`kept_rows` picks (``extra["plotted_rows_of"]`` holds the
    run's row count). Its metrics are not the run's: take those from
    `result`."""
    keep = kept_rows(result, max_rows)
    if len(keep) == len(result.t):
        return result
    return dataclasses.replace(result, **_take(result, keep), extra={**result.extra, "plotted_rows_of": len(result.t)})


class PlotRows:
    """The rows :func:`for_plotting` keeps of a run that comes in chunks (a
    streamed run): a run of `rows` rows with `thrusters` thrusters. Chunks
    whose lengths are multiples of :attr:`bucket` (all but the last) give
    exactly the rows of the whole run's :func:`for_plotting`."""

    def __init__(self, rows: int, thrusters: int, max_rows: int = MAX_PLOT_ROWS) -> None:
        self.rows = rows
        self.whole = rows <= max_rows
        self.bucket = bucket_rows(rows, drawn_columns(thrusters), max_rows)
        self._parts: list[dict[str, NDArray[np.float64]]] = []
        self._first: Result | None = None
        self._seen = 0
        self._diverged = False

    def chunk_rows(self, about: int) -> int:
        """A chunk length near `about` rows that is a multiple of :attr:`bucket`."""
        return max(1, round(about / self.bucket)) * self.bucket

    def add(self, chunk: Result) -> None:
        """The run's next rows."""
        self._first = self._first or chunk
        self._seen += len(chunk.t)
        self._diverged = self._diverged or chunk.diverged
        keep = np.arange(len(chunk.t)) if self.whole else _picks(chunk, self.bucket)
        self._parts.append(_take(chunk, keep))

    def result(self) -> Result:
        """The rows kept, as a Result of the run (its scenario, controller and
        how it ended, from the chunks); ``extra["plotted_rows_of"]`` holds
        the rows seen when some were dropped."""
        if self._first is None:
            raise ValueError("no rows were added")
        rows = {name: np.concatenate([p[name] for p in self._parts]) for name in SERIES}
        extra = dict(self._first.extra)
        if len(rows["t"]) < self._seen:
            extra["plotted_rows_of"] = self._seen
        return dataclasses.replace(self._first, **rows, extra=extra, diverged=self._diverged)
