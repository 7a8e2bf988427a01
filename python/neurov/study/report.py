"""The league table (league.md): per scenario the controllers ranked by the
median of the ranking metric, the mean rank over all scenarios, and the
head-to-head comparisons a study asks for, in Markdown."""

from __future__ import annotations

import math

import numpy as np
import pandas as pd

from neurov.results.metrics import metric_label
from neurov.study.spec import NORMAL_TRUNCATION, Perturbation, Study
from neurov.study.tables import Rows, Summary, as_frame, head_to_head, summarise
from neurov.study.verdict import vehicle_verdicts, verdict_markdown
from neurov.units import label_for_people

__all__ = ["league_markdown"]


def _num(x: float, digits: int = 4) -> str:
    if math.isinf(x):
        return "inf"
    if math.isnan(x):
        return "-"
    return f"{x:.{digits}g}" if abs(x) < 1e4 else f"{x:.3e}"


def league_markdown(study: Study, runs: Rows) -> str:
    """The league table: per scenario, controllers ranked by the median of
    the ranking metric, then the mean rank over all scenarios and the
    head-to-head comparisons the study asks for."""
    rows = as_frame(runs)
    summ = summarise(study, rows)
    metric = study.ranking_metric
    bounds = ", ".join(f"{k} > {v:g}" for k, v in study.failure.items())
    lines = [
        f"# League table: {study.name}",
        "",
        study.description,
        "",
        *verdict_markdown(vehicle_verdicts(study, rows, summ)),
        f"{study.samples} sample(s) per scenario and controller, seed {study.seed}; metrics over "
        f"t >= {study.after:g} s. Ranked by the median of `{metric}` (lower is better). A run fails "
        f"if it diverges or a metric is not finite{'; or ' + bounds if bounds else ''}; a run that "
        f"raised or whose worker died is a failed run too (\"errors\"; a run whose worker died is "
        f"retried once, alone).",
        "",
    ]
    ref = study.reference_controller()
    ref_label = study.label(ref)
    if study.samples == 1:
        lines += [f"One plant per scenario: each row is one run (no spread, interval or test to give); ranked by "
                  f"its `{metric}`, with its ratio to {ref_label}'s on the same plant.", ""]
    else:
        lines += [f"Statistics per scenario: the median's distribution-free 95 % interval (order statistics); "
                  f"against {ref_label} on the same plants, the median of the paired ratios with its interval, the "
                  f"plants where the controller is better and the Wilcoxon signed-rank p-value, Holm-corrected "
                  f"over the table's comparisons. Controllers share a rank while the paired ratio's interval "
                  f"against the first of the rank above contains 1 (with fewer than 6 plants: ranked by the "
                  f"median). \"n/a\": too few plants for a 95 % interval.", ""]
    if study.perturbations:
        lines += ["Perturbed per sample: " + ", ".join(_describe_perturbation(p) for p in study.perturbations) + ".", ""]
    for s in study.scenarios:
        group = [g for g in summ if g.scenario == s.name]
        if not group:
            continue
        best = group[0].median
        lines += [f"## {s.name}", "", f"{s.description}", ""]
        if study.samples == 1:
            lines += _one_run_rows(study, group, ref, best)
            continue
        extra_head = "".join(f" median {_shown(k)[0]} |" for k in study.also_show)
        lines += [
                  f"| rank | controller | median {metric} | 5th-95th percentile | failure rate | errors | "
                  f"diverged | median / best |" + extra_head + f" 95 % CI of the median | paired ratio to {ref_label} "
                  f"[95 % CI] | better than {ref_label} | p (Wilcoxon, Holm) |",
                  "|---|---|---|---|---|---|---|---|" + "---|" * len(study.also_show) + "---|---|---|---|"]
        for g in group:
            ratio = g.median / best if best > 0 and math.isfinite(best) else float("nan")
            extra = "".join(f" {_num(g.also[k] * _shown(k)[1])} |" for k in study.also_show)
            lines.append(f"| {g.rank} | {g.label} | {_num(g.median)} | {_num(g.p5)} - {_num(g.p95)} | "
                         f"{100 * g.failure_rate:.0f} % | {g.errors} | {g.diverged} | {_num(ratio, 3)} |" + extra
                         + _statistics_cells(g, ref))
        lines.append("")
    ranks: dict[str, list[int]] = {c: [] for c in study.controllers}
    fails: dict[str, list[float]] = {c: [] for c in study.controllers}
    for g in summ:
        ranks[g.controller].append(g.rank)
        fails[g.controller].append(g.failure_rate)
    overall = sorted((c for c in study.controllers if ranks[c]),
                     key=lambda c: (float(np.mean(ranks[c])), study.controllers.index(c)))
    if len(study.scenarios) > 1 and overall:
        lines += ["## Over all scenarios", "",
                  "| controller | mean rank | first places | mean failure rate |", "|---|---|---|---|"]
        for c in overall:
            lines.append(f"| {study.label(c)} | {np.mean(ranks[c]):.2f} | {ranks[c].count(1)} | "
                         f"{100 * float(np.mean(fails[c])):.0f} % |")
        lines.append("")
    spread_head = " 5th-95th percentile of the ratio |" if study.samples > 1 else ""
    for a, b in study.head_to_head:
        la, lb = study.label(a), study.label(b)
        others = study.also_show
        lines += [f"## {la} against {lb}", "",
                  f"Same plants and noise per sample. \"better\": samples where {la} has the lower value; "
                  f"ratio: {la} / {lb} (a failed run counts as infinitely bad).", "",
                  f"| scenario | better in `{metric}` | median ratio |" + spread_head
                  + "".join(f" better in `{k}` | median ratio |" for k in others),
                  "|---|---|---|" + "---|" * bool(spread_head) + "---|---|" * len(others)]
        main = head_to_head(study, rows, a, b)
        extra = {k: {h["scenario"]: h for h in head_to_head(study, rows, a, b, k)} for k in others}
        for h in main:
            cells = "".join(f" {extra[k][h['scenario']]['a_wins']} of {h['n']} | "
                            f"{_num(extra[k][h['scenario']]['median_ratio'], 3)} |" for k in others)
            spread = f" {_num(h['p5_ratio'], 3)} - {_num(h['p95_ratio'], 3)} |" if spread_head else ""
            lines.append(f"| {h['scenario']} | {h['a_wins']} of {h['n']} | {_num(h['median_ratio'], 3)} |"
                         + spread + cells)
        lines.append("")
    lines += _errors_section(rows)
    return "\n".join(lines).rstrip() + "\n"


