"""The paper's experiments (Figs. 3-5), reproduced by ``neurov paper``.

The set-ups are the shipped scenario files ``scenarios/paper_fig3.toml`` and
``scenarios/paper_fig5.toml``; the controllers compared are listed in
:data:`EXPERIMENTS`. Every choice the paper leaves open is marked "ours" in
those files and discussed in docs/paper-reproduction.md.
"""

from __future__ import annotations

import copy
import json
import time
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from neurov.paper.figures import figure_inputs, figure_xy, figure_yaw
from neurov.running.folder import RunFolder, finite_or_none, stopping, writing
from neurov.results.timeseries import Result, TRANSIENT_S, metrics_start
from neurov.config.reading import load_scenario
from neurov.config.scenario import ControllerSpec, SCENARIO_DIR, Scenario
from neurov.running.simulation import simulate
from neurov.units import ANGLE_UNIT, DEGREES_PER_RADIAN
from neurov.progress import stage

__all__ = ["EXPERIMENTS", "METRIC_KEYS", "OUTPUT_NAMES", "Experiment", "diverged_runs", "fig5_caption", "paper_scenario",
           "paper_tables", "run_paper"]

#: The files ``neurov paper`` writes in its folder (see neurov.running.folder).
OUTPUT_NAMES = ("fig3_xy.png", "fig4_inputs.png", "fig5_yaw_disturbance.png", "metrics.json", "summary.md")
#: The keys every metrics.json entry carries (more follow them). The metrics
#: cover Result.metrics()'s window, t >= neurov.results.timeseries.metrics_start(duration).
METRIC_KEYS = ("rmse_position_m", "rmse_yaw_rad", "max_position_error_m", "mean_abs_tau", "max_abs_tau",
               "window_start_s", "diverged")


@dataclass(frozen=True)
class Experiment:
    key: str
    scenario: str  # scenario file stem in SCENARIO_DIR
    label: str
    controller: dict[str, Any] | None = None  # overrides of the file's [controller]; None keeps it


#: What ``neurov paper`` runs: the file's NN controller, the same with K_d = 0
#: (the paper: "only the neural network controller was used"), and for Fig. 5
#: the linearly parameterised adaptive controller with the same Lambda and
#: K_d, theta_hat(0) = 0 and Gamma = I (ours).
EXPERIMENTS: tuple[Experiment, ...] = (
    Experiment("fig3_nn", "paper_fig3", "NN adaptive"),
    Experiment("fig3_nn_kd0", "paper_fig3", "NN adaptive, K_d = 0", {"kd": np.zeros(6)}),
    Experiment("fig5_nn", "paper_fig5", "NN adaptive"),
    Experiment("fig5_linear", "paper_fig5", "linear adaptive",
               {"type": "linear", "gamma": 1.0, "theta0": "zero"}),
)


#: The Fig. 5 comparison repeated over disturbance amplitudes [N m] and
#: frequencies [Hz]: the paper gives neither, and the answer depends on both.
SWEEP_AMPLITUDES = (5.0, 10.0, 30.0)
SWEEP_FREQUENCIES = (0.01, 0.05, 0.2)


def paper_scenario(name: str) -> Scenario:
    """A shipped paper scenario by file stem (``"paper_fig3"``, ``"paper_fig5"``)."""
    return load_scenario(SCENARIO_DIR / f"{name}.toml")


def _spec(base: ControllerSpec, changes: dict[str, Any] | None, label: str) -> ControllerSpec:
    return base.replace(label=label, **(changes or {}))


def run_experiments() -> dict[str, Result]:
    results: dict[str, Result] = {}
    for e in EXPERIMENTS:
        scenario = paper_scenario(e.scenario)
        results[e.key] = simulate(scenario, _spec(scenario.controller, e.controller, e.label))
    return results


def run_disturbance_sweep() -> list[dict[str, Any]]:
    """The fig5 NN and linear controllers under each amplitude x frequency."""
    base = paper_scenario("paper_fig5")
    specs = {e.key: _spec(base.controller, e.controller, e.label) for e in EXPERIMENTS
             if e.scenario == "paper_fig5"}
    rows = []
    for amplitude in SWEEP_AMPLITUDES:
        for frequency in SWEEP_FREQUENCIES:
            d = copy.copy(base.disturbances[0])
            d.amplitude, d.frequency = amplitude, frequency
            scenario = base.replace(disturbances=[d])
            row: dict[str, Any] = {"amplitude_nm": amplitude, "frequency_hz": frequency}
            for key, spec in specs.items():
                m = simulate(scenario, spec).metrics()
                row[key] = {k: m[k] for k in METRIC_KEYS}
            rows.append(row)
    return rows


