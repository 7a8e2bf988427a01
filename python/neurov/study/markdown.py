"""A study folder's tables as Markdown for a page: what ``neurov report``
prints. It reads the folder a study (or a tuning's verdict) wrote, runs
nothing, and refuses a folder whose runs are of another version of the
study, so that a table generated from committed data cannot outlive the
study file it came from.

Tables: ``medians`` (controllers by mean rank against the scenarios: each
cell the median of the ranking metric, with the 5th-95th percentile when
there is more than one plant, and the failure rate), ``overall`` (mean rank,
first places, mean failure rate), ``verdict`` (the verdict in words),
``league`` (the whole league.md), ``timing`` (how many runs, how long, on
what, from timing.json), ``versus`` (one controller against others on the
same plants, in the ranking metric and the first metric the study also
shows) and ``failed`` (the failed runs per scenario and controller, and how
far they ran away).
"""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pandas as pd

from neurov.results.metrics import metric_label
from neurov.study.reading import load_study, shipped_studies
from neurov.study.report import league_markdown
from neurov.study.spec import Study, StudyError, identity_differences
from neurov.study.tables import Summary, failed_runs, head_to_head, read_table, summarise
from neurov.study.verdict import vehicle_verdicts, verdict_lines
from neurov.units import label_for_people

__all__ = ["TABLES", "main_report", "medians_table", "overall_table", "read_study_folder"]

TABLES = ("medians", "overall", "verdict", "league", "timing", "versus", "failed")


def _runs_file(folder: Path) -> Path:
    for name in ("runs.csv", "runs.csv.gz", "runs.parquet"):
        if (folder / name).is_file():
            return folder / name
    raise StudyError(f"{folder}: no runs table (runs.csv, runs.csv.gz or runs.parquet); is it a study's folder?")


def read_study_folder(folder: str | Path, study: str | Path | Study | None = None) -> tuple[Study, pd.DataFrame]:
    """The study (`study`, else the shipped study of study.json's name, else
    its source file) and the runs table of a study folder. Raises
    :class:`StudyError` when the runs are of another version of the study
    (naming what differs) or a file is missing."""
    folder = Path(folder)
    try:
        meta = json.loads((folder / "study.json").read_text())
    except (OSError, json.JSONDecodeError) as e:
        raise StudyError(f"{folder}/study.json: not readable ({e}); is it a study's folder?") from None
    if study is None:
        study = meta.get("name") if meta.get("name") in shipped_studies() else meta.get("source", "")
    s = study if isinstance(study, Study) else load_study(study)
    old = meta.get("identity", {})
    diffs = [d for d in identity_differences(old, s.identity()) if not d.startswith("neurov version")]
    if diffs:
        raise StudyError(f"{folder}: its runs are of another version of study {s.name!r} (differs in "
                         f"{', '.join(diffs)}): run the study again into it (the command is in "
                         f"{folder}/README.md, or in study.json's source)")
    return s, read_table(_runs_file(folder))


def _cell(g: Summary, factor: float, spread: bool) -> str:
    def num(x: float) -> str:
        if math.isinf(x):
            return "inf"
        x *= factor
        if x != 0 and abs(x) < 0.01:
            return f"{x:.2g}"
        return f"{x:.3f}" if abs(x) < 1 else f"{x:.3g}" if abs(x) < 100 else f"{x:.0f}"

    text = f"**{num(g.median)}**" if g.rank == 1 else num(g.median)
    if spread:
        text += f" ({num(g.p5)}–{num(g.p95)})"
    if g.failure_rate > 0:
        text += f", fails {100 * g.failure_rate:.0f} %"
    return text