def _one_run_rows(study: Study, group: list[Summary], reference: str, best: float) -> list[str]:
    """A scenario's table when each controller ran once: the run's value,
    whether it failed (0 or 100 %), and plain ratios (to the best, to the
    reference)."""
    metric, ref_label = study.ranking_metric, study.label(reference)
    lines = [f"| rank | controller | {metric} | failure rate | errors | diverged | / best |"
             + "".join(f" {_shown(k)[0]} |" for k in study.also_show) + f" / {ref_label} |",
             "|---|---|---|---|---|---|---|" + "---|" * len(study.also_show) + "---|"]
    for g in group:
        ratio = g.median / best if best > 0 and math.isfinite(best) else float("nan")
        to_ref = "(reference)" if g.controller == reference else _na(g.ratio, 3) if g.pairs else "n/a"
        lines.append(f"| {g.rank} | {g.label} | {_num(g.median)} | {100 * g.failure_rate:.0f} % | "
                     f"{g.errors} | {g.diverged} | {_num(ratio, 3)} |"
                     + "".join(f" {_num(g.also[k] * _shown(k)[1])} |" for k in study.also_show) + f" {to_ref} |")
    return lines + [""]


def _shown(metric: str) -> tuple[str, float]:
    """A metric shown beside the ranking, as people read it (neurov.units:
    angles in degrees): its label and the factor on its values."""
    return label_for_people(metric_label(metric))


def _na(x: float, digits: int = 4) -> str:
    return "n/a" if math.isnan(x) else _num(x, digits)


def _statistics_cells(g: Summary, reference: str) -> str:
    ci = "n/a" if math.isnan(g.median_ci_low) else f"{_num(g.median_ci_low)} - {_num(g.median_ci_high)}"
    if g.controller == reference:
        return f" {ci} | (reference) | | |"
    interval = "" if math.isnan(g.ratio_ci_low) else f" [{_num(g.ratio_ci_low, 3)}, {_num(g.ratio_ci_high, 3)}]"
    ratio = "n/a" if not g.pairs else f"{_num(g.ratio, 3)}{interval}"
    better = f"{g.better} of {g.pairs}" if g.pairs else "n/a"
    return f" {ci} | {ratio} | {better} | {_na(g.p_value_holm, 3)} |"


#: Runs without a result listed in the league table; the rest are in the runs table.
LISTED_ERRORS = 20


def _errors_section(rows: pd.DataFrame) -> list[str]:
    """The runs that gave no result, with their errors: what a reader needs
    to tell a bad controller from a bad run."""
    if "error_kind" not in rows:
        return []
    bad = rows[rows["error_kind"].fillna("").astype(str) != ""]
    if bad.empty:
        return []
    lines = ["## Runs without a result", "",
             f"{len(bad)} run(s) raised or lost their worker process; each counts as failed (column `error` of "
             "the runs table, and the log `runs.jsonl`).", "",
             "| scenario | controller | sample | kind | error |", "|---|---|---|---|---|"]
    for r in bad.head(LISTED_ERRORS).itertuples():
        text = str(r.error).replace("|", "\\|").replace("\n", " ")
        lines.append(f"| {r.scenario} | {r.controller} | {r.sample} | {r.error_kind} | {text[:300]} |")
    if len(bad) > LISTED_ERRORS:
        lines.append(f"\nand {len(bad) - LISTED_ERRORS} more in the runs table.")
    return lines + [""]


def _describe_perturbation(p: Perturbation) -> str:
    if p.is_vehicle:
        spread = f"±{100 * p.relative:g} %" if p.distribution == "uniform" else \
            f"normal, sd {100 * p.relative:g} % (truncated at {NORMAL_TRUNCATION:g} sd)"
        each = " per element" if p.per_element and p.parameter not in ("mass", "weight", "buoyancy") else ""
        return f"{p.parameter} {spread}{each}"
    if p.distribution == "uniform":
        return f"{p.parameter} uniform {p.low:g}..{p.high:g}"
    return f"{p.parameter} normal mean {p.mean:g} sd {p.std:g}"
