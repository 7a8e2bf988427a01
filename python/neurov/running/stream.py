"""A run streamed chunk by chunk, as ``neurov run`` does it: the closed loop
hands its rows over in chunks (:func:`neurov._core.run_closed_loop_chunks`,
or :class:`neurov.Simulator` for a controller written in Python), and each
chunk is written to result.csv (or result.mcap) and result.npz, summed into the metrics and
thinned to the rows the figures draw, then dropped. A run of any length so
holds one chunk (about :data:`CHUNK_ROWS` rows) in memory, not its every row.
"""

from __future__ import annotations

import dataclasses
import time
from pathlib import Path
from typing import Any

import numpy as np

from neurov.results.decimation import PlotRows
from neurov.results.export import CsvWriter, NpzWriter
from neurov.results.metrics import MetricsWindow
from neurov.results.timeseries import SERIES, Result
from neurov.config.scenario import Scenario
from neurov.laws.registry import build_controller
from neurov import hooks
from neurov.progress import progress_bar
from neurov.running.closed_loop import run_loop
from neurov.running.folder import RunFolder, check_output_dir, write_metrics, writing
from neurov.running.plant import build_vehicle, simulation_config

__all__ = ["CHUNK_ROWS", "FILE_FORMATS", "StreamedRun", "stream_run"]

FILE_FORMATS = ("csv", "mcap")
"""What a streamed run writes its rows to besides result.npz: result.csv,
or result.mcap (a ROS 2 recording, :mod:`neurov.recording.mcap_writer`)."""

CHUNK_ROWS = 12_000
"""About this many rows per chunk (40 minutes at 5 Hz, some 7 MB): rounded to
a whole number of the plot buckets (see :class:`neurov.results.decimation.PlotRows`)."""


@dataclasses.dataclass
class StreamedRun:
    """What a streamed run leaves: `drawn`, the rows the figures draw (every
    row of a run of at most :data:`neurov.results.decimation.MAX_PLOT_ROWS` rows,
    else ``drawn.extra["plotted_rows_of"]`` holds the run's row count);
    `metrics`, :meth:`Result.metrics` of every row; `elevation`, the whole
    (t, wave_elevation) record when the scenario has waves (the realised
    spectrum needs it uniform); `sea`, whether the run met a current, waves
    or a payload change; `written`, the files written."""

    drawn: Result
    metrics: dict[str, Any]
    elevation: Result | None
    sea: bool
    written: list[Path]


class _Sinks:
    """Where each chunk goes."""

    def __init__(self, scenario: Scenario, label: str, out: Path | None, rows: int, thrusters: int,
                 quiet: bool, file_format: str = "csv") -> None:
        self.scenario, self.label, self.out, self.quiet = scenario, label, out, quiet
        self.metrics = MetricsWindow(scenario.duration, scenario.dt)
        self.plot_rows = PlotRows(rows, thrusters)
        self.csv: CsvWriter | None = None
        self.mcap: Any = None
        if out is not None and file_format == "mcap":
            with writing(out / "result.mcap"):  # the recording bridge's, lent through neurov.hooks
                self.mcap = hooks.provided("mcap_recorder")(out / "result.mcap", scenario, thrusters)
        self.npz = NpzWriter(out / "result.npz") if out is not None else None
        self.elevation: list[tuple[np.ndarray, np.ndarray]] | None = [] if scenario.waves is not None else None
        self.sea = False
        self.errors: dict[str, Any] = {}

    def add(self, raw: dict[str, Any]) -> int:
        diverged = bool(raw.pop("diverged"))
        chunk = Result(scenario=self.scenario, controller=self.label, diverged=diverged, **raw)
        self.metrics.add(chunk)
        self.plot_rows.add(chunk)
        self.sea = self.sea or chunk.met_sea
        if self.elevation is not None:
            self.elevation.append((chunk.t, chunk.wave_elevation))
        if self.out is not None and self.npz is not None:
            if self.mcap is not None:
                with writing(self.mcap.path):
                    self.mcap.add(chunk)
            else:
                cols = chunk.columns()
                with writing(self.out / "result.csv"):
                    if self.csv is None:
                        self.csv = CsvWriter(self.out / "result.csv", cols)
                    self.csv.write(cols)
            with writing(self.npz.path):
                self.npz.append({name: getattr(chunk, name) for name in SERIES})
        return len(chunk.t)

    def close(self, drawn: Result | None) -> list[Path]:
        """Closes the files; without `drawn` (the run failed) the CSV keeps
        the rows written (and the MCAP its messages) and the NPZ is not written."""
        written: list[Path] = []
        if self.csv is not None:
            with writing(self.csv.path):
                self.csv.close()
            written.append(self.csv.path)
        if self.npz is not None:
            if drawn is None:
                self.npz.discard()
                if self.mcap is not None:
                    with writing(self.mcap.path):
                        self.mcap.discard()
            else:
                for name, value in drawn.npz_arrays().items():
                    self.npz.set(name, value)
                with progress_bar(self.npz.count, "result.npz", unit="array", quiet=self.quiet) as bar, \
                        writing(self.npz.path):
                    written.append(self.npz.close(progress=bar))
                if self.mcap is not None:
                    metrics = {"scenario": self.scenario.name, "controller": self.label, **self.metrics.value()}
                    with writing(self.mcap.path):
                        written.insert(0, self.mcap.close(self.npz.path.read_bytes(), metrics, drawn))
        return written

    def partial_metrics(self) -> dict[str, Any]:
        """What metrics.json holds for a run that stopped: the metrics of the
        rows simulated (when they fill a window) and how far it got."""
        rows = self.metrics.rows
        metrics: dict[str, Any] = {"scenario": self.scenario.name, "controller": self.label,
                                   "rows_simulated": rows, "simulated_to_s": self.metrics.t_last}
        if self.csv is not None and self.csv.path.is_file():
            # Read back: a Ctrl-C right after a block is written comes before it is counted.
            metrics["rows_in_result_csv"], metrics["result_csv_to_s"] = _csv_extent(self.csv.path)
        try:
            metrics.update(self.metrics.value())
        except ValueError:
            pass  # too few rows for the window: the counts above say how far it got
        return metrics


