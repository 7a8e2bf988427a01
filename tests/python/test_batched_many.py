"""neurov.simulate_many with a batched Python policy: the runs sharing one
policy object are one batch, results in the order given and equal to the
same law run per run; metrics_only gives the same metrics; a policy failing
on one run fails only that run."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import neurov
import numpy as np
import pytest
from neurov.errors import RefusedStepsWarning
from neurov.laws.protocol import own_failures

SCENARIOS = Path(neurov.__file__).resolve().parent / "scenarios"


class BatchedPD:
    """tau = -20 (eta - eta_d) - 40 nu for K rows; raises if a run's x passes `limit`."""

    batched = True

    def __init__(self, limit: float = np.inf) -> None:
        self.limit = limit
        self.calls = 0

    def step_batch(self, eta: Any, nu: Any, eta_d: Any, eta_d_dot: Any, eta_d_ddot: Any) -> Any:
        self.calls += 1
        if (eta[:, 0] > self.limit).any():
            raise RuntimeError("past the limit")
        return -20.0 * (eta - eta_d) - 40.0 * nu


class PerRunPD:
    def __init__(self, limit: float = np.inf) -> None:
        self.limit = limit

    def step(self, eta: Any, nu: Any, eta_d: Any, eta_d_dot: Any, eta_d_ddot: Any) -> Any:
        if eta[0] > self.limit:
            raise RuntimeError("past the limit")
        return -20.0 * (eta - eta_d) - 40.0 * nu


def _scenarios() -> list[neurov.Scenario]:
    base = neurov.load_scenario(SCENARIOS / "nerov_square_disturbed.toml").replace(duration=2.0)
    return [base.replace(seed=s) for s in (1, 2, 3, 4)]


def _close(a: neurov.Result, b: neurov.Result) -> None:
    for name in ("t", "eta", "nu", "tau_applied", "controller_status"):
        x, y = np.asarray(getattr(a, name)), np.asarray(getattr(b, name))
        np.testing.assert_allclose(x, y, rtol=0, atol=1e-12 * max(1.0, float(np.abs(y).max())))


def test_runs_sharing_a_policy_are_one_batch_in_the_order_given() -> None:
    scenarios = _scenarios()
    policy = BatchedPD()
    # Interleaved with a built-in controller's runs: the order given is kept.
    runs = [(scenarios[0], policy), scenarios[1], (scenarios[2], policy), (scenarios[3], policy)]
    results = neurov.simulate_many(runs)
    assert policy.calls == len(results[0].t)  # one call per step for the three runs, not one per run
    for r, s in zip([results[0], results[2], results[3]], [scenarios[0], scenarios[2], scenarios[3]]):
        assert r.controller == "BatchedPD"
        _close(r, neurov.simulate(s, PerRunPD()))
    _close(results[1], neurov.simulate(scenarios[1]))


def test_metrics_only_of_a_batched_policy_are_its_results_metrics() -> None:
    scenarios = _scenarios()[:2]
    full = neurov.simulate_many([(s, BatchedPD()) for s in scenarios])
    policy = BatchedPD()
    metrics = neurov.simulate_many([(s, policy) for s in scenarios], metrics_only=True)
    assert metrics == [r.metrics() for r in full]


def test_a_policy_failing_on_one_run_fails_only_that_run() -> None:
    scenarios = _scenarios()[:3]
    # Run 1 starts 5 m ahead in x: the policy raises on it, never on the others (near x = 0).
    scenarios[1] = scenarios[1].replace(eta0=np.array([5.0, 0, 0, 0, 0, 0]))
    with pytest.warns(RefusedStepsWarning):
        alone = [neurov.simulate(s, PerRunPD(limit=3.0)) for s in scenarios]
    policy = BatchedPD(limit=3.0)
    with pytest.warns(RefusedStepsWarning):
        results = neurov.simulate_many([(s, policy) for s in scenarios])
    failed = [bool(own_failures(r.extra.get("controller_errors") or {})) for r in results]
    assert failed == [False, True, False]
    for r, a, f in zip(results, alone, failed):
        _close(r, a)  # the failing run too: its refused steps as the per-run controller's
