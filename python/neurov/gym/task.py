"""The tracking task of a scenario: the action's scale, the bounding box and
the spaces, and the compiled task that does a step's arithmetic (the
action's force, the observation, the reward and the episode's end) in C++.
The single environment (:class:`neurov.gym.TrackingEnv`) and the vector one
(:class:`neurov.gym.TrackingVectorEnv`) both step through it, so lane i of
the vector env is the single env to the last bit (docs/gymnasium.md)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
from gymnasium import spaces
from numpy.typing import NDArray

from neurov import _core
from neurov.gym.limits import single_dof_limits
from neurov.config.reading import load_scenario
from neurov.config.scenario import Scenario, ScenarioError, scenario_path
from neurov.config.vehicle_file import VehicleFile, read_vehicle_file

__all__ = ["TrackingTask", "resolve_scenario"]

Array = NDArray[np.float64]


def resolve_scenario(scenario: Scenario | str | Path) -> Scenario:
    """A Scenario as given, a scenario file by path, or a shipped scenario by
    name (:func:`neurov.config.scenario.scenario_path`)."""
    if isinstance(scenario, Scenario):
        return scenario
    if not isinstance(scenario, (str, Path)):
        raise TypeError(f"argument 'scenario' must be a Scenario, a shipped scenario's name or a path, "
                        f"got {type(scenario).__name__}")
    try:
        path = scenario_path(scenario)
    except ScenarioError as e:
        raise ValueError(f"argument 'scenario': {e}") from None
    return load_scenario(path)


def _vehicle_file(scenario: Scenario) -> VehicleFile:
    """The vehicle file the scenario read, or read now (a scenario object
    that does not keep one)."""
    vehicle_data = getattr(scenario, "vehicle_data", None)
    if vehicle_data is not None:
        return vehicle_data()
    return read_vehicle_file(scenario.vehicle_path())


class TrackingTask:
    """What the environment adds to a scenario's run: the spaces and the
    compiled task (:class:`neurov._core.TrackingTask`, `core`), which
    computes the normalised action's force, the observation, the reward,
    termination and truncation, and steps one simulator or a whole batch in
    one call (neurov/sim/tracking_task.hpp). The arguments are those of
    TrackingEnv; the task's constants are checked by the core's validator,
    which names the argument."""

    def __init__(self, scenario: Scenario, config: _core.SimulationConfig, action: str = "body", *,
                 position_weight: float = 1.0, attitude_weight: float = 1.0, effort_weight: float = 0.01,
                 box_margin: float = 5.0, velocity_bound: float = 5.0) -> None:
        if action not in ("body", "thrusters"):
            raise ValueError(f"argument 'action' must be 'body' or 'thrusters', got {action!r}")
        if not (np.isfinite(box_margin) and box_margin > 0):
            raise ValueError(f"argument 'box_margin' must be a finite number > 0, got {box_margin!r}")
        self.scenario = scenario
        self.action_kind = action
        self._set_action_scale(action)
        poses = np.asarray(config.command.poses)
        corners = np.vstack([poses[:, :3], np.asarray(config.eta0)[:3]])
        self.box_low = corners.min(axis=0) - box_margin
        self.box_high = corners.max(axis=0) + box_margin
        n = self.action_shape[0]
        self.core = _core.TrackingTask(_core.TrackingTaskConfig(
            position_weight=position_weight, attitude_weight=attitude_weight, effort_weight=effort_weight,
            box_low=self.box_low, box_high=self.box_high, velocity_bound=velocity_bound,
            action_positive=self.pos, action_negative=self.neg,
            thrusters=np.zeros((6, 0)) if self.matrix is None else self.matrix,
            # A sensor dropout's NaN reads 0 in the observation.
            dropouts_read_zero=len(config.sensor_faults) > 0))
        self.termination_cost = self.core.termination_cost
        high = self.core.observation_high
        self.observation_space = spaces.Box(-high, high, dtype=np.float32)
        self.action_space = spaces.Box(-1.0, 1.0, shape=(n,), dtype=np.float32)

    def _set_action_scale(self, action: str) -> None:
        vehicle = _vehicle_file(self.scenario)
        thrusters = vehicle.thrusters
        if action == "thrusters":
            if thrusters is None:
                raise ValueError(f"argument 'action': 'thrusters' needs a thruster layout, and vehicle file "
                                 f"{self.scenario.vehicle_path()} has no [thrusters] table")
            self.matrix: Array | None = np.asarray(thrusters["matrix"], dtype=np.float64)
            self.pos = np.asarray(thrusters["max_thrust"], dtype=np.float64)
            self.neg = -np.asarray(thrusters["min_thrust"], dtype=np.float64)
        else:
            self.matrix = None
            if thrusters is not None:
                self.pos, self.neg = single_dof_limits(thrusters["matrix"], thrusters["min_thrust"],
                                                       thrusters["max_thrust"])
            else:
                tau_max = vehicle.tau_max
                if tau_max is None:
                    raise ValueError(f"vehicle file {self.scenario.vehicle_path()} has neither a [thrusters] "
                                     "table nor [limits] tau_max, so the action cannot be normalised")
                self.pos = self.neg = tau_max
        if np.any(self.neg <= 0) or np.any(self.pos <= 0):
            raise ValueError("thrusters: every thruster must be able to push both ways "
                             "(min_thrust < 0 < max_thrust) for a normalised action")
        self.action_shape = (self.pos.shape[0],)

    def describe_end(self, t: float, diverged: bool, outside: bool) -> str:
        """Why an episode ended, for the error of a step after it."""
        why = ("the plant diverged" if diverged else
               "the vehicle left the bounding box" if outside else "the scenario's duration is simulated")
        return f"the episode ended at t = {t:g} s ({why}); call reset()"
