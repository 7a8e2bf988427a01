"""What the core runs a scenario on: the vehicle, with the scenario's
parameter overrides applied, and the checked configuration of the run. Both
loops (:mod:`neurov.running.closed_loop`) start from these."""

from __future__ import annotations

from neurov import _core
from neurov.config.scenario import Scenario

__all__ = ["build_vehicle", "simulation_config"]


def build_vehicle(scenario: Scenario) -> _core.Vehicle:
    """The scenario's vehicle, with its parameter overrides applied."""
    return scenario.vehicle_data().vehicle(scenario.vehicle_parameters)


def simulation_config(scenario: Scenario) -> _core.SimulationConfig:
    """The core's config of the run: the one the scenario holds, checked by
    the C++ validator (a ValueError names the field) unless it was checked
    since it last changed (:meth:`Scenario.run_config`)."""
    return scenario.run_config()
