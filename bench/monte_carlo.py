"""Monte-Carlo throughput: 600 s runs of NEROV on the paper_fig3 path under
the NN controller (N = 64) over plants perturbed as the robustness study
perturbs them, in runs per second (wall clock, the best of --repeats):

- one by one: ``neurov.simulate(plant, spec)`` per run (the path of a study
  before the batch: vehicle, controller with its Sobol centres, Result);
- ``neurov.simulate_many`` with 1 and 2 threads, full results and metrics-only;
- ``_core.run_batch`` alone on vehicles, controllers and configurations built
  beforehand (what the C++ costs without the Python set-up), 1 and 2 threads,
  full and metrics-only;
- the per-run Python set-up, timed apart: the plant's draw, its vehicle and
  configuration, the controller with and without its centres drawn afresh.

    python bench/monte_carlo.py [--runs 128] [--duration 600] [--repeats 3] [--json out.json]
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import timeit
from collections.abc import Callable

import neurov
import numpy as np
from neurov import _core
from neurov.laws.registry import build_controller, default_centre_box, make_centres
from neurov.config.scenario import scenario_path
from neurov.running.plant import build_vehicle, simulation_config
from neurov.study import load_study, sample_plant


def best(f: Callable[[], object], repeats: int) -> float:
    """The shortest of `repeats` calls of f [s] (the least disturbed)."""
    return min(timeit.repeat(f, number=1, repeat=repeats))


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--runs", type=int, default=128)
    p.add_argument("--duration", type=float, default=600.0)
    p.add_argument("--repeats", type=int, default=3)
    p.add_argument("--json", help="also write the figures to this file")
    args = p.parse_args()

    study = load_study("robustness")
    base = neurov.load_scenario(scenario_path("paper_fig3")).replace()
    base.duration = args.duration
    spec = base.controller
    plants = [sample_plant(study, base, k)[0] for k in range(args.runs)]
    n = args.runs
    rows = round(args.duration / base.dt) + 1
    figures: dict[str, float] = {}

    def rate(name: str, f: Callable[[], object]) -> None:
        figures[name] = n / best(f, args.repeats)
        print(f"{name:52s} {figures[name]:9.1f} runs/s")

    rate("one by one (neurov.simulate)", lambda: [neurov.simulate(pl, spec) for pl in plants])
    for threads in (1, 2):
        rate(f"simulate_many, {threads} thread(s), full", lambda threads=threads: neurov.simulate_many(plants, threads=threads))
        rate(f"simulate_many, {threads} thread(s), metrics-only",
             lambda threads=threads: neurov.simulate_many(plants, threads=threads, metrics_only=True))
    centred = spec.replace(centres=make_centres(spec, *default_centre_box(base)))
    vehicles = [build_vehicle(pl) for pl in plants]
    configs = [simulation_config(pl) for pl in plants]
    controllers = [build_controller(centred, pl) for pl in plants]
    after = np.full(n, 10.0)
    for threads in (1, 2):
        rate(f"_core.run_batch, {threads} thread(s), full",
             lambda threads=threads: _core.run_batch(vehicles, controllers, configs, threads=threads))
        rate(f"_core.run_batch, {threads} thread(s), metrics-only",
             lambda threads=threads: _core.run_batch(vehicles, controllers, configs, threads=threads, metrics_only=True,
                                     after=after))

    setup_ms = {
        "draw the plant (sample_plant)": best(lambda: [sample_plant(study, base, k) for k in range(n)], 1),
        "vehicle and configuration": best(lambda: [(build_vehicle(pl), simulation_config(pl)) for pl in plants], 1),
        "controller, centres drawn (build_controller)": best(lambda: [build_controller(spec, pl) for pl in plants], 1),
        "controller, centres given": best(lambda: [build_controller(centred, pl) for pl in plants], 1),
    }
    setup_ms = {k: 1e3 * v / n for k, v in setup_ms.items()}
    for k, v in setup_ms.items():
        print(f"per-run set-up: {k:45s} {v:7.3f} ms")
    one = 1e9 / figures["_core.run_batch, 1 thread(s), metrics-only"] / (rows - 1)
    print(f"C++ per control step (run_batch, 1 thread, metrics-only): {one:.0f} ns "
          f"({rows - 1} steps of {base.simulation.substeps} RK4 substeps per run)")
    out = {"runs": n, "duration_s": args.duration, "repeats": args.repeats, "runs_per_s": figures,
           "setup_ms_per_run": setup_ms, "ns_per_control_step": one, "cpus": os.cpu_count(),
           "python": platform.python_version(), "numpy": np.__version__}
    if args.json:
        with open(args.json, "w") as f:
            json.dump(out, f, indent=2)


if __name__ == "__main__":
    main()
