"""Factories of the study tests: functions of the scenario returning a controller."""

from __future__ import annotations

from typing import Any

import numpy as np

import neurov

KP = [200.0, 200, 200, 50, 50, 50]
KD = [200.0, 200, 200, 50, 50, 50]


class Delegate:
    """A Python controller that hands every step to a built-in one."""

    def __init__(self, inner: Any) -> None:
        self.inner = inner

    def step(self, eta: Any, nu: Any, eta_d: Any, eta_d_dot: Any, eta_d_ddot: Any) -> Any:
        return self.inner.step(eta, nu, eta_d, eta_d_dot, eta_d_ddot)

    def reset(self) -> None:
        self.inner.reset()

    @property
    def s(self) -> Any:
        return self.inner.s


class PythonPD(Delegate):
    """The built-in PD law stepped from Python (a controller that is only Python glue)."""

    def __init__(self) -> None:
        super().__init__(neurov.PDController(np.array(KP), np.array(KD)))


def python_pd(scenario: neurov.Scenario) -> PythonPD:
    return PythonPD()


def not_a_controller(scenario: neurov.Scenario) -> int:
    return 42


def raises(scenario: neurov.Scenario) -> PythonPD:
    raise RuntimeError(f"no gains for {scenario.name}")


NOT_CALLABLE = 3


def tunable_pd(scenario: neurov.Scenario, gain: float = 1.0) -> Delegate:
    """The built-in PD law with both gains scaled by `gain`: a factory whose keyword argument a tuning searches."""
    return Delegate(neurov.PDController(np.array(KP) * gain, np.array(KD) * gain))
