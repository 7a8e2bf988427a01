"""The verdict in words: per vehicle, which controller is first, by how much
and how sure, at what effort, and where the ranking is a tie. What
``neurov study`` and ``neurov tune`` print last and ``league.md`` opens with.

Two steps, so that a caller can add to the data before it is written:
:func:`vehicle_verdicts` computes the statistics (from the runs table and the
league's ranks, with the paired ratios, intervals and Wilcoxon tests of
:mod:`neurov.study.statistics`), :func:`verdict_lines` writes them. A
:class:`VehicleVerdict` is plain data: another comparison (say, at equal
effort) is added as its ``notes`` and printed under the vehicle's lines.

Pooled over a vehicle's scenarios: the leader is the controller of lowest
mean rank over the vehicle's scenarios (the league's ranks); "by how much" is
the median, over every (scenario, plant) both ran, of the leader's ranking
metric divided by the other controller's, with its distribution-free 95 %
interval; "how sure" is that interval and the Wilcoxon signed-rank p-value,
Holm-corrected over all the verdict's comparisons; a controller whose
interval against the leader contains 1 is tied with it.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field, replace

import numpy as np
import pandas as pd

from neurov.results.metrics import metric_label
from neurov.study.spec import Study, vehicle_key
from neurov.study.statistics import LEVEL, holm, paired_ratio, wilcoxon_p
from neurov.study.tables import Summary, as_frame, summarise
from neurov.units import label_for_people

__all__ = ["EFFORT_METRIC", "Paired", "Standing", "VehicleVerdict", "vehicle_verdicts", "verdict_lines",
           "verdict_markdown", "verdict_text"]

#: The effort a verdict states beside the ranking metric (when the runs table has it).
EFFORT_METRIC = "mean_abs_tau"


@dataclass(frozen=True)
class Paired:
    """The leader against one controller on the same plants: the median of
    leader / other with its interval, the plants where the leader is lower,
    and the Wilcoxon p-value (Holm-corrected over the verdict)."""

    ratio: float
    low: float
    high: float
    better: int
    pairs: int
    p_holm: float = math.nan

    @property
    def has_interval(self) -> bool:
        return not math.isnan(self.low)

    @property
    def tie(self) -> bool:
        """The interval contains 1: the plants cannot tell the two apart."""
        return self.has_interval and self.low <= 1.0 <= self.high


@dataclass(frozen=True)
class Standing:
    """One controller over one vehicle's scenarios."""

    controller: str
    label: str
    mean_rank: float
    firsts: int
    scenarios: int
    failure_rate: float
    median: float
    """The median of the ranking metric over the vehicle's runs (SI)."""
    effort: float = math.nan
    """The median of the effort metric over the vehicle's runs."""


@dataclass(frozen=True)
class VehicleVerdict:
    vehicle: str
    metric: str
    standings: tuple[Standing, ...]
    """Best first."""
    samples: int
    """Plants per scenario."""
    against: Mapping[str, Paired] = field(default_factory=dict)
    """Controller -> the leader against it on the ranking metric."""
    effort_metric: str | None = None
    effort: Mapping[str, Paired] = field(default_factory=dict)
    """Controller -> the leader against it on the effort metric."""
    notes: tuple[str, ...] = ()
    """Further lines printed under this vehicle's verdict (another comparison)."""

    @property
    def leader(self) -> Standing:
        return self.standings[0]

    @property
    def tied(self) -> list[Standing]:
        """The controllers the leader cannot be told apart from."""
        return [s for s in self.standings[1:] if self.against.get(s.controller, _NONE).tie]


_NONE = Paired(math.nan, math.nan, math.nan, 0, 0)


def _pairs(table: pd.DataFrame, metric: str, a: str, b: str) -> tuple[list[float], list[float]]:
    """a's and b's `metric` over every (scenario, sample) both ran."""
    x = table[table["controller"] == a].set_index(["scenario", "sample"])[metric]
    y = table[table["controller"] == b].set_index(["scenario", "sample"])[metric]
    common = x.index.intersection(y.index)
    return x.loc[common].astype(float).tolist(), y.loc[common].astype(float).tolist()


def _median(rows: pd.DataFrame, metric: str | None) -> float:
    if metric is None or not len(rows):
        return math.nan
    return float(rows[metric].astype(float).median())


def vehicle_verdicts(study: Study, runs: pd.DataFrame, summaries: Sequence[Summary] | None = None
                     ) -> list[VehicleVerdict]:
    """The verdict's statistics per vehicle, in the order the study's
    scenarios name the vehicles. `summaries`: :func:`summarise`'s, when the
    caller has them."""
    table = as_frame(runs)
    if table.empty:
        return []
    summ = list(summaries) if summaries is not None else summarise(study, table)
    metric = study.ranking_metric
    effort = EFFORT_METRIC if EFFORT_METRIC in table and EFFORT_METRIC != metric else None
    vehicle_of = {s.name: vehicle_key(s) for s in study.scenarios}
    table = table.assign(vehicle=table["scenario"].map(vehicle_of))
    vehicles = list(dict.fromkeys(vehicle_of[s.name] for s in study.scenarios if s.name in vehicle_of))
    out: list[VehicleVerdict] = []
    p_values: list[float] = []
    for v in vehicles:
        mine = [g for g in summ if vehicle_of.get(g.scenario) == v]
        rows = table[table["vehicle"] == v]
        standings = []
        for c in study.controllers:
            gs = [g for g in mine if g.controller == c]
            if not gs:
                continue
            ranks = [g.rank for g in gs]
            mine_rows = rows[rows["controller"] == c]
            standings.append(Standing(c, study.label(c), float(np.mean(ranks)), ranks.count(1), len(gs),
                                      float(np.mean([g.failure_rate for g in gs])),
                                      _median(mine_rows, metric), _median(mine_rows, effort)))
        standings.sort(key=lambda s: (s.mean_rank, -s.firsts, study.controllers.index(s.controller)))
        if not standings:
            continue
        lead = standings[0].controller
        against: dict[str, Paired] = {}
        efforts: dict[str, Paired] = {}
        for s in standings[1:]:
            a, b = _pairs(rows, metric, lead, s.controller)
            against[s.controller] = Paired(*paired_ratio(a, b), len(a))
            p_values.append(wilcoxon_p(a, b))
            if effort is not None:
                a, b = _pairs(rows, effort, lead, s.controller)
                efforts[s.controller] = Paired(*paired_ratio(a, b), len(a))
        out.append(VehicleVerdict(v, metric, tuple(standings), study.samples, against, effort, efforts))
    # Holm over every comparison of the verdict, in the order they were made.
    adjusted = iter(holm(p_values))
    return [replace(vv, against={c: replace(p, p_holm=next(adjusted)) for c, p in vv.against.items()})
            for vv in out]


