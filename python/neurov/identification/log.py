"""One log as identification sees it: samples on one time base, cut into
the contiguous segments between gaps and non-finite rows.

Row k holds the pose and body velocity measured at t_k and the force that
acted over [t_k, t_k+1) (the zero-order hold of a digital controller, and
what neurov logs as ``tau_applied``)."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
from numpy.typing import NDArray

from neurov.identification.errors import LogError

__all__ = ["ABSENT_OK", "Log", "fill_absent", "make_log"]

Array = NDArray[np.float64]

# The columns of [eta | nu] a log may lack (no DVL, no positioning: an IMU,
# an attitude estimator and a depth sensor); the attitude and rates may not.
ABSENT_OK = ("x", "y", "z", "u", "v", "w")
_NAMES = ("x", "y", "z", "roll", "pitch", "yaw", "u", "v", "w", "p", "q", "r")

# A step longer than this many times the median step is a gap: the data
# either side are separate segments (never interpolated across).
GAP_FACTOR = 1.5


@dataclass(frozen=True)
class Log:
    """A log's samples. `segments` are (start, stop) row ranges without a
    gap or a non-finite value inside; `cut` counts the rows dropped for
    non-finite values."""

    source: str
    t: Array
    eta: Array
    nu: Array
    tau: Array
    current: Array  #: (N, 3) NED current at the vehicle [m/s] (zero when unknown)
    segments: tuple[tuple[int, int], ...]
    cut: int = 0
    notes: tuple[str, ...] = field(default_factory=tuple)
    #: what the reader found wrong with the log, said first in the log report
    problems: tuple[str, ...] = field(default_factory=tuple)
    #: the pose and velocity columns (x y z u v w) the log does not have,
    #: held at zero: their DOFs are left out of the fit (the log report says so)
    absent: tuple[str, ...] = field(default_factory=tuple)

    @property
    def dt(self) -> float:
        """The median sampling step [s]."""
        return float(np.median(np.diff(self.t)))

    @property
    def duration(self) -> float:
        """Seconds covered by the segments (gaps excluded)."""
        return float(sum(self.t[b - 1] - self.t[a] for a, b in self.segments))


def fill_absent(source: str, eta: Array, nu: Array, where: str) -> tuple[str, ...]:
    """The columns of `eta` and `nu` (N, 6) that are NaN on every row, set
    to zero in place and named (only x y z u v w may be: a log with no
    linear velocity or position is fitted in the DOFs it has); a LogError
    naming `source` and `where` (the mapping) when an attitude or rate is
    missing."""
    empty = [n for k, n in enumerate(_NAMES) if np.all(np.isnan(eta[:, k] if k < 6 else nu[:, k - 6]))]
    if any(n not in ABSENT_OK for n in empty):
        raise LogError(f"{source}: no topic gives {', '.join(empty)} ({where}: an odometry topic, "
                       "or [[arrays]] elements for them; the attitude and rates are needed at least)")
    for n in empty:
        k = _NAMES.index(n)
        (eta[:, k] if k < 6 else nu[:, k - 6])[:] = 0.0
    return tuple(empty)


def make_log(source: str, t: object, eta: object, nu: object, tau: object,
             current: object = None, min_segment: int = 8, absent: tuple[str, ...] = ()) -> Log:
    """Checks and cuts a log: shapes, time strictly increasing (an error
    naming `source` otherwise), rows with a NaN or inf dropped and counted,
    gaps split into segments; segments shorter than `min_segment` rows are
    dropped (they hold no derivative)."""
    arrays = {"t": np.asarray(t, dtype=np.float64), "eta": np.asarray(eta, dtype=np.float64),
              "nu": np.asarray(nu, dtype=np.float64), "tau": np.asarray(tau, dtype=np.float64)}
    n = arrays["t"].shape[0] if arrays["t"].ndim == 1 else -1
    if n < 0:
        raise LogError(f"{source}: t: expected one time per row, got shape {arrays['t'].shape}")
    for name in ("eta", "nu", "tau"):
        if arrays[name].shape != (n, 6):
            raise LogError(f"{source}: {name}: expected ({n}, 6) (one row of 6 per time), "
                           f"got {arrays[name].shape}")
    c = np.zeros((n, 3)) if current is None else np.asarray(current, dtype=np.float64)
    if c.shape != (n, 3):
        raise LogError(f"{source}: current: expected ({n}, 3), got {c.shape}")
    finite_t = np.isfinite(arrays["t"])
    steps = np.diff(arrays["t"][finite_t])
    if np.any(steps <= 0):
        k = int(np.flatnonzero(steps <= 0)[0])
        times = arrays["t"][finite_t]
        raise LogError(f"{source}: t: time must increase; it goes from {times[k]:.9g} s to "
                       f"{times[k + 1]:.9g} s at row {int(np.flatnonzero(finite_t)[k + 1])}")
    good = finite_t & np.all(np.isfinite(np.hstack([arrays["eta"], arrays["nu"], arrays["tau"], c])), axis=1)
    cut = int(n - good.sum())
    t_all = arrays["t"]
    if good.sum() < 2:
        raise LogError(f"{source}: fewer than 2 rows with finite values ({cut} of {n} cut)")
    dt = float(np.median(np.diff(t_all[good])))
    segments: list[tuple[int, int]] = []
    kept = np.flatnonzero(good)
    # Break at each dropped row and at each gap in time.
    breaks = np.flatnonzero((np.diff(kept) != 1) | (np.diff(t_all[kept]) > GAP_FACTOR * dt)) + 1
    start = 0
    rows = []
    for stop in [*breaks.tolist(), len(kept)]:
        if stop - start >= min_segment:
            rows.append(kept[start:stop])
        start = stop
    if not rows:
        raise LogError(f"{source}: no stretch of {min_segment} consecutive finite rows without a gap")
    index = np.concatenate(rows)
    offset = 0
    for r in rows:
        segments.append((offset, offset + len(r)))
        offset += len(r)
    notes = (f"{cut} row(s) with non-finite values cut",) if cut else ()
    return Log(source=source, t=t_all[index], eta=arrays["eta"][index], nu=arrays["nu"][index],
               tau=arrays["tau"][index], current=c[index], segments=tuple(segments), cut=cut,
               notes=notes, absent=tuple(absent))


def advance_linear_velocity(log: Log, lag_s: float) -> Log:
    """The log with its linear velocities (u, v, w) moved `lag_s` seconds
    earlier (whole rows), for an estimator whose velocity lags the motion
    (an EKF fusing a DVL at a few Hz): a lag reads as extra inertia. Each
    segment loses its last rows."""
    if not lag_s >= 0:
        raise LogError(f"velocity_lag: expected seconds >= 0, got {lag_s}")
    rows = int(round(lag_s / log.dt))
    if rows == 0:
        return log
    keep, nu, segments, offset = [], [], [], 0
    for a, b in log.segments:
        if b - a - rows < 8:
            continue
        idx = np.arange(a, b - rows)
        moved = log.nu[idx].copy()
        moved[:, :3] = log.nu[idx + rows, :3]
        keep.append(idx)
        nu.append(moved)
        segments.append((offset, offset + len(idx)))
        offset += len(idx)
    if not keep:
        raise LogError(f"{log.source}: no segment longer than the velocity lag of {rows} rows")
    index = np.concatenate(keep)
    return Log(source=log.source, t=log.t[index], eta=log.eta[index], nu=np.concatenate(nu),
               tau=log.tau[index], current=log.current[index], segments=tuple(segments), cut=log.cut,
               absent=log.absent,
               notes=(*log.notes, f"linear velocity moved {rows} row(s) ({rows * log.dt:g} s) earlier "
                      "for the estimator's lag"))