def _sweep_table(rows: list[dict[str, Any]]) -> str:
    lines = [f"| amplitude [N m] | frequency [Hz] | NN: RMS yaw [{ANGLE_UNIT}] | linear: RMS yaw [{ANGLE_UNIT}] | "
             "NN: RMS position [m] | linear: RMS position [m] | lower yaw error |",
             "|" + "---|" * 7]
    for r in rows:
        nn, lin = r["fig5_nn"], r["fig5_linear"]
        if nn["diverged"] or lin["diverged"]:
            better = "(diverged: " + ", ".join(k for k, m in (("NN", nn), ("linear", lin)) if m["diverged"]) + ")"
        else:
            better = "NN" if nn["rmse_yaw_rad"] < lin["rmse_yaw_rad"] else "linear"
        lines.append(f"| {r['amplitude_nm']:g} | {r['frequency_hz']:g} | {_deg(nn['rmse_yaw_rad']):.3f} | "
                     f"{_deg(lin['rmse_yaw_rad']):.3f} | {nn['rmse_position_m']:.4f} | "
                     f"{lin['rmse_position_m']:.4f} | {better} |")
    return "\n".join(lines)


def _deg(x: float) -> float:
    return x * DEGREES_PER_RADIAN


def fig5_caption(compared: list[tuple[str, dict[str, Any]]], after: float = TRANSIENT_S,
                 degrees: bool = False) -> str:
    """Which controller has the lower RMS yaw and position error in the case
    Fig. 5 shows, from `compared`: (controller label, its metrics over
    t >= `after`) for each controller drawn; the yaw error in degrees with
    `degrees` (as ``neurov paper`` draws it), else in radians."""
    if len(compared) < 2:
        raise ValueError(f"argument 'compared' must hold at least two controllers, got {len(compared)}")
    parts = []
    yaw_unit, yaw_factor = ("deg", DEGREES_PER_RADIAN) if degrees else ("rad", 1.0)
    for key, what, unit, factor in (("rmse_yaw_rad", "yaw", yaw_unit, yaw_factor),
                                    ("rmse_position_m", "position", "m", 1.0)):
        values = [(float(m[key]) * factor, label) for label, m in compared]
        low = min(v for v, _ in values)
        best = [label for v, label in values if v == low]
        verdict = f"{best[0]} lower" if len(best) == 1 else "equal"
        listed = ", ".join(f"{label} {v:.3g} {unit}" for v, label in values)
        parts.append(f"RMS {what} error {listed} ({verdict})")
    return f"Over t >= {after:g} s: " + "; ".join(parts) + "."


# --- the command -----------------------------------------------------------------


def _table(rows: list[tuple[str, str, dict[str, Any]]]) -> str:
    head = (f"| experiment | controller | RMS position [m] | RMS yaw [{ANGLE_UNIT}] | max position error [m] | "
            "mean abs tau [N, N m] | max abs tau [N, N m] |")
    lines = [head, "|" + "---|" * 7]
    for key, ctrl, m in rows:
        lines.append(
            f"| {key} | {ctrl} | {m['rmse_position_m']:.4f} | {_deg(m['rmse_yaw_rad']):.3f} | "
            f"{m['max_position_error_m']:.4f} | {m['mean_abs_tau']:.2f} | {m['max_abs_tau']:.2f} |"
        )
    return "\n".join(lines)


def paper_tables() -> tuple[str, str]:
    """The two Markdown tables ``neurov paper`` prints (the experiments'
    metrics, and Fig. 5 over the disturbance's amplitude and frequency),
    from the runs alone: no figure, no file."""
    results = run_experiments()
    rows = [(e.key, results[e.key].controller, results[e.key].metrics()) for e in EXPERIMENTS]
    return _table(rows), _sweep_table(run_disturbance_sweep())


def diverged_runs(metrics: dict[str, Any]) -> list[str]:
    """The experiments (``fig3_nn``, ...) and sweep cases (``fig5_sweep[10 N m, 0.05 Hz].fig5_nn``)
    of `run_paper`'s metrics that diverged."""
    bad = [key for key, m in metrics.items() if isinstance(m, dict) and m.get("diverged")]
    for row in metrics.get("fig5_sweep", []):
        bad += [f"fig5_sweep[{row['amplitude_nm']:g} N m, {row['frequency_hz']:g} Hz].{key}"
                for key, m in row.items() if isinstance(m, dict) and m.get("diverged")]
    return bad


