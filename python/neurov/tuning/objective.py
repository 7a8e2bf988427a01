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

from neurov.study.spec import StudyError
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


def evaluate(tuning: Tuning, controller: str, values: Mapping[str, Any], runner: TrialRunner) -> TrialOutcome:
    """Runs the trial `values` of `controller` and returns its penalised aggregate."""
    s = tuning.settings
    start = time.perf_counter()
    try:
        study = trial_study(tuning, controller, values)
    except StudyError as e:
        # A value inside the ranges that the controller refuses: the trial is a failure, not the tuning.
        n = s.train_samples * len(tuning.study_table.get("scenarios", [1]))
        return TrialOutcome(s.failure_penalty, n, n, {f"refused: {e}": n}, feasible=False,
                            seconds=time.perf_counter() - start)
    records = runner.run(study)
    reasons: Counter[str] = Counter()
    values_per_run: list[float] = []
    rows = [r["row"] for r in records if "row" in r]
    failed = failed_runs(pd.DataFrame(rows), study.failure).tolist() if rows else []
    i = 0
    for rec in records:
        if "error" in rec:
            reasons[rec["error"]] += 1
            values_per_run.append(s.failure_penalty)
            continue
        row = rec["row"]
        if failed[i]:
            reasons[_reason(row, s.objective, study.failure)] += 1
            values_per_run.append(s.failure_penalty)
        else:
            values_per_run.append(float(row[s.objective]))
        i += 1
    runs = len(records)
    failures = sum(reasons.values())
    agg = np.mean if s.aggregate == "mean" else np.median
    value = float(agg(values_per_run))
    feasible = s.max_failure_rate is None or failures / runs <= s.max_failure_rate
    if not feasible:
        # Infeasible whatever its aggregate: worth no more than a trial whose every run failed.
        value = max(value, s.failure_penalty)
    return TrialOutcome(value, runs, failures, dict(reasons), feasible, time.perf_counter() - start)
