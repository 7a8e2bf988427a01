"""A trial's value: its controller on every (scenario x training plant), the
ranking metric of each run replaced by the failure penalty where the run
failed, aggregated by the mean (or the median)."""

from __future__ import annotations

import math
import time
from collections import Counter
from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any

import numpy as np
import pandas as pd

from neurov.study.one_run import plan_runs
from neurov.study.spec import StudyError, vehicle_key
from neurov.study.tables import failed_runs
from neurov.tuning.reading import trial_study
from neurov.tuning.spec import Tuning
from neurov.tuning.trial_runs import TrialRunner

__all__ = ["TrialOutcome", "evaluate"]


@dataclass
class TrialOutcome:
    value: float
    runs: int
    failures: int
    reasons: dict[str, int] = field(default_factory=dict)
    """Why runs failed: ``"diverged"``, ``"rmse_position_m > 1"``, an exception's type and message."""
    feasible: bool = True
    seconds: float = 0.0
    pruned: bool = False
    """Stopped by the pruner after `runs` of the trial's runs."""
    effort: float | None = None
    """With ``[tune] effort``: the aggregate of the effort metric (a failed run
    counts its measured effort, infinite where that is not finite)."""
    by_vehicle: dict[str, list[float]] = field(default_factory=dict)
    """Vehicle -> [penalised error, effort] aggregated over its runs alone
    (with an effort metric; where the fronts are read per vehicle)."""

    @property
    def failure_rate(self) -> float:
        return self.failures / self.runs if self.runs else 1.0


def _reason(row: Mapping[str, Any], metric: str, bounds: Mapping[str, float]) -> str:
    if row.get("diverged"):
        return "diverged"
    for k in ("rmse_position_m", "rmse_yaw_rad", metric, *bounds):
        if not math.isfinite(float(row[k])):
            return f"{k} not finite"
    for k, b in bounds.items():
        if float(row[k]) > b:
            return f"{k} > {b:g}"
    return "failed"


def _error_text(error: str | Mapping[str, Any]) -> str:
    """A failed run's error as a reason: a study record's error (its kind,
    type and message) or a trial's run-by-run text, already one."""
    return error if isinstance(error, str) else f"{error['type']}: {error['message']}"


def evaluate(tuning: Tuning, controller: str, values: Mapping[str, Any], runner: TrialRunner,
             pruning: Any = None) -> TrialOutcome:
    """Runs the trial `values` of `controller` and returns its penalised aggregate.

    `pruning` (an Optuna trial, or anything with its ``report(value, step)``
    and ``should_prune()``) is told the running aggregate after each run, in
    the study's order (scenario by scenario, plant by plant; step = runs in
    minus one), and may stop the trial before its last run: the outcome is
    then ``pruned``, its value the running aggregate when it stopped."""
    s = tuning.settings
    start = time.perf_counter()
    try:
        study = trial_study(tuning, controller, values)
    except StudyError as e:
        # A value inside the ranges that the controller refuses: the trial is a failure, not the tuning.
        n = s.train_samples * len(tuning.study_table.get("scenarios", [1]))
        return TrialOutcome(s.failure_penalty, n, n, {f"refused: {e}": n}, feasible=False,
                            seconds=time.perf_counter() - start)
    total = len(plan_runs(study))
    agg = np.mean if s.aggregate == "mean" else np.median
    reasons: Counter[str] = Counter()
    values_per_run: list[float] = []
    # With an effort metric: per run, its vehicle, penalised error and effort.
    vehicles = {sc.name: vehicle_key(sc) for sc in study.scenarios}
    per_run: list[tuple[str, float, float]] = []

    def effort_of(rec: Mapping[str, Any]) -> float:
        v = float(rec["row"].get(s.effort, math.inf)) if "row" in rec else math.inf
        return v if math.isfinite(v) else math.inf

    def take(records: list[dict[str, Any]]) -> bool:
        rows = [r["row"] for r in records if "row" in r]
        failed = iter(failed_runs(pd.DataFrame(rows), study.failure).tolist() if rows else [])
        for rec in records:
            bad = "error" in rec or next(failed)
            if "error" in rec:
                reasons[_error_text(rec["error"])] += 1
            elif bad:
                reasons[_reason(rec["row"], s.objective, study.failure)] += 1
            values_per_run.append(s.failure_penalty if bad else float(rec["row"][s.objective]))
            if s.effort is not None:
                effort = effort_of(rec)
                per_run.append((vehicles.get(rec["key"][0], ""), values_per_run[-1], effort))
                if s.effort_weight is not None and not bad:
                    # One objective: error + weight x effort, run by run; a failed run counts the penalty.
                    values_per_run[-1] += s.effort_weight * effort
            # Judged after each run, whatever the batches the runs came in, so that
            # the trials do not depend on the number of workers; never after the last.
            if pruning is not None and len(values_per_run) < total:
                pruning.report(float(agg(values_per_run)), len(values_per_run) - 1)
                if pruning.should_prune():
                    return True  # the batch's later runs are not counted
        return False

    runner.run(study, take)
    runs = len(values_per_run)
    failures = sum(reasons.values())
    value = float(agg(values_per_run))
    pruned = runs < total
    feasible = s.max_failure_rate is None or failures / runs <= s.max_failure_rate
    if not feasible and not pruned:
        # Infeasible whatever its aggregate: worth no more than a trial whose every run failed.
        value = max(value, s.failure_penalty)
    outcome = TrialOutcome(value, runs, failures, dict(reasons), feasible, time.perf_counter() - start, pruned)
    if per_run:
        outcome.effort = float(agg([e for _, _, e in per_run]))
        for v in sorted({v for v, _, _ in per_run}):
            mine = [(x, e) for w, x, e in per_run if w == v]
            outcome.by_vehicle[v] = [float(agg([x for x, _ in mine])), float(agg([e for _, e in mine]))]
    return outcome