def _g(x: float) -> str:
    return "n/a" if math.isnan(x) else ("inf" if math.isinf(x) else f"{x:.3g}")


def _quantity(metric: str) -> tuple[str, str, float]:
    """(name in words, unit, factor to that unit) of a metric."""
    label, factor = label_for_people(metric_label(metric))
    name, _, unit = label.rpartition(" [")
    return (name, unit.rstrip("]"), factor) if name else (label, "", 1.0)


def _sure(p: Paired) -> str:
    """The interval and the test, in words."""
    if not p.pairs:
        return "no plants in common"
    if not p.has_interval:
        return f"lower on {p.better} of {p.pairs} paired runs; too few for a 95 % interval"
    p_text = "" if math.isnan(p.p_holm) else f"; Wilcoxon p = {p.p_holm:.2g}, Holm-corrected"
    return (f"{100 * LEVEL:.0f} % CI {_g(p.low)}-{_g(p.high)}; lower on {p.better} of {p.pairs} paired runs"
            f"{p_text}")


def verdict_lines(verdicts: Sequence[VehicleVerdict], bullet: str = "- ") -> list[str]:
    """The verdict as a few lines a person reads: per vehicle, one line on
    the leader, one on how much and how sure against the runner-up and at
    what effort, and one on the ties; then the vehicle's notes."""
    lines: list[str] = []
    pad = " " * len(bullet)
    for vv in verdicts:
        name, unit, factor = _quantity(vv.metric)
        lead = vv.leader
        n = len(vv.standings)
        effort = ""
        if vv.effort_metric and not math.isnan(lead.effort):
            ename, eunit, _ = _quantity(vv.effort_metric)
            effort = f", {ename} {_g(lead.effort)} {eunit}"
        lines.append(f"{bullet}{vv.vehicle}: {lead.label} is first, mean rank {lead.mean_rank:.2f} of {n} "
                     f"(first on {lead.firsts} of {lead.scenarios} scenarios): median {name} "
                     f"{_g(lead.median * factor)} {unit}{effort}"
                     + (f", failing {100 * lead.failure_rate:.0f} % of runs" if lead.failure_rate > 0 else "")
                     + ".")
        if n > 1:
            second = vv.standings[1]
            p = vv.against.get(second.controller, _NONE)
            text = (f"{pad}By {_g(p.ratio)} times the error of the runner-up, {second.label} "
                    f"({_g(second.median * factor)} {unit}; {_sure(p)})")
            e = vv.effort.get(second.controller)
            if vv.effort_metric and e is not None and e.pairs:
                interval = f", {100 * LEVEL:.0f} % CI {_g(e.low)}-{_g(e.high)}" if e.has_interval else ""
                text += f", at {_g(e.ratio)} times its effort{interval}"
            lines.append(text + ".")
            tied = vv.tied
            if tied:
                lines.append(f"{pad}A tie: the plants cannot tell it from "
                             + ", ".join(f"{s.label} (x {_g(vv.against[s.controller].ratio)}, CI "
                                         f"{_g(vv.against[s.controller].low)}-{_g(vv.against[s.controller].high)})"
                                         for s in tied) + ".")
            elif p.has_interval:
                lines.append(f"{pad}No tie: its interval against every other controller excludes 1.")
            else:
                lines.append(f"{pad}Whether it is a tie cannot be said: too few paired runs for a 95 % interval.")
        lines += [f"{pad}{note}" for note in vv.notes]
    return lines


def verdict_text(verdicts: Sequence[VehicleVerdict], title: str = "verdict") -> str:
    """The verdict as ``neurov study`` and ``neurov tune`` print it (empty
    for no verdicts)."""
    if not verdicts:
        return ""
    name, _, _ = _quantity(verdicts[0].metric)
    n = verdicts[0].samples
    each = "one run per scenario" if n == 1 else f"{n} plants per scenario"
    return "\n".join([f"{title} ({name}, lower is better; {each}):",
                      *verdict_lines(verdicts)])


def verdict_markdown(verdicts: Sequence[VehicleVerdict]) -> list[str]:
    """The verdict as the opening section of league.md."""
    if not verdicts:
        return []
    name, _, _ = _quantity(verdicts[0].metric)
    return ["## Verdict", "", f"Per vehicle, by {name} (lower is better), the leader against the runner-up "
            "on the same plants; the tables below have the rest.", "", *verdict_lines(verdicts), ""]
