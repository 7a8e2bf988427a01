"""A run's tracking and effort metrics, summed as the rows come.

Each metric is one :class:`Metric` in :data:`METRICS`: its name (the column of
a study's runs table), its axis label and the function that computes it from
the window's sums. :meth:`Result.metrics`, a study's runs table, the league
table's checks, the tuner's objective and the figures' labels all read that one
table, so a metric added there (:func:`register_metric`) reaches all of them.

:class:`MetricsWindow` takes a run's rows in one piece (:meth:`Result.metrics`)
or chunk by chunk as a long run streams (``neurov run``), and gives the same
numbers either way: sums, counts and extremes over the window t >= `after`.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any, Protocol

import numpy as np

from neurov import _core

__all__ = ["METRICS", "TRANSIENT_S", "Metric", "MetricsWindow", "Window", "WindowSums", "flat_metrics",
           "metric_label", "metric_names", "metrics_start", "register_metric"]

TRANSIENT_S = 10.0
"""The start-up transient the metrics skip [s]: the weights start from zero
and the reference model catches up with the first command (the shipped
commands start moving within 5 s). A fixed time, so that a 24-hour run and a
1-minute run are judged on the same footing."""

DOF_NAMES = ("x", "y", "z", "roll", "pitch", "yaw")


class Rows(Protocol):
    """The series of a run's consecutive rows that its sums read (a
    :class:`~neurov.results.timeseries.Result` is one)."""

    t: np.ndarray
    eta: np.ndarray
    eta_d: np.ndarray
    tau_demanded: np.ndarray
    controller_status: np.ndarray
    adaptive_norm: np.ndarray
    diverged: bool


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


class WindowSums:
    """Sums and extremes of the tracking error and the force over some rows:
    the members of ``cpp/include/neurov/sim/window_sums.hpp`` (its table is
    :data:`neurov._core.WINDOW_SUMS`), which sums them. Empty by default."""

    rows: int
    t_first: float
    t_last: float
    e2: np.ndarray  #: sum of ``e_i**2`` per DOF
    abs_e: np.ndarray  #: sum of ``abs(e_i)`` per DOF
    max_abs_e: np.ndarray
    pos2: float  #: sum of ``norm(e_xyz)**2``
    max_pos: float
    abs_tau: float  #: sum of ``abs(tau_i)`` over every DOF
    abs_tau_dof: np.ndarray
    max_abs_tau_dof: np.ndarray
    tau_norm: float  #: sum of ``norm(tau)``
    refused: int

    def __init__(self, sums: dict[str, Any] | None = None) -> None:
        """The sums of a dict of :meth:`neurov._core.RunSums.as_dict` (its
        ``"before"`` or ``"window"``); None: no row yet."""
        vars(self).update(_core.RunSums(0.0).as_dict()["window"] if sums is None else sums)


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
        self._sums = _core.RunSums(self.after)
        self._given: dict[str, Any] | None = None  # sums C++ accumulated as a run ran (from_sums)

    def add(self, rows: Rows) -> None:
        """The next rows of the run (a Result of consecutive rows), summed by
        the C++ that sums a run in C++ (:class:`neurov._core.RunSums`)."""
        if self._given is not None:
            raise ValueError("a MetricsWindow made from_sums takes no rows")
        self._sums.add(rows.t, rows.eta, rows.eta_d, rows.tau_demanded, rows.controller_status,
                       rows.adaptive_norm, bool(rows.diverged))

    @classmethod
    def from_sums(cls, sums: dict[str, Any], duration: float, dt: float) -> MetricsWindow:
        """The window of a run whose sums C++ accumulated as it ran (a dict of
        ``_core.run_batch(..., metrics_only=True)``): the same metrics as
        :meth:`add` of its rows would give."""
        window = cls(duration, dt, sums["after"])
        window._given = sums
        return window

    def _raw(self) -> dict[str, Any]:
        return self._given if self._given is not None else self._sums.as_dict()

    @property
    def first_refused(self) -> tuple[float, int] | None:
        """(t, status) of the first refused controller step, None while there is none."""
        first = self._raw()["first_refused"]
        return None if first is None else (float(first[0]), int(first[1]))

    @property
    def rows(self) -> int:
        """Rows added so far, in the window and before it."""
        raw = self._raw()
        return int(raw["window"]["rows"] + raw["before"]["rows"])

    @property
    def t_last(self) -> float | None:
        """The time of the last row added (None before any)."""
        return self._t_last(self._raw())

    @staticmethod
    def _t_last(raw: dict[str, Any]) -> float | None:
        for part in ("window", "before"):
            if raw[part]["rows"]:
                return float(raw[part]["t_last"])
        return None

    def window(self) -> Window:
        """What the metrics are computed from: the sums of the rows judged. A
        diverged run with no row in the window is judged over every row (a
        run that failed before its first row over none: its metrics nan);
        otherwise an empty window raises ValueError naming 'after'."""
        raw = self._raw()
        w, before = WindowSums(raw["window"]), WindowSums(raw["before"])
        if not w.rows:
            last = before.t_last if before.rows else 0
            if not raw["diverged"]:
                raise ValueError(f"argument 'after' = {self.after} leaves no samples (run ends at {last})")
            w = before
        return Window(sums=w, dt=self.dt, refused_steps=int(raw["window"]["refused"] + before.refused),
                      final_adaptive_norm=float(raw["final_adaptive_norm"]),
                      max_adaptive_norm=float(raw["max_adaptive_norm"]), diverged=bool(raw["diverged"]),
                      t_last=self._t_last(raw))

    def value(self) -> dict[str, Any]:
        """The metrics of the rows added (see :meth:`Result.metrics`), nested
        as :meth:`Result.metrics` gives them: each metric of :data:`METRICS`
        under its name, or inside the dict or list its ``nest`` names."""
        window = self.window()
        out: dict[str, Any] = {}
        with np.errstate(over="ignore", invalid="ignore"):
            for m in METRICS.values():
                if window.sums.rows:
                    v = m.compute(window)
                else:  # a run that failed before its first row: its counts, and no value
                    v = m.compute(window) if m.name in _COUNTS else math.inf if m.error else math.nan
                if m.nest is None:
                    out[m.name] = v
                elif isinstance(m.nest[1], int):
                    out.setdefault(m.nest[0], []).append(v)
                else:
                    out.setdefault(m.nest[0], {})[m.nest[1]] = v
        return out

    def flat(self) -> dict[str, float]:
        """The metrics of the rows added as the columns of a study's runs
        table: each column metric under its own name, as a float."""
        return flat_metrics(self.value())


@dataclass(frozen=True)
class Window:
    """The rows a run is judged on, as a metric's function sees them."""

    sums: WindowSums  #: the sums and extremes over the rows judged
    dt: float  #: the row spacing [s]
    refused_steps: int  #: refused controller steps over the whole run
    final_adaptive_norm: float  #: the adapted parameters' norm at the last row
    max_adaptive_norm: float  #: its maximum over the whole run
    diverged: bool
    t_last: float | None  #: the time of the last row


