"""Run one scenario file: what ``neurov run SCENARIO.toml [--out DIR] [--plot]`` does.

Loads the scenario, runs the closed loop streaming its rows (see
:mod:`neurov.running.stream`), prints the metrics, and optionally writes the
results to a folder::

    from neurov.running.command import run_scenario_file
    result, metrics = run_scenario_file("examples/scenarios/square_nn.toml", out_dir="out", plot=True)
"""

from __future__ import annotations

import math
import shutil
import sys
from pathlib import Path
from typing import Any, TextIO

from neurov.results.timeseries import Result
from neurov.running.stream import stream_run
from neurov.config.reading import load_scenario
from neurov.config.scenario import scenario_path
from neurov import hooks
from neurov.progress import progress_bar
from neurov.running.folder import RunFolder, stopping, write_metrics, writing

__all__ = ["EXIT_DIVERGED", "FIGURES", "OUTPUT_NAMES", "SEA_FIGURES", "format_metrics", "refusal_message",
           "run_scenario_file", "write_figures", "write_outputs"]

EXIT_DIVERGED = 3
"""Exit status of ``neurov run`` and ``neurov paper`` when a run diverged
(everything simulated is still written): 0 is success, 1 an error (bad
file, unwritable output), 2 a bad command line, 130 interrupted."""

FIGURES = ("xy.png", "dofs.png", "errors.png", "inputs.png", "adaptive_norm.png")
SEA_FIGURES = ("sea.png", "wave_spectrum.png")
"""Also written for a run with a sea: the flow it met (a current, waves or a
payload change) and, with waves, their realised spectrum against the target."""
OUTPUT_NAMES = ("result.csv", "result.mcap", "result.npz", "metrics.json", "scenario.toml", *FIGURES, *SEA_FIGURES)
"""The files a run writes in its folder (see :mod:`neurov.running.folder`);
scenario.toml is the scenario file run, copied as it was (written by
:func:`run_scenario_file`, so that :func:`neurov.load_result` finds it)."""


def format_metrics(result: Result, metrics: dict[str, Any]) -> str:
    """The short text table `run_scenario_file` prints."""
    s = result.scenario
    lines = [
        f"scenario {s.name!r}: {result.controller}, {s.duration:g} s at dt = {s.dt:g} s"
        + (" (diverged)" if result.diverged else ""),
    ]
    if result.diverged:
        lines.append(result.divergence_message())
    lines.append(f"metrics over {metrics['window_start_s']:g} s <= t <= {metrics['window_end_s']:g} s"
                 + (" (what was simulated before the divergence)" if result.diverged else
                    " (the start-up transient before is skipped)"))
    rmse, mx = metrics["rmse"], metrics["max_abs_error"]
    rows = [
        ("RMS position error", f"{metrics['rmse_position_m']:.4g} m"),
        ("max position error", f"{metrics['max_position_error_m']:.4g} m"),
        ("RMS yaw error", f"{math.degrees(metrics['rmse_yaw_rad']):.4g} deg"),
        ("max yaw error", f"{math.degrees(metrics['max_yaw_error_rad']):.4g} deg"),
        ("RMS error x, y, z", ", ".join(f"{rmse[k]:.3g}" for k in ("x", "y", "z")) + " m"),
        ("RMS error roll, pitch", ", ".join(f"{math.degrees(rmse[k]):.3g}" for k in ("roll", "pitch")) + " deg"),
        ("max |error| x, y, z", ", ".join(f"{mx[k]:.3g}" for k in ("x", "y", "z")) + " m"),
        ("mean |tau|, max |tau|", f"{metrics['mean_abs_tau']:.4g}, {metrics['max_abs_tau']:.4g} (N or N m)"),
        ("control energy", f"{metrics['control_energy']:.4g} (integral of ||tau|| dt)"),
        ("final adaptive norm", f"{metrics['final_adaptive_norm']:.4g} (max {metrics['max_adaptive_norm']:.4g})"),
        ("refused controller steps", f"{metrics['refused_steps']} ({metrics['refused_steps_in_window']} "
                                     "in the window)"),
    ]
    width = max(len(name) for name, _ in rows)
    lines += [f"  {name:<{width}}  {value}" for name, value in rows]
    if metrics["refused_steps"]:
        lines.append(f"warning: {refusal_message(result, metrics)}")
    return "\n".join(lines)


def refusal_message(result: Result, metrics: dict[str, Any]) -> str:
    """One line on a run's refused controller steps ('' if none)."""
    if not metrics["refused_steps"]:
        return ""
    rows = result.extra.get("plotted_rows_of", len(result.t))
    policy = getattr(result.scenario.refused_step_policy, "name", result.scenario.refused_step_policy)
    return (f"{metrics['refused_steps']} of {rows} controller steps were refused "
            f"({metrics['refused_steps_in_window']} in the metrics window), the first at "
            f"{result.first_refusal}; the run went on with refused_step_policy {policy!r}")


