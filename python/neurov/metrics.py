"""A run's tracking and effort metrics, summed as the rows come.

:class:`MetricsWindow` takes a run's rows in one piece (:meth:`Result.metrics`)
or chunk by chunk as a long run streams (``neurov run``), and gives the same
numbers either way: sums, counts and extremes over the window t >= `after`.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING, Any

import numpy as np

if TYPE_CHECKING:
    from neurov.result import Result

__all__ = ["TRANSIENT_S", "MetricsWindow", "metrics_start"]

TRANSIENT_S = 10.0
"""The start-up transient the metrics skip [s]: the weights start from zero
and the reference model catches up with the first command (the shipped
commands start moving within 5 s). A fixed time, so that a 24-hour run and a
1-minute run are judged on the same footing."""

DOF_NAMES = ("x", "y", "z", "roll", "pitch", "yaw")


def metrics_start(duration: float) -> float:
    """Where the metrics window starts for a run of `duration` seconds:
    :data:`TRANSIENT_S`, or half the run if it is shorter than twice that.
    The one window of ``neurov run``, ``neurov paper``, :meth:`Result.metrics`
    and the run plots (studies set their own ``after``)."""
    return min(TRANSIENT_S, 0.5 * duration)


def _finite_or_inf(x: Any) -> float:
    """A metric as a float; NaN (from inf - inf in a diverged run) as inf."""
    x = float(x)
    return x if math.isfinite(x) else math.inf


class _Sums:
    """Sums and extremes of the tracking error and the force over some rows."""

    def __init__(self) -> None:
        self.rows = 0
        self.t_first = math.nan
        self.t_last = math.nan
        self.e2 = np.zeros(6)           # sum of e_i^2
        self.abs_e = np.zeros(6)        # sum of |e_i|
        self.max_abs_e = np.full(6, -np.inf)
        self.pos2 = 0.0                 # sum of |e_xyz|^2
        self.max_pos = -math.inf
        self.abs_tau = 0.0              # sum of |tau_i| over every DOF
        self.abs_tau_dof = np.zeros(6)
        self.max_abs_tau_dof = np.full(6, -np.inf)
        self.tau_norm = 0.0             # sum of ||tau||
        self.refused = 0

    def add(self, t: np.ndarray, e: np.ndarray, tau: np.ndarray, status: np.ndarray) -> None:
        if not len(t):
            return
        if not self.rows:
            self.t_first = float(t[0])
        self.t_last = float(t[-1])
        self.rows += len(t)
        pos = np.linalg.norm(e[:, :3], axis=1)
        abs_e, abs_tau = np.abs(e), np.abs(tau)
        self.e2 += np.array([np.sum(e[:, i] ** 2) for i in range(6)])
        self.abs_e += np.array([np.sum(abs_e[:, i]) for i in range(6)])
        self.max_abs_e = np.maximum(self.max_abs_e, np.max(abs_e, axis=0))
        self.pos2 += float(np.sum(pos**2))
        self.max_pos = float(np.maximum(self.max_pos, np.max(pos)))  # NaN stays NaN
        self.abs_tau += float(np.sum(abs_tau))
        self.abs_tau_dof += np.sum(abs_tau, axis=0)
        self.max_abs_tau_dof = np.maximum(self.max_abs_tau_dof, np.max(abs_tau, axis=0))
        self.tau_norm += float(np.sum(np.linalg.norm(tau, axis=1)))
        self.refused += int(np.count_nonzero(status))


class MetricsWindow:
    """Accumulates :meth:`Result.metrics` over t >= `after` [s] (default
    :func:`metrics_start` of the scenario's duration) from a run's rows given
    in time order, in one piece or in chunks (each a :class:`Result`)."""

    def __init__(self, duration: float, dt: float, after: float | None = None) -> None:
        if after is None:
            after = metrics_start(duration)
        if not math.isfinite(after):
            raise ValueError(f"argument 'after' must be a finite time [s], got {after}")
        self.after = float(after)
        self.dt = dt
        self._window, self._before = _Sums(), _Sums()
        self._final_norm = math.nan
        self._max_norm = -math.inf
        self._diverged = False
        #: (t, status) of the first refused controller step, None while there is none.
        self.first_refused: tuple[float, int] | None = None

    def add(self, rows: Result) -> None:
        """The next rows of the run (a Result of consecutive rows)."""
        if not len(rows.t):
            self._diverged = self._diverged or rows.diverged
            return
        # t is increasing, so the window is a slice (views, no copies).
        if self.first_refused is None:
            bad = np.flatnonzero(rows.controller_status)
            if len(bad):
                self.first_refused = (float(rows.t[bad[0]]), int(rows.controller_status[bad[0]]))
        first = int(np.searchsorted(rows.t, self.after, side="left"))
        with np.errstate(over="ignore", invalid="ignore"):
            for part, sums in ((slice(None, first), self._before), (slice(first, None), self._window)):
                sums.add(rows.t[part], rows.eta[part] - rows.eta_d[part], rows.tau_demanded[part],
                         rows.controller_status[part])
            self._final_norm = float(rows.adaptive_norm[-1])
            self._max_norm = float(np.maximum(self._max_norm, np.max(rows.adaptive_norm)))
        self._diverged = self._diverged or rows.diverged

    @property
    def rows(self) -> int:
        """Rows added so far, in the window and before it."""
        return self._window.rows + self._before.rows

    @property
    def t_last(self) -> float | None:
        """The time of the last row added (None before any)."""
        return self._t_last()

    def _t_last(self) -> float | None:
        """The time of the last row added (None before any)."""
        for sums in (self._window, self._before):
            if sums.rows:
                return sums.t_last
        return None

    def value(self) -> dict[str, Any]:
        """The metrics of the rows added (see :meth:`Result.metrics`). A
        diverged run with no row in the window gets them over every row;
        otherwise an empty window raises ValueError naming 'after'."""
        w = self._window
        if not w.rows:
            last = self._before.t_last if self._before.rows else 0
            if not (self._diverged and self._before.rows):
                raise ValueError(f"argument 'after' = {self.after} leaves no samples (run ends at {last})")
            w = self._before
        n, dt = w.rows, self.dt
        with np.errstate(over="ignore", invalid="ignore"):
            rmse = np.sqrt(w.e2 / n)
            return {
                "window_start_s": w.t_first,
                "window_end_s": w.t_last,
                "rmse_position_m": _finite_or_inf(np.sqrt(w.pos2 / n)),
                "max_position_error_m": _finite_or_inf(w.max_pos),
                "rmse_yaw_rad": _finite_or_inf(rmse[5]),
                "max_yaw_error_rad": _finite_or_inf(w.max_abs_e[5]),
                "rmse": {name: _finite_or_inf(rmse[i]) for i, name in enumerate(DOF_NAMES)},
                "max_abs_error": {name: _finite_or_inf(w.max_abs_e[i]) for i, name in enumerate(DOF_NAMES)},
                "iae": {name: _finite_or_inf(w.abs_e[i] * dt) for i, name in enumerate(DOF_NAMES)},
                "mean_abs_tau": _finite_or_inf(w.abs_tau / (6 * n)),
                "max_abs_tau": _finite_or_inf(np.max(w.max_abs_tau_dof)),
                "mean_abs_tau_dof": [_finite_or_inf(x) for x in w.abs_tau_dof / n],
                "max_abs_tau_dof": [_finite_or_inf(x) for x in w.max_abs_tau_dof],
                "control_energy": _finite_or_inf(w.tau_norm * dt),
                "final_adaptive_norm": _finite_or_inf(self._final_norm),
                "max_adaptive_norm": _finite_or_inf(self._max_norm),
                # Over the whole run: a controller failing in the transient is not hidden by the window.
                "refused_steps": self._window.refused + self._before.refused,
                "refused_steps_in_window": w.refused,
                "diverged": self._diverged,
                "diverged_at_s": self._t_last() if self._diverged else None,
            }
