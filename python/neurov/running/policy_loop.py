"""A batched Python policy (:class:`neurov.laws.protocol.BatchedController`)
driving K runs of a batch: one call of the policy and one step of the
batch per control period for all K, and the same :class:`neurov.Result`
per run as :func:`neurov.simulate` gives. A batch the policy fails on is
run again run by run, so only the run it fails in is recorded as failed."""

from __future__ import annotations

import time
from collections.abc import Sequence
from typing import Any

import numpy as np
from numpy.typing import NDArray

from neurov import _core
from neurov.laws.protocol import as_real_numbers, is_batched, takes_time
from neurov.results.timeseries import Result
from neurov.config.scenario import Scenario
from neurov.running.stepper import Simulator

__all__ = ["run_batched_policy"]


class _OneRun:
    """The batched policy as a per-run controller (K = 1): how a failed
    batch is run again, each run on its own."""

    def __init__(self, policy: Any) -> None:
        self.policy = policy
        self._with_t = takes_time(policy.step_batch)

    def reset(self) -> None:
        reset = getattr(self.policy, "reset", None)
        if callable(reset):
            reset()

    def step(self, eta: NDArray[np.float64], nu: NDArray[np.float64], eta_d: NDArray[np.float64],
             eta_d_dot: NDArray[np.float64], eta_d_ddot: NDArray[np.float64], t: float = 0.0) -> Any:
        rows = (eta[None], nu[None], eta_d[None], eta_d_dot[None], eta_d_ddot[None])
        out = self.policy.step_batch(*rows, t=np.array([t])) if self._with_t else self.policy.step_batch(*rows)
        tau = np.asarray(out)
        # Anything but one row goes back as it came, for ControllerCall to refuse by its rules.
        return tau[0] if tau.shape == (1, 6) else out


def _forces(out: Any, k: int, active: NDArray[np.bool_]) -> NDArray[np.float64]:
    """The policy's answer as K finite rows (rows of ended runs set to 0);
    raises saying what is wrong."""
    tau = as_real_numbers(out)
    if tau.shape != (k, 6):
        raise ValueError(f"step_batch returned shape {tau.shape}, expected ({k}, 6)")
    tau = np.where(active[:, None], tau, 0.0)
    if not np.isfinite(tau).all():
        raise ValueError("step_batch returned NaN or Inf")
    return tau


def run_batched_policy(batch: Any, policy: Any, scenarios: Sequence[Scenario], *,
                       vehicles: Sequence[_core.Vehicle] | None = None, label: str | None = None) -> list[Result]:
    """Runs `policy` on every run of `batch` (a ``neurov._core.BatchSimulator``
    at t = 0, run i made of ``scenarios[i]`` and ``vehicles[i]``, default the
    scenario's vehicle) to the end; returns the K results in the batch's
    order. If the policy raises, returns a wrong shape or NaN/Inf for a run
    still going, every run is run again alone (:class:`neurov.Simulator`
    with the policy at K = 1), so the failing runs record their refused
    steps as a per-run controller's do and the others are whole. Each
    result's wall_time is the batch's divided by K; ``s`` is not logged."""
    if not is_batched(policy):
        raise TypeError(f"argument 'policy' must declare itself batched (batched = True and a method "
                        f"step_batch(eta, nu, eta_d, eta_d_dot, eta_d_ddot) -> tau (K, 6)), "
                        f"got {type(policy).__name__}")
    k = batch.size
    if len(scenarios) != k or (vehicles is not None and len(vehicles) != k):
        raise ValueError(f"arguments 'scenarios' and 'vehicles' must have one entry per run of the batch ({k}), "
                         f"got {len(scenarios)} and {'None' if vehicles is None else len(vehicles)}")
    name = label or type(policy).__name__
    reset = getattr(policy, "reset", None)
    if callable(reset):
        reset()
    with_t = takes_time(policy.step_batch)
    start = time.perf_counter()
    while True:
        active = ~batch.done
        if not active.any():
            break
        o = batch.observation
        rows = (o["eta"], o["nu"], o["eta_d"], o["eta_d_dot"], o["eta_d_ddot"])
        try:
            tau = _forces(policy.step_batch(*rows, t=o["t"]) if with_t else policy.step_batch(*rows), k, active)
        except Exception:  # whatever the policy did wrong, each run alone will say it for itself
            return _run_alone(policy, scenarios, vehicles, name)
        batch.step(tau, active)
    wall = (time.perf_counter() - start) / k
    results = []
    for i, scenario in enumerate(scenarios):
        raw = batch.result(i)
        diverged = bool(raw.pop("diverged"))
        results.append(Result(scenario=scenario, controller=name, diverged=diverged, wall_time=wall, **raw))
    return results


def _run_alone(policy: Any, scenarios: Sequence[Scenario], vehicles: Sequence[_core.Vehicle] | None,
               label: str) -> list[Result]:
    one = _OneRun(policy)
    return [Simulator(s, vehicle=None if vehicles is None else vehicles[i], label=label).run(one)
            for i, s in enumerate(scenarios)]
