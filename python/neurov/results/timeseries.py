"""The result of one closed-loop run: the time series as arrays, its
metrics, and its export (CSV, NPZ, pandas, MCAP)."""

from __future__ import annotations

import json
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from neurov import _core, hooks
from neurov.config.scenario import Scenario
from neurov.progress import progress_bar
from neurov.results.columns import SERIES, STATUS_NAMES, table_columns
from neurov.results.export import CsvWriter, NpzWriter
from neurov.results.metrics import MetricsWindow, TRANSIENT_S, metrics_start

__all__ = ["SERIES", "TRANSIENT_S", "Result", "metrics_start"]

Array = NDArray[np.float64]

@dataclass
class Result:
    """Time series of one closed-loop run; rows at t_k = k dt. The arrays are
    the series of :data:`neurov._core.RESULT_SERIES` (their units and
    meaning there), in its order."""

    scenario: Scenario
    controller: str
    t: Array
    eta: Array
    nu: Array
    eta_d: Array
    eta_d_dot: Array
    tau_demanded: Array
    tau_applied: Array
    disturbance: Array
    s: Array
    eta_estimate: Array  #: (N, 6) the pose the controller was given (measured or estimated)
    nu_estimate: Array  #: (N, 6) the body velocity the controller was given
    thrusts: Array
    theta: Array
    adaptive_norm: Array
    controller_status: NDArray[np.uint8]
    plant_status: NDArray[np.uint8]
    faults: NDArray[np.uint8]
    current: Array  #: (N, 3) NED current at the vehicle [m/s]
    wave_velocity: Array  #: (N, 3) NED orbital velocity at the vehicle [m/s]
    wave_elevation: Array  #: (N,) surface elevation above the vehicle [m]
    payload_mass: Array  #: (N,) payload mass in effect [kg]
    diverged: bool
    wall_time: float = 0.0
    extra: dict[str, Any] = field(default_factory=dict)

    @property
    def error(self) -> Array:
        """eta - eta_d, shape (K, 6)."""
        return self.eta - self.eta_d

    @property
    def met_sea(self) -> bool:
        """True if the run met a current, waves or a payload change."""
        return bool(np.any(self.current) or np.any(self.wave_elevation) or np.any(self.payload_mass))

    def metrics(self, after: float | None = None) -> dict[str, Any]:
        """Tracking and effort metrics over t >= `after` [s]: RMS error per DOF
        and of the 3-D position, maximum errors, mean and maximum ``|tau|`` per
        DOF, control energy integral ``||tau|| dt``, integral absolute error
        per DOF. `after` defaults to :func:`metrics_start` (the one window
        ``neurov run``, ``neurov paper`` and the run plots use).

        ``window_start_s`` and ``window_end_s`` say what the numbers cover;
        ``refused_steps`` counts the refused controller steps of the whole
        run, ``refused_steps_in_window`` those in the window.
        A diverged run (``diverged`` true, ``diverged_at_s`` its last row)
        gets its metrics over what was simulated: from `after` if rows exist
        there, else over every row; non-finite values give inf."""
        window = MetricsWindow(self.scenario.duration, self.scenario.dt, after)
        window.add(self)
        return window.value()

    @property
    def first_refusal(self) -> str | None:
        """The first refused controller step, ``"t = 5 s, invalid_argument:
        step raised TypeError: ..."`` (a Python controller's message; a
        compiled controller's status only), or None if no step was refused."""
        errors = self.extra.get("controller_errors") or {}
        if errors:
            status, first = min(errors.items(), key=lambda kv: kv[1]["first_t"])
            return f"t = {first['first_t']:g} s, {status}: {first['first']}"
        # A streamed run's drawn rows are thinned: its first refused row is kept in extra.
        first = self.extra.get("first_refused")
        if first is None:
            bad = np.flatnonzero(self.controller_status)
            if not len(bad):
                return None
            first = (float(self.t[bad[0]]), int(self.controller_status[bad[0]]))
        return f"t = {first[0]:g} s, {_core.Status(first[1]).name}"

    def divergence_message(self) -> str:
        """One line saying when and how the run diverged ('' if it did not)."""
        if not self.diverged:
            return ""
        if not len(self.t):
            return "diverged before the first step"
        plant, ctrl = (_core.Status(int(a[-1])).name for a in (self.plant_status, self.controller_status))
        return (f"diverged at t = {self.t[-1]:g} s: plant status {plant}, controller status {ctrl}; "
                f"{len(self.t)} of {round(self.scenario.duration / self.scenario.dt) + 1} rows simulated")

    def columns(self) -> dict[str, Any]:
        """The run as flat named columns, the CSV's and :meth:`to_pandas`'s
        (see :mod:`neurov.results.columns`): ``t``, then ``eta_x`` ...
        ``eta_psi``, ``nu_u`` ..., ``tau_demanded_X`` ..., ``thrusts_0`` ...,
        ``theta_m`` ... (linear adaptive only), the statuses as
        :class:`neurov.Status` names and ``faults`` as its bits."""
        return table_columns({name: getattr(self, name) for name in SERIES})

    def to_pandas(self) -> Any:
        """The run as a tidy :class:`pandas.DataFrame`: one row per control
        step, indexed by time ``t`` [s], with the columns of
        :meth:`columns` (the CSV's header is ``t`` and these); the
        statuses are categorical (of every :class:`neurov.Status` name)."""
        import pandas as pd

        cols: dict[str, Any] = self.columns()
        t = cols.pop("t")
        for name in ("controller_status", "plant_status"):
            cols[name] = pd.Categorical(cols[name], categories=STATUS_NAMES)
        return pd.DataFrame(cols, index=pd.Index(t, name="t"))

    def to_parquet(self, path: str | Path) -> Path:
        """Writes :meth:`to_pandas` to a Parquet file (needs pyarrow,
        ``neurov[parquet]``); :func:`neurov.load_result` reads it back."""
        self.to_pandas().to_parquet(path)
        return Path(path)

    def to_csv(self, path: str | Path, quiet: bool = True) -> Path:
        """Writes every column of :meth:`columns` to a CSV file with a header
        row, each number as the shortest text that reads back to the same
        float64, in blocks (see :class:`neurov.results.export.CsvWriter`: pyarrow's
        C++ writer when installed, about four times faster); unless `quiet`,
        a progress bar."""
        cols = self.columns()
        with progress_bar(len(self.t), Path(path).name, unit="row", quiet=quiet) as bar, \
                CsvWriter(path, cols) as writer:
            writer.write(cols, progress=bar)
        return Path(path)

    def npz_arrays(self) -> dict[str, Any]:
        """What :meth:`to_npz` writes besides the series: the scenario's name,
        the controller and whether the run diverged."""
        return {"scenario": np.array(self.scenario.name), "controller": np.array(self.controller),
                "diverged": np.array(self.diverged)}

    def to_npz(self, path: str | Path, quiet: bool = True) -> Path:
        """Writes the arrays of :data:`SERIES` (and :meth:`npz_arrays`) to a
        compressed .npz, array by array (see :class:`neurov.results.export.NpzWriter`);
        unless `quiet`, a progress bar."""
        writer = NpzWriter(path)
        try:
            for name, value in self.npz_arrays().items():
                writer.set(name, value)
            writer.append({k: getattr(self, k) for k in SERIES})
        except BaseException:
            writer.discard()
            raise
        with progress_bar(writer.count, Path(path).name, unit="array", quiet=quiet) as bar:
            return writer.close(progress=bar)

    def to_mcap(self, path: str | Path) -> Path:
        """Writes this run as a ROS 2 recording (MCAP, for Foxglove,
        PlotJuggler, ``ros2 bag``; needs ``neurov[ros]``): odometry, desired
        pose, wrenches and /tf in the ENU/FLU frames of REP 103 (docs/recordings.md),
        and the whole run, which :func:`neurov.recording.mcap_reader.read_mcap`
        reads back; see :func:`neurov.recording.mcap_writer.write_mcap`."""
        return hooks.provided("write_mcap")(self, path)  # type: ignore[no-any-return]

    def to_time_response(self) -> Any:
        """This run as ``control.TimeResponseData`` (needs ``neurov[control]``);
        see :func:`neurov.control.to_time_response`."""
        return hooks.provided("to_time_response")(self)

    def view(self, *others: Result, **options: Any) -> Any:
        """The 3-D replay of this run, and of `others` on the same path to
        compare them (needs ``neurov[view]``: plotly): a
        :class:`neurov.replay.Replay`, which Jupyter shows inline and
        ``.write_html(path)`` writes as one file that opens offline.
        `options`: those of :func:`neurov.replay.replay` (``labels``,
        ``title``, ``max_frames``)."""
        return hooks.provided("replay")([self, *others], **options)

    def summary_json(self, after: float | None = None) -> str:
        return json.dumps({"scenario": self.scenario.name, "controller": self.controller,
                           **self.metrics(after)}, indent=2)
