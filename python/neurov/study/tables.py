"""The study's tables as :class:`pandas.DataFrame`: the runs table (one row
per run; CSV or Parquet), its statistics and the summary per scenario and
controller."""

from __future__ import annotations

import math
import os
from collections.abc import Iterable, Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd

from neurov.study.log import Record
from neurov.study.spec import Study, StudyError
from neurov.study.statistics import holm, median_ci, paired_ranks, paired_ratio, ratio, wilcoxon_p

__all__ = ["Summary", "failed", "failed_runs", "failure_counts", "head_to_head", "percentile", "read_table", "runs_table",
           "summarise", "summary_table", "write_table"]

Rows = pd.DataFrame | Iterable[Mapping[str, Any]]
"""A runs table, or its rows as mappings (column -> value)."""


def as_frame(runs: Rows) -> pd.DataFrame:
    return runs if isinstance(runs, pd.DataFrame) else pd.DataFrame([dict(r) for r in runs])


def write_table(table: Rows, path: Path) -> Path:
    """Writes a table as CSV (floats as Python writes them, the shortest text
    that reads back exactly; ``nan`` and ``inf`` spelt so), or as Parquet
    when `path` ends in .parquet (needs pyarrow). Replaced atomically."""
    frame = as_frame(table)
    tmp = path.with_name(path.name + ".tmp")
    if path.suffix == ".parquet":
        try:
            import pyarrow  # noqa: F401
        except ImportError:
            raise StudyError("writing Parquet needs pyarrow (pip install pyarrow); use --format csv") from None
        frame.to_parquet(tmp, index=False)
    else:
        frame.to_csv(tmp, index=False, lineterminator="\n", na_rep="nan")
    os.replace(tmp, path)
    return path


def read_table(path: str | Path) -> pd.DataFrame:
    """A table written by :func:`write_table`, numbers as numbers."""
    path = Path(path)
    if path.suffix == ".parquet":
        return pd.read_parquet(path)
    return pd.read_csv(path)


def runs_table(study: Study, records: Mapping[tuple[str, str, int], Record]) -> pd.DataFrame:
    """The runs table from the records of this study, in the study's order
    (scenario, controller, sample), each run judged by the study's failure
    bounds (here, not in the worker: changing a bound needs no rerun). When
    a run gave no result (it raised, or its worker died), the table has two
    more columns, last: ``error_kind`` (``error`` or ``crash``, empty for
    the runs that ran) and ``error`` (the error's type and message); a
    study whose runs all ran has the columns it always had."""
    order = [(s.name, c, k) for s in study.scenarios for c in study.controllers for k in range(study.samples)]
    rows: list[dict[str, Any]] = []
    columns: dict[str, None] = {}
    errors = False
    for key in order:
        rec = records.get(key)
        if rec is None:
            continue
        r = rec["row"]
        row = {k: r[k] for k in ("scenario", "vehicle", "controller", "sample")}
        row["failed"] = 0
        row.update((k, v) for k, v in r.items() if k not in row)
        err = rec.get("error")
        if err:
            errors = True
            row["error_kind"], row["error"] = err["kind"], f"{err['type']}: {err['message']}"
        elif not columns:
            # The columns in a run's order: a run that raised may lack its plant's draws.
            columns = dict.fromkeys(row)
        rows.append(row)
    for row in rows:
        columns.update(dict.fromkeys(k for k in row if k not in ("error_kind", "error")))
    if errors:
        columns.update({"error_kind": None, "error": None})
    table = pd.DataFrame(rows, columns=list(columns) or None)
    if len(table):
        table["failed"] = failed_runs(table, study.failure).astype(np.int64)
    return table


def failure_counts(table: pd.DataFrame) -> tuple[pd.Series, pd.Series]:
    """Per run, whether it gave no result (raised, or its worker died) and
    whether it diverged: the two kinds of failure the tables count apart
    from the failures by a bound."""
    error = table["error_kind"].fillna("").astype(str) != "" if "error_kind" in table else \
        pd.Series(False, index=table.index)
    diverged = table["diverged"].astype(np.float64) > 0 if "diverged" in table else \
        pd.Series(False, index=table.index)
    return error, diverged