def write_figures(drawn: Result, out: Path, quiet: bool = True, *, sea: bool | None = None,
                  elevation: Result | None = None) -> list[Path]:
    """The figures of :data:`FIGURES` of the run `drawn` (and of
    :data:`SEA_FIGURES` if it met a sea: `sea`, default from its rows) into
    `out`; the wave spectrum from `elevation` (a Result whose ``t`` and
    ``wave_elevation`` are the whole record), default `drawn`. Unless
    `quiet`, a progress bar."""
    # The plotting layer draws them (neurov.plotting.run_figures, lent
    # through neurov.hooks): it sits above this one, and Matplotlib costs a
    # second to import, which a run without plots never pays.
    figures = hooks.provided("run_figures")(drawn, sea=sea, elevation=elevation)
    written = []
    with progress_bar(len(figures), "figures", unit="figure", quiet=quiet) as bar:
        for name, draw in figures.items():
            with writing(out / name):
                written.append(draw(out / name))
            bar.update(1)
    return written


def write_outputs(result: Result, metrics: dict[str, Any], out_dir: str | Path, plot: bool = False,
                  quiet: bool = True) -> list[Path]:
    """Writes result.csv, result.npz, metrics.json and, with `plot`, the
    figures of :data:`FIGURES` (and :data:`SEA_FIGURES`) of a run held in
    memory into `out_dir` (created if missing; a folder holds one run, see
    :mod:`neurov.running.folder`); returns the paths written.
    Unless `quiet`, progress bars (on a terminal). A long run's figures draw
    at most :data:`neurov.results.decimation.MAX_PLOT_ROWS` rows."""
    folder = RunFolder(out_dir, OUTPUT_NAMES)
    out = folder.path
    with stopping(folder):
        with writing(out / "result.csv"):
            written = [result.to_csv(out / "result.csv", quiet=quiet)]
        with writing(out / "result.npz"):
            written.append(result.to_npz(out / "result.npz", quiet=quiet))
        written.append(write_metrics(metrics, out))
        if plot:
            written += write_figures(result, out, quiet)
        done = folder.commit()
    return [done / p.name for p in written]


def run_scenario_file(path: str | Path, out_dir: str | Path | None = None,
                      plot: bool = False, file_format: str = "csv") -> tuple[Result, dict[str, Any]]:
    """Loads the scenario file at `path` (or the shipped scenario of that
    name, :func:`neurov.config.scenario.scenario_path`), simulates it, and prints a short
    metrics table to stdout. The metrics cover t >= :func:`neurov.results.timeseries.metrics_start`
    (10 s, or half a shorter run: the start-up transient is skipped) and the
    table says so.

    With `out_dir` (checked before the run: an existing file or a folder
    that cannot be written raises OSError), writes result.csv (`file_format`
    "mcap": result.mcap, a ROS 2 recording, see docs/recordings.md),
    result.npz, metrics.json and scenario.toml (a copy of the scenario file)
    there, and with `plot` also xy.png, dofs.png, errors.png,
    inputs.png and adaptive_norm.png (and, with a sea, sea.png and
    wave_spectrum.png). `plot` without `out_dir` raises
    ValueError.

    A run that diverges is not an error: the table says when and how, the
    files hold every row simulated, and the metrics cover those rows
    (``diverged`` true, ``diverged_at_s`` set); check ``result.diverged``.

    The run is streamed (:func:`neurov.running.stream.stream_run`): the files
    are written as the rows come and a run of any length holds about
    :data:`neurov.running.stream.CHUNK_ROWS` rows in memory. So the result
    returned holds the rows the figures draw: every row of a run of at most
    :data:`neurov.results.decimation.MAX_PLOT_ROWS` rows, else a thinned set
    (``result.extra["plotted_rows_of"]`` the run's row count; the metrics are
    always of every row).

    Returns the result and the metrics: ``Result.metrics()`` plus
    ``scenario`` and ``controller``, the same dict metrics.json holds (where
    non-finite numbers are written as null). A bad file raises
    :class:`neurov.config.scenario.ScenarioError` naming the file and the field."""
    if plot and out_dir is None:
        raise ValueError("argument 'plot' needs 'out_dir': the figures are written as PNG files there")
    if file_format != "csv" and out_dir is None:
        raise ValueError(f"argument 'file_format' {file_format!r} needs 'out_dir': the rows are written there")
    source = scenario_path(path)
    scenario = load_scenario(source)
    folder = RunFolder(out_dir, OUTPUT_NAMES) if out_dir is not None else None
    with stopping(folder):
        run = stream_run(scenario, folder, quiet=False, file_format=file_format)
        result = run.drawn
        metrics: dict[str, Any] = {"scenario": scenario.name, "controller": result.controller, **run.metrics,
                                   "first_refusal": result.first_refusal}
        if folder is not None:
            metrics["partial"] = False
        stream: TextIO = sys.stdout
        print(format_metrics(result, metrics), file=stream)
        if folder is not None:
            written = [*run.written, write_metrics(metrics, folder.path)]
            with writing(folder.path / "scenario.toml"):
                written.append(Path(shutil.copyfile(source, folder.path / "scenario.toml")))
            if plot:
                written += write_figures(result, folder.path, quiet=False, sea=run.sea, elevation=run.elevation)
            out = folder.commit()
            print(f"wrote {', '.join(p.name for p in written)} to {out}", file=stream)
    return result, metrics
