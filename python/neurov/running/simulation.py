"""Run a scenario: :func:`neurov.simulate` builds the vehicle and the
controller and runs the closed loop (:mod:`neurov.running.closed_loop`
chooses which); :func:`neurov.simulate_many` (:mod:`neurov.running.many`) runs several."""

from __future__ import annotations

from typing import Any, cast

from neurov import _core
from neurov.config.scenario import ControllerSpec, Scenario
from neurov.laws.protocol import require_controller
from neurov.laws.registry import build_controller
from neurov.results.timeseries import Result
from neurov.running.closed_loop import run_loop
from neurov.running.plant import build_vehicle

__all__ = ["simulate"]


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
    plant = vehicle if vehicle is not None else build_vehicle(scenario)
    if controller is None or isinstance(controller, ControllerSpec):
        spec = controller or scenario.controller
        ctrl, name = build_controller(spec, scenario), spec.name
    else:
        require_controller(controller)
        ctrl, name = controller, type(controller).__name__
    return cast(Result, run_loop(scenario, plant, ctrl, label or name))  # not streamed: a whole Result