def percentile(values: Iterable[float], q: float) -> float:
    """The q-th percentile (linear interpolation) where a value that is not
    finite ranks above every number: between a number and a failed run the
    answer is inf, not the nan plain interpolation would give."""
    v = pd.Series(list(values), dtype=np.float64)
    if v.empty:
        return float("nan")
    finite = np.isfinite(v)
    if math.isinf(v.where(finite, np.inf).quantile(q / 100.0, interpolation="higher")):
        return float("inf")
    # The percentile lies between two finite values; a failed run above them
    # enters the interpolation only with weight 0, so it may stand in as the
    # largest finite value (inf times 0 would give nan).
    return float(v.where(finite, v[finite].max()).quantile(q / 100.0, interpolation="linear"))


def failed_runs(table: pd.DataFrame, thresholds: Mapping[str, float]) -> pd.Series:
    """Per run, whether it failed: it diverged, a judged metric is not
    finite, or a metric is above its stated bound."""
    bad = pd.Series(False, index=table.index)
    if "diverged" in table:
        bad |= table["diverged"].astype(np.float64) != 0.0
    for k in ("rmse_position_m", "rmse_yaw_rad", *thresholds):
        bad |= ~np.isfinite(table[k].astype(np.float64))
    for k, bound in thresholds.items():
        bad |= table[k].astype(np.float64) > bound
    return bad


def failed(row: Mapping[str, Any], thresholds: Mapping[str, float]) -> bool:
    """:func:`failed_runs` for one run's row."""
    return bool(failed_runs(pd.DataFrame([dict(row)]), thresholds).iloc[0])


@dataclass
class Summary:
    scenario: str
    controller: str
    label: str
    n: int
    median: float
    p5: float
    p95: float
    failure_rate: float
    rank: int = 0
    also: dict[str, float] = field(default_factory=dict)
    """Medians of the study's also_show metrics."""
    # The verdict's statistics (neurov.study.statistics); nan where they
    # cannot be computed (one plant, or too few for a 95 % interval).
    median_ci_low: float = math.nan
    median_ci_high: float = math.nan
    ratio: float = math.nan
    """Median over paired plants of this controller's metric / the reference's."""
    ratio_ci_low: float = math.nan
    ratio_ci_high: float = math.nan
    better: int = 0
    """Plants where this controller's metric is below the reference's."""
    pairs: int = 0
    p_value: float = math.nan
    p_value_holm: float = math.nan
    errors: int = 0
    """Runs that gave no result: they raised, or their worker died."""
    diverged: int = 0


def summarise(study: Study, runs: Rows) -> list[Summary]:
    """Per scenario and controller: median and 5th/95th percentile of the
    ranking metric and the failure rate; ranked per scenario by the median
    (then failure rate, then 95th percentile)."""
    table = as_frame(runs)
    metric = study.ranking_metric
    out: list[Summary] = []
    if table.empty:
        return out
    error, diverged = failure_counts(table)
    table = table.assign(_failed=failed_runs(table, study.failure), _error=error, _diverged=diverged)
    groups = dict(iter(table.groupby(["scenario", "controller"], sort=False)))
    for s in study.scenarios:
        group = []
        for c in study.controllers:
            g = groups.get((s.name, c))
            if g is None:
                continue
            m = g[metric]
            group.append(Summary(
                scenario=s.name, controller=c, label=study.label(c), n=len(g),
                median=percentile(m, 50), p5=percentile(m, 5), p95=percentile(m, 95),
                failure_rate=int(g["_failed"].sum()) / len(g),
                also={k: percentile(g[k], 50) for k in study.also_show},
                errors=int(g["_error"].sum()), diverged=int(g["_diverged"].sum()),
            ))
        group.sort(key=lambda g: (g.median, g.failure_rate, g.p95, study.controllers.index(g.controller)))
        samples = {g.controller: dict(zip(groups[(s.name, g.controller)]["sample"].astype(int),
                                          groups[(s.name, g.controller)][metric].astype(float)))
                   for g in group}
        ranks = _verdict_statistics(study, group, samples)
        for i, g in enumerate(group):
            g.rank = ranks[i] if ranks else i + 1
        out += group
    p_holm = holm([g.p_value for g in out])
    for g, p in zip(out, p_holm):
        g.p_value_holm = p
    return out