@dataclass(frozen=True)
class Metric:
    """One metric of a run, in one place.

    `name` is its key in :meth:`Result.metrics` and its column in a study's
    runs table; `label` its axis label in words with its unit in brackets;
    `compute` gives its value from the :class:`Window`. `error`: a tracking
    error, which a study sets to inf in a diverged run (so that the run ranks
    as the failure it is). `nest`: where :meth:`Result.metrics` puts it, a
    (dict name, key) or (list name, index) pair, for the per-DOF metrics.
    `column`: whether a study's runs table has it (the window's own facts,
    its start and end, are not metrics to rank by).
    """

    name: str
    label: str
    compute: Callable[[Window], Any]
    error: bool = False
    nest: tuple[str, str | int] | None = None
    column: bool = True


#: The metrics that are counts over the whole run, not values of its rows:
#: the only ones a run that failed before its first row has.
_COUNTS = ("refused_steps", "refused_steps_in_window", "diverged", "diverged_at_s")

#: Every metric, in the order of :meth:`Result.metrics` and of a study's runs
#: table. Filled below and by :func:`register_metric`.
METRICS: dict[str, Metric] = {}


def register_metric(metric: Metric) -> Metric:
    """Adds `metric` to :data:`METRICS` (and so to :meth:`Result.metrics`, a
    study's runs table, the names a study or tuning file may rank by and the
    figures' labels). A name already taken is refused. A study's worker
    processes import neurov afresh: register a metric of your own in a module
    that your study's controller factory imports, or run the study in this
    process (``executor="processes", workers=1``)."""
    if not isinstance(metric, Metric):
        raise TypeError(f"argument 'metric' must be a neurov.results.metrics.Metric, got {type(metric).__name__}")
    if not metric.name.isidentifier():
        raise ValueError(f"argument 'metric': name must be an identifier (a table column), got {metric.name!r}")
    if metric.name in METRICS:
        raise ValueError(f"argument 'metric': a metric named {metric.name!r} exists already")
    if not metric.label.strip():
        raise ValueError(f"argument 'metric': label of {metric.name!r} must say what it is and its unit")
    METRICS[metric.name] = metric
    return metric


def metric_names() -> list[str]:
    """The metric columns of a study's runs table, in their order."""
    return [m.name for m in METRICS.values() if m.column]


def metric_label(key: str) -> str:
    """The axis label of metric `key`; the key itself for a column that is not a metric."""
    m = METRICS.get(key)
    return m.label if m is not None else key


