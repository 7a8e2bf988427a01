"""The runs the plotting tests draw: the NN controller and a PD baseline on a
3 m square with thrusters."""

from __future__ import annotations

import numpy as np

from neurov.scenario import CommandSpec, ControllerSpec, Scenario
from neurov.simulation import Result, simulate

PD = ControllerSpec(type="pd", kp=np.full(6, 200.0), kd=np.full(6, 300.0))


def square(name: str, duration: float) -> Scenario:
    """A 3 m square from t = 1 s under the NN controller (16 Sobol centres)."""
    return Scenario(
        name=name, duration=duration, use_thrusters=True,
        command=CommandSpec(type="square", args={"side": 3.0, "start": 1.0}),
        controller=ControllerSpec(type="nn", centres={"method": "sobol", "n": 16, "seed": 0}),
    )


def nn_and_pd(scenario: Scenario) -> list[Result]:
    """The scenario's own NN run and the PD run on it."""
    return [simulate(scenario), simulate(scenario, PD)]
