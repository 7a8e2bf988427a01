"""neurov.simulate_many loses nothing: every run is checked before any runs
(a refusal names the run's 0-based index), and a run that fails while it
runs is a failed result among the others, as a study's failed run is."""

from __future__ import annotations

import math
from typing import Any

import numpy as np
import pytest

import neurov
from neurov import _core
from neurov.config.scenario import CommandSpec, ControllerSpec, Scenario
from neurov.running import many
from neurov.running.many import BATCH_RUNS, simulate_many

SHORT = Scenario(name="short", duration=1.0,
                 command=CommandSpec(type="waypoints", times=[0.0], poses=[[0.0] * 6]),
                 controller=ControllerSpec(type="pd", kp=np.ones(6), kd=np.ones(6)))


class ResetFails:
    """A Python controller that raises when its run starts."""

    def reset(self) -> None:
        raise RuntimeError("no sensor calibration")

    def step(self, eta: Any, nu: Any, eta_d: Any, eta_d_dot: Any, eta_d_ddot: Any) -> Any:
        return np.zeros(6)


@pytest.mark.parametrize(("bad", "field"), [({"substeps": 0}, "substeps"), ({"duration": -1.0}, "duration"),
                                            ({"dt": -1.0}, "dt")])
def test_a_bad_run_among_many_is_refused_by_index_before_any_runs(
        monkeypatch: pytest.MonkeyPatch, bad: dict[str, Any], field: str) -> None:
    calls = []
    real = _core.run_batch
    monkeypatch.setattr(many._core, "run_batch", lambda *a, **k: calls.append(1) or real(*a, **k))
    good = BATCH_RUNS + 10  # more than a batch: before, the first batch ran and was lost
    runs = [SHORT] * good + [SHORT.replace(name="bad one", **bad)] + [SHORT] * 3
    with pytest.raises(neurov.ValidationError, match=rf"^run {good} \(scenario 'bad one'\): .*{field}") as err:
        simulate_many(runs, metrics_only=True)
    assert calls == []  # nothing ran
    assert err.value.run == good and err.value.field == field  # the C++ validator's attributes kept


def test_a_bad_override_names_its_index() -> None:
    with pytest.raises(TypeError, match=r"^run 2 \(overrides\[2\]\): .*no_such_field"):
        simulate_many(SHORT, [{"seed": 1}, {"seed": 2}, {"no_such_field": 3}])


def test_a_run_that_fails_while_running_is_a_failed_result_among_the_others() -> None:
    runs: list[Any] = [(SHORT, None), (SHORT, ResetFails()), (SHORT.replace(seed=3), None)]
    results = simulate_many(runs)
    assert [r.diverged for r in results] == [False, True, False]
    failed = results[1]
    assert failed.extra["error"] == {"type": "RuntimeError", "message": "no sensor calibration"}
    assert len(failed.t) == 0 and failed.eta.shape == (0, 6)
    assert len(results[0].t) == len(results[2].t) == 6
    metrics = simulate_many(runs, metrics_only=True)
    assert metrics[1]["error"]["type"] == "RuntimeError" and metrics[1]["diverged"]
    assert math.isfinite(metrics[0]["rmse"]["x"]) and metrics[1]["rmse"]["x"] == math.inf and "error" not in metrics[0]


def test_a_batch_refused_while_running_keeps_its_other_runs(monkeypatch: pytest.MonkeyPatch) -> None:
    real = _core.run_batch

    def refuses_lane_one(vehicles: Any, controllers: Any, configs: Any, **kw: Any) -> Any:
        if any(c.duration == 0.8 for c in configs):
            raise neurov.ValidationError("run_batch: lane 1: out of memory for its rows")
        return real(vehicles, controllers, configs, **kw)

    monkeypatch.setattr(many._core, "run_batch", refuses_lane_one)
    results = simulate_many([SHORT, SHORT.replace(duration=0.8), SHORT.replace(seed=2)])
    assert [r.diverged for r in results] == [False, True, False]
    assert "lane 1" in results[1].extra["error"]["message"]
    assert len(results[2].t) == 6
