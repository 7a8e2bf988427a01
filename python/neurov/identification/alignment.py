"""Signals at different rates on one time base: each signal is held from
its latest sample (a zero-order hold, as a controller sees it) and is
missing (NaN, so the row is cut) where its latest sample is older than
`max_age` or where there is none yet: a gap is cut, never interpolated across."""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from neurov.identification.errors import LogError

__all__ = ["hold", "check_increasing"]

Array = NDArray[np.float64]


def check_increasing(t: Array, where: str) -> None:
    """Refuses stamps that go backwards (naming `where` and the row)."""
    steps = np.diff(t)
    if np.any(steps < 0):
        k = int(np.flatnonzero(steps < 0)[0])
        raise LogError(f"{where}: time must not go backwards; it goes from {t[k]:.9g} s to "
                       f"{t[k + 1]:.9g} s at sample {k + 1}")


def hold(base: Array, t: Array, values: Array, max_age: float, where: str) -> Array:
    """`values` (n, ...) sampled at `t` (n,), read at the times `base`."""
    check_increasing(t, where)
    if len(t) == 0:
        raise LogError(f"{where}: no samples")
    k = np.searchsorted(t, base, side="right") - 1
    out = values[np.clip(k, 0, None)].astype(np.float64, copy=True)
    stale = (k < 0) | (base - t[np.clip(k, 0, None)] > max_age)
    out[stale] = np.nan
    return out