def _verdict_statistics(study: Study, group: list[Summary], samples: dict[str, dict[int, float]]) -> list[int] | None:
    """Fills the statistics of one scenario's summaries; returns the ranks
    from the paired comparisons (None: too few plants, rank by the median)."""
    ref = study.reference_controller()
    for g in group:
        g.median_ci_low, g.median_ci_high = median_ci(list(samples[g.controller].values()))
        if ref in samples and g.controller != ref:
            common = sorted(set(samples[g.controller]) & set(samples[ref]))
            a = [samples[g.controller][k] for k in common]
            b = [samples[ref][k] for k in common]
            g.ratio, g.ratio_ci_low, g.ratio_ci_high, g.better = paired_ratio(a, b)
            g.pairs = len(common)
            g.p_value = wilcoxon_p(a, b)
    return paired_ranks([g.controller for g in group], samples)


def _or_na(x: float) -> float | str:
    return "n/a" if math.isnan(x) else x


def summary_table(study: Study, runs: Rows) -> pd.DataFrame:
    """:func:`summarise` as a table (summary.csv); a statistic that cannot be
    computed (one plant per scenario, too few for a 95 % interval, the
    reference against itself) says "n/a"."""
    ref = study.reference_controller()
    return pd.DataFrame([
        {"scenario": g.scenario, "controller": g.controller, "rank": g.rank, "n": g.n,
         "metric": study.ranking_metric, "median": g.median, "p5": g.p5, "p95": g.p95,
         "failure_rate": g.failure_rate, "failed_error": g.errors, "failed_diverged": g.diverged,
         **{f"median_{k}": v for k, v in g.also.items()},
         "median_ci_low": _or_na(g.median_ci_low), "median_ci_high": _or_na(g.median_ci_high),
         "reference": ref, "ratio_to_reference": _or_na(g.ratio), "ratio_ci_low": _or_na(g.ratio_ci_low),
         "ratio_ci_high": _or_na(g.ratio_ci_high),
         "better_than_reference": g.better if g.pairs else "n/a", "p_value": _or_na(g.p_value),
         "p_value_holm": _or_na(g.p_value_holm)}
        for g in summarise(study, runs)])


def head_to_head(study: Study, runs: Rows, a: str, b: str, metric: str | None = None) -> list[dict[str, Any]]:
    """Per scenario, A against B on the same plants (same sample): the share
    of samples where A's metric (the ranking metric unless given) is lower,
    and the median of A / B."""
    metric = metric or study.ranking_metric
    table = as_frame(runs)
    by = {(s, c, int(k)): float(v) for s, c, k, v in
          zip(table["scenario"], table["controller"], table["sample"], table[metric])}
    out = []
    for s in study.scenarios:
        pairs = [(by[(s.name, a, k)], by[(s.name, b, k)]) for k in range(study.samples)
                 if (s.name, a, k) in by and (s.name, b, k) in by]
        if not pairs:
            continue
        ratios = [ratio(x, y) for x, y in pairs]
        wins = sum(r < 1 for r in ratios)
        out.append({"scenario": s.name, "n": len(pairs), "a_wins": wins,
                    "median_ratio": percentile(ratios, 50), "p5_ratio": percentile(ratios, 5),
                    "p95_ratio": percentile(ratios, 95)})
    return out
