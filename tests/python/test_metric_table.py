"""A metric is one entry of neurov.results.metrics.METRICS: added there, it reaches
Result.metrics, a study's runs table, what a study may rank and bound by, the
league table and the figures' labels, with nothing else edited."""

from __future__ import annotations

from collections.abc import Iterator
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

from neurov import load_scenario, simulate
from neurov.results.metrics import METRICS, Metric, metric_label, metric_names, register_metric
from neurov.study import run_study
from study_files import step_scenario

STUDY = """
name = "depth_in_cm"
seed = 2
samples = 2
after = 5.0
scenarios = ["a.toml"]

[ranking]
metric = "rmse_depth_cm"

[failure]
rmse_depth_cm = 1000.0

[controllers.soft]
type = "pd"
kp = [50, 50, 50, 20, 20, 20]
kd = [200, 200, 200, 50, 50, 50]

[controllers.stiff]
type = "pd"
kp = [200, 200, 200, 50, 50, 50]
kd = [400, 400, 400, 100, 100, 100]

[[perturbations]]
parameter = "mass"
relative = 0.1
"""


@pytest.fixture
def depth_in_cm() -> Iterator[Metric]:
    """A metric of a test's own, gone again after the test."""
    yield register_metric(Metric(
        "rmse_depth_cm", "RMS depth error [cm]",
        lambda w: 100.0 * float(np.sqrt(w.sums.e2[2] / w.sums.rows)), error=True))
    del METRICS["rmse_depth_cm"]


def test_a_registered_metric_reaches_the_run_the_study_and_the_labels(tmp_path: Path,
                                                                    depth_in_cm: Metric) -> None:
    assert "rmse_depth_cm" in metric_names()
    assert metric_label("rmse_depth_cm") == "RMS depth error [cm]"

    (tmp_path / "a.toml").write_text(step_scenario(
        "a", "nerov", [0, 0, 0, 0, 0, 0], [0, 0, 1, 0, 0, 0], kp=50.0, kd=200.0, duration=12.0))
    m = simulate(load_scenario(tmp_path / "a.toml")).metrics(after=5.0)
    assert m["rmse_depth_cm"] == pytest.approx(100.0 * m["rmse"]["z"], rel=1e-12)

    (tmp_path / "study.toml").write_text(STUDY)
    # One local worker runs in this process, where the metric is registered.
    out = run_study(tmp_path / "study.toml", tmp_path / "out", executor="processes", workers=1,
                    progress=False, plots=False)
    runs = pd.read_csv(out.table_path)
    assert np.allclose(runs["rmse_depth_cm"], 100.0 * runs["rmse_z"], rtol=1e-9)
    # The league table ranks by it: its medians are of the new column.
    summary = pd.read_csv(out.summary_path)
    for controller, rows in runs.groupby("controller"):
        median = summary.loc[summary.controller == controller, "median"].item()
        assert median == pytest.approx(rows["rmse_depth_cm"].median(), rel=1e-9)
    assert "rmse_depth_cm" in out.league.read_text()


def test_a_metric_is_refused_with_its_reason(depth_in_cm: Metric) -> None:
    with pytest.raises(ValueError, match="'rmse_depth_cm' exists already"):
        register_metric(depth_in_cm)
    with pytest.raises(ValueError, match="name must be an identifier"):
        register_metric(Metric("depth error", "depth error [m]", lambda w: 0.0))
    with pytest.raises(ValueError, match="label of 'x_cm' must say"):
        register_metric(Metric("x_cm", " ", lambda w: 0.0))
    with pytest.raises(TypeError, match="argument 'metric' must be a neurov.results.metrics.Metric"):
        register_metric("rmse_depth_cm")  # type: ignore[arg-type]


def test_a_study_column_is_an_error_metric_exactly_when_it_is_inf_for_a_diverged_run() -> None:
    errors = {k for k, m in METRICS.items() if m.error}
    assert errors == {k for k in metric_names()
                      if k.startswith(("rmse", "max_position", "max_yaw", "max_abs_error", "iae"))}
