"""Run a scenario: build the vehicle and controller, run the closed loop in C++,
and wrap the arrays in a :class:`Result` with metrics and export."""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import NDArray

from neurov import _core
from neurov.result import Result
from neurov.controllers import build_controller, default_centre_box
from neurov.scenario import ControllerSpec, Scenario

__all__ = [
    "Result", "build_controller", "build_vehicle", "default_centre_box", "simulate", "simulate_many",
    "simulation_config",
]

Array = NDArray[np.float64]


def build_vehicle(scenario: Scenario) -> _core.Vehicle:
    """The scenario's vehicle, with its parameter overrides applied."""
    return scenario.vehicle_data().vehicle(scenario.vehicle_parameters)


def simulation_config(scenario: Scenario) -> _core.SimulationConfig:
    """The core's config of the run: the one the scenario holds, checked by
    the C++ validator (a ValueError names the field)."""
    scenario._sync()
    scenario.simulation.validate()
    return scenario.simulation


def simulate(scenario: Scenario, controller: ControllerSpec | Any = None, *,
             vehicle: _core.Vehicle | None = None, label: str | None = None) -> Result:
    """Runs one closed loop. `controller` is a :class:`ControllerSpec` (None:
    the scenario's), a built-in controller object (``neurov.PDController(kp,
    kd)``, ...: the loop runs in C++, no Python per step), or any object
    following :class:`neurov.Controller` (stepped from Python through
    :class:`neurov.Simulator`; its refused steps are logged and the run goes
    on; its ``reset()``, if any, is called first). A built-in object runs
    from the state it is in (e.g. warm-started weights). `label` names the
    controller in the result (default: the spec's name, the class name of
    an object)."""
    import time

    from neurov.controller import is_built_in, require_controller

    plant = vehicle if vehicle is not None else build_vehicle(scenario)
    if controller is None or isinstance(controller, ControllerSpec):
        spec = controller or scenario.controller
        ctrl, name = build_controller(spec, scenario), spec.name
    else:
        require_controller(controller)
        ctrl, name = controller, type(controller).__name__
        if not is_built_in(ctrl):
            from neurov.simulator import Simulator

            return Simulator(scenario, vehicle=plant, label=label or name).run(ctrl)
    config = simulation_config(scenario)
    start = time.perf_counter()
    raw = _core.run_closed_loop(plant, ctrl, config)
    wall = time.perf_counter() - start
    diverged = bool(raw.pop("diverged"))
    return Result(scenario=scenario, controller=label or name, diverged=diverged, wall_time=wall, **raw)


# Many runs, batched in C++ for built-in controllers: neurov/batch/many.py.
from neurov.batch.many import simulate_many  # noqa: E402
