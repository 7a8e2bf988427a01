"""A batched Python policy against the all-C++ batch: a linear feedback in
numpy, tau = -Kp e_b - Kd (nu - nu_d) with the pose error e_b and the desired
velocity nu_d in the body frame (``_core.to_body`` on all K rows at once),
over K runs of paper_fig3 (each its own noise seed), in runs per second
(wall clock, the best of --repeats):

- ``neurov.simulate_many`` with the policy (one ``step_batch`` call per step
  for the K runs, full Results);
- ``run_batched_policy`` on a ``_core.BatchSimulator`` built beforehand (the
  loop alone, without the per-run set-up);
- ``_core.run_batch`` with the built-in PD controller on the same K runs
  (vehicles, controllers and configurations built beforehand), 1 thread and
  one per core; and ``neurov.simulate_many`` with that PD (1 thread), the
  same per-run set-up as the policy's ``simulate_many``.

The ratios are the all-C++ batch's runs/s (1 thread, all threads) over the policy's.

    python bench/batched_policy.py [--runs 256] [--duration 20] [--repeats 3] [--json out.json]
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import timeit
from collections.abc import Callable
from typing import Any

import neurov
import numpy as np
from neurov import _core
from neurov.config.scenario import scenario_path
from neurov.running.plant import build_vehicle, simulation_config
from neurov.running.policy_loop import run_batched_policy

KP = np.array([200.0, 200, 200, 50, 50, 50])
KD = np.array([200.0, 200, 200, 50, 50, 50])


class BodyFrameFeedback:
    """tau = -Kp J(eta)^-1 (eta - eta_d) - Kd (nu - J(eta)^-1 eta_d_dot), K rows per call."""

    batched = True

    def step_batch(self, eta: Any, nu: Any, eta_d: Any, eta_d_dot: Any, eta_d_ddot: Any) -> Any:
        body = _core.to_body(eta, np.stack((eta - eta_d, eta_d_dot), axis=1))
        return -KP * body[:, 0] - KD * (nu - body[:, 1])


def best(f: Callable[[], object], repeats: int) -> float:
    """The shortest of `repeats` calls of f [s] (the least disturbed)."""
    return min(timeit.repeat(f, number=1, repeat=repeats))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--runs", type=int, default=256)
    parser.add_argument("--duration", type=float, default=20.0)
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--json", help="write the figures to this file")
    args = parser.parse_args()

    base = neurov.load_scenario(scenario_path("paper_fig3")).replace(duration=args.duration)
    scenarios = [base.replace(seed=1000 + i) for i in range(args.runs)]
    vehicles = [build_vehicle(s) for s in scenarios]
    configs = [simulation_config(s) for s in scenarios]
    policy = BodyFrameFeedback()
    steps = int(round(base.duration / base.dt))

    def loop_alone() -> None:
        run_batched_policy(_core.BatchSimulator(vehicles, configs), policy, scenarios, vehicles=vehicles)

    figures: dict[str, Any] = {
        "runs": args.runs, "duration_s": args.duration, "steps_per_run": steps, "cpus": os.cpu_count(),
        "machine": platform.processor() or platform.machine(),
    }
    timed = {
        "simulate_many_policy": lambda: neurov.simulate_many([(s, policy) for s in scenarios]),
        "simulate_many_pd_1_thread": lambda: neurov.simulate_many(
            [(s, neurov.PDController(KP, KD)) for s in scenarios], threads=1),
        "policy_loop_alone": loop_alone,
        "run_batch_pd_1_thread": lambda: _core.run_batch(
            vehicles, [neurov.PDController(KP, KD) for _ in scenarios], configs, threads=1),
        "run_batch_pd_all_threads": lambda: _core.run_batch(
            vehicles, [neurov.PDController(KP, KD) for _ in scenarios], configs, threads=0),
    }
    for name, f in timed.items():
        seconds = best(f, args.repeats)
        figures[name] = {"seconds": seconds, "runs_per_s": args.runs / seconds}
        print(f"{name:28s} {seconds * 1e3:9.1f} ms  {args.runs / seconds:10.1f} runs/s")
    for pd in ("run_batch_pd_1_thread", "run_batch_pd_all_threads", "simulate_many_pd_1_thread"):
        for name in ("simulate_many_policy", "policy_loop_alone"):
            ratio = figures[pd]["runs_per_s"] / figures[name]["runs_per_s"]
            figures[f"ratio_{pd}_over_{name}"] = ratio
            print(f"{pd} / {name}: {ratio:.2f}x (target <= 2x)")
    if args.json:
        with open(args.json, "w") as out:
            json.dump(figures, out, indent=2)


if __name__ == "__main__":
    main()