def run_paper(out_dir: str | Path = "paper-results", quiet: bool = False) -> dict[str, Any]:
    """Runs every experiment, writes fig3_xy.png, fig4_inputs.png,
    fig5_yaw_disturbance.png, metrics.json and summary.md into `out_dir`
    (checked first: an existing file or an unwritable folder raises OSError
    before anything runs), prints the metrics table, and returns the metrics
    (those of metrics.json: one entry per experiment and ``fig5_sweep``). A
    diverged run is written like the others, flagged ``diverged``: see
    :func:`diverged_runs`."""
    folder = RunFolder(out_dir, OUTPUT_NAMES)
    with stopping(folder):
        metrics = _run_into(folder.path, quiet)
        done = folder.commit()
    if not quiet:
        print(f"wrote {', '.join(OUTPUT_NAMES)} to {done}/")
    return metrics


def _run_into(out: Path, quiet: bool) -> dict[str, Any]:
    """What :func:`run_paper` does, writing into the staging folder `out`."""
    start = time.perf_counter()
    stage(f"paper: {len(EXPERIMENTS)} experiments and the Fig. 5 sweep "
          f"({len(SWEEP_AMPLITUDES) * len(SWEEP_FREQUENCIES)} cases x 2 controllers)", quiet)
    results = run_experiments()
    sweep = run_disturbance_sweep()
    sim_time = time.perf_counter() - start

    metrics: dict[str, Any] = {}
    rows = []
    for e in EXPERIMENTS:
        r = results[e.key]
        m = r.metrics()
        metrics[e.key] = {"scenario": e.scenario, "controller": r.controller, **m}
        rows.append((e.key, r.controller, m))
    caption5 = fig5_caption([(results[k].controller, metrics[k]) for k in ("fig5_nn", "fig5_linear")],
                            after=metrics_start(results["fig5_nn"].scenario.duration), degrees=True)

    figures = {
        "fig3_xy.png": lambda: figure_xy([results["fig3_nn"], results["fig3_nn_kd0"]],
                                         "Fig. 3: X-Y trajectory, NEROV, NN adaptive controller"),
        "fig4_inputs.png": lambda: figure_inputs(results["fig3_nn"]),
        "fig5_yaw_disturbance.png": lambda: figure_yaw([results["fig5_nn"], results["fig5_linear"]], caption5),
    }
    stage(f"paper: drawing {len(figures)} figures", quiet)
    for name, draw in figures.items():
        fig = draw()
        with writing(out / name):
            fig.savefig(out / name, dpi=120)
    table = _table(rows)
    sweep_table = _sweep_table(sweep)
    metrics["fig5_sweep"] = sweep
    with writing(out / "metrics.json"):
        (out / "metrics.json").write_text(json.dumps(finite_or_none(metrics), indent=2) + "\n")
    starts = sorted({m["window_start_s"] for m in metrics.values() if isinstance(m, dict)}
                    | {m["window_start_s"] for row in sweep for m in row.values() if isinstance(m, dict)})
    window = " and ".join(f"{t:g}" for t in starts)
    total = time.perf_counter() - start
    with writing(out / "summary.md"):
        _write_summary(out / "summary.md", window, table, caption5, sweep_table, len(results) + 2 * len(sweep),
                       sim_time, total)
    if not quiet:
        print(f"metrics over t >= {window} s (the start-up transient skipped)")
        print(table)
        print("\nFig. 5 comparison over disturbance amplitude and frequency:\n")
        print(sweep_table)
        print(f"\nran in {total:.2f} s")
    return metrics


def _write_summary(path: Path, window: str, table: str, caption5: str, sweep_table: str, runs: int,
                   sim_time: float, total: float) -> None:
    path.write_text(
        "# neurov paper: results\n\n"
        f"Metrics over t >= {window} s (the start-up transient skipped; "
        f"neurov.results.timeseries.metrics_start). Set-ups: scenarios/paper_fig3.toml and "
        "scenarios/paper_fig5.toml in the neurov package; the choices the paper leaves open "
        "are discussed in docs/paper-reproduction.md.\n\n"
        f"{table}\n\n"
        f"Fig. 5, the case shown. {caption5}\n\n"
        "## Fig. 5 over disturbance amplitude and frequency\n\n"
        "The paper gives neither; the same two controllers on the same path:\n\n"
        f"{sweep_table}\n\n"
        f"Ran {runs} closed loops in {sim_time:.3f} s; the whole command took {total:.2f} s.\n"
    )