def _mean_ranks(study: Study, summ: list[Summary]) -> list[tuple[str, float, int, float]]:
    """(controller, mean rank, first places, mean failure rate), best first."""
    ranks: dict[str, list[int]] = {c: [] for c in study.controllers}
    fails: dict[str, list[float]] = {c: [] for c in study.controllers}
    for g in summ:
        ranks[g.controller].append(g.rank)
        fails[g.controller].append(g.failure_rate)
    rows = [(c, float(np.mean(ranks[c])), ranks[c].count(1), float(np.mean(fails[c])))
            for c in study.controllers if ranks[c]]
    return sorted(rows, key=lambda r: (r[1], study.controllers.index(r[0])))


def medians_table(study: Study, runs: pd.DataFrame) -> str:
    """Controllers (rows, by mean rank) against scenarios (columns): the
    median of the ranking metric, **bold** at rank 1, its 5th-95th
    percentile when there is more than one plant, the failure rate where
    not 0 %, and the mean rank."""
    summ = summarise(study, runs)
    label, factor = label_for_people(metric_label(study.ranking_metric))
    spread = study.samples > 1
    by = {(g.scenario, g.controller): g for g in summ}
    scenarios = [s.name for s in study.scenarios if any(g.scenario == s.name for g in summ)]
    what = (f"median {label} over {study.samples} plants (5th–95th percentile)" if spread
            else f"{label}, one run each")
    lines = [f"{what}; **bold**: rank 1; rows by mean rank", "",
             "| controller | " + " | ".join(scenarios) + " | mean rank |",
             "|---|" + "---|" * (len(scenarios) + 1)]
    n = len(_mean_ranks(study, summ))
    for c, mean_rank, _, _ in _mean_ranks(study, summ):
        cells = [_cell(by[(s, c)], factor, spread) if (s, c) in by else "" for s in scenarios]
        lines.append(f"| {study.label(c)} | " + " | ".join(cells) + f" | {mean_rank:.2f} of {n} |")
    return "\n".join(lines) + "\n"


def overall_table(study: Study, runs: pd.DataFrame) -> str:
    """Mean rank over the scenarios, first places and mean failure rate, per controller."""
    rows = _mean_ranks(study, summarise(study, runs))
    each = "one run each" if study.samples == 1 else f"{study.samples} plants each"
    lines = [f"over {len(study.scenarios)} scenarios, {each}", "",
             "| controller | mean rank | first places | mean failure rate |", "|---|---|---|---|"]
    lines += [f"| {study.label(c)} | {r:.2f} | {f} | {100 * fr:.0f} % |" for c, r, f, fr in rows]
    return "\n".join(lines) + "\n"


def versus_table(study: Study, runs: pd.DataFrame, controllers: list[str]) -> str:
    """The first of `controllers` against each of the others, per scenario,
    on the same plants and noise: for the ranking metric and the first metric
    the study also shows, the samples in which the first is lower ("k of n")
    and the median of first / other (a failed run counts as infinitely bad)."""
    if len(controllers) < 2:
        raise ValueError(f"--versus: expected a controller and at least one to compare it with, got {controllers}")
    unknown = [c for c in controllers if c not in study.controllers]
    if unknown:
        raise ValueError(f"--versus: {unknown[0]!r} is not a controller of study {study.name!r} "
                         f"(it has: {', '.join(study.controllers)})")
    a, others = controllers[0], controllers[1:]
    metrics = [study.ranking_metric, *study.also_show[:1]]
    names = [label_for_people(metric_label(m))[0] for m in metrics]
    lines = [f"{study.label(a)} against the others on the same plants: samples in which it has the lower "
             f"value, median of {study.label(a)} / other", "",
             "| scenario | " + " | ".join(f"vs. {study.label(b)}: {n}" for b in others for n in names) + " |",
             "|---|" + "---|" * (len(others) * len(metrics))]
    cells = {(b, m): {h["scenario"]: h for h in head_to_head(study, runs, a, b, m)} for b in others for m in metrics}
    for sc in study.scenarios:
        row = []
        for b in others:
            for m in metrics:
                h = cells[(b, m)].get(sc.name)
                row.append("" if h is None else f"{h['a_wins']} of {h['n']}, {h['median_ratio']:.2f}")
        lines.append(f"| {sc.name} | " + " | ".join(row) + " |")
    return "\n".join(lines) + "\n"


