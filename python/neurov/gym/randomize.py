"""Domain randomisation: each episode's plant drawn from a perturbation
table in the study file's form (docs/studies.md), by the study's own reader
and sampler (:mod:`neurov.study.reading`, :mod:`neurov.study.sampling`)."""

from __future__ import annotations

from typing import Any

import numpy as np

from neurov import _core
from neurov.errors import StudyError
from neurov.config.scenario import Scenario
from neurov.running.plant import build_vehicle, simulation_config

__all__ = ["Randomization"]


class Randomization:
    """The perturbations of `table` (a list of tables, each as one
    ``[[perturbations]]`` of a study file: ``{"parameter": "mass",
    "relative": 0.3}``, ``{"parameter": "current_speed", "range": [0, 0.5]}``,
    ...) applied to `scenario`."""

    def __init__(self, table: Any, scenario: Scenario) -> None:
        # Deferred: the study package loads pandas, which an env without
        # randomisation never needs.
        from neurov.study.reading import read_perturbations

        try:
            self.perturbations = read_perturbations(table, [scenario], "argument 'randomize'")
        except StudyError as e:
            raise ValueError(str(e)) from None
        self.scenario = scenario

    @classmethod
    def of(cls, table: Any, scenario: Scenario) -> Randomization | None:
        """None for no table (None or empty), else the randomisation."""
        return None if table is None or (isinstance(table, list) and not table) else cls(table, scenario)

    def draw(self, rng: np.random.Generator) -> tuple[_core.Vehicle, _core.SimulationConfig]:
        """An episode's plant: the vehicle and configuration of one draw from `rng`."""
        from neurov.study.sampling import draw_perturbations, plant_changes  # pandas, as above

        changes, _ = plant_changes(self.scenario, self.perturbations, draw_perturbations(self.perturbations, rng))
        scenario = self.scenario.replace(**changes)
        return build_vehicle(scenario), simulation_config(scenario)