def stream_run(scenario: Scenario, out_dir: str | Path | RunFolder | None = None, *, quiet: bool = True,
               chunk_rows: int = CHUNK_ROWS, file_format: str = "csv") -> StreamedRun:
    """Runs `scenario` with its controller, streaming the rows (see the
    module): with `out_dir` (created if missing; an existing file or a
    folder that cannot be written raises OSError before the run),
    result.csv (`file_format` "mcap": result.mcap, as
    :meth:`Result.to_mcap` writes it) and result.npz are written there as
    the run goes (the same files as :meth:`Result.to_csv` and
    :meth:`Result.to_npz` of the whole run). Unless `quiet`, a progress bar
    of the rows on a terminal. A run that diverges ends with the chunk where
    it did; an exception (e.g. Ctrl-C, a full disk) keeps the CSV rows
    written so far and a metrics.json of those rows, ``"partial": true``
    (result.npz is not written). `out_dir` may be a :class:`RunFolder`
    (``neurov run --out``), checked when it was made: the files go to its
    staging folder."""
    if not isinstance(chunk_rows, int) or chunk_rows < 1:
        raise ValueError(f"argument 'chunk_rows' must be an int >= 1, got {chunk_rows!r}")
    if file_format not in FILE_FORMATS:
        raise ValueError(f"argument 'file_format' must be one of {FILE_FORMATS}, got {file_format!r}")
    out = out_dir.path if isinstance(out_dir, RunFolder) else None if out_dir is None else check_output_dir(out_dir)
    config = simulation_config(scenario)
    rows = round(scenario.duration / scenario.dt) + 1
    thrusters = config.thrusters.matrix.shape[1] if config.use_thrusters else 0
    spec = scenario.controller
    plant = build_vehicle(scenario)
    controller = build_controller(spec, scenario)
    sinks = _Sinks(scenario, spec.name, out, rows, thrusters, quiet, file_format)
    chunk = sinks.plot_rows.chunk_rows(chunk_rows)
    with progress_bar(rows, "run", unit="row", quiet=quiet) as bar:

        def on_rows(raw: dict[str, Any]) -> None:
            bar.update(sinks.add(raw))

        start = time.perf_counter()
        try:
            stepped = run_loop(scenario, plant, controller, spec.name, on_rows=on_rows, chunk_rows=chunk)
            if stepped is not None:  # the Python loop: its controller's errors
                sinks.errors = stepped.extra.get("controller_errors", {})
        except BaseException:
            _keep_what_was_written(sinks, out)
            raise
        wall = time.perf_counter() - start
    drawn = sinks.plot_rows.result()
    drawn.wall_time = wall
    if sinks.errors:
        drawn.extra["controller_errors"] = sinks.errors
    if sinks.metrics.first_refused is not None:
        drawn.extra["first_refused"] = sinks.metrics.first_refused
    written = sinks.close(drawn)  # after the above: result.mcap holds the wall time and extra
    elevation = None
    if sinks.elevation is not None:
        t, surface = (np.concatenate(parts) for parts in zip(*sinks.elevation))
        elevation = dataclasses.replace(drawn, t=t, wave_elevation=surface)
    return StreamedRun(drawn=drawn, metrics=sinks.metrics.value(), elevation=elevation, sea=sinks.sea,
                       written=written)


def _keep_what_was_written(sinks: _Sinks, out: Path | None) -> None:
    """After an exception: the CSV closed with its rows, a partial
    metrics.json beside it; a second failure (the disk still full) loses
    only the mark, never the exception that stopped the run."""
    try:
        sinks.close(None)
    except OSError:
        pass
    if out is None or not sinks.metrics.rows:
        return  # nothing simulated: nothing to keep
    try:
        write_metrics({**sinks.partial_metrics(), "partial": True}, out)
    except OSError:
        pass


def _csv_extent(path: Path) -> tuple[int, float | None]:
    """The data rows of the CSV at `path` and the ``t`` of its last one."""
    rows, tail = -1, b""
    with path.open("rb") as f:
        while block := f.read(1 << 22):
            rows += block.count(b"\n")
            tail = (tail + block)[-4096:]
    lines = tail.rstrip(b"\n").split(b"\n")
    try:
        last_t = float(lines[-1].split(b",", 1)[0]) if rows > 0 else None
    except ValueError:
        last_t = None
    return max(rows, 0), last_t
