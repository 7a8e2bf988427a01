"""Run one scenario file: what ``neurov run SCENARIO.toml [--out DIR] [--plot]`` does.

Loads the scenario, runs the closed loop, prints the metrics, and optionally
writes the results to a folder::

    from neurov.run import run_scenario_file
    result, metrics = run_scenario_file("examples/scenarios/square_nn.toml", out_dir="out", plot=True)
"""

from __future__ import annotations

import json
import math
import sys
from pathlib import Path
from typing import Any, TextIO

from neurov.scenario import load_scenario
from neurov.simulation import Result, simulate

__all__ = ["FIGURES", "TRANSIENT_FRACTION", "format_metrics", "run_scenario_file", "write_outputs"]

TRANSIENT_FRACTION = 0.1
"""Metrics skip this fraction of the run's duration: the start-up transient
(weights from zero, the reference model catching up) would otherwise dominate
the tracking errors of a short run."""

FIGURES = ("xy.png", "dofs.png", "errors.png", "inputs.png", "adaptive_norm.png")


def _finite_or_none(value: Any) -> Any:
    """JSON has no inf or NaN (a diverged run has inf errors): write null."""
    if isinstance(value, float) and not math.isfinite(value):
        return None
    if isinstance(value, dict):
        return {k: _finite_or_none(v) for k, v in value.items()}
    if isinstance(value, list):
        return [_finite_or_none(v) for v in value]
    return value


def format_metrics(result: Result, metrics: dict[str, Any]) -> str:
    """The short text table `run_scenario_file` prints."""
    s = result.scenario
    after = metrics["transient_s"]
    lines = [
        f"scenario {s.name!r}: {result.controller}, {s.duration:g} s at dt = {s.dt:g} s"
        + (" (diverged)" if result.diverged else ""),
        f"metrics over t >= {after:g} s (the first {TRANSIENT_FRACTION:.0%} of the duration is "
        "skipped as the start-up transient)",
    ]
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
        ("refused controller steps", f"{metrics['refused_steps']}"),
    ]
    width = max(len(name) for name, _ in rows)
    lines += [f"  {name:<{width}}  {value}" for name, value in rows]
    return "\n".join(lines)


def write_outputs(result: Result, metrics: dict[str, Any], out_dir: str | Path, plot: bool = False) -> list[Path]:
    """Writes result.csv, result.npz, metrics.json and, with `plot`, the
    figures of :data:`FIGURES` into `out_dir` (created if missing); returns
    the paths written."""
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    written = [result.to_csv(out / "result.csv"), result.to_npz(out / "result.npz")]
    metrics_path = out / "metrics.json"
    metrics_path.write_text(json.dumps(_finite_or_none(metrics), indent=2) + "\n", encoding="utf-8")
    written.append(metrics_path)
    if plot:
        # Imported here: matplotlib costs a second to import and a run without
        # plots does not need it.
        from neurov.plotting import runs as plots

        figures = {
            "xy.png": plots.xy_path(result),
            "dofs.png": plots.dof_time(result),
            "errors.png": plots.errors(result),
            "inputs.png": plots.control_inputs(result),
            "adaptive_norm.png": plots.adaptive_norm(result),
        }
        written += [plots.save(fig, out / name) for name, fig in figures.items()]
    return written


def run_scenario_file(path: str | Path, out_dir: str | Path | None = None,
                      plot: bool = False) -> tuple[Result, dict[str, Any]]:
    """Loads the scenario file at `path`, simulates it, and prints a short
    metrics table to stdout. The metrics skip the first 10 % of the duration
    (the start-up transient) and the table says so.

    With `out_dir`, writes result.csv, result.npz and metrics.json there, and
    with `plot` also xy.png, dofs.png, errors.png, inputs.png and
    adaptive_norm.png. `plot` without `out_dir` raises ValueError.

    Returns the result and the metrics: ``Result.metrics(after)`` plus
    ``scenario``, ``controller`` and ``transient_s`` (= after), the same dict
    metrics.json holds (where non-finite numbers are written as null). A bad
    file raises :class:`neurov.scenario.ScenarioError` naming the file and
    the field."""
    if plot and out_dir is None:
        raise ValueError("argument 'plot' needs 'out_dir': the figures are written as PNG files there")
    scenario = load_scenario(path)
    result = simulate(scenario)
    after = TRANSIENT_FRACTION * scenario.duration
    metrics: dict[str, Any] = {
        "scenario": scenario.name,
        "controller": result.controller,
        "transient_s": after,
        **result.metrics(after=after),
    }
    stream: TextIO = sys.stdout
    print(format_metrics(result, metrics), file=stream)
    if out_dir is not None:
        written = write_outputs(result, metrics, out_dir, plot=plot)
        print(f"wrote {', '.join(p.name for p in written)} to {Path(out_dir)}", file=stream)
    return result, metrics
