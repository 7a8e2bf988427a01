"""What a controller written in Python costs: a 600 s run at 5 Hz (3001
steps, 10 RK4 substeps each) of NEROV on the paper's square, the controller a
trivial one that returns a constant force, against the same run in the all-C++
loop and in the numpy baseline (bench/numpy_baseline.py: the plant in numpy).

    python bench/python_controller.py [--repeat 7] [--json out.json]

Reported, each the median of `--repeat` runs in this one process:

- python controller: ``neurov.simulate(scenario, Constant())``, the whole run;
- its parts: the bound ``_core.Simulator`` stepped with a constant force and no
  controller (the plant and one step call per period), the same plus reading
  the observation, and the controller's checked call (``ControllerCall``)
  alone on one observation, times the steps;
- all-C++ loop: ``neurov.simulate(scenario, neurov.PDController(...))``;
- numpy: numpy_baseline's plant and reference model with the same constant controller.

The scenario runs without thrusters so that the numpy baseline does the same work.
"""

from __future__ import annotations

import argparse
import json
import statistics
import sys
import time
from pathlib import Path
from typing import Any

import numpy as np

import neurov
from neurov import _core
from neurov.laws.protocol import ControllerCall
from neurov.running.plant import build_vehicle, simulation_config
from neurov.study.spec import SCENARIO_DIR

sys.path.insert(0, str(Path(__file__).resolve().parent))
import numpy_baseline as nb  # noqa: E402

TAU = np.array([10.0, 0.0, 5.0, 0.0, 0.0, 1.0])


class Constant:
    """The trivial controller: the same force at every step."""

    def step(self, eta: Any, nu: Any, eta_d: Any, eta_d_dot: Any, eta_d_ddot: Any) -> np.ndarray:
        return TAU


class NumpyConstant:
    def step(self, *args: Any) -> np.ndarray:
        return TAU


def median_time(fn: Any, repeat: int) -> float:
    times = []
    for _ in range(repeat):
        start = time.perf_counter()
        fn()
        times.append(time.perf_counter() - start)
    return statistics.median(times)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--repeat", type=int, default=7)
    parser.add_argument("--json", type=Path)
    args = parser.parse_args()

    scenario = neurov.load_scenario(SCENARIO_DIR / "paper_fig3.toml").replace(duration=600.0, use_thrusters=False)
    steps = round(scenario.duration / scenario.dt) + 1
    vehicle, config = build_vehicle(scenario), simulation_config(scenario)

    def plant_only() -> None:
        sim = _core.Simulator(vehicle, config)
        while not sim.done:
            sim.step(TAU)

    def plant_and_observation() -> None:
        sim = _core.Simulator(vehicle, config)
        while not sim.done:
            sim.observation  # noqa: B018 - what the loop reads for the controller
            sim.step(TAU)

    call = ControllerCall(Constant())
    obs = _core.Simulator(vehicle, config).observation

    def controller_calls() -> None:
        for _ in range(steps):
            call(obs)

    pd = neurov.PDController(np.full(6, 100.0), np.full(6, 200.0))
    times, poses = scenario.command.timed_poses()

    def numpy_loop() -> None:
        nb.simulate(nb.Nerov(), NumpyConstant(), dt=scenario.dt, substeps=scenario.substeps,
                    duration=scenario.duration, eta0=np.asarray(scenario.eta0), command_times=times,
                    command_poses=poses, lambda_d=np.asarray(scenario.lambda_d), omega=np.asarray(scenario.omega))

    python = neurov.simulate(scenario, Constant())
    assert len(python.t) == steps and not python.diverged
    assert np.all(python.tau_demanded == TAU)

    r = args.repeat
    report = {
        "steps": steps,
        "python_controller_s": median_time(lambda: neurov.simulate(scenario, Constant()), r),
        "plant_only_s": median_time(plant_only, r),
        "plant_and_observation_s": median_time(plant_and_observation, r),
        "controller_calls_s": median_time(controller_calls, r),
        "all_cpp_pd_s": median_time(lambda: neurov.simulate(scenario, pd), r),
        "numpy_constant_s": median_time(numpy_loop, max(1, r // 3)),
    }
    w = 22
    print(f"600 s at 5 Hz ({steps} steps, {scenario.substeps} RK4 substeps), median of {r} runs:")
    print(f"{'python controller':<{w}} {report['python_controller_s'] * 1e3:8.1f} ms  "
          f"({scenario.duration / report['python_controller_s']:,.0f} x real time)")
    print(f"{'  plant + step call':<{w}} {report['plant_only_s'] * 1e3:8.1f} ms")
    print(f"{'  + observation':<{w}} {(report['plant_and_observation_s'] - report['plant_only_s']) * 1e3:8.1f} ms")
    print(f"{'  controller calls':<{w}} {report['controller_calls_s'] * 1e3:8.1f} ms "
          f"({report['controller_calls_s'] / steps * 1e6:.2f} us each)")
    print(f"{'all-C++ loop (PD)':<{w}} {report['all_cpp_pd_s'] * 1e3:8.1f} ms")
    print(f"{'numpy plant':<{w}} {report['numpy_constant_s'] * 1e3:8.1f} ms")
    if args.json:
        args.json.write_text(json.dumps(report, indent=2))


if __name__ == "__main__":
    main()