def failed_table(study: Study, runs: pd.DataFrame) -> str:
    """Per scenario and controller with a failed run: how many of its runs
    failed, how many of those diverged (stopped, no finite value), and the
    ranking metric over the failed runs that finished (median, largest)."""
    bad = runs[failed_runs(runs, study.failure).to_numpy()]
    label, factor = label_for_people(metric_label(study.ranking_metric))
    lines = [f"failed runs of {study.samples} per scenario and controller; {label} over the failed runs "
             "that did not diverge (median, largest)", "",
             "| scenario | controller | failed | diverged | median | largest |", "|---|---|---|---|---|---|"]
    for sc in study.scenarios:
        for c in study.controllers:
            these = bad[(bad["scenario"] == sc.name) & (bad["controller"] == c)]
            if these.empty:
                continue
            diverged = these["diverged"].astype(float) != 0.0 if "diverged" in these else pd.Series(False, these.index)
            values = these[study.ranking_metric].astype(float)[~diverged] * factor
            values = values[np.isfinite(values)]
            median, largest = (f"{values.median():.3g}", f"{values.max():.3g}") if len(values) else ("-", "-")
            lines.append(f"| {sc.name} | {study.label(c)} | {len(these)} of {study.samples} | {int(diverged.sum())} | "
                         f"{median} | {largest} |")
    if len(lines) == 4:
        lines.append("| (none) | | | | | |")
    return "\n".join(lines) + "\n"


def report(folder: str | Path, table: str = "league", study: str | Path | Study | None = None,
           versus: list[str] | None = None) -> str:
    """The Markdown `table` (one of :data:`TABLES`) of a study folder (the
    study given, or found as :func:`read_study_folder` finds it); `versus`,
    for the table ``versus``: the controller, then those it is compared with."""
    if table not in TABLES:
        raise ValueError(f"argument 'table' must be one of {list(TABLES)}, got {table!r}")
    s, runs = read_study_folder(folder, study)
    if table == "versus":
        return versus_table(s, runs, list(versus or []))
    if table == "medians":
        return medians_table(s, runs)
    if table == "overall":
        return overall_table(s, runs)
    if table == "verdict":
        return "\n".join(verdict_lines(vehicle_verdicts(s, runs))) + "\n"
    if table == "timing":
        return timing_sentence(s, runs, Path(folder))
    if table == "failed":
        return failed_table(s, runs)
    return league_markdown(s, runs)


def timing_sentence(study: Study, runs: pd.DataFrame, folder: Path) -> str:
    """How many runs the study has and what running them took (timing.json)."""
    n = len(runs)
    each = "1 plant" if study.samples == 1 else f"{study.samples} plants"
    text = (f"{study.name}: {len(study.scenarios)} scenarios x {len(study.controllers)} controllers x "
            f"{each} = {n} runs")
    try:
        t = json.loads((folder / "timing.json").read_text())
    except (OSError, json.JSONDecodeError):
        return text + ".\n"
    load = t.get("load_average_at_start_and_end") or [None, None]
    where = f"{t['workers']} {'local processes' if t.get('executor') == 'processes' else 'Dask workers'}"
    text += (f", run in {t['seconds']:.1f} s on {where} ({t.get('worker_cpu_seconds', math.nan):.1f} s of worker "
             f"CPU; load average {load[0]} at the start, {load[1]} at the end); "
             f"{t.get('figures_drawn', 0)} figures drawn in {t.get('plot_seconds', math.nan):.1f} s")
    return text + ".\n"


def main_report(folder: str, table: str, study: str | Path | Study | None = None,
                versus: list[str] | None = None) -> None:
    """What ``neurov report`` does for a study folder: print the table."""
    print(report(folder, table, study, versus), end="")