def flat_metrics(nested: dict[str, Any]) -> dict[str, float]:
    """:meth:`Result.metrics` as the columns of a study's runs table (each a
    float; a missing time, None, as NaN)."""
    out: dict[str, float] = {}
    for m in METRICS.values():
        if not m.column:
            continue
        v = nested[m.name] if m.nest is None else nested[m.nest[0]][m.nest[1]]
        out[m.name] = math.nan if v is None else float(v)
    return out


def _define_metrics() -> None:
    """The shipped metrics. The mean and maximum of ``|tau|`` over all six
    DOFs, and the control energy, add forces and moments, hence "N, N m". The
    adapted parameters (NN weights or theta_hat) carry the units of different
    regressor columns: their norm has none of its own."""
    f = _finite_or_inf
    dofs = (("x", "x (north)", "m"), ("y", "y (east)", "m"), ("z", "z (depth)", "m"),
            ("roll", "roll", "rad"), ("pitch", "pitch", "rad"), ("yaw", "yaw", "rad"))
    taus = (("X", "N"), ("Y", "N"), ("Z", "N"), ("K", "N m"), ("M", "N m"), ("N", "N m"))

    def rmse(w: Window, i: int) -> float:
        return f(np.sqrt(w.sums.e2[i] / w.sums.rows))

    ms = [
        Metric("window_start_s", "start of the metrics window [s]", lambda w: w.sums.t_first, column=False),
        Metric("window_end_s", "end of the metrics window [s]", lambda w: w.sums.t_last, column=False),
        Metric("rmse_position_m", "RMS position error [m]",
               lambda w: f(np.sqrt(w.sums.pos2 / w.sums.rows)), error=True),
        Metric("max_position_error_m", "max position error [m]", lambda w: f(w.sums.max_pos), error=True),
        Metric("rmse_yaw_rad", "RMS yaw error [rad]", lambda w: rmse(w, 5), error=True),
        Metric("max_yaw_error_rad", "max yaw error [rad]", lambda w: f(w.sums.max_abs_e[5]), error=True),
    ]
    for i, (k, name, unit) in enumerate(dofs):
        ms.append(Metric(f"rmse_{k}", f"RMS {name} error [{unit}]", lambda w, i=i: rmse(w, i),
                         error=True, nest=("rmse", k)))
    for i, (k, name, unit) in enumerate(dofs):
        ms.append(Metric(f"max_abs_error_{k}", f"max |{name} error| [{unit}]",
                         lambda w, i=i: f(w.sums.max_abs_e[i]), error=True, nest=("max_abs_error", k)))
    for i, (k, name, unit) in enumerate(dofs):
        ms.append(Metric(f"iae_{k}", f"integral of |{name} error| [{unit} s]",
                         lambda w, i=i: f(w.sums.abs_e[i] * w.dt), error=True, nest=("iae", k)))
    ms += [
        Metric("mean_abs_tau", "mean |τ| over the six DOFs [N, N m]",
               lambda w: f(w.sums.abs_tau / (6 * w.sums.rows))),
        Metric("max_abs_tau", "max |τ| over the six DOFs [N, N m]", lambda w: f(np.max(w.sums.max_abs_tau_dof))),
    ]
    for i, (name, unit) in enumerate(taus):
        ms.append(Metric(f"mean_abs_tau_dof_{i}", f"mean |τ {name}| [{unit}]",
                         lambda w, i=i: f(w.sums.abs_tau_dof[i] / w.sums.rows), nest=("mean_abs_tau_dof", i)))
    for i, (name, unit) in enumerate(taus):
        ms.append(Metric(f"max_abs_tau_dof_{i}", f"max |τ {name}| [{unit}]",
                         lambda w, i=i: f(w.sums.max_abs_tau_dof[i]), nest=("max_abs_tau_dof", i)))
    ms += [
        Metric("control_energy", "control effort ∫‖τ‖ dt [N s, N m s]", lambda w: f(w.sums.tau_norm * w.dt)),
        Metric("final_adaptive_norm", "final norm of the adapted parameters [mixed units]",
               lambda w: f(w.final_adaptive_norm)),
        Metric("max_adaptive_norm", "max norm of the adapted parameters [mixed units]",
               lambda w: f(w.max_adaptive_norm)),
        # Over the whole run: a controller failing in the transient is not hidden by the window.
        Metric("refused_steps", "refused control steps [count]", lambda w: w.refused_steps),
        Metric("refused_steps_in_window", "refused control steps in the window [count]",
               lambda w: w.sums.refused, column=False),
        Metric("diverged", "run diverged [0 or 1]", lambda w: w.diverged),
        Metric("diverged_at_s", "time the run diverged [s]",
               lambda w: w.t_last if w.diverged else None, column=False),
    ]
    for m in ms:
        register_metric(m)


_define_metrics()
