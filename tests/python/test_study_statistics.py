"""The statistics of a verdict: the intervals cover a known median at their
nominal rate (seeded simulations, no simulator), the Wilcoxon p-value is
uniform under no difference, Holm's adjustment, and the league table's
columns ("n/a" with one plant, ranks shared when a paired interval holds 1)."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
from scipy.stats import binom

from neurov.study import StudyError, load_study, summarise, summary_table
from neurov.study.report import league_markdown
from neurov.study.statistics import holm, median_ci, order_statistic_rank, paired_ratio, wilcoxon_p

from study_files import STUDY, write_study


@pytest.mark.parametrize("n", [8, 20, 50])
def test_the_median_interval_covers_a_known_median_at_its_nominal_rate(n: int) -> None:
    rng = np.random.default_rng(20261201 + n)
    trials = 4000
    # A skewed distribution (lognormal): its median is exp(mu), its mean is not.
    mu = 0.3
    x = rng.lognormal(mu, 1.0, size=(trials, n))
    hits = 0
    for row in x:
        low, high = median_ci(row)
        hits += low <= math.exp(mu) <= high
    # The interval's exact coverage: 1 - 2 P(B <= l - 1), at least 95 %.
    l = order_statistic_rank(n)
    exact = 1.0 - 2.0 * binom.cdf(l - 1, n, 0.5)
    assert exact >= 0.95
    rate = hits / trials
    assert abs(rate - exact) < 4.0 * math.sqrt(exact * (1 - exact) / trials), (rate, exact)


def test_the_paired_ratio_interval_covers_at_its_nominal_rate() -> None:
    rng = np.random.default_rng(7)
    trials, n = 3000, 20
    hits = 0
    for _ in range(trials):
        ref = rng.lognormal(0.0, 0.5, n)
        # The controller is 20 % worse on the median plant, with plant-to-plant spread.
        other = ref * 1.2 * np.exp(rng.standard_t(3, n) * 0.3)
        _, low, high, _ = paired_ratio(other, ref)
        hits += low <= 1.2 <= high
    exact = 1.0 - 2.0 * binom.cdf(order_statistic_rank(n) - 1, n, 0.5)
    assert abs(hits / trials - exact) < 4.0 * math.sqrt(exact * (1 - exact) / trials)


def test_too_few_values_for_an_interval_give_nan() -> None:
    assert order_statistic_rank(5) is None and order_statistic_rank(6) == 1
    assert all(math.isnan(v) for v in median_ci([1.0, 2.0, 3.0]))
    # A failed run (inf or nan) is the worst value: it can be the upper end.
    assert median_ci([1, 2, 3, 4, 5, float("nan")]) == (1.0, math.inf)


def test_wilcoxon_p_is_uniform_when_nothing_differs_and_small_when_one_is_better() -> None:
    rng = np.random.default_rng(3)
    p = [wilcoxon_p(rng.normal(size=20), rng.normal(size=20)) for _ in range(1000)]
    assert 0.03 < np.mean(np.array(p) < 0.05) < 0.07
    a = rng.normal(size=20)
    assert wilcoxon_p(a, a + 1.0) < 1e-4
    # A failed run counts as worse than any finished one, not as a missing value.
    assert wilcoxon_p([1.0] * 8, [float("inf")] * 8) < 0.01
    assert wilcoxon_p([1.0, 2.0], [1.0, 2.0]) == 1.0


def test_holm_steps_down_and_skips_nan() -> None:
    assert holm([0.01, 0.04, 0.03, float("nan"), 0.5]) == pytest.approx([0.04, 0.09, 0.09, math.nan, 0.5],
                                                                        nan_ok=True)
    assert holm([0.3, 0.6]) == [0.6, 0.6]


def _rows(study, values):  # type: ignore[no-untyped-def]
    return [{"scenario": sc.name, "controller": c, "sample": k, "rmse_position_m": v, "rmse_yaw_rad": 0.0,
             "diverged": 0.0} for sc in study.scenarios for c, vals in values.items() for k, v in enumerate(vals)]


def test_league_table_statistics_and_paired_ranks(tmp_path: Path) -> None:
    s = load_study(write_study(tmp_path, STUDY.replace("samples = 4", "samples = 12")))
    rng = np.random.default_rng(1)
    base = rng.lognormal(0.0, 0.3, 12)
    # nn is the reference (the first head-to-head pair's first member); linear is
    # 2 % worse with noise (indistinguishable: shares nn's rank), pd twice as bad.
    values = {"nn": base, "linear": base * 1.02 * np.exp(rng.normal(0, 0.1, 12)), "pd": 2.0 * base}
    summ = [g for g in summarise(s, _rows(s, values)) if g.scenario == "short_nerov"]
    by = {g.controller: g for g in summ}
    assert by["pd"].rank == 3 and by["pd"].better == 0 and by["pd"].ratio == pytest.approx(2.0)
    assert by["pd"].ratio_ci_low == pytest.approx(2.0) and by["pd"].p_value_holm < 0.01
    assert by["linear"].ratio_ci_low <= 1.0 <= by["linear"].ratio_ci_high
    assert by["linear"].rank == by["nn"].rank == 1
    low, high = median_ci(values["nn"])
    assert (by["nn"].median_ci_low, by["nn"].median_ci_high) == (low, high)
    # Holm over the table's four comparisons (2 scenarios x 2 controllers): pd's
    # two are the smallest p-values (the scenarios got the same numbers), so x 4.
    assert by["pd"].p_value_holm == pytest.approx(min(1.0, 4 * by["pd"].p_value), rel=1e-12)
    table = summary_table(s, _rows(s, values))
    for col in ("median_ci_low", "median_ci_high", "ratio_ci_low", "ratio_ci_high", "p_value_holm"):
        assert col in table.columns
    md = league_markdown(s, _rows(s, values))
    assert "95 % CI of the median" in md and "paired ratio to NN adaptive [95 % CI]" in md
    assert "| (reference) |" in md and "0 of 12" in md


def test_one_plant_per_scenario_says_n_a(tmp_path: Path) -> None:
    s = load_study(write_study(tmp_path, STUDY.replace("samples = 4", "samples = 1")))
    table = summary_table(s, _rows(s, {"nn": [1.0], "linear": [2.0], "pd": [3.0]}))
    for col in ("median_ci_low", "median_ci_high", "ratio_ci_low", "ratio_ci_high", "p_value_holm"):
        assert set(table[col]) == {"n/a"}
    assert list(table["rank"][:3]) == [1, 2, 3]  # by the median
    md = league_markdown(s, _rows(s, {"nn": [1.0], "linear": [2.0], "pd": [3.0]}))
    # One plant: no spread, interval or test, only the run's value, whether it
    # failed and plain ratios (to the best, to the reference).
    assert "| 2 | linear adaptive | 2 | 100 % | 0 | 0 | 2 | 2 |" in md
    assert "5th-95th" not in md and "95 % CI" not in md and "Wilcoxon" not in md


def test_a_reference_that_is_not_a_controller_is_refused(tmp_path: Path) -> None:
    with pytest.raises(StudyError, match=r"ranking\.reference: expected one of the study's controllers"):
        load_study(write_study(tmp_path, STUDY.replace('metric = "rmse_position_m"',
                                                       'metric = "rmse_position_m"\nreference = "mpc"')))
    s = load_study(write_study(tmp_path, STUDY.replace('metric = "rmse_position_m"',
                                                       'metric = "rmse_position_m"\nreference = "pd"')))
    assert s.reference_controller() == "pd"
