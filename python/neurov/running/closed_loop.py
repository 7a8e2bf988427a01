"""The one place that chooses the loop a run goes through.

A built-in controller (one of ``neurov._core.BUILT_IN_CONTROLLERS``) runs in
the C++ loop, with no Python per step; any other object following
:class:`neurov.Controller` is stepped from Python by
:class:`neurov.Simulator`, which calls it once per control period. Both
loops run the same plant, sea and sensors, so a run's rows do not depend on
which loop ran them, only its speed does. :func:`neurov.simulate` and the
streamed run of ``neurov run`` (:mod:`neurov.running.stream`) both come here.
"""

from __future__ import annotations

import time
from collections.abc import Callable
from typing import Any

from neurov import _core
from neurov.config.scenario import Scenario
from neurov.laws.protocol import is_built_in
from neurov.results.timeseries import Result
from neurov.running.plant import simulation_config
from neurov.running.stepper import Simulator

__all__ = ["run_loop"]


def run_loop(scenario: Scenario, plant: _core.Vehicle, controller: Any, label: str, *,
             on_rows: Callable[[dict[str, Any]], None] | None = None, chunk_rows: int = 0) -> Result | None:
    """Runs `controller` on `plant` through `scenario`, in the C++ loop if
    the controller is built in, else stepped from Python.

    Without `on_rows`, the whole run is returned as a :class:`Result`
    labelled `label`. With `on_rows`, the rows are handed to it in chunks of
    about `chunk_rows` rows as they are made and not kept: the C++ loop then
    returns None, the Python loop the :class:`Result` of
    :meth:`neurov.Simulator.run` (which carries the controller's errors)."""
    if not is_built_in(controller):
        stepped = Simulator(scenario, vehicle=plant, label=label, log_rows=chunk_rows if on_rows else 0)
        return stepped.run(controller, on_rows=on_rows)
    config = simulation_config(scenario)
    if on_rows is not None:
        _core.run_closed_loop_chunks(plant, controller, config, chunk_rows, on_rows)
        return None
    start = time.perf_counter()
    raw = _core.run_closed_loop(plant, controller, config)
    wall = time.perf_counter() - start
    diverged = bool(raw.pop("diverged"))
    return Result(scenario=scenario, controller=label, diverged=diverged, wall_time=wall, **raw)
