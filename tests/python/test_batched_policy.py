"""neurov.running.policy_loop.run_batched_policy: a batched numpy policy over K runs
gives each run's Result as neurov.simulate gives it for the same policy run
by run; a policy that fails on one run fails only that run."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import neurov
import numpy as np
import pytest
from neurov import _core
from neurov.running.lanes import PythonLanes
from neurov.running.policy_loop import run_batched_policy
from neurov.laws.protocol import BatchedController, is_batched
from neurov.errors import RefusedStepsWarning
from neurov.running.plant import build_vehicle, simulation_config

SCENARIOS = Path(neurov.__file__).resolve().parent / "scenarios"


class LinearFeedback:
    """tau = -Kp (eta - eta_d) - Kd nu, K rows at once."""

    batched = True

    def __init__(self, limit: float = np.inf) -> None:
        self.limit = limit
        self.resets = 0

    def reset(self) -> None:
        self.resets += 1

    def step_batch(self, eta: Any, nu: Any, eta_d: Any, eta_d_dot: Any, eta_d_ddot: Any, t: Any = None) -> Any:
        if (eta[:, 0] > self.limit).any():
            raise RuntimeError("past the limit")
        return -20.0 * (eta - eta_d) - 40.0 * nu


class OneAtATime:
    """The same law as a per-run controller: what simulate() runs."""

    def step(self, eta: Any, nu: Any, eta_d: Any, eta_d_dot: Any, eta_d_ddot: Any) -> Any:
        return -20.0 * (eta - eta_d) - 40.0 * nu


def _scenarios() -> list[neurov.Scenario]:
    base = neurov.load_scenario(SCENARIOS / "nerov_square_disturbed.toml").replace(duration=3.0)
    return [base.replace(seed=s) for s in (1, 2, 3)]


def _batch(cls: Any, scenarios: list[neurov.Scenario]) -> Any:
    return cls([build_vehicle(s) for s in scenarios], [simulation_config(s) for s in scenarios])


def _same_rows(a: neurov.Result, b: neurov.Result) -> None:
    for name in ("t", "eta", "nu", "eta_d", "tau_demanded", "tau_applied", "eta_estimate", "controller_status"):
        x, y = np.asarray(getattr(a, name)), np.asarray(getattr(b, name))
        np.testing.assert_allclose(x, y, rtol=0, atol=1e-12 * max(1.0, float(np.abs(y).max())))


@pytest.mark.parametrize("cls", [_core.BatchSimulator, PythonLanes])
def test_a_batched_policy_gives_each_run_as_simulate_does(cls: Any) -> None:
    scenarios = _scenarios()
    policy = LinearFeedback()
    assert is_batched(policy) and isinstance(policy, BatchedController)
    results = run_batched_policy(_batch(cls, scenarios), policy, scenarios, label="linear")
    assert policy.resets == 1 and [r.controller for r in results] == ["linear"] * 3
    for s, r in zip(scenarios, results):
        _same_rows(r, neurov.simulate(s, OneAtATime()))
        assert not r.diverged


@pytest.mark.parametrize("cls", [_core.BatchSimulator, PythonLanes])
def test_a_policy_failing_on_one_run_fails_only_that_run(cls: Any) -> None:
    scenarios = _scenarios()
    # Run 1 starts 3 m north: the policy raises on it alone.
    scenarios[1] = scenarios[1].replace(eta0=np.array([3.0, 0, 0, 0, 0, 0]))
    with pytest.warns(RefusedStepsWarning, match="3 m|refused"):
        results = run_batched_policy(_batch(cls, scenarios), LinearFeedback(limit=2.5), scenarios)
    assert "controller_errors" in results[1].extra and results[1].first_refusal is not None
    for i in (0, 2):
        assert "controller_errors" not in results[i].extra
        _same_rows(results[i], neurov.simulate(scenarios[i], OneAtATime()))


def test_a_policy_that_is_not_batched_is_refused() -> None:
    scenarios = _scenarios()
    with pytest.raises(TypeError, match="batched"):
        run_batched_policy(_batch(PythonLanes, scenarios), OneAtATime(), scenarios)
    with pytest.raises(ValueError, match="one entry per run"):
        run_batched_policy(_batch(PythonLanes, scenarios), LinearFeedback(), scenarios[:2])
